//! # farm: a movie's frames rendered on other hosts by GNU parallel, written back in order
//!
//! A movie is `frame { NEXT.FRAME frame } END` (Theoharis 1985, Appendix 1; the stream's
//! grammar in docs/DESIGN.md), and its frames are independent: a run of them is a movie
//! of its own, and rendering the runs one after another gives the frames of the whole.
//! `render.sh --by frames` runs this program, which
//!
//! 1. cuts the movie, as it reads it, into *chunks* of a few frames (`--chunk N`), each a
//!    movie of its own with the movie's header ([`Cutter`]), kept in a private spool
//!    folder of `$TMPDIR`;
//! 2. hands the chunks to GNU parallel (Tange, `man parallel`), one argument line a
//!    chunk: parallel chooses the host with a free job slot (`--sshlogin N/host`,
//!    `--sshloginfile`), retries a chunk that failed on a host where it has not failed
//!    (`--retries`), keeps the job log (`--joblog`), and stops starting chunks after
//!    one failed on every try (`--halt soon,fail=1`);
//! 3. writes the frames in the movie's order on stdout, or each frame to its file
//!    (`-o PATTERN`, numbered from `--first-frame`) as its chunk comes back.
//!
//! What parallel cannot do is what remains here. Parallel's `--pipe` gives a job its
//! block of stdin, but cuts only at byte patterns, so a chunk could not start with the
//! movie's header, and reads whole `--block`s before it starts a job, so a chunk smaller
//! than a block would wait for the next to be cut. So parallel's ssh (`--ssh`) is a
//! small script of the spool ([`shim_script`]): it runs `$POLYPIPE_SSH` with the chunk
//! of the job's number (`$PARALLEL_SEQ`, the argument line's) on its stdin and its
//! frames into the spool, then waits until this program has checked them (every frame,
//! whole) and taken them: a chunk that came back short is a failed try that parallel
//! retries elsewhere, and a chunk the job log calls done is one whose frames were
//! written.
//!
//! Memory and disk stay bounded by the hosts' job slots, not the movie's length. The
//! movie is cut only while the spool holds fewer than two chunks a job slot
//! ([`spool_bound`]): chunks handed to parallel and not yet taken (their streams, `K.in`)
//! and chunks taken but waiting for an earlier one to be written (their frames, on
//! stdout's way); memory holds one chunk's frames at a time, and one chunk cut ahead.
//! parallel's own files in its `--tmpdir` (the spool) are a few a running job, its
//! buffers of the job's stdout and stderr, unlinked as they are opened or as the job
//! ends, and empty here (the script sends a job's output to the spool files above).
//!
//! Holding the chunks back needs one more thing of this program. parallel reads its next
//! argument as soon as its queue has none it could start on a free job slot, and waits
//! for it doing nothing else: it neither reaps a job that ended nor retries a chunk
//! elsewhere. A chunk that failed on one host and awaits another leaves that host's slot
//! free, so parallel waits for an argument, and the argument waits for the spool to
//! empty, which waits for the retry: a deadlock (with hosts `good,flaky`, flaky failing
//! every first try, it came within a second of the start). So when the spool is full,
//! no job is running and one has ended since the last argument, this program hands
//! parallel an *idle* argument ([`IDLE_ARG`]), whose job ends at once without a host:
//! parallel wakes, reaps, and retries the chunk. The job log shows these jobs as
//! `# idle`; they take job numbers, so `--resume` knows a chunk by its frames
//! ([`finished_chunks`]) and hands parallel only the chunks not finished.
//!
//! When a chunk fails on every try, the chunks before it are written whole and the run
//! ends with one line naming the host(s) and the chunk: status 3 for a host or the link,
//! the far render.sh's own status (1 or 2) for a fault it found in the movie or the
//! options. SIGINT and SIGTERM stop parallel and its jobs, and the run ends with 130 or
//! 143, as render.sh does; with `-o`, `--resume` renders only the chunks that did not
//! finish.

use proto::codec::{Control, Record};
use proto::{Form, Reader, SpaceKind, Token, Writer};
use stagecli::{Error, FrameNames, Result};
use std::collections::{BTreeMap, BTreeSet};
use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};
use std::sync::mpsc;
use std::time::Duration;

/// The frames of a chunk by default: few enough that the spool holds a few per host,
/// and enough that an ssh session's start (a connection, a render.sh and its choice of
/// depth there) is paid once for several frames.
pub const DEFAULT_CHUNK: u64 = 8;

/// Tries of a chunk by default, each on a host where it has not failed while there is
/// one (parallel's `--retries`).
pub const DEFAULT_RETRIES: u32 = 3;

/// The first line of a job log, as GNU parallel writes it.
pub const JOBLOG_HEADER: &str =
    "Seq\tHost\tStarttime\tJobRuntime\tSend\tReceive\tExitval\tSignal\tCommand\n";

// --- Cutting the movie. -----------------------------------------------------------------

/// One chunk of the movie: a movie of its own, in the binary form.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Chunk {
    /// Its place among the chunks, from 0.
    pub index: usize,
    /// The movie's number of its first frame (from 0).
    pub first: u64,
    /// How many frames it has.
    pub frames: u64,
    /// The stream: the movie's header, the frames' records, END.
    pub bytes: Vec<u8>,
}

/// Cuts a movie into chunks of `size` frames (the last may have fewer), reading it only
/// as far as the chunk asked for. Records pass unchanged (polygon numbers restart in
/// every frame); only the frame boundaries at a cut are new: END ends a chunk, and the
/// next starts with the header and no NEXT.FRAME.
pub struct Cutter<R: Read> {
    reader: Reader<Token, R>,
    size: u64,
    next_index: usize,
    next_frame: u64,
    done: bool,
}

impl<R: Read> Cutter<R> {
    /// A cutter of the movie `reader` reads: a polygon stream (world, eye or screen).
    pub fn new(reader: Reader<Token, R>, size: u64) -> Result<Self> {
        if SpaceKind::of(&reader.header().space) == SpaceKind::Fragments {
            return Err(Error::data(
                "a fragment stream; the hosts render polygon streams (world, eye or screen)",
            ));
        }
        Ok(Cutter {
            reader,
            size: size.max(1),
            next_index: 0,
            next_frame: 0,
            done: false,
        })
    }

