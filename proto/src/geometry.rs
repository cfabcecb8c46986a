//! Geometry shared by the clipper, the splitter, the scan converter and the reference:
//! classifying a point against a plane, intersecting an edge with it (thesis Appendix 2),
//! and Newell's plane of a polygon (Appendix 3.4).
//!
//! Planes are half-spaces in homogeneous eye coordinates `(x_e, y_e, z_e, w)`:
//! the inside is `n·v + k ≥ 0`. The six planes of the clipping pyramid
//! (−a·w ≤ x_e ≤ a·w, −w ≤ y_e ≤ w, K1 ≤ z_e ≤ K2) and the splitter's planes through the
//! eye (x_e = K·a·w, y_e = K·w) are all of this form, and so is any plane a user gives
//! by its coefficients: the thesis's clipping volume "may be any convenient shape
//! defined by any number of planes".

use crate::exact;
use crate::header::View;
// Newell's plane is `newell`'s; named here too, beside the other planes.
pub use crate::newell::{newell_normal, newell_plane, newell_plane_of};
use crate::polygon::Vertex;
use glam::{DVec3, DVec4};
use std::fmt;
use std::str::FromStr;

/// Which side of a plane a point is on.
///
/// A point is [`Side::On`] when its distance is within the rounding error of evaluating
/// the distance at all, so a vertex that the intersection put on the plane is classified
/// on it when read again: clipping twice then equals clipping once.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    Inside,
    On,
    Outside,
}

/// A half-space `n·v + k ≥ 0` of homogeneous eye space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    pub n: DVec4,
    pub k: f64,
}

/// Rounding allowance: distances within this many machine epsilons of the sum of the
/// magnitudes of their terms count as zero. A dot product of four terms plus a constant
/// is correct to about 2.5 epsilons of that sum, so exact-arithmetic signs are only
/// uncertain inside this band.
const ON_PLANE_EPSILONS: f64 = 4.0;

/// The half-width of the band of distances that count as on the plane, for a point whose
/// distance's terms have magnitudes summing to `scale`.
#[inline]
fn on_plane_band(scale: f64) -> f64 {
    ON_PLANE_EPSILONS * (f64::EPSILON * scale + 4.0 * UNDERFLOW_UNIT)
}

/// The smallest positive f64 (2^-1074, a subnormal). Below f64::MIN_POSITIVE rounding
/// is no longer relative: each operation may be off by half of this, so the band also
/// gets an absolute part of a few of these (a polygon of subnormal coordinates would
/// otherwise have its own intersections classified outside: found by fuzz target `clip`).
const UNDERFLOW_UNIT: f64 = 5e-324;

/// 2^-512 and 2^512: scaling by a power of two is exact, and brings coordinates near
/// f64::MAX into a range where a plane's distance cannot overflow.
const DOWN: f64 = 7.458340731200207e-155;
const UP: f64 = 1.3407807929942597e154;

/// An interpolated coordinate whose rounding error may exceed this fraction of its true
/// value has lost about a third of its bits to cancellation, and is recomputed
/// ([`Plane::intersect`]'s eye-space repair). Only an edge whose ends are some 10^5 times
/// farther from the eye than the crossing comes near this, so ordinary cuts are untouched.
/// (At 1e-8, a yon cut of an edge from z_e = 5.8e8 kept w 1.4e-9 off: found by the
/// clipplane property `far_edges_through_the_eye_plane_keep_w_proportional_to_z`.)
const LOST: f64 = 1e-10;

/// The edge's w/z_e, if both ends that define one agree on it to rounding (an eye-space
/// stream, w = z_e·s/d of docs/DESIGN.md, "Coordinates and camera"); None for a pair that does not.
fn w_over_z(p: DVec4, q: DVec4) -> Option<f64> {
    // Some(None) for the eye itself (0, 0): it keeps every ratio.
    let ratio = |v: DVec4| -> Option<Option<f64>> {
        if v.z == 0.0 && v.w == 0.0 {
            return Some(None);
        }
        let r = v.w / v.z;
        (r.is_finite() && r != 0.0).then_some(Some(r))
    };
    match (ratio(p)?, ratio(q)?) {
        (Some(a), Some(b)) => ((a - b).abs() <= 1e-9 * a.abs()).then_some(a),
        (Some(a), None) | (None, Some(a)) => Some(a),
        (None, None) => None,
    }
}

impl Plane {
    pub const fn new(n: DVec4, k: f64) -> Self {
        Plane { n, k }
    }

    /// The signed distance measure of Appendix 2 (`w − y` for the top plane, and so on):
    /// positive inside, zero on the plane, negative outside. Not normalised; only its sign
    /// and the ratio of two of them (α) matter.
    ///
    /// The terms are summed in one fixed order, which [`Plane::intersect`] relies on to
    /// put intersections exactly on single-coordinate planes.
    #[inline]
    pub fn distance(&self, v: DVec4) -> f64 {
        (((self.n.x * v.x + self.n.y * v.y) + self.n.z * v.z) + self.n.w * v.w) + self.k
    }

