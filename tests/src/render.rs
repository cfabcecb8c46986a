//! What the tests of `render` (bins/render) share: running it through
//! scripts/render.sh as a user would, and reading its frames.

use crate::{bin_dir, output_with_stdin, parse_ppm_stream, repo_root, succeeded, Frame};
use std::process::{Command, Output};

/// `scripts/render.sh ARGS`, the binaries built first.
pub fn render_cmd(args: &[&str]) -> Command {
    bin_dir();
    let mut cmd = Command::new(repo_root().join("scripts/render.sh"));
    // The depth auto chooses weighs the load average; the tests' own load must not change
    // it (docs/model.md).
    cmd.args(args).env("POLYPIPE_LOAD", "0");
    cmd
}

/// Runs render with `stdin` as its standard input.
pub fn render(args: &[&str], stdin: &[u8]) -> Output {
    output_with_stdin(render_cmd(args), stdin)
}

/// Runs render, which must succeed; its stdout.
pub fn render_ok(args: &[&str], stdin: &[u8]) -> Vec<u8> {
    succeeded(&format!("render {args:?}"), render(args, stdin))
}

/// The frames of a concatenated P6 stream.
pub fn frames(ppm: &[u8]) -> Vec<Frame> {
    parse_ppm_stream(ppm).expect("a P6 stream")
}

/// The repository's example scene, the one render draws on a terminal with no SCENE.
pub fn example() -> String {
    repo_root()
        .join("examples/penetrating.txt")
        .display()
        .to_string()
}

/// The pixels whose colours differ between two renderings.
pub fn differing_pixels(a: &[u8], b: &[u8]) -> Vec<(usize, usize)> {
    let (fa, fb) = (frames(a), frames(b));
    assert_eq!(fa.len(), fb.len());
    let mut diffs = Vec::new();
    for (x, y) in fa.iter().zip(&fb) {
        assert_eq!((x.width, x.height), (y.width, y.height));
        for (i, (p, q)) in x.pixels.iter().zip(&y.pixels).enumerate() {
            if p != q {
                diffs.push((i % x.width, i / x.width));
            }
        }
    }
    diffs
}
