//! Each stage binary run alone (its options, its stream in and out, its messages), and the
//! token stream's codec: the tests that lived beside each crate, one module a crate.
//!
//! One test binary of modules (a linked binary each costs the build a link and the run a
//! start): `cargo test --release -p pipeline-tests --test stages [FILTER]`.

mod clipbatch_cli;
mod clipplane_cli;
mod codec;
mod farm_cli;
mod frames_cli;
mod persp_cli;
mod scanconv_cli;
mod scene_cli;
mod splitter_cli;
mod tree_nodes;
mod viewxf_cli;
mod zbuf_cli;
mod zspec_accuracy;
mod zspec_cli;
