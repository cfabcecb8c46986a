//! The test objects: the thesis INPUTTER's two penetrating polygons, spheres and a
//! building after Archuleta's figures (seed 003), the triangle piercing a square of the
//! Warnock chapter (seed 004), and a screen-filling mesh for crack tests.
//!
//! Every object is placed around the world origin, which the default camera (eye at
//! (0, 0, 20), s = 10, d = 16) sees at z_e = 20, where the visible square is
//! |x|, |y| ≤ 20·10/16 = 12.5.
//!
//! Movies: an object turns about the vertical axis through its centre, a full turn over
//! the movie (frame f at angle 2π·f/K), so that frame K would repeat frame 0. Shaded
//! objects are lit after turning, so the light stays put while the object turns.

use glam::{DMat3, DVec3};
use proto::shade::Lighting;
use proto::{Colour, Polygon};
use std::f64::consts::{PI, TAU};

/// A face of an object before viewing: a base colour and its vertices.
#[derive(Clone, Debug, PartialEq)]
pub struct Face {
    pub colour: Colour,
    pub points: Vec<DVec3>,
    /// A unit normal at each point, for [`Shading::Gouraud`] (an OBJ model's `vn`, or its
    /// faces' normals averaged, [`crate::obj::smooth_normals`]); empty: the normal of a
    /// sphere about the spin's centre.
    pub normals: Vec<DVec3>,
}

impl Face {
    pub fn new(colour: Colour, points: Vec<DVec3>) -> Self {
        Face {
            colour,
            points,
            normals: Vec::new(),
        }
    }
}

/// How a face's colour is chosen in each frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shading {
    /// The base colour as given.
    Flat,
    /// The base colour times 0.3 + 0.7·|n·l| for a fixed light direction l (up, right
    /// and towards the viewer): a constant-shaded polygon, as the thesis's pipeline draws
    /// them, but one that shows the object's shape.
    Lambert,
    /// [`Shading::Lambert`]'s light at each vertex instead, with the face's vertex normal
    /// there ([`Face::normals`]; without them the normal of a sphere about the spin's
    /// centre), as vertex colours: the polygons are Gouraud-shaded (docs/DESIGN.md,
    /// "Shading").
    Gouraud,
    /// The same vertex normals as [`Shading::Gouraud`]'s, sent as they are (the stream's
    /// header says `vertex-normals` and carries the lighting): the z-buffer interpolates
    /// them and lights each pixel, Phong shading. The face keeps its base colour.
    Phong,
}

/// The base colour lit for the unit normal `n` ([`Lighting::colour`]), kept unrounded
/// as a vertex colour.
fn lit(colour: Colour, n: DVec3, lighting: &Lighting) -> DVec3 {
    lighting.colour(proto::shade::colour(colour), n)
}

fn shade(face: &Face, points: &[DVec3], shading: Shading, lighting: &Lighting) -> Colour {
    match shading {
        Shading::Flat | Shading::Gouraud | Shading::Phong => face.colour,
        Shading::Lambert => {
            let n = proto::geometry::newell_normal(points).normalize_or_zero();
            lit(face.colour, n, lighting)
                .to_array()
                .map(|c| c.round().clamp(0.0, 255.0) as u8)
        }
    }
}

/// The frames of a movie of `faces` turning about the vertical axis through `centre`:
/// frame f is turned by 2π·f/`frames` (frame 0 is the object as given).
pub fn spin(faces: &[Face], frames: usize, centre: DVec3, shading: Shading) -> Vec<Vec<Polygon>> {
    spin_lit(faces, frames, centre, shading, &Lighting::default())
}

/// [`spin`] under `lighting` instead of the default light.
pub fn spin_lit(
    faces: &[Face],
    frames: usize,
    centre: DVec3,
    shading: Shading,
    lighting: &Lighting,
) -> Vec<Vec<Polygon>> {
    let frames = frames.max(1);
    (0..frames)
        .map(|f| {
            let turn = DMat3::from_rotation_y(TAU * f as f64 / frames as f64);
            faces
                .iter()
                .map(|face| {
                    let points: Vec<DVec3> = if f == 0 {
                        face.points.clone()
                    } else {
                        face.points
                            .iter()
                            .map(|p| centre + turn * (*p - centre))
                            .collect()
                    };
                    let colour = shade(face, &points, shading, lighting);
                    let mut polygon =
                        Polygon::new(colour, points.iter().map(|p| p.extend(1.0)).collect());
                    let normal = |k: usize, p: &DVec3| match face.normals.get(k) {
                        Some(n) => turn * *n,
                        None => (*p - centre).normalize_or_zero(),
                    };
                    match shading {
                        Shading::Gouraud => {
                            polygon.vertex_attrs = points
                                .iter()
                                .enumerate()
                                .map(|(k, p)| {
                                    lit(face.colour, normal(k, p), lighting)
                                        .clamp(DVec3::ZERO, DVec3::splat(255.0))
                                })
                                .collect();
                        }
                        Shading::Phong => {
                            polygon.vertex_attrs = points
                                .iter()
                                .enumerate()
                                .map(|(k, p)| normal(k, p))
                                .collect();
                        }
                        Shading::Flat | Shading::Lambert => {}
                    }
                    polygon
                })
                .collect()
        })
        .collect()
}

