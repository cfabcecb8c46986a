//! The workspace's shape, read from `cargo metadata` and from its sources.
//!
//! Between crates: `proto` is the stream and the geometry, with no command-line parser
//! in it; `stagecli` is a stage binary's skeleton and links no rasteriser (`scan`), so a
//! geometry stage (viewxf, persp) links none either; no crate under `bins/` (a stage,
//! or a tool that composes, plans or measures them: render, plan, chart) depends on
//! another one: shared code lives in the libraries at the top (proto, stagecli, scan,
//! leaf, methods, costmodel, reference). No two crates depend on each other, through
//! any kind of dependency (a dev-dependency too: the end-to-end helpers link stage
//! libraries, so a stage's tests that need those helpers live in tests/).
//!
//! Within a crate: the files of its top-level modules, joined by every `crate::x` (and
//! `super::x` that reaches the crate's root) their code names, form no circle. A circle between two
//! files means neither can be read, tested or moved without the other; records apart
//! from their codecs, a parser in a module of its own, are how the libraries cut theirs.

use pipeline_tests::repo_root;
use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

// ---------------------------------------------------------------------------------------
// Manifests

/// What a dependency is for: the code (`[dependencies]`, `[build-dependencies]`), or
/// only its tests (`[dev-dependencies]`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum DepKind {
    Normal,
    Build,
    Dev,
}

/// One workspace crate: its package name, its folder (relative to the root), the
/// workspace crates it depends on, and every crate its code depends on (the registry's
/// too: `[dependencies]`, `[build-dependencies]`), by package name.
#[derive(Clone, Debug)]
struct Member {
    name: String,
    dir: PathBuf,
    deps: Vec<(String, DepKind)>,
    code_deps: Vec<String>,
}

/// The workspace as cargo reads it: `cargo metadata --format-version 1 --no-deps`, so
/// that every form a manifest may take (`x.workspace = true`, a path, a renamed package,
/// `[target.'cfg(…)'.dependencies]`) is cargo's to read, not this test's.
fn members() -> Vec<Member> {
    let root = repo_root();
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let out = std::process::Command::new(cargo)
        .args([
            "metadata",
            "--format-version",
            "1",
            "--no-deps",
            "--offline",
        ])
        .current_dir(&root)
        .output()
        .expect("cargo metadata");
    assert!(
        out.status.success(),
        "cargo metadata: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let meta: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let root = std::path::absolute(&root).unwrap();
    let packages = meta["packages"].as_array().unwrap();
    let names: BTreeSet<&str> = packages.iter().filter_map(|p| p["name"].as_str()).collect();
    packages
        .iter()
        .map(|p| {
            let manifest = Path::new(p["manifest_path"].as_str().unwrap());
            let dir = manifest.parent().unwrap().strip_prefix(&root).unwrap();
            let all_deps = p["dependencies"].as_array().unwrap();
            let kind = |d: &serde_json::Value| match d["kind"].as_str() {
                Some("dev") => DepKind::Dev,
                Some("build") => DepKind::Build,
                _ => DepKind::Normal,
            };
            let name = |d: &serde_json::Value| d["name"].as_str().unwrap().to_string();
            Member {
                name: p["name"].as_str().unwrap().to_string(),
                dir: dir.to_path_buf(),
                deps: all_deps
                    .iter()
                    .filter(|d| {
                        d["path"].is_string() && names.contains(d["name"].as_str().unwrap())
                    })
                    .map(|d| (name(d), kind(d)))
                    .collect(),
                code_deps: all_deps
                    .iter()
                    .filter(|d| kind(d) != DepKind::Dev)
                    .map(name)
                    .collect(),
            }
        })
        .collect()
}

fn member<'a>(all: &'a [Member], name: &str) -> &'a Member {
    all.iter()
        .find(|m| m.name == name)
        .unwrap_or_else(|| panic!("no workspace member {name}"))
}

/// The dependencies of `name` of the kinds `kinds`, sorted.
fn deps_of(all: &[Member], name: &str, kinds: &[DepKind]) -> Vec<String> {
    let mut d: Vec<String> = member(all, name)
        .deps
        .iter()
        .filter(|(_, k)| kinds.contains(k))
        .map(|(n, _)| n.clone())
        .collect();
    d.sort();
    d.dedup();
    d
}

