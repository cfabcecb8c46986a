//! Memory: whether a screen fits in this machine, decided at the stream's header; and
//! buffers kept for reuse between threads ([`Spare`]).
//!
//! A stage that keeps something for every pixel of the screen (the merger's frame
//! buffer, a leaf's region buffer) refuses a screen too large for this machine as soon
//! as the header gives its size, with what it would need, rather than after it has
//! asked the kernel for the memory (which Linux's overcommit grants, and then fills the
//! machine page by page) or has scan-converted a first frame. Too large for this
//! machine is the machine's limit, not a fault of the data: status 3, as for I/O and the
//! environment.

use crate::{Error, Result};

/// The memory this process can have, in bytes: the least of what the kernel says is
/// available (MemAvailable and free swap, from /proc/meminfo), the address-space limit
/// (`ulimit -v`) and the control group's limit (cgroup v2 `memory.max`); `None` where
/// none of them can be read.
pub fn available() -> Option<u64> {
    let mut least: Option<u64> = None;
    let mut take = |v: u64| least = Some(least.map_or(v, |l| l.min(v)));
    if let Ok(info) = std::fs::read_to_string("/proc/meminfo") {
        let field = |name: &str| -> Option<u64> {
            let line = info.lines().find(|l| l.starts_with(name))?;
            let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
            Some(kb * 1024)
        };
        if let Some(mem) = field("MemAvailable:") {
            take(mem + field("SwapFree:").unwrap_or(0));
        }
    }
    let mut limit = libc::rlimit {
        rlim_cur: 0,
        rlim_max: 0,
    };
    // SAFETY: getrlimit writes the one struct it is given, which lives on this stack.
    if unsafe { libc::getrlimit(libc::RLIMIT_AS, &mut limit) } == 0
        && limit.rlim_cur != libc::RLIM_INFINITY
    {
        take(limit.rlim_cur);
    }
    if let Ok(max) = std::fs::read_to_string("/sys/fs/cgroup/memory.max") {
        if let Ok(v) = max.trim().parse::<u64>() {
            take(v);
        }
    }
    least
}

/// Refuses a `width`×`height` screen whose `bytes_per_pixel` (`what` they hold, for the
/// message) do not fit in `available` bytes; `None` available accepts every screen.
pub fn check_screen_in(
    width: u32,
    height: u32,
    bytes_per_pixel: u64,
    what: &str,
    available: Option<u64>,
) -> Result<()> {
    let need = u64::from(width) * u64::from(height) * bytes_per_pixel;
    match available {
        Some(have) if need > have => Err(Error::io(format!(
            "a {width}x{height} screen needs {} ({bytes_per_pixel} bytes a pixel: {what}), \
             more memory than this machine can give ({} available)",
            crate::error::bytes_text(need),
            crate::error::bytes_text(have)
        ))),
        _ => Ok(()),
    }
}

/// [`check_screen_in`] this machine's [`available`] memory.
pub fn check_screen(width: u32, height: u32, bytes_per_pixel: u64, what: &str) -> Result<()> {
    check_screen_in(width, height, bytes_per_pixel, what, available())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Kind;

    #[test]
    fn a_screen_larger_than_what_is_available_is_refused_with_status_3() {
        let e = check_screen_in(65536, 65536, 15, "depth, polygon and colour", Some(8 << 30))
            .unwrap_err();
        assert_eq!(e.kind(), Kind::Io);
        assert_eq!(e.kind().status(), 3);
        assert_eq!(
            e.to_string(),
            "a 65536x65536 screen needs 60 GiB (15 bytes a pixel: depth, polygon and \
             colour), more memory than this machine can give (8 GiB available)"
        );
    }

    #[test]
    fn a_screen_that_fits_or_an_unknown_machine_passes() {
        assert!(check_screen_in(1920, 1080, 15, "x", Some(8 << 30)).is_ok());
        assert!(check_screen_in(65536, 65536, 15, "x", None).is_ok());
        // Exactly what is available fits.
        assert!(check_screen_in(1024, 1024, 4, "x", Some(4 << 20)).is_ok());
        assert!(check_screen_in(1024, 1024, 4, "x", Some((4 << 20) - 1)).is_err());
    }

    #[test]
    fn this_machine_has_some_memory() {
        assert!(available().is_some_and(|b| b > 0));
    }
}

/// Buffers not in use, kept for the next user. A buffer that goes from one thread to
/// another (a piece's bytes, a reader thread's batch of records) comes back here when it
/// is done with rather than to the allocator: glibc hands a freed block of a few hundred
/// kilobytes back to the kernel, and the next one is fresh pages, each a fault and a page
/// zeroed (the merger's reader threads spent a third of its time so).
pub struct Spare<T>(std::sync::Mutex<Vec<Vec<T>>>);

impl<T> Default for Spare<T> {
    fn default() -> Self {
        Spare(std::sync::Mutex::new(Vec::new()))
    }
}

impl<T> Spare<T> {
    /// An empty buffer: one used before, with its capacity, if there is one.
    pub fn take(&self) -> Vec<T> {
        self.0
            .lock()
            .ok()
            .and_then(|mut v| v.pop())
            .unwrap_or_default()
    }

    /// Keeps `buffer`, emptied, for the next [`Spare::take`].
    pub fn give(&self, mut buffer: Vec<T>) {
        buffer.clear();
        if let Ok(mut v) = self.0.lock() {
            v.push(buffer);
        }
    }
}

#[cfg(test)]
mod spare_tests {
    use super::Spare;

    #[test]
    fn a_buffer_given_back_is_taken_again_empty_with_its_capacity() {
        let spare = Spare::<u32>::default();
        assert_eq!(spare.take().capacity(), 0);
        let mut v = Vec::with_capacity(4096);
        v.extend([1, 2, 3]);
        let at = v.as_ptr();
        spare.give(v);
        let again = spare.take();
        assert!(again.is_empty() && again.capacity() == 4096 && again.as_ptr() == at);
        assert_eq!(spare.take().capacity(), 0);
    }
}
