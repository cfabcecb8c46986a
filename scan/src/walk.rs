//! Walking a polygon's scanlines: the covered spans of each row, with their depth.

use crate::depth::{depth_at, Depth, DepthPlane};
use crate::edges::{ActiveEdgeTable, EdgeTable, Outline};
use proto::raster::{centres_in_clamped, Point};
use proto::Polygon;
use std::convert::Infallible;
use std::ops::Range;

/// Pixels `x0..x1` (end exclusive) of row `y` covered by one polygon, on its depth plane:
/// pixel x has depth `z_row + x·dz` ([`depth_at`]). `z_row` is the plane's depth at the
/// centre of column 0 of the row, so every span of a row, and every piece of a split
/// polygon, gives a pixel the same depth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span {
    pub y: u32,
    pub x0: u32,
    pub x1: u32,
    pub z_row: Depth,
    pub dz: Depth,
}

impl Span {
    /// The depth of pixel `x` of the row.
    #[inline]
    pub fn depth(&self, x: u32) -> Depth {
        depth_at(self.z_row, self.dz, x)
    }

    /// The span's columns.
    #[inline]
    pub fn columns(&self) -> Range<u32> {
        self.x0..self.x1
    }
}

/// The scan conversion of one polygon at a time (the thesis's SCAN.CONVERTER without its
/// output), its tables reused from polygon to polygon.
#[derive(Debug, Default)]
pub struct SpanWalker {
    et: EdgeTable,
    aet: ActiveEdgeTable,
    /// The loaded polygon's outline, snapped (docs/DESIGN.md, "Coverage").
    outline: Outline,
}

impl SpanWalker {
    pub fn new() -> Self {
        SpanWalker::default()
    }

    /// Loads a polygon and builds its Edge Table: the rows of a screen `height` rows high
    /// that it may cover, to be walked in order with [`SpanWalker::crossings`]. Empty when
    /// it covers nothing: fewer than three vertices, every vertex on one line, or no edge
    /// across a scanline centre on the screen.
    pub fn start(&mut self, polygon: &Polygon, height: u32) -> Range<i64> {
        self.start_in(polygon, 0..height)
    }

    /// [`SpanWalker::start`] for the rows of `band` only (a band of a frame drawn a few
    /// rows at a time): the rows of the band the polygon may cover.
    pub fn start_in(&mut self, polygon: &Polygon, band: Range<u32>) -> Range<i64> {
        if !self.outline.load(polygon) {
            return 0..0;
        }
        self.aet.clear();
        self.et.build_in(
            &self.outline.points,
            &self.outline.supports,
            &self.outline.rows,
            band,
        )
    }

    /// The sorted crossings of the loaded polygon's edges with the centre line of `row`,
    /// each as the first column whose centre is at or right of it: pairs `c0, c1` of them
    /// bound the covered columns `c0..c1` (even-odd). Rows must be those
    /// [`SpanWalker::start`] returned, in order, each once.
    pub fn crossings(&mut self, row: i64) -> &[i64] {
        self.aet.advance(row, &self.et)
    }

    /// The spans `polygon` covers on a `width`×`height` screen, top row first, left to
    /// right, each handed to `emit`. Returns the number of pixels covered.
    pub fn spans<E>(
        &mut self,
        polygon: &Polygon,
        width: u32,
        height: u32,
        emit: impl FnMut(Span) -> Result<(), E>,
    ) -> Result<u64, E> {
        self.spans_in(polygon, width, 0..height, emit)
    }

    /// [`SpanWalker::spans`] on the rows of `band` only: exactly the spans of those rows
    /// that the whole walk gives, at the cost of the polygon's edges and the band's rows.
    pub fn spans_in<E>(
        &mut self,
        polygon: &Polygon,
        width: u32,
        band: Range<u32>,
        mut emit: impl FnMut(Span) -> Result<(), E>,
    ) -> Result<u64, E> {
        let rows = self.start_in(polygon, band);
        if rows.is_empty() {
            return Ok(0);
        }
        let depth = DepthPlane::of(polygon);
        let mut covered = 0u64;
        for row in rows {
            let crossings = self.aet.advance(row, &self.et);
            covered += row_spans(crossings, row as u32, width, &depth, &mut emit)?;
        }
        Ok(covered)
    }

