//! docs/extending.md, followed: a hidden-surface method added as that page says (a row
//! of the table of methods, a stage binary, its tests) is run by render at the leaves and
//! measured and drawn by chart, with no other file touched.
//!
//! The method is the page's trivial one, the nearest polygon's colour at each pixel
//! centre by brute force (`pipeline_tests::nearest`, binary `nearest`). In the
//! repository its row would be one more entry of `methods::METHODS`, compiled into render
//! and chart; here it is the same row appended to a copy of that table, which render
//! (`render::run_in`) and chart (`chart::methods::runs_in`, `chart::plot::style_in`) are
//! given in place of their own. render starts the stages from `POLYPIPE_BIN`, a folder
//! holding the built stages and `nearest`, as a host's copy of the binaries would.

use methods::{Draws, Input, Marker, Method, Selector, METHODS};
use pipeline_tests::nearest::Nearest;
use pipeline_tests::{bin_dir, repo_root};
use proptest::prelude::*;
use scan::frame::{differing_pixels, image_of, zbuffer_image};
use scan::HiddenSurface;
use std::ffi::OsString;
use std::path::Path;

/// The new row, as docs/extending.md writes it.
const NEAREST: Method = Method {
    name: "nearest",
    selector: Selector::Hse("nearest"),
    options: &["--hse", "nearest"],
    stage: &["nearest"],
    draws: Draws::Pixels,
    exact: true,
    input: Input::AsGiven,
    depths: &[0, 1, 2, 3, 4],
    quick: false,
    colour: [90, 60, 30], // umber
    marker: Marker::Diamond,
    fuzz: None,
};

/// The table with the new row at its end.
fn table() -> Vec<Method> {
    let mut t = METHODS.to_vec();
    t.push(NEAREST);
    t
}

#[test]
fn the_new_row_passes_the_tables_check() {
    assert_eq!(methods::check(&table()), Ok(()));
    // A row that would confuse the chart is refused: the colour of ss4 with its marker.
    let mut t = table();
    t.last_mut().unwrap().colour = [140, 90, 75];
    t.last_mut().unwrap().marker = Marker::Square;
    assert_eq!(
        methods::check(&t),
        Err("nearest: colour and marker too near ss4's (colour distance 4)".into())
    );
}

/// render, in this process with `table`, on `args`: its exit status.
fn render_in(table: &[Method], args: &[&str]) -> u8 {
    let args = std::iter::once("render").chain(args.iter().copied());
    render::run_in(table, args.map(OsString::from))
}

#[test]
fn render_runs_the_new_method_at_the_leaves_and_it_draws_the_zbuffers_frames() {
    // The stages render starts, and the new one, in one folder.
    let bin = tempfile::tempdir().unwrap();
    for stage in render::PIPELINE_STAGES {
        std::os::unix::fs::symlink(bin_dir().join(stage), bin.path().join(stage)).unwrap();
    }
    std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_nearest"), bin.path().join("nearest")).unwrap();
    // The only test of this file that touches the environment, before render reads it:
    // the binaries as they are (no rebuild from POLYPIPE_SOURCES), from that folder.
    std::env::remove_var("POLYPIPE_SOURCES");
    std::env::set_var("POLYPIPE_BIN", bin.path());
    let out = tempfile::tempdir().unwrap();
    let root = repo_root();
    let table = table();
    for scene in ["examples/penetrating.txt", "examples/cube.txt"] {
        let scene = root.join(scene).display().to_string();
        for depth in ["0", "2"] {
            let picture = |hse: &str| {
                let file = out.path().join(format!("{hse}-{depth}.ppm"));
                let path = file.display().to_string();
                let args = [
                    "--size", "160x120", "--depth", depth, "--hse", hse, "-o", &path, &scene,
                ];
                assert_eq!(render_in(&table, &args), 0, "--hse {hse} {depth} {scene}");
                std::fs::read(&file).unwrap()
            };
            let nearest = picture("nearest");
            let zbuf = picture("zbuf");
            assert_eq!(&nearest[..15], b"P6\n160 120\n255\n", "{scene}");
            assert!(nearest == zbuf, "{scene} at depth {depth}");
        }
    }
    // The table render is built with has no such method, and says which it has.
    assert_eq!(render_in(METHODS, &["--hse", "nearest", "-o", "x.ppm"]), 2);
    assert!(!Path::new("x.ppm").exists());
}

