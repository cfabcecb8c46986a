//! # hiddenline: the visible parts of polygon edges, as SVG (Archuleta's output)
//!
//! Archuleta's hidden-surface line drawing (Archuleta 1972, "Hidden surface line drawing
//! algorithm", its LINE DRAWING ALGORITHM) takes Watkins's scan-line visibility and,
//! instead of shading the visible segments, draws the parts of the polygons' edges that
//! are visible, as vectors. His vectors are found a scan line at a time, so they inherit
//! the raster's resolution (his "third problem") and overlap a little where edges cross
//! (his "first problem"). Here the visibility of an edge is computed in continuous
//! geometry instead, in f64, so the pieces are exact to rounding at any size:
//!
//! for an edge of polygon A and each polygon B that may hide it, the parameter intervals
//! of the edge where its projection is strictly inside B and B's plane is nearer than
//! the edge are hidden; their union is the hidden part, its complement is drawn. The
//! breakpoints are where the edge crosses B's edges and where the depth of the edge
//! crosses B's plane (a linear function along the edge: solved exactly); between two
//! breakpoints one point decides. A point on B's boundary is not inside B, so an edge B
//! shares is not hidden by B; at equal depth the polygon earlier in the stream hides the
//! later (the tie rule of every method here, docs/DESIGN.md, "Visibility").
//!
//! ## Lines of intersection (Archuleta's "second problem")
//!
//! Where two polygons pass through each other there is no edge, but a line: Archuleta's
//! program displays a dot wherever its shader meets an intersection, and he names the
//! better solution, "a segment block which contains similar edge information, and then
//! process the line" (his figures 1 and 3 show the dots). That is done here. Which pairs
//! pass through each other where it can be seen is found as Archuleta's scan lines find
//! it: each row of the screen is resolved into the polygon in front at each pixel centre
//! (the z-buffer's coverage and tie rule), and a pair is a candidate where the front
//! changes from one to the other between two neighbouring centres, across a column or a
//! row (at an edge of either, or where they cross). For each candidate, the line where their planes meet on the screen (depth_A(X, Y) =
//! depth_B(X, Y), a straight line since both depths are affine) is cut exactly to the
//! part inside both polygons, and each piece is processed as an edge of depth depth_A,
//! hidden by every other polygon as an edge is. Its visible pieces are drawn as
//! `<line class="intersection">`, in the colour of the earlier of the two polygons.
//!
//! Testing every pair whose depth extents overlap instead costs N² lines, each walked
//! against up to N polygons: cubic on crossing planes (2,000 of them ran past 120 s),
//! while the pairs that meet on the front number about its pieces. What the candidates
//! miss is a crossing whose two polygons are nowhere in front at neighbouring pixel
//! centres (both smaller than a pixel there, or the crossing shorter). Two
//! faces with a vertex in common (the same X, Y and depth, bit for bit: neighbours in a
//! mesh, whose planes meet along their shared edge or through the shared corner) are
//! never a candidate: their line is an edge of the model, drawn as one.
//!
//! ## Buckets: cost by what is visible, not by what is stacked
//!
//! Testing every edge against every polygon is quadratic in the polygons stacked over a
//! point. Instead the screen is divided into a grid of cells (buckets), about one per
//! polygon, up to 128 × 128. Polygons are put in the cells they touch, nearest ZMIN
//! first (the vertex depth nearest the eye), with Warnock's Looker (Newman and Sproull
//! 1973, Appendix VI, AVI.1) deciding whether a polygon touches a cell
//! or surrounds it, and with the listing's ZMIN test: once a polygon surrounds a cell,
//! any polygon whose ZMIN is farther than that surrounder's farthest corner in the cell
//! is hidden there and is not put in it. A stack of polygons costs one polygon per cell.
//! Each cell also keeps the three surrounders whose planes are nearest over it, and a
//! polygon whose plane lies behind one of them at all four corners of the cell is left
//! out of it (at the end, too, for those placed before that surrounder came): the ZMIN
//! test cannot do this for planes whose depth extents overlap, as crossing planes' do.
//! An edge is then walked cell by cell: where its polygon is not in the cell it is
//! hidden there; elsewhere only the cell's polygons that may be nearer (in ZMIN order,
//! up to the edge's own farthest depth) are tested, and the walk of a cell stops when
//! the edge's piece there is all hidden.
//!
//! An edge two polygons share is drawn once, in the colour of the earlier. Edges that
//! are not edges of the model are left out: where the splitter tree cut a polygon (two
//! pieces of one polygon, with the same colour and the same recorded `plane`, meeting
//! along the cut, which is vertical or horizontal on the screen; docs/DESIGN.md,
//! "Annotations: `plane` and `on`") and where the clipper cut one at the screen's border.
//!
//! Screen coordinates are the device's (X right, Y down, pixels), so the SVG's viewBox
//! is `0 0 W H` and its user units are pixels of the PPM frames. The SVG is written as
//! the pieces are found ([`for_each_segment`]), so memory holds the frame's polygons,
//! the grid and two rows of the screen, not the drawing.
//!
//! [`Method::Archuleta`] is the other way, Archuleta's own, at the raster's resolution
//! (the `archuleta` module).

mod archuleta;

use proto::{Colour, DVec2, Polygon};
use std::collections::{HashMap, HashSet};

/// How the visible pieces are found.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Method {
    /// Each edge against the polygons that may hide it, in continuous geometry (f64):
    /// exact pieces at any size (the module notes).
    #[default]
    Continuous,
    /// Archuleta's own: counters on Watkins's scan-line segments, vectors whose ends lie
    /// between the screen's rows (the `archuleta` module's notes).
    Archuleta,
}

/// The visible pieces of a frame by `method`, each handed to `emit` as it is found.
pub fn for_each_segment_by(
    method: Method,
    polygons: &[Polygon],
    width: u32,
    height: u32,
    stats: &mut LineStats,
    emit: impl FnMut(Segment),
) {
    match method {
        Method::Continuous => for_each_segment(polygons, width, height, stats, emit),
        Method::Archuleta => archuleta::for_each_segment(polygons, width, height, stats, emit),
    }
}
pub use lines::{svg, svg_line, svg_start, Segment, SvgWriter, SVG_END};

/// Counters for `--stats`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LineStats {
    /// Edges examined (of polygons that have an area on the screen).
    pub edges: u64,
    /// Edges left out: shared with an earlier polygon, splitter cuts, screen border.
    pub shared: u64,
    pub cuts: u64,
    pub border: u64,
    /// Edge–polygon pairs whose bounding boxes met, so that the edge was tested.
    pub pairs_tested: u64,
    /// Pieces of edges drawn.
    pub segments: u64,
    /// Pieces of lines of intersection found (inside both polygons), and drawn.
    pub intersection_lines: u64,
    pub intersections: u64,
    /// Pairs of polygons (counted in each cell that holds both) not tested for a line of
    /// intersection because they share a vertex: neighbours in a mesh.
    pub neighbours: u64,
    /// Placements of a polygon in a cell left out because a surrounder of the cell
    /// hides it there (the ZMIN test); a polygon hidden in every cell counts once.
    pub culled: u64,
    /// Watkins's visible segments the scan lines passed on (the stretches of a line
    /// where one polygon is in front): what Archuleta's counters count on.
    pub visible_segments: u64,
}

/// A polygon ready for the tests: its screen points, depths and depth plane.
struct Face {
    index: usize,
    colour: Colour,
    points: Vec<DVec2>,
    depths: Vec<f64>,
    /// Depth = −(a·X + b·Y + d)/c.
    plane: [f64; 4],
    /// The same as depth = gx·X + gy·Y + g0.
    gradient: [f64; 3],
    recorded: Option<[u64; 4]>,
    min: DVec2,
    max: DVec2,
    /// Its nearest depth (its plane's, at its vertices).
    zmin: f64,
    /// For a convex triangle or quadrilateral, each edge's start and unit inward normal:
    /// the inside test without divisions.
    convex: Option<Vec<(DVec2, DVec2)>>,
}

