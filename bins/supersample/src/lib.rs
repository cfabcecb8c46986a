//! supersample: anti-aliasing by K×K samples per pixel, box-filtered (docs/DESIGN.md,
//! "Anti-aliasing"), as a leaf of the splitter tree.
//!
//! Sample (i, j) of pixel (c, r) lies at (c + (i+½)/K, r + (j+½)/K): the pixel centre
//! (K·c + i + ½, K·r + j + ½) of a screen K times finer. Each polygon is carried onto that
//! screen exactly ([`scan::fine::scaled`]; K is a power of two) and every sample is decided
//! there by the z-buffer's own rule: coverage by [`scan::SpanWalker`], depth by the
//! polygon's depth plane, decided by the tie rule (`scan::takes`).
//! The picture is thus the point-sampled K·W × K·H picture box-filtered in K×K blocks,
//! which is what `zspec --samples K` computes, in its own arithmetic.
//!
//! The filter: each channel is `(sum + K²/2) / K²` in integers, a sample no polygon covers
//! counting as the background colour. A pixel none of whose samples is covered is not
//! sent (the merger shows the background there, as for point sampling).
//!
//! Memory is bounded: the frame's polygons are gathered (as every frame-resolving method
//! does), sorted by their top row ([`scan::fine::ActiveRows`]), and the fine screen is
//! drawn one pixel row (K fine rows) at a time, over the columns the row's polygons may
//! reach: one band of K × K·W samples, never the K·W × K·H screen.

use proto::shade::{Lighting, Shading};
use proto::{Colour, Polygon};
use scan::fine::{scaled, ActiveRows};
use scan::frame::{push_row_runs_at, HiddenSurface};
use scan::{Run, SpanWalker};
use std::sync::Arc;

/// No polygon has covered the sample yet.
const NONE: u32 = u32::MAX;

/// Counters over all frames, for `--stats`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Samples a polygon covered (each depth-tested).
    pub samples_tested: u64,
    /// Samples whose polygon changed.
    pub samples_written: u64,
    /// Pixels sent, and of those the ones whose samples were not all one polygon's.
    pub pixels: u64,
    pub mixed: u64,
}

/// The supersampling method: K×K samples per pixel, box filter.
pub struct Supersample {
    k: u32,
    background: Colour,
    walker: SpanWalker,
    rows: ActiveRows,
    /// The frame's polygons on the fine screen, in stream order.
    fine: Vec<Polygon>,
    /// Per fine polygon, its Gouraud shading on the finer screen, if it has vertex
    /// colours (docs/DESIGN.md, "Shading"): each sample takes its colour at the sample.
    shading: Vec<Option<Shading>>,
    /// The lighting of a Phong-shaded stream: each sample is lit by it.
    lighting: Option<Arc<Lighting>>,
    /// The band: K fine rows of the columns in use, depth and polygon of each sample.
    depth: Vec<scan::Depth>,
    owner: Vec<u32>,
    /// One pixel row of finished pixels.
    row: Vec<Option<Colour>>,
    pub stats: Stats,
}

impl Supersample {
    /// K×K samples per pixel; K must satisfy [`scan::fine::valid_samples`] (a power of two
    /// up to 16), else the message says why.
    pub fn new(k: u32, background: Colour) -> Result<Self, String> {
        if !scan::fine::valid_samples(k) {
            return Err(format!(
                "{k} samples a side: K must be 1, 2, 4, 8 or 16 (a power of two, so that the \
                 finer screen is exact)"
            ));
        }
        Ok(Supersample {
            k,
            background,
            walker: SpanWalker::new(),
            rows: ActiveRows::new(),
            fine: Vec::new(),
            shading: Vec::new(),
            lighting: None,
            depth: Vec::new(),
            owner: Vec::new(),
            row: Vec::new(),
            stats: Stats::default(),
        })
    }

