//! The anti-aliasing reference (docs/DESIGN.md, "Anti-aliasing"): K×K samples per pixel on a
//! regular grid, box-filtered.
//!
//! Pixel (c, r) takes its samples at the sub-pixel centres (c + (i+½)/K, r + (j+½)/K),
//! i, j = 0..K−1, and each sample is decided by exactly the rules of a pixel centre
//! (coverage by the even-odd rule with left and top edges holding the samples on them,
//! on the vertices snapped to 1/256 pixel, the depth of the ray through the sample,
//! K1 ≤ z_e ≤ K2, nearest wins, earlier wins a tie, background elsewhere). Those points
//! are the pixel centres (C + ½, R + ½) of the same view on a screen K times finer,
//! C = K·c + i, R = K·r + j, so the samples are *computed* as that finer screen's pixels:
//! the polygons are projected onto a (K·W)×(K·H) device and every sample is the point
//! rule there, what the pipeline's ssK, which renders at K·W × K·H and box-filters, must
//! reproduce. The vertices are snapped on the pixel screen's 1/256 grid, as ssK's are
//! (`scan::fine::scaled`), not on the finer screen's: so it is `zspec --size KWxKH` but
//! for samples within 1/256 pixel of an edge.
//!
//! The filter: each channel of a pixel is the average of its K² samples rounded to
//! nearest, halves up, in integers: `(sum + K²/2) / K²` (K²/2 rounded down; for odd K no
//! average lies exactly on a half).
//!
//! Memory stays bounded whatever K and the size: the frame's polygons are kept (prepared
//! for the fine screen), and the fine screen is drawn a band of sample rows at a time,
//! at most [`BAND_SAMPLES`] samples (or one sample row, if longer), each band's samples
//! summed into per-pixel accumulators before the next band is drawn. Memory is the
//! polygons, one band, and about 16 bytes a pixel; never the K·W × K·H screen.

use crate::error::{bail, Error, Result};
use crate::{Prepared, Setup};
use proto::{Colour, Polygon};

/// The most samples (depth and colour, 11 bytes each) one band holds: about 11 MiB.
pub const BAND_SAMPLES: usize = 1 << 20;

/// The largest K accepted: K² samples of 255 still sum within a u32.
pub const MAX_SAMPLES: u32 = 256;

/// A supersampled frame: the box-filtered pixels, and which pixels are edge pixels
/// (docs/DESIGN.md, "Measures": those whose K×K samples are not all one colour).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Supersampled {
    pub width: u32,
    pub height: u32,
    /// Row-major from the top-left.
    pub pixels: Vec<Colour>,
    /// Row-major: whether the pixel's samples are not all one colour.
    pub edges: Vec<bool>,
}

impl Supersampled {
    /// The edge pixels as an image: white where the samples differ, black elsewhere
    /// (what `zspec --edge-mask` writes and `zspec compare --edges` reads back).
    pub fn edge_mask(&self) -> Vec<Colour> {
        self.edges.iter().map(|&e| mask_colour(e)).collect()
    }
}

/// The colour of a mask pixel: white for an edge pixel, black otherwise.
pub fn mask_colour(edge: bool) -> Colour {
    if edge {
        [255; 3]
    } else {
        [0; 3]
    }
}

/// One frame of the supersampled reference being gathered: polygons are prepared as they
/// arrive (in stream order, which decides ties) and drawn by [`SupersampledFrame::finish`].
pub struct SupersampledFrame {
    /// The screen of pixels.
    setup: Setup,
    /// The same view on the K times finer screen of samples.
    fine: Setup,
    k: u32,
    background: Colour,
    polygons: Vec<Prepared>,
}

impl SupersampledFrame {
    /// A frame of K×K samples per pixel; K from 1 to [`MAX_SAMPLES`], and K·W, K·H must
    /// fit in a u32.
    pub fn new(setup: &Setup, k: u32, background: Colour) -> Result<Self> {
        if !(1..=MAX_SAMPLES).contains(&k) {
            bail!("{k} samples a side: K must be from 1 to {MAX_SAMPLES}");
        }
        let (Some(width), Some(height)) = (setup.width.checked_mul(k), setup.height.checked_mul(k))
        else {
            bail!(
                "{k}x{k} samples on a {}x{} screen is too many samples a row",
                setup.width,
                setup.height
            );
        };
        Ok(SupersampledFrame {
            setup: setup.clone(),
            fine: Setup {
                width,
                height,
                samples: k * setup.samples,
                ..setup.clone()
            },
            k,
            background,
            polygons: Vec::new(),
        })
    }

