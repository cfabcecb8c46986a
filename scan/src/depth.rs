//! A polygon's depth across the screen: its plane, stepped along each row in fixed point
//! (thesis Appendix 3.3 ii).

use proto::fragment::depth_to_fixed;
use proto::{DVec3, DVec4, Polygon};

/// The depth of a polygon across the screen, in the fixed point of
/// [`proto::fragment::DEPTH_ONE`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DepthPlane {
    /// `Z = −(a·X + b·Y + d)/c`, with `DZ = fixed(−a/c)` the step from a pixel to the next
    /// on its row (Appendix 3.3 ii).
    Plane {
        a: f64,
        b: f64,
        c: f64,
        d: f64,
        dz: i64,
    },
    /// A polygon seen edge-on or of no area (c = 0, or a plane that is not finite): it
    /// covers essentially nothing, and what it does cover gets its nearest vertex depth.
    Flat(i64),
}

impl DepthPlane {
    /// The polygon's depth plane as persp recorded it (the whole polygon's plane, the
    /// same for every piece the splitter tree cut it into), or else Newell's plane through
    /// the screen vertices (X, Y, depth): a hand-written stream, or persp's eye-z mode
    /// (Appendix 3.4; the occam code used three vertices and failed when they were
    /// collinear).
    pub fn of(polygon: &Polygon) -> Self {
        let points: Vec<DVec3> = polygon.vertices.iter().map(|v| v.truncate()).collect();
        let recorded = polygon.plane.filter(|n| n.z != 0.0 && n.is_finite());
        let DVec4 {
            x: a,
            y: b,
            z: c,
            w: d,
        } = recorded.unwrap_or_else(|| proto::geometry::newell_plane(&points));
        let dz = -a / c;
        if c != 0.0
            && a.is_finite()
            && b.is_finite()
            && c.is_finite()
            && d.is_finite()
            && dz.is_finite()
        {
            DepthPlane::Plane {
                a,
                b,
                c,
                d,
                dz: depth_to_fixed(dz),
            }
        } else {
            let nearest = points.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
            DepthPlane::Flat(if nearest.is_finite() {
                depth_to_fixed(nearest)
            } else {
                0
            })
        }
    }

    /// The fixed-point depth at the centre of column 0 of `row`, and the step per column.
    /// A pixel's depth is `z_row + x·dz` ([`depth_at`]), whatever span it is in.
    #[inline]
    pub fn row(&self, row: u32) -> (i64, i64) {
        match *self {
            DepthPlane::Plane { a, b, c, d, dz } => {
                let y = row as f64 + 0.5;
                (depth_to_fixed(-(a * 0.5 + b * y + d) / c), dz)
            }
            DepthPlane::Flat(z) => (z, 0),
        }
    }
}

/// A pixel's depth as every hidden-surface method holds it. Methods name this type, not
/// the representation, so that the depth form can change in one place.
pub type Depth = i64;

/// The tie rule of docs/DESIGN.md's Z specification, the one comparison every method
/// makes: does a polygon later in the stream, at depth `new` at a pixel centre, take the
/// pixel from the polygon that holds it at depth `held`? (At equal depth the holder, the
/// earlier polygon, keeps it.)
#[inline]
pub fn takes(new: Depth, held: Depth) -> bool {
    new < held
}

/// The depth of column `x` on a row: `z_row + x·dz` in 128 bits, saturated to `i64`.
///
/// Stepping `z ← z + dz` with saturating adds from any column gives the same values: the
/// exact sequence is monotone, so once it leaves the `i64` range it stays out on the same
/// side, where saturation holds it at the bound.
#[inline]
pub fn depth_at(z_row: i64, dz: i64, x: u32) -> i64 {
    let z = z_row as i128 + x as i128 * dz as i128;
    z.clamp(i64::MIN as i128, i64::MAX as i128) as i64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edge_on_polygon_takes_the_nearest_vertex_depth() {
        // All vertices on one line: no area, no plane, no NaN.
        let line = Polygon::from_xyz(
            [10, 20, 30],
            &[[0.0, 0.0, 0.7], [4.0, 4.0, 0.2], [2.0, 2.0, 0.9]],
        );
        assert_eq!(DepthPlane::of(&line), DepthPlane::Flat(depth_to_fixed(0.2)));
        assert_eq!(DepthPlane::of(&line).row(3), (depth_to_fixed(0.2), 0));
    }

    #[test]
    fn depth_at_saturates_like_stepping() {
        assert_eq!(depth_at(10, 3, 4), 22);
        assert_eq!(depth_at(i64::MAX - 5, 2, 3), i64::MAX);
        assert_eq!(depth_at(i64::MIN + 5, -2, 3), i64::MIN);
        // Stepping from column 1 with saturating adds reaches the same depths.
        let (z_row, dz) = (i64::MAX - 10, 4);
        let mut z = depth_at(z_row, dz, 1);
        for x in 2..8 {
            z = z.saturating_add(dz);
            assert_eq!(z, depth_at(z_row, dz, x), "column {x}");
        }
    }
}
