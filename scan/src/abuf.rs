//! Carpenter's a-buffer as the sampling thesis, 6.3, builds it (docs/DESIGN.md,
//! "Anti-aliasing"): the method of the `abuf` leaf of the splitter tree, and of `zbuf --aa
//! abuf`, which runs it in the leaf's place at depth 0.
//!
//! Scan conversion makes, for every pixel a polygon reaches, a *fragment*: its colour, an
//! 8×8 bit mask of the sub-pixel samples it covers, and its least and greatest depth
//! there (zmin, zmax; sampling thesis 6.3.2). The fragments go into the pixel's *pixelstruct*:
//! empty, simple (one fragment covering the whole pixel in front of all others: the fast
//! path, no list) or a list sorted by depth (6.3.1, 6.3.4, 6.3.5). After the last polygon
//! the *packer* resolves each list front to back (6.3.6), see [`list`].
//!
//! The masks follow the point rule exactly: sample (i, j) of pixel (c, r) is at
//! (c + (i+½)/8, r + (j+½)/8), the pixel centre of a screen 8 times finer, and the polygon
//! is carried onto that screen exactly ([`crate::fine::scaled`]) and walked by
//! [`crate::SpanWalker`]: a sample on an edge shared by two polygons goes to exactly one
//! of them, so two polygons of one colour sharing an edge leave no seam (the sampling thesis's grey
//! seam, 6.3). The seed computes masks from each edge's crossings of the pixel, and'ed
//! together; here they are the spans of the pixel row's eight sub-scanlines, or'ed, which
//! is the same region sampled by the same rule as every other method. zmin and zmax are
//! the polygon's fixed-point depth plane at the fragment's covered samples (at the ends
//! of each sub-scanline's run, the plane being linear).
//!
//! A Gouraud-shaded polygon (docs/DESIGN.md, "Shading") gives each of its fragments its
//! colour planes' value at the pixel centre (`proto::shade`, the z-buffer's calls): the
//! sampling thesis's fragment holds one colour (figure 6.6), so a shaded fragment is the
//! polygon sampled at the centre for colour and at the 64 samples for coverage. Opacity
//! and the packer are unchanged.
//!
//! Memory stays bounded (6.3.2's *mask buffer*): the frame's polygons are gathered and
//! sorted by their top row ([`crate::fine::ActiveRows`]), and the a-buffer is kept for one
//! pixel row at a time. For each row, each polygon that reaches it is walked over the
//! row's eight sub-scanlines into the mask buffer (one element per pixel of the row:
//! mask, zmin, zmax), whose touched elements become fragments; when every polygon of the
//! row is in, the row is packed and sent as runs. Memory is the polygons, one row of
//! pixelstructs and their fragments, never a frame of lists.
//!
//! Time stays bounded too, where the seed's structure alone is quadratic:
//!
//! * a list is at most [`list::MAX_LIST`] fragments long; past that its two farthest
//!   fragments are merged into one ([`list::Fragment::merge_behind`], counted as `merged`
//!   in `--stats`). The seed keeps lists short only by combining and by throwing away
//!   what is behind a fully covering fragment (6.3.5), which does nothing for N small
//!   fragments at N depths in one pixel: N tiny triangles on one pixel took time
//!   quadratic in N (10⁵: 5.07 s; now 0.35 s);
//! * the *cull*: per block of [`BLOCK`] pixels of the row, the farthest of its pixels'
//!   occluding depths (the zmax of the nearest fully covering fragment, behind which
//!   6.3.5 throws every fragment away) is kept, and a polygon whose nearest depth over
//!   the row, over a block, or (where the block has an occluding depth) over a pixel, is
//!   beyond it is left out there without its masks being
//!   made. Its fragments would all have been thrown away, so no pixel changes (a property
//!   test compares with [`ABuffer::without_cull`]); 20,000 stacked full-screen squares at
//!   500×500 took over 60 s, now 1.2 s.

