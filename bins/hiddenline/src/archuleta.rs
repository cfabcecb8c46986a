//! # Archuleta's own method: counters on Watkins's scan-line segments
//!
//! Archuleta (1972, "Hidden surface line drawing algorithm", LINE DRAWING ALGORITHM)
//! draws lines from what Watkins's scan-line algorithm already knows. Each segment (the
//! piece of a polygon between its left and right edge on a scan line) has a segment block
//! with a counter for each of its two edges: "every time the hidden surface algorithm
//! passes a visible segment over to the shader, a counter in the segment block is
//! incremented for the left or right edge", and "the first time that an edge becomes
//! visible, the starting point of the edge is stored". A line is drawn in two cases: "if
//! the edge is exiting on this scan line, then draw. If the edge was visible on the
//! previous scan line and not this scan line, then draw." So the vectors are found a scan
//! line at a time and their ends lie between scan lines, at the raster's resolution.
//!
//! Here, per scan line (the screen's rows, the centre of row r at Y = r + 0.5):
//!
//! - **Visibility along the line**: Watkins's own scan ([`scan::watkins`], the
//!   `scanline` stage's method, not a depth buffer): the active polygons' segments in X
//!   order, cut into sample spans, depth compared only where segments overlap, split
//!   where one comes in front (XINTER). Its visible segments, the stretches of the line
//!   where one polygon is in front, are what it would pass to the shader; here they give
//!   each column of the row the polygon in front at its pixel centre (the z-buffer's
//!   picture, to the pixel).
//! - **The counters**: an edge crossing the row's centre at X is visible on this line
//!   (its counter incremented, as when a visible segment that it bounds goes to the
//!   shader) unless the visible segment at X's column is another polygon's that holds
//!   (X, Y) strictly inside and is nearer there than the edge; an edge's own polygons, and those it is shared with,
//!   never hide it (one block per edge of the model: a shared edge has one counter, so
//!   it is drawn once). A run of visible lines is drawn from where it started (the
//!   edge's top vertex, or the boundary between lines where it became visible) to where
//!   it stopped (the boundary, or its bottom vertex when it exits).
//! - **Horizontal edges**, which cross no line's centre: Archuleta's rule, "visible on
//!   the current scan line to which they really belong, and possibly on the previous
//!   scan line": the parts of the edge over columns where one of its own polygons is in
//!   front on the line below or above it.
//! - **Lines of intersection** (his second problem): where the front changes from one
//!   polygon to another between two columns that both polygons cover, there is no edge,
//!   only the line where their planes meet. Archuleta names two cures, a dot there, or
//!   "a segment block which contains similar edge information, and then process the
//!   line"; this is the second: a block per pair of polygons, kept while the crossing is
//!   seen on consecutive lines and drawn when it is not.
//! - **The screen**: the scan lines are its rows and their samples its pixels, so every
//!   vector is cut to it; a piece of an edge off the screen (a stream may reach past it,
//!   within scan's guard band) has no sample and is not drawn.
//!
//! His first problem (a line drawn to the boundary between scan lines extends a little
//! over an edge that crossed it there) and his third (visibility changes only at the
//! resolution of the scan lines) are kept, as he describes them: docs/methods.md shows
//! them beside the continuous drawing. The cost is linear in the scan lines (his "Computation
//! time will increase linearly") and in the segments on them; memory is the frame's
//! polygons, their edges and two rows of the screen.

use super::{edge_key, is_pipeline_cut, shares_vertex, Face, LineStats, Segment};
use proto::{Colour, DVec2, Polygon};
use std::collections::HashMap;

/// No polygon at a column.
const NONE: u32 = u32::MAX;

/// An edge of the model and its segment block: the counter and the stored start of the
/// run of lines on which it is visible.
struct Edge {
    /// Its ends, top (smaller Y) first, and their depths.
    top: DVec2,
    bottom: DVec2,
    ztop: f64,
    zbottom: f64,
    /// Its polygons (places in ZMIN order), `owners[o0..o1]`, sorted.
    o0: u32,
    o1: u32,
    /// The stream index of its first polygon: a hider must be earlier to win a tie.
    tie: usize,
    /// The rows whose centres it crosses (`first > last`: none, a horizontal edge).
    first: i64,
    last: i64,
    /// Where the current run of visible lines began, and where it has reached.
    start: Option<DVec2>,
    end: DVec2,
    colour: Colour,
    /// The colour of its first polygon in the stream.
    base: Colour,
}

impl Edge {
    /// The point of the edge at height `y` (clamped to the edge).
    fn at(&self, y: f64) -> DVec2 {
        let dy = self.bottom.y - self.top.y;
        if dy <= 0.0 {
            return self.top;
        }
        let t = ((y - self.top.y) / dy).clamp(0.0, 1.0);
        self.top + (self.bottom - self.top) * t
    }

