//! persp as a filter: exact device coordinates and depths, refusals and exit codes.

use assert_cmd::Command;
use predicates::prelude::*;
use proto::{DVec4, Form, Header, Polygon, Reader, Space, Token, View, Writer};

fn persp() -> Command {
    Command::new(pipeline_tests::bin("persp"))
}

/// A 2:1 view volume with K1 = 2, K2 = 4, so K2/(K2 − K1) = 2 and depths are exact:
/// z_e = 4 → 1, z_e = 2 → 0, z_e = 3.2 → (1 − 2/3.2)·2 = 0.75.
const EYE: &str = "polypipe 1 eye aspect 2 hither 2 yon 4
colour 10 20 30
-5 2.5 4 2.5
0 0 2 1.25
2.5 -1 3.2 2
NEXT.POLYGON
colour 1 1 1
NEXT.FRAME
colour 40 50 60
5 -2.5 4 2.5
END
";

/// On a 400×200 screen: X = (x_e/(2w) + 1)·200, Y = (1 − y_e/w)·100. The triangle's
/// depth plane is depth = 0.05·X − 0.11·Y + 1 (through (0, 0, 1), (200, 100, 0) and
/// (325, 150, 0.75)), to within rounding of its eye-space plane's transform.
const SCREEN: &str = "polypipe 1 screen 400 200 depth projective 2 4
colour 10 20 30
plane 0.05000000000000011 -0.11000000000000025 -1 1.0000000000000013
0 0 1
200 100 0
325 150 0.75
NEXT.POLYGON
colour 1 1 1
NEXT.FRAME
colour 40 50 60
400 200 1
END
";

#[test]
fn projective_depth_text_to_text() {
    persp()
        .args(["--size", "400x200", "--zmode", "projective", "--text"])
        .write_stdin(EYE)
        .assert()
        .success()
        .stdout(SCREEN)
        .stderr("");
}

#[test]
fn eye_z_depth_passes_z_e() {
    persp()
        .args(["--size", "400x200", "--zmode", "eye-z", "--text"])
        .write_stdin(EYE)
        .assert()
        .success()
        .stdout(
            // No depth plane: z_e is not affine on the screen.
            SCREEN
                .replace("depth projective 2 4", "depth eye-z")
                .replace(
                    "plane 0.05000000000000011 -0.11000000000000025 -1 1.0000000000000013\n",
                    "",
                )
                .replace("0 0 1\n", "0 0 4\n")
                .replace("200 100 0\n", "200 100 2\n")
                .replace("325 150 0.75\n", "325 150 3.2\n")
                .replace("400 200 1\n", "400 200 4\n"),
        );
}

#[test]
fn thesis_scene_at_500x500() {
    // viewxf's output for docs/DESIGN.md's "The example scene" (thesis camera, K1 = 1, K2 = 30).
    persp()
        .args(["--size", "500x500", "--zmode", "projective", "--text"])
        .write_stdin(
            "polypipe 1 eye aspect 1 hither 1 yon 30\ncolour 60 60 255\n-9 5 16 10\n7 -7 24 15\nEND\n",
        )
        .assert()
        .success()
        // (1 − 1/16)·30/29 and (1 − 1/24)·30/29.
        .stdout(
            "polypipe 1 screen 500 500 depth projective 1 30\ncolour 60 60 255\n24.999999999999993 125 0.9698275862068966\n\
             366.6666666666667 366.6666666666667 0.9913793103448277\nEND\n",
        );
    // The default, reciprocal depth: −K1/z_e, −1/16 and −1/24.
    persp()
        .args(["--size", "500x500", "--text"])
        .write_stdin(
            "polypipe 1 eye aspect 1 hither 1 yon 30\ncolour 60 60 255\n-9 5 16 10\n7 -7 24 15\nEND\n",
        )
        .assert()
        .success()
        .stdout(
            "polypipe 1 screen 500 500 depth reciprocal 1\ncolour 60 60 255\n24.999999999999993 125 -0.0625\n\
             366.6666666666667 366.6666666666667 -0.041666666666666664\nEND\n",
        );
}

#[test]
fn aspect_mismatch_is_refused() {
    persp()
        .args(["--size", "640x480"])
        .write_stdin("polypipe 1 eye aspect 1 hither 1 yon 30\nEND\n")
        .assert()
        .code(1)
        .stdout("")
        .stderr(
            "persp: --size 640x480 has aspect 1.333 but the stream was viewed with aspect 1; \
             give viewxf --size 640x480\n",
        );
}

#[test]
fn wrong_space_is_refused() {
    persp()
        .args(["--size", "4x4"])
        .write_stdin("polypipe 1 world\nEND\n")
        .assert()
        .code(1)
        .stdout("")
        .stderr("persp: input is world-space, expected eye-space; put viewxf first\n");
    persp()
        .args(["--size", "4x4"])
        .write_stdin("polypipe 1 screen 4 4\nEND\n")
        .assert()
        .code(1)
        .stderr(predicate::str::contains(
            "input is screen-space, expected eye-space",
        ));
}

