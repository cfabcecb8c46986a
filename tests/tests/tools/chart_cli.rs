//! `scripts/chart.sh` (docs/DESIGN.md, "Measures"; docs/model.md): the chart's three files
//! on a small scene, with the columns the design names and real values in them; the cost
//! model's rows for depths 0-4; and `chart choose-depth` (`plan depth`), render.sh's
//! `--depth auto`. Every run that could calibrate the model is given a cache folder of
//! its own (XDG_CACHE_HOME) and the quick calibration (POLYPIPE_CALIBRATION=quick).

use pipeline_tests::{repo_root, sh};
use std::collections::HashMap;
use std::path::Path;

/// A CSV file as a header and rows of named fields (the chart's CSV has no quoted
/// fields).
fn read_csv(path: &Path) -> (Vec<String>, Vec<HashMap<String, String>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(String::from))
                .collect()
        })
        .collect();
    (header, rows)
}

fn num(row: &HashMap<String, String>, column: &str) -> f64 {
    row[column]
        .parse()
        .unwrap_or_else(|_| panic!("{column} = {:?} in {row:?}", row[column]))
}

/// The environment of a run with a cache folder of its own, and the quick calibration.
fn cached(cache: &Path) -> String {
    format!(
        "XDG_CACHE_HOME={} POLYPIPE_CALIBRATION=quick",
        cache.display()
    )
}

