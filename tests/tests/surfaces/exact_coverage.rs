//! Coverage decided exactly on vertices snapped to 1/256 pixel (docs/DESIGN.md,
//! "Coverage"): the pipeline, with every hidden-surface method and at every tree depth,
//! draws what the reference draws at every pixel, centres lying exactly on edges
//! included; meshes are watertight; and the pieces of polygons cut at pixel boundaries,
//! level after level as the tree cuts them, cover exactly the whole polygon's pixels.
//!
//! The in-process tests (meshes, pieces) take the scan converter and the splitter as
//! libraries; a handful of scenes go through render.sh and zspec.

use pipeline_tests::reference::agree_with_zspec as agree;
use pipeline_tests::scenes::{eye_at, projective, tilted_decals, Lcg};
use proptest::prelude::*;
use proto::geometry::Plane;
use proto::perspective::Perspective;
use proto::{DVec4, Polygon};
use scan::SpanWalker;
use std::collections::BTreeMap;

/// The methods, each at tree depths from 0 to 4 (the painter with its splitting step,
/// where it is exact).
fn variants(depths: &[u32]) -> Vec<String> {
    let mut out = Vec::new();
    for d in depths {
        for hse in ["zbuf", "scanline", "warnock", "painter --split"] {
            out.push(format!("--depth {d} --hse {hse}"));
        }
    }
    out
}

fn example(name: &str) -> String {
    std::fs::read_to_string(pipeline_tests::repo_root().join("examples").join(name)).unwrap()
}

const BLUE: [u8; 3] = [60, 60, 255];

#[test]
fn the_blue_polygons_left_edge_covers_every_centre_on_it() {
    // At 400x400 the thesis's blue polygon's edge runs from (20, 100) to (60, 60) (persp
    // makes the first 19.999999999999996): every centre with c + r = 119 lies on it, and
    // it is a left edge, so every one of them is blue, in the reference and the pipeline.
    let vs = variants(&[0, 2]);
    let vs: Vec<&str> = vs.iter().map(String::as_str).collect();
    let f = agree(&example("penetrating.txt"), "--size 400x400", &vs);
    assert_eq!(f.at(39, 80), BLUE);
    assert_eq!(f.at(59, 60), BLUE);
    for c in 20..60 {
        assert_eq!(f.at(c, 119 - c), BLUE, "({c}, {})", 119 - c);
        // Just outside the edge: the background.
        assert_eq!(f.at(c, 118 - c), [0, 0, 0], "({c}, {})", 118 - c);
    }
}

#[test]
fn the_penetrating_scene_is_the_reference_at_every_size_method_and_depth() {
    for size in [
        "96x64",
        "320x240",
        "400x400",
        "500x500",
        "512x512",
        "777x333",
        "1000x1000",
    ] {
        // Every method at every depth from 0 to 4.
        let vs = variants(&[0, 1, 2, 3, 4]);
        let vs: Vec<&str> = vs.iter().map(String::as_str).collect();
        agree(&example("penetrating.txt"), &format!("--size {size}"), &vs);
    }
}

#[test]
fn tilted_coplanar_decals_are_the_reference_from_three_eyes() {
    // A red quad and a green one inside it on one tilted plane: the green one ties.
    let s = tilted_decals(2);
    let vs = variants(&[0, 1, 2, 3, 4]);
    let vs: Vec<&str> = vs.iter().map(String::as_str).collect();
    for camera in [
        "--eye 6,-4,18 --size 500x500",
        "--eye -3,7,15 --size 320x240",
        "--eye 1,1,9 --size 777x333",
    ] {
        let f = agree(&s, camera, &vs);
        assert!(f.pixels.iter().filter(|p| **p == [255, 0, 0]).count() > 10_000);
    }
}

/// A W×H screen's device point (X, Y) as a world point on the plane z = 0 seen by the
/// default camera (x_e = x, z_e = 20, w = 12.5): X = (x/(a·w) + 1)·W/2.
fn world(x: f64, y: f64, w: u32, h: u32) -> String {
    let a = w as f64 / h as f64;
    let wx = (2.0 * x / w as f64 - 1.0) * a * 12.5;
    let wy = (1.0 - 2.0 * y / h as f64) * 12.5;
    format!("{wx:.17} {wy:.17} 0\n")
}

