//! Screen-space scenes for measuring the leaf methods alone (`bench scanline`,
//! `bench warnock`): polygons already in device coordinates of a W×H screen, X
//! and Y in pixels and a depth in (0, 1), smaller nearer, so that a leaf (`scanconv
//! --resolve`, `scanline`, `warnock`, `hiddenline`) reads them with no viewxf, clipper or
//! persp in front. Each scene makes one quantity that a method's cost follows grow while
//! the others stay put: the crossings on a scan line, the depth complexity, the visible
//! edges, the hidden polygons, the fragments in one pixel.
//!
//! Newman and Sproull (*Principles of Interactive Computer Graphics*) name what these
//! quantities are for each method: the scan-line method's computation "grows roughly as
//! the *visible* complexity" (14.4.3), area subdivision's with the edges its windows
//! must cut (14.3.4, Warnock's algorithm's performance).

use crate::shapes::{hostile_colour, shuffled};
use proto::{Colour, Polygon};
use std::f64::consts::TAU;

/// The width and height of the screen a scene is made for, in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Size {
    pub width: f64,
    pub height: f64,
}

impl Size {
    pub fn new(width: u32, height: u32) -> Self {
        Size {
            width: width as f64,
            height: height as f64,
        }
    }

    /// A quadrilateral over the whole screen with depth `left` along its left edge and
    /// `right` along its right: a plane tilted about the vertical axis when they differ.
    fn full(&self, colour: Colour, left: f64, right: f64) -> Polygon {
        let (w, h) = (self.width, self.height);
        Polygon::from_xyz(
            colour,
            &[
                [0.0, 0.0, left],
                [w, 0.0, right],
                [w, h, right],
                [0.0, h, left],
            ],
        )
    }
}

/// An axis-aligned rectangle from (x0, y0) to (x1, y1) at one depth.
fn rectangle(colour: Colour, (x0, y0): (f64, f64), (x1, y1): (f64, f64), z: f64) -> Polygon {
    Polygon::from_xyz(
        colour,
        &[[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]],
    )
}

/// `scene screen crossings K`: K columns side by side across the screen, each holding two
/// quadrilaterals of its full height whose depths run from 0.2 to 0.8 and from 0.8 to
/// 0.2 across it, so that their planes cross down its middle: depth complexity 2
/// everywhere, and K changes of the visible polygon on every scan line.
pub fn crossings(k: usize, size: Size) -> Vec<Polygon> {
    let column = size.width / k.max(1) as f64;
    (0..k)
        .flat_map(|i| {
            let (x0, x1) = (i as f64 * column, (i + 1) as f64 * column);
            [0u8, 1].map(|j| {
                let (za, zb) = if j == 0 { (0.2, 0.8) } else { (0.8, 0.2) };
                Polygon::from_xyz(
                    [(i * 7 % 256) as u8, j * 200, 90],
                    &[
                        [x0, 0.0, za],
                        [x1, 0.0, zb],
                        [x1, size.height, zb],
                        [x0, size.height, za],
                    ],
                )
            })
        })
        .collect()
}

/// `scene screen parallel D`: D full-screen planes at random depths in (0.05, 0.96),
/// each tilted by 0.01 across the screen, all the same way, in random order: depth
/// complexity D, and since no two cross, one polygon in front along a whole line.
pub fn parallel(d: usize, seed: u64, size: Size) -> Vec<Polygon> {
    let mut rng = fastrand::Rng::with_seed(seed);
    (0..d)
        .map(|k| {
            let z = 0.05 + 0.9 * rng.f64();
            size.full(hostile_colour(k), z, z + 0.01)
        })
        .collect()
}

/// `scene screen tilted D`: D full-screen planes, each with random depths in (0.05, 0.95)
/// at its left and right edges: depth complexity D, and the front of the pile changing
/// along every line.
pub fn tilted(d: usize, seed: u64, size: Size) -> Vec<Polygon> {
    let mut rng = fastrand::Rng::with_seed(seed);
    (0..d)
        .map(|k| {
            let left = 0.05 + 0.9 * rng.f64();
            let right = 0.05 + 0.9 * rng.f64();
            size.full(hostile_colour(k), left, right)
        })
        .collect()
}

/// `scene screen through D`: D full-screen planes that all pass through each other, each
/// with random depths a and b in (0.05, 0.95) at its top corners and 1 − a and 1 − b at
/// the corners opposite them: every plane holds depth 0.5 at the screen's centre, and
/// every pair crosses on a line through it, so no depth order exists (a depth sort must
/// cut them all, the painter's hardest case).
pub fn through(d: usize, seed: u64, size: Size) -> Vec<Polygon> {
    let mut rng = fastrand::Rng::with_seed(seed);
    let (w, h) = (size.width, size.height);
    (0..d)
        .map(|k| {
            let a = 0.05 + 0.9 * rng.f64();
            let b = 0.05 + 0.9 * rng.f64();
            Polygon::from_xyz(
                hostile_colour(k),
                &[
                    [0.0, 0.0, a],
                    [w, 0.0, b],
                    [w, h, 1.0 - a],
                    [0.0, h, 1.0 - b],
                ],
            )
        })
        .collect()
}

