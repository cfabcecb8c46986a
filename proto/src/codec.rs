//! The stream codec: one reader and one writer for both forms of both record kinds.
//!
//! A stream is a [`Header`] followed by records and closed by an END record
//! (thesis Appendix 1: `movie ::= frame { NEXT.FRAME frame } END`). The binary form is the
//! header's magic, the header in bincode, then fixed-layout records (below); the text form
//! is words and lines for people and tests. A reader recognises the form from the first
//! bytes; every stage writes binary unless asked for text.
//!
//! Records are of two kinds, each a [`Record`]: the polygon stream's [`Token`]s and the
//! scan converter's [`Fragment`]s. Both number their polygons the same way, so the reader
//! can say which frame and polygon an error is in.
//!
//! ## The binary records (stream version 2)
//!
//! Every record starts with an 8-byte head, `tag: u8, colour: [u8; 3], n: u32`, and is a
//! multiple of 8 bytes long; all numbers are little-endian, vertices four `f64`s
//! (`x, y, z, w`, 32 bytes). A vertex list is written and read as one block, straight
//! from and into the polygon's own `Vec` (a byte view of it, `bytemuck`), so a stage
//! neither formats nor allocates per polygon. Version 1 encoded the same records with
//! serde and bincode; `bench stages codec` measures the two, and the record
//! decoding was most of a geometry stage's time (the header stays bincode: it is read
//! once). The layouts are in [`polygons`] and [`crate::fragment`]. Bytes a record
//! does not use must be zero, so a corrupt stream is caught at the record where it
//! goes wrong rather than read as other numbers.
//!
//! [`Token`]: crate::Token
//! [`Fragment`]: crate::Fragment

pub mod polygons;

use crate::header::{text_version, Header, Space, BINARY_MAGIC, TEXT_MAGIC, VERSION};
use crate::text::{Lexer, Number, Shown};
use crate::StreamError;
use bincode::Options;
use glam::{DVec3, DVec4};
use std::io::{self, BufRead, BufReader, BufWriter, Read, Write};

/// The largest binary record a reader accepts: 64 MiB, two million eye-space vertices.
/// A corrupt length field cannot make a stage allocate more than this; and as a record's
/// vertices are read in blocks as they arrive, a length the stream does not back up
/// allocates no more than the stream holds.
pub const MAX_RECORD_BYTES: u64 = 64 << 20;

/// The most vertices a polygon may have (the same bound in both forms).
pub const MAX_VERTICES: usize = (MAX_RECORD_BYTES / 32) as usize - 1;

/// Buffer size for stage input and output: large enough that a pipe is read and written
/// in a few system calls per thousand polygons.
const IO_BUFFER: usize = 1 << 16;

// The lexer's reads go past a text reader's `BufReader` (see `text::BUFFER`).
const _: () = assert!(crate::text::BUFFER >= 2 * IO_BUFFER);

/// Vertices read per block of a long vertex list (64 KiB).
const VERTEX_BLOCK: usize = 2048;

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

/// The header's encoding (bincode, fixed-width little-endian integers).
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

/// Why a binary record could not be decoded; the reader adds where it was.
#[derive(Debug)]
pub enum BinaryError {
    /// The input ends inside the record.
    CutShort,
    /// The record claims more than [`MAX_RECORD_BYTES`].
    TooLarge,
    /// The bytes are no record of this kind (an unknown tag, a reserved byte set).
    Invalid(String),
    /// The operating system refused the read.
    Io(io::Error),
}

/// A kind of record: how it is checked, and how it is written and read in both forms.
///
/// Reading goes *into* a record that the caller keeps ([`Reader::next_into`]), so that a
/// polygon's vertex list is reused from one polygon to the next; `spare` is the reader's
/// own second record, where a polygon's buffers wait while the caller's record holds a
/// NEXT.FRAME or a skip.
pub trait Record: Sized + Default {
    /// The record's role in the grammar.
    fn control(&self) -> Control;

    /// The role of the binary record that starts with `head`, if its tag is known: what
    /// the reader names in a message about a record it could not finish reading.
    fn binary_control(head: &[u8; 8]) -> Option<Control>;

    /// Checks a decoded binary record (finite numbers, sizes, what the header declares);
    /// the message names what is wrong and the reader adds where.
    fn validate(&self, header: &Header) -> Result<(), String>;

    /// Decodes the rest of the binary record that starts with `head` into `self`.
    fn read_binary<R: Read>(
        &mut self,
        spare: &mut Self,
        head: &[u8; 8],
        input: &mut BinaryInput<R>,
    ) -> Result<(), BinaryError>;