    /// The next chunk, or `None` after the last.
    pub fn next_chunk(&mut self) -> Result<Option<Chunk>> {
        if self.done {
            return Ok(None);
        }
        let header = *self.reader.header();
        let mut writer = Writer::<Token, _>::new(Vec::new(), header, Form::Binary)?;
        let mut frames = 1; // the frame now being copied is the chunk's `frames`th
        loop {
            let Some(record) = self.reader.next_record()? else {
                // The reader returns END before the stream's end; a stream cut short
                // is its error, not this.
                return Err(Error::data("the movie ends without END"));
            };
            match record.control() {
                Control::NextFrame if frames == self.size => {
                    writer.write(&Token::End)?;
                    break;
                }
                Control::NextFrame => {
                    writer.write(&record)?;
                    frames += 1;
                }
                Control::End => {
                    writer.write(&record)?;
                    self.done = true;
                    break;
                }
                _ => writer.write(&record)?,
            }
        }
        let chunk = Chunk {
            index: self.next_index,
            first: self.next_frame,
            frames,
            bytes: writer.into_inner()?,
        };
        self.next_index += 1;
        self.next_frame += frames;
        Ok(Some(chunk))
    }

    /// The movie's frames cut so far.
    pub fn frames_so_far(&self) -> u64 {
        self.next_frame
    }
}

// --- The hosts. -------------------------------------------------------------------------

/// Where the chunks go: parallel's sshlogins.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Logins {
    /// `--hosts H1,H2,…`: each host with its job slots, a host named twice having two
    /// (`2/H`), in the order first named.
    List(Vec<(usize, String)>),
    /// `--sshloginfile FILE`, parallel's own format (`N/host` a line), read by parallel.
    File(PathBuf),
}

/// `--hosts H1,H2,…` as sshlogins: `a,b,a` is `2/a` and `1/b`.
pub fn logins_from_hosts(list: &str) -> std::result::Result<Vec<(usize, String)>, String> {
    let mut logins: Vec<(usize, String)> = Vec::new();
    for host in stagecli::remote::parse_hosts(list)? {
        match logins.iter_mut().find(|(_, h)| *h == host) {
            Some((n, _)) => *n += 1,
            None => logins.push((1, host)),
        }
    }
    Ok(logins)
}

/// The job slots an sshlogin file gives: `N/host` N, a bare host 1 (farm runs parallel
/// with `-j1`), blank lines and `#` comments none. A file with none is refused before
/// parallel starts; parallel reads the file itself.
pub fn slots_in_sshloginfile(text: &str) -> usize {
    text.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(|l| {
            l.split_once('/')
                .and_then(|(n, _)| n.trim().parse::<usize>().ok())
                .unwrap_or(1)
        })
        .sum()
}

// --- The frames. ------------------------------------------------------------------------

/// Reads one PPM frame (a header `P6 W H 255` and W·H RGB pixels, as zbuf writes it)
/// into the bytes zbuf would have written; `None` at the end; a message when it is not
/// one.
pub fn next_frame<R: BufRead>(input: &mut R) -> std::result::Result<Option<Frame>, String> {
    match proto::ppm::read(input) {
        Ok(None) => Ok(None),
        Ok(Some(image)) => {
            let mut rgb = Vec::with_capacity(image.pixels.len() * 3);
            for p in &image.pixels {
                rgb.extend_from_slice(p);
            }
            Ok(Some(Frame {
                width: image.width,
                height: image.height,
                rgb,
            }))
        }
        Err(e) => Err(e.to_string()),
    }
}

/// A frame as it came back.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

impl Frame {
    /// The frame as zbuf writes it on stdout: binary PPM.
    pub fn ppm(&self) -> Vec<u8> {
        let mut bytes = format!("P6\n{} {}\n255\n", self.width, self.height).into_bytes();
        bytes.extend_from_slice(&self.rgb);
        bytes
    }
}

/// Where the frames go.
#[derive(Clone, Debug)]
pub enum Output {
    /// Binary PPMs one after another on stdout, in the movie's order.
    Stdout,
    /// One file a frame, as zbuf's `-o PATTERN --first-frame N` writes them: the movie's
    /// frame k to `names.name(first + k)`, PNG or PPM by the extension.
    Files {
        pattern: String,
        names: FrameNames,
        png: bool,
        first: u64,
    },
}

impl Output {
    /// `-o PATTERN` (zbuf's: `%d`/`%0Nd` the frame's number, `.png` or `.ppm`) with
    /// `--first-frame N`.
    pub fn files(pattern: &str, first: u64) -> std::result::Result<Output, String> {
        let (names, ext) = FrameNames::parse_ending(pattern, &["png", "ppm"])?;
        if !names.numbered() {
            return Err(format!(
                "-o {pattern}: a movie needs a pattern with %d for the frame number (as \
                 frame%05d.png)"
            ));
        }
        Ok(Output::Files {
            pattern: pattern.to_string(),
            names,
            png: ext == "png",
            first,
        })
    }

    /// The file of the movie's frame `k` (`None` for stdout).
    pub fn path(&self, k: u64) -> Option<PathBuf> {
        match self {
            Output::Stdout => None,
            Output::Files { names, first, .. } => Some(names.name(first + k).into()),
        }
    }

    /// Writes the movie's frame `k` to its file, the bytes zbuf's `-o` would write.
    pub fn save(&self, k: u64, frame: &Frame) -> Result<()> {
        let (Some(path), Output::Files { png, .. }) = (self.path(k), self) else {
            return Ok(());
        };
        let fail = |e: String| Error::io(format!("cannot write {}: {e}", path.display()));
        if *png {
            image::save_buffer_with_format(
                &path,
                &frame.rgb,
                frame.width,
                frame.height,
                image::ExtendedColorType::Rgb8,
                image::ImageFormat::Png,
            )
            .map_err(|e| match e {
                image::ImageError::IoError(io) => fail(stagecli::error::io_message(&io)),
                other => fail(other.to_string()),
            })
        } else {
            std::fs::write(&path, frame.ppm()).map_err(|e| fail(stagecli::error::io_message(&e)))
        }
    }
}

/// The frames of a chunk, for messages: `frames 8 to 11`, `frame 3`.
pub fn frames_text(first: u64, frames: u64) -> String {
    if frames == 1 {
        format!("frame {first}")
    } else {
        format!("frames {first} to {}", first + frames - 1)
    }
}

/// A chunk's place in the movie.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ChunkInfo {
    pub first: u64,
    pub frames: u64,
}

