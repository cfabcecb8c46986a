//! An edge's crossing with a plane, each coordinate to within a few units in the last
//! place of its own size, however far the edge's ends are: for the clippers' crossings
//! on edges whose ends are so far from the crossing that interpolating from either end
//! leaves only rounding (docs/degenerate.md, the `huge` kind's row; docs/fuzzing.md).
//!
//! The crossing of the edge from `a` to `b` with the plane `n·v + k = 0`, where `a` is at
//! distance `d_a = n·a + k` and `b` at `d_b`, is, coordinate by coordinate,
//!
//! ```text
//! v_i = (d_a·b_i − d_b·a_i) / (d_a − d_b)
//!     = (Σ_j n_j·(a_j·b_i − b_j·a_i) + k·(b_i − a_i)) / Σ_j n_j·(a_j − b_j),
//! ```
//!
//! a ratio of two sums of products of the inputs. Interpolating `a + t·(b − a)` rounds
//! `t` to about 2⁻⁵³ of itself and multiplies that error by `|b − a|`: an edge from
//! −1e100 to 1e100 that crosses the plane near the eye gets a point some 1e84 off.
//! Here both sums are computed exactly, as expansions (Shewchuk, "Adaptive Precision
//! Floating-Point Arithmetic and Fast Robust Geometric Predicates", Discrete Comput.
//! Geom. 18, 1997: each product split into its rounded value and its error by a fused
//! multiply-add, the sums carried without loss by TwoSum), then divided and the quotient
//! corrected by its exact remainder: within about half a unit in the last place of each
//! coordinate, whatever the ends' size.

use glam::DVec4;