    fn depth(&self, q: DVec2) -> f64 {
        let d = self.bottom - self.top;
        let len2 = d.length_squared();
        let t = if len2 > 0.0 {
            ((q - self.top).dot(d) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        self.ztop + (self.zbottom - self.ztop) * t
    }
}

/// One row of the screen after visibility: per column the polygon in front at the pixel
/// centre (a place in ZMIN order, or [`NONE`]), from Watkins's visible segments.
struct Row {
    front: Vec<u32>,
}

/// A line of intersection being followed down the scan lines (its segment block).
struct Crossing {
    start: DVec2,
    end: DVec2,
    last: i64,
    colour: Colour,
    /// The common part of the two polygons' boxes: its ends, which lie between scan
    /// lines, are kept within it (and so on the screen).
    lo: DVec2,
    hi: DVec2,
}

/// The part of segment p→q inside the rectangle [lo, hi] (Liang and Barsky's parameters),
/// if any; an end inside is kept as it is.
fn clip_to(p: DVec2, q: DVec2, lo: DVec2, hi: DVec2) -> Option<(DVec2, DVec2)> {
    let d = q - p;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, d, lo, hi) in [(p.x, d.x, lo.x, hi.x), (p.y, d.y, lo.y, hi.y)] {
        if d == 0.0 {
            if p < lo || p > hi {
                return None;
            }
        } else {
            let (u, v) = ((lo - p) / d, (hi - p) / d);
            t0 = t0.max(u.min(v));
            t1 = t1.min(u.max(v));
        }
    }
    let at = |t: f64| match t {
        0.0 => p,
        1.0 => q,
        _ => (p + d * t).max(lo).min(hi), // rounding kept inside too
    };
    (t0 < t1).then(|| (at(t0), at(t1)))
}

/// Hands `emit` the part of `seg` on the screen [0, W] × [0, H] (`screen` = (W, H)), if
/// any, and says whether there was one. Archuleta's scan lines are the screen's rows and
/// their samples its pixels: a vector is found only where they see it, and a piece of an
/// edge off the screen (a stream the stage takes may reach past it, within scan's guard
/// band) has no sample of its own; the nearest column's would say whether a point many
/// pixels away is hidden.
fn on_screen(seg: Segment, screen: DVec2, emit: &mut impl FnMut(Segment)) -> bool {
    match clip_to(seg.from, seg.to, DVec2::ZERO, screen) {
        Some((from, to)) => {
            emit(Segment { from, to, ..seg });
            true
        }
        None => false,
    }
}

/// The edges of the model: every polygon's edges less the screen's border and the
/// splitter's cuts (as the continuous method leaves them out), one per distinct edge,
/// with the list of polygons that share it.
fn model_edges(
    faces: &[Face],
    width: u32,
    height: u32,
    tol: f64,
    stats: &mut LineStats,
) -> (Vec<Edge>, Vec<u32>) {
    let (w, h) = (width as f64, height as f64);
    // Pieces of one polygon the splitter cut: grouped by the recorded plane and colour.
    let mut pieces: HashMap<([u64; 4], Colour), Vec<u32>> = HashMap::new();
    for (k, f) in faces.iter().enumerate() {
        if let Some(r) = f.recorded {
            pieces.entry((r, f.colour)).or_default().push(k as u32);
        }
    }
    let mut found: Vec<([u64; 4], usize, u32, usize)> = Vec::new();
    for (k, a) in faces.iter().enumerate() {
        for i in 0..a.points.len() {
            let (p0, p1) = a.edge(i);
            if p0 == p1 {
                continue;
            }
            stats.edges += 1;
            let same_polygon = || {
                a.recorded
                    .and_then(|r| pieces.get(&(r, a.colour)))
                    .into_iter()
                    .flatten()
                    .map(|&j| &faces[j as usize])
            };
            if is_pipeline_cut(a, (p0, p1), (w, h), tol, stats, same_polygon) {
                continue;
            }
            found.push((edge_key(p0, p1), a.index, k as u32, i));
        }
    }
    // One edge per key, its polygons in stream order; drawn with the first one's depths.
    found.sort_unstable_by_key(|a| (a.0, a.1));
    let mut edges = Vec::new();
    let mut owners = Vec::with_capacity(found.len());
    let mut g = 0;
    while g < found.len() {
        let mut e = g + 1;
        while e < found.len() && found[e].0 == found[g].0 {
            e += 1;
        }
        stats.shared += (e - g - 1) as u64;
        let (_, index, k, i) = found[g];
        let f = &faces[k as usize];
        let n = f.points.len();
        let (mut top, mut bottom) = (
            (f.points[i], f.depths[i]),
            (f.points[(i + 1) % n], f.depths[(i + 1) % n]),
        );
        if (bottom.0.y, bottom.0.x) < (top.0.y, top.0.x) {
            std::mem::swap(&mut top, &mut bottom);
        }
        let o0 = owners.len() as u32;
        owners.extend(found[g..e].iter().map(|x| x.2));
        owners[o0 as usize..].sort_unstable();
        // The rows whose centres r + 0.5 lie in [top, bottom): the half-open rule of
        // the segments' coverage.
        let first = (top.0.y - 0.5).ceil() as i64;
        let last = (bottom.0.y - 0.5).ceil() as i64 - 1;
        edges.push(Edge {
            top: top.0,
            bottom: bottom.0,
            ztop: top.1,
            zbottom: bottom.1,
            o0,
            o1: owners.len() as u32,
            tie: index,
            first,
            last: last.min(height as i64 - 1),
            start: None,
            end: top.0,
            colour: f.colour,
            base: f.colour,
        });
        g = e;
    }
    (edges, owners)
}

impl Row {
    fn blank(width: usize) -> Row {
        Row {
            front: vec![NONE; width],
        }
    }
}

/// Watkins's scan-line method ([`scan::watkins`], the `scanline` stage's own) run down the
/// frame a line at a time: each line's visible segments (the pieces where one polygon's
/// segment is in front, as they go to the shader) become the row's fronts.
pub(crate) struct Scan<'a> {
    polygons: &'a [Polygon],
    /// Each polygon's place in ZMIN order, by stream index ([`NONE`]: not a face).
    place: Vec<u32>,
    watkins: scan::watkins::Scanline,
    runs: Vec<scan::Run>,
    width: u32,
    height: u32,
    /// Watkins's scan has passed its last polygon: every row from here is blank.
    done: bool,
}

