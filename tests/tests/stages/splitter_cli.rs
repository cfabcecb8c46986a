//! The splitter binary on exact text streams: what each output receives, and how it
//! refuses bad arguments and bad input.

use assert_cmd::Command;
use std::path::PathBuf;

/// A fresh directory for one test's output files.
fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("splitter-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Eye space of the default camera at z_e = 16 (w = 10): x=0 is x_e = 0, y=0.5 is
/// y_e = 5. A square cut by x=0, a diamond with two vertices on it, a triangle wholly
/// left of it; a second frame with a triangle cut by y=0.5.
const EYE: &str = "polypipe 1 eye aspect 1 hither 1 yon 30
colour 255 0 0
-2 -2 16 10
-2 2 16 10
2 2 16 10
2 -2 16 10
NEXT.POLYGON
colour 0 255 0
0 -3 16 10
-3 0 16 10
0 3 16 10
3 0 16 10
NEXT.POLYGON
colour 0 0 255
-3 0 16 10
-1 4 16 10
-2 -2 16 10
NEXT.FRAME
colour 7 7 7
0 0 16 10
4 8 16 10
-4 8 16 10
END
";

/// Runs `splitter ARGS… OUT1 OUT2 --text` and returns both outputs' text.
fn split(name: &str, args: &[&str]) -> (String, String) {
    let dir = scratch(name);
    let (a, b) = (dir.join("out1"), dir.join("out2"));
    Command::new(pipeline_tests::bin("splitter"))
        .args(args)
        .arg(&a)
        .arg(&b)
        .arg("--text")
        .write_stdin(EYE)
        .assert()
        .success()
        .stderr("");
    (
        std::fs::read_to_string(a).unwrap(),
        std::fs::read_to_string(b).unwrap(),
    )
}

#[test]
fn splits_about_x_0() {
    // Every polygon really cut gets its plane (here z_e = 16 exactly), and every piece of a
    // cut edge the edge's two ends after `on`; new edges along x_e = 0 get none.
    let (out1, out2) = split("x0", &["x=0"]);
    assert_eq!(
        out1,
        "polypipe 1 eye aspect 1 hither 1 yon 30
colour 255 0 0
plane 0 0 1 -16
0 -2 16 10 on 2 -2 16 10 -2 -2 16 10
-2 -2 16 10
-2 2 16 10 on -2 2 16 10 2 2 16 10
0 2 16 10
NEXT.POLYGON
colour 0 255 0
plane 0 0 1 -16
0 -3 16 10
-3 0 16 10
0 3 16 10
NEXT.POLYGON
colour 0 0 255
-3 0 16 10
-1 4 16 10
-2 -2 16 10
NEXT.FRAME
colour 7 7 7
plane 0 0 1 -16
0 0 16 10
0 8 16 10 on 4 8 16 10 -4 8 16 10
-4 8 16 10
END
"
    );
    assert_eq!(
        out2,
        "polypipe 1 eye aspect 1 hither 1 yon 30
colour 255 0 0
plane 0 0 1 -16
0 -2 16 10
0 2 16 10 on -2 2 16 10 2 2 16 10
2 2 16 10
2 -2 16 10 on 2 -2 16 10 -2 -2 16 10
NEXT.POLYGON
colour 0 255 0
plane 0 0 1 -16
0 -3 16 10
0 3 16 10
3 0 16 10
NEXT.POLYGON
skip 1
NEXT.FRAME
colour 7 7 7
plane 0 0 1 -16
0 0 16 10
4 8 16 10 on 4 8 16 10 -4 8 16 10
0 8 16 10
END
"
    );
}

#[test]
fn splits_about_y_one_half() {
    let (out1, out2) = split("y05", &["y=0.5"]);
    // y_e = 5 lies above the whole first frame (out2 gets nothing of its three polygons:
    // one `skip 3` in their place); it cuts
    // the triangle of the second frame at (±2.5, 5).
    assert_eq!(
        out1,
        "polypipe 1 eye aspect 1 hither 1 yon 30
colour 255 0 0
-2 -2 16 10
-2 2 16 10
2 2 16 10
2 -2 16 10
NEXT.POLYGON
colour 0 255 0
0 -3 16 10
-3 0 16 10
0 3 16 10
3 0 16 10
NEXT.POLYGON
colour 0 0 255
-3 0 16 10
-1 4 16 10
-2 -2 16 10
NEXT.FRAME
colour 7 7 7
plane 0 0 1 -16
-2.5 5 16 10 on -4 8 16 10 0 0 16 10
0 0 16 10 on 0 0 16 10 4 8 16 10
2.5 5 16 10
END
"
    );
    assert_eq!(
        out2,
        "polypipe 1 eye aspect 1 hither 1 yon 30
skip 3
NEXT.FRAME
colour 7 7 7
plane 0 0 1 -16
-2.5 5 16 10
2.5 5 16 10 on 0 0 16 10 4 8 16 10
4 8 16 10
-4 8 16 10 on -4 8 16 10 0 0 16 10
END
"
    );
}

#[test]
fn a_general_plane_and_stdout() {
    // 1·x_e + 0 + 0 − 0.1·w + 0 ≥ 0: x_e ≥ 1 at w = 10, to stdout (OUT1 = -).
    let dir = scratch("general");
    let b = dir.join("out2");
    Command::new(pipeline_tests::bin("splitter"))
        .args(["--plane", "1,0,0,-0.1,0", "-"])
        .arg(&b)
        .args(["--text", "--stats"])
        .write_stdin(
            "polypipe 1 eye aspect 1 hither 1 yon 30\ncolour 1 2 3\n0 0 16 10\n2 0 16 10\n2 2 16 10\nEND\n",
        )
        .assert()
        .success()
        .stdout(
            "polypipe 1 eye aspect 1 hither 1 yon 30\ncolour 1 2 3\nplane 0 0 1 -16\n1 1 16 10\n1 0 16 10 on 0 0 16 10 2 0 16 10\n2 0 16 10\n2 2 16 10 on 2 2 16 10 0 0 16 10\nEND\n",
        )
        .stderr(
            "splitter 1,0,0,-0.1,0: 1 polygons in; out1 1 polygons, 4 vertices; out2 1 polygons, 3 vertices; \
             159 and 149 bytes out\n\
             @stats splitter plane=1,0,0,-0.1,0 polygons_in=1 out1_polygons=1 out1_vertices=4 \
             out2_polygons=1 out2_vertices=3 out1_bytes=159 out2_bytes=149\n",
        );
    // The byte counts are the two outputs' lengths (stdout's is checked above).
    assert_eq!(std::fs::metadata(&b).unwrap().len(), 149);
    assert_eq!(
        std::fs::read_to_string(b).unwrap(),
        "polypipe 1 eye aspect 1 hither 1 yon 30\ncolour 1 2 3\nplane 0 0 1 -16\n1 1 16 10 on 2 2 16 10 0 0 16 10\n0 0 16 10 on 0 0 16 10 2 0 16 10\n1 0 16 10\nEND\n"
    );
}

#[test]
fn column_planes_use_the_aspect_ratio() {
    // a = 2: x=0.5 is x_e = 0.5·2·w = 10 at w = 10.
    let dir = scratch("aspect");
    let b = dir.join("out2");
    Command::new(pipeline_tests::bin("splitter"))
        .args(["x=0.5", "-"])
        .arg(&b)
        .arg("--text")
        .write_stdin(
            "polypipe 1 eye aspect 2 hither 1 yon 30\ncolour 1 2 3\n8 0 16 10\n12 0 16 10\n12 4 16 10\nEND\n",
        )
        .assert()
        .success()
        .stdout(
            "polypipe 1 eye aspect 2 hither 1 yon 30\ncolour 1 2 3\nplane 0 0 1 -16\n10 2 16 10 on 12 4 16 10 8 0 16 10\n8 0 16 10 on 8 0 16 10 12 0 16 10\n10 0 16 10\nEND\n",
        );
    assert_eq!(
        std::fs::read_to_string(b).unwrap(),
        "polypipe 1 eye aspect 2 hither 1 yon 30\ncolour 1 2 3\nplane 0 0 1 -16\n10 2 16 10\n10 0 16 10 on 8 0 16 10 12 0 16 10\n12 0 16 10\n12 4 16 10 on 12 4 16 10 8 0 16 10\nEND\n"
    );
}

#[test]
fn binary_output_reads_back_as_the_text() {
    let dir = scratch("binary");
    let (a, b) = (dir.join("a.bin"), dir.join("b.bin"));
    Command::new(pipeline_tests::bin("splitter"))
        .arg("x=0")
        .arg(&a)
        .arg(&b)
        .write_stdin(EYE)
        .assert()
        .success();
    let bin = std::fs::read(&a).unwrap();
    assert_eq!(bin[0], 0x89, "binary by default");
    // Splitting out1 again at the same plane changes nothing and sends nothing across.
    Command::new(pipeline_tests::bin("splitter"))
        .args(["x=0", "-"])
        .arg(dir.join("c"))
        .arg("--text")
        .write_stdin(bin)
        .assert()
        .success()
        .stdout(split("binary-text", &["x=0"]).0);
}

#[test]
fn k_off_the_screen_is_a_usage_error() {
    for plane in ["x=1.5", "y=-1.01", "x=nan"] {
        Command::new(pipeline_tests::bin("splitter"))
            .args([plane, "a", "b"])
            .write_stdin(EYE)
            .assert()
            .code(2)
            .stderr(predicates::str::contains(plane));
    }
    Command::new(pipeline_tests::bin("splitter"))
        .args(["x=1.5", "a", "b"])
        .assert()
        .code(2)
        .stderr(predicates::str::contains("K must be in [-1, 1]"));
}

#[test]
fn other_bad_arguments() {
    let cases: &[&[&str]] = &[
        &["z=0", "a", "b"],
        &["x=0", "a"],
        &["x=0", "-", "-"],
        &["--plane", "1,0,0", "a", "b"],
        &["--plane", "1,0,0,0,0", "x=0", "a", "b"],
    ];
    for args in cases {
        Command::new(pipeline_tests::bin("splitter"))
            .args(*args)
            .write_stdin(EYE)
            .assert()
            .code(2);
    }
}

#[test]
fn world_space_input_is_refused() {
    let dir = scratch("world");
    Command::new(pipeline_tests::bin("splitter"))
        .arg("x=0")
        .arg(dir.join("a"))
        .arg(dir.join("b"))
        .write_stdin("polypipe 1 world\ncolour 1 2 3\n0 0 0\n1 0 0\n0 1 0\nEND\n")
        .assert()
        .code(1)
        .stdout("")
        .stderr("splitter: input is world-space, expected eye-space; put viewxf first\n");
}

#[test]
fn bad_input_is_located_and_finished_frames_are_kept() {
    let dir = scratch("bad");
    let (a, b) = (dir.join("a"), dir.join("b"));
    Command::new(pipeline_tests::bin("splitter"))
        .arg("x=0")
        .arg(&a)
        .arg(&b)
        .arg("--text")
        .write_stdin(
            "polypipe 1 eye aspect 1 hither 1 yon 30\ncolour 1 2 3\n-1 0 16 10\nNEXT.FRAME\ncolour 1 2 3\n1 0 16\n",
        )
        .assert()
        .code(1)
        .stderr(predicates::str::starts_with("splitter: line 6"));
    // The one-vertex polygon draws nothing on either side: a skip on both.
    for out in [a, b] {
        assert_eq!(
            std::fs::read_to_string(out).unwrap(),
            "polypipe 1 eye aspect 1 hither 1 yon 30\nskip 1\nNEXT.FRAME\n"
        );
    }
}

/// The lean stream: polygons an output gets nothing of in a row, and skips
/// that arrive, become one `skip N` on that output, written just before its next record;
/// polygon k stays polygon k on both outputs.
#[test]
fn skips_coalesce_and_keep_numbering() {
    let dir = scratch("lean");
    let (a, b) = (dir.join("a"), dir.join("b"));
    let left = "-3 0 16 10\n-1 4 16 10\n-2 -2 16 10\n";
    let right = "3 0 16 10\n1 4 16 10\n2 -2 16 10\n";
    let input = format!(
        "polypipe 1 eye aspect 1 hither 1 yon 30\nskip 2\nNEXT.POLYGON\ncolour 1 1 1\n{left}\
         NEXT.POLYGON\ncolour 2 2 2\n{right}NEXT.POLYGON\ncolour 3 3 3\nNEXT.POLYGON\nskip 3\n\
         NEXT.POLYGON\ncolour 4 4 4\n{left}NEXT.FRAME\nskip 1\nEND\n"
    );
    Command::new(pipeline_tests::bin("splitter"))
        .args(["--text", "--stats", "x=0"])
        .arg(&a)
        .arg(&b)
        .write_stdin(input)
        .assert()
        .success()
        .stderr(
            "splitter x=0: 10 polygons in; out1 2 polygons, 6 vertices; out2 1 polygons, \
             3 vertices; 209 and 146 bytes out\n\
             @stats splitter plane=x%3D0 polygons_in=10 out1_polygons=2 out1_vertices=6 \
             out2_polygons=1 out2_vertices=3 out1_bytes=209 out2_bytes=146\n",
        );
    let sizes = [&a, &b].map(|f| std::fs::metadata(f).unwrap().len());
    assert_eq!(
        sizes,
        [209, 146],
        "--stats counts the bytes each output carried"
    );
    assert_eq!(
        std::fs::read_to_string(&a).unwrap(),
        format!(
            "polypipe 1 eye aspect 1 hither 1 yon 30\nskip 2\nNEXT.POLYGON\ncolour 1 1 1\n{left}\
             NEXT.POLYGON\nskip 5\nNEXT.POLYGON\ncolour 4 4 4\n{left}NEXT.FRAME\nskip 1\nEND\n"
        )
    );
    assert_eq!(
        std::fs::read_to_string(&b).unwrap(),
        format!(
            "polypipe 1 eye aspect 1 hither 1 yon 30\nskip 3\nNEXT.POLYGON\ncolour 2 2 2\n{right}\
             NEXT.POLYGON\nskip 5\nNEXT.FRAME\nskip 1\nEND\n"
        )
    );
}

/// `--project`: both outputs in screen space, byte for byte what `persp` makes of the
/// plain outputs (the square's cut at x_e = 0 lands on X = 4 of an 8×8 screen; every
/// vertex is at z_e = 16, so at the reciprocal depth −1/16).
#[test]
fn persp_projects_both_outputs_as_persp_would() {
    let (out1, out2) = split("persp", &["--size", "8x8", "--project", "x=0"]);
    assert_eq!(
        out1,
        "polypipe 1 screen 8 8 depth reciprocal 1
colour 255 0 0
plane -0 0 -1 -0.0625
4 4.8 -0.0625 on 4.8 4.8 -0.0625 3.2 4.8 -0.0625
3.2 4.8 -0.0625
3.2 3.2 -0.0625 on 3.2 3.2 -0.0625 4.8 3.2 -0.0625
4 3.2 -0.0625
NEXT.POLYGON
colour 0 255 0
plane -0 0 -1 -0.0625
4 5.2 -0.0625
2.8 4 -0.0625
4 2.8 -0.0625
NEXT.POLYGON
colour 0 0 255
plane -0 0 -1 -0.0625
2.8 4 -0.0625
3.6 2.4 -0.0625
3.2 4.8 -0.0625
NEXT.FRAME
colour 7 7 7
plane -0 0 -1 -0.0625
4 4 -0.0625
4 0.7999999999999998 -0.0625 on 5.6 0.7999999999999998 -0.0625 2.4 0.7999999999999998 -0.0625
2.4 0.7999999999999998 -0.0625
END
"
    );
    assert_eq!(
        out2,
        "polypipe 1 screen 8 8 depth reciprocal 1
colour 255 0 0
plane -0 0 -1 -0.0625
4 4.8 -0.0625
4 3.2 -0.0625 on 3.2 3.2 -0.0625 4.8 3.2 -0.0625
4.8 3.2 -0.0625
4.8 4.8 -0.0625 on 4.8 4.8 -0.0625 3.2 4.8 -0.0625
NEXT.POLYGON
colour 0 255 0
plane -0 0 -1 -0.0625
4 5.2 -0.0625
4 2.8 -0.0625
5.2 4 -0.0625
NEXT.POLYGON
skip 1
NEXT.FRAME
colour 7 7 7
plane -0 0 -1 -0.0625
4 4 -0.0625
5.6 0.7999999999999998 -0.0625 on 5.6 0.7999999999999998 -0.0625 2.4 0.7999999999999998 -0.0625
4 0.7999999999999998 -0.0625
END
"
    );
    // Each output is what persp makes of the plain split's (as text, through the
    // workspace's persp binary), with each depth form (`--zmode`, reciprocal by default).
    let (plain1, plain2) = split("persp-plain", &["x=0"]);
    let persp = pipeline_tests::bin_dir().join("persp");
    let mut cases = vec![
        ("reciprocal", plain1.clone(), out1),
        ("reciprocal", plain2.clone(), out2),
    ];
    for mode in ["reciprocal", "projective", "eye-z"] {
        let name = format!("persp-{mode}");
        let (out1, out2) = split(
            &name,
            &["--size", "8x8", "--project", "--zmode", mode, "x=0"],
        );
        assert!(
            out1.starts_with(&format!("polypipe 1 screen 8 8 depth {mode}")),
            "{out1}"
        );
        cases.push((mode, plain1.clone(), out1));
        cases.push((mode, plain2.clone(), out2));
    }
    for (mode, plain, projected) in cases {
        let out = std::process::Command::new(&persp)
            .args(["--size", "8x8", "--zmode", mode, "--text"])
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .spawn()
            .and_then(|mut child| {
                use std::io::Write;
                child.stdin.take().unwrap().write_all(plain.as_bytes())?;
                child.wait_with_output()
            })
            .unwrap();
        assert!(out.status.success(), "{out:?}");
        assert_eq!(String::from_utf8(out.stdout).unwrap(), projected);
    }
}

/// `--project` refuses what persp refuses, with persp's words: a screen of another shape
/// than the stream was viewed for, a vertex behind the eye; it needs `--size`, and
/// `--zmode` is for it.
#[test]
fn persp_refuses_as_persp_does() {
    let dir = scratch("persp-bad");
    let (a, b) = (dir.join("a"), dir.join("b"));
    let run = |args: &[&str], input: &str| {
        Command::new(pipeline_tests::bin("splitter"))
            .args(args)
            .arg(&a)
            .arg(&b)
            .write_stdin(input.to_string())
            .assert()
    };
    run(&["--size", "8x6", "--project", "x=0"], EYE)
        .code(1)
        .stderr(
            "splitter: --size 8x6 has aspect 1.333 but the stream was viewed with aspect 1; \
             give viewxf --size 8x6\n",
        );
    let behind = "polypipe 1 eye aspect 1 hither 1 yon 30\ncolour 1 2 3\n\
                  -1 -1 -1 -1\n1 -1 -1 -1\n0 1 -1 -1\nEND\n";
    run(&["--size", "8x8", "--project", "x=0"], behind)
        .code(1)
        .stderr(
            "splitter: frame 0, polygon 0: vertex 0 (-1 -1 -1 -1) has w = -1 ≤ 0, at or \
             behind the eye, and cannot be projected; clip against hither first (clipplane \
             hither)\n",
        );
    run(&["--project", "--zmode", "eye-z", "x=0"], EYE)
        .code(2)
        .stderr("splitter: the following required arguments were not provided: --size <WxH>\n");
    run(&["--size", "8x8", "x=0"], EYE)
        .code(2)
        .stderr("splitter: --size is for --node or --project\n");
    run(&["--size", "8x8", "--zmode", "projective", "x=0"], EYE)
        .code(2)
        .stderr(
            "splitter: --zmode projective is for --project (the depth its projection writes)\n",
        );
}

/// `--persp MODE`, the old spelling of `--project --zmode MODE`, is still taken for one
/// release: the same outputs, and a note on stderr saying what it is now called; beside
/// the new spelling it is refused.
#[test]
fn old_persp_spelling_still_works_with_a_note() {
    let dir = scratch("persp-old");
    let (a, b) = (dir.join("a"), dir.join("b"));
    let run = |args: &[&str]| {
        Command::new(pipeline_tests::bin("splitter"))
            .args(args)
            .arg(&a)
            .arg(&b)
            .arg("--text")
            .write_stdin(EYE)
            .assert()
    };
    let (new1, new2) = split(
        "persp-new",
        &["--size", "8x8", "--project", "--zmode", "eye-z", "x=0"],
    );
    run(&["--size", "8x8", "--persp", "eye-z", "x=0"])
        .success()
        .stderr(
            "splitter: --persp MODE is now --project --zmode MODE; the old spelling goes in \
             the next release\n",
        );
    assert_eq!(std::fs::read_to_string(&a).unwrap(), new1);
    assert_eq!(std::fs::read_to_string(&b).unwrap(), new2);
    run(&[
        "--size", "8x8", "--persp", "eye-z", "--zmode", "eye-z", "x=0",
    ])
    .code(2)
    .stderr("splitter: the argument '--persp <MODE>' cannot be used with '--zmode <MODE>'\n");
    // That the help tells of --project and --zmode, not of the old spelling, is held for
    // every binary that projects by tests/tests/composer/depth_option.rs.
}

/// `--levels L` is node K and the nodes below it in one process: its outputs are the
/// bytes that a process per node, chained through files, gives the same nodes' outputs,
/// on a two-frame movie of 400 polygons on a 97x61 screen (depth 3: node 1 with 3 levels;
/// node 2 with 2, its last level projecting; depth 2: node 1 with 2), with --stats
/// counting each node as its own process would.
#[test]
fn levels_in_one_process_write_what_a_process_per_node_writes() {
    let dir = scratch("levels");
    let bin = pipeline_tests::bin_dir();
    let eye = dir.join("eye");
    let scene = std::process::Command::new(bin.join("scene"))
        .args("environment --polygons 400 --depth-complexity 3 --frames 2".split(' '))
        .output()
        .unwrap();
    assert!(scene.status.success());
    let viewed = Command::new(bin.join("viewxf"))
        .args(["--size", "97x61"])
        .write_stdin(scene.stdout)
        .output()
        .unwrap();
    assert!(viewed.status.success());
    let clipped = Command::new(bin.join("clipbatch"))
        .write_stdin(viewed.stdout)
        .output()
        .unwrap();
    assert!(clipped.status.success());
    std::fs::write(&eye, &clipped.stdout).unwrap();
    let node = |k: u32, depth: u32, extra: &[&str], input: &PathBuf, outs: &[PathBuf]| {
        let out = Command::new(pipeline_tests::bin("splitter"))
            .args([
                "--stats",
                "--node",
                &k.to_string(),
                "--depth",
                &depth.to_string(),
            ])
            .args(["--size", "97x61"])
            .args(extra)
            .args(outs)
            .pipe_stdin(input)
            .unwrap()
            .output()
            .unwrap();
        assert!(out.status.success(), "{out:?}");
        String::from_utf8(out.stderr).unwrap()
    };
    let file = |name: String| dir.join(name);
    for (root, levels, depth, persp) in [(1, 3, 3, false), (2, 2, 3, true), (1, 2, 2, false)] {
        let extra: &[&str] = if persp { &["--project"] } else { &[] };
        // A process per node, level by level, the last level projecting if asked.
        let mut chained = String::new();
        let mut first = root;
        for level in 0..levels {
            for k in first..first + (1 << level) {
                let input = if k == root {
                    eye.clone()
                } else {
                    file(format!("c{k}"))
                };
                let outs = [file(format!("c{}", 2 * k)), file(format!("c{}", 2 * k + 1))];
                let last = level + 1 == levels;
                chained += &node(k, depth, if last { extra } else { &[] }, &input, &outs);
            }
            first *= 2;
        }
        // One process.
        let last = first + (1 << levels);
        let outs: Vec<PathBuf> = (first..last).map(|k| file(format!("f{k}"))).collect();
        let mut args = vec!["--levels".to_string(), levels.to_string()];
        args.extend(extra.iter().map(|s| s.to_string()));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let fused = node(root, depth, &args, &eye, &outs);
        for k in first..last {
            let (a, b) = (file(format!("c{k}")), file(format!("f{k}")));
            assert_eq!(
                std::fs::read(&a).unwrap(),
                std::fs::read(&b).unwrap(),
                "node {root}, {levels} levels: output for node {k}"
            );
        }
        // The same counts, node by node; the bytes only where this process writes them.
        let records = |s: &str| stagecli::stats::records(s).unwrap();
        let (c, f) = (records(&chained), records(&fused));
        assert_eq!(c.len(), f.len(), "{fused}");
        let bytes = ["out1_bytes", "out2_bytes"];
        for (c, f) in c.iter().zip(&f) {
            assert!(c.count("out1_bytes").is_some(), "{c}");
            if f.get("out1_bytes").is_some() {
                assert_eq!(c, f);
            } else {
                let mut without = stagecli::stats::Record::new("splitter");
                for (k, v) in c.fields() {
                    if !bytes.contains(&k.as_str()) {
                        without.set(k, v);
                    }
                }
                assert_eq!(&without, f);
            }
        }
        let written = f.iter().filter(|r| r.get("out1_bytes").is_some()).count();
        assert_eq!(written, 1 << (levels - 1));
    }
}

#[test]
fn levels_refuses_a_subtree_outside_the_tree_or_the_wrong_outputs() {
    let run = |args: &[&str]| {
        Command::new(pipeline_tests::bin("splitter"))
            .args(args)
            .write_stdin(EYE)
            .assert()
            .code(2)
    };
    run(&[
        "--node", "2", "--depth", "2", "--levels", "2", "--size", "8x8", "a", "b", "c", "d",
    ])
    .stderr(
        "splitter: --levels 2: node 2 and the nodes below it, 2 levels deep, are not all \
             splitter nodes of a depth-2 tree (nodes 1 to 3)\n",
    );
    run(&[
        "--node", "1", "--depth", "3", "--levels", "2", "--size", "8x8", "a", "b",
    ])
    .stderr("splitter: with --node and --levels 2, give the 4 outputs, left to right (2 given)\n");
    run(&[
        "--node", "1", "--depth", "3", "--levels", "0", "--size", "8x8", "a", "b",
    ])
    .stderr(
        "splitter: invalid value '0' for '--levels <L>': `0` is not a whole number from 1 \
         to 31\n",
    );
    run(&["--levels", "2", "x=0", "a", "b"]).stderr(predicates::str::contains("--node"));
    run(&[
        "--node", "1", "--depth", "2", "--levels", "2", "--size", "8x8", "-", "b", "-", "d",
    ])
    .stderr("splitter: at most one output may be `-` (stdout)\n");
    run(&[
        "--node", "1", "--depth", "2", "--levels", "2", "--size", "8x8", "a", "b", "c", "a",
    ])
    .stderr(predicates::str::contains("OUT1 a and OUT4 a are one file"));
}
