//! The launcher: render's process graph started, watched and ended by one process.
//!
//! render works out the graph ([`crate::graph`]: the clipper chain, the splitter tree,
//! the leaves and the merger: thesis chapter 6.3, occam's `PAR` over channels) and then
//! runs it here, which
//!
//! 1. makes each channel an anonymous pipe: a stage's stdin or stdout, or, for a stage
//!    that names its channels on its command line (a splitter's two outputs, the
//!    merger's inputs), `/dev/fd/N` with the pipe's end kept open in that stage alone;
//! 2. starts the stages, each with its stderr on a pipe of its own, read as it runs;
//! 3. waits for them. When all exit 0, it writes what each said on stderr, in the
//!    graph's order (the `--stats` counts), and exits 0. When one fails, the stages
//!    downstream of it fail in turn (their input ends short), so it waits a moment,
//!    names the cause (one killed by a signal, else the most upstream to fail), stops
//!    the rest (TERM, KILL a second later), writes only the cause's words and
//!    `render: STAGE failed (status N)`, and exits with the stage's class of
//!    failure (1 bad data, 2 usage, 3 I/O; otherwise 1). SIGINT, SIGTERM and SIGHUP stop
//!    every stage, and it exits 130, 143 or 129.
//!
//! Nothing goes to disk: no private folder, no named pipes, no stderr files, so nothing
//! is left behind however the run ends; a launcher killed outright takes its stages with
//! it (each is started with `PR_SET_PDEATHSIG`). Before it, a bash script did all
//! this itself with a folder of named pipes and `wait -n`: about 8 ms of a small
//! render's 17 on the 2-core machine this was measured on (docs/performance.md,
//! "Start-up").
//!
//! A scene on stdin that `--depth auto` has looked at is fed to its stage by a thread of
//! this process ([`Feed`]): the sample kept in memory, then the rest of the stream.
//!
//! A stage on another host (`render --hosts`, an ssh) carries its host and its node
//! of the tree, so that its failure is told as farm tells one ([`stagecli::remote`]),
//! and with `--links` the bytes each host's link carried are counted from the stages'
//! `--stats` lines.

use std::ffi::{OsStr, OsString};
use std::io::Write;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd, RawFd};
use std::os::unix::ffi::OsStrExt;
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::PathBuf;
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// Where a stage's stdin or stdout goes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum End {
    /// The launcher's own (`-`): the scene on stdin, the frames on stdout.
    Inherit,
    /// A file, opened here (`file:PATH`).
    Path(PathBuf),
    /// A channel to another stage (`pipe:NAME`).
    Pipe(String),
}

/// One process of the graph.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Stage {
    /// Its name in messages: `persp (leaf 2)`, `splitter (node 3)`.
    pub label: String,
    pub input: End,
    pub output: End,
    /// For a stage that runs on another host: the host and the node of the tree there.
    pub host: Option<(String, u64)>,
    /// The program and its arguments; the last `pipes` arguments are channel names,
    /// given to the program as `/dev/fd/N`.
    pub argv: Vec<OsString>,
    pub pipes: usize,
}

/// A graph that cannot be run (two readers of a channel, say): a bug in its builder.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum SpecError {
    #[error("stage {0}: the description ends early")]
    Short(usize),
    #[error("stage {0}: {1}")]
    Bad(usize, String),
    #[error("channel {0}: {1}")]
    Channel(String, String),
}

fn end_of(word: &OsStr, stage: usize, what: &str) -> Result<End, SpecError> {
    let bytes = word.as_bytes();
    if bytes == b"-" {
        Ok(End::Inherit)
    } else if let Some(path) = bytes.strip_prefix(b"file:") {
        Ok(End::Path(PathBuf::from(OsStr::from_bytes(path))))
    } else if let Some(name) = bytes.strip_prefix(b"pipe:") {
        Ok(End::Pipe(String::from_utf8_lossy(name).into_owned()))
    } else {
        Err(SpecError::Bad(
            stage,
            format!("{what} must be -, file:PATH or pipe:NAME, not {word:?}"),
        ))
    }
}

/// The stages from a description in words (the form the bash composer gave its
/// launcher, kept for tests and tools): for each, `LABEL IN OUT HOST NODE PIPES N`
/// and then the N words of its command. IN and OUT are `-`, `file:PATH` or `pipe:NAME`;
/// HOST and NODE are empty but for a stage on another host; the last PIPES words of the
/// command are channel names.
pub fn parse_stages(words: &[OsString]) -> Result<Vec<Stage>, SpecError> {
    let mut stages = Vec::new();
    let mut rest = words;
    while !rest.is_empty() {
        let i = stages.len();
        let [label, input, output, host, node, pipes, n, tail @ ..] = rest else {
            return Err(SpecError::Short(i));
        };
        let number = |w: &OsString, what: &str| -> Result<usize, SpecError> {
            w.to_str()
                .and_then(|s| s.parse().ok())
                .ok_or_else(|| SpecError::Bad(i, format!("{what} must be a count, not {w:?}")))
        };
        let (pipes, n) = (number(pipes, "PIPES")?, number(n, "N")?);
        if n == 0 || n > tail.len() || pipes >= n {
            return Err(SpecError::Short(i));
        }
        let host = match (host.is_empty(), node.is_empty()) {
            (true, true) => None,
            (false, false) => Some((
                host.to_string_lossy().into_owned(),
                number(node, "NODE")? as u64,
            )),
            _ => return Err(SpecError::Bad(i, "HOST and NODE go together".into())),
        };
        stages.push(Stage {
            label: label.to_string_lossy().into_owned(),
            input: end_of(input, i, "IN")?,
            output: end_of(output, i, "OUT")?,
            host,
            argv: tail[..n].to_vec(),
            pipes,
        });
        rest = &tail[n..];
    }
    Ok(stages)
}

/// Where a channel's two ends go: (stage, argument index or `None` for stdin/stdout).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Channel {
    pub writer: (usize, Option<usize>),
    pub reader: (usize, Option<usize>),
}

/// Each channel's writer and reader. A channel on a stdout is written there, on a stdin
/// read there; one named on a command line is the other end of one of those.
pub fn channels(stages: &[Stage]) -> Result<Vec<(String, Channel)>, SpecError> {
    let (chans, open) = channels_open(stages)?;
    match open.into_iter().next() {
        Some((name, _)) => Err(SpecError::Channel(
            name,
            "needs one writer and one reader".into(),
        )),
        None => Ok(chans),
    }
}

/// The channels of a graph's first stages, and those of their stdouts that none of them
/// reads (their readers start later), by name and writer.
pub type OpenChannels = (Vec<(String, Channel)>, Vec<(String, usize)>);

