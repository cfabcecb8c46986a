//! The coverage rule (docs/DESIGN.md, "Coverage"), decided exactly on vertices snapped to a
//! sub-pixel grid, written once for every method of the pipeline (the reference, zspec,
//! has its own).
//!
//! Pixel (c, r) is the square [c, c+1) × [r, r+1) and is covered when its centre
//! (c+½, r+½) is inside the polygon by the even-odd rule. A centre exactly on an edge
//! belongs to the polygon for which the edge is a left or a top edge. Both follow from
//! half-open intervals: on row r the edges that count are those with
//! y_top ≤ r+½ < y_bottom (a horizontal edge never counts; a bottom vertex is not on its
//! edge), and between consecutive crossings x_0 ≤ x_1 the covered centres are those with
//! x_0 ≤ c+½ < x_1. A shared edge is a left edge of one polygon and a right edge of the
//! other, so exactly one of them gets a centre that lies on it.
//!
//! **Snapping.** The rule is evaluated on the polygon's device vertices rounded to the
//! nearest multiple of 1/256 pixel, ties to even ([`snap`]), as Direct3D 11, Vulkan and
//! llvmpipe rasterise (8 sub-pixel bits). On that grid, in units of 1/256 pixel, every
//! vertex and every pixel centre (256c + 128, 256r + 128) is an integer, so every
//! decision of the rule is an exact integer comparison: an edge's crossing of a row is
//! the rational x_top + (y − y_top)·dx/dy, and the first centre at or right of it is a
//! ceiling division ([`Edge::column`]), stepped from row to row without error by a DDA
//! ([`EdgeWalk`]). Snapping also removes the noise of the projection: the vertex a scene
//! puts at (20, 100) arrives as (19.999999999999996, 100) and is drawn at (20, 100).
//!
//! **Crossings as columns.** A crossing x matters only through the first column whose
//! centre is at or right of it, ⌈x − ½⌉: the centre c+½ lies in [x_0, x_1) exactly when
//! ⌈x_0 − ½⌉ ≤ c < ⌈x_1 − ½⌉, and the map is monotone, so sorting those columns pairs
//! the crossings as sorting the crossings would. The scan converters carry them as `i64`.
//!
//! **Pieces of a split polygon.** A splitter's cut point lies on the original edge only
//! to within rounding, and snapped, up to 1/512 pixel off the snapped original: a piece
//! whose edge ran through its own snapped ends would cross rows elsewhere than the whole.
//! So an edge cut by a splitter (an `on` support) takes its crossings from the snapped
//! *support*, the whole edge ([`Edge::with_support`]), and the rows it is active on from
//! where the support itself meets the cut ([`vertex_rows`]): the tree's cuts lie on pixel
//! boundaries, so a cut along a row line Y = m puts the cut point at Y = m exactly (no
//! centre between it and the line), and a cut along a column line X = k, where the cut
//! point's snapped Y may be anywhere near the support, is replaced, for the rows, by the
//! support's exact crossing of X = k. Each piece then holds, on every row, the whole's
//! crossings on its side of the cut plus the cut edge's, which at an integer X decides no
//! centre (centres are at half-integers): the pieces cover exactly the whole's pixels.

use glam::DVec2;
use std::ops::Range;

/// Sub-pixel units to a pixel: vertices are snapped to multiples of 1/256 pixel.
pub const SUBPIXEL: i64 = 256;
/// Half a pixel, in sub-pixel units: pixel centres are at `SUBPIXEL·c + HALF`.
pub const HALF: i64 = SUBPIXEL / 2;

/// The largest snapped coordinate, 2^36 units (2^28 pixels): beyond any screen and its
/// guard band (17 screens of 65,536 pixels, times 16 for the finest supersampling, is
/// under 2^25 pixels), and small enough that a product of three coordinate differences
/// (2^111 at most, [`vertex_rows`]) fits an i128, and every row-to-row step an i64.
pub const LIMIT: i64 = 1 << 36;

