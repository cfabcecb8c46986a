//! Supersampling: anti-aliasing by K×K samples per pixel, box-filtered (docs/DESIGN.md,
//! "Anti-aliasing"): the method of the `supersample` leaf of the splitter tree, and of
//! `zbuf --aa ssK` and `adaptiveK`, which runs it in the leaf's place at depth 0.
//!
//! Sample (i, j) of pixel (c, r) lies at (c + (i+½)/K, r + (j+½)/K): the pixel centre
//! (K·c + i + ½, K·r + j + ½) of a screen K times finer. Each polygon is carried onto that
//! screen exactly ([`crate::fine::scaled`]; K is a power of two) and every sample is decided
//! there by the z-buffer's own rule: coverage by [`crate::SpanWalker`], depth by the
//! polygon's depth plane, decided by the tie rule (`crate::takes`).
//! The picture is thus the point-sampled K·W × K·H picture box-filtered in K×K blocks,
//! which is what `zspec --samples K` computes, in its own arithmetic.
//!
//! The filter: each channel is `(sum + K²/2) / K²` in integers, a sample no polygon covers
//! counting as the background colour. A pixel none of whose samples is covered is not
//! sent (the merger shows the background there, as for point sampling).
//!
//! Memory is bounded: the frame's polygons are gathered (as every frame-resolving method
//! does), sorted by their top row ([`crate::fine::ActiveRows`]), and the fine screen is
//! drawn one pixel row (K fine rows) at a time, over the columns the row's polygons may
//! reach: one band of K × K·W samples, never the K·W × K·H screen.

use crate::fine::{scaled, ActiveRows};
use crate::frame::{push_row_runs_at, HiddenSurface};
use crate::{BandWalk, Outline, Run, Span};
use proto::shade::{Lighting, Shading};
use proto::{Colour, Polygon};
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
    /// Adaptively: the pixels the test found mixed, whose K×K samples were decided,
    /// folded or counted (the others took one polygon's colour).
    pub sampled: u64,
}

/// The supersampling method: K×K samples per pixel, box filter.
pub struct Supersample {
    k: u32,
    background: Colour,
    walks: Walks,
    rows: ActiveRows,
    /// The fine screen's height.
    fine_h: u32,
    /// The frame's polygons on the fine screen, in stream order.
    fine: Vec<Polygon>,
    /// Per fine polygon, its Gouraud shading on the finer screen, if it has vertex
    /// colours (docs/DESIGN.md, "Shading"): each sample takes its colour at the sample.
    shading: Vec<Option<Shading>>,
    /// The lighting of a Phong-shaded stream: each sample is lit by it.
    lighting: Option<Arc<Lighting>>,
    /// Whether any polygon of the frame is shaded: the flat loop asks nothing more.
    shaded: bool,
    /// The band: K fine rows of the columns in use, depth and polygon of each sample.
    depth: Vec<crate::Depth>,
    owner: Vec<u32>,
    /// One pixel row of finished pixels.
    row: Vec<Option<Colour>>,
    /// Adaptive sampling: K×K samples only in the pixels that need them.
    adaptive: bool,
    /// Adaptively, clusters in depth order counted, not swept (off only in tests, to
    /// compare the two).
    ordered_clusters: bool,
    /// Per fine polygon, its flat colour: the filter reads this, not the polygons.
    colours: Vec<Colour>,
    /// The same packed for the flat filter, the background last.
    packed: Vec<Packed>,
    /// Adaptively, the row's spans (the touches' spans, in stream order), its touches,
    /// the sweep's events and its set of touches now, and the row's pieces with the
    /// touch sets of the mixed ones.
    spans: Vec<Span>,
    touches: Vec<Touch>,
    order: Vec<u64>,
    events: Vec<u64>,
    set: Vec<u32>,
    pieces: Vec<Piece>,
    sets: Vec<u32>,
    /// Adaptively, an ordered cluster's pixels as it is counted front to back
    /// ([`Supersample::count_ordered`]), and its touches' masks at the pixels they cover
    /// partly.
    held: Vec<u64>,
    sums: Vec<u64>,
    masks: Vec<u64>,
    pub stats: Stats,
}

impl Supersample {
    /// K×K samples per pixel; K must satisfy [`crate::fine::valid_samples`] (a power of two
    /// up to 16), else the message says why.
    pub fn new(k: u32, background: Colour) -> Result<Self, String> {
        if !crate::fine::valid_samples(k) {
            return Err(format!(
                "{k} samples a side: K must be 1, 2, 4, 8 or 16 (a power of two, so that the \
                 finer screen is exact)"
            ));
        }
        Ok(Supersample {
            k,
            background,
            walks: Walks::default(),
            rows: ActiveRows::new(),
            fine_h: 0,
            fine: Vec::new(),
            shading: Vec::new(),
            lighting: None,
            shaded: false,
            depth: Vec::new(),
            owner: Vec::new(),
            row: Vec::new(),
            adaptive: false,
            ordered_clusters: true,
            colours: Vec::new(),
            packed: Vec::new(),
            spans: Vec::new(),
            touches: Vec::new(),
            order: Vec::new(),
            events: Vec::new(),
            set: Vec::new(),
            pieces: Vec::new(),
            sets: Vec::new(),
            held: Vec::new(),
            sums: Vec::new(),
            masks: Vec::new(),
            stats: Stats::default(),
        })
    }

    /// Adaptive supersampling: K×K samples only in the pixels that an edge, a silhouette
    /// or a crossing of two polygons touches, one polygon's colour elsewhere (see
    /// [`Supersample::classify`]): the same bytes as all K² samples on flat polygons.
    pub fn adaptive(mut self) -> Self {
        self.adaptive = true;
        self
    }

    /// Pixel row `r`'s band over columns `cols` on the fine screen: its K fine rows, its
    /// first fine column and its width in fine columns.
    fn band(&self, r: u32, cols: &std::ops::Range<u32>) -> (std::ops::Range<u32>, u32, usize) {
        let k = self.k;
        (
            r * k..r * k + k,
            cols.start * k,
            ((cols.end - cols.start) * k) as usize,
        )
    }

