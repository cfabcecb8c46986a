//! plan: the command line of the cost model — `render.sh --depth auto`'s planner
//! (`plan depth`), the calibration (`plan calibrate`), the thesis's figures (`plan
//! thesis`), the sample of a scene on stdin (`plan sample`, `plan relay`), and the
//! launcher that runs render.sh's stages (`plan launch`).

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use plan::cache;
use plan::say;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The cost model of thesis chapters 5.2 and 6.4 on this machine: the splitter tree depth
/// it predicts fastest for a scene (render.sh --depth auto), its calibration, and the
/// thesis's own figures from the same code.
#[derive(Parser, Debug)]
#[command(
    name = "plan",
    version,
    after_help = "Examples:\n  \
        plan depth --size 1920x1080 fill.txt        # the depth render.sh --depth auto takes\n  \
        plan depth --cores 64 fill.txt              # … on a machine of 64 cores\n  \
        plan depth --hosts 4 --link-gbps 10 fill.txt\n  \
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
    /// why, as one line `N (reason; rule: …)`. It looks at the scene's first 512 KiB
    /// through the geometry viewxf, clipplane and persp share (proto's), in this process.
    Depth(Box<plan::cli::DepthArgs>),
    /// Prints the model's prediction at every depth (0 to --max-depth) for a scene, each
    /// stage's seconds (its busiest process) and the tree's per-level work, as a table:
    /// what `plan depth` chooses from.
    Predict(Box<plan::cli::DepthArgs>),
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
    /// Says whether this machine is calibrated, and where the calibration is kept.
    Status,
    /// Thesis 5.2's stage timings on its T424-20 from its own constants, beside its
    /// figures, and 6.4's depth of the splitter tree, through this model's code.
    Thesis,
    /// Copies the first 512 KiB of stdin to FILE (less when stdin ends, or pauses for
    /// 150 ms after its first byte) and prints `whole` (stdin ended) or `more`.
    Sample {
        #[arg(short = 'o', value_name = "FILE")]
        out: PathBuf,
    },
    /// Writes FILE, then the rest of stdin, to stdout: the sample and what followed it.
    Relay { file: PathBuf },
    /// Runs render.sh's process graph: for each stage `LABEL IN OUT HOST NODE PIPES N`
    /// and its command's N words (IN and OUT `-`, `file:PATH` or `pipe:NAME`; the last
    /// PIPES words channel names, given as /dev/fd/N); every channel an anonymous pipe.
    /// Exits as render.sh does: 0, the failing stage's class with one line naming it, or
    /// 128 + the signal that stopped the run.
    Launch {
        /// The tree's depth, for naming the hosts' nodes in messages.
        #[arg(long, default_value_t = 0)]
        depth: u32,
        /// Print the bytes each host's link carried, after the stages' counts.
        #[arg(long)]
        links: bool,
        /// Print each stage's CPU, peak memory and end, and their sums, after them.
        #[arg(long)]
        times: bool,
        /// The name the messages start with.
        #[arg(long = "as", value_name = "NAME", default_value = "render.sh")]
        name: String,
        /// A file to remove when the run ends (render.sh's sample of a stream).
        #[arg(long, value_name = "FILE")]
        remove: Vec<PathBuf>,
        #[arg(last = true, value_name = "STAGE")]
        stages: Vec<std::ffi::OsString>,
    },
}

fn calibrate(quick: bool, background_only: bool, root: Option<PathBuf>) -> Result<()> {
    let root = plan::cli::root_dir(root)?;
    if background_only {
        return plan::cli::background(&root);
    }
    let bin = plan::cli::bin_dir()?;
    let result = plan::calibrate::calibrate_and_store(
        "plan",
        &bin,
        &root.join("scripts/render.sh"),
        quick || plan::calibrate::quick_from_env(),
    );
    if let Some(dir) = cache::dir() {
        let _ = std::fs::remove_file(dir.join("calibrating"));
    }
    let (k, _) = result?;
    say(&plan::calibrate::table(&k))
}

fn status() -> Result<()> {
    let bin = plan::cli::bin_dir()?;
    let path = cache::path().map_or(
        "(no cache folder: neither XDG_CACHE_HOME nor HOME is set)".into(),
        |p| p.display().to_string(),
    );
    say(&format!("{}\n{path}\n", cache::load(&bin).describe()))
}

