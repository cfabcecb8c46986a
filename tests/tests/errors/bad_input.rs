//! Bad streams for every binary (docs/degenerate.md, "Bad input"): each fault gives one
//! line `stage: message` on stderr, exit status 1 (invalid input, stagecli's table),
//! no panic, no hang; `| head -c 100` ends a stage quietly; zbuf writes the frames it
//! finished before a fault.

use pipeline_tests::sh;
use std::io::Read;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Each stage: its name, its command line, and a shell pipeline writing a valid binary
/// stream of the space it reads (`T` is the world-space text scene).
const STAGES: &[(&str, &str, &str)] = &[
    ("viewxf", "viewxf", "scene penetrating"),
    ("clipplane", "clipplane left", "viewxf < T"),
    ("clipbatch", "clipbatch", "viewxf < T"),
    ("splitter", "splitter x=0 /dev/null /dev/null", "viewxf < T"),
    ("persp", "persp --size 8x8", "viewxf < T"),
    ("scanconv", "scanconv", "viewxf < T | persp --size 8x8"),
    ("zbuf", "zbuf", "viewxf < T | persp --size 8x8 | scanconv"),
    ("zspec", "zspec --size 8x8", "scene penetrating"),
];

const TEXT: &str = "polypipe 1 world\ncolour 255 0 0\n-5 -5 0\n5 -5 0\n0 5 0\nEND\n";

fn write_scene() -> tempfile::TempPath {
    let f = tempfile::NamedTempFile::new().unwrap();
    std::fs::write(f.path(), TEXT).unwrap();
    f.into_temp_path()
}

/// Asserts a refusal: status 1, one stderr line `stage: …` (returned), no panic.
fn refused(stage: &str, what: &str, out: &Output) -> String {
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(
        out.status.code(),
        Some(1),
        "{stage} {what}: status; stderr {err}"
    );
    assert!(!err.contains("panicked"), "{stage} {what}: {err}");
    assert_eq!(err.lines().count(), 1, "{stage} {what}: {err}");
    assert!(
        err.starts_with(&format!("{stage}: ")),
        "{stage} {what}: {err}"
    );
    err
}

fn run(cmd: &str, input: &[u8]) -> Output {
    sh(cmd, input)
}

#[test]
fn wrong_magic_version_and_space() {
    for &(stage, cmd, _) in STAGES {
        let e = refused(stage, "magic", &run(cmd, b"hello world\n"));
        assert!(
            e.contains("line 1, column 1") && e.contains("not a polypipe stream"),
            "{e}"
        );
        let e = refused(stage, "version", &run(cmd, b"polypipe 2 world\nEND\n"));
        assert!(e.contains("stream version 2 is not supported"), "{e}");
        let e = refused(stage, "binary magic", &run(cmd, b"\x89PPIPX\r\n\0\0\0\0"));
        assert!(e.contains("bad magic"), "{e}");
        // A space the stage does not read: name the stage that should come first.
        let wrong = if stage == "viewxf" || stage == "zspec" {
            "polypipe 1 screen 8 8\nEND\n"
        } else {
            "polypipe 2 fragments 8 8\nEND\n"
        };
        let wrong = if stage == "zbuf" {
            "polypipe 1 world\nEND\n"
        } else {
            wrong
        };
        let e = refused(stage, "space", &run(cmd, wrong.as_bytes()));
        assert!(e.contains("expected") && e.contains("space"), "{e}");
    }
}

#[test]
fn random_bytes() {
    // A fixed pseudo-random sequence (xorshift), with and without the binary magic.
    let mut x: u64 = 0x9e3779b97f4a7c15;
    let mut bytes = Vec::new();
    for _ in 0..4096 {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        bytes.push(x as u8);
    }
    let mut magic = b"\x89PPIPE\r\n".to_vec();
    magic.extend_from_slice(&bytes);
    for &(stage, cmd, _) in STAGES {
        refused(stage, "random", &run(cmd, &bytes));
        refused(stage, "random after magic", &run(cmd, &magic));
    }
}

#[test]
fn a_binary_stream_cut_at_every_byte() {
    let scene = write_scene();
    for &(stage, cmd, make) in STAGES {
        let make = make.replace('T', scene.to_str().unwrap());
        let whole = run(&make, b"");
        assert!(whole.status.success(), "{make}");
        let stream = whole.stdout;
        assert!(
            run(cmd, &stream).status.success(),
            "{stage} on the whole stream"
        );
        for cut in 0..stream.len() {
            let out = run(cmd, &stream[..cut]);
            let e = refused(stage, &format!("cut at {cut}"), &out);
            assert!(
                e.contains("byte") || e.contains("empty input"),
                "cut at {cut}: {e}"
            );
        }
    }
}

