//! warnock: screen-space polygons in, each frame's finished pixels out, by Warnock's area
//! subdivision (Newman and Sproull (1973), 14.3 and Appendix VI).

use clap::Parser;
use stagecli::TextFlag;
use std::process::ExitCode;
use warnock::Warnock;

/// Warnock's area subdivision (a hidden-surface method for a leaf of the splitter tree).
///
/// Reads a screen-space polygon stream (from persp) on stdin, gathers each frame, and
/// resolves it by windows: a window no polygon covers is left empty; one a single polygon
/// is left in, or that a surrounding polygon covers in front of all the others, is drawn
/// whole; any other is split in four, down to single pixels, which are decided by the
/// z-buffer's rule at their centre. Coverage and depth are the z-buffer's own (pixel
/// centres, the top-left rule, fixed-point depth, a tie to the earlier polygon), so the
/// frame is byte for byte `scanconv --resolve`'s. Writes the finished pixels as runs
/// (`run Y X0 X1 R G B`) for zbuf to place.
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
    /// visited at each depth of subdivision, how they were resolved, and the rows the
    /// Looker and the Thinker read.
    #[arg(long)]
    stats: bool,
}

fn main() -> ExitCode {
    stagecli::main("warnock", |args: Args| {
        stagecli::resolve_frames("warnock", args.text.form(), args.stats, &mut Warnock::new())
            .map(|_| ())
    })
}