/// [`channels`] of the first stages of a graph: also those written on a stage's stdout
/// that none of them reads (their readers start later), by name and writer.
pub fn channels_open(stages: &[Stage]) -> Result<OpenChannels, SpecError> {
    let mut writers: Vec<(String, (usize, Option<usize>))> = Vec::new();
    let mut readers: Vec<(String, (usize, Option<usize>))> = Vec::new();
    let mut named: Vec<(String, (usize, usize))> = Vec::new();
    for (i, s) in stages.iter().enumerate() {
        if let End::Pipe(n) = &s.output {
            writers.push((n.clone(), (i, None)));
        }
        if let End::Pipe(n) = &s.input {
            readers.push((n.clone(), (i, None)));
        }
        for k in s.argv.len() - s.pipes..s.argv.len() {
            named.push((s.argv[k].to_string_lossy().into_owned(), (i, k)));
        }
    }
    for (name, (i, k)) in named {
        let w = writers.iter().any(|(n, _)| *n == name);
        let r = readers.iter().any(|(n, _)| *n == name);
        match (w, r) {
            (true, false) => readers.push((name, (i, Some(k)))),
            (false, true) => writers.push((name, (i, Some(k)))),
            _ => {
                return Err(SpecError::Channel(
                    name,
                    "named on a command line needs its other end on a stdin or a stdout".into(),
                ))
            }
        }
    }
    let mut out = Vec::new();
    let mut open = Vec::new();
    for (name, writer) in &writers {
        let mut found = readers.iter().filter(|(n, _)| n == name);
        match (
            found.next(),
            found.next(),
            writers.iter().filter(|(n, _)| n == name).count(),
        ) {
            (Some((_, reader)), None, 1) => out.push((
                name.clone(),
                Channel {
                    writer: *writer,
                    reader: *reader,
                },
            )),
            (None, _, 1) if writer.1.is_none() => open.push((name.clone(), writer.0)),
            _ => {
                return Err(SpecError::Channel(
                    name.clone(),
                    "needs one writer and one reader".into(),
                ))
            }
        }
    }
    if let Some((name, _)) = readers
        .iter()
        .find(|(n, _)| !writers.iter().any(|(w, _)| w == n))
    {
        return Err(SpecError::Channel(name.clone(), "has no writer".into()));
    }
    Ok((out, open))
}

// --- What the stages said, and how they ended. -----------------------------------------

/// A stage's exit as the shell numbers it: its status, or 128 + the signal that killed it.
pub fn shell_status(status: ExitStatus) -> i32 {
    status
        .code()
        .or_else(|| status.signal().map(|s| 128 + s))
        .unwrap_or(1)
}

/// `status 3`, or `killed by SIGKILL`, for a status as the shell numbers it.
pub fn describe(status: i32) -> String {
    if status > 128 {
        format!("killed by {}", stagecli::remote::signal_name(status - 128))
    } else {
        format!("status {status}")
    }
}

/// How the messages name node `node` of a tree of depth `depth`: `leaf N` or `subtree K`.
pub fn what_node(node: u64, depth: u32) -> String {
    let leaves = 1u64 << depth;
    if node >= leaves {
        format!("leaf {}", node - leaves)
    } else {
        format!("subtree {node}")
    }
}

/// What a stage wrote on stderr, for the user: each `/dev/fd/N` the stage was given for
/// a channel named by the channel (`zbuf: /dev/fd/9: …` becomes `zbuf: leaf-2: …`); a
/// line that starts with the bare program name given the stage's full label instead
/// (`scanconv: …` from leaf 2 becomes `scanconv (leaf 2): …`; lines a stage labelled
/// itself, as `splitter y=0 (node 2): …`, are left alone); a host's render's lines
/// (labelled by it) given the host.
pub fn labelled(said: &str, stage: &Stage, fds: &[(RawFd, String)]) -> String {
    let program = stage.label.split(' ').next().unwrap_or("");
    let mut out = String::with_capacity(said.len());
    for line in said.lines() {
        let line = name_channels(line, fds);
        if let Some((host, _)) = &stage.host {
            let line = stagecli::remote::without_render_prefix(&line);
            out.push_str(&format!("host {host}: {line}\n"));
        } else if let Some(rest) = line
            .strip_prefix(program)
            .and_then(|r| r.strip_prefix(": "))
        {
            out.push_str(&format!("{}: {rest}\n", stage.label));
        } else {
            out.push_str(&line);
            out.push('\n');
        }
    }
    out
}

/// `line` with each `/dev/fd/N` in `fds` replaced by its channel's name.
fn name_channels(line: &str, fds: &[(RawFd, String)]) -> String {
    const DEV_FD: &str = "/dev/fd/";
    let mut out = String::new();
    let mut rest = line;
    while let Some(at) = rest.find(DEV_FD) {
        let after = &rest[at + DEV_FD.len()..];
        let digits = after.bytes().take_while(u8::is_ascii_digit).count();
        let name = after[..digits]
            .parse::<RawFd>()
            .ok()
            .and_then(|fd| fds.iter().find(|(f, _)| *f == fd));
        out.push_str(&rest[..at]);
        match name {
            Some((_, n)) => out.push_str(n),
            None => out.push_str(&rest[at..at + DEV_FD.len() + digits]),
        }
        rest = &after[digits..];
    }
    out.push_str(rest);
    out
}

/// The stage to blame for a failed run, among those whose exit is known (the shell's
/// numbering; 0 for one still running): one killed by a signal, or else the most
/// upstream (the first in the graph's order) that failed.
pub fn cause(statuses: &[Option<i32>]) -> Option<usize> {
    let mut first = None;
    for (i, st) in statuses.iter().enumerate() {
        match st.unwrap_or(0) {
            0 => continue,
            s if s > 128 => return Some(i),
            _ => {
                first.get_or_insert(i);
            }
        }
    }
    first
}

/// The node a merger's message says sent back nothing (`zbuf: from-5: empty input`).
fn empty_from(said: &str) -> Option<u64> {
    let at = said.find(": empty input")?;
    let before = &said[..at];
    let digits = before.bytes().rev().take_while(u8::is_ascii_digit).count();
    let node = &before[before.len() - digits..];
    before[..before.len() - digits]
        .ends_with("from-")
        .then(|| node.parse().ok())?
}

