//! The hidden-line figure (`chart hidden-lines`): time against line error for the two
//! hidden-line methods, over several scenes and resolutions.
//!
//! Each scene is drawn at each size by `hiddenline --method continuous` (exact geometry in
//! f64, the reference) and `--method archuleta` (Archuleta's counters on Watkins's
//! scan-line segments). The line error ([`lines::line_error`]) is the length of the
//! reference's lines that no drawn line comes within half a pixel of, plus the length
//! drawn that no reference line comes within half a pixel of, intersection lines
//! included, computed exactly; pixels are those of the largest size, whatever the size
//! drawn at: one pen on one sheet, the resolution of Archuleta's counters (the scan
//! lines) varied. His ends fall between scan lines (his "first" and "third problems"),
//! so at a coarse resolution they miss by more than the pen's half width; the finer his
//! scan lines, the smaller his error, and the longer he takes. That is his trade-off, and
//! the figure shows it beside the continuous method (error 0).

use crate::error::{Context, Error, Result};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Instant;

/// The scenes: a name and the shell command that writes it (run with the binaries on
/// PATH, in the repository).
pub const SCENES: [(&str, &str); 4] = [
    ("spheres", "scene spheres"),
    ("building", "scene building"),
    ("sphere", "scene sphere"),
    ("penetrating", "cat examples/penetrating.txt"),
];

/// The methods, as `hiddenline --method` names them.
pub const METHODS: [&str; 2] = ["continuous", "archuleta"];

/// One drawing measured.
#[derive(Clone, Debug, PartialEq)]
pub struct HiddenRow {
    pub scene: String,
    pub size: u32,
    pub method: String,
    /// Median wall-clock seconds of `hiddenline` alone on the screen-space stream.
    pub seconds: f64,
    pub error_px: f64,
    pub missed_px: f64,
    pub extra_px: f64,
    pub reference_px: f64,
}

impl HiddenRow {
    /// The line error as a share of the reference drawing's length, in percent.
    pub fn error_percent(&self) -> f64 {
        if self.reference_px > 0.0 {
            100.0 * self.error_px / self.reference_px
        } else {
            0.0
        }
    }
}

fn sh(bin: &Path, root: &Path, script: &str) -> Result<()> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    let mut dirs = vec![bin.to_path_buf()];
    dirs.extend(std::env::split_paths(&path));
    let status = Command::new("bash")
        .args(["-c", &format!("set -eo pipefail; {script}")])
        .current_dir(root)
        .env(
            "PATH",
            std::env::join_paths(dirs).map_err(|e| Error::Data(e.to_string()))?,
        )
        .stdin(Stdio::null())
        .status()
        .with_context(|| format!("cannot run {script}"))?;
    if !status.success() {
        return Err(Error::Data(format!("`{script}` failed ({status})")));
    }
    Ok(())
}

/// Draws every scene at every size with both methods (`reps` timed runs each, the median
/// kept), in `work`, and scores each drawing against the continuous one.
pub fn measure(
    bin: &Path,
    root: &Path,
    work: &Path,
    sizes: &[u32],
    reps: u32,
) -> Result<Vec<HiddenRow>> {
    std::fs::create_dir_all(work)?;
    let largest = sizes.iter().copied().max().unwrap_or(1);
    let mut rows = Vec::new();
    for (scene, make) in SCENES {
        for &size in sizes {
            let input = work.join(format!("{scene}-{size}.screen"));
            sh(
                bin,
                root,
                &format!(
                    "{make} | viewxf --size {size}x{size} | clipbatch | persp --size {size}x{size} > '{}'",
                    input.display()
                ),
            )?;
            let mut drawings = Vec::new();
            for method in METHODS {
                let svg = work.join(format!("{scene}-{size}-{method}.svg"));
                let mut times = Vec::new();
                for _ in 0..reps.max(1) {
                    let start = Instant::now();
                    let status = Command::new(bin.join("hiddenline"))
                        .args(["--method", method])
                        .stdin(std::fs::File::open(&input)?)
                        .stdout(std::fs::File::create(&svg)?)
                        .status()
                        .context("cannot run hiddenline")?;
                    times.push(start.elapsed().as_secs_f64());
                    if !status.success() {
                        return Err(Error::Data(format!(
                            "hiddenline --method {method} failed on {scene} at {size}"
                        )));
                    }
                }
                times.sort_by(f64::total_cmp);
                let text = std::fs::read_to_string(&svg)?;
                let pieces = lines::read_svg(&text).map_err(Error::Data)?;
                drawings.push((method, times[times.len() / 2], pieces));
            }
            let reference = drawings[0].2.clone();
            // The drawing is measured in pixels of the largest size, with a reach of half
            // of one of them: the same pen on the same paper, the counters' resolution
            // varied.
            let scale = largest as f64 / size as f64;
            for (method, seconds, pieces) in drawings {
                let e = lines::line_error(&pieces, &reference, 0.5 / scale);
                rows.push(HiddenRow {
                    scene: scene.into(),
                    size,
                    method: method.into(),
                    seconds,
                    error_px: e.total_px() * scale,
                    missed_px: e.missed_px * scale,
                    extra_px: e.extra_px * scale,
                    reference_px: e.reference_px * scale,
                });
            }
        }
    }
    Ok(rows)
}

/// The rows as CSV, one a drawing.
pub fn csv(rows: &[HiddenRow]) -> String {
    let mut s = String::from(
        "scene,size,method,seconds,line_error_px,missed_px,extra_px,reference_px,line_error_percent\n",
    );
    for r in rows {
        s += &format!(
            "{},{},{},{:.6},{:.3},{:.3},{:.3},{:.3},{:.4}\n",
            r.scene,
            r.size,
            r.method,
            r.seconds,
            r.error_px,
            r.missed_px,
            r.extra_px,
            r.reference_px,
            r.error_percent()
        );
    }
    s
}