/// `v` in sub-pixel units, rounded to the nearest integer, ties to even, and clamped to
/// ±[`LIMIT`] (NaN to 0): a vertex the stages let through lies well inside.
#[inline]
pub fn snap(v: f64) -> i64 {
    let u = v * SUBPIXEL as f64;
    // Adding and subtracting 1.5·2^52 rounds |u| < 2^51 to an integer, ties to even (the
    // default rounding of every IEEE operation), without the library call that baseline
    // x86-64 makes for `round_ties_even`.
    const MAGIC: f64 = 6_755_399_441_055_744.0; // 1.5 · 2^52
    if u.abs() < LIMIT as f64 {
        ((u + MAGIC) - MAGIC) as i64
    } else if u > 0.0 {
        LIMIT
    } else if u < 0.0 {
        -LIMIT
    } else {
        0
    }
}

/// A device point snapped to the sub-pixel grid ([`snap`]), in 1/256 pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct Point {
    pub x: i64,
    pub y: i64,
}

impl Point {
    /// The snapped device point (X, Y).
    #[inline]
    pub fn snap(p: DVec2) -> Point {
        Point {
            x: snap(p.x),
            y: snap(p.y),
        }
    }

    /// The point in pixels (exact: a multiple of 1/256 well within f64's precision).
    #[inline]
    pub fn to_f64(self) -> DVec2 {
        DVec2::new(
            self.x as f64 / SUBPIXEL as f64,
            self.y as f64 / SUBPIXEL as f64,
        )
    }
}

/// ⌈n / d⌉ for d > 0.
#[inline]
pub fn ceil_div(n: i128, d: i128) -> i128 {
    let q = n.div_euclid(d);
    if q * d == n {
        q
    } else {
        q + 1
    }
}

/// The first row whose centre is at or below `y` (sub-pixel units): the least r with
/// `SUBPIXEL·r + HALF ≥ y`. An edge from y_a to y_b counts on the rows
/// `row_at(min)..row_at(max)`, the half-open rule y_top ≤ r+½ < y_bottom.
#[inline]
pub fn row_at(y: i64) -> i64 {
    (y - HALF).div_euclid(SUBPIXEL) + ((y - HALF).rem_euclid(SUBPIXEL) != 0) as i64
}

/// The first column whose centre is at or right of `x` (sub-pixel units).
#[inline]
pub fn column_at(x: i64) -> i64 {
    row_at(x)
}

/// The columns `c0..c1` (crossings as columns, see the module's notes) clamped to
/// `0..limit` (the screen's width): the pixels of one covered span.
#[inline]
pub fn centres_in_clamped(c0: i64, c1: i64, limit: u32) -> Range<u32> {
    let start = c0.clamp(0, limit as i64) as u32;
    let end = c1.clamp(0, limit as i64) as u32;
    start..end.max(start)
}

/// A polygon edge in snapped device space: the rows it counts on, and the line its
/// crossings are measured on, oriented top to bottom so that the arithmetic is the same
/// whichever way a polygon walks it (Appendix 3's ET entry: y_max, x at y_min, 1/m, here
/// as exact integers).
///
/// The rows come from the edge's own ends ([`vertex_rows`]); the line is the edge itself,
/// or, for a piece of a longer edge that a splitter cut, that whole edge
/// ([`Edge::with_support`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edge {
    /// The rows r on which the edge counts: y_top ≤ r+½ < y_bottom.
    pub rows: (i64, i64),
    /// The top end of the line.
    pub x0: i64,
    pub y0: i64,
    /// The line's extent from its top end: dy > 0 (dy = 1, dx = 0 for a single point,
    /// which crosses every row at x0).
    pub dx: i64,
    pub dy: i64,
}