/// With `--stats` and `--hosts`: each host stage's node, host, and the bytes its link
/// carried each way (thesis 6.5 estimates them for the transputer links), from the
/// splitters' `…; A and B bytes out` and the merger's `zbuf: from-K: … N bytes in`. A
/// subtree at the root carries the clipper's whole output, which nothing counts.
pub fn links(stages: &[Stage], said: &[String], depth: u32, me: &str) -> String {
    let mut out = String::new();
    for s in stages {
        let Some((host, node)) = &s.host else {
            continue;
        };
        let mut there = "not counted (the clipper's output)".to_string();
        let mut back = "?".to_string();
        if *node > 1 {
            let parent = format!("(node {}): ", node >> 1);
            if let Some(line) = said
                .iter()
                .flat_map(|t| t.lines())
                .find(|l| l.contains(&parent))
            {
                if let Some((a, b)) = bytes_out(line) {
                    there = format!("{} bytes there", if node & 1 == 0 { a } else { b });
                }
            }
        }
        let from = format!("from-{node}: ");
        if let Some(line) = said
            .iter()
            .flat_map(|t| t.lines())
            .find(|l| l.starts_with("zbuf: ") && l.contains(&from))
        {
            if let Some(n) = line
                .strip_suffix(" bytes in")
                .and_then(|l| l.rsplit(' ').next())
                .filter(|n| n.parse::<u64>().is_ok())
            {
                back = format!("{n} bytes back");
            }
        }
        out.push_str(&format!(
            "{me}: {} on host {host}: {there}, {back}\n",
            what_node(*node, depth)
        ));
    }
    out
}

/// `…; A and B bytes out` at the end of a splitter's line.
fn bytes_out(line: &str) -> Option<(u64, u64)> {
    let tail = line.rsplit("; ").next()?.strip_suffix(" bytes out")?;
    let (a, b) = tail.split_once(" and ")?;
    Some((a.parse().ok()?, b.parse().ok()?))
}

// --- Running the graph. ----------------------------------------------------------------

/// How the run ended: the launcher's exit status and what it writes on stderr.
#[derive(Debug, PartialEq, Eq)]
pub struct Outcome {
    pub status: u8,
    pub message: String,
}

/// What a stage reading the launcher's stdin is fed instead: `sample` (the bytes
/// `--depth auto` looked at, kept in memory), then what is left of `rest` (the stream
/// they came from; `None` when the stream ended within the sample).
#[derive(Debug, Default)]
pub struct Feed {
    /// Shared with the look at it, which runs while the feed is written.
    pub sample: std::sync::Arc<Vec<u8>>,
    pub rest: Option<OwnedFd>,
}

/// How the launcher runs the stages.
#[derive(Debug, Default)]
pub struct Options {
    /// The tree's depth, for naming the hosts' nodes.
    pub depth: u32,
    /// Print the hosts' links' bytes on success (`--stats --hosts`).
    pub links: bool,
    /// Print what each stage cost on success ([`Cost`], `render --times`).
    pub times: bool,
    /// The stage that reads the launcher's stdin reads this instead.
    pub feed: Option<Feed>,
}

/// What one stage cost, from `wait4`: its CPU (user and system) and its own peak
/// resident memory, and when it ended, counted from the launcher's start.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Cost {
    pub user_s: f64,
    pub system_s: f64,
    pub peak_kib: u64,
    pub ended_s: f64,
}

impl Cost {
    fn of(usage: &libc::rusage, ended_s: f64) -> Cost {
        let s = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
        Cost {
            user_s: s(usage.ru_utime),
            system_s: s(usage.ru_stime),
            peak_kib: u64::try_from(usage.ru_maxrss).unwrap_or(0),
            ended_s,
        }
    }
}

/// `--times`: a line a stage, `render: LABEL: 6.6 ms CPU (6.1 user, 0.5 system), 3.1
/// MB peak, ended at 31.0 ms`, and a last line of their sums: the CPU of all of them, and
/// the sum of their peaks, a bound on what the stages, running side by side, held at any
/// one moment.
pub fn times(stages: &[Stage], costs: &[Cost], me: &str) -> String {
    let ms = |s: f64| s * 1e3;
    let mb = |kib: u64| kib as f64 / 1024.0;
    let mut out = String::new();
    for (s, c) in stages.iter().zip(costs) {
        out.push_str(&format!(
            "{me}: {}: {:.1} ms CPU ({:.1} user, {:.1} system), {:.1} MB peak, ended at {:.1} ms\n",
            s.label,
            ms(c.user_s + c.system_s),
            ms(c.user_s),
            ms(c.system_s),
            mb(c.peak_kib),
            ms(c.ended_s)
        ));
    }
    let cpu: f64 = costs.iter().map(|c| c.user_s + c.system_s).sum();
    let peak: u64 = costs.iter().map(|c| c.peak_kib).sum();
    let last = costs.iter().map(|c| c.ended_s).fold(0.0, f64::max);
    out.push_str(&format!(
        "{me}: {} stages: {:.1} ms CPU, {:.1} MB of peaks, the last ended at {:.1} ms\n",
        costs.len(),
        ms(cpu),
        mb(peak),
        ms(last)
    ));
    out
}

fn os_error(what: &str) -> std::io::Error {
    let e = std::io::Error::last_os_error();
    std::io::Error::new(e.kind(), format!("{what}: {e}"))
}

fn pipe() -> std::io::Result<(OwnedFd, OwnedFd)> {
    let mut fds = [0; 2];
    // SAFETY: pipe2 writes two descriptors into the array it is given.
    if unsafe { libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC) } != 0 {
        return Err(os_error("pipe"));
    }
    // SAFETY: both are new descriptors, owned by nothing else.
    Ok(unsafe { (OwnedFd::from_raw_fd(fds[0]), OwnedFd::from_raw_fd(fds[1])) })
}

/// Every descriptor this process inherited above stderr (bash's own, a copy of the
/// script's stdin) closed on exec: a stage must hold only its own ends, or a pipe would
/// never see its end.
fn cloexec_inherited() {
    let Ok(dir) = std::fs::read_dir("/proc/self/fd") else {
        return;
    };
    for fd in dir.filter_map(|e| e.ok()?.file_name().to_str()?.parse::<RawFd>().ok()) {
        if fd > 2 {
            // SAFETY: F_SETFD on a descriptor number; at worst EBADF (the listing's own).
            unsafe { libc::fcntl(fd, libc::F_SETFD, libc::FD_CLOEXEC) };
        }
    }
}

/// The signals the launcher takes through a signalfd: a stage's end, and the user's stop.
fn signal_set() -> libc::sigset_t {
    // SAFETY: sigemptyset/sigaddset initialise and fill the set they are given.
    unsafe {
        let mut set = std::mem::zeroed::<libc::sigset_t>();
        libc::sigemptyset(&mut set);
        for s in [libc::SIGCHLD, libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
            libc::sigaddset(&mut set, s);
        }
        set
    }
}

struct Running {
    stages: Vec<Stage>,
    pids: Vec<Option<libc::pid_t>>,
    /// How each stage exited, once it has.
    exits: Vec<Option<ExitStatus>>,
    /// What each cost, as it exited.
    costs: Vec<Cost>,
    started: Instant,
    errs: Vec<Option<OwnedFd>>,
    said: Vec<Vec<u8>>,
    fds: Vec<Vec<(RawFd, String)>>,
    signals: OwnedFd,
}