/// `scene screen reversing N`: N strips a pixel wide running from the top of the screen
/// to the bottom, strip i from x = 0.1 + i·W/N at the top to x = W − 0.9 − i·W/N at
/// the bottom, at depths 0.1 + 0.8·i/N: their order along a scan line at the top is
/// the reverse of that at the bottom, so every pair changes places once, the case that
/// defeats a segment list kept in order from line to line.
pub fn reversing(n: usize, size: Size) -> Vec<Polygon> {
    let step = size.width / n.max(1) as f64;
    (0..n)
        .map(|i| {
            let top = 0.1 + step * i as f64;
            let bottom = size.width - 0.9 - step * i as f64;
            let z = 0.1 + 0.8 * i as f64 / n as f64;
            Polygon::from_xyz(
                [(i % 256) as u8, 100, 200],
                &[
                    [top, 0.0, z],
                    [top + 1.0, 0.0, z],
                    [bottom + 1.0, size.height, z],
                    [bottom, size.height, z],
                ],
            )
        })
        .collect()
}

/// `scene screen stack N`: N full-screen squares facing the viewer at the distinct
/// depths 0.2 + 0.6·k/N, in the shuffled order of the world scene `stack` (neither back
/// to front nor front to back): depth complexity N at every pixel.
pub fn stack(n: usize, size: Size) -> Vec<Polygon> {
    shuffled(n)
        .map(|k| {
            let z = 0.2 + 0.6 * k as f64 / n as f64;
            size.full(hostile_colour(k), z, z)
        })
        .collect()
}

/// `scene screen slivers N`: N triangles from a point on one side of the screen to a
/// base 0.4 of a pixel high on the other, at random heights, with random depths in
/// (0.1, 0.9) at either end: many edges and little area, crossing one another everywhere.
pub fn slivers(n: usize, seed: u64, size: Size) -> Vec<Polygon> {
    let mut rng = fastrand::Rng::with_seed(seed);
    (0..n)
        .map(|k| {
            let (y0, y1) = (rng.f64() * size.height, rng.f64() * size.height);
            let (z0, z1) = (0.1 + 0.8 * rng.f64(), 0.1 + 0.8 * rng.f64());
            let (a, b) = if rng.bool() {
                (0.0, size.width)
            } else {
                (size.width, 0.0)
            };
            Polygon::from_xyz(
                hostile_colour(k),
                &[[a, y0, z0], [b, y1 - 0.2, z1], [b, y1 + 0.2, z1]],
            )
        })
        .collect()
}

/// `scene screen pinhead N`: N triangles around the centre of the pixel left of and
/// above the screen's middle, (⌊W/2⌋ − 0.5, ⌊H/2⌋ − 0.5), each containing it (vertices
/// at radii 0.24 to 0.6 of a pixel, about 120° apart), at the distinct depths
/// 0.2 + 0.6·k/N in shuffled order: N fragments in that pixel.
pub fn pinhead(n: usize, seed: u64, size: Size) -> Vec<Polygon> {
    let mut rng = fastrand::Rng::with_seed(seed);
    let (cx, cy) = (
        (size.width / 2.0).floor() - 0.5,
        (size.height / 2.0).floor() - 0.5,
    );
    shuffled(n)
        .map(|k| {
            let z = 0.2 + 0.6 * k as f64 / n as f64;
            let start = rng.f64() * TAU;
            let points: Vec<[f64; 3]> = (0..3)
                .map(|j| {
                    let angle = start + TAU * j as f64 / 3.0 + (rng.f64() - 0.5) * 0.6;
                    let r = 0.24 + 0.36 * rng.f64();
                    [cx + r * angle.cos(), cy + r * angle.sin(), z]
                })
                .collect();
            Polygon::from_xyz(hostile_colour(k), &points)
        })
        .collect()
}

