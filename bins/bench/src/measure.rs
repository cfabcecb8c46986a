//! One run of a command measured, and the statistics the tables print over many.
//!
//! A command is a line of bash (`bash -o pipefail -c LINE`), so that a pipe line is
//! measured as a whole, as a user's shell runs it. Its wall and CPU seconds (user +
//! system of it and every descendant it waited for) and its peak resident memory (the
//! largest single process's, `ru_maxrss`, as GNU time's `%M`) come from `wait4` through
//! the cost model's [`costmodel::measure::run`]. A command that fails is never timed as
//! a fast success: [`run`] is then an error naming the command, its status and the last
//! line it wrote on stderr.

use stagecli::{Error, Result};
use std::io::{BufRead, BufReader, Seek};
use std::process::{Command, Stdio};

pub use costmodel::measure::Usage;

/// Which figure of a run a table shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Figure {
    /// Wall seconds.
    Wall,
    /// CPU seconds, user + system.
    Cpu,
    /// Peak resident memory, KiB.
    Kib,
}

impl Figure {
    /// The figure of `u`.
    pub fn of(self, u: &Usage) -> f64 {
        match self {
            Figure::Wall => u.wall_s,
            Figure::Cpu => u.cpu_s,
            Figure::Kib => u.max_rss_kib as f64,
        }
    }
}

/// Runs the bash line `line` once, its stdout to /dev/null, and measures it.
pub fn run(line: &str) -> Result<Usage> {
    run_env(line, &[])
}

/// [`run`] with variables added to the command's environment.
pub fn run_env(line: &str, env: &[(&str, &str)]) -> Result<Usage> {
    let mut err = tempfile::tempfile().map_err(|e| Error::io(format!("a temporary file: {e}")))?;
    let mut cmd = Command::new("bash");
    cmd.args(["-o", "pipefail", "-c", line])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(
            err.try_clone()
                .map_err(|e| Error::io(format!("a temporary file: {e}")))?,
        );
    for (k, v) in env {
        cmd.env(k, v);
    }
    costmodel::measure::run(&mut cmd).map_err(|e| {
        let last = err.rewind().ok().and_then(|()| {
            BufReader::new(&mut err)
                .lines()
                .map_while(|l| l.ok())
                .last()
        });
        failed(line, &e.to_string(), last.as_deref())
    })
}

/// The one message for a measured command that failed: `` `LINE` failed with status N:
/// LAST`` (`how` is the cost model's error, which ends "failed (status N)").
fn failed(line: &str, how: &str, last: Option<&str>) -> Error {
    let how = how
        .rsplit_once(" failed (")
        .map_or(how, |(_, h)| h.trim_end_matches(')'));
    let last = last.filter(|l| !l.is_empty()).map(|l| format!(": {l}"));
    Error::data(format!(
        "`{line}` failed with {how}{}",
        last.unwrap_or_default()
    ))
}

/// The least of `reps` runs' `figure` (the run the machine disturbed least).
pub fn best_of(reps: usize, line: &str, figure: Figure) -> Result<f64> {
    let mut all = Vec::with_capacity(reps);
    for _ in 0..reps.max(1) {
        all.push(figure.of(&run(line)?));
    }
    Ok(least(&all))
}

/// Every command of `lines` run `reps` times, interleaved: round `r` runs them all once,
/// starting at the `r`-th (modulo their number), so that a change in the machine's load
/// falls on every command alike and none always runs first. The runs of each command, in
/// `lines`' order.
pub fn interleaved(reps: usize, lines: &[String]) -> Result<Vec<Vec<Usage>>> {
    interleaved_with(reps, lines.len(), |i| run(&lines[i]))
}

/// [`interleaved`] over `n` commands that `one(i)` runs and measures.
pub fn interleaved_with(
    reps: usize,
    n: usize,
    mut one: impl FnMut(usize) -> Result<Usage>,
) -> Result<Vec<Vec<Usage>>> {
    let mut runs = vec![Vec::with_capacity(reps); n];
    for r in 0..reps {
        for i in 0..n {
            let k = (i + r) % n;
            runs[k].push(one(k)?);
        }
    }
    Ok(runs)
}

/// The median (an odd count picks a value, an even one averages the middle two; none
/// gives 0).
pub fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    match n {
        0 => 0.0,
        _ if n % 2 == 1 => v[n / 2],
        _ => (v[n / 2 - 1] + v[n / 2]) / 2.0,
    }
}

/// The median of `runs`' `figure`.
pub fn median_of(runs: &[Usage], figure: Figure) -> f64 {
    median(&runs.iter().map(|u| figure.of(u)).collect::<Vec<_>>())
}

