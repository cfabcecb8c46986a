//! # painter: depth sort, drawn back to front (Newell, Newell and Sancha)
//!
//! The depth-priority method of Sutherland, Sproull and Schumacker's survey, "A
//! Characterization of Ten Hidden-Surface Algorithms" (1974: the survey the thesis cites
//! as \[SuSp74\] for its cost figures, chapter 5.1), after Newell, Newell and Sancha (1972):
//! sort the frame's polygons by their farthest depth, then paint them from the back to
//! the front into a frame of colours alone: no depth buffer, a nearer polygon simply
//! paints over a farther one, and each pixel ends with the colour painted last. Sorting
//! by one number per polygon is not enough where depth extents overlap, so before the
//! polygon P at the head of the list is painted it is checked against every polygon Q
//! whose depth extent overlaps its own, by the five tests, the cheapest first; any one
//! that succeeds shows that P hides no part of Q:
//!
//! 1. the depth extents of the vertices do not overlap (P is wholly farther than Q);
//! 2. the screen bounding boxes of the vertices do not overlap;
//! 3. every vertex of P lies behind Q's plane (or on it);
//! 4. every vertex of Q lies in front of P's plane (or on it);
//! 5. the projections do not overlap: a line through an edge of one has it on one side
//!    and the other on the other (for polygons not convex, failing that: no two edges
//!    cross, no vertex of one lies inside the other, the outlines do not touch).
//!
//! All five are decided on the polygons' geometry: the screen vertices (X, Y, depth),
//! their planes (`a·X + b·Y + c·depth + d = 0`, persp's recorded plane or Newell's), their
//! edges. Nothing is scan converted until a polygon is painted.
//!
//! When all five fail, Q is moved to the head of the list (it is painted before P) and
//! marked. A marked polygon that would have to move again shows a *cycle*: polygons that
//! overlap cyclically, or that pass through each other (the thesis's own test scene). The
//! survey's answer is the splitting step ([`Painter::with_split`]): Q is cut by P's plane
//! (or P by Q's, when Q does not straddle P's plane), with proto's Sutherland–Hodgman
//! primitives (the clipper's side test and edge crossing, [`proto::geometry::Plane`]), and
//! the pieces re-enter the sort at the head of the list, unmarked. Without the splitting
//! step, or once the frame's *cut budget* is spent, the cycle is painted in the order at
//! hand: the failure is kept and counted ([`PainterStats::given_up`]), and `painter` says
//! so on stderr. After the frame is painted, the centres beside each cut line that the
//! snapped pieces gave to the polygon behind there are mended ([`PainterStats::mended`]).
//!
//! ## Departures
//!
//! * Ties: at equal depth the z-buffer gives a pixel to the polygon earlier in the
//!   stream. A vertex within a rounding band of the other's plane counts as on it, and
//!   when every vertex is on it (coplanar polygons) tests 3 and 4 put the earlier polygon
//!   in front, so that coplanar scenes paint as the z-buffer draws them.
//! * The pieces of a cut keep, on every edge that lies on an edge of the whole, that edge
//!   as its *support* (proto's polygon annotation): the scan converter then computes their
//!   crossings from the whole edge, so the pieces cover exactly the pixels of the whole,
//!   each once; pixels on the cut line go to one piece by the sampling rule.
//! * What is cut: only a polygon whose plane gives its own vertices' depths (planar, and
//!   well conditioned) is cut or cut by, into pieces of at most [`MAX_PIECE_VERTICES`];
//!   a crossing within 10⁻⁶ pixel of a vertex is that vertex; a polygon whose vertices
//!   all lie on one line covers no pixel centre and is not sorted (each found by the
//!   `methods` fuzz target: pieces that lost pixels).
//! * Gouraud shading (docs/DESIGN.md, "Shading"): a shaded polygon is painted in its
//!   colour planes' value at each pixel centre (`proto::shade`, the z-buffer's calls), and
//!   a piece in the whole polygon's, found by the piece's index in the frame: the pieces
//!   are shaded as the whole would be.
//! * The cut budget ([`Painter::cut_budget`]): at most `n + 2048` cuts in a frame of n
//!   polygons. Every pair of N planes that all pass through each other must be cut (N² /
//!   2 pieces and more), and every cut adds a polygon the sort must test: unbounded, the
//!   method's time grows with the cube of the scene.
//!
//! The sorted list is a sorted run with the moved polygons (and pieces) in front of it, so
//! the search for the Q's that overlap P in depth stops at the first unmoved polygon
//! wholly nearer than P reaches: every one after it is nearer still.

use proto::geometry::{newell_plane, Plane, Side};
use proto::shade::{Lighting, Shading};
use proto::{Colour, DVec2, DVec3, DVec4, Polygon, Vertex};
use scan::frame::{push_row_runs, shaded_runs, HiddenSurface};
use scan::{depth_at, takes, DepthPlane, Run, SpanWalker};
use std::collections::VecDeque;
use std::sync::Arc;

/// The five tests of Newell, Newell and Sancha, in the order they are tried.
pub const TESTS: [&str; 5] = [
    "depth extents",
    "bounding boxes",
    "P behind Q's plane",
    "Q in front of P's plane",
    "projections disjoint",
];

/// The painter's counters over all frames.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PainterStats {
    /// Polygons sorted (of three vertices or more; pieces not counted).
    pub polygons: u64,
    /// Polygons and pieces painted.
    pub painted: u64,
    /// How many pairs (P, Q) each test resolved, test 1 first.
    pub resolved_by: [u64; 5],
    /// Pairs every test failed on.
    pub unresolved: u64,
    /// Polygons moved to the head of the list (painted earlier than sorted).
    pub swaps: u64,
    /// Times a marked polygon would have had to move again: a cyclic overlap or an
    /// interpenetration.
    pub cycles: u64,
    /// Cuts made by the splitting step.
    pub splits: u64,
    /// Cycles painted in the order at hand (no split possible, none asked for, or the
    /// cut budget spent) that left a pixel wrong: the method's failure.
    pub given_up: u64,
    /// Cycles painted in the order at hand that left no pixel wrong: every pixel P covers
    /// is held at the end of the frame by P or by a polygon in front of P there (mostly
    /// pieces that meet at a point the planes share, their outlines a rounding apart,
    /// sharing no pixel centre). Not a failure.
    pub apart: u64,
    /// Frames whose cut budget was spent.
    pub budget_spent: u64,
    /// Pixels repainted in what the z-buffer shows there ([`Painter::mend_pairs`]):
    /// beside a cut line, where the pieces' outlines gave them to the polygon behind, and
    /// where polygons the sort ordered by the tie rule meet.
    pub mended: u64,
    /// Frames whose cut lines and tied pairs were not all checked (the check's budget
    /// spent): said.
    pub unchecked: u64,
}

/// How far a cut moves the cutting plane in depth, relative to its depth scale
/// (1 + |the plane's constant|): a pixel centre exactly on the line of intersection then
/// falls strictly inside the piece the tie rule puts there ([`cut`]). Far less than a
/// pixel's depth step.
const CUT_HAIR: f64 = 1e-11;

/// The band, relative to the sum of the magnitudes of a distance's terms, within which a
/// vertex counts as on another polygon's plane, in tests 3 and 4 and in deciding whether
/// a polygon straddles a plane. The distance is proto's ([`Plane::distance`], the
/// clipper's sum in its order), but not proto's band ([`Plane::classify`]: 4 machine
/// epsilons of the same sum, the rounding of the distance itself): these tests must also
/// absorb persp's rounding of the vertex depths and of the planes fitted to them (two
/// coplanar polygons must tie), and the pieces of a cut, whose vertices on the cut line
/// lie on the cutting plane moved by [`CUT_HAIR`], a hundredth of this band. Under proto's
/// band those vertices are a hair in front of or behind the cutter's plane, a piece
/// straddles the plane it was cut by, and the cycles that splitting mends stay
/// unresolved (six of the unit tests fail with it, among them
/// `interpenetrating_squares_fail_and_split_mends_them`).
const ON_PLANE: f64 = 1e-9;

