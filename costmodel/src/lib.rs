//! # costmodel: the cost model, its calibration, and `render --depth auto`'s planner
//!
//! Thesis chapter 5.2 models each stage's time for an environment (polygons, screen,
//! depth complexity) as a sum of per-polygon, per-vertex, per-scan-line and per-pixel
//! costs, and chapter 6.4 grows the splitter tree until the hidden-surface layer is no
//! slower than the slowest other stage ([`model`]). This crate holds that model, a cheap
//! look at a scene that gives the model its environment ([`look`]), the fit of the
//! model's constants on the machine it runs on ([`calibrate`], kept by [`cache`] in
//! `${XDG_CACHE_HOME:-$HOME/.cache}/polypipe/model.toml`), the thesis's own T424-20
//! constants and environment ([`thesis`]). `render --depth auto` (the `render` crate,
//! which also starts and watches the stages) and `chart` (the measuring and plotting
//! binary) use this library in their own processes; the `plan` binary (bins/plan) is its
//! command line, whose subcommands' arguments and bodies are in [`cli`] because `chart
//! choose-depth` shares them. Its errors are one type, [`Error`], whose kind is a
//! command's exit status.

pub mod accuracy;
pub mod cache;
pub mod calibrate;
pub mod cli;
pub mod error;
pub mod look;
pub mod measure;
pub mod model;
pub mod movie;
pub mod thesis;

pub use error::{Error, Result};
use std::io::Write;

/// Writes `text` to stdout as the stages do ([`stagecli::stdout`]): the reader going
/// away ends the program quietly with 0, a failed write is `stdout: reason`, 3.
pub fn say(text: &str) -> Result<()> {
    let mut out = stagecli::stdout();
    out.write_all(text.as_bytes()).and_then(|_| out.flush())?;
    Ok(())
}

/// A line to stderr, for the person watching: if stderr is gone there is no one to tell.
pub fn say_err(line: &str) {
    let _ = writeln!(std::io::stderr(), "{line}");
}
