//! Structured `--stats`: one schema for every stage's counters, one writer, one parser.
//!
//! A stage under `--stats` prints, on stderr, its readable line for people (`zbuf: leaf-2:
//! 155 spans, …`) and right after it the same counts as a *record*, the line programs
//! read (render's links report, the tests):
//!
//! ```text
//! @stats zbuf input=leaf-2 spans=155 runs=0 pixels=13684 bytes_in=5025
//! ```
//!
//! - The line starts with [`MARKER`] and a space, then the stage's program name, then
//!   `key=value` fields separated by single spaces, in the order written.
//! - A stage name and a key are ASCII: a lower-case letter, then lower-case letters,
//!   digits and `_`. Keys are fixed by the code that writes them (docs/DESIGN.md,
//!   "Structured stats", lists them with their units), so a bad one is a bug: the writer
//!   panics. A key appears at most once in a record.
//! - A value is any text. `%`, `=`, whitespace and control characters in it are written
//!   as `%XX` (each byte of their UTF-8), so that a field is one word with one `=`;
//!   everything else is written as it is. Counts are decimal integers; a list (warnock's
//!   windows by depth) is its items joined by `,`.
//!
//! Why `key=value` lines rather than JSON lines: the stages' stderr is text read by
//! people as much as by programs, a record must sit among the readable lines and survive
//! the relabelling render does to them, and every value is a count, a name or a short
//! list; one word a field reads in a terminal, greps (`grep '^@stats zbuf'`) and needs no
//! JSON crate in every stage.
//!
//! The readable line stays the stage's own prose; only the record is for programs, and
//! nothing should match the prose ([`records`], [`human`]).

use std::fmt::{self, Display, Write as _};
use std::io::Write as _;
use std::str::FromStr;

/// What starts every record line, followed by a space.
pub const MARKER: &str = "@stats";

/// One stage's counters: its name and its fields in the order written.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Record {
    stage: String,
    fields: Vec<(String, String)>,
}

/// A line that starts with [`MARKER`] but does not follow the schema.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseError {
    pub line: String,
    pub message: String,
}

impl Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "stats record `{}`: {}", self.line, self.message)
    }
}

impl std::error::Error for ParseError {}

/// Whether `word` is a stage name or key: a lower-case ASCII letter, then lower-case
/// letters, digits and `_`.
pub fn is_name(word: &str) -> bool {
    let mut bytes = word.bytes();
    bytes.next().is_some_and(|b| b.is_ascii_lowercase())
        && bytes.all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'_')
}

fn check_name(what: &str, word: &str) {
    assert!(
        is_name(word),
        "a stats {what} is a lower-case letter, then letters, digits and `_`: `{word}`"
    );
}

impl Record {
    /// An empty record of `stage` (its program name). Panics on a name outside the schema.
    pub fn new(stage: &str) -> Record {
        check_name("stage name", stage);
        Record {
            stage: stage.to_string(),
            fields: Vec::new(),
        }
    }

    /// The record with `key` set to `value` (written with `Display`), added at the end,
    /// or replacing the value where the key is there already. Panics on a key outside
    /// the schema (keys are the code's, not the input's).
    pub fn with(mut self, key: &str, value: impl Display) -> Record {
        self.set(key, value);
        self
    }

    /// [`Record::with`] in place.
    pub fn set(&mut self, key: &str, value: impl Display) {
        check_name("key", key);
        let value = value.to_string();
        match self.fields.iter_mut().find(|(k, _)| k == key) {
            Some((_, v)) => *v = value,
            None => self.fields.push((key.to_string(), value)),
        }
    }

    /// `list` joined by `,`, under `key`.
    pub fn with_list<T: Display>(self, key: &str, list: impl IntoIterator<Item = T>) -> Record {
        let items: Vec<String> = list.into_iter().map(|x| x.to_string()).collect();
        self.with(key, items.join(","))
    }

    /// The stage's program name.
    pub fn stage(&self) -> &str {
        &self.stage
    }

    /// The fields, in the order written.
    pub fn fields(&self) -> &[(String, String)] {
        &self.fields
    }

