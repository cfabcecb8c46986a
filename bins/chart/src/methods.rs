//! The methods and variants the chart runs: data, one row each (docs/DESIGN.md, "Measures").
//!
//! A row names the method as the CSV and the chart do, the `scripts/render.sh` options
//! that select it, the form of scene it reads, and the tree depths it is run at. Adding a
//! method is one row here: the runner, the CSV and the pictures take every row alike.

/// The form of scene a variant reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Input {
    /// The scene as the user gave it.
    AsGiven,
    /// The scene rewritten in the text form (`frames --text`).
    Text,
    /// The scene rewritten in the binary form (`frames`).
    Binary,
}

/// One method or variant: what `render.sh` is told, on what, at which depths.
#[derive(Clone, Copy, Debug)]
pub struct Method {
    /// The name in `results.csv` and on the chart.
    pub name: &'static str,
    /// `render.sh`'s options that select it (besides `--size` and `--depth`).
    pub options: &'static [&'static str],
    /// The form of scene it reads.
    pub input: Input,
    /// The splitter tree depths it is run at (a method without a tree: `[0]`).
    pub depths: &'static [u8],
    /// Whether `--quick` runs it (at its first depth only).
    pub quick: bool,
    /// Whether it draws the visible edges (`render --hidden-line`, an SVG a frame) rather
    /// than frames of pixels: no pixel error against `zspec`, its pieces counted instead.
    pub lines: bool,
}

const TREE: &[u8] = &[0, 1, 2, 3, 4];
const ROOT: &[u8] = &[0];

/// Every method the chart runs, in the order of the CSV.
///
/// The hidden-surface methods (`--hse`) at every depth, the anti-aliasing modes (`--aa`,
/// the same frames at every depth, so two depths show what the tree does to their time),
/// the z-buffer's variants, and the two hidden-line methods (`--hidden-line`, at depth 0
/// only: the tree's cuts are not edges): the continuous one, each edge against the
/// polygons that may hide it in exact geometry, and Archuleta's, counters on Watkins's
/// scan-line segments at raster resolution (Archuleta, *Hidden Surface Line Drawing
/// Algorithm*, "Line Drawing Algorithm").
pub const METHODS: &[Method] = &[
    Method {
        name: "scanline",
        options: &["--hse", "scanline"],
        input: Input::AsGiven,
        depths: TREE,
        quick: true,
        lines: false,
    },
    Method {
        name: "warnock",
        options: &["--hse", "warnock"],
        input: Input::AsGiven,
        depths: TREE,
        quick: true,
        lines: false,
    },
    Method {
        name: "painter",
        options: &["--hse", "painter"],
        input: Input::AsGiven,
        depths: TREE,
        quick: true,
        lines: false,
    },
    Method {
        name: "painter-split",
        options: &["--hse", "painter", "--split"],
        input: Input::AsGiven,
        depths: TREE,
        quick: false,
        lines: false,
    },
    Method {
        name: "abuf",
        options: &["--aa", "abuf"],
        input: Input::AsGiven,
        depths: &[0, 2],
        quick: true,
        lines: false,
    },
    Method {
        name: "ss2",
        options: &["--aa", "ss2"],
        input: Input::AsGiven,
        depths: &[0, 2],
        quick: false,
        lines: false,
    },
    Method {
        name: "ss4",
        options: &["--aa", "ss4"],
        input: Input::AsGiven,
        depths: &[0, 2],
        quick: true,
        lines: false,
    },
    Method {
        name: "ss8",
        options: &["--aa", "ss8"],
        input: Input::AsGiven,
        depths: &[0, 2],
        quick: false,
        lines: false,
    },
    Method {
        name: "ss16",
        options: &["--aa", "ss16"],
        input: Input::AsGiven,
        depths: &[0, 2],
        quick: false,
        lines: false,
    },
    Method {
        name: "zbuf-pixels",
        options: &["--merge", "buffer", "--pixels"],
        input: Input::AsGiven,
        depths: ROOT,
        quick: false,
        lines: false,
    },
    Method {
        name: "zbuf",
        options: &[],
        input: Input::AsGiven,
        depths: TREE,
        quick: true,
        lines: false,
    },
    Method {
        name: "zbuf-eye-z",
        options: &["--zmode", "eye-z"],
        input: Input::AsGiven,
        depths: ROOT,
        quick: true,
        lines: false,
    },
    Method {
        name: "zbuf-buffer",
        options: &["--merge", "buffer"],
        input: Input::AsGiven,
        depths: &[0, 2],
        quick: false,
        lines: false,
    },
    Method {
        name: "zbuf-chain",
        options: &["--clip", "chain"],
        input: Input::AsGiven,
        depths: ROOT,
        quick: false,
        lines: false,
    },
    Method {
        name: "zbuf-text",
        options: &[],
        input: Input::Text,
        depths: ROOT,
        quick: false,
        lines: false,
    },
    Method {
        name: "zbuf-binary",
        options: &[],
        input: Input::Binary,
        depths: ROOT,
        quick: true,
        lines: false,
    },
    Method {
        name: "hiddenline",
        options: &["--hidden-line"],
        input: Input::AsGiven,
        depths: ROOT,
        quick: true,
        lines: true,
    },
    Method {
        name: "hiddenline-archuleta",
        options: &["--hidden-line", "--hidden-line-method", "archuleta"],
        input: Input::AsGiven,
        depths: ROOT,
        quick: true,
        lines: true,
    },
];

