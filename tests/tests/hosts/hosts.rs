//! Rendering on other hosts: `render.sh --hosts … --by frames`, which the `farm` binary
//! does, and `--by leaves`, over OpenSSH to sshd servers the tests start on loopback
//! addresses (`pipeline_tests::hosts`).
//!
//! A movie cut into chunks across hosts (by GNU parallel) comes back byte for byte as a
//! local render.sh writes it, the first frames before the last host is done, with no more
//! than the movie's stream and a few chunks' frames in the spool here; each host's sshd
//! log shows its sessions. A chunk a host fails (cannot be reached, refuses the command or
//! the login) is retried on another, and the frames are a local run's; with that host
//! alone, or one try (`--retries 1`) when a host drops mid-run, the run ends with the host
//! and the chunk named, the status given, within seconds, the frames finished before
//! written whole, and no process, temporary file or named pipe left here or on the hosts.
//!
//! Where sshd is not installed, each test says so and returns (skipped, not failed);
//! under `CI=true` it fails instead (`pipeline_tests::hosts::Hosts::start`).

use pipeline_tests::hosts::{self, Host, Hosts};
use pipeline_tests::{bin, bin_dir, output_with_stdin, repo_root, sh};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The bytes of one frame as zbuf writes it: `P6\nW H\n255\n` and W·H RGB pixels.
fn frame_bytes(w: usize, h: usize) -> usize {
    format!("P6\n{w} {h}\n255\n").len() + w * h * 3
}

