//! The model of accuracy: for each sampling mode of the z-buffer (`render --aa`), its RMS
//! error against the 16×16 reference (`zspec --samples 16`, 0–255 levels) and its share
//! of pixels wrong, predicted from the look ([`crate::look`]) and a cheap scan of the
//! scene's colours ([`Colours`]); and `render --max-error E`'s choice, the configuration
//! (sampling mode and depth) predicted cheapest among those predicted to meet E.
//!
//! The model is small on purpose. A point-sampled or supersampled frame differs from
//! the 16×16 reference only in pixels that an edge crosses (inside a flat polygon every
//! sample has the polygon's colour), and there by about the contrast across the edge
//! times the coverage the samples misjudge. So, for a mode m:
//!
//! - RMS_m = a_m · √(edge · contrast²), where `edge` is the edge pixels a screen pixel,
//!   by thesis 5.2's closed form (each of the P_r polygons in view a square of side
//!   H = √(X·Y·Dc/P_r), so 4·P_r·H = 4·√(P_r·X·Y·Dc) pixels of edge a frame, at most one a
//!   pixel), and `contrast²` the mean square colour difference, 0–1 a channel, between
//!   polygons that follow one another in the stream (neighbours in a mesh, strangers in
//!   a random environment) or a polygon and the black background, whichever is larger;
//! - wrong_m = b_m · edge: the share of pixels whose bytes differ from the reference.
//!
//! a_m and b_m are fitted to the chart's rows ([`fit`]) as the largest ratio of measured
//! to feature over the scenes fitted, so that the prediction is an upper bound on every
//! scene it was fitted on. `ss16` is the reference's own sampling (a 16×16 grid, a box
//! filter: `zspec --samples 16`'s bytes), so its a and b are 0, and so are `adaptive16`'s
//! on flat, opaque scenes, where `adaptiveK` gives `ssK`'s bytes. Under Gouraud or Phong
//! shading, or transparency, `adaptiveK` is left out (its difference from `ssK` there is
//! bounded but not modelled). The exact hidden-surface methods (scanline, warnock) give
//! the z-buffer's bytes, and the painter those or worse (cycles), so the modes here are
//! the z-buffer's, whose leaf the time model knows.

use crate::error::{Context, Result};
use crate::look::Environment;
use crate::model::{self, Constants, Target};
use proto::{Reader, Token};
use serde::{Deserialize, Serialize};
use std::io::Read;
use std::path::Path;

/// The sampling modes `--max-error` chooses among, cheapest first by samples a pixel.
pub const MODES: [&str; 10] = [
    "none",
    "adaptive2",
    "ss2",
    "adaptive4",
    "ss4",
    "abuf",
    "adaptive8",
    "ss8",
    "adaptive16",
    "ss16",
];

/// The safe choice: the reference's own sampling, 0 error on any scene.
pub const SAFE: &str = "ss16";

/// The budgets `plan accuracy` reports, `plan max-error-check` tries and the chart marks
/// on its speed-accuracy panels (RMS, 0–255 levels).
pub const BUDGETS: [f64; 4] = [0.0, 1.0, 4.0, 16.0];

/// The deepest tree `--max-error` considers.
pub const MAX_DEPTH: u8 = 6;

/// K of `ssK` or `adaptiveK` (1 for none; abuf's 8×8 mask counts as 8).
pub fn samples(mode: &str) -> u32 {
    let k = mode
        .strip_prefix("ss")
        .or_else(|| mode.strip_prefix("adaptive"))
        .and_then(|k| k.parse().ok());
    match (mode, k) {
        (_, Some(k)) => k,
        ("abuf", _) => 8,
        _ => 1,
    }
}

/// What the colour scan of a scene says ([`Colours::scan`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Colours {
    /// Polygons scanned.
    pub polygons: u64,
    /// The mean square colour difference, 0–1 a channel, between successive polygons,
    /// or between a polygon and the black background, whichever is larger.
    pub contrast2: f64,
    /// Whether every polygon scanned is one flat opaque colour.
    pub flat: bool,
}

