//! Newell's plane of a polygon (thesis Appendix 3.4), the plane every stage gives a
//! polygon: its depth plane, its colour planes, the plane it records before a split.

use glam::{DVec3, DVec4};

/// Newell's normal of a polygon (Appendix 3.4): for each edge (i, j = i+1 mod n)
///
///   a = Σ (y_i − y_j)(z_i + z_j),  b = Σ (z_i − z_j)(x_i + x_j),  c = Σ (x_i − x_j)(y_i + y_j).
///
/// Unlike the occam code, which used the first three vertices and so failed when they
/// were collinear, this sums over every edge: it is twice the polygon's vector area, the
/// least-squares best plane orientation of a non-planar polygon, and zero only for a
/// polygon of no area.
///
/// "No area" includes a polygon whose vector area is zero in exact arithmetic but not in
/// floating point: a bowtie whose two lobes cancel, or a polygon folded back on itself.
/// Its sums then end in rounding noise (about 1e-14 for a bowtie 20 units across) whose
/// direction is arbitrary, and a plane taken from that noise gives each renderer a
/// different, meaningless depth: zspec and the pipeline, which sum in other coordinates,
/// disagreed on the pixels of every such bowtie. Each component's sum is therefore
/// compared with the bound on its own rounding error, (n + 3)·ε·Σ|term| for n terms
/// (each product rounds twice, the sum n − 1 times; Higham, *Accuracy and Stability of
/// Numerical Algorithms*, §3.1), doubled for margin; when all three are within it, the
/// polygon has no area to speak of and the normal is exactly zero, which every stage
/// and the reference take as "no plane" (docs/degenerate.md: such a polygon gets the
/// depth of its nearest vertex). A polygon with any area above rounding keeps its sums
/// as they are, bit for bit.
///
/// The points are themselves rounded: the stages compute them (viewxf's transform, the
/// normalisation x·z_e/w) to a few units in the last place of each coordinate. The sums
/// do not change when the polygon is moved (Σ over a closed outline), so a change δ_i,
/// of the size of coordinate i's rounding, moves a by up to
/// Σ (|δy_i| + |δy_j|)(|z'_i| + |z'_j|) + (|y'_i| + |y'_j|)(|δz_i| + |δz_j|), the primed
/// coordinates taken from the vertices' centroid (b and c alike): the bound also holds
/// that for [`INPUT_ULPS`] units of each coordinate. Differential seed 7285's bowtie,
/// exactly planar in the world with lobes that cancel, reached eye space with sums of
/// 2·10⁻¹³ against a bound of 4·10⁻¹⁴ for the arithmetic alone, and took its plane from
/// that noise (29 pixels otherwise than zspec).
pub fn newell_normal(points: &[DVec3]) -> DVec3 {
    normal_about(points, centroid(points))
}

/// The mean of the points (zero for none).
fn centroid(points: &[DVec3]) -> DVec3 {
    points.iter().copied().sum::<DVec3>() / points.len().max(1) as f64
}

/// [`newell_normal`], the points' `centroid` given.
fn normal_about(points: &[DVec3], centroid: DVec3) -> DVec3 {
    let n = points.len();
    let mut normal = DVec3::ZERO;
    let mut magnitude = DVec3::ZERO;
    let mut sensitivity = DVec3::ZERO;
    for i in 0..n {
        let p = points[i];
        let q = points[(i + 1) % n];
        let term = DVec3::new(
            (p.y - q.y) * (p.z + q.z),
            (p.z - q.z) * (p.x + q.x),
            (p.x - q.x) * (p.y + q.y),
        );
        normal += term;
        magnitude += term.abs();
        // The rounding's size (absolute) and its lever (from the centroid).
        let (d, l) = (
            p.abs() + q.abs(),
            (p - centroid).abs() + (q - centroid).abs(),
        );
        sensitivity += DVec3::new(
            d.y * l.z + l.y * d.z,
            d.z * l.x + l.z * d.x,
            d.x * l.y + l.x * d.y,
        );
    }
    let bound = magnitude * (2.0 * (n as f64 + 3.0) * f64::EPSILON)
        + sensitivity * (INPUT_ULPS * f64::EPSILON);
    if normal.abs().cmple(bound).all() {
        return DVec3::ZERO;
    }
    normal
}

/// The rounding of a point's coordinates that [`newell_normal`] allows for, in units of
/// the last place: each stage's few operations on a coordinate (a 4×4 transform, a
/// product and a quotient), doubled for margin.
const INPUT_ULPS: f64 = 8.0;