/// The thesis INPUTTER's scene (Appendix 4): a red triangle in the plane z = 0 and a
/// blue quadrilateral that slopes through it, so the two penetrate along a line.
pub fn penetrating() -> Vec<Face> {
    vec![
        Face::new(
            [255, 60, 60],
            vec![
                DVec3::new(-8.0, -4.0, 0.0),
                DVec3::new(0.0, 7.0, 0.0),
                DVec3::new(8.0, -4.0, 0.0),
            ],
        ),
        Face::new(
            [60, 60, 255],
            vec![
                DVec3::new(-9.0, 5.0, 4.0),
                DVec3::new(-7.0, 7.0, 4.0),
                DVec3::new(7.0, -7.0, -4.0),
                DVec3::new(5.0, -9.0, -4.0),
            ],
        ),
    ]
}

/// A latitude–longitude sphere: `stacks` bands from pole to pole, `slices` around; the
/// polar bands are triangles, the others quadrilaterals, every face wound
/// counter-clockwise seen from outside.
pub fn sphere(
    centre: DVec3,
    radius: f64,
    stacks: usize,
    slices: usize,
    colour: Colour,
) -> Vec<Face> {
    let stacks = stacks.max(2);
    let slices = slices.max(3);
    // The point at polar angle θ (from +y) and azimuth φ.
    let point = |i: usize, j: usize| {
        let theta = PI * i as f64 / stacks as f64;
        let phi = TAU * (j % slices) as f64 / slices as f64;
        if i == 0 {
            return centre + DVec3::Y * radius;
        }
        if i == stacks {
            return centre - DVec3::Y * radius;
        }
        centre
            + radius
                * DVec3::new(
                    theta.sin() * phi.sin(),
                    theta.cos(),
                    theta.sin() * phi.cos(),
                )
    };
    let mut faces = Vec::with_capacity(stacks * slices);
    for i in 0..stacks {
        for j in 0..slices {
            let points = if i == 0 {
                vec![point(0, j), point(1, j), point(1, j + 1)]
            } else if i == stacks - 1 {
                vec![point(i, j), point(i + 1, j), point(i, j + 1)]
            } else {
                vec![
                    point(i, j),
                    point(i + 1, j),
                    point(i + 1, j + 1),
                    point(i, j + 1),
                ]
            };
            faces.push(Face::new(colour, points));
        }
    }
    faces
}

/// Two intersecting spheres, as in Archuleta's figure 1 (seed 003): a red one on the left
/// and a slightly nearer blue one on the right, overlapping by about a third of a radius.
pub fn spheres(stacks: usize, slices: usize) -> Vec<Face> {
    let mut faces = Vec::new();
    for (centre, radius, colour) in [
        (DVec3::new(-3.5, 0.0, -1.0), 6.0, [230, 70, 60]),
        (DVec3::new(3.5, 0.5, 1.0), 5.0, [70, 110, 235]),
    ] {
        // Each sphere's normals from its own centre (the spin's centre is the origin,
        // which neither is about), for --gouraud and --phong.
        faces.extend(
            sphere(centre, radius, stacks, slices, colour)
                .into_iter()
                .map(|mut f| {
                    f.normals = f
                        .points
                        .iter()
                        .map(|p| (*p - centre).normalize_or_zero())
                        .collect();
                    f
                }),
        );
    }
    faces
}

/// An axis-aligned rectangle in one of a box's wall planes, as a face wound
/// counter-clockwise about `normal`: `origin` is its lower-left corner seen from outside,
/// `right` and `up` its sides.
fn rectangle(colour: Colour, origin: DVec3, right: DVec3, up: DVec3) -> Face {
    Face::new(
        colour,
        vec![origin, origin + right, origin + right + up, origin + up],
    )
}