impl Colours {
    /// Scans the polygons of a world-space stream (at most `limit` bytes of it; a
    /// record cut there ends the scan).
    pub fn scan<R: Read>(input: R, limit: u64) -> Result<Colours> {
        let mut reader = Reader::<Token, _>::new(std::io::BufReader::new(input.take(limit)))
            .context("reading the scene's colours")?;
        let mut record = Token::default();
        let (mut n, mut successive, mut background) = (0u64, 0.0, 0.0);
        let mut flat = true;
        let mut last: Option<[u8; 3]> = None;
        loop {
            match reader.next_into(&mut record) {
                Ok(true) => {}
                Ok(false) => break,
                Err(_) if n > 0 => break,
                Err(e) => return Err(e).context("reading the scene's colours"),
            }
            let Token::Polygon(p) = &record else { continue };
            flat &= p.vertex_attrs.is_empty() && p.opacity == 255;
            let c = p.colour;
            let sq = |a: [u8; 3], b: [u8; 3]| {
                (0..3)
                    .map(|i| ((f64::from(a[i]) - f64::from(b[i])) / 255.0).powi(2))
                    .sum::<f64>()
                    / 3.0
            };
            if let Some(l) = last {
                successive += sq(c, l);
            }
            background += sq(c, [0, 0, 0]);
            last = Some(c);
            n += 1;
        }
        let mean = |s: f64, k: u64| if k == 0 { 0.0 } else { s / k as f64 };
        Ok(Colours {
            polygons: n,
            contrast2: mean(successive, n.saturating_sub(1)).max(mean(background, n) / 4.0),
            flat,
        })
    }
}

/// A scene file as `--max-error` sees it: the look at it on its screen and the scan of
/// its colours, each over its first [`crate::look::LOOK_BYTES`].
#[derive(Clone, Debug, PartialEq)]
pub struct Seen {
    pub env: Environment,
    pub colours: Colours,
}

impl Seen {
    /// The scene file `path` on a `width`×`height` screen through `camera` (viewxf's
    /// options, as [`crate::look::look`] takes them); `None` where the look or the colour
    /// scan cannot read it.
    pub fn of(path: &Path, width: u32, height: u32, camera: &[String]) -> Option<Seen> {
        let limit = crate::look::LOOK_BYTES;
        let env = crate::look::look(path, width, height, camera, Some(limit)).ok()?;
        let colours = Colours::scan(crate::look::open(path).ok()?, limit).ok()?;
        Some(Seen { env, colours })
    }
}

/// `render --max-error E`'s choice on a seen scene: every allowed configuration
/// predicted ([`Accuracy::predict_all`], trees to [`MAX_DEPTH`]) and the cheapest of those
/// predicted to meet `max_error` ([`cheapest`]); `None` where none is. The chart marks the
/// same choice on its panels.
pub fn choose(
    model: &Accuracy,
    k: &Constants,
    seen: &Seen,
    target: &Target,
    max_error: f64,
) -> Option<Predicted> {
    let all = model.predict_all(k, &seen.env, &seen.colours, target, MAX_DEPTH);
    cheapest(&all, max_error).cloned()
}

/// The visible edge pixels a screen pixel (0–1), by thesis 5.2's closed form: each of
/// the P_r polygons in view a square of side H = √(X·Y·Dc/P_r), 4·P_r·H = 4·√(P_r·X·Y·Dc)
/// pixels of edge a frame, of which a pixel covered Dc times shows one polygon's: over
/// the screen, 4/H where Dc ≥ 1.
pub fn edge_fraction(env: &Environment) -> f64 {
    if env.frames == 0 || env.screen() == 0.0 {
        return 0.0;
    }
    let all = 4.0 * env.spans() / (env.frames as f64 * env.screen());
    (all / env.depth_complexity().max(1.0)).min(1.0)
}

/// The fitted coefficients, a mode each: RMS_m = a·√(edge·contrast²), wrong_m = b·edge.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Accuracy {
    /// Where they were fitted (the command, the scenes).
    pub fitted_on: String,
    pub modes: Vec<ModeFit>,
}

