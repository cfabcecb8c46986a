//! clipplane as a filter: the four Sutherland–Hodgman cases on each of the six planes,
//! with exact vertex lists; general planes; refusals and exit codes.

use assert_cmd::Command;
use predicates::prelude::*;
use proto::{Form, Header, Polygon, Space, Token, View, Writer};

fn clipplane() -> Command {
    Command::new(pipeline_tests::bin("clipplane"))
}

const HEADER: &str = "polypipe 1 eye aspect 1 hither 1 yon 30\n";

/// Each test is written once in plane-local coordinates (u, v): u measures towards the
/// inside, the plane is at u = −10, v runs along the plane. `eye` places a local point in
/// eye space for each pyramid plane of the default volume (aspect 1, K1 = 1, K2 = 30):
/// the side planes at z_e = 16, w = 10 (so |x_e| ≤ 10, |y_e| ≤ 10); hither at
/// z_e = 11 + u (z_e ≥ 1), yon at z_e = 20 − u (z_e ≤ 30), with w = z_e·10/16. All the
/// numbers are dyadic, so the expected intersections are exact.
fn eye(plane: &str, u: f64, v: f64) -> [f64; 4] {
    match plane {
        "left" => [u, v, 16.0, 10.0],
        "right" => [-u, v, 16.0, 10.0],
        "bottom" => [v, u, 16.0, 10.0],
        "top" => [v, -u, 16.0, 10.0],
        "hither" => [v, 1.0, 11.0 + u, (11.0 + u) * 0.625],
        "yon" => [v, 1.0, 20.0 - u, (20.0 - u) * 0.625],
        _ => unreachable!(),
    }
}

const PLANES: [&str; 6] = ["left", "right", "top", "bottom", "hither", "yon"];

fn polygon_text(plane: &str, colour: &str, pts: &[(f64, f64)]) -> String {
    let mut s = format!("colour {colour}\n");
    for &(u, v) in pts {
        let [x, y, z, w] = eye(plane, u, v);
        s += &format!("{x} {y} {z} {w}\n");
    }
    s
}

/// Clips one polygon (local coordinates) against each plane and checks the exact output.
fn check_each_plane(input: &[(f64, f64)], expected: &[(f64, f64)]) {
    for plane in PLANES {
        let stdin = format!("{HEADER}{}END\n", polygon_text(plane, "7 8 9", input));
        let stdout = format!("{HEADER}{}END\n", polygon_text(plane, "7 8 9", expected));
        clipplane()
            .args([plane, "--text"])
            .write_stdin(stdin)
            .assert()
            .success()
            .stdout(stdout)
            .stderr("");
    }
}

#[test]
fn inside_to_inside_outputs_p() {
    // Every edge in→in (one vertex exactly on the plane counts as inside): unchanged.
    let quad = [(2.0, 0.0), (6.0, 0.0), (6.0, 5.0), (-10.0, 5.0)];
    check_each_plane(&quad, &quad);
}

#[test]
fn inside_to_outside_outputs_the_intersection() {
    // Edges: (2,8)→(2,0) in→in: (2,0). (2,0)→(−22,8) in→out: the midpoint (−10,4).
    // (−22,8)→(2,8) out→in: (−10,8), then (2,8).
    check_each_plane(
        &[(2.0, 0.0), (-22.0, 8.0), (2.0, 8.0)],
        &[(2.0, 0.0), (-10.0, 4.0), (-10.0, 8.0), (2.0, 8.0)],
    );
}

#[test]
fn outside_to_outside_outputs_nothing() {
    // Edges: (−22,6)→(2,2) out→in gives (−10,4), (2,2). (2,2)→(−22,−2) in→out: (−10,0).
    // (−22,−2)→(−30,0) and (−30,0)→(−22,6) out→out: nothing.
    check_each_plane(
        &[(2.0, 2.0), (-22.0, -2.0), (-30.0, 0.0), (-22.0, 6.0)],
        &[(-10.0, 4.0), (2.0, 2.0), (-10.0, 0.0)],
    );
    // Every edge out→out: the polygon becomes empty but is still passed on.
    check_each_plane(&[(-22.0, 0.0), (-30.0, 0.0), (-22.0, 5.0)], &[]);
}

