//! The chart, the cost model's `plan`, the benchmarks (`bench`), the scripts' names and how the binaries are
//! linked.
//!
//! One test binary of modules (a linked binary each costs the build a link and the run a
//! start): `cargo test --release -p pipeline-tests --test tools [FILTER]`.

mod bench;
mod chart_cli;
mod chart_sh;
mod max_error;
mod plan;
mod script_names;
mod static_pie;
