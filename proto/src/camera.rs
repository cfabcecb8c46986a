//! The viewing and perspective mappings of docs/DESIGN.md's "The Z specification", written once for
//! `viewxf`, `persp` and the exact reference.
//!
//! World coordinates are right-handed; eye coordinates are left-handed with the origin at
//! the eye, z_e along the view direction, x_e right and y_e up (thesis chapter 1). The
//! fourth eye coordinate is w = z_e·s/d: s is half the screen height and d the distance
//! from the eye to the screen, so that the clipping pyramid is |x_e| ≤ a·w, |y_e| ≤ w.

use crate::header::View;
// The parsers of a camera's numbers on a command line are `numbers`'s; named here too,
// where the stages look for them.
pub use crate::numbers::{parse_numbers, parse_size, parse_triple};
use glam::{DVec3, DVec4};

/// A camera: where the eye is, what it looks at, which way is up, and the screen's
/// half-height `s` and distance `d`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: DVec3,
    pub at: DVec3,
    pub up: DVec3,
    pub s: f64,
    pub d: f64,
}

impl Default for Camera {
    /// The thesis's camera (Appendix 4): eye at (0, 0, D = 20) looking at the origin,
    /// up +y, s = 10, d = 16. Then x_e = x_w, y_e = y_w, z_e = 20 − z_w exactly.
    fn default() -> Self {
        Camera {
            eye: DVec3::new(0.0, 0.0, 20.0),
            at: DVec3::ZERO,
            up: DVec3::Y,
            s: 10.0,
            d: 16.0,
        }
    }
}

/// The eye frame of a camera: its axes in world coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EyeFrame {
    pub eye: DVec3,
    pub x_axis: DVec3,
    pub y_axis: DVec3,
    pub z_axis: DVec3,
    /// s/d: w = z_e · s/d.
    pub w_per_z: f64,
}

impl Camera {
    /// The eye frame: f = normalize(at − eye), x = normalize(f × up), y = x × f, z = f.
    /// Fails when the camera cannot define a frame (eye = at, up parallel to the view
    /// direction, s or d not positive).
    pub fn frame(&self) -> Result<EyeFrame, String> {
        let f = self.at - self.eye;
        if f.length_squared() <= 0.0 || !f.is_finite() {
            return Err("the eye and the point looked at must differ".into());
        }
        let f = f.normalize();
        let x = f.cross(self.up);
        if x.length_squared() <= 0.0 || !x.is_finite() {
            return Err("the up vector must not be parallel to the view direction".into());
        }
        if !(self.s > 0.0 && self.d > 0.0 && self.s.is_finite() && self.d.is_finite()) {
            return Err(format!(
                "s = {} and d = {} must be positive",
                self.s, self.d
            ));
        }
        let x = x.normalize();
        Ok(EyeFrame {
            eye: self.eye,
            x_axis: x,
            y_axis: x.cross(f),
            z_axis: f,
            w_per_z: self.s / self.d,
        })
    }
}

impl EyeFrame {
    /// World point → eye coordinates `(x_e, y_e, z_e, w)`.
    #[inline]
    pub fn to_eye(&self, p: DVec3) -> DVec4 {
        let r = p - self.eye;
        let z = r.dot(self.z_axis);
        DVec4::new(r.dot(self.x_axis), r.dot(self.y_axis), z, z * self.w_per_z)
    }
}

/// The perspective and device mapping of a `width`×`height` screen:
/// x_s = x_e/(a·w), y_s = y_e/w; X = (x_s + 1)·W/2, Y = (1 − y_s)·H/2 (row 0 at the top).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Device {
    pub width: u32,
    pub height: u32,
    pub view: View,
}

impl Device {
    /// Device coordinates (X, Y) of an eye-space point in front of the eye (w > 0).
    #[inline]
    pub fn project(&self, v: DVec4) -> (f64, f64) {
        let xs = v.x / (self.view.aspect * v.w);
        let ys = v.y / v.w;
        (
            (xs + 1.0) * (self.width as f64 * 0.5),
            (1.0 - ys) * (self.height as f64 * 0.5),
        )
    }

    /// Projective depth (docs/DESIGN.md, "Depth"), z_s = (1 − K1/z_e)·K2/(K2 − K1): 0 at the hither
    /// plane, 1 at the yon plane, and an affine function of 1/z_e, so that planes stay
    /// planes and depth interpolates linearly across the screen.
    #[inline]
    pub fn projective_depth(&self, z_e: f64) -> f64 {
        let (k1, k2) = (self.view.hither, self.view.yon);
        (1.0 - k1 / z_e) * (k2 / (k2 - k1))
    }

    /// The reciprocal depth D = −K1/z_e: −1 at the hither plane, −K1/K2 at yon, smaller
    /// nearer. Like the projective depth it is an affine function of 1/z_e, so planes
    /// stay planes on the screen; unlike it, it is not crowded against a constant far
    /// from the eye, so an f64 holds it to 2⁻⁵³ of itself at every depth, which is what
    /// the tie rule needs ([`crate::depth`]). One correctly rounded division.
    #[inline]
    pub fn reciprocal_depth(&self, z_e: f64) -> f64 {
        -self.view.hither / z_e
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thesis_camera_is_exact() {
        let f = Camera::default().frame().unwrap();
        assert_eq!(
            f.to_eye(DVec3::new(-9.0, 5.0, 4.0)),
            DVec4::new(-9.0, 5.0, 16.0, 10.0)
        );
        assert_eq!(
            f.to_eye(DVec3::new(7.0, -7.0, -4.0)),
            DVec4::new(7.0, -7.0, 24.0, 15.0)
        );
    }

    #[test]
    fn degenerate_cameras_are_refused() {
        let c = Camera {
            at: Camera::default().eye,
            ..Camera::default()
        };
        assert!(c.frame().is_err());
        let c = Camera {
            up: DVec3::Z,
            ..Camera::default()
        };
        assert!(c.frame().is_err());
    }

    #[test]
    fn device_mapping_and_depth() {
        let dev = Device {
            width: 500,
            height: 500,
            view: View::default(),
        };
        // x_s = -0.9, y_s = 0.5 at w = 10.
        assert_eq!(
            dev.project(DVec4::new(-9.0, 5.0, 16.0, 10.0)),
            (24.999999999999993, 125.0)
        );
        assert_eq!(dev.projective_depth(1.0), 0.0);
        assert_eq!(dev.projective_depth(30.0), 1.0);
    }
}
