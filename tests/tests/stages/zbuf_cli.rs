//! zbuf as a filter and as PAR.BUFF: exact PPM bytes for exact fragment streams.

use assert_cmd::Command;
use proto::{Form, Fragment, Header, Reader, Space, SpaceKind, Token, Writer};
use scan::SpanWalker;
use std::path::{Path, PathBuf};

/// What `scanconv` writes for a screen-space text stream (binary form), made with the
/// `scan` library it is a thin user of (a stage crate's tests use no other stage).
fn scanconv(screen: &str) -> Vec<u8> {
    let mut input = Reader::<Token, _>::new(screen.as_bytes()).unwrap();
    input.header().expect(SpaceKind::Screen).unwrap();
    let (w, h) = input.header().space.screen_size().unwrap();
    let header = Header::new(Space::Fragments {
        width: w,
        height: h,
    });
    let mut out = Writer::<Fragment, _>::new(Vec::new(), header, Form::Binary).unwrap();
    // The scan conversion scanconv does (the shared `scan` library): a colour record,
    // then the polygon's spans with their depths.
    let mut walker = SpanWalker::new();
    while let Some(t) = input.next_record().unwrap() {
        match t {
            Token::Polygon(p) => {
                out.write(&Fragment::Polygon(p.colour)).unwrap();
                walker
                    .spans(&p, w, h, |s| {
                        out.write(&Fragment::Span {
                            y: s.y,
                            x0: s.x0,
                            x1: s.x1,
                            z: s.z_row,
                            dz: s.dz,
                        })
                    })
                    .unwrap();
            }
            Token::Skip(n) => out.write(&Fragment::Skip(n)).unwrap(),
            Token::NextFrame => out.write(&Fragment::NextFrame).unwrap(),
            Token::End => out.write(&Fragment::End).unwrap(),
        }
    }
    out.into_inner().unwrap()
}

fn zbuf() -> Command {
    Command::new(pipeline_tests::bin("zbuf"))
}

const R: [u8; 3] = [255, 0, 0];
const G: [u8; 3] = [0, 255, 0];
const B: [u8; 3] = [0, 0, 255];
const K: [u8; 3] = [0, 0, 0];

/// A P6 image from rows of pixels.
fn ppm(w: usize, h: usize, pixels: &[[u8; 3]]) -> Vec<u8> {
    assert_eq!(pixels.len(), w * h);
    let mut v = format!("P6\n{w} {h}\n255\n").into_bytes();
    v.extend(pixels.iter().flatten());
    v
}

fn write(dir: &Path, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

/// A red square at depth 0.5 behind (above row 1.5) and in front of (below) a blue
/// triangle whose depth is 0.25 + Y/8.
const OVERLAP: &str = "polypipe 1 screen 4 4
colour 255 0 0
1 1 0.5
3 1 0.5
3 3 0.5
1 3 0.5
NEXT.POLYGON
colour 0 0 255
0 0 0.25
4 0 0.25
0 4 0.75
END
";

#[test]
fn nearer_polygon_wins() {
    zbuf()
        .write_stdin(scanconv(OVERLAP))
        .assert()
        .success()
        .stdout(ppm(
            4,
            4,
            &[
                B, B, B, K, //
                B, B, R, K, // row 1: triangle depth 0.4375 < 0.5
                B, R, R, K, // row 2: 0.5625 > 0.5, the square shows
                K, K, K, K,
            ],
        ));
}

#[test]
fn text_fragments_background_and_stats() {
    let text = "polypipe 2 fragments 3 1
colour 0 255 0
span 0 1 3 5 0
NEXT.POLYGON
colour 255 0 0
pixel 2 0 4
END
";
    zbuf()
        .args(["--background", "1,2,3", "--stats", "-"])
        .write_stdin(text)
        .assert()
        .success()
        .stdout(ppm(3, 1, &[[1, 2, 3], G, R]))
        .stderr(format!(
            "zbuf: stdin: 1 spans, 3 pixels, {0} bytes in\n\
             @stats zbuf input=stdin spans=1 runs=0 pixels=3 bytes_in={0}\n",
            text.len()
        ));
}

/// Polygon 0 (red) and polygon 1 (blue) at the same depth over the same pixels, their
/// pixels sent through different inputs: the earlier polygon wins, whatever the order.
#[test]
fn equal_depth_goes_to_the_earlier_polygon_across_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let a = write(
        dir.path(),
        "a.frag",
        "polypipe 2 fragments 2 1\ncolour 255 0 0\nspan 0 0 2 7 0\nNEXT.POLYGON\ncolour 0 0 255\nEND\n",
    );
    let b = write(
        dir.path(),
        "b.frag",
        "polypipe 2 fragments 2 1\ncolour 255 0 0\nNEXT.POLYGON\ncolour 0 0 255\nspan 0 0 2 7 0\nEND\n",
    );
    for args in [[&a, &b], [&b, &a]] {
        zbuf()
            .args(args)
            .assert()
            .success()
            .stdout(ppm(2, 1, &[R, R]));
    }
    // And within one input, blue later in the stream loses the tie too.
    zbuf()
        .write_stdin("polypipe 2 fragments 2 1\ncolour 255 0 0\nspan 0 0 2 7 0\nNEXT.POLYGON\ncolour 0 0 255\nspan 0 0 2 7 0\nspan 0 1 2 6 0\nEND\n")
        .assert()
        .success()
        .stdout(ppm(2, 1, &[R, B]));
}

