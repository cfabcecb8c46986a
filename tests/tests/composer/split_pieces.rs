//! Split invariance at library level: a polygon cut by the splitter and projected by persp scan
//! converts, piece by piece, to exactly the pixels and depths of the whole polygon: each
//! pixel once, with the same fixed-point depth. The pieces' edge supports give their
//! crossings to the bit, and the plane recorded before the cut gives their depths.

use pipeline_tests::scenes::{eye_at, projective, Lcg};
use proto::geometry::Plane;
use proto::perspective::Perspective;
use proto::{DVec4, Fragment, Polygon};
use scanconv::{Output, ScanConverter};
use std::collections::BTreeMap;

const W: u32 = 16;
const H: u32 = 12;

/// (x, y) → depth of every pixel the polygons cover; a pixel covered twice is an error.
fn pixels(polys: &[Polygon]) -> Result<BTreeMap<(u32, u32), f64>, String> {
    let mut sc = ScanConverter::new(W, H, Output::Pixels);
    let mut map = BTreeMap::new();
    for p in polys {
        let mut frags = Vec::new();
        sc.convert(p, &mut |f| {
            frags.push(f);
            Ok::<_, ()>(())
        })
        .unwrap();
        for f in frags {
            if let Fragment::Pixel { x, y, z } = f {
                if map.insert((x, y), z).is_some() {
                    return Err(format!("pixel ({x}, {y}) covered twice"));
                }
            }
        }
    }
    Ok(map)
}

fn perspective() -> Perspective {
    projective(W, H)
}

/// An eye-space vertex that projects near screen point (X, Y) at depth z_e (w = z_e·s/d
/// for the default camera). X, Y on a half-pixel lattice put pixel centres on the edges.
fn at(x: f64, y: f64, z: f64) -> DVec4 {
    eye_at((W, H), x, y, z)
}

/// Splits `poly` by the column plane through device column `c` (a pixel boundary), the
/// row plane through row `r`, or both, and returns the projected pieces.
fn pieces(poly: &Polygon, c: u32, r: u32, strip: bool) -> Vec<Polygon> {
    let p = perspective();
    let column = Plane::column(2.0 * c as f64 / W as f64 - 1.0, W as f64 / H as f64);
    let row = Plane::row(1.0 - 2.0 * r as f64 / H as f64);
    let (mut a, mut b) = (Polygon::default(), Polygon::default());
    splitter::split(poly, &column, &mut a, &mut b);
    let mut out = Vec::new();
    for half in [a, b] {
        let (mut c, mut d) = (Polygon::default(), Polygon::default());
        splitter::split(&half, &row, &mut c, &mut d);
        for mut q in [c, d] {
            if strip {
                q.supports.clear();
                q.plane = None;
            }
            p.project_polygon(&mut q).unwrap();
            out.push(q);
        }
    }
    out
}

fn whole(poly: &Polygon) -> Polygon {
    let mut q = poly.clone();
    perspective().project_polygon(&mut q).unwrap();
    q
}

#[test]
fn a_quadrilateral_cut_four_ways_renders_as_the_whole() {
    // Tilted and not planar; edges through many pixel centres (vertices on half pixels).
    let quad = Polygon::new(
        [1, 2, 3],
        vec![
            at(1.5, 0.5, 5.0),
            at(14.5, 2.5, 9.0),
            at(12.5, 11.5, 20.0),
            at(0.5, 9.5, 3.0),
        ],
    );
    let expected = pixels(&[whole(&quad)]).unwrap();
    assert!(expected.len() > 100);
    for c in 1..W {
        for r in 1..H {
            assert_eq!(
                pixels(&pieces(&quad, c, r, false)),
                Ok(expected.clone()),
                "cut at {c}, {r}"
            );
        }
    }
}

#[test]
fn random_polygons_cut_at_pixel_boundaries_render_as_the_whole() {
    let mut rng = Lcg(1985);
    let mut differ_without_annotations = 0;
    for case in 0..300 {
        let n = 3 + rng.next(4) as usize;
        let vertices = (0..n)
            .map(|_| {
                at(
                    rng.next(2 * W as u64 + 1) as f64 / 2.0,
                    rng.next(2 * H as u64 + 1) as f64 / 2.0,
                    2.0 + rng.next(50) as f64 / 2.0,
                )
            })
            .collect();
        let poly = Polygon::new([9, 9, 9], vertices);
        let (c, r) = (
            1 + rng.next(W as u64 - 1) as u32,
            1 + rng.next(H as u64 - 1) as u32,
        );
        let expected = pixels(&[whole(&poly)]);
        // Self-intersecting polygons may cover a pixel twice only if the whole does.
        let Ok(expected) = expected else { continue };
        assert_eq!(
            pixels(&pieces(&poly, c, r, false)),
            Ok(expected.clone()),
            "case {case}"
        );
        if pixels(&pieces(&poly, c, r, true)) != Ok(expected) {
            differ_without_annotations += 1;
        }
    }
    // The annotations matter: without them some of these cases render differently.
    assert!(differ_without_annotations > 0);
}