pub mod list;

use crate::fine::{scaled, ActiveRows, Extent};
use crate::frame::{push_row_runs_at, HiddenSurface};
use crate::{depth_at, Depth, DepthPlane, Run, SpanWalker};
use list::{Fragment, ListStats, Mask, Packer, PixelStruct};
use proto::shade::{Lighting, Shading};
use proto::{Colour, Polygon};
use std::sync::Arc;

/// Sub-pixel samples a side.
pub const K: u32 = 8;

/// Pixels of a row in one *cull block*: the a-buffer keeps, per block of the current row,
/// the farthest of its pixels' occluding depths ([`PixelStruct::occluding_depth`]), so
/// that a polygon wholly beyond it over the block is left out there without its masks
/// being made (every fragment it would make there would be thrown away, 6.3.5).
pub const BLOCK: u32 = 8;

/// An element of the mask buffer (the sampling thesis, figure 6.9), less the area, which is the
/// mask's count of samples.
#[derive(Clone, Copy, Debug, Default)]
struct MaskElement {
    mask: Mask,
    zmin: crate::Depth,
    zmax: crate::Depth,
}

/// The a-buffer method.
pub struct ABuffer {
    background: Colour,
    walker: SpanWalker,
    rows: ActiveRows,
    /// The frame's polygons on the screen 8 times finer, in stream order, their depth
    /// planes there, and the pixel columns each may cover.
    fine: Vec<Polygon>,
    planes: Vec<DepthPlane>,
    columns: Vec<(u32, u32)>,
    /// The frame's polygons' Gouraud shading on the screen of pixels, in stream order,
    /// when any is shaded (empty for a flat frame).
    shadings: Vec<Option<Shading>>,
    /// The stream's lighting, for Phong shading.
    lighting: Option<Arc<Lighting>>,
    /// Per cull block of the current row (from its first column): the occluding depth,
    /// whether it must be worked out again, whether the current polygon is left out.
    occluding: Vec<Depth>,
    stale: Vec<bool>,
    culled: Vec<bool>,
    /// Per pixel of the current row: its occluding depth, and whether the current
    /// polygon is left out there.
    occluding_px: Vec<Depth>,
    pixel_culled: Vec<bool>,
    /// Pixels left out one by one, by the cull.
    pub pixels_culled: u64,
    /// Polygon rows left out wholly, and blocks left out, by the cull.
    pub rows_culled: u64,
    pub blocks_culled: u64,
    /// The mask buffer of the current row, over the columns in use, and the elements
    /// the current polygon touched.
    masks: Vec<MaskElement>,
    touched: Vec<u32>,
    /// The current row's a-buffer.
    pixels: Vec<PixelStruct>,
    pool: Vec<Vec<Fragment>>,
    packer: Packer,
    row: Vec<Option<Colour>>,
    pub stats: ListStats,
    pub pixels_out: u64,
    /// Whether the cull runs (it changes no pixel: the tests compare).
    cull: bool,
}

impl ABuffer {
    pub fn new(background: Colour) -> Self {
        ABuffer {
            background,
            walker: SpanWalker::new(),
            rows: ActiveRows::new(),
            fine: Vec::new(),
            planes: Vec::new(),
            columns: Vec::new(),
            shadings: Vec::new(),
            lighting: None,
            occluding: Vec::new(),
            stale: Vec::new(),
            culled: Vec::new(),
            occluding_px: Vec::new(),
            pixel_culled: Vec::new(),
            pixels_culled: 0,
            rows_culled: 0,
            blocks_culled: 0,
            masks: Vec::new(),
            touched: Vec::new(),
            pixels: Vec::new(),
            pool: Vec::new(),
            packer: Packer::default(),
            row: Vec::new(),
            stats: ListStats::default(),
            pixels_out: 0,
            cull: true,
        }
    }

