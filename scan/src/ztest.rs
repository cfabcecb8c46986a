//! The z-test over one row of a region buffer's tile: the inner loop of the thesis's
//! BUFFER (chapter 4.2.3), the place a z-buffer spends most of its time.
//!
//! A span of one polygon on one row is tested against the bars kept there: pixel x has
//! depth `z_row + x·dz` ([`proto::fragment::span_depth`]), and it is taken when the pixel
//! is empty (colour 0) and its depth is a number, or when its depth is under the pixel's
//! bar ([`proto::depth::bar`]); a taken pixel gets this polygon's colour and bar.
//!
//! Two kernels do this, with the same result to the bit:
//!
//! - [`ZTest::Scalar`], one pixel at a time, for every machine;
//! - [`ZTest::Avx2`], four pixels at a time in 256-bit registers, where the processor has
//!   AVX2 (found at run time). The row is walked in the four-pixel blocks of the tile row
//!   that the span touches (a tile row is 64 pixels, 16 blocks, so a block never leaves
//!   it), each block loaded whole, its lanes outside the span masked off, and stored back
//!   whole with the winners selected in (a blend, no branch per pixel, no scalar tail).
//!   The spans of a fill-heavy scene are short (tens of pixels), so a vector loop with a
//!   scalar head and tail spends most of its time in the tails; whole blocks do not.
//!
//! Each lane computes its depth exactly as the scalar expression does: the column as an
//! f64 (exact: columns are below 2³²), one rounded multiplication by `dz`, one rounded
//! addition of `z_row`, no fused multiply-add; and its bar as `z·(1 − copysign(TIE, z))`
//! in the same two rounded steps as [`proto::depth::bar`]. So the frames do not change.

use crate::depth::{depth_at, Depth};

/// Which kernel a region buffer's z-test runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ZTest {
    /// One pixel at a time.
    Scalar,
    /// Four pixels at a time with AVX2 (x86-64 only; [`ZTest::detect`] chooses it only
    /// where the processor has AVX2 and POPCNT).
    Avx2,
}

impl ZTest {
    /// The fastest kernel this processor runs.
    pub fn detect() -> ZTest {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("popcnt")
            {
                return ZTest::Avx2;
            }
        }
        ZTest::Scalar
    }

    /// Whether this processor can run the kernel.
    pub fn available(self) -> bool {
        match self {
            ZTest::Scalar => true,
            ZTest::Avx2 => ZTest::detect() == ZTest::Avx2,
        }
    }
}

/// The scalar kernel: the z-test of pixels `lo..hi` of one tile row, one pixel at a
/// time. `bars` and `colours` are the row's cells (of one length, a multiple of 4), cell
/// i is screen column `left + i`, and column x has depth `z_row + x·dz`. Returns the
/// pixels taken.
#[allow(clippy::too_many_arguments)]
#[inline]
pub(crate) fn scalar(
    bars: &mut [Depth],
    colours: &mut [u32],
    lo: usize,
    hi: usize,
    left: u32,
    z_row: Depth,
    dz: Depth,
    colour: u32,
) -> u64 {
    let (bars, colours) = (&mut bars[lo..hi], &mut colours[lo..hi]);
    let mut written = 0u64;
    let x0 = left + lo as u32;
    for (i, (bar, f)) in bars.iter_mut().zip(colours.iter_mut()).enumerate() {
        let z = depth_at(z_row, dz, x0 + i as u32);
        let win = (*f == 0 && !z.is_nan()) || z < *bar;
        if win {
            *bar = proto::depth::bar(z);
            *f = colour;
        }
        written += win as u64;
    }
    written
}

/// The AVX2 kernel: [`scalar`]'s z-test, in the four-pixel blocks of the row that
/// `lo..hi` touches.
///
/// # Safety
///
/// The processor must have AVX2 and POPCNT; `bars` and `colours` must be of one length,
/// a multiple of 4, with `lo <= hi <= len`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,popcnt")]
#[allow(clippy::too_many_arguments)]
#[inline]
pub(crate) unsafe fn avx2(
    bars: &mut [Depth],
    colours: &mut [u32],
    lo: usize,
    hi: usize,
    left: u32,
    z_row: Depth,
    dz: Depth,
    colour: u32,
) -> u64 {
    use std::arch::x86_64::*;
    debug_assert!(
        bars.len() == colours.len() && bars.len().is_multiple_of(4) && lo <= hi && hi <= bars.len()
    );
    let first = lo & !3;
    let last = (hi + 3) & !3;
    // Signed conversions: one instruction each (the values are below 2^33).
    let x0 = (left as i64 + first as i64) as f64;
    // The lanes' columns, as f64 (integers below 2^33: every step exact).
    let mut xs = _mm256_setr_pd(x0, x0 + 1.0, x0 + 2.0, x0 + 3.0);
    let four = _mm256_set1_pd(4.0);
    let (x_lo, x_hi) = (
        _mm256_set1_pd((left as i64 + lo as i64) as f64),
        _mm256_set1_pd((left as i64 + hi as i64) as f64),
    );
    let (zr, step) = (_mm256_set1_pd(z_row), _mm256_set1_pd(dz));
    let (one, tie, sign) = (
        _mm256_set1_pd(1.0),
        _mm256_set1_pd(proto::depth::TIE),
        _mm256_set1_pd(-0.0),
    );
    let paint = _mm_set1_epi32(colour as i32);
    // Takes the low half of each 64-bit lane: a lane mask of doubles as one of u32s.
    let narrow = _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);
    let mut written = 0u32;
    let mut i = first;
    while i < last {
        // SAFETY: i is a multiple of 4 below `last` <= the slices' length (a multiple of
        // 4), so cells i..i+4 are in both slices; unaligned loads and stores.
        unsafe {
            let pb = bars.as_mut_ptr().add(i);
            let pc = colours.as_mut_ptr().add(i) as *mut __m128i;
            // z = z_row + x·dz, rounded as the scalar expression is.
            let z = _mm256_add_pd(zr, _mm256_mul_pd(xs, step));
            let bar = _mm256_loadu_pd(pb);
            let col = _mm_loadu_si128(pc);
            let empty = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(_mm_cmpeq_epi32(
                col,
                _mm_setzero_si128(),
            )));
            let number = _mm256_cmp_pd::<_CMP_ORD_Q>(z, z);
            let under = _mm256_cmp_pd::<_CMP_LT_OQ>(z, bar);
            let inside = _mm256_and_pd(
                _mm256_cmp_pd::<_CMP_GE_OQ>(xs, x_lo),
                _mm256_cmp_pd::<_CMP_LT_OQ>(xs, x_hi),
            );
            let win = _mm256_and_pd(inside, _mm256_or_pd(_mm256_and_pd(empty, number), under));
            // The new bar, z·(1 − copysign(TIE, z)) as proto::depth::bar rounds it.
            let new_bar = _mm256_mul_pd(
                z,
                _mm256_sub_pd(one, _mm256_or_pd(_mm256_and_pd(z, sign), tie)),
            );
            store(pb, _mm256_blendv_pd(bar, new_bar, win));
            let win32 = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(
                _mm256_castpd_si256(win),
                narrow,
            ));
            _mm_storeu_si128(pc, _mm_blendv_epi8(col, paint, win32));
            written += (_mm256_movemask_pd(win) as u32).count_ones();
        }
        xs = _mm256_add_pd(xs, four);
        i += 4;
    }
    written as u64
}

