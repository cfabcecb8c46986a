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

use crate::newell::newell_plane;
use crate::polygon::Vertex;
pub use crate::polygon::{ColourPlanes, VertexAttr};
use glam::{DVec3, DVec4};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The colour planes of an eye-space polygon with per-vertex colours: each channel's
/// Newell plane over `(u, v, c)` at the vertices, where `(u, v) = (x_e/w, y_e/w)` is the
/// vertex's screen position `(a·x_s, y_s)` (a the aspect ratio, applied by
/// [`colour_planes_to_screen`]). `None` when a vertex is at or behind the eye (w ≤ 0: it
/// has no screen position; the polygon is shaded from its clipped vertices instead), when
/// the points span no area on the screen, or when anything is not finite.
pub fn eye_colour_planes(vertices: &[Vertex], colours: &[VertexAttr]) -> Option<ColourPlanes> {
    if vertices.len() < 3 || colours.len() != vertices.len() {
        return None;
    }
    if !vertices.iter().all(|v| v.w > 0.0) {
        return None;
    }
    planes_over(vertices.iter().map(|v| (v.x / v.w, v.y / v.w)), colours)
}

/// The colour planes the pipeline and the reference both give an eye-space polygon
/// (docs/DESIGN.md, "Shading"): [`eye_colour_planes`] of its vertices, or, for a polygon
/// with a vertex at or behind the eye (which has no screen position there), of its part in
/// front of the hither plane z_e = K1 ([`cut_coloured_at_hither`]), the attributes at a
/// cut interpolated as the positions are. viewxf records these before any clipper sees
/// the polygon and zspec computes them from the same vertices with the same function, so
/// the two shade such a polygon alike; fitted instead to whatever the clippers leave, a
/// polygon whose attributes are not coplanar (four random normals) got other planes.
pub fn front_colour_planes(
    vertices: &[Vertex],
    colours: &[VertexAttr],
    hither: f64,
    w_per_z: f64,
) -> Option<ColourPlanes> {
    eye_colour_planes(vertices, colours).or_else(|| {
        if colours.len() != vertices.len() || vertices.iter().all(|v| v.z >= hither) {
            return None;
        }
        let (front, attrs) = cut_coloured_at_hither(vertices, colours, hither, w_per_z);
        eye_colour_planes(&front, &attrs)
    })
}

/// Cuts an eye-space polygon and its vertex attributes to the half-space z_e ≥ K1 (one
/// plane, inline: each edge keeps its inside end and gains the crossing point when it
/// leaves or enters), a crossing's attributes interpolated with the position's parameter
/// and kept between the edge's ends.
///
/// A crossing point gets w = K1·s/d (`w_per_z`) from the definition of w, not by
/// interpolation: an edge from 1e30 behind the eye to 1e30 in front meets the plane at
/// t ≈ ½, where interpolating w from ±6e29 leaves nothing but rounding
/// (examples/degenerate/huge-through-eye.txt).
pub fn cut_coloured_at_hither(
    vertices: &[Vertex],
    colours: &[VertexAttr],
    k1: f64,
    w_per_z: f64,
) -> (Vec<Vertex>, Vec<VertexAttr>) {
    let n = vertices.len();
    let (mut out, mut out_colours) = (Vec::with_capacity(n + 2), Vec::with_capacity(n + 2));
    for i in 0..n {
        let (a, b) = (vertices[i], vertices[(i + 1) % n]);
        let (ca, cb) = (colours[i], colours[(i + 1) % n]);
        if a.z >= k1 {
            out.push(a);
            out_colours.push(ca);
        }
        if (a.z >= k1) != (b.z >= k1) {
            // From the inside end, as the clippers interpolate (`Plane::crossing`): the
            // same point whichever way the edge is walked, and where the outside end is
            // huge (1e200 behind the eye) and the inside one near, a point within
            // rounding of the near one's size, not of the huge one's.
            let ((from, c_from), (to, c_to)) = if a.z >= k1 {
                ((a, ca), (b, cb))
            } else {
                ((b, cb), (a, ca))
            };
            let (p, t) = crossing_at_depth(from, to, k1, w_per_z);
            out.push(p);
            out_colours.push((c_from + (c_to - c_from) * t).clamp(ca.min(cb), ca.max(cb)));
        }
    }
    (out, out_colours)
}

