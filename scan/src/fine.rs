//! What the anti-aliasing methods share (docs/DESIGN.md, "Anti-aliasing"): a screen K
//! times finer, and a frame's polygons walked a band of rows at a time.
//!
//! Sub-pixel sample (i, j) of pixel (c, r), at (c + (i+½)/K, r + (j+½)/K), is the pixel
//! centre (K·c + i + ½, K·r + j + ½) of a screen K times finer. A screen polygon's X and
//! Y (and its supports') are snapped to the pixel screen's 1/256 grid and then multiplied
//! by K (its recorded plane's a and b divided by K), exact in f64 for K a power of two, so
//! [`crate::SpanWalker`] on the [`scaled`] polygon decides every sample, a point of the
//! same grid for K ≤ 16, by exactly the point rule of docs/DESIGN.md, "Coverage", with
//! nothing new written for coverage.
//!
//! [`ActiveRows`] hands a method, pixel row by pixel row, the polygons that may cover
//! the row (gathered once per frame and sorted by their top row, Watkins-style), so a
//! method keeps one band of fine rows at a time and never the K·W × K·H screen.

use proto::{Colour, DVec4, Polygon};

/// The largest K a method samples with: the K² samples of a pixel, 255 each, sum within
/// a u32, and a fine row of a 65,536-pixel screen still fits in one.
pub const MAX_SAMPLES: u32 = 16;

/// Whether `k` is a sample count the methods accept: a power of two from 1 to
/// [`MAX_SAMPLES`] (exact scaling).
pub fn valid_samples(k: u32) -> bool {
    k.is_power_of_two() && k <= MAX_SAMPLES
}

/// `polygon` on the screen `k` times finer: X and Y of its vertices and supports snapped
/// to the pixel screen's 1/256-pixel grid ([`proto::raster::snap`]) and then times `k`,
/// its depth plane `a·X + b·Y + c·Z + d = 0` as `(a/k)·X' + (b/k)·Y' + c·Z + d = 0` (and
/// its colour planes alike).
/// Snapping first puts the fine polygon's vertices where the pixel screen's snapped ones
/// are (a multiple of 1/256 pixel times K is a multiple of 1/256 fine pixel, which the
/// walker's own snapping keeps), and for `k` a power of two every product is exact, so
/// the fine polygon covers a fine pixel centre exactly when the snapped polygon covers
/// the sub-pixel sample (c + (i+½)/K, r + (j+½)/K), a point of the same 1/256 grid; its
/// depth is the same plane.
pub fn scaled(polygon: &Polygon, k: u32) -> Polygon {
    let k = k as f64;
    let on_grid = |x: f64| proto::raster::snap(x) as f64 / proto::raster::SUBPIXEL as f64 * k;
    let s = |v: DVec4| DVec4::new(on_grid(v.x), on_grid(v.y), v.z, v.w);
    Polygon {
        colour: polygon.colour,
        vertices: polygon.vertices.iter().map(|&v| s(v)).collect(),
        plane: polygon
            .plane
            .map(|p| DVec4::new(p.x / k, p.y / k, p.z, p.w)),
        supports: polygon
            .supports
            .iter()
            .map(|o| o.map(|[a, b]| [s(a), s(b)]))
            .collect(),
        vertex_attrs: polygon.vertex_attrs.clone(),
        shade: polygon
            .shade
            .as_ref()
            .map(|planes| Box::new(planes.map(|p| DVec4::new(p.x / k, p.y / k, p.z, p.w)))),
        opacity: polygon.opacity,
    }
}

/// The pixel rows and columns a polygon may cover, from its vertices: `top..end` rows,
/// `left..right` columns, on a `width`×`height` screen, widened by a pixel each side
/// (a crossing computed on a support may round a hair past the piece's own ends).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Extent {
    pub top: u32,
    pub end: u32,
    pub left: u32,
    pub right: u32,
}

impl Extent {
    /// `None` when the polygon can cover nothing on the screen.
    pub fn of(polygon: &Polygon, width: u32, height: u32) -> Option<Extent> {
        if polygon.vertices.len() < 3 {
            return None;
        }
        let (mut x0, mut x1, mut y0, mut y1) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        for v in &polygon.vertices {
            x0 = x0.min(v.x);
            x1 = x1.max(v.x);
            y0 = y0.min(v.y);
            y1 = y1.max(v.y);
        }
        // `as` saturates (and takes NaN to 0); the clamps keep the screen.
        let clamp = |v: f64, limit: u32| (v.floor() as i64).clamp(0, limit as i64) as u32;
        let e = Extent {
            top: clamp(y0 - 1.0, height),
            end: clamp(y1 + 2.0, height),
            left: clamp(x0 - 1.0, width),
            right: clamp(x1 + 2.0, width),
        };
        (e.top < e.end && e.left < e.right).then_some(e)
    }
}

/// A frame's polygons by pixel row: built once per frame, then [`ActiveRows::advance`]d
/// row by row, top to bottom, giving the polygons that may cover the row in stream order
/// (the order that settles ties of depth).
#[derive(Debug, Default)]
pub struct ActiveRows {
    /// (extent, stream index), sorted by top row.
    order: Vec<(Extent, u32)>,
    next: usize,
    active: Vec<(Extent, u32)>,
    indices: Vec<u32>,
}

