//! render's command line: the options (clap), and the checks of what they ask for
//! together, each refused in one line that names the option as it was typed (status 2).
//!
//! clap parses each option into its type (a value enum, a size, a depth, a frame number),
//! and a refusal is put in render's own words (`--depth must be an integer from 0 to 6 or
//! auto, not '7'`, `--merge must be tiles or buffer, not 'zbuf'`) rather than clap's
//! several lines ([`usage_message`]). The methods (`--hse`, `--aa`,
//! `--hidden-line-method`) are the table of methods' names, checked against the table.
//! The camera and `-o` are left to the stages that take them (viewxf, zbuf), whose
//! usage errors come out of render as status 2.

use clap::error::{ContextKind, ContextValue, ErrorKind};
use clap::{CommandFactory, FromArgMatches, Parser, ValueEnum};
use methods::Method;
use stagecli::{DepthArg, Error};
use std::ffi::OsString;

/// `--merge`: how the leaves' pictures become one.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum Merge {
    /// Each leaf resolves its own region; zbuf places the finished pixels.
    #[default]
    Tiles,
    /// The thesis's PAR.BUFF: every fragment depth-tested in the one zbuf.
    Buffer,
}

/// `--clip`: the six clipping planes in one process or six.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum Clip {
    /// clipbatch: the six planes in one process.
    #[default]
    Batch,
    /// The thesis's six clipplane processes.
    Chain,
}

/// `--by`: what the hosts of `--hosts` are given.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum By {
    /// Each host a leaf, or a subtree.
    #[default]
    Leaves,
    /// Each host chunks of the movie's frames (the `farm` binary).
    Frames,
}

/// The name of a value enum's value as the command line spells it.
pub fn name<T: ValueEnum>(value: T) -> String {
    value
        .to_possible_value()
        .map_or_else(String::new, |v| v.get_name().to_string())
}

/// `--depth N|auto`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Depth {
    /// The depth the cost model chooses.
    Auto,
    /// A tree of this depth, 0 to 6.
    Fixed(u32),
}

impl Depth {
    /// The depth, `None` for auto.
    pub fn fixed(self) -> Option<u32> {
        match self {
            Depth::Auto => None,
            Depth::Fixed(d) => Some(d),
        }
    }
}

impl std::fmt::Display for Depth {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Depth::Auto => f.write_str("auto"),
            Depth::Fixed(d) => write!(f, "{d}"),
        }
    }
}

/// `--max-error E`: stagecli's finite number from 0 to 255, in render's words (the
/// message follows the option's name and comes before the value).
fn max_error(s: &str) -> Result<f64, String> {
    stagecli::numbers::between(0.0, 255.0)(s)
        .map_err(|_| "must be a number from 0 to 255 (RMS levels)".to_string())
}

/// `--depth N|auto`. The message follows the option's name and comes before the value
/// ([`usage_message`]).
fn tree_depth(s: &str) -> Result<Depth, String> {
    match s {
        "auto" => Ok(Depth::Auto),
        d if d.len() == 1 && (b'0'..=b'6').contains(&d.as_bytes()[0]) => {
            Ok(Depth::Fixed(u32::from(d.as_bytes()[0] - b'0')))
        }
        _ => Err("must be an integer from 0 to 6 or auto".into()),
    }
}

/// `--size WxH`, with the stages' bounds ([`parse_size`]).
fn size(s: &str) -> Result<(u32, u32), String> {
    parse_size(s).ok_or_else(|| "must be WxH with W and H from 1 to 65536".into())
}

/// `--first-frame N`.
fn frame_number(s: &str) -> Result<u64, String> {
    s.parse::<u64>()
        .map_err(|_| "must be a frame number, 0 or more".into())
}

/// `--chunk N`, `--retries N`: farm's, checked here first.
fn at_least_one(s: &str) -> Result<u64, String> {
    s.parse::<u64>()
        .ok()
        .filter(|n| *n >= 1)
        .ok_or_else(|| "must be a whole number, 1 or more".into())
}