impl Face {
    fn of(index: usize, p: &Polygon) -> Option<Face> {
        let points: Vec<DVec2> = p.vertices.iter().map(|v| DVec2::new(v.x, v.y)).collect();
        if points.len() < 3 || proto::raster::on_one_line(&points) {
            return None;
        }
        let recorded = p.plane.filter(|n| n.z != 0.0 && n.is_finite());
        let n = recorded.unwrap_or_else(|| {
            let pts: Vec<_> = p.vertices.iter().map(|v| v.truncate()).collect();
            proto::geometry::newell_plane(&pts)
        });
        if n.z == 0.0 || !n.is_finite() {
            return None; // seen edge-on: no area
        }
        let min = points.iter().copied().fold(DVec2::INFINITY, DVec2::min);
        let max = points.iter().copied().fold(DVec2::NEG_INFINITY, DVec2::max);
        let depths: Vec<f64> = p.vertices.iter().map(|v| v.z).collect();
        let convex = convex_edges(&points);
        // The extremes of its plane's depth over it (at its vertices): what it can hide
        // with, since its depth at a point is its plane's (its vertices' own depths may be
        // off the plane when it is not planar).
        let on_plane = points.iter().map(|q| -(n.x * q.x + n.y * q.y + n.w) / n.z);
        Some(Face {
            convex,
            index,
            colour: p.colour,
            zmin: on_plane.fold(f64::INFINITY, f64::min),
            depths,
            points,
            plane: [n.x, n.y, n.z, n.w],
            gradient: [-n.x / n.z, -n.y / n.z, -n.w / n.z],
            recorded: p.plane.map(|n| n.to_array().map(f64::to_bits)),
            min,
            max,
        })
    }

    fn depth_at(&self, q: DVec2) -> f64 {
        let [gx, gy, g0] = self.gradient;
        gx * q.x + gy * q.y + g0
    }

    /// The faces of a frame's polygons, each knowing its index in the stream; polygons
    /// with no area on the screen have none.
    fn all(polygons: &[Polygon]) -> Vec<Face> {
        polygons
            .iter()
            .enumerate()
            .filter_map(|(i, p)| Face::of(i, p))
            .collect()
    }

    fn edge(&self, i: usize) -> (DVec2, DVec2) {
        (self.points[i], self.points[(i + 1) % self.points.len()])
    }

