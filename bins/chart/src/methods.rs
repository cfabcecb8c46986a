//! The methods and variants the chart runs: the rows of the `methods` crate's table
//! (docs/DESIGN.md, "Measures").
//!
//! A row names the method as the CSV and the chart do, the `scripts/render.sh` options
//! that select it, the form of scene it reads, the tree depths it is run at, and its
//! colour and marker. Adding a method is a row in that table (docs/extending.md): the
//! runner, the CSV and the pictures take every row alike.

pub use methods::{Draws, Input, Marker, Method, METHODS};

/// The runs of one scene: (method, depth) pairs, every depth of every method, or with
/// `quick` the quick methods at their first depth (and zbuf at depths 0 to 4, which the
/// cost model is measured against); with `only`, of the methods it names.
pub fn runs(quick: bool, only: Option<&[String]>) -> Vec<(Method, u8)> {
    runs_in(METHODS, quick, only)
}

/// [`runs`] of the rows of `table`.
pub fn runs_in(table: &[Method], quick: bool, only: Option<&[String]>) -> Vec<(Method, u8)> {
    let mut runs = Vec::new();
    for m in table {
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

/// Whether the method of a name draws lines (a hidden-line method): it has no error
/// against the scene's pictures (its `rms_16x16` is its drawing's, against the exact
/// drawing's), and the speed-accuracy panels leave it out.
pub fn draws_lines(name: &str) -> bool {
    by_name(name).is_some_and(|m| m.draws == Draws::Lines)
}

/// The method of a name.
pub fn by_name(name: &str) -> Option<Method> {
    methods::by_name(METHODS, name).copied()
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
        let lines: Vec<_> = METHODS.iter().filter(|m| m.draws == Draws::Lines).collect();
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
