//! # painter: depth sort, drawn back to front (Newell, Newell and Sancha)
//!
//! The depth-priority method of the survey the thesis cites for its cost figures
//! ([SuSp74], thesis chapter 5.1 [references.md]): sort the frame's polygons by their
//! farthest depth, then paint them from the back to the front into a frame of colours
//! alone: no depth buffer, a nearer polygon simply paints over a farther one. Sorting by
//! one number per polygon is not enough where depth extents overlap, so before the
//! polygon P at the head of the list is painted it is checked against every polygon Q
//! whose depth extent overlaps its own, by the tests of Newell, Newell and Sancha, the
//! cheapest first; any one that succeeds shows that P does not hide any part of Q:
//!
//! 1. the depth extents do not overlap (P is wholly farther than Q);
//! 2. the screen bounding boxes do not overlap;
//! 3. P lies wholly behind Q's plane;
//! 4. Q lies wholly in front of P's plane;
//! 5. the projections do not overlap.
//!
//! When all five fail, Q is moved to the head of the list (it is painted before P) and
//! marked. A marked polygon that would have to move again shows a *cycle*: polygons that
//! overlap cyclically, or that pass through each other (the thesis's own test scene,
//! `examples/penetrating.txt`). The classic method then has no order to paint in; here it
//! gives up and paints in the order it has (the failure is kept and counted, in
//! [`PainterStats::cycles`]), or, with the splitting step ([`Painter::with_split`]), cuts one
//! polygon by the other's plane and sorts the pieces on.
//!
//! ## On the sampling grid
//!
//! Every test is decided on the pixels the polygons cover, as [`scan::SpanWalker`] samples
//! them (pixel centres, top-left rule; docs/DESIGN.md, "Coverage"), with the fixed-point
//! depths every method uses ([`scan::DepthPlane`]): the depth extent is that of the
//! covered pixels; the bounding box is that of the covered pixels; "wholly behind Q's
//! plane" means that at every pixel P covers, Q's plane (stepped as the z-buffer steps it)
//! is nearer, or as near with Q earlier in the stream; test 5 intersects the covered
//! spans. The survey's tests run on the vertices and the continuous projections; on the
//! grid they decide exactly what the z-buffer decides, so that a scene that has a depth
//! order is painted pixel for pixel as the z-buffer draws it, ties included (at equal
//! depth the polygon earlier in the stream ends in front). The cut of the splitting step
//! is made on the grid too: Q's pixels are parted by which side of P's plane they are on
//! by those same depths, so that its pieces are exactly the parts the z-buffer would show
//! and hide.
//!
//! The sorted list is a sorted run with the moved polygons (and pieces) in front of it, so
//! the search for the Q's that overlap P in depth stops at the first unmoved polygon
//! wholly farther than P: every one after it is farther still.

use proto::{Colour, Polygon};
use scan::frame::{push_row_runs, HiddenSurface};
use scan::{depth_at, DepthPlane, Run, Span, SpanWalker};
use std::collections::VecDeque;

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
    /// Polygons that cover a pixel, sorted and painted (pieces of a cut polygon count
    /// once, as the polygon).
    pub polygons: u64,
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
    /// Cycles painted in the order at hand (no split possible, or none asked for): the
    /// method's failure.
    pub given_up: u64,
}

/// A polygon of the list: the pixels it covers, as spans in row order, and what the tests
/// ask about them.
#[derive(Clone, Debug)]
struct Item {
    /// Its place in the stream: at equal depth the earlier wins.
    index: usize,
    colour: Colour,
    plane: DepthPlane,
    spans: Vec<Span>,
    /// Inclusive pixel bounds: columns, rows.
    x_min: u32,
    x_max: u32,
    y_min: u32,
    y_max: u32,
    /// Depth extent of the covered pixels (fixed point; smaller is nearer).
    z_min: scan::Depth,
    z_max: scan::Depth,
    /// Moved to the head once (the survey's mark).
    moved: bool,
    /// Still in the sorted run of the list (not moved, not a piece).
    sorted: bool,
}

