//! The stream codec: one reader and one writer for both forms of both record kinds.
//!
//! A stream is a [`Header`] followed by records and closed by an END record
//! (thesis Appendix 1: `movie ::= frame { NEXT.FRAME frame } END`). The binary form is the
//! header's magic followed by bincode records (fixed-width little-endian integers, so a
//! record's size never depends on its values); the text form is words and lines for
//! people and tests. A reader recognises the form from the first bytes; every stage
//! writes binary unless asked for text.
//!
//! Records are of two kinds, each a [`Record`]: the polygon stream's [`Token`]s and the
//! scan converter's [`Fragment`]s. Both number their polygons the same way, so the reader
//! can say which frame and polygon an error is in.
//!
//! [`Token`]: crate::Token
//! [`Fragment`]: crate::Fragment

use crate::header::{Header, Space, BINARY_MAGIC, TEXT_MAGIC, VERSION};
use crate::text::Lexer;
use crate::StreamError;
use bincode::Options;
use serde::{de::DeserializeOwned, Serialize};
use std::io::{self, BufRead, BufReader, BufWriter, Read, Write};

/// The largest binary record a reader accepts: 64 MiB, two million eye-space vertices.
/// A corrupt length field cannot make a stage allocate more than this.
pub const MAX_RECORD_BYTES: u64 = 64 << 20;

/// The most vertices a polygon may have (the same bound in both forms).
pub const MAX_VERTICES: usize = (MAX_RECORD_BYTES / 32) as usize - 1;

/// Buffer size for stage input and output: large enough that a pipe is read and written
/// in a few system calls per thousand polygons.
const IO_BUFFER: usize = 1 << 16;

/// Which form a stream is written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    Binary,
    Text,
}

impl Form {
    /// `--text` on the command line means text; binary otherwise.
    pub fn from_text_flag(text: bool) -> Self {
        if text {
            Form::Text
        } else {
            Form::Binary
        }
    }
}

fn bincode_options() -> impl Options {
    bincode::DefaultOptions::new()
        .with_fixint_encoding()
        .with_little_endian()
        .with_limit(MAX_RECORD_BYTES)
}

/// What a record means to the stream's grammar.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Control {
    /// A record that starts a polygon (and so is preceded by NEXT.POLYGON in text,
    /// unless it is the frame's first).
    Polygon,
    /// A record inside a polygon (a fragment's span or pixel).
    Data,
    /// `skip N`: stands for the next N polygons of the frame, none of which sends
    /// anything down this branch (the lean stream of a splitter tree). It keeps polygon
    /// numbering, so ties still go to the earlier polygon, and is counted as N polygons.
    Skip(u32),
    /// A record of finished pixels (a leaf's resolved region): belongs to no polygon and
    /// may stand anywhere in a frame.
    Finished,
    NextFrame,
    End,
}

/// A kind of record: how it is checked and how it is written and read as text.
pub trait Record: Serialize + DeserializeOwned + Sized {
    /// The record's role in the grammar.
    fn control(&self) -> Control;

    /// Checks a decoded binary record (finite numbers, sizes); the message names what is
    /// wrong and the reader adds where.
    fn validate(&self, space: &Space) -> Result<(), String>;

    /// Reads one record of the text form. `first_in_frame` says whether a polygon record
    /// here starts the frame (no NEXT.POLYGON before it). At the end of the input, fails.
    fn read_text<R: BufRead>(
        lex: &mut Lexer<R>,
        space: &Space,
        first_in_frame: bool,
    ) -> Result<Self, StreamError>;

    /// Writes one record in the text form, NEXT.POLYGON first where one is due.
    fn write_text<W: Write>(
        &self,
        out: &mut W,
        space: &Space,
        first_in_frame: bool,
    ) -> io::Result<()>;
}

/// A `Read` that counts the bytes taken, so that binary errors can say where they are.
struct Counted<R> {
    inner: BufReader<R>,
    offset: u64,
}

