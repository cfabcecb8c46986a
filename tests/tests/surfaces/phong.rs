//! Phong shading through the pipeline (docs/DESIGN.md, "Shading"): a stream whose header
//! says `vertex-normals` carries a normal at every vertex and its lighting in the header;
//! every stage interpolates the normals as it interpolates vertex colours, and the
//! renderer lights each pixel. Through `scripts/render.sh` at tree depths 0 to 3, in both
//! merge modes, its frames are `zspec`'s byte for byte; and a triangle's pixels are, to
//! within one level a channel, a held-out computation written here from scratch: the
//! normals mixed by barycentric weights on the screen, normalized, and lit by Phong's
//! model (ambient, two-sided diffuse, a white highlight (r·v)^N).

use pipeline_tests::reference::one_frame;
use pipeline_tests::{check_triangle_frame, only_frame as frame, run, screen_mix, sh};

#[test]
fn a_phong_scene_is_zspecs_at_every_depth_in_both_merge_modes() {
    let reference = run("zspec --size 96x80 < examples/phong.txt");
    let f = frame(&reference);
    // The highlight is white-ish inside the triangle, where no vertex is bright.
    let brightest = f
        .pixels
        .iter()
        .map(|p| p[0] as u32 + p[1] as u32 + p[2] as u32)
        .max();
    assert!(brightest > Some(600), "{brightest:?}");
    for depth in 0..=3 {
        for merge in ["tiles", "buffer"] {
            let ppm = run(&format!(
                "scripts/render.sh --size 96x80 --depth {depth} --merge {merge} examples/phong.txt"
            ));
            assert!(ppm == reference, "--depth {depth} --merge {merge}");
        }
    }
    let pixels =
        run("scripts/render.sh --size 96x80 --depth 2 --merge buffer --pixels examples/phong.txt");
    assert!(pixels == reference, "--merge buffer --pixels");
    let chain = run("scripts/render.sh --size 96x80 --depth 2 --clip chain examples/phong.txt");
    assert!(chain == reference, "--clip chain");
    for k in [2, 4] {
        let want = run(&format!(
            "zspec --size 96x80 --samples {k} < examples/phong.txt"
        ));
        for depth in [0, 2] {
            let got = run(&format!(
                "scripts/render.sh --size 96x80 --aa ss{k} --depth {depth} examples/phong.txt"
            ));
            assert!(got == want, "--aa ss{k} --depth {depth}");
        }
    }
}

/// Phong's colour at the centre of pixel (x, y) of a triangle, computed here without the
/// pipeline's code: the vertices projected with the thesis's camera (eye at z = 20,
/// s = 10, d = 16, so w = 0.625·z_e), the normals mixed by the centre's barycentric
/// weights, and the model of the header below. `None` outside (a weight below `margin`).
fn held_out(
    vertices: [[f64; 3]; 3],
    normals: [[f64; 3]; 3],
    size: (usize, usize),
    (x, y): (usize, usize),
    margin: f64,
) -> Option<[f64; 3]> {
    let mut n = screen_mix(
        vertices,
        normals,
        size,
        (x as f64 + 0.5, y as f64 + 0.5),
        margin,
    )?;
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    n = n.map(|c| c / len);
    // The header's lighting: ambient 0.3, light (0, 0.6, 0.8) of 0.9, specular 0.7 with
    // exponent 12, viewer +z; the colour (200, 60, 30).
    let light = [0.0, 0.6, 0.8];
    let nl = n[0] * light[0] + n[1] * light[1] + n[2] * light[2];
    let diffuse = 0.3 + 0.9 * nl.abs();
    // The normal faces the viewer (n_z > 0 here), so r·v is r's z: 2(n·l)n_z − l_z.
    assert!(n[2] > 0.0);
    let rv = 2.0 * nl * n[2] - light[2];
    let highlight = if nl > 0.0 && rv > 0.0 {
        0.7 * 0.9 * rv.powf(12.0)
    } else {
        0.0
    };
    Some([200.0, 60.0, 30.0].map(|c| (c * diffuse + 255.0 * highlight).min(255.0)))
}

