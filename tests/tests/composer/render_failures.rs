//! How a render ends when a stage fails or is killed: the stage named, its class of
//! failure passed through, every other stage stopped, nothing left on disk.

use pipeline_tests::bin_dir;
use pipeline_tests::render::{example, render, render_cmd};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

#[test]
fn a_failing_stage_is_named() {
    let out = render(
        &["--depth", "2", "-"],
        b"polypipe 1 world\ncolour 1 2 3\n0 0\n",
    );
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    // The stage said why, in one line naming itself: render adds no line of its own.
    assert_eq!(
        err,
        "viewxf: line 3, column 4: expected z of vertex 0 (3 numbers a vertex in world \
         space), found the end of the input\n"
    );
    let out = render(&["--depth", "7", &example()], b"");
    assert_eq!(out.status.code(), Some(2));
    let out = render(&["--merge", "zbuf", &example()], b"");
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr)
        .contains("render: --merge must be tiles or buffer, not 'zbuf'\n"));
    // viewxf's usage error stays a usage error.
    let out = render(&["--hither", "0", &example()], b"");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.starts_with("viewxf: ") && err.lines().count() == 1,
        "{err}"
    );
}

fn children_of(pid: u32, pattern: Option<&str>) -> Vec<u32> {
    let mut cmd = Command::new("pgrep");
    cmd.args(["-P", &pid.to_string()]);
    if let Some(p) = pattern {
        cmd.args(["-f", p]);
    }
    let out = cmd.output().unwrap();
    String::from_utf8_lossy(&out.stdout)
        .split_whitespace()
        .map(|s| s.parse().unwrap())
        .collect()
}

