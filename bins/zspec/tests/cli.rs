//! zspec's command line: exact PPM bytes for small text scenes, the comparison's report
//! and exit statuses, and refusals.

use assert_cmd::Command;
use predicates::str::contains;

fn zspec() -> Command {
    Command::cargo_bin("zspec").unwrap()
}

/// With the default camera on a 4x4 screen, device point (X, Y) at z_w = 4 (z_e = 16,
/// w = 10) is world (5X − 10, 10 − 5Y, 4). This triangle's corners are device (0,0),
/// (4,0), (0,4); its hypotenuse passes through four pixel centres, a right edge, so
/// they stay out.
const TRIANGLE: &str = "polypipe 1 world
colour 255 0 0
-10 10 4
10 10 4
-10 -10 4
END
";

fn ppm(w: u32, h: u32, rows: &[&str]) -> Vec<u8> {
    let mut out = format!("P6\n{w} {h}\n255\n").into_bytes();
    for row in rows {
        for ch in row.chars() {
            out.extend_from_slice(match ch {
                'R' => &[255, 0, 0],
                'G' => &[0, 255, 0],
                'b' => &[10, 20, 30],
                _ => &[0, 0, 0],
            });
        }
    }
    out
}

#[test]
fn triangle_exact_bytes() {
    zspec()
        .args(["--size", "4x4"])
        .write_stdin(TRIANGLE)
        .assert()
        .success()
        .stdout(ppm(4, 4, &["RRR.", "RR..", "R...", "...."]));
}

#[test]
fn background_frames_and_a_file_argument() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.txt");
    // Frame 0: the triangle; frame 1: a green square over device [1,3]x[1,3].
    let scene = TRIANGLE.replace(
        "END",
        "NEXT.FRAME\ncolour 0 255 0\n-5 5 4\n5 5 4\n5 -5 4\n-5 -5 4\nEND",
    );
    std::fs::write(&path, scene).unwrap();
    let mut want = ppm(4, 4, &["RRRb", "RRbb", "Rbbb", "bbbb"]);
    want.extend(ppm(4, 4, &["bbbb", "bGGb", "bGGb", "bbbb"]));
    zspec()
        .args(["--size", "4x4", "--background", "10,20,30"])
        .arg(&path)
        .assert()
        .success()
        .stdout(want);
}

#[test]
fn camera_options_are_viewxfs() {
    // Moving the eye back to z = 36 (z_e = 32 for the triangle, w = 20) halves it about
    // the centre: corners device (1,1), (3,1), (1,3); yon moves out to keep it.
    zspec()
        .args(["--size", "4x4", "--eye", "0,0,36", "--yon", "40"])
        .write_stdin(TRIANGLE)
        .assert()
        .success()
        .stdout(ppm(4, 4, &["....", ".R..", "....", "...."]));
    // Yon at 15 puts the triangle (z_e = 16) beyond it.
    zspec()
        .args(["--size", "4x4", "--yon", "15"])
        .write_stdin(TRIANGLE)
        .assert()
        .success()
        .stdout(ppm(4, 4, &["....", "....", "....", "...."]));
}

#[test]
fn refusals() {
    zspec()
        .write_stdin("polypipe 1 eye aspect 1 hither 1 yon 30\nEND\n")
        .assert()
        .code(1)
        .stderr(contains("zspec: input is eye-space, expected world-space"));
    zspec()
        .write_stdin("polypipe 1 world\ncolour 1 2 3\n0 0\nEND\n")
        .assert()
        .code(1)
        .stderr(
            "zspec: line 4, column 1: expected z of vertex 0 (3 numbers a vertex in world \
             space), found `END`\n",
        );
    zspec()
        .args(["--eye", "0,0,0"])
        .write_stdin(TRIANGLE)
        .assert()
        .code(2)
        .stderr(contains("the eye and the point looked at must differ"));
    zspec()
        .arg("/nonexistent/scene")
        .assert()
        .code(3)
        .stderr(contains("zspec: cannot open /nonexistent/scene"));
}

#[test]
fn compare_reports_and_decides() {
    let dir = tempfile::tempdir().unwrap();
    let a = dir.path().join("a.ppm");
    let b = dir.path().join("b.ppm");
    // Two frames of 2x2; b differs from a in one pixel of frame 1.
    let mut pa = ppm(2, 2, &["RR", "GG"]);
    pa.extend(ppm(2, 2, &["RG", "GR"]));
    let mut pb = ppm(2, 2, &["RR", "GG"]);
    pb.extend(ppm(2, 2, &["RG", "GG"]));
    std::fs::write(&a, &pa).unwrap();
    std::fs::write(&b, &pb).unwrap();
    let report = "frame 0: 4 pixels, 0 differ, 100.0000% agree\n\
                  frame 1: 4 pixels, 1 differ, 75.0000% agree\n";
    zspec()
        .arg("compare")
        .args([&a, &b])
        .assert()
        .code(1)
        .stdout(report)
        .stderr("zspec compare: 1 of 2 frames agree on fewer than 99.95% of pixels (frames [1])\n");
    zspec()
        .args(["compare", "--min-agreement", "75"])
        .args([&a, &b])
        .assert()
        .success()
        .stdout(report);
    // Different numbers of frames: nothing to compare.
    std::fs::write(&b, ppm(2, 2, &["RR", "GG"])).unwrap();
    zspec()
        .arg("compare")
        .args([&a, &b])
        .assert()
        .code(1)
        .stderr("zspec compare: the streams have 2 and 1 frames\n");
    // A cut-short stream is trouble (cmp's status 2), located by file and frame.
    std::fs::write(&b, &pa[..pa.len() - 1]).unwrap();
    zspec()
        .arg("compare")
        .args([&a, &b])
        .assert()
        .code(2)
        .stdout("")
        .stderr(format!(
            "zspec compare: {}: frame 1: the PPM ends before the 2x2 pixels (11 of 12 \
             bytes; cut short?)\n",
            b.display()
        ));
}

#[test]
fn help_has_an_example() {
    zspec()
        .arg("--help")
        .assert()
        .success()
        .stdout(contains("zspec compare ref.ppm pipe.ppm"));
}
