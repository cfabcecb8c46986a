//! Errors as values that carry their exit status.
//!
//! The kind of an error is decided where the error is made: a bad argument is
//! [`Error::usage`], a record the stage cannot take is [`Error::data`], a file that cannot
//! be opened is [`Error::io`]. Errors from the stream library convert by their own type:
//! [`StreamError`]'s grammar variants are data, its `Io` variant is I/O, and an
//! [`io::Error`] is I/O, or the reader going away when it is a broken pipe. Context
//! added on the way up ([`Context`]) keeps the kind.

pub use proto::StreamError;
use std::fmt;
use std::io;

/// What an error is, and so the status the stage exits with (docs/DESIGN.md, the error
/// policy).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Bad command-line arguments; checked before any input is read. Status 2.
    Usage,
    /// The input is not a valid stream for this stage, or a record in it cannot be
    /// processed (the message says where). Status 1.
    Data,
    /// An input or output could not be opened, read or written. Status 3.
    Io,
    /// The reader of our output went away (`… | head`): nothing is wrong with this
    /// stage, which ends quietly with status 0.
    ReaderGone,
}

impl Kind {
    /// The exit status of a stage: 0 reader gone, 1 data, 2 usage, 3 I/O.
    pub const fn status(self) -> u8 {
        match self {
            Kind::ReaderGone => 0,
            Kind::Data => 1,
            Kind::Usage => 2,
            Kind::Io => 3,
        }
    }

    /// The exit status of a comparison (`zspec compare`), in cmp's terms: 0 the same,
    /// 1 different (decided by the comparison, not by an error), 2 trouble: any error
    /// but the reader of the report going away.
    pub const fn cmp_status(self) -> u8 {
        match self {
            Kind::ReaderGone => 0,
            Kind::Data | Kind::Usage | Kind::Io => 2,
        }
    }
}

/// An error: its kind and a one-line message, printed after the stage's name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Error {
    kind: Kind,
    message: String,
}

