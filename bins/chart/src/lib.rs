//! # chart: speed against accuracy, and the cost model beside measurement
//!
//! `scripts/chart.sh -o DIR SCENE…` runs every method and variant of the project on each
//! scene through the real `scripts/render.sh` and measures it (docs/DESIGN.md, "Measures"):
//! time, CPU and memory of the whole process tree, and the frames' error against the
//! `zspec` references. It writes `DIR/results.csv` and the picture of time against error
//! (`speed-accuracy.png`, `.svg`), and puts the cost model of thesis chapters 5.2 and 6.4
//! beside measurement in `DIR/model.csv` and `model.png`. The model, its calibration and
//! the planner are the `costmodel` crate's (re-exported here under their old names, so
//! that `chart::model` still reads); `chart choose-depth` is a thin alias of `plan depth`.

pub mod bottleneck;
pub mod chart;
pub mod error;
pub mod hidden;
pub mod maxerror;
pub mod methods;
pub mod plot;
pub mod stats;
pub mod visibility;

pub use costmodel::{cache, calibrate, look, measure, model, thesis};