    /// Draws pixel row `r`'s K fine rows over columns `cols` for the `active` polygons
    /// (stream order), filters them and pushes the row's runs. Adaptively, only the
    /// pixels [`Supersample::classify`] finds mixed are sampled, by the same fold and the
    /// same filter; the others take their one polygon's colour.
    fn draw_row(
        &mut self,
        r: u32,
        active: &[u32],
        cols: std::ops::Range<u32>,
        fine_w: u32,
        runs: &mut Vec<Run>,
    ) {
        let k = self.k;
        let (band, fx0, n) = self.band(r, &cols);
        let len = n * k as usize;
        if self.depth.len() < len {
            self.depth.resize(len, 0.0);
            self.owner.resize(len, NONE);
        }
        if self.adaptive {
            return self.draw_row_adaptive(r, active, cols, fine_w, runs);
        }
        self.owner[..len].fill(NONE);
        let (depth, owner, stats) = (&mut self.depth, &mut self.owner, &mut self.stats);
        for &i in active {
            let p = &self.fine[i as usize];
            self.walks
                .spans(i, p, fine_w, self.fine_h, band.clone(), |s| {
                    let (x0, x1) = (s.x0.max(fx0), s.x1.min(fx0 + n as u32));
                    sample(&s, i, x0..x1, fx0, n, band.start, depth, owner, stats);
                });
        }
        // The box filter.
        let pixels = (cols.end - cols.start) as usize;
        self.row.clear();
        for c in 0..pixels {
            let colour = self.filter(c, fx0, n, band.start);
            self.row.push(colour);
        }
        push_row_runs_at(r, cols.start, &self.row, runs);
    }

    /// The box filter of pixel c of the row (its first fine column `fx0 + cK`, the band
    /// `n` fine columns wide from fine row `fy`): each channel `(sum + K²/2) / K²`, an
    /// uncovered sample counting as the background; `None` when no sample is covered.
    ///
    /// A flat frame sums packed colours ([`Packed`]): one addition a sample, the
    /// background at the end of the table, where an uncovered sample's index lands.
    #[inline]
    fn filter(&mut self, c: usize, fx0: u32, n: usize, fy: u32) -> Option<Colour> {
        let k = self.k as usize;
        let first = self.owner[c * k];
        let mut mixed = false;
        let mut covered = 0u32;
        let sum = if self.shaded {
            let mut sum = [0u32; 3];
            for j in 0..k {
                let at = j * n + c * k;
                for (i, &o) in self.owner[at..at + k].iter().enumerate() {
                    mixed |= o != first;
                    let colour = match o {
                        NONE => self.background,
                        o => {
                            covered += 1;
                            match &self.shading[o as usize] {
                                // Sample (i, j) of pixel c is fine pixel
                                // (fx0 + cK + i, fy + j).
                                Some(sh) => sh.at(fx0 + (c * k + i) as u32, fy + j as u32),
                                None => self.colours[o as usize],
                            }
                        }
                    };
                    for (s, v) in sum.iter_mut().zip(colour) {
                        *s += v as u32;
                    }
                }
            }
            sum
        } else {
            let background = self.packed.len() - 1;
            let mut sum = 0u64;
            for j in 0..k {
                let at = j * n + c * k;
                for &o in &self.owner[at..at + k] {
                    mixed |= o != first;
                    covered += (o != NONE) as u32;
                    sum += self.packed[(o as usize).min(background)].0;
                }
            }
            Packed(sum).channels()
        };
        self.filtered(sum, covered, mixed)
    }

    /// The box filter's end, whatever made the sums: each channel's sum of K² samples
    /// `(sum + K²/2) / K²`, counted in the stats; `None` (not sent) when no sample of the
    /// pixel is `covered`. `mixed`: its samples are not all one polygon's.
    #[inline]
    fn filtered(&mut self, sum: [u32; 3], covered: u32, mixed: bool) -> Option<Colour> {
        (covered > 0).then(|| {
            self.stats.pixels += 1;
            self.stats.mixed += mixed as u64;
            self.rounded(sum)
        })
    }

    /// Each channel's sum of K² samples as the box filter rounds it, `(sum + K²/2) / K²`.
    #[inline]
    fn rounded(&self, sum: [u32; 3]) -> Colour {
        let count = self.k * self.k;
        // K² is a power of two: a shift, not a division (three a mixed pixel).
        let shift = count.trailing_zeros();
        sum.map(|s| ((s + count / 2) >> shift) as u8)
    }

    /// The channels of `sum`, packed colours of `covered` samples of a pixel, with the
    /// background counted at each of its other samples.
    #[inline]
    fn with_background(&self, sum: u64, covered: u32) -> [u32; 3] {
        let background = self.packed[self.packed.len() - 1].0;
        Packed(sum + (self.k * self.k - covered) as u64 * background).channels()
    }

