//! `render` and the scripts: the graph of processes, the splitter tree at every depth,
//! movies, outputs, options and failures.
//!
//! One test binary of modules (a linked binary each costs the build a link and the run a
//! start): `cargo test --release -p pipeline-tests --test composer [FILTER]`.

mod clipbatch_render;
mod depth_option;
mod fused;
mod leaf_resolve;
mod movies;
mod outputs;
mod plain_ppm;
mod progress;
mod render_build;
mod render_failures;
mod render_graph;
mod render_options;
mod render_stdin;
mod split_invariance;
mod split_pieces;
mod split_planes;
mod tree;
mod tree_script;
