//! The `bench` binary: each subcommand at a tiny size (`--quick --reps 1`) prints its
//! tables, headers and rows as the benchmark scripts printed them; a bad option is a
//! usage error.

use assert_cmd::Command;
use pipeline_tests::bin_dir;

/// `bench ARGS`: its stdout, after asserting it succeeded.
fn bench(args: &[&str]) -> String {
    let out = Command::new(bin_dir().join("bench"))
        .args(args)
        .timeout(std::time::Duration::from_secs(600))
        .output()
        .unwrap();
    assert!(out.status.success(), "bench {args:?}: {out:?}");
    String::from_utf8(out.stdout).unwrap()
}

/// The rows of the markdown table whose header is `header`: each row's cells.
fn table(text: &str, header: &str) -> Vec<Vec<String>> {
    let mut lines = text.lines().skip_while(|l| *l != header);
    assert_eq!(lines.next(), Some(header), "no table {header} in:\n{text}");
    let rule = lines.next().unwrap_or_default();
    let cells = header.matches('|').count() - 1 - header.matches("\\|").count();
    assert_eq!(rule, "|---".repeat(cells) + "|");
    lines
        .take_while(|l| l.starts_with('|'))
        .map(|l| {
            let l = l.replace("\\|", "\u{1}");
            l[1..l.len() - 1]
                .split('|')
                .map(|c| c.trim().replace('\u{1}', "\\|"))
                .collect()
        })
        .collect()
}

/// A figure of a cell: seconds or a count.
fn number(cell: &str) -> f64 {
    cell.trim_matches('*')
        .parse()
        .unwrap_or_else(|_| panic!("not a number: {cell}"))
}

#[test]
fn tree_pipeline_prints_the_linear_accuracy_and_memory_tables() {
    let out = bench(&["tree", "pipeline", "--quick", "--reps", "1", "1", "4", "5"]);
    let linear = table(&out, "| scene | wall s |");
    assert_eq!(linear.len(), 1);
    assert_eq!(linear[0][0], "environment 1000 polygons, Dc 10");
    assert!(number(&linear[0][1]) > 0.0);
    let accuracy = table(
        &out,
        "| scene | pixels | projective depth | eye-z depth (occam) |",
    );
    let scenes: Vec<&str> = accuracy.iter().map(|r| r[0].as_str()).collect();
    assert_eq!(
        scenes,
        [
            "penetrating",
            "spheres",
            "triangle-square",
            "environment 1000, Dc 3",
            "environment 100000, Dc 10"
        ]
    );
    assert!(accuracy.iter().all(|r| r[1] == "250000"), "{accuracy:?}");
    let memory = table(&out, "| stage | 100 polygons | 10000 polygons |");
    let stages: Vec<&str> = memory.iter().map(|r| r[0].as_str()).collect();
    assert_eq!(
        stages,
        [
            "scene",
            "viewxf",
            "clipplane left",
            "splitter x=0",
            "persp",
            "scanconv",
            "zbuf",
            "zspec"
        ]
    );
    assert!(memory
        .iter()
        .all(|r| number(&r[1]) > 100.0 && number(&r[2]) > 100.0));
    assert!(!out.contains("## 2."), "sections not asked for ran:\n{out}");
}

#[test]
fn tree_merge_prints_the_leaves_and_the_merger_by_depth_and_mode() {
    let out = bench(&["tree", "merge", "--quick", "--reps", "1", "2"]);
    let rows = table(
        &out,
        "| depth | mode | slowest leaf scanconv s | largest leaf scanconv KiB | zbuf s | zbuf KiB \
         | bytes to zbuf |",
    );
    let keys: Vec<String> = rows.iter().map(|r| format!("{} {}", r[0], r[1])).collect();
    let want: Vec<String> = (0..=4)
        .flat_map(|d| [format!("{d} tiles"), format!("{d} buffer")])
        .collect();
    assert_eq!(keys, want);
    assert!(rows.iter().all(|r| number(&r[6]) > 0.0), "{rows:?}");
}