impl Running {
    fn all_exited(&self) -> bool {
        self.pids
            .iter()
            .zip(&self.exits)
            .all(|(p, e)| p.is_none() || e.is_some())
    }

    /// How each stage exited, as the shell numbers it ([`shell_status`]); `None` for one
    /// still running.
    fn statuses(&self) -> Vec<Option<i32>> {
        self.exits.iter().map(|e| e.map(shell_status)).collect()
    }

    /// Waits up to `timeout` (or for ever) for a stderr to speak or a signal; reads what
    /// is there. Returns the stop signal the launcher got, if any.
    fn step(&mut self, timeout: Option<Duration>) -> Option<i32> {
        let mut polls = vec![libc::pollfd {
            fd: self.signals.as_raw_fd(),
            events: libc::POLLIN,
            revents: 0,
        }];
        let mut which = Vec::new();
        for (i, e) in self.errs.iter().enumerate() {
            if let Some(fd) = e {
                polls.push(libc::pollfd {
                    fd: fd.as_raw_fd(),
                    events: libc::POLLIN,
                    revents: 0,
                });
                which.push(i);
            }
        }
        let ms = timeout.map_or(-1, |t| t.as_millis().min(i32::MAX as u128) as i32);
        // SAFETY: `polls` is a valid array of its length; poll writes only revents.
        let n = unsafe { libc::poll(polls.as_mut_ptr(), polls.len() as libc::nfds_t, ms) };
        let stop = if n > 0 {
            self.read_ready(&polls[1..], &which);
            if polls[0].revents != 0 {
                self.stop_signal()
            } else {
                None
            }
        } else {
            None
        };
        // Also after a quiet poll: a stage may have ended with its SIGCHLD taken by
        // another thread (a test harness's), and the wait would have no end.
        self.reap();
        stop
    }

    /// Reads what the stderr pipes `polls` found ready hold (`which`: their stages); a
    /// pipe that has ended is dropped.
    fn read_ready(&mut self, polls: &[libc::pollfd], which: &[usize]) {
        let mut buf = [0u8; 65536];
        for (p, &i) in polls.iter().zip(which) {
            if p.revents == 0 {
                continue;
            }
            let Some(fd) = &self.errs[i] else { continue };
            // SAFETY: reads into a buffer of its length from a descriptor we own.
            let got = unsafe { libc::read(fd.as_raw_fd(), buf.as_mut_ptr().cast(), buf.len()) };
            if got > 0 {
                self.said[i].extend_from_slice(&buf[..got as usize]);
            } else if got == 0
                || std::io::Error::last_os_error().raw_os_error() != Some(libc::EINTR)
            {
                self.errs[i] = None;
            }
        }
    }

    /// Reads the signalfd: the first signal other than SIGCHLD (the user's stop), if any.
    fn stop_signal(&mut self) -> Option<i32> {
        // SAFETY: a signalfd is read in whole signalfd_siginfo records.
        let mut info = [unsafe { std::mem::zeroed::<libc::signalfd_siginfo>() }; 16];
        let size = std::mem::size_of_val(&info);
        // SAFETY: reads at most `size` bytes into `info`, which is that long, from the
        // signalfd this struct owns.
        let got = unsafe { libc::read(self.signals.as_raw_fd(), info.as_mut_ptr().cast(), size) };
        let records = if got > 0 {
            got as usize / std::mem::size_of::<libc::signalfd_siginfo>()
        } else {
            0
        };
        info[..records]
            .iter()
            .map(|r| r.ssi_signo as i32)
            .find(|&s| s != libc::SIGCHLD)
    }

    /// Collects every stage that has exited, without waiting: the children this thread
    /// started (`__WNOTHREAD`), so that a process another thread started (a test
    /// harness's other tests) is left to whoever waits for it.
    fn reap(&mut self) {
        loop {
            let mut st = 0;
            // SAFETY: an all-zero rusage is a valid value of the plain C struct.
            let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
            let flags = libc::WNOHANG | libc::__WNOTHREAD;
            // SAFETY: wait4 writes the status and usage it is given.
            let pid = unsafe { libc::wait4(-1, &mut st, flags, &mut usage) };
            if pid <= 0 {
                return;
            }
            if let Some(i) = self.pids.iter().position(|p| *p == Some(pid)) {
                self.exited(i, st);
                self.costs[i] = Cost::of(&usage, self.started.elapsed().as_secs_f64());
            }
        }
    }

    /// TERM to every stage still running; KILL to those left a second later.
    fn stop_all(&mut self) {
        self.signal_running(libc::SIGTERM);
        let until = Instant::now() + Duration::from_secs(1);
        while !self.all_exited() {
            let now = Instant::now();
            if now >= until {
                self.signal_running(libc::SIGKILL);
                for i in 0..self.pids.len() {
                    if let (Some(pid), None) = (self.pids[i], self.exits[i]) {
                        let mut st = 0;
                        // SAFETY: waits for our own child, writing its status.
                        if unsafe { libc::waitpid(pid, &mut st, 0) } == pid {
                            self.exited(i, st);
                        }
                    }
                }
                break;
            }
            self.step(Some((until - now).min(Duration::from_millis(50))));
        }
        self.drain();
    }

    /// Reads what the stages' stderr pipes still hold, until they end or stay quiet for
    /// 20 ms (a grandchild may hold one open).
    fn drain(&mut self) {
        while self.errs.iter().any(Option::is_some) {
            let before = self.heard();
            self.step(Some(Duration::from_millis(20)));
            if self.heard() == before {
                break;
            }
        }
    }

    /// How much has been heard: pipes closed and bytes read.
    fn heard(&self) -> (usize, usize) {
        (
            self.errs.iter().filter(|e| e.is_none()).count(),
            self.said.iter().map(Vec::len).sum(),
        )
    }

    fn exited(&mut self, i: usize, wait_status: i32) {
        self.exits[i] = Some(ExitStatus::from_raw(wait_status));
    }

    fn signal_running(&self, sig: i32) {
        for (pid, st) in self.pids.iter().zip(&self.exits) {
            if let (Some(pid), None) = (pid, st) {
                // SAFETY: kill sends a signal to our own child; nothing else is touched.
                unsafe { libc::kill(*pid, sig) };
            }
        }
    }

    fn labelled(&self, i: usize) -> String {
        labelled(
            &String::from_utf8_lossy(&self.said[i]),
            &self.stages[i],
            &self.fds[i],
        )
    }
}

