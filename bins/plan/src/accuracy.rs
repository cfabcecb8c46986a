//! `plan accuracy` (each sampling mode's predicted time and error on a scene, and what
//! `render --max-error E` would choose), `plan accuracy-fit` (the error model's
//! coefficients fitted to renders of generated scenes) and `plan max-error-check` (the
//! choice against every configuration tried, on scenes the fit never saw).

use costmodel::accuracy::{self, Accuracy, Colours, Measured, Predicted};
use costmodel::cli::DepthArgs;
use costmodel::error::Context;
use costmodel::{Error, Result};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

/// The budgets the check and `plan accuracy` report (the chart marks the same).
pub use costmodel::accuracy::BUDGETS;

/// The colours of a scene file, scanned as far as the look reads (128 KiB).
pub fn colours(scene: &Path) -> Result<Colours> {
    let f = costmodel::look::open(scene)?;
    Colours::scan(f, costmodel::look::LOOK_BYTES)
}

/// `plan accuracy`: every mode's prediction, and the choice at each budget.
pub fn report(a: &DepthArgs) -> Result<String> {
    let (k, _, _, env, target) = costmodel::cli::setup(a)?;
    let c = colours(&a.scene)?;
    let model = Accuracy::load();
    let all = model.predict_all(&k, &env, &c, &target, a.max_depth);
    let mut t = format!(
        "edge pixels a pixel {:.4}, contrast² {:.4} ({} edges shared, {} open; across the \
         shared {:.4}, silhouette {:.3}), {} ({})\n\
         | aa | depth | predicted s | predicted rms | predicted % wrong |\n|---|---|---|---|---|\n",
        accuracy::edge_fraction(&env),
        c.contrast2,
        c.shared_edges,
        c.open_edges,
        c.across2,
        c.silhouette,
        if c.flat {
            "flat"
        } else {
            "shaded or transparent: no adaptiveK"
        },
        model.fitted_on
    );
    for p in &all {
        t += &format!(
            "| {} | {} | {:.4} | {:.2} | {:.2} |\n",
            p.aa,
            p.depth,
            p.seconds,
            p.rms,
            100.0 * p.wrong
        );
    }
    for e in BUDGETS {
        let chosen = accuracy::cheapest(&all, e).map_or("none predicted to meet it".into(), said);
        t += &format!("--max-error {e}: {chosen}\n");
    }
    Ok(t)
}

/// `--aa A --depth D`.
pub fn said(p: &Predicted) -> String {
    format!("--aa {} --depth {}", p.aa, p.depth)
}

/// A render's measured time (the least wall seconds of `reps`) and error against the 16×16
/// reference `reference`.
#[derive(Clone, Copy, Debug)]
pub struct Run {
    pub seconds: f64,
    pub rms: f64,
    pub wrong: f64,
}

/// Runs `render --size SIZE ARGS SCENE` `reps` times and compares its frames with
/// `reference`; `stats`: `--stats`'s lines, when asked.
pub fn measure(
    bin: &Path,
    work: &Path,
    scene: &Path,
    size: &str,
    args: &[String],
    reference: &Path,
    reps: usize,
) -> Result<(Run, String)> {
    let out = work.join("frame.ppm");
    let mut times = Vec::new();
    let mut stderr = String::new();
    for rep in 0..reps.max(1) {
        let t = Instant::now();
        let o = Command::new(bin.join("render"))
            .env("POLYPIPE_LOAD", "0")
            .arg("--size")
            .arg(size)
            .args(args)
            .arg(scene)
            .stdin(Stdio::null())
            .output()
            .context("render")?;
        times.push(t.elapsed().as_secs_f64());
        if !o.status.success() {
            return Err(Error::Data(format!(
                "render {} {}: {}",
                args.join(" "),
                scene.display(),
                String::from_utf8_lossy(&o.stderr).trim()
            )));
        }
        if rep == 0 {
            std::fs::write(&out, &o.stdout)?;
            stderr = String::from_utf8_lossy(&o.stderr).into_owned();
        }
    }
    let (rms, wrong) = compare(bin, reference, &out)?;
    Ok((
        Run {
            // The fastest of the runs: on a machine others share, the least disturbed.
            seconds: times.iter().copied().fold(f64::INFINITY, f64::min),
            rms,
            wrong,
        },
        stderr,
    ))
}

