//! A drawing as the picture a user sees: its pieces stroked as the SVG strokes them (a pen
//! `pen` pixels wide with round caps: every point within `pen`/2 of a piece is ink),
//! black on white, sampled K×K times a pixel and box-filtered, as the 16×16 reference
//! pictures are (`reference::supersample`): pixel (c, r)'s samples lie at
//! (c + (i+½)/K, r + (j+½)/K), i, j = 0..K−1, and its grey level is the average of its
//! samples (0 ink, 255 paper) rounded to nearest, halves up, in integers:
//! `(255·(K² − n) + K²/2) / K²` for n samples inked. Pieces that overlap ink a sample
//! once (the union of their strokes, not a sum), and the pieces' colours are not drawn:
//! the picture is of where the lines are.
//!
//! A sample row meets a piece's stroke (a capsule, convex) in one interval of x
//! ([`crate::within`]); the samples in it are set in a bit row, and the bits a pixel
//! are counted once the pieces of its pixel row are all drawn. Memory: K bit rows of
//! the width's samples, the pixels' counts, and the pieces' indices by pixel row.

use crate::{within, Segment};
use proto::ppm::Image;
use proto::DVec2;

/// The most samples a side ([`coverage`]'s K): 16, the reference's, is the one charted.
pub const MAX_SAMPLES: u32 = 64;

/// How many of each pixel's K×K samples (K = `samples`, 1 to [`MAX_SAMPLES`]) lie within
/// `pen`/2 of some piece, row-major, for a `width`×`height` screen. Pieces with a
/// coordinate that is not finite are left out; parts off the screen are cut.
pub fn coverage(segments: &[Segment], width: u32, height: u32, pen: f64, samples: u32) -> Vec<u32> {
    let k = samples.clamp(1, MAX_SAMPLES) as usize;
    let (w, h) = (width as usize, height as usize);
    let mut counts = vec![0u32; w * h];
    let r = pen.max(0.0) / 2.0;
    if w == 0 || h == 0 || !r.is_finite() {
        return counts;
    }
    // Each piece by the first pixel row its stroke reaches, with the last.
    let mut starting: Vec<Vec<(u32, u32)>> = vec![Vec::new(); h];
    for (i, s) in segments.iter().enumerate() {
        if ![s.from.x, s.from.y, s.to.x, s.to.y]
            .iter()
            .all(|v| v.is_finite())
        {
            continue;
        }
        let (lo, hi) = (s.from.y.min(s.to.y) - r, s.from.y.max(s.to.y) + r);
        if hi < 0.0 || lo >= h as f64 {
            continue;
        }
        let first = lo.floor().max(0.0) as usize;
        let last = (hi.floor() as usize).min(h - 1);
        starting[first].push((i as u32, last as u32));
    }
    let samples_wide = w * k;
    let words = samples_wide.div_ceil(64);
    let mut bits = vec![0u64; words * k];
    let mut active: Vec<(u32, u32)> = Vec::new();
    for (row, starts) in starting.iter().enumerate() {
        active.retain(|&(_, last)| last as usize >= row);
        active.extend_from_slice(starts);
        if active.is_empty() {
            continue;
        }
        bits.fill(0);
        for &(i, _) in &active {
            let s = &segments[i as usize];
            // A line across the piece's box grown by the pen, met by its stroke.
            let (x0, x1) = (
                s.from.x.min(s.to.x) - r - 1.0,
                s.from.x.max(s.to.x) + r + 1.0,
            );
            for j in 0..k {
                let y = row as f64 + (j as f64 + 0.5) / k as f64;
                let Some((t0, t1)) = within(DVec2::new(x0, y), DVec2::new(x1, y), s.from, s.to, r)
                else {
                    continue;
                };
                let (a, b) = (x0 + t0 * (x1 - x0), x0 + t1 * (x1 - x0));
                // Samples at (n + ½)/K with a ≤ x ≤ b: n from ⌈aK − ½⌉ to ⌊bK − ½⌋.
                let first = (a * k as f64 - 0.5).ceil().max(0.0);
                let last = (b * k as f64 - 0.5).floor().min(samples_wide as f64 - 1.0);
                if first > last {
                    continue;
                }
                set_bits(
                    &mut bits[j * words..(j + 1) * words],
                    first as usize,
                    last as usize,
                );
            }
        }
        let counted = &mut counts[row * w..(row + 1) * w];
        for j in 0..k {
            let line = &bits[j * words..(j + 1) * words];
            for (c, n) in counted.iter_mut().enumerate() {
                *n += count_bits(line, c * k, c * k + k);
            }
        }
    }
    counts
}

