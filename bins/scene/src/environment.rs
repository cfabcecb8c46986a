//! The test environment of thesis chapter 5.2: `P_t` four-sided polygons, a fraction of
//! them clipped out (the thesis borrows "half" from Sutherland & Sproull), and a depth
//! complexity `Dc`, "the average number of polygons that cover a pixel".
//!
//! Each visible polygon is made on the screen first and then lifted into the world, so
//! its projected area is known exactly:
//!
//! 1. a random parallelogram (random orientation, elongation and shear) of a chosen
//!    screen area is placed wholly inside the screen;
//! 2. a random plane z_e = z0 + g_x·x_e + g_y·y_e in front of the eye (K1 ≤ z_e ≤ K2 at
//!    every vertex) is chosen;
//! 3. each screen vertex is carried back along its ray from the eye onto that plane.
//!
//! Perspective maps the planar eye-space quad onto the screen parallelogram exactly, so
//! the polygon is planar, convex, wholly inside the clipping pyramid, and covers the area
//! it was given. The visible polygons' areas are random weights normalised so that they
//! sum to `Dc` × the screen area; placed uniformly, they leave about e^−Dc of the pixels
//! empty.
//!
//! A clipped-out polygon is made wholly outside one plane of the pyramid: beside the
//! screen (left, right, top or bottom), between the eye and the hither plane or behind
//! the eye, or beyond yon.
//!
//! In a movie (`frames` > 1) every polygon drifts with its own velocity; a visible polygon
//! bounces off the screen's edges so that it stays wholly visible with the same area, and
//! a clipped-out one drifts along the plane it is outside of, so it stays clipped out.

use glam::{DVec2, DVec3, DVec4};
use proto::camera::{Camera, EyeFrame};
use proto::{Colour, Polygon, View};

/// The parameters of the environment (chapter 5.2's environment parameters).
#[derive(Clone, Debug, PartialEq)]
pub struct Environment {
    /// P_t: the total number of polygons.
    pub polygons: usize,
    /// The fraction of polygons that lie wholly outside the clipping pyramid.
    pub clipped: f64,
    /// Dc: the depth complexity, total projected area of the visible polygons over the
    /// screen area.
    pub depth_complexity: f64,
    pub seed: u64,
    /// The screen's aspect ratio W/H (the pyramid is |x_e| ≤ a·w).
    pub aspect: f64,
    /// The number of frames.
    pub frames: usize,
}

impl Default for Environment {
    fn default() -> Self {
        Environment {
            polygons: 1000,
            clipped: 0.5,
            depth_complexity: 1.0,
            seed: 1,
            aspect: 1.0,
            frames: 1,
        }
    }
}

/// The view volume the environment is made for: the thesis's default camera (eye at
/// (0, 0, 20) looking at the origin, s = 10, d = 16) and K1 = 1, K2 = 30.
pub fn view_volume(aspect: f64) -> View {
    View {
        aspect,
        ..View::default()
    }
}

/// Where a polygon lives, and how it moves between frames.
#[derive(Clone, Debug)]
enum Placement {
    /// A parallelogram given on the screen in square-pixel units (x in [−a, a], y in
    /// [−1, 1]), lifted onto the eye-space plane z_e = z0 + g·(x_e, y_e).
    Screen {
        /// Corners relative to the centre.
        corners: [DVec2; 4],
        centre: DVec2,
        velocity: DVec2,
        /// The range the centre may take (it bounces between these).
        lo: DVec2,
        hi: DVec2,
        z0: f64,
        gradient: DVec2,
    },
    /// A quad given directly in eye space (beyond yon, or in front of hither), drifting
    /// parallel to the screen.
    Eye {
        corners: [DVec3; 4],
        velocity: DVec2,
    },
}

/// A polygon of the environment, with what it needs to be drawn at any frame.
#[derive(Clone, Debug)]
struct Item {
    colour: Colour,
    placement: Placement,
}

/// The environment's frames: `frames` lists of `polygons` world-space quads each.
pub fn generate(env: &Environment) -> Vec<Vec<Polygon>> {
    frames(env).map(Iterator::collect).collect()
}

