use super::*;
use proptest::prelude::*;
use proto::camera::Camera;

const R: Colour = [255, 0, 0];
const G: Colour = [0, 255, 0];
const B: Colour = [0, 0, 255];
const K: Colour = [0, 0, 0];

fn setup(w: u32, h: u32) -> Setup {
    Setup::new(
        Camera::default().frame().unwrap(),
        View {
            aspect: w as f64 / h as f64,
            ..View::default()
        },
        w,
        h,
    )
}

/// The world point that the default camera sees at device point (X, Y) of a W×H screen,
/// at eye depth z_e (z_w = 20 − z_e; x_e = x_s·a·w, y_e = y_s·w, w = z_e·10/16).
fn at(x: f64, y: f64, z_e: f64, w: u32, h: u32) -> [f64; 3] {
    let wv = z_e * 10.0 / 16.0;
    let a = w as f64 / h as f64;
    [
        (2.0 * x / w as f64 - 1.0) * a * wv,
        (1.0 - 2.0 * y / h as f64) * wv,
        20.0 - z_e,
    ]
}

/// A polygon of device-space corners at eye depth 16 on a W×H screen.
fn poly(c: Colour, pts: &[(f64, f64)], w: u32, h: u32) -> Polygon {
    poly_at(c, pts, 16.0, w, h)
}

fn poly_at(c: Colour, pts: &[(f64, f64)], z_e: f64, w: u32, h: u32) -> Polygon {
    let p: Vec<[f64; 3]> = pts.iter().map(|&(x, y)| at(x, y, z_e, w, h)).collect();
    Polygon::from_xyz(c, &p)
}

/// An image as rows of letters: R, G, B, and `.` for black.
fn picture(pixels: &[Colour], w: u32) -> Vec<String> {
    pixels
        .chunks(w as usize)
        .map(|row| {
            row.iter()
                .map(|p| match *p {
                    R => 'R',
                    G => 'G',
                    B => 'B',
                    K => '.',
                    _ => '?',
                })
                .collect()
        })
        .collect()
}

#[test]
fn device_helper_is_exact_at_depth_16() {
    // At z_e = 16 (w = 10) the 4x4 device point (X, Y) is world (5X − 10, 10 − 5Y, 4).
    assert_eq!(at(0.5, 2.5, 16.0, 4, 4), [-7.5, -2.5, 4.0]);
}

#[test]
fn triangle_on_a_4x4_screen() {
    // Right edge x + y = 4 passes through four centres: a right edge, so they stay out.
    let t = poly(R, &[(0.0, 0.0), (4.0, 0.0), (0.0, 4.0)], 4, 4);
    let img = render_frame(&[t], &setup(4, 4), K).unwrap();
    assert_eq!(picture(&img, 4), ["RRR.", "RR..", "R...", "...."]);
}

#[test]
fn top_left_rule_on_a_4x4_screen() {
    // Edges through pixel centres: X = 0.5 (left: in), X = 2.5 (right: out),
    // Y = 0.5 (top: in), Y = 2.5 (bottom: out).
    let sq = poly(R, &[(0.5, 0.5), (2.5, 0.5), (2.5, 2.5), (0.5, 2.5)], 4, 4);
    let img = render_frame(std::slice::from_ref(&sq), &setup(4, 4), K).unwrap();
    assert_eq!(picture(&img, 4), ["RR..", "RR..", "....", "...."]);
    // The same square wound the other way renders the same.
    let mut rev = sq;
    rev.vertices.reverse();
    assert_eq!(render_frame(&[rev], &setup(4, 4), K).unwrap(), img);
}

#[test]
fn shared_edge_through_centres_covers_each_pixel_once() {
    // Two triangles sharing the diagonal (0,0)-(4,4), which passes through the centres
    // (0.5,0.5), (1.5,1.5), ... : each centre goes to exactly one of them.
    let s = setup(4, 4);
    let upper = poly(R, &[(0.0, 0.0), (4.0, 0.0), (4.0, 4.0)], 4, 4);
    let lower = poly(G, &[(0.0, 0.0), (4.0, 4.0), (0.0, 4.0)], 4, 4);
    let both = [upper, lower];
    assert_eq!(coverage_counts(&both, &s), vec![1; 16]);
    // The diagonal is the lower triangle's right edge and the upper's left edge.
    assert_eq!(
        picture(&render_frame(&both, &s, K).unwrap(), 4),
        ["RRRR", "GRRR", "GGRR", "GGGR"]
    );
}

