//! What `render --max-error E` would choose on each charted scene, for E of
//! [`BUDGETS`]: the same choice, by the same code (`costmodel::accuracy::choose` on the
//! scene as `accuracy::Seen` sees it, render's target, this machine's accuracy fit), so
//! that the speed-accuracy panels can mark it and `DIR/max-error.csv` can be checked
//! against `render --max-error E --stats`. Each choice is set beside the chart's row of
//! the same method and depth, where the chart ran one.

use crate::chart::{Row, Scene, Setup};
use crate::error::Result;
use crate::look::Environment;
use crate::methods::METHODS;
use crate::model::{predict_on, Constants, Target};
use costmodel::accuracy::{self, Accuracy, Seen, BUDGETS};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// One row of `max-error.csv`: a scene, a budget, and the configuration chosen for it.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Choice {
    pub scene: String,
    /// E, RMS levels of 0–255 against the 16×16 reference.
    pub budget: f64,
    /// The chart's name of the configuration: the z-buffer's row of its `--aa` (`zbuf`
    /// for none).
    pub method: String,
    pub aa: String,
    /// Empty for the safe choice, whose depth is left to `--depth auto`.
    pub depth: Option<u8>,
    /// The model's prediction (empty for the safe choice): wall seconds, and RMS.
    pub predicted_time_s: Option<f64>,
    pub predicted_error: Option<f64>,
    /// The predicted seconds less the model's prediction for an empty scene at the same
    /// depth on the same screen, at least 0: the prediction on the panels' time axis
    /// (seconds less start-up).
    pub predicted_less_startup_s: Option<f64>,
    /// The chart's row of that method and depth, where it ran one: its time (CPU seconds
    /// less start-up) and its RMS against the 16×16 reference.
    pub measured_time_s: Option<f64>,
    pub measured_rms: Option<f64>,
    /// Why: `cheapest predicted to meet it`, or `safe: …` where render takes the safe
    /// choice (no commas: a CSV field unquoted).
    pub rule: String,
}

impl Choice {
    /// Whether the chart ran the chosen configuration.
    pub fn charted(&self) -> bool {
        self.measured_time_s.is_some()
    }
}

/// The chart's name of the row `--aa aa` selects: the table's, or `zbuf` for none.
pub fn method_of(aa: &str) -> String {
    methods::by_aa(METHODS, aa)
        .map_or("zbuf", |m| m.name)
        .to_string()
}

/// The choices on the scene file `path` (charted as `name` on `width`×`height`) at
/// each of [`BUDGETS`], with the constants `k` on `target`, beside `rows`.
pub fn choose_on(
    model: &Accuracy,
    k: &Constants,
    target: &Target,
    (path, name, width, height): (&Path, &str, u32, u32),
    rows: &[Row],
) -> Vec<Choice> {
    let seen = Seen::of(path, width, height, &[]);
    BUDGETS
        .iter()
        .map(|&budget| {
            let best = seen
                .as_ref()
                .and_then(|s| accuracy::choose(model, k, s, target, budget));
            let (aa, depth, rule) = match (&seen, &best) {
                (_, Some(p)) => (p.aa.clone(), Some(p.depth), "cheapest predicted to meet it"),
                (None, _) => (
                    accuracy::SAFE.to_string(),
                    None,
                    "safe: a scene the look cannot read",
                ),
                (Some(_), None) => (
                    accuracy::SAFE.to_string(),
                    None,
                    "safe: no mode predicted to meet it",
                ),
            };
            let method = method_of(&aa);
            let row = depth.and_then(|d| {
                rows.iter()
                    .find(|r| r.scene == name && r.method == method && r.depth == d)
            });
            Choice {
                scene: name.to_string(),
                budget,
                method,
                aa,
                depth,
                predicted_time_s: best.as_ref().map(|p| p.seconds),
                predicted_error: best.as_ref().map(|p| p.rms),
                predicted_less_startup_s: best.as_ref().zip(seen.as_ref()).map(|(p, s)| {
                    let empty = Environment {
                        frames: 1,
                        width,
                        height,
                        text: s.env.text,
                        ..Environment::default()
                    };
                    (p.seconds - predict_on(k, &empty, p.depth, target).total_s).max(0.0)
                }),
                measured_time_s: row.map(|r| r.time_s),
                measured_rms: row.and_then(|r| r.rms_16x16),
                rule: rule.to_string(),
            }
        })
        .collect()
}

/// Every scene's choices, on the scene as the chart's runs rendered it (in colours of its
/// own, `crate::visibility`), with the chart's constants on render's target (this
/// machine's cores and load, no hosts) and this machine's accuracy fit.
pub fn choices(setup: &Setup, scenes: &[Scene], rows: &[Row]) -> Result<Vec<Choice>> {
    let model = Accuracy::load();
    let target = costmodel::cli::target(None, None, None, None, 1.0);
    let mut all = Vec::new();
    for given in scenes {
        let scene = setup.coloured(given)?;
        all.extend(choose_on(
            &model,
            &setup.constants,
            &target,
            (&scene.path, &given.name, scene.width, scene.height),
            rows,
        ));
    }
    Ok(all)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_mode_is_named_as_the_chart_names_its_row() {
        assert_eq!(method_of("none"), "zbuf");
        assert_eq!(method_of("ss4"), "ss4");
        assert_eq!(method_of("adaptive16"), "adaptive16");
        assert_eq!(method_of("abuf"), "abuf");
    }

    #[test]
    fn a_scene_the_look_cannot_read_takes_the_safe_choice() {
        let k = Constants::committed();
        let c = choose_on(
            &Accuracy::committed(),
            &k,
            &Target::cores(1),
            (Path::new("/nonexistent/scene.txt"), "gone", 10, 10),
            &[],
        );
        assert_eq!(c.len(), BUDGETS.len());
        for (choice, e) in c.iter().zip(BUDGETS) {
            assert_eq!(
                (
                    choice.budget,
                    choice.aa.as_str(),
                    choice.method.as_str(),
                    choice.depth,
                    choice.predicted_time_s,
                    choice.charted(),
                    choice.rule.as_str()
                ),
                (
                    e,
                    "ss16",
                    "ss16",
                    None,
                    None,
                    false,
                    "safe: a scene the look cannot read"
                )
            );
        }
    }
}