/// The environment's frames one at a time, each a stream of polygons made as they are
/// taken: a scene of any size, and a movie of any length, is written in constant memory.
pub fn frames(env: &Environment) -> impl Iterator<Item = impl Iterator<Item = Polygon>> {
    let maker = std::rc::Rc::new(Maker::new(env));
    (0..env.frames.max(1)).map(move |f| {
        let maker = maker.clone();
        (0..maker.env.polygons).map(move |i| maker.polygon(i, f as f64))
    })
}

/// Margin kept between a polygon and the plane it must be inside or outside of, in the
/// plane's own units, so that no vertex is classified `On` a pyramid plane.
const MARGIN: f64 = 1e-3;

/// A drift of about 1% of the screen height per frame.
const SPEED: f64 = 0.02;

/// Makes polygon i of any frame from its own random stream, seeded by (seed, i): no
/// polygon needs another's state, so none is kept.
struct Maker {
    env: Environment,
    view: View,
    eye: EyeFrame,
    w_per_z: f64,
    /// Σ of the visible polygons' area weights, and their mean area.
    total_weight: f64,
    mean_area: f64,
}

impl Maker {
    fn new(env: &Environment) -> Self {
        let camera = Camera::default();
        // The default camera always defines a frame.
        let eye = camera.frame().unwrap_or_else(|_| unreachable!());
        // A first pass decides which polygons are clipped out and their area weights, so
        // that the visible ones' share of the depth complexity is known before any is made.
        let (mut visible, mut total_weight) = (0usize, 0.0);
        for i in 0..env.polygons {
            let (clipped, weight) = Self::fate(&mut Self::rng(env.seed, i), env);
            if !clipped {
                visible += 1;
                total_weight += weight;
            }
        }
        // Σ area = Dc × screen area (4a in square-pixel units); clipped-out polygons get
        // the size a visible one of average weight would have.
        let screen_area = 4.0 * env.aspect;
        let share = if visible > 0 {
            visible
        } else {
            env.polygons.max(1)
        };
        let mean_area = env.depth_complexity * screen_area / share as f64;
        Maker {
            env: env.clone(),
            view: view_volume(env.aspect),
            eye,
            w_per_z: camera.s / camera.d,
            total_weight,
            mean_area,
        }
    }

    /// Polygon i's random stream: SplitMix64 of the seed and the index.
    fn rng(seed: u64, i: usize) -> fastrand::Rng {
        let mut z = seed
            .wrapping_add((i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15))
            .wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        fastrand::Rng::with_seed(z ^ (z >> 31))
    }

    /// The first draws of a polygon's stream: whether it is clipped out, and its area
    /// weight in [0.5, 1.5).
    fn fate(rng: &mut fastrand::Rng, env: &Environment) -> (bool, f64) {
        let clipped = rng.f64() < env.clipped;
        (clipped, 0.5 + rng.f64())
    }

    fn polygon(&self, i: usize, f: f64) -> Polygon {
        let env = &self.env;
        let mut rng = Self::rng(env.seed, i);
        let (clipped, weight) = Self::fate(&mut rng, env);
        let colour = random_colour(&mut rng);
        let velocity = random_direction(&mut rng) * SPEED * (0.5 + rng.f64());
        let placement = if clipped {
            clipped_placement(&mut rng, &self.view, self.w_per_z, self.mean_area, velocity)
        } else {
            let area = env.depth_complexity * 4.0 * env.aspect * weight / self.total_weight;
            visible_placement(&mut rng, &self.view, self.w_per_z, area, velocity)
        };
        item_at(&Item { colour, placement }, f, &self.eye, self.w_per_z)
    }
}

/// A colour bright enough to tell from the black background.
fn random_colour(rng: &mut fastrand::Rng) -> Colour {
    [rng.u8(40..=255), rng.u8(40..=255), rng.u8(40..=255)]
}

fn random_direction(rng: &mut fastrand::Rng) -> DVec2 {
    let t = rng.f64() * std::f64::consts::TAU;
    DVec2::new(t.cos(), t.sin())
}

/// A parallelogram of the given area centred on the origin: random orientation, side
/// ratio in [1/2, 2] and shear up to ±0.5.
fn parallelogram(rng: &mut fastrand::Rng, area: f64) -> [DVec2; 4] {
    let dir = random_direction(rng);
    let ratio = 2f64.powf(rng.f64() * 2.0 - 1.0);
    let shear = rng.f64() - 0.5;
    // u along dir, v across it (plus shear along it): area = |u × v| = |u|·|v_perp|.
    let side = (area / ratio).sqrt();
    let u = dir * side * ratio;
    let v = dir.perp() * side + dir * side * shear;
    let (hu, hv) = (u * 0.5, v * 0.5);
    [-hu - hv, hu - hv, hu + hv, -hu + hv]
}

