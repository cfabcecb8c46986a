//! Error measures of a frame against a reference (docs/DESIGN.md, "Measures"), for
//! `zspec compare --metrics` and for the chart, which links this crate:
//!
//! * the differing fraction: the pixels whose RGB differ at all, over all pixels
//!   (against `zspec`'s point sampling this is the chart's `error_fraction`);
//! * the RMSE in 0–255 units over the three channels: √(Σ (a − b)² / 3N), the sum over
//!   the N pixels and their three channels;
//! * the largest absolute error of any channel of any pixel;
//! * the edge RMSE: the same RMSE over the edge pixels only, those whose 16×16 samples are
//!   not all one colour (against `zspec --samples 16`, with its `--edge-mask`, this is the
//!   chart's `edge_rmse`).
//!
//! Sums are kept exact (integers), so that frames add up into an overall figure that is
//! the figure of all their pixels taken together.

use crate::error::{bail, Result};
use crate::supersample::mask_colour;
use crate::Image;
use std::fmt::Write as _;

/// The squared error over the edge pixels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EdgeError {
    /// How many edge pixels there are.
    pub pixels: u64,
    /// Σ (a − b)² over the edge pixels and their three channels.
    pub sum_squared: u64,
}

/// How far one frame (or several, see [`Metrics::add`]) is from another.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Metrics {
    pub pixels: u64,
    /// Pixels whose RGB differ in any channel.
    pub differing: u64,
    /// Σ (a − b)² over all pixels and their three channels.
    pub sum_squared: u64,
    /// The largest |a − b| of any channel of any pixel.
    pub max_error: u8,
    /// Over the edge pixels; `None` when no edge pixels were given.
    pub edges: Option<EdgeError>,
}

/// √(sum / 3n): the RMS of n pixels' three channels.
fn rms(sum_squared: u64, pixels: u64) -> f64 {
    (sum_squared as f64 / (3 * pixels) as f64).sqrt()
}

impl Metrics {
    /// The fraction of pixels that differ (0 for a frame of no pixels).
    pub fn differing_fraction(&self) -> f64 {
        if self.pixels == 0 {
            0.0
        } else {
            self.differing as f64 / self.pixels as f64
        }
    }

    /// The RMS error in 0–255 units over the three channels (0 for no pixels).
    pub fn rmse(&self) -> f64 {
        if self.pixels == 0 {
            0.0
        } else {
            rms(self.sum_squared, self.pixels)
        }
    }

    /// The RMS error over the edge pixels; `None` without edge pixels (none given, or a
    /// frame with none: there is no edge to measure).
    pub fn edge_rmse(&self) -> Option<f64> {
        self.edges
            .filter(|e| e.pixels > 0)
            .map(|e| rms(e.sum_squared, e.pixels))
    }

    /// Adds another frame's measures: the result measures both frames' pixels together.
    pub fn add(&mut self, other: &Metrics) {
        self.pixels += other.pixels;
        self.differing += other.differing;
        self.sum_squared += other.sum_squared;
        self.max_error = self.max_error.max(other.max_error);
        self.edges = match (self.edges, other.edges) {
            (Some(a), Some(b)) => Some(EdgeError {
                pixels: a.pixels + b.pixels,
                sum_squared: a.sum_squared + b.sum_squared,
            }),
            (a, b) => a.or(b),
        };
    }

    /// The measures of every frame taken together.
    pub fn overall(frames: &[Metrics]) -> Metrics {
        let mut all = Metrics::default();
        for m in frames {
            all.add(m);
        }
        all
    }

    /// The measures as `key value` pairs on one line, e.g.
    /// `pixels 400 differing 12 differing_fraction 0.030000 rmse 4.560000 max 255 edge_pixels 34 edge_rmse 12.300000`;
    /// the edge pair is left out when no edge pixels were given, and `edge_rmse` is `-`
    /// for a frame without any.
    pub fn pairs(&self) -> String {
        let mut s = format!(
            "pixels {} differing {} differing_fraction {:.6} rmse {:.6} max {}",
            self.pixels,
            self.differing,
            self.differing_fraction(),
            self.rmse(),
            self.max_error
        );
        if let Some(e) = self.edges {
            let _ = write!(s, " edge_pixels {} edge_rmse ", e.pixels);
            match self.edge_rmse() {
                Some(v) => {
                    let _ = write!(s, "{v:.6}");
                }
                None => s.push('-'),
            }
        }
        s
    }

