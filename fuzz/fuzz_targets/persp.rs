//! persp on arbitrary eye-space polygons: either refused with a reason naming the vertex,
//! or every projected vertex finite (nothing inside makes NaN or infinity).
#![no_main]
use libfuzzer_sys::fuzz_target;
use polypipe_fuzz::{eye_vertex, polygon, project_and_check, Bytes};
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
    project_and_check(&p, &mut poly);
});