    /// The value of `key`, if the record has it.
    pub fn get(&self, key: &str) -> Option<&str> {
        self.fields
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// The value of `key` parsed as a `T` (a count: `u64`); `None` where it is missing
    /// or is not one.
    pub fn number<T: FromStr>(&self, key: &str) -> Option<T> {
        self.get(key)?.parse().ok()
    }

    /// The count under `key`: [`Record::number`] as `u64`.
    pub fn count(&self, key: &str) -> Option<u64> {
        self.number(key)
    }

    /// The list under `key` (items joined by `,`) parsed as `T`s; an empty value is an
    /// empty list. `None` where the key is missing or an item is not a `T`.
    pub fn list<T: FromStr>(&self, key: &str) -> Option<Vec<T>> {
        let v = self.get(key)?;
        if v.is_empty() {
            return Some(Vec::new());
        }
        v.split(',').map(|x| x.parse().ok()).collect()
    }

    /// Prints the readable line `human` (for people) and then this record (for programs)
    /// on stderr, in one write so that stages sharing a stderr do not interleave them.
    pub fn print(&self, human: &str) {
        let _ = std::io::stderr().write_all(format!("{human}\n{self}\n").as_bytes());
    }
}

/// `value` with `%`, `=`, whitespace and control characters written as `%XX`.
fn encode(value: &str, out: &mut String) {
    for c in value.chars() {
        if c == '%' || c == '=' || c.is_whitespace() || c.is_control() {
            let mut buf = [0; 4];
            for b in c.encode_utf8(&mut buf).bytes() {
                let _ = write!(out, "%{b:02X}");
            }
        } else {
            out.push(c);
        }
    }
}

/// The text `encode` wrote: `%XX` back to its byte.
fn decode(value: &str) -> Result<String, String> {
    let bytes = value.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = value
                .get(i + 1..i + 3)
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .filter(|_| bytes[i + 1].is_ascii_hexdigit() && bytes[i + 2].is_ascii_hexdigit())
                .ok_or_else(|| format!("`%` not followed by two hex digits in `{value}`"))?;
            out.push(hex);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| format!("`{value}` decodes to bytes that are not UTF-8"))
}

impl Display for Record {
    /// The record's line, without its newline.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut line = format!("{MARKER} {}", self.stage);
        for (k, v) in &self.fields {
            line.push(' ');
            line.push_str(k);
            line.push('=');
            encode(v, &mut line);
        }
        f.write_str(&line)
    }
}

impl FromStr for Record {
    type Err = ParseError;

    /// A record's line (without its newline), as [`Display`] writes it.
    fn from_str(line: &str) -> Result<Record, ParseError> {
        let fail = |message: String| ParseError {
            line: line.chars().take(80).collect(),
            message,
        };
        let rest = line
            .strip_prefix(MARKER)
            .and_then(|r| r.strip_prefix(' '))
            .ok_or_else(|| fail(format!("does not start with `{MARKER} `")))?;
        let mut words = rest.split(' ');
        let stage = words.next().unwrap_or("");
        if !is_name(stage) {
            return Err(fail(format!("`{stage}` is not a stage name")));
        }
        let mut record = Record {
            stage: stage.to_string(),
            fields: Vec::new(),
        };
        for word in words {
            let (key, value) = word
                .split_once('=')
                .ok_or_else(|| fail(format!("`{word}` is not key=value")))?;
            if !is_name(key) {
                return Err(fail(format!("`{key}` is not a key")));
            }
            if record.get(key).is_some() {
                return Err(fail(format!("`{key}` twice")));
            }
            if value.contains('=') {
                return Err(fail(format!("`{word}` has a second `=`")));
            }
            let value = decode(value).map_err(fail)?;
            record.fields.push((key.to_string(), value));
        }
        Ok(record)
    }
}

/// The record on `line`: `None` for a line that is not one (it does not start with
/// [`MARKER`] and a space), an error for one that does but breaks the schema.
pub fn parse_line(line: &str) -> Option<Result<Record, ParseError>> {
    line.strip_prefix(MARKER)?.strip_prefix(' ')?;
    Some(line.parse())
}

/// Every record in `text` (a stage's or a whole run's stderr), in order; the other lines
/// (the readable ones, messages) are passed over. An error for the first line that starts
/// like a record and is not one.
pub fn records(text: &str) -> Result<Vec<Record>, ParseError> {
    text.lines().filter_map(parse_line).collect()
}

/// The records of `stage` in `text` ([`records`]).
pub fn records_of(text: &str, stage: &str) -> Result<Vec<Record>, ParseError> {
    Ok(records(text)?
        .into_iter()
        .filter(|r| r.stage() == stage)
        .collect())
}