/// The smallest box around the corners: (min, max).
fn bounds(corners: &[DVec2; 4]) -> (DVec2, DVec2) {
    corners.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), c| (lo.min(*c), hi.max(*c)),
    )
}

/// The distance along the eye ray through square-pixel screen point `p` at which the ray
/// meets the plane z_e = z0 + g·(x_e, y_e). The ray is t·(p.x·w_per_z, p.y·w_per_z, 1)
/// (x_s = p.x/a and x_e = x_s·a·w), so t = z0 / (1 − w_per_z·g·p).
fn ray_depth(p: DVec2, z0: f64, gradient: DVec2, w_per_z: f64) -> f64 {
    z0 / (1.0 - w_per_z * gradient.dot(p))
}

/// The eye-space point of square-pixel screen point `p` at depth z_e.
fn lift(p: DVec2, z_e: f64, w_per_z: f64) -> DVec3 {
    DVec3::new(p.x * w_per_z * z_e, p.y * w_per_z * z_e, z_e)
}

fn visible_placement(
    rng: &mut fastrand::Rng,
    view: &View,
    w_per_z: f64,
    area: f64,
    velocity: DVec2,
) -> Placement {
    let a = view.aspect;
    let mut corners = parallelogram(rng, area);
    let (mut lo, mut hi) = bounds(&corners);
    // A polygon too big for the screen (few polygons, high Dc) is shrunk to fit: it then
    // covers less than its share, which only matters for degenerate parameters.
    let room = DVec2::new(2.0 * a, 2.0) * (1.0 - 2.0 * MARGIN);
    let fit = (room / (hi - lo)).min_element();
    if fit < 1.0 {
        corners = corners.map(|c| c * fit);
        (lo, hi) = (lo * fit, hi * fit);
    }
    let edge = DVec2::new(a, 1.0) * (1.0 - MARGIN);
    let (c_lo, c_hi) = (-edge - lo, edge - hi);
    let centre = c_lo + (c_hi - c_lo) * DVec2::new(rng.f64(), rng.f64());
    // The plane: a depth z0 and a tilt of up to 60° from facing the eye, reduced until
    // every vertex, wherever the polygon drifts, is between hither and yon.
    let (k1, k2) = (view.hither + MARGIN, view.yon - MARGIN);
    let z0 = k1 + 0.5 + (k2 - k1 - 1.0) * rng.f64();
    let tilt = (rng.f64() * 60.0).to_radians().tan();
    let mut gradient = random_direction(rng) * tilt;
    // The worst case of g·p over the screen is at a corner of the screen rectangle.
    let screen_corners = [
        DVec2::new(-a, -1.0),
        DVec2::new(a, -1.0),
        DVec2::new(a, 1.0),
        DVec2::new(-a, 1.0),
    ];
    let ok = |g: DVec2| {
        screen_corners.iter().all(|p| {
            let t = ray_depth(*p, z0, g, w_per_z);
            t.is_finite() && t >= k1 && t <= k2
        })
    };
    for _ in 0..40 {
        if ok(gradient) {
            break;
        }
        gradient *= 0.5;
    }
    if !ok(gradient) {
        gradient = DVec2::ZERO;
    }
    Placement::Screen {
        corners,
        centre,
        velocity,
        lo: c_lo,
        hi: c_hi,
        z0,
        gradient,
    }
}

