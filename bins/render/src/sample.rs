//! The sample of a scene on stdin (or in a pipe) that `render --depth auto` plans from:
//! the stream's first [`SAMPLE_BYTES`] (512 KiB), or less when the stream ends, or when
//! it pauses. It is kept in memory, and the launcher feeds the render the sample and
//! then the rest of the stream ([`crate::launch::Feed`]), so nothing more than the
//! sample is kept, and a live source (`scene … | render | ffmpeg`) is not held up: a
//! source that writes a frame and waits is sampled for at most [`PATIENCE`] after its
//! first byte.

use std::io::{self, Read, Write};
use std::os::fd::AsRawFd;
use std::time::{Duration, Instant};

pub use costmodel::look::SAMPLE_BYTES;

/// How long after the stream's first byte the sample may wait for the rest of its bytes.
pub const PATIENCE: Duration = Duration::from_millis(150);

/// How the sample ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ended {
    /// The stream ended within the sample: the sample is the whole scene.
    Whole,
    /// The sample is full, or the stream paused: more may come.
    More,
}

/// Copies up to `limit` bytes of `input` to `out`, stopping early at the end of `input`
/// or `patience` after its first byte. `input` must be a file descriptor that `poll`
/// works on (a pipe, a terminal, a socket, a file).
pub fn sample<R: Read + AsRawFd, W: Write>(
    input: &mut R,
    out: &mut W,
    limit: u64,
    patience: Duration,
) -> io::Result<(u64, Ended)> {
    let mut buf = vec![0u8; 64 * 1024];
    let mut got = 0u64;
    let mut since: Option<Instant> = None;
    while got < limit {
        if let Some(start) = since {
            let left = patience.saturating_sub(start.elapsed());
            if left.is_zero() || !readable(input.as_raw_fd(), left)? {
                return Ok((got, Ended::More));
            }
        }
        let want = buf.len().min((limit - got) as usize);
        let n = match input.read(&mut buf[..want]) {
            Ok(n) => n,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e),
        };
        if n == 0 {
            return Ok((got, Ended::Whole));
        }
        since.get_or_insert_with(Instant::now);
        out.write_all(&buf[..n])?;
        got += n as u64;
    }
    Ok((got, Ended::More))
}

/// Whether `fd` has something to read (or its end) within `wait`.
fn readable(fd: i32, wait: Duration) -> io::Result<bool> {
    let mut p = libc::pollfd {
        fd,
        events: libc::POLLIN,
        revents: 0,
    };
    let ms = wait.as_millis().min(i32::MAX as u128) as i32;
    loop {
        // SAFETY: one valid pollfd, for the length of the call.
        let r = unsafe { libc::poll(&mut p, 1, ms.max(1)) };
        if r >= 0 {
            return Ok(r > 0);
        }
        let e = io::Error::last_os_error();
        if e.kind() != io::ErrorKind::Interrupted {
            return Err(e);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_short_stream_is_whole_and_a_long_one_is_cut_at_the_limit() {
        let (mut r, mut w) = std::io::pipe().unwrap();
        w.write_all(&[7u8; 1000]).unwrap();
        drop(w);
        let mut out = Vec::new();
        let got = sample(&mut r, &mut out, 4096, PATIENCE).unwrap();
        assert_eq!(got, (1000, Ended::Whole));
        assert_eq!(out, vec![7u8; 1000]);

        let (mut r, mut w) = std::io::pipe().unwrap();
        let writer = std::thread::spawn(move || {
            let _ = w.write_all(&[1u8; 10_000]);
        });
        let mut out = Vec::new();
        assert_eq!(
            sample(&mut r, &mut out, 4096, PATIENCE).unwrap(),
            (4096, Ended::More)
        );
        // The rest is still there for the render.
        let mut rest = Vec::new();
        r.read_to_end(&mut rest).unwrap();
        writer.join().unwrap();
        assert_eq!(out.len() + rest.len(), 10_000);
    }

    #[test]
    fn a_pausing_source_is_not_waited_for() {
        // The source writes a frame and then nothing until the sample is taken (or 20 s
        // have passed): the sample is the frame alone, taken PATIENCE after it. Had the
        // sample waited for more, it would hold the second write too. The bound on the
        // time is that of a sample that waits, not of PATIENCE itself, which a loaded
        // machine's scheduling stretches.
        let (mut r, mut w) = std::io::pipe().unwrap();
        let (taken, wait) = std::sync::mpsc::channel::<()>();
        let writer = std::thread::spawn(move || {
            w.write_all(b"first frame").unwrap();
            let _ = wait.recv_timeout(Duration::from_secs(20));
            let _ = w.write_all(b"second");
        });
        let start = Instant::now();
        let mut out = Vec::new();
        let got = sample(&mut r, &mut out, 1 << 20, PATIENCE).unwrap();
        let took = start.elapsed();
        let _ = taken.send(());
        assert_eq!(got, (11, Ended::More));
        assert_eq!(out, b"first frame");
        assert!(took < Duration::from_secs(10), "took {took:?}");
        drop(r);
        writer.join().unwrap();
    }
}
