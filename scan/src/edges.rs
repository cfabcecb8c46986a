//! The Edge Table and the Active Edge Table (thesis Appendix 3.1).

use proto::raster::{Edge, EdgeWalk, Point};
use proto::Polygon;
use std::ops::Range;

/// An Edge Table entry: the edge's crossings from its first row on (an exact DDA, see
/// [`proto::raster::EdgeWalk`]) and the first scanline below its last one.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ActiveEdge {
    walk: EdgeWalk,
    /// Rows `r` with `r < end_row` still cross the edge (the thesis's y_max).
    end_row: i64,
}

/// The Edge Table (Appendix 3.1): the polygon's edges by the first scanline they cross,
/// the thesis's bucket of a scanline being the run of edges that start on it. Kept as one
/// sorted list rather than a bucket per scanline, so that its memory is the polygon's
/// edges whatever its height: the scan-line method keeps a table for every active polygon,
/// and 20,000 full-screen quads at 500 rows took 240 MB in buckets.
#[derive(Debug, Default)]
pub struct EdgeTable {
    /// The polygon's edges that cross a scanline centre in the band, with their first
    /// row, sorted by it (stably: edges starting on one row keep the polygon's order).
    edges: Vec<(i64, ActiveEdge)>,
    /// The first rows alone, in the same order, for the bucket look-up.
    starts: Vec<i64>,
    /// The edges alone, in the same order: a bucket is a slice of them.
    sorted: Vec<ActiveEdge>,
}

impl EdgeTable {
    /// CLEAR, then INSERT.ET.EDGE for each non-horizontal edge of the polygon that crosses
    /// a scanline centre on the screen. Returns the rows to walk (empty when none).
    /// `points` are the snapped screen vertices; `supports` is empty or holds, per edge,
    /// the snapped screen ends of the original edge it is a piece of; `rows` the first row
    /// at or below each vertex ([`proto::raster::vertex_rows`]).
    pub fn build(
        &mut self,
        points: &[Point],
        supports: &[Option<[Point; 2]>],
        rows: &[i64],
        height: u32,
    ) -> Range<i64> {
        self.build_in(points, supports, rows, 0..height)
    }

    /// [`EdgeTable::build`] for the scanlines `band` only: each edge's rows are clamped
    /// to the band, so a band of a tall polygon costs its edges and the band's rows, not
    /// the rows above it. Crossings are exact (integer DDA started at the band's first
    /// row), so a row walked in a band is crossed exactly as in the whole walk.
    pub fn build_in(
        &mut self,
        points: &[Point],
        supports: &[Option<[Point; 2]>],
        rows: &[i64],
        band: Range<u32>,
    ) -> Range<i64> {
        self.edges.clear();
        self.starts.clear();
        self.sorted.clear();
        self.edges.extend((0..points.len()).filter_map(|i| {
            let edge = polygon_edge(points, supports, rows, i)?;
            // The edge's rows, clamped to the band (the screen, for a whole walk): rows
            // above it are never walked.
            let rows = edge.rows();
            let start = rows.start.max(band.start as i64);
            let end = rows.end.min(band.end as i64);
            (start < end).then(|| {
                let walk = edge.walk(start);
                (start, ActiveEdge { walk, end_row: end })
            })
        }));
        let Some(first) = self.edges.iter().map(|(s, _)| *s).min() else {
            return 0..0;
        };
        let last = self
            .edges
            .iter()
            .map(|(_, e)| e.end_row)
            .max()
            .unwrap_or(first);
        self.edges.sort_by_key(|(start, _)| *start);
        self.starts.extend(self.edges.iter().map(|(s, _)| *s));
        self.sorted.extend(self.edges.iter().map(|(_, e)| *e));
        first..last
    }
}

/// Edge i of a polygon (vertex i → vertex i+1): rows from the vertices' rows, crossings
/// from its support if a splitter cut it out of a longer edge ([`Edge::with_support`]),
/// so that the pieces of a split polygon cover exactly the pixels the whole covers. The
/// rasteriser's name for proto's function.
pub use proto::raster::polygon_edge;

/// A polygon's outline on the sub-pixel grid (docs/DESIGN.md, "Coverage"): its vertices
/// and its edges' supports snapped to 1/256 pixel, and the first row at or below each
/// vertex, which is what [`polygon_edge`] reads. Kept by whatever walks polygons one
/// after another (the span walker, the scan-line method's edge arena) and reloaded for
/// each, so that loading allocates nothing once the buffers have grown.
#[derive(Debug, Default)]
pub struct Outline {
    pub points: Vec<Point>,
    pub supports: Vec<Option<[Point; 2]>>,
    pub rows: Vec<i64>,
}

