//! What the geometry tests build their scenes from: a generator of the same cases on
//! every run, points on one tilted plane, and eye-space points placed on the screen.

use proto::perspective::{DepthMode, Perspective};
use proto::{DVec4, View};

/// A small linear congruential generator (Knuth's MMIX constants), for cases that are
/// the same on every run and platform with no dependency on the rand crates' streams.
#[derive(Clone, Debug)]
pub struct Lcg(pub u64);

impl Lcg {
    /// The next number in 0..n, from the state's high bits.
    pub fn next(&mut self, n: u64) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 33) % n
    }
}

/// A world-space point on the plane z = (0.3x + 0.7y)/3, written to 16 digits as a user
/// would (a line of a scene's polygon).
pub fn on_tilted_plane(x: f64, y: f64) -> String {
    format!("{x:.16} {y:.16} {:.16}\n", (0.3 * x + 0.7 * y) / 3.0)
}

/// Decals on one tilted plane ([`on_tilted_plane`]), a world-space scene of the first
/// `n` (at most 3) of: a red quad, a green quad inside it, a blue triangle inside that.
/// Coplanar polygons tie at every pixel, and the earlier one must show.
pub fn tilted_decals(n: usize) -> String {
    let decals: [(&str, &[(f64, f64)]); 3] = [
        (
            "255 0 0",
            &[(-8.0, -6.0), (8.1, -5.7), (7.9, 6.2), (-8.3, 5.9)],
        ),
        (
            "0 255 0",
            &[(-5.1, -3.3), (2.2, -4.1), (3.3, 2.7), (-4.4, 3.1)],
        ),
        ("0 0 255", &[(0.3, -2.2), (6.1, 0.4), (1.3, 4.4)]),
    ];
    let mut s = String::from("polypipe 1 world\n");
    for (i, (colour, corners)) in decals.iter().take(n).enumerate() {
        if i > 0 {
            s += "NEXT.POLYGON\n";
        }
        s += &format!("colour {colour}\n");
        for &(x, y) in *corners {
            s += &on_tilted_plane(x, y);
        }
    }
    s + "END\n"
}

/// The default camera's projection (s = 10, d = 16, so w = z_e·s/d) onto a `w`×`h`
/// screen, with projective depth.
pub fn projective(w: u32, h: u32) -> Perspective {
    let view = View {
        aspect: w as f64 / h as f64,
        ..View::default()
    };
    Perspective::new(w, h, view, DepthMode::Projective).unwrap()
}

/// An eye-space vertex that [`projective`]`(w, h)` puts at screen point (X, Y) (to
/// rounding), at depth z_e. X, Y on a half-pixel lattice put pixel centres on the edges.
pub fn eye_at((w, h): (u32, u32), x: f64, y: f64, z: f64) -> DVec4 {
    let ww = z * 0.625;
    let a = w as f64 / h as f64;
    DVec4::new(
        (2.0 * x / w as f64 - 1.0) * a * ww,
        (1.0 - 2.0 * y / h as f64) * ww,
        z,
        ww,
    )
}
