//! # scanconv: screen-space polygons → fragments (thesis chapter 4.2.2, Appendix 3)
//!
//! The scan converter of the Z-buffer HSE algorithm. For each polygon it
//!
//! 1. takes the polygon's plane `a·X + b·Y + c·Z + d = 0` from the stream when persp
//!    recorded it (the whole polygon's plane, shared by every piece a splitter tree cut
//!    it into), or else finds it by Newell's method over all its vertices (Appendix 3.4;
//!    the occam code used three vertices and failed when they were collinear),
//! 2. builds an [`EdgeTable`]: one bucket per scanline, holding the edges whose first
//!    scanline it is (Appendix 3.1),
//! 3. walks the scanlines top to bottom, moving each bucket into the [`ActiveEdgeTable`]
//!    (MOVE.ET.BUCKET.TO.AET), dropping edges past their last scanline (UPDATE.AET),
//!    sorting the crossings (the thesis's BUBBLESORT) and filling between pairs of them,
//! 4. gives every covered pixel its depth on the plane, stepping by `−a/c` along the row
//!    (Appendix 3.3), in fixed point.
//!
//! Coverage (docs/DESIGN.md, "Coverage") comes from [`proto::raster`]: pixel (c, r) is covered when
//! its centre (c+½, r+½) is inside by the even-odd rule, a centre on an edge going to the
//! polygon for which that edge is a left or top edge. On scanline r the crossings of the
//! active edges with Y = r+½ are sorted, x₀ ≤ x₁ ≤ x₂ ≤ …, and the centres in
//! [x₀, x₁), [x₂, x₃), … are covered. Pairing sorted crossings is the even-odd rule
//! itself, so concave polygons, self-intersecting ones (a bowtie) and the zero-width
//! connecting edges Sutherland–Hodgman leaves when it cuts a concave polygon all come out
//! right.
//!
//! Instead of stepping each edge's crossing by 1/m from scanline to scanline (Appendix
//! 3.3 i), each crossing is evaluated from the edge's top end ([`Edge::x_at`]), so two
//! polygons that share an edge compute identical crossings: no pixel is covered twice or
//! missed along a shared edge.An edge that is a piece of a longer one cut by a splitter
//! carries that edge (its support) and is crossed where the whole edge is
//! ([`polygon_edge`]), so a split polygon covers exactly the pixels of the whole.

use proto::fragment::depth_to_fixed;
use proto::raster::{centres_in, centres_in_clamped, Edge};
use proto::{DVec2, DVec3, DVec4, Fragment, Polygon};

/// How covered pixels are sent on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Output {
    /// Runs of pixels on one row, depth at the first and a step (the default).
    #[default]
    Spans,
    /// One record per pixel, the thesis's (colour, x, y, depth) quadruplet.
    Pixels,
}

/// Counts for `--stats`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Polygons read.
    pub polygons_in: u64,
    /// Polygons that covered at least one pixel.
    pub polygons_drawn: u64,
    /// Span records written.
    pub spans: u64,
    /// Pixels covered (whether sent as spans or as pixels).
    pub pixels: u64,
}

/// An Active Edge Table entry: the edge and the first scanline below its last one.
#[derive(Clone, Copy, Debug)]
struct ActiveEdge {
    edge: Edge,
    /// Rows `r` with `r < end_row` still cross the edge (the thesis's y_max).
    end_row: i64,
}

/// The Edge Table (Appendix 3.1): one bucket per scanline of the polygon's (screen-clamped)
/// extent, each holding the edges whose first covered scanline it is. Buckets keep their
/// allocations from polygon to polygon.
#[derive(Debug, Default)]
pub struct EdgeTable {
    /// Screen row of bucket 0.
    first_row: i64,
    buckets: Vec<Vec<ActiveEdge>>,
    /// Buckets in use for the current polygon.
    len: usize,
}

