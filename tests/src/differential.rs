//! The differential suite: random scenes, seeded, drawn by every mode that claims the
//! reference's bytes, and each compared with what it claims to equal (README.md and
//! docs/antialiasing.md; docs/fuzzing.md, "The differential suite").
//!
//! A seed picks one scene ([`generate`]): a kind (tilted planes through each other,
//! coplanar and nearly coplanar stacks, slivers, meshes of shared edges, polygons across
//! the screen's edges and hither, concave and bowtie polygons, layers of constant depth,
//! vertices at ±1e308), world or screen space, a screen size, a camera, one to three
//! frames, and flat, Gouraud or Phong shading. [`check`] runs the real binaries on it
//! (`render`, `zspec`, and for screen space the leaves and `zbuf`) and returns every
//! claim it broke as a [`Failure`] that names the seed, the mode and a shell command
//! that shows the difference. The same code runs in `cargo test`
//! (tests/tests/differential.rs), in the `differential` binary (`--cases N`, for long
//! runs) and in the cargo-fuzz target `fuzz/fuzz_targets/differential.rs`.

use crate::{parse_ppm_stream, Frame};
use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::Path;
use std::process::{Command, Output, Stdio};

/// splitmix64: a seed's numbers are the same on every run and platform.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed ^ 0x5eed_d1ff_0000_0001)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// A number in 0..n.
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n.max(1)
    }
    /// A number in lo..hi.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn chance(&mut self, p: f64) -> bool {
        self.range(0.0, 1.0) < p
    }
    fn colour(&mut self) -> [u8; 3] {
        [0, 0, 0].map(|_| 20 + self.below(236) as u8)
    }
    fn pick<'a, T>(&mut self, of: &'a [T]) -> &'a T {
        &of[self.below(of.len() as u64) as usize]
    }
}

/// World or screen space: a world scene goes through `render` and `zspec`, a screen one
/// through the leaf methods and `zbuf`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Space {
    World,
    Screen,
}

/// The kinds of scene, world then screen; a seed picks `KINDS[seed % KINDS.len()]`, so
/// that consecutive seeds go through every kind.
pub const KINDS: &[(&str, Space)] = &[
    ("planes", Space::World),
    ("stack", Space::World),
    ("slivers", Space::World),
    ("mesh", Space::World),
    ("edges", Space::World),
    ("concave", Space::World),
    ("mixed", Space::World),
    ("layers", Space::World),
    ("huge", Space::World),
    ("screen-planes", Space::Screen),
    ("screen-stack", Space::Screen),
    ("screen-mixed", Space::Screen),
    ("screen-layers", Space::Screen),
];

/// One generated scene.
#[derive(Clone, Debug)]
pub struct Scene {
    pub seed: u64,
    pub kind: &'static str,
    pub space: Space,
    /// W, H in pixels.
    pub size: (u32, u32),
    /// The camera options render and zspec both get (world space).
    pub camera: String,
    pub frames: usize,
    /// `flat`, `gouraud` or `phong`.
    pub shading: &'static str,
    /// Every polygon at one depth, flat-shaded, opaque: the a-buffer claims the 8×8
    /// supersampled picture exactly (docs/antialiasing.md, the packer).
    pub flat_depth: bool,
    /// The stream, text form.
    pub text: String,
}

#[derive(Clone, Debug)]
struct Poly {
    colour: [u8; 3],
    verts: Vec<[f64; 3]>,
}

/// A plane z = a·x + b·y + c (world) or depth = a·X + b·Y + c (screen).
#[derive(Clone, Copy, Debug)]
struct Plane(f64, f64, f64);

impl Plane {
    fn at(self, x: f64, y: f64) -> [f64; 3] {
        [x, y, self.0 * x + self.1 * y + self.2]
    }
    fn lift(self, outline: &[[f64; 2]]) -> Vec<[f64; 3]> {
        outline.iter().map(|&[x, y]| self.at(x, y)).collect()
    }
}

/// A convex polygon of `n` vertices about (cx, cy) of radius about `r`.
fn convex(rng: &mut Rng, cx: f64, cy: f64, r: f64, n: usize) -> Vec<[f64; 2]> {
    let start = rng.range(0.0, std::f64::consts::TAU);
    let mut angles: Vec<f64> = (0..n)
        .map(|i| start + std::f64::consts::TAU * (i as f64 + rng.range(0.0, 0.8)) / n as f64)
        .collect();
    angles.sort_by(f64::total_cmp);
    let (sx, sy) = (rng.range(0.4, 1.0) * r, rng.range(0.4, 1.0) * r);
    angles
        .iter()
        .map(|a| [cx + sx * a.cos(), cy + sy * a.sin()])
        .collect()
}