/// Where the eye-space edge from `from` (its inside end) to `to` meets the plane
/// z_e = `k`, and the parameter t of that point along it: interpolated from `from`, or,
/// where the ends are too far out for interpolation to keep the point's digits, computed
/// exactly ([`crate::exact`]); then put on the plane, z_e = k and w = k·s/d (`w_per_z`)
/// from the definition of w. The hither cut's crossing here and the reference's yon cut.
pub fn crossing_at_depth(from: Vertex, to: Vertex, k: f64, w_per_z: f64) -> (Vertex, f64) {
    let t = crossing_at(k, from.z, to.z);
    let mut p = lerp(from, to, t);
    if crate::exact::interpolation_lost_digits(from, to, p) {
        let plane = DVec4::new(0.0, 0.0, 1.0, 0.0);
        p = crate::exact::crossing(from, to, plane, -k).unwrap_or(p);
    }
    p.z = k;
    p.w = k * w_per_z;
    (p, t)
}

/// The parameter t at which z goes from `a` to `b` through `k`: `(k − a)/(b − a)`, or,
/// where that overflows (ends near ±f64::MAX), the same with every term halved.
pub fn crossing_at(k: f64, a: f64, b: f64) -> f64 {
    let t = (k - a) / (b - a);
    if t.is_finite() {
        t
    } else {
        (k * 0.5 - a * 0.5) / (b * 0.5 - a * 0.5)
    }
}

/// `a + (b − a)·t`, or, where that overflows, `a·(1 − t) + b·t`.
pub fn lerp(a: DVec4, b: DVec4, t: f64) -> DVec4 {
    let p = a + (b - a) * t;
    if p.is_finite() {
        p
    } else {
        a * (1.0 - t) + b * t
    }
}

/// The colour planes of a screen-space polygon fitted to its own vertices: Newell's plane
/// over `(X, Y, c)` per channel. For a stream written without `shade` (by hand, or an
/// eye-space stream that could not record one).
pub fn screen_colour_planes(vertices: &[Vertex], colours: &[VertexAttr]) -> Option<ColourPlanes> {
    if vertices.len() < 3 || colours.len() != vertices.len() {
        return None;
    }
    planes_over(vertices.iter().map(|v| (v.x, v.y)), colours)
}

/// Positions beyond this are scaled down before Newell's sums, which multiply two of
/// them (u·v) and would overflow past about 1e154.
const LARGE_POSITION: f64 = 1e150;