fn chart(args: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let out = sh(
        &format!(
            "{} scripts/chart.sh -o {} {args}",
            cached(&dir.path().join("cache")),
            dir.path().display()
        ),
        b"",
    );
    assert!(
        out.status.success(),
        "chart.sh {args}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    dir
}

#[test]
fn quick_chart_of_a_small_scene_makes_its_files_with_real_values() {
    let dir = chart("--quick examples/penetrating.txt@120x90");
    let d = dir.path();
    for f in [
        "results.csv",
        "speed-accuracy.png",
        "speed-accuracy.svg",
        "model.csv",
        "model.png",
    ] {
        assert!(d.join(f).metadata().unwrap().len() > 0, "{f}");
    }
    let png = image::open(d.join("speed-accuracy.png")).unwrap();
    assert!(
        png.width() >= 700 && png.height() >= 500,
        "{}x{}",
        png.width(),
        png.height()
    );
    let svg = std::fs::read_to_string(d.join("speed-accuracy.svg")).unwrap();
    assert!(
        svg.contains("CPU s less start-up (log; median, bar least–most of the runs)"),
        "the x axis is titled"
    );
    assert!(svg.contains("penetrating"), "the panel names its scene");

    let (header, rows) = read_csv(&d.join("results.csv"));
    for c in [
        "scene",
        "method",
        "depth",
        "size",
        "polygons",
        "wall_s",
        "cpu_s",
        "max_rss_kib",
        "error_fraction",
        "edge_rmse",
        "rms_16x16",
        "visibility_error",
        "time_s",
        "startup_share",
    ] {
        assert!(
            header.iter().any(|h| h == c),
            "results.csv lacks {c}: {header:?}"
        );
    }
    let zbuf: Vec<_> = rows.iter().filter(|r| r["method"] == "zbuf").collect();
    let depths: Vec<&str> = zbuf.iter().map(|r| r["depth"].as_str()).collect();
    assert_eq!(depths, ["0", "1", "2", "3", "4"]);
    for r in &zbuf {
        assert_eq!(r["scene"], "penetrating");
        assert_eq!(r["size"], "120x90");
        assert_eq!(r["polygons"], "2");
        assert!(num(r, "error_fraction") <= 0.0005, "{r:?}");
        assert!(num(r, "wall_s") > 0.0 && num(r, "cpu_s") > 0.0, "{r:?}");
        assert!(num(r, "max_rss_kib") > 500.0, "{r:?}");
        // Point sampling against 16×16: the edge pixels are off, by a real amount.
        let e = num(r, "edge_rmse");
        assert!(e > 1.0 && e < 255.0, "{r:?}");
    }
    // max_rss_kib is the whole tree's: the stages' peaks summed (render's `--times`,
    // from its launcher's wait4 of each stage), so that depth 4's 23 stages hold more
    // than depth 0's 3 (ru_maxrss, the largest one process's, is one stage's; a sampler
    // of /proc missed the stages of this render of a few milliseconds).
    let rss = |d: usize| num(zbuf[d], "max_rss_kib");
    assert!(
        rss(4) > 1.2 * rss(0),
        "depth 0 {} KiB, depth 4 {} KiB",
        rss(0),
        rss(4)
    );
    // Text and binary input give the same frame, so the same error.
    let bin = rows.iter().find(|r| r["method"] == "zbuf-binary").unwrap();
    assert_eq!(bin["edge_rmse"], zbuf[0]["edge_rmse"]);
    assert!(rows.iter().any(|r| r["method"] == "zbuf-eye-z"));

    let (header, rows) = read_csv(&d.join("model.csv"));
    for c in [
        "scene",
        "depth",
        "predicted_s",
        "measured_s",
        "hse_s",
        "clip_s",
        "bottleneck",
    ] {
        assert!(
            header.iter().any(|h| h == c),
            "model.csv lacks {c}: {header:?}"
        );
    }
    let depths: Vec<&str> = rows.iter().map(|r| r["depth"].as_str()).collect();
    assert_eq!(depths, ["0", "1", "2", "3", "4"]);
    for r in &rows {
        assert!(
            num(r, "predicted_s") > 0.0 && num(r, "measured_s") > 0.0,
            "{r:?}"
        );
        assert_eq!(r["polygons_in_view"], "2");
    }
    // Each level adds processes: 3 at depth 0 (viewxf, clipbatch, zbuf projecting and
    // resolving the one leaf), 2 + 5 + 15 + 1 at depth 4 (the 15 splitter nodes two
    // levels to a process, the last projecting, the leaves one process each, zbuf
    // resolving leaf 0 itself).
    assert_eq!(rows[0]["processes"], "3");
    assert_eq!(rows[4]["processes"], "23");

    // The machine had no calibration: the chart made one first, and kept it.
    let kept = std::fs::read_to_string(d.join("cache/polypipe/model.toml")).unwrap();
    assert!(kept.contains("[machine]"), "{kept}");
    // The extrapolation beside it: 1 to 64 cores, depths 0-6, and four hosts.
    let (_, extra) = read_csv(&d.join("model-extrapolation.csv"));
    assert_eq!(
        extra.iter().filter(|r| r["target"] == "64 cores").count(),
        7
    );
    assert!(extra
        .iter()
        .any(|r| r["target"].starts_with("4 hosts") && r["depth"] == "2"));

    // --remodel predicts again from another model file and keeps what was measured: a
    // script a second slower is every prediction a second later than the committed
    // file's.
    let remodel = |model: &str| {
        let out = sh(
            &format!(
                "scripts/chart.sh -o {} --remodel --model {model} examples/penetrating.txt@120x90",
                d.display()
            ),
            b"",
        );
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        read_csv(&d.join("model.csv")).1
    };
    let rows = remodel("bench/model.toml");
    let committed = std::fs::read_to_string(repo_root().join("bench/model.toml")).unwrap();
    let slower: String = committed
        .lines()
        .map(|l| match l.strip_prefix("script = ") {
            Some(v) => format!("script = {}\n", v.parse::<f64>().unwrap() + 1.0),
            None => format!("{l}\n"),
        })
        .collect();
    let model = d.join("slower.toml");
    std::fs::write(&model, slower).unwrap();
    let again = remodel(&model.to_string_lossy());
    assert_eq!(again.len(), rows.len());
    for (a, r) in again.iter().zip(&rows) {
        assert_eq!(a["measured_s"], r["measured_s"]);
        let later = num(a, "predicted_s") - num(r, "predicted_s");
        assert!((later - 1.0).abs() < 1e-3, "{later}: {a:?} {r:?}");
    }
    // Scenes that are not those of the run are refused.
    let out = sh(
        &format!(
            "{} scripts/chart.sh -o {} --remodel examples/cube.txt",
            cached(&d.join("cache")),
            d.display()
        ),
        b"",
    );
    assert!(!out.status.success());
}

/// The chart's `max-error.csv` is what `render --max-error E` chooses on the scene as the
/// chart rendered it (in its own colours), with the same cache: the same configuration
/// and the same predictions, beside the chart's run of it where there is one; and the
/// speed-accuracy figure rings each, and says what the rings are.
#[test]
fn the_chart_marks_what_render_max_error_chooses() {
    let dir = chart("--quick --reps 1 examples/penetrating.txt@120x90");
    let d = dir.path();
    let (header, choices) = read_csv(&d.join("max-error.csv"));
    assert_eq!(
        header,
        [
            "scene",
            "budget",
            "method",
            "aa",
            "depth",
            "predicted_time_s",
            "predicted_error",
            "predicted_less_startup_s",
            "measured_time_s",
            "measured_rms",
            "rule"
        ]
    );
    let budgets: Vec<f64> = choices.iter().map(|c| num(c, "budget")).collect();
    assert_eq!(budgets, [0.0, 1.0, 4.0, 16.0]);
    let (_, rows) = read_csv(&d.join("results.csv"));
    let coloured = d.join("refs/penetrating.coloured.pp");
    for c in &choices {
        assert_eq!(
            (c["scene"].as_str(), c["rule"].as_str()),
            ("penetrating", "cheapest predicted to meet it"),
            "{c:?}"
        );
        let e = num(c, "budget");
        assert!(num(c, "predicted_error") <= e, "{c:?}");
        let less = num(c, "predicted_less_startup_s");
        assert!(less >= 0.0 && less < num(c, "predicted_time_s"), "{c:?}");
        let out = sh(
            &format!(
                "{} render --max-error {e} --stats --size 120x90 {} > /dev/null",
                cached(&d.join("cache")),
                coloured.display()
            ),
            b"",
        );
        let said = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{said}");
        let chose = format!(
            "render: max-error {e} chose --aa {} --depth {} (predicted {:.3} s, RMS {:.2}, ",
            c["aa"],
            c["depth"],
            num(c, "predicted_time_s"),
            num(c, "predicted_error")
        );
        assert!(said.contains(&chose), "{chose}\n{said}");
        // Beside the chart's run of that configuration, where it ran one.
        match rows
            .iter()
            .find(|r| r["method"] == c["method"] && r["depth"] == c["depth"])
        {
            Some(r) => assert_eq!(
                (&c["measured_time_s"], &c["measured_rms"]),
                (&r["time_s"], &r["rms_16x16"]),
                "{c:?}"
            ),
            None => assert_eq!(
                (&c["measured_time_s"][..], &c["measured_rms"][..]),
                ("", "")
            ),
        }
    }
    // 0 is the reference's own bytes: adaptive16 on this flat scene (ss16's bytes, fewer
    // samples), which --quick does not run; 16 is point sampling, the chart's zbuf at
    // depth 0.
    let fields = |c: &HashMap<String, String>| {
        ["method", "aa", "depth", "predicted_error", "measured_rms"].map(|f| c[f].clone())
    };
    assert_eq!(
        fields(&choices[0]),
        ["adaptive16", "adaptive16", "0", "0.0", ""]
    );
    let zbuf = rows
        .iter()
        .find(|r| r["method"] == "zbuf" && r["depth"] == "0")
        .unwrap();
    assert_eq!(
        fields(&choices[3])[..3],
        ["zbuf".to_string(), "none".into(), "0".into()]
    );
    assert_eq!(choices[3]["measured_rms"], zbuf["rms_16x16"]);
    // A ring a configuration chosen, and the legend's.
    let svg = std::fs::read_to_string(d.join("speed-accuracy.svg")).unwrap();
    let mut configurations: Vec<(&str, &str)> = choices
        .iter()
        .map(|c| (c["method"].as_str(), c["depth"].as_str()))
        .collect();
    configurations.dedup();
    let rings = svg.matches(r##"r="13" opacity="1" fill="none" stroke="#000000""##);
    assert_eq!(
        rings.count(),
        configurations.len() + 1,
        "{configurations:?}"
    );
    assert!(svg.contains("Ringed, labelled ≤E: what render --max-error E chooses"));
    // --replot draws them again from max-error.csv.
    std::fs::remove_file(d.join("speed-accuracy.svg")).unwrap();
    let out = sh(
        &format!("scripts/chart.sh -o {} --replot", d.display()),
        b"",
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let again = std::fs::read_to_string(d.join("speed-accuracy.svg")).unwrap();
    let rings = again.matches(r##"r="13" opacity="1" fill="none" stroke="#000000""##);
    assert_eq!(rings.count(), configurations.len() + 1);
}

#[test]
fn the_full_method_table_runs_every_variant() {
    let dir = chart("--reps 1 examples/triangle-square.txt@64x48");
    let (_, rows) = read_csv(&dir.path().join("results.csv"));
    let runs: Vec<String> = rows
        .iter()
        .map(|r| format!("{}@{}", r["method"], r["depth"]))
        .collect();
    for want in [
        "zbuf@0",
        "zbuf@4",
        "scanline@4",
        "warnock@4",
        "painter@0",
        "painter-split@4",
        "abuf@2",
        "ss2@0",
        "ss4@0",
        "ss8@0",
        "ss16@2",
        "adaptive4@0",
        "adaptive16@2",
        "zbuf-pixels@0",
        "zbuf-eye-z@0",
        "zbuf-buffer@0",
        "zbuf-buffer@2",
        "zbuf-chain@0",
        "zbuf-text@0",
        "zbuf-binary@0",
        "hiddenline@0",
        "hiddenline-archuleta@0",
    ] {
        assert!(runs.contains(&want.to_string()), "{want} not in {runs:?}");
    }
    // Every exact variant (projective depth, point-sampled) is the z-buffer's picture: no
    // pixel differs from zspec on this scene. The painter is wrong where the triangle
    // pierces the square; anti-aliasing changes the edge pixels on purpose, and brings
    // them nearer the 16×16 reference. The hidden-line methods draw lines, not pixels.
    let exact = |m: &str| {
        !(m == "zbuf-eye-z"
            || m.starts_with("painter")
            || m == "abuf"
            || m.starts_with("ss")
            || m.starts_with("adaptive")
            || m.starts_with("hiddenline"))
    };
    let painter = rows.iter().find(|r| r["method"] == "painter").unwrap();
    assert!(num(painter, "error_fraction") > 0.0);
    for r in rows.iter().filter(|r| exact(&r["method"])) {
        assert_eq!(num(r, "error_fraction"), 0.0, "{r:?}");
    }
    let edge = |method: &str| {
        let r = rows
            .iter()
            .find(|r| r["method"] == method && r["depth"] == "0")
            .unwrap();
        num(r, "edge_rmse")
    };
    assert!(
        edge("abuf") < edge("zbuf") / 4.0,
        "abuf {} zbuf {}",
        edge("abuf"),
        edge("zbuf")
    );
    assert!(edge("ss16") < edge("ss4") && edge("ss4") < edge("zbuf"));
    // A flat scene: adaptive sampling draws ssK's pixels.
    for k in [2, 4, 8, 16] {
        assert_eq!(
            edge(&format!("adaptive{k}")),
            edge(&format!("ss{k}")),
            "K = {k}"
        );
    }
    assert!(rows.len() >= 8);
}

/// What every row of results.csv has (docs/methods.md, "The chart"): its time less
/// start-up with the start-up's share and the spread of its runs, and `rms_16x16`
/// (a hidden-line row's of its drawing as a picture); the visibility error where it
/// point-samples; the line error where it draws lines; none of them empty or NaN. `runs`
/// is the number of timed runs each row must have.
fn assert_every_measure(rows: &[HashMap<String, String>], runs: u32) {
    assert!(!rows.is_empty());
    for r in rows {
        let finite = |c: &str| {
            let v = num(r, c);
            assert!(v.is_finite() && v >= 0.0, "{c} = {v} in {r:?}");
            v
        };
        let (t, lo, hi) = (finite("time_s"), finite("time_lo_s"), finite("time_hi_s"));
        assert!(lo <= t && t <= hi, "{r:?}");
        assert!(finite("startup_s") > 0.0, "{r:?}");
        finite("startup_share");
        assert_eq!(num(r, "runs"), runs as f64, "{r:?}");
        finite("rms_16x16");
        let m = r["method"].as_str();
        let lines = m.starts_with("hiddenline");
        let aa = m == "abuf" || m.starts_with("ss") || m.starts_with("adaptive");
        if lines {
            finite("line_error_px");
            assert_eq!(r["visibility_error"], "", "{r:?}");
        } else {
            assert_eq!(r["line_error_px"], "", "{r:?}");
            if aa {
                assert_eq!(r["visibility_error"], "", "{r:?}");
            } else {
                // The share of pixels unlike the point-sampled reference, in per cent.
                let v = finite("visibility_error");
                assert!((v - 100.0 * num(r, "error_fraction")).abs() < 1e-9, "{r:?}");
            }
        }
    }
}

/// A tiny chart of five interleaved runs a row: every measure on every row; the painter's
/// visibility error on the cyclic bars at depth 0, the z-buffer's none; anti-aliasing
/// nearer the 16×16 reference than point sampling; the exact hidden-line drawing scored
/// 0 against itself; both figures drawn, each naming its measure.
#[test]
fn every_row_has_its_time_its_spread_and_its_errors() {
    let dir = chart(
        "--reps 5 --methods zbuf,painter,ss4,hiddenline,hiddenline-archuleta \
         examples/cyclic-bars.txt@64x64",
    );
    let d = dir.path();
    let (_, rows) = read_csv(&d.join("results.csv"));
    assert_every_measure(&rows, 5);
    let row = |m: &str, depth: u8| find(&rows, "cyclic-bars", m, depth).unwrap();
    assert!(num(row("painter", 0), "visibility_error") > 0.5);
    for depth in 0..=4 {
        assert_eq!(num(row("zbuf", depth), "visibility_error"), 0.0);
    }
    assert!(num(row("ss4", 0), "rms_16x16") < num(row("zbuf", 0), "rms_16x16"));
    // Against itself: 0 but for rounding in the measure; its picture the exact one's,
    // Archuleta's not (his ends fall between the scan lines).
    assert!(num(row("hiddenline", 0), "line_error_px") < 1e-6);
    assert_eq!(num(row("hiddenline", 0), "rms_16x16"), 0.0);
    let archuleta = num(row("hiddenline-archuleta", 0), "rms_16x16");
    assert!(archuleta > 0.0 && archuleta < 40.0, "{archuleta}");
    let svg = std::fs::read_to_string(d.join("speed-accuracy.svg")).unwrap();
    assert!(svg.contains("RMS error vs 16×16 reference (0–255)") && svg.contains("ss4"));
    let vis = std::fs::read_to_string(d.join("visibility.svg")).unwrap();
    assert!(vis.contains("% pixels whose visible polygon is wrong"));
    assert!(vis.contains("painter") && !vis.contains(">ss4<"));
}

#[test]
fn the_painter_is_charted_wrong_on_a_cyclic_overlap() {
    let dir = chart("--quick examples/cyclic-bars.txt@96x96");
    let (_, rows) = read_csv(&dir.path().join("results.csv"));
    let error = |method: &str| {
        let r = rows.iter().find(|r| r["method"] == method).unwrap();
        num(r, "error_fraction")
    };
    assert!(error("painter") > 0.005, "painter: {}", error("painter"));
    for exact in ["zbuf", "scanline", "warnock"] {
        assert_eq!(error(exact), 0.0, "{exact}");
    }
    assert!(
        rows.iter()
            .filter(|r| r["scene"] == rows[0]["scene"])
            .count()
            >= 8
    );
}

#[test]
fn choose_depth_gives_two_polygons_depth_0_and_says_why() {
    let out = sh(
        "scripts/chart.sh choose-depth --size 500x500 examples/penetrating.txt",
        b"",
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let line = String::from_utf8(out.stdout).unwrap();
    assert!(line.starts_with("0 ("), "{line}");
    assert!(line.contains("2 polygons in view"), "{line}");
    assert_eq!(line.lines().count(), 1, "{line}");
}

#[test]
fn choose_depth_refuses_a_bad_size_and_a_missing_scene() {
    let out = sh(
        "scripts/chart.sh choose-depth --size 0x5 examples/penetrating.txt",
        b"",
    );
    assert_eq!(
        out.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // A camera nothing can be seen through is the command line's fault, 2, as viewxf
    // says of the same options; through render.sh's --depth auto as well.
    let out = sh(
        "scripts/chart.sh choose-depth --hither 0 examples/penetrating.txt",
        b"",
    );
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "chart: --hither 0 --yon 30: they must satisfy 0 < hither < yon\n"
    );
    let out = sh(
        "scripts/render.sh --depth auto --hither 0 examples/penetrating.txt",
        b"",
    );
    assert_eq!(out.status.code(), Some(2));
    // A scene that cannot be read is an I/O error, 3, in the stages' words.
    let out = sh("scripts/chart.sh choose-depth no-such-scene.txt", b"");
    assert_eq!(out.status.code(), Some(3));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "chart: cannot open no-such-scene.txt: No such file or directory\n"
    );
}

/// Runs a command line and gives its status and whole stderr.
fn status_and_stderr(command: &str) -> (Option<i32>, String) {
    let out = sh(command, b"");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn chart_exits_as_the_stages_do() {
    // The README's table: 0 when the reader went away, quietly; 2 bad arguments, one line
    // `chart: …`; 3 a file that cannot be opened, read or written, named.
    let cases: &[(&str, i32, &str)] = &[
        // The reader gone before chart writes its line.
        (
            "{ sleep 0.3; exec chart choose-depth examples/penetrating.txt; } | true",
            0,
            "",
        ),
        (
            "chart choose-depth examples/penetrating.txt > /dev/full",
            3,
            "chart: stdout: No space left on device\n",
        ),
        (
            "chart choose-depth /nonexistent/s.txt",
            3,
            "chart: cannot open /nonexistent/s.txt: No such file or directory\n",
        ),
        ("chart choose-depth /", 3, "chart: /: Is a directory\n"),
        (
            "chart -o OUT --quick /nonexistent/s.txt",
            3,
            "chart: cannot open /nonexistent/s.txt: No such file or directory\n",
        ),
        (
            "scripts/chart.sh -o OUT --quick /tmp",
            3,
            "chart: /tmp: Is a directory\n",
        ),
        (
            "scripts/chart.sh --quick examples/penetrating.txt",
            2,
            "chart: -o DIR is needed (where the CSV files and pictures go)\n",
        ),
        (
            "chart -o OUT --quick",
            2,
            "chart: no SCENE given (or --standard)\n",
        ),
        // A bad `@WxH` in --size's words (proto::camera::parse_size), before any folder
        // is made.
        (
            "scripts/chart.sh -o OUT --quick examples/penetrating.txt@0x5",
            2,
            "chart: invalid size in scene 'examples/penetrating.txt@0x5': \
             `0` in `0x5` is not a size from 1 to 65536\n",
        ),
        (
            "chart -o OUT --size 0x5 examples/penetrating.txt",
            2,
            "chart: invalid value '0x5' for '--size <WxH>': \
             `0` in `0x5` is not a size from 1 to 65536\n",
        ),
    ];
    // OUT: a folder that none of these makes, each failing before anything is written.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    for &(command, status, stderr) in cases {
        let command = command.replace("OUT", &out.to_string_lossy());
        assert_eq!(
            status_and_stderr(&command),
            (Some(status), stderr.to_string()),
            "{command}"
        );
        assert!(!out.exists(), "{command} made {}", out.display());
    }
    // clap's message as one line, its list of the valid values kept: the table's names
    // (methods::METHODS), whatever it holds.
    let names: Vec<&str> = methods::METHODS.iter().map(|m| m.name).collect();
    let command = format!(
        "chart -o {} --methods foo examples/penetrating.txt",
        out.display()
    );
    assert_eq!(
        status_and_stderr(&command),
        (
            Some(2),
            format!(
                "chart: invalid value 'foo' for '--methods <NAME,…>': no method foo; the \
                 methods: {}\n",
                names.join(", ")
            )
        )
    );
    assert!(!out.exists(), "{command} made {}", out.display());
}

#[test]
fn the_model_table_ends_quietly_when_its_reader_goes_away() {
    // The chart's own stdout (the model's table) is written as choose-depth's line is.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().display();
    // `true` is gone long before the table is written, a second or so of runs later.
    let (status, err) = status_and_stderr(&format!(
        "chart --root . -o {d} --model bench/model.toml --quick --methods zbuf examples/penetrating.txt@40x30 | true"
    ));
    assert_eq!((status, err.as_str()), (Some(0), ""));
    let (status, err) = status_and_stderr(&format!(
        "chart --root . -o {d} --model bench/model.toml --quick --methods zbuf examples/penetrating.txt@40x30 > /dev/full"
    ));
    assert_eq!(status, Some(3), "{err}");
    assert!(
        err.ends_with("chart: stdout: No space left on device\n"),
        "{err}"
    );
}

/// How `render --depth auto --stats` begins for two polygons: depth 0 and why, from the
/// look; or, with a core or less for the render (a one-CPU runner, a container's quota,
/// `taskset -c 0`), depth 0 without the look, said as such.
fn auto_chose_0_for_two_polygons() -> String {
    if pipeline_tests::one_core_for_render() {
        format!("render: {}", render::auto::ONE_CORE)
    } else {
        "render: depth auto chose 0 (2 polygons in view, ".to_string()
    }
}

#[test]
fn render_depth_auto_says_its_choice_and_renders_at_it() {
    // Two polygons: depth 0, said under --stats, the frame depth 0's; from stdin too.
    let at0 = sh("scripts/render.sh --depth 0 examples/penetrating.txt", b"");
    assert!(at0.status.success());
    for (command, stdin) in [
        (
            "scripts/render.sh --depth auto --stats examples/penetrating.txt",
            &b""[..],
        ),
        (
            "scripts/render.sh --depth auto --stats -",
            &std::fs::read(pipeline_tests::repo_root().join("examples/penetrating.txt")).unwrap()[..],
        ),
    ] {
        let out = sh(command, stdin);
        assert!(out.status.success(), "{command}");
        assert!(out.stdout == at0.stdout, "{command}: not depth 0's frame");
        let err = String::from_utf8(out.stderr).unwrap();
        let line = err.lines().next().unwrap_or("");
        assert!(
            line.starts_with(&auto_chose_0_for_two_polygons()),
            "{command}: {err}"
        );
        assert_eq!(
            pipeline_tests::stat(&err, "depth_auto"),
            0,
            "{command}: {err}"
        );
        let records = stagecli::stats::records(&err).unwrap();
        let stages: Vec<&str> = records.iter().map(|r| r.stage()).collect();
        assert!(
            !stages.contains(&"splitter"),
            "no splitter at depth 0: {err}"
        );
    }
    // Without --stats it says nothing.
    let quiet = sh(
        "scripts/render.sh --depth auto examples/penetrating.txt",
        b"",
    );
    assert!(quiet.status.success() && quiet.stderr.is_empty());
}

#[test]
fn auto_is_the_default_depth_and_a_scene_it_cannot_look_at_goes_to_the_stages() {
    // No --depth: the model chooses, here depth 0 for two polygons, from a pipe too
    // (`<(…)`, read twice: once by chart, once by the render), with a camera whose
    // coordinate starts with a minus.
    let out = sh(
        "scripts/render.sh --stats --eye -8,5,18 <(cat examples/penetrating.txt)",
        b"",
    );
    assert!(out.status.success(), "{out:?}");
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.starts_with(&auto_chose_0_for_two_polygons()), "{err}");
    assert_eq!(pipeline_tests::stat(&err, "depth_auto"), 0, "{err}");
    let at0 = sh(
        "scripts/render.sh --depth 0 --eye -8,5,18 examples/penetrating.txt",
        b"",
    );
    assert!(out.stdout == at0.stdout, "not depth 0's frame");
    // A scene the look cannot read: by default the stages say what is wrong (viewxf,
    // status 1), as at depth 0; with --depth auto asked for too: the sample the planner
    // could not read goes on to viewxf, which says what is wrong.
    let bad = b"polypipe 1 world\ncolour 1 2 3\n0 0\n";
    let out = sh("scripts/render.sh -", bad);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("viewxf: line 3, column 4: expected z of vertex 0"),
        "{err}"
    );
    let out = sh("scripts/render.sh --depth auto -", bad);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("viewxf: line 3, column 4: expected z of vertex 0")
            && err.lines().count() == 1,
        "{err}"
    );
}

/// The hard scenes of `--hard`, in the order the chart draws them.
const HARD: [&str; 6] = [
    "stack",
    "slivers",
    "planes",
    "cyclic-bars",
    "spheres",
    "strips",
];

/// Rows of one scene, method and depth.
fn find<'a>(
    rows: &'a [HashMap<String, String>],
    scene: &str,
    method: &str,
    depth: u8,
) -> Option<&'a HashMap<String, String>> {
    rows.iter()
        .find(|r| r["scene"] == scene && r["method"] == method && r["depth"] == depth.to_string())
}

