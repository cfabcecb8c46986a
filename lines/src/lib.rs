//! # lines: hidden-line drawings as SVG, read back, and scored
//!
//! A hidden-line drawing (Archuleta 1972, "Hidden surface line drawing algorithm") is a
//! set of straight pieces in device coordinates (X right, Y down, pixels): the visible
//! parts of polygon edges and of the lines where polygons pass through each other.
//! `hiddenline` writes them, `chart` reads them back and scores them; the form lives here
//! so that both agree on it.
//!
//! ## The SVG form
//!
//! Each piece is a `<line x1 y1 x2 y2 stroke="rgb(R,G,B)"/>` (`class="intersection"` on a
//! piece of a line of intersection). Pieces that come one after another along one line,
//! in one colour and class (the visible pieces of one edge, as the continuous method
//! finds them), are joined into one element ([`SvgWriter`]): a `<line>` from the first
//! piece's start to the last piece's end with `stroke-dasharray="d g d g … d"`, the
//! pieces' lengths and the gaps between them in pixels to 1/1000. With the round caps the
//! drawing uses, each dash is stroked as the separate line was, so the drawing is the
//! same; 20,000 slivers' 2.4 million pieces take 2 numbers each instead of a `<line>`
//! each. [`read_svg`] gives the pieces back.
//!
//! ## The line error
//!
//! [`line_error`]: the length of the reference's pieces that no drawn piece comes within
//! `tolerance` pixels of (visible edge missed), plus the length of the drawn pieces that
//! no reference piece comes within `tolerance` of (drawn where the reference has nothing:
//! hidden, or off the edge), in pixels, intersection lines included. It is computed
//! exactly, not sampled: the points of a segment within distance ε of another segment
//! are the segment's intersection with a capsule (a convex set), one interval of its
//! parameter, and the intervals' union is measured.
//!
//! ## The drawing as a picture
//!
//! [`raster::picture`]: the pieces stroked black on white as the SVG strokes them (a
//! pen with round caps), K×K samples a pixel box-filtered as the 16×16 reference
//! pictures are, so that a drawing has an RMS error in grey levels against the exact
//! drawing's picture, as the pictures of the hidden-surface methods have against theirs.

pub mod raster;

use proto::{Colour, DVec2};
use std::fmt::Write as _;

/// A visible piece of an edge, or of a line of intersection, in device coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    pub from: DVec2,
    pub to: DVec2,
    pub colour: Colour,
    /// A piece of the line where two polygons pass through each other, not of an edge.
    pub intersection: bool,
}

impl Segment {
    pub fn length(&self) -> f64 {
        (self.to - self.from).length()
    }
}

/// The SVG's opening: the `<svg>` element, the background and the group of lines.
pub fn svg_start(width: u32, height: u32, background: Colour, stroke: f64) -> String {
    let mut s = String::new();
    let [r, g, b] = background;
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}">"#
    );
    let _ = writeln!(
        s,
        r#"<rect width="{width}" height="{height}" fill="rgb({r},{g},{b})"/>"#
    );
    let _ = writeln!(
        s,
        r#"<g fill="none" stroke-width="{stroke}" stroke-linecap="round">"#
    );
    s
}

/// The SVG's closing.
pub const SVG_END: &str = "</g>\n</svg>\n";

/// One piece as a `<line>`.
pub fn svg_line(out: &mut String, seg: &Segment) {
    svg_element(out, seg, seg.to, "");
}

fn svg_element(out: &mut String, seg: &Segment, to: DVec2, dashes: &str) {
    let [r, g, b] = seg.colour;
    let class = if seg.intersection {
        r#" class="intersection""#
    } else {
        ""
    };
    let _ = writeln!(
        out,
        r#"<line{class} x1="{}" y1="{}" x2="{}" y2="{}" stroke="rgb({r},{g},{b})"{dashes}/>"#,
        seg.from.x, seg.from.y, to.x, to.y
    );
}

/// How far (pixels) a piece may lie off the line of the pieces before it and still be
/// joined to them: rounding, a millionth of a pixel.
const ON_LINE: f64 = 1e-6;

/// The dash lengths' unit: a thousandth of a pixel.
const DASH_UNIT: f64 = 1000.0;

/// Writes pieces as SVG elements, joining each run of consecutive pieces that lie along
/// one line, in order, in one colour and class, into one `<line>` with a dash array (the
/// module notes). Memory: the run being joined.
#[derive(Debug, Default)]
pub struct SvgWriter {
    /// The run: its first piece, its unit direction, and the positions along it (from
    /// the first piece's start) of each later piece's start and end.
    first: Option<Segment>,
    dir: DVec2,
    ends: Vec<f64>,
}

