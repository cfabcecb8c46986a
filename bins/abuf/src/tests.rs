use super::list::FULL;
use super::*;
use proptest::prelude::*;
use proto::DVec4;
/// The exact K×K reference.
use scan::fine::supersampled_image as reference;
use scan::frame::image_of;

fn render_with(polys: &[Polygon], w: u32, h: u32, bg: Colour) -> (Vec<Option<Colour>>, ListStats) {
    let mut runs = Vec::new();
    let mut a = ABuffer::new(bg);
    a.resolve(polys, w, h, &mut runs);
    (image_of(&runs, w, h), a.stats)
}

fn render(polys: &[Polygon], w: u32, h: u32, bg: Colour) -> Vec<Option<Colour>> {
    render_with(polys, w, h, bg).0
}

fn quad(colour: Colour, pts: [[f64; 3]; 4]) -> Polygon {
    Polygon::from_xyz(colour, &pts)
}

const RED: Colour = [255, 0, 0];
const BLUE: Colour = [0, 0, 255];
const WHITE: Colour = [255, 255, 255];

/// Sampling thesis figure 6.7: a near edge splits the pixel vertically in half, a far one
/// horizontally; the near fragment gives 50 %, the far one the 25 % not behind the near
/// one, the background the other 25 %.
#[test]
fn seed_figure_6_7_a_pixel_covered_50_25_25() {
    let near = quad(
        RED,
        [
            [0.0, 0.0, 0.2],
            [0.5, 0.0, 0.2],
            [0.5, 1.0, 0.2],
            [0.0, 1.0, 0.2],
        ],
    );
    let far = quad(
        BLUE,
        [
            [0.0, 0.0, 0.6],
            [1.0, 0.0, 0.6],
            [1.0, 0.5, 0.6],
            [0.0, 0.5, 0.6],
        ],
    );
    let bg = [0, 200, 0];
    for polys in [[near.clone(), far.clone()], [far, near]] {
        let (image, stats) = render_with(&polys, 1, 1, bg);
        // (32·255 + 32)/64, (16·200 + 32)/64, (16·255 + 32)/64.
        assert_eq!(image, vec![Some([128, 50, 64])]);
        assert_eq!(image, reference(&polys, 1, 1, 8, bg));
        let want16 = reference(&polys, 1, 1, 16, bg);
        assert_eq!(image, want16);
        assert_eq!((stats.fragments, stats.lists, stats.max_list), (2, 1, 2));
    }
}

/// The grey seam of sampling thesis 6.3: two white polygons sharing an edge on black. Mixing
/// each one's coverage into the frame buffer leaves the shared edge grey; the a-buffer's
/// masks give every sample on it to one polygon, and the two fragments of the one
/// surface combine into one fully covering fragment.
#[test]
fn seed_grey_seam_two_white_triangles_sharing_an_edge() {
    let a = Polygon::from_xyz(WHITE, &[[0.0, 0.0, 0.5], [4.0, 0.0, 0.5], [0.0, 3.0, 0.5]]);
    let b = Polygon::from_xyz(WHITE, &[[4.0, 0.0, 0.5], [4.0, 3.0, 0.5], [0.0, 3.0, 0.5]]);
    let (image, stats) = render_with(&[a.clone(), b.clone()], 4, 3, [0; 3]);
    assert_eq!(image, vec![Some(WHITE); 12]);
    assert_eq!(image, reference(&[a.clone(), b.clone()], 4, 3, 16, [0; 3]));
    assert!(stats.combined >= 4, "{stats:?}");
    // Sloping in depth too: the same.
    let slope = |p: &Polygon| {
        let mut p = p.clone();
        for v in &mut p.vertices {
            v.z = 0.1 + 0.05 * v.x + 0.1 * v.y;
        }
        p.plane = Some(DVec4::new(0.05, 0.1, -1.0, 0.1));
        p
    };
    let (image, _) = render_with(&[slope(&a), slope(&b)], 4, 3, [0; 3]);
    assert_eq!(image, vec![Some(WHITE); 12]);
}