#[test]
fn a_stage_killed_by_sigkill_stops_the_whole_tree() {
    bin_dir();
    // A private TMPDIR, to see that the run puts nothing there.
    let tmp = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("render-kill");
    let _ = std::fs::remove_dir_all(&tmp);
    std::fs::create_dir_all(&tmp).unwrap();
    // A movie long enough to be still running when a stage is killed.
    let mut scene = Command::new(bin_dir().join("scene"))
        .args([
            "environment",
            "--polygons",
            "20000",
            "--depth-complexity",
            "3",
        ])
        .args(["--frames", "20"])
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut render = render_cmd(&["--depth", "3", "--clip", "chain", "-"])
        .env("TMPDIR", &tmp)
        .stdin(scene.stdout.take().unwrap())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Depth 3: viewxf, 6 clippers, 3 splitters (the root, then nodes 2 and 3 each with
    // its children, the last level projecting), 7 scanconv and zbuf (which resolves leaf
    // 0 itself).
    let started = Instant::now();
    let stages = loop {
        let stages = children_of(render.id(), None);
        if stages.len() == 18 {
            break stages;
        }
        assert!(
            started.elapsed() < Duration::from_secs(60),
            "the tree did not start: {stages:?}"
        );
        std::thread::sleep(Duration::from_millis(20));
    };
    // The stages are joined by anonymous pipes: nothing on disk.
    assert_eq!(
        std::fs::read_dir(&tmp).unwrap().count(),
        0,
        "a file in TMPDIR"
    );
    let victim = children_of(render.id(), Some("clipplane hither"));
    assert_eq!(victim.len(), 1);
    let killed = Command::new("kill")
        .args(["-KILL", &victim[0].to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    // render gives the stages a second after its SIGTERM before it sends SIGKILL, so it
    // ends a second or so after the failure; the bound is that of a hang, not of that
    // second, which a loaded machine stretches (18 stages on one core).
    let killed_at = Instant::now();
    let status = loop {
        if let Some(status) = render.try_wait().unwrap() {
            break status;
        }
        assert!(
            killed_at.elapsed() < Duration::from_secs(30),
            "render still running 30 s after a stage was killed"
        );
        std::thread::sleep(Duration::from_millis(10));
    };
    let mut err = String::new();
    std::io::Read::read_to_string(render.stderr.as_mut().unwrap(), &mut err).unwrap();
    let _ = scene.wait();
    assert_eq!(status.code(), Some(1), "{err}");
    assert!(
        err.contains("render: clipplane hither failed (killed by SIGKILL)"),
        "{err}"
    );
    assert_eq!(
        std::fs::read_dir(&tmp).unwrap().count(),
        0,
        "nothing left in TMPDIR"
    );
    // render reaps its stages before it exits: none is left, not even as a zombie.
    for pid in stages {
        assert!(
            !Path::new(&format!("/proc/{pid}")).exists(),
            "stage {pid} outlived render"
        );
    }
}

/// render exits with the failing stage's class (1 bad data, 2 usage, 3 I/O),
/// not always 1. Bad data (viewxf, 1) and a stage's usage error (viewxf --hither 0, 2)
/// are in `a_failing_stage_is_named`.
#[test]
fn a_failing_stages_status_class_passes_through() {
    // --size 0x0 is the user's error, reported by the script as its own option: 2.
    let out = render(&["--size", "0x0", &example()], b"");
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "render: --size must be WxH with W and H from 1 to 65536, not '0x0'\n"
    );
    // An output zbuf cannot write: I/O, 3. (The tests may run as root, whom a read-only
    // folder does not stop, and -o's folder is made when missing: so a file is in the
    // way.)
    let nowhere = PathBuf::from("/dev/null/frame%02d.png");
    let out = render(
        &[
            "--size",
            "21x21",
            "-o",
            nowhere.to_str().unwrap(),
            &example(),
        ],
        b"",
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert_eq!(
        err,
        "zbuf: cannot write /dev/null/frame00.png: Not a directory\n"
    );
    // A scene that cannot be read: 3.
    let out = render(&["/nonexistent/scene.txt"], b"");
    assert_eq!(out.status.code(), Some(3));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "render: cannot read scene /nonexistent/scene.txt\n"
    );
}

/// render killed outright (SIGKILL: nothing of its own runs) takes its stages with it,
/// so that a render stopped however it is leaves no process behind.
#[test]
fn render_killed_takes_its_stages_with_it() {
    // A scene on a stdin that stays open: the stages wait for the rest of it.
    let mut render = render_cmd(&["--depth", "2", "--size", "32x32", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut input = render.stdin.take().unwrap();
    std::io::Write::write_all(&mut input, b"polypipe 1 world\n").unwrap();
    // viewxf, clipbatch, one splitter (two levels) and zbuf with three scanconv leaves.
    let started = Instant::now();
    let stages = loop {
        let stages = children_of(render.id(), None);
        if stages.len() == 7 {
            break stages;
        }
        assert!(
            started.elapsed() < Duration::from_secs(60),
            "the tree did not start: {stages:?}"
        );
        std::thread::sleep(Duration::from_millis(20));
    };
    render.kill().unwrap();
    render.wait().unwrap();
    // Each stage has SIGTERM from the kernel as render dies (PR_SET_PDEATHSIG) and ends
    // as soon as it is scheduled; the bound is that of a stage that ignored it, not of
    // the scheduling, which a loaded machine stretches.
    let gone = Instant::now();
    while stages.iter().any(|&p| running(p)) {
        assert!(
            gone.elapsed() < Duration::from_secs(30),
            "a stage outlived render by 30 s: {:?}",
            stages.iter().filter(|&&p| running(p)).collect::<Vec<_>>()
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    drop(input);
}

/// Whether process `pid` still runs: it exists and is not a zombie. A stage whose
/// launcher was killed is reaped by whichever process adopts it (init, or a container's
/// first process, which may never reap): a zombie has ended, whoever holds its status.
fn running(pid: u32) -> bool {
    std::fs::read_to_string(format!("/proc/{pid}/stat")).is_ok_and(|stat| {
        // "pid (comm) state …": comm may hold spaces and parentheses.
        stat.rsplit_once(") ")
            .is_some_and(|(_, rest)| !rest.starts_with('Z'))
    })
}

/// `--depth auto` starts viewxf and the clipper before it has looked at the scene: a scene
/// the look cannot read goes on at depth 0, and the render ends as a depth-0 render of it
/// ends, viewxf (started early) named with its own words and status.
#[test]
fn a_scene_the_look_cannot_read_fails_in_viewxf_as_at_depth_0() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.txt");
    std::fs::write(&bad, "polypipe 1 world\ncolour 1 2 3\n0 0\n").unwrap();
    let bad = bad.display().to_string();
    // 1920x1080: no scene file is small enough there for depth 0 without the model.
    let auto = render(&["--size", "1920x1080", "--stats", &bad], b"");
    let zero = render(&["--size", "1920x1080", "--depth", "0", &bad], b"");
    let err = String::from_utf8_lossy(&auto.stderr);
    assert_eq!(auto.status.code(), Some(1), "{err}");
    assert_eq!(zero.status.code(), Some(1));
    // With a core or less for the render (a one-CPU runner, a container's quota,
    // `taskset -c 0`), depth auto is 0 without a look, and `--stats` says so first; the
    // rest is the same depth-0 failure.
    let err = if pipeline_tests::one_core_for_render() {
        let said = format!("render: {}\n", render::auto::ONE_CORE);
        let Some(rest) = err.strip_prefix(said.as_str()) else {
            panic!("one core: {err}")
        };
        rest.to_string()
    } else {
        err.into_owned()
    };
    assert!(
        err.starts_with("viewxf: line 3, column 4: expected z of vertex 0")
            && err.lines().count() == 1,
        "{err}"
    );
    assert_eq!(err, String::from_utf8_lossy(&zero.stderr));
    assert!(auto.stdout.is_empty());
}

/// A stand-in for ssh in `dir`, named `name`: the shell `body`, run with ssh's arguments.
fn fake_ssh(dir: &Path, name: &str, body: &str) -> PathBuf {
    use std::os::unix::fs::PermissionsExt;
    let path = dir.join(name);
    std::fs::write(&path, format!("#!/bin/sh\n{body}\n")).unwrap();
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    path
}

#[test]
fn a_host_that_sends_nothing_is_named_when_its_time_is_up() {
    let dir = tempfile::tempdir().unwrap();
    // A host that takes the stream and never answers.
    let ssh = fake_ssh(dir.path(), "ssh", "exec sleep 1000");
    let start = Instant::now();
    let out = render_cmd(&[
        "--hosts",
        "alpha",
        "--depth",
        "1",
        "--host-timeout",
        "5",
        &example(),
    ])
    .env("POLYPIPE_SSH", &ssh)
    .stdin(Stdio::null())
    .output()
    .unwrap();
    let took = start.elapsed();
    assert_eq!(out.status.code(), Some(3));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "render: host alpha (subtree 1): sent nothing for 5 s (--host-timeout): counted as \
         failed\n"
    );
    assert!(out.stdout.is_empty());
    assert!(took >= Duration::from_secs(5), "{took:?}");
    assert!(took < Duration::from_secs(15), "{took:?}");
}

#[test]
fn a_host_timeout_out_of_range_is_a_usage_error() {
    for bad in ["-1", "nan", "inf", "1e9", "x", ""] {
        let out = render(&["--host-timeout", bad, &example()], b"");
        assert_eq!(out.status.code(), Some(2), "{bad}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr),
            format!(
                "render: --host-timeout must be seconds from 0 (wait for ever) to 86400, not \
                 '{bad}'\n"
            )
        );
    }
}

#[test]
fn garbage_from_a_host_is_named_as_garbage_from_it() {
    let dir = tempfile::tempdir().unwrap();
    // A host that sends more bytes than a pipe holds, none of them a stream, so that it
    // is still writing when the merger gives up (killed by SIGPIPE before this was named).
    let ssh = fake_ssh(
        dir.path(),
        "ssh",
        "cat >/dev/null &\nhead -c 2000000 /dev/zero | tr '\\0' 'x'",
    );
    for _ in 0..3 {
        let out = render_cmd(&["--hosts", "alpha", "--depth", "1", &example()])
            .env("POLYPIPE_SSH", &ssh)
            .stdin(Stdio::null())
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(3));
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.starts_with("render: host alpha (subtree 1): sent what is not a polypipe stream: "),
            "{err}"
        );
        assert_eq!(err.lines().count(), 1, "{err}");
    }
}