/// A star of `points` points (concave), or a bowtie (self-intersecting), about (cx, cy).
fn concave(rng: &mut Rng, cx: f64, cy: f64, r: f64) -> Vec<[f64; 2]> {
    match rng.below(3) {
        0 => {
            let points = 3 + rng.below(4) as usize;
            let inner = rng.range(0.2, 0.6);
            (0..2 * points)
                .map(|i| {
                    let a = std::f64::consts::PI * i as f64 / points as f64;
                    let k = if i % 2 == 0 { 1.0 } else { inner };
                    [cx + r * k * a.cos(), cy + r * k * a.sin()]
                })
                .collect()
        }
        1 => {
            let (w, h) = (r * rng.range(0.5, 1.5), r * rng.range(0.5, 1.5));
            vec![
                [cx - w, cy - h],
                [cx + w, cy + h],
                [cx + w, cy - h],
                [cx - w, cy + h],
            ]
        }
        _ => {
            let (w, h) = (r, r * rng.range(0.5, 1.2));
            let (t, u) = (rng.range(0.2, 0.8), rng.range(0.2, 0.8));
            vec![
                [cx - w, cy - h],
                [cx + w, cy - h],
                [cx + w, cy - h + 2.0 * h * t],
                [cx - w + 2.0 * w * u, cy - h + 2.0 * h * t],
                [cx - w + 2.0 * w * u, cy + h],
                [cx - w, cy + h],
            ]
        }
    }
}

fn sliver(rng: &mut Rng, half: f64) -> Vec<[f64; 2]> {
    let a = [rng.range(-half, half), rng.range(-half, half)];
    let b = [rng.range(-half, half), rng.range(-half, half)];
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len = (dx * dx + dy * dy).sqrt().max(1e-9);
    let w = half * rng.range(0.0005, 0.03);
    let t = rng.range(0.0, 1.0);
    let m = [a[0] + dx * t - dy / len * w, a[1] + dy * t + dx / len * w];
    vec![a, b, m]
}

fn tilted(rng: &mut Rng, slope: f64, depth: (f64, f64)) -> Plane {
    Plane(
        rng.range(-slope, slope),
        rng.range(-slope, slope),
        rng.range(depth.0, depth.1),
    )
}

/// A number as the scenes print it: shortest round trip.
fn num(x: f64) -> String {
    format!("{x}")
}

