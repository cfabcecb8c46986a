//! warnock: screen-space polygons in, each frame's finished pixels out, by Warnock's area
//! subdivision (Newman and Sproull (1973), 14.3 and Appendix VI).

use clap::Parser;
use stagecli::TextFlag;
use std::process::ExitCode;
use warnock::Warnock;

/// Warnock's area subdivision (a hidden-surface method for a leaf of the splitter tree).
///
/// Reads a screen-space polygon stream (from persp) on stdin, gathers each frame, and
/// resolves it by windows as Newman and Sproull's Appendix VI listing does: the polygons sorted by
/// their nearest depth (ZMIN); for each window the Looker sorts them into surrounders,
/// intersectors and disjoint ones from their edges (stopping at the first polygon behind a
/// surrounder), the Thinker compares depths at the window's four corners: a window with
/// nothing left is empty, one a surrounder hides everything else in is filled, one with a
/// single polygon in front of it is drawn, any other is split in four, down to single
/// pixels, which are decided by the z-buffer's rule at their centre. Depths and coverage
/// are the z-buffer's (pixel centres, the top-left rule, a tie to the earlier polygon), so
/// the frame is `scanconv --resolve`'s (docs/methods.md counts the pixels where it could
/// differ). Writes the finished pixels as runs (`run Y X0 X1 R G B`) for zbuf to place.
///
/// Example:
///   persp --size 500x500 < leaf.pp | warnock > leaf.frag
///   printf 'polypipe 1 screen 4 4\ncolour 255 0 0\n1 1 0.5\n3 1 0.5\n3 3 0.5\nEND\n' | warnock --text --stats
#[derive(Parser)]
#[command(name = "warnock", version, verbatim_doc_comment)]
struct Args {
    #[command(flatten)]
    text: TextFlag,
    /// Print counts on stderr at the end: polygons in, frames, runs out, the windows
    /// visited at each depth of subdivision, how they were resolved, the polygons the
    /// Looker looked at, those a surrounder hid, and the ZMIN exits.
    #[arg(long)]
    stats: bool,
}

fn main() -> ExitCode {
    stagecli::main("warnock", |args: Args| {
        leaf::resolve_frames("warnock", args.text.form(), args.stats, &mut Warnock::new())
            .map(|_| ())
    })
}
