//! # scene: world-space polygon streams for polypipe
//!
//! The sources of the pipeline (thesis chapter 5.2's test environment, the INPUTTER's
//! two penetrating polygons, the classic hidden-surface test objects of the survey
//! seeds, and Wavefront OBJ models), and screen-space scenes for timing one leaf method
//! alone ([`screen`]). Every world-space generator returns its movie as one
//! `Vec<Polygon>` per frame, in world coordinates, placed in view of the default camera
//! (eye at (0, 0, 20) looking at the origin, s = 10, d = 16, K1 = 1, K2 = 30);
//! `main.rs` only writes them.

pub mod environment;
pub mod obj;
pub mod screen;
pub mod shapes;

pub use environment::{generate as environment, Environment};
pub use shapes::{spin, Face, Shading};
