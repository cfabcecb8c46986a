//! fused: `scripts/render.sh --depth 0` as one process, for measurement.
//!
//! The same stage libraries render.sh's processes run (viewxf, the six clipplane stages or
//! clipbatch, persp, scanconv, zbuf), called one after the other on each polygon in one
//! process: no pipes, no encoding or decoding between stages. It reads the same scene
//! (text or binary) and writes the same PPM bytes, so `render.sh` time over `fused` time
//! is what the pipes and the codec cost (bench stages fused).
//!
//! The glue is one small function per stage (`view`, `clip_planes` / `clip_batch`,
//! `project`, `scan_convert`, and `ZBuffer` for zbuf's inner loop): when a stage
//! library's interface changes, only its function here does.

use anyhow::{anyhow, bail, Context};
use clap::{Parser, ValueEnum};
use clipbatch::ClipBatch;
use proto::camera::EyeFrame;
use proto::geometry::{Plane, PyramidPlane};
use proto::perspective::Perspective;
use proto::{Colour, Fragment, Polygon, Reader, SpaceKind, StreamError, Token, Vertex};
use scanconv::{Output, ScanConverter};
use stagecli::{DepthArg, ViewArgs};
use std::io::{self, Write};
use std::process::ExitCode;
use zbuf::FrameBuffer;

/// render.sh's depth-0 pipeline in one process (viewxf → clipper → persp → scanconv →
/// zbuf by function calls): the same PPM frames on stdout, for timing against the pipes.
#[derive(Parser, Debug)]
#[command(
    name = "fused",
    after_help = "Example:\n  fused --size 640x480 scene.pp > frame.ppm   # = scripts/render.sh --size 640x480 scene.pp\n  \
                  fused --clipper batch scene.pp > frame.ppm"
)]
struct Cli {
    /// The world-space scene, text or binary (`-` for stdin).
    #[arg(default_value = "examples/penetrating.txt")]
    scene: String,
    /// Camera and view volume, as viewxf (and render.sh) take them; the screen size
    /// defaults to render.sh's 500x500.
    #[command(flatten)]
    view: ViewArgs,
    /// The depth persp writes (render.sh --zmode).
    #[arg(long, value_enum, default_value_t = DepthArg::Reciprocal)]
    zmode: DepthArg,
    /// The clipper: the six clipplane stages one polygon at a time, or clipbatch's batch
    /// clipper (the same output).
    #[arg(long, value_enum, default_value_t = Clipper::Planes)]
    clipper: Clipper,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Clipper {
    Planes,
    Batch,
}

fn main() -> ExitCode {
    let mut cli = Cli::parse();
    if cli.view.size.is_none() && cli.view.aspect.is_none() {
        cli.view.size = Some((500, 500));
    }
    stagecli::report(
        "fused",
        render(&cli).map_err(|e| stagecli::Error::data(format!("{e:#}"))),
    )
}

/// The whole pipeline: each polygon through every stage, a frame written at each
/// NEXT.FRAME and at END (zbuf's PAR.BUFF shows a frame at either).
fn render(cli: &Cli) -> anyhow::Result<()> {
    let (frame, view) = cli.view.resolve().map_err(|e| anyhow!("{e}"))?;
    let (width, height) = cli
        .view
        .size
        .context("--aspect without --size: the screen size is needed for persp")?;
    let mut reader =
        Reader::<Token, _>::new(stagecli::open_input(&cli.scene).map_err(|e| anyhow!("{e}"))?)?;
    reader.header().expect(SpaceKind::World)?;
    let perspective =
        Perspective::new(width, height, view, cli.zmode.into()).map_err(StreamError::Invalid)?;
    let planes = PyramidPlane::ALL.map(|p| p.plane(&view));
    let mut batch = ClipBatch::new(&view, clipbatch::DEFAULT_BATCH);
    let mut scratch = Vec::new();
    let mut sc = ScanConverter::new(width, height, Output::Spans);
    let mut zb = ZBuffer::new(width, height)?;
    let mut out = io::BufWriter::with_capacity(1 << 16, io::stdout().lock());

    // persp, scanconv and zbuf on one clipped polygon.
    let mut rest = |poly: &mut Polygon, position: &str, zb: &mut ZBuffer| -> anyhow::Result<()> {
        project(&perspective, poly, position)?;
        scan_convert(&mut sc, poly, position, zb)
    };
    while let Some(token) = reader.next_record()? {
        match token {
            Token::Polygon(mut poly) => {
                view_polygon(&frame, view.hither, &mut poly);
                match cli.clipper {
                    Clipper::Planes => {
                        clip_planes(&planes, &mut poly, &mut scratch);
                        rest(&mut poly, &reader.position(), &mut zb)?;
                    }
                    Clipper::Batch => {
                        if !batch.fits(&poly) {
                            clip_batch(&mut batch, &mut |p| rest(p, BATCHED, &mut zb))?;
                        }
                        batch.push(poly);
                    }
                }
            }
            Token::Skip(_) => {}
            Token::NextFrame | Token::End => {
                clip_batch(&mut batch, &mut |p| rest(p, BATCHED, &mut zb))?;
                zb.show(&mut out)?;
            }
        }
    }
    out.flush()?;
    Ok(())
}

/// Where a message about a polygon out of clipbatch says it was (the reader has moved on).
const BATCHED: &str = "a polygon of the last batch";

/// viewxf.
fn view_polygon(frame: &EyeFrame, hither: f64, poly: &mut Polygon) {
    viewxf::view_polygon(frame, hither, poly);
}

/// The six clipplane stages, as each one's main loop does it: a polygon whose vertices a
/// plane changes loses its edge supports.
fn clip_planes(planes: &[Plane; 6], poly: &mut Polygon, scratch: &mut Vec<Vertex>) {
    for plane in planes {
        clipplane::clip_against(&poly.vertices, plane, scratch);
        if *scratch != poly.vertices {
            poly.supports.clear();
        }
        std::mem::swap(&mut poly.vertices, scratch);
    }
}

/// clipbatch: clips the waiting polygons and hands each to `next`, in order.
fn clip_batch(
    batch: &mut ClipBatch,
    next: &mut impl FnMut(&mut Polygon) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    for mut poly in batch.clip() {
        next(&mut poly)?;
    }
    Ok(())
}

/// persp. `position` names the polygon for the message (as persp's reader would).
fn project(perspective: &Perspective, poly: &mut Polygon, position: &str) -> anyhow::Result<()> {
    perspective
        .project_polygon(poly)
        .map_err(|e| anyhow!(StreamError::Invalid(format!("{position}: {}", e.reason))))
}

/// scanconv, its fragments straight into zbuf's buffer.
fn scan_convert(
    sc: &mut ScanConverter,
    poly: &Polygon,
    position: &str,
    zb: &mut ZBuffer,
) -> anyhow::Result<()> {
    let (width, height) = zb.size();
    scanconv::check_on_screen(poly, width, height).map_err(|m| anyhow!("{position}: {m}"))?;
    sc.convert(poly, &mut |f| zb.fragment(f))
}

/// zbuf's inner loop (zbuf::par_buff's `apply` for one input): the frame buffer, and the
/// index in the frame of the polygon whose fragments are arriving (ties in depth go to
/// the earlier polygon).
struct ZBuffer {
    fb: FrameBuffer,
    polygons: u32,
    colour: Colour,
}

impl ZBuffer {
    fn new(width: u32, height: u32) -> anyhow::Result<Self> {
        Ok(ZBuffer {
            fb: FrameBuffer::new(width, height, [0, 0, 0]).map_err(|m| anyhow!(m))?,
            polygons: 0,
            colour: [0; 3],
        })
    }