/// A building after Archuleta's figures 2 and 3 (seed 003): a box of `floors` storeys
/// with `bays` windows a floor on the long walls and half as many on the short walls,
/// each window a separate quadrilateral a little in front of its wall, a door, and a
/// gable roof. Turned 30° about the vertical and tipped 15° towards the viewer so that
/// two walls and the roof show. With the defaults (4 floors, 5 bays) it has 72
/// polygons and 286 edges.
pub fn building(floors: usize, bays: usize) -> Vec<Face> {
    let floors = floors.max(1);
    let bays = bays.max(1);
    let (width, depth, storey) = (14.0, 8.0, 2.2);
    let height = storey * floors as f64;
    let (hw, hd) = (width / 2.0, depth / 2.0);
    let base = -height / 2.0 - 1.0;
    let wall: Colour = [205, 185, 150];
    let window: Colour = [90, 140, 200];
    let door: Colour = [120, 70, 40];
    let roof: Colour = [170, 60, 45];
    let gable: Colour = [190, 170, 135];
    // The four walls: (lower-left corner seen from outside, rightwards, outward normal).
    let walls = [
        (DVec3::new(-hw, base, hd), DVec3::X * width, DVec3::Z),
        (DVec3::new(hw, base, hd), -DVec3::Z * depth, DVec3::X),
        (DVec3::new(hw, base, -hd), -DVec3::X * width, -DVec3::Z),
        (DVec3::new(-hw, base, -hd), DVec3::Z * depth, -DVec3::X),
    ];
    let up = DVec3::Y * height;
    let mut faces = Vec::new();
    for (k, &(corner, right, normal)) in walls.iter().enumerate() {
        faces.push(rectangle(wall, corner, right, up));
        let long = k % 2 == 0;
        let n = if long { bays } else { bays.div_ceil(2) };
        let bay = right / n as f64;
        let lift = normal * 0.05;
        for floor in 0..floors {
            for b in 0..n {
                let sill = DVec3::Y * (storey * floor as f64 + 0.7);
                let origin = corner + lift + sill + bay * (b as f64 + 0.25);
                // The middle bay of the ground floor of the front wall is the door.
                if k == 0 && floor == 0 && b == n / 2 {
                    let o = corner + lift + bay * (b as f64 + 0.2);
                    faces.push(rectangle(door, o, bay * 0.6, DVec3::Y * (storey * 0.85)));
                } else {
                    faces.push(rectangle(
                        window,
                        origin,
                        bay * 0.5,
                        DVec3::Y * (storey * 0.45),
                    ));
                }
            }
        }
    }
    // The gable roof: ridge along x, 3 units above the eaves, overhanging by 0.5.
    let top = base + height;
    let ridge = top + 3.0;
    let (ox, oz) = (hw + 0.5, hd + 0.5);
    faces.push(Face::new(
        roof,
        vec![
            DVec3::new(-ox, top - 0.3, oz),
            DVec3::new(ox, top - 0.3, oz),
            DVec3::new(ox, ridge, 0.0),
            DVec3::new(-ox, ridge, 0.0),
        ],
    ));
    faces.push(Face::new(
        roof,
        vec![
            DVec3::new(ox, top - 0.3, -oz),
            DVec3::new(-ox, top - 0.3, -oz),
            DVec3::new(-ox, ridge, 0.0),
            DVec3::new(ox, ridge, 0.0),
        ],
    ));
    for sx in [-1.0, 1.0] {
        let x = sx * hw;
        let (a, b) = if sx > 0.0 { (hd, -hd) } else { (-hd, hd) };
        faces.push(Face::new(
            gable,
            vec![
                DVec3::new(x, top, a),
                DVec3::new(x, top, b),
                DVec3::new(x, ridge - 0.2, 0.0),
            ],
        ));
    }
    let pose =
        DMat3::from_rotation_x(15f64.to_radians()) * DMat3::from_rotation_y(-30f64.to_radians());
    for face in &mut faces {
        for p in &mut face.points {
            *p = pose * *p;
        }
    }
    faces
}

/// Half the side of the square the default camera sees at the world origin (z_e = 20):
/// 20·s/d = 12.5.
pub const HALF_VIEW_AT_ORIGIN: f64 = 12.5;

