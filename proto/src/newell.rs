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
pub fn newell_normal(points: &[DVec3]) -> DVec3 {
    let n = points.len();
    let mut normal = DVec3::ZERO;
    for i in 0..n {
        let p = points[i];
        let q = points[(i + 1) % n];
        normal.x += (p.y - q.y) * (p.z + q.z);
        normal.y += (p.z - q.z) * (p.x + q.x);
        normal.z += (p.x - q.x) * (p.y + q.y);
    }
    normal
}

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
    let normal = newell_normal(points);
    if points.is_empty() {
        return DVec4::ZERO;
    }
    let z = points[0].z;
    if normal != DVec3::ZERO && points.iter().all(|p| p.z == z) {
        return DVec4::new(0.0, 0.0, 1.0, -z);
    }
    let centroid = points.iter().copied().sum::<DVec3>() / points.len() as f64;
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
}
