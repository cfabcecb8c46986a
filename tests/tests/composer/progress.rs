//! render's progress on stderr: shown on a terminal (a pseudo-terminal of util-linux
//! `script`) or with `--progress`, never otherwise; the frames done reach the movie's
//! count, with frames a second; the image is the same bytes with it or without; the line
//! is erased before a failure's message and on a stop.

use pipeline_tests::bin_dir;
use pipeline_tests::render::{render, render_cmd};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// A movie of `frames` frames of spheres, written to `dir`.
fn movie(dir: &Path, frames: u32) -> PathBuf {
    let out = Command::new(bin_dir().join("scene"))
        .args(["spheres", "--frames", &frames.to_string()])
        .output()
        .unwrap();
    assert!(out.status.success());
    let path = dir.join("movie.pp");
    std::fs::write(&path, out.stdout).unwrap();
    path
}

/// What is left of a progress stream once each redraw has drawn over the one before:
/// the text after the last erase of the line.
fn last_drawn(err: &str) -> &str {
    err.rsplit("\x1b[2K").next().unwrap_or(err)
}

#[test]
fn a_terminal_shows_the_frames_done_and_their_rate() {
    let has_script = Command::new("script")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !has_script {
        pipeline_tests::skip("util-linux `script` not installed");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let scene = movie(dir.path(), 12);
    let line = format!(
        "POLYPIPE_LOAD=0 {} --size 48x48 --depth 1 -o {}/f%03d.png {}",
        pipeline_tests::repo_root()
            .join("scripts/render.sh")
            .display(),
        dir.path().display(),
        scene.display()
    );
    let out = Command::new("script")
        .args(["-qec", &line, "/dev/null"])
        .stdin(Stdio::null())
        .env("TERM", "xterm")
        .output()
        .expect("script (util-linux) to run render on a terminal");
    let screen = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{screen:?}");
    // The last state drawn, left on its line: every frame, and the rate.
    let last = last_drawn(&screen);
    assert!(last.starts_with("render: 12 frames, "), "{screen:?}");
    assert!(last.contains(" frames/s ("), "{screen:?}");
    assert!(screen.ends_with("\n"), "{screen:?}");
    assert!(dir.path().join("f011.png").exists());
}

#[test]
fn no_terminal_no_progress_and_progress_into_a_pipe_when_asked() {
    let dir = tempfile::tempdir().unwrap();
    let scene = movie(dir.path(), 6);
    let scene = scene.to_str().unwrap();
    for depth in ["0", "2"] {
        let args = ["--size", "40x30", "--depth", depth, scene];
        // stderr a pipe: nothing, even where the environment asks the stages for it.
        let quiet = render_cmd(&args)
            .env("POLYPIPE_PROGRESS", "1")
            .output()
            .unwrap();
        assert!(quiet.status.success());
        assert_eq!(String::from_utf8_lossy(&quiet.stderr), "", "depth {depth}");
        // --progress: shown in the pipe, the same image on stdout.
        let shown = render(&[&["--progress"][..], &args].concat(), b"");
        assert!(shown.status.success());
        let err = String::from_utf8_lossy(&shown.stderr);
        let last = last_drawn(&err);
        assert!(
            last.starts_with("render: 6 frames, ") && last.contains(" frames/s ("),
            "depth {depth}: {err:?}"
        );
        // Left on a line of its own (indicatif pads it to the width).
        assert!(
            err.ends_with('\n') && err.trim_end().ends_with(')'),
            "{err:?}"
        );
        assert!(!err.contains("polypipe-progress"), "{err:?}");
        assert!(
            shown.stdout == quiet.stdout,
            "depth {depth}: the image changed"
        );
        // --no-progress after it wins.
        let not = render(&[&["--progress", "--no-progress"][..], &args].concat(), b"");
        assert_eq!(String::from_utf8_lossy(&not.stderr), "");
    }
}

/// A failure's message stands alone after the line is erased; a stop erases it too.
#[test]
fn the_line_is_erased_before_a_failure_and_on_a_stop() {
    let out = render(
        &["--progress", "--depth", "1", "-"],
        b"polypipe 1 world\ncolour 1 2 3\n0 0\n",
    );
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        last_drawn(&err).starts_with("viewxf: line 3, column 4: ")
            && last_drawn(&err).lines().count() == 1,
        "{err:?}"
    );
    // SIGINT once the first frames are done: status 130, the line erased last.
    let dir = tempfile::tempdir().unwrap();
    let scene = movie(dir.path(), 2000);
    let mut child = render_cmd(&["--progress", "--size", "200x200", "--depth", "1"])
        .arg(&scene)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut err = child.stderr.take().unwrap();
    let mut seen = Vec::new();
    let mut buf = [0u8; 4096];
    use std::io::Read;
    while !String::from_utf8_lossy(&seen).contains(" frames/s") {
        let n = err.read(&mut buf).unwrap();
        assert!(n > 0, "{}", String::from_utf8_lossy(&seen));
        seen.extend_from_slice(&buf[..n]);
    }
    // SAFETY: kill sends SIGINT to the child this test started.
    unsafe { libc::kill(child.id() as i32, libc::SIGINT) };
    err.read_to_end(&mut seen).unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    let seen = String::from_utf8_lossy(&seen);
    assert!(seen.ends_with("\r\x1b[2K"), "{seen:?}");
}
