//! # render: the polypipe stages composed into the thesis's pipeline
//!
//! One program plans, starts and watches a render's process graph (thesis chapter 6.3;
//! docs/DESIGN.md, "The splitter tree"): its options ([`options`]), the graph they ask
//! for ([`graph`]), the depth the cost model chooses for `--depth auto`, from a look at
//! the scene in this process ([`auto`], with the `costmodel` crate's model), and the launcher
//! that runs the stages, each a process of its own joined to the next by an anonymous
//! pipe, and ends the run as one ([`launch`]). `scripts/render.sh` builds the binaries
//! and becomes it ([`fresh`]); `chart` runs it.
//!
//! Exit status: 0 success, 1 bad input data, 2 bad arguments, 3 I/O or environment; a
//! failing stage's own class, the stage named; 130 or 143 when stopped by SIGINT or
//! SIGTERM. Nothing is left running or on disk on any way out.

pub mod auto;
pub mod budget;
pub mod fresh;
pub mod graph;
pub mod launch;
pub mod options;
pub mod sample;

use options::{By, Options, Parsed, Scene};
use stagecli::Error;
use std::ffi::OsString;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};

/// The name render's messages start with.
pub const ME: &str = "render";

/// The repository: `POLYPIPE_SOURCES` (scripts/render.sh names it), else the folder
/// above this binary's with scripts/render.sh, else the current one.
pub fn repository() -> PathBuf {
    if let Some(root) = std::env::var_os("POLYPIPE_SOURCES").filter(|r| !r.is_empty()) {
        return root.into();
    }
    stagecli::place::root_dir(None).unwrap_or_else(|_| PathBuf::from("."))
}

/// The scene rendered when none is given and stdin is a terminal.
pub fn repository_example() -> PathBuf {
    repository().join("examples/penetrating.txt")
}

/// The stage binaries' folder: `POLYPIPE_BIN` (a host's folder of built binaries, given
/// by `--remote-bin`, run as they are), else this binary's own.
fn bin_dir() -> Result<(PathBuf, bool), Error> {
    if let Some(dir) = std::env::var_os("POLYPIPE_BIN").filter(|d| !d.is_empty()) {
        return Ok((dir.into(), true));
    }
    let exe = std::env::current_exe().map_err(|e| Error::from(e).context("where render is"))?;
    Ok((exe.parent().unwrap_or(Path::new(".")).to_path_buf(), false))
}

/// The stages a graph may run whatever its leaves' method: the pipeline above the leaves
/// and the merger (a method's own stage comes from the table of methods).
pub const PIPELINE_STAGES: [&str; 7] = [
    "viewxf",
    "clipplane",
    "clipbatch",
    "splitter",
    "persp",
    "scanconv",
    "zbuf",
];

/// Every binary `o`'s graph runs is in `bin`: `no X in DIR`, status 3, before anything
/// starts.
fn check_binaries(o: &Options, bin: &Path, from_env: bool) -> Result<(), Error> {
    let method = graph::method(o);
    for b in PIPELINE_STAGES.iter().copied().chain([method[0].as_str()]) {
        if !bin.join(b).is_file() {
            let whose = if from_env { " (POLYPIPE_BIN)" } else { "" };
            return Err(Error::io(format!("no {b} in {}{whose}", bin.display())));
        }
    }
    Ok(())
}

/// The options about the picture, for the hosts' renders of `--by frames`.
fn picture_options(cli: &options::Cli) -> Vec<String> {
    let (width, height) = cli.size;
    let mut w: Vec<String> = vec!["--size".into(), format!("{width}x{height}")];
    if let Some(d) = cli.depth {
        w.extend(["--depth".into(), d.to_string()]);
    }
    w.extend(cli.camera());
    for (opt, v) in [
        ("--zmode", cli.zmode.name().to_string()),
        ("--merge", options::name(cli.merge)),
        ("--hse", cli.hse.clone()),
        ("--aa", cli.aa.clone()),
        ("--clip", options::name(cli.clip)),
    ] {
        w.extend([opt.to_string(), v]);
    }
    if let Some(m) = &cli.hidden_line_method {
        w.extend(["--hidden-line-method".into(), m.clone()]);
    }
    for (opt, on) in [
        ("--split", cli.split),
        ("--pixels", cli.pixels),
        ("--hidden-line", cli.hidden_line),
        ("--stats", cli.stats),
    ] {
        if on {
            w.push(opt.into());
        }
    }
    w
}

