//! # methods: the one table of polypipe's methods
//!
//! Every way the project draws a frame that is measured against the others is a row of
//! [`METHODS`]: the hidden-surface methods of the leaves (`render --hse NAME`, thesis
//! chapter 2.3, Newman and Sproull's chapter 14, and the depth sort of Sutherland,
//! Sproull and Schumacker, *A Characterization of Ten Hidden-Surface Algorithms*, which
//! the thesis cites and the seeds do not hold), the anti-aliasing modes (`render --aa NAME`), the
//! z-buffer's variants, and the hidden-line drawings (`render --hidden-line`). A row says
//! how render selects it, which stage binary does the work at each leaf, what it draws,
//! whether its pictures are the z-buffer's byte for byte, the tree depths and the form of
//! scene the chart runs it at, the colour and marker the chart draws it in, and the fuzz
//! target that checks it.
//!
//! Who reads the table: `render` (the names `--hse`, `--aa` and `--hidden-line-method`
//! take, and the stage each one starts; `render --list-methods` prints the table for the scripts, one line a
//! row), `chart` (the runs, the CSV's names, the colours and markers), the end-to-end
//! tests (which methods must give the z-buffer's bytes) and the fuzz target (which check
//! each row gets). Adding a method is a row here, its stage crate under `bins/`, and its
//! tests: docs/extending.md walks through it.
//!
//! The crate has no dependencies, and no stage crate depends on it: the table names
//! stages by their binaries, so that render, chart and the tests can read it without
//! linking a stage.

use std::fmt::Write as _;

/// The form of scene a row reads in the chart's runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Input {
    /// The scene as the user gave it.
    AsGiven,
    /// The scene rewritten in the text form (`frames --text`).
    Text,
    /// The scene rewritten in the binary form (`frames`).
    Binary,
}

impl Input {
    /// The word `render --list-methods` prints.
    pub fn word(self) -> &'static str {
        match self {
            Input::AsGiven => "as-given",
            Input::Text => "text",
            Input::Binary => "binary",
        }
    }
}

/// What a row's stage writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Draws {
    /// Frames of pixels (runs or fragments the merger places): their error against
    /// `zspec`'s exact-area picture is what the chart measures.
    Pixels,
    /// The visible parts of the edges, as SVG (Archuleta, *Hidden Surface Line Drawing
    /// Algorithm*): no pixel error; the chart counts their pieces instead.
    Lines,
}

impl Draws {
    /// The word `render --list-methods` prints.
    pub fn word(self) -> &'static str {
        match self {
            Draws::Pixels => "pixels",
            Draws::Lines => "lines",
        }
    }
}

/// How render selects a row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Selector {
    /// A hidden-surface method of the leaves: `render --hse NAME`.
    Hse(&'static str),
    /// An anti-aliasing mode of the leaves (a z-buffer that samples more than the pixel
    /// centre): `render --aa NAME`.
    Aa(&'static str),
    /// A hidden-line drawing: `render --hidden-line`, with `--hidden-line-method NAME`
    /// (hiddenline's `--method`).
    HiddenLine(&'static str),
    /// A variant of another row, by other options of render (its `--merge`, `--zmode`,
    /// `--clip`, `--split`) or another form of the scene: the chart runs it, render has no
    /// name for it of its own.
    Variant,
}

/// The chart's marker shapes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Marker {
    Circle,
    Square,
    Triangle,
    Diamond,
    Cross,
}

impl Marker {
    /// The word `render --list-methods` prints.
    pub fn word(self) -> &'static str {
        match self {
            Marker::Circle => "circle",
            Marker::Square => "square",
            Marker::Triangle => "triangle",
            Marker::Diamond => "diamond",
            Marker::Cross => "cross",
        }
    }
}