const AFTER_HELP: &str = "\
The frames are byte-identical for every --depth with reciprocal or projective depth, but not
with --zmode eye-z: eye-space z is not linear across the screen, and each piece
of a split polygon interpolates it between its own vertices.

With no SCENE, the scene is read from stdin when stdin is a pipe or a file (as a filter
reads it); when it is a terminal or a device such as /dev/null, examples/penetrating.txt
is rendered, and stderr says so.

Run through scripts/render.sh, the binaries are built first when missing (cargo,
release, into $CARGO_TARGET_DIR, taken from the repository root when relative, or
target/), and rebuilt when their sources change. Needs Linux (/proc).

Exit status: 0 success, 1 bad input data, 2 bad arguments, 3 I/O or environment;
a failing stage's own status passes through (a stage killed by a signal: 1); 130 or
143 when stopped by SIGINT or SIGTERM.

Examples:
  scripts/render.sh -o penetrating.png
  scripts/render.sh --depth 3 --size 640x480 --eye 10,10,20 scene.txt > out.ppm
  scene environment --frames 10 | scripts/render.sh --depth 2 -o frame%03d.png
  target/bin/render --hosts a,b --by frames --joblog jobs.txt movie.txt > movie.ppm";

/// Renders a world-space scene (text or binary) through the polypipe stages, one process
/// each, joined by pipes (thesis chapter 6.3), and writes one binary PPM (P6) per frame
/// on stdout.
#[derive(Parser, Debug, Default)]
#[command(
    name = "render",
    version,
    args_override_self = true,
    after_help = AFTER_HELP,
    max_term_width = 100
)]
pub struct Cli {
    /// Screen size in pixels, W and H from 1 to 65536.
    #[arg(long, value_name = "WxH", default_value = "500x500", value_parser = size)]
    pub size: (u32, u32),
    /// Splitter tree depth, 0 to 6 (0: no splitter), or auto: the depth the cost model
    /// (docs/model.md) predicts fastest for this scene, screen and machine (and
    /// --hosts), from a look at its first 512 KiB; `chart calibrate` fits the model to
    /// this machine.
    #[arg(long, value_name = "N|auto", value_parser = tree_depth)]
    pub depth: Option<Depth>,
    /// Camera: the eye (viewxf's options, as given).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub eye: Option<String>,
    /// Camera: the point looked at.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub at: Option<String>,
    /// Camera: the up direction.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub up: Option<String>,
    /// View volume: the screen's half-size.
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub s: Option<String>,
    /// View volume: the eye's distance to the screen.
    #[arg(long, value_name = "D", allow_hyphen_values = true)]
    pub d: Option<String>,
    /// View volume: the hither plane.
    #[arg(long, value_name = "K1", allow_hyphen_values = true)]
    pub hither: Option<String>,
    /// View volume: the yon plane.
    #[arg(long, value_name = "K2", allow_hyphen_values = true)]
    pub yon: Option<String>,
    /// persp's depth: reciprocal (-K1/z_e), projective (the classic z-buffer's, which
    /// loses precision near yon) or eye-z (the occam code's).
    #[arg(long, value_name = "MODE", value_enum, default_value_t)]
    pub zmode: DepthArg,
    /// tiles: each leaf resolves its own region and zbuf only places the finished
    /// pixels; buffer: the thesis's PAR.BUFF, every fragment depth-tested in the one zbuf.
    #[arg(long, value_name = "MODE", value_enum, default_value_t)]
    pub merge: Merge,
    /// The leaves' hidden-surface method: zbuf, scanline (Watkins), warnock (area
    /// subdivision) or painter (depth sort, wrong where polygons interpenetrate or
    /// overlap cyclically); every one at every --depth, with --merge tiles
    /// (--list-methods: the table of methods).
    #[arg(long, value_name = "METHOD", default_value = "zbuf")]
    pub hse: String,
    /// With --hse painter: cut polygons by each other's planes where no depth order
    /// exists (Newell, Newell and Sancha's splitting step).
    #[arg(long)]
    pub split: bool,
    /// Anti-aliasing at the leaves: none (one sample at each pixel centre), ss2, ss4,
    /// ss8, ss16 (K×K samples a pixel, box filter), adaptive2 … adaptive16 (K×K samples
    /// only where an edge or a crossing touches the pixel: ssK's bytes on flat polygons)
    /// or abuf (Carpenter's a-buffer).
    #[arg(long, value_name = "MODE", default_value = "none")]
    pub aa: String,
    /// Choose --aa and --depth: the cheapest predicted to keep the RMS error against the
    /// 16×16 reference (zspec --samples 16) within E levels (0–255; 0: the reference's
    /// own bytes). --stats says the choice and its predictions (docs/model.md).
    #[arg(long, value_name = "E", value_parser = max_error)]
    pub max_error: Option<f64>,
    /// With --merge buffer: one fragment per pixel (the thesis's quadruplets) instead of
    /// spans.
    #[arg(long)]
    pub pixels: bool,
    /// Draw the visible parts of the polygons' edges as SVG, to the file -o names
    /// (FILE.svg; frame%03d.svg for a movie), at depth 0 (not with --hse, --aa, --merge
    /// buffer or --pixels).
    #[arg(long)]
    pub hidden_line: bool,
    /// With --hidden-line: continuous (default: exact pieces, hiddenline's own) or
    /// archuleta (Archuleta's counters on Watkins's scan-line segments, raster
    /// resolution), hiddenline's --method.
    #[arg(long, value_name = "M")]
    pub hidden_line_method: Option<String>,
    /// batch: clipbatch, the six planes in one process (Theoharis & Page's DAP
    /// clipper); chain: the thesis's six clipplane processes.
    #[arg(long, value_name = "MODE", value_enum, default_value_t)]
    pub clip: Clip,
    /// Splitter nodes, scan converters and zbuf print counts on stderr.
    #[arg(long)]
    pub stats: bool,
    /// After the run, each stage's CPU (user, system), its peak memory and when it
    /// ended, and their sums, on stderr.
    #[arg(long)]
    pub times: bool,
    /// Show progress on stderr (frames done, frames a second, in a tree the leaves done
    /// of the frame being made), also when stderr is not a terminal; by default only on
    /// a terminal. The image never mixes with it.
    #[arg(long, overrides_with = "no_progress")]
    pub progress: bool,
    /// No progress, also on a terminal.
    #[arg(long, overrides_with = "progress")]
    pub no_progress: bool,
    /// zbuf writes one file per frame (e.g. frame%04d.png) instead of stdout.
    #[arg(short = 'o', value_name = "PATTERN", allow_hyphen_values = true)]
    pub output: Option<String>,
    /// The number -o's pattern gives the first frame.
    #[arg(long, value_name = "N", value_parser = frame_number)]
    pub first_frame: Option<u64>,
    /// Run the tree on other hosts over ssh ($POLYPIPE_SSH HOST …, default ssh),
    /// round-robin: each host a leaf, or a whole subtree when the tree has more leaves
    /// than there are hosts.
    #[arg(long, value_name = "H1,H2,…")]
    pub hosts: Option<String>,
    /// With --hosts: leaves (default), or frames: a movie cut into chunks of frames,
    /// each rendered whole on the next host free (the `farm` binary).
    #[arg(long, value_name = "MODE", value_enum)]
    pub by: Option<By>,
    /// With --hosts: a host that sends nothing for S seconds is named and counts as failed
    /// (default 60; 0 waits for ever): status 3 with --by leaves, its chunk tried again
    /// elsewhere with --by frames.
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub host_timeout: Option<String>,
    /// With --by frames: frames a chunk, one ssh session each (farm's default 8).
    #[arg(long, value_name = "N", value_parser = at_least_one)]
    pub chunk: Option<u64>,
    /// With --by frames: farm's hosts from FILE (GNU parallel's form), passed to farm.
    #[arg(long, value_name = "FILE")]
    pub sshloginfile: Option<String>,
    /// With --by frames: a chunk's tries, passed to farm.
    #[arg(long, value_name = "N", value_parser = at_least_one)]
    pub retries: Option<u64>,
    /// With --by frames: a host whose tries fail K times in a row gets no more chunks
    /// (farm's default 2), passed to farm.
    #[arg(long, value_name = "K", value_parser = at_least_one)]
    pub host_failures: Option<u64>,
    /// With --by frames: farm's record of each chunk, passed to farm.
    #[arg(long, value_name = "FILE")]
    pub joblog: Option<String>,
    /// With --by frames: skip the chunks --joblog says are done, passed to farm.
    #[arg(long)]
    pub resume: bool,
    /// With --by frames: write a Slurm job array for the chunks into DIR (farm's).
    #[arg(long, value_name = "DIR")]
    pub slurm_array: Option<String>,
    /// With --hosts: the binaries' folder on the hosts (default: this one's).
    #[arg(long, value_name = "DIR")]
    pub remote_bin: Option<String>,
    /// What --hosts runs on a host: node K's part of the tree (its splitters, leaves and
    /// a zbuf --runs), from the stream into node K on stdin to its runs on stdout.
    #[arg(long, value_name = "K")]
    pub subtree: Option<String>,
    /// Print the table of methods, for scripts, and exit: a header line, then one line a
    /// method, tab-separated (name, selector, options, stage, draws, exact, input,
    /// depths, quick, colour, marker, fuzz; `-` for none).
    #[arg(long)]
    pub list_methods: bool,
    /// Only make the binaries current with their sources (in $POLYPIPE_SOURCES, else
    /// the repository above this binary) and exit: scripts/lib/binaries.sh's check.
    #[arg(long, hide = true)]
    pub build_only: bool,
    /// The scene (`-` for stdin; without one, stdin, or the example on a terminal).
    #[arg(value_name = "SCENE", allow_hyphen_values = false)]
    pub scene: Vec<OsString>,
}