/// The scene of `seed`.
pub fn generate(seed: u64) -> Scene {
    let (kind, space) = KINDS[(seed % KINDS.len() as u64) as usize];
    let mut rng = Rng::new(seed);
    let size = if rng.chance(0.3) {
        let s = 8 + rng.below(72) as u32;
        (s, s)
    } else {
        (8 + rng.below(88) as u32, 8 + rng.below(72) as u32)
    };
    let frames = if rng.chance(0.35) {
        2 + rng.below(2) as usize
    } else {
        1
    };
    let mut shading = *rng.pick(&["flat", "flat", "gouraud", "phong"]);
    let mut camera = String::new();
    let mut flat_depth = false;
    let aspect = size.0 as f64 / size.1 as f64;
    // The visible half-height at world z = 0 with the default camera is 12.5.
    let hx = 13.0 * aspect;
    let hy = 13.0;
    let mut polys = Vec::new();
    let mut push = |rng: &mut Rng, verts: Vec<[f64; 3]>| {
        polys.push(Poly {
            colour: rng.colour(),
            verts,
        })
    };
    match kind {
        "planes" | "screen-planes" => {
            let n = 2 + rng.below(6);
            for _ in 0..n {
                let p = tilted(&mut rng, 0.6, (-4.0, 4.0));
                let m = rng.range(1.0, 1.3);
                push(
                    &mut rng,
                    p.lift(&[
                        [-hx * m, -hy * m],
                        [hx * m, -hy * m],
                        [hx * m, hy * m],
                        [-hx * m, hy * m],
                    ]),
                );
            }
        }
        "stack" | "screen-stack" => {
            let base = tilted(&mut rng, 0.5, (-3.0, 3.0));
            let n = 3 + rng.below(6);
            for _ in 0..n {
                let outline = if rng.chance(0.3) {
                    let e = [[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]];
                    e.to_vec()
                } else {
                    let sides = 3 + rng.below(3) as usize;
                    let (cx, cy, r) = (
                        rng.range(-6.0, 6.0),
                        rng.range(-6.0, 6.0),
                        rng.range(3.0, 9.0),
                    );
                    convex(&mut rng, cx, cy, r, sides)
                };
                let offset = *rng.pick(&[0.0, 0.0, 1e-12, 1e-9, 1e-7, 1e-4, -1e-9]);
                let plane = Plane(base.0, base.1, base.2 + offset);
                push(&mut rng, plane.lift(&outline));
                if rng.chance(0.25) {
                    // The same polygon again, another colour: the earlier one wins.
                    push(&mut rng, plane.lift(&outline));
                }
            }
        }
        "slivers" => {
            let n = 3 + rng.below(10);
            for _ in 0..n {
                let p = tilted(&mut rng, 0.4, (-4.0, 4.0));
                let outline = sliver(&mut rng, hy);
                push(&mut rng, p.lift(&outline));
            }
            // Something behind them to be seen through their gaps.
            let p = tilted(&mut rng, 0.2, (-6.0, -5.0));
            push(
                &mut rng,
                p.lift(&[[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]]),
            );
        }
        "mesh" => {
            let (gx, gy) = (2 + rng.below(5) as usize, 2 + rng.below(5) as usize);
            let m = rng.range(0.6, 1.3);
            let bump = rng.range(0.0, 3.0);
            let z: Vec<Vec<f64>> = (0..=gy)
                .map(|_| (0..=gx).map(|_| rng.range(-bump, bump)).collect())
                .collect();
            let at = |i: usize, j: usize| {
                [
                    -hx * m + 2.0 * hx * m * i as f64 / gx as f64,
                    -hy * m + 2.0 * hy * m * j as f64 / gy as f64,
                    z[j][i],
                ]
            };
            for j in 0..gy {
                for i in 0..gx {
                    let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                    if rng.chance(0.5) {
                        push(&mut rng, vec![a, b, c]);
                        push(&mut rng, vec![a, c, d]);
                    } else {
                        push(&mut rng, vec![a, b, d]);
                        push(&mut rng, vec![b, c, d]);
                    }
                }
            }
        }
        "edges" => {
            let n = 2 + rng.below(5);
            for _ in 0..n {
                // Steep planes reaching past hither (z = 19) and the eye (z = 20), and far
                // past the screen's edges.
                let p = Plane(
                    rng.range(-1.5, 1.5),
                    rng.range(-1.5, 1.5),
                    rng.range(-2.0, 16.0),
                );
                let sides = 3 + rng.below(3) as usize;
                let (cx, cy, r) = (
                    rng.range(-20.0, 20.0),
                    rng.range(-20.0, 20.0),
                    rng.range(8.0, 30.0),
                );
                let outline = convex(&mut rng, cx, cy, r, sides);
                push(&mut rng, p.lift(&outline));
            }
        }
        "concave" => {
            let n = 2 + rng.below(5);
            for _ in 0..n {
                let p = tilted(&mut rng, 0.5, (-4.0, 4.0));
                let (cx, cy, r) = (
                    rng.range(-7.0, 7.0),
                    rng.range(-7.0, 7.0),
                    rng.range(3.0, 9.0),
                );
                let outline = concave(&mut rng, cx, cy, r);
                push(&mut rng, p.lift(&outline));
            }
        }
        "mixed" | "screen-mixed" => {
            let n = 3 + rng.below(10);
            for _ in 0..n {
                let p = tilted(&mut rng, 0.8, (-5.0, 5.0));
                let (cx, cy, r) = (
                    rng.range(-9.0, 9.0),
                    rng.range(-9.0, 9.0),
                    rng.range(1.0, 10.0),
                );
                let outline = match rng.below(4) {
                    0 => concave(&mut rng, cx, cy, r),
                    1 => sliver(&mut rng, hy),
                    _ => {
                        let sides = 3 + rng.below(5) as usize;
                        convex(&mut rng, cx, cy, r, sides)
                    }
                };
                push(&mut rng, p.lift(&outline));
            }
        }
        "layers" | "screen-layers" => {
            flat_depth = true;
            shading = "flat";
            let n = 2 + rng.below(8);
            let depths: Vec<f64> = (0..3).map(|_| rng.range(-5.0, 5.0)).collect();
            for _ in 0..n {
                let z = *rng.pick(&depths) + *rng.pick(&[0.0, 0.0, 0.5, 1e-9]);
                let (cx, cy, r) = (
                    rng.range(-9.0, 9.0),
                    rng.range(-9.0, 9.0),
                    rng.range(2.0, 10.0),
                );
                let outline = match rng.below(3) {
                    0 => concave(&mut rng, cx, cy, r),
                    1 => sliver(&mut rng, hy),
                    _ => {
                        let sides = 3 + rng.below(5) as usize;
                        convex(&mut rng, cx, cy, r, sides)
                    }
                };
                push(&mut rng, Plane(0.0, 0.0, z).lift(&outline));
            }
        }
        "huge" => {
            let p = tilted(&mut rng, 0.5, (-4.0, 4.0));
            let outline = convex(&mut rng, 0.0, 0.0, 8.0, 4);
            push(&mut rng, p.lift(&outline));
            let big = *rng.pick(&[1e308, 1e300, 1e200, 1e100]);
            let z = rng.range(-5.0, 5.0);
            push(
                &mut rng,
                vec![[-big, -big, z], [big, -big, z], [0.0, big, z]],
            );
        }
        _ => unreachable!("a kind in KINDS"),
    }
    if space == Space::World && kind != "layers" && rng.chance(0.3) {
        camera = format!(
            "--eye {},{},{}",
            rng.range(-8.0, 8.0).round(),
            rng.range(-8.0, 8.0).round(),
            rng.range(14.0, 24.0).round()
        );
    }
    if space == Space::Screen && shading == "phong" {
        shading = "gouraud";
    }
    let text = write_scene(&mut rng, space, size, &polys, frames, shading);
    Scene {
        seed,
        kind,
        space,
        size,
        camera,
        frames,
        shading,
        flat_depth,
        text,
    }
}