/// Intersecting fragments: a red and a blue polygon crossing in depth at X = ½ inside the
/// one pixel, red in front on the left. The packer splits the samples both cover by
/// zmin/zmax: half each, as the exact reference has it.
#[test]
fn seed_intersecting_fragments_split_by_zmin_zmax() {
    let mut red = quad(
        RED,
        [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 0.0],
        ],
    );
    red.plane = Some(DVec4::new(1.0, 0.0, -1.0, 0.0)); // Z = X
    let mut blue = quad(
        BLUE,
        [
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 1.0],
        ],
    );
    blue.plane = Some(DVec4::new(-1.0, 0.0, -1.0, 1.0)); // Z = 1 − X
    let polys = [red.clone(), blue.clone()];
    let (image, stats) = render_with(&polys, 1, 1, [0; 3]);
    assert_eq!(image, vec![Some([128, 0, 128])]);
    assert_eq!(image, reference(&polys, 1, 1, 16, [0; 3]));
    assert_eq!(stats.intersections, 1);
    // Crossing at X = ¼ instead: red in front on a quarter. The estimate is a share of
    // the depth ranges, not of the area, and is near the reference's quarter.
    blue.plane = Some(DVec4::new(-1.0, 0.0, -1.0, 0.5)); // Z = ½ − X
    let polys = [red, blue];
    let (image, _) = render_with(&polys, 1, 1, [0; 3]);
    let want = reference(&polys, 1, 1, 16, [0; 3])[0].unwrap();
    let got = image[0].unwrap();
    assert_eq!(want, [64, 0, 191]);
    for ch in 0..3 {
        assert!(
            (got[ch] as i32 - want[ch] as i32).abs() <= 32,
            "{got:?} against {want:?}"
        );
    }
}

#[test]
fn a_fully_covered_pixel_needs_no_list() {
    let sq = quad(
        RED,
        [
            [0.0, 0.0, 0.5],
            [3.0, 0.0, 0.5],
            [3.0, 3.0, 0.5],
            [0.0, 3.0, 0.5],
        ],
    );
    let behind = quad(
        BLUE,
        [
            [0.0, 0.0, 0.7],
            [3.0, 0.0, 0.7],
            [3.0, 3.0, 0.7],
            [0.0, 3.0, 0.7],
        ],
    );
    let (image, stats) = render_with(&[sq, behind], 3, 3, [0; 3]);
    assert_eq!(image, vec![Some(RED); 9]);
    assert_eq!((stats.simple, stats.lists, stats.hidden), (9, 0, 9));
}

#[test]
fn insertion_cases_keep_the_list_sorted_and_hide_what_is_behind() {
    let frag = |mask, z: i32, order| Fragment {
        colour: [order as u8; 3],
        mask,
        zmin: z as f64,
        zmax: z as f64 + 10.0,
        order,
    };
    let (mut pool, mut stats) = (Vec::new(), ListStats::default());
    let mut p = PixelStruct::Empty;
    p.insert(frag(0xFF, 50, 0), &mut pool, &mut stats); // partial into empty: a list
    p.insert(frag(0xFF00, 20, 1), &mut pool, &mut stats); // partial into a list, in front
    p.insert(frag(FULL, 100, 2), &mut pool, &mut stats); // full, behind both
    p.insert(frag(0xF0, 200, 3), &mut pool, &mut stats); // behind the full one: thrown away
    let orders: Vec<u32> = p.fragments().iter().map(|f| f.order).collect();
    assert_eq!(orders, vec![1, 0, 2]);
    assert_eq!(stats.hidden, 1);
    p.insert(frag(FULL, 0, 4), &mut pool, &mut stats); // full in front of all: simple
    assert_eq!(p, PixelStruct::Simple(frag(FULL, 0, 4)));
    assert_eq!(stats.hidden, 4);
    p.insert(frag(0x1, 5, 5), &mut pool, &mut stats); // partial, intersecting the simple one
    assert_eq!(p.fragments().len(), 2);
    p.clear(&mut pool);
    assert_eq!(p, PixelStruct::Empty);
    assert_eq!(pool.len(), 1);
}

