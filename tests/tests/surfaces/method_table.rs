//! The hidden-surface methods through `scripts/render.sh --hse` (docs/DESIGN.md,
//! "Leaves resolve visibility"): Watkins's scan line and Warnock's subdivision draw the
//! z-buffer's frames byte for byte at every tree depth, on every scene of the suite, on
//! random environments of 1,000 and 100,000 polygons and on movies; the painter draws
//! them where the scene has a depth order and fails, by a counted number of pixels,
//! where polygons interpenetrate. Each leaf's counters come out under --stats.

use pipeline_tests::{parse_ppm_stream, run, sh};

/// `render.sh OPTIONS` as a shell command line.
fn render(options: &str) -> Vec<u8> {
    run(&format!("scripts/render.sh {options}"))
}

/// Pixels that differ between two frame streams of the same sizes.
fn differing(a: &[u8], b: &[u8]) -> usize {
    let (a, b) = (parse_ppm_stream(a).unwrap(), parse_ppm_stream(b).unwrap());
    assert_eq!(a.len(), b.len(), "frame counts");
    a.iter()
        .zip(&b)
        .map(|(f, g)| {
            assert_eq!((f.width, f.height), (g.width, g.height));
            f.pixels
                .iter()
                .zip(&g.pixels)
                .filter(|(p, q)| p != q)
                .count()
        })
        .sum()
}

/// The hidden-surface methods the table of methods says are exact, besides the z-buffer
/// itself (scanline and warnock, and any added so).
fn exact_methods() -> Vec<&'static str> {
    methods::METHODS
        .iter()
        .filter_map(|m| match m.selector {
            methods::Selector::Hse(name) if m.exact && name != "zbuf" => Some(name),
            _ => None,
        })
        .collect()
}

/// Each exact `--hse` method gives `--hse zbuf`'s bytes at depths 0–4.
fn exact_at_every_depth(options: &str) {
    for depth in 0..=4 {
        let zbuf = render(&format!("--depth {depth} {options}"));
        assert!(!zbuf.is_empty());
        for method in exact_methods() {
            let other = render(&format!("--hse {method} --depth {depth} {options}"));
            assert!(
                other == zbuf,
                "--hse {method} --depth {depth} {options}: {} pixels differ from zbuf",
                differing(&other, &zbuf)
            );
        }
    }
}

#[test]
fn scanline_and_warnock_are_exact() {
    // The thesis's exact methods are in the table as exact (a method added to it may
    // join them, and is then compared with the z-buffer as they are).
    for name in ["scanline", "warnock"] {
        assert!(exact_methods().contains(&name), "{name}");
    }
}

#[test]
fn render_lists_the_table_of_methods_for_scripts() {
    // The table as methods::listing prints it, through render.sh as a script runs it.
    let listing = run("scripts/render.sh --list-methods");
    assert_eq!(
        String::from_utf8(listing).unwrap(),
        methods::listing(methods::METHODS)
    );
    // Read as a bench script reads it: the header skipped, the columns by name.
    let read = run(r#"scripts/render.sh --list-methods | {
        read -r
        while IFS=$'\t' read -r name selector options stage draws exact rest; do
            if [[ $selector == hse:* && $exact == exact ]]; then printf '%s=%s;' "$name" "$stage"; fi
        done
    }"#);
    assert_eq!(
        String::from_utf8(read).unwrap(),
        "scanline=scanline;warnock=warnock;zbuf=scanconv --resolve;"
    );
}

