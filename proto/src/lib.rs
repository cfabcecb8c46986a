//! # proto: the polypipe token stream and the geometry every stage shares
//!
//! One concept, one place: the stream codec ([`codec`]), the polygon records of thesis
//! Appendix 1 ([`polygon`]), the scan converter's fragment records ([`fragment`]), plane
//! classification and edge intersection ([`geometry`]), the pixel-centre coverage rule
//! ([`raster`]) and the frames' picture format ([`ppm`]) are written here once and used
//! by every stage. How a stage binary parses its arguments, reports an error and exits
//! is not here but in the `stagecli` crate: a user of the stream needs no CLI parser.

pub mod camera;
pub mod codec;
pub mod depth;
pub mod error;
pub mod exact;
pub mod fragment;
pub mod geometry;
pub mod header;
pub mod newell;
pub mod numbers;
pub mod perspective;
pub mod polygon;
pub mod ppm;
pub mod raster;
pub mod shade;
pub mod text;

pub use codec::{Form, Reader, Record, Writer};
pub use error::StreamError;
pub use fragment::Fragment;
pub use glam::{DVec2, DVec3, DVec4};
pub use header::{Attributes, DepthForm, Header, Space, SpaceKind, View};
pub use polygon::{Colour, ColourPlanes, Polygon, Token, Vertex, VertexAttr, OPAQUE};