/// `--quick --hard`: the small hard scenes (the full ones' 16×16 references are a minute
/// and a half of CPU), the z-buffer at every depth and the painter at depth 0.
#[test]
fn hard_scenes_run_every_depth_and_count_their_statistics() {
    let dir = chart("--quick --hard --methods zbuf,painter");
    let d = dir.path();
    let (header, rows) = read_csv(&d.join("results.csv"));
    for c in [
        "edges",
        "depth_complexity",
        "visible_polygons",
        "visible_segments",
        "segments_per_line",
    ] {
        assert!(header.iter().any(|h| h == c), "results.csv lacks {c}");
    }
    for scene in HARD {
        for (method, depths) in [
            ("zbuf", &["0", "1", "2", "3", "4"][..]),
            ("painter", &["0"]),
        ] {
            let ran: Vec<&str> = rows
                .iter()
                .filter(|r| r["scene"] == scene && r["method"] == method)
                .map(|r| r["depth"].as_str())
                .collect();
            assert_eq!(ran, depths, "{method} on {scene}");
        }
        // The z-buffer is the reference's picture on every hard scene, at every depth.
        for depth in 0..=4 {
            let z = find(&rows, scene, "zbuf", depth).unwrap();
            assert_eq!(num(z, "error_fraction"), 0.0, "{z:?}");
        }
    }
    // The failure the chart must show: the painter alone on the cyclic bars.
    let p = find(&rows, "cyclic-bars", "painter", 0).unwrap();
    assert!(num(p, "error_fraction") > 0.005, "{p:?}");
    // The stack, by hand: 100 screen-filling squares on 50×50 (300 on 100×100 without
    // --quick), so every pixel is covered 100 times, one square owns them all, one
    // segment on each of 50 rows.
    let s = find(&rows, "stack", "zbuf", 0).unwrap();
    assert_eq!(s["size"], "50x50");
    assert_eq!(
        [
            "polygons",
            "edges",
            "depth_complexity",
            "visible_polygons",
            "visible_segments",
            "segments_per_line"
        ]
        .map(|c| num(s, c)),
        [100.0, 400.0, 100.0, 1.0, 50.0, 1.0]
    );
    // The cyclic bars: three bars, each visible, none hidden.
    let c = find(&rows, "cyclic-bars", "zbuf", 0).unwrap();
    assert_eq!(num(c, "visible_polygons"), 3.0);
    // Every hard scene has its 16×16 reference: an RMS error on every pixel row, and the
    // figures are drawn.
    for r in &rows {
        assert!(num(r, "rms_16x16").is_finite(), "{r:?}");
    }
    let cost = std::fs::read_to_string(d.join("cost-environment.svg")).unwrap();
    for axis in [
        "polygons P_t, a frame",
        "depth complexity Dc",
        "visible segments on the scan lines",
    ] {
        assert!(cost.contains(axis), "cost-environment.svg lacks {axis}");
    }
    let svg = std::fs::read_to_string(d.join("speed-accuracy.svg")).unwrap();
    assert!(
        svg.contains("stack (100 polygons, 50×50)"),
        "the stack's panel"
    );
    assert!(
        svg.contains("RMS error vs 16×16 reference (0–255)"),
        "every panel of the first figure is RMS"
    );
    let vis = std::fs::read_to_string(d.join("visibility.svg")).unwrap();
    assert!(
        vis.contains("% pixels whose visible polygon is wrong"),
        "the second figure says its measure"
    );
}