#[test]
fn every_exact_variant_of_the_table_is_the_zbuffer_at_its_depths() {
    // The variants the table calls exact (the one z-buffer's fragments or pixels, the
    // clipper chain, the scene rewritten as text or binary) at each depth the chart runs
    // them at, on the penetrating polygons, in the form of scene each reads. (Marking
    // zbuf-eye-z exact fails here: 44 pixels differ at depth 0.)
    let dir = tempfile::tempdir().unwrap();
    let scene = "examples/penetrating.txt";
    let mut checked = Vec::new();
    for row in methods::METHODS
        .iter()
        .filter(|m| m.exact && m.selector == methods::Selector::Variant)
    {
        let input = match row.input {
            methods::Input::AsGiven => scene.to_string(),
            form => {
                let path = dir.path().join(row.name);
                let text = if form == methods::Input::Text {
                    "--text"
                } else {
                    ""
                };
                run(&format!("frames {text} {scene} > {}", path.display()));
                path.display().to_string()
            }
        };
        for depth in row.depths {
            let zbuf = render(&format!("--size 96x72 --depth {depth} {scene}"));
            let options = row.options.join(" ");
            let other = render(&format!("--size 96x72 --depth {depth} {options} {input}"));
            assert!(
                other == zbuf,
                "{} at depth {depth}: {} pixels differ from zbuf",
                row.name,
                differing(&other, &zbuf)
            );
            checked.push(format!("{}@{depth}", row.name));
        }
    }
    assert_eq!(
        checked,
        [
            "zbuf-pixels@0",
            "zbuf-buffer@0",
            "zbuf-buffer@2",
            "zbuf-chain@0",
            "zbuf-text@0",
            "zbuf-binary@0"
        ]
    );
}

#[test]
fn scanline_and_warnock_are_the_zbuffer_on_the_example_scenes() {
    for scene in [
        "examples/penetrating.txt",
        "examples/triangle-square.txt",
        "examples/cube.txt",
        "examples/concave.txt",
        "examples/overlapping-squares.txt",
    ] {
        exact_at_every_depth(&format!("--size 160x120 {scene}"));
    }
}

#[test]
fn scanline_and_warnock_are_the_zbuffer_on_the_degenerate_scenes() {
    let dir = pipeline_tests::repo_root().join("examples/degenerate");
    let mut scenes: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    scenes.sort();
    assert_eq!(scenes.len(), 15);
    for scene in scenes {
        exact_at_every_depth(&format!("--size 96x64 {}", scene.display()));
    }
}

#[test]
fn scanline_and_warnock_are_the_zbuffer_on_random_environments_and_movies() {
    let dir = tempfile::tempdir().unwrap();
    let scene = |name: &str, args: &str| {
        let path = dir.path().join(name);
        run(&format!("scene environment {args} > {}", path.display()));
        path.display().to_string()
    };
    let small = scene("1k.pp", "--polygons 1000 --size 200x150 --seed 7");
    exact_at_every_depth(&format!("--size 200x150 {small}"));
    let big = scene("100k.pp", "--polygons 100000 --size 320x240 --seed 8");
    exact_at_every_depth(&format!("--size 320x240 {big}"));
    let movie = scene(
        "movie.pp",
        "--polygons 400 --frames 6 --depth-complexity 6 --size 128x96 --seed 9",
    );
    exact_at_every_depth(&format!("--size 128x96 {movie}"));
}

#[test]
fn the_painter_is_the_zbuffer_where_there_is_a_depth_order_and_fails_by_counted_pixels() {
    // A depth order: the cube's faces, the overlapping squares (one behind the other).
    for scene in ["examples/cube.txt", "examples/overlapping-squares.txt"] {
        for depth in [0, 2] {
            let zbuf = render(&format!("--size 160x120 --depth {depth} {scene}"));
            let painter = render(&format!(
                "--size 160x120 --depth {depth} --hse painter {scene}"
            ));
            assert!(
                painter == zbuf,
                "{scene} at depth {depth}: the painter differs"
            );
        }
    }
    // The thesis's penetrating polygons have none: at depth 0 the red one is drawn whole
    // over the blue where the blue comes through it. The tree helps: each leaf sorts its
    // own pieces, and from depth 2 (the cut y = 0) the pieces on one side no longer
    // overlap in depth, so only the leaves the penetration line crosses go wrong.
    for (depth, wrong) in [(0, 4571), (1, 4571), (2, 1678), (3, 1678), (4, 1678)] {
        let zbuf = render(&format!("--depth {depth} examples/penetrating.txt"));
        let painter = render(&format!(
            "--depth {depth} --hse painter examples/penetrating.txt"
        ));
        assert_eq!(differing(&painter, &zbuf), wrong, "depth {depth}");
    }
}

