//! # viewxf: the viewing transformation, world → eye (thesis chapter 1, Appendix 4)
//!
//! Every world point p becomes eye coordinates (x_e, y_e, z_e, w): its components along
//! the camera's axes, measured from the eye, with w = z_e·s/d (docs/DESIGN.md, "Coordinates and camera").
//! The camera itself (axes, w) is [`proto::camera::EyeFrame`]; this crate only applies it
//! to a stream's polygons, in place, so the stage allocates nothing of its own.

use proto::camera::EyeFrame;
use proto::{Polygon, Vertex};

/// World vertex `(x, y, z, 1)` → eye vertex `(x_e, y_e, z_e, w)`.
#[inline]
pub fn view_vertex(frame: &EyeFrame, v: Vertex) -> Vertex {
    frame.to_eye(v.truncate())
}

/// Transforms every vertex of a polygon in place. The colour is unchanged, and an empty
/// polygon stays empty (it keeps the polygon numbering, docs/DESIGN.md, "Grammar").
///
/// A polygon with vertex colours also gets its colour planes recorded (`shade`,
/// [`proto::shade::front_colour_planes`]) here, before any clipper or splitter changes its
/// vertices, so that every piece of it is shaded as the whole is (docs/DESIGN.md,
/// "Shading"); the colours themselves are left as they are. A polygon with a vertex at or
/// behind the eye gets the planes of its part in front of the hither plane `hither`
/// (K1), as zspec shades it.
#[inline]
pub fn view_polygon(frame: &EyeFrame, hither: f64, poly: &mut Polygon) {
    for v in &mut poly.vertices {
        *v = view_vertex(frame, *v);
    }
    if poly.is_shaded() {
        poly.shade = proto::shade::front_colour_planes(
            &poly.vertices,
            &poly.vertex_attrs,
            hither,
            frame.w_per_z,
        )
        .map(Box::new);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proto::camera::Camera;
    use proto::{DVec3, DVec4};

    #[test]
    fn thesis_camera_gives_z_e_equal_20_minus_z_w() {
        let frame = Camera::default().frame().unwrap();
        let mut p = Polygon::from_xyz([1, 2, 3], &[[-8.0, -4.0, 0.0], [0.0, 7.0, 4.0]]);
        view_polygon(&frame, 1.0, &mut p);
        assert_eq!(p.colour, [1, 2, 3]);
        assert_eq!(
            p.vertices,
            vec![
                DVec4::new(-8.0, -4.0, 20.0, 12.5),
                DVec4::new(0.0, 7.0, 16.0, 10.0)
            ]
        );
    }

    #[test]
    fn general_camera_axes() {
        // Eye on +x looking at the origin, up +y: the view direction is −x, so
        // x_e = normalize(f × up) = (−1,0,0)×(0,1,0) = (0,0,−1).
        let cam = Camera {
            eye: DVec3::new(10.0, 0.0, 0.0),
            ..Camera::default()
        };
        let frame = cam.frame().unwrap();
        let v = view_vertex(&frame, DVec4::new(0.0, 3.0, -2.0, 1.0));
        assert_eq!(v, DVec4::new(2.0, 3.0, 10.0, 6.25));
    }

    #[test]
    fn empty_polygon_stays_empty() {
        let frame = Camera::default().frame().unwrap();
        let mut p = Polygon::new([9, 9, 9], vec![]);
        view_polygon(&frame, 1.0, &mut p);
        assert_eq!(p, Polygon::new([9, 9, 9], vec![]));
    }
}