/// Newell's plane `a·x + b·y + c·z + d = 0`, returned as `(a, b, c, d)`. The constant is
/// found through the centroid of the vertices rather than one vertex, which is the best
/// fit for a polygon that is not quite planar.
///
/// A polygon whose vertices all have the same z (in eye space: parallel to the screen;
/// in screen space: of constant depth) gets exactly the plane `z = const`, `(0, 0, 1, −z)`.
/// Newell's sums would leave rounding noise of about 1e-16 in a and b, different for
/// every polygon, and two such polygons at the same depth would then not tie: the Z
/// spec gives a tie to the earlier polygon, so equal depths must come out equal.
pub fn newell_plane(points: &[DVec3]) -> DVec4 {
    let centroid = centroid(points);
    let normal = normal_about(points, centroid);
    if points.is_empty() {
        return DVec4::ZERO;
    }
    let z = points[0].z;
    if normal != DVec3::ZERO && points.iter().all(|p| p.z == z) {
        return DVec4::new(0.0, 0.0, 1.0, -z);
    }
    normal.extend(-normal.dot(centroid))
}

/// [`newell_plane`] of the points `point` makes of `vertices`, gathered on the stack for
/// up to eight vertices (a quad clipped by a few planes): persp and the scan converters
/// ask for a plane per polygon, and a vector for each was a malloc and a free.
pub fn newell_plane_of(vertices: &[DVec4], point: impl Fn(&DVec4) -> DVec3) -> DVec4 {
    const ON_STACK: usize = 8;
    if vertices.len() <= ON_STACK {
        let mut points = [DVec3::ZERO; ON_STACK];
        for (p, v) in points.iter_mut().zip(vertices) {
            *p = point(v);
        }
        newell_plane(&points[..vertices.len()])
    } else {
        newell_plane(&vertices.iter().map(point).collect::<Vec<_>>())
    }
}

