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
//! In the binary form a polygon without annotations is the version-1 record it always
//! was; an annotated one is a fourth record kind, so old streams stay readable.

use crate::codec::{Control, Record, MAX_VERTICES};
use crate::geometry::newell_plane;
use crate::header::Space;
use crate::text::Lexer;
use crate::StreamError;
use glam::{DVec3, DVec4};
use serde::{Deserialize, Serialize};
use std::io::{self, BufRead, Write};

/// An 8-bit RGB colour.
pub type Colour = [u8; 3];

/// A vertex. World `(x, y, z, 1)`; eye `(x_e, y_e, z_e, w)`; screen `(X, Y, depth, 1)`.
/// Keeping one type for every space lets one codec and one clipper serve them all; the
/// text form writes only the numbers the space has.
pub type Vertex = DVec4;

/// A polygon: a colour and its vertices in order (either winding).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Polygon {
    pub colour: Colour,
    pub vertices: Vec<Vertex>,
    /// The plane of the whole polygon (see the module notes), if a stage recorded it.
    pub plane: Option<DVec4>,
    /// Per edge i, the original edge it lies on, if it is a piece of one; empty = none.
    pub supports: Vec<Option<[Vertex; 2]>>,
}

impl Polygon {
    pub fn new(colour: Colour, vertices: Vec<Vertex>) -> Self {
        Polygon {
            colour,
            vertices,
            ..Default::default()
        }
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
    /// (persp does so). `None` when it is not a plane (fewer than three distinct
    /// points, w = 0).
    pub fn eye_plane(&self) -> Option<DVec4> {
        let points: Vec<DVec3> = self
            .vertices
            .iter()
            .map(|v| {
                let r = v.z / v.w;
                DVec3::new(v.x * r, v.y * r, v.z)
            })
            .collect();
        let n = newell_plane(&points);
        (n.is_finite() && n.truncate() != DVec3::ZERO).then_some(n)
    }

    /// Whether the polygon carries either annotation.
    pub fn is_annotated(&self) -> bool {
        self.plane.is_some() || self.supports.iter().any(Option::is_some)
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

/// The binary form of a [`Token`] as written: a polygon without annotations is record
/// kind 0 with only its colour and vertices (stream version 1 as it always was), an
/// annotated one is record kind 3 (appended, so the first three keep their numbers).
#[derive(Serialize)]
enum WireOut<'a> {
    Polygon(PlainRef<'a>),
    NextFrame,
    End,
    Annotated(&'a Polygon),
    Skip(u32),
}

#[derive(Serialize)]
struct PlainRef<'a> {
    colour: &'a Colour,
    vertices: &'a Vec<Vertex>,
}

#[derive(Deserialize)]
enum WireIn {
    Polygon(Plain),
    NextFrame,
    End,
    Annotated(Polygon),
    Skip(u32),
}

#[derive(Deserialize)]
struct Plain {
    colour: Colour,
    vertices: Vec<Vertex>,
}

impl Serialize for Token {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Token::Polygon(p) if p.is_annotated() => WireOut::Annotated(p).serialize(s),
            Token::Polygon(p) => WireOut::Polygon(PlainRef {
                colour: &p.colour,
                vertices: &p.vertices,
            })
            .serialize(s),
            Token::Skip(n) => WireOut::Skip(*n).serialize(s),
            Token::NextFrame => WireOut::NextFrame.serialize(s),
            Token::End => WireOut::End.serialize(s),
        }
    }
}

impl<'de> Deserialize<'de> for Token {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        Ok(match WireIn::deserialize(d)? {
            WireIn::Polygon(Plain { colour, vertices }) => {
                Token::Polygon(Polygon::new(colour, vertices))
            }
            WireIn::NextFrame => Token::NextFrame,
            WireIn::End => Token::End,
            WireIn::Annotated(p) => Token::Polygon(p),
            WireIn::Skip(n) => Token::Skip(n),
        })
    }
}

/// The keywords of the text form (Appendix 1's special values).
pub const NEXT_POLYGON: &str = "NEXT.POLYGON";
pub const NEXT_FRAME: &str = "NEXT.FRAME";
pub const END: &str = "END";
pub const COLOUR: &str = "colour";
/// The optional plane line after `colour`.
pub const PLANE: &str = "plane";
/// Starts a vertex's support (the original edge from it to the next vertex lies on).
pub const ON: &str = "on";
/// `skip N`, standing for N polygons of which the stream carries nothing.
pub const SKIP: &str = "skip";

