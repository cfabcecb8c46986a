//! persp on arbitrary eye-space polygons: either refused with a reason naming the vertex,
//! or every projected vertex finite (nothing inside makes NaN or infinity).
#![no_main]
use libfuzzer_sys::fuzz_target;
use polypipe_fuzz::{eye_vertex, polygon, Bytes};
use proto::perspective::{DepthMode, Perspective};
use proto::View;

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes(data);
    let depth = match b.u8() % 3 {
        0 => DepthMode::Reciprocal,
        1 => DepthMode::Projective,
        _ => DepthMode::EyeZ,
    };
    let p = Perspective::new(64, 64, View::default(), depth).unwrap();
    let mut poly = polygon(&mut b, eye_vertex);
    let before = poly.clone();
    match p.project_polygon(&mut poly) {
        Ok(()) => {
            for v in &poly.vertices {
                assert!(v.is_finite(), "{v:?} from {before:?}");
            }
        }
        Err(e) => {
            assert!(e.vertex < before.vertices.len());
            assert_eq!(poly, before, "a refused polygon was changed");
        }
    }
});