/// One method or variant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Method {
    /// The name in `results.csv`, on the chart and in `render --list-methods`.
    pub name: &'static str,
    /// How render selects it.
    pub selector: Selector,
    /// render's options that select it (besides `--size` and `--depth`), as the chart
    /// and the benchmarks give them.
    pub options: &'static [&'static str],
    /// The stage each leaf runs: its binary (the crate under `bins/` of that name), then
    /// that binary's options. For a hidden-line row, the one stage after persp.
    pub stage: &'static [&'static str],
    /// What it draws.
    pub draws: Draws,
    /// Whether its frames are the z-buffer's (`--hse zbuf`) byte for byte at every tree
    /// depth, on every scene: the end-to-end tests hold it to that. Otherwise its pixels
    /// differ where its method does (the painter, where there is no depth order; the
    /// anti-aliasing modes, by design), and the chart shows by how much against `zspec`.
    pub exact: bool,
    /// The form of scene the chart gives it.
    pub input: Input,
    /// The splitter tree depths the chart runs it at (a method without a tree: `[0]`).
    pub depths: &'static [u8],
    /// Whether the chart's `--quick` runs it (at its first depth only).
    pub quick: bool,
    /// Its colour on the chart (sRGB): apart from every other row's, dark enough for
    /// white paper.
    pub colour: [u8; 3],
    /// Its marker on the chart: rows of near colours differ in shape.
    pub marker: Marker,
    /// The fuzz target (fuzz/fuzz_targets/NAME.rs, docs/fuzzing.md) that checks its
    /// algorithm on arbitrary input, if one does.
    pub fuzz: Option<&'static str>,
}

impl Method {
    /// The stage binary each leaf runs.
    pub fn binary(&self) -> &'static str {
        self.stage[0]
    }

    /// The stage as words, the binary first.
    pub fn stage_words(&self) -> Vec<String> {
        self.stage.iter().map(|s| s.to_string()).collect()
    }
}

const TREE: &[u8] = &[0, 1, 2, 3, 4];
const ROOT: &[u8] = &[0];
const AA: &[u8] = &[0, 2];