    /// The a-buffer without the cull: every fragment made and inserted (for the tests).
    pub fn without_cull(background: Colour) -> Self {
        ABuffer {
            cull: false,
            ..ABuffer::new(background)
        }
    }

    /// Scan converts the `active` polygons (stream order) over pixel row `r`'s eight
    /// sub-scanlines, columns `cols`, into the row's a-buffer; packs it; pushes its runs.
    /// `shadings` are the frame's polygons' shadings (empty for a flat frame).
    fn draw_row(
        &mut self,
        r: u32,
        active: &[u32],
        cols: std::ops::Range<u32>,
        fine_w: u32,
        runs: &mut Vec<Run>,
        shadings: &[Option<Shading>],
    ) {
        let n = (cols.end - cols.start) as usize;
        if self.masks.len() < n {
            self.masks.resize(n, MaskElement::default());
            self.pixels.resize(n, PixelStruct::Empty);
        }
        let band = r * K..r * K + K;
        let (fx0, fx1) = (cols.start * K, cols.end * K);
        let blocks = (n as u32).div_ceil(BLOCK) as usize;
        self.occluding.clear();
        self.occluding.resize(blocks, f64::INFINITY);
        self.stale.clear();
        self.stale.resize(blocks, false);
        self.culled.clear();
        self.culled.resize(blocks, false);
        self.occluding_px.clear();
        self.occluding_px.resize(n, f64::INFINITY);
        self.pixel_culled.clear();
        self.pixel_culled.resize(n, false);
        let mut row_occluding = f64::INFINITY;
        let mut row_stale = false;
        for &i in active {
            // The cull: the polygon's nearest depth over the row (then over each block)
            // against the farthest occluding depth there. The depth plane is linear along
            // a sub-scanline and monotone down the rows, so a rectangle's corners bound it.
            let plane = self.planes[i as usize];
            let (left, right) = self.columns[i as usize];
            let (left, right) = (left.max(cols.start), right.min(cols.end));
            if left >= right {
                continue;
            }
            let (top, bottom) = (plane.row(band.start), plane.row(band.end - 1));
            let nearest = |a: u32, b: u32| {
                let (x0, x1) = (a * K, b * K - 1);
                depth_at(top.0, top.1, x0)
                    .min(depth_at(top.0, top.1, x1))
                    .min(depth_at(bottom.0, bottom.1, x0))
                    .min(depth_at(bottom.0, bottom.1, x1))
            };
            if row_stale {
                for (b, stale) in self.stale.iter_mut().enumerate() {
                    if *stale {
                        let from = b * BLOCK as usize;
                        let to = (from + BLOCK as usize).min(n);
                        self.occluding[b] = self.occluding_px[from..to]
                            .iter()
                            .copied()
                            .fold(f64::NEG_INFINITY, f64::max);
                        *stale = false;
                    }
                }
                row_occluding = self
                    .occluding
                    .iter()
                    .copied()
                    .fold(f64::NEG_INFINITY, f64::max);
                row_stale = false;
            }
            if nearest(left, right) > row_occluding {
                self.rows_culled += 1;
                continue;
            }
            let (b0, b1) = (
                ((left - cols.start) / BLOCK) as usize,
                ((right - 1 - cols.start) / BLOCK) as usize + 1,
            );
            let mut any = false;
            for b in b0..b1 {
                let a = (cols.start + b as u32 * BLOCK).max(left);
                let e = (cols.start + (b as u32 + 1) * BLOCK).min(right);
                let out = nearest(a, e) > self.occluding[b];
                self.culled[b] = out;
                self.blocks_culled += out as u64;
                any |= !out;
            }
            if !any {
                continue;
            }
            // Within the blocks kept, pixel by pixel: the polygon's nearest depth over the
            // pixel against the pixel's occluding depth.
            if self.cull {
                // (A block with a pixel nothing covers fully has nothing to cull by.)
                for b in (b0..b1).filter(|&b| !self.culled[b] && self.occluding[b] != f64::INFINITY)
                {
                    let a = (cols.start + b as u32 * BLOCK).max(left);
                    let e = (cols.start + (b as u32 + 1) * BLOCK).min(right);
                    for c in a..e {
                        let k = (c - cols.start) as usize;
                        let out = nearest(c, c + 1) > self.occluding_px[k];
                        self.pixel_culled[k] = out;
                        self.pixels_culled += out as u64;
                    }
                }
            }
            let (masks, touched, culled) = (&mut self.masks, &mut self.touched, &self.culled);
            let pixel_culled = &self.pixel_culled;
            let cull = self.cull;
            // 6.3.3 (b): the mask buffer for this polygon's part of the row.
            self.walker
                .for_each_span_in(&self.fine[i as usize], fine_w, band.clone(), |s| {
                    let j = s.y - band.start;
                    let (x0, x1) = (s.x0.max(fx0), s.x1.min(fx1));
                    if x0 >= x1 {
                        return;
                    }
                    let mut c = x0 / K;
                    let end = (x1 - 1) / K + 1;
                    while c < end {
                        let b = ((c - cols.start) / BLOCK) as usize;
                        // (A block outside the polygon's own columns was not decided
                        // for it: never left out.)
                        if (b0..b1).contains(&b) && culled[b] {
                            // On to the next block.
                            c = cols.start + (b as u32 + 1) * BLOCK;
                            continue;
                        }
                        if cull
                            && (left..right).contains(&c)
                            && pixel_culled[(c - cols.start) as usize]
                        {
                            c += 1;
                            continue;
                        }
                        let lo = x0.max(c * K);
                        let hi = x1.min(c * K + K);
                        let bits = ((1u64 << (hi - lo)) - 1) << (lo - c * K) << (8 * j);
                        let (z0, z1) = (s.depth(lo), s.depth(hi - 1));
                        let e = &mut masks[(c - cols.start) as usize];
                        if e.mask == 0 {
                            touched.push(c - cols.start);
                            e.zmin = z0.min(z1);
                            e.zmax = z0.max(z1);
                        } else {
                            e.zmin = e.zmin.min(z0.min(z1));
                            e.zmax = e.zmax.max(z0.max(z1));
                        }
                        e.mask |= bits;
                        c += 1;
                    }
                });
            for &c in &self.touched {
                self.stale[(c / BLOCK) as usize] = true;
            }
            row_stale |= self.cull && !self.touched.is_empty();
            // 6.3.3 (d): a fragment for each pixel, into the a-buffer. A Gouraud-shaded
            // polygon's fragment takes its colour at the pixel centre: the a-buffer keeps
            // one colour a fragment.
            let colour = self.fine[i as usize].colour;
            match shadings.get(i as usize) {
                Some(Some(shading)) => {
                    let (row, x0) = (shading.row(r), cols.start);
                    self.insert_fragments(i, |c| row.at(x0 + c));
                }
                _ => self.insert_fragments(i, |_| colour),
            }
            self.touched.clear();
        }
        // Pack the row.
        self.row.clear();
        for p in &mut self.pixels[..n] {
            let colour = p.pack(self.background, &mut self.packer, &mut self.stats);
            self.pixels_out += colour.is_some() as u64;
            self.row.push(colour);
            p.clear(&mut self.pool);
        }
        push_row_runs_at(r, cols.start, &self.row, runs);
    }
}

