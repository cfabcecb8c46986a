//! Rendering on other hosts over real OpenSSH on loopback addresses, on GNU parallel, and
//! on a one-node Slurm.
//!
//! One test binary of modules (a linked binary each costs the build a link and the run a
//! start): `cargo test --release -p pipeline-tests --test hosts [FILTER]`.

mod hosts;
mod slurm;