#[test]
fn stats_give_each_leafs_method_counters() {
    for (method, counters) in [
        ("scanline", "sample_spans"),
        ("warnock", "windows_by_depth"),
        ("painter", "swaps"),
    ] {
        let out = sh(
            &format!("scripts/render.sh --hse {method} --depth 2 --stats examples/penetrating.txt >/dev/null"),
            b"",
        );
        assert!(out.status.success());
        let err = String::from_utf8(out.stderr).unwrap();
        let records = stagecli::stats::records_of(&err, method).unwrap();
        for leaf in 0..4 {
            // (The painter's leaves also say the cycles they painted out of order.)
            let label = format!("{method} (leaf {leaf})");
            assert!(
                records
                    .iter()
                    .any(|r| r.get("label") == Some(&label) && r.get(counters).is_some()),
                "no counters of leaf {leaf} in {err}"
            );
        }
    }
}

#[test]
fn options_that_cannot_combine_are_refused() {
    for (options, message) in [
        (
            "--merge buffer --hse scanline",
            "render: --merge buffer is the z-buffer's, point-sampled: not with --hse scanline --aa none",
        ),
        (
            "--pixels",
            "render: --pixels sends fragments to the one z-buffer: it needs --merge buffer",
        ),
        ("--hidden-line", "render: --hidden-line needs -o FILE.svg"),
        (
            "--hidden-line --depth 2 -o x.svg",
            "render: --hidden-line draws at depth 0 (the tree's cuts are not edges), not --depth 2",
        ),
        (
            "--hidden-line --aa ss4 -o x.svg",
            "render: --hidden-line draws the visible edges: not with --hse, --aa, --merge buffer or --pixels",
        ),
        (
            "--hidden-line --hse painter -o x.svg",
            "render: --hidden-line draws the visible edges: not with --hse, --aa, --merge buffer or --pixels",
        ),
        (
            "--hidden-line --merge buffer -o x.svg",
            "render: --hidden-line draws the visible edges: not with --hse, --aa, --merge buffer or --pixels",
        ),
    ] {
        let out = sh(&format!("scripts/render.sh {options}"), b"");
        assert_eq!(out.status.code(), Some(2), "{options}");
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(err.lines().next(), Some(message), "{options}");
    }
    // The names --hse takes are the table's, in its order.
    let names = methods::hse_names(methods::METHODS);
    let (last, rest) = names.split_last().expect("a method");
    let out = sh("scripts/render.sh --hse zsort", b"");
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8(out.stderr).unwrap(),
        format!(
            "render: --hse must be {} or {last}, not 'zsort'\n",
            rest.join(", ")
        )
    );
}

#[test]
fn pixels_through_the_one_zbuffer_are_the_same_frames() {
    let spans = render("--merge buffer --depth 2 examples/penetrating.txt");
    assert!(render("--merge buffer --pixels --depth 2 examples/penetrating.txt") == spans);
    assert!(render("--depth 2 examples/penetrating.txt") == spans);
}

#[test]
fn hidden_lines_go_to_the_svg_file() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("lines.svg");
    let out = render(&format!(
        "--hidden-line --size 200x100 -o {} examples/overlapping-squares.txt",
        svg.display()
    ));
    assert!(out.is_empty(), "nothing on stdout");
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains(r#"viewBox="0 0 200 100""#), "{text}");
    assert!(
        text.matches("<line").count() + text.matches("<path").count() > 0,
        "{text}"
    );
}