const TWO_FRAMES: &str = "polypipe 2 fragments 2 2
colour 255 0 0
span 0 0 2 0 0
NEXT.FRAME
colour 0 255 0
pixel 1 1 0
END
";

#[test]
fn frames_are_concatenated() {
    let mut want = ppm(2, 2, &[R, R, K, K]);
    want.extend(ppm(2, 2, &[K, K, K, G]));
    zbuf()
        .write_stdin(TWO_FRAMES)
        .assert()
        .success()
        .stdout(want);
    // An empty last frame is a frame: the grammar is frame { NEXT.FRAME frame } END.
    zbuf()
        .write_stdin("polypipe 2 fragments 1 1\nNEXT.FRAME\nEND\n")
        .assert()
        .success()
        .stdout([ppm(1, 1, &[K]), ppm(1, 1, &[K])].concat());
}

#[test]
fn one_file_per_frame() {
    let dir = tempfile::tempdir().unwrap();
    let pattern = dir.path().join("out%03d.png");
    zbuf()
        .arg("-o")
        .arg(&pattern)
        .args(["--background", "9,9,9"])
        .write_stdin(TWO_FRAMES)
        .assert()
        .success()
        .stdout("");
    let read = |name: &str| {
        let img = image::open(dir.path().join(name)).unwrap().to_rgb8();
        assert_eq!(img.dimensions(), (2, 2));
        img.pixels().map(|p| p.0).collect::<Vec<_>>()
    };
    assert_eq!(read("out000.png"), vec![R, R, [9, 9, 9], [9, 9, 9]]);
    assert_eq!(read("out001.png"), vec![[9, 9, 9], [9, 9, 9], [9, 9, 9], G]);
    assert!(!dir.path().join("out002.png").exists());

    // PPM files are the bytes stdout would have had.
    zbuf()
        .arg("-o")
        .arg(dir.path().join("f%d.ppm"))
        .write_stdin(TWO_FRAMES)
        .assert()
        .success();
    assert_eq!(
        std::fs::read(dir.path().join("f1.ppm")).unwrap(),
        ppm(2, 2, &[K, K, K, G])
    );

    // No frame number in the name: the second frame is refused, the first taken back.
    let still = dir.path().join("still.png");
    zbuf()
        .arg("-o")
        .arg(&still)
        .write_stdin(TWO_FRAMES)
        .assert()
        .code(1)
        .stderr(format!(
            "zbuf: -o {s}: the input is a movie (a second frame came), and {s} names one \
             picture: give a pattern with %d for the frame number (as frame%03d.png); \
             nothing was kept\n",
            s = still.display()
        ));
    assert!(!still.exists());
    zbuf()
        .args(["-o", "x%d.jpg"])
        .write_stdin(TWO_FRAMES)
        .assert()
        .code(2)
        .stderr("zbuf: -o x%d.jpg: the file name must end .png or .ppm\n");
}

#[test]
fn first_frame_numbers_the_files_from_n() {
    // A chunk of a movie rendered alone writes the files of the whole movie's run.
    let dir = tempfile::tempdir().unwrap();
    zbuf()
        .arg("-o")
        .arg(dir.path().join("f%03d.ppm"))
        .args(["--first-frame", "40"])
        .write_stdin(TWO_FRAMES)
        .assert()
        .success()
        .stdout("");
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["f040.ppm", "f041.ppm"]);
    assert_eq!(
        std::fs::read(dir.path().join("f041.ppm")).unwrap(),
        ppm(2, 2, &[K, K, K, G])
    );
    // It numbers files: without -o there are none to number.
    zbuf()
        .args(["--first-frame", "3"])
        .write_stdin(TWO_FRAMES)
        .assert()
        .code(2);
}