/// Newell's plane over `(x, y, c)` per channel. Positions of ordinary size are used as
/// they are, bit for bit; where one is beyond [`LARGE_POSITION`] (a triangle with
/// vertices at ±1e308 seen from close by), every position is first divided by a power of
/// two s, which is exact, and the plane A'·(x/s) + B'·(y/s) + C·c + D = 0 found there is
/// the plane (A'/s)·x + (B'/s)·y + C·c + D = 0: the same plane, where the unscaled sums
/// gave none and each renderer fell back to a colour of its own.
fn planes_over(
    positions: impl Iterator<Item = (f64, f64)> + Clone,
    colours: &[VertexAttr],
) -> Option<ColourPlanes> {
    let largest = positions
        .clone()
        .map(|(x, y)| x.abs().max(y.abs()))
        .fold(0.0, f64::max);
    let scale = if largest > LARGE_POSITION && largest.is_finite() {
        2f64.powi((largest.log2().ceil() as i32).min(1023))
    } else {
        1.0
    };
    let mut planes = [DVec4::ZERO; 3];
    let mut points = Vec::with_capacity(colours.len());
    for (k, plane) in planes.iter_mut().enumerate() {
        points.clear();
        points.extend(
            positions
                .clone()
                .zip(colours)
                .map(|((x, y), c)| DVec3::new(x / scale, y / scale, c[k])),
        );
        let mut n = newell_plane(&points);
        n.x /= scale;
        n.y /= scale;
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
///
/// Gouraud shading interpolates colours; Phong shading interpolates normals the same
/// way (the planes are then the normal's x, y and z over the screen) and lights each
/// pixel by [`Lighting`] (the sampling thesis, "A Comparison of Phong and Gouraud
/// Shading": the illumination "put off until the very end").
#[derive(Clone, Debug, PartialEq)]
pub struct Shading {
    /// The device-space planes divided by their colour coefficient C: `(a, b, 1, d)` =
    /// `(A/C, B/C, 1, D/C)`, so that `c = −(a·X + b·Y + d)`.
    planes: ColourPlanes,
    /// −a per channel: the step along a row.
    step: DVec3,
    /// For Phong shading, the polygon's own colour and the stream's lighting.
    phong: Option<Phong>,
}

/// What Phong shading needs beyond the interpolated normal.
#[derive(Clone, Debug, PartialEq)]
struct Phong {
    base: DVec3,
    lighting: Arc<Lighting>,
}

impl Shading {
    /// The shading of device-space colour planes (C ≠ 0): each is divided by its C once,
    /// here (a plane already so divided is unchanged: x/1 = x).
    pub fn new(planes: ColourPlanes) -> Self {
        let planes = planes.map(|n| DVec4::new(n.x / n.z, n.y / n.z, 1.0, n.w / n.z));
        let step = DVec3::new(-planes[0].x + 0.0, -planes[1].x + 0.0, -planes[2].x + 0.0);
        Shading {
            planes,
            step,
            phong: None,
        }
    }

    /// The same planes read as a normal's, each pixel lit by `lighting` from the base
    /// colour `base` (Phong shading); unchanged when `lighting` is `None` (Gouraud).
    pub fn lit(self, lighting: Option<&Arc<Lighting>>, base: [u8; 3]) -> Self {
        Shading {
            phong: lighting.map(|l| Phong {
                base: colour(base),
                lighting: Arc::clone(l),
            }),
            ..self
        }
    }

    /// A polygon's shading on the screen, if it has per-vertex values: its recorded
    /// planes (`shade`, persp's), or else planes fitted to its own screen vertices
    /// ([`screen_colour_planes`]). A polygon whose values give no plane (it has no area,
    /// and covers nothing) is shaded by its first vertex's. With `lighting` (the stream
    /// says `vertex-normals`) the values are normals, lit per pixel from the polygon's
    /// colour; without, colours.
    pub fn of(polygon: &crate::Polygon, lighting: Option<&Arc<Lighting>>) -> Option<Shading> {
        if !polygon.is_shaded() {
            return None;
        }
        let planes = polygon
            .shade
            .as_deref()
            .copied()
            .or_else(|| screen_colour_planes(&polygon.vertices, &polygon.vertex_attrs))
            .unwrap_or_else(|| {
                let c = polygon.vertex_attrs[0];
                [0, 1, 2].map(|k| DVec4::new(0.0, 0.0, 1.0, -c[k]))
            });
        Some(Shading::new(planes).lit(lighting, polygon.colour))
    }

    /// The colour planes, divided by their colour coefficient (C = 1).
    pub fn planes(&self) -> &ColourPlanes {
        &self.planes
    }

    /// The values (unrounded) at the centre of column 0 of `row`, and the step per column:
    /// column x has `c_row + x·dc` ([`ShadeRow::at`]).
    #[inline]
    pub fn row(&self, row: u32) -> ShadeRow<'_> {
        let y = row as f64 + 0.5;
        let at = |n: DVec4| -(n.x * 0.5 + n.y * y + n.w) + 0.0;
        ShadeRow {
            c_row: DVec3::new(at(self.planes[0]), at(self.planes[1]), at(self.planes[2])),
            dc: self.step,
            phong: self.phong.as_ref(),
        }
    }

    /// The finished colour of pixel (x, y).
    #[inline]
    pub fn at(&self, x: u32, y: u32) -> [u8; 3] {
        self.row(y).at(x)
    }
}

/// A row of a polygon's shading: the values at column 0 and their step per column.
#[derive(Clone, Copy, Debug)]
pub struct ShadeRow<'a> {
    pub c_row: DVec3,
    pub dc: DVec3,
    phong: Option<&'a Phong>,
}

