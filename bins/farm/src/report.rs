//! What a run that succeeded reports: the hosts' own lines, and `--stats`.

use crate::checks::{frames_text, ChunkInfo};
use crate::hosts::Logins;
use crate::joblog::parse_joblog;
use crate::spool::Handed;
use stagecli::stats::Record;
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

/// On success: the hosts' own stderr lines (their --stats), labelled with the host (a
/// record given a `host`), in the movie's order (a host's `depth auto chose` once while
/// it is the same); with --stats, each host's part (and its record: `host`, `frames`,
/// `chunks`, `chunk_starts` and `chunk_frames` (lists, a chunk each), `sent_bytes`,
/// `received_bytes`, `busy_s`; a host with none has `frames=0 chunks=0`) and each failed try (its record:
/// `first_frame`, `frames`, `host`, `failed_status`).
pub(crate) fn report(
    handed: &[Handed],
    by_seq: &BTreeMap<usize, usize>,
    (logins, stats): (&Logins, bool),
    joblog: (&Path, usize, usize),
    log: &mut dyn Write,
) {
    // A host's choice of depth is said by each of its chunks: said once a host, and again
    // only when it changes. Its record (`depth_auto`, stagecli::stats) says which lines
    // those are: the record and the readable line before it.
    let mut depth_said: BTreeMap<&str, u64> = BTreeMap::new();
    for h in handed {
        let host = h.host.as_deref().unwrap_or("?");
        let lines: Vec<&str> = h.stderr.lines().collect();
        let mut skip_next = false;
        for (i, line) in lines.iter().enumerate() {
            if std::mem::take(&mut skip_next) {
                continue;
            }
            let record = |l: &str| stagecli::stats::parse_line(l).and_then(Result::ok);
            let depth = |r: &Record| (r.stage() == "render").then(|| r.count("depth_auto"))?;
            if let Some(d) = lines
                .get(i + 1)
                .and_then(|l| record(l))
                .and_then(|r| depth(&r))
            {
                if depth_said.insert(host, d) == Some(d) {
                    skip_next = true;
                    continue;
                }
            }
            match record(line) {
                Some(mut r) => {
                    if r.get("host").is_none() {
                        r.set("host", host);
                    }
                    let _ = writeln!(log, "{r}");
                }
                None => {
                    let line = stagecli::remote::without_render_prefix(line);
                    let _ = writeln!(log, "host {host}: {line}");
                }
            }
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
            let record = Record::new("farm")
                .with("host", host)
                .with("frames", 0)
                .with("chunks", 0);
            let _ = writeln!(
                log,
                "farm: host {host}: no frames (the movie has {total})\n{record}"
            );
            continue;
        };
        let frames: u64 = s.chunks.iter().map(|c| c.frames).sum();
        let ranges: Vec<String> = s
            .chunks
            .iter()
            .map(|c| frames_text(c.first, c.frames))
            .collect();
        let record = Record::new("farm")
            .with("host", host)
            .with("frames", frames)
            .with("chunks", s.chunks.len())
            .with_list("chunk_starts", s.chunks.iter().map(|c| c.first))
            .with_list("chunk_frames", s.chunks.iter().map(|c| c.frames))
            .with("sent_bytes", s.sent)
            .with("received_bytes", s.received)
            .with("busy_s", format!("{:.3}", s.busy));
        let _ = writeln!(
            log,
            "farm: host {host}: {frames} frame{} in {} chunk{} ({}), sent {} bytes, \
             received {} bytes, {:.2} s\n{record}",
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
            let record = Record::new("farm")
                .with("first_frame", h.info.first)
                .with("frames", h.info.frames)
                .with("host", &l.host)
                .with("failed_status", l.exit);
            let _ = writeln!(
                log,
                "farm: {}: a try on host {} failed (status {}), retried\n{record}",
                frames_text(h.info.first, h.info.frames),
                l.host,
                l.exit
            );
        }
    }
}
