//! The polygon stream of thesis Appendix 1:
//!
//! ```text
//! movie   ::= frame { NEXT.FRAME frame } END
//! frame   ::= [ polygon { NEXT.POLYGON polygon } ]
//! polygon ::= colour { vertex }
//! ```
//!
//! In the binary form each polygon is one record, so NEXT.POLYGON is implied between
//! records; the text form writes it out. A polygon may have no vertex, or one or two
//! (extreme splitter cases, bad input): stages pass such polygons on so that polygon k is
//! the same polygon on every branch of the splitter tree, and the scan converter discards
//! them.
//!
//! Two opt-in annotations ride along with a polygon, for the splitter tree (thesis ch. 6)
//! to render exactly as the linear pipeline does; stages that do not need them pass them
//! through untouched, and a polygon without them is written exactly as before:
//!
//! * `plane`: the polygon's plane, computed once before any split so that every piece
//!   of it gets the whole's depth. In eye space it is the Newell plane
//!   `a·x' + b·y' + c·z_e + d = 0` over the normalised eye coordinates
//!   `(x', y') = (x_e, y_e)·z_e/w` (in which the viewing pyramid has unit slopes, so that
//!   the plane can be taken to the screen without knowing s/d); in screen space it is
//!   the depth plane `a·X + b·Y + c·depth + d = 0`. Text: a line `plane a b c d` after
//!   `colour`.
//! * `supports`: for edge i (vertex i → vertex i+1), optionally the two endpoints of the
//!   original edge it is a piece of, so that the scan converter computes its crossings
//!   from the whole edge, bit for bit as for the unsplit polygon. Text: `on` and the two
//!   endpoints after vertex i, e.g. `x y z w on ax ay az aw bx by bz bw`. An empty list,
//!   or one of all `None`, means no edge has a support.
//!
//! The annotations belong to eye and screen space; a world-space stream that carries
//! them is refused where they stand (viewxf would pass them on untransformed).
//!
//! These are the records; their binary and text forms are [`crate::codec`]'s
//! (`codec::polygons`): in the binary form a polygon without annotations is a head and
//! its vertices, an annotated one a record kind of its own.

use crate::newell::newell_plane_of;
use glam::{DVec3, DVec4};
use serde::{Deserialize, Serialize};

/// An 8-bit RGB colour.
pub type Colour = [u8; 3];

/// A vertex. World `(x, y, z, 1)`; eye `(x_e, y_e, z_e, w)`; screen `(X, Y, depth, 1)`.
/// Keeping one type for every space lets one codec and one clipper serve them all; the
/// text form writes only the numbers the space has.
pub type Vertex = DVec4;

/// What a vertex carries besides its position: three numbers whose meaning the stream's
/// header decides. Under `vertex-colours` they are the vertex's colour (red, green and
/// blue, each a number from 0 to 255; Gouraud shading), under `vertex-normals` its normal
/// (Phong shading: the pixel is lit with it). Either way they are kept as f64 through the
/// pipeline and interpolated alike, at every cut and across the screen, so that an
/// interpolated colour is rounded once, at the pixel.
pub type VertexAttr = DVec3;

/// A polygon's colour planes, one per channel (red, green, blue): `(A, B, C, D)` with
/// `A·x + B·y + C·c + D = 0`, over eye-space screen positions `(x_s, y_s)` or over device
/// coordinates `(X, Y)`, as the stream's space says.
pub type ColourPlanes = [DVec4; 3];

/// A polygon: a colour and its vertices in order (either winding).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Polygon {
    pub colour: Colour,
    pub vertices: Vec<Vertex>,
    /// The plane of the whole polygon (see the module notes), if a stage recorded it.
    pub plane: Option<DVec4>,
    /// Per edge i, the original edge it lies on, if it is a piece of one; empty = none.
    pub supports: Vec<Option<[Vertex; 2]>>,
    /// Per vertex, its colour (Gouraud shading, [`crate::shade`]), or in a stream whose
    /// header says `vertex-normals` its normal (Phong shading: the polygon's `colour` is
    /// then the surface's, lit per pixel); empty = the polygon is one flat `colour`. A
    /// stream declares them in its header (`vertex-colours`, `vertex-normals`). Both are
    /// three numbers interpolated the same way at every cut and across the screen, so every
    /// stage but the one that lights pixels treats them alike.
    pub vertex_attrs: Vec<VertexAttr>,
    /// The colour planes of the whole polygon ([`crate::shade`]), if a stage recorded
    /// them: over the screen position in eye space, over device coordinates in screen
    /// space. Text: a line `shade` and twelve numbers after `plane`. Boxed, so that a flat
    /// polygon stays as small as it was (the codec's encode loop measured it).
    pub shade: Option<Box<ColourPlanes>>,
    /// The colour's opacity, 0–255 (255 opaque, the default). A stream declares it in its
    /// header (`opacity`), and every colour record is then `colour R G B A`.
    pub opacity: u8,
}

