//! Where a depth form is too coarse for the tie rule: the z-buffer's precision failure,
//! noticed and counted (docs/methods.md, "The z-buffer near yon").
//!
//! The tie rule (docs/DESIGN.md, "Visibility") orders two polygons at a pixel centre by
//! eye-space depth when they are more than 2⁻³⁰ of it apart. Every z-buffer here applies it
//! to the depths persp wrote, f64s in some [`DepthForm`], as `D_new < D_held − 2⁻³⁰·|D_held|`.
//! For reciprocal depth and eye-z that is the rule itself (both are relative measures of
//! z_e). Projective depth z_s = k·(1 − K1/z_e) crowds against 1 far from the eye: there the
//! rule's width in z_s spans 2⁻³⁰·(z_e − K1)/K1 of z_e ([`DepthForm::rule_width`]), and
//! where K2/K1 passes about 10⁶ a few ulps of z_s span more than 2⁻³⁰ as well
//! ([`DepthForm::quantum`]). Two polygons within that width tie on the z-buffer and the
//! earlier one shows, where the rule put the later one in front: the "z-fighting" that
//! loses a whole polygon near yon.
//!
//! [`QuantumWatch`] finds those tests. It exists only for a stream whose header names a
//! form that can be that coarse in its view volume ([`QuantumWatch::for_form`]: projective
//! depth); for every other stream the z-test runs as before and nothing is counted. It
//! keeps its own depth per pixel and folds the same spans by the same test, and where a
//! later polygon lost, it maps both depths back to eye space and counts the test if the
//! rule would have given the pixel to the newcomer there, or if the two were within
//! [`ULPS`] ulps that are wider in eye space than the rule: rounding decided those.

use crate::walk::Span;
use crate::Depth;
use proto::depth::{takes, TIE};
use proto::fragment::span_depth;
use proto::DepthForm;

/// How many ulps of depth the pipeline's own rounding may put between two coplanar
/// polygons' depths at a pixel (persp's one division per vertex, the depth plane's fit, the
/// step along the row): two depths closer than this are a tie that rounding, not the
/// geometry, may have made.
pub const ULPS: f64 = 4.0;

/// A frame's pixels where rounding in the stream's depth form, not the tie rule, ordered
/// two polygons (see the module notes).
pub struct QuantumWatch {
    form: DepthForm,
    width: u32,
    height: u32,
    /// Per pixel, row-major, the depth of the polygon that holds it (+∞: none yet).
    held: Vec<Depth>,
    /// This frame's count.
    lost: u64,
}

impl QuantumWatch {
    /// A watch for a `width`×`height` screen whose depths are in `form`, or `None` when
    /// the z-buffer's test on that form is the tie rule everywhere in the view volume
    /// (reciprocal depth and eye-z), or the form is unknown: then nothing need be watched.
    pub fn for_form(form: Option<DepthForm>, width: u32, height: u32) -> Option<Self> {
        let form = form?;
        (form.widest(ULPS) > TIE).then(|| QuantumWatch {
            form,
            width,
            height,
            held: vec![Depth::INFINITY; width as usize * height as usize],
            lost: 0,
        })
    }

    /// A polygon's span, in stream order, as the z-buffer tests it.
    pub fn span(&mut self, span: &Span) {
        self.row(span.y, span.x0, span.x1, span.z_row, span.dz);
    }

    /// Pixels `x0..x1` of row `y`, pixel x at depth `z_row + x·dz`
    /// ([`proto::fragment::span_depth`]); a span off the screen is clipped.
    pub fn row(&mut self, y: u32, x0: u32, x1: u32, z_row: Depth, dz: Depth) {
        if y >= self.height {
            return;
        }
        let x1 = x1.min(self.width);
        for x in x0.min(x1)..x1 {
            self.pixel(x, y, span_depth(z_row, dz, x));
        }
    }

    /// One pixel at depth `z`.
    pub fn pixel(&mut self, x: u32, y: u32, z: Depth) {
        if x >= self.width || y >= self.height {
            return;
        }
        let at = y as usize * self.width as usize + x as usize;
        let held = self.held[at];
        if takes(z, held) {
            self.held[at] = z;
        } else if held.is_finite() && self.rounding_decided(z, held) {
            self.lost += 1;
        }
    }

