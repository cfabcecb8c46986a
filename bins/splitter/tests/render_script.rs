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
    // The depth auto chooses weighs the load average; the tests' own load must not change
    // it (docs/model.md).
    cmd.args(args).env("POLYPIPE_LOAD", "0");
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

/// The two ways the leaves' pixels reach the picture (render.sh --merge): the thesis's
/// PAR.BUFF, every fragment depth-tested in the one zbuf, and the leaves resolving their
/// own regions, zbuf placing finished runs.
const MERGES: [&str; 2] = ["buffer", "tiles"];

/// Every (merge mode, depth) rendering to compare with the linear PAR.BUFF pipeline:
/// both modes at `depths`, and tiles at depth 0.
fn trees(depths: &[&'static str]) -> Vec<(&'static str, &'static str)> {
    let mut v = vec![("tiles", "0")];
    for merge in MERGES {
        v.extend(depths.iter().map(|d| (merge, *d)));
    }
    v
}

/// Asserts that render.sh at depths 1, 2 and 5, with either merge mode, and with the leaves
/// resolving at depth 0, gives the bytes of the linear pipeline, for `args` and standard input
/// `stdin`. A scene that depth 0 refuses must be refused the same way by every tree.
fn assert_trees_render_as_depth_0(what: &str, args: &[&str], stdin: &[u8]) {
    let linear = render(
        [&["--merge", "buffer", "--depth", "0"], args]
            .concat()
            .as_slice(),
        stdin,
    );
    // Depths 1, 2 and 5 of real trees (processes, pipes, both merges); every depth from
    // 1 to 6 of the geometry is checked in process (tests/tests/split_invariance.rs).
    for (merge, depth) in trees(&["1", "2", "5"]) {
        let tree = render(
            [&["--merge", merge, "--depth", depth], args]
                .concat()
                .as_slice(),
            stdin,
        );
        assert_eq!(
            tree.status.code(),
            linear.status.code(),
            "{what} --merge {merge} depth {depth}"
        );
        assert!(
            tree.stdout == linear.stdout,
            "{what} {args:?}: --merge {merge} depth {depth} differs from depth 0 at {:?}",
            differing_pixels(&linear.stdout, &tree.stdout)
        );
    }
}

#[test]
fn splitter_trees_render_the_penetrating_polygons_as_the_linear_pipeline() {
    // The scene's round numbers put many pixel centres exactly on its edges, and from
    // depth 3 on the planes cut those edges: the pieces' crossings come from the whole
    // edges (their supports), so every on-edge centre is decided as at depth 0.
    // At 500x500 and 21x21 too in process (tests/tests/split_invariance.rs).
    assert_trees_render_as_depth_0("penetrating", &["--size", "333x187"], b"");
    let linear = render_ok(&[], b"");
    for merge in MERGES {
        assert!(
            render_ok(&["--merge", merge, "--depth", "6"], b"") == linear,
            "--merge {merge} depth 6"
        );
    }
}

// Every example at depths 1 to 6 is checked in process (tests/tests/split_invariance.rs:
// the stage libraries, no processes, in about a second); the 336 render.sh runs that did
// it here took most of the suite's time. The tests here keep a handful of real trees.

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
    let linear = render_ok(&["--merge", "buffer", "-"], &scene.stdout);
    assert_eq!(frames(&linear).len(), 2);
    for (merge, depth) in trees(&["1", "2", "3", "4", "5"]) {
        let tree = render_ok(&["--merge", merge, "--depth", depth, "-"], &scene.stdout);
        assert!(
            tree == linear,
            "--merge {merge} depth {depth}: {:?}",
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
    for (merge, depth) in trees(&["1", "2", "3", "4", "5"]) {
        let tree = render_ok(
            &["--merge", merge, "--depth", depth, "-"],
            ON_THE_PLANES.as_bytes(),
        );
        assert!(
            tree == linear,
            "--merge {merge} depth {depth}: {:?}",
            differing_pixels(&linear, &tree)
        );
    }
}

/// `--stats` through the tree: every line names its node or leaf, zbuf names its inputs
/// by leaf, and the leaves' pixels add up to what the linear pipeline draws (the split
/// loses and doubles nothing), in either merge mode.
#[test]
fn stats_name_each_node_and_leaf_and_add_up_to_the_linear_pipeline() {
    let scene = repo_root().join("examples/penetrating.txt");
    let stats = |merge: &str, depth: &str| {
        let out = render(
            &[
                "--merge",
                merge,
                "--depth",
                depth,
                "--stats",
                scene.to_str().unwrap(),
            ],
            b"",
        );
        assert!(out.status.success(), "{out:?}");
        String::from_utf8(out.stderr).unwrap()
    };
    // One process is nodes 1, 2 and 3 (`splitter --levels 2`): node 1's outputs stay in
    // it, so its line has no bytes; nodes 2 and 3, the last level, write the leaves'
    // screen-space streams (`--project`), whose header is 4 bytes shorter than an
    // eye-space one.
    const SPLITTERS: &str = "splitter x=0 (node 1): 2 polygons in; out1 2 polygons, 7 vertices; out2 2 polygons, 7 vertices\n\
         splitter y=0 (node 2): 2 polygons in; out1 2 polygons, 7 vertices; out2 2 polygons, 7 vertices; 641 and 641 bytes out\n\
         splitter y=0 (node 3): 2 polygons in; out1 2 polygons, 8 vertices; out2 1 polygons, 3 vertices; 737 and 337 bytes out\n";
    assert_eq!(
        stats("buffer", "0"),
        "scanconv: 2 polygons in, 2 drawn, 543 spans, 59356 pixels\n\
         zbuf: leaf-0: 543 spans, 59356 pixels, 17441 bytes in\n"
    );
    // Node 3's second output gets a one-vertex piece of one polygon, which draws
    // nothing: the lean stream sends leaf 3 a `skip 1` for it.
    assert_eq!(
        stats("buffer", "2"),
        SPLITTERS.to_string()
            + "scanconv (leaf 0): 2 polygons in, 2 drawn, 155 spans, 13684 pixels\n\
         scanconv (leaf 1): 2 polygons in, 2 drawn, 313 spans, 21082 pixels\n\
         scanconv (leaf 2): 2 polygons in, 2 drawn, 229 spans, 17463 pixels\n\
         scanconv (leaf 3): 1 polygons in, 1 drawn, 139 spans, 7127 pixels\n\
         zbuf: leaf-0: 155 spans, 13684 pixels, 5025 bytes in\n\
         zbuf: leaf-1: 313 spans, 21082 pixels, 10081 bytes in\n\
         zbuf: leaf-2: 229 spans, 17463 pixels, 7393 bytes in\n\
         zbuf: leaf-3: 139 spans, 7127 pixels, 4513 bytes in\n"
    );
    assert_eq!(13684 + 21082 + 17463 + 7127, 59356);
    // Leaves that resolve test the same pixels; each sends only its visible ones, as
    // runs, and 500x500 is 8x8 tiles of 64, of which each leaf makes those it touches.
    // At depth 0 the one leaf is zbuf itself, reading persp's polygons; in a tree, zbuf
    // resolves leaf 0 itself (the same counts scanconv gave it: 12151 written pixels,
    // 10473 of them still showing when the other leaves' runs are in), and places its
    // region whole, with no runs made of it.
    assert_eq!(
        stats("tiles", "0"),
        "zbuf: leaf-0: 2 polygons in, 59356 pixels tested, 54673 written\n"
    );
    assert_eq!(
        stats("tiles", "2"),
        SPLITTERS.to_string()
            + "scanconv (leaf 1): 2 polygons in, 2 drawn, 21082 pixels tested, 21082 written, 322 runs out, 10 tiles\n\
         scanconv (leaf 2): 2 polygons in, 2 drawn, 17463 pixels tested, 14313 written, 150 runs out, 13 tiles\n\
         scanconv (leaf 3): 1 polygons in, 1 drawn, 7127 pixels tested, 7127 written, 139 runs out, 7 tiles\n\
         zbuf: leaf-0: 2 polygons in, 13684 pixels tested, 12151 written\n\
         zbuf: leaf-1: 0 spans, 322 runs, 18189 pixels, 5201 bytes in\n\
         zbuf: leaf-2: 0 spans, 150 runs, 14313 pixels, 2449 bytes in\n\
         zbuf: leaf-3: 0 spans, 139 runs, 7127 pixels, 2273 bytes in\n"
    );
    assert_eq!(18189 + 14313 + 7127, 50102 - 10473);
}

/// `--times`: after the stages' own words, a line a stage in the graph's order with its
/// CPU (user and system), peak memory and end, then their sums; the frames the same.
#[test]
fn times_give_each_stage_its_cpu_and_memory_in_order() {
    let scene = repo_root().join("examples/penetrating.txt");
    let scene = scene.to_str().unwrap();
    let out = render(&["--depth", "1", "--times", scene], b"");
    assert!(out.status.success(), "{out:?}");
    assert_eq!(out.stdout, render_ok(&["--depth", "1", scene], b""));
    let err = String::from_utf8(out.stderr).unwrap();
    let lines: Vec<&str> = err.lines().collect();
    let labels: Vec<&str> = lines
        .iter()
        .map(|l| {
            let l = l
                .strip_prefix("render.sh: ")
                .unwrap_or_else(|| panic!("{err}"));
            l.split(": ").next().unwrap()
        })
        .collect();
    assert_eq!(
        labels,
        [
            "viewxf",
            "clipbatch",
            "splitter (node 1)",
            "scanconv (leaf 1)",
            "zbuf",
            "5 stages"
        ],
        "{err}"
    );
    let number = |l: &str, before: &str| -> f64 {
        let head = &l[..l.find(before).unwrap_or_else(|| panic!("{l}"))];
        head.rsplit([' ', '(']).next().unwrap().parse().unwrap()
    };
    let ended = |l: &str| -> f64 {
        let at = l.rsplit("ended at ").next().unwrap();
        at.strip_suffix(" ms")
            .unwrap_or_else(|| panic!("{l}"))
            .parse()
            .unwrap()
    };
    for l in &lines[..5] {
        let (cpu, user, system) = (
            number(l, " ms CPU"),
            number(l, " user"),
            number(l, " system"),
        );
        assert!((cpu - user - system).abs() < 0.11, "{l}");
        assert!(number(l, " MB peak") > 0.5, "{l}");
        assert!(ended(l) > 0.0 && ended(l) <= ended(lines[5]), "{err}");
    }
    let sum: f64 = lines[..5].iter().map(|l| number(l, " ms CPU")).sum();
    assert!((number(lines[5], " ms CPU") - sum).abs() < 0.3, "{err}");
    let peaks: f64 = lines[..5].iter().map(|l| number(l, " MB peak")).sum();
    assert!(
        (number(lines[5], " MB of peaks") - peaks).abs() < 0.3,
        "{err}"
    );
    // Not with --by frames: the stages are the hosts'.
    let out = render(&["--hosts", "a", "--by", "frames", "--times", scene], b"");
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "render.sh: --times is the stages' here: not with --by frames\n"
    );
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
    let out = render(&["--merge", "zbuf"], b"");
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr)
        .contains("render.sh: --merge must be tiles or buffer, not 'zbuf'\n"));
    // viewxf's usage error stays a usage error.
    let out = render(&["--hither", "0"], b"");
    assert_eq!(out.status.code(), Some(2));
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
        "nothing left in TMPDIR"
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
        // Each case is eleven real renders (processes, pipes, both merge modes); the
        // geometry's invariance is tested in process over every example
        // (tests/tests/split_invariance.rs), so a few cases suffice here.
        #![proptest_config(ProptestConfig { cases: 6, ..ProptestConfig::default() })]

        /// As a property: any scene, trees of depth 1–3 at 64×48, either merge
        /// mode, byte for byte.
        #[test]
        fn any_scene_renders_the_same_through_any_tree(text in scene_text()) {
            let linear = render_ok(&["--size", "64x48", "--merge", "buffer", "-"], text.as_bytes());
            for (merge, depth) in trees(&["1", "2", "3"]) {
                let tree = render_ok(
                    &["--size", "64x48", "--merge", merge, "--depth", depth, "-"],
                    text.as_bytes(),
                );
                prop_assert!(
                    tree == linear,
                    "--merge {} depth {}: {:?}",
                    merge,
                    depth,
                    differing_pixels(&linear, &tree)
                );
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// The tree's planes computed by the nodes, the script's exit statuses, option
// errors, the first build, the freshness check and the script's own requirements.

/// The old scripts/tree-planes.sh, which render.sh sourced until the nodes computed their
/// own planes (`splitter --node K`): the oracle for them, kept verbatim.
const OLD_TREE_PLANES_SH: &str = r#"
k_of() {
    awk -v n="$1" -v d="$2" -v s="$3" \
        'BEGIN { k = s * (2 * n / d - 1); if (k == 0) k = 0; printf "%.17g", k }'
}

tree_planes() {
    local width=$1 height=$2 depth=$3
    local leaves=$((1 << depth)) node level n a b m
    local -A x0 x1 y0 y1
    declare -gA plane_of=()
    x0[1]=0 x1[1]=$width y0[1]=0 y1[1]=$height
    for ((node = 1; node < leaves; node++)); do
        level=0
        for ((n = node; n > 1; n /= 2)); do level=$((level + 1)); done
        a=$((2 * node)) b=$((2 * node + 1))
        x0[$a]=${x0[$node]} x1[$a]=${x1[$node]} y0[$a]=${y0[$node]} y1[$a]=${y1[$node]}
        x0[$b]=${x0[$node]} x1[$b]=${x1[$node]} y0[$b]=${y0[$node]} y1[$b]=${y1[$node]}
        if ((level % 2 == 0)); then
            m=$(((x0[$node] + x1[$node]) / 2))
            plane_of[$node]="x=$(k_of "$m" "$width" 1)"
            x1[$a]=$m x0[$b]=$m
        else
            m=$(((y0[$node] + y1[$node]) / 2))
            plane_of[$node]="y=$(k_of "$m" "$height" -1)"
            y0[$a]=$m y1[$b]=$m
        fi
    done
}
"#;

/// `x=K` or `y=K` as (axis, the bits of K).
fn plane_bits(plane: &str) -> (char, u64) {
    let (axis, k) = plane.split_once('=').expect("x=K or y=K");
    let k: f64 = k.parse().expect("a number");
    (axis.chars().next().unwrap(), k.to_bits())
}

/// The sizes the tree's planes are checked at: square, odd, tiny, wide.
const TREE_SIZES: [(u32, u32); 7] = [
    (500, 500),
    (333, 187),
    (21, 21),
    (1920, 1080),
    (64, 48),
    (7, 3),
    (1, 1),
];

#[test]
fn tree_nodes_compute_the_planes_of_the_old_awk_to_the_bit() {
    use splitter::{SplitPlane, Tree};
    for (w, h) in TREE_SIZES {
        let script = format!(
            "{OLD_TREE_PLANES_SH}\nfor d in 0 1 2 3 4 5 6; do tree_planes {w} {h} $d; \
             for ((n = 1; n < 1 << d; n++)); do echo \"$d $n ${{plane_of[$n]}}\"; done; done"
        );
        let out = Command::new("bash").args(["-c", &script]).output().unwrap();
        assert!(out.status.success(), "{out:?}");
        let text = String::from_utf8(out.stdout).unwrap();
        // Depth 0 has no node; depths 1–6 have 2^d − 1 each.
        assert_eq!(text.lines().count(), 1 + 3 + 7 + 15 + 31 + 63, "{w}x{h}");
        for line in text.lines() {
            let mut fields = line.split(' ');
            let (_depth, node, old) = (
                fields.next().unwrap(),
                fields.next().unwrap().parse::<u32>().unwrap(),
                fields.next().unwrap(),
            );
            let new = match (Tree {
                width: w,
                height: h,
            })
            .plane(node)
            {
                SplitPlane::Column(k) => ('x', k.to_bits()),
                SplitPlane::Row(k) => ('y', k.to_bits()),
                other => panic!("{other:?}"),
            };
            assert_eq!(new, plane_bits(old), "{w}x{h} node {node}: awk {old}");
        }
    }
}

/// The splitter binary with --node computes the same planes: its --stats label prints K
/// in the shortest form that reads back as the same double.
#[test]
fn splitter_node_labels_its_stats_with_the_old_plane_and_its_node() {
    for (w, h) in [(333, 187), (21, 21), (500, 500)] {
        let script = format!(
            "{OLD_TREE_PLANES_SH}\ntree_planes {w} {h} 6; \
             for ((n = 1; n < 64; n++)); do echo \"${{plane_of[$n]}}\"; done"
        );
        let out = Command::new("bash").args(["-c", &script]).output().unwrap();
        let old: Vec<String> = String::from_utf8(out.stdout)
            .unwrap()
            .lines()
            .map(String::from)
            .collect();
        assert_eq!(old.len(), 63);
        for node in 1..64u32 {
            let out = output_with_stdin(
                {
                    let mut cmd = Command::new(bin_dir().join("splitter"));
                    cmd.args(["--stats", "--node", &node.to_string(), "--depth", "6"])
                        .args(["--size", &format!("{w}x{h}"), "/dev/null", "/dev/null"]);
                    cmd
                },
                b"polypipe 1 eye aspect 1 hither 1 yon 30\nEND\n",
            );
            assert!(out.status.success(), "{out:?}");
            let err = String::from_utf8(out.stderr).unwrap();
            let label = err
                .strip_prefix("splitter ")
                .and_then(|rest| rest.split_once(&format!(" (node {node}): 0 polygons in")))
                .map(|(plane, _)| plane)
                .unwrap_or_else(|| panic!("{w}x{h} node {node}: {err}"));
            assert_eq!(
                plane_bits(label),
                plane_bits(&old[node as usize - 1]),
                "{w}x{h} node {node}: {label} against awk's {}",
                old[node as usize - 1]
            );
        }
    }
}

/// `--node` outside its tree, or without the screen size, is a usage error (2).
#[test]
fn splitter_node_refuses_a_node_outside_its_tree() {
    let splitter = |args: &[&str]| {
        let mut cmd = Command::new(bin_dir().join("splitter"));
        cmd.args(args).args(["/dev/null", "/dev/null"]);
        output_with_stdin(cmd, b"polypipe 1 eye aspect 1 hither 1 yon 30\nEND\n")
    };
    let out = splitter(&["--node", "4", "--depth", "2", "--size", "500x500"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--node 4 is not a splitter node of a depth-2 tree (nodes 1 to 3)"),
        "{err}"
    );
    let out = splitter(&["--node", "1", "--depth", "1"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--size"));
    let out = splitter(&["--node", "1", "--depth", "1", "--size", "9x9", "x=0"]);
    assert_eq!(out.status.code(), Some(2));
}

/// render.sh exits with the failing stage's class (1 bad data, 2 usage, 3 I/O),
/// not always 1. Bad data (viewxf, 1) and a stage's usage error (viewxf --hither 0, 2)
/// are in `a_failing_stage_is_named`.
#[test]
fn a_failing_stages_status_class_passes_through() {
    // --size 0x0 is the user's error, reported by the script as its own option: 2.
    let out = render(&["--size", "0x0"], b"");
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "render.sh: --size must be WxH with W and H from 1 to 65536, not '0x0'\n"
    );
    // An output zbuf cannot write: I/O, 3. (The tests may run as root, whom a read-only
    // folder does not stop, so the folder does not exist.)
    let nowhere = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("no-such-folder")
        .join("frame%02d.png");
    let out = render(&["--size", "21x21", "-o", nowhere.to_str().unwrap()], b"");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert!(
        err.ends_with("render.sh: zbuf failed (status 3)\n"),
        "{err}"
    );
    // A scene that cannot be read: 3.
    let out = render(&["/nonexistent/scene.txt"], b"");
    assert_eq!(out.status.code(), Some(3));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "render.sh: cannot read scene /nonexistent/scene.txt\n"
    );
}

/// an option error is one line, starting with `render.sh:`, naming the option
/// the user typed (`--zmode foo` used to come back as persp's `--depth <DEPTH>`).
#[test]
fn option_errors_are_one_line_naming_the_option_typed() {
    for (args, message) in [
        (
            &["--zmode", "foo"][..],
            "render.sh: --zmode must be reciprocal, projective or eye-z, not 'foo'",
        ),
        (
            &["--zmode=bar"],
            "render.sh: --zmode must be reciprocal, projective or eye-z, not 'bar'",
        ),
        (
            &["--depth", "7"],
            "render.sh: --depth must be an integer from 0 to 6 or auto, not '7'",
        ),
        (
            &["--size", "65537x10"],
            "render.sh: --size must be WxH with W and H from 1 to 65536, not '65537x10'",
        ),
        (&["--size"], "render.sh: --size needs a value"),
        (&["--stats=yes"], "render.sh: --stats takes no value"),
        (&["--bogus=1"], "render.sh: unknown option --bogus"),
        (
            &["a.txt", "b.txt"],
            "render.sh: more than one SCENE: 'a.txt' and 'b.txt'",
        ),
    ] {
        let out = render(args, b"");
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr),
            format!("{message}\n"),
            "{args:?}"
        );
        assert!(out.stdout.is_empty());
    }
    // The valid modes get through to persp.
    let eye_z = render_ok(&["--size", "21x21", "--zmode", "eye-z"], b"");
    assert_eq!(frames(&eye_z).len(), 1);
}

/// `--version`, and what --help and the README say about eye-z and the
/// depth.
#[test]
fn version_and_the_eye_z_caveat() {
    let out = render(&["--version"], b"");
    assert!(out.status.success());
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        format!("render.sh {}\n", env!("CARGO_PKG_VERSION"))
    );
    let help = String::from_utf8(render(&["--help"], b"").stdout).unwrap();
    assert!(
        help.contains("The frames are byte-identical for every --depth with reciprocal or projective depth, but not\nwith --zmode eye-z"),
        "{help}"
    );
    assert!(
        help.contains("Needs bash 5.1 or later and /proc."),
        "{help}"
    );
    // The caveat is real: with eye-z depth, a tree changes pixels where the polygons
    // interpenetrate (2,282 of 250,000 at depth 4), and the README says how many. The
    // linear render names depth 0: the default, auto, weighs the machine's load.
    let linear = render_ok(&["--zmode", "eye-z", "--depth", "0"], b"");
    let tree = render_ok(&["--zmode", "eye-z", "--depth", "4"], b"");
    let differ = differing_pixels(&linear, &tree).len();
    assert!(differ > 0 && differ < 2500, "{differ} pixels differ");
    let readme = std::fs::read_to_string(repo_root().join("README.md")).unwrap();
    assert!(
        readme.contains(&format!(
            "{},{:03} of its 250,000 pixels",
            differ / 1000,
            differ % 1000
        )),
        "the README should say that {differ} pixels differ"
    );
}

