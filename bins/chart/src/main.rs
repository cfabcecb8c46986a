//! chart: the command line of `scripts/chart.sh` and of `render.sh --depth auto`.

use chart::chart::{Scene, Setup};
use chart::error::{Context, Error, Result};
use chart::model::Constants;
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
// The built binaries (beside this one) and the repository, found as plan finds them.
use proto::camera::parse_size;
use stagecli::place::{bin_dir, root_dir};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

/// Charts speed against accuracy: runs every method and variant on each scene through
/// scripts/render.sh, measures it (wall and CPU seconds and peak memory of the whole
/// process tree; the frames' error against zspec and zspec --samples 16), and writes
/// DIR/results.csv, DIR/speed-accuracy.png and .svg (each panel marking what `render
/// --max-error E` would choose for E of 0, 1, 4 and 16, also in DIR/max-error.csv), and
/// DIR/model.csv and model.png: the thesis's cost model (chapters 5.2 and 6.4) beside the
/// measured times of zbuf at depths 0-4.
#[derive(Parser, Debug)]
#[command(
    name = "chart",
    version,
    args_conflicts_with_subcommands = true,
    after_help = "Examples:\n  \
        scripts/chart.sh -o out examples/penetrating.txt\n  \
        scripts/chart.sh -o out --quick scene.txt fill.txt@1920x1080\n  \
        scripts/chart.sh -o out --standard            # the four scene classes and the failure scene\n  \
        scripts/chart.sh --figures                    # docs/images: standard and hard scenes\n  \
        scripts/chart.sh -o out --calibrate           # measure the model's constants: bench/model.toml\n  \
        plan depth --size 1920x1080 fill.txt          # the depth render.sh --depth auto takes"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Sub>,
    /// The output folder (made if missing).
    #[arg(short = 'o', value_name = "DIR")]
    out: Option<PathBuf>,
    /// A small run: few methods and depths, one timing each; with --standard or --hard,
    /// small scenes.
    #[arg(long)]
    quick: bool,
    /// First measure the cost model's constants on this machine and write them to the
    /// model file (the repository's bench/model.toml unless --model).
    #[arg(long)]
    calibrate: bool,
    /// Chart the standard scenes: the four scene classes of bench llvmpipe, made with
    /// `scene environment` into DIR/scenes, and examples/penetrating.txt.
    #[arg(long)]
    standard: bool,
    /// Chart the seeds' hard cases as well, made with `scene` into the --work folder's
    /// scenes/: a stack of 300 squares (100×100), 1,000 slivers (250×250), 100 crossing
    /// planes (160×160), examples/cyclic-bars.txt, two interpenetrating spheres and 2,100
    /// strips (500×500); with --quick, 100 squares (50×50), 200 slivers (125×125) and 20
    /// planes (80×80).
    #[arg(long)]
    hard: bool,
    /// The figures of docs/images, at this commit: --standard (its small scenes, every
    /// method at every depth), --hard and `chart hidden-lines`, written to the repository's docs/images (or
    /// -o DIR), the scenes, references, frames and the cost model's files kept in
    /// target/chart.
    #[arg(long)]
    figures: bool,
    /// Where the scenes, references and frames go (default: DIR).
    #[arg(long, value_name = "DIR")]
    work: Option<PathBuf>,
    /// The screen for scenes without their own `@WxH`.
    #[arg(long, default_value = "500x500", value_parser = parse_size, value_name = "WxH")]
    size: (u32, u32),
    /// Timed runs of each row, interleaved with the scene's other rows, each followed by
    /// the same render of an empty scene (its start-up); the median, least and most are
    /// kept (default 5, or 1 with --quick).
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
    /// `plan depth` under its old name, kept for scripts and hidden from the list: the
    /// splitter tree depth the cost model predicts fastest for a scene on this machine,
    /// and why, as one line `N (reason; rule: …)`. The name to use is `plan depth`.
    #[command(
        name = "choose-depth",
        hide = true,
        after_help = "Example:\n  plan depth --size 1920x1080 --cores 2 fill.txt\n  \
                      1 (10000 polygons in view, Dc 9.8, …; rule: …)"
    )]
    ChooseDepth(Box<costmodel::cli::DepthArgs>),
    /// Fits the cost model's constants on this machine now (at most 20 s) and keeps them
    /// in ${XDG_CACHE_HOME:-$HOME/.cache}/polypipe/model.toml, where `render.sh --depth
    /// auto` and the chart read them; prints them.
    Calibrate {
        /// A small fit (four small scenes, about two seconds): for tests.
        #[arg(long)]
        quick: bool,
        /// Also write the constants to FILE (`--model bench/model.toml`: the repository's
        /// fallback and example).
        #[arg(long, value_name = "FILE")]
        model: Option<PathBuf>,
        /// The repository (scripts/render.sh); chart.sh gives it.
        #[arg(long, value_name = "DIR")]
        root: Option<PathBuf>,
    },
    /// Thesis 5.2's stage timings on its T424-20 from its own constants, beside its
    /// figures, and 6.4's depth (5), through the model code `--depth auto` uses. With
    /// --measure, 5.1.3's table too: environments A, B and C built with its E_t and E_r
    /// (800/400, 20K/10K, 480K/240K) and viewing, clipping, perspective and every
    /// hidden-surface method timed on them here (CPU seconds a frame, one core), beside
    /// the thesis's figures.
    Thesis {
        /// Build and time environments A, B and C (5.1.3).
        #[arg(long)]
        measure: bool,
        /// The environments at this fraction of the thesis's sizes (for a quick look).
        #[arg(long, default_value_t = 1.0, value_name = "F")]
        scale: f64,
        /// The repository; chart.sh gives it.
        #[arg(long, value_name = "DIR")]
        root: Option<PathBuf>,
    },
    /// The hidden-line figure: `hiddenline --method continuous` and `archuleta` on four
    /// scenes at several sizes, each drawing's line error against the continuous one
    /// (lines::line_error: length missed plus length drawn not on it, 0.5 px reach) and
    /// its time; writes DIR/hidden-lines.csv and DIR/hidden-lines.png (DIR: the
    /// repository's docs/images unless -o).
    #[command(name = "hidden-lines")]
    HiddenLines {
        /// The output folder.
        #[arg(short = 'o', value_name = "DIR")]
        out: Option<PathBuf>,
        /// The square screen sizes.
        #[arg(long, value_delimiter = ',', default_value = "256,512,1024,2048")]
        sizes: Vec<u32>,
        /// Timed runs of each drawing; the median is kept.
        #[arg(long, default_value_t = 5)]
        reps: u32,
        /// The repository; chart.sh gives it.
        #[arg(long, value_name = "DIR")]
        root: Option<PathBuf>,
    },
}