    /// [`Supersample::draw_row`] adaptively: the row's spans walked and the pixels
    /// classified ([`Supersample::classify`]), the mixed ones sampled and filtered as
    /// whole supersampling does, the uniform ones their polygon's colour; the row's runs
    /// pushed left to right, maximal runs of one colour as
    /// [`crate::frame::push_row_runs_at`] makes them.
    fn draw_row_adaptive(
        &mut self,
        r: u32,
        active: &[u32],
        cols: std::ops::Range<u32>,
        fine_w: u32,
        runs: &mut Vec<Run>,
    ) {
        let k = self.k;
        let (band, fx0, n) = self.band(r, &cols);
        self.classify(active, cols.clone(), fine_w, band.clone());
        // The mixed pieces whose touches are in depth order are counted; the others
        // sampled, each by the polygons that touch it, in stream order, over its own fine
        // columns only.
        if !self.shaded {
            for piece in &mut self.pieces {
                if let Fill::Mixed(set) = &piece.fill {
                    let set = set.clone();
                    let touches = &mut self.sets[set.start as usize..set.end as usize];
                    if in_depth_order(touches, &self.touches) {
                        piece.fill = Fill::Counted(set);
                    }
                }
            }
        }
        let (depth, owner, stats) = (&mut self.depth, &mut self.owner, &mut self.stats);
        for piece in &self.pieces {
            let Fill::Mixed(set) = piece.fill.clone() else {
                continue;
            };
            let (p0, p1) = (fx0 + piece.px.start * k, fx0 + piece.px.end * k);
            for j in 0..k as usize {
                let at = j * n + (p0 - fx0) as usize;
                owner[at..at + (p1 - p0) as usize].fill(NONE);
            }
            for &t in &self.sets[set.start as usize..set.end as usize] {
                let touch = &self.touches[t as usize];
                for s in &self.spans[touch.spans.start as usize..touch.spans.end as usize] {
                    let (a, b) = (s.x0.max(p0), s.x1.min(p1));
                    if a < b {
                        sample(s, touch.i, a..b, fx0, n, band.start, depth, owner, stats);
                    }
                }
            }
        }
        // The row's pixels, left to right, as runs.
        let row_start = runs.len();
        let push = |runs: &mut Vec<Run>, x0: u32, x1: u32, colour: Colour| match runs[row_start..]
            .last_mut()
        {
            Some(last) if last.x1 == x0 && last.colour == colour => last.x1 = x1,
            _ => runs.push(Run {
                y: r,
                x0,
                x1,
                colour,
            }),
        };
        for p in 0..self.pieces.len() {
            let Piece { px, fill } = self.pieces[p].clone();
            match fill {
                Fill::Uniform(o) if !self.shaded => {
                    // A run of one polygon's pixels at once.
                    self.stats.pixels += px.len() as u64;
                    let colour = self.colours[o as usize];
                    push(runs, cols.start + px.start, cols.start + px.end, colour);
                }
                Fill::Uniform(o) => {
                    for c in px.clone() {
                        self.stats.pixels += 1;
                        let (fx, fy) = (fx0 + c * k, band.start);
                        let colour = match &self.shading[o as usize] {
                            // Phong: every sample lit, as whole supersampling lights them.
                            Some(sh) if self.lighting.is_some() => block_mean(sh, fx, fy, 0..k),
                            // Gouraud: the central 2×2 samples.
                            Some(sh) => block_mean(sh, fx, fy, k / 2 - 1..k / 2 + 1),
                            None => self.colours[o as usize],
                        };
                        let x = cols.start + c;
                        push(runs, x, x + 1, colour);
                    }
                }
                Fill::Ordered(set) => {
                    self.count_ordered(px.clone(), set, fx0, band.start);
                    // Runs of pixels alike (the same samples held, the same sum) at once.
                    let mut c = 0;
                    while c < px.len() {
                        let (held, sum) = (self.held[c], self.sums[c]);
                        let mut e = c + 1;
                        while e < px.len() && self.held[e] == held && self.sums[e] == sum {
                            e += 1;
                        }
                        // A pixel no touch won is sampled, as the sweep's mixed pixels
                        // are, even where no sample is held (between two spans of one
                        // row of a concave polygon): then it is not sent.
                        let n = (e - c) as u64;
                        self.stats.sampled += (sum & WON == 0) as u64 * n;
                        if held != 0 {
                            self.stats.pixels += n;
                            self.stats.mixed += (sum & ONE == 0) as u64 * n;
                            let sum = sum & !(ONE | WON | REACHED);
                            let colour = self.rounded(self.with_background(sum, held.count_ones()));
                            let x = cols.start + px.start + c as u32;
                            push(runs, x, x + (e - c) as u32, colour);
                        }
                        c = e;
                    }
                }
                Fill::Mixed(_) | Fill::Counted(_) => {
                    for c in px.clone() {
                        self.stats.sampled += 1;
                        let colour = match &fill {
                            Fill::Counted(set) => self.coverage(set.clone(), c, fx0, band.start),
                            _ => self.filter(c as usize, fx0, n, band.start),
                        };
                        if let Some(colour) = colour {
                            let x = cols.start + c;
                            push(runs, x, x + 1, colour);
                        }
                    }
                }
            }
        }
    }

    /// The pixels `px` of an ordered cluster ([`Fill::Ordered`], its touches `sets[set]`
    /// front to back) counted into `held` and `sums`: each touch, front to back, takes
    /// the samples of its spans that no touch in front of it holds, each pixel as
    /// [`Supersample::coverage`] counts it, but a touch at a time over its pixels: those it
    /// covers wholly all K² samples at once, the others (at its ends) by masks of its
    /// spans (`fy` the band's first fine row). A pixel's sum is of packed colours, with
    /// [`ONE`] set where one touch took all K² samples, and [`WON`] where the nearest
    /// touch covers it wholly.
    fn count_ordered(
        &mut self,
        px: std::ops::Range<u32>,
        set: std::ops::Range<u32>,
        fx0: u32,
        fy: u32,
    ) {
        let k = self.k;
        let shift = k.trailing_zeros();
        let count = k * k;
        let full = u64::MAX >> (64 - count);
        let n = px.len();
        self.held.clear();
        self.held.resize(n, 0);
        self.sums.clear();
        self.sums.resize(n, 0);
        if self.masks.len() < n {
            self.masks.resize(n, 0);
        }
        let (held, sums, masks) = (&mut self.held, &mut self.sums, &mut self.masks);
        for &t in &self.sets[set.start as usize..set.end as usize] {
            let touch = &self.touches[t as usize];
            let colour = self.packed[touch.i as usize].0;
            let (t0, t1) = (touch.touched.start, touch.touched.end);
            let whole = if touch.whole.is_empty() {
                t1..t1
            } else {
                touch.whole.clone()
            };
            // The partly covered pixels' masks, span by span (the spans reach no pixel
            // outside the touched ones, which were found from them).
            for s in &self.spans[touch.spans.start as usize..touch.spans.end as usize] {
                let (x0, x1) = (s.x0.max(fx0 + t0 * k), s.x1.min(fx0 + t1 * k));
                if x0 >= x1 {
                    continue;
                }
                let row = (s.y - fy) * k;
                // The span's first and last pixels, which it may cover partly, and those
                // between, whose K samples on its fine row it holds all of.
                let (first, last) = ((x0 - fx0) >> shift, (x1 - 1 - fx0) >> shift);
                let bits = ((1u64 << k) - 1) << row;
                for q in [
                    first + 1..last.min(whole.start),
                    (first + 1).max(whole.end)..last,
                ] {
                    let q = (q.start - px.start) as usize..(q.end.max(q.start) - px.start) as usize;
                    for m in &mut masks[q] {
                        *m |= bits;
                    }
                }
                for p in [first, last] {
                    if !whole.contains(&p) {
                        masks[(p - px.start) as usize] |= pixel_bits(x0, x1, fx0 + p * k, k) << row;
                    }
                    if last == first {
                        break;
                    }
                }
            }
            let (t0, t1) = ((t0 - px.start) as usize, (t1 - px.start) as usize);
            let (w0, w1) = (
                (whole.start - px.start) as usize,
                (whole.end - px.start) as usize,
            );
            let counted = |held: &mut u64, sum: &mut u64, mask: u64| {
                let new = mask & !*held;
                *held |= mask;
                *sum += if new == full {
                    (count as u64 * colour) | ONE
                } else {
                    new.count_ones() as u64 * colour
                };
            };
            for p in (t0..w0).chain(w1..t1) {
                counted(&mut held[p], &mut sums[p], std::mem::take(&mut masks[p]));
                sums[p] |= REACHED;
            }
            // Wholly covered: all K² samples where none is held (the nearest touch there,
            // which wins the pixel), none where all are, else those not held.
            let all = (count as u64 * colour) | ONE | WON;
            for (h, sum) in held[w0..w1].iter_mut().zip(&mut sums[w0..w1]) {
                if *sum == 0 {
                    (*h, *sum) = (full, all);
                } else if *h != full {
                    counted(h, sum, full);
                }
            }
        }
    }