#[test]
fn two_inputs_as_files() {
    // The overlap scene cut in two by the splitter's rule, by hand: the square goes to
    // input a, the triangle to input b, each keeping the other's polygon record.
    let dir = tempfile::tempdir().unwrap();
    let a = write(
        dir.path(),
        "a.frag",
        scanconv(&OVERLAP.replace("0 0 0.25\n4 0 0.25\n0 4 0.75\n", "")),
    );
    let b = write(
        dir.path(),
        "b.frag",
        scanconv(&OVERLAP.replace("1 1 0.5\n3 1 0.5\n3 3 0.5\n1 3 0.5\n", "")),
    );
    let whole = zbuf()
        .write_stdin(scanconv(OVERLAP))
        .output()
        .unwrap()
        .stdout;
    assert_eq!(whole.len(), 11 + 48);
    for args in [[&a, &b], [&b, &a]] {
        zbuf()
            .args(args)
            .arg("--stats")
            .assert()
            .success()
            .stdout(whole.clone());
    }
    zbuf()
        .args([&a, &b])
        .arg("--stats")
        .assert()
        .stderr(format!(
            "zbuf: {0}: 2 spans, 4 pixels, {1} bytes in\n\
             @stats zbuf input={0} spans=2 runs=0 pixels=4 bytes_in={1}\n\
             zbuf: {2}: 3 spans, 6 pixels, {3} bytes in\n\
             @stats zbuf input={2} spans=3 runs=0 pixels=6 bytes_in={3}\n",
            a.display(),
            std::fs::metadata(&a).unwrap().len(),
            b.display(),
            std::fs::metadata(&b).unwrap().len(),
        ));
}

#[test]
fn mismatched_sizes_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let a = write(dir.path(), "a", "polypipe 2 fragments 4 4\nEND\n");
    let b = write(dir.path(), "b", "polypipe 2 fragments 8 8\nEND\n");
    let out = zbuf().args([&a, &b]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty());
    // Whichever header arrives first sets the size; the message names both.
    let stderr = String::from_utf8(out.stderr).unwrap();
    let (a, b) = (a.display(), b.display());
    assert!(
        stderr == format!("zbuf: {b}: header: screen 8x8, but {a} is 4x4 (all inputs must have the same screen size)\n")
            || stderr == format!("zbuf: {a}: header: screen 4x4, but {b} is 8x8 (all inputs must have the same screen size)\n"),
        "{stderr}"
    );
}

#[test]
fn mismatched_frame_counts_are_refused_after_the_common_frames() {
    let dir = tempfile::tempdir().unwrap();
    let a = write(
        dir.path(),
        "a",
        "polypipe 2 fragments 1 1\nNEXT.FRAME\nEND\n",
    );
    let b = write(dir.path(), "b", "polypipe 2 fragments 1 1\nEND\n");
    zbuf()
        .args([&a, &b])
        .assert()
        .code(1)
        .stdout(ppm(1, 1, &[K]))
        .stderr(format!(
            "zbuf: {}: frame 0: END here, but {} goes on to frame 1 (all inputs must have the same number of frames)\n",
            b.display(),
            a.display()
        ));
}

#[test]
fn a_bad_input_is_named_and_earlier_frames_are_written() {
    let dir = tempfile::tempdir().unwrap();
    let good = write(dir.path(), "good", TWO_FRAMES);
    let bad = write(
        dir.path(),
        "bad",
        "polypipe 2 fragments 2 2\ncolour 0 0 255\npixel 0 1 0\nNEXT.FRAME\ncolour 0 0 255\npixel 5 0 0\nEND\n",
    );
    zbuf()
        .args([&good, &bad])
        .assert()
        .code(1)
        .stdout(ppm(2, 2, &[R, R, B, K]))
        .stderr(format!(
            "zbuf: {}: line 6, column 11: pixel (5, 0) is outside the 2x2 screen\n",
            bad.display()
        ));
    // The binary form: the message gives the byte offset.
    let mut bytes = scanconv("polypipe 1 screen 2 2\ncolour 1 1 1\n0 0 0\n2 0 0\n2 2 0\nNEXT.FRAME\ncolour 1 1 1\n0 0 0\n2 0 0\n2 2 0\nEND\n");
    let len = bytes.len();
    bytes.truncate(len - 10);
    let cut = write(dir.path(), "cut", &bytes);
    let out = zbuf().arg(&cut).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(out.stdout, ppm(2, 2, &[[1, 1, 1], [1, 1, 1], K, [1, 1, 1]]));
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(
        stderr.starts_with(&format!("zbuf: {}: byte ", cut.display()))
            && stderr.ends_with("the stream ends in the middle of a record (cut short?)\n"),
        "{stderr}"
    );
    // Pixels before any colour record.
    zbuf()
        .write_stdin("polypipe 2 fragments 2 2\nspan 0 0 1 0 0\nEND\n")
        .assert()
        .code(1)
        .stderr("zbuf: stdin: line 2, column 1: pixels before the frame's first `colour`\n");
    zbuf()
        .arg(dir.path().join("missing"))
        .assert()
        .code(3)
        .stderr(format!(
            "zbuf: {}: No such file or directory\n",
            dir.path().join("missing").display()
        ));
    zbuf()
        .write_stdin("polypipe 1 eye 1 2 3 1\nEND\n")
        .assert()
        .code(1)
        .stderr(
            "zbuf: stdin: input is eye-space, expected fragments (scanconv's) or screen-space \
             polygons (persp's); put persp first\n",
        );
}

