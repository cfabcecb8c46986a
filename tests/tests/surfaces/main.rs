//! The hidden-surface, hidden-line and anti-aliasing methods against the reference, and
//! where each one fails (the failure suite).
//!
//! One test binary of modules (a linked binary each costs the build a link and the run a
//! start): `cargo test --release -p pipeline-tests --test surfaces [FILTER]`.

mod antialiasing;
mod degenerate;
mod differential;
mod exact_coverage;
mod hidden_lines;
mod method_table;
mod painter;
mod phong;
mod scanline;
mod shading;
mod thesis;
mod tie_rule;
mod warnock;
mod where_abuf_fails;
mod where_hiddenline_fails;
mod where_painter_fails;
mod where_scanline_fails;
mod where_warnock_fails;
