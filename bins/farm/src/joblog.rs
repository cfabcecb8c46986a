//! The job log, in GNU parallel's format, and the chunks it says finished.

use crate::checks::{frames_text, ChunkInfo, Output};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The first line of a job log, as GNU parallel writes it.
pub const JOBLOG_HEADER: &str =
    "Seq\tHost\tStarttime\tJobRuntime\tSend\tReceive\tExitval\tSignal\tCommand\n";

/// A line of a job log: a try of the chunk on argument line `seq` (from 1).
#[derive(Clone, Debug, PartialEq)]
pub struct JobLine {
    pub seq: usize,
    pub host: String,
    pub runtime: f64,
    pub exit: i32,
    pub signal: i32,
    pub command: String,
}

/// The lines of a job log (its header and any line not in its form left out).
pub fn parse_joblog(text: &str) -> Vec<JobLine> {
    text.lines()
        .filter_map(|line| {
            let f: Vec<&str> = line.splitn(9, '\t').collect();
            if f.len() < 9 {
                return None;
            }
            Some(JobLine {
                seq: f[0].trim().parse().ok()?,
                host: f[1].to_string(),
                runtime: f[3].trim().parse().ok()?,
                exit: f[6].trim().parse().ok()?,
                signal: f[7].trim().parse().ok()?,
                command: f[8].to_string(),
            })
        })
        .collect()
}

/// A chunk's argument line, which the job log shows at the end of its command (`… #
/// frames-8-to-15`): its frames, in one word.
pub fn chunk_arg(chunk: ChunkInfo) -> String {
    frames_text(chunk.first, chunk.frames).replace(' ', "-")
}

/// The argument line of an *idle* job: one farm hands parallel only to wake it when it
/// waits for its next argument while a chunk awaits a retry ([`run`](crate::run) says why). It
/// renders nothing and contacts no host.
pub const IDLE_ARG: &str = "idle";

/// The chunk a job log's command was run for (its argument line, after the last `# `),
/// `None` for an idle job or a line not farm's.
pub fn chunk_of_command(command: &str) -> Option<ChunkInfo> {
    let (_, arg) = command.rsplit_once("# ")?;
    let arg = arg.trim();
    if let Some(one) = arg.strip_prefix("frame-") {
        return Some(ChunkInfo {
            first: one.parse().ok()?,
            frames: 1,
        });
    }
    let (a, b) = arg.strip_prefix("frames-")?.split_once("-to-")?;
    let (a, b): (u64, u64) = (a.parse().ok()?, b.parse().ok()?);
    (b >= a).then(|| ChunkInfo {
        first: a,
        frames: b - a + 1,
    })
}

/// The chunks a job log says finished (exit 0, no signal), by their frames: what
/// `--resume` skips. A chunk is known by its frames rather than its job number, which
/// idle jobs shift from run to run; a run with another `--chunk` cuts other chunks and
/// skips none of them.
pub fn finished_chunks(lines: &[JobLine]) -> BTreeSet<ChunkInfo> {
    lines
        .iter()
        .filter(|l| l.exit == 0 && l.signal == 0)
        .filter_map(|l| chunk_of_command(&l.command))
        .collect()
}

/// The job log's path: `--joblog`, else beside -o's files (`DIR/farm.joblog`, DIR the
/// pattern's folder), else `None` (a temporary one in the spool).
pub fn joblog_path(joblog: Option<&Path>, output: &Output) -> Option<PathBuf> {
    if let Some(j) = joblog {
        return Some(j.to_path_buf());
    }
    match output {
        Output::Stdout => None,
        Output::Files { pattern, .. } => {
            let dir = Path::new(pattern)
                .parent()
                .filter(|d| !d.as_os_str().is_empty())
                .unwrap_or(Path::new("."));
            Some(dir.join("farm.joblog"))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_job_log_gives_the_chunks_finished() {
        let log = format!(
            "{JOBLOG_HEADER}\
             2\tflaky\t1.0\t 0.1\t0\t0\t255\t0\tfarm: frames 8 to 15, a failed try\n\
             1\tgood\t1.0\t 0.5\t0\t0\t0\t0\texec render.sh - # frames-0-to-7\n\
             3\tgood\t1.0\t 0.5\t0\t0\t-1\t2\texec render.sh - # frames-16-to-23\n\
             2\tgood\t1.2\t 0.4\t0\t0\t0\t0\texec render.sh - # frames-8-to-15\n"
        );
        let lines = parse_joblog(&log);
        assert_eq!(lines.len(), 4);
        assert_eq!(
            (lines[0].seq, lines[0].host.as_str(), lines[0].exit),
            (2, "flaky", 255)
        );
        let chunk = |first, frames| ChunkInfo { first, frames };
        assert_eq!(
            finished_chunks(&lines).into_iter().collect::<Vec<_>>(),
            [chunk(0, 8), chunk(8, 8)]
        );
        // An idle job finishes no chunk; a chunk of one frame is `frame-N`.
        let log = format!(
            "{JOBLOG_HEADER}\
             4\tgood\t1.0\t 0.0\t0\t0\t0\t0\texec render.sh - # idle\n\
             5\tgood\t1.0\t 0.5\t0\t0\t0\t0\texec render.sh - # frame-24\n"
        );
        assert_eq!(
            finished_chunks(&parse_joblog(&log))
                .into_iter()
                .collect::<Vec<_>>(),
            [chunk(24, 1)]
        );
        assert_eq!(chunk_arg(chunk(8, 8)), "frames-8-to-15");
        assert_eq!(chunk_arg(chunk(24, 1)), "frame-24");
        assert_eq!(chunk_of_command("x # frames-9-to-8"), None);
        assert_eq!(chunk_of_command("x # idle"), None);
    }
}
