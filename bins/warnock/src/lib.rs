//! # warnock: Warnock's area subdivision at a leaf of the splitter tree
//! (Newman and Sproull 1973, 14.3, Appendix VI; docs/DESIGN.md, "Leaves resolve visibility")
//!
//! Warnock examines *windows* of the screen instead of polygons (14.3): for a window the
//! **Looker** sorts every polygon still in question into surrounders, intersectors and
//! disjoint ones (14.3.2, AVI.1), the **Thinker** decides whether what is left is simple
//! enough to display (14.3.3, AVI.2), and the **Controller** subdivides a window the
//! Thinker fails on into four, depth first, down to single pixels, which are **displayed
//! by default** (14.3.1). The listing's `WARNOCK (LEFT, BOTTOM, SIZE)` works on square
//! windows whose sides halve at each level; so does [`Warnock`], starting from the
//! smallest power-of-two square that holds the frame's coverage.
//!
//! ## At pixel resolution
//!
//! Newman and Sproull's Looker clips polygon edges against the window in real coordinates; here
//! every decision is taken on the pixels themselves, with the point sampling every other
//! method uses, so that the frame is byte for byte the z-buffer's
//! ([`scan::frame::ZBuffer`]):
//!
//! - A polygon's *coverage* is exactly the spans [`scan::SpanWalker`] gives it,
//!   computed once per frame ([`Warnock::resolve`] keeps them by row). A polygon is
//!   **disjoint** from a window when it covers none of the window's pixel centres, a
//!   **surrounder** when it covers all of them, an **intersector** otherwise. As in the
//!   listing's HISTORY array, what is known of a window holds for its descendants: a
//!   disjoint polygon is not in their lists, a surrounder is not examined again.
//! - Depth is the depth of [`scan::DepthPlane`]: pixel x of row y has
//!   `depth_at(z_row, dz, x)`, smaller in front, decided by the tie rule
//!   ([`scan::takes`]). On a row it is linear in x, so whether polygon A is in front of
//!   polygon B over a stretch of the row is decided by its two end columns. The seed compares the planes at the window's four corners,
//!   extending intersectors over the whole window (AVI.1.1, "sufficient but not
//!   necessary"); here each row of the window is compared where B covers it, which is
//!   exact for this sampling and still sufficient.
//!
//! ## The Thinker
//!
//! A window is resolved ([`Resolution`]) when
//!
//! 1. its list is empty: nothing is drawn (the background shows);
//! 2. it is one pixel: displayed by default, the z-buffer's rule at its centre;
//! 3. one polygon is left: a surrounder fills the window, an intersector draws the
//!    pixels it covers;
//! 4. a surrounder is in front of every other polygon of the list wherever that one
//!    covers the window: it fills the window. The candidate is the surrounder nearest at
//!    the window's first pixel (any surrounder in front everywhere is nearest there).
//!    Polygons it hides are taken off the list of this window and its descendants, as
//!    the listing removes from INTERSECTORS the polygons hidden by the HIDER;
//! 5. after that, one intersector is left beside the surrounder and it is in front of
//!    the surrounder wherever it covers the window: the surrounder fills the window and
//!    the intersector's pixels are drawn over it (the "smart Thinker" of 14.3.3 and
//!    AVI.2, Thinker 2 with I = 1).
//!
//! Otherwise the window is subdivided. Penetrating polygons fail cases 4 and 5 along
//! their line of intersection and are subdivided down to pixels there, as Newman and Sproull say
//! the implied edge is found (14.3.3, Figure 14-18).
//!
//! Output: each resolved window puts its pieces of rows on its rows' lists (memory for
//! what is drawn, not for the bounding box: a frame of two small polygons in opposite
//! corners costs two polygons' worth), which are sent at the frame's end row by row as
//! maximal runs of one colour, the same runs `scanconv --resolve` sends.

use proto::{Colour, Polygon};
use scan::frame::HiddenSurface;
use scan::{depth_at, Run, SpanWalker};

/// How a window was resolved (for `--stats`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Resolution {
    /// No polygon covers a pixel of it.
    Empty,
    /// One pixel, decided by the z-buffer rule at its centre (display by default).
    Pixel,
    /// One polygon left, an intersector: its covered pixels drawn.
    OnePolygon,
    /// A surrounder in front of all the others (or alone): it fills the window.
    Surrounded,
    /// A surrounder and one intersector in front of it: both drawn.
    InFront,
    /// Too complex: split in four.
    Subdivided,
}

/// The Looker's class of a polygon for a window (Figure 14-13, by pixel centres).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Class {
    /// Covers none of the window's pixel centres.
    Disjoint,
    /// Covers some of them.
    Intersector,
    /// Covers all of them.
    Surrounder,
}

/// A window: pixels `x0..x1` × `y0..y1`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Window {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
}

impl Window {
    fn width(&self) -> u32 {
        self.x1 - self.x0
    }
    fn is_pixel(&self) -> bool {
        self.x1 - self.x0 == 1 && self.y1 - self.y0 == 1
    }
}

