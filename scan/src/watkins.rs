//! # Watkins's scan-line hidden-surface algorithm
//!
//! The `scanline` stage's method, here so that the hidden-line stage can take its
//! visible segments too (Archuleta 1972 draws his lines from Watkins's segments: his
//! counters are incremented as the visible segments go to the shader).
//!
//! After Watkins's algorithm as Archuleta describes it (Archuleta (1972), "Watkins'
//! Algorithm" and the listing of HIDDEN) and as Newman and Sproull's chapter 14.4 explains
//! it (Newman and Sproull 1973, 14.4.1 "Processing a scan-line", 14.4.2 "Scan-line coherence"). A
//! frame is resolved one scan line at a time, top to bottom, with no depth buffer:
//!
//! 1. **Active polygons.** The frame's polygons are sorted by the first scan line they
//!    can reach (Archuleta's "sorted with respect to Y" preframe processing). A polygon
//!    enters the active list at that line and leaves it after its last. The active
//!    polygons' edges are kept in one shared table (`EdgeArena`): each polygon's block
//!    of it, sorted by first line, holds its active edges at the front (its Active Edge
//!    Table in place), stepped one line at a time and never rebuilt: Archuleta's "after a
//!    scan line has been completed, all segments are updated to the next scan line". The
//!    blocks of polygons that have left are reclaimed, so the memory is linear in the
//!    edges active at once, with no allocation per polygon (200,000 triangles in one
//!    pixel: 105 MB peak, where an Edge Table and an Active Edge Table a polygon took
//!    358 MB).
//! 2. **Segments, kept in X order.** On each line, an active polygon's crossings, paired
//!    by the even-odd rule, give its *segments* (14.4: "the intersection of the
//!    scan-line window and a planar polygon"): the columns whose pixel centres it covers,
//!    exactly the spans the z-buffer draws (docs/DESIGN.md, "Leaves resolve
//!    visibility"), each with the polygon's depth plane on the line (`z_row`, `dz`) and
//!    its stream index. The segment list is kept from one line to the next in X order
//!    (Archuleta: "all segments are updated to the next scan line. Some minor sorting is
//!    performed at this time, due to exiting edges and new entering edges"): the polygons
//!    are stepped in the X order of their first segments on the line above, so that their
//!    new segments come out in that order, those gone are dropped, an insertion sort puts
//!    back the few that moved past one another (none where nothing did), and the segments
//!    new on the line are sorted among themselves and merged in. A segment is cut in two
//!    where its depth changes sign ([`sign_change`]): the tie is relative to the held
//!    depth, sign and all, so across a change of sign the rule between two segments can
//!    change its answer twice, and every test below at two ends assumes once.
//! 3. **Sample spans.** The line is cut at every segment end into *sample spans*, inside
//!    which the set of segments does not change. A sample span with one segment is that
//!    segment's (14.4.1, simple case 1); a span with none is background.
//! 4. **Depth only where segments overlap.** In a sample span with several segments the
//!    front one at its left end is, in this order: the front carried from the span before
//!    (while it stays, a segment coming in is compared with it alone); the front the line
//!    above had at that column, verified against every other segment by the tie rule (a
//!    segment in front of each of the others is what the z-buffer's fold leaves); or the
//!    fold itself, their depths in stream order with the tie rule (docs/DESIGN.md, "The Z
//!    specification": a later polygon takes the pixel only when nearer by more than 2⁻³⁰
//!    of the holder's depth). Every other segment is then tested against the front at the
//!    next column and at the end of their overlap: the rule between two planar depths
//!    changes its answer once at most along a line, so two tests say whether it comes in
//!    front at all. Then Watkins's cases (14.4.1): no segment comes in front inside the
//!    span — the front is a spanner, visible across it (case 2); one does — a simple
//!    intersection (case 3), whose X is computed where the two depth lines meet
//!    ([`xinter`]; Archuleta's XINTER, "the X point of intersection"; 14.4.1: "we can
//!    compute the X_s coordinate of the point of intersection") and the column settled
//!    by the z-buffer's own test at the pixel centres beside it ([`settle`]: at most
//!    four tests, not a search), so that it is exactly the column where the z-buffer's
//!    answer changes; several do — a complicated case (case
//!    4): the span is subdivided at its midpoint (14.4.1 divides "at the left-most
//!    segment endpoint in the span", and "if there is no segment endpoint in the span ...
//!    at its midpoint by default"; a sample span here holds no endpoint), or where the
//!    line above changed (below), keeping the half where the first of them comes in
//!    front, until one is left. The span is split at that column (Figure 14-33's
//!    non-recursive subdivision: process the left part, then go on with the remainder),
//!    and the front is found afresh there.
//!    Segments that come in front only past the span's end are solved at once, so the
//!    bound carried to the next span is exact.
//! 5. **Coherence from line to line** (14.4.2: "use the record of subdivisions on scan
//!    line k to predict fruitful subdivisions for scan line k+1"). Each line keeps its
//!    *pieces*, the stretches where one polygon was found in front. On the next line the
//!    piece at a column predicts the front there (verified as above, the fold only if it
//!    fails), the column where that piece ended predicts where a segment subdivision
//!    should cut, and, when the next piece is the same polygon that now comes in front,
//!    the crossing column itself, verified by two tests (in front there, not one column
//!    before) before XINTER is computed. `--stats` counts what held and what failed.
//!
//! Without the coherence (`sort_afresh`, `scanline --sort-afresh`), the line's segments
//! are sorted afresh and nothing is predicted; the picture is the same.
//!
//! Depths are [`crate::depth_at`]'s, the z-buffer's, so the result is the z-buffer's
//! picture to the pixel ([`crate::frame::zbuffer_image`]). (Where three or more polygons
//! lie within two tie widths of one another at a pixel without all tying, the front
//! carried along the line is compared pairwise, which can differ from the fold; the
//! front is found afresh by the fold at every split, so only such a pixel can differ.)
//!
//! A Gouraud-shaded polygon (docs/DESIGN.md, "Shading") is decided as a flat one; each
//! piece of a line where its segment is in front is painted pixel by pixel in its colour
//! planes' value at the centre (`proto::shade`, as the z-buffer's shaded span), and sent as
//! runs of one colour ([`crate::frame::shaded_runs`]).
//!
//! The counters Watkins's timings are about (14.4.3: the computation "grows roughly as the
//! *visible* complexity") are kept in [`ScanlineStats`].

use crate::frame::{shaded_runs, HiddenSurface};
use crate::{depth_at, Depth, DepthPlane, Outline, Run};
use proto::raster::centres_in_clamped;
use proto::shade::{Lighting, Shading};
use proto::{Colour, Polygon};
use std::ops::Range;
use std::sync::Arc;

/// Counters over all frames, for `--stats`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ScanlineStats {
    /// Scan lines processed (those with at least one active polygon).
    pub scan_lines: u64,
    /// Segments: one per covered stretch of a polygon on a scan line.
    pub segments: u64,
    /// Sample spans: stretches between segment ends holding at least one segment.
    pub sample_spans: u64,
    /// Segments examined: the sum, over sample spans, of the segments in each.
    pub segments_examined: u64,
    /// Depth comparisons of one segment against another (at a column, or a crossing solve).
    pub depth_comparisons: u64,
    /// Splits of a sample span where another segment comes in front (intersections and
    /// segments emerging from behind).
    pub crossings: u64,
    /// The minor sorting of the kept segment list (Archuleta (1972), HIDDEN): segments new
    /// on their line (and a concave polygon's second and later segments), merged in;
    /// segments found out of order and moved back by the insertion sort; and the places
    /// they moved past.
    pub merged: u64,
    pub resorted: u64,
    pub swaps: u64,
    /// The line above's front at a column tried first, and verified, when the front is
    /// looked for afresh: held, or failed (and the fold run).
    pub fronts_predicted: u64,
    pub fronts_mispredicted: u64,
    /// The column where the line above changed from one polygon to another tried first
    /// for the crossing of the same two: held (two tests), or failed (and computed).
    pub crossings_predicted: u64,
    pub crossings_mispredicted: u64,
    /// Crossing columns computed from the two depth lines (XINTER, [`settle`]), and of
    /// those the ones whose X the z-buffer's test put more than a column off, bisected.
    pub crossings_computed: u64,
    pub crossings_searched: u64,
    /// Cuts of a span that is none of the simple cases (more than one segment coming in
    /// front of the front inside it), at the line above's split or at the midpoint.
    pub midpoint_subdivisions: u64,
}

/// One polygon's segment on the current scan line (Archuleta (1972), "pairs of edges
/// that belong to the same polygon are linked together to form segments").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// Covered columns `x0..x1` (end exclusive, non-empty).
    pub x0: u32,
    pub x1: u32,
    /// The polygon's depth at column 0 of the line and its step per column: column x has
    /// depth `depth_at(z_row, dz, x)`.
    pub z_row: Depth,
    pub dz: Depth,
    /// The polygon's place in the frame's stream: the tie rule favours the earlier.
    pub polygon: usize,
    /// Which of the polygon's segments on the line this is, counting from the left (a
    /// concave polygon has several): the 0th's place in the list orders the polygon for
    /// the next line, the others are merged in anew.
    pub k: u32,
    pub colour: Colour,
}

impl Segment {
    /// The depth the z-buffer gives column x.
    #[inline]
    pub fn depth(&self, x: u32) -> Depth {
        depth_at(self.z_row, self.dz, x)
    }

    /// Whether this segment is in front of `other` at column x, by the tie rule for two
    /// polygons: if it comes later in the stream it must take the pixel from `other`; if
    /// earlier, `other` must not take the pixel from it.
    #[inline]
    pub fn in_front_of(&self, other: &Segment, x: u32) -> bool {
        proto::depth::in_front(self.depth(x), self.polygon > other.polygon, other.depth(x))
    }
}

/// Archuleta's XINTER ("the X point of intersection"; Newman and Sproull (1973), 14.4.1,
/// simple case 3: "we can compute the X_s coordinate of the point of intersection"): the X
/// at which `s` comes in front of `front` on their two depth lines, by the tie rule. A
/// later `s` must take the pixel, `z_s(x) < (1 − 2⁻³⁰·σ)·z_f(x)`; an earlier one must not
/// lose it, `z_f(x) ≥ (1 − 2⁻³⁰·σ)·z_s(x)` (σ the sign of the holder's depth, taken at
/// `at`). Both sides are linear in x, so the boundary is where two lines meet: `None`
/// when they are parallel (or the depths not finite).
pub fn xinter(s: &Segment, front: &Segment, at: u32) -> Option<f64> {
    let later = s.polygon > front.polygon;
    // The holder (whose depth the tie width is relative to) and the newcomer.
    let (held, new) = if later { (front, s) } else { (s, front) };
    let k = 1.0 - proto::depth::TIE.copysign(held.depth(at));
    // new(x) = k·held(x): (z_new − k·z_held) + x·(dz_new − k·dz_held) = 0.
    let x = (k * held.z_row - new.z_row) / (new.dz - k * held.dz);
    x.is_finite().then_some(x)
}

