//! The degenerate-geometry suite (docs/degenerate.md, examples/degenerate/): every scene
//! rendered by the pipeline (`render.sh`, 64x64) at splitter depths 0 to 3 is
//! byte-identical to the exact reference (`zspec`), and each case's own pixels are
//! asserted.

use pipeline_tests::{parse_ppm_stream, sh, Frame};

const SIZE: usize = 64;
const BLACK: [u8; 3] = [0, 0, 0];

/// Renders examples/degenerate/NAME.txt with `zspec` and with `render.sh` at depths
/// 0..=3; asserts all five PPMs are identical and returns the frame.
fn reference_and_every_depth(name: &str) -> Frame {
    let scene = format!("examples/degenerate/{name}.txt");
    let reference = sh(&format!("zspec --size 64x64 {scene}"), b"");
    assert!(
        reference.status.success(),
        "zspec {name}: {}",
        String::from_utf8_lossy(&reference.stderr)
    );
    for depth in 0..=3 {
        let out = sh(
            &format!("scripts/render.sh --size 64x64 --depth {depth} {scene}"),
            b"",
        );
        assert!(
            out.status.success(),
            "render.sh --depth {depth} {name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            out.stderr.is_empty(),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        if out.stdout != reference.stdout {
            let a = &parse_ppm_stream(&reference.stdout).unwrap()[0];
            let b = &parse_ppm_stream(&out.stdout).unwrap()[0];
            let differ: Vec<_> = (0..SIZE * SIZE)
                .filter(|&i| a.pixels[i] != b.pixels[i])
                .map(|i| (i % SIZE, i / SIZE, a.pixels[i], b.pixels[i]))
                .take(8)
                .collect();
            panic!(
                "{name} at depth {depth} differs from zspec (x, y, zspec, pipeline): {differ:?}"
            );
        }
    }
    let frames = parse_ppm_stream(&reference.stdout).expect("a PPM stream");
    assert_eq!(frames.len(), 1);
    assert_eq!((frames[0].width, frames[0].height), (SIZE, SIZE));
    frames.into_iter().next().unwrap()
}

/// The pixel whose centre is nearest world point (x, y) on the plane z = 0 (default
/// camera, 64x64: a pixel is 0.390625 units there).
fn px(x: f64, y: f64) -> (usize, usize) {
    (
        ((x + 12.5) / 0.390625).floor() as usize,
        ((12.5 - y) / 0.390625).floor() as usize,
    )
}

fn count(frame: &Frame, colour: [u8; 3]) -> usize {
    frame.pixels.iter().filter(|&&p| p == colour).count()
}

fn at(frame: &Frame, (x, y): (usize, usize)) -> [u8; 3] {
    frame.at(x, y)
}

#[test]
fn vertices_on_the_six_clip_planes() {
    let f = reference_and_every_depth("on-clip-planes");
    // The square whose corners are the screen's corners fills it.
    assert_eq!(count(&f, BLACK), 0);
    assert_eq!(at(&f, (63, 0)), [40, 40, 200]);
    // The corner triangle's apex is the bottom-left corner.
    assert_eq!(at(&f, (0, 63)), [230, 200, 40]);
    // The triangle reaching hither covers the centre.
    assert_eq!(at(&f, px(0.0, -2.0)), [230, 60, 60]);
    // The yon triangle's near base (z = 1) shows in front of the square; its apex on
    // yon and top is behind it.
    assert!(count(&f, [60, 200, 60]) > 0);
    assert_eq!(at(&f, (32, 0)), [40, 40, 200]);
}

#[test]
fn edges_lying_in_clip_planes() {
    let f = reference_and_every_depth("edges-in-clip-planes");
    // The edge in the left plane is the screen's left border: column 0 is covered from
    // y_w = -3 up.
    assert_eq!(at(&f, (0, px(0.0, 0.0).1)), [200, 80, 40]);
    assert_eq!(at(&f, (63, 63)), [150, 60, 200]);
    assert_eq!(at(&f, (0, 0)), BLACK);
    assert!(
        count(&f, [240, 240, 240]) > 0,
        "the hither triangle is drawn"
    );
}

#[test]
fn vertices_and_edges_on_the_splitting_planes() {
    let f = reference_and_every_depth("on-split-planes");
    // The rectangle whose left edge is x_w = 0 owns column 32 (centre x_w = 0.195) and
    // not column 31 (the diamond shows there).
    assert_eq!(at(&f, (32, 32)), [60, 200, 60]);
    assert_eq!(at(&f, (31, 32)), [220, 60, 60]);
    assert!(count(&f, [60, 60, 220]) > 0 && count(&f, [220, 220, 60]) > 0);
}

#[test]
fn polygons_through_and_behind_the_eye() {
    let f = reference_and_every_depth("eye-plane");
    // The square wholly behind the eye draws nothing, not even inverted.
    assert_eq!(count(&f, [255, 0, 255]), 0);
    // The floor crossing the eye plane is drawn in front of it.
    assert!(count(&f, [200, 120, 60]) > 100);
    // The triangle with a vertex at the eye is edge-on (its plane holds the eye).
    assert_eq!(count(&f, [60, 200, 200]), 0);
}

