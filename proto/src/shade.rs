//! Per-vertex colours and Gouraud shading (docs/DESIGN.md, "Shading").
//!
//! Gouraud's smooth shading gives every vertex of a polygon a colour and fills the
//! polygon with colours interpolated linearly across the *screen*, along the edges and
//! then along each span, as the sampling thesis's scan conversion does ("Gouraud and Phong
//! shading", its chapter 4). Linear on the screen means: each channel is a plane over
//! device coordinates, `A·X + B·Y + C·c + D = 0`, the same kind of plane as a polygon's
//! depth plane (Theoharis 1985, Appendix 3.3), and a pixel takes the plane's value at its
//! centre. For a triangle the plane is the one through its three (X, Y, c); for an n-gon it
//! is Newell's plane over the (X, Y, c) points, exact when the colours are themselves
//! planar, a fitted average otherwise, as the depth plane is fitted to a non-planar
//! polygon.
//!
//! So that every piece of a polygon the splitter tree cuts gets the whole polygon's colour
//! at every pixel, bit for bit (docs/DESIGN.md, "Why a split renders as the whole"), the
//! colour planes are computed once, in eye space over the screen position
//! `(u, v) = (x_e/w, y_e/w) = (a·x_s, y_s)` of each vertex, and carried as the polygon's `shade`
//! annotation, as the `plane` annotation carries its depth plane; `persp` carries them to
//! device coordinates. `viewxf` records them as it makes a polygon eye-space, from the
//! polygon before any clipping, so a clipped polygon is shaded as the whole was; and the
//! reference renderer, `zspec`, computes them with the same functions from the same
//! eye-space vertices.

use crate::geometry::newell_plane;
use crate::polygon::Vertex;
use glam::{DVec3, DVec4};

/// A vertex's colour: red, green and blue, each a number from 0 to 255, kept as f64
/// through the pipeline so that an interpolated colour is rounded once, at the pixel.
pub type VertexColour = DVec3;

/// A polygon's colour planes, one per channel (red, green, blue): `(A, B, C, D)` with
/// `A·x + B·y + C·c + D = 0`, over eye-space screen positions `(x_s, y_s)` or over device
/// coordinates `(X, Y)`, as the stream's space says.
pub type ColourPlanes = [DVec4; 3];

/// The colour planes of an eye-space polygon with per-vertex colours: each channel's
/// Newell plane over `(u, v, c)` at the vertices, where `(u, v) = (x_e/w, y_e/w)` is the
/// vertex's screen position `(a·x_s, y_s)` (a the aspect ratio, applied by
/// [`colour_planes_to_screen`]). `None` when a vertex is at or behind the eye (w ≤ 0: it
/// has no screen position; the polygon is shaded from its clipped vertices instead), when
/// the points span no area on the screen, or when anything is not finite.
pub fn eye_colour_planes(vertices: &[Vertex], colours: &[VertexColour]) -> Option<ColourPlanes> {
    if vertices.len() < 3 || colours.len() != vertices.len() {
        return None;
    }
    if !vertices.iter().all(|v| v.w > 0.0) {
        return None;
    }
    planes_over(vertices.iter().map(|v| (v.x / v.w, v.y / v.w)), colours)
}

/// The colour planes of a screen-space polygon fitted to its own vertices: Newell's plane
/// over `(X, Y, c)` per channel. For a stream written without `shade` (by hand, or an
/// eye-space stream that could not record one).
pub fn screen_colour_planes(vertices: &[Vertex], colours: &[VertexColour]) -> Option<ColourPlanes> {
    if vertices.len() < 3 || colours.len() != vertices.len() {
        return None;
    }
    planes_over(vertices.iter().map(|v| (v.x, v.y)), colours)
}

fn planes_over(
    positions: impl Iterator<Item = (f64, f64)> + Clone,
    colours: &[VertexColour],
) -> Option<ColourPlanes> {
    let mut planes = [DVec4::ZERO; 3];
    let mut points = Vec::with_capacity(colours.len());
    for (k, plane) in planes.iter_mut().enumerate() {
        points.clear();
        points.extend(
            positions
                .clone()
                .zip(colours)
                .map(|((x, y), c)| DVec3::new(x, y, c[k])),
        );
        let n = newell_plane(&points);
        if !(n.is_finite() && n.z != 0.0) {
            return None;
        }
        *plane = n;
    }
    Some(planes)
}