impl ActiveRows {
    pub fn new() -> Self {
        ActiveRows::default()
    }

    /// Takes a new frame. Polygons past `u32::MAX` in a frame are not drawn.
    pub fn start(&mut self, polygons: &[Polygon], width: u32, height: u32) {
        self.order.clear();
        self.active.clear();
        self.next = 0;
        self.order.extend(
            polygons
                .iter()
                .take(u32::MAX as usize)
                .enumerate()
                .filter_map(|(i, p)| Some((Extent::of(p, width, height)?, i as u32))),
        );
        // Stable: equal tops stay in stream order.
        self.order.sort_by_key(|(e, _)| e.top);
    }

    /// The first row any polygon may cover (the frame's height if none).
    pub fn first_row(&self) -> Option<u32> {
        self.order.first().map(|(e, _)| e.top)
    }

    /// Moves to pixel row `row` (rows in increasing order): the polygons that may cover
    /// it, in stream order, and the columns `left..right` they may cover (empty if none).
    pub fn advance(&mut self, row: u32) -> (&[u32], std::ops::Range<u32>) {
        self.active.retain(|(e, _)| e.end > row);
        let before = self.active.len();
        while let Some(&(e, i)) = self.order.get(self.next) {
            if e.top > row {
                break;
            }
            self.next += 1;
            if e.end > row {
                self.active.push((e, i));
            }
        }
        if self.active.len() > before {
            self.active.sort_unstable_by_key(|&(_, i)| i);
        }
        self.indices.clear();
        self.indices.extend(self.active.iter().map(|&(_, i)| i));
        let left = self.active.iter().map(|(e, _)| e.left).min().unwrap_or(0);
        let right = self.active.iter().map(|(e, _)| e.right).max().unwrap_or(0);
        (&self.indices, left..right.max(left))
    }

    /// Moves to the first pixel row from `row` on, below `height`, that some polygon may
    /// cover, skipping the rows none reaches: that row and the columns its polygons may
    /// cover (those polygons are then [`ActiveRows::indices`]), or `None` past the last.
    /// Rows must come in increasing order.
    pub fn next_row(&mut self, mut row: u32, height: u32) -> Option<(u32, std::ops::Range<u32>)> {
        while row < height {
            let (now, cols) = self.advance(row);
            if !now.is_empty() {
                return Some((row, cols));
            }
            row = self.next_top()?.max(row + 1);
        }
        None
    }

    /// The polygons of the row last moved to, in stream order.
    pub fn indices(&self) -> &[u32] {
        &self.indices
    }

    /// The top row of the next polygon not yet active, if any.
    pub fn next_top(&self) -> Option<u32> {
        self.order.get(self.next).map(|(e, _)| e.top)
    }
}

