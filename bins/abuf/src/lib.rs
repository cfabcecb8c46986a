//! abuf: Carpenter's a-buffer as the sampling thesis, 6.3, builds it, as a leaf of the splitter
//! tree (docs/DESIGN.md, "Anti-aliasing").
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
//! is carried onto that screen exactly ([`scan::fine::scaled`]) and walked by
//! [`scan::SpanWalker`]: a sample on an edge shared by two polygons goes to exactly one
//! of them, so two polygons of one colour sharing an edge leave no seam (the sampling thesis's grey
//! seam, 6.3). The seed computes masks from each edge's crossings of the pixel, and'ed
//! together; here they are the spans of the pixel row's eight sub-scanlines, or'ed, which
//! is the same region sampled by the same rule as every other method. zmin and zmax are
//! the polygon's fixed-point depth plane at the fragment's covered samples (at the ends
//! of each sub-scanline's run, the plane being linear).
//!
//! Memory stays bounded (6.3.2's *mask buffer*): the frame's polygons are gathered and
//! sorted by their top row ([`scan::fine::ActiveRows`]), and the a-buffer is kept for one
//! pixel row at a time. For each row, each polygon that reaches it is walked over the
//! row's eight sub-scanlines into the mask buffer (one element per pixel of the row:
//! mask, zmin, zmax), whose touched elements become fragments; when every polygon of the
//! row is in, the row is packed and sent as runs. Memory is the polygons, one row of
//! pixelstructs and their fragments, never a frame of lists.

pub mod list;

use list::{Fragment, ListStats, Mask, Packer, PixelStruct};
use proto::{Colour, Polygon};
use scan::fine::{scaled, ActiveRows};
use scan::frame::{push_row_runs_at, HiddenSurface};
use scan::{Run, SpanWalker};

/// Sub-pixel samples a side.
pub const K: u32 = 8;

/// An element of the mask buffer (the sampling thesis, figure 6.9), less the area, which is the
/// mask's count of samples.
#[derive(Clone, Copy, Debug, Default)]
struct MaskElement {
    mask: Mask,
    zmin: scan::Depth,
    zmax: scan::Depth,
}

/// The a-buffer method.
pub struct ABuffer {
    background: Colour,
    walker: SpanWalker,
    rows: ActiveRows,
    /// The frame's polygons on the screen 8 times finer, in stream order.
    fine: Vec<Polygon>,
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
}

impl ABuffer {
    pub fn new(background: Colour) -> Self {
        ABuffer {
            background,
            walker: SpanWalker::new(),
            rows: ActiveRows::new(),
            fine: Vec::new(),
            masks: Vec::new(),
            touched: Vec::new(),
            pixels: Vec::new(),
            pool: Vec::new(),
            packer: Packer::default(),
            row: Vec::new(),
            stats: ListStats::default(),
            pixels_out: 0,
        }
    }

    /// Scan converts the `active` polygons (stream order) over pixel row `r`'s eight
    /// sub-scanlines, columns `cols`, into the row's a-buffer; packs it; pushes its runs.
    fn draw_row(
        &mut self,
        r: u32,
        active: &[u32],
        cols: std::ops::Range<u32>,
        fine_w: u32,
        runs: &mut Vec<Run>,
    ) {
        let n = (cols.end - cols.start) as usize;
        if self.masks.len() < n {
            self.masks.resize(n, MaskElement::default());
            self.pixels.resize(n, PixelStruct::Empty);
        }
        let band = r * K..r * K + K;
        let (fx0, fx1) = (cols.start * K, cols.end * K);
        for &i in active {
            let (masks, touched) = (&mut self.masks, &mut self.touched);
            // 6.3.3 (b): the mask buffer for this polygon's part of the row.
            self.walker
                .for_each_span_in(&self.fine[i as usize], fine_w, band.clone(), |s| {
                    let j = s.y - band.start;
                    let (x0, x1) = (s.x0.max(fx0), s.x1.min(fx1));
                    if x0 >= x1 {
                        return;
                    }
                    for c in x0 / K..(x1 - 1) / K + 1 {
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
                    }
                });
            // 6.3.3 (d): a fragment for each pixel, into the a-buffer.
            let colour = self.fine[i as usize].colour;
            for &c in &self.touched {
                let e = std::mem::take(&mut self.masks[c as usize]);
                self.pixels[c as usize].insert(
                    Fragment {
                        colour,
                        mask: e.mask,
                        zmin: e.zmin,
                        zmax: e.zmax,
                        order: i,
                    },
                    &mut self.pool,
                    &mut self.stats,
                );
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

impl HiddenSurface for ABuffer {
    fn resolve(&mut self, polygons: &[Polygon], width: u32, height: u32, runs: &mut Vec<Run>) {
        // A screen so wide that 8 of its rows overflow u32 keeps the columns that fit.
        let width = width.min(u32::MAX / K);
        let height = height.min(u32::MAX / K);
        self.fine.clear();
        self.fine.extend(polygons.iter().map(|p| scaled(p, K)));
        self.rows.start(polygons, width, height);
        let mut from = self.rows.first_row().unwrap_or(height);
        let mut active = Vec::new();
        while let Some((r, cols)) = self.rows.next_row(from, height) {
            active.clear();
            active.extend_from_slice(self.rows.indices());
            self.draw_row(r, &active, cols, width * K, runs);
            from = r + 1;
        }
        self.fine.clear();
    }

    fn stats(&self) -> String {
        let s = self.stats;
        format!(
            "{} fragments, {} simple, {} lists, max list length {}, {} combined, {} hidden, \
             {} intersect cases, {} pixels out",
            s.fragments,
            s.simple,
            s.lists,
            s.max_list,
            s.combined,
            s.hidden,
            s.intersections,
            self.pixels_out
        )
    }
}

#[cfg(test)]
mod tests;
