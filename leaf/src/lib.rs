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

use proto::{Form, Fragment, Header, Polygon, Reader, Space, SpaceKind, Token, Writer};
use scan::frame::HiddenSurface;
use stagecli::{next, read_stdin, refuse_transparent, write_stdout, Error, Result};
use std::io::{Read, Write};

/// Counts every frame-resolving stage prints under `--stats`, before its method's own.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameCounts {
    pub polygons_in: u64,
    pub frames: u64,
    pub runs_out: u64,
}

/// Reads a screen-space stream on stdin, gathers each frame's polygons in stream order,
/// has `method` resolve them at the frame's end, and writes the finished pixels to stdout
/// in `form` as `run` records, frame by frame, for the merger (`zbuf`) to place
/// ([`resolve`]). Under `stats`, prints on stderr at the end one line for people, `STAGE:
/// P polygons in, F frames, R runs out, ` then the method's own counters, and the same
/// counts as a record (`stagecli::stats`): `polygons_in`, `frames`, `runs_out`, then
/// [`HiddenSurface::counters`].
pub fn resolve_frames(
    stage: &str,
    form: Form,
    stats: bool,
    method: &mut impl HiddenSurface,
) -> Result<FrameCounts> {
    let mut input = read_stdin::<Token>(SpaceKind::Screen)?;
    let counts = resolve(
        stage,
        &mut input,
        |header| write_stdout(header, form),
        method,
    )?;
    if stats {
        let human = format!(
            "{stage}: {} polygons in, {} frames, {} runs out, {}",
            counts.polygons_in,
            counts.frames,
            counts.runs_out,
            method.stats()
        );
        let mut record = stagecli::stats::Record::new(stage)
            .with("polygons_in", counts.polygons_in)
            .with("frames", counts.frames)
            .with("runs_out", counts.runs_out);
        for (key, value) in method.counters() {
            record.set(key, value);
        }
        record.print(&human);
    }
    Ok(counts)
}

