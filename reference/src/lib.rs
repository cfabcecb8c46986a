//! reference: the exact reference renderer, docs/DESIGN.md's "The Z specification"
//! evaluated directly; the `zspec` binary (bins/zspec) is its command line.
//!
//! The pipeline reaches its pictures through clipping (chapter 3), perspective, an edge
//! table scan converter (chapter 4, Appendix 3) and a depth buffer with reciprocal depth
//! (chapter 2.3's Z-buffer). zspec shares none of those algorithms: it is the *Z spec*
//! of chapter 2.3 written out literally, in f64, one pixel centre at a time:
//!
//! * a polygon covers pixel (c, r) iff the centre (c+½, r+½) is inside its projection,
//!   its vertices snapped to the nearest 1/256 pixel (ties to even), by the even-odd rule
//!   with the top-left rule for centres on an edge, decided exactly in integers by an edge
//!   function at every centre ([`exact`]: its own arithmetic, not the scan converter's);
//! * the polygon is first cut to the view volume, as the pipeline's clippers cut it: at
//!   z_e = K1 and z_e = K2 in eye space, and at the screen's edges (the images of the
//!   pyramid's side planes) in device space, so that the outline whose vertices are
//!   snapped is the pipeline's;
//! * its depth at a covered centre is the z_e where the ray from the eye through the
//!   centre meets the polygon's (Newell) plane;
//! * folding the covering polygons in stream order, a later one takes the pixel only when
//!   its z_e is smaller than the holder's by more than 2⁻³⁰ of it (the tie rule,
//!   [`proto::depth`]), so coplanar polygons tie and the earlier one shows.
//!
//! The depth at a centre is computed robustly enough that the rule's decision does not
//! depend on rounding: z_e = −d/(n·r) for Newell's plane (n, d) and the ray r through the
//! centre, with n·r evaluated by the compensated algorithm of Ogita, Rump and Oishi
//! ([`dot3`]: as accurate as if computed in twice the precision, then rounded), so that a
//! plane seen at a grazing angle, where the terms of n·r cancel, still gives its depth to
//! a few ulps.
//!
//! Polygons that reach behind the hither plane are first cut at z_e = K1, so that every
//! vertex projected lies in front of the eye. The cut removes only points that the depth
//! test would reject anyway, so it changes no pixel.
//!
//! Two more things live here for the anti-aliasing methods: the K×K
//! supersampled reference ([`supersample`]: the same rules at every sub-pixel centre,
//! box-filtered) and the error measures of a frame against a reference ([`metrics`]:
//! differing fraction, RMSE, maximum error, edge-pixel RMSE).
//!
//! The frames are PPM images ([`proto::ppm`], whose [`Image`] `zspec compare` reads).

pub mod error;
mod exact;
pub mod metrics;
pub mod supersample;

pub use error::Error;
pub use metrics::{edges_from_mask, metrics, metrics_streams, EdgeError, Metrics};
pub use supersample::{render_supersampled, Supersampled, SupersampledFrame};

use exact::Outline;
use proto::camera::{Device, EyeFrame};
use proto::geometry::newell_plane;
use proto::shade::{self, crossing_at_depth, cut_coloured_at_hither, Lighting, Shading};
use proto::{Colour, DVec2, DVec3, DVec4, Polygon, View};
use std::ops::Range;
use std::sync::Arc;

pub use proto::ppm::Image;

/// Newell's plane of eye-space points whatever their size. Its sums multiply coordinates
/// in pairs, so points beyond about 1e154 would overflow them (a triangle with vertices at
/// ±1e307 got an infinite normal and drew nothing). Such points are first divided by a
/// power of two, which is exact and leaves the plane's normal as it is; the constant is
/// then multiplied back. Points of ordinary size are not scaled at all, so their plane
/// is bit for bit `newell_plane`'s.
fn plane_of(points: &[DVec3]) -> DVec4 {
    const LARGE: f64 = 1e150;
    let largest = points
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0, f64::max);
    if largest <= LARGE {
        return newell_plane(points);
    }
    // 2^e ≥ largest, so that the scaled points are at most 1 in size (2^1023 at most,
    // 2^1024 being infinite: then they are below 2).
    let scale = 2f64.powi((largest.log2().ceil() as i32).min(1023));
    let scaled: Vec<DVec3> = points.iter().map(|p| *p / scale).collect();
    let plane = newell_plane(&scaled);
    plane.truncate().extend(plane.w * scale)
}