/// A screen-space input (persp's output) is scan-converted and resolved in zbuf: the
/// frame `scanconv | zbuf` makes, with the leaf's counts under --stats.
#[test]
fn a_screen_space_input_is_resolved_here() {
    let picture = ppm(
        4,
        4,
        &[
            B, B, B, K, //
            B, B, R, K, //
            B, R, R, K, //
            K, K, K, K,
        ],
    );
    zbuf()
        .write_stdin(scanconv(OVERLAP))
        .assert()
        .success()
        .stdout(picture.clone());
    // Square: 4 pixels; triangle: 6, all written (it is the nearer where the two meet,
    // row 1, column 1).
    zbuf()
        .arg("--stats")
        .write_stdin(OVERLAP)
        .assert()
        .success()
        .stdout(picture)
        .stderr(
            "zbuf: stdin: 2 polygons in, 10 pixels tested, 10 written\n\
             @stats zbuf input=stdin polygons_in=2 pixels_tested=10 pixels_written=10 runs=0 \
             rounding_decided=0\n",
        );
}

/// An eye-space stream of two frames: two overlapping polygons at different depths, then
/// one.
const EYE: &str = "polypipe 1 eye aspect 1 hither 1 yon 30\n\
                   colour 255 0 0\n-2 -2 10 10\n2 -2 10 10\n0 2 10 10\nNEXT.POLYGON\n\
                   colour 0 0 255\n-3 -1 12 12\n3 -1 14 14\n3 1 14 14\n-3 1 12 12\n\
                   NEXT.FRAME\ncolour 0 255 0\n-1 -1 5 5\n1 -1 5 5\n0 1 5 5\nEND\n";

/// The frames zbuf makes of what `persp --size 8x8 --zmode MODE` writes for `eye`, the
/// projection made with the code persp uses (proto's `Perspective`); and that screen-space
/// stream.
fn projected(eye: &str, mode: proto::perspective::DepthMode) -> (Vec<u8>, Vec<u8>) {
    use proto::perspective::Perspective;
    let mut input = Reader::<Token, _>::new(eye.as_bytes()).unwrap();
    let Space::Eye(view) = input.header().space else {
        panic!("eye")
    };
    let perspective = Perspective::new(8, 8, view, mode).unwrap();
    let mut screen = Writer::<Token, _>::new(
        Vec::new(),
        perspective.screen_header(input.header()),
        Form::Binary,
    )
    .unwrap();
    while let Some(mut t) = input.next_record().unwrap() {
        if let Token::Polygon(p) = &mut t {
            perspective.project_polygon(p).unwrap();
        }
        screen.write(&t).unwrap();
    }
    let screen = screen.into_inner().unwrap();
    let frames = zbuf()
        .write_stdin(screen.clone())
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    assert_eq!(frames.len(), 2 * (11 + 8 * 8 * 3), "two 8x8 frames");
    (frames, screen)
}