#[test]
fn nearer_square_wins_whatever_the_order() {
    let s = setup(4, 4);
    let far = poly_at(
        R,
        &[(0.0, 0.0), (3.0, 0.0), (3.0, 3.0), (0.0, 3.0)],
        20.0,
        4,
        4,
    );
    let near = poly_at(
        B,
        &[(1.0, 1.0), (4.0, 1.0), (4.0, 4.0), (1.0, 4.0)],
        10.0,
        4,
        4,
    );
    let expect = ["RRR.", "RBBB", "RBBB", ".BBB"];
    let img = render_frame(&[far.clone(), near.clone()], &s, K).unwrap();
    assert_eq!(picture(&img, 4), expect);
    let img = render_frame(&[near, far], &s, K).unwrap();
    assert_eq!(picture(&img, 4), expect);
}

#[test]
fn equal_depth_the_earlier_polygon_wins() {
    let s = setup(4, 4);
    let a = poly(R, &[(0.0, 0.0), (3.0, 0.0), (3.0, 3.0), (0.0, 3.0)], 4, 4);
    let b = poly(G, &[(1.0, 1.0), (4.0, 1.0), (4.0, 4.0), (1.0, 4.0)], 4, 4);
    assert_eq!(
        picture(&render_frame(&[a.clone(), b.clone()], &s, K).unwrap(), 4),
        ["RRR.", "RRRG", "RRRG", ".GGG"]
    );
    assert_eq!(
        picture(&render_frame(&[b, a], &s, K).unwrap(), 4),
        ["RRR.", "RGGG", "RGGG", ".GGG"]
    );
}

#[test]
fn interpenetrating_polygons_meet_along_their_intersection() {
    // A vertical (constant z_e = 16) red square and a blue square tilted in depth from
    // z_e = 12 at the left of the screen to z_e = 20 at the right: blue is in front on
    // the left half, behind on the right.
    let s = setup(4, 4);
    let red = poly(R, &[(0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0)], 4, 4);
    // World points with x_w from −8 to 8 and z_w from 8 to 0 (z_e 12 → 20): the plane
    // z_e = 16 + x_w/2 crosses z_e = 16 at x_w = 0, the screen's middle column line.
    let blue = Polygon::from_xyz(
        B,
        &[
            [-8.0, 20.0, 8.0],
            [8.0, 20.0, 0.0],
            [8.0, -20.0, 0.0],
            [-8.0, -20.0, 8.0],
        ],
    );
    let img = render_frame(&[red, blue], &s, K).unwrap();
    assert_eq!(picture(&img, 4), ["BBRR", "BBRR", "BBRR", "BBRR"]);
}

#[test]
fn polygon_crossing_the_hither_plane_and_beyond_yon() {
    // A floor y_e = −2 from behind the eye (z_e = −5) to z_e = 100, past yon. On a 20x20 screen the ray through row r has y_s = 0.95 − r/10 and meets
    // the floor at z_e = −2/(y_s·10/16): beyond K2 = 30 for rows ≤ 10, and never nearer
    // than K1 = 1 on screen (that would need y_s < −3.2). So rows 11..20 are covered.
    let s = setup(20, 20);
    let floor = Polygon::from_xyz(
        G,
        &[
            [-100.0, -2.0, 25.0],
            [100.0, -2.0, 25.0],
            [100.0, -2.0, -80.0],
            [-100.0, -2.0, -80.0],
        ],
    );
    let img = render_frame(&[floor], &s, K).unwrap();
    let rows = picture(&img, 20);
    for (r, row) in rows.iter().enumerate() {
        let want = if r >= 11 { "G" } else { "." }.repeat(20);
        assert_eq!(row, &want, "row {r}");
    }
}

