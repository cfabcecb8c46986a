//! The parsers of numeric options, one set for every binary: each refuses what is not a
//! number, NaN, infinity and a value out of its range, in words that give the range, and
//! clap puts the option's name before them (`invalid value 'nan' for '--link-gbps <G>':
//! `nan` is not a finite number above 0`), status 2. A negative value reaches them as a
//! value, not as an unknown option (`args::hyphen_values`). Whole numbers use clap's own
//! `value_parser!(u32).range(…)`, which says its range the same way.

use proto::text::Shown;

/// Any finite number.
pub fn finite(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(format!("`{}` is not a finite number", Shown(s))),
        Err(_) => Err(format!("`{}` is not a number", Shown(s))),
    }
}

/// A finite number above 0.
pub fn positive(s: &str) -> Result<f64, String> {
    in_range(s, "a finite number above 0", |v| v > 0.0)
}

/// A finite number, 0 or more.
pub fn non_negative(s: &str) -> Result<f64, String> {
    in_range(s, "a finite number, 0 or more", |v| v >= 0.0)
}

/// A fraction, 0 to 1.
pub fn fraction(s: &str) -> Result<f64, String> {
    in_range(s, "a fraction from 0 to 1", |v| (0.0..=1.0).contains(&v))
}

/// A percentage, 0 to 100.
pub fn percent(s: &str) -> Result<f64, String> {
    in_range(s, "a percentage from 0 to 100", |v| {
        (0.0..=100.0).contains(&v)
    })
}

/// An angle in degrees, 0 to 180.
pub fn degrees(s: &str) -> Result<f64, String> {
    in_range(s, "an angle from 0 to 180 degrees", |v| {
        (0.0..=180.0).contains(&v)
    })
}

/// A parser of finite numbers from `min` to `max`, both included (`--link-gbps`: a link
/// of 1e-300 Gbit/s is no link, and predicted NaN seconds).
pub fn between(
    min: f64,
    max: f64,
) -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    move |s: &str| {
        let range = format!("a finite number from {min} to {max}");
        in_range(s, &range, |v| (min..=max).contains(&v))
    }
}

/// A parser of whole numbers from `min` to `max` (both included) of type `T`; a sign, a
/// fraction or a word is refused in the same words as a number out of range.
pub fn whole<T>(
    min: u64,
    max: u64,
) -> impl Fn(&str) -> Result<T, String> + Clone + Send + Sync + 'static
where
    T: TryFrom<u64> + Clone + Send + Sync + 'static,
{
    move |s: &str| {
        let range = if max == u64::MAX {
            format!("{min} or more")
        } else {
            format!("from {min} to {max}")
        };
        s.trim()
            .parse::<u64>()
            .ok()
            .filter(|v| (min..=max).contains(v))
            .and_then(|v| T::try_from(v).ok())
            .ok_or_else(|| format!("`{}` is not a whole number {range}", Shown(s)))
    }
}

/// A parser of one of the whole numbers `values` (supersample's `--samples`: 1, 2, 4, 8
/// or 16), which the message lists.
pub fn one_of(
    values: &'static [u32],
) -> impl Fn(&str) -> Result<u32, String> + Clone + Send + Sync + 'static {
    move |s: &str| {
        let v = s.trim().parse::<u32>().ok().filter(|v| values.contains(v));
        v.ok_or_else(|| {
            let listed: Vec<String> = values.iter().map(u32::to_string).collect();
            let list = match listed.split_last() {
                Some((last, rest)) if !rest.is_empty() => {
                    format!("{} or {last}", rest.join(", "))
                }
                _ => listed.concat(),
            };
            format!("`{}` is not {list}", Shown(s))
        })
    }
}

/// `s` as a finite number that `ok` takes; `what` says which those are (`a fraction from
/// 0 to 1`), for a word that is not one, NaN, an infinity or a number out of range alike.
fn in_range(s: &str, what: &str, ok: impl Fn(f64) -> bool) -> Result<f64, String> {
    match finite(s) {
        Ok(v) if ok(v) => Ok(v),
        _ => Err(format!("`{}` is not {what}", Shown(s.trim()))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_parser_takes_its_range_and_says_it() {
        assert_eq!(positive("2.5"), Ok(2.5));
        assert_eq!(non_negative("0"), Ok(0.0));
        assert_eq!(fraction("1"), Ok(1.0));
        assert_eq!(percent("99.95"), Ok(99.95));
        assert_eq!(degrees("180"), Ok(180.0));
        assert_eq!(finite("-3"), Ok(-3.0));
        for (parsed, said) in [
            (positive("0"), "`0` is not a finite number above 0"),
            (positive("-1"), "`-1` is not a finite number above 0"),
            (positive("nan"), "`nan` is not a finite number above 0"),
            (positive("inf"), "`inf` is not a finite number above 0"),
            (positive("x"), "`x` is not a finite number above 0"),
            (
                non_negative("-0.5"),
                "`-0.5` is not a finite number, 0 or more",
            ),
            (fraction("1.5"), "`1.5` is not a fraction from 0 to 1"),
            (percent("-1"), "`-1` is not a percentage from 0 to 100"),
            (
                degrees("1e308"),
                "`1e308` is not an angle from 0 to 180 degrees",
            ),
            (finite("-inf"), "`-inf` is not a finite number"),
        ] {
            assert_eq!(parsed, Err(said.to_string()));
        }
        let gbps = between(1e-3, 1e5);
        assert_eq!(gbps("10"), Ok(10.0));
        assert_eq!(
            gbps("1e-300"),
            Err("`1e-300` is not a finite number from 0.001 to 100000".into())
        );
        let frame = whole::<u64>(0, u64::MAX);
        assert_eq!(frame("7"), Ok(7));
        assert_eq!(
            frame("-3"),
            Err("`-3` is not a whole number 0 or more".into())
        );
        let cores = whole::<u32>(1, 4096);
        assert_eq!(
            cores("4097"),
            Err("`4097` is not a whole number from 1 to 4096".into())
        );
        assert_eq!(
            cores("2.5"),
            Err("`2.5` is not a whole number from 1 to 4096".into())
        );
        let samples = one_of(&[1, 2, 4, 8, 16]);
        assert_eq!(samples("8"), Ok(8));
        for bad in ["3", "-1", "32", "nan"] {
            assert_eq!(
                samples(bad),
                Err(format!("`{bad}` is not 1, 2, 4, 8 or 16"))
            );
        }
        // A long word is cut in the message.
        let long = "9".repeat(1000);
        let e = positive(&format!("-{long}")).unwrap_err();
        assert!(
            e.len() < 140 && e.contains("99… (1001 bytes)` is not"),
            "{e}"
        );
    }
}
