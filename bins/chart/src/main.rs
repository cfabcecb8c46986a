//! chart: the command line of `scripts/chart.sh` and of `render.sh --depth auto`.

use anyhow::{bail, Context, Result};
use chart::chart::{Scene, Setup};
use chart::model::Constants;
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use proto::camera::parse_size;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

/// Charts speed against accuracy: runs every method and variant on each scene through
/// scripts/render.sh, measures it (wall and CPU seconds and peak memory of the whole
/// process tree; the frames' error against zspec and zspec --samples 16), and writes
/// DIR/results.csv, DIR/speed-accuracy.png and .svg, and DIR/model.csv and model.png: the
/// thesis's cost model (chapters 5.2 and 6.4) beside the measured times of zbuf at
/// depths 0-4.
#[derive(Parser, Debug)]
#[command(
    name = "chart",
    version,
    args_conflicts_with_subcommands = true,
    after_help = "Examples:\n  \
        scripts/chart.sh -o out examples/penetrating.txt\n  \
        scripts/chart.sh -o out --quick scene.txt fill.txt@1920x1080\n  \
        scripts/chart.sh -o out --standard            # the four scene classes and the failure scene\n  \
        scripts/chart.sh -o out --calibrate           # measure the model's constants: bench/model.toml\n  \
        chart choose-depth --size 1920x1080 fill.txt  # the depth render.sh --depth auto takes"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Sub>,
    /// The output folder (made if missing).
    #[arg(short = 'o', value_name = "DIR")]
    out: Option<PathBuf>,
    /// A small run: few methods and depths, one timing each; with --standard, small scenes.
    #[arg(long)]
    quick: bool,
    /// First measure the cost model's constants on this machine and write them to the
    /// model file (the repository's bench/model.toml unless --model).
    #[arg(long)]
    calibrate: bool,
    /// Chart the standard scenes: the four scene classes of scripts/bench.sh, made with
    /// `scene environment` into DIR/scenes, and examples/penetrating.txt.
    #[arg(long)]
    standard: bool,
    /// The screen for scenes without their own `@WxH`.
    #[arg(long, default_value = "500x500", value_parser = parse_size, value_name = "WxH")]
    size: (u32, u32),
    /// Timed runs of each row; the median is kept (default 3, or 1 with --quick).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=100))]
    reps: Option<u32>,
    /// The model's constants file (default: the repository's bench/model.toml).
    #[arg(long, value_name = "FILE")]
    model: Option<PathBuf>,
    /// Only these methods, by the names results.csv gives them (`--methods zbuf` measures
    /// what model.csv needs and no more).
    #[arg(long, value_delimiter = ',', value_name = "NAME,…", value_parser = method_name)]
    methods: Option<Vec<String>>,
    /// Only draw the pictures again from DIR/results.csv and DIR/model.csv.
    #[arg(long)]
    replot: bool,
    /// Only predict again: DIR/model.csv's measured times kept, its predictions made
    /// anew from the model file and a look at the scenes (the same SCENEs, or
    /// --standard, as the run that wrote it), and model.png drawn again.
    #[arg(long, conflicts_with_all = ["replot", "calibrate"])]
    remodel: bool,
    /// The repository (scripts/render.sh, bench/); chart.sh gives it.
    #[arg(long, value_name = "DIR")]
    root: Option<PathBuf>,
    /// Scenes, each `PATH` or `PATH@WxH`.
    scenes: Vec<String>,
}

#[derive(Subcommand, Debug)]
enum Sub {
    /// Prints the splitter tree depth the cost model predicts is fastest for a scene on
    /// this machine, and why, as one line `N (reason)`. It looks at the scene's first 512
    /// KiB through the geometry viewxf, clipplane and persp share (proto's), in this
    /// process, and scales what it saw to the whole file: polygons in view, screen, depth
    /// complexity.
    #[command(
        name = "choose-depth",
        after_help = "Example:\n  chart choose-depth --size 1920x1080 --cores 2 fill.txt\n  \
                      2 (10000 polygons in view, Dc 9.8, …)"
    )]
    ChooseDepth {
        /// The screen size, as render.sh's --size.
        #[arg(long, default_value = "500x500", value_parser = parse_size, value_name = "WxH")]
        size: (u32, u32),
        /// Cores to plan for (default: this machine's).
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..=4096))]
        cores: Option<u32>,
        /// The deepest tree to consider.
        #[arg(long, default_value_t = 6, value_parser = clap::value_parser!(u8).range(0..=6))]
        max_depth: u8,
        /// The model's constants file (default: the repository's bench/model.toml, else
        /// the constants built in).
        #[arg(long, value_name = "FILE")]
        model: Option<PathBuf>,
        /// The repository, for bench/model.toml.
        #[arg(long, value_name = "DIR")]
        root: Option<PathBuf>,
        /// viewxf's camera options, as render.sh was given them, e.g. `--eye 10,10,20`.
        #[arg(long = "eye", value_name = "X,Y,Z", allow_hyphen_values = true)]
        eye: Option<String>,
        #[arg(long = "at", value_name = "X,Y,Z", allow_hyphen_values = true)]
        at: Option<String>,
        #[arg(long = "up", value_name = "X,Y,Z", allow_hyphen_values = true)]
        up: Option<String>,
        #[arg(long = "s", value_name = "S", allow_hyphen_values = true)]
        s: Option<String>,
        #[arg(long = "d", value_name = "D", allow_hyphen_values = true)]
        d: Option<String>,
        #[arg(long = "hither", value_name = "K1", allow_hyphen_values = true)]
        hither: Option<String>,
        #[arg(long = "yon", value_name = "K2", allow_hyphen_values = true)]
        yon: Option<String>,
        /// The scene (a file: it is read here and again by the render).
        scene: PathBuf,
    },
}

