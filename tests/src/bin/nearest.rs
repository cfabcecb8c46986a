//! nearest: screen-space polygons in, each frame's visible pixels out as runs, the
//! nearest polygon at each pixel centre found by brute force (`pipeline_tests::nearest`).
//!
//! The test-only method of docs/extending.md: tests/tests/house/extending.rs gives it a row of
//! the table of methods and has render run it at the leaves.

use clap::Parser;
use pipeline_tests::nearest::Nearest;
use stagecli::TextFlag;
use std::process::ExitCode;

/// The nearest polygon's colour at each pixel centre, by brute force.
///
/// Reads a screen-space polygon stream (from persp) on stdin and writes each frame's
/// visible pixels as runs (`run Y X0 X1 R G B`) for zbuf to place: the z-buffer's
/// picture, found one centre at a time with no coherence.
#[derive(Parser)]
#[command(name = "nearest", version, verbatim_doc_comment)]
struct Args {
    #[command(flatten)]
    text: TextFlag,
    /// Print counts on stderr at the end: polygons in, frames, runs out, centres tested.
    #[arg(long)]
    stats: bool,
}

fn main() -> ExitCode {
    stagecli::main("nearest", |args: Args| {
        let mut method = Nearest::default();
        leaf::resolve_frames("nearest", args.text.form(), args.stats, &mut method)?;
        Ok(())
    })
}