/// The scene as a text stream; world polygons move between frames (a turn about the
/// vertical through the origin and a step), screen ones are mapped onto the screen.
fn write_scene(
    rng: &mut Rng,
    space: Space,
    (w, h): (u32, u32),
    polys: &[Poly],
    frames: usize,
    shading: &str,
) -> String {
    let mut s = String::new();
    match space {
        Space::World => s.push_str("polypipe 1 world"),
        Space::Screen => {
            let _ = write!(s, "polypipe 1 screen {w} {h}");
        }
    }
    match shading {
        "gouraud" => s.push_str(" vertex-colours"),
        "phong" => {
            let _ = write!(
                s,
                " vertex-normals ambient {} light {} {} {} {} specular {} {} viewer 0 0 1",
                num(rng.range(0.1, 0.4)),
                num(rng.range(-1.0, 1.0)),
                num(rng.range(-1.0, 1.0)),
                num(rng.range(0.3, 1.0)),
                num(rng.range(0.3, 0.8)),
                num(rng.range(0.0, 0.7)),
                num(rng.range(1.0, 40.0)),
            );
        }
        _ => {}
    }
    s.push('\n');
    let turn = rng.range(-0.3, 0.3);
    let step = [
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    ];
    let layers = polys
        .iter()
        .all(|p| p.verts.iter().all(|v| v[2] == p.verts[0][2]));
    let extras: Vec<Vec<String>> = polys
        .iter()
        .flat_map(|p| p.verts.iter())
        .map(|_| match shading {
            "gouraud" => (0..3).map(|_| num(rng.range(0.0, 255.0))).collect(),
            "phong" => {
                let n = [
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                    rng.range(0.2, 1.0),
                ];
                n.iter().map(|&c| num(c)).collect()
            }
            _ => Vec::new(),
        })
        .collect();
    for f in 0..frames {
        if f > 0 {
            s.push_str("NEXT.FRAME\n");
        }
        let t = f as f64;
        let (sin, cos) = if layers {
            (0.0, 1.0)
        } else {
            (turn * t).sin_cos()
        };
        let mut k = 0;
        for (i, p) in polys.iter().enumerate() {
            if i > 0 {
                s.push_str("NEXT.POLYGON\n");
            }
            let [r, g, b] = p.colour;
            let _ = writeln!(s, "colour {r} {g} {b}");
            for v in &p.verts {
                let [x, y, z] = [
                    cos * v[0] + sin * v[2] + step[0] * t,
                    v[1] + step[1] * t,
                    -sin * v[0] + cos * v[2] + step[2] * t,
                ];
                let (x, y, z) = match space {
                    Space::World => (x, y, z),
                    // World x, y within about ±13 onto the screen (beyond it where they
                    // are), depth in (0, 1), smaller nearer.
                    Space::Screen => {
                        let snap = |c: f64| (c * 8.0).round() / 8.0;
                        (
                            snap((x / 13.0 * 0.5 + 0.5) * w as f64),
                            snap((0.5 - y / 13.0 * 0.5) * h as f64),
                            0.5 - z / 20.0,
                        )
                    }
                };
                let _ = write!(s, "{} {} {}", num(x), num(y), num(z));
                for e in &extras[k] {
                    let _ = write!(s, " {e}");
                }
                k += 1;
                s.push('\n');
            }
        }
    }
    s.push_str("END\n");
    s
}

/// How much of the suite a scene gets.
#[derive(Clone, Debug)]
pub struct Plan {
    /// Every tree depth 0–4 for every mode (`--all-depths`), or depth 0 and one other the
    /// seed picks for each mode (the long runs' default).
    pub all_depths: bool,
    /// Only the one depth (0–4) the seed picks for each mode (`cargo test`; a mode
    /// compared with its own depth 0, projective and abuf, still draws that too).
    pub one_depth: bool,
    /// Modes (or prefixes of modes, `painter-split`) not to run.
    pub skip: Vec<String>,
    /// When not empty, only the modes these begin (`ss`, `leaf-painter`).
    pub only: Vec<String>,
}