impl Edge {
    /// The edge from `a` to `b`, active on the rows between the vertices' first rows
    /// `row_a` and `row_b` ([`vertex_rows`]), or `None` when it spans no row centre (a
    /// horizontal edge covers no centre of its own; the edges beside it decide the pixels
    /// along it).
    #[inline]
    pub fn new(a: Point, b: Point, row_a: i64, row_b: i64) -> Option<Edge> {
        Edge::on_line(a, b, row_a, row_b)
    }

    /// The piece `a`–`b` of the original edge `support_a`–`support_b`: active on the rows
    /// of `a`–`b`, crossing them where the original edge does (exactly as the unsplit
    /// polygon's edge does, whichever way either is walked). `None` if the piece spans no
    /// row centre or the original edge is horizontal: a horizontal original covers no
    /// centre of its own, so neither may its pieces.
    #[inline]
    pub fn with_support(
        row_a: i64,
        row_b: i64,
        support_a: Point,
        support_b: Point,
    ) -> Option<Edge> {
        if support_a.y == support_b.y {
            return None;
        }
        Edge::on_line(support_a, support_b, row_a, row_b)
    }

    #[inline]
    fn on_line(a: Point, b: Point, row_a: i64, row_b: i64) -> Option<Edge> {
        if row_a == row_b {
            return None;
        }
        let (top, bottom) = if (a.y, a.x) <= (b.y, b.x) {
            (a, b)
        } else {
            (b, a)
        };
        let (dx, dy) = if top.y == bottom.y {
            // Only a cut edge whose ends the rows were moved for can be here (a piece of a
            // vertical cut that is shorter than the grid); it lies at one X.
            (0, 1)
        } else {
            (bottom.x - top.x, bottom.y - top.y)
        };
        Some(Edge {
            rows: (row_a.min(row_b), row_a.max(row_b)),
            x0: top.x,
            y0: top.y,
            dx,
            dy,
        })
    }

    /// The rows whose centres the edge spans.
    #[inline]
    pub fn rows(&self) -> Range<i64> {
        self.rows.0..self.rows.1
    }

    /// The first column whose centre is at or right of the edge's crossing of row `row`:
    /// ⌈(x0 + (y − y0)·dx/dy − HALF)/SUBPIXEL⌉ at y = SUBPIXEL·row + HALF, exactly.
    #[inline]
    pub fn column(&self, row: i64) -> i64 {
        self.walk(row).column
    }

    /// The edge's crossings from row `row` on, as a DDA.
    #[inline]
    pub fn walk(&self, row: i64) -> EdgeWalk {
        let dy = self.dy as i128;
        let dx = self.dx as i128;
        let den = SUBPIXEL as i128 * dy;
        let yc = SUBPIXEL as i128 * row as i128 + HALF as i128;
        let n = (self.x0 as i128 - HALF as i128) * dy + (yc - self.y0 as i128) * dx;
        let column = ceil_div(n, den);
        // n = column·den − rem, 0 ≤ rem < den.
        let rem = column * den - n;
        let step = SUBPIXEL as i128 * dx;
        let step_column = step.div_euclid(den);
        let step_rem = step.rem_euclid(den);
        EdgeWalk {
            column: column.clamp(i64::MIN as i128 / 4, i64::MAX as i128 / 4) as i64,
            rem: rem as i64,
            step_column: step_column as i64,
            step_rem: step_rem as i64,
            den: den as i64,
        }
    }
}

/// An edge's crossings row after row (a DDA on the exact rational crossing): the column
/// ⌈x − ½⌉ of the current row and the remainder that makes it exact. The numerator of
/// x − ½ grows by SUBPIXEL·dx a row; `den` = SUBPIXEL·dy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EdgeWalk {
    pub column: i64,
    /// column·den − numerator, in [0, den).
    rem: i64,
    step_column: i64,
    /// The step's numerator is step_column·den + step_rem, 0 ≤ step_rem < den.
    step_rem: i64,
    den: i64,
}