/// The constants the chart predicts with: `--model FILE`; else this machine's
/// calibration, made first (at most 20 s, with a progress line) when there is none, or
/// when it is stale or another machine's.
fn load_constants(model: Option<&Path>, bin: &Path) -> Result<Constants> {
    if let Some(path) = model {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read {}", path.display()))?;
        return Constants::parse(&text).with_context(|| format!("reading {}", path.display()));
    }
    match chart::cache::load(bin) {
        chart::cache::State::Current(k) => Ok(k),
        _ => Ok(calibrate_now(bin, chart::calibrate::quick_from_env())?.0),
    }
}

fn calibrate_now(bin: &Path, quick: bool) -> Result<(Constants, PathBuf)> {
    chart::calibrate::calibrate_and_store("chart", bin, &bin.join("render"), quick)
        .map_err(Error::from)
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

/// The standard scenes (bench llvmpipe's four classes, and the failure scene).
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
                return Err(Error::Data(format!("scene environment failed for {name}")));
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

/// A hard case: name, `scene` arguments, screen.
type Hard = (&'static str, &'static [&'static str], (u32, u32));

/// The seeds' hard cases, each scaled so that one render takes at most a few seconds
/// here and the 16×16 reference (zspec tests 256 samples in every pixel of every
/// polygon's box) less than a minute of CPU: the stack, the slivers and the planes on
/// small screens.
///
/// - `stack`: 300 screen-filling squares in depth (Dc 300), 100×100: one window for
///   Warnock (Newman and Sproull 14.3.4: work follows visible, not scene, complexity),
///   300 writes a pixel for the z-buffer;
/// - `slivers`: 1,000 triangles about 0.2 px wide across a 250×250 screen (0.4 px at
///   500×500): pixel-sized windows for Warnock, many short segments for Watkins;
/// - `planes`: 100 tilted full-screen planes (160×160), every pair crossing: no depth order, the
///   painter's splitting step and the a-buffer's fragment lists at their worst;
/// - `cyclic-bars`: three bars overlapping in a cycle (examples/cyclic-bars.txt): no
///   order of whole polygons draws them right; the painter without `--split` fails;
/// - `spheres`: two interpenetrating spheres (Archuleta's figure 1);
/// - `strips`: 2,100 disjoint strips whose depth extents all overlap: the depth sort's
///   N(N−1)/2 pair tests. Not 2,000: 500/2,000 puts a strip's edge through every other
///   pixel centre, where the pipeline's rounding and the reference's exact f64 decide
///   the tie differently (29,067 pixels at depth 0, 34,774 at depth 1, for every exact
///   method alike); at 2,100 no edge meets a centre and the exact methods are exact.
const HARD: [Hard; 5] = [
    ("stack", &["stack", "300"], (100, 100)),
    ("slivers", &["slivers", "1000"], (250, 250)),
    ("planes", &["planes", "100"], (160, 160)),
    ("spheres", &["spheres"], (500, 500)),
    ("strips", &["strips", "2100"], (500, 500)),
];

/// The hard cases of `--quick`: [`HARD`] with the stack, the slivers and the planes
/// smaller, whose 16×16 references took most of a run (17, 49 and 15 s of CPU; the other
/// three at 500×500 took 0.7 to 1.8 s). Each is still its case: one square owning every
/// pixel under 100 (Dc 100), slivers 0.1 px wide, every pair of 20 planes crossing.
const HARD_QUICK: [Hard; 5] = [
    ("stack", &["stack", "100"], (50, 50)),
    ("slivers", &["slivers", "200"], (125, 125)),
    ("planes", &["planes", "20"], (80, 80)),
    HARD[3],
    HARD[4],
];

/// The hard scenes ([`HARD`], or [`HARD_QUICK`], and the cyclic bars), made with `scene`
/// into `dir`, each in a file named by its arguments (`stack-300.pp`).
fn hard_scenes(bin: &Path, root: &Path, dir: &Path, quick: bool) -> Result<Vec<Scene>> {
    std::fs::create_dir_all(dir)?;
    let mut scenes = Vec::new();
    for (name, args, (w, h)) in if quick { HARD_QUICK } else { HARD } {
        let path = dir.join(format!("{}.pp", args.join("-")));
        if !path.exists() {
            let status = Command::new(bin.join("scene"))
                .args(args)
                .stdout(std::fs::File::create(&path)?)
                .status()?;
            if !status.success() {
                let _ = std::fs::remove_file(&path);
                return Err(Error::Data(format!("scene {} failed", args.join(" "))));
            }
        }
        scenes.push(Scene {
            path,
            name: name.into(),
            width: w,
            height: h,
        });
    }
    scenes.insert(
        3,
        Scene::parse(
            &root.join("examples/cyclic-bars.txt").to_string_lossy(),
            (500, 500),
        )?,
    );
    Ok(scenes)
}

fn run(mut cli: Cli) -> Result<()> {
    let root = root_dir(cli.root.clone())?;
    if cli.figures {
        cli.standard = true;
        cli.hard = true;
        cli.out.get_or_insert_with(|| root.join("docs/images"));
        cli.work.get_or_insert_with(|| root.join("target/chart"));
    }
    let Some(out) = cli.out else {
        return Err(Error::Usage(
            "-o DIR is needed (where the CSV files and pictures go)".into(),
        ));
    };
    // The scene arguments first: a bad `@WxH` is a usage error, said before anything is
    // made or read.
    let mut scenes: Vec<Scene> = cli
        .scenes
        .iter()
        .map(|s| Scene::parse(s, cli.size))
        .collect::<Result<_>>()?;
    if scenes.is_empty() && !(cli.standard || cli.hard || cli.calibrate || cli.replot) {
        return Err(Error::Usage("no SCENE given (or --standard)".into()));
    }
    // Each scene opened and its first bytes read before anything is made or run, so that
    // one that cannot be read is said at once, in the stages' words (`cannot open PATH: …`).
    for s in &scenes {
        chart::look::is_text(&s.path)?;
    }
    let bin = bin_dir()?;
    let work = cli.work.clone().unwrap_or_else(|| out.clone());
    let work_dir = work.clone();
    let render = bin.join("render");
    if out.exists() && !out.is_dir() {
        return Err(Error::Usage(format!(
            "-o {0}: {0} is a file; -o names a folder for the CSV files and pictures (a new one, or one to write into)",
            out.display()
        )));
    }
    for dir in [&out, &work] {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot make the folder {}", dir.display()))?;
    }
    if cli.replot {
        let rows: Vec<chart::chart::Row> = chart::chart::read_csv(&out.join("results.csv"))?;
        let model_rows: Vec<chart::chart::ModelRow> =
            chart::chart::read_csv(&out.join("model.csv"))?;
        let extra = read_if_there(&out, "model-extrapolation.csv")?;
        let choices = read_if_there(&out, "max-error.csv")?;
        chart::plot::speed_accuracy_marked(&out, &rows, &choices)?;
        chart::plot::environment(&out, &rows)?;
        return chart::plot::model(&out, &model_rows, &extra);
    }
    let cores = chart::calibrate::cores();
    if cli.standard {
        scenes.extend(standard_scenes(
            &bin,
            &root,
            &work.join("scenes"),
            cli.quick || cli.figures,
        )?);
    }
    if cli.hard {
        scenes.extend(hard_scenes(&bin, &root, &work.join("scenes"), cli.quick)?);
    }
    if cli.remodel {
        return remodel(&out, &scenes, cli.model.as_deref(), &bin, cores);
    }
    if cli.calibrate {
        calibrate(cli.quick, cli.model.as_deref(), &bin)?;
        if scenes.is_empty() {
            return Ok(());
        }
    }
    let constants = if cli.calibrate {
        // Just fitted: this machine's, whatever --model named for writing.
        load_constants(None, &bin)?
    } else {
        load_constants(cli.model.as_deref(), &bin)?
    };
    let setup = Setup {
        bin,
        render,
        out: out.clone(),
        work,
        quick: cli.quick,
        only: cli.methods.clone(),
        reps: cli
            .reps
            .map_or(if cli.quick { 1 } else { 5 }, |r| r as usize),
        cores,
        constants,
    };
    let total = scenes.len() as u64
        * (chart::methods::runs(cli.quick, cli.methods.as_deref()).len() as u64
            * setup.reps as u64
            + 1);
    let progress = bar(total);
    let mut first = true;
    let (rows, model_rows, extra) = chart::chart::chart(&setup, &scenes, |what| {
        if !first {
            progress.inc(1);
        }
        first = false;
        progress.set_message(what.to_string());
    })?;
    progress.finish_and_clear();
    chart::chart::write_csv(&out.join("results.csv"), &rows)?;
    // With --figures the cost model's files go beside the scenes, not into docs/images:
    // its picture there is docs/model.md's, drawn from a calibration of its own.
    let model_out = if cli.figures { &work_dir } else { &out };
    chart::chart::write_csv(&model_out.join("model.csv"), &model_rows)?;
    chart::chart::write_csv(&model_out.join("model-extrapolation.csv"), &extra)?;
    let choices = chart::maxerror::choices(&setup, &scenes, &rows)?;
    chart::chart::write_csv(&out.join("max-error.csv"), &choices)?;
    chart::plot::speed_accuracy_marked(&out, &rows, &choices)?;
    chart::plot::environment(&out, &rows)?;
    chart::plot::model(model_out, &model_rows, &extra)?;
    if cli.figures {
        hidden_lines(&root, &out, &HIDDEN_SIZES, 5)?;
    }
    say(&model_table(&model_rows))?;
    say_err(&format!(
        "chart: wrote {0}/results.csv, {0}/max-error.csv, {0}/speed-accuracy.png and .svg, {0}/cost-environment.png and .svg, {1}/model.csv, {1}/model.png",
        out.display(),
        model_out.display()
    ));
    Ok(())
}

/// The sizes of the committed hidden-line figure (`chart hidden-lines`' default).
const HIDDEN_SIZES: [u32; 4] = [256, 512, 1024, 2048];

/// `chart hidden-lines`, also run by `--figures`: `out`/hidden-lines.csv and .png.
fn hidden_lines(
    root: &Path,
    out: &Path,
    sizes: &[u32],
    reps: u32,
) -> Result<Vec<chart::hidden::HiddenRow>> {
    std::fs::create_dir_all(out)?;
    let work = root.join("target/chart/hidden-lines");
    let rows = chart::hidden::measure(&bin_dir()?, root, &work, sizes, reps)?;
    std::fs::write(out.join("hidden-lines.csv"), chart::hidden::csv(&rows))?;
    chart::plot::hidden_lines(&out.join("hidden-lines.png"), &rows)?;
    Ok(rows)
}

/// `--remodel`: the predictions of `DIR/model.csv` made again beside its measurements.
fn remodel(
    out: &Path,
    scenes: &[Scene],
    model: Option<&Path>,
    bin: &Path,
    cores: usize,
) -> Result<()> {
    let k = load_constants(model, bin)?;
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
                r.load,
                r.measured_s,
            ));
        }
    }
    if rows.len() != old.len() {
        return Err(Error::Data(format!(
            "{} has rows of scenes not given ({} of {} matched): give the same scenes as the run that wrote it",
            path.display(),
            rows.len(),
            old.len()
        )));
    }
    chart::chart::write_csv(&path, &rows)?;
    let mut extra = Vec::new();
    let mut most = -1.0;
    for scene in scenes {
        let env = chart::look::look(&scene.path, scene.width, scene.height, &[], None)?;
        if env.area > most {
            most = env.area;
            extra = chart::chart::extrapolate(&k, &env, &scene.name, cores);
        }
    }
    chart::chart::write_csv(&out.join("model-extrapolation.csv"), &extra)?;
    chart::plot::model(out, &rows, &extra)?;
    say(&model_table(&rows))
}