#[test]
fn behind_the_eye_names_frame_and_polygon() {
    let out = persp()
        .args(["--size", "400x200", "--zmode", "projective", "--text"])
        .write_stdin(
            "polypipe 1 eye aspect 2 hither 2 yon 4\ncolour 1 1 1\n0 0 2 1.25\nNEXT.FRAME\n\
             colour 2 2 2\nNEXT.POLYGON\ncolour 3 3 3\n0 0 2 1.25\n1 1 -1 -0.625\nEND\n",
        )
        .assert()
        .code(1)
        .stderr(
            "persp: frame 1, polygon 1: vertex 1 (1 1 -1 -0.625) has w = -0.625 ≤ 0, at or \
             behind the eye, and cannot be projected; clip against hither first (clipplane hither)\n",
        )
        .get_output()
        .stdout
        .clone();
    // The frame finished before the fault is written whole.
    assert!(String::from_utf8(out).unwrap().starts_with(
        "polypipe 1 screen 400 200 depth projective 2 4\ncolour 1 1 1\n200 100 0\nNEXT.FRAME\n"
    ));
    // w = 0 exactly is refused too.
    persp()
        .args(["--size", "4x4"])
        .write_stdin("polypipe 1 eye\ncolour 1 1 1\n0 0 0 0\nEND\n")
        .assert()
        .code(1)
        .stderr(predicate::str::contains(
            "frame 0, polygon 0: vertex 0 (0 0 0 0) has w = 0",
        ));
}

#[test]
fn usage_errors() {
    persp()
        .write_stdin(EYE)
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--size <WxH>"));
    persp()
        .args(["--size", "0x5"])
        .write_stdin(EYE)
        .assert()
        .code(2)
        .stderr(predicate::str::contains("not a size from 1 to 65536"));
    persp()
        .args(["--size", "4x2", "--zmode", "linear"])
        .write_stdin(EYE)
        .assert()
        .code(2)
        .stderr(predicate::str::contains("invalid value 'linear'"));
}

fn tokens_of(bytes: &[u8]) -> (Header, Vec<Token>) {
    let mut r = Reader::<Token, _>::new(bytes).unwrap();
    let header = *r.header();
    let mut v = Vec::new();
    while let Some(t) = r.next_record().unwrap() {
        v.push(t);
    }
    (header, v)
}

#[test]
fn binary_in_and_out_match_text() {
    let view = View {
        aspect: 2.0,
        hither: 2.0,
        yon: 4.0,
    };
    let mut w = Writer::new(Vec::new(), Header::new(Space::Eye(view)), Form::Binary).unwrap();
    for t in [
        Token::Polygon(Polygon::new(
            [10, 20, 30],
            vec![
                DVec4::new(-5.0, 2.5, 4.0, 2.5),
                DVec4::new(0.0, 0.0, 2.0, 1.25),
                DVec4::new(2.5, -1.0, 3.2, 2.0),
            ],
        )),
        Token::Polygon(Polygon::new([1, 1, 1], vec![])),
        Token::NextFrame,
        Token::Polygon(Polygon::new(
            [40, 50, 60],
            vec![DVec4::new(5.0, -2.5, 4.0, 2.5)],
        )),
        Token::End,
    ] {
        w.write(&t).unwrap();
    }
    let binary_in = w.into_inner().unwrap();
    // Binary in, text out.
    persp()
        .args(["--size", "400x200", "--zmode", "projective", "--text"])
        .write_stdin(binary_in.clone())
        .assert()
        .success()
        .stdout(SCREEN);
    // Binary in, binary out: the same records as the text output.
    let binary_out = persp()
        .args(["--size", "400x200", "--zmode", "projective"])
        .write_stdin(binary_in)
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    assert_eq!(&binary_out[..8], &proto::header::BINARY_MAGIC);
    assert_eq!(tokens_of(&binary_out), tokens_of(SCREEN.as_bytes()));
}

#[test]
fn help_has_an_example() {
    persp()
        .arg("--help")
        .assert()
        .success()
        .stdout(predicate::str::contains("Example:"));
}

/// The depth form is `--zmode` on every binary that takes one; persp's old `--depth MODE`
/// is still taken for one release, writes the same stream and says, once on stderr, what
/// it is now called. The new spelling says nothing; the two together are refused.
#[test]
fn old_depth_spelling_still_works_with_a_note() {
    persp()
        .args(["--size", "400x200", "--depth", "projective", "--text"])
        .write_stdin(EYE)
        .assert()
        .success()
        .stdout(SCREEN)
        .stderr(
            "persp: --depth MODE is now --zmode MODE; the old spelling goes in the next \
             release\n",
        );
    persp()
        .args(["--size", "400x200", "--zmode", "projective", "--text"])
        .write_stdin(EYE)
        .assert()
        .success()
        .stdout(SCREEN)
        .stderr("");
    persp()
        .args(["--size", "400x200", "--depth", "eye-z", "--zmode", "eye-z"])
        .write_stdin(EYE)
        .assert()
        .code(2)
        .stdout("")
        .stderr("persp: the argument '--depth <MODE>' cannot be used with '--zmode <MODE>'\n");
    // That the help names --zmode and its modes, not the old spelling, is held for every
    // binary that projects by tests/tests/composer/depth_option.rs.
}