/// The built binaries: beside this one.
fn bin_dir() -> Result<PathBuf> {
    let exe = std::env::current_exe().context("where chart is")?;
    Ok(exe.parent().context("chart's folder")?.to_path_buf())
}

/// The repository: --root, else two folders up from target/release, else here.
fn root_dir(root: Option<PathBuf>) -> Result<PathBuf> {
    if let Some(r) = root {
        return Ok(r);
    }
    let bin = bin_dir()?;
    for up in bin.ancestors() {
        if up.join("scripts/render.sh").is_file() {
            return Ok(up.to_path_buf());
        }
    }
    Ok(std::env::current_dir()?)
}

fn load_constants(model: Option<&Path>, root: &Path) -> Result<Constants> {
    let path = model
        .map(Path::to_path_buf)
        .unwrap_or_else(|| root.join("bench/model.toml"));
    match std::fs::read_to_string(&path) {
        Ok(text) => Constants::parse(&text).with_context(|| format!("reading {}", path.display())),
        Err(_) if model.is_none() => Ok(Constants::committed()),
        Err(e) => Err(e).with_context(|| format!("cannot read {}", path.display())),
    }
}

fn bar(len: u64) -> ProgressBar {
    let bar = ProgressBar::new(len);
    if let Ok(style) = ProgressStyle::with_template("{bar:30} {pos}/{len} [{elapsed}] {msg}") {
        bar.set_style(style);
    }
    bar
}