/// The committed figures (`scripts/chart.sh --figures`): the CSV beside them has, for
/// every method on every hard scene, its depth-0 run and the depths it was tried at,
/// the painter's depth-0 error on the cyclic bars is there, above 0, and both
/// hidden-line methods are there on every scene.
#[test]
fn the_committed_figures_have_every_method_at_depth_0_and_its_best() {
    let images = repo_root().join("docs/images");
    let (_, rows) = read_csv(&images.join("results.csv"));
    let methods: Vec<String> = {
        let mut m: Vec<String> = Vec::new();
        for r in &rows {
            if !m.contains(&r["method"]) {
                m.push(r["method"].clone());
            }
        }
        m
    };
    for want in [
        "zbuf",
        "scanline",
        "warnock",
        "painter",
        "painter-split",
        "abuf",
        "ss4",
        "ss16",
    ] {
        assert!(methods.iter().any(|m| m == want), "{want} not charted");
    }
    for scene in HARD {
        for m in &methods {
            let runs: Vec<_> = rows
                .iter()
                .filter(|r| r["scene"] == scene && &r["method"] == m)
                .collect();
            assert!(
                runs.iter().any(|r| r["depth"] == "0"),
                "{m} at depth 0 on {scene}"
            );
            assert!(!runs.is_empty(), "{m} on {scene}");
        }
        for m in ["zbuf", "scanline", "warnock", "painter", "painter-split"] {
            let depths: Vec<&str> = rows
                .iter()
                .filter(|r| r["scene"] == scene && r["method"] == m)
                .map(|r| r["depth"].as_str())
                .collect();
            assert_eq!(depths, ["0", "1", "2", "3", "4"], "{m} on {scene}");
        }
    }
    let p = find(&rows, "cyclic-bars", "painter", 0).expect("the painter on the cyclic bars");
    assert!(num(p, "error_fraction") > 0.0, "{p:?}");
    // Every row the table of methods marks exact draws 0 pixels unlike the reference, on
    // every scene at every depth (docs/methods.md, "The exact methods"); zbuf-eye-z,
    // not marked so, does not.
    let exact: Vec<&str> = methods::METHODS
        .iter()
        .filter(|m| m.exact)
        .map(|m| m.name)
        .collect();
    let mut seen = 0;
    for r in rows
        .iter()
        .filter(|r| exact.contains(&r["method"].as_str()))
    {
        assert_eq!(num(r, "error_fraction"), 0.0, "{r:?}");
        seen += 1;
    }
    assert!(seen >= 200, "{seen} rows of exact methods");
    assert!(rows
        .iter()
        .any(|r| r["method"] == "zbuf-eye-z" && num(r, "error_fraction") > 0.0));
    // Both hidden-line methods on every scene of the figures, standard and hard, at
    // depth 0 alone, each with its drawing counted and no pixel error.
    let mut scenes: Vec<&str> = rows.iter().map(|r| r["scene"].as_str()).collect();
    scenes.dedup();
    assert!(scenes.len() >= HARD.len() + 5, "{scenes:?}");
    for scene in &scenes {
        for m in ["hiddenline", "hiddenline-archuleta"] {
            let runs: Vec<_> = rows
                .iter()
                .filter(|r| r["scene"] == *scene && r["method"] == m)
                .collect();
            assert_eq!(runs.len(), 1, "{m} on {scene}");
            assert_eq!(runs[0]["depth"], "0");
            // No error against the scene's pictures: empty.
            assert_eq!(runs[0]["error_fraction"], "", "{:?}", runs[0]);
            // The stack's squares fill the screen: every edge lies on its border, and
            // neither method draws one. Every other scene has lines.
            let pieces = num(runs[0], "line_pieces");
            if *scene == "stack" {
                assert_eq!(pieces, 0.0, "{:?}", runs[0]);
            } else {
                assert!(pieces > 0.0, "{:?}", runs[0]);
            }
        }
    }
    // Every row has its time, start-up share and spread of five runs, and its RMS
    // against the 16×16 reference; the point-sampling rows their visibility error, the
    // hidden-line rows their line error. None is NaN.
    assert_every_measure(&rows, 5);
    for f in [
        "speed-accuracy.png",
        "speed-accuracy.svg",
        "visibility.png",
        "visibility.svg",
        "cost-environment.png",
        "cost-environment.svg",
        "hidden-lines.png",
        "model.png",
    ] {
        assert!(images.join(f).metadata().unwrap().len() > 0, "{f}");
    }
}

