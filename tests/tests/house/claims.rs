//! Claims held by name: a sentence of README.md or docs/*.md that says "byte for byte",
//! "exact", "the same bytes", "says so" or "bounded" points to the test that holds it, as
//! `(held by `FILE::NAME`)`: FILE a module of a test binary under tests/tests/ without `.rs`
//! (`differential::supersampling_is_zspec_samples_k`), or any `.rs` path from the
//! repository root (`bins/scan/src/lib.rs::name`); NAME a function in it. Sentences are
//! read across line breaks (a paragraph, a list item or a table row is joined first), code
//! blocks are skipped.

use pipeline_tests::repo_root;
use std::fs;

/// The words that make a sentence a claim ("exact" as a word: not "exactly").
const CLAIMS: &[&str] = &[
    "byte for byte",
    "the same bytes",
    "says so",
    "bounded",
    "exact",
];

/// The documents every claim of which must name its test today. The others are on their
/// way: for them only the pointers they have are checked, and the count of sentences
/// without one must not grow past [`UNHELD_AT_MOST`].
const HELD: &[&str] = &["README.md"];

/// The documents not yet in [`HELD`], and the most claims without a pointer each may have.
const UNHELD_AT_MOST: &[(&str, usize)] = &[
    ("docs/DESIGN.md", 23),
    ("docs/antialiasing.md", 8),
    ("docs/degenerate.md", 3),
    ("docs/extending.md", 7),
    ("docs/fuzzing.md", 3),
    ("docs/methods.md", 22),
    ("docs/model.md", 3),
    ("docs/performance.md", 1),
    ("docs/references.md", 0),
];

/// The blocks of `text` as one line each: paragraphs, list items and table rows, with
/// fenced and indented code left out.
fn blocks(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut fenced = false;
    let flush = |cur: &mut String, out: &mut Vec<String>| {
        if !cur.trim().is_empty() {
            out.push(std::mem::take(cur));
        }
        cur.clear();
    };
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            flush(&mut cur, &mut out);
            continue;
        }
        if fenced || line.starts_with("    ") && cur.is_empty() {
            continue;
        }
        let t = line.trim();
        if t.is_empty() || t.starts_with('#') {
            flush(&mut cur, &mut out);
            if t.starts_with('#') {
                out.push(t.to_string());
            }
            continue;
        }
        if t.starts_with('|') || t.starts_with("- ") || t.starts_with("* ") {
            flush(&mut cur, &mut out);
        }
        cur.push(' ');
        cur.push_str(t);
        if t.starts_with('|') {
            flush(&mut cur, &mut out);
        }
    }
    flush(&mut cur, &mut out);
    out
}

/// The sentences of a block: split after `.`, `!` or `?` followed by a space and a capital
/// or a backquote, and at the cells of a table row; a `(held by …)` right after the full
/// stop belongs to the sentence before it.
fn sentences(block: &str) -> Vec<String> {
    if block.trim_start().starts_with('|') {
        return vec![block.to_string()];
    }
    let chars: Vec<char> = block.chars().collect();
    let mut out = Vec::new();
    let mut start = 0;
    let mut i = 0;
    while i < chars.len() {
        if ".!?".contains(chars[i])
            && chars.get(i + 1) == Some(&' ')
            && chars
                .get(i + 2)
                .is_some_and(|c| c.is_uppercase() || *c == '`')
        {
            let rest: String = chars[i + 2..].iter().collect();
            if !rest.starts_with("(held by") {
                out.push(chars[start..=i].iter().collect::<String>());
                start = i + 2;
            }
        }
        i += 1;
    }
    out.push(chars[start..].iter().collect());
    out
}

fn is_claim(sentence: &str) -> bool {
    let lower = sentence.to_lowercase();
    CLAIMS.iter().any(|c| {
        lower.match_indices(c).any(|(at, _)| {
            let after = lower[at + c.len()..].chars().next();
            let before = lower[..at].chars().next_back();
            !after.is_some_and(|a| a.is_alphanumeric())
                && !before.is_some_and(|b| b.is_alphanumeric())
        })
    })
}