impl<'a> Scan<'a> {
    /// `faces` in ZMIN order, made from `polygons` (stream order).
    pub(crate) fn new(
        faces: &[Face],
        polygons: &'a [Polygon],
        width: u32,
        height: u32,
    ) -> Scan<'a> {
        let mut place = vec![NONE; polygons.len()];
        for (k, f) in faces.iter().enumerate() {
            place[f.index] = k as u32;
        }
        let mut watkins = scan::watkins::Scanline::new();
        watkins.begin(polygons, height);
        Scan {
            polygons,
            place,
            watkins,
            runs: Vec::new(),
            width,
            height,
            done: false,
        }
    }

    /// Row `r`'s fronts into `row` (blank below the screen's last row). The rows come
    /// one after another from 0, as Watkins's scan goes.
    fn resolve(&mut self, r: i64, row: &mut Row, stats: &mut LineStats) {
        row.front.fill(NONE);
        if r < 0 || r >= self.height as i64 || self.done {
            return;
        }
        self.runs.clear();
        let (y, w, h) = (r as u32, self.width, self.height);
        self.done = !self.watkins.line(self.polygons, y, w, h, &mut self.runs);
        for p in self.watkins.pieces() {
            stats.visible_segments += 1;
            let k = self.place[p.polygon];
            row.front[p.x0 as usize..p.x1 as usize].fill(k);
        }
    }
}

/// May the change of front from polygon `ka` at pixel centre `qa` to `kb` at the
/// neighbouring centre `qb` be a crossing of the two? Not where they are neighbours in a
/// mesh (a vertex in common) or pieces of one polygon; and, when `both_cover`, only
/// where each holds the other's centre strictly inside, so that no edge of either lies
/// between the centres (Archuleta's test: then it is a crossing).
fn crossing_between(
    faces: &[Face],
    ka: u32,
    kb: u32,
    qa: DVec2,
    qb: DVec2,
    (tol, both_cover): (f64, bool),
    stats: &mut LineStats,
) -> bool {
    if ka == kb || ka == NONE || kb == NONE {
        return false;
    }
    let (a, b) = (&faces[ka as usize], &faces[kb as usize]);
    if both_cover && !(a.strictly_inside(qb, tol) && b.strictly_inside(qa, tol)) {
        return false;
    }
    if (a.recorded.is_some() && a.recorded == b.recorded && a.colour == b.colour)
        || shares_vertex(a, b)
    {
        stats.neighbours += 1;
        return false;
    }
    true
}