impl SvgWriter {
    pub fn new() -> SvgWriter {
        SvgWriter::default()
    }

    /// Adds a piece, writing to `out` whatever run it does not continue.
    pub fn push(&mut self, out: &mut String, seg: &Segment) {
        if let Some(first) = &self.first {
            if first.colour == seg.colour && first.intersection == seg.intersection {
                let (a, b) = (seg.from - first.from, seg.to - first.from);
                let off = |v: DVec2| v.perp_dot(self.dir).abs();
                let (sa, sb) = (a.dot(self.dir), b.dot(self.dir));
                let last = self.ends.last().copied().unwrap_or(first.length());
                if off(a) <= ON_LINE && off(b) <= ON_LINE && sa >= last && sb > sa {
                    self.ends.extend([sa, sb]);
                    return;
                }
            }
            self.flush(out);
        }
        let len = seg.length();
        // A piece too short to give a direction is written alone.
        if len >= 0.01 && len.is_finite() {
            self.first = Some(*seg);
            self.dir = (seg.to - seg.from) / len;
        } else {
            svg_line(out, seg);
        }
    }

    /// Writes the run being joined.
    pub fn flush(&mut self, out: &mut String) {
        let Some(first) = self.first.take() else {
            return;
        };
        if self.ends.is_empty() {
            svg_line(out, &first);
            return;
        }
        // Each boundary rounded to the unit, the dashes and gaps their differences: no
        // rounding accumulates along the line.
        let mut dashes = String::from(r#" stroke-dasharray=""#);
        let mut before = 0i64;
        let bounds = std::iter::once(first.length()).chain(self.ends.iter().copied());
        for (i, s) in bounds.enumerate() {
            let at = (s * DASH_UNIT).round() as i64;
            if i > 0 {
                dashes.push(' ');
            }
            let d = at - before;
            let whole = d / DASH_UNIT as i64;
            let frac = d % DASH_UNIT as i64;
            // ".25" for 0.25, as SVG's number grammar allows: a byte a dash.
            if whole != 0 || frac == 0 {
                let _ = write!(dashes, "{whole}");
            }
            if frac != 0 {
                let digits = format!("{frac:03}");
                let _ = write!(dashes, ".{}", digits.trim_end_matches('0'));
            }
            before = at;
        }
        dashes.push('"');
        let end = self.ends.last().copied().unwrap_or(0.0);
        svg_element(out, &first, first.from + self.dir * end, &dashes);
        self.ends.clear();
    }
}

/// One frame's SVG: the pieces (joined as [`SvgWriter`] joins them) stroked in their
/// colours over a background.
pub fn svg(
    segments: &[Segment],
    width: u32,
    height: u32,
    background: Colour,
    stroke: f64,
) -> String {
    let mut s = svg_start(width, height, background, stroke);
    let mut writer = SvgWriter::new();
    for seg in segments {
        writer.push(&mut s, seg);
    }
    writer.flush(&mut s);
    s.push_str(SVG_END);
    s
}

/// The pieces of an SVG as [`SvgWriter`] writes it: every `<line>` element, a dashed one
/// split into its dashes. An error names the line of text that is not such an element.
pub fn read_svg(svg: &str) -> Result<Vec<Segment>, String> {
    let mut out = Vec::new();
    for line in svg.lines().filter(|l| l.starts_with("<line")) {
        let attr = |name: &str| -> Option<&str> {
            let key = format!(" {name}=\"");
            let at = line.find(&key)? + key.len();
            let rest = &line[at..];
            Some(&rest[..rest.find('"')?])
        };
        let num = |name: &str| -> Result<f64, String> {
            let v = attr(name).ok_or_else(|| format!("no {name} in the SVG's line {line}"))?;
            v.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("{name}=\"{v}\" is not a number in the SVG's line {line}"))
        };
        let (from, to) = (
            DVec2::new(num("x1")?, num("y1")?),
            DVec2::new(num("x2")?, num("y2")?),
        );
        let colour = match attr("stroke") {
            Some(s) => parse_rgb(s).ok_or_else(|| {
                format!("stroke=\"{s}\" is not rgb(R,G,B) in the SVG's line {line}")
            })?,
            None => [0, 0, 0],
        };
        let intersection = line.contains(r#" class="intersection""#);
        let piece = |a: DVec2, b: DVec2| Segment {
            from: a,
            to: b,
            colour,
            intersection,
        };
        match attr("stroke-dasharray") {
            None => out.push(piece(from, to)),
            Some(list) => {
                let len = (to - from).length();
                let dir = if len > 0.0 {
                    (to - from) / len
                } else {
                    DVec2::ZERO
                };
                let mut at = 0.0;
                for (i, w) in list.split([' ', ',']).filter(|w| !w.is_empty()).enumerate() {
                    let d: f64 = w
                        .parse()
                        .ok()
                        .filter(|d: &f64| d.is_finite() && *d >= 0.0)
                        .ok_or_else(|| format!("`{w}` in a dash array is not a length: {line}"))?;
                    if i % 2 == 0 {
                        // The last dash ends at the line's end (the rounding is the
                        // dash array's, a thousandth of a pixel).
                        out.push(piece(from + dir * at, from + dir * (at + d).min(len)));
                    }
                    at += d;
                }
            }
        }
    }
    Ok(out)
}

fn parse_rgb(s: &str) -> Option<Colour> {
    let inner = s.strip_prefix("rgb(")?.strip_suffix(')')?;
    let mut c = [0u8; 3];
    let mut parts = inner.split(',');
    for v in &mut c {
        *v = parts.next()?.trim().parse().ok()?;
    }
    parts.next().is_none().then_some(c)
}

/// A drawing's line error against a reference, in pixels ([`line_error`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LineError {
    /// Length of the reference that no drawn piece comes near: visible lines missed.
    pub missed_px: f64,
    /// Length drawn that no reference piece comes near: hidden lines drawn (or lines
    /// drawn off their place).
    pub extra_px: f64,
    /// The two drawings' total lengths.
    pub reference_px: f64,
    pub drawn_px: f64,
}