impl EdgeWalk {
    /// Moves to the next row.
    #[inline]
    pub fn step(&mut self) {
        // numerator' = (column + step_column)·den − (rem − step_rem)
        self.column += self.step_column;
        // rem − step_rem lies in (−den, den): where it is negative, one more column and
        // den back. Without a branch: the borrow is taken from the sign (−1 or 0), as the
        // sign of a sloping edge's remainder changes from row to row unpredictably, and
        // a mispredicted branch here was most of the Active Edge Table's time.
        let rem = self.rem - self.step_rem;
        let borrow = rem >> 63;
        self.rem = rem + (self.den & borrow);
        self.column -= borrow;
    }
}

/// Twice the signed area of the triangle a, b, c (exact).
#[inline]
pub fn cross(a: Point, b: Point, c: Point) -> i128 {
    (b.x - a.x) as i128 * (c.y - a.y) as i128 - (b.y - a.y) as i128 * (c.x - a.x) as i128
}

/// The first row at or below each vertex (`rows[i]` for `points[i]`), which the edges on
/// either side of it share, so that the rows a polygon's edges count on pair up.
///
/// For an ordinary vertex it is [`row_at`] of its Y. A vertex where a cut (the splitter
/// tree's, or the painter's along another polygon's plane) met an edge (edge i−1 → i or
/// i → i+1 has a support that the vertex is not an end of) takes instead the row of the
/// point where the snapped support meets the line of the cut edge on its other side (that
/// edge's own support if it has one, else the line through the vertex and its
/// neighbour): there, exactly, the support's crossings pass from one side of the cut to
/// the other. Each piece then counts the support on exactly the rows where it crosses on
/// the piece's side, and the cut edge on exactly the rows where it lies between the
/// whole's edges, so the pieces' spans tile the whole's. For a cut along a row line
/// Y = m the point is at Y = m, where the snapped cut point is too; along a column line
/// X = k it may be well away from the snapped cut point's Y if the edge is steep.
pub fn vertex_rows(points: &[Point], supports: &[Option<[Point; 2]>], rows: &mut Vec<i64>) {
    rows.clear();
    let n = points.len();
    rows.extend(points.iter().map(|p| row_at(p.y)));
    if supports.iter().all(Option::is_none) || n < 3 {
        return;
    }
    let support = |i: usize| supports.get(i).copied().flatten();
    for (i, row) in rows.iter_mut().enumerate() {
        let p = points[i];
        let (before, after) = ((i + n - 1) % n, (i + 1) % n);
        // The supported edge the vertex cuts, and the cut edge on its other side: its
        // line's two points.
        let cut = if let Some([a, b]) = support(i).filter(|&[a, b]| p != a && p != b) {
            Some(([a, b], support(before).unwrap_or([points[before], p])))
        } else if let Some([a, b]) = support(before).filter(|&[a, b]| p != a && p != b) {
            Some(([a, b], support(i).unwrap_or([p, points[after]])))
        } else {
            None
        };
        let Some(([a, b], [c, d])) = cut else {
            continue;
        };
        // a + t·(b − a) on the line c–d: t = (c − a)×(d − c) / (b − a)×(d − c), and
        // y = a.y + t·(b.y − a.y) = num/den.
        let cross2 = |u: (i128, i128), v: (i128, i128)| u.0 * v.1 - u.1 * v.0;
        let dc = ((d.x - c.x) as i128, (d.y - c.y) as i128);
        let ba = ((b.x - a.x) as i128, (b.y - a.y) as i128);
        let mut den = cross2(ba, dc);
        if den == 0 {
            continue; // parallel, or a degenerate cut edge: the vertex's own Y stands
        }
        let mut t = cross2(((c.x - a.x) as i128, (c.y - a.y) as i128), dc);
        if den < 0 {
            (t, den) = (-t, -den);
        }
        let num = a.y as i128 * den + t * ba.1;
        let exact = ceil_div(num - HALF as i128 * den, SUBPIXEL as i128 * den);
        // Within the support's own rows (a cut meets the edge between its ends; this only
        // bounds what a degenerate near-parallel cut could give).
        let (lo, hi) = (row_at(a.y.min(b.y)), row_at(a.y.max(b.y)));
        *row = exact.clamp(lo as i128, hi as i128) as i64;
    }
}

