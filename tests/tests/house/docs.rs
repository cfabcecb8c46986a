//! The repository explains itself: every citation of the design points at the copy in the
//! repository, docs/DESIGN.md, by that path and by a section it has, and nothing cites a
//! file outside the repository. (The code once cited a design kept beside the
//! repository, which a reader of the repository never sees.)

use pipeline_tests::repo_root;
use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

/// The design's file name and the folder beside the repository, each spelled in pieces so
/// that this file does not itself contain what it looks for.
const NAME: &str = concat!("DESIGN", ".md");
const OUTSIDE: &str = concat!("..", "/shared/");
/// The one way to cite the design.
const PATH: &str = "docs/DESIGN.md";

/// The kinds of file that carry comments or prose (C for the benchmark harness).
const CHECKED: &[&str] = &["rs", "sh", "md", "txt", "c", "h", "toml"];

/// Every file under `dir` with a checked extension, skipping build output (`target/`,
/// also fuzz/target) and git's folder; symbolic links are not followed.
fn source_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let entries = fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    for entry in entries {
        let entry = entry.expect("a directory entry");
        let path = entry.path();
        let kind = entry.file_type().expect("a file type");
        let name = entry.file_name();
        if kind.is_dir() {
            if name != "target" && name != ".git" {
                source_files(&path, out);
            }
        } else if kind.is_file()
            && path
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| CHECKED.contains(&e))
        {
            out.push(path);
        }
    }
}

/// The headings of the design, without their `#`s.
fn sections(design: &str) -> BTreeSet<String> {
    design
        .lines()
        .filter(|l| l.starts_with('#'))
        .map(|l| l.trim_start_matches('#').trim().to_string())
        .collect()
}

/// What is wrong with one file's text, as `line N: …` messages: a citation of the design
/// by any other path than `docs/DESIGN.md`, a quoted section name after it that the design
/// does not have, or a path into the folder beside the repository.
fn problems(text: &str, sections: &BTreeSet<String>) -> Vec<String> {
    let mut found = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let n = i + 1;
        if line.contains(OUTSIDE) {
            found.push(format!(
                "line {n}: cites `{OUTSIDE}`, outside the repository"
            ));
        }
        for (at, _) in line.match_indices(NAME) {
            let before = &line[..at];
            let prefix = &PATH[..PATH.len() - NAME.len()];
            // The path must be exactly docs/DESIGN.md, not part of a longer path.
            let whole = before
                .strip_suffix(prefix)
                .is_some_and(|b| !b.ends_with(|c: char| c.is_alphanumeric() || "_-./".contains(c)));
            if !whole {
                found.push(format!("line {n}: cites the design other than as `{PATH}`"));
                continue;
            }
            // A section named right after it, `docs/DESIGN.md, "Coverage"` or
            // `docs/DESIGN.md's "Coverage"` or `docs/DESIGN.md ("Depth")`, must exist.
            let after = &line[at + NAME.len()..];
            let after = after.strip_prefix("'s").unwrap_or(after);
            let after = after.trim_start_matches([',', ' ', '(']);
            if let Some(quoted) = after.strip_prefix('"') {
                if let Some((section, _)) = quoted.split_once('"') {
                    if !sections.contains(section) {
                        found.push(format!(
                            "line {n}: cites section \"{section}\", which {PATH} does not have"
                        ));
                    }
                }
            }
        }
    }
    found
}

#[test]
fn every_citation_of_the_design_is_docs_design_md_and_names_a_section_it_has() {
    let root = repo_root();
    let design = fs::read_to_string(root.join(PATH)).expect("docs/DESIGN.md exists");
    let sections = sections(&design);
    for wanted in [
        "The token stream",
        "The Z specification",
        "Coverage",
        "Visibility",
        "The stages",
        "The splitter tree",
        "The merge",
        "Errors and exit statuses",
        "Departures from the thesis and the card",
        "The leaves and the merge",
        "Hidden-surface methods",
        "Stages on other hosts",
    ] {
        assert!(
            sections.contains(wanted),
            "docs/DESIGN.md has no section \"{wanted}\""
        );
    }

    let mut files = Vec::new();
    source_files(&root, &mut files);
    files.sort();
    // The walk reaches the code, the scripts and the docs (a walk that found nothing would
    // pass vacuously).
    for must in [
        "proto/src/raster.rs",
        "scripts/render.sh",
        "README.md",
        PATH,
    ] {
        assert!(files.contains(&root.join(must)), "the walk missed {must}");
    }
    let mut report = Vec::new();
    for file in &files {
        // Binary files among them (none today) have nothing to cite.
        let Ok(text) = fs::read_to_string(file) else {
            continue;
        };
        let shown = file
            .strip_prefix(&root)
            .unwrap_or(file)
            .display()
            .to_string();
        report.extend(
            problems(&text, &sections)
                .into_iter()
                .map(|p| format!("{shown}: {p}")),
        );
    }
    assert!(report.is_empty(), "{}", report.join("\n"));
}