    /// Is `q` on the boundary, to `tol`?
    fn on_boundary(&self, q: DVec2, tol: f64) -> bool {
        (0..self.points.len()).any(|i| {
            let (a, b) = self.edge(i);
            let ab = b - a;
            let len2 = ab.length_squared();
            let t = if len2 > 0.0 {
                ((q - a).dot(ab) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (a + ab * t - q).length_squared() <= tol * tol
        })
    }

    /// Is `q` inside by the even-odd rule (a ray to the right crosses an odd number of
    /// edges)?
    fn inside(&self, q: DVec2) -> bool {
        let mut inside = false;
        for i in 0..self.points.len() {
            let (a, b) = self.edge(i);
            if (a.y > q.y) != (b.y > q.y) {
                let x = a.x + (q.y - a.y) / (b.y - a.y) * (b.x - a.x);
                if q.x < x {
                    inside = !inside;
                }
            }
        }
        inside
    }

    /// Is `q` strictly inside (even-odd, the boundary excluded)?
    fn strictly_inside(&self, q: DVec2, tol: f64) -> bool {
        match &self.convex {
            Some(edges) => edges.iter().all(|&(a, n)| n.dot(q - a) > tol),
            None => !self.on_boundary(q, tol) && self.inside(q),
        }
    }

    /// The Looker's class of this polygon for the rectangle [lo, hi] (Appendix VI,
    /// AVI.1): its box misses it, or an edge passes through it (the corners in the
    /// edge's line equation), or else the parity of a ray from a corner says whether it
    /// surrounds it.
    fn classify(&self, lo: DVec2, hi: DVec2) -> Class {
        if self.max.x < lo.x || self.min.x > hi.x || self.max.y < lo.y || self.min.y > hi.y {
            return Class::Disjoint;
        }
        let corners = [lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)];
        for i in 0..self.points.len() {
            let (a, b) = self.edge(i);
            if a.x.max(b.x) < lo.x
                || a.x.min(b.x) > hi.x
                || a.y.max(b.y) < lo.y
                || a.y.min(b.y) > hi.y
            {
                continue;
            }
            let d = b - a;
            let side = corners.map(|c| d.perp_dot(c - a));
            if !(side.iter().all(|&s| s > 0.0) || side.iter().all(|&s| s < 0.0)) {
                return Class::Intersector;
            }
        }
        if self.inside(lo) {
            Class::Surrounder
        } else {
            Class::Disjoint
        }
    }
}

/// A triangle's or a convex quadrilateral's edges as (start, unit inward normal); `None`
/// for anything else (concave, self-intersecting, more vertices, a repeated vertex).
fn convex_edges(points: &[DVec2]) -> Option<Vec<(DVec2, DVec2)>> {
    let n = points.len();
    if !(3..=4).contains(&n) {
        return None;
    }
    let turns: Vec<f64> = (0..n)
        .map(|i| {
            let (a, b, c) = (points[i], points[(i + 1) % n], points[(i + 2) % n]);
            cross(b - a, c - b)
        })
        .collect();
    let sign = if turns.iter().all(|&t| t > 0.0) {
        1.0
    } else if turns.iter().all(|&t| t < 0.0) {
        -1.0
    } else {
        return None;
    };
    (0..n)
        .map(|i| {
            let (a, b) = (points[i], points[(i + 1) % n]);
            let d = b - a;
            let len = d.length();
            (len > 0.0 && len.is_finite()).then(|| (a, DVec2::new(-d.y, d.x) * (sign / len)))
        })
        .collect()
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Class {
    Disjoint,
    Intersector,
    Surrounder,
}

/// Could the box [bmin, bmax] hold a point of the edge's box [emin, emax] strictly
/// inside it? (Each axis: the edge's range meets B's open range.)
fn straddles(bmin: DVec2, bmax: DVec2, emin: DVec2, emax: DVec2) -> bool {
    let axis = |bl: f64, bh: f64, el: f64, eh: f64| {
        if el == eh {
            bl < el && el < bh
        } else {
            bl < eh && el < bh
        }
    };
    axis(bmin.x, bmax.x, emin.x, emax.x) && axis(bmin.y, bmax.y, emin.y, emax.y)
}

/// A surrounder of a cell, kept to hide what lies behind its plane there: its place in
/// ZMIN order and its plane's depths at the cell's corners.
#[derive(Clone, Copy)]
struct Cover {
    k: u32,
    corners: [f64; 4],
}

impl Cover {
    /// The surrounders a cell keeps: those whose planes are nearest over it.
    const KEPT: usize = 3;
    const NONE: Cover = Cover {
        k: u32::MAX,
        corners: [f64::INFINITY; 4],
    };

    /// Does this surrounder hide, in its cell, a polygon whose plane has these depths at
    /// the cell's corners? Both depths are affine over the cell, so a plane nearer at
    /// the four corners (by the tie rule's width, whatever the stream order) is nearer
    /// everywhere in it, and the surrounder covers all of it: with crossing planes this
    /// leaves out what the ZMIN test cannot, a polygon whose depth extent overlaps the
    /// surrounder's but lies behind it in this cell.
    fn hides(&self, corners: &[f64; 4]) -> bool {
        self.k != u32::MAX
            && self
                .corners
                .iter()
                .zip(corners)
                .all(|(&s, &f)| proto::depth::takes(s, f))
    }

    /// Keeps surrounder `k` among a cell's nearest (by its depths' sum over the corners).
    fn offer(kept: &mut [Cover; Cover::KEPT], k: u32, corners: [f64; 4]) {
        let sum = |c: &Cover| c.corners.iter().sum::<f64>();
        let new = Cover { k, corners };
        let worst = (0..Cover::KEPT)
            .max_by(|&a, &b| sum(&kept[a]).total_cmp(&sum(&kept[b])))
            .unwrap_or(0);
        if kept[worst].k == u32::MAX || sum(&new) < sum(&kept[worst]) {
            kept[worst] = new;
        }
    }
}

/// The buckets: a grid of cells over the frame's polygons, each listing the polygons
/// that touch it and are not hidden in it by a surrounder, by their place in ZMIN order
/// (ascending).
struct Grid {
    origin: DVec2,
    cell: DVec2,
    n: usize,
    cells: Vec<Vec<u32>>,
}

impl Grid {
    /// Places the faces (in ZMIN order) in the cells (see the module notes).
    fn new(faces: &[Face], stats: &mut LineStats) -> Grid {
        let min = faces.iter().fold(DVec2::INFINITY, |m, f| m.min(f.min));
        let max = faces.iter().fold(DVec2::NEG_INFINITY, |m, f| m.max(f.max));
        // About √faces cells a side, but none finer than a sixteenth of a pixel:
        // polygons piled inside a pixel share a few cells, rather than each being placed
        // in thousands of cells smaller than its edges' rounding, most of which only an
        // edge crosses and no polygon surrounds; and many small polygons over a pixel or
        // two (a pinhead's) still get cells about their own size. Measured alone: the
        // pinhead's 100,000 polygons over 1.3 pixels take 0.8 s at 16 cells a pixel, 5.7 s
        // at one; a pile of 100,000 copies in 0.6 of a pixel 0.5 s at 16 cells a side.
        let sixteenths = (16.0 * (max - min).max_element()).ceil();
        let n = ((faces.len() as f64).sqrt().ceil().min(sixteenths) as usize).clamp(1, 128);
        let extent = (max - min).max(DVec2::splat(1e-9));
        let mut grid = Grid {
            origin: min,
            cell: extent / n as f64,
            n,
            cells: vec![Vec::new(); n * n],
        };
        // A polygon farther than this in a cell is hidden there (the listing's ZMINMAX).
        let mut zminmax = vec![f64::INFINITY; n * n];
        // Per cell, the surrounders whose planes are nearest over it.
        let mut best: Vec<[Cover; Cover::KEPT]> = vec![[Cover::NONE; Cover::KEPT]; n * n];
        let margin = 1e-9 * (1.0 + min.abs().max(max.abs()).max_element());
        // An upper bound of the largest ZMINMAX of all cells (infinite while a cell has
        // no surrounder), recomputed when a polygon passes it after ZMINMAX changed: a
        // polygon beyond it is hidden in every cell, and is passed over at once.
        let (mut bound, mut changed) = (f64::INFINITY, false);
        // "Farther" by the tie rule (the far depth must take the pixel from the polygon's
        // nearest), so that a polygon earlier in the stream within the tie width of a
        // surrounder, whose edges then show, is not passed over.
        let hidden = |zmin: f64, far: f64| proto::depth::takes(far, zmin);
        for (k, f) in faces.iter().enumerate() {
            if hidden(f.zmin, bound) {
                stats.culled += 1;
                continue;
            }
            if changed {
                bound = zminmax.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                changed = false;
                if hidden(f.zmin, bound) {
                    stats.culled += 1;
                    continue;
                }
            }
            let (xs, ys) = grid.range(f.min, f.max);
            for j in ys {
                for i in xs.clone() {
                    let c = j * n + i;
                    if hidden(f.zmin, zminmax[c]) {
                        stats.culled += 1;
                        continue;
                    }
                    let (lo, hi) = grid.finite_rect(i, j);
                    let (lo, hi) = (lo - margin, hi + margin);
                    let class = f.classify(lo, hi);
                    if class == Class::Disjoint {
                        continue;
                    }
                    let corners = Grid::corners(f, lo, hi);
                    if best[c].iter().any(|s| s.hides(&corners)) {
                        stats.culled += 1;
                        continue;
                    }
                    grid.cells[c].push(k as u32);
                    if class == Class::Surrounder {
                        let far = corners.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                        if far < zminmax[c] {
                            zminmax[c] = far;
                            changed = true;
                        }
                        Cover::offer(&mut best[c], k as u32, corners);
                    }
                }
            }
        }
        // A polygon placed before the surrounder that hides it came: left out now.
        let mut cells = std::mem::take(&mut grid.cells);
        for (c, list) in cells.iter_mut().enumerate() {
            let (lo, hi) = grid.finite_rect_of(c);
            let (lo, hi) = (lo - margin, hi + margin);
            let before = list.len();
            list.retain(|&k| {
                let corners = Grid::corners(&faces[k as usize], lo, hi);
                !best[c].iter().any(|s| s.hides(&corners))
            });
            stats.culled += (before - list.len()) as u64;
        }
        grid.cells = cells;
        grid
    }

    /// A face's plane's depths at the corners of the rectangle [lo, hi].
    fn corners(f: &Face, lo: DVec2, hi: DVec2) -> [f64; 4] {
        [lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)].map(|q| f.depth_at(q))
    }

    /// Cell `c`'s rectangle within the grid.
    fn finite_rect_of(&self, c: usize) -> (DVec2, DVec2) {
        self.finite_rect(c % self.n, c / self.n)
    }

    fn index(&self, v: f64, axis: usize) -> usize {
        let (o, c) = if axis == 0 {
            (self.origin.x, self.cell.x)
        } else {
            (self.origin.y, self.cell.y)
        };
        let i = ((v - o) / c).floor();
        if i.is_nan() || i < 0.0 {
            0
        } else {
            (i as usize).min(self.n - 1)
        }
    }

    /// The cells a box meets.
    fn range(&self, min: DVec2, max: DVec2) -> (std::ops::Range<usize>, std::ops::Range<usize>) {
        (
            self.index(min.x, 0)..self.index(max.x, 0) + 1,
            self.index(min.y, 1)..self.index(max.y, 1) + 1,
        )
    }

    /// Cell (i, j)'s rectangle within the grid.
    fn finite_rect(&self, i: usize, j: usize) -> (DVec2, DVec2) {
        let lo = self.origin + self.cell * DVec2::new(i as f64, j as f64);
        (lo, lo + self.cell)
    }

    /// Cell (i, j)'s rectangle; the last row and column reach to infinity, so that
    /// rounding at the far side of the grid loses no point.
    fn rect(&self, i: usize, j: usize) -> (DVec2, DVec2) {
        let lo = self.origin + self.cell * DVec2::new(i as f64, j as f64);
        let mut hi = lo + self.cell;
        if i + 1 == self.n {
            hi.x = f64::INFINITY;
        }
        if j + 1 == self.n {
            hi.y = f64::INFINITY;
        }
        let lo = DVec2::new(
            if i == 0 { f64::NEG_INFINITY } else { lo.x },
            if j == 0 { f64::NEG_INFINITY } else { lo.y },
        );
        (lo, hi)
    }

    /// Walks segment p0→p1 cell by cell: `visit(cell, t0, t1)` for each cell whose
    /// (closed) rectangle holds the parameters t0..t1 of the segment, t0 < t1.
    fn walk(&self, p0: DVec2, p1: DVec2, mut visit: impl FnMut(usize, f64, f64) -> bool) {
        let d = p1 - p0;
        // The parameters where coordinate `axis` is within [lo, hi], within [a, b].
        let band = |lo: f64, hi: f64, axis: usize, a: f64, b: f64| -> Option<(f64, f64)> {
            let (p, d) = if axis == 0 { (p0.x, d.x) } else { (p0.y, d.y) };
            let (t0, t1) = if d == 0.0 {
                if lo <= p && p <= hi {
                    (a, b)
                } else {
                    return None;
                }
            } else {
                let (u, v) = ((lo - p) / d, (hi - p) / d);
                (u.min(v).max(a), u.max(v).min(b))
            };
            (t0 <= t1).then_some((t0, t1))
        };
        let (_, ys) = self.range(p0.min(p1), p0.max(p1));
        for j in ys {
            let (lo, hi) = self.rect(0, j);
            let Some((ta, tb)) = band(lo.y, hi.y, 1, 0.0, 1.0) else {
                continue;
            };
            let (xa, xb) = (p0.x + d.x * ta, p0.x + d.x * tb);
            for i in self.index(xa.min(xb), 0)..self.index(xa.max(xb), 0) + 1 {
                let (lo, hi) = self.rect(i, j);
                if let Some((t0, t1)) = band(lo.x, hi.x, 0, ta, tb) {
                    if (t0 < t1 || d == DVec2::ZERO) && !visit(j * self.n + i, t0, t1) {
                        return;
                    }
                }
            }
        }
    }

    fn cell_of(&self, q: DVec2) -> usize {
        self.index(q.y, 1) * self.n + self.index(q.x, 0)
    }
}

fn cross(a: DVec2, b: DVec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Does segment (c, d) lie on the line of (a, b), overlapping it over a positive length?
fn collinear_overlap(a: DVec2, b: DVec2, c: DVec2, d: DVec2, tol: f64) -> bool {
    let ab = b - a;
    let len = ab.length();
    if len == 0.0 {
        return false;
    }
    let off = |p: DVec2| cross(ab, p - a).abs() / len;
    if off(c) > tol || off(d) > tol {
        return false;
    }
    let t = |p: DVec2| (p - a).dot(ab) / (len * len);
    let (lo, hi) = (t(c).min(t(d)), t(c).max(t(d)));
    hi.min(1.0) - lo.max(0.0) > tol / len
}

/// Is edge p0→p1 of `a` a cut the pipeline made rather than an edge of the scene's polygon,
/// and so not drawn? Two kinds, counted in `stats`:
///
/// - the clipper's cut, lying on the screen's border (`x = 0`, `x = w`, `y = 0` or `y = h`
///   within `tol`);
/// - a splitter's cut: vertical or horizontal on the screen, on a piece of a split polygon
///   (its recorded plane), and met along a positive length by an edge of another piece of
///   the same polygon (same recorded plane and colour, another stream index), found among
///   the faces `near` gives (a grid's cells, or the polygon's pieces). `near` is asked
///   only for such an axial edge of a split polygon.
///
/// Both hidden-line methods leave the same edges out through this one test.
fn is_pipeline_cut<'f, I>(
    a: &Face,
    (p0, p1): (DVec2, DVec2),
    (w, h): (f64, f64),
    tol: f64,
    stats: &mut LineStats,
    near: impl FnOnce() -> I,
) -> bool
where
    I: IntoIterator<Item = &'f Face>,
{
    let on = |u: f64, v: f64, k: f64| (u - k).abs() <= tol && (v - k).abs() <= tol;
    if on(p0.x, p1.x, 0.0) || on(p0.x, p1.x, w) || on(p0.y, p1.y, 0.0) || on(p0.y, p1.y, h) {
        stats.border += 1;
        return true;
    }
    let axial = (p0.x - p1.x).abs() <= tol || (p0.y - p1.y).abs() <= tol;
    if a.recorded.is_none() || !axial {
        return false;
    }
    let cut = near().into_iter().any(|b| {
        b.index != a.index
            && b.recorded == a.recorded
            && b.colour == a.colour
            && (0..b.points.len()).any(|j| {
                let (q0, q1) = b.edge(j);
                collinear_overlap(p0, p1, q0, q1, tol)
            })
    });
    if cut {
        stats.cuts += 1;
    }
    cut
}

/// The first and last parameters of t0..t1 that the sorted, disjoint intervals `hidden`
/// leave uncovered; `None` when they cover all of it.
fn uncovered(hidden: &[(f64, f64)], t0: f64, t1: f64) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (t0, t1);
    let i = hidden.partition_point(|&(_, e)| e < lo);
    if i < hidden.len() && hidden[i].0 <= lo {
        lo = hidden[i].1;
    }
    let j = hidden.partition_point(|&(s, _)| s <= hi);
    if j > 0 && hidden[j - 1].1 >= hi {
        hi = hidden[j - 1].0;
    }
    (lo < hi).then_some((lo, hi))
}