/// Everything `name` links: its dependencies of `kinds`, theirs, and so on.
fn linked(all: &[Member], name: &str, kinds: &[DepKind]) -> BTreeSet<String> {
    let mut seen = BTreeSet::new();
    let mut todo = deps_of(all, name, kinds);
    while let Some(n) = todo.pop() {
        if seen.insert(n.clone()) {
            todo.extend(deps_of(all, &n, &[DepKind::Normal, DepKind::Build]));
        }
    }
    seen
}

/// The crates under bins/ that are not stages of the stream: the composer, the cost
/// model's command line, the chart and the benchmarks.
const TOOLS: [&str; 4] = ["bench", "chart", "plan", "render"];

/// The binary crates: the folders under bins/.
fn binaries(all: &[Member]) -> Vec<&Member> {
    all.iter().filter(|m| m.dir.starts_with("bins")).collect()
}

/// The stage crates: the folders under bins/ that are not tools.
fn stages(all: &[Member]) -> Vec<&Member> {
    binaries(all)
        .into_iter()
        .filter(|m| !TOOLS.contains(&m.name.as_str()))
        .collect()
}

const CODE: [DepKind; 2] = [DepKind::Normal, DepKind::Build];
const ALL: [DepKind; 3] = [DepKind::Normal, DepKind::Build, DepKind::Dev];

#[test]
fn the_workspace_is_read_as_cargo_reads_it() {
    let all = members();
    assert!(stages(&all).len() >= 9);
    // `proto.workspace = true`
    assert_eq!(deps_of(&all, "stagecli", &CODE), ["proto"]);
    // `costmodel.workspace = true`, through the root's `costmodel = { path = "costmodel" }`
    assert!(deps_of(&all, "render", &CODE).contains(&"costmodel".to_string()));
    // `splitter = { path = "../bins/splitter" }`
    assert!(deps_of(&all, "pipeline-tests", &CODE).contains(&"splitter".to_string()));
    assert_eq!(member(&all, "render").dir, Path::new("bins/render"));
}

#[test]
fn no_crate_under_bins_depends_on_another() {
    let all = members();
    let names: Vec<&str> = binaries(&all).iter().map(|m| m.name.as_str()).collect();
    for krate in binaries(&all) {
        let deps: Vec<String> = deps_of(&all, &krate.name, &ALL)
            .into_iter()
            .filter(|d| names.contains(&d.as_str()))
            .collect();
        assert!(
            deps.is_empty(),
            "{}/Cargo.toml depends on the crates under bins/ {deps:?}",
            krate.dir.display()
        );
    }
}

#[test]
fn stagecli_and_the_geometry_stages_link_no_rasteriser() {
    let all = members();
    for name in [
        "stagecli",
        "viewxf",
        "persp",
        "clipplane",
        "clipbatch",
        "splitter",
    ] {
        let links = linked(&all, name, &CODE);
        assert!(
            links.contains("proto") || name == "proto",
            "{name}: {links:?}"
        );
        assert!(!links.contains("scan"), "{name} links scan: {links:?}");
    }
    // The leaf's loop is where the rasteriser comes in.
    assert_eq!(deps_of(&all, "leaf", &CODE), ["proto", "scan", "stagecli"]);
}

/// The groups of nodes of `graph` that reach each other (its strongly connected
/// components of more than one node), each sorted.
fn circles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    let reach = |from: &String| -> BTreeSet<String> {
        let mut seen = BTreeSet::new();
        let mut todo: Vec<&String> = graph.get(from).into_iter().flatten().collect();
        while let Some(n) = todo.pop() {
            if seen.insert(n.clone()) {
                todo.extend(graph.get(n).into_iter().flatten());
            }
        }
        seen
    };
    let reached: BTreeMap<&String, BTreeSet<String>> =
        graph.keys().map(|k| (k, reach(k))).collect();
    let mut groups: BTreeSet<Vec<String>> = BTreeSet::new();
    for (a, from_a) in &reached {
        let group: Vec<String> = reached
            .iter()
            .filter(|(b, from_b)| {
                a == *b || (from_a.contains(b.as_str()) && from_b.contains(a.as_str()))
            })
            .map(|(b, _)| b.to_string())
            .collect();
        if group.len() > 1 {
            groups.insert(group);
        }
    }
    groups.into_iter().collect()
}

