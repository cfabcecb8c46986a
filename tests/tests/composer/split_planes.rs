//! The painter with geometric splitting on the scene with no depth order: N full-screen
//! planes tilted about different axes, every pair crossing (`scene planes N`), at
//! 500×500. For N = 5, 50 and 400 the picture differs from the z-buffer's in under 0.5%
//! of the pixels, or the painter says on stderr that it could not order every polygon:
//! never a wrong picture in silence.

use pipeline_tests::{parse_ppm_stream, sh, Frame};

/// The frame of `scene planes n` through `leaf` at 500×500, and the leaf's stderr.
fn frame(n: u32, leaf: &str) -> (Frame, String) {
    let out = sh(
        &format!(
            "e=$(mktemp); trap 'rm -f \"$e\"' EXIT
             scene planes {n} | viewxf | clipbatch | persp --size 500x500 | {leaf} 2>\"$e\" | zbuf
             s=$?; cat \"$e\" >&2; exit $s"
        ),
        b"",
    );
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "planes {n}, {leaf}: {stderr}");
    let mut frames = parse_ppm_stream(&out.stdout).expect("PPM");
    assert_eq!(frames.len(), 1);
    (frames.remove(0), stderr)
}

#[test]
fn split_planes_are_the_zbuffers_within_half_a_percent_or_said() {
    for n in [5, 50, 400] {
        let (z, _) = frame(n, "scanconv --resolve");
        let (p, said) = frame(n, "painter --split");
        assert_eq!(z.pixels.len(), 500 * 500);
        let differ = z
            .pixels
            .iter()
            .zip(&p.pixels)
            .filter(|(a, b)| a != b)
            .count();
        let gave_up = said.contains(": could not order every polygon");
        assert!(
            differ * 200 < z.pixels.len() || gave_up,
            "planes {n}: {differ} pixels unlike the z-buffer's, and nothing said: {said}"
        );
        // What was measured (docs/methods.md, the Done-when table): five planes are cut
        // into the z-buffer's picture, the two centres that lie 0.0004 and 0.0015 pixel
        // from a line where two planes have equal depth, (153, 63) and (176, 96), mended
        // (the cut's ends are snapped to 1/256 pixel while the z-buffer compares depths at
        // the centre, docs/DESIGN.md, "Coverage"); fifty and four hundred spend the cut
        // budget, and say so.
        match n {
            5 => assert_eq!((differ, said.as_str()), (0, ""), "planes 5"),
            _ => assert!(gave_up, "planes {n}: {said}"),
        }
    }
}