#[test]
fn the_check_finds_each_kind_of_bad_citation() {
    let sections: BTreeSet<String> = ["Coverage".to_string()].into();
    let ok = |t: &str| problems(t, &sections).is_empty();
    assert!(ok("// pixel centres (docs/DESIGN.md, \"Coverage\")"));
    assert!(ok("//! docs/DESIGN.md's \"Coverage\" rule"));
    assert!(ok("# see docs/DESIGN.md (\"Coverage\") and docs/DESIGN.md"));
    assert!(ok("the design is in docs/DESIGN.md."));
    assert_eq!(
        problems(&format!("// as {NAME} asks"), &sections),
        ["line 1: cites the design other than as `docs/DESIGN.md`"]
    );
    assert!(!ok(&format!("x\n// see ../docs/{NAME}")));
    assert!(!ok(&format!("// see mydocs/{NAME}")));
    assert!(!ok(&format!("// see shared/{NAME}")));
    assert_eq!(
        problems("a\nb (docs/DESIGN.md, \"Nowhere\")", &sections),
        ["line 2: cites section \"Nowhere\", which docs/DESIGN.md does not have"]
    );
    assert_eq!(
        problems(&format!("read `{OUTSIDE}seeds` first"), &sections),
        [format!("line 1: cites `{OUTSIDE}`, outside the repository")]
    );
}

/// What dates a line as a run's log rather than a description: a calendar date
/// (`2026-11-25`), a time of day in UTC, a commit hash (a word of 7 to 12 hexadecimal
/// digits with both digits and letters in it, or of 40), or a load average with its
/// figure. History goes in git (CONTRIBUTING.md); a document gives current figures, each
/// with the command that gives them.
fn dated(line: &str) -> Vec<String> {
    let mut found = Vec::new();
    for word in line.split(|c: char| !c.is_ascii_alphanumeric() && c != '-' && c != ':') {
        let w = word.trim_matches(|c| c == '-' || c == ':');
        let b = w.as_bytes();
        let digits = |r: std::ops::Range<usize>| b[r].iter().all(u8::is_ascii_digit);
        if b.len() == 10
            && digits(0..4)
            && b[4] == b'-'
            && digits(5..7)
            && b[7] == b'-'
            && digits(8..10)
        {
            found.push(format!("a date, {w}"));
        }
        let hex = w
            .bytes()
            .all(|c| c.is_ascii_digit() || (b'a'..=b'f').contains(&c));
        let mixed =
            w.bytes().any(|c| c.is_ascii_digit()) && w.bytes().any(|c| c.is_ascii_alphabetic());
        if hex && mixed && ((7..=12).contains(&w.len()) || w.len() == 40) {
            found.push(format!("a commit hash, {w}"));
        }
    }
    for (i, _) in line.match_indices(" UTC") {
        let before = line[..i].trim_end_matches(|c: char| c.is_ascii_digit());
        if before.ends_with(':') {
            found.push("a time of day".to_string());
        }
    }
    let lower = line.to_lowercase();
    for (i, m) in lower.match_indices("load average") {
        let after: String = lower[i + m.len()..].chars().take(24).collect();
        if after.chars().any(|c| c.is_ascii_digit()) {
            found.push(format!("a load average, `{m}{after}`"));
        }
    }
    // The load a run saw, in other words: `load 4.6`, `(load 3–4: …`, `at a load of 11`.
    for (i, m) in lower.match_indices("load ") {
        // The word, not the end of another (`download 5 files`).
        if lower[..i].ends_with(|c: char| c.is_alphanumeric()) {
            continue;
        }
        let mut after = &lower[i + m.len()..];
        for word in ["of ", "about ", "around ", "near "] {
            after = after.trim_start_matches(word);
        }
        if after.starts_with(|c: char| c.is_ascii_digit()) {
            let figure: String = after.chars().take_while(|c| !c.is_whitespace()).collect();
            found.push(format!("a load, `load {figure}`"));
        }
    }
    found
}

#[test]
fn dated_runs_are_found() {
    let cases = [
        (
            "measured at commit 3a66264 on 2 cores",
            vec!["a commit hash, 3a66264"],
        ),
        (
            "2026-11-25 20:00 UTC",
            vec!["a date, 2026-11-25", "a time of day"],
        ),
        (
            "load average before: 2.01 2.21",
            vec!["a load average, `load average before: 2.01 2.21`"],
        ),
        ("15 rounds (load 3.7) gave", vec!["a load, `load 3.7)`"]),
        (
            "shared with other builds (load about 6), each",
            vec!["a load, `load 6),`"],
        ),
        (
            "at a load of 11 it also chose depth 1",
            vec!["a load, `load 11`"],
        ),
        ("`--load L`, or the load L the model takes", vec![]),
        ("download 5 files, upload 2", vec![]),
        // A description, not a run: the planner reads the load average.
        ("or else the 1-minute load average less one", vec![]),
        (
            "a hash such as 0dd0b7baeefcafc1, 1e156 px, the 16x16 reference",
            vec![],
        ),
    ];
    for (line, want) in cases {
        assert_eq!(dated(line), want, "{line}");
    }
}

/// The documents describe the code as it is; a run's date, commit and load belong in
/// the commit that measured it.
#[test]
fn no_document_holds_a_dated_run() {
    let root = repo_root();
    let mut files = vec![root.join("README.md")];
    for e in fs::read_dir(root.join("docs")).unwrap() {
        let path = e.unwrap().path();
        if path.extension().is_some_and(|x| x == "md") {
            files.push(path);
        }
    }
    files.sort();
    let mut bad = Vec::new();
    for file in &files {
        let text = fs::read_to_string(file).unwrap();
        for (i, line) in text.lines().enumerate() {
            for what in dated(line) {
                let name = file.strip_prefix(&root).unwrap().display();
                bad.push(format!("{name}:{}: {what}", i + 1));
            }
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

/// The README is the way in, not the manual: at most 400 lines (docs/ has the detail).
#[test]
fn the_readme_is_at_most_400_lines() {
    let readme = fs::read_to_string(repo_root().join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(
        lines <= 400,
        "README.md has {lines} lines, at most 400: move detail into docs/"
    );
}
