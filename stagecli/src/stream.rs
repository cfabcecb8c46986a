//! Opening a stage's inputs and outputs, the checks on a polygon read or about to be
//! written, and the one-reader loop of the one-in, one-out geometry stages
//! ([`filter_records`]; [`crate::filter`] chooses between it and the reader in pieces).

use crate::{Context, Error, Kind, Result};
use proto::{Form, Header, Polygon, Reader, Record, SpaceKind, StreamError, Token, Writer};
use std::fs::File;
use std::io::{self, Read, Write};

/// How an input named on the command line is called in messages: `stdin` for `-`.
pub fn input_name(path: &str) -> &str {
    if path == "-" {
        "stdin"
    } else {
        path
    }
}

/// Opens an input named on the command line; `-` is standard input. A file that cannot
/// be opened is an I/O error naming it.
pub fn open_input(path: &str) -> Result<Box<dyn Read + Send>> {
    open(path).with_context(|| format!("cannot open {path}"))
}

/// [`open_input`] for a caller that names its inputs in every message of its own (zbuf
/// with many inputs): the error is the operating system's alone.
pub fn open(path: &str) -> io::Result<Box<dyn Read + Send>> {
    if path == "-" {
        Ok(Box::new(io::stdin()))
    } else {
        let f = File::open(path)?;
        widen(&f);
        Ok(Box::new(f))
    }
}

/// Opens an output named on the command line; `-` is standard output. A named pipe's
/// open waits for its reader, as an occam channel waits for its partner.
pub fn open_output(path: &str) -> Result<Box<dyn Write + Send>> {
    if path == "-" {
        Ok(Box::new(io::stdout()))
    } else {
        let f = File::create(path).with_context(|| format!("cannot open {path} for writing"))?;
        widen(&f);
        Ok(Box::new(f))
    }
}

/// An error reading input `name`: an I/O failure is prefixed with the input's name
/// (`stdin: Is a directory`); a fault in the stream already says where it is.
pub fn input_error(name: &str, e: StreamError) -> Error {
    let e = Error::from(e);
    match e.kind() {
        Kind::Io => e.context(name),
        _ => e,
    }
}

/// A stream reader on standard input; the header is read and checked to be in space
/// `expect`.
pub fn read_stdin<T: Record>(expect: SpaceKind) -> Result<Reader<T, io::StdinLock<'static>>> {
    let reader = Reader::new(io::stdin().lock()).map_err(|e| input_error("stdin", e))?;
    reader.header().expect(expect)?;
    Ok(reader)
}

/// The next record of `reader` (reading standard input), errors as [`input_error`].
pub fn next<T: Record, R: Read>(reader: &mut Reader<T, R>) -> Result<Option<T>> {
    reader.next_record().map_err(|e| input_error("stdin", e))
}

/// An output that names itself in its errors: a failed write says `stdout: No space
/// left on device`, keeping the error's kind (a broken pipe stays a broken pipe, so the
/// reader going away is still told apart).
pub struct Named<W> {
    inner: W,
    name: String,
    /// Bytes written so far (the load on the link this output is: `--stats`).
    bytes: u64,
}

impl<W: Write> Named<W> {
    pub fn new(inner: W, name: impl Into<String>) -> Self {
        Named {
            inner,
            name: name.into(),
            bytes: 0,
        }
    }

    /// Bytes written so far.
    pub fn bytes(&self) -> u64 {
        self.bytes
    }

    fn label(&self, e: io::Error) -> io::Error {
        let message = format!("{}: {}", self.name, crate::error::io_message(&e));
        io::Error::new(e.kind(), message)
    }
}

impl<W: Write> Write for Named<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(buf).map_err(|e| self.label(e))?;
        self.bytes += n as u64;
        Ok(n)
    }

    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        self.inner.write_all(buf).map_err(|e| self.label(e))?;
        self.bytes += buf.len() as u64;
        Ok(())
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush().map_err(|e| self.label(e))
    }
}

