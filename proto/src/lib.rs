//! # proto: the polypipe token stream and the geometry every stage shares
//!
//! One concept, one place: the stream codec ([`codec`]), the polygon records of thesis
//! Appendix 1 ([`polygon`]), the scan converter's fragment records ([`fragment`]), plane
//! classification and edge intersection ([`geometry`]), the pixel-centre coverage rule
//! ([`raster`]) and the way every binary reports errors ([`cli`]) are written here once
//! and used by every stage.

pub mod camera;
pub mod cli;
pub mod codec;
pub mod error;
pub mod fragment;
pub mod geometry;
pub mod header;
pub mod polygon;
pub mod raster;
pub mod text;

pub use codec::{Form, Reader, Record, Writer};
pub use error::StreamError;
pub use fragment::Fragment;
pub use glam::{DVec2, DVec3, DVec4};
pub use header::{Header, Space, SpaceKind, View};
pub use polygon::{Colour, Polygon, Token, Vertex};
