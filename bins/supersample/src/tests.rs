use super::*;
use proptest::prelude::*;
use proto::DVec4;
/// The exact K×K reference.
use scan::fine::supersampled_image as reference;
use scan::frame::{image_of, square, zbuffer_image};

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