/// A `cols`×`rows` mesh of quadrilaterals in the plane z = 0 that covers the whole screen
/// of the default camera (for aspect ratio `aspect`) and a little more (2%), each quad
/// its own colour, neighbours sharing their edges exactly (the same vertex values).
///
/// In a movie the interior vertices wobble (each by at most 0.15 of a cell along each
/// axis, so every quad stays convex) while the border stays put: the mesh still covers
/// the screen and still shares its edges, so any crack or double-drawn pixel is a bug.
pub fn mesh(cols: usize, rows: usize, aspect: f64, frames: usize) -> Vec<Vec<Polygon>> {
    let cols = cols.max(1);
    let rows = rows.max(1);
    let half_h = HALF_VIEW_AT_ORIGIN * 1.02;
    let half_w = half_h * aspect;
    let (cw, ch) = (2.0 * half_w / cols as f64, 2.0 * half_h / rows as f64);
    let frames = frames.max(1);
    (0..frames)
        .map(|f| {
            let phase = TAU * f as f64 / frames as f64;
            let vertex = |i: usize, j: usize| {
                let mut x = -half_w + cw * i as f64;
                let mut y = half_h - ch * j as f64;
                if f > 0 && i > 0 && i < cols && j > 0 && j < rows {
                    x += 0.15 * cw * (phase + 0.7 * i as f64 + 1.3 * j as f64).sin();
                    y += 0.15 * ch * (phase + 1.1 * i as f64 - 0.9 * j as f64).cos();
                }
                glam::DVec4::new(x, y, 0.0, 1.0)
            };
            let mut polygons = Vec::with_capacity(cols * rows);
            for j in 0..rows {
                for i in 0..cols {
                    polygons.push(Polygon::new(
                        mesh_colour(i, j, cols, rows),
                        vec![
                            vertex(i, j),
                            vertex(i, j + 1),
                            vertex(i + 1, j + 1),
                            vertex(i + 1, j),
                        ],
                    ));
                }
            }
            polygons
        })
        .collect()
}

/// A colour of its own for each cell (for meshes of up to 2^24 cells): a gradient that
/// tells position, with the low bits of the cell number mixed in so neighbours differ.
fn mesh_colour(i: usize, j: usize, cols: usize, rows: usize) -> Colour {
    let k = (j * cols + i) as u32;
    // A bijective mix of the cell number (odd multiplier modulo 2^24), so that no two
    // cells of a mesh of up to 2^24 cells share a colour.
    let m = k.wrapping_mul(0x9E3779) & 0xFF_FFFF;
    let _ = (cols, rows);
    [(m >> 16) as u8, (m >> 8) as u8, m as u8]
}

/// `scene needles`: 24 triangles a quarter of a world unit (about half a pixel at 64×48)
/// wide at their base on y = −10, each tapering to a point on y = 10 leaning by −3 to 3
/// units, at depths −2 to 2: edges at many slopes that point sampling breaks into dashes
/// (docs/antialiasing.md; the sampling thesis, 6.3, on the a-buffer's thin polygons).
pub fn needles() -> Vec<Face> {
    (0..24u8)
        .map(|i| {
            let x = -11.0 + f64::from(i) * 0.93;
            let lean = f64::from(i % 7) - 3.0;
            let z = f64::from(i % 5) - 2.0;
            Face::new(
                [255 - i * 8, 60 + i * 7, 40 + i * 9],
                vec![
                    DVec3::new(x, -10.0, z),
                    DVec3::new(x + 0.25, -10.0, z),
                    DVec3::new(x + lean, 10.0, z),
                ],
            )
        })
        .collect()
}

/// The triangle piercing a square of the Warnock chapter (seed 004, figure 14-8a): a
/// green square facing the viewer in the plane z = 0, and a yellow triangle whose base is
/// behind the square and whose tip comes through it, so that the line where they meet,
/// the *implied edge*, is visible.
pub fn triangle_square() -> Vec<Face> {
    vec![
        Face::new(
            [60, 200, 80],
            vec![
                DVec3::new(-6.0, -6.0, 0.0),
                DVec3::new(6.0, -6.0, 0.0),
                DVec3::new(6.0, 6.0, 0.0),
                DVec3::new(-6.0, 6.0, 0.0),
            ],
        ),
        Face::new(
            [240, 200, 40],
            vec![
                DVec3::new(-8.0, -8.0, -5.0),
                DVec3::new(8.0, -8.0, -5.0),
                DVec3::new(0.0, 3.0, 4.0),
            ],
        ),
    ]
}

// ---------------------------------------------------------------------------------------
// Hostile scenes: depth complexity, slivers, many fragments in one pixel, and planes that
// all pass through each other. They are what a user can make in a minute to break a
// hidden-surface method, and what the methods' bounds are tested on.

/// Half the side of the square every hostile "full-screen" polygon spans: wide enough to
/// cover the default camera's screen at every depth these scenes use (|z| ≤ 8, where the
/// visible half side is at most (20 + 8)·10/16 = 17.5), so the clipper cuts them to the
/// screen.
pub const FULL_SCREEN_HALF: f64 = 20.0;