/// A grid mesh of triangles over the screen point (x0, y0), `n`×`n` cells of `cell`
/// pixels, its inner vertices moved by `jitter(i, j)`: every triangle in its own colour.
fn mesh_scene(w: u32, h: u32, x0: f64, y0: f64, cell: f64, n: usize, step: f64) -> String {
    let mut s = String::from("polypipe 1 world\n");
    let mut k = 0u32;
    let point = |i: usize, j: usize| {
        let inner = i > 0 && j > 0 && i < n && j < n;
        let d = if inner {
            (((i * 7 + j * 3) % 5) as f64 - 2.0) * step
        } else {
            0.0
        };
        (x0 + i as f64 * cell + d, y0 + j as f64 * cell - d)
    };
    for i in 0..n {
        for j in 0..n {
            let (a, b, c, d) = (
                point(i, j),
                point(i + 1, j),
                point(i + 1, j + 1),
                point(i, j + 1),
            );
            for tri in [[a, b, c], [a, c, d]] {
                k += 1;
                if k > 1 {
                    s += "NEXT.POLYGON\n";
                }
                s += &format!(
                    "colour {} {} {}\n",
                    40 + k % 200,
                    30 + (k * 7) % 220,
                    20 + (k * 13) % 230
                );
                for (x, y) in tri {
                    s += &world(x, y, w, h);
                }
            }
        }
    }
    s + "END\n"
}

#[test]
fn meshes_on_integer_half_and_third_pixels_are_the_reference() {
    let (w, h) = (96u32, 64u32);
    for (cell, step) in [(8.0, 1.0), (6.5, 0.5), (7.0, 1.0 / 3.0)] {
        let scene = mesh_scene(w, h, 10.0, 4.0, cell, 7, step);
        let vs = variants(&[0, 1, 2, 3, 4]);
        let vs: Vec<&str> = vs.iter().map(String::as_str).collect();
        let f = agree(&scene, &format!("--size {w}x{h}"), &vs);
        // Watertight: every centre inside the mesh's square outline is drawn, none
        // outside (the outline's left and top edges hold their centres).
        let side = cell * 7.0;
        for y in 0..h as usize {
            for x in 0..w as usize {
                let (cx, cy) = (x as f64 + 0.5, y as f64 + 0.5);
                let inside = 10.0 <= cx && cx < 10.0 + side && 4.0 <= cy && cy < 4.0 + side;
                assert_eq!(f.at(x, y) != [0, 0, 0], inside, "({x}, {y}) cell {cell}");
            }
        }
    }
}

#[test]
fn edges_meant_on_centres_are_drawn_as_meant() {
    // Quads whose top and left edges a scene puts on pixel centres: (X, Y) from
    // (c + ½, r + ½) to (c + 10½, r + 3½), every 7 rows down a 400×400 screen. persp
    // makes some of those a hair off (14.500000000000002 for the quad at row 14): snapped,
    // each edge is back on its centres, a top and a left edge that holds them, so every
    // quad is 10 × 3 pixels from (c, r), the last one cut to row 399 by the screen, and
    // every method draws them so (the scan-line method once entered such a quad a line
    // late, from its unsnapped top, and lost its top row).
    let (w, h) = (400u32, 400u32);
    let mut s = String::from("polypipe 1 world\n");
    let rows: Vec<u32> = (0..h).step_by(7).collect();
    for (i, &r) in rows.iter().enumerate() {
        if i > 0 {
            s += "NEXT.POLYGON\n";
        }
        s += "colour 200 100 50\n";
        let (x, y) = (10.5 + (i % 9) as f64, r as f64 + 0.5);
        for (px, py) in [(x, y), (x + 10.0, y), (x + 10.0, y + 3.0), (x, y + 3.0)] {
            s += &world(px, py, w, h);
        }
    }
    s += "END\n";
    let vs = variants(&[0, 2]);
    let vs: Vec<&str> = vs.iter().map(String::as_str).collect();
    let f = agree(&s, &format!("--size {w}x{h}"), &vs);
    for y in 0..h as usize {
        for x in 0..w as usize {
            let quad = rows.iter().enumerate().any(|(i, &r)| {
                (r..r + 3).contains(&(y as u32)) && (10 + i % 9..20 + i % 9).contains(&x)
            });
            let want = if quad { [200, 100, 50] } else { [0, 0, 0] };
            assert_eq!(f.at(x, y), want, "({x}, {y})");
        }
    }
}

