//! The coverage rule (docs/DESIGN.md, "Coverage"), written once so that scanconv and the exact
//! reference decide every pixel the same way.
//!
//! Pixel (c, r) is the square [c, c+1) × [r, r+1) and is covered when its centre
//! (c+½, r+½) is inside the polygon by the even-odd rule. A centre exactly on an edge
//! belongs to the polygon for which the edge is a left or a top edge. Both follow from
//! half-open intervals: on row r the edges that count are those with
//! y_top ≤ r+½ < y_bottom (a horizontal edge never counts; a bottom vertex is not on its
//! edge), and between consecutive crossings x_0 ≤ x_1 the covered centres are those with
//! x_0 ≤ c+½ < x_1. A shared edge is a left edge of one polygon and a right edge of the
//! other, so exactly one of them gets a centre that lies on it.

use glam::DVec2;
use std::ops::Range;

/// Below this magnitude every f64 converts to i64 and back without overflow, and
/// `x − trunc(x)` is exact (the two are within a factor of two, or trunc(x) is 0).
const EXACT_TRUNC: f64 = 4_503_599_627_370_496.0; // 2^52

/// `x.ceil()`, the same value, without the library call that baseline x86-64 (no
/// SSE4.1 `roundsd`) makes for it: the scan converter takes two a span. The sign of a
/// zero result may differ (`ceil(−0.5)` is −0 here +0), which no integer cast sees.
#[inline]
pub fn ceil(x: f64) -> f64 {
    if x.abs() < EXACT_TRUNC {
        let t = x as i64 as f64;
        if t < x {
            t + 1.0
        } else {
            t
        }
    } else {
        x.ceil()
    }
}

/// `x.round()` (halves away from zero), the same value, without the library call; see
/// [`ceil`]. Not `(x + 0.5).floor()`, which rounds 0.49999999999999994 up.
#[inline]
pub fn round(x: f64) -> f64 {
    if x.abs() < EXACT_TRUNC {
        let t = x as i64 as f64;
        let d = x - t;
        if d >= 0.5 {
            t + 1.0
        } else if d <= -0.5 {
            t - 1.0
        } else {
            t
        }
    } else {
        x.round()
    }
}

/// The pixel indices `i` whose centres `i + ½` satisfy `lo ≤ i + ½ < hi`.
#[inline]
pub fn centres_in(lo: f64, hi: f64) -> Range<i64> {
    let first = ceil(lo - 0.5);
    let end = ceil(hi - 0.5);
    // Saturating casts: a huge coordinate (bad input, a polygon seen edge-on) gives an
    // empty or screen-clamped range rather than wrapping.
    (first as i64)..(end as i64).max(first as i64)
}

/// The same, clamped to `0..limit` (the screen's columns or rows).
#[inline]
pub fn centres_in_clamped(lo: f64, hi: f64, limit: u32) -> Range<u32> {
    let r = centres_in(lo, hi);
    let start = r.start.clamp(0, limit as i64) as u32;
    let end = r.end.clamp(0, limit as i64) as u32;
    start..end.max(start)
}

/// A non-horizontal polygon edge in screen space, oriented top to bottom whichever way
/// the polygon walks it, so that two polygons sharing the edge compute the same crossing
/// of every scanline to the last bit (Appendix 3's ET entry: y_max, x at y_min, 1/m).
///
/// The rows an edge is active on come from its own ends (`top`, `bottom`); its crossings
/// come from its *line*, which is the edge itself unless the edge is a piece of a longer
/// one that a splitter cut ([`Edge::with_support`]). A piece's ends are on the whole edge
/// only to within rounding, so crossings computed from them would differ in the last bits
/// from the unsplit polygon's and the top-left rule could decide a centre lying exactly on
/// the edge the other way; computed from the whole edge they are the same to the bit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Edge {
    /// The end with the smaller Y (nearer the top of the image).
    pub top: DVec2,
    /// The end with the larger Y.
    pub bottom: DVec2,
    /// The top end of the line the crossings are measured on (`top` for an unsplit edge).
    pub origin: DVec2,
    /// dX/dY of that line, the inverse slope 1/m.
    pub inverse_slope: f64,
}

