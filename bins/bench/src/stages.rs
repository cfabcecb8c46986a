//! `bench stages MODE`: the stages and the stream between them, one mode a run.
//!
//! - `geometry`: polygons per second of viewxf, clipplane ×6, splitter and persp, binary
//!   to binary, file to /dev/null, best of REPS (default 3), on N quads of side ~1
//!   scattered over x, y ∈ [−13, 13], z ∈ [−8, 8] (a realistic share cut by the side
//!   planes), written as text and put in the binary form by `frames`. Target: every
//!   stage ≥ 2 million/s.
//! - `clip`: clipbatch (Theoharis & Page's batch clipper) against the six-process chain
//!   and the paper's DAP figure of 25,000 polygons a second (Theoharis & Page 1989,
//!   §4.3), median of REPS (5), on an `environment` scene (nothing cut) and a cut-heavy
//!   one (large polygons seen with s = 5), outputs checked against the chain's first.
//! - `codec`: the stream codec in memory (proto's example codec_bench), the text form
//!   through viewxf, and the geometry table.
//! - `fused`: render against the same stage libraries in one process (`fused`), and the
//!   same processes as one pipe line, median of REPS (5), frames checked first.
//! - `fill`: zbuf's depth tests per CPU second on the fill-heavy scene's screen stream,
//!   median of REPS (9), against `--base ZBUF` interleaved; then scan's example ztest.
//! - `shading`: flat, Gouraud and Phong shading of one sphere: zbuf's CPU and render's,
//!   median of REPS (9) interleaved, and each frame's error against Phong's.

use crate::kit::{header, row, Kit};
use crate::measure::{self, best_of, interleaved, median_of, ms, ratio, Figure};
use stagecli::{Error, Result};

/// The options of `bench stages`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// geometry, clip, codec, fused, fill or shading.
    #[arg(value_enum)]
    pub mode: Mode,
    /// Polygons: geometry and clip 1000000, codec 200000.
    #[arg(long)]
    pub polygons: Option<usize>,
    /// Repetitions (geometry 3, clip, codec and fused 5, fill and shading 9).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub reps: Option<u32>,
    /// Scenes of a hundredth the polygons, to try a mode out.
    #[arg(long)]
    pub quick: bool,
    /// fill: another zbuf to measure beside this one.
    #[arg(long, value_name = "ZBUF")]
    pub base: Option<String>,
}

/// The modes of `bench stages`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    Geometry,
    Clip,
    Codec,
    Fused,
    Fill,
    Shading,
}

/// Runs `bench stages`.
pub fn main(a: &Args) -> Result<()> {
    let k = Kit::new()?;
    let n = |full: usize| if a.quick { (full / 100).max(10) } else { full };
    let reps = |d: u32| a.reps.unwrap_or(d) as usize;
    match a.mode {
        Mode::Geometry => geometry(&k, a.polygons.unwrap_or(n(1_000_000)), reps(3)),
        Mode::Clip => clip(&k, a.polygons.unwrap_or(n(1_000_000)), reps(5)),
        Mode::Codec => codec(&k, a.polygons.unwrap_or(n(200_000)), reps(5), &n),
        Mode::Fused => fused(&k, reps(5), &n),
        Mode::Fill => fill(&k, reps(9), a.base.as_deref(), &n),
        Mode::Shading => shading(&k, reps(9), a.quick),
    }
}

/// `n` quads of side ~1 scattered over x, y ∈ [−13, 13], z ∈ [−8, 8], as a text world
/// scene (`frames` writes it in the binary form), from a fixed seed.
pub fn quads(n: usize) -> String {
    use std::fmt::Write;
    let mut out = String::from("polypipe 1 world\n");
    let mut state: u64 = 1985;
    let mut uniform = |lo: f64, hi: f64| {
        // xorshift64*: a fixed, portable sequence.
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        let x = state.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        lo + (hi - lo) * (x as f64 / (1u64 << 53) as f64)
    };
    for i in 0..n {
        let (cx, cy, cz) = (
            uniform(-13.0, 13.0),
            uniform(-13.0, 13.0),
            uniform(-8.0, 8.0),
        );
        if i > 0 {
            out.push_str("NEXT.POLYGON\n");
        }
        let _ = writeln!(
            out,
            "colour {} {} {}",
            i * 37 % 256,
            i * 101 % 256,
            i * 59 % 256
        );
        for [x, y, z] in [
            [cx - 0.5, cy - 0.5, cz],
            [cx + 0.5, cy - 0.4, cz + 0.1],
            [cx + 0.4, cy + 0.5, cz],
            [cx - 0.5, cy + 0.4, cz - 0.1],
        ] {
            let _ = writeln!(out, "{x} {y} {z}");
        }
    }
    out.push_str("END\n");
    out
}

