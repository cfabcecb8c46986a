//! A text stream read in pieces on several threads (the text parser had set the
//! pace of a 100,000-polygon render, one core parsing while the other waited).
//!
//! After its header a text stream is cut into pieces of about [`PIECE_BYTES`], each just
//! before a line that begins with `NEXT.POLYGON`: there, and only there, a reader of the
//! whole stream is between two polygons of a frame, so a piece can be read from its first
//! line by a reader of its own ([`Reader::piece_of_text`]) knowing only the line number it
//! starts at. Worker threads read, transform and encode pieces; this thread reads the
//! input, cuts it, and writes the encoded pieces in their order.
//!
//! A piece is only a guess that the stream is well formed there. Whatever goes wrong in a
//! piece (a syntax error, a polygon the transformation refuses, a NEXT.POLYGON that
//! follows NEXT.FRAME, data after END), nothing of that piece is written: the stream is
//! read on from the piece's first line by one reader resumed in the exact state the
//! pieces before left ([`Reader::resume_text`]), which writes what the one-reader loop
//! would have written and stops with the message it would have given. The output, and
//! every message, are the same as the one-reader loop's, byte for byte.

use crate::memory::Spare;
use crate::stream::{filter_records, input_error, Counts};
use crate::Result;
use proto::codec::{TextRest, Writer};
use proto::{Header, Polygon, Reader, StreamError, Token};
use std::collections::VecDeque;
use std::io::{self, Read, Write};
use std::sync::mpsc::{channel, sync_channel, Receiver, SyncSender};
use std::sync::{Arc, Mutex};

/// The size a piece is cut at (it ends at the last NEXT.POLYGON line before this): about
/// 1,000 quads of the environment scene's text, a quarter of a millisecond's parsing.
pub const PIECE_BYTES: usize = 256 << 10;

/// The longest stretch searched for a NEXT.POLYGON line, in pieces' sizes, before the rest
/// of the stream is read by one reader (a scene of one polygon per frame has none).
const MOST_PIECES: usize = 32;

/// The worker threads for a stream in pieces: one a core, at most four; `None` on one
/// core, where pieces would only add work.
pub fn piece_workers() -> Option<usize> {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    (cores > 1).then(|| cores.min(4))
}

/// Where the stream stands between two pieces: lines read and the last of them (as the
/// lexer keeps it, for a message about a stream that stops there), frame, and polygons
/// of the frame so far.
#[derive(Clone, Debug)]
struct Place {
    lines: u64,
    last_line: String,
    frame: u64,
    polygons: u64,
}

/// The last line of a piece (which ends with a newline, and was read whole, so is
/// UTF-8) as the lexer keeps a line.
fn last_line(piece: &[u8]) -> String {
    let body = piece.strip_suffix(b"\n").unwrap_or(piece);
    let raw = &body[memchr::memrchr(b'\n', body).map_or(0, |i| i + 1)..];
    proto::text::kept_line(raw, false).map_or_else(|_| String::new(), |(line, _)| line.to_string())
}

/// A piece cut from the input, and where its answer will come.
struct InFlight {
    bytes: Arc<Vec<u8>>,
    /// Lines read at its end.
    lines_after: u64,
    /// The piece right after the header (the others start at NEXT.POLYGON).
    first: bool,
    answer: Receiver<Answer>,
}

/// A piece read: its records encoded, and what they were; `None` if anything in it went
/// wrong (the one reader then says what).
type Answer = Option<(Vec<u8>, Counts)>;

/// A piece for a worker: its bytes, the lines before it, whether it is the first, and
/// where to answer.
type Job = (Arc<Vec<u8>>, u64, bool, SyncSender<Answer>);

/// Where `bytes` may be cut: just before the last line that begins with `NEXT.POLYGON`
/// (followed by whitespace or a comment) in its first `limit` bytes, and ends, as UTF-8,
/// within `bytes`; `None` if there is none, or only at its start. The one reader takes in
/// the line after a polygon's last vertex before the polygon is done: a line it could not
/// take in (not UTF-8) would stop it before that polygon, so a piece must not end there.
fn cut_at(bytes: &[u8], limit: usize) -> Option<usize> {
    const WORD: &[u8] = b"\nNEXT.POLYGON";
    let mut hay = &bytes[..limit.min(bytes.len())];
    while let Some(i) = memchr::memmem::rfind(hay, WORD) {
        let line = &bytes[i + 1..];
        let after = line.get(WORD.len() - 1).copied();
        let ends_well = || {
            memchr::memchr(b'\n', line).is_some_and(|end| std::str::from_utf8(&line[..end]).is_ok())
        };
        if matches!(
            after,
            Some(b' ' | b'\t' | b'\n' | b'\r' | 0x0b | 0x0c | b'#')
        ) && ends_well()
        {
            return Some(i + 1);
        }
        hay = &hay[..i];
    }
    None
}

