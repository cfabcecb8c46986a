use super::list::FULL;
use super::*;
/// The exact K×K reference.
use crate::fine::supersampled_image as reference;
use crate::frame::{image_of, square};
use proptest::prelude::*;
use proto::DVec4;

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
    let near = square(RED, 0.0, 0.0, 0.5, 1.0, 0.2);
    let far = square(BLUE, 0.0, 0.0, 1.0, 0.5, 0.6);
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
    let sq = square(RED, 0.0, 0.0, 3.0, 3.0, 0.5);
    let behind = square(BLUE, 0.0, 0.0, 3.0, 3.0, 0.7);
    let (image, stats) = render_with(&[sq.clone(), behind.clone()], 3, 3, [0; 3]);
    assert_eq!(image, vec![Some(RED); 9]);
    // The square behind is culled row by row: its fragments are never made.
    assert_eq!((stats.simple, stats.lists, stats.hidden), (9, 0, 0));
    let mut runs = Vec::new();
    let mut a = ABuffer::new([0; 3]);
    a.resolve(&[sq.clone(), behind.clone()], 3, 3, &mut runs);
    assert_eq!((a.rows_culled, a.blocks_culled), (3, 0));
    // Without the cull they are made and thrown away behind the full fragments (6.3.5).
    let mut b = ABuffer::without_cull([0; 3]);
    let mut uncut = Vec::new();
    b.resolve(&[sq, behind], 3, 3, &mut uncut);
    assert_eq!(uncut, runs);
    assert_eq!((b.stats.simple, b.stats.hidden, b.rows_culled), (9, 9, 0));
}

/// Two constant depths within the tie rule's width (2⁻³⁰ of the depth), the later polygon
/// the nearer: the earlier keeps every sample, as the z-buffer and the K×K reference keep
/// it, whether the pixel is covered wholly or in part, with and without the cull. The
/// a-buffer ordered them nearest-first and shared their samples (the differential suite's
/// seed 12, and 72 of 3,000 seeds from 1000).
#[test]
fn depths_within_the_tie_go_to_the_earlier_polygon() {
    let z = 0.431_761_162_708_381_4;
    let nearer = z - 5.0e-11;
    assert!(!proto::depth::takes(nearer, z) && nearer < z);
    let bg = [0, 200, 0];
    for (x1, y1) in [(2.0, 2.0), (1.5, 2.0), (2.0, 0.5)] {
        let early = square(BLUE, 0.0, 0.0, 2.0, 2.0, z);
        let late = square(RED, 0.0, 0.0, x1, y1, nearer);
        let polys = [early.clone(), late.clone()];
        let image = render(&polys, 2, 2, bg);
        assert_eq!(image, vec![Some(BLUE); 4], "{x1} {y1}");
        assert_eq!(image, reference(&polys, 2, 2, 8, bg), "{x1} {y1}");
        let mut b = ABuffer::without_cull(bg);
        let mut runs = Vec::new();
        b.resolve(&polys, 2, 2, &mut runs);
        assert_eq!(image_of(&runs, 2, 2), image, "{x1} {y1}");
        // The other way round the earlier is the nearer, and wins as before.
        let polys = [late, early];
        assert_eq!(render(&polys, 2, 2, bg), reference(&polys, 2, 2, 8, bg));
    }
}

