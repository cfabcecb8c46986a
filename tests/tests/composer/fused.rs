//! `fused` (src/bin/fused.rs), render.sh's depth-0 pipeline as one process, writes
//! render.sh's PPM bytes: otherwise timing one against the other would measure something
//! other than the pipes and the codec.

use pipeline_tests::{parse_ppm_stream, run, sh};

/// Asserts `fused ARGS` (with each clipper) writes what `render.sh ARGS` writes, and
/// returns the number of frames.
fn same_as_render_sh(args: &str) -> usize {
    let expected = run(&format!("scripts/render.sh {args}"));
    for clipper in ["planes", "batch"] {
        let got = run(&format!("fused --clipper {clipper} {args}"));
        assert!(
            got == expected,
            "fused --clipper {clipper} {args}: not render.sh's bytes"
        );
    }
    let frames = parse_ppm_stream(&expected).expect("PPM frames");
    // A real picture: not one colour.
    assert!(frames[0].pixels.iter().any(|p| *p != frames[0].pixels[0]));
    frames.len()
}

#[test]
fn penetrating_as_render_sh_renders_it() {
    assert_eq!(same_as_render_sh("examples/penetrating.txt"), 1);
    assert_eq!(
        same_as_render_sh("--size 64x48 --eye 10,5,20 --hither 2 examples/cube.txt"),
        1
    );
}

#[test]
fn an_environment_movie_as_render_sh_renders_it() {
    // Binary, as scene writes it, and its text form; the camera's aspect from --size.
    let scene = "<(scene environment --polygons 5000 --depth-complexity 4 --frames 3 --size 320x200 --seed 5)";
    assert_eq!(same_as_render_sh(&format!("--size 320x200 {scene}")), 3);
    let text =
        "<(scene environment --polygons 2000 --depth-complexity 2 --frames 2 --seed 6 --text)";
    assert_eq!(same_as_render_sh(text), 2);
}

#[test]
fn fused_refuses_what_viewxf_refuses() {
    let out = sh("viewxf < examples/penetrating.txt | fused -", b"");
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "fused: input is eye-space, expected world-space; this stage takes a scene as the source writes it\n"
    );
}