/// How many of `polys` cover each pixel centre of a w×h screen.
fn coverage(polys: &[Polygon], w: u32, h: u32) -> Vec<u32> {
    let mut map = vec![0u32; (w * h) as usize];
    let mut walker = SpanWalker::new();
    for p in polys {
        walker.for_each_span(p, w, h, |s| {
            for x in s.columns() {
                map[(s.y * w + x) as usize] += 1;
            }
        });
    }
    map
}

fn screen_poly(points: &[(f64, f64)]) -> Polygon {
    let pts: Vec<[f64; 3]> = points.iter().map(|&(x, y)| [x, y, 0.5]).collect();
    Polygon::from_xyz([1, 2, 3], &pts)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// A triangulated grid whose inner vertices sit on multiples of 1/2 or 1/3 pixel
    /// (and the boundary's on its straight sides) covers every centre of its outline
    /// exactly once and none outside, whatever way each cell is cut in two.
    #[test]
    fn meshes_are_watertight(
        denominator in prop::sample::select(vec![1u32, 2, 3]),
        moves in prop::collection::vec((-4i32..=4, -4i32..=4), 25),
        diagonals in prop::collection::vec(any::<bool>(), 36),
        origin in (0u32..6, 0u32..6),
    ) {
        let (w, h) = (40u32, 40u32);
        let n = 6usize;
        let cell = 5.0;
        let (ox, oy) = (origin.0 as f64 + 0.5 * (denominator == 2) as u32 as f64, origin.1 as f64);
        let point = |i: usize, j: usize| {
            let (mut x, mut y) = (ox + i as f64 * cell, oy + j as f64 * cell);
            if i > 0 && j > 0 && i < n && j < n {
                // At most a pixel each way: no triangle of 5-pixel cells folds over.
                let (dx, dy) = moves[(i - 1) * 5 + (j - 1)];
                let den = denominator as i32;
                x += dx.clamp(-den, den) as f64 / denominator as f64;
                y += dy.clamp(-den, den) as f64 / denominator as f64;
            }
            (x, y)
        };
        let mut polys = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let (a, b, c, d) = (point(i, j), point(i + 1, j), point(i + 1, j + 1), point(i, j + 1));
                if diagonals[i * n + j] {
                    polys.push(screen_poly(&[a, b, c]));
                    polys.push(screen_poly(&[a, c, d]));
                } else {
                    polys.push(screen_poly(&[a, b, d]));
                    polys.push(screen_poly(&[b, c, d]));
                }
            }
        }
        let map = coverage(&polys, w, h);
        let side = cell * n as f64;
        for y in 0..h {
            for x in 0..w {
                let (cx, cy) = (x as f64 + 0.5, y as f64 + 0.5);
                let inside = ox <= cx && cx < ox + side && oy <= cy && cy < oy + side;
                prop_assert_eq!(map[(y * w + x) as usize], inside as u32, "({}, {})", x, y);
            }
        }
    }
}

const W: u32 = 48;
const H: u32 = 32;

fn perspective() -> Perspective {
    projective(W, H)
}

/// An eye-space vertex that projects to screen point (X, Y) at depth z_e (to rounding).
fn at(x: f64, y: f64, z: f64) -> DVec4 {
    eye_at((W, H), x, y, z)
}

/// The pixel → covering count map of projected polygons (screen space).
fn pixel_counts(polys: &[Polygon]) -> BTreeMap<(u32, u32), u32> {
    let map = coverage(polys, W, H);
    map.iter()
        .enumerate()
        .filter(|(_, &n)| n > 0)
        .map(|(i, &n)| ((i as u32 % W, i as u32 / W), n))
        .collect()
}