impl Default for Polygon {
    fn default() -> Self {
        Polygon {
            colour: [0; 3],
            vertices: Vec::new(),
            plane: None,
            supports: Vec::new(),
            vertex_attrs: Vec::new(),
            shade: None,
            opacity: OPAQUE,
        }
    }
}

/// The opacity of an opaque colour.
pub const OPAQUE: u8 = 255;

impl Polygon {
    pub fn new(colour: Colour, vertices: Vec<Vertex>) -> Self {
        Polygon {
            colour,
            vertices,
            ..Default::default()
        }
    }

    /// Whether the polygon carries per-vertex colours or normals (is Gouraud- or
    /// Phong-shaded).
    #[inline]
    pub fn is_shaded(&self) -> bool {
        !self.vertex_attrs.is_empty()
    }

    /// The support of edge i (vertex i → vertex i+1), if it has one.
    #[inline]
    pub fn support(&self, i: usize) -> Option<[Vertex; 2]> {
        self.supports.get(i).copied().flatten()
    }

    /// The plane an eye-space polygon records before it is split: Newell's plane
    /// (`proto::geometry::newell_plane`) over the normalised eye points
    /// `(x_e·z_e/w, y_e·z_e/w, z_e)`. Those are `z_e·(x_e/w, y_e/w, 1)`, and x_e/w, y_e/w
    /// are a·x_s and y_s, so the plane takes itself to the screen without s/d
    /// (persp does so). A polygon of no net area there (a bowtie whose lobes cancel)
    /// gets the plane it is seen in ([`crate::newell::plane_seen_in_perspective`]), the
    /// same for every piece of it. `None` when it is not a plane (fewer than three
    /// distinct points, w = 0, no area on the screen either).
    pub fn eye_plane(&self) -> Option<DVec4> {
        let n = newell_plane_of(&self.vertices, |v| {
            let r = v.z / v.w;
            DVec3::new(v.x * r, v.y * r, v.z)
        });
        if n.is_finite() && n.truncate() != DVec3::ZERO {
            return Some(n);
        }
        crate::newell::plane_seen_in_perspective(&self.vertices)
    }

    /// Whether the polygon carries an annotation (`plane`, `on` or `shade`).
    pub fn is_annotated(&self) -> bool {
        self.plane.is_some() || self.shade.is_some() || self.supports.iter().any(Option::is_some)
    }

    /// A polygon with its vertices given as `[x, y, z]` triples (w = 1).
    pub fn from_xyz(colour: Colour, points: &[[f64; 3]]) -> Self {
        Polygon::new(
            colour,
            points
                .iter()
                .map(|p| DVec4::new(p[0], p[1], p[2], 1.0))
                .collect(),
        )
    }

    /// The edges (v_i, v_{i+1}), closing back to the first vertex.
    pub fn edges(&self) -> impl Iterator<Item = (Vertex, Vertex)> + '_ {
        let n = self.vertices.len();
        (0..n).map(move |i| (self.vertices[i], self.vertices[(i + 1) % n]))
    }
}

/// One record of the polygon stream.
#[derive(Clone, Debug, PartialEq)]
pub enum Token {
    Polygon(Polygon),
    /// `skip N`: the next N polygons of the frame, of which this stream carries nothing
    /// (a splitter output that gets no piece of them). It keeps polygon numbering, so
    /// polygon k is the same polygon on every branch of the tree, in one record instead
    /// of N empty ones. N ≥ 1. Text: `skip N` where a polygon would stand.
    Skip(u32),
    NextFrame,
    End,
}

impl Default for Token {
    /// A placeholder for [`Reader::next_into`](crate::Reader::next_into) to read into.
    fn default() -> Self {
        Token::End
    }
}
