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
//!    chunk: parallel chooses the host with a free job slot (`N/host` lines of the
//!    `--sshloginfile` farm writes), retries a chunk that failed on a host where it has
//!    not failed (`--retries`), reads the file again when farm drops a failing host from
//!    it (`watch`), and stops starting chunks after one failed on every try (`--halt
//!    soon,fail=1`);
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
//! parallel wakes, reaps, and retries the chunk. They take job numbers, so `--resume`
//! knows a chunk by its frames ([`finished_chunks`]), and checks them
//! ([`verify_frame`]). The job log, in parallel's format, is the shim's: a line a try.
//!
//! When a chunk fails on every try, the chunks before it are written whole and the run
//! ends with one line naming the host(s) and the chunk: status 3 for a host or the link,
//! the far render.sh's own status (1 or 2) for a fault it found in the movie or the
//! options. SIGINT and SIGTERM stop parallel and its jobs, and the run ends with 130 or
//! 143, as render.sh does; with `-o`, `--resume` renders only the chunks that did not
//! finish.

/// The frames of a chunk by default: few enough that the spool holds a few per host,
/// and enough that an ssh session's start (a connection, a render.sh and its choice of
/// depth there) is paid once for several frames.
pub const DEFAULT_CHUNK: u64 = 8;

/// Tries of a chunk by default, each on a host where it has not failed while there is
/// one (parallel's `--retries`).
pub const DEFAULT_RETRIES: u32 = 3;

mod checks;
mod cutter;
mod driver;
mod files;
pub use files::make_folder;
mod hosts;
mod joblog;
mod report;
mod resume;
mod shim;
mod slurm;
mod spool;
mod supervise;
mod watch;

pub use checks::{
    check_frames, classify, every_try_failed, frames_text, last_line, next_frame, parse_hosts,
    remote_command, verify_frame, ChunkInfo, Failure, Frame, Output, Try,
};
pub use cutter::{count_frames, Chunk, Cutter};
pub use driver::{find_parallel, run, Options};
pub use hosts::{logins_from_hosts, slots_in_sshloginfile, Logins};
pub use joblog::{
    chunk_arg, chunk_of_command, finished_chunks, joblog_path, parse_joblog, JobLine, IDLE_ARG,
    JOBLOG_HEADER,
};
pub use shim::shim_script;
pub use slurm::{
    array_tasks, check_frames_of, check_script, sbatch_path_ok, sbatch_script, SlurmArray,
};
pub use spool::{failed_chunk, spool_bound};
pub use supervise::{adopt_orphans, catch_stop_signals, Outcome};
pub use watch::{DEFAULT_HOST_FAILURES, DEFAULT_HOST_TIMEOUT};
