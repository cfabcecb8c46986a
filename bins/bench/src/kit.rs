//! What the benchmarks share besides the clock: the built binaries (made current first,
//! as `scripts/render.sh` makes them), a scratch folder, the scenes, the methods they
//! run (the table of methods, as render runs them), and the small readers of other
//! stages' output that a table needs.

use stagecli::{Error, Result};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// The six clipping planes as a pipe line of `clipplane`s (`CLIP` is replaced by the
/// binary).
const PLANES: [&str; 6] = ["left", "right", "top", "bottom", "hither", "yon"];

/// Quotes `s` for bash when it holds anything but plain path characters.
pub fn q(s: &str) -> String {
    if !s.is_empty()
        && s.bytes()
            .all(|b| b.is_ascii_alphanumeric() || b"/._-+,=:@%".contains(&b))
    {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', r"'\''"))
    }
}

/// The binaries, the repository and a scratch folder removed at the end.
pub struct Kit {
    /// The folder of the built binaries (the one this program runs from).
    pub bin: PathBuf,
    /// The repository (examples/, bench/).
    pub root: PathBuf,
    work: tempfile::TempDir,
}

impl Kit {
    /// The binaries beside this one, made current with their sources first (`render
    /// --build-only`, which has cargo build only when a source is newer than them), so
    /// that no timed run times a build.
    /// `POLYPIPE_BIN` names another folder of binaries, measured as they are.
    pub fn new() -> Result<Kit> {
        let bin = match std::env::var_os("POLYPIPE_BIN").filter(|d| !d.is_empty()) {
            Some(d) => PathBuf::from(d),
            None => stagecli::place::bin_dir()?,
        };
        let root = stagecli::place::root_dir(None)?;
        let status = Command::new(bin.join("render"))
            .arg("--build-only")
            .env("POLYPIPE_SOURCES", &root)
            .stdout(Stdio::null())
            .status()
            .map_err(|e| Error::io(format!("cannot run {}/render: {e}", bin.display())))?;
        if !status.success() {
            return Err(Error::io("the binaries could not be made current"));
        }
        let work = tempfile::Builder::new()
            .prefix("bench.")
            .tempdir()
            .map_err(|e| Error::io(format!("a scratch folder: {e}")))?;
        Ok(Kit { bin, root, work })
    }

    /// The binary `name`, quoted for a bash line.
    pub fn b(&self, name: &str) -> String {
        q(&self.bin.join(name).display().to_string())
    }

    /// The file `name` of the scratch folder, quoted for a bash line.
    pub fn w(&self, name: &str) -> String {
        q(&self.work(name).display().to_string())
    }

    /// The path of the file `name` of the scratch folder.
    pub fn work(&self, name: &str) -> PathBuf {
        self.work.path().join(name)
    }

    /// The repository's file `rel`, quoted for a bash line.
    pub fn r(&self, rel: &str) -> String {
        q(&self.root.join(rel).display().to_string())
    }

    /// The leaf command `words` (`scanconv --resolve`) as a bash line, its binary in
    /// the binaries' folder.
    pub fn leaf(&self, words: &str) -> String {
        match words.split_once(' ') {
            Some((b, rest)) => format!("{} {rest}", self.b(b)),
            None => self.b(words),
        }
    }

    /// `scene ARGS`, taken to screen space at `size` (viewxf | clipbatch | persp), in
    /// the scratch file `name`, quoted.
    pub fn screen(&self, name: &str, args: &str, size: &str) -> Result<String> {
        self.make(
            name,
            &format!(
                "{} {args} | {} --size {size} | {} | {} --size {size}",
                self.b("scene"),
                self.b("viewxf"),
                self.b("clipbatch"),
                self.b("persp")
            ),
        )?;
        Ok(self.w(name))
    }

    /// The six clippers as a pipe line.
    pub fn clip(&self) -> String {
        PLANES
            .iter()
            .map(|p| format!("{} {p}", self.b("clipplane")))
            .collect::<Vec<_>>()
            .join(" | ")
    }

    /// `render ARGS` as a bash line (the binary itself: made current once by [`Kit::new`]).
    pub fn render(&self, args: &str) -> String {
        format!("{} {args}", self.b("render"))
    }

    /// Runs the bash line `line` (in the repository), its stdout to the scratch file
    /// `out`; its path.
    pub fn make(&self, out: &str, line: &str) -> Result<PathBuf> {
        let path = self.work(out);
        sh(&format!("{line} > {}", self.w(out)), &self.root)?;
        Ok(path)
    }

    /// The stdout of the bash line `line`, run in the repository, as text.
    pub fn out(&self, line: &str) -> Result<String> {
        Ok(String::from_utf8_lossy(&sh(line, &self.root)?).into_owned())
    }

