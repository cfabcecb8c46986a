//! `warnock`, Warnock's area subdivision as a leaf stage (Newman and Sproull 1973, 14.3 and Appendix
//! VI): its exact records on a hand-written screen stream, its `--stats`, its refusals of
//! bad input, and frames byte-identical to the z-buffer leaf's (`scanconv --resolve`) on
//! the test scenes at tree depths 0 to 2, including the scenes where area subdivision
//! slows down: many small polygons, slivers, penetrating planes that subdivide to pixels.

use assert_cmd::Command;
use pipeline_tests::{bin, run, sh};

/// Two frames on an 8×6 screen: a red background (depth 0.5), a green triangle in front
/// (0.25), and a blue quadrilateral whose depth runs from 0.2 at X = 1 to 0.8 at X = 4:
/// in front of the red at column 1 (centre depth 0.3), as deep as it at column 2 (0.5: a
/// tie, the red is earlier and stays), behind it at column 3. Then a frame of one square.
const STREAM: &str = "polypipe 1 screen 8 6
colour 255 0 0
0 0 0.5
8 0 0.5
8 6 0.5
0 6 0.5
NEXT.POLYGON
colour 0 255 0
2 1 0.25
5 1 0.25
5 4 0.25
NEXT.POLYGON
colour 0 0 255
1 2 0.2
4 2 0.8
4 5 0.8
1 5 0.2
NEXT.FRAME
colour 9 9 9
1 1 0.5
3 1 0.5
3 3 0.5
1 3 0.5
END
";

const RUNS: &str = "polypipe 2 fragments 8 6
run 0 0 8 255 0 0
run 1 0 2 255 0 0
run 1 2 5 0 255 0
run 1 5 8 255 0 0
run 2 0 1 255 0 0
run 2 1 2 0 0 255
run 2 2 3 255 0 0
run 2 3 5 0 255 0
run 2 5 8 255 0 0
run 3 0 1 255 0 0
run 3 1 2 0 0 255
run 3 2 4 255 0 0
run 3 4 5 0 255 0
run 3 5 8 255 0 0
run 4 0 1 255 0 0
run 4 1 2 0 0 255
run 4 2 8 255 0 0
run 5 0 8 255 0 0
NEXT.FRAME
run 1 1 3 9 9 9
run 2 1 3 9 9 9
END
";

#[test]
fn exact_runs_and_stats_on_a_hand_written_stream() {
    let out = Command::new(bin("warnock"))
        .args(["--text", "--stats"])
        .write_stdin(STREAM)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(String::from_utf8_lossy(&out.stdout), RUNS);
    // Frame 1: the 8×6 screen in a square of 8. The red surrounds it, the green and
    // blue are in front of it in places: subdivided; of the four quarters (clipped to
    // the screen) the right two have the green or nothing in front of the red, the left
    // two are subdivided again into 4 + 2 windows. Frame 2: the square fills the first
    // window, its own bounding box.
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "warnock: 4 polygons in, 2 frames, 20 runs out, windows by depth: 2 4 6; 0 empty, \
         0 single pixels, 0 one polygon, 4 surrounded, 5 one in front of a surrounder, \
         3 subdivided; 22 polygons looked at, 2 hidden by a surrounder, 0 ZMIN exits \
         leaving 0 unexamined\n\
         @stats warnock polygons_in=4 frames=2 runs_out=20 windows_by_depth=2,4,6 empty=0 \
         single_pixels=0 one_polygon=0 surrounded=4 in_front=5 subdivided=3 looked_at=22 \
         hidden=2 zmin_exits=0 zmin_skipped=0\n"
    );
    // The z-buffer leaf sends the same records.
    let zbuf = Command::new(bin("scanconv"))
        .args(["--text", "--resolve"])
        .write_stdin(STREAM)
        .output()
        .unwrap();
    assert_eq!(String::from_utf8_lossy(&zbuf.stdout), RUNS);
}

