//! The workspace's shape: `proto` is the stream and the geometry, with no
//! command-line parser in it, and no stage crate depends on another stage crate (shared
//! code lives in the libraries: proto, stagecli, scan).

use pipeline_tests::repo_root;
use std::fs;

/// The stage crates: every folder under bins/.
fn stages() -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(repo_root().join("bins"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn no_stage_crate_depends_on_another() {
    let stages = stages();
    assert!(stages.len() >= 9, "{stages:?}");
    for stage in &stages {
        let manifest =
            fs::read_to_string(repo_root().join("bins").join(stage).join("Cargo.toml")).unwrap();
        for other in stages.iter().filter(|o| *o != stage) {
            assert!(
                !manifest.contains(&format!("path = \"../{other}\"")),
                "bins/{stage}/Cargo.toml depends on the stage crate {other}"
            );
        }
    }
}

#[test]
fn proto_has_no_command_line_parser() {
    let manifest = fs::read_to_string(repo_root().join("proto/Cargo.toml")).unwrap();
    let deps = manifest
        .split("[dependencies]")
        .nth(1)
        .and_then(|d| d.split("\n[").next())
        .unwrap();
    for cli in ["clap", "anyhow", "stagecli"] {
        assert!(
            !deps.lines().any(|l| l.trim_start().starts_with(cli)),
            "proto depends on {cli}"
        );
    }
}
