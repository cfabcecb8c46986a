//! The text form's lexer: whitespace-separated words, `#` to the end of the line is a
//! comment, and every word knows its `line:column` so that errors can point at it.
//!
//! It is written for speed as well as for people (a stage reads text at
//! hundreds of MB/s): a line is read into a buffer kept from line to line, words are
//! found by scanning its bytes, and numbers are parsed from the line in place; nothing
//! is allocated per word, and a message is formatted only when there is an error.
//! Columns count characters, as an editor does; a UTF-8 byte-order mark that starts
//! the input is skipped (editors write one and show none).

use crate::StreamError;
use std::fmt;
use std::io::{self, Read};
use std::ops::Range;

mod decimal;
pub use decimal::parse_decimal;

/// The input buffer's size once a stream has shown it is long; it starts at
/// [`FIRST_BUFFER`] (a short stream then costs little) and grows past this only for a
/// line longer than it. Twice the `BufReader` a stream's reader puts before the lexer
/// (`codec`'s `IO_BUFFER`, which checks this): a read of at least a `BufReader`'s
/// capacity, when it holds nothing, goes straight to its input, so that the input's
/// bytes are copied once, into this buffer, and not first into the `BufReader`'s and
/// then here.
pub(crate) const BUFFER: usize = 1 << 17;
const FIRST_BUFFER: usize = 1 << 12;

/// Reads words one line at a time; memory is one buffer of input (at most 128 KiB, or the
/// longest line), whatever the stream's length.
pub struct Lexer<R> {
    input: R,
    /// Input bytes; `buf[next..end]` is not yet read as lines.
    buf: Vec<u8>,
    end: usize,
    next: usize,
    /// The current line, its end of line and comment removed.
    line: String,
    /// Whether `line` is all ASCII, so that a byte offset is a column.
    ascii: bool,
    line_no: u64,
    /// Byte offset in `line` where the next search for a word starts.
    cursor: usize,
    /// The word looked at but not yet taken, as a range of `line`.
    peeked: Option<Range<usize>>,
    /// Where the last word taken or peeked starts (1-based line and column).
    at: (u64, usize),
    eof: bool,
}

/// The text form's whitespace: what `char::is_whitespace` says, decided on a byte for
/// ASCII (a non-ASCII line goes the slow way, by characters).
#[inline]
fn is_space(b: u8) -> bool {
    b == b' ' || (b'\t'..=b'\r').contains(&b)
}

/// Where the word of an ASCII line that starts at `from` ends. A word's bytes are almost
/// all above the space, so eight at a time are tested for one at or below it (the
/// lowest byte the test flags is a true one), and only such a byte is looked at.
#[inline]
fn word_end(bytes: &[u8], from: usize) -> usize {
    const ONES: u64 = 0x0101_0101_0101_0101;
    const HIGHS: u64 = 0x8080_8080_8080_8080;
    let mut i = from;
    loop {
        while let Some(chunk) = bytes.get(i..i + 8) {
            let x = u64::from_le_bytes(chunk.try_into().expect("8 bytes"));
            // Bytes below 0x21 (the line is ASCII, so no byte has its high bit set).
            let low = x.wrapping_sub(ONES * 0x21) & !x & HIGHS;
            if low != 0 {
                i += low.trailing_zeros() as usize / 8;
                break;
            }
            i += 8;
        }
        while i < bytes.len() && bytes[i] > b' ' {
            i += 1;
        }
        if i >= bytes.len() || is_space(bytes[i]) {
            return i.min(bytes.len());
        }
        // A control character that is not whitespace belongs to the word.
        i += 1;
    }
}

impl<R: Read> Lexer<R> {
    pub fn new(input: R) -> Self {
        Lexer {
            input,
            buf: vec![0; FIRST_BUFFER],
            end: 0,
            next: 0,
            line: String::new(),
            ascii: true,
            line_no: 0,
            cursor: 0,
            peeked: None,
            at: (1, 1),
            eof: false,
        }
    }

    /// A lexer that goes on with a stream part way through: `input` starts at the start
    /// of a line, and `lines_before` lines came before it, the last of them `last_line`
    /// (as the lexer keeps a line: [`kept_line`], [`Lexer::into_rest`]; empty will do
    /// where `input` has a line), so that messages give lines and columns as in the whole
    /// stream.
    pub fn resume(input: R, lines_before: u64, last_line: String) -> Self {
        let mut lx = Lexer::new(input);
        lx.line_no = lines_before;
        lx.ascii = last_line.is_ascii();
        lx.cursor = last_line.len();
        lx.line = last_line;
        lx.at = (lines_before.max(1), lx.cursor + 1);
        lx
    }

    /// [`Lexer::resume`] with the input's next bytes already in hand: `bytes` (whole
    /// lines), then `input`. They become the lexer's buffer as they are, so a stream cut
    /// into pieces in memory is read from each piece's own copy, without the reads from a
    /// reader into a buffer grown from [`FIRST_BUFFER`] (a tenth of a piece reader's
    /// instructions, on pieces of 256 KiB).
    pub fn resume_with(bytes: Vec<u8>, input: R, lines_before: u64, last_line: String) -> Self {
        let mut lx = Lexer::resume(input, lines_before, last_line);
        if !bytes.is_empty() {
            // (An empty buffer stays the one `new` made: a read into no room would look
            // like the input's end.)
            lx.end = bytes.len();
            lx.buf = bytes;
        }
        lx
    }

    /// Takes the lexer apart where it stands at the end of a line with nothing peeked
    /// (after a stream's header): the bytes it has read but not lexed, its input, the
    /// lines read and the last of them. Anywhere else it is handed back.
    pub fn into_rest(self) -> Result<(Vec<u8>, R, u64, String), Self> {
        let rest = &self.line.as_bytes()[self.cursor.min(self.line.len())..];
        if self.peeked.is_some() || !rest.iter().all(|&b| is_space(b)) {
            return Err(self);
        }
        let unread = self.buf[self.next..self.end].to_vec();
        Ok((unread, self.input, self.line_no, self.line))
    }

