//! # scanline: Watkins's scan-line hidden-surface algorithm
//!
//! After Watkins's algorithm as Archuleta describes it (Archuleta (1972), "Watkins'
//! Algorithm" and the listing of HIDDEN) and as Newman and Sproull's chapter 14.4 explains
//! it (Newman and Sproull 1973, 14.4.1 "Processing a scan-line", 14.4.2 "Scan-line coherence"). A
//! frame is resolved one scan line at a time, top to bottom, with no depth buffer:
//!
//! 1. **Active polygons.** The frame's polygons are sorted by the first scan line they
//!    can reach (Archuleta's "sorted with respect to Y" preframe processing). A polygon
//!    enters the active list at that line and leaves it after its last. Each active
//!    polygon keeps its own [`scan::SpanWalker`] (its Edge Table and Active Edge Table),
//!    stepped one line at a time and never rebuilt: Archuleta's "after a scan line has
//!    been completed, all segments are updated to the next scan line".
//! 2. **Segments.** On each line, an active polygon's crossings, paired by the even-odd
//!    rule, give its *segments* (14.4: "the intersection of the scan-line window and a
//!    planar polygon"): the columns whose pixel centres it covers, exactly the spans the
//!    z-buffer draws (docs/DESIGN.md, "Leaves resolve visibility"), each with the
//!    polygon's depth plane on the line (`z_row`, `dz`) and its stream index.
//! 3. **Sample spans.** The line is cut at every segment end into *sample spans*, inside
//!    which the set of segments does not change. A sample span with one segment is that
//!    segment's (14.4.1, simple case 1); a span with none is background.
//! 4. **Depth only where segments overlap.** In a sample span with several segments the
//!    front one at its left end is found by folding their depths there in stream order
//!    with the tie rule (docs/DESIGN.md, "The Z specification": a later polygon takes the
//!    pixel only when nearer by more than 2⁻³⁰ of the holder's depth). Then, instead of
//!    subdividing at midpoints, the first column where another segment comes in front is
//!    found on the two depth lines ([`first_in_front`]; Archuleta's XINTER, "the X point
//!    of intersection"): the rule between two planar depths changes its answer once at
//!    most along a line, so a binary search over the columns, each decided by the
//!    z-buffer's own arithmetic, finds exactly the column where the z-buffer's answer
//!    changes. The span is split there (14.4.1 case 3, "simple intersection", and Figure
//!    14-33's non-recursive subdivision: process the left part, then go on with the
//!    remainder), and the search goes on from that column. A spanner in front of all the
//!    others (case 2) needs no split at all. The front segment and the column up to
//!    which it holds are carried from one sample span to the next: while it stays, a
//!    segment coming in is compared with it alone, and the whole span is looked at again
//!    only where the front leaves or may be overtaken. The active polygons' segments are
//!    sorted afresh on each line (see the note in [`Scanline`]'s resolve on Watkins's
//!    "minor sorting").
//!
//! Depths are [`scan::depth_at`]'s, the z-buffer's, so the result is the z-buffer's
//! picture to the pixel ([`scan::frame::zbuffer_image`]). (Where three or more polygons
//! lie within two tie widths of one another at a pixel without all tying, the front
//! carried along the line is compared pairwise, which can differ from the fold; the
//! front is found afresh by the fold at every split, so only such a pixel can differ.)
//!
//! The counters Watkins's timings are about (14.4.3: the computation "grows roughly as the
//! *visible* complexity") are kept in [`ScanlineStats`].

use proto::raster::centres_in_clamped;
use proto::{Colour, Polygon};
use scan::frame::HiddenSurface;
use scan::{depth_at, Depth, DepthPlane, Run, SpanWalker};
use std::ops::Range;

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

/// The first column `c ≥ from` at which `s` is in front of `front` ([`Segment::in_front_of`])
/// while both are on the line, or `None` — Archuleta's XINTER, "the X point of
/// intersection", rounded to the pixel centres the z-buffer samples. Both depths are
/// linear in x, so the answer changes at most once along their overlap: a binary search
/// on the z-buffer's own test finds the column where it does.
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
    // Not in front at `lo`, in front at `hi`.
    let (mut lo, mut hi) = (from, last);
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if s.in_front_of(front, mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(hi)
}

/// An active polygon: the walker holding its edge tables, stepped line by line.
struct ActivePolygon {
    polygon: usize,
    colour: Colour,
    /// The lines its edges cross (from [`SpanWalker::start`]).
    rows: Range<i64>,
    depth: DepthPlane,
    walker: SpanWalker,
}