    /// Writes the record's binary form.
    fn write_binary<W: Write>(&self, out: &mut W) -> io::Result<()>;

    /// Reads one record of the text form into `self`. `first_in_frame` says whether a
    /// polygon record here starts the frame (no NEXT.POLYGON before it). At the end of
    /// the input, fails.
    fn read_text<R: BufRead>(
        &mut self,
        spare: &mut Self,
        lex: &mut Lexer<R>,
        header: &Header,
        first_in_frame: bool,
    ) -> Result<(), StreamError>;

    /// Writes one record in the text form, NEXT.POLYGON first where one is due.
    fn write_text<W: Write>(
        &self,
        out: &mut W,
        header: &Header,
        first_in_frame: bool,
    ) -> io::Result<()>;
}

/// The binary form's input: buffered, counting the bytes taken so that errors can say
/// where they are, and handing out records' bytes without a system call per record.
pub struct BinaryInput<R> {
    inner: BufReader<R>,
    offset: u64,
}

impl<R: Read> BinaryInput<R> {
    /// The offset of the next byte from the start of the stream.
    pub fn offset(&self) -> u64 {
        self.offset
    }

    /// Fills `buf` from the input.
    #[inline]
    pub fn read_exact(&mut self, buf: &mut [u8]) -> Result<(), BinaryError> {
        // The hot path: the bytes are in the buffer already.
        let available = self.inner.buffer();
        if available.len() >= buf.len() {
            buf.copy_from_slice(&available[..buf.len()]);
            self.inner.consume(buf.len());
            self.offset += buf.len() as u64;
            return Ok(());
        }
        self.read_exact_slow(buf)
    }

    #[cold]
    fn read_exact_slow(&mut self, buf: &mut [u8]) -> Result<(), BinaryError> {
        let mut done = 0;
        while done < buf.len() {
            match self.inner.read(&mut buf[done..]) {
                Ok(0) => {
                    self.offset += done as u64;
                    return Err(BinaryError::CutShort);
                }
                Ok(n) => done += n,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => {
                    self.offset += done as u64;
                    return Err(BinaryError::Io(e));
                }
            }
        }
        self.offset += done as u64;
        Ok(())
    }

    /// The next `N` bytes.
    #[inline]
    pub fn array<const N: usize>(&mut self) -> Result<[u8; N], BinaryError> {
        let mut a = [0u8; N];
        self.read_exact(&mut a)?;
        Ok(a)
    }

    /// One vertex (four little-endian `f64`s).
    #[inline]
    pub fn vertex(&mut self) -> Result<DVec4, BinaryError> {
        let b: [u8; 32] = self.array()?;
        Ok(vertex_from_le(&b))
    }

    /// Replaces `vertices` by the next `n` vertices. The list grows block by block as the
    /// bytes arrive, so a corrupt `n` allocates no more than the stream holds.
    #[inline]
    pub fn vertices(&mut self, vertices: &mut Vec<DVec4>, n: usize) -> Result<(), BinaryError> {
        vertices.clear();
        while vertices.len() < n {
            let from = vertices.len();
            let to = from + (n - from).min(VERTEX_BLOCK);
            vertices.resize(to, DVec4::ZERO);
            self.read_exact(bytemuck::cast_slice_mut(&mut vertices[from..to]))?;
        }
        #[cfg(target_endian = "big")]
        for x in bytemuck::cast_slice_mut::<DVec4, f64>(vertices) {
            *x = f64::from_bits(u64::from_le(x.to_bits()));
        }
        Ok(())
    }

    /// Reads `n` vertex attributes (three little-endian `f64`s each: colours or normals,
    /// as the header says) into `colours`, in blocks as they arrive, as
    /// [`BinaryInput::vertices`] reads vertices.
    #[inline]
    pub fn vertex_attrs(&mut self, colours: &mut Vec<DVec3>, n: usize) -> Result<(), BinaryError> {
        colours.clear();
        while colours.len() < n {
            let from = colours.len();
            let to = from + (n - from).min(VERTEX_BLOCK);
            colours.resize(to, DVec3::ZERO);
            self.read_exact(bytemuck::cast_slice_mut(&mut colours[from..to]))?;
        }
        #[cfg(target_endian = "big")]
        for x in bytemuck::cast_slice_mut::<DVec3, f64>(colours) {
            *x = f64::from_bits(u64::from_le(x.to_bits()));
        }
        Ok(())
    }

