//! viewxf as a filter: exact text in and out, headers, refusals and exit codes.

use assert_cmd::Command;
use predicates::prelude::*;
use proto::{Form, Header, Polygon, Space, Token, Writer};

fn viewxf() -> Command {
    Command::new(pipeline_tests::bin("viewxf"))
}

/// docs/DESIGN.md's "The example scene", plus an empty polygon and a second frame.
const SCENE: &str = "polypipe 1 world
colour 255 60 60
-8 -4 0
0 7 0
8 -4 0
NEXT.POLYGON
colour 1 2 3
NEXT.FRAME
colour 60 60 255
-9 5 4
-7 7 4
7 -7 -4
5 -9 -4
END
";

/// With the thesis camera x_e = x_w, y_e = y_w, z_e = 20 − z_w and w = z_e·10/16.
const SCENE_EYE: &str = "polypipe 1 eye aspect 1 hither 1 yon 30
colour 255 60 60
-8 -4 20 12.5
0 7 20 12.5
8 -4 20 12.5
NEXT.POLYGON
colour 1 2 3
NEXT.FRAME
colour 60 60 255
-9 5 16 10
-7 7 16 10
7 -7 24 15
5 -9 24 15
END
";

#[test]
fn thesis_camera_text_to_text() {
    viewxf()
        .arg("--text")
        .write_stdin(SCENE)
        .assert()
        .success()
        .stdout(SCENE_EYE)
        .stderr("");
}

#[test]
fn header_records_size_hither_and_yon() {
    viewxf()
        .args([
            "--text", "--size", "640x480", "--hither", "2", "--yon", "50",
        ])
        .write_stdin("polypipe 1 world\nEND\n")
        .assert()
        .success()
        .stdout("polypipe 1 eye aspect 1.3333333333333333 hither 2 yon 50\nEND\n");
    viewxf()
        .args(["--text", "--aspect", "2"])
        .write_stdin("polypipe 1 world\nEND\n")
        .assert()
        .success()
        .stdout("polypipe 1 eye aspect 2 hither 1 yon 30\nEND\n");
}

#[test]
fn general_camera() {
    // Eye at (10,0,0) looking at the origin, up +y: z_e = 10 − x_w; the x axis is
    // f × up = (−1,0,0)×(0,1,0) = (0,0,−1), so x_e = −z_w; w = z_e·8/16.
    viewxf()
        .args(["--text", "--eye", "10,0,0", "--s", "8", "--d", "16"])
        .write_stdin("polypipe 1 world\ncolour 0 0 0\n0 3 -2\n4 0 1\nEND\n")
        .assert()
        .success()
        .stdout("polypipe 1 eye aspect 1 hither 1 yon 30\ncolour 0 0 0\n2 3 10 5\n-1 0 6 3\nEND\n");
}

#[test]
fn negative_triples_parse() {
    viewxf()
        .args(["--text", "--eye", "0,0,-20", "--up", "0,1,0"])
        .write_stdin("polypipe 1 world\ncolour 0 0 0\n1 2 0\nEND\n")
        .assert()
        .success()
        // Looking along +z from z = −20: x axis = (0,0,1)×(0,1,0) = (−1,0,0).
        .stdout("polypipe 1 eye aspect 1 hither 1 yon 30\ncolour 0 0 0\n-1 2 20 12.5\nEND\n");
}

#[test]
fn invalid_cameras_are_usage_errors() {
    viewxf()
        .args(["--eye", "1,2,3", "--at", "1,2,3"])
        .write_stdin(SCENE)
        .assert()
        .code(2)
        .stdout("")
        .stderr(predicate::str::contains(
            "the eye and the point looked at must differ",
        ));
    viewxf()
        .args(["--up", "0,0,1"])
        .write_stdin(SCENE)
        .assert()
        .code(2)
        .stderr(predicate::str::contains("up vector must not be parallel"));
    viewxf()
        .args(["--hither", "5", "--yon", "2"])
        .write_stdin(SCENE)
        .assert()
        .code(2)
        .stderr("viewxf: --hither 5 --yon 2: they must satisfy 0 < hither < yon\n");
    viewxf()
        .args(["--d", "0"])
        .write_stdin(SCENE)
        .assert()
        .code(2)
        .stderr(predicate::str::contains("must be positive"));
    viewxf()
        .args(["--eye", "1,2"])
        .write_stdin(SCENE)
        .assert()
        .code(2)
        .stderr(predicate::str::contains(
            "expected X,Y,Z (3 numbers), found `1,2`",
        ));
}