/// Edge i of a polygon (vertex i → vertex i+1): rows from [`vertex_rows`], crossings from
/// its support if a splitter cut it out of a longer edge.
#[inline]
pub fn polygon_edge(
    points: &[Point],
    supports: &[Option<[Point; 2]>],
    rows: &[i64],
    i: usize,
) -> Option<Edge> {
    let j = (i + 1) % points.len();
    match supports.get(i).copied().flatten() {
        Some([sa, sb]) => Edge::with_support(rows[i], rows[j], sa, sb),
        None => Edge::new(points[i], points[j], rows[i], rows[j]),
    }
}

/// Whether every point lies on one straight line, to within the rounding of their
/// coordinates (unsnapped: for the stages that draw edges rather than pixels, such as
/// hiddenline, and as a quick test before a polygon is set up). Coverage itself asks
/// [`snapped_on_one_line`].
pub fn on_one_line(points: &[DVec2]) -> bool {
    let Some(&p0) = points.first() else {
        return true;
    };
    let far = points
        .iter()
        .copied()
        .max_by(|a, b| {
            (*a - p0)
                .length_squared()
                .total_cmp(&(*b - p0).length_squared())
        })
        .unwrap_or(p0);
    let d = far - p0;
    let magnitude = points
        .iter()
        .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
    // A point off the line by less than a few ulps of the coordinates is on it.
    let tolerance = 16.0 * f64::EPSILON * magnitude * d.abs().max_element();
    points
        .iter()
        .all(|&p| d.perp_dot(p - p0).abs() <= tolerance)
}

/// Whether every snapped point lies on one straight line, exactly. Such a polygon has no
/// interior and covers no pixel centre (every row's crossings come in equal pairs).
/// [`on_one_line`] for points already snapped.
pub fn snapped_on_one_line(points: &[Point]) -> bool {
    all_on_one_line(points.iter().copied())
}

/// Whether a polygon's snapped outline covers nothing: its snapped vertices on one
/// straight line, and the ends of its edges' snapped supports on that line too. A piece
/// whose edges cross rows on their supports ([`vertex_rows`], [`polygon_edge`]) covers
/// what lies between them even where its own ends snap onto one line: a sliver cut at a
/// pixel boundary can have two crossings a third of 1/256 apart become one point while
/// the whole's edges it lies on still hold a sample between them (differential seed
/// 7310: `--aa ss8` at depth 4 lost it). For a polygon without supports, exactly
/// [`snapped_on_one_line`].
pub fn snapped_covers_nothing(
    points: &[Point],
    supports: impl Iterator<Item = Point> + Clone,
) -> bool {
    snapped_on_one_line(points) && all_on_one_line(points.iter().copied().chain(supports))
}