#[test]
fn bad_input_is_refused_with_status_1() {
    let cases = [
        (
            "polypipe 1 screen 8 8\ncolour 1 2 3\n0 0 0.5\n1e6 0 0.5\n0 5 0.5\nEND\n",
            "warnock: frame 0, polygon 0: vertex 1 at (1e6, 0e0) lies far outside the 8x8 \
             screen; clip in eye space (clipplane left, right, top, bottom) before persp\n",
        ),
        (
            "polypipe 1 eye\ncolour 1 2 3\n0 0 0.5\n1 0 0.5\n0 5 0.5\nEND\n",
            "warnock: input is eye-space, expected screen-space; put persp first\n",
        ),
        (
            "polypipe 1 screen 8 8\ncolour 1 2 3\n0 0 0.5\n",
            "warnock: line 3, column 8: the stream ends without END (cut short?)\n",
        ),
        (
            "hello\n",
            "warnock: line 1, column 1: not a polypipe stream: expected the header \
             `polypipe 1 SPACE`, found `hello`\n",
        ),
    ];
    for (input, message) in cases {
        let out = Command::new(bin("warnock"))
            .arg("--text")
            .write_stdin(input)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1), "{input}");
        assert_eq!(String::from_utf8_lossy(&out.stderr), message, "{input}");
    }
    let out = Command::new(bin("warnock"))
        .arg("--windows")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
}

