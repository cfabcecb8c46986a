//! How every polypipe binary starts, reports an error and exits.
//!
//! Errors travel as values up to [`run`], which prints one line, `stage: message`, and
//! chooses the exit status:
//!
//! | status | meaning |
//! |--------|---------|
//! | 0 | success; also when the reader of our output went away (`… \| head`) |
//! | 1 | the input is not a valid stream for this stage (the message says where) |
//! | 2 | usage: bad command-line arguments (clap's own status) |
//! | 3 | an input or output could not be opened, read or written |

use crate::StreamError;
use std::fs::File;
use std::io::{self, Read};
use std::process::ExitCode;

pub const EXIT_INVALID_INPUT: u8 = 1;
pub const EXIT_USAGE: u8 = 2;
pub const EXIT_IO: u8 = 3;

/// Runs a stage's body and turns its result into a message and an exit status.
pub fn run(stage: &str, body: impl FnOnce() -> anyhow::Result<()>) -> ExitCode {
    match body() {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            let status = exit_status(&err);
            if status != 0 {
                eprintln!("{stage}: {err:#}");
            }
            ExitCode::from(status)
        }
    }
}

/// The exit status an error gets: 0 for a closed output pipe, 3 for other I/O failures,
/// 1 for everything the input is to blame for.
pub fn exit_status(err: &anyhow::Error) -> u8 {
    for cause in err.chain() {
        if let Some(e) = cause.downcast_ref::<StreamError>() {
            return match e {
                StreamError::Io(io) if io.kind() == io::ErrorKind::BrokenPipe => 0,
                StreamError::Io(_) => EXIT_IO,
                _ => EXIT_INVALID_INPUT,
            };
        }
        if let Some(e) = cause.downcast_ref::<io::Error>() {
            return if e.kind() == io::ErrorKind::BrokenPipe {
                0
            } else {
                EXIT_IO
            };
        }
    }
    EXIT_INVALID_INPUT
}

/// Opens an input named on the command line; `-` is standard input.
pub fn open_input(path: &str) -> anyhow::Result<Box<dyn Read + Send>> {
    use anyhow::Context;
    if path == "-" {
        Ok(Box::new(io::stdin()))
    } else {
        let f = File::open(path).with_context(|| format!("cannot open {path}"))?;
        Ok(Box::new(f))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use anyhow::Context;

    #[test]
    fn statuses() {
        let pipe: anyhow::Error = StreamError::Io(io::ErrorKind::BrokenPipe.into()).into();
        assert_eq!(exit_status(&pipe.context("writing")), 0);
        let bad: anyhow::Error = StreamError::Invalid("x".into()).into();
        assert_eq!(exit_status(&bad), 1);
        let missing =
            Err::<(), _>(io::Error::from(io::ErrorKind::NotFound)).context("cannot open x");
        assert_eq!(exit_status(&missing.unwrap_err()), 3);
    }
}
