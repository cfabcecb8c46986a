//! The thesis's own test: Appendix 4's INPUTTER scene of two penetrating polygons,
//! rendered on its 21×21 screen, against its "SAMPLE OUTPUT: PENETRATING POLYGONS".

use pipeline_tests::{parse_ppm_stream, sh};

const RED: [u8; 3] = [255, 60, 60];
const BLUE: [u8; 3] = [60, 60, 255];
const TABLE: &[([u8; 3], char)] = &[([0, 0, 0], '.'), (RED, '0'), (BLUE, '1')];

/// The thesis's sample, as printed at the end of Appendix 4 (its OCR'd `I` is the
/// character `1`, and the OCR lost the leading blanks, which do not matter below).
const THESIS_SAMPLE: &str = "
  I
 III
IIIII  0
IIIII  00
  IIII10000
   IIII10000
    IIII10000
     IIII10000
      0011000000
       00000000000
        000000000000
          IIII
           II
            I
";

/// What polypipe draws, exactly, by the pixel-centre rules of docs/DESIGN.md ("Coverage").
const POLYPIPE: &str = "\
.....................
.....................
.....................
.....................
..11.................
.1111.....0..........
..1111...000.........
....111.00000........
.....11100000........
......11100000.......
......011100000......
.....00010000000.....
.....00000000000.....
....0000000000000....
...........111.......
.............11......
.....................
.....................
.....................
.....................
.....................
";

/// A row's sequence of colours left to right, runs collapsed: `IIII10000` → `10`.
fn runs(row: &str) -> String {
    let mut out = String::new();
    for ch in row.chars().filter(|c| *c == '0' || *c == '1' || *c == 'I') {
        let ch = if ch == 'I' { '1' } else { ch };
        if !out.ends_with(ch) {
            out.push(ch);
        }
    }
    out
}

/// The picture's structure: each row's run sequence, repeated rows collapsed.
fn structure(picture: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for row in picture.lines().map(runs).filter(|r| !r.is_empty()) {
        if out.last() != Some(&row) {
            out.push(row);
        }
    }
    out
}

#[test]
fn penetrating_polygons_match_the_thesis_sample() {
    let out = sh(
        "scripts/render.sh --size 21x21 examples/penetrating.txt",
        b"",
    );
    assert!(
        out.status.success(),
        "render.sh failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let frames = parse_ppm_stream(&out.stdout).unwrap();
    assert_eq!(frames.len(), 1);
    let picture = frames[0].as_chars(TABLE);
    assert_eq!(picture, POLYPIPE);
    // The occam code mapped x_s to integer pixel coordinates and filled spans inclusive
    // of both ends, so its shapes are up to a pixel larger on each side than pixel
    // centres give; the structure, the blue quad alone, then beside the red triangle,
    // then piercing it, the triangle alone, and the quad's tail below, is the same.
    assert_eq!(structure(&picture), structure(THESIS_SAMPLE));
    assert_eq!(structure(&picture), ["1", "10", "010", "0", "1"]);
}