/// The first column in `lo + 1..=hi` where `s` is in front of `front`, given that it is
/// not at `lo` and is at `hi`, and how many depth comparisons it took: the column at or
/// after [`xinter`]'s X, settled by the z-buffer's own test at the pixel centres around
/// it (at most four comparisons: the X rounds to the right column or one beside it). Only
/// if the test disagrees with the X by more than a column (a holder's depth changing sign
/// inside the span, or X lost to rounding on nearly parallel lines) is the rest bisected;
/// the third value says so.
pub fn settle(s: &Segment, front: &Segment, lo: u32, hi: u32) -> (u32, u64, bool) {
    debug_assert!(lo < hi);
    if hi - lo == 1 {
        return (hi, 0, false);
    }
    let mut tests = 0u64;
    let mut at = |x: u32| {
        tests += 1;
        s.in_front_of(front, x)
    };
    if hi - lo == 2 {
        // One column between: one test decides.
        return (if at(lo + 1) { lo + 1 } else { hi }, tests, false);
    }
    let (mut lo, mut hi) = (lo, hi);
    if let Some(x) = xinter(s, front, hi) {
        // The first column whose centre is at or past X, inside lo + 1..=hi.
        let c = x.ceil().clamp((lo + 1) as f64, hi as f64) as u32;
        if at(c) {
            if c - 1 == lo || !at(c - 1) {
                return (c, tests, false);
            }
            if c - 2 == lo || !at(c - 2) {
                return (c - 1, tests, false);
            }
            hi = c - 2;
        } else {
            if c + 1 == hi || at(c + 1) {
                return (c + 1, tests, false);
            }
            lo = c + 1;
        }
    }
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if at(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    (hi, tests, true)
}

/// The first column `c ≥ from` at which `s` is in front of `front` ([`Segment::in_front_of`])
/// while both are on the line, or `None`: [`xinter`]'s X rounded to the pixel centres the
/// z-buffer samples ([`settle`]). Both depths are linear in x, so the answer changes at
/// most once along their overlap: two tests at its ends say whether it does.
pub fn first_in_front(s: &Segment, front: &Segment, from: u32) -> Option<u32> {
    let last = s.x1.min(front.x1).checked_sub(1)?;
    if from > last {
        return None;
    }
    if s.in_front_of(front, from) {
        return Some(from);
    }
    if !s.in_front_of(front, last) {
        return None;
    }
    Some(settle(s, front, from, last).0)
}

/// The first column of `cols`, after the first, whose depth (`z_row + x·dz`, as the
/// z-buffer computes it) has the other sign bit than the first column's, if one does:
/// depth is monotone along the line, so its sign changes once at most.
fn sign_change(z_row: Depth, dz: Depth, cols: Range<u32>) -> Option<u32> {
    let last = cols.end.checked_sub(1).filter(|&l| l > cols.start)?;
    let sign = |x: u32| depth_at(z_row, dz, x).is_sign_negative();
    let first = sign(cols.start);
    if sign(last) == first {
        return None;
    }
    // sign(lo) == first, sign(hi) != first.
    let (mut lo, mut hi) = (cols.start, last);
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if sign(mid) == first {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(hi)
}

/// One edge of an active polygon in the [`EdgeArena`]: the snapped line it crosses a
/// line's centre on (proto's exact [`proto::raster::Edge`], so that the crossings are the
/// z-buffer's walker's, as columns, docs/DESIGN.md, "Coverage") and the lines
/// `start..end` whose centres it crosses (the Edge Table's first line and the thesis's
/// y_max).
#[derive(Clone, Copy, Debug)]
struct ArenaEdge {
    edge: proto::raster::Edge,
    start: u32,
    end: u32,
}

/// The edges of every active polygon, in one table (Archuleta's single list of the
/// frame's edges, "sorted with respect to Y", rather than an Edge Table and an Active
/// Edge Table a polygon): each polygon owns a block of it, its edges sorted by first line
/// as they enter, and within the block keeps its own active edges at the front (the
/// Active Edge Table in place: an edge that enters is swapped to the end of the active
/// run, one that leaves swapped out of it). The table grows by a block per polygon that
/// enters and is compacted when more than half of it is blocks of polygons that have
/// left: its memory is linear in the edges of the polygons active at once, with no
/// allocation per polygon.
#[derive(Debug, Default)]
struct EdgeArena {
    edges: Vec<ArenaEdge>,
    /// Entries of blocks whose polygons have left.
    dead: usize,
    /// Scratch: a polygon's outline, snapped, as it enters; a line's crossings (each the
    /// first column at or right of it).
    outline: Outline,
    crossings: Vec<i64>,
}

impl EdgeArena {
    fn clear(&mut self) {
        self.edges.clear();
        self.dead = 0;
    }

    /// Appends the block of `polygon`'s edges that cross a line centre on a screen
    /// `height` lines high, sorted by first line: `(start of the block, its length, the
    /// lines from the first to the last crossed)`, or `None` when it covers no line
    /// (fewer than three vertices, every vertex on one line, no edge across a centre).
    /// The edges are [`crate::polygon_edge`]'s: from the supports of a split polygon.
    fn enter(&mut self, polygon: &Polygon, height: u32) -> Option<(usize, u32, Range<i64>)> {
        // Snapped as scan::SpanWalker loads a polygon.
        if !self.outline.load(polygon) {
            return None;
        }
        let base = self.edges.len();
        for i in 0..self.outline.points.len() {
            let Some(edge) = self.outline.edge(i) else {
                continue;
            };
            let rows = edge.rows();
            let (start, end) = (rows.start.max(0), rows.end.min(height as i64));
            if start < end {
                self.edges.push(ArenaEdge {
                    edge,
                    start: start as u32,
                    end: end as u32,
                });
            }
        }
        let block = &mut self.edges[base..];
        if block.is_empty() {
            return None;
        }
        block.sort_by_key(|e| e.start);
        let first = block[0].start as i64;
        let last = block.iter().map(|e| e.end).max().unwrap_or(0) as i64;
        Some((base, block.len() as u32, first..last))
    }

    /// Steps `a`'s edges to line `row` (any line at or below the last, in order): those
    /// whose first line has come move into its active run, those past their last move
    /// out; then the sorted crossings of the active ones with the line's centre (pairs
    /// bound the covered centres, even-odd).
    fn crossings(&mut self, a: &mut ActivePolygon, row: i64) -> &[i64] {
        let block = &mut self.edges[a.base..a.base + a.len as usize];
        while (a.entered as usize) < block.len() && block[a.entered as usize].start as i64 <= row {
            block.swap(a.live as usize, a.entered as usize);
            a.live += 1;
            a.entered += 1;
        }
        let mut i = 0;
        while i < a.live as usize {
            if block[i].end as i64 <= row {
                a.live -= 1;
                block.swap(i, a.live as usize);
            } else {
                i += 1;
            }
        }
        self.crossings.clear();
        // Evaluated exactly at each line (the lines need not come one by one).
        self.crossings
            .extend(block[..a.live as usize].iter().map(|e| e.edge.column(row)));
        crate::sort_crossings(&mut self.crossings);
        &self.crossings
    }

    /// A polygon's block is no longer used; when such blocks are more than half the
    /// table, the active polygons' blocks are moved down over them.
    fn leave(&mut self, a: &ActivePolygon, active: &mut [ActivePolygon]) {
        self.dead += a.len as usize;
        if self.dead * 2 > self.edges.len() && self.dead > 1024 {
            // Blocks keep their order in the table, so each moves down (or stays) and
            // none is overwritten before it moves.
            let mut by_base: Vec<usize> = (0..active.len()).collect();
            by_base.sort_unstable_by_key(|&i| active[i].base);
            let mut to = 0;
            for i in by_base {
                let p = &mut active[i];
                let n = p.len as usize;
                self.edges.copy_within(p.base..p.base + n, to);
                p.base = to;
                to += n;
            }
            self.edges.truncate(to);
            self.dead = 0;
        }
    }
}

/// An active polygon: its block of the shared [`EdgeArena`], stepped line by line.
struct ActivePolygon {
    polygon: usize,
    colour: Colour,
    /// The lines its edges cross.
    rows: Range<i64>,
    depth: DepthPlane,
    /// Its block of the arena: `base..base + len`, the first `live` its active edges, the
    /// first `entered` those whose first line has come.
    base: usize,
    len: u32,
    live: u32,
    entered: u32,
    /// The last line its edges were stepped to.
    stepped: i64,
}

impl ActivePolygon {
    /// Steps the polygon's edges to line y and appends its segments there, left to right:
    /// the first to `first`, the others to `rest` (or to `first` too).
    #[inline]
    fn segments(
        &mut self,
        y: u32,
        width: u32,
        arena: &mut EdgeArena,
        first: &mut Vec<Segment>,
        mut rest: Option<&mut Vec<Segment>>,
    ) {
        let line = y as i64;
        self.stepped = line;
        if line < self.rows.start {
            return;
        }
        let (z_row, dz) = self.depth.row(y);
        let (polygon, colour) = (self.polygon, self.colour);
        let mut k = 0;
        for pair in arena.crossings(self, line).chunks_exact(2) {
            let cols = centres_in_clamped(pair[0], pair[1], width);
            // Cut where the depth changes sign: the tie is relative to the holder's
            // depth, sign and all, so across a change of sign the rule between two
            // segments can change its answer twice (a polygon 5e-11 nearer wins only
            // where the other's depth is within 5e-11·2³⁰ of 0: differential seed 50385),
            // and every test at two ends assumes once.
            let cut = sign_change(z_row, dz, cols.clone()).unwrap_or(cols.end);
            for (x0, x1) in [(cols.start, cut), (cut, cols.end)] {
                if x0 < x1 {
                    let s = Segment {
                        x0,
                        x1,
                        z_row,
                        dz,
                        polygon,
                        k,
                        colour,
                    };
                    match &mut rest {
                        Some(rest) if k > 0 => rest.push(s),
                        _ => first.push(s),
                    }
                    k += 1;
                }
            }
        }
    }
}

/// Watkins's scan-line method as a [`HiddenSurface`]. Its tables (walkers, lists) are
/// kept from frame to frame.
#[derive(Default)]
pub struct Scanline {
    /// The frame's polygons by the first line they may reach: (line, stream index).
    entering: Vec<(i64, usize)>,
    active: Vec<ActivePolygon>,
    /// The active polygons' edges, in one table.
    arena: EdgeArena,
    /// The segment list, kept in X order (by left end, then stream index) from one line
    /// to the next.
    segments: Vec<Segment>,
    /// The active polygons with a segment on the line above, in the X order of their
    /// first segment there (stream indices), and each polygon's slot in `active`
    /// (`GONE` when it is not active), indexed by stream index.
    order: Vec<usize>,
    slot_of: Vec<u32>,
    /// Segments new on the line, and the list they are merged into.
    incoming: Vec<Segment>,
    merged: Vec<Segment>,
    /// Indices into `segments` of those in the current sample span.
    present: Vec<usize>,
    /// The line above's pieces and this line's (the record of subdivisions).
    above: Vec<Piece>,
    pieces: Vec<Piece>,
    /// The segments that may come in front inside a span.
    candidates: Vec<usize>,
    /// The frame's polygons' Gouraud shading, by stream index, when any is shaded (empty
    /// for a flat frame).
    shadings: Vec<Option<Shading>>,
    /// The stream's lighting, for Phong shading.
    lighting: Option<Arc<Lighting>>,
    pub stats: ScanlineStats,
    /// Without the coherence from line to line, to measure what it buys: the segments
    /// sorted afresh on every line, and no prediction from the line above (`--sort-afresh`).
    pub sort_afresh: bool,
    /// The next of `entering` to enter.
    next: usize,
}

/// The slot of a polygon that is not in the active list.
const GONE: u32 = u32::MAX;

impl Scanline {
    pub fn new() -> Self {
        Scanline::default()
    }
}

/// The runs of one line, joined where the same colour goes on.
struct RowRuns<'a> {
    y: u32,
    open: Option<Run>,
    runs: &'a mut Vec<Run>,
}

impl RowRuns<'_> {
    #[inline]
    fn paint(&mut self, x0: u32, x1: u32, colour: Colour) {
        match &mut self.open {
            Some(run) if run.x1 == x0 && run.colour == colour => run.x1 = x1,
            open => {
                if let Some(run) = open.replace(Run {
                    y: self.y,
                    x0,
                    x1,
                    colour,
                }) {
                    self.runs.push(run);
                }
            }
        }
    }

    /// [`RowRuns::paint`] for a Gouraud-shaded polygon: each pixel its colour at the
    /// centre. Apart, so that the flat paint stays small enough to inline in the sweep.
    #[inline(never)]
    fn paint_shaded(&mut self, x0: u32, x1: u32, shading: &Shading) {
        shaded_runs(shading, self.y, x0..x1, |a, b, c| self.paint(a, b, c));
    }

    fn finish(self) {
        if let Some(run) = self.open {
            self.runs.push(run);
        }
    }
}

