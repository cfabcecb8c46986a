//! `scanline`, Watkins's scan-line method as a leaf stage: its runs and counters on a
//! hand-written screen-space stream, the same bytes as the z-buffer leaf (`scanconv
//! --resolve`) on real scenes, and its errors on bad input.

use assert_cmd::Command;
use pipeline_tests::{bin, sh};

/// Two frames on an 8×4 screen. Frame 0: red at depth 0.5 over columns 0–5; green
/// (later) sloping from 0.2 at X = 2 to 0.8 at X = 8, so nearer at the centres 2.5–4.5
/// and farther from 5.5 (an intersection inside the overlap). Frame 1: a blue triangle.
const STREAM: &str = "polypipe 1 screen 8 4
colour 255 0 0
0 0 0.5
6 0 0.5
6 4 0.5
0 4 0.5
NEXT.POLYGON
colour 0 255 0
2 0 0.2
8 0 0.8
8 4 0.8
2 4 0.2
NEXT.FRAME
colour 0 0 255
1 1 0.5
3 1 0.5
3 3 0.5
END
";

#[test]
fn runs_and_counters_of_a_hand_written_stream() {
    let row = |y| {
        format!(
            "run {y} 0 2 255 0 0\nrun {y} 2 5 0 255 0\nrun {y} 5 6 255 0 0\nrun {y} 6 8 0 255 0\n"
        )
    };
    let want = format!(
        "polypipe 1 fragments 8 4\n{}{}{}{}NEXT.FRAME\nrun 1 1 3 0 0 255\nrun 2 2 3 0 0 255\nEND\n",
        row(0),
        row(1),
        row(2),
        row(3)
    );
    Command::new(bin("scanline"))
        .args(["--text", "--stats"])
        .write_stdin(STREAM)
        .assert()
        .success()
        .stdout(want)
        // Frame 0, per line: 2 segments; sample spans 0–2, 2–6, 6–8; in 2–6 the front at
        // column 2 (1 comparison), the solve (1), the split at 5, the front there (1),
        // the solve (1). Frame 1: lines 1 and 2, one segment each.
        .stderr(
            "scanline: 3 polygons in, 2 frames, 18 runs out, 6 scan lines, 10 segments, \
             14 sample spans, 18 segments examined, 16 depth comparisons, 4 crossings, \
             0 sample spans per pixel\n",
        );
}

#[test]
fn the_same_bytes_as_the_zbuffer_leaf() {
    // Binary and text forms, on the hand-written stream.
    for form in ["", " --text"] {
        let a = sh(&format!("scanline{form}"), STREAM.as_bytes());
        let b = sh(&format!("scanconv --resolve{form}"), STREAM.as_bytes());
        assert!(a.status.success() && b.status.success());
        assert_eq!(a.stdout, b.stdout, "form{form}");
    }
}

/// A scene's pipeline to one leaf, then `leaf`, then zbuf placing its runs.
fn frame(scene: &str, leaf: &str) -> Vec<u8> {
    let out = sh(
        &format!(
            "scene {scene} | viewxf --size 160x120 | clipplane left | clipplane right | clipplane top \
             | clipplane bottom | clipplane hither | clipplane yon | persp --size 160x120 \
             | {leaf} | zbuf"
        ),
        b"",
    );
    assert!(
        out.status.success(),
        "{scene} | {leaf}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

#[test]
fn scenes_are_the_zbuffers_to_the_byte() {
    for scene in [
        "penetrating",
        "spheres",
        "triangle-square",
        "building",
        "mesh",
        "environment --polygons 400 --depth-complexity 3 --seed 7 --frames 2",
    ] {
        let want = frame(scene, "scanconv --resolve");
        assert!(want.len() > 160 * 120 * 3, "{scene}");
        assert!(frame(scene, "scanline") == want, "{scene}");
    }
}

#[test]
fn an_off_screen_polygon_is_refused() {
    Command::new(bin("scanline"))
        .arg("--text")
        .write_stdin("polypipe 1 screen 8 4\ncolour 255 0 0\n0 0 0.5\n6 0 0.5\n6 400 0.5\nEND\n")
        .assert()
        .code(1)
        .stderr(
            "scanline: frame 0, polygon 0: vertex 2 at (6e0, 4e2) lies far outside the 8x4 \
             screen; clip in eye space (clipplane left, right, top, bottom) before persp\n",
        );
}

#[test]
fn a_wrong_header_is_refused() {
    Command::new(bin("scanline"))
        .write_stdin("polypipe 1 eye\ncolour 255 0 0\n0 0 0.5\n6 0 0.5\n6 4 0.5\nEND\n")
        .assert()
        .code(1)
        .stdout("")
        .stderr("scanline: input is eye-space, expected screen-space; put persp first\n");
    Command::new(bin("scanline"))
        .write_stdin("hello\n")
        .assert()
        .code(1)
        .stderr(
            "scanline: line 1, column 1: not a polypipe stream: expected the header \
             `polypipe 1 SPACE`, found `hello`\n",
        );
    Command::new(bin("scanline"))
        .arg("--bogus")
        .assert()
        .code(2)
        .stderr(predicates::str::starts_with(
            "scanline: unexpected argument '--bogus' found",
        ));
}
