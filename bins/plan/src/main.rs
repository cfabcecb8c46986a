//! plan: the command line of the cost model — what `render --depth auto` chooses (`plan
//! depth`, `plan predict`), the calibration (`plan calibrate`) and the thesis's figures
//! (`plan thesis`).

mod accuracy;

use clap::{Parser, Subcommand};
use costmodel::{cache, say, Result};
use std::path::PathBuf;
use std::process::ExitCode;

/// The cost model of thesis chapters 5.2 and 6.4 on this machine: the splitter tree depth
/// it predicts fastest for a scene (render --depth auto), its calibration, and the
/// thesis's own figures from the same code.
#[derive(Parser, Debug)]
#[command(
    name = "plan",
    version,
    after_help = "Examples:\n  \
        plan depth --size 1920x1080 fill.txt        # the depth render --depth auto takes\n  \
        plan depth --cores 64 fill.txt              # … on a machine of 64 cores\n  \
        plan depth --hosts 4 --link-gbps 10 fill.txt\n  \
        plan movie --hosts 1,2,4 --chunk 8 --size 512x512 movie.pp   # render --by frames\n  \
        plan calibrate                              # fit this machine's constants (at most 20 s)\n  \
        plan thesis                                 # thesis 5.2's timings and 6.4's depth 5"
)]
struct Cli {
    #[command(subcommand)]
    command: Sub,
}

#[derive(Subcommand, Debug)]
enum Sub {
    /// Prints the splitter tree depth the cost model predicts fastest for a scene, and
    /// why, as one line `N (reason; rule: …)`. It looks at the scene's first 128 KiB
    /// through the geometry viewxf, clipplane and persp share (proto's), in this process.
    Depth(Box<costmodel::cli::DepthArgs>),
    /// Prints the model's prediction at every depth (0 to --max-depth) for a scene, each
    /// stage's seconds (its busiest process) and the tree's per-level work, as a table:
    /// what `plan depth` chooses from.
    Predict(Box<costmodel::cli::DepthArgs>),
    /// Prints what a movie rendered in chunks over other hosts (render --by frames)
    /// takes, a row for each number of hosts: its wall time, frames a second and work,
    /// each chunk a render of its own by the model, the chunks shared among the hosts'
    /// job slots and written back in order.
    Movie(Box<costmodel::cli::MovieArgs>),
    /// Fits the model's constants on this machine (at most 20 s) and keeps them in
    /// ${XDG_CACHE_HOME:-$HOME/.cache}/polypipe/model.toml.
    Calibrate {
        /// A small fit (four small scenes, about two seconds): for tests.
        #[arg(long)]
        quick: bool,
        /// Fit in a process of its own, detached, at low priority, unless one is already
        /// fitting; return at once.
        #[arg(long)]
        background: bool,
        /// The repository (for scripts/render.sh).
        #[arg(long, value_name = "DIR")]
        root: Option<PathBuf>,
    },
    /// Prints each sampling mode's (--aa) predicted time, RMS error against the 16×16
    /// reference and share of pixels wrong on a scene, and what `render --max-error E`
    /// chooses for E of 0, 1, 4 and 16 (docs/model.md, "Accuracy").
    Accuracy(Box<costmodel::cli::DepthArgs>),
    /// Fits the error model to renders of generated scenes (every mode against `zspec
    /// --samples 16`) and keeps it in ${XDG_CACHE_HOME:-$HOME/.cache}/polypipe/accuracy.toml.
    AccuracyFit {
        /// Write the fit here instead (bench/accuracy.toml is the repository's).
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
    },
    /// Checks `render --max-error E` (E of 0, 1, 4, 16) on scenes the fit never saw:
    /// every configuration tried, the choice's measured error and time beside the
    /// cheapest configuration that met E; a row a case and a summary.
    MaxErrorCheck(accuracy::CheckArgs),
    /// Says whether this machine is calibrated, and where the calibration is kept.
    Status,
    /// Thesis 5.2's stage timings on its T424-20 from its own constants, beside its
    /// figures, and 6.4's depth of the splitter tree, through this model's code.
    Thesis,
}

fn calibrate(quick: bool, background_only: bool, root: Option<PathBuf>) -> Result<()> {
    let root = costmodel::cli::root_dir(root)?;
    if background_only {
        return costmodel::cli::background(&root);
    }
    let bin = costmodel::cli::bin_dir()?;
    let result = costmodel::calibrate::calibrate_and_store(
        "plan",
        &bin,
        &bin.join("render"),
        quick || costmodel::calibrate::quick_from_env(),
    );
    if let Some(dir) = cache::dir() {
        let _ = std::fs::remove_file(dir.join("calibrating"));
    }
    let (k, _) = result?;
    say(&costmodel::calibrate::table(&k))
}

fn status() -> Result<()> {
    let bin = costmodel::cli::bin_dir()?;
    let path = cache::path().map_or(
        "(no cache folder: neither XDG_CACHE_HOME nor HOME is set)".into(),
        |p| p.display().to_string(),
    );
    say(&format!("{}\n{path}\n", cache::load(&bin).describe()))
}

fn main() -> ExitCode {
    stagecli::main::<Cli>("plan", |cli| {
        let done = match cli.command {
            Sub::Depth(a) => costmodel::cli::depth(*a),
            Sub::Predict(a) => costmodel::cli::predict(*a),
            Sub::Movie(a) => costmodel::cli::movie(*a),
            Sub::Calibrate {
                quick,
                background,
                root,
            } => calibrate(quick, background, root),
            Sub::Accuracy(a) => accuracy::report(&a).and_then(|t| say(&t)),
            Sub::AccuracyFit { out } => accuracy::fit(out).and_then(|t| say(&t)),
            Sub::MaxErrorCheck(a) => accuracy::check(&a).and_then(|(_, t)| say(&t)),
            Sub::Status => status(),
            Sub::Thesis => say(&costmodel::thesis::report()),
        };
        // The library's error carries its kind, and so the status: 1, 2 or 3.
        done.map_err(stagecli::Error::from)
    })
}
