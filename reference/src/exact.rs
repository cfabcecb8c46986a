//! The reference's coverage test: docs/DESIGN.md's "Coverage" evaluated at one sample
//! point at a time, in integers, sharing no code with the pipeline's scan conversion
//! (`proto::raster`).
//!
//! A polygon's device vertices are snapped to the nearest multiple of 1/256 pixel, ties to
//! even. In units of 1/256 pixel every snapped vertex and every pixel centre
//! (256c + 128, 256r + 128) is an integer, and the rule is decided exactly: a sample point
//! (x, y) is inside when an odd number of edges (t, b), oriented so that t.y < b.y,
//! satisfy
//!
//! ```text
//!     t.y ≤ y < b.y   and   (x − t.x)·(b.y − t.y) ≥ (y − t.y)·(b.x − t.x),
//! ```
//!
//! that is, the edge spans the sample's row by the half-open rule and crosses it at or
//! left of the sample (the crossing x_t + (y − y_t)·dx/dy ≤ x, multiplied out by dy > 0).
//! A sample on an edge is counted when that crossing is at it, so it is inside exactly
//! when the edge is one the polygon lies right of: a left edge. A horizontal edge spans no
//! row. Products of two coordinate differences are formed in i128. A polygon is first cut
//! to the screen, as the pipeline's clippers cut it ([`Outline::new`]).
//!
//! For the K×K reference the fine screen is K times the pixel screen: a fine device
//! coordinate is snapped as X/K on the pixel grid (the pipeline's samples lie on that
//! grid), and the fine pixel centres are the sub-pixel samples (c + (i+½)/K, r + (j+½)/K).

use proto::DVec2;

/// Sub-pixel units to a pixel.
const SUBPIXEL: i128 = 256;

/// A polygon's edges, snapped, ready for the per-sample test.
#[derive(Clone, Debug, Default)]
pub(crate) struct Outline {
    /// Each non-horizontal edge as (top x, top y, bottom x, bottom y), top.y < bottom.y.
    edges: Vec<[i128; 4]>,
    /// The snapped vertices' bounding box: (min x, min y, max x, max y).
    bounds: [i128; 4],
}

/// The nearest integer to `v`, ties to even (`v` is finite and within ±2^50: a point of
/// the screen, or at most 16 times finer).
fn round_ties_even(v: f64) -> i128 {
    let r = v.round();
    // `round` takes halves away from zero; a half whose rounding is odd goes back one.
    if (v - v.trunc()).abs() == 0.5 && r % 2.0 != 0.0 {
        (r - v.signum()) as i128
    } else {
        r as i128
    }
}

/// Sutherland–Hodgman against one side of the screen: keeps the points with
/// `sign·coordinate ≤ limit`. A crossing is interpolated from the edge's inside end, so
/// two polygons that share the edge get the same new vertex, bit for bit.
fn cut(points: &[DVec2], axis: usize, sign: f64, limit: f64) -> Vec<DVec2> {
    let inside = |p: DVec2| sign * p[axis] <= limit;
    let mut out = Vec::with_capacity(points.len() + 2);
    for (i, &a) in points.iter().enumerate() {
        let b = points[(i + 1) % points.len()];
        if inside(a) {
            out.push(a);
        }
        if inside(a) != inside(b) {
            let (from, to) = if inside(a) { (a, b) } else { (b, a) };
            let t = (limit - sign * from[axis]) / (sign * (to[axis] - from[axis]));
            let mut p = from + (to - from) * t;
            p[axis] = sign * limit;
            out.push(p);
        }
    }
    out
}

