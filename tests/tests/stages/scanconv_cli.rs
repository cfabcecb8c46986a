//! scanconv as a filter: exact fragment text for exact screen-space input.

use assert_cmd::Command;

fn scanconv(args: &[&str], input: &str) -> assert_cmd::assert::Assert {
    Command::new(pipeline_tests::bin("scanconv"))
        .args(args)
        .write_stdin(input)
        .assert()
}

/// A red square at depth 0.5 and a blue triangle whose depth runs 0.25 → 0.75 down the
/// screen, an empty polygon between them, then a second frame with one triangle.
const SCREEN: &str = "polypipe 1 screen 4 4
colour 255 0 0
1 1 0.5
3 1 0.5
3 3 0.5
1 3 0.5
NEXT.POLYGON
colour 9 9 9
NEXT.POLYGON
colour 0 0 255
0 0 0.25
4 0 0.25
0 4 0.75
NEXT.FRAME
colour 0 255 0
0.5 0.5 0
3.5 0.5 0
0.5 3.5 0
END
";

// DEPTH_ONE = 2^40: 0.5 is 0.5. The triangle's plane is depth = 0.25 + Y/8, so
// row r has depth 0.25 + (r + ½)/8 and a zero step along the row.
const SPANS: &str = "polypipe 2 fragments 4 4
colour 255 0 0
span 1 1 3 0.5 0
span 2 1 3 0.5 0
NEXT.POLYGON
colour 9 9 9
NEXT.POLYGON
colour 0 0 255
span 0 0 3 0.3125 0
span 1 0 2 0.4375 0
span 2 0 1 0.5625 0
NEXT.FRAME
colour 0 255 0
span 0 0 3 0 0
span 1 0 2 0 0
span 2 0 1 0 0
END
";

#[test]
fn spans_exactly() {
    scanconv(&["--text"], SCREEN).success().stdout(SPANS);
}

#[test]
fn pixels_exactly() {
    let input = "polypipe 1 screen 4 2
colour 1 2 3
0 0 0
2 0 0.25
2 2 0.25
0 2 0
END
";
    // depth = X/8: pixel centres 0.5 and 1.5 give 1/16 and 3/16; the step is 1/8.
    scanconv(&["--text", "--pixels"], input).success().stdout(
        "polypipe 2 fragments 4 2
colour 1 2 3
pixel 0 0 0.0625
pixel 1 0 0.1875
pixel 0 1 0.0625
pixel 1 1 0.1875
END
",
    );
    scanconv(&["--text"], input).success().stdout(
        "polypipe 2 fragments 4 2
colour 1 2 3
span 0 0 2 0.0625 0.125
span 1 0 2 0.0625 0.125
END
",
    );
}

#[test]
fn binary_output_reads_back_as_the_same_text() {
    let binary = scanconv(&[], SCREEN).success().get_output().stdout.clone();
    assert_eq!(&binary[..8], b"\x89PPIPE\r\n");
    // scanconv itself refuses fragments, naming the stage to use; the binary form is
    // recognised and read far enough to say so.
    Command::new(pipeline_tests::bin("scanconv"))
        .write_stdin(binary)
        .assert()
        .code(1)
        .stderr("scanconv: input is fragments-space, expected screen-space; this is scan converter output, for zbuf\n");
}

#[test]
fn stats_on_stderr() {
    scanconv(&["--stats"], SCREEN).success().stderr(
        "scanconv: 4 polygons in, 3 drawn, 8 spans, 16 pixels\n\
             @stats scanconv polygons_in=4 polygons_drawn=3 spans=8 pixels=16\n",
    );
    scanconv(&["--stats", "--pixels"], SCREEN).success().stderr(
        "scanconv: 4 polygons in, 3 drawn, 0 spans, 16 pixels\n\
             @stats scanconv polygons_in=4 polygons_drawn=3 spans=0 pixels=16\n",
    );
}

#[test]
fn wrong_space_is_refused() {
    scanconv(&[], "polypipe 1 world\ncolour 1 1 1\n0 0 0\nEND\n")
        .code(1)
        .stderr("scanconv: input is world-space, expected screen-space; put viewxf, the clipper chain and persp first\n");
}

#[test]
fn bad_input_names_the_position() {
    scanconv(
        &["--text"],
        "polypipe 1 screen 4 4\ncolour 1 1 1\n0 0 0\n1 x 0\nEND\n",
    )
    .code(1)
    .stdout("polypipe 2 fragments 4 4\n")
    .stderr("scanconv: line 4, column 3: expected y of vertex 1 (3 numbers a vertex in screen space), found `x`\n");
}

#[test]
fn frames_before_a_fault_are_written() {
    scanconv(
        &["--text"],
        "polypipe 1 screen 2 2\ncolour 1 1 1\n0 0 0\n2 0 0\n2 2 0\nNEXT.FRAME\ncolour 1 1 1\n0 0\n",
    )
    .code(1)
    .stdout("polypipe 2 fragments 2 2\ncolour 1 1 1\nspan 0 0 2 0 0\nspan 1 1 2 0 0\nNEXT.FRAME\n");
}

/// `--resolve`: the leaf decides visibility and sends, at each frame's end, its finished
/// pixels as runs along the rows; skips and colour records are not sent on. Frame 0: the
/// blue triangle (depth 0.3125, 0.4375, 0.5625 on rows 0–2) is in front of the red square
/// (0.5) on rows 0 and 1, behind it on row 2.
#[test]
fn resolve_exactly() {
    let input = SCREEN.replacen(
        "NEXT.FRAME\n",
        "NEXT.POLYGON\nskip 3\nNEXT.FRAME\nskip 1\nNEXT.POLYGON\n",
        1,
    );
    scanconv(&["--text", "--resolve"], &input).success().stdout(
        "polypipe 2 fragments 4 4
run 0 0 3 0 0 255
run 1 0 2 0 0 255
run 1 2 3 255 0 0
run 2 0 1 0 0 255
run 2 1 3 255 0 0
NEXT.FRAME
run 0 0 3 0 255 0
run 1 0 2 0 255 0
run 2 0 1 0 255 0
END
",
    );
    scanconv(&["--resolve", "--stats"], &input)
        .success()
        .stderr(
            "scanconv: 4 polygons in, 3 drawn, 16 pixels tested, 16 written, 8 runs out, 1 tiles\n\
             @stats scanconv polygons_in=4 polygons_drawn=3 pixels_tested=16 pixels_written=16 \
             runs_out=8 tiles=1 rounding_decided=0\n",
        );
    // Pixels and resolving do not go together.
    scanconv(&["--resolve", "--pixels"], SCREEN).code(2);
}
