//! A decimal number of the text form, read in one pass and rounded exactly: the short
//! form every scene is written in (`-7.697877382108967`, `0.5`, `1e-3`), its digits taken
//! eight at a time.
//!
//! A number is `[+-]digits[.digits][(e|E)[+-]digits]` with at least one digit before the
//! exponent: every such word is one `str::parse::<f64>` reads, and this reads it to the
//! same bits. Its significant digits (leading zeros left out) make an integer `w` below
//! 10¹⁹, and its value is `w·10^q`, rounded to the nearest double once by the
//! Eisel–Lemire method (D. Lemire, "Number Parsing at a Gigabyte per Second", Software:
//! Practice and Experience 51 (2021), §5–§7): `w`, shifted to fill 64 bits, times a
//! 128-bit truncation of 5^q gives the significand's top bits, and the product's low bits
//! tell whether a carry from the truncated part could change them; where it could, the
//! number is left to the full parser. That is how `str::parse` and fast_float2 round
//! too; here only for q within [`Q_MIN`]..=[`Q_MAX`], whose powers of five are tabulated
//! below, computed at compile time. (Clinger's fast path, one IEEE division of two exact
//! doubles, is exact as well where `w` ≤ 2⁵³ and |q| ≤ 22, but half of a scene's numbers
//! have 17 digits and miss it, and the branch between the two methods, taken at random,
//! cost more than the division saved.)
//!
//! The common shape, `[-]D.DDDDDDDDDDDDDDDD` with one to three digits before the point
//! and at most 16 after it, is read without a branch that depends on the digits: the
//! integer part and the fraction as 8-byte words, each word's run of digits found by a
//! bit test and converted by multiplications, the fraction padded with zeros to 16
//! digits (`w·10⁻¹⁶` is the same number, and the rounding does not see the zeros).
//! Anything else (an exponent, no point, a longer integer part or fraction, a number near
//! the end of the input) is read digit by digit; and what is not a number of this form
//! or out of range (more than 19 significant digits, q outside the table, an exponent of
//! more than four digits, `inf`, `nan`, no digit) answers `None`, and the caller reads
//! the word with the full parser: this one is only faster, never different.

/// The least and greatest power of ten read here; a number needing another goes to the
/// full parser. Scenes' numbers have q from −21 to 2 (17 digits after the point at most
/// for a double printed shortest).
pub(crate) const Q_MIN: i32 = -64;
pub(crate) const Q_MAX: i32 = 32;

/// The most significant digits read here: 10¹⁹ − 1 fits in 64 bits.
const MOST_DIGITS: usize = 19;

/// 10^k, for k up to 19 digits.
const POW10_U64: [u64; 20] = {
    let mut t = [1u64; 20];
    let mut k = 1;
    while k < 20 {
        t[k] = t[k - 1] * 10;
        k += 1;
    }
    t
};

/// The bytes the read of the common shape looks at: a sign, eight from the integer part
/// on (three digits and the point at most are its), and from the fraction's start 16 and
/// the byte after them.
const SHAPE_BYTES: usize = 1 + 4 + 16 + 1;

/// Reads the number at the start of `s`: its value and the bytes it took, which stop at
/// the first byte that cannot go on the number (the caller checks what that byte is).
/// `None` where the number is not one read here (see the module's notes), and the full
/// parser must decide.
#[inline]
pub fn parse_decimal(s: &[u8]) -> Option<(f64, usize)> {
    if s.len() >= SHAPE_BYTES {
        if let Some(read) = common_shape(s) {
            return Some(read);
        }
    }
    digit_by_digit(s)
}

