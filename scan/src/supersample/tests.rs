use super::*;
/// The exact K×K reference.
use crate::fine::supersampled_image as reference;
use crate::frame::{image_of, square, zbuffer_image};
use proptest::prelude::*;
use proto::DVec4;

fn render(polys: &[Polygon], w: u32, h: u32, k: u32, bg: Colour) -> Vec<Option<Colour>> {
    let mut runs = Vec::new();
    let mut ss = Supersample::new(k, bg).unwrap();
    ss.resolve(polys, w, h, &mut runs);
    image_of(&runs, w, h)
}

fn tri(colour: Colour, pts: [[f64; 3]; 3]) -> Polygon {
    Polygon::from_xyz(colour, &pts)
}

#[test]
fn k_must_be_a_power_of_two_up_to_16() {
    assert!(Supersample::new(3, [0; 3]).is_err());
    assert!(Supersample::new(32, [0; 3]).is_err());
    assert!(Supersample::new(0, [0; 3]).is_err());
    let e = Supersample::new(6, [0; 3]).err().unwrap();
    assert!(
        e.starts_with("6 samples a side: K must be 1, 2, 4, 8 or 16"),
        "{e}"
    );
    for k in [1, 2, 4, 8, 16] {
        assert!(Supersample::new(k, [0; 3]).is_ok());
    }
}

#[test]
fn half_a_pixel_is_half_the_colour() {
    // White over the left half of pixel (0, 0) on black, 4×4 samples: 8 of 16 covered.
    let sq = square([255, 255, 255], 0.0, 0.0, 0.5, 1.0, 0.5);
    let image = render(std::slice::from_ref(&sq), 2, 1, 4, [0; 3]);
    assert_eq!(image, vec![Some([128; 3]), None]);
    // On a grey background the uncovered half counts as grey: (8·255 + 8·100 + 8)/16.
    let image = render(&[sq], 2, 1, 4, [100; 3]);
    assert_eq!(image, vec![Some([178; 3]), None]);
}

#[test]
fn k_1_is_point_sampling() {
    let polys = [
        tri(
            [200, 0, 0],
            [[0.3, 0.2, 0.5], [7.6, 1.1, 0.2], [2.2, 6.9, 0.8]],
        ),
        tri(
            [0, 200, 0],
            [[1.3, 5.2, 0.3], [6.6, 0.1, 0.6], [7.2, 7.9, 0.1]],
        ),
    ];
    assert_eq!(render(&polys, 8, 8, 1, [0; 3]), zbuffer_image(&polys, 8, 8));
}

#[test]
fn recorded_planes_are_scaled_with_the_screen() {
    // Two squares crossing in depth along X = 2: the recorded planes decide.
    let mut a = Polygon::from_xyz(
        [255, 0, 0],
        &[
            [0.0, 0.0, 0.0],
            [4.0, 0.0, 1.0],
            [4.0, 2.0, 1.0],
            [0.0, 2.0, 0.0],
        ],
    );
    a.plane = Some(DVec4::new(0.25, 0.0, -1.0, 0.0)); // Z = X/4
    let mut b = Polygon::from_xyz(
        [0, 0, 255],
        &[
            [0.0, 0.0, 1.0],
            [4.0, 0.0, 0.0],
            [4.0, 2.0, 0.0],
            [0.0, 2.0, 1.0],
        ],
    );
    b.plane = Some(DVec4::new(-0.25, 0.0, -1.0, 1.0)); // Z = 1 − X/4
    let polys = [a, b];
    for k in [2, 4, 8] {
        let image = render(&polys, 4, 2, k, [0; 3]);
        assert_eq!(image, reference(&polys, 4, 2, k, [0; 3]), "K = {k}");
        assert_eq!(image[0], Some([255, 0, 0]));
        assert_eq!(image[3], Some([0, 0, 255]));
    }
}