    /// Does the current line hold another word (or one peeked)? A header's optional words
    /// are looked for only on its own line, so that reading them never reads ahead into
    /// the records (see [`Lexer::into_rest`]).
    pub fn more_on_line(&self) -> bool {
        let rest = &self.line.as_bytes()[self.cursor.min(self.line.len())..];
        self.peeked.is_some() || !rest.iter().all(|&b| is_space(b))
    }

    /// An error located at the word last peeked or taken.
    pub fn error(&self, msg: impl Into<String>) -> StreamError {
        self.error_at(self.at, msg)
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
            msg: explained(msg.into()),
        }
    }

    /// An error located just past the end of the input: after the last line's words
    /// (its comment excluded), counted in bytes.
    pub fn error_at_end(&self, msg: impl Into<String>) -> StreamError {
        StreamError::Text {
            line: self.line_no.max(1),
            column: self.line.len() + 1,
            msg: explained(msg.into()),
        }
    }

    /// Moves to the next line; `false` at the end of the input (the current line stays
    /// the last one, for messages).
    fn next_line(&mut self) -> Result<bool, StreamError> {
        let mut searched = self.next;
        let newline = loop {
            if let Some(i) = memchr::memchr(b'\n', &self.buf[searched..self.end]) {
                break Some(searched + i);
            }
            if self.eof {
                break None;
            }
            if self.end - self.next > MAX_LINE_BYTES {
                return Err(StreamError::Text {
                    line: self.line_no + 1,
                    column: 1,
                    msg: line_too_long(),
                });
            }
            // Make room: keep the unread part, and grow the buffer for a long line.
            if self.next > 0 {
                self.buf.copy_within(self.next..self.end, 0);
                self.end -= self.next;
                self.next = 0;
            } else if self.end == self.buf.len() {
                self.buf.resize(self.buf.len() * 2, 0);
            }
            searched = self.end;
            loop {
                match self.input.read(&mut self.buf[self.end..]) {
                    Ok(0) => self.eof = true,
                    Ok(n) => self.end += n,
                    Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                    Err(e) => return Err(e.into()),
                }
                break;
            }
            if self.end == self.buf.len() && self.buf.len() < BUFFER {
                // The read filled the buffer: a long stream; read more at a time.
                self.buf.resize(self.buf.len() * 2, 0);
            }
        };
        let (start, stop) = match newline {
            Some(i) => (self.next, i),
            None if self.next < self.end => (self.next, self.end),
            None => return Ok(false),
        };
        if stop - start > MAX_LINE_BYTES {
            return Err(StreamError::Text {
                line: self.line_no + 1,
                column: 1,
                msg: line_too_long(),
            });
        }
        self.next = newline.map_or(self.end, |i| i + 1);
        self.line_no += 1;
        let (line, ascii) =
            kept_line(&self.buf[start..stop], self.line_no == 1).map_err(|valid_up_to| {
                StreamError::Text {
                    line: self.line_no,
                    column: valid_up_to + 1,
                    msg: "not UTF-8 text (is this a binary stream cut or corrupted before its \
                          magic?)"
                        .into(),
                }
            })?;
        self.line.clear();
        self.line.push_str(line);
        self.ascii = ascii;
        self.cursor = 0;
        Ok(true)
    }

    /// Finds the next word of the current line from the cursor, as a range of `line`.
    #[inline]
    fn word_in_line(&mut self) -> Option<Range<usize>> {
        let bytes = self.line.as_bytes();
        let (start, end) = if self.ascii {
            let rest = bytes.get(self.cursor..)?;
            let start = self.cursor + rest.iter().position(|&b| !is_space(b))?;
            (start, word_end(bytes, start))
        } else {
            let rest = &self.line[self.cursor..];
            let start = self.cursor + rest.find(|c: char| !c.is_whitespace())?;
            let len = self.line[start..]
                .find(char::is_whitespace)
                .unwrap_or(self.line.len() - start);
            (start, start + len)
        };
        self.cursor = end;
        let column = if self.ascii {
            start + 1
        } else {
            self.line[..start].chars().count() + 1
        };
        self.at = (self.line_no, column);
        Some(start..end)
    }

    /// The next word's range in `line`, without taking it; `None` at the end of input.
    #[inline]
    fn peek_range(&mut self) -> Result<Option<Range<usize>>, StreamError> {
        if self.peeked.is_none() {
            loop {
                if let Some(r) = self.word_in_line() {
                    self.peeked = Some(r);
                    break;
                }
                if !self.next_line()? {
                    return Ok(None);
                }
            }
        }
        Ok(self.peeked.clone())
    }

    /// A word of the current line.
    #[inline]
    fn word(&self, r: Range<usize>) -> &str {
        &self.line[r]
    }

    /// Looks at the next word without taking it; `None` at the end of the input.
    #[inline]
    pub fn peek(&mut self) -> Result<Option<&str>, StreamError> {
        Ok(self.peek_range()?.map(|r| self.word(r)))
    }

    /// Takes the word peeked (after [`Lexer::peek`] said there is one).
    #[inline]
    pub fn skip_word(&mut self) {
        self.peeked = None;
    }

    /// Takes the next word; `None` at the end of the input.
    pub fn next_word(&mut self) -> Result<Option<String>, StreamError> {
        Ok(self.peek_range()?.map(|r| {
            self.peeked = None;
            self.word(r).to_string()
        }))
    }

    /// Takes the next word, which must be there; `what` says what was expected.
    #[inline]
    fn take(&mut self, what: &dyn fmt::Display) -> Result<Range<usize>, StreamError> {
        match self.peek_range()? {
            Some(r) => {
                self.peeked = None;
                Ok(r)
            }
            None => Err(self.error_at_end(format!("expected {what}, found the end of the input"))),
        }
    }

    /// Takes the next word, which must be there; `what` says what was expected.
    pub fn expect_word(&mut self, what: &str) -> Result<String, StreamError> {
        let r = self.take(&what)?;
        Ok(self.word(r).to_string())
    }

    /// Takes the next word and checks that it is `keyword`.
    pub fn expect_keyword(&mut self, keyword: &str) -> Result<(), StreamError> {
        let r = self.take(&format_args!("`{keyword}`"))?;
        let w = self.word(r);
        if w == keyword {
            Ok(())
        } else {
            Err(self.error(format!("expected `{keyword}`, found `{}`", Shown(w))))
        }
    }

    /// Takes a finite number; `what` (formatted only for a message) says what it is.
    #[inline]
    pub fn number(&mut self, what: impl fmt::Display) -> Result<f64, StreamError> {
        let r = self.take(&what)?;
        let w = self.word(r);
        match parse_f64(w) {
            Some(v) if v.is_finite() => Ok(v),
            Some(_) => Err(self.error(format!(
                "{what} is `{}`; coordinates must be finite",
                Shown(w)
            ))),
            None => Err(self.error(format!("expected {what}, found `{}`", Shown(w)))),
        }
    }

    /// [`Lexer::number`] with a message made by `what` only if one is needed.
    pub fn number_with(&mut self, what: impl FnOnce() -> String) -> Result<f64, StreamError> {
        struct Lazy<F>(std::cell::Cell<Option<F>>);
        impl<F: FnOnce() -> String> fmt::Display for Lazy<F> {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                match self.0.take() {
                    Some(what) => f.write_str(&what()),
                    None => Ok(()),
                }
            }
        }
        self.number(Lazy(std::cell::Cell::new(Some(what))))
    }

    /// Takes the rest of the current line when it is exactly `out.len()` finite numbers,
    /// the first of them already peeked (a vertex line: `next_is_number` looked at it),
    /// and answers whether it did. Otherwise it takes nothing and answers `false`, and
    /// the caller reads the words one by one, which is where every message comes from.
    /// The numbers are parsed by the same [`parse_f64`] as [`Lexer::number`]'s, so the
    /// two paths read the same values; this one only spares the per-word bookkeeping of
    /// peeking and taking (viewxf on the 100,000-quad text scene: 96.5 → 94.6 ms).
    #[inline]
    pub fn numbers_to_line_end(&mut self, out: &mut [f64]) -> bool {
        let Some(first) = self.peeked.clone() else {
            return false;
        };
        if !self.ascii || out.is_empty() {
            return false;
        }
        let bytes = self.line.as_bytes();
        let (mut start, mut end) = (first.start, first.end);
        for (k, slot) in out.iter_mut().enumerate() {
            if k > 0 {
                start = end;
                while start < bytes.len() && is_space(bytes[start]) {
                    start += 1;
                }
                if start == bytes.len() {
                    return false;
                }
                end = word_end(bytes, start);
            }
            match parse_f64(&self.line[start..end]) {
                Some(v) if v.is_finite() => *slot = v,
                _ => return false,
            }
        }
        if !bytes[end..].iter().all(|&b| is_space(b)) {
            return false;
        }
        self.cursor = bytes.len();
        self.peeked = None;
        self.at = (self.line_no, start + 1);
        true
    }

    /// Takes whole lines of exactly `n` finite numbers (at most 8) straight from the
    /// input buffer, for as long as the next line is one and `take`, handed its numbers,
    /// accepts it; answers how many lines it took. Only where the lexer stands between
    /// lines, or has peeked the first word of its current line; it stops, taking nothing
    /// more, at any line it is not sure of (another word, a comment, a carriage return or
    /// other whitespace than spaces and tabs, a number that does not parse, a line not yet
    /// read whole), which the word-by-word path then reads, with its messages. Afterwards
    /// the lexer stands where that path would: the last line taken is its current line,
    /// every line counted.
    ///
    /// A vertex line is nearly every line of a scene, and this is its reading without the
    /// copy of each line into the lexer's and the peek and take of each word (viewxf on
    /// the 100,000-quad text scene, one core, interleaved: 77 → 71 ms of CPU, 996 → 945
    /// million instructions). The numbers have [`parse_f64`]'s values (`number_line`).
    pub fn number_lines(&mut self, n: usize, mut take: impl FnMut(&[f64]) -> bool) -> usize {
        if n == 0 || n > 8 {
            return 0;
        }
        let mut numbers = [0.0; 8];
        let mut taken = 0;
        let line = self.line.as_bytes();
        if let Some(first) = self.peeked.clone() {
            // The current line, if its first word is the one peeked and it is a line of
            // numbers (the reader peeks past each vertex for an edge support).
            if !line[..first.start].iter().all(|&b| is_space(b)) {
                return 0;
            }
            match number_line(line, &mut numbers[..n], LineEnd::Text) {
                Some((last_word, _)) if take(&numbers[..n]) => {
                    self.peeked = None;
                    self.cursor = line.len();
                    self.at = (self.line_no, last_word + 1);
                    taken = 1;
                }
                _ => return 0,
            }
        } else if !self.line_read_to_end() {
            return 0;
        }
        let lines_before = taken;
        let mut last = (0, 0, 0); // the last line taken: start, stop, its last word's start
                                  // A line is read where it stands in the buffer, up to its newline (not found
                                  // first: the numbers' reading finds it), so a line not in the buffer whole stops
                                  // the loop, as a line the word-by-word path must read does.
        while let Some((last_word, length)) = number_line(
            &self.buf[self.next..self.end],
            &mut numbers[..n],
            LineEnd::Newline,
        ) {
            if !take(&numbers[..n]) {
                break;
            }
            let (start, stop) = (self.next, self.next + length);
            self.next = stop + 1;
            taken += 1;
            last = (start, stop, last_word);
        }
        if taken > lines_before {
            let (start, stop, last_word) = last;
            self.line_no += (taken - lines_before) as u64;
            self.line.clear();
            // SAFETY: number_line takes only ASCII lines.
            self.line
                .push_str(unsafe { std::str::from_utf8_unchecked(&self.buf[start..stop]) });
            self.ascii = true;
            self.cursor = self.line.len();
            self.at = (self.line_no, last_word + 1);
        }
        taken
    }

    /// Takes the current line, when it is the peeked `word` alone, and the next line
    /// straight from the input buffer, when `read` reads it (answering its value and
    /// where its last word starts); answers `read`'s value. Anything else (another word
    /// peeked or more on the line, the next line not read whole, `read` refusing it)
    /// takes nothing, and the word-by-word path reads on with its messages. Afterwards
    /// the lexer stands where that path would, at the end of the line `read` read.
    ///
    /// For the two lines between polygons, `NEXT.POLYGON` and `colour R G B`, peeked and
    /// copied and taken word by word a tenth of viewxf's time on a scene of quads.
    pub fn line_after<T>(
        &mut self,
        word: &str,
        read: impl FnOnce(&[u8]) -> Option<(T, usize)>,
    ) -> Option<T> {
        // `word` peeked alone on the current line; or, with the current line read to its
        // end, alone on the next line, which is then taken too (`next_line_is`).
        let from = match self.peeked.clone() {
            Some(peeked) => {
                let line = self.line.as_bytes();
                if &line[peeked.clone()] != word.as_bytes()
                    || !line[..peeked.start].iter().all(|&b| is_space(b))
                    || !line[peeked.end..].iter().all(|&b| is_space(b))
                {
                    return None;
                }
                self.next
            }
            None => {
                let (start, stop) = self.buffered_next_line()?;
                if !alone(&self.buf[start..stop], word) {
                    return None;
                }
                stop + 1
            }
        };
        let skipped = u64::from(from != self.next);
        let length = memchr::memchr(b'\n', &self.buf[from..self.end])?;
        let (start, stop) = (from, from + length);
        let (value, last_word) = read(&self.buf[start..stop])?;
        let line = &self.buf[start..stop];
        let text = if line.is_ascii() {
            // SAFETY: ASCII is UTF-8 (the check is from_utf8's, without its set-up on a
            // short line: the colour line between every two polygons).
            unsafe { std::str::from_utf8_unchecked(line) }
        } else {
            std::str::from_utf8(line).ok()?
        };
        self.line.clear();
        self.line.push_str(text);
        self.ascii = text.is_ascii();
        self.next = stop + 1;
        self.line_no += 1 + skipped;
        self.cursor = self.line.len();
        self.peeked = None;
        self.at = (self.line_no, last_word + 1);
        Some(value)
    }

    /// Whether only whitespace is left of the current line, past the words taken.
    #[inline]
    fn line_read_to_end(&self) -> bool {
        let line = self.line.as_bytes();
        line[self.cursor.min(line.len())..]
            .iter()
            .all(|&b| is_space(b))
    }

    /// The next line of the input (its start and end in the buffer, without its
    /// newline), when the current line has been read to its end (no word peeked, only
    /// whitespace left) and the next one is in the buffer whole; `None` otherwise.
    #[inline]
    fn buffered_next_line(&self) -> Option<(usize, usize)> {
        if self.peeked.is_some() || !self.line_read_to_end() {
            return None;
        }
        let length = memchr::memchr(b'\n', &self.buf[self.next..self.end])?;
        Some((self.next, self.next + length))
    }

    /// Whether the next line is `word` alone (spaces or tabs around it), as far as the
    /// input buffer tells without reading on: `false` where it cannot tell. A reader that
    /// knows what comes next so need not peek, which copies the line and finds its words.
    #[inline]
    pub fn next_line_is(&self, word: &str) -> bool {
        self.buffered_next_line()
            .is_some_and(|(start, stop)| alone(&self.buf[start..stop], word))
    }

    /// Whether a word is ahead for certain: the next line, in the buffer whole, starts
    /// (after spaces or tabs) with a byte that begins a word, not a comment.
    #[inline]
    pub fn word_ahead(&self) -> bool {
        self.buffered_next_line().is_some_and(|(start, stop)| {
            self.buf[start..stop]
                .iter()
                .find(|&&b| !is_blank(b))
                .is_some_and(|&b| b > b' ' && b != b'#' && b.is_ascii())
        })
    }

    /// Takes an unsigned integer no larger than `max`.
    #[inline]
    pub fn integer(&mut self, what: impl fmt::Display, max: u64) -> Result<u64, StreamError> {
        let r = self.take(&what)?;
        let w = self.word(r);
        match w.parse::<u64>() {
            Ok(v) if v <= max => Ok(v),
            Ok(v) => Err(self.error(format!("{what} is {v}, out of range 0..={max}"))),
            Err(_) => Err(self.error(format!(
                "expected {what} (an integer 0..={max}), found `{}`",
                Shown(w)
            ))),
        }
    }

    /// Takes a signed 64-bit integer.
    #[inline]
    pub fn signed(&mut self, what: impl fmt::Display) -> Result<i64, StreamError> {
        let r = self.take(&what)?;
        let w = self.word(r);
        w.parse::<i64>().map_err(|_| {
            self.error(format!(
                "expected {what} (an integer), found `{}`",
                Shown(w)
            ))
        })
    }

    /// Whether the next word reads as a number (a vertex coordinate follows).
    #[inline]
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