/// Every method and variant, in the order of the chart's CSV.
///
/// The hidden-surface methods at every depth; the anti-aliasing modes (the same frames
/// at every depth, so two depths show what the tree does to their time); the
/// z-buffer's variants; and the two hidden-line methods, at depth 0 only (the tree's
/// cuts are not edges): the continuous one, each edge against the polygons that may
/// hide it in exact geometry, and Archuleta's, counters on Watkins's scan-line segments
/// at raster resolution (Archuleta, *Hidden Surface Line Drawing Algorithm*, "Line
/// Drawing Algorithm").
pub const METHODS: &[Method] = &[
    // Watkins's scan line (Archuleta; Newman and Sproull, 14.4).
    Method {
        name: "scanline",
        selector: Selector::Hse("scanline"),
        options: &["--hse", "scanline"],
        stage: &["scanline"],
        draws: Draws::Pixels,
        exact: true,
        input: Input::AsGiven,
        depths: TREE,
        quick: true,
        colour: [31, 119, 180], // blue
        marker: Marker::Square,
        fuzz: Some("methods"),
    },
    // Warnock's area subdivision (Newman and Sproull, 14.3 and Appendix VI).
    Method {
        name: "warnock",
        selector: Selector::Hse("warnock"),
        options: &["--hse", "warnock"],
        stage: &["warnock"],
        draws: Draws::Pixels,
        exact: true,
        input: Input::AsGiven,
        depths: TREE,
        quick: true,
        colour: [214, 39, 40], // red
        marker: Marker::Triangle,
        fuzz: Some("methods"),
    },
    // Newell, Newell and Sancha's depth sort without its splitting step: wrong where
    // polygons interpenetrate or overlap cyclically.
    Method {
        name: "painter",
        selector: Selector::Hse("painter"),
        options: &["--hse", "painter"],
        stage: &["painter"],
        draws: Draws::Pixels,
        exact: false,
        input: Input::AsGiven,
        depths: TREE,
        quick: true,
        colour: [44, 160, 44], // green
        marker: Marker::Diamond,
        fuzz: Some("methods"),
    },
    Method {
        name: "painter-split",
        selector: Selector::Variant,
        options: &["--hse", "painter", "--split"],
        stage: &["painter", "--split"],
        draws: Draws::Pixels,
        exact: false,
        input: Input::AsGiven,
        depths: TREE,
        quick: false,
        colour: [0, 200, 100], // spring green
        marker: Marker::Circle,
        fuzz: Some("methods"),
    },
    // Carpenter's a-buffer (*The A-buffer, an Antialiased Hidden Surface Method*).
    Method {
        name: "abuf",
        selector: Selector::Aa("abuf"),
        options: &["--aa", "abuf"],
        stage: &["abuf"],
        draws: Draws::Pixels,
        exact: false,
        input: Input::AsGiven,
        depths: AA,
        quick: true,
        colour: [255, 127, 14], // orange
        marker: Marker::Circle,
        fuzz: Some("abuf"),
    },
    // K×K samples a pixel, box-filtered.
    Method {
        name: "ss2",
        selector: Selector::Aa("ss2"),
        options: &["--aa", "ss2"],
        stage: &["supersample", "--samples", "2"],
        draws: Draws::Pixels,
        exact: false,
        input: Input::AsGiven,
        depths: AA,
        quick: false,
        colour: [148, 103, 189], // purple
        marker: Marker::Diamond,
        fuzz: None,
    },
    Method {
        name: "ss4",
        selector: Selector::Aa("ss4"),
        options: &["--aa", "ss4"],
        stage: &["supersample", "--samples", "4"],
        draws: Draws::Pixels,
        exact: false,
        input: Input::AsGiven,
        depths: AA,
        quick: true,
        colour: [140, 86, 75], // brown
        marker: Marker::Square,
        fuzz: None,
    },
    Method {
        name: "ss8",
        selector: Selector::Aa("ss8"),
        options: &["--aa", "ss8"],
        stage: &["supersample", "--samples", "8"],
        draws: Draws::Pixels,
        exact: false,
        input: Input::AsGiven,
        depths: AA,
        quick: false,
        colour: [227, 119, 194], // pink
        marker: Marker::Triangle,
        fuzz: None,
    },
    Method {
        name: "ss16",
        selector: Selector::Aa("ss16"),
        options: &["--aa", "ss16"],
        stage: &["supersample", "--samples", "16"],
        draws: Draws::Pixels,
        exact: false,
        input: Input::AsGiven,
        depths: AA,
        quick: false,
        colour: [127, 127, 127], // grey
        marker: Marker::Circle,
        fuzz: None,
    },
    // K×K samples only where an edge, a silhouette or a crossing touches the pixel:
    // ssK's bytes on flat polygons (docs/antialiasing.md, "Adaptive supersampling").
    Method {
        name: "adaptive2",
        selector: Selector::Aa("adaptive2"),
        options: &["--aa", "adaptive2"],
        stage: &["supersample", "--samples", "2", "--adaptive"],
        draws: Draws::Pixels,
        exact: false,
        input: Input::AsGiven,
        depths: AA,
        quick: false,
        colour: [70, 20, 250], // violet
        marker: Marker::Diamond,
        fuzz: None,
    },
    Method {
        name: "adaptive4",
        selector: Selector::Aa("adaptive4"),
        options: &["--aa", "adaptive4"],
        stage: &["supersample", "--samples", "4", "--adaptive"],
        draws: Draws::Pixels,
        exact: false,
        input: Input::AsGiven,
        depths: AA,
        quick: true,
        colour: [110, 250, 80], // light green
        marker: Marker::Square,
        fuzz: None,
    },
    Method {
        name: "adaptive8",
        selector: Selector::Aa("adaptive8"),
        options: &["--aa", "adaptive8"],
        stage: &["supersample", "--samples", "8", "--adaptive"],
        draws: Draws::Pixels,
        exact: false,
        input: Input::AsGiven,
        depths: AA,
        quick: false,
        colour: [160, 0, 130], // plum
        marker: Marker::Triangle,
        fuzz: None,
    },
    Method {
        name: "adaptive16",
        selector: Selector::Aa("adaptive16"),
        options: &["--aa", "adaptive16"],
        stage: &["supersample", "--samples", "16", "--adaptive"],
        draws: Draws::Pixels,
        exact: false,
        input: Input::AsGiven,
        depths: AA,
        quick: false,
        colour: [10, 250, 0], // bright green
        marker: Marker::Circle,
        fuzz: None,
    },
    // The thesis's PAR.BUFF with its quadruplets: one fragment a pixel to the one zbuf.
    Method {
        name: "zbuf-pixels",
        selector: Selector::Variant,
        options: &["--merge", "buffer", "--pixels"],
        stage: &["scanconv", "--pixels"],
        draws: Draws::Pixels,
        exact: true,
        input: Input::AsGiven,
        depths: ROOT,
        quick: false,
        colour: [188, 189, 34], // olive
        marker: Marker::Square,
        fuzz: Some("scanconv"),
    },
    // The z-buffer (thesis chapter 2.3), each leaf resolving its own region: the
    // reference every exact row is held to.
    Method {
        name: "zbuf",
        selector: Selector::Hse("zbuf"),
        options: &[],
        stage: &["scanconv", "--resolve"],
        draws: Draws::Pixels,
        exact: true,
        input: Input::AsGiven,
        depths: TREE,
        quick: true,
        colour: [0, 0, 0], // black
        marker: Marker::Circle,
        fuzz: Some("scanconv"),
    },
    // Eye-space z, the occam code's depth: not linear across the screen, so a split
    // polygon's pieces interpolate it differently and the frames change with the depth.
    Method {
        name: "zbuf-eye-z",
        selector: Selector::Variant,
        options: &["--zmode", "eye-z"],
        stage: &["scanconv", "--resolve"],
        draws: Draws::Pixels,
        exact: false,
        input: Input::AsGiven,
        depths: ROOT,
        quick: true,
        colour: [23, 190, 207], // cyan
        marker: Marker::Triangle,
        fuzz: None,
    },
    Method {
        name: "zbuf-buffer",
        selector: Selector::Variant,
        options: &["--merge", "buffer"],
        stage: &["scanconv"],
        draws: Draws::Pixels,
        exact: true,
        input: Input::AsGiven,
        depths: AA,
        quick: false,
        colour: [0, 0, 128], // navy
        marker: Marker::Diamond,
        fuzz: Some("scanconv"),
    },
    // The thesis's six clipplane processes in place of clipbatch.
    Method {
        name: "zbuf-chain",
        selector: Selector::Variant,
        options: &["--clip", "chain"],
        stage: &["scanconv", "--resolve"],
        draws: Draws::Pixels,
        exact: true,
        input: Input::AsGiven,
        depths: ROOT,
        quick: false,
        colour: [128, 0, 0], // maroon
        marker: Marker::Square,
        fuzz: Some("clip"),
    },
    Method {
        name: "zbuf-text",
        selector: Selector::Variant,
        options: &[],
        stage: &["scanconv", "--resolve"],
        draws: Draws::Pixels,
        exact: true,
        input: Input::Text,
        depths: ROOT,
        quick: false,
        colour: [0, 128, 128], // teal
        marker: Marker::Cross,
        fuzz: Some("decode_text"),
    },
    Method {
        name: "zbuf-binary",
        selector: Selector::Variant,
        options: &[],
        stage: &["scanconv", "--resolve"],
        draws: Draws::Pixels,
        exact: true,
        input: Input::Binary,
        depths: ROOT,
        quick: true,
        colour: [184, 134, 11], // dark gold
        marker: Marker::Triangle,
        fuzz: Some("decode_binary"),
    },
    Method {
        name: "hiddenline",
        selector: Selector::HiddenLine("continuous"),
        options: &["--hidden-line"],
        stage: &["hiddenline"],
        draws: Draws::Lines,
        exact: false,
        input: Input::AsGiven,
        depths: ROOT,
        quick: true,
        colour: [230, 0, 230], // magenta
        marker: Marker::Cross,
        fuzz: Some("methods"),
    },
    Method {
        name: "hiddenline-archuleta",
        selector: Selector::HiddenLine("archuleta"),
        options: &["--hidden-line", "--hidden-line-method", "archuleta"],
        stage: &["hiddenline", "--method", "archuleta"],
        draws: Draws::Lines,
        exact: false,
        input: Input::AsGiven,
        depths: ROOT,
        quick: true,
        colour: [90, 150, 0], // leaf green
        marker: Marker::Cross,
        fuzz: None,
    },
];

