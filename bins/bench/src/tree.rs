//! `bench tree MODE`: the splitter tree and its merge measured, one mode a run.
//!
//! - `pipeline [SECTION…]`: the whole pipeline's tables (1 the linear pipeline, 2 the
//!   splitter depths 0-4, 3 spans against per-pixel records, 4 accuracy against zspec,
//!   5 peak memory of every stage, 6 each process of the depth-0..4 graphs alone: with a
//!   processor per process, the slowest bounds the wall time, thesis 6.1).
//! - `merge [SECTION…]`: leaves that resolve (`--merge tiles`) against PAR.BUFF
//!   (`--merge buffer`): 1 render's wall time by depth, 2 the leaves and merger alone.
//! - `depth-auto`: `--depth auto` against every fixed depth on one and all cores, and
//!   render's start-up against the stages by hand.
//! - `plan`: the cost model against this machine (docs/model.md).
//! - `work [MAX-DEPTH]`: the user-space instructions of every process (cachegrind).
//! - `farm`: a movie by frames over 1, 2, 4 stand-in hosts beside `plan movie`.
//!
//! The fill-heavy scene is 10,000 quads, depth complexity 10, 1920×1080; the
//! geometry-heavy one 100,000 small polygons at 500×500 (`--quick`: a hundredth).

use crate::kit::{cores, header, load, machine, row, Kit};
use crate::measure::{self, best_of, interleaved, median_of, ms, ratio, Figure, Usage};
use stagecli::{Error, Result};
use std::collections::BTreeMap;

/// The options of `bench tree`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// pipeline, merge, depth-auto, plan, work or farm.
    #[arg(value_enum)]
    pub mode: Mode,
    /// pipeline's and merge's sections (default all); work's deepest depth (default 2).
    pub sections: Vec<u32>,
    /// Repetitions (pipeline 3, merge 5, depth-auto 7, plan 5, farm 5).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub reps: Option<u32>,
    /// Scenes of a hundredth the polygons, to try a mode out.
    #[arg(long)]
    pub quick: bool,
    /// farm: the host counts.
    #[arg(long, default_value = "1,2,4")]
    pub hosts: String,
    /// farm: the movie's frames.
    #[arg(long, default_value_t = 96)]
    pub frames: u32,
    /// farm: frames a job.
    #[arg(long, default_value_t = 8)]
    pub chunk: u32,
}

/// The modes of `bench tree`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    Pipeline,
    Merge,
    DepthAuto,
    Plan,
    Work,
    Farm,
}

/// Runs `bench tree`.
pub fn main(a: &Args) -> Result<()> {
    let k = Kit::new()?;
    let n = |full: usize| if a.quick { (full / 100).max(10) } else { full };
    let reps = |d: u32| a.reps.unwrap_or(d) as usize;
    let want = |s: u32| a.sections.is_empty() || a.sections.contains(&s);
    match a.mode {
        Mode::Pipeline => pipeline(&k, reps(3), &want, &n),
        Mode::Merge => merge(&k, reps(5), &want, &n),
        Mode::DepthAuto => depth_auto(&k, reps(7), &n),
        Mode::Plan => plan(&k, reps(5), &n),
        Mode::Work => work(&k, a.sections.first().copied().unwrap_or(2), &n),
        Mode::Farm => farm(&k, reps(5), a, &n),
    }
}

type Want<'a> = &'a dyn Fn(u32) -> bool;
type Count<'a> = &'a dyn Fn(usize) -> usize;

/// The least wall seconds of `reps` runs, to the ms.
fn wall(reps: usize, line: &str) -> Result<String> {
    Ok(ms(best_of(reps, line, Figure::Wall)?))
}

/// The fill-heavy and geometry-heavy scenes, in the scratch files fill.pp and geo.pp.
fn scenes(k: &Kit, n: Count) -> Result<(String, String)> {
    let fill = k.scene(
        "fill.pp",
        &format!(
            "environment --polygons {} --depth-complexity 10 --size 1920x1080 --seed 2",
            n(10_000)
        ),
    )?;
    let geo = k.scene(
        "geo.pp",
        &format!(
            "environment --polygons {} --depth-complexity 1 --seed 3",
            n(100_000)
        ),
    )?;
    Ok((fill, geo))
}

