//! render's progress display (`--progress`, or a terminal on stderr): one line on stderr,
//! redrawn in place, of the frames done, the frames a second and the time, and, in a
//! tree, how many leaves have finished the frame being made.
//!
//! The stages tell their progress by lines on their stderr ([`stagecli::progress`]):
//! render starts them with `POLYPIPE_PROGRESS=1` when it shows progress, and a stage
//! writes `polypipe-progress: frame` each time it finishes a frame. The supervisor takes
//! those lines out of what it relays and counts them by stage: the last stage's (the
//! merger, or hiddenline) are the frames done, the leaves' how far the next one is. The
//! image never passes here; the line is erased on a failure or a stop, so that the
//! message stands alone, and left, ended, on success.

use std::io::Write;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressState, ProgressStyle, TermLike};

use super::plan::Stage;

/// The display, while the run lasts.
pub struct Shown {
    bar: ProgressBar,
    /// The stages that are leaves on this machine (their frames say how far a frame is).
    leaves: Vec<usize>,
}

/// Stderr as indicatif's terminal, also when it is not one (`--progress` into a file or
/// a pipe: the same line, redrawn with `\r`).
#[derive(Debug)]
struct Stderr {
    width: u16,
}

impl Stderr {
    fn put(&self, s: &str) -> std::io::Result<()> {
        std::io::stderr().write_all(s.as_bytes())
    }

    /// The cursor moved `n` places `way` (`A` up … `D` left); none for 0, which a
    /// terminal takes as 1.
    fn step(&self, n: usize, way: char) -> std::io::Result<()> {
        if n == 0 {
            return Ok(());
        }
        self.put(&format!("\x1b[{n}{way}"))
    }
}

impl TermLike for Stderr {
    fn width(&self) -> u16 {
        self.width
    }
    fn move_cursor_up(&self, n: usize) -> std::io::Result<()> {
        self.step(n, 'A')
    }
    fn move_cursor_down(&self, n: usize) -> std::io::Result<()> {
        self.step(n, 'B')
    }
    fn move_cursor_right(&self, n: usize) -> std::io::Result<()> {
        self.step(n, 'C')
    }
    fn move_cursor_left(&self, n: usize) -> std::io::Result<()> {
        self.step(n, 'D')
    }
    fn write_line(&self, s: &str) -> std::io::Result<()> {
        self.put(&format!("{s}\n"))
    }
    fn write_str(&self, s: &str) -> std::io::Result<()> {
        self.put(s)
    }
    fn clear_line(&self) -> std::io::Result<()> {
        self.put("\r\x1b[2K")
    }
    fn flush(&self) -> std::io::Result<()> {
        std::io::stderr().flush()
    }
}

/// The terminal's width, or 100 off a terminal.
fn width() -> u16 {
    // SAFETY: a winsize is plain integers, all zero a valid value; TIOCGWINSZ writes one
    // into the struct given, for stderr's descriptor, and touches nothing else.
    let (got, ws) = unsafe {
        let mut ws = std::mem::zeroed::<libc::winsize>();
        (libc::ioctl(2, libc::TIOCGWINSZ, &mut ws), ws)
    };
    if got == 0 && ws.ws_col > 0 {
        ws.ws_col
    } else {
        100
    }
}

impl Shown {
    /// Starts the display of a run of `stages`, its name `me`, on stderr.
    pub fn new(stages: &[Stage], me: &str) -> Shown {
        let target = ProgressDrawTarget::term_like_with_hz(Box::new(Stderr { width: width() }), 8);
        Shown::to(target, stages, me)
    }

    fn to(target: ProgressDrawTarget, stages: &[Stage], me: &str) -> Shown {
        let last = stages.len().saturating_sub(1);
        let leaves = (0..last)
            .filter(|&i| stages[i].host.is_none() && stages[i].label.contains("(leaf "))
            .collect();
        let bar = ProgressBar::with_draw_target(None, target);
        let template = format!("{me}: {{pos}} frames, {{fps}}{{msg}} ({{elapsed}})");
        if let Ok(style) = ProgressStyle::with_template(&template) {
            bar.set_style(style.with_key(
                "fps",
                |state: &ProgressState, w: &mut dyn std::fmt::Write| {
                    let _ = w.write_fmt(format_args!("{:.1} frames/s", state.per_sec()));
                },
            ));
        }
        // The time goes on during one long frame.
        bar.enable_steady_tick(Duration::from_millis(250));
        Shown { bar, leaves }
    }

    /// Shows the frames `frames` (by stage) say are done.
    pub fn update(&self, frames: &[u64]) {
        let done = frames.last().copied().unwrap_or(0);
        if self.leaves.len() > 1 {
            let leaves = self
                .leaves
                .iter()
                .filter(|&&i| frames.get(i).is_some_and(|&f| f > done))
                .count();
            self.bar.set_message(format!(
                ", frame {}: {leaves}/{} leaves done",
                done + 1,
                self.leaves.len()
            ));
        }
        self.bar.set_position(done);
    }

    /// Ends the display: on success its last state left on a line of its own; else
    /// erased, for the message that follows.
    pub fn end(self, ok: bool) {
        if ok {
            self.bar.set_message("");
            self.bar.abandon();
            let _ = std::io::stderr().write_all(b"\n");
        } else {
            self.bar.finish_and_clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::plan::End;
    use super::*;

    #[test]
    fn the_last_stage_counts_frames_and_the_leaves_say_how_far_the_next_is() {
        let stage = |label: &str, host: Option<(String, u64)>| Stage {
            label: label.into(),
            input: End::Inherit,
            output: End::Inherit,
            host,
            argv: Vec::new(),
            pipes: 0,
        };
        let stages = [
            stage("viewxf", None),
            stage("scanconv (leaf 0)", None),
            stage("scanconv (leaf 1)", None),
            stage("leaf 2 (host a)", Some(("a".into(), 6))),
            stage("zbuf", None),
        ];
        let shown = Shown::to(ProgressDrawTarget::hidden(), &stages, "render");
        assert_eq!(shown.leaves, [1, 2]);
        shown.update(&[0, 3, 2, 0, 2]);
        assert_eq!(shown.bar.position(), 2);
        assert_eq!(shown.bar.message(), ", frame 3: 1/2 leaves done");
        shown.update(&[0, 3, 3, 0, 3]);
        assert_eq!(shown.bar.message(), ", frame 4: 0/2 leaves done");
        // One leaf (depth 0): frames alone.
        let shown = Shown::to(ProgressDrawTarget::hidden(), &stages[..2], "render");
        shown.update(&[0, 1]);
        assert_eq!(
            (shown.bar.position(), shown.bar.message()),
            (1, String::new())
        );
    }
}