    /// Pixel c's colour when the touches `sets[set]`, front to back, are in depth order
    /// ([`in_depth_order`]), without the fold: each sample shows the nearest touch that
    /// covers it, so front to back each touch counts the samples of its spans that no
    /// touch in front of it covers (a mask of the pixel's K columns a fine row, `fy` the
    /// band's first), and the sum the filter makes is Σ count·colour + (K² − Σ
    /// count)·background: [`Supersample::filter`]'s bytes. `None` when none is covered.
    fn coverage(&mut self, set: std::ops::Range<u32>, c: u32, fx0: u32, fy: u32) -> Option<Colour> {
        let k = self.k;
        let count = k * k;
        let x0 = fx0 + c * k;
        let (mut sum, mut covered, mut one) = (0u64, 0u32, false);
        if k <= 8 {
            // The pixel's K² samples in one mask, fine row j at bits jK..jK + K: one count
            // a touch.
            let mut held = 0u64;
            for &t in &self.sets[set.start as usize..set.end as usize] {
                let touch = &self.touches[t as usize];
                let mut mask = 0u64;
                for s in &self.spans[touch.spans.start as usize..touch.spans.end as usize] {
                    mask |= pixel_bits(s.x0, s.x1, x0, k) << ((s.y - fy) * k);
                }
                let mine = (mask & !held).count_ones();
                held |= mask;
                sum += mine as u64 * self.packed[touch.i as usize].0;
                covered += mine;
                one |= mine == count;
            }
            let sum = self.with_background(sum, covered);
            return self.filtered(sum, covered, !one);
        }
        let mut rows = [0u32; 16];
        for &t in &self.sets[set.start as usize..set.end as usize] {
            let touch = &self.touches[t as usize];
            let mut mine = 0;
            for s in &self.spans[touch.spans.start as usize..touch.spans.end as usize] {
                // K ≤ 16 columns: a fine row's bits fit a u32.
                let bits = pixel_bits(s.x0, s.x1, x0, k) as u32;
                let row = &mut rows[(s.y - fy) as usize];
                mine += (bits & !*row).count_ones();
                *row |= bits;
            }
            sum += mine as u64 * self.packed[touch.i as usize].0;
            covered += mine;
            one |= mine == count;
        }
        let sum = self.with_background(sum, covered);
        self.filtered(sum, covered, !one)
    }

