//! The spool: how much it holds, and what the tries left in it.

use crate::checks::{classify, every_try_failed, frames_text, ChunkInfo, Failure, Try};
use stagecli::Error;
use std::io::Write;
use std::path::{Path, PathBuf};

/// A chunk of the movie, handed to parallel or skipped as finished before.
pub(crate) struct Handed {
    pub(crate) info: ChunkInfo,
    /// Its job number (its argument line's, from 1); `None` when skipped.
    pub(crate) seq: Option<usize>,
    /// Its frames taken (checked, and written or held), or skipped as finished before.
    pub(crate) taken: bool,
    /// Its frames written (to -o's files or to stdout), or skipped.
    pub(crate) written: bool,
    /// Its frames, held in the spool for stdout until its turn.
    pub(crate) held: Option<PathBuf>,
    /// The host of the try that rendered it, and that try's stderr.
    pub(crate) host: Option<String>,
    pub(crate) stderr: String,
    pub(crate) sent: u64,
    pub(crate) received: u64,
}

/// The chunks the spool holds at most (their streams, or their frames waiting for their
/// turn on stdout): two a job slot, so that each host has a chunk to start as soon as it
/// finishes one while the writer waits for an earlier chunk.
pub fn spool_bound(slots: usize) -> usize {
    2 * slots.max(1)
}

/// The chunks of `from` whose stream or frames are in the spool: handed and not yet
/// written.
pub(crate) fn in_spool(from: &[Handed]) -> usize {
    from.iter().filter(|h| !h.written).count()
}

/// The bytes of a file (0 when there is none): the jobs' count of their starts and ends.
pub(crate) fn count_bytes(path: &Path) -> u64 {
    std::fs::metadata(path).map_or(0, |m| m.len())
}

/// Of the chunks not rendered, as (job number, failed tries) in the movie's order, the
/// job of the earliest that failed on every one of its `retries` tries; `None` when none
/// did (parallel ended for another reason).
pub fn failed_chunk(pending: &[(usize, usize)], retries: usize) -> Option<usize> {
    pending
        .iter()
        .find(|&&(_, tries)| tries >= retries)
        .map(|&(seq, _)| seq)
}

/// The failed tries of the chunk of job `seq`, from the spool.
pub(crate) fn tries_of(dir: &Path, seq: usize) -> Vec<(Try, String)> {
    let list = std::fs::read_to_string(dir.join(format!("{seq}.tries"))).unwrap_or_default();
    list.lines()
        .enumerate()
        .filter_map(|(i, line)| {
            let (host, status) = line.rsplit_once('\t')?;
            let status: i32 = status.trim().parse().ok()?;
            let stderr = std::fs::read_to_string(dir.join(format!("{seq}.err.{}", i + 1)))
                .unwrap_or_default();
            let failure = classify(status, &stderr).unwrap_or(Failure {
                message: format!("failed (status {status})"),
                status: 3,
            });
            Some((
                Try {
                    host: host.to_string(),
                    failure,
                },
                stderr,
            ))
        })
        .collect()
}

/// The run's error when parallel ended with a chunk (the earliest not written: job `seq`,
/// frames `info`) not rendered: its tries' one line, the lines its last host wrote before its last on `log`;
/// or, with no try of it on record, parallel's own last line.
pub(crate) fn failure_of(
    dir: &Path,
    seq: Option<usize>,
    info: Option<ChunkInfo>,
    status: std::process::ExitStatus,
    log: &mut dyn Write,
) -> Error {
    let tries = seq.map(|seq| tries_of(dir, seq)).unwrap_or_default();
    if let (Some(info), false) = (info, tries.is_empty()) {
        let (last, stderr) = &tries[tries.len() - 1];
        let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
        for l in &lines[..lines.len().saturating_sub(1)] {
            let l = stagecli::remote::without_render_prefix(l);
            let _ = writeln!(log, "host {}: {l}", last.host);
        }
        let just: Vec<Try> = tries.into_iter().map(|(t, _)| t).collect();
        let f = every_try_failed(info, &just);
        return Error::new(kind_of(f.status), f.message);
    }
    let said = std::fs::read_to_string(dir.join("parallel.err")).unwrap_or_default();
    let line = said
        .lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("")
        .trim();
    let what = info.map_or_else(String::new, |i| {
        format!(" with {} not rendered", frames_text(i.first, i.frames))
    });
    if line.is_empty() {
        Error::io(format!("parallel ended ({status}){what}"))
    } else {
        Error::io(format!("parallel ended ({status}){what}: {line}"))
    }
}

fn kind_of(status: u8) -> stagecli::Kind {
    match status {
        1 => stagecli::Kind::Data,
        2 => stagecli::Kind::Usage,
        _ => stagecli::Kind::Io,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_failure_is_the_chunk_that_used_up_its_tries() {
        // Job 3 failed once and waits for a retry that --halt soon never starts; job 5
        // failed its three: the run's line is job 5's.
        assert_eq!(failed_chunk(&[(3, 1), (4, 0), (5, 3), (6, 3)], 3), Some(5));
        assert_eq!(failed_chunk(&[(3, 1), (4, 0)], 3), None);
        assert_eq!(failed_chunk(&[], 1), None);
    }

    #[test]
    fn the_spool_holds_two_chunks_a_job_slot() {
        assert_eq!(spool_bound(1), 2);
        assert_eq!(spool_bound(3), 6);
        assert_eq!(spool_bound(0), 2);
    }
}