impl Edge {
    /// The edge between two points, or `None` for a horizontal one (it covers no centre
    /// of its own; the edges beside it decide the pixels along it).
    #[inline]
    pub fn new(a: DVec2, b: DVec2) -> Option<Edge> {
        if a.y == b.y {
            return None;
        }
        let (top, bottom) = if a.y < b.y { (a, b) } else { (b, a) };
        Some(Edge {
            top,
            bottom,
            origin: top,
            inverse_slope: (bottom.x - top.x) / (bottom.y - top.y),
        })
    }

    /// The piece `a`–`b` of the original edge `support_a`–`support_b`: active on the rows
    /// of `a`–`b`, crossing them where the original edge does (computed exactly as
    /// `Edge::new(support_a, support_b)` computes it, whichever way either is walked).
    /// `None` if the piece or the original edge is horizontal: a horizontal original covers
    /// no centre of its own, so neither may its pieces, which are horizontal but for
    /// rounding.
    #[inline]
    pub fn with_support(a: DVec2, b: DVec2, support_a: DVec2, support_b: DVec2) -> Option<Edge> {
        let piece = Edge::new(a, b)?;
        let line = Edge::new(support_a, support_b)?;
        Some(Edge {
            origin: line.origin,
            inverse_slope: line.inverse_slope,
            ..piece
        })
    }

    /// The rows whose centres the edge spans: `top.y ≤ r + ½ < bottom.y`.
    #[inline]
    pub fn rows(&self) -> Range<i64> {
        centres_in(self.top.y, self.bottom.y)
    }

    /// Where the edge crosses the horizontal line Y = y. Evaluated from the top end rather
    /// than stepped, so the crossing depends only on the edge and the row.
    #[inline]
    pub fn x_at(&self, y: f64) -> f64 {
        self.origin.x + (y - self.origin.y) * self.inverse_slope
    }
}

/// Whether every point lies on one straight line, to within the rounding of their
/// coordinates. Such a polygon has no interior and covers no pixel centre; counting
/// crossings would still claim a centre exactly on the line whenever two of its edges
/// (the same line, different endpoints) round their crossings apart, so both renderers
/// ask this first.
pub fn on_one_line(points: &[DVec2]) -> bool {
    let Some(&p0) = points.first() else {
        return true;
    };
    let far = points
        .iter()
        .copied()
        .max_by(|a, b| {
            (*a - p0)
                .length_squared()
                .total_cmp(&(*b - p0).length_squared())
        })
        .unwrap_or(p0);
    let d = far - p0;
    let magnitude = points
        .iter()
        .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
    // A point off the line by less than a few ulps of the coordinates is on it.
    let tolerance = 16.0 * f64::EPSILON * magnitude * d.abs().max_element();
    points
        .iter()
        .all(|&p| d.perp_dot(p - p0).abs() <= tolerance)
}

