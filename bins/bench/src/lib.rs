//! The benchmarks, one module a question, each printing markdown tables on stdout.
//!
//! They share [`measure`] (one run of a command measured, the statistics over many:
//! interleaved rounds, medians, spreads, the least) and [`kit`] (the built binaries, the
//! scenes, the helpers the tables need). Every figure is from the run that prints it, on
//! one machine under one load: ratios, not seconds, are what carry over.

pub mod aa;
pub mod aatable;
pub mod adaptive;
pub mod bounds;
pub mod kit;
pub mod llvmpipe;
pub mod measure;
pub mod methods;
pub mod painter;
pub mod scanline;
pub mod stages;
pub mod tree;
pub mod warnock;
