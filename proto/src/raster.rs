//! DESIGN.md's coverage rule, written once so that the scan converter and the exact
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

/// The pixel indices `i` whose centres `i + ½` satisfy `lo ≤ i + ½ < hi`.
#[inline]
pub fn centres_in(lo: f64, hi: f64) -> Range<i64> {
    let first = (lo - 0.5).ceil();
    let end = (hi - 0.5).ceil();
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
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Edge {
    /// The end with the smaller Y (nearer the top of the image).
    pub top: DVec2,
    /// The end with the larger Y.
    pub bottom: DVec2,
    /// dX/dY, the inverse slope 1/m.
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
            inverse_slope: (bottom.x - top.x) / (bottom.y - top.y),
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
        self.top.x + (y - self.top.y) * self.inverse_slope
    }
}

#[cfg(test)]
mod tests {
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
}