/// render.sh needs bash 5.1 (`wait -n -p`); an older bash or plain sh stops
/// at the first lines with one clear message and status 3 (the environment, as for a
/// missing cargo), not a syntax error half-way.
#[test]
fn an_old_bash_or_plain_sh_is_told_what_render_sh_needs() {
    let script = repo_root().join("scripts/render.sh");
    // bash sets BASH_VERSION at start; an older one is simulated by setting it before
    // sourcing the script (the check reads BASH_VERSION, as it must under any shell).
    let out = Command::new("bash")
        .args([
            "-c",
            r#"BASH_VERSION="4.4.23(1)-release"; . "$0" --version"#,
        ])
        .arg(&script)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(3));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "render.sh: needs bash 5.1 or later (this is 4.4.23(1)-release)\n"
    );
    assert!(out.stdout.is_empty());
    // A POSIX sh (dash on Debian and Ubuntu) that is not bash at all.
    let sh = ["dash", "posh", "busybox"]
        .into_iter()
        .find(|sh| {
            Command::new("sh")
                .args(["-c", &format!("command -v {sh}")])
                .output()
                .is_ok_and(|o| o.status.success())
        })
        .expect("a POSIX sh other than bash (dash) to test with");
    let mut cmd = Command::new(sh);
    if sh == "busybox" {
        cmd.arg("sh");
    }
    let out = cmd.arg(&script).arg("--version").output().unwrap();
    assert_eq!(out.status.code(), Some(3), "{sh}");
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "render.sh: needs bash 5.1 or later (this is not bash)\n"
    );
}