    /// Adaptive sampling's test: the row cut into pieces, left to right, each either
    /// uniform (one polygon wins every sample of its pixels: [`Fill::Uniform`]) or mixed
    /// (to be sampled, with the polygons that touch it: [`Fill::Mixed`]); pixels no
    /// polygon reaches are in no piece. Walks the row's spans once, keeping them in
    /// `spans` for the sampling.
    ///
    /// A polygon *covers* pixel c wholly when each of the band's K fine rows has exactly
    /// one of its spans and that span holds all K of the pixel's sample columns; every
    /// other pixel its spans reach it *touches*. Each touch carries the least and greatest
    /// depth the fold can compute at the pixel's samples: a sample's depth is
    /// `z_row + x·dz` rounded twice ([`Span::depth`]), monotone in `z_row` and in `x`
    /// (rounding to nearest is monotone), so the bounds are that expression at the least
    /// and greatest `z_row` of the polygon's rows in the band and at the pixel's first
    /// and last sample column, exact and attained. A pixel is uniform when a polygon P
    /// covers it wholly and its greatest depth is below the tie bar ([`proto::depth::bar`])
    /// of every other toucher's least: then at every sample P takes the sample from
    /// whoever holds it, and no later polygon takes it from P ([`crate::takes`]), so the
    /// fold ends at P everywhere, and K² samples of one flat colour filter to that colour.
    /// Hidden edges under P, and crossings of polygons, leave the pixel mixed unless P is
    /// in front of them by more than the tie at every sample.
    ///
    /// The test works on the row's touches, not on every pixel. The touches are taken left
    /// to right in clusters whose touched pixels overlap. A touch alone is three pieces at
    /// once: its partly covered pixels at each end mixed, those between uniform. A
    /// cluster of a flat frame whose touches are in depth order is one piece, counted
    /// front to back without a test ([`Supersample::ordered`]). Another cluster
    /// is swept ([`Supersample::sweep`]): the ends of its touches' touched and wholly
    /// covered pixels cut it into segments over which the same polygons touch and the
    /// same ones cover. A segment one polygon touches is uniform where it covers and mixed
    /// where it does not. A segment two or more touch is tested as one pixel, first with
    /// each touch's depth bounds over all its pixels in the row, then with its bounds over
    /// the segment (the bounds are monotone along the row, so both are those at the two
    /// end pixels), and pixel by pixel only when both fail. A segment that passes passes
    /// at each of its pixels with the same polygon (its bounds hold each pixel's, and
    /// `bar` is monotone), so the verdicts are those of the pixel-by-pixel test
    /// everywhere.
    fn classify(
        &mut self,
        active: &[u32],
        cols: std::ops::Range<u32>,
        fine_w: u32,
        band: std::ops::Range<u32>,
    ) {
        let k = self.k;
        self.spans.clear();
        self.touches.clear();
        self.order.clear();
        let (fx0, fx1) = (cols.start * k, cols.end * k);
        let shift = k.trailing_zeros();
        for &i in active {
            let from = self.spans.len();
            let spans = &mut self.spans;
            let p = &self.fine[i as usize];
            self.walks
                .spans(i, p, fine_w, self.fine_h, band.clone(), |s| {
                    if s.x0.max(fx0) < s.x1.min(fx1) {
                        spans.push(s);
                    }
                });
            let mine = &self.spans[from..];
            let Some(&s0) = mine.first() else {
                continue;
            };
            let dz = s0.dz;
            let (mut zmin, mut zmax) = (s0.z_row, s0.z_row);
            // Touched pixels t0..t1, wholly covered ones a..b (relative to cols.start).
            let (mut t0, mut t1) = (u32::MAX, 0);
            let (mut a, mut b) = (0, u32::MAX);
            let one_span_a_row =
                mine.len() == k as usize && mine.windows(2).all(|w| w[0].y < w[1].y);
            let mut nan = false;
            for s in mine {
                zmin = zmin.min(s.z_row);
                zmax = zmax.max(s.z_row);
                nan |= s.z_row.is_nan();
                let (x0, x1) = (s.x0.max(fx0) - fx0, s.x1.min(fx1) - fx0);
                // K is a power of two: shifts, not divisions.
                let (first, end) = (x0 >> shift, (x1 + k - 1) >> shift);
                t0 = t0.min(first);
                t1 = t1.max(end);
                a = a.max((x0 + k - 1) >> shift);
                b = b.min(x1 >> shift);
            }
            if !one_span_a_row || nan {
                // Some row with no span or several: no pixel wholly covered (safe);
                // a NaN depth: the row's touches all mixed.
                (a, b) = (0, 0);
                if nan {
                    (zmin, zmax) = (f64::NAN, f64::NAN);
                }
            }
            let mut touch = Touch {
                i,
                spans: from as u32..self.spans.len() as u32,
                zmin,
                zmax,
                dz,
                touched: t0..t1,
                whole: a..b.max(a),
                finite: true,
                lo: f64::NAN,
                hi: f64::NAN,
            };
            // Its depth bounds are monotone across the row, so those at the ends of its
            // pixels hold all of them, and finite there means finite at all of them; a
            // touch that is not is tested pixel by pixel, where `Class::touch` decides each.
            let ((lo0, hi0), (lo1, hi1)) = (touch.depths(t0, fx0, k), touch.depths(t1 - 1, fx0, k));
            touch.finite = [lo0, hi0, lo1, hi1].iter().all(|z| z.is_finite());
            (touch.lo, touch.hi) = (lo0.min(lo1), hi0.max(hi1));
            self.order
                .push((t0 as u64) << 32 | self.touches.len() as u64);
            self.touches.push(touch);
        }
        self.pieces.clear();
        self.sets.clear();
        // The touches left to right, in clusters whose touched pixels overlap: a touch
        // alone is three pieces at once, a cluster is swept.
        self.order.sort_unstable();
        let mut c = 0;
        while c < self.order.len() {
            let first = self.order[c] as u32;
            let mut end = self.touches[first as usize].touched.end;
            let mut d = c + 1;
            while let Some(&o) = self.order.get(d).filter(|&&o| ((o >> 32) as u32) < end) {
                end = end.max(self.touches[o as u32 as usize].touched.end);
                d += 1;
            }
            if d == c + 1 {
                // Alone: its three segments are known without a sweep (partly covered
                // pixels, wholly covered ones, partly covered ones; empty ones add
                // nothing).
                let touch = &self.touches[first as usize];
                let (touched, whole) = (touch.touched.clone(), touch.whole.clone());
                self.set.clear();
                self.set.push(first);
                if whole.is_empty() {
                    self.segment(touched, fx0);
                } else {
                    self.segment(touched.start..whole.start, fx0);
                    self.segment(whole.clone(), fx0);
                    self.segment(whole.end..touched.end, fx0);
                }
            } else if !self.ordered(c..d, end) {
                self.sweep(c..d, fx0);
            }
            c = d;
        }
    }

    /// Whether the cluster of touches `order[cluster]` (its pixels up to `end`) is in
    /// depth order ([`in_depth_order`]) in a flat frame, with K ≤ 8 (a pixel's samples in
    /// one `u64`): then it is one piece, [`Fill::Ordered`], its touches front to back,
    /// counted pixel by pixel without a sweep ([`Supersample::count_ordered`]).
    ///
    /// Its verdicts are the sweep's: in depth order, the pixels where the nearest touch
    /// covers wholly are those the sweep finds uniform (that touch is in front of every
    /// other there, by more than the tie, at the row's bounds and so at the pixel's), and
    /// there it counts K² samples of that touch, that polygon's colour.
    fn ordered(&mut self, cluster: std::ops::Range<usize>, end: u32) -> bool {
        if self.shaded || self.k > 8 || !self.ordered_clusters {
            return false;
        }
        self.set.clear();
        self.set
            .extend(self.order[cluster.clone()].iter().map(|&o| o as u32));
        if !in_depth_order(&mut self.set, &self.touches) {
            return false;
        }
        let start = self.sets.len() as u32;
        self.sets.extend_from_slice(&self.set);
        let first = (self.order[cluster.start] >> 32) as u32;
        self.push_piece(first..end, Fill::Ordered(start..self.sets.len() as u32));
        true
    }

    /// [`Supersample::classify`]'s sweep over the touches `order[cluster]`: their ends
    /// cut the cluster's pixels into segments over which the same polygons touch and the
    /// same ones cover wholly, each classified by [`Supersample::segment`].
    fn sweep(&mut self, cluster: std::ops::Range<usize>, fx0: u32) {
        self.events.clear();
        for &o in &self.order[cluster] {
            let t = o as u32 as u64;
            let touch = &self.touches[t as usize];
            self.events
                .push(Event::at(touch.touched.start, Event::ENTER, t));
            self.events
                .push(Event::at(touch.touched.end, Event::LEAVE, t));
            if !touch.whole.is_empty() {
                self.events
                    .push(Event::at(touch.whole.start, Event::CUT, t));
                self.events.push(Event::at(touch.whole.end, Event::CUT, t));
            }
        }
        self.set.clear();
        // Few events: an unstable sort of plain integers.
        self.events.sort_unstable();
        let mut e = 0;
        while e < self.events.len() {
            let x = Event::x(self.events[e]);
            while let Some(&ev) = self.events.get(e).filter(|&&ev| Event::x(ev) == x) {
                let t = Event::touch(ev);
                match Event::kind(ev) {
                    // The set stays in stream order: touches were made in it.
                    Event::ENTER => {
                        let at = self.set.partition_point(|&u| u < t);
                        self.set.insert(at, t);
                    }
                    Event::LEAVE => {
                        if let Some(at) = self.set.iter().position(|&u| u == t) {
                            self.set.remove(at);
                        }
                    }
                    _ => {}
                }
                e += 1;
            }
            let Some(&next) = self.events.get(e) else {
                break;
            };
            if !self.set.is_empty() {
                self.segment(x..Event::x(next), fx0);
            }
        }
    }