/// What the command line asked for: the options parsed, or `--help`/`--version` text.
pub enum Parsed {
    Run(Box<Cli>),
    Print(String),
}

/// Parses `args` (the program's name first). A usage error is one line, status 2.
pub fn parse<I: IntoIterator<Item = OsString>>(args: I) -> Result<Parsed, Error> {
    // stagecli's conventions: a value that starts with `-` is the option's (`--depth -1`
    // is refused as a depth, not as an unknown option `-1`).
    let mut cmd = stagecli::args::command::<Cli>();
    let parsed = cmd
        .try_get_matches_from_mut(args)
        .and_then(|mut m| Cli::from_arg_matches_mut(&mut m));
    match parsed {
        Ok(cli) => Ok(Parsed::Run(Box::new(cli))),
        Err(e) if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) => {
            Ok(Parsed::Print(e.render().to_string()))
        }
        Err(e) => Err(Error::usage(usage_message(&e))),
    }
}

/// clap's error in render's words: `unknown option --bogus`, `--size needs a value`,
/// `--stats takes no value`, `--merge must be tiles or buffer, not 'zbuf'` (a value
/// enum's), `--depth must be an integer from 0 to 6 or auto, not '7'` (a typed parser's
/// words, which follow the option's name); anything else as clap says it, in one line.
fn usage_message(e: &clap::Error) -> String {
    use std::error::Error as _;
    let arg = match e.get(ContextKind::InvalidArg) {
        Some(ContextValue::String(s)) => s.split([' ', '=']).next().unwrap_or("").to_string(),
        _ => String::new(),
    };
    let value = match e.get(ContextKind::InvalidValue) {
        Some(ContextValue::String(v)) => v.clone(),
        _ => String::new(),
    };
    let value_given = !value.is_empty();
    let shown = proto::text::Shown(&value);
    match e.kind() {
        ErrorKind::ValueValidation if !arg.is_empty() => match e.source() {
            Some(why) => format!("{arg} {why}, not '{shown}'"),
            None => stagecli::args::usage_line(e, &Cli::command()),
        },
        ErrorKind::InvalidValue if !arg.is_empty() && value_given => {
            match e.get(ContextKind::ValidValue) {
                Some(ContextValue::Strings(valid)) => {
                    let valid: Vec<&str> = valid.iter().map(String::as_str).collect();
                    format!("{arg} must be {}, not '{shown}'", either(&valid))
                }
                _ => stagecli::args::usage_line(e, &Cli::command()),
            }
        }
        ErrorKind::UnknownArgument if !arg.is_empty() => format!("unknown option {arg}"),
        ErrorKind::InvalidValue if !arg.is_empty() && !value_given => {
            format!("{arg} needs a value")
        }
        ErrorKind::TooManyValues | ErrorKind::UnknownArgument if !arg.is_empty() => {
            format!("{arg} takes no value")
        }
        _ => stagecli::args::usage_line(e, &Cli::command()),
    }
}