/// Cuts `poly` (eye space) as the splitter tree does, `levels` deep: alternately at a
/// column line and a row line (pixel boundaries, chosen by `pick`), every piece again,
/// and projects the leaves' pieces.
fn tree_pieces(poly: &Polygon, levels: u32, pick: &mut impl FnMut(u32) -> u32) -> Vec<Polygon> {
    let mut pieces = vec![poly.clone()];
    for level in 0..levels {
        let plane = if level % 2 == 0 {
            Plane::column(2.0 * pick(W) as f64 / W as f64 - 1.0, W as f64 / H as f64)
        } else {
            Plane::row(1.0 - 2.0 * pick(H) as f64 / H as f64)
        };
        let mut next = Vec::new();
        for p in &pieces {
            let (mut a, mut b) = (Polygon::default(), Polygon::default());
            splitter::split(p, &plane, &mut a, &mut b);
            next.extend([a, b].into_iter().filter(|q| q.vertices.len() >= 3));
        }
        pieces = next;
    }
    let persp = perspective();
    for q in &mut pieces {
        persp.project_polygon(q).unwrap();
    }
    pieces
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Polygons with vertices on integer, half and third pixels (edges through many
    /// centres, steep and shallow), cut up to four levels deep at random pixel
    /// boundaries, cover exactly the pixels of the uncut polygon, each once.
    #[test]
    fn pieces_cut_at_pixel_boundaries_cover_the_whole(
        denominator in prop::sample::select(vec![1u32, 2, 3]),
        vertices in prop::collection::vec((0u32..=144, 0u32..=96, 2u32..40), 3..7),
        levels in 1u32..=4,
        cuts in prop::collection::vec(1u32..1000, 8),
    ) {
        let d = denominator as f64;
        let poly = Polygon::new(
            [9, 9, 9],
            vertices
                .iter()
                .map(|&(x, y, z)| at((x as f64 / d).min(W as f64), (y as f64 / d).min(H as f64), z as f64 / 2.0))
                .collect(),
        );
        let mut whole = poly.clone();
        perspective().project_polygon(&mut whole).unwrap();
        let expected = pixel_counts(std::slice::from_ref(&whole));
        let mut k = 0;
        let mut pick = |limit: u32| {
            k += 1;
            1 + cuts[(k - 1) % cuts.len()] % (limit - 1)
        };
        let pieces = tree_pieces(&poly, levels, &mut pick);
        prop_assert_eq!(pixel_counts(&pieces), expected);
    }
}

/// The rows of each vertex of a projected piece, by proto::raster::vertex_rows with the
/// piece's supports, and without them (the snapped vertices' own rows).
fn rows_with_and_without_supports(p: &Polygon) -> (Vec<i64>, Vec<i64>) {
    use proto::raster::{vertex_rows, Point};
    let snap = |v: &DVec4| Point {
        x: proto::raster::snap(v.x),
        y: proto::raster::snap(v.y),
    };
    let points: Vec<Point> = p.vertices.iter().map(snap).collect();
    let supports: Vec<Option<[Point; 2]>> = p
        .supports
        .iter()
        .map(|s| s.as_ref().map(|[a, b]| [snap(a), snap(b)]))
        .collect();
    let (mut with, mut without) = (Vec::new(), Vec::new());
    vertex_rows(&points, &supports, &mut with);
    vertex_rows(&points, &[], &mut without);
    (with, without)
}

#[test]
fn shallow_edges_cut_near_a_row_centre_cover_the_whole() {
    // A shallow edge (up to 40 columns over a twelfth of a row, its ends near twelfths
    // and thirds of a pixel) cut by
    // a column line where it passes within a sub-pixel unit of a row centre: snapped, the
    // cut point can land on the other side of that centre from the point where the
    // snapped edge meets the line, and then a piece that counted the edge on its own
    // cut point's rows would cross that row up to a pixel away from the cut. Thousands of
    // such cuts; the pieces cover exactly the whole's pixels, and the cases where the
    // rows move are counted, so that the test is known to reach them.
    let mut rng = Lcg(0x1985);
    let mut next = |n: u64| rng.next(n);
    let mut moved = 0;
    for case in 0..20_000 {
        let k = 10 + next(28) as u32;
        let r = 3.0 + next(20) as f64;
        let (a, b) = (8.0 + next(30) as f64 / 3.0, 8.0 + next(30) as f64 / 3.0);
        let (ya, yb) = (
            (4 + next(3)) as f64 / 12.0 + next(3) as f64 / 768.0,
            (4 + next(3)) as f64 / 12.0,
        );
        let left = (k as f64 - a, r + ya);
        let right = (k as f64 + b, r + 1.0 - yb);
        let apex = (
            k as f64 + next(9) as f64 / 3.0 - 1.0,
            r + 6.0 + next(4) as f64,
        );
        let z = [
            4.0 + next(30) as f64,
            4.0 + next(30) as f64,
            4.0 + next(30) as f64,
        ];
        let poly = Polygon::new(
            [9, 9, 9],
            [left, right, apex]
                .iter()
                .zip(z)
                .map(|(&(x, y), z)| at(x, y, z))
                .collect(),
        );
        let mut whole = poly.clone();
        perspective().project_polygon(&mut whole).unwrap();
        let pieces = tree_pieces(&poly, 1, &mut |_| k);
        for p in &pieces {
            let (with, without) = rows_with_and_without_supports(p);
            moved += (with != without) as u32;
        }
        assert_eq!(
            pixel_counts(&pieces),
            pixel_counts(std::slice::from_ref(&whole)),
            "case {case}: {left:?} {right:?} {apex:?} cut at {k}"
        );
    }
    assert!(moved > 20, "only {moved} pieces had a vertex's rows moved");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    /// Steep edges on third pixels, cut by the column line they cross: snapped, the cut
    /// point's Y may lie a row centre away from where the snapped edge meets the line
    /// (a 1/768-pixel move of an end shifts that point by dy/dx times as much), and the
    /// pieces still cover exactly the whole's pixels.
    #[test]
    fn steep_edges_cut_at_a_column_line_cover_the_whole(
        k in 4u32..40,
        ends in (1u32..6, 1u32..6, 0u32..6, 12u32..30),
        far in (0u32..4, 0u32..30),
        z in (4u32..40, 4u32..40, 4u32..40),
        row_too in any::<bool>(),
    ) {
        let (a, b, y0, dy) = ends;
        let top = (k as f64 - a as f64 / 3.0, y0 as f64 + 1.0 / 3.0);
        let bottom = (k as f64 + b as f64 / 3.0, (y0 + dy) as f64 - 1.0 / 3.0);
        let left = (far.0 as f64 + 1.0 / 3.0, far.1 as f64 + 2.0 / 3.0);
        let poly = Polygon::new(
            [9, 9, 9],
            [top, bottom, left]
                .iter()
                .zip([z.0, z.1, z.2])
                .map(|(&(x, y), z)| at(x, y, z as f64 / 2.0))
                .collect(),
        );
        let mut whole = poly.clone();
        perspective().project_polygon(&mut whole).unwrap();
        let expected = pixel_counts(std::slice::from_ref(&whole));
        let r = (y0 + dy / 2).max(1);
        let mut picks = [k, r].into_iter().cycle();
        let pieces = tree_pieces(&poly, 1 + row_too as u32, &mut |_| picks.next().unwrap());
        prop_assert_eq!(pixel_counts(&pieces), expected);
    }
}

#[test]
fn polygons_clipped_at_the_screen_and_at_yon_are_the_reference() {
    // gouraud.txt's square is clipped by the screen's left edge and by yon: the pipeline
    // snaps the clipped outline, and the reference cuts where the clippers cut, so the
    // centres along the cut edges are decided alike (before it cut, 2 pixels differed at
    // 1000x1000 and 1 at 777x333, (275, 249) on the edge from the yon cut).
    for size in ["1000x1000", "777x333"] {
        agree(
            &example("gouraud.txt"),
            &format!("--size {size}"),
            &[
                "--depth 0",
                "--depth 3 --hse warnock",
                "--depth 2 --hse scanline",
            ],
        );
    }
}