    /// Classifies pixels `px` of the row, over which the polygons of `set` touch and the
    /// same ones cover wholly (a segment of [`Supersample::classify`]'s sweep), into
    /// pieces.
    fn segment(&mut self, px: std::ops::Range<u32>, fx0: u32) {
        if px.is_empty() {
            return;
        }
        let k = self.k;
        let touches = &self.touches;
        if let [t] = self.set[..] {
            let touch = &touches[t as usize];
            if touch.finite {
                let fill = if touch.covers(&px) {
                    Fill::Uniform(touch.i)
                } else {
                    self.mixed_fill()
                };
                return self.push_piece(px, fill);
            }
        } else if !self.set.iter().any(|&t| touches[t as usize].covers(&px)) {
            // None covers it: mixed throughout, whatever the depths.
            let fill = self.mixed_fill();
            return self.push_piece(px, fill);
        } else if self.set.iter().all(|&t| touches[t as usize].finite) {
            // The whole segment as one pixel: first with each touch's bounds over the row,
            // then with its bounds over the segment, those at its two ends.
            let mut class = Class::default();
            for &t in &self.set {
                let touch = &touches[t as usize];
                class.touch(touch.i, touch.lo, touch.hi, touch.covers(&px));
            }
            if let Verdict::Uniform(o) = class.verdict() {
                return self.push_piece(px, Fill::Uniform(o));
            }
            let mut class = Class::default();
            let last = px.end - 1;
            for &t in &self.set {
                let touch = &touches[t as usize];
                let ((lo0, hi0), (lo1, hi1)) =
                    (touch.depths(px.start, fx0, k), touch.depths(last, fx0, k));
                class.touch(touch.i, lo0.min(lo1), hi0.max(hi1), touch.covers(&px));
            }
            match class.verdict() {
                Verdict::Uniform(o) => return self.push_piece(px, Fill::Uniform(o)),
                _ if px.len() == 1 => {
                    let fill = self.mixed_fill();
                    return self.push_piece(px, fill);
                }
                _ => {}
            }
        }
        // Pixel by pixel.
        for c in px {
            let mut class = Class::default();
            for &t in &self.set {
                let touch = &self.touches[t as usize];
                let (lo, hi) = touch.depths(c, fx0, k);
                class.touch(touch.i, lo, hi, touch.whole.contains(&c));
            }
            let fill = match class.verdict() {
                Verdict::Uniform(o) => Fill::Uniform(o),
                _ => self.mixed_fill(),
            };
            self.push_piece(c..c + 1, fill);
        }
    }

    /// A mixed fill for the current segment: its set of touches, kept once a segment.
    fn mixed_fill(&mut self) -> Fill {
        let end = self.sets.len() as u32;
        // The segment's set is already the last one kept when a piece of this segment
        // was mixed before.
        if let Some(Piece {
            fill: Fill::Mixed(set),
            ..
        }) = self.pieces.last()
        {
            if set.end == end && self.sets[set.start as usize..] == self.set[..] {
                return Fill::Mixed(set.clone());
            }
        }
        self.sets.extend_from_slice(&self.set);
        Fill::Mixed(end..self.sets.len() as u32)
    }

    /// Adds a piece (not empty) at the row's right, joined to the last when they continue each other
    /// with the same fill.
    fn push_piece(&mut self, px: std::ops::Range<u32>, fill: Fill) {
        if px.is_empty() {
            return;
        }
        match self.pieces.last_mut() {
            Some(last) if last.px.end == px.start && last.fill == fill => last.px.end = px.end,
            _ => self.pieces.push(Piece { px, fill }),
        }
    }
}

/// A colour's three channels in one integer, 21 bits apart, so that the filter adds all
/// three at once: K² ≤ 256 samples of at most 255 sum to at most 65,280, within 21 bits.
#[derive(Clone, Copy, Debug)]
struct Packed(u64);

impl Packed {
    const SHIFT: u32 = 21;

    fn of(c: Colour) -> Packed {
        Packed(c[0] as u64 | (c[1] as u64) << Self::SHIFT | (c[2] as u64) << (2 * Self::SHIFT))
    }

    /// The channels of a sum of packed colours.
    fn channels(self) -> [u32; 3] {
        let mask = (1 << Self::SHIFT) - 1;
        [0, 1, 2].map(|i| ((self.0 >> (i * Self::SHIFT)) & mask) as u32)
    }
}

/// One event of [`Supersample::classify`]'s sweep, packed in a `u64` so that a sort
/// orders them by pixel: the pixel in the high 32 bits, then the kind, then the touch.
struct Event;

impl Event {
    const LEAVE: u64 = 0;
    const CUT: u64 = 1;
    const ENTER: u64 = 2;

    #[inline]
    fn at(x: u32, kind: u64, touch: u64) -> u64 {
        (x as u64) << 32 | kind << 30 | touch
    }
    #[inline]
    fn x(e: u64) -> u32 {
        (e >> 32) as u32
    }
    #[inline]
    fn kind(e: u64) -> u64 {
        (e >> 30) & 3
    }
    #[inline]
    fn touch(e: u64) -> u32 {
        (e & ((1 << 30) - 1)) as u32
    }
}

/// A run of pixels of the row that adaptive sampling draws alike.
#[derive(Clone, Debug, PartialEq)]
struct Piece {
    px: std::ops::Range<u32>,
    fill: Fill,
}

/// How a piece is drawn.
#[derive(Clone, Debug, PartialEq)]
enum Fill {
    /// This polygon wins every sample of every pixel.
    Uniform(u32),
    /// Sampled K×K, by the touches `sets[range]` (stream order).
    Mixed(std::ops::Range<u32>),
    /// Mixed, but counted, not sampled: the touches `sets[range]` are in depth order,
    /// front to back ([`in_depth_order`]).
    Counted(std::ops::Range<u32>),
    /// A cluster of touches in depth order, `sets[range]` front to back
    /// ([`Supersample::ordered`]): counted a touch at a time over its pixels.
    Ordered(std::ops::Range<u32>),
}

