//! # farm: a movie's frames rendered on other hosts, written back in order as they come
//!
//! A movie is `frame { NEXT.FRAME frame } END` (Theoharis 1985, Appendix 1; the stream's
//! grammar in docs/DESIGN.md), and its frames are independent: a run of them is a movie
//! of its own, and rendering the runs one after another gives the frames of the whole.
//! `render.sh --hosts H1,H2,… --by frames` runs this program, which
//!
//! 1. cuts the movie, as it reads it, into *chunks* of a few frames (`--chunk N`), each
//!    a movie of its own ([`Cutter`]);
//! 2. sends each chunk to a host that has nothing to do, over `$POLYPIPE_SSH HOST
//!    COMMAND` (ssh by default), to a render.sh there that renders it to PPM frames;
//! 3. writes the frames on stdout in the movie's order: those of the earliest chunk not
//!    yet written as they arrive, those of later chunks kept until their turn
//!    ([`InOrder`]).
//!
//! Nothing goes to disk here. What is held in memory is bounded by the frames of a few
//! chunks per host: a chunk is sent only while it is less than [`WINDOW_PER_HOST`]
//! chunks per host ahead of the earliest unwritten one, so a host that runs ahead waits
//! rather than filling memory, and a slow host holds up the others by at most that
//! much. A host named twice in `--hosts` renders two chunks at once.
//!
//! The first host to fail (cannot be reached, refuses the command, lacks the programs,
//! drops mid-run, or sends back fewer frames than it was given, nothing included) stops
//! the others, and the run ends with one line naming the host and what failed
//! ([`Failure`]), status 3 for the host or the link, the far render.sh's own status (1
//! or 2) for a fault it found in the movie or the options. The frames written before
//! are whole and the movie's first. SIGINT and SIGTERM stop the hosts' sessions too, and
//! the run ends with 130 or 143, as render.sh does.

use proto::codec::{Control, Record};
use proto::{Form, Reader, SpaceKind, Token, Writer};
use stagecli::{Error, Result};
use std::collections::VecDeque;
use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
use std::time::{Duration, Instant};

/// How far ahead of the earliest unwritten chunk the chunks sent may run: this many per
/// host (each `--hosts` entry), so that every host has its next chunk while the
/// earliest is still being rendered, and no more.
pub const WINDOW_PER_HOST: usize = 2;

/// The frames of a chunk by default: few enough that memory holds a few per host, and
/// enough that an ssh session's start (a connection, a render.sh and its choice of
/// depth there) is paid once for several frames.
pub const DEFAULT_CHUNK: u64 = 8;

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

// --- Putting the frames back in order. --------------------------------------------------

/// The frames of the chunks sent, written in the movie's order: the earliest chunk not
/// yet written (the *head*) as its frames arrive, the others kept until their turn.
#[derive(Debug, Default)]
pub struct InOrder {
    head: usize,
    /// Per chunk from the head on: frames kept, and whether the chunk has ended well.
    pending: VecDeque<(Vec<Vec<u8>>, bool)>,
}

impl InOrder {
    pub fn new() -> Self {
        Self::default()
    }

    /// The earliest chunk not wholly written.
    pub fn head(&self) -> usize {
        self.head
    }

    fn slot(&mut self, chunk: usize) -> &mut (Vec<Vec<u8>>, bool) {
        debug_assert!(chunk >= self.head, "chunk {chunk} was already written");
        let i = chunk - self.head;
        while self.pending.len() <= i {
            self.pending.push_back((Vec::new(), false));
        }
        &mut self.pending[i]
    }

    /// A frame of `chunk` has arrived: written at once when `chunk` is the head, else
    /// kept. Returns the frames to write now, in order.
    pub fn frame(&mut self, chunk: usize, frame: Vec<u8>) -> Vec<Vec<u8>> {
        if chunk == self.head {
            vec![frame]
        } else {
            self.slot(chunk).0.push(frame);
            Vec::new()
        }
    }

    /// `chunk` has ended with all its frames sent back. Returns the frames that can be
    /// written now, in order: those kept of the chunks after it that became the head.
    pub fn ended(&mut self, chunk: usize) -> Vec<Vec<u8>> {
        self.slot(chunk).1 = true;
        let mut out = Vec::new();
        while self.pending.front().is_some_and(|(_, done)| *done) {
            self.pending.pop_front();
            self.head += 1;
            if let Some((frames, _)) = self.pending.front_mut() {
                out.append(frames);
            }
        }
        out
    }

