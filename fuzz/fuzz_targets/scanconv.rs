//! The scan converter (thesis chapter 4, Appendix 3) on arbitrary screen polygons: no
//! panic, exactly one colour record, every span or pixel on the screen and inside the
//! polygon's bounding box widened by one pixel, spans on a row in order and disjoint.
#![no_main]
use libfuzzer_sys::fuzz_target;
use polypipe_fuzz::{polygon, Bytes};
use proto::{Fragment, Vertex};
use scanconv::{Output, ScanConverter};

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes(data);
    let width = 1 + (b.u8() % 64) as u32;
    let height = 1 + (b.u8() % 64) as u32;
    let output = if b.u8() & 1 == 0 {
        Output::Spans
    } else {
        Output::Pixels
    };
    // Screen vertices: X and Y mostly near the screen, depth anything finite.
    let poly = polygon(&mut b, |b| {
        let c = |b: &mut Bytes| {
            if b.u8() % 4 == 0 {
                b.f64()
            } else {
                b.grid() * 4.0 + 32.0
            }
        };
        Vertex::new(c(b), c(b), b.coord(), 1.0)
    });
    // The stage refuses vertices far outside the screen (an unclipped stream) before it
    // converts anything; the fuzzer checks what it does accept.
    if scanconv::check_on_screen(&poly, width, height).is_err() {
        return;
    }
    let (mut x_lo, mut x_hi, mut y_lo, mut y_hi) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for v in &poly.vertices {
        x_lo = x_lo.min(v.x);
        x_hi = x_hi.max(v.x);
        y_lo = y_lo.min(v.y);
        y_hi = y_hi.max(v.y);
    }
    let mut frags = Vec::new();
    let mut sc = ScanConverter::new(width, height, output);
    sc.convert(&poly, &mut |f| {
        frags.push(f);
        Ok::<(), ()>(())
    })
    .unwrap();
    assert_eq!(frags.first(), Some(&Fragment::Polygon(poly.colour)));
    let in_box = |x: u32, y: u32| {
        x < width
            && y < height
            && x as f64 >= x_lo - 1.0
            && x as f64 + 1.0 <= x_hi + 1.0
            && y as f64 >= y_lo - 1.0
            && y as f64 + 1.0 <= y_hi + 1.0
    };
    let mut last: Option<(u32, u32)> = None;
    for f in &frags[1..] {
        match *f {
            Fragment::Span { y, x0, x1, .. } => {
                assert!(x0 < x1, "empty span {f:?}");
                assert!(
                    in_box(x0, y) && in_box(x1 - 1, y),
                    "{f:?} outside, from {poly:?}"
                );
                if let Some((ly, lx)) = last {
                    assert!(
                        (y, x0) >= (ly, lx),
                        "spans out of order: {f:?} after row {ly} col {lx}"
                    );
                }
                last = Some((y, x1));
            }
            Fragment::Pixel { x, y, .. } => {
                assert!(in_box(x, y), "{f:?} outside, from {poly:?}");
                if let Some((ly, lx)) = last {
                    assert!((y, x) >= (ly, lx), "pixels out of order: {f:?}");
                }
                last = Some((y, x + 1));
            }
            other => panic!("unexpected {other:?}"),
        }
    }
    if poly.vertices.len() < 3 {
        assert_eq!(
            frags.len(),
            1,
            "a polygon of fewer than 3 vertices drew {frags:?}"
        );
    }
});