#[test]
fn the_hither_plane_cuts_a_floor_close_under_the_eye() {
    // Floor y_e = −0.1: z_e = 0.16/(−y_s) must lie in [1, 30], so
    // −y_s ∈ [0.00533, 0.16]: rows 10 (z_e 3.2) and 11 (z_e 1.067) only; row 12 would
    // meet it at z_e = 0.64, in front of the hither plane.
    let s = setup(20, 20);
    let floor = Polygon::from_xyz(
        G,
        &[
            [-100.0, -0.1, 25.0],
            [100.0, -0.1, 25.0],
            [100.0, -0.1, -80.0],
            [-100.0, -0.1, -80.0],
        ],
    );
    let img = render_frame(std::slice::from_ref(&floor), &s, K).unwrap();
    for (r, row) in picture(&img, 20).iter().enumerate() {
        let want = if r == 10 || r == 11 { "G" } else { "." }.repeat(20);
        assert_eq!(row, &want, "row {r}");
    }
    let counts = coverage_counts(&[floor], &s);
    assert_eq!(counts.iter().sum::<u32>(), 40);
}

#[test]
fn cut_at_hither_keeps_the_front_part() {
    let v = |x, z: f64| DVec4::new(x, 0.0, z, z * 0.625);
    let front = vec![v(0.0, 2.0), v(1.0, 2.0), v(1.0, 3.0)];
    assert_eq!(cut_at_hither(&front, 1.0, 0.625), front);
    let cut = cut_at_hither(&[v(0.0, 0.0), v(2.0, 2.0), v(0.0, 2.0)], 1.0, 0.625);
    assert_eq!(
        cut,
        vec![v(1.0, 1.0), v(2.0, 2.0), v(0.0, 2.0), v(0.0, 1.0)]
    );
    assert!(cut_at_hither(&[v(0.0, -1.0), v(1.0, 0.5), v(0.0, 0.9)], 1.0, 0.625).is_empty());
}

#[test]
fn behind_the_eye_or_degenerate_polygons_draw_nothing() {
    let s = setup(4, 4);
    let behind = poly_at(R, &[(0.0, 0.0), (4.0, 0.0), (0.0, 4.0)], -5.0, 4, 4);
    let beyond = poly_at(R, &[(0.0, 0.0), (4.0, 0.0), (0.0, 4.0)], 31.0, 4, 4);
    let line = poly(R, &[(0.0, 0.0), (4.0, 4.0), (2.0, 2.0)], 4, 4);
    let two = poly(R, &[(0.0, 0.0), (4.0, 4.0)], 4, 4);
    let empty = Polygon::new(R, vec![]);
    let img = render_frame(&[behind, beyond, line, two, empty], &s, G).unwrap();
    assert_eq!(img, vec![G; 16]);
}

#[test]
fn non_square_screen_uses_the_aspect_ratio() {
    // An 8x4 screen: a = 2. A square spanning device X 0..4 (the left half) and all rows.
    let s = setup(8, 4);
    let left = poly(R, &[(0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0)], 8, 4);
    assert_eq!(at(4.0, 0.0, 16.0, 8, 4), [0.0, 10.0, 4.0]);
    assert_eq!(at(0.0, 0.0, 16.0, 8, 4), [-20.0, 10.0, 4.0]);
    assert_eq!(
        picture(&render_frame(&[left], &s, K).unwrap(), 8),
        ["RRRR....", "RRRR....", "RRRR....", "RRRR...."]
    );
}

#[test]
fn comparison() {
    let img = |pixels: Vec<Colour>| Image {
        width: 3,
        height: 2,
        pixels,
    };
    let imgs = [img(vec![R, G, B, K, R, G]), img(vec![K; 6])];
    let cmp = compare(&imgs[..1], &imgs[1..]).unwrap();
    assert_eq!(cmp[0].pixels, 6);
    assert_eq!(cmp[0].differing, 5);
    assert_eq!(
        cmp[0].differences,
        vec![(0, 0), (1, 0), (2, 0), (1, 1), (2, 1)]
    );
    assert!((cmp[0].percent() - 100.0 / 6.0).abs() < 1e-12);
    assert_eq!(cmp[0].to_string(), "6 pixels, 5 differ, 16.6667% agree");
    assert_eq!(agreed(&cmp, 5.0 / 6.0), Ok(()));
    assert_eq!(
        agreed(&cmp, 0.5),
        Err("1 of 1 frames differ (more than --tolerance 0.5) (frames [0])".into())
    );
    assert_eq!(
        agreed(&cmp, 0.0),
        Err("1 of 1 frames differ (frames [0])".into())
    );
    assert_eq!(
        compare(&imgs, &imgs[..1]).unwrap_err(),
        "the streams have 2 and 1 frames"
    );
    let small = Image {
        width: 1,
        height: 1,
        pixels: vec![K],
    };
    assert_eq!(
        compare(&imgs[..1], &[small]).unwrap_err(),
        "frame 0 is 3x2 in one stream and 1x1 in the other"
    );
}

