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
        "polypipe 2 fragments 8 4\n{}{}{}{}NEXT.FRAME\nrun 1 1 3 0 0 255\nrun 2 2 3 0 0 255\nEND\n",
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
        // Frame 0, per line: 2 segments; sample spans 0–2, 2–6, 6–8. In 2–6 on line 0:
        // green coming in against red (1 test), red tested at 3 and at 5 (2: a simple
        // intersection), one test at 4, the only column between (1: XINTER computed), the
        // fold at 5 (1). On lines 1–3 the
        // line above predicts: the crossing at 5 (2 tests: red in front at 5, not at 4)
        // and red in front at 5 (1). Frame 1: lines 1 and 2, one segment each. Each
        // polygon's segment is merged into the list once; nothing moves.
        .stderr(
            "scanline: 3 polygons in, 2 frames, 18 runs out, 6 scan lines, 10 segments, \
             14 sample spans, 18 segments examined, 23 depth comparisons, 4 crossings; \
             minor sort: 3 segments merged in, 0 re-sorted, 0 swaps; predicted from the \
             line above: 3 fronts held, 0 failed, 3 crossings held, 0 failed; \
             0 midpoint subdivisions; 1 crossings computed (XINTER), 0 of them searched\n\
             @stats scanline polygons_in=3 frames=2 runs_out=18 scan_lines=6 segments=10 \
             sample_spans=14 segments_examined=18 depth_comparisons=23 crossings=4 merged=3 \
             resorted=0 swaps=0 fronts_predicted=3 fronts_mispredicted=0 crossings_predicted=3 \
             crossings_mispredicted=0 midpoint_subdivisions=0 crossings_computed=1 \
             crossings_searched=0\n",
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

/// The picture of `scene` (a shell command writing a world-space stream) through a
/// splitter tree of `depth` levels built by hand as render.sh builds it (files instead
/// of named pipes), each leaf `persp | LEAF`, merged by zbuf: render.sh's `--hse` for
/// any leaf command.
fn tree(scene: &str, depth: u32, leaf: &str) -> Vec<u8> {
    let script = format!(
        r#"set -e
        d=$(mktemp -d); trap 'rm -rf "$d"' EXIT
        {scene} | viewxf --size 64x64 | clipplane left | clipplane right | clipplane top \
            | clipplane bottom | clipplane hither | clipplane yon > "$d/n1"
        for ((k = 1; k < 1 << {depth}; k++)); do
            splitter --node $k --depth {depth} --size 64x64 "$d/n$((2 * k))" "$d/n$((2 * k + 1))" < "$d/n$k"
        done
        leaves=()
        for ((l = 0; l < 1 << {depth}; l++)); do
            persp --size 64x64 < "$d/n$(((1 << {depth}) + l))" | {leaf} > "$d/leaf$l"
            leaves+=("$d/leaf$l")
        done
        zbuf "${{leaves[@]}}""#
    );
    let out = sh(&script, b"");
    assert!(
        out.status.success() && out.stderr.is_empty(),
        "{scene} at depth {depth} with {leaf}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// The cases common to every method (docs/degenerate.md's scenes:
/// coincident polygons, polygons edge-on, huge and tiny coordinates, horizontal edges
/// and local minima, slivers, concave pieces, bowties) and the scenes of the suite, at
/// splitter depths 0 to 3: scanline's frames are the z-buffer leaf's to the byte.
#[test]
fn every_scene_at_every_depth_is_the_zbuffers() {
    let mut scenes: Vec<String> = [
        "scene penetrating",
        "scene spheres",
        "scene building",
        "scene triangle-square",
        "scene mesh --frames 2",
        "scene environment --polygons 1000 --depth-complexity 4 --seed 3 --frames 2",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let mut files: Vec<String> =
        std::fs::read_dir(pipeline_tests::repo_root().join("examples/degenerate"))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".txt"))
            .collect();
    files.sort();
    assert!(files.len() >= 15, "{files:?}");
    scenes.extend(files.iter().map(|f| format!("cat examples/degenerate/{f}")));
    for scene in &scenes {
        let want = tree(scene, 0, "scanconv --resolve");
        for depth in 0..=3 {
            assert!(
                tree(scene, depth, "scanline") == want,
                "{scene} at depth {depth}"
            );
        }
    }
}

/// A 128×16 screen of `k` columns, each holding two quads whose depths cross in its
/// middle (the bench's section 1).
fn crossings(k: u32) -> String {
    let mut s = String::from("polypipe 1 screen 128 16\n");
    let w = 128.0 / k as f64;
    for i in 0..k {
        let (x0, x1) = (i as f64 * w, (i + 1) as f64 * w);
        for (j, (za, zb)) in [(0.2, 0.8), (0.8, 0.2)].into_iter().enumerate() {
            if i + j as u32 > 0 {
                s.push_str("NEXT.POLYGON\n");
            }
            s.push_str(&format!(
                "colour {} {} 90\n{x0} 0 {za}\n{x1} 0 {zb}\n{x1} 16 {zb}\n{x0} 16 {za}\n",
                i % 256,
                j * 200
            ));
        }
    }
    s.push_str("END\n");
    s
}

/// Scanline's own hard case: many crossings per line. 64 crossings on
/// each of 16 lines: exactly 64 splits a line, the z-buffer's picture, and the counters
/// that say what it cost.
#[test]
fn many_crossings_per_line() {
    let stream = crossings(64);
    let a = sh("scanline --text --stats", stream.as_bytes());
    let b = sh("scanconv --resolve --text", stream.as_bytes());
    assert!(a.status.success() && b.status.success());
    assert_eq!(a.stdout, b.stdout);
    // Each line: 128 segments in 64 sample spans two columns wide; in each span the
    // front at its left end (1 test), the other in front at the next column (1), the
    // split, the front there (1). From the second line on, the line above's front is
    // tried first and holds, every time.
    assert_eq!(
        String::from_utf8_lossy(&a.stderr),
        "scanline: 128 polygons in, 1 frames, 2048 runs out, 16 scan lines, 2048 segments, \
         1024 sample spans, 2048 segments examined, 3072 depth comparisons, 1024 crossings; \
         minor sort: 128 segments merged in, 0 re-sorted, 0 swaps; predicted from the line \
         above: 1920 fronts held, 0 failed, 0 crossings held, 0 failed; \
         0 midpoint subdivisions; 0 crossings computed (XINTER), 0 of them searched\n\
         @stats scanline polygons_in=128 frames=1 runs_out=2048 scan_lines=16 segments=2048 \
         sample_spans=1024 segments_examined=2048 depth_comparisons=3072 crossings=1024 \
         merged=128 resorted=0 swaps=0 fronts_predicted=1920 fronts_mispredicted=0 \
         crossings_predicted=0 crossings_mispredicted=0 midpoint_subdivisions=0 \
         crossings_computed=0 crossings_searched=0\n"
    );
}

/// Near-equal depths: planes within a few tie widths (2^-30 of the depth) of each
/// other, crossing and tying along a line: decided as the z-buffer decides them, to the
/// pixel.
#[test]
fn near_equal_depths() {
    let tie = 1.0 / (1u64 << 30) as f64;
    let mut s = String::from("polypipe 1 screen 64 8\n");
    for (i, (z0, z1)) in [
        (0.5, 0.5),
        // Within half a width of the first everywhere: a tie, the first stays.
        (0.5 * (1.0 - 0.4 * tie), 0.5 * (1.0 + 0.4 * tie)),
        // From 20 widths behind to 44 in front: nearer by more than a width from the
        // column whose centre is past (20 + 1)/64 of the row, X > 21.
        (0.5 * (1.0 + 20.0 * tie), 0.5 * (1.0 - 44.0 * tie)),
        (0.5, 0.5),
    ]
    .into_iter()
    .enumerate()
    {
        if i > 0 {
            s.push_str("NEXT.POLYGON\n");
        }
        s.push_str(&format!(
            "colour {} 0 0\n0 0 {z0:e}\n64 0 {z1:e}\n64 8 {z1:e}\n0 8 {z0:e}\n",
            50 * (i + 1)
        ));
    }
    s.push_str("END\n");
    let a = sh("scanline --text", s.as_bytes());
    let b = sh("scanconv --resolve --text", s.as_bytes());
    assert!(a.status.success() && b.status.success());
    assert_eq!(a.stdout, b.stdout);
    let first_line: Vec<&str> = std::str::from_utf8(&a.stdout)
        .unwrap()
        .lines()
        .filter(|l| l.starts_with("run 0 "))
        .collect();
    assert_eq!(first_line, ["run 0 0 21 50 0 0", "run 0 21 64 150 0 0"]);
}

/// `--sort-afresh`, the method without its line-to-line coherence (kept to measure what
/// the coherence buys), gives the same bytes; its counters say it kept no order and
/// predicted nothing, where the coherent method's say what it kept and predicted.
#[test]
fn without_the_coherence_the_same_bytes() {
    for scene in [
        "spheres",
        "environment --polygons 2000 --depth-complexity 4 --seed 9",
    ] {
        let leaf = |flags: &str| {
            sh(
                &format!(
                    "scene {scene} | viewxf --size 200x150 | clipbatch | persp --size 200x150 \
                     | scanline --stats {flags}"
                ),
                b"",
            )
        };
        let (a, b) = (leaf(""), leaf("--sort-afresh"));
        assert!(a.status.success() && b.status.success(), "{scene}");
        assert_eq!(a.stdout, b.stdout, "{scene}");
        let (a, b) = (
            String::from_utf8_lossy(&a.stderr),
            String::from_utf8_lossy(&b.stderr),
        );
        let coherence = [
            "merged",
            "resorted",
            "swaps",
            "fronts_predicted",
            "fronts_mispredicted",
            "crossings_predicted",
            "crossings_mispredicted",
        ];
        assert_eq!(
            coherence.map(|k| pipeline_tests::stat(&b, k)),
            [0; 7],
            "{b}"
        );
        assert!(
            pipeline_tests::stat(&a, "fronts_predicted") > 0,
            "{scene}: {a}"
        );
    }
}
