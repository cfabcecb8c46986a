//! `chart calibrate` (and the first use of the model on a machine): the model's constants
//! measured on this machine, in at most 20 seconds. Each stage binary
//! is run alone on the streams of synthetic scenes (`scene environment`, the thesis's
//! test environment of 5.2, over a grid of polygon counts, screens and depth
//! complexities), reading a file and writing a file, and its CPU seconds are fitted by
//! least squares ([`crate::model::fit`]) to its work in the model's terms. The
//! script's and each process's start-up are then fitted to the `render` binary's wall time on a
//! two-polygon scene at depths 0 to 4, less what the stages predict there.

// The cores are part of what identifies the machine a calibration was made on (the
// cache's); named here too, where the model's callers look for them.
pub use crate::cache::{cores, machine_cores};
use crate::error::{Context, Result};
use crate::look::{count_screen, count_world, Environment};
use crate::measure::{self, Usage};
use crate::model::{fit, stage_work, Constants, Cost, Overheads, StageWork, Work};
use std::fs::File;
use std::path::Path;
use std::process::{Command, Stdio};

/// One measured stage run: its work's regressors and its CPU seconds.
#[derive(Default)]
struct Samples {
    rows: Vec<[f64; 6]>,
    seconds: Vec<f64>,
}

impl Samples {
    fn push(&mut self, work: &Work, seconds: f64) {
        self.rows.push(work.features());
        self.seconds.push(seconds);
    }

    fn fit(&self, columns: [bool; 6]) -> Cost {
        Cost::from_coefficients(fit_relative(&self.rows, &self.seconds, columns))
    }
}

/// [`fit`] in relative terms: each run's row and seconds divided by its seconds, so that
/// the least squares weigh a 1-ms run's error of 1 ms as a 1-s run's of 1 s. In absolute
/// terms the large scenes decide every coefficient and the constant a process is what
/// their line extrapolates to at no work, which was twice a two-polygon run's own time;
/// with the tiny scene among the runs ([`TINY`]) and the relative weights, the constant
/// is that run's measured start-up, and the model's error is what the chart reports,
/// relative. Runs of no measurable time (0 s) keep their absolute weight.
fn fit_relative(rows: &[[f64; 6]], seconds: &[f64], columns: [bool; 6]) -> [f64; 6] {
    let weight = |t: f64| if t > 0.0 { 1.0 / t } else { 1.0 };
    let scaled: Vec<[f64; 6]> = rows
        .iter()
        .zip(seconds)
        .map(|(row, &t)| row.map(|x| x * weight(t)))
        .collect();
    let ones: Vec<f64> = seconds.iter().map(|&t| t * weight(t)).collect();
    fit(&scaled, &ones, columns)
}

/// The tiny scene (polygons, width, height, depth complexity) measured beside
/// [`grid`]'s: two polygons at 500×500, a stage run that is all start-up (the process,
/// its exec, its header, its exit), so that each stage's constant a process is measured
/// on this machine, not extrapolated from thousands of polygons. Always measured, late or
/// not: its runs take milliseconds.
pub const TINY: (u64, u32, u32, f64) = (2, 500, 500, 1.0);

/// Runs of each stage on [`TINY`] (the fastest kept): a start-up of a few milliseconds
/// varies by a millisecond from run to run.
const TINY_REPS: usize = 5;

/// The fastest of `reps` runs of a command (CPU seconds), its stdin and stdout files.
fn cpu(reps: usize, mut make: impl FnMut() -> Result<Command>) -> Result<f64> {
    let mut best = f64::INFINITY;
    for _ in 0..reps.max(1) {
        let mut cmd = make()?;
        best = best.min(measure::run(&mut cmd)?.cpu_s);
    }
    Ok(best)
}

fn stage(bin: &Path, name: &str, input: &Path, output: Option<&Path>) -> Result<Command> {
    let mut cmd = Command::new(bin.join(name));
    cmd.stdin(File::open(input).with_context(|| format!("{}", input.display()))?)
        .stderr(Stdio::null());
    match output {
        Some(o) => cmd.stdout(File::create(o)?),
        None => cmd.stdout(Stdio::null()),
    };
    Ok(cmd)
}