fn write(k: &Kit, name: &str, bytes: &[u8]) -> Result<String> {
    std::fs::write(k.work(name), bytes).map_err(|e| Error::io(format!("{name}: {e}")))?;
    Ok(k.w(name))
}

fn size_of(k: &Kit, name: &str) -> u64 {
    std::fs::metadata(k.work(name)).map_or(0, |m| m.len())
}

fn geometry(k: &Kit, n: usize, reps: usize) -> Result<()> {
    let text = write(k, "world.txt", quads(n).as_bytes())?;
    k.make("world.bin", &format!("{} < {text}", k.b("frames")))?;
    let world = k.w("world.bin");
    k.make("eye.bin", &format!("{} < {world}", k.b("viewxf")))?;
    let eye = k.w("eye.bin");
    let clipped = k.w("clipped.bin");
    k.make("clipped.bin", &format!("< {eye} {}", k.clip()))?;
    println!(
        "input sizes: world {} B, eye {} B, clipped {} B",
        size_of(k, "world.bin"),
        size_of(k, "eye.bin"),
        size_of(k, "clipped.bin")
    );
    println!(
        "{:<16} {:>10} {:>9} {:>14}",
        "stage", "polygons", "seconds", "polygons/s"
    );
    let bench = |name: &str, line: String| -> Result<()> {
        let t = best_of(reps, &line, Figure::Wall)?;
        println!("{name:<16} {n:>10} {t:>9.3} {:>14.0}", n as f64 / t);
        Ok(())
    };
    bench("viewxf", format!("{} < {world}", k.b("viewxf")))?;
    for plane in ["left", "right", "top", "bottom", "hither", "yon"] {
        bench(
            &format!("clipplane {plane}"),
            format!("{} {plane} < {eye}", k.b("clipplane")),
        )?;
    }
    // The root node of a splitter tree, both outputs to /dev/null.
    bench(
        "splitter x=0",
        format!("{} x=0 /dev/null /dev/null < {clipped}", k.b("splitter")),
    )?;
    bench(
        "persp",
        format!("{} --size 500x500 < {clipped}", k.b("persp")),
    )?;
    bench(
        "persp eye-z",
        format!("{} --size 500x500 --zmode eye-z < {clipped}", k.b("persp")),
    )?;
    // The whole chain as the thesis wires it: 8 processes on this machine's cores.
    bench(
        "chain (8 procs)",
        format!(
            "{} < {world} | {} | {} --size 500x500",
            k.b("viewxf"),
            k.clip(),
            k.b("persp")
        ),
    )
}

