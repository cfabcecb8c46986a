//! Gouraud shading through the pipeline (docs/DESIGN.md, "Shading"; Phong's in phong.rs,
//! and here through the methods other than the z-buffer): a stream that
//! declares `vertex-colours` is shaded by every stage alike. Through `scripts/render.sh`
//! at tree depths 0 to 3, in both merge modes and with either clipper, its frames are
//! `zspec`'s byte for byte; and a triangle's pixels are, to within one level a channel, a
//! held-out computation of Gouraud's rule written here from scratch: the vertex colours
//! interpolated linearly across the screen (barycentric weights at each pixel centre).

use pipeline_tests::reference::one_frame;
use pipeline_tests::{check_triangle_frame, only_frame as frame, run, screen_mix, sh};

#[test]
fn a_shaded_scene_is_zspecs_at_every_depth_in_both_merge_modes() {
    let reference = run("zspec --size 96x80 < examples/gouraud.txt");
    let f = frame(&reference);
    // The triangle's red corner, the square's yellow corner and the flat grey one.
    let colours: std::collections::HashSet<[u8; 3]> = f.pixels.iter().copied().collect();
    assert!(colours.len() > 1000, "{} colours", colours.len());
    assert!(colours.contains(&[90, 90, 90]));
    for depth in 0..=3 {
        for merge in ["tiles", "buffer"] {
            let ppm = run(&format!(
                "scripts/render.sh --size 96x80 --depth {depth} --merge {merge} \
                 examples/gouraud.txt"
            ));
            assert!(ppm == reference, "--depth {depth} --merge {merge}");
        }
    }
    let pixels = run(
        "scripts/render.sh --size 96x80 --depth 2 --merge buffer --pixels examples/gouraud.txt",
    );
    assert!(pixels == reference, "--merge buffer --pixels");
    let chain = run("scripts/render.sh --size 96x80 --depth 2 --clip chain examples/gouraud.txt");
    assert!(chain == reference, "--clip chain");
}

/// The exact hidden-surface methods other than the z-buffer shade as it does: each visible
/// span of a shaded polygon takes its colour planes' value at every pixel centre, so the
/// frames of examples/gouraud.txt (a shaded triangle through a shaded square, a flat
/// quadrilateral behind) and of the Gouraud sphere are `zspec`'s at every tree depth. The
/// painter needs its splitting step where the triangle passes through the square (without
/// it the painter is wrong there, flat or shaded); the sphere it paints without.
#[test]
fn every_exact_method_shades_as_zspec_does() {
    let sphere = run("scene sphere --stacks 6 --slices 12 --gouraud --text");
    let exact = ["scanline", "warnock", "painter --split"];
    let sphere_methods = ["scanline", "warnock", "painter --split", "painter"];
    let scenes: [(&str, &[u8], &[&str]); 2] = [
        ("examples/gouraud.txt", &[], &exact),
        ("-", &sphere, &sphere_methods),
    ];
    for (scene, input, methods) in scenes {
        let out = sh(&format!("zspec --size 96x80 {scene}"), input);
        assert!(out.status.success());
        let reference = out.stdout;
        for method in methods {
            for depth in 0..=3 {
                let out = sh(
                    &format!(
                        "scripts/render.sh --size 96x80 --hse {method} --depth {depth} {scene}"
                    ),
                    input,
                );
                let stderr = String::from_utf8_lossy(&out.stderr);
                assert!(out.status.success(), "{method} {depth} {scene}: {stderr}");
                assert!(
                    out.stdout == reference,
                    "--hse {method} --depth {depth} {scene}"
                );
            }
        }
    }
}