/// Whether `line` is `word` with only spaces and tabs around it.
#[inline]
fn alone(line: &[u8], word: &str) -> bool {
    let start = line
        .iter()
        .position(|&b| !is_blank(b))
        .unwrap_or(line.len());
    let stop = line
        .iter()
        .rposition(|&b| !is_blank(b))
        .map_or(start, |i| i + 1);
    &line[start..stop] == word.as_bytes()
}

/// What separates the words of a line that [`Lexer::number_lines`] or
/// [`Lexer::line_after`]'s readers take whole: a space or a tab (any other whitespace,
/// and a line holding it, is left to the word-by-word path).
#[inline]
pub(crate) fn is_blank(b: u8) -> bool {
    b == b' ' || b == b'\t'
}

/// Where a line that [`number_line`] reads ends.
#[derive(Clone, Copy, PartialEq, Eq)]
enum LineEnd {
    /// At the end of the text given (a line the lexer keeps, without its newline).
    Text,
    /// At a newline, within the text given (the input buffer from the line's start).
    Newline,
}

/// Reads a line at the start of `text` as exactly `out.len()` finite numbers separated
/// by spaces and tabs (blanks after the last allowed), the line ending where `end` says;
/// answers where its last number starts and where the line ends (the newline's offset,
/// or the text's length). `None` for anything else (a word that is not a number, a
/// comment, a byte that is not ASCII, other whitespace, no newline in `text`), which
/// [`Lexer::number_lines`] leaves to the word-by-word path.
///
/// Each number is found and read in one pass: by [`parse_decimal`], which reads the short
/// form of a scene's numbers (digits, a point, an exponent, at most 19 significant
/// digits) to `str::parse`'s bits, and otherwise by `fast_float2::parse_partial` (the
/// same Eisel–Lemire rounding as `str::parse`, so the same value). A number is taken only
/// when a blank or the line's end follows what was read; where the parsers' grammars
/// differ from [`parse_f64`]'s (`str::parse` takes `+1`, `1.`, `.5`, `1e5`; a word one of
/// them refuses is not followed by a blank, or is refused whole), the line goes to the
/// word-by-word path, which reads with [`parse_f64`], so what is accepted, and every
/// message, is unchanged. Every byte of a line taken is a number's or a blank, so ASCII.
///
/// Finding the numbers' ends and reading them in one pass spared reading every digit
/// twice (viewxf on the 100,000-quad scene 899 → 728 M instructions), and finding the
/// newline by the same pass spares a search of each line for it.
#[inline]
fn number_line(text: &[u8], out: &mut [f64], end: LineEnd) -> Option<(usize, usize)> {
    let (mut i, mut last) = (0, 0);
    for slot in out.iter_mut() {
        while i < text.len() && is_blank(text[i]) {
            i += 1;
        }
        let start = i;
        let rest = &text[start..];
        let (value, used) = match parse_decimal(rest) {
            Some(read) => read,
            None => fast_float2::parse_partial::<f64, _>(rest).ok()?,
        };
        i = start + used;
        if i < text.len() && !is_blank(text[i]) && text[i] != b'\n' {
            return None;
        }
        *slot = Some(value).filter(|v| v.is_finite())?;
        last = start;
    }
    while i < text.len() && is_blank(text[i]) {
        i += 1;
    }
    match end {
        LineEnd::Text => (i == text.len()).then_some((last, i)),
        LineEnd::Newline => (text.get(i) == Some(&b'\n')).then_some((last, i)),
    }
}

