//! painter: screen-space polygons in, each frame's finished pixels out, by depth sort.

use clap::Parser;
use painter::Painter;
use proto::shade::Lighting;
use proto::Polygon;
use scan::frame::HiddenSurface;
use scan::Run;
use stagecli::TextFlag;
use std::io::Write;
use std::process::ExitCode;
use std::sync::Arc;

/// Depth sort, painted back to front (Newell, Newell and Sancha, in Sutherland, Sproull
/// and Schumacker's survey of ten hidden-surface algorithms, [SuSp74]): a hidden-surface
/// method for a leaf of the splitter tree.
///
/// Reads a screen-space polygon stream (from persp) on stdin; per frame, sorts the
/// polygons by their farthest vertex depth, orders the ones whose depths overlap by the
/// five tests of Newell, Newell and Sancha on their geometry (depth extents, bounding
/// boxes, P behind Q's plane, Q in front of P's plane, projections disjoint), paints them
/// from the back to the front into a frame of colours (no depth buffer), and writes the
/// finished pixels as runs (`run Y X0 X1 R G B`) for zbuf to place.
///
/// Where it fails (counted by --stats, and said on stderr, one line a frame):
///   - interpenetrating polygons (examples/penetrating.txt) and cyclic overlap
///     (A over B over C over A): there is no order to paint in; without --split one
///     polygon of the cycle is painted whole over the others, and a frame where that
///     happened gets `painter: frame N: K cycles painted out of order; --split cuts
///     them` (frames counted from 0);
///   - with --split the cycle is broken by cutting a polygon by the other's plane
///     (Sutherland-Hodgman) and the pieces sorted on, up to a cut budget a frame
///     (--cuts-per-polygon x polygons + --cuts-base); when the budget is spent (or no
///     cut has two pieces) the rest is painted in the order at hand and painter says
///     `painter: frame N: could not order every polygon: ...` on stderr.
///   - a cycle painted in the order at hand that left no pixel wrong (pieces that
///     meet at a point, sharing no pixel centre) is no failure and is not said.
///   - coincident polygons and equal depths in general: the earlier in the stream is in
///     front, as the z-buffer decides; a vertex within a rounding band of a plane
///     counts as on it.
///
/// Exit status: 0 done (also when the budget was spent: the frames are written), 1 bad
/// input, 2 usage, 3 I/O.
///
/// Example:
///   persp --size 500x500 < eye.pp | painter --stats > leaf.frag
///   scene planes 50 | viewxf | clipbatch | persp --size 300x300 | painter --split | zbuf > f.ppm
#[derive(Parser)]
#[command(name = "painter", version, verbatim_doc_comment)]
struct Args {
    #[command(flatten)]
    text: TextFlag,
    /// The splitting step: break a cycle (cyclic overlap, interpenetration) by cutting a
    /// polygon by the other's plane instead of painting it in the order at hand.
    #[arg(long)]
    split: bool,
    /// With --split: cuts allowed a frame, per polygon of the frame.
    #[arg(long, default_value_t = painter::CUTS_PER_POLYGON, requires = "split",
          value_parser = stagecli::numbers::whole::<usize>(0, u32::MAX as u64))]
    cuts_per_polygon: usize,
    /// With --split: cuts allowed a frame, in addition to those per polygon.
    #[arg(long, default_value_t = painter::CUTS_BASE, requires = "split",
          value_parser = stagecli::numbers::whole::<usize>(0, u32::MAX as u64))]
    cuts_base: usize,
    /// Print counts on stderr at the end: polygons, pieces painted, the pairs each of
    /// the five tests resolved, swaps, cycles met, splits, cycles painted out of order.
    #[arg(long)]
    stats: bool,
}

/// The painter, saying each frame's note on stderr as soon as the frame is resolved: one
/// line for people, and, with `--stats`, its record after it for programs (the
/// differential suite and render read those).
struct Loud(Painter, bool);

impl HiddenSurface for Loud {
    fn resolve(&mut self, polygons: &[Polygon], width: u32, height: u32, runs: &mut Vec<Run>) {
        self.0.resolve(polygons, width, height, runs);
        if let Some(line) = self.0.take_note() {
            let line = format!("painter: {line}");
            if self.1 {
                self.0.note_record().print(&line);
            } else {
                let _ = writeln!(std::io::stderr(), "{line}");
            }
        }
    }
    fn stats(&self) -> String {
        self.0.stats()
    }
    fn counters(&self) -> Vec<(&'static str, String)> {
        self.0.counters()
    }
    fn lighting(&mut self) -> Option<&mut Option<Arc<Lighting>>> {
        self.0.lighting()
    }
    fn transparency(&self) -> bool {
        self.0.transparency()
    }
}

fn main() -> ExitCode {
    stagecli::main("painter", |args: Args| {
        let method = if args.split {
            Painter::with_split_budget(args.cuts_per_polygon, args.cuts_base)
        } else {
            Painter::new()
        };
        leaf::resolve_frames(
            "painter",
            args.text.form(),
            args.stats,
            &mut Loud(method, args.stats),
        )?;
        Ok(())
    })
}