#[test]
fn outside_to_inside_outputs_the_intersection_then_p() {
    // (6,8)→(6,0) in→in: (6,0). (6,0)→(−26,4) in→out: α = 16/32, (−10,2).
    // (−26,4)→(6,8) out→in: (−10,6), then (6,8).
    check_each_plane(
        &[(6.0, 0.0), (-26.0, 4.0), (6.0, 8.0)],
        &[(6.0, 0.0), (-10.0, 2.0), (-10.0, 6.0), (6.0, 8.0)],
    );
}

#[test]
fn vertices_on_the_plane_are_not_doubled() {
    // on→out and out→on compute no intersection: the on-vertices stand for them.
    check_each_plane(
        &[(2.0, 0.0), (-10.0, 5.0), (-22.0, 0.0), (-10.0, -5.0)],
        &[(2.0, 0.0), (-10.0, 5.0), (-10.0, -5.0)],
    );
    // Degenerate results are passed on: one vertex on the plane, the rest outside.
    check_each_plane(
        &[(-10.0, 0.0), (-22.0, 4.0), (-22.0, -4.0)],
        &[(-10.0, 0.0)],
    );
}

#[test]
fn numbering_kept_across_frames() {
    let stdin = format!(
        "{HEADER}colour 1 1 1\n0 0 16 10\nNEXT.POLYGON\ncolour 2 2 2\n-30 0 16 10\n\
         NEXT.POLYGON\ncolour 3 3 3\nNEXT.FRAME\ncolour 4 4 4\n-30 0 16 10\n10 0 16 10\n10 4 16 10\nEND\n"
    );
    clipplane()
        .args(["left", "--text"])
        .write_stdin(stdin)
        .assert()
        .success()
        .stdout(format!(
            "{HEADER}colour 1 1 1\n0 0 16 10\nNEXT.POLYGON\ncolour 2 2 2\n\
             NEXT.POLYGON\ncolour 3 3 3\nNEXT.FRAME\ncolour 4 4 4\n-10 2 16 10\n-10 0 16 10\n10 0 16 10\n10 4 16 10\nEND\n"
        ));
}

#[test]
fn aspect_from_the_header() {
    // a = 2: the left plane is x_e ≥ −2w = −20.
    clipplane()
        .args(["left", "--text"])
        .write_stdin(
            "polypipe 1 eye aspect 2 hither 1 yon 30\ncolour 1 1 1\n0 0 16 10\n-40 0 16 10\n0 4 16 10\nEND\n",
        )
        .assert()
        .success()
        .stdout("polypipe 1 eye aspect 2 hither 1 yon 30\ncolour 1 1 1\n0 0 16 10\n-20 0 16 10\n-20 2 16 10\n0 4 16 10\nEND\n");
}

#[test]
fn at_overrides_hither_and_yon() {
    let input = format!("{HEADER}colour 1 1 1\n0 0 2 1.25\n0 0 10 6.25\n4 0 10 6.25\nEND\n");
    clipplane()
        .args(["hither", "--at", "4", "--text"])
        .write_stdin(input.clone())
        .assert()
        .success()
        .stdout(format!(
            "{HEADER}colour 1 1 1\n1 0 4 2.5\n0 0 4 2.5\n0 0 10 6.25\n4 0 10 6.25\nEND\n"
        ));
    clipplane()
        .args(["yon", "--at", "6", "--text"])
        .write_stdin(input)
        .assert()
        .success()
        .stdout(format!(
            "{HEADER}colour 1 1 1\n2 0 6 3.75\n0 0 2 1.25\n0 0 6 3.75\nEND\n"
        ));
}

#[test]
fn general_plane() {
    // Inside where x_e − 3 ≥ 0.
    clipplane()
        .args(["--plane", "1,0,0,0,-3", "--text"])
        .write_stdin(format!(
            "{HEADER}colour 1 1 1\n0 0 16 10\n8 2 16 10\n8 -2 16 10\nEND\n"
        ))
        .assert()
        .success()
        .stdout(format!(
            "{HEADER}colour 1 1 1\n3 -0.75 16 10\n3 0.75 16 10\n8 2 16 10\n8 -2 16 10\nEND\n"
        ));
}

