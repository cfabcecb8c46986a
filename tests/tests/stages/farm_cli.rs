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
    let frames_dir = pipeline_tests::bin("farm").parent().unwrap().to_path_buf();
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
            "farm: host quiet: a try of frames 0 to 2 failed: sent back nothing for its frames \
             0 to 2\nfarm: host quiet: frames 0 to 2, 2 tries: sent back nothing for its \
             frames 0 to 2\n",
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

/// PATH with the folder of the binaries (farm, frames) first.
fn path_with_frames() -> String {
    format!(
        "{}:{}",
        pipeline_tests::bin_dir().display(),
        std::env::var("PATH").unwrap()
    )
}

/// A POLYPIPE_SSH as [`fake_ssh`]'s, whose hosts behave as `cases` (a shell `case`
/// body on the host, `$1`) says before the command runs.
fn fake_ssh_with(dir: &std::path::Path, cases: &str) -> PathBuf {
    let path = dir.join("ssh");
    std::fs::write(
        &path,
        format!(
            "#!/bin/sh\necho \"$1\" >> '{}/hosts'\ncase $1 in {cases} esac\nshift\n\
             [ \"$1\" = -- ] && shift\nexec sh -c \"$*\"\n",
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

/// The frames RENDER gives for a movie of `n`, as PPM on stdout.
fn reds(n: u8) -> Vec<u8> {
    (0..n)
        .flat_map(|k| [b"P6\n1 1\n255\n".as_slice(), &[k, 0, 0]].concat())
        .collect()
}

/// farm ARGS -- sh -c RENDER (after `before`, shell run first on the host) with `ssh`.
fn farm_run(ssh: &std::path::Path, args: &[&str], before: &str, n: u64) -> std::process::Output {
    let render = format!("{before}{RENDER}");
    let mut cmd = Command::new(pipeline_tests::bin("farm"));
    cmd.args(args)
        .args(["--", "sh", "-c", &render])
        .env("POLYPIPE_SSH", ssh)
        .env("PATH", path_with_frames())
        .env("LC_ALL", "C")
        .write_stdin(movie(n))
        .timeout(std::time::Duration::from_secs(120));
    cmd.output().unwrap()
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// The job log's lines of tries: (seq, host, start, runtime, exit, command).
fn tries(joblog: &std::path::Path) -> Vec<(usize, String, f64, f64, i32, String)> {
    let text = std::fs::read_to_string(joblog).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("Seq\tHost\tStarttime\tJobRuntime\tSend\tReceive\tExitval\tSignal\tCommand")
    );
    lines
        .map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            assert_eq!(f.len(), 9, "{l}");
            (
                f[0].parse().unwrap(),
                f[1].to_string(),
                f[2].trim().parse().unwrap(),
                f[3].trim().parse().unwrap(),
                f[6].parse().unwrap(),
                f[8].to_string(),
            )
        })
        .collect()
}

#[test]
fn two_slots_on_one_host_run_two_chunks_at_once() {
    // `2/a` from an sshlogin file: two chunks of a second each overlap in the job log.
    let dir = tempfile::tempdir().unwrap();
    let ssh = fake_ssh(dir.path());
    let logins = dir.path().join("logins");
    std::fs::write(&logins, "2/a\n").unwrap();
    let joblog = dir.path().join("log");
    let out = farm_run(
        &ssh,
        &[
            "--sshloginfile",
            logins.to_str().unwrap(),
            "--chunk",
            "1",
            "--joblog",
            joblog.to_str().unwrap(),
            "-",
        ],
        "sleep 1; ",
        4,
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(out.stdout, reds(4));
    let t = tries(&joblog);
    assert_eq!(t.len(), 4, "one line a try: {t:?}");
    // Each line gives the bytes of the chunk sent and of its one frame received.
    let log = std::fs::read_to_string(&joblog).unwrap();
    for line in log.lines().skip(1) {
        let f: Vec<&str> = line.split('\t').collect();
        assert!(f[4].parse::<u64>().unwrap() > 0, "{line}");
        assert_eq!(f[5], "14", "{line}");
    }
    let overlap = t.iter().enumerate().any(|(i, a)| {
        t[i + 1..]
            .iter()
            .any(|b| a.2 < b.2 + b.3 && b.2 < a.2 + a.3)
    });
    assert!(overlap, "no two chunks ran at once: {t:?}");
}

#[test]
fn a_dead_host_is_named_at_once_and_dropped_after_two_failures() {
    let dir = tempfile::tempdir().unwrap();
    let ssh = fake_ssh_with(
        dir.path(),
        "dead) echo 'ssh: connect to host dead port 22: Connection refused' >&2; exit 255 ;;",
    );
    let joblog = dir.path().join("log");
    let out = farm_run(
        &ssh,
        &[
            "--hosts",
            "dead,good",
            "--chunk",
            "1",
            "--joblog",
            joblog.to_str().unwrap(),
            "-",
        ],
        "",
        12,
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(out.stdout, reds(12));
    let err = text(&out.stderr);
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 2, "{err}");
    assert!(
        lines[0].starts_with("farm: host dead: a try of frame")
            && lines[0].ends_with(" failed: ssh: connect to host dead port 22: Connection refused"),
        "{err}"
    );
    assert_eq!(
        lines[1],
        "farm: host dead: 2 failed tries in a row; it gets no more chunks"
    );
    // Two tries, and on a loaded machine one or two more that started before farm saw
    // the second fail; never one for each chunk.
    let dead = tries(&joblog).iter().filter(|t| t.1 == "dead").count();
    assert!((2..=4).contains(&dead), "{dead} tries on dead");
    let good: Vec<_> = tries(&joblog)
        .into_iter()
        .filter(|t| t.1 == "good")
        .collect();
    assert!(
        good.iter().all(|t| t.4 == 0) && good.len() == 12,
        "{good:?}"
    );
}

#[test]
fn a_host_silent_past_the_host_timeout_has_its_chunks_rendered_elsewhere() {
    let dir = tempfile::tempdir().unwrap();
    let ssh = fake_ssh_with(dir.path(), "sleepy) exec sleep 1000 ;;");
    let joblog = dir.path().join("log");
    let started = std::time::Instant::now();
    let out = farm_run(
        &ssh,
        &[
            "--hosts",
            "sleepy,good",
            "--chunk",
            "2",
            "--host-timeout",
            "2",
            "--joblog",
            joblog.to_str().unwrap(),
            "-",
        ],
        "",
        8,
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(out.stdout, reds(8), "byte for byte, all on good");
    let err = text(&out.stderr);
    assert!(
        err.lines()
            .any(|l| l.starts_with("farm: host sleepy: a try of frames ")
                && l.ends_with(" failed: sent nothing for 2 s (--host-timeout 2)")),
        "{err}"
    );
    assert!(started.elapsed() < std::time::Duration::from_secs(60));
    let t = tries(&joblog);
    assert!(t.iter().filter(|t| t.1 == "good").all(|t| t.4 == 0));
    assert!(
        t.iter().filter(|t| t.1 == "sleepy").all(|t| t.4 == 3),
        "{t:?}"
    );
}

/// The frames RENDER writes for frame k, as farm's -o writes PPM files.
fn ppm(k: u8) -> Vec<u8> {
    [b"P6\n1 1\n255\n".as_slice(), &[k, 0, 0]].concat()
}

#[test]
fn resume_renders_again_the_chunks_of_a_missing_and_a_cut_frame_in_a_folder_with_quotes() {
    // The -o folder does not exist yet and holds a space and a quote.
    let dir = tempfile::tempdir().unwrap();
    let ssh = fake_ssh(dir.path());
    let out_dir = dir.path().join("it's a movie");
    let pattern = format!("{}/f%03d.ppm", out_dir.display());
    let args = [
        "--hosts",
        "a,b",
        "--chunk",
        "2",
        "-o",
        &pattern,
        "--first-frame",
        "100",
        "-",
    ];
    let out = farm_run(&ssh, &args, "", 8);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let frame = |k: u64| out_dir.join(format!("f{:03}.ppm", 100 + k));
    for k in 0..8 {
        assert_eq!(std::fs::read(frame(k)).unwrap(), ppm(k as u8));
    }
    let joblog = out_dir.join("farm.joblog");
    let first = tries(&joblog);
    assert_eq!(first.len(), 4);
    // Frame 101 (chunk 0) deleted, frame 106 (chunk 3) cut.
    std::fs::remove_file(frame(1)).unwrap();
    std::fs::write(frame(6), b"P6\n1 1\n255\n\x06").unwrap();
    let resumed = [&args[..8], &["--resume", "-"]].concat();
    let out = farm_run(&ssh, &resumed, "", 8);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let err = text(&out.stderr);
    assert_eq!(
        err,
        format!(
            "farm: --resume: frame 101 ({}): missing; frames 0 to 1 rendered again\nfarm: --resume: frame 106 ({}): cut or damaged: {}; frames \
             6 to 7 rendered again\n",
            frame(1).display(),
            frame(6).display(),
            err.split("cut or damaged: ")
                .nth(1)
                .and_then(|r| r.split("; frames 6").next())
                .unwrap_or("?")
        )
    );
    for k in 0..8 {
        assert_eq!(std::fs::read(frame(k)).unwrap(), ppm(k as u8), "frame {k}");
    }
    let all = tries(&joblog);
    let again: Vec<&str> = all[4..]
        .iter()
        .map(|t| t.5.rsplit("# ").next().unwrap())
        .collect();
    let mut again = again;
    again.sort();
    assert_eq!(again, ["frames-0-to-1", "frames-6-to-7"]);
    // The job numbers go on from the first run's.
    let mut seqs: Vec<usize> = all.iter().map(|t| t.0).collect();
    seqs.sort();
    seqs.dedup();
    assert_eq!(seqs.len(), all.len(), "{all:?}");
    // Nothing of farm's own is left in the folder but the frames and the job log.
    let mut names: Vec<String> = std::fs::read_dir(&out_dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names.len(), 9, "{names:?}");
}

#[test]
fn resume_without_a_job_log_renders_everything_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let ssh = fake_ssh(dir.path());
    let pattern = format!("{}/out/f%d.ppm", dir.path().display());
    let out = farm_run(
        &ssh,
        &["--hosts", "a", "-o", &pattern, "--resume", "-"],
        "",
        3,
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(
        text(&out.stderr),
        format!(
            "farm: --resume: no job log {}/out/farm.joblog: every chunk is rendered\n",
            dir.path().display()
        )
    );
    for k in 0..3u8 {
        let f = dir.path().join(format!("out/f{k}.ppm"));
        assert_eq!(std::fs::read(f).unwrap(), ppm(k));
    }
}

#[test]
fn an_output_folder_that_cannot_be_made_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let ssh = fake_ssh(dir.path());
    std::fs::write(dir.path().join("file"), "").unwrap();
    let pattern = format!("{}/file/sub/f%d.ppm", dir.path().display());
    let out = farm_run(&ssh, &["--hosts", "a", "-o", &pattern, "-"], "", 1);
    assert_eq!(out.status.code(), Some(3));
    assert_eq!(
        text(&out.stderr),
        format!(
            "farm: cannot make -o's folder {}/file/sub: Not a directory\n",
            dir.path().display()
        )
    );
}

#[test]
fn a_hosts_choice_of_depth_is_said_once() {
    let dir = tempfile::tempdir().unwrap();
    let ssh = fake_ssh(dir.path());
    let say =
        "printf 'render: depth auto chose 2 (a reason)\\n@stats render depth_auto=2\\n' >&2; ";
    let out = farm_run(&ssh, &["--hosts", "a", "--chunk", "1", "-"], say, 3);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(out.stdout, reds(3));
    assert_eq!(
        text(&out.stderr),
        "host a: depth auto chose 2 (a reason)\n@stats render depth_auto=2 host=a\n"
    );
}

#[test]
fn garbage_from_a_host_is_named_as_garbage() {
    let dir = tempfile::tempdir().unwrap();
    let ssh = fake_ssh_with(
        dir.path(),
        "noisy) shift; [ \"$1\" = -- ] && shift; sh -c \"$*\" >/dev/null; echo hello; exit 0 ;;",
    );
    let out = farm_run(&ssh, &["--hosts", "noisy", "--retries", "1", "-"], "", 2);
    assert_eq!(out.status.code(), Some(3));
    let err = text(&out.stderr);
    assert!(
        err.ends_with(&format!(
            "farm: host noisy: frames 0 to 1, 1 try: sent back 0 of its frames 0 to 1, then \
             garbage (not a frame: {}\n",
            err.rsplit("not a frame: ").next().unwrap().trim_end()
        )) && err.lines().count() == 2,
        "{err}"
    );
}

#[test]
fn the_slurm_check_names_frames_by_the_movies_numbers_and_the_tasks_to_submit_again() {
    // Frames 100 to 105 in tasks of two: 101 missing, 102 cut, 105 a folder.
    let dir = tempfile::tempdir().unwrap();
    let movie_file = dir.path().join("movie.pp");
    std::fs::write(&movie_file, movie(6)).unwrap();
    let array = dir.path().join("it's an array");
    let pattern = format!("{}/f%d.ppm", array.display());
    let farm = |extra: &[&str]| {
        let mut cmd = Command::new(pipeline_tests::bin("farm"));
        cmd.arg("--slurm-array")
            .arg(&array)
            .args(["--chunk", "2", "-o", &pattern, "--first-frame", "100"])
            .arg(&movie_file)
            .args(extra);
        cmd.output().unwrap()
    };
    let made = farm(&["--", "true"]);
    assert!(made.status.success(), "{}", text(&made.stderr));
    for k in [100, 103, 104] {
        std::fs::write(array.join(format!("f{k}.ppm")), ppm(k as u8)).unwrap();
    }
    std::fs::write(array.join("f102.ppm"), b"P6\n1 1\n255\n\x01").unwrap();
    std::fs::create_dir(array.join("f105.ppm")).unwrap();
    let out = farm(&["--check"]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    let a = array.display();
    let said = text(&out.stdout);
    let lines: Vec<&str> = said.lines().collect();
    assert_eq!(lines.len(), 4, "{said}");
    assert_eq!(lines[0], format!("frame 101 ({a}/f101.ppm): missing"));
    assert!(lines[1].starts_with(&format!("frame 102 ({a}/f102.ppm): cut or damaged: ")));
    assert_eq!(lines[2], format!("frame 105 ({a}/f105.ppm): not a file"));
    assert_eq!(
        lines[3],
        format!(
            "sbatch --array=0,1,2 '{}/render.sbatch'",
            a.to_string().replace('\'', r"'\''")
        )
    );
    assert_eq!(
        text(&out.stderr),
        "farm: 3 of 6 frames missing or bad, of array tasks 0,1,2: the line above submits \
         them again\n"
    );
    // The script's --check is this check.
    let by_script = std::process::Command::new("bash")
        .arg(array.join("render.sbatch"))
        .arg("--check")
        .output()
        .unwrap();
    assert_eq!(by_script.status.code(), Some(1));
    assert_eq!(by_script.stdout, out.stdout);
}
