//! farm as a program, with a stand-in for ssh (`POLYPIPE_SSH`) that runs the command
//! here: the frames in order, a host that sends nothing back named, usage errors.

use assert_cmd::Command;
use std::path::PathBuf;

/// A POLYPIPE_SSH that takes the host (and the `--` GNU parallel puts after it), logs
/// the host and runs the command with sh.
fn fake_ssh(dir: &std::path::Path) -> PathBuf {
    let path = dir.join("ssh");
    std::fs::write(
        &path,
        format!(
            "#!/bin/sh\necho \"$1\" >> '{}/hosts'\nshift\n[ \"$1\" = -- ] && shift\n\
             exec sh -c \"$*\"\n",
            dir.display()
        ),
    )
    .unwrap();
    std::process::Command::new("chmod")
        .arg("+x")
        .arg(&path)
        .status()
        .unwrap();
    path
}

/// A movie of `n` frames, frame k one triangle of colour (k, 0, 0).
fn movie(n: u64) -> String {
    let frames: Vec<String> = (0..n)
        .map(|k| format!("colour {k} 0 0\n0 0 0\n1 0 0\n0 1 0\n"))
        .collect();
    format!("polypipe 1 world\n{}END\n", frames.join("NEXT.FRAME\n"))
}

/// A "renderer" for the hosts: one 1x1 PPM a frame, its red the frame's colour, from
/// the text of the chunk (`frames --text` turns the chunk's binary into text).
const RENDER: &str =
    "frames --text | awk '/^colour/ { printf \"P6\\n1 1\\n255\\n%c%c%c\", $2, 0, 0 }'";

#[test]
fn the_frames_come_back_in_the_movies_order() {
    let dir = tempfile::tempdir().unwrap();
    let ssh = fake_ssh(dir.path());
    let frames_dir = PathBuf::from(env!("CARGO_BIN_EXE_farm"))
        .parent()
        .unwrap()
        .to_path_buf();
    if !frames_dir.join("frames").exists() {
        // `cargo test -p farm` alone builds farm's binaries only.
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let mut build = std::process::Command::new(cargo);
        build.args(["build", "--quiet", "-p", "frames"]);
        if frames_dir.ends_with("release") {
            build.arg("--release");
        }
        assert!(build.status().unwrap().success(), "cargo build -p frames");
    }
    let path = format!(
        "{}:{}",
        frames_dir.display(),
        std::env::var("PATH").unwrap()
    );
    let out = Command::cargo_bin("farm")
        .unwrap()
        .args([
            "--hosts", "a,b,c", "--chunk", "2", "-", "--", "sh", "-c", RENDER,
        ])
        .env("POLYPIPE_SSH", &ssh)
        .env("PATH", path)
        .env("LC_ALL", "C")
        .write_stdin(movie(7))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let want: Vec<u8> = (0..7u8)
        .flat_map(|k| [b"P6\n1 1\n255\n".as_slice(), &[k, 0, 0]].concat())
        .collect();
    assert_eq!(out.stdout, want);
    // Four chunks, four sessions.
    let hosts = std::fs::read_to_string(dir.path().join("hosts")).unwrap();
    assert_eq!(hosts.lines().count(), 4, "{hosts}");
}

#[test]
fn a_host_that_sends_nothing_back_is_named_with_status_3() {
    let dir = tempfile::tempdir().unwrap();
    let ssh = fake_ssh(dir.path());
    Command::cargo_bin("farm")
        .unwrap()
        .args([
            "--hosts",
            "quiet",
            "--chunk",
            "4",
            "--retries",
            "2",
            "-",
            "--",
            "cat",
            "/dev/null",
        ])
        .env("POLYPIPE_SSH", &ssh)
        .write_stdin(movie(3))
        .assert()
        .code(3)
        .stdout("")
        .stderr(
            "farm: host quiet: frames 0 to 2, 2 tries: sent back nothing for its frames 0 to 2\n",
        );
}

#[test]
fn usage_errors_are_status_2() {
    Command::cargo_bin("farm")
        .unwrap()
        .args(["--hosts", "a,,b", "-", "--", "true"])
        .write_stdin(movie(1))
        .assert()
        .code(2)
        .stderr("farm: --hosts must be host names separated by commas, not 'a,,b'\n");
    Command::cargo_bin("farm")
        .unwrap()
        .args(["--hosts", "a", "-"])
        .assert()
        .code(2);
    // Files that frames are written to, and only those, can be resumed.
    Command::cargo_bin("farm")
        .unwrap()
        .args(["--hosts", "a", "--resume", "-", "--", "true"])
        .env("POLYPIPE_SSH", "ssh")
        .write_stdin(movie(1))
        .assert()
        .code(2)
        .stderr(
            "farm: --resume needs -o: frames written to stdout by an earlier run are not kept\n",
        );
    Command::cargo_bin("farm")
        .unwrap()
        .args([
            "--slurm-array",
            "out",
            "-o",
            "out/f%03d.png",
            "-",
            "--",
            "true",
        ])
        .write_stdin(movie(1))
        .assert()
        .code(2)
        .stderr(
            "farm: --slurm-array needs the movie as a file: each task reads its frames from it\n",
        );
}