/// The row of a name in `table`.
pub fn by_name<'t>(table: &'t [Method], name: &str) -> Option<&'t Method> {
    table.iter().find(|m| m.name == name)
}

/// The row `render --hse NAME` selects in `table`.
pub fn by_hse<'t>(table: &'t [Method], name: &str) -> Option<&'t Method> {
    table
        .iter()
        .find(|m| matches!(m.selector, Selector::Hse(n) if n == name))
}

/// The row `render --aa NAME` selects in `table`.
pub fn by_aa<'t>(table: &'t [Method], name: &str) -> Option<&'t Method> {
    table
        .iter()
        .find(|m| matches!(m.selector, Selector::Aa(n) if n == name))
}

/// The row `render --hidden-line --hidden-line-method NAME` selects in `table`; without
/// a NAME, the first hidden-line row (hiddenline's default method).
pub fn by_hidden_line<'t>(table: &'t [Method], name: Option<&str>) -> Option<&'t Method> {
    table.iter().find(|m| match m.selector {
        Selector::HiddenLine(n) => name.is_none_or(|name| n == name),
        _ => false,
    })
}

/// The names `render --hidden-line-method` takes, in the table's order.
pub fn hidden_line_names(table: &[Method]) -> Vec<&'static str> {
    table
        .iter()
        .filter_map(|m| match m.selector {
            Selector::HiddenLine(n) => Some(n),
            _ => None,
        })
        .collect()
}