/// The input after the header, and what its reads have said.
struct Input<R, P> {
    read: R,
    /// Whether more input can be read at once, without waiting (`poll`).
    ready: P,
    /// The input has ended.
    ended: bool,
    /// The input comes slower than it is read (nothing there to read at once): a live
    /// stream, or a slow writer. Pieces would only hold its polygons back, so the one
    /// reader takes it from here, record by record as it comes.
    dry: bool,
}

impl<R: Read, P: Fn() -> bool> Input<R, P> {
    /// Reads into `pending` until it holds `want` bytes, the input ends, or it runs dry.
    fn fill(&mut self, pending: &mut Vec<u8>, want: usize) -> Result<()> {
        while pending.len() < want && !self.ended && !self.dry {
            if !(self.ready)() {
                self.dry = true;
                break;
            }
            let have = pending.len();
            pending.resize(want, 0);
            let n = loop {
                match self.read.read(&mut pending[have..]) {
                    Ok(n) => break n,
                    Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                    Err(e) => {
                        pending.truncate(have);
                        return Err(input_error("stdin", StreamError::Io(e)));
                    }
                }
            };
            pending.truncate(have + n);
            self.ended = n == 0;
        }
        Ok(())
    }
}

/// [`crate::filter_polygons`]'s loop over a text stream after its header (`rest`), in
/// pieces of about `piece_bytes` ([`PIECE_BYTES`]) on `workers` threads; the same output
/// and messages as the one-reader loop.
#[allow(clippy::too_many_arguments)]
pub fn filter_text_in_pieces<R, W, F>(
    rest: TextRest<R>,
    in_header: Header,
    out_header: Header,
    writer: &mut Writer<Token, W>,
    transform: F,
    doing: &str,
    (workers, piece_bytes): (usize, usize),
    ready: impl Fn() -> bool,
) -> Result<()>
where
    R: Read,
    W: Write,
    F: FnMut(&mut Polygon) -> std::result::Result<(), String> + Clone + Send,
{
    let most_bytes = piece_bytes.saturating_mul(MOST_PIECES);
    let TextRest {
        unread,
        input,
        lines,
        last_line: header_line,
    } = rest;
    let mut pending = unread;
    let mut input = Input {
        read: input,
        ready,
        ended: false,
        dry: false,
    };
    let mut at = Place {
        lines,
        last_line: header_line,
        frame: 0,
        polygons: 0,
    };
    // A short stream, or a live one, is read here by one reader, without threads.
    input.fill(&mut pending, piece_bytes)?;
    if input.ended || input.dry {
        let rest = vec![pending];
        return one_reader(rest, input.read, in_header, at, writer, transform, doing);
    }
    keep_freed_memory();
    let (jobs, queue) = channel::<Job>();
    let queue = Mutex::new(queue);
    // Buffers go round (pieces' bytes, and their encoded records): a new one for each
    // piece would be fresh memory from the kernel each time, a fifth of the stage's time.
    let spare = Spare::<u8>::default();
    std::thread::scope(|scope| -> Result<()> {
        for _ in 0..workers {
            let (queue, spare, mut transform) = (&queue, &spare, transform.clone());
            scope.spawn(move || loop {
                let job = match queue.lock() {
                    Ok(q) => q.recv(),
                    Err(_) => return,
                };
                let Ok((bytes, lines_before, first, answer)) = job else {
                    return; // no more pieces
                };
                let piece = read_piece(
                    &bytes,
                    (lines_before, first),
                    (in_header, out_header),
                    spare.take(),
                    &mut transform,
                    doing,
                );
                // The piece's bytes let go before the answer goes: the writer then holds
                // them alone and puts them back in `spare`. Dropped after, they raced the
                // writer's `Arc::try_unwrap`, which lost most of the time, and each piece
                // was read into fresh memory: 2,000 page faults on the 100,000-quad scene.
                drop(bytes);
                let _ = answer.send(piece);
            });
        }
        let mut in_flight: VecDeque<InFlight> = VecDeque::new();
        let mut lines_next = at.lines;
        let mut first = true;
        // Where one reader takes over, if it must: the pieces not written, and the place
        // before them. `None`: the stream ended well in a piece.
        let one_reader_from: Option<(Vec<Vec<u8>>, Place)> = loop {
            // Cut pieces while the workers could use more and there is input, coming fast.
            while in_flight.len() < 2 * workers
                && !input.dry
                && !(input.ended && pending.is_empty())
            {
                let mut cut = if input.ended {
                    Some(pending.len())
                } else {
                    cut_at(&pending, piece_bytes)
                };
                while cut.is_none() && !input.ended && !input.dry && pending.len() < most_bytes {
                    let want = (pending.len() * 2).clamp(piece_bytes, most_bytes);
                    input.fill(&mut pending, want)?;
                    cut = if input.ended {
                        Some(pending.len())
                    } else {
                        cut_at(&pending, want)
                    };
                }
                let Some(cut) = cut.filter(|_| !input.dry) else {
                    break; // no NEXT.POLYGON line in most_bytes, or a live stream
                };
                let mut rest = spare.take();
                rest.extend_from_slice(&pending[cut..]);
                pending.truncate(cut);
                let bytes = Arc::new(std::mem::replace(&mut pending, rest));
                let (answer_to, answer) = sync_channel(1);
                let lines_before = lines_next;
                lines_next += memchr::memchr_iter(b'\n', &bytes).count() as u64;
                let lines_after = lines_next;
                if jobs
                    .send((Arc::clone(&bytes), lines_before, first, answer_to))
                    .is_err()
                {
                    break;
                }
                in_flight.push_back(InFlight {
                    bytes,
                    lines_after,
                    first,
                    answer,
                });
                first = false;
                input.fill(&mut pending, piece_bytes)?;
            }
            let Some(piece) = in_flight.pop_front() else {
                // Nothing to cut at, or a live stream: one reader for the rest.
                break Some((Vec::new(), at));
            };
            let last = in_flight.is_empty() && input.ended && pending.is_empty();
            let answer = piece.answer.recv().ok().flatten();
            let fits = match &answer {
                // A piece after the first starts at NEXT.POLYGON: the frame must have a
                // polygon already. END must end the last piece, and only it.
                Some((_, counts)) => (piece.first || at.polygons > 0) && counts.ended == last,
                None => false,
            };
            let Some((encoded, counts)) = answer.filter(|_| fits) else {
                let mut rest = vec![Arc::unwrap_or_clone(piece.bytes)];
                rest.extend(in_flight.drain(..).map(|p| Arc::unwrap_or_clone(p.bytes)));
                break Some((rest, at));
            };
            writer.write_encoded(&encoded, counts.frames > 0 || counts.ended)?;
            spare.give(encoded);
            at.lines = piece.lines_after;
            at.last_line = last_line(&piece.bytes);
            if let Ok(bytes) = Arc::try_unwrap(piece.bytes) {
                spare.give(bytes);
            }
            if counts.frames > 0 {
                at.frame += counts.frames;
                at.polygons = counts.polygons;
            } else {
                at.polygons += counts.polygons;
            }
            if counts.ended {
                break None;
            }
        };
        drop(jobs);
        match one_reader_from {
            None => Ok(()),
            Some((mut rest, place)) => {
                rest.push(std::mem::take(&mut pending));
                one_reader(rest, input.read, in_header, place, writer, transform, doing)
            }
        }
    })
}