/// A reader that counts the bytes read through it into a counter it shares: the load on
/// an input's link (zbuf's `--stats`), or how far into a scene a look has read (chart).
pub struct Counted<R> {
    pub inner: R,
    pub bytes: std::sync::Arc<std::sync::atomic::AtomicU64>,
}

impl<R: Read> Read for Counted<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.bytes
            .fetch_add(n as u64, std::sync::atomic::Ordering::Relaxed);
        Ok(n)
    }
}

/// Standard output, named `stdout` in its errors, unbuffered: every writer of a stage's
/// stdout buffers for itself (the stream [`Writer`], zbuf's frames) or writes a line or two.
pub fn stdout() -> Named<RawStdout> {
    Named::new(RawStdout, "stdout")
}

/// File descriptor 1, written with `write(2)`. std's `Stdout` is a `LineWriter`, which
/// searches every write for its last newline: over binary records and PPM frames that
/// search was a tenth of zbuf's CPU placing a full-HD frame's runs.
#[derive(Debug)]
pub struct RawStdout;

impl Write for RawStdout {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        // SAFETY: write(2) reads `buf.len()` bytes from a live slice; on a descriptor that
        // is closed or not writable it fails with an errno, returned as the error.
        let n = unsafe { libc::write(1, buf.as_ptr().cast(), buf.len()) };
        if n < 0 {
            Err(io::Error::last_os_error())
        } else {
            Ok(n as usize)
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

/// A stream writer on standard output.
pub fn write_stdout<T: Record>(header: Header, form: Form) -> Result<Writer<T, Named<RawStdout>>> {
    Ok(Writer::new(stdout(), header, form)?)
}

/// Whether two outputs named on the command line are one file, so that writing both
/// would interleave two streams in it: the same name, or (for files that exist) the same
/// file by device and inode, or (for files to be made) the same folder and name. `-` is
/// standard output, wherever it leads. A character device (`/dev/null`, a terminal) is
/// not a file that two streams could corrupt.
pub fn same_file(a: &str, b: &str) -> bool {
    use std::os::unix::fs::{FileTypeExt, MetadataExt};
    use std::path::{Path, PathBuf};
    let path = |p: &str| PathBuf::from(if p == "-" { "/dev/stdout" } else { p });
    let (pa, pb) = (path(a), path(b));
    match (std::fs::metadata(&pa), std::fs::metadata(&pb)) {
        (Ok(ma), Ok(mb)) => {
            (ma.dev(), ma.ino()) == (mb.dev(), mb.ino()) && !ma.file_type().is_char_device()
        }
        (Err(_), Err(_)) => {
            // Neither exists yet: compare where they would be made.
            let place = |p: &Path| {
                let dir = p.parent().filter(|d| !d.as_os_str().is_empty());
                let dir = dir.unwrap_or(Path::new(".")).canonicalize().ok()?;
                Some(dir.join(p.file_name()?))
            };
            a == b || place(&pa).is_some_and(|x| Some(x) == place(&pb))
        }
        _ => false,
    }
}

/// One of several outputs of a stage (the splitter's two): when its reader goes away,
/// this output closes quietly and the others go on, so that every other branch still
/// gets the whole stream and its END.
pub struct Branch<T: Record> {
    writer: Option<Writer<T, Named<Box<dyn Write + Send>>>>,
    /// The bytes written when the reader went away.
    gone_at: u64,
}

impl<T: Record> Branch<T> {
    /// Opens output `path` ([`open_output`]) and writes the header.
    pub fn open(path: &str, header: Header, form: Form) -> Result<Self> {
        let name = if path == "-" { "stdout" } else { path };
        let out = Named::new(open_output(path)?, name);
        Ok(Branch {
            writer: Self::kept(Writer::new(out, header, form))?,
            gone_at: 0,
        })
    }

    /// Bytes written to the output so far (those buffered included once flushed).
    pub fn bytes(&self) -> u64 {
        self.writer
            .as_ref()
            .map_or(self.gone_at, |w| w.get_ref().bytes())
    }

    /// Whether the output's reader is still there.
    pub fn is_open(&self) -> bool {
        self.writer.is_some()
    }

    /// Writes a record; nothing once the reader has gone.
    pub fn write(&mut self, record: &T) -> Result<()> {
        if let Some(w) = &mut self.writer {
            if Self::kept(w.write(record))?.is_none() {
                self.gone();
            }
        }
        Ok(())
    }

    /// Flushes what is buffered.
    pub fn flush(&mut self) -> Result<()> {
        if let Some(w) = &mut self.writer {
            if Self::kept(w.flush())?.is_none() {
                self.gone();
            }
        }
        Ok(())
    }

    /// The reader has gone: nothing more is written.
    fn gone(&mut self) {
        self.gone_at = self.bytes();
        self.writer = None;
    }

    /// `Some` for success, `None` when the reader has gone, the error (which names the
    /// output) for any other failure.
    fn kept<V>(result: io::Result<V>) -> Result<Option<V>> {
        match result.map_err(Error::from) {
            Ok(v) => Ok(Some(v)),
            Err(e) if e.kind() == Kind::ReaderGone => Ok(None),
            Err(e) => Err(e),
        }
    }
}

impl Branch<proto::Token> {
    /// Writes a polygon record without making a token of it; nothing once the reader has
    /// gone.
    pub fn write_polygon(&mut self, polygon: &Polygon) -> Result<()> {
        if let Some(w) = &mut self.writer {
            if Self::kept(w.write_polygon(polygon))?.is_none() {
                self.gone();
            }
        }
        Ok(())
    }
}

/// Refuses a polygon that is not opaque (opacity below 255, a stream whose header says
/// `opacity`), for a stage that draws opaque polygons only: status 2 and a line naming the
/// a-buffer, rather than drawing it opaque. `at` says where it is (`frame F, polygon P`),
/// asked only for a polygon refused: an opaque one costs one comparison.
#[inline]
pub fn refuse_transparent(
    stage: &str,
    polygon: &Polygon,
    at: impl FnOnce() -> String,
) -> Result<()> {
    if polygon.opacity == proto::OPAQUE {
        return Ok(());
    }
    Err(Error::usage(format!(
        "{}: a polygon of opacity {} (below 255): {stage} draws opaque polygons only; \
         transparency is the a-buffer's (render.sh --aa abuf)",
        at(),
        polygon.opacity
    )))
}

/// [`check_finite`] on a polygon `doing` (the split, the perspective division, …) made:
/// the message says which work made a number too large.
#[inline]
pub fn check_finite_after(poly: &Polygon, doing: &str) -> std::result::Result<(), String> {
    check_finite(poly).map_err(|m| {
        format!("{m} after {doing}: not a finite number (coordinates this large overflow)")
    })
}

/// persp's work on one polygon, for a stage that does it without persp's process (the
/// tree's last splitters, `zbuf --project`): projected to the screen, or refused as persp
/// refuses it, a vertex at or behind the eye or a number the division made too large.
pub fn project_to_screen(
    perspective: &proto::perspective::Perspective,
    poly: &mut Polygon,
) -> std::result::Result<(), String> {
    perspective.project_polygon(poly).map_err(|e| e.reason)?;
    check_finite_after(poly, "the perspective division")
}

/// Checks that a polygon about to be written has only finite numbers (vertices, plane,
/// edge supports): a stage never passes on an infinity or a NaN of its own making, so
/// that the stage at fault, not the next one, refuses. The message names the vertex.
pub fn check_finite(poly: &Polygon) -> std::result::Result<(), String> {
    let show = |v: proto::DVec4| format!("({:?} {:?} {:?} {:?})", v.x, v.y, v.z, v.w);
    if let Some((i, v)) = poly
        .vertices
        .iter()
        .enumerate()
        .find(|(_, v)| !v.is_finite())
    {
        return Err(format!("vertex {i} comes out as {}", show(*v)));
    }
    if let Some(p) = poly.plane.filter(|p| !p.is_finite()) {
        return Err(format!("its plane comes out as {}", show(p)));
    }
    for (i, s) in poly.supports.iter().enumerate() {
        if let Some([a, b]) = s.filter(|[a, b]| !(a.is_finite() && b.is_finite())) {
            return Err(format!(
                "the support of edge {i} comes out as {} {}",
                show(a),
                show(b)
            ));
        }
    }
    Ok(())
}

/// What [`filter_records`] read: NEXT.FRAMEs, the polygons after the last of them (or
/// from the start, if none), and whether END was among the records.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    pub frames: u64,
    pub polygons: u64,
    pub ended: bool,
}

/// [`crate::filter_polygons`]'s loop on one reader: every record of `reader` to `writer`, each polygon
/// transformed and checked, until the reader has no more.
pub fn filter_records<R: Read, W: Write, F>(
    reader: &mut Reader<Token, R>,
    writer: &mut Writer<Token, W>,
    transform: &mut F,
    doing: &str,
) -> Result<Counts>
where
    F: FnMut(&mut Polygon) -> std::result::Result<(), String>,
{
    let mut counts = Counts::default();
    // One token, its polygon's vertex list reused from record to record: the loop
    // allocates nothing per polygon.
    let mut token = Token::default();
    while reader
        .next_into(&mut token)
        .map_err(|e| input_error("stdin", e))?
    {
        match &mut token {
            Token::Polygon(poly) => {
                transform(poly)
                    .and_then(|()| check_finite_after(poly, doing))
                    .map_err(|m| Error::data(format!("{}: {m}", reader.position())))?;
                writer.write_polygon(poly)?;
                counts.polygons += 1;
                continue;
            }
            Token::Skip(n) => counts.polygons += *n as u64,
            Token::NextFrame => {
                counts.frames += 1;
                counts.polygons = 0;
            }
            Token::End => counts.ended = true,
        }
        writer.write(&token)?;
    }
    Ok(counts)
}

/// [`widen_pipe`] on an opened file (a named pipe, say).
fn widen(f: &File) {
    #[cfg(unix)]
    widen_pipe(std::os::fd::AsRawFd::as_raw_fd(f));
}

/// The capacity asked for a pipe between stages: 1 MiB, Linux's default most a process
/// may ask for (`/proc/sys/fs/pipe-max-size`), against the 64 KiB a pipe starts with.
pub const PIPE_BYTES: i32 = 1 << 20;

/// Widens the pipe (or fifo) on file descriptor `fd` to [`PIPE_BYTES`], so that a stage
/// ahead of its reader can write on for longer before it blocks: with more stages than
/// cores, every block is a switch of process, and with the default 64 KiB the stages of
/// a render switched ten times as often. Nothing happens where `fd` is not a pipe, or
/// the system refuses (the stages work at any capacity).
pub fn widen_pipe(fd: i32) {
    #[cfg(target_os = "linux")]
    // SAFETY: F_SETPIPE_SZ on a descriptor only changes that pipe's capacity; on a
    // descriptor that is not a pipe (or not open) it fails with EBADF/EINVAL and does
    // nothing.
    unsafe {
        libc::fcntl(fd, libc::F_SETPIPE_SZ, PIPE_BYTES);
    }
    #[cfg(not(target_os = "linux"))]
    let _ = fd;
}

#[cfg(test)]
mod tests {
    use super::*;
    use proto::DVec4;