fn pipeline(k: &Kit, reps: usize, want: Want, n: Count) -> Result<()> {
    let (fill, geo) = scenes(k, n)?;
    if want(1) {
        println!("## 1. Linear pipeline, {} polygons, 500x500", n(100_000));
        let scene = k.scene(
            "lin.pp",
            &format!(
                "environment --polygons {} --depth-complexity 10 --seed 1",
                n(100_000)
            ),
        )?;
        let t = wall(reps, &k.render(&scene))?;
        header(&["scene", "wall s"]);
        row(&[format!("environment {} polygons, Dc 10", n(100_000)), t]);
        println!();
    }
    if want(2) {
        println!("## 2. Splitter depth (wall seconds, best of {reps})");
        header(&[
            "depth",
            "fill-heavy (10k, Dc 10, 1920x1080)",
            "geometry-heavy (100k small, 500x500)",
        ]);
        for d in 0..=4 {
            let tf = wall(
                reps,
                &k.render(&format!("--depth {d} --size 1920x1080 {fill}")),
            )?;
            let tg = wall(reps, &k.render(&format!("--depth {d} {geo}")))?;
            row(&[d.to_string(), tf, tg]);
        }
        println!();
        println!("Leaf balance at depth 2 (fill-heavy scene), from --stats:");
        let stats = k.out(&format!(
            "{} 2>&1 >/dev/null",
            k.render(&format!("--depth 2 --size 1920x1080 --stats {fill}"))
        ))?;
        for l in stats.lines() {
            if l.starts_with("scanconv") || l.starts_with("zbuf") {
                println!("{l}");
            }
        }
        println!();
    }
    if want(3) {
        println!("## 3. Fragment encoding: spans against per-pixel records (fill-heavy scene)");
        let screen = k.w("fill.screen");
        k.make(
            "fill.screen",
            &format!(
                "{} --size 1920x1080 < {fill} | {} | {} --size 1920x1080",
                k.b("viewxf"),
                k.clip(),
                k.b("persp")
            ),
        )?;
        header(&[
            "encoding",
            "scanconv bytes",
            "scanconv s",
            "scanconv + zbuf s",
        ]);
        for (mode, flag) in [("spans", ""), ("pixels", "--pixels")] {
            let conv = format!("{} {flag} < {screen}", k.b("scanconv"));
            let bytes = k.out(&format!("{conv} | wc -c"))?.trim().to_string();
            let ts = wall(reps, &conv)?;
            let tz = wall(reps, &format!("{conv} | {}", k.b("zbuf")))?;
            row(&[mode.to_string(), bytes, ts, tz]);
        }
        println!();
    }
    if want(4) {
        println!("## 4. Accuracy against the exact reference (pixels that differ from zspec)");
        header(&["scene", "pixels", "projective depth", "eye-z depth (occam)"]);
        let cases = [
            ("penetrating", "penetrating".to_string()),
            ("spheres", "spheres".to_string()),
            ("triangle-square", "triangle-square".to_string()),
            (
                "environment 1000, Dc 3",
                format!(
                    "environment --polygons {} --depth-complexity 3 --seed 4",
                    n(1000)
                ),
            ),
            (
                "environment 100000, Dc 10",
                format!(
                    "environment --polygons {} --depth-complexity 10 --seed 5",
                    n(100_000)
                ),
            ),
        ];
        for (name, args) in cases {
            let scene = k.scene("acc.pp", &args)?;
            let size = "--size 500x500";
            k.make("ref.ppm", &format!("{} {size} {scene}", k.b("zspec")))?;
            k.make("proj.ppm", &k.render(&format!("{size} {scene}")))?;
            k.make(
                "eyez.ppm",
                &k.render(&format!("{size} --zmode eye-z {scene}")),
            )?;
            let (p, total) = k.differing(&k.w("ref.ppm"), &k.w("proj.ppm"))?;
            let (e, _) = k.differing(&k.w("ref.ppm"), &k.w("eyez.ppm"))?;
            row(&[
                name.to_string(),
                total.to_string(),
                p.to_string(),
                e.to_string(),
            ]);
        }
        println!();
    }
    if want(5) {
        println!("## 5. Peak resident memory (KiB) by number of polygons");
        let counts = [n(10_000), n(1_000_000)];
        header(&[
            "stage",
            &format!("{} polygons", counts[0]),
            &format!("{} polygons", counts[1]),
        ]);
        let world = |c: usize| {
            format!("environment --polygons {c} --depth-complexity 1 --clipped 0.2 --seed 6")
        };
        for c in counts {
            k.scene(&format!("w{c}"), &world(c))?;
            k.make(
                &format!("e{c}"),
                &format!("{} < {}", k.b("viewxf"), k.w(&format!("w{c}"))),
            )?;
            k.make(
                &format!("c{c}"),
                &format!("< {} {}", k.w(&format!("e{c}")), k.clip()),
            )?;
            k.make(
                &format!("s{c}"),
                &format!(
                    "{} --size 500x500 < {}",
                    k.b("persp"),
                    k.w(&format!("c{c}"))
                ),
            )?;
            k.make(
                &format!("f{c}"),
                &format!("{} < {}", k.b("scanconv"), k.w(&format!("s{c}"))),
            )?;
        }
        let stages: [(&str, &dyn Fn(usize) -> String); 8] = [
            ("scene", &|c| format!("{} {}", k.b("scene"), world(c))),
            ("viewxf", &|c| {
                format!("{} < {}", k.b("viewxf"), k.w(&format!("w{c}")))
            }),
            ("clipplane left", &|c| {
                format!("{} left < {}", k.b("clipplane"), k.w(&format!("e{c}")))
            }),
            ("splitter x=0", &|c| {
                format!(
                    "{} x=0 - /dev/null < {}",
                    k.b("splitter"),
                    k.w(&format!("c{c}"))
                )
            }),
            ("persp", &|c| {
                format!(
                    "{} --size 500x500 < {}",
                    k.b("persp"),
                    k.w(&format!("c{c}"))
                )
            }),
            ("scanconv", &|c| {
                format!("{} < {}", k.b("scanconv"), k.w(&format!("s{c}")))
            }),
            ("zbuf", &|c| {
                format!("{} < {}", k.b("zbuf"), k.w(&format!("f{c}")))
            }),
            ("zspec", &|c| {
                format!("{} {}", k.b("zspec"), k.w(&format!("w{c}")))
            }),
        ];
        for (name, line) in stages {
            let mut cells = vec![name.to_string()];
            for c in counts {
                let u = measure::run(&format!("exec {}", line(c)))?;
                cells.push(u.max_rss_kib.to_string());
            }
            row(&cells);
        }
        println!();
    }
    if want(6) {
        println!(
            "## 6. What the tree would buy with one processor per process (CPU seconds, best of {reps})"
        );
        println!();
        println!(
            "Each process of render's graph run alone, file to file (no pipes). On one processor"
        );
        println!("the wall time is at least the sum; with one processor per process, streaming, at least");
        println!("the slowest process's time.");
        println!();
        tree_cost(
            k,
            reps,
            "Fill-heavy (10,000 polygons, Dc 10, 1920x1080)",
            &fill,
            "1920x1080",
        )?;
        tree_cost(
            k,
            reps,
            "Geometry-heavy (100,000 small polygons, 500x500)",
            &geo,
            "500x500",
        )?;
    }
    Ok(())
}