    /// Whether the input is at its end (no byte left).
    fn at_end(&mut self) -> io::Result<bool> {
        loop {
            match self.inner.fill_buf() {
                Ok(b) => return Ok(b.is_empty()),
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
    }
}

/// A vertex from its 32 little-endian bytes.
#[inline]
pub fn vertex_from_le(b: &[u8; 32]) -> DVec4 {
    let f = |i: usize| f64::from_le_bytes(b[i..i + 8].try_into().expect("8 bytes"));
    DVec4::new(f(0), f(8), f(16), f(24))
}

/// Writes vertices as little-endian `f64`s, as one block on a little-endian machine.
#[inline]
pub fn write_vertices<W: Write>(out: &mut W, vertices: &[DVec4]) -> io::Result<()> {
    #[cfg(target_endian = "little")]
    {
        out.write_all(bytemuck::cast_slice(vertices))
    }
    #[cfg(target_endian = "big")]
    {
        for x in bytemuck::cast_slice::<DVec4, f64>(vertices) {
            out.write_all(&x.to_le_bytes())?;
        }
        Ok(())
    }
}

/// Writes vertex attributes (colours or normals) as one block of little-endian `f64`s,
/// three a vertex.
#[inline]
pub fn write_vertex_attrs<W: Write>(out: &mut W, colours: &[DVec3]) -> io::Result<()> {
    #[cfg(target_endian = "little")]
    {
        out.write_all(bytemuck::cast_slice(colours))
    }
    #[cfg(target_endian = "big")]
    {
        for x in bytemuck::cast_slice::<DVec3, f64>(colours) {
            out.write_all(&x.to_le_bytes())?;
        }
        Ok(())
    }
}

/// A record's 8-byte head: tag, three bytes (a colour, or zero) and a count or number.
#[inline]
pub fn head(tag: u8, bytes: [u8; 3], n: u32) -> [u8; 8] {
    let n = n.to_le_bytes();
    [tag, bytes[0], bytes[1], bytes[2], n[0], n[1], n[2], n[3]]
}

/// The head's `n` field.
#[inline]
pub fn head_n(head: &[u8; 8]) -> u32 {
    u32::from_le_bytes([head[4], head[5], head[6], head[7]])
}

/// Refuses a head whose unused bytes (the colour slot, or also `n`) are not zero.
pub fn expect_zero(head: &[u8; 8], with_n: bool, what: &str) -> Result<(), BinaryError> {
    let unused = if with_n { &head[1..] } else { &head[1..4] };
    if unused.iter().any(|&b| b != 0) {
        return Err(BinaryError::Invalid(format!(
            "not a valid {what} record (unused bytes {unused:02x?} are not zero); is the stream corrupt?"
        )));
    }
    Ok(())
}

enum Source<R> {
    Binary(BinaryInput<R>),
    Text(Lexer<BufReader<R>>),
}

/// Reads a stream of records of kind `T`, one at a time, from either form.
pub struct Reader<T, R> {
    source: Source<R>,
    header: Header,
    /// Frame number (from 0) of the next record.
    frame: u64,
    /// Polygon-starting records seen in the current frame (a skip counts its N).
    polygons_in_frame: u64,
    ended: bool,
    /// Where a polygon's buffers wait while the caller's record holds something else.
    spare: T,
    /// A piece of a text stream ([`Reader::piece_of_text`]): its end is not an error.
    piece: bool,
}

/// A text stream taken apart after its header ([`Reader::into_text_rest`]): the bytes read
/// but not yet lexed, then the rest of the input; `lines` lines were read.
pub struct TextRest<R> {
    pub unread: Vec<u8>,
    pub input: R,
    pub lines: u64,
    /// The header's last line, from the end of which a message about a stream that
    /// stops there counts its column.
    pub last_line: String,
}

/// Where a binary record of role `control` stands, for a message: ` (frame F, polygon
/// P)` for a record of polygon P, ` (frame F)` for one of the frame as a whole, and for
/// a record of unknown role (its head unread or its tag unknown), the last polygon read.
fn binary_context(frame: u64, polygons_in_frame: u64, control: Option<Control>) -> String {
    match control {
        Some(Control::Polygon | Control::Skip(_)) => {
            format!(" (frame {frame}, polygon {polygons_in_frame})")
        }
        Some(Control::Data) if polygons_in_frame > 0 => {
            format!(" (frame {frame}, polygon {})", polygons_in_frame - 1)
        }
        Some(_) => format!(" (frame {frame})"),
        None if polygons_in_frame > 0 => {
            format!(" (frame {frame}, after polygon {})", polygons_in_frame - 1)
        }
        None => format!(" (frame {frame}, before its first polygon)"),
    }
}

impl<T: Record, R: Read> Reader<T, R> {
    /// Hands a decoder of the binary input's bytes already buffered (with the header)
    /// to `take`, which returns how many of them it decoded: whole records that change
    /// no count of the reader's (only [`Control::Finished`] ones, a leaf's runs), checked
    /// as [`Reader::next_into`] checks them. A text stream, or one ended, gives nothing.
    pub(crate) fn decode_buffered(&mut self, take: impl FnOnce(&[u8], &Header) -> usize) {
        if self.ended {
            return;
        }
        if let Source::Binary(input) = &mut self.source {
            let used = take(input.inner.buffer(), &self.header);
            input.inner.consume(used);
            input.offset += used as u64;
        }
    }

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
            let mut input = BinaryInput {
                inner: buffered,
                offset: 0,
            };
            let header = read_binary_header(&mut input)?;
            (Source::Binary(input), header)
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
            spare: T::default(),
            piece: false,
        })
    }

    /// A reader of a text stream from part way through: `input` starts at the start of a
    /// line, after `lines` lines (the last of them `last_line`, see [`Lexer::resume`]),
    /// in frame `frame` after `polygons_in_frame` of its polygons. It reads what a reader
    /// of the whole stream would read from there, with the same messages.
    pub fn resume_text(
        input: R,
        header: Header,
        (lines, last_line): (u64, String),
        frame: u64,
        polygons_in_frame: u64,
    ) -> Self {
        let lex = Lexer::resume(BufReader::with_capacity(IO_BUFFER, input), lines, last_line);
        Self::resumed(lex, header, (frame, polygons_in_frame), false)
    }

    /// A reader of text from `lex`, a lexer resumed part way through a stream, in frame
    /// `frame` after `polygons_in_frame` of its polygons; `piece`: its input's end is a
    /// piece's, not the stream's.
    fn resumed(
        lex: Lexer<BufReader<R>>,
        header: Header,
        (frame, polygons_in_frame): (u64, u64),
        piece: bool,
    ) -> Self {
        Reader {
            source: Source::Text(lex),
            header,
            frame,
            polygons_in_frame,
            ended: false,
            spare: T::default(),
            piece,
        }
    }

    /// A text stream's rest, right after its header (for a reader of it in pieces,
    /// `stagecli`'s); a binary stream, or a text one whose header line goes on, is handed
    /// back.
    #[allow(clippy::result_large_err)] // once a stream, and the reader is handed back whole
    pub fn into_text_rest(self) -> Result<TextRest<R>, Self> {
        let fresh = self.frame == 0 && self.polygons_in_frame == 0 && !self.ended && !self.piece;
        match self.source {
            Source::Text(lex) if fresh => match lex.into_rest() {
                Ok((mut unread, buffered, lines, last_line)) => {
                    unread.extend_from_slice(buffered.buffer());
                    Ok(TextRest {
                        unread,
                        input: buffered.into_inner(),
                        lines,
                        last_line,
                    })
                }
                Err(lex) => Err(Reader {
                    source: Source::Text(lex),
                    ..self
                }),
            },
            source => Err(Reader { source, ..self }),
        }
    }

    pub fn header(&self) -> &Header {
        &self.header
    }

    /// The same stream, read on as records of kind `U`: for a stage that takes more than
    /// one kind of stream and learns which from the header (`zbuf` reads fragments, or a
    /// screen-space polygon stream that it resolves itself). Meant to be called before
    /// the first record; the position and the frame count carry over.
    pub fn into_kind<U: Record>(self) -> Reader<U, R> {
        Reader {
            source: self.source,
            header: self.header,
            frame: self.frame,
            polygons_in_frame: self.polygons_in_frame,
            ended: self.ended,
            spare: U::default(),
            piece: self.piece,
        }
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
    /// A stage's loop should use [`Reader::next_into`], which reuses its record.
    pub fn next_record(&mut self) -> Result<Option<T>, StreamError> {
        let mut record = T::default();
        Ok(self.next_into(&mut record)?.then_some(record))
    }

    /// Reads the next record into `record`, reusing its buffers (a polygon's vertex
    /// list): `false` once END has been read (and nothing follows it), leaving `record`
    /// as it was. NEXT.FRAME and END are records like the others.
    pub fn next_into(&mut self, record: &mut T) -> Result<bool, StreamError> {
        if self.ended {
            return Ok(false);
        }
        let first_in_frame = self.polygons_in_frame == 0;
        let (frame, polygons) = (self.frame, self.polygons_in_frame);
        match &mut self.source {
            Source::Binary(input) => {
                let start = input.offset;
                let fail = |offset, control, msg: String| StreamError::Binary {
                    offset,
                    context: binary_context(frame, polygons, control),
                    msg,
                };
                let decoded = if input.at_end()? {
                    return Err(fail(
                        start,
                        None,
                        "the stream ends without END (cut short?)".into(),
                    ));
                } else {
                    input.array::<8>().map_err(|e| (e, None)).and_then(|head| {
                        record
                            .read_binary(&mut self.spare, &head, input)
                            .map_err(|e| (e, T::binary_control(&head)))
                    })
                };
                if let Err((e, control)) = decoded {
                    let msg = match e {
                        BinaryError::CutShort => {
                            "the stream ends in the middle of a record (cut short?)".to_string()
                        }
                        BinaryError::Io(io) => return Err(StreamError::Io(io)),
                        BinaryError::TooLarge => format!(
                            "record larger than {MAX_RECORD_BYTES} bytes (at most {MAX_VERTICES} vertices a polygon)"
                        ),
                        BinaryError::Invalid(msg) => msg,
                    };
                    return Err(fail(start, control, msg));
                }
                let control = record.control();
                if control == Control::Data && first_in_frame {
                    return Err(fail(
                        start,
                        Some(Control::NextFrame),
                        "pixels before the frame's first colour record".into(),
                    ));
                }
                if let Err(msg) = record.validate(&self.header) {
                    return Err(fail(start, Some(control), msg));
                }
            }
            Source::Text(lex) => {
                // (A word that the buffer shows is ahead needs no peek, which would copy
                // its line: between two polygons, the NEXT.POLYGON line.)
                if !lex.word_ahead() && lex.peek()?.is_none() {
                    if self.piece {
                        return Ok(false);
                    }
                    return Err(lex.error_at_end("the stream ends without END (cut short?)"));
                }
                record.read_text(&mut self.spare, lex, &self.header, first_in_frame)?;
            }
        }
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
        Ok(true)
    }

    fn expect_nothing_after_end(&mut self) -> Result<(), StreamError> {
        match &mut self.source {
            Source::Binary(input) => {
                if !input.at_end()? {
                    return Err(StreamError::Binary {
                        offset: input.offset,
                        context: String::new(),
                        msg: "data after END".into(),
                    });
                }
            }
            Source::Text(lex) => {
                if let Some(w) = lex.peek()? {
                    let msg = format!("data after END: `{}`", Shown(w));
                    return Err(lex.error(msg));
                }
            }
        }
        Ok(())
    }
}