/// Reads what a try of `chunk` sent back: its frames, or why they are not the chunk's
/// (nothing, too few, too many, or what is not a frame) in the words of a host's failure.
pub fn check_frames<R: BufRead>(
    input: &mut R,
    chunk: ChunkInfo,
) -> std::result::Result<Vec<Frame>, String> {
    let what = frames_text(chunk.first, chunk.frames);
    let mut frames = Vec::new();
    loop {
        match next_frame(input) {
            Ok(Some(f)) => frames.push(f),
            Ok(None) => break,
            Err(why) => {
                return Err(format!(
                    "sent back {} of its {what}, then what is not a frame: {why}",
                    frames.len()
                ))
            }
        }
    }
    let got = frames.len() as u64;
    match got {
        0 if chunk.frames > 0 => Err(format!("sent back nothing for its {what}")),
        n if n < chunk.frames => Err(format!("sent back {n} of its {what}")),
        n if n > chunk.frames => Err(format!("sent back {n} frames for its {what}")),
        _ => Ok(frames),
    }
}

// --- How a try ended. -------------------------------------------------------------------

pub use stagecli::remote::{last_line, parse_hosts, remote_command, Failure};

/// What a try that ended with the shell status `status` (ssh's: the far command's, 255
/// for ssh's own failure, 128 + N when killed by signal N) and `stderr` means
/// ([`stagecli::remote::classify`], the command there being render.sh's).
pub fn classify(status: i32, stderr: &str) -> Option<Failure> {
    if (129..=128 + 64).contains(&status) {
        stagecli::remote::classify(None, Some(status - 128), stderr, "the command")
    } else {
        stagecli::remote::classify(Some(status), None, stderr, "the command")
    }
}

/// One try of a chunk that failed: the host and what it said.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Try {
    pub host: String,
    pub failure: Failure,
}

/// The one line for a chunk that failed on every try: the host(s), the chunk, the tries
/// and the last try's own words; its status is the last try's.
pub fn every_try_failed(chunk: ChunkInfo, tries: &[Try]) -> Failure {
    let what = frames_text(chunk.first, chunk.frames);
    let Some(last) = tries.last() else {
        return Failure {
            message: format!("{what}: not rendered (no try of it ended)"),
            status: 3,
        };
    };
    let mut hosts: Vec<&str> = Vec::new();
    for t in tries {
        if !hosts.contains(&t.host.as_str()) {
            hosts.push(&t.host);
        }
    }
    let n = tries.len();
    let times = if n == 1 {
        "1 try".to_string()
    } else {
        format!("{n} tries")
    };
    let message = if hosts.len() == 1 {
        format!(
            "host {}: {what}, {times}: {}",
            hosts[0], last.failure.message
        )
    } else {
        format!(
            "hosts {}: {what}, {times}, the last on {}: {}",
            hosts.join(", "),
            last.host,
            last.failure.message
        )
    };
    Failure {
        message,
        status: last.failure.status,
    }
}

// --- The job log. -----------------------------------------------------------------------

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
/// waits for its next argument while a chunk awaits a retry ([`run`] says why). It
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

// --- parallel's ssh. --------------------------------------------------------------------

use stagecli::remote::quote;

/// The script parallel runs as its ssh (`--ssh`): `SCRIPT [OPTIONS] HOST COMMAND…`. For a
/// job (`$PARALLEL_SEQ` set: the chunk's argument line, from 1) it runs `SSH… "$@"` with
/// the chunk's stream `SPOOL/K.in` on stdin, its stdout to `K.part` and stderr to
/// `K.err`; on success it renames `K.part` to `K.out` (with the host in `K.host`) and
/// waits for farm to take it: `K.ok` then says the frames were whole and written, and
/// the job succeeds; `K.bad` says why not, and the try fails. A failed try is kept
/// (`K.tries`: host and status a line; `K.err.N`: its stderr) and logged in the job log
/// as a line of its own (parallel logs only a job's last try). An idle job (`K.idle`)
/// ends at once with status 0. Each job appends a byte to `starts` as it starts and to
/// `ends` as it ends. Anything else parallel runs through its ssh goes straight to
/// `SSH…`.
pub fn shim_script(spool: &Path, ssh: &[String], joblog: &Path) -> String {
    let ssh: Vec<String> = ssh.iter().map(|w| quote(w)).collect();
    let ssh = ssh.join(" ");
    let spool = quote(&spool.display().to_string());
    let joblog = quote(&joblog.display().to_string());
    format!(
        r#"#!/bin/sh
# farm's ssh for GNU parallel: chunk $PARALLEL_SEQ of the spool to the host and back.
spool={spool}
# parallel's worker runs the command with the far side's $SHELL, which sshd sets from the
# user's login; a stand-in for ssh that runs it here (a test's, a container's) inherits
# ours, and without one the worker runs nothing and exits 0. sh, as sshd would say.
export SHELL="${{SHELL:-/bin/sh}}"
k=${{PARALLEL_SEQ-}}
case $k in '' | *[!0-9]*) exec {ssh} "$@" ;; esac
# Every job of farm's is counted as it starts and as it ends: farm tells from the two
# when nothing runs.
if [ -e "$spool/$k.idle" ]; then
    rm -f "$spool/$k.idle"
    printf s >>"$spool/starts"
    printf e >>"$spool/ends"
    exit 0
fi
[ -e "$spool/$k.in" ] || exec {ssh} "$@"
printf s >>"$spool/starts"
trap '{{ printf e >>"$spool/ends"; }} 2>/dev/null' EXIT
host=${{PARALLEL_SSHLOGIN:-?}}
start=$(date +%s.%N)
{ssh} "$@" <"$spool/$k.in" >"$spool/$k.part" 2>"$spool/$k.err"
st=$?
if [ "$st" -eq 0 ]; then
    printf '%s\n' "$host" >"$spool/$k.host"
    mv -f "$spool/$k.part" "$spool/$k.out"
    while [ -e "$spool/$k.out" ]; do sleep 0.01; done
    if [ -e "$spool/$k.ok" ]; then
        rm -f "$spool/$k.ok"
        exit 0
    fi
    # farm's reason: the try's last line.
    cat "$spool/$k.bad" >>"$spool/$k.err" 2>/dev/null
    rm -f "$spool/$k.bad"
    st=3
fi
[ -d "$spool" ] || exit "$st"
rm -f "$spool/$k.part"
n=1
[ ! -e "$spool/$k.tries" ] || n=$(($(wc -l <"$spool/$k.tries") + 1))
mv -f "$spool/$k.err" "$spool/$k.err.$n"
printf '%s\t%s\n' "$host" "$st" >>"$spool/$k.tries"
end=$(date +%s.%N)
printf '%s\t%s\t%.3f\t%10.3f\t0\t0\t%s\t0\tfarm: %s, a failed try (retried while tries are left)\n' \
    "$k" "$host" "$start" "$(awk -v a="$start" -v b="$end" 'BEGIN {{ print b - a }}')" "$st" \
    "$(cat "$spool/$k.what")" >>{joblog}
exit "$st"
"#
    )
}