    /// The point's side, and its distance.
    #[inline]
    pub fn classify(&self, v: DVec4) -> (Side, f64) {
        let d = self.distance(v);
        let scale = (self.n * v).abs().element_sum() + self.k.abs();
        if !scale.is_finite() {
            // Coordinates near f64::MAX overflow the sum: decide the side on the point
            // and plane scaled down by 2^-512 (exact), where nothing overflows.
            let (side, _) = self.scaled_down().classify(v * DOWN);
            return (side, d);
        }
        let side = if d.abs() <= on_plane_band(scale) {
            Side::On
        } else if d > 0.0 {
            Side::Inside
        } else {
            Side::Outside
        };
        (side, d)
    }

    /// [`Plane::classify`] of many points at once, laid out structure-of-arrays (lane i is
    /// the point `(x[i], y[i], z[i], w[i])`): writes each lane's distance to `dist` and its
    /// side to `side`, both exactly as `classify` gives them, bit for bit.
    ///
    /// This is the inside test of the DAP clipper (Theoharis and Page 1989, §4.2,
    /// step 1: `INSIDEV1 = VERTEXY(,,I).LE.VERTEXW(,,I)` for all N² polygons at once).
    /// The loop has no branch, so the compiler vectorises it; the rare lane whose terms
    /// overflow (coordinates near f64::MAX, where `classify` rescales) is then decided
    /// again by `classify` itself. Every slice must be as long as `x`.
    pub fn classify_lanes(&self, [x, y, z, w]: [&[f64]; 4], dist: &mut [f64], side: &mut [Side]) {
        let n = x.len();
        let (y, z, w, dist, side) = (&y[..n], &z[..n], &w[..n], &mut dist[..n], &mut side[..n]);
        let (a, b, c, e, k) = (self.n.x, self.n.y, self.n.z, self.n.w, self.k);
        let mut overflowed = false;
        for i in 0..n {
            // `distance` and `classify`'s sums, term for term in the same order.
            let d = (((a * x[i] + b * y[i]) + c * z[i]) + e * w[i]) + k;
            let scale = ((((a * x[i]).abs() + (b * y[i]).abs()) + (c * z[i]).abs())
                + (e * w[i]).abs())
                + k.abs();
            overflowed |= !scale.is_finite();
            let band = on_plane_band(scale);
            dist[i] = d;
            side[i] = if d.abs() <= band {
                Side::On
            } else if d > 0.0 {
                Side::Inside
            } else {
                Side::Outside
            };
        }
        if overflowed {
            for i in 0..n {
                side[i] = self.classify(DVec4::new(x[i], y[i], z[i], w[i])).0;
            }
        }
    }

    /// Whether the point is inside or on the plane.
    #[inline]
    pub fn contains(&self, v: DVec4) -> bool {
        self.classify(v).0 != Side::Outside
    }

    /// Where the edge from `a` (distance `da`) to `b` (distance `db`) crosses the plane,
    /// given that they lie strictly on opposite sides (Appendix 2.2).
    ///
    /// α = |P1 I| / |P1 P2| is the ratio of distances, I = P1 + α (P2 − P1). The result is
    /// the same to the last bit whichever way the edge is walked (we always interpolate
    /// from the inside end), so two polygons that share an edge get the same new vertex
    /// and the clipped mesh keeps no crack. The coordinate with the largest coefficient is
    /// then solved for from the others, which puts the point exactly on the six pyramid
    /// planes and on the splitter's planes, and within rounding of any other.
    #[inline]
    pub fn intersect(&self, a: DVec4, da: f64, b: DVec4, db: f64) -> DVec4 {
        self.crossing(a, da, b, db).point
    }