/// The segment of `present` in front at column x, counting the comparisons: the tie
/// rule's fold in stream order, as the z-buffer draws them. `present` is in the line's
/// order (by left end); the fold visits it by stream index.
#[inline]
fn front_at(segments: &[Segment], present: &[usize], x: u32, comparisons: &mut u64) -> usize {
    let sorted;
    let order = if present.is_sorted_by_key(|&i| segments[i].polygon) {
        present
    } else {
        sorted = {
            let mut v = present.to_vec();
            v.sort_unstable_by_key(|&i| segments[i].polygon);
            v
        };
        &sorted[..]
    };
    let mut front = order[0];
    for &i in &order[1..] {
        if crate::takes(segments[i].depth(x), segments[front].depth(x)) {
            front = i;
        }
    }
    *comparisons += present.len() as u64 - 1;
    front
}

/// The segment in front as the sweep along a line left it, and the column before which no
/// other segment present can come in front of it (a bound: it may be early, never late).
#[derive(Clone, Copy)]
struct Front {
    segment: usize,
    until: u32,
}

/// One stretch of a line's picture: the columns `x0..x1` where the segment of `polygon`
/// was found in front. The pieces of line k are Watkins's "record of subdivisions on scan
/// line k", which predicts the front and the crossings on line k + 1 (Newman and Sproull
/// 1973, 14.4.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Piece {
    pub x0: u32,
    pub x1: u32,
    /// Its place in the frame's stream.
    pub polygon: usize,
}

/// What the sweep along one line works with: the line's segments, the line above's
/// pieces (the prediction), and where the decisions go.
struct Sweep<'a, 'r> {
    segments: &'a [Segment],
    /// The polygons' shading by stream index (empty when none is shaded).
    shadings: &'a [Option<Shading>],
    /// The line above's pieces, left to right.
    above: &'a [Piece],
    /// This line's pieces, as they are decided.
    pieces: &'a mut Vec<Piece>,
    /// The segments that may come in front of the front inside the span being decided.
    candidates: &'a mut Vec<usize>,
    stats: &'a mut ScanlineStats,
    out: RowRuns<'r>,
}

impl Sweep<'_, '_> {
    /// Paints `x0..x1` with `segment`'s colour, or a shaded polygon's colour at each
    /// pixel centre, and records the piece.
    #[inline]
    /// `SHADED`: whether the frame has a shaded polygon (a flat frame's sweep is compiled
    /// without the look-up).
    fn paint<const SHADED: bool>(&mut self, x0: u32, x1: u32, segment: usize) {
        let s = &self.segments[segment];
        match self.shadings.get(s.polygon) {
            Some(Some(shading)) if SHADED => self.out.paint_shaded(x0, x1, shading),
            _ => self.out.paint(x0, x1, s.colour),
        }
        match self.pieces.last_mut() {
            Some(p) if p.x1 == x0 && p.polygon == s.polygon => p.x1 = x1,
            _ => self.pieces.push(Piece {
                x0,
                x1,
                polygon: s.polygon,
            }),
        }
    }

    /// The line above's piece holding column x.
    #[inline]
    fn above_at(&self, x: u32) -> Option<usize> {
        let i = self.above.partition_point(|p| p.x1 <= x);
        (i < self.above.len() && self.above[i].x0 <= x).then_some(i)
    }

    /// The column where, on the line above, `front`'s polygon stopped being in front after
    /// column `lo` (the end of its piece there), when `lo < c < hi`, and the polygon that
    /// came in front there: the subdivision that line made, predicted for this one.
    #[inline]
    fn predicted_split(&self, front: usize, lo: u32, hi: u32) -> Option<(u32, Option<usize>)> {
        let i = self.above_at(lo)?;
        let p = &self.above[i];
        if p.polygon != self.segments[front].polygon || p.x1 <= lo || p.x1 >= hi {
            return None;
        }
        let next = self
            .above
            .get(i + 1)
            .filter(|q| q.x0 == p.x1)
            .map(|q| q.polygon);
        Some((p.x1, next))
    }

    /// The first column in `lo + 1..=hi` where `s` is in front of `front`, given that it is
    /// not at `lo` and is at `hi` (Archuleta's XINTER on the z-buffer's own test). The
    /// column where the line above changed from `front` to `s`, if it did near here, is
    /// tried first (two tests verify it); otherwise, or if it fails, the column is
    /// computed from the two depth lines ([`settle`]).
    fn crossing(&mut self, s: usize, front: usize, mut lo: u32, mut hi: u32) -> u32 {
        let segments = self.segments;
        let (a, f) = (&segments[s], &segments[front]);
        if let Some((g, Some(next))) = self.predicted_split(front, lo, hi + 1) {
            if next == a.polygon {
                self.stats.depth_comparisons += 1;
                if a.in_front_of(f, g) {
                    self.stats.depth_comparisons += 1;
                    if g - 1 == lo || !a.in_front_of(f, g - 1) {
                        self.stats.crossings_predicted += 1;
                        return g;
                    }
                    hi = g - 1;
                } else {
                    lo = g;
                }
                self.stats.crossings_mispredicted += 1;
            }
        }
        let (c, tests, searched) = settle(a, f, lo, hi);
        self.stats.depth_comparisons += tests;
        self.stats.crossings_computed += 1;
        self.stats.crossings_searched += searched as u64;
        c
    }

    /// The first column where one of `self.candidates` comes in front of `front`, given
    /// that none is at `lo` and all are at `hi`: Watkins's subdivision of a span that is
    /// not one of the simple cases. While more than one candidate is left, the span is cut
    /// at the column where the line above changed (if it did inside it) or else at its
    /// midpoint, and the half holding the first crossing kept, with the candidates that
    /// cross in it; one candidate left is a simple intersection, solved by [`Self::crossing`].
    fn subdivide(&mut self, front: usize, mut lo: u32, mut hi: u32) -> u32 {
        let f = self.segments[front];
        loop {
            if let [only] = self.candidates[..] {
                return self.crossing(only, front, lo, hi);
            }
            if hi - lo <= 1 {
                return hi;
            }
            let m = match self.predicted_split(front, lo, hi) {
                Some((c, _)) => c,
                None => lo + (hi - lo) / 2,
            };
            self.stats.midpoint_subdivisions += 1;
            // The candidates in front at m, moved to the head of the list.
            let mut k = 0;
            for j in 0..self.candidates.len() {
                let c = self.candidates[j];
                self.stats.depth_comparisons += 1;
                if self.segments[c].in_front_of(&f, m) {
                    self.candidates.swap(j, k);
                    k += 1;
                }
            }
            if k > 0 {
                self.candidates.truncate(k);
                hi = m;
            } else {
                lo = m;
            }
        }
    }

    /// The first column from `x + 1` on where a segment of `others` comes in front of
    /// `front` (`u32::MAX` if none), the span being `x..b`. Each segment is tested at
    /// `x + 1` and at the end of its overlap with the front (the two depths are planar, so
    /// the answer changes once at most between them); those that cross inside the span
    /// are the candidates for [`Self::subdivide`], those that cross beyond it are solved
    /// at once (the bound carried along the line).
    fn overtaken_at(&mut self, others: &[usize], front: usize, x: u32, b: u32) -> u32 {
        let segments = self.segments;
        let f = segments[front];
        let from = x + 1;
        let span_last = b - 1;
        let mut until = u32::MAX;
        self.candidates.clear();
        for &i in others {
            if i == front {
                continue;
            }
            let s = &segments[i];
            let last = match s.x1.min(f.x1).checked_sub(1) {
                Some(last) if last >= from => last,
                _ => continue,
            };
            self.stats.depth_comparisons += 1;
            if s.in_front_of(&f, from) {
                // Nothing can come in front earlier.
                self.candidates.clear();
                return from;
            }
            self.stats.depth_comparisons += 1;
            if !s.in_front_of(&f, last) {
                continue;
            }
            let inside = from <= span_last
                && (last <= span_last || {
                    self.stats.depth_comparisons += 1;
                    s.in_front_of(&f, span_last)
                });
            if inside {
                self.candidates.push(i);
            } else {
                // Not in front at `from` nor (if the span goes on past it) at its end.
                let c = self.crossing(i, front, span_last.max(from), last);
                until = until.min(c);
            }
        }
        if !self.candidates.is_empty() {
            until = until.min(self.subdivide(front, from, span_last));
        }
        until
    }

