//! scripts/render.sh end to end: the whole pipeline, the splitter tree of every depth
//! against the linear pipeline, and the script's behaviour when a stage dies.
//!
//! These tests live here, in the splitter crate, because the repository root is a
//! virtual workspace; they need every stage's release binary and build them first.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Builds every binary once for all the tests of this file.
fn built() -> &'static Path {
    static BUILT: OnceLock<PathBuf> = OnceLock::new();
    BUILT.get_or_init(|| {
        let status = Command::new(env!("CARGO"))
            .args(["build", "--release", "--bins"])
            .current_dir(root())
            .status()
            .expect("cargo runs");
        assert!(status.success(), "cargo build --release --bins failed");
        root().join("target/release")
    })
}

fn render_cmd(args: &[&str]) -> Command {
    built();
    let mut cmd = Command::new(root().join("scripts/render.sh"));
    cmd.args(args);
    cmd
}

/// Runs render.sh with `stdin` as its standard input.
fn render(args: &[&str], stdin: &[u8]) -> Output {
    use std::io::Write;
    let mut child = render_cmd(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("render.sh starts");
    let mut input = child.stdin.take().unwrap();
    let data = stdin.to_vec();
    let writer = std::thread::spawn(move || {
        let _ = input.write_all(&data);
    });
    let out = child.wait_with_output().unwrap();
    writer.join().unwrap();
    out
}

fn render_ok(args: &[&str], stdin: &[u8]) -> Vec<u8> {
    let out = render(args, stdin);
    assert!(
        out.status.success(),
        "render.sh {args:?}: {:?}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// The frames of a concatenated P6 stream: (width, height, RGB bytes).
fn frames(ppm: &[u8]) -> Vec<(usize, usize, Vec<u8>)> {
    let mut rest = ppm;
    let mut out = Vec::new();
    while !rest.is_empty() {
        let text = std::str::from_utf8(&rest[..rest.len().min(40)])
            .unwrap_or_else(|e| std::str::from_utf8(&rest[..e.valid_up_to()]).unwrap());
        let mut words = text.split_ascii_whitespace();
        assert_eq!(words.next(), Some("P6"));
        let w: usize = words.next().unwrap().parse().unwrap();
        let h: usize = words.next().unwrap().parse().unwrap();
        assert_eq!(words.next(), Some("255"));
        let header = format!("P6\n{w} {h}\n255\n");
        assert!(rest.starts_with(header.as_bytes()), "header {header:?}");
        let body = &rest[header.len()..header.len() + 3 * w * h];
        out.push((w, h, body.to_vec()));
        rest = &rest[header.len() + 3 * w * h..];
    }
    out
}

fn pixel(frame: &(usize, usize, Vec<u8>), c: usize, r: usize) -> [u8; 3] {
    let i = 3 * (r * frame.0 + c);
    [frame.2[i], frame.2[i + 1], frame.2[i + 2]]
}

#[test]
fn default_renders_the_penetrating_polygons_at_500x500() {
    let ppm = render_ok(&[], b"");
    assert_eq!(ppm.len(), 15 + 500 * 500 * 3);
    let f = frames(&ppm);
    assert_eq!(f.len(), 1);
    assert_eq!((f[0].0, f[0].1), (500, 500));
    // The blue quadrilateral's upper-left end projects to (25,125)-(75,75): pixel
    // (50, 100) is inside it and nothing else; (150, 320) is inside only the red
    // triangle (90,330)-(250,110)-(410,330); the corner is background.
    assert_eq!(pixel(&f[0], 50, 100), [60, 60, 255]);
    assert_eq!(pixel(&f[0], 150, 320), [255, 60, 60]);
    assert_eq!(pixel(&f[0], 5, 5), [0, 0, 0]);
}

#[test]
fn scene_from_stdin_size_and_output_pattern() {
    let scene = std::fs::read(root().join("examples/penetrating.txt")).unwrap();
    let small = render_ok(&["--size", "64x48", "-"], &scene);
    let f = frames(&small);
    assert_eq!((f.len(), f[0].0, f[0].1), (1, 64, 48));
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("render-pattern");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let pattern = dir.join("frame%02d.ppm");
    let out = render_ok(
        &[
            "--size",
            "64x48",
            "--depth",
            "2",
            "-o",
            pattern.to_str().unwrap(),
            "-",
        ],
        &scene,
    );
    assert!(out.is_empty());
    assert_eq!(std::fs::read(dir.join("frame00.ppm")).unwrap(), small);
}

/// The pixels whose colours differ between two renderings.
fn differing_pixels(a: &[u8], b: &[u8]) -> Vec<(usize, usize)> {
    let (fa, fb) = (frames(a), frames(b));
    assert_eq!(fa.len(), fb.len());
    let mut diffs = Vec::new();
    for (x, y) in fa.iter().zip(&fb) {
        assert_eq!((x.0, x.1), (y.0, y.1));
        for i in 0..x.0 * x.1 {
            if x.2[3 * i..3 * i + 3] != y.2[3 * i..3 * i + 3] {
                diffs.push((i % x.0, i / x.0));
            }
        }
    }
    diffs
}

/// Whether pixel (c, r)'s centre lies exactly on an edge of the penetrating scene as
/// the default camera projects it onto a 500x500 screen, in exact integer arithmetic
/// (device coordinates times 6: the vertices are multiples of 1/3, the centres of 1/2).
fn on_a_penetrating_edge(c: usize, r: usize) -> bool {
    let polygons: [&[(i128, i128)]; 2] = [
        &[(150, 750), (450, 450), (2200, 2200), (2000, 2400)],
        &[(540, 1980), (1500, 660), (2460, 1980)],
    ];
    let (px, py) = (6 * c as i128 + 3, 6 * r as i128 + 3);
    polygons.iter().any(|p| {
        (0..p.len()).any(|i| {
            let ((ax, ay), (bx, by)) = (p[i], p[(i + 1) % p.len()]);
            (bx - ax) * (py - ay) == (by - ay) * (px - ax) && ay.min(by) <= py && py <= ay.max(by)
        })
    })
}

#[test]
fn splitter_trees_render_the_penetrating_polygons_as_the_linear_pipeline() {
    let linear = render_ok(&["--depth", "0"], b"");
    for depth in ["1", "2"] {
        let tree = render_ok(&["--depth", depth], b"");
        assert!(tree == linear, "depth {depth} differs from depth 0");
    }
    // From depth 3 on, a splitting plane cuts an edge of the scene that passes exactly
    // through pixel centres (the scene's round numbers put many centres on its edges).
    // The cut edge's two pieces end at the intersection, which is on the edge only to
    // within rounding, so the top-left rule may decide such a centre the other way.
    // Every other pixel must agree.
    for depth in ["3", "4", "5"] {
        let tree = render_ok(&["--depth", depth], b"");
        let diffs = differing_pixels(&linear, &tree);
        let off_edge: Vec<_> = diffs
            .iter()
            .filter(|&&(c, r)| !on_a_penetrating_edge(c, r))
            .collect();
        assert!(
            off_edge.is_empty(),
            "depth {depth}: pixels off every edge differ: {off_edge:?}"
        );
    }
}

#[test]
fn splitter_trees_render_a_random_environment_as_the_linear_pipeline() {
    built();
    let scene = Command::new(root().join("target/release/scene"))
        .args([
            "environment",
            "--polygons",
            "400",
            "--depth-complexity",
            "3",
            "--seed",
            "11",
            "--frames",
            "2",
        ])
        .output()
        .unwrap();
    assert!(scene.status.success());
    let linear = render_ok(&["-"], &scene.stdout);
    assert_eq!(frames(&linear).len(), 2);
    for depth in ["1", "2", "3", "4", "5"] {
        let tree = render_ok(&["--depth", depth, "-"], &scene.stdout);
        assert!(
            tree == linear,
            "depth {depth}: {:?}",
            differing_pixels(&linear, &tree)
        );
    }
}

/// Polygons cut by the tree's planes and with vertices exactly on them. All are planar:
/// a non-planar polygon's depth plane is a best fit, which differs for its pieces. With the
/// default camera, z_w = 4 is z_e = 16 and w = 10, so x_s = K is x_w = 10·K and y_s = K
/// is y_w = 10·K; at z_w = −4, w = 15.
const ON_THE_PLANES: &str = "polypipe 1 world
colour 200 30 30       # vertices on x=0, y=0, x=0.5, y=-0.25
0 3.3 4
5 -1.7 4
2.2 -2.5 4
-3.9 0 4
NEXT.POLYGON
colour 30 200 30       # tilted in depth, cutting the first, corners on x=-0.5, x=0.5, y=0.5
-7.5 -6.1 -4
7.5 -2.3 -4
3.1 5 4
NEXT.POLYGON
colour 30 30 200       # a wide sliver crossing every column of the tree
-9.7 0.31 2
9.8 -0.43 -2
9.6 1.37 -2
NEXT.POLYGON
colour 200 200 30      # a vertex at the screen centre, edges along x=0 and y=0
0 0 4
0 -7.5 -4
-7.3 0 0
END
";

#[test]
fn splitter_trees_render_polygons_cut_and_touched_by_the_planes_unchanged() {
    let linear = render_ok(&["-"], ON_THE_PLANES.as_bytes());
    let f = frames(&linear);
    // Something of every polygon is visible.
    for colour in [[200, 30, 30], [30, 200, 30], [30, 30, 200], [200, 200, 30]] {
        assert!(f[0].2.chunks(3).any(|p| p == colour), "{colour:?} is drawn");
    }
    for depth in ["1", "2", "3", "4", "5"] {
        let tree = render_ok(&["--depth", depth, "-"], ON_THE_PLANES.as_bytes());
        assert!(
            tree == linear,
            "depth {depth}: {:?}",
            differing_pixels(&linear, &tree)
        );
    }
}

#[test]
fn a_failing_stage_is_named() {
    let out = render(
        &["--depth", "2", "-"],
        b"polypipe 1 world\ncolour 1 2 3\n0 0\n",
    );
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("viewxf: line 3, column 4: expected z of vertex 0"),
        "{err}"
    );
    assert!(
        err.contains("render.sh: viewxf failed (status 1)\n"),
        "{err}"
    );
    let out = render(&["--depth", "7"], b"");
    assert_eq!(out.status.code(), Some(2));
    let out = render(&["--hither", "0"], b"");
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("render.sh: viewxf failed (status 2)\n"));
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
    built();
    // A private TMPDIR, so that the script's fifo directory can be seen to go.
    let tmp = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("render-kill");
    let _ = std::fs::remove_dir_all(&tmp);
    std::fs::create_dir_all(&tmp).unwrap();
    // A movie long enough to be still running when a stage is killed.
    let mut scene = Command::new(root().join("target/release/scene"))
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
    let mut render = render_cmd(&["--depth", "3", "-"])
        .env("TMPDIR", &tmp)
        .stdin(scene.stdout.take().unwrap())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Depth 3: viewxf, 6 clippers, 7 splitters, 8 persp, 8 scanconv and zbuf.
    let started = Instant::now();
    let stages = loop {
        let stages = children_of(render.id(), None);
        if stages.len() == 31 {
            break stages;
        }
        assert!(
            started.elapsed() < Duration::from_secs(60),
            "the tree did not start: {stages:?}"
        );
        std::thread::sleep(Duration::from_millis(20));
    };
    let fifo_dirs = std::fs::read_dir(&tmp).unwrap().count();
    assert_eq!(fifo_dirs, 1, "one private fifo directory");
    let victim = children_of(render.id(), Some("clipplane hither"));
    assert_eq!(victim.len(), 1);
    let killed = Command::new("kill")
        .args(["-KILL", &victim[0].to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let killed_at = Instant::now();
    let status = loop {
        if let Some(status) = render.try_wait().unwrap() {
            break status;
        }
        assert!(
            killed_at.elapsed() < Duration::from_secs(2),
            "render.sh still running 2 s after a stage was killed"
        );
        std::thread::sleep(Duration::from_millis(10));
    };
    let mut err = String::new();
    std::io::Read::read_to_string(render.stderr.as_mut().unwrap(), &mut err).unwrap();
    let _ = scene.wait();
    assert_eq!(status.code(), Some(1), "{err}");
    assert!(
        err.contains("render.sh: clipplane hither failed (killed by SIGKILL)"),
        "{err}"
    );
    assert_eq!(
        std::fs::read_dir(&tmp).unwrap().count(),
        0,
        "the fifo directory is removed"
    );
    for pid in stages {
        assert!(
            !Path::new(&format!("/proc/{pid}")).exists(),
            "stage {pid} outlived render.sh"
        );
    }
}
