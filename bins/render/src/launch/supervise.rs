//! The supervisor: makes the channels, starts the stages, reads their stderr as they
//! run, takes their ends and the user's stop on a signalfd, and stops the rest when one
//! fails; [`super::report`] words how it ended.

use super::plan::{channels, channels_open, Channel, End, SpecError, Stage};
use super::report::{cause, labelled, shell_status, silent_host, Cost, Ended, Outcome};
use std::ffi::OsString;
use std::io::Read;
use std::io::Write;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd, RawFd};
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::process::{Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

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
    /// A stage on a host that sends nothing for this long fails the run (`--host-timeout`;
    /// `None` waits for ever).
    pub host_timeout: Option<Duration>,
    /// The tree's depth, for naming the hosts' nodes.
    pub depth: u32,
    /// Print the hosts' links' bytes on success (`--stats --hosts`).
    pub links: bool,
    /// Print what each stage cost on success ([`Cost`], `render --times`).
    pub times: bool,
    /// The stage that reads the launcher's stdin reads this instead.
    pub feed: Option<Feed>,
    /// Show progress on stderr ([`super::progress`]); the stages are told to report it
    /// by the environment render sets for them (`POLYPIPE_PROGRESS`).
    pub progress: bool,
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
    /// For a stage on a host: when it last sent anything ([`Heard`]).
    heard: Vec<Option<Arc<Heard>>>,
    /// Where each stage's unread progress lines begin in `said`, and the frames it has
    /// said it finished ([`stagecli::progress`]).
    marks_from: Vec<usize>,
    frames: Vec<u64>,
    shown: Option<super::progress::Shown>,
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
                if let Some(h) = &self.heard[i] {
                    h.now();
                }
                let done = stagecli::progress::take(&mut self.said[i], &mut self.marks_from[i]);
                if done > 0 {
                    self.frames[i] += done;
                    if let Some(shown) = &self.shown {
                        shown.update(&self.frames);
                    }
                }
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
        heard: Vec::new(),
        marks_from: vec![0; n],
        frames: vec![0; n],
        shown: None,
    };
    let mut ends = Ends::new(n);
    let mut pending = Vec::new();
    let mut heard = vec![None; n];
    let made = (|| -> std::io::Result<()> {
        for (name, ch) in &chans {
            join(&run.stages, ch, name, &mut ends, &mut heard)?;
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
    run.heard = heard;
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
        let mut heard = std::mem::take(&mut run.heard);
        heard.resize(n, None);
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
                if let Err(e) = join(&full, ch, name, &mut ends, &mut heard) {
                    return Ok(Err(e));
                }
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
        run.marks_from.resize(n, 0);
        run.frames.resize(n, 0);
        run.heard = heard;
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

    /// The first stage on a host, still running, that has sent nothing (on its stdout or
    /// its stderr) for `timeout`, while nothing here kept it waiting.
    fn silent(&self, timeout: Duration) -> Option<usize> {
        (0..self.stages.len()).find(|&i| {
            self.exits[i].is_none()
                && self.pids[i].is_some()
                && self.heard[i]
                    .as_ref()
                    .is_some_and(|h| h.silent_for() >= timeout)
        })
    }

    /// Watches every stage to its end, and says how the run ended; the progress shown
    /// meanwhile, when asked, is ended before the outcome is told.
    fn watch(mut self, options: &Options, me: &str) -> Result<Outcome, SpecError> {
        if options.progress {
            self.shown = Some(super::progress::Shown::new(&self.stages, me));
        }
        let outcome = self.watch_to_end(options, me);
        if let Some(shown) = self.shown.take() {
            shown.end(matches!(&outcome, Ok(o) if o.status == 0));
        }
        outcome
    }

    fn watch_to_end(&mut self, options: &Options, me: &str) -> Result<Outcome, SpecError> {
        let run = self;
        let n = run.stages.len();
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
            if let Some((i, t)) = options
                .host_timeout
                .and_then(|t| run.silent(t).map(|i| (i, t)))
            {
                run.stop_all();
                let said = run.labelled(i);
                return Ok(silent_host(&run.stages[i], &said, options.depth, t, me));
            }
        }

        let cause = failed_at.and_then(|_| cause(&run.statuses()));
        if cause.is_some() {
            run.stop_all();
        }
        let ended = Ended {
            stages: &run.stages,
            said: (0..n).map(|i| run.labelled(i)).collect(),
            raw: &run.said,
            exits: &run.exits,
            costs: &run.costs,
            depth: options.depth,
            links: options.links,
            times: options.times,
        };
        Ok(ended.outcome(cause, me))
    }
}

/// When a stage on a host last sent anything: a byte on its stdout (through [`relay`])
/// or its stderr. While the relay waits on the stage's reader, the host is not silent:
/// it is this side that is slow.
#[derive(Debug)]
struct Heard {
    since: Instant,
    /// Milliseconds from `since` to the last byte.
    last_ms: AtomicU64,
    /// The relay is writing to the reader, or is done (the stdout ended).
    not_waiting: AtomicBool,
}

impl Heard {
    fn new() -> Heard {
        Heard {
            since: Instant::now(),
            last_ms: AtomicU64::new(0),
            not_waiting: AtomicBool::new(false),
        }
    }

    fn now(&self) {
        let ms = u64::try_from(self.since.elapsed().as_millis()).unwrap_or(u64::MAX);
        self.last_ms.fetch_max(ms, Ordering::Relaxed);
    }

    /// How long the host has been silent while the relay waited for it.
    fn silent_for(&self) -> Duration {
        if self.not_waiting.load(Ordering::Relaxed) {
            return Duration::ZERO;
        }
        let last = Duration::from_millis(self.last_ms.load(Ordering::Relaxed));
        self.since.elapsed().saturating_sub(last)
    }
}

/// Makes a channel's pipe, its ends given to its writer and its reader. Out of a stage on
/// a host, two pipes with a [`relay`] between them, which notes when the host last sent
/// anything (`--host-timeout`).
fn join(
    stages: &[Stage],
    ch: &Channel,
    name: &str,
    ends: &mut Ends,
    heard: &mut [Option<Arc<Heard>>],
) -> std::io::Result<()> {
    let (r, w) = pipe()?;
    let (i, arg) = ch.writer;
    if stages[i].host.is_none() || arg.is_some() {
        ends.writer(ch.writer, w, name);
        ends.reader(ch.reader, r, name);
        return Ok(());
    }
    let (r2, w2) = pipe()?;
    ends.writer(ch.writer, w, name);
    ends.reader(ch.reader, r2, name);
    let h = Arc::new(Heard::new());
    heard[i] = Some(h.clone());
    std::thread::spawn(move || relay(r, w2, &h));
    Ok(())
}

/// Copies what a host sends into its reader's pipe, noting when each byte came. Ends with
/// the host's stdout, or when the reader has gone.
fn relay(from: OwnedFd, to: OwnedFd, heard: &Heard) {
    let (mut from, mut to) = (std::fs::File::from(from), std::fs::File::from(to));
    let mut buf = vec![0u8; 1 << 16];
    loop {
        let n = match from.read(&mut buf) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(_) => break,
        };
        heard.now();
        heard.not_waiting.store(true, Ordering::Relaxed);
        let gone = to.write_all(&buf[..n]).is_err();
        heard.now();
        heard.not_waiting.store(false, Ordering::Relaxed);
        if gone {
            break;
        }
    }
    heard.not_waiting.store(true, Ordering::Relaxed);
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

#[cfg(test)]
mod tests {
    use super::super::plan::tests::words;
    use super::*;

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
                message: "a: bad\n".into()
            }
        );
        // A stage that failed saying nothing, or not by a status of the house's: named.
        for (script, status, said) in [
            ("exit 3", 3, "render: a failed (status 3)\n"),
            (
                "echo a: panicked >&2; exit 101",
                1,
                "a: panicked\nrender: a failed (status 101)\n",
            ),
            ("kill -KILL $$", 1, "render: a failed (killed by SIGKILL)\n"),
        ] {
            assert_eq!(
                two(script, "cat >/dev/null"),
                Outcome {
                    status,
                    message: said.into()
                },
                "{script}"
            );
        }
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
                message: "viewxf: line 1: bad\n".into()
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