/// `scene screen tiles K --behind N`: N squares of side 50 to 250 pixels at random
/// places and depths in (0.5, 0.9), then K × K tiles covering the screen in front of
/// them at depth 0.2. With N fixed the visible edges grow with K while the hidden
/// polygons stay; with K fixed the hidden polygons grow while the visible edges stay.
pub fn tiles(k: usize, behind: usize, seed: u64, size: Size) -> Vec<Polygon> {
    let mut rng = fastrand::Rng::with_seed(seed);
    let hidden = (0..behind).map(|i| {
        let (x, y) = (rng.f64() * size.width, rng.f64() * size.height);
        let side = 50.0 + 200.0 * rng.f64();
        let z = 0.5 + 0.4 * rng.f64();
        rectangle(hostile_colour(i), (x, y), (x + side, y + side), z)
    });
    let mut polygons: Vec<Polygon> = hidden.collect();
    let (w, h) = (size.width / k as f64, size.height / k as f64);
    for j in 0..k {
        for i in 0..k {
            polygons.push(rectangle(
                hostile_colour(behind + j * k + i),
                (w * i as f64, h * j as f64),
                (w * (i + 1) as f64, h * (j + 1) as f64),
                0.2,
            ));
        }
    }
    polygons
}

/// `scene screen penetrate`: two planes over the whole screen crossing along a vertical
/// line, a red one from depth 0.2 at the left to 0.6 at the right and a blue one from
/// 0.55 to 0.31: the one implied edge a method must find.
pub fn penetrate(size: Size) -> Vec<Polygon> {
    vec![
        size.full([200, 0, 0], 0.2, 0.6),
        size.full([0, 0, 200], 0.55, 0.31),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec4;

    fn xyz(p: &Polygon) -> Vec<[f64; 3]> {
        p.vertices.iter().map(|v| [v.x, v.y, v.z]).collect()
    }

    const S: Size = Size {
        width: 500.0,
        height: 400.0,
    };

    #[test]
    fn crossings_are_two_crossing_quads_a_column() {
        let scene = crossings(4, S);
        assert_eq!(scene.len(), 8);
        assert_eq!(scene[0].colour, [0, 0, 90]);
        assert_eq!(
            xyz(&scene[0]),
            [
                [0.0, 0.0, 0.2],
                [125.0, 0.0, 0.8],
                [125.0, 400.0, 0.8],
                [0.0, 400.0, 0.2]
            ]
        );
        assert_eq!(scene[1].colour, [0, 200, 90]);
        assert_eq!(xyz(&scene[1])[0], [0.0, 0.0, 0.8]);
        // The last column ends at the screen's right edge.
        assert_eq!(scene[7].colour, [21, 200, 90]);
        assert_eq!(xyz(&scene[7])[0], [375.0, 0.0, 0.8]);
        assert_eq!(xyz(&scene[7])[1], [500.0, 0.0, 0.2]);
    }

    #[test]
    fn parallel_and_tilted_planes_cover_the_screen_at_depths_in_range() {
        for (scene, tilt) in [(parallel(16, 3, S), Some(0.01)), (tilted(16, 3, S), None)] {
            assert_eq!(scene.len(), 16);
            for p in &scene {
                let v = xyz(p);
                assert_eq!([v[0][0], v[0][1]], [0.0, 0.0]);
                assert_eq!([v[2][0], v[2][1]], [500.0, 400.0]);
                assert_eq!(v[0][2], v[3][2], "the left edge at one depth");
                assert_eq!(v[1][2], v[2][2], "the right edge at one depth");
                assert!((0.05..0.96).contains(&v[0][2]) && (0.05..0.96).contains(&v[1][2]));
                if let Some(t) = tilt {
                    assert!((v[1][2] - v[0][2] - t).abs() < 1e-12);
                }
            }
        }
        // The same seed, the same scene; another seed, another.
        assert_eq!(parallel(16, 3, S), parallel(16, 3, S));
        assert_ne!(tilted(16, 3, S), tilted(16, 4, S));
    }

    #[test]
    fn through_planes_all_hold_half_at_the_centre() {
        let scene = through(7, 5, S);
        assert_eq!(scene.len(), 7);
        for p in &scene {
            let v = xyz(p);
            assert_eq!(
                [v[0][0], v[0][1], v[2][0], v[2][1]],
                [0.0, 0.0, 500.0, 400.0]
            );
            assert_eq!(v[0][2] + v[2][2], 1.0);
            assert_eq!(v[1][2] + v[3][2], 1.0);
            assert!((0.05..0.95).contains(&v[0][2]) && (0.05..0.95).contains(&v[1][2]));
        }
        assert_eq!(through(7, 5, S), through(7, 5, S));
        assert_ne!(through(7, 5, S), through(7, 6, S));
    }

    #[test]
    fn reversing_strips_change_order_from_top_to_bottom() {
        let scene = reversing(1000, Size::new(500, 500));
        assert_eq!(scene.len(), 1000);
        assert_eq!(
            xyz(&scene[0]),
            [
                [0.1, 0.0, 0.1],
                [1.1, 0.0, 0.1],
                [500.1, 500.0, 0.1],
                [499.1, 500.0, 0.1]
            ]
        );
        assert_eq!(scene[999].colour, [231, 100, 200]);
        let last = xyz(&scene[999]);
        for (got, want) in [
            (last[0], [499.6, 0.0, 0.8992]),
            (last[3], [-0.4, 500.0, 0.8992]),
        ] {
            assert!(
                got.iter().zip(want).all(|(g, w)| (g - w).abs() < 1e-9),
                "{got:?}"
            );
        }
    }

    #[test]
    fn a_stack_holds_every_depth_once_in_shuffled_order() {
        let scene = stack(10, S);
        assert_eq!(scene.len(), 10);
        // 10·0.618 = 6 is not prime to 10; 7 is: the order 0, 7, 4, 1, …
        let z = 0.2 + 0.6 * 7.0 / 10.0;
        assert_eq!(
            xyz(&scene[1]),
            [
                [0.0, 0.0, z],
                [500.0, 0.0, z],
                [500.0, 400.0, z],
                [0.0, 400.0, z]
            ]
        );
        assert!((z - 0.62).abs() < 1e-15);
        let mut depths: Vec<f64> = scene.iter().map(|p| p.vertices[0].z).collect();
        depths.sort_by(f64::total_cmp);
        let want: Vec<f64> = (0..10).map(|k| 0.2 + 0.6 * k as f64 / 10.0).collect();
        assert_eq!(depths, want);
    }

    #[test]
    fn slivers_run_from_side_to_side_with_a_base_of_0_4_pixels() {
        let scene = slivers(100, 2, S);
        assert_eq!(scene.len(), 100);
        for p in &scene {
            let v = xyz(p);
            assert_eq!(v.len(), 3);
            assert!(v[0][0] == 0.0 && v[1][0] == 500.0 || v[0][0] == 500.0 && v[1][0] == 0.0);
            assert_eq!(v[1][0], v[2][0]);
            assert!((v[2][1] - v[1][1] - 0.4).abs() < 1e-9);
            assert!((0.1..0.9).contains(&v[0][2]) && (0.1..0.9).contains(&v[1][2]));
        }
        assert_eq!(slivers(100, 2, S), scene);
    }

    #[test]
    fn a_pinhead_s_triangles_all_contain_one_pixel_centre() {
        let scene = pinhead(1000, 3, S);
        assert_eq!(scene.len(), 1000);
        let (cx, cy) = (249.5, 199.5);
        for p in &scene {
            let v = xyz(p);
            // The centre is inside: on the same side of all three edges.
            let side = |a: [f64; 3], b: [f64; 3]| {
                (b[0] - a[0]) * (cy - a[1]) - (b[1] - a[1]) * (cx - a[0])
            };
            let s = [side(v[0], v[1]), side(v[1], v[2]), side(v[2], v[0])];
            assert!(
                s.iter().all(|x| *x > 0.0) || s.iter().all(|x| *x < 0.0),
                "{v:?}"
            );
            for q in &v {
                let r = ((q[0] - cx).powi(2) + (q[1] - cy).powi(2)).sqrt();
                assert!((0.24..=0.6).contains(&r), "{r}");
            }
        }
    }

    #[test]
    fn tiles_cover_the_screen_in_front_of_the_hidden_squares() {
        let scene = tiles(4, 30, 5, S);
        assert_eq!(scene.len(), 30 + 16);
        assert!(scene[..30].iter().all(|p| {
            let v = xyz(p);
            (0.5..0.9).contains(&v[0][2]) && (50.0..250.0).contains(&(v[1][0] - v[0][0]))
        }));
        assert_eq!(
            xyz(&scene[30]),
            [
                [0.0, 0.0, 0.2],
                [125.0, 0.0, 0.2],
                [125.0, 100.0, 0.2],
                [0.0, 100.0, 0.2]
            ]
        );
        assert_eq!(xyz(&scene[45])[2], [500.0, 400.0, 0.2]);
        let area: f64 = scene[30..]
            .iter()
            .map(|p| (p.vertices[1].x - p.vertices[0].x) * (p.vertices[2].y - p.vertices[1].y))
            .sum();
        assert_eq!(area, 500.0 * 400.0);
    }

    #[test]
    fn penetrate_is_two_planes_crossing() {
        let scene = penetrate(S);
        assert_eq!(scene.len(), 2);
        assert_eq!(scene[0].colour, [200, 0, 0]);
        assert_eq!(
            scene[1].vertices,
            [
                DVec4::new(0.0, 0.0, 0.55, 1.0),
                DVec4::new(500.0, 0.0, 0.31, 1.0),
                DVec4::new(500.0, 400.0, 0.31, 1.0),
                DVec4::new(0.0, 400.0, 0.55, 1.0)
            ]
        );
    }
}
