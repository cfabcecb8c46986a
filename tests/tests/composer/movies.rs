//! Movies on engines people already run: `render.sh --by frames` on GNU parallel (farm),
//! with a stand-in for ssh (`POLYPIPE_SSH`: a script that takes ssh's options and a host,
//! then runs the command here), and as a Slurm job array run task by task here.
//!
//! A chunk that fails on a host is retried on another and the frames are a local run's
//! bytes; a chunk that fails on every try ends the run with status 3, the host and the
//! chunk named, the frames before it written whole and nothing else; `--resume` after a
//! run stopped with SIGINT renders only the chunks the job log does not call finished;
//! the sbatch script's tasks write a local run's files. The movies are small (32×32, 60
//! frames of 20 polygons) so that the file runs in seconds.

use pipeline_tests::{bin, bin_dir, repo_root, sh};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

/// The bytes of one 32×32 frame as zbuf writes it.
const FRAME: usize = 13 + 32 * 32 * 3;

/// A fake ssh in `dir`: skips ssh's options, takes the host, runs the command with sh.
/// `rule` is shell run first, with `$host` and `$PARALLEL_SEQ` (the chunk's job number)
/// set, that may fail the try (as ssh fails, status 255).
fn fake_ssh(dir: &Path, name: &str, rule: &str) -> PathBuf {
    let path = dir.join(name);
    let script = format!(
        "#!/bin/sh\n\
         while [ $# -gt 0 ]; do case $1 in -[oplSOiF]) shift 2 ;; -*) shift ;; *) break ;; esac; done\n\
         host=$1; shift\n\
         [ \"${{1-}}\" = -- ] && shift\n\
         {rule}\n\
         exec sh -c \"$*\"\n"
    );
    std::fs::write(&path, script).unwrap();
    let status = Command::new("chmod").arg("+x").arg(&path).status().unwrap();
    assert!(status.success());
    path
}