/// The synthetic scenes: (polygons, width, height, depth complexity). Chosen so that the
/// hidden-surface stage's five terms (a process, a polygon, a span, a pixel, a screen
/// pixel) vary independently: polygons against screen and Dc, which set the spans and
/// pixels, over a factor of 30 each, in few enough scenes to fit 20 seconds.
/// `quick`: four small scenes, for tests (about two seconds).
pub fn grid(quick: bool) -> Vec<(u64, u32, u32, f64)> {
    if quick {
        return vec![
            (300, 200, 150, 1.0),
            (2000, 200, 150, 6.0),
            (300, 640, 480, 6.0),
            (2000, 640, 480, 1.0),
        ];
    }
    vec![
        (1000, 400, 400, 1.0),
        (1000, 1280, 720, 8.0),
        (8000, 400, 400, 8.0),
        (8000, 1280, 720, 1.0),
        (8000, 1920, 1080, 10.0),
        (30000, 640, 480, 4.0),
        (30000, 1280, 720, 8.0),
        (2000, 1920, 1080, 2.0),
    ]
}

/// How long the scenes may take before the calibration cuts itself short (it has 20 s in
/// all; the start-up's renders take 2 to 4 s after the scenes).
pub const LATE: std::time::Duration = std::time::Duration::from_secs(13);

/// Whether the automatic calibration should be the quick one: `POLYPIPE_CALIBRATION=quick`
/// (the tests set it, so that a test that meets an uncalibrated machine does not spend
/// 20 seconds fitting it).
pub fn quick_from_env() -> bool {
    std::env::var("POLYPIPE_CALIBRATION").is_ok_and(|v| v == "quick")
}

