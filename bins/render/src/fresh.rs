//! The binaries kept current with their sources, for a render started by
//! `scripts/render.sh` (which names the repository in `POLYPIPE_SOURCES`).
//!
//! `cargo build --release` with nothing to do takes about 0.1 s, several times a small
//! render; so render looks first, with a stat a file: when no source of any binary is
//! newer than the oldest binary (and than the last time it asked cargo), it starts the
//! render at once. Otherwise cargo builds, and a render binary cargo rebuilt is started
//! again in place of this one.

use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// The stages a render runs whatever its method ([`crate::PIPELINE_STAGES`]), and the
/// other binaries the README's examples use; [`binaries`] adds the methods' stages from
/// the table of methods: all built together, so that every command in the README works
/// after the first run.
pub const BINARIES: [&str; 15] = join(
    &crate::PIPELINE_STAGES,
    &[
        "scene", "zspec", "frames", "farm", "chart", "plan", "render", "bench",
    ],
);

/// `a` then `b`, as one array of `N` names (N their lengths' sum, checked as it is built).
const fn join<const N: usize>(a: &[&'static str], b: &[&'static str]) -> [&'static str; N] {
    assert!(
        a.len() + b.len() == N,
        "N must be the two lists' lengths together"
    );
    let mut out = [""; N];
    let mut i = 0;
    while i < a.len() {
        out[i] = a[i];
        i += 1;
    }
    let mut j = 0;
    while j < b.len() {
        out[a.len() + j] = b[j];
        j += 1;
    }
    out
}

/// [`BINARIES`], and the stage binary of every row of the table of methods that it does
/// not name: a method added to the table is built and kept current with the rest.
pub fn binaries() -> Vec<&'static str> {
    let mut all = BINARIES.to_vec();
    for b in methods::binaries(methods::METHODS) {
        if !all.contains(&b) {
            all.push(b);
        }
    }
    all
}

/// The file whose time says when render last had cargo bring the binaries up to date
/// (cargo leaves a binary alone when what changed does not affect it, as an unrelated
/// change to Cargo.lock: without it, every run would ask cargo again).
const STAMP: &str = ".render-asked-cargo";

fn mtime(p: &Path) -> Option<SystemTime> {
    std::fs::metadata(p).and_then(|m| m.modified()).ok()
}

/// The newest time among the files a binary can be built from: the workspace's
/// manifest and lock and, in each of its crates (proto, scan, stagecli, methods and bins/*:
/// docs/DESIGN.md's layout), the manifest, a build script, and what is under src/ or
/// fonts/ (chart's font); not tests, benches, scripts, documents or examples.
pub fn newest_source(root: &Path) -> Option<SystemTime> {
    fn walk(dir: &Path, newest: &mut Option<SystemTime>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries.flatten() {
            let Ok(kind) = e.file_type() else { continue };
            if kind.is_dir() {
                walk(&e.path(), newest);
            } else if let Some(t) = e.metadata().ok().and_then(|m| m.modified().ok()) {
                *newest = (*newest).max(Some(t));
            }
        }
    }
    let mut crates: Vec<PathBuf> = ["proto", "scan", "stagecli", "methods"]
        .iter()
        .map(|c| root.join(c))
        .collect();
    if let Ok(bins) = std::fs::read_dir(root.join("bins")) {
        crates.extend(bins.flatten().map(|e| e.path()));
    }
    let mut newest = [root.join("Cargo.toml"), root.join("Cargo.lock")]
        .iter()
        .filter_map(|p| mtime(p))
        .max();
    for c in &crates {
        for f in ["Cargo.toml", "build.rs"] {
            newest = newest.max(mtime(&c.join(f)));
        }
        walk(&c.join("src"), &mut newest);
        walk(&c.join("fonts"), &mut newest);
    }
    newest
}

