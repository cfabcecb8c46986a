//! The benchmark scripts' shared library (scripts/lib/bench.sh) and the scripts
//! themselves: a command that fails is never timed as a success, the pixels that differ
//! between two frames are counted, the methods a benchmark runs are render's, and no
//! script names a script that does not exist.

use pipeline_tests::{bin_dir, repo_root};
use std::path::Path;
use std::process::{Command, Output};

/// Runs `script` in bash with scripts/lib/bench.sh sourced, as a script named
/// `bench-test` (the name its messages start with), `bindir` the binaries' folder.
fn lib(script: &str) -> Output {
    Command::new("bash")
        .args([
            "-c",
            &format!("set -euo pipefail; source scripts/lib/bench.sh; {script}"),
            "bench-test",
        ])
        .current_dir(repo_root())
        .env("bindir", bin_dir())
        .output()
        .expect("run bash")
}

fn text(bytes: &[u8]) -> &str {
    std::str::from_utf8(bytes).expect("UTF-8")
}

/// A command that fails: `seconds`, `cpu_seconds` and `peak_kib` print no time, say
/// which command failed with what status and what it said last, and return its status
/// (before, they printed a short time and returned 0).
#[test]
fn timing_a_failing_command_fails_with_its_status_and_last_words() {
    for function in ["seconds", "cpu_seconds", "peak_kib"] {
        let out = lib(&format!(
            "{function} sh -c 'echo starting >&2; echo no such scene >&2; exit 3'"
        ));
        assert_eq!(out.status.code(), Some(3), "{function}: {out:?}");
        assert_eq!(text(&out.stdout), "", "{function}");
        assert_eq!(
            text(&out.stderr),
            "bench-test: `sh -c echo starting >&2; echo no such scene >&2; exit 3` failed \
             with status 3: no such scene\n",
            "{function}"
        );
    }
    // Under `set -e` the script stops at the assignment: nothing after it runs.
    let out = lib("t=$(seconds false); echo \"timed $t\"");
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(text(&out.stdout), "");
    assert_eq!(
        text(&out.stderr),
        "bench-test: `false` failed with status 1\n"
    );
    // `timed` and `best_of` too, whichever way `timed` measures (hyperfine's status is
    // its own).
    for call in ["timed 3 false", "best_of 3 cpu_seconds false"] {
        let out = lib(call);
        assert!(!out.status.success(), "{call}: {out:?}");
        assert_eq!(text(&out.stdout), "", "{call}");
        assert!(
            text(&out.stderr).starts_with("bench-test: `false` failed with status 1"),
            "{call}: {out:?}"
        );
    }
}

/// A command that succeeds is timed: a sleep of 0.2 s takes 0.2 s and more of the
/// clock, a bash loop some CPU time, a process that fills 64 MiB at least that much
/// memory; `reading` gives every run its input afresh.
#[test]
fn timing_a_command_that_succeeds_gives_its_figures() {
    let out = lib("seconds sleep 0.2; \
         cpu_seconds bash -c 'for ((i = 0; i < 200000; i++)); do :; done'; \
         peak_kib python3 -c 'b = bytearray(64 << 20); b[-1] = 1'; \
         best_of 2 seconds reading scripts/lib/bench.sh grep -q bench_options");
    assert!(out.status.success(), "{out:?}");
    let figures: Vec<f64> = text(&out.stdout)
        .lines()
        .map(|l| l.parse().expect(l))
        .collect();
    let [wall, cpu, kib, read] = figures[..] else {
        panic!("{figures:?}")
    };
    assert!((0.2..10.0).contains(&wall), "{wall}");
    assert!((0.01..60.0).contains(&cpu), "{cpu}");
    assert!(kib >= 65536.0, "{kib}");
    assert!((0.0..10.0).contains(&read), "{read}");
}

/// A PPM stream of `frames` frames of 3×2 black pixels, with pixel `i` of frame `f` red
/// for each (f, i) in `red`.
fn ppm(dir: &Path, name: &str, frames: usize, red: &[(usize, usize)]) -> String {
    let mut bytes = Vec::new();
    for f in 0..frames {
        bytes.extend_from_slice(b"P6\n3 2\n255\n");
        for i in 0..6 {
            let r = if red.contains(&(f, i)) { 255 } else { 0 };
            bytes.extend_from_slice(&[r, 0, 0]);
        }
    }
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path.display().to_string()
}