fn clipped_placement(
    rng: &mut fastrand::Rng,
    view: &View,
    w_per_z: f64,
    area: f64,
    velocity: DVec2,
) -> Placement {
    let a = view.aspect;
    let corners = parallelogram(rng, area);
    let (lo, hi) = bounds(&corners);
    let (k1, k2) = (view.hither, view.yon);
    // Six regions: beside each of the four side planes, before hither, beyond yon.
    match rng.usize(0..6) {
        side @ 0..=3 => {
            // Beside the screen: the whole parallelogram at |x_s| > 1 (or |y_s| > 1), up
            // to one screen further out, at a depth within [K1, K2]. It drifts along the
            // edge it is beside, within the edge's length, so it stays outside.
            let edge = DVec2::new(a, 1.0);
            let (axis, sign) = (side / 2, if side % 2 == 0 { -1.0 } else { 1.0 });
            let mut c_lo = -edge - lo;
            let mut c_hi = edge - hi;
            // Across the edge: from just beyond it to one screen further.
            let beyond = edge[axis] * (1.0 + MARGIN * 10.0);
            let (near, far) = if sign > 0.0 {
                (beyond - lo[axis], beyond - lo[axis] + edge[axis])
            } else {
                (-beyond - hi[axis] - edge[axis], -beyond - hi[axis])
            };
            c_lo[axis] = near;
            c_hi[axis] = far;
            // Along the edge a large polygon may not fit; let it hang over (it is
            // outside regardless).
            let other = 1 - axis;
            if c_lo[other] > c_hi[other] {
                c_lo[other] = 0.0;
                c_hi[other] = 0.0;
            }
            let centre = c_lo + (c_hi - c_lo) * DVec2::new(rng.f64(), rng.f64());
            let mut v = velocity;
            v[axis] = 0.0;
            Placement::Screen {
                corners,
                centre,
                velocity: v,
                lo: c_lo,
                hi: c_hi,
                z0: k1 + 0.5 + (k2 - k1 - 1.0) * rng.f64(),
                gradient: DVec2::ZERO,
            }
        }
        region => {
            // Before hither (between the eye and K1, or behind the eye) or beyond yon,
            // facing the eye, at a lateral position that would otherwise be on screen.
            let z = if region == 4 {
                -10.0 + (k1 - MARGIN * 10.0 + 10.0) * rng.f64()
            } else {
                k2 * (1.0 + MARGIN * 10.0) + 15.0 * rng.f64()
            };
            // Its size on the screen as if it were at z (or at K2 for z ≤ 0).
            let scale = w_per_z * z.abs().max(k1);
            let edge = DVec2::new(a, 1.0);
            let (c_lo, c_hi) = (-edge - lo, edge - hi);
            let centre = if c_lo.x <= c_hi.x && c_lo.y <= c_hi.y {
                c_lo + (c_hi - c_lo) * DVec2::new(rng.f64(), rng.f64())
            } else {
                DVec2::ZERO
            };
            let corners = corners.map(|c| {
                let p = (centre + c) * scale;
                DVec3::new(p.x, p.y, z)
            });
            Placement::Eye {
                corners,
                velocity: velocity * scale,
            }
        }
    }
}

/// The triangle wave that bounces `x` between `lo` and `hi`.
fn bounce(x: f64, lo: f64, hi: f64) -> f64 {
    let span = hi - lo;
    if span.is_nan() || span <= 0.0 {
        return lo;
    }
    let t = (x - lo).rem_euclid(2.0 * span);
    lo + if t <= span { t } else { 2.0 * span - t }
}

fn item_at(item: &Item, f: f64, eye: &EyeFrame, w_per_z: f64) -> Polygon {
    let eye_points: Vec<DVec3> = match &item.placement {
        Placement::Screen {
            corners,
            centre,
            velocity,
            lo,
            hi,
            z0,
            gradient,
        } => {
            let moved = *centre + *velocity * f;
            let c = DVec2::new(bounce(moved.x, lo.x, hi.x), bounce(moved.y, lo.y, hi.y));
            corners
                .iter()
                .map(|k| {
                    let p = c + *k;
                    lift(p, ray_depth(p, *z0, *gradient, w_per_z), w_per_z)
                })
                .collect()
        }
        Placement::Eye { corners, velocity } => corners
            .iter()
            .map(|k| *k + (*velocity * f).extend(0.0))
            .collect(),
    };
    Polygon::new(
        item.colour,
        eye_points
            .into_iter()
            .map(|p| to_world(eye, p).extend(1.0))
            .collect(),
    )
}

/// Eye coordinates → world coordinates: the inverse of [`EyeFrame::to_eye`] (the axes
/// are orthonormal). For the default camera this is x_w = x_e, y_w = y_e, z_w = 20 − z_e.
pub fn to_world(eye: &EyeFrame, p: DVec3) -> DVec3 {
    eye.eye + eye.x_axis * p.x + eye.y_axis * p.y + eye.z_axis * p.z
}