/// Counters over all frames, for `--stats`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Windows visited at each level of subdivision (0: the first window).
    pub windows_by_depth: Vec<u64>,
    pub empty: u64,
    pub pixels: u64,
    pub one_polygon: u64,
    pub surrounded: u64,
    pub in_front: u64,
    pub subdivided: u64,
    /// Rows of coverage the Looker read to classify polygons against windows.
    pub looker_rows: u64,
    /// Rows on which the Thinker compared two polygons' depths.
    pub depth_rows: u64,
}

/// One polygon that covers something this frame: where its rows are kept.
#[derive(Clone, Copy, Debug)]
struct Coverage {
    /// Its rows `y0..y1` (some may be empty: a concave polygon's gap).
    y0: u32,
    y1: u32,
    /// The columns its spans reach, `x0..x1`.
    x0: u32,
    x1: u32,
    /// Index of its first row in [`Warnock::rows`]; row y is `rows[row + (y − y0)]`, and
    /// its spans are `spans[rows[i].start..rows[i + 1].start]`.
    row: usize,
    dz: scan::Depth,
    colour: Colour,
}

/// One row of a polygon: where its spans start, and its depth at column 0.
#[derive(Clone, Copy, Debug)]
struct Row {
    start: usize,
    z_row: scan::Depth,
}

/// An entry of a window's polygon list: an index into the frame's coverages (stream
/// order, so a smaller index wins a tie) and whether it is known to surround the window.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Entry {
    poly: u32,
    surrounds: bool,
}

/// Warnock's area subdivision as a [`HiddenSurface`]. Its buffers are kept from frame
/// to frame.
#[derive(Default)]
pub struct Warnock {
    walker: SpanWalker,
    covs: Vec<Coverage>,
    rows: Vec<Row>,
    /// Every polygon's spans, `(x0, x1)`, polygon by polygon, row by row.
    spans: Vec<(u32, u32)>,
    /// The window lists of the windows on the current path of the subdivision, each on
    /// top of its ancestor's (the listing's HISTORY, one level per window).
    lists: Vec<Entry>,
    /// The frame's finished pieces of rows, `(x0, x1, colour)`, one list per row of the
    /// coverage's bounding box: memory for what the windows draw, not for the box.
    pieces: Vec<Vec<(u32, u32, Colour)>>,
    bbox: Window,
    pub stats: Stats,
}

impl Warnock {
    pub fn new() -> Self {
        Warnock::default()
    }

    /// Scan-converts every polygon once: its spans and depths by row.
    fn gather(&mut self, polygons: &[Polygon], width: u32, height: u32) {
        self.covs.clear();
        self.rows.clear();
        self.spans.clear();
        let (rows, spans) = (&mut self.rows, &mut self.spans);
        for p in polygons {
            let row = rows.len();
            let mut first: Option<(u32, scan::Depth)> = None;
            let (mut y_next, mut x0, mut x1) = (0u32, u32::MAX, 0u32);
            self.walker.for_each_span(p, width, height, |s| {
                if first.is_none() {
                    first = Some((s.y, s.dz));
                    y_next = s.y;
                }
                // A row without spans (a gap across a concave polygon) keeps depth 0:
                // nothing reads the depth of a row where the polygon covers nothing.
                while y_next <= s.y {
                    rows.push(Row {
                        start: spans.len(),
                        z_row: 0.0,
                    });
                    y_next += 1;
                }
                if let Some(r) = rows.last_mut() {
                    r.z_row = s.z_row;
                }
                spans.push((s.x0, s.x1));
                x0 = x0.min(s.x0);
                x1 = x1.max(s.x1);
            });
            let Some((y0, dz)) = first else { continue };
            rows.push(Row {
                start: spans.len(),
                z_row: 0.0,
            });
            self.covs.push(Coverage {
                y0,
                y1: y_next,
                x0,
                x1,
                row,
                dz,
                colour: p.colour,
            });
        }
    }

    /// The spans of polygon `c` on row `y` (which must be one of its rows).
    fn row_spans(&self, c: &Coverage, y: u32) -> (&[(u32, u32)], scan::Depth) {
        let i = c.row + (y - c.y0) as usize;
        let (r, next) = (self.rows[i], self.rows[i + 1]);
        (&self.spans[r.start..next.start], r.z_row)
    }

    /// The Looker: polygon `poly`'s class for window `w`, from its spans.
    pub fn classify(&mut self, poly: u32, w: Window) -> Class {
        let c = self.covs[poly as usize];
        if c.x1 <= w.x0 || w.x1 <= c.x0 || c.y1 <= w.y0 || w.y1 <= c.y0 {
            return Class::Disjoint;
        }
        let mut all = c.x0 <= w.x0 && w.x1 <= c.x1 && c.y0 <= w.y0 && w.y1 <= c.y1;
        let mut any = false;
        let rows = w.y0.max(c.y0)..w.y1.min(c.y1);
        let mut looked = 0;
        for y in rows {
            looked += 1;
            let (spans, _) = self.row_spans(&c, y);
            let covered: u32 = spans
                .iter()
                .map(|&(a, b)| b.min(w.x1).saturating_sub(a.max(w.x0)))
                .sum();
            any |= covered > 0;
            all &= covered == w.width();
            if any && !all {
                break;
            }
        }
        self.stats.looker_rows += looked;
        match (any, all) {
            (false, _) => Class::Disjoint,
            (true, false) => Class::Intersector,
            (true, true) => Class::Surrounder,
        }
    }