/// A colour of its own for polygon `k` of up to 2^24: the bijective mix of
/// [`mesh_colour`], kept away from black (the background) by setting the top bit of red.
pub(crate) fn hostile_colour(k: usize) -> Colour {
    let m = (k as u32).wrapping_mul(0x9E3779) & 0xFF_FFFF;
    [(m >> 16) as u8 | 0x80, (m >> 8) as u8, m as u8]
}

/// The order in which a hostile scene writes its `n` polygons: k·p mod n for a step p
/// prime to n near n·0.618, so the stream is neither back to front nor front to back
/// (each order favours some method).
pub(crate) fn shuffled(n: usize) -> impl Iterator<Item = usize> {
    let mut p = ((n as f64 * 0.618) as usize).max(1);
    while gcd(p, n.max(1)) != 1 {
        p += 1;
    }
    (0..n).map(move |k| (k * p) % n)
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// `scene stack N`: N full-screen squares facing the viewer, stacked in depth from
/// z = −6 to z = 6 (distinct depths), written in a shuffled order: depth complexity N at
/// every pixel, the worst case for any method whose cost follows the polygons that
/// cover a pixel rather than the visible ones.
pub fn stack(n: usize) -> Vec<Face> {
    let h = FULL_SCREEN_HALF;
    shuffled(n)
        .map(|k| {
            let z = if n > 1 {
                -6.0 + 12.0 * k as f64 / (n - 1) as f64
            } else {
                0.0
            };
            Face::new(
                hostile_colour(k),
                vec![
                    DVec3::new(-h, -h, z),
                    DVec3::new(h, -h, z),
                    DVec3::new(h, h, z),
                    DVec3::new(-h, h, z),
                ],
            )
        })
        .collect()
}

/// `scene slivers N`: N long thin triangles across the screen, each from a point on the
/// left edge to a short base on the right edge (0.02 world units, about 0.4 of a pixel at
/// 500×500), at random heights, slopes and depths (|z| ≤ 4, tilted in depth along their
/// length), crossing one another everywhere: many edges, little area, the worst case for
/// area subdivision along edges and for scan-line segment lists.
pub fn slivers(n: usize, seed: u64) -> Vec<Face> {
    let mut rng = fastrand::Rng::with_seed(seed);
    let x = HALF_VIEW_AT_ORIGIN * 1.05;
    (0..n)
        .map(|k| {
            let y0 = (rng.f64() * 2.0 - 1.0) * HALF_VIEW_AT_ORIGIN;
            let y1 = (rng.f64() * 2.0 - 1.0) * HALF_VIEW_AT_ORIGIN;
            let z0 = (rng.f64() * 2.0 - 1.0) * 4.0;
            let z1 = (rng.f64() * 2.0 - 1.0) * 4.0;
            let (a, b) = if rng.bool() { (-x, x) } else { (x, -x) };
            Face::new(
                hostile_colour(k),
                vec![
                    DVec3::new(a, y0, z0),
                    DVec3::new(b, y1 - 0.01, z1),
                    DVec3::new(b, y1 + 0.01, z1),
                ],
            )
        })
        .collect()
}

/// The world point that the default camera at 500×500 sees at the centre of pixel
/// (250, 249): one pixel there is 25/500 = 0.05 world units wide.
pub const PINHEAD_CENTRE: (f64, f64) = (0.025, 0.025);

/// `scene pinhead N`: N tiny triangles around one point ([`PINHEAD_CENTRE`]), each
/// containing it (three vertices at random radii 0.012 to 0.03 and angles about 120°
/// apart), at N distinct depths in a shuffled order (|z| ≤ 2): at 500×500 they all
/// cover the centre of one pixel and parts of its neighbours, N fragments in a pixel.
pub fn pinhead(n: usize, seed: u64) -> Vec<Face> {
    let mut rng = fastrand::Rng::with_seed(seed);
    let (cx, cy) = PINHEAD_CENTRE;
    shuffled(n)
        .map(|k| {
            let z = if n > 1 {
                -2.0 + 4.0 * k as f64 / (n - 1) as f64
            } else {
                0.0
            };
            let start = rng.f64() * TAU;
            let points = (0..3)
                .map(|i| {
                    let angle = start + TAU * i as f64 / 3.0 + (rng.f64() - 0.5) * 0.6;
                    let r = 0.012 + 0.018 * rng.f64();
                    DVec3::new(cx + r * angle.cos(), cy + r * angle.sin(), z)
                })
                .collect();
            Face::new(hostile_colour(k), points)
        })
        .collect()
}

/// `scene planes N`: N full-screen planes through the origin's neighbourhood, plane k
/// tilted by 0.3 (about 17°) about the axis at angle π·k/N in the screen, and shifted in
/// depth by at most ±0.5: every pair crosses inside the screen, so no plane is wholly in
/// front of another and a depth sort must cut them (the painter's hardest case).
pub fn planes(n: usize) -> Vec<Face> {
    let h = FULL_SCREEN_HALF;
    (0..n)
        .map(|k| {
            let phi = PI * k as f64 / n.max(1) as f64;
            let (gx, gy) = (0.3 * phi.cos(), 0.3 * phi.sin());
            let offset = if n > 1 {
                -0.5 + k as f64 / (n - 1) as f64
            } else {
                0.0
            };
            let z = |x: f64, y: f64| gx * x + gy * y + offset;
            Face::new(
                hostile_colour(k),
                [(-h, -h), (h, -h), (h, h), (-h, h)]
                    .iter()
                    .map(|&(x, y)| DVec3::new(x, y, z(x, y)))
                    .collect(),
            )
        })
        .collect()
}

/// `scene strips N`: N horizontal strips, each the screen's width and 1/N of its height
/// (no two overlap on the screen), each slanted in depth from z = −3 at one end to 3 at
/// the other (drawn so that its edges are level on the screen): every strip's depth extent overlaps every other's, so a depth sort that
/// resolves overlaps by extents alone compares every pair (the painter's quadratic case),
/// though no pixel has more than one polygon.
pub fn strips(n: usize) -> Vec<Face> {
    let (w, top) = (FULL_SCREEN_HALF, HALF_VIEW_AT_ORIGIN);
    let band = 2.0 * top / n.max(1) as f64;
    shuffled(n)
        .map(|k| {
            let (y0, y1) = (top - band * (k + 1) as f64, top - band * k as f64);
            let (zl, zr) = if k % 2 == 0 { (-3.0, 3.0) } else { (3.0, -3.0) };
            // y scaled by (20 − z)/20, the eye's distance over the origin's, so that the
            // strip's edges are the horizontal lines y0 and y1 on the screen, wherever
            // along the strip the depth is.
            let at = |x: f64, y: f64, z: f64| DVec3::new(x, y * (20.0 - z) / 20.0, z);
            Face::new(
                hostile_colour(k),
                vec![at(-w, y0, zl), at(w, y0, zr), at(w, y1, zr), at(-w, y1, zl)],
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn needles_are_24_thin_triangles_at_many_slopes() {
        let n = needles();
        assert_eq!(n.len(), 24);
        assert_eq!(
            n[0],
            Face::new(
                [255, 60, 40],
                vec![
                    DVec3::new(-11.0, -10.0, -2.0),
                    DVec3::new(-10.75, -10.0, -2.0),
                    DVec3::new(-14.0, 10.0, -2.0)
                ]
            )
        );
        assert_eq!(n[23].colour, [71, 221, 247]);
        assert_eq!(
            n[23].points[2],
            DVec3::new(-11.0 + 23.0 * 0.93 - 1.0, 10.0, 1.0)
        );
    }

    #[test]
    fn penetrating_is_the_inputter_scene() {
        let frames = spin(&penetrating(), 1, DVec3::ZERO, Shading::Flat);
        assert_eq!(
            frames,
            vec![vec![
                Polygon::from_xyz(
                    [255, 60, 60],
                    &[[-8.0, -4.0, 0.0], [0.0, 7.0, 0.0], [8.0, -4.0, 0.0]]
                ),
                Polygon::from_xyz(
                    [60, 60, 255],
                    &[
                        [-9.0, 5.0, 4.0],
                        [-7.0, 7.0, 4.0],
                        [7.0, -7.0, -4.0],
                        [5.0, -9.0, -4.0]
                    ]
                ),
            ]]
        );
    }

    #[test]
    fn spin_turns_about_the_vertical_axis() {
        let frames = spin(&penetrating(), 4, DVec3::ZERO, Shading::Flat);
        assert_eq!(frames.len(), 4);
        // A quarter turn about +y: (x, y, z) → (z, y, −x).
        let v = frames[1][0].vertices[0];
        assert!(
            (v - glam::DVec4::new(0.0, -4.0, 8.0, 1.0)).length() < 1e-12,
            "{v}"
        );
        // Half a turn: (x, y, z) → (−x, y, −z).
        let v = frames[2][1].vertices[0];
        assert!(
            (v - glam::DVec4::new(9.0, 5.0, -4.0, 1.0)).length() < 1e-12,
            "{v}"
        );
    }

    #[test]
    fn sphere_faces_lie_on_the_sphere_and_wind_outwards() {
        let c = DVec3::new(1.0, 2.0, 3.0);
        let faces = sphere(c, 5.0, 6, 8, [1, 2, 3]);
        assert_eq!(faces.len(), 48);
        assert_eq!(faces.iter().filter(|f| f.points.len() == 3).count(), 16);
        for f in &faces {
            for p in &f.points {
                assert!(((*p - c).length() - 5.0).abs() < 1e-12);
            }
            let n = proto::geometry::newell_normal(&f.points);
            let mid = f.points.iter().copied().sum::<DVec3>() / f.points.len() as f64;
            assert!(n.dot(mid - c) > 0.0, "face winds inwards: {:?}", f.points);
        }
    }

    #[test]
    fn building_has_a_few_hundred_edges() {
        let faces = building(4, 5);
        let edges: usize = faces.iter().map(|f| f.points.len()).sum();
        assert_eq!(faces.len(), 72);
        assert_eq!(edges, 286);
        // Everything in front of the eye and within the visible square at its depth.
        for f in &faces {
            for p in &f.points {
                let z_e = 20.0 - p.z;
                let half = z_e * 10.0 / 16.0;
                assert!(z_e > 1.0 && z_e < 30.0);
                assert!(p.x.abs() < half && p.y.abs() < half, "{p}");
            }
        }
    }

    #[test]
    fn mesh_shares_edges_and_covers_the_screen() {
        for frames in [mesh(4, 3, 1.0, 1), mesh(4, 3, 1.0, 3)] {
            for frame in &frames {
                assert_eq!(frame.len(), 12);
                // Cell (i, j)'s right edge is cell (i+1, j)'s left edge, reversed.
                let right = &frame[1].vertices;
                let left = &frame[0].vertices;
                assert_eq!((left[3], left[2]), (right[0], right[1]));
                // The corners cover the visible square with 2% to spare.
                let x0 = frame[0].vertices[0].x;
                assert!(x0 < -12.5 && x0 > -13.0);
            }
        }
        let colours: std::collections::HashSet<_> =
            mesh(64, 64, 1.0, 1)[0].iter().map(|p| p.colour).collect();
        assert_eq!(colours.len(), 64 * 64);
    }

    /// Screen position under the default camera: x·16/(10·(20 − z)) of the half side.
    fn on_screen(p: DVec3) -> (f64, f64) {
        let k = 20.0 / (20.0 - p.z);
        (p.x * k, p.y * k)
    }

    #[test]
    fn stack_covers_the_screen_at_distinct_depths() {
        let faces = stack(100);
        assert_eq!(faces.len(), 100);
        let mut depths: Vec<f64> = faces.iter().map(|f| f.points[0].z).collect();
        assert!(faces
            .iter()
            .all(|f| f.points.iter().all(|p| p.z == f.points[0].z)));
        // Neither back to front nor front to back.
        assert!(depths.windows(2).any(|w| w[0] < w[1]));
        assert!(depths.windows(2).any(|w| w[0] > w[1]));
        depths.sort_by(f64::total_cmp);
        assert_eq!(depths[0], -6.0);
        assert_eq!(depths[99], 6.0);
        assert!(depths.windows(2).all(|w| w[0] < w[1]));
        for f in &faces {
            // Each corner is outside the visible square at its depth.
            for p in &f.points {
                let (x, y) = on_screen(*p);
                assert!(x.abs() > HALF_VIEW_AT_ORIGIN && y.abs() > HALF_VIEW_AT_ORIGIN);
            }
        }
        let colours: std::collections::HashSet<_> = faces.iter().map(|f| f.colour).collect();
        assert_eq!(colours.len(), 100);
    }

    #[test]
    fn pinhead_triangles_all_contain_the_centre() {
        let (cx, cy) = PINHEAD_CENTRE;
        let faces = pinhead(500, 3);
        assert_eq!(faces.len(), 500);
        for f in &faces {
            assert_eq!(f.points.len(), 3);
            // The centre is on the same side of all three edges.
            let sides: Vec<f64> = (0..3)
                .map(|i| {
                    let (a, b) = (f.points[i], f.points[(i + 1) % 3]);
                    (b.x - a.x) * (cy - a.y) - (b.y - a.y) * (cx - a.x)
                })
                .collect();
            assert!(
                sides.iter().all(|s| *s > 0.0) || sides.iter().all(|s| *s < 0.0),
                "{f:?}"
            );
            // Inside one pixel's neighbourhood: 0.03 world units is 0.6 pixel at 500×500.
            assert!(f
                .points
                .iter()
                .all(|p| (p.x - cx).hypot(p.y - cy) <= 0.0300001));
        }
    }

    #[test]
    fn every_pair_of_planes_crosses_on_the_screen() {
        let faces = planes(7);
        let plane = |f: &Face| {
            let n = proto::geometry::newell_normal(&f.points);
            (n, n.dot(f.points[0]))
        };
        for i in 0..faces.len() {
            for j in i + 1..faces.len() {
                // z_i − z_j changes sign over the screen's corners at z ≈ 0.
                let (ni, di) = plane(&faces[i]);
                let (nj, dj) = plane(&faces[j]);
                let z = |n: DVec3, d: f64, x: f64, y: f64| (d - n.x * x - n.y * y) / n.z;
                let h = HALF_VIEW_AT_ORIGIN * 0.8;
                let signs: Vec<bool> = [(-h, -h), (h, -h), (h, h), (-h, h)]
                    .iter()
                    .map(|&(x, y)| z(ni, di, x, y) > z(nj, dj, x, y))
                    .collect();
                assert!(signs.contains(&true) && signs.contains(&false), "{i} {j}");
            }
        }
    }

    #[test]
    fn strips_are_level_and_disjoint_on_screen_with_overlapping_depths() {
        let n = 30;
        let faces = strips(n);
        let mut bands: Vec<(f64, f64)> = faces
            .iter()
            .map(|f| {
                let ys: Vec<f64> = f.points.iter().map(|p| on_screen(*p).1).collect();
                // The bottom edge is level, and so is the top.
                assert!((ys[0] - ys[1]).abs() < 1e-9 && (ys[2] - ys[3]).abs() < 1e-9);
                let zs: Vec<f64> = f.points.iter().map(|p| p.z).collect();
                assert_eq!(zs.iter().cloned().fold(f64::INFINITY, f64::min), -3.0);
                assert_eq!(zs.iter().cloned().fold(f64::NEG_INFINITY, f64::max), 3.0);
                (ys[0], ys[2])
            })
            .collect();
        bands.sort_by(|a, b| a.0.total_cmp(&b.0));
        for w in bands.windows(2) {
            assert!((w[0].1 - w[1].0).abs() < 1e-9, "{w:?}");
        }
        assert!((bands[0].0 + HALF_VIEW_AT_ORIGIN).abs() < 1e-9);
        assert!((bands[n - 1].1 - HALF_VIEW_AT_ORIGIN).abs() < 1e-9);
    }

    #[test]
    fn slivers_cross_the_screen_thinly() {
        let faces = slivers(50, 1);
        assert_eq!(faces.len(), 50);
        for f in &faces {
            let width = f.points[1].distance(f.points[2]);
            assert!((width - 0.02).abs() < 1e-9);
            assert!((f.points[0].x - f.points[1].x).abs() > 2.0 * HALF_VIEW_AT_ORIGIN);
        }
        assert_eq!(slivers(50, 1), faces);
        assert_ne!(slivers(50, 2), faces);
    }

    #[test]
    fn triangle_tip_pierces_the_square() {
        let faces = triangle_square();
        let tip = faces[1].points[2];
        assert!(tip.z > 0.0 && tip.x.abs() < 6.0 && tip.y.abs() < 6.0);
        assert!(faces[1].points[..2].iter().all(|p| p.z < 0.0));
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(32))]
        /// In every frame the mesh's quads are convex, wound the same way, and tile the
        /// covered rectangle: their areas sum to its area.
        #[test]
        fn wobbling_mesh_tiles_its_rectangle(cols in 1usize..12, rows in 1usize..12, aspect in 0.5f64..2.0) {
            let half_h = HALF_VIEW_AT_ORIGIN * 1.02;
            let rect = 4.0 * half_h * half_h * aspect;
            for frame in mesh(cols, rows, aspect, 4) {
                let mut total = 0.0;
                for p in &frame {
                    let v: Vec<glam::DVec2> = p.vertices.iter().map(|v| v.truncate().truncate()).collect();
                    for k in 0..4 {
                        let turn = (v[(k + 1) % 4] - v[k]).perp_dot(v[(k + 2) % 4] - v[(k + 1) % 4]);
                        proptest::prop_assert!(turn > 0.0);
                    }
                    total += (0..4).map(|k| v[k].perp_dot(v[(k + 1) % 4])).sum::<f64>() / 2.0;
                }
                proptest::prop_assert!((total - rect).abs() < 1e-9 * rect);
            }
        }
    }
}