/// [`parse_decimal`] for the common shape, `[+-]D.DDD…` (one to three digits before the
/// point, at most 16 after it, no exponent), with [`SHAPE_BYTES`] bytes of `s` to look
/// at; `None` for any other shape. The integer part and the fraction are read as 8-byte
/// words, each word's digits found by a bit test, and the fraction is taken as 16 digits,
/// zeros after its own: `int·10¹⁶ + fraction·10^(16−n)` times 10⁻¹⁶ is the number, and
/// the Eisel–Lemire step rounds it the same whatever zeros it ends in. So the only
/// branches test the shape, and no digit count moves a digit.
#[inline]
fn common_shape(s: &[u8]) -> Option<(f64, usize)> {
    let word = |at: usize| u64::from_le_bytes(s[at..at + 8].try_into().expect("8 bytes"));
    let first = s[0];
    let negative = first == b'-';
    let p = usize::from(negative || first == b'+');
    let a = word(p);
    let int_run = digit_run(a);
    if int_run == 0 || int_run > 3 || s[p + int_run] != b'.' {
        return None;
    }
    let f = p + int_run + 1;
    let (b, c) = (word(f), word(f + 8));
    // The second word counts only where the first is all digits (r1 >> 3 is 1 for a run
    // of 8, else 0: a product, not a branch).
    let r1 = digit_run(b);
    let r2 = (r1 >> 3) * digit_run(c);
    let end = f + r1 + r2;
    // A 17th digit after the point, or an exponent: read digit by digit.
    if matches!(s[end], b'0'..=b'9' | b'e' | b'E') {
        return None;
    }
    // int·10¹⁶ (below 10¹⁹: three digits at most) plus the fraction's 16 digits.
    let w = padded_digits(a, int_run) * POW10_U64[8 + int_run]
        + padded_digits(b, r1) * POW10_U64[8]
        + padded_digits(c, r2);
    let magnitude = if w == 0 { 0 } else { eisel_lemire(-16, w)? };
    // The sign as a bit, not a branch: a scene's signs come at random.
    Some((f64::from_bits(magnitude | u64::from(negative) << 63), end))
}

/// [`parse_decimal`] a digit at a time (eight at a time after the point, where eight
/// bytes are left): every shape of the grammar.
fn digit_by_digit(s: &[u8]) -> Option<(f64, usize)> {
    let mut i = 0;
    let negative = match s.first()? {
        b'-' => {
            i = 1;
            true
        }
        b'+' => {
            i = 1;
            false
        }
        _ => false,
    };
    let int_start = i;
    // Leading zeros are not significant digits: `0.000123` is w = 123, q = −6.
    while s.get(i) == Some(&b'0') {
        i += 1;
    }
    let int_digits = i;
    let mut w = 0u64;
    while let Some(d) = s.get(i).map(|b| b.wrapping_sub(b'0')).filter(|&d| d < 10) {
        w = w.wrapping_mul(10).wrapping_add(u64::from(d));
        i += 1;
    }
    let mut significant = i - int_digits;
    let mut any_digit = i > int_start;
    let mut q = 0i64;
    if s.get(i) == Some(&b'.') {
        i += 1;
        let frac_start = i;
        if w == 0 {
            while s.get(i) == Some(&b'0') {
                i += 1;
            }
        }
        let digits_start = i;
        // The digits after the point, eight at a time while eight bytes are left, and
        // the run that ends within those eight read at once too; a short tail by bytes.
        loop {
            let Some(chunk) = s.get(i..i + 8) else {
                while let Some(d) = s.get(i).map(|b| b.wrapping_sub(b'0')).filter(|&d| d < 10) {
                    w = w.wrapping_mul(10).wrapping_add(u64::from(d));
                    i += 1;
                }
                break;
            };
            let v = u64::from_le_bytes(chunk.try_into().expect("8 bytes"));
            let run = digit_run(v);
            if run == 8 {
                w = w.wrapping_mul(100_000_000).wrapping_add(eight_digits(v));
                i += 8;
                if i - digits_start + significant > MOST_DIGITS {
                    return None;
                }
                continue;
            }
            w = w
                .wrapping_mul(POW10_U64[run])
                .wrapping_add(leading_digits(v, run));
            i += run;
            break;
        }
        significant += i - digits_start;
        any_digit |= i > frac_start;
        q = -((i - frac_start) as i64);
    }
    if !any_digit || significant > MOST_DIGITS {
        return None;
    }
    if let Some(b'e' | b'E') = s.get(i) {
        let mut j = i + 1;
        let exp_negative = match s.get(j) {
            Some(b'-') => {
                j += 1;
                true
            }
            Some(b'+') => {
                j += 1;
                false
            }
            _ => false,
        };
        let exp_start = j;
        let mut e = 0i64;
        while let Some(d) = s.get(j).map(|b| b.wrapping_sub(b'0')).filter(|&d| d < 10) {
            e = e * 10 + i64::from(d);
            j += 1;
            if j - exp_start > 4 {
                return None;
            }
        }
        if j == exp_start {
            return None; // `1e`, `1e+`: not a number, which the full parser says
        }
        q += if exp_negative { -e } else { e };
        i = j;
    }
    let magnitude = if w == 0 {
        0.0
    } else if (i64::from(Q_MIN)..=i64::from(Q_MAX)).contains(&q) {
        f64::from_bits(eisel_lemire(q as i32, w)?)
    } else {
        return None;
    };
    Some((if negative { -magnitude } else { magnitude }, i))
}

