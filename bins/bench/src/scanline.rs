//! `bench scanline`: how Watkins's scan-line method (`scanline`) grows against the
//! z-buffer leaf (`scanconv --resolve`) on the same screen-space streams, each leaf alone,
//! file to /dev/null. Newman and Sproull, 14.4.3: "the computation grows roughly as the
//! *visible* complexity increases".
//!
//! 1. crossings K: K columns across a 1024x1024 screen, each two full-height quads whose
//!    planes cross down its middle (depth complexity 2, K crossings a scan line)
//! 2. parallel D: D full-screen planes at random depths (no crossing)
//! 3. tilted D: D full-screen planes tilted at random (the front changing along a line)
//! 4. environment Dc: the thesis's test environment (chapter 5.2), 10,000 quads at
//!    500x500, 10 frames
//! 5. Archuleta's building at 256 and 1024 scan lines, 1000 frames, against his 7.2 s
//!    and 23.7 s on a DECsystem-10
//! 6. what coherence from line to line buys: `scanline` against `scanline
//!    --sort-afresh` on scenes of much coherence and little, 500x500: the instructions
//!    callgrind counts (`-` without valgrind), CPU seconds, the counters per scan line
//!
//! Sections 1-3 are 10 frames of one scene. Times are the least CPU seconds of N runs
//! (default 3); `ratio` is scanline's over the z-buffer's; the counters come from
//! `scanline --stats`, per scan line.

use crate::kit::{method_leaf, row, stat_count, Kind, Kit};
use crate::measure::{best_of, ms, quotient, ratio, Figure};
use stagecli::{Error, Result};

/// The options of `bench scanline`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Sections 1 to 6 (default all).
    #[arg(value_parser = clap::value_parser!(u32).range(1..=6))]
    pub sections: Vec<u32>,
    /// Runs of each command (default 3).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub reps: Option<u32>,
    /// Smaller scenes, fewer frames and one run each: a check that it works.
    #[arg(long)]
    pub quick: bool,
}

/// `a / b` to `places` places, 0 when `b` is 0.
fn per(a: u64, b: u64, places: usize) -> String {
    format!(
        "{:.*}",
        places,
        if b > 0 { a as f64 / b as f64 } else { 0.0 }
    )
}

fn table(title: &str, first: &str) {
    println!("## {title}");
    println!();
    crate::kit::header(&[
        first,
        "polygons a frame",
        "segments/line",
        "sample spans/line",
        "depth comparisons/line",
        "crossings/line",
        "scanline s",
        "z-buffer s",
        "ratio",
    ]);
}

