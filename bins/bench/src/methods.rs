//! `bench methods`: each hidden-surface method of render (--hse) at every splitter
//! depth, on the four scene classes of `bench llvmpipe`: whole process, wall seconds.
//!
//! Scenes (`scene environment`, thesis chapter 5.2): (a) 1,024 quads at 500x500; (b)
//! 100,000 quads at Dc 2; (c) the fill-heavy scene, 10,000 quads at Dc 10 at
//! 1920x1080; (d) a movie of 1,024 quads, 100 frames. Each cell is the median of N runs
//! (default 3) of `render --hse METHOD --depth D`; the table gives each method's time at
//! depth 0, its best depth of 0-4 and the time there, and that best over the z-buffer's
//! best. The leaf methods alone are measured by `bench painter`, `bench scanline`,
//! `bench warnock` and `bench aa`; their bounds on hostile scenes by `bench bounds`.

use crate::kit::{header, methods_list, row, Kind, Kit};
use crate::measure::{interleaved, median_of, ms, ratio, Figure};
use stagecli::Result;

/// The options of `bench methods`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Runs of each command (default 3).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub reps: Option<u32>,
    /// Smaller scenes, depths 0 and 2, one run each: a check that it works.
    #[arg(long)]
    pub quick: bool,
}

/// Runs `bench methods`.
pub fn main(a: &Args) -> Result<()> {
    let k = Kit::new()?;
    let reps = a.reps.map_or(if a.quick { 1 } else { 3 }, |r| r as usize);
    let (env_n, geo_n, fill_n, fill_size, frames, depths): (u32, u32, u32, &str, u32, &[u32]) =
        if a.quick {
            (256, 5000, 1000, "480x270", 5, &[0, 2])
        } else {
            (1024, 100_000, 10_000, "1920x1080", 100, &[0, 1, 2, 3, 4])
        };
    let scenes = [
        (
            "500x500",
            format!("(a) {env_n} quads"),
            format!("--seed 1 --polygons {env_n} --size 500x500"),
        ),
        (
            "500x500",
            format!("(b) {geo_n} quads, Dc≈2"),
            format!("--seed 3 --polygons {geo_n} --depth-complexity 2 --size 500x500"),
        ),
        (
            fill_size,
            format!("(c) {fill_n} quads, Dc≈10, {fill_size}"),
            format!("--seed 2 --polygons {fill_n} --depth-complexity 10 --size {fill_size}"),
        ),
        (
            "500x500",
            format!("(d) {env_n} quads × {frames} frames"),
            format!("--seed 4 --polygons {env_n} --frames {frames} --size 500x500"),
        ),
    ];
    let methods: Vec<String> = methods_list(Kind::Hse).into_iter().map(|m| m.0).collect();
    println!(
        "{} render whole process, wall seconds, median of {reps}. The last column is the \
         method's best time over the z-buffer's best.",
        crate::kit::stamp(&format!("methods{}", if a.quick { " --quick" } else { "" }))
    );
    println!();
    header(&[
        "scene",
        "method",
        "depth 0 s",
        "best depth",
        "best s",
        "best / zbuf best",
    ]);
    for (i, (size, label, args)) in scenes.iter().enumerate() {
        let file = k.scene(&format!("scene{i}"), &format!("environment {args}"))?;
        let mut lines = Vec::new();
        for m in &methods {
            for d in depths {
                lines.push(k.render(&format!("--size {size} --hse {m} --depth {d} {file}")));
            }
        }
        eprintln!("bench: {label}");
        let runs = interleaved(reps, &lines)?;
        let at = |mi: usize, di: usize| median_of(&runs[mi * depths.len() + di], Figure::Wall);
        let best = |mi: usize| {
            (0..depths.len())
                .map(|di| (at(mi, di), depths[di]))
                .fold((f64::MAX, 0), |b, x| if x.0 < b.0 { x } else { b })
        };
        let z = methods
            .iter()
            .position(|m| m == "zbuf")
            .map_or(0.0, |zi| best(zi).0);
        for (mi, m) in methods.iter().enumerate() {
            let (t, d) = best(mi);
            row(&[
                label.clone(),
                m.clone(),
                ms(at(mi, 0)),
                d.to_string(),
                ms(t),
                ratio(t, z),
            ]);
        }
    }
    Ok(())
}