#[test]
fn no_circle_between_crates() {
    let all = members();
    let graph: BTreeMap<String, BTreeSet<String>> = all
        .iter()
        .map(|m| {
            (
                m.name.clone(),
                deps_of(&all, &m.name, &ALL).into_iter().collect(),
            )
        })
        .collect();
    let found = circles(&graph);
    assert!(
        found.is_empty(),
        "crates that depend on each other: {found:?}"
    );
}

#[test]
fn proto_has_no_command_line_parser() {
    let all = members();
    let deps = &member(&all, "proto").code_deps;
    assert!(deps.iter().any(|d| d == "glam"), "{deps:?}");
    for cli in ["clap", "anyhow", "stagecli"] {
        assert!(!deps.iter().any(|d| d == cli), "proto depends on {cli}");
    }
}

// ---------------------------------------------------------------------------------------
// Module files

/// `source` with its comments, string and character literals blanked (newlines kept,
/// so that a position is still on its line) and its `#[cfg(test)] mod … { … }` bodies
/// taken out: what the code of the module names, and not its tests.
fn code_of(source: &str) -> String {
    let s: Vec<char> = source.chars().collect();
    let mut out: Vec<char> = Vec::with_capacity(s.len());
    let ident = |c: char| c.is_alphanumeric() || c == '_';
    let blank = |out: &mut Vec<char>, c: char| out.push(if c == '\n' { '\n' } else { ' ' });
    let mut i = 0;
    while i < s.len() {
        let c = s[i];
        let next = s.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < s.len() && s[i] != '\n' {
                blank(&mut out, s[i]);
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < s.len() {
                if s[i] == '/' && s.get(i + 1) == Some(&'*') {
                    depth += 1;
                    out.extend([' ', ' ']);
                    i += 2;
                } else if s[i] == '*' && s.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    out.extend([' ', ' ']);
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    blank(&mut out, s[i]);
                    i += 1;
                }
            }
        } else if c == 'r'
            && (i == 0 || !ident(s[i - 1]) || (s[i - 1] == 'b' && (i < 2 || !ident(s[i - 2]))))
            && matches!(next, Some('"' | '#'))
            && {
                let hashes = s[i + 1..].iter().take_while(|&&h| h == '#').count();
                s.get(i + 1 + hashes) == Some(&'"')
            }
        {
            // A raw string: r"…", r#"…"#, br"…".
            let hashes = s[i + 1..].iter().take_while(|&&h| h == '#').count();
            let close: Vec<char> = std::iter::once('"')
                .chain(std::iter::repeat_n('#', hashes))
                .collect();
            let start = i;
            i += 2 + hashes;
            while i < s.len() && !s[i..].starts_with(&close) {
                i += 1;
            }
            i = (i + close.len()).min(s.len());
            for &c in &s[start..i] {
                blank(&mut out, c);
            }
        } else if c == '"' {
            blank(&mut out, c);
            i += 1;
            while i < s.len() && s[i] != '"' {
                if s[i] == '\\' {
                    blank(&mut out, s[i]);
                    i += 1;
                }
                if i < s.len() {
                    blank(&mut out, s[i]);
                    i += 1;
                }
            }
            if i < s.len() {
                blank(&mut out, s[i]);
                i += 1;
            }
        } else if c == '\'' {
            // A character literal ('x', '\n', '\u{1F600}'), or a lifetime ('a), kept.
            let len = if next == Some('\\') {
                s[i + 2..].iter().position(|&c| c == '\'').map(|p| p + 3)
            } else if s.get(i + 2) == Some(&'\'') {
                Some(3)
            } else {
                None
            };
            match len {
                Some(n) => {
                    for &c in &s[i..(i + n).min(s.len())] {
                        blank(&mut out, c);
                    }
                    i += n;
                }
                None => {
                    out.push(c);
                    i += 1;
                }
            }
        } else {
            out.push(c);
            i += 1;
        }
    }
    let mut code: String = out.into_iter().collect();
    // Take out the tests: `#[cfg(test)]`, then `mod NAME {`, to its closing brace.
    while let Some(at) = code.find("#[cfg(test)]") {
        let after = at + "#[cfg(test)]".len();
        let rest = code[after..].trim_start();
        let Some(body) = rest.strip_prefix("mod ") else {
            // `#[cfg(test)]` on something else (an item only the tests use): its
            // attribute goes, and the item is read as code.
            code.replace_range(at..after, "");
            continue;
        };
        let open = body.find(['{', ';']).map(|p| code.len() - body.len() + p);
        let Some(open) = open.filter(|&p| code.as_bytes()[p] == b'{') else {
            // `mod tests;`: a file of its own, for the tests only.
            let end = open.map_or(code.len(), |p| p + 1);
            code.replace_range(at..end, "");
            continue;
        };
        let mut depth = 0;
        let mut end = code.len();
        for (k, b) in code.bytes().enumerate().skip(open) {
            match b {
                b'{' => depth += 1,
                b'}' => {
                    depth -= 1;
                    if depth == 0 {
                        end = k + 1;
                        break;
                    }
                }
                _ => {}
            }
        }
        code.replace_range(at..end, "");
    }
    code
}