/// A line of the input (without its newline) as the lexer keeps it, and whether it is
/// ASCII: trailing carriage returns taken off, checked as UTF-8 (`Err` with the length of
/// its valid start if it is not), a byte-order mark taken off the `first` line of the
/// input, and the comment from `#` on taken off. For a reader that resumes a stream after
/// a line it did not read itself ([`Lexer::resume`]), as well as for the lexer.
#[inline]
pub fn kept_line(raw: &[u8], first: bool) -> Result<(&str, bool), usize> {
    let mut stop = raw.len();
    while stop > 0 && raw[stop - 1] == b'\r' {
        stop -= 1;
    }
    let bytes = &raw[..stop];
    let ascii = bytes.is_ascii();
    let line = if ascii {
        // SAFETY: ASCII bytes are UTF-8. The check is the same as from_utf8's on the
        // lines of numbers that make up nearly all of a scene, but without its per-call
        // set-up, which on 60-byte lines was a tenth of viewxf's time.
        unsafe { std::str::from_utf8_unchecked(bytes) }
    } else {
        std::str::from_utf8(bytes).map_err(|e| e.valid_up_to())?
    };
    // A byte-order mark, which some editors put first, is not part of the text.
    let line = match line.strip_prefix('\u{feff}') {
        Some(rest) if first => rest,
        _ => line,
    };
    // A comment runs from `#` to the end of the line.
    let line = match memchr::memchr(b'#', line.as_bytes()) {
        Some(hash) => &line[..hash],
        None => line,
    };
    Ok((line, ascii))
}