/// Adds interval (a, b) to a sorted list of disjoint intervals, merging.
fn add_interval(list: &mut Vec<(f64, f64)>, (a, b): (f64, f64)) {
    let at = list.partition_point(|&(_, e)| e < a);
    let mut end = at;
    let (mut lo, mut hi) = (a, b);
    while end < list.len() && list[end].0 <= hi {
        lo = lo.min(list[end].0);
        hi = hi.max(list[end].1);
        end += 1;
    }
    list.splice(at..end, [(lo, hi)]);
}

/// A frame's polygons, ready to be drawn: faces in ZMIN order, and the grid.
struct Frame {
    faces: Vec<Face>,
    /// Each face's ZMIN and box, packed together for the walk's candidate loop.
    hot: Vec<(f64, DVec2, DVec2)>,
    /// Each face packed for the hidden test, when it is a convex triangle or
    /// quadrilateral.
    shapes: Vec<Option<Shape>>,
    grid: Grid,
    tol: f64,
}

/// What the tests of one line after another reuse.
struct Scratch {
    /// Per face, the last line it was tested against (each face is tested against a
    /// line once, over the whole line, however many cells they share).
    tested: Vec<u32>,
    line: u32,
    /// A test's breakpoints.
    ts: Vec<f64>,
}

/// A segment to find the hidden parts of: its ends and depths, the faces (places in
/// ZMIN order) it belongs to, which do not hide it, and the stream index a hider must
/// be earlier than to win a tie.
struct Line {
    p0: DVec2,
    p1: DVec2,
    z0: f64,
    z1: f64,
    owners: [u32; 2],
    tie: usize,
}

impl Frame {
    /// The hidden parameter intervals of `line`, sorted and merged.
    fn hidden(&self, scratch: &mut Scratch, line: &Line, stats: &mut LineStats) -> Vec<(f64, f64)> {
        let mut hidden: Vec<(f64, f64)> = Vec::new();
        scratch.line = scratch.line.wrapping_add(1);
        if scratch.line == u32::MAX {
            scratch.tested.iter_mut().for_each(|t| *t = u32::MAX);
            scratch.line = 0;
        }
        let Frame {
            faces,
            hot,
            shapes,
            grid,
            tol,
        } = self;
        let Scratch {
            tested,
            line: id,
            ts,
        } = scratch;
        grid.walk(line.p0, line.p1, |c, t0, t1| {
            let list = &grid.cells[c];
            if line.owners.iter().any(|o| list.binary_search(o).is_err()) {
                // Its polygon is hidden in this cell by a surrounder.
                add_interval(&mut hidden, (t0, t1));
                return true;
            }
            let z = |t: f64| line.z0 + (line.z1 - line.z0) * t;
            let far = z(t0).max(z(t1));
            let scale = 1e-12 * (1.0 + line.z0.abs().max(line.z1.abs()));
            // The box of what is not yet hidden of the piece: a polygon that cannot
            // hold a point of it strictly inside is passed over at once.
            let mut gap = (line.p0, line.p1);
            let mut gap_changed = true;
            // Polygons from this place in ZMIN order on lie behind the piece.
            let behind = hot.partition_point(|h| h.0 <= far + scale) as u32;
            for &k in list {
                if k >= behind {
                    break;
                }
                if tested[k as usize] == *id {
                    continue;
                }
                let (_, bmin, bmax) = hot[k as usize];
                if gap_changed {
                    let Some((g0, g1)) = uncovered(&hidden, t0, t1) else {
                        break; // all of the piece is hidden
                    };
                    let r = line.p1 - line.p0;
                    gap = (line.p0 + r * g0, line.p0 + r * g1);
                    gap_changed = false;
                }
                if line.owners.contains(&k)
                    || !straddles(bmin, bmax, gap.0.min(gap.1), gap.0.max(gap.1))
                {
                    continue;
                }
                tested[k as usize] = *id;
                let before = hidden.len();
                match &shapes[k as usize] {
                    Some(shape) => hidden_by(shape, line, &mut hidden, ts, *tol, stats),
                    None => hidden_by(&faces[k as usize], line, &mut hidden, ts, *tol, stats),
                }
                gap_changed = hidden.len() != before || before > 0;
            }
            true
        });
        hidden
    }