#[test]
fn text_errors_are_located() {
    for &(stage, cmd, _) in STAGES {
        let (space, vertex) = match stage {
            "viewxf" | "zspec" => ("world", "0 0 0"),
            "scanconv" => ("screen 8 8", "1 1 0.5"),
            "zbuf" => ("fragments 8 8", "span 1 1 3 0 0"),
            _ => ("eye", "0 0 16 10"),
        };
        let version = if stage == "zbuf" { 2 } else { 1 };
        let syntax = format!("polypipe {version} {space}\ncolour 1 2 3\n{vertex}\n  oops\nEND\n");
        let e = refused(stage, "syntax", &run(cmd, syntax.as_bytes()));
        assert!(e.contains("line 4, column 3"), "{e}");
        let colour = format!("polypipe {version} {space}\ncolour 1 256 3\n{vertex}\nEND\n");
        let e = refused(stage, "colour", &run(cmd, colour.as_bytes()));
        assert!(
            e.contains("line 2, column 10") && e.contains("out of range 0..=255"),
            "{e}"
        );
        let missing = format!("polypipe {version} {space}\ncolour 1 2 3\n{vertex}\n");
        let e = refused(stage, "missing END", &run(cmd, missing.as_bytes()));
        assert!(e.contains("without END"), "{e}");
        let after = format!("polypipe {version} {space}\ncolour 1 2 3\n{vertex}\nEND\nEND\n");
        let e = refused(stage, "after END", &run(cmd, after.as_bytes()));
        assert!(e.contains("line 5, column 1: data after END"), "{e}");
    }
}

#[test]
fn nan_and_infinity_are_refused_naming_the_polygon() {
    for &(stage, cmd, _) in STAGES {
        if stage == "zbuf" {
            continue; // fragments have integer coordinates
        }
        let (space, pre) = match stage {
            "viewxf" | "zspec" => ("world", ""),
            "scanconv" => ("screen 8 8", ""),
            _ => ("eye", ""),
        };
        let n = if space == "eye" {
            "0 0 16 10\n1 0 16 10\nnan 1 16 10"
        } else {
            "0 0 0\n1 0 0\n0 nan 0"
        };
        let text = format!(
            "polypipe 1 {space}\n{pre}colour 1 2 3\n0 0 1{}\nEND\n",
            if space == "eye" { " 1" } else { "" }
        );
        let text = text
            .replace("0 0 1 1\n", &format!("{n}\n"))
            .replace("0 0 1\n", &format!("{n}\n"));
        let e = refused(stage, "text nan", &run(cmd, text.as_bytes()));
        assert!(e.contains("must be finite"), "{e}");
        let inf = text.replace("nan", "inf");
        let e = refused(stage, "text inf", &run(cmd, inf.as_bytes()));
        assert!(e.contains("`inf`; coordinates must be finite"), "{e}");
    }
    // Binary NaN: a valid eye stream with one coordinate's bytes replaced by NaN.
    let scene = write_scene();
    let eye = run(&format!("viewxf < {}", scene.to_str().unwrap()), b"").stdout;
    let needle = (-5.0f64).to_le_bytes();
    let at = eye
        .windows(8)
        .position(|w| w == needle)
        .expect("x = -5 in the stream");
    let mut bad = eye.clone();
    bad[at..at + 8].copy_from_slice(&f64::NAN.to_le_bytes());
    for &(stage, cmd, _) in STAGES {
        if matches!(stage, "clipplane" | "clipbatch" | "splitter" | "persp") {
            let e = refused(stage, "binary nan", &run(cmd, &bad));
            assert!(e.contains("frame 0, polygon 0"), "{e}");
        }
    }
}

#[test]
fn three_million_vertices_are_refused_or_streamed() {
    // A text polygon with 3 million vertices: more than proto's MAX_VERTICES (2 million),
    // refused with a clear message before it is held whole.
    let cmd = "{ echo 'polypipe 1 world'; echo 'colour 1 2 3'; \
               awk 'BEGIN { for (i = 0; i < 3000000; i++) print i % 7, i % 5, 0 }'; echo END; } \
               | viewxf";
    let out = sh(cmd, b"");
    let e = refused("viewxf", "3M vertices", &out);
    assert!(e.contains("vertices"), "{e}");
}

