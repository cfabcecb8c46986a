//! scripts/render.sh end to end: the whole pipeline, the splitter tree of every depth
//! against the linear pipeline, and the script's behaviour when a stage dies.
//!
//! These tests live here, in the splitter crate, because the repository root is a
//! virtual workspace; they need every stage's release binary and build them first.

use pipeline_tests::{bin_dir, output_with_stdin, parse_ppm_stream, repo_root, Frame};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn render_cmd(args: &[&str]) -> Command {
    bin_dir();
    let mut cmd = Command::new(repo_root().join("scripts/render.sh"));
    cmd.args(args);
    cmd
}

/// Runs render.sh with `stdin` as its standard input.
fn render(args: &[&str], stdin: &[u8]) -> Output {
    output_with_stdin(render_cmd(args), stdin)
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

/// The frames of a concatenated P6 stream.
fn frames(ppm: &[u8]) -> Vec<Frame> {
    parse_ppm_stream(ppm).expect("a P6 stream")
}

#[test]
fn default_renders_the_penetrating_polygons_at_500x500() {
    let ppm = render_ok(&[], b"");
    assert_eq!(ppm.len(), 15 + 500 * 500 * 3);
    let f = frames(&ppm);
    assert_eq!(f.len(), 1);
    assert_eq!((f[0].width, f[0].height), (500, 500));
    // The blue quadrilateral's upper-left end projects to (25,125)-(75,75): pixel
    // (50, 100) is inside it and nothing else; (150, 320) is inside only the red
    // triangle (90,330)-(250,110)-(410,330); the corner is background.
    assert_eq!(f[0].at(50, 100), [60, 60, 255]);
    assert_eq!(f[0].at(150, 320), [255, 60, 60]);
    assert_eq!(f[0].at(5, 5), [0, 0, 0]);
}

#[test]
fn scene_from_stdin_size_and_output_pattern() {
    let scene = std::fs::read(repo_root().join("examples/penetrating.txt")).unwrap();
    let small = render_ok(&["--size", "64x48", "-"], &scene);
    let f = frames(&small);
    assert_eq!((f.len(), f[0].width, f[0].height), (1, 64, 48));
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
        assert_eq!((x.width, x.height), (y.width, y.height));
        for (i, (p, q)) in x.pixels.iter().zip(&y.pixels).enumerate() {
            if p != q {
                diffs.push((i % x.width, i / x.width));
            }
        }
    }
    diffs
}

/// Asserts that render.sh at depths 1–5 gives the bytes of depth 0 (issue 3), for
/// `args` and standard input `stdin`. A scene that depth 0 refuses must be refused the
/// same way by every tree.
fn assert_trees_render_as_depth_0(what: &str, args: &[&str], stdin: &[u8]) {
    let linear = render([&["--depth", "0"], args].concat().as_slice(), stdin);
    for depth in ["1", "2", "3", "4", "5"] {
        let tree = render([&["--depth", depth], args].concat().as_slice(), stdin);
        assert_eq!(
            tree.status.code(),
            linear.status.code(),
            "{what} depth {depth}"
        );
        assert!(
            tree.stdout == linear.stdout,
            "{what} {args:?}: depth {depth} differs from depth 0 at {:?}",
            differing_pixels(&linear.stdout, &tree.stdout)
        );
    }
}

#[test]
fn splitter_trees_render_the_penetrating_polygons_as_the_linear_pipeline() {
    // The scene's round numbers put many pixel centres exactly on its edges, and from
    // depth 3 on the planes cut those edges: the pieces' crossings come from the whole
    // edges (their supports), so every on-edge centre is decided as at depth 0.
    for size in ["500x500", "21x21", "333x187"] {
        assert_trees_render_as_depth_0("penetrating", &["--size", size], b"");
    }
    let linear = render_ok(&[], b"");
    assert!(render_ok(&["--depth", "6"], b"") == linear, "depth 6");
}

/// Every scene in examples/ (and its subdirectories), at a square and an odd size.
#[test]
fn splitter_trees_render_every_example_as_the_linear_pipeline() {
    fn scenes(dir: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                scenes(&p, out);
            } else if p.extension().is_some_and(|x| x == "txt") {
                out.push(p);
            }
        }
    }
    let mut files = Vec::new();
    scenes(&repo_root().join("examples"), &mut files);
    files.sort();
    assert!(files.len() >= 5, "{files:?}");
    for f in &files {
        let scene = std::fs::read(f).unwrap();
        // The top-level examples at two sizes, the many small cases below at one.
        let top = f.parent() == Some(repo_root().join("examples").as_path());
        let sizes: &[&str] = if top {
            &["500x500", "333x187"]
        } else {
            &["333x187"]
        };
        for size in sizes {
            assert_trees_render_as_depth_0(
                &f.display().to_string(),
                &["--size", size, "-"],
                &scene,
            );
        }
    }
}

