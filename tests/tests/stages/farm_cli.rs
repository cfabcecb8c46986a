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
    let frames_dir = PathBuf::from(pipeline_tests::bin("farm"))
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
    let out = Command::new(pipeline_tests::bin("farm"))
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
    Command::new(pipeline_tests::bin("farm"))
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
    Command::new(pipeline_tests::bin("farm"))
        .args(["--hosts", "a,,b", "-", "--", "true"])
        .write_stdin(movie(1))
        .assert()
        .code(2)
        .stderr("farm: --hosts must be host names separated by commas, not 'a,,b'\n");
    Command::new(pipeline_tests::bin("farm"))
        .args(["--hosts", "a", "-"])
        .assert()
        .code(2);
    // Files that frames are written to, and only those, can be resumed.
    Command::new(pipeline_tests::bin("farm"))
        .args(["--hosts", "a", "--resume", "-", "--", "true"])
        .env("POLYPIPE_SSH", "ssh")
        .write_stdin(movie(1))
        .assert()
        .code(2)
        .stderr(
            "farm: --resume needs -o: frames written to stdout by an earlier run are not kept\n",
        );
    Command::new(pipeline_tests::bin("farm"))
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

#[test]
fn a_job_parallel_leaves_behind_when_stopped_is_stopped_by_farm() {
    // GNU parallel stops its jobs by process group when asked to stop, but a job it is
    // starting at that moment escapes it (about one stop in six, with ssh jobs). This
    // stand-in for parallel starts a job in a session of its own and, asked to stop,
    // ends without it: farm, the reaper of what its children leave, must stop it.
    let dir = tempfile::tempdir().unwrap();
    let pid_file = dir.path().join("job.pid");
    let fake = dir.path().join("parallel");
    std::fs::write(
        &fake,
        format!(
            "#!/bin/sh\nsetsid sleep 301 &\necho $! > '{}.tmp'\nmv '{0}.tmp' '{0}'\n\
             trap 'exit 0' INT TERM\nwhile :; do sleep 0.05; done\n",
            pid_file.display()
        ),
    )
    .unwrap();
    std::process::Command::new("chmod")
        .arg("+x")
        .arg(&fake)
        .status()
        .unwrap();
    let path = format!(
        "{}:{}",
        dir.path().display(),
        std::env::var("PATH").unwrap()
    );
    let movie_file = dir.path().join("movie.txt");
    std::fs::write(&movie_file, movie(4)).unwrap();
    let mut farm = std::process::Command::new(pipeline_tests::bin("farm"))
        .args(["--hosts", "a", "--chunk", "2"])
        .arg(&movie_file)
        .args(["--", "true"])
        .env("POLYPIPE_SSH", "ssh")
        .env("PATH", path)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let started = std::time::Instant::now();
    while !pid_file.exists() {
        assert!(
            started.elapsed().as_secs() < 60,
            "the stand-in never started its job"
        );
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let job = std::fs::read_to_string(&pid_file)
        .unwrap()
        .trim()
        .to_string();
    assert!(std::path::Path::new(&format!("/proc/{job}")).exists());
    let status = std::process::Command::new("kill")
        .args(["-TERM", &farm.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    assert_eq!(farm.wait().unwrap().code(), Some(143));
    let left = std::fs::read_to_string(format!("/proc/{job}/cmdline")).unwrap_or_default();
    if left.starts_with("sleep\u{0}301") {
        let _ = std::process::Command::new("kill").arg(&job).status();
        panic!("the job parallel left (pid {job}) outlived farm");
    }
}
