//! Progress a stage tells the launcher that started it (render), as lines on its stderr.
//!
//! render, when it shows progress, starts its stages with [`ENV`] set to `1`; a stage
//! that finishes a frame then writes the one line [`FRAME`] on stderr ([`frame_done`]),
//! in one `write` (a pipe keeps a write of at most 512 bytes whole, so the line never
//! mixes with another). render takes these lines out of what it relays ([`take`]) and
//! counts them: the last stage's are the movie's frames, the others' (the leaves') say how
//! far one frame is. A stage run by hand, or by render without progress, never writes
//! one; its stdout (the image) is never touched.

use std::io::Write;
use std::sync::OnceLock;

/// The variable render sets, `1`, in the environment of the stages it starts when it
/// shows progress.
pub const ENV: &str = "POLYPIPE_PROGRESS";

/// The line a stage writes on stderr when it has finished a frame.
pub const FRAME: &[u8] = b"polypipe-progress: frame\n";

/// Whether this stage was asked for progress lines ([`ENV`] is `1`).
pub fn asked() -> bool {
    static ASKED: OnceLock<bool> = OnceLock::new();
    *ASKED.get_or_init(|| std::env::var_os(ENV).is_some_and(|v| v == "1"))
}

/// Tells the launcher a frame is finished, when it asked ([`asked`]); a stderr that
/// cannot be written is no failure of the stage's work.
pub fn frame_done() {
    if asked() {
        let _ = std::io::stderr().write_all(FRAME);
    }
}

/// Takes the [`FRAME`] lines out of `said` from byte `*from` on (a line's start) and
/// says how many there were; `*from` is left at the start of the last line not yet
/// ended, so that a line cut between two reads is looked at whole on the next call.
pub fn take(said: &mut Vec<u8>, from: &mut usize) -> u64 {
    let mut found = 0;
    let mut read = *from;
    let mut kept = *from;
    while let Some(len) = said[read..].iter().position(|&b| b == b'\n').map(|n| n + 1) {
        if &said[read..read + len] == FRAME {
            found += 1;
        } else {
            said.copy_within(read..read + len, kept);
            kept += len;
        }
        read += len;
    }
    said.copy_within(read.., kept);
    said.truncate(kept + (said.len() - read));
    *from = kept;
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_lines_are_taken_out_and_counted_even_cut_between_reads() {
        let mut said = Vec::new();
        let mut from = 0;
        said.extend_from_slice(b"zbuf: a\npolypipe-progress: frame\npolypipe-pro");
        assert_eq!(take(&mut said, &mut from), 1);
        assert_eq!(said, b"zbuf: a\npolypipe-pro");
        assert_eq!(from, 8);
        said.extend_from_slice(b"gress: frame\nzbuf: b");
        assert_eq!(take(&mut said, &mut from), 1);
        assert_eq!(said, b"zbuf: a\nzbuf: b");
        said.extend_from_slice(b"\npolypipe-progress: frame\n");
        assert_eq!(take(&mut said, &mut from), 1);
        assert_eq!(said, b"zbuf: a\nzbuf: b\n");
        assert_eq!(from, said.len());
        // A line that only starts like one is kept.
        said.extend_from_slice(b"polypipe-progress: frames\n");
        assert_eq!(take(&mut said, &mut from), 0);
        assert_eq!(said, b"zbuf: a\nzbuf: b\npolypipe-progress: frames\n");
    }
}
