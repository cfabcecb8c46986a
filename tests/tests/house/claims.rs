//! Claims held by name: a sentence of README.md or docs/*.md that says "byte for byte",
//! "exact", "the same bytes", "says so" or "bounded" points to the test that holds it, as
//! `(held by `FILE::NAME`)`: FILE a module of a test binary under tests/tests/ without `.rs`
//! (`differential::supersampling_is_zspec_samples_k`), or any `.rs` path from the
//! repository root (`bins/scan/src/lib.rs::name`); NAME a test in it (a `#[test]` function,
//! proptest's included). Sentences are read across line breaks (a paragraph, a list item or
//! a table row is joined first), code blocks are skipped. A heading is not read: a pointer
//! in it would change its anchor, and the sentences under it hold what it names.

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

/// The documents whose every claim must name its test: the README and every page of docs/.
fn documents() -> Vec<String> {
    let mut docs: Vec<String> = fs::read_dir(repo_root().join("docs"))
        .expect("docs/")
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".md"))
        .map(|n| format!("docs/{n}"))
        .collect();
    docs.sort();
    docs.insert(0, "README.md".to_string());
    docs
}

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
    let lines: Vec<&str> = text.lines().collect();
    for (i, line) in lines.iter().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            flush(&mut cur, &mut out);
            continue;
        }
        if fenced || line.starts_with("    ") && cur.is_empty() {
            continue;
        }
        // A table's header row names its columns and claims nothing.
        let separator = |l: &&str| {
            let l = l.trim();
            l.starts_with("|-") || l.starts_with("| -") || l.starts_with("|:")
        };
        if line.trim_start().starts_with('|') && lines.get(i + 1).is_some_and(separator) {
            continue;
        }
        let t = line.trim();
        if t.is_empty() || t.starts_with('#') {
            flush(&mut cur, &mut out);
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

/// Whether a sentence is a claim: one of [`CLAIMS`] as words, in its prose (code spans,
/// a path or an option between backquotes, are not read).
fn is_claim(sentence: &str) -> bool {
    let prose: String = sentence.split('`').step_by(2).collect::<Vec<_>>().join(" ");
    let lower = prose.to_lowercase();
    CLAIMS.iter().any(|c| {
        lower.match_indices(c).any(|(at, _)| {
            let after = lower[at + c.len()..].chars().next();
            let before = lower[..at].chars().next_back();
            !after.is_some_and(|a| a.is_alphanumeric())
                && !before.is_some_and(|b| b.is_alphanumeric())
        })
    })
}

/// The `(held by `X::Y`)` pointers of a sentence: every backquoted name between `held by`
/// and the closing parenthesis (`(held by `a::b`, `c::d`)`).
fn pointers(sentence: &str) -> Vec<String> {
    sentence
        .match_indices("held by `")
        .flat_map(|(at, m)| {
            let rest = &sentence[at + m.len() - 1..];
            let inside = rest.split_once(')').map_or(rest, |(i, _)| i);
            inside
                .split('`')
                .skip(1)
                .step_by(2)
                .map(str::to_string)
                .collect::<Vec<_>>()
        })
        .collect()
}

/// What is wrong with a pointer: a file that is not there (a module of no test binary, or
/// of two), or no test of that name in it.
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
        let found: Vec<_> = fs::read_dir(&tests)
            .into_iter()
            .flatten()
            .flatten()
            .map(|binary| binary.path().join(&module))
            .filter(|path| path.is_file())
            .collect();
        match found.as_slice() {
            [one] => one.clone(),
            [] => return Some(format!("`{pointer}`: no test module {file}")),
            _ => return Some(format!("`{pointer}`: {file} is a module of two binaries")),
        }
    };
    let Ok(text) = fs::read_to_string(&path) else {
        return Some(format!("`{pointer}`: no file {}", path.display()));
    };
    (!is_test(&text, name)).then(|| format!("`{pointer}`: no test {name} in {file}"))
}

/// Whether `text` has a function `name` that is a test: `#[test]` among the attributes
/// right above it (other attributes and doc comments may stand between).
fn is_test(text: &str, name: &str) -> bool {
    let lines: Vec<&str> = text.lines().collect();
    let head = format!("fn {name}(");
    lines.iter().enumerate().any(|(i, line)| {
        let t = line.trim_start();
        (t.starts_with(&head) || t.starts_with(&format!("pub {head}")))
            && lines[..i]
                .iter()
                .rev()
                .map(|l| l.trim())
                .take_while(|l| l.starts_with("#[") || l.starts_with("//") || l.ends_with(")]"))
                .any(|l| l == "#[test]")
    })
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
    for doc in documents() {
        let text = fs::read_to_string(repo_root().join(&doc)).unwrap();
        for (s, ps) in claims(&text) {
            if ps.is_empty() {
                report.push(format!("{doc}: no (held by `…`): {s}"));
            }
            for p in ps {
                if let Some(why) = broken(&p) {
                    report.push(format!("{doc}: {why}: {s}"));
                }
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
    let two = claims("It is exact (held by `a::b`, `c::d`). Then.");
    assert_eq!(two[0].1, ["a::b", "c::d"]);
    assert_eq!(found[0].1, ["differential::a_seed_gives_one_scene"]);
    assert!(broken(&found[0].1[0]).is_none());
    assert!(found[1].1.is_empty());
    assert!(broken("differential::no_such_test").is_some());
    assert!(broken("nowhere::x").is_some());
    // A test that exists, named by the wrong module or path.
    assert!(broken("painter::a_seed_gives_one_scene").is_some());
    assert!(broken("surfaces::differential::a_seed_gives_one_scene").is_some());
    assert!(broken("tests/tests/surfaces/painter.rs::a_seed_gives_one_scene").is_some());
    assert!(broken("tests/tests/surfaces/differential.rs::a_seed_gives_one_scene").is_none());
    // A function that is not a test.
    assert!(broken("differential::holds").is_some());
    assert!(broken("bins/zspec/src/main.rs::main").is_some());
    // A heading is not a sentence, nor a table's header row, nor a code span; the claims
    // under them are.
    let found = claims("## The method is exact\n\nIt is exact.\n\n| exact? |\n|---|\n| exact |\n");
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(claims("In `reference/src/exact.rs`.").is_empty());
}