/// The exact K×K supersampled picture of `polygons` on a `width`×`height` screen, the
/// reference the anti-aliasing leaves are tested against: the z-buffer's picture of the
/// K-times-finer screen, box-filtered (`(sum + K²/2)/K²`, uncovered samples counting as
/// `background`), `None` where no sample is covered.
pub fn supersampled_image(
    polygons: &[Polygon],
    width: u32,
    height: u32,
    k: u32,
    background: Colour,
) -> Vec<Option<Colour>> {
    let fine: Vec<Polygon> = polygons.iter().map(|p| scaled(p, k)).collect();
    let image = crate::frame::zbuffer_image(&fine, width * k, height * k);
    let count = k * k;
    let mut out = Vec::with_capacity(width as usize * height as usize);
    for r in 0..height {
        for c in 0..width {
            let mut sum = [0u32; 3];
            let mut covered = false;
            for j in 0..k {
                for i in 0..k {
                    let s = image[((r * k + j) * width * k + c * k + i) as usize];
                    covered |= s.is_some();
                    for (t, v) in sum.iter_mut().zip(s.unwrap_or(background)) {
                        *t += v as u32;
                    }
                }
            }
            out.push(covered.then(|| sum.map(|s| ((s + count / 2) / count) as u8)));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::zbuffer_image;
    use crate::SpanWalker;

    #[test]
    fn scaling_is_exact_and_keeps_the_plane() {
        let mut p = Polygon::from_xyz(
            [1, 2, 3],
            &[[0.1, 0.3, 0.5], [3.7, 0.2, 0.25], [1.9, 2.9, 0.75]],
        );
        p.plane = Some(DVec4::new(0.3, -0.7, 1.1, 0.2));
        let s = scaled(&p, 4);
        // (3.7, 0.2) snaps to (947/256, 51/256), times 4.
        assert_eq!(s.vertices[1], DVec4::new(14.796875, 0.796875, 0.25, 1.0));
        assert_eq!(s.plane, Some(DVec4::new(0.075, -0.175, 1.1, 0.2)));
        for (a, b) in p.vertices.iter().zip(&s.vertices) {
            let snapped = proto::raster::snap(a.x) as f64 / 256.0;
            assert_eq!(snapped * 4.0, b.x);
            assert_eq!(b.x / 4.0, snapped);
            // The fine vertex is on the fine grid already: the walker's snap keeps it.
            assert_eq!(proto::raster::snap(b.x) as f64 / 256.0, b.x);
        }
    }

    #[test]
    fn a_sliver_piece_whose_ends_snap_onto_one_line_keeps_its_sample() {
        // Differential seed 7310 at depth 4: a sliver 0.0004 pixel wide, cut by the
        // splitter tree at Y = 3 and X = 20, holds sample (19 + 9/16, 3 + 1/16) of pixel
        // (19, 3) between its two long edges. The piece's four ends snap to two points,
        // (19.5, 3) and (20, 3.484375), on one line, and the piece was taken to cover
        // nothing; its edges cross the rows on their supports, the whole's, which do
        // hold the sample.
        let v = |x: f64, y: f64| DVec4::new(x, y, -0.0333, 1.0);
        let (a0, a1) = (
            v(22.056121939284367, 5.468882902755973),
            v(18.53937670391129, 2.0738924824657516),
        );
        let (b0, b1) = (
            v(18.323392409969323, 1.8656028331380485),
            v(22.064260314741915, 5.477262853685904),
        );
        let whole = Polygon {
            colour: [1, 1, 1],
            vertices: vec![a0, a1, b0, b1],
            ..Polygon::default()
        };
        let piece = Polygon {
            colour: [1, 1, 1],
            vertices: vec![
                v(20.0, 3.483946883903744),
                v(19.498697289992162, 3.0),
                v(19.498372870099985, 3.0),
                v(20.0, 3.4843011558816817),
            ],
            supports: vec![Some([a0, a1]), None, Some([b0, b1]), None],
            ..Polygon::default()
        };
        // Pixel (19, 3)'s 8×8 samples: fine columns 152..160 of fine rows 24..32.
        let samples = |p: &Polygon| {
            let mut held = Vec::new();
            SpanWalker::new().for_each_span_in(&scaled(p, 8), 41 * 8, 24..32, |s| {
                held.extend((s.x0.max(152)..s.x1.min(160)).map(|x| (x, s.y)));
            });
            held
        };
        assert_eq!(samples(&whole), vec![(156, 24)]);
        assert_eq!(samples(&piece), samples(&whole));
    }

    #[test]
    fn a_fine_screen_samples_at_sub_pixel_centres() {
        // A triangle over the top-left half of pixel (0, 0): of its 2×2 sub-pixel
        // centres (¼, ¼), (¾, ¼), (¼, ¾), (¾, ¾) the triangle X + Y < 1 holds the first;
        // the next two lie on its hypotenuse, a right edge, which the rule leaves out.
        let t = Polygon::from_xyz(
            [9, 9, 9],
            &[[0.0, 0.0, 0.5], [1.0, 0.0, 0.5], [0.0, 1.0, 0.5]],
        );
        let image = zbuffer_image(&[scaled(&t, 2)], 2, 2);
        let c = Some([9, 9, 9]);
        assert_eq!(image, vec![c, None, None, None]);
        // 4×4: the centres with i + j + 1 < 4.
        let mut walker = SpanWalker::new();
        let mut n = 0;
        walker.for_each_span(&scaled(&t, 4), 4, 4, |s| n += s.x1 - s.x0);
        assert_eq!(n, 6); // 3 + 2 + 1 of the 4×4 centres
    }

    #[test]
    fn active_rows_follow_the_polygons_in_stream_order() {
        let sq = |y0: f64, y1: f64| {
            Polygon::from_xyz(
                [1, 1, 1],
                &[
                    [1.0, y0, 0.0],
                    [3.0, y0, 0.0],
                    [3.0, y1, 0.0],
                    [1.0, y1, 0.0],
                ],
            )
        };
        let polys = [sq(10.0, 12.0), sq(2.0, 4.0), sq(3.0, 11.0)];
        let mut rows = ActiveRows::new();
        rows.start(&polys, 20, 20);
        assert_eq!(rows.first_row(), Some(1));
        let mut seen = Vec::new();
        for r in 0..20 {
            let (active, cols) = rows.advance(r);
            seen.push((r, active.to_vec(), cols));
        }
        assert_eq!(seen[0], (0, vec![], 0..0));
        assert_eq!(seen[3], (3, vec![1, 2], 0..5));
        assert_eq!(seen[10], (10, vec![0, 2], 0..5));
        assert_eq!(seen[14], (14, vec![], 0..0));
        // next_row visits exactly the rows with polygons, skipping the others.
        let mut rows = ActiveRows::new();
        rows.start(&polys, 20, 20);
        let mut visited = Vec::new();
        let mut from = 0;
        while let Some((r, cols)) = rows.next_row(from, 20) {
            visited.push((r, rows.indices().to_vec(), cols));
            from = r + 1;
        }
        let want: Vec<_> = seen.into_iter().filter(|(_, a, _)| !a.is_empty()).collect();
        assert_eq!(visited, want);
    }
}