    /// The frames held in memory, not yet written.
    pub fn held(&self) -> usize {
        self.pending.iter().map(|(f, _)| f.len()).sum()
    }
}

// --- How a host's session ended. ------------------------------------------------------

pub use stagecli::remote::{last_line, Failure};

/// What a session that ended with `status` (the ssh's: the far command's, 255 for ssh's
/// own failure, `None` when killed by a signal `signal`) and `stderr` means
/// ([`stagecli::remote::classify`], the command there being render.sh's).
pub fn classify(status: Option<i32>, signal: Option<i32>, stderr: &str) -> Option<Failure> {
    stagecli::remote::classify(status, signal, stderr, "the command")
}

/// The frames of a chunk, for messages: `frames 8 to 11`, `frame 3`.
pub fn frames_text(first: u64, frames: u64) -> String {
    if frames == 1 {
        format!("frame {first}")
    } else {
        format!("frames {first} to {}", first + frames - 1)
    }
}

/// What a session that ended well but sent back `got` frames of the `want` it was given
/// means.
pub fn short_failure(got: u64, chunk: &ChunkInfo) -> Failure {
    let what = frames_text(chunk.first, chunk.frames);
    let message = if got == 0 {
        format!("sent back nothing for its {what}")
    } else {
        format!("sent back {got} of its {what}")
    };
    Failure { message, status: 3 }
}

// --- Running it. ----------------------------------------------------------------------

/// What the run needs besides the movie.
#[derive(Clone, Debug)]
pub struct Options {
    /// The hosts, one entry a session at a time (a host named twice runs two).
    pub hosts: Vec<String>,
    /// The command that runs a command on a host: `SSH… HOST COMMAND`.
    pub ssh: Vec<String>,
    /// The command line run on a host, for a POSIX shell there: renders the movie on its
    /// stdin to PPM frames on its stdout.
    pub command: String,
    /// Frames a chunk.
    pub chunk: u64,
    /// Per host: the frames it rendered, the bytes each way, the time.
    pub stats: bool,
    /// The movie's name in messages (`stdin` for `-`).
    pub scene: String,
}

/// A chunk's place, kept after its bytes are sent.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChunkInfo {
    pub first: u64,
    pub frames: u64,
}

pub use stagecli::remote::{parse_hosts, remote_command};

/// The signal that asked the run to stop (SIGINT or SIGTERM), 0 while none has.
static STOP: AtomicI32 = AtomicI32::new(0);

extern "C" fn on_signal(sig: libc::c_int) {
    STOP.store(sig, Ordering::SeqCst);
}

/// From now on SIGINT and SIGTERM ask the run to stop (the sessions are stopped and the
/// run ends with 128 + the signal) instead of ending it at once. A program run from here
/// gets the default actions back when it starts.
pub fn catch_stop_signals() {
    let handler = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
    // SAFETY: the handler only stores into an atomic, which is async-signal-safe.
    unsafe {
        libc::signal(libc::SIGINT, handler);
        libc::signal(libc::SIGTERM, handler);
    }
}

enum Event {
    /// The cutter's next chunk, or its end (`None`).
    Chunk(Result<Option<Chunk>>),
    /// A whole frame from a chunk's session.
    Frame(usize, Vec<u8>),
    /// A chunk's session has ended and been reaped.
    Ended(usize, Ended),
}

/// How a session ended, as its watcher saw it.
struct Ended {
    status: ExitStatus,
    stderr: String,
    /// The whole frames it sent back, and their bytes.
    frames: u64,
    bytes: u64,
    /// Why its output stopped being frames, if it did.
    bad_output: Option<String>,
}