    /// The segment in front at column x, found afresh, and the first column where another
    /// comes in front of it. The line above's front at x is tried first: it is verified
    /// against every other segment by the tie rule (a segment in front of each of the
    /// others is what the z-buffer's fold leaves), and only if that fails is the fold run.
    fn front_afresh(&mut self, present: &[usize], x: u32, b: u32) -> Front {
        let predicted = self.above_at(x).and_then(|i| {
            let polygon = self.above[i].polygon;
            present
                .iter()
                .copied()
                .find(|&j| self.segments[j].polygon == polygon)
        });
        let mut segment = None;
        if let Some(p) = predicted {
            let segments = self.segments;
            let s = &segments[p];
            let mut held = true;
            for &j in present {
                if j != p {
                    self.stats.depth_comparisons += 1;
                    if !s.in_front_of(&segments[j], x) {
                        held = false;
                        break;
                    }
                }
            }
            if held {
                self.stats.fronts_predicted += 1;
                segment = Some(p);
            } else {
                self.stats.fronts_mispredicted += 1;
            }
        }
        let segment = segment.unwrap_or_else(|| {
            front_at(self.segments, present, x, &mut self.stats.depth_comparisons)
        });
        Front {
            segment,
            until: self.overtaken_at(present, segment, x, b),
        }
    }

    /// Sweeps the line: cuts it at every segment end into sample spans, left to right, and
    /// decides each ([`Sweep::sample_span`]); `present` is scratch for the segments of a
    /// span. `SHADED`: whether the frame has a shaded polygon.
    fn line<const SHADED: bool>(mut self, present: &mut Vec<usize>) {
        present.clear();
        let mut entered = 0;
        let segments = self.segments;
        let mut x = segments[0].x0;
        let mut front = None;
        // The nearest right end among the segments present: kept as segments come and
        // go rather than looked for each span.
        let mut first_end = u32::MAX;
        loop {
            if present.is_empty() {
                match segments.get(entered) {
                    Some(s) => x = x.max(s.x0),
                    None => break,
                }
            }
            let entering = present.len();
            while entered < segments.len() && segments[entered].x0 <= x {
                let s = &segments[entered];
                first_end = first_end.min(s.x1);
                present.push(entered);
                entered += 1;
            }
            let mut end = first_end;
            if let Some(s) = segments.get(entered) {
                end = end.min(s.x0);
            }
            let span = SampleSpan {
                present,
                entering,
                a: x,
                b: end,
            };
            self.sample_span::<SHADED>(span, &mut front);
            x = end;
            if first_end <= x {
                // Some segment ends here: drop those that do, finding the next end.
                first_end = u32::MAX;
                present.retain(|&i| {
                    let s = &segments[i];
                    if s.x1 > x {
                        first_end = first_end.min(s.x1);
                        true
                    } else {
                        false
                    }
                });
            }
        }
        self.out.finish();
    }

    /// Decides a sample span (14.4.1), carrying `front` along the line.
    ///
    /// Depth is compared only where segments overlap, and only as much as the last span
    /// left undecided: while the front segment stays, a segment coming in is compared with
    /// it alone, and everything is looked at again only where the front leaves or is
    /// overtaken (Watkins's coherence along a scan line).
    fn sample_span<const SHADED: bool>(&mut self, span: SampleSpan, front: &mut Option<Front>) {
        let SampleSpan {
            present,
            entering,
            a,
            b,
        } = span;
        let segments = self.segments;
        self.stats.sample_spans += 1;
        self.stats.segments_examined += present.len() as u64;
        if let [only] = present {
            // Case 1: one segment, visible across the span.
            self.paint::<SHADED>(a, b, *only);
            *front = Some(Front {
                segment: *only,
                until: u32::MAX,
            });
            return;
        }
        // Cases 2 and 3 and the rest: the front segment holds until the first column where
        // another comes in front of it; split there and go on from that column.
        let mut f = match *front {
            // The front is still here and nothing overtakes it at `a`: it is in front of
            // every segment that was here before, so only those coming in need looking at.
            Some(f) if segments[f.segment].x1 > a && f.until > a => {
                let mut best = f.segment;
                for &e in &present[entering..] {
                    self.stats.depth_comparisons += 1;
                    if segments[e].in_front_of(&segments[best], a) {
                        best = e;
                    }
                }
                if best == f.segment {
                    let until = self.overtaken_at(&present[entering..], best, a, b);
                    Front {
                        segment: best,
                        until: f.until.min(until),
                    }
                } else {
                    // A segment comes in in front: every other is solved against it.
                    Front {
                        segment: best,
                        until: self.overtaken_at(present, best, a, b),
                    }
                }
            }
            _ => self.front_afresh(present, a, b),
        };
        let mut x = a;
        loop {
            let split = f.until.min(b);
            self.paint::<SHADED>(x, split, f.segment);
            if split >= b {
                break;
            }
            x = split;
            let next = self.front_afresh(present, x, b);
            if next.segment != f.segment {
                self.stats.crossings += 1;
            }
            f = next;
        }
        *front = Some(f);
    }
}

/// A sample span `a..b` (14.4.1): the segments `present` (indices into the line's
/// segments), of which `present[entering..]` begin at `a`.
struct SampleSpan<'a> {
    present: &'a [usize],
    entering: usize,
    a: u32,
    b: u32,
}

/// The order of the segment list: by left end, then stream index.
#[inline]
fn key(s: &Segment) -> (u32, usize) {
    (s.x0, s.polygon)
}

impl Scanline {
    /// The line's segments built afresh and sorted, the line above forgotten: the method
    /// without its coherence from line to line.
    fn segments_afresh(&mut self, y: u32, width: u32) {
        let line = y as i64;
        self.segments.clear();
        for a in &mut self.active {
            if line < a.rows.start {
                continue;
            }
            let (z_row, dz) = a.depth.row(y);
            for (k, pair) in self.arena.crossings(a, line).chunks_exact(2).enumerate() {
                let cols = centres_in_clamped(pair[0], pair[1], width);
                if !cols.is_empty() {
                    self.segments.push(Segment {
                        x0: cols.start,
                        x1: cols.end,
                        z_row,
                        dz,
                        polygon: a.polygon,
                        k: k as u32,
                        colour: a.colour,
                    });
                }
            }
        }
        self.segments.sort_unstable_by_key(key);
    }

    /// Steps the segment list to the next line, keeping it in X order (Archuleta (1972):
    /// "all segments are updated to the next scan line. Some minor sorting is performed at
    /// this time"): the polygons are stepped in the X order of their first segments on
    /// the line above, so that the new segments come out in that order, those gone
    /// dropped; an insertion sort puts back the few that moved past one another (none
    /// where nothing moved); and the segments new on this line (of polygons that had none
    /// above, and a concave polygon's second and later ones), sorted among themselves,
    /// are merged in.
    fn step_segments(&mut self, y: u32, width: u32) {
        let line = y as i64;
        self.segments.clear();
        self.incoming.clear();
        // The polygons in the order of the line above: their first segments come out in
        // that order, which the minor sort then repairs where they moved past one another.
        for &p in &self.order {
            let slot = self.slot_of[p];
            if slot != GONE {
                let a = &mut self.active[slot as usize];
                a.segments(
                    y,
                    width,
                    &mut self.arena,
                    &mut self.segments,
                    Some(&mut self.incoming),
                );
            }
        }
        // The polygons that had no segment on the line above: all theirs are new.
        for a in &mut self.active {
            if a.stepped != line {
                a.segments(y, width, &mut self.arena, &mut self.incoming, None);
            }
        }
        // The minor sorting: an insertion sort, linear on a list still in order.
        let list = &mut self.segments;
        for i in 1..list.len() {
            if key(&list[i]) < key(&list[i - 1]) {
                self.stats.resorted += 1;
                let s = list[i];
                let mut j = i;
                while j > 0 && key(&s) < key(&list[j - 1]) {
                    list[j] = list[j - 1];
                    j -= 1;
                }
                self.stats.swaps += (i - j) as u64;
                list[j] = s;
            }
        }
        // The segments new on this line, merged in.
        if !self.incoming.is_empty() {
            self.stats.merged += self.incoming.len() as u64;
            self.incoming.sort_unstable_by_key(key);
            if self.segments.is_empty() {
                std::mem::swap(&mut self.segments, &mut self.incoming);
            } else {
                self.merged.clear();
                let (mut i, mut j) = (0, 0);
                let (old, new) = (&self.segments, &self.incoming);
                while i < old.len() && j < new.len() {
                    if key(&new[j]) < key(&old[i]) {
                        self.merged.push(new[j]);
                        j += 1;
                    } else {
                        self.merged.push(old[i]);
                        i += 1;
                    }
                }
                self.merged.extend_from_slice(&old[i..]);
                self.merged.extend_from_slice(&new[j..]);
                std::mem::swap(&mut self.segments, &mut self.merged);
            }
        }
        self.order.clear();
        self.order
            .extend(self.segments.iter().filter(|s| s.k == 0).map(|s| s.polygon));
    }
}

impl Scanline {
    /// Begins a frame: the preframe processing. Then [`Scanline::line`] for each line from
    /// 0 down, until it says no line is left.
    pub fn begin(&mut self, polygons: &[Polygon], height: u32) {
        // Preframe processing: the polygons sorted by the first line they may reach, the
        // least of their vertices' rows on the snapped outline (docs/DESIGN.md,
        // "Coverage": each vertex's first row whose centre is at or below it, once
        // snapped to 1/256 pixel; a cut vertex's from where its support meets the cut).
        // No edge counts on a line above it. Taken from the unsnapped top vertex instead,
        // a vertex a hair below a line centre (14.500000000000002 for the 14.5 a scene
        // meant), snapped onto that centre, would enter a line after its edges start and
        // lose that line's span. A polygon that covers nothing never enters.
        self.entering.clear();
        for (i, p) in polygons.iter().enumerate() {
            if !self.arena.outline.load(p) {
                continue;
            }
            let Some(&first) = self.arena.outline.rows.iter().min() else {
                continue;
            };
            let first = first.max(0);
            if first < height as i64 {
                self.entering.push((first, i));
            }
        }
        // Stable, so polygons entering together keep their stream order.
        self.entering.sort_by_key(|&(line, _)| line);
        self.active.clear();
        self.arena.clear();
        self.segments.clear();
        self.above.clear();
        self.order.clear();
        self.slot_of.clear();
        self.slot_of.resize(polygons.len(), GONE);
        // A shaded polygon's visible pieces take its colour planes' value at each pixel
        // centre (docs/DESIGN.md, "Shading"); a flat frame keeps no table.
        self.shadings.clear();
        if polygons.iter().any(Polygon::is_shaded) {
            let lighting = self.lighting.as_ref();
            self.shadings
                .extend(polygons.iter().map(|p| Shading::of(p, lighting)));
        }

        self.next = 0;
    }

