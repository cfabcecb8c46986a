//! bench: the benchmarks, one subcommand a question, each printing markdown tables.

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// The benchmarks of polypipe: each subcommand runs the built binaries (made current
/// first; `POLYPIPE_BIN=DIR` measures DIR's as they are) and prints markdown tables on
/// stdout. Every figure is from the one run that prints it: compare figures within a
/// run, not across machines.
#[derive(Parser, Debug)]
#[command(name = "bench", version)]
struct Cli {
    #[command(subcommand)]
    command: Sub,
}

#[derive(Subcommand, Debug)]
enum Sub {
    /// polypipe against Mesa's llvmpipe, the fused run and itself at depths 0-4.
    Llvmpipe(bench::llvmpipe::Args),
    /// The splitter tree and its merge: pipeline, merge, depth-auto, plan, work, farm.
    Tree(bench::tree::Args),
    /// The stages and the stream: geometry, clip, codec, fused, fill, shading.
    Stages(bench::stages::Args),
    /// Each --hse method at every depth on the four scene classes.
    Methods(bench::methods::Args),
    /// Watkins's scan-line method against the z-buffer leaf as the scene grows.
    Scanline(bench::scanline::Args),
    /// The depth sort and the hidden lines against the z-buffer leaf.
    Painter(bench::painter::Args),
    /// Warnock's subdivision and the hidden lines against the z-buffer leaf.
    Warnock(bench::warnock::Args),
    /// Every method's time and memory bounds on the hostile scenes.
    Bounds(bench::bounds::Args),
    /// The anti-aliasing leaves alone: time, memory, output.
    Aa(bench::aa::Args),
    /// The anti-aliasing leaves' error against the 16×16 reference.
    AaTable(bench::aatable::Args),
    /// Adaptive supersampling against supersampling.
    Adaptive(bench::adaptive::Args),
}

fn main() -> ExitCode {
    stagecli::main("bench", |cli: Cli| match &cli.command {
        Sub::Llvmpipe(a) => bench::llvmpipe::main(a),
        Sub::Tree(a) => bench::tree::main(a),
        Sub::Stages(a) => bench::stages::main(a),
        Sub::Methods(a) => bench::methods::main(a),
        Sub::Scanline(a) => bench::scanline::main(a),
        Sub::Painter(a) => bench::painter::main(a),
        Sub::Warnock(a) => bench::warnock::main(a),
        Sub::Bounds(a) => bench::bounds::main(a),
        Sub::Aa(a) => bench::aa::main(a),
        Sub::AaTable(a) => bench::aatable::main(a),
        Sub::Adaptive(a) => bench::adaptive::main(a),
    })
}