/// Runs a chunk's session: its stream goes in from one thread, its stderr is read by
/// another, and its frames are read here, each sent on as it is whole; at the end of its
/// output the child is reaped and its end sent.
fn watch_session(mut child: Child, chunk: usize, input: Vec<u8>, events: Sender<Event>) {
    let stdin = child.stdin.take();
    let stdout = child.stdout.take();
    let stderr = child.stderr.take();
    std::thread::spawn(move || {
        if let Some(mut stdin) = stdin {
            // A session that stops reading (it failed, or was stopped) ends this early.
            let _ = stdin.write_all(&input);
        }
    });
    let err_reader = std::thread::spawn(move || {
        let mut text = String::new();
        if let Some(mut e) = stderr {
            let mut bytes = Vec::new();
            let _ = e.read_to_end(&mut bytes);
            text = String::from_utf8_lossy(&bytes).into_owned();
        }
        text
    });
    std::thread::spawn(move || {
        let mut frames = 0;
        let mut bytes = 0;
        let mut bad_output = None;
        if let Some(stdout) = stdout {
            let mut input = BufReader::with_capacity(1 << 16, stdout);
            loop {
                match next_frame(&mut input) {
                    Ok(Some(frame)) => {
                        frames += 1;
                        bytes += frame.len() as u64;
                        if events.send(Event::Frame(chunk, frame)).is_err() {
                            break;
                        }
                    }
                    Ok(None) => break,
                    Err(why) => {
                        bad_output = Some(why);
                        // Read the rest, so that the session is not stopped by us.
                        let _ = std::io::copy(&mut input, &mut std::io::sink());
                        break;
                    }
                }
            }
        }
        let stderr = err_reader.join().unwrap_or_default();
        let status = match child.wait() {
            Ok(s) => s,
            Err(_) => std::os::unix::process::ExitStatusExt::from_raw(1 << 8),
        };
        let _ = events.send(Event::Ended(
            chunk,
            Ended {
                status,
                stderr,
                frames,
                bytes,
                bad_output,
            },
        ));
    });
}

/// The next PPM frame of a session's output, as its bytes (`P6\nW H\n255\n` and W·H RGB
/// pixels, as zbuf writes them); `None` at the end; a message when it is not one.
pub fn next_frame<R: BufRead>(input: &mut R) -> std::result::Result<Option<Vec<u8>>, String> {
    match proto::ppm::read(input) {
        Ok(None) => Ok(None),
        Ok(Some(image)) => {
            let mut bytes = format!("P6\n{} {}\n255\n", image.width, image.height).into_bytes();
            bytes.reserve(image.pixels.len() * 3);
            for p in &image.pixels {
                bytes.extend_from_slice(p);
            }
            Ok(Some(bytes))
        }
        Err(e) => Err(e.to_string()),
    }
}

/// A session running a chunk.
struct Running {
    chunk: usize,
    slot: usize,
    pid: u32,
    started: Instant,
}

#[derive(Default, Clone)]
struct SlotStats {
    chunks: Vec<ChunkInfo>,
    sent: u64,
    received: u64,
    busy: Duration,
}

/// How the run ended, for main to report.
#[derive(Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Every frame written (or the reader of the frames went away: a quiet end).
    Done,
    /// Stopped by a signal (its number).
    Stopped(i32),
}

