//! # warnock: Warnock's area subdivision at a leaf of the splitter tree
//!
//! Newman and Sproull (1973), 14.3, and their Appendix VI (the Looker and
//! Thinker of AVI.1 and AVI.2, and the SAIL listing `WARNOCK (LEFT, BOTTOM, SIZE)`);
//! docs/DESIGN.md, "Leaves resolve visibility"; docs/methods.md, "warnock".
//!
//! Warnock examines *windows* of the screen instead of polygons (14.3). For a window the
//! **Looker** sorts the polygons still in question into surrounders, intersectors and
//! disjoint ones (AVI.1), the **Thinker** decides whether what is left is simple enough to
//! display (AVI.2), and the **Controller** subdivides a window the Thinker fails on into
//! four, depth first, down to single pixels, which are **displayed by default** (14.3.1).
//! Everything above the pixel is decided in object space, on the polygons' screen
//! coordinates, so the cost follows the windows the picture needs, not the pixels the
//! polygons cover (14.3.4: "computation time is proportional to *visible* complexity").
//!
//! ## Windows and their sample rectangle
//!
//! A window is a block of pixels `x0..x1` × `y0..y1`; the listing's squares of side SIZE,
//! halved at each level, clipped to the frame's bounding box on the screen. What a window
//! shows is decided at its pixel centres (docs/DESIGN.md, "Coverage"), so the Looker and
//! the Thinker work on the window's **sample rectangle**, the hull of its centres,
//! `[x0+½, x1−½] × [y0+½, y1−½]`, instead of the listing's `[LEFT, LEFT+SIZE−EPSILON]`:
//! a polygon that surrounds the sample rectangle covers every pixel of the window.
//!
//! ## The Looker (AVI.1)
//!
//! For each polygon of the parent's list, in the listing's order (by ZMIN, the nearest
//! vertex depth, nearest first):
//!
//! 1. **ZMIN early exit**: `IF POLY!ZMIN[P] > ZMINMAX THEN DONE`. ZMINMAX is the smallest,
//!    over the surrounders found so far, of the surrounder's largest depth at the sample
//!    rectangle's corners: a polygon whose nearest vertex is farther than that lies behind
//!    a surrounder everywhere in the window, and so does every polygon after it.
//! 2. **Ancestral check** (the listing's HISTORY): a surrounder of the parent surrounds
//!    the child; a polygon disjoint from the parent is not in the parent's list.
//! 3. **Bounding-box quick reject** (Figure AVI-1): the polygon's box misses the sample
//!    rectangle: disjoint.
//! 4. **Edges against the window**: an edge whose box meets the rectangle and whose line
//!    does not have all four corners strictly on one side ("substitute the coordinates of
//!    the corners of the window into the line equation of the edge") passes through the
//!    window: an intersector.
//! 5. Otherwise no edge comes near the window, and the polygon either surrounds it or is
//!    disjoint from it: Warnock's own test decides, a line from the window to a point
//!    outside the polygon and the parity of the edges it crosses (AVI.1, Figure AVI-3).
//!    The parity is the even-odd rule of the coverage, so a self-intersecting polygon is
//!    judged as the z-buffer fills it (the angle count of Figure AVI-5 gives the winding
//!    number instead, which would call a doubly wound region surrounded).
//!
//! The rectangle is widened by a millionth of a pixel for steps 3 and 4, so an edge that
//! merely touches it (or a piece cut by the splitter tree, whose coverage is computed on
//! its whole edge) is an intersector: an intersector is always safe, it only costs a
//! subdivision; surrounder and disjoint are only said when they hold for every centre.
//!
//! ## The Thinker (AVI.2, the listing's "smart Thinker")
//!
//! Depths are compared at the sample rectangle's four corners (the listing's
//! `GETZ (P, WLX, WBY)` …): each polygon's depth there is the z-buffer's own depth of that
//! pixel ([`scan::DepthPlane`]), compared by [`scan::takes`] with the tie to the polygon
//! earlier in the stream. Polygon A is *in front of* B over the window when it wins all
//! four corners and the earlier one's depth has one sign at all four; depth is affine on
//! the screen, and the tie then a fixed fraction of the held depth, so A then wins at
//! every centre between (B's plane extended over the window: "sufficient but not
//! necessary", AVI.1.1). Where the held depth changes sign the tie rule can change its
//! answer twice across the window, so the window is not decided so.
//!
//! 1. An empty list: nothing is drawn (the background shows).
//! 2. A one-pixel window: displayed by default, the z-buffer's rule at its centre: the
//!    polygons whose coverage holds the centre folded in stream order by [`scan::takes`],
//!    as the z-buffer folds them (the tie rule is not transitive: the nearest by pairs is
//!    not always the fold's).
//! 3. The **hider** (the listing's critical surrounder): of the surrounders, the one in
//!    front at the first corner; if another surrounder is not behind it at all four
//!    corners, the surrounders penetrate: fail.
//! 4. Polygons the hider is in front of are taken off the list, for this window and its
//!    descendants ("remove from intersectors list any polygons hidden by the hider"),
//!    where that cannot change the z-buffer's fold: each one behind every polygon that
//!    stays by more than the tie width, or one that every other polygon is in front of
//!    (`Warnock::separable`). A hidden polygon within the tie width of another that
//!    stays can decide who keeps a pixel the hider takes in the end (differential seed
//!    200470), and stays on the list.
//! 5. Every intersector left must be in front of the hider at all four corners, or it
//!    penetrates it: fail.
//! 6. No intersector left: the hider fills the window (or, without a hider, the window
//!    is empty). One left: it is clipped to the window and displayed over the hider
//!    ("display by computation if only one intersector polygon lies in front of a
//!    surrounder", Thinker 2, I = 1). More: fail.
//!
//! A failed window is split in four; penetrating polygons fail along their line of
//! intersection down to pixels (14.3.3, Figure 14-18).
//!
//! ## Against the z-buffer
//!
//! Coverage is the z-buffer's wherever a window is drawn (one intersector's spans come
//! from [`scan::SpanWalker`], pixel windows test their centre with it too), and depths
//! are its per-pixel depths. What can differ is the corner test's premise: the z-buffer
//! rounds each row's depth to fixed point, so its depths are affine across a window only
//! to one unit of the last place. Two planes that come within a unit of each other
//! inside a window, but not at its corners, can be ordered differently there; the ZMIN
//! early exit compares the vertices' depths with the planes of the surrounder and of
//! every polygon kept in `f64`, with the same margin. docs/methods.md counts the pixels
//! this changes on the test scenes.
//!
//! Gouraud shading (docs/DESIGN.md, "Shading") changes nothing of the above: a shaded
//! polygon that fills a window, or is drawn as its one intersector, puts its pieces of rows
//! on the lists pixel by pixel in its colour planes' value at each centre (`proto::shade`,
//! the z-buffer's calls), as runs of one colour.
//!
//! Output: each resolved window puts its pieces of rows on its rows' lists, which are
//! sent at the frame's end row by row as maximal runs of one colour, the runs
//! `scanconv --resolve` sends.

use proto::shade::{Lighting, Shading};
use proto::{Colour, DVec2, Polygon};
use scan::frame::{shaded_runs, HiddenSurface};
use scan::{depth_at, takes, Depth, DepthPlane, Run, SpanWalker};
use std::sync::Arc;

/// How a window was resolved (for `--stats`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Resolution {
    /// No polygon left in its list.
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

/// The Looker's class of a polygon for a window (Figure 14-13), on its sample rectangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Class {
    /// Covers none of the window's pixel centres.
    Disjoint,
    /// May cover some of them: an edge passes near the window.
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
    fn is_pixel(&self) -> bool {
        self.x1 - self.x0 == 1 && self.y1 - self.y0 == 1
    }

    /// The centres of its corner pixels, in the listing's order of `GETZ` calls.
    fn corners(&self) -> [(u32, u32); 4] {
        let (x1, y1) = (self.x1 - 1, self.y1 - 1);
        [(self.x0, self.y0), (self.x0, y1), (x1, self.y0), (x1, y1)]
    }

    /// The sample rectangle (the hull of the pixel centres), widened by [`MARGIN`].
    fn sample_rectangle(&self) -> (DVec2, DVec2) {
        (
            DVec2::new(self.x0 as f64 + 0.5 - MARGIN, self.y0 as f64 + 0.5 - MARGIN),
            DVec2::new(self.x1 as f64 - 0.5 + MARGIN, self.y1 as f64 - 0.5 + MARGIN),
        )
    }
}

/// How far (pixels) the Looker widens a window's sample rectangle: an edge this close to
/// it makes its polygon an intersector, and the window is subdivided down to pixels,
/// whose centres the scan converter's exact coverage decides. The Looker classifies the
/// unsnapped polygon, while coverage is decided on its vertices snapped to 1/256 pixel
/// and, for a piece cut by a splitter, on its edges' snapped supports (docs/DESIGN.md,
/// "Coverage"): an edge of either lies within 1/512·√2 pixel of the unsnapped edge (a
/// support's, on the piece, within twice that), so a margin of 1/64 pixel keeps every
/// centre the Looker calls surrounded or disjoint on the same side of both.
const MARGIN: f64 = 1.0 / 64.0;

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
    /// Polygons the Looker classified against a window (edges clipped, parity counted);
    /// a surrounder known from an ancestor is not looked at again.
    pub looked_at: u64,
    /// Polygons the hider took off a window's list.
    pub hidden: u64,
    /// Windows whose Looker stopped early at the ZMIN test, and the polygons it left
    /// unexamined there.
    pub zmin_exits: u64,
    pub zmin_skipped: u64,
}