/// Phong shading (a `vertex-normals` stream, its lighting in the header) goes through the
/// same calls: scanline, warnock and the painter light each visible pixel as the z-buffer
/// does, so examples/phong.txt is `zspec`'s at every depth; the a-buffer lights each
/// fragment at its pixel centre, the same frame at every depth, and zspec's colour
/// wherever one polygon covers the pixel (all but 166 edge pixels of 7,680).
#[test]
fn the_other_methods_light_a_phong_stream_as_zspec_does() {
    let reference = run("zspec --size 96x80 < examples/phong.txt");
    for method in ["scanline", "warnock", "painter", "painter --split"] {
        for depth in 0..=3 {
            let ppm = run(&format!(
                "scripts/render.sh --size 96x80 --hse {method} --depth {depth} examples/phong.txt"
            ));
            assert!(ppm == reference, "--hse {method} --depth {depth}");
        }
    }
    let abuf = |depth: u32| {
        run(&format!(
            "scripts/render.sh --size 96x80 --aa abuf --depth {depth} examples/phong.txt"
        ))
    };
    let at_0 = abuf(0);
    for depth in 1..=3 {
        assert!(abuf(depth) == at_0, "--aa abuf --depth {depth}");
    }
    let (a, z) = (frame(&at_0), frame(&reference));
    let differ = a
        .pixels
        .iter()
        .zip(&z.pixels)
        .filter(|(p, q)| p != q)
        .count();
    let lit = z.pixels.iter().filter(|p| **p != [0, 0, 0]).count();
    assert!(lit > 4000, "{lit} pixels lit");
    assert!(differ <= 200, "{differ} pixels differ from zspec's");
}

/// A triangle's screen-space Gouraud colour at the centre of pixel (x, y), computed
/// without the pipeline's code ([`screen_mix`]). `None` for a centre outside it (a
/// weight below `margin`).
fn held_out(
    vertices: [[f64; 3]; 3],
    colours: [[f64; 3]; 3],
    size: (usize, usize),
    x: usize,
    y: usize,
    margin: f64,
) -> Option<[f64; 3]> {
    screen_mix(
        vertices,
        colours,
        size,
        (x as f64 + 0.5, y as f64 + 0.5),
        margin,
    )
}

/// The triangle of the held-out tests: its world vertices and their colours.
const TRIANGLE: [[f64; 3]; 3] = [[-7.3, -5.1, 0.3], [1.2, 7.7, -1.1], [8.1, -3.9, 2.2]];
const TRIANGLE_COLOURS: [[f64; 3]; 3] = [
    [250.3, 10.2, 20.7],
    [15.1, 240.6, 30.4],
    [40.9, 35.2, 230.1],
];

/// [`TRIANGLE`] as a `vertex-colours` scene.
fn triangle_scene() -> String {
    let mut scene = String::from("polypipe 1 world vertex-colours\ncolour 0 0 0\n");
    for (v, c) in TRIANGLE.iter().zip(&TRIANGLE_COLOURS) {
        scene += &format!("{} {} {} {} {} {}\n", v[0], v[1], v[2], c[0], c[1], c[2]);
    }
    scene + "END\n"
}

#[test]
fn a_triangles_pixels_are_the_screen_space_interpolation_of_its_vertex_colours() {
    let (vertices, colours) = (TRIANGLE, TRIANGLE_COLOURS);
    let scene = triangle_scene();
    let size = (120, 90);
    let methods = ["zbuf", "scanline", "warnock", "painter"];
    for (method, depth) in methods.iter().flat_map(|m| [(m, 0), (m, 3)]) {
        let f = one_frame(
            &format!("scripts/render.sh --size 120x90 --hse {method} --depth {depth} -"),
            scene.as_bytes(),
        );
        assert_eq!((f.width, f.height), size);
        let covered = check_triangle_frame(&f, |x, y, margin| {
            held_out(vertices, colours, size, x, y, margin)
        });
        assert!(covered > 1200, "{covered} pixels covered");
    }
}

/// The a-buffer keeps one colour a fragment, the polygon's at the pixel centre: a pixel
/// the triangle covers wholly (its four corners inside) is, to within one level a
/// channel, the held-out interpolation at its centre, at every tree depth alike; the
/// Gouraud sphere's frames are the same at every depth too.
#[test]
fn the_a_buffer_shades_a_fully_covered_pixel_at_its_centre() {
    let scene = triangle_scene();
    let size = (120, 90);
    let render = |depth: u32| {
        let out = sh(
            &format!("scripts/render.sh --size 120x90 --aa abuf --depth {depth} -"),
            scene.as_bytes(),
        );
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "--depth {depth}: {stderr}");
        out.stdout
    };
    let reference = render(0);
    for depth in 1..=3 {
        assert!(render(depth) == reference, "--aa abuf --depth {depth}");
    }
    let f = frame(&reference);
    let mut full = 0;
    for y in 0..size.1 {
        for x in 0..size.0 {
            let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
                .map(|(i, j)| (x as f64 + i, y as f64 + j));
            if corners
                .iter()
                .any(|&c| screen_mix(TRIANGLE, TRIANGLE_COLOURS, size, c, 1e-9).is_none())
            {
                continue;
            }
            full += 1;
            let want = held_out(TRIANGLE, TRIANGLE_COLOURS, size, x, y, -1.0).unwrap();
            let got = f.at(x, y);
            for k in 0..3 {
                assert!(
                    (got[k] as f64 - want[k]).abs() <= 1.0,
                    "pixel ({x}, {y}): {got:?} against {want:?}"
                );
            }
        }
    }
    assert!(full > 1100, "{full} pixels wholly covered");
    let sphere = run("scene sphere --stacks 6 --slices 12 --gouraud --text");
    let abuf = |depth: u32| {
        let out = sh(
            &format!("scripts/render.sh --size 96x80 --aa abuf --depth {depth} -"),
            &sphere,
        );
        assert!(out.status.success());
        out.stdout
    };
    let at_0 = abuf(0);
    assert!(
        abuf(2) == at_0 && abuf(3) == at_0,
        "the sphere through --aa abuf"
    );
}