// --- Slurm. -----------------------------------------------------------------------------

/// What the sbatch script needs.
#[derive(Clone, Debug)]
pub struct SlurmArray {
    /// The movie, a file (absolute).
    pub movie: PathBuf,
    /// Its frames, and the frames of a chunk (an array task).
    pub frames: u64,
    pub chunk: u64,
    /// `-o`'s pattern (absolute) and `--first-frame`.
    pub pattern: String,
    pub first_frame: u64,
    /// The `frames` binary (absolute).
    pub frames_bin: PathBuf,
    /// The command that renders a movie on stdin (`env POLYPIPE_BIN=… …/render.sh OPTIONS
    /// -`), to which each task adds `-o PATTERN --first-frame A`.
    pub command: Vec<String>,
    /// Where Slurm writes each task's output.
    pub dir: PathBuf,
}

/// The array tasks needed: ⌈frames / chunk⌉.
pub fn array_tasks(frames: u64, chunk: u64) -> u64 {
    frames.div_ceil(chunk.max(1))
}

/// `DIR/render.sbatch`: array task k renders frames k·N to k·N + N − 1 of the whole movie
/// (`frames --from A --to B MOVIE | render … -o PATTERN --first-frame A`); run with
/// `--check` (a job that depends on the array, or by hand) it lists the frames missing
/// and fails when any is.
pub fn sbatch_script(s: &SlurmArray) -> String {
    let tasks = array_tasks(s.frames, s.chunk);
    let q = |p: &Path| quote(&p.display().to_string());
    let mut render = String::new();
    for w in &s.command {
        render.push_str(&quote(w));
        render.push(' ');
    }
    format!(
        r#"#!/bin/bash
# A movie's frames as a Slurm job array, written by farm (render.sh --by frames
# --slurm-array): task k renders chunk k, frames k*{chunk} to k*{chunk}+{last}, the
# frame numbers of the whole movie.
#
#   jid=$(sbatch --parsable {script})
#   sbatch --dependency=afterok:$jid --wrap 'bash {script} --check'
#
# Locally, as Slurm would: for k in $(seq 0 {max}); do SLURM_ARRAY_TASK_ID=$k bash {script}; done
#SBATCH --job-name=polypipe-frames
#SBATCH --array=0-{max}
#SBATCH --output={dir}/slurm-%A_%a.out
set -euo pipefail
movie={movie}
pattern={pattern}
frames={frames} chunk={chunk} first={first}
if [[ ${{1-}} == --check ]]; then
    missing=0
    for ((i = 0; i < frames; i++)); do
        # shellcheck disable=SC2059 # the pattern is the format: %d, %0Nd, %%
        printf -v file "$pattern" $((first + i))
        [[ -s $file ]] || {{ echo "render.sbatch: frame $i missing: $file" >&2; missing=$((missing + 1)); }}
    done
    ((missing == 0)) || {{ echo "render.sbatch: $missing of $frames frames missing" >&2; exit 1; }}
    echo "render.sbatch: all $frames frames there"
    exit 0
fi
k=${{SLURM_ARRAY_TASK_ID:?render.sbatch: run by sbatch --array, or with SLURM_ARRAY_TASK_ID=k, or --check}}
a=$((k * chunk))
b=$((a + chunk < frames ? a + chunk : frames))
((a < frames)) || {{ echo "render.sbatch: task $k is past the movie's $frames frames" >&2; exit 2; }}
{frames_bin} --from "$a" --to "$b" "$movie" | {render}-o "$pattern" --first-frame $((first + a))
"#,
        chunk = s.chunk,
        last = s.chunk - 1,
        max = tasks.saturating_sub(1),
        script = q(&s.dir.join("render.sbatch")),
        dir = q(&s.dir),
        movie = q(&s.movie),
        pattern = quote(&s.pattern),
        frames = s.frames,
        first = s.first_frame,
        frames_bin = q(&s.frames_bin),
    )
}

/// Counts the movie's frames (cutting it as [`Cutter`] does, holding a chunk at a time).
pub fn count_frames<R: Read>(reader: Reader<Token, R>) -> Result<u64> {
    let mut cutter = Cutter::new(reader, 64)?;
    while cutter.next_chunk()?.is_some() {}
    Ok(cutter.frames_so_far())
}

// --- Running it. ----------------------------------------------------------------------

/// What the run needs besides the movie.
#[derive(Clone, Debug)]
pub struct Options {
    pub logins: Logins,
    /// The command that reaches a host: `SSH… HOST COMMAND` (`POLYPIPE_SSH`).
    pub ssh: Vec<String>,
    /// The command line run on a host, for a POSIX shell there: renders the movie on its
    /// stdin to PPM frames on its stdout.
    pub command: String,
    /// Frames a chunk.
    pub chunk: u64,
    /// Tries of a chunk (parallel's `--retries`).
    pub retries: u32,
    /// The job log; `None`: beside -o's files, or (frames on stdout) a temporary one.
    pub joblog: Option<PathBuf>,
    /// Render only the chunks the job log does not call finished.
    pub resume: bool,
    pub output: Output,
    /// Per host: the frames it rendered, the bytes each way, the time; each failed try.
    pub stats: bool,
    /// The movie's name in messages (`stdin` for `-`).
    pub scene: String,
    /// The parallel to run (`parallel`, found on PATH).
    pub parallel: PathBuf,
}

/// `parallel` on PATH, or the one line saying to install it (status 3).
pub fn find_parallel(path: Option<&std::ffi::OsStr>) -> Result<PathBuf> {
    let found = path.and_then(|p| {
        std::env::split_paths(p)
            .map(|d| d.join("parallel"))
            .find(|f| is_executable(f))
    });
    found.ok_or_else(|| {
        Error::io(
            "--by frames runs on GNU parallel, and there is no parallel on PATH: install it \
             (Debian and Ubuntu: apt install parallel)",
        )
    })
}