/// `--by frames`: the `farm` binary cuts the movie into chunks and runs each on a host,
/// `render.sh OPTIONS -` there (at the same path, with the binaries of --remote-bin), and
/// writes the frames back in order; farm's own options pass through as given. The
/// options are checked here first, as a local render would check them. Returns only on
/// an error: farm takes this process's place.
fn frames_on_hosts(cli: &options::Cli, list: Option<&str>) -> Error {
    use std::os::unix::process::CommandExt;
    if cli.subtree.is_some() {
        return Error::usage("--subtree is a host's part of --by leaves: not with --by frames");
    }
    if cli.times {
        return Error::usage("--times is the stages' here: not with --by frames");
    }
    let o = match cli
        .validate(Vec::new(), stdin_gives_no_scene().is_some())
        .and_then(|o| options::check_scene(&o.scene).map(|_| o))
    {
        Ok(o) => o,
        Err(e) => return e,
    };
    if let Err(e) = host_timeout(cli) {
        return e;
    }
    let (bin, from_env) = match bin_dir() {
        Ok(b) => b,
        Err(e) => return e,
    };
    if let Err(e) = check_binaries(&o, &bin, from_env) {
        return e;
    }
    tell_example(&o);
    let root = repository();
    let mut farm = std::process::Command::new(bin.join("farm"));
    if let Some(list) = list {
        farm.args(["--hosts", list]);
    }
    let number = |n: Option<u64>| n.map(|n| n.to_string());
    let valued = [
        ("--chunk", &number(cli.chunk)),
        ("--sshloginfile", &cli.sshloginfile),
        ("--retries", &number(cli.retries)),
        ("--host-failures", &number(cli.host_failures)),
        ("--host-timeout", &cli.host_timeout),
        ("--joblog", &cli.joblog),
        ("--slurm-array", &cli.slurm_array),
        ("-o", &cli.output),
        ("--first-frame", &number(cli.first_frame)),
    ];
    for (opt, v) in valued {
        if let Some(v) = v {
            farm.args([opt, v]);
        }
    }
    if cli.resume {
        farm.arg("--resume");
    }
    if cli.stats {
        farm.arg("--stats");
    }
    match &o.scene {
        Scene::Stdin => farm.arg("-"),
        Scene::Path(p) => farm.arg(p),
    };
    let remote_bin = cli
        .remote_bin
        .clone()
        .unwrap_or_else(|| bin.display().to_string());
    farm.arg("--")
        .arg("env")
        .arg(format!("POLYPIPE_BIN={remote_bin}"))
        .arg(root.join("scripts/render.sh"))
        .args(picture_options(cli))
        .arg("-");
    let e = farm.exec();
    Error::from(e).context(format!("cannot run {}", bin.join("farm").display()))
}

/// Why stdin gives no scene, where it gives none: a terminal (a person at the keyboard),
/// a character device such as /dev/null (a job started with no input: cron, CI, `ssh HOST
/// COMMAND`, `< /dev/null`), or a closed stdin. A pipe or a file is a scene, read as a
/// filter reads it, even an empty one (viewxf then says so).
pub fn stdin_gives_no_scene() -> Option<&'static str> {
    use std::os::fd::AsFd;
    use std::os::unix::fs::FileTypeExt;
    let stdin = std::io::stdin();
    if stdin.is_terminal() {
        return Some("a terminal");
    }
    let Ok(fd) = stdin.as_fd().try_clone_to_owned() else {
        return Some("closed");
    };
    match std::fs::File::from(fd).metadata() {
        Ok(m) if m.file_type().is_char_device() => Some("a device (such as /dev/null)"),
        Ok(_) => None,
        Err(_) => Some("closed"),
    }
}

