//! render's graph end to end: the splitter tree of every depth against the linear
//! pipeline, byte for byte, for every merge mode, and what the stages count (--stats)
//! and cost (--times).

use pipeline_tests::render::{differing_pixels, example, frames, render, render_ok};
use pipeline_tests::{bin_dir, repo_root};
use std::process::Command;

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

/// Asserts that render at depths 1, 2 and 5, with either merge mode, and with the leaves
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
    // 1 to 6 of the geometry is checked in process (tests/tests/composer/split_invariance.rs).
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
    // At 500x500 and 21x21 too in process (tests/tests/composer/split_invariance.rs).
    let scene = example();
    assert_trees_render_as_depth_0("penetrating", &["--size", "333x187", &scene], b"");
    let linear = render_ok(&[&scene], b"");
    for merge in MERGES {
        assert!(
            render_ok(&["--merge", merge, "--depth", "6", &scene], b"") == linear,
            "--merge {merge} depth 6"
        );
    }
}

// Every example at depths 1 to 6 is checked in process (tests/tests/composer/split_invariance.rs:
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
        let said = String::from_utf8(out.stderr).unwrap();
        // Each readable line has its record, labelled with the stage.
        let records = stagecli::stats::records(&said).unwrap();
        let human = stagecli::stats::human(&said);
        assert_eq!(records.len(), human.lines().count(), "{said}");
        for (r, line) in records.iter().zip(human.lines()) {
            // The splitters label their own lines, with their planes.
            let label = match r.stage() {
                "splitter" => "splitter",
                _ => r.get("label").unwrap_or_default(),
            };
            assert!(line.starts_with(label), "{r} / {line}");
        }
        (human, records)
    };
    // What the leaves drew (scanconv's `pixels`, or what zbuf resolved itself).
    let drawn = |records: &[stagecli::stats::Record]| -> u64 {
        let leaves = records.iter().filter(|r| r.stage() == "scanconv");
        let own = records.iter().filter(|r| r.stage() == "zbuf");
        leaves.filter_map(|r| r.count("pixels")).sum::<u64>()
            + own.filter_map(|r| r.count("pixels_tested")).sum::<u64>()
    };
    let buffer_0 = stats("buffer", "0");
    let buffer_2 = stats("buffer", "2");
    assert_eq!(drawn(&buffer_0.1), 59393);
    assert_eq!(drawn(&buffer_2.1), 59393);
    let stats = |merge: &str, depth: &str| match (merge, depth) {
        ("buffer", "0") => buffer_0.0.clone(),
        ("buffer", "2") => buffer_2.0.clone(),
        _ => stats(merge, depth).0,
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
        "scanconv: 2 polygons in, 2 drawn, 544 spans, 59393 pixels\n\
         zbuf: leaf-0: 544 spans, 59393 pixels, 17473 bytes in\n"
    );
    // Node 3's second output gets a one-vertex piece of one polygon, which draws
    // nothing: the lean stream sends leaf 3 a `skip 1` for it.
    assert_eq!(
        stats("buffer", "2"),
        SPLITTERS.to_string()
            + "scanconv (leaf 0): 2 polygons in, 2 drawn, 155 spans, 13684 pixels\n\
         scanconv (leaf 1): 2 polygons in, 2 drawn, 314 spans, 21119 pixels\n\
         scanconv (leaf 2): 2 polygons in, 2 drawn, 229 spans, 17463 pixels\n\
         scanconv (leaf 3): 1 polygons in, 1 drawn, 139 spans, 7127 pixels\n\
         zbuf: leaf-0: 155 spans, 13684 pixels, 5025 bytes in\n\
         zbuf: leaf-1: 314 spans, 21119 pixels, 10113 bytes in\n\
         zbuf: leaf-2: 229 spans, 17463 pixels, 7393 bytes in\n\
         zbuf: leaf-3: 139 spans, 7127 pixels, 4513 bytes in\n"
    );
    assert_eq!(13684 + 21119 + 17463 + 7127, 59393);
    // Leaves that resolve test the same pixels; each sends only its visible ones, as
    // runs, and 500x500 is 8x8 tiles of 64, of which each leaf makes those it touches.
    // At depth 0 the one leaf is zbuf itself, reading persp's polygons; in a tree, zbuf
    // resolves leaf 0 itself (the same counts scanconv gave it: 12151 written pixels,
    // 10473 of them still showing when the other leaves' runs are in), and places its
    // region whole, with no runs made of it.
    assert_eq!(
        stats("tiles", "0"),
        "zbuf: leaf-0: 2 polygons in, 59393 pixels tested, 54710 written\n"
    );
    assert_eq!(
        stats("tiles", "2"),
        SPLITTERS.to_string()
            + "scanconv (leaf 1): 2 polygons in, 2 drawn, 21119 pixels tested, 21119 written, 323 runs out, 10 tiles\n\
         scanconv (leaf 2): 2 polygons in, 2 drawn, 17463 pixels tested, 14313 written, 150 runs out, 13 tiles\n\
         scanconv (leaf 3): 1 polygons in, 1 drawn, 7127 pixels tested, 7127 written, 139 runs out, 7 tiles\n\
         zbuf: leaf-0: 2 polygons in, 13684 pixels tested, 12151 written\n\
         zbuf: leaf-1: 0 spans, 323 runs, 18226 pixels, 5217 bytes in\n\
         zbuf: leaf-2: 0 spans, 150 runs, 14313 pixels, 2449 bytes in\n\
         zbuf: leaf-3: 0 spans, 139 runs, 7127 pixels, 2273 bytes in\n"
    );
    assert_eq!(18226 + 14313 + 7127, 50139 - 10473);
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
    let records = stagecli::stats::records_of(&err, "render").unwrap();
    let labels: Vec<&str> = records
        .iter()
        .map(|r| r.get("label").unwrap_or_default())
        .collect();
    assert_eq!(
        labels,
        [
            "viewxf",
            "clipbatch",
            "splitter (node 1)",
            "scanconv (leaf 1)",
            "zbuf",
            ""
        ],
        "{err}"
    );
    assert_eq!(records[5].count("stages"), Some(5), "{err}");
    let ms = |r: &stagecli::stats::Record, key: &str| -> f64 {
        r.number(key).unwrap_or_else(|| panic!("{key} in {r}"))
    };
    let (stages, sums) = (&records[..5], &records[5]);
    for r in stages {
        assert!(r.count("peak_kib").unwrap_or(0) > 512, "{r}");
        assert!(ms(r, "user_ms") >= 0.0 && ms(r, "system_ms") >= 0.0, "{r}");
        let ended = ms(r, "ended_ms");
        assert!(ended > 0.0 && ended <= ms(sums, "last_ended_ms"), "{err}");
    }
    let cpu: f64 = stages
        .iter()
        .map(|r| ms(r, "user_ms") + ms(r, "system_ms"))
        .sum();
    assert!((ms(sums, "cpu_ms") - cpu).abs() < 0.01, "{err}");
    let peaks: u64 = stages.iter().filter_map(|r| r.count("peak_kib")).sum();
    assert_eq!(sums.count("peaks_kib"), Some(peaks), "{err}");
    // People get a line a stage and one of the sums.
    assert_eq!(stagecli::stats::human(&err).lines().count(), 6, "{err}");
    // Not with --by frames: the stages are the hosts'.
    let out = render(&["--hosts", "a", "--by", "frames", "--times", scene], b"");
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "render: --times is the stages' here: not with --by frames\n"
    );
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
        // (tests/tests/composer/split_invariance.rs), so a few cases suffice here.
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