/// The movie: 60 frames of a 20-polygon environment, in `dir`.
fn movie(dir: &Path) -> PathBuf {
    let path = dir.join("movie.pp");
    let out = Command::new(bin("scene"))
        .args(["environment", "--frames", "60", "--polygons", "20"])
        .args(["--size", "32x32"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::write(&path, out.stdout).unwrap();
    path
}

/// render.sh's options for every run here.
const OPTIONS: &str = "--size 32x32 --depth 0";

/// The movie rendered here by render.sh, with `extra` options.
fn local(movie: &Path, extra: &str) -> Vec<u8> {
    let out = sh(
        &format!("scripts/render.sh {OPTIONS} {extra} '{}'", movie.display()),
        b"",
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// `render.sh --by frames ARGS… OPTIONS MOVIE` with `ssh` as POLYPIPE_SSH.
fn farm_cmd(ssh: &Path, args: &[&str], movie: &Path) -> Command {
    bin_dir();
    let mut cmd = Command::new("bash");
    cmd.arg(repo_root().join("scripts/render.sh"))
        .args(["--by", "frames"])
        .args(args)
        .args(OPTIONS.split(' '))
        .arg(movie)
        .current_dir(repo_root())
        .env("POLYPIPE_SSH", ssh)
        .env("POLYPIPE_LOAD", "0")
        .env_remove("POLYPIPE_BIN");
    cmd
}

fn farm(ssh: &Path, args: &[&str], movie: &Path) -> Output {
    output_within(farm_cmd(ssh, args, movie))
}

/// The command's output, or a failed test when it has not ended within two minutes (a
/// run whose GNU parallel waits forever for an argument hangs rather than fails).
fn output_within(mut cmd: Command) -> Output {
    use std::io::Read;
    let mut child = cmd
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut out = child.stdout.take().unwrap();
    let mut err = child.stderr.take().unwrap();
    let out = std::thread::spawn(move || {
        let mut v = Vec::new();
        out.read_to_end(&mut v).map(|_| v)
    });
    let err = std::thread::spawn(move || {
        let mut v = Vec::new();
        err.read_to_end(&mut v).map(|_| v)
    });
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > Duration::from_secs(120) {
            let _ = Command::new("kill")
                .args(["-TERM", &child.id().to_string()])
                .status();
            panic!("the run has not ended in 120 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    Output {
        status,
        stdout: out.join().unwrap().unwrap(),
        stderr: err.join().unwrap().unwrap(),
    }
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A job log's lines after its header: (job number, host, exit status, the first frame
/// of its chunk: `None` for an idle job).
fn joblog(path: &Path) -> Vec<(usize, String, i32, Option<usize>)> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("Seq\tHost\tStarttime\tJobRuntime\tSend\tReceive\tExitval\tSignal\tCommand")
    );
    lines
        .map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            // parallel's lines end `# frames-A-to-B` (or `# frame-A`, `# idle`); the
            // failed tries' lines farm writes end `farm: frames A to B, a failed try …`.
            let first = f[8]
                .rsplit_once("frames")
                .or_else(|| f[8].rsplit_once("frame"))
                .and_then(|(_, r)| {
                    r.trim_start_matches(['-', ' '])
                        .split(['-', ' ', ','])
                        .next()?
                        .parse()
                        .ok()
                });
            (
                f[0].parse().unwrap(),
                f[1].to_string(),
                f[6].parse().unwrap(),
                first,
            )
        })
        .collect()
}

/// A fake ssh's rule that appends to `record` how many chunks the spool in `tmp` holds as
/// a chunk starts: their streams (`K.in`) and frames held for their turn (`K.held`).
fn count_spool(tmp: &Path, record: &Path) -> String {
    format!(
        "ls '{}'/farm.*/ | grep -cE '\\.(in|held)$' >> '{}'",
        tmp.display(),
        record.display()
    )
}

/// The counts `count_spool` recorded.
fn counts(record: &Path) -> Vec<usize> {
    std::fs::read_to_string(record)
        .unwrap()
        .lines()
        .map(|l| l.trim().parse().unwrap())
        .collect()
}

/// The files of `dir` whose names end `.png`, by name, with their bytes.
fn pngs(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().ends_with(".png"))
        .map(|e| {
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect();
    files.sort();
    files
}

#[test]
fn a_chunk_that_fails_on_flaky_is_retried_on_good_and_the_frames_are_a_local_runs() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().display();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir_all(&tmp).unwrap();
    let record = dir.path().join("in-spool");
    // flaky fails every job's first try (it leaves a mark for each it failed).
    let ssh = fake_ssh(
        dir.path(),
        "ssh",
        &format!(
            "{}; if [ \"$host\" = flaky ] && [ ! -e '{d}/failed.'$PARALLEL_SEQ ]; then \
             : > '{d}/failed.'$PARALLEL_SEQ; \
             echo 'ssh: connect to host flaky port 22: Connection refused' >&2; exit 255; fi",
            count_spool(&tmp, &record)
        ),
    );
    let m = movie(dir.path());
    let want = local(&m, "");
    assert_eq!(want.len(), 60 * FRAME);
    let log = dir.path().join("jobs");
    let log_arg = log.display().to_string();
    let mut cmd = farm_cmd(
        &ssh,
        &[
            "--hosts",
            "good,flaky",
            "--chunk",
            "8",
            "--joblog",
            &log_arg,
            "--stats",
        ],
        &m,
    );
    cmd.env("TMPDIR", &tmp);
    let out = output_within(cmd);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(out.stdout == want, "the frames differ from a local run's");
    // Two job slots: four chunks in the spool at most, while chunks wait for good.
    let seen = counts(&record);
    assert!(seen.iter().all(|&n| n <= 4), "{seen:?}");

    // The log: each chunk flaky tried has its failed try (255 on flaky) and then its
    // success on good; every chunk of the 8 succeeded once. A job is known by its
    // number, a chunk by its first frame (idle jobs take numbers too).
    let lines = joblog(&log);
    let failed_here: BTreeSet<usize> = lines
        .iter()
        .map(|l| l.0)
        .filter(|k| dir.path().join(format!("failed.{k}")).exists())
        .collect();
    assert!(!failed_here.is_empty(), "flaky was never tried: {lines:?}");
    let failed_in_log: BTreeSet<usize> = lines
        .iter()
        .filter(|l| l.1 == "flaky" && l.2 == 255)
        .map(|l| l.0)
        .collect();
    assert_eq!(failed_in_log, failed_here, "{lines:?}");
    let ok: Vec<usize> = {
        let mut v: Vec<usize> = lines
            .iter()
            .filter(|l| l.2 == 0)
            .filter_map(|l| l.3)
            .collect();
        v.sort();
        v
    };
    assert_eq!(ok, (0..8).map(|k| 8 * k).collect::<Vec<_>>(), "{lines:?}");
    // The frames of the chunks flaky failed, each then rendered on good.
    let failed_frames: BTreeSet<usize> = lines
        .iter()
        .filter(|l| l.1 == "flaky" && l.2 == 255)
        .map(|l| l.3.unwrap())
        .collect();
    for f in &failed_frames {
        assert!(
            lines
                .iter()
                .any(|l| l.1 == "good" && l.2 == 0 && l.3 == Some(*f)),
            "the chunk of frame {f} retried on good: {lines:?}"
        );
    }
    // --stats says so too, a line a failed try.
    let err = stderr(&out);
    let farm = stagecli::stats::records_of(&err, "farm").unwrap();
    let retried: BTreeSet<usize> = farm
        .iter()
        .filter(|r| r.get("host") == Some("flaky") && r.count("failed_status") == Some(255))
        .filter_map(|r| r.count("first_frame"))
        .map(|f| f as usize)
        .collect();
    assert_eq!(retried, failed_frames, "{err}");
    assert!(
        farm.iter()
            .any(|r| r.get("host") == Some("good") && r.count("chunks").is_some()),
        "{err}"
    );
}

#[test]
fn the_spool_holds_two_chunks_a_job_slot_however_long_the_movie() {
    // 30 chunks of 2 frames over two hosts, one of them slow: the chunks the fast host
    // renders wait in the spool for the slow one's, and no more are cut meanwhile.
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir_all(&tmp).unwrap();
    let record = dir.path().join("in-spool");
    let ssh = fake_ssh(
        dir.path(),
        "ssh",
        &format!(
            "{}; [ \"$host\" = slow ] && sleep 0.3",
            count_spool(&tmp, &record)
        ),
    );
    let m = movie(dir.path());
    let want = local(&m, "");
    let mut cmd = farm_cmd(&ssh, &["--hosts", "fast,slow", "--chunk", "2"], &m);
    cmd.env("TMPDIR", &tmp);
    let out = output_within(cmd);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(out.stdout == want, "the frames differ from a local run's");
    let seen = counts(&record);
    assert_eq!(seen.len(), 30, "a count a chunk: {seen:?}");
    assert!(seen.iter().all(|&n| (1..=4).contains(&n)), "{seen:?}");
    // The spool is gone with the run.
    assert_eq!(std::fs::read_dir(&tmp).unwrap().count(), 0);
}

#[test]
fn a_chunk_that_fails_every_try_names_the_host_and_the_frames_before_it_are_whole() {
    let dir = tempfile::tempdir().unwrap();
    // broken renders the first two chunks, then refuses every connection.
    let ssh = fake_ssh(
        dir.path(),
        "ssh",
        "if [ \"$host\" = broken ] && [ \"${PARALLEL_SEQ:-0}\" -ge 3 ]; then \
         echo 'ssh: connect to host broken port 22: Connection refused' >&2; exit 255; fi",
    );
    let m = movie(dir.path());
    let want = local(&m, "");
    let out = farm(&ssh, &["--hosts", "broken", "--chunk", "8"], &m);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    assert_eq!(
        stderr(&out),
        "farm: host broken: a try of frames 16 to 23 failed: ssh: connect to host broken \
         port 22: Connection refused\nfarm: host broken: frames 16 to 23, 3 tries: ssh: \
         connect to host broken port 22: Connection refused\n"
    );
    assert!(
        out.stdout == want[..16 * FRAME],
        "not the movie's first 16 frames, whole: {} bytes",
        out.stdout.len()
    );

    // A host that fails from the start, and no other: nothing written.
    let down = fake_ssh(
        dir.path(),
        "down",
        "echo 'ssh: connect to host down port 22: No route to host' >&2; exit 255",
    );
    let out = farm(&down, &["--hosts", "down", "--retries", "2"], &m);
    assert_eq!(out.status.code(), Some(3));
    assert_eq!(
        stderr(&out),
        "farm: host down: a try of frames 0 to 7 failed: ssh: connect to host down port \
         22: No route to host\nfarm: host down: frames 0 to 7, 2 tries: ssh: connect to host \
         down port 22: No route to host\n"
    );
    assert!(out.stdout.is_empty());
}

#[test]
fn a_chunk_that_fails_its_last_try_while_another_runs_is_the_one_named() {
    // Three hosts. The first chunk is slow wherever it runs; the second fails wherever it
    // runs (its hosts recorded). It fails its second and last try while the first is
    // still rendering: --halt soon starts nothing more, the first chunk ends and is
    // written, and the line names the second chunk and its two hosts.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().display();
    let ssh = fake_ssh(
        dir.path(),
        "ssh",
        &format!(
            "case ${{PARALLEL_SEQ:-0}} in \
             1) echo \"$host\" > '{d}/host.1'; sleep 2 ;; \
             2) echo \"$host\" >> '{d}/host.2'; \
             echo \"ssh: connect to host $host port 22: Connection refused\" >&2; exit 255 ;; \
             esac"
        ),
    );
    let m = movie(dir.path());
    let want = local(&m, "");
    let out = farm(
        &ssh,
        &["--hosts", "a,b,c", "--chunk", "8", "--retries", "2"],
        &m,
    );
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    let read = |f: &str| std::fs::read_to_string(dir.path().join(f)).unwrap();
    let first = read("host.1");
    let tried: Vec<String> = read("host.2").lines().map(String::from).collect();
    assert_eq!(tried.len(), 2, "{tried:?}");
    assert!(
        !tried.contains(&first.trim().to_string()),
        "{tried:?} {first}"
    );
    assert_eq!(
        stderr(&out),
        format!(
            "farm: host {a}: a try of frames 8 to 15 failed: ssh: connect to host {a} port \
             22: Connection refused\nfarm: host {b}: a try of frames 8 to 15 failed: ssh: \
             connect to host {b} port 22: Connection refused\nfarm: hosts {a}, {b}: frames 8 \
             to 15, 2 tries, the last on {b}: ssh: connect to host {b} port 22: Connection \
             refused\n",
            a = tried[0],
            b = tried[1],
        )
    );
    assert!(
        out.stdout == want[..8 * FRAME],
        "not the movie's first 8 frames, whole: {} bytes",
        out.stdout.len()
    );
}

#[test]
fn resume_after_sigint_renders_only_the_missing_chunks() {
    let dir = tempfile::tempdir().unwrap();
    let ssh = fake_ssh(dir.path(), "ssh", "sleep 0.3");
    let m = movie(dir.path());
    let here = dir.path().join("here");
    let there = dir.path().join("there");
    std::fs::create_dir_all(&here).unwrap();
    std::fs::create_dir_all(&there).unwrap();
    local(&m, &format!("-o '{}/f%05d.png'", here.display()));
    let want = pngs(&here);
    assert_eq!(want.len(), 60);

    let pattern = format!("{}/f%05d.png", there.display());
    let args = ["--hosts", "a", "--chunk", "8", "-o", &pattern];
    let log = there.join("farm.joblog"); // beside -o's files by default
    let child = farm_cmd(&ssh, &args, &m)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Stopped once three chunks are done.
    let start = Instant::now();
    loop {
        let done = std::fs::read_to_string(&log)
            .map(|t| {
                t.lines()
                    .filter(|l| l.split('\t').nth(6) == Some("0") && !l.ends_with("# idle"))
                    .count()
            })
            .unwrap_or(0);
        if done >= 3 {
            break;
        }
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no three chunks in 60 s"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let sent = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(130), "{}", stderr(&out));
    // The chunks finished, from 1, by their first frames.
    let before: BTreeSet<usize> = joblog(&log)
        .into_iter()
        .filter(|l| l.2 == 0)
        .filter_map(|l| Some(l.3? / 8 + 1))
        .collect();
    assert!(
        before.len() >= 3 && before.len() < 8,
        "stopped halfway: {before:?}"
    );
    let lines_before = joblog(&log).len();
    // The files written are the finished chunks' frames, no others.
    let names: BTreeSet<String> = pngs(&there).into_iter().map(|(n, _)| n).collect();
    let finished: BTreeSet<String> = before
        .iter()
        .flat_map(|k| (8 * (k - 1)..(8 * k).min(60)).map(|f| format!("f{f:05}.png")))
        .collect();
    assert_eq!(names, finished);

    let mut resume = args.to_vec();
    resume.push("--resume");
    let out = farm(&ssh, &resume, &m);
    assert!(out.status.success(), "{}", stderr(&out));
    // The log's new lines: the missing chunks, each once.
    let new: Vec<usize> = joblog(&log)[lines_before..]
        .iter()
        .filter_map(|l| Some(l.3? / 8 + 1))
        .collect();
    let missing: Vec<usize> = (1..=8).filter(|k| !before.contains(k)).collect();
    let mut sorted = new.clone();
    sorted.sort();
    assert_eq!(sorted, missing, "the resumed run's jobs: {new:?}");
    assert!(pngs(&there) == want, "the frames differ from a local run's");
}

#[test]
fn the_slurm_arrays_tasks_run_here_give_a_local_runs_frames() {
    let dir = tempfile::tempdir().unwrap();
    let m = movie(dir.path());
    let here = dir.path().join("here");
    std::fs::create_dir_all(&here).unwrap();
    local(&m, &format!("-o '{}/f%05d.png'", here.display()));
    let array = dir.path().join("array");
    let pattern = format!("{}/f%05d.png", array.display());
    let unused = dir.path().join("no-ssh-needed");
    let out = farm(
        &unused,
        &[
            "--slurm-array",
            &array.display().to_string(),
            "--chunk",
            "16",
            "-o",
            &pattern,
        ],
        &m,
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let script = array.join("render.sbatch");
    let text = std::fs::read_to_string(&script).unwrap();
    assert!(text.contains("#SBATCH --array=0-3\n"), "{text}");
    // Before any task: the check says what is missing.
    let check = Command::new("bash")
        .arg(&script)
        .arg("--check")
        .output()
        .unwrap();
    assert_eq!(check.status.code(), Some(1));
    assert_eq!(
        stderr(&check),
        "farm: 60 of 60 frames missing or bad, of array tasks 0,1,2,3: the line above \
         submits them again\n"
    );
    let said = String::from_utf8_lossy(&check.stdout).into_owned();
    assert_eq!(
        said.lines().next().unwrap(),
        format!("frame 0 ({}/f00000.png): missing", array.display())
    );
    assert_eq!(
        said.lines().last().unwrap(),
        format!("sbatch --array=0,1,2,3 '{}'", script.display())
    );
    for k in 0..4 {
        let task = Command::new("bash")
            .arg(&script)
            .env("SLURM_ARRAY_TASK_ID", k.to_string())
            .output()
            .unwrap();
        assert!(task.status.success(), "task {k}: {}", stderr(&task));
    }
    let check = Command::new("bash")
        .arg(&script)
        .arg("--check")
        .output()
        .unwrap();
    assert!(check.status.success(), "{}", stderr(&check));
    assert_eq!(
        String::from_utf8_lossy(&check.stdout),
        "all 60 frames there, whole\n"
    );
    assert!(
        pngs(&array) == pngs(&here),
        "the tasks' frames differ from a local run's"
    );
}

#[test]
fn without_parallel_the_run_says_to_install_it() {
    let dir = tempfile::tempdir().unwrap();
    let ssh = fake_ssh(dir.path(), "ssh", "");
    let m = movie(dir.path());
    let out = Command::new(bin("farm"))
        .args(["--hosts", "a"])
        .arg(&m)
        .args(["--", "true"])
        .env("PATH", dir.path()) // a PATH with no parallel on it
        .env("POLYPIPE_SSH", &ssh)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(3));
    assert_eq!(
        stderr(&out),
        "farm: --by frames runs on GNU parallel, and there is no parallel on PATH: install \
         it (Debian and Ubuntu: apt install parallel)\n"
    );
}

#[test]
fn a_blank_polypipe_ssh_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    let m = movie(dir.path());
    let out = farm(Path::new(" "), &["--hosts", "a"], &m);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        stderr(&out),
        "render: POLYPIPE_SSH is set but blank: set it to the command that reaches a host \
         (say 'ssh -p 2222'), or unset it for ssh\n"
    );
    // farm says the same of itself.
    let out = Command::new(bin("farm"))
        .args(["--hosts", "a"])
        .arg(&m)
        .args(["--", "true"])
        .env("POLYPIPE_SSH", "")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).starts_with("farm: POLYPIPE_SSH is set but blank"));
}