/// A private copy of the repository's sources (no target/), every file dated an hour
/// ago, for the tests of how render.sh finds and builds its binaries.
fn copy_of_repository(name: &str) -> PathBuf {
    fn copy(from: &Path, to: &Path, past: std::time::SystemTime) {
        if from.is_dir() {
            std::fs::create_dir_all(to).unwrap();
            for e in std::fs::read_dir(from).unwrap() {
                let e = e.unwrap();
                if e.file_name() != "target" {
                    copy(&e.path(), &to.join(e.file_name()), past);
                }
            }
        } else {
            std::fs::copy(from, to).unwrap();
            set_mtime(to, past);
        }
    }
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("render-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    let repo = dir.join("repo");
    std::fs::create_dir_all(&repo).unwrap();
    let past = std::time::SystemTime::now() - Duration::from_secs(3600);
    for part in [
        "Cargo.toml",
        "Cargo.lock",
        "README.md",
        "scripts",
        "examples",
        "proto",
        "bins",
        "tests",
    ] {
        copy(&repo_root().join(part), &repo.join(part), past);
    }
    dir
}

fn set_mtime(path: &Path, time: std::time::SystemTime) {
    std::fs::File::options()
        .write(true)
        .open(path)
        .and_then(|f| f.set_modified(time))
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
}

/// A folder of the tools render.sh runs (found on PATH), linked, to be the whole PATH
/// of a run: with `fake_cargo`, a `cargo` that logs each call (its folder and arguments)
/// to DIR/cargo.log and "builds" each `-p NAME` by copying the test's own binary into
/// the release folder cargo would use (CARGO_TARGET_DIR taken from its working folder,
/// as cargo does, then the host's folder, [`release_subdir`]), with a dep-info file
/// listing the crate's and proto's sources.
fn tools(dir: &Path, fake_cargo: bool) -> PathBuf {
    let bin = dir.join(if fake_cargo { "tools-cargo" } else { "tools" });
    let _ = std::fs::remove_dir_all(&bin);
    std::fs::create_dir_all(&bin).unwrap();
    let path = std::env::var_os("PATH").unwrap();
    for tool in [
        "bash", "env", "cat", "cp", "ln", "mkdir", "mkfifo", "mktemp", "readlink", "rm", "sed",
        "sleep", "touch",
    ] {
        let found = std::env::split_paths(&path)
            .map(|d| d.join(tool))
            .find(|p| p.is_file())
            .unwrap_or_else(|| panic!("{tool} on PATH"));
        std::os::unix::fs::symlink(found, bin.join(tool)).unwrap();
    }
    if fake_cargo {
        let cargo = bin.join("cargo");
        std::fs::write(
            &cargo,
            format!(
                r#"#!/usr/bin/env bash
echo "$PWD $*" >> {log}
[[ -n ${{FAKE_CARGO_NOOP-}} ]] && exit 0
t=${{CARGO_TARGET_DIR:-target}}
[[ $t == /* ]] || t=$PWD/$t
r=$t/{sub}
mkdir -p "$r"
while (($# > 0)); do
    if [[ $1 == -p ]]; then
        cp {real}/"$2" "$r/$2"
        echo "$r/$2:" "$PWD/bins/$2"/src/*.rs "$PWD"/proto/src/*.rs > "$r/$2.d"
        shift
    fi
    shift
done
"#,
                log = dir.join("cargo.log").display(),
                real = bin_dir().display(),
                sub = release_subdir()
            ),
        )
        .unwrap();
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&cargo, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    bin
}

/// Where cargo puts release binaries in its target folder: `<host tuple>/release`, as
/// .cargo/config.toml's `target = "host-tuple"` has it (the tests' own folder says which
/// tuple), or `release` for a build without that setting.
fn release_subdir() -> String {
    let tuple = bin_dir().parent().and_then(Path::file_name).unwrap();
    if tuple.to_string_lossy().contains('-') {
        format!("{}/release", tuple.to_string_lossy())
    } else {
        "release".into()
    }
}

/// The calls the fake cargo has logged so far (and forgets them).
fn cargo_calls(dir: &Path) -> Vec<String> {
    let log = dir.join("cargo.log");
    let calls = std::fs::read_to_string(&log).unwrap_or_default();
    let _ = std::fs::remove_file(&log);
    calls.lines().map(String::from).collect()
}

/// Runs SCRIPT (a render.sh) from folder CWD with only TOOLS on PATH.
fn render_in(script: &Path, cwd: &Path, tools: &Path, args: &[&str]) -> Output {
    let mut cmd = Command::new(script);
    cmd.args(args)
        .current_dir(cwd)
        .env("PATH", tools)
        .env_remove("CARGO_TARGET_DIR")
        .env_remove("FAKE_CARGO_NOOP");
    output_with_stdin(cmd, b"")
}

/// The binaries the README runs, as `$B/NAME` or `target/bin/NAME`.
fn binaries_the_readme_uses() -> std::collections::BTreeSet<String> {
    let readme = std::fs::read_to_string(repo_root().join("README.md")).unwrap();
    let mut names = std::collections::BTreeSet::new();
    for prefix in ["$B/", "target/bin/"] {
        for (i, _) in readme.match_indices(prefix) {
            let name: String = readme[i + prefix.len()..]
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_' || *c == '-')
                .collect();
            if !name.is_empty() {
                names.insert(name);
            }
        }
    }
    names
}

/// the README's first command builds every binary the README goes on to use,
/// saying so on stderr, and the README's next commands then run.
#[test]
fn the_first_run_builds_every_binary_the_readme_uses() {
    let dir = copy_of_repository("first-run");
    let repo = dir.join("repo");
    let tools = tools(&dir, true);
    let out = render_in(
        &repo.join("scripts/render.sh"),
        &repo,
        &tools,
        &["-o", "penetrating.png"],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert_eq!(
        err,
        "render.sh: building the polypipe binaries (first run only)…\n"
    );
    assert!(repo.join("penetrating.png").is_file());
    let calls = cargo_calls(&dir);
    assert_eq!(calls.len(), 1, "{calls:?}");
    assert!(
        calls[0].starts_with(&format!("{} build --release", repo.display())),
        "{calls:?}"
    );
    let used = binaries_the_readme_uses();
    assert!(used.contains("scene") && used.contains("zspec"), "{used:?}");
    for name in &used {
        assert!(
            calls[0].contains(&format!(" -p {name}")),
            "the first run does not build {name}: {calls:?}"
        );
        let b = repo.join("target/bin").join(name);
        let help = Command::new(&b).arg("--help").output().unwrap();
        assert!(help.status.success(), "{}", b.display());
    }
    // cargo built them in its folder for this host, and target/bin links to it.
    let link = std::fs::read_link(repo.join("target/bin")).unwrap();
    assert_eq!(link, Path::new(&release_subdir()));
    // The README's next block (`B=target/bin`), with the binaries the first run built.
    let b = repo.join("target/bin");
    let text = Command::new(b.join("scene"))
        .args(["penetrating", "--text"])
        .output()
        .unwrap();
    assert!(text.status.success());
    assert!(text.stdout.starts_with(b"polypipe 1 world"));
    // A second run finds them all built and current: no cargo.
    let out = render_in(
        &repo.join("scripts/render.sh"),
        &repo,
        &tools,
        &["--size", "21x21"],
    );
    assert!(out.status.success());
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(cargo_calls(&dir), Vec::<String>::new());
}

/// only the binaries' sources (src/ .rs files, Cargo.toml, Cargo.lock) make
/// render.sh call cargo; without cargo it runs what is built.
#[test]
fn only_the_binaries_sources_make_render_sh_call_cargo() {
    let dir = copy_of_repository("fresh");
    let repo = dir.join("repo");
    let script = repo.join("scripts/render.sh");
    let with_cargo = tools(&dir, true);
    let without_cargo = tools(&dir, false);
    let args = ["--size", "21x21"];
    // Without cargo and nothing built: status 3, saying what is missing.
    let out = render_in(&script, &repo, &without_cargo, &args);
    assert_eq!(out.status.code(), Some(3));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.starts_with("render.sh: cannot build viewxf clipplane clipbatch splitter persp scanconv zbuf scanline warnock painter hiddenline supersample abuf scene zspec frames farm chart plan into ")
            && err.ends_with(": cargo is not on PATH (Rust: https://rustup.rs)\n"),
        "{err}"
    );
    let first = render_in(&script, &repo, &with_cargo, &args);
    assert!(first.status.success());
    assert_eq!(cargo_calls(&dir).len(), 1);
    // The binaries a minute old, the sources an hour.
    let built = std::time::SystemTime::now() - Duration::from_secs(60);
    let release = repo.join("target").join(release_subdir());
    for e in std::fs::read_dir(&release).unwrap() {
        set_mtime(&e.unwrap().path(), built);
    }
    let now = std::time::SystemTime::now();
    // Tests, test helpers and documents are not sources of the binaries.
    for file in [
        "bins/splitter/tests/render_script.rs",
        "bins/zbuf/tests/cli.rs",
        "tests/src/lib.rs",
        "README.md",
        "examples/penetrating.txt",
    ] {
        set_mtime(&repo.join(file), now);
        let out = render_in(&script, &repo, &with_cargo, &args);
        assert!(out.status.success());
        assert_eq!(out.stdout, first.stdout);
        assert_eq!(cargo_calls(&dir), Vec::<String>::new(), "touched {file}");
    }
    // A source of a binary is (changed now, after those runs: a run that finds every
    // binary current by its sources notes the time in its stamp).
    set_mtime(&repo.join("proto/src/lib.rs"), std::time::SystemTime::now());
    // Without cargo: run them as they are, with one warning.
    let out = render_in(&script, &repo, &without_cargo, &args);
    assert!(out.status.success());
    assert_eq!(out.stdout, first.stdout);
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "render.sh: warning: viewxf clipplane clipbatch splitter persp scanconv zbuf scanline warnock painter \
         hiddenline supersample abuf scene zspec frames farm chart plan: \
         older than their sources, and no cargo on PATH to rebuild them; running them as they are\n"
    );
    // With cargo: rebuilt, once.
    let out = render_in(&script, &repo, &with_cargo, &args);
    assert!(out.status.success(), "{out:?}");
    assert_eq!(cargo_calls(&dir).len(), 1);
    let out = render_in(&script, &repo, &with_cargo, &args);
    assert!(out.status.success());
    assert_eq!(cargo_calls(&dir), Vec::<String>::new());
    // A change to Cargo.lock that leaves every binary alone (cargo has nothing to do)
    // calls cargo once, not on every run from then on.
    set_mtime(&repo.join("Cargo.lock"), std::time::SystemTime::now());
    for _ in 0..2 {
        let mut cmd = Command::new(&script);
        cmd.args(args)
            .current_dir(&repo)
            .env("PATH", &with_cargo)
            .env("FAKE_CARGO_NOOP", "1");
        assert!(output_with_stdin(cmd, b"").status.success());
    }
    assert_eq!(cargo_calls(&dir).len(), 1);
    // A crate's Cargo.toml counts too.
    set_mtime(
        &repo.join("bins/zbuf/Cargo.toml"),
        std::time::SystemTime::now(),
    );
    assert!(render_in(&script, &repo, &with_cargo, &args)
        .status
        .success());
    assert_eq!(cargo_calls(&dir).len(), 1);
}

/// a relative CARGO_TARGET_DIR is where cargo, run from the repository root,
/// builds; and a symlink to render.sh finds the repository the script is in.
#[test]
fn a_relative_target_dir_and_a_symlinked_script_find_the_binaries() {
    let dir = copy_of_repository("elsewhere");
    let repo = dir.join("repo");
    let cargo = tools(&dir, true);
    let elsewhere = dir.join("elsewhere");
    std::fs::create_dir_all(&elsewhere).unwrap();
    let run = |script: &Path| {
        let mut cmd = Command::new(script);
        cmd.args(["--size", "21x21"])
            .current_dir(&elsewhere)
            .env("PATH", &cargo)
            .env("CARGO_TARGET_DIR", "build/here");
        output_with_stdin(cmd, b"")
    };
    let out = run(&repo.join("scripts/render.sh"));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(frames(&out.stdout).len(), 1);
    assert_eq!(cargo_calls(&dir).len(), 1);
    assert!(repo
        .join("build/here")
        .join(release_subdir())
        .join("viewxf")
        .is_file());
    // render.sh links the target folder's `bin` to them.
    assert!(repo.join("build/here/bin/viewxf").is_file());
    assert!(!elsewhere.join("build").exists());
    // Found where it was built: no second build.
    assert!(run(&repo.join("scripts/render.sh")).status.success());
    assert_eq!(cargo_calls(&dir), Vec::<String>::new());
    // Through a symlink in another folder (and a symlink to that).
    let link = dir.join("links/render");
    std::fs::create_dir_all(link.parent().unwrap()).unwrap();
    std::os::unix::fs::symlink(repo.join("scripts/render.sh"), &link).unwrap();
    let link2 = elsewhere.join("r");
    std::os::unix::fs::symlink(&link, &link2).unwrap();
    for script in [&link, &link2] {
        let out = run(script);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert_eq!(frames(&out.stdout).len(), 1);
    }
    assert_eq!(cargo_calls(&dir), Vec::<String>::new());
}

/// With the real cargo's dep-info: right after cargo built the binaries (as
/// the tests' `bin_dir` does), render.sh finds them current and, without cargo on PATH,
/// runs them without a warning.
#[test]
fn binaries_cargo_just_built_are_current_by_their_dep_info() {
    bin_dir();
    // A run with cargo first, so that a Cargo.lock newer than every binary (which cargo
    // leaves alone) has been asked about once.
    assert!(render(&["--size", "21x21"], b"").status.success());
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("render-dep-info");
    std::fs::create_dir_all(&dir).unwrap();
    let out = render_in(
        &repo_root().join("scripts/render.sh"),
        &repo_root(),
        &tools(&dir, false),
        &["--size", "21x21"],
    );
    assert!(out.status.success());
    assert_eq!(String::from_utf8_lossy(&out.stderr), "");
}