/// With no SCENE and nothing on stdin: says which scene is rendered, and why.
fn tell_example(o: &Options) {
    if o.example {
        let why = stdin_gives_no_scene().unwrap_or("a terminal");
        let _ = writeln!(
            std::io::stderr(),
            "{ME}: no SCENE given and stdin is {why}: rendering {} (give a SCENE, `-`, or pipe one in)",
            repository_example().display()
        );
    }
}

/// The first of the options only farm takes (besides --chunk) that is given.
fn farm_option(cli: &options::Cli) -> Option<&'static str> {
    let given = [
        ("--sshloginfile", cli.sshloginfile.is_some()),
        ("--retries", cli.retries.is_some()),
        ("--host-failures", cli.host_failures.is_some()),
        ("--joblog", cli.joblog.is_some()),
        ("--resume", cli.resume),
        ("--slurm-array", cli.slurm_array.is_some()),
    ];
    given.iter().find(|(_, on)| *on).map(|(opt, _)| *opt)
}

/// `--host-timeout S`: how long a host may send nothing (default 60 s; 0, for ever).
fn host_timeout(cli: &options::Cli) -> Result<Option<std::time::Duration>, Error> {
    const MAX: f64 = 86_400.0;
    let Some(text) = &cli.host_timeout else {
        return Ok(Some(std::time::Duration::from_secs(60)));
    };
    match text.trim().parse::<f64>() {
        Ok(0.0) => Ok(None),
        Ok(s) if s.is_finite() && s > 0.0 && s <= MAX => {
            Ok(Some(std::time::Duration::from_secs_f64(s)))
        }
        _ => Err(Error::usage(format!(
            "--host-timeout must be seconds from 0 (wait for ever) to {MAX}, not '{}'",
            text.chars().take(80).collect::<String>()
        ))),
    }
}

/// farm's options: refused without `--by frames`.
fn farm_only(cli: &options::Cli) -> Result<(), Error> {
    if cli.chunk.is_some() {
        return Err(Error::usage("--chunk is for --by frames"));
    }
    match farm_option(cli) {
        Some(opt) => Err(Error::usage(format!("{opt} is for --by frames"))),
        None => Ok(()),
    }
}

/// `--depth auto`'s choice as render's `--stats` record (`stagecli::stats`), printed
/// after its readable line: `depth_auto` is the depth the tree was built with.
pub fn depth_record(depth: u32) -> stagecli::stats::Record {
    stagecli::stats::Record::new(ME).with("depth_auto", depth)
}

/// `--max-error`'s choice, said on stderr with `--stats`.
fn say_chosen(stats: bool, chosen: &budget::Chosen) {
    if stats {
        let _ = writeln!(std::io::stderr(), "{ME}: {}", chosen.said);
    }
}

/// Renders as the command line `args` (the program's name first) asks, and returns the
/// exit status. Messages go to stderr as `render: …`.
pub fn run<I: IntoIterator<Item = OsString>>(args: I) -> u8 {
    run_in(methods::METHODS, args)
}

/// [`run`], with the methods of `table` (a table with a row of a test's own, whose stage
/// binary is in `POLYPIPE_BIN`: docs/extending.md).
pub fn run_in<I: IntoIterator<Item = OsString>>(table: &[methods::Method], args: I) -> u8 {
    match run_inner(table, args) {
        Ok(status) => status,
        Err(e) => {
            if e.kind() != stagecli::Kind::ReaderGone {
                let _ = writeln!(std::io::stderr(), "{ME}: {e}");
            }
            e.kind().status()
        }
    }
}

