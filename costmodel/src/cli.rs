//! The planner's command line, shared by `plan depth` and its alias `chart choose-depth`
//! (so that users' scripts that call the old name keep working), and the background
//! calibration that a first `render --depth auto` starts.

use crate::cache::{self, State};
use crate::error::{Context, Error, Result};
use crate::look;
use crate::model::{self, Constants, Hosts, Target};
use proto::camera::parse_size;
use std::path::{Path, PathBuf};

pub use stagecli::place::{bin_dir, root_dir};

#[derive(clap::Args, Debug)]
pub struct DepthArgs {
    /// The screen size, as render's --size.
    #[arg(long, default_value = "500x500", value_parser = parse_size, value_name = "WxH")]
    pub size: (u32, u32),
    /// Cores to plan for (default: this machine's).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub cores: Option<u32>,
    /// The deepest tree to consider.
    #[arg(long, default_value_t = 6, value_parser = clap::value_parser!(u8).range(0..=6))]
    pub max_depth: u8,
    /// Plan for the tree's subtrees on this many other hosts (render --hosts).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=64))]
    pub hosts: Option<u32>,
    /// Cores of each host (default: as many as this machine's).
    #[arg(long, value_name = "C", value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub host_cores: Option<u32>,
    /// Other programs' runnable threads on this machine's cores, which the render shares
    /// them with (default: $POLYPIPE_LOAD, or else the 1-minute load average, less one
    /// for the render's own stages seen in it; 0 plans for an idle machine).
    #[arg(long, value_name = "L", value_parser = stagecli::numbers::non_negative)]
    pub load: Option<f64>,
    /// The links to the hosts, gigabits a second (default 1).
    #[arg(long, value_name = "G", default_value_t = 1.0,
          value_parser = stagecli::numbers::between(1e-3, 1e5))]
    pub link_gbps: f64,
    /// The model's constants file (default: this machine's calibration, else the
    /// repository's bench/model.toml).
    #[arg(long, value_name = "FILE")]
    pub model: Option<PathBuf>,
    /// The repository, for bench/model.toml.
    #[arg(long, value_name = "DIR")]
    pub root: Option<PathBuf>,
    /// SCENE is a sample of a stream (its first bytes, kept in a file): `whole` when the
    /// stream ended within it, `more` when it did not.
    #[arg(long, value_name = "whole|more", value_parser = ["whole", "more"])]
    pub stream: Option<String>,
    /// On an uncalibrated machine, say so once (on stderr; the first time only) and
    /// start the calibration in the background: what render asks when a person is
    /// watching its stderr.
    #[arg(long)]
    pub tell_once: bool,
    /// viewxf's camera options, as render was given them, e.g. `--eye 10,10,20`.
    #[arg(long = "eye", value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub eye: Option<String>,
    #[arg(long = "at", value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub at: Option<String>,
    #[arg(long = "up", value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub up: Option<String>,
    #[arg(long = "s", value_name = "S", allow_hyphen_values = true)]
    pub s: Option<String>,
    #[arg(long = "d", value_name = "D", allow_hyphen_values = true)]
    pub d: Option<String>,
    #[arg(long = "hither", value_name = "K1", allow_hyphen_values = true)]
    pub hither: Option<String>,
    #[arg(long = "yon", value_name = "K2", allow_hyphen_values = true)]
    pub yon: Option<String>,
    /// The scene (a file: it is read here and again by the render).
    pub scene: PathBuf,
}

/// The constants to plan with and, when they are not this machine's, a note saying so:
/// `--model FILE`; else this machine's calibration (stale or not); else the repository's
/// bench/model.toml (another machine's), else the copy built in.
pub fn constants(
    model: Option<&Path>,
    root: &Path,
    bin: &Path,
) -> Result<(Constants, Option<String>, State)> {
    if let Some(path) = model {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read {}", path.display()))?;
        let k = Constants::parse(&text).with_context(|| format!("reading {}", path.display()))?;
        return Ok((k, None, State::Missing));
    }
    let state = cache::load(bin);
    if let Some(k) = state.constants() {
        let note = match &state {
            State::Stale(_, why) => Some(format!("calibration stale: {why}")),
            _ => None,
        };
        return Ok((k.clone(), note, state));
    }
    let fallback = root.join("bench/model.toml");
    let k = std::fs::read_to_string(&fallback)
        .ok()
        .and_then(|t| Constants::parse(&t).ok())
        .unwrap_or_else(Constants::committed);
    Ok((
        k,
        Some(
            "uncalibrated: bench/model.toml's constants; `chart calibrate` fits this machine's"
                .into(),
        ),
        state,
    ))
}