impl<R: Read> Read for Counted<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.offset += n as u64;
        Ok(n)
    }

    fn read_exact(&mut self, buf: &mut [u8]) -> io::Result<()> {
        // The hot path: a few bytes at a time out of the buffer.
        let available = self.inner.buffer();
        if available.len() >= buf.len() {
            buf.copy_from_slice(&available[..buf.len()]);
            self.inner.consume(buf.len());
            self.offset += buf.len() as u64;
            return Ok(());
        }
        let mut done = 0;
        while done < buf.len() {
            match self.inner.read(&mut buf[done..]) {
                Ok(0) => {
                    self.offset += done as u64;
                    return Err(io::ErrorKind::UnexpectedEof.into());
                }
                Ok(n) => done += n,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => {
                    self.offset += done as u64;
                    return Err(e);
                }
            }
        }
        self.offset += done as u64;
        Ok(())
    }
}

enum Source<R> {
    Binary(Counted<R>),
    Text(Lexer<BufReader<R>>),
}

/// Reads a stream of records of kind `T`, one at a time, from either form.
pub struct Reader<T, R> {
    source: Source<R>,
    header: Header,
    /// Frame number (from 0) of the next record.
    frame: u64,
    /// Polygon-starting records seen in the current frame.
    polygons_in_frame: u64,
    ended: bool,
    _kind: std::marker::PhantomData<T>,
}

impl<T: Record, R: Read> Reader<T, R> {
    /// Reads the header, recognising the form from the first bytes.
    pub fn new(input: R) -> Result<Self, StreamError> {
        let mut buffered = BufReader::with_capacity(IO_BUFFER, input);
        let first = loop {
            match buffered.fill_buf() {
                Ok(b) => break b,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e.into()),
            }
        };
        if first.is_empty() {
            return Err(StreamError::Invalid(
                "empty input: expected a polypipe stream header".into(),
            ));
        }
        let (source, header) = if first[0] == BINARY_MAGIC[0] {
            let mut counted = Counted {
                inner: buffered,
                offset: 0,
            };
            let header = read_binary_header(&mut counted)?;
            (Source::Binary(counted), header)
        } else {
            let mut lex = Lexer::new(buffered);
            let header = read_text_header(&mut lex)?;
            (Source::Text(lex), header)
        };
        Ok(Reader {
            source,
            header,
            frame: 0,
            polygons_in_frame: 0,
            ended: false,
            _kind: std::marker::PhantomData,
        })
    }

    pub fn header(&self) -> &Header {
        &self.header
    }

    /// Where the reader is, in the stream's own terms, for messages about a record:
    /// `frame 0, polygon 3` (both from 0).
    pub fn position(&self) -> String {
        format!(
            "frame {}, polygon {}",
            self.frame,
            self.polygons_in_frame.saturating_sub(1)
        )
    }

    /// The next record, or `None` once END has been read (and nothing follows it).
    /// NEXT.FRAME and END are returned as records; after END this returns `None`.
    pub fn next_record(&mut self) -> Result<Option<T>, StreamError> {
        if self.ended {
            return Ok(None);
        }
        let first_in_frame = self.polygons_in_frame == 0;
        let record = match &mut self.source {
            Source::Binary(input) => {
                if input.inner.fill_buf()?.is_empty() {
                    return Err(StreamError::Binary {
                        offset: input.offset,
                        context: String::new(),
                        msg: "the stream ends without END (cut short?)".into(),
                    });
                }
                let start = input.offset;
                let record: T = bincode_options().deserialize_from(&mut *input).map_err(|e| {
                    let msg = match *e {
                        bincode::ErrorKind::Io(ref io) if io.kind() == io::ErrorKind::UnexpectedEof => {
                            "the stream ends in the middle of a record (cut short?)".to_string()
                        }
                        bincode::ErrorKind::Io(io) => return StreamError::Io(io),
                        bincode::ErrorKind::SizeLimit => format!(
                            "record larger than {MAX_RECORD_BYTES} bytes (at most {MAX_VERTICES} vertices a polygon)"
                        ),
                        other => format!("not a valid record ({other}); is the stream corrupt?"),
                    };
                    StreamError::Binary {
                        offset: start,
                        context: String::new(),
                        msg,
                    }
                })?;
                if record.control() == Control::Data && first_in_frame {
                    return Err(StreamError::Binary {
                        offset: start,
                        context: format!(" (frame {})", self.frame),
                        msg: "pixels before the frame's first colour record".into(),
                    });
                }
                if let Err(msg) = record.validate(&self.header.space) {
                    let context = if matches!(record.control(), Control::Polygon | Control::Skip(_)) {
                        format!(
                            " (frame {}, polygon {})",
                            self.frame, self.polygons_in_frame
                        )
                    } else {
                        format!(" ({})", self.position())
                    };
                    return Err(StreamError::Binary {
                        offset: start,
                        context,
                        msg,
                    });
                }
                record
            }
            Source::Text(lex) => {
                if lex.peek()?.is_none() {
                    return Err(lex.error_at_end("the stream ends without END (cut short?)"));
                }
                T::read_text(lex, &self.header.space, first_in_frame)?
            }
        };
        match record.control() {
            Control::Polygon => self.polygons_in_frame += 1,
            Control::Skip(n) => self.polygons_in_frame += n as u64,
            Control::Data | Control::Finished => {}
            Control::NextFrame => {
                self.frame += 1;
                self.polygons_in_frame = 0;
            }
            Control::End => {
                self.ended = true;
                self.expect_nothing_after_end()?;
            }
        }
        Ok(Some(record))
    }

    fn expect_nothing_after_end(&mut self) -> Result<(), StreamError> {
        match &mut self.source {
            Source::Binary(input) => {
                if !input.inner.fill_buf()?.is_empty() {
                    return Err(StreamError::Binary {
                        offset: input.offset,
                        context: String::new(),
                        msg: "data after END".into(),
                    });
                }
            }
            Source::Text(lex) => {
                if let Some(w) = lex.peek()? {
                    let w = w.to_string();
                    return Err(lex.error(format!("data after END: `{w}`")));
                }
            }
        }
        Ok(())
    }
}