impl EdgeTable {
    /// CLEAR, then INSERT.ET.EDGE for each non-horizontal edge of the polygon that crosses
    /// a scanline centre on the screen. Returns the rows to walk.
    /// `supports` is empty or holds, per edge, the screen ends of the original edge it is
    /// a piece of ([`polygon_edge`]).
    fn build(
        &mut self,
        points: &[DVec2],
        supports: &[Option<[DVec2; 2]>],
        height: u32,
    ) -> std::ops::Range<i64> {
        for b in &mut self.buckets[..self.len] {
            b.clear();
        }
        self.len = 0;
        let edges = || {
            (0..points.len()).filter_map(move |i| {
                let edge = polygon_edge(points, supports, i)?;
                // The edge's rows, clamped to the screen: rows above 0 are never walked.
                let rows = edge.rows();
                let start = rows.start.max(0);
                let end = rows.end.min(height as i64);
                (start < end).then_some((start, ActiveEdge { edge, end_row: end }))
            })
        };
        let Some(first) = edges().map(|(s, _)| s).min() else {
            return 0..0;
        };
        let last = edges().map(|(_, e)| e.end_row).max().unwrap_or(first);
        self.first_row = first;
        self.len = (last - first) as usize;
        if self.buckets.len() < self.len {
            self.buckets.resize_with(self.len, Vec::new);
        }
        for (start, e) in edges() {
            self.buckets[(start - first) as usize].push(e);
        }
        first..last
    }

    /// The bucket of edges that start on screen row `row`.
    fn bucket(&self, row: i64) -> &[ActiveEdge] {
        &self.buckets[(row - self.first_row) as usize]
    }
}

/// Edge i of a polygon (vertex i → vertex i+1): rows from its own ends, crossings from
/// its support if a splitter cut it out of a longer edge ([`Edge::with_support`]), so that
/// the pieces of a split polygon cover exactly the pixels the whole covers.
#[inline]
pub fn polygon_edge(points: &[DVec2], supports: &[Option<[DVec2; 2]>], i: usize) -> Option<Edge> {
    let (a, b) = (points[i], points[(i + 1) % points.len()]);
    match supports.get(i).copied().flatten() {
        Some([sa, sb]) => Edge::with_support(a, b, sa, sb),
        None => Edge::new(a, b),
    }
}

/// The Active Edge Table (Appendix 3.1): the edges the current scanline crosses.
#[derive(Debug, Default)]
pub struct ActiveEdgeTable {
    edges: Vec<ActiveEdge>,
    /// Scratch: this scanline's crossings, sorted.
    crossings: Vec<f64>,
}

impl ActiveEdgeTable {
    /// UPDATE.AET's removal half, then MOVE.ET.BUCKET.TO.AET for `row`, then the crossings
    /// at the scanline centre `row + ½`, sorted (the thesis's BUBBLESORT; the list is
    /// nearly sorted from row to row, which an insertion-style sort handles in one pass).
    fn advance(&mut self, row: i64, bucket: &[ActiveEdge]) -> &[f64] {
        self.edges.retain(|e| e.end_row > row);
        self.edges.extend_from_slice(bucket);
        let yc = row as f64 + 0.5;
        self.crossings.clear();
        self.crossings
            .extend(self.edges.iter().map(|e| e.edge.x_at(yc)));
        self.crossings.sort_unstable_by(f64::total_cmp);
        &self.crossings
    }
}

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
    /// the screen vertices (X, Y, depth): a hand-written stream, or persp's eye-z mode.
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
    /// A pixel's depth is `z_row + x·dz`, whatever span it is in.
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

/// The depth of column `x` on a row: `z_row + x·dz` in 128 bits, saturated to `i64`.
#[inline]
pub fn depth_at(z_row: i64, dz: i64, x: u32) -> i64 {
    let z = z_row as i128 + x as i128 * dz as i128;
    z.clamp(i64::MIN as i128, i64::MAX as i128) as i64
}

/// The scan converter for one screen, its tables reused from polygon to polygon.
#[derive(Debug)]
pub struct ScanConverter {
    width: u32,
    height: u32,
    output: Output,
    et: EdgeTable,
    aet: ActiveEdgeTable,
    points: Vec<DVec2>,
    supports: Vec<Option<[DVec2; 2]>>,
    pub stats: Stats,
}