    #[cfg(target_os = "linux")]
    #[test]
    fn a_pipe_is_widened_and_a_file_left_alone() {
        let mut fds = [0i32; 2];
        // SAFETY: a fresh pipe, its two descriptors closed below.
        unsafe {
            assert_eq!(libc::pipe(fds.as_mut_ptr()), 0);
            assert_eq!(libc::fcntl(fds[1], libc::F_GETPIPE_SZ), 1 << 16);
        }
        widen_pipe(fds[1]);
        // Either end: the capacity is the pipe's. (The system's limit may be lower than
        // the default most, then the pipe keeps 64 KiB.)
        let limit: i32 = std::fs::read_to_string("/proc/sys/fs/pipe-max-size")
            .ok()
            .and_then(|s| s.trim().parse().ok())
            .unwrap_or(0);
        let want = if limit >= PIPE_BYTES {
            PIPE_BYTES
        } else {
            1 << 16
        };
        // SAFETY: the pipe made above, whose descriptors nothing else has closed.
        unsafe {
            assert_eq!(libc::fcntl(fds[0], libc::F_GETPIPE_SZ), want);
            libc::close(fds[0]);
            libc::close(fds[1]);
        }
        // A file: nothing happens, and nothing fails.
        let f = std::fs::File::open("Cargo.toml").unwrap();
        widen_pipe(std::os::fd::AsRawFd::as_raw_fd(&f));
    }