impl Prepared {
    /// The polygon's colour at the centre of pixel (c, r) of the screen it was prepared
    /// for: its flat colour, or its shading there.
    #[inline]
    fn colour_at(&self, c: u32, r: u32) -> Colour {
        match &self.shading {
            None => self.colour,
            Some(shading) => shading.at(c, r),
        }
    }
}

/// A polygon made ready for the per-pixel tests: its colour, its eye-space plane and its
/// non-horizontal screen edges.
struct Prepared {
    colour: Colour,
    /// A Gouraud-shaded polygon's colours on this screen (docs/DESIGN.md, "Shading").
    shading: Option<Shading>,
    /// Newell's plane a·x_e + b·y_e + c·z_e + d = 0 of the eye-space vertices.
    plane: DVec4,
    /// The snapped outline on the screen, for the coverage test.
    outline: Outline,
}

/// Cuts an eye-space polygon to the half-space z_e ≥ K1 with
/// [`shade::cut_coloured_at_hither`], the cut viewxf's shading planes are fitted to. A
/// polygon wholly in front of the plane comes back unchanged, bit for bit.
fn cut_at_hither(vertices: &[DVec4], k1: f64, w_per_z: f64) -> Vec<DVec4> {
    if vertices.iter().all(|v| v.z >= k1) {
        return vertices.to_vec();
    }
    // The coloured cut with no colours: one routine for both.
    let none = vec![DVec3::ZERO; vertices.len()];
    cut_coloured_at_hither(vertices, &none, k1, w_per_z).0
}

/// The part of an eye-space polygon at or before the yon plane z_e = K2, as the pipeline's
/// clippers leave it: a crossing is interpolated from the edge's inside end and put on the
/// plane (z_e = K2, w = K2·s/d). Coverage is decided on the clipped polygon's snapped
/// outline (docs/DESIGN.md, "Coverage"), so the reference cuts where the pipeline cuts
/// rather than testing each centre's depth against K2, which would decide the centres
/// along the cut by the unsnapped line.
fn cut_at_yon(vertices: &[DVec4], k2: f64, w_per_z: f64) -> Vec<DVec4> {
    if vertices.iter().all(|v| v.z <= k2) {
        return vertices.to_vec();
    }
    let n = vertices.len();
    let mut out = Vec::with_capacity(n + 2);
    for i in 0..n {
        let (a, b) = (vertices[i], vertices[(i + 1) % n]);
        if a.z <= k2 {
            out.push(a);
        }
        if (a.z <= k2) != (b.z <= k2) {
            let (from, to) = if a.z <= k2 { (a, b) } else { (b, a) };
            out.push(crossing_at_depth(from, to, k2, w_per_z).0);
        }
    }
    out
}

/// Projected coordinates beyond this, in pixels, are first cut to [`GUARD`].
const HUGE: f64 = 1e300;

/// The guard band's half-width, in half-screens: the planes x_e = ±G·aspect·w and
/// y_e = ±G·w, 2^20 screens off the screen's edges.
const GUARD: f64 = (1u64 << 20) as f64;

/// An eye-space polygon cut to the guard band's four planes by the clippers' own
/// Sutherland–Hodgman step ([`proto::geometry::clip_against`]: its crossing is put
/// exactly on the plane, and computed scaled down where the coordinates' sums would
/// overflow). The screen's edges lie far inside the band, so the cut changes no pixel:
/// the points it removes project beyond the screen.
fn cut_to_guard(vertices: &[DVec4], aspect: f64) -> Vec<DVec4> {
    use proto::geometry::{clip_against, Plane};
    let (g, ga) = (GUARD, GUARD * aspect);
    let mut pts = vertices.to_vec();
    let mut out = Vec::with_capacity(pts.len() + 4);
    for n in [
        DVec4::new(1.0, 0.0, 0.0, ga),
        DVec4::new(-1.0, 0.0, 0.0, ga),
        DVec4::new(0.0, -1.0, 0.0, g),
        DVec4::new(0.0, 1.0, 0.0, g),
    ] {
        clip_against(&pts, &Plane::new(n, 0.0), &mut out);
        std::mem::swap(&mut pts, &mut out);
    }
    pts
}