/// A polygon's depth plane (a, b, 1, d), the points at depth −(a·X + b·Y + d), with `d`
/// moved by `moved`, as the clipper's [`Plane`]: the distance of a vertex (X, Y, depth),
/// `((a·X + b·Y) + depth) + d`, is positive behind the plane.
fn depth_plane_as_plane(p: DVec4, moved: f64) -> Plane {
    Plane::new(DVec4::new(p.x, p.y, 1.0, p.w + moved), 0.0)
}

/// Where a point lies against a polygon's plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Depthwise {
    Front,
    On,
    Behind,
}

/// A polygon of the list (or a piece of one): its screen vertices and what the tests ask
/// about them.
#[derive(Clone, Debug)]
struct Item {
    /// Its place in the stream: at equal depth the earlier wins.
    index: usize,
    polygon: Polygon,
    /// The depth plane `a·X + b·Y + c·depth + d = 0`, scaled so that c = 1: the depth at
    /// (X, Y) is `−(a·X + b·Y + d)`.
    plane: DVec4,
    x_min: f64,
    x_max: f64,
    y_min: f64,
    y_max: f64,
    /// Depth extent of the vertices (smaller is nearer).
    z_min: f64,
    z_max: f64,
    /// Moved to the head since the last polygon was painted (the survey's mark, kept as
    /// the `generation` it was made in: painting a polygon starts a new one).
    moved: u64,
    /// Still in the sorted run of the list (not moved, not a piece).
    sorted: bool,
    /// Its plane gives its own vertices' depths (to 10⁻³): only such a polygon is cut,
    /// or cut by. A polygon that is not planar, or whose plane's terms cancel (a depth
    /// of 10³⁰⁴ beside depths of 1), would be cut along a line its plane misplaces, into
    /// pieces that need not tile it.
    cuttable: bool,
}

/// The depth plane of a polygon's screen vertices, with c = 1: persp's recorded plane,
/// else Newell's (as [`scan::DepthPlane::of`] takes it); a polygon seen edge-on (c = 0)
/// or of no area gets the flat plane of its nearest vertex, as the z-buffer does.
fn depth_plane(polygon: &Polygon) -> DVec4 {
    let points: Vec<DVec3> = polygon.vertices.iter().map(|v| v.truncate()).collect();
    let n = polygon
        .plane
        .filter(|n| n.z != 0.0 && n.is_finite())
        .unwrap_or_else(|| newell_plane(&points));
    let unit = n / n.z;
    if n.z != 0.0 && unit.is_finite() {
        unit
    } else {
        let nearest = points.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
        DVec4::new(0.0, 0.0, 1.0, -nearest)
    }
}

impl Item {
    fn new(index: usize, polygon: Polygon, plane: DVec4) -> Item {
        let mut item = Item {
            index,
            polygon,
            plane,
            x_min: f64::INFINITY,
            x_max: f64::NEG_INFINITY,
            y_min: f64::INFINITY,
            y_max: f64::NEG_INFINITY,
            z_min: f64::INFINITY,
            z_max: f64::NEG_INFINITY,
            moved: 0,
            sorted: true,
            cuttable: true,
        };
        item.cuttable = (0..item.polygon.vertices.len()).all(|i| {
            let (z, on) = (item.polygon.vertices[i].z, item.vertex(i).z);
            (z - on).abs() <= 1e-3 * (1.0 + z.abs() + on.abs())
        });
        for i in 0..item.polygon.vertices.len() {
            let v = item.vertex(i);
            item.x_min = item.x_min.min(v.x);
            item.x_max = item.x_max.max(v.x);
            item.y_min = item.y_min.min(v.y);
            item.y_max = item.y_max.max(v.y);
            item.z_min = item.z_min.min(v.z);
            item.z_max = item.z_max.max(v.z);
        }
        item
    }

    /// Vertex `i` with its depth on the polygon's own plane: the depth the z-buffer gives
    /// the polygon's pixels there (persp's vertex depths may lie a rounding off the
    /// recorded plane, and two planes that cross at a shallow angle would move their line
    /// of intersection by that much over many pixels).
    fn vertex(&self, i: usize) -> Vertex {
        let v = self.polygon.vertices[i];
        let p = self.plane;
        DVec4::new(v.x, v.y, -(p.x * v.x + p.y * v.y + p.w), 1.0)
    }

    /// Where `v` lies against this polygon's plane, within [`ON_PLANE`] of the terms'
    /// size.
    fn side(&self, v: Vertex) -> Depthwise {
        let plane = depth_plane_as_plane(self.plane, 0.0);
        let v = v.with_w(1.0);
        let d = plane.distance(v);
        let scale = (plane.n * v).abs().element_sum();
        if d.abs() <= ON_PLANE * scale {
            Depthwise::On
        } else if d > 0.0 {
            Depthwise::Behind
        } else {
            Depthwise::Front
        }
    }

    /// Every vertex of `self` on the `wanted` side of `other`'s plane or on it; when all
    /// are on it, `earlier_wins` decides (the coplanar tie).
    fn wholly(&self, other: &Item, wanted: Depthwise, tie: bool) -> bool {
        let mut all_on = true;
        for i in 0..self.polygon.vertices.len() {
            match other.side(self.vertex(i)) {
                Depthwise::On => {}
                s if s == wanted => all_on = false,
                _ => return false,
            }
        }
        !all_on || tie
    }

    /// Whether every vertex of `self` lies on `other`'s plane (within [`ON_PLANE`]).
    fn coplanar_with(&self, other: &Item) -> bool {
        (0..self.polygon.vertices.len()).all(|i| other.side(self.vertex(i)) == Depthwise::On)
    }

    /// Whether some vertices lie strictly in front of `other`'s plane and some strictly
    /// behind it: a cut by that plane leaves two pieces with area.
    fn straddles(&self, other: &Item) -> bool {
        let (mut front, mut behind) = (false, false);
        for i in 0..self.polygon.vertices.len() {
            match other.side(self.vertex(i)) {
                Depthwise::Front => front = true,
                Depthwise::Behind => behind = true,
                Depthwise::On => {}
            }
        }
        front && behind
    }
}

/// Twice the signed area of the triangle (a, b, c).
#[inline]
fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)
}

/// Whether segments (a, b) and (c, d) cross at a point inside both (touching, collinear
/// overlap and shared ends do not count: the sampling rule gives a pixel on a shared
/// boundary to one polygon only).
fn edges_cross(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    // A point within a rounding band of the other segment's line is on it.
    let band = |p: DVec2, q: DVec2| 1e-10 * (q - p).length_squared().max(f64::MIN_POSITIVE);
    let (ab, cd) = (band(a, b), band(c, d));
    let (o1, o2) = (orient(a, b, c), orient(a, b, d));
    let (o3, o4) = (orient(c, d, a), orient(c, d, b));
    let apart = |x: f64, y: f64, band: f64| (x > band && y < -band) || (x < -band && y > band);
    apart(o1, o2, ab) && apart(o3, o4, cd)
}

/// Whether `p` lies strictly inside the polygon `poly` (crossing number; a point on an
/// edge, to rounding, is not inside).
fn strictly_inside(p: DVec2, poly: &[DVec2]) -> bool {
    let n = poly.len();
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        let o = orient(a, b, p);
        let len = (b - a).length();
        if o.abs() <= 1e-12 * (len * (len + (p - a).length())).max(f64::MIN_POSITIVE)
            && (p - a).dot(b - a) >= 0.0
            && (p - b).dot(a - b) >= 0.0
        {
            return false;
        }
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            inside = !inside;
        }
    }
    inside
}

/// Whether `c` lies on the far side of the line through the edge (a, b) from the polygon,
/// or on it to within a rounding band: `side` is the sign the polygon's own vertices
/// take (+1 or −1).
#[inline]
fn beyond(a: DVec2, b: DVec2, c: DVec2, side: f64) -> bool {
    let band = 1e-10 * (b - a).length_squared().max(f64::MIN_POSITIVE);
    orient(a, b, c) * side <= band
}

