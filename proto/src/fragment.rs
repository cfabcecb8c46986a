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
//! Depth is an f64 in the form persp wrote (the reciprocal depth −K1/z_e by default;
//! [`crate::depth`]). A span carries its row's depth plane, not its first pixel's depth:
//! pixel x of the span has depth `z + x·dz`, where `z` is the plane's depth at the centre
//! of column 0 of the row ([`span_depth`]). So a pixel's depth is computed the same way,
//! to the bit, whether its span started at the polygon's left edge or at a splitting
//! plane (which is what keeps a split polygon identical to the whole).

use crate::codec::polygons::{
    read_polygon_start, write_polygon_start, write_skip, Start, END, NEXT_FRAME,
};
use crate::codec::{expect_zero, head, head_n, BinaryError, BinaryInput, Control, Record};
use crate::header::Header;
use crate::polygon::Colour;
use crate::text::Lexer;
use crate::StreamError;
use serde::{Deserialize, Serialize};
use std::io::{self, BufRead, Read, Write};

/// The depth of pixel `x` of a span whose row has depth `z` at column 0 and steps `dz`
/// a column: `z + x·dz`, one multiplication and one addition, each rounded (no fused
/// multiply-add, so that every stage and every vector width computes the same bits).
#[inline]
pub fn span_depth(z: f64, dz: f64, x: u32) -> f64 {
    z + x as f64 * dz
}

/// One record of the fragment stream.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Fragment {
    /// Opens the next polygon (NEXT.POLYGON and its colour, in the thesis's terms).
    Polygon(Colour),
    /// Pixels `x0..x1` (end exclusive) of row `y`; pixel `x` has depth `z + x·dz`
    /// ([`span_depth`]): `z` is the row's depth at column 0, wherever the span starts.
    Span {
        y: u32,
        x0: u32,
        x1: u32,
        z: f64,
        dz: f64,
    },
    /// One pixel and its depth: the thesis's quadruplet, less the colour sent once above.
    Pixel {
        x: u32,
        y: u32,
        z: f64,
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
    /// `shade K A B D`: one channel (K = 0 red, 1 green, 2 blue) of the current
    /// polygon's colour plane over device coordinates, divided by its colour coefficient,
    /// `c = −(A·X + B·Y + D)`, after its colour record and before its spans: the polygon is
    /// Gouraud-shaded, and each of its pixels takes the colour the planes give at its
    /// centre, as the scan converter computes it ([`crate::shade::Shading`]), instead of
    /// the colour record's. Three records, one a channel, so that a fragment stays as
    /// small as a span (32 bytes).
    Shade {
        channel: u8,
        plane: [f64; 3],
    },
}

impl Default for Fragment {
    /// A placeholder for [`Reader::next_into`](crate::Reader::next_into) to read into.
    fn default() -> Self {
        Fragment::End
    }
}

/// The binary records of the fragment stream (stream version 3; `proto::codec`
/// describes the 8-byte head `tag, three bytes, n`), each a multiple of 8 bytes:
///
/// | tag | record | head | then |
/// |-----|--------|------|------|
/// | 0 | colour (a polygon starts) | colour, n = 0 | – |
/// | 1 | span | zeros, n = y | `x0: u32, x1: u32, z: f64, dz: f64` |
/// | 2 | pixel | zeros, n = y | `x: u32`, a zero `u32`, `z: f64` |
/// | 3 | NEXT.FRAME | zeros | – |
/// | 4 | END | zeros | – |
/// | 5 | `skip N` | zeros, n = N | – |
/// | 6 | run | colour, n = y | `x0: u32, x1: u32` |
mod tag {
    pub const POLYGON: u8 = 0;
    pub const SPAN: u8 = 1;
    pub const PIXEL: u8 = 2;
    pub const NEXT_FRAME: u8 = 3;
    pub const END: u8 = 4;
    pub const SKIP: u8 = 5;
    pub const RUN: u8 = 6;
    pub const SHADE: u8 = 7;
}