    /// The stdout of the bash line `line`, run in the repository, as bytes (frames and
    /// streams compared byte for byte).
    pub fn bytes(&self, line: &str) -> Result<Vec<u8>> {
        sh(line, &self.root)
    }

    /// `scene ARGS` written to the scratch file `name`, quoted.
    pub fn scene(&self, name: &str, args: &str) -> Result<String> {
        self.make(name, &format!("{} {args}", self.b("scene")))?;
        Ok(self.w(name))
    }

    /// The fill-heavy scene as text: `scene environment`, seed 2, depth complexity 10,
    /// `polygons` quads at `size`, in the scratch file `name`.
    pub fn fill_scene(&self, name: &str, polygons: usize, size: &str) -> Result<String> {
        self.scene(
            name,
            &format!(
                "environment --text --seed 2 --polygons {polygons} --depth-complexity 10 \
                 --size {size}"
            ),
        )
    }

    /// The pixels of frames `b` unlike `a`'s, over all frames (`zspec compare --metrics
    /// --csv`'s `overall` row), and the pixels in all.
    pub fn differing(&self, a: &str, b: &str) -> Result<(u64, u64)> {
        let csv = self.out(&format!(
            "{} compare --metrics --csv {a} {b}",
            self.b("zspec")
        ))?;
        overall(&csv)
            .ok_or_else(|| Error::data(format!("zspec compare {a} {b} gave no overall row")))
    }
}

/// The `pixels` and `differing` of zspec compare's `overall,PIXELS,DIFFERING,…` row,
/// as (differing, pixels).
pub fn overall(csv: &str) -> Option<(u64, u64)> {
    let row = csv.lines().find(|l| l.starts_with("overall,"))?;
    let mut f = row.split(',').skip(1);
    let pixels = f.next()?.parse().ok()?;
    let differing = f.next()?.parse().ok()?;
    Some((differing, pixels))
}

/// Runs the bash line `line` in `dir`; its stdout, or an error with its status and the
/// last line of its stderr.
pub fn sh(line: &str, dir: &Path) -> Result<Vec<u8>> {
    let out = Command::new("bash")
        .args(["-o", "pipefail", "-c", line])
        .current_dir(dir)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| Error::io(format!("cannot run bash: {e}")))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        let last = err
            .lines()
            .last()
            .map(|l| format!(": {l}"))
            .unwrap_or_default();
        let how = match out.status.code() {
            Some(c) => format!("status {c}"),
            None => "a signal".to_string(),
        };
        return Err(Error::data(format!("`{line}` failed with {how}{last}")));
    }
    Ok(out.stdout)
}

/// The number before `words` in a stage's --stats line (`50 polygons in`), or an error
/// naming the line. A `#` in `words` stands for any number (`failed, # crossings held`).
pub fn stat_count(line: &str, words: &str) -> Result<u64> {
    let b = line.as_bytes();
    for start in 0..b.len() {
        if !b[start].is_ascii_digit() || (start > 0 && b[start - 1].is_ascii_digit()) {
            continue;
        }
        let end = start + b[start..].iter().take_while(|c| c.is_ascii_digit()).count();
        if line[end..]
            .strip_prefix(' ')
            .is_some_and(|rest| follows(rest, words))
        {
            if let Ok(n) = line[start..end].parse() {
                return Ok(n);
            }
        }
    }
    Err(Error::data(format!("no count of '{words}' in: {line}")))
}

/// Whether `text` starts with `pattern`, a `#` of which matches one or more digits.
fn follows(text: &str, pattern: &str) -> bool {
    let (t, p) = (text.as_bytes(), pattern.as_bytes());
    let mut i = 0;
    for &c in p {
        if c == b'#' {
            let n = t[i.min(t.len())..]
                .iter()
                .take_while(|c| c.is_ascii_digit())
                .count();
            if n == 0 {
                return false;
            }
            i += n;
        } else if t.get(i) == Some(&c) {
            i += 1;
        } else {
            return false;
        }
    }
    true
}

/// Which of render's methods a benchmark runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// The hidden-surface methods (`--hse NAME`).
    Hse,
    /// The anti-aliasing leaves (`--aa NAME`), after `point`: none, zbuf's leaf.
    Aa,
    /// The hidden-line drawing (the hiddenline stage's continuous method).
    Lines,
}