/// Renders the movie `reader` reads on the hosts, writing the frames to `out` in order.
/// The hosts' own stderr lines, labelled with the host, and `--stats` go to `log`; a
/// failure's message is the error returned (the lines its host wrote before it are on
/// `log` first).
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
    if options.hosts.is_empty() {
        return Err(Error::usage("--hosts must name at least one host"));
    }
    if options.ssh.is_empty() {
        return Err(Error::usage("POLYPIPE_SSH names no command"));
    }
    let mut cutter = Cutter::new(reader, options.chunk).map_err(|e| e.context(&options.scene))?;
    let (events, inbox) = mpsc::channel::<Event>();
    // The movie is read in a thread of its own, a chunk each time one is asked for, so
    // that a slow input holds up only the sending of chunks.
    let (ask, asked) = mpsc::channel::<()>();
    {
        let events = events.clone();
        let scene = options.scene.clone();
        std::thread::spawn(move || {
            while asked.recv().is_ok() {
                let next = cutter.next_chunk().map_err(|e| e.context(&scene));
                let last = !matches!(next, Ok(Some(_)));
                if events.send(Event::Chunk(next)).is_err() || last {
                    break;
                }
            }
        });
    }

    let mut state = State {
        options,
        events,
        busy: vec![false; options.hosts.len()],
        running: Vec::new(),
        chunks: Vec::new(),
        slot_of: Vec::new(),
        order: InOrder::new(),
        stats: vec![SlotStats::default(); options.hosts.len()],
        stderr: Vec::new(),
        notes: Vec::new(),
    };
    let window = WINDOW_PER_HOST * options.hosts.len();
    let mut asking = false;
    let mut input_done = false;

    let result: Result<Outcome> = loop {
        if !asking
            && !input_done
            && state.busy.contains(&false)
            && state.chunks.len() < state.order.head() + window
        {
            if ask.send(()).is_err() {
                break Err(Error::io("the movie's reader stopped"));
            }
            asking = true;
        }
        if input_done && state.order.head() == state.chunks.len() {
            break Ok(Outcome::Done);
        }
        let sig = STOP.load(Ordering::SeqCst);
        if sig != 0 {
            break Ok(Outcome::Stopped(sig));
        }
        let event = match inbox.recv_timeout(Duration::from_millis(50)) {
            Ok(e) => e,
            Err(RecvTimeoutError::Timeout) => continue,
            Err(RecvTimeoutError::Disconnected) => break Err(Error::io("lost every session")),
        };
        let now = match event {
            Event::Chunk(Ok(Some(chunk))) => {
                asking = false;
                match state.start(chunk) {
                    Ok(()) => continue,
                    Err(e) => break Err(e),
                }
            }
            Event::Chunk(Ok(None)) => {
                asking = false;
                input_done = true;
                continue;
            }
            Event::Chunk(Err(e)) => break Err(e),
            Event::Frame(chunk, frame) => state.order.frame(chunk, frame),
            Event::Ended(chunk, ended) => match state.ended(chunk, ended) {
                Ok(now) => now,
                Err(e) => break Err(e),
            },
        };
        match write_frames(out, now) {
            Ok(true) => {}
            Ok(false) => break Ok(Outcome::Done), // the reader went away: a quiet end
            Err(e) => break Err(e),
        }
    };
    // Whatever the way out, no session is left running.
    state.stop_all(&inbox);
    let _ = out.flush();
    for line in &state.notes {
        let _ = writeln!(log, "{line}");
    }
    if let Ok(Outcome::Done) = result {
        if state.order.head() == state.chunks.len() {
            state.report(log);
        }
    }
    result
}