#[test]
fn hosts_from_an_sshloginfile_write_files_numbered_from_first_frame() {
    // parallel's own file: a comment, 2 job slots on one host, 1 on another. -o with
    // --first-frame 100: frame k of the movie in f(100 + k).ppm, a local run's bytes.
    let dir = tempfile::tempdir().unwrap();
    let ssh = fake_ssh(dir.path(), "ssh", "");
    let m = movie(dir.path());
    let want = local(&m, "");
    let logins = dir.path().join("hosts");
    std::fs::write(&logins, "# two hosts\n2/alpha\n1/beta\n").unwrap();
    let out_dir = dir.path().join("out");
    std::fs::create_dir_all(&out_dir).unwrap();
    let pattern = format!("{}/f%05d.ppm", out_dir.display());
    let logins_arg = logins.display().to_string();
    let args = [
        "--sshloginfile",
        &logins_arg,
        "--chunk",
        "7",
        "-o",
        &pattern,
        "--first-frame",
        "100",
    ];
    let out = farm(&ssh, &args, &m);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(out.stdout.is_empty());
    for k in 0..60 {
        let file = out_dir.join(format!("f{:05}.ppm", 100 + k));
        let bytes = std::fs::read(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        assert!(bytes == want[k * FRAME..(k + 1) * FRAME], "frame {k}");
    }
    // The job log beside the files: 9 chunks (8 of 7 frames and one of 4), all done.
    let lines = joblog(&out_dir.join("farm.joblog"));
    let mut done: Vec<usize> = lines
        .iter()
        .filter(|l| l.2 == 0)
        .filter_map(|l| l.3)
        .collect();
    done.sort();
    assert_eq!(done, (0..9).map(|k| 7 * k).collect::<Vec<_>>());
    assert_eq!(std::fs::read_dir(&out_dir).unwrap().count(), 61);
}
