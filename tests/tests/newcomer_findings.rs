//! What a new user and an attacker tripped on, each with the
//! command that showed it and the behaviour now. The exit-status and usage findings (#4,
//! #5, #10: `zbuf -o x.jpg`, `clipplane --plane 1,2,3`, `zspec compare --min-agreement
//! nan`, `zbuf - -`, `splitter x=0 same same`) are rows of the tables in exit_codes.rs.

use pipeline_tests::{parse_ppm_stream, sh};

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// #1: `printf 'polypipe 2 fragments 65536 65536\nEND\n' | zbuf` aborted with SIGABRT
/// (`memory allocation of 34359738368 bytes failed`). The address space is limited to
/// 8 GB so that the frame cannot be had on any machine.
#[test]
fn a_frame_too_large_for_memory_is_refused_in_one_line() {
    let out = sh(
        "ulimit -v 8000000; printf 'polypipe 2 fragments 65536 65536\\nEND\\n' | zbuf",
        b"",
    );
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    assert!(
        stderr(&out).starts_with(
            "zbuf: stdin: a 65536x65536 screen needs 60 GiB (15 bytes a pixel: depth, polygon \
             and colour), more memory than this machine can give ("
        ),
        "{}",
        stderr(&out)
    );
    assert!(out.stdout.is_empty());
    // The reference's frame the same way.
    let out = sh(
        "ulimit -v 8000000; scene penetrating | zspec --size 65536x65536",
        b"",
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert_eq!(
        stderr(&out),
        "zspec: a 65536x65536 frame needs 44 GiB (11 bytes a pixel: colour and depth), more \
         memory than can be had\n"
    );
}

/// Vertices at ±1.7e308: finite, but too large for the viewing transformation's sums.
const HUGE: &str = "polypipe 1 world\ncolour 1 2 3\n-1.7e308 -1.7e308 -1.7e308\n\
                    1.7e308 -1.7e308 1.7e308\n0 1.7e308 0\nEND\n";

/// #2: `viewxf --eye 10,5,20` on vertices at ±1.7e308 printed `-inf` and exited 0, so
/// that the next stage took the blame.
#[test]
fn viewxf_refuses_to_write_an_infinity() {
    let out = sh("viewxf --eye 10,5,20 --text", HUGE.as_bytes());
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        stderr(&out),
        "viewxf: frame 0, polygon 0: vertex 0 comes out as (-7.602631123499285e307 \
         -1.1613210868087544e308 inf inf) after the viewing transformation: not a finite \
         number (coordinates this large overflow)\n"
    );
    // Only the header was written: no polygon with an infinity in it.
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "polypipe 1 eye aspect 1 hither 1 yon 30\n"
    );
}

/// #2: persp refuses a vertex whose projection overflows, naming its place in the input.
#[test]
fn persp_refuses_to_write_an_infinity() {
    let eye = "polypipe 1 eye aspect 1 hither 1 yon 30\ncolour 1 2 3\n-1e300 0 16 10\n\
               1e300 0 16 10\n0 1e308 0 1e308\nEND\n";
    let out = sh("persp --size 4x4 --text", eye.as_bytes());
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(
        err.starts_with("persp: frame 0, polygon 0: vertex 2 ") && err.lines().count() == 1,
        "{err}"
    );
    assert!(!String::from_utf8_lossy(&out.stdout).contains("inf"));
}

/// #2: the clippers and the splitter, on eye-space input and planes at the edge of f64:
/// whatever they make of it, they never write a number that is not finite. (Their
/// intersections clamp, so today they write; the shared check would refuse naming the
/// polygon if one did not.)
#[test]
fn clippers_and_splitters_never_write_an_infinity() {
    let header = "polypipe 1 eye aspect 1 hither 1 yon 30\ncolour 1 2 3\n";
    let polygons = [
        "1.7e308 0 16 1.7e308\n-1.7e308 0 16 10\n0 1 16 10\n",
        "1.7e308 1.7e308 16 1.7e308\n-1.7e308 -1.7e308 16 1.7e308\n0 -1.7e308 16 10\n",
        "-1.7e308 0 1.7e308 1.7e308\n1.7e308 0 -1.7e308 1.7e308\n0 1e308 0 1e308\n",
        "1e300 1e300 16 10\n-1e300 -1e300 16 10\n1e300 -1e300 16 10\n",
    ];
    let stages = [
        "clipplane left",
        "clipplane hither",
        "clipplane yon",
        "clipplane --plane 1e308,1e308,0,0,-1e308",
        "clipplane --plane 1e308,-1e308,1e308,0,0",
        "splitter x=0.5 /dev/null -",
        "splitter --plane 1e308,1e308,0,0,-1e308 /dev/null -",
    ];
    for polygon in polygons {
        let input = format!("{header}{polygon}END\n");
        for stage in stages {
            let out = sh(&format!("{stage} --text"), input.as_bytes());
            let text = String::from_utf8_lossy(&out.stdout).to_lowercase();
            assert!(
                !text.contains("inf") && !text.contains("nan"),
                "{stage}: {text}"
            );
            if !out.status.success() {
                let err = stderr(&out);
                assert_eq!(out.status.code(), Some(1), "{stage}: {err}");
                assert!(err.contains(": frame 0, polygon 0: "), "{stage}: {err}");
            }
        }
    }
}