#[test]
fn edge_on_polygons_cover_nothing() {
    let f = reference_and_every_depth("edge-on");
    for c in [[255, 0, 0], [0, 255, 0], [0, 0, 255]] {
        assert_eq!(count(&f, c), 0, "edge-on polygon {c:?} drew pixels");
    }
    assert_eq!(at(&f, (32, 32)), [90, 90, 90]);
    assert_eq!(at(&f, (31, 31)), [90, 90, 90]);
}

#[test]
fn collinear_leading_vertices() {
    let f = reference_and_every_depth("collinear-leading");
    // The zero-area triangle draws nothing.
    assert_eq!(count(&f, [255, 255, 0]), 0);
    // Newell's plane: the pentagon is in front of the grey square right of x = 0 and
    // behind it on the left.
    assert_eq!(at(&f, px(4.0, 0.0)), [220, 80, 200]);
    assert_eq!(at(&f, px(-4.0, 0.0)), [120, 120, 120]);
}

#[test]
fn slivers_and_specks_smaller_than_a_pixel() {
    let f = reference_and_every_depth("slivers-and-specks");
    // The speck around pixel (10, 10)'s centre covers exactly that pixel.
    assert_eq!(count(&f, [80, 255, 80]), 1);
    assert_eq!(at(&f, (10, 10)), [80, 255, 80]);
    // The speck between centres covers none.
    assert_eq!(count(&f, [80, 80, 255]), 0);
    // The horizontal sliver over row 40's centres is a one-pixel line from x = -6 to 6:
    // columns 17 to 46 (centres -5.8594 .. 5.8594), 30 pixels.
    assert_eq!(count(&f, [250, 250, 250]), 30);
    assert!((0..SIZE).all(|y| y == 40 || f.at(20, y) != [250, 250, 250]));
    // The slanted sliver is dotted: fewer pixels than the 52 columns it spans.
    let dots = count(&f, [255, 80, 80]);
    assert!(dots > 0 && dots < 52, "{dots}");
}

#[test]
fn local_minima_and_horizontal_edges() {
    let f = reference_and_every_depth("minima-horizontal");
    // Top edge on row 10's centres: a top edge, so row 10 is covered; bottom edge on
    // row 50's top boundary: row 49 is covered, row 50 is not.
    assert_eq!(at(&f, px(-7.5, 8.3984375)), [230, 120, 30]);
    assert_eq!(at(&f, px(-7.5, 8.3984375 + 0.390625)), BLACK);
    assert_eq!(at(&f, (12, 49)), [230, 120, 30]);
    assert_eq!(at(&f, (12, 50)), BLACK);
    // The V's apex is exactly pixel (32, 60)'s centre: a bottom vertex, so not covered,
    // while the pixel above it is. Its horizontal top edge lies exactly on row 45's
    // centres: a top edge, so covered, and row 44 not.
    let v = [30, 120, 230];
    assert_eq!(at(&f, (32, 60)), BLACK);
    assert_eq!(at(&f, (32, 59)), v);
    assert_eq!((0..SIZE).filter(|&x| at(&f, (x, 45)) == v).count(), 22);
    assert!((0..SIZE).all(|x| at(&f, (x, 44)) != v));
    assert_eq!(count(&f, v), 174);
}

#[test]
fn concave_polygons_cut_into_pieces() {
    let f = reference_and_every_depth("concave-clipped");
    // The comb's teeth reach the right edge; the gaps between them stay empty there.
    assert_eq!(at(&f, (63, px(0.0, -8.0).1)), [240, 200, 40]);
    assert_eq!(at(&f, (63, px(0.0, -4.0).1)), BLACK);
    assert_eq!(at(&f, (63, px(0.0, 0.0).1)), [240, 200, 40]);
    assert_eq!(at(&f, (63, px(0.0, 4.0).1)), BLACK);
    assert!(count(&f, [40, 200, 240]) > 0);
    assert!(count(&f, [200, 60, 200]) > 0);
}

#[test]
fn coplanar_ties_go_to_the_earlier_polygon() {
    let f = reference_and_every_depth("coplanar-ties");
    assert_eq!(at(&f, px(0.0, 0.0)), [255, 0, 0]);
    assert_eq!(at(&f, px(5.0, 5.0)), [0, 255, 0]);
    assert_eq!(at(&f, px(-8.0, 8.0)), [0, 0, 255]);
    assert_eq!(count(&f, [255, 255, 255]), 0);
}

#[test]
fn self_intersecting_and_non_planar_polygons() {
    let f = reference_and_every_depth("bowtie-nonplanar");
    // Both lobes of the bowtie, by the even-odd rule.
    assert_eq!(at(&f, px(-9.0, 6.0)), [255, 100, 100]);
    assert_eq!(at(&f, px(-3.0, 6.0)), [255, 100, 100]);
    assert_eq!(at(&f, px(-6.0, 9.0)), BLACK);
    // The pentagram's points are covered, its centre is not.
    assert_eq!(at(&f, px(5.0, 9.0)), [100, 255, 100]);
    assert_eq!(at(&f, px(5.0, 5.5)), BLACK);
    // The non-planar quad's depth is Newell's plane z = 0: the square at z = 1 shows,
    // the one at z = -1 does not.
    assert_eq!(at(&f, px(-7.0, -7.0)), [200, 200, 200]);
    assert_eq!(at(&f, px(-5.0, -5.0)), [100, 100, 255]);
    assert_eq!(count(&f, [255, 255, 255]), 0);
}