    /// The header of [`Metrics::csv_row`].
    pub const CSV_HEADER: &'static str =
        "frame,pixels,differing,differing_fraction,rmse,max,edge_pixels,edge_rmse";

    /// One CSV row, `frame` first (a number or `overall`); the edge fields are empty when
    /// no edge pixels were given, `edge_rmse` also for a frame without any.
    pub fn csv_row(&self, frame: &str) -> String {
        let (edge_pixels, edge_rmse) = match self.edges {
            Some(e) => (
                e.pixels.to_string(),
                self.edge_rmse()
                    .map(|v| format!("{v:.6}"))
                    .unwrap_or_default(),
            ),
            None => (String::new(), String::new()),
        };
        format!(
            "{frame},{},{},{:.6},{:.6},{},{edge_pixels},{edge_rmse}",
            self.pixels,
            self.differing,
            self.differing_fraction(),
            self.rmse(),
            self.max_error
        )
    }
}

/// Measures frame `b` against frame `a` (the measures are symmetric), over the pixels
/// flagged in `edges` (row-major, one flag a pixel) for the edge RMSE. Frames of
/// different sizes, or a flag list of another length, are an error.
pub fn metrics(a: &Image, b: &Image, edges: Option<&[bool]>) -> Result<Metrics> {
    if (a.width, a.height) != (b.width, b.height) || a.pixels.len() != b.pixels.len() {
        bail!(
            "the frames are {}x{} and {}x{}",
            a.width,
            a.height,
            b.width,
            b.height
        );
    }
    if let Some(e) = edges {
        if e.len() != a.pixels.len() {
            bail!(
                "{} edge flags for a {}x{} frame of {} pixels",
                e.len(),
                a.width,
                a.height,
                a.pixels.len()
            );
        }
    }
    let mut m = Metrics {
        pixels: a.pixels.len() as u64,
        edges: edges.map(|_| EdgeError::default()),
        ..Metrics::default()
    };
    for (i, (p, q)) in a.pixels.iter().zip(&b.pixels).enumerate() {
        if p == q {
            continue;
        }
        m.differing += 1;
        let mut sq = 0u64;
        for ch in 0..3 {
            let d = p[ch].abs_diff(q[ch]);
            m.max_error = m.max_error.max(d);
            sq += d as u64 * d as u64;
        }
        m.sum_squared += sq;
        if let (Some(flags), Some(e)) = (edges, m.edges.as_mut()) {
            if flags[i] {
                e.sum_squared += sq;
            }
        }
    }
    if let (Some(flags), Some(e)) = (edges, m.edges.as_mut()) {
        e.pixels = flags.iter().filter(|&&f| f).count() as u64;
    }
    Ok(m)
}

/// Measures two PPM streams frame by frame, with an edge mask stream (as
/// [`edges_from_mask`] reads them) when given. Streams of different lengths are an error.
pub fn metrics_streams(
    a: &[Image],
    b: &[Image],
    edge_masks: Option<&[Image]>,
) -> Result<Vec<Metrics>> {
    if a.len() != b.len() {
        bail!("the streams have {} and {} frames", a.len(), b.len());
    }
    if let Some(masks) = edge_masks {
        if masks.len() != a.len() {
            bail!(
                "the edge mask has {} frames and the streams {}",
                masks.len(),
                a.len()
            );
        }
    }
    a.iter()
        .zip(b)
        .enumerate()
        .map(|(k, (fa, fb))| {
            let flags = edge_masks
                .map(|masks| {
                    let m = &masks[k];
                    if (m.width, m.height) != (fa.width, fa.height) {
                        bail!(
                            "is {}x{}, the frame {}x{}",
                            m.width,
                            m.height,
                            fa.width,
                            fa.height
                        );
                    }
                    edges_from_mask(m)
                })
                .transpose()
                .map_err(|e| e.context(format!("edge mask frame {k}")))?;
            metrics(fa, fb, flags.as_deref()).map_err(|e| e.context(format!("frame {k}")))
        })
        .collect()
}

/// Reads an edge mask (`zspec --samples K --edge-mask`): white pixels are edge pixels,
/// black are not; any other colour means the image is not a mask.
pub fn edges_from_mask(mask: &Image) -> Result<Vec<bool>> {
    mask.pixels
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            if p == mask_colour(true) {
                Ok(true)
            } else if p == mask_colour(false) {
                Ok(false)
            } else {
                let w = mask.width as usize;
                bail!(
                    "pixel ({}, {}) is {p:?}: an edge mask is black and white only",
                    i % w,
                    i / w
                )
            }
        })
        .collect()
}