#[test]
fn tree_depth_auto_and_plan_print_auto_against_the_fixed_depths() {
    let out = bench(&["tree", "depth-auto", "--quick", "--reps", "1"]);
    let rows = table(
        &out,
        "| fill scene, cores | | depth 0 | 1 | 2 | 3 | auto | best | auto / best | auto chose |",
    );
    assert_eq!(rows.len(), 4, "{out}");
    assert_eq!(rows[0][0], "`taskset -c 0`");
    assert_eq!(rows[1][1], "CPU s");
    let start = table(
        &out,
        "| two polygons, 64×64 | render | viewxf \\| clipbatch \\| persp \\| zbuf | render / by hand |",
    );
    assert_eq!(start.len(), 2);
    let out = bench(&["tree", "plan", "--quick", "--reps", "1"]);
    let levels = table(
        &out,
        "| level | nodes | polygons in view read, all nodes (measured) | largest node | model, each node |",
    );
    let nodes: Vec<&str> = levels.iter().map(|r| r[1].as_str()).collect();
    assert_eq!(nodes, ["2", "4", "8"]);
    // Every level read polygons, and the model's share of the polygons in view halves
    // with each level (read from `plan predict`'s line).
    let model: Vec<u64> = levels.iter().map(|r| r[4].parse().unwrap()).collect();
    assert!(
        levels.iter().all(|r| r[2].parse::<u64>().unwrap() > 0) && model[0] > 0,
        "{out}"
    );
    assert_eq!(model[1], model[0] / 2, "{out}");
    assert!(
        out.contains("live source: the first frame came out "),
        "{out}"
    );
}