    /// [`Plane::intersect`], with the parameter of the crossing along the edge, so that
    /// what else the vertices carry (their colours, for Gouraud shading) is interpolated at
    /// the same point: [`Crossing::mix`].
    #[inline]
    pub fn crossing(&self, a: DVec4, da: f64, b: DVec4, db: f64) -> Crossing {
        let from_b = da < db;
        let (p, dp, q, dq) = if !from_b {
            (a, da, b, db)
        } else {
            (b, db, a, da)
        };
        // dp > 0 > dq, so the divisor is positive and at least dp: α lies in [0, 1].
        let mut alpha = dp / (dp - dq);
        let mut v = p + (q - p) * alpha;
        let mut along = q - p;
        if !(alpha.is_finite() && v.is_finite()) {
            // Coordinates near f64::MAX overflowed a distance, the divisor or q − p
            // (inf·0 is NaN: found by fuzz target `clip`). The same point, computed with
            // everything scaled down by 2^-512, lies between p and q, so scaled back up
            // it is finite.
            let down = self.scaled_down();
            let (ps, qs) = (p * DOWN, q * DOWN);
            let (dps, dqs) = (down.distance(ps), down.distance(qs));
            alpha = (dps / (dps - dqs)).clamp(0.0, 1.0);
            along = qs - ps;
            v = (ps + (qs - ps) * alpha) * UP;
            if !v.is_finite() {
                // Only a point within rounding of ±f64::MAX can get here.
                v = v.clamp(DVec4::splat(f64::MIN), DVec4::splat(f64::MAX));
            }
        }
        if self.k != 0.0 && exact::interpolation_lost_digits(p, q, v) {
            // Ends so far out that interpolating kept only rounding in some coordinate
            // (an edge from 1e100 behind the eye to 1e100 in front, cut by hither near
            // it): computed exactly instead, each coordinate to its own last places.
            // Not for a plane through the eye (k = 0, the side planes and the
            // splitter's): there an edge whose ends lie on another such plane only to
            // their rounding (1e291 at 1e307) meets it near the eye, where that rounding
            // is the crossing's whole size, and the exact crossing of those rounded ends
            // lies as far outside the other plane as it is from the eye (differential
            // seed 61186); interpolation's point near the eye is the safer one.
            if let Some(exact) = exact::crossing(p, q, self.n, self.k) {
                v = exact;
            }
        }
        if let Some(solved) = self.snap(&mut v, along) {
            self.keep_w_proportional_to_z(&mut v, p, q, solved);
        }
        Crossing {
            point: v,
            alpha,
            from_b,
        }
    }

    /// Eye space has w = z_e·s/d at every point (docs/DESIGN.md, "Coordinates and camera"),
    /// so w/z_e is one ratio for the whole stream, kept by exact interpolation. In floating point,
    /// where an edge runs from far behind the eye to far in front and crosses a plane near
    /// the eye, z_e and w both cancel, and the one the snap did not solve for keeps only
    /// rounding noise: a 1e30 edge cut by the left plane at w = −6 came out with z_e = 0
    /// where it is −9.6, and then hither, which reads z_e, kept what lies behind the eye
    /// (examples/degenerate/huge-through-eye.txt). When that coordinate's rounding error
    /// (a few ε of the endpoints' magnitudes) is more than [`LOST`] of its true size, it is
    /// recomputed from the solved one and the edge's ratio. Elsewhere it is left to the
    /// last bit, so ordinary intersections are as before.
    fn keep_w_proportional_to_z(&self, v: &mut DVec4, p: DVec4, q: DVec4, solved: usize) {
        let derived = match solved {
            2 => 3,
            3 => 2,
            _ => return,
        };
        let (pa, qa) = (p.to_array(), q.to_array());
        let mut c = v.to_array();
        let error = 4.0 * f64::EPSILON * pa[derived].abs().max(qa[derived].abs());
        if error <= 0.5 * LOST * c[derived].abs() {
            // The common case, decided without a division: the interpolated value is
            // larger than its possible error by far, so it kept its digits.
            return;
        }
        let Some(ratio) = w_over_z(p, q) else {
            return;
        };
        // Coordinate `derived` follows from coordinate `solved`: w = z_e·ratio, or
        // z_e = w/ratio.
        let derive = |x: f64| if derived == 3 { x * ratio } else { x / ratio };
        let wanted = derive(c[solved]);
        if !(error > LOST * wanted.abs() && wanted.is_finite()) {
            return;
        }
        let n = self.n.to_array();
        if n[derived] == 0.0 {
            // Every built-in plane: the derived coordinate is not in the plane, so the
            // point stays exactly where the snap put it.
            c[derived] = wanted;
        } else {
            // A user's plane in both z_e and w: solve it jointly with the ratio.
            let divisor = n[solved] + n[derived] * derive(1.0);
            if divisor == 0.0 {
                return;
            }
            c[solved] = -self.other_terms(&c, [solved, derived]) / divisor;
            c[derived] = derive(c[solved]);
        }
        let fixed = DVec4::from_array(c);
        if fixed.is_finite() {
            *v = fixed;
        }
    }

    /// The plane's terms for the coordinates not in `except`, and k, summed in the order
    /// `distance` sums them (so that solving for one coordinate is exact on
    /// single-coordinate planes).
    fn other_terms(&self, c: &[f64; 4], except: [usize; 2]) -> f64 {
        let n = self.n.to_array();
        let mut rest = 0.0;
        for i in 0..4 {
            if !except.contains(&i) {
                rest += n[i] * c[i];
            }
        }
        rest + self.k
    }

    /// The plane for points scaled by [`DOWN`]: the same normal, k scaled alike.
    fn scaled_down(&self) -> Plane {
        Plane::new(self.n, self.k * DOWN)
    }