impl<'a, T: Record> Reader<T, &'a [u8]> {
    /// [`Reader::resume_text`] over a piece of a stream cut between two records, in
    /// memory, whose end is the end of the piece: `next_into` answers `false` there (or
    /// after END) rather than finding the stream cut short. The lexer reads a copy of the
    /// piece as its buffer ([`Lexer::resume_with`]).
    pub fn piece_of_text(
        input: &'a [u8],
        header: Header,
        (lines, last_line): (u64, String),
        frame: u64,
        polygons_in_frame: u64,
    ) -> Self {
        let nothing_more = BufReader::with_capacity(0, &input[input.len()..]);
        let lex = Lexer::resume_with(input.to_vec(), nothing_more, lines, last_line);
        Self::resumed(lex, header, (frame, polygons_in_frame), true)
    }
}

impl<R: Read> Read for BinaryInput<R> {
    /// For bincode's header decoder.
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.offset += n as u64;
        Ok(n)
    }
}

fn read_binary_header<R: Read>(input: &mut BinaryInput<R>) -> Result<Header, StreamError> {
    let mut magic = [0u8; 8];
    let bad = |offset, msg: &str| StreamError::Binary {
        offset,
        context: String::new(),
        msg: msg.to_string(),
    };
    if Read::read_exact(input, &mut magic).is_err() || magic != BINARY_MAGIC {
        return Err(bad(0, "not a polypipe stream (bad magic)"));
    }
    // The version first, alone, so that a stream of another version is named as such
    // whatever the rest of its header holds.
    let version: u32 = bincode_options()
        .deserialize_from(&mut *input)
        .map_err(|_| bad(8, "unreadable stream header"))?;
    if version != VERSION {
        return Err(bad(
            8,
            &format!("stream version {version} is not supported (this is version {VERSION})"),
        ));
    }
    let (space, attributes): (Space, crate::header::Attributes) = bincode_options()
        .deserialize_from(&mut *input)
        .map_err(|_| bad(12, "unreadable stream header"))?;
    let header = Header {
        version,
        space,
        attributes,
    };
    check_space(&header.space).map_err(|m| bad(8, &m))?;
    check_attributes(&header).map_err(|m| bad(8, &m))?;
    Ok(header)
}

