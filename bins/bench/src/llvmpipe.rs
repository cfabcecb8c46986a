//! `bench llvmpipe`: polypipe against Mesa's llvmpipe, against its own fused run, and
//! against itself at splitter depths 0-4: one markdown table of ratios, every figure from
//! this one run.
//!
//! Every figure is the whole process's wall time (start to exit, reading the text scene
//! and writing the PPM frames to /dev/null), the median of REPS runs (default 5). The
//! commands run interleaved, one round of all of them per repetition, after one run each
//! not timed (the page cache warmed, the pictures kept for the last column). Beside each
//! A/B (the ratio of the medians) is the median of the rounds' own A/B ("by rounds").
//!
//! The scenes, `scene environment` as text: (a) 1,024 quads at 500x500; (b) 100,000
//! quads, Dc 2, 500x500; (c) 10,000 quads, Dc 10, 1920x1080 (the fill-heavy scene); (d) a
//! 100-frame movie of 1,024 quads at 500x500; (e) two polygons at 64x64
//! (examples/triangle-square.txt); (f) a large mesh at 500x500 (`--mesh FILE.obj`,
//! default Debian's assimp-testmodels WusonOBJ.obj; its row is skipped, saying so, when
//! the file is missing).
//!
//! The rows: render against the llvmpipe harness (bench/llvmpipe/render.c through OSMesa;
//! its rows read n/a without it) and the fused run (`fused`: one process chaining the same
//! stage libraries), then render --depth 0..4 on (c) with each merge mode, each against
//! depth 0 in the same mode. A second table gives render against llvmpipe by CPU seconds,
//! a third the work the tree adds: the CPU seconds of depths 0..4 on one core.
//! `--scaling` instead runs depths 0..6 on (c) on every core count from 1 to nproc.

use crate::kit::{cores, header, machine, q, row, Kit};
use crate::measure::{interleaved_with, median_of, median_ratio, ms, ratio, Figure, Usage};
use stagecli::{Error, Result};
use std::collections::BTreeMap;

/// The options of `bench llvmpipe`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Repetitions per command (median of N; default 5, or 3 with --quick).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub reps: Option<u32>,
    /// Smaller scenes (b: 20,000 quads; c: 2,000 quads at 960x540; d: 20 frames).
    #[arg(long)]
    pub quick: bool,
    /// Only the table of depths 0-6 against core counts 1..nproc.
    #[arg(long)]
    pub scaling: bool,
    /// The fill-heavy scene (c) with N quads at WxH instead.
    #[arg(long, num_args = 2, value_names = ["N", "WxH"])]
    pub fill: Vec<String>,
    /// The OBJ file of row (f).
    #[arg(long, default_value = "/usr/share/assimp/models/OBJ/WusonOBJ.obj")]
    pub mesh: String,
}