/// The names `render --hse` takes, in the table's order.
pub fn hse_names(table: &[Method]) -> Vec<&'static str> {
    table
        .iter()
        .filter_map(|m| match m.selector {
            Selector::Hse(n) => Some(n),
            _ => None,
        })
        .collect()
}

/// The names `render --aa` takes besides `none`, in the table's order.
pub fn aa_names(table: &[Method]) -> Vec<&'static str> {
    table
        .iter()
        .filter_map(|m| match m.selector {
            Selector::Aa(n) => Some(n),
            _ => None,
        })
        .collect()
}

/// The stage binaries the rows run, each once, in the table's order.
pub fn binaries(table: &[Method]) -> Vec<&'static str> {
    let mut out: Vec<&'static str> = Vec::new();
    for m in table {
        if !out.contains(&m.binary()) {
            out.push(m.binary());
        }
    }
    out
}

/// The header line of [`listing`], its columns' names.
pub const LISTING_HEADER: &str =
    "name\tselector\toptions\tstage\tdraws\texact\tinput\tdepths\tquick\tcolour\tmarker\tfuzz";

/// The table as `render --list-methods` prints it, for scripts: [`LISTING_HEADER`],
/// then one line a row, tab-separated, no field empty (`-` for none, so that bash's
/// `IFS=$'\t' read`, which joins runs of tabs, keeps the columns):
///
/// - `name`: the row's name (the CSV's);
/// - `selector`: `hse:NAME`, `aa:NAME`, `hidden-line:NAME` or `variant`;
/// - `options`: render's options that select it, space-separated (`-`: none, the default);
/// - `stage`: the leaf's stage, its binary first, space-separated;
/// - `draws`: `pixels` or `lines`;
/// - `exact`: `exact` (the z-buffer's frames byte for byte) or `approximate`;
/// - `input`: `as-given`, `text` or `binary`;
/// - `depths`: the chart's tree depths, comma-separated;
/// - `quick`: `quick` or `full` (whether the chart's `--quick` runs it);
/// - `colour`: `#rrggbb`;
/// - `marker`: `circle`, `square`, `triangle`, `diamond` or `cross`;
/// - `fuzz`: the fuzz target, or `-`.
pub fn listing(table: &[Method]) -> String {
    let mut out = format!("{LISTING_HEADER}\n");
    let or_dash = |words: &[&str]| {
        if words.is_empty() {
            "-".to_string()
        } else {
            words.join(" ")
        }
    };
    for m in table {
        let selector = match m.selector {
            Selector::Hse(n) => format!("hse:{n}"),
            Selector::Aa(n) => format!("aa:{n}"),
            Selector::HiddenLine(n) => format!("hidden-line:{n}"),
            Selector::Variant => "variant".to_string(),
        };
        let depths: Vec<String> = m.depths.iter().map(u8::to_string).collect();
        let [r, g, b] = m.colour;
        let _ = writeln!(
            out,
            "{}\t{selector}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t#{r:02x}{g:02x}{b:02x}\t{}\t{}",
            m.name,
            or_dash(m.options),
            or_dash(m.stage),
            m.draws.word(),
            if m.exact { "exact" } else { "approximate" },
            m.input.word(),
            depths.join(","),
            if m.quick { "quick" } else { "full" },
            m.marker.word(),
            m.fuzz.unwrap_or("-"),
        );
    }
    out
}