/// `zspec compare --metrics --csv`: the RMS and the share of pixels differing.
pub fn compare(bin: &Path, reference: &Path, frames: &Path) -> Result<(f64, f64)> {
    let o = Command::new(bin.join("zspec"))
        .args(["compare", "--metrics", "--csv"])
        .arg(reference)
        .arg(frames)
        .output()
        .context("zspec compare")?;
    let text = String::from_utf8_lossy(&o.stdout);
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let row = lines
        .find(|l| l.starts_with("overall"))
        .or_else(|| text.lines().nth(1))
        .ok_or_else(|| Error::Data(format!("zspec compare: no row in {text:?}")))?;
    let cells: Vec<&str> = row.split(',').collect();
    let col = |name: &str| -> Result<f64> {
        let i = head
            .iter()
            .position(|h| *h == name)
            .ok_or_else(|| Error::Data(format!("zspec compare: no column {name}")))?;
        let cell = cells.get(i).unwrap_or(&"");
        cell.parse()
            .map_err(|e| Error::Data(format!("zspec compare: column {name}: {cell:?}: {e}")))
    };
    Ok((col("rmse")?, col("differing")? / col("pixels")?.max(1.0)))
}

/// `zspec --samples 16`'s frames of `scene` at `size`, into `out`.
pub fn reference(bin: &Path, scene: &Path, size: &str, out: &Path) -> Result<()> {
    let o = Command::new(bin.join("zspec"))
        .args(["--samples", "16", "--size", size])
        .arg(scene)
        .output()
        .context("zspec")?;
    if !o.status.success() {
        return Err(Error::Data(format!(
            "zspec {}: {}",
            scene.display(),
            String::from_utf8_lossy(&o.stderr).trim()
        )));
    }
    std::fs::write(out, &o.stdout)?;
    Ok(())
}

/// `scene ARGS > DIR/NAME.pp`, and its path.
pub fn make_scene(bin: &Path, work: &Path, name: &str, args: &[&str]) -> Result<PathBuf> {
    let path = work.join(format!("{name}.pp"));
    let o = Command::new(bin.join("scene"))
        .args(args)
        .output()
        .context("scene")?;
    if !o.status.success() {
        return Err(Error::Data(format!(
            "scene {}: {}",
            args.join(" "),
            String::from_utf8_lossy(&o.stderr).trim()
        )));
    }
    std::fs::write(&path, &o.stdout)?;
    Ok(path)
}

/// The features of a scene file at a size, as `render --max-error` sees them.
fn features(scene: &Path, (w, h): (u32, u32)) -> Result<(f64, Colours)> {
    let env = costmodel::look::look(scene, w, h, &[], Some(costmodel::look::LOOK_BYTES))?;
    Ok((accuracy::edge_fraction(&env), colours(scene)?))
}

fn size_of(size: &str) -> Result<(u32, u32)> {
    proto::camera::parse_size(size).map_err(|e| Error::Usage(format!("--size: {e}")))
}

/// The scenes the fit renders: generated, none of them the check's.
fn fit_scenes(bin: &Path, work: &Path) -> Result<Vec<PathBuf>> {
    let root = stagecli::place::root_dir(None)?;
    Ok(vec![
        make_scene(
            bin,
            work,
            "env-dc1",
            &[
                "environment",
                "--polygons",
                "1024",
                "--clipped",
                "0.5",
                "--depth-complexity",
                "1",
                "--seed",
                "101",
            ],
        )?,
        make_scene(
            bin,
            work,
            "env-dc4",
            &[
                "environment",
                "--polygons",
                "3000",
                "--clipped",
                "0.2",
                "--depth-complexity",
                "4",
                "--seed",
                "103",
            ],
        )?,
        make_scene(bin, work, "sphere", &["sphere"])?,
        make_scene(
            bin,
            work,
            "icosahedron",
            &[
                "obj",
                &root
                    .join("examples/models/icosahedron.obj")
                    .to_string_lossy(),
            ],
        )?,
    ])
}