#[test]
fn a_mode_bench_tree_does_not_know_is_a_usage_error() {
    let out = Command::new(bin_dir().join("bench"))
        .args(["tree", "forest"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    assert!(String::from_utf8_lossy(&out.stderr).contains("invalid value 'forest'"));
}

/// The first column of a table's rows.
fn firsts(rows: &[Vec<String>]) -> Vec<&str> {
    rows.iter().map(|r| r[0].as_str()).collect()
}

#[test]
fn stages_geometry_clip_fused_and_shading_print_their_tables() {
    let out = bench(&["stages", "geometry", "--polygons", "2000", "--reps", "1"]);
    let names: Vec<&str> = out
        .lines()
        .skip_while(|l| !l.starts_with("stage "))
        .skip(1)
        .map(|l| l.split("  ").next().unwrap().trim())
        .collect();
    assert_eq!(
        names,
        [
            "viewxf",
            "clipplane left",
            "clipplane right",
            "clipplane top",
            "clipplane bottom",
            "clipplane hither",
            "clipplane yon",
            "splitter x=0",
            "persp",
            "persp eye-z",
            "chain (8 procs)"
        ],
        "{out}"
    );
    let out = bench(&["stages", "clip", "--polygons", "2000", "--reps", "1"]);
    assert!(
        out.contains("| scene       | clipper                  |   wall |"),
        "{out}"
    );
    assert_eq!(out.matches("| cut-heavy   |").count(), 4, "{out}");
    let out = bench(&["stages", "fused", "--quick", "--reps", "1"]);
    let rows = table(
        &out,
        "| scene | form | run | wall s | cpu s | wall ÷ fused | cpu ÷ fused |",
    );
    assert_eq!(rows.len(), 20, "{out}");
    assert_eq!(rows[3][2], "fused");
    assert_eq!(rows[3][5], "1.00");
    let out = bench(&["stages", "shading", "--quick", "--reps", "1"]);
    let rows = table(
        &out,
        "| shading | zbuf CPU ms | ratio | render --depth 0 CPU ms | ratio | error against Phong, 1152 polygons | the same, 288 polygons |",
    );
    assert_eq!(firsts(&rows), ["flat", "gouraud", "phong"]);
    assert_eq!(rows[2][5], "0.00 / 0", "Phong against itself: {out}");
}

#[test]
fn llvmpipe_compares_render_with_llvmpipe_fused_and_its_depths() {
    let out = bench(&["llvmpipe", "--quick", "--reps", "1"]);
    let rows = table(
        &out,
        "| A against B | scene | A s | B s | A/B | by rounds | pictures |",
    );
    assert!(rows.len() >= 20, "{out}");
    let depth = rows
        .iter()
        .find(|r| r[0] == "depth 2 against depth 0, `--merge tiles`")
        .unwrap_or_else(|| panic!("{out}"));
    assert_eq!(depth[1], "(c) 2,000 quads, Dc≈10, 960×540");
    assert_eq!(depth[6], "identical to tiles depth 0");
    let work = table(&out, "| depth | CPU s | against depth 0 | by rounds |");
    assert_eq!(firsts(&work), ["0", "1", "2", "3", "4"]);
    assert_eq!(work[0][2], "**1.00**");
}

#[test]
fn bench_scanline_prints_a_row_per_scene() {
    let out = bench(&["scanline", "--quick", "1"]);
    let rows = table(
        &out,
        "| K | polygons a frame | segments/line | sample spans/line | depth comparisons/line | crossings/line | scanline s | z-buffer s | ratio |",
    );
    assert_eq!(firsts(&rows), ["1", "16", "64", "512"]);
}

#[test]
fn bench_painter_prints_a_row_per_scene_and_method() {
    let out = bench(&["painter", "--quick"]);
    let rows = table(
        &out,
        "| scene | method | wall s | peak KiB | pixels ≠ zbuf | cycles | painted out of order |",
    );
    assert_eq!(rows.len(), 16, "{out}");
    assert_eq!(rows[0][..2], ["penetrating", "scanconv --resolve"]);
}

#[test]
fn bench_aa_table_prints_the_error_table() {
    let out = bench(&["aa-table", "--size", "32x24"]);
    let mut lines = out.lines();
    assert_eq!(
        lines.next(),
        Some("against zspec --samples 16, 32x24, tree depth 0")
    );
    assert_eq!(
        lines.next(),
        Some("scene        method edge_rmse      rmse  differing")
    );
    assert!(out.contains("\nenvironment  point  "), "{out}");
}

#[test]
fn bench_warnock_prints_a_row_per_scene() {
    let out = bench(&["warnock", "--quick", "--size", "100x100"]);
    let rows = table(
        &out,
        "| scene | polygons | visible edges | zbuf s | warnock s | hiddenline s | zbuf KiB | warnock KiB | hiddenline KiB | windows | pixel windows | looked at | pixels ≠ zbuf |",
    );
    assert_eq!(rows.len(), 14, "{out}");
    assert_eq!(rows[0][..2], ["stack-100", "100"]);
}

#[test]
fn bench_bounds_prints_the_planes_table() {
    let out = bench(&["bounds", "--quick"]);
    let rows = table(
        &out,
        "| scene planes N, 500x500 | pixels unlike the z-buffer | share | painter --split said it could not order | within 0.5% or said |",
    );
    assert_eq!(firsts(&rows), ["5", "50", "400"]);
}

#[test]
fn bench_methods_prints_each_method_s_best_depth() {
    let out = bench(&["methods", "--quick"]);
    let rows = table(
        &out,
        "| scene | method | depth 0 s | best depth | best s | best / zbuf best |",
    );
    assert_eq!(rows.len(), 4 * methods::hse_names(methods::METHODS).len());
}

#[test]
fn bench_aa_prints_a_row_per_leaf() {
    let out = bench(&["aa", "--quick", "--polygons", "500", "--size", "160x120"]);
    let rows = table(
        &out,
        "| method | leaf | wall s | CPU s | peak KiB | output bytes |",
    );
    assert_eq!(rows[0][..2], ["point", "`scanconv --resolve`"]);
    assert_eq!(rows.len(), methods::aa_names(methods::METHODS).len() + 1);
}

#[test]
fn bench_adaptive_prints_render_and_the_leaf() {
    let small = [
        "adaptive",
        "--quick",
        "--polygons",
        "100",
        "--size",
        "100x100",
    ];
    let out = bench(&small);
    let rows = table(&out, "| what | ss4 CPU s | adaptive4 CPU s | ratio |");
    assert_eq!(firsts(&rows), ["render", "leaf", "method (in-process)"]);
    // The method alone, timed in bench's own process: seconds, each a time taken.
    let method: Vec<f64> = rows[2][1..3].iter().map(|c| c.parse().unwrap()).collect();
    assert!(method.iter().all(|&s| s > 0.0 && s < 1.0), "{out}");
    assert!(out.contains("adaptive4's frame against ss4's: "), "{out}");
    // The shell's own start, measured alone, and the leaves' ratio less it.
    assert!(
        out.contains("Each figure counts the start of the shell that runs it ("),
        "{out}"
    );
    assert!(
        out.contains(" ms of CPU alone); the leaves less it: "),
        "{out}"
    );
    assert!(!out.contains("in the same rounds"), "{out}");
    // --before DIR: that build's render timed in the same rounds (here this build's own).
    let dir = bin_dir().display().to_string();
    let out = bench(&[&small[..], &["--before", &dir]].concat());
    assert!(
        out.contains(&format!("The render of {dir} in the same rounds:")),
        "{out}"
    );
    let rows = table(&out, "| render | before CPU s | now CPU s | now / before |");
    assert_eq!(firsts(&rows), ["ss4", "adaptive4"]);
}

/// Every subcommand prints its usage for --help, and refuses an option it does not know
/// with status 2 and one line naming it.
#[test]
fn every_subcommand_says_its_usage_and_refuses_an_unknown_option() {
    for sub in [
        "llvmpipe", "tree", "stages", "methods", "scanline", "painter", "warnock", "bounds", "aa",
        "aa-table", "adaptive",
    ] {
        let out = Command::new(bin_dir().join("bench"))
            .args([sub, "--help"])
            .output()
            .unwrap();
        assert!(out.status.success(), "{sub} --help: {out:?}");
        let help = String::from_utf8_lossy(&out.stdout);
        assert!(
            help.contains(&format!("Usage: bench {sub} ")),
            "{sub}: {help}"
        );
        let out = Command::new(bin_dir().join("bench"))
            .args([sub, "--fast"])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{sub} --fast: {out:?}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr),
            "bench: unexpected argument '--fast' found\n"
        );
    }
}