#[test]
fn wrong_space_is_refused() {
    viewxf()
        .write_stdin(SCENE_EYE)
        .assert()
        .code(1)
        .stdout("")
        .stderr(
            "viewxf: input is eye-space, expected world-space; \
             this stage takes a scene as the source writes it\n",
        );
}

#[test]
fn bad_text_names_the_position() {
    viewxf()
        .write_stdin("polypipe 1 world\ncolour 1 2 3\n1 2 x\nEND\n")
        .assert()
        .code(1)
        .stderr(predicate::str::starts_with("viewxf: line 3, column 5:"));
}

#[test]
fn help_has_an_example() {
    viewxf()
        .arg("--help")
        .assert()
        .success()
        .stdout(predicate::str::contains("Example:"));
}

fn binary(header: Header, tokens: &[Token]) -> Vec<u8> {
    let mut w = Writer::new(Vec::new(), header, Form::Binary).unwrap();
    for t in tokens {
        w.write(t).unwrap();
    }
    w.into_inner().unwrap()
}

#[test]
fn binary_in_text_out_equals_text_in_text_out() {
    let tokens = [
        Token::Polygon(Polygon::from_xyz(
            [255, 60, 60],
            &[[-8.0, -4.0, 0.0], [0.0, 7.0, 0.0], [8.0, -4.0, 0.0]],
        )),
        Token::Polygon(Polygon::new([1, 2, 3], vec![])),
        Token::NextFrame,
        Token::Polygon(Polygon::from_xyz(
            [60, 60, 255],
            &[
                [-9.0, 5.0, 4.0],
                [-7.0, 7.0, 4.0],
                [7.0, -7.0, -4.0],
                [5.0, -9.0, -4.0],
            ],
        )),
        Token::End,
    ];
    let input = binary(Header::new(Space::World), &tokens);
    viewxf()
        .arg("--text")
        .write_stdin(input.clone())
        .assert()
        .success()
        .stdout(SCENE_EYE);
    // Binary out, read back by a second viewxf as the wrong space, proves it is binary
    // eye-space: the header survives the round trip.
    let out = viewxf()
        .write_stdin(input)
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    assert_eq!(&out[..8], &proto::header::BINARY_MAGIC);
    viewxf()
        .write_stdin(out)
        .assert()
        .code(1)
        .stderr(predicate::str::contains("input is eye-space"));
}

#[test]
fn stream_cut_short_keeps_finished_frames() {
    let out = viewxf()
        .arg("--text")
        .write_stdin("polypipe 1 world\ncolour 1 1 1\n0 0 0\nNEXT.FRAME\ncolour 2 2 2\n")
        .assert()
        .code(1)
        .stderr(predicate::str::contains("ends without END"))
        .get_output()
        .stdout
        .clone();
    assert!(String::from_utf8(out).unwrap().starts_with(
        "polypipe 1 eye aspect 1 hither 1 yon 30\ncolour 1 1 1\n0 0 20 12.5\nNEXT.FRAME\n"
    ));
}

#[test]
fn a_reader_that_goes_away_ends_the_stage_quietly() {
    use std::io::{Read, Write};
    use std::process::{Command as Std, Stdio};
    // Far more output than a pipe holds, of which only a few bytes are read.
    let mut scene = String::from("polypipe 1 world\n");
    for i in 0..50_000 {
        if i > 0 {
            scene += "NEXT.POLYGON\n";
        }
        scene += "colour 1 2 3\n1 2 3\n4 5 6\n7 8 9\n";
    }
    scene += "END\n";
    let mut child = Std::new(pipeline_tests::bin("viewxf"))
        .arg("--text")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let writer = std::thread::spawn(move || {
        let _ = stdin.write_all(scene.as_bytes());
    });
    let mut first = [0u8; 8];
    child.stdout.take().unwrap().read_exact(&mut first).unwrap();
    assert_eq!(&first, b"polypipe");
    // stdout is dropped here: the stage's next write finds no reader.
    let out = child.wait_with_output().unwrap();
    writer.join().unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(String::from_utf8_lossy(&out.stderr), "");
}