/// The items of a use tree after its leading `crate::`/`self::`, as (the first segment
/// of its path, the name it binds): `a::{B, c::D as E}` → (a, B), (a, E); `a::{self}`
/// → (a, a); `a::*` → (a, *).
fn use_tree(tree: &str) -> Vec<(String, String)> {
    // Words and the punctuation of a use tree.
    let mut tokens: Vec<String> = Vec::new();
    let mut chars = tree.chars().peekable();
    while let Some(c) = chars.next() {
        if c.is_alphanumeric() || c == '_' {
            let mut w = c.to_string();
            while let Some(&d) = chars.peek().filter(|d| d.is_alphanumeric() || **d == '_') {
                w.push(d);
                chars.next();
            }
            tokens.push(w);
        } else if c == ':' && chars.peek() == Some(&':') {
            chars.next();
            tokens.push("::".into());
        } else if !c.is_whitespace() {
            tokens.push(c.to_string());
        }
    }
    let mut start = 0;
    if tokens.first().map(String::as_str) == Some("::") {
        start = 1;
    } else if matches!(tokens.first().map(String::as_str), Some("crate" | "self"))
        && tokens.get(1).map(String::as_str) == Some("::")
    {
        start = 2;
    }
    let mut out = Vec::new();
    let mut i = start;
    use_item(&tokens, &mut i, None, None, &mut out);
    out
}

/// One item of a use tree from `tokens[*i]`: `first` is the first segment of the path
/// it continues, `parent` the segment before its group (what `self` binds).
fn use_item(
    tokens: &[String],
    i: &mut usize,
    first: Option<&str>,
    parent: Option<&str>,
    out: &mut Vec<(String, String)>,
) {
    let tok = |k: usize| tokens.get(k).map_or("", String::as_str);
    match tok(*i) {
        "{" => {
            *i += 1;
            while !matches!(tok(*i), "}" | "") {
                use_item(tokens, i, first, parent, out);
                if tok(*i) == "," {
                    *i += 1;
                }
            }
            *i += 1;
            return;
        }
        "*" => {
            *i += 1;
            out.push((first.unwrap_or("*").into(), "*".into()));
            return;
        }
        _ => {}
    }
    let mut segments: Vec<&str> = Vec::new();
    loop {
        segments.push(tok(*i));
        *i += 1;
        if tok(*i) != "::" {
            break;
        }
        *i += 1;
        if matches!(tok(*i), "{" | "*") {
            let head = first.unwrap_or(segments[0]);
            let last = segments.last().copied();
            use_item(tokens, i, Some(head), last, out);
            return;
        }
    }
    let head = first.unwrap_or(segments[0]);
    let mut name = segments.last().copied().unwrap_or_default();
    if name == "self" {
        name = parent.unwrap_or(head);
    }
    if tok(*i) == "as" {
        name = tok(*i + 1);
        *i += 2;
    }
    out.push((head.to_string(), name.to_string()));
}

/// The `use` statements of a crate root at its top level, as their trees.
fn root_uses(code: &str) -> Vec<String> {
    top_level_statements(code)
        .into_iter()
        .filter_map(|s| {
            // Attributes (`#[doc(inline)]`) may come first.
            let s = s.rsplit(']').next().unwrap_or(s);
            let words: Vec<&str> = s.split_whitespace().collect();
            let at = words.iter().position(|w| *w == "use")?;
            // Only visibility before `use`: `pub`, `pub(crate)`.
            words[..at]
                .iter()
                .all(|w| w.starts_with("pub"))
                .then(|| words[at + 1..].join(" "))
        })
        .collect()
}

