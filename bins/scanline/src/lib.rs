//! # scanline: Watkins's scan-line hidden-surface algorithm
//!
//! The method is [`scan::watkins`] (its notes say how it works), in the shared library so
//! that the hidden-line stage's Archuleta method takes its visible segments too; this
//! crate is the stage around it.

pub use scan::watkins::*;