/// The side (+1 or −1) of the line through the edge (a, b) on which every vertex of
/// `poly` lies, to within the band (a *supporting* edge), if there is one.
fn supporting_side(a: DVec2, b: DVec2, poly: &[DVec2]) -> Option<f64> {
    let band = 1e-10 * (b - a).length_squared().max(f64::MIN_POSITIVE);
    let (mut pos, mut neg) = (false, false);
    for &v in poly {
        let o = orient(a, b, v);
        pos |= o > band;
        neg |= o < -band;
    }
    match (pos, neg) {
        (true, false) => Some(1.0),
        (false, true) => Some(-1.0),
        _ => None,
    }
}

/// Whether a line through an edge of `pp` that has all of `pp` on one side has all of
/// `qq` on the other (or on the line): the projections' interiors are then disjoint,
/// whatever their shapes. Also says whether every edge of `pp` was such an edge (`pp` is
/// convex).
fn separated_by_an_edge_of(pp: &[DVec2], qq: &[DVec2]) -> (bool, bool) {
    let n = pp.len();
    let mut convex = true;
    for i in 0..n {
        let (a, b) = (pp[i], pp[(i + 1) % n]);
        if a == b {
            continue;
        }
        match supporting_side(a, b, pp) {
            Some(side) => {
                if qq.iter().all(|&c| beyond(a, b, c, side)) {
                    return (true, convex);
                }
            }
            None => convex = false,
        }
    }
    (false, convex)
}

/// Whether `p` lies on the segment (a, b), to within the band of [`edges_cross`].
fn on_segment(p: DVec2, a: DVec2, b: DVec2) -> bool {
    let band = 1e-10 * (b - a).length_squared().max(f64::MIN_POSITIVE);
    orient(a, b, p).abs() <= band && (p - a).dot(b - a) >= 0.0 && (p - b).dot(a - b) >= 0.0
}

/// Test 5's question: do the projections of two polygons share an interior point?
///
/// A line through an edge of either that has that polygon on one side and the other on
/// the other side shows they do not (the separating axis: for two convex polygons, the
/// pieces of a cut, there is such an edge exactly when they share no interior point).
/// For a polygon that is not convex, they share one if two edges cross, a vertex of one
/// lies inside the other, or (not knowing better) the outlines touch: edges crossing and
/// vertices inside alone miss two wedges with a common apex whose edges lie along each
/// other (the pieces of planes that all pass through one point), which overlap with no
/// edge crossing and no vertex strictly inside.
fn projections_overlap(p: &Polygon, q: &Polygon) -> bool {
    let pp: Vec<DVec2> = p.vertices.iter().map(|v| v.truncate().truncate()).collect();
    let qq: Vec<DVec2> = q.vertices.iter().map(|v| v.truncate().truncate()).collect();
    let (apart, p_convex) = separated_by_an_edge_of(&pp, &qq);
    if apart {
        return false;
    }
    let (apart, q_convex) = separated_by_an_edge_of(&qq, &pp);
    if apart {
        return false;
    }
    if p_convex && q_convex {
        return true;
    }
    let (n, m) = (pp.len(), qq.len());
    for i in 0..n {
        let (a, b) = (pp[i], pp[(i + 1) % n]);
        for j in 0..m {
            if edges_cross(a, b, qq[j], qq[(j + 1) % m]) {
                return true;
            }
        }
    }
    let touches = |vs: &[DVec2], poly: &[DVec2]| {
        let k = poly.len();
        vs.iter()
            .any(|&v| (0..k).any(|j| on_segment(v, poly[j], poly[(j + 1) % k])))
    };
    pp.iter().any(|&v| strictly_inside(v, &qq))
        || qq.iter().any(|&v| strictly_inside(v, &pp))
        || touches(&pp, &qq)
        || touches(&qq, &pp)
}

/// The first of the five tests that shows P may be painted before Q (P hides no part of
/// Q), numbered from 0; `None` when all fail.
fn first_passing_test(p: &Item, q: &Item) -> Option<usize> {
    // Pieces of one polygon part it: they share no interior point (test 5, known).
    if p.index == q.index {
        return Some(4);
    }
    // 1. Depth extents: P wholly farther, by the tie rule (`proto::depth`): Q's farthest
    //    point takes a pixel from P's nearest, or, Q the earlier, P's nearest could not
    //    take it from Q's farthest. Depths within 2⁻³⁰ of each other tie, and the earlier
    //    polygon must win them: decided by plain order, two constant depths 1e-9 apart
    //    were painted nearest-first whatever their order in the stream (tests 3 and 4
    //    then give the tie to the earlier, their plane band being wider than the rule's).
    if proto::depth::in_front(q.z_max, q.index > p.index, p.z_min) {
        return Some(0);
    }
    // 2. Screen bounding boxes (touching is apart: a shared boundary's pixels go to one).
    if p.x_max <= q.x_min || q.x_max <= p.x_min || p.y_max <= q.y_min || q.y_max <= p.y_min {
        return Some(1);
    }
    // 3. P wholly behind Q's plane (coplanar: P the later).
    if p.wholly(q, Depthwise::Behind, p.index > q.index) {
        return Some(2);
    }
    // 4. Q wholly in front of P's plane (coplanar: Q the earlier).
    if q.wholly(p, Depthwise::Front, q.index < p.index) {
        return Some(3);
    }
    // 5. The projections are disjoint.
    if !projections_overlap(&p.polygon, &q.polygon) {
        return Some(4);
    }
    None
}

/// Whether the sort's order of `p` and `q`, test `t` having shown that P may be painted
/// before Q, rests on the tie rule where their pixels may meet: their screen boxes
/// overlap, and test 1 passed only because Q, the earlier, keeps a pixel it ties with P
/// (Q not in front by more than the tie), or test 3 or 4 found every vertex of one on the
/// other's plane (coplanar by [`ON_PLANE`], a band wider than the tie rule's). The tie
/// rule is not transitive: with depths z, z(1 − ½t) and z(1 − 1.2t) (t its width), in
/// that stream order, each pair is ordered as the z-buffer orders it, and no order of
/// painting gives the z-buffer's pixel, the third's. Such pairs are mended at the end
/// ([`Painter::mend_pairs`]). Two polygons of one plane (copies, coplanar decals whose
/// planes came out the same) are not: equal depths tie at every pixel, a relation as
/// transitive as equality, and a third polygon near them is tied with each of them.
fn tied(p: &Item, q: &Item, t: usize) -> bool {
    let boxes_meet =
        p.x_max > q.x_min && q.x_max > p.x_min && p.y_max > q.y_min && q.y_max > p.y_min;
    boxes_meet
        && p.plane != q.plane
        && match t {
            0 => !proto::depth::takes(q.z_max, p.z_min),
            2 => p.coplanar_with(q),
            3 => q.coplanar_with(p),
            _ => false,
        }
}

/// The most vertices a piece may have. Planes that all pass near one point cut a piece
/// again and again along lines through it, and the piece's outline, a convex polygon
/// bounded by every one of them, gains a vertex at each cut (2,000 planes: pieces of
/// 2,000 vertices, test 5 then comparing millions of edge pairs, 230 MB). A cut that
/// would make a longer piece is not made: the cycle is painted in the order at hand.
pub const MAX_PIECE_VERTICES: usize = 64;

/// A piece's vertices, and for each the edges of the whole it lies on: a vertex of the
/// whole the two that meet there, a crossing the edge it cuts (twice).
type Outline = (Vec<Vertex>, Vec<(usize, usize)>);