impl ShadeRow<'_> {
    /// A row of Gouraud shading: colour `c_row` at column 0, stepping `dc` a column.
    pub fn gouraud(c_row: DVec3, dc: DVec3) -> Self {
        ShadeRow {
            c_row,
            dc,
            phong: None,
        }
    }

    /// The finished colour of column `x`: Gouraud's interpolated colour
    /// ([`shade_at`]), or Phong's: the interpolated normal `c_row + x·dc` (the same
    /// arithmetic), normalized and lit ([`Lighting::colour`]), rounded and clamped as
    /// Gouraud's is. Every renderer that shades calls this.
    #[inline]
    pub fn at(&self, x: u32) -> [u8; 3] {
        match self.phong {
            None => shade_at(self.c_row, self.dc, x),
            Some(p) => {
                let n = interpolate(self.c_row, self.dc, x).normalize_or_zero();
                let c = p.lighting.colour(p.base, n);
                [round(c.x), round(c.y), round(c.z)]
            }
        }
    }
}

/// `c_row + x·dc` per channel: a multiplication and an addition, each rounded, no fused
/// multiply-add, as a span's depth.
#[inline]
fn interpolate(c_row: DVec3, dc: DVec3, x: u32) -> DVec3 {
    let x = x as f64;
    DVec3::new(c_row.x + x * dc.x, c_row.y + x * dc.y, c_row.z + x * dc.z)
}

/// A channel rounded to the nearest integer (halves away from zero) and clamped to 0–255
/// (`as u8` saturates, and takes NaN to 0).
#[inline]
fn round(v: f64) -> u8 {
    v.round() as u8
}

/// The finished colour of column `x` of a row whose colour at column 0 is `c_row`, stepping
/// `dc` per column: `c_row + x·dc` per channel (a multiplication and an addition, each
/// rounded, no fused multiply-add, as a span's depth), rounded to the nearest integer
/// (halves away from zero) and clamped to 0–255 (Gouraud shading).
#[inline]
pub fn shade_at(c_row: DVec3, dc: DVec3, x: u32) -> [u8; 3] {
    let c = interpolate(c_row, dc, x);
    [round(c.x), round(c.y), round(c.z)]
}

/// At most this many lights in a stream's lighting (OpenGL's minimum, `GL_MAX_LIGHTS`):
/// the header keeps them in a fixed array, so that it stays a plain value.
pub const MAX_LIGHTS: usize = 8;

/// The illumination of a scene: an ambient term, directional lights and a specular term,
/// by Phong's model as the sampling thesis describes it ("a linear combination of the
/// diffuse and specular components", its section on Gouraud and Phong shading). Every
/// direction is a unit vector in world coordinates, *towards* the light or the viewer, and
/// both are at infinity (as OpenGL's default, non-local viewer): so the light a surface
/// gets depends on its normal alone, and normals need not follow the camera into eye space
/// (a rotation changes no dot product).
///
/// A surface of unit normal n and base colour C is lit to
/// `C·(ambient + Σ I·|n·l|) + 255·specular·Σ I·max(0, r·v)^exponent`,
/// with `r = 2(n'·l)n' − l` the light reflected about n' (n turned to face the viewer,
/// and no highlight where n'·l ≤ 0). The diffuse term is two-sided, |n·l|, so a face is
/// lit from either side (a model's faces may be wound either way); the highlight is white.
/// `scene` lights vertices with it (Gouraud shading) and the z-buffer lights pixels with it
/// (Phong shading), so the two differ only in where the light is sampled.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Lighting {
    /// The ambient term, lit everywhere.
    pub ambient: f64,
    /// The specular coefficient (0: none).
    pub specular: f64,
    /// Phong's exponent: the larger, the smaller and sharper the highlight.
    pub exponent: f64,
    viewer: [f64; 3],
    count: u8,
    directions: [[f64; 3]; MAX_LIGHTS],
    intensities: [f64; MAX_LIGHTS],
}

impl Default for Lighting {
    /// One light up, right and towards the viewer, (1, 1.5, 2), of intensity 0.7; ambient
    /// 0.3; no highlight; the viewer on +z (the default camera's side).
    fn default() -> Self {
        let mut lighting = Lighting {
            ambient: 0.3,
            specular: 0.0,
            exponent: 20.0,
            viewer: [0.0, 0.0, 1.0],
            count: 0,
            directions: [[0.0; 3]; MAX_LIGHTS],
            intensities: [0.0; MAX_LIGHTS],
        };
        lighting
            .set_lights(&[(DVec3::new(1.0, 1.5, 2.0).normalize(), 0.7)])
            .expect("one light");
        lighting
    }
}