/// The two hidden-line methods (`render --hidden-line`, continuous and Archuleta's) are
/// charted on every scene at depth 0: timed, with no error against the scene's pictures
/// (they draw lines, not pixels) but an RMS error of their drawing's picture against the
/// exact drawing's, their drawings' pieces counted over every frame, the same count the
/// SVGs that render writes itself hold; on the figures, the cost one alone.
#[test]
fn the_hidden_line_methods_are_charted_on_every_scene() {
    let work = tempfile::tempdir().unwrap();
    let movie = work.path().join("movie.txt");
    let made = sh(
        &format!(
            "scene environment --text --seed 4 --polygons 60 --depth-complexity 1 \
             --size 120x90 --frames 3 > {}",
            movie.display()
        ),
        b"",
    );
    assert!(made.status.success(), "{made:?}");
    let dir = chart(&format!(
        "--reps 1 --methods zbuf,hiddenline,hiddenline-archuleta \
         examples/penetrating.txt@200x150 {}@120x90",
        movie.display()
    ));
    let d = dir.path();
    let (header, rows) = read_csv(&d.join("results.csv"));
    for c in ["line_pieces", "intersection_pieces", "line_length_px"] {
        assert!(header.iter().any(|h| h == c), "results.csv lacks {c}");
    }
    for (scene, size, frames) in [("penetrating", "200x150", 1), ("movie", "120x90", 3)] {
        for (method, how) in [
            ("hiddenline", "continuous"),
            ("hiddenline-archuleta", "archuleta"),
        ] {
            let runs: Vec<_> = rows
                .iter()
                .filter(|r| r["scene"] == scene && r["method"] == method)
                .collect();
            assert_eq!(runs.len(), 1, "{method} on {scene}: {runs:?}");
            let r = runs[0];
            assert_eq!((r["depth"].as_str(), r["size"].as_str()), ("0", size));
            assert_eq!(r["frames"], frames.to_string());
            assert!(num(r, "wall_s") > 0.0 && num(r, "cpu_s") > 0.0, "{r:?}");
            assert_eq!([&r["error_fraction"], &r["edge_rmse"]], ["", ""]);
            // Its drawing as a picture against the exact drawing's: the continuous
            // method's is it.
            let rms = num(r, "rms_16x16");
            assert!(rms.is_finite() && rms >= 0.0, "{r:?}");
            if method == "hiddenline" {
                assert_eq!(rms, 0.0, "{r:?}");
            }
            // Scored against the exact drawing: the continuous method is it.
            let e = num(r, "line_error_px");
            assert!(e.is_finite() && e >= 0.0, "{r:?}");
            if method == "hiddenline" {
                assert!(e < 1e-6, "{r:?}");
            }
            // The drawing render makes of the scene, frame by frame: as many lines.
            let input = if scene == "movie" {
                movie.display().to_string()
            } else {
                "examples/penetrating.txt".into()
            };
            let svgs = work.path().join(method);
            std::fs::create_dir_all(&svgs).unwrap();
            let out = sh(
                &format!(
                    "render --size {size} --hidden-line --hidden-line-method {how} \
                     -o {0}/f%d.svg {input}",
                    svgs.display()
                ),
                b"",
            );
            assert!(out.status.success(), "{out:?}");
            // Its pieces: a `<line>` each, or the dashes of one (an edge's pieces joined).
            let pieces: usize = std::fs::read_dir(&svgs)
                .unwrap()
                .map(|f| {
                    let text = std::fs::read_to_string(f.unwrap().path()).unwrap();
                    lines::read_svg(&text).unwrap().len()
                })
                .sum();
            assert_eq!(num(r, "line_pieces"), pieces as f64, "{r:?}");
            assert_eq!(std::fs::read_dir(&svgs).unwrap().count(), frames);
        }
        // The two agree on what they draw: the same length within 2% (Archuleta's ends
        // fall between the scan lines).
        let length = |m: &str| num(find(&rows, scene, m, 0).unwrap(), "line_length_px");
        let (c, a) = (length("hiddenline"), length("hiddenline-archuleta"));
        assert!(
            c > 100.0 && (a - c).abs() < 0.02 * c,
            "{scene}: {c} against {a}"
        );
    }
    // The penetrating scene's one line of intersection, drawn by both.
    for m in ["hiddenline", "hiddenline-archuleta"] {
        let r = find(&rows, "penetrating", m, 0).unwrap();
        assert_eq!(num(r, "intersection_pieces"), 1.0, "{r:?}");
    }
    // No hidden-line mark on the speed-accuracy panels; both on the cost figure.
    let svg = std::fs::read_to_string(d.join("speed-accuracy.svg")).unwrap();
    assert!(!svg.contains("hiddenline"));
    let cost = std::fs::read_to_string(d.join("cost-environment.svg")).unwrap();
    assert!(cost.contains("\nhiddenline-archuleta\n") && cost.contains("\nhiddenline\n"));
}