impl LineError {
    /// Missed plus extra.
    pub fn total_px(&self) -> f64 {
        self.missed_px + self.extra_px
    }
}

/// The segments near a point, by a grid of square cells.
struct Index<'a> {
    segments: &'a [Segment],
    cell: f64,
    lo: DVec2,
    nx: usize,
    ny: usize,
    cells: Vec<Vec<u32>>,
}

impl<'a> Index<'a> {
    fn new(segments: &'a [Segment], reach: f64) -> Index<'a> {
        let lo = segments
            .iter()
            .fold(DVec2::INFINITY, |m, s| m.min(s.from).min(s.to));
        let hi = segments
            .iter()
            .fold(DVec2::NEG_INFINITY, |m, s| m.max(s.from).max(s.to));
        let cell = 4.0f64.max(reach);
        let (nx, ny) = if segments.is_empty() {
            (0, 0)
        } else {
            let n = |d: f64| ((d / cell).floor() as usize + 1).min(4096);
            (n(hi.x - lo.x), n(hi.y - lo.y))
        };
        let mut index = Index {
            segments,
            cell,
            lo,
            nx,
            ny,
            cells: vec![Vec::new(); nx * ny],
        };
        for (k, s) in segments.iter().enumerate() {
            // Chunks no longer than a cell, each put in the cells its box (grown by the
            // reach) meets.
            let n = ((s.length() / cell).ceil() as usize).max(1);
            let mut last = usize::MAX;
            for i in 0..n {
                let a = s.from + (s.to - s.from) * (i as f64 / n as f64);
                let b = s.from + (s.to - s.from) * ((i + 1) as f64 / n as f64);
                let (x0, y0) = index.at(a.min(b) - DVec2::splat(reach));
                let (x1, y1) = index.at(a.max(b) + DVec2::splat(reach));
                for y in y0..=y1 {
                    for x in x0..=x1 {
                        let c = y * nx + x;
                        if c != last && index.cells[c].last() != Some(&(k as u32)) {
                            index.cells[c].push(k as u32);
                        }
                        last = c;
                    }
                }
            }
        }
        index
    }

    fn at(&self, q: DVec2) -> (usize, usize) {
        let f = |v: f64, o: f64, n: usize| {
            let i = ((v - o) / self.cell).floor();
            if i.is_nan() || i < 0.0 {
                0
            } else {
                (i as usize).min(n - 1)
            }
        };
        (f(q.x, self.lo.x, self.nx), f(q.y, self.lo.y, self.ny))
    }

    /// The segments that may come within the reach of segment `s`, each once.
    fn near(&self, s: &Segment, reach: f64, out: &mut Vec<u32>) {
        out.clear();
        if self.cells.is_empty() {
            return;
        }
        let n = ((s.length() / self.cell).ceil() as usize).max(1);
        for i in 0..n {
            let a = s.from + (s.to - s.from) * (i as f64 / n as f64);
            let b = s.from + (s.to - s.from) * ((i + 1) as f64 / n as f64);
            let (x0, y0) = self.at(a.min(b) - DVec2::splat(reach));
            let (x1, y1) = self.at(a.max(b) + DVec2::splat(reach));
            for y in y0..=y1 {
                for x in x0..=x1 {
                    out.extend_from_slice(&self.cells[y * self.nx + x]);
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        let _ = self.segments;
    }
}

/// The parameters t in [0, 1] of p(t) = p0 + t·(p1 − p0) within distance `r` of
/// segment a–b: the line's intersection with a capsule, one interval (or none).
pub fn within(p0: DVec2, p1: DVec2, a: DVec2, b: DVec2, r: f64) -> Option<(f64, f64)> {
    let d = p1 - p0;
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    let mut take = |t0: f64, t1: f64| {
        lo = lo.min(t0);
        hi = hi.max(t1);
    };
    // The two discs.
    for c in [a, b] {
        let f = p0 - c;
        let (qa, qb, qc) = (d.dot(d), 2.0 * f.dot(d), f.dot(f) - r * r);
        if qa == 0.0 {
            if qc <= 0.0 {
                take(0.0, 1.0);
            }
            continue;
        }
        let disc = qb * qb - 4.0 * qa * qc;
        if disc >= 0.0 {
            let s = disc.sqrt();
            take((-qb - s) / (2.0 * qa), (-qb + s) / (2.0 * qa));
        }
    }
    // The rectangle: 0 ≤ (p − a)·u ≤ L and |(p − a)×u| ≤ r.
    let ab = b - a;
    let len = ab.length();
    if len > 0.0 {
        let u = ab / len;
        let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
        let mut slab = |v0: f64, dv: f64, l: f64, h: f64| {
            if dv == 0.0 {
                if v0 < l || v0 > h {
                    t0 = f64::INFINITY;
                }
            } else {
                let (x, y) = ((l - v0) / dv, (h - v0) / dv);
                t0 = t0.max(x.min(y));
                t1 = t1.min(x.max(y));
            }
        };
        slab((p0 - a).dot(u), d.dot(u), 0.0, len);
        slab((p0 - a).perp_dot(u), d.perp_dot(u), -r, r);
        if t0 <= t1 {
            take(t0, t1);
        }
    }
    let (lo, hi) = (lo.max(0.0), hi.min(1.0));
    (lo <= hi).then_some((lo, hi))
}

/// The length of each segment of `of` that no segment of `by` comes within `r` of.
fn uncovered(of: &[Segment], by: &[Segment], r: f64) -> f64 {
    let index = Index::new(by, r);
    let mut near = Vec::new();
    let mut spans: Vec<(f64, f64)> = Vec::new();
    let mut total = 0.0;
    for s in of {
        let len = s.length();
        if len == 0.0 {
            continue;
        }
        index.near(s, r, &mut near);
        spans.clear();
        spans.extend(
            near.iter()
                .filter_map(|&k| within(s.from, s.to, by[k as usize].from, by[k as usize].to, r)),
        );
        spans.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (mut covered, mut reach) = (0.0, 0.0f64);
        for &(a, b) in &spans {
            if b > reach {
                covered += b - a.max(reach);
                reach = b;
            }
        }
        total += (1.0 - covered) * len;
    }
    total
}

/// `drawn`'s line error against `reference` (the module notes): the reference's length
/// farther than `tolerance` pixels from every drawn piece, and the drawn length farther
/// than `tolerance` from every reference piece.
pub fn line_error(drawn: &[Segment], reference: &[Segment], tolerance: f64) -> LineError {
    LineError {
        missed_px: uncovered(reference, drawn, tolerance),
        extra_px: uncovered(drawn, reference, tolerance),
        reference_px: reference.iter().map(Segment::length).sum(),
        drawn_px: drawn.iter().map(Segment::length).sum(),
    }
}

/// A tests' segment from (x0, y0) to (x1, y1), not a line of intersection, for this
/// crate's tests and [`raster`]'s.
#[cfg(test)]
pub(crate) fn seg(x0: f64, y0: f64, x1: f64, y1: f64) -> Segment {
    Segment {
        from: DVec2::new(x0, y0),
        to: DVec2::new(x1, y1),
        colour: [1, 2, 3],
        intersection: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pieces_along_one_edge_are_one_dashed_line() {
        let pieces = [
            seg(0.0, 0.0, 3.0, 4.0),
            seg(6.0, 8.0, 7.5, 10.0),
            seg(9.0, 12.0, 12.0, 16.0),
            // Another edge: a line of its own.
            seg(20.0, 0.0, 20.0, 5.0),
        ];
        let text = svg(&pieces, 30, 20, [255, 255, 255], 1.0);
        let lines: Vec<&str> = text.lines().filter(|l| l.starts_with("<line")).collect();
        assert_eq!(
            lines,
            [
                r#"<line x1="0" y1="0" x2="12" y2="16" stroke="rgb(1,2,3)" stroke-dasharray="5 5 2.5 2.5 5"/>"#,
                r#"<line x1="20" y1="0" x2="20" y2="5" stroke="rgb(1,2,3)"/>"#,
            ]
        );
        let back = read_svg(&text).unwrap();
        assert_eq!(back.len(), 4);
        for (a, b) in back.iter().zip(&pieces) {
            assert!(
                (a.from - b.from).length() < 1e-9 && (a.to - b.to).length() < 1e-9,
                "{a:?} {b:?}"
            );
        }
    }

    #[test]
    fn pieces_out_of_order_or_off_the_line_are_not_joined() {
        let pieces = [
            seg(5.0, 0.0, 6.0, 0.0),
            seg(0.0, 0.0, 1.0, 0.0),
            seg(2.0, 0.001, 3.0, 0.001),
        ];
        let text = svg(&pieces, 10, 10, [0, 0, 0], 1.0);
        assert_eq!(text.matches("<line").count(), 3);
        assert!(!text.contains("dasharray"));
    }

    #[test]
    fn the_line_error_is_what_is_missed_plus_what_is_extra() {
        let reference = [seg(0.0, 0.0, 10.0, 0.0), seg(0.0, 5.0, 0.0, 9.0)];
        // Half the first line, a hair off; a line 3 px long where nothing is.
        let drawn = [seg(0.0, 0.1, 5.0, 0.1), seg(20.0, 20.0, 23.0, 20.0)];
        let e = line_error(&drawn, &reference, 0.5);
        // Missed: the first line's far half past the drawn end's reach (5 + √(0.25 −
        // 0.01)), and all 4 px of the second.
        let reach = (0.25f64 - 0.01).sqrt();
        assert!((e.missed_px - (5.0 - reach + 4.0)).abs() < 1e-9, "{e:?}");
        assert!((e.extra_px - 3.0).abs() < 1e-9, "{e:?}");
        assert_eq!((e.reference_px, e.drawn_px), (14.0, 8.0));
        assert_eq!(line_error(&reference, &reference, 0.5).total_px(), 0.0);
    }

    #[test]
    fn within_a_capsule_is_one_interval() {
        let t = within(
            DVec2::new(-10.0, 0.0),
            DVec2::new(10.0, 0.0),
            DVec2::new(0.0, 0.0),
            DVec2::new(0.0, 1.0),
            1.0,
        )
        .unwrap();
        assert!(
            (t.0 - 0.45).abs() < 1e-12 && (t.1 - 0.55).abs() < 1e-12,
            "{t:?}"
        );
    }

    mod properties {
        use super::*;
        use proptest::prelude::*;

        proptest! {
            /// What the writer writes the reader reads back, to the dash unit.
            #[test]
            fn written_pieces_read_back(
                x0 in -50.0f64..50.0, y0 in -50.0f64..50.0, dx in -1.0f64..1.0, dy in -1.0f64..1.0,
                cuts in prop::collection::vec(0.01f64..5.0, 1..20),
            ) {
                prop_assume!(dx.hypot(dy) > 0.1);
                let d = DVec2::new(dx, dy).normalize();
                let p = DVec2::new(x0, y0);
                let mut at = 0.0;
                let mut pieces = Vec::new();
                for (i, c) in cuts.iter().enumerate() {
                    if i % 2 == 0 {
                        pieces.push(Segment { from: p + d * at, to: p + d * (at + c), colour: [0, 0, 0], intersection: false });
                    }
                    at += c;
                }
                let back = read_svg(&svg(&pieces, 100, 100, [9, 9, 9], 1.0)).unwrap();
                prop_assert_eq!(back.len(), pieces.len());
                let e = line_error(&back, &pieces, 0.002);
                prop_assert!(e.total_px() < 0.01, "{:?}", e);
            }
        }
    }
}