/// Where the scene comes from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Scene {
    /// stdin (`-`, or no SCENE with stdin not a terminal).
    Stdin,
    /// A file (or a pipe named as a file, `<(…)`).
    Path(std::path::PathBuf),
}

/// The options render checks itself, as the run uses them.
#[derive(Clone, Debug)]
pub struct Options {
    pub size: String,
    pub width: u32,
    pub height: u32,
    /// The tree's depth; `None` for auto.
    pub depth: Option<u32>,
    pub depth_asked: bool,
    pub zmode: DepthArg,
    pub merge: Merge,
    pub hse: String,
    pub split: bool,
    pub aa: String,
    /// The stage at each leaf for --hse and --aa, its binary first, from the table of
    /// methods (with --merge tiles; --merge buffer's is scanconv's fragments); with
    /// --hidden-line, the drawing's stage after persp.
    pub leaf: Vec<String>,
    pub pixels: bool,
    pub hidden_line: bool,
    pub hidden_line_method: Option<String>,
    pub clip: Clip,
    pub stats: bool,
    pub times: bool,
    pub output: Option<String>,
    pub first_frame: Option<u64>,
    /// viewxf's options, as given (`--eye`, `X,Y,Z`, …).
    pub camera: Vec<String>,
    pub hosts: Vec<String>,
    pub remote_bin: Option<String>,
    pub subtree: Option<u64>,
    pub scene: Scene,
    /// Whether the scene is the example, chosen because stdin gives none (a terminal, a
    /// device such as /dev/null).
    pub example: bool,
}