/// `plan accuracy-fit`: renders the fit's scenes at 200×200 and 400×400 with every mode
/// at depth 0, measures each against the 16×16 reference, fits ([`accuracy::fit`]) and
/// writes the coefficients to `out` (default: the cache's accuracy.toml).
pub fn fit(out: Option<PathBuf>) -> Result<String> {
    let bin = costmodel::cli::bin_dir()?;
    let dir = tempfile_dir()?;
    let mut rows = Vec::new();
    let root = stagecli::place::root_dir(None)?;
    let (k, _, _) = costmodel::cli::constants(None, &root, &bin)?;
    let target = costmodel::cli::target(None, Some(0.0), None, None, 1.0);
    let mut factors: Vec<(String, f64)> = Vec::new();
    for scene in fit_scenes(&bin, &dir)? {
        for size in ["200x200", "400x400"] {
            let (w, h) = size_of(size)?;
            let env = costmodel::look::look(&scene, w, h, &[], Some(costmodel::look::LOOK_BYTES))?;
            let mut none_s = None;
            let reference_frames = dir.join("reference.ppm");
            reference(&bin, &scene, size, &reference_frames)?;
            let (edge, c) = features(&scene, size_of(size)?)?;
            for aa in accuracy::MODES {
                let args = [
                    "--aa".to_string(),
                    aa.to_string(),
                    "--depth".into(),
                    "0".into(),
                ];
                let (r, _) = measure(&bin, &dir, &scene, size, &args, &reference_frames, 3)?;
                let none = *none_s.get_or_insert(r.seconds);
                let ratio = r.seconds / none;
                let mut s = accuracy::samples_for_ratio(&k, &env, &target, ratio);
                if aa.starts_with("adaptive") {
                    // K² samples in the edge pixels only: the factor there.
                    s = 1.0 + (s - 1.0) / accuracy::edge_fraction(&env).max(0.01);
                }
                factors.push((aa.into(), s));
                let (rms, wrong) = (r.rms, r.wrong);
                rows.push(Measured {
                    aa: aa.into(),
                    edge,
                    colours: c,
                    rms,
                    wrong,
                });
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    let model = accuracy::fit(
        &rows,
        "plan accuracy-fit: 2 environments, a sphere, an OBJ icosahedron; 200x200, 400x400",
        |aa| {
            median(
                factors
                    .iter()
                    .filter(|(m, _)| m == aa)
                    .map(|(_, s)| *s)
                    .collect(),
            )
        },
    );
    let path = match out {
        Some(p) => p,
        None => costmodel::cache::dir()
            .ok_or_else(|| {
                Error::Io("no cache folder: neither XDG_CACHE_HOME nor HOME is set".into())
            })?
            .join("accuracy.toml"),
    };
    if let Some(d) = path.parent() {
        std::fs::create_dir_all(d)?;
    }
    std::fs::write(&path, model.to_toml()?)?;
    let mut t = format!(
        "{}\n| aa | rms a unit (open edges) | (shared edges) | wrong an edge pixel | samples |\n|---|---|---|---|---|\n",
        path.display()
    );
    for m in &model.modes {
        t += &format!(
            "| {} | {:.2} | {:.2} | {:.3} | {:.1} |\n",
            m.aa,
            m.rms,
            m.rms_shared.unwrap_or(m.rms),
            m.wrong,
            m.samples
        );
    }
    Ok(t)
}

/// A fresh folder for the renders' files.
pub fn tempfile_dir() -> Result<PathBuf> {
    let d = std::env::temp_dir().join(format!("plan-accuracy-{}", std::process::id()));
    std::fs::create_dir_all(&d)?;
    Ok(d)
}

/// The median of `v` (1 for none).
fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(1.0)
}

/// `plan max-error-check`'s arguments.
#[derive(clap::Args, Debug)]
pub struct CheckArgs {
    /// The screens, comma-separated.
    #[arg(
        long,
        default_value = "250x250,500x500,1000x1000",
        value_name = "WxH,…"
    )]
    pub sizes: String,
    /// Timed runs of each configuration (the fastest is taken).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u64).range(1..=50))]
    pub reps: u64,
    /// Only the first N scenes (environment, spheres, OBJ torus, the thesis's scene,
    /// a denser environment).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=5))]
    pub scenes: Option<u64>,
    /// The depths every configuration is tried at, comma-separated.
    #[arg(long, default_value = "0,1,2", value_name = "D,…")]
    pub depths: String,
}