/// `a·b` for three-vectors, as accurately as if computed in twice the working precision
/// and then rounded: Ogita, Rump and Oishi's Dot2 ("Accurate sum and dot product", SIAM
/// J. Sci. Comput. 26, 2005), each product split exactly by a fused multiply-add and the
/// sum carried with its rounding errors (TwoSum).
pub fn dot3(a: DVec3, b: DVec3) -> f64 {
    use proto::exact::{two_product, two_sum};
    let (mut s, mut c) = two_product(a.x, b.x);
    for (x, y) in [(a.y, b.y), (a.z, b.z)] {
        let (p, e) = two_product(x, y);
        let (t, f) = two_sum(s, p);
        s = t;
        c += e + f;
    }
    s + c
}

/// The reference's view of one frame: camera, view volume and screen.
#[derive(Clone, Debug)]
pub struct Setup {
    pub frame: EyeFrame,
    pub view: View,
    pub width: u32,
    pub height: u32,
    /// How many times finer than the pixel screen this screen is (1, or K for the K×K
    /// reference): vertices are snapped to the pixel screen's 1/256-pixel grid.
    pub samples: u32,
    /// The lighting of a Phong-shaded scene (its header says `vertex-normals`): a shaded
    /// polygon's values are then normals, and each pixel is lit by it.
    pub lighting: Option<Arc<Lighting>>,
}

impl Setup {
    pub fn new(frame: EyeFrame, view: View, width: u32, height: u32) -> Self {
        Setup {
            frame,
            view,
            width,
            height,
            samples: 1,
            lighting: None,
        }
    }

    /// The same setup for a scene whose header has `attributes` (its lighting, if it is
    /// Phong-shaded).
    pub fn for_scene(self, attributes: &proto::Attributes) -> Self {
        Setup {
            lighting: attributes.phong(),
            ..self
        }
    }

    fn device(&self) -> Device {
        Device {
            width: self.width,
            height: self.height,
            view: self.view,
        }
    }