/// `--size`'s bounds, the stages' own (proto::camera::parse_size): W and H from 1 to
/// 65536, leading zeros allowed, `x` or `X` between.
pub fn parse_size(size: &str) -> Option<(u32, u32)> {
    let (w, h) = size.split_once(['x', 'X'])?;
    let number = |s: &str| -> Option<u32> {
        let t = s.trim_start_matches('0');
        if s.is_empty() || !s.bytes().all(|b| b.is_ascii_digit()) || t.is_empty() || t.len() > 5 {
            return None;
        }
        t.parse().ok().filter(|n| (1..=65536).contains(n))
    };
    Some((number(w)?, number(h)?))
}

/// `a, b or c`.
fn either(allowed: &[&str]) -> String {
    match allowed {
        [a, b] => format!("{a} or {b}"),
        [rest @ .., last] => format!("{} or {last}", rest.join(", ")),
        [] => String::new(),
    }
}

fn one_of(option: &str, value: &str, allowed: &[&str]) -> Result<(), Error> {
    if allowed.contains(&value) {
        return Ok(());
    }
    Err(Error::usage(format!(
        "{option} must be {}, not '{}'",
        either(allowed),
        proto::text::Shown(value)
    )))
}

impl Cli {
    /// The camera options as viewxf takes them, in a fixed order.
    pub fn camera(&self) -> Vec<String> {
        let mut out = Vec::new();
        for (opt, v) in [
            ("--eye", &self.eye),
            ("--at", &self.at),
            ("--up", &self.up),
            ("--s", &self.s),
            ("--d", &self.d),
            ("--hither", &self.hither),
            ("--yon", &self.yon),
        ] {
            if let Some(v) = v {
                out.push(opt.to_string());
                out.push(v.clone());
            }
        }
        out
    }

    /// Checks the options against each other, as a local render uses them; `hosts` are
    /// --hosts' (checked already), `stdin_gives_none` chooses the scene when none is
    /// given. The scene itself is checked by [`check_scene`].
    pub fn validate(&self, hosts: Vec<String>, stdin_gives_none: bool) -> Result<Options, Error> {
        self.validate_in(methods::METHODS, hosts, stdin_gives_none)
    }