/// In a sum of packed colours that [`Supersample::count_ordered`] makes, bits above the
/// three channels' sums (each below 2¹⁶, 21 bits apart): one touch took all K² samples
/// of the pixel, and that touch, the nearest, covers it wholly: the pixel the sweep
/// finds uniform, not sampled (one touch may take all K² of a pixel it does not cover
/// wholly, by two spans of a fine row).
const ONE: u64 = 1 << 63;
const WON: u64 = 1 << 62;
/// And: a touch nearer than the one counted reached the pixel, samples or none (between
/// two spans of a concave polygon's row), so that no touch wins it whole, as none is
/// uniform in the sweep where another touches it in front.
const REACHED: u64 = 1 << 61;

/// One polygon's reach in one pixel row, adaptively: its spans, its least and greatest
/// `z_row` over the band's fine rows and its step, the pixels it touches and those it covers wholly
/// (relative to the row's first column).
#[derive(Clone, Debug)]
struct Touch {
    i: u32,
    /// Its spans in the row's `spans`.
    spans: std::ops::Range<u32>,
    zmin: crate::Depth,
    zmax: crate::Depth,
    dz: crate::Depth,
    touched: std::ops::Range<u32>,
    whole: std::ops::Range<u32>,
    /// Whether its depth bounds are finite at every pixel it touches, and if they are,
    /// the least and the greatest over those pixels.
    finite: bool,
    lo: crate::Depth,
    hi: crate::Depth,
}

impl Touch {
    /// Whether it covers every pixel of `px` wholly.
    #[inline]
    fn covers(&self, px: &std::ops::Range<u32>) -> bool {
        self.whole.start <= px.start && px.end <= self.whole.end
    }

    /// The least and greatest depth the fold can compute at pixel c's samples (`fx0`
    /// the row's first fine column, K samples a side): `z_row + x·dz`, rounded twice, is
    /// monotone in `z_row` and in `x`, so the bounds are the expression at the least and
    /// greatest `z_row` and at the pixel's first and last sample column, exact.
    #[inline]
    fn depths(&self, c: u32, fx0: u32, k: u32) -> (crate::Depth, crate::Depth) {
        let (x_first, x_last) = (fx0 + c * k, fx0 + c * k + k - 1);
        let (near, far) = if self.dz >= 0.0 {
            (x_first, x_last)
        } else {
            (x_last, x_first)
        };
        (
            crate::depth_at(self.zmin, self.dz, near),
            crate::depth_at(self.zmax, self.dz, far),
        )
    }
}

/// The frame's polygons walked down the fine screen, one [`BandWalk`] for each polygon
/// the current band reaches (its Edge Table built once, not once a band): the active
/// polygons' edges, never the screen.
#[derive(Debug, Default)]
struct Walks {
    outline: Outline,
    walks: Vec<BandWalk>,
    /// The walks not in use.
    free: Vec<u32>,
    /// Per polygon of the frame, its walk, or [`UNSTARTED`] or [`WALKED`].
    slot: Vec<u32>,
}

/// A polygon whose walk has not begun.
const UNSTARTED: u32 = u32::MAX;
/// A polygon walked to its last row.
const WALKED: u32 = u32::MAX - 1;

impl Walks {
    /// A frame of `n` polygons.
    fn start_frame(&mut self, n: usize) {
        self.slot.clear();
        self.slot.resize(n, UNSTARTED);
        self.free.clear();
        self.free.extend(0..self.walks.len() as u32);
    }

    /// Polygon `i`'s (`p`'s) spans on the `band` of a `width`×`height` screen, each
    /// handed to `emit`; bands top to bottom, as [`BandWalk::for_each_span_in`] takes
    /// them.
    fn spans(
        &mut self,
        i: u32,
        p: &Polygon,
        width: u32,
        height: u32,
        band: std::ops::Range<u32>,
        emit: impl FnMut(Span),
    ) {
        let at = match self.slot[i as usize] {
            WALKED => return,
            UNSTARTED => {
                let at = self.free.pop().unwrap_or_else(|| {
                    self.walks.push(BandWalk::new());
                    self.walks.len() as u32 - 1
                });
                if !self.walks[at as usize].start(&mut self.outline, p, band.start..height) {
                    self.free.push(at);
                    self.slot[i as usize] = WALKED;
                    return;
                }
                at
            }
            at => at,
        };
        let walk = &mut self.walks[at as usize];
        walk.for_each_span_in(width, band, emit);
        if walk.done() {
            self.free.push(at);
            self.slot[i as usize] = WALKED;
        } else {
            self.slot[i as usize] = at;
        }
    }
}

/// Decides the samples of span `s` of polygon `i` at fine columns `xs` (within the band's
/// `fx0..fx0 + n`) by the z-buffer's rule: the one fold of supersampling, whole or
/// adaptive.
#[allow(clippy::too_many_arguments)]
#[inline]
fn sample(
    s: &Span,
    i: u32,
    xs: std::ops::Range<u32>,
    fx0: u32,
    n: usize,
    band_start: u32,
    depth: &mut [crate::Depth],
    owner: &mut [u32],
    stats: &mut Stats,
) {
    let base = (s.y - band_start) as usize * n;
    stats.samples_tested += xs.len() as u64;
    let at = base + (xs.start - fx0) as usize..base + (xs.end - fx0) as usize;
    for ((x, d), o) in xs.zip(&mut depth[at.clone()]).zip(&mut owner[at]) {
        let z = s.depth(x);
        // Polygons come in stream order, so the holder is the earlier
        // one: the tie rule (the z-buffer's). Decided without a branch: where
        // edges and crossings are, which way it goes is anyone's guess.
        let take = (*o == NONE) & !z.is_nan() | crate::takes(z, *d);
        *d = if take { z } else { *d };
        *o = if take { i } else { *o };
        stats.samples_written += take as u64;
    }
}

