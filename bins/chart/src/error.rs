//! chart's errors: one type for the library, whose kind is the exit status chart gives it
//! (the stages' policy, `stagecli`: 1 bad data, 2 usage, 3 I/O or the machine's limits, 0
//! when the reader of the output went away). The kind is decided where the error is made,
//! as in the stages and the cost model (`costmodel::Error`, whose shape this is): a bad
//! scene argument is usage, a scene that cannot be read I/O, a broken pipe the reader
//! gone, a run that failed data; context added on the way up ([`Context`]) keeps it.
//! chart's main turns it into a [`stagecli::Error`] by `From`, printed once as
//! `chart: message`.

use proto::StreamError;
use std::fmt::Display;

/// An error of the chart, by kind, with its one-line message.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum Error {
    /// A scene, a CSV file or a measured run that is not what it should be. Status 1.
    #[error("{0}")]
    Data(String),
    /// Bad words from the user (a scene's `@WxH`, a missing `-o`). Status 2.
    #[error("{0}")]
    Usage(String),
    /// A file or folder that cannot be made, read or written, a program that cannot be
    /// started. Status 3.
    #[error("{0}")]
    Io(String),
    /// The reader of the output went away (`chart … | head`): nothing wrong. Status 0,
    /// quietly.
    #[error("{0}")]
    ReaderGone(String),
}

/// A result of the chart's.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// The stages' kind of this error, which gives the exit status.
    pub fn kind(&self) -> stagecli::Kind {
        match self {
            Error::Data(_) => stagecli::Kind::Data,
            Error::Usage(_) => stagecli::Kind::Usage,
            Error::Io(_) => stagecli::Kind::Io,
            Error::ReaderGone(_) => stagecli::Kind::ReaderGone,
        }
    }

    /// The exit status chart gives this error: 1, 2, 3, or 0 for the reader gone.
    pub fn status(&self) -> u8 {
        self.kind().status()
    }

    /// The message, without the kind.
    pub fn message(&self) -> &str {
        match self {
            Error::Data(m) | Error::Usage(m) | Error::Io(m) | Error::ReaderGone(m) => m,
        }
    }

    /// The same error, its message prefixed with `context: `.
    pub fn context(self, context: impl Display) -> Self {
        let with = |m: String| format!("{context}: {m}");
        match self {
            Error::Data(m) => Error::Data(with(m)),
            Error::Usage(m) => Error::Usage(with(m)),
            Error::Io(m) => Error::Io(with(m)),
            Error::ReaderGone(m) => Error::ReaderGone(with(m)),
        }
    }

    /// An error of `kind` saying `message`.
    pub fn new(kind: stagecli::Kind, message: impl Into<String>) -> Self {
        let m = message.into();
        match kind {
            stagecli::Kind::Data => Error::Data(m),
            stagecli::Kind::Usage => Error::Usage(m),
            stagecli::Kind::Io => Error::Io(m),
            stagecli::Kind::ReaderGone => Error::ReaderGone(m),
        }
    }
}

impl From<stagecli::Error> for Error {
    fn from(e: stagecli::Error) -> Self {
        Error::new(e.kind(), e.message())
    }
}

/// The cost model's errors keep their kind (a scene that cannot be opened is I/O, a bad
/// camera option usage).
impl From<costmodel::Error> for Error {
    fn from(e: costmodel::Error) -> Self {
        Error::new(e.kind(), e.message())
    }
}

/// An operating-system error is I/O, or the reader gone for a broken pipe, said as a
/// person reads it (`No such file or directory`), as the stages say it.
impl From<std::io::Error> for Error {
    fn from(e: std::io::Error) -> Self {
        stagecli::Error::from(e).into()
    }
}

/// A stream's grammar is data, its reading I/O.
impl From<StreamError> for Error {
    fn from(e: StreamError) -> Self {
        stagecli::Error::from(e).into()
    }
}

/// A CSV file's reading or writing is I/O; its contents that are not the rows', data.
impl From<csv::Error> for Error {
    fn from(e: csv::Error) -> Self {
        let text = e.to_string();
        match e.into_kind() {
            csv::ErrorKind::Io(io) => io.into(),
            _ => Error::Data(text),
        }
    }
}