/// #2: `scene obj` on `v nan 0 0` wrote `NaN`; it refuses, naming the OBJ line. A model
/// too large to turn (--no-fit) is refused naming the frame where it overflows.
#[test]
fn scene_refuses_numbers_that_are_not_finite() {
    let out = sh("scene obj -", b"v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        stderr(&out),
        "scene: <stdin>: line 2: vertex `v nan 0 0` has a coordinate `nan` that is not a \
         finite number\n"
    );
    assert!(out.stdout.is_empty());
    let huge = b"v 1.7e308 0 1.7e308\nv 1.7e308 1 1.7e308\nv 1.6e308 0 1.7e308\nf 1 2 3\n";
    let out = sh("scene obj --no-fit --frames 8 -", huge);
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(
        err.starts_with("scene: frame 1, polygon 0: vertex 0 comes out as (inf ")
            && err.ends_with("leave out --no-fit)\n"),
        "{err}"
    );
    // Fitted (the default), the same model is scaled into view without overflowing.
    let out = sh("scene obj --frames 8 --text -", huge);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout).to_lowercase();
    assert!(!text.contains("inf") && !text.contains("nan"));
}

/// The whole linear pipeline at W×H, from a world-space scene on stdin.
fn pipeline(size: &str) -> String {
    format!(
        "viewxf --size {size} | clipplane left | clipplane right | clipplane top \
         | clipplane bottom | clipplane hither | clipplane yon | persp --size {size} \
         | scanconv | zbuf"
    )
}

/// #3: `zspec`, the reference, drew a triangle with vertices at ±1e307 all black (its
/// Newell sums overflowed) while the pipeline drew it; now both draw it, alike.
#[test]
fn the_reference_draws_a_triangle_at_1e307() {
    let triangle = "polypipe 1 world\ncolour 255 0 0\n-1e307 -1e307 1\n1e307 -1e307 1\n\
                    0 1e307 -1\nEND\n";
    let exact = sh("zspec --size 8x8", triangle.as_bytes());
    assert!(exact.status.success(), "{}", stderr(&exact));
    let exact = parse_ppm_stream(&exact.stdout).unwrap();
    assert!(
        exact[0].pixels.iter().all(|p| *p == [255, 0, 0]),
        "{exact:?}"
    );
    let piped = sh(&pipeline("8x8"), triangle.as_bytes());
    assert!(piped.status.success(), "{}", stderr(&piped));
    assert_eq!(parse_ppm_stream(&piped.stdout).unwrap(), exact);
}

/// #4: `scene obj /tmp` exited 1 for an I/O error.
#[test]
fn an_obj_file_that_cannot_be_read_is_an_io_error() {
    let out = sh("scene obj /tmp", b"");
    assert_eq!(out.status.code(), Some(3));
    assert_eq!(stderr(&out), "scene: /tmp: Is a directory\n");
}

/// #4: `zspec compare` used 1 both for "differ" and for "not a PPM"; now cmp's 0 same,
/// 1 different, 2 trouble.
#[test]
fn zspec_compare_exits_as_cmp_does() {
    let dir = tempfile::tempdir().unwrap();
    let file = |name: &str, bytes: &[u8]| {
        let p = dir.path().join(name);
        std::fs::write(&p, bytes).unwrap();
        p.display().to_string()
    };
    let red = file("red.ppm", b"P6\n1 1\n255\n\xff\x00\x00");
    let red_plain = file("red-plain.ppm", b"P3\n1 1\n255\n255 0 0\n");
    let blue = file("blue.ppm", b"P6\n1 1\n255\n\x00\x00\xff");
    let two = file(
        "two.ppm",
        b"P6\n1 1\n255\n\xff\x00\x00P6\n1 1\n255\n\xff\x00\x00",
    );
    let text = file("scene.txt", b"polypipe 1 world\nEND\n");
    let cases = [
        (format!("zspec compare {red} {red_plain}"), 0, ""),
        (
            format!("zspec compare {red} {blue}"),
            1,
            "zspec compare: 1 of 1 frames differ (frames [0])\n",
        ),
        (
            format!("zspec compare {red} {two}"),
            1,
            "zspec compare: the streams have 1 and 2 frames\n",
        ),
        (
            format!("zspec compare {red} {text}"),
            2,
            "expected a PPM (P6 or P3), found \"po\"\n",
        ),
        (
            format!("zspec compare {red} /nonexistent"),
            2,
            "zspec compare: cannot open /nonexistent: No such file or directory\n",
        ),
        (
            format!("zspec compare --min-agreement 101 {red} {red}"),
            2,
            "zspec: invalid value '101' for '--min-agreement <MIN_AGREEMENT>': `101` is not \
             a percentage from 0 to 100\n",
        ),
    ];
    for (cmd, status, message) in cases {
        let out = sh(&cmd, b"");
        assert_eq!(out.status.code(), Some(status), "{cmd}: {}", stderr(&out));
        assert!(stderr(&out).ends_with(message), "{cmd}: {}", stderr(&out));
    }
}

