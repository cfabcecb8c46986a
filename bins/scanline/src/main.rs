//! scanline: screen-space polygons in, each frame's visible pixels out as runs.

use clap::Parser;
use scanline::Scanline;
use stagecli::TextFlag;
use std::process::ExitCode;

/// Watkins's scan-line hidden-surface algorithm (Archuleta (1972); Newman and Sproull (1973), 14.4).
///
/// Reads a screen-space polygon stream (from persp) on stdin and resolves each frame
/// one scan line at a time, with no depth buffer: the active polygons' segments on the
/// line, kept in X order from line to line by a minor sort, cut into sample spans at
/// the segment ends; in a span where segments overlap, depth is compared at its left
/// end, the first column where another segment comes in front is computed where the
/// two depth lines meet (XINTER) and settled by the z-buffer's test at the pixel
/// centres beside it (by midpoint subdivision first where several may), and the span
/// split there; the active polygons' edges are kept in one shared table; the line above's
/// front and crossing columns are tried first and verified. Writes the visible pixels
/// of each frame as runs of one colour (`run Y X0 X1 R G B`), which zbuf places without
/// a depth test; a Gouraud-shaded polygon's pixels (a `vertex-colours` stream) each in
/// its colour at the pixel centre. The picture is the z-buffer's (`scanconv --resolve`)
/// to the pixel.
///
/// It fails on no scene; what it pays for is segments and sample spans, not pixels
/// (docs/methods.md, `bench scanline`): much faster than the z-buffer
/// on piles of big polygons (about 30 times on 64 stacked full-screen planes), slower
/// with hundreds of crossings a line on polygons a few pixels wide (up to 1.9 times) and
/// on many small polygons piled deep (1.7 times on the test environment at depth
/// complexity 16). The coherence from line to line saves 6% of the instructions on
/// Archuleta's spheres and costs 2 to 7% where everything moves (slivers) or nothing
/// does (20,000 stacked quads): --sort-afresh measures it.
///
/// Example:
///   persp --size 500x500 < leaf.pp | scanline > leaf.frag
///   printf 'polypipe 1 screen 4 4\ncolour 255 0 0\n1 1 0.5\n3 1 0.5\n3 3 0.5\nEND\n' | scanline --text
#[derive(Parser)]
#[command(name = "scanline", version, verbatim_doc_comment)]
struct Args {
    #[command(flatten)]
    text: TextFlag,
    /// Print counts on stderr at the end: polygons in, frames, runs out, then Watkins's
    /// quantities: scan lines, segments, sample spans, segments examined, depth
    /// comparisons (tests of the tie rule at a column) and crossings (splits where another
    /// segment comes in front); the minor sort's segments merged in, re-sorted and swaps;
    /// the predictions from the line above (fronts and crossing columns) that held and
    /// that failed; the midpoint subdivisions; and the crossings computed from the depth
    /// lines (XINTER), with those whose X was more than a column off and were searched.
    #[arg(long)]
    stats: bool,
    /// Sort the segments afresh on every line and predict nothing from the line above:
    /// the method without Watkins's scan-line coherence, for measuring what it buys
    /// (`bench scanline`). The picture is the same.
    #[arg(long)]
    sort_afresh: bool,
}

fn main() -> ExitCode {
    stagecli::main("scanline", |args: Args| {
        let mut method = Scanline::new();
        method.sort_afresh = args.sort_afresh;
        leaf::resolve_frames("scanline", args.text.form(), args.stats, &mut method)?;
        Ok(())
    })
}