/// The spread of some figures about their median: (largest − least) / median, 0 for
/// fewer than two or a median of 0.
pub fn spread(v: &[f64]) -> f64 {
    let m = median(v);
    if v.len() < 2 || m <= 0.0 {
        return 0.0;
    }
    let hi = v.iter().copied().fold(f64::MIN, f64::max);
    (hi - least(v)) / m
}

/// The least (0 for none).
pub fn least(v: &[f64]) -> f64 {
    v.iter().copied().reduce(f64::min).unwrap_or(0.0)
}

/// The median of the rounds' own ratios `a[r] / b[r]` (runs of one round ran moments
/// apart, so a change in load between rounds falls on both).
pub fn median_ratio(a: &[Usage], b: &[Usage], figure: Figure) -> f64 {
    let r: Vec<f64> = a
        .iter()
        .zip(b)
        .filter(|(_, b)| figure.of(b) > 0.0)
        .map(|(a, b)| figure.of(a) / figure.of(b))
        .collect();
    median(&r)
}

/// `a / b` to `places` places, `-` unless both are above 0.
pub fn quotient(a: f64, b: f64, places: usize) -> String {
    if a > 0.0 && b > 0.0 {
        format!("{:.*}", places, a / b)
    } else {
        "-".to_string()
    }
}

/// `a / b` to two places (see [`quotient`]).
pub fn ratio(a: f64, b: f64) -> String {
    quotient(a, b, 2)
}

/// Seconds to the millisecond.
pub fn ms(s: f64) -> String {
    format!("{s:.3}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_picks_the_middle_or_averages_the_middle_two() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
        assert_eq!(median(&[]), 0.0);
        assert_eq!(median(&[7.5]), 7.5);
    }

    #[test]
    fn spread_is_the_range_over_the_median() {
        assert_eq!(spread(&[1.0, 2.0, 3.0]), 1.0);
        assert_eq!(spread(&[2.0]), 0.0);
        assert_eq!(spread(&[0.0, 0.0]), 0.0);
        assert_eq!(least(&[3.0, 0.5, 2.0]), 0.5);
        assert_eq!(least(&[]), 0.0);
    }

    #[test]
    fn quotients_are_a_dash_unless_both_are_positive() {
        assert_eq!(ratio(1.0, 3.0), "0.33");
        assert_eq!(quotient(2.0, 3.0, 3), "0.667");
        assert_eq!(ratio(0.0, 3.0), "-");
        assert_eq!(ratio(1.0, 0.0), "-");
        assert_eq!(ms(0.12345), "0.123");
    }

    #[test]
    fn rounds_rotate_which_command_runs_first() {
        let mut order = Vec::new();
        let runs = interleaved_with(3, 3, |i| {
            order.push(i);
            Ok(Usage {
                wall_s: i as f64,
                ..Usage::default()
            })
        })
        .unwrap();
        assert_eq!(order, [0, 1, 2, 1, 2, 0, 2, 0, 1]);
        assert_eq!(runs.len(), 3);
        assert!(runs
            .iter()
            .enumerate()
            .all(|(i, r)| r.len() == 3 && r.iter().all(|u| u.wall_s == i as f64)));
    }

    #[test]
    fn the_median_ratio_is_of_the_rounds_own_ratios() {
        let u = |w| Usage {
            wall_s: w,
            ..Usage::default()
        };
        let a = [u(2.0), u(3.0), u(10.0)];
        let b = [u(1.0), u(3.0), u(2.0)];
        assert_eq!(median_ratio(&a, &b, Figure::Wall), 2.0);
    }

    #[test]
    fn a_run_gives_its_wall_cpu_and_memory() {
        let u = run("sleep 0.2").unwrap();
        assert!((0.2..10.0).contains(&u.wall_s), "{u:?}");
        let u = run("for ((i = 0; i < 200000; i++)); do :; done").unwrap();
        assert!(u.cpu_s > 0.01, "{u:?}");
        let u = run("exec python3 -c 'b = bytearray(64 << 20); b[-1] = 1'").unwrap();
        assert!(u.max_rss_kib >= 65536, "{u:?}");
        let best = best_of(2, "sleep 0.05", Figure::Wall).unwrap();
        assert!((0.05..10.0).contains(&best), "{best}");
    }

    #[test]
    fn a_failing_command_is_an_error_with_its_status_and_last_words() {
        let e = run("echo starting >&2; echo no such scene >&2; exit 3").unwrap_err();
        assert_eq!(
            e.to_string(),
            "`echo starting >&2; echo no such scene >&2; exit 3` failed with status 3: \
             no such scene"
        );
        assert_eq!(e.kind(), stagecli::Kind::Data);
        let e = best_of(3, "false", Figure::Cpu).unwrap_err();
        assert_eq!(e.to_string(), "`false` failed with status 1");
        // A pipe line fails when any of its commands does.
        let e = run("false | cat").unwrap_err();
        assert_eq!(e.to_string(), "`false | cat` failed with status 1");
    }
}