    fn size(&self) -> (u32, u32) {
        (self.fb.width(), self.fb.height())
    }

    fn fragment(&mut self, f: Fragment) -> anyhow::Result<()> {
        match f {
            Fragment::Polygon(colour) => {
                self.polygons = self
                    .polygons
                    .checked_add(1)
                    .filter(|p| *p != u32::MAX)
                    .context("more than 4294967294 polygons in one frame")?;
                self.colour = colour;
            }
            Fragment::Span { y, x0, x1, z, dz } => {
                self.fb
                    .span(y, x0..x1, z, dz, self.polygons - 1, self.colour)
            }
            Fragment::Pixel { x, y, z } => self.fb.pixel(x, y, z, self.polygons - 1, self.colour),
            Fragment::Skip(n) => {
                self.polygons = self
                    .polygons
                    .checked_add(n)
                    .filter(|p| *p != u32::MAX)
                    .context("more than 4294967294 polygons in one frame")?;
            }
            Fragment::Run { y, x0, x1, colour } => self.fb.paint(y, x0..x1, colour),
            Fragment::Shade { .. } => {
                bail!("a Gouraud-shaded polygon: the fused benchmark draws flat scenes only")
            }
            Fragment::NextFrame | Fragment::End => bail!("a frame boundary inside a polygon"),
        }
        Ok(())
    }

    /// Writes the frame as zbuf does (a binary PPM, flushed) and clears the buffer.
    fn show(&mut self, out: &mut impl Write) -> io::Result<()> {
        self.fb.write_ppm(out, proto::ppm::Form::Binary)?;
        out.flush()?;
        self.fb.clear();
        self.polygons = 0;
        Ok(())
    }
}