fn scene(args: &[&str]) -> Vec<u8> {
    let out = Command::new(bin_dir().join("scene"))
        .args(args)
        .output()
        .unwrap();
    assert!(out.status.success(), "scene {args:?}");
    out.stdout
}

#[test]
fn splitter_trees_render_the_mesh_and_the_spheres_as_the_linear_pipeline() {
    // The mesh: quadrilaterals sharing every edge at one depth; a movie whose interior
    // vertices wobble. The spheres: many small tilted facets that intersect.
    let mesh = scene(&["mesh", "--frames", "2"]);
    assert_trees_render_as_depth_0("mesh", &["--size", "333x187", "-"], &mesh);
    let spheres = scene(&["spheres", "--frames", "2"]);
    assert_trees_render_as_depth_0("spheres", &["-"], &spheres);
}

/// Overlapping polygons of exactly equal depth: the first drawn wins every tie (the Z
/// spec), and it must win the same pixels in every tree. Two squares at one depth, two
/// tilted polygons in one tilted plane, and a pair crossing along a line.
const COPLANAR: &str = "polypipe 1 world
colour 255 0 0
-6 -6 0
3 -6 0
3 3 0
-6 3 0
NEXT.POLYGON
colour 0 255 0
-3 -3 0
6 -3 0
6 6 0
-3 6 0
NEXT.POLYGON
colour 0 0 255
-8 -8 -6
8 -8 -2
8 -1 -2
-8 -1 -6
NEXT.POLYGON
colour 255 255 0
-8 -4 -6
8 -4 -2
8 4 -2
-8 4 -6
NEXT.POLYGON
colour 0 255 255
-7 1.3 -4
7 -2.9 -4.7
6.1 7.3 2.2
NEXT.POLYGON
colour 255 0 255
-7 1.3 -4
7 -2.9 -4.7
-5.5 8.1 3.9
END
";

#[test]
fn splitter_trees_break_equal_depth_ties_as_the_linear_pipeline() {
    let linear = render_ok(&["-"], COPLANAR.as_bytes());
    let f = frames(&linear);
    for colour in [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 0]] {
        assert!(f[0].pixels.contains(&colour), "{colour:?} is drawn");
    }
    for size in ["500x500", "333x187", "64x48"] {
        assert_trees_render_as_depth_0("coplanar", &["--size", size, "-"], COPLANAR.as_bytes());
    }
}

/// At 512×512 every plane of a depth-5 tree is dyadic (columns 256, 128, 384, …; K = 0,
/// ±0.5, ±0.25, …) and, at z_w = 4 (z_e = 16, w = 10, X = (x_w/10 + 1)·256), a world
/// coordinate k/256·10 lands exactly on device coordinate 256 + k: vertices on the
/// planes, and edges of slope ±1 and 0 between half-pixel points through whole rows of
/// pixel centres.
const ON_THE_LATTICE: &str = "polypipe 1 world
colour 200 30 30        # (256, 128) (384, 256) (256, 384) (128, 256): on x=0, ±0.5, y=0, ±0.5
0 5 4
5 0 4
0 -5 4
-5 0 4
NEXT.POLYGON
colour 30 200 30        # half-pixel corners, slope-1 edges through centres, cut by x=0
-3.18359375 3.18359375 4
3.18359375 -3.18359375 4
6.15234375 -3.18359375 4
NEXT.POLYGON
colour 30 30 200        # a tilted quad with a vertex on x=0, y=0 and edges on y=0.25
0 0 2
7.5 2.5 -3
7.5 5 1
-2.5 5 4
END
";

#[test]
fn splitter_trees_render_vertices_on_the_planes_and_edges_through_centres_unchanged() {
    let linear = render_ok(&["--size", "512x512", "-"], ON_THE_LATTICE.as_bytes());
    let f = frames(&linear);
    for colour in [[200, 30, 30], [30, 200, 30], [30, 30, 200]] {
        assert!(f[0].pixels.contains(&colour), "{colour:?} is drawn");
    }
    assert_trees_render_as_depth_0(
        "lattice",
        &["--size", "512x512", "-"],
        ON_THE_LATTICE.as_bytes(),
    );
    assert_trees_render_as_depth_0(
        "lattice",
        &["--size", "333x187", "-"],
        ON_THE_LATTICE.as_bytes(),
    );
}