/// Renders a world-space scene (a shell command writing it) through a splitter tree of
/// `depth` built by hand, each leaf `persp | LEAF`, merged by zbuf: render.sh's tiles
/// mode with the leaf command given. Returns the PPM stream and the leaves' stderr.
fn tree(scene: &str, size: &str, depth: u32, leaf: &str) -> (Vec<u8>, String) {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().display();
    let mut script =
        format!("set -e; cd {d}; {scene} | viewxf --size {size} | clipbatch > node-1\n");
    for node in 1..(1u32 << depth) {
        script += &format!(
            "splitter --node {node} --depth {depth} --size {size} node-{} node-{} < node-{node}\n",
            2 * node,
            2 * node + 1
        );
    }
    let leaves: Vec<u32> = ((1u32 << depth)..(2u32 << depth)).collect();
    for l in &leaves {
        script += &format!("persp --size {size} < node-{l} | {leaf} > leaf-{l}\n");
    }
    let inputs: Vec<String> = leaves.iter().map(|l| format!("leaf-{l}")).collect();
    script += &format!("zbuf {}\n", inputs.join(" "));
    let out = sh(&script, b"");
    assert!(
        out.status.success(),
        "{script}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    (
        out.stdout,
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The windows `warnock --stats` reports at each depth, from its record.
fn windows_by_depth(stats: &str) -> Vec<u64> {
    pipeline_tests::stat_list(stats, "windows_by_depth")
}

/// The count `key` in warnock's stats record (`single_pixels`, …).
fn count(stats: &str, key: &str) -> u64 {
    pipeline_tests::stat(stats, key)
}

const SCENES: &[&str] = &[
    "scene penetrating",
    "scene triangle-square",
    "scene spheres",
    "scene building",
    "scene mesh",
    "scene sphere --frames 3",
    "scene environment --polygons 1000 --clipped 0.2 --depth-complexity 2 --seed 3 --frames 2",
];

#[test]
fn frames_are_the_zbuffer_leafs_at_depths_0_to_2() {
    for scene in SCENES {
        for depth in 0..=2 {
            let (want, _) = tree(scene, "96x80", depth, "scanconv --resolve");
            let (got, _) = tree(scene, "96x80", depth, "warnock");
            assert!(!want.is_empty());
            assert!(want == got, "{scene} at depth {depth}: frames differ");
        }
    }
}

/// Where area subdivision slows down: it stays exact, and its
/// counters show why it is slow.
mod where_it_slows {
    use super::*;

    /// Many small polygons: every one of them has its edges inside windows down to
    /// single pixels, so pixel windows run to thousands, and windows are visited at
    /// every level down to one pixel (a 128×128 screen: levels 0 to 7).
    #[test]
    fn many_small_polygons() {
        let scene = "scene environment --polygons 4000 --clipped 0 --depth-complexity 1 --seed 7";
        let (want, _) = tree(scene, "128x128", 0, "scanconv --resolve");
        let (got, stats) = tree(scene, "128x128", 0, "warnock --stats");
        assert!(want == got, "frames differ");
        let by_depth = windows_by_depth(&stats);
        assert_eq!(by_depth.len(), 8, "{stats}");
        assert!(count(&stats, "single_pixels") > 2000, "{stats}");
    }

    /// Slivers: a fan of triangles a fraction of a pixel wide in front of a background.
    /// Two slivers in one window fail the Thinker, and windows along them are split down
    /// to pixels; the picture is the z-buffer's.
    #[test]
    fn slivers() {
        let mut s = String::from(
            "polypipe 1 screen 64 64\ncolour 10 10 10\n0 0 0.9\n64 0 0.9\n64 64 0.9\n0 64 0.9\n",
        );
        for k in 0..40 {
            let a = k as f64 * std::f64::consts::PI / 80.0;
            let (x, y) = (1.0 + 62.0 * a.cos(), 1.0 + 62.0 * a.sin());
            let (x2, y2) = (x + 0.3 * a.sin(), y - 0.3 * a.cos());
            s += &format!(
                "NEXT.POLYGON\ncolour {} 200 0\n1 1 0.{}\n{x} {y} 0.5\n{x2} {y2} 0.5\n",
                k * 6,
                k + 10
            );
        }
        s += "END\n";
        let out = Command::new(bin("warnock"))
            .arg("--stats")
            .write_stdin(s.as_str())
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(0));
        let want = Command::new(bin("scanconv"))
            .arg("--resolve")
            .write_stdin(s.as_str())
            .output()
            .unwrap();
        assert!(out.stdout == want.stdout, "runs differ");
        let stats = String::from_utf8_lossy(&out.stderr);
        // 64×64: levels 0 to 6, all visited: windows holding two slivers are split
        // again and again. The Looker decides on the polygons' edges, as the listing's
        // does, not on the pixels they cover: a window that a sliver's edge passes
        // through between its centres holds it as an intersector, so windows are split
        // along every edge down to pixels (508 of them; deciding on covered pixels, as
        // this stage did before, split down to 32). An edge within the Looker's margin of
        // 1/64 pixel of a window's centres counts as passing through it (coverage is
        // decided on snapped vertices; with a margin of 1e-6 pixel, 480 pixels).
        assert_eq!(
            windows_by_depth(&stats),
            vec![1, 4, 16, 60, 216, 744, 508],
            "{stats}"
        );
        assert_eq!(count(&stats, "single_pixels"), 508, "{stats}");
        assert_eq!(count(&stats, "subdivided"), 387, "{stats}");
    }

    /// Deep subdivision: two planes that penetrate along a line across the screen fail
    /// every window the line crosses, down to pixels (the implied edge of 14.3.3,
    /// Figure 14-18), and are exact.
    #[test]
    fn penetrating_planes_subdivide_to_pixels_along_their_crossing() {
        let input = "polypipe 1 screen 64 64
colour 200 0 0
0 0 0.2
64 0 0.6
64 64 0.6
0 64 0.2
NEXT.POLYGON
colour 0 0 200
0 0 0.55
64 0 0.31
64 64 0.31
0 64 0.55
END
";
        let out = Command::new(bin("warnock"))
            .args(["--stats", "--text"])
            .write_stdin(input)
            .output()
            .unwrap();
        let want = Command::new(bin("scanconv"))
            .args(["--resolve", "--text"])
            .write_stdin(input)
            .output()
            .unwrap();
        assert_eq!(
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&want.stdout)
        );
        // The planes cross at X = 35 (0.2 + 0.4·35/64 = 0.55 − 0.24·35/64): columns
        // 0..35 red, 35..64 blue, on every row.
        let runs: Vec<String> = String::from_utf8_lossy(&out.stdout)
            .lines()
            .filter(|l| l.starts_with("run "))
            .map(|l| {
                l.split_once(' ')
                    .unwrap()
                    .1
                    .split_once(' ')
                    .unwrap()
                    .1
                    .to_string()
            })
            .collect();
        assert_eq!(runs.len(), 128);
        assert!(
            runs.iter()
                .all(|r| r == "0 35 200 0 0" || r == "35 64 0 0 200"),
            "{runs:?}"
        );
        let stats = String::from_utf8_lossy(&out.stderr);
        // Of each level's windows, one per band of rows holds the crossing (columns
        // 32..64, 32..48, 32..40, 32..36, 34..36) and is subdivided: 1, 2, 4, 8, 16, 32
        // of them; then columns 34 and 35 of every row are pixel windows.
        assert_eq!(
            windows_by_depth(&stats),
            vec![1, 4, 8, 16, 32, 64, 128],
            "{stats}"
        );
        assert_eq!(count(&stats, "single_pixels"), 128, "{stats}");
    }
}