/// Section 6's table for one scene: a row per depth.
fn tree_cost(k: &Kit, reps: usize, name: &str, scene: &str, size: &str) -> Result<()> {
    let cpu = |line: &str| best_of(reps, line, Figure::Cpu);
    let mut chain: Vec<(String, f64)> = Vec::new();
    k.make(
        "t.view",
        &format!("{} --size {size} < {scene}", k.b("viewxf")),
    )?;
    chain.push((
        "viewxf".into(),
        cpu(&format!("{} --size {size} < {scene}", k.b("viewxf")))?,
    ));
    let mut prev = k.w("t.view");
    for plane in ["left", "right", "top", "bottom", "hither", "yon"] {
        let line = format!("{} {plane} < {prev}", k.b("clipplane"));
        k.make(&format!("t.{plane}"), &line)?;
        chain.push((format!("clipplane {plane}"), cpu(&line)?));
        prev = k.w(&format!("t.{plane}"));
    }
    println!("{name}:");
    println!();
    header(&[
        "depth",
        "processes",
        "sum of CPU s",
        "slowest upstream (viewxf, clippers, splitters)",
        "slowest leaf (persp, scanconv)",
        "zbuf",
        "slowest of all",
        "bound on speedup over depth 0",
    ]);
    let mut base = None;
    for d in 0..=4u32 {
        let mut times = chain.clone();
        let leaves = 1usize << d;
        std::fs::copy(k.work("t.yon"), k.work("t.node1"))
            .map_err(|e| Error::io(format!("copy: {e}")))?;
        let node = |i: usize| k.w(&format!("t.node{i}"));
        for i in 1..leaves {
            let tree = format!("--node {i} --depth {d} --size {size}");
            k.out(&format!(
                "{} {tree} {} {} < {}",
                k.b("splitter"),
                node(2 * i),
                node(2 * i + 1),
                node(i)
            ))?;
            let t = cpu(&format!(
                "{} {tree} /dev/null /dev/null < {}",
                k.b("splitter"),
                node(i)
            ))?;
            times.push((format!("splitter node {i}"), t));
        }
        let mut fragments = Vec::new();
        for leaf in leaves..2 * leaves {
            let persp = format!("{} --size {size} < {}", k.b("persp"), node(leaf));
            k.make(&format!("t.screen{leaf}"), &persp)?;
            let conv = format!("{} < {}", k.b("scanconv"), k.w(&format!("t.screen{leaf}")));
            k.make(&format!("t.frag{leaf}"), &conv)?;
            times.push((format!("persp leaf {}", leaf - leaves), cpu(&persp)?));
            times.push((format!("scanconv leaf {}", leaf - leaves), cpu(&conv)?));
            fragments.push(k.w(&format!("t.frag{leaf}")));
        }
        times.push((
            "zbuf".into(),
            cpu(&format!("{} {}", k.b("zbuf"), fragments.join(" ")))?,
        ));
        let slowest = |f: &dyn Fn(&str) -> bool| {
            times
                .iter()
                .filter(|(n, _)| f(n))
                .fold(
                    ("", 0.0),
                    |b, (n, t)| if *t > b.1 { (n.as_str(), *t) } else { b },
                )
        };
        let up = slowest(&|n| !n.contains("leaf") && n != "zbuf");
        let leaf = slowest(&|n| n.contains("leaf"));
        let zbuf = slowest(&|n| n == "zbuf");
        let all = slowest(&|_| true);
        let base = *base.get_or_insert(all.1);
        row(&[
            d.to_string(),
            times.len().to_string(),
            format!("{:.3}", times.iter().map(|t| t.1).sum::<f64>()),
            format!("{} {:.3}", up.0, up.1),
            format!("{} {:.3}", leaf.0, leaf.1),
            format!("{:.3}", zbuf.1),
            all.0.to_string(),
            ratio(base, all.1),
        ]);
    }
    println!();
    Ok(())
}