/// [`resolve_frames`] on any screen-space `input`, writing to the writer `open` makes of
/// the output's header. A stream shaded in a way the method does not draw is a usage
/// error, before any output; so is a polygon that is not opaque, for a method without
/// transparency. A polygon off the screen's guard band is a data error naming its place.
/// `skip N` records carry nothing a frame-resolving method needs (the order of the
/// polygons it does get is what decides ties).
pub fn resolve<R: Read, W: Write>(
    stage: &str,
    input: &mut Reader<Token, R>,
    open: impl FnOnce(Header) -> Result<Writer<Fragment, W>>,
    method: &mut impl HiddenSurface,
) -> Result<FrameCounts> {
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
    let mut out = open(header)?;
    // The header goes on at once, so that the merger can refuse a screen too large for
    // it now, not after this leaf's first frame (a minute, at 65536x65536).
    out.flush()?;
    let mut counts = FrameCounts::default();
    let mut polygons: Vec<Polygon> = Vec::new();
    let mut runs = Vec::new();
    while let Some(token) = next(input)? {
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
        // A leaf of render's that shows progress: this leaf's part of the frame is done.
        stagecli::progress::frame_done();
    }
    out.flush()?;
    Ok(counts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proto::Colour;
    use scan::Run;
    use stagecli::Kind;

    /// A method for the loop's tests: each polygon's first vertex's pixel, in its colour,
    /// and the frames it was given, by their polygon counts.
    #[derive(Default)]
    struct FirstPixel {
        frames: Vec<usize>,
        shades: bool,
    }

    impl HiddenSurface for FirstPixel {
        fn resolve(&mut self, polygons: &[Polygon], _: u32, _: u32, runs: &mut Vec<Run>) {
            self.frames.push(polygons.len());
            for p in polygons {
                let (x, y) = (p.vertices[0].x as u32, p.vertices[0].y as u32);
                runs.push(Run {
                    y,
                    x0: x,
                    x1: x + 1,
                    colour: p.colour,
                });
            }
        }
        fn stats(&self) -> String {
            String::new()
        }
        fn counters(&self) -> Vec<(&'static str, String)> {
            Vec::new()
        }
        fn shades(&mut self) -> bool {
            self.shades
        }
    }

    fn run(text: &str, method: &mut FirstPixel) -> Result<(FrameCounts, Vec<Fragment>)> {
        let mut input = Reader::<Token, _>::new(text.as_bytes()).unwrap();
        let mut bytes = Vec::new();
        let counts = resolve(
            "first",
            &mut input,
            |h| Ok(Writer::new(&mut bytes, h, Form::Binary)?),
            method,
        )?;
        let mut out = Reader::<Fragment, _>::new(&bytes[..]).unwrap();
        assert_eq!(
            out.header().space,
            Space::Fragments {
                width: 8,
                height: 4
            }
        );
        let mut records = Vec::new();
        while let Some(f) = out.next_record().unwrap() {
            records.push(f);
        }
        Ok((counts, records))
    }

    fn tri(colour: Colour, x: u32, y: u32) -> String {
        let [r, g, b] = colour;
        format!("colour {r} {g} {b}\n{x}.5 {y}.5 0.5\n{x}.5 3 0.5\n7 3 0.5\n")
    }

    fn run_at(y: u32, x: u32, colour: Colour) -> Fragment {
        Run {
            y,
            x0: x,
            x1: x + 1,
            colour,
        }
        .into()
    }

    #[test]
    fn each_frame_is_resolved_at_its_end_and_its_runs_written_before_its_marker() {
        let text = format!(
            "polypipe 1 screen 8 4\n{}NEXT.POLYGON\nskip 2\nNEXT.POLYGON\n{}NEXT.FRAME\n\
             NEXT.FRAME\n{}END\n",
            tri([1, 2, 3], 0, 0),
            tri([4, 5, 6], 2, 1),
            tri([7, 8, 9], 5, 2)
        );
        let mut method = FirstPixel::default();
        let (counts, records) = run(&text, &mut method).unwrap();
        assert_eq!(
            counts,
            FrameCounts {
                polygons_in: 3,
                frames: 3,
                runs_out: 3
            }
        );
        // Stream order within a frame; an empty frame is resolved too.
        assert_eq!(method.frames, [2, 0, 1]);
        assert_eq!(
            records,
            [
                run_at(0, 0, [1, 2, 3]),
                run_at(1, 2, [4, 5, 6]),
                Fragment::NextFrame,
                Fragment::NextFrame,
                run_at(2, 5, [7, 8, 9]),
                Fragment::End,
            ]
        );
    }

    #[test]
    fn a_shaded_stream_is_refused_by_a_method_that_does_not_shade() {
        let text = "polypipe 1 screen 8 4 vertex-colours\nEND\n";
        let e = run(text, &mut FirstPixel::default()).unwrap_err();
        assert_eq!(e.kind(), Kind::Usage);
        assert_eq!(
            e.to_string(),
            "first draws each polygon in one colour, and this stream is Gouraud-shaded (its \
             header says `vertex-colours`); shading is drawn by every hidden-surface method \
             (render.sh --hse zbuf, scanline, warnock, painter) and by anti-aliasing (--aa \
             ssK, abuf)"
        );
        let mut shades = FirstPixel {
            shades: true,
            ..FirstPixel::default()
        };
        let (counts, records) = run(text, &mut shades).unwrap();
        assert_eq!((counts.frames, records), (1, vec![Fragment::End]));
    }

    #[test]
    fn a_transparent_or_off_screen_polygon_is_refused_naming_its_place() {
        let text = format!(
            "polypipe 1 screen 8 4 opacity\n{}NEXT.FRAME\ncolour 1 2 3 128\n0 0 0\n1 0 0\n0 1 0\nEND\n",
            tri([1, 2, 3], 0, 0).replace("colour 1 2 3", "colour 1 2 3 255")
        );
        let e = run(&text, &mut FirstPixel::default()).unwrap_err();
        assert_eq!(e.kind(), Kind::Usage);
        assert_eq!(
            e.to_string(),
            "frame 1, polygon 0: a polygon of opacity 128 (below 255): first draws opaque \
             polygons only; transparency is the a-buffer's (render.sh --aa abuf)"
        );
        let far = "polypipe 1 screen 8 4\ncolour 1 2 3\n0 0 0\n1e9 0 0\n0 1 0\nEND\n";
        let e = run(far, &mut FirstPixel::default()).unwrap_err();
        assert_eq!(e.kind(), Kind::Data);
        assert_eq!(
            e.to_string(),
            "frame 0, polygon 0: vertex 1 at (1e9, 0e0) lies far outside the 8x4 screen; clip \
             in eye space (clipplane left, right, top, bottom) before persp"
        );
    }
}