/// Has the allocator keep the memory the pieces free for the next ones. The pieces'
/// buffers (a quarter of a megabyte to a few) go between threads; glibc gave each worker
/// an arena of its own, and handed freed memory at an arena's top back to the kernel
/// (`madvise`, a hundred times on the 100,000-quad scene), so the next buffer there was
/// fresh pages again, each a fault and a page zeroed: 1,100 to 2,600 faults where one
/// reader has 225. One arena, no trimming, and buffers up to 32 MiB (glibc's most) from
/// the heap rather than mapped and unmapped each time bring that to some 700. Set before
/// the workers start, which is when glibc would make their arenas.
fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only changes the allocator's parameters; called from the one
    // thread there is, before any other starts.
    unsafe {
        libc::mallopt(libc::M_ARENA_MAX, 1);
        libc::mallopt(libc::M_TRIM_THRESHOLD, 256 << 20);
        libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20);
    }
}

/// Reads, transforms and encodes one piece (after `lines_before` lines; `first`: the
/// one right after the header) into `out`; `None` if anything in it went wrong.
fn read_piece<F>(
    bytes: &[u8],
    (lines_before, first): (u64, bool),
    (in_header, out_header): (Header, Header),
    out: Vec<u8>,
    transform: &mut F,
    doing: &str,
) -> Answer
where
    F: FnMut(&mut Polygon) -> std::result::Result<(), String>,
{
    // A piece after the first starts at NEXT.POLYGON, after some polygon of a frame
    // (which one does not matter: a message would come from the one reader).
    let before = if first { 0 } else { 1 };
    let lines = (lines_before, String::new());
    let mut reader = Reader::<Token, _>::piece_of_text(bytes, in_header, lines, 0, before);
    let mut writer = Writer::continuing_binary(out, out_header);
    let counts = filter_records(&mut reader, &mut writer, transform, doing).ok()?;
    Some((writer.into_inner().ok()?, counts))
}