    /// Resolves line `y` (the lines one after another from 0, after [`Scanline::begin`])
    /// into its runs, appended to `runs`; its pieces are then [`Scanline::pieces`]. False
    /// when no polygon is left to enter or active: every line after this one is empty.
    pub fn line(
        &mut self,
        polygons: &[Polygon],
        y: u32,
        width: u32,
        height: u32,
        runs: &mut Vec<Run>,
    ) -> bool {
        {
            let line = y as i64;
            // Polygons entering on this line.
            while self.next < self.entering.len() && self.entering[self.next].0 <= line {
                let i = self.entering[self.next].1;
                self.next += 1;
                let p = &polygons[i];
                // (Its edges' first line is never above this one: both come from the
                // same snapped outline.)
                let Some((base, len, rows)) = self.arena.enter(p, height) else {
                    continue;
                };
                self.slot_of[i] = self.active.len() as u32;
                self.active.push(ActivePolygon {
                    polygon: i,
                    colour: p.colour,
                    rows,
                    depth: DepthPlane::of(p),
                    base,
                    len,
                    live: 0,
                    entered: 0,
                    stepped: -1,
                });
            }
            // Polygons past their last line leave (their segments with them).
            let mut k = 0;
            while k < self.active.len() {
                if self.active[k].rows.end <= line {
                    let gone = self.active.swap_remove(k);
                    self.slot_of[gone.polygon] = GONE;
                    if let Some(moved) = self.active.get(k) {
                        self.slot_of[moved.polygon] = k as u32;
                    }
                    self.arena.leave(&gone, &mut self.active);
                } else {
                    k += 1;
                }
            }
            if self.active.is_empty() {
                self.segments.clear();
                self.order.clear();
                self.above.clear();
                self.pieces.clear();
                return self.next < self.entering.len();
            }
            self.stats.scan_lines += 1;

            // The active polygons' segments on this line, in X order.
            if self.sort_afresh {
                self.segments_afresh(y, width);
            } else {
                self.step_segments(y, width);
            }
            self.pieces.clear();
            if self.segments.is_empty() {
                std::mem::swap(&mut self.above, &mut self.pieces);
                return true;
            }
            self.stats.segments += self.segments.len() as u64;

            // The sample spans, left to right: cut at every segment end.
            let segments = &self.segments;
            let sweep = Sweep {
                segments,
                shadings: &self.shadings,
                above: &self.above,
                pieces: &mut self.pieces,
                candidates: &mut self.candidates,
                stats: &mut self.stats,
                out: RowRuns {
                    y,
                    open: None,
                    runs,
                },
            };
            if self.shadings.is_empty() {
                sweep.line::<false>(&mut self.present);
            } else {
                sweep.line::<true>(&mut self.present);
            }
            // This line's record of subdivisions predicts the next.
            if !self.sort_afresh {
                std::mem::swap(&mut self.above, &mut self.pieces);
            }
        }
        true
    }

    /// The pieces of the line [`Scanline::line`] last resolved, left to right: the
    /// stretches of columns where one polygon's segment was found in front (Watkins's
    /// visible segments, as they go to the shader).
    pub fn pieces(&self) -> &[Piece] {
        if self.sort_afresh {
            &self.pieces
        } else {
            &self.above
        }
    }
}

impl HiddenSurface for Scanline {
    fn resolve(&mut self, polygons: &[Polygon], width: u32, height: u32, runs: &mut Vec<Run>) {
        self.begin(polygons, height);
        for y in 0..height {
            if !self.line(polygons, y, width, height, runs) {
                break;
            }
        }
    }

    /// A Gouraud- or Phong-shaded polygon's visible spans take its colour at each pixel
    /// centre, as the z-buffer's do, lit by the stream's lighting.
    fn lighting(&mut self) -> Option<&mut Option<Arc<Lighting>>> {
        Some(&mut self.lighting)
    }

    fn stats(&self) -> String {
        let s = &self.stats;
        format!(
            "{} scan lines, {} segments, {} sample spans, {} segments examined, \
             {} depth comparisons, {} crossings; minor sort: {} segments merged in, \
             {} re-sorted, {} swaps; predicted from the line above: {} fronts held, \
             {} failed, {} crossings held, {} failed; {} midpoint subdivisions; \
             {} crossings computed (XINTER), {} of them searched",
            s.scan_lines,
            s.segments,
            s.sample_spans,
            s.segments_examined,
            s.depth_comparisons,
            s.crossings,
            s.merged,
            s.resorted,
            s.swaps,
            s.fronts_predicted,
            s.fronts_mispredicted,
            s.crossings_predicted,
            s.crossings_mispredicted,
            s.midpoint_subdivisions,
            s.crossings_computed,
            s.crossings_searched,
        )
    }