    /// Whether polygon `a` beats polygon `b` (is nearer, or as near and earlier in the
    /// stream) at every pixel of window `w` that polygon `on` covers; `on` is `a` or `b`,
    /// and the other one surrounds `w`, so both have depths on every row compared.
    /// `None`: not decided, a depth at the `i64` bounds (it may be saturated).
    ///
    /// On a row both depths are linear in x (exact, unsaturated), so their difference is
    /// too, and the two end columns of `on`'s pixels on the row decide for the pixels
    /// between them.
    pub fn beats(&mut self, a: u32, b: u32, on: u32, w: Window) -> Option<bool> {
        let (ca, cb, con) = (
            self.covs[a as usize],
            self.covs[b as usize],
            self.covs[on as usize],
        );
        let mut compared = 0;
        let mut result = Some(true);
        'rows: for y in w.y0.max(con.y0)..w.y1.min(con.y1) {
            let (spans, _) = self.row_spans(&con, y);
            let mut ends: Option<(u32, u32)> = None;
            for &(s0, s1) in spans {
                let (s0, s1) = (s0.max(w.x0), s1.min(w.x1));
                if s0 < s1 {
                    ends = Some((ends.map_or(s0, |e| e.0), s1 - 1));
                }
            }
            let Some((first, last)) = ends else {
                continue;
            };
            compared += 1;
            let (_, za) = self.row_spans(&ca, y);
            let (_, zb) = self.row_spans(&cb, y);
            for x in [first, last] {
                let (da, db) = (depth_at(za, ca.dz, x), depth_at(zb, cb.dz, x));
                let a_in_front = if a > b {
                    scan::takes(da, db)
                } else {
                    proto::depth::takes_back(da, db)
                };
                if !a_in_front {
                    result = Some(false);
                    break 'rows;
                }
            }
        }
        self.stats.depth_rows += compared;
        result
    }

    /// The depth of polygon `poly` at pixel (x, y), which it covers.
    fn depth(&self, poly: u32, x: u32, y: u32) -> scan::Depth {
        let c = &self.covs[poly as usize];
        let (_, z_row) = self.row_spans(c, y);
        depth_at(z_row, c.dz, x)
    }

    fn fill(&mut self, w: Window, colour: Colour) {
        let y0 = self.bbox.y0;
        for y in w.y0..w.y1 {
            self.pieces[(y - y0) as usize].push((w.x0, w.x1, colour));
        }
    }

    /// Draws the pixels of window `w` that polygon `poly` covers, and, with `under`,
    /// the rest of the window in that colour.
    fn draw(&mut self, poly: u32, w: Window, under: Option<Colour>) {
        let c = self.covs[poly as usize];
        let y0 = self.bbox.y0;
        for y in w.y0..w.y1 {
            let row = &mut self.pieces[(y - y0) as usize];
            let mut x = w.x0;
            if (c.y0..c.y1).contains(&y) {
                let i = c.row + (y - c.y0) as usize;
                for &(s0, s1) in &self.spans[self.rows[i].start..self.rows[i + 1].start] {
                    let (s0, s1) = (s0.max(w.x0), s1.min(w.x1));
                    if s0 < s1 {
                        if let Some(u) = under.filter(|_| x < s0) {
                            row.push((x, s0, u));
                        }
                        row.push((s0, s1, c.colour));
                        x = s1;
                    }
                }
            }
            if let Some(u) = under.filter(|_| x < w.x1) {
                row.push((x, w.x1, u));
            }
        }
    }

    /// Sends the frame's pieces as runs, row by row, left to right, pieces that meet in
    /// one colour joined: the runs `scanconv --resolve` sends.
    fn emit(&mut self, runs: &mut Vec<Run>) {
        for (i, row) in self.pieces.iter_mut().enumerate() {
            row.sort_unstable_by_key(|p| p.0);
            let y = self.bbox.y0 + i as u32;
            let mut open: Option<Run> = None;
            for &(x0, x1, colour) in row.iter() {
                match &mut open {
                    Some(r) if r.x1 == x0 && r.colour == colour => r.x1 = x1,
                    _ => {
                        runs.extend(open.take());
                        open = Some(Run { y, x0, x1, colour });
                    }
                }
            }
            runs.extend(open);
            row.clear();
        }
    }

    /// The Thinker on window `w`, whose list is `lists[start..]`: resolves it and draws
    /// it, or says it must be subdivided. Polygons the list's nearest surrounder hides
    /// are taken off the list.
    pub fn think(&mut self, w: Window, start: usize) -> Resolution {
        let n = self.lists.len() - start;
        if n == 0 {
            return Resolution::Empty;
        }
        if w.is_pixel() {
            // Display by default: every polygon of a one-pixel window's list covers it; the
            // tie rule's fold in stream order picks the one seen.
            let mut order: Vec<u32> = self.lists[start..].iter().map(|e| e.poly).collect();
            order.sort_unstable();
            let mut best = (self.depth(order[0], w.x0, w.y0), order[0]);
            for &p in &order[1..] {
                let z = self.depth(p, w.x0, w.y0);
                if scan::takes(z, best.0) {
                    best = (z, p);
                }
            }
            self.fill(w, self.covs[best.1 as usize].colour);
            return Resolution::Pixel;
        }
        if n == 1 {
            let e = self.lists[start];
            if e.surrounds {
                self.fill(w, self.covs[e.poly as usize].colour);
                return Resolution::Surrounded;
            }
            self.draw(e.poly, w, None);
            return Resolution::OnePolygon;
        }
        // The candidate hider: the nearest surrounder at the window's first pixel.
        let Some((_, hider)) = self.lists[start..]
            .iter()
            .filter(|e| e.surrounds)
            .map(|e| (self.depth(e.poly, w.x0, w.y0), e.poly))
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
        else {
            return Resolution::Subdivided;
        };
        let mut kept = start;
        for i in start..self.lists.len() {
            let e = self.lists[i];
            if e.poly == hider || self.beats(hider, e.poly, e.poly, w) != Some(true) {
                self.lists[kept] = e;
                kept += 1;
            }
        }
        self.lists.truncate(kept);
        match kept - start {
            1 => {
                self.fill(w, self.covs[hider as usize].colour);
                Resolution::Surrounded
            }
            2 => {
                let other = self.lists[start..]
                    .iter()
                    .find(|e| e.poly != hider)
                    .expect("two entries, one the hider");
                let other = other.poly;
                if self.beats(other, hider, other, w) == Some(true) {
                    self.draw(other, w, Some(self.covs[hider as usize].colour));
                    Resolution::InFront
                } else {
                    Resolution::Subdivided
                }
            }
            _ => Resolution::Subdivided,
        }
    }

    /// The Controller: visits window `w` (part of the square of side `size` at
    /// (`sx`, `sy`)) at subdivision depth `depth`, its list being `lists[start..]`.
    fn visit(&mut self, sx: u64, sy: u64, size: u64, depth: usize, start: usize) {
        let w = self
            .clip(sx, sy, size)
            .expect("visited windows are not empty");
        if self.stats.windows_by_depth.len() <= depth {
            self.stats.windows_by_depth.resize(depth + 1, 0);
        }
        self.stats.windows_by_depth[depth] += 1;
        let r = self.think(w, start);
        match r {
            Resolution::Empty => self.stats.empty += 1,
            Resolution::Pixel => self.stats.pixels += 1,
            Resolution::OnePolygon => self.stats.one_polygon += 1,
            Resolution::Surrounded => self.stats.surrounded += 1,
            Resolution::InFront => self.stats.in_front += 1,
            Resolution::Subdivided => self.stats.subdivided += 1,
        }
        if r != Resolution::Subdivided {
            return;
        }
        let half = size / 2;
        let end = self.lists.len();
        for (qx, qy) in [(0, 0), (half, 0), (0, half), (half, half)] {
            let (cx, cy) = (sx + qx, sy + qy);
            let Some(child) = self.clip(cx, cy, half) else {
                continue;
            };
            // The Looker, with the ancestral check: a surrounder of this window surrounds
            // the child; a polygon disjoint from this window is not in its list.
            for i in start..end {
                let e = self.lists[i];
                let class = if e.surrounds {
                    Class::Surrounder
                } else {
                    self.classify(e.poly, child)
                };
                if class != Class::Disjoint {
                    self.lists.push(Entry {
                        poly: e.poly,
                        surrounds: class == Class::Surrounder,
                    });
                }
            }
            self.visit(cx, cy, half, depth + 1, end);
            self.lists.truncate(end);
        }
    }

    /// The part of the square of side `size` at (`sx`, `sy`) inside the coverage's
    /// bounding box, if any.
    fn clip(&self, sx: u64, sy: u64, size: u64) -> Option<Window> {
        let b = self.bbox;
        let x0 = sx.max(b.x0 as u64);
        let y0 = sy.max(b.y0 as u64);
        let x1 = (sx + size).min(b.x1 as u64);
        let y1 = (sy + size).min(b.y1 as u64);
        (x0 < x1 && y0 < y1).then_some(Window {
            x0: x0 as u32,
            y0: y0 as u32,
            x1: x1 as u32,
            y1: y1 as u32,
        })
    }
}

