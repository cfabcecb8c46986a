//! Signals, and the processes parallel leaves: a run stops and reaps what it started.

use stagecli::Result;
use std::collections::BTreeMap;
use std::process::Child;
use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};
use std::time::Duration;

/// How the run ended, for main to report.
#[derive(Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Every frame written (or the reader of the frames went away: a quiet end).
    Done,
    /// Stopped by a signal (its number).
    Stopped(i32),
}

/// The signal that asked the run to stop (SIGINT or SIGTERM), 0 while none has.
pub(crate) static STOP: AtomicI32 = AtomicI32::new(0);

extern "C" fn on_signal(sig: libc::c_int) {
    STOP.store(sig, Ordering::SeqCst);
}

/// From now on SIGINT and SIGTERM ask the run to stop (parallel and its jobs are stopped
/// and the run ends with 128 + the signal) instead of ending it at once. A program run
/// from here gets the default actions back when it starts.
pub fn catch_stop_signals() {
    let handler = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
    // SAFETY: the handler only stores into an atomic, which is async-signal-safe.
    unsafe {
        libc::signal(libc::SIGINT, handler);
        libc::signal(libc::SIGTERM, handler);
    }
}

/// Whether [`adopt_orphans`] has made this process the reaper of its descendants.
static ADOPTING: AtomicBool = AtomicBool::new(false);

/// From now on a process started under this one (a job of parallel's, its ssh) that
/// outlives its parent is handed to this process, not to init, and [`run`](crate::run) stops and
/// reaps every such process before it returns. GNU parallel stops its jobs by process
/// group when asked to stop, but a job it is starting at that moment (forked, not yet in
/// its table of running jobs) escapes that and goes on: its ssh and the session on the
/// host outlived the run about one stop in six. Call it once, from the program's main,
/// before [`run`](crate::run): a process that adopts must know all its children.
pub fn adopt_orphans() {
    // SAFETY: prctl(PR_SET_CHILD_SUBREAPER) takes an integer and touches no memory.
    let done = unsafe { libc::prctl(libc::PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0) } == 0;
    ADOPTING.store(done, Ordering::SeqCst);
}

/// The processes whose parent is this one, by pid, with their process groups.
fn children() -> Vec<(libc::pid_t, libc::pid_t)> {
    let me = std::process::id() as libc::pid_t;
    let Ok(entries) = std::fs::read_dir("/proc") else {
        return Vec::new();
    };
    let mut found = Vec::new();
    for entry in entries.flatten() {
        let Some(pid) = entry.file_name().to_str().and_then(|n| n.parse().ok()) else {
            continue;
        };
        let Ok(stat) = std::fs::read_to_string(format!("/proc/{pid}/stat")) else {
            continue;
        };
        // pid (comm) state ppid pgrp ...: the name may hold spaces and parentheses.
        let Some((_, rest)) = stat.rsplit_once(") ") else {
            continue;
        };
        let mut fields = rest.split(' ').skip(1);
        let ppid: Option<libc::pid_t> = fields.next().and_then(|f| f.parse().ok());
        let pgrp: Option<libc::pid_t> = fields.next().and_then(|f| f.parse().ok());
        if let (Some(ppid), Some(pgrp)) = (ppid, pgrp) {
            if ppid == me {
                found.push((pid, pgrp));
            }
        }
    }
    found
}

/// Once parallel has ended: stops (SIGTERM, then SIGKILL after a second) and reaps every
/// process handed to this one ([`adopt_orphans`]), and those they leave in turn, for at
/// most ten seconds (a loaded machine can take a while to end a killed process). A
/// process in a group of its own gets the signal by its group, as parallel would send it.
fn reap_orphans() {
    if !ADOPTING.load(Ordering::SeqCst) {
        return;
    }
    let start = std::time::Instant::now();
    let mut signalled: BTreeMap<libc::pid_t, i32> = BTreeMap::new();
    loop {
        let left = children();
        if left.is_empty() || start.elapsed() > Duration::from_secs(10) {
            return;
        }
        let sig = if start.elapsed() < Duration::from_secs(1) {
            libc::SIGTERM
        } else {
            libc::SIGKILL
        };
        for &(pid, pgrp) in &left {
            let mut status = 0;
            // SAFETY: waitpid on a child of ours, WNOHANG; status is a local.
            if unsafe { libc::waitpid(pid, &mut status, libc::WNOHANG) } == pid {
                continue;
            }
            if signalled.get(&pid) != Some(&sig) {
                signalled.insert(pid, sig);
                let target = if pgrp == pid { -pid } else { pid };
                // SAFETY: kill(2) touches no memory of ours.
                unsafe {
                    libc::kill(target, sig);
                }
            }
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Waits for parallel, which ends by itself once every frame is written (`all_written`:
/// its input has ended and every job has), else stops it (SIGINT: it stops its jobs and
/// ends; then SIGTERM and SIGKILL if it lingers); removes the spool, and returns
/// `result`.
pub(crate) fn finish(
    mut child: Child,
    all_written: bool,
    result: Result<Outcome>,
) -> Result<Outcome> {
    let steps = [
        (libc::SIGINT, 3000),
        (libc::SIGTERM, 1000),
        (libc::SIGTERM, 1000),
        (libc::SIGKILL, 1000),
    ];
    let mut step = 0;
    let mut waited: u64 = 0;
    // Once everything is written, parallel ends by itself: its input has ended and
    // every job has.
    let mut grace: u64 = if all_written { 5000 } else { 0 };
    loop {
        match child.try_wait() {
            Ok(Some(_)) | Err(_) => break,
            Ok(None) => {}
        }
        if grace > 0 {
            grace -= 10;
        } else if waited == 0 && step < steps.len() {
            kill(child.id(), steps[step].0);
            waited = steps[step].1;
            step += 1;
        } else if waited == 0 {
            break;
        }
        std::thread::sleep(Duration::from_millis(10));
        waited = waited.saturating_sub(10);
    }
    reap_orphans();
    result
}

/// Sends `sig` to process `pid`.
fn kill(pid: u32, sig: i32) {
    if let Ok(pid) = libc::pid_t::try_from(pid) {
        // SAFETY: kill(2) takes any pid and signal; it touches no memory of ours.
        unsafe {
            libc::kill(pid, sig);
        }
    }
}