#[cfg(test)]
mod tests {
    #[test]
    fn ceil_and_round_agree_with_the_library() {
        let cases = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.5,
            -1.5,
            2.5,
            -2.5,
            0.49999999999999994,
            -0.49999999999999994,
            1e-300,
            -1e-300,
            3.0,
            -3.0,
            4503599627370495.5,
            -4503599627370495.5,
            4503599627370496.0,
            9.007199254740993e15,
            1e300,
            -1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            123.456,
            -123.456,
            0.999999999999,
        ];
        for x in cases {
            for (ours, theirs) in [(super::ceil(x), x.ceil()), (super::round(x), x.round())] {
                assert!(
                    ours == theirs || (ours.is_nan() && theirs.is_nan()),
                    "{x}: {ours} against {theirs}"
                );
            }
        }
        let mut state = 0x2545f4914f6cdd1du64;
        for _ in 0..100_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = f64::from_bits(state);
            let y = (state >> 11) as f64 / (1u64 << 40) as f64 - 4096.0;
            for v in [x, y] {
                assert!(super::ceil(v) == v.ceil() || v.is_nan(), "{v}");
                assert!(super::round(v) == v.round() || v.is_nan(), "{v}");
            }
        }
    }

    use super::*;

    #[test]
    fn half_open_centres() {
        assert_eq!(centres_in(0.0, 3.0), 0..3);
        assert_eq!(centres_in(0.5, 2.5), 0..2); // centre 0.5 in, 2.5 out
        assert_eq!(centres_in(0.6, 2.6), 1..3);
        assert_eq!(centres_in(1.2, 1.4), 1..1);
        assert_eq!(centres_in(-3.0, -1.0), -3..-1);
        assert_eq!(centres_in_clamped(-3.0, 2.0, 10), 0..2);
        assert_eq!(centres_in_clamped(8.0, 1e300, 10), 8..10);
        assert_eq!(centres_in_clamped(f64::MAX, f64::INFINITY, 10), 10..10);
    }

    #[test]
    fn lines_and_not_lines() {
        let p = |x, y| DVec2::new(x, y);
        assert!(on_one_line(&[]));
        assert!(on_one_line(&[p(3.0, 3.0), p(3.0, 3.0), p(3.0, 3.0)]));
        assert!(on_one_line(&[p(16.5, 47.5), p(32.0, 32.0), p(47.5, 16.5)]));
        assert!(on_one_line(&[
            p(0.0, 0.0),
            p(0.1, 0.3),
            p(0.3, 0.9000000000000001)
        ]));
        assert!(!on_one_line(&[p(0.0, 0.0), p(10.0, 0.0), p(10.0, 1e-9)]));
        // A bowtie has no net area but is not a line.
        assert!(!on_one_line(&[
            p(0.0, 0.0),
            p(4.0, 4.0),
            p(4.0, 0.0),
            p(0.0, 4.0)
        ]));
    }

    #[test]
    fn edges_are_oriented_top_down() {
        let a = DVec2::new(1.0, 5.0);
        let b = DVec2::new(3.0, 1.0);
        let e = Edge::new(a, b).unwrap();
        assert_eq!(e, Edge::new(b, a).unwrap());
        assert_eq!(e.top, b);
        assert_eq!(e.x_at(3.0), 2.0);
        assert_eq!(e.rows(), 1..5); // centres 1.5 .. 4.5
        assert!(Edge::new(a, DVec2::new(9.0, 5.0)).is_none());
    }

    #[test]
    fn a_supported_piece_crosses_where_the_whole_edge_does() {
        // The whole edge (0, 0)–(10, 3) and a piece of it cut at a point I that is on the
        // line only to within rounding.
        let (a, b) = (DVec2::new(0.0, 0.0), DVec2::new(10.0, 3.0));
        let i = a + (b - a) * 0.7;
        let whole = Edge::new(a, b).unwrap();
        let upper = Edge::with_support(a, i, b, a).unwrap();
        let lower = Edge::with_support(b, i, a, b).unwrap();
        assert_eq!((upper.top, upper.bottom), (a, i));
        assert_eq!((lower.top, lower.bottom), (i, b));
        assert_eq!(upper.rows(), 0..2); // centres 0.5, 1.5 < I.y = 2.1
        assert_eq!(lower.rows(), 2..3);
        for y in [0.5, 1.5] {
            assert_eq!(upper.x_at(y).to_bits(), whole.x_at(y).to_bits());
        }
        assert_eq!(lower.x_at(2.5).to_bits(), whole.x_at(2.5).to_bits());
        // Horizontal pieces or originals cover nothing.
        assert!(Edge::with_support(a, DVec2::new(4.0, 0.0), a, b).is_none());
        assert!(Edge::with_support(a, b, a, DVec2::new(4.0, 0.0)).is_none());
    }
}