impl ScanConverter {
    pub fn new(width: u32, height: u32, output: Output) -> Self {
        ScanConverter {
            width,
            height,
            output,
            et: EdgeTable::default(),
            aet: ActiveEdgeTable::default(),
            points: Vec::new(),
            supports: Vec::new(),
            stats: Stats::default(),
        }
    }

    /// Scan-converts one polygon: its colour record, then its spans or pixels, each handed
    /// to `emit` in order (top row first, left to right). A polygon of fewer than three
    /// vertices covers nothing but still emits its colour record, to keep the numbering.
    pub fn convert<E>(
        &mut self,
        polygon: &Polygon,
        emit: &mut impl FnMut(Fragment) -> Result<(), E>,
    ) -> Result<(), E> {
        self.stats.polygons_in += 1;
        emit(Fragment::Polygon(polygon.colour))?;
        if polygon.vertices.len() < 3 {
            return Ok(());
        }
        self.points.clear();
        self.points
            .extend(polygon.vertices.iter().map(|v| DVec2::new(v.x, v.y)));
        self.supports.clear();
        self.supports.extend(
            polygon
                .supports
                .iter()
                .map(|s| s.map(|[a, b]| [DVec2::new(a.x, a.y), DVec2::new(b.x, b.y)])),
        );
        if proto::raster::on_one_line(&self.points) {
            return Ok(());
        }
        let rows = self.et.build(&self.points, &self.supports, self.height);
        if rows.is_empty() {
            return Ok(());
        }
        let depth = DepthPlane::of(polygon);
        self.aet.edges.clear();
        let mut covered = 0u64;
        for row in rows {
            let crossings = self.aet.advance(row, self.et.bucket(row));
            let y = row as u32;
            let (z_row, dz) = depth.row(y);
            for pair in crossings.chunks_exact(2) {
                let cols = centres_in_clamped(pair[0], pair[1], self.width);
                if cols.is_empty() {
                    continue;
                }
                covered += cols.len() as u64;
                match self.output {
                    Output::Spans => {
                        self.stats.spans += 1;
                        emit(Fragment::Span {
                            y,
                            x0: cols.start,
                            x1: cols.end,
                            z0: depth_at(z_row, dz, cols.start),
                            dz,
                        })?;
                    }
                    Output::Pixels => {
                        for x in cols {
                            emit(Fragment::Pixel {
                                x,
                                y,
                                z: depth_at(z_row, dz, x),
                            })?;
                        }
                    }
                }
            }
        }
        if covered > 0 {
            self.stats.polygons_drawn += 1;
        }
        self.stats.pixels += covered;
        Ok(())
    }
}

/// How far outside the screen, in screen widths and heights, a vertex may lie. A clipped
/// stream's vertices are on the screen (to rounding); a vertex far outside means the
/// stream was not clipped, and crossings computed from such coordinates cancel.
pub const GUARD_BAND: f64 = 16.0;

/// Checks that every vertex lies within [`GUARD_BAND`] screens of the screen.
pub fn check_on_screen(polygon: &Polygon, width: u32, height: u32) -> Result<(), String> {
    let (w, h) = (width as f64, height as f64);
    for (i, v) in polygon.vertices.iter().enumerate() {
        let inside = |c: f64, size: f64| -GUARD_BAND * size <= c && c <= (GUARD_BAND + 1.0) * size;
        if !(inside(v.x, w) && inside(v.y, h)) {
            return Err(format!(
                "vertex {i} at ({:e}, {:e}) lies far outside the {width}x{height} screen; \
                 clip in eye space (clipplane left, right, top, bottom) before persp",
                v.x, v.y
            ));
        }
    }
    Ok(())
}