/// One case of the check: a scene, a screen and a budget.
pub struct Case {
    pub scene: String,
    pub size: String,
    pub budget: f64,
    pub chose: String,
    pub predicted_rms: f64,
    pub run: Run,
    /// The cheapest configuration tried that met the budget, and its time when timed in
    /// turn with the choice.
    pub best: Option<(String, f64)>,
}

impl Case {
    pub fn met(&self) -> bool {
        self.run.rms <= self.budget
    }
    /// Its time over the cheapest that met the budget.
    pub fn ratio(&self) -> Option<f64> {
        self.best.as_ref().map(|(_, s)| self.run.seconds / s)
    }
}

/// The scenes the check renders: none of them the fit's or the tests'.
fn check_scenes(bin: &Path, work: &Path) -> Result<Vec<PathBuf>> {
    let root = stagecli::place::root_dir(None)?;
    Ok(vec![
        make_scene(
            bin,
            work,
            "environment",
            &[
                "environment",
                "--polygons",
                "600",
                "--clipped",
                "0.3",
                "--depth-complexity",
                "2",
                "--seed",
                "7",
            ],
        )?,
        make_scene(bin, work, "spheres", &["spheres"])?,
        make_scene(
            bin,
            work,
            "torus",
            &[
                "obj",
                &root.join("examples/models/torus.obj").to_string_lossy(),
            ],
        )?,
        make_scene(
            bin,
            work,
            "thesis",
            &[
                "environment",
                "--polygons",
                "1024",
                "--clipped",
                "0.5",
                "--depth-complexity",
                "1",
                "--seed",
                "1",
            ],
        )?,
        make_scene(
            bin,
            work,
            "dense",
            &[
                "environment",
                "--polygons",
                "5000",
                "--clipped",
                "0.5",
                "--depth-complexity",
                "3",
                "--seed",
                "11",
            ],
        )?,
    ])
}

