//! chart's errors as a stage's: its library passes errors up as `anyhow` errors with
//! context; at the top they become one [`stagecli::Error`], so that chart prints and exits
//! as every stage does ([`stagecli::report`]: 0 when the reader went away, 1 data, 2
//! usage, 3 I/O).
//!
//! The kind is decided where the error is made, as in the stages: a [`stagecli::Error`]
//! made there ([`stagecli::Error::usage`] for a bad scene argument,
//! [`stagecli::Error::io`] for a scene that cannot be read) keeps its kind through the
//! context added above it. An operating-system error is I/O (the reader going away when it
//! is a broken pipe), as `stagecli` converts it; anything else is data.

use proto::StreamError;
use stagecli::error::io_message;
use stagecli::{Error, Kind};
use std::io;

/// `e` as a stage's error: its contexts and its cause joined by `: ` (anyhow's `{:#}`),
/// an OS error said once and without `(os error N)`, and the kind of the cause.
pub fn stage_error(e: &anyhow::Error) -> Error {
    let mut said = Vec::new();
    let mut kind = Kind::Data;
    for cause in e.chain() {
        // The first cause whose kind is known ends the message: its own sources would
        // only say it again (a StreamError::Io's source is its io::Error).
        if let Some((k, text)) = known(cause) {
            kind = k;
            said.push(text);
            break;
        }
        said.push(cause.to_string());
    }
    Error::new(kind, said.join(": "))
}

/// The kind and text of a cause whose kind is known by its type.
fn known(cause: &(dyn std::error::Error + 'static)) -> Option<(Kind, String)> {
    if let Some(e) = cause.downcast_ref::<Error>() {
        return Some((e.kind(), e.message().to_string()));
    }
    let os = |e: &io::Error| {
        let kind = if e.kind() == io::ErrorKind::BrokenPipe {
            Kind::ReaderGone
        } else {
            Kind::Io
        };
        (kind, io_message(e))
    };
    if let Some(e) = cause.downcast_ref::<io::Error>() {
        return Some(os(e));
    }
    if let Some(e) = cause.downcast_ref::<StreamError>() {
        return Some(match e {
            StreamError::Io(io) => os(io),
            other => (Kind::Data, other.to_string()),
        });
    }
    if let Some(csv::ErrorKind::Io(e)) = cause.downcast_ref::<csv::Error>().map(csv::Error::kind) {
        return Some(os(e));
    }
    if let Some(image::ImageError::IoError(e)) = cause.downcast_ref::<image::ImageError>() {
        return Some(os(e));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use anyhow::Context;

    #[test]
    fn a_stage_error_keeps_its_kind_under_context() {
        let e = anyhow::Error::from(Error::usage("bad size")).context("scene x@0x5");
        let s = stage_error(&e);
        assert_eq!(
            (s.kind(), s.message()),
            (Kind::Usage, "scene x@0x5: bad size")
        );
    }

    #[test]
    fn os_errors_are_io_said_once_and_a_broken_pipe_is_the_reader_gone() {
        let e: anyhow::Result<()> = Err(StreamError::Io(io::Error::from_raw_os_error(21)).into());
        let s = stage_error(&e.context("reading /tmp").unwrap_err());
        assert_eq!(
            (s.kind(), s.message()),
            (Kind::Io, "reading /tmp: Is a directory")
        );
        let pipe = anyhow::Error::from(io::Error::from(io::ErrorKind::BrokenPipe));
        assert_eq!(stage_error(&pipe).kind(), Kind::ReaderGone);
        let full = anyhow::Error::from(io::Error::from_raw_os_error(28)).context("cannot write x");
        let s = stage_error(&full);
        assert_eq!(
            (s.kind(), s.message()),
            (Kind::Io, "cannot write x: No space left on device")
        );
    }

    #[test]
    fn anything_else_is_data() {
        let e = anyhow::anyhow!("no overall row").context("zspec compare");
        let s = stage_error(&e);
        assert_eq!(
            (s.kind(), s.message()),
            (Kind::Data, "zspec compare: no overall row")
        );
    }
}