/// The splitting step: `x` cut by `by`'s plane into the piece in front of it and the
/// piece behind, by Sutherland–Hodgman's walk over the vertices with proto's side test
/// and edge crossing (one crossing computed per cut edge, shared by both pieces, so they
/// meet exactly). Each piece's edges that lie on an edge of `x` keep that edge as their
/// support. `None` unless both pieces have three vertices.
fn cut(x: &Item, by: &Item) -> Option<(Item, Item)> {
    // The tie rule on the cut line: a pixel centre exactly on the line of intersection is
    // the earlier polygon's. The cut plane is moved by a hair ([`CUT_HAIR`] of the depth
    // scale, far less than a pixel's depth step, and within the band [`ON_PLANE`] in which
    // a vertex is on a plane) so that such centres fall strictly inside the
    // piece that the tie puts behind (x later) or in front (x earlier).
    let p = by.plane;
    let delta = CUT_HAIR * (1.0 + p.w.abs());
    let plane = depth_plane_as_plane(p, if x.index > by.index { delta } else { -delta });
    let vertices: Vec<Vertex> = (0..x.polygon.vertices.len()).map(|i| x.vertex(i)).collect();
    let n = vertices.len();
    let support = |i: usize| {
        x.polygon
            .support(i)
            .unwrap_or([vertices[i], vertices[(i + 1) % n]])
    };
    let mut pieces: [Outline; 2] = Default::default();
    // The clipper's own side test (proto's `Plane::classify`: on the plane within 4
    // machine epsilons of the sum of the distance's terms, |a·X| + |b·Y| + |depth| + |d|),
    // the plane's inside (distance > 0) being behind it: depth − the plane's depth > 0.
    let sides: Vec<(Side, f64)> = vertices
        .iter()
        .map(|&v| plane.classify(v.with_w(1.0)))
        .collect();
    for i in 0..n {
        let (s, p) = (i, (i + 1) % n);
        let ((s_side, s_d), (p_side, p_d)) = (sides[s], sides[p]);
        // Vertex s goes to the pieces it belongs to; the edge (s, p) leaves it on
        // edge s of x.
        for (k, want) in [(0usize, Side::Outside), (1, Side::Inside)] {
            if s_side == want || s_side == Side::On {
                pieces[k].0.push(vertices[s]);
                pieces[k].1.push(((s + n - 1) % n, s));
            }
        }
        if matches!(
            (s_side, p_side),
            (Side::Inside, Side::Outside) | (Side::Outside, Side::Inside)
        ) {
            let mut c = plane.intersect(vertices[s].with_w(1.0), s_d, vertices[p].with_w(1.0), p_d);
            c.w = vertices[s].w;
            // A crossing within 10⁻⁶ pixel of an end of its edge is that end: a vertex on
            // the cutting plane (two polygons that share it and cross through it) is
            // moved off it by the hair the plane is moved, and a piece whose corner sits
            // a hair below a row of centres loses that row.
            let mut edges = (s, s);
            for (end, at) in [(vertices[s], ((s + n - 1) % n, s)), (vertices[p], (s, p))] {
                if (c.x - end.x).abs() <= 1e-6 && (c.y - end.y).abs() <= 1e-6 {
                    (c, edges) = (end, at);
                }
            }
            // A crossing that rounding has put off the edge it cuts (depths of 10³⁰⁰
            // beside depths of 1: the plane's terms cancel) would give pieces that do not
            // tile the whole: no cut.
            let [s0, s1] = support(s);
            if !c.is_finite() || !on_segment_line(c, s0, s1, 1e-9) {
                return None;
            }
            for piece in &mut pieces {
                piece.0.push(c);
                piece.1.push(edges);
            }
        }
    }
    // In each piece, an edge lies on an edge of `x`, and keeps its support, exactly when
    // both its ends lie on that edge: known from where each vertex came from, not
    // measured (a crossing is on its edge only to the rounding of its coordinates, which
    // a test of 10⁻¹⁵ of the terms failed at coordinates near 90: a piece's edge then
    // ran from its own rounded vertices, a centre 0.001 pixel inside the whole's edge fell
    // outside the piece, and the frame lost a pixel in silence). The edges along the cut
    // have no support.
    let mut out = Vec::with_capacity(2);
    for (mut verts, mut on) in pieces {
        // A vertex equal to the one before it (a crossing that is a vertex) is dropped,
        // the edges it lies on kept with the other's. (Only equal ones: dropping one a
        // hair away changes the outline of a sliver a hair wide, which the fuzz target
        // `methods` found.)
        let mut j = 0;
        while verts.len() > 3 && j < verts.len() {
            let next = (j + 1) % verts.len();
            let (a, b) = (verts[j], verts[next]);
            if a.x == b.x && a.y == b.y {
                on[j] = both_edges(on[j], on[next]);
                verts.remove(next);
                on.remove(next);
                if next < j {
                    j -= 1;
                }
            } else {
                j += 1;
            }
        }
        if verts.len() < 3 || verts.len() > MAX_PIECE_VERTICES {
            return None;
        }
        let m = verts.len();
        let supports = (0..m)
            .map(|j| {
                let ((a0, a1), (b0, b1)) = (on[j], on[(j + 1) % m]);
                let common = [a0, a1].into_iter().find(|&e| e == b0 || e == b1);
                common.map(support)
            })
            .collect();
        let polygon = Polygon {
            colour: x.polygon.colour,
            vertices: verts,
            plane: Some(x.plane),
            supports,
            ..Polygon::default()
        };
        out.push(Item::new(x.index, polygon, x.plane));
    }
    let back = out.pop()?;
    let front = out.pop()?;
    Some((front, back))
}

/// The edges of a polygon a vertex lies on, as [`cut`] keeps them, for two equal
/// vertices merged into one: those of either (at most two distinct: a vertex lies on the
/// two edges that meet at it, a crossing on the one it cuts).
fn both_edges(a: (usize, usize), b: (usize, usize)) -> (usize, usize) {
    let extra = [b.0, b.1].into_iter().find(|&e| e != a.0 && e != a.1);
    match extra {
        Some(e) if a.0 == a.1 => (a.0, e),
        _ => a,
    }
}

/// Whether `v` lies on the line through `s0` and `s1` (in X, Y), to `tolerance` of the
/// terms: 10⁻⁹ to accept a crossing as on the edge it cuts. (Which edge of the whole a
/// piece's edge lies on is not measured so: a sliver's two long edges lie a hair apart,
/// and a loose test gave a piece's edge the other one's support, and a tight one none to
/// a crossing rounded off its edge; [`cut`] knows it from where each vertex came from.)
fn on_segment_line(v: Vertex, s0: Vertex, s1: Vertex, tolerance: f64) -> bool {
    let (a, b, p) = (
        s0.truncate().truncate(),
        s1.truncate().truncate(),
        v.truncate().truncate(),
    );
    let len = (b - a).length();
    orient(a, b, p).abs() <= tolerance * len * (len + (p - a).length()).max(1.0)
}

/// Puts `items[i]` into the sorted run of `list` (after the moved polygons at its head),
/// at its place by farthest depth (at an equal one, the later polygon first).
fn insert_sorted(items: &mut [Item], list: &mut VecDeque<usize>, i: usize) {
    items[i].sorted = true;
    let start = list.iter().take_while(|&&j| !items[j].sorted).count();
    let (z, index) = (items[i].z_max, items[i].index);
    let mut lo = start;
    let mut hi = list.len();
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        let m = &items[list[mid]];
        // Is m before i in the order (farther, or as far and later)?
        if m.z_max > z || (m.z_max == z && m.index >= index) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    list.insert(lo, i);
}

/// Depth sort as a [`HiddenSurface`].
#[derive(Debug, Default)]
pub struct Painter {
    split: bool,
    /// Cuts allowed per polygon of a frame, and in addition per frame.
    cuts_per_polygon: usize,
    cuts_base: usize,
    walker: SpanWalker,
    /// The colour-only frame, row-major (no depth buffer).
    frame: Vec<Option<Colour>>,
    /// The item painted last at each pixel, row-major, from the frame's first cut, tied
    /// pair ([`tied`]) or cycle painted out of order on (empty until then): kept only to
    /// mend the pixels beside the cut lines and where tied pairs meet, and to judge, at
    /// the end of the frame, whether the pixels such a cycle painted are wrong (never to
    /// decide the order of painting).
    owner: Vec<u32>,
    /// The pairs of whole polygons (indices in the frame) one of which was cut by the
    /// other's plane in this frame, each once.
    cut_pairs: Vec<(usize, usize)>,
    /// The pairs of whole polygons, overlapping on the screen, that the sort ordered by
    /// the tie rule ([`tied`]), each once: mended by the z-buffer's fold at the end.
    tie_pairs: Vec<(usize, usize)>,
    /// Per pixel, row-major, whether the mend has folded it ([`Painter::mend_pairs`]).
    folded: Vec<bool>,
    /// Per polygon of the frame, the row whose spans the mend found last, and those
    /// spans (`u32::MAX`: none yet).
    covered_rows: Vec<(u32, Vec<(u32, u32)>)>,
    /// The stream's lighting, for Phong shading.
    lighting: Option<Arc<Lighting>>,
    /// Frames resolved so far: the number of the next one (from 0, as the stream's
    /// positions and `zspec compare` count them).
    frames: u64,
    /// The line the last frame resolved has to say on stderr, if any.
    note: Option<String>,
    /// The last frame resolved's cycles painted out of order, and whether the pixels
    /// beside its cut lines were all checked, for [`Painter::note_record`].
    last: (u64, bool),
    pub stats: PainterStats,
}

