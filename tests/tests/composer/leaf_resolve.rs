//! A leaf that resolves its own region (scan's RegionBuffer, `scanconv --resolve`) draws
//! what the thesis's one Z-buffer draws (zbuf's FrameBuffer fed every span): the same
//! picture for any polygons, ties to the earlier polygon, saturated depths and several
//! frames included. Its runs, placed without a depth test, give the FrameBuffer's bytes.

use proptest::prelude::*;
use proto::{Colour, Polygon};
use scan::{RegionBuffer, SpanWalker};
use zbuf::FrameBuffer;

/// 150×90 crosses tile boundaries at columns 64 and 128 and row 64.
const W: u32 = 150;
const H: u32 = 90;

/// A few colours, so that neighbouring pixels of different polygons often share one and
/// runs have to join (or not) across polygon and tile edges.
const PALETTE: [Colour; 4] = [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 0, 0]];

/// A span as zbuf receives it: row, columns, depth at column 0, step.
type Span = (u32, u32, u32, f64, f64);

/// The frame as zbuf draws it from every polygon's spans, numbered in order.
fn par_buff(fb: &mut FrameBuffer, polygons: &[(Colour, Vec<Span>)]) -> Vec<u8> {
    fb.clear();
    for (index, (colour, spans)) in polygons.iter().enumerate() {
        for &(y, x0, x1, z0, dz) in spans {
            fb.span(y, x0..x1, z0, dz, index as u32, *colour);
        }
    }
    fb.rgb().to_vec()
}

/// The frame as a leaf resolves it and zbuf places its runs; checks the runs are in row
/// order, disjoint, non-empty and maximal.
fn resolved(
    rb: &mut RegionBuffer,
    fb: &mut FrameBuffer,
    polygons: &[(Colour, Vec<Span>)],
) -> Vec<u8> {
    fb.clear();
    for (colour, spans) in polygons {
        for &(y, x0, x1, z0, dz) in spans {
            rb.span(y, x0..x1, z0, dz, *colour);
        }
    }
    let mut runs = vec![];
    rb.finish_frame(|r| {
        runs.push(r);
        Ok::<_, ()>(())
    })
    .unwrap();
    for pair in runs.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        assert!((a.y, a.x1) <= (b.y, b.x0), "{a:?} then {b:?}");
        assert!(
            a.y != b.y || a.x1 != b.x0 || a.colour != b.colour,
            "{a:?} and {b:?} not joined"
        );
    }
    for r in &runs {
        assert!(r.x0 < r.x1 && r.x1 <= W && r.y < H, "{r:?}");
        fb.paint(r.y, r.x0..r.x1, r.colour);
    }
    fb.rgb().to_vec()
}

/// The spans of screen polygons, by the shared scan conversion.
fn spans_of(polygons: &[Polygon]) -> Vec<(Colour, Vec<Span>)> {
    let mut walker = SpanWalker::new();
    polygons
        .iter()
        .map(|p| {
            let mut spans = vec![];
            walker.for_each_span(p, W, H, |s| spans.push((s.y, s.x0, s.x1, s.z_row, s.dz)));
            (p.colour, spans)
        })
        .collect()
}

/// A screen polygon: 3–6 vertices reaching past the screen, in one of a few planes
/// (two level ones at depths 0.25 and 0.5 that tie often, and tilted ones).
fn polygon() -> impl Strategy<Value = Polygon> {
    (
        0usize..4,
        prop::collection::vec((-10.0f64..160.0, -10.0f64..100.0), 3..7),
        0usize..4,
    )
        .prop_map(|(colour, points, plane)| {
            let depth = |x: f64, y: f64| match plane {
                0 => 0.25,
                1 => 0.5,
                2 => 0.3 + x * 0.002 - y * 0.001,
                _ => 0.6 - x * 0.003 + y * 0.002,
            };
            let points: Vec<[f64; 3]> = points.iter().map(|&(x, y)| [x, y, depth(x, y)]).collect();
            Polygon::from_xyz(PALETTE[colour], &points)
        })
}

/// A depth or a step from the ends of the range, near zero, and within a few tie widths
/// of one another (so that the tie rule, not the order of depths, decides).
fn extreme() -> impl Strategy<Value = f64> {
    use proto::depth::TIE;
    prop_oneof![
        (-3i32..3).prop_map(f64::from),
        Just(f64::MAX),
        Just(-f64::MAX),
        Just(f64::MAX / 60.0),
        Just(-1e-300),
        any::<f64>().prop_filter("finite", |z| z.is_finite()),
        (0usize..5).prop_map(|k| -0.25 * (1.0 + [0.0, 0.5, 0.99, 1.01, 2.0][k] * TIE)),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    /// Random polygons, two frames through the same buffers: identical pictures.
    #[test]
    fn a_resolved_region_draws_what_the_one_z_buffer_draws(
        frames in prop::collection::vec(prop::collection::vec(polygon(), 0..12), 1..3),
    ) {
        let mut rb = RegionBuffer::new(W, H);
        let (mut whole, mut placed) = (FrameBuffer::new(W, H, [9, 9, 9]).unwrap(), FrameBuffer::new(W, H, [9, 9, 9]).unwrap());
        for polygons in &frames {
            let spans = spans_of(polygons);
            prop_assert_eq!(resolved(&mut rb, &mut placed, &spans), par_buff(&mut whole, &spans));
        }
    }

    /// Spans at the ends of the depth range, stepping out of it, and near ties: the leaf
    /// decides as zbuf does.
    #[test]
    fn extreme_depths_and_ties_resolve_as_in_zbuf(
        polygons in prop::collection::vec(
            (0usize..4, prop::collection::vec((0u32..H, 0u32..W, 1u32..140, extreme(), extreme()), 1..6)),
            1..10,
        ),
    ) {
        let spans: Vec<(Colour, Vec<Span>)> = polygons
            .into_iter()
            .map(|(c, s)| (PALETTE[c], s.into_iter().map(|(y, x0, len, z0, dz)| (y, x0, (x0 + len).min(W), z0, dz)).collect()))
            .collect();
        let mut rb = RegionBuffer::new(W, H);
        let (mut whole, mut placed) = (FrameBuffer::new(W, H, [0, 0, 0]).unwrap(), FrameBuffer::new(W, H, [0, 0, 0]).unwrap());
        prop_assert_eq!(resolved(&mut rb, &mut placed, &spans), par_buff(&mut whole, &spans));
    }
}