fn polygon_strategy() -> impl Strategy<Value = Polygon> {
    (
        prop::collection::vec((-3.0f64..13.0, -3.0f64..11.0), 3..7),
        (0.0f64..1.0, -0.1f64..0.1, -0.1f64..0.1),
        prop::sample::select(vec![[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]]),
        any::<bool>(),
    )
        .prop_map(|(pts, (z0, zx, zy), colour, flat)| {
            // Quarter-pixel coordinates meet sample lines and other polygons' edges.
            let q = |v: f64| if flat { (v * 4.0).round() / 4.0 } else { v };
            let pts: Vec<[f64; 3]> = pts
                .iter()
                .map(|&(x, y)| {
                    let (x, y) = (q(x), q(y));
                    [x, y, if flat { z0 } else { z0 + zx * x + zy * y }]
                })
                .collect();
            Polygon::from_xyz(colour, &pts)
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// Supersampling is the z-buffer of the K-times-finer screen, box-filtered: overlaps,
    /// interpenetration, equal depths, concave and self-intersecting polygons, slivers.
    #[test]
    fn equals_the_fine_zbuffer_box_filtered(
        polys in prop::collection::vec(polygon_strategy(), 1..7),
        k in prop::sample::select(vec![1u32, 2, 4, 8]),
        bg in prop::sample::select(vec![[0u8; 3], [10, 20, 30]]),
    ) {
        let (w, h) = (10, 8);
        prop_assert_eq!(render(&polys, w, h, k, bg), reference(&polys, w, h, k, bg));
    }
}

/// The runs and stats of whole (`adaptive` false) or adaptive K×K supersampling.
fn resolved(
    polys: &[Polygon],
    (w, h): (u32, u32),
    k: u32,
    bg: Colour,
    adaptive: bool,
) -> (Vec<Run>, Stats) {
    let mut runs = Vec::new();
    let mut ss = Supersample::new(k, bg).unwrap();
    if adaptive {
        ss = ss.adaptive();
    }
    ss.resolve(polys, w, h, &mut runs);
    (runs, ss.stats)
}

/// The frame and stats of adaptive K×K supersampling.
fn adaptive(polys: &[Polygon], w: u32, h: u32, k: u32, bg: Colour) -> (Vec<Option<Colour>>, Stats) {
    let (runs, stats) = resolved(polys, (w, h), k, bg, true);
    (image_of(&runs, w, h), stats)
}

/// A square of one depth plane `z = z0 + zx·X` over x0..x1 × y0..y1.
fn slab(colour: Colour, [x0, y0, x1, y1]: [f64; 4], z0: f64, zx: f64) -> Polygon {
    let z = |x: f64| z0 + zx * x;
    Polygon::from_xyz(
        colour,
        &[
            [x0, y0, z(x0)],
            [x1, y0, z(x1)],
            [x1, y1, z(x1)],
            [x0, y1, z(x0)],
        ],
    )
}

#[test]
fn adaptive_samples_only_the_pixels_edges_and_crossings_touch() {
    // A square over pixels 2.5..13.5 in front of a smaller one whose edges it hides:
    // only the front square's outline ring is sampled (12 pixels a side, 44 in all).
    let front = slab([255, 0, 0], [2.5, 2.5, 13.5, 13.5], 0.2, 0.0);
    let hidden = slab([0, 0, 255], [4.25, 5.5, 10.75, 9.5], 0.6, 0.0);
    for k in [2, 4, 8, 16] {
        for polys in [
            [front.clone(), hidden.clone()],
            [hidden.clone(), front.clone()],
        ] {
            let (image, stats) = adaptive(&polys, 16, 16, k, [0; 3]);
            assert_eq!(image, render(&polys, 16, 16, k, [0; 3]), "K = {k}");
            assert_eq!(stats.sampled, 44, "K = {k}");
            assert_eq!(stats.pixels, 144);
        }
    }
    // The hidden square in front instead: its edges are seen, and sampled too (7 × 4 + 2
    // rings' corners: columns 4 and 10, rows 5 and 9 of the smaller square's outline).
    let (image, stats) = adaptive(
        &[
            front.clone(),
            slab([0, 0, 255], [4.25, 5.5, 10.75, 9.5], 0.1, 0.0),
        ],
        16,
        16,
        4,
        [0; 3],
    );
    assert_eq!(image[7 * 16 + 7], Some([0, 0, 255]));
    assert_eq!(stats.sampled, 44 + 2 * 7 + 2 * 3);
    // Two screen-filling planes crossing along X = 8.5: only column 8 is sampled.
    let a = slab([255, 255, 255], [0.0, 0.0, 16.0, 16.0], 0.5, 0.01);
    let b = slab([0, 255, 0], [0.0, 0.0, 16.0, 16.0], 0.67, -0.01);
    for k in [2, 4, 8, 16] {
        let (image, stats) = adaptive(&[a.clone(), b.clone()], 16, 16, k, [0; 3]);
        assert_eq!(image, render(&[a.clone(), b.clone()], 16, 16, k, [0; 3]));
        assert_eq!(stats.sampled, 16, "K = {k}");
        assert_eq!(image[3 * 16 + 2], Some([255; 3]));
        assert_eq!(image[3 * 16 + 12], Some([0, 255, 0]));
    }
    // One plane on the other (equal depths everywhere): the tie is for the samples.
    let (image, stats) = adaptive(&[a.clone(), a.clone()], 16, 16, 4, [0; 3]);
    assert_eq!(image, render(&[a.clone(), a], 16, 16, 4, [0; 3]));
    assert_eq!(stats.sampled, 256);
}

#[test]
fn squares_on_pixel_boundaries_are_never_sampled() {
    // Every pixel such a square touches it covers wholly: alone, abutting another (a
    // shared edge on a pixel boundary), or overlapping one at another depth, on either
    // side of it in the stream; and the runs are whole supersampling's, one for one.
    let near = slab([255, 0, 0], [2.0, 2.0, 8.0, 9.0], 0.2, 0.0);
    let far = slab([0, 0, 255], [5.0, 4.0, 12.0, 12.0], 0.6, 0.0);
    let beside = slab([0, 255, 0], [8.0, 2.0, 11.0, 4.0], 0.4, 0.0);
    for k in [1, 2, 4, 16] {
        for polys in [
            vec![near.clone()],
            vec![near.clone(), beside.clone()],
            vec![near.clone(), far.clone(), beside.clone()],
            vec![far.clone(), beside.clone(), near.clone()],
        ] {
            let (runs, stats) = resolved(&polys, (16, 14), k, [0; 3], true);
            assert_eq!(
                runs,
                resolved(&polys, (16, 14), k, [0; 3], false).0,
                "K = {k}"
            );
            assert!(runs.iter().all(|r| r.x0 < r.x1), "K = {k}: {runs:?}");
            assert_eq!(stats.sampled, 0, "K = {k}");
        }
    }
    // The near square's pixels are red, the far one's own blue, in the same order.
    let image = adaptive(&[far.clone(), near.clone()], 16, 14, 4, [0; 3]).0;
    assert_eq!(image[5 * 16 + 6], Some([255, 0, 0]));
    assert_eq!(image[10 * 16 + 10], Some([0, 0, 255]));
}

/// Larger polygons than [`polygon_strategy`]'s, so that most pixels are inside one:
/// depths from a few planes (coplanar overlaps and equal depths), some tilted across
/// each other (crossings), some nearer than the tie rule tells apart.
fn big_polygon_strategy() -> impl Strategy<Value = Polygon> {
    (
        prop::collection::vec((-6.0f64..30.0, -6.0f64..22.0), 3..6),
        (
            prop::sample::select(vec![0.25, 0.5, 0.5 + 1e-12, 0.75]),
            prop::sample::select(vec![0.0, 0.02, -0.03]),
            prop::sample::select(vec![0.0, 0.01, -0.02]),
        ),
        prop::sample::select(vec![[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]]),
        any::<bool>(),
    )
        .prop_map(|(pts, (z0, zx, zy), colour, grid)| {
            // Quarter-pixel corners put edges on sample lines and pixel boundaries.
            let q = |v: f64| if grid { (v * 4.0).round() / 4.0 } else { v };
            let pts: Vec<[f64; 3]> = pts
                .iter()
                .map(|&(x, y)| {
                    let (x, y) = (q(x), q(y));
                    [x, y, z0 + zx * (x - 12.0) + zy * (y - 8.0)]
                })
                .collect();
            Polygon::from_xyz(colour, &pts)
        })
}

/// A Gouraud-shaded triangle: random vertex colours.
fn gouraud_strategy() -> impl Strategy<Value = Polygon> {
    (
        big_polygon_strategy(),
        prop::collection::vec((0.0f64..=255.0, 0.0f64..=255.0, 0.0f64..=255.0), 3),
    )
        .prop_map(|(mut p, colours)| {
            p.vertices.truncate(3);
            p.vertex_attrs = colours
                .iter()
                .map(|&(r, g, b)| proto::DVec3::new(r, g, b))
                .collect();
            p
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// Adaptive supersampling is whole supersampling byte for byte on flat polygons:
    /// overlaps, hidden edges, crossings, equal and near-equal depths, concave and
    /// self-intersecting polygons, at every K.
    #[test]
    fn adaptive_is_whole_supersampling_on_flat_polygons(
        polys in prop::collection::vec(big_polygon_strategy(), 1..9),
        small in prop::collection::vec(polygon_strategy(), 0..3),
        k in prop::sample::select(vec![1u32, 2, 4, 8, 16]),
        bg in prop::sample::select(vec![[0u8; 3], [10, 20, 30]]),
    ) {
        let polys: Vec<Polygon> = polys.into_iter().chain(small).collect();
        let (w, h) = (24, 16);
        // The same runs, one for one (so the same image).
        prop_assert_eq!(
            resolved(&polys, (w, h), k, bg, true).0,
            resolved(&polys, (w, h), k, bg, false).0
        );
    }

    /// A cluster of touches in depth order, counted front to back, draws what the sweep
    /// draws and finds the same pixels uniform: the same runs and the same counts of
    /// pixels, mixed pixels and sampled ones as with every cluster swept.
    #[test]
    fn ordered_clusters_count_what_the_sweep_finds(
        polys in prop::collection::vec(big_polygon_strategy(), 1..9),
        small in prop::collection::vec(polygon_strategy(), 0..3),
        k in prop::sample::select(vec![1u32, 2, 4, 8]),
        bg in prop::sample::select(vec![[0u8; 3], [10, 20, 30]]),
    ) {
        let polys: Vec<Polygon> = polys.into_iter().chain(small).collect();
        let mut swept = Supersample::new(k, bg).unwrap().adaptive();
        swept.ordered_clusters = false;
        let (mut want, mut got) = (Vec::new(), Vec::new());
        swept.resolve(&polys, 24, 16, &mut want);
        let (runs, stats) = resolved(&polys, (24, 16), k, bg, true);
        got.extend(runs);
        prop_assert_eq!(got, want);
        prop_assert_eq!(stats, swept.stats);
    }

    /// Under Gouraud shading a pixel one polygon wins takes the mean of its central 2×2
    /// samples: within one level of all K² samples' mean in every channel (both are
    /// within half a level of the affine colour's mean, which the central four share).
    #[test]
    fn adaptive_gouraud_is_within_a_level_of_whole_supersampling(
        polys in prop::collection::vec(gouraud_strategy(), 1..5),
        k in prop::sample::select(vec![2u32, 4, 8, 16]),
    ) {
        let (w, h) = (24, 16);
        let (image, _) = adaptive(&polys, w, h, k, [0; 3]);
        let whole = render(&polys, w, h, k, [0; 3]);
        for (got, want) in image.iter().zip(&whole) {
            match (got, want) {
                (Some(g), Some(w)) => {
                    let d = (0..3).map(|c| g[c].abs_diff(w[c])).max().unwrap();
                    prop_assert!(d <= 1 || k == 2 && d == 0, "{:?} against {:?}", g, w);
                }
                _ => prop_assert_eq!(got, want),
            }
        }
        if k == 2 {
            prop_assert_eq!(image, whole);
        }
    }
}