/// `differing` counts the pixels unlike over every frame (the warnock benchmark once
/// printed the word `pixels,` there, read from the wrong field, which a table showed as
/// 0); the same frames give 0, and a missing file is zspec's error and status.
#[test]
fn differing_counts_the_pixels_unlike_in_every_frame() {
    let dir = tempfile::tempdir().unwrap();
    let a = ppm(dir.path(), "a.ppm", 2, &[]);
    let b = ppm(dir.path(), "b.ppm", 2, &[(0, 1), (1, 0), (1, 5)]);
    let out = lib(&format!("differing {a} {b}; differing {a} {a}"));
    assert!(out.status.success(), "{out:?}");
    assert_eq!(text(&out.stdout), "3\n0\n");
    let missing = dir.path().join("missing.ppm").display().to_string();
    let out = lib(&format!("differing {a} {missing}"));
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    assert_eq!(text(&out.stdout), "");
    assert_eq!(
        text(&out.stderr),
        format!("zspec compare: cannot open {missing}: No such file or directory\n")
    );
}

/// `stat_count` reads a counter of a stage's --stats line by the words after it, and a
/// counter that is not there is an error, not an empty table cell.
#[test]
fn stat_count_reads_a_counter_by_its_words() {
    let line = "warnock: 50 polygons in, 1 frames, 500 runs out, 0 single pixels, \
                7 polygons looked at";
    let out = lib(&format!(
        "stat_count '{line}' 'polygons in'; stat_count '{line}' 'polygons looked at'; \
         stat_count '{line}' 'single pixels'; stat_count '{line}' 'crossings'"
    ));
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(text(&out.stdout), "50\n7\n0\n");
    assert_eq!(
        text(&out.stderr),
        format!("bench-test: no count of 'crossings' in: {line}\n")
    );
}

/// The names render refuses `--hse` and `--aa` values with.
fn render_accepts(option: &str) -> Vec<String> {
    let out = Command::new(bin_dir().join("render"))
        .args([option, "none-such", "scene.txt"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    // "render: --hse must be zbuf, scanline, warnock or painter, not 'none-such'"
    let message = text(&out.stderr);
    let list = message
        .split_once(" must be ")
        .and_then(|(_, rest)| rest.split_once(", not "))
        .map(|(list, _)| list)
        .unwrap_or_else(|| panic!("{message}"));
    list.replace(" or ", ", ")
        .split(", ")
        .map(str::to_string)
        .collect()
}

/// The benchmarks' methods are render's (`render --list-methods`, the table of methods):
/// `methods_list hse` names each `--hse` method
/// and `methods_list aa` each `--aa` leaf (`point` for none), each with the leaf command
/// render puts at a leaf for it, which `method_leaf` finds by name.
#[test]
fn methods_list_is_render_s_methods() {
    let out = lib("methods_list hse; echo; methods_list aa; echo; methods_list lines");
    assert!(out.status.success(), "{out:?}");
    let stdout = text(&out.stdout);
    let lists: Vec<&str> = stdout.split("\n\n").collect();
    let names = |list: &str| -> Vec<String> {
        list.lines()
            .map(|l| l.split('\t').next().unwrap().to_string())
            .collect()
    };
    assert_eq!(names(lists[0]), render_accepts("--hse"));
    let mut aa = names(lists[1]);
    aa[0] = aa[0].replace("point", "none");
    assert_eq!(aa, render_accepts("--aa"));
    assert_eq!(
        lists[0],
        "scanline\tscanline\nwarnock\twarnock\npainter\tpainter\nzbuf\tscanconv --resolve"
    );
    assert!(lists[1].contains("ss8\tsupersample --samples 8\n"));
    assert_eq!(lists[2], "hiddenline\thiddenline\n");
    // A method's leaf command by its name, for the scripts that compare a few methods.
    let out = lib("method_leaf hse zbuf; method_leaf aa ss4; method_leaf hse abuf");
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        text(&out.stdout),
        "scanconv --resolve\nsupersample --samples 4\n"
    );
    assert_eq!(
        text(&out.stderr),
        "bench-test: methods_list hse has no method 'abuf'\n"
    );
    let out = lib("methods_list all");
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        text(&out.stderr),
        "bench-test: methods_list: no kind 'all' (kinds: hse aa lines)\n"
    );
}