    /// Eye-space vertices, hither cut, projection and plane of a world-space polygon;
    /// `None` for a polygon that can cover no pixel (fewer than three vertices, no area,
    /// nothing in front of the hither plane). A polygon whose projection overflows f64
    /// (a vertex at ±1e308 off the screen's side) is first cut to a guard band around the
    /// view, as the pipeline's clippers cut it to the view, and drawn as they draw it. A
    /// polygon the reference cannot compute exactly enough is refused, the message saying
    /// why: one whose eye coordinates overflow f64 (as viewxf refuses it).
    fn prepare(&self, poly: &Polygon) -> Result<Option<Prepared>, String> {
        if poly.vertices.len() < 3 {
            return Ok(None);
        }
        let eye: Vec<DVec4> = poly
            .vertices
            .iter()
            .map(|v| self.frame.to_eye(v.truncate()))
            .collect();
        if let Some((i, v)) = eye.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(format!(
                "vertex {i} is ({:?} {:?} {:?} {:?}) in eye coordinates: too large for f64",
                v.x, v.y, v.z, v.w
            ));
        }
        let eye3: Vec<DVec3> = eye.iter().map(|v| v.truncate()).collect();
        let mut plane = plane_of(&eye3);
        let front = cut_at_yon(
            &cut_at_hither(&eye, self.view.hither, self.frame.w_per_z),
            self.view.yon,
            self.frame.w_per_z,
        );
        if front.len() < 3 {
            return Ok(None);
        }
        if let Some(v) = front.iter().find(|v| !v.is_finite()) {
            return Err(format!(
                "cut at hither and yon, a vertex is ({:?} {:?} {:?} {:?}): too large for f64",
                v.x, v.y, v.z, v.w
            ));
        }
        if plane.truncate() == DVec3::ZERO {
            plane = self.plane_on_the_screen(&front);
        }
        let device = self.device();
        let project = |front: &[DVec4]| -> Vec<DVec2> {
            front
                .iter()
                .map(|&v| {
                    let (x, y) = device.project(v);
                    DVec2::new(x, y)
                })
                .collect()
        };
        let mut points = project(&front);
        // A vertex so far off the screen that its projection overflows (or is too large
        // for the cut to the screen's sums): the part of the polygon within a guard band
        // around the view is what covers the screen, as the pipeline's clippers keep the
        // part within the pyramid.
        if points
            .iter()
            .any(|p| !p.is_finite() || p.abs().max_element() > HUGE)
        {
            points = project(&cut_to_guard(&front, self.view.aspect));
        }
        if let Some(p) = points.iter().find(|p| !p.is_finite()) {
            return Err(format!(
                "a vertex projects to ({:?}, {:?}) on the screen: too far off it for f64",
                p.x, p.y
            ));
        }
        let Some(outline) = Outline::new(&points, self.width, self.height, self.samples) else {
            return Ok(None);
        };
        Ok(Some(Prepared {
            colour: poly.colour,
            shading: self.shading(poly, &eye),
            plane,
            outline,
        }))
    }

    /// The eye plane of a polygon of no net area in eye space, e.g. a bowtie whose lobes
    /// cancel: the plane it is seen in, as the pipeline records it
    /// ([`proto::newell::plane_seen_in_perspective`], over x' = x_e·z_e/w = x_e/(s/d),
    /// here over x_e). A polygon of no area on the screen either gets the depth of its
    /// nearest vertex in front of hither, as the scan converter's flat depth does
    /// (docs/degenerate.md); one of no area at all still covers nothing.
    fn plane_on_the_screen(&self, front: &[DVec4]) -> DVec4 {
        if let Some(p) = proto::newell::plane_seen_in_perspective(front) {
            let per_w = 1.0 / self.frame.w_per_z;
            return DVec4::new(p.x * per_w, p.y * per_w, p.z, p.w);
        }
        let nearest = front.iter().map(|v| v.z).fold(f64::INFINITY, f64::min);
        DVec4::new(0.0, 0.0, 1.0, -nearest)
    }

    /// The direction of the ray from the eye through device point (X, Y), scaled to
    /// z_e = 1: x_s = 2X/W − 1, y_s = 1 − 2Y/H, and a point of the ray at depth z_e has
    /// x_e = x_s·a·w, y_e = y_s·w with w = z_e·s/d.
    /// The shading of a polygon with vertex colours (or normals), by the rule of
    /// docs/DESIGN.md, "Shading": each channel's plane over the vertices' screen positions, taken (as viewxf
    /// records it) from the eye-space polygon before any cut, and carried to this screen
    /// as persp carries it. A polygon with a vertex at or behind the eye has its planes
    /// from its part in front of the hither plane instead, the colours at the cut
    /// interpolated as the positions are: [`shade::front_colour_planes`], viewxf's.
    fn shading(&self, poly: &Polygon, eye: &[DVec4]) -> Option<Shading> {
        if !poly.is_shaded() {
            return None;
        }
        let planes = shade::front_colour_planes(
            eye,
            &poly.vertex_attrs,
            self.view.hither,
            self.frame.w_per_z,
        );
        let screen = planes.and_then(|p| {
            shade::colour_planes_to_screen(&p, self.view.aspect, self.width, self.height)
        });
        let shading = match screen {
            Some(planes) => Shading::new(planes),
            None => {
                let c = poly.vertex_attrs[0];
                Shading::new([0, 1, 2].map(|k| DVec4::new(0.0, 0.0, 1.0, -c[k])))
            }
        };
        // Phong shading: the planes are a normal's, lit per pixel from the polygon's
        // colour.
        Some(shading.lit(self.lighting.as_ref(), poly.colour))
    }

    #[inline]
    fn ray(&self, x: f64, y: f64) -> DVec3 {
        let xs = 2.0 * x / self.width as f64 - 1.0;
        let ys = 1.0 - 2.0 * y / self.height as f64;
        let k = self.frame.w_per_z;
        DVec3::new(xs * self.view.aspect * k, ys * k, 1.0)
    }

    /// Calls `f(column, row, z_e)` for every pixel whose centre the polygon covers and
    /// whose depth lies in the view volume.
    fn for_each_covered(&self, p: &Prepared, f: impl FnMut(u32, u32, f64)) {
        self.for_each_covered_in(p, 0..self.height, f)
    }

    /// The rows of `band` that the polygon's bounding box spans (empty if none).
    fn rows_in(&self, p: &Prepared, band: &Range<u32>) -> Range<u32> {
        let rows = p.outline.rows(self.height);
        let start = rows.start.max(band.start);
        start..rows.end.min(band.end).max(start)
    }

    /// [`Setup::for_each_covered`] on the rows of `band` only: the pixels of other rows
    /// are left alone, so that a frame can be drawn a band of rows at a time.
    fn for_each_covered_in(
        &self,
        p: &Prepared,
        band: Range<u32>,
        mut f: impl FnMut(u32, u32, f64),
    ) {
        let rows = self.rows_in(p, &band);
        let cols = p.outline.columns(self.width);
        let n = p.plane.truncate();
        for r in rows {
            let yc = r as f64 + 0.5;
            for c in cols.clone() {
                let xc = c as f64 + 0.5;
                // Even-odd with the half-open and top-left rules, exactly, on the snapped
                // outline.
                if !p.outline.covers(c, r) {
                    continue;
                }
                // The ray t·dir meets the plane n·v + d = 0 at t = −d / (n·dir); t is z_e.
                // n·dir is where a plane seen at a grazing angle cancels: compensated.
                let dir = self.ray(xc, yc);
                let z = -p.plane.w / dot3(n, dir);
                // The polygon was cut at hither and yon before it was snapped: its
                // centres are in the view volume but for the snapping's 1/512 pixel,
                // which the pipeline's clipped polygons share.
                if z.is_finite() && z > 0.0 {
                    f(c, r, z);
                }
            }
        }
    }
}

