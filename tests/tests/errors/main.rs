//! What every binary does with bad input: one line naming the stage, the place and the
//! problem, and the documented status.
//!
//! One test binary of modules (a linked binary each costs the build a link and the run a
//! start): `cargo test --release -p pipeline-tests --test errors [FILTER]`.

mod bad_input;
mod error_reports;
mod exit_codes;
mod overflow;
mod reader_gone;
mod stream_messages;
mod too_large;