#[test]
fn planes_of_huge_polygons_do_not_overflow() {
    // Ordinary points: exactly Newell's plane.
    let small = [
        DVec3::new(1.0, 2.0, 16.0),
        DVec3::new(3.0, -1.0, 17.5),
        DVec3::new(-2.0, 0.5, 15.0),
    ];
    assert_eq!(plane_of(&small), newell_plane(&small));
    // At ±1.7e308 Newell's products overflow; scaled by a power of two they do not, and
    // the plane still contains the points: z = 16 + x·1e-300, roughly.
    let huge = [
        DVec3::new(-1.7e308, -1.7e308, 1.0),
        DVec3::new(1.7e308, -1.7e308, 1.0),
        DVec3::new(0.0, 1.7e308, -1.0),
    ];
    assert!(!newell_plane(&huge).is_finite());
    let p = plane_of(&huge);
    assert!(p.is_finite(), "{p:?}");
    let n = p.truncate().normalize();
    // The normal is that of the scaled triangle: mostly z, a little y.
    assert!(n.z > 0.99 && n.x.abs() < 1e-12, "{n:?}");
}

#[test]
fn a_polygon_projecting_beyond_f64_is_cut_to_the_guard_band_and_drawn() {
    // x_e = 1.7e308 at the hither distance projects to about 2.7e308 · W/2: infinite. It
    // was refused while the pipeline, which clips before it projects, drew it; cut to the
    // guard band first, it is drawn as the band y_e in (−1, 1) it is on the screen.
    let s = setup(8, 8);
    let p = Polygon::from_xyz(
        R,
        &[[1.7e308, 0.0, 19.0], [0.0, 1.0, 19.0], [0.0, -1.0, 19.0]],
    );
    let band = Polygon::from_xyz(
        R,
        &[
            [1e6, 1.0, 19.0],
            [0.0, 1.0, 19.0],
            [0.0, -1.0, 19.0],
            [1e6, -1.0, 19.0],
        ],
    );
    let drawn = render_frame(&[p], &s, K).unwrap();
    assert_eq!(drawn, render_frame(&[band], &s, K).unwrap());
    assert!(drawn.contains(&R), "{drawn:?}");
}

#[test]
fn colours_parse() {
    assert_eq!(parse_colour("1, 2,3"), Ok([1, 2, 3]));
    assert!(parse_colour("1,2").is_err());
    assert!(parse_colour("1,2,256").is_err());
}

proptest! {
    /// A jittered grid mesh (every triangle of every cell) that spans the whole screen
    /// covers every pixel centre exactly once, whatever the jitter: the top-left rule
    /// leaves no cracks and no double hits, also for vertices and edges that fall on
    /// centres (the jitter is in quarter pixels). The jitter stays within one pixel of a
    /// 5-pixel grid, so no vertex crosses its cell's diagonal and every cell stays a
    /// convex quad: with more, the "mesh" itself would overlap (a vertex jittered 1.5
    /// pixels inward lands inside the other triangle of its cell).
    #[test]
    fn a_mesh_covers_every_pixel_exactly_once(
        jitter in prop::collection::vec((-4i32..=4, -4i32..=4), 25),
        flip in prop::collection::vec(any::<bool>(), 16),
    ) {
        let (w, h) = (16u32, 16u32);
        let s = setup(w, h);
        // 5x5 grid points from −2 to 18 in steps of 5; interior points jittered.
        let point = |i: usize, j: usize| {
            let (mut x, mut y) = (-2.0 + 5.0 * i as f64, -2.0 + 5.0 * j as f64);
            if (1..4).contains(&i) && (1..4).contains(&j) {
                let (dx, dy) = jitter[j * 5 + i];
                x += dx as f64 * 0.25;
                y += dy as f64 * 0.25;
            }
            (x, y)
        };
        let mut mesh = Vec::new();
        for j in 0..4 {
            for i in 0..4 {
                let (a, b, c, d) = (point(i, j), point(i + 1, j), point(i + 1, j + 1), point(i, j + 1));
                // Either diagonal.
                if flip[j * 4 + i] {
                    mesh.push(poly(R, &[a, b, c], w, h));
                    mesh.push(poly(G, &[a, c, d], w, h));
                } else {
                    mesh.push(poly(R, &[a, b, d], w, h));
                    mesh.push(poly(G, &[b, c, d], w, h));
                }
            }
        }
        let counts = coverage_counts(&mesh, &s);
        prop_assert!(counts.iter().all(|&n| n == 1), "counts {:?}", counts);
    }
}