fn is_executable(path: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(path).is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
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

/// How the run ended, for main to report.
#[derive(Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Every frame written (or the reader of the frames went away: a quiet end).
    Done,
    /// Stopped by a signal (its number).
    Stopped(i32),
}

/// The signal that asked the run to stop (SIGINT or SIGTERM), 0 while none has.
static STOP: AtomicI32 = AtomicI32::new(0);

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
/// outlives its parent is handed to this process, not to init, and [`run`] stops and
/// reaps every such process before it returns. GNU parallel stops its jobs by process
/// group when asked to stop, but a job it is starting at that moment (forked, not yet in
/// its table of running jobs) escapes that and goes on: its ssh and the session on the
/// host outlived the run about one stop in six. Call it once, from the program's main,
/// before [`run`]: a process that adopts must know all its children.
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

/// A chunk of the movie, handed to parallel or skipped as finished before.
struct Handed {
    info: ChunkInfo,
    /// Its job number (its argument line's, from 1); `None` when skipped.
    seq: Option<usize>,
    /// Its frames taken (checked, and written or held), or skipped as finished before.
    taken: bool,
    /// Its frames written (to -o's files or to stdout), or skipped.
    written: bool,
    /// Its frames, held in the spool for stdout until its turn.
    held: Option<PathBuf>,
    /// The host of the try that rendered it, and that try's stderr.
    host: Option<String>,
    stderr: String,
    sent: u64,
    received: u64,
}

/// Per host, for --stats.
#[derive(Default)]
struct HostStats {
    chunks: Vec<ChunkInfo>,
    sent: u64,
    received: u64,
    busy: f64,
}