/// Carries eye-space colour planes (over `(u, v)`) to the device coordinates of a
/// `width`×`height` screen of aspect ratio `aspect`: `X = (u/a + 1)·W/2` and
/// `Y = (1 − v)·H/2`, so `u = a·(2X/W − 1)` and `v = 1 − 2Y/H`, and
/// `A·u + B·v + C·c + D = 0` becomes `(2aA/W)·X − (2B/H)·Y + C·c + (D − aA + B) = 0`.
/// `None` if anything is not finite.
pub fn colour_planes_to_screen(
    planes: &ColourPlanes,
    aspect: f64,
    width: u32,
    height: u32,
) -> Option<ColourPlanes> {
    let (w, h) = (width as f64, height as f64);
    let mut out = [DVec4::ZERO; 3];
    for (o, n) in out.iter_mut().zip(planes) {
        let au = aspect * n.x;
        *o = DVec4::new(2.0 * au / w, -2.0 * n.y / h, n.z, n.w - au + n.y);
        if !(o.is_finite() && o.z != 0.0) {
            return None;
        }
    }
    Some(out)
}

/// A polygon's colours across the screen, evaluated as its depth is: the value at the
/// centre of column 0 of a row, and the step from a column to the next.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shading {
    /// The device-space planes divided by their colour coefficient C: `(a, b, 1, d)` =
    /// `(A/C, B/C, 1, D/C)`, so that `c = −(a·X + b·Y + d)`.
    planes: ColourPlanes,
    /// −a per channel: the step along a row.
    step: DVec3,
}

impl Shading {
    /// The shading of device-space colour planes (C ≠ 0): each is divided by its C once,
    /// here (a plane already so divided is unchanged: x/1 = x).
    pub fn new(planes: ColourPlanes) -> Self {
        let planes = planes.map(|n| DVec4::new(n.x / n.z, n.y / n.z, 1.0, n.w / n.z));
        let step = DVec3::new(-planes[0].x + 0.0, -planes[1].x + 0.0, -planes[2].x + 0.0);
        Shading { planes, step }
    }

    /// A polygon's shading on the screen, if it has vertex colours: its recorded colour
    /// planes (`shade`, persp's), or else planes fitted to its own screen vertices
    /// ([`screen_colour_planes`]). A polygon whose colours give no plane (it has no area,
    /// and covers nothing) is shaded in its first vertex's colour.
    pub fn of(polygon: &crate::Polygon) -> Option<Shading> {
        if !polygon.is_shaded() {
            return None;
        }
        let planes = polygon
            .shade
            .as_deref()
            .copied()
            .or_else(|| screen_colour_planes(&polygon.vertices, &polygon.colours))
            .unwrap_or_else(|| {
                let c = polygon.colours[0];
                [0, 1, 2].map(|k| DVec4::new(0.0, 0.0, 1.0, -c[k]))
            });
        Some(Shading::new(planes))
    }

    /// The colour planes, divided by their colour coefficient (C = 1).
    pub fn planes(&self) -> &ColourPlanes {
        &self.planes
    }

    /// The colour (unrounded) at the centre of column 0 of `row`, and the step per column:
    /// column x has `c_row + x·dc` ([`shade_at`]).
    #[inline]
    pub fn row(&self, row: u32) -> (DVec3, DVec3) {
        let y = row as f64 + 0.5;
        let at = |n: DVec4| -(n.x * 0.5 + n.y * y + n.w) + 0.0;
        (
            DVec3::new(at(self.planes[0]), at(self.planes[1]), at(self.planes[2])),
            self.step,
        )
    }

    /// The finished colour of pixel (x, y).
    #[inline]
    pub fn at(&self, x: u32, y: u32) -> [u8; 3] {
        let (c_row, dc) = self.row(y);
        shade_at(c_row, dc, x)
    }
}

/// The finished colour of column `x` of a row whose colour at column 0 is `c_row`, stepping
/// `dc` per column: `c_row + x·dc` per channel (a multiplication and an addition, each
/// rounded, no fused multiply-add, as a span's depth), rounded to the nearest integer
/// (halves away from zero) and clamped to 0–255. Every renderer that shades calls this.
#[inline]
pub fn shade_at(c_row: DVec3, dc: DVec3, x: u32) -> [u8; 3] {
    let x = x as f64;
    let channel = |c: f64, d: f64| -> u8 {
        let v = c + x * d;
        // `as u8` saturates, and takes NaN to 0.
        v.round() as u8
    };
    [
        channel(c_row.x, dc.x),
        channel(c_row.y, dc.y),
        channel(c_row.z, dc.z),
    ]
}