/// Opens a file end of a stage: IN for reading (without waiting for a named pipe's
/// writer: a scene given as a fifo is the stage's to wait for), OUT for writing.
fn open_end(path: &std::path::Path, write: bool) -> std::io::Result<std::fs::File> {
    use std::os::unix::fs::OpenOptionsExt;
    let named =
        |e: std::io::Error| std::io::Error::new(e.kind(), format!("{}: {e}", path.display()));
    if write {
        return std::fs::OpenOptions::new()
            .write(true)
            .create(true)
            .truncate(true)
            .open(path)
            .map_err(named);
    }
    let f = std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK)
        .open(path)
        .map_err(named)?;
    // SAFETY: F_GETFL/F_SETFL on a descriptor we own.
    unsafe {
        let flags = libc::fcntl(f.as_raw_fd(), libc::F_GETFL);
        libc::fcntl(f.as_raw_fd(), libc::F_SETFL, flags & !libc::O_NONBLOCK);
    }
    Ok(f)
}

/// Runs the graph to its end and says how it ended ([`Outcome`]); `me` is the name the
/// messages start with (`render`).
pub fn run(stages: Vec<Stage>, mut options: Options, me: &str) -> Result<Outcome, SpecError> {
    let feed = options.feed.take();
    start(stages.clone(), feed, me)?.finish(stages, options)
}

/// The first stages of a graph, running while the rest of it is worked out (`render
/// --depth auto` starts viewxf and the clipper chain, whose command lines no depth
/// changes, and looks at the scene meanwhile): [`Early::finish`] starts the rest and
/// watches them all; [`Early::stop`] ends those started.
pub struct Early {
    me: String,
    /// `None` when the launcher could not begin (no signalfd): `failed` says so.
    run: Option<Running>,
    /// How the run ended already: a stage that could not be started (the others
    /// stopped).
    failed: Option<Outcome>,
    /// The read ends of the started stages' outputs whose readers are not started yet,
    /// by their writer: (stage, argument or `None` for its stdout).
    pending: Vec<((usize, Option<usize>), OwnedFd, String)>,
}

/// Starts `stages`, the first stages of a graph in its order, each output channel that
/// no stage of them reads left open for the stages [`Early::finish`] adds. The stage that
/// would read the launcher's stdin reads `feed` instead, when given.
pub fn start(stages: Vec<Stage>, feed: Option<Feed>, me: &str) -> Result<Early, SpecError> {
    let (chans, open) = channels_open(&stages)?;
    cloexec_inherited();
    let set = signal_set();
    // SAFETY: blocks the signals for this thread (the only one), so that they queue on
    // the signalfd; each stage unblocks them again before its exec.
    let signals = unsafe {
        libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut());
        libc::signalfd(-1, &set, libc::SFD_CLOEXEC | libc::SFD_NONBLOCK)
    };
    let failed = |run: Option<Running>, message: String| Early {
        me: me.to_string(),
        run,
        failed: Some(Outcome { status: 3, message }),
        pending: Vec::new(),
    };
    if signals < 0 {
        return Ok(failed(None, format!("{me}: {}\n", os_error("signalfd"))));
    }
    // SAFETY: a new descriptor, owned by nothing else.
    let signals = unsafe { OwnedFd::from_raw_fd(signals) };
    let n = stages.len();
    let mut run = Running {
        pids: vec![None; n],
        exits: vec![None; n],
        costs: vec![Cost::default(); n],
        started: Instant::now(),
        errs: (0..n).map(|_| None).collect(),
        said: vec![Vec::new(); n],
        fds: vec![Vec::new(); n],
        signals,
        stages,
    };
    let mut ends = Ends::new(n);
    let mut pending = Vec::new();
    let made = (|| -> std::io::Result<()> {
        for (name, ch) in &chans {
            let (r, w) = pipe()?;
            ends.writer(ch.writer, w, name);
            ends.reader(ch.reader, r, name);
        }
        for (name, writer) in open {
            let (r, w) = pipe()?;
            ends.writer((writer, None), w, &name);
            pending.push(((writer, None), r, name));
        }
        // The feed: a pipe into the stage that would read stdin, written by a thread,
        // which holds the signals blocked as this one does (blocked before it starts).
        if let Some(feed) = feed {
            if let Some(i) = run.stages.iter().position(|s| s.input == End::Inherit) {
                let (r, w) = pipe()?;
                ends.reader((i, None), r, "");
                std::thread::spawn(move || feed_stage(feed, w));
            }
        }
        Ok(())
    })();
    if let Err(e) = made {
        return Ok(failed(Some(run), format!("{me}: {e}\n")));
    }
    if let Err(message) = run.spawn(0, ends, me) {
        return Ok(failed(Some(run), message));
    }
    Ok(Early {
        me: me.to_string(),
        run: Some(run),
        failed: None,
        pending,
    })
}

/// Each stage's ends before it starts: stdin, stdout, and (argument, fd, name) for its
/// named channels.
struct Ends {
    stdin: Vec<Option<OwnedFd>>,
    stdout: Vec<Option<OwnedFd>>,
    named: Vec<Vec<(usize, OwnedFd, String)>>,
}

impl Ends {
    fn new(n: usize) -> Ends {
        Ends {
            stdin: (0..n).map(|_| None).collect(),
            stdout: (0..n).map(|_| None).collect(),
            named: (0..n).map(|_| Vec::new()).collect(),
        }
    }

    /// `fd`, a channel's write end, as stage `at.0`'s stdout or its argument `at.1`.
    fn writer(&mut self, at: (usize, Option<usize>), fd: OwnedFd, name: &str) {
        match at {
            (i, None) => self.stdout[i] = Some(fd),
            (i, Some(k)) => self.named[i].push((k, fd, name.to_string())),
        }
    }

    /// `fd`, a channel's read end, as stage `at.0`'s stdin or its argument `at.1`.
    fn reader(&mut self, at: (usize, Option<usize>), fd: OwnedFd, name: &str) {
        match at {
            (i, None) => self.stdin[i] = Some(fd),
            (i, Some(k)) => self.named[i].push((k, fd, name.to_string())),
        }
    }
}