impl HiddenSurface for Warnock {
    fn resolve(&mut self, polygons: &[Polygon], width: u32, height: u32, runs: &mut Vec<Run>) {
        self.gather(polygons, width, height);
        if self.covs.is_empty() {
            return;
        }
        let b = self.covs.iter().fold(
            Window {
                x0: u32::MAX,
                y0: u32::MAX,
                x1: 0,
                y1: 0,
            },
            |b, c| Window {
                x0: b.x0.min(c.x0),
                y0: b.y0.min(c.y0),
                x1: b.x1.max(c.x1),
                y1: b.y1.max(c.y1),
            },
        );
        self.bbox = b;
        let height = (b.y1 - b.y0) as usize;
        self.pieces.truncate(height);
        self.pieces.resize_with(height, Vec::new);
        let size = (b.width().max(b.y1 - b.y0) as u64).next_power_of_two();
        let (sx, sy) = (b.x0 as u64, b.y0 as u64);
        let root = self.clip(sx, sy, size).expect("the coverage is not empty");
        self.lists.clear();
        for poly in 0..self.covs.len() as u32 {
            let class = self.classify(poly, root);
            if class != Class::Disjoint {
                self.lists.push(Entry {
                    poly,
                    surrounds: class == Class::Surrounder,
                });
            }
        }
        self.visit(sx, sy, size, 0, 0);
        self.emit(runs);
    }