impl Outline {
    /// The outline of the device polygon `points` on a `width`×`height` screen that is `k`
    /// times the pixel screen (k = 1: the pixel screen itself); `None` when it covers no
    /// sample: fewer than three vertices, or all of them on one line once snapped.
    pub(crate) fn new(points: &[DVec2], width: u32, height: u32, k: u32) -> Option<Outline> {
        let mut pts = points.to_vec();
        // Cut to the screen before snapping, as the pipeline's clippers cut a polygon at
        // the sides of the viewing pyramid (whose images are the screen's edges): the
        // polygon whose vertices are snapped is its part on the screen. Cut in device
        // space rather than eye space (the map between them keeps lines), the new
        // vertices are the clippers' to a few ulps, and snapped they are the same but
        // for a coordinate within those ulps of a 1/512-pixel tie. Every coordinate is
        // then a small integer, whatever the input.
        let (w, h) = (width as f64, height as f64);
        pts = cut(&pts, 0, -1.0, 0.0);
        pts = cut(&pts, 0, 1.0, w);
        pts = cut(&pts, 1, -1.0, 0.0);
        pts = cut(&pts, 1, 1.0, h);
        if pts.len() < 3 {
            return None;
        }
        let k = k as f64;
        let snapped: Vec<[i128; 2]> = pts
            .iter()
            .map(|p| {
                // Snapped on the pixel grid, then in 1/256 of a fine pixel.
                let on_grid = |v: f64| round_ties_even(v / k * SUBPIXEL as f64) * k as i128;
                [on_grid(p.x), on_grid(p.y)]
            })
            .collect();
        let p0 = snapped[0];
        let p1 = *snapped.iter().find(|&&p| p != p0)?;
        let area =
            |p: [i128; 2]| (p1[0] - p0[0]) * (p[1] - p0[1]) - (p1[1] - p0[1]) * (p[0] - p0[0]);
        if snapped.iter().all(|&p| area(p) == 0) {
            return None;
        }
        let n = snapped.len();
        let edges = (0..n)
            .filter_map(|i| {
                let (a, b) = (snapped[i], snapped[(i + 1) % n]);
                match a[1].cmp(&b[1]) {
                    std::cmp::Ordering::Less => Some([a[0], a[1], b[0], b[1]]),
                    std::cmp::Ordering::Greater => Some([b[0], b[1], a[0], a[1]]),
                    std::cmp::Ordering::Equal => None,
                }
            })
            .collect();
        let mut bounds = [i128::MAX, i128::MAX, i128::MIN, i128::MIN];
        for p in &snapped {
            bounds[0] = bounds[0].min(p[0]);
            bounds[1] = bounds[1].min(p[1]);
            bounds[2] = bounds[2].max(p[0]);
            bounds[3] = bounds[3].max(p[1]);
        }
        Some(Outline { edges, bounds })
    }

    /// The first and last-plus-one pixel indices whose centres lie in the half-open range
    /// [lo, hi) of units, clamped to `0..limit`.
    fn centres(lo: i128, hi: i128, limit: u32) -> std::ops::Range<u32> {
        let first = |v: i128| {
            (v - SUBPIXEL / 2).div_euclid(SUBPIXEL)
                + ((v - SUBPIXEL / 2).rem_euclid(SUBPIXEL) != 0) as i128
        };
        let start = first(lo).clamp(0, limit as i128) as u32;
        let end = first(hi).clamp(0, limit as i128) as u32;
        start..end.max(start)
    }

    /// The rows whose centres the outline may cover.
    pub(crate) fn rows(&self, height: u32) -> std::ops::Range<u32> {
        Outline::centres(self.bounds[1], self.bounds[3], height)
    }

    /// The columns whose centres the outline may cover (a centre at or right of the
    /// rightmost vertex has every crossing at or left of it: an even count).
    pub(crate) fn columns(&self, width: u32) -> std::ops::Range<u32> {
        Outline::centres(self.bounds[0], self.bounds[2], width)
    }