/// Runs `bench scanline`.
pub fn main(a: &Args) -> Result<()> {
    let k = Kit::new()?;
    let reps = a.reps.map_or(if a.quick { 1 } else { 3 }, |r| r as usize);
    let want = |s: u32| a.sections.is_empty() || a.sections.contains(&s);
    let scanline = k.leaf(&method_leaf(Kind::Hse, "scanline")?);
    let zbuf = k.leaf(&method_leaf(Kind::Hse, "zbuf")?);
    let (frames, counts, env_n, building_frames, d): (u32, &[u32], u32, u32, u32) = if a.quick {
        (2, &[1, 16, 64], 1000, 20, 10)
    } else {
        (10, &[1, 4, 16, 64, 256], 10_000, 1000, 1)
    };
    let cpu = |line: String| best_of(reps, &line, Figure::Cpu);
    let line_of = |label: String, f: &str| -> Result<()> {
        let s = cpu(format!("{scanline} < {f}"))?;
        let z = cpu(format!("{zbuf} < {f}"))?;
        let stats = k.out(&format!("{scanline} --stats < {f} 2>&1 >/dev/null"))?;
        let lines = stat_count(&stats, "scan lines")?;
        let mut cells = vec![
            label,
            (stat_count(&stats, "polygons in")? / stat_count(&stats, "frames")?.max(1)).to_string(),
        ];
        for c in [
            "segments,",
            "sample spans",
            "depth comparisons",
            "crossings;",
        ] {
            cells.push(per(stat_count(&stats, c)?, lines, 1));
        }
        cells.extend([ms(s), ms(z), ratio(s, z)]);
        row(&cells);
        Ok(())
    };
    println!(
        "{} Each leaf alone, CPU seconds, the least of {reps}.",
        crate::kit::stamp("scanline")
    );
    println!();
    if want(1) {
        table(
            &format!("1. Crossings per scan line (depth complexity 2, 1024x1024, {frames} frames)"),
            "K",
        );
        for n in counts.iter().chain(&[512]) {
            let f = k.scene(
                &format!("cross{n}"),
                &format!("screen crossings {n} --size 1024x1024 --frames {frames}"),
            )?;
            line_of(n.to_string(), &f)?;
        }
        println!();
    }
    for (section, kind, what) in [
        (2, "parallel", "no crossing"),
        (3, "tilted", "the front changing along each line"),
    ] {
        if !want(section) {
            continue;
        }
        table(
            &format!("{section}. {kind} full-screen planes (depth complexity D, {what}, 1024x1024, {frames} frames)"),
            "D",
        );
        for n in counts {
            let f = k.scene(
                &format!("{kind}{n}"),
                &format!("screen {kind} {n} --seed {n} --size 1024x1024 --frames {frames}"),
            )?;
            line_of(n.to_string(), &f)?;
        }
        println!();
    }
    if want(4) {
        table(
            &format!("4. The test environment, {env_n} quads at 500x500, a 10-frame movie"),
            "Dc",
        );
        for dc in [1, 4, 16] {
            let f = k.screen(
                &format!("env{dc}"),
                &format!("environment --polygons {env_n} --depth-complexity {dc} --seed 5 --size 500x500 --frames 10"),
                "500x500",
            )?;
            line_of(dc.to_string(), &f)?;
        }
        println!();
    }
    if want(5) {
        table(
            &format!(
                "5. Archuleta's building at 256 and 1024 scan lines, {building_frames} frames"
            ),
            "lines",
        );
        for n in [256, 1024] {
            let f = k.screen(
                &format!("building{n}"),
                &format!("building --frames {building_frames}"),
                &format!("{n}x{n}"),
            )?;
            line_of(n.to_string(), &f)?;
        }
        println!();
    }
    if want(6) {
        println!(
            "## 6. What the coherence from line to line buys, 500x500 (instructions: callgrind)"
        );
        println!();
        crate::kit::header(&[
            "scene",
            "segments/line",
            "merged in/line",
            "re-sorted/line",
            "swaps/line",
            "fronts predicted held / failed",
            "crossings predicted held / failed",
            "midpoint subdivisions/line",
            "instructions, coherent",
            "instructions, --sort-afresh",
            "ratio",
            "CPU s, coherent",
            "CPU s, --sort-afresh",
        ]);
        let valgrind = k.out("command -v valgrind").is_ok();
        let instructions = |f: &str, extra: &str| -> Result<Option<u64>> {
            if !valgrind {
                return Ok(None);
            }
            let out = k.out(&format!(
                "valgrind --tool=callgrind --callgrind-out-file=/dev/null {scanline} {extra} < {f} 2>&1 >/dev/null"
            ))?;
            out.split("Collected : ")
                .nth(1)
                .and_then(|r| r.split_whitespace().next()?.parse().ok())
                .map(Some)
                .ok_or_else(|| Error::data(format!("callgrind counted nothing: {out}")))
        };
        let scenes = [
            ("spheres", "spheres".to_string(), true),
            ("stack", format!("stack {}", 20000 / d), true),
            ("slivers", format!("slivers {}", 10000 / d), true),
            ("reversing", format!("screen reversing {}", 1000 / d), false),
            ("planes", format!("planes {}", 400 / d), true),
        ];
        for (name, args, world) in scenes {
            let f = if world {
                k.screen(name, &args, "500x500")?
            } else {
                k.scene(name, &args)?
            };
            let stats = k.out(&format!("{scanline} --stats < {f} 2>&1 >/dev/null"))?;
            let lines = stat_count(&stats, "scan lines")?;
            let mut cells = vec![name.to_string()];
            for c in ["segments,", "segments merged in", "re-sorted", "swaps"] {
                cells.push(per(stat_count(&stats, c)?, lines, 2));
            }
            cells.push(format!(
                "{} / {}",
                stat_count(&stats, "fronts held")?,
                stat_count(&stats, "failed, # crossings held")?
            ));
            cells.push(format!(
                "{} / {}",
                stat_count(&stats, "crossings held")?,
                stat_count(&stats, "failed; # midpoint")?
            ));
            cells.push(per(stat_count(&stats, "midpoint subdivisions")?, lines, 2));
            let (ic, ia) = (instructions(&f, "")?, instructions(&f, "--sort-afresh")?);
            let show = |i: Option<u64>| i.map_or("-".to_string(), |n| n.to_string());
            cells.extend([
                show(ic),
                show(ia),
                quotient(ic.unwrap_or(0) as f64, ia.unwrap_or(0) as f64, 3),
                ms(cpu(format!("{scanline} < {f}"))?),
                ms(cpu(format!("{scanline} --sort-afresh < {f}"))?),
            ]);
            row(&cells);
        }
        println!();
    }
    Ok(())
}