/// How many of the eight bytes of `v` (the first in the lowest byte) are digits before
/// the first that is not. Each byte is flagged when it is below `0` (the subtraction's
/// top bit) or above `9` (the addition's); a byte's borrow or carry only reaches the
/// bytes after it, and a digit makes neither, so the first flagged byte is the first
/// non-digit.
#[inline]
fn digit_run(v: u64) -> usize {
    const HIGHS: u64 = 0x8080_8080_8080_8080;
    let flags =
        (v.wrapping_add(0x4646_4646_4646_4646) | v.wrapping_sub(0x3030_3030_3030_3030)) & HIGHS;
    // No flag: 64 trailing zeros, eight digits.
    flags.trailing_zeros() as usize / 8
}

/// The eight ASCII digits of `v` (the first in the lowest byte) as a number: pairs, then
/// fours, then the eight combined by multiplications (as fast_float's SWAR step).
#[inline]
fn eight_digits(v: u64) -> u64 {
    combine_eight(v.wrapping_sub(0x3030_3030_3030_3030))
}

/// The first `run` (0 to 8) bytes of `v`, digits, as a number.
#[inline]
fn leading_digits(v: u64, run: usize) -> u64 {
    // The digits' values in the low bytes (a digit borrows nothing), then moved up so
    // that the bytes past the run fall off the top and zeros lead: the same number as
    // eight digits. Two shifts, each under 64 bits, so that a run of 0 gives 0.
    let shift = 4 * (8 - run) as u32;
    combine_eight((v.wrapping_sub(0x3030_3030_3030_3030) << shift) << shift)
}

/// The first `run` (0 to 8) bytes of `v`, digits, followed by zeros to eight digits, as
/// a number: the run's value times 10^(8 − run).
#[inline]
fn padded_digits(v: u64, run: usize) -> u64 {
    // The digits' values (a digit borrows nothing from the bytes after it), the bytes
    // past the run cleared; two shifts, each under 64 bits, for runs of 0 and 8.
    let keep = !((u64::MAX << (4 * run)) << (4 * run));
    combine_eight(v.wrapping_sub(0x3030_3030_3030_3030) & keep)
}

/// Eight digit values, one a byte, the most significant in the lowest byte, as a number.
#[inline]
fn combine_eight(mut v: u64) -> u64 {
    const MASK: u64 = 0x0000_00FF_0000_00FF;
    const MUL1: u64 = 0x000F_4240_0000_0064; // 100 + (1,000,000 << 32)
    const MUL2: u64 = 0x0000_2710_0000_0001; // 1 + (10,000 << 32)
    v = v.wrapping_mul(10).wrapping_add(v >> 8); // pairs
    let v1 = (v & MASK).wrapping_mul(MUL1);
    let v2 = ((v >> 16) & MASK).wrapping_mul(MUL2);
    u64::from((v1.wrapping_add(v2) >> 32) as u32)
}