/// The runs of one scene: (method, depth) pairs, every depth of every method, or with
/// `quick` the quick methods at their first depth (and zbuf at depths 0 to 4, which the
/// cost model is measured against); with `only`, of the methods it names.
pub fn runs(quick: bool, only: Option<&[String]>) -> Vec<(Method, u8)> {
    let mut runs = Vec::new();
    for m in METHODS {
        if quick && !m.quick || only.is_some_and(|o| !o.iter().any(|n| n == m.name)) {
            continue;
        }
        let depths: &[u8] = match (quick, m.name) {
            (true, "zbuf") => m.depths,
            (true, _) => &m.depths[..1],
            (false, _) => m.depths,
        };
        runs.extend(depths.iter().map(|&d| (*m, d)));
    }
    runs
}

/// Whether the method of a name draws lines (a hidden-line method): it has no pixel error,
/// and the speed-accuracy panels leave it out.
pub fn draws_lines(name: &str) -> bool {
    by_name(name).is_some_and(|m| m.lines)
}

/// The method of a name.
pub fn by_name(name: &str) -> Option<Method> {
    METHODS.iter().find(|m| m.name == name).copied()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_zbuf_runs_the_tree() {
        let mut names: Vec<_> = METHODS.iter().map(|m| m.name).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), METHODS.len());
        assert_eq!(by_name("zbuf").unwrap().depths, &[0, 1, 2, 3, 4]);
        assert!(by_name("nothing").is_none());
        // The hidden-line methods draw lines at depth 0 alone; no other method does.
        let lines: Vec<_> = METHODS.iter().filter(|m| m.lines).collect();
        assert_eq!(
            lines.iter().map(|m| m.name).collect::<Vec<_>>(),
            ["hiddenline", "hiddenline-archuleta"]
        );
        assert!(lines.iter().all(|m| m.depths == [0]
            && m.options.first() == Some(&"--hidden-line")
            && m.input == Input::AsGiven));
        assert!(draws_lines("hiddenline-archuleta") && !draws_lines("zbuf"));
        assert!(!draws_lines("nothing"));
    }

    #[test]
    fn quick_is_a_subset() {
        let all = runs(false, None);
        let quick = runs(true, None);
        assert!(quick.len() < all.len());
        for (m, d) in &quick {
            assert!(all.iter().any(|(a, e)| a.name == m.name && e == d));
        }
        assert_eq!(
            quick.iter().filter(|(m, _)| m.name == "zbuf").count(),
            5,
            "zbuf at depths 0-4 in a quick run"
        );
        let only = ["zbuf".to_string(), "painter".to_string()];
        let some = runs(false, Some(&only));
        assert_eq!(some.len(), 10, "zbuf and painter at depths 0-4");
        assert!(some.iter().all(|(m, _)| only.iter().any(|o| o == m.name)));
    }
}