/// A text scene long enough to be read in pieces (several times stagecli's 256 KiB):
/// `n` quads, numbers of every length, a frame break every 5,000.
fn long_scene(n: usize) -> String {
    let mut s = String::from("polypipe 1 world\n");
    let mut x: u64 = 0x2545_f491_4f6c_dd1d;
    let mut number = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x % 2_000_000) as f64 / 997.0 - 1000.0
    };
    for i in 0..n {
        if i > 0 {
            s += if i % 5000 == 0 {
                "NEXT.FRAME\n"
            } else {
                "NEXT.POLYGON\n"
            };
        }
        s += &format!("colour {} 2 3\n", i % 256);
        for _ in 0..4 {
            s += &format!("{} {} {}\n", number(), number(), number());
        }
    }
    s + "END\n"
}

/// What viewxf writes, says and exits with, on all the cores or on one (`taskset -c 0`,
/// where it reads the text with one reader).
fn run(scene: &str, one_core: bool) -> (Vec<u8>, String, Option<i32>) {
    let mut cmd = if one_core {
        let mut c = Command::new("taskset");
        c.args(["-c", "0"]).arg(pipeline_tests::bin("viewxf"));
        c
    } else {
        viewxf()
    };
    let out = cmd.write_stdin(scene.as_bytes().to_vec()).output().unwrap();
    let err = String::from_utf8(out.stderr).unwrap();
    (out.stdout, err, out.status.code())
}

/// A long text scene read in pieces on two cores gives the bytes, the message and the
/// status one reader gives: whole, and spoilt at a line far into it in each way a piece
/// can go wrong.
#[test]
fn a_long_text_scene_reads_in_pieces_as_with_one_reader() {
    let good = long_scene(20_000);
    assert!(good.len() > 1 << 20, "{}", good.len());
    let line_start = |k: usize| good.match_indices('\n').nth(k - 2).unwrap().0 + 1;
    let at = line_start(70_001);
    let spoilt = [
        format!("{}1 2 x\n{}", &good[..at], &good[at..]),
        format!("{}NEXT.FRAME\nNEXT.POLYGON\n{}", &good[..at], &good[at..]),
        format!("{}END\n{}", &good[..at], &good[at..]),
        good[..good.len() - 4].to_string(),
        format!("{good}NEXT.POLYGON\n"),
    ];
    let whole = run(&good, false);
    assert_eq!(whole.2, Some(0), "{}", whole.1);
    assert_eq!(whole, run(&good, true));
    for (i, scene) in spoilt.iter().enumerate() {
        let (out, err, code) = run(scene, false);
        assert_eq!(code, Some(1), "{err}");
        assert!(err.starts_with("viewxf: line "), "{err}");
        if i == 0 || i == 3 {
            // What came before the fault is written, as it was in the whole scene.
            assert!(out.len() > whole.0.len() / 2 && whole.0.starts_with(&out));
        }
        assert_eq!((out, err, code), run(scene, true), "spoilt scene {i}");
    }
    // The first spoilt line is named where it is.
    assert_eq!(
        run(&spoilt[0], false).1,
        "viewxf: line 70001, column 5: expected z of vertex 2 (3 numbers a vertex in world \
         space), found `x`\n"
    );
}

/// A live stream (a writer that sends a frame and waits) gets its frame back at once:
/// viewxf does not hold polygons back to make pieces of a stream that comes slower than
/// it reads.
#[test]
fn a_live_stream_gets_each_frame_back_as_it_ends() {
    use std::io::{Read, Write};
    use std::process::{Command as Std, Stdio};
    let frame = "polypipe 1 world\ncolour 1 2 3\n0 0 0\n1 0 0\n0 1 0\nNEXT.FRAME\n";
    // What the frame comes to: the whole stream's output but its END record.
    let whole = viewxf()
        .write_stdin(format!("{frame}END\n"))
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let want = whole[..whole.len() - 8].to_vec();
    let mut child = Std::new(pipeline_tests::bin("viewxf"))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    stdin.write_all(frame.as_bytes()).unwrap();
    stdin.flush().unwrap();
    // Read the frame while stdin stays open; a reader that waited for more would hang,
    // and the test fails after 20 s instead.
    let mut stdout = child.stdout.take().unwrap();
    let n = want.len();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut got = vec![0u8; n];
        let _ = tx.send(stdout.read_exact(&mut got).map(|()| got));
    });
    let got = rx
        .recv_timeout(std::time::Duration::from_secs(20))
        .expect("the first frame, before the stream goes on")
        .unwrap();
    assert_eq!(got, want);
    stdin.write_all(b"END\n").unwrap();
    drop(stdin);
    assert!(child.wait().unwrap().success());
}