#[inline]
fn u32_at(b: &[u8], i: usize) -> u32 {
    u32::from_le_bytes(b[i..i + 4].try_into().expect("4 bytes"))
}

#[inline]
fn f64_at(b: &[u8], i: usize) -> f64 {
    f64::from_le_bytes(b[i..i + 8].try_into().expect("8 bytes"))
}

impl<R: Read> crate::codec::Reader<Fragment, R> {
    /// Appends to `out` the run records that come next (at most `max`), as many as the
    /// input has buffered whole: the merger's hot path, a leaf's finished pixels decoded
    /// without a call per record. It stops before any other record, and before a run
    /// outside the screen, for [`crate::codec::Reader::next_into`] to read or refuse.
    pub fn runs_into(&mut self, out: &mut Vec<Fragment>, max: usize) {
        self.decode_buffered(|bytes, header| {
            let (width, height) = header.space.screen_size().unwrap_or((0, 0));
            let mut used = 0;
            for r in bytes.chunks_exact(16).take(max) {
                let (y, x0, x1) = (u32_at(r, 4), u32_at(r, 8), u32_at(r, 12));
                if r[0] != tag::RUN || y >= height || x0 > x1 || x1 > width {
                    break;
                }
                out.push(Fragment::Run {
                    y,
                    x0,
                    x1,
                    colour: [r[1], r[2], r[3]],
                });
                used += 16;
            }
            used
        });
    }
}

impl Record for Fragment {
    #[inline]
    fn control(&self) -> Control {
        match self {
            Fragment::Polygon(_) => Control::Polygon,
            Fragment::Span { .. } | Fragment::Pixel { .. } | Fragment::Shade { .. } => {
                Control::Data
            }
            Fragment::Skip(n) => Control::Skip(*n),
            Fragment::Run { .. } => Control::Finished,
            Fragment::NextFrame => Control::NextFrame,
            Fragment::End => Control::End,
        }
    }

