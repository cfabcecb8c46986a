//! Thesis 5.1.3, "The Bottleneck", measured (`chart thesis --measure`).
//!
//! The thesis compares clipping and the two coordinate transformations with the best and
//! worst hidden-surface algorithm of [SuSp74]'s table 7 in three environments, A, B and
//! C, given by their statistics E_t (the edges in the environment, before clipping) and
//! E_r (the relevant edges, those that survive the clipper): 800/400, 20K/10K and
//! 480K/240K. Its table is in abstract units of time (complexity factors); here each
//! environment is built with `scene environment` (four-sided polygons, so P_t = E_t/4,
//! half wholly outside the pyramid, so E_r ≈ E_t/2; `--scale` shrinks them) and every
//! stage is timed alone on its input, CPU seconds (user + system, `/usr/bin/time`) on
//! one core (`taskset -c 0` where there is one), a frame: a small environment is run as
//! a movie of several frames so that the times are more than the timer's resolution.

use crate::error::{Context, Error, Result};
use proto::{Reader, Token};
use std::path::Path;
use std::process::{Command, Stdio};

/// The environments: name, E_t, E_r (thesis 5.1.3, from [SuSp74]).
pub const ENVIRONMENTS: [(&str, u64, u64); 3] = [
    ("A", 800, 400),
    ("B", 20_000, 10_000),
    ("C", 480_000, 240_000),
];

/// The thesis's table (units of time): HSE best, HSE worst, clipping, viewing
/// transformation, perspective transformation.
pub const THESIS: [[f64; 5]; 3] = [
    [140e3, 2.4e9, 8e3, 8e3, 4e3],
    [1.4e6, 62e9, 200e3, 200e3, 100e3],
    [7.5e6, 1500e9, 4.8e6, 4.8e6, 2.4e6],
];

/// One environment measured: its statistics as built and CPU seconds a frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Measured {
    pub name: String,
    pub polygons: u64,
    pub frames: u64,
    /// E_t and E_r as built (edges a frame before and after the clipper).
    pub et: u64,
    pub er: u64,
    pub viewing: f64,
    pub clipping: f64,
    pub perspective: f64,
    /// Each hidden-surface method of the leaves (methods::METHODS' `--hse` rows), alone.
    pub hse: Vec<(String, f64)>,
}

impl Measured {
    pub fn best(&self) -> (&str, f64) {
        self.hse
            .iter()
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map_or(("", f64::NAN), |(n, t)| (n.as_str(), *t))
    }
    pub fn worst(&self) -> (&str, f64) {
        self.hse
            .iter()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map_or(("", f64::NAN), |(n, t)| (n.as_str(), *t))
    }
}

/// Edges (vertices) a frame in a stream, and its frames.
fn edges_in(path: &Path) -> Result<(u64, u64)> {
    let file =
        std::fs::File::open(path).with_context(|| format!("cannot open {}", path.display()))?;
    let mut reader = Reader::<Token, _>::new(std::io::BufReader::new(file))
        .with_context(|| format!("reading {}", path.display()))?;
    let (mut edges, mut frames) = (0u64, 0u64);
    loop {
        match reader
            .next_record()
            .with_context(|| format!("reading {}", path.display()))?
        {
            Some(Token::Polygon(p)) => edges += p.vertices.len() as u64,
            Some(Token::Skip(_)) => {}
            Some(Token::NextFrame) => frames += 1,
            Some(Token::End) | None => return Ok((edges, frames + 1)),
        }
    }
}

/// CPU seconds (user + system) of `args` run on one core, `input` to `output`.
fn cpu(bin: &Path, args: &[&str], input: &Path, output: &Path, work: &Path) -> Result<f64> {
    let times = work.join("time");
    let mut cmd = if Path::new("/usr/bin/taskset").exists() {
        let mut c = Command::new("/usr/bin/taskset");
        c.args(["-c", "0", "/usr/bin/time"]);
        c
    } else {
        Command::new("/usr/bin/time")
    };
    let status = cmd
        .args(["-f", "%U %S", "-o"])
        .arg(&times)
        .arg(bin.join(args[0]))
        .args(&args[1..])
        .stdin(std::fs::File::open(input)?)
        .stdout(std::fs::File::create(output)?)
        .stderr(Stdio::null())
        .status()
        .with_context(|| format!("cannot run {}", args[0]))?;
    if !status.success() {
        return Err(Error::Data(format!("{} failed ({status})", args.join(" "))));
    }
    let text = std::fs::read_to_string(&times)?;
    let line = text.lines().last().unwrap_or_default();
    let parts: Vec<f64> = line
        .split_whitespace()
        .map(|w| w.parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| Error::Data(format!("/usr/bin/time wrote `{line}`: {e}")))?;
    Ok(parts.iter().sum())
}