/// A frame being rendered by the reference: the nearest z_e so far and its colour at every
/// pixel. Polygons are drawn one at a time, in stream order, so memory is one frame
/// whatever the number of polygons.
pub struct ReferenceFrame {
    pub colour: Vec<Colour>,
    depth: Vec<f64>,
    width: usize,
    background: Colour,
}

impl ReferenceFrame {
    /// A frame of the background colour; a screen too large for this machine's memory is
    /// refused saying what it would need.
    pub fn new(setup: &Setup, background: Colour) -> Result<Self, String> {
        let size = setup.width as usize * setup.height as usize;
        let refuse = |_| {
            format!(
                "a {}x{} frame needs {} (11 bytes a pixel: colour and depth), more memory \
                 than can be had",
                setup.width,
                setup.height,
                stagecli::error::bytes_text(size as u64 * 11)
            )
        };
        let mut colour = Vec::new();
        let mut depth = Vec::new();
        colour.try_reserve_exact(size).map_err(refuse)?;
        depth.try_reserve_exact(size).map_err(refuse)?;
        colour.resize(size, background);
        depth.resize(size, f64::INFINITY);
        Ok(ReferenceFrame {
            colour,
            depth,
            width: setup.width as usize,
            background,
        })
    }

    /// Draws the next polygon of the frame; a polygon the reference cannot compute is
    /// refused (see `Setup::prepare`).
    pub fn draw(&mut self, setup: &Setup, poly: &Polygon) -> Result<(), String> {
        let Some(p) = setup.prepare(poly)? else {
            return Ok(());
        };
        let (colour, depth, w) = (&mut self.colour, &mut self.depth, self.width);
        setup.for_each_covered(&p, |c, r, z| {
            let i = r as usize * w + c as usize;
            // The tie rule: nearer by more than 2^-30 of the holder's depth (an empty
            // pixel is held at +inf).
            if proto::depth::takes(z, depth[i]) {
                depth[i] = z;
                colour[i] = p.colour_at(c, r);
            }
        });
        Ok(())
    }

    /// Empties the frame for the next one.
    pub fn clear(&mut self) {
        self.colour.fill(self.background);
        self.depth.fill(f64::INFINITY);
    }
}