    fn validate(&self, header: &Header) -> Result<(), String> {
        let (width, height) = header.space.screen_size().unwrap_or((0, 0));
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
            Fragment::Span { z, dz, .. } if !(z.is_finite() && dz.is_finite()) => Err(format!(
                "span depth {z} and step {dz}: depths must be finite"
            )),
            Fragment::Pixel { z, .. } if !z.is_finite() => {
                Err(format!("pixel depth {z}: depths must be finite"))
            }
            Fragment::Shade { channel, .. } if channel > 2 => Err(format!(
                "shade of channel {channel}: the channels are 0 (red), 1 (green) and 2 (blue)"
            )),
            Fragment::Shade { plane, .. } if !plane.iter().all(|c| c.is_finite()) => Err(format!(
                "colour plane {plane:?}: its numbers must be finite"
            )),
            Fragment::Skip(0) => Err("`skip 0`: a skip stands for at least one polygon".into()),
            _ => Ok(()),
        }
    }

    fn binary_control(head: &[u8; 8]) -> Option<Control> {
        match head[0] {
            tag::POLYGON => Some(Control::Polygon),
            tag::SPAN | tag::PIXEL | tag::SHADE => Some(Control::Data),
            tag::NEXT_FRAME => Some(Control::NextFrame),
            tag::END => Some(Control::End),
            tag::SKIP => Some(Control::Skip(head_n(head))),
            tag::RUN => Some(Control::Finished),
            _ => None,
        }
    }

    #[inline]
    fn read_binary<R: Read>(
        &mut self,
        _spare: &mut Self,
        head: &[u8; 8],
        input: &mut BinaryInput<R>,
    ) -> Result<(), BinaryError> {
        let n = head_n(head);
        *self = match head[0] {
            tag::POLYGON => {
                if n != 0 {
                    return Err(BinaryError::Invalid(format!(
                        "not a valid colour record (n = {n}, not zero); is the stream corrupt?"
                    )));
                }
                Fragment::Polygon([head[1], head[2], head[3]])
            }
            tag::SPAN => {
                expect_zero(head, false, "span")?;
                let b: [u8; 24] = input.array()?;
                Fragment::Span {
                    y: n,
                    x0: u32_at(&b, 0),
                    x1: u32_at(&b, 4),
                    z: f64_at(&b, 8),
                    dz: f64_at(&b, 16),
                }
            }
            tag::PIXEL => {
                expect_zero(head, false, "pixel")?;
                let b: [u8; 16] = input.array()?;
                if u32_at(&b, 4) != 0 {
                    return Err(BinaryError::Invalid(
                        "not a valid pixel record (unused bytes are not zero); is the stream corrupt?"
                            .into(),
                    ));
                }
                Fragment::Pixel {
                    x: u32_at(&b, 0),
                    y: n,
                    z: f64_at(&b, 8),
                }
            }
            tag::NEXT_FRAME => {
                expect_zero(head, true, "NEXT.FRAME")?;
                Fragment::NextFrame
            }
            tag::END => {
                expect_zero(head, true, "END")?;
                Fragment::End
            }
            tag::SKIP => {
                expect_zero(head, false, "skip")?;
                Fragment::Skip(n)
            }
            tag::RUN => {
                let b: [u8; 8] = input.array()?;
                Fragment::Run {
                    y: n,
                    x0: u32_at(&b, 0),
                    x1: u32_at(&b, 4),
                    colour: [head[1], head[2], head[3]],
                }
            }
            tag::SHADE => {
                if head[2..].iter().any(|&b| b != 0) {
                    return Err(BinaryError::Invalid(
                        "not a valid shade record (unused bytes are not zero); is the stream \
                         corrupt?"
                            .into(),
                    ));
                }
                let b: [u8; 24] = input.array()?;
                Fragment::Shade {
                    channel: head[1],
                    plane: [f64_at(&b, 0), f64_at(&b, 8), f64_at(&b, 16)],
                }
            }
            other => {
                return Err(BinaryError::Invalid(format!(
                "not a valid record (unknown fragment-stream tag {other}); is the stream corrupt?"
            )))
            }
        };
        Ok(())
    }

    #[inline]
    fn write_binary<W: Write>(&self, out: &mut W) -> io::Result<()> {
        match *self {
            Fragment::Polygon(colour) => out.write_all(&head(tag::POLYGON, colour, 0)),
            Fragment::Span { y, x0, x1, z, dz } => {
                let mut b = [0u8; 32];
                b[..8].copy_from_slice(&head(tag::SPAN, [0; 3], y));
                b[8..12].copy_from_slice(&x0.to_le_bytes());
                b[12..16].copy_from_slice(&x1.to_le_bytes());
                b[16..24].copy_from_slice(&z.to_le_bytes());
                b[24..32].copy_from_slice(&dz.to_le_bytes());
                out.write_all(&b)
            }
            Fragment::Pixel { x, y, z } => {
                let mut b = [0u8; 24];
                b[..8].copy_from_slice(&head(tag::PIXEL, [0; 3], y));
                b[8..12].copy_from_slice(&x.to_le_bytes());
                b[16..24].copy_from_slice(&z.to_le_bytes());
                out.write_all(&b)
            }
            Fragment::NextFrame => out.write_all(&head(tag::NEXT_FRAME, [0; 3], 0)),
            Fragment::End => out.write_all(&head(tag::END, [0; 3], 0)),
            Fragment::Skip(n) => out.write_all(&head(tag::SKIP, [0; 3], n)),
            Fragment::Run { y, x0, x1, colour } => {
                let mut b = [0u8; 16];
                b[..8].copy_from_slice(&head(tag::RUN, colour, y));
                b[8..12].copy_from_slice(&x0.to_le_bytes());
                b[12..16].copy_from_slice(&x1.to_le_bytes());
                out.write_all(&b)
            }
            Fragment::Shade { channel, plane } => {
                let mut b = [0u8; 32];
                b[..8].copy_from_slice(&head(tag::SHADE, [channel, 0, 0], 0));
                for (k, c) in plane.iter().enumerate() {
                    b[8 + 8 * k..16 + 8 * k].copy_from_slice(&c.to_le_bytes());
                }
                out.write_all(&b)
            }
        }
    }

    fn read_text<R: BufRead>(
        &mut self,
        _spare: &mut Self,
        lex: &mut Lexer<R>,
        header: &Header,
        first_in_frame: bool,
    ) -> Result<(), StreamError> {
        let record = match lex.peek()? {
            Some("span") | Some("pixel") | Some("shade") if first_in_frame => {
                return Err(lex.error("pixels before the frame's first `colour`"));
            }
            Some("span") => {
                lex.skip_word();
                let y = lex.integer("the span's row", u32::MAX as u64)? as u32;
                let x0 = lex.integer("the span's first column", u32::MAX as u64)? as u32;
                let x1 = lex.integer("the span's end column", u32::MAX as u64)? as u32;
                let z = lex.number("the span's depth at column 0")?;
                let dz = lex.number("the span's depth step")?;
                Fragment::Span { y, x0, x1, z, dz }
            }
            Some("pixel") => {
                lex.skip_word();
                let x = lex.integer("the pixel's column", u32::MAX as u64)? as u32;
                let y = lex.integer("the pixel's row", u32::MAX as u64)? as u32;
                let z = lex.number("the pixel's depth")?;
                Fragment::Pixel { x, y, z }
            }
            Some("shade") => {
                lex.skip_word();
                let channel = lex.integer("the shade's channel (0, 1 or 2)", 2)? as u8;
                let mut plane = [0.0; 3];
                for (c, name) in plane.iter_mut().zip(["A", "B", "D"]) {
                    *c = lex.number(format_args!("{name} of the colour plane"))?;
                }
                Fragment::Shade { channel, plane }
            }
            Some("run") => {
                lex.skip_word();
                let y = lex.integer("the run's row", u32::MAX as u64)? as u32;
                let x0 = lex.integer("the run's first column", u32::MAX as u64)? as u32;
                let x1 = lex.integer("the run's end column", u32::MAX as u64)? as u32;
                let mut colour = [0u8; 3];
                for (c, name) in colour.iter_mut().zip(["red", "green", "blue"]) {
                    *c = lex.integer(
                        format_args!("the {name} component of the run's colour"),
                        255,
                    )? as u8;
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
        record.validate(header).map_err(|m| lex.error(m))?;
        *self = record;
        Ok(())
    }

    fn write_text<W: Write>(
        &self,
        out: &mut W,
        _header: &Header,
        first_in_frame: bool,
    ) -> io::Result<()> {
        match *self {
            Fragment::Polygon(colour) => write_polygon_start(out, colour, first_in_frame),
            Fragment::Span { y, x0, x1, z, dz } => writeln!(out, "span {y} {x0} {x1} {z} {dz}"),
            Fragment::Pixel { x, y, z } => writeln!(out, "pixel {x} {y} {z}"),
            Fragment::Skip(n) => write_skip(out, n, first_in_frame),
            Fragment::Run {
                y,
                x0,
                x1,
                colour: [r, g, b],
            } => {
                writeln!(out, "run {y} {x0} {x1} {r} {g} {b}")
            }
            Fragment::Shade {
                channel,
                plane: [a, b, d],
            } => writeln!(out, "shade {channel} {a} {b} {d}"),
            Fragment::NextFrame => writeln!(out, "{NEXT_FRAME}"),
            Fragment::End => writeln!(out, "{END}"),
        }
    }
}