/// Writes frames: Ok(true) done, Ok(false) when the reader has gone away (`| head`),
/// an error for any other failure to write.
fn write_frames<W: Write>(out: &mut W, frames: Vec<Vec<u8>>) -> Result<bool> {
    if frames.is_empty() {
        return Ok(true);
    }
    let mut written = Ok(());
    for f in &frames {
        written = out.write_all(f);
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

struct State<'a> {
    options: &'a Options,
    events: Sender<Event>,
    /// Per slot (`--hosts` entry): whether it has a session running.
    busy: Vec<bool>,
    running: Vec<Running>,
    /// Per chunk sent: its frames, and the slot it went to.
    chunks: Vec<ChunkInfo>,
    slot_of: Vec<usize>,
    order: InOrder,
    stats: Vec<SlotStats>,
    /// Per chunk ended well: its session's stderr.
    stderr: Vec<(usize, String)>,
    /// Lines for stderr before the run's own message.
    notes: Vec<String>,
}

impl State<'_> {
    /// Sends `chunk` to the first free host.
    fn start(&mut self, chunk: Chunk) -> Result<()> {
        let slot = self
            .busy
            .iter()
            .position(|b| !b)
            .ok_or_else(|| Error::io("a chunk came with no host free for it"))?;
        let host = &self.options.hosts[slot];
        let info = ChunkInfo {
            first: chunk.first,
            frames: chunk.frames,
        };
        self.chunks.push(info);
        self.slot_of.push(slot);
        self.busy[slot] = true;
        self.stats[slot].chunks.push(info);
        self.stats[slot].sent += chunk.bytes.len() as u64;
        let (program, args) = self
            .options
            .ssh
            .split_first()
            .ok_or_else(|| Error::usage("POLYPIPE_SSH names no command"))?;
        let child = Command::new(program)
            .args(args)
            .arg(host)
            .arg(&self.options.command)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| {
                Error::io(format!(
                    "host {host}: cannot run {program}: {}",
                    stagecli::error::io_message(&e)
                ))
            })?;
        self.running.push(Running {
            chunk: chunk.index,
            slot,
            pid: child.id(),
            started: Instant::now(),
        });
        watch_session(child, chunk.index, chunk.bytes, self.events.clone());
        Ok(())
    }

    /// A session has ended: the frames to write now, or the run's error.
    fn ended(&mut self, chunk: usize, ended: Ended) -> Result<Vec<Vec<u8>>> {
        let Some(i) = self.running.iter().position(|r| r.chunk == chunk) else {
            return Ok(Vec::new());
        };
        let running = self.running.remove(i);
        let slot = running.slot;
        self.busy[slot] = false;
        self.stats[slot].busy += running.started.elapsed();
        let info = self.chunks[chunk];
        let host = &self.options.hosts[slot];
        let signal = std::os::unix::process::ExitStatusExt::signal(&ended.status);
        let failure = classify(ended.status.code(), signal, &ended.stderr)
            .or_else(|| {
                ended.bad_output.as_ref().map(|why| Failure {
                    message: format!(
                        "sent back {} of its {}, then what is not a frame: {why}",
                        ended.frames,
                        frames_text(info.first, info.frames)
                    ),
                    status: 3,
                })
            })
            .or_else(|| (ended.frames != info.frames).then(|| short_failure(ended.frames, &info)));
        if let Some(f) = failure {
            // What the host said before its last line (which the message gives).
            let lines: Vec<&str> = ended
                .stderr
                .lines()
                .filter(|l| !l.trim().is_empty())
                .collect();
            for l in &lines[..lines.len().saturating_sub(1)] {
                let l = stagecli::remote::without_render_prefix(l);
                self.notes.push(format!("host {host}: {l}"));
            }
            return Err(Error::new(
                kind_of(f.status),
                format!("host {host}: {}", f.message),
            ));
        }
        self.stats[slot].received += ended.bytes;
        self.stderr.push((chunk, ended.stderr));
        Ok(self.order.ended(chunk))
    }

    /// Stops every session still running (TERM, then KILL after a second) and waits
    /// until each has been reaped.
    fn stop_all(&mut self, inbox: &Receiver<Event>) {
        for r in &self.running {
            kill(r.pid, libc::SIGTERM);
        }
        let deadline = Instant::now() + Duration::from_secs(1);
        let mut killed = false;
        while !self.running.is_empty() {
            if !killed && Instant::now() >= deadline {
                for r in &self.running {
                    kill(r.pid, libc::SIGKILL);
                }
                killed = true;
            }
            match inbox.recv_timeout(Duration::from_millis(20)) {
                Ok(Event::Ended(chunk, _)) => self.running.retain(|r| r.chunk != chunk),
                Ok(_) | Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) => break,
            }
        }
    }

    /// On success: the hosts' own stderr lines (their --stats), labelled with the host,
    /// in the movie's order; with --stats, each host's part.
    fn report(&mut self, log: &mut dyn Write) {
        self.stderr.sort_by_key(|(c, _)| *c);
        for (chunk, text) in &self.stderr {
            let host = &self.options.hosts[self.slot_of[*chunk]];
            for line in text.lines() {
                let line = stagecli::remote::without_render_prefix(line);
                let _ = writeln!(log, "host {host}: {line}");
            }
        }
        if !self.options.stats {
            return;
        }
        let total: u64 = self.chunks.iter().map(|c| c.frames).sum();
        for (s, host) in self.stats.iter().zip(&self.options.hosts) {
            if s.chunks.is_empty() {
                let _ = writeln!(log, "farm: host {host}: no frames (the movie has {total})");
                continue;
            }
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
                s.busy.as_secs_f64()
            );
        }
    }
}

fn kind_of(status: u8) -> stagecli::Kind {
    match status {
        1 => stagecli::Kind::Data,
        2 => stagecli::Kind::Usage,
        _ => stagecli::Kind::Io,
    }
}

