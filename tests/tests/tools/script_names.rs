//! No script, source file, test or document names a script that does not exist: a
//! script renamed, merged or ported to `bench` leaves no message, usage line or comment
//! sending a reader to the old name.

use pipeline_tests::repo_root;
use std::path::Path;

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
