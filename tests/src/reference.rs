//! Frames drawn through shell pipelines of the stages, and compared: with zspec's exact
//! frame, with the z-buffer's, pixel by pixel.

use crate::{only_frame, parse_ppm_stream, run_with, sh, Frame};

/// The one frame `script` (see [`sh`]) writes as PPM with `stdin` as its input; a
/// failure, or a number of frames other than one, fails the test with the script.
pub fn one_frame(script: &str, stdin: &[u8]) -> Frame {
    only_frame(&run_with(script, stdin))
}

/// Renders `scene` with zspec and with `scripts/render.sh` under each of `variants`
/// (render.sh options), both with `camera` options, and asserts that every pixel agrees;
/// returns zspec's frame.
pub fn agree_with_zspec(scene: &str, camera: &str, variants: &[&str]) -> Frame {
    let reference = one_frame(&format!("zspec {camera} -"), scene.as_bytes());
    for v in variants {
        let got = one_frame(
            &format!("scripts/render.sh {camera} {v} -"),
            scene.as_bytes(),
        );
        let differ = got.differences(&reference).len();
        assert_eq!(
            differ, 0,
            "render.sh {camera} {v}: {differ} pixels differ from zspec"
        );
    }
    reference
}

/// The frames of `stream_cmd | LEAF | zbuf`, which must exit 0, and the leaf's stderr
/// (its `--stats` line, its notes), whole, after the pipeline's own.
pub fn through_leaf(stream_cmd: &str, leaf: &str, stdin: &[u8]) -> (Vec<Frame>, String) {
    let out = sh(
        &format!(
            "e=$(mktemp); trap 'rm -f \"$e\"' EXIT
             {stream_cmd} | {leaf} 2>\"$e\" | zbuf; s=$?; cat \"$e\" >&2; exit $s"
        ),
        stdin,
    );
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{leaf}: {stderr}");
    (parse_ppm_stream(&out.stdout).expect("PPM frames"), stderr)
}

/// Three bars on a 32×32 screen, each over the next (red over blue at the top left, blue
/// over green at the bottom right, green over red at the top right), no two passing
/// through each other: a cyclic overlap, no order to paint them in. The polygons only,
/// for a `polypipe 1 screen 32 32` header and an `END` (or more frames) around them.
pub const CYCLIC_BARS: &str = "colour 255 0 0
2 4 0.2
28 4 0.8
28 10 0.8
2 10 0.2
NEXT.POLYGON
colour 0 255 0
20 2 0.5
26 2 0.5
26 28 0.8
20 28 0.8
NEXT.POLYGON
colour 0 0 255
2 8 0.6
6 4 0.6
28 26 0.3
24 30 0.3
";
