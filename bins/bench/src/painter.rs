//! `bench painter`: the depth sort (`painter`, with and without --split) and the hidden
//! lines (`hiddenline`) against the z-buffer leaf (`scanconv --resolve`), each leaf
//! alone: the screen-space stream of a scene (500x500, made once) in, its output to
//! /dev/null.
//!
//! Scenes: the thesis's penetrating scene and its test environment (chapter 5.2) of
//! 1,000, 10,000 and 100,000 polygons at Dc 3. Per scene and method: the least wall
//! seconds of N runs (default 5), the peak resident KiB of one more, and for the painter
//! the pixels unlike the z-buffer's frame and, from --stats, the cycles it met and those
//! it painted out of order (Newell, Newell and Sancha's depth sort, as Sutherland,
//! Sproull and Schumacker describe it).
//!
//! `--hostile`: `scene stack`, `slivers`, `pinhead`, `strips` and `planes`, every leaf
//! under `timeout 120`: the least wall seconds of N (default 3), peak MB, both over the
//! z-buffer's, and for the painter the pixels unlike the z-buffer's and whether it said
//! it could not order the polygons.

use crate::kit::{header, method_leaf, row, Kind, Kit};
use crate::measure::{self, best_of, ms, ratio, Figure};
use stagecli::Result;

/// The options of `bench painter`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The hostile scenes instead.
    #[arg(long)]
    pub hostile: bool,
    /// Runs of each command (default 5, --hostile 3).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub reps: Option<u32>,
    /// A tenth of the polygons and one run each: a check that it works.
    #[arg(long)]
    pub quick: bool,
}

/// `LINE` under `timeout 120`: `None` when the time ran out.
pub fn over(line: &str, f: impl FnOnce(&str) -> Result<f64>) -> Result<Option<f64>> {
    match f(&format!("timeout 120 {line}")) {
        Ok(t) => Ok(Some(t)),
        Err(e) if e.message().contains("failed with status 124") => Ok(None),
        Err(e) => Err(e),
    }
}

/// The frame the leaf `leaf` (a bash line) draws from `input`, merged by zbuf, into the
/// scratch file `name`; the leaf's stderr.
pub fn frame(k: &Kit, input: &str, leaf: &str, name: &str) -> Result<String> {
    let err = k.w(&format!("{name}.err"));
    k.make(
        name,
        &format!("{leaf} < {input} 2> {err} | {}", k.b("zbuf")),
    )?;
    Ok(std::fs::read_to_string(k.work(&format!("{name}.err"))).unwrap_or_default())
}

/// Runs `bench painter`.
pub fn main(a: &Args) -> Result<()> {
    let k = Kit::new()?;
    let reps = a.reps.map_or(
        if a.quick {
            1
        } else if a.hostile {
            3
        } else {
            5
        },
        |r| r as usize,
    );
    let d = if a.quick { 10 } else { 1 };
    println!(
        "{} Each leaf alone, 500x500, the least wall seconds of {reps}.",
        crate::kit::stamp(&format!(
            "painter{}",
            if a.hostile { " --hostile" } else { "" }
        ))
    );
    println!();
    let zbuf = method_leaf(Kind::Hse, "zbuf")?;
    let painter = method_leaf(Kind::Hse, "painter")?;
    let lines = method_leaf(Kind::Lines, "hiddenline")?;
    let abuf = method_leaf(Kind::Aa, "abuf")?;
    let peak =
        |line: &str| -> Result<u64> { Ok(measure::run(&format!("exec {line}"))?.max_rss_kib) };
    if !a.hostile {
        let mut scenes = vec![(
            "penetrating".to_string(),
            k.screen("penetrating", "penetrating", "500x500")?,
        )];
        for n in [1000 / d, 10000 / d, 100000 / d] {
            let name = format!("env{n}");
            let args = format!("environment --polygons {n} --depth-complexity 3 --seed 4");
            scenes.push((name.clone(), k.screen(&name, &args, "500x500")?));
        }
        header(&[
            "scene",
            "method",
            "wall s",
            "peak KiB",
            "pixels ≠ zbuf",
            "cycles",
            "painted out of order",
        ]);
        for (scene, input) in &scenes {
            frame(&k, input, &k.leaf(&zbuf), "z.ppm")?;
            for method in [
                zbuf.clone(),
                painter.clone(),
                format!("{painter} --split"),
                lines.clone(),
            ] {
                eprintln!("bench: {scene}, {method}");
                let line = format!("{} < {input}", k.leaf(&method));
                let t = best_of(reps, &line, Figure::Wall)?;
                let kib = peak(&line)?;
                let (mut differ, mut cycles, mut out_of_order) =
                    ("—".to_string(), "—".to_string(), "—".to_string());
                if method.starts_with(&painter) {
                    let stats = frame(&k, input, &format!("{} --stats", k.leaf(&method)), "m.ppm")?;
                    differ = k.differing(&k.w("z.ppm"), &k.w("m.ppm"))?.0.to_string();
                    cycles = crate::kit::stat_count(&stats, "cycles,")?.to_string();
                    out_of_order =
                        crate::kit::stat_count(&stats, "cycles painted out of order")?.to_string();
                }
                row(&[
                    scene.clone(),
                    method,
                    ms(t),
                    kib.to_string(),
                    differ,
                    cycles,
                    out_of_order,
                ]);
            }
        }
        return Ok(());
    }
    header(&[
        "scene, 500x500",
        "method",
        "wall s",
        "peak MB",
        "time / zbuf",
        "memory / zbuf",
        "pixels ≠ zbuf",
        "said it could not order",
    ]);
    let scenes = [
        format!("stack {}", 20000 / d),
        format!("slivers {}", 10000 / d),
        format!("pinhead {}", 100000 / d),
        format!("strips {}", 3000 / d),
        format!("stack {}", 2000 / d),
        format!("planes {}", 2000 / d),
        "planes 5".into(),
        "planes 50".into(),
        format!("planes {}", 400 / d),
    ];
    for scene in scenes {
        let input = k.screen(&scene.replace(' ', "-"), &scene, "500x500")?;
        frame(&k, &input, &k.leaf(&zbuf), "z.ppm")?;
        let mut base: Option<(f64, u64)> = None;
        for method in [
            zbuf.clone(),
            painter.clone(),
            format!("{painter} --split"),
            abuf.clone(),
        ] {
            eprintln!("bench: {scene}, {method}");
            let line = format!("{} < {input}", k.leaf(&method));
            let Some(t) = over(&line, |l| best_of(reps, l, Figure::Wall))? else {
                row(&[
                    scene.clone(),
                    method,
                    "over 120".into(),
                    "—".into(),
                    "—".into(),
                    "—".into(),
                    "—".into(),
                    "—".into(),
                ]);
                continue;
            };
            let kib = peak(&line)?;
            let (zt, zk) = *base.get_or_insert((t, kib));
            let (mut differ, mut said) = ("—".to_string(), "—".to_string());
            if method.starts_with(&painter) {
                let err = frame(&k, &input, &k.leaf(&method), "m.ppm")?;
                differ = k.differing(&k.w("z.ppm"), &k.w("m.ppm"))?.0.to_string();
                said = if err.contains("could not order") {
                    "yes"
                } else {
                    "no"
                }
                .into();
            }
            row(&[
                scene.clone(),
                method,
                ms(t),
                (kib / 1024).to_string(),
                ratio(t, zt),
                ratio(kib as f64, zk as f64),
                differ,
                said,
            ]);
        }
    }
    Ok(())
}
