//! zspec's command line: exact PPM bytes for small text scenes, the comparison's report
//! and exit statuses, and refusals.

use assert_cmd::Command;
use predicates::str::contains;

fn zspec() -> Command {
    Command::new(pipeline_tests::bin("zspec"))
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
        .stderr("zspec compare: 1 of 2 frames differ (frames [1])\n");
    zspec()
        .args(["compare", "--min-agreement", "75"])
        .args([&a, &b])
        .assert()
        .success()
        .stdout(report);
    // A tolerance is explicit: a quarter of a frame may differ, a fifth may not.
    zspec()
        .args(["compare", "--tolerance", "0.25"])
        .args([&a, &b])
        .assert()
        .success()
        .stdout(report);
    zspec()
        .args(["compare", "--tolerance", "0.2"])
        .args([&a, &b])
        .assert()
        .code(1)
        .stderr("zspec compare: 1 of 2 frames differ (more than --tolerance 0.2) (frames [1])\n");
    zspec()
        .args(["compare", "--tolerance", "1.5"])
        .args([&a, &b])
        .assert()
        .code(2);
    // Two empty files are trouble, not two equal streams of no frames.
    let empty = dir.path().join("empty.ppm");
    std::fs::write(&empty, b"").unwrap();
    zspec()
        .arg("compare")
        .args([&empty, &empty])
        .assert()
        .code(2)
        .stdout("")
        .stderr(format!(
            "zspec compare: {}: empty: not a PPM stream (no frame)\n",
            empty.display()
        ));
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

fn example(name: &str) -> String {
    format!("{}/../examples/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn stdout_of(args: &[&str]) -> Vec<u8> {
    let out = zspec().args(args).output().unwrap();
    assert!(
        out.status.success(),
        "zspec {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// The pixels of a one-frame binary PPM of the given size.
fn pixels_of(ppm: &[u8], w: u32, h: u32) -> Vec<[u8; 3]> {
    let header = format!("P6\n{w} {h}\n255\n");
    assert_eq!(&ppm[..header.len()], header.as_bytes());
    let body = &ppm[header.len()..];
    assert_eq!(body.len(), (w * h * 3) as usize);
    body.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect()
}

#[test]
fn samples_4_at_20x20_are_the_box_filter_of_80x80() {
    // The pipeline's ssK renders at K·W × K·H and averages each K×K block with
    // (sum + K²/2) / K²: zspec --samples K must be exactly that, byte for byte.
    for scene in ["penetrating.txt", "concave.txt", "cube.txt"] {
        let scene = example(scene);
        let fine = pixels_of(&stdout_of(&["--size", "80x80", &scene]), 80, 80);
        let mut want = b"P6\n20 20\n255\n".to_vec();
        for r in 0..20 {
            for c in 0..20 {
                let mut sum = [0u32; 3];
                for j in 0..4 {
                    for i in 0..4 {
                        let p = fine[(4 * r + j) * 80 + 4 * c + i];
                        for ch in 0..3 {
                            sum[ch] += p[ch] as u32;
                        }
                    }
                }
                want.extend(sum.map(|s| ((s + 8) / 16) as u8));
            }
        }
        let got = stdout_of(&["--samples", "4", "--size", "20x20", &scene]);
        assert!(
            got == want,
            "{scene}: --samples 4 is not the box filter of 80x80"
        );
    }
}

#[test]
fn one_sample_is_todays_output() {
    // --samples 1 takes today's path; with --edge-mask it goes through the banded
    // supersampling renderer, which must give the same bytes, and a mask all black.
    let dir = tempfile::tempdir().unwrap();
    let mask = dir.path().join("mask.ppm");
    let scene = example("penetrating.txt");
    let today = stdout_of(&[&scene]);
    assert_eq!(stdout_of(&["--samples", "1", &scene]), today);
    let banded = stdout_of(&[
        "--samples",
        "1",
        "--edge-mask",
        mask.to_str().unwrap(),
        &scene,
    ]);
    assert_eq!(banded, today);
    let mask = std::fs::read(&mask).unwrap();
    assert!(pixels_of(&mask, 500, 500).iter().all(|p| *p == [0, 0, 0]));
    // The picture is not empty: both polygons show.
    let pixels = pixels_of(&today, 500, 500);
    assert!(pixels.contains(&[255, 60, 60]) && pixels.contains(&[60, 60, 255]));
}

#[test]
fn triangle_with_4x4_samples_a_pixel_and_its_edge_mask() {
    // The hypotenuse x + y = 4 crosses the pixels c + r = 3 corner to corner; of their 16
    // samples 6 lie strictly inside, 4 on the edge (a right edge: out):
    // (255·6 + 8) / 16 = 96. The other pixels are whole.
    let dir = tempfile::tempdir().unwrap();
    let mask = dir.path().join("mask.ppm");
    let out = zspec()
        .args(["--size", "4x4", "--samples", "4", "--edge-mask"])
        .arg(&mask)
        .write_stdin(TRIANGLE)
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let r = [255, 0, 0];
    let e = [96, 0, 0];
    let k = [0, 0, 0];
    assert_eq!(
        pixels_of(&out, 4, 4),
        [r, r, r, e, r, r, e, k, r, e, k, k, e, k, k, k]
    );
    let w = [255; 3];
    assert_eq!(
        pixels_of(&std::fs::read(&mask).unwrap(), 4, 4),
        [k, k, k, w, k, k, w, k, k, w, k, k, w, k, k, k]
    );
}

#[test]
fn samples_refusals() {
    zspec()
        .args(["--samples", "0"])
        .write_stdin(TRIANGLE)
        .assert()
        .code(2)
        .stderr(contains("0 is not in 1..=256"));
    // A missing folder is made (outputs are written whole, -o's folder made); a path
    // through a file is not a folder at all.
    zspec()
        .args(["--samples", "2", "--edge-mask", "/dev/null/mask.ppm"])
        .write_stdin(TRIANGLE)
        .assert()
        .code(3)
        .stderr("zspec: cannot write /dev/null/mask.ppm: Not a directory\n");
    // Bad input is refused on the supersampling path as on the other.
    zspec()
        .args(["--samples", "4"])
        .write_stdin("polypipe 1 world\ncolour 1 2 3\n0 0\nEND\n")
        .assert()
        .code(1)
        .stderr(contains("zspec: line 4, column 1: expected z of vertex 0"));
}

#[test]
fn compare_metrics_reports_the_measures() {
    let dir = tempfile::tempdir().unwrap();
    let [a, b, m] = ["a.ppm", "b.ppm", "m.ppm"].map(|n| dir.path().join(n));
    // Frame 0: one pixel of four differs, green against red: channel errors 255, 255, 0,
    // Σ² = 130050, RMSE √(130050/12) = 104.103…; frame 1 the same.
    // The mask flags two pixels of frame 0, the differing one among them
    // (edge RMSE √(130050/6) = 147.224…), and none of frame 1.
    let mut pa = ppm(2, 2, &["RR", "GG"]);
    pa.extend(ppm(2, 2, &["RG", "GR"]));
    let mut pb = ppm(2, 2, &["RG", "GG"]);
    pb.extend(ppm(2, 2, &["RG", "GR"]));
    let white = |rows: &[&str]| {
        let mut out = b"P6\n2 2\n255\n".to_vec();
        for ch in rows.concat().chars() {
            out.extend([if ch == 'W' { 255 } else { 0 }; 3]);
        }
        out
    };
    let mut pm = white(&["WW", ".."]);
    pm.extend(white(&["..", ".."]));
    std::fs::write(&a, &pa).unwrap();
    std::fs::write(&b, &pb).unwrap();
    std::fs::write(&m, &pm).unwrap();
    zspec()
        .args(["compare", "--metrics"])
        .args([&a, &b])
        .assert()
        .success()
        .stdout(
            "frame 0: pixels 4 differing 1 differing_fraction 0.250000 rmse 104.103314 max 255\n\
             frame 1: pixels 4 differing 0 differing_fraction 0.000000 rmse 0.000000 max 0\n\
             overall: pixels 8 differing 1 differing_fraction 0.125000 rmse 73.612159 max 255\n",
        );
    zspec()
        .args(["compare", "--metrics", "--edges"])
        .args([&m, &a, &b])
        .assert()
        .success()
        .stdout(
            "frame 0: pixels 4 differing 1 differing_fraction 0.250000 rmse 104.103314 max 255 \
             edge_pixels 2 edge_rmse 147.224319\n\
             frame 1: pixels 4 differing 0 differing_fraction 0.000000 rmse 0.000000 max 0 \
             edge_pixels 0 edge_rmse -\n\
             overall: pixels 8 differing 1 differing_fraction 0.125000 rmse 73.612159 max 255 \
             edge_pixels 2 edge_rmse 147.224319\n",
        );
    zspec()
        .args(["compare", "--metrics", "--csv", "--edges"])
        .args([&m, &a, &b])
        .assert()
        .success()
        .stdout(
            "frame,pixels,differing,differing_fraction,rmse,max,edge_pixels,edge_rmse\n\
             0,4,1,0.250000,104.103314,255,2,147.224319\n\
             1,4,0,0.000000,0.000000,0,0,\n\
             overall,8,1,0.125000,73.612159,255,2,147.224319\n",
        );
    // Trouble (2, as cmp's): a mask that is not black and white, streams of other lengths
    // (which cannot be measured against each other), and the options that need --metrics.
    std::fs::write(&m, ppm(2, 2, &["RR", "GG"])).unwrap();
    zspec()
        .args(["compare", "--metrics", "--edges"])
        .args([&m, &a, &a])
        .assert()
        .code(2)
        .stderr(contains(
            "zspec compare: the edge mask has 1 frames and the streams 2",
        ));
    std::fs::write(
        &m,
        [white(&["..", ".."]), ppm(2, 2, &["RR", "GG"])].concat(),
    )
    .unwrap();
    zspec()
        .args(["compare", "--metrics", "--edges"])
        .args([&m, &a, &a])
        .assert()
        .code(2)
        .stderr(
            "zspec compare: edge mask frame 1: pixel (0, 0) is [255, 0, 0]: an edge mask is \
             black and white only\n",
        );
    std::fs::write(&b, ppm(2, 2, &["RR", "GG"])).unwrap();
    zspec()
        .args(["compare", "--metrics"])
        .args([&a, &b])
        .assert()
        .code(2)
        .stderr("zspec compare: the streams have 2 and 1 frames\n");
    zspec()
        .args(["compare", "--csv"])
        .args([&a, &b])
        .assert()
        .code(2)
        .stderr(contains("--metrics"));
}

#[test]
fn edge_mask_and_metrics_together_measure_point_sampling() {
    // The pieces as the chart uses them: the ss16 reference and its mask, then point
    // sampling measured against it. In a scene of polygons far wider than a sample, the
    // pixels point sampling gets wrong are edge pixels (elsewhere all 256 samples and
    // the centre between them see one polygon), so the edge RMSE is at least the RMSE
    // over all pixels.
    let dir = tempfile::tempdir().unwrap();
    let [r16, m16, p1] = ["r16.ppm", "m16.ppm", "p1.ppm"].map(|n| dir.path().join(n));
    let scene = example("penetrating.txt");
    let mask = m16.to_str().unwrap();
    std::fs::write(
        &r16,
        stdout_of(&[
            "--samples",
            "16",
            "--size",
            "40x40",
            "--edge-mask",
            mask,
            &scene,
        ]),
    )
    .unwrap();
    std::fs::write(&p1, stdout_of(&["--size", "40x40", &scene])).unwrap();
    let csv = zspec()
        .args(["compare", "--metrics", "--csv", "--edges"])
        .args([&m16, &r16, &p1])
        .output()
        .unwrap();
    assert!(csv.status.success());
    let text = String::from_utf8(csv.stdout).unwrap();
    let overall: Vec<&str> = text.lines().last().unwrap().split(',').collect();
    assert_eq!(overall[0], "overall");
    let differing: u64 = overall[2].parse().unwrap();
    let rmse: f64 = overall[4].parse().unwrap();
    let edge_pixels: u64 = overall[6].parse().unwrap();
    let edge_rmse: f64 = overall[7].parse().unwrap();
    assert!(differing > 0 && differing <= edge_pixels && edge_pixels < 1600);
    assert!(edge_rmse >= rmse && rmse > 0.0);
}
