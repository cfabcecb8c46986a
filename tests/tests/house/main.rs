//! The house rules: the docs and their claims, the crates' layout, and the walk-through of
//! adding a method.
//!
//! One test binary of modules (a linked binary each costs the build a link and the run a
//! start): `cargo test --release -p pipeline-tests --test house [FILTER]`.

mod claims;
mod docs;
mod extending;
mod layout;
mod test_binaries;
