//! # chart: speed against accuracy, and the thesis's cost model
//!
//! `scripts/chart.sh -o DIR SCENE…` runs every method and variant of the project on each
//! scene through the real `scripts/render.sh` and measures it (docs/DESIGN.md, "Measures"):
//! time, CPU and memory of the whole process tree, and the frames' error against the
//! `zspec` references. It writes `DIR/results.csv` and the picture of time against error
//! (`speed-accuracy.png`, `.svg`), and puts the cost model of thesis chapters 5.2 and 6.4
//! ([`model`]) beside measurement in `DIR/model.csv` and `model.png`. `--calibrate`
//! measures the model's constants on this machine ([`calibrate`]); `chart choose-depth`
//! is `render.sh --depth auto`'s choice ([`model::choose_depth`]).

pub mod calibrate;
pub mod chart;
pub mod error;
pub mod look;
pub mod measure;
pub mod methods;
pub mod model;
pub mod plot;