/// A result whose error carries its exit status.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    pub fn new(kind: Kind, message: impl Into<String>) -> Self {
        Error {
            kind,
            message: message.into(),
        }
    }

    /// A bad command-line argument: the message names the option as the user typed it.
    pub fn usage(message: impl Into<String>) -> Self {
        Error::new(Kind::Usage, message)
    }

    /// Input this stage cannot take; the message says where in the input.
    pub fn data(message: impl Into<String>) -> Self {
        Error::new(Kind::Data, message)
    }

    /// A file that cannot be opened, read or written; the message names it.
    pub fn io(message: impl Into<String>) -> Self {
        Error::new(Kind::Io, message)
    }

    pub fn kind(&self) -> Kind {
        self.kind
    }

    pub fn message(&self) -> &str {
        &self.message
    }

    /// The same error, its message prefixed with `context: `.
    pub fn context(self, context: impl fmt::Display) -> Self {
        Error {
            kind: self.kind,
            message: format!("{context}: {}", self.message),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Error {}

/// An operating-system error as a person reads it: `No such file or directory`, without
/// the `(os error 2)` that the standard library appends.
pub fn io_message(e: &io::Error) -> String {
    let text = e.to_string();
    match e.raw_os_error() {
        Some(code) => text
            .strip_suffix(&format!(" (os error {code})"))
            .map_or_else(|| text.clone(), str::to_string),
        None => text,
    }
}

/// A size in bytes as a person reads it, for messages: `60 GiB`, `1.5 MiB`, `700 bytes`.
pub fn bytes_text(bytes: u64) -> String {
    let mut value = bytes as f64;
    let mut unit = "bytes";
    for u in ["KiB", "MiB", "GiB", "TiB"] {
        if value < 1024.0 {
            break;
        }
        value /= 1024.0;
        unit = u;
    }
    let text = format!("{value:.1}");
    format!("{} {unit}", text.strip_suffix(".0").unwrap_or(&text))
}

impl From<io::Error> for Error {
    fn from(e: io::Error) -> Self {
        let kind = if e.kind() == io::ErrorKind::BrokenPipe {
            Kind::ReaderGone
        } else {
            Kind::Io
        };
        Error::new(kind, io_message(&e))
    }
}

impl From<StreamError> for Error {
    fn from(e: StreamError) -> Self {
        match e {
            StreamError::Io(io) => io.into(),
            other => Error::data(other.to_string()),
        }
    }
}

/// Adds context to an error on its way up, keeping its kind (as anyhow's `Context`).
pub trait Context<T> {
    fn context(self, context: impl fmt::Display) -> Result<T>;
    fn with_context<C: fmt::Display>(self, context: impl FnOnce() -> C) -> Result<T>;
}

impl<T, E: Into<Error>> Context<T> for std::result::Result<T, E> {
    fn context(self, context: impl fmt::Display) -> Result<T> {
        self.map_err(|e| e.into().context(context))
    }

    fn with_context<C: fmt::Display>(self, context: impl FnOnce() -> C) -> Result<T> {
        self.map_err(|e| e.into().context(context()))
    }
}

/// A library's own error type, of the stages' kinds: `kinded_error!();` in a module
/// `error` of a library that is not a stage (the cost model, the chart) defines there
///
/// - `enum Error { Data(String), Usage(String), Io(String), ReaderGone(String) }`, whose
///   variant is the [`Kind`] and so the exit status a command gives it, decided where the
///   error is made (a library can match on it, as on any enum of its own);
/// - `kind`, `status`, `message`, `context` (prefixes `context: ` keeping the kind) and
///   `new(kind, message)`;
/// - conversions from [`Error`], [`io::Error`] (I/O, or the reader gone for a broken pipe,
///   said as the stages say it) and [`StreamError`] (grammar data, reading I/O), and into
///   [`Error`], which a main prints once as `name: message`;
/// - `Result<T>` and a `Context` trait adding context on the way up, keeping the kind,
///   from any error that converts into the library's.
///
/// One definition, so that every library's errors behave alike; each library adds the
/// conversions from the errors of the crates it alone uses (TOML, CSV, pictures), which
/// only it may write (Rust's orphan rule).
#[macro_export]
macro_rules! kinded_error {
    () => {
        /// An error of this library, by kind (the exit status), with its one-line message
        /// (`stagecli::kinded_error`).
        #[derive(Clone, Debug, PartialEq, Eq)]
        pub enum Error {
            /// A scene, a file's contents or a measured run that is not what it should
            /// be. Status 1.
            Data(String),
            /// Bad words from the user (an option's value, a scene's `@WxH`). Status 2.
            Usage(String),
            /// A file or folder that cannot be made, read or written, a program that
            /// cannot be started. Status 3.
            Io(String),
            /// The reader of the output went away (`… | head`): nothing wrong. Status 0,
            /// quietly.
            ReaderGone(String),
        }

        /// A result of this library's.
        pub type Result<T, E = Error> = std::result::Result<T, E>;

        impl Error {
            /// The stages' kind of this error, which gives the exit status.
            pub fn kind(&self) -> $crate::Kind {
                match self {
                    Error::Data(_) => $crate::Kind::Data,
                    Error::Usage(_) => $crate::Kind::Usage,
                    Error::Io(_) => $crate::Kind::Io,
                    Error::ReaderGone(_) => $crate::Kind::ReaderGone,
                }
            }

            /// The exit status a command gives this error: 1, 2, 3, or 0 for the reader
            /// gone.
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
            pub fn context(self, context: impl std::fmt::Display) -> Self {
                let kind = self.kind();
                Error::new(kind, format!("{context}: {}", self.message()))
            }

            /// An error of `kind` saying `message`.
            pub fn new(kind: $crate::Kind, message: impl Into<String>) -> Self {
                let m = message.into();
                match kind {
                    $crate::Kind::Data => Error::Data(m),
                    $crate::Kind::Usage => Error::Usage(m),
                    $crate::Kind::Io => Error::Io(m),
                    $crate::Kind::ReaderGone => Error::ReaderGone(m),
                }
            }
        }

        impl std::fmt::Display for Error {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.message())
            }
        }

        impl std::error::Error for Error {}

        impl From<$crate::Error> for Error {
            fn from(e: $crate::Error) -> Self {
                Error::new(e.kind(), e.message())
            }
        }

        impl From<std::io::Error> for Error {
            fn from(e: std::io::Error) -> Self {
                $crate::Error::from(e).into()
            }
        }

        impl From<$crate::error::StreamError> for Error {
            fn from(e: $crate::error::StreamError) -> Self {
                $crate::Error::from(e).into()
            }
        }

        impl From<Error> for $crate::Error {
            fn from(e: Error) -> Self {
                $crate::Error::new(e.kind(), e.message())
            }
        }

        /// Context on the way up, keeping the kind: `.context("reading x")?`.
        pub trait Context<T> {
            fn context(self, context: impl std::fmt::Display) -> Result<T>;
            fn with_context<D: std::fmt::Display>(self, context: impl FnOnce() -> D) -> Result<T>;
        }

        impl<T, E: Into<Error>> Context<T> for std::result::Result<T, E> {
            fn context(self, context: impl std::fmt::Display) -> Result<T> {
                self.map_err(|e| e.into().context(context))
            }

            fn with_context<D: std::fmt::Display>(self, context: impl FnOnce() -> D) -> Result<T> {
                self.map_err(|e| e.into().context(context()))
            }
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    mod library {
        crate::kinded_error!();
    }

    /// A library's error made by `kinded_error!` keeps its kind through context and
    /// reaches a main's [`Error`] with it: each kind's status, the broken pipe quiet.
    #[test]
    fn a_kinded_error_keeps_its_kind_through_context() {
        use library::Error as Lib;
        let cases: [(Lib, u8); 4] = [
            (Lib::Data("bad row".into()), 1),
            (Error::usage("bad size").into(), 2),
            (io::Error::from_raw_os_error(2).into(), 3),
            (StreamError::Io(io::ErrorKind::BrokenPipe.into()).into(), 0),
        ];
        let said = [
            "bad row",
            "bad size",
            "No such file or directory",
            "broken pipe",
        ];
        for ((e, status), said) in cases.into_iter().zip(said) {
            let e = library::Context::with_context(Err::<(), _>(e), || "x").unwrap_err();
            let e = library::Context::context(Err::<(), _>(e), "reading").unwrap_err();
            assert_eq!(
                (e.status(), e.to_string()),
                (status, format!("reading: x: {said}"))
            );
            let main = Error::from(e.clone());
            assert_eq!((main.kind(), main.message()), (e.kind(), e.message()));
        }
    }

    #[test]
    fn kinds_come_from_the_error_type() {
        let pipe: Error = StreamError::Io(io::ErrorKind::BrokenPipe.into()).into();
        assert_eq!(pipe.kind(), Kind::ReaderGone);
        assert_eq!(pipe.context("writing").kind().status(), 0);
        let bad: Error = StreamError::Invalid("x".into()).into();
        assert_eq!((bad.kind(), bad.kind().status()), (Kind::Data, 1));
        let text: Error = StreamError::Text {
            line: 3,
            column: 5,
            msg: "expected a number".into(),
        }
        .into();
        assert_eq!(text.to_string(), "line 3, column 5: expected a number");
        assert_eq!(text.kind(), Kind::Data);
        let missing = Err::<(), _>(io::Error::from_raw_os_error(2)).context("cannot open x");
        let missing = missing.unwrap_err();
        assert_eq!(missing.kind().status(), 3);
        assert_eq!(
            missing.to_string(),
            "cannot open x: No such file or directory"
        );
        assert_eq!(Error::usage("--size 0x0: …").kind().status(), 2);
    }

    #[test]
    fn an_os_error_is_said_once() {
        // Through StreamError::Io (whose source is the io::Error) the reason appears
        // once, without the `(os error 21)` suffix.
        let e: Error = StreamError::Io(io::Error::from_raw_os_error(21)).into();
        assert_eq!(e.context("/tmp").to_string(), "/tmp: Is a directory");
        let other: Error = io::Error::other("custom").into();
        assert_eq!(other.to_string(), "custom");
    }

    #[test]
    fn sizes_read_as_people_say_them() {
        assert_eq!(bytes_text(700), "700 bytes");
        assert_eq!(bytes_text(1536 << 10), "1.5 MiB");
        assert_eq!(bytes_text(44 << 30), "44 GiB");
    }

    #[test]
    fn cmp_statuses() {
        assert_eq!(Kind::Data.cmp_status(), 2);
        assert_eq!(Kind::Io.cmp_status(), 2);
        assert_eq!(Kind::Usage.cmp_status(), 2);
        assert_eq!(Kind::ReaderGone.cmp_status(), 0);
    }
}