fn read_text_header<R: BufRead>(lex: &mut Lexer<R>) -> Result<Header, StreamError> {
    let magic = lex.expect_word("the header `polypipe 1 SPACE`")?;
    if magic != TEXT_MAGIC {
        return Err(lex.error(format!(
            "not a polypipe stream: expected the header `polypipe 1 SPACE`, found `{}`",
            Shown(&magic.chars().take(20).collect::<String>())
        )));
    }
    let version = lex.integer("the stream version", u32::MAX as u64)? as u32;
    let version_at = lex.mark();
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
                *slot = lex.number_with(|| format!("the {name} value"))?;
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
                "unknown coordinate space `{}` (expected world, eye, screen or fragments)",
                Shown(other)
            )))
        }
    };
    let wanted = text_version(&space);
    if version != wanted {
        let why = if matches!(space, Space::Fragments { .. }) && version == 1 {
            " (version 1 fragments carry fixed-point depths; scan-convert again with this \
             build's scanconv)"
        } else {
            ""
        };
        return Err(lex.error_at(
            version_at,
            format!(
                "stream version {version} is not supported (this is version {wanted} for {} \
                 streams){why}",
                space.name()
            ),
        ));
    }
    check_space(&space).map_err(|m| lex.error_at(space_at, m))?;
    let attributes = read_text_attributes(lex, &space)?;
    Ok(Header {
        version: VERSION,
        space,
        attributes,
    })
}