fn clip(k: &Kit, n: usize, reps: usize) -> Result<()> {
    k.make(
        "environment.eye",
        &format!(
            "{} environment --polygons {n} --clipped 0.5 --depth-complexity 1 --seed 1985 | {}",
            k.b("scene"),
            k.b("viewxf")
        ),
    )?;
    k.make(
        "cut-heavy.eye",
        &format!(
            "{} environment --polygons {n} --clipped 0.5 --depth-complexity {} --seed 1985 | {} --s 5",
            k.b("scene"),
            (n / 10).max(1),
            k.b("viewxf")
        ),
    )?;
    println!("clipping {n} four-vertex polygons, binary to binary, median of {reps} (wall and CPU seconds)");
    println!();
    println!(
        "| {:<11} | {:<24} | {:>6} | {:>6} | {:>10} | {:>10} | {:>13} | {:>12} | {:>6} |",
        "scene",
        "clipper",
        "wall",
        "cpu",
        "polygons/s",
        "per cpu-s",
        "÷ chain, wall",
        "÷ chain, cpu",
        "÷ DAP"
    );
    println!("|-------------|--------------------------|--------|--------|------------|------------|---------------|--------------|--------|");
    for scene in ["environment", "cut-heavy"] {
        let input = k.w(&format!("{scene}.eye"));
        let chain = k.bytes(&format!("< {input} {}", k.clip()))?;
        for b in [1024, 4096] {
            if k.bytes(&format!("{} --batch {b} < {input}", k.b("clipbatch")))? != chain {
                return Err(Error::data(format!(
                    "clipbatch --batch {b} differs from the chain on {scene}"
                )));
            }
        }
        let rows = [
            ("chain (6 x clipplane)", format!("< {input} {}", k.clip())),
            (
                "clipbatch --batch 1024",
                format!("{} --batch 1024 < {input}", k.b("clipbatch")),
            ),
            (
                "clipbatch --batch 4096",
                format!("{} --batch 4096 < {input}", k.b("clipbatch")),
            ),
            (
                "clipplane left (1 plane)",
                format!("{} left < {input}", k.b("clipplane")),
            ),
        ];
        let mut base = None;
        for (name, line) in rows {
            let runs: Vec<_> = (0..reps)
                .map(|_| measure::run(&line))
                .collect::<Result<_>>()?;
            let (wall, cpu) = (
                median_of(&runs, Figure::Wall),
                median_of(&runs, Figure::Cpu),
            );
            let (rate, cpu_rate) = (n as f64 / wall, n as f64 / cpu.max(1e-3));
            let (r0, c0) = *base.get_or_insert((rate, cpu_rate));
            println!(
                "| {scene:<11} | {name:<24} | {wall:>6.2} | {cpu:>6.2} | {rate:>10.0} | {cpu_rate:>10.0} | {:>13.2} | {:>12.2} | {:>6.0} |",
                rate / r0,
                cpu_rate / c0,
                rate / 25000.0
            );
        }
    }
    println!();
    println!("per cpu-s: polygons per CPU second (user + system of every process), the figure that a busy");
    println!(
        "machine disturbs least. ÷ DAP: polygons/s (wall) over the paper's 25,000/s (the 64×64 ICL"
    );
    println!("DAP in DAP Fortran, §4.3).");
    Ok(())
}

/// Builds `cargo ARGS` in the repository (an example the benchmark runs).
fn cargo(k: &Kit, args: &str) -> Result<()> {
    k.out(&format!(
        "cd {} && cargo {args} --release --quiet >&2",
        k.r(".")
    ))
    .map(drop)
}

fn codec(k: &Kit, n: usize, reps: usize, count: &dyn Fn(usize) -> usize) -> Result<()> {
    cargo(k, "build -p proto --example codec_bench")?;
    let scene = k.scene(
        "scene.txt",
        &format!(
            "environment --polygons {} --depth-complexity 2 --seed 1 --text",
            count(100_000)
        ),
    )?;
    let bytes = size_of(k, "scene.txt");
    println!(
        "## 1-2. Codec in one process ({n} polygons; text: scene environment --polygons {})",
        count(100_000)
    );
    println!();
    print!(
        "{}",
        k.out(&format!(
            "{} {n} {reps} {scene}",
            k.b("examples/codec_bench")
        ))?
    );
    println!();
    println!("## 3. Text through a stage: viewxf < scene.txt > /dev/null ({bytes} bytes, best of {reps})");
    println!();
    let t = best_of(reps, &format!("{} < {scene}", k.b("viewxf")), Figure::Wall)?;
    header(&["stage", "wall s", "MB/s"]);
    row(&[
        "viewxf (text in, binary out)".into(),
        ms(t),
        format!("{:.0}", if t > 0.0 { bytes as f64 / t / 1e6 } else { 0.0 }),
    ]);
    println!();
    let g = count(1_000_000);
    println!("## 4. Geometry stages, binary to binary (bench stages geometry --polygons {g} --reps {reps})");
    println!();
    println!("```");
    geometry(k, g, reps)?;
    println!("```");
    Ok(())
}