/// [`snapped_on_one_line`] of any points, walked three times at most.
fn all_on_one_line(mut points: impl Iterator<Item = Point> + Clone) -> bool {
    let Some(p0) = points.clone().next() else {
        return true;
    };
    let Some(p1) = points.clone().find(|&p| p != p0) else {
        return true;
    };
    points.all(|p| cross(p0, p1, p) == 0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pt(x: f64, y: f64) -> Point {
        Point::snap(DVec2::new(x, y))
    }

    #[test]
    fn snapping_rounds_to_the_nearest_256th_ties_to_even() {
        assert_eq!(snap(0.0), 0);
        assert_eq!(snap(1.0), 256);
        assert_eq!(snap(19.999999999999996), 20 * 256);
        assert_eq!(snap(0.5 / 256.0), 0); // a tie, to even
        assert_eq!(snap(1.5 / 256.0), 2);
        assert_eq!(snap(2.5 / 256.0), 2);
        assert_eq!(snap(-2.5 / 256.0), -2);
        assert_eq!(snap(-0.6 / 256.0), -1);
        assert_eq!(snap(1.0 / 3.0), 85); // 85.33…
        assert_eq!(snap(f64::NAN), 0);
        assert_eq!(snap(1e300), LIMIT);
        assert_eq!(snap(-1e10), -LIMIT);
        assert_eq!(snap(-f64::INFINITY), -LIMIT);
        let mut state = 0x2545f4914f6cdd1du64;
        for _ in 0..100_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let v = (state >> 11) as f64 / (1u64 << 30) as f64 - 4096.0;
            assert_eq!(snap(v), (v * 256.0).round_ties_even() as i64, "{v}");
        }
    }

    #[test]
    fn rows_and_columns_are_half_open() {
        assert_eq!(row_at(0), 0);
        assert_eq!(row_at(128), 0); // centre 0.5 at y = 0.5 counts
        assert_eq!(row_at(129), 1);
        assert_eq!(row_at(-128), -1);
        assert_eq!(row_at(-129), -1);
        assert_eq!(row_at(-384), -2);
        assert_eq!(column_at(2 * 256 + 128), 2);
        assert_eq!(centres_in_clamped(-3, 2, 10), 0..2);
        assert_eq!(centres_in_clamped(8, i64::MAX, 10), 8..10);
        assert_eq!(centres_in_clamped(12, 11, 10), 10..10);
    }

    fn edge(a: Point, b: Point) -> Option<Edge> {
        Edge::new(a, b, row_at(a.y), row_at(b.y))
    }

    #[test]
    fn edges_are_oriented_top_down_and_cross_exactly() {
        let (a, b) = (pt(1.0, 5.0), pt(3.0, 1.0));
        let e = edge(a, b).unwrap();
        assert_eq!(e, edge(b, a).unwrap());
        assert_eq!(e.rows(), 1..5); // centres 1.5 .. 4.5
                                    // x = 3 − (y − 1)/2: at y = 1.5, x = 2.75 (first centre 3); at y = 2.5, x = 2.25
                                    // (first centre 2.5, column 2); at y = 3.5, x = 1.75; at 4.5, 1.25.
        let cols: Vec<i64> = e.rows().map(|r| e.column(r)).collect();
        assert_eq!(cols, [3, 2, 2, 1]);
        let mut w = e.walk(1);
        let mut stepped = Vec::new();
        for _ in 0..4 {
            stepped.push(w.column);
            w.step();
        }
        assert_eq!(stepped, cols);
        assert!(edge(a, pt(9.0, 5.0)).is_none());
        // A crossing exactly on a centre gives that centre's column (x0 ≤ c+½).
        let diag = edge(pt(20.0, 100.0), pt(60.0, 60.0)).unwrap();
        assert_eq!(diag.column(80), 39); // x = 39.5 at y = 80.5
        assert_eq!(diag.column(60), 59);
    }

    #[test]
    fn the_dda_agrees_with_direct_evaluation() {
        let mut state = 0x9e3779b97f4a7c15u64;
        let mut next = |m: u64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % m) as i64 - (m / 2) as i64
        };
        for _ in 0..2000 {
            let a = Point {
                x: next(1 << 20),
                y: next(1 << 16),
            };
            let b = Point {
                x: next(1 << 20),
                y: next(1 << 16),
            };
            let Some(e) = edge(a, b) else { continue };
            let mut w = e.walk(e.rows.0);
            for r in e.rows().take(300) {
                assert_eq!(w.column, e.column(r), "{a:?} {b:?} row {r}");
                // The exact definition: the least c with 256c + 128 ≥ x, i.e.
                // (256c + 128 − x0)·dy ≥ (256r + 128 − y0)·dx.
                let c = w.column as i128;
                let lhs = |c: i128| (256 * c + 128 - e.x0 as i128) * e.dy as i128;
                let rhs = (256 * r as i128 + 128 - e.y0 as i128) * e.dx as i128;
                assert!(lhs(c) >= rhs && lhs(c - 1) < rhs);
                w.step();
            }
        }
    }

    #[test]
    fn a_supported_piece_crosses_where_the_whole_edge_does() {
        // The whole edge (0, 0)–(10, 3) and a piece of it cut at a point I that is on the
        // line only to within rounding.
        let (a, b) = (pt(0.0, 0.0), pt(10.0, 3.0));
        let i = pt(7.0 + 1e-3, 2.1);
        let whole = edge(a, b).unwrap();
        let upper = Edge::with_support(row_at(a.y), row_at(i.y), b, a).unwrap();
        let lower = Edge::with_support(row_at(i.y), row_at(b.y), a, b).unwrap();
        assert_eq!(upper.rows(), 0..2); // centres 0.5, 1.5 < I.y = 2.1
        assert_eq!(lower.rows(), 2..3);
        for r in 0..2 {
            assert_eq!(upper.column(r), whole.column(r));
        }
        assert_eq!(lower.column(2), whole.column(2));
        // Horizontal originals cover nothing.
        assert!(Edge::with_support(0, 2, a, pt(4.0, 0.0)).is_none());
    }

    #[test]
    fn a_cut_on_a_column_line_moves_the_rows_to_the_support() {
        // The edge (0, 0)–(8, 1.2) cut at X = 4, where it is at Y = 0.6; the cut point
        // arrives as (4, 0.4) (farther off than snapping moves one, to show the effect).
        // The support crosses row 0's centre line Y = 0.5 at x = 3.33…, left of the cut,
        // so the left piece must count it on row 0: its rows split at 0.6, not 0.4.
        let (a, b) = (pt(0.0, 0.0), pt(8.0, 1.2));
        let cut = pt(4.0, 0.4);
        let far = pt(4.0, 3.0); // the other end of the cut edge, on X = 4
        let left = [a, cut, far, pt(0.0, 3.0)];
        let supports = [Some([a, b]), None, None, None];
        let mut rows = Vec::new();
        vertex_rows(&left, &supports, &mut rows);
        assert_eq!(rows, [0, 1, 3, 3]);
        // Without the support the cut point is an ordinary vertex.
        vertex_rows(&left, &[], &mut rows);
        assert_eq!(rows, [0, 0, 3, 3]);
    }

    #[test]
    fn lines_and_not_lines() {
        let p = |x, y| DVec2::new(x, y);
        assert!(on_one_line(&[]));
        assert!(on_one_line(&[p(3.0, 3.0), p(3.0, 3.0), p(3.0, 3.0)]));
        assert!(on_one_line(&[p(16.5, 47.5), p(32.0, 32.0), p(47.5, 16.5)]));
        assert!(on_one_line(&[
            p(0.0, 0.0),
            p(0.1, 0.3),
            p(0.3, 0.9000000000000001)
        ]));
        assert!(!on_one_line(&[p(0.0, 0.0), p(10.0, 0.0), p(10.0, 1e-9)]));
        // A bowtie has no net area but is not a line.
        let bowtie = [p(0.0, 0.0), p(4.0, 4.0), p(4.0, 0.0), p(0.0, 4.0)];
        assert!(!on_one_line(&bowtie));
        let snapped = |pts: &[DVec2]| {
            let s: Vec<Point> = pts.iter().map(|&q| Point::snap(q)).collect();
            snapped_on_one_line(&s)
        };
        assert!(snapped(&[]));
        // Off the line by less than the grid: snapped onto it.
        assert!(snapped(&[p(0.0, 0.0), p(10.0, 0.0), p(10.0, 1e-9)]));
        assert!(!snapped(&[p(0.0, 0.0), p(10.0, 0.0), p(10.0, 0.01)]));
        // Not on one line once snapped: (26, 77) and (77, 230) 256ths of a pixel.
        assert!(!snapped(&[
            p(0.0, 0.0),
            p(0.1, 0.3),
            p(0.3, 0.9000000000000001)
        ]));
        assert!(!snapped(&bowtie));
    }
}