    /// Moves `v` onto the plane along the axis that carries the edge across it: the one
    /// whose coordinate changes the distance most along the edge (`along` = q − p). That
    /// coordinate is the least precise of the interpolated point (it moved the most), and
    /// solving for it keeps the others, which hardly moved. Choosing by the coefficient
    /// alone could solve the left plane's x_e = −w for w from an x_e that lost all its
    /// digits in cancellation (an edge from x = −1e30 to 1e30 got w = −0: found with
    /// examples/degenerate/huge-and-tiny.txt).
    /// Returns the coordinate solved for, if the snapped point was kept.
    fn snap(&self, v: &mut DVec4, along: DVec4) -> Option<usize> {
        let n = self.n.to_array();
        let d = along.to_array();
        let weight = |i: usize| {
            let w = (n[i] * d[i]).abs();
            if w.is_nan() {
                0.0
            } else {
                w
            }
        };
        let axis = (0..4)
            .max_by(|&i, &j| {
                weight(i)
                    .total_cmp(&weight(j))
                    .then(n[i].abs().total_cmp(&n[j].abs()))
            })
            .unwrap_or(0);
        if n[axis] == 0.0 {
            return None;
        }
        let mut c = v.to_array();
        c[axis] = -self.other_terms(&c, [axis, axis]) / n[axis];
        let snapped = DVec4::from_array(c);
        // Keep the snapped point only where it is no worse (a general plane's other terms
        // may round differently); on single-coordinate planes it is exact.
        if snapped.is_finite() && self.distance(snapped).abs() <= self.distance(*v).abs() {
            *v = snapped;
            Some(axis)
        } else {
            None
        }
    }

    /// The plane x_e = K·a·w (a column boundary on the screen at x_s = K), inside where
    /// x_e ≤ K·a·w.
    pub fn column(k: f64, aspect: f64) -> Plane {
        Plane::new(DVec4::new(-1.0, 0.0, 0.0, k * aspect), 0.0)
    }

    /// The plane y_e = K·w (a row boundary at y_s = K), inside where y_e ≤ K·w.
    pub fn row(k: f64) -> Plane {
        Plane::new(DVec4::new(0.0, -1.0, 0.0, k), 0.0)
    }

    /// Parses a general plane `a,b,c,d,k`: the half-space a·x_e + b·y_e + c·z_e + d·w + k ≥ 0.
    pub fn parse(s: &str) -> Result<Plane, String> {
        let c = crate::numbers::parse_numbers::<5>(s, "a,b,c,d,k")?;
        let n = DVec4::new(c[0], c[1], c[2], c[3]);
        if n == DVec4::ZERO {
            return Err(format!("`{s}` is not a plane: a, b, c and d are all zero"));
        }
        Ok(Plane::new(n, c[4]))
    }

    /// The same plane with its inside and outside exchanged.
    pub fn flipped(&self) -> Plane {
        Plane::new(-self.n, -self.k)
    }
}

/// Where an edge (a, b) crosses a plane ([`Plane::crossing`]): the point, and α, the
/// fraction of the way from the edge's inside end to its outside end at which the
/// position was interpolated (before it was put exactly on the plane).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    pub point: DVec4,
    alpha: f64,
    /// Whether the inside end, interpolated from, is b.
    from_b: bool,
}

impl Crossing {
    /// The value at the crossing of something linear along the edge, `at_a` at a and
    /// `at_b` at b (a vertex colour): interpolated from the same end with the same α as
    /// the position, so either direction of travel gives the same bits, as it does for
    /// the point. The result is kept between the two ends (rounding could otherwise take
    /// it an ulp past one, out of a colour's 0–255).
    #[inline]
    pub fn mix(&self, at_a: DVec3, at_b: DVec3) -> DVec3 {
        let (p, q) = if self.from_b {
            (at_b, at_a)
        } else {
            (at_a, at_b)
        };
        (p + (q - p) * self.alpha).clamp(p.min(q), p.max(q))
    }
}

/// [`clip_against`] for a polygon with per-vertex colours: the same vertices, bit for bit,
/// and beside them in `out_colours` the colours, a crossing's interpolated with the
/// position's parameter ([`Crossing::mix`]). `colours` has one per vertex.
pub fn clip_coloured(
    vertices: &[Vertex],
    colours: &[DVec3],
    plane: &Plane,
    out: &mut Vec<Vertex>,
    out_colours: &mut Vec<DVec3>,
) {
    out.clear();
    out_colours.clear();
    let (Some(&last), Some(&last_colour)) = (vertices.last(), colours.last()) else {
        return;
    };
    out.reserve(vertices.len() + 1);
    out_colours.reserve(vertices.len() + 1);
    let (mut s, mut s_colour) = (last, last_colour);
    let (mut s_side, mut s_dist) = plane.classify(s);
    for (&p, &p_colour) in vertices.iter().zip(colours) {
        let (p_side, p_dist) = plane.classify(p);
        if matches!(
            (s_side, p_side),
            (Side::Inside, Side::Outside) | (Side::Outside, Side::Inside)
        ) {
            let crossing = plane.crossing(s, s_dist, p, p_dist);
            out.push(crossing.point);
            out_colours.push(crossing.mix(s_colour, p_colour));
        }
        if p_side != Side::Outside {
            out.push(p);
            out_colours.push(p_colour);
        }
        (s, s_colour, s_side, s_dist) = (p, p_colour, p_side, p_dist);
    }
}