/// The scripts, one per question: each prints its opening comment for --help without
/// building anything, and refuses an option it does not know with status 2.
const BENCH_SCRIPTS: [&str; 1] = ["bench-adaptive.sh"];

#[test]
fn each_benchmark_says_its_usage_and_refuses_an_unknown_option() {
    for script in BENCH_SCRIPTS {
        let path = repo_root().join("scripts").join(script);
        let out = Command::new(&path).arg("--help").output().unwrap();
        assert!(out.status.success(), "{script} --help: {out:?}");
        let help = text(&out.stdout);
        assert!(
            help.starts_with(&format!("{script}: ")),
            "{script} --help: {help}"
        );
        assert!(
            help.contains(&format!("Usage: scripts/{script} ")),
            "{script} --help: {help}"
        );
        let out = Command::new(&path).arg("--fast").output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{script} --fast: {out:?}");
        assert_eq!(
            text(&out.stderr),
            format!("{script}: unknown option --fast (--help says more)\n")
        );
    }
}

/// Every `NAME.sh` or `NAME.py` that a script, a source file, a test or CI names is a
/// file of the repository: a script renamed or merged leaves no message, usage line or
/// comment sending a reader to the old name.
#[test]
fn no_script_names_a_script_that_does_not_exist() {
    let root = repo_root();
    let mut files = Vec::new();
    for top in [
        "scripts", "bins", "tests", "proto", "stagecli", "scan", ".ci", "bench", "docs", "methods",
    ] {
        walk(&root.join(top), &mut files);
    }
    for top in ["README.md", "CONTRIBUTING.md"] {
        files.push(root.join(top));
    }
    let mut everything = Vec::new();
    walk(&root, &mut everything);
    let exists: Vec<String> = everything
        .iter()
        .filter_map(|p| p.file_name()?.to_str().map(str::to_string))
        .collect();
    let mut stale = Vec::new();
    for file in &files {
        let Ok(content) = std::fs::read_to_string(file) else {
            continue;
        };
        for (number, line) in content.lines().enumerate() {
            for name in script_names(line) {
                if !exists.contains(&name) {
                    stale.push(format!(
                        "{}:{}: {name}",
                        file.strip_prefix(&root).unwrap().display(),
                        number + 1
                    ));
                }
            }
        }
    }
    assert!(stale.is_empty(), "names of no file:\n{}", stale.join("\n"));
}

/// The files under `dir`, but not build output or fuzzing corpora.
fn walk(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name();
        if path.is_dir() {
            if name != "target" && name != ".git" && name != "corpus" && name != "artifacts" {
                walk(&path, out);
            }
        } else {
            out.push(path);
        }
    }
}

/// The words of `line` that name a shell or Python script: a lower-case letter, then
/// letters, digits, `_` and `-`, then `.sh` or `.py`, not followed by another name
/// character.
fn script_names(line: &str) -> Vec<String> {
    let bytes = line.as_bytes();
    let name_char = |b: u8| b.is_ascii_alphanumeric() || b == b'_' || b == b'-';
    let mut names = Vec::new();
    for ext in [".sh", ".py"] {
        let mut from = 0;
        while let Some(at) = line[from..].find(ext).map(|i| i + from) {
            from = at + ext.len();
            let end_ok = bytes.get(from).is_none_or(|b| !name_char(*b));
            let mut start = line[..at]
                .bytes()
                .rposition(|b| !name_char(b))
                .map_or(0, |i| i + 1);
            // `\nrender.sh` in a string is a new line and render.sh.
            if start > 0 && bytes[start - 1] == b'\\' {
                start += 1;
            }
            if end_ok && start < at && bytes[start].is_ascii_lowercase() {
                names.push(line[start..from].to_string());
            }
        }
    }
    names
}