/// #8: when one output's reader went away, the other output was left without END. Now
/// it gets the whole stream: the same as when both readers stay.
#[test]
fn when_one_reader_goes_the_other_branch_is_finished() {
    let dir = tempfile::tempdir().unwrap();
    let (kept, whole) = (dir.path().join("kept"), dir.path().join("whole"));
    let scene = "scene environment --polygons 20000 --seed 3 | viewxf";
    let out = sh(
        &format!(
            "{scene} | splitter --text x=0 - {} | head -c 10",
            kept.display()
        ),
        b"",
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(out.stderr.is_empty());
    let out = sh(
        &format!(
            "{scene} | splitter --text x=0 /dev/null {}",
            whole.display()
        ),
        b"",
    );
    assert!(out.status.success());
    let kept = std::fs::read_to_string(kept).unwrap();
    assert!(kept.ends_with("\nEND\n"));
    assert_eq!(kept, std::fs::read_to_string(whole).unwrap());
}

/// #9: `zbuf /tmp` said `Is a directory (os error 21): Is a directory (os error 21)`.
#[test]
fn an_os_error_is_said_once() {
    let out = sh("zbuf /tmp", b"");
    assert_eq!(out.status.code(), Some(3));
    assert_eq!(stderr(&out), "zbuf: /tmp: Is a directory\n");
}

/// #11: "Add `--text` to any stage", but zbuf and zspec refused it. For the stages that
/// write pictures it means plain PPM (P3): the same pixels as text.
#[test]
fn text_on_the_picture_stages_writes_plain_ppm() {
    let size = "6x4";
    let binary = sh(
        &format!("scene penetrating --frames 2 | {}", pipeline(size)),
        b"",
    );
    let plain = sh(
        &format!("scene penetrating --frames 2 | {} --text", pipeline(size)),
        b"",
    );
    assert!(binary.status.success() && plain.status.success());
    assert!(plain.stdout.starts_with(b"P3\n6 4\n255\n"));
    assert!(plain.stdout.is_ascii());
    let frames = parse_ppm_stream(&binary.stdout).unwrap();
    assert_eq!(frames.len(), 2);
    assert_eq!(parse_ppm_stream(&plain.stdout).unwrap(), frames);
    // The reference alike, and to files: -o f%d.ppm --text writes P3 files.
    let exact = sh(
        "scene penetrating --frames 2 | zspec --size 6x4 --text",
        b"",
    );
    assert!(exact.stdout.starts_with(b"P3\n6 4\n255\n"));
    assert_eq!(parse_ppm_stream(&exact.stdout).unwrap(), frames);
    let dir = tempfile::tempdir().unwrap();
    let files = sh(
        &format!(
            "scene penetrating --frames 2 | {} --text -o {}/f%d.ppm",
            pipeline(size),
            dir.path().display()
        ),
        b"",
    );
    assert!(files.status.success(), "{}", stderr(&files));
    let f1 = std::fs::read(dir.path().join("f1.ppm")).unwrap();
    assert!(f1.starts_with(b"P3\n"));
    assert_eq!(parse_ppm_stream(&f1).unwrap()[0], frames[1]);
}

/// A review: `render.sh /tmp` let `cat` say `cat: /tmp: Is a directory` and then
/// said only that it could not keep the scene; now one line in the stages' words, status 3,
/// at any depth (`--depth auto` copies a scene before looking at it; a given depth does not).
#[test]
fn render_sh_says_a_folder_is_not_a_scene() {
    for depth in ["auto", "0", "2"] {
        let out = sh(&format!("scripts/render.sh --depth {depth} /tmp"), b"");
        assert_eq!(out.status.code(), Some(3), "--depth {depth}");
        assert_eq!(
            stderr(&out),
            "render.sh: /tmp: Is a directory\n",
            "--depth {depth}"
        );
        assert!(out.stdout.is_empty());
    }
}

// --- What a newcomer tripped on (the newcomer's list). The others
// have their tests beside their code: `frames --from` past the end
// (bins/frames/tests/cli.rs), `zbuf -o one.png` on a movie (bins/zbuf/tests/cli.rs and
// exit_codes.rs), the OBJ reader's four (bins/scene/src/obj.rs), `--by frames -o`,
// once refused and now writing the files (movies.rs, `resume_after_sigint_…`).

/// `render.sh --subtree 3` without `--depth` failed with `line 237: auto: unbound
/// variable`, status 1: a subtree is cut by the tree's depth, which must be given.
#[test]
fn subtree_without_a_depth_is_a_usage_error() {
    let out = sh("scripts/render.sh --subtree 3 < /dev/null", b"");
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        stderr(&out),
        "render.sh: --subtree needs --depth N, the depth of the tree it is part of\n"
    );
}