/// What `plan depth` and `plan predict` share: the constants (and a note when they are
/// not this machine's), the look at the scene, and the target.
pub fn setup(
    a: &DepthArgs,
) -> Result<(Constants, Option<String>, State, look::Environment, Target)> {
    let root = root_dir(a.root.clone())?;
    let bin = bin_dir()?;
    let (k, note, state) = constants(a.model.as_deref(), &root, &bin)?;
    let mut camera = Vec::new();
    for (opt, v) in [
        ("--eye", &a.eye),
        ("--at", &a.at),
        ("--up", &a.up),
        ("--s", &a.s),
        ("--d", &a.d),
        ("--hither", &a.hither),
        ("--yon", &a.yon),
    ] {
        if let Some(v) = v {
            // One word, so that a value with a leading minus stays a value.
            camera.push(format!("{opt}={v}"));
        }
    }
    let (w, h) = a.size;
    let env = match a.stream.as_deref() {
        Some(ended) => look::look_stream(&a.scene, w, h, &camera, ended == "whole")?,
        None => look::look(&a.scene, w, h, &camera, Some(look::LOOK_BYTES))?,
    };
    let target = target(a.cores, a.load, a.hosts, a.host_cores, a.link_gbps);
    Ok((k, note, state, env, target))
}

/// The machine to plan for: `cores` (default: this machine's), sharing them with `load`
/// other runnable threads (default: this machine's, as [`DepthArgs::load`] says), and
/// `hosts` other hosts of `host_cores` cores each over links of `link_gbps`.
pub fn target(
    cores: Option<u32>,
    load: Option<f64>,
    hosts: Option<u32>,
    host_cores: Option<u32>,
    link_gbps: f64,
) -> Target {
    let cores = cores.map_or_else(crate::calibrate::cores, |c| c as usize);
    Target {
        cores,
        load: load.unwrap_or_else(|| {
            // The load is spread over the machine's cores: a plan for fewer of them
            // (taskset) meets its part; one for more cores than this machine has is a
            // plan for another, idle, machine.
            let here = crate::calibrate::machine_cores();
            if cores <= here {
                crate::calibrate::background_load() * cores as f64 / here as f64
            } else {
                0.0
            }
        }),
        hosts: hosts.map(|n| Hosts {
            count: n as usize,
            cores: host_cores.map_or(cores, |c| c as usize),
            link_bytes_per_s: link_gbps * 1e9 / 8.0,
            start_s: 0.1,
        }),
    }
}

pub fn depth(a: DepthArgs) -> Result<()> {
    let root = root_dir(a.root.clone())?;
    let (k, note, state, env, target) = setup(&a)?;
    let (depth, reason, _) = model::choose_depth_on(&k, &env, &target, a.max_depth);
    let reason = match note {
        Some(n) => format!("{reason}; {n}"),
        None => reason,
    };
    crate::say(&format!("{depth} ({reason})\n"))?;
    if a.tell_once && a.model.is_none() && state.needs_fitting() {
        tell_once(&state, &root, "plan");
    }
    Ok(())
}

/// `plan predict`: every depth's prediction, a row each.
pub fn predict(a: DepthArgs) -> Result<()> {
    let (k, note, _, env, target) = setup(&a)?;
    let (chosen, _, all) = model::choose_depth_on(&k, &env, &target, a.max_depth);
    let mut t = String::from(
        "| depth | predicted s | slowest s | shared s | processes | viewxf | clip | splitter (root) | persp (leaf) | hse (leaf) | merge | bottleneck |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for p in &all {
        let stage = |name: &str| {
            p.stages
                .iter()
                .find(|s| s.stage == name)
                .map_or("–".to_string(), |s| format!("{:.4}", s.each_s))
        };
        t += &format!(
            "| {}{} | {:.4} | {:.4} | {:.4} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            p.depth,
            if p.depth == chosen { " (chosen)" } else { "" },
            p.total_s,
            p.slowest_s,
            p.shared_s,
            p.processes,
            stage("viewxf"),
            stage("clip"),
            stage("splitter"),
            stage("persp"),
            stage("hse"),
            stage("merge"),
            p.bottleneck()
        );
    }
    t += &format!(
        "\n{} polygons in view of {}, Dc {:.2}, {}x{}, {} frame(s); {}\n",
        env.relevant,
        env.polygons,
        env.depth_complexity(),
        env.width,
        env.height,
        env.frames,
        note.unwrap_or_else(|| k.measured_on.clone())
    );
    crate::say(&t)
}

/// Says once (a marker in the cache folder remembers) that this machine is not
/// calibrated, and starts the calibration in the background; `me` starts the line.
pub fn tell_once(state: &State, root: &Path, me: &str) {
    let Some(dir) = cache::dir() else { return };
    let marker = dir.join("uncalibrated-said");
    if std::fs::create_dir_all(&dir).is_err() || marker.exists() {
        return;
    }
    let _ = std::fs::write(&marker, b"");
    let started = background(root).is_ok();
    crate::say_err(&format!(
        "{me}: the cost model is {}: --depth auto uses bench/model.toml's constants (another machine's) until {}",
        state.describe(),
        if started {
            "this machine's are fitted, now, in the background (at most 20 s; `chart calibrate` to do it yourself)"
        } else {
            "`chart calibrate` fits this machine's (at most 20 s)"
        }
    ));
}