    /// Emits the visible pieces of `line` (the complement of `hidden` in 0..1).
    fn emit_visible(
        &self,
        line: &Line,
        hidden: &[(f64, f64)],
        colour: Colour,
        intersection: bool,
        emit: &mut impl FnMut(Segment),
    ) -> u64 {
        let (p0, p1) = (line.p0, line.p1);
        let len = (p1 - p0).length();
        let at = |t: f64| {
            if t <= 0.0 {
                p0
            } else if t >= 1.0 {
                p1
            } else {
                p0 + (p1 - p0) * t
            }
        };
        let mut drawn = 0;
        let mut piece = |t0: f64, t1: f64| {
            if (t1 - t0) * len > self.tol {
                emit(Segment {
                    from: at(t0),
                    to: at(t1),
                    colour,
                    intersection,
                });
                drawn += 1;
            }
        };
        let mut t = 0.0;
        for &(h0, h1) in hidden {
            piece(t, h0.max(t));
            t = t.max(h1);
        }
        piece(t, 1.0);
        drawn
    }
}

/// A convex triangle or quadrilateral packed for the hidden test: what the test reads,
/// in one place (the walk tests many polygons, each once, so the reads are cache misses).
#[derive(Clone, Copy)]
struct Shape {
    gradient: [f64; 3],
    index: usize,
    len: usize,
    points: [DVec2; 4],
    normals: [DVec2; 4],
}

impl Shape {
    fn of(f: &Face) -> Option<Shape> {
        let edges = f.convex.as_ref()?;
        let mut shape = Shape {
            gradient: f.gradient,
            index: f.index,
            len: edges.len(),
            points: [DVec2::ZERO; 4],
            normals: [DVec2::ZERO; 4],
        };
        for (i, &(a, n)) in edges.iter().enumerate() {
            shape.points[i] = a;
            shape.normals[i] = n;
        }
        Some(shape)
    }
}

/// What the hidden test needs of a polygon.
trait Hider {
    fn index(&self) -> usize;
    fn depth(&self, q: DVec2) -> f64;
    fn points(&self) -> &[DVec2];
    fn strictly_inside(&self, q: DVec2, tol: f64) -> bool;
}

impl Hider for Face {
    fn index(&self) -> usize {
        self.index
    }
    fn depth(&self, q: DVec2) -> f64 {
        self.depth_at(q)
    }
    fn points(&self) -> &[DVec2] {
        &self.points
    }
    fn strictly_inside(&self, q: DVec2, tol: f64) -> bool {
        Face::strictly_inside(self, q, tol)
    }
}

impl Hider for Shape {
    fn index(&self) -> usize {
        self.index
    }
    fn depth(&self, q: DVec2) -> f64 {
        let [gx, gy, g0] = self.gradient;
        gx * q.x + gy * q.y + g0
    }
    fn points(&self) -> &[DVec2] {
        &self.points[..self.len]
    }
    fn strictly_inside(&self, q: DVec2, tol: f64) -> bool {
        (0..self.len).all(|i| self.normals[i].dot(q - self.points[i]) > tol)
    }
}

/// The intervals of `line`'s parameters that polygon `b` hides, added to `out`. (The
/// caller has checked that `b`'s box meets the line's.)
fn hidden_by(
    b: &impl Hider,
    line: &Line,
    out: &mut Vec<(f64, f64)>,
    ts: &mut Vec<f64>,
    tol: f64,
    stats: &mut LineStats,
) {
    let (p0, p1, r) = (line.p0, line.p1, line.p1 - line.p0);
    stats.pairs_tested += 1;
    // How much nearer B is than the line, along it: linear in t.
    let (d0, d1) = (line.z0 - b.depth(p0), line.z1 - b.depth(p1));
    let scale = 1e-12 * (1.0 + line.z0.abs().max(line.z1.abs()));
    let tie_hides = b.index() < line.tie;
    if d0 < -scale && d1 < -scale {
        return; // the line is nearer than B's plane all along
    }
    if (d0.abs() <= scale && d1.abs() <= scale) && !tie_hides {
        return; // coplanar, and B later: B does not hide it
    }
    ts.clear();
    ts.extend([0.0, 1.0]);
    if (d0 > scale && d1 < -scale) || (d0 < -scale && d1 > scale) {
        ts.push(d0 / (d0 - d1));
    }
    let points = b.points();
    for j in 0..points.len() {
        let (e0, e1) = (points[j], points[(j + 1) % points.len()]);
        let s = e1 - e0;
        let denom = cross(r, s);
        if denom == 0.0 {
            continue;
        }
        let t = cross(e0 - p0, s) / denom;
        let u = cross(e0 - p0, r) / denom;
        if t > 0.0 && t < 1.0 && (-1e-9..=1.0 + 1e-9).contains(&u) {
            ts.push(t);
        }
    }
    ts.sort_by(f64::total_cmp);
    for k in 0..ts.len() - 1 {
        let (ta, tb) = (ts[k], ts[k + 1]);
        if tb <= ta {
            continue;
        }
        let m = 0.5 * (ta + tb);
        let d = d0 + (d1 - d0) * m;
        let nearer = if d.abs() <= scale { tie_hides } else { d > 0.0 };
        if nearer && b.strictly_inside(p0 + r * m, tol.max(1e-9)) {
            add_interval(out, (ta, tb));
        }
    }
}

/// The visible pieces of every edge of a frame of screen-space polygons (stream order)
/// on a `width`×`height` screen, and of the lines where they pass through each other.
pub fn visible_segments(
    polygons: &[Polygon],
    width: u32,
    height: u32,
    stats: &mut LineStats,
) -> Vec<Segment> {
    let mut out = Vec::new();
    for_each_segment(polygons, width, height, stats, |s| out.push(s));
    out
}