    /// [`Cli::validate`], with the methods of `table` (`methods::METHODS`, or a table
    /// with a row of a test's own).
    pub fn validate_in(
        &self,
        table: &[Method],
        hosts: Vec<String>,
        stdin_gives_none: bool,
    ) -> Result<Options, Error> {
        let usage = |m: String| Err(Error::usage(m));
        let depth = self.depth.and_then(Depth::fixed);
        let (width, height) = self.size;
        one_of("--hse", &self.hse, &methods::hse_names(table))?;
        let (hse, aa) = (self.hse.as_str(), self.aa.as_str());
        if self.split && hse != "painter" {
            return usage("--split is the painter's splitting step: it needs --hse painter".into());
        }
        let mut aa_names = vec!["none"];
        aa_names.extend(methods::aa_names(table));
        one_of("--aa", aa, &aa_names)?;
        // The leaf's stage: the anti-aliasing mode's, else the method's.
        let leaf = match methods::by_aa(table, aa) {
            Some(row) => row.stage_words(),
            None => methods::by_hse(table, hse).map_or_else(Vec::new, Method::stage_words),
        };
        // The methods and anti-aliasing modes are the leaves' own: PAR.BUFF sends every
        // fragment to the one zbuf, and anti-aliasing resolves with a z-buffer.
        if self.merge != Merge::Tiles && !(hse == "zbuf" && aa == "none") {
            return usage(format!(
                "--merge buffer is the z-buffer's, point-sampled: not with --hse {hse} --aa {aa}"
            ));
        }
        if hse != "zbuf" && aa != "none" {
            return usage(format!(
                "--aa {aa} is a z-buffer's anti-aliasing: not with --hse {hse}"
            ));
        }
        if self.pixels && self.merge != Merge::Buffer {
            return usage(
                "--pixels sends fragments to the one z-buffer: it needs --merge buffer".into(),
            );
        }
        if self.hidden_line_method.is_some() && !self.hidden_line {
            return usage("--hidden-line-method needs --hidden-line".into());
        }
        let mut leaf = leaf;
        if self.hidden_line {
            if let Some(m) = &self.hidden_line_method {
                one_of(
                    "--hidden-line-method",
                    m,
                    &methods::hidden_line_names(table),
                )?;
            }
            // The drawing's one stage after persp, from its row.
            let row = methods::by_hidden_line(table, self.hidden_line_method.as_deref());
            leaf = row.map_or_else(Vec::new, Method::stage_words);
            if let Some(d) = depth.filter(|d| *d != 0) {
                return usage(format!(
                    "--hidden-line draws at depth 0 (the tree's cuts are not edges), not --depth {d}"
                ));
            }
            if self.output.is_none() {
                return usage("--hidden-line needs -o FILE.svg".into());
            }
            // Its drawing has no hidden-surface method, samples or merger of its own to
            // change: options for those would be taken and do nothing.
            if hse != "zbuf" || aa != "none" || self.merge != Merge::Tiles || self.pixels {
                return usage("--hidden-line draws the visible edges: not with --hse, --aa, --merge buffer or --pixels".into());
            }
        }
        let mut subtree = None;
        if let Some(k) = &self.subtree {
            // A host's part of the tree is cut by the tree's depth, which --hosts gives it.
            let Some(d) = depth else {
                return usage(
                    "--subtree needs --depth N, the depth of the tree it is part of".into(),
                );
            };
            let nodes = (2u64 << d) - 1;
            match k.parse::<u64>() {
                Ok(n) if !k.starts_with('0') && n >= 1 && n <= nodes => subtree = Some(n),
                _ => {
                    return usage(format!(
                        "--subtree must be a node of the tree, 1 to {nodes}, not '{k}'"
                    ))
                }
            }
            if self.merge != Merge::Tiles || !hosts.is_empty() || self.hidden_line {
                return usage("--subtree is a host's part of --hosts: not with --merge buffer, --hosts or --hidden-line".into());
            }
        }
        if !hosts.is_empty() {
            if self.merge != Merge::Tiles {
                return usage(
                    "--hosts runs leaves that resolve their regions: not with --merge buffer"
                        .into(),
                );
            }
            if self.hidden_line {
                return usage("--hidden-line is drawn here: not with --hosts".into());
            }
        }
        let (scene, example) = match self.scene.as_slice() {
            [] if stdin_gives_none => (Scene::Path(crate::repository_example()), true),
            [] => (Scene::Stdin, false),
            [one] if one == "-" => (Scene::Stdin, false),
            [one] => (Scene::Path(one.into()), false),
            [a, b, ..] => {
                return usage(format!(
                    "more than one SCENE: '{}' and '{}'",
                    a.to_string_lossy(),
                    b.to_string_lossy()
                ))
            }
        };
        Ok(Options {
            size: format!("{width}x{height}"),
            width,
            height,
            depth,
            depth_asked: self.depth.is_some(),
            zmode: self.zmode,
            merge: self.merge,
            hse: self.hse.clone(),
            split: self.split,
            aa: self.aa.clone(),
            leaf,
            pixels: self.pixels,
            hidden_line: self.hidden_line,
            hidden_line_method: self.hidden_line_method.clone(),
            clip: self.clip,
            stats: self.stats,
            times: self.times,
            output: self.output.clone(),
            first_frame: self.first_frame,
            camera: self.camera(),
            hosts,
            remote_bin: self.remote_bin.clone(),
            subtree,
            scene,
            example,
        })
    }
}