fn read_binary_header<R: Read>(input: &mut Counted<R>) -> Result<Header, StreamError> {
    let mut magic = [0u8; 8];
    let bad = |offset, msg: &str| StreamError::Binary {
        offset,
        context: String::new(),
        msg: msg.to_string(),
    };
    if input.read_exact(&mut magic).is_err() || magic != BINARY_MAGIC {
        return Err(bad(0, "not a polypipe stream (bad magic)"));
    }
    let header: Header = bincode_options()
        .deserialize_from(&mut *input)
        .map_err(|_| bad(8, "unreadable stream header"))?;
    if header.version != VERSION {
        return Err(bad(
            8,
            &format!(
                "stream version {} is not supported (this is version {VERSION})",
                header.version
            ),
        ));
    }
    check_space(&header.space).map_err(|m| bad(8, &m))?;
    Ok(header)
}

fn read_text_header<R: BufRead>(lex: &mut Lexer<R>) -> Result<Header, StreamError> {
    let magic = lex.expect_word("the header `polypipe 1 SPACE`")?;
    if magic != TEXT_MAGIC {
        return Err(lex.error(format!(
            "not a polypipe stream: expected the header `polypipe 1 SPACE`, found `{}`",
            magic.chars().take(20).collect::<String>()
        )));
    }
    let version = lex.integer("the stream version", u32::MAX as u64)? as u32;
    if version != VERSION {
        return Err(lex.error(format!(
            "stream version {version} is not supported (this is version {VERSION})"
        )));
    }
    let space_word = lex.expect_word("a coordinate space (world, eye, screen W H)")?;
    let space_at = lex.mark();
    let space = match space_word.as_str() {
        "world" => Space::World,
        "eye" => {
            let mut view = crate::View::default();
            while let Some(w) = lex.peek()? {
                let slot = match w {
                    "aspect" => &mut view.aspect,
                    "hither" => &mut view.hither,
                    "yon" => &mut view.yon,
                    _ => break,
                };
                let name = w.to_string();
                lex.next_word()?;
                *slot = lex.number(&format!("the {name} value"))?;
            }
            Space::Eye(view)
        }
        "screen" | "fragments" => {
            let width = lex.integer("the screen width", u32::MAX as u64)? as u32;
            let height = lex.integer("the screen height", u32::MAX as u64)? as u32;
            if space_word == "screen" {
                Space::Screen { width, height }
            } else {
                Space::Fragments { width, height }
            }
        }
        other => {
            return Err(lex.error(format!(
                "unknown coordinate space `{other}` (expected world, eye, screen or fragments)"
            )))
        }
    };
    check_space(&space).map_err(|m| lex.error_at(space_at, m))?;
    Ok(Header { version, space })
}