#[test]
fn supersampling_shades_each_sample_as_zspec_does() {
    for k in [2, 4] {
        let reference = run(&format!(
            "zspec --size 96x80 --samples {k} < examples/gouraud.txt"
        ));
        for depth in [0, 2] {
            let ppm = run(&format!(
                "scripts/render.sh --size 96x80 --aa ss{k} --depth {depth} examples/gouraud.txt"
            ));
            assert!(ppm == reference, "--aa ss{k} --depth {depth}");
        }
    }
}

/// Hidden lines, stroked in one colour a polygon, refuse a shaded stream (status 2, and a
/// line naming what does shade) rather than draw it flat; every other method shades.
#[test]
fn hidden_lines_refuse_a_shaded_stream_and_name_what_shades() {
    let out = sh(
        &format!(
            "scripts/render.sh --size 96x80 --hidden-line -o {}/shaded.svg examples/gouraud.txt",
            env!("CARGO_TARGET_TMPDIR")
        ),
        b"",
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("hiddenline: ")
            && stderr.contains("this stream is Gouraud-shaded (its header says `vertex-colours`); shading is drawn by every hidden-surface method (render.sh --hse zbuf, scanline, warnock, painter) and by anti-aliasing (--aa ssK, abuf)"),
        "{stderr}"
    );
    assert!(out.stdout.is_empty());
}

/// A polygon of opacity below 255 is refused (status 2, naming the a-buffer) by every
/// stage that would draw it opaque; a stream that says `opacity` but holds only opaque
/// polygons renders as it would without the word.
#[test]
fn a_transparent_polygon_is_refused_where_it_would_be_drawn_opaque() {
    // At depth 1 either leaf may be the first to meet the polygon (both get a piece); with
    // --merge tiles leaf 0 is the merger's own, zbuf, for the z-buffer.
    for (options, refusers) in [
        ("--depth 0", &[("zbuf: leaf-0: ", "zbuf")][..]),
        (
            "--depth 1 --merge buffer",
            &[("scanconv (leaf ", "scanconv")],
        ),
        (
            "--depth 1",
            &[
                ("scanconv (leaf 1): ", "scanconv"),
                ("zbuf: leaf-0: ", "zbuf"),
            ],
        ),
        ("--hse scanline --depth 0", &[("scanline: ", "scanline")]),
        // At depth 0 the merger runs the anti-aliasing leaf's method itself, and names
        // the leaf.
        ("--aa ss2 --depth 0", &[("zbuf: leaf-0: ", "supersample")]),
        (
            "--aa ss2 --depth 1",
            &[("supersample (leaf ", "supersample")],
        ),
    ] {
        let out = sh(
            &format!("scripts/render.sh --size 64x64 {options} examples/transparent.txt"),
            b"",
        );
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{options}: {stderr}");
        assert!(
            refusers
                .iter()
                .any(|(stage, name)| stderr.starts_with(stage)
                    && stderr.contains(&format!(
                        "frame 0, polygon 1: a polygon of opacity 128 (below 255): {name} draws \
                     opaque polygons only; transparency is the a-buffer's (render.sh --aa abuf)"
                    ))),
            "{options}: {stderr}"
        );
    }
    let out = sh("zspec --size 64x64 < examples/transparent.txt", b"");
    assert_eq!(out.status.code(), Some(2));
    let opaque = "polypipe 1 world opacity\ncolour 0 0 255 255\n-6 -6 -2\n6 -6 -2\n6 6 -2\nEND\n";
    let plain = "polypipe 1 world\ncolour 0 0 255\n-6 -6 -2\n6 -6 -2\n6 6 -2\nEND\n";
    let a = sh("scripts/render.sh --size 32x32 -", opaque.as_bytes());
    let b = sh("scripts/render.sh --size 32x32 -", plain.as_bytes());
    assert!(a.status.success() && a.stdout == b.stdout);
}

