//! The test binaries: few (a linked binary each costs the build a link and the run a
//! start), and a skipped test is counted and listed when its binary exits, and under
//! `CI=true` it is a failure, not a pass (`pipeline_tests::skip`).

use pipeline_tests::repo_root;
use std::path::Path;
use std::process::Command;

/// The integration-test targets cargo finds in a package folder: each `tests/NAME.rs` and
/// each `tests/NAME/main.rs`.
fn integration_tests(package: &Path) -> Vec<String> {
    let Ok(entries) = std::fs::read_dir(package.join("tests")) else {
        return Vec::new();
    };
    let mut found = Vec::new();
    for entry in entries.flatten() {
        let path = entry.path();
        if path.extension().is_some_and(|e| e == "rs") || path.join("main.rs").is_file() {
            found.push(
                path.strip_prefix(repo_root())
                    .unwrap()
                    .display()
                    .to_string(),
            );
        }
    }
    found
}

#[test]
fn the_workspace_links_at_most_sixteen_integration_test_binaries() {
    let root = repo_root();
    let mut packages = vec![root.join("tests")];
    for top in ["", "bins"] {
        for entry in std::fs::read_dir(root.join(top)).unwrap().flatten() {
            if entry.path().join("Cargo.toml").is_file() && entry.file_name() != "tests" {
                packages.push(entry.path());
            }
        }
    }
    let binaries: Vec<String> = packages.iter().flat_map(|p| integration_tests(p)).collect();
    assert!(binaries.len() >= 7, "{binaries:?}");
    assert!(
        binaries.len() <= 16,
        "{} integration-test binaries, at most 16: put a new file in one of \
         tests/tests/*/ as a module: {binaries:?}",
        binaries.len()
    );
}

/// Runs the test `leaf` of this module in a child of this test binary, with `CI` as
/// given, so that the environment, the panic and the exit stay there.
fn child(leaf: &str, ci: &str) -> (bool, String) {
    let module = module_path!().split_once("::").map_or("", |(_, m)| m);
    let out = Command::new(std::env::current_exe().unwrap())
        .args(["--exact", &format!("{module}::{leaf}"), "--nocapture"])
        .env("POLYPIPE_TEST_CHILD", "1")
        .env("CI", ci)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout) + String::from_utf8_lossy(&out.stderr);
    (out.status.success(), text.into_owned())
}

#[test]
fn a_skip_passes_and_is_listed_at_exit_but_fails_under_ci() {
    if std::env::var_os("POLYPIPE_TEST_CHILD").is_some() {
        pipeline_tests::skip("the child's stand-in tool is not installed");
        return;
    }
    let leaf = "a_skip_passes_and_is_listed_at_exit_but_fails_under_ci";
    let (ok, text) = child(leaf, "false");
    assert!(ok, "{text}");
    assert!(
        text.contains("SKIPPED: the child's stand-in tool is not installed\n")
            && text.contains(
                "1 test(s) skipped in this test binary:\n  \
                 SKIPPED: the child's stand-in tool is not installed\n"
            ),
        "{text}"
    );
    let (ok, text) = child(leaf, "true");
    assert!(!ok, "{text}");
    assert!(
        text.contains(
            "not skipped under CI=true, where it must run: the child's stand-in tool is not \
             installed"
        ) && text.contains("1 failed"),
        "{text}"
    );
}