impl Plan {
    pub fn quick() -> Plan {
        Plan {
            all_depths: false,
            one_depth: false,
            skip: Vec::new(),
            only: Vec::new(),
        }
    }
    /// The quick plan for the modes `only` begins.
    pub fn only(only: &[&str]) -> Plan {
        Plan {
            only: only.iter().map(|s| s.to_string()).collect(),
            ..Plan::quick()
        }
    }
    /// Whether no mode of `family` (`ss4`, `painter-split`) is to run.
    fn skips_family(&self, family: &str) -> bool {
        self.skip.iter().any(|s| family.starts_with(s.as_str()))
            || (!self.only.is_empty()
                && !self
                    .only
                    .iter()
                    .any(|o| family.starts_with(o.as_str()) || o.starts_with(family)))
    }
    fn skips(&self, mode: &str) -> bool {
        self.skip.iter().any(|s| mode.starts_with(s.as_str()))
            || (!self.only.is_empty() && !self.only.iter().any(|o| mode.starts_with(o.as_str())))
    }
}

/// One broken claim.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Failure {
    pub seed: u64,
    /// The mode, e.g. `warnock@2`, `ss4@0`, `painter-split@1`, `zspec`.
    pub mode: String,
    pub detail: String,
    /// A shell command, from the repository root with the binaries on PATH (`PATH=
    /// target/bin:$PATH`) and the scene in `scene.txt`, that shows the difference.
    pub command: String,
}

impl Failure {
    /// The mode without its depth: `warnock@2` → `warnock`.
    pub fn family(&self) -> &str {
        self.mode.split('@').next().unwrap_or(&self.mode)
    }
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "seed {} {}: {}\n  scene: target/bin/differential --seed {} --print-scene > scene.txt\n  \
             again: target/bin/differential --seed {} --cases 1 --all-depths\n  shows it: {}",
            self.seed, self.mode, self.detail, self.seed, self.seed, self.command
        )
    }
}

/// Runs `script` under bash with `bins` first on PATH in `dir`.
fn shell(bins: &Path, dir: &Path, script: &str) -> Output {
    let path = format!(
        "{}:{}",
        bins.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    Command::new("bash")
        .args(["-o", "pipefail", "-c", script])
        .current_dir(dir)
        .env("PATH", path)
        .env("POLYPIPE_BIN", bins)
        .env("POLYPIPE_LOAD", "0")
        .stdin(Stdio::null())
        .output()
        .unwrap_or_else(|e| panic!("cannot start bash for `{script}`: {e}"))
}

/// A command's frames, or why there are none.
struct Drawn {
    frames: Result<Vec<Frame>, String>,
    stderr: String,
}

fn draw(bins: &Path, dir: &Path, script: &str) -> Drawn {
    let out = shell(bins, dir, script);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    let frames = if out.status.success() {
        parse_ppm_stream(&out.stdout).map_err(|e| format!("not PPM: {e}"))
    } else {
        Err(format!(
            "exited {}: {}",
            out.status
                .code()
                .map_or("by a signal".into(), |c| c.to_string()),
            stderr.trim_end().lines().last().unwrap_or("")
        ))
    };
    Drawn { frames, stderr }
}

/// A pixel that differs: x, y, the colour drawn and the colour wanted.
type Pixel = (usize, usize, [u8; 3], [u8; 3]);

/// Per frame, the pixels where `got` differs from `want`; `Err` when the streams do not
/// have the same frames.
fn differing(got: &[Frame], want: &[Frame]) -> Result<Vec<Vec<Pixel>>, String> {
    if got.len() != want.len() {
        return Err(format!(
            "{} frames, the reference {}",
            got.len(),
            want.len()
        ));
    }
    got.iter()
        .zip(want)
        .map(|(g, w)| {
            if (g.width, g.height) != (w.width, w.height) {
                return Err(format!(
                    "{}x{}, the reference {}x{}",
                    g.width, g.height, w.width, w.height
                ));
            }
            Ok((0..g.pixels.len())
                .filter(|&i| g.pixels[i] != w.pixels[i])
                .map(|i| (i % g.width, i / g.width, g.pixels[i], w.pixels[i]))
                .collect())
        })
        .collect()
}

fn describe(diff: &[Vec<Pixel>], of: usize) -> String {
    let mut s = String::new();
    for (f, d) in diff.iter().enumerate().filter(|(_, d)| !d.is_empty()) {
        let (x, y, g, w) = d[0];
        let _ = write!(
            s,
            "frame {f}: {} of {of} pixels differ, first ({x}, {y}) {g:?} not {w:?}; ",
            d.len()
        );
    }
    s.trim_end_matches("; ").to_string()
}

/// What [`check`] collects while it runs.
struct Run<'a> {
    scene: &'a Scene,
    bins: &'a Path,
    dir: &'a Path,
    plan: &'a Plan,
    failures: Vec<Failure>,
    /// Modes run (for the tallies of the long runs).
    ran: Vec<String>,
}