/// What is wrong with a table, or nothing: names unique and without tabs or spaces; a
/// selector name once; render's options starting with the selector's (`--hse NAME`,
/// `--aa NAME`, `--hidden-line`); a stage, some depth, depth 0 alone for a hidden-line
/// row (the tree's cuts are not edges); no exact row that draws lines; colours and
/// markers that tell the rows apart. This crate's tests check [`METHODS`] with it, and
/// tests/tests/house/extending.rs a table with a row of its own.
pub fn check(table: &[Method]) -> Result<(), String> {
    for (i, m) in table.iter().enumerate() {
        let name = m.name;
        if name.is_empty() || name.contains(|c: char| c.is_whitespace()) {
            return Err(format!("row {i}: name '{name}' is empty or has a space"));
        }
        if table[..i].iter().any(|o| o.name == name) {
            return Err(format!("{name}: two rows of that name"));
        }
        if m.selector != Selector::Variant && table[..i].iter().any(|o| o.selector == m.selector) {
            return Err(format!("{name}: {:?} selects another row too", m.selector));
        }
        let leads: Vec<&str> = match m.selector {
            Selector::Hse(n) => vec!["--hse", n],
            Selector::Aa(n) => vec!["--aa", n],
            Selector::HiddenLine(_) => vec!["--hidden-line"],
            Selector::Variant => vec![],
        };
        // The default method is selected by no option at all.
        if !(m.options.is_empty() || m.options.starts_with(&leads)) {
            return Err(format!(
                "{name}: options {:?} do not start with {leads:?}",
                m.options
            ));
        }
        if m.stage.is_empty() || m.depths.is_empty() {
            return Err(format!("{name}: no stage or no depth"));
        }
        if m.draws == Draws::Lines && (m.depths != [0] || m.exact) {
            return Err(format!(
                "{name}: lines are drawn at depth 0 alone, and are not pixels to compare"
            ));
        }
        for o in &table[..i] {
            let d: u32 = (0..3)
                .map(|c| m.colour[c].abs_diff(o.colour[c]) as u32)
                .sum();
            if d <= 60 || d <= 150 && m.marker == o.marker {
                return Err(format!(
                    "{name}: colour and marker too near {}'s (colour distance {d})",
                    o.name
                ));
            }
        }
        if m.colour.iter().map(|&c| c as u32).sum::<u32>() >= 600 {
            return Err(format!("{name}: colour too light for white paper"));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_passes_its_own_check() {
        assert_eq!(check(METHODS), Ok(()));
    }

    #[test]
    fn render_names_come_from_the_selectors() {
        // The thesis's four (a method added to the table joins them).
        for name in ["scanline", "warnock", "painter", "zbuf"] {
            assert!(hse_names(METHODS).contains(&name), "{name}");
        }
        for name in ["abuf", "ss2", "ss4", "ss8", "ss16", "adaptive4"] {
            assert!(aa_names(METHODS).contains(&name), "{name}");
        }
        assert_eq!(
            by_hse(METHODS, "zbuf").unwrap().stage,
            ["scanconv", "--resolve"]
        );
        assert_eq!(by_hse(METHODS, "painter").unwrap().name, "painter");
        assert_eq!(
            by_aa(METHODS, "ss8").unwrap().stage,
            ["supersample", "--samples", "8"]
        );
        assert!(by_hse(METHODS, "painter-split").is_none());
        assert_eq!(hidden_line_names(METHODS), ["continuous", "archuleta"]);
        assert_eq!(by_hidden_line(METHODS, None).unwrap().stage, ["hiddenline"]);
        assert_eq!(
            by_hidden_line(METHODS, Some("archuleta")).unwrap().name,
            "hiddenline-archuleta"
        );
        assert!(by_hidden_line(METHODS, Some("exact")).is_none());
        assert!(by_name(METHODS, "nothing").is_none());
        // Each row's stage binary, once, in the order of the rows.
        let bins = binaries(METHODS);
        for m in METHODS {
            assert_eq!(
                bins.iter().filter(|b| **b == m.binary()).count(),
                1,
                "{}",
                m.name
            );
        }
        assert!(bins
            .iter()
            .all(|b| METHODS.iter().any(|m| m.binary() == *b)));
    }

    #[test]
    fn the_listing_is_one_line_a_row_with_every_column() {
        let text = listing(METHODS);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), METHODS.len() + 1);
        assert_eq!(lines[0], LISTING_HEADER);
        let columns = LISTING_HEADER.split('\t').count();
        for line in &lines {
            let fields: Vec<&str> = line.split('\t').collect();
            assert_eq!(fields.len(), columns, "{line}");
            assert!(fields.iter().all(|f| !f.is_empty()), "{line}");
        }
        let row = |name: &str| {
            *lines
                .iter()
                .find(|l| l.split('\t').next() == Some(name))
                .unwrap()
        };
        assert_eq!(
            row("scanline"),
            "scanline\thse:scanline\t--hse scanline\tscanline\tpixels\texact\tas-given\t0,1,2,3,4\tquick\t#1f77b4\tsquare\tmethods"
        );
        assert_eq!(
            row("zbuf"),
            "zbuf\thse:zbuf\t-\tscanconv --resolve\tpixels\texact\tas-given\t0,1,2,3,4\tquick\t#000000\tcircle\tscanconv"
        );
        assert_eq!(
            row("hiddenline-archuleta"),
            "hiddenline-archuleta\thidden-line:archuleta\t--hidden-line --hidden-line-method archuleta\thiddenline --method archuleta\tlines\tapproximate\tas-given\t0\tquick\t#5a9600\tcross\t-"
        );
    }

    #[test]
    fn check_refuses_what_would_confuse_a_reader() {
        let row = |name, colour, marker| Method {
            name,
            selector: Selector::Variant,
            options: &[],
            stage: &["scanconv", "--resolve"],
            draws: Draws::Pixels,
            exact: true,
            input: Input::AsGiven,
            depths: ROOT,
            quick: false,
            colour,
            marker,
            fuzz: None,
        };
        let a = row("a", [0, 0, 0], Marker::Circle);
        assert_eq!(
            check(&[a, row("a", [200, 0, 0], Marker::Circle)]),
            Err("a: two rows of that name".into())
        );
        assert_eq!(
            check(&[a, row("b", [50, 50, 0], Marker::Circle)]),
            Err("b: colour and marker too near a's (colour distance 100)".into())
        );
        assert_eq!(check(&[a, row("b", [50, 50, 0], Marker::Square)]), Ok(()));
        assert_eq!(
            check(&[row("pale", [250, 250, 250], Marker::Circle)]),
            Err("pale: colour too light for white paper".into())
        );
        let lines = Method {
            draws: Draws::Lines,
            exact: false,
            depths: TREE,
            ..a
        };
        assert_eq!(
            check(&[lines]),
            Err("a: lines are drawn at depth 0 alone, and are not pixels to compare".into())
        );
        assert_eq!(
            check(&[Method {
                depths: ROOT,
                exact: true,
                ..lines
            }]),
            Err("a: lines are drawn at depth 0 alone, and are not pixels to compare".into())
        );
        let x = Method {
            selector: Selector::Hse("x"),
            options: &["--hse", "x"],
            ..a
        };
        assert_eq!(
            check(&[
                x,
                Method {
                    name: "b",
                    colour: [200, 0, 0],
                    ..x
                }
            ]),
            Err("b: Hse(\"x\") selects another row too".into())
        );
        let hse = Method {
            selector: Selector::Hse("x"),
            options: &["--aa", "x"],
            ..a
        };
        assert_eq!(
            check(&[hse]),
            Err("a: options [\"--aa\", \"x\"] do not start with [\"--hse\", \"x\"]".into())
        );
        assert_eq!(
            check(&[Method {
                name: "two words",
                ..a
            }]),
            Err("row 0: name 'two words' is empty or has a space".into())
        );
    }
}