impl ABuffer {
    /// 6.3.3 (d): a fragment for each element of the mask buffer polygon `i` touched, into
    /// the row's a-buffer, in the colour `colour_at` gives its column (from the row's first
    /// column in use): the polygon's, or a Gouraud-shaded polygon's at the pixel centre.
    #[inline(always)]
    fn insert_fragments(&mut self, i: u32, colour_at: impl Fn(u32) -> Colour) {
        let opacity = self.fine[i as usize].opacity;
        for &c in &self.touched {
            let e = std::mem::take(&mut self.masks[c as usize]);
            self.pixels[c as usize].insert(
                Fragment {
                    colour: colour_at(c),
                    mask: e.mask,
                    zmin: e.zmin,
                    zmax: e.zmax,
                    order: i,
                    opacity,
                },
                &mut self.pool,
                &mut self.stats,
            );
            if self.cull {
                self.occluding_px[c as usize] = self.pixels[c as usize].occluding_depth();
            }
        }
    }
}

impl HiddenSurface for ABuffer {
    fn resolve(&mut self, polygons: &[Polygon], width: u32, height: u32, runs: &mut Vec<Run>) {
        // A screen so wide that 8 of its rows overflow u32 keeps the columns that fit.
        let width = width.min(u32::MAX / K);
        let height = height.min(u32::MAX / K);
        self.fine.clear();
        self.fine.extend(polygons.iter().map(|p| scaled(p, K)));
        self.planes.clear();
        self.planes.extend(self.fine.iter().map(DepthPlane::of));
        self.columns.clear();
        self.columns.extend(
            polygons
                .iter()
                .map(|p| Extent::of(p, width, height).map_or((0, 0), |e| (e.left, e.right))),
        );
        self.shadings.clear();
        if polygons.iter().any(Polygon::is_shaded) {
            let lighting = self.lighting.as_ref();
            self.shadings
                .extend(polygons.iter().map(|p| Shading::of(p, lighting)));
        }
        self.rows.start(polygons, width, height);
        let mut from = self.rows.first_row().unwrap_or(height);
        let mut active = Vec::new();
        // Lent to the rows, which borrow the a-buffer mutably.
        let shadings = std::mem::take(&mut self.shadings);
        while let Some((r, cols)) = self.rows.next_row(from, height) {
            active.clear();
            active.extend_from_slice(self.rows.indices());
            self.draw_row(r, &active, cols, width * K, runs, &shadings);
            from = r + 1;
        }
        self.shadings = shadings;
        self.fine.clear();
    }