#[test]
fn help_says_what_it_is() {
    let help = run("warnock --help");
    let help = String::from_utf8_lossy(&help);
    assert!(help.contains("Warnock's area subdivision"), "{help}");
    assert!(help.contains("--stats"), "{help}");
}

/// Scenes a user can make in a minute to break a hidden-surface method, at a
/// size a test can afford: Warnock's cost is the windows the picture needs, not the
/// polygons stacked behind (`bench warnock` measures the full-size ones).
mod hostile {
    use super::*;

    /// `n` polygons as a screen-space text stream on a `w`×`h` screen.
    fn stream(w: u32, h: u32, polygons: impl Iterator<Item = (u32, Vec<[f64; 3]>)>) -> String {
        let mut s = format!("polypipe 1 screen {w} {h}\n");
        for (k, (colour, vertices)) in polygons.enumerate() {
            if k > 0 {
                s += "NEXT.POLYGON\n";
            }
            s += &format!(
                "colour {} {} {}\n",
                128 + colour % 128,
                (colour / 128) % 256,
                colour % 251
            );
            for [x, y, z] in vertices {
                s += &format!("{x} {y} {z}\n");
            }
        }
        s + "END\n"
    }

    fn warnock_and_zbuf(input: &str) -> (String, Vec<u8>, Vec<u8>) {
        let out = Command::new(bin("warnock"))
            .arg("--stats")
            .write_stdin(input)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(0));
        let want = Command::new(bin("scanconv"))
            .arg("--resolve")
            .write_stdin(input)
            .output()
            .unwrap();
        (
            String::from_utf8_lossy(&out.stderr).into_owned(),
            out.stdout,
            want.stdout,
        )
    }

    /// 2,000 full-screen squares at distinct depths, shuffled: the nearest surrounds the
    /// first window, the ZMIN exit passes over the other 1,999, one window is drawn.
    #[test]
    fn a_stack_is_one_window() {
        let n = 2000u32;
        let input = stream(
            200,
            150,
            (0..n).map(|i| {
                let k = (i * 1237) % n;
                let z = 0.2 + 0.6 * k as f64 / n as f64;
                (
                    k,
                    vec![
                        [0.0, 0.0, z],
                        [200.0, 0.0, z],
                        [200.0, 150.0, z],
                        [0.0, 150.0, z],
                    ],
                )
            }),
        );
        let (stats, got, want) = warnock_and_zbuf(&input);
        assert!(got == want, "frames differ");
        assert_eq!(windows_by_depth(&stats), vec![1], "{stats}");
        assert_eq!(count(&stats, "looked_at"), 1, "{stats}");
        assert_eq!(count(&stats, "zmin_exits"), 1, "{stats}");
        assert_eq!(count(&stats, "zmin_skipped"), 1999, "{stats}");
    }

    /// 20,000 tiny triangles around one pixel centre, at distinct depths: the windows
    /// that hold them are carried down to that pixel, which is decided among them.
    #[test]
    fn a_pinhead_is_decided_at_its_pixel() {
        let n = 20000u32;
        let input = stream(
            64,
            64,
            (0..n).map(|i| {
                let k = (i * 12361) % n;
                let z = 0.2 + 0.6 * k as f64 / n as f64;
                let a = i as f64 * 2.399;
                let v = (0..3)
                    .map(|j| {
                        let b = a + j as f64 * 2.0944;
                        let r = 0.3 + 0.25 * ((i * 7 + j) % 11) as f64 / 11.0;
                        [32.5 + r * b.cos(), 31.5 + r * b.sin(), z]
                    })
                    .collect();
                (k, v)
            }),
        );
        let (stats, got, want) = warnock_and_zbuf(&input);
        assert!(got == want, "frames differ");
        // Levels 0 to 6 of a 64×64 screen, a few windows each around the pin.
        let by_depth = windows_by_depth(&stats);
        assert!(by_depth.iter().sum::<u64>() < 100, "{stats}");
        assert!(count(&stats, "single_pixels") < 40, "{stats}");
    }
}