/// One mode's coefficients.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModeFit {
    pub aa: String,
    /// RMS (0–255) per unit of √(edge·contrast²).
    pub rms: f64,
    /// Pixels wrong per edge pixel.
    pub wrong: f64,
    /// The leaf's work a covered pixel, in point samples' (1 for none, K² for ssK).
    pub samples: f64,
}

/// What the model predicts of one configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct Predicted {
    pub aa: String,
    pub depth: u8,
    pub seconds: f64,
    /// RMS error against the 16×16 reference, 0–255.
    pub rms: f64,
    /// Share of pixels wrong, 0–1.
    pub wrong: f64,
}

/// One measured row the fit reads: the scene's features and a mode's measured error.
#[derive(Clone, Debug, PartialEq)]
pub struct Measured {
    pub aa: String,
    pub edge: f64,
    pub contrast2: f64,
    pub rms: f64,
    pub wrong: f64,
}

impl Accuracy {
    /// The repository's coefficients (bench/accuracy.toml), fitted by `plan accuracy
    /// --fit` on generated scenes none of which the check uses.
    pub fn committed() -> Accuracy {
        toml::from_str(include_str!("../../bench/accuracy.toml"))
            .expect("bench/accuracy.toml is the model's own")
    }

    pub fn to_toml(&self) -> Result<String> {
        Ok(toml::to_string(self)?)
    }

    pub fn parse(text: &str) -> Result<Accuracy> {
        Ok(toml::from_str(text)?)
    }

    /// The fit this machine's cache holds (`accuracy.toml` beside model.toml), else the
    /// repository's.
    pub fn load() -> Accuracy {
        crate::cache::dir()
            .and_then(|d| std::fs::read_to_string(d.join("accuracy.toml")).ok())
            .and_then(|t| Accuracy::parse(&t).ok())
            .unwrap_or_else(Accuracy::committed)
    }

    fn mode(&self, aa: &str) -> Option<&ModeFit> {
        self.modes.iter().find(|m| m.aa == aa)
    }

    /// The predicted RMS and share of pixels wrong of `aa` on a scene; `None` for a mode
    /// the fit has no row for.
    pub fn error(&self, aa: &str, edge: f64, colours: &Colours) -> Option<(f64, f64)> {
        let m = self.mode(aa)?;
        Some((m.rms * (edge * colours.contrast2).sqrt(), m.wrong * edge))
    }

    /// The modes that may run on a scene: adaptiveK only on flat opaque ones.
    pub fn allowed<'a>(&'a self, colours: &'a Colours) -> impl Iterator<Item = &'a ModeFit> {
        self.modes
            .iter()
            .filter(move |m| colours.flat || !m.aa.starts_with("adaptive"))
    }

    /// Every allowed configuration's prediction: each mode at the depth the time model
    /// chooses for it ([`model::choose_depth_on`] on the scene with its covered pixels
    /// times the mode's samples, the leaf's work that sampling multiplies).
    pub fn predict_all(
        &self,
        k: &Constants,
        env: &Environment,
        colours: &Colours,
        target: &Target,
        max_depth: u8,
    ) -> Vec<Predicted> {
        let edge = edge_fraction(env);
        self.allowed(colours)
            .map(|m| {
                let scaled = Environment {
                    area: env.area * effective_samples(m, edge),
                    ..*env
                };
                let (depth, _, _) = model::choose_depth_on(k, &scaled, target, max_depth);
                let seconds = model::predict_on(k, &scaled, depth, target).total_s;
                let (rms, wrong) = self.error(&m.aa, edge, colours).unwrap_or((0.0, 0.0));
                Predicted {
                    aa: m.aa.clone(),
                    depth,
                    seconds,
                    rms,
                    wrong,
                }
            })
            .collect()
    }
}

