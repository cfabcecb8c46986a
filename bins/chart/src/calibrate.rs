//! `chart --calibrate`: the model's constants measured on this machine. Each stage binary
//! is run alone on the streams of synthetic scenes (`scene environment`, the thesis's
//! test environment of 5.2, over a grid of polygon counts, screens and depth
//! complexities), reading a file and writing a file, and its CPU seconds are fitted by
//! least squares ([`crate::model::fit`]) to its work in the model's terms. The
//! script's and each process's start-up are then fitted to `render.sh`'s wall time on a
//! two-polygon scene at depths 0 to 4, less what the stages predict there.

use crate::look::{count_screen, count_world, Environment};
use crate::measure::{self, Usage};
use crate::model::{fit, predict, stage_work, Constants, Cost, Overheads, StageWork, Work};
use anyhow::{Context, Result};
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
        Cost::from_coefficients(fit(&self.rows, &self.seconds, columns))
    }
}

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

/// The synthetic scenes: (polygons, width, height, depth complexity).
pub fn grid(quick: bool) -> Vec<(u64, u32, u32, f64)> {
    let (ps, sizes, dcs): (&[u64], &[(u32, u32)], &[f64]) = if quick {
        (&[500, 4000], &[(300, 300), (800, 600)], &[1.0, 6.0])
    } else {
        (
            &[1000, 8000, 40000],
            &[(400, 400), (1280, 720)],
            &[1.0, 8.0],
        )
    };
    let mut g = Vec::new();
    for &p in ps {
        for &(w, h) in sizes {
            for &dc in dcs {
                g.push((p, w, h, dc));
            }
        }
    }
    g
}

/// Measures the stages and fits the constants. `tick` is called after each scene.
pub fn calibrate(
    bin: &Path,
    render: &Path,
    work: &Path,
    quick: bool,
    mut tick: impl FnMut(&str),
) -> Result<Constants> {
    let reps = if quick { 1 } else { 3 };
    let [mut vt, mut vb, mut clip, mut split, mut persp, mut hse, mut merge, mut resolve] =
        std::array::from_fn(|_| Samples::default());
    let f = |n: &str| work.join(n);
    for (i, &(p, w, h, dc)) in grid(quick).iter().enumerate() {
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
        } = stage_work(&env);
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
    tick("render.sh on two polygons, depths 0-4");
    k.overheads = overheads(bin, render, work, &k, if quick { 3 } else { 5 })?;
    Ok(k)
}

/// The script's and the processes' start-up: `render.sh` on two polygons at depths 0-4
/// (wall seconds, median of `reps`) less the stages' predicted time, fitted to
/// script + process × processes.
fn overheads(
    bin: &Path,
    render: &Path,
    work: &Path,
    k: &Constants,
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
    let mut rows = Vec::new();
    let mut y = Vec::new();
    for d in 0..=4u8 {
        let mut runs: Vec<Usage> = Vec::new();
        for _ in 0..reps {
            runs.push(measure::run(
                Command::new(render)
                    .args(["--size", "500x500", "--depth", &d.to_string()])
                    .arg(&scene)
                    .stdout(Stdio::null())
                    .stderr(Stdio::null()),
            )?);
        }
        let wall = measure::median(&runs).wall_s;
        let p = predict(k, &env, d, cores);
        rows.push([1.0, p.processes as f64, 0.0, 0.0, 0.0, 0.0]);
        y.push(wall - p.slowest_s.max(p.shared_s));
    }
    let c = fit(&rows, &y, [true, true, false, false, false, false]);
    Ok(Overheads {
        script: c[0],
        process: c[1],
    })
}

/// The machine's cores (what the standard library sees as available).
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The CPU model and cores, and the date, for the constants file.
pub fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| "an unknown CPU".into());
    let days = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs() / 86400);
    format!("{cpu}, {} cores, day {days} since 1970", cores())
}
