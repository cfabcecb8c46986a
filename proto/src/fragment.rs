//! The scan converter's output, the BUFFER process's input.
//!
//! The thesis sends a `(colour, x, y, depth)` quadruplet per pixel (chapter 4.2.2).
//! polypipe sends, per polygon, its colour once, then either runs of pixels on one row
//! (spans, the default) or single pixels (the thesis's form, `scanconv --pixels`), so the
//! two can be measured against each other. Polygons are numbered as in the polygon
//! stream (every polygon, even one that covers no pixel, opens with its colour record),
//! which is what lets `zbuf` give a tie in depth to the earlier polygon whichever input
//! its pixels came from.
//!
//! Depth is fixed point: [`DEPTH_ONE`] units to one unit of depth. A span carries the
//! depth at its first pixel and the step to the next; in integers the stepping is exact,
//! so a pixel's depth is the same whether its span started at the polygon's left edge or
//! at a splitting plane (which is what keeps a split polygon identical to the whole).

use crate::codec::{Control, Record};
use crate::header::Space;
use crate::polygon::{read_polygon_start, write_polygon_start, write_skip, Colour, Start, END, NEXT_FRAME};
use crate::text::Lexer;
use crate::StreamError;
use serde::{Deserialize, Serialize};
use std::io::{self, BufRead, Write};

/// Fixed-point units in one unit of depth: 2^40, about 1e-12 resolution for depths in
/// [0, 1], with room in an `i64` for depths up to about 8 million (eye-z mode).
pub const DEPTH_ONE: f64 = (1u64 << 40) as f64;

/// A depth in fixed point, rounded to the nearest unit and saturated at the `i64` range.
pub fn depth_to_fixed(z: f64) -> i64 {
    (z * DEPTH_ONE).round() as i64
}

/// A fixed-point depth back as a float.
pub fn depth_from_fixed(z: i64) -> f64 {
    z as f64 / DEPTH_ONE
}

/// One record of the fragment stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Fragment {
    /// Opens the next polygon (NEXT.POLYGON and its colour, in the thesis's terms).
    Polygon(Colour),
    /// Pixels `x0..x1` (end exclusive) of row `y`; pixel `x` has depth `z0 + (x − x0)·dz`.
    Span {
        y: u32,
        x0: u32,
        x1: u32,
        z0: i64,
        dz: i64,
    },
    /// One pixel and its depth: the thesis's quadruplet, less the colour sent once above.
    Pixel {
        x: u32,
        y: u32,
        z: i64,
    },
    NextFrame,
    End,
    /// The next N polygons of the frame, none of which covers a pixel of this stream
    /// (they missed this leaf of the splitter tree): polygon numbering is kept in one
    /// record. N ≥ 1. Text: `skip N` where a colour record would stand.
    Skip(u32),
    /// Finished pixels `x0..x1` (end exclusive) of row `y`, all of `colour`: visibility is
    /// already resolved (a leaf of the tree that resolved its own region, docs/DESIGN.md's
    /// "leaves resolve visibility"). The merger places them without a depth test; they
    /// belong to no polygon and may stand anywhere in a frame. Text: `run y x0 x1 R G B`.
    Run {
        y: u32,
        x0: u32,
        x1: u32,
        colour: Colour,
    },
}

impl Record for Fragment {
    fn control(&self) -> Control {
        match self {
            Fragment::Polygon(_) => Control::Polygon,
            Fragment::Span { .. } | Fragment::Pixel { .. } => Control::Data,
            Fragment::Skip(n) => Control::Skip(*n),
            Fragment::Run { .. } => Control::Finished,
            Fragment::NextFrame => Control::NextFrame,
            Fragment::End => Control::End,
        }
    }

    fn validate(&self, space: &Space) -> Result<(), String> {
        let (width, height) = space.screen_size().unwrap_or((0, 0));
        match *self {
            Fragment::Span { y, x0, x1, .. } if y >= height || x0 > x1 || x1 > width => {
                Err(format!(
                    "span of row {y}, columns {x0}..{x1}, is outside the {width}x{height} screen"
                ))
            }
            Fragment::Pixel { x, y, .. } if x >= width || y >= height => Err(format!(
                "pixel ({x}, {y}) is outside the {width}x{height} screen"
            )),
            Fragment::Run { y, x0, x1, .. } if y >= height || x0 > x1 || x1 > width => {
                Err(format!(
                    "run of row {y}, columns {x0}..{x1}, is outside the {width}x{height} screen"
                ))
            }
            Fragment::Skip(0) => Err("`skip 0`: a skip stands for at least one polygon".into()),
            _ => Ok(()),
        }
    }

    fn read_text<R: BufRead>(
        lex: &mut Lexer<R>,
        space: &Space,
        first_in_frame: bool,
    ) -> Result<Self, StreamError> {
        let record = match lex.peek()? {
            Some("span") | Some("pixel") if first_in_frame => {
                return Err(lex.error("pixels before the frame's first `colour`"));
            }
            Some("span") => {
                lex.next_word()?;
                let y = lex.integer("the span's row", u32::MAX as u64)? as u32;
                let x0 = lex.integer("the span's first column", u32::MAX as u64)? as u32;
                let x1 = lex.integer("the span's end column", u32::MAX as u64)? as u32;
                let z0 = lex.signed("the span's first depth")?;
                let dz = lex.signed("the span's depth step")?;
                Fragment::Span { y, x0, x1, z0, dz }
            }
            Some("pixel") => {
                lex.next_word()?;
                let x = lex.integer("the pixel's column", u32::MAX as u64)? as u32;
                let y = lex.integer("the pixel's row", u32::MAX as u64)? as u32;
                let z = lex.signed("the pixel's depth")?;
                Fragment::Pixel { x, y, z }
            }
            Some("run") => {
                lex.next_word()?;
                let y = lex.integer("the run's row", u32::MAX as u64)? as u32;
                let x0 = lex.integer("the run's first column", u32::MAX as u64)? as u32;
                let x1 = lex.integer("the run's end column", u32::MAX as u64)? as u32;
                let mut colour = [0u8; 3];
                for (c, name) in colour.iter_mut().zip(["red", "green", "blue"]) {
                    *c = lex.integer(&format!("the {name} component of the run's colour"), 255)?
                        as u8;
                }
                Fragment::Run { y, x0, x1, colour }
            }
            _ => match read_polygon_start(lex, first_in_frame)? {
                Start::Colour(colour) => Fragment::Polygon(colour),
                Start::Skip(n) => Fragment::Skip(n),
                Start::NextFrame => Fragment::NextFrame,
                Start::End => Fragment::End,
            },
        };
        record.validate(space).map_err(|m| lex.error(m))?;
        Ok(record)
    }

    fn write_text<W: Write>(
        &self,
        out: &mut W,
        _space: &Space,
        first_in_frame: bool,
    ) -> io::Result<()> {
        match *self {
            Fragment::Polygon(colour) => write_polygon_start(out, colour, first_in_frame),
            Fragment::Span { y, x0, x1, z0, dz } => writeln!(out, "span {y} {x0} {x1} {z0} {dz}"),
            Fragment::Pixel { x, y, z } => writeln!(out, "pixel {x} {y} {z}"),
            Fragment::Skip(n) => write_skip(out, n, first_in_frame),
            Fragment::Run { y, x0, x1, colour: [r, g, b] } => {
                writeln!(out, "run {y} {x0} {x1} {r} {g} {b}")
            }
            Fragment::NextFrame => writeln!(out, "{NEXT_FRAME}"),
            Fragment::End => writeln!(out, "{END}"),
        }
    }
}