/// A vertex colour from whole numbers (tests and scene generators).
pub fn colour(rgb: [u8; 3]) -> VertexColour {
    DVec3::new(rgb[0] as f64, rgb[1] as f64, rgb[2] as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::header::View;

    fn v(x: f64, y: f64, z: f64) -> Vertex {
        DVec4::new(x, y, z, 1.0)
    }

    #[test]
    fn a_triangles_planes_pass_through_its_vertex_colours() {
        let vertices = [v(10.0, 10.0, 0.0), v(90.0, 20.0, 0.0), v(30.0, 80.0, 0.0)];
        let colours = [
            DVec3::new(255.0, 0.0, 0.0),
            DVec3::new(0.0, 255.0, 0.0),
            DVec3::new(0.0, 0.0, 255.0),
        ];
        let shading = Shading::new(screen_colour_planes(&vertices, &colours).unwrap());
        // Pixel (9, 9)'s centre is (9.5, 9.5), near the red vertex; evaluate the exact
        // vertex by a plane's value at (10, 10) instead.
        for (p, c) in vertices.iter().zip(&colours) {
            for (k, n) in shading.planes.iter().enumerate() {
                let at = -(n.x * p.x + n.y * p.y + n.w) / n.z;
                assert!((at - c[k]).abs() < 1e-9, "{at} against {}", c[k]);
            }
        }
        // The centroid (43.33, 36.67) is grey 85 in every channel; pixel (43, 36) is at
        // (43.5, 36.5), within a level of it.
        let got = shading.at(43, 36);
        for c in got {
            assert!((84..=86).contains(&c), "{got:?}");
        }
    }

    #[test]
    fn rounding_is_to_nearest_and_clamped() {
        let c_row = DVec3::new(-3.0, 254.6, 10.49);
        let dc = DVec3::new(0.0, 1.0, 0.0);
        assert_eq!(shade_at(c_row, dc, 0), [0, 255, 10]);
        assert_eq!(shade_at(c_row, dc, 3), [0, 255, 10]);
        let nan = DVec3::new(f64::NAN, 0.5, 1.5);
        assert_eq!(shade_at(nan, DVec3::ZERO, 7), [0, 1, 2]);
    }

    #[test]
    fn eye_planes_carried_to_the_screen_agree_with_planes_fitted_there() {
        let view = View::default();
        let device = crate::camera::Device {
            width: 200,
            height: 100,
            view: View {
                aspect: 2.0,
                ..view
            },
        };
        let eye = [
            DVec4::new(-8.0, -4.0, 20.0, 12.5),
            DVec4::new(3.0, 7.0, 16.0, 10.0),
            DVec4::new(8.0, -4.0, 24.0, 15.0),
        ];
        let colours = [
            DVec3::new(200.0, 10.0, 30.0),
            DVec3::new(20.0, 250.0, 30.0),
            DVec3::new(90.0, 90.0, 240.0),
        ];
        let planes = eye_colour_planes(&eye, &colours).unwrap();
        let screen = colour_planes_to_screen(&planes, 2.0, 200, 100).unwrap();
        let projected: Vec<Vertex> = eye
            .iter()
            .map(|&p| {
                let (x, y) = device.project(p);
                v(x, y, 0.0)
            })
            .collect();
        let fitted = screen_colour_planes(&projected, &colours).unwrap();
        let (a, b) = (Shading::new(screen), Shading::new(fitted));
        for (x, y) in [(0, 0), (100, 50), (150, 20), (199, 99)] {
            let (ca, _) = a.row(y);
            let (cb, _) = b.row(y);
            let step = a.step * x as f64 - b.step * x as f64;
            assert!((ca - cb + step).abs().max_element() < 1e-9, "({x}, {y})");
        }
    }

    #[test]
    fn no_planes_behind_the_eye_or_without_area() {
        let c = [DVec3::ONE; 3];
        let behind = [
            DVec4::new(0.0, 0.0, 1.0, 0.625),
            DVec4::new(1.0, 0.0, -1.0, -0.625),
            DVec4::new(0.0, 1.0, 1.0, 0.625),
        ];
        assert_eq!(eye_colour_planes(&behind, &c), None);
        let line = [v(0.0, 0.0, 0.0), v(1.0, 1.0, 0.0), v(2.0, 2.0, 0.0)];
        assert_eq!(screen_colour_planes(&line, &c), None);
    }
}
