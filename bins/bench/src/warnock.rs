//! `bench warnock`: where Warnock's area subdivision and the hidden-line drawing slow
//! down, against the z-buffer leaf: each leaf alone on screen-space scenes (`scene
//! screen`) that make one cost grow at a time, file to /dev/null.
//!
//! CPU seconds of `scanconv --resolve` (the z-buffer leaf render runs), `warnock` and
//! `hiddenline` (SVG): the least of N runs (default 3); hiddenline runs once where one
//! run takes over 5 s. Peak resident KiB from one more run. "pixels ≠ zbuf" is the
//! pixels of warnock's frame unlike the z-buffer's; from warnock --stats, the windows it
//! visited, those decided pixel by pixel and the polygons its Looker looked at; from
//! hiddenline --stats, the visible edge pieces it draws. Newman and Sproull, 14.3.4, on
//! what Warnock's cost follows.
//!
//! Scenes (`scene screen KIND N`): stack-N (N full-screen squares, shuffled), slivers-N
//! (N triangles 0.4 px wide at the base, crossing), pinhead-N (N triangles around one
//! pixel's centre), tiles-K (K x K tiles in front of 2,000 squares), hidden-N (8 x 8
//! tiles in front of N squares), penetrate (two full-screen planes crossing).

use crate::kit::{header, method_leaf, row, stat_count, Kind, Kit};
use crate::measure::{self, best_of, ms, Figure};
use stagecli::{Error, Result};

/// The options of `bench warnock`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The screen.
    #[arg(long, default_value = "500x500")]
    pub size: String,
    /// Runs of each command (default 3).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub reps: Option<u32>,
    /// A tenth of the polygons and one run each: a check that it works.
    #[arg(long)]
    pub quick: bool,
}

/// The windows warnock visited: the sum of its "windows by depth: N N …;" list.
pub fn windows(stats: &str) -> Result<u64> {
    let list = stats
        .split_once("windows by depth: ")
        .and_then(|(_, rest)| rest.split_once(';'))
        .map(|(list, _)| list)
        .ok_or_else(|| Error::data(format!("no windows by depth in: {stats}")))?;
    Ok(list
        .split_whitespace()
        .filter_map(|n| n.parse::<u64>().ok())
        .sum())
}

/// Runs `bench warnock`.
pub fn main(a: &Args) -> Result<()> {
    proto::numbers::parse_size(&a.size).map_err(|e| Error::usage(format!("--size: {e}")))?;
    let k = Kit::new()?;
    let size = &a.size;
    let reps = a.reps.map_or(if a.quick { 1 } else { 3 }, |r| r as usize);
    let d = if a.quick { 10 } else { 1 };
    let scenes: Vec<(String, String)> = [
        ("stack", 1000 / d),
        ("stack", 20000 / d),
        ("slivers", 1000 / d),
        ("slivers", 10000 / d),
        ("pinhead", 10000 / d),
        ("pinhead", 100000 / d),
    ]
    .iter()
    .map(|(kind, n)| (format!("{kind}-{n}"), format!("{kind} {n}")))
    .chain([2, 8, 32, 128].iter().map(|t| {
        (
            format!("tiles-{t}"),
            format!("tiles {t} --behind {}", 2000 / d),
        )
    }))
    .chain(
        [1000 / d, 10000 / d, 100000 / d]
            .iter()
            .map(|n| (format!("hidden-{n}"), format!("tiles 8 --behind {n}"))),
    )
    .chain([("penetrate".to_string(), "penetrate".to_string())])
    .collect();
    let z = k.leaf(&method_leaf(Kind::Hse, "zbuf")?);
    let w = k.leaf(&method_leaf(Kind::Hse, "warnock")?);
    let h = k.leaf(&method_leaf(Kind::Lines, "hiddenline")?);
    println!("## warnock and hiddenline against the z-buffer leaf, {size} (CPU s, best of {reps}; peak KiB)");
    println!();
    println!(
        "{} Each leaf alone, file to /dev/null.",
        crate::kit::stamp("warnock")
    );
    println!();
    header(&[
        "scene",
        "polygons",
        "visible edges",
        "zbuf s",
        "warnock s",
        "hiddenline s",
        "zbuf KiB",
        "warnock KiB",
        "hiddenline KiB",
        "windows",
        "pixel windows",
        "looked at",
        "pixels ≠ zbuf",
    ]);
    let peak =
        |line: &str| -> Result<u64> { Ok(measure::run(&format!("exec {line}"))?.max_rss_kib) };
    for (name, words) in scenes {
        eprintln!("bench: {name}");
        let f = k.scene(
            &format!("{name}.pp"),
            &format!("screen {words} --size {size}"),
        )?;
        let zs = best_of(reps, &format!("{z} < {f}"), Figure::Cpu)?;
        let ws = best_of(reps, &format!("{w} < {f}"), Figure::Cpu)?;
        let mut hs = measure::run(&format!("{h} < {f}"))?.cpu_s;
        if hs < 5.0 {
            hs = best_of(reps, &format!("{h} < {f}"), Figure::Cpu)?;
        }
        let (zk, wk, hk) = (
            peak(&format!("{z} < {f}"))?,
            peak(&format!("{w} < {f}"))?,
            peak(&format!("{h} < {f}"))?,
        );
        let wstats = k.out(&format!("{w} --stats < {f} 2>&1 > {}", k.w("w.runs")))?;
        let hstats = k.out(&format!("{h} --stats < {f} 2>&1 > /dev/null"))?;
        k.make("z.ppm", &format!("{z} < {f} | {}", k.b("zbuf")))?;
        k.make("w.ppm", &format!("{} < {}", k.b("zbuf"), k.w("w.runs")))?;
        row(&[
            name,
            stat_count(&wstats, "polygons in")?.to_string(),
            stat_count(&hstats, "pieces drawn;")?.to_string(),
            ms(zs),
            ms(ws),
            ms(hs),
            zk.to_string(),
            wk.to_string(),
            hk.to_string(),
            windows(&wstats)?.to_string(),
            stat_count(&wstats, "single pixels")?.to_string(),
            stat_count(&wstats, "polygons looked at")?.to_string(),
            k.differing(&k.w("z.ppm"), &k.w("w.ppm"))?.0.to_string(),
        ]);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn windows_sums_the_list_by_depth() {
        let s = "warnock: 5 polygons in, windows by depth: 1 4 16; 3 single pixels";
        assert_eq!(super::windows(s).unwrap(), 21);
        assert!(super::windows("warnock: nothing").is_err());
    }
}
