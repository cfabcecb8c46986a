//! # leaf: the stream loop of a stage that resolves whole frames at a leaf
//!
//! A leaf of the splitter tree (docs/DESIGN.md, "Leaves resolve visibility") gets the
//! screen-space polygons of its part of the screen and sends on finished pixels as `run`
//! records for the merger (`zbuf`) to place. The methods that resolve a frame at once
//! (scan-line, area subdivision, depth sort, supersampling, the a-buffer) share that
//! loop; each is a [`scan::frame::HiddenSurface`], and [`resolve_frames`] is the rest:
//! reading the stream, gathering a frame's polygons, refusing what the method cannot
//! draw, writing the runs, the `--stats` line.
//!
//! It is a crate of its own because it is where the rasteriser (`scan`) meets a stage's
//! skeleton (`stagecli`): the geometry stages (viewxf, clipplane, persp, the splitter)
//! use `stagecli` and link no rasteriser.

use proto::{Form, Fragment, Header, Polygon, Space, SpaceKind, Token};
use scan::frame::HiddenSurface;
use stagecli::{next, read_stdin, refuse_transparent, write_stdout, Error, Result};

/// Counts every frame-resolving stage prints under `--stats`, before its method's own.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameCounts {
    pub polygons_in: u64,
    pub frames: u64,
    pub runs_out: u64,
}

/// Reads a screen-space stream on stdin, gathers each frame's polygons in stream order,
/// has `method` resolve them at the frame's end, and writes the finished pixels to stdout
/// in `form` as `run` records, frame by frame, for the merger (`zbuf`) to place. A
/// polygon off the screen's guard band is a data error naming its place. `skip N`
/// records carry nothing a frame-resolving method needs (the order of the polygons it
/// does get is what decides ties). Under `stats`, prints one line on stderr at the end:
/// `STAGE: P polygons in, F frames, R runs out, ` then the method's own counters.
pub fn resolve_frames(
    stage: &str,
    form: Form,
    stats: bool,
    method: &mut impl HiddenSurface,
) -> Result<FrameCounts> {
    let mut input = read_stdin::<Token>(SpaceKind::Screen)?;
    if let Some((name, word)) = input.header().attributes.smooth_shading() {
        if !method.shades() {
            return Err(Error::usage(format!(
                "{stage} draws each polygon in one colour, and this stream is {name}-shaded \
                 (its header says `{word}`); shading is drawn by every hidden-surface method \
                 (render.sh --hse zbuf, scanline, warnock, painter) and by anti-aliasing \
                 (--aa ssK, abuf)"
            )));
        }
    }
    method.set_lighting(input.header().attributes.phong());
    let (width, height) = input
        .header()
        .space
        .screen_size()
        .ok_or_else(|| Error::data("screen-space header without a size"))?;
    // At least a resolved colour for every pixel a frame's polygons may cover.
    stagecli::memory::check_screen(width, height, 3, "at least a resolved colour")?;
    let header = Header::new(Space::Fragments { width, height })
        .with(input.header().attributes.for_fragments());
    let mut out = write_stdout::<Fragment>(header, form)?;
    // The header goes on at once, so that the merger can refuse a screen too large for
    // it now, not after this leaf's first frame (a minute, at 65536x65536).
    out.flush()?;
    let mut counts = FrameCounts::default();
    let mut polygons: Vec<Polygon> = Vec::new();
    let mut runs = Vec::new();
    while let Some(token) = next(&mut input)? {
        let end = match token {
            Token::Polygon(p) => {
                scan::check_on_screen(&p, width, height)
                    .map_err(|m| Error::data(format!("{}: {m}", input.position())))?;
                if !method.transparency() {
                    refuse_transparent(stage, &p, || input.position())?;
                }
                counts.polygons_in += 1;
                polygons.push(p);
                continue;
            }
            Token::Skip(_) => continue,
            Token::NextFrame => Fragment::NextFrame,
            Token::End => Fragment::End,
        };
        method.resolve(&polygons, width, height, &mut runs);
        polygons.clear();
        counts.frames += 1;
        counts.runs_out += runs.len() as u64;
        for r in runs.drain(..) {
            out.write(&r.into())?;
        }
        out.write(&end)?;
    }
    out.flush()?;
    if stats {
        eprintln!(
            "{stage}: {} polygons in, {} frames, {} runs out, {}",
            counts.polygons_in,
            counts.frames,
            counts.runs_out,
            method.stats()
        );
    }
    Ok(counts)
}
