//! clipbatch as a filter: exact vertex lists for cuts by every plane of the pyramid, batch
//! boundaries anywhere, polygon numbering, refusals and exit codes. (That its output is
//! the six-process clipplane chain's, byte for byte, is tested in
//! tests/tests/composer/clipbatch_render.rs, where both sets of binaries are at hand.)

use assert_cmd::Command;
use predicates::prelude::*;
use proto::{DVec4, Form, Header, Polygon, Space, Token, View, Writer};

fn clipbatch() -> Command {
    Command::new(pipeline_tests::bin("clipbatch"))
}

const HEADER: &str = "polypipe 1 eye aspect 1 hither 1 yon 30\n";

/// One frame of five polygons and a second of one, with every number dyadic so that the
/// intersections are exact (w = z_e·10/16 throughout):
/// A crosses hither, B crosses yon, C crosses left and then top (z_e = 16, w = 10: the
/// pyramid is |x_e|, |y_e| ≤ 10 there), D is wholly outside right, E has no vertex, F is
/// inside.
const INPUT: &str = "colour 1 0 0\n0 0 0.5 0.3125\n0 0 1.5 0.9375\n0.5 0 1.5 0.9375\n\
    NEXT.POLYGON\ncolour 2 0 0\n0 0 28 17.5\n0 0 32 20\n4 0 28 17.5\n\
    NEXT.POLYGON\ncolour 3 0 0\n-14 -2 16 10\n2 -2 16 10\n2 14 16 10\n-14 14 16 10\n\
    NEXT.POLYGON\ncolour 4 0 0\n20 0 16 10\n30 0 16 10\n30 5 16 10\n\
    NEXT.POLYGON\ncolour 5 0 0\n\
    NEXT.FRAME\ncolour 6 0 0\n1 1 16 10\n2 1 16 10\n2 2 16 10\nEND\n";

/// The chain's output for [`INPUT`], worked by hand. Each polygon starts where clipplane
/// starts it: with the closing edge's intersection when that edge is cut (A, B's second
/// cut, C's top cut).
const OUTPUT: &str =
    "colour 1 0 0\n0.25 0 1 0.625\n0 0 1 0.625\n0 0 1.5 0.9375\n0.5 0 1.5 0.9375\n\
    NEXT.POLYGON\ncolour 2 0 0\n0 0 28 17.5\n0 0 30 18.75\n2 0 30 18.75\n4 0 28 17.5\n\
    NEXT.POLYGON\ncolour 3 0 0\n-10 10 16 10\n-10 -2 16 10\n2 -2 16 10\n2 10 16 10\n\
    NEXT.POLYGON\ncolour 4 0 0\n\
    NEXT.POLYGON\ncolour 5 0 0\n\
    NEXT.FRAME\ncolour 6 0 0\n1 1 16 10\n2 1 16 10\n2 2 16 10\nEND\n";

#[test]
fn every_plane_cuts_in_one_process_whatever_the_batch() {
    for batch in [None, Some("1"), Some("2"), Some("3"), Some("1048576")] {
        let mut cmd = clipbatch();
        cmd.arg("--text");
        if let Some(n) = batch {
            cmd.args(["--batch", n]);
        }
        cmd.write_stdin(format!("{HEADER}{INPUT}"))
            .assert()
            .success()
            .stdout(format!("{HEADER}{OUTPUT}"))
            .stderr("");
    }
}

#[test]
fn aspect_hither_and_yon_come_from_the_header() {
    // a = 2, K1 = 4, K2 = 7: left is x_e ≥ −2w. The triangle reaches from z_e = 2 to 10;
    // left cuts two edges, hither one (its other end lands on hither, so no second
    // intersection), yon two.
    let header = "polypipe 1 eye aspect 2 hither 4 yon 7\n";
    clipbatch()
        .arg("--text")
        .write_stdin(format!(
            "{header}colour 1 1 1\n0 0 2 1.25\n0 0 10 6.25\n-20 0 10 6.25\nEND\n"
        ))
        .assert()
        .success()
        .stdout(format!(
            "{header}colour 1 1 1\n-8.75 0 7 4.375\n-5 0 4 2.5\n0 0 4 2.5\n0 0 7 4.375\nEND\n"
        ));
}