/// The header's attribute words after the space's ([`crate::header::Attributes`]), in any
/// order: `depth reciprocal K1`, `depth projective K1 K2` or `depth eye-z`, for screen and
/// fragment streams; `vertex-colours` and `opacity` for polygon streams. All on the
/// header's own line (so that the header is read without reading into the records:
/// `stagecli::pieces` cuts the rest of a text stream).
fn read_text_attributes<R: BufRead>(
    lex: &mut Lexer<R>,
    space: &Space,
) -> Result<crate::header::Attributes, StreamError> {
    use crate::header::DepthForm;
    let mut attributes = crate::header::Attributes::default();
    // The lighting words, and where the first of them was (they need `vertex-normals`).
    let mut lights = Vec::new();
    let mut lighting_at = None;
    while lex.more_on_line() {
        let flag = match lex.peek()? {
            Some("depth") => None,
            Some("vertex-colours") => Some(&mut attributes.vertex_colours),
            Some("vertex-normals") => Some(&mut attributes.vertex_normals),
            Some("opacity") => Some(&mut attributes.opacity),
            Some("ambient" | "light" | "specular" | "viewer") => {
                let word = lex.next_word()?.unwrap_or_default();
                lighting_at.get_or_insert(lex.mark());
                read_lighting_word(lex, &word, &mut attributes.lighting, &mut lights)?;
                continue;
            }
            _ => break,
        };
        let word = lex.next_word()?.unwrap_or_default();
        let at = lex.mark();
        if let Some(flag) = flag {
            // Vertex normals are also said by a fragment stream (its `shade` records
            // are then a normal's planes); the other flags only by polygon streams.
            let fragments_too = word == "vertex-normals" && space.screen_size().is_some();
            if space.vertex_arity() == 0 && !fragments_too {
                return Err(lex.error_at(
                    at,
                    format!(
                        "`{word}` in the header is for polygon streams (world, eye, screen), \
                         not {}-space",
                        space.name()
                    ),
                ));
            }
            if *flag {
                return Err(lex.error_at(at, format!("the header says `{word}` twice")));
            }
            *flag = true;
            continue;
        }
        if space.screen_size().is_none() {
            return Err(lex.error_at(
                at,
                format!(
                    "`depth` in the header is for screen and fragment streams, not {}-space",
                    space.name()
                ),
            ));
        }
        if attributes.depth.is_some() {
            return Err(lex.error_at(at, "the header names the depth form twice".to_string()));
        }
        let form = lex.expect_word("a depth form (reciprocal K1, projective K1 K2, eye-z)")?;
        let form_at = lex.mark();
        let mut positive = |what: &str| -> Result<f64, StreamError> {
            let v = lex.number_with(|| format!("the depth form's {what}"))?;
            if v.is_finite() && v > 0.0 {
                Ok(v)
            } else {
                Err(lex.error(format!(
                    "the depth form's {what} {} must be positive",
                    Number(v)
                )))
            }
        };
        let depth = match form.as_str() {
            "reciprocal" => DepthForm::Reciprocal {
                hither: positive("hither")?,
            },
            "projective" => {
                let hither = positive("hither")?;
                let yon = positive("yon")?;
                if hither >= yon {
                    return Err(lex.error(format!(
                        "the depth form's hither {} and yon {} must satisfy hither < yon",
                        Number(hither),
                        Number(yon)
                    )));
                }
                DepthForm::Projective { hither, yon }
            }
            "eye-z" => DepthForm::EyeZ,
            other => {
                return Err(lex.error_at(
                    form_at,
                    format!(
                        "unknown depth form `{}` (expected reciprocal, projective or eye-z)",
                        Shown(other)
                    ),
                ))
            }
        };
        attributes.depth = Some(depth);
    }
    if let Some(at) = lighting_at {
        if !attributes.vertex_normals {
            return Err(lex.error_at(
                at,
                "lighting words (ambient, light, specular, viewer) in a header without \
                 `vertex-normals`: they light the normals of a Phong-shaded stream"
                    .to_string(),
            ));
        }
    }
    if attributes.vertex_normals && attributes.vertex_colours {
        return Err(lex.error(
            "the header says both `vertex-colours` and `vertex-normals`: a vertex carries \
             a colour (Gouraud) or a normal (Phong), not both"
                .to_string(),
        ));
    }
    if !lights.is_empty() {
        attributes
            .lighting
            .set_lights(&lights)
            .map_err(|m| lex.error(format!("the header's lights: {m}")))?;
    }
    Ok(attributes)
}

