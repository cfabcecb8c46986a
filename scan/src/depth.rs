//! A polygon's depth across the screen: its plane, evaluated along each row (thesis
//! Appendix 3.3 ii).

use proto::{DVec4, Polygon};

/// The depth of a polygon across the screen, in the form persp wrote (an f64; the
/// reciprocal depth −K1/z_e by default, [`proto::depth`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DepthPlane {
    /// `Z = −(a·X + b·Y + d)/c`, with `dz = −a/c` the step from a pixel to the next on
    /// its row (Appendix 3.3 ii).
    Plane {
        a: f64,
        b: f64,
        c: f64,
        d: f64,
        dz: f64,
    },
    /// A polygon seen edge-on or of no area (c = 0, or a plane that is not finite): it
    /// covers essentially nothing, and what it does cover gets its nearest vertex depth.
    Flat(f64),
}

impl DepthPlane {
    /// The polygon's depth plane as persp recorded it (the whole polygon's plane, the
    /// same for every piece the splitter tree cut it into), or else Newell's plane through
    /// the screen vertices (X, Y, depth): a hand-written stream, or persp's eye-z mode
    /// (Appendix 3.4; the occam code used three vertices and failed when they were
    /// collinear).
    pub fn of(polygon: &Polygon) -> Self {
        let recorded = polygon.plane.filter(|n| n.z != 0.0 && n.is_finite());
        let DVec4 {
            x: a,
            y: b,
            z: c,
            w: d,
        } = recorded.unwrap_or_else(|| {
            proto::geometry::newell_plane_of(&polygon.vertices, |v| v.truncate())
        });
        // `+ 0.0` turns −0 into +0 (and changes nothing else), so that text shows `0`.
        let dz = -a / c + 0.0;
        // A plane so steep that a row of the largest screen would step past f64's range
        // is taken as edge-on: its depths could not be finite across the row.
        if c != 0.0
            && a.is_finite()
            && b.is_finite()
            && c.is_finite()
            && d.is_finite()
            && (dz * MAX_COLUMNS).is_finite()
            && (-(b * MAX_COLUMNS + d) / c).is_finite()
        {
            DepthPlane::Plane { a, b, c, d, dz }
        } else {
            let nearest = polygon
                .vertices
                .iter()
                .map(|v| v.z)
                .fold(f64::INFINITY, f64::min);
            DepthPlane::Flat(if nearest.is_finite() { nearest } else { 0.0 })
        }
    }

    /// The depth at the centre of column 0 of `row`, and the step per column. A pixel's
    /// depth is `z_row + x·dz` ([`depth_at`]), whatever span it is in.
    #[inline]
    pub fn row(&self, row: u32) -> (Depth, Depth) {
        match *self {
            DepthPlane::Plane { a, b, c, d, dz } => {
                let y = row as f64 + 0.5;
                (-(a * 0.5 + b * y + d) / c + 0.0, dz)
            }
            DepthPlane::Flat(z) => (z, 0.0),
        }
    }

    /// The depth at the centre of pixel (x, y): the same bits as the row's
    /// [`depth_at`].
    #[inline]
    pub fn at(&self, x: u32, y: u32) -> Depth {
        let (z_row, dz) = self.row(y);
        depth_at(z_row, dz, x)
    }
}

/// Screen columns and rows a depth plane must stay finite over (the codec's largest
/// screen side is a u32; planes are checked at 2^32).
const MAX_COLUMNS: f64 = 4_294_967_296.0;

/// A pixel's depth as every hidden-surface method holds it: an f64 in the form persp
/// wrote, smaller nearer. Methods name this type, not the representation.
pub type Depth = f64;

/// The tie rule of docs/DESIGN.md's Z specification, the one comparison every method
/// makes: does a polygon later in the stream, at depth `new` at a pixel centre, take the
/// pixel from the polygon that holds it at depth `held`? Only when nearer by more than
/// 2⁻³⁰ of the holder's depth ([`proto::depth::takes`]).
#[inline]
pub fn takes(new: Depth, held: Depth) -> bool {
    proto::depth::takes(new, held)
}

/// The depth of column `x` on a row: `z_row + x·dz` ([`proto::fragment::span_depth`]).
#[inline]
pub fn depth_at(z_row: Depth, dz: Depth, x: u32) -> Depth {
    proto::fragment::span_depth(z_row, dz, x)
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
        assert_eq!(DepthPlane::of(&line), DepthPlane::Flat(0.2));
        assert_eq!(DepthPlane::of(&line).row(3), (0.2, 0.0));
    }

    #[test]
    fn depth_at_is_the_row_plane_at_the_column() {
        assert_eq!(depth_at(10.0, 3.0, 4), 22.0);
        let plane = DepthPlane::Plane {
            a: 1.0,
            b: 2.0,
            c: -8.0,
            d: 0.5,
            dz: 0.125,
        };
        // Z = (X + 2Y + 0.5)/8 at (4.5, 3.5): (4.5 + 7 + 0.5)/8 = 1.5.
        assert_eq!(plane.at(4, 3), 1.5);
    }

    /// Exact arithmetic on a plane's depth at a column, in i128 units of 2^-64, for
    /// planes with dyadic coefficients: z_row + x·dz.
    fn exact(z_row: f64, dz: f64, x: u32) -> f64 {
        let unit = (1u128 << 64) as f64;
        let zr = (z_row * unit) as i128;
        let step = (dz * unit) as i128;
        (zr + x as i128 * step) as f64 / unit
    }

    #[test]
    fn depth_along_a_16384_pixel_row_is_within_a_small_fraction_of_the_tie_width() {
        // Reciprocal depths from hither (−1) to a thousandth of it across the row, in
        // both directions, and a row nearly parallel to the screen far away: every
        // column's depth within 2^-40 of the exact value (the rule's width is 2^-30).
        let w = 16384u32;
        let rows: [(f64, f64); 4] = [
            (-1.0, (1.0 - 1e-3) / w as f64),
            (-1e-3, -(1.0 - 1e-3) / w as f64),
            (-1e-6, 1e-18),
            (-0.5, 1.0 / 65536.0),
        ];
        for (z_row, dz) in rows {
            // Round the inputs to 2^-64 so the exact sum is representable in i128 units.
            let unit = (1u128 << 64) as f64;
            let (z_row, dz) = ((z_row * unit).round() / unit, (dz * unit).round() / unit);
            for x in 0..w {
                let got = depth_at(z_row, dz, x);
                let want = exact(z_row, dz, x);
                if want != 0.0 {
                    let rel = ((got - want) / want).abs();
                    assert!(
                        rel < proto::depth::TIE / 1024.0,
                        "row ({z_row}, {dz}) column {x}: {got} against {want}, {rel:e}"
                    );
                }
            }
        }
    }
}