impl Outline {
    /// Loads `polygon`'s snapped outline. `false`, leaving nothing to draw, when it covers
    /// nothing: fewer than three vertices, every vertex on one line once snapped, or a
    /// vertex or support with no place on the screen (NaN, infinite). The stages refuse
    /// a polygon far off the screen before it gets here ([`crate::check_on_screen`]),
    /// and no snapped stand-in for a vertex at infinity would be the polygon.
    pub fn load(&mut self, polygon: &Polygon) -> bool {
        let finite = |v: &proto::DVec4| v.x.is_finite() && v.y.is_finite();
        if polygon.vertices.len() < 3
            || !polygon.vertices.iter().all(finite)
            || !polygon.supports.iter().flatten().flatten().all(finite)
        {
            return false;
        }
        let snap = |v: &proto::DVec4| Point {
            x: proto::raster::snap(v.x),
            y: proto::raster::snap(v.y),
        };
        self.points.clear();
        self.points.extend(polygon.vertices.iter().map(snap));
        self.supports.clear();
        self.supports.extend(
            polygon
                .supports
                .iter()
                .map(|s| s.as_ref().map(|[a, b]| [snap(a), snap(b)])),
        );
        let supports = self.supports.iter().flatten().flatten().copied();
        if proto::raster::snapped_covers_nothing(&self.points, supports) {
            return false;
        }
        proto::raster::vertex_rows(&self.points, &self.supports, &mut self.rows);
        true
    }

    /// Edge i of the loaded polygon (vertex i → vertex i+1), by [`polygon_edge`].
    #[inline]
    pub fn edge(&self, i: usize) -> Option<Edge> {
        polygon_edge(&self.points, &self.supports, &self.rows, i)
    }
}

/// The Active Edge Table (Appendix 3.1): the edges the current scanline crosses.
#[derive(Debug, Default)]
pub struct ActiveEdgeTable {
    edges: Vec<ActiveEdge>,
    /// The Edge Table's edges (in order of their first row) moved in so far.
    moved: usize,
    /// Scratch: this scanline's crossings, sorted, each as the first column whose centre
    /// is at or right of it (proto::raster's "crossings as columns").
    crossings: Vec<i64>,
}

impl ActiveEdgeTable {
    /// Empties the table for a new polygon.
    pub fn clear(&mut self) {
        self.edges.clear();
        self.moved = 0;
    }

    /// UPDATE.AET's removal half, then MOVE.ET.BUCKET.TO.AET for `row`, then the crossings
    /// at the scanline centre `row + ½`, sorted (the thesis's BUBBLESORT; the list is
    /// nearly sorted from row to row, which an insertion-style sort handles in one pass).
    /// Rows are walked in order, each once, from the table's first.
    ///
    /// The Edge Table's edges are sorted by first row, so the buckets are taken in turn
    /// from where the last one ended, not looked up; and a row crossed by two edges, most
    /// rows of most polygons, has its pair put in order with one comparison.
    pub fn advance(&mut self, row: i64, et: &EdgeTable) -> &[i64] {
        if self.edges.iter().any(|e| e.end_row <= row) {
            self.edges.retain(|e| e.end_row > row);
        }
        let waiting = &et.starts[self.moved..];
        let n = waiting.partition_point(|&s| s <= row);
        if n > 0 {
            self.edges
                .extend_from_slice(&et.sorted[self.moved..self.moved + n]);
            self.moved += n;
        }
        self.crossings.clear();
        // This row's crossing of each edge, then the DDA's step to the next row (Appendix
        // 3.3 i's x ← x + 1/m, here exact: an integer and its remainder).
        self.crossings.extend(self.edges.iter_mut().map(|e| {
            let c = e.walk.column;
            e.walk.step();
            c
        }));
        sort_crossings(&mut self.crossings);
        &self.crossings
    }
}

/// Sorts a row's crossings (columns) into the order in which they bound the covered
/// columns, pairs `c0, c1` of them (even-odd): the two of a convex polygon, the common
/// case, by one comparison, more by a sort.
#[inline]
pub fn sort_crossings(crossings: &mut [i64]) {
    if let [a, b] = crossings {
        if *b < *a {
            crossings.swap(0, 1);
        }
    } else {
        crossings.sort_unstable();
    }
}