/// `--size 65536x65536` was refused only after abuf had computed for over 60 s, with
/// status 1. Too large for this machine is status 3, said at the header: by the merger
/// in a render, and by each leaf stage on its own (the address space limited to 8 GB,
/// so that 3 bytes a pixel of 65536x65536 cannot be had on any machine).
#[test]
fn a_screen_too_large_for_this_machine_is_refused_at_the_header() {
    let started = std::time::Instant::now();
    let out = sh(
        "scripts/render.sh --size 65536x65536 --depth 1 --aa abuf > /dev/null",
        b"",
    );
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    assert!(
        stderr(&out).ends_with("render.sh: zbuf failed (status 3)\n"),
        "{}",
        stderr(&out)
    );
    assert!(
        started.elapsed() < std::time::Duration::from_secs(20),
        "took {:?}",
        started.elapsed()
    );
    for (stage, bytes, what) in [
        ("scanconv --resolve", "48 GiB (12", "depth and colour"),
        ("warnock", "12 GiB (3", "at least a resolved colour"),
        ("scanline", "12 GiB (3", "at least a resolved colour"),
        ("supersample", "12 GiB (3", "at least a resolved colour"),
    ] {
        // The input stays open after the header: a stage that waited for polygons
        // instead of refusing would be stopped after 20 s and fail here.
        let mut words = stage.split(' ');
        let program = pipeline_tests::bin(words.next().unwrap());
        let mut child = std::process::Command::new("bash")
            .arg("-c")
            .arg("ulimit -v 8000000; exec \"$0\" \"$@\"")
            .arg(&program)
            .args(words)
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let mut input = child.stdin.take().unwrap();
        std::io::Write::write_all(&mut input, b"polypipe 1 screen 65536 65536\n").unwrap();
        let (status, _) =
            pipeline_tests::wait_within(&mut child, std::time::Duration::from_secs(20), || {
                format!("{stage} waited for polygons instead of refusing the screen")
            });
        drop(input);
        let mut err = String::new();
        std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
        let out = std::process::Output {
            status,
            stdout: Vec::new(),
            stderr: err.into_bytes(),
        };
        let name = stage.split(' ').next().unwrap();
        assert_eq!(out.status.code(), Some(3), "{stage}: {}", stderr(&out));
        assert!(
            stderr(&out).starts_with(&format!(
                "{name}: a 65536x65536 screen needs {bytes} bytes a pixel: {what}), more \
                 memory than this machine can give ("
            )),
            "{stage}: {}",
            stderr(&out)
        );
    }
}

/// `chart.sh` ran cargo on every run; now it runs it only when a binary is missing or
/// older than its sources (render.sh's check, scripts/lib/binaries.sh). A `cargo` first
/// on PATH that records being run shows it.
#[test]
fn chart_sh_runs_no_cargo_when_the_binaries_are_current() {
    let dir = tempfile::tempdir().unwrap();
    // Once with the real cargo, which leaves the binaries and the freshness stamp
    // current.
    let out = sh("scripts/chart.sh --help > /dev/null", b"");
    assert!(out.status.success(), "{}", stderr(&out));
    let fake = dir.path().join("cargo");
    std::fs::write(
        &fake,
        format!("#!/bin/sh\ntouch '{}/ran'\nexit 1\n", dir.path().display()),
    )
    .unwrap();
    std::process::Command::new("chmod")
        .arg("+x")
        .arg(&fake)
        .status()
        .unwrap();
    let out = sh(
        &format!(
            "PATH='{}':$PATH scripts/chart.sh --help | head -n 1",
            dir.path().display()
        ),
        b"",
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(!out.stdout.is_empty());
    assert!(!dir.path().join("ran").exists(), "chart.sh ran cargo");
}