/// Writes `scene ARGS` to `dir/name` and returns the path.
fn scene_file(dir: &Path, name: &str, args: &[&str]) -> PathBuf {
    let out = Command::new(bin("scene"))
        .args(args)
        .output()
        .expect("run scene");
    assert!(
        out.status.success(),
        "scene {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let path = dir.join(name);
    std::fs::write(&path, out.stdout).expect("write the scene");
    path
}

/// A folder for the run's TMPDIR, to see that nothing is left in it.
fn local_tmp(hosts: &Hosts) -> PathBuf {
    let dir = hosts.dir().join("local-tmp");
    std::fs::create_dir_all(&dir).expect("a local TMPDIR");
    dir
}

/// `scripts/render.sh ARGS` (which hands `--hosts … --by frames` to farm) reaching
/// `hosts`, with TMPDIR `tmp`.
fn render_frames_cmd(hosts: &Hosts, tmp: &Path, args: &[&str]) -> Command {
    bin_dir(); // the binaries built and current before the script looks at them
    let mut cmd = Command::new("bash");
    cmd.arg(repo_root().join("scripts/render.sh")).args(args);
    if !args.contains(&"--by") {
        cmd.args(["--by", "frames"]);
    }
    cmd.current_dir(repo_root())
        .env("POLYPIPE_SSH", hosts.ssh())
        .env("TMPDIR", tmp)
        .env_remove("POLYPIPE_BIN");
    cmd
}

fn render_frames(hosts: &Hosts, tmp: &Path, args: &[&str], stdin: &[u8]) -> (Output, Duration) {
    let start = Instant::now();
    let out = output_with_stdin(render_frames_cmd(hosts, tmp, args), stdin);
    (out, start.elapsed())
}

/// The same movie rendered here by render.sh.
fn render_locally(args: &str) -> Vec<u8> {
    let out = sh(&format!("scripts/render.sh {args}"), b"");
    assert!(
        out.status.success(),
        "local render.sh {args}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The last line of the run's stderr: its one-line message.
fn last_line(out: &Output) -> String {
    stderr(out).lines().last().unwrap_or("").to_string()
}

/// Asserts that nothing of a run is left. Here, at once: farm stops and reaps its ssh
/// processes before it exits, and leaves nothing in the local TMPDIR. The run's processes
/// here are those with its TMPDIR in their environment or its ssh_config on their command
/// line (a farm of another test, run beside this one, is not this run's). On the hosts:
/// no session process under any host's sshd, no render.sh or stage process, nothing in
/// any host's TMPDIR. A remote render.sh stops when its ssh goes (its input ends, its
/// output has no reader), which takes it a moment: well under a second idle, and it is
/// given 30 s, the bound of one that does not stop, not of a loaded machine's scheduling.
fn assert_nothing_left(hosts: &Hosts, n_hosts: usize, tmp: &Path) {
    let mut here =
        hosts::processes_matching(&[], &[hosts.dir().join("ssh_config").display().to_string()]);
    here.extend(hosts::processes_with_env("TMPDIR", tmp));
    here.sort();
    here.dedup();
    assert!(
        here.is_empty(),
        "left running here after the run: {here:#?}"
    );
    let files: Vec<_> = std::fs::read_dir(tmp)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .collect();
    assert!(files.is_empty(), "left in the local TMPDIR: {files:#?}");

    let stages: Vec<PathBuf> = [
        "viewxf",
        "clipplane",
        "splitter",
        "persp",
        "scanconv",
        "zbuf",
    ]
    .iter()
    .map(|p| bin(p))
    .collect();
    let render = vec![repo_root().join("scripts/render.sh").display().to_string()];
    let deadline = Instant::now() + Duration::from_secs(30);
    loop {
        let mut left = hosts::processes_matching(&stages, &render);
        for i in 0..n_hosts {
            left.extend(hosts.session_processes(i));
        }
        let mut files = Vec::new();
        for i in 0..n_hosts {
            for entry in std::fs::read_dir(hosts.remote_tmp(i)).unwrap().flatten() {
                files.push(entry.path().display().to_string());
            }
        }
        if left.is_empty() && files.is_empty() {
            return;
        }
        assert!(
            Instant::now() < deadline,
            "left on the hosts 30 s after the run:\nprocesses: {left:#?}\nfiles: {files:#?}"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[test]
fn frames_on_two_hosts_are_a_local_runs_bytes() {
    let _serial = hosts::serial();
    let Some(hosts) = Hosts::start(&[Host::Serving, Host::Serving]) else {
        return;
    };
    let tmp = local_tmp(&hosts);
    let movie = scene_file(hosts.dir(), "spheres.pp", &["spheres", "--frames", "12"]);
    let m = movie.display().to_string();
    let local = render_locally(&format!("--size 64x64 {m}"));
    assert_eq!(local.len(), 12 * frame_bytes(64, 64));

    let (out, _) = render_frames(
        &hosts,
        &tmp,
        &["--hosts", "node1,node2", "--size", "64x64", &m],
        b"",
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        out.stdout == local,
        "the frames from two hosts differ from a local run's"
    );
    assert_eq!(stderr(&out), "", "a run without --stats says nothing");
    for i in 0..2 {
        assert_eq!(
            hosts.sessions(i),
            1,
            "{}'s sshd log:\n{}",
            hosts.name(i),
            hosts.log(i)
        );
        assert!(
            hosts.log(i).contains("Accepted publickey for"),
            "{}",
            hosts.log(i)
        );
    }
    assert_nothing_left(&hosts, 2, &tmp);
}

/// The peak resident memory of process `pid` so far (VmHWM), in bytes.
fn peak_memory(pid: u32) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// The bytes of the files under `dir`, at any depth.
fn bytes_under(dir: &Path) -> u64 {
    let mut total = 0;
    for entry in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let Ok(meta) = entry.metadata() else { continue };
        if meta.is_dir() {
            total += bytes_under(&entry.path());
        } else {
            total += meta.len();
        }
    }
    total
}

#[test]
fn frames_stream_back_before_the_last_host_is_done_with_the_spool_bounded() {
    // 96 frames of 256x256 (19 MB of frames) in chunks of 4 over two hosts: 24 sessions.
    // The first frame is written while chunks are still to be sent; the local TMPDIR
    // holds farm's spool, never the movie's frames; a host's TMPDIR holds at most its
    // chunk's private folder;
    // farm's memory stays far below the movie's frames (two chunks a host: 16 frames,
    // 3 MB).
    let _serial = hosts::serial();
    let Some(hosts) = Hosts::start(&[Host::Serving, Host::Serving]) else {
        return;
    };
    let tmp = local_tmp(&hosts);
    let movie = scene_file(
        hosts.dir(),
        "env.pp",
        &[
            "environment",
            "--frames",
            "96",
            "--polygons",
            "100",
            "--size",
            "256x256",
        ],
    );
    let m = movie.display().to_string();
    let mut cmd = render_frames_cmd(
        &hosts,
        &tmp,
        &[
            "--hosts",
            "node1,node2",
            "--size",
            "256x256",
            "--depth",
            "0",
            "--chunk",
            "4",
            &m,
        ],
    );
    let started = Instant::now();
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start render.sh --by frames");
    let pid = child.id();
    let mut stdout = child.stdout.take().unwrap();
    // The sessions started by the time the first frame is whole, counted by the thread
    // that reads it, at that moment: counted by the loop below, they would be those of
    // whenever a loaded machine next ran the loop.
    let (first_tx, first_rx) = std::sync::mpsc::channel();
    let hosts_at_first = &hosts;
    let (frames, peak, local_disk, remote_disk) = std::thread::scope(|scope| {
        let reader = scope.spawn(move || {
            use std::io::Read;
            let mut all = Vec::new();
            let mut buf = vec![0u8; 1 << 16];
            let mut told = false;
            loop {
                let n = stdout.read(&mut buf).unwrap();
                if n == 0 {
                    break;
                }
                all.extend_from_slice(&buf[..n]);
                if !told && all.len() >= frame_bytes(256, 256) {
                    let _ = first_tx.send(hosts_at_first.sessions(0) + hosts_at_first.sessions(1));
                    told = true;
                }
            }
            all
        });
        let (mut peak, mut local_disk, mut remote_disk) = (0, 0, 0);
        loop {
            peak = peak.max(peak_memory(pid).unwrap_or(0));
            local_disk = local_disk.max(bytes_under(&tmp));
            remote_disk = remote_disk.max(
                (0..2)
                    .map(|i| bytes_under(hosts.remote_tmp(i)))
                    .max()
                    .unwrap(),
            );
            if child.try_wait().unwrap().is_some() {
                break;
            }
            assert!(
                started.elapsed() < Duration::from_secs(120),
                "still running after 120 s"
            );
            std::thread::sleep(Duration::from_millis(2));
        }
        let frames = reader.join().unwrap();
        (frames, peak, local_disk, remote_disk)
    });
    let status = child.wait().unwrap();
    let sessions_at_first = first_rx.try_recv().ok();
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    assert!(status.success(), "{err}");
    assert_eq!(
        frames,
        render_locally(&format!("--size 256x256 --depth 0 {m}"))
    );
    let sessions = hosts.sessions(0) + hosts.sessions(1);
    assert_eq!(sessions, 24, "one session a chunk");
    let at_first = sessions_at_first.expect("the first frame was seen");
    assert!(
        at_first < 24,
        "the first frame came only after all {at_first} sessions had started"
    );
    // farm's spool in the local TMPDIR: two chunks a job slot at most (four here), each
    // its stream (cut as the movie is read) or its frames done before their turn, and
    // the frames of the two chunks coming back (one more while a chunk's frames are
    // taken, under two names for a moment); never the movie's stream or frames.
    let movie_bytes = std::fs::metadata(&movie).unwrap().len();
    let chunk_frames = 4 * frame_bytes(256, 256) as u64;
    let chunk_stream = movie_bytes.div_ceil(24);
    assert!(
        local_disk <= 4 * chunk_stream.max(chunk_frames) + 3 * chunk_frames + (64 << 10),
        "{local_disk} bytes in the local TMPDIR, for chunks of {chunk_stream} bytes in and \
         {chunk_frames} out"
    );
    // A host's render.sh keeps its chunk (4 frames of about 11 KB) to choose... nothing
    // at --depth 0: its folder holds named pipes and its stages' messages.
    assert!(
        remote_disk < 1 << 20,
        "{remote_disk} bytes in a host's TMPDIR"
    );
    let movie_frames = 96 * frame_bytes(256, 256) as u64;
    assert!(
        peak < movie_frames / 2,
        "farm's peak memory {peak} bytes, against {movie_frames} bytes of frames"
    );
    eprintln!(
        "first frame with {at_first} of 24 sessions started; farm's peak memory {} MB and \
         spool {} KB for {} MB of frames",
        peak >> 20,
        local_disk >> 10,
        movie_frames >> 20
    );
    assert_nothing_left(&hosts, 2, &tmp);
}

#[test]
fn uneven_chunks_from_stdin_at_depth_2_with_a_camera() {
    // 7 frames over 3 hosts in chunks of 2: 2, 2, 2 and 1 frames, four sessions; the
    // scene from stdin; each host runs a depth-2 tree and a camera of its own options.
    let _serial = hosts::serial();
    let Some(hosts) = Hosts::start(&[Host::Serving, Host::Serving, Host::Serving]) else {
        return;
    };
    let tmp = local_tmp(&hosts);
    let movie = scene_file(hosts.dir(), "spheres.pp", &["spheres", "--frames", "7"]);
    let m = movie.display().to_string();
    let opts = "--size 48x40 --depth 2 --eye 6,4,20";
    let local = render_locally(&format!("{opts} {m}"));
    let args: Vec<&str> = [
        "--hosts",
        "node1,node2,node3",
        "--by",
        "frames",
        "--chunk",
        "2",
    ]
    .into_iter()
    .chain(opts.split(' '))
    .chain(["-"])
    .collect();
    let stdin = std::fs::read(&movie).unwrap();
    let (out, _) = render_frames(&hosts, &tmp, &args, &stdin);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        out.stdout == local,
        "the frames from three hosts differ from a local run's"
    );
    let sessions: Vec<usize> = (0..3).map(|i| hosts.sessions(i)).collect();
    assert_eq!(sessions.iter().sum::<usize>(), 4, "{sessions:?}");
    assert!(sessions.iter().all(|&n| n >= 1), "{sessions:?}");
    assert_nothing_left(&hosts, 3, &tmp);
}

#[test]
fn stats_give_each_hosts_frames_and_the_bytes_each_way() {
    // Three frames in chunks of one, four hosts (node3 named twice): the last gets none;
    // the bytes sent are each cut's, the bytes received one frame's.
    let _serial = hosts::serial();
    let Some(hosts) = Hosts::start(&[Host::Serving, Host::Serving, Host::Serving]) else {
        return;
    };
    let tmp = local_tmp(&hosts);
    let movie = scene_file(hosts.dir(), "two.pp", &["spheres", "--frames", "3"]);
    let m = movie.display().to_string();
    let cut = |a: &str, b: &str| {
        let out = Command::new(bin("frames"))
            .args(["--from", a, "--to", b, &m])
            .output()
            .unwrap();
        assert!(out.status.success());
        out.stdout.len()
    };
    let (out, _) = render_frames(
        &hosts,
        &tmp,
        &[
            "--hosts",
            "node1,node2,node3,node3",
            "--size",
            "32x32",
            "--chunk",
            "1",
            "--stats",
            &m,
        ],
        b"",
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(out.stdout == render_locally(&format!("--size 32x32 {m}")));
    let f = frame_bytes(32, 32);
    let err = stderr(&out);
    let ours = stagecli::stats::records_of(&err, "farm").unwrap();
    assert_eq!(ours.len(), 3, "one record a host: {err}");
    // GNU parallel chooses the host of each chunk: whichever rendered frame k, its record
    // gives the bytes of frame k's cut sent and of one frame received; the records'
    // frames are the movie's, each once.
    let mut frames_seen = Vec::new();
    for (i, r) in ours.iter().enumerate() {
        let host = format!("node{}", i + 1);
        assert_eq!(r.get("host"), Some(host.as_str()), "{r}");
        if r.count("frames") == Some(0) {
            assert_eq!(r.count("chunks"), Some(0), "{r}");
            continue;
        }
        let ks: Vec<usize> = r.list("chunk_starts").unwrap_or_default();
        assert_eq!(
            r.list::<usize>("chunk_frames"),
            Some(vec![1; ks.len()]),
            "{r}"
        );
        let sent: usize = ks
            .iter()
            .map(|k| cut(&k.to_string(), &(k + 1).to_string()))
            .sum();
        assert_eq!(r.number::<usize>("sent_bytes"), Some(sent), "{r}");
        assert_eq!(
            r.number::<usize>("received_bytes"),
            Some(ks.len() * f),
            "{r}"
        );
        assert!(r.number::<f64>("busy_s").is_some(), "{r}");
        frames_seen.extend(ks);
    }
    frames_seen.sort();
    assert_eq!(frames_seen, [0, 1, 2], "{err}");
    // Each host's own --stats lines come labelled with it.
    let zbufs = stagecli::stats::records_of(&err, "zbuf").unwrap();
    let hosts_said: Vec<_> = zbufs
        .iter()
        .filter(|r| r.get("input") == Some("leaf-0") && r.get("host").is_some())
        .collect();
    assert_eq!(hosts_said.len(), 3, "{err}");
    assert_nothing_left(&hosts, 3, &tmp);
}

/// With `bad` and a host that serves: every chunk `bad` failed is retried on the other,
/// and the frames are a local run's; `bad` alone: status 3 and the returned last line.
fn retried_elsewhere_and_named_alone(hosts: &Hosts, tmp: &Path, both: &str, bad: &str) -> Output {
    let movie = scene_file(hosts.dir(), "spheres.pp", &["spheres", "--frames", "4"]);
    let m = movie.display().to_string();
    let run = |list: &str| {
        let args = [
            "--hosts",
            list,
            "--size",
            "32x32",
            "--chunk",
            "2",
            m.as_str(),
        ];
        render_frames(hosts, tmp, &args, b"")
    };
    let (out, took) = run(both);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        out.stdout == render_locally(&format!("--size 32x32 {m}")),
        "the frames differ from a local run's"
    );
    assert!(took < Duration::from_secs(30), "took {took:?}");
    let (out, took) = run(bad);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    assert!(out.stdout.is_empty());
    // Usually well under a second; on a loaded machine, an ssh connection has once
    // taken 10 s, so the bound here is loose.
    assert!(took < Duration::from_secs(30), "took {took:?}");
    out
}

#[test]
fn a_host_that_cannot_be_reached_is_named() {
    let _serial = hosts::serial();
    let Some(hosts) = Hosts::start(&[Host::Serving, Host::Unreachable]) else {
        return;
    };
    let tmp = local_tmp(&hosts);
    let out = retried_elsewhere_and_named_alone(&hosts, &tmp, "node1,node2", "node2");
    let (address, port) = hosts.address(1);
    assert_eq!(
        last_line(&out),
        format!(
            "farm: host node2: frames 0 to 1, 3 tries: ssh: connect to host {address} port \
             {port}: Connection refused"
        )
    );
    assert_nothing_left(&hosts, 2, &tmp);
}

#[test]
fn a_host_dead_from_the_start_is_named_at_once_and_dropped_after_two_failures() {
    let _serial = hosts::serial();
    let Some(hosts) = Hosts::start(&[Host::Serving, Host::Unreachable]) else {
        return;
    };
    let tmp = local_tmp(&hosts);
    let movie = scene_file(hosts.dir(), "spheres.pp", &["spheres", "--frames", "8"]);
    let m = movie.display().to_string();
    let args = [
        "--hosts",
        "node1,node2",
        "--size",
        "32x32",
        "--chunk",
        "1",
        &m,
    ];
    let (out, _) = render_frames(&hosts, &tmp, &args, b"");
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        out.stdout == render_locally(&format!("--size 32x32 {m}")),
        "the frames differ from a local run's"
    );
    let (address, port) = hosts.address(1);
    let err = stderr(&out);
    let ours: Vec<&str> = err.lines().filter(|l| l.starts_with("farm: ")).collect();
    assert_eq!(ours.len(), 2, "{err}");
    assert!(
        ours[0].starts_with("farm: host node2: a try of frame ")
            && ours[0].ends_with(&format!(
                " failed: ssh: connect to host {address} port {port}: Connection refused"
            )),
        "{err}"
    );
    assert_eq!(
        ours[1],
        "farm: host node2: 2 failed tries in a row; it gets no more chunks"
    );
    assert_nothing_left(&hosts, 2, &tmp);
}

#[test]
fn a_host_that_refuses_the_command_is_named() {
    // node2 lets the key in only to run `false`, whatever is asked.
    let _serial = hosts::serial();
    let Some(hosts) = Hosts::start(&[Host::Serving, Host::ForcedCommand("false".into())]) else {
        return;
    };
    let tmp = local_tmp(&hosts);
    let out = retried_elsewhere_and_named_alone(&hosts, &tmp, "node1,node2", "node2");
    assert_eq!(
        last_line(&out),
        "farm: host node2: frames 0 to 1, 3 tries: the command exited with status 1 and no \
         message (does the host allow only another command?)"
    );
    assert!(
        hosts.sessions(1) >= 3,
        "node2 let the key in: {}",
        hosts.log(1)
    );
    assert_nothing_left(&hosts, 2, &tmp);
}

#[test]
fn a_host_that_refuses_the_login_is_named() {
    let _serial = hosts::serial();
    let Some(hosts) = Hosts::start(&[Host::DeniesKey, Host::Serving]) else {
        return;
    };
    let tmp = local_tmp(&hosts);
    let out = retried_elsewhere_and_named_alone(&hosts, &tmp, "node1,node2", "node1");
    let (address, _) = hosts.address(0);
    let user = String::from_utf8(Command::new("id").arg("-un").output().unwrap().stdout).unwrap();
    assert_eq!(
        last_line(&out),
        format!(
            "farm: host node1: frames 0 to 1, 3 tries: ssh: {}@{address}: Permission denied \
             (publickey).",
            user.trim()
        )
    );
    assert_nothing_left(&hosts, 2, &tmp);
}

#[test]
fn a_host_whose_command_sends_nothing_back_is_named() {
    // A forced command that succeeds without rendering: the frames missing are noticed.
    let _serial = hosts::serial();
    let Some(hosts) = Hosts::start(&[Host::ForcedCommand("cat >/dev/null".into())]) else {
        return;
    };
    let tmp = local_tmp(&hosts);
    let movie = scene_file(hosts.dir(), "spheres.pp", &["spheres", "--frames", "4"]);
    let (out, _) = render_frames(
        &hosts,
        &tmp,
        &[
            "--hosts",
            "node1",
            "--size",
            "32x32",
            "--chunk",
            "2",
            &movie.display().to_string(),
        ],
        b"",
    );
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    assert_eq!(
        last_line(&out),
        "farm: host node1: frames 0 to 1, 3 tries: sent back nothing for its frames 0 to 1"
    );
    assert!(out.stdout.is_empty());
    assert_nothing_left(&hosts, 1, &tmp);
}

#[test]
fn a_host_without_the_binaries_is_named() {
    let _serial = hosts::serial();
    let Some(hosts) = Hosts::start(&[Host::Serving]) else {
        return;
    };
    let tmp = local_tmp(&hosts);
    let movie = scene_file(hosts.dir(), "spheres.pp", &["spheres", "--frames", "4"]);
    let (out, took) = render_frames(
        &hosts,
        &tmp,
        &[
            "--hosts",
            "node1",
            "--remote-bin",
            "/nonexistent",
            "--size",
            "32x32",
            "--chunk",
            "2",
            &movie.display().to_string(),
        ],
        b"",
    );
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    assert_eq!(
        last_line(&out),
        "farm: host node1: frames 0 to 1, 3 tries: no viewxf in /nonexistent (POLYPIPE_BIN)"
    );
    // Three tries, three ssh connections: a second in all, idle; one such run took 28.8 s
    // on a loaded machine (an ssh connection there has once taken 10 s), so the bound is
    // that of a run that hangs.
    assert!(took < Duration::from_secs(60), "took {took:?}");
    assert!(out.stdout.is_empty());
    assert_nothing_left(&hosts, 1, &tmp);
}

/// A movie long enough that a host can be dropped or the run stopped while it renders:
/// 600 frames of a fill-heavy environment at 128×128.
fn long_movie(hosts: &Hosts) -> PathBuf {
    scene_file(
        hosts.dir(),
        "long.pp",
        &[
            "environment",
            "--frames",
            "600",
            "--polygons",
            "200",
            "--depth-complexity",
            "30",
            "--size",
            "128x128",
        ],
    )
}

/// Starts `render.sh --by frames` on the long movie, stdout to a file; waits until two
/// frames are written and host `watch` has had a session, so that what follows happens
/// mid-run.
fn start_long_run(
    hosts: &Hosts,
    tmp: &Path,
    movie: &Path,
    watch: usize,
) -> (std::process::Child, PathBuf) {
    let stdout_path = hosts.dir().join("long.ppm");
    // One try a chunk: the chunk of a host that drops is not retried, and the run ends.
    let mut cmd = render_frames_cmd(
        hosts,
        tmp,
        &[
            "--hosts",
            &hosts.names(),
            "--retries",
            "1",
            "--size",
            "128x128",
            &movie.display().to_string(),
        ],
    );
    cmd.stdin(Stdio::null())
        .stdout(std::fs::File::create(&stdout_path).unwrap())
        .stderr(Stdio::piped());
    let mut child = cmd.spawn().expect("start render.sh --by frames");
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        let written = std::fs::metadata(&stdout_path).map_or(0, |m| m.len() as usize);
        if written >= 2 * frame_bytes(128, 128) && hosts.sessions(watch) > 0 {
            break;
        }
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the run ended ({status}) before two frames and host {watch} had a session");
        }
        assert!(
            Instant::now() < deadline,
            "no two frames and a session of host {watch} in 60 s"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    (child, stdout_path)
}

/// Waits for `child` at most `limit`, and returns its status, stderr and the time taken.
fn wait_at_most(
    child: &mut std::process::Child,
    limit: Duration,
) -> (std::process::ExitStatus, String, Duration) {
    use std::io::Read;
    let (status, took) =
        pipeline_tests::wait_within(child, limit, || format!("still running {limit:?} later"));
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    (status, err, took)
}

#[test]
fn a_host_that_drops_mid_run_ends_it_within_seconds_leaving_nothing() {
    let _serial = hosts::serial();
    let Some(mut hosts) = Hosts::start(&[Host::Serving, Host::Serving]) else {
        return;
    };
    let tmp = local_tmp(&hosts);
    let movie = long_movie(&hosts);
    let (child, stdout_path) = start_long_run(&hosts, &tmp, &movie, 1);
    // node2's sshd and its sessions, render.sh and stages there: SIGKILL. Its chunk now,
    // or the next it is sent, fails.
    hosts.drop_host(1);
    the_dropped_run_ends_well(&hosts, &tmp, child, &stdout_path, "farm: host node2: ", "");
}

/// After node2 dropped: the run ends within 30 s (a second or two idle; the bound is that
/// of a run that waits on the lost host, not of a loaded machine), status 3, its last
/// line starting `prefix`; what it wrote is whole frames, the first of the movie as
/// `render.sh --size 128x128 LOCAL` renders it here, fewer than all; node1 and here are
/// clean. (node2 went down with its processes killed outright, as a machine losing power
/// does: what that left in node2's own TMPDIR is node2's.)
fn the_dropped_run_ends_well(
    hosts: &Hosts,
    tmp: &Path,
    mut child: std::process::Child,
    stdout_path: &Path,
    prefix: &str,
    local: &str,
) {
    let movie = hosts.dir().join("long.pp");
    let (status, err, took) = wait_at_most(&mut child, Duration::from_secs(30));
    assert_eq!(status.code(), Some(3), "{err}");
    let message = err.lines().last().unwrap_or("");
    assert!(message.starts_with(prefix), "{err}");
    let written = std::fs::read(stdout_path).unwrap();
    let f = frame_bytes(128, 128);
    assert_eq!(
        written.len() % f,
        0,
        "{} bytes: a frame cut short",
        written.len()
    );
    let whole = render_locally(&format!("--size 128x128 {local} {}", movie.display()));
    assert!(
        whole.starts_with(&written),
        "the {} frames written are not the movie's first",
        written.len() / f
    );
    assert!(written.len() < whole.len());
    eprintln!(
        "node2 dropped: the run ended {took:?} later, {message:?}, {} of {} frames written",
        written.len() / f,
        whole.len() / f
    );
    assert_nothing_left(hosts, 1, tmp);
}

#[test]
fn stopping_the_run_leaves_nothing_here_or_on_the_hosts() {
    let _serial = hosts::serial();
    let Some(hosts) = Hosts::start(&[Host::Serving, Host::Serving]) else {
        return;
    };
    let tmp = local_tmp(&hosts);
    let movie = long_movie(&hosts);
    let (mut child, stdout_path) = start_long_run(&hosts, &tmp, &movie, 0);
    let status = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    // farm stops parallel, then what parallel leaves (SIGTERM, SIGKILL a second later):
    // a second or two idle. The bound is that of a stop that hangs, not of a loaded
    // machine's scheduling.
    let (status, _, took) = wait_at_most(&mut child, Duration::from_secs(30));
    assert_eq!(status.code(), Some(143));
    eprintln!("stopped: the run ended {took:?} after SIGTERM");
    let written = std::fs::metadata(&stdout_path).unwrap().len() as usize;
    assert_eq!(written % frame_bytes(128, 128), 0);
    assert_nothing_left(&hosts, 2, &tmp);
}

#[test]
fn a_reader_that_goes_away_ends_the_run_quietly() {
    // `| head -c 100`: the frames' reader goes; the run ends with status 0 and no
    // message, as the stages do, and stops its hosts.
    let _serial = hosts::serial();
    let Some(hosts) = Hosts::start(&[Host::Serving, Host::Serving]) else {
        return;
    };
    let tmp = local_tmp(&hosts);
    let movie = scene_file(hosts.dir(), "spheres.pp", &["spheres", "--frames", "8"]);
    bin_dir();
    let script = format!(
        "bash '{}' --hosts node1,node2 --by frames --size 64x64 '{}' | head -c 100 | wc -c; \
         echo \"status ${{PIPESTATUS[0]}}\"",
        repo_root().join("scripts/render.sh").display(),
        movie.display()
    );
    let out = Command::new("bash")
        .args(["-c", &script])
        .env("POLYPIPE_SSH", hosts.ssh())
        .env("TMPDIR", &tmp)
        .env_remove("POLYPIPE_BIN")
        .output()
        .unwrap();
    assert_eq!(String::from_utf8_lossy(&out.stdout), "100\nstatus 0\n");
    assert_eq!(stderr(&out), "");
    assert_nothing_left(&hosts, 2, &tmp);
}

#[test]
fn without_sshd_the_tests_are_skipped_not_failed() {
    // What every test here does where sshd is not installed: no hosts, and a message
    // (under CI=true, Hosts::start fails instead: see the next test).
    assert!(Hosts::start_using(Path::new("/nonexistent/sshd"), &[Host::Serving]).is_none());
    assert_eq!(
        hosts::unavailable(Path::new("/nonexistent/sshd")).as_deref(),
        Some("/nonexistent/sshd is not installed (apt-get install openssh-server openssh-client)")
    );
}

#[test]
fn under_ci_a_missing_sshd_fails_the_tests() {
    // Hosts::start with CI=true and no sshd panics, naming why; run in a child process
    // of this test binary so that the environment and the panic stay there.
    if std::env::var("POLYPIPE_TEST_CHILD").is_ok() {
        let _ = Hosts::start_checked(Path::new("/nonexistent/sshd"), true, &[Host::Serving]);
        return;
    }
    // The test's name in its binary: its module's path less the binary's own name.
    let module = module_path!().split_once("::").map_or("", |(_, m)| m);
    let name = format!("{module}::under_ci_a_missing_sshd_fails_the_tests");
    let out = Command::new(std::env::current_exe().unwrap())
        .args(["--exact", &name, "--nocapture"])
        .env("POLYPIPE_TEST_CHILD", "1")
        .output()
        .unwrap();
    assert!(!out.status.success());
    let text = String::from_utf8_lossy(&out.stdout) + String::from_utf8_lossy(&out.stderr);
    assert!(text.contains("1 failed"), "{text}");
    assert!(
        text.contains(
            "no loopback ssh hosts under CI=true, where they must run: /nonexistent/sshd is \
             not installed"
        ),
        "{text}"
    );
}

#[test]
fn usage_errors_need_no_hosts() {
    // --by frames without --hosts, with -o or --subtree, a bad --by, --hosts or --size:
    // status 2 before any ssh, in render's words and no other.
    for (args, message) in [
        (
            vec!["--by", "frames", "examples/penetrating.txt"],
            "render: --by frames needs hosts: --hosts H1,H2,… or --sshloginfile FILE (or \
             --slurm-array DIR, for Slurm's)",
        ),
        (
            vec!["--by", "leaves", "examples/penetrating.txt"],
            "render: --by leaves needs --hosts H1,H2,…",
        ),
        (
            vec!["--hosts", "a,b", "--by", "frames", "--subtree", "1"],
            "render: --subtree is a host's part of --by leaves: not with --by frames",
        ),
        (
            vec!["--resume", "examples/penetrating.txt"],
            "render: --resume is for --by frames",
        ),
        (
            vec!["--hosts", "a", "--by", "tiles"],
            "render: --by must be leaves or frames, not 'tiles'",
        ),
        (
            vec!["--hosts", "a,,b", "--by", "frames"],
            "render: --hosts must be host names separated by commas, not 'a,,b'",
        ),
        (
            vec!["--hosts", "a", "--by", "frames", "--size", "0x3"],
            "render: --size must be WxH with W and H from 1 to 65536, not '0x3'",
        ),
        (
            vec!["--chunk", "3", "examples/penetrating.txt"],
            "render: --chunk is for --by frames",
        ),
    ] {
        let out = Command::new("bash")
            .arg(repo_root().join("scripts/render.sh"))
            .args(&args)
            .current_dir(repo_root())
            .env("POLYPIPE_SSH", "false")
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert_eq!(stderr(&out), format!("{message}\n"), "{args:?}");
    }
}

// --- The tree's leaves on hosts (`--by leaves`, the default with --hosts). ---------------

/// `scripts/render.sh --by leaves ARGS` reaching `hosts`, with TMPDIR `tmp`, the
/// example scene on stdin (read when ARGS name no scene).
fn render_leaves(hosts: &Hosts, tmp: &Path, args: &[&str]) -> (Output, Duration) {
    let mut all = vec!["--by", "leaves"];
    all.extend_from_slice(args);
    let example = std::fs::read(repo_root().join("examples/penetrating.txt")).unwrap();
    render_frames(hosts, tmp, &all, &example)
}

#[test]
fn leaves_on_two_hosts_give_a_local_runs_frames_at_depths_1_to_3() {
    let _serial = hosts::serial();
    let Some(hosts) = Hosts::start(&[Host::Serving, Host::Serving]) else {
        return;
    };
    let tmp = local_tmp(&hosts);
    let movie = scene_file(
        hosts.dir(),
        "env.pp",
        &[
            "environment",
            "--frames",
            "3",
            "--polygons",
            "300",
            "--size",
            "96x64",
        ],
    );
    let m = movie.display().to_string();
    let mut sessions = 0;
    for depth in ["1", "2", "3"] {
        let local = render_locally(&format!("--size 96x64 --depth {depth} {m}"));
        assert_eq!(local.len(), 3 * frame_bytes(96, 64));
        let (out, _) = render_leaves(
            &hosts,
            &tmp,
            &[
                "--hosts",
                "node1,node2",
                "--size",
                "96x64",
                "--depth",
                depth,
                &m,
            ],
        );
        assert!(out.status.success(), "depth {depth}: {}", stderr(&out));
        assert!(
            out.stdout == local,
            "depth {depth}: frames differ from a local run's"
        );
        assert_eq!(stderr(&out), "", "a run without --stats says nothing");
        // Two hosts take the root's two subtrees (depth 1: its two leaves), each over
        // one ssh session, and run their splitters and leaves there.
        sessions += 1;
        for i in 0..2 {
            assert_eq!(hosts.sessions(i), sessions, "{}", hosts.log(i));
        }
    }
    assert_nothing_left(&hosts, 2, &tmp);
}

#[test]
fn stats_name_each_subtrees_host_and_its_links_bytes() {
    let _serial = hosts::serial();
    let Some(hosts) = Hosts::start(&[Host::Serving, Host::Serving]) else {
        return;
    };
    let tmp = local_tmp(&hosts);
    // The links' records: render's own, a host each (stagecli::stats).
    let links = |out: &Output| -> Vec<String> {
        stagecli::stats::records_of(&stderr(out), "render")
            .unwrap()
            .iter()
            .filter(|r| r.get("label").is_none())
            .map(ToString::to_string)
            .collect()
    };
    // Two hosts at depth 2: each takes one of the root's subtrees, its splitter and two
    // leaves; their lines come back labelled with the host. The bytes are those of the
    // root splitter's outputs and of the runs each host's zbuf --runs sends back.
    let (out, _) = render_leaves(
        &hosts,
        &tmp,
        &[
            "--hosts",
            "node1,node2",
            "--depth",
            "2",
            "--stats",
            &repo_root()
                .join("examples/penetrating.txt")
                .display()
                .to_string(),
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let err = stderr(&out);
    let records = stagecli::stats::records(&err).unwrap();
    let said = |stage: &str, host: &str, key: &str, value: &str| {
        records
            .iter()
            .any(|r| r.stage() == stage && r.get("host") == Some(host) && r.get(key) == Some(value))
    };
    assert!(
        said("scanconv", "node1", "label", "scanconv (leaf 1)")
            && records
                .iter()
                .any(|r| r.get("label") == Some("scanconv (leaf 1)")
                    && r.count("pixels_tested") == Some(21119))
            && said("splitter", "node2", "node", "3"),
        "{err}"
    );
    assert_eq!(
        links(&out),
        [
            "@stats render node=2 host=node1 bytes_there=581 bytes_back=7765",
            "@stats render node=3 host=node2 bytes_there=581 bytes_back=4661",
        ]
    );
    // Four hosts (each named twice) at depth 2: a leaf each, round-robin. A leaf's runs
    // come back as it sent them: the bytes zbuf counts from each leaf in a local run.
    let (out, _) = render_leaves(
        &hosts,
        &tmp,
        &[
            "--hosts",
            "node1,node2,node1,node2",
            "--depth",
            "2",
            "--stats",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(
        links(&out),
        [
            "@stats render node=4 host=node1 bytes_there=645 bytes_back=2609",
            "@stats render node=5 host=node2 bytes_there=645 bytes_back=5217",
            "@stats render node=6 host=node1 bytes_there=741 bytes_back=2449",
            "@stats render node=7 host=node2 bytes_there=341 bytes_back=2273",
        ]
    );
    assert_eq!((hosts.sessions(0), hosts.sessions(1)), (3, 3));
    assert_nothing_left(&hosts, 2, &tmp);
}

/// How one host fails with `--by leaves`: the hosts, render.sh's arguments after `--by
/// leaves`, and the run's last line given the hosts.
struct LeafFault {
    kinds: Vec<Host>,
    args: &'static [&'static str],
    message: fn(&Hosts) -> String,
}

#[test]
fn each_way_a_leaf_host_fails_is_named_within_seconds_leaving_nothing() {
    let faults = [
        // Cannot be reached.
        LeafFault {
            kinds: vec![Host::Serving, Host::Unreachable],
            args: &["--hosts", "node1,node2", "--depth", "1"],
            message: |h| {
                let (address, port) = h.address(1);
                format!(
                    "render: host node2 (leaf 1): ssh: connect to host {address} port {port}: \
                     Connection refused"
                )
            },
        },
        // Lets the key in only to run `false`, whatever is asked.
        LeafFault {
            kinds: vec![Host::Serving, Host::ForcedCommand("false".into())],
            args: &["--hosts", "node1,node2", "--depth", "1"],
            message: |_| {
                "render: host node2 (leaf 1): the command exited with status 1 and no \
                 message (does the host allow only another command?)"
                    .into()
            },
        },
        // Answers with nothing: a forced command that reads the stream and succeeds.
        LeafFault {
            kinds: vec![Host::ForcedCommand("cat >/dev/null".into())],
            args: &["--hosts", "node1", "--depth", "0"],
            message: |_| {
                "render: host node1 (leaf 0): sent back nothing (status 0 from its command)".into()
            },
        },
        // Lacks the binaries. Depth 0: one leaf (at depth 1 both would fail, and either
        // may be named first).
        LeafFault {
            kinds: vec![Host::Serving],
            args: &[
                "--hosts",
                "node1",
                "--remote-bin",
                "/nonexistent",
                "--depth",
                "0",
            ],
            message: |_| {
                "render: host node1 (leaf 0): no viewxf in /nonexistent (POLYPIPE_BIN)".into()
            },
        },
    ];
    for fault in faults {
        let _serial = hosts::serial();
        let Some(hosts) = Hosts::start(&fault.kinds) else {
            return;
        };
        let tmp = local_tmp(&hosts);
        let (out, took) = render_leaves(&hosts, &tmp, fault.args);
        assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
        assert_eq!(last_line(&out), (fault.message)(&hosts));
        // Usually well under a second; the bound is loose for a loaded machine (see the
        // frames test of an unreachable host).
        assert!(took < Duration::from_secs(30), "took {took:?}");
        assert!(
            out.stdout.is_empty(),
            "no frame is whole without the failed leaf"
        );
        assert_nothing_left(&hosts, fault.kinds.len(), &tmp);
    }
}

#[test]
fn a_leaf_host_that_drops_mid_movie_ends_the_run_within_seconds() {
    let _serial = hosts::serial();
    let Some(mut hosts) = Hosts::start(&[Host::Serving, Host::Serving]) else {
        return;
    };
    let tmp = local_tmp(&hosts);
    let movie = long_movie(&hosts);
    let stdout_path = hosts.dir().join("leaves.ppm");
    let mut cmd = render_frames_cmd(
        &hosts,
        &tmp,
        &[
            "--by",
            "leaves",
            "--hosts",
            "node1,node2",
            "--depth",
            "1",
            "--size",
            "128x128",
            &movie.display().to_string(),
        ],
    );
    cmd.stdin(Stdio::null())
        .stdout(std::fs::File::create(&stdout_path).unwrap())
        .stderr(Stdio::piped());
    let mut child = cmd.spawn().expect("start render.sh");
    let f = frame_bytes(128, 128);
    let deadline = Instant::now() + Duration::from_secs(60);
    while std::fs::metadata(&stdout_path).map_or(0, |m| m.len() as usize) < 2 * f {
        assert!(child.try_wait().unwrap().is_none(), "the run ended early");
        assert!(Instant::now() < deadline, "no two frames in 60 s");
        std::thread::sleep(Duration::from_millis(5));
    }
    hosts.drop_host(1);
    the_dropped_run_ends_well(
        &hosts,
        &tmp,
        child,
        &stdout_path,
        "render: host node2 (leaf 1): ssh",
        "--depth 1",
    );
}
