//! Running a command as a user would, and measuring the whole process tree it makes:
//! wall time, CPU time (user + system) and the peak resident set, from `wait4`'s
//! resource usage of the child, which counts every descendant it waited for
//! (`render.sh` waits for all its stages).

use anyhow::{bail, Context, Result};
use std::process::Command;
use std::time::Instant;

/// What one run cost.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Usage {
    /// Seconds from start to exit.
    pub wall_s: f64,
    /// User plus system CPU seconds of the process and every descendant it waited for.
    pub cpu_s: f64,
    /// The largest resident set of any process of the tree, KiB (`ru_maxrss`).
    pub max_rss_kib: u64,
}

fn seconds(t: libc::timeval) -> f64 {
    t.tv_sec as f64 + t.tv_usec as f64 * 1e-6
}

/// Runs `cmd` to its end and measures it; a non-zero exit is an error carrying the
/// command's stderr (which must not be inherited, or captured through a pipe, by the
/// caller: give the command its own files).
pub fn run(cmd: &mut Command) -> Result<Usage> {
    let start = Instant::now();
    let child = cmd.spawn().with_context(|| format!("cannot run {cmd:?}"))?;
    let pid = child.id() as libc::pid_t;
    // std's Child is not waited on: wait4 reaps it and gives its usage.
    drop(child);
    let mut status: libc::c_int = 0;
    // SAFETY: an all-zero rusage is a valid value of the plain C struct.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    loop {
        // SAFETY: pid is our own child, status and usage point at live locals.
        let r = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
        if r == pid {
            break;
        }
        let e = std::io::Error::last_os_error();
        if e.kind() != std::io::ErrorKind::Interrupted {
            return Err(e).context("wait4");
        }
    }
    let wall_s = start.elapsed().as_secs_f64();
    if !libc::WIFEXITED(status) || libc::WEXITSTATUS(status) != 0 {
        let how = if libc::WIFEXITED(status) {
            format!("status {}", libc::WEXITSTATUS(status))
        } else {
            format!("signal {}", libc::WTERMSIG(status))
        };
        bail!("{cmd:?} failed ({how})");
    }
    Ok(Usage {
        wall_s,
        cpu_s: seconds(usage.ru_utime) + seconds(usage.ru_stime),
        max_rss_kib: usage.ru_maxrss.max(0) as u64,
    })
}

/// The median of some runs' figures, each figure its own median (an odd count picks a
/// run's value; an even one averages the middle two).
pub fn median(runs: &[Usage]) -> Usage {
    fn med(mut v: Vec<f64>) -> f64 {
        if v.is_empty() {
            return 0.0;
        }
        v.sort_by(f64::total_cmp);
        let n = v.len();
        if n % 2 == 1 {
            v[n / 2]
        } else {
            (v[n / 2 - 1] + v[n / 2]) / 2.0
        }
    }
    Usage {
        wall_s: med(runs.iter().map(|u| u.wall_s).collect()),
        cpu_s: med(runs.iter().map(|u| u.cpu_s).collect()),
        max_rss_kib: med(runs.iter().map(|u| u.max_rss_kib as f64).collect()) as u64,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_busy_child_and_its_grandchild_are_counted() {
        // The grandchild spins ~0.2 s of CPU; its parent waits for it.
        let u = run(Command::new("bash").args([
            "-c",
            "bash -c 'e=$((SECONDS+1)); i=0; while ((i < 200000)); do ((i++)); done' ; true",
        ]))
        .unwrap();
        assert!(u.cpu_s > 0.05, "{u:?}");
        assert!(u.wall_s >= u.cpu_s * 0.5, "{u:?}");
        assert!(u.max_rss_kib > 100, "{u:?}");
    }

    #[test]
    fn a_failing_command_is_an_error() {
        let e = run(Command::new("bash").args(["-c", "exit 3"])).unwrap_err();
        assert!(e.to_string().contains("status 3"), "{e}");
    }

    #[test]
    fn median_of_three() {
        let u = |w| Usage {
            wall_s: w,
            cpu_s: w * 2.0,
            max_rss_kib: (w * 10.0) as u64,
        };
        let m = median(&[u(3.0), u(1.0), u(2.0)]);
        assert_eq!(m, u(2.0));
    }
}