/// The statements of `code` at its top level that end in `;` (not inside a brace).
fn top_level_statements(code: &str) -> Vec<&str> {
    let mut statements = Vec::new();
    let mut depth = 0i32;
    let mut start = 0;
    for (k, c) in code.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => {
                depth -= 1;
                // A block ends an item (`fn f() { … }`); a group before `;` does not
                // (`use a::{B, C};`).
                if depth == 0 && !code[k + 1..].trim_start().starts_with(';') {
                    start = k + 1;
                }
            }
            ';' if depth == 0 => {
                statements.push(code[start..k].trim());
                start = k + 1;
            }
            _ => {}
        }
    }
    statements
}

/// The modules a crate root declares in files (`mod x;`, `pub mod x;`, …), not those
/// for tests only.
fn declared_modules(source: &str) -> Vec<String> {
    let code = code_of(source);
    top_level_statements(&code)
        .into_iter()
        .filter_map(|s| {
            // Attributes (`#[cfg(unix)]`) and visibility may come first.
            let s = s.rsplit(']').next().unwrap_or(s);
            let words: Vec<&str> = s.split_whitespace().collect();
            match words.as_slice() {
                [vis @ .., "mod", name] if vis.iter().all(|w| w.starts_with("pub")) => {
                    Some(name.to_string())
                }
                _ => None,
            }
        })
        .collect()
}

/// The paths the code of a module file names from its crate's root: the first segment
/// after each `crate::` (a `crate::{a, b::C}` group gives each of its items'), and after
/// each `super::…` that climbs to the root from `depth` (1 for `src/x.rs`, 2 for
/// `src/x/y.rs`, one more inside each inline `mod … {`).
fn root_paths(code: &str, depth: usize) -> Vec<String> {
    let bytes = code.as_bytes();
    let ident = |b: u8| b.is_ascii_alphanumeric() || b == b'_';
    // The word at `k` and where it ends, if it is `w` whole.
    let word = |k: usize, w: &str| {
        (code[k..].starts_with(w)
            && (k == 0 || !ident(bytes[k - 1]))
            && !bytes.get(k + w.len()).is_some_and(|&b| ident(b)))
        .then_some(k + w.len())
    };
    // After `::` (whitespace either side), if it is there.
    let colons = |k: usize| {
        let t = code[k..].trim_start().strip_prefix("::")?;
        Some(code.len() - t.trim_start().len())
    };
    let mut found = Vec::new();
    let mut inline_mods: Vec<i32> = Vec::new();
    let mut braces = 0i32;
    let mut k = 0;
    while k < bytes.len() {
        match bytes[k] {
            b'{' => {
                braces += 1;
                let mut words = code[..k].split_whitespace().rev();
                let _name = words.next();
                if words.next() == Some("mod") {
                    inline_mods.push(braces);
                }
            }
            b'}' => {
                if inline_mods.last() == Some(&braces) {
                    inline_mods.pop();
                }
                braces -= 1;
            }
            _ => {}
        }
        // `crate::` reaches the root from anywhere; `super::` × n from depth n.
        let mut path = word(k, "crate").and_then(colons).map(|j| (j, true));
        if path.is_none() {
            let mut n = 0;
            let mut j = k;
            while let Some(after) = word(j, "super").and_then(colons) {
                n += 1;
                j = after;
            }
            if n > 0 {
                path = Some((j, n == depth + inline_mods.len()));
            }
        }
        let Some((after, to_root)) = path else {
            k += 1;
            continue;
        };
        if to_root {
            let tail = &code[after..];
            if let Some(group) = tail.strip_prefix('{') {
                let inside = &group[..matching_brace(group)];
                let mut firsts: Vec<String> = use_tree(&format!("{{{inside}}}"))
                    .into_iter()
                    .map(|(f, _)| f)
                    .collect();
                firsts.dedup();
                found.extend(firsts);
            } else {
                let name: String = tail
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if !name.is_empty() {
                    found.push(name);
                }
            }
        }
        k = after;
    }
    found
}

/// The length of a group's inside: `group` starts after its `{`.
fn matching_brace(group: &str) -> usize {
    let mut depth = 1;
    for (k, c) in group.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => {
                depth -= 1;
                if depth == 0 {
                    return k;
                }
            }
            _ => {}
        }
    }
    group.len()
}

/// One crate root's modules and the edges between them: module → (module it names,
/// the file that names it).
type ModuleGraph = BTreeMap<String, BTreeMap<String, BTreeSet<String>>>;