/// Measures the stages and fits the constants. `tick` is called after each scene.
pub fn calibrate(
    bin: &Path,
    render: &Path,
    work: &Path,
    quick: bool,
    mut tick: impl FnMut(&str),
) -> Result<Constants> {
    let scene_reps = if quick { 1 } else { 2 };
    let [mut vt, mut vb, mut clip, mut split, mut persp, mut hse, mut merge, mut resolve] =
        std::array::from_fn(|_| Samples::default());
    let f = |n: &str| work.join(n);
    let start = std::time::Instant::now();
    let scenes = grid(quick);
    let count = scenes.len();
    for (i, &(p, w, h, dc)) in scenes.iter().chain([&TINY]).enumerate() {
        let tiny = i == count;
        // The 20 s bound on a loaded machine: past LATE, no more scenes once the five
        // the fit needs at least (five terms of the leaf's cost) are measured, but the
        // tiny one.
        if i >= 5 && !tiny && start.elapsed() > LATE {
            continue;
        }
        let reps = if tiny { TINY_REPS } else { scene_reps };
        let size = format!("{w}x{h}");
        tick(&format!("{p} polygons, {size}, Dc {dc}"));
        for (text, name) in [(false, "w.pp"), (true, "w.txt")] {
            let mut cmd = Command::new(bin.join("scene"));
            cmd.args(["environment", "--polygons", &p.to_string()])
                .args(["--depth-complexity", &dc.to_string(), "--size", &size])
                .args(["--seed", &(i + 1).to_string()]);
            if text {
                cmd.arg("--text");
            }
            measure::run(cmd.stdout(File::create(f(name))?))?;
        }
        let (frames, polygons, vertices) = count_world(File::open(f("w.pp"))?)?;
        let v = |input: &str| -> Result<Command> {
            let mut c = stage(bin, "viewxf", &f(input), Some(&f("e.pp")))?;
            c.args(["--size", &size]);
            Ok(c)
        };
        let t_vt = cpu(reps, || v("w.txt"))?;
        let t_vb = cpu(reps, || v("w.pp"))?;
        let t_clip = cpu(reps, || {
            stage(bin, "clipbatch", &f("e.pp"), Some(&f("c.pp")))
        })?;
        let t_split = cpu(reps, || {
            let mut c = stage(bin, "splitter", &f("c.pp"), None)?;
            c.args(["--node", "1", "--depth", "1", "--size", &size])
                .arg(f("s1.pp"))
                .arg(f("s2.pp"));
            Ok(c)
        })?;
        let t_persp = cpu(reps, || {
            let mut c = stage(bin, "persp", &f("c.pp"), Some(&f("p.pp")))?;
            c.args(["--size", &size]);
            Ok(c)
        })?;
        let t_hse = cpu(reps, || {
            let mut c = stage(bin, "scanconv", &f("p.pp"), Some(&f("r.pp")))?;
            c.arg("--resolve");
            Ok(c)
        })?;
        let t_merge = cpu(reps, || {
            let mut c = stage(bin, "zbuf", &f("r.pp"), None)?;
            c.arg(f("r.pp")).stdin(Stdio::null());
            Ok(c)
        })?;
        let t_resolve = cpu(reps, || stage(bin, "zbuf", &f("p.pp"), None))?;
        let (relevant, relevant_vertices, area) = count_screen(File::open(f("p.pp"))?)?;
        let env = Environment {
            frames,
            polygons,
            vertices,
            relevant,
            relevant_vertices,
            area,
            width: w,
            height: h,
            text: true,
        };
        let StageWork {
            world,
            flowing,
            merge: merge_work,
            ..
        } = stage_work(&env, false);
        vt.push(&world, t_vt);
        vb.push(&world, t_vb);
        clip.push(&world, t_clip);
        // The stages after the clipper, as at depth 0 (and the root splitter).
        split.push(&flowing, t_split);
        persp.push(&flowing, t_persp);
        hse.push(&flowing, t_hse);
        merge.push(&merge_work, t_merge);
        // zbuf resolving the screen stream (depth 0): the leaf's work and the frames'.
        let mut both = flowing;
        both.screen += merge_work.screen;
        resolve.push(&both, t_resolve);
    }
    // Every scene is of quads (E = 4), so a cost per vertex cannot be told from one per
    // polygon: the geometry stages get a cost per polygon of four vertices.
    let geometry = [true, true, false, false, false, false];
    let mut k = Constants {
        measured_on: machine(),
        machine: crate::cache::this_machine(bin),
        drops_emptied: false,
        persp_at_leaves: false,
        viewxf_text: vt.fit(geometry),
        viewxf_binary: vb.fit(geometry),
        clip: clip.fit(geometry),
        splitter: split.fit(geometry),
        persp: persp.fit(geometry),
        // T_sc's terms (5.2.4): per polygon, span and pixel, and the region.
        hse: hse.fit([true, true, false, true, true, true]),
        merge: merge.fit([true, false, false, true, false, true]),
        resolve: resolve.fit([true, true, false, true, true, true]),
        overheads: Overheads::default(),
    };
    tick("render on two polygons, depths 0-4");
    // Late, the start-up is timed once at three depths instead of three times at five.
    let late = start.elapsed() > LATE;
    let depths: &[u8] = if quick {
        &[0, 2]
    } else if late {
        &[0, 2, 4]
    } else {
        &[0, 1, 2, 3, 4]
    };
    let reps = if quick || late { 1 } else { 3 };
    k.overheads = overheads(bin, render, work, &k, depths, reps)?;
    Ok(k)
}