/// The pixel tests spent judging whether the cycles painted out of order in a frame left
/// a pixel wrong, per pixel of the screen: past them, a cycle counts as wrong unjudged.
const JUDGED_PER_PIXEL: u64 = 64;

/// How far from a line of equal depth, in pixels, a pixel centre is checked by
/// [`Painter::mend_pairs`]: the pieces' vertices on a cut are snapped to 1/256 pixel
/// by the scan converter (docs/DESIGN.md, "Coverage"), moving the cut by at most 1/256.
const CUT_LINE_BAND: f64 = 1.0 / 32.0;

/// How far past the box of a polygon's vertices, in pixels, a centre it covers may lie:
/// the scan converter snaps each vertex to the nearest 1/256 pixel (docs/DESIGN.md,
/// "Coverage"), moving an edge by at most 1/512; the margin is four times that.
const SNAP_MARGIN: f64 = 1.0 / 128.0;

/// The default cut budget: `CUTS_PER_POLYGON·n + CUTS_BASE` cuts for a frame of n
/// polygons.
pub const CUTS_PER_POLYGON: usize = 1;
pub const CUTS_BASE: usize = 2048;

impl Painter {
    /// The classic method: cycles are painted in the order at hand.
    pub fn new() -> Self {
        Painter {
            cuts_per_polygon: CUTS_PER_POLYGON,
            cuts_base: CUTS_BASE,
            ..Painter::default()
        }
    }

    /// With the splitting step: a cycle is broken by cutting a polygon by another's plane.
    pub fn with_split() -> Self {
        Painter {
            split: true,
            ..Painter::new()
        }
    }

    /// With the splitting step and a cut budget of `per_polygon·n + base` a frame.
    pub fn with_split_budget(per_polygon: usize, base: usize) -> Self {
        Painter {
            split: true,
            cuts_per_polygon: per_polygon,
            cuts_base: base,
            ..Painter::default()
        }
    }

    /// The cut budget of a frame of `n` polygons.
    pub fn cut_budget(&self, n: usize) -> usize {
        self.cuts_per_polygon
            .saturating_mul(n)
            .saturating_add(self.cuts_base)
    }

    /// The line the frame just resolved has for stderr (`painter: ` is the caller's), taken
    /// once: None when every cycle of the frame was ordered, cut, or left no pixel wrong.
    ///
    /// * Without the splitting step: `frame N: K cycles painted out of order; --split cuts
    ///   them`.
    /// * With it, only where what was drawn may be wrong: `frame N: could not order every
    ///   polygon: K cycles painted out of order, ` and why: the frame's cut budget was
    ///   spent, or no cut by either plane has two pieces (a polygon not planar enough to
    ///   cut, or a piece that would pass [`MAX_PIECE_VERTICES`]).
    ///
    /// N counts frames from 0, as the stream's positions and `zspec compare` do.
    pub fn take_note(&mut self) -> Option<String> {
        self.note.take()
    }

    /// The note of the frame last resolved as a `--stats` record (`stagecli::stats`),
    /// printed after the note's line: `frame` (from 0), `out_of_order` (its cycles painted
    /// out of order) and `unchecked` (1 where the pixels beside its cut lines were not all
    /// checked, else 0).
    pub fn note_record(&self) -> stagecli::stats::Record {
        stagecli::stats::Record::new("painter")
            .with("frame", self.frames.saturating_sub(1))
            .with("out_of_order", self.last.0)
            .with("unchecked", u8::from(!self.last.1))
    }

    /// The note of frame `frame`, which painted `given_up` cycles out of order and spent
    /// its budget of `budget` cuts or not.
    fn note_of(&self, frame: u64, given_up: u64, spent: bool, budget: usize) -> Option<String> {
        if given_up == 0 {
            return None;
        }
        Some(if !self.split {
            format!("frame {frame}: {given_up} cycles painted out of order; --split cuts them")
        } else if spent {
            format!(
                "frame {frame}: could not order every polygon: {given_up} cycles painted out \
                 of order, the cut budget spent ({budget} cuts: {} a polygon + {})",
                self.cuts_per_polygon, self.cuts_base
            )
        } else {
            format!(
                "frame {frame}: could not order every polygon: {given_up} cycles painted out \
                 of order, no cut by either plane has two pieces"
            )
        })
    }

    /// Whether the cycle painted out of order whose P is `items[p]` left a pixel wrong:
    /// a pixel P covers (by the sampling rule, as it was painted) that is held at the end
    /// of the frame by a polygon not in front of P there (on the polygons' depth planes
    /// as the z-buffer takes them, [`scan::DepthPlane`], by the tie rule). Such a polygon
    /// was painted after P where P should hide it: the frame shows it where the z-buffer
    /// shows P or something nearer. Each pixel judged costs one from `budget`; when it
    /// runs out the cycle counts as wrong (what was drawn may be wrong, unjudged).
    #[allow(clippy::too_many_arguments)]
    fn left_a_pixel_wrong(
        &mut self,
        polygons: &[Polygon],
        items: &[Item],
        p: usize,
        planes: &mut [Option<DepthPlane>],
        width: u32,
        height: u32,
        budget: &mut u64,
    ) -> bool {
        let pi = &items[p];
        let owner = &self.owner;
        let mut plane = |i: usize| *planes[i].get_or_insert_with(|| DepthPlane::of(&polygons[i]));
        let p_plane = plane(pi.index);
        let mut wrong = false;
        self.walker.for_each_span(&pi.polygon, width, height, |s| {
            if wrong {
                return;
            }
            let (z_row, dz) = p_plane.row(s.y);
            let row = s.y as usize * width as usize;
            for x in s.x0..s.x1 {
                if *budget == 0 {
                    wrong = true;
                    return;
                }
                *budget -= 1;
                let o = owner[row + x as usize] as usize;
                let oi = &items[o];
                if o == p || oi.index == pi.index {
                    continue;
                }
                let z_p = depth_at(z_row, dz, x);
                let (o_row, o_dz) = plane(oi.index).row(s.y);
                let z_o = depth_at(o_row, o_dz, x);
                let o_in_front = if oi.index < pi.index {
                    !takes(z_p, z_o)
                } else {
                    takes(z_o, z_p)
                };
                if !o_in_front {
                    wrong = true;
                    return;
                }
            }
        });
        wrong
    }