/// The rows of DIR/NAME (model-extrapolation.csv, max-error.csv), none when there is no
/// such file (a run before the chart wrote it).
fn read_if_there<T: serde::de::DeserializeOwned>(out: &Path, name: &str) -> Result<Vec<T>> {
    let path = out.join(name);
    if path.exists() {
        chart::chart::read_csv(&path)
    } else {
        Ok(Vec::new())
    }
}

/// Writes `text` to stdout as the stages do ([`stagecli::stdout`]): the reader going
/// away (`| head`) ends chart quietly with 0, a failed write is `stdout: reason`, 3.
/// (println! would panic on either.)
fn say(text: &str) -> Result<()> {
    stagecli::stdout().write_all(text.as_bytes())?;
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

/// `chart calibrate`: this machine's constants fitted now, kept in the cache (and in
/// `model` when given), and printed.
fn calibrate(quick: bool, model: Option<&Path>, bin: &Path) -> Result<()> {
    let (k, _) = calibrate_now(bin, quick || chart::calibrate::quick_from_env())?;
    if let Some(path) = model {
        let text = format!(
            "# The cost model's constants (costmodel/src/model.rs), seconds, fitted by\n\
             # `chart calibrate{}` on {}: each stage binary alone on\n\
             # synthetic scenes, least squares. The fallback of `render.sh --depth auto`\n\
             # until a machine has its own calibration, and the example of the file.\n{}",
            if quick { " --quick" } else { "" },
            k.measured_on,
            k.to_toml()?
        );
        stagecli::whole::write_whole(path, text.as_bytes())?;
        say_err(&format!("chart: wrote {}", path.display()));
    }
    say(&chart::calibrate::table(&k))
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
    stagecli::main::<Cli>("chart", |cli| dispatch(cli).map_err(stagecli::Error::from))
}

fn dispatch(cli: Cli) -> Result<()> {
    match cli.command {
        Some(Sub::ChooseDepth(args)) => costmodel::cli::depth(*args).map_err(Error::from),
        Some(Sub::Calibrate { quick, model, root }) => {
            // The repository is checked as for every subcommand, though the start-up is
            // now the render binary's, not scripts/render.sh's.
            root_dir(root)?;
            calibrate(quick, model.as_deref(), &bin_dir()?)
        }
        Some(Sub::Thesis {
            measure,
            scale,
            root,
        }) => {
            say(&chart::thesis::report())?;
            if !measure {
                return Ok(());
            }
            if !(scale > 0.0 && scale <= 1.0) {
                return Err(Error::Usage("--scale is a fraction in (0, 1]".into()));
            }
            let work = root_dir(root)?.join("target/chart/thesis");
            let rows = chart::bottleneck::measure(&bin_dir()?, &work, scale)?;
            say(&format!("\n{}", chart::bottleneck::report(&rows, scale)))
        }
        Some(Sub::HiddenLines {
            out,
            sizes,
            reps,
            root,
        }) => {
            let root = root_dir(root)?;
            let out = out.unwrap_or_else(|| root.join("docs/images"));
            let rows = hidden_lines(&root, &out, &sizes, reps)?;
            say(&chart::hidden::csv(&rows))
        }
        None => run(cli),
    }
}