/// [`visible_segments`], each piece handed to `emit` as it is found: edges first,
/// polygon by polygon in stream order, then the lines of intersection.
pub fn for_each_segment(
    polygons: &[Polygon],
    width: u32,
    height: u32,
    stats: &mut LineStats,
    mut emit: impl FnMut(Segment),
) {
    let mut faces = Face::all(polygons);
    if faces.is_empty() {
        return;
    }
    faces.sort_by(|a, b| a.zmin.total_cmp(&b.zmin));
    // Lengths below this are rounding: a millionth of a millionth of the screen.
    let tol = 1e-12 * (width as f64 + height as f64).max(1.0);
    let (w, h) = (width as f64, height as f64);
    let grid = Grid::new(&faces, stats);
    let mut scratch = Scratch {
        tested: vec![u32::MAX; faces.len()],
        line: 0,
        ts: Vec::new(),
    };
    let hot = faces.iter().map(|f| (f.zmin, f.min, f.max)).collect();
    let shapes = faces.iter().map(Shape::of).collect();
    let frame = Frame {
        faces,
        hot,
        shapes,
        grid,
        tol,
    };
    let faces = &frame.faces;
    let mut by_stream: Vec<u32> = (0..faces.len() as u32).collect();
    by_stream.sort_by_key(|&k| faces[k as usize].index);
    // Every edge's owners, in stream order: an edge two polygons share is drawn once.
    let mut owners: HashMap<[u64; 4], Vec<u32>> = HashMap::new();
    for &k in &by_stream {
        let f = &faces[k as usize];
        for i in 0..f.points.len() {
            let (p0, p1) = f.edge(i);
            owners.entry(edge_key(p0, p1)).or_default().push(k);
        }
    }
    let mut drawn: HashSet<[u64; 4]> = HashSet::new();
    let mut near: Vec<u32> = Vec::new();
    for &k in &by_stream {
        let a = &faces[k as usize];
        for i in 0..a.points.len() {
            let (p0, p1) = a.edge(i);
            if p0 == p1 {
                continue;
            }
            stats.edges += 1;
            // The clipper's and the splitters' cuts are not the scene's edges.
            let (grid, near) = (&frame.grid, &mut near);
            let near_cells = move || {
                let cells = near; // moved out: the closure is FnOnce, and so may lend it
                cells.clear();
                grid.walk(p0, p1, |c, _, _| {
                    cells.extend_from_slice(&grid.cells[c]);
                    true
                });
                cells.sort_unstable();
                cells.dedup();
                cells.iter().map(|&j| &faces[j as usize])
            };
            if is_pipeline_cut(a, (p0, p1), (w, h), tol, stats, near_cells) {
                continue;
            }
            // Shared with a polygon before: drawn once.
            let key = edge_key(p0, p1);
            if !drawn.insert(key) {
                stats.shared += 1;
                continue;
            }
            // In the colour of the first owner that shows beside it (a silhouette edge
            // shared with a hidden back face takes the front face's colour), else the
            // first's.
            let edge_owners = &owners[&key];
            let colour = if edge_owners.len() == 1 {
                a.colour
            } else {
                beside_front(&frame, p0, p1, edge_owners).map_or(a.colour, |f| f.colour)
            };
            let line = Line {
                p0,
                p1,
                z0: a.depths[i],
                z1: a.depths[(i + 1) % a.points.len()],
                owners: [k, k],
                tie: a.index,
            };
            let hidden = frame.hidden(&mut scratch, &line, stats);
            stats.segments += frame.emit_visible(&line, &hidden, colour, false, &mut emit);
        }
    }
    intersections(
        &frame,
        polygons,
        &mut scratch,
        (width, height),
        stats,
        &mut emit,
    );
}

/// The lines where two polygons pass through each other (see the module notes): the
/// pairs whose front changes from one to the other between neighbouring pixel centres,
/// each pair's line then cut exactly to the part inside both and hidden as an edge.
fn intersections(
    frame: &Frame,
    polygons: &[Polygon],
    scratch: &mut Scratch,
    (width, height): (u32, u32),
    stats: &mut LineStats,
    emit: &mut impl FnMut(Segment),
) {
    let faces = &frame.faces;
    let mut scan = LineStats::default();
    let pairs = archuleta::front_crossings(faces, polygons, width, height, &mut scan);
    stats.neighbours += scan.neighbours;
    for (ka, kb) in pairs {
        let (a, b) = (&faces[ka as usize], &faces[kb as usize]);
        // depth_A − depth_B = α·X + β·Y + γ.
        let k = |f: &Face| {
            let [pa, pb, pc, pd] = f.plane;
            [pa / pc, pb / pc, pd / pc]
        };
        let (ca, cb) = (k(a), k(b));
        let (al, be, ga) = (cb[0] - ca[0], cb[1] - ca[1], cb[2] - ca[2]);
        let size = ca[0].abs() + ca[1].abs() + cb[0].abs() + cb[1].abs();
        if al.abs() + be.abs() <= 1e-12 * size || !(al.is_finite() && be.is_finite()) {
            continue; // parallel planes: no line
        }
        for (p0, p1) in line_in_both(a, b, (al, be, ga)) {
            stats.intersection_lines += 1;
            let line = Line {
                p0,
                p1,
                z0: a.depth_at(p0),
                z1: a.depth_at(p1),
                owners: [ka, kb],
                tie: a.index.min(b.index),
            };
            let hidden = frame.hidden(scratch, &line, stats);
            let colour = if a.index < b.index {
                a.colour
            } else {
                b.colour
            };
            stats.intersections += frame.emit_visible(&line, &hidden, colour, true, emit);
        }
    }
}

/// Do two faces have a vertex in common: the same screen X, Y and depth, bit for bit? A
/// mesh's faces that meet along an edge or at a corner carry the same numbers there (the
/// stages transform a shared vertex alike), so this is exact, with no tolerance to choose.
fn shares_vertex(a: &Face, b: &Face) -> bool {
    a.points.iter().zip(&a.depths).any(|(p, z)| {
        b.points
            .iter()
            .zip(&b.depths)
            .any(|(q, w)| p.x == q.x && p.y == q.y && z == w)
    })
}

/// The pieces of the line α·X + β·Y + γ = 0 inside both polygons (even-odd).
fn line_in_both(a: &Face, b: &Face, (al, be, ga): (f64, f64, f64)) -> Vec<(DVec2, DVec2)> {
    // The line across the two boxes' common part.
    let (lo, hi) = (a.min.max(b.min), a.max.min(b.max));
    let n2 = al * al + be * be;
    let base = DVec2::new(-ga * al / n2, -ga * be / n2);
    let dir = DVec2::new(-be, al);
    let (mut s0, mut s1) = (f64::NEG_INFINITY, f64::INFINITY);
    for (p, d, l, h) in [(base.x, dir.x, lo.x, hi.x), (base.y, dir.y, lo.y, hi.y)] {
        if d == 0.0 {
            if p < l || p > h {
                return vec![];
            }
        } else {
            let (u, v) = ((l - p) / d, (h - p) / d);
            s0 = s0.max(u.min(v));
            s1 = s1.min(u.max(v));
        }
    }
    if s0.partial_cmp(&s1) != Some(std::cmp::Ordering::Less) {
        return vec![];
    }
    let (q0, q1) = (base + dir * s0, base + dir * s1);
    let inside = |f: &Face| -> Vec<(f64, f64)> {
        let r = q1 - q0;
        let mut ts = vec![0.0, 1.0];
        for j in 0..f.points.len() {
            let (e0, e1) = f.edge(j);
            let s = e1 - e0;
            let denom = cross(r, s);
            if denom == 0.0 {
                continue;
            }
            let t = cross(e0 - q0, s) / denom;
            let u = cross(e0 - q0, r) / denom;
            if t > 0.0 && t < 1.0 && (0.0..=1.0).contains(&u) {
                ts.push(t);
            }
        }
        ts.sort_by(f64::total_cmp);
        let mut out: Vec<(f64, f64)> = Vec::new();
        for k in 0..ts.len() - 1 {
            let (t0, t1) = (ts[k], ts[k + 1]);
            if t1 > t0 && f.inside(q0 + r * (0.5 * (t0 + t1))) {
                add_interval(&mut out, (t0, t1));
            }
        }
        out
    };
    let (ia, ib) = (inside(a), inside(b));
    let mut out = Vec::new();
    for &(a0, a1) in &ia {
        for &(b0, b1) in &ib {
            let (t0, t1) = (a0.max(b0), a1.min(b1));
            if t1 > t0 {
                let r = q1 - q0;
                out.push((q0 + r * t0, q0 + r * t1));
            }
        }
    }
    out
}

/// An edge's key: its ends, in either direction, bit for bit.
fn edge_key(p0: DVec2, p1: DVec2) -> [u64; 4] {
    let (u, v) = if (p0.x, p0.y) <= (p1.x, p1.y) {
        (p0, p1)
    } else {
        (p1, p0)
    };
    [u.x, u.y, v.x, v.y].map(f64::to_bits)
}