/// The Eisel–Lemire step for doubles (Lemire 2021, §5–§7, as fast_float's
/// `compute_float`): the bits of the double nearest `w·10^q` (w > 0, q in
/// `Q_MIN..=Q_MAX`), or `None` where the 128-bit product cannot tell which it is.
/// Doubles have 52 explicit significand bits; with q in this range the result is never
/// subnormal or infinite.
#[inline]
fn eisel_lemire(q: i32, w: u64) -> Option<u64> {
    const EXPLICIT: i32 = 52;
    let lz = w.leading_zeros() as i32;
    let w = w << lz;
    // w·5^q to 128 bits: the first product, and the second only when the first's low
    // part of the significand's bits is all ones (a carry from below could change it).
    let (hi5, lo5) = POW5_128[(q - Q_MIN) as usize];
    let first = u128::from(w) * u128::from(hi5);
    let (mut lo, mut hi) = (first as u64, (first >> 64) as u64);
    const PRECISION_MASK: u64 = u64::MAX >> (EXPLICIT + 3);
    if hi & PRECISION_MASK == PRECISION_MASK {
        let second_hi = ((u128::from(w) * u128::from(lo5)) >> 64) as u64;
        lo = lo.wrapping_add(second_hi);
        if second_hi > lo {
            hi += 1;
        }
    }
    // All ones below: the truncated power may have lost the carry that would decide the
    // rounding. Exact for q in −27..=55, where 5^q is held exactly (or w·5^q is).
    if lo == u64::MAX && !(-27..=55).contains(&q) {
        return None;
    }
    let upper = (hi >> 63) as i32;
    let mut mantissa = hi >> (upper + 64 - EXPLICIT - 3);
    // The binary exponent: floor(q·log2(10)) + 63 (Lemire's 152,170/65,536 + 1 for
    // log2(10)), with the bias of 1,023.
    let mut power2 = (((q.wrapping_mul(152_170 + 65_536)) >> 16) + 63) + upper - lz + 1023;
    if power2 <= 0 {
        return None; // subnormal: not within this range of q, but not assumed either
    }
    // Exactly halfway between two doubles (possible only for q in −4..=23): round to
    // even, where adding one would round up.
    if lo <= 1
        && (-4..=23).contains(&q)
        && mantissa & 3 == 1
        && (mantissa << (upper + 64 - EXPLICIT - 3)) == hi
    {
        mantissa &= !1;
    }
    mantissa += mantissa & 1;
    mantissa >>= 1;
    if mantissa >= 2 << EXPLICIT {
        mantissa = 1 << EXPLICIT;
        power2 += 1;
    }
    mantissa &= !(1 << EXPLICIT);
    if power2 >= 0x7ff {
        return None;
    }
    Some(mantissa | (power2 as u64) << EXPLICIT)
}

/// 5^q for q in `Q_MIN..=Q_MAX` as 128 bits (high, low), normalised to have the top bit
/// set: for q ≥ 0 the power's top 128 bits; for q < 0, 2^b / 5^−q rounded up, with b
/// large enough that the quotient has at least 128 bits, then its top 128 (Lemire 2021,
/// §6: rounded up, the product errs on one side only, which the step above allows for).
static POW5_128: [(u64, u64); (Q_MAX - Q_MIN + 1) as usize] = pow5_table();

/// A number of up to 512 bits, eight 64-bit limbs from the least significant, for the
/// table's computation at compile time.
type Big = [u64; 8];

const fn pow5_table() -> [(u64, u64); (Q_MAX - Q_MIN + 1) as usize] {
    let mut table = [(0, 0); (Q_MAX - Q_MIN + 1) as usize];
    let mut k = 0;
    while k < table.len() {
        table[k] = pow5_128(Q_MIN + k as i32);
        k += 1;
    }
    table
}

/// One entry of [`POW5_128`] (the rule of fast_float's table generator).
const fn pow5_128(q: i32) -> (u64, u64) {
    let mut c: Big = [0; 8];
    if q >= 0 {
        c[0] = 1;
        let mut k = 0;
        while k < q {
            c = mul_small(c, 5);
            k += 1;
        }
    } else {
        // z: the bit length of 5^−q (never a power of two), so 2^z > 5^−q.
        let mut pow: Big = [0; 8];
        pow[0] = 1;
        let mut k = 0;
        while k < -q {
            pow = mul_small(pow, 5);
            k += 1;
        }
        let z = bit_length(&pow);
        let b = if q < -27 { 2 * z + 128 } else { z + 127 };
        // floor(2^b / 5^−q) is 2^b divided by 5, −q times (floor of floor is floor).
        c[(b / 64) as usize] = 1 << (b % 64);
        let mut k = 0;
        while k < -q {
            c = div_small(c, 5);
            k += 1;
        }
        c = add_one(c);
    }
    let length = bit_length(&c);
    if length > 128 {
        c = shift_right(c, length - 128);
    } else {
        c = shift_left(c, 128 - length);
    }
    (c[1], c[0])
}

const fn mul_small(a: Big, m: u64) -> Big {
    let mut out: Big = [0; 8];
    let mut carry: u128 = 0;
    let mut k = 0;
    while k < 8 {
        let t = a[k] as u128 * m as u128 + carry;
        out[k] = t as u64;
        carry = t >> 64;
        k += 1;
    }
    assert!(carry == 0, "the table's numbers fit in 512 bits");
    out
}