// ---- The supersampled reference -------------------------------------------------------

/// The box filter written out on its own, as the test's independent oracle: each K×K
/// block of a (K·W)×(K·H) image averaged per channel, `(sum + K²/2) / K²`.
fn box_filter(fine: &[Colour], w: u32, h: u32, k: u32) -> Vec<Colour> {
    let (w, h, k) = (w as usize, h as usize, k as usize);
    assert_eq!(fine.len(), w * k * h * k);
    let n = (k * k) as u32;
    let mut out = Vec::new();
    for r in 0..h {
        for c in 0..w {
            let mut s = [0u32; 3];
            for j in 0..k {
                for i in 0..k {
                    let p = fine[(r * k + j) * w * k + c * k + i];
                    for ch in 0..3 {
                        s[ch] += p[ch] as u32;
                    }
                }
            }
            out.push(s.map(|v| ((v + n / 2) / n) as u8));
        }
    }
    out
}

/// The frames of a text scene file of the repository's `examples/`.
fn example(name: &str) -> Vec<Vec<Polygon>> {
    let path = format!("{}/../examples/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read(&path).unwrap();
    let mut reader = proto::Reader::<proto::Token, _>::new(&text[..]).unwrap();
    let mut frames = vec![Vec::new()];
    while let Some(t) = reader.next_record().unwrap() {
        match t {
            proto::Token::Polygon(p) => frames.last_mut().unwrap().push(p),
            proto::Token::NextFrame => frames.push(Vec::new()),
            _ => {}
        }
    }
    frames
}

fn supersampled(polys: &[Polygon], s: &Setup, k: u32) -> Supersampled {
    render_supersampled(polys, s, k, K).unwrap()
}

#[test]
fn a_diagonal_edge_covers_ten_or_six_of_sixteen_samples() {
    // The shared diagonal (0,0)-(4,4) crosses each diagonal pixel corner to corner. Of
    // the 16 samples ((i+½)/4, (j+½)/4), 6 lie strictly above it (i > j), 6 strictly
    // below, and 4 on it; the diagonal is the upper triangle's left edge, so those 4 go
    // to the upper (red) one: red 10/16, green 6/16.
    // Red: (255·10 + 8) / 16 = 159; green: (255·6 + 8) / 16 = 96.
    let s = setup(4, 4);
    let upper = poly(R, &[(0.0, 0.0), (4.0, 0.0), (4.0, 4.0)], 4, 4);
    let lower = poly(G, &[(0.0, 0.0), (4.0, 4.0), (0.0, 4.0)], 4, 4);
    let both = supersampled(&[upper.clone(), lower.clone()], &s, 4);
    for r in 0..4 {
        for c in 0..4 {
            let want = match c.cmp(&r) {
                std::cmp::Ordering::Equal => [159, 96, 0],
                std::cmp::Ordering::Greater => R,
                std::cmp::Ordering::Less => G,
            };
            assert_eq!(both.pixels[r * 4 + c], want, "pixel ({c}, {r})");
            assert_eq!(both.edges[r * 4 + c], c == r, "edge flag of ({c}, {r})");
        }
    }
    // Each alone on black: the same counts.
    assert_eq!(supersampled(&[upper], &s, 4).pixels[5], [159, 0, 0]);
    assert_eq!(supersampled(&[lower], &s, 4).pixels[5], [0, 96, 0]);
}

#[test]
fn a_vertical_edge_inside_a_pixel_covers_whole_sample_columns() {
    // A square over device X 0..1.3: pixel 0 whole, pixel 1 (samples at X = 1.125,
    // 1.375, 1.625, 1.875) one column of 4: (255·4 + 8) / 16 = 64.
    let s = setup(4, 4);
    let sq = poly(R, &[(0.0, 0.0), (1.3, 0.0), (1.3, 4.0), (0.0, 4.0)], 4, 4);
    let img = supersampled(std::slice::from_ref(&sq), &s, 4);
    assert_eq!(&img.pixels[..4], &[R, [64, 0, 0], K, K]);
    assert_eq!(&img.edges[..4], &[false, true, false, false]);
    // K = 2: samples at X = 1.25 and 1.75, one of two columns: 2 of 4 samples, 127.5,
    // which rounds half up to 128.
    assert_eq!(
        &supersampled(&[sq], &s, 2).pixels[..4],
        &[R, [128, 0, 0], K, K]
    );
}

#[test]
fn one_sample_is_point_sampling() {
    // The penetrating scene and the small scenes above: K = 1 through the banded
    // renderer gives render_frame's pixels, and no edge pixels.
    let s = setup(40, 30);
    for polys in example("penetrating.txt")
        .iter()
        .chain(&example("cube.txt"))
    {
        let one = supersampled(polys, &s, 1);
        assert_eq!(one.pixels, render_frame(polys, &s, K).unwrap());
        assert!(one.edges.iter().all(|e| !e));
    }
}

#[test]
fn k_samples_are_the_box_filter_of_a_k_times_finer_screen() {
    // zspec --samples 4 at 20x20 against zspec at 80x80 with its vertices snapped to
    // the 20x20 screen's grid (1/256 of a 20x20 pixel), box-filtered; also for a
    // non-square screen (aspect 40/30 = 160/120 to the last bit).
    for (w, h) in [(20, 20), (40, 30)] {
        for polys in example("penetrating.txt")
            .iter()
            .chain(&example("concave.txt"))
        {
            let fine_setup = Setup {
                samples: 4,
                ..setup(4 * w, 4 * h)
            };
            let fine = render_frame(polys, &fine_setup, K).unwrap();
            let ss = supersampled(polys, &setup(w, h), 4);
            assert_eq!(ss.pixels, box_filter(&fine, w, h, 4), "{w}x{h}");
            assert!(ss.edges.iter().any(|&e| e), "the scene has edges");
        }
    }
}

#[test]
fn bands_change_nothing() {
    // Bands of one sample row, of three (not a multiple of K = 4), and the whole screen.
    let polys = &example("penetrating.txt")[0];
    let s = setup(20, 20);
    let mut frame = SupersampledFrame::new(&s, 4, K).unwrap();
    let mut results = Vec::new();
    for band in [1, 3 * 80, 80 * 80] {
        for p in polys {
            frame.draw(p).unwrap();
        }
        results.push(frame.finish_in_bands(band));
    }
    assert_eq!(results[0], results[2]);
    assert_eq!(results[1], results[2]);
    // finish() emptied the frame each time: nothing left to draw.
    assert_eq!(frame.finish().pixels, vec![K; 400]);
}

#[test]
fn one_colour_either_side_of_a_shared_edge_is_no_edge() {
    // Two red triangles sharing the diagonal: every sample is red, so no pixel is an
    // edge pixel and no background shows through the seam.
    let s = setup(4, 4);
    let upper = poly(R, &[(0.0, 0.0), (4.0, 0.0), (4.0, 4.0)], 4, 4);
    let lower = poly(R, &[(0.0, 0.0), (4.0, 4.0), (0.0, 4.0)], 4, 4);
    let img = supersampled(&[upper, lower], &s, 16);
    assert_eq!(img.pixels, vec![R; 16]);
    assert_eq!(img.edges, vec![false; 16]);
    assert_eq!(img.edge_mask(), vec![[0, 0, 0]; 16]);
}

#[test]
fn sample_counts_out_of_range_are_refused() {
    let s = setup(4, 4);
    let msg = |k, s: &Setup| format!("{:#}", SupersampledFrame::new(s, k, K).err().unwrap());
    assert!(msg(0, &s).contains("K must be from 1 to 256"));
    assert!(msg(257, &s).contains("K must be from 1 to 256"));
    assert!(msg(256, &setup(1 << 25, 1)).contains("too many samples"));
}

proptest! {
    /// Any few triangles and quads at any depths, any K from 1 to 5 and any band: the
    /// supersampled frame is the box filter of the point-sampled K times finer frame,
    /// and the edge pixels are exactly the blocks of that frame that hold two colours.
    #[test]
    fn supersampling_is_the_finer_point_rule_box_filtered(
        shapes in prop::collection::vec(
            (prop::collection::vec((-2i32..=26, -2i32..=26), 3..=4), 4u32..28, 0usize..3),
            1..5),
        k in 1u32..=5,
        band in 1usize..2000,
    ) {
        let (w, h) = (6u32, 5u32);
        let colours = [R, G, B];
        let polys: Vec<Polygon> = shapes.iter().map(|(pts, z, c)| {
            // Corners in quarter pixels, so that edges and vertices fall on samples.
            let pts: Vec<(f64, f64)> = pts.iter().map(|&(x, y)| (x as f64 / 4.0, y as f64 / 4.0)).collect();
            poly_at(colours[*c], &pts, *z as f64, w, h)
        }).collect();
        // The finer frame with its vertices snapped on the pixel screen's grid, as the
        // samples' are.
        let fine_setup = Setup { samples: k, ..setup(k * w, k * h) };
        let fine = render_frame(&polys, &fine_setup, K).unwrap();
        let mut frame = SupersampledFrame::new(&setup(w, h), k, K).unwrap();
        for p in &polys {
            frame.draw(p).unwrap();
        }
        let ss = frame.finish_in_bands(band);
        prop_assert_eq!(&ss.pixels, &box_filter(&fine, w, h, k));
        let (fw, k) = ((k * w) as usize, k as usize);
        for r in 0..h as usize {
            for c in 0..w as usize {
                let first = fine[r * k * fw + c * k];
                let mixed = (0..k).any(|j| (0..k).any(|i| fine[(r * k + j) * fw + c * k + i] != first));
                prop_assert_eq!(ss.edges[r * w as usize + c], mixed);
            }
        }
    }
}

// ---- Error measures -------------------------------------------------------------------

fn image(w: u32, h: u32, pixels: Vec<Colour>) -> Image {
    Image {
        width: w,
        height: h,
        pixels,
    }
}

#[test]
fn metrics_of_hand_made_frames() {
    // Two pixels differ: by 10 in blue, and by (3, 4, 0).
    // Σ² = 100 + 9 + 16 = 125 over 4 pixels × 3 channels: RMSE √(125/12) = 3.2275…
    let a = image(2, 2, vec![R, G, B, K]);
    let b = image(2, 2, vec![R, G, [0, 0, 245], [3, 4, 0]]);
    let m = metrics(&a, &b, None).unwrap();
    assert_eq!(
        m,
        Metrics {
            pixels: 4,
            differing: 2,
            sum_squared: 125,
            max_error: 10,
            edges: None
        }
    );
    assert_eq!(m.differing_fraction(), 0.5);
    assert_eq!(m.rmse(), (125.0f64 / 12.0).sqrt());
    assert_eq!(m.edge_rmse(), None);
    assert_eq!(
        m.pairs(),
        "pixels 4 differing 2 differing_fraction 0.500000 rmse 3.227486 max 10"
    );
    assert_eq!(m.csv_row("0"), "0,4,2,0.500000,3.227486,10,,");
    // The measures are symmetric.
    assert_eq!(metrics(&b, &a, None).unwrap(), m);
    // Edge pixels: the blue one and an unchanged one. Edge Σ² = 100 over 2 pixels:
    // √(100/6) = 4.0824…
    let flags = [false, true, true, false];
    let e = metrics(&a, &b, Some(&flags)).unwrap();
    assert_eq!(
        e.edges,
        Some(EdgeError {
            pixels: 2,
            sum_squared: 100
        })
    );
    assert_eq!(e.edge_rmse(), Some((100.0f64 / 6.0).sqrt()));
    assert_eq!(
        e.pairs(),
        "pixels 4 differing 2 differing_fraction 0.500000 rmse 3.227486 max 10 \
         edge_pixels 2 edge_rmse 4.082483"
    );
    assert_eq!(e.csv_row("3"), "3,4,2,0.500000,3.227486,10,2,4.082483");
    // A frame against itself: nothing, and no edge pixels flagged gives no edge RMSE.
    let same = metrics(&a, &a, Some(&[false; 4])).unwrap();
    assert_eq!(
        (same.differing, same.sum_squared, same.max_error),
        (0, 0, 0)
    );
    assert_eq!(same.edge_rmse(), None);
    assert!(same.pairs().ends_with("max 0 edge_pixels 0 edge_rmse -"));
    assert_eq!(
        same.csv_row("overall"),
        "overall,4,0,0.000000,0.000000,0,0,"
    );
}

#[test]
fn a_full_scale_error_is_255() {
    // Black against white everywhere: every channel off by 255, RMSE exactly 255.
    let m = metrics(
        &image(1, 2, vec![K; 2]),
        &image(1, 2, vec![[255; 3]; 2]),
        None,
    )
    .unwrap();
    assert_eq!(
        (m.differing_fraction(), m.rmse(), m.max_error),
        (1.0, 255.0, 255)
    );
}

#[test]
fn overall_metrics_pool_the_pixels_of_all_frames() {
    let a = [image(2, 1, vec![K, K]), image(1, 1, vec![K])];
    let b = [
        image(2, 1, vec![K, [6, 0, 0]]),
        image(1, 1, vec![[0, 0, 3]]),
    ];
    let masks = [image(2, 1, vec![[255; 3], [255; 3]]), image(1, 1, vec![K])];
    let frames = metrics_streams(&a, &b, Some(&masks)).unwrap();
    assert_eq!(frames[0].edge_rmse(), Some((36.0f64 / 6.0).sqrt()));
    assert_eq!(frames[1].edge_rmse(), None);
    let all = Metrics::overall(&frames);
    // 3 pixels, 2 differ, Σ² = 36 + 9 over 9 channels; edges: the 2 pixels of frame 0.
    assert_eq!(
        all,
        Metrics {
            pixels: 3,
            differing: 2,
            sum_squared: 45,
            max_error: 6,
            edges: Some(EdgeError {
                pixels: 2,
                sum_squared: 36
            })
        }
    );
    assert_eq!(all.rmse(), 5.0f64.sqrt());
    assert_eq!(Metrics::overall(&[]), Metrics::default());
}

#[test]
fn metrics_refuse_what_does_not_match() {
    fn err<T>(r: crate::error::Result<T>) -> String {
        r.err().unwrap().to_string()
    }
    let a = image(2, 1, vec![K, K]);
    let tall = image(1, 2, vec![K, K]);
    assert_eq!(err(metrics(&a, &tall, None)), "the frames are 2x1 and 1x2");
    assert_eq!(
        err(metrics(&a, &a, Some(&[true]))),
        "1 edge flags for a 2x1 frame of 2 pixels"
    );
    let grey = image(2, 1, vec![K, [128; 3]]);
    assert_eq!(
        err(metrics_streams(
            std::slice::from_ref(&a),
            std::slice::from_ref(&a),
            Some(&[grey])
        )),
        "edge mask frame 0: pixel (1, 0) is [128, 128, 128]: an edge mask is black and white only"
    );
    assert_eq!(
        err(metrics_streams(std::slice::from_ref(&a), &[], None)),
        "the streams have 1 and 0 frames"
    );
    assert_eq!(
        err(metrics_streams(
            std::slice::from_ref(&a),
            std::slice::from_ref(&a),
            Some(&[])
        )),
        "the edge mask has 0 frames and the streams 1"
    );
    assert_eq!(
        err(metrics_streams(
            std::slice::from_ref(&a),
            std::slice::from_ref(&a),
            Some(&[tall])
        )),
        "edge mask frame 0: is 1x2, the frame 2x1"
    );
}