    /// Mends the pixels beside the frame's cut lines, and those of the pairs the sort
    /// ordered by the tie rule ([`tied`]).
    ///
    /// A cut's pieces cover exactly the whole's pixels, but their vertices on the cut
    /// line are snapped to 1/256 pixel as every vertex is, so a pixel centre within 1/256
    /// pixel of the line where two planes have equal depth may fall in the piece that is
    /// behind there, while the z-buffer compares the two depths at the centre. For each
    /// pair of polygons one of which was cut by the other's plane, every centre within
    /// [`CUT_LINE_BAND`] pixel of their line of equal depth that is held by one of the two
    /// while the other covers it (by the sampling rule) and is in front there (on the
    /// z-buffer's depth planes, by the tie rule) is repainted in what the z-buffer shows.
    ///
    /// A tied pair's pixels are ordered right pair by pair, but the tie rule is not
    /// transitive, so every centre where the two come within the tie rule's width of
    /// each other and one of them holds it is repainted in what the z-buffer shows there,
    /// whichever of the two is in front.
    ///
    /// Only the rows and columns of the two polygons' screen boxes are looked at (both
    /// boxes for a tied pair, either for a cut pair), at most [`JUDGED_PER_PIXEL`] centres
    /// a pixel of the screen; false when that ran out before every pair was checked.
    fn mend_pairs(
        &mut self,
        polygons: &[Polygon],
        items: &[Item],
        planes: &mut [Option<DepthPlane>],
        width: u32,
        height: u32,
    ) -> bool {
        // An item of each whole polygon, to hold a repainted pixel.
        let mut item_of = vec![u32::MAX; polygons.len()];
        for (k, it) in items.iter().enumerate() {
            item_of[it.index] = k as u32;
        }
        // Each polygon's box on the screen, for the fold of a pixel to be repainted,
        // widened by [`SNAP_MARGIN`]: the scan converter snaps vertices to 1/256 pixel, so
        // a centre a hair outside the box of the vertices may be covered.
        let boxes: Vec<[f64; 4]> = polygons
            .iter()
            .map(|p| {
                let [x0, y0, x1, y1] = p.vertices.iter().fold(
                    [
                        f64::INFINITY,
                        f64::INFINITY,
                        f64::NEG_INFINITY,
                        f64::NEG_INFINITY,
                    ],
                    |[x0, y0, x1, y1], v| [x0.min(v.x), y0.min(v.y), x1.max(v.x), y1.max(v.y)],
                );
                let m = SNAP_MARGIN;
                [x0 - m, y0 - m, x1 + m, y1 + m]
            })
            .collect();
        self.folded.clear();
        self.folded.resize(width as usize * height as usize, false);
        for (row, _) in &mut self.covered_rows {
            *row = u32::MAX;
        }
        self.covered_rows
            .resize_with(polygons.len(), || (u32::MAX, Vec::new()));
        let mut budget = JUDGED_PER_PIXEL * width as u64 * height as u64;
        // Each pair once: tied (false < true, so a pair both cut and tied is mended as
        // tied, the stronger).
        let mut pairs: Vec<((usize, usize), bool)> = self
            .cut_pairs
            .iter()
            .map(|&pair| (pair, false))
            .chain(self.tie_pairs.iter().map(|&pair| (pair, true)))
            .collect();
        pairs.sort_unstable();
        pairs.reverse();
        pairs.dedup_by_key(|(pair, _)| *pair);
        // The centres (c + ½, r + ½) within both boxes.
        let within = |lo: f64, hi: f64, n: u32| {
            let (a, b) = ((lo - 0.5).ceil(), (hi - 0.5).floor());
            if a.is_nan() || b.is_nan() || a > b || b < 0.0 || a >= n as f64 {
                0..0
            } else {
                a.max(0.0) as u32..(b.min(n as f64 - 1.0) as u32) + 1
            }
        };
        let mut near = Vec::new();
        let mut complete = true;
        'pairs: for &((x, b), tied) in &pairs {
            let px = *planes[x].get_or_insert_with(|| DepthPlane::of(&polygons[x]));
            let pb = *planes[b].get_or_insert_with(|| DepthPlane::of(&polygons[b]));
            // The difference of the depths, A + c·D along row r; its step down a row.
            let diff = |r: u32| {
                let ((zx, dx), (zb, db)) = (px.row(r), pb.row(r));
                (
                    zx - zb,
                    dx - db,
                    zx.abs() + zb.abs() + (dx.abs() + db.abs()) * width as f64,
                )
            };
            let (a0, d, _) = diff(0);
            let step = diff(1).0 - a0;
            let band = CUT_LINE_BAND * d.hypot(step);
            // A tied pair's centres are those both cover, in both boxes; a cut pair's
            // pieces may have lost a centre of the one cut where the other's plane
            // crosses it, outside the other's box: in either box.
            let (bx, bb) = (boxes[x], boxes[b]);
            let span = |lo: f64, hi: f64, lo2: f64, hi2: f64, n: u32| {
                if tied {
                    within(lo.max(lo2), hi.min(hi2), n)
                } else {
                    within(lo.min(lo2), hi.max(hi2), n)
                }
            };
            let rows = span(bx[1], bx[3], bb[1], bb[3], height);
            let columns = span(bx[0], bx[2], bb[0], bb[2], width);
            // The polygons whose boxes meet those rows and columns: the only ones a fold
            // here can meet, in stream order.
            let (x0, x1) = (columns.start as f64 + 0.5, columns.end as f64 - 0.5);
            let (y0, y1) = (rows.start as f64 + 0.5, rows.end as f64 - 0.5);
            near.clear();
            near.extend((0..boxes.len()).filter(|&i| {
                !(x1 < boxes[i][0] || x0 > boxes[i][2] || y1 < boxes[i][1] || y0 > boxes[i][3])
            }));
            for r in rows {
                let (a, d, size) = diff(r);
                // Within the band, or within the tie rule's width of equal depth.
                let tol = band + 4.0 * proto::depth::TIE * size;
                let cols = if d != 0.0 {
                    let (u, v) = ((-a - tol) / d, (-a + tol) / d);
                    let (lo, hi) = (u.min(v).floor().max(0.0), u.max(v).ceil());
                    if lo.is_nan() || hi.is_nan() || lo > hi || hi < 0.0 || lo >= width as f64 {
                        continue;
                    }
                    lo as u32..(hi as u32).saturating_add(1).min(width)
                } else if a.abs() <= tol {
                    0..width
                } else {
                    continue;
                };
                let cols = cols.start.max(columns.start)..cols.end.min(columns.end);
                if budget < cols.len() as u64 {
                    complete = false;
                    break 'pairs;
                }
                budget -= cols.len() as u64;
                for c in cols {
                    self.mend_pixel(
                        polygons,
                        items,
                        &item_of,
                        &boxes,
                        &near,
                        planes,
                        (x, b, tied),
                        c,
                        r,
                        width,
                    );
                }
            }
        }
        complete
    }

    /// [`Painter::mend_pairs`] at pixel (c, r), for the wholes `x` and `b`. For a cut
    /// pair: where either of the two covers the centre and the one in front there does
    /// not hold it (the other does, or a third polygon painted over a piece that lost the
    /// centre, or none), or where its holder's whole does not cover it (a piece's
    /// sliver); for a `tied` pair, wherever one of the two holds it. The pixel is then
    /// repainted in what the z-buffer shows there, or left to the background where no
    /// polygon covers its centre: the fold, in stream order by the tie rule, of every polygon
    /// covering its centre (`boxes` the polygons' screen boxes, `near` those of them that
    /// meet the pair's, in stream order, `planes` their depth planes, made as they are
    /// asked for), not the pair's front alone, which a polygon coplanar with it and
    /// earlier in the stream takes the pixel from (seed 200236 of the differential suite:
    /// three copies of one quad).
    #[allow(clippy::too_many_arguments)]
    fn mend_pixel(
        &mut self,
        polygons: &[Polygon],
        items: &[Item],
        item_of: &[u32],
        boxes: &[[f64; 4]],
        near: &[usize],
        planes: &mut [Option<DepthPlane>],
        (x, b, tied): (usize, usize, bool),
        c: u32,
        r: u32,
        width: u32,
    ) {
        let at = r as usize * width as usize + c as usize;
        let held = match self.owner[at] {
            u32::MAX => None,
            o => Some(items[o as usize].index),
        };
        // A tied pair is mended where one of the two holds the pixel. A cut pair also
        // where a third polygon holds it: a piece that lost a centre beside the cut line
        // (its vertices snapped) leaves the centre to the piece painted before, and
        // whatever was painted over that piece there (seed 60161: the cut one's back
        // piece, then a polygon coplanar with the cutter, behind the cut one there).
        if tied && held.is_none_or(|h| h != x && h != b) {
            return;
        }
        let mut depth = |i: usize| {
            planes[i]
                .get_or_insert_with(|| DepthPlane::of(&polygons[i]))
                .at(c, r)
        };
        // Coverage by the sampling rule, each polygon's spans on row r found once.
        let (walker, rows) = (&mut self.walker, &mut self.covered_rows);
        let mut covers = |i: usize| {
            let (row, spans) = &mut rows[i];
            if *row != r {
                spans.clear();
                walker.for_each_span_in(&polygons[i], width, r..r + 1, |s| {
                    spans.push((s.x0, s.x1));
                });
                *row = r;
            }
            spans.iter().any(|&(x0, x1)| x0 <= c && c < x1)
        };
        if !tied {
            let (zx, zb) = (depth(x), depth(b));
            // x < b: the earlier, x, keeps a tie.
            let (front, back) = if takes(zb, zx) { (b, x) } else { (x, b) };
            // A piece may hold a centre its whole does not cover: the two pieces of a
            // self-intersecting polygon run along the cut line both ways, between the
            // crossings of its edges, and with their ends snapped the two edges part by a
            // hair, a sliver that covers a centre on the line (seed 131370).
            let stray = held.is_some_and(|h| !covers(h));
            if held == Some(front) && !stray {
                return;
            }
            // Either of the two may have lost the centre to a piece's snapped corner, the
            // one behind too: it is cut along the whole line where the planes meet, the
            // one in front there may not reach the centre, and a third polygon, behind
            // the lost one, may hold it (seed 141913).
            if !(stray || covers(front) || covers(back)) {
                return;
            }
        }
        // The z-buffer's fold at the centre, over every polygon covering it: what the
        // pixel shows, found once (a centre many pairs meet at is folded by the first).
        if std::mem::replace(&mut self.folded[at], true) {
            return;
        }
        let (cx, cy) = (c as f64 + 0.5, r as f64 + 0.5);
        let mut winner: Option<(usize, scan::Depth)> = None;
        for &i in near {
            let bx = &boxes[i];
            if cx < bx[0] || cx > bx[2] || cy < bx[1] || cy > bx[3] {
                continue;
            }
            let z = depth(i);
            // One that would not take the pixel from the fold so far changes nothing,
            // covering or not: its coverage is asked only when it would.
            if winner.is_none_or(|(_, w)| takes(z, w)) && covers(i) {
                winner = Some((i, z));
            }
        }
        let Some((to, _)) = winner else {
            // No polygon covers the centre: the z-buffer shows the background there.
            if held.is_some() {
                self.frame[at] = None;
                self.owner[at] = u32::MAX;
                self.stats.mended += 1;
            }
            return;
        };
        if held == Some(to) || item_of[to] == u32::MAX {
            return;
        }
        let shading = Shading::of(&polygons[to], self.lighting.as_ref());
        let pixel = &mut self.frame[at];
        match shading {
            None => *pixel = Some(polygons[to].colour),
            Some(sh) => shaded_runs(&sh, r, c..c + 1, |_, _, colour| *pixel = Some(colour)),
        }
        self.owner[at] = item_of[to];
        self.stats.mended += 1;
    }

    /// The frame's items, sorted farthest first (at an equal farthest depth, the later
    /// polygon first, so that the earlier ends in front).
    fn items(polygons: &[Polygon]) -> Vec<Item> {
        let mut items: Vec<Item> = polygons
            .iter()
            .enumerate()
            .filter(|(_, p)| {
                // A polygon whose vertices all lie on one line in the screen covers no
                // pixel centre: it is neither sorted nor painted (nor cut by, its plane
                // being no plane).
                let xy: Vec<DVec2> = p.vertices.iter().map(|v| v.truncate().truncate()).collect();
                let turns = xy.first().is_some_and(|&a| {
                    xy.iter()
                        .find(|&&b| b != a)
                        .is_some_and(|&b| xy.iter().any(|&c| orient(a, b, c) != 0.0))
                });
                p.vertices.len() >= 3 && p.vertices.iter().all(|v| v.is_finite()) && turns
            })
            .map(|(index, p)| Item::new(index, p.clone(), depth_plane(p)))
            .collect();
        items.sort_by(|a, b| b.z_max.total_cmp(&a.z_max).then(b.index.cmp(&a.index)));
        items
    }

    /// Breaks the cycle met at the head `list[0]` (P) against the marked `list[k]` (Q):
    /// Q cut by P's plane, or P by Q's; failing those (each lies wholly on one side of the
    /// other's plane: the cycle runs through other polygons), a marked polygon of the list
    /// cut by P's or Q's plane, or P by its. The pieces go to the head of the list,
    /// unmarked. False when no cut has two pieces.
    fn split_cycle(
        &mut self,
        items: &mut Vec<Item>,
        list: &mut VecDeque<usize>,
        k: usize,
        generation: u64,
    ) -> bool {
        let mut tries = vec![(0, k), (k, 0)];
        let marked: Vec<usize> = (1..list.len())
            .filter(|&m| m != k && items[list[m]].moved == generation)
            .take(64)
            .collect();
        for &m in &marked {
            tries.extend([(m, 0), (m, k), (0, m), (k, m)]);
        }
        for (x, by) in tries {
            let (xi, bi) = (list[x], list[by]);
            if !items[xi].cuttable || !items[bi].cuttable || !items[xi].straddles(&items[bi]) {
                continue;
            }
            let Some((front, back)) = cut(&items[xi], &items[bi]) else {
                continue;
            };
            let pair = (items[xi].index, items[bi].index);
            let pair = (pair.0.min(pair.1), pair.0.max(pair.1));
            if !self.cut_pairs.contains(&pair) {
                self.cut_pairs.push(pair);
            }
            list.remove(x);
            // The pieces re-enter the sort, each at its farthest depth.
            for piece in [front, back] {
                items.push(piece);
                let i = items.len() - 1;
                insert_sorted(items, list, i);
            }
            self.stats.splits += 1;
            return true;
        }
        false
    }

    /// Records the whole polygons `a` and `b` as a pair the sort ordered by the tie rule,
    /// to be mended at the end of the frame ([`Painter::mend_pairs`]); from now on the
    /// items painted are recorded at their pixels (neither of the two is painted yet).
    fn note_tie(&mut self, a: usize, b: usize, width: u32, height: u32) {
        let pair = (a.min(b), a.max(b));
        if self.tie_pairs.last() != Some(&pair) {
            self.tie_pairs.push(pair);
        }
        if self.owner.is_empty() {
            self.owner
                .resize(width as usize * height as usize, u32::MAX);
        }
    }

    /// Records item `item` as the last painted on `polygon`'s pixels.
    fn claim(&mut self, item: usize, width: u32, height: u32, polygon: &Polygon) {
        let owner = &mut self.owner;
        self.walker.for_each_span(polygon, width, height, |s| {
            let row = s.y as usize * width as usize;
            owner[row + s.x0 as usize..row + s.x1 as usize].fill(item as u32);
        });
    }

    /// Paints `polygon` (a polygon of the frame, or a piece cut from one) over what is
    /// there: in its colour, or, where `shading` is the whole polygon's Gouraud shading,
    /// each pixel in the whole's colour at its centre, so that a piece is shaded as the
    /// whole would be.
    fn paint(&mut self, polygon: &Polygon, shading: Option<&Shading>, width: u32, height: u32) {
        let frame = &mut self.frame;
        match shading {
            None => {
                let colour = Some(polygon.colour);
                self.walker.for_each_span(polygon, width, height, |s| {
                    let row = s.y as usize * width as usize;
                    frame[row + s.x0 as usize..row + s.x1 as usize].fill(colour);
                });
            }
            Some(shading) => {
                self.walker.for_each_span(polygon, width, height, |s| {
                    let row = s.y as usize * width as usize;
                    shaded_runs(shading, s.y, s.x0..s.x1, |x0, x1, c| {
                        frame[row + x0 as usize..row + x1 as usize].fill(Some(c));
                    });
                });
            }
        }
        self.stats.painted += 1;
    }
}