/// `--project --size WxH [--zmode MODE]`: an eye-space input (the clipper's output) is
/// projected here as persp projects it and resolved: the frame zbuf makes of the projected
/// stream, for each depth form (reciprocal by default), alone or beside another input; a
/// polygon persp would refuse is refused, named by its place; --project and --size go
/// together, and --zmode is for --project.
#[test]
fn an_eye_space_input_is_projected_with_persp() {
    use proto::perspective::DepthMode;
    let (want, screen) = projected(EYE, DepthMode::Reciprocal);
    zbuf()
        .args(["--project", "--size", "8x8"])
        .write_stdin(EYE)
        .assert()
        .success()
        .stdout(want.clone())
        .stderr("");
    for (mode, depth) in [
        ("reciprocal", DepthMode::Reciprocal),
        ("projective", DepthMode::Projective),
        ("eye-z", DepthMode::EyeZ),
    ] {
        zbuf()
            .args(["--project", "--zmode", mode, "--size", "8x8"])
            .write_stdin(EYE)
            .assert()
            .success()
            .stdout(projected(EYE, depth).0)
            .stderr("");
    }
    // Beside another input (threads and the merger's buffer): the projected stream twice.
    let dir = tempfile::tempdir().unwrap();
    let screen_file = write(dir.path(), "screen", &screen);
    zbuf()
        .args(["--project", "--size", "8x8", "-"])
        .arg(&screen_file)
        .write_stdin(EYE)
        .assert()
        .success()
        .stdout(want);
    // A vertex persp cannot project (w lost: in front by z_e, yet w = 0).
    let bad =
        "polypipe 1 eye aspect 1 hither 1 yon 30\ncolour 1 2 3\n0 0 5 5\n1 0 5 5\n0 1 5 0\nEND\n";
    let out = zbuf()
        .args(["--project", "--size", "8x8"])
        .write_stdin(bad)
        .assert()
        .code(1)
        .get_output()
        .stderr
        .clone();
    let err = String::from_utf8(out).unwrap();
    assert!(
        err.starts_with("zbuf: stdin: frame 0, polygon 0: vertex 2 (0 1 5 0) has w = 0")
            && err.lines().count() == 1,
        "{err}"
    );
    for (args, message) in [
        (
            &["--project"][..],
            "zbuf: the following required arguments were not provided: --size <WxH>\n",
        ),
        (&["--size", "8x8"], "zbuf: --size is for --project\n"),
        (
            &["--zmode", "eye-z", "--size", "8x8"],
            "zbuf: --zmode eye-z is for --project (the depth its projection writes)\n",
        ),
    ] {
        zbuf()
            .args(args)
            .write_stdin(EYE)
            .assert()
            .code(2)
            .stdout("")
            .stderr(message);
    }
}

/// `--persp MODE`, the old spelling of `--project --zmode MODE`, is still taken for one
/// release: the same frames, and a note on stderr saying what it is now called; beside
/// the new spelling it is refused.
#[test]
fn old_persp_spelling_still_works_with_a_note() {
    use proto::perspective::DepthMode;
    zbuf()
        .args(["--persp", "projective", "--size", "8x8"])
        .write_stdin(EYE)
        .assert()
        .success()
        .stdout(projected(EYE, DepthMode::Projective).0)
        .stderr(
            "zbuf: --persp MODE is now --project --zmode MODE; the old spelling goes in the \
             next release\n",
        );
    zbuf()
        .args(["--persp", "eye-z", "--project", "--size", "8x8"])
        .write_stdin(EYE)
        .assert()
        .code(2)
        .stdout("")
        .stderr("zbuf: the argument '--persp <MODE>' cannot be used with '--project'\n");
    zbuf()
        .args(["--persp", "reciprocal"])
        .write_stdin(EYE)
        .assert()
        .code(2)
        .stdout("")
        .stderr("zbuf: the following required arguments were not provided: --size <WxH>\n");
    // That the help tells of --project and --zmode, not of the old spelling, is held for
    // every binary that projects by tests/tests/composer/depth_option.rs.
}

/// Two screen-space inputs, a frame each of two, over disjoint halves of the screen (two
/// leaves of a splitter tree): each is resolved on its own and the frames assembled.
#[test]
fn screen_space_inputs_are_leaves_and_frames_stay_apart() {
    let dir = tempfile::tempdir().unwrap();
    let left = write(
        dir.path(),
        "left",
        "polypipe 1 screen 4 1\ncolour 255 0 0\n0 0 0.5\n2 0 0.5\n2 1 0.5\n0 1 0.5\n\
         NEXT.FRAME\ncolour 0 255 0\n0 0 0.5\n1 0 0.5\n1 1 0.5\n0 1 0.5\nEND\n",
    );
    let right = write(
        dir.path(),
        "right",
        "polypipe 1 screen 4 1\ncolour 0 0 255\n3 0 0.5\n4 0 0.5\n4 1 0.5\n3 1 0.5\n\
         NEXT.FRAME\nskip 1\nNEXT.POLYGON\ncolour 255 0 0\n2 0 0.5\n4 0 0.5\n4 1 0.5\n2 1 0.5\nEND\n",
    );
    let mut frames = ppm(4, 1, &[R, R, K, B]);
    frames.extend(ppm(4, 1, &[G, K, R, R]));
    zbuf()
        .args([&left, &right])
        .assert()
        .success()
        .stdout(frames);
}