/// The pairs of polygons (places in ZMIN order, the smaller first, sorted) whose front
/// changes from one to the other between two neighbouring pixel centres, across a
/// column or a row, less neighbours in a mesh: the pairs that may pass through each
/// other where it can be seen, at the raster's resolution (the caller finds whether they
/// do, exactly).
pub(crate) fn front_crossings(
    faces: &[Face],
    polygons: &[Polygon],
    width: u32,
    height: u32,
    stats: &mut LineStats,
) -> Vec<(u32, u32)> {
    let mut pairs = std::collections::HashSet::new();
    if faces.is_empty() || width == 0 || height == 0 {
        return Vec::new();
    }
    let tol = 1e-12 * (width as f64 + height as f64).max(1.0);
    let wc = width as usize;
    let mut scan = Scan::new(faces, polygons, width, height);
    let (mut prev, mut cur) = (Row::blank(wc), Row::blank(wc));
    for r in 0..height as i64 {
        std::mem::swap(&mut prev, &mut cur);
        scan.resolve(r, &mut cur, stats);
        let y = r as f64 + 0.5;
        for c in 0..wc {
            let q = DVec2::new(c as f64 + 0.5, y);
            let (k, right, above) = (
                cur.front[c],
                cur.front.get(c + 1).copied().unwrap_or(NONE),
                prev.front[c],
            );
            if crossing_between(faces, k, right, q, q + DVec2::X, (tol, false), stats) {
                pairs.insert((k.min(right), k.max(right)));
            }
            if r > 0 && crossing_between(faces, k, above, q, q - DVec2::Y, (tol, false), stats) {
                pairs.insert((k.min(above), k.max(above)));
            }
        }
    }
    let mut pairs: Vec<(u32, u32)> = pairs.into_iter().collect();
    pairs.sort_unstable();
    pairs
}