    /// [`SpanWalker::spans_in`] for an `emit` that cannot fail.
    pub fn for_each_span_in(
        &mut self,
        polygon: &Polygon,
        width: u32,
        band: Range<u32>,
        mut emit: impl FnMut(Span),
    ) -> u64 {
        let Ok(n) = self.spans_in(polygon, width, band, |s| {
            emit(s);
            Ok::<(), Infallible>(())
        });
        n
    }

    /// [`SpanWalker::spans`] for an `emit` that cannot fail.
    pub fn for_each_span(
        &mut self,
        polygon: &Polygon,
        width: u32,
        height: u32,
        mut emit: impl FnMut(Span),
    ) -> u64 {
        let Ok(n) = self.spans(polygon, width, height, |s| {
            emit(s);
            Ok::<(), Infallible>(())
        });
        n
    }
}

/// Row `y`'s spans from its sorted `crossings` (pairs `c0, c1`, even-odd), clamped to a
/// screen `width` wide, on the polygon's `depth` plane, each handed to `emit`: the one
/// step from crossings to spans of every walk. Returns the pixels covered.
#[inline]
fn row_spans<E>(
    crossings: &[i64],
    y: u32,
    width: u32,
    depth: &DepthPlane,
    emit: &mut impl FnMut(Span) -> Result<(), E>,
) -> Result<u64, E> {
    let (z_row, dz) = depth.row(y);
    let mut covered = 0;
    for pair in crossings.chunks_exact(2) {
        let cols = centres_in_clamped(pair[0], pair[1], width);
        if cols.is_empty() {
            continue;
        }
        covered += cols.len() as u64;
        emit(Span {
            y,
            x0: cols.start,
            x1: cols.end,
            z_row,
            dz,
        })?;
    }
    Ok(covered)
}

/// One polygon walked down the screen a band of rows at a time, its Edge Table built
/// once: what [`SpanWalker::spans_in`] gives band by band, without rebuilding the table
/// (loading the outline, setting up each edge's exact DDA) for every band. A method that
/// draws a frame one band at a time keeps one of these per polygon the band reaches, so
/// its memory is the active polygons' edges, not the screen.
#[derive(Debug, Default)]
pub struct BandWalk {
    et: EdgeTable,
    aet: ActiveEdgeTable,
    depth: Option<DepthPlane>,
    /// The rows not yet walked.
    rows: Range<i64>,
}

impl BandWalk {
    pub fn new() -> Self {
        BandWalk::default()
    }

    /// Loads `polygon` (its outline through `outline`, whose buffers are reused) for the
    /// rows `rows` of the screen. `false` when it covers none of them.
    pub fn start(&mut self, outline: &mut Outline, polygon: &Polygon, rows: Range<u32>) -> bool {
        self.aet.clear();
        if !outline.load(polygon) {
            self.rows = 0..0;
            self.depth = None;
            return false;
        }
        self.rows = self
            .et
            .build_in(&outline.points, &outline.supports, &outline.rows, rows);
        self.depth = Some(DepthPlane::of(polygon));
        !self.rows.is_empty()
    }

    /// Whether every row the polygon covers has been walked.
    pub fn done(&self) -> bool {
        self.rows.is_empty()
    }

    /// The spans of the rows of `band` on a screen `width` wide, exactly those of
    /// [`SpanWalker::spans_in`] for the band. Bands must come top to bottom without
    /// overlapping; the rows between two bands are stepped over. Returns the pixels
    /// covered.
    pub fn for_each_span_in(
        &mut self,
        width: u32,
        band: Range<u32>,
        mut emit: impl FnMut(Span),
    ) -> u64 {
        let Some(depth) = self.depth else {
            return 0;
        };
        let end = self.rows.end.min(band.end as i64);
        let mut covered = 0;
        let mut emit = |s| {
            emit(s);
            Ok::<(), Infallible>(())
        };
        while self.rows.start < end {
            let row = self.rows.start;
            self.rows.start += 1;
            let crossings = self.aet.advance(row, &self.et);
            if row >= band.start as i64 {
                let Ok(n) = row_spans(crossings, row as u32, width, &depth, &mut emit);
                covered += n;
            }
        }
        covered
    }
}

pub use proto::perspective::GUARD_BAND;