/// A screen-space polygon off the guard band is refused as scanconv refuses it, the
/// input and the polygon named, the frames before it written.
#[test]
fn a_bad_screen_space_input_is_named() {
    zbuf()
        .write_stdin(
            "polypipe 1 screen 2 1\ncolour 1 2 3\n0 0 0\n2 0 0\n2 1 0\n0 1 0\nNEXT.FRAME\n\
             colour 1 2 3\n0 0 0\n1e12 0 0\n2 1 0\nEND\n",
        )
        .assert()
        .code(1)
        .stdout(ppm(2, 1, &[[1, 2, 3], [1, 2, 3]]))
        .stderr(predicates::str::starts_with(
            "zbuf: stdin: frame 1, polygon 0: ",
        ));
}

/// A big uneven frame through two named pipes written at once: input a has one pixel a
/// frame, input b far more than a pipe holds. zbuf must neither deadlock nor mix frames.
#[test]
fn named_pipes_with_uneven_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let (pa, pb) = (dir.path().join("a"), dir.path().join("b"));
    for p in [&pa, &pb] {
        let status = std::process::Command::new("mkfifo")
            .arg(p)
            .status()
            .unwrap();
        assert!(status.success());
    }
    let frames = 3;
    let (w, h) = (96u32, 96u32);
    let mut a = format!("polypipe 2 fragments {w} {h}\n");
    let mut b = a.clone();
    let mut want = Vec::new();
    for f in 0..frames {
        if f > 0 {
            a += "NEXT.FRAME\n";
            b += "NEXT.FRAME\n";
        }
        // Polygon 0 (in a): one pixel at depth 0 in column f. Polygon 1 (in b): the
        // whole screen at depth 1, one span a pixel so the stream is large.
        a += &format!("colour 255 0 0\npixel {f} 0 0\nNEXT.POLYGON\ncolour 0 0 255\n");
        b += "colour 255 0 0\nNEXT.POLYGON\ncolour 0 0 255\n";
        for y in 0..h {
            for x in 0..w {
                b += &format!("span {y} {x} {} 1 0\n", x + 1);
            }
        }
        let mut pixels = vec![B; (w * h) as usize];
        pixels[f as usize] = R;
        want.extend(ppm(w as usize, h as usize, &pixels));
    }
    a += "END\n";
    b += "END\n";
    assert!(b.len() > 4 * 65536);
    let writer = |path: PathBuf, text: String| {
        std::thread::spawn(move || std::fs::write(path, text).unwrap())
    };
    let (ta, tb) = (writer(pa.clone(), a), writer(pb.clone(), b));
    // A deadlock would hang here; the timeout turns it into a failure.
    zbuf()
        .args([&pa, &pb])
        .timeout(std::time::Duration::from_secs(120))
        .assert()
        .success()
        .stdout(want);
    ta.join().unwrap();
    tb.join().unwrap();
}

#[test]
fn closed_stdout_ends_quietly() {
    let mut text = String::from("polypipe 2 fragments 64 64\n");
    for _ in 0..200 {
        text += "NEXT.FRAME\n";
    }
    text += "END\n";
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "in", text);
    let zbuf = pipeline_tests::bin("zbuf");
    let out = std::process::Command::new("bash")
        .arg("-c")
        .arg(format!(
            "'{}' '{}' | head -c 10 > /dev/null; echo ${{PIPESTATUS[0]}}",
            zbuf.display(),
            input.display()
        ))
        .output()
        .unwrap();
    assert_eq!(String::from_utf8(out.stdout).unwrap(), "0\n");
    assert_eq!(String::from_utf8(out.stderr).unwrap(), "");
}

/// `--progress` off a terminal: stderr redirected to a file gets nothing, and the frames
/// are the same bytes as without it.
#[test]
fn progress_is_silent_when_stderr_is_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "two.frag", TWO_FRAMES);
    let err_path = dir.path().join("stderr.txt");
    let out = std::process::Command::new(pipeline_tests::bin("zbuf"))
        .arg("--progress")
        .arg(&input)
        .stderr(std::fs::File::create(&err_path).unwrap())
        .output()
        .unwrap();
    assert!(out.status.success());
    assert_eq!(std::fs::read(&err_path).unwrap(), b"");
    let mut want = ppm(2, 2, &[R, R, K, K]);
    want.extend(ppm(2, 2, &[K, K, K, G]));
    assert_eq!(out.stdout, want);
    // A pipe is not a terminal either; errors still come through.
    zbuf()
        .arg("--progress")
        .write_stdin(TWO_FRAMES)
        .assert()
        .success()
        .stderr("")
        .stdout(want);
    zbuf()
        .arg("--progress")
        .write_stdin("polypipe 2 fragments 1 1\nbogus\n")
        .assert()
        .code(1)
        .stderr(predicates::str::starts_with("zbuf: stdin: line 2"));
}