#[test]
fn annotations_pass_through_and_supports_go_where_a_plane_cuts() {
    // The first polygon is inside: its plane and its edge support stay. The second is
    // cut by right: its supports go, its plane stays.
    let input = format!(
        "{HEADER}colour 1 1 1\nplane 0 0 1 -16\n1 1 16 10 on -4 1 16 10 4 1 16 10\n2 1 16 10\n2 2 16 10\n\
         NEXT.POLYGON\ncolour 2 2 2\nplane 0 0 1 -16\n2 1 16 10 on -4 1 16 10 4 1 16 10\n18 1 16 10\n2 2 16 10\nEND\n"
    );
    clipbatch()
        .arg("--text")
        .write_stdin(input)
        .assert()
        .success()
        .stdout(format!(
            "{HEADER}colour 1 1 1\nplane 0 0 1 -16\n1 1 16 10 on -4 1 16 10 4 1 16 10\n2 1 16 10\n2 2 16 10\n\
             NEXT.POLYGON\ncolour 2 2 2\nplane 0 0 1 -16\n2 1 16 10\n10 1 16 10\n10 1.5 16 10\n2 2 16 10\nEND\n"
        ));
}

#[test]
fn binary_in_text_out_equals_text_in_text_out() {
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
                DVec4::new(2.0, 0.0, 16.0, 10.0),
                DVec4::new(-22.0, 8.0, 16.0, 10.0),
                DVec4::new(2.0, 8.0, 16.0, 10.0),
            ],
        )),
        Token::NextFrame,
        Token::Polygon(Polygon::new([1, 2, 3], vec![])),
        Token::End,
    ] {
        w.write(&t).unwrap();
    }
    let expected = format!(
        "{HEADER}colour 9 9 9\n2 0 16 10\n-10 4 16 10\n-10 8 16 10\n2 8 16 10\nNEXT.FRAME\ncolour 1 2 3\nEND\n"
    );
    let binary_in = w.into_inner().unwrap();
    clipbatch()
        .arg("--text")
        .write_stdin(binary_in.clone())
        .assert()
        .success()
        .stdout(expected.clone());
    // Binary out, read back as text by a second run (nothing more to cut).
    let binary_out = clipbatch()
        .write_stdin(binary_in)
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    assert_eq!(&binary_out[..8], &proto::header::BINARY_MAGIC);
    clipbatch()
        .arg("--text")
        .write_stdin(binary_out)
        .assert()
        .success()
        .stdout(expected);
}

#[test]
fn bad_input_ends_the_run_after_the_polygons_before_it() {
    // The second polygon's vertex has three numbers: the first polygon, still waiting in
    // the batch, is written clipped before the message, as the chain's first stage
    // would have written it.
    clipbatch()
        .arg("--text")
        .write_stdin(format!(
            "{HEADER}colour 1 1 1\n0 0 16 10\n-20 0 16 10\n0 4 16 10\nNEXT.POLYGON\ncolour 2 2 2\n0 0 16\nEND\n"
        ))
        .assert()
        .code(1)
        .stdout(format!(
            "{HEADER}colour 1 1 1\n0 0 16 10\n-10 0 16 10\n-10 2 16 10\n0 4 16 10\n"
        ))
        .stderr(predicate::str::starts_with("clipbatch: line 9, column 1:"));
}

#[test]
fn wrong_space_is_refused() {
    clipbatch()
        .write_stdin("polypipe 1 world\nEND\n")
        .assert()
        .code(1)
        .stdout("")
        .stderr("clipbatch: input is world-space, expected eye-space; put viewxf first\n");
}

#[test]
fn usage_errors() {
    for (args, msg) in [
        (vec!["--batch", "0"], "--batch"),
        (vec!["--batch", "many"], "--batch"),
        (vec!["left"], "unexpected argument"),
    ] {
        clipbatch()
            .args(&args)
            .write_stdin(format!("{HEADER}END\n"))
            .assert()
            .code(2)
            .stdout("")
            .stderr(predicate::str::contains(msg));
    }
}

#[test]
fn help_has_an_example() {
    clipbatch()
        .arg("--help")
        .assert()
        .success()
        .stdout(predicate::str::contains("Example:"));
}
