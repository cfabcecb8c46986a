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
    assert_eq!(agreed(&cmp, 16.0), Ok(()));
    assert_eq!(
        agreed(&cmp, 99.95),
        Err("1 of 1 frames agree on fewer than 99.95% of pixels (frames [0])".into())
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
fn a_polygon_projecting_beyond_f64_is_refused() {
    // x_e = 1.7e308 at the hither distance projects to about 2.7e308 · W/2: infinite.
    let s = setup(4, 4);
    let p = Polygon::from_xyz(
        R,
        &[[1.7e308, 0.0, 19.0], [0.0, 1.0, 19.0], [0.0, -1.0, 19.0]],
    );
    let e = render_frame(&[p], &s, K).unwrap_err();
    assert!(
        e.starts_with("polygon 0: a vertex projects to (inf, "),
        "{e}"
    );
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