/// The methods of `kind` from the table of methods, each its name and the leaf command
/// render runs for it (`scanconv --resolve`).
pub fn methods_list(kind: Kind) -> Vec<(String, String)> {
    let table = methods::METHODS;
    let leaf = |m: &methods::Method| m.stage.join(" ");
    let mut out = Vec::new();
    if kind == Kind::Aa {
        if let Some(z) = methods::by_hse(table, "zbuf") {
            out.push(("point".to_string(), leaf(z)));
        }
    }
    for m in table {
        use methods::Selector;
        let take = match (kind, m.selector) {
            (Kind::Hse, Selector::Hse(_)) | (Kind::Aa, Selector::Aa(_)) => true,
            (Kind::Lines, Selector::HiddenLine(n)) => n == "continuous",
            _ => false,
        };
        if take {
            out.push((m.name.to_string(), leaf(m)));
        }
    }
    out
}

/// The leaf command of method `name` of `kind`.
pub fn method_leaf(kind: Kind, name: &str) -> Result<String> {
    methods_list(kind)
        .into_iter()
        .find(|(n, _)| n == name)
        .map(|(_, leaf)| leaf)
        .ok_or_else(|| Error::usage(format!("{kind:?} has no method '{name}'")))
}

/// The machine: `N cores (MODEL)`.
pub fn machine() -> String {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let model = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(": ").map(|(_, m)| m.to_string()))
        })
        .unwrap_or_else(|| "unknown".to_string());
    format!("{cores} cores ({model})")
}

/// The load average now: `load average A B C, runnable now R`.
pub fn load() -> String {
    let text = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    let w: Vec<&str> = text.split_whitespace().collect();
    match w.as_slice() {
        [a, b, c, r, ..] => format!("load average {a} {b} {c}, runnable now {r}"),
        _ => "load average unknown".to_string(),
    }
}

/// The number of cores.
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// "Measured by `bench ARGS` on N cores (MODEL), LOAD": the line a table's figures go
/// with (the commit and date are git's to remember).
pub fn stamp(args: &str) -> String {
    format!("Measured by `bench {args}` on {}, {}.", machine(), load())
}

/// A markdown table's header and rule.
pub fn header(cells: &[&str]) {
    println!("{}", line(cells));
    println!("|{}", "---|".repeat(cells.len()));
}

/// A markdown table's row.
pub fn row(cells: &[String]) {
    println!("{}", line(cells));
}

/// `| A | B |`, an empty cell `| |`.
fn line<S: AsRef<str>>(cells: &[S]) -> String {
    let mut l = String::from("|");
    for c in cells {
        match c.as_ref() {
            "" => l.push_str(" |"),
            c => l.push_str(&format!(" {c} |")),
        }
    }
    l
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stat_count_reads_a_counter_by_its_words() {
        let line = "warnock: 50 polygons in, 1 frames, 500 runs out, 0 single pixels, \
                    7 polygons looked at";
        assert_eq!(stat_count(line, "polygons in").unwrap(), 50);
        assert_eq!(stat_count(line, "polygons looked at").unwrap(), 7);
        assert_eq!(stat_count(line, "single pixels").unwrap(), 0);
        assert_eq!(stat_count(line, "runs out, # single").unwrap(), 500);
        let fronts = "scanline: 9 fronts held / 2 failed, 30 crossings held / 4 failed; 5 midpoint";
        assert_eq!(stat_count(fronts, "failed, # crossings held").unwrap(), 2);
        assert_eq!(stat_count(fronts, "failed; # midpoint").unwrap(), 4);
        assert_eq!(
            stat_count(line, "crossings").unwrap_err().to_string(),
            format!("no count of 'crossings' in: {line}")
        );
    }

    #[test]
    fn overall_reads_zspec_s_row() {
        let csv = "frame,pixels,differing,x\n0,6,1,0\n1,6,2,0\noverall,12,3,0.1\n";
        assert_eq!(overall(csv), Some((3, 12)));
        assert_eq!(overall("frame,pixels\n"), None);
    }

    #[test]
    fn methods_are_the_table_s() {
        let hse: Vec<String> = methods_list(Kind::Hse).into_iter().map(|m| m.0).collect();
        assert_eq!(hse, methods::hse_names(methods::METHODS));
        let aa = methods_list(Kind::Aa);
        assert_eq!(aa[0].0, "point");
        assert_eq!(
            method_leaf(Kind::Hse, "zbuf").unwrap(),
            "scanconv --resolve"
        );
        assert!(method_leaf(Kind::Hse, "abuf").is_err());
        assert_eq!(methods_list(Kind::Lines).len(), 1);
    }

    #[test]
    fn a_table_line_has_its_cells_between_bars() {
        assert_eq!(line(&["a", "", "b c"]), "| a | | b c |");
    }

    #[test]
    fn quoting_leaves_paths_alone() {
        assert_eq!(q("/tmp/a-b.txt"), "/tmp/a-b.txt");
        assert_eq!(q("a b"), "'a b'");
        assert_eq!(q("it's"), r"'it'\''s'");
    }
}
