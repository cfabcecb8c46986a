//! The workspace's shape: `proto` is the stream and the geometry, with no
//! command-line parser in it, and no stage crate depends on another crate under `bins/`
//! (shared code lives in the libraries: proto, stagecli, scan). The tools that compose,
//! plan and measure the stages (render, plan, chart) may use a stage's library, as chart
//! counts its statistics on the reference renderer's pixels.

use pipeline_tests::repo_root;
use std::fs;

/// The crates under bins/ that are not stages of the stream: the composer, the cost
/// model and the chart.
const TOOLS: [&str; 3] = ["chart", "plan", "render"];

/// The crates under bins/: every folder there.
fn bins() -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(repo_root().join("bins"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// The lines of a manifest's `[dependencies]` table (not its dev- or build-dependencies).
fn dependency_lines(manifest: &str) -> Vec<&str> {
    let mut inside = false;
    let mut lines = Vec::new();
    for line in manifest.lines().map(str::trim) {
        if line.starts_with('[') {
            inside = line == "[dependencies]";
        } else if inside && !line.is_empty() && !line.starts_with('#') {
            lines.push(line);
        }
    }
    lines
}

/// The crates under bins/ that the manifest `bins/<krate>/Cargo.toml` depends on, named
/// by a path (`path = "../x"`) or through the workspace's table (`x.workspace = true`,
/// `x = { workspace = true }`, where the root names `x = { path = "bins/x" }`).
fn bins_dependencies(krate: &str, all: &[String]) -> Vec<String> {
    let root = fs::read_to_string(repo_root().join("Cargo.toml")).unwrap();
    let manifest =
        fs::read_to_string(repo_root().join("bins").join(krate).join("Cargo.toml")).unwrap();
    let mut found = Vec::new();
    for line in dependency_lines(&manifest) {
        let name = line
            .split(['=', '.', ' '])
            .next()
            .unwrap_or_default()
            .to_string();
        let by_path = all
            .iter()
            .any(|b| line.contains(&format!("path = \"../{b}\"")));
        let by_workspace = line.contains("workspace = true")
            && root.lines().any(|l| {
                l.trim_start().starts_with(&format!("{name} "))
                    && l.contains(&format!("path = \"bins/{name}\""))
            });
        if (by_path || by_workspace) && all.contains(&name) {
            found.push(name);
        }
    }
    found
}

#[test]
fn no_stage_crate_depends_on_another() {
    let all = bins();
    assert!(all.len() >= 9, "{all:?}");
    for krate in all.iter().filter(|b| !TOOLS.contains(&b.as_str())) {
        let deps = bins_dependencies(krate, &all);
        assert!(
            deps.is_empty(),
            "bins/{krate}/Cargo.toml depends on {deps:?} under bins/"
        );
    }
}

#[test]
fn workspace_dependencies_are_read_and_no_tool_depends_on_itself_in_a_circle() {
    let all = bins();
    // Through the workspace's table, and through a path.
    assert_eq!(bins_dependencies("render", &all), ["plan"]);
    assert_eq!(bins_dependencies("chart", &all), ["plan", "zspec"]);
    // No circle among the tools: none of what a tool uses uses it back.
    for tool in TOOLS {
        for dep in bins_dependencies(tool, &all) {
            assert!(
                !bins_dependencies(&dep, &all).contains(&tool.to_string()),
                "{tool} and {dep} depend on each other"
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

#[test]
fn the_table_of_methods_depends_on_nothing_and_no_stage_reads_it() {
    let manifest = fs::read_to_string(repo_root().join("methods/Cargo.toml")).unwrap();
    assert_eq!(dependency_lines(&manifest), Vec::<&str>::new());
    // Its readers are the tools (render, chart) and the tests, never a stage.
    for krate in bins().iter().filter(|b| !TOOLS.contains(&b.as_str())) {
        let manifest =
            fs::read_to_string(repo_root().join(format!("bins/{krate}/Cargo.toml"))).unwrap();
        assert!(
            !dependency_lines(&manifest)
                .iter()
                .any(|l| l.starts_with("methods")),
            "bins/{krate} depends on the table of methods"
        );
    }
    for tool in ["render", "chart"] {
        let manifest =
            fs::read_to_string(repo_root().join(format!("bins/{tool}/Cargo.toml"))).unwrap();
        assert!(
            dependency_lines(&manifest).contains(&"methods.workspace = true"),
            "{tool} reads its methods from elsewhere"
        );
    }
}