#[test]
fn huge_and_tiny_coordinates() {
    let f = reference_and_every_depth("huge-and-tiny");
    // The 2e30 square is clipped to exactly the screen: no background.
    assert_eq!(count(&f, BLACK), 0);
    // The 1e-7 triangle around pixel (31, 31)'s centre is snapped to a point (docs/DESIGN.md,
    // "Coverage") and covers nothing: the square behind it shows there.
    assert_eq!(count(&f, [60, 200, 60]), 0);
    assert_eq!(at(&f, (31, 31)), [40, 40, 40]);
    assert!(count(&f, [200, 60, 60]) > 0 && count(&f, [60, 60, 200]) > 0);
}

#[test]
fn huge_edge_through_the_eye_keeps_w_proportional_to_z() {
    // An edge from 1e30 behind the eye to 1e30 in front: where clipping cuts it near the
    // eye, z_e and w both cancel; proto's intersection recomputes the unsolved one from
    // w = z_e·s/d, zspec's hither cut sets w = K1·s/d. Both then draw the part between
    // hither and yon, which a rational-arithmetic ray cast gives as these rows (columns
    // from, to inclusive); before, the pipeline met w = 0 and refused the polygon.
    let f = reference_and_every_depth("huge-through-eye");
    let blue = [60, 60, 200];
    assert_eq!(count(&f, blue) + count(&f, BLACK), SIZE * SIZE);
    let span = |r: usize| {
        let xs: Vec<usize> = (0..SIZE).filter(|&c| at(&f, (c, r)) == blue).collect();
        xs.first().map(|&a| (a, *xs.last().unwrap()))
    };
    assert_eq!(span(0), Some((48, 63)));
    assert_eq!(span(10), Some((43, 63)));
    assert_eq!(span(11), Some((42, 62)));
    assert_eq!(span(18), Some((39, 51)));
    assert_eq!(span(24), Some((42, 42)));
    assert_eq!(span(25), None);
    assert_eq!(count(&f, blue), 381);
}

#[test]
fn polygons_of_zero_one_and_two_vertices() {
    let f = reference_and_every_depth("vertex-counts");
    assert_eq!(
        count(&f, [255, 0, 0]) + count(&f, [0, 255, 0]) + count(&f, [0, 0, 255]),
        0
    );
    assert_eq!(count(&f, BLACK) + count(&f, [255, 255, 255]), SIZE * SIZE);
    assert_eq!(at(&f, (32, 32)), [255, 255, 255]);
}

/// Per-pixel hit counts from the scan converter's spans (`span y x0 x1 z0 dz`).
fn hit_counts(scene: &str) -> Vec<u32> {
    let out = sh(
        &format!(
            "viewxf < {scene} | clipplane left | clipplane right | clipplane top \
             | clipplane bottom | clipplane hither | clipplane yon | persp --size 64x64 \
             | scanconv --text"
        ),
        b"",
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut counts = vec![0u32; SIZE * SIZE];
    for line in String::from_utf8(out.stdout).unwrap().lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        if w.first() == Some(&"span") {
            let n: Vec<usize> = w[1..4].iter().map(|s| s.parse().unwrap()).collect();
            for x in n[1]..n[2] {
                counts[n[0] * SIZE + x] += 1;
            }
        } else if w.first() == Some(&"pixel") {
            panic!("expected spans: {line}");
        }
    }
    counts
}

#[test]
fn a_mesh_of_shared_edges_has_no_crack_and_no_double_hit() {
    let f = reference_and_every_depth("mesh");
    assert_eq!(count(&f, BLACK), 0, "a crack shows the background");
    let counts = hit_counts("examples/degenerate/mesh.txt");
    let wrong: Vec<_> = (0..SIZE * SIZE)
        .filter(|&i| counts[i] != 1)
        .map(|i| (i % SIZE, i / SIZE, counts[i]))
        .collect();
    assert!(wrong.is_empty(), "pixels not hit exactly once: {wrong:?}");
}

/// Every scene of examples/degenerate/ is one of this file's: rendered by
/// `reference_and_every_depth`, at depths 0 to 3 against zspec, by a test above.
#[test]
fn every_degenerate_scene_is_rendered_against_the_reference() {
    let source = include_str!("degenerate.rs");
    let dir = pipeline_tests::repo_root().join("examples/degenerate");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            name.strip_suffix(".txt").map(str::to_string)
        })
        .collect();
    names.sort();
    assert_eq!(names.len(), 15, "{names:?}");
    let missing: Vec<&String> = names
        .iter()
        .filter(|n| !source.contains(&format!("reference_and_every_depth(\"{n}\")")))
        .collect();
    assert!(missing.is_empty(), "scenes no test renders: {missing:?}");
}
