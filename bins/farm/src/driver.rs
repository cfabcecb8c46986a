//! The GNU parallel driver: the chunks handed to parallel, their frames taken back in
//! order.

use crate::checks::{check_frames, frames_text, ChunkInfo, Frame, Output};
use crate::cutter::{Chunk, Cutter};
use crate::files::make_folder;
use crate::hosts::{login_lines, slots_in_sshloginfile, Logins};
use crate::joblog::{chunk_arg, joblog_path, IDLE_ARG, JOBLOG_HEADER};
use crate::report::report;
use crate::resume::resume;
use crate::shim::shim_script;
use crate::spool::{
    count_bytes, failed_chunk, failure_of, in_spool, spool_bound, tries_of, Handed,
};
use crate::supervise::{finish, Outcome, STOP};
use crate::watch::{HostWatch, HOSTS_FILE};
use proto::{Reader, Token};
use stagecli::whole::write_whole;
use stagecli::{Error, Result};
use std::collections::{BTreeMap, BTreeSet};
use std::io::{BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::Ordering;
use std::sync::mpsc;
use std::time::Duration;

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
    /// Failed tries in a row after which a host gets no more chunks.
    pub host_failures: u32,
    /// Seconds a host may send nothing before its try fails (0: for ever).
    pub host_timeout: u64,
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
    let mut login_text = None;
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
            let n = slots_in_sshloginfile(&text);
            if n == 0 {
                return Err(Error::usage(format!(
                    "--sshloginfile {} names no host",
                    f.display()
                )));
            }
            login_text = Some(text);
            n
        }
    };
    let joblog_given = joblog_path(options.joblog.as_deref(), &options.output);
    if let Output::Files { pattern, .. } = &options.output {
        make_folder(
            Path::new(pattern).parent().unwrap_or(Path::new("")),
            "-o's folder",
        )?;
    }
    let mut finished = BTreeSet::new();
    let mut seq0 = 0;
    let mut fresh_log = !options.resume;
    if options.resume {
        let Some(path) = &joblog_given else {
            return Err(Error::usage(
                "--resume needs -o: frames written to stdout by an earlier run are not kept",
            ));
        };
        let resumed = resume(path, &options.output, log)?;
        (finished, seq0, fresh_log) = (resumed.finished, resumed.seq0, !resumed.found);
    }
    let mut cutter = Cutter::new(reader, options.chunk).map_err(|e| e.context(&options.scene))?;

    let spool = tempfile::Builder::new()
        .prefix("farm.")
        .tempdir()
        .map_err(|e| Error::io(format!("cannot make a spool folder in $TMPDIR: {e}")))?;
    let dir = spool.path().to_path_buf();
    let joblog = joblog_given.clone().unwrap_or_else(|| dir.join("joblog"));
    if fresh_log {
        // The message names the file: `cannot write PATH: why`.
        write_whole(&joblog, JOBLOG_HEADER.as_bytes())
            .map_err(|e| Error::from(e).context("the job log"))?;
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
    std::fs::write(dir.join("seq0"), seq0.to_string()).map_err(spool_io)?;
    let mut watch = HostWatch::new(
        login_lines(&options.logins, login_text.as_deref()),
        options.host_failures,
        options.host_timeout,
    );
    watch.write_hosts(&dir)?;
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&shim, std::fs::Permissions::from_mode(0o700))
            .map_err(spool_io)?;
    }

    let mut parallel = Command::new(&options.parallel);
    parallel
        .arg("--retries")
        .arg(options.retries.max(1).to_string())
        .arg("--halt")
        .arg("soon,fail=1")
        .arg("--tmpdir")
        .arg(&dir)
        .arg("--ssh")
        .arg(&shim);
    // parallel reads its sshlogin file again when it changes: a host dropped from it
    // gets no more chunks. The chunk's frames ride in the command as a comment, for
    // the job log.
    parallel
        .arg("--sshloginfile")
        .arg(dir.join(HOSTS_FILE))
        .arg(format!("{} # {{}}", options.command));
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
                let wrote = std::fs::write(dir.join(format!("{seq}.in")), &chunk.bytes)
                    .and_then(|()| {
                        std::fs::write(
                            dir.join(format!("{seq}.what")),
                            frames_text(info.first, info.frames),
                        )
                    })
                    .and_then(|()| {
                        std::fs::write(
                            dir.join(format!("{seq}.cmd")),
                            format!("{} # {}", options.command, chunk_arg(info)),
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
        // A host's first failure named, a host failing again and again dropped, a
        // silent one stopped.
        let running: Vec<usize> = handed[head..]
            .iter()
            .filter(|h| !h.taken)
            .filter_map(|h| h.seq)
            .collect();
        if let Err(e) = watch.poll(&dir, &running, log) {
            break Err(e);
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
    let result = finish(child, all_written, result);
    if let (Ok(Outcome::Done), true) = (&result, all_written) {
        let joblog = (joblog.as_path(), joblog_from, seq0);
        report(
            &handed,
            &by_seq,
            (&options.logins, options.stats),
            joblog,
            log,
        );
    }
    drop(spool);
    result
}

/// Hands parallel an argument line; when it has gone, its end says why.
fn hand(args: &mut Option<std::process::ChildStdin>, line: &str) {
    if let Some(a) = args {
        if writeln!(a, "{line}").and_then(|()| a.flush()).is_err() {
            *args = None;
        }
    }
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