/// Clips the closed polygon `vertices` against `plane` (f_plane of thesis section 3.2, Sutherland–Hodgman: the
/// vertices in pairs (s, p), each pair giving p if inside, the crossing if the pair
/// straddles the plane), writing
/// the clipped polygon to `out` (cleared first, its capacity reused). A polygon wholly
/// outside gives no vertices; one wholly inside (or on) the plane comes out unchanged,
/// vertex for vertex. Degenerate inputs (1 or 2 vertices) follow the same rule.
#[inline]
pub fn clip_against(vertices: &[Vertex], plane: &Plane, out: &mut Vec<Vertex>) {
    out.clear();
    let Some(&last) = vertices.last() else {
        return;
    };
    // A convex polygon gains at most one vertex from one plane.
    out.reserve(vertices.len() + 1);
    // s starts as the last vertex, so the closing edge (v_n, v_1) comes first and the
    // output starts where the input does.
    let mut s = last;
    let (mut s_side, mut s_dist) = plane.classify(s);
    for &p in vertices {
        let (p_side, p_dist) = plane.classify(p);
        if matches!(
            (s_side, p_side),
            (Side::Inside, Side::Outside) | (Side::Outside, Side::Inside)
        ) {
            out.push(plane.intersect(s, s_dist, p, p_dist));
        }
        if p_side != Side::Outside {
            out.push(p);
        }
        (s, s_side, s_dist) = (p, p_side, p_dist);
    }
}

/// The six planes of the clipping pyramid (Appendix 2.1's table, with the aspect ratio a).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PyramidPlane {
    Left,
    Right,
    Top,
    Bottom,
    Hither,
    Yon,
}

impl PyramidPlane {
    pub const ALL: [PyramidPlane; 6] = [
        PyramidPlane::Left,
        PyramidPlane::Right,
        PyramidPlane::Top,
        PyramidPlane::Bottom,
        PyramidPlane::Hither,
        PyramidPlane::Yon,
    ];

    /// The half-space whose inside is the inside of the pyramid:
    ///
    /// | plane  | inside if      |
    /// |--------|----------------|
    /// | left   | x_e ≥ −a·w     |
    /// | right  | x_e ≤ a·w      |
    /// | top    | y_e ≤ w        |
    /// | bottom | y_e ≥ −w       |
    /// | hither | z_e ≥ K1       |
    /// | yon    | z_e ≤ K2       |
    pub fn plane(self, view: &View) -> Plane {
        let a = view.aspect;
        match self {
            PyramidPlane::Left => Plane::new(DVec4::new(1.0, 0.0, 0.0, a), 0.0),
            PyramidPlane::Right => Plane::new(DVec4::new(-1.0, 0.0, 0.0, a), 0.0),
            PyramidPlane::Top => Plane::new(DVec4::new(0.0, -1.0, 0.0, 1.0), 0.0),
            PyramidPlane::Bottom => Plane::new(DVec4::new(0.0, 1.0, 0.0, 1.0), 0.0),
            PyramidPlane::Hither => Plane::new(DVec4::new(0.0, 0.0, 1.0, 0.0), -view.hither),
            PyramidPlane::Yon => Plane::new(DVec4::new(0.0, 0.0, -1.0, 0.0), view.yon),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            PyramidPlane::Left => "left",
            PyramidPlane::Right => "right",
            PyramidPlane::Top => "top",
            PyramidPlane::Bottom => "bottom",
            PyramidPlane::Hither => "hither",
            PyramidPlane::Yon => "yon",
        }
    }
}

