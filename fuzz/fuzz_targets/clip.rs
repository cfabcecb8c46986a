//! clipplane's f_plane (thesis 3.2) on arbitrary eye-space polygons and any of the six
//! pyramid planes of an arbitrary view volume: no panic, every output vertex finite and
//! not outside the plane.
#![no_main]
use libfuzzer_sys::fuzz_target;
use polypipe_fuzz::{eye_vertex, polygon, Bytes};
use proto::geometry::{PyramidPlane, Side};
use proto::View;

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes(data);
    let which = PyramidPlane::ALL[(b.u8() % 6) as usize];
    let view = match b.u8() % 3 {
        0 => View::default(),
        1 => View {
            aspect: 16.0 / 9.0,
            hither: 0.5,
            yon: 100.0,
        },
        _ => View {
            aspect: 0.75,
            hither: 1e-3,
            yon: 1e6,
        },
    };
    let plane = clipplane::ClipPlane::new(which, None).unwrap().plane(&view);
    let poly = polygon(&mut b, eye_vertex);
    let mut out = Vec::new();
    clipplane::clip_against(&poly.vertices, &plane, &mut out);
    for v in &out {
        assert!(
            v.is_finite(),
            "{which}: non-finite output {v:?} from {poly:?}"
        );
        let (side, d) = plane.classify(*v);
        assert!(
            side != Side::Outside,
            "{which}: {v:?} outside (d = {d}) from {poly:?}"
        );
    }
    // Clipping again changes nothing (Appendix 2: on the plane counts as inside).
    let mut again = Vec::new();
    clipplane::clip_against(&out, &plane, &mut again);
    assert_eq!(out, again, "{which}: clipping twice differs, from {poly:?}");
});