/// The first of an edge's `owners` (stream order) that shows just beside the middle of
/// the edge p0→p1: whose inside a hair from the edge is hidden by no other polygon. The
/// polygon in front is found once on each side of the edge (one pass over the cell's
/// list), so that an edge a pile of copies share costs the pile once, not once a copy.
fn beside_front<'f>(frame: &'f Frame, p0: DVec2, p1: DVec2, owners: &[u32]) -> Option<&'f Face> {
    let m = (p0 + p1) * 0.5;
    let d = p1 - p0;
    let n = DVec2::new(-d.y, d.x) * (1e-6 / d.length().max(1e-300)) * (1.0 + m.abs().max_element());
    let tol = 1e-9;
    // The polygon in front at q among those holding it strictly inside: nearer by more
    // than the rounding, or within it and earlier in the stream.
    let front = |q: DVec2| -> Option<u32> {
        let list = &frame.grid.cells[frame.grid.cell_of(q)];
        let mut best: Option<(u32, f64)> = None;
        for &k in list {
            let b = &frame.faces[k as usize];
            if !b.strictly_inside(q, tol) {
                continue;
            }
            let zb = b.depth_at(q);
            let wins = match best {
                None => true,
                Some((h, z)) => {
                    let scale = 1e-12 * (1.0 + z.abs());
                    if (zb - z).abs() <= scale {
                        b.index < frame.faces[h as usize].index
                    } else {
                        zb < z
                    }
                }
            };
            if wins {
                best = Some((k, zb));
            }
        }
        best.map(|(k, _)| k)
    };
    let sides = [m + n, m - n].map(|q| (q, front(q)));
    owners
        .iter()
        .map(|&k| (k, &frame.faces[k as usize]))
        .find_map(|(k, f)| {
            let (_, shown) = sides.iter().find(|(q, _)| f.strictly_inside(*q, tol))?;
            (*shown == Some(k)).then_some(f)
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square at depth `z` from (x0, y0) to (x1, y1) in screen coordinates; also the
    /// fixture of Archuleta's method's tests.
    pub(crate) use scan::frame::square;

    /// Red square at depth 0.5, and blue sloping through red's plane at X = 40, inside
    /// red: the line of intersection is X = 40 from Y = 30 to Y = 50.
    pub(crate) fn crossing_pair() -> [Polygon; 2] {
        let red = square(RED, 10.0, 10.0, 70.0, 70.0, 0.5);
        let blue = Polygon::from_xyz(
            BLUE,
            &[
                [20.0, 30.0, 0.7],
                [60.0, 30.0, 0.3],
                [60.0, 50.0, 0.3],
                [20.0, 50.0, 0.7],
            ],
        );
        [red, blue]
    }

    fn lines(polygons: &[Polygon]) -> Vec<(f64, f64, f64, f64, Colour)> {
        let mut stats = LineStats::default();
        visible_segments(polygons, 100, 100, &mut stats)
            .iter()
            .map(|s| (s.from.x, s.from.y, s.to.x, s.to.y, s.colour))
            .collect()
    }

    pub(crate) const RED: Colour = [255, 0, 0];
    const GREEN: Colour = [0, 255, 0];
    pub(crate) const BLUE: Colour = [0, 0, 255];

    #[test]
    fn a_nearer_square_hides_part_of_a_farther_one() {
        // Red (near) over the top-left corner of blue (far).
        let red = square(RED, 10.0, 10.0, 50.0, 50.0, 0.2);
        let blue = square(BLUE, 30.0, 30.0, 70.0, 70.0, 0.6);
        let want = vec![
            (10.0, 10.0, 50.0, 10.0, RED),
            (50.0, 10.0, 50.0, 50.0, RED),
            (50.0, 50.0, 10.0, 50.0, RED),
            (10.0, 50.0, 10.0, 10.0, RED),
            (50.0, 30.0, 70.0, 30.0, BLUE),
            (70.0, 30.0, 70.0, 70.0, BLUE),
            (70.0, 70.0, 30.0, 70.0, BLUE),
            (30.0, 70.0, 30.0, 50.0, BLUE),
        ];
        assert_eq!(lines(&[red.clone(), blue.clone()]), want);
        // Stream order does not matter when depths differ.
        let mut swapped = lines(&[blue, red]);
        swapped.sort_by(|a, b| a.partial_cmp(b).unwrap());
        let mut want = want;
        want.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(swapped, want);
    }

    #[test]
    fn at_equal_depth_the_earlier_hides_the_later() {
        let a = square(RED, 10.0, 10.0, 50.0, 50.0, 0.5);
        let b = square(BLUE, 30.0, 30.0, 70.0, 70.0, 0.5);
        let l = lines(&[a.clone(), b.clone()]);
        assert_eq!(l.len(), 8);
        assert!(l.contains(&(30.0, 70.0, 30.0, 50.0, BLUE)));
        assert!(l.contains(&(50.0, 50.0, 10.0, 50.0, RED)));
        let l = lines(&[b, a]);
        // Now blue is first: red's corner inside blue is hidden.
        assert!(l.contains(&(50.0, 10.0, 50.0, 30.0, RED)));
        assert!(l.contains(&(30.0, 50.0, 10.0, 50.0, RED)));
        assert!(l.contains(&(30.0, 70.0, 30.0, 30.0, BLUE)));
    }

    #[test]
    fn a_shared_edge_is_drawn_once_in_the_earlier_colour() {
        let left = square(RED, 10.0, 10.0, 40.0, 40.0, 0.5);
        let right = square(BLUE, 40.0, 10.0, 70.0, 40.0, 0.3);
        let mut stats = LineStats::default();
        let segs = visible_segments(&[left, right], 100, 100, &mut stats);
        assert_eq!(segs.len(), 7);
        assert_eq!(stats.shared, 1);
        let on_x40: Vec<_> = segs
            .iter()
            .filter(|s| s.from.x == 40.0 && s.to.x == 40.0)
            .collect();
        assert_eq!(on_x40.len(), 1);
        assert_eq!(on_x40[0].colour, RED);
    }

    #[test]
    fn penetration_hides_up_to_the_crossing() {
        // Blue slopes through red's plane (z = 0.5) at X = 40: nearer on the right.
        let red = square(RED, 10.0, 10.0, 70.0, 70.0, 0.5);
        let blue = Polygon::from_xyz(
            BLUE,
            &[
                [20.0, 30.0, 0.7],
                [60.0, 30.0, 0.3],
                [60.0, 50.0, 0.3],
                [20.0, 50.0, 0.7],
            ],
        );
        let l = lines(&[red, blue]);
        let blue_lines: Vec<_> = l.iter().filter(|s| s.4 == BLUE).collect();
        assert_eq!(
            blue_lines,
            vec![
                &(40.0, 30.0, 60.0, 30.0, BLUE),
                &(60.0, 30.0, 60.0, 50.0, BLUE),
                &(60.0, 50.0, 40.0, 50.0, BLUE),
            ]
        );
    }

    #[test]
    fn the_line_where_two_polygons_cross_is_drawn() {
        // Blue slopes through red's plane (z = 0.5) at X = 40, inside red: the line of
        // intersection is X = 40 across blue, from Y = 30 to Y = 50, in red's colour
        // (red is earlier in the stream).
        let [red, blue] = crossing_pair();
        let mut stats = LineStats::default();
        let segs = visible_segments(&[red.clone(), blue.clone()], 100, 100, &mut stats);
        let crossing: Vec<_> = segs.iter().filter(|s| s.intersection).collect();
        assert_eq!(crossing.len(), 1, "{segs:?}");
        let c = crossing[0];
        let ends = [(c.from.x, c.from.y), (c.to.x, c.to.y)];
        assert!(
            ends.iter().all(|&(x, y)| (x - 40.0).abs() < 1e-9
                && ((y - 30.0).abs() < 1e-9 || (y - 50.0).abs() < 1e-9)),
            "{c:?}"
        );
        assert!((c.from.y - c.to.y).abs() > 19.999);
        assert_eq!(c.colour, RED);
        assert_eq!((stats.intersection_lines, stats.intersections), (1, 1));
        // A third square in front of the middle of it hides Y = 35..45 of it.
        let front = square(GREEN, 30.0, 35.0, 50.0, 45.0, 0.1);
        let segs = visible_segments(&[red, blue, front], 100, 100, &mut stats);
        let mut crossing: Vec<(f64, f64)> = segs
            .iter()
            .filter(|s| s.intersection)
            .map(|s| (s.from.y.min(s.to.y), s.from.y.max(s.to.y)))
            .collect();
        crossing.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(crossing.len(), 2);
        assert!((crossing[0].0 - 30.0).abs() < 1e-9 && (crossing[0].1 - 35.0).abs() < 1e-9);
        assert!((crossing[1].0 - 45.0).abs() < 1e-9 && (crossing[1].1 - 50.0).abs() < 1e-9);
        // Parallel planes have no line.
        let a = square(RED, 10.0, 10.0, 70.0, 70.0, 0.5);
        let b = square(BLUE, 20.0, 20.0, 60.0, 60.0, 0.25);
        let segs = visible_segments(&[a, b], 100, 100, &mut LineStats::default());
        assert!(segs.iter().all(|s| !s.intersection));
    }

    #[test]
    fn a_stack_costs_one_polygon_per_cell() {
        // 400 squares over the same 80×80, nearest in the middle of the stream: in every
        // cell the nearest surrounds it and the others are left out (the ZMIN test), so
        // the hidden edges are never tested against the stack.
        let polygons: Vec<Polygon> = (0..400)
            .map(|k| {
                let z = 0.1 + 0.002 * ((k * 241) % 400) as f64;
                square([k as u8, 1, 2], 10.0, 10.0, 90.0, 90.0, z)
            })
            .collect();
        let mut stats = LineStats::default();
        let segs = visible_segments(&polygons, 100, 100, &mut stats);
        // Four edges of the nearest (k = 0: z = 0.1) drawn; the same edges of the others
        // are shared with it and drawn once.
        assert_eq!(segs.len(), 4);
        assert!(segs.iter().all(|s| s.colour == [0, 1, 2]));
        assert_eq!(stats.shared, 4 * 399);
        assert_eq!(stats.pairs_tested, 0);
        assert!(stats.culled > 0);
        // Smaller squares stacked behind a screen-filling one are hidden in their
        // cells: their edges are hidden without a test (and the screen-filling one's
        // edges are the screen's border).
        let mut polygons = vec![square(RED, 0.0, 0.0, 100.0, 100.0, 0.05)];
        polygons.extend((0..300).map(|k| {
            square(
                BLUE,
                20.0 + (k % 7) as f64,
                20.0,
                60.0,
                60.0,
                0.5 + k as f64 * 1e-3,
            )
        }));
        let mut stats = LineStats::default();
        let segs = visible_segments(&polygons, 100, 100, &mut stats);
        assert_eq!(segs.len(), 0);
        assert_eq!((stats.border, stats.pairs_tested), (4, 0));
    }

    #[test]
    fn splitter_cuts_and_the_screen_border_are_left_out() {
        // A square cut at X = 40 into two pieces that carry the whole's plane.
        let plane = proto::DVec4::new(0.0, 0.0, 1.0, -0.5);
        let mut l = square(RED, 10.0, 10.0, 40.0, 40.0, 0.5);
        let mut r = square(RED, 40.0, 10.0, 70.0, 40.0, 0.5);
        l.plane = Some(plane);
        r.plane = Some(plane);
        // A polygon the clipper cut at the screen's left and top.
        let clipped = square(BLUE, 0.0, 0.0, 5.0, 5.0, 0.9);
        let mut stats = LineStats::default();
        let segs = visible_segments(&[l, r, clipped], 100, 100, &mut stats);
        assert_eq!((stats.cuts, stats.border), (2, 2));
        assert_eq!(segs.len(), 6 + 2);
        assert!(segs.iter().all(|s| !(s.from.x == 40.0 && s.to.x == 40.0)));
    }

    #[test]
    fn degenerate_polygons_draw_and_hide_nothing() {
        let line = Polygon::from_xyz(
            RED,
            &[[0.0, 0.0, 0.1], [50.0, 50.0, 0.1], [20.0, 20.0, 0.1]],
        );
        let two = Polygon::from_xyz(RED, &[[0.0, 0.0, 0.1], [50.0, 50.0, 0.1]]);
        let sq = square(BLUE, 10.0, 10.0, 30.0, 30.0, 0.5);
        assert_eq!(lines(&[line, two, sq]).len(), 4);
        assert_eq!(lines(&[]), vec![]);
    }

    #[test]
    fn svg_in_device_coordinates() {
        let segs = [Segment {
            from: DVec2::new(1.5, 2.0),
            to: DVec2::new(3.0, 0.1),
            colour: [1, 2, 3],
            intersection: false,
        }];
        assert_eq!(
            svg(&segs, 8, 6, [255, 255, 255], 1.0),
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"8\" height=\"6\" viewBox=\"0 0 8 6\">\n\
             <rect width=\"8\" height=\"6\" fill=\"rgb(255,255,255)\"/>\n\
             <g fill=\"none\" stroke-width=\"1\" stroke-linecap=\"round\">\n\
             <line x1=\"1.5\" y1=\"2\" x2=\"3\" y2=\"0.1\" stroke=\"rgb(1,2,3)\"/>\n\
             </g>\n</svg>\n"
        );
    }

    mod properties {
        use super::*;
        use proptest::prelude::*;

        proptest! {
            /// Flat squares at distinct depths: a point of an edge is drawn exactly when
            /// no nearer square has it strictly inside (checked at many points).
            #[test]
            fn drawn_points_are_those_no_nearer_square_covers(
                squares in prop::collection::vec(([0.0f64..80.0, 0.0f64..80.0, 1.0f64..40.0, 1.0f64..40.0], 0u8..255), 1..6),
            ) {
                let polygons: Vec<Polygon> = squares.iter().enumerate().map(|(i, &([x, y, w, h], c))| {
                    square([c, i as u8, 0], x, y, x + w, y + h, 0.1 + 0.1 * ((i * 7) % 6) as f64)
                }).collect();
                let mut stats = LineStats::default();
                let segs = visible_segments(&polygons, 100, 100, &mut stats);
                let faces: Vec<Face> = polygons.iter().enumerate().filter_map(|(i, p)| Face::of(i, p)).collect();
                for a in &faces {
                    for e in 0..4 {
                        let (p0, p1) = a.edge(e);
                        for k in 1..40 {
                            let q = p0 + (p1 - p0) * (k as f64 / 40.0 + 0.0031);
                            let z = a.depths[0];
                            let covered = faces.iter().any(|b| b.index != a.index && b.depths[0] < z && b.strictly_inside(q, 1e-6));
                            let near_cover = faces.iter().any(|b| b.index != a.index && b.on_boundary(q, 1e-6));
                            if near_cover { continue; }
                            let drawn = segs.iter().any(|s| {
                                s.colour == a.colour && {
                                    let d = s.to - s.from;
                                    let t = (q - s.from).dot(d) / d.length_squared();
                                    (-1e-9..=1.0 + 1e-9).contains(&t) && (s.from + d * t - q).length() < 1e-6
                                }
                            });
                            prop_assert_eq!(drawn, !covered, "edge {} of {} at {:?}", e, a.index, q);
                        }
                    }
                }
            }
        }
    }
}