#[test]
fn a_triangles_pixels_are_its_normals_interpolated_on_the_screen_and_lit() {
    let vertices = [[-7.3, -5.1, 0.3], [1.2, 7.7, -1.1], [8.1, -3.9, 2.2]];
    let normals = [[-0.5, -0.4, 0.77], [0.1, 0.7, 0.7], [0.6, -0.3, 0.74]];
    let mut scene = String::from(
        "polypipe 1 world vertex-normals ambient 0.3 light 0 0.6 0.8 0.9 specular 0.7 12\n\
         colour 200 60 30\n",
    );
    for (v, n) in vertices.iter().zip(&normals) {
        scene += &format!("{} {} {} {} {} {}\n", v[0], v[1], v[2], n[0], n[1], n[2]);
    }
    scene += "END\n";
    let size = (120, 90);
    let mut highlight = 0;
    for depth in [0, 3] {
        let f = one_frame(
            &format!("scripts/render.sh --size 120x90 --depth {depth} -"),
            scene.as_bytes(),
        );
        assert_eq!((f.width, f.height), size);
        let covered = check_triangle_frame(&f, |x, y, margin| {
            held_out(vertices, normals, size, (x, y), margin)
        });
        assert!(covered > 1200, "{covered} pixels covered");
        highlight += f.pixels.iter().filter(|p| p[1] > 150).count();
    }
    // The highlight is there (green is 60·diffuse ≤ 72 without it).
    assert!(highlight > 20, "{highlight} highlight pixels");
}

/// The hidden-line drawing strokes edges in one colour a polygon: it refuses a
/// Phong-shaded stream with status 2, naming what shades.
#[test]
fn hidden_lines_refuse_a_phong_stream() {
    let out = sh(
        &format!(
            "scripts/render.sh --size 64x64 --hidden-line -o {}/phong.svg examples/phong.txt",
            env!("CARGO_TARGET_TMPDIR")
        ),
        b"",
    );
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(
            "hiddenline: hiddenline strokes each polygon's edges in its one colour, and this \
             stream is Phong-shaded (its header says `vertex-normals`)"
        ),
        "{stderr}"
    );
}

/// `scene sphere --phong` writes normals and its lighting in the header; the same sphere
/// through the pipeline is zspec's, and its highlight is round where Gouraud's is not:
/// Phong's brightest pixel is near the point where the normal halves light and viewer.
#[test]
fn the_phong_sphere_has_its_highlight_where_the_normal_halves_light_and_viewer() {
    let scene = run("scene sphere --stacks 8 --slices 16 --phong --specular 0.8,40 --text");
    let text = String::from_utf8(scene.clone()).unwrap();
    assert!(
        text.starts_with("polypipe 1 world vertex-normals ambient 0.3 light "),
        "{}",
        &text[..80]
    );
    assert!(text.contains(" specular 0.8 40 viewer 0 0 1\n"));
    let reference = frame(&sh("zspec --size 128x128", &scene).stdout);
    let rendered = sh("scripts/render.sh --size 128x128 --depth 1 -", &scene);
    assert!(rendered.status.success());
    let f = frame(&rendered.stdout);
    assert!(f.pixels == reference.pixels);
    // The default light (1, 1.5, 2) and the viewer +z: the half vector's direction on
    // the sphere of radius 8 at the origin, projected (w = 0.625·(20 − z)).
    let l = [1.0f64, 1.5, 2.0];
    let ll = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();
    let h = [l[0] / ll, l[1] / ll, l[2] / ll + 1.0];
    let hh = (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt();
    let p = h.map(|c| 8.0 * c / hh);
    let w = 0.625 * (20.0 - p[2]);
    let (sx, sy) = ((p[0] / w + 1.0) * 64.0, (1.0 - p[1] / w) * 64.0);
    let (mut best, mut at) = (0u32, (0usize, 0usize));
    for y in 0..128 {
        for x in 0..128 {
            let c = f.at(x, y);
            let v = c[0] as u32 + c[1] as u32 + c[2] as u32;
            if v > best {
                (best, at) = (v, (x, y));
            }
        }
    }
    let d = ((at.0 as f64 + 0.5 - sx).powi(2) + (at.1 as f64 + 0.5 - sy).powi(2)).sqrt();
    assert!(
        d < 3.0,
        "brightest at {at:?}, the highlight's centre at ({sx:.1}, {sy:.1})"
    );
}
