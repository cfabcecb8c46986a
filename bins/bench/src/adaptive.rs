//! `bench adaptive`: what adaptive supersampling saves: `render --aa ssK` against
//! `render --aa adaptiveK` (docs/antialiasing.md, "Adaptive supersampling"), the whole
//! pipeline and the supersample leaf alone, in interleaved rounds.
//!
//! The scene is `scene environment --polygons N --size WxH --seed 1` (thesis chapter
//! 5.2) in a file. Each round runs render at depth 0 with --aa ssK and --aa adaptiveK,
//! then the leaf alone on the screen-space stream (`supersample --samples K`, then with
//! --adaptive), so that a change in load falls on both alike. CPU seconds are the
//! medians of the rounds (each counts the start of the bash that runs it, which is
//! measured alone too and said). Last, the method alone: the frame's polygons resolved
//! by [`Supersample`] in this process, whole and adaptive in turn, its memory warm: the
//! sampling's own cost, without a process's start, its reading or its page faults. Run
//! it on one core to compare as CI's machine would: `taskset -c 0 target/bin/bench
//! adaptive`.

use crate::kit::{header, row, stat_count, Kit};
use crate::measure::{interleaved, median, median_of, ms, ratio, Figure};
use scan::frame::HiddenSurface;
use scan::supersample::Supersample;
use stagecli::{Context, Error, Result};
use std::time::Instant;

/// The options of `bench adaptive`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Samples a side: 2, 4, 8 or 16.
    #[arg(long, default_value_t = 4)]
    pub samples: u32,
    /// The environment's polygons.
    #[arg(long, default_value_t = 1024)]
    pub polygons: u32,
    /// The screen.
    #[arg(long, default_value = "500x500")]
    pub size: String,
    /// Rounds (default 11).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub reps: Option<u32>,
    /// One round: a check that it works.
    #[arg(long)]
    pub quick: bool,
    /// Also time DIR's render (another build's binaries, as they are) with both modes in
    /// the same rounds, and print its figures beside these: a change measured before and
    /// after on the one machine at once.
    #[arg(long, value_name = "DIR")]
    pub before: Option<std::path::PathBuf>,
}