#[test]
fn usage_errors() {
    for (args, msg) in [
        (vec![], "PLANE"),
        (vec!["front"], "unknown plane `front`"),
        (
            vec!["left", "--at", "3"],
            "--at sets the distance of the hither or yon plane, not of left",
        ),
        (vec!["hither", "--at", "-1"], "must be in front of the eye"),
        (vec!["--plane", "0,0,0,0,1"], "a, b, c and d are all zero"),
        (vec!["--plane", "1,2,3"], "expected a,b,c,d,k"),
        (vec!["left", "--plane", "1,0,0,0,0"], "cannot be used with"),
    ] {
        clipplane()
            .args(&args)
            .write_stdin(format!("{HEADER}END\n"))
            .assert()
            .code(2)
            .stdout("")
            .stderr(predicate::str::contains(msg));
    }
}

#[test]
fn wrong_space_is_refused() {
    clipplane()
        .arg("left")
        .write_stdin("polypipe 1 world\nEND\n")
        .assert()
        .code(1)
        .stdout("")
        .stderr("clipplane: input is world-space, expected eye-space; put viewxf first\n");
    clipplane()
        .arg("left")
        .write_stdin("polypipe 1 screen 4 4\nEND\n")
        .assert()
        .code(1)
        .stderr(predicate::str::contains(
            "input is screen-space, expected eye-space",
        ));
}

#[test]
fn bad_input_names_the_position() {
    clipplane()
        .arg("top")
        .write_stdin(format!("{HEADER}colour 1 1 1\n0 0 16\nEND\n"))
        .assert()
        .code(1)
        .stderr(predicate::str::starts_with("clipplane: line 4, column 1:"));
}

#[test]
fn binary_in_text_out_equals_text_in_text_out() {
    let text_in = format!(
        "{HEADER}colour 9 9 9\n2 0 16 10\n-22 8 16 10\n2 8 16 10\nNEXT.FRAME\ncolour 1 2 3\nEND\n"
    );
    let expected = format!(
        "{HEADER}colour 9 9 9\n2 0 16 10\n-10 4 16 10\n-10 8 16 10\n2 8 16 10\nNEXT.FRAME\ncolour 1 2 3\nEND\n"
    );
    clipplane()
        .args(["left", "--text"])
        .write_stdin(text_in.clone())
        .assert()
        .success()
        .stdout(expected.clone());
    // The same stream in binary, written by proto.
    let mut w = Writer::new(
        Vec::new(),
        Header::new(Space::Eye(View::default())),
        Form::Binary,
    )
    .unwrap();
    for t in [
        Token::Polygon(Polygon::new(
            [9, 9, 9],
            vec![
                proto::DVec4::new(2.0, 0.0, 16.0, 10.0),
                proto::DVec4::new(-22.0, 8.0, 16.0, 10.0),
                proto::DVec4::new(2.0, 8.0, 16.0, 10.0),
            ],
        )),
        Token::NextFrame,
        Token::Polygon(Polygon::new([1, 2, 3], vec![])),
        Token::End,
    ] {
        w.write(&t).unwrap();
    }
    let binary_in = w.into_inner().unwrap();
    clipplane()
        .args(["left", "--text"])
        .write_stdin(binary_in.clone())
        .assert()
        .success()
        .stdout(expected.clone());
    // Binary out of one stage into the next (left then right: nothing more is cut).
    let binary_out = clipplane()
        .arg("left")
        .write_stdin(binary_in)
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    assert_eq!(&binary_out[..8], &proto::header::BINARY_MAGIC);
    clipplane()
        .args(["right", "--text"])
        .write_stdin(binary_out)
        .assert()
        .success()
        .stdout(expected);
}

#[test]
fn help_has_an_example() {
    clipplane()
        .arg("--help")
        .assert()
        .success()
        .stdout(predicate::str::contains("Example:"));
}