/// A polygon of the frame that may cover something, as the Looker and Thinker see it.
#[derive(Clone, Copy, Debug)]
struct Face {
    /// Its place in the stream (a tie goes to the smaller).
    poly: u32,
    /// Its screen points: `points[start..start + len]`.
    start: u32,
    len: u32,
    /// Its bounding box (Figure AVI-1).
    min: DVec2,
    max: DVec2,
    /// The listing's POLY!ZMIN: its nearest vertex depth, on its plane; and its farthest.
    zmin: f64,
    zmax: f64,
    /// Its plane in `f64`, depth = −(a·X + b·Y + d)/c (AVI.1.1), for the ZMIN test;
    /// `None` seen edge-on.
    plane: Option<[f64; 4]>,
    /// Its depth at a pixel, as the z-buffer has it.
    depth: DepthPlane,
    colour: Colour,
}

impl Face {
    /// Its depth at the centre of pixel (x, y): the z-buffer's.
    fn pixel_depth(&self, x: u32, y: u32) -> Depth {
        let (z_row, dz) = self.depth.row(y);
        depth_at(z_row, dz, x)
    }

    /// Its depth at the centre of pixel (x, y) where that depth follows its plane, so
    /// that comparisons at a window's corners hold at every centre between: not where
    /// the depth, its row's origin or its step is clamped, nor where the rounding of
    /// `z_row + x·dz` may be more than 2⁻¹⁰ of the tie rule's width (a plane so steep
    /// that its terms cancel: a vertex at depth 1e135 two pixels from others at 0.25
    /// leaves the z-buffer's depths there rounding noise, which only a pixel can decide).
    fn planar_depth(&self, x: u32, y: u32) -> Option<Depth> {
        let (z_row, dz) = self.depth.row(y);
        let d = depth_at(z_row, dz, x);
        if clamped(z_row) || clamped(dz) || clamped(d) {
            return None;
        }
        if let DepthPlane::Plane { a, b, c, d: e, .. } = self.depth {
            // A bound on the rounding: a few ulps of each term's magnitude.
            let terms = (a.abs() * 0.5 + b.abs() * (y as f64 + 0.5) + e.abs()) / c.abs()
                + x as f64 * dz.abs()
                + d.abs();
            // Written so that a NaN bound refuses too.
            let affine = 4.0 * f64::EPSILON * terms <= proto::depth::TIE / 1024.0 * d.abs();
            if !affine {
                return None;
            }
        }
        Some(d)
    }

    /// Its largest depth at the corners of `w`'s sample rectangle (the listing's
    /// maximum of Z1…Z4), in `f64`.
    fn farthest_at(&self, w: Window) -> f64 {
        let Some([a, b, c, d]) = self.plane else {
            return self.zmax;
        };
        w.corners()
            .iter()
            .map(|&(x, y)| -(a * (x as f64 + 0.5) + b * (y as f64 + 0.5) + d) / c)
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// Its depth at the centre of pixel (x, y) in `f64` (the ZMIN test at a pixel): its
    /// plane's, or without one the z-buffer's (not its ZMIN, which may be −∞).
    fn depth_at_centre(&self, x: u32, y: u32) -> f64 {
        match self.plane {
            Some([a, b, c, d]) => -(a * (x as f64 + 0.5) + b * (y as f64 + 0.5) + d) / c,
            None => self.pixel_depth(x, y),
        }
    }
}

/// Puts columns `x0..x1` of row `y` on the row's list of pieces: in `colour`, or, for a
/// Gouraud-shaded polygon, each pixel in its colour at the centre (runs of one colour).
#[inline]
fn push_piece(
    row: &mut Vec<(u32, u32, Colour)>,
    shading: Option<&Shading>,
    (y, x0, x1): (u32, u32, u32),
    colour: Colour,
) {
    match shading {
        None => row.push((x0, x1, colour)),
        Some(s) => shaded_runs(s, y, x0..x1, |a, b, c| row.push((a, b, c))),
    }
}

/// Does polygon `a`, at depth `da` at a pixel, beat polygon `b` at depth `db` there (the
/// tie rule: the later one must [`takes`] the pixel from the earlier)?
fn beats(a: &Face, da: Depth, b: &Face, db: Depth) -> bool {
    proto::depth::in_front(da, a.poly >= b.poly, db)
}

/// A depth (or a depth step) that may have been clamped to the representation's range:
/// nothing is decided from it but at a pixel.
fn clamped(d: Depth) -> bool {
    d == Depth::MIN || d == Depth::MAX
}

/// An entry of a window's polygon list: an index into the frame's faces (ZMIN order)
/// and whether it is known to surround the window.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Entry {
    face: u32,
    surrounds: bool,
}

/// Warnock's area subdivision as a [`HiddenSurface`]. Its buffers are kept from frame
/// to frame.
#[derive(Default)]
pub struct Warnock {
    walker: SpanWalker,
    /// The frame's faces, sorted by ZMIN (the listing's polygon list).
    faces: Vec<Face>,
    points: Vec<DVec2>,
    /// Scratch: a polygon's vertices snapped to the sub-pixel grid.
    snapped: Vec<proto::raster::Point>,
    /// The window lists of the windows on the current path of the subdivision, each on
    /// top of its ancestor's (the listing's HISTORY, one level per window).
    lists: Vec<Entry>,
    /// The frame's finished pieces of rows, `(x0, x1, colour)`, one list per row of the
    /// frame's bounding box: memory for what the windows draw.
    pieces: Vec<Vec<(u32, u32, Colour)>>,
    /// Scratch for one intersector's spans.
    spans: Vec<(u32, u32, u32)>,
    /// Scratch for the polygons covering one pixel's centre, and their depths there.
    covering: Vec<(Face, Depth)>,
    /// Scratch for the faces a hider takes off a window's list.
    hidden: Vec<u32>,
    /// The frame's polygons' Gouraud shading, by stream index, when any is shaded (empty
    /// for a flat frame).
    shadings: Vec<Option<Shading>>,
    /// The stream's lighting, for Phong shading.
    lighting: Option<Arc<Lighting>>,
    bbox: Window,
    width: u32,
    pub stats: Stats,
    /// When set, every window visited and how it was resolved, in the order visited
    /// (for pictures of the subdivision: `cargo run --example windows`).
    pub record: Option<Vec<(Window, Resolution)>>,
}

impl Warnock {
    pub fn new() -> Self {
        Warnock::default()
    }