/// Renders the movie `reader` reads on the hosts through GNU parallel, writing the
/// frames to `out` in order (or to -o's files). The hosts' own stderr lines, labelled
/// with the host, and `--stats` go to `log`; a failure's message is the error returned.
pub fn run<R, W>(
    reader: Reader<Token, R>,
    options: &Options,
    out: &mut W,
    log: &mut dyn Write,
) -> Result<Outcome>
where
    R: Read + Send + 'static,
    W: Write,
{
    if options.ssh.is_empty() {
        return Err(Error::usage("POLYPIPE_SSH names no command"));
    }
    let slots = match &options.logins {
        Logins::List(l) if l.is_empty() => {
            return Err(Error::usage("--hosts must name at least one host"))
        }
        Logins::List(l) => l.iter().map(|(n, _)| n).sum(),
        Logins::File(f) => {
            let text = std::fs::read_to_string(f).map_err(|e| {
                Error::io(format!(
                    "cannot read --sshloginfile {}: {}",
                    f.display(),
                    stagecli::error::io_message(&e)
                ))
            })?;
            match slots_in_sshloginfile(&text) {
                0 => {
                    return Err(Error::usage(format!(
                        "--sshloginfile {} names no host",
                        f.display()
                    )))
                }
                n => n,
            }
        }
    };
    let joblog_given = joblog_path(options.joblog.as_deref(), &options.output);
    let mut finished = BTreeSet::new();
    if options.resume {
        let Some(path) = &joblog_given else {
            return Err(Error::usage(
                "--resume needs -o: frames written to stdout by an earlier run are not kept",
            ));
        };
        let text = std::fs::read_to_string(path).map_err(|e| {
            Error::io(format!(
                "--resume: cannot read the job log {}: {}",
                path.display(),
                stagecli::error::io_message(&e)
            ))
        })?;
        finished = finished_chunks(&parse_joblog(&text));
    }
    let mut cutter = Cutter::new(reader, options.chunk).map_err(|e| e.context(&options.scene))?;

    let spool = tempfile::Builder::new()
        .prefix("farm.")
        .tempdir()
        .map_err(|e| Error::io(format!("cannot make a spool folder in $TMPDIR: {e}")))?;
    let dir = spool.path().to_path_buf();
    let joblog = joblog_given.clone().unwrap_or_else(|| dir.join("joblog"));
    if !options.resume {
        std::fs::write(&joblog, JOBLOG_HEADER).map_err(|e| {
            Error::io(format!(
                "cannot write the job log {}: {}",
                joblog.display(),
                stagecli::error::io_message(&e)
            ))
        })?;
    }
    let joblog_from = count_bytes(&joblog) as usize;
    let shim = dir.join("ssh");
    let spool_io = |e: std::io::Error| {
        Error::io(format!(
            "cannot write to the spool {}: {}",
            dir.display(),
            stagecli::error::io_message(&e)
        ))
    };
    std::fs::write(&shim, shim_script(&dir, &options.ssh, &joblog)).map_err(spool_io)?;
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&shim, std::fs::Permissions::from_mode(0o700))
            .map_err(spool_io)?;
    }

    let mut parallel = Command::new(&options.parallel);
    parallel
        .arg("-j1")
        .arg("--retries")
        .arg(options.retries.max(1).to_string())
        .arg("--halt")
        .arg("soon,fail=1")
        .arg("--joblog")
        .arg(format!("+{}", joblog.display()))
        .arg("--tmpdir")
        .arg(&dir)
        .arg("--ssh")
        .arg(&shim);
    match &options.logins {
        Logins::List(l) => {
            for (n, host) in l {
                parallel.arg("--sshlogin").arg(format!("{n}/{host}"));
            }
        }
        Logins::File(f) => {
            parallel.arg("--sshloginfile").arg(f);
        }
    }
    // The chunk's frames ride in the command as a comment, for the job log.
    parallel.arg(format!("{} # {{}}", options.command));
    let parallel_err = std::fs::File::create(dir.join("parallel.err")).map_err(spool_io)?;
    let mut child = parallel
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(parallel_err)
        .spawn()
        .map_err(|e| {
            Error::io(format!(
                "cannot run {}: {}",
                options.parallel.display(),
                stagecli::error::io_message(&e)
            ))
        })?;
    let mut args = child.stdin.take();

    // The movie is read in a thread of its own, a chunk ahead at most.
    let (chunks_tx, chunks_rx) = mpsc::sync_channel::<Result<Option<Chunk>>>(0);
    {
        let scene = options.scene.clone();
        std::thread::spawn(move || loop {
            let next = cutter.next_chunk().map_err(|e| e.context(&scene));
            let last = !matches!(next, Ok(Some(_)));
            if chunks_tx.send(next).is_err() || last {
                break;
            }
        });
    }

    debug_assert!(slots > 0);
    let bound = spool_bound(slots);
    let mut handed: Vec<Handed> = Vec::new();
    let mut lines = 0; // argument lines handed: the last one's job number
    let mut by_seq: BTreeMap<usize, usize> = BTreeMap::new(); // job number → chunk
    let mut ends_at_last_line = 0;
    let mut head = 0; // the earliest chunk not yet written
    let mut input_done = false;
    let mut ended: Option<std::process::ExitStatus> = None;
    let result: Result<Outcome> = loop {
        // Hand parallel the next chunks while fewer than `bound` are in the spool.
        let mut cut_error = None;
        while !input_done && in_spool(&handed[head..]) < bound {
            let chunk = match chunks_rx.try_recv() {
                Ok(Ok(Some(chunk))) => chunk,
                Ok(Ok(None)) | Err(mpsc::TryRecvError::Disconnected) => {
                    input_done = true;
                    args = None; // no more chunks: parallel's input ends
                    break;
                }
                Ok(Err(e)) => {
                    cut_error = Some(e);
                    break;
                }
                Err(mpsc::TryRecvError::Empty) => break,
            };
            let info = ChunkInfo {
                first: chunk.first,
                frames: chunk.frames,
            };
            let mut h = Handed {
                info,
                seq: None,
                taken: true,
                written: true,
                held: None,
                host: None,
                stderr: String::new(),
                sent: chunk.bytes.len() as u64,
                received: 0,
            };
            if !finished.contains(&info) {
                let seq = lines + 1;
                let wrote =
                    std::fs::write(dir.join(format!("{seq}.in")), &chunk.bytes).and_then(|()| {
                        std::fs::write(
                            dir.join(format!("{seq}.what")),
                            frames_text(info.first, info.frames),
                        )
                    });
                if let Err(e) = wrote {
                    cut_error = Some(spool_io(e));
                    break;
                }
                h.seq = Some(seq);
                h.taken = false;
                h.written = false;
                by_seq.insert(seq, handed.len());
                hand(&mut args, &chunk_arg(info));
                lines = seq;
                ends_at_last_line = count_bytes(&dir.join("ends"));
            }
            handed.push(h);
        }
        if let Some(e) = cut_error {
            break Err(e);
        }
        // parallel reads its next argument as soon as its queue has none, and does
        // nothing else until it comes: a try that failed is neither reaped nor retried
        // meanwhile. So when the spool is full, nothing runs, and a job has ended since
        // the last line (parallel may be waiting for one), an idle job wakes it: it
        // contacts no host and adds nothing to the spool.
        if !input_done && in_spool(&handed[head..]) >= bound {
            let ends = count_bytes(&dir.join("ends"));
            let running = count_bytes(&dir.join("starts")).saturating_sub(ends);
            if running == 0 && ends != ends_at_last_line {
                let seq = lines + 1;
                if let Err(e) = std::fs::write(dir.join(format!("{seq}.idle")), "") {
                    break Err(spool_io(e));
                }
                hand(&mut args, IDLE_ARG);
                lines = seq;
                ends_at_last_line = ends;
            }
        }
        // The chunks that came back: checked, then written (files) or held (stdout).
        let mut fatal = None;
        for h in handed.iter_mut().skip(head) {
            let (false, Some(seq)) = (h.taken, h.seq) else {
                continue;
            };
            let landed = dir.join(format!("{seq}.out"));
            let Ok(file) = std::fs::File::open(&landed) else {
                continue;
            };
            let received = file.metadata().map(|m| m.len()).unwrap_or(0);
            let checked = check_frames(&mut BufReader::new(file), h.info);
            let verdict = match checked {
                Ok(frames) => {
                    let mut written = Ok(());
                    match &options.output {
                        // Kept in the spool until its turn: the frames of one chunk are
                        // in memory at a time.
                        Output::Stdout => {
                            let held = dir.join(format!("{seq}.held"));
                            written = std::fs::hard_link(&landed, &held).map_err(spool_io);
                            h.held = Some(held);
                        }
                        output => {
                            for (i, f) in frames.iter().enumerate() {
                                written = output.save(h.info.first + i as u64, f);
                                if written.is_err() {
                                    break;
                                }
                            }
                            h.written = written.is_ok();
                        }
                    }
                    if let Err(e) = written {
                        // A file that cannot be written is ours to report, not a host's.
                        let _ = std::fs::write(dir.join(format!("{seq}.bad")), e.message());
                        let _ = std::fs::remove_file(&landed);
                        fatal = Some(e);
                        break;
                    }
                    h.taken = true;
                    h.received = received;
                    h.host = std::fs::read_to_string(dir.join(format!("{seq}.host")))
                        .ok()
                        .map(|s| s.trim().to_string());
                    h.stderr =
                        std::fs::read_to_string(dir.join(format!("{seq}.err"))).unwrap_or_default();
                    let _ = std::fs::remove_file(dir.join(format!("{seq}.in")));
                    std::fs::write(dir.join(format!("{seq}.ok")), "")
                }
                Err(why) => std::fs::write(dir.join(format!("{seq}.bad")), format!("{why}\n")),
            };
            if let Err(e) = verdict {
                fatal = Some(spool_io(e));
                break;
            }
            let _ = std::fs::remove_file(&landed);
        }
        if let Some(e) = fatal {
            break Err(e);
        }
        // The chunks whose turn has come.
        let mut gone = false;
        let mut written_error = None;
        while head < handed.len() && handed[head].taken {
            if let Some(held) = handed[head].held.take() {
                let frames = std::fs::File::open(&held).map_err(spool_io).and_then(|f| {
                    check_frames(&mut BufReader::new(f), handed[head].info).map_err(Error::io)
                });
                let _ = std::fs::remove_file(&held);
                let frames = match frames {
                    Ok(f) => f,
                    Err(e) => {
                        written_error = Some(e);
                        break;
                    }
                };
                match write_frames(out, &frames) {
                    Ok(true) => {}
                    Ok(false) => gone = true,
                    Err(e) => {
                        written_error = Some(e);
                        break;
                    }
                }
                handed[head].written = true;
            }
            head += 1;
        }
        if let Some(e) = written_error {
            break Err(e);
        }
        if gone {
            break Ok(Outcome::Done); // the reader went away: a quiet end
        }
        if input_done && head == handed.len() {
            break Ok(Outcome::Done);
        }
        let sig = STOP.load(Ordering::SeqCst);
        if sig != 0 {
            break Ok(Outcome::Stopped(sig));
        }
        if let Some(status) = ended {
            // parallel has ended with chunks not rendered. The failure is the chunk that
            // failed on its last try (`--halt soon` stops there, after the jobs running
            // then end), not an earlier one left with a try to go; else the earliest.
            let pending: Vec<(usize, usize)> = handed[head..]
                .iter()
                .filter(|h| !h.taken)
                .filter_map(|h| Some((h.seq?, tries_of(&dir, h.seq?).len())))
                .collect();
            let failed = failed_chunk(&pending, options.retries.max(1) as usize);
            let h = failed
                .and_then(|seq| by_seq.get(&seq))
                .and_then(|&k| handed.get(k))
                .or(handed.get(head));
            let (seq, info) = (h.and_then(|h| h.seq), h.map(|h| h.info));
            break Err(failure_of(&dir, seq, info, status, log));
        }
        match child.try_wait() {
            Ok(Some(status)) => ended = Some(status), // one more look at what came back
            Ok(None) => std::thread::sleep(Duration::from_millis(10)),
            Err(e) => break Err(Error::io(format!("cannot wait for parallel: {e}"))),
        }
    };
    drop(args);
    let _ = out.flush();
    let all_written = input_done && head == handed.len();
    if let (Ok(Outcome::Done), true) = (&result, all_written) {
        report(&handed, &by_seq, options, (&joblog, joblog_from), log);
    }
    finish(child, spool, all_written, result)
}