/// The one-reader loop from `place` on: `rest` (bytes already read, in order), then the
/// input. What it writes and says is what a reader of the whole stream would.
fn one_reader<R, W, F>(
    rest: Vec<Vec<u8>>,
    input: R,
    in_header: Header,
    place: Place,
    writer: &mut Writer<Token, W>,
    mut transform: F,
    doing: &str,
) -> Result<()>
where
    R: Read,
    W: Write,
    F: FnMut(&mut Polygon) -> std::result::Result<(), String>,
{
    let read = io::Cursor::new(rest.concat()).chain(input);
    let start = (place.lines, place.last_line);
    let mut reader =
        Reader::<Token, _>::resume_text(read, in_header, start, place.frame, place.polygons);
    filter_records(&mut reader, writer, &mut transform, doing)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stream::filter_records;
    use proto::{Form, Space};

    /// A transformation that refuses a polygon with a vertex beyond x = 90, as a stage
    /// refuses one it cannot process, and moves the rest.
    fn shift(p: &mut Polygon) -> std::result::Result<(), String> {
        if p.vertices.iter().any(|v| v.x > 90.0) {
            return Err("a vertex beyond x = 90".into());
        }
        for v in &mut p.vertices {
            v.x += 1.0;
        }
        Ok(())
    }

    /// Output bytes and the message, if any, of the one-reader loop over `text`.
    fn one(text: &[u8]) -> (Vec<u8>, Option<String>) {
        let header = Header::new(Space::World);
        let mut out = Writer::new(Vec::new(), header, Form::Binary).unwrap();
        let result = Reader::<Token, _>::new(text)
            .map_err(|e| input_error("stdin", e))
            .and_then(|mut r| filter_records(&mut r, &mut out, &mut shift, "shifting"));
        out.flush().unwrap();
        (
            out.into_inner().unwrap(),
            result.err().map(|e| e.to_string()),
        )
    }

    /// The same, in pieces of about `size` bytes on `workers` threads.
    fn in_pieces(text: &[u8], size: usize, workers: usize) -> (Vec<u8>, Option<String>) {
        in_pieces_from(text, size, workers, usize::MAX)
    }

    /// [`in_pieces`] from `input`, which runs dry (more input not there at once) after
    /// `ready` looks.
    fn in_pieces_from(
        input: impl Read,
        size: usize,
        workers: usize,
        ready: usize,
    ) -> (Vec<u8>, Option<String>) {
        let header = Header::new(Space::World);
        let mut out = Writer::new(Vec::new(), header, Form::Binary).unwrap();
        let reader = Reader::<Token, _>::new(input).unwrap();
        let rest = reader.into_text_rest().ok().expect("a text header line");
        let looks = std::cell::Cell::new(0);
        let ready = || {
            looks.set(looks.get() + 1);
            looks.get() <= ready
        };
        let result = filter_text_in_pieces(
            rest,
            header,
            header,
            &mut out,
            shift,
            "shifting",
            (workers, size),
            ready,
        );
        out.flush().unwrap();
        (
            out.into_inner().unwrap(),
            result.err().map(|e| e.to_string()),
        )
    }

    /// Hands `text` out `chunk` bytes a read, as a pipe fed by a slower writer does.
    struct Chunks<'a>(&'a [u8], usize);

    impl Read for Chunks<'_> {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            let n = self.1.min(buf.len()).min(self.0.len());
            buf[..n].copy_from_slice(&self.0[..n]);
            self.0 = &self.0[n..];
            Ok(n)
        }
    }

    /// A small pseudo-random generator (xorshift), so that the cases are the same each run.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self, n: u64) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0 % n
        }
    }

    /// A text stream of `frames` frames of quads, some skips and comments, with odd
    /// spacing; `END` at the end.
    fn scene(rng: &mut Rng, frames: u64) -> String {
        let mut s = String::from("polypipe 1 world\n");
        for f in 0..frames {
            if f > 0 {
                s += "NEXT.FRAME\n";
            }
            for p in 0..1 + rng.next(12) {
                if p > 0 {
                    s += if rng.next(5) == 0 {
                        "NEXT.POLYGON # next\n"
                    } else {
                        "NEXT.POLYGON\n"
                    };
                }
                if rng.next(9) == 0 {
                    s += &format!("skip {}\n", 1 + rng.next(3));
                    continue;
                }
                s += &format!(
                    "colour {} {} {}\n",
                    rng.next(256),
                    rng.next(256),
                    rng.next(256)
                );
                for _ in 0..3 + rng.next(3) {
                    let sep = ["  ", " ", "\t"][rng.next(3) as usize];
                    s += &format!(
                        "{}.{}{sep}{} {}.5\n",
                        rng.next(100),
                        rng.next(1000),
                        rng.next(50) as i64 - 25,
                        rng.next(9)
                    );
                }
            }
        }
        s + "END\n"
    }

    /// What may go wrong in a stream, put at a random line.
    const FAULTS: [&str; 10] = [
        "1 2 x\n",
        "NEXT.FRAME\nNEXT.POLYGON\n",
        "END\n",
        "colour 1 2\n",
        "95 0 0\n",
        "NEXT.POLYGON\nNEXT.POLYGON\n",
        "skip 0\n",
        "1e999 0 0\n",
        "é\n",
        "\n# only a comment\n\n",
    ];

    #[test]
    fn pieces_read_as_one_reader_does_good_streams_and_bad() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let mut faults_seen = 0;
        for case in 0..300 {
            let frames = 1 + rng.next(4);
            let mut text = scene(&mut rng, frames);
            match case % 4 {
                0 => {} // well formed
                1 => {
                    // A fault at a line start.
                    let starts: Vec<usize> = std::iter::once(0)
                        .chain(text.match_indices('\n').map(|(i, _)| i + 1))
                        .filter(|&i| i > 17 && i < text.len())
                        .collect();
                    let at = starts[rng.next(starts.len() as u64) as usize];
                    text.insert_str(at, FAULTS[rng.next(FAULTS.len() as u64) as usize]);
                }
                2 => {
                    // Cut short, anywhere after the header.
                    let at = 17 + rng.next((text.len() - 17) as u64) as usize;
                    text.truncate(at);
                }
                _ => text += "NEXT.POLYGON\ncolour 1 2 3\n", // data after END
            }
            let want = one(text.as_bytes());
            faults_seen += want.1.is_some() as u32;
            for (size, workers) in [(30, 1), (64, 2), (200, 3), (1 << 12, 2)] {
                let got = in_pieces(text.as_bytes(), size, workers);
                assert_eq!(got.1, want.1, "case {case}, pieces of {size}:\n{text}");
                assert!(
                    got.0 == want.0,
                    "case {case}, pieces of {size}: output differs\n{text}"
                );
            }
        }
        // The cases did go wrong, in most of the ways there are.
        assert!(faults_seen > 150, "{faults_seen}");
    }

    /// A stream that comes slower than it is read (a live one) goes to the one reader,
    /// at once or after some pieces, and reads as the one reader reads it.
    #[test]
    fn a_stream_running_dry_goes_on_with_one_reader() {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        for case in 0..60 {
            let frames = 1 + rng.next(4);
            let mut text = scene(&mut rng, frames);
            match case % 3 {
                0 => {}
                1 => text.truncate(text.len() - 4), // no END: the message's column counts
                _ => {
                    // At the start of a line past the middle (and past the header).
                    let at = text[text.len() / 2..].find('\n').unwrap() + text.len() / 2 + 1;
                    text.insert_str(at, "1 2 x\n")
                }
            }
            let want = one(text.as_bytes());
            for ready in [0, 1, 2, 5] {
                for chunk in [7, 50] {
                    let got = in_pieces_from(Chunks(text.as_bytes(), chunk), 64, 2, ready);
                    assert_eq!(
                        got, want,
                        "case {case}, dry after {ready}, reads of {chunk}"
                    );
                }
            }
        }
    }

    /// Pieces, then a stretch with no place to cut and a fault in it: the one reader
    /// takes over at the right line.
    #[test]
    fn one_reader_after_pieces_counts_lines_from_the_pieces() {
        let mut text = String::from("polypipe 1 world\ncolour 1 2 3\n0 0 0\n");
        for _ in 0..40 {
            text += "NEXT.POLYGON\ncolour 4 5 6\n1 1 1\n2 2 2\n";
        }
        for f in 0..60 {
            text += "NEXT.FRAME\ncolour 1 2 3\n0 0 0\n1 0 0\n";
            if f == 50 {
                text += "0 x 0\n";
            }
        }
        text += "END\n";
        let want = one(text.as_bytes());
        assert!(
            want.1.as_deref().unwrap_or("").contains(", column 3: "),
            "{want:?}"
        );
        assert_eq!(in_pieces(text.as_bytes(), 40, 2), want);
        // And cut short after the pieces: the column past the last line's end.
        let short = &text[..text.find("NEXT.FRAME").unwrap()];
        let want = one(short.as_bytes());
        assert!(
            want.1.as_deref().unwrap_or("").contains("ends without END"),
            "{want:?}"
        );
        assert_eq!(in_pieces(short.as_bytes(), 40, 2), want);
        assert_eq!(
            in_pieces_from(Chunks(short.as_bytes(), 300), 40, 2, 3),
            want
        );
    }

    /// Found by the `pieces` fuzz target: a NEXT.POLYGON line that is not UTF-8 stops the
    /// one reader before the polygon above it is done, so no piece may end above it.
    #[test]
    fn no_piece_ends_above_a_line_the_lexer_refuses() {
        let body = b"colour\x0b\n\x0b20\x0b2\x0b\x0b2\x0b20\x0b2\x0b12\x0b\x0b#{kiq\nNEXT.POLYGON\r\x01\0\0 \r\r\r\r\0\0\xefc\0\0\x0020\x0b2\xbfgN\xbbcdEND\n\xef\xbb\xbf\x93\x93\r\r\xfd";
        let mut text = b"polypipe 1 world\n".to_vec();
        text.extend_from_slice(body);
        let want = one(&text);
        assert!(
            want.1.as_deref().unwrap_or("").contains("not UTF-8"),
            "{want:?}"
        );
        assert_eq!(in_pieces_from(Chunks(&text, 48), 16, 1, 13), want);
        assert_eq!(in_pieces(&text, 16, 2), want);
    }

    #[test]
    fn last_lines_are_kept_as_the_lexer_keeps_them() {
        assert_eq!(last_line(b"a\nb c\n"), "b c");
        assert_eq!(last_line(b"b c # note\r\n"), "b c ");
        assert_eq!(last_line(b"x\n\r\r\n"), "");
    }

    #[test]
    fn a_stream_without_a_place_to_cut_is_read_by_one_reader() {
        // One polygon a frame: no NEXT.POLYGON line anywhere.
        let mut text = String::from("polypipe 1 world\n");
        for f in 0..400 {
            if f > 0 {
                text += "NEXT.FRAME\n";
            }
            text += "colour 1 2 3\n0 0 0\n1 0 0\n0 1 0\n";
        }
        text += "END\n";
        let want = one(text.as_bytes());
        assert_eq!(want.1, None);
        assert_eq!(in_pieces(text.as_bytes(), 40, 2), want);
    }

    #[test]
    fn cuts_fall_before_a_next_polygon_line_only() {
        let text =
            b"colour 1 2 3\n0 0 0\nNEXT.POLYGONS\n# NEXT.POLYGON\nNEXT.POLYGON\t# x\n1 1 1\n";
        let line = text
            .windows(14)
            .position(|w| w == b"NEXT.POLYGON\t#")
            .unwrap();
        assert_eq!(cut_at(text, text.len()), Some(line));
        assert_eq!(cut_at(text, line - 1), None);
        assert_eq!(cut_at(b"NEXT.POLYGON\n1 2 3\n", 100), None);
        assert_eq!(cut_at(b"1 2 3\nNEXT.POLYGON\n", 100), Some(6));
        // Not where the line has not ended yet, nor where it is not UTF-8.
        assert_eq!(cut_at(b"1 2 3\nNEXT.POLYGON", 100), None);
        assert_eq!(
            cut_at(b"1\nNEXT.POLYGON\n2\nNEXT.POLYGON \xff\n", 100),
            Some(2)
        );
    }
}
