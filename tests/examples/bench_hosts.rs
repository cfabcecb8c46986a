//! Benchmark: a movie rendered here, split by frames over 1, 2 and 3 loopback ssh hosts
//! (`render.sh --by frames`, the farm binary), and with the splitter tree's leaves or
//! subtrees on them
//! (`render.sh --hosts … --by leaves`, depth 2), with the bytes each link carried.
//!
//!     cargo run --release -p pipeline-tests --example bench_hosts [RUNS]
//!
//! Prints a Markdown table per movie: wall time (best of RUNS, default 3), frames per
//! second, the ratio to the local run, and per host the frames it rendered and the bytes
//! sent to it and back. The hosts are sshd servers on this machine (the test harness,
//! `pipeline_tests::hosts`), so they share its cores: on a 2-core machine the figures show
//! the cost of the ssh transport and the splitting, not a speed-up. The link bytes are
//! what a reader needs to work the speed-up out for real hosts: a chunk's time there is
//! its frames' render time plus its bytes over the link.

use pipeline_tests::hosts::{Host, Hosts};
use pipeline_tests::{bin, bin_dir, repo_root};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

struct Movie {
    label: &'static str,
    scene: Vec<&'static str>,
    size: &'static str,
}

fn main() {
    let runs: usize = std::env::args()
        .nth(1)
        .map(|a| a.parse().expect("RUNS: a number"))
        .unwrap_or(3);
    bin_dir();
    let Some(hosts) = Hosts::start(&[Host::Serving, Host::Serving, Host::Serving]) else {
        std::process::exit(1);
    };
    let movies = [
        Movie {
            label: "300-frame movie: two intersecting spheres (scene spheres), 320×240",
            scene: vec!["spheres", "--frames", "300"],
            size: "320x240",
        },
        Movie {
            label: "fill-heavy movie: 30 frames of 2,000 quads, Dc 10, 960×540",
            scene: vec![
                "environment",
                "--frames",
                "30",
                "--polygons",
                "2000",
                "--depth-complexity",
                "10",
                "--size",
                "960x540",
                "--seed",
                "2",
            ],
            size: "960x540",
        },
        Movie {
            label: "fill-heavy scene: one frame of 10,000 quads, Dc 10, 1920×1080",
            scene: vec![
                "environment",
                "--frames",
                "1",
                "--polygons",
                "10000",
                "--depth-complexity",
                "10",
                "--size",
                "1920x1080",
                "--seed",
                "2",
            ],
            size: "1920x1080",
        },
    ];
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    println!("Machine: {cores} cores; best of {runs} runs; loopback sshd hosts.\n");
    for movie in &movies {
        let path = hosts.dir().join("movie.pp");
        let out = Command::new(bin("scene"))
            .args(&movie.scene)
            .output()
            .unwrap();
        assert!(out.status.success());
        std::fs::write(&path, &out.stdout).unwrap();
        let frames: usize = movie
            .scene
            .iter()
            .position(|&a| a == "--frames")
            .map(|i| movie.scene[i + 1].parse().unwrap())
            .unwrap();
        println!("### {}\n", movie.label);
        println!("Scene stream: {} bytes.\n", out.stdout.len());
        println!("| run | wall s | frames/s | × local time | per host: frames, bytes sent → bytes back |");
        println!("|---|---|---|---|---|");
        let (local, local_bytes) = best(runs, || {
            let mut cmd = Command::new("bash");
            cmd.arg(repo_root().join("scripts/render.sh"))
                .args(["--size", movie.size])
                .arg(&path);
            cmd
        });
        row("render.sh here", local, local, frames, "");
        for n in 1..=3 {
            let names = (1..=n)
                .map(|k| format!("node{k}"))
                .collect::<Vec<_>>()
                .join(",");
            let mut links = String::new();
            let (t, bytes) = best(runs, || {
                let mut cmd = Command::new("bash");
                cmd.arg(repo_root().join("scripts/render.sh"))
                    .args(["--hosts", &names, "--by", "frames"])
                    .args(["--size", movie.size, "--stats"])
                    .arg(&path)
                    .env("POLYPIPE_SSH", hosts.ssh());
                cmd
            });
            assert_eq!(
                bytes.0, local_bytes.0,
                "{n} hosts: not the local run's bytes"
            );
            let farm = stagecli::stats::records_of(&bytes.1, "farm").unwrap_or_default();
            for r in farm.iter().filter(|r| r.get("sent_bytes").is_some()) {
                let get = |key: &str| r.get(key).unwrap_or("?");
                links += &format!(
                    "{} {} fr, {} → {}; ",
                    get("host"),
                    get("frames"),
                    get("sent_bytes"),
                    get("received_bytes")
                );
            }
            row(
                &format!("--by frames, {n} host{}", if n > 1 { "s" } else { "" }),
                t,
                local,
                frames,
                links.trim_end_matches("; "),
            );
        }
        let (local2, local2_bytes) = best(runs, || {
            let mut cmd = Command::new("bash");
            cmd.arg(repo_root().join("scripts/render.sh"))
                .args(["--size", movie.size, "--depth", "2"])
                .arg(&path);
            cmd
        });
        assert_eq!(
            local2_bytes.0, local_bytes.0,
            "depth 2: not depth 0's bytes"
        );
        row("render.sh here, depth 2", local2, local, frames, "");
        for n in 1..=3 {
            let names = (1..=n)
                .map(|k| format!("node{k}"))
                .collect::<Vec<_>>()
                .join(",");
            let (t, bytes) = best(runs, || {
                let mut cmd = Command::new("bash");
                cmd.arg(repo_root().join("scripts/render.sh"))
                    .args(["--hosts", &names, "--by", "leaves", "--depth", "2"])
                    .args(["--size", movie.size, "--stats"])
                    .arg(&path)
                    .env("POLYPIPE_SSH", hosts.ssh());
                cmd
            });
            assert_eq!(
                bytes.0, local_bytes.0,
                "{n} hosts: not the local run's bytes"
            );
            // render's records of the links: node, host, bytes there and back.
            let links: Vec<String> = stagecli::stats::records_of(&bytes.1, "render")
                .unwrap_or_default()
                .iter()
                .filter(|r| r.get("bytes_back").is_some())
                .map(|r| {
                    let get = |key: &str| r.get(key).unwrap_or("?");
                    format!(
                        "node {} on host {}: {} → {}",
                        get("node"),
                        get("host"),
                        get("bytes_there"),
                        get("bytes_back")
                    )
                })
                .collect();
            row(
                &format!(
                    "--by leaves, depth 2, {n} host{}",
                    if n > 1 { "s" } else { "" }
                ),
                t,
                local,
                frames,
                &links.join("; "),
            );
        }
        println!();
    }
}

/// Runs `make()` `runs` times; the best wall time, and (stdout, stderr) of the last run.
fn best(runs: usize, make: impl Fn() -> Command) -> (Duration, (Vec<u8>, String)) {
    let mut best = Duration::MAX;
    let mut last = (Vec::new(), String::new());
    for _ in 0..runs {
        let start = Instant::now();
        let out = make().stdin(Stdio::null()).output().expect("run");
        let took = start.elapsed();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        best = best.min(took);
        last = (
            out.stdout,
            String::from_utf8_lossy(&out.stderr).into_owned(),
        );
    }
    (best, last)
}

fn row(label: &str, t: Duration, local: Duration, frames: usize, links: &str) {
    let s = t.as_secs_f64();
    println!(
        "| {label} | {s:.2} | {:.1} | {:.2} | {links} |",
        frames as f64 / s,
        s / local.as_secs_f64()
    );
}
