//! A scene on stdin: given as `-`, or as no SCENE at all when stdin is not a terminal
//! (as a filter reads it), and a stream --depth auto looks at before the stages read it.

use pipeline_tests::render::{frames, render, render_cmd, render_ok};
use pipeline_tests::{bin_dir, output_with_stdin, repo_root};
use std::path::PathBuf;
use std::process::Command;

#[test]
fn scene_from_stdin_size_and_output_pattern() {
    let scene = std::fs::read(repo_root().join("examples/penetrating.txt")).unwrap();
    let small = render_ok(&["--size", "64x48", "-"], &scene);
    let f = frames(&small);
    assert_eq!((f.len(), f[0].width, f[0].height), (1, 64, 48));
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("render-pattern");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let pattern = dir.join("frame%02d.ppm");
    let out = render_ok(
        &[
            "--size",
            "64x48",
            "--depth",
            "2",
            "-o",
            pattern.to_str().unwrap(),
            "-",
        ],
        &scene,
    );
    assert!(out.is_empty());
    assert_eq!(std::fs::read(dir.join("frame00.ppm")).unwrap(), small);
}

/// `scene … | render` reads the scene from stdin, as a filter does when given no file:
/// the same bytes as `scene … | render -`, at a fixed depth and at auto.
#[test]
fn stdin_without_a_scene_is_read_as_with_dash() {
    let sphere = Command::new(bin_dir().join("scene"))
        .arg("sphere")
        .output()
        .unwrap();
    assert!(sphere.status.success());
    for depth in [&["--depth", "2"][..], &[]] {
        let with_dash = render_ok(&[depth, &["--size", "64x48", "-"]].concat(), &sphere.stdout);
        let without = render_ok(&[depth, &["--size", "64x48"]].concat(), &sphere.stdout);
        assert_eq!(frames(&with_dash).len(), 1);
        assert!(with_dash == without, "{depth:?}");
    }
    // An empty stdin is an empty scene, said by the stage that reads it.
    let out = render(&["--size", "8x8"], b"");
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "viewxf: empty input: expected a polypipe stream header\n"
    );
}

/// A world-space text scene of `polygons` quadrilaterals (about 260 bytes each).
fn environment(polygons: u32) -> Vec<u8> {
    let out = Command::new(bin_dir().join("scene"))
        .args([
            "environment",
            "--polygons",
            &polygons.to_string(),
            "--seed",
            "3",
        ])
        .args(["--depth-complexity", "2", "--text"])
        .output()
        .unwrap();
    assert!(out.status.success());
    out.stdout
}

/// The depth `--depth auto --stats` says it chose.
fn chosen(stderr: &[u8]) -> String {
    let err = String::from_utf8_lossy(stderr);
    pipeline_tests::stat(&err, "depth_auto").to_string()
}

/// `--depth auto` on a stream longer than its 512 KiB sample reads the stream once: the
/// sample it looked at, kept in memory, then the rest reach viewxf, and the frames are
/// the chosen depth's from the file. On stdin, and on a named pipe given as the SCENE
/// (which can be opened and read only once); nothing is left in TMPDIR.
#[test]
fn depth_auto_reads_a_pipe_once() {
    let text = environment(8000);
    assert!(text.len() > 1 << 20, "{} bytes", text.len());
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("render-auto-pipe");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("tmp")).unwrap();
    let file = dir.join("scene.txt");
    std::fs::write(&file, &text).unwrap();
    let out = output_with_stdin(
        {
            let mut c = render_cmd(&["--size", "160x120", "--stats"]);
            c.env("TMPDIR", dir.join("tmp"));
            c
        },
        &text,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let depth = chosen(&out.stderr);
    let expected = render_ok(
        &[
            "--size",
            "160x120",
            "--depth",
            &depth,
            file.to_str().unwrap(),
        ],
        b"",
    );
    assert!(out.stdout == expected, "stdin at auto (depth {depth})");
    // A named pipe as the SCENE, written once by another process.
    let fifo = dir.join("scene.fifo");
    let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    let writer = {
        let (fifo, text) = (fifo.clone(), text.clone());
        std::thread::spawn(move || std::fs::write(fifo, text).unwrap())
    };
    let out = render(
        &["--size", "160x120", "--stats", fifo.to_str().unwrap()],
        b"",
    );
    writer.join().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(chosen(&out.stderr), depth);
    assert!(out.stdout == expected, "a named pipe at auto");
    assert_eq!(std::fs::read_dir(dir.join("tmp")).unwrap().count(), 0);
}

/// A small scene given as a pipe's path (`/dev/stdin`, `<(…)`) on a screen where a file
/// that small is depth 0 for its size alone: render does not open it to measure it (the
/// bytes it read would be lost to viewxf), and the frame is the file's.
#[test]
fn a_small_scene_named_as_a_pipe_is_read_once() {
    let example = repo_root().join("examples/penetrating.txt");
    let text = std::fs::read(&example).unwrap();
    let out = output_with_stdin(
        render_cmd(&["--size", "64x64", "--stats", "/dev/stdin"]),
        &text,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let expected = render_ok(&["--size", "64x64", example.to_str().unwrap()], b"");
    assert_eq!(frames(&out.stdout).len(), 1);
    assert!(
        out.stdout == expected,
        "the pipe's frame against the file's"
    );
}