fn merge(k: &Kit, reps: usize, want: Want, n: Count) -> Result<()> {
    let (fill, geo) = scenes(k, n)?;
    if want(1) {
        println!("## 1. render wall seconds (best of {reps}) and speed-up over depth 0");
        println!();
        header(&[
            "depth",
            "fill tiles",
            "fill buffer",
            "geometry tiles",
            "geometry buffer",
            "render alone",
        ]);
        let mut base: BTreeMap<String, f64> = BTreeMap::new();
        for d in 0..=4 {
            let mut cells = vec![d.to_string()];
            for (scene, size) in [(&fill, "1920x1080"), (&geo, "500x500")] {
                for m in ["tiles", "buffer"] {
                    let line = k.render(&format!("--merge {m} --depth {d} --size {size} {scene}"));
                    let t = best_of(reps, &line, Figure::Wall)?;
                    let b = *base.entry(format!("{scene}{m}")).or_insert(t);
                    cells.push(format!("{} ({}x)", ms(t), ratio(b, t)));
                }
            }
            let alone = k.render(&format!(
                "--depth {d} --size 8x8 {}",
                k.r("examples/penetrating.txt")
            ));
            cells.push(wall(reps, &alone)?);
            row(&cells);
        }
        println!();
    }
    if want(2) {
        println!(
            "## 2. Leaves and merger alone, file to file, fill-heavy scene (CPU s, best of {reps}; peak KiB)"
        );
        println!();
        header(&[
            "depth",
            "mode",
            "slowest leaf scanconv s",
            "largest leaf scanconv KiB",
            "zbuf s",
            "zbuf KiB",
            "bytes to zbuf",
        ]);
        let size = "1920x1080";
        k.make(
            "node1",
            &format!("{} --size {size} < {fill} | {}", k.b("viewxf"), k.clip()),
        )?;
        // The least CPU seconds of `reps` runs and the peak memory of one more.
        let cpu_rss = |line: &str| -> Result<(f64, u64)> {
            let t = best_of(reps, &format!("exec {line}"), Figure::Cpu)?;
            Ok((t, measure::run(&format!("exec {line}"))?.max_rss_kib))
        };
        for d in 0..=4u32 {
            let leaves = 1usize << d;
            let node = |i: usize| k.w(&format!("node{i}"));
            for i in 1..leaves {
                k.out(&format!(
                    "{} --node {i} --depth {d} --size {size} {} {} < {}",
                    k.b("splitter"),
                    node(2 * i),
                    node(2 * i + 1),
                    node(i)
                ))?;
            }
            for (m, flag) in [("tiles", "--resolve"), ("buffer", "")] {
                let (mut slow, mut big, mut bytes, mut frags) = (0.0f64, 0u64, 0u64, Vec::new());
                for leaf in leaves..2 * leaves {
                    let screen = format!("screen{leaf}");
                    k.make(
                        &screen,
                        &format!("{} --size {size} < {}", k.b("persp"), node(leaf)),
                    )?;
                    let conv = format!("{} {flag} < {}", k.b("scanconv"), k.w(&screen));
                    let frag = k.make(&format!("frag{leaf}"), &conv)?;
                    let (s, kib) = cpu_rss(&conv)?;
                    slow = slow.max(s);
                    big = big.max(kib);
                    bytes += std::fs::metadata(&frag).map_or(0, |m| m.len());
                    frags.push(k.w(&format!("frag{leaf}")));
                }
                let (zs, zk) = cpu_rss(&format!("{} {}", k.b("zbuf"), frags.join(" ")))?;
                row(&[
                    d.to_string(),
                    m.to_string(),
                    ms(slow),
                    big.to_string(),
                    ms(zs),
                    zk.to_string(),
                    bytes.to_string(),
                ]);
            }
        }
        println!();
    }
    Ok(())
}

/// What render's --stats says `depth auto` chose (its line after "depth auto chose ").
fn auto_chose(k: &Kit, prefix: &str, args: &str) -> Result<String> {
    let stats = k.out(&format!(
        "{prefix}{} 2>&1 >/dev/null",
        k.render(&format!("--stats {args}"))
    ))?;
    Ok(stats
        .lines()
        .find_map(|l| l.strip_prefix("render: depth auto chose "))
        .unwrap_or("")
        .to_string())
}