impl Run<'_> {
    fn fail(&mut self, mode: &str, detail: String, command: String) {
        self.failures.push(Failure {
            seed: self.scene.seed,
            mode: mode.to_string(),
            detail,
            command,
        });
    }

    /// The depths the modes of `family` run at: the other depth is the seed's and the
    /// family's, whatever else runs.
    fn depths(&self, family: &str) -> Vec<u32> {
        if self.plan.all_depths {
            (0..=4).collect()
        } else {
            let name = family
                .bytes()
                .fold(0u64, |h, b| h.wrapping_mul(31).wrapping_add(b as u64));
            let mut rng = Rng::new(self.scene.seed ^ name);
            if self.plan.one_depth {
                vec![rng.below(5) as u32]
            } else {
                vec![0, 1 + rng.below(4) as u32]
            }
        }
    }

    /// Compares `script`'s frames with `want` byte for byte; returns the frames drawn.
    fn same(
        &mut self,
        mode: &str,
        script: &str,
        want: &[Frame],
        want_cmd: &str,
    ) -> Option<Vec<Frame>> {
        if self.plan.skips(mode) {
            return None;
        }
        self.ran.push(mode.to_string());
        let got = draw(self.bins, self.dir, script);
        let command = format!("zspec compare <({script}) <({want_cmd})");
        match got.frames {
            Err(e) => {
                self.fail(mode, e, script.to_string());
                None
            }
            Ok(frames) => {
                match differing(&frames, want) {
                    Err(e) => self.fail(mode, e, command),
                    Ok(d) if d.iter().any(|f| !f.is_empty()) => {
                        let (w, h) = self.scene.size;
                        self.fail(mode, describe(&d, (w * h) as usize), command)
                    }
                    Ok(_) => {}
                }
                Some(frames)
            }
        }
    }

    /// The painter's claim: each frame is the z-buffer's, or its stderr says so for that
    /// frame; its `--stats` count of cycles painted out of order is the frames' lines'.
    fn painter(&mut self, mode: &str, script: &str, want: &[Frame], want_cmd: &str) {
        if self.plan.skips(mode) {
            return;
        }
        self.ran.push(mode.to_string());
        let got = draw(self.bins, self.dir, script);
        let command =
            format!("{script} > /dev/null; zspec compare <({script} 2>/dev/null) <({want_cmd})");
        let frames = match got.frames {
            Err(e) => return self.fail(mode, e, script.to_string()),
            Ok(f) => f,
        };
        let diff = match differing(&frames, want) {
            Err(e) => return self.fail(mode, e, command),
            Ok(d) => d,
        };
        let (said, line_cycles, stats_cycles) = painter_says(&got.stderr);
        let unsaid: Vec<usize> = (0..diff.len())
            .filter(|&f| !diff[f].is_empty() && !said.contains(&f))
            .collect();
        if !unsaid.is_empty() {
            let shown: Vec<_> = diff
                .iter()
                .enumerate()
                .map(|(f, d)| {
                    if unsaid.contains(&f) {
                        d.clone()
                    } else {
                        Vec::new()
                    }
                })
                .collect();
            let (w, h) = self.scene.size;
            self.fail(
                mode,
                format!(
                    "wrong and not said: {} ({} painter records on stderr)",
                    describe(&shown, (w * h) as usize),
                    stagecli::stats::records_of(&got.stderr, "painter").map_or(0, |r| r.len())
                ),
                command.clone(),
            );
        }
        if let Some(stats) = stats_cycles {
            if stats != line_cycles {
                self.fail(
                    mode,
                    format!("--stats counts {stats} cycles painted out of order, its frame lines {line_cycles}"),
                    command,
                );
            }
        }
    }
}

/// From a painter's stderr (alone or under render), by its `--stats` records
/// (stagecli::stats): the frames a note names (a record with `frame`), the sum of the
/// cycles those notes say were painted out of order, and the sum of the totals' count
/// (the records without `frame`; `None` without `--stats`).
pub fn painter_says(stderr: &str) -> (BTreeSet<usize>, u64, Option<u64>) {
    let mut said = BTreeSet::new();
    let mut lines = 0;
    let mut stats = None;
    let records = stagecli::stats::records_of(stderr, "painter").unwrap_or_else(|e| panic!("{e}"));
    for r in records {
        let cycles = r.count("out_of_order").unwrap_or(0);
        match r.count("frame") {
            Some(frame) => {
                said.insert(frame as usize);
                lines += cycles;
            }
            None => *stats.get_or_insert(0) += cycles,
        }
    }
    (said, lines, stats)
}

