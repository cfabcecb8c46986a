//! The hosts watched as the run goes: a host's first failed try named at once, a host
//! that failed `--host-failures` tries in a row dropped from parallel's sshlogin file
//! (parallel reads the file again when it changes, and starts no more chunks there), and
//! a host silent for `--host-timeout` stopped, so that its chunk is retried elsewhere.

use crate::hosts::host_of_line;
use crate::spool::tries_of;
use stagecli::whole::write_whole;
use stagecli::Result;
use std::collections::{BTreeMap, BTreeSet};
use std::io::Write;
use std::path::Path;
use std::time::{Duration, SystemTime};

/// Failures in a row after which a host gets no more chunks, by default.
pub const DEFAULT_HOST_FAILURES: u32 = 2;

/// Seconds a host may send nothing (no frame byte, no stderr) before its try fails, by
/// default; 0 waits for ever.
pub const DEFAULT_HOST_TIMEOUT: u64 = 60;

/// The file of sshlogins farm hands parallel, in the spool.
pub const HOSTS_FILE: &str = "hosts";

/// What is known of the hosts during a run.
pub(crate) struct HostWatch {
    /// The sshlogin lines, in the order given.
    lines: Vec<String>,
    dropped: BTreeSet<String>,
    named: BTreeSet<String>,
    in_row: BTreeMap<String, u32>,
    /// The bytes of the spool's `ended` read so far.
    read: usize,
    limit: u32,
    timeout: Option<Duration>,
    timed_out: BTreeSet<usize>,
}

impl HostWatch {
    /// `limit` failures in a row drop a host; `timeout` seconds of silence (0: none) fail
    /// a try.
    pub(crate) fn new(lines: Vec<String>, limit: u32, timeout: u64) -> HostWatch {
        HostWatch {
            lines,
            dropped: BTreeSet::new(),
            named: BTreeSet::new(),
            in_row: BTreeMap::new(),
            read: 0,
            limit: limit.max(1),
            timeout: (timeout > 0).then(|| Duration::from_secs(timeout)),
            timed_out: BTreeSet::new(),
        }
    }

    /// Writes the sshlogin file parallel reads (the lines whose host is not dropped), and
    /// the hosts left and dropped, a line each, for the shim.
    pub(crate) fn write_hosts(&self, dir: &Path) -> Result<()> {
        let mut text = String::new();
        for l in &self.lines {
            if !self.dropped.contains(host_of_line(l)) {
                text.push_str(l);
                text.push('\n');
            }
        }
        let mut left = String::new();
        let mut dropped = String::new();
        let mut seen = BTreeSet::new();
        for l in &self.lines {
            let host = host_of_line(l);
            if seen.insert(host) {
                let list = if self.dropped.contains(host) {
                    &mut dropped
                } else {
                    &mut left
                };
                list.push_str(host);
                list.push('\n');
            }
        }
        for (name, text) in [("left", left), ("dropped", dropped), (HOSTS_FILE, text)] {
            let path = dir.join(name);
            write_whole(&path, text.as_bytes())?;
        }
        Ok(())
    }

    /// The hosts still given chunks.
    fn left(&self) -> usize {
        let hosts: BTreeSet<&str> = self.lines.iter().map(|l| host_of_line(l)).collect();
        hosts.iter().filter(|h| !self.dropped.contains(**h)).count()
    }

    /// Reads the tries that ended since the last look (the spool's `ended`): names a
    /// host's first failure, drops a host after `limit` failures in a row while another
    /// host is left; and stops the tries of `running` (job numbers) whose host has sent
    /// nothing for the timeout.
    pub(crate) fn poll(
        &mut self,
        dir: &Path,
        running: &[usize],
        log: &mut dyn Write,
    ) -> Result<()> {
        let text = std::fs::read(dir.join("ended")).unwrap_or_default();
        let new = text.get(self.read..).unwrap_or_default();
        let complete = new.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
        self.read += complete;
        let mut changed = false;
        for line in String::from_utf8_lossy(&new[..complete]).lines() {
            let f: Vec<&str> = line.split('\t').collect();
            let [host, status, seq] = f[..] else { continue };
            let (Ok(status), Ok(seq)) = (status.parse::<i32>(), seq.parse::<usize>()) else {
                continue;
            };
            if status == 0 {
                self.in_row.insert(host.to_string(), 0);
                continue;
            }
            let n = self.in_row.entry(host.to_string()).or_insert(0);
            *n += 1;
            let n = *n;
            if self.named.insert(host.to_string()) {
                let what =
                    std::fs::read_to_string(dir.join(format!("{seq}.what"))).unwrap_or_default();
                let why = tries_of(dir, seq).last().map_or_else(
                    || format!("status {status}"),
                    |(t, _)| t.failure.message.clone(),
                );
                let _ = writeln!(log, "farm: host {host}: a try of {what} failed: {why}");
            }
            if n >= self.limit && !self.dropped.contains(host) && self.left() > 1 {
                self.dropped.insert(host.to_string());
                changed = true;
                let _ = writeln!(
                    log,
                    "farm: host {host}: {n} failed tries in a row; it gets no more chunks"
                );
            }
        }
        if changed {
            self.write_hosts(dir)?;
        }
        if let Some(limit) = self.timeout {
            for &seq in running {
                self.stop_if_silent(dir, seq, limit);
            }
        }
        Ok(())
    }

    /// Stops the try of job `seq` when its host has sent nothing for `limit`: the last
    /// change of its output, its stderr or its start (`K.pid`) is older.
    fn stop_if_silent(&mut self, dir: &Path, seq: usize, limit: Duration) {
        let pid_file = dir.join(format!("{seq}.pid"));
        let Ok(pid) = std::fs::read_to_string(&pid_file) else {
            return;
        };
        let Ok(pid) = pid.trim().parse::<libc::pid_t>() else {
            return;
        };
        let last = [
            format!("{seq}.pid"),
            format!("{seq}.part"),
            format!("{seq}.err"),
        ]
        .iter()
        .filter_map(|f| {
            std::fs::metadata(dir.join(f))
                .and_then(|m| m.modified())
                .ok()
        })
        .max();
        let Some(last) = last else { return };
        let silent = SystemTime::now().duration_since(last).unwrap_or_default();
        if silent < limit || self.timed_out.contains(&seq) {
            return;
        }
        let secs = limit.as_secs();
        let said = format!("sent nothing for {secs} s (--host-timeout {secs})\n");
        if std::fs::write(dir.join(format!("{seq}.timeout")), said).is_err() {
            return;
        }
        self.timed_out.insert(seq);
        for child in children_of(pid) {
            // SAFETY: kill(2) touches no memory of ours; the pid is a child of the shim,
            // which waits for it (so it has not been reaped and its pid not reused).
            unsafe {
                libc::kill(child, libc::SIGTERM);
            }
        }
    }
}

/// The processes whose parent is `parent` (from /proc).
fn children_of(parent: libc::pid_t) -> Vec<libc::pid_t> {
    let Ok(entries) = std::fs::read_dir("/proc") else {
        return Vec::new();
    };
    entries
        .flatten()
        .filter_map(|e| e.file_name().to_str()?.parse::<libc::pid_t>().ok())
        .filter(|pid| {
            let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
            // pid (comm) state ppid …: the name may hold spaces and parentheses.
            let ppid = stat
                .rsplit_once(") ")
                .and_then(|(_, rest)| rest.split(' ').nth(1))
                .and_then(|p| p.parse::<libc::pid_t>().ok());
            ppid == Some(parent)
        })
        .collect()
}