/// What a look at the binaries in `bin` found.
#[derive(Debug, PartialEq, Eq)]
pub enum Look {
    Fresh,
    /// These are missing (all others may be stale too).
    Missing(Vec<&'static str>),
    /// A source is newer than a binary.
    Stale,
}

/// Looks at the binaries in `bin` against the sources in `root`.
pub fn look(root: &Path, bin: &Path) -> Look {
    let mut oldest: Option<SystemTime> = None;
    let mut missing = Vec::new();
    for b in binaries() {
        match mtime(&bin.join(b)) {
            Some(t) => oldest = Some(oldest.map_or(t, |o| o.min(t))),
            None => missing.push(b),
        }
    }
    if !missing.is_empty() {
        return Look::Missing(missing);
    }
    // A source newer than both the oldest binary and the stamp: newer than the newer.
    let since = oldest.max(mtime(&bin.join(STAMP)));
    if newest_source(root) > since {
        Look::Stale
    } else {
        Look::Fresh
    }
}

/// Brings the binaries in `bin` up to date with the sources in `root`, with cargo, when
/// they are not; says what it does on stderr as `me: …`. Returns whether the render
/// binary itself was rebuilt (its time changed), so that the caller starts the new one.
/// Without cargo, binaries already built are run as they are, with a warning.
pub fn ensure(root: &Path, bin: &Path, me: &str) -> stagecli::Result<bool> {
    use std::io::IsTerminal;
    let look = look(root, bin);
    if look == Look::Fresh {
        return Ok(false);
    }
    let before = mtime(&bin.join("render"));
    let mut cmd = std::process::Command::new("cargo");
    cmd.current_dir(root)
        .args(["build", "--release", "--quiet"])
        .args(binaries().iter().flat_map(|b| ["-p", *b]))
        .stdout(std::io::stderr());
    match &look {
        Look::Missing(m) if m.len() == binaries().len() => {
            eprintln!("{me}: building the polypipe binaries (first run only)…")
        }
        Look::Missing(m) => eprintln!("{me}: building {}…", m.join(" ")),
        _ if std::io::stderr().is_terminal() => {
            eprintln!("{me}: rebuilding the polypipe binaries (their sources changed)…")
        }
        _ => {}
    }
    match cmd.status() {
        Ok(s) if s.success() => {}
        Ok(_) => return Err(stagecli::Error::io("cargo build failed")),
        Err(_) => {
            if let Look::Missing(m) = look {
                return Err(stagecli::Error::io(format!(
                    "cannot build {} into {}: cargo is not on PATH (Rust: https://rustup.rs)",
                    m.join(" "),
                    bin.display()
                )));
            }
            eprintln!(
                "{me}: warning: the binaries are older than their sources, and no cargo on PATH to rebuild them; running them as they are"
            );
            return Ok(false);
        }
    }
    let _ = std::fs::File::create(bin.join(STAMP));
    Ok(mtime(&bin.join("render")) != before)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn touch(p: &Path, t: SystemTime) {
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        let f = std::fs::File::create(p).unwrap();
        f.set_modified(t).unwrap();
    }

    #[test]
    fn every_methods_binary_is_built_once() {
        let all = binaries();
        for b in BINARIES.iter().chain(&methods::binaries(methods::METHODS)) {
            assert_eq!(all.iter().filter(|a| a == &b).count(), 1, "{b}");
        }
        // Nothing else: the list, then the methods' stages it does not name.
        assert_eq!(&all[..BINARIES.len()], BINARIES);
        assert!(all[BINARIES.len()..]
            .iter()
            .all(|b| methods::binaries(methods::METHODS).contains(b)));
    }

    #[test]
    fn a_source_newer_than_the_oldest_binary_and_the_stamp_is_stale() {
        let d = tempfile::tempdir().unwrap();
        let (root, bin) = (d.path().join("r"), d.path().join("b"));
        let t = |s: u64| SystemTime::UNIX_EPOCH + std::time::Duration::from_secs(1_000_000 + s);
        touch(&root.join("Cargo.toml"), t(0));
        touch(&root.join("bins/zbuf/src/deep/mod.rs"), t(5));
        touch(&root.join("bins/zbuf/tests/t.rs"), t(50)); // not a source
        touch(&root.join("README.md"), t(50));
        assert_eq!(newest_source(&root), Some(t(5)));
        assert_eq!(look(&root, &bin), Look::Missing(binaries()));
        for b in binaries() {
            touch(&bin.join(b), t(10));
        }
        assert_eq!(look(&root, &bin), Look::Fresh);
        touch(&bin.join("zbuf"), t(1));
        assert_eq!(look(&root, &bin), Look::Stale);
        touch(&bin.join(STAMP), t(6));
        assert_eq!(look(&root, &bin), Look::Fresh);
        touch(&root.join("stagecli/src/lib.rs"), t(7));
        assert_eq!(look(&root, &bin), Look::Stale);
        std::fs::remove_file(bin.join("farm")).unwrap();
        assert_eq!(look(&root, &bin), Look::Missing(vec!["farm"]));
    }
}
