//! `bench aa`: what anti-aliasing costs at a leaf: each anti-aliasing leaf of render
//! (--aa: point sampling, supersampling 2x2 to 16x16, the a-buffer; docs/antialiasing.md)
//! alone on one screen-space frame, its time, memory and output.
//!
//! The scene is `scene environment` (thesis chapter 5.2) taken to screen space once;
//! each leaf then reads that file, so that only the leaf is timed. Wall and CPU seconds
//! are the medians of N runs (default 3), interleaved; peak resident KiB that of one more
//! run, and the output bytes what the leaf sends to the merger.

use crate::kit::{header, methods_list, row, stat_count, Kind, Kit};
use crate::measure::{self, interleaved, median_of, ms, Figure};
use stagecli::{Error, Result};

/// The options of `bench aa`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The scene's polygons (default 100000; --quick 5000).
    #[arg(long)]
    pub polygons: Option<usize>,
    /// The screen (default 1920x1080; --quick 480x270).
    #[arg(long)]
    pub size: Option<String>,
    /// Runs of each command (default 3).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub reps: Option<u32>,
    /// 5,000 polygons at 480x270, one run each: a check that it works.
    #[arg(long)]
    pub quick: bool,
}

/// Runs `bench aa`.
pub fn main(a: &Args) -> Result<()> {
    let (n, size) = if a.quick {
        (5000, "480x270")
    } else {
        (100_000, "1920x1080")
    };
    let n = a.polygons.unwrap_or(n);
    let size = a.size.clone().unwrap_or(size.into());
    proto::numbers::parse_size(&size).map_err(|e| Error::usage(format!("--size: {e}")))?;
    let reps = a.reps.map_or(if a.quick { 1 } else { 3 }, |r| r as usize);
    let k = Kit::new()?;
    let args = format!("environment --polygons {n} --size {size} --seed 1");
    let screen = k.screen("screen", &args, &size)?;
    let stats = k.out(&format!(
        "{} --stats < {screen} 2>&1 >/dev/null",
        k.b("scanconv")
    ))?;
    let polygons = stat_count(&stats, "polygons in")?;
    println!(
        "{} `scene {args}`, {polygons} polygons into one leaf (depth 0); wall and CPU seconds \
         the median of {reps}.",
        crate::kit::stamp("aa")
    );
    println!();
    header(&[
        "method",
        "leaf",
        "wall s",
        "CPU s",
        "peak KiB",
        "output bytes",
    ]);
    let methods = methods_list(Kind::Aa);
    let lines: Vec<String> = methods
        .iter()
        .map(|(_, leaf)| format!("{} < {screen}", k.leaf(leaf)))
        .collect();
    let runs = interleaved(reps, &lines)?;
    for ((name, leaf), (line, r)) in methods.iter().zip(lines.iter().zip(&runs)) {
        let kib = measure::run(&format!("exec {line}"))?.max_rss_kib;
        let out = k.make("out", line)?;
        row(&[
            name.clone(),
            format!("`{leaf}`"),
            ms(median_of(r, Figure::Wall)),
            ms(median_of(r, Figure::Cpu)),
            kib.to_string(),
            std::fs::metadata(out).map_or(0, |m| m.len()).to_string(),
        ]);
    }
    Ok(())
}