/// Facts about a frame measured the way the pipeline sees it: through proto's camera
/// and pyramid planes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameStats {
    /// Polygons with every vertex outside one pyramid plane.
    pub outside: usize,
    /// Polygons with every vertex inside every pyramid plane.
    pub inside: usize,
    /// Σ projected area of the wholly inside polygons / screen area.
    pub depth_complexity: f64,
}

/// Measures a world-space frame against the default camera's pyramid for `view`.
pub fn frame_stats(polygons: &[Polygon], view: &View) -> FrameStats {
    use proto::geometry::{PyramidPlane, Side};
    let camera = Camera::default();
    let eye = camera.frame().unwrap_or_else(|_| unreachable!());
    let planes = PyramidPlane::ALL.map(|p| p.plane(view));
    let mut stats = FrameStats {
        outside: 0,
        inside: 0,
        depth_complexity: 0.0,
    };
    for poly in polygons {
        let eye_vertices: Vec<DVec4> = poly
            .vertices
            .iter()
            .map(|v| eye.to_eye(v.truncate()))
            .collect();
        let outside = planes.iter().any(|pl| {
            eye_vertices
                .iter()
                .all(|v| pl.classify(*v).0 == Side::Outside)
        });
        let inside = planes.iter().all(|pl| {
            eye_vertices
                .iter()
                .all(|v| pl.classify(*v).0 == Side::Inside)
        });
        if outside {
            stats.outside += 1;
        }
        if inside {
            stats.inside += 1;
            // Shoelace area in screen coordinates x_s, y_s ∈ [−1, 1] (screen area 4).
            let s: Vec<DVec2> = eye_vertices
                .iter()
                .map(|v| DVec2::new(v.x / (view.aspect * v.w), v.y / v.w))
                .collect();
            let twice: f64 = (0..s.len())
                .map(|i| s[i].perp_dot(s[(i + 1) % s.len()]))
                .sum();
            stats.depth_complexity += twice.abs() * 0.5 / 4.0;
        }
    }
    stats
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_environment_statistics() {
        let env = Environment::default();
        let frames = generate(&env);
        assert_eq!(frames.len(), 1);
        let frame = &frames[0];
        assert_eq!(frame.len(), 1000);
        assert!(frame.iter().all(|p| p.vertices.len() == 4));
        let stats = frame_stats(frame, &view_volume(1.0));
        // Every polygon is either wholly inside or wholly outside.
        assert_eq!(stats.inside + stats.outside, 1000);
        // Bernoulli(0.5) over 1000 polygons: σ ≈ 16; allow 3σ.
        assert!(
            (stats.outside as f64 - 500.0).abs() < 50.0,
            "outside {}",
            stats.outside
        );
        assert!(
            (stats.depth_complexity - 1.0).abs() < 1e-6,
            "Dc {}",
            stats.depth_complexity
        );
    }

    #[test]
    fn other_parameters_and_aspect() {
        let env = Environment {
            polygons: 400,
            clipped: 0.2,
            depth_complexity: 3.0,
            seed: 7,
            aspect: 16.0 / 9.0,
            frames: 3,
        };
        let frames = generate(&env);
        assert_eq!(frames.len(), 3);
        for frame in &frames {
            let stats = frame_stats(frame, &view_volume(env.aspect));
            assert_eq!(stats.inside + stats.outside, 400);
            // Bernoulli(0.2) over 400: σ = 8.
            assert!((stats.outside as f64 - 80.0).abs() < 30.0, "{stats:?}");
            assert!((stats.depth_complexity - 3.0).abs() < 1e-6, "{stats:?}");
        }
        // The polygons move between frames.
        assert_ne!(frames[0], frames[1]);
    }

    #[test]
    fn no_clipping_and_all_clipped() {
        let all_in = generate(&Environment {
            clipped: 0.0,
            polygons: 50,
            ..Environment::default()
        });
        let s = frame_stats(&all_in[0], &view_volume(1.0));
        assert_eq!((s.inside, s.outside), (50, 0));
        let all_out = generate(&Environment {
            clipped: 1.0,
            polygons: 50,
            ..Environment::default()
        });
        let s = frame_stats(&all_out[0], &view_volume(1.0));
        assert_eq!((s.inside, s.outside), (0, 50));
    }

    #[test]
    fn same_seed_same_scene_other_seed_other_scene() {
        let a = generate(&Environment::default());
        let b = generate(&Environment::default());
        let c = generate(&Environment {
            seed: 2,
            ..Environment::default()
        });
        assert_eq!(a, b);
        assert_ne!(a, c);
    }

    #[test]
    fn planar_convex_quads() {
        let frame = &generate(&Environment::default())[0];
        for p in frame {
            let v: Vec<DVec3> = p.vertices.iter().map(|v| v.truncate()).collect();
            // Planar: the fourth vertex lies on the plane of the first three.
            let n = (v[1] - v[0]).cross(v[2] - v[0]);
            let off = n.normalize().dot(v[3] - v[0]);
            assert!(off.abs() < 1e-9 * (1.0 + v[0].length()), "{off}");
            // Convex: every corner turns the same way about n.
            for i in 0..4 {
                let t = (v[(i + 1) % 4] - v[i]).cross(v[(i + 2) % 4] - v[(i + 1) % 4]);
                assert!(t.dot(n) > 0.0);
            }
        }
    }

    /// Uniform placement: about e^−Dc of the screen is left uncovered. Point samples on a
    /// 100×100 grid of pixel centres.
    #[test]
    fn empty_fraction_is_about_e_to_minus_dc() {
        let view = view_volume(1.0);
        let eye = Camera::default().frame().unwrap();
        let frame = &generate(&Environment::default())[0];
        let quads: Vec<Vec<DVec2>> = frame
            .iter()
            .map(|p| {
                p.vertices
                    .iter()
                    .map(|v| {
                        let e = eye.to_eye(v.truncate());
                        DVec2::new(e.x / e.w, e.y / e.w)
                    })
                    .collect()
            })
            .collect();
        // Only the visible ones: those beyond yon or behind the eye project onto the
        // screen too.
        let quads: Vec<Vec<DVec2>> = quads
            .into_iter()
            .zip(frame)
            .filter(|(_, p)| frame_stats(std::slice::from_ref(*p), &view).inside == 1)
            .map(|(q, _)| q)
            .collect();
        let n = 100;
        let mut empty = 0;
        for r in 0..n {
            for c in 0..n {
                let p = DVec2::new(
                    (c as f64 + 0.5) / n as f64 * 2.0 - 1.0,
                    (r as f64 + 0.5) / n as f64 * 2.0 - 1.0,
                );
                let covered = quads.iter().any(|q| {
                    let s: Vec<f64> = (0..4)
                        .map(|i| (q[(i + 1) % 4] - q[i]).perp_dot(p - q[i]))
                        .collect();
                    s.iter().all(|x| *x >= 0.0) || s.iter().all(|x| *x <= 0.0)
                });
                if !covered {
                    empty += 1;
                }
            }
        }
        let fraction = empty as f64 / (n * n) as f64;
        assert!(
            (fraction - (-1f64).exp()).abs() < 0.05,
            "empty fraction {fraction}"
        );
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(24))]
        /// For any parameters, every polygon is wholly inside or wholly outside the
        /// pyramid, and the inside ones cover exactly Dc screens, in every frame.
        #[test]
        fn every_polygon_wholly_in_or_out(
            polygons in 1usize..300,
            clipped in 0.0f64..=1.0,
            dc in 0.0f64..6.0,
            seed in proptest::prelude::any::<u64>(),
            aspect in 0.3f64..3.0,
        ) {
            let env = Environment { polygons, clipped, depth_complexity: dc, seed, aspect, frames: 3 };
            for frame in generate(&env) {
                let s = frame_stats(&frame, &view_volume(aspect));
                proptest::prop_assert_eq!(s.inside + s.outside, polygons);
                if s.inside > 0 {
                    // Exact unless a polygon had to shrink to fit the screen.
                    proptest::prop_assert!(s.depth_complexity <= dc * (1.0 + 1e-9));
                    if dc * 4.0 * aspect.max(1.0 / aspect) / (s.inside as f64) < 0.5 {
                        proptest::prop_assert!((s.depth_complexity - dc).abs() < 1e-6 * (1.0 + dc));
                    }
                }
            }
        }
    }
}