/// Stores four doubles, unaligned, as one plain store. Written out so that the compiler
/// cannot fold the load, blend and store of a block into a masked store (`vmaskmovpd`),
/// which some processors (AMD's) run far slower than a load, blend and store.
///
/// # Safety
///
/// `p` must be valid for writing four doubles; the processor must have AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,popcnt")]
#[inline]
unsafe fn store(p: *mut f64, v: std::arch::x86_64::__m256d) {
    // SAFETY: as the caller promises; the instruction writes exactly those 32 bytes.
    unsafe {
        std::arch::asm!(
            "vmovupd ymmword ptr [{p}], {v}",
            p = in(reg) p,
            v = in(ymm_reg) v,
            options(nostack, preserves_flags)
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A tile row after the same spans through each kernel.
    fn after(
        kernel: ZTest,
        spans: &[(usize, usize, u32, f64, f64, u32)],
    ) -> (Vec<u64>, Vec<u32>, Vec<u64>) {
        let mut bars = vec![0.0f64; 64];
        let mut colours = vec![0u32; 64];
        let written = spans
            .iter()
            .map(|&(lo, hi, left, z, dz, c)| match kernel {
                ZTest::Scalar => scalar(&mut bars, &mut colours, lo, hi, left, z, dz, c),
                // SAFETY: the test runs it only where the processor has AVX2 and POPCNT.
                #[cfg(target_arch = "x86_64")]
                ZTest::Avx2 => unsafe { avx2(&mut bars, &mut colours, lo, hi, left, z, dz, c) },
                #[cfg(not(target_arch = "x86_64"))]
                ZTest::Avx2 => unreachable!(),
            })
            .collect();
        let bits = bars
            .iter()
            .zip(&colours)
            .map(|(b, &c)| if c == 0 { 0 } else { b.to_bits() })
            .collect();
        (bits, colours, written)
    }

    #[test]
    fn the_scalar_kernel_takes_empty_and_nearer_pixels() {
        let t = (1.0f64 - proto::depth::TIE) * 2.0;
        // Columns 66..70 at depth 2, then columns 67..73 at 17 − x/4 = 0.25, 0, …, −1:
        // nearer than 2 where covered, and the empty ones taken too.
        let r = after(
            ZTest::Scalar,
            &[(2, 6, 64, 2.0, 0.0, 7), (3, 9, 64, 17.0, -0.25, 9)],
        );
        assert_eq!(r.2, [4, 6]);
        assert_eq!(&r.1[..10], [0, 0, 7, 9, 9, 9, 9, 9, 9, 0]);
        assert_eq!(r.0[3], (0.25 * (1.0 - proto::depth::TIE)).to_bits());
        assert_eq!(r.0[2], t.to_bits());
    }

    fn span() -> impl Strategy<Value = (usize, usize, u32, f64, f64, u32)> {
        let depth = prop_oneof![
            8 => -4.0f64..4.0,
            1 => Just(f64::NAN),
            1 => Just(f64::INFINITY),
            1 => Just(f64::NEG_INFINITY),
            1 => Just(0.0),
            1 => Just(-0.0),
        ];
        (
            0usize..=64,
            0usize..=64,
            0u32..4096,
            depth,
            -1e-2f64..1e-2,
            1u32..4,
        )
            .prop_map(|(a, b, tile, z, dz, c)| (a.min(b), a.max(b), tile * 64, z, dz, c))
    }

    proptest! {
        /// The vector kernel leaves the same row (bars to the bit where a pixel is
        /// covered, colours) and counts the same pixels as the scalar one.
        #[test]
        fn avx2_matches_scalar(spans in prop::collection::vec(span(), 1..40)) {
            prop_assume!(ZTest::Avx2.available());
            prop_assert_eq!(after(ZTest::Avx2, &spans), after(ZTest::Scalar, &spans));
        }
    }
}
