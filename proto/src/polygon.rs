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

use crate::codec::{Control, Record, MAX_VERTICES};
use crate::header::Space;
use crate::text::Lexer;
use crate::StreamError;
use glam::DVec4;
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
}

impl Polygon {
    pub fn new(colour: Colour, vertices: Vec<Vertex>) -> Self {
        Polygon { colour, vertices }
    }

    /// A polygon with its vertices given as `[x, y, z]` triples (w = 1).
    pub fn from_xyz(colour: Colour, points: &[[f64; 3]]) -> Self {
        Polygon {
            colour,
            vertices: points
                .iter()
                .map(|p| DVec4::new(p[0], p[1], p[2], 1.0))
                .collect(),
        }
    }

    /// The edges (v_i, v_{i+1}), closing back to the first vertex.
    pub fn edges(&self) -> impl Iterator<Item = (Vertex, Vertex)> + '_ {
        let n = self.vertices.len();
        (0..n).map(move |i| (self.vertices[i], self.vertices[(i + 1) % n]))
    }
}

/// One record of the polygon stream.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Token {
    Polygon(Polygon),
    NextFrame,
    End,
}

/// The keywords of the text form (Appendix 1's special values).
pub const NEXT_POLYGON: &str = "NEXT.POLYGON";
pub const NEXT_FRAME: &str = "NEXT.FRAME";
pub const END: &str = "END";
pub const COLOUR: &str = "colour";

/// Reads the `colour R G B` that starts a polygon or a fragment polygon, NEXT.POLYGON
/// first unless it starts the frame. `None` means NEXT.FRAME or END was read instead.
pub(crate) fn read_polygon_start<R: BufRead>(
    lex: &mut Lexer<R>,
    first_in_frame: bool,
) -> Result<Result<Colour, Control>, StreamError> {
    let word = lex.expect_word("a polygon, NEXT.FRAME or END")?;
    match word.as_str() {
        NEXT_FRAME => return Ok(Err(Control::NextFrame)),
        END => return Ok(Err(Control::End)),
        NEXT_POLYGON if !first_in_frame => {
            let w = lex.expect_word("`colour` after NEXT.POLYGON")?;
            if w != COLOUR && w != "color" {
                return Err(lex.error(format!("expected `colour` after NEXT.POLYGON, found `{w}`")));
            }
        }
        NEXT_POLYGON => {
            return Err(
                lex.error("NEXT.POLYGON before the frame's first polygon (expected `colour`)")
            )
        }
        COLOUR | "color" if first_in_frame => {}
        COLOUR | "color" => {
            return Err(lex.error("expected NEXT.POLYGON between polygons, found `colour`"))
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
    }
    let mut colour = [0u8; 3];
    for (c, name) in colour.iter_mut().zip(["red", "green", "blue"]) {
        *c = lex.integer(&format!("the {name} component of the colour"), 255)? as u8;
    }
    Ok(Ok(colour))
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
            Token::NextFrame => Control::NextFrame,
            Token::End => Control::End,
        }
    }

    fn validate(&self, _space: &Space) -> Result<(), String> {
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
        }
        Ok(())
    }

    fn read_text<R: BufRead>(
        lex: &mut Lexer<R>,
        space: &Space,
        first_in_frame: bool,
    ) -> Result<Self, StreamError> {
        let colour = match read_polygon_start(lex, first_in_frame)? {
            Ok(c) => c,
            Err(Control::NextFrame) => return Ok(Token::NextFrame),
            Err(_) => return Ok(Token::End),
        };
        let arity = space.vertex_arity();
        let mut vertices = Vec::new();
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
        }
        Ok(Token::Polygon(Polygon { colour, vertices }))
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
                for v in &p.vertices {
                    match space.vertex_arity() {
                        4 => writeln!(out, "{} {} {} {}", v.x, v.y, v.z, v.w)?,
                        _ => writeln!(out, "{} {} {}", v.x, v.y, v.z)?,
                    }
                }
                Ok(())
            }
            Token::NextFrame => writeln!(out, "{NEXT_FRAME}"),
            Token::End => writeln!(out, "{END}"),
        }
    }
}