/// Sends `sig` to a session's ssh that its watcher has not yet reported reaped.
fn kill(pid: u32, sig: i32) {
    if let Ok(pid) = libc::pid_t::try_from(pid) {
        // SAFETY: kill(2) takes any pid and signal; it touches no memory of ours.
        unsafe {
            libc::kill(pid, sig);
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
    fn frames_are_written_in_order_whatever_order_they_come_in() {
        let mut order = InOrder::new();
        let f = |k: u8| vec![k];
        // Chunk 1 finishes first: kept; chunk 0's frames go out as they come.
        assert!(order.frame(1, f(2)).is_empty());
        assert!(order.frame(1, f(3)).is_empty());
        assert!(order.ended(1).is_empty());
        assert_eq!(order.held(), 2);
        assert_eq!(order.frame(0, f(0)), [f(0)]);
        assert_eq!(order.frame(0, f(1)), [f(1)]);
        // Chunk 0 ends: chunk 1's kept frames follow, and chunk 2 is the head.
        assert_eq!(order.ended(0), [f(2), f(3)]);
        assert_eq!((order.head(), order.held()), (2, 0));
        assert_eq!(order.frame(2, f(4)), [f(4)]);
    }

    proptest! {
        /// However the chunks' frames and ends interleave (each chunk's own in order),
        /// the frames come out as the movie's, each once.
        #[test]
        fn any_interleaving_gives_the_movie(sizes in prop::collection::vec(0usize..4, 1..6),
                                            picks in prop::collection::vec(0usize..100, 0..60)) {
            // Events per chunk: its frames, then its end.
            let mut next_frame = 0u8;
            let mut queues: Vec<VecDeque<Option<u8>>> = sizes.iter().map(|&n| {
                let mut q: VecDeque<Option<u8>> = (0..n).map(|_| { next_frame += 1; Some(next_frame - 1) }).collect();
                q.push_back(None);
                q
            }).collect();
            let mut order = InOrder::new();
            let mut out = Vec::new();
            let mut picks = picks.into_iter();
            while queues.iter().any(|q| !q.is_empty()) {
                let live: Vec<usize> = (0..queues.len()).filter(|&i| !queues[i].is_empty()).collect();
                let i = live[picks.next().unwrap_or(0) % live.len()];
                match queues[i].pop_front().unwrap() {
                    Some(frame) => out.extend(order.frame(i, vec![frame])),
                    None => out.extend(order.ended(i)),
                }
            }
            let want: Vec<Vec<u8>> = (0..next_frame).map(|k| vec![k]).collect();
            prop_assert_eq!(out, want);
            prop_assert_eq!(order.head(), sizes.len());
        }
    }

    #[test]
    fn how_a_session_ended_is_told_in_one_line() {
        let f = |status, signal, err: &str| classify(status, signal, err);
        assert_eq!(f(Some(0), None, "render.sh: zbuf: 3 frames\n"), None);
        let ssh = f(
            Some(255),
            None,
            "ssh: connect to host x port 22: Connection refused\n",
        )
        .unwrap();
        assert_eq!(
            (ssh.message.as_str(), ssh.status),
            ("ssh: connect to host x port 22: Connection refused", 3)
        );
        let far = f(
            Some(1),
            None,
            "render.sh: viewxf: stdin: line 3: not a number\n",
        )
        .unwrap();
        assert_eq!(
            (far.message.as_str(), far.status),
            ("viewxf: stdin: line 3: not a number", 1)
        );
        let silent = f(Some(1), None, "").unwrap();
        assert_eq!(
            (silent.message.as_str(), silent.status),
            (
                "the command exited with status 1 and no message (does the host allow only \
                 another command?)",
                3
            )
        );
        let missing = f(Some(127), None, "sh: 1: exec: render.sh: not found\n").unwrap();
        assert_eq!(
            missing.message,
            "cannot run the command there: sh: 1: exec: render.sh: not found"
        );
        let killed = f(None, Some(libc::SIGKILL), "").unwrap();
        assert_eq!(
            (killed.message.as_str(), killed.status),
            ("ssh was killed by SIGKILL", 3)
        );
        let info = ChunkInfo {
            first: 8,
            frames: 4,
        };
        assert_eq!(
            short_failure(0, &info).message,
            "sent back nothing for its frames 8 to 11"
        );
        assert_eq!(
            short_failure(2, &info).message,
            "sent back 2 of its frames 8 to 11"
        );
    }
}