/// `chart hidden-lines` at a small scale: a row for each scene, size and hidden-line
/// method, the continuous drawing the reference (line error 0), Archuleta's scored
/// against it, no figure NaN, and the picture written.
#[test]
fn the_hidden_line_figure_scores_both_methods() {
    let out_dir = tempfile::tempdir().unwrap();
    let out = sh(
        &format!(
            "chart hidden-lines --sizes 64,128 --reps 1 -o {} --root {}",
            out_dir.path().display(),
            repo_root().display()
        ),
        b"",
    );
    assert!(out.status.success(), "{out:?}");
    let csv = std::fs::read_to_string(out_dir.path().join("hidden-lines.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("scene,size,method,seconds,line_error_px,missed_px,extra_px,reference_px,line_error_percent")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 4 * 2 * 2, "{csv}");
    for r in &rows {
        let nums: Vec<f64> = r[3..].iter().map(|v| v.parse().unwrap()).collect();
        assert!(nums.iter().all(|v| v.is_finite()), "{r:?}");
        if r[2] == "continuous" {
            assert_eq!(nums[1], 0.0, "{r:?}");
        }
        assert!(nums[4] > 0.0, "{r:?}: a drawing with length");
    }
    // Archuleta's counters at 64 scan lines miss somewhere.
    assert!(rows
        .iter()
        .any(|r| r[2] == "archuleta" && r[4].parse::<f64>().unwrap() > 0.0));
    assert!(out_dir.path().join("hidden-lines.png").exists());
}

/// `chart thesis --measure` at 0.1% of the thesis's sizes: the thesis's 5.1.3 table (E_t and
/// E_r of A, B and C, its HSE best and worst, clipping and the transformations) and ours
/// beside it, every stage timed, every hidden-surface method named.
#[test]
fn thesis_5_1_is_measured_beside_its_table() {
    let out = sh(
        &format!(
            "chart thesis --measure --scale 0.001 --root {}",
            repo_root().display()
        ),
        b"",
    );
    assert!(out.status.success(), "{out:?}");
    let text = String::from_utf8_lossy(&out.stdout);
    let lines: Vec<&str> = text.lines().collect();
    let at = |head: &str| {
        lines
            .iter()
            .position(|l| l.starts_with(head))
            .unwrap_or_else(|| panic!("no `{head}` in {text}"))
    };
    let thesis = at("thesis (units of time)");
    let words = |i: usize| lines[i].split_whitespace().collect::<Vec<_>>();
    assert_eq!(
        words(thesis + 2)[..8],
        ["A", "800", "400", "140K", "2.4B", "8K", "8K", "4K"]
    );
    assert_eq!(words(thesis + 3)[..3], ["B", "20K", "10K"]);
    assert_eq!(
        words(thesis + 4)[..8],
        ["C", "480K", "240K", "7.5M", "1500B", "4.8M", "4.8M", "2.4M"]
    );
    let ours = at("measured here");
    for (k, (name, polygons)) in [("A", 2u64), ("B", 5), ("C", 120)].iter().enumerate() {
        let w = words(ours + 2 + k);
        assert_eq!(w[0], *name, "{text}");
        let (et, er, p): (u64, u64, u64) = (
            w[1].parse().unwrap(),
            w[2].parse().unwrap(),
            w[3].parse().unwrap(),
        );
        // Four-sided polygons: E_t = 4·P_t; about half survive the clipper.
        assert_eq!((p, et), (*polygons, 4 * polygons), "{text}");
        if *name == "C" {
            assert!(
                (et as f64 * 0.3..=et as f64 * 0.7).contains(&(er as f64)),
                "{text}"
            );
        }
        // Every time a number, the best method and the worst named.
        for i in [5, 7, 9, 10, 11] {
            assert!(w[i].parse::<f64>().unwrap() >= 0.0, "{text}");
        }
    }
    for m in ["zbuf", "scanline", "warnock", "painter"] {
        assert!(text.contains(&format!("{m} ")), "{m} not timed: {text}");
    }
}
