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
//!    the rest (TERM, KILL a second later), writes only the cause's words (its one
//!    line, when it exited 1 to 3 and said why; else they and `render: STAGE failed
//!    (status N)`), and exits with the stage's class of
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
//!
//! The plan of processes is [`plan`], the supervisor [`supervise`], what is told of
//! the run [`report`], the progress shown while it runs [`progress`].

pub mod plan;
pub mod progress;
pub mod report;
pub mod supervise;

pub use plan::{channels, channels_open, Channel, End, OpenChannels, SpecError, Stage};
pub use report::{
    cause, describe, labelled, links, shell_status, tell, times, what_node, Cost, Outcome,
};
pub use supervise::{run, start, Early, Feed, Options};