    fn counters(&self) -> Vec<(&'static str, String)> {
        let s = &self.stats;
        [
            ("scan_lines", s.scan_lines),
            ("segments", s.segments),
            ("sample_spans", s.sample_spans),
            ("segments_examined", s.segments_examined),
            ("depth_comparisons", s.depth_comparisons),
            ("crossings", s.crossings),
            ("merged", s.merged),
            ("resorted", s.resorted),
            ("swaps", s.swaps),
            ("fronts_predicted", s.fronts_predicted),
            ("fronts_mispredicted", s.fronts_mispredicted),
            ("crossings_predicted", s.crossings_predicted),
            ("crossings_mispredicted", s.crossings_mispredicted),
            ("midpoint_subdivisions", s.midpoint_subdivisions),
            ("crossings_computed", s.crossings_computed),
            ("crossings_searched", s.crossings_searched),
        ]
        .into_iter()
        .map(|(k, n)| (k, n.to_string()))
        .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::{differing_pixels, image_of, zbuffer_image};

    fn seg(z_row: f64, dz: f64, polygon: usize) -> Segment {
        Segment {
            x0: 0,
            x1: 1 << 20,
            z_row,
            dz,
            polygon,
            k: 0,
            colour: [0, 0, 0],
        }
    }

    /// The first column from `from` on (below `limit`) where `s` is in front, by testing
    /// every column.
    fn brute(s: &Segment, f: &Segment, from: u32, limit: u32) -> Option<u32> {
        (from..limit).find(|&x| s.in_front_of(f, x))
    }

    #[test]
    fn the_crossing_of_two_depth_lines() {
        // D(x) = 100 − 20x: zero at x = 5 exactly.
        let front = seg(0.0, 10.0, 0);
        let later = seg(100.0, -10.0, 1);
        // Later in the stream, it needs to be nearer: from column 6.
        assert_eq!(first_in_front(&later, &front, 0), Some(6));
        // Earlier in the stream, the tie at column 5 is already its.
        let earlier = seg(100.0, -10.0, 0);
        let front1 = seg(0.0, 10.0, 1);
        assert_eq!(first_in_front(&earlier, &front1, 0), Some(5));
        // Not before `from`.
        assert_eq!(first_in_front(&later, &front, 9), Some(9));
        // A crossing that is not at a whole column: D(x) = 7 − 3x, < 0 from x = 3.
        assert_eq!(
            first_in_front(&seg(7.0, 0.0, 1), &seg(0.0, 3.0, 0), 0),
            Some(3)
        );
        assert_eq!(
            first_in_front(&seg(7.0, 0.0, 0), &seg(0.0, 3.0, 1), 0),
            Some(3)
        );
        // Negative depths: D(x) = 10 − 2x, < 0 from x = 6; and s in front from the start.
        assert_eq!(
            first_in_front(&seg(-50.0, -3.0, 1), &seg(-60.0, -1.0, 0), 0),
            Some(6)
        );
        assert_eq!(
            first_in_front(&seg(-70.0, -1.0, 1), &seg(-60.0, 0.0, 0), 4),
            Some(4)
        );
    }

    #[test]
    fn parallel_or_diverging_lines_never_cross() {
        let front = seg(0.0, 10.0, 0);
        assert_eq!(first_in_front(&seg(1.0, 10.0, 1), &front, 0), None);
        assert_eq!(first_in_front(&seg(1.0, 11.0, 1), &front, 0), None);
        // Coincident: the later polygon never comes in front, the earlier is in front at once.
        assert_eq!(first_in_front(&seg(0.0, 10.0, 1), &front, 3), None);
        assert_eq!(
            first_in_front(&seg(0.0, 10.0, 0), &seg(0.0, 10.0, 1), 3),
            Some(3)
        );
    }

    #[test]
    fn within_the_tie_width_the_later_segment_never_comes_in_front() {
        // Reciprocal depths near yon, the later segment nearer by half the tie width
        // everywhere, then by twice it from column 1000 on.
        use proto::depth::TIE;
        let f = seg(-1e-6, 0.0, 0);
        assert_eq!(
            first_in_front(&seg(-1e-6 * (1.0 + 0.5 * TIE), 0.0, 1), &f, 0),
            None
        );
        let step = -1e-6 * TIE / 1000.0;
        let s = seg(-1e-6, step, 1);
        let c = first_in_front(&s, &f, 0).expect("crosses");
        assert!((1000..1003).contains(&c), "{c}");
        assert!(s.in_front_of(&f, c) && !s.in_front_of(&f, c - 1));
    }

    /// XINTER's X settles the column in at most four tests, without a search, on lines
    /// of every slope and depth (far beyond the pixel's width of columns, where a search
    /// would take log₂ of it), and agrees with testing every column.
    #[test]
    fn the_crossing_is_computed_in_four_tests_at_most() {
        for (z_s, dz_s, z_f, dz_f) in [
            (0.9, -0.001, 0.5, 0.0),
            (-0.2, 0.0, -0.9, 0.0007),
            (0.5 + 3e-6, -1e-9, 0.5, 1e-9),
            (1e6, -3.0, 2e5, 1.0),
        ] {
            for (p_s, p_f) in [(0, 1), (1, 0)] {
                let (mut s, mut f) = (seg(z_s, dz_s, p_s), seg(z_f, dz_f, p_f));
                s.x1 = 1 << 20;
                f.x1 = 1 << 20;
                let want = brute(&s, &f, 0, 1 << 20).expect("crosses");
                assert!(want > 1, "{s:?} {f:?}");
                let (c, tests, searched) = settle(&s, &f, 0, (1 << 20) - 1);
                assert_eq!((c, searched), (want, false), "{s:?} {f:?}");
                assert!(tests <= 4, "{tests}");
            }
        }
    }

    /// The search agrees with testing every column, for small lines of every kind.
    #[test]
    fn the_solve_agrees_with_every_column() {
        let values = [-40.0, -7.0, -3.0, -1.0, 0.0, 1.0, 2.0, 5.0, 13.0, 40.0];
        let steps = [-9.0, -4.0, -1.0, 0.0, 1.0, 3.0, 8.0];
        for &z1 in &values {
            for &d1 in &steps {
                for &z2 in &values {
                    for &d2 in &steps {
                        for (p1, p2) in [(0, 1), (1, 0)] {
                            let (mut s, mut f) = (seg(z1, d1, p1), seg(z2, d2, p2));
                            s.x1 = 200;
                            f.x1 = 200;
                            for from in [0, 1, 4] {
                                let got = first_in_front(&s, &f, from);
                                assert_eq!(got, brute(&s, &f, from, 200), "{s:?} {f:?} {from}");
                            }
                        }
                    }
                }
            }
        }
    }

    fn quad(colour: Colour, pts: [[f64; 3]; 4]) -> Polygon {
        Polygon::from_xyz(colour, &pts)
    }

    fn resolve(polygons: &[Polygon], w: u32, h: u32) -> (Vec<Run>, ScanlineStats) {
        let mut method = Scanline::new();
        let mut runs = vec![];
        method.resolve(polygons, w, h, &mut runs);
        (runs, method.stats)
    }

    fn run(y: u32, x0: u32, x1: u32, colour: Colour) -> Run {
        Run { y, x0, x1, colour }
    }

    const RED: Colour = [255, 0, 0];
    const GREEN: Colour = [0, 255, 0];
    const BLUE: Colour = [0, 0, 255];

    #[test]
    fn interpenetrating_planes_split_at_their_intersection() {
        // Red at depth 0.5; green slopes from 0.2 at X = 2 by 0.1 a column: at pixel
        // centres 2.5, 3.5, 4.5 it is nearer (0.25, 0.35, 0.45), at 5.5 farther (0.55).
        let red = quad(
            RED,
            [[0., 0., 0.5], [6., 0., 0.5], [6., 1., 0.5], [0., 1., 0.5]],
        );
        let green = quad(
            GREEN,
            [[2., 0., 0.2], [8., 0., 0.8], [8., 1., 0.8], [2., 1., 0.2]],
        );
        let (runs, stats) = resolve(&[red, green], 8, 1);
        assert_eq!(
            runs,
            vec![
                run(0, 0, 2, RED),
                run(0, 2, 5, GREEN),
                run(0, 5, 6, RED),
                run(0, 6, 8, GREEN)
            ]
        );
        assert_eq!(
            stats,
            ScanlineStats {
                scan_lines: 1,
                segments: 2,
                sample_spans: 3,
                segments_examined: 4,
                // At 2 green (coming in) against red (carried); red tested at 3 and at
                // 5 (in front there: a simple intersection), one test at 4, the only
                // column between;
                // the fold at 5, where green has no column left to come back in.
                depth_comparisons: 5,
                crossings: 1,
                merged: 2,
                crossings_computed: 1,
                ..ScanlineStats::default()
            }
        );
    }

    /// Where Watkins's simple cases miss a crossing: A is in front at the span's left end,
    /// B at its right end, and the two cross at column 32; a span decided by its two ends
    /// alone (14.4.1's "simple intersection") would paint A then B and miss C, which is in
    /// front of both in the middle. Two segments come in front of A inside the span, so
    /// it is subdivided (at the midpoint on the first line, at the line above's split on
    /// the next ones, which predict C's crossing exactly), and C shows where the z-buffer
    /// shows it.
    #[test]
    fn a_crossing_the_simple_cases_miss_is_found_by_subdivision() {
        const CYAN: Colour = [0, 255, 255];
        let a = quad(
            RED,
            [[0., 0., 0.2], [64., 0., 0.8], [64., 4., 0.8], [0., 4., 0.2]],
        );
        let b = quad(
            GREEN,
            [[0., 0., 0.8], [64., 0., 0.2], [64., 4., 0.2], [0., 4., 0.8]],
        );
        let c = quad(
            CYAN,
            [
                [0., 0., 0.45],
                [64., 0., 0.45],
                [64., 4., 0.45],
                [0., 4., 0.45],
            ],
        );
        let polygons = [a, b, c];
        // The crossing of A and B alone: the simple intersection.
        let seg = |p: &Polygon, i| {
            let (z_row, dz) = DepthPlane::of(p).row(0);
            Segment {
                x0: 0,
                x1: 64,
                z_row,
                dz,
                polygon: i,
                k: 0,
                colour: p.colour,
            }
        };
        let (sa, sb) = (seg(&polygons[0], 0), seg(&polygons[1], 1));
        assert_eq!(first_in_front(&sb, &sa, 0), Some(32));
        let (runs, stats) = resolve(&polygons, 64, 4);
        assert_eq!(image_of(&runs, 64, 4), zbuffer_image(&polygons, 64, 4));
        for y in 0..4 {
            assert_eq!(
                runs[3 * y as usize..3 * y as usize + 3],
                [
                    run(y, 0, 27, RED),
                    run(y, 27, 37, CYAN),
                    run(y, 37, 64, GREEN)
                ]
            );
        }
        // Line 0: cut at 32 (B and C in front there), 16 and 24 (neither), 28 (C alone:
        // a simple intersection, computed at 27). Lines 1-3: one cut each, at 27, where
        // line 0 changed from A to C, and C's crossing there verified.
        assert_eq!(stats.midpoint_subdivisions, 4 + 3);
        assert_eq!(stats.crossings_predicted, 3 + 3);
        assert_eq!(stats.crossings_mispredicted, 0);
        assert_eq!(stats.crossings, 2 * 4);
    }

    /// Where the coherence does not pay: 64 thin quads whose order along the line reverses
    /// from the top of the screen to the bottom, so that every pair changes places once.
    /// The minor sort does at least one exchange per pair (64·63/2 = 2,016), spread over
    /// the lines where they pass, and a few more where two passing segments' left ends,
    /// rounded to columns, meet and part again; the same quads side by side, not
    /// crossing, cost none. (A sort afresh costs the same whatever the order; Watkins's
    /// list costs what moved.)
    #[test]
    fn segments_that_all_change_places_cost_one_swap_a_pair() {
        let strips = |cross: bool| -> Vec<Polygon> {
            (0..64)
                .map(|i| {
                    let top = 4.0 * i as f64 + 0.25;
                    let bottom = if cross { 252.25 - 4.0 * i as f64 } else { top };
                    let z = 0.1 + 0.01 * i as f64;
                    quad(
                        [i as u8, 100, 200],
                        [
                            [top, 0., z],
                            [top + 1.5, 0., z],
                            [bottom + 1.5, 64., z],
                            [bottom, 64., z],
                        ],
                    )
                })
                .collect()
        };
        for (cross, swaps) in [(true, 2208), (false, 0)] {
            let polygons = strips(cross);
            let (runs, stats) = resolve(&polygons, 256, 64);
            assert_eq!(
                differing_pixels(
                    &image_of(&runs, 256, 64),
                    &zbuffer_image(&polygons, 256, 64)
                ),
                0
            );
            assert_eq!(stats.swaps, swaps, "cross {cross}: {stats:?}");
            assert_eq!(stats.merged, 64);
        }
    }

    #[test]
    fn a_tie_inside_a_span_goes_to_the_earlier_polygon() {
        // Red (earlier) flat at 0.5; green (later) z = 0.5 + (X − 4.5)/16, in front left of
        // column 4 and exactly as near at its centre 4.5: column 4 is red's, as in the
        // z-buffer, and the split falls there, not a column later.
        let red = quad(
            RED,
            [[0., 0., 0.5], [8., 0., 0.5], [8., 1., 0.5], [0., 1., 0.5]],
        );
        let z = |x: f64| 0.5 + (x - 4.5) / 16.0;
        let green = quad(
            GREEN,
            [
                [0., 0., z(0.)],
                [8., 0., z(8.)],
                [8., 1., z(8.)],
                [0., 1., z(0.)],
            ],
        );
        let (runs, stats) = resolve(&[red, green], 8, 1);
        assert_eq!(runs, vec![run(0, 0, 4, GREEN), run(0, 4, 8, RED)]);
        assert_eq!(stats.crossings, 1);
    }

    #[test]
    fn a_spanner_in_front_needs_no_split_and_ties_go_to_the_earlier() {
        // Blue in front of the whole span; red and green coincide behind it at one depth.
        let red = quad(
            RED,
            [[0., 0., 0.5], [4., 0., 0.5], [4., 2., 0.5], [0., 2., 0.5]],
        );
        let green = quad(
            GREEN,
            [[0., 0., 0.5], [4., 0., 0.5], [4., 2., 0.5], [0., 2., 0.5]],
        );
        let blue = quad(
            BLUE,
            [[1., 0., 0.1], [3., 0., 0.1], [3., 1., 0.1], [1., 1., 0.1]],
        );
        let (runs, stats) = resolve(&[red, green, blue], 4, 2);
        assert_eq!(
            runs,
            vec![
                run(0, 0, 1, RED),
                run(0, 1, 3, BLUE),
                run(0, 3, 4, RED),
                run(1, 0, 4, RED)
            ]
        );
        assert_eq!(stats.crossings, 0);
        assert_eq!(stats.sample_spans, 4);
    }

    #[test]
    fn coplanar_polygons_tie_and_the_earliest_shows() {
        // A decal: three polygons on one tilted plane, each fitted to its own vertices
        // (whose depths round differently), drawn red, green, blue: all red, as the
        // z-buffer draws it.
        let z = |x: f64, y: f64| -0.05 - 0.0013 * x - 0.0007 * y;
        let p = |x: f64, y: f64| [x, y, z(x, y)];
        let polygons = [
            Polygon::from_xyz(
                RED,
                &[p(0.3, 0.2), p(31.7, 0.4), p(31.1, 15.9), p(0.1, 15.6)],
            ),
            Polygon::from_xyz(GREEN, &[p(3.3, 2.2), p(20.7, 3.1), p(17.1, 12.9)]),
            Polygon::from_xyz(
                BLUE,
                &[p(10.1, 1.7), p(29.9, 8.3), p(12.2, 14.4), p(5.5, 9.0)],
            ),
        ];
        let (runs, _) = resolve(&polygons, 32, 16);
        assert_eq!(image_of(&runs, 32, 16), zbuffer_image(&polygons, 32, 16));
        assert!(runs.iter().all(|r| r.colour == RED), "{runs:?}");
    }

    #[test]
    fn empty_frames_and_degenerate_polygons_give_no_runs() {
        let (runs, _) = resolve(&[], 8, 8);
        assert!(runs.is_empty());
        let polygons = [
            Polygon::from_xyz(RED, &[]),
            Polygon::from_xyz(RED, &[[1., 1., 0.], [3., 3., 0.]]),
            Polygon::from_xyz(RED, &[[1., 1., 0.], [2., 2., 0.], [3., 3., 0.]]),
            Polygon::from_xyz(RED, &[[-5., -5., 0.], [-1., -5., 0.], [-1., -1., 0.]]),
            Polygon::from_xyz(RED, &[[1., 9., 0.], [3., 9., 0.], [3., 12., 0.]]),
            Polygon::from_xyz(RED, &[[f64::NAN, 1., 0.], [3., 1., 0.], [3., 3., 0.]]),
        ];
        let (runs, _) = resolve(&polygons, 8, 8);
        assert_eq!(image_of(&runs, 8, 8), zbuffer_image(&polygons, 8, 8));
        let (runs, _) = resolve(&polygons, 0, 0);
        assert!(runs.is_empty());
    }

    #[test]
    fn a_top_edge_a_hair_below_a_line_centre_is_drawn_on_that_line() {
        // Tops a hair below a line centre, snapped onto it (persp makes a scene's 14.5
        // into 14.500000000000002; 2.5 + 1/1024 is a quarter of a sub-pixel unit off):
        // a top edge holds the centres on it, so the line is drawn, as the z-buffer
        // draws it, down to the screen's last line. A top a hair above a line centre
        // stays above it too.
        let top = |y: f64, colour| {
            quad(
                colour,
                [
                    [1.25, y, 0.5],
                    [6.25, y, 0.5],
                    [6.25, 30.0, 0.5],
                    [1.25, 30.0, 0.5],
                ],
            )
        };
        let cases = [
            (14.500000000000002, 14),
            (2.5 + 1.0 / 1024.0, 2),
            (15.500000000000002, 15),
            (0.5 + 1.0 / 1024.0, 0),
            (3.4999999999999996, 3),
        ];
        for (y, line) in cases {
            let polygons = [top(y, RED)];
            let (runs, _) = resolve(&polygons, 8, 16);
            assert_eq!(runs.first(), Some(&run(line, 1, 6, RED)), "top at {y}");
            assert_eq!(runs.len(), 16 - line as usize, "top at {y}");
            assert_eq!(image_of(&runs, 8, 16), zbuffer_image(&polygons, 8, 16));
        }
        // A sliver whose apex lies one ulp below the line of its other two vertices,
        // exactly on a snapping tie: the two ends snap to the centre of line 0 (ties to
        // even), the apex just past it, so the sliver holds the centres of line 0 between
        // its ends.
        let y0 = 0.5 + 1.0 / 512.0;
        let sliver = Polygon::from_xyz(
            GREEN,
            &[
                [0.25, y0, 0.5],
                [6.25, y0, 0.5],
                [3.25, y0 + f64::EPSILON, 0.5],
            ],
        );
        let (runs, _) = resolve(std::slice::from_ref(&sliver), 8, 8);
        assert_eq!(runs, vec![run(0, 0, 6, GREEN)]);
    }

    #[test]
    fn frames_reuse_the_tables() {
        // Two frames through one method: the second is not disturbed by the first.
        let a = [quad(
            RED,
            [[0., 0., 0.5], [8., 0., 0.5], [8., 8., 0.5], [0., 8., 0.5]],
        )];
        let b = [quad(
            GREEN,
            [[2., 2., 0.5], [4., 2., 0.5], [4., 4., 0.5], [2., 4., 0.5]],
        )];
        let mut method = Scanline::new();
        let mut runs = vec![];
        method.resolve(&a, 8, 8, &mut runs);
        runs.clear();
        method.resolve(&b, 8, 8, &mut runs);
        assert_eq!(runs, vec![run(2, 2, 4, GREEN), run(3, 2, 4, GREEN)]);
        assert_eq!(method.stats.scan_lines, 10);
    }

    /// The shared edge table on a tall scene where polygons keep entering and leaving:
    /// 3,000 small triangles and quads down a 64×3000 screen, crossing one another. The
    /// blocks of those that left are reclaimed (the table is compacted whenever they
    /// pass half of it), so it never holds more than twice the edges active at once (plus
    /// the 1,024 it lets lie); the picture is the z-buffer's.
    #[test]
    fn the_shared_edge_table_stays_as_small_as_the_active_edges() {
        let mut next = crate::frame::pseudo_random(0x9e37_79b9_7f4a_7c15u64);
        let (w, h) = (64u32, 3000u32);
        let polygons: Vec<Polygon> = (0..3000)
            .map(|i| {
                let (cx, cy) = (next() * 64.0, i as f64 + next() * 4.0);
                let n = 3 + (i % 2);
                let pts: Vec<[f64; 3]> = (0..n)
                    .map(|_| [cx + next() * 30.0 - 15.0, cy + next() * 12.0 - 6.0, next()])
                    .collect();
                Polygon::from_xyz([i as u8, (i >> 8) as u8, 7], &pts)
            })
            .collect();
        let mut method = Scanline::new();
        let mut runs = Vec::new();
        method.resolve(&polygons, w, h, &mut runs);
        assert_eq!(
            differing_pixels(&image_of(&runs, w, h), &zbuffer_image(&polygons, w, h)),
            0
        );
        // About 3 polygons start a line and each spans ~12: ~40 active, ~140 edges; the
        // table after 3,000 polygons' blocks is bounded by the active ones, not the frame.
        let held = method.arena.edges.len();
        assert!(held <= 2 * 4 * 60 + 1024 + 8, "{held}");
        // (Measured: 413 held, capacity 2,048, of the frame's ~10,500 edges.)
        let capacity = method.arena.edges.capacity();
        assert!(capacity <= 4096, "{capacity}");
    }

    #[test]
    fn a_nearer_copy_wins_only_where_depth_nears_zero_as_the_fold_gives() {
        let polygons = crate::frame::nearer_copy_through_depth_zero();
        let (w, h) = (68, 68);
        let zbuffer = zbuffer_image(&polygons, w, h);
        // The copy shows in a band, the first quad on both sides of it on one row.
        let row: Vec<_> = (0..w).map(|x| zbuffer[(60 * w + x) as usize]).collect();
        let copy = Some([127, 79, 235]);
        let band: Vec<u32> = (0..w).filter(|&x| row[x as usize] == copy).collect();
        assert!(
            !band.is_empty() && band[0] > 0 && *band.last().unwrap() < w - 1,
            "{row:?}"
        );
        let (runs, _) = resolve(&polygons, w, h);
        assert_eq!(differing_pixels(&image_of(&runs, w, h), &zbuffer), 0);
        // The line is cut where the depth changes sign, once.
        let (z_row, dz) = crate::DepthPlane::of(&polygons[0]).row(60);
        let cut = sign_change(z_row, dz, 0..w).unwrap();
        assert!(
            crate::depth_at(z_row, dz, cut - 1) >= 0.0 && crate::depth_at(z_row, dz, cut) < 0.0
        );
        assert_eq!(sign_change(z_row, dz, 0..cut), None);
    }

    /// A pseudo-random scene larger than the property tests': many overlapping,
    /// interpenetrating triangles and quads on a screen wider than a region tile.
    #[test]
    fn a_larger_random_scene_is_the_zbuffers() {
        let mut next = crate::frame::pseudo_random(0x2545_f491_4f6c_dd1du64);
        let (w, h) = (200u32, 150u32);
        let polygons: Vec<Polygon> = (0..600)
            .map(|i| {
                let (cx, cy) = (next() * 220.0 - 10.0, next() * 170.0 - 10.0);
                let n = 3 + (i % 3);
                let pts: Vec<[f64; 3]> = (0..n)
                    .map(|_| [cx + next() * 40.0 - 20.0, cy + next() * 40.0 - 20.0, next()])
                    .collect();
                Polygon::from_xyz([i as u8, (i >> 8) as u8, 9], &pts)
            })
            .collect();
        let (runs, stats) = resolve(&polygons, w, h);
        assert_eq!(
            differing_pixels(&image_of(&runs, w, h), &zbuffer_image(&polygons, w, h)),
            0
        );
        assert!(stats.crossings > 100, "{stats:?}");
    }
    /// Gouraud-shaded polygons among flat ones: every visible pixel of a shaded polygon is
    /// its colour planes' value at the centre, the z-buffer's byte for byte, and a row's
    /// runs of one colour are joined.
    #[test]
    fn shaded_polygons_are_drawn_as_the_zbuffer_shades_them() {
        let mut next = crate::frame::pseudo_random(0x9e37_79b9_7f4a_7c15u64);
        let (w, h) = (150u32, 100u32);
        let polygons: Vec<Polygon> = (0..120)
            .map(|i| {
                let (cx, cy) = (next() * 170.0 - 10.0, next() * 120.0 - 10.0);
                let n = 3 + (i % 2);
                let pts: Vec<[f64; 3]> = (0..n)
                    .map(|_| [cx + next() * 50.0 - 25.0, cy + next() * 50.0 - 25.0, next()])
                    .collect();
                let mut p = Polygon::from_xyz([i as u8, 7, 9], &pts);
                if i % 3 != 0 {
                    p.vertex_attrs = (0..n)
                        .map(|_| proto::DVec3::new(next(), next(), next()) * 255.0)
                        .collect();
                }
                p
            })
            .collect();
        let (runs, _) = resolve(&polygons, w, h);
        let image = image_of(&runs, w, h);
        assert_eq!(differing_pixels(&image, &zbuffer_image(&polygons, w, h)), 0);
        // Far more colours than polygons: the shaded ones are smooth.
        let colours: std::collections::HashSet<_> = image.iter().flatten().collect();
        assert!(colours.len() > 2000, "{} colours", colours.len());
        assert_eq!(crate::frame::unjoined_runs(&runs), None);
    }
}

/// Property tests: the scan-line picture is the z-buffer's on random polygon sets.
#[cfg(test)]
mod properties {
    use super::*;
    use crate::frame::{differing_pixels, image_of, zbuffer_image};
    use proptest::prelude::*;
    use proto::{DVec4, Vertex};