/// `--depth auto` starts the clipper chain before the depth is chosen, and joins the rest
/// of the graph to it once it is: the frames are the bytes of the depth it chose, given
/// as a fixed depth, and of depth 0.
#[test]
fn depth_auto_draws_the_bytes_of_the_depth_it_chose() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("fill.txt");
    let made = Command::new(bin_dir().join("scene"))
        .args(["environment", "--text", "--seed", "2", "--polygons", "3000"])
        .args([
            "--depth-complexity",
            "6",
            "--frames",
            "2",
            "--size",
            "640x360",
        ])
        .output()
        .unwrap();
    assert!(made.status.success());
    std::fs::write(&scene, &made.stdout).unwrap();
    let scene = scene.display().to_string();
    let auto = render(&["--size", "640x360", "--stats", &scene], b"");
    assert!(
        auto.status.success(),
        "{}",
        String::from_utf8_lossy(&auto.stderr)
    );
    let err = String::from_utf8_lossy(&auto.stderr);
    let chose = pipeline_tests::stat(&err, "depth_auto").to_string();
    let fixed = render_ok(&["--size", "640x360", "--depth", &chose, &scene], b"");
    let zero = render_ok(&["--size", "640x360", "--depth", "0", &scene], b"");
    assert_eq!(frames(&auto.stdout).len(), 2);
    assert!(auto.stdout == fixed, "auto against --depth {chose}");
    assert!(auto.stdout == zero, "auto (depth {chose}) against depth 0");
}

/// With a core or less for the render (one core under `taskset -c 0`; a loaded machine's
/// share) `--depth auto` is depth 0 without the look or the model, which would choose it
/// anyway: `--stats` says so, and the frames are depth 0's. (At 500x500 no scene file is
/// small enough to be depth 0 for its size alone.)
#[test]
fn depth_auto_on_one_core_is_depth_0_without_a_look() {
    let scene = example();
    let mut one_core = Command::new("taskset");
    one_core
        .args(["-c", "0"])
        .arg(repo_root().join("scripts/render.sh"))
        .args(["--size", "500x500", "--stats", &scene])
        .env("POLYPIPE_LOAD", "0");
    let out = pipeline_tests::output_with_stdin(one_core, b"");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.lines().any(|l| l
            == "render: depth auto chose 0 (a core or less for the render: a deeper tree \
                cannot run its stages side by side and only adds work; the model not asked)"),
        "{err}"
    );
    assert_eq!(pipeline_tests::stat(&err, "depth_auto"), 0, "{err}");
    let zero = render_ok(&["--size", "500x500", "--depth", "0", &scene], b"");
    assert!(out.stdout == zero, "auto on one core against depth 0");
}
