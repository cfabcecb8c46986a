//! The z-buffer's precision failure near yon, measured for each depth form persp writes
//! (docs/methods.md, "The z-buffer near yon").
//!
//! Two parallel squares face the eye near yon, at z_e = 0.88·K2, a red one first in the
//! stream and a blue one a relative gap g nearer. The tie rule (docs/DESIGN.md,
//! "Visibility") puts blue in front exactly when g > 2⁻³⁰. For each form, each
//! hither/yon ratio and each gap, this computes the two depths as persp writes them (a
//! square facing the eye has one depth at every pixel, so the vertex depth is every
//! pixel's) and decides as the z-buffer does, then prints whether the form draws the
//! pair as the rule says: ✓ right, ✗ wrong. The form that persp wrote before the rule,
//! projective depth in 2⁻⁴⁰ fixed point compared strictly, is the first table.
//!
//!     cargo run --release -p pipeline-tests --example depth_precision

use proto::perspective::{DepthMode, Perspective};
use proto::{DVec4, View};

/// The gaps of the table's columns.
pub const GAPS: [f64; 11] = [
    1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12,
];
/// Hither distances for yon 1000: ratios 10³ to 10⁹.
pub const HITHERS: [f64; 7] = [1.0, 1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6];

/// Whether a form draws blue (at eye depth `near`) over red (at `far`) in a view.
type Draws = Box<dyn Fn(View, f64, f64) -> bool>;

/// The forms compared, by name.
fn forms() -> Vec<(&'static str, Draws)> {
    let depth = |mode: DepthMode, view: View, z: f64| {
        let p = Perspective::new(1, 1, view, mode).expect("a square screen");
        p.project_vertex(DVec4::new(0.0, 0.0, z, z * 0.625)).z
    };
    vec![
        (
            "projective, 2⁻⁴⁰ fixed point, strictly nearer (before the rule)",
            Box::new(move |view, far, near| {
                let fixed =
                    |z: f64| (depth(DepthMode::Projective, view, z) * 2f64.powi(40)).round() as i64;
                fixed(near) < fixed(far)
            }),
        ),
        (
            "projective, f64, the rule (`--zmode projective`)",
            Box::new(move |view, far, near| {
                proto::depth::takes(
                    depth(DepthMode::Projective, view, near),
                    depth(DepthMode::Projective, view, far),
                )
            }),
        ),
        (
            "projective, f64, strictly nearer (no tie width: decals z-fight)",
            Box::new(move |view, far, near| {
                depth(DepthMode::Projective, view, near) < depth(DepthMode::Projective, view, far)
            }),
        ),
        (
            "eye-z, f64, the rule (`--zmode eye-z`)",
            Box::new(move |view, far, near| {
                proto::depth::takes(
                    depth(DepthMode::EyeZ, view, near),
                    depth(DepthMode::EyeZ, view, far),
                )
            }),
        ),
        (
            "reciprocal −K1/z_e, f64, the rule (the default)",
            Box::new(move |view, far, near| {
                proto::depth::takes(
                    depth(DepthMode::Reciprocal, view, near),
                    depth(DepthMode::Reciprocal, view, far),
                )
            }),
        ),
    ]
}

fn main() {
    for (name, blue_drawn) in forms() {
        println!("{name}:\n");
        print!("| yon/hither |");
        for g in GAPS {
            print!(" {g:.0e} |");
        }
        print!("\n|---|");
        for _ in GAPS {
            print!("---|");
        }
        println!();
        for k1 in HITHERS {
            let view = View {
                aspect: 1.0,
                hither: k1,
                yon: 1000.0,
            };
            print!("| {:.0e} |", 1000.0 / k1);
            for g in GAPS {
                let far = 0.88 * view.yon;
                let near = far * (1.0 - g);
                let rule = proto::depth::takes(near, far);
                let right = blue_drawn(view, far, near) == rule;
                print!(" {} |", if right { "✓" } else { "✗" });
            }
            println!();
        }
        println!();
    }
}