/// Archuleta's hidden-line drawing of one frame (see the module notes): each visible
/// piece handed to `emit` when its run of scan lines ends, edges and lines of
/// intersection as they are found, from the top of the screen down.
pub(crate) fn for_each_segment(
    polygons: &[Polygon],
    width: u32,
    height: u32,
    stats: &mut LineStats,
    mut emit: impl FnMut(Segment),
) {
    let mut faces = Face::all(polygons);
    if faces.is_empty() || width == 0 || height == 0 {
        return;
    }
    faces.sort_by(|a, b| a.zmin.total_cmp(&b.zmin));
    let tol = 1e-12 * (width as f64 + height as f64).max(1.0);
    let (wc, hr) = (width as usize, height as i64);
    let screen = DVec2::new(width as f64, height as f64);
    let (mut edges, owners) = model_edges(&faces, width, height, tol, stats);
    let owns = |e: &Edge, k: u32| {
        owners[e.o0 as usize..e.o1 as usize]
            .binary_search(&k)
            .is_ok()
    };

    // Watkins's Y buckets: edges by the row they enter on; a horizontal edge by the row
    // below the boundary it lies on (processed with the row above).
    let mut scan = Scan::new(&faces, polygons, width, height);
    let mut edge_enter: Vec<Vec<u32>> = vec![Vec::new(); hr as usize + 1];
    for (j, e) in edges.iter().enumerate() {
        if e.first <= e.last {
            if e.last >= 0 && e.first < hr {
                edge_enter[e.first.max(0) as usize].push(j as u32);
            }
        } else {
            edge_enter[e.first.clamp(0, hr) as usize].push(j as u32);
        }
    }

    let (mut prev, mut cur) = (Row::blank(wc), Row::blank(wc));
    let mut active_edges: Vec<u32> = Vec::new();
    let mut blocks: HashMap<(u32, u32), Crossing> = HashMap::new();
    let mut seen: Vec<(u32, u32)> = Vec::new();
    let mut seen_before: Vec<(u32, u32)> = Vec::new();

    for r in 0..=hr {
        std::mem::swap(&mut prev, &mut cur);
        scan.resolve(r, &mut cur, stats);
        let y = r as f64 + 0.5;

        // Does edge `e` show at `q` (depth `z`) on a row? It does where one of its own
        // polygons, or none, is in front at its column; else it is hidden if a polygon in
        // front at that column or beside it (the pixel centre a polygon wins need not be
        // on the edge's side of a neighbour's edge) holds q strictly inside and is nearer
        // there.
        let shows = |row: &Row, e: &Edge, q: DVec2, z: f64| {
            let c = (q.x.floor().max(0.0) as usize).min(wc - 1);
            let k = row.front[c];
            if k == NONE || owns(e, k) {
                return true;
            }
            let near = [c.saturating_sub(1), c, (c + 1).min(wc - 1)].map(|i| row.front[i]);
            !near.iter().enumerate().any(|(i, &k)| {
                k != NONE && !near[..i].contains(&k) && !owns(e, k) && {
                    let f = &faces[k as usize];
                    f.strictly_inside(q, tol)
                        && proto::depth::in_front(f.depth_at(q), f.index > e.tie, z)
                }
            })
        };
        // The colour of a run: of the edge's polygon in front beside it, if one is.
        let colour_at = |row: &Row, e: &Edge, q: DVec2| {
            let c = (q.x.floor().max(0.0) as usize).min(wc - 1);
            let k = row.front[c];
            if k != NONE && owns(e, k) {
                faces[k as usize].colour
            } else {
                e.base
            }
        };

        // The counters of the edges crossing this line.
        {
            for &j in &edge_enter[r as usize] {
                let e = &edges[j as usize];
                if e.first <= e.last {
                    active_edges.push(j);
                    continue;
                }
                // A horizontal edge: the parts over columns where one of its polygons
                // is in front on the line above or below it.
                stats.pairs_tested += 1;
                let (x0, x1) = (e.top.x.min(e.bottom.x), e.top.x.max(e.bottom.x));
                let (c0, c1) = (
                    (x0.floor().max(0.0) as usize).min(wc - 1),
                    (x1.floor().max(0.0) as usize).min(wc - 1),
                );
                let mut run: Option<(f64, usize)> = None;
                for c in c0..=c1 + 1 {
                    let on = c <= c1
                        && [&prev, &cur].iter().any(|row| {
                            let k = row.front[c];
                            k != NONE && owns(e, k)
                        });
                    match (on, run) {
                        (true, None) => run = Some(((c as f64).max(x0), c)),
                        (false, Some((from, c_from))) => {
                            let to = (c as f64).min(x1);
                            let along = |x: f64| {
                                if x1 > x0 {
                                    let t = (x - e.top.x) / (e.bottom.x - e.top.x);
                                    e.top + (e.bottom - e.top) * t.clamp(0.0, 1.0)
                                } else {
                                    e.top
                                }
                            };
                            let (p, q) = if x1 > x0 {
                                (along(from), along(to))
                            } else {
                                (e.top, e.bottom)
                            };
                            if p != q {
                                let row = if owns(e, cur.front[c_from]) {
                                    &cur
                                } else {
                                    &prev
                                };
                                let colour = colour_at(row, e, DVec2::new(c_from as f64 + 0.5, y));
                                let seg = Segment {
                                    from: p,
                                    to: q,
                                    colour,
                                    intersection: false,
                                };
                                if on_screen(seg, screen, &mut emit) {
                                    stats.segments += 1;
                                }
                            }
                            run = None;
                        }
                        _ => {}
                    }
                }
            }
        }
        if r < hr {
            let mut i = 0;
            while i < active_edges.len() {
                let j = active_edges[i] as usize;
                let e = &edges[j];
                if e.last < r {
                    active_edges.swap_remove(i);
                    continue;
                }
                i += 1;
                if e.first > r {
                    continue;
                }
                stats.pairs_tested += 1;
                let q = e.at(y);
                let visible = shows(&cur, e, q, e.depth(q));
                let colour = colour_at(&cur, e, q);
                let e = &mut edges[j];
                if visible {
                    if e.start.is_none() {
                        e.start = Some(if r == e.first { e.top } else { e.at(r as f64) });
                        e.colour = colour;
                    }
                    e.end = if r == e.last {
                        e.bottom
                    } else {
                        e.at(r as f64 + 1.0)
                    };
                }
                // Draw where the run ends: the edge exits, or it was visible on the line
                // before and is not on this one.
                if let Some(start) = e.start {
                    if !visible || r == e.last {
                        let seg = Segment {
                            from: start,
                            to: e.end,
                            colour: e.colour,
                            intersection: false,
                        };
                        if start != e.end && on_screen(seg, screen, &mut emit) {
                            stats.segments += 1;
                        }
                        e.start = None;
                    }
                }
            }
            // Lines of intersection: the front changes between two columns that both
            // polygons cover, with no edge between them.
            seen.clear();
            for c in 0..wc.saturating_sub(1) {
                let (ka, kb) = (cur.front[c], cur.front[c + 1]);
                let qa = DVec2::new(c as f64 + 0.5, y);
                // Inside by more than the snapping of Watkins's coverage (vertices to
                // 1/256 pixel): a centre nearer an edge than that may be covered on
                // either side of it, and a change of front there is the edge's.
                let inside = tol.max(1.0 / 256.0);
                if !crossing_between(&faces, ka, kb, qa, qa + DVec2::X, (inside, true), stats) {
                    continue;
                }
                let (a, b) = (&faces[ka as usize], &faces[kb as usize]);
                // depth_A − depth_B = α·X + β·Y + γ; the line where it is 0.
                let (al, be, ga) = (
                    a.gradient[0] - b.gradient[0],
                    a.gradient[1] - b.gradient[1],
                    a.gradient[2] - b.gradient[2],
                );
                if al == 0.0 || !al.is_finite() {
                    continue;
                }
                let at = |y: f64| DVec2::new(-(be * y + ga) / al, y);
                let key = (ka.min(kb), ka.max(kb));
                if let Some(block) = blocks.get_mut(&key) {
                    if block.last == r {
                        continue;
                    }
                    if block.last == r - 1 {
                        block.end = at(r as f64 + 1.0);
                        block.last = r;
                        seen.push(key);
                        continue;
                    }
                }
                stats.intersection_lines += 1;
                let colour = if a.index < b.index {
                    a.colour
                } else {
                    b.colour
                };
                blocks.insert(
                    key,
                    Crossing {
                        start: at(r as f64),
                        end: at(r as f64 + 1.0),
                        last: r,
                        colour,
                        lo: a.min.max(b.min),
                        hi: a.max.min(b.max),
                    },
                );
                seen.push(key);
            }
        }
        // Draw the lines of intersection not seen on this line.
        for key in seen_before.drain(..) {
            if blocks.get(&key).is_some_and(|b| b.last < r) {
                if let Some(b) = blocks.remove(&key) {
                    if let Some((from, to)) = clip_to(b.start, b.end, b.lo, b.hi) {
                        let seg = Segment {
                            from,
                            to,
                            colour: b.colour,
                            intersection: true,
                        };
                        if on_screen(seg, screen, &mut emit) {
                            stats.intersections += 1;
                        }
                    }
                }
            }
        }
        std::mem::swap(&mut seen, &mut seen_before);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tests::{crossing_pair, square, BLUE, RED};
    use crate::{for_each_segment_by, Method};

    fn draw(polygons: &[Polygon], stats: &mut LineStats) -> Vec<Segment> {
        let mut out = Vec::new();
        for_each_segment_by(Method::Archuleta, polygons, 100, 100, stats, |s| {
            out.push(s)
        });
        out
    }

    /// The pieces as (x0, y0, x1, y1, colour), each from its smaller end, sorted.
    fn sorted(segments: &[Segment]) -> Vec<(f64, f64, f64, f64, Colour)> {
        let mut v: Vec<_> = segments
            .iter()
            .map(|s| {
                let (a, b) = if (s.from.x, s.from.y) <= (s.to.x, s.to.y) {
                    (s.from, s.to)
                } else {
                    (s.to, s.from)
                };
                (a.x, a.y, b.x, b.y, s.colour)
            })
            .collect();
        v.sort_by(|a, b| a.partial_cmp(b).unwrap());
        v
    }

    #[test]
    fn on_whole_pixels_the_counters_draw_the_exact_pieces() {
        // Red (near) over blue's top-left corner, every edge on a pixel boundary: the
        // visibility changes where a scan line's centre says, and here that is exact.
        // Blue's left edge X = 30 is hidden on the lines whose centres red covers, 30.5 to
        // 49.5: its run starts at the boundary Y = 50 and exits at its bottom vertex.
        // Blue's top edge is horizontal: drawn over the columns where blue is in front
        // on the line below it, 50 to 69.
        let mut stats = LineStats::default();
        let segs = draw(
            &[
                square(RED, 10.0, 10.0, 50.0, 50.0, 0.2),
                square(BLUE, 30.0, 30.0, 70.0, 70.0, 0.6),
            ],
            &mut stats,
        );
        let want = vec![
            (10.0, 10.0, 10.0, 50.0, RED),
            (10.0, 10.0, 50.0, 10.0, RED),
            (10.0, 50.0, 50.0, 50.0, RED),
            (30.0, 50.0, 30.0, 70.0, BLUE),
            (30.0, 70.0, 70.0, 70.0, BLUE),
            (50.0, 10.0, 50.0, 50.0, RED),
            (50.0, 30.0, 70.0, 30.0, BLUE),
            (70.0, 30.0, 70.0, 70.0, BLUE),
        ];
        assert_eq!(sorted(&segs), want);
        // Four vertical edges tested on 40 lines each, four horizontal ones once.
        assert_eq!(stats.pairs_tested, 4 * 40 + 4);
        assert_eq!((stats.edges, stats.segments), (8, 8));
    }

    #[test]
    fn a_shared_edge_has_one_block_and_is_drawn_once() {
        let mut stats = LineStats::default();
        let segs = draw(
            &[
                square(RED, 10.0, 10.0, 40.0, 40.0, 0.5),
                square(BLUE, 40.0, 10.0, 70.0, 40.0, 0.3),
            ],
            &mut stats,
        );
        assert_eq!(stats.shared, 1);
        let on_40: Vec<_> = segs
            .iter()
            .filter(|s| s.from.x == 40.0 && s.to.x == 40.0)
            .collect();
        assert_eq!(on_40.len(), 1, "{segs:?}");
        assert_eq!(segs.len(), 7);
    }

    #[test]
    fn the_line_of_intersection_is_a_segment_block() {
        // Blue slopes through red's plane at X = 40 (Archuleta's second problem): the
        // front changes from red to blue between columns 39 and 40 on lines 30 to 49,
        // one block, drawn from the boundary Y = 30 to Y = 50, in red's colour.
        let mut stats = LineStats::default();
        let segs = draw(&crossing_pair(), &mut stats);
        let crossing: Vec<_> = segs.iter().filter(|s| s.intersection).collect();
        assert_eq!(crossing.len(), 1, "{segs:?}");
        let c = crossing[0];
        assert_eq!(
            (c.from, c.to, c.colour),
            (DVec2::new(40.0, 30.0), DVec2::new(40.0, 50.0), RED)
        );
        assert_eq!((stats.intersection_lines, stats.intersections), (1, 1));
        // Blue's long edges are hidden left of the crossing: drawn from X = 40 on, as
        // horizontal edges over the columns where blue is in front (40 to 59).
        let top = segs
            .iter()
            .find(|s| !s.intersection && s.colour == BLUE && s.from.y == 30.0 && s.to.y == 30.0)
            .expect("blue's top edge");
        assert_eq!(
            (top.from.x.min(top.to.x), top.from.x.max(top.to.x)),
            (40.0, 60.0)
        );
    }

    #[test]
    fn a_run_ends_between_scan_lines_not_where_the_edges_cross() {
        // Archuleta's first and third problems: red's slanted edge X + Y = 80 crosses
        // blue's left edge X = 30 at Y = 50. On line 49 (centre 49.5) the edge's column
        // 30 has its centre (30.5, 49.5) on red's edge, outside red by the half-open
        // rule, so blue is in front there and the edge counts as visible: its run starts
        // at the boundary Y = 49, a pixel over red, where the continuous piece starts at
        // the crossing.
        let red = Polygon::from_xyz(
            RED,
            &[[10.0, 10.0, 0.2], [70.0, 10.0, 0.2], [10.0, 70.0, 0.2]],
        );
        let blue = square(BLUE, 30.0, 20.5, 90.0, 90.0, 0.6);
        let polygons = [red, blue];
        let mut stats = LineStats::default();
        let segs = draw(&polygons, &mut stats);
        let on_30 = |segs: &[Segment]| -> Vec<(f64, f64)> {
            segs.iter()
                .filter(|s| s.colour == BLUE && s.from.x == 30.0 && s.to.x == 30.0)
                .map(|s| (s.from.y.min(s.to.y), s.from.y.max(s.to.y)))
                .collect()
        };
        assert_eq!(on_30(&segs), vec![(49.0, 90.0)], "{segs:?}");
        let exact = crate::visible_segments(&polygons, 100, 100, &mut LineStats::default());
        assert_eq!(on_30(&exact), vec![(50.0, 90.0)], "{exact:?}");
    }

    /// Archuleta's visibility is Watkins's, not a depth buffer's: on every row the
    /// polygon his counters read as in front at each column is the one that Watkins's
    /// visible segments (`scan::watkins`, run here on its own as the scanline stage runs
    /// it) paint there, the scanline stage's picture, through a crossing, an overlap and
    /// a triangle; and the segments his drawing reads are as many as Watkins passes on.
    #[test]
    fn the_fronts_are_watkins_visible_segments() {
        let [red, blue] = crossing_pair();
        let polygons = vec![
            red,
            blue,
            square([0, 200, 0], 50.0, 5.0, 90.0, 45.0, 0.4),
            Polygon::from_xyz(
                [200, 200, 0],
                &[[5.0, 60.0, 0.1], [80.0, 75.5, 0.9], [30.0, 95.0, 0.2]],
            ),
        ];
        let (w, h) = (100u32, 100u32);
        let mut faces: Vec<Face> = polygons
            .iter()
            .enumerate()
            .filter_map(|(i, p)| Face::of(i, p))
            .collect();
        faces.sort_by(|a, b| a.zmin.total_cmp(&b.zmin));
        let mut scan = Scan::new(&faces, &polygons, w, h);
        let mut row = Row::blank(w as usize);
        let mut stats = LineStats::default();
        let mut fronts = Vec::new();
        for y in 0..h {
            scan.resolve(y as i64, &mut row, &mut stats);
            fronts.extend(
                row.front
                    .iter()
                    .map(|&k| (k != NONE).then(|| polygons[faces[k as usize].index].colour)),
            );
        }
        let mut watkins = scan::watkins::Scanline::new();
        watkins.begin(&polygons, h);
        let (mut runs, mut pieces) = (Vec::new(), 0u64);
        for y in 0..h {
            let more = watkins.line(&polygons, y, w, h, &mut runs);
            pieces += watkins.pieces().len() as u64;
            if !more {
                break;
            }
        }
        let picture = scan::frame::image_of(&runs, w, h);
        assert_eq!(fronts, picture);
        assert!(
            fronts.iter().filter(|c| c.is_some()).count() > 5000,
            "a real picture"
        );
        assert_eq!(stats.visible_segments, pieces);
        let mut drawn = LineStats::default();
        draw(&polygons, &mut drawn);
        assert_eq!(drawn.visible_segments, pieces);
    }

    /// A square reaching past the screen's right side (as a stream the stage takes may,
    /// within scan's guard band): its right edge, X = 130, is seen on no scan line and is
    /// not drawn (it was, judged by column 99's front, 30 px away); its top and bottom
    /// are drawn to the screen's side, X = 100.
    #[test]
    fn nothing_is_drawn_off_the_screen() {
        let mut stats = LineStats::default();
        let segs = draw(&[square(BLUE, 60.0, 20.0, 130.0, 60.0, 0.5)], &mut stats);
        assert_eq!(
            sorted(&segs),
            vec![
                (60.0, 20.0, 60.0, 60.0, BLUE),
                (60.0, 20.0, 100.0, 20.0, BLUE),
                (60.0, 60.0, 100.0, 60.0, BLUE),
            ]
        );
        assert_eq!(stats.segments, 3);
    }

    #[test]
    fn a_stack_is_one_polygon_a_line() {
        let polygons: Vec<Polygon> = (0..300)
            .map(|k| {
                let z = 0.1 + 0.002 * ((k * 131) % 300) as f64;
                square([k as u8, 1, 2], 10.0, 10.0, 90.0, 90.0, z)
            })
            .collect();
        let mut stats = LineStats::default();
        let segs = draw(&polygons, &mut stats);
        assert_eq!(sorted(&segs).len(), 4);
        assert!(segs.iter().all(|s| s.colour == [0, 1, 2]), "{segs:?}");
        // On each of the 80 lines Watkins's scan passes one visible segment on, the
        // nearest's: the other 299 are behind it across the line.
        assert_eq!(stats.visible_segments, 80);
    }

    mod properties {
        use super::*;
        use proptest::prelude::*;

        proptest! {
            #![proptest_config(ProptestConfig::with_cases(64))]
            /// At the raster's resolution: every point of Archuleta's drawing lies within
            /// a pixel and a half of the continuous drawing. His vectors start and stop
            /// at the boundaries between lines, half a line from the centre whose test
            /// drew them; a test at a centre is wrong only where a hider's edge, or its
            /// line of intersection with the edge's polygon, passes between the point
            /// tested and the pixel centre whose front was taken (half a pixel across, a
            /// line up or down for a horizontal edge): √(1 + ½²) ≈ 1.1 px at most, on
            /// the screen. Off it there is no sample, and nothing is drawn; the squares
            /// here reach past it (to X, Y = 120), as a stream the stage takes may.
            #[test]
            fn archuletas_lines_lie_on_the_exact_ones(
                squares in prop::collection::vec([0.0f64..80.0, 0.0f64..80.0, 2.0f64..40.0, 2.0f64..40.0, 0.1f64..0.9, -0.004f64..0.004], 1..6),
            ) {
                let polygons: Vec<Polygon> = squares.iter().enumerate().map(|(i, &[x, y, w, h, z, g])| {
                    Polygon::from_xyz([i as u8, 0, 0], &[
                        [x, y, z], [x + w, y, z + g * w], [x + w, y + h, z + g * w], [x, y + h, z],
                    ])
                }).collect();
                let mut stats = LineStats::default();
                let ours = draw(&polygons, &mut stats);
                let exact = crate::visible_segments(&polygons, 100, 100, &mut LineStats::default());
                let dist = |q: DVec2, s: &Segment| {
                    let d = s.to - s.from;
                    let t = if d.length_squared() > 0.0 { ((q - s.from).dot(d) / d.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
                    (s.from + d * t - q).length()
                };
                for s in &ours {
                    for k in 0..=8 {
                        let q = s.from + (s.to - s.from) * (k as f64 / 8.0);
                        let near = exact.iter().map(|e| dist(q, e)).fold(f64::INFINITY, f64::min);
                        prop_assert!(near <= 1.5, "{:?} at {:?}: {} from the exact drawing", s, q, near);
                    }
                }
            }
        }
    }
}