/// The columns of the pixel whose first sample column is `c0` (K of them, `k`) that the
/// span `x0..x1` of one fine row holds, as bits 0..K: none where it misses the pixel (both
/// ends clamp to one side).
#[inline]
fn pixel_bits(x0: u32, x1: u32, c0: u32, k: u32) -> u64 {
    let (a, b) = (x0.clamp(c0, c0 + k) - c0, x1.clamp(c0, c0 + k) - c0);
    ((1u64 << b) - 1) ^ ((1u64 << a) - 1)
}

/// Whether the touches `set` (indices into `touches`) are in depth order, sorting them
/// front to back if they are: each at finite depths, and each one's greatest depth over
/// its pixels of the row below the tie bar of the next one's least. Then at every sample
/// the nearest touch that covers it takes it from whoever holds it and nothing takes it
/// from that touch, whatever the stream order (`bar(z) ≤ z`, and `bar` is monotone): the
/// fold ends at the nearest covering touch, which [`Supersample::coverage`] counts
/// without folding. A polygon alone at finite depths is in depth order. Otherwise `set`
/// keeps its stream order, which the fold needs.
fn in_depth_order(set: &mut [u32], touches: &[Touch]) -> bool {
    if set.iter().any(|&t| !touches[t as usize].finite) {
        return false;
    }
    if let [a, b] = *set {
        // Two, the most common: no sort.
        let (p, q) = (&touches[a as usize], &touches[b as usize]);
        return if p.hi < proto::depth::bar(q.lo) {
            true
        } else if q.hi < proto::depth::bar(p.lo) {
            set.swap(0, 1);
            true
        } else {
            false
        };
    }
    let mut sorted = set.to_vec();
    sorted.sort_by(|&a, &b| touches[a as usize].lo.total_cmp(&touches[b as usize].lo));
    let ordered = sorted.windows(2).all(|w| {
        let (p, q) = (&touches[w[0] as usize], &touches[w[1] as usize]);
        p.hi < proto::depth::bar(q.lo)
    });
    if ordered {
        set.copy_from_slice(&sorted);
    }
    ordered
}

/// A shaded polygon's colour over a pixel it wins wholly, adaptively: the mean of its
/// colours at the samples (i, j) of `block` × `block` of the pixel whose first sample is
/// fine pixel (fx, fy), rounded as the box filter rounds. Gouraud takes the central 2×2
/// samples: its colour is affine, so they average to what all K² do within a level
/// (docs/antialiasing.md, "Adaptive supersampling"); for K = 2 they are all the samples.
/// Phong takes all K²: its colour is not affine, and lighting them all gives ssK's bytes.
fn block_mean(shading: &Shading, fx: u32, fy: u32, block: std::ops::Range<u32>) -> Colour {
    let mut sum = [0u32; 3];
    for y in block.clone() {
        let row = shading.row(fy + y);
        for x in block.clone() {
            for (s, v) in sum.iter_mut().zip(row.at(fx + x)) {
                *s += v as u32;
            }
        }
    }
    let count = block.len() as u32 * block.len() as u32;
    sum.map(|s| ((s + count / 2) / count) as u8)
}

/// What adaptive sampling knows of one pixel of the row after [`Supersample::classify`].
#[derive(Clone, Copy, Debug)]
struct Class {
    /// The wholly covering polygon of least greatest depth, or [`NONE`].
    front: u32,
    front_lo: crate::Depth,
    front_hi: crate::Depth,
    /// The least depth of every other polygon that touches the pixel.
    other_lo: crate::Depth,
    /// Whether any other polygon touches it.
    others: bool,
}

impl Default for Class {
    fn default() -> Self {
        Class {
            front: NONE,
            front_lo: f64::INFINITY,
            front_hi: f64::INFINITY,
            other_lo: f64::INFINITY,
            others: false,
        }
    }
}

/// How a pixel is drawn adaptively.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Verdict {
    /// No polygon reaches it: not sent.
    Empty,
    /// This polygon wins every sample.
    Uniform(u32),
    /// Sampled K×K.
    Mixed,
}

impl Class {
    /// Polygon `i` touches the pixel, its depths at the samples within `lo..=hi`,
    /// covering it wholly or not.
    fn touch(&mut self, i: u32, lo: crate::Depth, hi: crate::Depth, whole: bool) {
        if lo.is_nan() || hi.is_nan() {
            // No order is known: the pixel is sampled.
            self.others = true;
            self.other_lo = f64::NEG_INFINITY;
        } else if whole && hi < self.front_hi {
            if self.front != NONE {
                self.others = true;
                self.other_lo = self.other_lo.min(self.front_lo);
            }
            (self.front, self.front_lo, self.front_hi) = (i, lo, hi);
        } else {
            self.others = true;
            self.other_lo = self.other_lo.min(lo);
        }
    }

    fn verdict(&self) -> Verdict {
        if self.front == NONE {
            if self.others {
                Verdict::Mixed
            } else {
                Verdict::Empty
            }
        } else if !self.others || self.front_hi < proto::depth::bar(self.other_lo) {
            Verdict::Uniform(self.front)
        } else {
            Verdict::Mixed
        }
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
        self.colours.clear();
        self.colours.extend(self.fine.iter().map(|p| p.colour));
        self.packed.clear();
        self.packed
            .extend(self.colours.iter().map(|&c| Packed::of(c)));
        self.packed.push(Packed::of(self.background));
        self.fine_h = height * k;
        self.walks.start_frame(self.fine.len());
        self.shading.clear();
        let lighting = self.lighting.as_ref();
        self.shading
            .extend(self.fine.iter().map(|p| Shading::of(p, lighting)));
        self.shaded = self.shading.iter().any(Option::is_some);
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
        let adaptive = if self.adaptive {
            format!(", {} sampled (adaptive)", s.sampled)
        } else {
            String::new()
        };
        format!(
            "{0}x{0} samples, {1} samples tested, {2} written, {3} pixels out, {4} of them \
             mixed{adaptive}",
            self.k, s.samples_tested, s.samples_written, s.pixels, s.mixed
        )
    }

    fn counters(&self) -> Vec<(&'static str, String)> {
        let s = self.stats;
        let mut c = vec![
            ("samples", self.k.to_string()),
            ("samples_tested", s.samples_tested.to_string()),
            ("samples_written", s.samples_written.to_string()),
            ("pixels_out", s.pixels.to_string()),
            ("mixed", s.mixed.to_string()),
        ];
        if self.adaptive {
            c.push(("sampled", s.sampled.to_string()));
        }
        c
    }
}

#[cfg(test)]
mod tests;
