//! Running a command as a user would, and measuring the whole process tree it makes:
//! wall time and CPU time (user + system), from `wait4`'s resource usage of the child,
//! which counts every descendant it waited for (`render.sh` waits for all its stages);
//! and, with [`run_watched`], the peak memory of the whole tree: the sum of every
//! process's own peak resident set (`VmHWM`), the stages running side by side. (`wait4`'s
//! `ru_maxrss` is the largest single process's, bash's 4 MB on every small render; cgroup
//! v2's `memory.peak` would be exact but needs a cgroup of one's own, which this machine,
//! on cgroup v1, does not give.)

use crate::error::{Context, Error, Result};
use std::process::Command;
use std::time::Instant;

/// What one run cost.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Usage {
    /// Seconds from start to exit.
    pub wall_s: f64,
    /// User plus system CPU seconds of the process and every descendant it waited for.
    pub cpu_s: f64,
    /// Peak memory, KiB: with [`run_watched`], the sum of the tree's processes' peak
    /// resident sets (at least the largest one's); with [`run`], the largest single
    /// process's (`ru_maxrss`).
    pub max_rss_kib: u64,
}

fn seconds(t: libc::timeval) -> f64 {
    t.tv_sec as f64 + t.tv_usec as f64 * 1e-6
}

/// Runs `cmd` to its end and measures it; a non-zero exit is an error carrying the
/// command's stderr (which must not be inherited, or captured through a pipe, by the
/// caller: give the command its own files).
pub fn run(cmd: &mut Command) -> Result<Usage> {
    run_with(cmd, false)
}

/// [`run`], and the peak memory of the whole process tree: every process's `VmHWM`
/// (its own peak resident set), sampled from /proc every 5 ms while the tree runs and
/// summed. A process that lives less than 5 ms may be missed; the stages of a render
/// live as long as it.
pub fn run_watched(cmd: &mut Command) -> Result<Usage> {
    run_with(cmd, true)
}

fn run_with(cmd: &mut Command, watched: bool) -> Result<Usage> {
    let start = Instant::now();
    let child = cmd.spawn().with_context(|| format!("cannot run {cmd:?}"))?;
    let pid = child.id() as libc::pid_t;
    let watch = watched.then(|| TreeWatch::start(pid));
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
    let tree_kib = watch.map(TreeWatch::finish);
    if !libc::WIFEXITED(status) || libc::WEXITSTATUS(status) != 0 {
        let how = if libc::WIFEXITED(status) {
            format!("status {}", libc::WEXITSTATUS(status))
        } else {
            format!("signal {}", libc::WTERMSIG(status))
        };
        return Err(Error::Data(format!("{cmd:?} failed ({how})")));
    }
    // The largest single process's peak (`ru_maxrss`, over the child and every descendant
    // it waited for) is a floor under the tree's sum: a render of a few milliseconds can
    // end its stages between two of the watch's looks (three processes and 12 ms for
    // the two polygons at depth 0, where the watch once saw only 408 KiB).
    let largest_kib = usage.ru_maxrss.max(0) as u64;
    Ok(Usage {
        wall_s,
        cpu_s: seconds(usage.ru_utime) + seconds(usage.ru_stime),
        max_rss_kib: tree_kib.map_or(largest_kib, |sum| sum.max(largest_kib)),
    })
}

/// A thread that follows a process tree through /proc (each task's `children`) and keeps
/// each process's largest `VmHWM`.
struct TreeWatch {
    stop: std::sync::Arc<std::sync::atomic::AtomicBool>,
    thread: std::thread::JoinHandle<u64>,
}

impl TreeWatch {
    fn start(root: libc::pid_t) -> TreeWatch {
        use std::sync::atomic::Ordering::Relaxed;
        let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let flag = std::sync::Arc::clone(&stop);
        let thread = std::thread::spawn(move || {
            let mut peak: std::collections::HashMap<i32, u64> = Default::default();
            loop {
                let last = flag.load(Relaxed);
                for pid in tree(root) {
                    if let Some(kib) = hwm_kib(pid) {
                        let p = peak.entry(pid).or_insert(0);
                        *p = (*p).max(kib);
                    }
                }
                if last {
                    break;
                }
                std::thread::sleep(std::time::Duration::from_millis(5));
            }
            peak.values().sum()
        });
        TreeWatch { stop, thread }
    }

    fn finish(self) -> u64 {
        self.stop.store(true, std::sync::atomic::Ordering::Relaxed);
        self.thread.join().unwrap_or(0)
    }
}

/// `root` and its descendants, from /proc/PID/task/TID/children.
fn tree(root: libc::pid_t) -> Vec<i32> {
    let mut all = vec![root];
    let mut i = 0;
    while i < all.len() {
        let pid = all[i];
        i += 1;
        let Ok(tasks) = std::fs::read_dir(format!("/proc/{pid}/task")) else {
            continue;
        };
        for task in tasks.flatten() {
            let text = std::fs::read_to_string(task.path().join("children")).unwrap_or_default();
            all.extend(
                text.split_whitespace()
                    .filter_map(|w| w.parse::<i32>().ok()),
            );
        }
    }
    all
}

/// A process's peak resident set, KiB (`VmHWM` of /proc/PID/status).
fn hwm_kib(pid: i32) -> Option<u64> {
    let text = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = text.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
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
    fn the_tree_s_memory_is_the_sum_of_its_processes_peaks() {
        // Two children side by side, each holding 20 MB of text for a moment: the tree's
        // peak is theirs together, where ru_maxrss gives one of them.
        let hold = "x=$(head -c 20000000 /dev/zero | tr '\\0' a); sleep 0.3";
        let script = format!("({hold}) & ({hold}) & wait");
        let one = run(Command::new("bash").args(["-c", &script])).unwrap();
        let all = run_watched(Command::new("bash").args(["-c", &script])).unwrap();
        assert!(one.max_rss_kib > 20_000, "{one:?}");
        assert!(
            all.max_rss_kib as f64 > 1.6 * one.max_rss_kib as f64,
            "{all:?} against {one:?}"
        );
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