/// Runs `bench adaptive`.
pub fn main(a: &Args) -> Result<()> {
    let s = a.samples;
    if ![2, 4, 8, 16].contains(&s) {
        return Err(Error::usage(format!(
            "--samples must be 2, 4, 8 or 16, not {s}"
        )));
    }
    proto::numbers::parse_size(&a.size).map_err(|e| Error::usage(format!("--size: {e}")))?;
    let reps = a.reps.map_or(if a.quick { 1 } else { 11 }, |r| r as usize);
    let k = Kit::new()?;
    let (n, size) = (a.polygons, &a.size);
    let args = format!("environment --polygons {n} --size {size} --seed 1");
    let world = k.scene("world", &args)?;
    let screen = k.screen("screen", &args, size)?;
    let render = |aa: &str| k.render(&format!("--size {size} --depth 0 --aa {aa} {world}"));
    k.make("ss.ppm", &render(&format!("ss{s}")))?;
    k.make("adaptive.ppm", &render(&format!("adaptive{s}")))?;
    let (same, _) = k.differing(&k.w("ss.ppm"), &k.w("adaptive.ppm"))?;
    let leaf = format!("{} --samples {s}", k.b("supersample"));
    let stats = k.out(&format!(
        "{leaf} --adaptive --stats < {screen} 2>&1 >/dev/null"
    ))?;
    let mut lines = vec![
        render(&format!("ss{s}")),
        render(&format!("adaptive{s}")),
        format!("{leaf} < {screen}"),
        format!("{leaf} --adaptive < {screen}"),
        // The shell each line is run by, alone: its start is in every figure.
        "true".to_string(),
    ];
    let before = a.before.as_ref().map(|dir| {
        let render = crate::kit::q(&dir.join("render").display().to_string());
        let line = |aa: &str| format!("{render} --size {size} --depth 0 --aa {aa} {world}");
        (
            dir.display().to_string(),
            line(&format!("ss{s}")),
            line(&format!("adaptive{s}")),
        )
    });
    if let Some((_, ss, adaptive)) = &before {
        lines.extend([ss.clone(), adaptive.clone()]);
    }
    let runs = interleaved(reps, &lines)?;
    let method = in_process(&k.work("screen"), s, size, reps)?;
    println!(
        "{} `scene {args}`; CPU seconds, median of {reps} interleaved rounds.",
        crate::kit::stamp("adaptive")
    );
    println!();
    println!(
        "adaptive{s}'s frame against ss{s}'s: {same} pixels differ; {} of {} pixels sampled.",
        stat_count(&stats, "sampled")?,
        stat_count(&stats, "pixels out")?
    );
    println!();
    header(&[
        "what",
        &format!("ss{s} CPU s"),
        &format!("adaptive{s} CPU s"),
        "ratio",
    ]);
    for (i, what) in ["render", "leaf"].iter().enumerate() {
        let (x, y) = (
            median_of(&runs[2 * i], Figure::Cpu),
            median_of(&runs[2 * i + 1], Figure::Cpu),
        );
        row(&[(*what).into(), ms(x), ms(y), ratio(y, x)]);
    }
    // The method takes well under a millisecond on small screens: two more places.
    row(&[
        "method (in-process)".into(),
        format!("{:.5}", method.0),
        format!("{:.5}", method.1),
        ratio(method.1, method.0),
    ]);
    let shell = median_of(&runs[4], Figure::Cpu);
    let (ss, adaptive) = (
        median_of(&runs[2], Figure::Cpu),
        median_of(&runs[3], Figure::Cpu),
    );
    println!();
    println!(
        "Each figure counts the start of the shell that runs it ({:.1} ms of CPU alone); \
         the leaves less it: {}. The method's are wall seconds of `Supersample::resolve` \
         alone, in this process, its memory warm.",
        shell * 1000.0,
        ratio(adaptive - shell, ss - shell)
    );
    if let Some((dir, ..)) = &before {
        println!();
        println!("The render of {dir} in the same rounds:");
        println!();
        header(&["render", "before CPU s", "now CPU s", "now / before"]);
        for (i, what) in [format!("ss{s}"), format!("adaptive{s}")]
            .iter()
            .enumerate()
        {
            let (was, now) = (
                median_of(&runs[5 + i], Figure::Cpu),
                median_of(&runs[i], Figure::Cpu),
            );
            row(&[what.clone(), ms(was), ms(now), ratio(now, was)]);
        }
    }
    Ok(())
}

/// The seconds `Supersample::resolve` takes over the first frame of the screen-space
/// stream `screen` (a `size` screen), whole and adaptive, K = `k`: the medians of `reps`
/// interleaved rounds, in this process, after one round unmeasured (the memory warm).
fn in_process(screen: &std::path::Path, k: u32, size: &str, reps: usize) -> Result<(f64, f64)> {
    let (width, height) =
        proto::numbers::parse_size(size).map_err(|e| Error::usage(format!("--size: {e}")))?;
    let file = std::fs::File::open(screen).context(screen.display())?;
    let mut reader = proto::Reader::<proto::Token, _>::new(std::io::BufReader::new(file))?;
    let mut polygons = Vec::new();
    let mut token = proto::Token::default();
    while reader.next_into(&mut token)? {
        match &mut token {
            proto::Token::Polygon(p) => polygons.push(std::mem::take(p)),
            proto::Token::NextFrame | proto::Token::End => break,
            proto::Token::Skip(_) => {}
        }
    }
    let method = |adaptive: bool| -> Result<Supersample> {
        let m = Supersample::new(k, [0, 0, 0]).map_err(Error::usage)?;
        Ok(if adaptive { m.adaptive() } else { m })
    };
    let mut methods = [method(false)?, method(true)?];
    let mut out = Vec::new();
    let mut seconds = [Vec::new(), Vec::new()];
    for round in 0..=reps {
        for (m, times) in methods.iter_mut().zip(&mut seconds) {
            out.clear();
            let t = Instant::now();
            m.resolve(&polygons, width, height, &mut out);
            if round > 0 {
                times.push(t.elapsed().as_secs_f64());
            }
        }
    }
    Ok((median(&seconds[0]), median(&seconds[1])))
}