/// A scene class: name, seed, polygons, depth complexity, screen, frames.
type Class = (&'static str, u64, u64, f64, (u32, u32), u64);

/// The standard scenes (scripts/bench.sh's four classes, and the failure scene).
fn standard_scenes(bin: &Path, root: &Path, dir: &Path, quick: bool) -> Result<Vec<Scene>> {
    std::fs::create_dir_all(dir)?;
    let (geo, fill, fill_size, movie) = if quick {
        (20_000, 2_000, (960, 540), 20)
    } else {
        (100_000, 10_000, (1920, 1080), 100)
    };
    let specs: [Class; 4] = [
        ("a-1024-quads", 1, 1024, 1.0, (500, 500), 1),
        ("b-geometry", 3, geo, 2.0, (500, 500), 1),
        ("c-fill", 2, fill, 10.0, fill_size, 1),
        ("d-movie", 4, 1024, 1.0, (500, 500), movie),
    ];
    let mut scenes = Vec::new();
    for (name, seed, polygons, dc, (w, h), frames) in specs {
        let path = dir.join(format!("{name}.txt"));
        if !path.exists() {
            let status = Command::new(bin.join("scene"))
                .args(["environment", "--text", "--seed", &seed.to_string()])
                .args(["--polygons", &polygons.to_string()])
                .args(["--depth-complexity", &dc.to_string()])
                .args([
                    "--size",
                    &format!("{w}x{h}"),
                    "--frames",
                    &frames.to_string(),
                ])
                .stdout(std::fs::File::create(&path)?)
                .status()?;
            if !status.success() {
                let _ = std::fs::remove_file(&path);
                bail!("scene environment failed for {name}");
            }
        }
        scenes.push(Scene {
            path,
            name: name.into(),
            width: w,
            height: h,
        });
    }
    scenes.push(Scene::parse(
        &root.join("examples/penetrating.txt").to_string_lossy(),
        (500, 500),
    )?);
    Ok(scenes)
}

fn run(cli: Cli) -> Result<()> {
    let Some(out) = cli.out else {
        return Err(stagecli::Error::usage(
            "-o DIR is needed (where the CSV files and pictures go)",
        )
        .into());
    };
    // The scene arguments first: a bad `@WxH` is a usage error, said before anything is
    // made or read.
    let mut scenes: Vec<Scene> = cli
        .scenes
        .iter()
        .map(|s| Scene::parse(s, cli.size))
        .collect::<Result<_>>()?;
    if scenes.is_empty() && !(cli.standard || cli.calibrate || cli.replot) {
        return Err(stagecli::Error::usage("no SCENE given (or --standard)").into());
    }
    // Each scene opened and its first bytes read before anything is made or run, so that
    // one that cannot be read is said at once, in the stages' words (`cannot open PATH: …`).
    for s in &scenes {
        chart::look::is_text(&s.path)?;
    }
    let root = root_dir(cli.root)?;
    let bin = bin_dir()?;
    let render = root.join("scripts/render.sh");
    std::fs::create_dir_all(&out).with_context(|| format!("cannot make {}", out.display()))?;
    if cli.replot {
        let rows: Vec<chart::chart::Row> = chart::chart::read_csv(&out.join("results.csv"))?;
        let model_rows: Vec<chart::chart::ModelRow> =
            chart::chart::read_csv(&out.join("model.csv"))?;
        chart::plot::speed_accuracy(&out, &rows)?;
        return chart::plot::model(&out, &model_rows);
    }
    let model_path = cli
        .model
        .clone()
        .unwrap_or_else(|| root.join("bench/model.toml"));
    let cores = chart::calibrate::cores();
    if cli.standard {
        scenes.extend(standard_scenes(
            &bin,
            &root,
            &out.join("scenes"),
            cli.quick,
        )?);
    }
    if cli.remodel {
        return remodel(&out, &scenes, cli.model.as_deref(), &root, cores);
    }
    if cli.calibrate {
        let work = out.join("calibration");
        std::fs::create_dir_all(&work)?;
        let grid = chart::calibrate::grid(cli.quick).len() as u64;
        let progress = bar(grid + 1);
        progress.set_message("calibrating");
        let mut first = true;
        let k = chart::calibrate::calibrate(&bin, &render, &work, cli.quick, |what| {
            if !first {
                progress.inc(1);
            }
            first = false;
            progress.set_message(format!("calibrating: {what}"));
        })?;
        progress.finish_and_clear();
        let _ = std::fs::remove_dir_all(&work);
        let text = format!(
            "# The cost model's constants (bins/chart/src/model.rs), seconds, measured by\n\
             # `scripts/chart.sh --calibrate{}`: each stage binary alone on synthetic scenes,\n\
             # least squares. Read by chart's model.csv and `chart choose-depth`.\n{}",
            if cli.quick { " --quick" } else { "" },
            k.to_toml()?
        );
        std::fs::write(&model_path, text)
            .with_context(|| format!("cannot write {}", model_path.display()))?;
        say_err(&format!("chart: wrote {}", model_path.display()));
        let mut table = String::new();
        for (name, cost) in [
            ("viewxf (text)", k.viewxf_text),
            ("viewxf (binary)", k.viewxf_binary),
            ("clip", k.clip),
            ("splitter", k.splitter),
            ("persp", k.persp),
            ("hse", k.hse),
            ("merge", k.merge),
            ("resolve (depth 0)", k.resolve),
        ] {
            table += &format!("{name:16} {cost:?}\n");
        }
        table += &format!("overheads        {:?}\n", k.overheads);
        say(&table)?;
        if scenes.is_empty() {
            return Ok(());
        }
    }
    let constants = load_constants(cli.model.as_deref(), &root)?;
    let setup = Setup {
        bin,
        render,
        out: out.clone(),
        quick: cli.quick,
        only: cli.methods.clone(),
        reps: cli
            .reps
            .map_or(if cli.quick { 1 } else { 3 }, |r| r as usize),
        cores,
        constants,
    };
    let total = scenes.len() as u64
        * (chart::methods::runs(cli.quick, cli.methods.as_deref()).len() as u64 + 1);
    let progress = bar(total);
    let mut first = true;
    let (rows, model_rows) = chart::chart::chart(&setup, &scenes, |what| {
        if !first {
            progress.inc(1);
        }
        first = false;
        progress.set_message(what.to_string());
    })?;
    progress.finish_and_clear();
    chart::chart::write_csv(&out.join("results.csv"), &rows)?;
    chart::chart::write_csv(&out.join("model.csv"), &model_rows)?;
    chart::plot::speed_accuracy(&out, &rows)?;
    chart::plot::model(&out, &model_rows)?;
    say(&model_table(&model_rows))?;
    say_err(&format!(
        "chart: wrote {0}/results.csv, {0}/speed-accuracy.png, {0}/speed-accuracy.svg, {0}/model.csv, {0}/model.png",
        out.display()
    ));
    Ok(())
}

/// `--remodel`: the predictions of `DIR/model.csv` made again beside its measurements.
fn remodel(
    out: &Path,
    scenes: &[Scene],
    model: Option<&Path>,
    root: &Path,
    cores: usize,
) -> Result<()> {
    let k = load_constants(model, root)?;
    let path = out.join("model.csv");
    let old: Vec<chart::chart::ModelRow> = chart::chart::read_csv(&path)?;
    let mut rows = Vec::with_capacity(old.len());
    for scene in scenes {
        let env = chart::look::look(&scene.path, scene.width, scene.height, &[], None)?;
        for r in old.iter().filter(|r| r.scene == scene.name) {
            rows.push(chart::chart::model_row(
                &k,
                &env,
                &scene.name,
                r.depth,
                cores,
                r.measured_s,
            ));
        }
    }
    if rows.len() != old.len() {
        bail!(
            "{} has rows of scenes not given ({} of {} matched): give the same scenes as the run that wrote it",
            path.display(),
            rows.len(),
            old.len()
        );
    }
    chart::chart::write_csv(&path, &rows)?;
    chart::plot::model(out, &rows)?;
    say(&model_table(&rows))
}

/// Writes `text` to stdout as the stages do ([`stagecli::stdout`]): the reader going
/// away (`| head`) ends chart quietly with 0, a failed write is `stdout: reason`, 3.
/// (println! would panic on either.)
fn say(text: &str) -> Result<()> {
    stagecli::stdout()
        .write_all(text.as_bytes())
        .map_err(stagecli::Error::from)?;
    Ok(())
}

/// A line to stderr, for the person watching: if stderr is gone there is no one to tell,
/// and the run goes on (eprintln! would panic).
fn say_err(line: &str) {
    let _ = writeln!(std::io::stderr(), "{line}");
}

/// The model's rows as a markdown table, and the mean |error|.
fn model_table(rows: &[chart::chart::ModelRow]) -> String {
    let mut t = String::from("| scene | depth | predicted s | measured s | error | bottleneck |\n");
    t += "|---|---|---|---|---|---|\n";
    for r in rows {
        t += &format!(
            "| {} | {} | {:.3} | {:.3} | {:+.0}% | {} |\n",
            r.scene,
            r.depth,
            r.predicted_s,
            r.measured_s,
            r.error * 100.0,
            r.bottleneck
        );
    }
    let mean = rows.iter().map(|r| r.error.abs()).sum::<f64>() / rows.len().max(1) as f64;
    t += &format!(
        "\nmean |error| {:.1}% over {} rows\n",
        mean * 100.0,
        rows.len()
    );
    t
}

#[allow(clippy::too_many_arguments)]
fn choose_depth(
    size: (u32, u32),
    cores: Option<u32>,
    max_depth: u8,
    model: Option<PathBuf>,
    root: Option<PathBuf>,
    camera: Vec<String>,
    scene: PathBuf,
) -> Result<()> {
    let root = root_dir(root)?;
    let k = load_constants(model.as_deref(), &root)?;
    let env = chart::look::look(
        &scene,
        size.0,
        size.1,
        &camera,
        Some(chart::look::SAMPLE_BYTES),
    )?;
    let cores = cores.map_or_else(chart::calibrate::cores, |c| c as usize);
    let (depth, reason, _) = chart::model::choose_depth(&k, &env, cores, max_depth);
    say(&format!("{depth} ({reason})\n"))
}

/// A method's name, one of the chart's.
fn method_name(s: &str) -> Result<String, String> {
    match chart::methods::by_name(s) {
        Some(m) => Ok(m.name.to_string()),
        None => Err(format!(
            "no method {s}; the methods: {}",
            chart::methods::METHODS
                .iter()
                .map(|m| m.name)
                .collect::<Vec<_>>()
                .join(", ")
        )),
    }
}

/// Through stagecli, as every stage: a usage error is one line `chart: …` and 2, and
/// any other error one line and its kind's status (0 quietly when the reader went away).
fn main() -> ExitCode {
    stagecli::main::<Cli>("chart", |cli| {
        dispatch(cli).map_err(|e| chart::error::stage_error(&e))
    })
}

fn dispatch(cli: Cli) -> Result<()> {
    match cli.command {
        Some(Sub::ChooseDepth {
            size,
            cores,
            max_depth,
            model,
            root,
            eye,
            at,
            up,
            s,
            d,
            hither,
            yon,
            scene,
        }) => {
            let mut camera = Vec::new();
            for (opt, v) in [
                ("--eye", eye),
                ("--at", at),
                ("--up", up),
                ("--s", s),
                ("--d", d),
                ("--hither", hither),
                ("--yon", yon),
            ] {
                if let Some(v) = v {
                    // One word, so that a value with a leading minus stays a value.
                    camera.push(format!("{opt}={v}"));
                }
            }
            choose_depth(size, cores, max_depth, model, root, camera, scene)
        }
        None => run(cli),
    }
}