#[test]
fn head_ends_every_stage_quietly() {
    let scene = write_scene();
    for &(stage, cmd, make) in STAGES {
        // A long input: the same stream 2000 frames over, read through `head -c 100`.
        let make = make.replace('T', scene.to_str().unwrap());
        let input: Vec<u8> = match stage {
            "viewxf" | "zspec" => {
                let mut s = String::from("polypipe 1 world\n");
                for _ in 0..3000 {
                    s.push_str("colour 255 0 0\n-5 -5 0\n5 -5 0\n0 5 0\nNEXT.FRAME\n");
                }
                s.push_str("END\n");
                s.into_bytes()
            }
            _ => {
                let mut s = String::from("polypipe 1 world\n");
                for _ in 0..3000 {
                    s.push_str("colour 255 0 0\n-5 -5 0\n5 -5 0\n0 5 0\nNEXT.FRAME\n");
                }
                s.push_str("END\n");
                let m = make.replace(&format!("< {}", scene.to_str().unwrap()), "");
                sh(&m, s.as_bytes()).stdout
            }
        };
        let cmd = if stage == "splitter" {
            "splitter x=0 /dev/stdout /dev/null"
        } else {
            cmd
        };
        let out = sh(
            &format!("{cmd} | head -c 100 > /dev/null; echo ${{PIPESTATUS[0]}}"),
            &input,
        );
        assert_eq!(
            String::from_utf8_lossy(&out.stdout).trim(),
            "0",
            "{stage}: status; stderr {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            out.stderr.is_empty(),
            "{stage}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

#[test]
fn zbuf_writes_the_frames_finished_before_a_fault_in_frame_3() {
    let mut s = String::from("polypipe 1 world\n");
    for _ in 0..3 {
        s.push_str("colour 255 0 0\n-5 -5 0\n5 -5 0\n0 5 0\nNEXT.FRAME\n");
    }
    s.push_str("END\n");
    let frags = sh("viewxf | persp --size 8x8 | scanconv", s.as_bytes()).stdout;
    // Frames 0, 1, 2 then an empty frame 3 and END: NEXT.FRAME and END are the last
    // 8 bytes, so cutting 10 cuts frame 2's last span.
    let cut = &frags[..frags.len() - 10];
    let out = sh("zbuf", cut);
    refused("zbuf", "cut in frame 3", &out);
    let frames = pipeline_tests::parse_ppm_stream(&out.stdout).expect("whole frames");
    assert_eq!(frames.len(), 2, "frames 0 and 1 whole");
}

/// Runs `args` (the binary first, from the build) with stdin from `stdin` (a path; none
/// for /dev/null), and returns its status, stderr, wall time and peak memory (KiB, from
/// wait4: the largest of the process and the children it waited for).
// The child is reaped by wait4 (for its rusage), which clippy does not see.
#[allow(clippy::zombie_processes)]
fn measured(args: &[&str], stdin: Option<&str>) -> (Option<i32>, String, Duration, i64) {
    use std::os::unix::process::ExitStatusExt;
    let input = match stdin {
        Some(p) => Stdio::from(std::fs::File::open(p).unwrap()),
        None => Stdio::null(),
    };
    let start = Instant::now();
    let mut child = Command::new(pipeline_tests::bin(args[0]))
        .args(&args[1..])
        .current_dir(pipeline_tests::repo_root())
        .env("POLYPIPE_BIN", pipeline_tests::bin_dir())
        .env("POLYPIPE_LOAD", "0")
        .stdin(input)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut err = String::new();
    // stderr is read to its end (one short line, or a hang's worth), then the child reaped
    // by wait4 for its rusage; a child still running after 60 s is killed.
    let pid = child.id() as libc::pid_t;
    let mut stderr = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = stderr.read_to_string(&mut s);
        s
    });
    let killer = std::thread::spawn(move || {
        std::thread::sleep(Duration::from_secs(60));
        // SAFETY: kill reads its two integer arguments; a pid already reaped at worst
        // names no process (the test has failed its time bound by then anyway).
        unsafe { libc::kill(pid, libc::SIGKILL) };
    });
    let mut status = 0;
    // SAFETY: an all-zero rusage is a valid value of the plain C struct.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: wait4 writes the status and the rusage through the two pointers, which point
    // at live locals of the right types.
    let reaped = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
    assert_eq!(reaped, pid, "{args:?}: wait4");
    let elapsed = start.elapsed();
    drop(killer);
    err.push_str(&reader.join().unwrap());
    let code = std::process::ExitStatus::from_raw(status).code();
    (code, err, elapsed, usage.ru_maxrss)
}

/// Input that never ends and holds no line, or no text (`/dev/zero`, `/dev/urandom`),
/// into every reader: the stream codec's (viewxf, clipbatch, persp, zbuf, zspec, `frames
/// --count`), `plan depth`'s look, render's (the scene a FILE, and stdin) and `scene
/// obj`'s (a FILE, and stdin). Each ends with status 1 and one line of at most 200 bytes
/// (render: its stage's, and the line naming the stage) within a hang's bound (a second where the machine is idle: the figures are printed),
/// its peak memory at most 64 MB (a text line is refused past 1 MiB,
/// `proto::text::MAX_LINE_BYTES`; before, each read on past 1.7 GB).
#[test]
fn endless_devices_are_refused_at_once_in_bounded_memory() {
    for device in ["/dev/zero", "/dev/urandom"] {
        let cases: Vec<(Vec<&str>, Option<&str>)> = vec![
            (vec!["viewxf"], Some(device)),
            (vec!["clipbatch"], Some(device)),
            (vec!["persp", "--size", "8x8"], Some(device)),
            (vec!["zbuf"], Some(device)),
            (vec!["zspec", "--size", "8x8"], Some(device)),
            (vec!["frames", "--count"], Some(device)),
            (vec!["frames", "--count", device], None),
            (vec!["plan", "depth", device], None),
            (vec!["render", "--depth", "0", device], None),
            (vec!["render", "--depth", "0", "-"], Some(device)),
            (vec!["render", "--depth", "auto", "-"], Some(device)),
            (vec!["scene", "obj", device], None),
            (vec!["scene", "obj", "-"], Some(device)),
        ];
        for (args, stdin) in cases {
            let what = format!("{} < {}", args.join(" "), stdin.unwrap_or("/dev/null"));
            let (code, err, took, kib) = measured(&args, stdin);
            eprintln!("{what}: status {code:?}, {took:.2?}, {kib} KiB; {err:?}");
            assert_eq!(code, Some(1), "{what}: {err}");
            // render passes on its first stage's line, which names that stage, and adds
            // none of its own (docs/DESIGN.md, "Errors and exit statuses").
            let lines: Vec<&str> = err.lines().collect();
            assert_eq!(lines.len(), 1, "{what}: {err}");
            let stage = if args[0] == "render" {
                "viewxf"
            } else {
                args[0]
            };
            assert!(
                lines[0].len() <= 200 && lines[0].starts_with(stage),
                "{what}: {} bytes: {err}",
                lines[0].len()
            );
            assert!(lines[0].len() <= 200, "{what}: {err}");
            assert!(!err.contains("panicked"), "{what}: {err}");
            assert!(took < Duration::from_secs(20), "{what}: {took:?}");
            assert!(kib <= 64_000, "{what}: {kib} KiB");
        }
    }
}

/// A word of 50 MB (a number with no end, on one line within the bound, or quoted by a
/// stage's message) is quoted cut to about 80 characters: a message stays one short line.
#[test]
fn a_long_word_is_quoted_cut() {
    let digits = "9".repeat(900_000);
    for (what, input) in [
        (
            "a long number",
            format!("polypipe 1 world\ncolour 1 2 3\n{digits}x 0 0\n"),
        ),
        ("a long keyword", format!("polypipe 1 world\n{digits}\n")),
    ] {
        let out = run("viewxf", input.as_bytes());
        let e = refused("viewxf", what, &out);
        assert!(e.len() < 300, "{what}: {} bytes", e.len());
        assert!(
            e.contains("999… (900001 bytes)") || e.contains("999… (900000 bytes)"),
            "{e}"
        );
    }
    // A text line longer than the bound is refused where it starts.
    let long = format!("polypipe 1 world\n# {}\n", " ".repeat(2 << 20));
    let e = refused("viewxf", "a long line", &run("viewxf", long.as_bytes()));
    assert_eq!(
        e.trim_end(),
        "viewxf: line 2, column 1: expected a line of text of at most 1048576 bytes, found \
         1048576 bytes with no end of line (not a text stream?)"
    );
}
