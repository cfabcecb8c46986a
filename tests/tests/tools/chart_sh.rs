//! `scripts/chart.sh` builds only what is out of date: it runs cargo when a binary is
//! missing or older than its sources (render.sh's check, scripts/lib/binaries.sh), not on
//! every run.

use pipeline_tests::sh;

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// `chart.sh` ran cargo on every run; now it runs it only when a binary is missing or
/// older than its sources (render.sh's check, scripts/lib/binaries.sh). A `cargo` first
/// on PATH that records being run shows it.
#[test]
fn chart_sh_runs_no_cargo_when_the_binaries_are_current() {
    let dir = tempfile::tempdir().unwrap();
    // Once with the real cargo, which leaves the binaries and the freshness stamp
    // current.
    let out = sh("scripts/chart.sh --help > /dev/null", b"");
    assert!(out.status.success(), "{}", stderr(&out));
    let fake = dir.path().join("cargo");
    std::fs::write(
        &fake,
        format!("#!/bin/sh\ntouch '{}/ran'\nexit 1\n", dir.path().display()),
    )
    .unwrap();
    std::process::Command::new("chmod")
        .arg("+x")
        .arg(&fake)
        .status()
        .unwrap();
    let out = sh(
        &format!(
            "PATH='{}':$PATH scripts/chart.sh --help | head -n 1",
            dir.path().display()
        ),
        b"",
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(!out.stdout.is_empty());
    assert!(!dir.path().join("ran").exists(), "chart.sh ran cargo");
}