    /// 70×40: wider than a region tile (64), so the z-buffer's tiles are crossed too.
    const W: u32 = 70;
    const H: u32 = 40;

    /// A shape drawn from raw numbers in 0..1 (shrinks well).
    #[derive(Clone, Debug)]
    struct Shape {
        kind: u8,
        points: Vec<(f64, f64, f64)>,
        cut: f64,
    }

    fn shape() -> impl Strategy<Value = Shape> {
        (
            0u8..10,
            prop::collection::vec((0.0f64..1.0, 0.0f64..1.0, 0.0f64..1.0), 3..8),
            0.0f64..1.0,
        )
            .prop_map(|(kind, points, cut)| Shape { kind, points, cut })
    }

    /// Splits `p` at X = k the way the splitter cuts (Sutherland–Hodgman): a piece of a
    /// cut edge carries the whole edge as its support, the edges along the cut none, and
    /// both pieces the whole polygon's plane. `None` unless both pieces have an area.
    fn cut(p: &Polygon, k: f64) -> Option<[Polygon; 2]> {
        let n = p.vertices.len();
        let plane = proto::geometry::newell_plane(
            &p.vertices.iter().map(|v| v.truncate()).collect::<Vec<_>>(),
        );
        let piece = |left: bool| {
            let inside = |v: &Vertex| (v.x < k) == left;
            let mut out = Polygon::new(p.colour, vec![]);
            out.plane = Some(plane);
            for i in 0..n {
                let (a, b) = (p.vertices[i], p.vertices[(i + 1) % n]);
                let at = |a: Vertex, b: Vertex| {
                    let t = (k - a.x) / (b.x - a.x);
                    let mut v = a + (b - a) * t;
                    v.x = k;
                    v
                };
                match (inside(&a), inside(&b)) {
                    (true, true) => {
                        out.vertices.push(a);
                        out.supports.push(None);
                    }
                    (true, false) => {
                        out.vertices.push(a);
                        out.supports.push(Some([a, b]));
                        out.vertices.push(at(a, b));
                        out.supports.push(None);
                    }
                    (false, true) => {
                        out.vertices.push(at(a, b));
                        out.supports.push(Some([a, b]));
                    }
                    (false, false) => {}
                }
            }
            out
        };
        let (l, r) = (piece(true), piece(false));
        (l.vertices.len() >= 3 && r.vertices.len() >= 3).then_some([l, r])
    }