fn fused(k: &Kit, reps: usize, count: &dyn Fn(usize) -> usize) -> Result<()> {
    let scenes = [
        (
            "environment",
            "500x500",
            format!(
                "--polygons {} --depth-complexity 2 --seed 1",
                count(100_000)
            ),
        ),
        (
            "fill-heavy",
            "1920x1080",
            format!(
                "--polygons {} --depth-complexity 10 --size 1920x1080 --seed 2",
                count(10_000)
            ),
        ),
    ];
    println!(
        "render against the same stages in one process: median of {reps}, wall and CPU seconds"
    );
    println!("(user + system of every process); ratios over fused (six planes) in the same scene and form");
    println!();
    header(&[
        "scene",
        "form",
        "run",
        "wall s",
        "cpu s",
        "wall ÷ fused",
        "cpu ÷ fused",
    ]);
    for (scene, size, args) in scenes {
        for (form, flag) in [("binary", ""), ("text", "--text")] {
            let file = k.scene(
                &format!("{scene}.{form}"),
                &format!("environment {args} {flag}"),
            )?;
            let names = [
                "render",
                "pipes",
                "pipes, clipbatch",
                "fused",
                "fused, clipbatch",
            ];
            let tail = format!(
                "{} --size {size} | {} | {}",
                k.b("persp"),
                k.b("scanconv"),
                k.b("zbuf")
            );
            let lines = [
                k.render(&format!("--size {size} {file}")),
                format!(
                    "{} --size {size} < {file} | {} | {tail}",
                    k.b("viewxf"),
                    k.clip()
                ),
                format!(
                    "{} --size {size} < {file} | {} | {tail}",
                    k.b("viewxf"),
                    k.b("clipbatch")
                ),
                format!("{} --size {size} {file}", k.b("fused")),
                format!("{} --clipper batch --size {size} {file}", k.b("fused")),
            ];
            let expected = k.bytes(&lines[0])?;
            for l in &lines[1..] {
                if k.bytes(l)? != expected {
                    return Err(Error::data(format!("`{l}` does not write render's frame")));
                }
            }
            let runs = interleaved(reps, &lines)?;
            let (w3, c3) = (
                median_of(&runs[3], Figure::Wall),
                median_of(&runs[3], Figure::Cpu),
            );
            for (i, name) in names.iter().enumerate() {
                let (w, c) = (
                    median_of(&runs[i], Figure::Wall),
                    median_of(&runs[i], Figure::Cpu),
                );
                row(&[
                    format!("{scene} {size}"),
                    form.into(),
                    (*name).into(),
                    ms(w),
                    format!("{c:.2}"),
                    ratio(w, w3),
                    ratio(c, c3),
                ]);
            }
        }
    }
    println!();
    println!("pipes: render's processes as one shell pipe line (no named pipes).");
    Ok(())
}

fn fill(k: &Kit, reps: usize, base: Option<&str>, count: &dyn Fn(usize) -> usize) -> Result<()> {
    let scene = k.fill_scene("fill.txt", count(10_000), "1920x1080")?;
    let screen = k.w("fill.screen");
    k.make(
        "fill.screen",
        &format!(
            "{} --size 1920x1080 < {scene} | {} | {} --size 1920x1080",
            k.b("viewxf"),
            k.b("clipbatch"),
            k.b("persp")
        ),
    )?;
    let stats = k.out(&format!("{} --stats {screen} 2>&1 >/dev/null", k.b("zbuf")))?;
    let tested = crate::kit::stat_count(&stats, "pixels tested")?;
    let mut zbufs = vec![k.b("zbuf")];
    if let Some(b) = base {
        let b = crate::kit::q(b);
        if k.bytes(&format!("{b} {screen}"))? != k.bytes(&format!("{} {screen}", k.b("zbuf")))? {
            return Err(Error::data(format!("{b} draws another frame")));
        }
        zbufs.push(b);
    }
    let lines: Vec<String> = zbufs.iter().map(|z| format!("{z} {screen}")).collect();
    let runs = interleaved(reps, &lines)?;
    header(&[
        "zbuf",
        "pixels tested",
        &format!("CPU s (median of {reps})"),
        "M tests per CPU s",
    ]);
    for (z, r) in zbufs.iter().zip(&runs) {
        let c = median_of(r, Figure::Cpu);
        row(&[
            z.clone(),
            tested.to_string(),
            ms(c),
            format!("{:.0}", tested as f64 / c / 1e6),
        ]);
    }
    if runs.len() == 2 {
        println!();
        println!(
            "CPU of this zbuf over BASE's: {}",
            ratio(
                median_of(&runs[0], Figure::Cpu),
                median_of(&runs[1], Figure::Cpu)
            )
        );
    }
    println!();
    cargo(k, "build -p scan --example ztest")?;
    print!("{}", k.out(&k.b("examples/ztest"))?);
    Ok(())
}

