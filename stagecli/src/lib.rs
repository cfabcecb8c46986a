//! # stagecli: the skeleton every polypipe stage binary shares
//!
//! `proto` is the stream and the geometry, usable by any program; this crate is how a
//! *stage binary* uses it: its command-line conventions ([`parse`], [`TextFlag`],
//! [`ViewArgs`], `--version` everywhere), opening its inputs and outputs and the
//! read-transform-write loop ([`filter_polygons`]), and how it reports an error and exits
//! ([`main`], [`report`]).
//!
//! ## Errors and exit statuses
//!
//! Errors travel as [`Error`] values, each carrying its [`Kind`], decided where the error
//! is made. At the top, [`report`] prints one line, `stage: message`, on stderr (nothing
//! when the reader of our output went away) and exits with the kind's status:
//!
//! | status | kind | meaning |
//! |--------|------|---------|
//! | 0 | — / [`Kind::ReaderGone`] | success; also when the reader of our output went away (`… \| head`), quietly |
//! | 1 | [`Kind::Data`] | the input is not a valid stream for this stage, or a record in it cannot be processed (the message says where) |
//! | 2 | [`Kind::Usage`] | bad command-line arguments, found before any input is read |
//! | 3 | [`Kind::Io`] | an input or output could not be opened, read or written, or the screen is too large for this machine's memory ([`memory::check_screen`]) |
//!
//! A comparison (`zspec compare`) exits as cmp does instead ([`report_cmp`]): 0 the
//! same, 1 different, 2 trouble (a usage error, a file that is not a PPM, a missing
//! file).
//!
//! Usage errors are one line too, naming the option as the user typed it: clap's
//! several-line messages are joined ([`args::usage_line`]), with clap's status 2.
//! `--help` and `--version` print as usual and exit 0.

pub mod antialias;
pub mod args;
pub mod error;
pub mod filter;
pub mod memory;
pub mod names;
pub mod numbers;
pub mod pieces;
pub mod place;
pub mod progress;
pub mod project;
pub mod remote;
pub mod stats;
pub mod stream;
pub mod whole;

pub use antialias::AntialiasArgs;
pub use args::{parse, parse_colour, DepthArg, PpmTextFlag, TextFlag, ViewArgs};
pub use error::{Context, Error, Kind, Result};
pub use filter::filter_polygons;
pub use names::FrameNames;
pub use project::ProjectArgs;
pub use stream::{
    check_finite, check_finite_after, filter_records, input_error, input_name, next, open_input,
    open_output, read_stdin, refuse_transparent, same_file, stdout, write_stdout, Branch, Counted,
    Counts, Named, RawStdout,
};

use std::io::Write;
use std::process::ExitCode;

/// A stage's `main`: parses the command line into `C` (a usage error exits 2 at once),
/// runs `body` and [`report`]s its result.
pub fn main<C: clap::Parser>(stage: &str, body: impl FnOnce(C) -> Result<()>) -> ExitCode {
    stream::widen_pipe(0);
    stream::widen_pipe(1);
    match parse::<C>(stage) {
        Ok(cli) => report(stage, body(cli)),
        Err(code) => code,
    }
}

/// Ends a stage: prints `stage: message` for an error (unless the reader went away) and
/// gives the exit status of the table above.
pub fn report(stage: &str, result: Result<()>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => fail(stage, &e, e.kind().status()),
    }
}

/// Ends a comparison, as cmp does: `Ok(true)` the same (0), `Ok(false)` different (1;
/// the comparison has said how on its own), an error trouble (2, with its message).
pub fn report_cmp(stage: &str, result: Result<bool>) -> ExitCode {
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => fail(stage, &e, e.kind().cmp_status()),
    }
}

fn fail(stage: &str, e: &Error, status: u8) -> ExitCode {
    if e.kind() != Kind::ReaderGone {
        // stderr itself may be gone; there is no one left to tell then.
        let _ = writeln!(std::io::stderr(), "{stage}: {e}");
    }
    ExitCode::from(status)
}