/// `plan max-error-check`: for each scene and screen, every configuration (each mode at
/// each of `--depths`) rendered and measured against the 16×16 reference, then `render
/// --max-error E` for E of 0, 1, 4 and 16, timed in turn with the cheapest configuration
/// that met E; a row a case, and the summary.
pub fn check(a: &CheckArgs) -> Result<(Vec<Case>, String)> {
    let bin = costmodel::cli::bin_dir()?;
    let dir = tempfile_dir()?;
    let reps = a.reps as usize;
    let depths: Vec<&str> = a.depths.split(',').collect();
    let mut scenes = check_scenes(&bin, &dir)?;
    scenes.truncate(a.scenes.unwrap_or(5) as usize);
    let mut cases = Vec::new();
    // Every scene at the first screen before any at the next (the small screens first).
    for size in a.sizes.split(',') {
        for scene in &scenes {
            let name = scene
                .file_stem()
                .map_or(String::new(), |s| s.to_string_lossy().into_owned());
            let refs = dir.join("reference.ppm");
            reference(&bin, scene, size, &refs)?;
            let mut tried = Vec::new();
            for aa in accuracy::MODES {
                for d in &depths {
                    let args = ["--aa", aa, "--depth", d].map(String::from);
                    let (r, _) = measure(&bin, &dir, scene, size, &args, &refs, reps)?;
                    tried.push((format!("--aa {aa} --depth {d}"), r));
                }
            }
            for budget in BUDGETS {
                let args = ["--max-error".to_string(), budget.to_string()];
                let cheapest = tried
                    .iter()
                    .filter(|(_, r)| r.rms <= budget)
                    .min_by(|x, y| x.1.seconds.total_cmp(&y.1.seconds))
                    .map(|(c, _)| c.clone());
                // What render chose and predicted, from a run with --stats; then the
                // user's command, without it (--stats costs every stage a report), and
                // the cheapest configuration tried that met E, timed in turn (one run
                // each, `reps` times), so that a machine's load falls on both alike; the
                // fastest run of each is taken.
                let stats = [&["--stats".to_string()][..], &args].concat();
                let (mut run, said) = measure(&bin, &dir, scene, size, &stats, &refs, 1)?;
                let mut best_s = f64::INFINITY;
                for rep in 0..reps {
                    let (r, _) = measure(&bin, &dir, scene, size, &args, &refs, 1)?;
                    if rep == 0 || r.seconds < run.seconds {
                        run = r;
                    }
                    if let Some(c) = &cheapest {
                        let words: Vec<String> = c.split(' ').map(String::from).collect();
                        let (b, _) = measure(&bin, &dir, scene, size, &words, &refs, 1)?;
                        best_s = best_s.min(b.seconds);
                    }
                }
                let line = said.lines().find(|l| l.contains("max-error")).unwrap_or("");
                let chose = line
                    .split_once("chose ")
                    .map_or("?", |(_, r)| r.split(" (").next().unwrap_or("?"))
                    .to_string();
                let predicted_rms = line
                    .split_once("RMS ")
                    .and_then(|(_, r)| r.split(',').next())
                    .and_then(|v| v.parse().ok())
                    .unwrap_or(f64::NAN);
                let best = cheapest.map(|c| (c, best_s));
                cases.push(Case {
                    scene: name.clone(),
                    size: size.to_string(),
                    budget,
                    chose,
                    predicted_rms,
                    run,
                    best,
                });
                // Each row as it is measured: the whole check takes a while.
                eprint!("{}", row(&cases[cases.len() - 1]));
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    let text = table(&cases);
    Ok((cases, text))
}

/// The check's table and its summary.
pub fn table(cases: &[Case]) -> String {
    let mut t = String::from(
        "| scene | size | E | chose | predicted rms | measured rms | ≤ E | s | cheapest meeting E (tried) | its s | ratio |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for c in cases {
        t += &row(c);
    }
    let n = cases.len();
    let met = cases.iter().filter(|c| c.met()).count();
    let timed: Vec<f64> = cases.iter().filter_map(Case::ratio).collect();
    let fast = timed.iter().filter(|r| **r <= 1.25).count();
    t += &format!(
        "error at most E in {met} of {n} cases ({:.0}%); time at most 1.25× the cheapest \
         configuration tried that met E in {fast} of {} ({:.0}%)\n",
        100.0 * met as f64 / n.max(1) as f64,
        timed.len(),
        100.0 * fast as f64 / timed.len().max(1) as f64,
    );
    t
}

/// One case's row of the check's table.
pub fn row(c: &Case) -> String {
    let (best, best_s) = c
        .best
        .as_ref()
        .map_or(("–".to_string(), "–".to_string()), |(b, s)| {
            (b.clone(), format!("{s:.3}"))
        });
    format!(
        "| {} | {} | {} | {} | {:.2} | {:.2} | {} | {:.3} | {best} | {best_s} | {} |\n",
        c.scene,
        c.size,
        c.budget,
        c.chose,
        c.predicted_rms,
        c.run.rms,
        if c.met() { "yes" } else { "**no**" },
        c.run.seconds,
        c.ratio().map_or("–".into(), |r| format!("{r:.2}")),
    )
}