#[test]
fn insertion_cases_keep_the_list_sorted_and_hide_what_is_behind() {
    let frag = |mask, z: i32, order| Fragment {
        colour: [order as u8; 3],
        mask,
        zmin: z as f64,
        zmax: z as f64 + 10.0,
        order,
        opacity: proto::OPAQUE,
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
        opacity: proto::OPAQUE,
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
        opacity: proto::OPAQUE,
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

#[test]
fn a_list_past_its_cap_merges_its_farthest_fragments() {
    // 100 rectangles over the left half of one pixel, at 100 depths in a shuffled
    // order, each its own colour: masks that neither combine nor cover the pixel.
    let polys: Vec<Polygon> = (0..100u32)
        .map(|k| {
            let i = (k * 37) % 100;
            let z = 0.1 + 0.008 * i as f64;
            quad(
                [i as u8 * 2, 100, 255 - i as u8],
                [[0.0, 0.0, z], [0.5, 0.0, z], [0.5, 1.0, z], [0.0, 1.0, z]],
            )
        })
        .collect();
    let (image, stats) = render_with(&polys, 1, 1, [0; 3]);
    assert_eq!(stats.max_list, list::MAX_LIST as u64);
    assert_eq!(stats.merged, 100 - list::MAX_LIST as u64);
    // The nearest (i = 0) shows on its 32 samples, the background on the rest.
    assert_eq!(image, vec![Some([0, 50, 128])]);
}

#[test]
fn merge_behind_keeps_the_nearer_colour_where_both_cover() {
    use list::Fragment;
    let near = Fragment {
        colour: [200, 0, 0],
        mask: 0xFFFF_FFFF,
        zmin: 10.0,
        zmax: 20.0,
        order: 3,
        opacity: proto::OPAQUE,
    };
    let far = Fragment {
        colour: [0, 0, 100],
        mask: 0xFFFF_FFFF_0000_0000 | 0xFFFF,
        zmin: 15.0,
        zmax: 40.0,
        order: 1,
        opacity: proto::OPAQUE,
    };
    let m = near.merge_behind(&far);
    // 32 samples red, 32 blue: the mean.
    assert_eq!(m.colour, [100, 0, 50]);
    assert_eq!((m.mask, m.zmin, m.zmax, m.order), (u64::MAX, 10.0, 40.0, 3));
}

/// A polygon of `quad`'s with an opacity.
fn see_through(colour: Colour, opacity: u8, pts: [[f64; 3]; 4]) -> Polygon {
    let mut p = quad(colour, pts);
    p.opacity = opacity;
    p
}

/// The sampling thesis's eq. 6.5, front to back: two transparent layers over an opaque
/// one, each covering the whole pixel. Red (opacity 128) shows 128/255 of itself and
/// passes the rest to green (opacity 64), which passes the rest to blue.
#[test]
fn eq_6_5_two_transparent_layers_over_an_opaque_one() {
    let square = |z: f64| [[0.0, 0.0, z], [1.0, 0.0, z], [1.0, 1.0, z], [0.0, 1.0, z]];
    let polys = [
        see_through([255, 0, 0], 128, square(0.2)),
        see_through([0, 255, 0], 64, square(0.5)),
        quad([0, 0, 255], square(0.7)),
    ];
    let (a, b) = (128.0 / 255.0, 64.0 / 255.0);
    let want = [
        255.0 * a,
        255.0 * (1.0 - a) * b,
        255.0 * (1.0 - a) * (1.0 - b),
    ];
    let (image, stats) = render_with(&polys, 1, 1, [0; 3]);
    let got = image[0].expect("covered");
    for k in 0..3 {
        assert!(
            (got[k] as f64 - want[k]).abs() <= 0.5,
            "{got:?} against {want:?}"
        );
    }
    // Nothing is thrown away behind a transparent full fragment: a list of three.
    assert_eq!(stats.max_list, 3);
    // In any order of the stream, the same colour (the list is sorted by depth).
    let reversed: Vec<Polygon> = polys.iter().rev().cloned().collect();
    assert_eq!(render_with(&reversed, 1, 1, [0; 3]).0, image);
}

/// A transparent polygon crossing an opaque one inside a pixel: where the transparent one
/// is in front its samples blend, where it is behind the opaque one hides it. Half the
/// pixel each way, so the colour is the mean of the blend and the opaque colour.
#[test]
fn a_transparent_polygon_crossing_an_opaque_one_inside_a_pixel() {
    // Blue at depth 0.5 everywhere; red (opacity 128) from depth 0.3 on the left to 0.7
    // on the right: in front on the left half of the pixel, behind on the right.
    let polys = [
        square([0, 0, 255], 0.0, 0.0, 1.0, 1.0, 0.5),
        see_through(
            [255, 0, 0],
            128,
            [
                [0.0, 0.0, 0.3],
                [1.0, 0.0, 0.7],
                [1.0, 1.0, 0.7],
                [0.0, 1.0, 0.3],
            ],
        ),
    ];
    let a = 128.0 / 255.0;
    let blend = [255.0 * a, 0.0, 255.0 * (1.0 - a)];
    let want = [blend[0] / 2.0, 0.0, (blend[2] + 255.0) / 2.0];
    let got = render(&polys, 1, 1, [0; 3])[0].expect("covered");
    for k in 0..3 {
        assert!(
            (got[k] as f64 - want[k]).abs() <= 1.0,
            "{got:?} against {want:?}"
        );
    }
}

mod cull {
    use super::*;

    proptest! {
        /// The cull leaves out only fragments the a-buffer would throw away: the same
        /// runs with and without it, on stacks of tilted and flat quads.
        #[test]
        fn the_cull_changes_no_pixel(
            quads in prop::collection::vec(
                ([0.0f64..20.0, 0.0f64..20.0, 2.0f64..24.0, 2.0f64..24.0], 0.0f64..1.0, -0.02f64..0.02, any::<u8>()),
                1..16,
            ),
        ) {
            let polys: Vec<Polygon> = quads
                .iter()
                .map(|&([x, y, dx, dy], z, g, c)| {
                    let d = |px: f64| z + g * px;
                    quad(
                        [c, 255 - c, 7],
                        [[x, y, d(x)], [x + dx, y, d(x + dx)], [x + dx, y + dy, d(x + dx)], [x, y + dy, d(x)]],
                    )
                })
                .collect();
            let (mut a, mut b) = (ABuffer::new([0; 3]), ABuffer::without_cull([0; 3]));
            let (mut ra, mut rb) = (Vec::new(), Vec::new());
            a.resolve(&polys, 32, 32, &mut ra);
            b.resolve(&polys, 32, 32, &mut rb);
            prop_assert_eq!(ra, rb);
        }
    }
}

#[test]
fn the_depth_extent_artefact_along_a_column() {
    // examples/screen/abuf-depth-extent.txt: a flat red rectangle (depth 2) ends at
    // X = 7.5, inside pixel column 7; a steep green plane crosses depth 2 at X = 7.55,
    // just outside it. Where both cover (X < 7.5) the green is behind everywhere, but
    // its fragment's depth extent in column 7 straddles the red's depth, so the packer
    // takes the two as crossing inside the pixel and gives green a share of the red's
    // samples: 48 levels of red too few, all down the column.
    let red = square([255, 40, 40], 0.0, 0.0, 7.5, 16.0, 2.0);
    let green = quad(
        [40, 200, 40],
        [
            [0.0, 0.0, 2.3775],
            [16.0, 0.0, 1.5775],
            [16.0, 16.0, 1.5775],
            [0.0, 16.0, 2.3775],
        ],
    );
    let scene = [red, green];
    let (image, stats) = render_with(&scene, 16, 16, [0; 3]);
    let exact = reference(&scene, 16, 16, 8, [0; 3]);
    for y in 0..16 {
        let at = y * 16 + 7;
        assert_eq!(exact[at], Some([148, 120, 40]), "row {y}");
        assert_eq!(image[at], Some([100, 155, 40]), "row {y}");
        // Every other column is exact.
        for x in (0..16).filter(|&x| x != 7) {
            assert_eq!(image[y * 16 + x], exact[y * 16 + x], "({x}, {y})");
        }
    }
    assert_eq!(stats.intersections, 16);
}

/// A Gouraud-shaded quadrilateral: its corners red, green, blue and grey.
fn shaded_quad(pts: [[f64; 3]; 4]) -> Polygon {
    let mut p = quad(WHITE, pts);
    p.vertex_attrs = [
        [250.0, 10.0, 0.0],
        [0.0, 240.0, 20.0],
        [30.0, 0.0, 255.0],
        [128.0, 128.0, 128.0],
    ]
    .map(proto::DVec3::from)
    .to_vec();
    p
}

/// A shaded polygon's fragment has its colour at the pixel centre (one colour a
/// fragment): a pixel it covers wholly is exactly that colour, the z-buffer's; an edge
/// pixel is that colour over its covered samples and the background over the rest.
#[test]
fn a_shaded_fragment_has_its_colour_at_the_pixel_centre() {
    let p = shaded_quad([
        [0.3, 0.2, 0.5],
        [7.6, 0.2, 0.4],
        [7.6, 5.5, 0.6],
        [0.3, 5.5, 0.5],
    ]);
    let shading = proto::shade::Shading::of(&p, None).expect("shaded");
    let image = render(std::slice::from_ref(&p), 8, 6, [0; 3]);
    let mut distinct = std::collections::HashSet::new();
    for y in 1..5 {
        for x in 1..7 {
            let got = image[y * 8 + x].expect("covered");
            assert_eq!(got, shading.at(x as u32, y as u32), "pixel ({x}, {y})");
            distinct.insert(got);
        }
    }
    assert!(distinct.len() > 20, "{distinct:?}");
    // Pixel (0, 2): the samples at X = (i + ½)/8 ≥ 0.3 are covered, 6 of every 8.
    let got = image[2 * 8].expect("covered");
    let want = shading.at(0, 2).map(|c| c as f64 * 0.75);
    for k in 0..3 {
        assert!(
            (got[k] as f64 - want[k]).abs() <= 1.0,
            "{got:?} against {want:?}"
        );
    }
}

/// Transparency keeps working with shading: a shaded square of opacity 128 over an
/// opaque blue one blends its colour at each pixel centre with the blue by eq. 6.5.
#[test]
fn a_transparent_shaded_polygon_blends_its_colour_at_the_centre_by_eq_6_5() {
    let mut front = shaded_quad([
        [0.0, 0.0, 0.2],
        [6.0, 0.0, 0.2],
        [6.0, 4.0, 0.2],
        [0.0, 4.0, 0.2],
    ]);
    front.opacity = 128;
    let back = square(BLUE, 0.0, 0.0, 6.0, 4.0, 0.7);
    let shading = proto::shade::Shading::of(&front, None).expect("shaded");
    // Either order in the stream: the list is sorted by depth.
    for polys in [[front.clone(), back.clone()], [back, front]] {
        let image = render(&polys, 6, 4, [0; 3]);
        for y in 0..4 {
            for x in 0..6 {
                let c = shading.at(x, y);
                let got = image[(y * 6 + x) as usize].expect("covered");
                let a = 128.0 / 255.0;
                for k in 0..3 {
                    let want = c[k] as f64 * a + BLUE[k] as f64 * (1.0 - a);
                    assert!(
                        (got[k] as f64 - want).abs() <= 1.0,
                        "pixel ({x}, {y}): {got:?}, {c:?} over blue"
                    );
                }
            }
        }
    }
}