/// A picture that cannot be written is I/O; one that cannot be encoded, data.
impl From<image::ImageError> for Error {
    fn from(e: image::ImageError) -> Self {
        match e {
            image::ImageError::IoError(io) => io.into(),
            other => Error::Data(other.to_string()),
        }
    }
}

impl From<Error> for stagecli::Error {
    fn from(e: Error) -> Self {
        let kind = e.kind();
        stagecli::Error::new(kind, e.message())
    }
}

/// Context on the way up, keeping the kind: `.context("reading x")?`.
pub trait Context<T> {
    fn context(self, context: impl Display) -> Result<T>;
    fn with_context<D: Display>(self, context: impl FnOnce() -> D) -> Result<T>;
}

impl<T, E: Into<Error>> Context<T> for std::result::Result<T, E> {
    fn context(self, context: impl Display) -> Result<T> {
        self.map_err(|e| e.into().context(context))
    }

    fn with_context<D: Display>(self, context: impl FnOnce() -> D) -> Result<T> {
        self.map_err(|e| e.into().context(context()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io;

    /// Each kind, made where the error is, gives its status through the context added
    /// above it, and reaches a main's [`stagecli::Error`] with its kind and whole message.
    #[test]
    fn each_kind_is_its_exit_status_through_context() {
        let cases: [(Error, u8, &str); 4] = [
            (
                Error::Data("no overall row".into()),
                1,
                "zspec compare: no overall row",
            ),
            (
                stagecli::Error::usage("bad size").into(),
                2,
                "zspec compare: bad size",
            ),
            (
                io::Error::from_raw_os_error(28).into(),
                3,
                "zspec compare: No space left on device",
            ),
            (
                io::Error::from(io::ErrorKind::BrokenPipe).into(),
                0,
                "zspec compare: broken pipe",
            ),
        ];
        for (e, status, message) in cases {
            let e = Err::<(), _>(e)
                .context("zspec compare")
                .context("outer")
                .unwrap_err();
            assert_eq!(e.status(), status, "{e}");
            assert_eq!(e.message(), format!("outer: {message}"));
            let s = stagecli::Error::from(e.clone());
            assert_eq!((s.kind(), s.message()), (e.kind(), e.message()));
        }
    }

    #[test]
    fn os_errors_are_io_said_once() {
        let e = Err::<(), _>(StreamError::Io(io::Error::from_raw_os_error(21)))
            .context("reading /tmp")
            .unwrap_err();
        assert_eq!(e, Error::Io("reading /tmp: Is a directory".into()));
        let e = std::fs::read("/nonexistent/polypipe/s.txt")
            .with_context(|| "cannot open /nonexistent/polypipe/s.txt")
            .unwrap_err();
        assert_eq!(
            e,
            Error::Io("cannot open /nonexistent/polypipe/s.txt: No such file or directory".into())
        );
    }

    #[test]
    fn the_libraries_errors_keep_their_kind() {
        let e = Error::from(costmodel::Error::Usage("--size 0x0".into())).context("camera");
        assert_eq!((e.status(), e.message()), (2, "camera: --size 0x0"));
        // A CSV file that cannot be read is I/O, one whose rows are not the chart's data.
        let missing = csv::Reader::from_path("/nonexistent/polypipe/results.csv")
            .map(|_| ())
            .context("cannot read /nonexistent/polypipe/results.csv")
            .unwrap_err();
        assert_eq!(
            missing,
            Error::Io(
                "cannot read /nonexistent/polypipe/results.csv: No such file or directory".into()
            )
        );
        let rows: std::result::Result<Vec<(u32,)>, _> = csv::Reader::from_reader(&b"n\nx\n"[..])
            .deserialize()
            .collect();
        let bad = Error::from(rows.unwrap_err());
        assert_eq!(bad.status(), 1, "{bad}");
        let stream = Error::from(StreamError::Text {
            line: 2,
            column: 1,
            msg: "no".into(),
        });
        assert_eq!(stream.status(), 1, "{stream}");
    }
}
