//! The whole-frame hidden-surface methods (docs/methods.md) on arbitrary frames of screen
//! polygons, some of them Gouraud-shaded (a colour a vertex, docs/DESIGN.md, "Shading"):
//! Watkins's scan line and Warnock's subdivision give the z-buffer's picture pixel for
//! pixel, shaded colours included, the painter (with and without its cuts, and with a cut budget of
//! one) covers exactly the z-buffer's pixels, the hidden-line solver does not panic and
//! keeps every piece (edges and lines of intersection) finite and within the polygons'
//! extent, and every
//! method's runs stay on the screen, each pixel at most once (`scan::frame::image_of`
//! checks both).
#![no_main]
use libfuzzer_sys::fuzz_target;
use methods::METHODS;
use polypipe_fuzz::{polygon, Bytes};
use proto::Vertex;
use scan::frame::{differing_pixels, image_of, zbuffer_image, HiddenSurface};

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes(data);
    let width = 1 + (b.u8() % 48) as u32;
    let height = 1 + (b.u8() % 48) as u32;
    let count = 1 + b.u8() % 8;
    let mut polygons = Vec::new();
    for _ in 0..count {
        // Screen vertices: X and Y mostly on a grid near the screen (shared edges, ties),
        // depth mostly from a few planes (equal depths), else anything finite.
        let mut poly = polygon(&mut b, |b| {
            let c = |b: &mut Bytes| {
                if b.u8() % 8 == 0 {
                    b.f64()
                } else {
                    b.grid() * 2.0 + 24.0
                }
            };
            let z = if b.u8() % 4 == 0 {
                b.coord()
            } else {
                (b.u8() % 4) as f64 * 0.25
            };
            Vertex::new(c(b), c(b), z, 1.0)
        });
        // Half the polygons Gouraud-shaded: any colour at each vertex.
        if b.u8() % 2 == 0 {
            poly.vertex_attrs = (0..poly.vertices.len())
                .map(|_| proto::DVec3::new(b.u8() as f64, b.u8() as f64, b.u8() as f64))
                .collect();
        }
        // The stages refuse a polygon far off the screen before any method sees it.
        if scan::check_on_screen(&poly, width, height).is_ok() {
            polygons.push(poly);
        }
    }
    let reference = zbuffer_image(&polygons, width, height);
    // Every exact row of the table of methods that names this target, held to the
    // z-buffer's picture pixel for pixel (a row added there without a resolver here
    // stops the fuzzer on its first input, by name).
    let mut runs = Vec::new();
    for row in METHODS
        .iter()
        .filter(|m| m.fuzz == Some("methods") && m.exact)
    {
        let mut method: Box<dyn HiddenSurface> = match row.name {
            "scanline" => Box::new(scanline::Scanline::default()),
            "warnock" => Box::new(warnock::Warnock::default()),
            other => panic!("fuzz target methods: no resolver for the exact row {other}"),
        };
        runs.clear();
        method.resolve(&polygons, width, height, &mut runs);
        let image = image_of(&runs, width, height);
        assert_eq!(differing_pixels(&image, &reference), 0, "{}", row.name);
    }
    // Hidden lines: no panic, and every piece (edges and lines of intersection) finite
    // and within the polygons' extent.
    let (lo, hi) = polygons.iter().flat_map(|p| &p.vertices).fold(
        (
            (f64::INFINITY, f64::INFINITY),
            (f64::NEG_INFINITY, f64::NEG_INFINITY),
        ),
        |(l, h), v| ((l.0.min(v.x), l.1.min(v.y)), (h.0.max(v.x), h.1.max(v.y))),
    );
    let mut line_stats = hiddenline::LineStats::default();
    hiddenline::for_each_segment(&polygons, width, height, &mut line_stats, |s| {
        for q in [s.from, s.to] {
            let slack = 1e-6 * (1.0 + q.x.abs().max(q.y.abs()));
            assert!(q.is_finite(), "hiddenline: {s:?}");
            assert!(
                lo.0 - slack <= q.x
                    && q.x <= hi.0 + slack
                    && lo.1 - slack <= q.y
                    && q.y <= hi.1 + slack,
                "hiddenline: {s:?} outside {lo:?}..{hi:?}"
            );
        }
    });
    // The painter: no panic, and whatever order it paints in (cuts, a spent cut budget,
    // cycles painted in the order at hand), exactly the z-buffer's covered pixels: a cut
    // polygon's pieces cover its pixels, each once.
    for (name, mut painter) in [
        ("painter", painter::Painter::new()),
        ("painter --split", painter::Painter::with_split()),
        (
            "painter, one cut",
            painter::Painter::with_split_budget(0, 1),
        ),
    ] {
        runs.clear();
        painter.resolve(&polygons, width, height, &mut runs);
        let image = image_of(&runs, width, height);
        for (i, (a, z)) in image.iter().zip(&reference).enumerate() {
            assert_eq!(
                a.is_some(),
                z.is_some(),
                "{name}: pixel {i} of {width}x{height}, {:?}: {polygons:?}",
                painter.stats
            );
        }
    }
});