fn run_inner<I: IntoIterator<Item = OsString>>(
    table: &[methods::Method],
    args: I,
) -> Result<u8, Error> {
    let args: Vec<OsString> = args.into_iter().collect();
    let cli = match options::parse(args.iter().cloned())? {
        Parsed::Print(text) => {
            let _ = std::io::stdout().write_all(text.as_bytes());
            return Ok(0);
        }
        Parsed::Run(cli) => cli,
    };
    // Started by scripts/render.sh (or asked --build-only): the binaries made current
    // first, and a render binary cargo rebuilt run in this one's place.
    let sources = std::env::var_os("POLYPIPE_SOURCES")
        .filter(|r| !r.is_empty())
        .map(PathBuf::from)
        .or_else(|| cli.build_only.then(repository));
    let from_env = std::env::var_os("POLYPIPE_BIN").is_some_and(|d| !d.is_empty());
    if let (Some(root), false) = (sources, from_env) {
        let (bin, _) = bin_dir()?;
        if fresh::ensure(&root, &bin, ME)? && !cli.build_only {
            use std::os::unix::process::CommandExt;
            let e = std::process::Command::new(bin.join("render"))
                .args(&args[1..])
                .exec();
            return Err(Error::from(e).context("cannot run the rebuilt render"));
        }
    }
    if cli.build_only {
        return Ok(0);
    }
    if cli.list_methods {
        let listing = methods::listing(table);
        return match std::io::stdout().write_all(listing.as_bytes()) {
            Ok(()) => Ok(0),
            Err(e) => Err(Error::from(e).context("the list of methods")),
        };
    }
    let mut hosts = Vec::new();
    let mut ssh = Vec::new();
    if cli.hosts.is_some() || cli.by.is_some() {
        let by = cli.by.unwrap_or_default();
        // --by frames may take its hosts from farm's --sshloginfile, or need none
        // (--slurm-array).
        let farm_hosts = by == By::Frames && farm_option(&cli).is_some();
        if cli.hosts.is_none() && !farm_hosts {
            return Err(Error::usage(if by == By::Frames {
                "--by frames needs hosts: --hosts H1,H2,… or --sshloginfile FILE (or \
                 --slurm-array DIR, for Slurm's)"
            } else {
                "--by leaves needs --hosts H1,H2,…"
            }));
        }
        ssh = stagecli::remote::ssh_command_from_env()?;
        if let Some(list) = &cli.hosts {
            hosts = stagecli::remote::parse_hosts(list).map_err(Error::usage)?;
        }
        if by == By::Frames {
            return Err(frames_on_hosts(&cli, cli.hosts.as_deref()));
        }
    }
    farm_only(&cli)?;
    if cli.output.is_none() && cli.first_frame.is_some() {
        return Err(Error::usage(
            "--first-frame numbers -o's files: it needs -o",
        ));
    }
    budget::check(&cli)?;
    let o = cli.validate_in(table, hosts, stdin_gives_no_scene().is_some())?;
    options::check_scene(&o.scene)?;
    if !Path::new("/proc/self/stat").exists() {
        return Err(Error::io("needs /proc (Linux), to run its stages"));
    }
    let (bin, from_env) = bin_dir()?;
    check_binaries(&o, &bin, from_env)?;
    tell_example(&o);
    let root = repository();
    // --max-error on a stream: the safe choice, said before anything starts (on a scene
    // file the choice is made while the chain works, below).
    let file = matches!(o.scene, Scene::Path(_));
    let o = match cli.max_error {
        Some(e) if !file => {
            let chosen = budget::choose(&o, e, &root, &bin);
            say_chosen(o.stats, &chosen);
            budget::apply(o, &chosen, table)
        }
        _ => o,
    };
    let fixed = match o.depth {
        Some(d) => Some(d),
        None if o.hidden_line || o.subtree.is_some() => Some(0),
        None => None,
    };
    let context = |depth: u32, fed: bool| graph::Context {
        bin: &bin,
        depth,
        ssh: &ssh,
        root: &root,
        fed,
    };
    let host_timeout = host_timeout(&cli)?;
    // Progress: asked for, or a terminal on stderr. The stages are told by their
    // environment to report it (stagecli::progress); set here, before any thread or
    // stage is started.
    let progress = cli.progress || (!cli.no_progress && std::io::stderr().is_terminal());
    if progress {
        std::env::set_var(stagecli::progress::ENV, "1");
    } else {
        std::env::remove_var(stagecli::progress::ENV);
    }
    let options = |depth: u32| launch::Options {
        host_timeout,
        depth,
        links: o.stats && !o.hosts.is_empty(),
        times: o.times,
        feed: None,
        progress,
    };
    let graph_error = |e: launch::SpecError| Error::usage(format!("the graph: {e}"));
    // --depth auto's depth 0 without the model: a scene file too small for the tree to pay
    // (decided before the load is read), or a core or less for the render.
    let deferred = cli.max_error.filter(|_| file);
    let auto = fixed.is_none() && deferred.is_none();
    let tiny = auto.then(|| auto::tiny_scene(&o)).flatten();
    let target = (auto && tiny.is_none()).then(|| auto::target(&o));
    let depth_0_said = tiny.or_else(|| {
        target
            .filter(auto::one_core_at_most)
            .map(|_| auto::ONE_CORE.to_string())
    });
    // --depth auto's choice for `o` (its scene sampled when a stream), said with --stats.
    let auto_depth =
        |o: &Options, sampled: Option<&auto::Sampled>, target: &costmodel::model::Target| {
            let tell = std::io::stderr().is_terminal();
            let choice = auto::choose(o, sampled, target, &root, &bin, tell, ME);
            if let (true, Some(said)) = (o.stats, &choice.said) {
                depth_record(choice.depth).print(&format!("{ME}: {said}"));
            }
            choice.depth
        };
    let outcome = match (deferred, fixed) {
        // --max-error on a scene file, in two phases as --depth auto: viewxf and the
        // clipper, which neither --aa nor the depth changes, start first and work while
        // the scene is looked at and the sampling mode and depth chosen (the look costs
        // about a millisecond, a fifth of a small scene's whole render).
        (Some(e), _) => {
            let chain = graph::chain(&o, &context(0, false));
            let early = launch::start(chain, None, ME).map_err(graph_error)?;
            let chosen = budget::choose(&o, e, &root, &bin);
            say_chosen(o.stats, &chosen);
            let chose = budget::apply(o.clone(), &chosen, table);
            let depth = chosen
                .depth
                .unwrap_or_else(|| auto_depth(&chose, None, &auto::target(&chose)));
            let stages = graph::build(&chose, &context(depth, false));
            early.finish(stages, options(depth)).map_err(graph_error)?
        }
        (None, Some(depth)) => {
            let stages = graph::build(&o, &context(depth, false));
            launch::run(stages, options(depth), ME).map_err(graph_error)?
        }
        // Depth 0 without the model, in one phase: a scene file too small for the tree
        // to pay, or a core or less for the render, where the model takes depth 0
        // whatever the scene (costmodel::model::Target::shares).
        (None, None) if depth_0_said.is_some() => {
            if let (true, Some(said)) = (o.stats, &depth_0_said) {
                depth_record(0).print(&format!("{ME}: {said}"));
            }
            let stages = graph::build(&o, &context(0, false));
            launch::run(stages, options(0), ME).map_err(graph_error)?
        }
        (None, None) => {
            // --depth auto, in two phases: viewxf and the clipper, which no depth
            // changes, start first and work while the scene is looked at and the model
            // asked; the tree, the leaves and the merger, which the depth makes, then.
            let target = target.unwrap_or_else(|| auto::target(&o));
            let mut sampled = auto::sample_stream(&o)?;
            let feed = sampled.as_mut().map(auto::Sampled::feed);
            let chain = graph::chain(&o, &context(0, feed.is_some()));
            let early = launch::start(chain, feed, ME).map_err(graph_error)?;
            let depth = auto_depth(&o, sampled.as_ref(), &target);
            let stages = graph::build(&o, &context(depth, sampled.is_some()));
            early.finish(stages, options(depth)).map_err(graph_error)?
        }
    };
    launch::tell(&outcome);
    Ok(outcome.status)
}