    /// A newcomer at `z` lost to the holder at `held`: would the rule, in eye space, have
    /// given it the pixel, or were the two within [`ULPS`] ulps wider than the rule?
    fn rounding_decided(&self, z: Depth, held: Depth) -> bool {
        let form = &self.form;
        if takes(form.eye_depth(z), form.eye_depth(held)) {
            return true;
        }
        (z - held).abs() <= ULPS * held.abs() * f64::EPSILON && form.quantum(held) * ULPS > TIE
    }

    /// This frame's count, and a clear buffer for the next frame.
    fn end_frame(&mut self) -> u64 {
        self.held.fill(Depth::INFINITY);
        std::mem::take(&mut self.lost)
    }

    /// At the end of frame `frame` (from 0): its count, with the warning a stage prints
    /// after its name when there is any; the buffer is cleared for the next frame.
    pub fn finish_frame(&mut self, frame: u64) -> (u64, Option<String>) {
        let lost = self.end_frame();
        (lost, (lost > 0).then(|| self.message(frame, lost)))
    }

    /// The warning a stage prints (after its name) for a frame with `lost` such tests.
    pub fn message(&self, frame: u64, lost: u64) -> String {
        let form = self.form.name();
        format!(
            "frame {frame}: {lost} depth tests where a polygon nearer than the tie rule's \
             2^-30 lost to one within the {form} depth's quantum (up to {:.1e} of the \
             eye-space depth in this view volume): the earlier polygon shows there \
             (persp --zmode reciprocal keeps the rule at any hither/yon)",
            self.form.widest(ULPS),
        )
    }
}

/// What `--stats` adds to a resolving stage's line for `lost` such tests (nothing for 0).
pub fn stats_suffix(lost: u64) -> String {
    if lost > 0 {
        format!(", {lost} depth tests lost to the depth form's quantum")
    } else {
        String::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn projective(hither: f64, yon: f64) -> Option<DepthForm> {
        Some(DepthForm::Projective { hither, yon })
    }

    /// Reciprocal depth and eye-z need no watch at any hither/yon; projective depth does,
    /// even in the thesis's volume (K1 = 1, K2 = 30: the rule spans 29·2⁻³⁰ at yon).
    #[test]
    fn only_projective_depth_is_watched() {
        assert!(QuantumWatch::for_form(None, 4, 4).is_none());
        for hither in [1e-9, 1e-3, 1.0, 1e6] {
            let reciprocal = Some(DepthForm::Reciprocal { hither });
            assert!(QuantumWatch::for_form(reciprocal, 4, 4).is_none());
        }
        assert!(QuantumWatch::for_form(Some(DepthForm::EyeZ), 4, 4).is_none());
        assert!(QuantumWatch::for_form(projective(1.0, 30.0), 4, 4).is_some());
        assert!(QuantumWatch::for_form(projective(1e-3, 1e3), 4, 4).is_some());
    }

    /// Two parallel polygons near yon (K1 = 10⁻³, K2 = 10³, z_e = 880), the later one
    /// 3.4·10⁻⁷ of the depth nearer, far more than the rule's 2⁻³⁰: in projective depth
    /// the rule's width there is 8.8·10⁵·2⁻³⁰, so the nearer one loses every pixel:
    /// counted. A third polygon well in front takes its pixels: not counted; nor is a
    /// coplanar pair.
    #[test]
    fn a_near_yon_pair_in_projective_depth_is_counted() {
        let form = DepthForm::Projective {
            hither: 1e-3,
            yon: 1e3,
        };
        let device = |z_e: f64| (1.0 - 1e-3 / z_e) * (1e3 / (1e3 - 1e-3));
        let (far, near) = (device(880.0), device(880.0 * (1.0 - 3.4e-7)));
        assert!(!takes(near, far), "the z-buffer ties them");
        let mut watch = QuantumWatch::for_form(Some(form), 8, 3).unwrap();
        watch.row(0, 0, 8, far, 0.0);
        watch.row(0, 0, 8, near, 0.0);
        watch.row(1, 0, 8, far, 0.0);
        watch.row(1, 0, 8, device(100.0), 0.0);
        watch.row(2, 0, 8, far, 0.0);
        watch.row(2, 0, 8, far, 0.0);
        assert_eq!(watch.end_frame(), 8);
        // The next frame starts clear.
        watch.row(0, 0, 8, far, 0.0);
        assert_eq!(watch.end_frame(), 0);
        assert!(watch.message(3, 8).starts_with(
            "frame 3: 8 depth tests where a polygon nearer than the tie rule's 2^-30 lost to one within the projective depth's quantum (up to 9.3e-4"
        ), "{}", watch.message(3, 8));
    }
}