    #[test]
    fn non_finite_numbers_are_named() {
        let mut p = Polygon::new(
            [1, 2, 3],
            vec![DVec4::ONE, DVec4::new(1.0, f64::NEG_INFINITY, 2.0, 1.0)],
        );
        assert_eq!(
            check_finite(&p).unwrap_err(),
            "vertex 1 comes out as (1.0 -inf 2.0 1.0)"
        );
        p.vertices[1].y = 1.7e308;
        assert_eq!(check_finite(&p), Ok(()));
        p.plane = Some(DVec4::new(f64::NAN, 0.0, 1.0, 0.0));
        assert_eq!(
            check_finite(&p).unwrap_err(),
            "its plane comes out as (NaN 0.0 1.0 0.0)"
        );
        p.plane = None;
        p.supports = vec![None, Some([DVec4::ONE, DVec4::splat(f64::INFINITY)])];
        assert!(check_finite(&p)
            .unwrap_err()
            .starts_with("the support of edge 1"));
    }

    #[test]
    fn outputs_that_are_one_file() {
        let dir = std::env::temp_dir().join(format!("stagecli-same-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("f");
        let f = f.to_str().unwrap();
        assert!(same_file(f, f));
        assert!(same_file("x-not-made", "./x-not-made"));
        assert!(!same_file("x-not-made", "y-not-made"));
        std::fs::write(f, "").unwrap();
        let twin = format!(
            "{}/../{}/f",
            dir.display(),
            dir.file_name().unwrap().to_str().unwrap()
        );
        assert!(same_file(f, &twin));
        assert!(!same_file(f, "/dev/null"));
        assert!(!same_file("/dev/null", "/dev/null"));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn an_output_names_itself_and_keeps_the_kind() {
        struct Failing(bool);
        impl Write for Failing {
            fn write(&mut self, _: &[u8]) -> io::Result<usize> {
                Err(if self.0 {
                    io::Error::from_raw_os_error(28)
                } else {
                    io::ErrorKind::BrokenPipe.into()
                })
            }
            fn flush(&mut self) -> io::Result<()> {
                Ok(())
            }
        }
        let full = Named::new(Failing(true), "stdout").write(b"x");
        let full = Error::from(full.unwrap_err());
        assert_eq!(full.kind(), Kind::Io);
        assert_eq!(full.to_string(), "stdout: No space left on device");
        let gone = Named::new(Failing(false), "out").write_all(b"x");
        assert_eq!(Error::from(gone.unwrap_err()).kind(), Kind::ReaderGone);
    }

    #[test]
    fn input_errors_name_the_input_only_for_io() {
        let io = input_error("stdin", StreamError::Io(io::Error::from_raw_os_error(21)));
        assert_eq!(
            (io.kind(), io.to_string().as_str()),
            (Kind::Io, "stdin: Is a directory")
        );
        let bad = input_error("stdin", StreamError::Invalid("empty input".into()));
        assert_eq!(
            (bad.kind(), bad.to_string().as_str()),
            (Kind::Data, "empty input")
        );
        let missing = open_input("/nonexistent/x").err().unwrap();
        assert_eq!(
            missing.to_string(),
            "cannot open /nonexistent/x: No such file or directory"
        );
        assert_eq!(missing.kind(), Kind::Io);
    }
}