    /// Takes the next polygon of the frame; refuses one the reference cannot draw
    /// exactly (its projection overflows), as [`crate::ReferenceFrame::draw`] does.
    pub fn draw(&mut self, poly: &Polygon) -> std::result::Result<(), String> {
        if let Some(p) = self.fine.prepare(poly)? {
            self.polygons.push(p);
        }
        Ok(())
    }

    /// Draws the frame's polygons at every sample, box-filters them, and empties the
    /// frame for the next one.
    pub fn finish(&mut self) -> Supersampled {
        self.finish_in_bands(BAND_SAMPLES)
    }

    /// [`SupersampledFrame::finish`] with bands of at most `band_samples` samples (at
    /// least one sample row): the bands change the memory, never the picture.
    pub(crate) fn finish_in_bands(&mut self, band_samples: usize) -> Supersampled {
        let (w, h) = (self.setup.width as usize, self.setup.height as usize);
        let k = self.k as usize;
        let fine_w = self.fine.width as usize;
        let band_rows =
            (band_samples / fine_w.max(1)).clamp(1, self.fine.height.max(1) as usize) as u32;
        let band_len = band_rows as usize * fine_w;
        let mut depth = vec![f64::INFINITY; band_len];
        let mut colour = vec![self.background; band_len];
        let mut sums = vec![[0u32; 3]; w * h];
        let mut first = vec![self.background; w * h];
        let mut edges = vec![false; w * h];
        let mut r0 = 0u32;
        while r0 < self.fine.height {
            let band = r0..r0.saturating_add(band_rows).min(self.fine.height);
            let n = band.len() * fine_w;
            depth[..n].fill(f64::INFINITY);
            colour[..n].fill(self.background);
            // The point rule at every sample of the band: polygons in stream order, a
            // later one takes a sample only by the tie rule (nearer by more than 2⁻³⁰ of
            // the holder's depth, [`proto::depth::takes`]), as at a pixel centre: the
            // earlier polygon keeps a tie.
            for p in &self.polygons {
                self.fine.for_each_covered_in(p, band.clone(), |c, r, z| {
                    let i = (r - r0) as usize * fine_w + c as usize;
                    if proto::depth::takes(z, depth[i]) {
                        depth[i] = z;
                        colour[i] = p.colour_at(c, r);
                    }
                });
            }
            // Into the pixels' sums. Sample rows come in order and each row left to
            // right, so a pixel's first sample is its top-left one, (i, j) = (0, 0).
            for (dr, row) in colour[..n].chunks_exact(fine_w).enumerate() {
                let r = r0 as usize + dr;
                // Sample row j of pixel row r / K; the row holds W blocks of K samples.
                let (base, j) = ((r / k) * w, r % k);
                for (c, block) in row.chunks_exact(k).enumerate() {
                    let px = base + c;
                    for (i, sample) in block.iter().enumerate() {
                        let s = &mut sums[px];
                        s[0] += sample[0] as u32;
                        s[1] += sample[1] as u32;
                        s[2] += sample[2] as u32;
                        if (i, j) == (0, 0) {
                            first[px] = *sample;
                        } else if *sample != first[px] {
                            edges[px] = true;
                        }
                    }
                }
            }
            r0 = band.end;
        }
        self.polygons.clear();
        let count = (k * k) as u32;
        let pixels = sums
            .iter()
            .map(|s| s.map(|sum| ((sum + count / 2) / count) as u8))
            .collect();
        Supersampled {
            width: self.setup.width,
            height: self.setup.height,
            pixels,
            edges,
        }
    }
}

/// Renders one frame with K×K samples per pixel, box-filtered (see the module's notes).
/// K = 1 gives [`crate::render_frame`]'s pixels.
pub fn render_supersampled(
    polys: &[Polygon],
    setup: &Setup,
    k: u32,
    background: Colour,
) -> Result<Supersampled> {
    let mut frame = SupersampledFrame::new(setup, k, background)?;
    for (i, poly) in polys.iter().enumerate() {
        frame
            .draw(poly)
            .map_err(|m| Error::Data(format!("polygon {i}: {m}")))?;
    }
    Ok(frame.finish())
}
