//! `-o PATTERN`: the file names of a stage that writes one file per frame (zbuf's pictures,
//! hiddenline's SVG), as ffmpeg's image2 muxer reads them.

/// A file name pattern for one file per frame: `%d` is the frame number (from 0), `%0Nd`
/// (or `%Nd`) the frame number zero-padded to N digits, `%%` a literal `%`. At most one
/// number field.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FrameNames {
    prefix: String,
    /// The field's width and the text after it; `None` when the pattern has no field.
    field: Option<(usize, String)>,
}

impl FrameNames {
    /// Parses `pattern`; the error names it as `-o PATTERN: …`.
    pub fn parse(pattern: &str) -> Result<Self, String> {
        let mut prefix = String::new();
        let mut field: Option<(usize, String)> = None;
        let mut chars = pattern.chars().peekable();
        while let Some(ch) = chars.next() {
            let text = match &mut field {
                Some((_, suffix)) => suffix,
                None => &mut prefix,
            };
            if ch != '%' {
                text.push(ch);
                continue;
            }
            if chars.peek() == Some(&'%') {
                chars.next();
                text.push('%');
                continue;
            }
            let mut digits = String::new();
            while let Some(d) = chars.peek().filter(|d| d.is_ascii_digit()) {
                digits.push(*d);
                chars.next();
            }
            if chars.next() != Some('d') {
                return Err(format!(
                    "-o {pattern}: `%` must start %d, %0Nd or %% (as in ffmpeg's image2)"
                ));
            }
            if field.is_some() {
                return Err(format!("-o {pattern}: more than one frame number field"));
            }
            let width = if digits.is_empty() {
                0
            } else {
                digits
                    .parse::<usize>()
                    .ok()
                    .filter(|w| *w <= 20)
                    .ok_or_else(|| format!("-o {pattern}: field width {digits} is too wide"))?
            };
            field = Some((width, String::new()));
        }
        Ok(FrameNames { prefix, field })
    }

    /// Parses `pattern` as [`FrameNames::parse`] does, and requires its file names to end
    /// in one of `extensions` (any case): a picture or drawing written under another
    /// name would be read as something it is not. Returns the names and the extension
    /// matched, as `extensions` spells it.
    pub fn parse_ending<'a>(
        pattern: &str,
        extensions: &[&'a str],
    ) -> Result<(Self, &'a str), String> {
        let names = FrameNames::parse(pattern)?;
        let ext = std::path::Path::new(pattern)
            .extension()
            .and_then(|e| e.to_str());
        let found = extensions
            .iter()
            .find(|want| ext.is_some_and(|e| e.eq_ignore_ascii_case(want)));
        match found {
            Some(&want) => Ok((names, want)),
            None => {
                let mut list: Vec<String> = extensions.iter().map(|e| format!(".{e}")).collect();
                let last = list.pop().unwrap_or_default();
                let ends = if list.is_empty() {
                    last
                } else {
                    format!("{} or {last}", list.join(", "))
                };
                Err(format!("-o {pattern}: the file name must end {ends}"))
            }
        }
    }

    /// Whether the pattern numbers its files (and so can take more than one frame).
    pub fn numbered(&self) -> bool {
        self.field.is_some()
    }

    /// The file name of frame `n`.
    pub fn name(&self, n: u64) -> String {
        match &self.field {
            Some((width, suffix)) => format!("{}{n:0width$}{suffix}", self.prefix),
            None => self.prefix.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_ending_is_required_in_any_case_and_named_when_missing() {
        let (names, ext) = FrameNames::parse_ending("f%02d.PNG", &["png", "ppm"]).unwrap();
        assert_eq!((names.name(3).as_str(), ext), ("f03.PNG", "png"));
        assert_eq!(
            FrameNames::parse_ending("a.ppm", &["png", "ppm"])
                .unwrap()
                .1,
            "ppm"
        );
        for (pattern, extensions, ends) in [
            ("x.jpg", &["png", "ppm"][..], ".png or .ppm"),
            ("lines.png", &["svg"][..], ".svg"),
            ("-", &["svg"][..], ".svg"),
            ("f.x", &["a", "b", "c"][..], ".a, .b or .c"),
        ] {
            assert_eq!(
                FrameNames::parse_ending(pattern, extensions).unwrap_err(),
                format!("-o {pattern}: the file name must end {ends}")
            );
        }
        // The pattern's own errors come first.
        assert!(FrameNames::parse_ending("x%s.svg", &["svg"])
            .unwrap_err()
            .contains("`%` must start"));
    }

    #[test]
    fn fields_widths_and_percent_signs() {
        let p = FrameNames::parse("f%03d.png").unwrap();
        assert!(p.numbered());
        assert_eq!(p.name(7), "f007.png");
        assert_eq!(p.name(12345), "f12345.png");
        assert_eq!(FrameNames::parse("a%d%%.svg").unwrap().name(12), "a12%.svg");
        assert_eq!(FrameNames::parse("one.svg").unwrap().name(3), "one.svg");
        assert!(!FrameNames::parse("one.svg").unwrap().numbered());
        assert_eq!(
            FrameNames::parse("x%s").unwrap_err(),
            "-o x%s: `%` must start %d, %0Nd or %% (as in ffmpeg's image2)"
        );
        assert_eq!(
            FrameNames::parse("%d%d").unwrap_err(),
            "-o %d%d: more than one frame number field"
        );
        assert_eq!(
            FrameNames::parse("%099d").unwrap_err(),
            "-o %099d: field width 099 is too wide"
        );
    }
}