/// The graph of the top-level modules of the crate whose root is `root` (lib.rs,
/// main.rs, bin/x.rs): an edge a → b for each file of module `a` that names `b` from
/// the root, by its own name (`crate::b::…`) or by a name the root re-exports from it
/// (`crate::B` after `pub use b::B`).
fn module_graph(root: &Path) -> ModuleGraph {
    let source = fs::read_to_string(root).unwrap();
    let dir = root.parent().unwrap();
    let modules = declared_modules(&source);
    // What the root's `use` statements bind, and from which module.
    let mut names: BTreeMap<String, String> = BTreeMap::new();
    for tree in root_uses(&code_of(&source)) {
        for (first, bound) in use_tree(&tree) {
            if modules.contains(&first) && bound != "*" {
                names.insert(bound, first);
            }
        }
    }
    for m in &modules {
        names.insert(m.clone(), m.clone());
    }
    let mut graph = ModuleGraph::new();
    for m in &modules {
        let mut files: Vec<(PathBuf, usize)> = Vec::new();
        let flat = dir.join(format!("{m}.rs"));
        if flat.exists() {
            files.push((flat, 1));
        }
        let folder = dir.join(m);
        if folder.is_dir() {
            let mut todo = vec![(folder, 2usize)];
            while let Some((d, depth)) = todo.pop() {
                for e in fs::read_dir(&d).unwrap() {
                    let p = e.unwrap().path();
                    if p.is_dir() {
                        todo.push((p, depth + 1));
                    } else if p.extension().is_some_and(|x| x == "rs") {
                        let mod_rs = p.file_name().is_some_and(|n| n == "mod.rs");
                        files.push((p, if mod_rs { depth - 1 } else { depth }));
                    }
                }
            }
        }
        let edges = graph.entry(m.clone()).or_default();
        for (file, depth) in files {
            let code = code_of(&fs::read_to_string(&file).unwrap());
            let shown = file
                .strip_prefix(repo_root())
                .unwrap_or(&file)
                .display()
                .to_string();
            for first in root_paths(&code, depth) {
                if let Some(target) = names.get(&first).filter(|t| *t != m) {
                    edges
                        .entry(target.clone())
                        .or_default()
                        .insert(shown.clone());
                }
            }
        }
    }
    graph
}

/// The crate roots of a member: src/lib.rs, src/main.rs, src/bin/*.rs.
fn crate_roots(dir: &Path) -> Vec<PathBuf> {
    let src = dir.join("src");
    let mut roots: Vec<PathBuf> = ["lib.rs", "main.rs"]
        .iter()
        .map(|f| src.join(f))
        .filter(|p| p.exists())
        .collect();
    if let Ok(bins) = fs::read_dir(src.join("bin")) {
        roots.extend(
            bins.map(|e| e.unwrap().path())
                .filter(|p| p.extension().is_some_and(|x| x == "rs")),
        );
    }
    roots.sort();
    roots
}

/// The circles among a graph's modules, each with the files that close it.
fn module_circles(graph: &ModuleGraph) -> Vec<(Vec<String>, Vec<String>)> {
    let plain: BTreeMap<String, BTreeSet<String>> = graph
        .iter()
        .map(|(m, e)| (m.clone(), e.keys().cloned().collect()))
        .collect();
    circles(&plain)
        .into_iter()
        .map(|circle| {
            let mut why = Vec::new();
            for a in &circle {
                for (b, files) in &graph[a] {
                    if circle.contains(b) {
                        for f in files {
                            why.push(format!("{f} names {b}"));
                        }
                    }
                }
            }
            (circle, why)
        })
        .collect()
}