/// The sampling thesis's eq. 6.5 for a transparent fragment, front to back: the covered
/// region is its colour times its opacity plus what lies behind times the rest.
fn eq_6_5(front: [f64; 3], opacity: f64, behind: [f64; 3]) -> [f64; 3] {
    let t = 1.0 - opacity / 255.0;
    [0, 1, 2].map(|k| front[k] * (1.0 - t) + behind[k] * t)
}

/// A red square of opacity 128 over an opaque blue one through `--aa abuf`: the overlap is
/// eq. 6.5's colour, the red over the black background its share of red, and a pixel
/// half covered along the red square's edge half of each, at every tree depth.
#[test]
fn the_a_buffer_blends_a_transparent_square_by_eq_6_5() {
    let reference =
        run("scripts/render.sh --size 64x64 --aa abuf --depth 0 examples/transparent.txt");
    for depth in 1..=3 {
        let ppm = run(&format!(
            "scripts/render.sh --size 64x64 --aa abuf --depth {depth} examples/transparent.txt"
        ));
        assert!(ppm == reference, "--depth {depth}");
    }
    let f = frame(&reference);
    let (red, blue, black) = ([255.0, 0.0, 0.0], [0.0, 0.0, 255.0], [0.0; 3]);
    let overlap = eq_6_5(red, 128.0, blue);
    // The red square spans X 23.47..40.53 and Y 7.47..40.53 (z_e = 18, w = 11.25): its
    // bottom edge covers half of row 40's samples, its left edge half of column 23's.
    let half = |a: [f64; 3], b: [f64; 3]| [0, 1, 2].map(|k| (a[k] + b[k]) / 2.0);
    for ((x, y), want) in [
        ((30, 30), overlap),
        ((50, 15), eq_6_5(red, 128.0, black)),
        ((30, 40), half(overlap, blue)),
        ((23, 30), half(overlap, blue)),
        ((30, 41), blue),
    ] {
        let got = f.at(x, y);
        for k in 0..3 {
            assert!(
                (got[k] as f64 - want[k]).abs() <= 1.0,
                "pixel ({x}, {y}): {got:?} against eq. 6.5's {want:?}"
            );
        }
    }
}

/// `scene sphere --gouraud` writes a vertex-coloured sphere (its header says so), which
/// renders to zspec's bytes through a tree.
#[test]
fn the_gouraud_sphere_renders_as_zspec_does() {
    let scene = run("scene sphere --stacks 6 --slices 12 --gouraud --text");
    let text = String::from_utf8(scene).unwrap();
    assert!(
        text.starts_with("polypipe 1 world vertex-colours\n"),
        "{}",
        &text[..60]
    );
    let reference = sh("zspec --size 80x60 -", text.as_bytes());
    let tree = sh(
        "scripts/render.sh --size 80x60 --depth 2 -",
        text.as_bytes(),
    );
    assert!(reference.status.success() && tree.status.success());
    assert!(reference.stdout == tree.stdout);
}

/// The clippers cut a vertex colour where they cut the edge, with the position's
/// parameter: the square of examples/gouraud.txt crosses the left plane on its edge from
/// (−26, −8.2, −10.44), black, to (9.5, −7.9, 0.27), yellow, about 24 % of the way in
/// from the outside, and both clippers give that point the same interpolated colour.
#[test]
fn the_clippers_interpolate_colours_at_the_cut() {
    let chain = run(
        "viewxf --size 500x500 < examples/gouraud.txt | clipplane left | clipplane right \
         | clipplane top | clipplane bottom | clipplane hither | clipplane yon --text",
    );
    let batch = run("viewxf --size 500x500 < examples/gouraud.txt | clipbatch --text");
    assert_eq!(
        String::from_utf8_lossy(&chain),
        String::from_utf8_lossy(&batch)
    );
    let text = String::from_utf8(chain).unwrap();
    let cut = "\n-17.40420915599913 -8.127359513994358 27.84673464959861 17.40420915599913 \
               61.74441310479497 60.65480581471036 0.0605337383380343\n";
    assert!(text.contains(cut), "{text}");
}