    /// Whether the centre of pixel (c, r) is inside, by the rule of the module's notes.
    pub(crate) fn covers(&self, c: u32, r: u32) -> bool {
        let x = SUBPIXEL * c as i128 + SUBPIXEL / 2;
        let y = SUBPIXEL * r as i128 + SUBPIXEL / 2;
        let passed = self
            .edges
            .iter()
            .filter(|&&[tx, ty, bx, by]| {
                ty <= y && y < by && (x - tx) * (by - ty) >= (y - ty) * (bx - tx)
            })
            .count();
        passed % 2 == 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ties_go_to_even() {
        let cases = [
            (0.5, 0),
            (1.5, 2),
            (2.5, 2),
            (-0.5, 0),
            (-1.5, -2),
            (-2.5, -2),
            (2.4, 2),
            (2.6, 3),
            (-2.6, -3),
            (5119.999999999999, 5120),
        ];
        for (v, want) in cases {
            assert_eq!(round_ties_even(v), want, "{v}");
        }
    }

    fn outline(points: &[(f64, f64)]) -> Outline {
        let pts: Vec<DVec2> = points.iter().map(|&(x, y)| DVec2::new(x, y)).collect();
        Outline::new(&pts, 100, 100, 1).unwrap()
    }

    #[test]
    fn on_edge_centres_go_to_left_and_top_edges() {
        // The square (1, 1)–(3, 3) covers exactly the pixels (1..3, 1..3); a triangle
        // whose hypotenuse runs through the centres (1.5, 2.5), (2.5, 1.5) holds them on
        // its right edge: not covered.
        let sq = outline(&[(1.0, 1.0), (3.0, 1.0), (3.0, 3.0), (1.0, 3.0)]);
        for r in 0..5 {
            for c in 0..5 {
                assert_eq!(sq.covers(c, r), (1..3).contains(&c) && (1..3).contains(&r));
            }
        }
        let right = outline(&[(0.0, 0.0), (4.0, 0.0), (0.0, 4.0)]);
        assert!(right.covers(0, 0) && right.covers(2, 0) && right.covers(1, 1));
        assert!(!right.covers(3, 0) && !right.covers(2, 1) && !right.covers(1, 2));
        // The other half of the square: the hypotenuse is its left edge.
        let left = outline(&[(4.0, 0.0), (4.0, 4.0), (0.0, 4.0)]);
        assert!(left.covers(3, 0) && left.covers(2, 1) && left.covers(1, 2));
        assert!(!left.covers(2, 0));
    }

    #[test]
    fn vertices_a_hair_off_the_grid_are_drawn_where_they_were_meant() {
        // persp's (19.999999999999996, 100) for the scene's (20, 100): after snapping,
        // the edge to (60, 60) holds every centre with c + r = 119 (on X + Y = 120), and
        // it is a left edge of the triangle below it, which covers them all.
        let p = outline(&[(19.999999999999996, 100.0), (60.0, 60.0), (60.0, 100.0)]);
        for c in 20..60 {
            assert!(p.covers(c, 119 - c), "({c}, {})", 119 - c);
            assert!(!p.covers(c, 118 - c), "({c}, {})", 118 - c);
        }
        // For the triangle above it the edge is a right edge: none of them.
        let q = outline(&[(19.999999999999996, 100.0), (60.0, 60.0), (20.0, 60.0)]);
        for c in 20..60 {
            assert!(!q.covers(c, 119 - c));
        }
        for c in 20..59 {
            assert!(q.covers(c, 118 - c));
        }
    }

    #[test]
    fn polygons_are_cut_to_the_screen() {
        let o = outline(&[(-1e300, -1e300), (1e300, -1e300), (0.0, 1e300)]);
        assert!(o.covers(0, 0) && o.covers(99, 99));
        assert_eq!(o.bounds, [0, 0, 100 * 256, 100 * 256]);
        // An edge shared by two polygons, walked both ways, is cut at the same point.
        let a = [DVec2::new(-7.3, 1.1), DVec2::new(50.2, 30.7)];
        let one = cut(&[a[0], a[1], DVec2::new(40.0, 90.0)], 0, -1.0, 0.0);
        let two = cut(&[a[1], a[0], DVec2::new(-3.0, -9.0)], 0, -1.0, 0.0);
        assert!(one.iter().any(|p| p.x == 0.0 && two.contains(p)));
    }
}