#[test]
fn module_files_are_read_as_the_compiler_reads_them() {
    let source = r##"
        //! crate::doc is a comment
        use crate::{alpha::A, beta, gamma::{x::Y, Z}};
        use super::super::delta::D;
        const S: &str = "crate::string";
        const R: &str = r#"crate::raw"#;
        const C: char = '"';
        fn f<'a>(x: &'a str) -> crate::Epsilon { crate :: zeta::z() }
        mod inner {
            use super::super::eta::H;
        }
        #[cfg(test)]
        mod tests {
            use crate::theta::T;
        }
    "##;
    let code = code_of(source);
    assert!(!code.contains("string") && !code.contains("raw") && !code.contains("theta"));
    assert!(code.contains("'a str"));
    // From src/x/y.rs (depth 2): super::super is the root; inside `mod inner` it is one
    // level short, and reaches only x.
    assert_eq!(
        root_paths(&code, 2),
        ["alpha", "beta", "gamma", "delta", "Epsilon", "zeta"]
    );
    assert_eq!(
        use_tree("{A, b::C as D, e::{self, F, g::H}}"),
        [("A", "A"), ("b", "D"), ("e", "e"), ("e", "F"), ("e", "H")]
            .map(|(a, b)| (a.into(), b.into()))
    );
    assert_eq!(
        use_tree("crate::codec::{Form, Reader as R}"),
        [("codec", "Form"), ("codec", "R")].map(|(a, b)| (a.into(), b.into()))
    );
    assert_eq!(
        declared_modules(
            "pub mod a;\n#[cfg(unix)]\npub(crate) mod b;\n#[cfg(test)]\nmod tests;\nmod c { }\n"
        ),
        ["a", "b"]
    );
}

#[test]
fn a_circle_between_module_files_is_found_with_its_files() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("src");
    fs::create_dir_all(src.join("c")).unwrap();
    let write = |p: &str, t: &str| fs::write(src.join(p), t).unwrap();
    write(
        "lib.rs",
        "pub mod a;\npub mod b;\npub mod c;\npub use b::Bee;\n",
    );
    write("a.rs", "use crate::Bee;\n");
    write("b.rs", "pub struct Bee;\nfn f() { crate::c::g() }\n");
    write("c.rs", "mod d;\n");
    write("c/d.rs", "use super::super::a;\n");
    let graph = module_graph(&src.join("lib.rs"));
    let circles = module_circles(&graph);
    assert_eq!(circles.len(), 1, "{graph:?}");
    let (modules, why) = &circles[0];
    assert_eq!(modules, &["a", "b", "c"]);
    let files: Vec<String> = why
        .iter()
        .map(|w| w.rsplit('/').take(2).collect::<Vec<_>>().join(" < "))
        .collect();
    assert_eq!(
        files,
        [
            "a.rs names b < src",
            "b.rs names c < src",
            "d.rs names a < c"
        ]
    );
}

#[test]
fn no_circle_between_module_files() {
    let mut found = Vec::new();
    for m in members() {
        for root in crate_roots(&repo_root().join(&m.dir)) {
            for (circle, why) in module_circles(&module_graph(&root)) {
                found.push((m.name.clone(), circle, why));
            }
        }
    }
    let said: Vec<String> = found
        .iter()
        .map(|(krate, circle, why)| format!("{krate}: {} ({})", circle.join(" ↔ "), why.join("; ")))
        .collect();
    assert!(
        said.is_empty(),
        "import circles between module files:\n{}",
        said.join("\n")
    );
}

#[test]
fn protos_records_are_apart_from_their_codecs() {
    let graph = module_graph(&repo_root().join("proto/src/lib.rs"));
    let names = |m: &str| -> Vec<&str> { graph[m].keys().map(String::as_str).collect() };
    // The polygon records need Newell's plane (for the plane a polygon records), and
    // nothing of the stream's forms; the codec is above them.
    assert_eq!(names("polygon"), ["newell"]);
    assert_eq!(names("header"), ["depth", "error", "shade"]);
    assert_eq!(
        names("codec"),
        ["error", "header", "polygon", "shade", "text"]
    );
    // A plane from the command line is read by the number parser, not by the camera; a
    // crossing too far out to interpolate is computed by `exact`, which needs nothing.
    assert_eq!(
        names("geometry"),
        ["exact", "header", "newell", "numbers", "polygon"]
    );
    assert!(names("exact").is_empty(), "{:?}", names("exact"));
}

#[test]
fn the_table_of_methods_depends_on_nothing_and_no_stage_reads_it() {
    let all = members();
    let deps = &member(&all, "methods").code_deps;
    assert!(
        deps.is_empty(),
        "methods depends on {deps:?}: the table is plain data"
    );
    // Its readers are the tools (render, chart) and the tests, never a stage.
    for stage in stages(&all) {
        assert!(
            !deps_of(&all, &stage.name, &ALL).contains(&"methods".to_string()),
            "{} depends on the table of methods",
            stage.name
        );
    }
    for tool in ["render", "chart"] {
        assert!(
            deps_of(&all, tool, &CODE).contains(&"methods".to_string()),
            "{tool} reads its methods from elsewhere"
        );
    }
}