impl Item {
    /// An item of `spans` (non-empty, in row order).
    fn new(index: usize, colour: Colour, plane: DepthPlane, spans: Vec<Span>) -> Item {
        let mut item = Item {
            index,
            colour,
            plane,
            spans,
            x_min: u32::MAX,
            x_max: 0,
            y_min: u32::MAX,
            y_max: 0,
            z_min: f64::INFINITY,
            z_max: f64::NEG_INFINITY,
            moved: false,
            sorted: true,
        };
        for s in &item.spans {
            item.x_min = item.x_min.min(s.x0);
            item.x_max = item.x_max.max(s.x1 - 1);
            item.y_min = item.y_min.min(s.y);
            item.y_max = item.y_max.max(s.y);
            // Depth is linear along a span: its ends are its extremes.
            for z in [s.depth(s.x0), s.depth(s.x1 - 1)] {
                item.z_min = item.z_min.min(z);
                item.z_max = item.z_max.max(z);
            }
        }
        item
    }
}

/// Does `a` (depth `za`, stream place `ia`) win a pixel over `b` (depth `zb`, place `ib`),
/// as the z-buffer decides it, by the tie rule for two polygons. Pieces of one polygon
/// (equal places) never share a pixel; either answer is right for them.
#[inline]
fn wins(za: scan::Depth, ia: usize, zb: scan::Depth, ib: usize) -> bool {
    if ia > ib {
        scan::takes(za, zb)
    } else {
        proto::depth::takes_back(za, zb)
    }
}

/// At every pixel `a` covers, does `a` win (`front`) or lose (`!front`) against `b`'s
/// plane? The difference of two planes is linear along a span, so its ends decide.
fn wholly_on_side(a: &Item, b: &Item, front: bool) -> bool {
    a.spans.iter().all(|s| {
        let (zb_row, dzb) = b.plane.row(s.y);
        [s.x0, s.x1 - 1].into_iter().all(|x| {
            let w = wins(s.depth(x), a.index, depth_at(zb_row, dzb, x), b.index);
            w == front
        })
    })
}

/// Do two sets of spans (each in row order, disjoint within a row) share a pixel?
fn spans_overlap(a: &[Span], b: &[Span]) -> bool {
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        let (s, t) = (&a[i], &b[j]);
        if s.y < t.y {
            i += 1;
        } else if t.y < s.y {
            j += 1;
        } else if s.x1 <= t.x0 {
            i += 1;
        } else if t.x1 <= s.x0 {
            j += 1;
        } else {
            return true;
        }
    }
    false
}

/// The first of the five tests that shows P may be painted before Q (P hides no part of
/// Q), numbered from 0; `None` when all fail.
fn first_passing_test(p: &Item, q: &Item) -> Option<usize> {
    // 1. Depth extents: every pixel of P at least as far as every pixel of Q (and P
    //    later, if they can meet at one depth).
    if p.z_min > q.z_max || (p.z_min == q.z_max && p.index >= q.index) {
        return Some(0);
    }
    // 2. Screen bounding boxes of the covered pixels.
    if p.x_max < q.x_min || q.x_max < p.x_min || p.y_max < q.y_min || q.y_max < p.y_min {
        return Some(1);
    }
    // 3. P wholly behind Q's plane: Q's plane wins at every pixel of P.
    if wholly_on_side(p, q, false) {
        return Some(2);
    }
    // 4. Q wholly in front of P's plane: Q wins against P's plane at every pixel of Q.
    if wholly_on_side(q, p, true) {
        return Some(3);
    }
    // 5. The projections (covered pixel sets) are disjoint.
    if !spans_overlap(&p.spans, &q.spans) {
        return Some(4);
    }
    None
}