/// Renders one frame of world-space polygons: every pixel takes the colour of the
/// covering polygon nearest the eye (the earliest on a tie), or `background`.
/// Pixels are row-major from the top-left. An error names the polygon (from 0).
pub fn render_frame(
    polys: &[Polygon],
    setup: &Setup,
    background: Colour,
) -> Result<Vec<Colour>, String> {
    let mut frame = ReferenceFrame::new(setup, background)?;
    for (k, poly) in polys.iter().enumerate() {
        frame
            .draw(setup, poly)
            .map_err(|m| format!("polygon {k}: {m}"))?;
    }
    Ok(frame.colour)
}

/// How many polygons cover each pixel centre inside the view volume (row-major). A
/// closed mesh seen from outside covers each pixel it spans exactly twice (front and
/// back), an open sheet exactly once: the top-left rule leaves no cracks and no overlaps.
pub fn coverage_counts(polys: &[Polygon], setup: &Setup) -> Vec<u32> {
    let mut counts = vec![0u32; setup.width as usize * setup.height as usize];
    let w = setup.width as usize;
    for poly in polys {
        if let Ok(Some(p)) = setup.prepare(poly) {
            setup.for_each_covered(&p, |c, r, _| counts[r as usize * w + c as usize] += 1);
        }
    }
    counts
}

/// How two renderings of one frame agree.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameAgreement {
    pub pixels: u64,
    pub differing: u64,
    /// Positions (x, y) of the differing pixels.
    pub differences: Vec<(u32, u32)>,
}

impl FrameAgreement {
    /// The percentage of pixels that agree.
    pub fn percent(&self) -> f64 {
        if self.pixels == 0 {
            100.0
        } else {
            100.0 * (self.pixels - self.differing) as f64 / self.pixels as f64
        }
    }
}

impl std::fmt::Display for FrameAgreement {
    /// `4 pixels, 1 differ, 75.0000% agree`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} pixels, {} differ, {:.4}% agree",
            self.pixels,
            self.differing,
            self.percent()
        )
    }
}

/// Whether no frame has more than `tolerance` (a fraction) of its pixels differing; if
/// one does, the message names the frames that do.
pub fn agreed(frames: &[FrameAgreement], tolerance: f64) -> Result<(), String> {
    let failing: Vec<usize> = (0..frames.len())
        .filter(|&k| {
            let f = &frames[k];
            f.differing > 0 && f.differing as f64 > tolerance * f.pixels as f64
        })
        .collect();
    if failing.is_empty() {
        return Ok(());
    }
    let allowed = if tolerance == 0.0 {
        String::new()
    } else {
        format!(" (more than --tolerance {tolerance})")
    };
    Err(format!(
        "{} of {} frames differ{allowed} (frames {failing:?})",
        failing.len(),
        frames.len(),
    ))
}

/// Compares two renderings frame by frame. Streams of different lengths, or frames of
/// different sizes, differ with no agreement to measure: the message says how.
pub fn compare(a: &[Image], b: &[Image]) -> Result<Vec<FrameAgreement>, String> {
    if a.len() != b.len() {
        return Err(format!(
            "the streams have {} and {} frames",
            a.len(),
            b.len()
        ));
    }
    a.iter()
        .zip(b)
        .enumerate()
        .map(|(k, (a, b))| {
            if (a.width, a.height) != (b.width, b.height) {
                return Err(format!(
                    "frame {k} is {}x{} in one stream and {}x{} in the other",
                    a.width, a.height, b.width, b.height
                ));
            }
            let differences: Vec<(u32, u32)> = a
                .pixels
                .iter()
                .zip(&b.pixels)
                .enumerate()
                .filter(|(_, (p, q))| p != q)
                .map(|(i, _)| ((i % a.width as usize) as u32, (i / a.width as usize) as u32))
                .collect();
            Ok(FrameAgreement {
                pixels: a.pixels.len() as u64,
                differing: differences.len() as u64,
                differences,
            })
        })
        .collect()
}

pub use stagecli::parse_colour;

#[cfg(test)]
mod tests;