/// Builds and times the three environments, scaled by `scale` (1: the thesis's sizes).
pub fn measure(bin: &Path, work: &Path, scale: f64) -> Result<Vec<Measured>> {
    std::fs::create_dir_all(work)?;
    let size = "500x500";
    let mut out = Vec::new();
    for (name, et, _) in ENVIRONMENTS {
        let polygons = ((et as f64 * scale / 4.0).round() as u64).max(2);
        // About 200,000 polygons timed in all (the timer counts hundredths of a
        // second), at least a frame.
        let frames = (200_000 / polygons).clamp(1, 1000);
        let world = work.join(format!("{name}.world"));
        let status = Command::new(bin.join("scene"))
            .args([
                "environment",
                "--clipped",
                "0.5",
                "--seed",
                "1",
                "--size",
                size,
            ])
            .args([
                "--polygons",
                &polygons.to_string(),
                "--frames",
                &frames.to_string(),
            ])
            .stdout(std::fs::File::create(&world)?)
            .status()
            .context("cannot run scene")?;
        if !status.success() {
            return Err(Error::Data(format!("scene environment failed for {name}")));
        }
        let (eye, clipped, screen, sink) = (
            work.join(format!("{name}.eye")),
            work.join(format!("{name}.clipped")),
            work.join(format!("{name}.screen")),
            work.join("out"),
        );
        let per = |t: f64| t / frames as f64;
        let viewing = per(cpu(bin, &["viewxf", "--size", size], &world, &eye, work)?);
        let clipping = per(cpu(bin, &["clipbatch"], &eye, &clipped, work)?);
        let perspective = per(cpu(
            bin,
            &["persp", "--size", size],
            &clipped,
            &screen,
            work,
        )?);
        let mut hse = Vec::new();
        for m in methods::METHODS {
            if let methods::Selector::Hse(n) = m.selector {
                hse.push((n.to_string(), per(cpu(bin, m.stage, &screen, &sink, work)?)));
            }
        }
        let (world_edges, nframes) = edges_in(&world)?;
        let (clipped_edges, _) = edges_in(&clipped)?;
        out.push(Measured {
            name: name.into(),
            polygons,
            frames: nframes,
            et: world_edges / nframes,
            er: clipped_edges / nframes,
            viewing,
            clipping,
            perspective,
            hse,
        });
    }
    Ok(out)
}

fn units(v: f64) -> String {
    match v {
        v if v >= 1e9 => format!("{}B", v / 1e9),
        v if v >= 1e6 => format!("{}M", v / 1e6),
        v if v >= 1e3 => format!("{}K", v / 1e3),
        v => format!("{v}"),
    }
}

/// The thesis's table and ours, and the verdict: is hidden-surface elimination still the
/// bottleneck, by what factor (the best method against the slowest of the other three
/// stages), which method is best and worst.
pub fn report(rows: &[Measured], scale: f64) -> String {
    let mut s = String::from(
        "Thesis 5.1.3, \"The Bottleneck\": [SuSp74] table 7's best and worst HSE against clipping and the two transformations\n\n\
         thesis (units of time)\n\
         env  E_t    E_r    HSE(best)  HSE(worst)  clipping  viewing  perspective  best HSE / slowest other\n",
    );
    for (i, (name, et, er)) in ENVIRONMENTS.iter().enumerate() {
        let t = THESIS[i];
        s += &format!(
            "{name:<4} {:<6} {:<6} {:<10} {:<11} {:<9} {:<8} {:<12} {:.1}\n",
            units(*et as f64),
            units(*er as f64),
            units(t[0]),
            units(t[1]),
            units(t[2]),
            units(t[3]),
            units(t[4]),
            t[0] / t[2].max(t[3]).max(t[4])
        );
    }
    s += &format!(
        "\nmeasured here (CPU seconds a frame, one core; environments at {scale} of the thesis's size)\n\
         env  E_t     E_r     polygons frames  HSE(best)           HSE(worst)          clipping  viewing   perspective  best HSE / slowest other\n"
    );
    for r in rows {
        let (bn, bt) = r.best();
        let (wn, wt) = r.worst();
        let other = r.clipping.max(r.viewing).max(r.perspective);
        s += &format!(
            "{:<4} {:<7} {:<7} {:<8} {:<7} {:<19} {:<19} {:<9.5} {:<9.5} {:<12.5} {}\n",
            r.name,
            r.et,
            r.er,
            r.polygons,
            r.frames,
            format!("{bt:.5} {bn}"),
            format!("{wt:.5} {wn}"),
            r.clipping,
            r.viewing,
            r.perspective,
            if other > 0.0 {
                format!("{:.1}", bt / other)
            } else {
                "-".into()
            }
        );
    }
    s += "\nevery hidden-surface method (CPU seconds a frame):\n";
    for r in rows {
        let all: Vec<String> = r.hse.iter().map(|(n, t)| format!("{n} {t:.5}")).collect();
        s += &format!("{}: {}\n", r.name, all.join(", "));
    }
    s
}