/// Parses a number of the text form: `str::parse::<f64>`, which is the Eisel–Lemire
/// algorithm of fast_float since Rust 1.55. The grammar of the text form is this
/// function's. The vertex lines that make up nearly all of a scene are read faster, to
/// the same bits, by `number_line` ([`parse_decimal`] and fast_float2, one pass for a
/// line's numbers and its end); `bench stages codec` measures the parsers on
/// the environment scene's numbers.
#[inline]
pub fn parse_f64(w: &str) -> Option<f64> {
    w.parse::<f64>().ok()
}

/// A word of the input as a message shows it: control characters, a byte-order mark and
/// other invisible characters escaped (`\x00`, `\x1a`, `\u{feff}`), so that a message is
/// one readable line whatever the input held, and a word longer than [`SHOWN_CHARS`]
/// characters cut to its first ones and its length (`123456… (50000000 bytes)`), so that
/// a 50 MB number does not make a 50 MB message. Every message that quotes its input
/// quotes it through this (stagecli's too).
pub struct Shown<'a>(pub &'a str);

/// How many characters of a word [`Shown`] shows: a message stays one line of a
/// terminal's width or two, whatever it quotes.
pub const SHOWN_CHARS: usize = 80;

/// The longest line of text a reader takes, 1 MiB: a line of the text form holds one
/// vertex, one keyword's words or a comment, a few hundred bytes at most; a line of an
/// OBJ file one face. A longer line is refused as bad input (status 1) when its first
/// 1 MiB has no end of line in it, so that input with no newline (`/dev/zero`) costs a
/// reader 2 MiB of buffer and not all the memory there is. A binary record's bound is
/// `codec::MAX_RECORD_BYTES` (64 MiB): the text form spreads a polygon over lines, so a
/// polygon's bound is the same in both forms. docs/DESIGN.md, "Errors and exit
/// statuses".
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// What a reader says of a line longer than [`MAX_LINE_BYTES`], after where it starts.
pub fn line_too_long() -> String {
    format!(
        "expected a line of text of at most {MAX_LINE_BYTES} bytes, found {MAX_LINE_BYTES} \
         bytes with no end of line (not a text stream?)"
    )
}