/// The plane of an eye-space polygon of no net area in eye space (a bowtie whose lobes
/// cancel, whose [`newell_normal`] is zero), found from how it is seen: in perspective its
/// lobes no longer cancel, and over the points (u, v, q) = (x_e/w, y_e/w, 1/z_e), in
/// which every plane not through the eye is a plane (1/z_e is affine in the screen
/// position), Newell's plane `A·u + B·v + C·q + D = 0` is the polygon's own. Times z_e,
/// with x' = x_e·z_e/w, that is `A·x' + B·y' + D·z_e + C = 0`, returned as (A, B, D, C)
/// over the normalised eye points (x', y', z_e) of [`crate::Polygon::eye_plane`].
/// `None` for a polygon with a vertex at or behind the eye, or of no area on the screen
/// either (seen edge-on, or its lobes cancel there too): the scan converter gives such a
/// polygon its nearest vertex's depth.
pub fn plane_seen_in_perspective(vertices: &[DVec4]) -> Option<DVec4> {
    if !vertices.iter().all(|v| v.w > 0.0 && v.z > 0.0) {
        return None;
    }
    let seen = newell_plane_of(vertices, |v| DVec3::new(v.x / v.w, v.y / v.w, 1.0 / v.z));
    let plane = DVec4::new(seen.x, seen.y, seen.w, seen.z);
    (plane.is_finite() && seen.z != 0.0).then_some(plane)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn newell_ignores_collinear_leading_vertices() {
        // The first three vertices are collinear: a three-vertex plane would be 0.
        let pts = [
            DVec3::new(0.0, 0.0, 2.0),
            DVec3::new(1.0, 0.0, 2.0),
            DVec3::new(2.0, 0.0, 2.0),
            DVec3::new(2.0, 2.0, 2.0),
            DVec3::new(0.0, 2.0, 2.0),
        ];
        let p = newell_plane(&pts);
        assert_eq!(p, DVec4::new(0.0, 0.0, 1.0, -2.0));
        assert_eq!(newell_normal(&pts), DVec3::new(0.0, 0.0, 8.0));
        // Tilted, the same polygon's plane passes through every vertex.
        let tilted: Vec<DVec3> = pts
            .iter()
            .map(|p| DVec3::new(p.x, p.y, p.x + 2.0))
            .collect();
        let p = newell_plane(&tilted);
        for v in &tilted {
            assert_eq!(p.truncate().dot(*v) + p.w, 0.0);
        }
    }

    #[test]
    fn polygons_of_one_depth_get_exactly_that_plane() {
        // Rounding in Newell's sums would otherwise leave a and b slightly off zero.
        let a = [
            DVec3::new(0.1, 0.7, 20.0),
            DVec3::new(3.3, 0.2, 20.0),
            DVec3::new(1.9, 5.3, 20.0),
        ];
        let b = [
            DVec3::new(-7.3, 1.1, 20.0),
            DVec3::new(0.3, -2.9, 20.0),
            DVec3::new(2.2, 9.1, 20.0),
        ];
        assert_eq!(newell_plane(&a), DVec4::new(0.0, 0.0, 1.0, -20.0));
        assert_eq!(newell_plane(&a), newell_plane(&b));
        // No area: no plane, whatever the depths.
        let flat = [
            DVec3::new(0.0, 0.0, 3.0),
            DVec3::new(1.0, 1.0, 3.0),
            DVec3::new(2.0, 2.0, 3.0),
        ];
        assert_eq!(newell_plane(&flat).truncate(), DVec3::ZERO);
    }

    #[test]
    fn a_bowtie_whose_lobes_cancel_has_no_plane_not_a_plane_of_noise() {
        // A planar bowtie found by the differential suite: its sums leave
        // (2.8e-14, -2.8e-14, 0), a vertical plane in an arbitrary direction.
        let bowtie = [
            DVec3::new(-9.422154311560915, -6.858588079080317, -5.093216671888795),
            DVec3::new(12.10366239857507, 11.848213681031712, 5.628495387079276),
            DVec3::new(12.10366239857507, -6.858588079080317, 7.786818060084505),
            DVec3::new(-9.422154311560915, 11.848213681031712, -7.251539344894023),
        ];
        assert_eq!(newell_normal(&bowtie), DVec3::ZERO);
        // Its lobes made unequal by a hundredth of a unit: a plane again, the bowtie's.
        let mut uneven = bowtie;
        uneven[1] += (uneven[1] - uneven[0]) * 1e-3;
        let plane = newell_plane(&uneven);
        assert!(plane.truncate() != DVec3::ZERO);
        for v in &uneven {
            let off = (plane.truncate().dot(*v) + plane.w) / plane.truncate().length();
            assert!(off.abs() < 1e-9, "{v} is {off} off the plane");
        }
    }

    #[test]
    fn a_bowtie_of_no_eye_area_gets_the_plane_it_is_seen_in() {
        // The bowtie above in eye space (the thesis camera: z_e = 20 − z, w = 0.625·z_e):
        // no plane from its eye points, its own plane from how it is seen.
        let eye: Vec<DVec4> = [
            [-9.422154311560915, -6.858588079080317, -5.093216671888795],
            [12.10366239857507, 11.848213681031712, 5.628495387079276],
            [12.10366239857507, -6.858588079080317, 7.786818060084505],
            [-9.422154311560915, 11.848213681031712, -7.251539344894023],
        ]
        .iter()
        .map(|p| DVec4::new(p[0], p[1], 20.0 - p[2], 0.625 * (20.0 - p[2])))
        .collect();
        let normalised = |v: &DVec4| DVec3::new(v.x * v.z / v.w, v.y * v.z / v.w, v.z);
        assert_eq!(newell_plane_of(&eye, normalised).truncate(), DVec3::ZERO);
        let plane = plane_seen_in_perspective(&eye).expect("a plane");
        for v in &eye {
            let p = normalised(v);
            let off = (plane.truncate().dot(p) + plane.w) / plane.truncate().length();
            assert!(off.abs() < 1e-9, "{p} is {off} off the plane");
        }
        // Behind the eye it has no screen position, and no such plane.
        let mut behind = eye.clone();
        behind[0].z = -1.0;
        behind[0].w = -0.625;
        assert_eq!(plane_seen_in_perspective(&behind), None);
    }

    #[test]
    fn a_bowtie_with_rounded_points_has_no_area() {
        // Differential seed 7285's bowtie as viewxf leaves it, in the normalised eye
        // points eye_plane sums over: planar, its lobes cancelling in exact arithmetic,
        // its sums 2e-13, 4e-14 and -5e-14 of rounding carried in from the transform.
        let eye = [
            [
                -4.434658357772511,
                -4.288576278249963,
                28.06192709307579,
                17.53870443317237,
            ],
            [
                11.410111227078607,
                4.431022850644239,
                19.252896076928693,
                12.033060048080433,
            ],
            [
                11.189535183941986,
                -4.69179278167421,
                25.841946503530394,
                16.151216564706495,
            ],
            [
                -4.214082314635891,
                4.834239354068488,
                21.47287666647409,
                13.420547916546306,
            ],
        ]
        .map(DVec4::from_array);
        let points = eye.map(|v| DVec3::new(v.x * (v.z / v.w), v.y * (v.z / v.w), v.z));
        assert_eq!(newell_normal(&points), DVec3::ZERO);
        // So it is given the plane it is seen in, which holds its four points.
        let p = crate::Polygon::new([0, 0, 0], eye.to_vec())
            .eye_plane()
            .expect("a plane");
        for q in points {
            assert!((p.truncate().dot(q) + p.w).abs() < 1e-12, "{p:?}");
        }
    }

    #[test]
    fn a_tiny_triangle_far_away_still_has_its_plane() {
        // Area 1e-16 at 1e3 from the origin: far above the sums' rounding.
        let t = [
            DVec3::new(1e3, 1e3, 1e3),
            DVec3::new(1e3 + 1e-8, 1e3, 1e3),
            DVec3::new(1e3, 1e3 + 1e-8, 1e3 + 1e-8),
        ];
        let n = newell_normal(&t);
        assert!(n != DVec3::ZERO);
        assert!((n.normalize() - DVec3::new(0.0, -1.0, 1.0).normalize()).length() < 1e-6);
    }
}