    /// Draws pixel row `r`'s K fine rows over columns `cols` for the `active` polygons
    /// (stream order), filters them and pushes the row's runs.
    fn draw_row(
        &mut self,
        r: u32,
        active: &[u32],
        cols: std::ops::Range<u32>,
        fine_w: u32,
        runs: &mut Vec<Run>,
    ) {
        let k = self.k;
        let band = r * k..r * k + k;
        let fx0 = cols.start * k;
        let n = ((cols.end - cols.start) * k) as usize;
        let len = n * k as usize;
        if self.depth.len() < len {
            self.depth.resize(len, 0.0);
            self.owner.resize(len, NONE);
        }
        self.owner[..len].fill(NONE);
        let (depth, owner, stats) = (&mut self.depth, &mut self.owner, &mut self.stats);
        for &i in active {
            self.walker
                .for_each_span_in(&self.fine[i as usize], fine_w, band.clone(), |s| {
                    let base = (s.y - band.start) as usize * n;
                    let (x0, x1) = (s.x0.max(fx0), s.x1.min(fx0 + n as u32));
                    for x in x0..x1 {
                        let at = base + (x - fx0) as usize;
                        let z = s.depth(x);
                        stats.samples_tested += 1;
                        // Polygons come in stream order, so the holder is the earlier
                        // one: the tie rule (the z-buffer's).
                        if (owner[at] == NONE && !z.is_nan()) || scan::takes(z, depth[at]) {
                            depth[at] = z;
                            owner[at] = i;
                            stats.samples_written += 1;
                        }
                    }
                });
        }
        // The box filter.
        let count = k * k;
        let pixels = (cols.end - cols.start) as usize;
        self.row.clear();
        // Whether any polygon of the frame is shaded: the flat loop asks nothing more.
        let shaded = self.shading.iter().any(Option::is_some);
        for c in 0..pixels {
            let mut sum = [0u32; 3];
            let mut covered = 0u32;
            let first = owner[c * k as usize];
            let mut mixed = false;
            for j in 0..k as usize {
                let at = j * n + c * k as usize;
                for (i, &o) in owner[at..at + k as usize].iter().enumerate() {
                    mixed |= o != first;
                    let colour = if o == NONE {
                        self.background
                    } else {
                        covered += 1;
                        match &self.shading[o as usize] {
                            // Sample (i, j) of pixel c is fine pixel (fx0 + cK + i, band + j).
                            Some(sh) if shaded => {
                                sh.at(fx0 + (c * k as usize + i) as u32, band.start + j as u32)
                            }
                            _ => self.fine[o as usize].colour,
                        }
                    };
                    for (s, v) in sum.iter_mut().zip(colour) {
                        *s += v as u32;
                    }
                }
            }
            self.row.push((covered > 0).then(|| {
                self.stats.pixels += 1;
                self.stats.mixed += mixed as u64;
                sum.map(|s| ((s + count / 2) / count) as u8)
            }));
        }
        push_row_runs_at(r, cols.start, &self.row, runs);
    }
}

impl HiddenSurface for Supersample {
    fn resolve(&mut self, polygons: &[Polygon], width: u32, height: u32, runs: &mut Vec<Run>) {
        let k = self.k;
        // A screen so wide that K of its rows overflow u32 keeps the columns that fit.
        let width = width.min(u32::MAX / k);
        let height = height.min(u32::MAX / k);
        let fine_w = width * k;
        self.fine.clear();
        self.fine.extend(polygons.iter().map(|p| scaled(p, k)));
        self.shading.clear();
        let lighting = self.lighting.as_ref();
        self.shading
            .extend(self.fine.iter().map(|p| Shading::of(p, lighting)));
        self.rows.start(polygons, width, height);
        let mut from = self.rows.first_row().unwrap_or(height);
        let mut active = Vec::new();
        while let Some((r, cols)) = self.rows.next_row(from, height) {
            active.clear();
            active.extend_from_slice(self.rows.indices());
            self.draw_row(r, &active, cols, fine_w, runs);
            from = r + 1;
        }
        self.fine.clear();
    }

    /// A Gouraud- or Phong-shaded polygon's sample takes its colour at the sample, lit
    /// there by the stream's lighting.
    fn lighting(&mut self) -> Option<&mut Option<Arc<Lighting>>> {
        Some(&mut self.lighting)
    }

    fn stats(&self) -> String {
        let s = self.stats;
        format!(
            "{0}x{0} samples, {1} samples tested, {2} written, {3} pixels out, {4} of them mixed",
            self.k, s.samples_tested, s.samples_written, s.pixels, s.mixed
        )
    }
}

#[cfg(test)]
mod tests;