/// `--progress` on a terminal (a pseudo-terminal made by util-linux `script`, when it is
/// installed): the final count of frames is shown, and stdout is unchanged.
#[test]
fn progress_counts_frames_on_a_terminal() {
    let has_script = std::process::Command::new("script")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !has_script {
        pipeline_tests::skip("util-linux `script` not installed");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "two.frag", TWO_FRAMES);
    let ppm_path = dir.path().join("out.ppm");
    let cmd = format!(
        "'{}' --progress < '{}' > '{}'",
        pipeline_tests::bin("zbuf").display(),
        input.display(),
        ppm_path.display()
    );
    let out = std::process::Command::new("script")
        .args(["-q", "-e", "-c", &cmd, "/dev/null"])
        .stdin(std::process::Stdio::null())
        .env("TERM", "xterm")
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let screen = String::from_utf8_lossy(&out.stdout);
    assert!(screen.contains("zbuf: 2 frames, "), "{screen:?}");
    assert!(screen.contains(" frames/s"), "{screen:?}");
    let mut want = ppm(2, 2, &[R, R, K, K]);
    want.extend(ppm(2, 2, &[K, K, K, G]));
    assert_eq!(std::fs::read(&ppm_path).unwrap(), want);
}

/// A `skip N` keeps polygon numbering: on one input a skip of 2 then blue, on the other
/// red as the first polygon, both at one depth on pixel (0, 0): red is polygon 0, blue
/// polygon 2, so red wins the tie whichever input arrives first.
#[test]
fn skip_keeps_numbering_for_ties() {
    let dir = tempfile::tempdir().unwrap();
    let a = write(
        dir.path(),
        "a",
        "polypipe 2 fragments 2 1\nskip 2\nNEXT.POLYGON\ncolour 0 0 255\nspan 0 0 2 7 0\nEND\n",
    );
    let b = write(
        dir.path(),
        "b",
        "polypipe 2 fragments 2 1\ncolour 255 0 0\npixel 0 0 7\nNEXT.POLYGON\nskip 2\nEND\n",
    );
    for order in [[&a, &b], [&b, &a]] {
        zbuf()
            .args(order)
            .assert()
            .success()
            .stdout(ppm(2, 1, &[R, B]));
    }
    // Spans after a skip belong to no polygon: refused.
    zbuf()
        .write_stdin(
            "polypipe 2 fragments 2 1\ncolour 1 1 1\nNEXT.POLYGON\nskip 1\nspan 0 0 1 0 0\nEND\n",
        )
        .assert()
        .code(1)
        .stderr(predicates::str::contains("pixels outside a polygon"));
}

/// Finished runs from leaves that resolved their own regions are placed as they come,
/// with no depth test; the background shows where no run fell.
#[test]
fn runs_are_placed_without_a_depth_test() {
    let dir = tempfile::tempdir().unwrap();
    let left = write(
        dir.path(),
        "l",
        "polypipe 2 fragments 3 2\nrun 0 0 2 255 0 0\nrun 1 0 1 0 255 0\nEND\n",
    );
    let right = write(
        dir.path(),
        "r",
        "polypipe 2 fragments 3 2\nrun 1 2 3 0 0 255\nEND\n",
    );
    zbuf()
        .args([&left, &right])
        .assert()
        .success()
        .stdout(ppm(3, 2, &[R, R, K, G, K, B]));
    let out = zbuf().arg("--stats").args([&left]).output().unwrap();
    assert!(out.status.success());
    let said = String::from_utf8_lossy(&out.stderr);
    let record = pipeline_tests::stat_record(&said, "runs");
    let counts = ["spans", "runs", "pixels"].map(|k| record.count(k));
    assert_eq!(counts, [Some(0), Some(2), Some(3)], "{said}");
}

