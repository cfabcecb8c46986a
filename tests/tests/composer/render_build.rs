//! How scripts/render.sh finds and builds the binaries: the first run builds every
//! binary the README uses; later runs call cargo only when a source of a binary is newer
//! than the binaries (render's look, bins/render/src/fresh.rs).

// The binaries render builds: its own list.
use pipeline_tests::output_with_stdin;
use pipeline_tests::render::{example, frames, render};
use pipeline_tests::{bin_dir, repo_root};
use render::fresh::binaries;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::Duration;

/// A private copy of the repository's sources (no target/), every file dated an hour
/// ago, for the tests of how render.sh finds and builds its binaries.
fn copy_of_repository(name: &str) -> PathBuf {
    fn copy(from: &Path, to: &Path, past: std::time::SystemTime) {
        if from.is_dir() {
            std::fs::create_dir_all(to).unwrap();
            for e in std::fs::read_dir(from).unwrap() {
                let e = e.unwrap();
                if e.file_name() != "target" {
                    copy(&e.path(), &to.join(e.file_name()), past);
                }
            }
        } else {
            std::fs::copy(from, to).unwrap();
            set_mtime(to, past);
        }
    }
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("render-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    let repo = dir.join("repo");
    std::fs::create_dir_all(&repo).unwrap();
    let past = std::time::SystemTime::now() - Duration::from_secs(3600);
    for part in [
        "Cargo.toml",
        "Cargo.lock",
        "README.md",
        "scripts",
        "examples",
        "proto",
        "bins",
        "tests",
    ] {
        copy(&repo_root().join(part), &repo.join(part), past);
    }
    dir
}

fn set_mtime(path: &Path, time: std::time::SystemTime) {
    std::fs::File::options()
        .write(true)
        .open(path)
        .and_then(|f| f.set_modified(time))
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
}

/// A folder of the tools render.sh runs (found on PATH), linked, to be the whole PATH
/// of a run: with `fake_cargo`, a `cargo` that logs each call (its folder and arguments)
/// to DIR/cargo.log and "builds" each `-p NAME` (every binary of [`binaries`] for
/// `--bins`) by copying the test's own binary into the release folder cargo would use (CARGO_TARGET_DIR taken from its working folder,
/// as cargo does, then the host's folder, [`release_subdir`]), with a dep-info file
/// listing the crate's and proto's sources.
fn tools(dir: &Path, fake_cargo: bool) -> PathBuf {
    let bin = dir.join(if fake_cargo { "tools-cargo" } else { "tools" });
    let _ = std::fs::remove_dir_all(&bin);
    std::fs::create_dir_all(&bin).unwrap();
    let path = std::env::var_os("PATH").unwrap();
    for tool in [
        "bash", "env", "cat", "cp", "ln", "mkdir", "mkfifo", "mktemp", "readlink", "rm", "sed",
        "sleep", "touch",
    ] {
        let found = std::env::split_paths(&path)
            .map(|d| d.join(tool))
            .find(|p| p.is_file())
            .unwrap_or_else(|| panic!("{tool} on PATH"));
        std::os::unix::fs::symlink(found, bin.join(tool)).unwrap();
    }
    if fake_cargo {
        let cargo = bin.join("cargo");
        std::fs::write(
            &cargo,
            format!(
                r#"#!/usr/bin/env bash
echo "$PWD $*" >> {log}
[[ -n ${{FAKE_CARGO_NOOP-}} ]] && exit 0
t=${{CARGO_TARGET_DIR:-target}}
[[ $t == /* ]] || t=$PWD/$t
r=$t/{sub}
mkdir -p "$r"
build() {{ cp {real}/"$1" "$r/$1"; }}
while (($# > 0)); do
    if [[ $1 == -p ]]; then
        build "$2"
        shift
    elif [[ $1 == --bins ]]; then
        for b in {all}; do build "$b"; done
    fi
    shift
done
"#,
                log = dir.join("cargo.log").display(),
                real = bin_dir().display(),
                all = binaries().join(" "),
                sub = release_subdir()
            ),
        )
        .unwrap();
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&cargo, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    bin
}

/// Where cargo puts release binaries in its target folder: `<host tuple>/release`, as
/// .cargo/config.toml's `target = "host-tuple"` has it (the tests' own folder says which
/// tuple), or `release` for a build without that setting.
fn release_subdir() -> String {
    let tuple = bin_dir().parent().and_then(Path::file_name).unwrap();
    if tuple.to_string_lossy().contains('-') {
        format!("{}/release", tuple.to_string_lossy())
    } else {
        "release".into()
    }
}

/// The calls the fake cargo has logged so far (and forgets them).
fn cargo_calls(dir: &Path) -> Vec<String> {
    let log = dir.join("cargo.log");
    let calls = std::fs::read_to_string(&log).unwrap_or_default();
    let _ = std::fs::remove_file(&log);
    calls.lines().map(String::from).collect()
}

/// Runs SCRIPT (a render.sh) from folder CWD with only TOOLS on PATH, stdin empty.
fn render_in(script: &Path, cwd: &Path, tools: &Path, args: &[&str]) -> Output {
    let mut cmd = Command::new(script);
    cmd.args(args)
        .current_dir(cwd)
        .env("PATH", tools)
        .env_remove("CARGO_TARGET_DIR")
        .env_remove("FAKE_CARGO_NOOP");
    output_with_stdin(cmd, b"")
}

/// The binaries the README runs, as `$B/NAME` or `target/bin/NAME`.
fn binaries_the_readme_uses() -> std::collections::BTreeSet<String> {
    let readme = std::fs::read_to_string(repo_root().join("README.md")).unwrap();
    let mut names = std::collections::BTreeSet::new();
    for prefix in ["$B/", "target/bin/"] {
        for (i, _) in readme.match_indices(prefix) {
            let name: String = readme[i + prefix.len()..]
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_' || *c == '-')
                .collect();
            if !name.is_empty() {
                names.insert(name);
            }
        }
    }
    names
}

/// the README's first command builds every binary the README goes on to use,
/// saying so on stderr, and the README's next commands then run. (The README runs it
/// on a terminal, where render draws the example; here the example is named.)
#[test]
fn the_first_run_builds_every_binary_the_readme_uses() {
    let dir = copy_of_repository("first-run");
    let repo = dir.join("repo");
    let tools = tools(&dir, true);
    let out = render_in(
        &repo.join("scripts/render.sh"),
        &repo,
        &tools,
        &["-o", "penetrating.png", "examples/penetrating.txt"],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert_eq!(
        err,
        "render.sh: building the polypipe binaries (first run only)…\n"
    );
    assert!(repo.join("penetrating.png").is_file());
    let calls = cargo_calls(&dir);
    assert_eq!(
        calls,
        [format!("{} build --release --quiet --bins", repo.display())]
    );
    let used = binaries_the_readme_uses();
    assert!(used.contains("scene") && used.contains("zspec"), "{used:?}");
    for name in &used {
        let b = repo.join("target/bin").join(name);
        let help = Command::new(&b).arg("--help").output().unwrap();
        assert!(help.status.success(), "{}", b.display());
    }
    // cargo built them in its folder for this host, and target/bin links to it.
    let link = std::fs::read_link(repo.join("target/bin")).unwrap();
    assert_eq!(link, Path::new(&release_subdir()));
    // The README's next block (`B=target/bin`), with the binaries the first run built.
    let b = repo.join("target/bin");
    let text = Command::new(b.join("scene"))
        .args(["penetrating", "--text"])
        .output()
        .unwrap();
    assert!(text.status.success());
    assert!(text.stdout.starts_with(b"polypipe 1 world"));
    // A second run finds them all built and current: no cargo.
    let out = render_in(
        &repo.join("scripts/render.sh"),
        &repo,
        &tools,
        &["--size", "21x21", "examples/penetrating.txt"],
    );
    assert!(out.status.success());
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(cargo_calls(&dir), Vec::<String>::new());
}

/// only the binaries' sources (src/ .rs files, Cargo.toml, Cargo.lock) make
/// render call cargo; without cargo it runs what is built.
#[test]
fn only_the_binaries_sources_make_render_sh_call_cargo() {
    let dir = copy_of_repository("fresh");
    let repo = dir.join("repo");
    let script = repo.join("scripts/render.sh");
    let with_cargo = tools(&dir, true);
    let without_cargo = tools(&dir, false);
    let args = ["--size", "21x21", "examples/penetrating.txt"];
    // Without cargo and nothing built: status 3, saying what is missing.
    let out = render_in(&script, &repo, &without_cargo, &args);
    assert_eq!(out.status.code(), Some(3));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        err,
        format!(
            "render.sh: cannot build the polypipe binaries into {}: cargo is not on PATH (Rust: https://rustup.rs)\n",
            repo.join("target/release").display()
        )
    );
    let first = render_in(&script, &repo, &with_cargo, &args);
    assert!(first.status.success());
    assert_eq!(cargo_calls(&dir).len(), 1);
    // The binaries a minute old, the sources an hour.
    let built = std::time::SystemTime::now() - Duration::from_secs(60);
    let release = repo.join("target").join(release_subdir());
    for e in std::fs::read_dir(&release).unwrap() {
        set_mtime(&e.unwrap().path(), built);
    }
    let now = std::time::SystemTime::now();
    // Tests, test helpers and documents are not sources of the binaries.
    for file in [
        "tests/tests/stages/tree_nodes.rs",
        "tests/tests/stages/zbuf_cli.rs",
        "tests/src/lib.rs",
        "README.md",
        "examples/penetrating.txt",
    ] {
        set_mtime(&repo.join(file), now);
        let out = render_in(&script, &repo, &with_cargo, &args);
        assert!(out.status.success());
        assert_eq!(out.stdout, first.stdout);
        assert_eq!(cargo_calls(&dir), Vec::<String>::new(), "touched {file}");
    }
    // A source of a binary is (changed now, after those runs: a run that finds every
    // binary current by its sources notes the time in its stamp).
    set_mtime(&repo.join("proto/src/lib.rs"), std::time::SystemTime::now());
    // Without cargo: run them as they are, with one warning.
    let out = render_in(&script, &repo, &without_cargo, &args);
    assert!(out.status.success());
    assert_eq!(out.stdout, first.stdout);
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "render: warning: the binaries are older than their sources, and no cargo on PATH to \
         rebuild them; running them as they are\n"
    );
    // With cargo: rebuilt, once (and the render cargo rebuilt runs in place of the old).
    let out = render_in(&script, &repo, &with_cargo, &args);
    assert!(out.status.success(), "{out:?}");
    assert_eq!(cargo_calls(&dir).len(), 1);
    let out = render_in(&script, &repo, &with_cargo, &args);
    assert!(out.status.success());
    assert_eq!(cargo_calls(&dir), Vec::<String>::new());
    // A change to Cargo.lock that leaves every binary alone (cargo has nothing to do)
    // calls cargo once, not on every run from then on.
    set_mtime(&repo.join("Cargo.lock"), std::time::SystemTime::now());
    for _ in 0..2 {
        let mut cmd = Command::new(&script);
        cmd.args(args)
            .current_dir(&repo)
            .env("PATH", &with_cargo)
            .env("FAKE_CARGO_NOOP", "1");
        assert!(output_with_stdin(cmd, b"").status.success());
    }
    assert_eq!(cargo_calls(&dir).len(), 1);
    // A crate's Cargo.toml counts too.
    set_mtime(
        &repo.join("bins/zbuf/Cargo.toml"),
        std::time::SystemTime::now(),
    );
    assert!(render_in(&script, &repo, &with_cargo, &args)
        .status
        .success());
    assert_eq!(cargo_calls(&dir).len(), 1);
}

/// a relative CARGO_TARGET_DIR is where cargo, run from the repository root,
/// builds; and a symlink to render.sh finds the repository the script is in.
#[test]
fn a_relative_target_dir_and_a_symlinked_script_find_the_binaries() {
    let dir = copy_of_repository("elsewhere");
    let repo = dir.join("repo");
    let cargo = tools(&dir, true);
    let elsewhere = dir.join("elsewhere");
    std::fs::create_dir_all(&elsewhere).unwrap();
    let run = |script: &Path| {
        let mut cmd = Command::new(script);
        cmd.args(["--size", "21x21"])
            .arg(repo.join("examples/penetrating.txt"))
            .current_dir(&elsewhere)
            .env("PATH", &cargo)
            .env("CARGO_TARGET_DIR", "build/here");
        output_with_stdin(cmd, b"")
    };
    let out = run(&repo.join("scripts/render.sh"));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(frames(&out.stdout).len(), 1);
    assert_eq!(cargo_calls(&dir).len(), 1);
    assert!(repo
        .join("build/here")
        .join(release_subdir())
        .join("viewxf")
        .is_file());
    // render.sh links the target folder's `bin` to them.
    assert!(repo.join("build/here/bin/viewxf").is_file());
    assert!(!elsewhere.join("build").exists());
    // Found where it was built: no second build.
    assert!(run(&repo.join("scripts/render.sh")).status.success());
    assert_eq!(cargo_calls(&dir), Vec::<String>::new());
    // Through a symlink in another folder (and a symlink to that).
    let link = dir.join("links/render");
    std::fs::create_dir_all(link.parent().unwrap()).unwrap();
    std::os::unix::fs::symlink(repo.join("scripts/render.sh"), &link).unwrap();
    let link2 = elsewhere.join("r");
    std::os::unix::fs::symlink(&link, &link2).unwrap();
    for script in [&link, &link2] {
        let out = run(script);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert_eq!(frames(&out.stdout).len(), 1);
    }
    assert_eq!(cargo_calls(&dir), Vec::<String>::new());
}

/// With the real cargo: after a run that had cargo make the binaries current (as the
/// tests' `bin_dir` does), render finds them current and, without cargo on PATH, runs
/// them without a warning.
#[test]
fn binaries_cargo_just_built_are_current() {
    bin_dir();
    // A run with cargo first, so that a Cargo.lock newer than every binary (which cargo
    // leaves alone) has been asked about once.
    assert!(render(&["--size", "21x21", &example()], b"")
        .status
        .success());
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("render-dep-info");
    std::fs::create_dir_all(&dir).unwrap();
    let out = render_in(
        &repo_root().join("scripts/render.sh"),
        &repo_root(),
        &tools(&dir, false),
        &["--size", "21x21", &example()],
    );
    assert!(out.status.success());
    assert_eq!(String::from_utf8_lossy(&out.stderr), "");
}