fn quote(s: &str) -> String {
    if s.is_empty() {
        String::new()
    } else {
        format!(" {s}")
    }
}

/// Every claim on `scene`, run with the binaries in `bins`; the broken ones, and the
/// modes run.
pub fn check(scene: &Scene, bins: &Path, plan: &Plan) -> (Vec<Failure>, Vec<String>) {
    let dir = tempfile::tempdir().expect("a temporary folder");
    std::fs::write(dir.path().join("scene.txt"), &scene.text).expect("write the scene");
    let mut run = Run {
        scene,
        bins,
        dir: dir.path(),
        plan,
        failures: Vec::new(),
        ran: Vec::new(),
    };
    match scene.space {
        Space::World => world(&mut run),
        Space::Screen => screen(&mut run),
    }
    (run.failures, run.ran)
}

fn world(run: &mut Run) {
    let scene = run.scene;
    let (w, h) = scene.size;
    let cam = quote(&scene.camera);
    let zspec = |samples: u32| {
        if samples == 1 {
            format!("zspec --size {w}x{h}{cam} scene.txt")
        } else {
            format!("zspec --size {w}x{h}{cam} --samples {samples} scene.txt")
        }
    };
    let render = |args: &str, depth: u32| {
        format!("render --size {w}x{h} --depth {depth}{cam} {args} scene.txt")
    };
    let reference_cmd = zspec(1);
    run.ran.push("zspec".into());
    let reference = draw(run.bins, run.dir, &reference_cmd);
    let reference = match reference.frames {
        Ok(f) => f,
        Err(e) => {
            // The reference refuses: render must refuse too (the same class of status).
            let r = render("", 0);
            let out = shell(run.bins, run.dir, &format!("{r} > /dev/null"));
            if out.status.success() {
                run.fail(
                    "zspec",
                    format!("zspec {e}, render draws it (status 0)"),
                    format!("{reference_cmd} > /dev/null; echo $?; {r} > /dev/null; echo $?"),
                );
            }
            return;
        }
    };
    // The exact methods, the merges, the chain of clippers.
    let mut zbuf_at = std::collections::BTreeMap::new();
    for (family, args) in [
        ("zbuf", "--hse zbuf"),
        ("scanline", "--hse scanline"),
        ("warnock", "--hse warnock"),
        ("buffer", "--merge buffer"),
        ("buffer-pixels", "--merge buffer --pixels"),
        ("chain", "--clip chain"),
    ] {
        if run.plan.skips_family(family) {
            continue;
        }
        for d in run.depths(family) {
            let mode = format!("{family}@{d}");
            if run.plan.skips(&mode) {
                continue;
            }
            let frames = run.same(&mode, &render(args, d), &reference, &reference_cmd);
            if family == "zbuf" {
                zbuf_at.insert(d, frames);
            }
        }
    }
    // Projective depth: every tree depth the same bytes as depth 0; where it is not
    // zspec's frame, zbuf says so on stderr (docs/DESIGN.md, "Depth").
    if !run.plan.skips_family("projective") {
        let base_cmd = render("--zmode projective", 0);
        run.ran.push("projective@0".into());
        let base = draw(run.bins, run.dir, &base_cmd);
        match base.frames {
            Err(e) => run.fail("projective@0", e, base_cmd.clone()),
            Ok(frames) => {
                if let Ok(diff) = differing(&frames, &reference) {
                    let unsaid: Vec<usize> = (0..diff.len())
                        .filter(|&f| {
                            !diff[f].is_empty()
                                && !base.stderr.lines().any(|l| {
                                    l.contains(&format!("frame {f}: "))
                                        && l.contains("projective depth's quantum")
                                })
                        })
                        .collect();
                    if !unsaid.is_empty() {
                        run.fail(
                            "projective@0",
                            format!(
                                "frames {unsaid:?} differ from zspec's and zbuf says nothing: {}",
                                describe(&diff, (w * h) as usize)
                            ),
                            format!("zspec compare <({base_cmd}) <({reference_cmd})"),
                        );
                    }
                }
                for d in run.depths("projective").into_iter().filter(|&d| d > 0) {
                    run.same(
                        &format!("projective@{d}"),
                        &render("--zmode projective", d),
                        &frames,
                        &base_cmd,
                    );
                }
            }
        }
    }
    // Supersampling: `--aa ssK` is `zspec --samples K`.
    for k in [2, 4, 8] {
        let family = format!("ss{k}");
        if run.plan.skips_family(&family) {
            continue;
        }
        let want_cmd = zspec(k);
        let want = match draw(run.bins, run.dir, &want_cmd).frames {
            Ok(f) => f,
            Err(e) => {
                run.fail(&family, format!("zspec --samples {k} {e}"), want_cmd);
                continue;
            }
        };
        for d in run.depths(&family) {
            run.same(
                &format!("{family}@{d}"),
                &render(&format!("--aa ss{k}"), d),
                &want,
                &want_cmd,
            );
        }
    }
    // Adaptive supersampling: on flat scenes `--aa adaptiveK` is `--aa ssK` at the same
    // depth, byte for byte (docs/antialiasing.md, "Adaptive supersampling").
    for k in [2, 4, 8] {
        let family = format!("adaptive{k}");
        if scene.shading != "flat" || run.plan.skips_family(&family) {
            continue;
        }
        for d in run.depths(&family) {
            let want_cmd = render(&format!("--aa ss{k}"), d);
            let want = match draw(run.bins, run.dir, &want_cmd).frames {
                Ok(f) => f,
                Err(e) => {
                    run.fail(&format!("{family}@{d}"), format!("ss{k}: {e}"), want_cmd);
                    continue;
                }
            };
            run.same(
                &format!("{family}@{d}"),
                &render(&format!("--aa adaptive{k}"), d),
                &want,
                &want_cmd,
            );
        }
    }
    // The a-buffer: the same bytes at every depth; on layers of one depth each (nothing
    // intersects in depth), flat, exactly the 8×8 supersampled picture.
    if !run.plan.skips_family("abuf") {
        let base_cmd = render("--aa abuf", 0);
        let base = if scene.flat_depth {
            let want_cmd = zspec(8);
            match draw(run.bins, run.dir, &want_cmd).frames {
                Ok(want) => run.same("abuf@0", &base_cmd, &want, &want_cmd),
                Err(_) => None,
            }
        } else {
            run.ran.push("abuf@0".into());
            let b = draw(run.bins, run.dir, &base_cmd);
            match b.frames {
                Ok(f) => Some(f),
                Err(e) => {
                    run.fail("abuf@0", e, base_cmd.clone());
                    None
                }
            }
        };
        if let Some(base) = base {
            for d in run.depths("abuf").into_iter().filter(|&d| d > 0) {
                run.same(
                    &format!("abuf@{d}"),
                    &render("--aa abuf", d),
                    &base,
                    &base_cmd,
                );
            }
        }
    }
    // The painter, plain and splitting: the z-buffer's bytes or a line saying so.
    for (family, args) in [
        ("painter", "--hse painter --stats"),
        ("painter-split", "--hse painter --split --stats"),
    ] {
        if run.plan.skips_family(family) {
            continue;
        }
        for d in run.depths(family) {
            let mode = format!("{family}@{d}");
            let want_cmd = render("--hse zbuf", d);
            let want = match zbuf_at.get(&d).cloned().flatten() {
                Some(f) => f,
                None => match draw(run.bins, run.dir, &want_cmd).frames {
                    Ok(f) => f,
                    Err(_) => continue,
                },
            };
            run.painter(&mode, &render(args, d), &want, &want_cmd);
        }
    }
}