/// 1024 → "1,024".
pub fn commas(n: u64) -> String {
    let s = n.to_string();
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

struct Scene {
    key: &'static str,
    size: String,
    label: String,
    file: String,
}

/// Runs `bench llvmpipe`.
pub fn main(a: &Args) -> Result<()> {
    let k = Kit::new()?;
    let reps = a.reps.map_or(if a.quick { 3 } else { 5 }, |r| r as usize);
    let (geo_n, mut fill_n, mut fill_size, frames) = if a.quick {
        (20_000u64, 2000u64, "960x540".to_string(), 20)
    } else {
        (100_000, 10_000, "1920x1080".to_string(), 100)
    };
    if let [n, size] = a.fill.as_slice() {
        fill_n = n
            .parse()
            .map_err(|_| Error::usage(format!("--fill needs a count, not '{n}'")))?;
        proto::numbers::parse_size(size).map_err(|e| Error::usage(format!("--fill: {e}")))?;
        fill_size = size.clone();
    }
    eprintln!("bench: generating the scenes");
    let mut scenes = vec![
        Scene {
            key: "env",
            size: "500x500".into(),
            label: "(a) 1,024 quads, 500×500".into(),
            file: k.scene("env.txt", "environment --text --seed 1 --polygons 1024 --size 500x500")?,
        },
        Scene {
            key: "geo",
            size: "500x500".into(),
            label: format!("(b) {} quads, Dc≈2, 500×500", commas(geo_n)),
            file: k.scene(
                "geo.txt",
                &format!("environment --text --seed 3 --polygons {geo_n} --depth-complexity 2 --size 500x500"),
            )?,
        },
        Scene {
            key: "fill",
            size: fill_size.clone(),
            label: format!("(c) {} quads, Dc≈10, {}", commas(fill_n), fill_size.replace('x', "×")),
            file: k.fill_scene("fill.txt", fill_n as usize, &fill_size)?,
        },
        Scene {
            key: "movie",
            size: "500x500".into(),
            label: format!("(d) 1,024 quads × {frames} frames, 500×500"),
            file: k.scene(
                "movie.txt",
                &format!("environment --text --seed 4 --polygons 1024 --frames {frames} --size 500x500"),
            )?,
        },
        Scene {
            key: "two",
            size: "64x64".into(),
            label: "(e) two polygons, 64×64".into(),
            file: k.r("examples/triangle-square.txt"),
        },
    ];
    if a.scaling {
        return scaling(&k, reps, &scenes[2]);
    }
    let mesh = std::path::Path::new(&a.mesh);
    match k.scene("mesh.txt", &format!("obj --shade --text {}", q(&a.mesh))) {
        Ok(file) if mesh.is_file() => {
            let text = std::fs::read_to_string(mesh).unwrap_or_default();
            let faces = text.lines().filter(|l| l.trim_start().starts_with("f ")).count();
            let name = mesh.file_name().map_or(a.mesh.clone(), |n| n.to_string_lossy().into_owned());
            scenes.push(Scene {
                key: "mesh",
                size: "500x500".into(),
                label: format!("(f) {name}, {} faces, 500×500", commas(faces as u64)),
                file,
            });
        }
        _ => eprintln!(
            "bench: no large mesh at {} (apt-get install assimp-testmodels, or --mesh FILE.obj): row (f) skipped",
            a.mesh
        ),
    }
    let gl = k
        .out(&format!("{} 2>/dev/null", k.r("bench/llvmpipe/build.sh")))
        .ok()
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty());
    if gl.is_none() {
        eprintln!("bench: no llvmpipe harness; its rows will read n/a");
    }
    let fused = k.bin.join("fused").is_file().then(|| k.b("fused"));
    // The commands, by name.
    let mut jobs: Vec<(String, String)> = Vec::new();
    for s in &scenes {
        let args = format!("--size {} {}", s.size, s.file);
        jobs.push((format!("pipe.{}", s.key), k.render(&args)));
        if let Some(gl) = &gl {
            jobs.push((format!("gl.{}", s.key), format!("{} {args}", q(gl))));
        }
        if let Some(f) = &fused {
            jobs.push((format!("fused.{}", s.key), format!("{f} {args}")));
        }
    }
    let fill = &scenes[2];
    for m in ["tiles", "buffer"] {
        for d in 0..=4 {
            jobs.push((
                format!("depth.{m}.{d}"),
                k.render(&format!(
                    "--size {} --depth {d} --merge {m} {}",
                    fill.size, fill.file
                )),
            ));
        }
    }
    for d in 0..=4 {
        jobs.push((
            format!("one.{d}"),
            format!(
                "taskset -c 0 {}",
                k.render(&format!("--size {} --depth {d} {}", fill.size, fill.file))
            ),
        ));
    }
    // Warm-up: every command once, its pictures kept; a failure is reported and its rows
    // read n/a (render failing stops the run: nothing to compare).
    eprintln!("bench: warming up ({} commands)", jobs.len());
    let mut pictures: BTreeMap<String, Vec<u8>> = BTreeMap::new();
    let mut ok = Vec::new();
    for (name, line) in &jobs {
        let out = k.work(&format!("out.{name}"));
        match k.out(&format!("{line} > {}", q(&out.display().to_string()))) {
            Ok(_) => {
                pictures.insert(name.clone(), std::fs::read(&out).unwrap_or_default());
                ok.push((name.clone(), line.clone()));
            }
            Err(e) if name.starts_with("pipe.") => return Err(e),
            Err(e) => eprintln!("bench: {name} failed: {e}"),
        }
    }
    let runs = interleaved_with(reps, ok.len(), |i| crate::measure::run(&ok[i].1))?;
    let by: BTreeMap<&str, &[Usage]> = ok
        .iter()
        .zip(&runs)
        .map(|((n, _), r)| (n.as_str(), r.as_slice()))
        .collect();
    let differ = |a: &str, b: &str| -> String {
        let (Some(pa), Some(pb)) = (pictures.get(a), pictures.get(b)) else {
            return "n/a".into();
        };
        if pa == pb {
            return "identical".into();
        }
        let (fa, fb) = (k.w(&format!("out.{a}")), k.w(&format!("out.{b}")));
        match k.differing(&fa, &fb) {
            Ok((d, px)) => format!("{} of {} px differ", commas(d), commas(px)),
            Err(_) => "frames differ".into(),
        }
    };
    let line = |what: &str, label: &str, a: &str, b: &str, check: String| {
        let (ta, tb) = (by.get(a), by.get(b));
        let cell =
            |t: Option<&&[Usage]>| t.map_or("n/a".into(), |r| ms(median_of(r, Figure::Wall)));
        let (q, rounds) = match (ta, tb) {
            (Some(x), Some(y)) => (
                ratio(median_of(x, Figure::Wall), median_of(y, Figure::Wall)),
                format!("{:.2}", median_ratio(x, y, Figure::Wall)),
            ),
            _ => ("n/a".into(), "n/a".into()),
        };
        row(&[
            what.into(),
            label.into(),
            cell(ta),
            cell(tb),
            format!("**{q}**"),
            rounds,
            check,
        ]);
    };
    let mesa = gl
        .as_ref()
        .and_then(|g| k.out(&format!("{} --renderer", q(g))).ok())
        .map_or("n/a".into(), |s| s.trim().to_string());
    println!();
    println!(
        "Measured by `bench llvmpipe{}` on {}: whole-process wall seconds, median of {reps}, \
         from one run. A/B below 1 means A is faster. llvmpipe: {mesa}, through OSMesa, \
         reading the same text scene (bench/llvmpipe/render.c).",
        if a.quick { " --quick" } else { "" },
        machine()
    );
    println!();
    header(&[
        "A against B",
        "scene",
        "A s",
        "B s",
        "A/B",
        "by rounds",
        "pictures",
    ]);
    for s in &scenes {
        let (p, g) = (format!("pipe.{}", s.key), format!("gl.{}", s.key));
        line("render against llvmpipe", &s.label, &p, &g, differ(&p, &g));
    }
    for s in &scenes {
        let (p, f) = (format!("pipe.{}", s.key), format!("fused.{}", s.key));
        line("render against fused run", &s.label, &p, &f, differ(&p, &f));
    }
    for m in ["tiles", "buffer"] {
        for d in 0..=4 {
            let (a, b) = (format!("depth.{m}.{d}"), format!("depth.{m}.0"));
            let check = format!("{} to tiles depth 0", differ(&a, "depth.tiles.0"));
            line(
                &format!("depth {d} against depth 0, `--merge {m}`"),
                &fill.label,
                &a,
                &b,
                check,
            );
        }
    }
    println!();
    println!(
        "The same runs by CPU: user + system seconds of the whole process tree (llvmpipe's \
         threads counted), median of {reps}."
    );
    println!();
    header(&[
        "A against B",
        "scene",
        "A CPU s",
        "B CPU s",
        "A/B",
        "by rounds",
    ]);
    let cpu = |n: &str| by.get(n).map(|r| median_of(r, Figure::Cpu));
    let rounds = |a: &str, b: &str| match (by.get(a), by.get(b)) {
        (Some(x), Some(y)) => format!("{:.2}", median_ratio(x, y, Figure::Cpu)),
        _ => "-".into(),
    };
    for s in &scenes {
        let (p, g) = (format!("pipe.{}", s.key), format!("gl.{}", s.key));
        let (ca, cb) = (cpu(&p), cpu(&g));
        row(&[
            "render against llvmpipe".into(),
            s.label.clone(),
            ca.map_or("n/a".into(), ms),
            cb.map_or("n/a".into(), ms),
            format!("**{}**", ratio(ca.unwrap_or(0.0), cb.unwrap_or(0.0))),
            rounds(&p, &g),
        ]);
    }
    println!();
    println!(
        "The work the tree adds: render --depth D on {}, all on one core (`taskset -c 0`), \
         CPU seconds (user + system of the whole process tree), median of {reps}.",
        fill.label
    );
    println!();
    header(&["depth", "CPU s", "against depth 0", "by rounds"]);
    let base = cpu("one.0").unwrap_or(0.0);
    for d in 0..=4 {
        let n = format!("one.{d}");
        let t = cpu(&n);
        row(&[
            d.to_string(),
            t.map_or("n/a".into(), ms),
            format!("**{}**", ratio(t.unwrap_or(0.0), base)),
            rounds(&n, "one.0"),
        ]);
    }
    Ok(())
}