impl HiddenSurface for Painter {
    fn resolve(&mut self, polygons: &[Polygon], width: u32, height: u32, runs: &mut Vec<Run>) {
        self.frame.clear();
        self.frame.resize(width as usize * height as usize, None);
        // Kept from the first cycle painted out of order on (the pixels judged are all
        // painted from then on); a frame without one allocates nothing.
        self.owner.clear();
        self.cut_pairs.clear();
        self.tie_pairs.clear();
        let mut items = Self::items(polygons);
        self.stats.polygons += items.len() as u64;
        let budget = self.cut_budget(items.len());
        let mut list: VecDeque<usize> = (0..items.len()).collect();
        let mut cuts = 0usize;
        let mut spent = false;
        // Marks are of this generation; 0 is no mark.
        let mut generation = 1u64;
        // Moves since the last paint, and the moves of marked polygons the frame has left
        // (each costs a search of the list: bounded as the cuts are).
        let mut moves = 0usize;
        let mut moves_left = budget.saturating_mul(8);
        // Cycles painted out of order in this frame.
        // Each cycle painted out of order: the P painted, and the Q's painted after it
        // that it may hide part of.
        let mut out_of_order: Vec<usize> = Vec::new();
        'list: while let Some(&p) = list.front() {
            // Find a Q that P might hide part of.
            let mut obstructing = None;
            for (k, &q) in list.iter().enumerate().skip(1) {
                let (pi, qi) = (&items[p], &items[q]);
                if qi.sorted && proto::depth::takes(qi.z_max, pi.z_min) {
                    // This and every later sorted one are wholly nearer than P reaches,
                    // by more than the tie rule's width, whichever comes first.
                    break;
                }
                match first_passing_test(pi, qi) {
                    Some(t) => {
                        self.stats.resolved_by[t] += 1;
                        if pi.index != qi.index && tied(pi, qi, t) {
                            self.note_tie(pi.index, qi.index, width, height);
                        }
                    }
                    None => {
                        self.stats.unresolved += 1;
                        obstructing = Some(k);
                        break;
                    }
                }
            }
            if let Some(k) = obstructing {
                let q = list[k];
                let (pi, qi) = (&items[p], &items[q]);
                // The tests the other way round (3' and 4'): may Q be painted before P?
                let q_first = qi.wholly(pi, Depthwise::Behind, qi.index > pi.index)
                    || pi.wholly(qi, Depthwise::Front, pi.index < qi.index);
                // Q first by the coplanar tie (tests 3' and 4', [`tied`]'s).
                if q_first && qi.index != pi.index && (tied(qi, pi, 2) || tied(qi, pi, 3)) {
                    self.note_tie(qi.index, pi.index, width, height);
                }
                if items[q].moved != generation && (q_first || !self.split) {
                    // Q goes before P, marked.
                    items[q].moved = generation;
                    moves += 1;
                    items[q].sorted = false;
                    list.remove(k);
                    list.push_front(q);
                    self.stats.swaps += 1;
                    continue 'list;
                }
                // Q has moved before (a cycle), or neither may go first: they pass
                // through each other.
                self.stats.cycles += 1;
                if q_first && moves < list.len() + 16 && moves_left > 0 {
                    // A mark can outlive its reason (thin pieces whose tests fail for
                    // one pair and pass for the next): while the tests say Q may go
                    // first, it goes, a bounded number of times before a paint and in the
                    // frame (eight times the cut budget).
                    list.remove(k);
                    list.push_front(q);
                    moves += 1;
                    moves_left -= 1;
                    self.stats.swaps += 1;
                    continue 'list;
                }
                if self.split {
                    if cuts < budget {
                        if self.split_cycle(&mut items, &mut list, k, generation) {
                            cuts += 1;
                            if self.owner.is_empty() {
                                self.owner
                                    .resize(width as usize * height as usize, u32::MAX);
                            }
                            continue 'list;
                        }
                    } else {
                        spent = true;
                    }
                }
                // P is painted now, before Q and any other it may hide part of: the
                // picture may be wrong only where P shares a pixel centre with one of them.
                out_of_order.push(p);
                if self.owner.is_empty() {
                    self.owner
                        .resize(width as usize * height as usize, u32::MAX);
                }
            }
            // Paint P over what is there.
            list.pop_front();
            // A piece is shaded by the whole polygon it was cut from.
            let shading = Shading::of(&polygons[items[p].index], self.lighting.as_ref());
            self.paint(&items[p].polygon, shading.as_ref(), width, height);
            if !self.owner.is_empty() {
                self.claim(p, width, height, &items[p].polygon);
            }
            generation += 1;
            moves = 0;
        }
        self.stats.budget_spent += spent as u64;
        let mut planes: Vec<Option<DepthPlane>> = Vec::new();
        if !self.owner.is_empty() {
            planes.resize(polygons.len(), None);
        }
        let mut checked = true;
        if !self.cut_pairs.is_empty() || !self.tie_pairs.is_empty() {
            checked = self.mend_pairs(polygons, &items, &mut planes, width, height);
            self.stats.unchecked += !checked as u64;
        }
        // A cycle painted out of order is a failure where it left a pixel wrong: judged
        // on P's pixels against the polygon painted last there, up to JUDGED_PER_PIXEL
        // pixel tests a pixel of the screen in the frame.
        let mut given_up = 0u64;
        if !out_of_order.is_empty() {
            let mut budget = JUDGED_PER_PIXEL * width as u64 * height as u64;
            for &p in &out_of_order {
                if self.left_a_pixel_wrong(
                    polygons,
                    &items,
                    p,
                    &mut planes,
                    width,
                    height,
                    &mut budget,
                ) {
                    given_up += 1;
                } else {
                    self.stats.apart += 1;
                }
            }
        }
        self.stats.given_up += given_up;
        self.note = self.note_of(self.frames, given_up, spent, budget);
        self.last = (given_up, checked);
        if !checked {
            let line = format!(
                "frame {}: the pixels beside the cut lines and where polygons tie were not all \
                 checked: the picture may be wrong there",
                self.frames
            );
            self.note = Some(match self.note.take() {
                Some(n) => format!("{n}; {}", &line[line.find(": ").unwrap_or(0) + 2..]),
                None => line,
            });
        }
        self.frames += 1;
        for (y, row) in self.frame.chunks_exact(width.max(1) as usize).enumerate() {
            push_row_runs(y as u32, row, runs);
        }
    }

    /// A Gouraud- or Phong-shaded polygon is painted in its colour at each pixel centre
    /// (its pieces in the whole's), as the z-buffer draws it, lit by the stream's lighting.
    fn lighting(&mut self) -> Option<&mut Option<Arc<Lighting>>> {
        Some(&mut self.lighting)
    }

    fn stats(&self) -> String {
        let s = &self.stats;
        let tests: Vec<String> = TESTS
            .iter()
            .zip(s.resolved_by)
            .enumerate()
            .map(|(i, (name, n))| format!("test {} ({name}) {n}", i + 1))
            .collect();
        format!(
            "{} polygons sorted, {} painted, pairs resolved by {}, {} unresolved, {} swaps, {} cycles, {} splits, {} cycles painted out of order, {} out of order that left no pixel wrong, {} pixels mended",
            s.polygons,
            s.painted,
            tests.join(", "),
            s.unresolved,
            s.swaps,
            s.cycles,
            s.splits,
            s.given_up,
            s.apart,
            s.mended
        )
    }

    fn counters(&self) -> Vec<(&'static str, String)> {
        let s = &self.stats;
        let resolved_by: Vec<String> = s.resolved_by.iter().map(u64::to_string).collect();
        vec![
            ("polygons_sorted", s.polygons.to_string()),
            ("painted", s.painted.to_string()),
            ("resolved_by_test", resolved_by.join(",")),
            ("unresolved", s.unresolved.to_string()),
            ("swaps", s.swaps.to_string()),
            ("cycles", s.cycles.to_string()),
            ("splits", s.splits.to_string()),
            ("out_of_order", s.given_up.to_string()),
            ("out_of_order_harmless", s.apart.to_string()),
            ("pixels_mended", s.mended.to_string()),
        ]
    }
}

#[cfg(test)]
mod tests;