/// The splitting step on the grid: `x`'s pixels parted by `by`'s plane into those where
/// `x` wins (in front of the plane) and those where it loses. `None` unless both parts
/// have pixels.
fn cut(x: &Item, by: &Item) -> Option<(Item, Item)> {
    let (mut front, mut back) = (Vec::new(), Vec::new());
    for s in &x.spans {
        let (zb_row, dzb) = by.plane.row(s.y);
        let wins_at = |c: u32| wins(s.depth(c), x.index, depth_at(zb_row, dzb, c), by.index);
        let (first, last) = (wins_at(s.x0), wins_at(s.x1 - 1));
        if first == last {
            if first { &mut front } else { &mut back }.push(*s);
            continue;
        }
        // The sides along a span are two runs (the depth difference is linear): find the
        // first column on the last column's side.
        let (mut lo, mut hi) = (s.x0, s.x1 - 1); // wins_at(lo) == first, wins_at(hi) == last
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            if wins_at(mid) == first {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let (head, tail) = (Span { x1: hi, ..*s }, Span { x0: hi, ..*s });
        let (f, b) = if first { (head, tail) } else { (tail, head) };
        front.push(f);
        back.push(b);
    }
    if front.is_empty() || back.is_empty() {
        return None;
    }
    let piece = |spans| {
        let mut item = Item::new(x.index, x.colour, x.plane, spans);
        item.sorted = false;
        item
    };
    Some((piece(front), piece(back)))
}

/// Depth sort as a [`HiddenSurface`].
#[derive(Debug, Default)]
pub struct Painter {
    split: bool,
    walker: SpanWalker,
    /// The colour-only frame, row-major (no depth buffer).
    frame: Vec<Option<Colour>>,
    pub stats: PainterStats,
}

impl Painter {
    /// The classic method: cycles are painted in the order at hand.
    pub fn new() -> Self {
        Painter::default()
    }

    /// With the splitting step: a cycle is broken by cutting a polygon by another's plane.
    pub fn with_split() -> Self {
        Painter {
            split: true,
            ..Painter::default()
        }
    }

    /// The frame's items, sorted farthest first (at an equal farthest depth, the later
    /// polygon first, so that the earlier ends in front).
    fn items(&mut self, polygons: &[Polygon], width: u32, height: u32) -> Vec<Item> {
        let mut items = Vec::new();
        for (index, p) in polygons.iter().enumerate() {
            let mut spans = Vec::new();
            self.walker
                .for_each_span(p, width, height, |s| spans.push(s));
            if !spans.is_empty() {
                items.push(Item::new(index, p.colour, DepthPlane::of(p), spans));
            }
        }
        items.sort_by(|a, b| b.z_max.total_cmp(&a.z_max).then(b.index.cmp(&a.index)));
        items
    }

    /// Tries to break a cycle met at the head `p` against the marked `q` (at `k`): cut `q`
    /// by `p`'s plane, or `p` by `q`'s; failing those (each lies wholly on one side of the
    /// other's plane: the cycle runs through other polygons), one of the marked polygons
    /// by another's plane or by `p`'s, or `p` by theirs. The pieces go to the head of the
    /// list, unmarked.
    fn split_cycle(&mut self, items: &mut Vec<Item>, list: &mut VecDeque<usize>, k: usize) -> bool {
        let mut members = vec![0, k];
        members.extend(
            list.iter()
                .enumerate()
                .skip(1)
                .filter(|&(m, &i)| m != k && items[i].moved)
                .map(|(m, _)| m)
                .take(MARKED_TRIED),
        );
        let pairs = members
            .iter()
            .flat_map(|&x| members.iter().map(move |&by| (x, by)))
            .filter(|(x, by)| x != by);
        for (xi, byi) in pairs {
            if let Some((front, back)) = cut(&items[list[xi]], &items[list[byi]]) {
                list.remove(xi);
                items.push(back);
                items.push(front);
                list.push_front(items.len() - 2);
                list.push_front(items.len() - 1);
                self.stats.splits += 1;
                return true;
            }
        }
        false
    }
}

/// How many marked polygons, besides P and Q, a cycle's cut is looked for among.
const MARKED_TRIED: usize = 16;

/// At most this many cuts per polygon of the frame, and this many more, before a cycle is
/// painted as it stands: every cut makes pieces of fewer pixels, but a frame of many
/// cycles should not cost without bound.
const CUTS_PER_POLYGON: usize = 4;
const CUTS_EXTRA: usize = 64;

impl HiddenSurface for Painter {
    fn resolve(&mut self, polygons: &[Polygon], width: u32, height: u32, runs: &mut Vec<Run>) {
        let mut items = self.items(polygons, width, height);
        self.stats.polygons += items.len() as u64;
        let max_cuts = items.len() * CUTS_PER_POLYGON + CUTS_EXTRA;
        let mut cuts = 0;
        let mut list: VecDeque<usize> = (0..items.len()).collect();
        self.frame.clear();
        self.frame.resize(width as usize * height as usize, None);
        while let Some(&p) = list.front() {
            // The first Q that P may hide.
            let mut blocker = None;
            for (k, &q) in list.iter().enumerate().skip(1) {
                if items[q].sorted && items[q].z_max < items[p].z_min {
                    break; // this one and all after it are wholly farther than P
                }
                match first_passing_test(&items[p], &items[q]) {
                    Some(t) => self.stats.resolved_by[t] += 1,
                    None => {
                        self.stats.unresolved += 1;
                        blocker = Some(k);
                        break;
                    }
                }
            }
            if let Some(k) = blocker {
                let q = list[k];
                if !items[q].moved {
                    // Q goes before P, marked.
                    items[q].moved = true;
                    items[q].sorted = false;
                    list.remove(k);
                    list.push_front(q);
                    self.stats.swaps += 1;
                    continue;
                }
                self.stats.cycles += 1;
                if self.split && cuts < max_cuts && self.split_cycle(&mut items, &mut list, k) {
                    cuts += 1;
                    continue;
                }
                self.stats.given_up += 1;
            }
            // Paint P over what is there.
            list.pop_front();
            let item = &items[p];
            for s in &item.spans {
                let row = s.y as usize * width as usize;
                self.frame[row + s.x0 as usize..row + s.x1 as usize].fill(Some(item.colour));
            }
        }
        for (y, row) in self.frame.chunks_exact(width.max(1) as usize).enumerate() {
            push_row_runs(y as u32, row, runs);
        }
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
            "{} polygons sorted, pairs resolved by {}, {} unresolved, {} swaps, {} cycles, {} splits, {} cycles painted out of order",
            s.polygons,
            tests.join(", "),
            s.unresolved,
            s.swaps,
            s.cycles,
            s.splits,
            s.given_up
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use scan::frame::{differing_pixels, image_of, zbuffer_image};

    fn quad(colour: Colour, corners: [[f64; 2]; 4], z: impl Fn(f64, f64) -> f64) -> Polygon {
        let v: Vec<[f64; 3]> = corners.iter().map(|&[x, y]| [x, y, z(x, y)]).collect();
        Polygon::from_xyz(colour, &v)
    }

    fn square(colour: Colour, x0: f64, y0: f64, x1: f64, y1: f64, z: f64) -> Polygon {
        quad(colour, [[x0, y0], [x1, y0], [x1, y1], [x0, y1]], |_, _| z)
    }

    fn paint(painter: &mut Painter, polygons: &[Polygon], w: u32, h: u32) -> Vec<Option<Colour>> {
        let mut runs = Vec::new();
        painter.resolve(polygons, w, h, &mut runs);
        image_of(&runs, w, h)
    }

    /// The z-buffer's picture, the painter's, and the painter's with --split.
    fn against_zbuffer(polygons: &[Polygon], w: u32, h: u32) -> (usize, usize, Painter, Painter) {
        let z = zbuffer_image(polygons, w, h);
        let (mut plain, mut split) = (Painter::new(), Painter::with_split());
        let a = differing_pixels(&z, &paint(&mut plain, polygons, w, h));
        let b = differing_pixels(&z, &paint(&mut split, polygons, w, h));
        (a, b, plain, split)
    }

    #[test]
    fn back_to_front_and_the_earlier_of_a_tie_in_front() {
        // The z-buffer's own worked example (scan::frame): nearer wins, a tie goes to
        // the earlier square.
        let polygons = [
            square([1, 0, 0], 0.0, 0.0, 2.0, 2.0, 0.5),
            square([2, 0, 0], 1.0, 0.0, 3.0, 1.0, 0.25),
            square([3, 0, 0], 0.0, 1.0, 1.0, 2.0, 0.5),
        ];
        let r = |v| Some([v, 0, 0]);
        let mut p = Painter::new();
        assert_eq!(
            paint(&mut p, &polygons, 3, 2),
            vec![r(1), r(2), r(2), r(1), r(1), None]
        );
        assert_eq!(p.stats.cycles, 0);
        assert_eq!(p.stats.polygons, 3);
    }

    #[test]
    fn each_test_resolves_the_pairs_it_is_for() {
        let (w, h) = (20, 20);
        // A far square wholly behind a near one: the search for overlapping depths
        // stops at once, no test is needed.
        let mut p = Painter::new();
        paint(
            &mut p,
            &[
                square([1, 1, 1], 0.0, 0.0, 8.0, 8.0, 0.2),
                square([2, 2, 2], 4.0, 4.0, 12.0, 12.0, 0.8),
            ],
            w,
            h,
        );
        assert_eq!((p.stats.resolved_by, p.stats.swaps), ([0; 5], 0));
        // Test 1: the extents meet at one depth (two flat squares at 0.5), and the
        // farther-sorted is the later: the earlier ends in front.
        let mut p = Painter::new();
        let first = square([1, 1, 1], 0.0, 0.0, 8.0, 8.0, 0.5);
        let second = square([2, 2, 2], 4.0, 4.0, 12.0, 12.0, 0.5);
        let image = paint(&mut p, &[first.clone(), second.clone()], w, h);
        assert_eq!((p.stats.resolved_by, p.stats.swaps), ([1, 0, 0, 0, 0], 0));
        assert_eq!(image, zbuffer_image(&[first, second], w, h));
        assert_eq!(image[5 * 20 + 5], Some([1, 1, 1]));
        // Test 2: depth extents overlap (tilted), boxes apart.
        let mut p = Painter::new();
        let a = quad(
            [1, 1, 1],
            [[0.0, 0.0], [8.0, 0.0], [8.0, 8.0], [0.0, 8.0]],
            |x, _| 0.1 + x * 0.05,
        );
        let b = quad(
            [2, 2, 2],
            [[10.0, 0.0], [18.0, 0.0], [18.0, 8.0], [10.0, 8.0]],
            |x, _| 0.1 + (x - 10.0) * 0.05,
        );
        paint(&mut p, &[a, b], w, h);
        assert_eq!(p.stats.resolved_by, [0, 1, 0, 0, 0]);
        // Test 3: a far tilted square behind a near flat one that overlaps its depths
        // only where it does not reach: the flat one's plane is nearer all over it.
        let mut p = Painter::new();
        let far = quad(
            [1, 1, 1],
            [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]],
            |x, _| 0.5 + x * 0.04,
        );
        let near = square([2, 2, 2], 5.0, 5.0, 15.0, 15.0, 0.45);
        let mut q = Painter::new();
        let image = paint(&mut p, &[far.clone(), near.clone()], w, h);
        assert_eq!(image, zbuffer_image(&[far.clone(), near.clone()], w, h));
        // Sorted: far (farthest 0.9) is P; near is Q, behind it? No: near's plane at
        // 0.45 is nearer than all of far (≥ 0.5): test 1 already. Tilt near instead.
        let near = quad(
            [2, 2, 2],
            [[5.0, 5.0], [15.0, 5.0], [15.0, 15.0], [5.0, 15.0]],
            |x, _| 0.3 + x * 0.02,
        );
        // near spans 0.4..0.6, far 0.5..0.9 (extents overlap); near's plane is nearer
        // than far at every pixel of far: test 3.
        paint(&mut q, &[far.clone(), near.clone()], w, h);
        assert_eq!(q.stats.resolved_by, [0, 0, 1, 0, 0]);
        // Test 4: Q wholly in front of P's plane, though P is not behind Q's plane.
        let big = quad(
            [1, 1, 1],
            [[0.0, 0.0], [20.0, 0.0], [20.0, 20.0], [0.0, 20.0]],
            |x, _| 0.2 + x * 0.04,
        );
        let small = square([2, 2, 2], 12.0, 2.0, 14.0, 4.0, 0.5); // big is 0.68..0.76 there
        let mut p = Painter::new();
        let image = paint(&mut p, &[big.clone(), small.clone()], w, h);
        assert_eq!(p.stats.resolved_by, [0, 0, 0, 1, 0]);
        assert_eq!(image, zbuffer_image(&[big, small], w, h));
        // Test 5: boxes overlap, pixels do not (two triangles of a square, tilted apart).
        let t1 = Polygon::from_xyz(
            [1, 1, 1],
            &[[0.0, 0.0, 0.1], [10.0, 0.0, 0.9], [0.0, 10.0, 0.1]],
        );
        let t2 = Polygon::from_xyz(
            [2, 2, 2],
            &[[10.0, 0.0, 0.2], [10.0, 10.0, 0.2], [0.0, 10.0, 0.8]],
        );
        let mut p = Painter::new();
        paint(&mut p, &[t1, t2], w, h);
        assert_eq!(p.stats.resolved_by, [0, 0, 0, 0, 1]);
    }

    /// Three bars each over the next: A over C at the top left, C over B at the bottom
    /// right, B over A at the top right. No pair passes through the other.
    fn cyclic_bars() -> Vec<Polygon> {
        let a = quad(
            [255, 0, 0],
            [[2.0, 4.0], [28.0, 4.0], [28.0, 10.0], [2.0, 10.0]],
            |x, _| 0.2 + 0.6 * (x - 2.0) / 26.0,
        );
        let b = quad(
            [0, 255, 0],
            [[20.0, 2.0], [26.0, 2.0], [26.0, 28.0], [20.0, 28.0]],
            |_, y| 0.5 + 0.3 * (y - 2.0) / 26.0,
        );
        let c = quad(
            [0, 0, 255],
            [[2.0, 8.0], [6.0, 4.0], [28.0, 26.0], [24.0, 30.0]],
            |x, y| 0.6 - 0.3 * (x + y - 10.0) / 44.0,
        );
        vec![a, b, c]
    }

    /// The pixels two polygons both cover.
    fn shared_pixels(a: &Polygon, b: &Polygon, w: u32, h: u32) -> usize {
        let one = |p: &Polygon| zbuffer_image(std::slice::from_ref(p), w, h);
        one(a)
            .iter()
            .zip(one(b))
            .filter(|(x, y)| x.is_some() && y.is_some())
            .count()
    }

    #[test]
    fn a_cyclic_overlap_is_painted_wrong_where_one_pair_overlaps_and_split_mends_it() {
        let bars = cyclic_bars();
        let (w, h) = (32, 32);
        let (plain, split, p, s) = against_zbuffer(&bars, w, h);
        // Every pair overlaps and the z-buffer shows a true cycle.
        let overlaps = [
            shared_pixels(&bars[0], &bars[1], w, h),
            shared_pixels(&bars[1], &bars[2], w, h),
            shared_pixels(&bars[2], &bars[0], w, h),
        ];
        assert_eq!(overlaps, [36, 38, 32]);
        // Without the splitting step one pair's overlap comes out the wrong way round:
        // exactly the pixels A and B share (B is painted under A).
        assert_eq!(plain, overlaps[0]);
        assert_eq!((p.stats.cycles, p.stats.given_up, p.stats.swaps), (2, 2, 3));
        // With it, the z-buffer's picture.
        assert_eq!(split, 0);
        assert_eq!((s.stats.given_up, s.stats.splits), (0, 4));
    }

    #[test]
    fn interpenetrating_squares_fail_and_split_mends_them() {
        // Two squares crossing along X = 10: red nearer on the left, blue on the right.
        let red = quad(
            [255, 0, 0],
            [[0.0, 0.0], [20.0, 0.0], [20.0, 16.0], [0.0, 16.0]],
            |x, _| 0.3 + x * 0.02,
        );
        let blue = quad(
            [0, 0, 255],
            [[4.0, 4.0], [20.0, 4.0], [20.0, 20.0], [4.0, 20.0]],
            |_, _| 0.5,
        );
        let (plain, split, p, _) = against_zbuffer(&[red, blue], 20, 20);
        // Blue's part over red where red is nearer (X < 10: columns 4..9 of rows 4..15)
        // or red's over blue where blue is nearer (columns 10..19): one side is wrong.
        assert!(plain == 6 * 12 || plain == 10 * 12, "{plain}");
        assert_eq!(plain, 6 * 12);
        assert_eq!(p.stats.given_up, 1);
        assert_eq!(split, 0);
    }

    #[test]
    fn coincident_polygons_go_to_the_earlier() {
        let a = square([1, 0, 0], 0.0, 0.0, 8.0, 8.0, 0.5);
        let b = square([2, 0, 0], 0.0, 0.0, 8.0, 8.0, 0.5);
        let tilt = |c| {
            quad(
                c,
                [[0.0, 0.0], [8.0, 0.0], [8.0, 8.0], [0.0, 8.0]],
                |x, y| 0.2 + x * 0.03 + y * 0.01,
            )
        };
        for scene in [
            vec![a.clone(), b.clone()],
            vec![b, a],
            vec![tilt([3, 0, 0]), tilt([4, 0, 0])],
        ] {
            let (plain, split, p, _) = against_zbuffer(&scene, 8, 8);
            assert_eq!((plain, split, p.stats.cycles), (0, 0, 0));
        }
    }

    #[test]
    fn nothing_to_paint() {
        let mut runs = Vec::new();
        let mut p = Painter::new();
        p.resolve(&[], 4, 4, &mut runs);
        p.resolve(
            &[Polygon::from_xyz(
                [1, 1, 1],
                &[[0.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
            )],
            4,
            4,
            &mut runs,
        );
        p.resolve(
            &[square([1, 1, 1], 0.0, 0.0, 4.0, 4.0, 0.5)],
            0,
            0,
            &mut runs,
        );
        assert!(runs.is_empty());
        assert_eq!(p.stats.polygons, 0);
        assert!(p
            .stats()
            .starts_with("0 polygons sorted, pairs resolved by test 1 (depth extents) 0,"));
    }

    mod properties {
        use super::*;
        use proptest::prelude::*;

        /// A quad anywhere (partly off the screen too): its level, rectangle, whether it
        /// is tilted, a colour.
        fn layered_quad() -> impl Strategy<Value = (u8, [f64; 4], bool, u8)> {
            (
                0u8..5,
                [-8.0f64..40.0, -8.0f64..40.0, 1.0f64..30.0, 1.0f64..30.0],
                any::<bool>(),
                any::<u8>(),
            )
        }

        proptest! {
            /// Scenes that have a depth order although their depth extents overlap:
            /// tilted quads on parallel planes (one gradient for the scene, each quad a
            /// plane of its own, 0.05 apart), and in front of them flat quads at a few
            /// depths (coincident where they share one: the earlier in front).
            #[test]
            fn depth_ordered_scenes_paint_as_the_zbuffer_draws(
                quads in prop::collection::vec(layered_quad(), 1..12),
                gradient in [-0.03f64..0.03, -0.03f64..0.03],
                split in any::<bool>(),
            ) {
                let (w, h) = (32, 32);
                let [gx, gy] = gradient;
                let polygons: Vec<Polygon> = quads.iter().enumerate().map(|(i, &(level, [x, y, dx, dy], tilted, c))| {
                    let corners = [[x, y], [x + dx, y], [x + dx, y + dy], [x, y + dy]];
                    if tilted {
                        let base = 1.0 + 0.05 * i as f64;
                        quad([c, level, 1], corners, |px, py| base + gx * (px - 16.0) + gy * (py - 16.0))
                    } else {
                        quad([c, level, 0], corners, |_, _| -10.0 + 0.02 * level as f64)
                    }
                }).collect();
                let z = zbuffer_image(&polygons, w, h);
                let mut p = if split { Painter::with_split() } else { Painter::new() };
                let image = paint(&mut p, &polygons, w, h);
                prop_assert_eq!(differing_pixels(&z, &image), 0);
                prop_assert_eq!(p.stats.cycles, 0);
            }

            /// Any scene, interpenetrating and cyclic ones included: every covered pixel
            /// painted once (image_of checks), the covered set the z-buffer's; with
            /// --split, the z-buffer's picture whenever no cycle was left uncut.
            #[test]
            fn any_scene_covers_the_zbuffers_pixels(
                tris in prop::collection::vec(prop::array::uniform3((-4.0f64..36.0, -4.0f64..36.0, 0.0f64..1.0)), 1..10),
            ) {
                let (w, h) = (32, 32);
                let polygons: Vec<Polygon> = tris.iter().enumerate().map(|(i, t)| {
                    Polygon::from_xyz([i as u8, 7, 7], &t.map(|(x, y, z)| [x, y, z]))
                }).collect();
                let z = zbuffer_image(&polygons, w, h);
                let mut p = Painter::new();
                let plain = paint(&mut p, &polygons, w, h);
                prop_assert!(z.iter().zip(&plain).all(|(a, b)| a.is_some() == b.is_some()));
                let mut s = Painter::with_split();
                let split = paint(&mut s, &polygons, w, h);
                if s.stats.given_up == 0 {
                    prop_assert_eq!(differing_pixels(&z, &split), 0);
                }
                // Without cycles the plain method is exact too.
                if p.stats.cycles == 0 {
                    prop_assert_eq!(differing_pixels(&z, &plain), 0);
                }
            }
        }
    }
}