/// The header's numbers must make sense before any stage computes with them.
fn check_space(space: &Space) -> Result<(), String> {
    match *space {
        Space::Eye(v) => {
            if !(v.aspect.is_finite() && v.aspect > 0.0) {
                return Err(format!("aspect ratio {} must be positive", v.aspect));
            }
            if !(v.hither.is_finite() && v.yon.is_finite() && 0.0 < v.hither && v.hither < v.yon) {
                return Err(format!(
                    "hither {} and yon {} must satisfy 0 < hither < yon",
                    v.hither, v.yon
                ));
            }
        }
        Space::Screen { width, height } | Space::Fragments { width, height } => {
            if width == 0 || height == 0 || width > 1 << 16 || height > 1 << 16 {
                return Err(format!(
                    "screen size {width}x{height} must be between 1x1 and 65536x65536"
                ));
            }
        }
        Space::World => {}
    }
    Ok(())
}

/// Writes a stream of records of kind `T` in either form, buffered.
pub struct Writer<T, W: Write> {
    out: BufWriter<W>,
    form: Form,
    space: Space,
    polygons_in_frame: u64,
    _kind: std::marker::PhantomData<T>,
}

impl<T: Record, W: Write> Writer<T, W> {
    /// Writes the header.
    pub fn new(out: W, header: Header, form: Form) -> io::Result<Self> {
        let mut out = BufWriter::with_capacity(IO_BUFFER, out);
        match form {
            Form::Binary => {
                out.write_all(&BINARY_MAGIC)?;
                bincode_options()
                    .serialize_into(&mut out, &header)
                    .map_err(into_io)?;
            }
            Form::Text => writeln!(out, "{TEXT_MAGIC} {} {}", header.version, header.space)?,
        }
        Ok(Writer {
            out,
            form,
            space: header.space,
            polygons_in_frame: 0,
            _kind: std::marker::PhantomData,
        })
    }

    /// Writes one record.
    pub fn write(&mut self, record: &T) -> io::Result<()> {
        match self.form {
            Form::Binary => bincode_options()
                .serialize_into(&mut self.out, record)
                .map_err(into_io)?,
            Form::Text => {
                record.write_text(&mut self.out, &self.space, self.polygons_in_frame == 0)?
            }
        }
        match record.control() {
            Control::Polygon => self.polygons_in_frame += 1,
            Control::Skip(n) => self.polygons_in_frame += n as u64,
            // A frame boundary is flushed at once. In the splitter tree zbuf waits at
            // NEXT.FRAME for every input; a boundary left in one branch's buffer while
            // the stage blocks on another branch would deadlock the tree.
            Control::NextFrame | Control::End => {
                self.polygons_in_frame = 0;
                self.out.flush()?;
            }
            Control::Data | Control::Finished => {}
        }
        Ok(())
    }

    /// Flushes what is buffered (after END, or before waiting on a slow input).
    pub fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }

    /// Flushes and hands back the underlying writer.
    pub fn into_inner(self) -> io::Result<W> {
        self.out.into_inner().map_err(|e| e.into_error())
    }
}

#[allow(clippy::boxed_local)] // bincode::Error is a Box; this takes what bincode returns
fn into_io(e: bincode::Error) -> io::Error {
    match *e {
        bincode::ErrorKind::Io(io) => io,
        other => io::Error::other(other.to_string()),
    }
}