#[test]
fn render_lists_the_new_row_and_chart_runs_and_draws_it() {
    let table = table();
    let listing = methods::listing(&table);
    assert_eq!(
        listing.lines().last(),
        Some("nearest\thse:nearest\t--hse nearest\tnearest\tpixels\texact\tas-given\t0,1,2,3,4\tfull\t#5a3c1e\tdiamond\t-")
    );
    // The chart's runs of it: every depth; not in a quick run.
    let only = ["nearest".to_string()];
    let runs = chart::methods::runs_in(&table, false, Some(&only));
    assert_eq!(
        runs.iter().map(|(m, d)| (m.name, *d)).collect::<Vec<_>>(),
        [0, 1, 2, 3, 4].map(|d| ("nearest", d))
    );
    assert_eq!(runs[0].0.options, ["--hse", "nearest"]);
    assert!(chart::methods::runs_in(&table, true, Some(&only)).is_empty());
    // Its colour and marker, from its row; the other rows' unchanged.
    let (colour, marker) = chart::plot::style_in(&table, "nearest");
    assert_eq!(
        ((colour.0, colour.1, colour.2), marker),
        ((90, 60, 30), Marker::Diamond)
    );
    for m in METHODS {
        assert_eq!(
            chart::plot::style_in(&table, m.name),
            chart::plot::style_of(m.name)
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// The method's own test, as for any exact method: the z-buffer's picture on random
    /// frames of overlapping, interpenetrating triangles with shared depths.
    #[test]
    fn nearest_is_the_zbuffer_on_random_frames(
        triangles in prop::collection::vec(
            (prop::array::uniform3((0u8..=24, 0u8..=24, 0u8..=3)), any::<[u8; 3]>()),
            1..12,
        ),
        (width, height) in (1u32..=24, 1u32..=24),
    ) {
        let polygons: Vec<proto::Polygon> = triangles
            .iter()
            .map(|(corners, colour)| {
                let vertices = corners
                    .iter()
                    .map(|&(x, y, z)| proto::Vertex::new(x as f64, y as f64, z as f64 * 0.25, 1.0))
                    .collect();
                proto::Polygon::new(*colour, vertices)
            })
            .collect();
        let mut runs = Vec::new();
        let mut method = Nearest::default();
        method.resolve(&polygons, width, height, &mut runs);
        let image = image_of(&runs, width, height);
        prop_assert_eq!(differing_pixels(&image, &zbuffer_image(&polygons, width, height)), 0);
    }
}

/// The `methods` fuzz target holds every exact row that names it to the z-buffer's
/// picture: each such row has its resolver in the target's one `match`, so that a row
/// added without one is found here, not on the fuzzer's first input.
#[test]
fn the_methods_fuzz_target_resolves_every_exact_row_that_names_it() {
    let target = std::fs::read_to_string(repo_root().join("fuzz/fuzz_targets/methods.rs"))
        .expect("fuzz/fuzz_targets/methods.rs");
    assert!(
        target.contains(".filter(|m| m.fuzz == Some(\"methods\") && m.exact)"),
        "the target no longer picks its rows from the table"
    );
    let rows: Vec<&str> = METHODS
        .iter()
        .filter(|m| m.fuzz == Some("methods") && m.exact)
        .map(|m| m.name)
        .collect();
    assert!(
        rows.contains(&"scanline") && rows.contains(&"warnock"),
        "{rows:?}"
    );
    for name in rows {
        assert!(
            target.contains(&format!("\"{name}\" => Box::new(")),
            "the methods fuzz target has no resolver for {name}"
        );
    }
}
