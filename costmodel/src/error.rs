//! The cost model's errors: one type for the library, whose kind is the exit status a
//! command gives it (the stages' policy, `stagecli`: 1 bad data, 2 usage, 3 I/O or the
//! machine's limits, 0 when the reader of the output went away). The kind is decided
//! where the error is made, as in the stages, and context added on the way up
//! ([`Context`]) keeps it; a main turns it into a [`stagecli::Error`] by `From`, printed
//! once as `plan: message`.

use proto::StreamError;
use std::fmt::Display;

/// An error of the cost model, by kind, with its one-line message.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum Error {
    /// A scene, a constants file or a measured run that is not what it should be.
    /// Status 1.
    #[error("{0}")]
    Data(String),
    /// Bad words from the user (a camera option, an option's value). Status 2.
    #[error("{0}")]
    Usage(String),
    /// A file or folder that cannot be made, read or written, a program that cannot be
    /// started, no cache folder. Status 3.
    #[error("{0}")]
    Io(String),
    /// The reader of the output went away (`plan predict … | head`): nothing wrong.
    /// Status 0, quietly.
    #[error("{0}")]
    ReaderGone(String),
}

/// A result of the cost model's.
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

    /// The exit status a command gives this error: 1, 2, 3, or 0 for the reader gone.
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
}

impl From<stagecli::Error> for Error {
    fn from(e: stagecli::Error) -> Self {
        let m = e.message().to_string();
        match e.kind() {
            stagecli::Kind::Data => Error::Data(m),
            stagecli::Kind::Usage => Error::Usage(m),
            stagecli::Kind::Io => Error::Io(m),
            stagecli::Kind::ReaderGone => Error::ReaderGone(m),
        }
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

/// A constants file that is not the model's TOML is data.
impl From<toml::de::Error> for Error {
    fn from(e: toml::de::Error) -> Self {
        Error::Data(e.to_string().trim_end().replace('\n', " "))
    }
}

/// Constants that cannot be written as TOML (a non-finite number) are data.
impl From<toml::ser::Error> for Error {
    fn from(e: toml::ser::Error) -> Self {
        Error::Data(e.to_string())
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

    #[test]
    fn each_kind_is_its_exit_status_through_context() {
        let missing = std::fs::read("/nonexistent/polypipe/model.toml")
            .context("cannot read /nonexistent/polypipe/model.toml")
            .unwrap_err();
        assert_eq!(
            (missing.status(), missing.message()),
            (
                3,
                "cannot read /nonexistent/polypipe/model.toml: No such file or directory"
            )
        );
        let bad = crate::model::Constants::parse("overheads = 3")
            .context("reading m.toml")
            .unwrap_err();
        assert_eq!(bad.status(), 1, "{bad}");
        assert!(bad.message().starts_with("reading m.toml: "), "{bad}");
        let usage = Error::from(stagecli::Error::usage("--size 0x0")).context("camera");
        assert_eq!(
            (usage.status(), usage.to_string().as_str()),
            (2, "camera: --size 0x0")
        );
        let gone = Error::from(std::io::Error::from(std::io::ErrorKind::BrokenPipe));
        assert_eq!(gone.status(), 0);
        // A main's error, printed once: the kind and the whole message kept.
        let s = stagecli::Error::from(missing);
        assert_eq!(s.kind(), stagecli::Kind::Io);
        assert_eq!(
            s.message(),
            "cannot read /nonexistent/polypipe/model.toml: No such file or directory"
        );
    }
}