/// Found by fuzzing (fuzz/regressions/abuf): a fragment combined with its successor took
/// the smaller stream order of the two with the smaller zmin, a key before a full
/// fragment of the same zmin ahead of it, and the list was no longer sorted.
#[test]
fn a_combined_fragment_keeps_its_place() {
    let frag = |colour, mask, zmin: i32, zmax: i32, order| Fragment {
        colour,
        mask,
        zmin: zmin as f64,
        zmax: zmax as f64,
        order,
    };
    let (mut pool, mut stats) = (Vec::new(), ListStats::default());
    let mut p = PixelStruct::Empty;
    p.insert(frag(WHITE, FULL, 2, 8, 35331), &mut pool, &mut stats);
    p.insert(frag(BLUE, 0xFF00, 5, 15, 20225), &mut pool, &mut stats);
    p.insert(frag(BLUE, 0x00FF, 2, 6, 40000), &mut pool, &mut stats);
    assert_eq!(
        p.fragments(),
        &[
            frag(WHITE, FULL, 2, 8, 35331),
            frag(BLUE, 0xFFFF, 2, 15, 40000)
        ]
    );
    assert_eq!(stats.combined, 1);
}

/// Found by fuzzing (fuzz/artifacts/abuf): a fragment whose depths span a huge range (a
/// nearly edge-on plane) must still combine with a neighbour of one surface within that
/// extent.
#[test]
fn a_huge_depth_extent_still_combines() {
    let frag = |mask, zmin: f64, zmax: f64, order| Fragment {
        colour: BLUE,
        mask,
        zmin,
        zmax,
        order,
    };
    let (mut pool, mut stats) = (Vec::new(), ListStats::default());
    let mut p = PixelStruct::Empty;
    p.insert(frag(0x00FF, -1e300, 100.0, 1), &mut pool, &mut stats);
    p.insert(frag(0xFF00, 200.0, 200.0, 2), &mut pool, &mut stats);
    assert_eq!(p.fragments(), [frag(0xFFFF, -1e300, 200.0, 1)]);
}

fn polygon_strategy(flat: bool) -> impl Strategy<Value = Polygon> {
    (
        prop::collection::vec((-2.0f64..10.0, -2.0f64..8.0), 3..7),
        (0u8..4, -0.1f64..0.1, -0.1f64..0.1),
        prop::sample::select(vec![RED, BLUE, WHITE]),
    )
        .prop_map(move |(pts, (z0, zx, zy), colour)| {
            let z0 = 0.2 + 0.2 * z0 as f64;
            let pts: Vec<[f64; 3]> = pts
                .iter()
                .map(|&(x, y)| {
                    let (x, y) = ((x * 4.0).round() / 4.0, (y * 4.0).round() / 4.0);
                    [x, y, if flat { z0 } else { z0 + zx * x + zy * y }]
                })
                .collect();
            Polygon::from_xyz(colour, &pts)
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Where no fragments intersect in depth (every polygon at one depth, ties and all),
    /// the a-buffer is the 8×8 supersampled picture exactly.
    #[test]
    fn without_intersections_it_is_8x8_supersampling(
        polys in prop::collection::vec(polygon_strategy(true), 1..8),
        bg in prop::sample::select(vec![[0u8; 3], [10, 20, 30]]),
    ) {
        prop_assert_eq!(render(&polys, 8, 6, bg), reference(&polys, 8, 6, 8, bg));
    }

    /// Any polygons: every pixel a sample of which is covered is sent, once, and only
    /// those; colours are within the range of the colours present.
    #[test]
    fn sloped_polygons_cover_what_the_samples_cover(
        polys in prop::collection::vec(polygon_strategy(false), 1..8),
    ) {
        let got = render(&polys, 8, 6, [0; 3]);
        let want = reference(&polys, 8, 6, 8, [0; 3]);
        for (g, w) in got.iter().zip(&want) {
            prop_assert_eq!(g.is_some(), w.is_some());
        }
    }
}