/// The centres a polygon covers on one row by the coverage rule, computed directly (no
/// tables): a reference for the tests.
pub fn covered_on_row(points: &[DVec2], row: i64) -> Vec<i64> {
    let yc = row as f64 + 0.5;
    let mut xs: Vec<f64> = (0..points.len())
        .filter_map(|i| Edge::new(points[i], points[(i + 1) % points.len()]))
        .filter(|e| e.rows().contains(&row))
        .map(|e| e.x_at(yc))
        .collect();
    xs.sort_by(f64::total_cmp);
    xs.chunks_exact(2)
        .flat_map(|p| centres_in(p[0], p[1]))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proto::fragment::DEPTH_ONE;

    fn poly(points: &[[f64; 3]]) -> Polygon {
        Polygon::from_xyz([10, 20, 30], points)
    }

    /// Runs the converter and returns its fragments.
    fn run(w: u32, h: u32, output: Output, polys: &[Polygon]) -> Vec<Fragment> {
        let mut sc = ScanConverter::new(w, h, output);
        let mut out = Vec::new();
        for p in polys {
            sc.convert(p, &mut |f| {
                out.push(f);
                Ok::<_, ()>(())
            })
            .unwrap();
        }
        out
    }

    /// A coverage map: how many polygons cover each pixel, row by row.
    fn coverage(w: u32, h: u32, polys: &[Polygon]) -> Vec<Vec<u32>> {
        let mut map = vec![vec![0; w as usize]; h as usize];
        for f in run(w, h, Output::Pixels, polys) {
            if let Fragment::Pixel { x, y, .. } = f {
                map[y as usize][x as usize] += 1;
            }
        }
        map
    }

    fn spans(frags: &[Fragment]) -> Vec<(u32, u32, u32)> {
        frags
            .iter()
            .filter_map(|f| match *f {
                Fragment::Span { y, x0, x1, .. } => Some((y, x0, x1)),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn square_covers_its_pixels_at_constant_depth() {
        let sq = poly(&[
            [1.0, 1.0, 0.5],
            [3.0, 1.0, 0.5],
            [3.0, 3.0, 0.5],
            [1.0, 3.0, 0.5],
        ]);
        let frags = run(4, 4, Output::Spans, &[sq]);
        let half = depth_to_fixed(0.5);
        assert_eq!(
            frags,
            vec![
                Fragment::Polygon([10, 20, 30]),
                Fragment::Span {
                    y: 1,
                    x0: 1,
                    x1: 3,
                    z0: half,
                    dz: 0
                },
                Fragment::Span {
                    y: 2,
                    x0: 1,
                    x1: 3,
                    z0: half,
                    dz: 0
                },
            ]
        );
    }

    #[test]
    fn triangle_top_left_tie() {
        // Vertices on pixel centres: (0.5,0.5), (3.5,0.5), (0.5,3.5). The top edge
        // Y = 0.5 is horizontal (a top edge: its centres belong), the left edge X = 0.5
        // is a left edge (its centres belong), the hypotenuse X + Y = 4 is a right edge
        // (its centres do not).
        let t = poly(&[[0.5, 0.5, 0.0], [3.5, 0.5, 0.0], [0.5, 3.5, 0.0]]);
        assert_eq!(
            coverage(4, 4, &[t]),
            vec![
                vec![1, 1, 1, 0],
                vec![1, 1, 0, 0],
                vec![1, 0, 0, 0],
                vec![0, 0, 0, 0],
            ]
        );
    }

    #[test]
    fn triangles_sharing_a_diagonal_cover_every_pixel_once() {
        let a = poly(&[[0.0, 0.0, 0.0], [8.0, 0.0, 0.0], [0.0, 8.0, 0.0]]);
        let b = poly(&[[8.0, 0.0, 0.0], [8.0, 8.0, 0.0], [0.0, 8.0, 0.0]]);
        assert_eq!(coverage(8, 8, &[a, b]), vec![vec![1; 8]; 8]);
        // And through pixel centres, off the grid, sloping both ways.
        let a = poly(&[[0.0, 0.0, 0.0], [8.0, 0.5, 0.0], [0.2, 7.5, 0.0]]);
        let b = poly(&[
            [8.0, 0.5, 0.0],
            [8.0, 8.0, 0.0],
            [0.0, 8.0, 0.0],
            [0.2, 7.5, 0.0],
        ]);
        let c = poly(&[[0.0, 0.0, 0.0], [0.2, 7.5, 0.0], [0.0, 8.0, 0.0]]);
        let d = poly(&[[0.0, 0.0, 0.0], [8.0, 0.0, 0.0], [8.0, 0.5, 0.0]]);
        assert_eq!(coverage(8, 8, &[a, b, c, d]), vec![vec![1; 8]; 8]);
    }

    #[test]
    fn concave_u_shape() {
        // A U: two prongs joined at the bottom, opening upwards.
        let u = poly(&[
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 3.0, 0.0],
            [4.0, 3.0, 0.0],
            [4.0, 0.0, 0.0],
            [6.0, 0.0, 0.0],
            [6.0, 5.0, 0.0],
            [0.0, 5.0, 0.0],
        ]);
        let frags = run(6, 6, Output::Spans, &[u]);
        assert_eq!(
            spans(&frags),
            vec![
                (0, 0, 2),
                (0, 4, 6),
                (1, 0, 2),
                (1, 4, 6),
                (2, 0, 2),
                (2, 4, 6),
                (3, 0, 6),
                (4, 0, 6),
            ]
        );
    }

    #[test]
    fn bowtie_is_even_odd() {
        // Self-intersecting: a left and a right triangle meeting at (2, 2).
        let bowtie = poly(&[
            [0.0, 0.0, 0.0],
            [4.0, 4.0, 0.0],
            [4.0, 0.0, 0.0],
            [0.0, 4.0, 0.0],
        ]);
        assert_eq!(
            coverage(4, 4, &[bowtie]),
            vec![
                // Row 0: crossings 0, 0.5, 3.5, 4. The centre 0.5 lies on the left
                // triangle's right edge (not its own), 3.5 on the right one's left edge.
                vec![0, 0, 0, 1],
                vec![1, 0, 1, 1],
                vec![1, 0, 1, 1],
                vec![0, 0, 0, 1],
            ]
        );
        // A pentagram: the even-odd rule leaves its centre pentagon empty.
        let star: Vec<[f64; 3]> = (0..5)
            .map(|k| {
                let t = std::f64::consts::TAU * (k * 2) as f64 / 5.0;
                [20.0 + 19.0 * t.sin(), 20.0 - 19.0 * t.cos(), 0.0]
            })
            .collect();
        let map = coverage(40, 40, &[poly(&star)]);
        assert_eq!(map[20][20], 0);
        assert_eq!(map[5][20], 1);
    }

    #[test]
    fn sutherland_hodgman_connecting_edge() {
        // A U clipped by Y ≤ 2 the way Sutherland–Hodgman does it: one polygon whose
        // prongs are joined along Y = 2 by an edge that runs there and back.
        let clipped = poly(&[
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 2.0, 0.0],
            [4.0, 2.0, 0.0],
            [4.0, 0.0, 0.0],
            [6.0, 0.0, 0.0],
            [6.0, 2.0, 0.0],
            [0.0, 2.0, 0.0],
        ]);
        let map = coverage(6, 3, &[clipped]);
        assert_eq!(
            map,
            vec![vec![1, 1, 0, 0, 1, 1], vec![1, 1, 0, 0, 1, 1], vec![0; 6]]
        );
    }

    #[test]
    fn degenerate_polygons_emit_only_their_colour() {
        let frags = run(
            4,
            4,
            Output::Spans,
            &[
                poly(&[]),
                poly(&[[1.0, 1.0, 0.0]]),
                poly(&[[1.0, 1.0, 0.0], [3.0, 3.0, 0.0]]),
                poly(&[[1.1, 1.1, 0.0], [1.4, 1.1, 0.0], [1.4, 1.4, 0.0]]),
                poly(&[[-5.0, -5.0, 0.0], [-1.0, -5.0, 0.0], [-1.0, -1.0, 0.0]]),
            ],
        );
        assert_eq!(frags, vec![Fragment::Polygon([10, 20, 30]); 5]);
    }

    #[test]
    fn clamped_to_the_screen() {
        let big = poly(&[[-1e9, -1e9, 1.0], [1e9, -1e9, 1.0], [0.0, 1e9, 1.0]]);
        let frags = run(3, 2, Output::Spans, &[big]);
        assert_eq!(spans(&frags), vec![(0, 0, 3), (1, 0, 3)]);
    }

    #[test]
    fn depth_follows_the_plane() {
        // depth = X/8 + Y/16: at (c+½, r+½), (c+½)/8 + (r+½)/16.
        let p = |x: f64, y: f64| [x, y, x / 8.0 + y / 16.0];
        let sq = poly(&[p(0.0, 0.0), p(4.0, 0.0), p(4.0, 4.0), p(0.0, 4.0)]);
        let frags = run(4, 4, Output::Pixels, std::slice::from_ref(&sq));
        for f in &frags[1..] {
            let Fragment::Pixel { x, y, z } = *f else {
                panic!()
            };
            let exact = (x as f64 + 0.5) / 8.0 + (y as f64 + 0.5) / 16.0;
            assert!((z as f64 / DEPTH_ONE - exact).abs() < 1e-9, "{f:?}");
        }
        // Spans carry the same depths: z0 + (x − x0)·dz.
        let spans = run(4, 4, Output::Spans, &[sq]);
        let mut from_spans = vec![];
        for f in &spans[1..] {
            let Fragment::Span { y, x0, x1, z0, dz } = *f else {
                panic!()
            };
            for x in x0..x1 {
                from_spans.push(Fragment::Pixel {
                    x,
                    y,
                    z: z0 + (x - x0) as i64 * dz,
                });
            }
        }
        assert_eq!(from_spans, frags[1..]);
    }

    #[test]
    fn split_polygon_has_the_whole_ones_depths() {
        // The same plane, cut at X = 2.3: a pixel's depth does not depend on its span.
        let p = |x: f64, y: f64| [x, y, 0.3 + x * 0.01 + y * 0.02];
        let whole = poly(&[p(0.0, 0.0), p(6.0, 0.0), p(6.0, 4.0), p(0.0, 4.0)]);
        let left = poly(&[p(0.0, 0.0), p(2.3, 0.0), p(2.3, 4.0), p(0.0, 4.0)]);
        let right = poly(&[p(2.3, 0.0), p(6.0, 0.0), p(6.0, 4.0), p(2.3, 4.0)]);
        let pixels = |polys: &[Polygon]| {
            let mut v: Vec<_> = run(6, 4, Output::Pixels, polys)
                .into_iter()
                .filter(|f| matches!(f, Fragment::Pixel { .. }))
                .collect();
            v.sort_by_key(|f| match *f {
                Fragment::Pixel { x, y, .. } => (y, x),
                _ => unreachable!(),
            });
            v
        };
        let w = pixels(&[whole]);
        assert_eq!(w.len(), 24);
        let ends = |f: &Fragment| match *f {
            Fragment::Pixel { z, .. } => z,
            _ => unreachable!(),
        };
        let s = pixels(&[left, right]);
        assert_eq!(s.len(), 24);
        // Planes fitted to different vertices agree to rounding.
        for (a, b) in w.iter().zip(&s) {
            assert!((ends(a) - ends(b)).abs() < 64, "{a:?} {b:?}");
        }
    }

    #[test]
    fn a_polygon_on_one_line_covers_nothing() {
        // Its centres on the line would otherwise be claimed by crossings that round
        // apart (found by tests/tests/degenerate.rs and the fuzzer).
        let line = poly(&[[16.5, 47.5, 0.5], [32.0, 32.0, 0.5], [47.5, 16.5, 0.5]]);
        assert_eq!(
            run(64, 64, Output::Spans, &[line]),
            vec![Fragment::Polygon([10, 20, 30])]
        );
    }

    #[test]
    fn vertices_far_off_screen_are_refused() {
        let near = poly(&[[-100.0, 0.0, 0.5], [90.0, 0.0, 0.5], [0.0, 9.0, 0.5]]);
        assert_eq!(check_on_screen(&near, 8, 8), Ok(()));
        let far = poly(&[
            [1.76e156, 0.0, 0.5],
            [20.0, -4.28e227, 0.5],
            [18.0, 3.0, 0.5],
        ]);
        assert_eq!(
            check_on_screen(&far, 64, 64).unwrap_err(),
            "vertex 0 at (1.76e156, 0e0) lies far outside the 64x64 screen; clip in eye space (clipplane left, right, top, bottom) before persp"
        );
    }

    #[test]
    fn edge_on_polygon_takes_the_nearest_vertex_depth() {
        // All vertices on one line: no area, no plane, no pixel, no NaN.
        let line = poly(&[[0.0, 0.0, 0.7], [4.0, 4.0, 0.2], [2.0, 2.0, 0.9]]);
        assert_eq!(DepthPlane::of(&line), DepthPlane::Flat(depth_to_fixed(0.2)));
        assert_eq!(run(4, 4, Output::Spans, &[line]).len(), 1);
    }

    #[test]
    fn stats_count() {
        let sq = poly(&[
            [1.0, 1.0, 0.5],
            [3.0, 1.0, 0.5],
            [3.0, 3.0, 0.5],
            [1.0, 3.0, 0.5],
        ]);
        let mut sc = ScanConverter::new(4, 4, Output::Spans);
        for p in [sq, poly(&[])] {
            sc.convert(&p, &mut |_| Ok::<_, ()>(())).unwrap();
        }
        assert_eq!(
            sc.stats,
            Stats {
                polygons_in: 2,
                polygons_drawn: 1,
                spans: 2,
                pixels: 4
            }
        );
    }

    mod properties {
        use super::*;
        use proptest::prelude::*;

        proptest! {
            /// The Edge Table and Active Edge Table find, row by row, exactly the centres
            /// the coverage rule gives when every edge is tested directly.
            #[test]
            fn tables_agree_with_the_rule(
                pts in prop::collection::vec((-4.0f64..20.0, -4.0f64..20.0), 3..9),
            ) {
                let (w, h) = (16u32, 16u32);
                let points: Vec<DVec2> = pts.iter().map(|&(x, y)| DVec2::new(x, y)).collect();
                let p = Polygon::from_xyz([1, 1, 1], &pts.iter().map(|&(x, y)| [x, y, 0.0]).collect::<Vec<_>>());
                let map = coverage(w, h, &[p]);
                for r in 0..h as i64 {
                    let mut want = vec![0u32; w as usize];
                    for c in covered_on_row(&points, r) {
                        if (0..w as i64).contains(&c) {
                            want[c as usize] += 1;
                        }
                    }
                    prop_assert_eq!(&map[r as usize], &want, "row {}", r);
                }
            }

            /// A jittered grid cut into triangles, reaching past the screen, covers every
            /// pixel exactly once: no cracks, no double cover (docs/DESIGN.md, "Coverage").
            #[test]
            fn a_mesh_covers_every_pixel_once(
                // Up to 0.2 of a cell keeps every quad convex, so either diagonal cuts it cleanly.
                jitter in prop::collection::vec((-0.2f64..0.2, -0.2f64..0.2), 36),
                flips in prop::collection::vec(any::<bool>(), 25),
            ) {
                // A 6x6 lattice of points 3.2 apart from −1, so the mesh covers 0..15.
                let at = |i: usize, j: usize| {
                    let (dx, dy) = if i == 0 || j == 0 || i == 5 || j == 5 {
                        (0.0, 0.0)
                    } else {
                        jitter[j * 6 + i]
                    };
                    [-1.0 + 3.4 * (i as f64 + dx), -1.0 + 3.4 * (j as f64 + dy), 0.0]
                };
                let mut tris = vec![];
                for j in 0..5 {
                    for i in 0..5 {
                        let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                        if flips[j * 5 + i] {
                            tris.push(poly(&[a, b, c]));
                            tris.push(poly(&[a, c, d]));
                        } else {
                            tris.push(poly(&[a, b, d]));
                            tris.push(poly(&[b, c, d]));
                        }
                    }
                }
                prop_assert_eq!(coverage(15, 15, &tris), vec![vec![1; 15]; 15]);
            }
        }
    }
}
