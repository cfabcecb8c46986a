//! What a run that succeeded reports: the hosts' own lines, and `--stats`.

use crate::checks::{frames_text, ChunkInfo};
use crate::hosts::Logins;
use crate::joblog::parse_joblog;
use crate::spool::Handed;
use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

/// Per host, for --stats.
#[derive(Default)]
struct HostStats {
    chunks: Vec<ChunkInfo>,
    sent: u64,
    received: u64,
    busy: f64,
}

/// On success: the hosts' own stderr lines (their --stats), labelled with the host, in
/// the movie's order (a host's `depth auto chose` once while it is the same); with --stats, each host's part and each failed try.
pub(crate) fn report(
    handed: &[Handed],
    by_seq: &BTreeMap<usize, usize>,
    (logins, stats): (&Logins, bool),
    joblog: (&Path, usize, usize),
    log: &mut dyn Write,
) {
    // A host's choice of depth is said by each of its chunks: said once a host, and again
    // only when it changes.
    let mut depth_said: BTreeMap<&str, &str> = BTreeMap::new();
    for h in handed {
        let host = h.host.as_deref().unwrap_or("?");
        for line in h.stderr.lines() {
            let line = stagecli::remote::without_render_prefix(line);
            if line.contains("depth auto chose ") {
                let choice = line.split(" (").next().unwrap_or(line);
                if depth_said.insert(host, choice) == Some(choice) {
                    continue;
                }
            }
            let _ = writeln!(log, "host {host}: {line}");
        }
    }
    if !stats {
        return;
    }
    // This run's lines: those after the log's length when it started.
    let text = std::fs::read(joblog.0).unwrap_or_default();
    let lines = parse_joblog(&String::from_utf8_lossy(
        text.get(joblog.1..).unwrap_or_default(),
    ));
    let mut hosts: BTreeMap<String, HostStats> = BTreeMap::new();
    let mut order: Vec<String> = match logins {
        Logins::List(l) => l.iter().map(|(_, h)| h.clone()).collect(),
        Logins::File(_) => Vec::new(),
    };
    for h in handed {
        let (Some(host), Some(seq)) = (&h.host, h.seq) else {
            continue;
        };
        if !order.contains(host) {
            order.push(host.clone());
        }
        let s = hosts.entry(host.clone()).or_default();
        s.chunks.push(h.info);
        s.sent += h.sent;
        s.received += h.received;
        if let Some(l) = lines
            .iter()
            .rev()
            .find(|l| l.seq == seq + joblog.2 && l.exit == 0 && l.signal == 0)
        {
            s.busy += l.runtime;
        }
    }
    let total: u64 = handed.iter().map(|h| h.info.frames).sum();
    for host in &order {
        let Some(s) = hosts.get(host) else {
            let _ = writeln!(log, "farm: host {host}: no frames (the movie has {total})");
            continue;
        };
        let frames: u64 = s.chunks.iter().map(|c| c.frames).sum();
        let ranges: Vec<String> = s
            .chunks
            .iter()
            .map(|c| frames_text(c.first, c.frames))
            .collect();
        let _ = writeln!(
            log,
            "farm: host {host}: {frames} frame{} in {} chunk{} ({}), sent {} bytes, \
             received {} bytes, {:.2} s",
            if frames == 1 { "" } else { "s" },
            s.chunks.len(),
            if s.chunks.len() == 1 { "" } else { "s" },
            ranges.join(", "),
            s.sent,
            s.received,
            s.busy
        );
    }
    for l in lines.iter().filter(|l| l.exit != 0 || l.signal != 0) {
        if let Some(h) = by_seq
            .get(&l.seq.saturating_sub(joblog.2))
            .and_then(|&k| handed.get(k))
        {
            let _ = writeln!(
                log,
                "farm: {}: a try on host {} failed (status {}), retried",
                frames_text(h.info.first, h.info.frames),
                l.host,
                l.exit
            );
        }
    }
}
