//! # warnock: Warnock's area subdivision at a leaf of the splitter tree
//! (seeds/004_…, 14.3 and Appendix VI; docs/DESIGN.md, "Leaves resolve visibility")
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
//! The seed's Looker clips polygon edges against the window in real coordinates; here
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
//! - Depth is the fixed-point depth of [`scan::DepthPlane`]: pixel x of row y has
//!   `depth_at(z_row, dz, x)`, smaller in front, a tie to the polygon earlier in the
//!   stream. On a row it is linear in x, so whether polygon A is in front of polygon B
//!   over a stretch of the row is decided by its two end columns (unless a depth there
//!   sits at the `i64` bounds, where it may be saturated: then nothing is decided and the
//!   window is subdivided). The seed compares the planes at the window's four corners,
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
//! their line of intersection and are subdivided down to pixels there, as the seed says
//! the implied edge is found (14.3.3, Figure 14-18).
//!
//! Output: the resolved windows paint a buffer over the coverage's bounding box, which
//! is sent row by row as maximal runs of one colour, the same runs `scanconv --resolve`
//! sends.

use proto::{Colour, Polygon};
use scan::frame::{push_row_runs, HiddenSurface};
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
    dz: i64,
    colour: Colour,
}

/// One row of a polygon: where its spans start, and its depth at column 0.
#[derive(Clone, Copy, Debug)]
struct Row {
    start: usize,
    z_row: i64,
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
    /// The frame's picture over the bounding box of its coverage.
    image: Vec<Option<Colour>>,
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
            let mut first: Option<(u32, i64)> = None;
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
                        z_row: 0,
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
                z_row: 0,
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
    fn row_spans(&self, c: &Coverage, y: u32) -> (&[(u32, u32)], i64) {
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
                if [da, db].iter().any(|&d| d == i64::MIN || d == i64::MAX) {
                    result = None;
                    break 'rows;
                }
                if !(da < db || (da == db && a < b)) {
                    result = Some(false);
                    break 'rows;
                }
            }
        }
        self.stats.depth_rows += compared;
        result
    }

    /// The depth of polygon `poly` at pixel (x, y), which it covers.
    fn depth(&self, poly: u32, x: u32, y: u32) -> i64 {
        let c = &self.covs[poly as usize];
        let (_, z_row) = self.row_spans(c, y);
        depth_at(z_row, c.dz, x)
    }

    fn fill(&mut self, w: Window, colour: Colour) {
        let b = self.bbox;
        let bw = b.width() as usize;
        for y in w.y0..w.y1 {
            let at = (y - b.y0) as usize * bw;
            self.image[at + (w.x0 - b.x0) as usize..at + (w.x1 - b.x0) as usize].fill(Some(colour));
        }
    }

    /// Draws the pixels of window `w` that polygon `poly` covers.
    fn draw(&mut self, poly: u32, w: Window) {
        let c = self.covs[poly as usize];
        let b = self.bbox;
        let bw = b.width() as usize;
        for y in w.y0.max(c.y0)..w.y1.min(c.y1) {
            let i = c.row + (y - c.y0) as usize;
            let at = (y - b.y0) as usize * bw;
            for s in self.rows[i].start..self.rows[i + 1].start {
                let (s0, s1) = self.spans[s];
                let (s0, s1) = (s0.max(w.x0), s1.min(w.x1));
                if s0 < s1 {
                    self.image[at + (s0 - b.x0) as usize..at + (s1 - b.x0) as usize]
                        .fill(Some(c.colour));
                }
            }
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
            // Display by default: every polygon of a one-pixel window's list covers it.
            let best = self.lists[start..]
                .iter()
                .map(|e| (self.depth(e.poly, w.x0, w.y0), e.poly))
                .min()
                .expect("the list is not empty");
            self.fill(w, self.covs[best.1 as usize].colour);
            return Resolution::Pixel;
        }
        if n == 1 {
            let e = self.lists[start];
            if e.surrounds {
                self.fill(w, self.covs[e.poly as usize].colour);
                return Resolution::Surrounded;
            }
            self.draw(e.poly, w);
            return Resolution::OnePolygon;
        }
        // The candidate hider: the nearest surrounder at the window's first pixel.
        let Some((_, hider)) = self.lists[start..]
            .iter()
            .filter(|e| e.surrounds)
            .map(|e| (self.depth(e.poly, w.x0, w.y0), e.poly))
            .min()
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
                    self.fill(w, self.covs[hider as usize].colour);
                    self.draw(other, w);
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
        let w = self.clip(sx, sy, size).expect("visited windows are not empty");
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
        (x0 < x1 && y0 < y1).then(|| Window {
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
        self.image.clear();
        self.image
            .resize(b.width() as usize * (b.y1 - b.y0) as usize, None);
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
        let bw = b.width() as usize;
        for (i, row) in self.image.chunks_exact(bw).enumerate() {
            let first = runs.len();
            push_row_runs(b.y0 + i as u32, row, runs);
            for r in &mut runs[first..] {
                r.x0 += b.x0;
                r.x1 += b.x0;
            }
        }
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
