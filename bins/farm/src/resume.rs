//! `--resume`: the chunks an earlier run finished, by its job log, whose frames are all
//! there and whole.

use crate::checks::{frames_text, verify_frame, ChunkInfo, Output};
use crate::joblog::{finished_chunks, parse_joblog};
use stagecli::{Error, Result};
use std::collections::BTreeSet;
use std::io::Write;
use std::path::Path;

/// What an earlier run left.
pub(crate) struct Resumed {
    /// The chunks not to render again.
    pub finished: BTreeSet<ChunkInfo>,
    /// The job log's last job number: this run's numbers follow it.
    pub seq0: usize,
    /// Whether there was a job log at all.
    pub found: bool,
}

/// Reads the job log `path` and checks the frames of each chunk it calls finished as
/// `--check` does (there, a whole PNG or PPM, all of one size): a chunk with a frame
/// missing, cut or of another size is rendered again, each said in one line on `log`.
/// Without a job log, every chunk is rendered, and that is said.
pub(crate) fn resume(path: &Path, output: &Output, log: &mut dyn Write) -> Result<Resumed> {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            let _ = writeln!(
                log,
                "farm: --resume: no job log {}: every chunk is rendered",
                path.display()
            );
            return Ok(Resumed {
                finished: BTreeSet::new(),
                seq0: 0,
                found: false,
            });
        }
        Err(e) => {
            return Err(Error::io(format!(
                "--resume: cannot read the job log {}: {}",
                path.display(),
                stagecli::error::io_message(&e)
            )))
        }
    };
    let lines = parse_joblog(&text);
    let seq0 = lines.iter().map(|l| l.seq).max().unwrap_or(0);
    let png = matches!(output, Output::Files { png: true, .. });
    let mut size = None;
    let mut finished = BTreeSet::new();
    for chunk in finished_chunks(&lines) {
        let bad = (chunk.first..chunk.first + chunk.frames).find_map(|k| {
            let file = output.path(k)?;
            let why = match (verify_frame(&file, png), size) {
                (Err(why), _) => why,
                (Ok(wh), None) => {
                    size = Some(wh);
                    return None;
                }
                (Ok(wh), Some(s)) if wh == s => return None,
                (Ok((w, h)), Some((sw, sh))) => format!("{w}x{h}, the others {sw}x{sh}"),
            };
            Some((k, file, why))
        });
        match bad {
            None => {
                finished.insert(chunk);
            }
            Some((k, file, why)) => {
                let _ = writeln!(
                    log,
                    "farm: --resume: frame {} ({}): {why}; {} rendered again",
                    output.number(k),
                    file.display(),
                    frames_text(chunk.first, chunk.frames)
                );
            }
        }
    }
    Ok(Resumed {
        finished,
        seq0,
        found: true,
    })
}