/// The script's, the processes' and the pipes' start-up: `render` on two polygons at
/// `depths` (wall seconds, median of `reps`) less the stages' predicted time, fitted to
/// script + process × processes / cores + pipe × pipes / cores ([`fit_overheads`]).
fn overheads(
    bin: &Path,
    render: &Path,
    work: &Path,
    k: &Constants,
    depths: &[u8],
    reps: usize,
) -> Result<Overheads> {
    let scene = work.join("two.txt");
    measure::run(
        Command::new(bin.join("scene"))
            .args(["environment", "--polygons", "2", "--clipped", "0", "--text"])
            .args(["--size", "500x500"])
            .stdout(File::create(&scene)?),
    )?;
    let env = crate::look::look(&scene, 500, 500, &[], None)?;
    let cores = cores();
    // The start-up is timed on the machine as it is: its load, as the predictions will
    // take it, is taken out of what is fitted.
    let load = background_load();
    let target = crate::model::Target::cores(cores).loaded(load);
    let mut runs = Vec::new();
    for &d in depths {
        let mut walls: Vec<Usage> = Vec::new();
        for _ in 0..reps {
            walls.push(measure::run(
                Command::new(render)
                    // The binaries measured, run as they are: render.sh's own check for
                    // stale binaries could start a build in the middle of the timing.
                    .env("POLYPIPE_BIN", bin)
                    .args(["--size", "500x500", "--depth", &d.to_string()])
                    .arg(&scene)
                    .stdout(Stdio::null())
                    .stderr(Stdio::null()),
            )?);
        }
        // With no start-up costs yet in `k`, shared_s is the stages' work over the
        // cores, and a two-polygon render is all start-up: the shared bound is the
        // larger.
        let p = crate::model::predict_on(k, &env, d, &target);
        runs.push(StartUp {
            processes: p.processes,
            pipes: p.pipes,
            wall_s: measure::median(&walls).wall_s,
            stages_s: p.shared_s.max(p.slowest_s),
        });
    }
    Ok(fit_overheads(&runs, target.shares(0).1))
}

/// One render of the two-polygon scene, for the start-up's fit.
struct StartUp {
    processes: usize,
    pipes: usize,
    /// Its measured wall seconds.
    wall_s: f64,
    /// Its stages' predicted seconds, with no start-up costs.
    stages_s: f64,
}

/// The start-up's constants from renders at several depths on `all` cores' worth: the
/// wall time less the stages' is the script's, and each process's and each pipe's over
/// the cores. The depths tell the two apart because a splitter writes two or four pipes
/// (at depth 0 to 4: 3, 5, 7, 13 and 23 processes; 2, 5, 9, 19 and 37 pipes).
/// Non-negative least squares in relative terms, as the stages' ([`fit_relative`]): a
/// 5 ms render's millisecond counts as a 50 ms one's ten.
fn fit_overheads(runs: &[StartUp], all: f64) -> Overheads {
    let all = all.max(f64::MIN_POSITIVE);
    let rows: Vec<[f64; 6]> = runs
        .iter()
        .map(|r| {
            [
                1.0,
                r.processes as f64 / all,
                r.pipes as f64 / all,
                0.0,
                0.0,
                0.0,
            ]
        })
        .collect();
    let y: Vec<f64> = runs.iter().map(|r| r.wall_s - r.stages_s).collect();
    // Weighed by the measured wall time (what the chart's error is relative to), not the
    // remainder, which can be near 0.
    let weight = |r: &StartUp| if r.wall_s > 0.0 { 1.0 / r.wall_s } else { 1.0 };
    let scaled: Vec<[f64; 6]> = rows
        .iter()
        .zip(runs)
        .map(|(row, r)| row.map(|x| x * weight(r)))
        .collect();
    let ys: Vec<f64> = y.iter().zip(runs).map(|(y, r)| y * weight(r)).collect();
    let c = fit(&scaled, &ys, [true, true, true, false, false, false]);
    Overheads {
        script: c[0],
        process: c[1],
        pipe: c[2],
    }
}