/// Checks that every vertex lies within [`GUARD_BAND`] screens of the screen
/// ([`proto::perspective::guard_band`]).
pub fn check_on_screen(polygon: &Polygon, width: u32, height: u32) -> Result<(), String> {
    let ((x0, x1), (y0, y1)) = (
        proto::perspective::guard_band(width),
        proto::perspective::guard_band(height),
    );
    for (i, v) in polygon.vertices.iter().enumerate() {
        if !((x0..=x1).contains(&v.x) && (y0..=y1).contains(&v.y)) {
            return Err(format!(
                "vertex {i} at ({:e}, {:e}) lies far outside the {width}x{height} screen; \
                 clip in eye space (clipplane left, right, top, bottom) before persp",
                v.x, v.y
            ));
        }
    }
    Ok(())
}

/// The centres a polygon covers on one row by the coverage rule, computed directly, one
/// centre at a time (no tables, no crossings: the parity of the edges spanning the row
/// that pass at or left of the centre, from the sign of an exact edge function): a
/// reference for the tests.
pub fn covered_on_row(points: &[proto::DVec2], row: i64) -> Vec<i64> {
    let points: Vec<Point> = points.iter().map(|&p| Point::snap(p)).collect();
    if points.len() < 3 || proto::raster::snapped_on_one_line(&points) {
        return Vec::new();
    }
    let (sub, half) = (proto::raster::SUBPIXEL, proto::raster::HALF);
    let yc = sub * row + half;
    let left = points
        .iter()
        .map(|p| p.x)
        .min()
        .unwrap_or(0)
        .div_euclid(sub)
        - 1;
    let right = points
        .iter()
        .map(|p| p.x)
        .max()
        .unwrap_or(0)
        .div_euclid(sub)
        + 1;
    (left..=right)
        .filter(|&c| {
            let xc = (sub * c + half) as i128;
            let n = points.len();
            let passed = (0..n)
                .filter(|&i| {
                    let (a, b) = (points[i], points[(i + 1) % n]);
                    let (t, u) = if a.y < b.y { (a, b) } else { (b, a) };
                    if !(t.y <= yc && yc < u.y) {
                        return false;
                    }
                    // The crossing x_t + (yc − y_t)·dx/dy lies at or left of the centre.
                    (xc - t.x as i128) * (u.y - t.y) as i128
                        >= (yc - t.y) as i128 * (u.x - t.x) as i128
                })
                .count();
            passed % 2 == 1
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poly(points: &[[f64; 3]]) -> Polygon {
        Polygon::from_xyz([10, 20, 30], points)
    }

    /// Every polygon's spans, in order.
    fn spans_of(w: u32, h: u32, polys: &[Polygon]) -> Vec<Span> {
        let mut walker = SpanWalker::new();
        let mut out = Vec::new();
        for p in polys {
            walker.for_each_span(p, w, h, |s| out.push(s));
        }
        out
    }

    /// A coverage map: how many polygons cover each pixel, row by row.
    fn coverage(w: u32, h: u32, polys: &[Polygon]) -> Vec<Vec<u32>> {
        let mut map = vec![vec![0; w as usize]; h as usize];
        for s in spans_of(w, h, polys) {
            for x in s.columns() {
                map[s.y as usize][x as usize] += 1;
            }
        }
        map
    }

    fn rows(spans: &[Span]) -> Vec<(u32, u32, u32)> {
        spans.iter().map(|s| (s.y, s.x0, s.x1)).collect()
    }

    #[test]
    fn square_covers_its_pixels_at_constant_depth() {
        let sq = poly(&[
            [1.0, 1.0, 0.5],
            [3.0, 1.0, 0.5],
            [3.0, 3.0, 0.5],
            [1.0, 3.0, 0.5],
        ]);
        let half = 0.5;
        let span = |y| Span {
            y,
            x0: 1,
            x1: 3,
            z_row: half,
            dz: 0.0,
        };
        assert_eq!(
            spans_of(4, 4, std::slice::from_ref(&sq)),
            vec![span(1), span(2)]
        );
        assert_eq!(span(1).depth(1), half);
        assert_eq!(SpanWalker::new().for_each_span(&sq, 4, 4, |_| {}), 4);
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
        assert_eq!(
            rows(&spans_of(6, 6, &[u])),
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
    fn degenerate_polygons_cover_nothing() {
        let polys = [
            poly(&[]),
            poly(&[[1.0, 1.0, 0.0]]),
            poly(&[[1.0, 1.0, 0.0], [3.0, 3.0, 0.0]]),
            poly(&[[1.1, 1.1, 0.0], [1.4, 1.1, 0.0], [1.4, 1.4, 0.0]]),
            poly(&[[-5.0, -5.0, 0.0], [-1.0, -5.0, 0.0], [-1.0, -1.0, 0.0]]),
        ];
        let mut walker = SpanWalker::new();
        for p in &polys {
            assert_eq!(walker.for_each_span(p, 4, 4, |s| panic!("{s:?}")), 0);
        }
        assert_eq!(walker.start(&polys[2], 4), 0..0);
    }

    #[test]
    fn rows_and_crossings_step_by_step() {
        // A triangle (0,0)-(4,0)-(0,4): on row r the crossings are 0 and 4 − (r+½).
        let t = poly(&[[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]]);
        let mut walker = SpanWalker::new();
        assert_eq!(walker.start(&t, 3), 0..3);
        for row in 0..3 {
            // x = 4 − (r+½) is a centre's X: that centre is the first one at or right
            // of it, column 3 − r.
            assert_eq!(walker.crossings(row), &[0, 3 - row]);
        }
    }

    #[test]
    fn clamped_to_the_screen() {
        let big = poly(&[[-1e9, -1e9, 1.0], [1e9, -1e9, 1.0], [0.0, 1e9, 1.0]]);
        assert_eq!(rows(&spans_of(3, 2, &[big])), vec![(0, 0, 3), (1, 0, 3)]);
    }

    #[test]
    fn depth_follows_the_plane() {
        // depth = X/8 + Y/16: at (c+½, r+½), (c+½)/8 + (r+½)/16.
        let p = |x: f64, y: f64| [x, y, x / 8.0 + y / 16.0];
        let sq = poly(&[p(0.0, 0.0), p(4.0, 0.0), p(4.0, 4.0), p(0.0, 4.0)]);
        let spans = spans_of(4, 4, std::slice::from_ref(&sq));
        assert_eq!(spans.len(), 4);
        for s in &spans {
            for x in s.columns() {
                let exact = (x as f64 + 0.5) / 8.0 + (s.y as f64 + 0.5) / 16.0;
                let z = s.depth(x);
                assert!((z - exact).abs() < 1e-15, "{s:?} {x}");
            }
        }
    }

    #[test]
    fn split_polygon_has_the_whole_ones_depths() {
        // The same plane, cut at X = 2.3: a pixel's depth does not depend on its span.
        let p = |x: f64, y: f64| [x, y, 0.3 + x * 0.01 + y * 0.02];
        let whole = poly(&[p(0.0, 0.0), p(6.0, 0.0), p(6.0, 4.0), p(0.0, 4.0)]);
        let left = poly(&[p(0.0, 0.0), p(2.3, 0.0), p(2.3, 4.0), p(0.0, 4.0)]);
        let right = poly(&[p(2.3, 0.0), p(6.0, 0.0), p(6.0, 4.0), p(2.3, 4.0)]);
        let pixels = |polys: &[Polygon]| {
            let mut v: Vec<(u32, u32, f64)> = spans_of(6, 4, polys)
                .iter()
                .flat_map(|s| s.columns().map(move |x| (s.y, x, s.depth(x))))
                .collect();
            v.sort_by_key(|a| (a.0, a.1));
            v
        };
        let w = pixels(&[whole]);
        assert_eq!(w.len(), 24);
        let s = pixels(&[left, right]);
        assert_eq!(s.len(), 24);
        // Planes fitted to different vertices agree to rounding.
        for (a, b) in w.iter().zip(&s) {
            assert_eq!((a.0, a.1), (b.0, b.1));
            assert!(
                !crate::takes(a.2, b.2) && !crate::takes(b.2, a.2),
                "{a:?} {b:?}"
            );
        }
    }

    #[test]
    fn a_polygon_on_one_line_covers_nothing() {
        // Its centres on the line would otherwise be claimed by crossings that round
        // apart (found by tests/tests/surfaces/degenerate.rs and the fuzzer).
        let line = poly(&[[16.5, 47.5, 0.5], [32.0, 32.0, 0.5], [47.5, 16.5, 0.5]]);
        assert_eq!(spans_of(64, 64, &[line]), vec![]);
        let line = poly(&[[0.0, 0.0, 0.7], [4.0, 4.0, 0.2], [2.0, 2.0, 0.9]]);
        assert_eq!(spans_of(4, 4, &[line]), vec![]);
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
    fn an_error_from_emit_stops_the_walk() {
        let sq = poly(&[
            [0.0, 0.0, 0.0],
            [4.0, 0.0, 0.0],
            [4.0, 4.0, 0.0],
            [0.0, 4.0, 0.0],
        ]);
        let mut seen = 0;
        let r = SpanWalker::new().spans(&sq, 4, 4, |s| {
            seen += 1;
            if s.y == 1 {
                Err("stop")
            } else {
                Ok(())
            }
        });
        assert_eq!((r, seen), (Err("stop"), 2));
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
                let points: Vec<proto::DVec2> = pts.iter().map(|&(x, y)| proto::DVec2::new(x, y)).collect();
                let p = Polygon::from_xyz([1, 1, 1], &pts.iter().map(|&(x, y)| [x, y, 0.0]).collect::<Vec<_>>());
                let map = coverage(w, h, &[p]);
                for r in 0..h as i64 {
                    let mut want = vec![0u32; w as usize];
                    if !proto::raster::on_one_line(&points) {
                        for c in covered_on_row(&points, r) {
                            if (0..w as i64).contains(&c) {
                                want[c as usize] += 1;
                            }
                        }
                    }
                    prop_assert_eq!(&map[r as usize], &want, "row {}", r);
                }
            }

            /// Walking a polygon a band of rows at a time gives exactly the spans of the
            /// whole walk, band by band.
            #[test]
            fn bands_give_the_whole_walks_spans(
                pts in prop::collection::vec((-4.0f64..20.0, -4.0f64..20.0, 0.0f64..1.0), 3..9),
                band in 1u32..6,
            ) {
                let (w, h) = (16u32, 16u32);
                let p = Polygon::from_xyz([1, 1, 1], &pts.iter().map(|&(x, y, z)| [x, y, z]).collect::<Vec<_>>());
                let whole = spans_of(w, h, std::slice::from_ref(&p));
                let mut banded = Vec::new();
                let mut walker = SpanWalker::new();
                let mut r0 = 0;
                while r0 < h {
                    walker.for_each_span_in(&p, w, r0..(r0 + band).min(h), |s| banded.push(s));
                    r0 += band;
                }
                prop_assert_eq!(banded, whole);
            }

            /// A polygon walked band after band by one [`BandWalk`] (its table built
            /// once) gives exactly the spans of the whole walk, bands skipped or not.
            #[test]
            fn a_band_walk_gives_the_whole_walks_spans(
                pts in prop::collection::vec((-4.0f64..20.0, -4.0f64..20.0, 0.0f64..1.0), 3..9),
                band in 1u32..6,
                first in 0u32..8,
                skip in 0u32..4,
            ) {
                let (w, h) = (16u32, 16u32);
                let p = Polygon::from_xyz([1, 1, 1], &pts.iter().map(|&(x, y, z)| [x, y, z]).collect::<Vec<_>>());
                let mut walker = SpanWalker::new();
                let mut outline = Outline::default();
                let mut walk = BandWalk::new();
                let started = walk.start(&mut outline, &p, first..h);
                let (mut banded, mut want) = (Vec::new(), Vec::new());
                let mut r0 = first;
                let mut i = 0;
                while r0 < h {
                    let b = r0..(r0 + band).min(h);
                    // Every third band is skipped when `skip` says so.
                    if skip == 0 || i % 3 != skip % 3 {
                        walk.for_each_span_in(w, b.clone(), |s| banded.push(s));
                        walker.for_each_span_in(&p, w, b, |s| want.push(s));
                    }
                    r0 += band;
                    i += 1;
                }
                prop_assert_eq!(&banded, &want);
                prop_assert!(started || want.is_empty());
                // An empty band at the bottom steps over what is left.
                walk.for_each_span_in(w, h..h, |s| banded.push(s));
                prop_assert!(walk.done());
                prop_assert_eq!(banded.len(), want.len());
            }

            /// A jittered grid cut into triangles, reaching past the screen, covers every
            /// pixel exactly once: no cracks, no double cover (docs/DESIGN.md, "Coverage").
            #[test]
            fn a_mesh_covers_every_pixel_once(
                // Up to 0.2 of a cell keeps every quad convex, so either diagonal cuts it cleanly.
                jitter in prop::collection::vec((-0.2f64..0.2, -0.2f64..0.2), 36),
                flips in prop::collection::vec(any::<bool>(), 25),
            ) {
                // A 6x6 lattice of points 3.4 apart from −1, so the mesh covers 0..15.
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
