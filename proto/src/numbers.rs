//! The numbers a stage takes on its command line: a comma-separated point or plane
//! (`X,Y,Z`, `a,b,c,d,k`) and a screen size (`WxH`), each refused with a message that
//! names the form expected and the text found.

use glam::DVec3;

/// Parses `N` comma-separated finite numbers, e.g. `X,Y,Z`; `form` names them for the
/// message (`X,Y,Z`, `a,b,c,d,k`).
pub fn parse_numbers<const N: usize>(s: &str, form: &str) -> Result<[f64; N], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != N {
        return Err(format!("expected {form} ({N} numbers), found `{s}`"));
    }
    let mut v = [0.0; N];
    for (slot, p) in v.iter_mut().zip(&parts) {
        *slot = p
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("`{p}` in `{s}` is not a finite number"))?;
    }
    Ok(v)
}

/// Parses `X,Y,Z`.
pub fn parse_triple(s: &str) -> Result<DVec3, String> {
    parse_numbers::<3>(s, "X,Y,Z").map(DVec3::from_array)
}

/// Parses a screen size `WxH` (each 1 to 65536).
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WxH, e.g. 500x500, found `{s}`"))?;
    let dim = |t: &str| {
        t.trim()
            .parse::<u32>()
            .ok()
            .filter(|v| (1..=65536).contains(v))
            .ok_or_else(|| format!("`{t}` in `{s}` is not a size from 1 to 65536"))
    };
    Ok((dim(w)?, dim(h)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_read_in_their_form() {
        assert_eq!(parse_numbers::<2>(" 1.5, -2e3 ", "A,B"), Ok([1.5, -2000.0]));
        assert_eq!(parse_triple("0,0,-10"), Ok(DVec3::new(0.0, 0.0, -10.0)));
        assert_eq!(
            parse_numbers::<3>("1,2", "X,Y,Z"),
            Err("expected X,Y,Z (3 numbers), found `1,2`".to_string())
        );
        assert_eq!(
            parse_triple("1,inf,3"),
            Err("`inf` in `1,inf,3` is not a finite number".to_string())
        );
        assert_eq!(
            parse_triple("1,x,3"),
            Err("`x` in `1,x,3` is not a finite number".to_string())
        );
    }

    #[test]
    fn sizes_are_from_1_to_65536() {
        assert_eq!(parse_size("640x480"), Ok((640, 480)));
        assert_eq!(parse_size("1X65536"), Ok((1, 65536)));
        assert_eq!(
            parse_size("0x10"),
            Err("`0` in `0x10` is not a size from 1 to 65536".to_string())
        );
        assert_eq!(
            parse_size("10x65537"),
            Err("`65537` in `10x65537` is not a size from 1 to 65536".to_string())
        );
        assert_eq!(
            parse_size("500"),
            Err("expected WxH, e.g. 500x500, found `500`".to_string())
        );
    }
}