impl Early {
    /// Starts the rest of the graph `full` (whose first stages are those started, the
    /// same command lines reading the same inputs; the channel out of the last of them
    /// may have another name now) and runs it all to its end ([`run`]).
    pub fn finish(self, full: Vec<Stage>, options: Options) -> Result<Outcome, SpecError> {
        let Early {
            me,
            run,
            failed,
            mut pending,
        } = self;
        let me = me.as_str();
        let (Some(mut run), None) = (run, failed.as_ref()) else {
            return Ok(failed.unwrap_or(Outcome {
                status: 3,
                message: String::new(),
            }));
        };
        let k = run.stages.len();
        for (i, s) in run.stages.iter().enumerate() {
            match full.get(i) {
                Some(f) if f.argv == s.argv && f.input == s.input => {}
                _ => return Err(SpecError::Bad(i, "not the stage started early".into())),
            }
        }
        let chans = channels(&full)?;
        let n = full.len();
        let mut ends = Ends::new(n);
        let made = (|| -> Result<std::io::Result<()>, SpecError> {
            for (name, ch) in &chans {
                let (w, r) = (ch.writer.0, ch.reader.0);
                if r < k {
                    if w >= k {
                        return Err(SpecError::Bad(r, "reads a stage started after it".into()));
                    }
                    continue; // made when both started
                }
                if w < k {
                    let Some(at) = pending.iter().position(|(by, _, _)| *by == ch.writer) else {
                        return Err(SpecError::Channel(name.clone(), "has no writer".into()));
                    };
                    let (_, fd, _) = pending.swap_remove(at);
                    ends.reader(ch.reader, fd, name);
                    continue;
                }
                let (rd, wr) = match pipe() {
                    Ok(p) => p,
                    Err(e) => return Ok(Err(e)),
                };
                ends.writer(ch.writer, wr, name);
                ends.reader(ch.reader, rd, name);
            }
            Ok(Ok(()))
        })()?;
        if let Some((_, _, name)) = pending.first() {
            return Err(SpecError::Channel(name.clone(), "has no reader".into()));
        }
        run.stages = full;
        run.pids.resize(n, None);
        run.exits.resize(n, None);
        run.costs.resize(n, Cost::default());
        run.errs.resize_with(n, || None);
        run.said.resize(n, Vec::new());
        run.fds.resize(n, Vec::new());
        if let Err(e) = made {
            run.stop_all();
            return Ok(Outcome {
                status: 3,
                message: format!("{me}: {e}\n"),
            });
        }
        if let Err(message) = run.spawn(k, ends, me) {
            return Ok(Outcome { status: 3, message });
        }
        run.watch(&options, me)
    }

    /// Stops the stages started, and waits for them: the graph will not be finished (the
    /// look at the scene failed, and render says why).
    pub fn stop(self) {
        if let Some(mut run) = self.run {
            run.stop_all();
        }
    }
}

impl Running {
    /// Starts stages `from..` with their ends. On a failure to start one, stops every
    /// stage started and returns the message.
    fn spawn(&mut self, from: usize, mut ends: Ends, me: &str) -> Result<(), String> {
        // SAFETY: getpid has no failure.
        let launcher = unsafe { libc::getpid() };
        for i in from..self.stages.len() {
            let stage = self.stages[i].clone();
            let named = std::mem::take(&mut ends.named[i]);
            let (stdin, stdout) = (ends.stdin[i].take(), ends.stdout[i].take());
            let started = self.spawn_one(i, &stage, stdin, stdout, &named, launcher);
            // The stage's ends are its own now: this process keeps none of them.
            drop(named);
            match started {
                Ok(pid) => self.pids[i] = Some(pid),
                Err(e) => {
                    drop(ends);
                    self.stop_all();
                    return Err(format!("{me}: {}: {e}\n", stage.label));
                }
            }
        }
        Ok(())
    }

    fn spawn_one(
        &mut self,
        i: usize,
        stage: &Stage,
        stdin: Option<OwnedFd>,
        stdout: Option<OwnedFd>,
        named: &[(usize, OwnedFd, String)],
        launcher: libc::pid_t,
    ) -> std::io::Result<libc::pid_t> {
        let mut cmd = Command::new(&stage.argv[0]);
        let mut args: Vec<OsString> = stage.argv[1..].to_vec();
        let mut keep = Vec::new();
        for (k, fd, name) in named {
            args[k - 1] = format!("/dev/fd/{}", fd.as_raw_fd()).into();
            keep.push(fd.as_raw_fd());
            self.fds[i].push((fd.as_raw_fd(), name.clone()));
        }
        cmd.args(&args);
        cmd.stdin(match (&stage.input, stdin) {
            (_, Some(fd)) => Stdio::from(fd),
            (End::Path(p), None) => Stdio::from(open_end(p, false)?),
            _ => Stdio::inherit(),
        });
        cmd.stdout(match (&stage.output, stdout) {
            (_, Some(fd)) => Stdio::from(fd),
            (End::Path(p), None) => Stdio::from(open_end(p, true)?),
            _ => Stdio::inherit(),
        });
        let (err_r, err_w) = pipe()?;
        cmd.stderr(Stdio::from(err_w));
        // SAFETY: between fork and exec the closure makes only system calls on
        // numbers it was given, allocating nothing.
        unsafe {
            cmd.pre_exec(move || {
                // The signals the launcher takes on its signalfd, the stage gets.
                let mut none = std::mem::zeroed::<libc::sigset_t>();
                libc::sigemptyset(&mut none);
                libc::sigprocmask(libc::SIG_SETMASK, &none, std::ptr::null_mut());
                // The stage ends with the launcher, however that ends (SIGKILL too).
                if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGTERM) != 0
                    || libc::getppid() != launcher
                {
                    return Err(std::io::Error::other("the launcher is gone"));
                }
                for &fd in &keep {
                    if libc::fcntl(fd, libc::F_SETFD, 0) != 0 {
                        return Err(std::io::Error::last_os_error());
                    }
                }
                Ok(())
            });
        }
        let child = cmd.spawn().map_err(|e| {
            std::io::Error::new(
                e.kind(),
                format!("cannot run {}: {e}", stage.argv[0].to_string_lossy()),
            )
        })?;
        self.errs[i] = Some(err_r);
        Ok(child.id() as libc::pid_t)
    }

    /// Watches every stage to its end, and says how the run ended.
    fn watch(mut self, options: &Options, me: &str) -> Result<Outcome, SpecError> {
        let run = &mut self;
        let n = run.stages.len();
        let fail = |message: String| Outcome { status: 3, message };
        // Watch. The first failure starts a short wait for the stages it brings down.
        let mut failed_at: Option<Instant> = None;
        const SETTLE: Duration = Duration::from_millis(100);
        loop {
            if failed_at.is_none() && run.exits.iter().flatten().any(|e| !e.success()) {
                failed_at = Some(Instant::now());
            }
            let timeout = match failed_at {
                Some(t) => match SETTLE.checked_sub(t.elapsed()) {
                    Some(left) => left,
                    None => break,
                },
                None if run.all_exited() => {
                    run.drain();
                    break;
                }
                // A stage's end wakes this by SIGCHLD, or by its stderr ending; the bound
                // is for a SIGCHLD taken by another thread (the tests').
                None => Duration::from_millis(200),
            };
            if let Some(sig) = run.step(Some(timeout)) {
                run.stop_all();
                return Ok(Outcome {
                    status: (128 + sig) as u8,
                    message: String::new(),
                });
            }
        }

        let statuses = run.statuses();
        let Some(c) = failed_at.and_then(|_| cause(&statuses)) else {
            let said: Vec<String> = (0..n).map(|i| run.labelled(i)).collect();
            let mut message = said.concat();
            if options.links {
                message.push_str(&links(&run.stages, &said, options.depth, me));
            }
            if options.times {
                message.push_str(&times(&run.stages, &run.costs, me));
            }
            return Ok(Outcome { status: 0, message });
        };
        run.stop_all();
        let statuses = run.statuses();
        let st = statuses[c].unwrap_or(0);
        let said = run.labelled(c);
        let stage = &run.stages[c];
        if stage.host.is_none() {
            // The merger found a host's runs empty: that host answered with nothing (a
            // command that is not render, say), the host's fault, not the data's.
            if let Some(node) = empty_from(&said) {
                if let Some(h) = run
                    .stages
                    .iter()
                    .position(|s| matches!(&s.host, Some((_, k)) if *k == node))
                {
                    let (host, _) = run.stages[h].host.clone().unwrap_or_default();
                    return Ok(fail(format!(
                        "{me}: host {host} ({}): sent back nothing ({} from its command)\n",
                        what_node(node, options.depth),
                        describe(statuses[h].unwrap_or(0))
                    )));
                }
            }
        }
        if let Some((host, node)) = &stage.host {
            // A subtree on a host: what ssh or the far side said last is the message.
            let lines: Vec<&str> = said.lines().collect();
            let mut message: String = lines[..lines.len().saturating_sub(1)]
                .iter()
                .map(|l| format!("{l}\n"))
                .collect();
            let raw = String::from_utf8_lossy(&run.said[c]);
            let (code, signal) = run.exits[c].map_or((Some(st), None), |e| (e.code(), e.signal()));
            let f = stagecli::remote::classify(code, signal, &raw, "render.sh").unwrap_or(
                stagecli::remote::Failure {
                    message: "failed".into(),
                    status: 1,
                },
            );
            message.push_str(&format!(
                "{me}: host {host} ({}): {}\n",
                what_node(*node, options.depth),
                f.message
            ));
            return Ok(Outcome {
                status: f.status,
                message,
            });
        }
        Ok(Outcome {
            status: if (1..=3).contains(&st) { st as u8 } else { 1 },
            message: format!("{said}{me}: {} failed ({})\n", stage.label, describe(st)),
        })
    }
}

