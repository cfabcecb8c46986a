//! The reference's one error type: what is wrong with its inputs (frames of other sizes,
//! a mask that is not black and white, a sample count out of range). Every kind is bad
//! data, status 1 ([`stagecli::Kind::Data`]); `zspec` reports it as `zspec: message`.

/// An error of the reference renderer or its measures.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The inputs do not fit together or are out of range; the message says how.
    #[error("{0}")]
    Data(String),
    /// An error in one part of the input: `frame 3: the frames are 2x1 and 1x2`.
    #[error("{context}: {inner}")]
    In { context: String, inner: Box<Error> },
}

/// The reference's results.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// `self` in `context` (a frame, a mask frame, a polygon).
    pub fn context(self, context: impl Into<String>) -> Self {
        Error::In {
            context: context.into(),
            inner: Box::new(self),
        }
    }

    /// The exit status's kind: bad data, whatever the error.
    pub fn kind(&self) -> stagecli::Kind {
        stagecli::Kind::Data
    }
}

impl From<Error> for stagecli::Error {
    fn from(e: Error) -> Self {
        stagecli::Error::new(e.kind(), e.to_string())
    }
}

/// Returns early with [`Error::Data`] made from a format string.
macro_rules! bail {
    ($($t:tt)*) => {
        return Err($crate::error::Error::Data(format!($($t)*)))
    };
}
pub(crate) use bail;