impl Lighting {
    /// The lights: each a unit direction towards it and an intensity.
    pub fn lights(&self) -> impl Iterator<Item = (DVec3, f64)> + '_ {
        self.directions[..self.count as usize]
            .iter()
            .zip(&self.intensities)
            .map(|(d, &i)| (DVec3::from_array(*d), i))
    }

    /// The unit direction towards the viewer.
    pub fn viewer(&self) -> DVec3 {
        DVec3::from_array(self.viewer)
    }

    /// Replaces the lights: 1 to [`MAX_LIGHTS`] of them, each a direction (normalized
    /// here) and a finite intensity ≥ 0.
    pub fn set_lights(&mut self, lights: &[(DVec3, f64)]) -> Result<(), String> {
        if lights.is_empty() || lights.len() > MAX_LIGHTS {
            return Err(format!(
                "{} lights: a lighting has 1 to {MAX_LIGHTS}",
                lights.len()
            ));
        }
        for (k, &(d, i)) in lights.iter().enumerate() {
            let Some(d) = unit(d) else {
                return Err(format!("light {k} has no direction (0 0 0, or not finite)"));
            };
            if !(i.is_finite() && i >= 0.0) {
                return Err(format!("light {k}'s intensity {i} must be 0 or more"));
            }
            self.directions[k] = d.to_array();
            self.intensities[k] = i;
        }
        self.directions[lights.len()..].fill([0.0; 3]);
        self.intensities[lights.len()..].fill(0.0);
        self.count = lights.len() as u8;
        Ok(())
    }

    /// Sets the direction towards the viewer (normalized here).
    pub fn set_viewer(&mut self, v: DVec3) -> Result<(), String> {
        let v = unit(v)
            .ok_or_else(|| "the viewer has no direction (0 0 0, or not finite)".to_string())?;
        self.viewer = v.to_array();
        Ok(())
    }

    /// Sets the ambient term: a finite number, 0 or more.
    pub fn set_ambient(&mut self, ambient: f64) -> Result<(), String> {
        self.ambient = at_least(ambient, 0.0, "ambient term")?;
        Ok(())
    }

    /// Sets the highlight: its coefficient (finite, 0 or more) and Phong's exponent
    /// (finite, 1 or more).
    pub fn set_specular(&mut self, specular: f64, exponent: f64) -> Result<(), String> {
        self.specular = at_least(specular, 0.0, "specular coefficient")?;
        self.exponent = at_least(exponent, 1.0, "specular exponent")?;
        Ok(())
    }

    /// Whether every number is in range: what a reader checks before trusting a header.
    pub fn check(&self) -> Result<(), String> {
        let count = self.count as usize;
        if count > MAX_LIGHTS {
            return Err(format!("{count} lights: a lighting has 1 to {MAX_LIGHTS}"));
        }
        let mut copy = *self;
        let lights: Vec<_> = self.lights().collect();
        copy.set_lights(&lights)?;
        copy.set_viewer(self.viewer())?;
        if copy != *self {
            return Err(
                "a light's or the viewer's direction is not a unit vector, or an \
                        unused light is not zero"
                    .to_string(),
            );
        }
        copy.set_ambient(self.ambient)?;
        copy.set_specular(self.specular, self.exponent)?;
        Ok(())
    }

    /// The diffuse factor for the unit normal `n`: ambient + Σ I·|n·l| (the ambient term
    /// alone for a zero normal).
    pub fn diffuse(&self, n: DVec3) -> f64 {
        self.ambient
            + self
                .lights()
                .map(|(l, intensity)| intensity * n.dot(l).abs())
                .sum::<f64>()
    }

    /// The specular term for the unit normal `n`: specular·Σ I·max(0, r·v)^exponent.
    pub fn highlight(&self, n: DVec3) -> f64 {
        if self.specular == 0.0 {
            return 0.0;
        }
        let v = self.viewer();
        let n = if n.dot(v) < 0.0 { -n } else { n };
        let sum: f64 = self
            .lights()
            .map(|(l, intensity)| {
                let nl = n.dot(l);
                if nl <= 0.0 {
                    return 0.0;
                }
                let rv = (2.0 * nl * n - l).dot(v);
                if rv <= 0.0 {
                    0.0
                } else {
                    intensity * rv.powf(self.exponent)
                }
            })
            .sum();
        self.specular * sum
    }

    /// The colour `base` (0–255 per channel) lit for the unit normal `n`, unrounded and
    /// unclamped: `base·diffuse(n) + 255·highlight(n)`.
    pub fn colour(&self, base: DVec3, n: DVec3) -> DVec3 {
        let lit = base * self.diffuse(n);
        let h = self.highlight(n);
        if h == 0.0 {
            lit
        } else {
            lit + DVec3::splat(255.0 * h)
        }
    }
}