/// Starts `plan calibrate` (the `plan` binary beside this one's) in a process of its own
/// session, at low priority, unless a calibration is already under way (a lock file
/// younger than a minute).
pub fn background(root: &Path) -> Result<()> {
    use std::os::unix::process::CommandExt;
    let dir = cache::dir().ok_or_else(|| Error::Io("no cache folder".into()))?;
    std::fs::create_dir_all(&dir)?;
    let lock = dir.join("calibrating");
    if let Ok(m) = std::fs::metadata(&lock) {
        let young = m
            .modified()
            .ok()
            .and_then(|t| t.elapsed().ok())
            .is_some_and(|age| age.as_secs() < 60);
        if young {
            return Ok(());
        }
    }
    std::fs::write(&lock, std::process::id().to_string())?;
    let mut cmd = std::process::Command::new(bin_dir()?.join("plan"));
    cmd.args(["calibrate", "--root"])
        .arg(root)
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null());
    // SAFETY: setsid and nice are async-signal-safe; nothing else runs in the child
    // before exec.
    unsafe {
        cmd.pre_exec(|| {
            libc::setsid();
            libc::nice(10);
            Ok(())
        });
    }
    cmd.spawn()?;
    Ok(())
}

#[derive(clap::Args, Debug)]
pub struct MovieArgs {
    /// The screen size, as render's --size.
    #[arg(long, default_value = "500x500", value_parser = parse_size, value_name = "WxH")]
    pub size: (u32, u32),
    /// The numbers of hosts to predict for, a row each.
    #[arg(long, value_name = "N,…", value_delimiter = ',', default_values_t = [1u32, 2, 4],
          value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub hosts: Vec<u32>,
    /// Job slots on each host (`N/host` in an sshloginfile; a host named N times).
    #[arg(long, value_name = "N", default_value_t = 1,
          value_parser = clap::value_parser!(u32).range(1..=256))]
    pub slots: u32,
    /// Frames a chunk (render --chunk).
    #[arg(long, value_name = "N", default_value_t = 8,
          value_parser = clap::value_parser!(u64).range(1..))]
    pub chunk: u64,
    /// Cores of each host (default: as many as this machine's).
    #[arg(long, value_name = "C", value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub host_cores: Option<u32>,
    /// Seconds of a chunk's login to its host (ssh); 0 for a stand-in that runs the
    /// command here.
    #[arg(long, value_name = "S", default_value_t = 0.1,
          value_parser = stagecli::numbers::non_negative)]
    pub login: f64,
    /// Seconds GNU parallel adds to a job (its Perl wrapper on the host).
    #[arg(long, value_name = "S", default_value_t = crate::movie::PARALLEL_JOB_S,
          value_parser = stagecli::numbers::non_negative)]
    pub job: f64,
    /// The model's constants file (default: this machine's calibration, else the
    /// repository's bench/model.toml).
    #[arg(long, value_name = "FILE")]
    pub model: Option<PathBuf>,
    /// The repository, for bench/model.toml.
    #[arg(long, value_name = "DIR")]
    pub root: Option<PathBuf>,
    /// The movie (a file, read whole).
    pub scene: PathBuf,
}

/// `plan movie`: a movie rendered in chunks over 1, 2, … hosts (render --by frames), a
/// row each: the wall time, the frames a second and the work ([`crate::movie`]).
pub fn movie(a: MovieArgs) -> Result<()> {
    let root = root_dir(a.root.clone())?;
    let bin = bin_dir()?;
    let (k, note, _) = constants(a.model.as_deref(), &root, &bin)?;
    let (w, h) = a.size;
    let env = look::look(&a.scene, w, h, &[], None)?;
    let host_cores = a
        .host_cores
        .map_or_else(crate::calibrate::cores, |c| c as usize);
    let mut t = String::from(
        "| hosts | job slots | chunks | predicted wall s | frames/s | predicted CPU s | chunks a slot |\n\
         |---|---|---|---|---|---|---|\n",
    );
    let mut last = None;
    for &n in &a.hosts {
        let slots = (n * a.slots) as usize;
        let f = crate::movie::farm_from_model(&k, &env, a.chunk, slots, host_cores, a.login, a.job);
        let p = crate::movie::predict_farm(&f);
        let spread: Vec<String> = p.per_slot.iter().map(u64::to_string).collect();
        t += &format!(
            "| {n} | {slots} | {} | {:.3} | {:.1} | {:.3} | {} |\n",
            p.chunks,
            p.wall_s,
            p.frames_per_s(f.frames),
            p.work_s,
            spread.join(", ")
        );
        last = Some(f);
    }
    if let Some(f) = last {
        t += &format!(
            "\n{} frames, {} a chunk, {}x{}, {} core{} a host: a chunk {:.4} s to start \
             ({:.3} s login, {:.3} s parallel's job) + {:.4} s a frame (CPU {:.4} + {:.4}), \
             the writer {:.4} s a frame, parallel's start {:.3} s; {}\n",
            f.frames,
            a.chunk,
            w,
            h,
            host_cores,
            if host_cores == 1 { "" } else { "s" },
            f.start_s,
            a.login,
            a.job,
            f.frame_s,
            f.start_cpu_s,
            f.frame_cpu_s,
            f.write_s,
            f.run_s,
            note.unwrap_or_else(|| k.measured_on.clone())
        );
    }
    crate::say(&t)
}