#[test]
fn splitter_trees_render_a_random_environment_as_the_linear_pipeline() {
    let scene = Command::new(bin_dir().join("scene"))
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

/// Polygons cut by the tree's planes and with vertices exactly on them (at 500×500 the
/// planes x=0, ±0.5 and y=0, ±0.5 are pixel boundaries of the tree). With the default camera, z_w = 4 is z_e = 16 and w = 10, so x_s = K is x_w = 10·K and y_s = K
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
        assert!(f[0].pixels.contains(&colour), "{colour:?} is drawn");
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

/// `--stats` through the tree: every line names its node or leaf, zbuf names its inputs
/// by leaf, and the leaves' pixels add up to what the linear pipeline draws (the split
/// loses and doubles nothing).
#[test]
fn stats_name_each_node_and_leaf_and_add_up_to_the_linear_pipeline() {
    let scene = repo_root().join("examples/penetrating.txt");
    let stats = |depth: &str| {
        let out = render(&["--depth", depth, "--stats", scene.to_str().unwrap()], b"");
        assert!(out.status.success(), "{out:?}");
        String::from_utf8(out.stderr).unwrap()
    };
    assert_eq!(
        stats("0"),
        "scanconv: 2 polygons in, 2 drawn, 543 spans, 59356 pixels\n\
         zbuf: leaf-0: 543 spans, 59356 pixels\n"
    );
    // Node 3's second output gets a one-vertex piece of one polygon, which draws
    // nothing: the lean stream sends leaf 3 a `skip 1` for it (issue 9).
    assert_eq!(
        stats("2"),
        "splitter x=0 (node 1): 2 polygons in; out1 2 polygons, 7 vertices; out2 2 polygons, 7 vertices\n\
         splitter y=0 (node 2): 2 polygons in; out1 2 polygons, 7 vertices; out2 2 polygons, 7 vertices\n\
         splitter y=0 (node 3): 2 polygons in; out1 2 polygons, 8 vertices; out2 1 polygons, 3 vertices\n\
         scanconv (leaf 0): 2 polygons in, 2 drawn, 155 spans, 13684 pixels\n\
         scanconv (leaf 1): 2 polygons in, 2 drawn, 313 spans, 21082 pixels\n\
         scanconv (leaf 2): 2 polygons in, 2 drawn, 229 spans, 17463 pixels\n\
         scanconv (leaf 3): 1 polygons in, 1 drawn, 139 spans, 7127 pixels\n\
         zbuf: leaf-0: 155 spans, 13684 pixels\n\
         zbuf: leaf-1: 313 spans, 21082 pixels\n\
         zbuf: leaf-2: 229 spans, 17463 pixels\n\
         zbuf: leaf-3: 139 spans, 7127 pixels\n"
    );
    assert_eq!(13684 + 21082 + 17463 + 7127, 59356);
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
    bin_dir();
    // A private TMPDIR, so that the script's fifo directory can be seen to go.
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

mod random_scenes {
    use super::*;
    use proptest::prelude::*;

    /// A coordinate: uniform, or on a coarse lattice that puts vertices on the tree's
    /// planes and edges through pixel centres more often than chance.
    fn coordinate(range: f64) -> impl Strategy<Value = f64> {
        prop_oneof![
            -range..range,
            (-16i32..=16).prop_map(move |k| k as f64 * range / 16.0),
        ]
    }

    fn scene_text() -> impl Strategy<Value = String> {
        let vertex = (coordinate(12.0), coordinate(12.0), coordinate(8.0));
        let polygon = (any::<[u8; 3]>(), prop::collection::vec(vertex, 3..6));
        prop::collection::vec(polygon, 20).prop_map(|polys| {
            let mut text = String::from("polypipe 1 world\n");
            for (i, (c, vs)) in polys.iter().enumerate() {
                if i > 0 {
                    text.push_str("NEXT.POLYGON\n");
                }
                text.push_str(&format!("colour {} {} {}\n", c[0], c[1], c[2]));
                for (x, y, z) in vs {
                    text.push_str(&format!("{x} {y} {z}\n"));
                }
            }
            text.push_str("END\n");
            text
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 16, ..ProptestConfig::default() })]

        /// Issue 3 as a property: any scene, trees of depth 1–3 at 64×48, byte for byte.
        #[test]
        fn any_scene_renders_the_same_through_any_tree(text in scene_text()) {
            let linear = render_ok(&["--size", "64x48", "-"], text.as_bytes());
            for depth in ["1", "2", "3"] {
                let tree = render_ok(&["--size", "64x48", "--depth", depth, "-"], text.as_bytes());
                prop_assert!(
                    tree == linear,
                    "depth {}: {:?}",
                    depth,
                    differing_pixels(&linear, &tree)
                );
            }
        }
    }
}