/// What starts an item of a frame in the text form.
pub(crate) enum Start {
    /// `colour R G B`: a polygon (or a fragment polygon) follows.
    Colour(Colour),
    /// `skip N`.
    Skip(u32),
    NextFrame,
    End,
}

/// Reads what starts a polygon or a fragment polygon (`colour R G B`, or `skip N` in its
/// place), NEXT.POLYGON first unless it starts the frame; or NEXT.FRAME or END.
pub(crate) fn read_polygon_start<R: BufRead>(
    lex: &mut Lexer<R>,
    first_in_frame: bool,
) -> Result<Start, StreamError> {
    let word = lex.expect_word("a polygon, NEXT.FRAME or END")?;
    let head = match word.as_str() {
        NEXT_FRAME => return Ok(Start::NextFrame),
        END => return Ok(Start::End),
        NEXT_POLYGON if !first_in_frame => {
            let w = lex.expect_word("`colour` after NEXT.POLYGON")?;
            if w != COLOUR && w != "color" && w != SKIP {
                return Err(lex.error(format!("expected `colour` after NEXT.POLYGON, found `{w}`")));
            }
            w
        }
        NEXT_POLYGON => {
            return Err(
                lex.error("NEXT.POLYGON before the frame's first polygon (expected `colour`)")
            )
        }
        COLOUR | "color" | SKIP if first_in_frame => word,
        COLOUR | "color" | SKIP => {
            return Err(lex.error(format!(
                "expected NEXT.POLYGON between polygons, found `{word}`"
            )))
        }
        other if first_in_frame => {
            return Err(lex.error(format!(
                "expected `colour`, NEXT.FRAME or END, found `{other}`"
            )))
        }
        other => {
            return Err(lex.error(format!(
                "expected a vertex, NEXT.POLYGON, NEXT.FRAME or END, found `{other}`"
            )))
        }
    };
    if head == SKIP {
        let n = lex.integer("the number of polygons skipped", u32::MAX as u64)? as u32;
        if n == 0 {
            return Err(lex.error("`skip 0`: a skip stands for at least one polygon"));
        }
        return Ok(Start::Skip(n));
    }
    let mut colour = [0u8; 3];
    for (c, name) in colour.iter_mut().zip(["red", "green", "blue"]) {
        *c = lex.integer(&format!("the {name} component of the colour"), 255)? as u8;
    }
    Ok(Start::Colour(colour))
}

/// Writes `skip N`, after NEXT.POLYGON unless it starts the frame.
pub(crate) fn write_skip<W: Write>(out: &mut W, n: u32, first_in_frame: bool) -> io::Result<()> {
    if !first_in_frame {
        writeln!(out, "{NEXT_POLYGON}")?;
    }
    writeln!(out, "{SKIP} {n}")
}

/// Writes `colour R G B`, after NEXT.POLYGON unless it starts the frame.
pub(crate) fn write_polygon_start<W: Write>(
    out: &mut W,
    colour: Colour,
    first_in_frame: bool,
) -> io::Result<()> {
    if !first_in_frame {
        writeln!(out, "{NEXT_POLYGON}")?;
    }
    writeln!(out, "{COLOUR} {} {} {}", colour[0], colour[1], colour[2])
}

impl Record for Token {
    fn control(&self) -> Control {
        match self {
            Token::Polygon(_) => Control::Polygon,
            Token::Skip(n) => Control::Skip(*n),
            Token::NextFrame => Control::NextFrame,
            Token::End => Control::End,
        }
    }

    fn validate(&self, _space: &Space) -> Result<(), String> {
        if let Token::Skip(0) = self {
            return Err("`skip 0`: a skip stands for at least one polygon".into());
        }
        if let Token::Polygon(p) = self {
            if p.vertices.len() > MAX_VERTICES {
                return Err(format!(
                    "polygon of {} vertices (at most {MAX_VERTICES})",
                    p.vertices.len()
                ));
            }
            if let Some(i) = p.vertices.iter().position(|v| !v.is_finite()) {
                return Err(format!(
                    "vertex {i} is {:?}; coordinates must be finite",
                    p.vertices[i].to_array()
                ));
            }
            if !p.supports.is_empty() && p.supports.len() != p.vertices.len() {
                return Err(format!(
                    "{} edge supports for {} vertices (one per edge, or none)",
                    p.supports.len(),
                    p.vertices.len()
                ));
            }
            if let Some(i) = p
                .supports
                .iter()
                .position(|s| s.is_some_and(|[a, b]| !a.is_finite() || !b.is_finite()))
            {
                return Err(format!(
                    "the support of edge {i} is not finite; coordinates must be finite"
                ));
            }
            if p.plane.is_some_and(|n| !n.is_finite()) {
                return Err("the polygon's plane is not finite".into());
            }
        }
        Ok(())
    }