fn invisible(c: char) -> bool {
    c.is_control()
        || matches!(c, '\u{200b}'..='\u{200f}' | '\u{2028}'..='\u{202e}' | '\u{2060}'..='\u{2064}'
            | '\u{2066}'..='\u{2069}' | '\u{feff}' | '\u{fff9}'..='\u{fffb}')
}

impl fmt::Display for Shown<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // Cut where the first SHOWN_CHARS characters end (a char boundary).
        let cut = self.0.char_indices().nth(SHOWN_CHARS).map(|(i, _)| i);
        let shown = &self.0[..cut.unwrap_or(self.0.len())];
        if !shown.chars().any(invisible) {
            f.write_str(shown)?;
        } else {
            escaped(shown, f)?;
        }
        match cut {
            Some(_) => write!(f, "… ({} bytes)", self.0.len()),
            None => Ok(()),
        }
    }
}

fn escaped(s: &str, f: &mut fmt::Formatter<'_>) -> fmt::Result {
    for c in s.chars() {
        match c {
            '\t' => f.write_str("\\t")?,
            '\n' => f.write_str("\\n")?,
            '\r' => f.write_str("\\r")?,
            c if c.is_ascii() && invisible(c) => write!(f, "\\x{:02x}", c as u32)?,
            c if invisible(c) => write!(f, "\\u{{{:x}}}", c as u32)?,
            c => write!(f, "{c}")?,
        }
    }
    Ok(())
}

/// Adds to a message that shows an escaped byte-order mark what that is.
fn explained(msg: String) -> String {
    if msg.contains("\\u{feff}") {
        msg + " (\\u{feff} is a UTF-8 byte-order mark)"
    } else {
        msg
    }
}

/// A number as a message shows it: as Rust prints it, but in exponent form when it is
/// very large or very small (|x| ≥ 1e16, or non-zero and < 1e-6), so that 1e300 is
/// `1e300` and not 301 digits.
#[derive(Clone, Copy, Debug)]
pub struct Number(pub f64);