/// Other programs' runnable threads on the cores now: the threads runnable at this
/// instant, as /proc/loadavg's fourth field counts them (`R/T`), less the one reading it
/// ([`load_now`]), or the 1-minute load average less one (the render's own stages, or
/// the runs before it, are in the average too) when that is less: the average alone
/// lags the machine by a minute (a render started when other programs' builds had just
/// ended planned for a load of 8 on an idle machine, and chose a deeper tree for it than
/// the idle machine's best), the count alone takes a thread runnable for a moment for a
/// load. Never below 0; 0 where there is no /proc/loadavg. On a machine shared with
/// others, a render gets only its share of the cores ([`crate::model::Target::shares`]);
/// on an idle one this is 0 and changes nothing. `POLYPIPE_LOAD=L` in the environment
/// sets it instead (what `--load L` does for `plan depth`, for a render whose choice
/// must not depend on what else the machine runs: the test suite's).
pub fn background_load() -> f64 {
    if let Some(l) = std::env::var("POLYPIPE_LOAD")
        .ok()
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|l| l.is_finite())
    {
        return l.max(0.0);
    }
    // Two reads 100 µs apart, the lesser kept: a thread runnable for a moment (a pipeline's
    // other end, a process exiting) is in one of them, a program holding a core in both.
    let read = || {
        std::fs::read_to_string("/proc/loadavg")
            .ok()
            .and_then(|s| load_now(&s))
    };
    let Some(first) = read() else { return 0.0 };
    std::thread::sleep(std::time::Duration::from_micros(100));
    read().map_or(first, |second| first.min(second))
}

/// The load in the text of /proc/loadavg (`0.52 0.41 0.30 3/210 4567`): the runnable
/// threads but the reader (3 runnable now, so 2), or the 1-minute average less one when
/// that is less (so 0 here), in whole threads: a fraction of one is no other program
/// holding a core but the renders that ran just before (a movie's frames, a benchmark's
/// rounds, one after another, keep the average near 1.5 on an idle 2-core machine, where
/// planning for a load of 0.6 chose depth 0 and depth 1 was 20% faster:
/// `target/bin/bench tree depth-auto --reps 21`).
pub fn load_now(loadavg: &str) -> Option<f64> {
    let mut fields = loadavg.split_whitespace();
    let average: f64 = fields.next()?.parse().ok()?;
    let (running, _) = fields.nth(2)?.split_once('/')?;
    let running: u32 = running.parse().ok()?;
    Some(
        f64::from(running.saturating_sub(1))
            .min((average - 1.0).max(0.0))
            .floor(),
    )
}

/// The CPU model and cores, and the date, for the constants file.
pub fn machine() -> String {
    let cpu = crate::cache::cpu_model();
    let days = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs() / 86400);
    format!("{cpu}, {} cores, day {days} since 1970", machine_cores())
}

/// The steps [`calibrate`] reports to its `tick`: a scene each, and the start-up fit.
pub fn steps(quick: bool) -> usize {
    grid(quick).len() + 2
}

/// Calibrates this machine and keeps the result in the cache ([`crate::cache`]), saying
/// how far it is on one line of stderr (`STAGE: calibrating the cost model for this
/// machine (at most 20 s): 3/9 …`, rewritten in place on a terminal; elsewhere said at
/// the start and at the end). `bin`: the binaries; `render`: the `render` binary, whose
/// start-up is what the chart measures and what `--depth auto` predicts for itself
/// (scripts/render.sh's shim adds its own bash start and freshness check, before render).
pub fn calibrate_and_store(
    stage: &str,
    bin: &Path,
    render: &Path,
    quick: bool,
) -> Result<(Constants, std::path::PathBuf)> {
    use std::io::{IsTerminal, Write};
    let work = std::env::temp_dir().join(format!("polypipe-calibration.{}", std::process::id()));
    std::fs::create_dir_all(&work).with_context(|| format!("cannot make {}", work.display()))?;
    let start = std::time::Instant::now();
    let tty = std::io::stderr().is_terminal();
    let total = steps(quick);
    let head = format!("{stage}: calibrating the cost model for this machine (at most 20 s)");
    if !tty {
        let _ = writeln!(std::io::stderr(), "{head}…");
    }
    let mut step = 0;
    let trace = std::env::var_os("POLYPIPE_CALIBRATION_TRACE").is_some();
    let result = calibrate(bin, render, &work, quick, |what| {
        step += 1;
        if trace {
            let _ = writeln!(
                std::io::stderr(),
                "{stage}: {:.2} s: {step}/{total} {what}",
                start.elapsed().as_secs_f64()
            );
        }
        if tty {
            let _ = write!(std::io::stderr(), "\r\x1b[K{head}: {step}/{total} {what}");
        }
    });
    let _ = std::fs::remove_dir_all(&work);
    let k = result?;
    let header = format!(
        "# The cost model's constants for this machine (costmodel/src/model.rs), seconds,\n\
         # fitted by `chart calibrate{}` in {:.1} s: each stage binary alone on synthetic\n\
         # scenes, least squares. `render.sh --depth auto`, `plan depth` and `chart` read it.\n",
        if quick { " --quick" } else { "" },
        start.elapsed().as_secs_f64()
    );
    let path = crate::cache::store(&k, &header)?;
    let done = format!(
        "{stage}: calibrated in {:.1} s: {}",
        start.elapsed().as_secs_f64(),
        path.display()
    );
    let _ = if tty {
        writeln!(std::io::stderr(), "\r\x1b[K{done}")
    } else {
        writeln!(std::io::stderr(), "{done}")
    };
    Ok((k, path))
}

