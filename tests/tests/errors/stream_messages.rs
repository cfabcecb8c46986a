//! Stream messages, each case as the command that showed it: messages that echo
//! the input escape what cannot be seen (a byte-order mark first is read past), numbers
//! print in exponent form when very large or small, a cut binary stream names frame and
//! polygon, and annotations in a world-space stream are refused at the reader.

use pipeline_tests::sh;

/// Runs `cmd` on `input`; returns the status and stderr.
fn run(cmd: &str, input: &[u8]) -> (Option<i32>, String) {
    let out = sh(cmd, input);
    (
        out.status.code(),
        String::from_utf8(out.stderr).expect("messages are UTF-8"),
    )
}

#[test]
fn a_byte_order_mark_first_is_read_past() {
    // As a Windows editor saves a scene.
    let (status, err) = run(
        "viewxf --text",
        b"\xef\xbb\xbfpolypipe 1 world\ncolour 1 2 3\n0 0 0\nEND\n",
    );
    assert_eq!((status, err.as_str()), (Some(0), ""));
    // Anywhere else it is named, escaped.
    let (status, err) = run(
        "viewxf",
        "polypipe 1 world\n\u{feff}colour 1 2 3\nEND\n".as_bytes(),
    );
    assert_eq!(status, Some(1));
    assert_eq!(
        err,
        "viewxf: line 2, column 1: expected `colour`, NEXT.FRAME or END, found \
         `\\u{feff}colour` (\\u{feff} is a UTF-8 byte-order mark)\n"
    );
}

#[test]
fn control_characters_are_escaped_in_messages() {
    // NUL in a number, Ctrl-Z (DOS's end of file) after END.
    let (status, err) = run(
        "viewxf",
        b"polypipe 1 world\ncolour 1 2 3\n0 0 1\x00\nEND\n",
    );
    assert_eq!(status, Some(1));
    assert_eq!(
        err,
        "viewxf: line 3, column 5: expected z of vertex 0 (3 numbers a vertex in world \
         space), found `1\\x00`\n"
    );
    let (status, err) = run("clipplane left", b"polypipe 1 eye\nEND\n\x1a\n");
    assert_eq!(status, Some(1));
    assert_eq!(
        err,
        "clipplane: line 3, column 1: data after END: `\\x1a`\n"
    );
}

#[test]
fn huge_numbers_in_messages_are_in_exponent_form() {
    let (status, err) = run(
        "persp --size 8x8",
        b"polypipe 1 eye hither 1e300 yon 2\nEND\n",
    );
    assert_eq!(status, Some(1));
    assert_eq!(
        err,
        "persp: line 1, column 12: hither 1e300 and yon 2 must satisfy 0 < hither < yon\n"
    );
}

#[test]
fn a_cut_binary_stream_names_frame_and_polygon() {
    // Three polygons in frame 0, two in frame 1; cut inside frame 1's second polygon.
    let scene = "polypipe 1 world\ncolour 1 1 1\n0 0 0\n1 0 0\n0 1 0\nNEXT.POLYGON\n\
                 colour 2 2 2\n0 0 0\n1 0 0\n0 1 0\nNEXT.POLYGON\ncolour 3 3 3\n0 0 0\n\
                 1 0 0\n0 1 0\nNEXT.FRAME\ncolour 4 4 4\n0 0 0\n1 0 0\n0 1 0\nNEXT.POLYGON\n\
                 colour 5 5 5\n0 0 0\n1 0 0\n0 1 0\nEND\n";
    // The eye-space header is the magic's 8 bytes, the version and space tag (4 + 4), the
    // view volume (3 · 8) and the attributes (1: no depth form; 1 each for vertex colours,
    // vertex normals and opacity; 1: no lighting); a triangle is 8 + 3 · 32 = 104 bytes;
    // NEXT.FRAME 8.
    let polygon_4 = 45 + 3 * 104 + 8 + 104;
    let cut = polygon_4 + 50;
    let (status, err) = run(
        &format!("viewxf | head -c {cut} | clipplane left"),
        scene.as_bytes(),
    );
    assert_eq!(status, Some(1));
    assert_eq!(
        err,
        format!(
            "clipplane: byte {polygon_4} (frame 1, polygon 1): the stream ends in the middle \
             of a record (cut short?)\n"
        )
    );
    // Cut between records: after polygon 0 of frame 1.
    let (status, err) = run(
        &format!("viewxf | head -c {polygon_4} | clipplane left"),
        scene.as_bytes(),
    );
    assert_eq!(status, Some(1));
    assert_eq!(
        err,
        format!(
            "clipplane: byte {polygon_4} (frame 1, after polygon 0): the stream ends without \
             END (cut short?)\n"
        )
    );
}

#[test]
fn annotations_in_a_world_space_stream_are_refused() {
    // The plane would pass viewxf untransformed and the picture would be wrong.
    let world = "polypipe 1 world\ncolour 1 2 3\nplane 0 0 1 -16\n-5 -5 0\n5 -5 0\n0 5 0\nEND\n";
    let (status, err) = run("viewxf", world.as_bytes());
    assert_eq!(status, Some(1));
    assert_eq!(
        err,
        "viewxf: line 3, column 1: a `plane` line in a world-space stream: annotations \
         (`plane`, `shade`, `on`) are defined for eye and screen space only\n"
    );
    let (status, err) = run("zspec --size 8x8", world.as_bytes());
    assert_eq!(status, Some(1));
    assert!(
        err.contains("line 3, column 1: a `plane` line in a world-space stream"),
        "{err}"
    );
    let on = "polypipe 1 world\ncolour 1 2 3\n-5 -5 0 on -5 -5 0 5 -5 0\n5 -5 0\n0 5 0\nEND\n";
    let (status, err) = run("viewxf", on.as_bytes());
    assert_eq!(status, Some(1));
    assert_eq!(
        err,
        "viewxf: line 3, column 9: an edge support (`on`) in a world-space stream: annotations \
         (`plane`, `shade`, `on`) are defined for eye and screen space only\n"
    );
    // In eye space, where the splitter writes them, they are read.
    let eye =
        "polypipe 1 eye\ncolour 1 2 3\nplane 0 0 1 -16\n0 0 16 10\n1 0 16 10\n0 1 16 10\nEND\n";
    let (status, err) = run("clipplane left --text", eye.as_bytes());
    assert_eq!((status, err.as_str()), (Some(0), ""));
}