/// `v` where it is finite and at least `min`, else why not.
fn at_least(v: f64, min: f64, what: &str) -> Result<f64, String> {
    if v.is_finite() && v >= min {
        Ok(v)
    } else {
        Err(format!("the {what} {v} must be {min} or more"))
    }
}

/// `d` as a unit vector: as it is where its length is 1 to within rounding (so that a
/// direction normalized once, written and read back, keeps its bits), else normalized;
/// `None` for a zero or non-finite vector.
fn unit(d: DVec3) -> Option<DVec3> {
    if d.is_finite() && (d.length_squared() - 1.0).abs() <= 8.0 * f64::EPSILON {
        Some(d)
    } else {
        d.try_normalize()
    }
}

/// A vertex colour from whole numbers (tests and scene generators).
pub fn colour(rgb: [u8; 3]) -> VertexAttr {
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
            let ca = a.row(y).c_row;
            let cb = b.row(y).c_row;
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

    #[test]
    fn lighting_by_phongs_model() {
        let mut l = Lighting::default();
        l.set_lights(&[(DVec3::Z, 0.5)]).unwrap();
        l.ambient = 0.2;
        let base = DVec3::new(200.0, 100.0, 0.0);
        // Facing the light: 0.2 + 0.5; turned away it is lit the same (two-sided).
        assert_eq!(l.colour(base, DVec3::Z), base * 0.7);
        assert_eq!(l.colour(base, -DVec3::Z), base * 0.7);
        // Edge-on: the ambient term alone.
        assert_eq!(l.colour(base, DVec3::X), base * 0.2);
        // A highlight of 0.5·0.5·(r·v)^N: r = v where n halves l and v.
        l.specular = 0.5;
        l.exponent = 10.0;
        l.set_lights(&[(DVec3::new(1.0, 0.0, 1.0), 1.0)]).unwrap();
        let half = DVec3::new(1.0, 0.0, 2f64.sqrt() + 1.0).normalize();
        assert!((l.highlight(half) - 0.5).abs() < 1e-12);
        // Seen from behind, the normal is turned to the viewer first.
        assert!((l.highlight(-half) - 0.5).abs() < 1e-12);
        // A light behind the surface makes no highlight.
        assert_eq!(l.highlight(DVec3::new(-1.0, 0.0, 0.0)), 0.0);
        assert!(l.check().is_ok());
    }

    #[test]
    fn directions_normalized_once_keep_their_bits() {
        let mut l = Lighting::default();
        let d = DVec3::new(1.0, 1.5, 2.0).normalize();
        l.set_lights(&[(d, 1.0)]).unwrap();
        assert_eq!(l.lights().next().unwrap().0, d);
        l.set_lights(&[(DVec3::new(0.0, 3.0, 0.0), 1.0)]).unwrap();
        assert_eq!(l.lights().next().unwrap().0, DVec3::Y);
        assert!(l.set_lights(&[]).is_err());
        assert!(l.set_lights(&[(DVec3::X, 1.0); MAX_LIGHTS + 1]).is_err());
        assert!(l.set_lights(&[(DVec3::X, -1.0)]).is_err());
        assert!(l.set_viewer(DVec3::ZERO).is_err());
    }

    #[test]
    fn phong_rows_light_the_interpolated_normal() {
        let mut l = Lighting::default();
        l.set_lights(&[(DVec3::Z, 1.0)]).unwrap();
        l.ambient = 0.0;
        // Normal planes over the screen: n = (X − 1.5, 0, 1) at X (planes
        // c = −(a·X + b·Y + d) with a = −1 for x, constant 1 for z).
        let planes = [
            DVec4::new(-1.0, 0.0, 1.0, 1.5),
            DVec4::new(0.0, 0.0, 1.0, 0.0),
            DVec4::new(0.0, 0.0, 1.0, -1.0),
        ];
        let shading = Shading::new(planes).lit(Some(&Arc::new(l)), [100, 200, 255]);
        let row = shading.row(0);
        // Column 2's centre X = 2.5: n = (1, 0, 1), so |n̂·z| = 1/√2.
        let k = 0.5f64.sqrt();
        let want = [100.0 * k, 200.0 * k, 255.0 * k].map(|c: f64| c.round() as u8);
        assert_eq!(row.at(2), want);
        assert_eq!(shading.at(2, 0), want);
        // Without the lighting, the same planes are colours.
        let gouraud = Shading::new(planes);
        assert_eq!(gouraud.at(2, 0), [1, 0, 1]);
    }

    #[test]
    fn a_polygon_through_the_eye_is_shaded_from_its_part_in_front_of_hither() {
        // Four vertex colours not on one plane, one vertex behind the eye: the planes are
        // those of the hither cut, whatever clippers later leave of the polygon.
        let eye = [
            DVec4::new(-4.0, -3.0, 10.0, 6.25),
            DVec4::new(4.0, -3.0, 10.0, 6.25),
            DVec4::new(4.0, 3.0, -5.0, -3.125),
            DVec4::new(-4.0, 3.0, 12.0, 7.5),
        ];
        let colours = [
            DVec3::new(255.0, 0.0, 0.0),
            DVec3::new(0.0, 255.0, 0.0),
            DVec3::new(0.0, 0.0, 255.0),
            DVec3::new(255.0, 255.0, 0.0),
        ];
        assert_eq!(eye_colour_planes(&eye, &colours), None);
        let (front, attrs) = cut_coloured_at_hither(&eye, &colours, 1.0, 0.625);
        assert_eq!(front.len(), 5);
        assert!(front.iter().all(|v| v.z >= 1.0 && v.w > 0.0));
        let planes = front_colour_planes(&eye, &colours, 1.0, 0.625).expect("planes");
        assert_eq!(Some(planes), eye_colour_planes(&front, &attrs));
        // A polygon wholly in front keeps the planes of its own vertices.
        let ahead = [eye[0], eye[1], eye[3]];
        let c3 = [colours[0], colours[1], colours[3]];
        assert_eq!(
            front_colour_planes(&ahead, &c3, 1.0, 0.625),
            eye_colour_planes(&ahead, &c3)
        );
    }

    #[test]
    fn colours_over_huge_positions_still_have_their_plane() {
        // A triangle at ±1e308 seen from z_e = 20: its screen positions are about 1e307,
        // and u·v overflows Newell's sums unless they are scaled first.
        let eye = [
            DVec4::new(-1e308, -1e308, 20.0, 12.5),
            DVec4::new(1e308, -1e308, 20.0, 12.5),
            DVec4::new(0.0, 1e308, 20.0, 12.5),
        ];
        let colours = [
            DVec3::new(10.0, 20.0, 30.0),
            DVec3::new(50.0, 20.0, 30.0),
            DVec3::new(10.0, 60.0, 30.0),
        ];
        let planes = eye_colour_planes(&eye, &colours).expect("planes");
        for (v, c) in eye.iter().zip(&colours) {
            let (u, w) = (v.x / v.w, v.y / v.w);
            for k in 0..3 {
                let p = planes[k];
                let at = -(p.x * u + p.y * w + p.w) / p.z;
                assert!((at - c[k]).abs() < 1e-9, "channel {k}: {at} not {}", c[k]);
            }
        }
        // Positions of ordinary size are not scaled: the plane is Newell's, bit for bit.
        let small = eye.map(|v| DVec4::new(v.x * 1e-300, v.y * 1e-300, v.z, v.w));
        let direct: Vec<DVec3> = small
            .iter()
            .zip(&colours)
            .map(|(v, c)| DVec3::new(v.x / v.w, v.y / v.w, c[0]))
            .collect();
        assert_eq!(
            eye_colour_planes(&small, &colours).unwrap()[0],
            newell_plane(&direct)
        );
    }
}