const fn div_small(a: Big, d: u64) -> Big {
    let mut out: Big = [0; 8];
    let mut rem: u128 = 0;
    let mut k = 8;
    while k > 0 {
        k -= 1;
        let t = (rem << 64) | a[k] as u128;
        out[k] = (t / d as u128) as u64;
        rem = t % d as u128;
    }
    out
}

const fn add_one(a: Big) -> Big {
    let mut out = a;
    let mut k = 0;
    while k < 8 {
        out[k] = out[k].wrapping_add(1);
        if out[k] != 0 {
            break;
        }
        k += 1;
    }
    out
}

const fn bit_length(a: &Big) -> u32 {
    let mut k = 8;
    while k > 0 {
        k -= 1;
        if a[k] != 0 {
            return k as u32 * 64 + 64 - a[k].leading_zeros();
        }
    }
    0
}

const fn shift_right(a: Big, n: u32) -> Big {
    let mut out: Big = [0; 8];
    let (limbs, bits) = ((n / 64) as usize, n % 64);
    let mut k = 0;
    while k + limbs < 8 {
        let lo = a[k + limbs] >> bits;
        let hi = if bits > 0 && k + limbs + 1 < 8 {
            a[k + limbs + 1] << (64 - bits)
        } else {
            0
        };
        out[k] = lo | hi;
        k += 1;
    }
    out
}

