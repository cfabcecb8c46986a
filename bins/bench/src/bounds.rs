//! `bench bounds`: the bounds every method must keep on the scenes a user makes in a
//! minute to break it, and whether it keeps them.
//!
//! 1. On `scene stack 20000`, `slivers 10000` and `pinhead 100000` at 500x500, every
//!    hidden-surface method (render's --hse), painter --split, the hidden-line drawing
//!    and the a-buffer: under 256 MB of peak resident memory and 30 s.
//! 2. painter --split on `scene planes N` (N = 5, 50, 400): within 0.5% of the
//!    z-buffer's pixels, or saying on stderr that it could not order the planes.
//!
//! Each method runs as a leaf alone, the screen-space stream in and its output to
//! /dev/null, under `timeout 120`: wall and CPU seconds and peak resident memory. On a
//! loaded machine the wall time can be several times the CPU time; the bound is checked
//! on both, and a row says which it misses.

use crate::kit::{header, method_leaf, methods_list, row, Kind, Kit};
use crate::measure::{self, best_of, ms, quotient, Figure};
use crate::painter::{frame, over};
use stagecli::Result;

/// The options of `bench bounds`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Runs of each command (default 1); the table gives the one of least CPU.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub reps: Option<u32>,
    /// A tenth of the polygons: a check that it works (the bounds are not for it).
    #[arg(long)]
    pub quick: bool,
}

/// Runs `bench bounds`.
pub fn main(a: &Args) -> Result<()> {
    let k = Kit::new()?;
    let reps = a.reps.map_or(1, |r| r as usize);
    let d = if a.quick { 10 } else { 1 };
    let painter = method_leaf(Kind::Hse, "painter")?;
    let mut methods = methods_list(Kind::Hse);
    methods.push(("painter --split".into(), format!("{painter} --split")));
    methods.extend(methods_list(Kind::Lines));
    methods.push(("abuf".into(), method_leaf(Kind::Aa, "abuf")?));
    println!(
        "{} Each leaf alone, 500x500; the run of least CPU of {reps}.",
        crate::kit::stamp("bounds")
    );
    println!();
    header(&[
        "scene",
        "method",
        "wall s",
        "CPU s",
        "peak MB",
        "CPU / zbuf",
        "within 256 MB and 30 s",
    ]);
    for scene in [
        format!("stack {}", 20000 / d),
        format!("slivers {}", 10000 / d),
        format!("pinhead {}", 100000 / d),
    ] {
        let input = k.screen(&scene.replace(' ', "-"), &scene, "500x500")?;
        let mut zcpu = None;
        for (name, leaf) in &methods {
            eprintln!("bench: {scene}, {name}");
            let line = format!("{} < {input}", k.leaf(leaf));
            let Some(cpu) = over(&line, |l| best_of(reps, l, Figure::Cpu))? else {
                row(&[
                    scene.clone(),
                    name.clone(),
                    "over 120".into(),
                    "—".into(),
                    "—".into(),
                    "—".into(),
                    "no: over 120 s".into(),
                ]);
                continue;
            };
            let wall = measure::run(&line)?.wall_s;
            let mb = measure::run(&format!("exec {line}"))?.max_rss_kib / 1024;
            let z = *zcpu.get_or_insert(cpu);
            let ok = if mb >= 256 {
                "no: memory"
            } else if cpu >= 30.0 {
                "no: CPU time"
            } else if wall >= 30.0 {
                "CPU yes, wall no"
            } else {
                "yes"
            };
            row(&[
                scene.clone(),
                name.clone(),
                ms(wall),
                ms(cpu),
                mb.to_string(),
                quotient(cpu, z, 1),
                ok.into(),
            ]);
        }
    }
    println!();
    header(&[
        "scene planes N, 500x500",
        "pixels unlike the z-buffer",
        "share",
        "painter --split said it could not order",
        "within 0.5% or said",
    ]);
    let zbuf = k.leaf(&method_leaf(Kind::Hse, "zbuf")?);
    let split = format!("{} --split", k.leaf(&painter));
    for n in [5, 50, 400] {
        let input = k.screen(&format!("planes-{n}"), &format!("planes {n}"), "500x500")?;
        frame(&k, &input, &zbuf, "z.ppm")?;
        let err = frame(&k, &input, &split, "p.ppm")?;
        let (differ, pixels) = k.differing(&k.w("z.ppm"), &k.w("p.ppm"))?;
        let said = err.contains("could not order");
        let ok = differ * 200 < pixels || said;
        row(&[
            n.to_string(),
            differ.to_string(),
            format!("{:.2}%", differ as f64 * 100.0 / pixels.max(1) as f64),
            if said { "yes" } else { "no" }.into(),
            if ok { "yes" } else { "no" }.into(),
        ]);
    }
    Ok(())
}