/// The text before " (" of auto's line.
fn short(chose: &str) -> &str {
    chose.split(" (").next().unwrap_or(chose)
}

fn plan_status(k: &Kit) -> String {
    k.out(&format!("{} status", k.b("plan")))
        .ok()
        .and_then(|s| s.lines().next().map(str::to_string))
        .unwrap_or_default()
}

fn depth_auto(k: &Kit, reps: usize, n: Count) -> Result<()> {
    let size = "1920x1080";
    let fill = k.fill_scene("fill.txt", n(10_000), size)?;
    let two = k.r("examples/triangle-square.txt");
    let all = format!("0-{}", cores() - 1);
    let core_sets = ["0".to_string(), all];
    let depths = ["0", "1", "2", "3", "auto"];
    let mut names = Vec::new();
    let mut lines = Vec::new();
    for c in &core_sets {
        for d in depths {
            names.push(format!("fill {c} {d}"));
            lines.push(format!(
                "taskset -c {c} {}",
                k.render(&format!("--size {size} --depth {d} {fill}"))
            ));
        }
    }
    names.push("start render".into());
    lines.push(k.render(&format!("--size 64x64 {two}")));
    names.push("start hand".into());
    lines.push(format!(
        "{} --size 64x64 < {two} | {} | {} --size 64x64 | {}",
        k.b("viewxf"),
        k.b("clipbatch"),
        k.b("persp"),
        k.b("zbuf")
    ));
    // Every command once, its frames checked: every depth's the same bytes as depth 0's.
    let outs: Vec<Vec<u8>> = lines.iter().map(|l| k.bytes(l)).collect::<Result<_>>()?;
    for (i, name) in names.iter().enumerate().take(names.len() - 2) {
        if outs[i] != outs[0] {
            return Err(Error::data(format!("{name} drew other bytes than depth 0")));
        }
    }
    if outs[names.len() - 2] != outs[names.len() - 1] {
        return Err(Error::data(
            "render and the stages by hand drew other bytes",
        ));
    }
    let before = load();
    let runs = interleaved_env(reps, &lines)?;
    let after = load();
    println!();
    println!(
        "Measured by `bench tree depth-auto --reps {reps}` on {}; before: {before}; after: \
         {after}; POLYPIPE_LOAD unset; constants: {}.",
        machine(),
        plan_status(k)
    );
    println!();
    header(&[
        "fill scene, cores",
        "",
        "depth 0",
        "1",
        "2",
        "3",
        "auto",
        "best",
        "auto / best",
        "auto chose",
    ]);
    let mut chosen = Vec::new();
    for (ci, c) in core_sets.iter().enumerate() {
        let at = |d: usize, f| median_of(&runs[ci * depths.len() + d], f);
        let (bestd, best) = (0..4)
            .map(|d| (d, at(d, Figure::Wall)))
            .fold((0, f64::MAX), |b, x| if x.1 < b.1 { x } else { b });
        let chose = auto_chose(
            k,
            &format!("taskset -c {c} "),
            &format!("--size {size} {fill}"),
        )?;
        let mut wall = vec![format!("`taskset -c {c}`"), "wall s".into()];
        let mut cpu = vec![String::new(), "CPU s".into()];
        for d in 0..5 {
            wall.push(ms(at(d, Figure::Wall)));
            cpu.push(ms(at(d, Figure::Cpu)));
        }
        wall.extend([
            bestd.to_string(),
            format!("**{}**", ratio(at(4, Figure::Wall), best)),
            short(&chose).to_string(),
        ]);
        cpu.extend([String::new(), String::new(), String::new()]);
        row(&wall);
        row(&cpu);
        chosen.push(format!("cores {c}: depth auto chose {chose}"));
    }
    println!();
    for l in chosen {
        println!("{l}");
    }
    println!();
    let r = &runs[runs.len() - 2];
    let h = &runs[runs.len() - 1];
    header(&[
        "two polygons, 64×64",
        "render",
        "viewxf \\| clipbatch \\| persp \\| zbuf",
        "render / by hand",
    ]);
    for (label, f, bold) in [
        ("wall s", Figure::Wall, true),
        ("CPU s", Figure::Cpu, false),
    ] {
        let q = ratio(median_of(r, f), median_of(h, f));
        row(&[
            label.into(),
            ms(median_of(r, f)),
            ms(median_of(h, f)),
            if bold { format!("**{q}**") } else { q },
        ]);
    }
    Ok(())
}

/// [`interleaved`] with POLYPIPE_LOAD unset (auto plans for the load it finds).
fn interleaved_env(reps: usize, lines: &[String]) -> Result<Vec<Vec<Usage>>> {
    let lines: Vec<String> = lines
        .iter()
        .map(|l| format!("unset POLYPIPE_LOAD; {l}"))
        .collect();
    interleaved(reps, &lines)
}