fn sample(out: &Path) -> Result<()> {
    use std::os::fd::FromRawFd;
    // A new file: a name that exists (a link someone put there included) is refused.
    let mut file = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(out)
        .with_context(|| format!("cannot write {}", out.display()))?;
    // stdin read unbuffered, as a File on fd 0 (not closed when done: ManuallyDrop), so
    // that `poll` sees what is left in the pipe.
    // SAFETY: fd 0 is open for the life of the process, and nothing else reads it here.
    let mut stdin = std::mem::ManuallyDrop::new(unsafe { std::fs::File::from_raw_fd(0) });
    let (_, ended) = plan::sample::sample(
        &mut *stdin,
        &mut file,
        plan::sample::SAMPLE_BYTES,
        plan::sample::PATIENCE,
    )
    .context("stdin")?;
    say(match ended {
        plan::sample::Ended::Whole => "whole\n",
        plan::sample::Ended::More => "more\n",
    })
}

/// The sample, then the rest of stdin, to stdout. The reader going away ends it quietly.
fn relay(file: &Path) -> Result<()> {
    let mut out = stagecli::stdout();
    let mut sample = std::fs::File::open(file)
        .map_err(|e| stagecli::Error::from(e).context(format!("cannot open {}", file.display())))?;
    std::io::copy(&mut sample, &mut out).map_err(stagecli::Error::from)?;
    std::io::copy(&mut std::io::stdin().lock(), &mut out)
        .map_err(|e| stagecli::Error::from(e).context("stdin"))?;
    out.flush().map_err(stagecli::Error::from)?;
    Ok(())
}

/// `plan launch` ([`plan::launch::run`]): exits with the run's status.
fn launch(
    options: &plan::launch::Options,
    name: &str,
    remove: &[PathBuf],
    words: &[std::ffi::OsString],
) -> Result<()> {
    let outcome = plan::launch::parse_stages(words)
        .and_then(|stages| plan::launch::run(stages, options, name));
    for file in remove {
        let _ = std::fs::remove_file(file);
    }
    let outcome = outcome.map_err(|e| stagecli::Error::usage(e.to_string()))?;
    plan::launch::tell(&outcome);
    std::process::exit(outcome.status.into())
}
fn main() -> ExitCode {
    stagecli::main::<Cli>("plan", |cli| {
        let done = match cli.command {
            Sub::Depth(a) => plan::cli::depth(*a),
            Sub::Predict(a) => plan::cli::predict(*a),
            Sub::Calibrate {
                quick,
                background,
                root,
            } => calibrate(quick, background, root),
            Sub::Status => status(),
            Sub::Thesis => say(&plan::thesis::report()),
            Sub::Sample { out } => sample(&out),
            Sub::Relay { file } => relay(&file),
            Sub::Launch {
                depth,
                links,
                times,
                name,
                remove,
                stages,
            } => launch(
                &plan::launch::Options {
                    depth,
                    links,
                    times,
                },
                &name,
                &remove,
                &stages,
            ),
        };
        done.map_err(|e| plan_error(&e))
    })
}

/// An error as a stage's: its kind kept where it was made (a usage error, an I/O
/// error), its contexts joined by `: `.
fn plan_error(e: &anyhow::Error) -> stagecli::Error {
    let mut said = Vec::new();
    for cause in e.chain() {
        if let Some(s) = cause.downcast_ref::<stagecli::Error>() {
            said.push(s.message().to_string());
            return stagecli::Error::new(s.kind(), said.join(": "));
        }
        if let Some(io) = cause.downcast_ref::<std::io::Error>() {
            said.push(stagecli::error::io_message(io));
            let kind = if io.kind() == std::io::ErrorKind::BrokenPipe {
                stagecli::Kind::ReaderGone
            } else {
                stagecli::Kind::Io
            };
            return stagecli::Error::new(kind, said.join(": "));
        }
        if let Some(proto::StreamError::Io(io)) = cause.downcast_ref::<proto::StreamError>() {
            said.push(stagecli::error::io_message(io));
            return stagecli::Error::new(stagecli::Kind::Io, said.join(": "));
        }
        said.push(cause.to_string());
    }
    stagecli::Error::new(stagecli::Kind::Data, said.join(": "))
}
