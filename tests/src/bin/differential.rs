//! differential: the differential suite's long runs (`pipeline_tests::differential`).
//!
//! Runs the scenes of seeds S, S+1, … through every mode that claims the reference's
//! bytes, prints each broken claim as it is found (seed, mode, what differs, and the
//! commands that show it), a tally by mode every so often and at the end. Exit status 0
//! when every claim held, 1 when one broke, 2 usage.

use clap::Parser;
use pipeline_tests::differential::{check, generate, Plan};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// Random scenes, every mode against what it claims to equal (docs/fuzzing.md).
#[derive(Parser)]
#[command(name = "differential", version)]
struct Args {
    /// The first seed; case i runs seed S + i.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// How many scenes.
    #[arg(long, default_value_t = 100)]
    cases: u64,
    /// Every mode at every tree depth 0–4 (else depth 0 and one other a mode).
    #[arg(long)]
    all_depths: bool,
    /// Leave out a mode, or every mode it begins (`painter-split`, `ss4@2`); repeatable.
    #[arg(long)]
    skip: Vec<String>,
    /// Run only the modes this begins (`ss`, `painter`, `leaf-`); repeatable.
    #[arg(long)]
    only: Vec<String>,
    /// Print the scene of --seed as text and exit.
    #[arg(long)]
    print_scene: bool,
    /// The stage binaries' folder (default: this binary's).
    #[arg(long)]
    bin_dir: Option<PathBuf>,
    /// Print at most this many failures of each mode in full (the tallies count them all).
    #[arg(long, default_value_t = 5)]
    show: usize,
    /// Seconds between tallies on stdout.
    #[arg(long, default_value_t = 300)]
    tally_every: u64,
}

fn tally(
    cases: u64,
    start: Instant,
    ran: &BTreeMap<String, u64>,
    failed: &BTreeMap<String, Vec<u64>>,
) {
    let mut out = std::io::stdout().lock();
    let _ = writeln!(
        out,
        "tally: {cases} cases in {:.0} s, {} mode runs; failures by mode:{}",
        start.elapsed().as_secs_f64(),
        ran.values().sum::<u64>(),
        if failed.is_empty() { " none" } else { "" }
    );
    for (mode, seeds) in failed {
        let shown: Vec<String> = seeds.iter().take(12).map(|s| s.to_string()).collect();
        let _ = writeln!(
            out,
            "  {mode}: {} of {} runs, seeds {}{}",
            seeds.len(),
            ran.get(mode).copied().unwrap_or(0),
            shown.join(" "),
            if seeds.len() > 12 { " …" } else { "" }
        );
    }
    let _ = out.flush();
}

fn main() -> ExitCode {
    let args = Args::parse();
    if args.print_scene {
        print!("{}", generate(args.seed).text);
        return ExitCode::SUCCESS;
    }
    let bins = args.bin_dir.clone().unwrap_or_else(|| {
        std::env::current_exe()
            .ok()
            .and_then(|e| e.parent().map(PathBuf::from))
            .unwrap_or_else(|| PathBuf::from("."))
    });
    for need in [
        "render",
        "zspec",
        "zbuf",
        "painter",
        "scanline",
        "warnock",
        "abuf",
        "supersample",
        "scanconv",
    ] {
        if !bins.join(need).is_file() {
            eprintln!("differential: no {need} in {}; build the binaries (cargo build --release --workspace --bins) or give --bin-dir", bins.display());
            return ExitCode::from(2);
        }
    }
    let plan = Plan {
        all_depths: args.all_depths,
        one_depth: false,
        skip: args.skip.clone(),
        only: args.only.clone(),
    };
    let start = Instant::now();
    let mut last = Instant::now();
    let mut ran: BTreeMap<String, u64> = BTreeMap::new();
    let mut failed: BTreeMap<String, Vec<u64>> = BTreeMap::new();
    let mut cases = 0;
    for i in 0..args.cases {
        let seed = args.seed.wrapping_add(i);
        let scene = generate(seed);
        let (failures, modes) = check(&scene, &bins, &plan);
        for m in modes {
            *ran.entry(m).or_default() += 1;
        }
        for f in &failures {
            let seeds = failed.entry(f.mode.clone()).or_default();
            if seeds.len() < args.show {
                println!("FAIL {f}");
            }
            seeds.push(seed);
        }
        cases += 1;
        if last.elapsed() >= Duration::from_secs(args.tally_every) {
            tally(cases, start, &ran, &failed);
            last = Instant::now();
        }
    }
    tally(cases, start, &ran, &failed);
    if failed.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