/// The scene can be read (a folder is refused as the stages refuse one: `PATH: Is a
/// directory`), status 3. Asked of the file system (access(2)), not by opening it: a
/// named pipe opened and closed here would end its writer's stream.
pub fn check_scene(scene: &Scene) -> Result<(), Error> {
    use std::os::unix::ffi::OsStrExt;
    let Scene::Path(p) = scene else {
        return Ok(());
    };
    let readable = std::ffi::CString::new(p.as_os_str().as_bytes())
        // SAFETY: access reads the NUL-terminated path it is given, and nothing else.
        .is_ok_and(|c| unsafe { libc::access(c.as_ptr(), libc::R_OK) } == 0);
    match std::fs::metadata(p) {
        Ok(m) if m.is_dir() => Err(Error::io(format!("{}: Is a directory", p.display()))),
        Ok(_) if readable => Ok(()),
        _ => Err(Error::io(format!("cannot read scene {}", p.display()))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cli(args: &[&str]) -> Result<Options, Error> {
        let args = std::iter::once("render")
            .chain(args.iter().copied())
            .map(OsString::from);
        match parse(args)? {
            Parsed::Run(c) => c.validate(Vec::new(), false),
            Parsed::Print(_) => panic!("help"),
        }
    }

    fn refused(args: &[&str]) -> String {
        let e = cli(args).unwrap_err();
        assert_eq!(e.kind(), stagecli::Kind::Usage, "{args:?}");
        e.message().to_string()
    }

    #[test]
    fn each_refusal_is_one_line_naming_the_option_as_typed() {
        for (args, said) in [
            (
                &["--zmode", "foo"][..],
                "--zmode must be reciprocal, projective or eye-z, not 'foo'",
            ),
            (
                &["--zmode=bar"],
                "--zmode must be reciprocal, projective or eye-z, not 'bar'",
            ),
            (
                &["--depth", "7"],
                "--depth must be an integer from 0 to 6 or auto, not '7'",
            ),
            (
                &["--size", "65537x10"],
                "--size must be WxH with W and H from 1 to 65536, not '65537x10'",
            ),
            (
                &["--size", "0x0"],
                "--size must be WxH with W and H from 1 to 65536, not '0x0'",
            ),
            (&["--size"], "--size needs a value"),
            (&["--stats=yes"], "--stats takes no value"),
            (&["--bogus=1"], "unknown option --bogus"),
            (&["--bogus"], "unknown option --bogus"),
            (
                &["a.txt", "b.txt"],
                "more than one SCENE: 'a.txt' and 'b.txt'",
            ),
            (
                &["--merge", "zbuf"],
                "--merge must be tiles or buffer, not 'zbuf'",
            ),
            (
                &["--split"],
                "--split is the painter's splitting step: it needs --hse painter",
            ),
            (
                &["--subtree", "4", "--depth", "1"],
                "--subtree must be a node of the tree, 1 to 3, not '4'",
            ),
            (
                &["--subtree", "1"],
                "--subtree needs --depth N, the depth of the tree it is part of",
            ),
            (&["--hidden-line"], "--hidden-line needs -o FILE.svg"),
            (
                &["--hidden-line", "--hidden-line-method", "exact"],
                "--hidden-line-method must be continuous or archuleta, not 'exact'",
            ),
            (
                &["--first-frame", "-1"],
                "--first-frame must be a frame number, 0 or more, not '-1'",
            ),
        ] {
            assert_eq!(refused(args), said, "{args:?}");
        }
        // The methods' names are the table's (methods::METHODS), whatever it holds.
        let hse = methods::hse_names(methods::METHODS);
        assert_eq!(
            refused(&["--hse", "zsort"]),
            format!("--hse must be {}, not 'zsort'", either(&hse))
        );
        let mut aa = vec!["none"];
        aa.extend(methods::aa_names(methods::METHODS));
        assert_eq!(
            refused(&["--aa", "ss3"]),
            format!("--aa must be {}, not 'ss3'", either(&aa))
        );
        assert!(hse.contains(&"zbuf") && either(&["a", "b", "c"]) == "a, b or c");
    }

    #[test]
    fn values_are_kept_as_given_and_the_last_repeat_wins() {
        let o = cli(&[
            "--size=0640X480",
            "--depth",
            "3",
            "--eye",
            "-1,2,3",
            "--s",
            "-2",
            "--size",
            "64x32",
            "-",
        ])
        .unwrap();
        assert_eq!((o.width, o.height, o.depth), (64, 32, Some(3)));
        assert_eq!(o.camera, ["--eye", "-1,2,3", "--s", "-2"]);
        assert_eq!(o.scene, Scene::Stdin);
        let o = cli(&[]).unwrap();
        assert_eq!(
            (o.depth, o.scene.clone(), o.example),
            (None, Scene::Stdin, false)
        );
    }

    #[test]
    fn each_leaf_stage_is_its_rows_in_the_table_of_methods() {
        for row in methods::METHODS {
            let args: Vec<&str> = match row.selector {
                methods::Selector::Hse(n) => vec!["--hse", n],
                methods::Selector::Aa(n) => vec!["--aa", n],
                _ => continue,
            };
            assert_eq!(cli(&args).unwrap().leaf, row.stage, "{args:?}");
        }
        assert_eq!(cli(&[]).unwrap().leaf, ["scanconv", "--resolve"]);
        // A row of another table: its name taken, its stage at the leaves.
        let row = methods::Method {
            name: "nearest",
            selector: methods::Selector::Hse("nearest"),
            options: &["--hse", "nearest"],
            stage: &["nearest", "--brute"],
            ..methods::METHODS[0]
        };
        let table = [row];
        let args = ["render", "--hse", "nearest"].map(OsString::from);
        let Ok(Parsed::Run(c)) = parse(args) else {
            panic!("options")
        };
        let o = c.validate_in(&table, Vec::new(), false).unwrap();
        assert_eq!(o.leaf, ["nearest", "--brute"]);
        assert_eq!(
            c.validate(Vec::new(), false).unwrap_err().message(),
            format!(
                "--hse must be {}, not 'nearest'",
                either(&methods::hse_names(methods::METHODS))
            )
        );
    }

    #[test]
    fn sizes_are_the_stages_bounds() {
        assert_eq!(parse_size("65536x1"), Some((65536, 1)));
        assert_eq!(parse_size("007x08"), Some((7, 8)));
        for bad in ["65537x1", "0x5", "x5", "5x", "5", "1x-1", "+1x1", "1x1x1"] {
            assert_eq!(parse_size(bad), None, "{bad}");
        }
    }
}