/// A mode's leaf work a covered pixel, in point samples: its fitted samples, and for
/// `adaptiveK` one sample in the interior and K² in the edge pixels.
fn effective_samples(m: &ModeFit, edge: f64) -> f64 {
    if m.aa.starts_with("adaptive") {
        1.0 + (m.samples - 1.0) * edge
    } else {
        m.samples
    }
}

/// The factor on a scene's covered pixels that makes the model's depth-0 time `ratio`
/// times its point-sampled time: a mode's `samples`, from a measured ratio of its time
/// to `none`'s on the scene (bisection; 1 when the ratio is 1 or less).
pub fn samples_for_ratio(k: &Constants, env: &Environment, target: &Target, ratio: f64) -> f64 {
    let time = |s: f64| {
        let scaled = Environment {
            area: env.area * s,
            ..*env
        };
        model::predict_on(k, &scaled, 0, target).total_s
    };
    let want = time(1.0) * ratio;
    let (mut lo, mut hi) = (1.0f64, 1.0e5f64);
    if ratio <= 1.0 || env.area <= 0.0 {
        return 1.0;
    }
    for _ in 0..60 {
        let mid = (lo * hi).sqrt();
        if time(mid) < want {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// The configuration predicted cheapest among those predicted to meet `max_error`
/// (`predicted`: [`Accuracy::predict_all`]); with `max_error` 0 only a mode of the
/// reference's own bytes (rms 0) qualifies. `None` when none is predicted to meet it.
pub fn cheapest(predicted: &[Predicted], max_error: f64) -> Option<&Predicted> {
    predicted
        .iter()
        .filter(|p| p.rms <= max_error)
        .min_by(|a, b| a.seconds.total_cmp(&b.seconds))
}

/// Fits each mode's coefficients to measured rows: the largest ratio of measured to
/// feature over the rows (an upper envelope, so that every fitted scene is predicted at
/// or above its measured error); a mode of 0 error everywhere (ss16) gets 0. `samples_of`
/// gives each mode's factor on the covered pixels ([`samples_for_ratio`]).
pub fn fit(rows: &[Measured], fitted_on: &str, samples_of: impl Fn(&str) -> f64) -> Accuracy {
    let modes = MODES
        .iter()
        .filter_map(|aa| {
            let mine: Vec<&Measured> = rows.iter().filter(|r| r.aa == *aa).collect();
            if mine.is_empty() {
                return None;
            }
            let ratio = |num: fn(&Measured) -> f64, den: fn(&Measured) -> f64| {
                mine.iter()
                    .filter(|r| den(r) > 0.0)
                    .map(|r| num(r) / den(r))
                    .fold(0.0, f64::max)
            };
            Some(ModeFit {
                aa: aa.to_string(),
                rms: ratio(|r| r.rms, |r| (r.edge * r.contrast2).sqrt()),
                wrong: ratio(|r| r.wrong, |r| r.edge),
                samples: samples_of(aa),
            })
        })
        .collect();
    Accuracy {
        fitted_on: fitted_on.to_string(),
        modes,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn colours(contrast2: f64, flat: bool) -> Colours {
        Colours {
            polygons: 10,
            contrast2,
            flat,
        }
    }

    #[test]
    fn samples_of_each_mode() {
        let k: Vec<u32> = MODES.iter().map(|m| samples(m)).collect();
        assert_eq!(k, [1, 2, 2, 4, 4, 8, 8, 8, 16, 16]);
    }

    #[test]
    fn the_fit_is_the_upper_envelope_and_ss16_is_exact() {
        let row = |aa: &str, edge: f64, rms: f64, wrong: f64| Measured {
            aa: aa.into(),
            edge,
            contrast2: 0.25,
            rms,
            wrong,
        };
        let rows = [
            row("none", 0.16, 4.0, 0.08), // √(0.04) = 0.2: 20 a unit, 0.5 an edge pixel
            row("none", 0.04, 3.0, 0.028), // √(0.01) = 0.1: 30 a unit, 0.7
            row("ss16", 0.16, 0.0, 0.0),
        ];
        let a = fit(&rows, "test", |aa| f64::from(samples(aa)).powi(2));
        assert_eq!(a.modes.len(), 2);
        let none = &a.modes[0];
        assert_eq!((none.aa.as_str(), none.samples), ("none", 1.0));
        assert!((none.rms - 30.0).abs() < 1e-9, "{}", none.rms);
        assert!((none.wrong - 0.7).abs() < 1e-9, "{}", none.wrong);
        assert_eq!(
            (a.modes[1].rms, a.modes[1].wrong, a.modes[1].samples),
            (0.0, 0.0, 256.0)
        );
        // Every fitted row is predicted at or above what was measured.
        for r in &rows {
            let (rms, wrong) = a.error(&r.aa, r.edge, &colours(0.25, true)).unwrap();
            assert!(rms >= r.rms - 1e-9 && wrong >= r.wrong - 1e-9);
        }
        let back = Accuracy::parse(&a.to_toml().unwrap()).unwrap();
        assert_eq!(back, a);
    }

    #[test]
    fn the_edge_fraction_is_the_closed_form_at_most_one() {
        // 512 squares tiling 500×500: sides of 22.1 px, 4·√(512·250000) = 45,255 px.
        let env = Environment {
            frames: 1,
            relevant: 512,
            area: 250_000.0,
            width: 500,
            height: 500,
            ..Default::default()
        };
        assert!((edge_fraction(&env) - 0.181).abs() < 0.001);
        let tiny = Environment {
            relevant: 100_000,
            ..env
        };
        assert_eq!(edge_fraction(&tiny), 1.0);
        // Stacked four deep: a quarter of the edges show (4/H, H = √(4·250000/512)).
        let deep = Environment {
            area: 1_000_000.0,
            ..env
        };
        assert!((edge_fraction(&deep) - 4.0 / (1_000_000.0f64 / 512.0).sqrt()).abs() < 1e-9);
        assert_eq!(edge_fraction(&Environment::default()), 0.0);
    }

    #[test]
    fn the_colour_scan_reads_contrast_and_shading() {
        let text = "polypipe 1 world\ncolour 255 0 0\n0 0 0\n1 0 0\n0 1 0\nNEXT.POLYGON\n\
                    colour 0 0 0\n0 0 0\n1 0 0\n0 1 0\nNEXT.POLYGON\n";
        let c = Colours::scan(text.as_bytes(), 1 << 20).unwrap();
        assert_eq!(c.polygons, 2);
        assert!(c.flat);
        // Successive: (1² + 0 + 0)/3 once; background: (1/3 + 0)/2 / 4.
        assert!((c.contrast2 - 1.0 / 3.0).abs() < 1e-9, "{}", c.contrast2);
    }

    #[test]
    fn the_cheapest_that_meets_the_budget_and_zero_is_the_reference() {
        let p = |aa: &str, seconds: f64, rms: f64| Predicted {
            aa: aa.into(),
            depth: 0,
            seconds,
            rms,
            wrong: 0.0,
        };
        let all = [
            p("none", 0.1, 12.0),
            p("ss2", 0.2, 4.0),
            p("adaptive4", 0.15, 1.5),
            p("ss16", 2.0, 0.0),
        ];
        assert_eq!(cheapest(&all, 16.0).unwrap().aa, "none");
        assert_eq!(cheapest(&all, 4.0).unwrap().aa, "adaptive4");
        assert_eq!(cheapest(&all, 0.0).unwrap().aa, "ss16");
        assert!(cheapest(&all[..2], 1.0).is_none());
    }

    #[test]
    fn shaded_scenes_leave_the_adaptive_modes_out() {
        let a = Accuracy::committed();
        let shaded_scene = colours(0.1, false);
        let shaded: Vec<&str> = a.allowed(&shaded_scene).map(|m| m.aa.as_str()).collect();
        assert!(!shaded.iter().any(|m| m.starts_with("adaptive")));
        assert!(shaded.contains(&SAFE));
        assert_eq!(a.allowed(&colours(0.1, true)).count(), MODES.len());
    }
}