impl fmt::Display for Number {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        if x.is_finite() && x != 0.0 && (x.abs() >= 1e16 || x.abs() < 1e-6) {
            write!(f, "{x:e}")
        } else {
            write!(f, "{x}")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_vertex_line_is_read_as_str_parse_reads_its_words() {
        // Where number_line takes a word, its value is parse_f64's to the bit; what it
        // leaves, the word-by-word path reads with parse_f64 itself. The plain decimals
        // a scene is made of it must take.
        let words = [
            "1",
            "-1",
            "+1",
            "1.",
            ".5",
            "-.5",
            "+.5",
            "1e5",
            "1E5",
            "1e+5",
            "1e-5",
            "1.e5",
            ".e5",
            "1e",
            "1e+",
            "e5",
            ".",
            "-",
            "+",
            "1.5.2",
            "0x10",
            "1_0",
            "inf",
            "-inf",
            "nan",
            "infinity",
            "1d5",
            "00012",
            "1,5",
            "1.7976931348623157e308",
            "1.8e308",
            "4.9e-324",
            "2.4703282292062327e-324",
            "123456789012345678901234567890",
            "0.1000000000000000055511151231257827",
            "9007199254740993",
            "-0",
            "9.819403625187153",
            "-7.697877382108967",
            "1.0006495953187375",
        ];
        for w in words {
            let want = parse_f64(w).filter(|v| v.is_finite());
            for (text, end) in in_both_forms(w) {
                let mut out = [0.0];
                if number_line(text.as_bytes(), &mut out, end).is_some() {
                    assert_eq!(Some(out[0].to_bits()), want.map(f64::to_bits), "{text:?}");
                }
            }
        }
        let mut out = [0.0; 3];
        for line in [
            "9.819403625187153 -7.697877382108967 1.0006495953187375",
            "\t1 2.5\t -3e-2  ",
            "0 -0 1e308",
            "-0.0004417409009040803 12345678.12345678901 .5",
        ] {
            for (text, end) in in_both_forms(line) {
                let read = number_line(text.as_bytes(), &mut out, end);
                let last = line.rfind(|c: char| !c.is_ascii_whitespace()).unwrap();
                let last_word = line[..last].rfind([' ', '\t']).unwrap() + 1;
                assert_eq!(read, Some((last_word, line.len())), "{text:?}");
                let want: Vec<u64> = line
                    .split_ascii_whitespace()
                    .map(|w| parse_f64(w).unwrap().to_bits())
                    .collect();
                assert_eq!(out.map(f64::to_bits).to_vec(), want, "{text:?}");
            }
        }
        // A word run into another, or a number too few or too many: not taken.
        for line in [
            "1.5x 2 3",
            "1 2",
            "1 2 3 4",
            "1 2 3#c",
            "1 2 3e",
            "1 2 3\r",
            "1 2\x0b3",
            "1 2 3é",
            "1 2 1.000000000000000000000001x",
        ] {
            for (text, end) in in_both_forms(line) {
                assert_eq!(
                    number_line(text.as_bytes(), &mut out, end),
                    None,
                    "{text:?}"
                );
            }
        }
        // With no newline in the buffer, a line is not whole yet.
        assert_eq!(number_line(b"1 2 3", &mut out, LineEnd::Newline), None);
    }

    /// A line as number_line is given it: alone (as the lexer keeps it), and at the start
    /// of the input buffer, its newline and more lines after it (whose bytes a reader of
    /// eight at a time may look at, but must not take).
    fn in_both_forms(line: &str) -> [(String, LineEnd); 2] {
        [
            (line.to_string(), LineEnd::Text),
            (
                format!("{line}\n12345678901234567890 1.5e3\nNEXT.POLYGON\n"),
                LineEnd::Newline,
            ),
        ]
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2_000))]

        /// Lines of three numbers, printed in every way a double is printed and with
        /// blanks of every kind between: number_line takes each, with the values
        /// str::parse gives its words, whether it stands alone or in the buffer.
        #[test]
        fn lines_of_printed_doubles_read_as_their_words(
            bits in proptest::array::uniform3(proptest::prelude::any::<u64>()),
            forms in proptest::array::uniform3(0usize..4),
            blanks in proptest::array::uniform4("[ \t]{0,3}"),
        ) {
            let words: Vec<String> = bits
                .iter()
                .zip(forms)
                .map(|(&b, form)| {
                    let x = f64::from_bits(b);
                    let x = if x.is_finite() { x } else { b as f64 };
                    match form {
                        0 => format!("{x}"),
                        1 => format!("{x:e}"),
                        2 => format!("{:.3}", x / 1e300),
                        _ if (x as f32).is_finite() => format!("{}", x as f32),
                        _ => format!("{x:?}"),
                    }
                })
                .collect();
            // At least one blank between words.
            let line = format!(
                "{}{} {}{} {}{} {}",
                blanks[0], words[0], blanks[1], words[1], blanks[2], words[2], blanks[3]
            );
            let want: Vec<u64> = words.iter().map(|w| parse_f64(w).unwrap().to_bits()).collect();
            for (text, end) in in_both_forms(&line) {
                let mut out = [0.0; 3];
                let read = number_line(text.as_bytes(), &mut out, end);
                proptest::prop_assert_eq!(read.map(|(_, stop)| stop), Some(line.len()));
                proptest::prop_assert_eq!(out.map(f64::to_bits).to_vec(), want.clone());
            }
        }
    }

    /// A line is read up to [`MAX_LINE_BYTES`] and no further: input that never ends and
    /// has no newline (`/dev/zero`) is refused after 1 MiB, as is a longer line that does
    /// end; a line of exactly the bound is read.
    #[test]
    fn a_line_longer_than_the_bound_is_refused_where_it_starts() {
        let mut lx = Lexer::new(std::io::Read::take(std::io::repeat(0), 1 << 40));
        let e = lx.next_word().unwrap_err().to_string();
        assert_eq!(e, format!("line 1, column 1: {}", line_too_long()));
        let mut long = b"a\n".to_vec();
        long.extend(std::iter::repeat_n(b'x', MAX_LINE_BYTES + 1));
        long.push(b'\n');
        let mut lx = Lexer::new(&long[..]);
        assert_eq!(lx.next_word().unwrap().as_deref(), Some("a"));
        let e = lx.next_word().unwrap_err().to_string();
        assert!(e.starts_with("line 2, column 1: expected a line"), "{e}");
        let mut exact = vec![b'y'; MAX_LINE_BYTES];
        exact.extend_from_slice(b"\nz\n");
        let mut lx = Lexer::new(&exact[..]);
        assert_eq!(
            lx.next_word().unwrap().map(|w| w.len()),
            Some(MAX_LINE_BYTES)
        );
        assert_eq!(lx.next_word().unwrap().as_deref(), Some("z"));
    }

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

    #[test]
    fn columns_count_characters_and_unicode_spaces_separate() {
        // U+00E9 is two bytes, U+3000 an ideographic space.
        let mut lx = Lexer::new("é\u{3000}x\u{a0}7\n".as_bytes());
        assert_eq!(lx.next_word().unwrap().as_deref(), Some("é"));
        let e = lx.number("n").unwrap_err();
        assert_eq!(e.to_string(), "line 1, column 3: expected n, found `x`");
        assert_eq!(lx.number("n").unwrap(), 7.0);
        // Vertical tab and form feed are whitespace too, as char::is_whitespace says.
        let mut lx = Lexer::new("1\x0b2\x0c3\r\n".as_bytes());
        assert_eq!(lx.number("a").unwrap(), 1.0);
        assert_eq!(lx.number("b").unwrap(), 2.0);
        assert_eq!(lx.number("c").unwrap(), 3.0);
    }

    /// The whole-line path takes a line only when it is exactly the numbers asked for,
    /// reads the values word-by-word reading would, and leaves the lexer where that
    /// would: the next word, and the place a later message points at.
    #[test]
    fn a_line_of_numbers_is_taken_whole_or_not_at_all() {
        // (line, numbers asked, taken whole?)
        let cases = [
            ("1 2 3", 3, true),
            ("  -1.5e3\t2.25 +3  ", 3, true),
            (
                "7.475800962976068 -0.9027782933982392 3.843741095252387",
                3,
                true,
            ),
            ("1 2 3 # a comment", 3, true),
            ("1 2", 3, false),
            ("1 2 3 4", 3, false),
            ("1 2 x", 3, false),
            ("1 inf 3", 3, false),
            ("1 2 3 on 0 0 0 1 1 1", 3, false),
            ("1 2 é", 3, false),
            ("1 2", 2, true),
        ];
        for (line, n, whole) in cases {
            let text = format!("{line}\nnext\n");
            let mut fast = Lexer::new(text.as_bytes());
            let mut slow = Lexer::new(text.as_bytes());
            assert!(fast.next_is_number().unwrap(), "{line}");
            let mut got = [0.0; 3];
            assert_eq!(fast.numbers_to_line_end(&mut got[..n]), whole, "{line}");
            if !whole {
                // Nothing was taken: the words are all still there.
                let mut words = vec![];
                while let Some(w) = fast.next_word().unwrap() {
                    words.push(w);
                }
                let mut expect = vec![];
                while let Some(w) = slow.next_word().unwrap() {
                    expect.push(w);
                }
                assert_eq!(words, expect, "{line}");
                continue;
            }
            for (k, v) in got[..n].iter().enumerate() {
                assert_eq!(v.to_bits(), slow.number(k).unwrap().to_bits(), "{line}");
            }
            assert_eq!(fast.mark(), slow.mark(), "{line}");
            assert_eq!(fast.next_word().unwrap().as_deref(), Some("next"));
            assert_eq!(slow.next_word().unwrap().as_deref(), Some("next"));
            assert_eq!(fast.mark(), slow.mark(), "{line}");
        }
        // Nothing peeked: nothing to go on.
        let mut lx = Lexer::new("1 2 3\n".as_bytes());
        assert!(!lx.numbers_to_line_end(&mut [0.0; 3]));
        assert_eq!(lx.number("x").unwrap(), 1.0);
    }

    /// A reader that hands out a few bytes at a time, as a pipe may.
    struct Trickle<'a>(&'a [u8], usize);

    impl Read for Trickle<'_> {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            self.1 = self.1 % 3 + 1;
            let n = self.1.min(buf.len()).min(self.0.len());
            buf[..n].copy_from_slice(&self.0[..n]);
            self.0 = &self.0[n..];
            Ok(n)
        }
    }

    /// A word and where it starts (line, column).
    type Placed = (String, (u64, usize));

    /// Every word with its place, and the message at the end of the input.
    fn words<R: Read>(mut lx: Lexer<R>) -> (Vec<Placed>, String) {
        let mut out = Vec::new();
        while let Some(w) = lx.next_word().unwrap() {
            out.push((w, lx.mark()));
        }
        (out, lx.number("x").unwrap_err().to_string())
    }

    #[test]
    fn lines_across_reads_and_past_the_buffer_read_the_same() {
        let mut text = String::from("polypipe 1 world # c\r\n\n  colour 1 2 3\n");
        // A line longer than the buffer, and one of non-ASCII words.
        for i in 0..20_000 {
            text.push_str(&format!("{i} "));
        }
        text.push_str("\n é\u{3000}ü 4 # ü\nlast 5 # end");
        let whole = words(Lexer::new(text.as_bytes()));
        assert_eq!(whole.0.len(), 3 + 4 + 20_000 + 3 + 2);
        assert_eq!(whole.0[3], ("colour".to_string(), (3, 3)));
        assert_eq!(whole.0[20_007], ("é".to_string(), (5, 2)));
        assert_eq!(whole.0[20_009], ("4".to_string(), (5, 6)));
        assert_eq!(whole.0[20_011], ("5".to_string(), (6, 6)));
        assert_eq!(
            whole.1,
            "line 6, column 8: expected x, found the end of the input"
        );
        assert_eq!(words(Lexer::new(Trickle(text.as_bytes(), 0))), whole);
    }

    /// A lexer given the next bytes in hand reads what one reading them from its input
    /// reads: the same words, places and last message, whatever more the input holds.
    #[test]
    fn bytes_in_hand_read_as_bytes_read() {
        let text = "colour 1 2 3\n1.5 -2 3\n  4 5 6 # c\nNEXT.POLYGON\nx\u{3000}y 7\n";
        for cut in [0, 1, 13, 22, text.find('#').unwrap(), text.len()] {
            let (hand, rest) = text.as_bytes().split_at(cut);
            let read = words(Lexer::resume(text.as_bytes(), 4, "prev".to_string()));
            let in_hand = words(Lexer::resume_with(
                hand.to_vec(),
                Trickle(rest, 0),
                4,
                "prev".to_string(),
            ));
            assert_eq!(in_hand, read, "{cut}");
            assert_eq!(read.0[0], ("colour".to_string(), (5, 1)));
        }
        // Nothing in hand, and nothing more: the end, after the last line.
        let (found, message) = words(Lexer::resume_with(vec![], &b""[..], 7, "a b".into()));
        assert!(found.is_empty());
        assert_eq!(
            message,
            "line 7, column 4: expected x, found the end of the input"
        );
    }

    #[test]
    fn words_end_at_whitespace_only() {
        let line = b"abcdefghijk\x00lmnop\x1aq rest\tx\x0by 12345678901234567890";
        let words: Vec<&[u8]> = {
            let mut v = Vec::new();
            let mut i = 0;
            while i < line.len() {
                while i < line.len() && is_space(line[i]) {
                    i += 1;
                }
                let end = word_end(line, i);
                v.push(&line[i..end]);
                i = end;
            }
            v
        };
        assert_eq!(
            words,
            [
                &b"abcdefghijk\x00lmnop\x1aq"[..],
                b"rest",
                b"x",
                b"y",
                b"12345678901234567890"
            ]
        );
        for n in 0..20 {
            let w = vec![b'7'; n];
            assert_eq!(word_end(&w, 0), n);
        }
    }

    #[test]
    fn messages_escape_what_cannot_be_seen() {
        assert_eq!(Shown("a\0b\x1a").to_string(), "a\\x00b\\x1a");
        assert_eq!(
            Shown("\u{feff}x\u{200b}").to_string(),
            "\\u{feff}x\\u{200b}"
        );
        assert_eq!(Shown("plain é").to_string(), "plain é");
        // A long word: its first 80 characters and its length in bytes.
        let long = "é".repeat(100);
        assert_eq!(
            Shown(&long).to_string(),
            format!("{}… (200 bytes)", "é".repeat(80))
        );
        assert_eq!(Shown(&"x".repeat(80)).to_string(), "x".repeat(80));
        // A byte-order mark first is skipped; elsewhere it is escaped and named.
        let mut lx = Lexer::new("\u{feff}polypipe\n\u{feff}1\n".as_bytes());
        assert_eq!(lx.next_word().unwrap().as_deref(), Some("polypipe"));
        assert_eq!(lx.mark(), (1, 1));
        assert_eq!(
            lx.integer("the version", 9).unwrap_err().to_string(),
            "line 2, column 1: expected the version (an integer 0..=9), found `\\u{feff}1` \
             (\\u{feff} is a UTF-8 byte-order mark)"
        );
    }

    #[test]
    fn large_and_tiny_numbers_show_in_exponent_form() {
        assert_eq!(Number(1e300).to_string(), "1e300");
        assert_eq!(Number(-2.5e-7).to_string(), "-2.5e-7");
        assert_eq!(Number(1e16).to_string(), "1e16");
        assert_eq!(Number(9999999999999998.0).to_string(), "9999999999999998");
        assert_eq!(Number(0.000001).to_string(), "0.000001");
        assert_eq!(Number(0.0).to_string(), "0");
        assert_eq!(Number(30.0).to_string(), "30");
    }
}