/// Sets bits `first..=last` of a bit row.
fn set_bits(line: &mut [u64], first: usize, last: usize) {
    let (fw, lw) = (first / 64, last / 64);
    let from = |b: usize| u64::MAX << (b % 64);
    let to = |b: usize| u64::MAX >> (63 - b % 64);
    if fw == lw {
        line[fw] |= from(first) & to(last);
        return;
    }
    line[fw] |= from(first);
    for word in &mut line[fw + 1..lw] {
        *word = u64::MAX;
    }
    line[lw] |= to(last);
}

/// The bits set in `first..end` of a bit row.
fn count_bits(line: &[u64], first: usize, end: usize) -> u32 {
    let mut n = 0;
    let mut at = first;
    while at < end {
        let word = line[at / 64] >> (at % 64);
        let take = (64 - at % 64).min(end - at);
        let mask = if take == 64 {
            u64::MAX
        } else {
            (1u64 << take) - 1
        };
        n += (word & mask).count_ones();
        at += take;
    }
    n
}

/// The drawing as a grey picture (R = G = B), black lines `pen` pixels wide on white,
/// K×K samples a pixel ([`coverage`], the module notes).
pub fn picture(segments: &[Segment], width: u32, height: u32, pen: f64, samples: u32) -> Image {
    let k = samples.clamp(1, MAX_SAMPLES);
    let all = k * k;
    let pixels = coverage(segments, width, height, pen, k)
        .into_iter()
        .map(|n| {
            let grey = (255 * (all - n) + all / 2) / all;
            let grey = grey as u8;
            [grey, grey, grey]
        })
        .collect();
    Image {
        width,
        height,
        pixels,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::seg;

    fn grey(img: &Image, x: u32, y: u32) -> u8 {
        let [r, g, b] = img.at(x, y);
        assert!(r == g && g == b, "{:?}", img.at(x, y));
        r
    }

    /// A horizontal line 1 px wide through pixel centres, from x = 1 to 4 on row 2: its
    /// stroke is the band 2 ≤ y ≤ 3 from x = 1 to 4 and two half-discs of radius ½. The
    /// pixels it crosses are inked whole (256 of 256, grey 0); the rows above and below
    /// not at all (their nearest samples are 1/32 px beyond the stroke); each end pixel
    /// holds a half-disc, 104 of its 256 samples ((i+½)/16 − 1)² + ((j+½)/16 − ½)² ≤ ¼
    /// for i, j = 0..15), grey (255·152 + 128) / 256 = 151.
    #[test]
    fn a_line_on_pixel_centres_inks_its_pixels_whole_and_its_ends_by_half_discs() {
        let line = [seg(1.0, 2.5, 4.0, 2.5)];
        let counts = coverage(&line, 6, 5, 1.0, 16);
        let row = |y: usize| counts[y * 6..y * 6 + 6].to_vec();
        assert_eq!(row(2), [104, 256, 256, 256, 104, 0]);
        for y in [0, 1, 3, 4] {
            assert_eq!(row(y), [0; 6], "row {y}");
        }
        let img = picture(&line, 6, 5, 1.0, 16);
        let greys: Vec<u8> = (0..6).map(|x| grey(&img, x, 2)).collect();
        assert_eq!(greys, [151, 0, 0, 0, 151, 255]);
        assert_eq!(grey(&img, 2, 1), 255);
        // Drawn backwards, or as two pieces meeting (dashes of one edge), the same.
        assert_eq!(coverage(&[seg(4.0, 2.5, 1.0, 2.5)], 6, 5, 1.0, 16), counts);
        assert_eq!(
            coverage(
                &[seg(1.0, 2.5, 2.5, 2.5), seg(2.5, 2.5, 4.0, 2.5)],
                6,
                5,
                1.0,
                16
            ),
            counts
        );
    }

    /// A line along a pixel border (y = 2) inks half of the rows on either side: 8 of 16
    /// sample rows, 128 of 256 samples, grey (255·128 + 128) / 256 = 128 (127.5, half up).
    /// The same line vertical, on x = 3, inks columns 2 and 3 so.
    #[test]
    fn a_line_on_a_pixel_border_inks_both_sides_by_half() {
        let img = picture(&[seg(1.0, 2.0, 4.0, 2.0)], 6, 5, 1.0, 16);
        for y in [1, 2] {
            let greys: Vec<u8> = (1..4).map(|x| grey(&img, x, y)).collect();
            assert_eq!(greys, [128, 128, 128], "row {y}");
        }
        assert_eq!(grey(&img, 2, 0), 255);
        assert_eq!(grey(&img, 2, 3), 255);
        let counts = coverage(&[seg(3.0, 1.0, 3.0, 4.0)], 6, 5, 1.0, 16);
        for y in 1..4 {
            assert_eq!(counts[y * 6..y * 6 + 6], [0, 0, 128, 128, 0, 0], "row {y}");
        }
    }

    /// Overlapping pieces ink a sample once; a pen 2 px wide on pixel centres inks the
    /// rows beside the line by half; off the screen nothing is inked, and a piece with
    /// a coordinate that is not finite is left out.
    #[test]
    fn overlaps_ink_once_wide_pens_ink_more_and_off_screen_nothing() {
        let one = coverage(&[seg(1.0, 2.5, 4.0, 2.5)], 6, 5, 1.0, 16);
        let twice = coverage(
            &[seg(1.0, 2.5, 4.0, 2.5), seg(0.5, 2.5, 4.0, 2.5)],
            6,
            5,
            1.0,
            16,
        );
        assert!(twice.iter().all(|&n| n <= 256));
        assert_eq!(twice[2 * 6 + 2], one[2 * 6 + 2]);
        let wide = coverage(&[seg(1.0, 2.5, 4.0, 2.5)], 6, 5, 2.0, 16);
        assert_eq!(wide[6 + 2..6 + 4], [128, 128]);
        assert_eq!(wide[2 * 6 + 2], 256);
        assert_eq!(
            coverage(&[seg(-10.0, -5.0, 20.0, -5.0)], 6, 5, 1.0, 16),
            vec![0; 30]
        );
        assert_eq!(
            coverage(&[seg(f64::NAN, 1.0, 2.0, 2.0)], 6, 5, 1.0, 16),
            vec![0; 30]
        );
        // One sample a pixel: a pixel centre within ½ px of the line, its border included
        // (the centres (0.5, 2.5) and (4.5, 2.5) lie on the caps' rims).
        let point = coverage(&[seg(1.2, 2.5, 3.8, 2.5)], 6, 5, 1.0, 1);
        assert_eq!(point[12..18], [0, 1, 1, 1, 0, 0]);
        let point = coverage(&[seg(1.0, 2.5, 4.0, 2.5)], 6, 5, 1.0, 1);
        assert_eq!(point[12..18], [1, 1, 1, 1, 1, 0]);
    }

    /// A piece longer than 64 samples sets whole words of the bit row; a diagonal crosses
    /// every row between its ends.
    #[test]
    fn long_and_diagonal_pieces() {
        let counts = coverage(&[seg(0.0, 0.5, 40.0, 0.5)], 40, 1, 1.0, 16);
        assert_eq!(counts, [256; 40]);
        let counts = coverage(&[seg(3.0, 0.5, 37.0, 0.5)], 40, 1, 1.0, 16);
        assert_eq!(
            counts[2..=37],
            [&[104][..], &[256; 34], &[104]].concat()[..]
        );
        assert_eq!(counts.iter().sum::<u32>(), 2 * 104 + 34 * 256);
        let d = coverage(&[seg(0.5, 0.5, 9.5, 9.5)], 10, 10, 1.0, 16);
        for i in 1..9 {
            assert!(d[i * 10 + i] > 200, "{i}: {}", d[i * 10 + i]);
            assert_eq!(d[i * 10 + i], d[10 + 1], "{i}: the same along the diagonal");
        }
    }

    mod properties {
        use super::*;
        use proptest::prelude::*;

        proptest! {
            /// The count of a pixel is that of testing each of its samples against each
            /// piece's stroke one by one (the distance to a segment).
            #[test]
            fn counts_are_the_samples_within_half_the_pen(
                pieces in prop::collection::vec(
                    (-2.0f64..10.0, -2.0f64..8.0, -2.0f64..10.0, -2.0f64..8.0), 1..4),
                pen in 0.2f64..3.0,
                k in 1u32..6,
            ) {
                let segs: Vec<Segment> =
                    pieces.iter().map(|&(a, b, c, d)| seg(a, b, c, d)).collect();
                let (w, h) = (8u32, 6u32);
                let got = coverage(&segs, w, h, pen, k);
                let dist = |p: DVec2, s: &Segment| {
                    let d = s.to - s.from;
                    let t = if d.length_squared() > 0.0 {
                        ((p - s.from).dot(d) / d.length_squared()).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    (p - (s.from + d * t)).length()
                };
                for y in 0..h {
                    for x in 0..w {
                        let mut want = 0;
                        let mut close = false;
                        for j in 0..k {
                            for i in 0..k {
                                let p = DVec2::new(
                                    x as f64 + (i as f64 + 0.5) / k as f64,
                                    y as f64 + (j as f64 + 0.5) / k as f64,
                                );
                                let near = segs.iter().map(|s| dist(p, s)).fold(f64::INFINITY, f64::min);
                                want += u32::from(near <= pen / 2.0);
                                close |= (near - pen / 2.0).abs() < 1e-9;
                            }
                        }
                        // A sample on the stroke's very border may fall either way.
                        if !close {
                            prop_assert_eq!(got[(y * w + x) as usize], want, "pixel {} {}", x, y);
                        }
                    }
                }
            }
        }
    }
}