fn shading(k: &Kit, reps: usize, quick: bool) -> Result<()> {
    let kinds = [("flat", ""), ("gouraud", "--gouraud"), ("phong", "--phong")];
    let fine = if quick { 24 } else { 96 };
    let size = "1000x1000";
    for f in [fine, 12] {
        for (kind, option) in kinds {
            let world = k.scene(
                &format!("{kind}-{f}.world"),
                &format!(
                    "sphere --stacks {f} --slices {} {option} --specular 0.5,30",
                    2 * f
                ),
            )?;
            k.make(
                &format!("{kind}-{f}.screen"),
                &format!(
                    "{} --size {size} < {world} | {} | {} --size {size}",
                    k.b("viewxf"),
                    k.b("clipbatch"),
                    k.b("persp")
                ),
            )?;
            let ppm = k.make(
                &format!("{kind}-{f}.ppm"),
                &format!("{} --size {size} < {world}", k.b("zspec")),
            )?;
            let z = k.bytes(&format!(
                "{} {}",
                k.b("zbuf"),
                k.w(&format!("{kind}-{f}.screen"))
            ))?;
            if std::fs::read(&ppm).map_err(|e| Error::io(e.to_string()))? != z {
                return Err(Error::data(format!("{kind}: zbuf's frame is not zspec's")));
            }
        }
    }
    // "RMSE / max" of a frame against Phong's.
    let error = |kind: &str, f: u32| -> Result<String> {
        let text = k.out(&format!(
            "{} compare --metrics {} {}",
            k.b("zspec"),
            k.w(&format!("{kind}-{f}.ppm")),
            k.w(&format!("phong-{f}.ppm"))
        ))?;
        let words: Vec<&str> = text
            .lines()
            .find(|l| l.starts_with("overall"))
            .map(|l| l.split_whitespace().collect())
            .unwrap_or_default();
        let after = |key: &str| {
            words
                .iter()
                .position(|w| *w == key)
                .and_then(|i| words.get(i + 1))
                .copied()
        };
        let r: f64 = after("rmse").and_then(|v| v.parse().ok()).unwrap_or(0.0);
        Ok(format!("{r:.2} / {}", after("max").unwrap_or("0")))
    };
    let mut lines = Vec::new();
    for (kind, _) in kinds {
        lines.push(format!(
            "{} {}",
            k.b("zbuf"),
            k.w(&format!("{kind}-{fine}.screen"))
        ));
        lines.push(format!(
            "POLYPIPE_LOAD=0 {}",
            k.render(&format!(
                "--size {size} --depth 0 {}",
                k.w(&format!("{kind}-{fine}.world"))
            ))
        ));
    }
    let runs = interleaved(reps, &lines)?;
    let polygons = 2 * fine * fine;
    header(&[
        "shading",
        "zbuf CPU ms",
        "ratio",
        "render --depth 0 CPU ms",
        "ratio",
        &format!("error against Phong, {polygons} polygons"),
        "the same, 288 polygons",
    ]);
    let (z0, w0) = (
        median_of(&runs[0], Figure::Cpu),
        median_of(&runs[1], Figure::Cpu),
    );
    for (i, (kind, _)) in kinds.iter().enumerate() {
        let (z, w) = (
            median_of(&runs[2 * i], Figure::Cpu),
            median_of(&runs[2 * i + 1], Figure::Cpu),
        );
        row(&[
            (*kind).into(),
            format!("{:.1}", z * 1000.0),
            ratio(z, z0),
            format!("{:.1}", w * 1000.0),
            ratio(w, w0),
            error(kind, fine)?,
            error(kind, 12)?,
        ]);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_quads_are_a_text_scene_of_four_vertices_each() {
        let t = super::quads(3);
        assert!(t.starts_with("polypipe 1 world\ncolour 0 0 0\n"), "{t}");
        assert_eq!(t.matches("NEXT.POLYGON").count(), 2);
        assert_eq!(t.lines().count(), 1 + 3 * 5 + 2 + 1);
        assert!(t.ends_with("END\n"));
    }
}
