//! painter: screen-space polygons in, each frame's finished pixels out, by depth sort.

use clap::Parser;
use painter::Painter;
use stagecli::TextFlag;
use std::process::ExitCode;

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
/// Where it fails (counted by --stats):
///   - interpenetrating polygons (examples/penetrating.txt) and cyclic overlap
///     (A over B over C over A): there is no order to paint in; without --split one
///     polygon of the cycle is painted whole over the others;
///   - with --split the cycle is broken by cutting a polygon by the other's plane
///     (Sutherland-Hodgman) and the pieces sorted on, up to a cut budget a frame
///     (--cuts-per-polygon x polygons + --cuts-base); when the budget is spent the rest
///     is painted in the order at hand and painter says so on stderr, every time.
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
    #[arg(long, default_value_t = painter::CUTS_PER_POLYGON, requires = "split")]
    cuts_per_polygon: usize,
    /// With --split: cuts allowed a frame, in addition to those per polygon.
    #[arg(long, default_value_t = painter::CUTS_BASE, requires = "split")]
    cuts_base: usize,
    /// Print counts on stderr at the end: polygons, pieces painted, the pairs each of
    /// the five tests resolved, swaps, cycles met, splits, cycles painted out of order.
    #[arg(long)]
    stats: bool,
}

fn main() -> ExitCode {
    stagecli::main("painter", |args: Args| {
        let mut method = if args.split {
            Painter::with_split_budget(args.cuts_per_polygon, args.cuts_base)
        } else {
            Painter::new()
        };
        let result = stagecli::resolve_frames("painter", args.text.form(), args.stats, &mut method);
        // Said whether or not --stats was given, and whatever became of the output.
        if let Some(line) = method.gave_up_message() {
            eprintln!("painter: {line}");
        }
        result?;
        Ok(())
    })
}