    /// The listing's INITIALIZE: each polygon's box, plane and ZMIN, the list sorted by
    /// ZMIN. Polygons of fewer than three vertices, or with all on one line once snapped, cover no
    /// centre and are left out.
    fn gather(&mut self, polygons: &[Polygon], width: u32, height: u32) {
        self.faces.clear();
        self.points.clear();
        self.width = width;
        self.shadings.clear();
        if polygons.iter().any(Polygon::is_shaded) {
            let lighting = self.lighting.as_ref();
            self.shadings
                .extend(polygons.iter().map(|p| Shading::of(p, lighting)));
        }
        for (i, p) in polygons.iter().enumerate() {
            let start = self.points.len();
            self.points
                .extend(p.vertices.iter().map(|v| DVec2::new(v.x, v.y)));
            let pts = &self.points[start..];
            // On one line as the walker decides it, on the vertices snapped to 1/256
            // pixel (docs/DESIGN.md, "Coverage"): three points within rounding of a line
            // may snap apart, a sliver that holds the centres it passes over.
            // A piece whose edges cross rows on their supports covers what lies between
            // them even there, as the walker has it.
            self.snapped.clear();
            self.snapped
                .extend(pts.iter().map(|&v| proto::raster::Point::snap(v)));
            let supports = p.supports.iter().flatten().flatten();
            let supports = supports.map(|v| proto::raster::Point::snap(DVec2::new(v.x, v.y)));
            if pts.len() < 3 || proto::raster::snapped_covers_nothing(&self.snapped, supports) {
                self.points.truncate(start);
                continue;
            }
            let min = pts.iter().copied().fold(DVec2::INFINITY, DVec2::min);
            let max = pts.iter().copied().fold(DVec2::NEG_INFINITY, DVec2::max);
            let n = p
                .plane
                .filter(|n| n.z != 0.0 && n.is_finite())
                .unwrap_or_else(|| {
                    let v: Vec<_> = p.vertices.iter().map(|v| v.truncate()).collect();
                    proto::geometry::newell_plane(&v)
                });
            let plane = (n.z != 0.0 && n.is_finite()).then_some([n.x, n.y, n.z, n.w]);
            // ZMIN and ZMAX of the plane the pixels get, at the vertices (where an affine
            // depth has its extremes over the polygon): a polygon that is not planar has
            // vertex depths off its plane, and the listing's test must bound the plane.
            let zs = p.vertices.iter().map(|v| match plane {
                Some([a, b, c, d]) => -(a * v.x + b * v.y + d) / c,
                None => v.z,
            });
            let zmin = zs.clone().fold(f64::INFINITY, f64::min);
            let zmax = zs.fold(f64::NEG_INFINITY, f64::max);
            let mut face = Face {
                poly: i as u32,
                start: start as u32,
                len: (self.points.len() - start) as u32,
                min,
                max,
                zmin,
                zmax,
                plane,
                depth: DepthPlane::of(p),
                colour: p.colour,
            };
            // A polygon whose plane is not finite across the screen gets one depth from
            // the z-buffer, its nearest vertex's (`DepthPlane::Flat`): its plane in `f64`
            // then says nothing of its pixels, and ZMIN and ZMAX are that depth.
            if let DepthPlane::Flat(z) = face.depth {
                face.plane = None;
                face.zmin = z;
                face.zmax = z;
            }
            // Where the z-buffer's depth of a polygon leaves its plane (clamped at a row's
            // origin, column 0, which may lie far outside the polygon), its vertices say
            // nothing of the depths the z-buffer gives it: such a polygon is never passed
            // over by the ZMIN test, it sorts first.
            let (cols, rows) = (
                [min.x, max.x].map(|x| x.floor().clamp(0.0, width.saturating_sub(1) as f64) as u32),
                [min.y, max.y]
                    .map(|y| y.floor().clamp(0.0, height.saturating_sub(1) as f64) as u32),
            );
            // So is one whose depth changes sign over its box: the relative rounding bound
            // of `planar_depth` fails where a depth passes through 0, and a plane so steep
            // that it does (the fuzzer's vertex at 3.6e88) gives pixels depths far from
            // its vertices' (-4.5e89 to 7.5e89 inside a polygon whose vertices say 1.4e73
            // and up). Real depths never do: reciprocal depth is negative everywhere.
            let corner_depths =
                [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(i, j)| face.planar_depth(cols[i], rows[j]));
            let one_sign = corner_depths.iter().all(|d| d.is_some_and(|d| d < 0.0))
                || corner_depths.iter().all(|d| d.is_some_and(|d| d > 0.0));
            if !one_sign {
                face.zmin = f64::NEG_INFINITY;
            }
            self.faces.push(face);
        }
        // Nearest first; equal ZMINs in stream order (a stable sort).
        self.faces.sort_by(|a, b| a.zmin.total_cmp(&b.zmin));
        let (w, h) = (width as f64, height as f64);
        let b = self
            .faces
            .iter()
            .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |b, f| {
                (b.0.min(f.min), b.1.max(f.max))
            });
        let x0 = b.0.x.floor().clamp(0.0, w) as u32;
        let y0 = b.0.y.floor().clamp(0.0, h) as u32;
        let x1 = b.1.x.ceil().clamp(0.0, w) as u32;
        let y1 = b.1.y.ceil().clamp(0.0, h) as u32;
        self.bbox = if x0 < x1 && y0 < y1 {
            Window { x0, y0, x1, y1 }
        } else {
            Window::default()
        };
    }

    fn face_points(&self, f: &Face) -> &[DVec2] {
        &self.points[f.start as usize..(f.start + f.len) as usize]
    }

    /// The Looker (AVI.1): face `face`'s class for window `w`, from its screen geometry.
    pub fn classify(&self, face: u32, w: Window) -> Class {
        let f = &self.faces[face as usize];
        let (lo, hi) = w.sample_rectangle();
        // The bounding-box quick reject (Figure AVI-1).
        if f.max.x < lo.x || f.min.x > hi.x || f.max.y < lo.y || f.min.y > hi.y {
            return Class::Disjoint;
        }
        let pts = self.face_points(f);
        let corners = [lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)];
        for i in 0..pts.len() {
            let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
            if a.x.max(b.x) < lo.x
                || a.x.min(b.x) > hi.x
                || a.y.max(b.y) < lo.y
                || a.y.min(b.y) > hi.y
            {
                continue; // the edge's box misses the window
            }
            // The corners in the edge's line equation: all strictly on one side, or the
            // edge passes through the window.
            let d = b - a;
            let side = corners.map(|c| d.perp_dot(c - a));
            if !(side.iter().all(|&s| s > 0.0) || side.iter().all(|&s| s < 0.0)) {
                return Class::Intersector;
            }
        }
        // No edge near the window: all of it is inside or all outside. A line from its
        // corner to the right, out of the polygon, crosses an odd number of edges when
        // it is inside (AVI.1, Figure AVI-3; a vertex on the line counts on the side of
        // its edges' other ends, as the figure's rule has it).
        let q = lo;
        let mut inside = false;
        for i in 0..pts.len() {
            let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
            if (a.y > q.y) != (b.y > q.y) && q.x < a.x + (q.y - a.y) / (b.y - a.y) * (b.x - a.x) {
                inside = !inside;
            }
        }
        if inside {
            Class::Surrounder
        } else {
            Class::Disjoint
        }
    }

    /// The Looker over a window: the entries of `lists[start..end]` (its parent's list,
    /// ZMIN order) that are not disjoint from `w`, pushed on top; stops at the ZMIN test.
    fn look(&mut self, start: usize, end: usize, w: Window) {
        // The nearest farthest depth of a surrounder kept, and the farthest depth of any
        // polygon kept (+∞ once one may be clamped at a corner).
        let mut zminmax = f64::INFINITY;
        let mut farthest = f64::NEG_INFINITY;
        // The entries kept before `lists[folded..]` are in `farthest`: it is brought up to
        // date only when a surrounder is in front of a polygon (most windows never are).
        let mut folded = self.lists.len();
        for i in start..end {
            let e = self.lists[i];
            let f = self.faces[e.face as usize];
            if takes(zminmax, f.zmin) {
                for k in folded..self.lists.len() {
                    farthest = farthest.max(self.planar_farthest(self.lists[k].face, w));
                }
                folded = self.lists.len();
                if takes(farthest, f.zmin) {
                    // `IF POLY!ZMIN[P] > ZMINMAX THEN DONE`: behind a surrounder, and so
                    // is every polygon after it. "Behind" by the tie rule, and behind
                    // every polygon kept, not only the surrounder: the tie rule is not
                    // transitive, and a polygon left off that is within the tie width of
                    // one kept could change the z-buffer's fold where it covers (it may
                    // hold a pixel that a later polygon then fails to take, or takes).
                    // Behind them all by more than the tie, it holds a pixel only until
                    // the first of them takes it, and takes it from none of them: the
                    // fold over those kept is the fold over all (`decide_pixel`). As the
                    // list is in ZMIN order, every polygon after it passes the test too.
                    self.stats.zmin_exits += 1;
                    self.stats.zmin_skipped += (end - i) as u64;
                    break;
                }
            }
            let class = if e.surrounds {
                Class::Surrounder
            } else {
                self.stats.looked_at += 1;
                self.classify(e.face, w)
            };
            if class == Class::Disjoint {
                continue;
            }
            self.lists.push(Entry {
                face: e.face,
                surrounds: class == Class::Surrounder,
            });
            if class == Class::Surrounder {
                zminmax = zminmax.min(self.planar_farthest(e.face, w));
            }
        }
    }

    /// Face `face`'s farthest depth at `w`'s corners ([`Face::farthest_at`]), or +∞
    /// where its depth may be clamped at a corner: the z-buffer ties what it clamps, and
    /// only a pixel can say who wins the tie, so such a depth sets no bound.
    fn planar_farthest(&self, face: u32, w: Window) -> f64 {
        let f = &self.faces[face as usize];
        let planar = w
            .corners()
            .iter()
            .all(|&(x, y)| f.planar_depth(x, y).is_some());
        if planar {
            f.farthest_at(w)
        } else {
            f64::INFINITY
        }
    }

    /// Is face `a` in front of face `b` at all four corners of `w` (and so at every
    /// centre of it)? Not when a depth there may be clamped.
    fn in_front(&self, a: u32, b: u32, w: Window) -> bool {
        let (fa, fb) = (&self.faces[a as usize], &self.faces[b as usize]);
        // The tie is relative to the earlier polygon's depth, sign and all: where that
        // changes sign inside the window the rule can change its answer twice across it
        // (a polygon 5e-11 nearer wins only near depth 0: differential seed 50385), and
        // the corners say nothing of the centres between. Its depth is monotone along
        // rows and columns, so equal signs at the corners hold inside.
        let a_holds = fa.poly < fb.poly;
        let mut sign = None;
        w.corners().iter().all(
            |&(x, y)| match (fa.planar_depth(x, y), fb.planar_depth(x, y)) {
                (Some(da), Some(db)) => {
                    let held = if a_holds { da } else { db }.is_sign_negative();
                    *sign.get_or_insert(held) == held && beats(fa, da, fb, db)
                }
                _ => false,
            },
        )
    }

    /// Does face `f`'s coverage hold the centre of pixel (x, y)? The z-buffer's own
    /// coverage ([`SpanWalker`] on that row).
    fn covers(&mut self, polygons: &[Polygon], f: &Face, x: u32, y: u32) -> bool {
        let mut hit = false;
        self.walker
            .for_each_span_in(&polygons[f.poly as usize], self.width, y..y + 1, |s| {
                hit |= s.x0 <= x && x < s.x1;
            });
        hit
    }

    /// The Thinker on window `w`, whose list is `lists[start..]`: resolves it and draws
    /// it, or says it must be subdivided. Polygons the hider is in front of are taken off
    /// the list.
    fn think(&mut self, polygons: &[Polygon], w: Window, start: usize) -> Resolution {
        let n = self.lists.len() - start;
        if n == 0 {
            return Resolution::Empty;
        }
        if w.is_pixel() {
            self.decide_pixel(polygons, w, start);
            return Resolution::Pixel;
        }
        // The hider: the surrounder in front at the first corner.
        let (cx, cy) = (w.x0, w.y0);
        let mut hider: Option<u32> = None;
        for e in &self.lists[start..] {
            if !e.surrounds {
                continue;
            }
            let f = &self.faces[e.face as usize];
            hider = match hider {
                Some(h) => {
                    let g = &self.faces[h as usize];
                    if beats(f, f.pixel_depth(cx, cy), g, g.pixel_depth(cx, cy)) {
                        Some(e.face)
                    } else {
                        Some(h)
                    }
                }
                None => Some(e.face),
            };
        }
        let Some(hider) = hider else {
            if n == 1 {
                let face = self.lists[start].face;
                self.draw(polygons, face, w, None);
                return Resolution::OnePolygon;
            }
            return Resolution::Subdivided;
        };
        // The polygons the hider is in front of at every corner are taken off the list
        // only where that cannot change the z-buffer's fold: as a set behind every
        // polygon that stays by more than the tie width ([`Warnock::separable`]).
        let hidden = self.separable(hider, start, w);
        let mut kept = start;
        let mut penetrates = false;
        for i in start..self.lists.len() {
            let e = self.lists[i];
            if hidden.binary_search(&e.face).is_ok() {
                self.stats.hidden += 1;
                continue; // completely hidden: off the list
            }
            if e.face != hider && (e.surrounds || !self.in_front(e.face, hider, w)) {
                penetrates = true;
            }
            self.lists[kept] = e;
            kept += 1;
        }
        self.hidden = hidden;
        self.lists.truncate(kept);
        if penetrates {
            return Resolution::Subdivided;
        }
        let h = &self.faces[hider as usize];
        let hider_paint = (h.poly, h.colour);
        match kept - start {
            1 => {
                self.fill(w, hider_paint);
                Resolution::Surrounded
            }
            2 => {
                let other = self.lists[start..]
                    .iter()
                    .find(|e| e.face != hider)
                    .expect("two entries, one the hider")
                    .face;
                self.draw(polygons, other, w, Some(hider_paint));
                Resolution::InFront
            }
            _ => Resolution::Subdivided,
        }
    }

    /// The faces of `lists[start..]` that the hider hides and that can be taken off the
    /// window's list without changing the z-buffer's fold at any of its pixels.
    ///
    /// The hider in front of a polygon at every corner is not enough under the tie rule,
    /// which is not transitive: with depths 1, 1 − ½t and 1 − t (t the tie width), in
    /// that stream order, the second fails to take the pixel from the first and the
    /// third takes it; without the first, the third fails to take it from the second.
    /// Two things are enough, each for its own reason:
    ///
    /// * A set B of the hidden polygons that is behind every polygon that stays (the
    ///   hider, a surrounder, among them) by more than the tie at every corner, and so at
    ///   every centre: a polygon of B then holds a pixel only until the first of those
    ///   that stay takes it (as from an empty pixel), and takes it from none of them. B
    ///   starts as every polygon the hider is in front of; one not behind the farthest
    ///   that stay by more than the tie stays too, until none is left to move.
    /// * A hidden polygon that every other polygon of the list is in front of at every
    ///   corner by the tie rule (the later ones take the pixel from it, it would take it
    ///   from none of the earlier ones): it takes no pixel from whoever holds one, and
    ///   when it holds one (the first to cover it), the next to come takes it as from an
    ///   empty pixel. So a copy of the hider later in the stream goes, where it ties.
    fn separable(&mut self, hider: u32, start: usize, w: Window) -> Vec<u32> {
        // A face's nearest and farthest depth at the corners, the depths the z-buffer
        // computes there, ±∞ where one may be clamped (never separable).
        let range = |face: u32| {
            let f = &self.faces[face as usize];
            let mut near = f64::INFINITY;
            let mut far = f64::NEG_INFINITY;
            for (x, y) in w.corners() {
                match f.planar_depth(x, y) {
                    Some(d) => (near, far) = (near.min(d), far.max(d)),
                    None => return (f64::NEG_INFINITY, f64::INFINITY),
                }
            }
            (near, far)
        };
        let mut hidden = std::mem::take(&mut self.hidden);
        hidden.clear();
        for i in start..self.lists.len() {
            let face = self.lists[i].face;
            if face != hider && self.in_front(hider, face, w) {
                hidden.push(face);
            }
        }
        if hidden.is_empty() {
            return hidden;
        }
        // The farthest of those that stay: the list less `hidden`, which is in its order.
        let mut farthest = f64::NEG_INFINITY;
        let mut next_hidden = hidden.iter().peekable();
        for i in start..self.lists.len() {
            let face = self.lists[i].face;
            if next_hidden.next_if_eq(&&face).is_none() {
                farthest = farthest.max(range(face).1);
            }
        }
        // The set behind all that stay; those it gives up, one by one.
        let mut given_up = Vec::new();
        loop {
            let before = hidden.len();
            hidden.retain(|&face| {
                let (near, far) = range(face);
                let behind = takes(farthest, near);
                if !behind {
                    farthest = farthest.max(far);
                    given_up.push(face);
                }
                behind
            });
            if hidden.len() == before {
                break;
            }
        }
        for face in given_up {
            let list = &self.lists[start..];
            if list
                .iter()
                .all(|e| e.face == face || self.in_front(e.face, face, w))
            {
                hidden.push(face);
            }
        }
        hidden.sort_unstable(); // for the Thinker's binary search
        hidden
    }

    /// Display by default: the z-buffer's fold at the pixel's centre. The list's polygons
    /// whose coverage holds the centre are taken in stream order, and each later one
    /// takes the pixel from the holder when [`takes`] says so: the tie rule is not
    /// transitive (of three depths each within the tie width of the next, the first and
    /// the third may be farther apart than it), so only the fold in the z-buffer's own
    /// order gives its pixel, not the pairwise nearest in ZMIN order.
    ///
    /// The list is in ZMIN order, so the search stops at the first polygon whose nearest
    /// vertex every covering polygon met so far would take the pixel from: such a polygon
    /// (and every one after it, farther still) can take the pixel from none of them, and
    /// whichever of them comes later in the stream takes it from it, so the fold over
    /// the ones met is the fold over all.
    fn decide_pixel(&mut self, polygons: &[Polygon], w: Window, start: usize) {
        let (x, y) = (w.x0, w.y0);
        // The covering polygons met: (face, depth at the centre as the z-buffer has it).
        let mut covering = std::mem::take(&mut self.covering);
        covering.clear();
        // The farthest of their depths in `f64`, while every one of them is planar there
        // (a depth that may be clamped or be rounding noise sets no bound).
        let mut farthest = Some(f64::NEG_INFINITY);
        for i in start..self.lists.len() {
            let e = self.lists[i];
            let f = self.faces[e.face as usize];
            if !covering.is_empty() && farthest.is_some_and(|z| takes(z, f.zmin)) {
                break;
            }
            if !e.surrounds && !self.covers(polygons, &f, x, y) {
                continue;
            }
            let planar = f.planar_depth(x, y).map(|_| f.depth_at_centre(x, y));
            farthest = farthest.zip(planar).map(|(a, b)| a.max(b));
            covering.push((f, f.pixel_depth(x, y)));
        }
        covering.sort_unstable_by_key(|(f, _)| f.poly);
        let held = covering.iter().copied().reduce(
            |held, (f, d)| {
                if takes(d, held.1) {
                    (f, d)
                } else {
                    held
                }
            },
        );
        self.covering = covering;
        if let Some((f, _)) = held {
            self.fill(w, (f.poly, f.colour));
        }
    }

    /// Fills window `w` with polygon `poly` (its stream index) in `colour`, or, if it is
    /// Gouraud-shaded, in its colour at each pixel centre.
    #[inline]
    fn fill(&mut self, w: Window, (poly, colour): (u32, Colour)) {
        if let Some(Some(_)) = self.shadings.get(poly as usize) {
            return self.fill_shaded(w, poly);
        }
        let y0 = self.bbox.y0;
        for y in w.y0..w.y1 {
            self.pieces[(y - y0) as usize].push((w.x0, w.x1, colour));
        }
    }

    /// [`Warnock::fill`] for a Gouraud-shaded polygon. Apart, so that the flat fill stays
    /// small enough to inline.
    #[inline(never)]
    fn fill_shaded(&mut self, w: Window, poly: u32) {
        let y0 = self.bbox.y0;
        let Some(shading) = &self.shadings[poly as usize] else {
            return;
        };
        for y in w.y0..w.y1 {
            let row = &mut self.pieces[(y - y0) as usize];
            shaded_runs(shading, y, w.x0..w.x1, |a, b, c| row.push((a, b, c)));
        }
    }

    /// Clips face `face` to window `w` and draws the pixels it covers (its spans, the
    /// z-buffer's coverage), and, with `under` (a polygon's stream index and colour), the
    /// rest of the window in that polygon's colours.
    fn draw(&mut self, polygons: &[Polygon], face: u32, w: Window, under: Option<(u32, Colour)>) {
        let f = self.faces[face as usize];
        let mut spans = std::mem::take(&mut self.spans);
        spans.clear();
        self.walker
            .for_each_span_in(&polygons[f.poly as usize], self.width, w.y0..w.y1, |s| {
                let (x0, x1) = (s.x0.max(w.x0), s.x1.min(w.x1));
                if x0 < x1 {
                    spans.push((s.y, x0, x1));
                }
            });
        let by = self.bbox.y0;
        let shading = self.shadings.get(f.poly as usize).and_then(Option::as_ref);
        let under = under.map(|(poly, colour)| {
            let s = self.shadings.get(poly as usize).and_then(Option::as_ref);
            (s, colour)
        });
        let mut k = 0;
        for y in w.y0..w.y1 {
            let row = &mut self.pieces[(y - by) as usize];
            let mut x = w.x0;
            while k < spans.len() && spans[k].0 == y {
                let (_, s0, s1) = spans[k];
                if let Some((us, u)) = under.filter(|_| x < s0) {
                    push_piece(row, us, (y, x, s0), u);
                }
                push_piece(row, shading, (y, s0, s1), f.colour);
                x = s1;
                k += 1;
            }
            if let Some((us, u)) = under.filter(|_| x < w.x1) {
                push_piece(row, us, (y, x, w.x1), u);
            }
        }
        self.spans = spans;
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

    /// The Controller, the listing's `WARNOCK (LEFT, BOTTOM, SIZE)`: visits window `w`
    /// (part of the square of side `size` at (`sx`, `sy`)) at subdivision depth `depth`,
    /// its list being `lists[start..]`.
    fn visit(&mut self, polygons: &[Polygon], sq: (u64, u64, u64), depth: usize, start: usize) {
        let (sx, sy, size) = sq;
        let w = self
            .clip(sx, sy, size)
            .expect("visited windows are not empty");
        if self.stats.windows_by_depth.len() <= depth {
            self.stats.windows_by_depth.resize(depth + 1, 0);
        }
        self.stats.windows_by_depth[depth] += 1;
        let r = self.think(polygons, w, start);
        if let Some(record) = &mut self.record {
            record.push((w, r));
        }
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
            self.look(start, end, child);
            self.visit(polygons, (cx, cy, half), depth + 1, end);
            self.lists.truncate(end);
        }
    }

    /// The part of the square of side `size` at (`sx`, `sy`) inside the frame's
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
        let b = self.bbox;
        if b.x0 >= b.x1 {
            return;
        }
        let rows = (b.y1 - b.y0) as usize;
        self.pieces.truncate(rows);
        self.pieces.resize_with(rows, Vec::new);
        let size = ((b.x1 - b.x0).max(b.y1 - b.y0) as u64).next_power_of_two();
        let (sx, sy) = (b.x0 as u64, b.y0 as u64);
        let root = self.clip(sx, sy, size).expect("the box is not empty");
        self.lists.clear();
        self.lists
            .extend((0..self.faces.len() as u32).map(|face| Entry {
                face,
                surrounds: false,
            }));
        let n = self.lists.len();
        self.look(0, n, root);
        self.visit(polygons, (sx, sy, size), 0, n);
        self.lists.clear();
        self.emit(runs);
    }

    /// A Gouraud- or Phong-shaded polygon's visible pixels take its colour at each
    /// centre, as the z-buffer's do, lit by the stream's lighting.
    fn lighting(&mut self) -> Option<&mut Option<Arc<Lighting>>> {
        Some(&mut self.lighting)
    }

    fn stats(&self) -> String {
        let s = &self.stats;
        let depths: Vec<String> = s.windows_by_depth.iter().map(u64::to_string).collect();
        format!(
            "windows by depth: {}; {} empty, {} single pixels, {} one polygon, \
             {} surrounded, {} one in front of a surrounder, {} subdivided; {} polygons \
             looked at, {} hidden by a surrounder, {} ZMIN exits leaving {} unexamined",
            depths.join(" "),
            s.empty,
            s.pixels,
            s.one_polygon,
            s.surrounded,
            s.in_front,
            s.subdivided,
            s.looked_at,
            s.hidden,
            s.zmin_exits,
            s.zmin_skipped
        )
    }

    fn counters(&self) -> Vec<(&'static str, String)> {
        let s = &self.stats;
        let depths: Vec<String> = s.windows_by_depth.iter().map(u64::to_string).collect();
        let mut c = vec![("windows_by_depth", depths.join(","))];
        c.extend(
            [
                ("empty", s.empty),
                ("single_pixels", s.pixels),
                ("one_polygon", s.one_polygon),
                ("surrounded", s.surrounded),
                ("in_front", s.in_front),
                ("subdivided", s.subdivided),
                ("looked_at", s.looked_at),
                ("hidden", s.hidden),
                ("zmin_exits", s.zmin_exits),
                ("zmin_skipped", s.zmin_skipped),
            ]
            .map(|(k, n)| (k, n.to_string())),
        );
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use scan::frame::{differing_pixels, image_of, square, zbuffer_image};

    fn win(x0: u32, y0: u32, x1: u32, y1: u32) -> Window {
        Window { x0, y0, x1, y1 }
    }

    /// A Warnock with `polygons` gathered on a `w`×`h` screen, nothing drawn yet.
    fn loaded(polygons: &[Polygon], w: u32, h: u32) -> Warnock {
        let mut m = Warnock::new();
        m.gather(polygons, w, h);
        m.bbox = win(0, 0, w, h);
        m.pieces = vec![Vec::new(); h as usize];
        m
    }

    /// What the windows thought about so far have drawn; a pixel drawn twice panics.
    fn picture(m: &mut Warnock) -> Vec<Option<Colour>> {
        let mut runs = vec![];
        let kept = m.pieces.clone();
        m.emit(&mut runs);
        m.pieces = kept;
        image_of(&runs, m.bbox.x1, m.bbox.y1)
    }

    /// The Looker on every gathered polygon for `w`, then the Thinker.
    fn think_on(m: &mut Warnock, polygons: &[Polygon], w: Window) -> Resolution {
        m.lists.clear();
        m.lists.extend((0..m.faces.len() as u32).map(|face| Entry {
            face,
            surrounds: false,
        }));
        let n = m.lists.len();
        m.look(0, n, w);
        m.lists.drain(..n);
        m.think(polygons, w, 0)
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
    fn the_looker_classifies_by_the_windows_sample_rectangle() {
        // Covers pixels 2..6 × 2..6.
        let m = loaded(&[square(RED, 2.0, 2.0, 6.0, 6.0, 0.5)], 8, 8);
        assert_eq!(m.classify(0, win(0, 0, 8, 8)), Class::Intersector);
        assert_eq!(m.classify(0, win(2, 2, 6, 6)), Class::Surrounder);
        assert_eq!(m.classify(0, win(3, 4, 4, 5)), Class::Surrounder);
        assert_eq!(m.classify(0, win(5, 5, 7, 7)), Class::Intersector);
        assert_eq!(m.classify(0, win(6, 0, 8, 8)), Class::Disjoint);
        assert_eq!(m.classify(0, win(0, 0, 2, 2)), Class::Disjoint);
        // Edges just short of the centres of row 6 and column 6: the box rejects.
        let m = loaded(&[square(RED, 2.0, 2.0, 6.4, 6.4, 0.5)], 8, 8);
        assert_eq!(m.classify(0, win(6, 6, 8, 8)), Class::Disjoint);
        assert_eq!(m.classify(0, win(2, 2, 6, 6)), Class::Surrounder);
        // A U opening upwards (Figure AVI-2's concave case): the notch is outside it
        // though inside its box, found by the parity of the crossings; the prongs
        // surround windows of their own.
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
        let m = loaded(&[u], 6, 6);
        assert_eq!(m.classify(0, win(2, 0, 4, 3)), Class::Disjoint);
        assert_eq!(m.classify(0, win(2, 0, 4, 4)), Class::Intersector);
        assert_eq!(m.classify(0, win(4, 0, 6, 5)), Class::Surrounder);
        assert_eq!(m.classify(0, win(0, 0, 6, 6)), Class::Intersector);
        // A triangle whose box holds the window but whose hypotenuse passes by its far
        // corner: outside by the corners' line test, then by parity.
        let t = Polygon::from_xyz(RED, &[[0.0, 0.0, 0.5], [8.0, 0.0, 0.5], [0.0, 8.0, 0.5]]);
        let m = loaded(&[t], 8, 8);
        assert_eq!(m.classify(0, win(6, 6, 8, 8)), Class::Disjoint);
        assert_eq!(m.classify(0, win(1, 1, 3, 3)), Class::Surrounder);
        assert_eq!(m.classify(0, win(3, 3, 5, 5)), Class::Intersector);
        // A bowtie: two triangles meeting at (4, 4), told apart by the parity.
        let bowtie = Polygon::from_xyz(
            RED,
            &[
                [0.0, 0.0, 0.5],
                [8.0, 8.0, 0.5],
                [8.0, 0.0, 0.5],
                [0.0, 8.0, 0.5],
            ],
        );
        let m = loaded(&[bowtie], 8, 8);
        assert_eq!(m.classify(0, win(3, 0, 5, 1)), Class::Disjoint);
        assert_eq!(m.classify(0, win(0, 3, 1, 5)), Class::Surrounder);
        assert_eq!(m.classify(0, win(0, 0, 8, 8)), Class::Intersector);
    }

    #[test]
    fn empty_and_one_polygon_windows() {
        let polygons = [square(RED, 2.0, 2.0, 6.0, 6.0, 0.5)];
        let mut m = loaded(&polygons, 8, 8);
        assert_eq!(
            think_on(&mut m, &polygons, win(6, 0, 8, 8)),
            Resolution::Empty
        );
        assert_eq!(
            think_on(&mut m, &polygons, win(0, 0, 8, 8)),
            Resolution::OnePolygon
        );
        // The one polygon is clipped to the window: its pixels drawn, and only those.
        let image = picture(&mut m);
        assert_eq!(image.iter().filter(|p| p.is_some()).count(), 16);
        assert_eq!(image[2 * 8 + 2], Some(RED));
        assert_eq!(image[6 * 8 + 6], None);
        let mut m = loaded(&polygons, 8, 8);
        assert_eq!(
            think_on(&mut m, &polygons, win(3, 3, 5, 5)),
            Resolution::Surrounded
        );
        assert_eq!(picture(&mut m).iter().filter(|p| p.is_some()).count(), 4);
    }

    #[test]
    fn a_sliver_on_one_line_only_before_snapping_is_drawn() {
        // The apex lies one ulp below the line of the other two vertices, which sit
        // exactly on a snapping tie: the ends snap to the centre of row 0 (ties to even),
        // the apex just past it, and the snapped sliver holds the centres of row 0
        // between its ends (docs/DESIGN.md, "Coverage"), with its recorded plane or
        // without one. Collinear points stay out.
        let y0 = 0.5 + 1.0 / 512.0;
        let mut sliver = Polygon::from_xyz(
            RED,
            &[
                [0.25, y0, 0.5],
                [6.25, y0, 0.5],
                [3.25, y0 + f64::EPSILON, 0.5],
            ],
        );
        let flat = Polygon::from_xyz(
            GREEN,
            &[[0.25, 3.0, 0.5], [6.25, 3.0, 0.5], [3.25, 3.0, 0.5]],
        );
        for plane in [None, Some(proto::DVec4::new(0.0, 0.0, -1.0, 0.5))] {
            sliver.plane = plane;
            let polygons = [sliver.clone(), flat.clone()];
            let (runs, _) = resolved(&polygons, 8, 8);
            assert_eq!(
                runs,
                vec![Run {
                    y: 0,
                    x0: 0,
                    x1: 6,
                    colour: RED
                }],
                "{plane:?}"
            );
            assert_eq!(image_of(&runs, 8, 8), zbuffer_image(&polygons, 8, 8));
        }
    }

    #[test]
    fn the_hider_takes_what_it_hides_off_the_list() {
        let polygons = [
            square(RED, 0.0, 0.0, 8.0, 8.0, 0.25), // the hider, nearest
            square(GREEN, 1.0, 1.0, 5.0, 5.0, 0.5),
            square(BLUE, -2.0, -2.0, 10.0, 10.0, 0.75),
        ];
        let mut m = loaded(&polygons, 8, 8);
        assert_eq!(
            think_on(&mut m, &polygons, win(0, 0, 8, 8)),
            Resolution::Surrounded
        );
        assert_eq!(picture(&mut m), vec![Some(RED); 64]);
        // The ZMIN test stopped the Looker at the green, farther than the red's farthest
        // corner, leaving the green and the blue unexamined.
        assert_eq!((m.stats.zmin_exits, m.stats.zmin_skipped), (1, 2));
        // Two surrounders that cross inside the window penetrate: fail.
        let p = |x: f64, y: f64| [x, y, 0.5 + (x - 4.0) / 64.0];
        let sloped =
            Polygon::from_xyz(GREEN, &[p(0.0, 0.0), p(8.0, 0.0), p(8.0, 8.0), p(0.0, 8.0)]);
        let polygons = [square(RED, 0.0, 0.0, 8.0, 8.0, 0.5), sloped];
        let mut m = loaded(&polygons, 8, 8);
        assert_eq!(
            think_on(&mut m, &polygons, win(0, 0, 8, 8)),
            Resolution::Subdivided
        );
        assert_eq!(m.lists.len(), 2);
        // Left of the crossing (X = 4) the sloped one is in front at all four corners.
        assert_eq!(
            think_on(&mut m, &polygons, win(0, 0, 4, 8)),
            Resolution::Surrounded
        );
        assert_eq!(picture(&mut m)[0], Some(GREEN));
        // Two intersectors left in front of the hider fail the window.
        let polygons = [
            square(RED, 0.0, 0.0, 8.0, 8.0, 0.5),
            square(GREEN, 1.0, 1.0, 5.0, 5.0, 0.25),
            square(BLUE, 3.0, 3.0, 7.0, 7.0, 0.125),
            square(BLUE, 0.0, 4.0, 4.0, 8.0, 0.75), // hidden
        ];
        let mut m = loaded(&polygons, 8, 8);
        assert_eq!(
            think_on(&mut m, &polygons, win(0, 0, 8, 8)),
            Resolution::Subdivided
        );
        let left: Vec<u32> = m
            .lists
            .iter()
            .map(|e| m.faces[e.face as usize].poly)
            .collect();
        assert_eq!(left, vec![2, 1, 0]);
    }

    #[test]
    fn one_intersector_in_front_of_the_hider_is_displayed_over_it() {
        let polygons = [
            square(RED, 0.0, 0.0, 8.0, 8.0, 0.5),
            square(GREEN, 2.0, 2.0, 5.0, 5.0, 0.25),
            square(BLUE, 4.0, 0.0, 8.0, 8.0, 0.75), // hidden by the red
        ];
        let mut m = loaded(&polygons, 8, 8);
        assert_eq!(
            think_on(&mut m, &polygons, win(0, 0, 8, 8)),
            Resolution::InFront
        );
        assert_eq!(picture(&mut m), zbuffer_image(&polygons, 8, 8));
        // In front of the hider where it covers, behind it at a corner of the window
        // (its plane extended): the corner test fails, as the listing's does.
        let p = |x: f64, y: f64| [x, y, 0.5 + (x - 7.5) / 16.0];
        let polygons = [
            square(RED, 0.0, 0.0, 8.0, 8.0, 0.5),
            Polygon::from_xyz(GREEN, &[p(2.0, 2.0), p(7.0, 2.0), p(7.0, 5.0), p(2.0, 5.0)]),
        ];
        let mut m = loaded(&polygons, 8, 8);
        assert_eq!(
            think_on(&mut m, &polygons, win(0, 0, 8, 8)),
            Resolution::Subdivided
        );
        let (runs, _) = resolved(&polygons, 8, 8);
        assert_eq!(image_of(&runs, 8, 8), zbuffer_image(&polygons, 8, 8));
    }

    #[test]
    fn ties_go_to_the_earlier_polygon() {
        let polygons = [
            square(GREEN, 0.0, 0.0, 8.0, 8.0, 0.5),
            square(RED, 0.0, 0.0, 8.0, 8.0, 0.5),
        ];
        let mut m = loaded(&polygons, 8, 8);
        assert_eq!(
            think_on(&mut m, &polygons, win(0, 0, 8, 8)),
            Resolution::Surrounded
        );
        assert_eq!(picture(&mut m), vec![Some(GREEN); 64]);
        // An intersector as deep as the surrounder loses to it when it is later...
        let polygons = [
            square(GREEN, 0.0, 0.0, 8.0, 8.0, 0.5),
            square(RED, 2.0, 2.0, 4.0, 4.0, 0.5),
        ];
        let mut m = loaded(&polygons, 8, 8);
        assert_eq!(
            think_on(&mut m, &polygons, win(0, 0, 8, 8)),
            Resolution::Surrounded
        );
        // ...and wins when it is earlier.
        let polygons = [
            square(RED, 2.0, 2.0, 4.0, 4.0, 0.5),
            square(GREEN, 0.0, 0.0, 8.0, 8.0, 0.5),
        ];
        let mut m = loaded(&polygons, 8, 8);
        assert_eq!(
            think_on(&mut m, &polygons, win(0, 0, 8, 8)),
            Resolution::InFront
        );
        assert_eq!(picture(&mut m)[2 * 8 + 2], Some(RED));
        assert_eq!(picture(&mut m)[0], Some(GREEN));
    }

    #[test]
    fn far_depths_are_ordered_and_a_tie_width_apart_tie() {
        // Depths far beyond the old fixed point's range are f64s like any other: the
        // nearer square hides the farther in one window; one within the tie width of the
        // first (2^-30 of its depth) ties, and the earlier square shows.
        let polygons = [
            square(RED, 0.0, 0.0, 4.0, 4.0, 1e8),
            square(GREEN, 0.0, 0.0, 4.0, 4.0, 2e7),
        ];
        let (runs, m) = resolved(&polygons, 4, 4);
        assert_eq!(image_of(&runs, 4, 4), zbuffer_image(&polygons, 4, 4));
        assert_eq!(m.stats.windows_by_depth, vec![1]);
        let near = 1e8 * (1.0 - 0.5 / (1u64 << 30) as f64);
        let polygons = [
            square(RED, 0.0, 0.0, 4.0, 4.0, 1e8),
            square(GREEN, 0.0, 0.0, 4.0, 4.0, near),
        ];
        let (runs, _) = resolved(&polygons, 4, 4);
        assert_eq!(image_of(&runs, 4, 4), zbuffer_image(&polygons, 4, 4));
        assert!(runs.iter().all(|r| r.colour == RED), "{runs:?}");
    }

    #[test]
    fn three_depths_each_within_the_tie_of_the_next_fold_as_the_z_buffer_folds() {
        // Differential seed 200470's stack, made plain: at depths z, z(1 − ½t) and
        // z(1 − 1.2t) (t the tie width), in that stream order, the second fails to take
        // the pixel from the first and the third takes it: blue. The third is in front
        // of the first, so a hider that took the first off the list left the second to
        // keep the pixel from the third: green, 64 pixels wrong.
        let polygons = scan::frame::near_ties();
        let want = zbuffer_image(&polygons, 8, 8);
        assert_eq!(want, vec![Some(BLUE); 64]);
        let (runs, _) = resolved(&polygons, 8, 8);
        assert_eq!(image_of(&runs, 8, 8), want);
        // Whatever the stream order.
        for order in [[0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]] {
            let polygons = order.map(|i| polygons[i].clone());
            let (runs, _) = resolved(&polygons, 8, 8);
            assert_eq!(
                image_of(&runs, 8, 8),
                zbuffer_image(&polygons, 8, 8),
                "{order:?}"
            );
        }
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
        assert_eq!(runs.len(), 32);
        assert_eq!((runs[0].x0, runs[0].x1, runs[0].colour), (0, 5, RED));
        assert_eq!((runs[1].x0, runs[1].x1, runs[1].colour), (5, 16, GREEN));
        // The windows holding columns 4 and 5 fail at every size: columns 0..8, 4..8,
        // 4..6 and then the pixels of columns 4 and 5, down all 16 rows.
        assert_eq!(m.stats.windows_by_depth, vec![1, 4, 8, 16, 32]);
        assert_eq!(
            (m.stats.subdivided, m.stats.surrounded, m.stats.pixels),
            (1 + 2 + 4 + 8, 2 + 4 + 8, 32)
        );
        // The Looker looks at each polygon once, for the first window; both surround it
        // and so every descendant (the ancestral check).
        assert_eq!(m.stats.looked_at, 2);
    }

    #[test]
    fn a_stack_is_decided_by_its_nearest_polygon_alone() {
        // 1,000 full-screen squares, shuffled in depth: the ZMIN sort puts the nearest
        // first, it surrounds the screen, and the Looker stops at the next one.
        let polygons: Vec<Polygon> = (0..1000)
            .map(|k| {
                let z = 0.1 + 0.0008 * ((k * 617) % 1000) as f64;
                square([k as u8, (k / 256) as u8, 9], 0.0, 0.0, 64.0, 64.0, z)
            })
            .collect();
        let (runs, m) = resolved(&polygons, 64, 64);
        assert_eq!(image_of(&runs, 64, 64), zbuffer_image(&polygons, 64, 64));
        assert_eq!(m.stats.windows_by_depth, vec![1]);
        assert_eq!(m.stats.looked_at, 1);
        assert_eq!((m.stats.zmin_exits, m.stats.zmin_skipped), (1, 999));
    }

    #[test]
    fn zmin_bounds_the_plane_not_the_vertices() {
        // Found by the methods fuzz target: a quadrilateral whose vertex depths are not on
        // one plane (two vertices at one point, depths 0.75 and 0.25). Its pixels take
        // Newell's plane, 0 at (6.5, 9.25) where its vertex says 0.25: a ZMIN from the
        // vertices (0.25) let the ZMIN test pass over it behind the triangle's 0.25 there.
        let quad = Polygon::from_xyz(
            RED,
            &[
                [23.75, 7.75, 0.75],
                [9.25, 47.0, 0.75],
                [9.25, 47.0, 0.25],
                [6.5, 9.25, 0.25],
            ],
        );
        let triangle = Polygon::from_xyz(
            GREEN,
            &[
                [9.25, 9.25, 0.25],
                [18.75, 24.0, 0.25],
                [-128.0, -128.0, 0.0],
            ],
        );
        let polygons = [quad, triangle];
        let (runs, m) = resolved(&polygons, 16, 16);
        assert_eq!(image_of(&runs, 16, 16), zbuffer_image(&polygons, 16, 16));
        let quad = m
            .faces
            .iter()
            .find(|f| f.poly == 0)
            .expect("the quadrilateral");
        // The plane's 0 at (6.5, 9.25), not the vertices' 0.25; in fact −∞: its depth is
        // 0 at a corner of its box, where no rounding bound holds relative to the
        // depth, so it is never passed over.
        assert!(quad.zmin < 1e-12, "{}", quad.zmin);
    }

    #[test]
    fn a_pixel_on_an_edge_two_polygons_share_at_one_depth_goes_to_the_earlier() {
        // Found by the methods fuzz target: two triangles with an edge on the diagonal
        // x = y at depth 0.25, both on its x > y side, the yellow one later in the
        // stream and nearer off the diagonal. On the diagonal's centres they tie and the
        // earlier (cream) one shows. The pixel window's search stopped at the cream one
        // because its ZMIN, its plane at its vertices, came out a rounding above yellow's
        // depth there: it stops now only where the tie rule puts a polygon behind.
        const CREAM: Colour = [217, 217, 173];
        const YELLOW: Colour = [173, 173, 0];
        let polygons = [
            Polygon::from_xyz(
                CREAM,
                &[
                    [23.75, 3.25, 0.75],
                    [3.25, 23.75, 0.25],
                    [14.25, 14.25, 0.75],
                ],
            ),
            Polygon::from_xyz(
                CREAM,
                &[
                    [23.75, 23.75, 0.25],
                    [25.75, 14.25, 0.75],
                    [14.25, 14.25, 0.25],
                ],
            ),
            Polygon::from_xyz(
                YELLOW,
                &[
                    [23.75, 23.75, 0.25],
                    [41.0, -8.939734142804938e-7, 0.75],
                    [3.25, 3.25, 0.25],
                ],
            ),
        ];
        let (runs, _) = resolved(&polygons, 36, 45);
        let image = image_of(&runs, 36, 45);
        assert_eq!(image, zbuffer_image(&polygons, 36, 45));
        for k in 14..24 {
            assert_eq!(image[k * 36 + k], Some(CREAM), "pixel ({k}, {k})");
        }
    }

    #[test]
    fn a_plane_too_steep_to_be_affine_is_decided_at_its_pixels() {
        // Found by the methods fuzz target: a triangle with two vertices at depth 0.25 on
        // the diagonal x = y and a third at depth 1.45e135 a few pixels off it. Its plane's
        // terms cancel along the diagonal, where the z-buffer's depths are rounding noise
        // of about 1e118: comparisons at a window's corners say nothing of the centres
        // between, and three diagonal pixels came out unlike the z-buffer. Such depths
        // are now decided pixel by pixel, as the z-buffer decides them.
        const WHITE: Colour = [255, 255, 255];
        const CYAN: Colour = [18, 217, 217];
        let polygons = [
            Polygon::from_xyz(
                WHITE,
                &[
                    [23.75, 23.75, 0.75],
                    [3.25, 24.0, 0.75],
                    [34.25, 3.25, 0.25],
                    [29.25, 24.0, 0.25],
                    [27.25, 24.0, 0.25],
                ],
            ),
            Polygon::from_xyz(
                WHITE,
                &[
                    [3.25, 3.25, 0.25],
                    [36.25, 35.0, 1.4536201648020902e135],
                    [23.75, 23.75, 0.25],
                ],
            ),
            Polygon::from_xyz(
                CYAN,
                &[[37.5, 3.25, 0.0], [3.25, 3.25, 0.25], [14.25, 24.0, 0.25]],
            ),
        ];
        let (runs, _) = resolved(&polygons, 36, 45);
        assert_eq!(image_of(&runs, 36, 45), zbuffer_image(&polygons, 36, 45));
    }

    #[test]
    fn a_polygon_without_a_finite_plane_has_its_flat_depth_for_zmin() {
        // Found by the methods fuzz target: a thirteen-vertex polygon, far from planar,
        // one vertex at depth -2.01e305. Its plane is not finite across the screen, so
        // the z-buffer gives its pixels its nearest vertex depth (`DepthPlane::Flat`) and
        // it is in front; but its ZMIN came from the f64 plane at its vertices (1.2e306),
        // and the Looker passed over it behind the grey quadrilateral: 207 pixels.
        const GREY: Colour = [38, 53, 62];
        const BLACK: Colour = [0, 0, 0];
        let polygons = [
            Polygon::from_xyz(
                GREY,
                &[
                    [24.0, 34.25, 0.25],
                    [35.0, 3.25, 0.25],
                    [23.75, 3.25, 0.75],
                    [3.25, 3.25, 0.25],
                ],
            ),
            Polygon::from_xyz(
                BLACK,
                &[
                    [44.5, 44.5, 0.5],
                    [38.5, 22.5, 0.75],
                    [23.75, 3.25, -2.0102879725023188e305],
                    [15.25, 14.25, 0.25],
                    [1.74686011721e-312, 44.5, 0.5],
                    [44.5, 44.5, 0.5],
                    [3.25, 23.75, 0.25],
                    [36.25, 36.25, 0.5],
                    [36.25, 36.25, 0.75],
                    [-128.0, -128.0, 0.75],
                    [-128.0, -128.0, 0.0],
                    [-128.0, -128.0, 0.0],
                    [-128.0, -128.0, 0.0],
                ],
            ),
        ];
        let (runs, m) = resolved(&polygons, 38, 38);
        let image = image_of(&runs, 38, 38);
        assert_eq!(image, zbuffer_image(&polygons, 38, 38));
        assert_eq!(image[4 * 38 + 23], Some(BLACK));
        // ZMIN and ZMAX are the depth the z-buffer gives it, and no plane is kept.
        let black = m.faces.iter().find(|f| f.poly == 1).expect("the polygon");
        assert!(matches!(black.depth, DepthPlane::Flat(_)));
        assert_eq!(
            (black.zmin, black.zmax),
            (-2.0102879725023188e305, -2.0102879725023188e305)
        );
        assert_eq!(black.plane, None);
    }

    #[test]
    fn a_plane_whose_depth_changes_sign_is_never_passed_over() {
        // Found by the methods fuzz target: a triangle with a vertex at depth 3.6e88. Its
        // plane's depths at its vertices come out 1.4e73 and up, but its pixels' depths run
        // from -4.5e89 to 7.5e89, through 0 at (10, 35), where it is in front of the
        // surrounding polygon at 14.5; the ZMIN exit passed over it. A polygon whose
        // depth changes sign over its box now sorts first.
        let polygons = [
            Polygon::from_xyz(
                [6, 82, 82],
                &[
                    [-3.25, -3.25, 0.75],
                    [55.75, 55.75, 0.75],
                    [44.5, 3.25, 0.75],
                    [3.0, 44.5, 0.5],
                    [-3.25, -3.25, 0.75],
                    [35.0, 3.25, 0.75],
                    [3.25, 14.25, 0.75],
                    [14.25, 14.25, 0.75],
                    [54.5, 14.25, 0.75],
                    [20.25, 15.25, 0.5],
                    [44.5, 24.25, 0.25],
                ],
            ),
            Polygon::from_xyz(
                [127, 127, 127],
                &[
                    [-5.0, -5.0, 0.25],
                    [-3.25, -3.25, 3.644696722363238e88],
                    [18.25, 55.75, 0.75],
                ],
            ),
        ];
        let (runs, m) = resolved(&polygons, 37, 45);
        assert_eq!(image_of(&runs, 37, 45), zbuffer_image(&polygons, 37, 45));
        let steep = m.faces.iter().find(|f| f.poly == 1).expect("the triangle");
        assert_eq!(steep.zmin, f64::NEG_INFINITY, "it sorts first");
    }

    #[test]
    fn a_flat_winner_bounds_the_pixel_search_by_its_depth_not_its_zmin() {
        // Found by the methods fuzz target after the sign rule above: at a pixel whose
        // winner so far had no plane (a flat depth, 0) and a ZMIN of −∞, the search's stop
        // took that −∞ as the winner's depth and passed over a flat polygon at -1.04e307
        // in front of it: 19 pixels.
        let polygons = [
            Polygon::from_xyz(
                [147, 147, 147],
                &[
                    [23.75, 3.25, 0.75],
                    [3.25, 3.25, 0.25],
                    [-5.0, 37.25, 0.75],
                    [44.5, 44.5, 0.25],
                    [3.25, 3.25, 0.25],
                    [14.25, -5.0, 0.25],
                    [3.25, 44.5, 6.0],
                    [44.5, 44.5, 0.5],
                ],
            ),
            Polygon::from_xyz(
                [173, 126, 173],
                &[
                    [3.25, 3.25, 0.25],
                    [14.75, 3.25, 0.25],
                    [44.5, 44.5, 0.25],
                    [-3.25, -3.25, 0.5],
                    [-3.25, 35.0, 0.75],
                    [23.75, 3.25, 0.25],
                    [23.75, 55.5, -1.0419962179003233e307],
                    [14.75, -5.0, 0.25],
                    [44.5, 44.5, -10.375],
                    [44.5, -3.25, 0.5],
                    [23.75, 23.75, 0.75],
                ],
            ),
            Polygon::from_xyz(
                [147, 147, 147],
                &[[41.0, 5.75, 0.25], [44.5, 44.5, 0.0], [-3.25, -3.25, 0.75]],
            ),
            Polygon::from_xyz(
                [0, 0, 0],
                &[
                    [3.25, 14.25, 7.212803097935351e307],
                    [14.25, 14.25, 0.75],
                    [33.75, 20.25, 0.25],
                    [24.5, 14.25, 0.25],
                    [55.75, 3.25, 0.25],
                    [23.75, 14.25, 0.25],
                    [14.25, 33.75, 0.25],
                    [14.25, 24.5, 0.25],
                    [14.25, 44.5, 0.25],
                    [44.5, 44.5, 0.5],
                    [44.5, -128.0, 0.5],
                    [-128.0, -128.0, 0.0],
                    [-128.0, -128.0, 0.0],
                ],
            ),
        ];
        let (runs, _) = resolved(&polygons, 36, 45);
        let image = image_of(&runs, 36, 45);
        assert_eq!(image, zbuffer_image(&polygons, 36, 45));
        assert_eq!(image[2 * 36 + 18], Some([173, 126, 173]));
    }

    /// Differential seed 50385: a quad and a copy 5e-11 nearer, their depth through 0;
    /// the copy wins only in a band near depth 0, so the corner test must not decide a
    /// window the held depth changes sign in.
    #[test]
    fn a_nearer_copy_wins_only_where_depth_nears_zero_as_the_fold_gives() {
        let polygons = scan::frame::nearer_copy_through_depth_zero();
        let zbuffer = zbuffer_image(&polygons, 68, 68);
        assert!(zbuffer.contains(&Some([127, 79, 235])));
        let (runs, _) = resolved(&polygons, 68, 68);
        assert_eq!(differing_pixels(&image_of(&runs, 68, 68), &zbuffer), 0);
    }

    /// Gouraud-shaded polygons among flat ones, on a screen wide enough for windows of
    /// every kind (surrounders filled, one intersector over a hider, pixels): every visible
    /// pixel of a shaded polygon is its colour at the centre, the z-buffer's byte for
    /// byte, and a row's runs of one colour are joined.
    #[test]
    fn shaded_polygons_are_drawn_as_the_zbuffer_shades_them() {
        let mut next = scan::frame::pseudo_random(0x9e37_79b9_7f4a_7c15u64);
        let (w, h) = (150u32, 100u32);
        let mut polygons = vec![square([1, 2, 3], -5.0, -5.0, 160.0, 110.0, 0.9)];
        polygons[0].vertex_attrs = [
            [200.0, 0.0, 0.0],
            [0.0, 200.0, 0.0],
            [0.0, 0.0, 200.0],
            [90.0; 3],
        ]
        .map(proto::DVec3::from)
        .to_vec();
        for i in 0..60 {
            let (cx, cy) = (next() * 170.0 - 10.0, next() * 120.0 - 10.0);
            let n = 3 + (i % 2);
            let pts: Vec<[f64; 3]> = (0..n)
                .map(|_| {
                    [
                        cx + next() * 50.0 - 25.0,
                        cy + next() * 50.0 - 25.0,
                        next() * 0.8,
                    ]
                })
                .collect();
            let mut p = Polygon::from_xyz([i as u8, 7, 9], &pts);
            if i % 3 != 0 {
                p.vertex_attrs = (0..n)
                    .map(|_| proto::DVec3::new(next(), next(), next()) * 255.0)
                    .collect();
            }
            polygons.push(p);
        }
        let (runs, m) = resolved(&polygons, w, h);
        let image = image_of(&runs, w, h);
        assert_eq!(differing_pixels(&image, &zbuffer_image(&polygons, w, h)), 0);
        assert!(
            m.stats.surrounded > 0 && m.stats.in_front > 0,
            "{:?}",
            m.stats
        );
        let colours: std::collections::HashSet<_> = image.iter().flatten().collect();
        assert!(colours.len() > 2000, "{} colours", colours.len());
        assert_eq!(scan::frame::unjoined_runs(&runs), None);
    }

    #[test]
    fn runs_are_maximal_and_in_row_order() {
        let polygons = [
            square(RED, 3.0, 2.0, 6.0, 4.0, 0.5),
            square(RED, 6.0, 2.0, 9.0, 3.0, 0.25),
        ];
        let (runs, _) = resolved(&polygons, 12, 6);
        let got: Vec<(u32, u32, u32)> = runs.iter().map(|r| (r.y, r.x0, r.x1)).collect();
        assert_eq!(got, vec![(2, 3, 9), (3, 3, 6)]);
        // Nothing on the screen: no runs, no windows.
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