/// Watkins's scan-line method as a [`HiddenSurface`]. Its tables (walkers, lists) are
/// kept from frame to frame.
#[derive(Default)]
pub struct Scanline {
    /// The frame's polygons by the first line they may reach: (line, stream index).
    entering: Vec<(i64, usize)>,
    active: Vec<ActivePolygon>,
    /// Walkers of polygons that have left, for the next to enter.
    pool: Vec<SpanWalker>,
    /// The current line's segments, sorted by left end.
    segments: Vec<Segment>,
    /// Indices into `segments` of those in the current sample span.
    present: Vec<usize>,
    pub stats: ScanlineStats,
}

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
        if scan::takes(segments[i].depth(x), segments[front].depth(x)) {
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

/// The first column from `from` on where a segment of `present` comes in front of
/// `front` (`u32::MAX` if none): one crossing solve for each.
fn overtaken_at(
    segments: &[Segment],
    present: &[usize],
    front: usize,
    from: u32,
    stats: &mut ScanlineStats,
) -> u32 {
    let f = &segments[front];
    let mut until = u32::MAX;
    for &i in present {
        if i != front {
            stats.depth_comparisons += 1;
            if let Some(c) = first_in_front(&segments[i], f, from) {
                until = until.min(c);
            }
        }
    }
    until
}

/// Finds the front segment at column x afresh and the first column where another comes
/// in front of it: Archuleta's "depth processing" of every segment in the span.
fn front_afresh(
    segments: &[Segment],
    present: &[usize],
    x: u32,
    stats: &mut ScanlineStats,
) -> Front {
    let segment = front_at(segments, present, x, &mut stats.depth_comparisons);
    Front {
        segment,
        until: overtaken_at(segments, present, segment, x + 1, stats),
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

/// Decides a sample span (14.4.1), carrying `front` along the line.
///
/// Depth is compared only where segments overlap, and only as much as the last span left
/// undecided: while the front segment stays, a segment coming in is compared with it
/// alone (at `a`, and by one crossing solve); everything is looked at again only where
/// the front leaves or may be overtaken (Watkins's coherence along a scan line).
fn sample_span(
    segments: &[Segment],
    span: SampleSpan,
    front: &mut Option<Front>,
    stats: &mut ScanlineStats,
    out: &mut RowRuns,
) {
    let SampleSpan {
        present,
        entering,
        a,
        b,
    } = span;
    stats.sample_spans += 1;
    stats.segments_examined += present.len() as u64;
    if let [only] = present {
        // Case 1: one segment, visible across the span.
        out.paint(a, b, segments[*only].colour);
        *front = Some(Front {
            segment: *only,
            until: u32::MAX,
        });
        return;
    }
    // Cases 2 and 3: the front segment holds until the first column where another comes
    // in front of it; split there (Archuleta's XINTER) and go on from that column.
    let mut f = match *front {
        // The front is still here and nothing overtakes it at `a`: it is in front of every
        // segment that was here before, so only those coming in need looking at.
        Some(f) if segments[f.segment].x1 > a && f.until > a => {
            let mut best = f.segment;
            for &e in &present[entering..] {
                stats.depth_comparisons += 1;
                if segments[e].in_front_of(&segments[best], a) {
                    best = e;
                }
            }
            if best == f.segment {
                let until = overtaken_at(segments, &present[entering..], best, a + 1, stats);
                Front {
                    segment: best,
                    until: f.until.min(until),
                }
            } else {
                // A segment comes in in front: every other is solved against it.
                Front {
                    segment: best,
                    until: overtaken_at(segments, present, best, a + 1, stats),
                }
            }
        }
        _ => front_afresh(segments, present, a, stats),
    };
    let mut x = a;
    loop {
        let split = f.until.min(b);
        out.paint(x, split, segments[f.segment].colour);
        if split >= b {
            break;
        }
        x = split;
        let next = front_afresh(segments, present, x, stats);
        if next.segment != f.segment {
            stats.crossings += 1;
        }
        f = next;
    }
    *front = Some(f);
}

impl HiddenSurface for Scanline {
    fn resolve(&mut self, polygons: &[Polygon], width: u32, height: u32, runs: &mut Vec<Run>) {
        // Preframe processing: the polygons sorted by the first line they may reach (a
        // line whose centre is at or below their top vertex). The walker finds the exact
        // lines when the polygon enters.
        self.entering.clear();
        for (i, p) in polygons.iter().enumerate() {
            if p.vertices.len() < 3 {
                continue;
            }
            let top = p.vertices.iter().map(|v| v.y).fold(f64::INFINITY, f64::min);
            // Saturating: NaN gives 0, −∞ gives i64::MIN.
            let first = ((top - 0.5).ceil() as i64).max(0);
            if first < height as i64 {
                self.entering.push((first, i));
            }
        }
        // Stable, so polygons entering together keep their stream order.
        self.entering.sort_by_key(|&(line, _)| line);
        for a in self.active.drain(..) {
            self.pool.push(a.walker);
        }

        let mut next = 0;
        for y in 0..height {
            let line = y as i64;
            // Polygons entering on this line.
            while next < self.entering.len() && self.entering[next].0 <= line {
                let i = self.entering[next].1;
                next += 1;
                let p = &polygons[i];
                let mut walker = self.pool.pop().unwrap_or_default();
                let rows = walker.start(p, height);
                if rows.is_empty() {
                    self.pool.push(walker);
                    continue;
                }
                // The walker's first line is never above the one found from the top vertex;
                // should rounding ever say otherwise, its tables still step every line.
                for skipped in rows.start..line {
                    walker.crossings(skipped);
                }
                self.active.push(ActivePolygon {
                    polygon: i,
                    colour: p.colour,
                    rows,
                    depth: DepthPlane::of(p),
                    walker,
                });
            }
            // Polygons past their last line leave.
            let mut k = 0;
            while k < self.active.len() {
                if self.active[k].rows.end <= line {
                    let gone = self.active.swap_remove(k);
                    self.pool.push(gone.walker);
                } else {
                    k += 1;
                }
            }
            if self.active.is_empty() {
                if next == self.entering.len() {
                    break;
                }
                continue;
            }
            self.stats.scan_lines += 1;

            // The active polygons' segments on this line, stepping each one's edges.
            self.segments.clear();
            for a in &mut self.active {
                if line < a.rows.start {
                    continue;
                }
                let (z_row, dz) = a.depth.row(y);
                for pair in a.walker.crossings(line).chunks_exact(2) {
                    let cols = centres_in_clamped(pair[0], pair[1], width);
                    if cols.is_empty() {
                        continue;
                    }
                    self.segments.push(Segment {
                        x0: cols.start,
                        x1: cols.end,
                        z_row,
                        dz,
                        polygon: a.polygon,
                        colour: a.colour,
                    });
                }
            }
            if self.segments.is_empty() {
                continue;
            }
            self.stats.segments += self.segments.len() as u64;
            // Watkins's list is kept in X order from line to line with "some minor sorting"
            // (Archuleta (1972), HIDDEN); here the line's segments are sorted afresh. Keeping the
            // active list in the last line's X order so that they came out nearly sorted
            // measured slower (moving the active polygons costs more than the sort saves).
            self.segments.sort_unstable_by_key(|s| (s.x0, s.polygon));

            // The sample spans, left to right: cut at every segment end.
            let mut out = RowRuns {
                y,
                open: None,
                runs,
            };
            let segments = &self.segments;
            let present = &mut self.present;
            present.clear();
            let mut entered = 0;
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
                sample_span(segments, span, &mut front, &mut self.stats, &mut out);
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
            out.finish();
        }
    }

    fn stats(&self) -> String {
        let s = &self.stats;
        format!(
            "{} scan lines, {} segments, {} sample spans, {} segments examined, \
             {} depth comparisons, {} crossings",
            s.scan_lines,
            s.segments,
            s.sample_spans,
            s.segments_examined,
            s.depth_comparisons,
            s.crossings
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use scan::frame::{differing_pixels, image_of, zbuffer_image};

    fn seg(z_row: f64, dz: f64, polygon: usize) -> Segment {
        Segment {
            x0: 0,
            x1: 1 << 20,
            z_row,
            dz,
            polygon,
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
                // front at 2, solve, front at 5, solve
                depth_comparisons: 4,
                crossings: 1,
            }
        );
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

    /// A pseudo-random scene larger than the property tests': many overlapping,
    /// interpenetrating triangles and quads on a screen wider than a region tile.
    #[test]
    fn a_larger_random_scene_is_the_zbuffers() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
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
}

/// Property tests: the scan-line picture is the z-buffer's on random polygon sets.
#[cfg(test)]
mod properties {
    use super::*;
    use proptest::prelude::*;
    use proto::{DVec4, Vertex};
    use scan::frame::{differing_pixels, image_of, zbuffer_image};

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