fn plan(k: &Kit, reps: usize, n: Count) -> Result<()> {
    let size = "1920x1080";
    let scene = k.fill_scene("fill.txt", n(10_000), size)?;
    println!();
    println!(
        "Measured by `bench tree plan --reps {reps}` on {}, {} before; {}.",
        machine(),
        load(),
        plan_status(k)
    );
    // 1. auto against fixed depths, interleaved.
    let depths = ["auto", "0", "1", "2", "3"];
    let lines: Vec<String> = depths
        .iter()
        .map(|d| k.render(&format!("--size {size} --depth {d} {scene}")))
        .collect();
    let runs = interleaved(reps, &lines)?;
    let med: Vec<f64> = runs.iter().map(|r| median_of(r, Figure::Wall)).collect();
    let (bestd, best) = (1..5)
        .map(|i| (depths[i], med[i]))
        .fold(("", f64::MAX), |b, x| if x.1 < b.1 { x } else { b });
    let choice = auto_chose(k, "", &format!("--size {size} --depth auto {scene}"))?;
    println!();
    header(&[
        &format!("fill scene, wall s, median of {reps} interleaved"),
        "depth 0",
        "1",
        "2",
        "3",
        "best",
        "auto",
        "auto / best",
        "auto chose",
    ]);
    row(&[
        "render".into(),
        ms(med[1]),
        ms(med[2]),
        ms(med[3]),
        ms(med[4]),
        bestd.into(),
        ms(med[0]),
        format!("**{}**", ratio(med[0], best)),
        short(&choice).into(),
    ]);
    println!();
    println!("auto's line: {choice}");
    // 2. 1 and 2 cores: the model against taskset.
    println!();
    header(&[
        "cores",
        "depth",
        "predicted s",
        "measured s (taskset)",
        "error",
    ]);
    for (cpus, c) in [("0", 1), ("0,1", 2)] {
        let table = k.out(&format!(
            "{} predict --size {size} --cores {c} --max-depth 2 {scene}",
            k.b("plan")
        ))?;
        for d in 0..=2 {
            let predicted: f64 = table
                .lines()
                .filter_map(|l| {
                    let f: Vec<&str> = l.split('|').map(str::trim).collect();
                    (f.len() > 2 && f[1].split(' ').next() == Some(&d.to_string()))
                        .then(|| f[2].parse().ok())
                        .flatten()
                })
                .next()
                .unwrap_or(0.0);
            let line = format!(
                "taskset -c {cpus} {}",
                k.render(&format!("--size {size} --depth {d} {scene}"))
            );
            let m: Vec<f64> = (0..reps)
                .map(|_| measure::run(&line).map(|u| u.wall_s))
                .collect::<Result<_>>()?;
            let m = measure::median(&m);
            row(&[
                c.to_string(),
                d.to_string(),
                predicted.to_string(),
                ms(m),
                format!("{:+.0}%", (predicted - m) / m * 100.0),
            ]);
        }
    }
    // 3. The tree's per-level work at depth 3: the polygons in view each node of a level
    // reads (its parent's output to it), against the model's P_r/2^l.
    println!();
    header(&[
        "level",
        "nodes",
        "polygons in view read, all nodes (measured)",
        "largest node",
        "model, each node",
    ]);
    let stats = k.out(&format!(
        "{} 2>&1 >/dev/null",
        k.render(&format!("--size {size} --depth 3 --stats {scene}"))
    ))?;
    let predict = k.out(&format!(
        "{} predict --size {size} --max-depth 0 {scene}",
        k.b("plan")
    ))?;
    let (pr, pt) = predict
        .lines()
        .find_map(|l| {
            // "6313 polygons in view of 9982, Dc 6.87, …"
            let (a, rest) = l.split_once(" polygons in view of ")?;
            let b = rest.split([' ', ',']).next()?;
            Some((a.parse::<u64>().ok()?, b.parse::<u64>().ok()?))
        })
        .unwrap_or((0, 0));
    // "(node P): N polygons in; out1 A polygons, V vertices; out2 B polygons"
    let outs = |parent: usize| -> (u64, u64) {
        let tag = format!("(node {parent}): ");
        stats
            .lines()
            .find_map(|l| {
                let rest = &l[l.find(&tag)? + tag.len()..];
                let a = rest
                    .split("out1 ")
                    .nth(1)?
                    .split(' ')
                    .next()?
                    .parse()
                    .ok()?;
                let b = rest
                    .split("out2 ")
                    .nth(1)?
                    .split(' ')
                    .next()?
                    .parse()
                    .ok()?;
                Some((a, b))
            })
            .unwrap_or((0, 0))
    };
    for level in 1..=3u32 {
        let (first, last) = (1usize << level, (2usize << level) - 1);
        let (mut sum, mut most) = (0, 0);
        for node in first..=last {
            let (a, b) = outs(node / 2);
            let v = if node % 2 == 0 { a } else { b };
            sum += v;
            most = most.max(v);
        }
        row(&[
            level.to_string(),
            (1 << level).to_string(),
            sum.to_string(),
            most.to_string(),
            (pr >> level).to_string(),
        ]);
    }
    println!("(the root reads all {pt} polygons of the scene; {pr} of them are in view)");
    // 4. A live source: the first frame out after it was written.
    let delay = live_source(k)?;
    println!();
    println!(
        "live source: the first frame came out {delay:.3} s after it was written (the source then waited 1 s)"
    );
    println!("{} after", load());
    Ok(())
}