/// Writes `feed` into `to`: the sample, then the rest of its stream. A reader that has
/// gone (the stage failed, and says so itself) ends it, as does the stream's end.
fn feed_stage(feed: Feed, to: OwnedFd) {
    let mut to = std::fs::File::from(to);
    if to.write_all(&feed.sample).is_err() {
        return;
    }
    if let Some(rest) = feed.rest {
        let _ = std::io::copy(&mut std::fs::File::from(rest), &mut to);
    }
}

/// Writes the outcome's message on stderr, in one write.
pub fn tell(outcome: &Outcome) {
    if !outcome.message.is_empty() {
        let _ = std::io::stderr().write_all(outcome.message.as_bytes());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(s: &[&str]) -> Vec<OsString> {
        s.iter().map(OsString::from).collect()
    }

    fn linear() -> Vec<Stage> {
        parse_stages(&words(&[
            "viewxf",
            "file:scene.txt",
            "pipe:view",
            "",
            "",
            "0",
            "2",
            "viewxf",
            "--text",
            "splitter (node 1)",
            "pipe:view",
            "file:/dev/null",
            "",
            "",
            "2",
            "3",
            "splitter",
            "node-2",
            "node-3",
            "leaf 0 (host a)",
            "pipe:node-2",
            "pipe:from-2",
            "a",
            "2",
            "0",
            "1",
            "ssh",
            "leaf 1 (host b)",
            "pipe:node-3",
            "pipe:from-3",
            "b",
            "3",
            "0",
            "1",
            "ssh",
            "zbuf",
            "file:/dev/null",
            "-",
            "",
            "",
            "2",
            "3",
            "zbuf",
            "from-2",
            "from-3",
        ]))
        .unwrap()
    }

    #[test]
    fn stages_and_channels_are_read_from_the_description() {
        let s = linear();
        assert_eq!(s.len(), 5);
        assert_eq!(s[0].input, End::Path("scene.txt".into()));
        assert_eq!(s[0].output, End::Pipe("view".into()));
        assert_eq!(s[0].argv, words(&["viewxf", "--text"]));
        assert_eq!(s[2].host, Some(("a".into(), 2)));
        assert_eq!(s[4].output, End::Inherit);
        let c = channels(&s).unwrap();
        let find = |n: &str| c.iter().find(|(name, _)| name == n).unwrap().1;
        assert_eq!(
            find("view"),
            Channel {
                writer: (0, None),
                reader: (1, None)
            }
        );
        assert_eq!(
            find("node-3"),
            Channel {
                writer: (1, Some(2)),
                reader: (3, None)
            }
        );
        assert_eq!(
            find("from-2"),
            Channel {
                writer: (2, None),
                reader: (4, Some(1))
            }
        );
        assert_eq!(c.len(), 5);
    }

    #[test]
    fn a_description_that_cannot_be_a_graph_is_refused() {
        assert_eq!(
            parse_stages(&words(&["a", "-", "-", "", "", "0"])),
            Err(SpecError::Short(0))
        );
        assert_eq!(
            parse_stages(&words(&["a", "-", "-", "", "", "0", "2", "x"])),
            Err(SpecError::Short(0))
        );
        assert!(matches!(
            parse_stages(&words(&["a", "x", "-", "", "", "0", "1", "x"])),
            Err(SpecError::Bad(0, _))
        ));
        let two_readers = parse_stages(&words(&[
            "a", "-", "pipe:p", "", "", "0", "1", "a", "b", "pipe:p", "-", "", "", "0", "1", "b",
            "c", "pipe:p", "-", "", "", "0", "1", "c",
        ]))
        .unwrap();
        assert!(matches!(channels(&two_readers), Err(SpecError::Channel(n, _)) if n == "p"));
        let no_writer = parse_stages(&words(&["b", "pipe:p", "-", "", "", "0", "1", "b"])).unwrap();
        assert!(matches!(channels(&no_writer), Err(SpecError::Channel(n, _)) if n == "p"));
    }

    #[test]
    fn what_the_stages_said_names_the_stage_and_its_channels() {
        let s = linear();
        let zbuf = labelled(
            "zbuf: /dev/fd/12: empty input\nzbuf: /dev/fd/1: x\n",
            &s[4],
            &[(12, "from-3".into())],
        );
        assert_eq!(zbuf, "zbuf: from-3: empty input\nzbuf: /dev/fd/1: x\n");
        let mut leaf = s[1].clone();
        leaf.label = "scanconv (leaf 2)".into();
        assert_eq!(
            labelled("scanconv: bad\nsplitter y=0 (node 2): 5\n", &leaf, &[]),
            "scanconv (leaf 2): bad\nsplitter y=0 (node 2): 5\n"
        );
        assert_eq!(
            labelled("render: zbuf failed\nrender.sh: old\n", &s[2], &[]),
            "host a: zbuf failed\nhost a: old\n"
        );
        assert_eq!(
            name_channels("/dev/fd/123 /dev/fd/12 /dev/fd/", &[(12, "x".into())]),
            "/dev/fd/123 x /dev/fd/"
        );
    }

    #[test]
    fn the_cause_is_one_killed_or_else_the_most_upstream() {
        assert_eq!(cause(&[Some(0), None, Some(1), Some(1)]), Some(2));
        assert_eq!(cause(&[Some(0), Some(1), Some(137), None]), Some(2));
        assert_eq!(cause(&[Some(0), None]), None);
        assert_eq!(describe(137), "killed by SIGKILL");
        assert_eq!(describe(2), "status 2");
        assert_eq!(what_node(5, 2), "leaf 1");
        assert_eq!(what_node(3, 2), "subtree 3");
        assert_eq!(empty_from("zbuf: from-5: empty input: expected"), Some(5));
        assert_eq!(empty_from("zbuf: stdin: empty input"), None);
    }

    #[test]
    fn times_are_a_line_a_stage_and_their_sums() {
        let s = linear();
        let cost = |user_s, system_s, peak_kib, ended_s| Cost {
            user_s,
            system_s,
            peak_kib,
            ended_s,
        };
        let costs = [
            cost(0.0061, 0.0005, 3174, 0.031),
            cost(0.002, 0.0, 1024, 0.04),
        ];
        assert_eq!(
            times(&s[..2], &costs, "render"),
            "render: viewxf: 6.6 ms CPU (6.1 user, 0.5 system), 3.1 MB peak, ended at 31.0 ms\n\
             render: splitter (node 1): 2.0 ms CPU (2.0 user, 0.0 system), 1.0 MB peak, ended at 40.0 ms\n\
             render: 2 stages: 8.6 ms CPU, 4.1 MB of peaks, the last ended at 40.0 ms\n"
        );
    }

    #[test]
    fn links_count_the_bytes_each_host_carried() {
        let s = linear();
        let said = vec![
            String::new(),
            "splitter x=0 (node 1): 10 polygons; 700 and 300 bytes out\n".into(),
            String::new(),
            String::new(),
            "zbuf: from-2: 3 runs, 40 bytes in\nzbuf: from-3: 1 runs, 9 bytes in\n".into(),
        ];
        assert_eq!(
            links(&s, &said, 1, "render"),
            "render: leaf 0 on host a: 700 bytes there, 40 bytes back\n\
             render: leaf 1 on host b: 300 bytes there, 9 bytes back\n"
        );
    }

    #[test]
    fn a_graph_runs_and_its_failure_is_named() {
        // Stage a writes into a pipe that stage b reads; each a shell script.
        let two = |a: &str, b: &str| {
            let sh = |label: &str, input: End, output: End, script: &str| Stage {
                label: label.into(),
                input,
                output,
                host: None,
                argv: words(&["sh", "-c", script]),
                pipes: 0,
            };
            let null = || End::Path("/dev/null".into());
            let pipe = || End::Pipe("p".into());
            let stages = vec![sh("a", null(), pipe(), a), sh("b", pipe(), null(), b)];
            run(stages, Options::default(), "render").unwrap()
        };
        assert_eq!(
            two(
                "echo hi; echo a: said >&2",
                "cat >/dev/null; echo b: done >&2"
            ),
            Outcome {
                status: 0,
                message: "a: said\nb: done\n".into()
            }
        );
        assert_eq!(
            two(
                "echo a: bad >&2; exit 2",
                "cat >/dev/null; echo b: short >&2; exit 1"
            ),
            Outcome {
                status: 2,
                message: "a: bad\nrender: a failed (status 2)\n".into()
            }
        );
    }

    /// `sh -c SCRIPT` as a stage labelled `label`.
    fn sh(label: &str, input: End, output: End, script: &str) -> Stage {
        Stage {
            label: label.into(),
            input,
            output,
            host: None,
            argv: words(&["sh", "-c", script]),
            pipes: 0,
        }
    }

    #[test]
    fn stages_started_early_join_the_rest_through_their_open_channel() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let null = || End::Path("/dev/null".into());
        // The first stage writes into `clipped`, which none of the early stages reads;
        // the whole graph names that channel `leaf-0`.
        let first = sh(
            "a",
            null(),
            End::Pipe("clipped".into()),
            "echo early; echo a: said >&2",
        );
        let early = start(vec![first.clone()], None, "render").unwrap();
        let mut renamed = first;
        renamed.output = End::Pipe("leaf-0".into());
        let full = vec![
            renamed,
            sh(
                "b",
                End::Pipe("leaf-0".into()),
                End::Path(out.clone()),
                "tr a-z A-Z; echo b: done >&2",
            ),
        ];
        assert_eq!(
            early.finish(full, Options::default()).unwrap(),
            Outcome {
                status: 0,
                message: "a: said\nb: done\n".into()
            }
        );
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "EARLY\n");
    }

    #[test]
    fn an_early_stage_that_fails_is_named_as_in_one_phase() {
        let null = || End::Path("/dev/null".into());
        let pipe = || End::Pipe("p".into());
        // It fails before the rest of the graph starts: the rest still starts, reads
        // its short input, and the early stage is the cause, with its own words.
        let first = sh(
            "viewxf",
            null(),
            pipe(),
            "echo 'viewxf: line 1: bad' >&2; exit 1",
        );
        let early = start(vec![first.clone()], None, "render").unwrap();
        std::thread::sleep(Duration::from_millis(50));
        let full = vec![
            first,
            sh(
                "zbuf",
                pipe(),
                null(),
                "cat >/dev/null; echo 'zbuf: empty input' >&2; exit 1",
            ),
        ];
        assert_eq!(
            early.finish(full, Options::default()).unwrap(),
            Outcome {
                status: 1,
                message: "viewxf: line 1: bad\nrender: viewxf failed (status 1)\n".into()
            }
        );
    }

    #[test]
    fn a_graph_that_does_not_begin_with_the_early_stages_is_refused() {
        let null = || End::Path("/dev/null".into());
        let pipe = || End::Pipe("p".into());
        let early = start(vec![sh("a", null(), pipe(), "cat")], None, "render").unwrap();
        let other = vec![
            sh("a", null(), pipe(), "cat -u"),
            sh("b", pipe(), null(), "cat"),
        ];
        assert_eq!(
            early.finish(other, Options::default()),
            Err(SpecError::Bad(0, "not the stage started early".into()))
        );
        assert!(matches!(
            channels(&[sh("a", null(), pipe(), "cat")]),
            Err(SpecError::Channel(n, _)) if n == "p"
        ));
    }
}