/// One lighting word of the header and its numbers ([`crate::shade::Lighting`]):
/// `ambient A`, `light X Y Z I` (repeatable, collected in `lights`), `specular KS N`,
/// `viewer X Y Z`.
fn read_lighting_word<R: BufRead>(
    lex: &mut Lexer<R>,
    word: &str,
    lighting: &mut crate::shade::Lighting,
    lights: &mut Vec<(glam::DVec3, f64)>,
) -> Result<(), StreamError> {
    let mut numbers = |names: &[&str]| -> Result<Vec<f64>, StreamError> {
        names
            .iter()
            .map(|name| lex.number_with(|| format!("the {word} word's {name}")))
            .collect()
    };
    let checked = match word {
        "ambient" => {
            let n = numbers(&["A"])?;
            lighting.set_ambient(n[0])
        }
        "light" => {
            let n = numbers(&["X", "Y", "Z", "intensity I"])?;
            if lights.len() == crate::shade::MAX_LIGHTS {
                Err(format!("more than {} lights", crate::shade::MAX_LIGHTS))
            } else {
                lights.push((glam::DVec3::new(n[0], n[1], n[2]), n[3]));
                Ok(())
            }
        }
        "specular" => {
            let n = numbers(&["coefficient KS", "exponent N"])?;
            lighting.set_specular(n[0], n[1])
        }
        _ => {
            let n = numbers(&["X", "Y", "Z"])?;
            lighting.set_viewer(glam::DVec3::new(n[0], n[1], n[2]))
        }
    };
    checked.map_err(|m| lex.error(format!("the header's `{word}`: {m}")))
}

