//! The text form's lexer: whitespace-separated words, `#` to the end of the line is a
//! comment, and every word knows its `line:column` so that errors can point at it.

use crate::StreamError;
use std::io::BufRead;
use std::ops::Range;

/// Reads words one line at a time; memory is one line, whatever the stream's length.
pub struct Lexer<R> {
    input: R,
    line: String,
    raw: Vec<u8>,
    line_no: u64,
    /// Byte offset in `line` where the next search for a word starts.
    cursor: usize,
    /// The word looked at but not yet taken, as a range of `line`.
    peeked: Option<Range<usize>>,
    /// Where the last word taken or peeked starts (1-based line and column).
    at: (u64, usize),
    eof: bool,
}

impl<R: BufRead> Lexer<R> {
    pub fn new(input: R) -> Self {
        Lexer {
            input,
            line: String::new(),
            raw: Vec::new(),
            line_no: 0,
            cursor: 0,
            peeked: None,
            at: (1, 1),
            eof: false,
        }
    }

    /// An error located at the word last peeked or taken.
    pub fn error(&self, msg: impl Into<String>) -> StreamError {
        StreamError::Text {
            line: self.at.0,
            column: self.at.1,
            msg: msg.into(),
        }
    }

    /// Where the word last peeked or taken starts, for an error found later.
    pub fn mark(&self) -> (u64, usize) {
        self.at
    }

    /// An error located at a [`Lexer::mark`].
    pub fn error_at(&self, at: (u64, usize), msg: impl Into<String>) -> StreamError {
        StreamError::Text {
            line: at.0,
            column: at.1,
            msg: msg.into(),
        }
    }

    /// An error located just past the end of the input.
    pub fn error_at_end(&self, msg: impl Into<String>) -> StreamError {
        StreamError::Text {
            line: self.line_no.max(1),
            column: self.line.len() + 1,
            msg: msg.into(),
        }
    }

    fn next_line(&mut self) -> Result<bool, StreamError> {
        self.raw.clear();
        let n = self.input.read_until(b'\n', &mut self.raw)?;
        if n == 0 {
            self.eof = true;
            return Ok(false);
        }
        self.line_no += 1;
        self.line.clear();
        match std::str::from_utf8(&self.raw) {
            Ok(s) => self.line.push_str(s.trim_end_matches(['\n', '\r'])),
            Err(e) => return Err(StreamError::Text {
                line: self.line_no,
                column: e.valid_up_to() + 1,
                msg: "not UTF-8 text (is this a binary stream cut or corrupted before its magic?)"
                    .into(),
            }),
        }
        // A comment runs from `#` to the end of the line.
        if let Some(hash) = self.line.find('#') {
            self.line.truncate(hash);
        }
        self.cursor = 0;
        Ok(true)
    }

    /// Looks at the next word without taking it; `None` at the end of the input.
    pub fn peek(&mut self) -> Result<Option<&str>, StreamError> {
        if self.peeked.is_none() {
            loop {
                let rest = &self.line[self.cursor..];
                if let Some(start) = rest.find(|c: char| !c.is_whitespace()) {
                    let start = self.cursor + start;
                    let len = self.line[start..]
                        .find(char::is_whitespace)
                        .unwrap_or(self.line.len() - start);
                    self.peeked = Some(start..start + len);
                    self.cursor = start + len;
                    self.at = (self.line_no, self.line[..start].chars().count() + 1);
                    break;
                }
                if self.eof || !self.next_line()? {
                    return Ok(None);
                }
            }
        }
        Ok(self.peeked.clone().map(|r| &self.line[r]))
    }

    /// Takes the next word; `None` at the end of the input.
    pub fn next_word(&mut self) -> Result<Option<String>, StreamError> {
        self.peek()?;
        Ok(self.peeked.take().map(|r| self.line[r].to_string()))
    }

    /// Takes the next word, which must be there; `what` says what was expected.
    pub fn expect_word(&mut self, what: &str) -> Result<String, StreamError> {
        match self.next_word()? {
            Some(w) => Ok(w),
            None => Err(self.error_at_end(format!("expected {what}, found the end of the input"))),
        }
    }

    /// Takes the next word and checks that it is `keyword`.
    pub fn expect_keyword(&mut self, keyword: &str) -> Result<(), StreamError> {
        let w = self.expect_word(&format!("`{keyword}`"))?;
        if w == keyword {
            Ok(())
        } else {
            Err(self.error(format!("expected `{keyword}`, found `{w}`")))
        }
    }

    /// Takes a finite number.
    pub fn number(&mut self, what: &str) -> Result<f64, StreamError> {
        let w = self.expect_word(what)?;
        match w.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(self.error(format!("{what} is `{w}`; coordinates must be finite"))),
            Err(_) => Err(self.error(format!("expected {what}, found `{w}`"))),
        }
    }

    /// Takes an unsigned integer no larger than `max`.
    pub fn integer(&mut self, what: &str, max: u64) -> Result<u64, StreamError> {
        let w = self.expect_word(what)?;
        match w.parse::<u64>() {
            Ok(v) if v <= max => Ok(v),
            Ok(v) => Err(self.error(format!("{what} is {v}, out of range 0..={max}"))),
            Err(_) => Err(self.error(format!(
                "expected {what} (an integer 0..={max}), found `{w}`"
            ))),
        }
    }

    /// Takes a signed 64-bit integer.
    pub fn signed(&mut self, what: &str) -> Result<i64, StreamError> {
        let w = self.expect_word(what)?;
        w.parse::<i64>()
            .map_err(|_| self.error(format!("expected {what} (an integer), found `{w}`")))
    }

    /// Whether the next word reads as a number (a vertex coordinate follows).
    pub fn next_is_number(&mut self) -> Result<bool, StreamError> {
        Ok(match self.peek()? {
            Some(w) => {
                let c = w.as_bytes()[0];
                c.is_ascii_digit()
                    || c == b'-'
                    || c == b'+'
                    || c == b'.'
                    || w.parse::<f64>().is_ok()
            }
            None => false,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_carry_their_line_and_column() {
        let mut lx = Lexer::new("polypipe 1 world # a comment\n\n  colour 1 2 3\n".as_bytes());
        assert_eq!(lx.next_word().unwrap().as_deref(), Some("polypipe"));
        assert_eq!(lx.next_word().unwrap().as_deref(), Some("1"));
        assert_eq!(lx.next_word().unwrap().as_deref(), Some("world"));
        assert_eq!(lx.next_word().unwrap().as_deref(), Some("colour"));
        assert_eq!(lx.integer("red", 255).unwrap(), 1);
        assert_eq!(lx.number("green").unwrap(), 2.0);
        assert_eq!(lx.signed("blue").unwrap(), 3);
        let e = lx.number("x").unwrap_err();
        assert_eq!(
            e.to_string(),
            "line 3, column 15: expected x, found the end of the input"
        );
    }

    #[test]
    fn bad_numbers_are_located() {
        let mut lx = Lexer::new("1 2\n  3 x 4\n".as_bytes());
        lx.number("x").unwrap();
        lx.number("y").unwrap();
        lx.number("z").unwrap();
        let e = lx.number("x").unwrap_err();
        assert_eq!(e.to_string(), "line 2, column 5: expected x, found `x`");
    }

    #[test]
    fn non_finite_numbers_are_refused() {
        let mut lx = Lexer::new("NaN".as_bytes());
        let e = lx.number("x").unwrap_err();
        assert_eq!(
            e.to_string(),
            "line 1, column 1: x is `NaN`; coordinates must be finite"
        );
    }
}
