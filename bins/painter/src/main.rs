//! painter: screen-space polygons in, each frame's finished pixels out, by depth sort.

use clap::Parser;
use painter::Painter;
use stagecli::TextFlag;
use std::process::ExitCode;

/// Depth sort, painted back to front (Newell, Newell and Sancha, in the survey the thesis
/// cites, [SuSp74]): a hidden-surface method for a leaf of the splitter tree.
///
/// Reads a screen-space polygon stream (from persp) on stdin; per frame, sorts the
/// polygons by their farthest depth, orders the ones whose depths overlap by the five
/// tests of Newell, Newell and Sancha (depth extents, bounding boxes, P behind Q's plane,
/// Q in front of P's plane, disjoint projections), paints them from the back to the front
/// into a frame of colours (no depth buffer), and writes the finished pixels as runs
/// (`run Y X0 X1 R G B`) for zbuf to place. Every test is decided on the pixels the
/// polygons cover, with the depths the z-buffer uses: a scene that has a depth order comes
/// out pixel for pixel as the z-buffer draws it, and at equal depth the earlier polygon
/// is in front.
///
/// Where it fails (the failures are kept, and counted by --stats):
///   - interpenetrating polygons (the thesis's scene, examples/penetrating.txt): neither
///     is in front, there is no order to paint in; one of them is painted whole over
///     the other where the z-buffer shows each in front on its side of the crossing;
///   - cyclic overlap (A over B over C over A): likewise, one of the cycle is painted
///     wrong where it overlaps the others;
///   - coincident polygons and equal depths in general are decided by the stream order
///     (the earlier in front), as the z-buffer decides them; the fixed-point depths are
///     compared, so polygons that differ only below their resolution tie.
///
/// Both failures are met as a polygon that would have to move twice (a cycle); without
/// --split it is painted in the order at hand. With --split the cycle is broken by cutting
/// one polygon by the other's plane, on the pixel grid, and the pieces sorted on: the
/// frame is then the z-buffer's.
///
/// Example:
///   persp --size 500x500 < eye.pp | painter --stats > leaf.frag
///   scene spheres | viewxf | clipbatch | persp --size 64x64 | painter --split | zbuf > f.ppm
#[derive(Parser)]
#[command(name = "painter", version, verbatim_doc_comment)]
struct Args {
    #[command(flatten)]
    text: TextFlag,
    /// The splitting step: break a cycle (cyclic overlap, interpenetration) by cutting a
    /// polygon by the other's plane instead of painting it in the order at hand.
    #[arg(long)]
    split: bool,
    /// Print counts on stderr at the end: polygons, the pairs each of the five tests
    /// resolved, swaps, cycles met, splits, cycles painted out of order.
    #[arg(long)]
    stats: bool,
}

fn main() -> ExitCode {
    stagecli::main("painter", |args: Args| {
        let mut method = if args.split {
            Painter::with_split()
        } else {
            Painter::new()
        };
        stagecli::resolve_frames("painter", args.text.form(), args.stats, &mut method)?;
        Ok(())
    })
}
