//! Errors as values, each with the position in the input where it arose.
//!
//! The variant says what kind of failure it is, and so (in the stage binaries, through
//! `stagecli`) the exit status: `Io` is an input or output that failed (3; 0, quietly,
//! for a broken pipe: the reader went away), every other variant is input the stage
//! cannot take (1).

use std::io;

/// What went wrong reading or writing a stream. Displayed after the stage name, it makes
/// the one-line message of docs/DESIGN.md, "Errors and exit statuses": `persp: line 3, …`.
#[derive(Debug, thiserror::Error)]
pub enum StreamError {
    /// The operating system refused a read or a write.
    #[error("{0}")]
    Io(#[from] io::Error),
    /// A text stream broke its grammar at `line:column` (1-based).
    #[error("line {line}, column {column}: {msg}")]
    Text {
        line: u64,
        column: usize,
        msg: String,
    },
    /// A binary stream broke its grammar at byte `offset` (0-based).
    #[error("byte {offset}{context}: {msg}")]
    Binary {
        offset: u64,
        context: String,
        msg: String,
    },
    /// The stream is well formed but in a space this stage does not take.
    #[error("{0}")]
    WrongSpace(String),
    /// The stream is well formed but a record in it cannot be processed.
    #[error("{0}")]
    Invalid(String),
}

impl StreamError {
    /// Whether this is the reader of our output going away (`| head`): a stage then ends
    /// quietly with status 0 (docs/DESIGN.md, "Errors and exit statuses").
    pub fn is_broken_pipe(&self) -> bool {
        matches!(self, StreamError::Io(e) if e.kind() == io::ErrorKind::BrokenPipe)
    }
}
