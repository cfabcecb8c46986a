//! The span z-test alone: depth tests a second of [`RegionBuffer::span`] with each
//! z-test kernel, on spans of several lengths over a region small enough to stay in the
//! caches (the cost of the test, not of the memory behind it). The spans come 16 rows
//! at a time at one place, as a polygon's do.
//!
//! Usage: `cargo run --release -p scan --example ztest [-- MILLION-TESTS]` (default 200
//! million tests a kernel and length). The kernels are run interleaved, five rounds, and
//! the best round of each is printed, with the vector kernel's speed over the scalar's.
//! Every round of every kernel draws the same spans, and the buffers' pictures are
//! checked to be the same.

use scan::{RegionBuffer, ZTest};
use std::time::Instant;

/// A small deterministic generator (xorshift64*), so that every kernel sees one sequence.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// One span: row, first column, last column + 1, depth at column 0, step.
type Spec = (u32, u32, u32, f64, f64);

/// Spans of `len` pixels, in blocks of 16 rows at one random place of a `w`×`h` region
/// (the spans of one polygon come row after row), with random depths in the reciprocal
/// form (−1 .. 0) and small steps.
fn spans(len: u32, w: u32, h: u32, n: usize) -> Vec<Spec> {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15 ^ len as u64);
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let y0 = (rng.next() % (h - 15) as u64) as u32;
        let x0 = (rng.next() % (w - len + 1) as u64) as u32;
        let z = -rng.unit();
        let dz = (rng.unit() - 0.5) * 1e-4;
        for y in y0..y0 + 16 {
            out.push((y, x0, x0 + len, z + y as f64 * 1e-5, dz));
        }
    }
    out
}

/// Seconds to draw `specs` `reps` times through a fresh buffer with `kernel`, and the
/// last picture's colours.
fn run(kernel: ZTest, specs: &[Spec], reps: usize, w: u32, h: u32) -> (f64, Vec<Option<[u8; 3]>>) {
    let mut rb = RegionBuffer::new(w, h);
    rb.set_kernel(kernel);
    let colours = [[200, 10, 10], [10, 200, 10], [10, 10, 200]];
    let t = Instant::now();
    for r in 0..reps {
        if r > 0 {
            rb.clear();
        }
        for (i, &(y, x0, x1, z, dz)) in specs.iter().enumerate() {
            rb.span(y, x0..x1, z, dz, colours[i % 3]);
        }
    }
    let secs = t.elapsed().as_secs_f64();
    let picture = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| rb.colour_at(x, y))
        .collect();
    (secs, picture)
}

fn main() {
    let millions: f64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(200.0);
    // 256×64 pixels: four tiles, 192 KiB of bars and colours, in the L2 cache.
    let (w, h) = (256u32, 64u32);
    let mut kernels = vec![ZTest::Scalar];
    if ZTest::Avx2.available() {
        kernels.push(ZTest::Avx2);
    }
    println!("| span length | kernel | M tests/s | ns/test | × scalar |");
    println!("|---|---|---|---|---|");
    for len in [8u32, 16, 32, 48, 64, 128, 256] {
        let specs = spans(len, w, h, 4096);
        let per_rep = specs.len() as f64 * len as f64;
        let reps = ((millions * 1e6 / per_rep).ceil() as usize).max(1);
        let mut best = vec![f64::INFINITY; kernels.len()];
        let mut pictures = vec![Vec::new(); kernels.len()];
        for _round in 0..5 {
            for (k, &kernel) in kernels.iter().enumerate() {
                let (s, p) = run(kernel, &specs, reps, w, h);
                best[k] = best[k].min(s);
                pictures[k] = p;
            }
        }
        assert!(
            pictures.windows(2).all(|p| p[0] == p[1]),
            "the kernels' pictures differ"
        );
        for (k, kernel) in kernels.iter().enumerate() {
            let rate = per_rep * reps as f64 / best[k];
            println!(
                "| {len} | {kernel:?} | {:.0} | {:.2} | {:.2} |",
                rate / 1e6,
                1e9 / rate,
                best[0] / best[k]
            );
        }
    }
}