fn screen(run: &mut Run) {
    let reference_cmd = "zbuf < scene.txt".to_string();
    run.ran.push("zbuf".into());
    let reference = match draw(run.bins, run.dir, &reference_cmd).frames {
        Ok(f) => f,
        Err(e) => return run.fail("zbuf", e, reference_cmd),
    };
    for (mode, leaf) in [
        ("leaf-zbuf", "scanconv --resolve"),
        ("leaf-spans", "scanconv"),
        ("leaf-pixels", "scanconv --pixels"),
        ("leaf-scanline", "scanline"),
        ("leaf-warnock", "warnock"),
    ] {
        if !run.plan.skips(mode) {
            run.same(
                mode,
                &format!("{leaf} < scene.txt | zbuf"),
                &reference,
                &reference_cmd,
            );
        }
    }
    for (mode, leaf) in [
        ("leaf-painter", "painter --stats"),
        ("leaf-painter-split", "painter --split --stats"),
    ] {
        if !run.plan.skips(mode) {
            run.painter(
                mode,
                &format!("{leaf} < scene.txt | zbuf"),
                &reference,
                &reference_cmd,
            );
        }
    }
    if run.scene.flat_depth && !run.plan.skips("leaf-abuf") {
        let want_cmd = "supersample --samples 8 < scene.txt | zbuf".to_string();
        match draw(run.bins, run.dir, &want_cmd).frames {
            Ok(want) => {
                run.same("leaf-abuf", "abuf < scene.txt | zbuf", &want, &want_cmd);
            }
            Err(e) => run.fail("leaf-ss8", e, want_cmd),
        }
    }
}