/// `text` without its record lines: what people read.
pub fn human(text: &str) -> String {
    text.lines()
        .filter(|l| parse_line(l).is_none())
        .map(|l| format!("{l}\n"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn a_record_is_one_line_of_key_value_words() {
        let r = Record::new("zbuf")
            .with("input", "leaf-2")
            .with("spans", 155u64)
            .with_list("windows", [12, 48, 0])
            .with("label", "splitter x=0 (node 2)")
            .with("share", "100%");
        let line = r.to_string();
        assert_eq!(
            line,
            "@stats zbuf input=leaf-2 spans=155 windows=12,48,0 \
             label=splitter%20x%3D0%20(node%202) share=100%25"
        );
        let back: Record = line.parse().unwrap();
        assert_eq!(back, r);
        assert_eq!(back.stage(), "zbuf");
        assert_eq!(back.count("spans"), Some(155));
        assert_eq!(back.get("label"), Some("splitter x=0 (node 2)"));
        assert_eq!(back.list::<u64>("windows"), Some(vec![12, 48, 0]));
        assert_eq!(back.count("input"), None);
        assert_eq!(back.get("missing"), None);
        assert_eq!(
            Record::new("x").with("l", "").list::<u64>("l"),
            Some(vec![])
        );
        // Setting a key again replaces its value, in its place.
        let r = Record::new("a").with("k", 1).with("j", 2).with("k", 3);
        assert_eq!(r.to_string(), "@stats a k=3 j=2");
    }

    #[test]
    fn lines_that_are_not_records_are_passed_over_and_kept_for_people() {
        let text = "zbuf: leaf-2: 155 spans\n@stats zbuf spans=155\nzbuf: done\n@statsx y\n";
        let got = records(text).unwrap();
        assert_eq!(got, vec![Record::new("zbuf").with("spans", 155)]);
        assert_eq!(
            human(text),
            "zbuf: leaf-2: 155 spans\nzbuf: done\n@statsx y\n"
        );
        assert_eq!(records_of(text, "scanconv").unwrap(), vec![]);
        assert_eq!(parse_line("zbuf: 1 span"), None);
    }

    #[test]
    fn lines_that_break_the_schema_are_refused_with_the_reason() {
        for (line, message) in [
            ("@stats ", "`` is not a stage name"),
            ("@stats Zbuf a=1", "`Zbuf` is not a stage name"),
            ("@stats zbuf a", "`a` is not key=value"),
            ("@stats zbuf a=1  b=2", "`` is not key=value"),
            ("@stats zbuf A=1", "`A` is not a key"),
            ("@stats zbuf a=1 a=2", "`a` twice"),
            ("@stats zbuf a=b=c", "`a=b=c` has a second `=`"),
            (
                "@stats zbuf a=%4",
                "`%` not followed by two hex digits in `%4`",
            ),
            (
                "@stats zbuf a=%+1",
                "`%` not followed by two hex digits in `%+1`",
            ),
            (
                "@stats zbuf a=%FF",
                "`%FF` decodes to bytes that are not UTF-8",
            ),
        ] {
            let e = parse_line(line).unwrap().unwrap_err();
            assert_eq!(e.message, message, "{line}");
            assert_eq!(e.line, line);
        }
        assert_eq!(
            records("@stats zbuf a\n").unwrap_err().to_string(),
            "stats record `@stats zbuf a`: `a` is not key=value"
        );
    }

    #[test]
    #[should_panic(expected = "a stats key is a lower-case letter")]
    fn a_key_outside_the_schema_is_a_bug() {
        let _ = Record::new("zbuf").with("bytes in", 1);
    }

    #[test]
    #[should_panic(expected = "a stats stage name is a lower-case letter")]
    fn a_stage_name_outside_the_schema_is_a_bug() {
        let _ = Record::new("zbuf=");
    }

    proptest! {
        /// Any values written parse back the same, and the line is one line.
        #[test]
        fn any_values_round_trip(
            stage in "[a-z][a-z0-9_]{0,8}",
            fields in prop::collection::vec(("[a-z][a-z0-9_]{0,6}", any::<String>()), 0..6),
        ) {
            let mut r = Record::new(&stage);
            for (k, v) in &fields {
                r.set(k, v);
            }
            let line = r.to_string();
            prop_assert!(!line.contains('\n') && !line.contains('\r'));
            prop_assert_eq!(line.split(' ').count(), 2 + r.fields().len());
            let back = parse_line(&line).unwrap().unwrap();
            prop_assert_eq!(&back, &r);
            prop_assert_eq!(records(&format!("said\n{line}\nmore\n")).unwrap(), vec![r]);
        }

        /// No line, whatever it holds, makes the parser panic.
        #[test]
        fn any_line_parses_or_is_refused(line in "@stats [ -~]{0,40}") {
            let _ = parse_line(&line);
        }
    }
}