/// The constants as a table, one stage a line, for `chart calibrate`'s report.
pub fn table(k: &Constants) -> String {
    let mut t = String::new();
    for (name, cost) in [
        ("viewxf (text)", k.viewxf_text),
        ("viewxf (binary)", k.viewxf_binary),
        ("clip", k.clip),
        ("splitter", k.splitter),
        ("persp", k.persp),
        ("hse", k.hse),
        ("merge", k.merge),
        ("resolve (depth 0)", k.resolve),
    ] {
        t += &format!(
            "{name:18} process {:.2e} s, polygon {:.2e}, span {:.2e}, pixel {:.2e}, screen pixel {:.2e}\n",
            cost.process, cost.polygon, cost.span, cost.pixel, cost.screen
        );
    }
    t += &format!(
        "{:18} script {:.4} s, each process {:.5} s, each pipe {:.5} s\n",
        "start-up", k.overheads.script, k.overheads.process, k.overheads.pipe
    );
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A stage of 2 ms a process and 1 µs a polygon, slower a polygon on the large scenes
    /// (its memory outgrows the caches: what a linear model cannot follow). The absolute
    /// fit over scenes of 1,000 to 30,000 polygons and the two-polygon run puts the
    /// constant where the large runs' line meets zero, and predicts the two polygons far
    /// off; the relative fit predicts every run within its error, the tiny one best.
    #[test]
    fn the_relative_fit_takes_the_start_up_from_the_tiny_run() {
        let polygons = [2.0, 1000.0, 8000.0, 30000.0, 2000.0];
        let rows: Vec<[f64; 6]> = polygons
            .iter()
            .map(|&p| [1.0, p, 0.0, 0.0, 0.0, 0.0])
            .collect();
        let y: Vec<f64> = polygons
            .iter()
            .map(|&p| 0.002 + 1e-6 * p + 5e-12 * p * p)
            .collect();
        let columns = [true, true, false, false, false, false];
        let errors = |c: [f64; 6]| -> Vec<f64> {
            rows.iter()
                .zip(&y)
                .map(|(r, &t)| ((c[0] + c[1] * r[1]) - t).abs() / t)
                .collect()
        };
        let (relative, absolute) = (
            errors(fit_relative(&rows, &y, columns)),
            errors(fit(&rows, &y, columns)),
        );
        let mean = |e: &[f64]| e.iter().sum::<f64>() / e.len() as f64;
        assert!(
            relative[0] < 0.05 && absolute[0] > 0.1,
            "{relative:?} {absolute:?}"
        );
        assert!(
            mean(&relative) < mean(&absolute),
            "{relative:?} {absolute:?}"
        );
        // Exact linear data: both give the constants back.
        let exact: Vec<f64> = polygons.iter().map(|&p| 0.002 + 1e-6 * p).collect();
        for c in [
            fit_relative(&rows, &exact, columns),
            fit(&rows, &exact, columns),
        ] {
            assert!(
                (c[0] - 0.002).abs() < 1e-9 && (c[1] - 1e-6).abs() < 1e-12,
                "{c:?}"
            );
        }
        // A run of no measurable time keeps its absolute weight: no division by zero.
        let c = fit_relative(&rows, &[0.0, 0.003, 0.01, 0.032, 0.004], columns);
        assert!(c.iter().all(|v| v.is_finite()), "{c:?}");
    }

    /// Renders of two polygons at depths 0 to 4 on 2 cores, timed as a script of 12 ms,
    /// 1.5 ms a process and 0.4 ms a pipe over the cores: the fit gives each back, the
    /// pipe's apart from the process's because the splitters' fan-out makes the pipes
    /// outgrow the processes. Without the pipe term the process's cost takes the pipes'
    /// and the deep trees are predicted off.
    #[test]
    fn the_start_up_fit_tells_a_pipe_from_a_process() {
        let k = Constants::default();
        let env = crate::look::Environment {
            frames: 1,
            polygons: 2,
            vertices: 8,
            relevant: 2,
            relevant_vertices: 8,
            area: 100.0,
            width: 500,
            height: 500,
            text: true,
        };
        let target = crate::model::Target::cores(2);
        let (script, process, pipe) = (0.012, 0.0015, 0.0004);
        let runs: Vec<StartUp> = (0..=4)
            .map(|d| {
                let p = crate::model::predict_on(&k, &env, d, &target);
                StartUp {
                    processes: p.processes,
                    pipes: p.pipes,
                    wall_s: script + (process * p.processes as f64 + pipe * p.pipes as f64) / 2.0,
                    stages_s: 0.0,
                }
            })
            .collect();
        let counts: Vec<(usize, usize)> = runs.iter().map(|r| (r.processes, r.pipes)).collect();
        assert_eq!(counts, [(3, 2), (5, 5), (7, 9), (13, 19), (23, 37)]);
        let o = fit_overheads(&runs, 2.0);
        assert!((o.script - script).abs() < 1e-9, "{o:?}");
        assert!((o.process - process).abs() < 1e-9, "{o:?}");
        assert!((o.pipe - pipe).abs() < 1e-9, "{o:?}");
        // Each run predicted back exactly, through the model's own sum.
        let mut fitted = k.clone();
        fitted.overheads = o;
        for (d, r) in (0..=4).zip(&runs) {
            let p = crate::model::predict_on(&fitted, &env, d, &target);
            assert!((p.total_s - r.wall_s).abs() < 1e-6, "depth {d}: {p:?}");
        }
        // Noise of a millisecond on the shallow runs keeps every cost non-negative.
        let mut noisy = runs;
        noisy[0].wall_s += 0.001;
        noisy[1].wall_s -= 0.001;
        let o = fit_overheads(&noisy, 2.0);
        assert!(
            o.script >= 0.0 && o.process >= 0.0 && o.pipe >= 0.0,
            "{o:?}"
        );
    }

    #[test]
    fn the_load_is_the_threads_runnable_now_but_the_reader() {
        assert_eq!(load_now("9.5 10.94 8.01 13/208 15186\n"), Some(8.0));
        assert_eq!(load_now("13.5 10.94 8.01 7/208 15186\n"), Some(6.0));
        // A machine whose builds have just ended: the average still says 9, the
        // runnable threads now are the reader alone.
        assert_eq!(load_now("9.11 11.22 9.72 1/102 8177"), Some(0.0));
        // A thread runnable for a moment on an idle machine is no load.
        assert_eq!(load_now("0.30 0.20 0.10 2/102 8177"), Some(0.0));
        // Renders one after another on an idle machine keep the average above 1: a
        // fraction of a thread is no program holding a core.
        assert_eq!(load_now("1.65 1.32 3.32 2/85 9120"), Some(0.0));
        assert_eq!(load_now("2.9 2.5 2.0 3/85 9120"), Some(1.0));
        assert_eq!(load_now("0.00 0.00 0.00 0/1 1"), Some(0.0));
        assert_eq!(load_now("0.5 0.4 0.3"), None);
        assert_eq!(load_now("0.5 0.4 0.3 x/9 1"), None);
    }
}