const fn shift_left(a: Big, n: u32) -> Big {
    let mut out: Big = [0; 8];
    let (limbs, bits) = ((n / 64) as usize, n % 64);
    let mut k = limbs;
    while k < 8 {
        let hi = a[k - limbs] << bits;
        let lo = if bits > 0 && k > limbs {
            a[k - limbs - 1] >> (64 - bits)
        } else {
            0
        };
        out[k] = hi | lo;
        k += 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// What `str::parse` says of a word, as bits (`None`: not a number).
    fn std_bits(w: &str) -> Option<u64> {
        w.parse::<f64>().ok().map(f64::to_bits)
    }

    /// What follows a word in a line: nothing (the input's end), or a blank or a newline
    /// and more, so that the common shape's read (which needs bytes to look at) is tried.
    const TAILS: [&str; 3] = [
        "",
        " 0123456789012345678901234567890123456789",
        "\n99999999999999999999999999999999999999e",
    ];

    /// parse_decimal over a word, with each of [`TAILS`] after it: the same bits as
    /// `str::parse` wherever it answers, stopping where the word ends.
    fn check(w: &str) {
        for tail in TAILS {
            let text = format!("{w}{tail}");
            if let Some((v, used)) = parse_decimal(text.as_bytes()) {
                // Where it stops early, the rest is not part of a number of this form,
                // and the part read is one str::parse reads to the same bits.
                assert!(used <= w.len(), "{text:?}");
                assert_eq!(Some(v.to_bits()), std_bits(&w[..used]), "{text:?}");
            }
        }
    }

    /// parse_decimal reads all of `w`, with any tail, to str::parse's bits.
    fn read_whole(w: &str) {
        for tail in TAILS {
            let text = format!("{w}{tail}");
            let got = parse_decimal(text.as_bytes()).map(|(v, used)| (v.to_bits(), used));
            assert_eq!(got, Some((std_bits(w).unwrap(), w.len())), "{text:?}");
        }
    }

    #[test]
    fn the_table_holds_the_known_powers() {
        // 5^0 and 5^1 normalised; 5^−1 = 0.2 = 0x3333…·2^−130, rounded up.
        assert_eq!(POW5_128[(0 - Q_MIN) as usize], (1 << 63, 0));
        assert_eq!(POW5_128[(1 - Q_MIN) as usize], (0xa000_0000_0000_0000, 0));
        assert_eq!(
            POW5_128[(-1 - Q_MIN) as usize],
            (0xcccc_cccc_cccc_cccc, 0xcccc_cccc_cccc_cccd)
        );
        // 5^27 is the largest power below 2^64: exact, shifted up.
        let p27 = 5u64.pow(27);
        let lz = p27.leading_zeros();
        assert_eq!(POW5_128[(27 - Q_MIN) as usize], (p27 << lz, 0));
        // 5^32 takes 75 bits; its top 128 are it, shifted up by 53.
        let p32 = 5u128.pow(32) << 53;
        assert_eq!(
            POW5_128[(32 - Q_MIN) as usize],
            ((p32 >> 64) as u64, p32 as u64)
        );
    }

    #[test]
    fn the_scenes_numbers_and_the_edges_read_as_str_parse_reads_them() {
        let words = [
            "9.819403625187153",
            "-7.697877382108967",
            "1.0006495953187375",
            "0.07108830759799653",
            "-0.0004417409009040803",
            "0",
            "-0",
            "-0.0",
            "+0.0e5",
            "1",
            "+1",
            "1.",
            ".5",
            "-.5",
            "1e5",
            "1E5",
            "1e+5",
            "1e-5",
            "1.e5",
            "00012",
            "0.1",
            "0.3",
            "9007199254740993",
            "9007199254740992",
            "9007199254740991.5",
            "18446744073709551615",
            "9999999999999999999",
            "1000000000000000000",
            "0.1000000000000000055511151231257827",
            "2.2250738585072014e-308",
            "1.7976931348623157e308",
            "1e-64",
            "1e-65",
            "9.999999999999999e-50",
            "1e32",
            "1e33",
            "123456789012345678e-30",
            "4.35679e-6",
            "8.98846567431158e307",
            "0.000000000000000000000000000000000001",
            "12345.678901234567890",
            "1e00001",
            "1e0001",
            "1e23",
            "8.589973e9",
            "0.000000000000000e0",
            "7552238296763070.5",
        ];
        for w in words {
            check(w);
        }
        // The form a scene is written in is always read here.
        for w in [
            "9.819403625187153",
            "-0.0004417409009040803",
            "1",
            ".5",
            "1e-5",
            "+1234567.123456789012",
            "12345678.12345678901",
            "0.1234567890123456789",
            "-1.",
            "-0.0",
        ] {
            read_whole(w);
        }
        // Halfway cases: 2^53 + 1 and its neighbours, and 0.5 ulp past 1.
        for w in [
            "9007199254740993",
            "9007199254740995",
            "9007199254740993.0",
            "1.00000000000000011102230246251565",
            "1.0000000000000001110223024625156",
        ] {
            check(w);
        }
        // What is not read here.
        for w in [
            "", "-", "+", ".", "e5", "inf", "nan", "-inf", "1e", "1e+", "1e12345",
        ] {
            assert_eq!(parse_decimal(w.as_bytes()), None, "{w:?}");
        }
        for w in [
            "12345678901234567890",
            "0.12345678901234567890",
            "1e-65",
            "1e33",
        ] {
            assert_eq!(parse_decimal(w.as_bytes()), None, "{w:?}");
        }
    }

    #[test]
    fn it_stops_where_the_number_stops() {
        assert_eq!(parse_decimal(b"1.5 2"), Some((1.5, 3)));
        assert_eq!(parse_decimal(b"-2.25\n"), Some((-2.25, 5)));
        assert_eq!(parse_decimal(b"1.5.2"), Some((1.5, 3)));
        assert_eq!(parse_decimal(b"12345678x"), Some((12345678.0, 8)));
        assert_eq!(
            parse_decimal(b"0.123456789012x3"),
            Some((0.123456789012, 14))
        );
        assert_eq!(parse_decimal(b"3e2x"), Some((300.0, 3)));
        assert_eq!(parse_decimal(b"7,5"), Some((7.0, 1)));
    }

    #[test]
    fn eight_digits_at_a_time() {
        assert_eq!(digit_run(u64::from_le_bytes(*b"12345678")), 8);
        assert_eq!(digit_run(u64::from_le_bytes(*b"123 5678")), 3);
        assert_eq!(digit_run(u64::from_le_bytes(*b"/2345678")), 0);
        assert_eq!(digit_run(u64::from_le_bytes(*b"9:345678")), 1);
        assert_eq!(digit_run(u64::from_le_bytes(*b"99\xff45678")), 2);
        assert_eq!(
            digit_run(u64::from_le_bytes(*b"999\x00\xff\xff\xff\xff")),
            3
        );
        assert_eq!(eight_digits(u64::from_le_bytes(*b"12345678")), 12_345_678);
        assert_eq!(eight_digits(u64::from_le_bytes(*b"00000009")), 9);
        for run in 1..8 {
            let v = u64::from_le_bytes(*b"9876543 ");
            let v = (v & (u64::MAX >> (8 * (8 - run))))
                | (u64::from_le_bytes(*b"\xff\xff\xff\xff\xff\xff\xff\xff") << (8 * run));
            let want: u64 = "9876543"[..run].parse().unwrap();
            assert_eq!(leading_digits(v, run), want, "{run}");
        }
        assert_eq!(leading_digits(u64::from_le_bytes(*b" 1234567"), 0), 0);
        assert_eq!(
            leading_digits(u64::from_le_bytes(*b"87654321"), 8),
            87_654_321
        );
    }

    /// A decimal word of the short form: sign, integer digits, point, fraction digits,
    /// exponent, each part optional as the grammar allows.
    fn decimal_word() -> impl Strategy<Value = String> {
        (
            prop::sample::select(vec!["", "-", "+"]),
            "[0-9]{0,12}",
            prop::option::of("[0-9]{0,22}"),
            prop::option::of((
                prop::sample::select(vec!["e", "E", "e-", "e+", "E-"]),
                0u32..80,
            )),
        )
            .prop_map(|(sign, int, frac, exp)| {
                let mut w = format!("{sign}{int}");
                if let Some(f) = frac {
                    w.push('.');
                    w.push_str(&f);
                }
                if let Some((e, n)) = exp {
                    w.push_str(&format!("{e}{n}"));
                }
                w
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]

        /// Any word of the short form: the bits of str::parse, or left to it.
        #[test]
        fn short_form_words_read_as_str_parse(w in decimal_word()) {
            check(&w);
        }

        /// Every double, printed as a scene prints it (shortest, and with an exponent)
        /// and with fewer digits: read back to the bits str::parse gives, and read here
        /// wherever it is in the short form's range.
        #[test]
        fn doubles_as_printed_read_back(bits in any::<u64>(), digits in 1usize..18) {
            let x = f64::from_bits(bits);
            prop_assume!(x.is_finite());
            for w in [format!("{x}"), format!("{x:e}"), format!("{x:.digits$e}"), format!("{:.*}", digits, x)] {
                check(&w);
            }
        }

        /// Numbers of a scene's size (about 10⁻⁶ to 10⁴), where nearly every one must be read
        /// here and exactly.
        #[test]
        fn scene_sized_numbers_are_read_here(m in (1u64 << 52)..(1 << 53), e in -72i32..-38, neg: bool) {
            // m·2^e: every double from 2^−20 to 2^15.
            let x = m as f64 * 2f64.powi(e);
            let x = if neg { -x } else { x };
            read_whole(&format!("{x}"));
        }

        /// Numbers exactly halfway between two doubles, which round to the even one, and
        /// their neighbours a unit of the last digit away: doubles from 2^(53+s) up are
        /// 2^s apart, so (2t + 1)·2^(s−1) is halfway, and written as w·10^q when 2t + 1 is
        /// a multiple of 5^q and s − 1 ≥ q (the only q where a halfway w·10^q exists,
        /// 1 to 23, with w below 10^19; q = 0 by the integers' own halfway points).
        #[test]
        fn halfway_numbers_round_to_even(q in 0u32..=23, r: u64, extra in 0u32..=9, t in (1u64 << 52)..(1 << 53)) {
            let five = 5u64.pow(q);
            // An odd multiple of 5^q between 2^53 and 2^54 (odd, so halfway), the rest of
            // 2^(s−1) in `extra`.
            let lo = ((1u64 << 53) / five + 1) | 1;
            let hi = (1u64 << 54) / five;
            prop_assume!(lo <= hi);
            let odd = (lo + (r % (hi - lo + 1))) | 1;
            prop_assume!(odd <= hi);
            let w = (five * odd) << extra;
            prop_assume!(w < 10_000_000_000_000_000_000);
            for word in [format!("{w}e{q}"), format!("{}e{q}", w - 1), format!("{}e{q}", w + 1)] {
                check(&word);
            }
            // q = 0: the halfway point above the double 2t·2^s for s = 1..=10.
            let h = (u128::from(t) * 2 + 1) << (extra);
            if h < 10_000_000_000_000_000_000 {
                read_whole(&h.to_string());
            }
            if h < 1_000_000_000_000_000_000 {
                read_whole(&format!("{h}.0"));
            }
        }

        /// w·10^q over the table's whole range, with w of every length up to 19 digits:
        /// the Eisel–Lemire step and the fast path against str::parse.
        #[test]
        fn every_power_of_the_table(w in 1u64..10_000_000_000_000_000_000, q in (Q_MIN - 19)..=Q_MAX) {
            let word = format!("{w}e{q}");
            check(&word);
        }
    }
}