/// The `(held by `X::Y`)` pointers of a sentence.
fn pointers(sentence: &str) -> Vec<String> {
    sentence
        .match_indices("held by `")
        .filter_map(|(at, m)| {
            let rest = &sentence[at + m.len()..];
            rest.split_once('`').map(|(p, _)| p.to_string())
        })
        .collect()
}

/// What is wrong with a pointer: a file that is not there, or no function of that name.
fn broken(pointer: &str) -> Option<String> {
    let Some((file, name)) = pointer.rsplit_once("::") else {
        return Some(format!("`{pointer}` is not FILE::NAME"));
    };
    let path = if file.ends_with(".rs") {
        repo_root().join(file)
    } else {
        // A module of one of the test binaries, tests/tests/BINARY/FILE.rs.
        let tests = repo_root().join("tests/tests");
        let module = format!("{file}.rs");
        fs::read_dir(&tests)
            .into_iter()
            .flatten()
            .flatten()
            .map(|binary| binary.path().join(&module))
            .find(|path| path.is_file())
            .unwrap_or_else(|| tests.join(&module))
    };
    let Ok(text) = fs::read_to_string(&path) else {
        return Some(format!("`{pointer}`: no file {}", path.display()));
    };
    (!text.contains(&format!("fn {name}("))).then(|| format!("`{pointer}`: no fn {name} in {file}"))
}

/// Each claim of `text`: (the sentence, its pointers).
fn claims(text: &str) -> Vec<(String, Vec<String>)> {
    blocks(text)
        .iter()
        .flat_map(|b| sentences(b))
        .filter(|s| is_claim(s))
        .map(|s| {
            let p = pointers(&s);
            (s.trim().to_string(), p)
        })
        .collect()
}

#[test]
fn every_claim_names_the_test_that_holds_it() {
    let mut report = Vec::new();
    let docs = HELD.iter().chain(UNHELD_AT_MOST.iter().map(|(d, _)| d));
    for doc in docs {
        let text = fs::read_to_string(repo_root().join(doc)).unwrap();
        let found = claims(&text);
        let unheld: Vec<&String> = found
            .iter()
            .filter(|(_, p)| p.is_empty())
            .map(|(s, _)| s)
            .collect();
        for (s, ps) in &found {
            for p in ps {
                if let Some(why) = broken(p) {
                    report.push(format!("{doc}: {why}: {s}"));
                }
            }
        }
        if HELD.contains(doc) {
            report.extend(
                unheld
                    .iter()
                    .map(|s| format!("{doc}: no (held by `…`): {s}")),
            );
        } else {
            let most = UNHELD_AT_MOST
                .iter()
                .find(|(d, _)| d == doc)
                .map_or(0, |m| m.1);
            if unheld.len() > most {
                report.push(format!(
                    "{doc}: {} claims without a (held by `…`), at most {most}",
                    unheld.len()
                ));
            }
        }
    }
    assert!(report.is_empty(), "{}", report.join("\n"));
}

#[test]
fn the_check_reads_sentences_across_lines_and_finds_bad_pointers() {
    let text = "Intro line.\nThe frames are the same bytes\nat every depth (held by\n`differential::a_seed_gives_one_scene`). Exactly so, not a claim.\n\n```\nbyte for byte in code\n```\n| a | byte for byte |\n";
    let found = claims(text);
    assert_eq!(found.len(), 2, "{found:?}");
    assert_eq!(found[0].1, ["differential::a_seed_gives_one_scene"]);
    assert!(broken(&found[0].1[0]).is_none());
    assert!(found[1].1.is_empty());
    assert!(broken("differential::no_such_test").is_some());
    assert!(broken("nowhere::x").is_some());
    assert!(broken("bins/zspec/src/main.rs::main").is_none());
}