    fn stats(&self) -> String {
        let s = &self.stats;
        let depths: Vec<String> = s.windows_by_depth.iter().map(u64::to_string).collect();
        format!(
            "windows by depth: {}; {} empty, {} single pixels, {} one polygon, {} surrounded, \
             {} one in front of a surrounder, {} subdivided; {} coverage rows looked at, \
             {} depth rows compared",
            depths.join(" "),
            s.empty,
            s.pixels,
            s.one_polygon,
            s.surrounded,
            s.in_front,
            s.subdivided,
            s.looker_rows,
            s.depth_rows
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use scan::frame::{differing_pixels, image_of, zbuffer_image};

    fn square(colour: Colour, x0: f64, y0: f64, x1: f64, y1: f64, z: f64) -> Polygon {
        Polygon::from_xyz(
            colour,
            &[[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]],
        )
    }

    fn win(x0: u32, y0: u32, x1: u32, y1: u32) -> Window {
        Window { x0, y0, x1, y1 }
    }

    /// A Warnock with `polygons` gathered on a `w`×`h` screen, and the whole screen
    /// painted by nothing yet.
    fn loaded(polygons: &[Polygon], w: u32, h: u32) -> Warnock {
        let mut m = Warnock::new();
        m.gather(polygons, w, h);
        m.bbox = win(0, 0, w, h);
        m.pieces = vec![Vec::new(); h as usize];
        m
    }

    /// What the windows thought about so far have drawn, on the `w`×`h` screen of
    /// [`loaded`]; a pixel drawn twice panics.
    fn picture(m: &mut Warnock) -> Vec<Option<Colour>> {
        let mut runs = vec![];
        let kept = m.pieces.clone();
        m.emit(&mut runs);
        m.pieces = kept;
        image_of(&runs, m.bbox.x1, m.bbox.y1)
    }

    /// Puts every gathered polygon on the list as the Looker finds it for `w`, and thinks.
    fn think_on(m: &mut Warnock, w: Window) -> Resolution {
        m.lists.clear();
        for poly in 0..m.covs.len() as u32 {
            let class = m.classify(poly, w);
            if class != Class::Disjoint {
                m.lists.push(Entry {
                    poly,
                    surrounds: class == Class::Surrounder,
                });
            }
        }
        m.think(w, 0)
    }

    fn resolved(polygons: &[Polygon], w: u32, h: u32) -> (Vec<Run>, Warnock) {
        let mut m = Warnock::new();
        let mut runs = vec![];
        m.resolve(polygons, w, h, &mut runs);
        (runs, m)
    }

    const RED: Colour = [255, 0, 0];
    const GREEN: Colour = [0, 255, 0];
    const BLUE: Colour = [0, 0, 255];

    #[test]
    fn the_looker_classifies_by_pixel_centres() {
        // Covers pixels 2..6 × 2..6.
        let mut m = loaded(&[square(RED, 2.0, 2.0, 6.0, 6.0, 0.5)], 8, 8);
        assert_eq!(m.classify(0, win(0, 0, 8, 8)), Class::Intersector);
        assert_eq!(m.classify(0, win(2, 2, 6, 6)), Class::Surrounder);
        assert_eq!(m.classify(0, win(3, 4, 4, 5)), Class::Surrounder);
        assert_eq!(m.classify(0, win(5, 5, 7, 7)), Class::Intersector);
        assert_eq!(m.classify(0, win(6, 0, 8, 8)), Class::Disjoint);
        assert_eq!(m.classify(0, win(0, 0, 2, 2)), Class::Disjoint);
        // A square whose edges pass just short of the centres of row 6 and column 6.
        let mut m = loaded(&[square(RED, 2.0, 2.0, 6.4, 6.4, 0.5)], 8, 8);
        assert_eq!(m.classify(0, win(6, 6, 8, 8)), Class::Disjoint);
        assert_eq!(m.classify(0, win(2, 2, 6, 6)), Class::Surrounder);
        // A U opening upwards: the notch (columns 2..4, rows 0..3) is outside it though
        // inside its bounding box, and the prongs surround windows of their own.
        let u = Polygon::from_xyz(
            RED,
            &[
                [0.0, 0.0, 0.5],
                [2.0, 0.0, 0.5],
                [2.0, 3.0, 0.5],
                [4.0, 3.0, 0.5],
                [4.0, 0.0, 0.5],
                [6.0, 0.0, 0.5],
                [6.0, 5.0, 0.5],
                [0.0, 5.0, 0.5],
            ],
        );
        let mut m = loaded(&[u], 6, 6);
        assert_eq!(m.classify(0, win(2, 0, 4, 3)), Class::Disjoint);
        assert_eq!(m.classify(0, win(2, 0, 4, 4)), Class::Intersector);
        assert_eq!(m.classify(0, win(4, 0, 6, 5)), Class::Surrounder);
        assert_eq!(m.classify(0, win(0, 0, 6, 6)), Class::Intersector);
    }

    #[test]
    fn empty_and_one_polygon_windows() {
        let mut m = loaded(&[square(RED, 2.0, 2.0, 6.0, 6.0, 0.5)], 8, 8);
        assert_eq!(think_on(&mut m, win(6, 0, 8, 8)), Resolution::Empty);
        assert_eq!(think_on(&mut m, win(0, 0, 8, 8)), Resolution::OnePolygon);
        // The one polygon's pixels are drawn, and only those.
        let image = picture(&mut m);
        assert_eq!(image.iter().filter(|p| p.is_some()).count(), 16);
        assert_eq!(image[2 * 8 + 2], Some(RED));
        assert_eq!(image[6 * 8 + 6], None);
        let mut m = loaded(&[square(RED, 2.0, 2.0, 6.0, 6.0, 0.5)], 8, 8);
        assert_eq!(think_on(&mut m, win(3, 3, 5, 5)), Resolution::Surrounded);
        assert_eq!(picture(&mut m).iter().filter(|p| p.is_some()).count(), 4);
    }

    #[test]
    fn a_surrounder_in_front_hides_the_rest_and_they_leave_the_list() {
        let polygons = [
            square(RED, 0.0, 0.0, 8.0, 8.0, 0.25), // the hider, nearest
            square(GREEN, 1.0, 1.0, 5.0, 5.0, 0.5),
            square(BLUE, -2.0, -2.0, 10.0, 10.0, 0.75),
        ];
        let mut m = loaded(&polygons, 8, 8);
        assert_eq!(think_on(&mut m, win(0, 0, 8, 8)), Resolution::Surrounded);
        assert_eq!(picture(&mut m), vec![Some(RED); 64]);
        // Nearest, but only as near at the first pixel as a later polygon is: sloped
        // planes that cross inside the window are not decided, and nothing is hidden.
        let p = |x: f64, y: f64| [x, y, 0.5 + (x - 4.0) / 64.0];
        let sloped =
            Polygon::from_xyz(GREEN, &[p(0.0, 0.0), p(8.0, 0.0), p(8.0, 8.0), p(0.0, 8.0)]);
        let polygons = [square(RED, 0.0, 0.0, 8.0, 8.0, 0.5), sloped];
        let mut m = loaded(&polygons, 8, 8);
        assert_eq!(think_on(&mut m, win(0, 0, 8, 8)), Resolution::Subdivided);
        assert_eq!(m.lists.len(), 2);
        // Left of the crossing (X = 4) the flat one is behind.
        assert_eq!(think_on(&mut m, win(0, 0, 4, 8)), Resolution::Surrounded);
        assert_eq!(picture(&mut m)[0], Some(GREEN));
        // The hider takes the polygons it hides off the list; two that are left in front
        // of it (and overlap) make the window fail.
        let polygons = [
            square(RED, 0.0, 0.0, 8.0, 8.0, 0.5),
            square(GREEN, 1.0, 1.0, 5.0, 5.0, 0.25),
            square(BLUE, 3.0, 3.0, 7.0, 7.0, 0.125),
            square(BLUE, 0.0, 4.0, 4.0, 8.0, 0.75), // hidden
        ];
        let mut m = loaded(&polygons, 8, 8);
        assert_eq!(think_on(&mut m, win(0, 0, 8, 8)), Resolution::Subdivided);
        let left: Vec<u32> = m.lists.iter().map(|e| e.poly).collect();
        assert_eq!(left, vec![0, 1, 2]);
    }

    #[test]
    fn one_intersector_in_front_of_a_surrounder() {
        let polygons = [
            square(RED, 0.0, 0.0, 8.0, 8.0, 0.5),
            square(GREEN, 2.0, 2.0, 5.0, 5.0, 0.25),
            square(BLUE, 4.0, 0.0, 8.0, 8.0, 0.75), // hidden by the red
        ];
        let mut m = loaded(&polygons, 8, 8);
        assert_eq!(think_on(&mut m, win(0, 0, 8, 8)), Resolution::InFront);
        assert_eq!(picture(&mut m), zbuffer_image(&polygons, 8, 8));
        // Behind the surrounder where it covers, in front elsewhere: not decided here.
        let p = |x: f64, y: f64| [x, y, 0.5 + (x - 4.0) / 16.0];
        let polygons = [
            square(RED, 0.0, 0.0, 8.0, 8.0, 0.5),
            Polygon::from_xyz(GREEN, &[p(2.0, 2.0), p(7.0, 2.0), p(7.0, 5.0), p(2.0, 5.0)]),
        ];
        let mut m = loaded(&polygons, 8, 8);
        assert_eq!(think_on(&mut m, win(0, 0, 8, 8)), Resolution::Subdivided);
    }

    #[test]
    fn ties_go_to_the_earlier_polygon() {
        // Coincident squares: the first one wins, whichever comes first in the list.
        let polygons = [
            square(GREEN, 0.0, 0.0, 8.0, 8.0, 0.5),
            square(RED, 0.0, 0.0, 8.0, 8.0, 0.5),
        ];
        let mut m = loaded(&polygons, 8, 8);
        assert_eq!(think_on(&mut m, win(0, 0, 8, 8)), Resolution::Surrounded);
        assert_eq!(picture(&mut m), vec![Some(GREEN); 64]);
        // An intersector as deep as the surrounder loses to it when it is later...
        let polygons = [
            square(GREEN, 0.0, 0.0, 8.0, 8.0, 0.5),
            square(RED, 2.0, 2.0, 4.0, 4.0, 0.5),
        ];
        let mut m = loaded(&polygons, 8, 8);
        assert_eq!(think_on(&mut m, win(0, 0, 8, 8)), Resolution::Surrounded);
        // ...and wins when it is earlier.
        let polygons = [
            square(RED, 2.0, 2.0, 4.0, 4.0, 0.5),
            square(GREEN, 0.0, 0.0, 8.0, 8.0, 0.5),
        ];
        let mut m = loaded(&polygons, 8, 8);
        assert_eq!(think_on(&mut m, win(0, 0, 8, 8)), Resolution::InFront);
        assert_eq!(picture(&mut m)[2 * 8 + 2], Some(RED));
        assert_eq!(picture(&mut m)[0], Some(GREEN));
    }

    #[test]
    fn penetrating_planes_are_subdivided_down_to_pixels_along_their_crossing() {
        // Two squares over the whole 16x16 screen whose planes cross at X = 5.3: left of
        // it red is in front, right of it green.
        let c = 5.3;
        let plane = |colour, slope: f64| {
            let z = |x: f64| 0.5 + slope * (x - c);
            Polygon::from_xyz(
                colour,
                &[
                    [0.0, 0.0, z(0.0)],
                    [16.0, 0.0, z(16.0)],
                    [16.0, 16.0, z(16.0)],
                    [0.0, 16.0, z(0.0)],
                ],
            )
        };
        let polygons = [plane(RED, 0.02), plane(GREEN, -0.01)];
        let (runs, m) = resolved(&polygons, 16, 16);
        assert_eq!(
            differing_pixels(&image_of(&runs, 16, 16), &zbuffer_image(&polygons, 16, 16)),
            0
        );
        // Every row: red 0..5, green 5..16 (the crossing is between centres 4.5 and 5.5).
        assert_eq!(runs.len(), 32);
        assert_eq!((runs[0].x0, runs[0].x1, runs[0].colour), (0, 5, RED));
        assert_eq!((runs[1].x0, runs[1].x1, runs[1].colour), (5, 16, GREEN));
        // The windows holding column 4.5..5.5 fail at every size: columns 0..8, 4..8,
        // 4..6 and then the pixels of columns 4 and 5, down all 16 rows.
        assert_eq!(m.stats.windows_by_depth, vec![1, 4, 8, 16, 32]);
        assert_eq!(
            (m.stats.subdivided, m.stats.surrounded, m.stats.pixels),
            (1 + 2 + 4 + 8, 2 + 4 + 8, 32)
        );
        // The Looker reads each polygon's 16 rows once, for the first window; both
        // surround it, so no descendant looks again (the ancestral check).
        assert_eq!(m.stats.looker_rows, 32);
    }

    #[test]
    fn runs_are_maximal_and_in_row_order_and_offset_by_the_bounding_box() {
        let polygons = [
            square(RED, 3.0, 2.0, 6.0, 4.0, 0.5),
            square(RED, 6.0, 2.0, 9.0, 3.0, 0.25),
        ];
        let (runs, _) = resolved(&polygons, 12, 6);
        let got: Vec<(u32, u32, u32)> = runs.iter().map(|r| (r.y, r.x0, r.x1)).collect();
        assert_eq!(got, vec![(2, 3, 9), (3, 3, 6)]);
        // Nothing covered: no runs, no windows.
        let (runs, m) = resolved(&[square(RED, -5.0, 0.0, -1.0, 4.0, 0.5)], 12, 6);
        assert!(runs.is_empty());
        assert!(m.stats.windows_by_depth.is_empty());
    }

    mod properties {
        use super::*;
        use proptest::prelude::*;

        /// 37×29: odd sizes, so windows are clipped squares of every shape.
        const W: u32 = 37;
        const H: u32 = 29;

        /// A depth plane `z = z0 + gx·X + gy·Y`: a few shared flat depths (ties and
        /// coincident polygons), random slopes (interpenetration), steep slopes, and
        /// depths past the fixed point's range (saturation).
        fn plane() -> impl Strategy<Value = (f64, f64, f64)> {
            prop_oneof![
                3 => prop::sample::select(vec![0.25, 0.5, 0.75]).prop_map(|z| (z, 0.0, 0.0)),
                4 => (0.1f64..0.9, -0.02f64..0.02, -0.02f64..0.02),
                1 => (0.1f64..0.9, -2.0f64..2.0, -2.0f64..2.0),
                1 => (-1e7f64..1e7, -1e6f64..1e6, -1e6f64..1e6),
            ]
        }

        /// The outline of a polygon in screen coordinates.
        fn outline() -> impl Strategy<Value = Vec<(f64, f64)>> {
            let (w, h) = (W as f64, H as f64);
            prop_oneof![
                // Anything: convex, concave, self-intersecting (bowties), reaching past
                // the screen.
                4 => prop::collection::vec((-4.0..w + 4.0, -4.0..h + 4.0), 3..8),
                // Small: within a pixel or three, many of them cover nothing.
                3 => ((0.0..w, 0.0..h), prop::collection::vec((-1.5f64..1.5, -1.5f64..1.5), 3..5))
                    .prop_map(|((cx, cy), d)| d.iter().map(|(dx, dy)| (cx + dx, cy + dy)).collect()),
                // Slivers: long and a fraction of a pixel wide.
                2 => ((-2.0..w + 2.0, -2.0..h + 2.0), (-2.0..w + 2.0, -2.0..h + 2.0), -0.6f64..0.6)
                    .prop_map(|((ax, ay), (bx, by), t)| {
                        let (nx, ny) = (-(by - ay), bx - ax);
                        let len = (nx * nx + ny * ny).sqrt().max(1e-9);
                        let (mx, my) = ((ax + bx) / 2.0, (ay + by) / 2.0);
                        vec![(ax, ay), (mx + t * nx / len, my + t * ny / len), (bx, by)]
                    }),
                // Big: vertices out in the guard band.
                1 => prop::collection::vec((-15.0 * w..16.0 * w, -15.0 * h..16.0 * h), 3..6),
            ]
        }

        fn polygon(colour: Colour, pts: &[(f64, f64)], (z0, gx, gy): (f64, f64, f64)) -> Polygon {
            let v: Vec<[f64; 3]> = pts
                .iter()
                .map(|&(x, y)| [x, y, z0 + gx * x + gy * y])
                .collect();
            Polygon::from_xyz(colour, &v)
        }

        /// A frame: random polygons, some repeated later in another colour (coincident),
        /// and optionally a jittered triangle mesh (shared edges) on one plane.
        fn frame() -> impl Strategy<Value = Vec<Polygon>> {
            (
                prop::collection::vec((outline(), plane()), 0..24),
                prop::collection::vec(any::<prop::sample::Index>(), 0..3),
                prop::option::of((
                    plane(),
                    prop::collection::vec((-0.3f64..0.3, -0.3f64..0.3), 25),
                )),
                any::<bool>(),
            )
                .prop_map(|(shapes, repeats, mesh, few_colours)| {
                    // Few colours: neighbours of one colour join into runs; many: every
                    // polygon is told apart, ties included.
                    let colour = |i: usize| -> Colour {
                        if few_colours {
                            [(i % 3) as u8 * 100, 50, 0]
                        } else {
                            [i as u8, (i / 256) as u8, 7]
                        }
                    };
                    let mut polygons: Vec<Polygon> = shapes
                        .iter()
                        .enumerate()
                        .map(|(i, (o, p))| polygon(colour(i), o, *p))
                        .collect();
                    if !shapes.is_empty() {
                        for r in repeats {
                            let (o, p) = &shapes[r.index(shapes.len())];
                            polygons.push(polygon(colour(polygons.len()), o, *p));
                        }
                    }
                    if let Some((p, jitter)) = mesh {
                        let at = |i: usize, j: usize| {
                            let (dx, dy) = if i == 0 || j == 0 || i == 4 || j == 4 {
                                (0.0, 0.0)
                            } else {
                                jitter[j * 5 + i]
                            };
                            (
                                -1.0 + (W as f64 + 2.0) / 4.0 * (i as f64 + dx),
                                -1.0 + (H as f64 + 2.0) / 4.0 * (j as f64 + dy),
                            )
                        };
                        for j in 0..4 {
                            for i in 0..4 {
                                let (a, b, c, d) =
                                    (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                                let n = polygons.len();
                                polygons.push(polygon(colour(n), &[a, b, c], p));
                                polygons.push(polygon(colour(n + 1), &[a, c, d], p));
                            }
                        }
                    }
                    polygons
                })
        }

        proptest! {
            #![proptest_config(ProptestConfig::with_cases(512))]

            /// Warnock's picture is the z-buffer's, pixel for pixel, and its runs are in
            /// row order, disjoint and maximal.
            #[test]
            fn warnock_is_the_zbuffer(polygons in frame()) {
                let (runs, m) = resolved(&polygons, W, H);
                let image = image_of(&runs, W, H);
                prop_assert_eq!(differing_pixels(&image, &zbuffer_image(&polygons, W, H)), 0);
                for pair in runs.windows(2) {
                    let (a, b) = (pair[0], pair[1]);
                    prop_assert!((a.y, a.x1) <= (b.y, b.x0), "{:?} then {:?}", a, b);
                    prop_assert!(a.y != b.y || a.x1 != b.x0 || a.colour != b.colour, "{:?} {:?} not joined", a, b);
                }
                // Every window visited was resolved one way or subdivided.
                let s = &m.stats;
                let visited: u64 = s.windows_by_depth.iter().sum();
                prop_assert_eq!(visited, s.empty + s.pixels + s.one_polygon + s.surrounded + s.in_front + s.subdivided);
            }

            /// Frames one after another in one Warnock give each frame's own picture.
            #[test]
            fn frames_are_independent(a in frame(), b in frame()) {
                let mut m = Warnock::new();
                for polygons in [&a, &b, &a] {
                    let mut runs = vec![];
                    m.resolve(polygons, W, H, &mut runs);
                    prop_assert_eq!(image_of(&runs, W, H), zbuffer_image(polygons, W, H));
                }
            }
        }
    }
}