impl fmt::Display for PyramidPlane {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for PyramidPlane {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        PyramidPlane::ALL
            .into_iter()
            .find(|p| p.name() == s)
            .ok_or_else(|| {
                format!("unknown plane `{s}` (expected left, right, top, bottom, hither or yon)")
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn view() -> View {
        View::default()
    }

    #[test]
    fn colours_are_interpolated_where_the_edge_is_cut() {
        // Left plane x_e ≥ −w = −10: the edge from x = 2 to x = −22 crosses at half way
        // (α = 12/24), the edge back from −22 at x = 2, the same point from its inside end.
        let left = PyramidPlane::Left.plane(&view());
        let e = |x: f64, y: f64| DVec4::new(x, y, 16.0, 10.0);
        let tri = [e(2.0, 0.0), e(-22.0, 8.0), e(2.0, 8.0)];
        let colours = [
            DVec3::new(200.0, 0.0, 10.0),
            DVec3::new(0.0, 100.0, 30.0),
            DVec3::new(50.0, 50.0, 50.0),
        ];
        let (mut out, mut out_colours) = (vec![], vec![]);
        clip_coloured(&tri, &colours, &left, &mut out, &mut out_colours);
        let mut flat = vec![];
        clip_against(&tri, &left, &mut flat);
        assert_eq!(out, flat);
        assert_eq!(
            out,
            [e(2.0, 0.0), e(-10.0, 4.0), e(-10.0, 8.0), e(2.0, 8.0)]
        );
        assert_eq!(
            out_colours,
            [
                DVec3::new(200.0, 0.0, 10.0),
                DVec3::new(100.0, 50.0, 20.0),
                DVec3::new(25.0, 75.0, 40.0),
                DVec3::new(50.0, 50.0, 50.0),
            ]
        );
    }

    proptest! {
        /// The crossing's colour is the same bits whichever way the edge is walked, as
        /// its position is, and lies between the ends' colours.
        #[test]
        fn a_crossings_colour_does_not_depend_on_the_direction(
            a in prop::array::uniform4(-50.0f64..50.0),
            b in prop::array::uniform4(-50.0f64..50.0),
            ca in prop::array::uniform3(0.0f64..=255.0),
            cb in prop::array::uniform3(0.0f64..=255.0),
        ) {
            let plane = PyramidPlane::Left.plane(&view());
            let (a, b) = (DVec4::from_array(a), DVec4::from_array(b));
            let (ca, cb) = (DVec3::from_array(ca), DVec3::from_array(cb));
            let (sa, da) = plane.classify(a);
            let (sb, db) = plane.classify(b);
            prop_assume!(matches!((sa, sb), (Side::Inside, Side::Outside) | (Side::Outside, Side::Inside)));
            let forth = plane.crossing(a, da, b, db);
            let back = plane.crossing(b, db, a, da);
            prop_assert_eq!(forth.point, back.point);
            prop_assert_eq!(forth.point, plane.intersect(a, da, b, db));
            let (c1, c2) = (forth.mix(ca, cb), back.mix(cb, ca));
            prop_assert_eq!(c1, c2);
            prop_assert!(c1.cmpge(ca.min(cb)).all() && c1.cmple(ca.max(cb)).all());
        }
    }

    /// Fuzz target `clip`'s first crash (fuzz/regressions/clip-subnormal): an edge of
    /// subnormal coordinates clipped against the left plane gave an intersection whose
    /// distance rounded to -2^-1074, classified outside. Within a few units of 2^-1074
    /// a point is on the plane.
    #[test]
    fn subnormal_distances_are_on_the_plane() {
        let left = PyramidPlane::Left.plane(&View {
            aspect: 16.0 / 9.0,
            ..View::default()
        });
        let p = DVec4::new(
            1.08673021503e-313,
            1.7206164110350098e-299,
            -6.1128574593e-314,
            -6.1128574598e-314,
        );
        assert_eq!(left.classify(p).0, Side::On);
        assert_eq!(
            left.classify(DVec4::new(-1e-300, 0.0, 0.0, 0.0)).0,
            Side::Outside
        );
        assert_eq!(
            left.classify(DVec4::new(1e-300, 0.0, 0.0, 0.0)).0,
            Side::Inside
        );
    }

    /// Fuzz target `clip`'s second crash (fuzz/regressions/clip-overflow): an edge from
    /// w = 8e298 to w = -f64::MAX overflowed the divisor of α and q − p, and the top plane
    /// got an intersection with w = NaN. Every intersection is finite and on the plane.
    #[test]
    fn huge_coordinates_intersect_finitely() {
        let top = PyramidPlane::Top.plane(&view());
        let a = DVec4::new(15.25, 15.25, 35.0, 8.3711609936427125e298);
        let b = DVec4::new(3.0135153699541016e296, 125.0, -1.0, -f64::MAX);
        let (sa, da) = top.classify(a);
        let (sb, db) = top.classify(b);
        assert_eq!((sa, sb), (Side::Inside, Side::Outside));
        let i = top.intersect(a, da, b, db);
        assert!(i.is_finite(), "{i:?}");
        assert_eq!(top.classify(i).0, Side::On);
        // A distance that overflows still gets the right side.
        let right = PyramidPlane::Right.plane(&View {
            aspect: 16.0 / 9.0,
            ..view()
        });
        assert_eq!(
            right.classify(DVec4::new(-f64::MAX, 0.0, 1.0, f64::MAX)).0,
            Side::Inside
        );
        assert_eq!(
            right.classify(DVec4::new(f64::MAX, 0.0, 1.0, -f64::MAX)).0,
            Side::Outside
        );
    }

    /// An edge from x_e = −1e30 to 1e30 at w = 15.625 meets the left plane at
    /// x_e = −w = −15.625: the interpolated x_e has lost every digit, so the snap solves
    /// for x_e and keeps w (it used to solve for w and gave w = −0, behind the eye).
    #[test]
    fn huge_edges_keep_their_w() {
        let left = PyramidPlane::Left.plane(&view());
        let a = DVec4::new(1e30, -1e30, 25.0, 15.625);
        let b = DVec4::new(-1e30, -1e30, 25.0, 15.625);
        let (_, da) = left.classify(a);
        let (_, db) = left.classify(b);
        let i = left.intersect(a, da, b, db);
        assert_eq!(i, DVec4::new(-15.625, -1e30, 25.0, 15.625));
    }

    /// examples/degenerate/huge-through-eye.txt: the edge from (4, 4, −1e30) to
    /// (8, 4, 1e30) in eye space (w = 0.625·z_e). The left plane solves w = −x_e = −6;
    /// interpolated z_e is rounding noise, so it is recomputed: z_e = w/0.625 = −9.6.
    /// Hither then solves z_e = 1, and w = 0.625 follows (interpolated, it was 0).
    #[test]
    fn cancelled_z_or_w_is_recomputed_from_the_other() {
        let a = DVec4::new(4.0, 4.0, -1e30, -6.25e29);
        let b = DVec4::new(8.0, 4.0, 1e30, 6.25e29);
        let left = PyramidPlane::Left.plane(&view());
        let i = left.intersect(a, left.distance(a), b, left.distance(b));
        assert_eq!(i, DVec4::new(6.0, 4.0, -6.0 / 0.625, -6.0));
        let hither = PyramidPlane::Hither.plane(&view());
        let j = hither.intersect(b, hither.distance(b), a, hither.distance(a));
        assert_eq!((j.z, j.w), (1.0, 0.625));
        // A user's plane in both z_e and w (z_e + w ≥ 16.25, i.e. z_e ≥ 10) is solved
        // jointly with the ratio.
        let both = Plane::new(DVec4::new(0.0, 0.0, 1.0, 1.0), -16.25);
        let k = both.intersect(b, both.distance(b), a, both.distance(a));
        assert_eq!((k.z, k.w), (10.0, 6.25));
    }

    /// Differential seed 61186: after the left cut, an edge whose ends lie on the left
    /// plane only to their rounding (1e291 at 1e307) meets the right plane near the eye.
    /// A side plane keeps the interpolated crossing there, the eye itself, which the
    /// later cuts remove; the exact crossing of those rounded ends lies 1e291 from the
    /// eye, as far outside the left plane, and survived to the screen ("far outside
    /// the 90x31 screen"). Hither, which is not through the eye, takes the exact one.
    #[test]
    fn a_side_plane_keeps_interpolation_where_its_edge_meets_the_eye() {
        let view = View {
            aspect: 90.0 / 31.0,
            ..view()
        };
        let right = PyramidPlane::Right.plane(&view);
        let a = DVec4::new(
            -2.5368663685982835e307,
            4.605132077428136e307,
            1.3980952431386095e307,
            8.738095269616309e306,
        );
        let b = DVec4::new(
            5.317335560455483e307,
            -9.652472380495508e307,
            -2.930442708873244e307,
            -1.8315266930457777e307,
        );
        let i = right.intersect(a, right.distance(a), b, right.distance(b));
        assert_eq!(i.abs(), DVec4::ZERO);
        let exact = crate::exact::crossing(a, b, right.n, right.k).unwrap();
        let left = PyramidPlane::Left.plane(&view);
        assert!(left.distance(exact) < -1e290, "{exact}");
    }

    /// Where nothing cancelled, the repair leaves every bit as interpolation gave it; and
    /// a point pair that does not keep one w/z_e (not an eye-space stream) is left alone.
    #[test]
    fn ordinary_intersections_are_not_repaired() {
        let hither = PyramidPlane::Hither.plane(&view());
        let a = DVec4::new(1.0, 2.0, 0.3, 0.3 * 0.625);
        let b = DVec4::new(3.0, -1.0, 7.7, 7.7 * 0.625);
        let i = hither.intersect(b, hither.distance(b), a, hither.distance(a));
        let alpha = hither.distance(b) / (hither.distance(b) - hither.distance(a));
        let mut expect = b + (a - b) * alpha;
        expect.z = 1.0;
        assert_eq!(i, expect);
        let odd = (
            DVec4::new(4.0, 4.0, -1e30, 5.0),
            DVec4::new(8.0, 4.0, 1e30, 7.0),
        );
        let j = hither.intersect(odd.1, hither.distance(odd.1), odd.0, hither.distance(odd.0));
        assert_eq!((j.z, j.w), (1.0, 6.0));
        assert_eq!(w_over_z(odd.0, odd.1), None);
        assert_eq!(w_over_z(DVec4::ZERO, b), Some(0.625));
    }

    /// The lane classifier is `classify`, lane for lane and bit for bit: points on, near
    /// and across every pyramid plane and a general one, subnormal coordinates, and
    /// coordinates whose distance overflows (where `classify` rescales).
    #[test]
    fn classify_lanes_is_classify_on_every_lane() {
        let view = View {
            aspect: 16.0 / 9.0,
            ..view()
        };
        let mut planes: Vec<Plane> = PyramidPlane::ALL.iter().map(|p| p.plane(&view)).collect();
        planes.push(Plane::new(DVec4::new(0.3, -0.7, 1.1, 0.2), -2.5));
        let mut points = vec![
            DVec4::new(-10.0, 0.0, 16.0, 10.0),
            DVec4::new(-160.0 / 9.0, 10.0, 16.0, 10.0),
            DVec4::new(1e-313, -1e-313, 6e-314, 6e-314),
            DVec4::new(-f64::MAX, 0.0, 1.0, f64::MAX),
            DVec4::new(f64::MAX, f64::MAX, -f64::MAX, -f64::MAX),
            DVec4::new(1e300, -1e300, 1e300, 1e300),
            DVec4::new(0.0, 0.0, 1.0, 0.625),
            DVec4::new(0.0, 0.0, 30.0, 18.75),
            DVec4::ZERO,
        ];
        // A lattice through the pyramid, some of it behind the eye.
        for i in 0..7 {
            for j in 0..7 {
                let z = -2.0 + 5.5 * i as f64;
                let x = (j as f64 - 3.0) * 0.5 * z;
                points.push(DVec4::new(x, -x * 0.75, z, z * 0.625));
            }
        }
        let lanes: [Vec<f64>; 4] = std::array::from_fn(|c| points.iter().map(|p| p[c]).collect());
        for plane in planes {
            let mut dist = vec![0.0; points.len()];
            let mut side = vec![Side::On; points.len()];
            plane.classify_lanes(
                [&lanes[0], &lanes[1], &lanes[2], &lanes[3]],
                &mut dist,
                &mut side,
            );
            for (i, p) in points.iter().enumerate() {
                let (s, d) = plane.classify(*p);
                assert_eq!(side[i], s, "{plane:?} {p:?}");
                assert_eq!(dist[i].to_bits(), d.to_bits(), "{plane:?} {p:?}");
            }
        }
    }

    #[test]
    fn pyramid_sides_match_appendix_2() {
        let v = view();
        let p = |x, y, z: f64| DVec4::new(x, y, z, z * 10.0 / 16.0);
        // z_e = 16 gives w = 10.
        assert_eq!(
            PyramidPlane::Left.plane(&v).classify(p(-11.0, 0.0, 16.0)).0,
            Side::Outside
        );
        assert_eq!(
            PyramidPlane::Left.plane(&v).classify(p(-10.0, 0.0, 16.0)).0,
            Side::On
        );
        assert_eq!(
            PyramidPlane::Left.plane(&v).classify(p(-9.0, 0.0, 16.0)).0,
            Side::Inside
        );
        assert_eq!(
            PyramidPlane::Right.plane(&v).classify(p(11.0, 0.0, 16.0)).0,
            Side::Outside
        );
        assert_eq!(
            PyramidPlane::Top.plane(&v).classify(p(0.0, 11.0, 16.0)).0,
            Side::Outside
        );
        assert_eq!(
            PyramidPlane::Bottom
                .plane(&v)
                .classify(p(0.0, -9.0, 16.0))
                .0,
            Side::Inside
        );
        assert_eq!(
            PyramidPlane::Hither.plane(&v).classify(p(0.0, 0.0, 0.5)).0,
            Side::Outside
        );
        assert_eq!(
            PyramidPlane::Yon.plane(&v).classify(p(0.0, 0.0, 30.0)).0,
            Side::On
        );
    }

    #[test]
    fn intersections_land_exactly_on_pyramid_planes() {
        let v = view();
        let a = DVec4::new(0.3, 0.7, 5.0, 5.0 * 0.625);
        let b = DVec4::new(-40.1, -33.3, 0.1, 0.1 * 0.625);
        for which in PyramidPlane::ALL {
            let plane = which.plane(&v);
            let (sa, da) = plane.classify(a);
            let (sb, db) = plane.classify(b);
            if sa == sb || sa == Side::On || sb == Side::On {
                continue;
            }
            let i = plane.intersect(a, da, b, db);
            assert_eq!(plane.distance(i), 0.0, "{which}");
            assert_eq!(
                plane.intersect(b, db, a, da),
                i,
                "{which} is walk-order independent"
            );
        }
    }

    #[test]
    fn column_and_row_planes_pass_through_the_eye() {
        let c = Plane::column(0.5, 2.0);
        // x_e = 0.5·2·w
        assert_eq!(c.classify(DVec4::new(5.0, 0.0, 8.0, 5.0)).0, Side::On);
        assert_eq!(c.classify(DVec4::new(4.0, 0.0, 8.0, 5.0)).0, Side::Inside);
        let r = Plane::row(-0.25);
        assert_eq!(r.classify(DVec4::new(0.0, -1.0, 8.0, 4.0)).0, Side::On);
        assert_eq!(
            r.flipped().classify(DVec4::new(0.0, 0.0, 8.0, 4.0)).0,
            Side::Inside
        );
    }
}