/// The chunks the spool holds at most (their streams, or their frames waiting for their
/// turn on stdout): two a job slot, so that each host has a chunk to start as soon as it
/// finishes one while the writer waits for an earlier chunk.
pub fn spool_bound(slots: usize) -> usize {
    2 * slots.max(1)
}

/// The chunks of `from` whose stream or frames are in the spool: handed and not yet
/// written.
fn in_spool(from: &[Handed]) -> usize {
    from.iter().filter(|h| !h.written).count()
}

/// Hands parallel an argument line; when it has gone, its end says why.
fn hand(args: &mut Option<std::process::ChildStdin>, line: &str) {
    if let Some(a) = args {
        if writeln!(a, "{line}").and_then(|()| a.flush()).is_err() {
            *args = None;
        }
    }
}

/// The bytes of a file (0 when there is none): the jobs' count of their starts and ends.
fn count_bytes(path: &Path) -> u64 {
    std::fs::metadata(path).map_or(0, |m| m.len())
}

/// Writes frames to stdout: Ok(true) done, Ok(false) when the reader has gone away
/// (`| head`), an error for any other failure to write.
fn write_frames<W: Write>(out: &mut W, frames: &[Frame]) -> Result<bool> {
    let mut written = Ok(());
    for f in frames {
        written = out.write_all(&f.ppm());
        if written.is_err() {
            break;
        }
    }
    match written.and_then(|()| out.flush()) {
        Ok(()) => Ok(true),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(false),
        Err(e) => Err(Error::io(format!(
            "cannot write the frames to stdout: {}",
            stagecli::error::io_message(&e)
        ))),
    }
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
fn tries_of(dir: &Path, seq: usize) -> Vec<(Try, String)> {
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
fn failure_of(
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

/// Waits for parallel, which ends by itself once every frame is written (`all_written`:
/// its input has ended and every job has), else stops it (SIGINT: it stops its jobs and
/// ends; then SIGTERM and SIGKILL if it lingers); removes the spool, and returns
/// `result`.
fn finish(
    mut child: Child,
    spool: tempfile::TempDir,
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
    drop(spool);
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

/// On success: the hosts' own stderr lines (their --stats), labelled with the host, in
/// the movie's order; with --stats, each host's part and each failed try.
fn report(
    handed: &[Handed],
    by_seq: &BTreeMap<usize, usize>,
    options: &Options,
    joblog: (&Path, usize),
    log: &mut dyn Write,
) {
    for h in handed {
        let host = h.host.as_deref().unwrap_or("?");
        for line in h.stderr.lines() {
            let line = stagecli::remote::without_render_prefix(line);
            let _ = writeln!(log, "host {host}: {line}");
        }
    }
    if !options.stats {
        return;
    }
    // This run's lines: those after the log's length when it started.
    let text = std::fs::read(joblog.0).unwrap_or_default();
    let lines = parse_joblog(&String::from_utf8_lossy(
        text.get(joblog.1..).unwrap_or_default(),
    ));
    let mut hosts: BTreeMap<String, HostStats> = BTreeMap::new();
    let mut order: Vec<String> = match &options.logins {
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
            .find(|l| l.seq == seq && l.exit == 0 && l.signal == 0)
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
        if let Some(h) = by_seq.get(&l.seq).and_then(|&k| handed.get(k)) {
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

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A text movie of `n` frames, frame k one triangle of colour (k, 0, 0).
    fn movie(n: u64) -> String {
        let frames: Vec<String> = (0..n)
            .map(|k| format!("colour {k} 0 0\n0 0 0\n1 0 0\n0 1 0\n"))
            .collect();
        format!("polypipe 1 world\n{}END\n", frames.join("NEXT.FRAME\n"))
    }

    fn chunks(n: u64, size: u64) -> Vec<Chunk> {
        let text = movie(n);
        let reader = Reader::<Token, _>::new(std::io::Cursor::new(text.into_bytes())).unwrap();
        let mut cutter = Cutter::new(reader, size).unwrap();
        let mut out = Vec::new();
        while let Some(c) = cutter.next_chunk().unwrap() {
            out.push(c);
        }
        out
    }

    /// A chunk's frames, each as its colour's red.
    fn reds(chunk: &Chunk) -> Vec<u8> {
        let mut reader = Reader::<Token, _>::new(&chunk.bytes[..]).unwrap();
        let mut reds = Vec::new();
        let mut ends = 0;
        while let Some(t) = reader.next_record().unwrap() {
            match t {
                Token::Polygon(p) => reds.push(p.colour[0]),
                Token::End => ends += 1,
                _ => {}
            }
        }
        assert_eq!(ends, 1, "a chunk ends with one END");
        reds
    }

    #[test]
    fn a_movie_is_cut_into_chunks_that_are_movies_of_their_own() {
        let c = chunks(7, 3);
        let places: Vec<(usize, u64, u64)> =
            c.iter().map(|c| (c.index, c.first, c.frames)).collect();
        assert_eq!(places, [(0, 0, 3), (1, 3, 3), (2, 6, 1)]);
        assert_eq!(reds(&c[0]), [0, 1, 2]);
        assert_eq!(reds(&c[1]), [3, 4, 5]);
        assert_eq!(reds(&c[2]), [6]);
        // One chunk of the whole movie when it is no longer than a chunk.
        let c = chunks(2, 8);
        assert_eq!((c.len(), c[0].frames), (1, 2));
    }

    #[test]
    fn a_fragment_stream_is_refused() {
        let reader = Reader::<Token, _>::new(&b"polypipe 2 fragments 4 4\nEND\n"[..]).unwrap();
        let err = Cutter::new(reader, 4).err().unwrap();
        assert_eq!(err.kind(), stagecli::Kind::Data);
        assert_eq!(
            err.to_string(),
            "a fragment stream; the hosts render polygon streams (world, eye or screen)"
        );
    }

    #[test]
    fn hosts_named_twice_have_two_job_slots() {
        assert_eq!(
            logins_from_hosts("a,b,a").unwrap(),
            [(2, "a".to_string()), (1, "b".to_string())]
        );
        assert!(logins_from_hosts("a,,b").is_err());
        assert_eq!(
            slots_in_sshloginfile("# farm\n4/alpha\nbeta\n\n2/ssh -p 2222 gamma\n"),
            7
        );
    }

    proptest! {
        /// Cut at any chunk size, the chunks' frames are the movie's, each once, in
        /// order, and every chunk but the last has the size asked for.
        #[test]
        fn chunks_join_to_the_movie(n in 1u64..20, size in 1u64..8) {
            let c = chunks(n, size);
            let all: Vec<u8> = c.iter().flat_map(reds).collect();
            prop_assert_eq!(all, (0..n as u8).collect::<Vec<_>>());
            for (i, chunk) in c.iter().enumerate() {
                prop_assert_eq!(chunk.first, i as u64 * size);
                if i + 1 < c.len() {
                    prop_assert_eq!(chunk.frames, size);
                }
            }
        }
    }

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

    #[test]
    fn what_came_back_is_checked_frame_by_frame() {
        let frame = |r: u8| [b"P6\n1 1\n255\n".as_slice(), &[r, 0, 0]].concat();
        let chunk = ChunkInfo {
            first: 8,
            frames: 2,
        };
        let two = [frame(1), frame(2)].concat();
        let got = check_frames(&mut &two[..], chunk).unwrap();
        assert_eq!(got.iter().map(|f| f.rgb[0]).collect::<Vec<_>>(), [1, 2]);
        assert_eq!(
            check_frames(&mut &b""[..], chunk).unwrap_err(),
            "sent back nothing for its frames 8 to 9"
        );
        assert_eq!(
            check_frames(&mut &frame(1)[..], chunk).unwrap_err(),
            "sent back 1 of its frames 8 to 9"
        );
        let three = [frame(1), frame(2), frame(3)].concat();
        assert_eq!(
            check_frames(&mut &three[..], chunk).unwrap_err(),
            "sent back 3 frames for its frames 8 to 9"
        );
        let cut = [frame(1), b"P6\n1 1\n255\n\x01".to_vec()].concat();
        assert!(check_frames(&mut &cut[..], chunk)
            .unwrap_err()
            .starts_with("sent back 1 of its frames 8 to 9, then what is not a frame: "));
    }

    #[test]
    fn a_chunk_that_failed_every_try_is_one_line() {
        let chunk = ChunkInfo {
            first: 16,
            frames: 8,
        };
        let t = |host: &str, message: &str, status| Try {
            host: host.to_string(),
            failure: Failure {
                message: message.to_string(),
                status,
            },
        };
        let one = every_try_failed(chunk, &[t("bad", "ssh: x", 3), t("bad", "ssh: y", 3)]);
        assert_eq!(
            (one.message.as_str(), one.status),
            ("host bad: frames 16 to 23, 2 tries: ssh: y", 3)
        );
        let two = every_try_failed(
            chunk,
            &[
                t("a", "ssh: x", 3),
                t("b", "viewxf: stdin: line 3: not a number", 1),
            ],
        );
        assert_eq!(
            (two.message.as_str(), two.status),
            (
                "hosts a, b: frames 16 to 23, 2 tries, the last on b: viewxf: stdin: line 3: \
                 not a number",
                1
            )
        );
    }

    #[test]
    fn how_a_try_ended_is_told_in_one_line() {
        assert_eq!(classify(0, "render.sh: zbuf: 3 frames\n"), None);
        let ssh = classify(255, "ssh: connect to host x port 22: Connection refused\n").unwrap();
        assert_eq!(
            (ssh.message.as_str(), ssh.status),
            ("ssh: connect to host x port 22: Connection refused", 3)
        );
        let far = classify(1, "render.sh: viewxf: stdin: line 3: not a number\n").unwrap();
        assert_eq!(
            (far.message.as_str(), far.status),
            ("viewxf: stdin: line 3: not a number", 1)
        );
        let killed = classify(128 + libc::SIGKILL, "").unwrap();
        assert_eq!(
            (killed.message.as_str(), killed.status),
            ("ssh was killed by SIGKILL", 3)
        );
    }

    #[test]
    fn the_sbatch_script_renders_chunk_k_with_the_movies_numbers() {
        let s = sbatch_script(&SlurmArray {
            movie: "/m/movie.pp".into(),
            frames: 60,
            chunk: 16,
            pattern: "/out/f%05d.png".into(),
            first_frame: 0,
            frames_bin: "/bin/frames".into(),
            command: vec![
                "/r/render.sh".into(),
                "--size".into(),
                "32x32".into(),
                "-".into(),
            ],
            dir: "/out".into(),
        });
        assert!(s.contains("#SBATCH --array=0-3\n"), "{s}");
        assert!(s.contains("frames=60 chunk=16 first=0\n"), "{s}");
        assert!(
            s.contains(
                "'/bin/frames' --from \"$a\" --to \"$b\" \"$movie\" | '/r/render.sh' '--size' \
             '32x32' '-' -o \"$pattern\" --first-frame $((first + a))\n"
            ),
            "{s}"
        );
        assert_eq!(array_tasks(60, 16), 4);
        assert_eq!(array_tasks(64, 16), 4);
    }
}