/// The header's numbers must make sense before any stage computes with them.
fn check_space(space: &Space) -> Result<(), String> {
    match *space {
        Space::Eye(v) => {
            if !(v.aspect.is_finite() && v.aspect > 0.0) {
                return Err(format!(
                    "aspect ratio {} must be positive",
                    Number(v.aspect)
                ));
            }
            if !(v.hither.is_finite() && v.yon.is_finite() && 0.0 < v.hither && v.hither < v.yon) {
                return Err(format!(
                    "hither {} and yon {} must satisfy 0 < hither < yon",
                    Number(v.hither),
                    Number(v.yon)
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

/// A binary header's attributes must be what a text header could say.
fn check_attributes(header: &Header) -> Result<(), String> {
    use crate::header::DepthForm;
    let a = &header.attributes;
    if (a.vertex_colours || a.opacity) && header.space.vertex_arity() == 0 {
        return Err(format!(
            "vertex colours and opacity in the header are for polygon streams, not {}-space",
            header.space.name()
        ));
    }
    if a.vertex_normals && a.vertex_colours {
        return Err("the header has both vertex colours and vertex normals".to_string());
    }
    if a.vertex_normals {
        a.lighting
            .check()
            .map_err(|m| format!("the header's lighting: {m}"))?;
    } else if a.lighting != crate::shade::Lighting::default() {
        return Err("lighting in a header without vertex normals".to_string());
    }
    let Some(form) = header.attributes.depth else {
        return Ok(());
    };
    if header.space.screen_size().is_none() {
        return Err(format!(
            "a depth form in the header is for screen and fragment streams, not {}-space",
            header.space.name()
        ));
    }
    let positive = |v: f64| v.is_finite() && v > 0.0;
    match form {
        DepthForm::Reciprocal { hither } if !positive(hither) => {
            Err("the depth form's hither must be positive".to_string())
        }
        DepthForm::Projective { hither, yon }
            if !(positive(hither) && positive(yon) && hither < yon) =>
        {
            Err("the depth form's hither and yon must satisfy 0 < hither < yon".to_string())
        }
        _ => Ok(()),
    }
}

/// Writes a stream of records of kind `T` in either form, buffered.
pub struct Writer<T, W: Write> {
    out: BufWriter<W>,
    form: Form,
    header: Header,
    polygons_in_frame: u64,
    _kind: std::marker::PhantomData<T>,
}

impl<T: Record> Writer<T, Vec<u8>> {
    /// A binary writer that goes on with a stream whose header is written elsewhere: for
    /// a piece of the stream encoded apart, in memory, to be put in its place by the
    /// stream's own writer with [`Writer::write_encoded`]. The records go straight into
    /// `out` (a buffer before a buffer would copy every byte once more).
    pub fn continuing_binary(out: Vec<u8>, header: Header) -> Self {
        Writer {
            out: BufWriter::with_capacity(0, out),
            form: Form::Binary,
            header,
            polygons_in_frame: 0,
            _kind: std::marker::PhantomData,
        }
    }
}

impl<T: Record, W: Write> Writer<T, W> {
    /// Writes the header: the binary form's magic and bincode header (version
    /// [`VERSION`], whatever `header.version` says), or the text form's
    /// `polypipe N SPACE` ([`text_version`]).
    pub fn new(out: W, header: Header, form: Form) -> io::Result<Self> {
        let mut out = BufWriter::with_capacity(IO_BUFFER, out);
        match form {
            Form::Binary => {
                out.write_all(&BINARY_MAGIC)?;
                let header = Header {
                    version: VERSION,
                    ..header
                };
                bincode_options()
                    .serialize_into(&mut out, &header)
                    .map_err(into_io)?;
            }
            Form::Text => writeln!(
                out,
                "{TEXT_MAGIC} {} {}{}",
                text_version(&header.space),
                header.space,
                header.attributes
            )?,
        }
        Ok(Writer {
            out,
            form,
            header,
            polygons_in_frame: 0,
            _kind: std::marker::PhantomData,
        })
    }

    /// Writes records encoded by a [`Writer::continuing_binary`] (a binary stream only),
    /// flushing when they end a frame, as `write` does at a frame's end.
    pub fn write_encoded(&mut self, bytes: &[u8], ends_a_frame: bool) -> io::Result<()> {
        debug_assert!(self.form == Form::Binary);
        self.out.write_all(bytes)?;
        if ends_a_frame {
            self.polygons_in_frame = 0;
            self.out.flush()?;
        }
        Ok(())
    }

    /// Writes one record.
    #[inline]
    pub fn write(&mut self, record: &T) -> io::Result<()> {
        match self.form {
            Form::Binary => record.write_binary(&mut self.out)?,
            Form::Text => {
                record.write_text(&mut self.out, &self.header, self.polygons_in_frame == 0)?
            }
        }
        self.count(record.control())
    }

    /// Keeps the polygon count (for NEXT.POLYGON in text) and flushes at frame ends.
    #[inline]
    fn count(&mut self, control: Control) -> io::Result<()> {
        match control {
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

    /// The underlying writer (what has been flushed to it, that is).
    pub fn get_ref(&self) -> &W {
        self.out.get_ref()
    }

    /// Flushes and hands back the underlying writer.
    pub fn into_inner(self) -> io::Result<W> {
        self.out.into_inner().map_err(|e| e.into_error())
    }
}

impl<W: Write> Writer<crate::Token, W> {
    /// Writes a polygon record without wrapping it in a [`Token`](crate::Token): the
    /// same bytes as `write(&Token::Polygon(p))`, for a stage that keeps its pieces as
    /// polygons (the splitter).
    #[inline]
    pub fn write_polygon(&mut self, p: &crate::Polygon) -> io::Result<()> {
        match self.form {
            Form::Binary => polygons::write_polygon_binary(p, &mut self.out)?,
            Form::Text => polygons::write_polygon_text(
                p,
                &mut self.out,
                &self.header,
                self.polygons_in_frame == 0,
            )?,
        }
        self.count(Control::Polygon)
    }
}

#[allow(clippy::boxed_local)] // bincode::Error is a Box; this takes what bincode returns
fn into_io(e: bincode::Error) -> io::Error {
    match *e {
        bincode::ErrorKind::Io(io) => io,
        other => io::Error::other(other.to_string()),
    }
}