    /// The polygons of a scene: each shape in a colour of its own (so that which polygon
    /// wins a tie shows in the picture), some shapes becoming two polygons.
    fn scene(shapes: &[Shape]) -> Vec<Polygon> {
        let (w, h) = (W as f64, H as f64);
        let mut out: Vec<Polygon> = vec![];
        for (i, s) in shapes.iter().enumerate() {
            let colour = [(i * 37) as u8, (i * 91 + 11) as u8, i as u8];
            let free = |x: f64, y: f64| (x * (w + 10.0) - 5.0, y * (h + 10.0) - 5.0);
            let pts: Vec<[f64; 3]> = match s.kind {
                // Free polygons: convex, concave or self-crossing (bowties), their planes
                // tilted every way, so they interpenetrate.
                0 | 1 => s
                    .points
                    .iter()
                    .map(|&(x, y, z)| {
                        let (x, y) = free(x, y);
                        [x, y, z]
                    })
                    .collect(),
                // On a half-pixel grid with depths in eighths: vertices on pixel centres,
                // shared edges, horizontal edges, equal depths.
                2 => s
                    .points
                    .iter()
                    .map(|&(x, y, z)| {
                        let (x, y) = free(x, y);
                        [
                            (x * 2.0).round() / 2.0,
                            (y * 2.0).round() / 2.0,
                            (z * 8.0).round() / 8.0,
                        ]
                    })
                    .collect(),
                // A polygon coincident with the one before (same vertices, another colour).
                3 if !out.is_empty() => {
                    let mut p = out[out.len() - 1].clone();
                    p.colour = colour;
                    out.push(p);
                    continue;
                }
                // A sliver: a long triangle a hundredth of a pixel wide.
                3 | 4 => {
                    let (x0, y0) = free(s.points[0].0, s.points[0].1);
                    let (x1, y1) = free(s.points[1].0, s.points[1].1);
                    let (z0, z1) = (s.points[0].2, s.points[1].2);
                    vec![[x0, y0, z0], [x1, y1, z1], [x1 + 0.01, y1 + 0.013, z1]]
                }
                // Big coordinates, up to 15 screens out (inside the guard band).
                5 => s
                    .points
                    .iter()
                    .map(|&(x, y, z)| [(x - 0.5) * 30.0 * w, (y - 0.5) * 30.0 * h, z])
                    .collect(),
                // Near-equal depths: planes within a few fixed-point units of 0.5.
                6 => s
                    .points
                    .iter()
                    .map(|&(x, y, z)| {
                        let (x, y) = free(x, y);
                        [x, y, 0.5 + (z - 0.5) * 4e-12]
                    })
                    .collect(),
                // Steep depths: in fixed point they reach past the i64 range.
                7 => s
                    .points
                    .iter()
                    .map(|&(x, y, z)| {
                        let (x, y) = free(x, y);
                        [x, y, (z - 0.5) * 4e7]
                    })
                    .collect(),
                // Dyadic planes over integer vertices: depths exact in fixed point, so two
                // planes often meet exactly at a pixel centre (a tie inside a span).
                8 => {
                    let k = |v: f64| (v * 9.0).floor() - 4.0;
                    let (k0, kx, ky) = (k(s.cut), k(s.points[0].2), k(s.points[1].2));
                    s.points
                        .iter()
                        .map(|&(x, y, _)| {
                            let (x, y) = free(x, y);
                            let (x, y) = (x.round(), y.round());
                            [x, y, 0.5 + (k0 + kx * x + ky * y) / 256.0]
                        })
                        .collect()
                }
                // A free polygon cut in two at X = k by the splitter's rule.
                _ => {
                    let pts: Vec<[f64; 3]> = s
                        .points
                        .iter()
                        .map(|&(x, y, z)| {
                            let (x, y) = free(x, y);
                            [x, y, z]
                        })
                        .collect();
                    let whole = Polygon::from_xyz(colour, &pts);
                    match cut(&whole, s.cut * w) {
                        Some(pieces) => out.extend(pieces),
                        None => out.push(whole),
                    }
                    continue;
                }
            };
            out.push(Polygon::from_xyz(colour, &pts));
        }
        out
    }

    /// Mostly numbers on and near a 16×8 screen, sometimes anything at all.
    fn num() -> impl Strategy<Value = f64> {
        prop_oneof![
            6 => -8.0f64..24.0,
            1 => Just(f64::NAN),
            1 => Just(f64::INFINITY),
            1 => Just(f64::NEG_INFINITY),
            1 => Just(1e300),
            1 => Just(-1e-300),
            1 => Just(0.0),
            2 => prop::num::f64::ANY,
        ]
    }

    fn check(polygons: &[Polygon], w: u32, h: u32) -> Result<(), TestCaseError> {
        let mut method = Scanline::new();
        let mut runs = vec![];
        method.resolve(polygons, w, h, &mut runs);
        let want = zbuffer_image(polygons, w, h);
        // Without the coherence: the same runs.
        let mut afresh = Scanline {
            sort_afresh: true,
            ..Scanline::new()
        };
        let mut runs_afresh = vec![];
        afresh.resolve(polygons, w, h, &mut runs_afresh);
        prop_assert_eq!(&runs_afresh, &runs);
        prop_assert_eq!(differing_pixels(&image_of(&runs, w, h), &want), 0);
        // Runs are in row order, left to right, and as long as they can be.
        for pair in runs.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            prop_assert!((a.y, a.x1) <= (b.y, b.x0), "{:?} then {:?}", a, b);
            prop_assert!(a.y != b.y || a.x1 != b.x0 || a.colour != b.colour);
        }
        Ok(())
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        /// Overlapping, interpenetrating, coincident, concave and self-crossing polygons,
        /// slivers, split pieces with supports, big coordinates, near-equal and clamped
        /// depths: the scan-line picture is the z-buffer's to the pixel.
        #[test]
        fn the_picture_is_the_zbuffers(shapes in prop::collection::vec(shape(), 1..14)) {
            check(&scene(&shapes), W, H)?;
        }

        /// Any numbers at all (infinite, NaN, huge, subnormal), and recorded planes of any
        /// numbers: no panic, and still the z-buffer's picture.
        #[test]
        fn any_numbers_are_the_zbuffers(
            polys in prop::collection::vec(
                (
                    prop::collection::vec(
                        (num(), num(), num()),
                        0..6,
                    ),
                    prop::option::of((num(), num(), num(), num())),
                ),
                1..6,
            ),
        ) {
            let polygons: Vec<Polygon> = polys
                .iter()
                .enumerate()
                .map(|(i, (pts, plane))| {
                    let pts: Vec<[f64; 3]> = pts.iter().map(|&(x, y, z)| [x, y, z]).collect();
                    let mut p = Polygon::from_xyz([i as u8, 1, 2], &pts);
                    p.plane = plane.map(|(a, b, c, d)| DVec4::new(a, b, c, d));
                    p
                })
                .collect();
            check(&polygons, 16, 8)?;
        }

        /// Many polygons piled on one spot: deep sample spans, many crossings per line.
        #[test]
        fn deep_piles_are_the_zbuffers(
            depths in prop::collection::vec((0.0f64..1.0, 0.0f64..1.0, 0.0f64..1.0), 2..40),
        ) {
            let polygons: Vec<Polygon> = depths
                .iter()
                .enumerate()
                .map(|(i, &(a, b, c))| {
                    let mut p = if i % 2 == 0 {
                        Polygon::from_xyz(
                            [i as u8, 0, 1],
                            &[[2.0, 1.0, a], [30.0, 1.5, b], [29.0, 15.0, c], [1.0, 14.0, a]],
                        )
                    } else {
                        // A dyadic plane: exact in fixed point, so planes meet exactly at
                        // pixel centres and ties fall inside sample spans.
                        let k = |v: f64| (v * 9.0).floor() - 4.0;
                        let z = |x: f64, y: f64| 0.5 + (k(a) + k(b) * x + k(c) * y) / 256.0;
                        Polygon::from_xyz(
                            [i as u8, 0, 1],
                            &[[1.0, 1.0, z(1.0, 1.0)], [31.0, 1.0, z(31.0, 1.0)],
                              [31.0, 15.0, z(31.0, 15.0)], [1.0, 15.0, z(1.0, 15.0)]],
                        )
                    };
                    if i % 5 == 4 {
                        p.plane = Some(DVec4::new(a - 0.5, b - 0.5, 1.0, -c));
                    }
                    p
                })
                .collect();
            check(&polygons, 32, 16)?;
        }
    }
}