    fn read_text<R: BufRead>(
        lex: &mut Lexer<R>,
        space: &Space,
        first_in_frame: bool,
    ) -> Result<Self, StreamError> {
        let colour = match read_polygon_start(lex, first_in_frame)? {
            Start::Colour(c) => c,
            Start::Skip(n) => return Ok(Token::Skip(n)),
            Start::NextFrame => return Ok(Token::NextFrame),
            Start::End => return Ok(Token::End),
        };
        let arity = space.vertex_arity();
        if arity == 0 {
            // A fragments stream has no vertices: a polygon's vertices there would have no
            // numbers, and reading them would take nothing from the input (found by the
            // decode_text fuzz target). Stages check the space first; this keeps the
            // reader itself from looping.
            return Err(lex.error(format!(
                "a polygon in a {}-space stream, which holds no vertices",
                space.name()
            )));
        }
        let mut plane = None;
        if lex.peek()? == Some(PLANE) {
            lex.next_word()?;
            let mut n = [0.0; 4];
            for (c, name) in n.iter_mut().zip(["a", "b", "c", "d"]) {
                *c = lex.number(&format!("{name} of the polygon's plane (plane a b c d)"))?;
            }
            plane = Some(DVec4::from_array(n));
        }
        let mut vertices = Vec::new();
        let mut supports: Vec<Option<[Vertex; 2]>> = Vec::new();
        while lex.next_is_number()? {
            if vertices.len() == MAX_VERTICES {
                lex.peek()?;
                return Err(lex.error(format!("polygon has more than {MAX_VERTICES} vertices")));
            }
            let mut v = [0.0, 0.0, 0.0, 1.0];
            for (k, c) in v.iter_mut().take(arity).enumerate() {
                let what = match (space, k) {
                    (Space::Eye(_), 3) => "w".to_string(),
                    (Space::Screen { .. }, 2) => "depth".to_string(),
                    (_, k) => ["x", "y", "z"][k].to_string(),
                };
                *c = lex.number(&format!(
                    "{what} of vertex {} ({arity} numbers a vertex in {} space)",
                    vertices.len(),
                    space.name()
                ))?;
            }
            vertices.push(DVec4::from_array(v));
            if lex.peek()? == Some(ON) {
                lex.next_word()?;
                let i = vertices.len() - 1;
                let mut ends = [DVec4::new(0.0, 0.0, 0.0, 1.0); 2];
                for (end, name) in ends.iter_mut().zip(["A", "B"]) {
                    let mut c = [0.0, 0.0, 0.0, 1.0];
                    for (k, slot) in c.iter_mut().take(arity).enumerate() {
                        *slot = lex.number(&format!(
                            "coordinate {k} of support end {name} of edge {i} ({arity} numbers a point)"
                        ))?;
                    }
                    *end = DVec4::from_array(c);
                }
                supports.resize(i, None);
                supports.push(Some(ends));
            }
        }
        if !supports.is_empty() {
            supports.resize(vertices.len(), None);
        }
        Ok(Token::Polygon(Polygon {
            colour,
            vertices,
            plane,
            supports,
        }))
    }

    fn write_text<W: Write>(
        &self,
        out: &mut W,
        space: &Space,
        first_in_frame: bool,
    ) -> io::Result<()> {
        match self {
            Token::Polygon(p) => {
                write_polygon_start(out, p.colour, first_in_frame)?;
                if let Some(n) = p.plane {
                    writeln!(out, "{PLANE} {} {} {} {}", n.x, n.y, n.z, n.w)?;
                }
                let point = |out: &mut W, v: &Vertex| match space.vertex_arity() {
                    4 => write!(out, "{} {} {} {}", v.x, v.y, v.z, v.w),
                    _ => write!(out, "{} {} {}", v.x, v.y, v.z),
                };
                for (i, v) in p.vertices.iter().enumerate() {
                    point(out, v)?;
                    if let Some([a, b]) = p.support(i) {
                        write!(out, " {ON} ")?;
                        point(out, &a)?;
                        write!(out, " ")?;
                        point(out, &b)?;
                    }
                    writeln!(out)?;
                }
                Ok(())
            }
            Token::Skip(n) => write_skip(out, *n, first_in_frame),
            Token::NextFrame => writeln!(out, "{NEXT_FRAME}"),
            Token::End => writeln!(out, "{END}"),
        }
    }
}
