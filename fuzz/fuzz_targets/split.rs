//! The splitter node (thesis 6.2) on arbitrary eye-space polygons, about a column or row
//! plane x_s = K / y_s = K: no panic, out1 never outside the plane, out2 never inside,
//! every vertex finite, both outputs keep the colour; vertex colours cut with the edges
//! stay one a vertex and within 0–255. Then each piece projected, as the tree's last
//! level does (`splitter --project`): refused naming a vertex and left as it was, or every
//! projected vertex finite.
#![no_main]
use libfuzzer_sys::fuzz_target;
use polypipe_fuzz::{eye_vertex, polygon, project_and_check, Bytes};
use proto::geometry::{Plane, Side};
use proto::perspective::{DepthMode, Perspective};
use proto::{Polygon, View};

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes(data);
    let k = (b.u8() as i8) as f64 / 128.0;
    let (aspect, width, height) =
        [(1.0, 64, 64), (16.0 / 9.0, 64, 36), (0.75, 48, 64)][(b.u8() % 3) as usize];
    let depth = [
        DepthMode::Reciprocal,
        DepthMode::Projective,
        DepthMode::EyeZ,
    ][(b.u8() % 3) as usize];
    let plane = if b.u8() & 1 == 0 {
        Plane::column(k, aspect)
    } else {
        Plane::row(k)
    };
    let mut poly = polygon(&mut b, eye_vertex);
    // Vertex colours for some polygons (Gouraud shading): whole numbers and fractions.
    if b.u8() & 1 == 1 {
        poly.vertex_attrs = (0..poly.vertices.len())
            .map(|_| {
                proto::DVec3::new(
                    b.u8() as f64,
                    b.u8() as f64 / 1.7,
                    255.0 - b.u8() as f64 / 3.0,
                )
            })
            .collect();
    }
    let (mut out1, mut out2) = (Polygon::default(), Polygon::default());
    splitter::split(&poly, &plane, &mut out1, &mut out2);
    assert_eq!(out1.colour, poly.colour);
    assert_eq!(out2.colour, poly.colour);
    for out in [&out1, &out2] {
        // A piece has a colour for each vertex, each channel within 0-255, and the
        // reader's checks accept it.
        if poly.is_shaded() {
            assert_eq!(out.vertex_attrs.len(), out.vertices.len(), "from {poly:?}");
        } else {
            assert!(out.vertex_attrs.is_empty());
        }
        for c in &out.vertex_attrs {
            assert!(
                c.cmpge(proto::DVec3::ZERO).all() && c.cmple(proto::DVec3::splat(255.0)).all(),
                "colour {c:?} out of 0-255, from {poly:?}"
            );
        }
    }
    for v in &out1.vertices {
        assert!(v.is_finite(), "non-finite {v:?} from {poly:?}");
        assert!(
            plane.classify(*v).0 != Side::Outside,
            "out1 {v:?} outside, from {poly:?}"
        );
    }
    for v in &out2.vertices {
        assert!(v.is_finite(), "non-finite {v:?} from {poly:?}");
        assert!(
            plane.classify(*v).0 != Side::Inside,
            "out2 {v:?} inside, from {poly:?}"
        );
    }
    let view = View {
        aspect,
        ..View::default()
    };
    let perspective = Perspective::new(width, height, view, depth).unwrap();
    for mut piece in [out1, out2] {
        project_and_check(&perspective, &mut piece);
    }
});