/// `zbuf --project --aa MODE`, what render runs for `--aa MODE` at depth 0, is the
/// anti-aliasing leaf piped to zbuf byte for byte, and says what the leaf said: on
/// generated scenes (random environments of two frames at three seeds, where the second
/// frame is painted over the first's pixels; a shaded sphere; the Gouraud, Phong and
/// transparent examples), every mode, on screens of two shapes.
#[test]
fn zbuf_aa_is_the_anti_aliasing_leaf_piped_to_zbuf() {
    let leaf = |mode: &str| match mode {
        "abuf" => "abuf".to_string(),
        m => match m.strip_prefix("adaptive") {
            Some(k) => format!("supersample --samples {k} --adaptive"),
            None => format!("supersample --samples {}", &m[2..]),
        },
    };
    let scenes = [
        "scene environment --polygons 300 --frames 2 --seed 1",
        "scene environment --polygons 300 --frames 2 --seed 2 --depth-complexity 3",
        "scene environment --polygons 60 --frames 2 --seed 3",
        "scene sphere",
        "cat examples/gouraud.txt",
        "cat examples/phong.txt",
        "cat examples/transparent.txt",
    ];
    for scene in scenes {
        for size in ["97x61", "64x128"] {
            let eye = format!("{scene} | viewxf --size {size} | clipbatch");
            for mode in ["ss2", "ss4", "adaptive4", "adaptive8", "ss16", "abuf"] {
                let apart = pipeline_tests::sh(
                    &format!(
                        "{eye} | persp --size {size} | {} --stats | zbuf",
                        leaf(mode)
                    ),
                    b"",
                );
                let fused = pipeline_tests::sh(
                    &format!("{eye} | zbuf --project --size {size} --aa {mode} --stats"),
                    b"",
                );
                let what = format!("{scene} at {size}, {mode}");
                assert_eq!(apart.status.success(), fused.status.success(), "{what}");
                if !apart.status.success() {
                    // The transparent example under supersampling: refused alike (the
                    // pipe's status is zbuf's, its input cut short).
                    assert_eq!(fused.status.code(), Some(2), "{what}");
                    let said = String::from_utf8_lossy(&fused.stderr);
                    assert!(
                        said.starts_with("zbuf: stdin: frame 0, polygon 1: a polygon of opacity")
                            && said.contains("supersample draws opaque polygons only"),
                        "{what}: {said}"
                    );
                    continue;
                }
                assert!(!fused.stdout.is_empty(), "{what}");
                assert!(apart.stdout == fused.stdout, "{what}: the frames differ");
                // The leaf's counters, under zbuf's name: `supersample: … N runs out,
                // COUNTS` against `zbuf: stdin: … N runs, COUNTS`.
                let counts = |stderr: &[u8], after: &str| {
                    let text = String::from_utf8_lossy(stderr).into_owned();
                    let line = text.lines().next().unwrap_or_default().to_string();
                    line.split_once(after).map(|(_, c)| c.to_string())
                };
                let (a, f) = (
                    counts(&apart.stderr, "runs out, "),
                    counts(&fused.stderr, "runs, "),
                );
                assert!(a.is_some() && a == f, "{what}: {a:?} {f:?}");
            }
        }
    }
}

/// `zbuf --aa` resolves one polygon input into pictures: several inputs, `--runs`, a
/// fragment stream and a mode that is none of the leaves' are usage errors (status 2).
#[test]
fn zbuf_aa_refuses_what_it_cannot_resolve() {
    for (script, said) in [
        (
            "zbuf --aa ss4 a b",
            "zbuf: --aa resolves one polygon input into pictures: not with several inputs or --runs\n",
        ),
        (
            "zbuf --aa adaptive2 --runs",
            "zbuf: --aa resolves one polygon input into pictures: not with several inputs or --runs\n",
        ),
        (
            "scene penetrating | viewxf --size 40x30 | clipbatch | persp --size 40x30 | scanconv | zbuf --aa ss2",
            "zbuf: stdin: --aa resolves a polygon stream here (screen space, or eye space with \
             --project), and this is a stream of fragments\n",
        ),
    ] {
        let out = pipeline_tests::sh(script, b"");
        assert_eq!(out.status.code(), Some(2), "{script}");
        assert_eq!(String::from_utf8_lossy(&out.stderr), said, "{script}");
        assert!(out.stdout.is_empty(), "{script}");
    }
    for mode in ["ss3", "adaptive", "ss", "abuf8", "zbuf"] {
        let out = pipeline_tests::sh(&format!("zbuf --aa {mode} < /dev/null"), b"");
        assert_eq!(out.status.code(), Some(2), "{mode}");
        let said = String::from_utf8_lossy(&out.stderr);
        assert!(
            said.starts_with(&format!("zbuf: invalid value '{mode}' for '--aa <MODE>': not none, ssK, adaptiveK (K = 2, 4, 8 or 16) or abuf")),
            "{mode}: {said}"
        );
    }
}