    /// Polygons of opacity below 255 are blended front to back by eq. 6.5 of the
    /// sampling thesis ([`list::Packer`]).
    fn transparency(&self) -> bool {
        true
    }

    /// A Gouraud- or Phong-shaded polygon's fragment has its colour at the pixel centre,
    /// lit there by the stream's lighting.
    fn lighting(&mut self) -> Option<&mut Option<Arc<Lighting>>> {
        Some(&mut self.lighting)
    }

    fn stats(&self) -> String {
        let s = self.stats;
        format!(
            "{} fragments, {} simple, {} lists, max list length {}, {} combined, {} hidden, \
             {} intersect cases, {} merged past {} a list, {} polygon rows, {} blocks and {} pixels culled, \
             {} pixels out",
            s.fragments,
            s.simple,
            s.lists,
            s.max_list,
            s.combined,
            s.hidden,
            s.intersections,
            s.merged,
            list::MAX_LIST,
            self.rows_culled,
            self.blocks_culled,
            self.pixels_culled,
            self.pixels_out
        )
    }

    fn counters(&self) -> Vec<(&'static str, String)> {
        let s = self.stats;
        [
            ("fragments", s.fragments),
            ("simple", s.simple),
            ("lists", s.lists),
            ("max_list", s.max_list),
            ("combined", s.combined),
            ("hidden", s.hidden),
            ("intersections", s.intersections),
            ("merged", s.merged),
            ("merge_limit", list::MAX_LIST as u64),
            ("rows_culled", self.rows_culled),
            ("blocks_culled", self.blocks_culled),
            ("pixels_culled", self.pixels_culled),
            ("pixels_out", self.pixels_out),
        ]
        .into_iter()
        .map(|(k, n)| (k, n.to_string()))
        .collect()
    }
}

#[cfg(test)]
mod tests;