fn scaling(k: &Kit, reps: usize, fill: &Scene) -> Result<()> {
    let n = cores();
    let mut lines = Vec::new();
    for c in 1..=n {
        for d in 0..=6 {
            lines.push(format!(
                "taskset -c 0-{} {}",
                c - 1,
                k.render(&format!("--size {} --depth {d} {}", fill.size, fill.file))
            ));
        }
    }
    let runs = interleaved_with(reps, lines.len(), |i| crate::measure::run(&lines[i]))?;
    println!();
    println!(
        "Measured by `bench llvmpipe --scaling` on {}: render --depth D on {} under \
         `taskset -c 0-(N-1)`, whole-process wall seconds, median of {reps}, from one run; \
         speed-up against depth 0 on one core.",
        machine(),
        fill.label
    );
    println!();
    let mut head = vec!["cores".to_string()];
    head.extend((0..=6).map(|d| format!("depth {d} s (speed-up)")));
    header(&head.iter().map(String::as_str).collect::<Vec<_>>());
    let base = median_of(&runs[0], Figure::Wall);
    for c in 1..=n {
        let mut cells = vec![c.to_string()];
        for d in 0..=6 {
            let t = median_of(&runs[(c - 1) * 7 + d], Figure::Wall);
            cells.push(format!("{} ({})", ms(t), ratio(base, t)));
        }
        row(&cells);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn commas_group_thousands() {
        assert_eq!(super::commas(1024), "1,024");
        assert_eq!(super::commas(100000), "100,000");
        assert_eq!(super::commas(12), "12");
        assert_eq!(super::commas(1234567), "1,234,567");
    }
}