/// Seconds from writing a live scene's first frame to render's stdin to that frame
/// coming out (a frame, then the source waits a second before the rest).
fn live_source(k: &Kit) -> Result<f64> {
    use std::io::{Read, Write};
    use std::process::{Command, Stdio};
    let io = |e: std::io::Error| Error::io(format!("live source: {e}"));
    let text = std::fs::read_to_string(k.root.join("examples/penetrating.txt")).map_err(io)?;
    let body: Vec<&str> = text.lines().filter(|l| !l.starts_with("END")).collect();
    let mut child = Command::new(k.bin.join("render"))
        .args(["--size", "320x240", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .map_err(io)?;
    let mut stdin = child.stdin.take().ok_or_else(|| Error::io("no stdin"))?;
    let mut stdout = child.stdout.take().ok_or_else(|| Error::io("no stdout"))?;
    let reader = std::thread::spawn(move || {
        let mut frame = vec![0u8; 15 + 320 * 240 * 3];
        let r = stdout.read_exact(&mut frame);
        let at = std::time::Instant::now();
        let _ = std::io::copy(&mut stdout, &mut std::io::sink());
        r.map(|()| at)
    });
    std::thread::sleep(std::time::Duration::from_millis(500));
    writeln!(stdin, "{}\nNEXT.FRAME", body.join("\n")).map_err(io)?;
    stdin.flush().map_err(io)?;
    let t0 = std::time::Instant::now();
    std::thread::sleep(std::time::Duration::from_secs(1));
    writeln!(stdin, "{}\nEND", body[1..].join("\n")).map_err(io)?;
    drop(stdin);
    let t1 = reader
        .join()
        .map_err(|_| Error::io("live source: the reader failed"))?
        .map_err(io)?;
    child.wait().map_err(io)?;
    Ok(t1.duration_since(t0).as_secs_f64())
}

fn work(k: &Kit, max: u32, n: Count) -> Result<()> {
    if max > 6 {
        return Err(Error::usage(format!("MAX-DEPTH must be 0 to 6, not {max}")));
    }
    if k.out("command -v valgrind").is_err() {
        return Err(Error::io("work needs valgrind (apt install valgrind)"));
    }
    let fill = k.fill_scene("fill.txt", n(10_000), "1920x1080")?;
    let depth0 = k.make(
        "depth0.ppm",
        &k.render(&format!("--size 1920x1080 --depth 0 {fill}")),
    )?;
    let mut programs: Vec<String> = Vec::new();
    // (program, depth) → (instructions, processes); depth → all instructions.
    let mut count: BTreeMap<(String, u32), (u64, u64)> = BTreeMap::new();
    let mut total = vec![0u64; max as usize + 1];
    for d in 0..=max {
        let dir = k.work(&format!("d{d}"));
        std::fs::create_dir(&dir).map_err(|e| Error::io(format!("{}: {e}", dir.display())))?;
        let out = k.make(
            &format!("out{d}.ppm"),
            &format!(
                "valgrind --trace-children=yes --tool=cachegrind --cache-sim=no \
                 --cachegrind-out-file={}/%p {} 2>/dev/null",
                dir.display(),
                k.render(&format!("--size 1920x1080 --depth {d} {fill}"))
            ),
        )?;
        if std::fs::read(&out).ok() != std::fs::read(&depth0).ok() {
            return Err(Error::data(format!(
                "depth {d}'s frame differs from depth 0's"
            )));
        }
        for f in std::fs::read_dir(&dir)
            .map_err(|e| Error::io(e.to_string()))?
            .flatten()
        {
            let text = std::fs::read_to_string(f.path()).unwrap_or_default();
            let field = |key: &str| {
                text.lines()
                    .find_map(|l| l.strip_prefix(key).map(|v| v.trim().to_string()))
            };
            let program = field("cmd:")
                .and_then(|c| {
                    c.split(' ')
                        .next()
                        .map(|p| p.rsplit('/').next().unwrap_or(p).to_string())
                })
                .unwrap_or_default();
            let n: u64 = field("summary:").and_then(|s| s.parse().ok()).unwrap_or(0);
            if !programs.contains(&program) {
                programs.push(program.clone());
            }
            let c = count.entry((program, d)).or_default();
            c.0 += n;
            c.1 += 1;
            total[d as usize] += n;
        }
    }
    let millions = |n: u64| format!("{:.1}", n as f64 / 1e6);
    println!();
    println!(
        "Measured by `bench tree work {max}`: render --depth D on the fill-heavy scene, \
         millions of user-space instructions by program (cachegrind, children traced; \
         processes in brackets), every depth's frame identical to depth 0's."
    );
    println!();
    let mut head = vec!["program".to_string()];
    head.extend((0..=max).map(|d| format!("depth {d}")));
    header(&head.iter().map(String::as_str).collect::<Vec<_>>());
    for p in &programs {
        let mut cells = vec![p.clone()];
        for d in 0..=max {
            cells.push(match count.get(&(p.clone(), d)) {
                Some((n, procs)) => format!("{} ({procs})", millions(*n)),
                None => "–".into(),
            });
        }
        row(&cells);
    }
    let mut all = vec!["**all**".to_string()];
    let mut against = vec!["**against depth 0**".to_string()];
    for t in &total {
        all.push(format!("**{}**", millions(*t)));
        against.push(format!("**{}**", ratio(*t as f64, total[0] as f64)));
    }
    row(&all);
    row(&against);
    Ok(())
}

/// The stand-in ssh of the tests' POLYPIPE_SSH: runs the command here.
const SSH: &str = r#"#!/bin/sh
while [ $# -gt 0 ]; do case $1 in -[oplSOiF]) shift 2 ;; -*) shift ;; *) break ;; esac; done
shift
[ "${1-}" = -- ] && shift
exec sh -c "$*"
"#;

fn farm(k: &Kit, reps: usize, a: &Args, n: Count) -> Result<()> {
    if k.out("command -v parallel").is_err() {
        return Err(Error::io("farm needs GNU parallel"));
    }
    let size = "512x512";
    let counts: Vec<u32> = a
        .hosts
        .split(',')
        .map(|h| {
            h.parse()
                .map_err(|_| Error::usage(format!("--hosts: not a count: '{h}'")))
        })
        .collect::<Result<_>>()?;
    let polygons = n(1000).max(100);
    let movie = k.scene(
        "movie.pp",
        &format!(
            "environment --polygons {polygons} --depth-complexity 30 --size {size} --frames {}",
            a.frames
        ),
    )?;
    let ssh = k.work("ssh");
    std::fs::write(&ssh, SSH).map_err(|e| Error::io(e.to_string()))?;
    k.out(&format!("chmod +x {}", k.w("ssh")))?;
    let mut lines = vec![k.render(&format!("--size {size} --depth 0 {movie}"))];
    for c in &counts {
        let list: Vec<String> = (1..=*c).map(|i| format!("h{i}")).collect();
        lines.push(format!(
            "POLYPIPE_SSH={} POLYPIPE_LOAD=0 {}",
            k.w("ssh"),
            k.render(&format!(
                "--by frames --hosts {} --chunk {} --size {size} --depth 0 {movie}",
                list.join(","),
                a.chunk
            ))
        ));
    }
    let runs = interleaved(reps, &lines)?;
    let plan = k.out(&format!(
        "{} movie --hosts {} --chunk {} --size {size} --login 0 --host-cores {} {movie}",
        k.b("plan"),
        a.hosts,
        a.chunk,
        cores()
    ))?;
    let predicted = |hosts: u32, col: usize| -> String {
        plan.lines()
            .find_map(|l| {
                let f: Vec<&str> = l.split('|').map(str::trim).collect();
                (f.len() > col && f[1].split(' ').next() == Some(&hosts.to_string()))
                    .then(|| f[col].to_string())
            })
            .unwrap_or_else(|| "–".into())
    };
    let local_cpu = median_of(&runs[0], Figure::Cpu);
    println!();
    println!(
        "Measured by `bench tree farm --reps {reps}` on {}, {}: {} frames of `scene environment \
         --polygons {polygons} --depth-complexity 30 --size {size}`, render --size {size} --depth 0, \
         --by frames --chunk {}, medians of {reps}.",
        machine(),
        load(),
        a.frames,
        a.chunk
    );
    println!();
    header(&[
        "run",
        "wall s",
        "CPU s",
        "CPU × local",
        "predicted CPU s",
        &format!("predicted wall s, hosts of {} cores", cores()),
    ]);
    row(&[
        "render here".into(),
        ms(median_of(&runs[0], Figure::Wall)),
        ms(local_cpu),
        "1.00".into(),
        "–".into(),
        "–".into(),
    ]);
    for (i, c) in counts.iter().enumerate() {
        let cpu = median_of(&runs[i + 1], Figure::Cpu);
        row(&[
            format!("--by frames, {c} host{}", if *c == 1 { "" } else { "s" }),
            ms(median_of(&runs[i + 1], Figure::Wall)),
            ms(cpu),
            ratio(cpu, local_cpu),
            predicted(*c, 6),
            predicted(*c, 4),
        ]);
    }
    println!();
    for l in plan.lines().filter(|l| l.contains("frames, ")) {
        println!("{l}");
    }
    Ok(())
}
