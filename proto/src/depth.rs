//! The tie rule: which of two polygons is seen at a pixel centre (docs/DESIGN.md, "The Z
//! specification"), written once for every renderer.
//!
//! The thesis's Z specification (Theoharis 1985, §2.3) gives a pixel to the covering
//! polygon of smallest depth, and a tie to the polygon earlier in the stream. Taken
//! literally in floating point that is a coin toss for coplanar polygons: two polygons on
//! one plane, each with its own rounded vertices, get depths a few ulps apart, and a decal
//! comes out as noise. So "equal" is given a width:
//!
//! > Folding the polygons that cover a pixel centre in stream order, a later polygon takes
//! > the pixel from the one that holds it only when it is nearer there by more than
//! > 2⁻³⁰ of the holder's depth: z_new < z_held − 2⁻³⁰·|z_held|.
//!
//! Coplanar polygons, whose depths differ by rounding (about 2⁻⁵⁰ of the depth), then tie
//! and the earlier one shows; polygons more than one part in 10⁹ apart are always ordered
//! by depth. The rule is relative, so it holds at any distance from the eye.
//!
//! The pipeline does not keep eye-space z_e but the *reciprocal depth* D = −K1/z_e that
//! persp writes by default ([`crate::camera::Device::reciprocal_depth`]): an affine
//! function of screen position on any plane, so it interpolates exactly, and an f64 with
//! the same relative precision at every distance. For it the same formula, D_new < D_held − 2⁻³⁰·|D_held|,
//! reads 1/z_new > (1 + 2⁻³⁰)/z_held, that is z_new·(1 + 2⁻³⁰) < z_held: the rule above to
//! within 2⁻⁶⁰ of the depth, below what an f64 can tell apart. So [`takes`] serves every
//! depth a stage may hold (z_e itself in zspec and in eye-z mode, D in the pipeline).

/// The rule's relative width: 2⁻³⁰.
pub const TIE: f64 = 1.0 / (1u64 << 30) as f64;

/// Does a polygon later in the stream, at depth `new` at a pixel centre, take the pixel
/// from the polygon that holds it at depth `held`? Smaller depth is nearer; `new` must be
/// nearer by more than [`TIE`] of `|held|`. A NaN depth never takes a pixel.
#[inline]
pub fn takes(new: f64, held: f64) -> bool {
    new < bar(held)
}

/// The depth a newcomer must be below to take a pixel held at `held`: `held − TIE·|held|`,
/// computed as `held·(1 ∓ TIE)` so that `±∞` stay themselves. A z-buffer can keep this
/// instead of the depth, so that its test is one comparison. An empty pixel is held at
/// `+∞`, which any finite depth is below.
#[inline]
pub fn bar(held: f64) -> f64 {
    held * (1.0 - TIE.copysign(held))
}

/// Whether a polygon *earlier* in the stream than the holder, at depth `early`, takes the
/// pixel from it: the same rule seen from the other side (the holder would not have taken
/// the pixel from it). For a z-buffer whose inputs do not arrive in stream order (zbuf
/// merging inputs that overlap): with two polygons at a pixel the outcome is the fold's.
#[inline]
pub fn takes_back(early: f64, held: f64) -> bool {
    !takes(held, early) && !early.is_nan()
}

/// Whether a polygon at depth `z` is in front of another at depth `other` at one pixel,
/// the rule for two polygons: coming `later` in the stream it must take the pixel from the
/// other ([`takes`]); coming earlier, the other must not take the pixel from it
/// ([`takes_back`]). The pairwise test of every method that does not fold in stream order.
#[inline]
pub fn in_front(z: f64, later: bool, other: f64) -> bool {
    if later {
        takes(z, other)
    } else {
        takes_back(z, other)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tie_keeps_the_holder_and_a_gap_beyond_the_width_orders() {
        // Eye-space depths: 2^-30 is the width, relative to the holder.
        let held = 100.0;
        assert!(!takes(held, held));
        assert!(!takes(held * (1.0 - 0.9 * TIE), held));
        assert!(takes(held * (1.0 - 1.1 * TIE), held));
        assert!(!takes(held * (1.0 + TIE), held));
        // Reciprocal depths are negative: nearer is more negative.
        let d = -1.0 / 880.0;
        assert!(!takes(d * (1.0 + 0.9 * TIE), d));
        assert!(takes(d * (1.0 + 1.1 * TIE), d));
        // An empty pixel is held at +inf; NaN never takes.
        assert!(takes(1e300, f64::INFINITY));
        assert!(!takes(f64::NAN, f64::INFINITY));
        assert!(!takes(f64::NAN, 1.0));
    }

    #[test]
    fn the_reciprocal_form_keeps_the_eye_space_rule() {
        // z_new·(1 + 2^-30) < z_held in eye space, for gaps either side of the width.
        for &z in &[1e-3, 0.7, 20.0, 880.0, 1e6, 1e9] {
            for &k in &[0.5, 0.99, 1.01, 2.0, 1e3] {
                let near = z * (1.0 - k * TIE);
                let (d_near, d_held) = (-1e-3 / near, -1e-3 / z);
                assert_eq!(takes(near, z), k > 1.0, "eye z {z}, gap {k} widths");
                assert_eq!(takes(d_near, d_held), k > 1.0, "reciprocal at {z}, {k}");
            }
        }
    }

    #[test]
    fn takes_back_agrees_with_the_fold_for_two() {
        for &(a, b) in &[(1.0, 1.0), (1.0, 0.5), (0.5, 1.0), (1.0, 1.0 - 0.5 * TIE)] {
            // Stream order a then b: b takes iff takes(b, a). Arriving b first, a later:
            // a takes back iff the fold's answer is a.
            let fold_a_wins = !takes(b, a);
            assert_eq!(takes_back(a, b), fold_a_wins, "{a} {b}");
        }
    }
}