/// `a + b` as its rounded value and the rounding error, exactly (Knuth's TwoSum).
#[inline]
pub fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `a·b` as its rounded value and the rounding error, exactly (a fused multiply-add
/// gives the error; exact unless the product underflows).
#[inline]
pub fn two_product(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// A sum kept exactly as an expansion: components of increasing magnitude that do not
/// overlap (Shewchuk's GROW-EXPANSION, zero components dropped).
#[derive(Default)]
struct Expansion {
    parts: Vec<f64>,
}

impl Expansion {
    /// Adds `x`, exactly.
    fn add(&mut self, x: f64) {
        let mut q = x;
        let mut kept = 0;
        for i in 0..self.parts.len() {
            let (s, e) = two_sum(q, self.parts[i]);
            if e != 0.0 {
                self.parts[kept] = e;
                kept += 1;
            }
            q = s;
        }
        self.parts.truncate(kept);
        if q != 0.0 {
            self.parts.push(q);
        }
    }

    /// Adds `c·(x·y)`, exactly: four products of doubles.
    fn add_scaled_product(&mut self, c: f64, x: f64, y: f64) {
        let (p, e) = two_product(x, y);
        for part in [p, e] {
            let (q, f) = two_product(c, part);
            self.add(q);
            self.add(f);
        }
    }

    /// Adds `c·(x − y)`, exactly.
    fn add_scaled_difference(&mut self, c: f64, x: f64, y: f64) {
        let (d, e) = two_sum(x, -y);
        for part in [d, e] {
            let (q, f) = two_product(c, part);
            self.add(q);
            self.add(f);
        }
    }

    /// The sum rounded: the components added from the smallest, each below the rounding
    /// of the sum of the larger ones, so within about one unit in the last place.
    fn value(&self) -> f64 {
        self.parts.iter().sum()
    }
}

/// `top / bottom` of two exact sums (`bottom_value` the rounded `bottom`), within about
/// half a unit in the last place: the quotient of the rounded sums, then corrected by
/// the remainder `top − q·bottom`, itself computed exactly.
fn quotient(top: &Expansion, bottom: &Expansion, bottom_value: f64) -> f64 {
    let q = top.value() / bottom_value;
    if !q.is_finite() || q == 0.0 {
        return q;
    }
    let mut rest = Expansion {
        parts: top.parts.clone(),
    };
    for &part in &bottom.parts {
        let (p, e) = two_product(q, part);
        rest.add(-p);
        rest.add(-e);
    }
    q + rest.value() / bottom_value
}

/// Coordinates beyond this (2⁴⁰⁰) are scaled down by a power of two before the products
/// are formed, so that a product of two cannot overflow; scaling by a power of two is
/// exact, and the crossing scales with the ends.
const SCALE_ABOVE: f64 = 2.582249878086908e120;

/// The crossing of the edge from `a` to `b` with the plane `n·v + k = 0` (the ends on
/// opposite sides of it), each coordinate within a few units in its last place. `None`
/// where the ends' distances do not differ (no crossing) or the result is not finite.
pub fn crossing(a: DVec4, b: DVec4, n: DVec4, k: f64) -> Option<DVec4> {
    let largest = a.abs().max_element().max(b.abs().max_element());
    if !largest.is_finite() {
        return None;
    }
    // 2^e with largest·2^-e ≤ 2^400: exact scaling, undone on the result.
    let shift = if largest > SCALE_ABOVE {
        (largest.log2().ceil() as i32) - 400
    } else {
        0
    };
    let down = 2f64.powi(-shift);
    let (a, b, k) = (a * down, b * down, k * down);
    let (na, aa, ba) = (n.to_array(), a.to_array(), b.to_array());
    let mut divisor = Expansion::default();
    for j in 0..4 {
        if na[j] != 0.0 {
            divisor.add_scaled_difference(na[j], aa[j], ba[j]);
        }
    }
    let divisor_parts = divisor;
    let divisor = divisor_parts.value();
    if divisor == 0.0 || !divisor.is_finite() {
        return None;
    }
    let mut v = [0.0; 4];
    for (i, vi) in v.iter_mut().enumerate() {
        let mut top = Expansion::default();
        for j in 0..4 {
            if na[j] != 0.0 && j != i {
                top.add_scaled_product(na[j], aa[j], ba[i]);
                top.add_scaled_product(-na[j], ba[j], aa[i]);
            }
        }
        if k != 0.0 {
            top.add_scaled_difference(k, ba[i], aa[i]);
        }
        *vi = quotient(&top, &divisor_parts, divisor);
    }
    let up = 2f64.powi(shift);
    let v = DVec4::from_array(v) * up;
    v.is_finite().then_some(v)
}

/// The fraction of a crossing's size (2⁻²⁰, about 1e-6) beyond which its interpolation
/// error sends it to [`crossing`].
const LOST_TO_INTERPOLATION: f64 = 9.5367431640625e-7;

/// Whether a coordinate of an interpolated crossing `v` of the edge from `a` to `b` may be
/// off by more than [`LOST_TO_INTERPOLATION`] of its size (or of 1, so that a crossing
/// at the eye does not call for it): its error is a few units in the last place of the
/// ends' coordinate. Only an edge whose ends are some 10^9 times farther out than the
/// crossing, in some coordinate, is; every other keeps its interpolated crossing, bit
/// for bit.
pub fn interpolation_lost_digits(a: DVec4, b: DVec4, v: DVec4) -> bool {
    let error = a.abs().max(b.abs()) * (4.0 * f64::EPSILON);
    let size = v.abs().max(DVec4::ONE);
    error.cmpgt(size * LOST_TO_INTERPOLATION).any()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The hither plane z_e = 1: n = (0, 0, 1, 0), k = −1.
    const HITHER: (DVec4, f64) = (DVec4::new(0.0, 0.0, 1.0, 0.0), -1.0);

    #[test]
    fn an_ordinary_edge_crosses_where_interpolation_puts_it() {
        let (a, b) = (
            DVec4::new(-3.0, 2.0, -1.0, -0.625),
            DVec4::new(5.0, -6.0, 3.0, 1.875),
        );
        let v = crossing(a, b, HITHER.0, HITHER.1).unwrap();
        // t = 2/4 = 0.5: exactly the midpoint, z_e on the plane.
        assert_eq!(v, DVec4::new(1.0, -2.0, 1.0, 0.625));
    }

    #[test]
    fn an_edge_from_far_behind_to_far_in_front_crosses_at_its_true_point() {
        // From 2^330 behind the eye to 2^330 in front along x = 2·z_e, crossing hither at
        // x = 2 (the differential suite's `huge` kind, seed 41088, at 1e100).
        let big = 2f64.powi(330);
        let a = DVec4::new(-2.0 * big, -1e100, -big, -big * 0.625);
        let b = DVec4::new(2.0 * big, -1e100, big, big * 0.625);
        let v = crossing(a, b, HITHER.0, HITHER.1).unwrap();
        assert_eq!(v.z, 1.0);
        assert_eq!(v.x, 2.0);
        assert_eq!(v.y, -1e100);
        assert_eq!(v.w, 0.625);
        // Interpolation rounds t = (1 + 2^330)/2^331 to ½ and lands on the middle, x = 0.
        let t = (1.0 - a.z) / (b.z - a.z);
        let interpolated = a + (b - a) * t;
        assert_eq!((t, interpolated.x), (0.5, 0.0));
        assert!(interpolation_lost_digits(a, b, interpolated));
    }

    #[test]
    fn ends_near_the_largest_f64_are_scaled_and_stay_finite() {
        let big = 8.0e307;
        let a = DVec4::new(-big, -1e308, -big, -big * 0.5);
        let b = DVec4::new(big, -1e308, big, big * 0.5);
        let v = crossing(a, b, HITHER.0, HITHER.1).unwrap();
        // x = z_e on this edge (through the rounded ends exactly): 1 at the plane.
        assert_eq!((v.x, v.y, v.z, v.w), (1.0, -1e308, 1.0, 0.5));
    }

    #[test]
    fn ordinary_edges_keep_their_interpolated_crossings() {
        let (a, b) = (
            DVec4::new(-3.0, 2.0, -1.0, -0.625),
            DVec4::new(5.0, -6.0, 3.0, 1.875),
        );
        assert!(!interpolation_lost_digits(
            a,
            b,
            DVec4::new(1.0, -2.0, 1.0, 0.625)
        ));
        // Ends 1e6 out, crossing at the eye: 4ε·1e6 ≈ 9e-10, kept; 1e10 out, recomputed.
        let far = DVec4::splat(1e6);
        assert!(!interpolation_lost_digits(-far, far, DVec4::ZERO));
        assert!(interpolation_lost_digits(
            -far * 1e4,
            far * 1e4,
            DVec4::ZERO
        ));
    }

    use proptest::prelude::*;

    proptest! {
        /// An edge along x = c·z_e, y constant, w = 0.625·z_e, from 2^e behind the eye
        /// to 2^e in front (every end exact in f64), crosses z_e = K1 at (c·K1, y, K1,
        /// 0.625·K1) exactly, however large 2^e; interpolation keeps that only while 2^e
        /// is small.
        #[test]
        fn far_ends_on_a_known_line_cross_at_its_point(
            c in -64i32..=64,
            y in -1e6f64..1e6,
            e in 0i32..1000,
            k1 in 1i32..=8,
        ) {
            let (c, k1, far) = (c as f64, k1 as f64, 2f64.powi(e));
            let a = DVec4::new(-c * far, y, -far, -0.625 * far);
            let b = DVec4::new(c * far, y, far, 0.625 * far);
            let v = crossing(a, b, DVec4::new(0.0, 0.0, 1.0, 0.0), -k1).unwrap();
            prop_assert_eq!(v, DVec4::new(c * k1, y, k1, 0.625 * k1));
        }

        /// On ordinary edges the crossing is interpolation's to within rounding.
        #[test]
        fn ordinary_edges_cross_where_interpolation_does(
            a in prop::array::uniform4(-1e3f64..1e3),
            b in prop::array::uniform4(-1e3f64..1e3),
            n in prop::array::uniform4(-4f64..4.0),
            k in -10f64..10.0,
        ) {
            let (a, b, n) = (DVec4::from_array(a), DVec4::from_array(b), DVec4::from_array(n));
            let (da, db) = (n.dot(a) + k, n.dot(b) + k);
            prop_assume!(da > 1e-3 && db < -1e-3);
            let t = da / (da - db);
            let interpolated = a + (b - a) * t;
            let v = crossing(a, b, n, k).unwrap();
            let size = a.abs().max(b.abs()).max_element();
            // The interpolation's own error: t's rounding, and da − db's cancellation
            // (the distances are at least 1e-3 apart from 0, each within ε·|n|·|a|).
            let bound = 1e-9 * size / (da - db).min(1.0);
            prop_assert!((v - interpolated).abs().max_element() <= bound, "{} {}", v, interpolated);
        }

        /// Scaling the ends and the plane's constant by a power of two scales the
        /// crossing by it, exactly (within the range where nothing overflows or becomes
        /// subnormal).
        #[test]
        fn the_crossing_scales_with_its_ends(
            a in prop::array::uniform4(-1e3f64..1e3),
            b in prop::array::uniform4(-1e3f64..1e3),
            k in -10f64..10.0,
            s in -200i32..700,
        ) {
            let n = DVec4::new(1.0, -0.5, 0.25, 2.0);
            let (a, b) = (DVec4::from_array(a), DVec4::from_array(b));
            prop_assume!((n.dot(a) + k) * (n.dot(b) + k) < 0.0);
            let up = 2f64.powi(s);
            let v = crossing(a, b, n, k).unwrap();
            prop_assert_eq!(crossing(a * up, b * up, n, k * up).unwrap(), v * up);
        }
    }
}
