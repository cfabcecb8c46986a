//! The command-line conventions every stage shares: `--version` and `--help` on every
//! binary, `--text`, the camera options, and usage errors as one line.

use crate::Error;
use clap::error::ErrorKind;
use clap::{ArgMatches, Command};
use proto::camera::{parse_size, parse_triple, Camera, EyeFrame};
use proto::perspective::DepthMode;
use proto::text::Shown;
use proto::{DVec3, Form, View};
use std::ffi::OsString;
use std::io::Write;
use std::process::ExitCode;

/// The depth a screen-space stream carries, `--zmode MODE` on every binary that projects
/// (`persp`, `zbuf --project`, `splitter --project`, fused):
/// [`proto::perspective::DepthMode`] on the command line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum DepthArg {
    /// D = −K1/z_e: −1 at hither, −K1/K2 at yon, linear on the screen, and held by an f64
    /// to 2⁻⁵³ of itself at every depth (the tie rule's form, docs/DESIGN.md).
    #[default]
    Reciprocal,
    /// z_s = (1 − K1/z_e)·K2/(K2 − K1): 0 at hither, 1 at yon, linear on the screen, but
    /// crowded against 1 far from the eye (the classic z-buffer's precision failure).
    Projective,
    /// z_e itself, as the thesis's occam code does. An approximation (z_e is not linear on
    /// the screen): each polygon's depth plane is fitted to its own screen vertices, so a
    /// splitter tree need not render it exactly as depth 0 does.
    EyeZ,
}

impl DepthArg {
    /// The mode's name as the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            DepthArg::Reciprocal => "reciprocal",
            DepthArg::Projective => "projective",
            DepthArg::EyeZ => "eye-z",
        }
    }
}

impl From<DepthArg> for DepthMode {
    fn from(arg: DepthArg) -> DepthMode {
        match arg {
            DepthArg::Reciprocal => DepthMode::Reciprocal,
            DepthArg::Projective => DepthMode::Projective,
            DepthArg::EyeZ => DepthMode::EyeZ,
        }
    }
}

/// The note a stage prints on stderr when an option is given by its old name, which is
/// still accepted for one release: `persp: --depth MODE is now --zmode MODE; the old
/// spelling goes in the next release`.
pub fn renamed(stage: &str, old: &str, new: &str) -> String {
    format!("{stage}: {old} is now {new}; the old spelling goes in the next release")
}

/// The depth form of a stage that projects to the screen on request (`zbuf`,
/// `splitter`): `--project` asks for the projection, `--zmode MODE` says its depth
/// (default reciprocal), and `--persp MODE`, the old spelling of both, is still taken,
/// with [`renamed`]'s note on stderr. `None`: no projection. `--zmode` without
/// `--project` is a usage error (the caller's clap refuses `--persp` beside either).
pub fn projection(
    stage: &str,
    project: bool,
    zmode: Option<DepthArg>,
    persp: Option<DepthArg>,
) -> Result<Option<DepthArg>, Error> {
    match (project, zmode, persp) {
        (_, _, Some(mode)) => {
            let note = renamed(stage, "--persp MODE", "--project --zmode MODE");
            let _ = writeln!(std::io::stderr(), "{note}");
            Ok(Some(mode))
        }
        (true, zmode, None) => Ok(Some(zmode.unwrap_or_default())),
        (false, Some(mode), None) => Err(Error::usage(format!(
            "--zmode {} is for --project (the depth its projection writes)",
            mode.name()
        ))),
        (false, None, None) => Ok(None),
    }
}

/// Parses `R,G,B` (each 0–255), for `--background`; the messages are zbuf's.
pub fn parse_colour(s: &str) -> Result<proto::Colour, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!(
            "expected R,G,B (three numbers 0-255), got `{}`",
            Shown(s)
        ));
    }
    let mut c = [0u8; 3];
    for (slot, p) in c.iter_mut().zip(parts) {
        *slot = p
            .parse()
            .map_err(|_| format!("`{}` is not a colour component 0-255", Shown(p)))?;
    }
    Ok(c)
}

/// Parses the command line of stage `stage` into `C`.
///
/// `--help` and `--version` print as clap prints them and give `Err(0)`; any other
/// problem prints one line, `stage: message` naming the option as typed, and gives
/// `Err(2)`. Every binary gets `--version` (the workspace's version) whether or not its
/// `#[command]` asks for it.
pub fn parse<C: clap::Parser>(stage: &str) -> Result<C, ExitCode> {
    parse_from(stage, std::env::args_os())
}

/// [`parse`] from the given words (the first is the program's name).
pub fn parse_from<C, I, T>(stage: &str, args: I) -> Result<C, ExitCode>
where
    C: clap::Parser,
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let args: Vec<OsString> = args.into_iter().map(Into::into).collect();
    let mut cmd = command::<C>();
    let parsed = cmd
        .try_get_matches_from_mut(args.clone())
        .and_then(|mut m: ArgMatches| C::from_arg_matches_mut(&mut m));
    parsed.map_err(|e| {
        let e = e.format(&mut cmd);
        match e.kind() {
            ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
                let _ = e.print();
                ExitCode::SUCCESS
            }
            _ => {
                // A subcommand's missing subcommand lists its own (`scene screen`).
                cmd.build();
                let sub = subcommand_named(&cmd, &args);
                let _ = writeln!(std::io::stderr(), "{stage}: {}", usage_line(&e, sub));
                ExitCode::from(Error::usage("").kind().status())
            }
        }
    })
}

/// The innermost subcommand of `cmd` that `args` (the program's name first) name, in
/// turn: `scene screen` is `screen`'s, whose own subcommands a message lists.
fn subcommand_named<'a>(cmd: &'a Command, args: &[OsString]) -> &'a Command {
    let mut at = cmd;
    for word in args.iter().skip(1).filter_map(|a| a.to_str()) {
        if let Some(sub) = at.find_subcommand(word) {
            at = sub;
        }
    }
    at
}

/// The stage's clap command with the conventions applied (a version everywhere, and
/// [`hyphen_values`]).
pub fn command<C: clap::CommandFactory>() -> Command {
    let cmd = C::command();
    let cmd = if cmd.get_version().is_none() {
        cmd.version(env!("CARGO_PKG_VERSION"))
    } else {
        cmd
    };
    hyphen_values(cmd.propagate_version(true))
}

/// A value that starts with `-` is the value of the option before it, in every
/// subcommand: `--cores -1`, `--size -5x5`, `--background -1,0,0` are refused by the
/// option's own parser, naming the option and its range, rather than taken for an
/// unknown option `-1`. An option that takes exactly one value takes the next word
/// whatever it is; an option with an optional value, or several, and a positional
/// argument take a negative number (`scene stack -3`) but not a word such as `--text`.
pub fn hyphen_values(cmd: Command) -> Command {
    cmd.mut_args(|a| {
        if !a.get_action().takes_values() {
            return a;
        }
        let one = a
            .get_num_args()
            .is_none_or(|n| n.min_values() == 1 && n.max_values() == 1);
        if one && !a.is_positional() {
            a.allow_hyphen_values(true)
        } else {
            a.allow_negative_numbers(true)
        }
    })
    .mut_subcommands(hyphen_values)
}

/// A clap error as one line without the program name: clap's own message, with its
/// further lines (the missing arguments, the possible values, a similar option's name)
/// joined on, and its usage block, "For more information" and the tip about `--`
/// dropped. A missing subcommand, for which clap
/// prints the whole help, lists the subcommands.
pub fn usage_line(e: &clap::Error, cmd: &Command) -> String {
    if matches!(
        e.kind(),
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand | ErrorKind::MissingSubcommand
    ) {
        let names: Vec<&str> = cmd
            .get_subcommands()
            .map(Command::get_name)
            .filter(|n| *n != "help")
            .collect();
        // A subcommand built by its parent is named `parent-sub`; a person types
        // `parent sub`.
        let name = cmd.get_bin_name().unwrap_or(cmd.get_name());
        return format!(
            "give a subcommand: {} (`{name} --help` describes them)",
            names.join(", "),
        );
    }
    let text = e.render().to_string();
    let text = text.strip_prefix("error: ").unwrap_or(&text);
    let mut parts = Vec::new();
    for line in text.lines().map(str::trim) {
        if line.starts_with("Usage:") || line.starts_with("For more information") {
            break;
        }
        match line.strip_prefix("tip: ") {
            Some(tip) if !tip.starts_with("to pass") => parts.push(format!("({tip})")),
            Some(_) => {}
            None if !line.is_empty() => parts.push(line.to_string()),
            None => {}
        }
    }
    cut_long_words(&parts.join(" "))
}

/// A message with each word longer than [`proto::text::SHOWN_CHARS`] characters cut, as
/// [`Shown`] cuts a word of the input: clap quotes a value whole (`invalid value
/// '99…9' for '--cores <N>'`), and an argument may be 128 KiB long.
pub fn cut_long_words(line: &str) -> String {
    let max = proto::text::SHOWN_CHARS;
    let words: Vec<String> = line
        .split(' ')
        .map(|w| match w.char_indices().nth(max) {
            Some((cut, _)) => {
                let close = w
                    .ends_with(['\'', '`', ',', ':'])
                    .then(|| &w[w.len() - 1..]);
                format!("{}… ({} bytes){}", &w[..cut], w.len(), close.unwrap_or(""))
            }
            None => w.to_string(),
        })
        .collect();
    words.join(" ")
}

/// `--text`: write the stream's text form instead of binary.
#[derive(Clone, Copy, Debug, Default, clap::Args)]
pub struct TextFlag {
    /// Write the text form instead of binary.
    #[arg(long)]
    pub text: bool,
}

impl TextFlag {
    pub fn form(self) -> Form {
        Form::from_text_flag(self.text)
    }
}

/// `--text` for the stages that write pictures (zbuf, zspec): plain PPM.
#[derive(Clone, Copy, Debug, Default, clap::Args)]
pub struct PpmTextFlag {
    /// Write plain PPM (P3: the pixel values as decimal text) instead of binary PPM (P6).
    #[arg(long)]
    pub text: bool,
}

impl PpmTextFlag {
    pub fn form(self) -> proto::ppm::Form {
        if self.text {
            proto::ppm::Form::Plain
        } else {
            proto::ppm::Form::Binary
        }
    }
}

/// The camera and view-volume options, shared by every binary that views a world-space
/// scene (`viewxf`, and the exact reference `zspec`) so that they read the same words.
/// A negative number is taken as the value it is (`--s -3`, `--hither -1`), so that the
/// message says what is wrong with it rather than that `-3` is not an option.
#[derive(Clone, Debug, clap::Args)]
pub struct ViewArgs {
    /// Where the eye is, `X,Y,Z` (default: the thesis's 0,0,20).
    #[arg(long, value_parser = parse_triple, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub eye: Option<DVec3>,
    /// The point looked at, `X,Y,Z` (default 0,0,0).
    #[arg(long, value_parser = parse_triple, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub at: Option<DVec3>,
    /// Which way is up, `X,Y,Z` (default 0,1,0).
    #[arg(long, value_parser = parse_triple, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub up: Option<DVec3>,
    /// s: half the screen height, in eye units at distance d.
    #[arg(long, allow_negative_numbers = true, default_value_t = 10.0)]
    pub s: f64,
    /// d: the eye-to-screen distance.
    #[arg(long, allow_negative_numbers = true, default_value_t = 16.0)]
    pub d: f64,
    /// The screen's aspect ratio W/H (default 1, or W/H of --size).
    #[arg(long, conflicts_with = "size", allow_negative_numbers = true)]
    pub aspect: Option<f64>,
    /// The screen size the scene will be drawn at, `WxH`; sets the aspect ratio.
    #[arg(long, value_parser = parse_size, value_name = "WxH")]
    pub size: Option<(u32, u32)>,
    /// K1: the hither plane z_e = K1.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
    pub hither: f64,
    /// K2: the yon plane z_e = K2.
    #[arg(long, allow_negative_numbers = true, default_value_t = 30.0)]
    pub yon: f64,
}

/// `X,Y,Z` as the options take it.
fn triple(v: DVec3) -> String {
    format!("{},{},{}", v.x, v.y, v.z)
}

impl ViewArgs {
    /// The camera the options describe.
    pub fn camera(&self) -> Camera {
        let default = Camera::default();
        Camera {
            eye: self.eye.unwrap_or(default.eye),
            at: self.at.unwrap_or(default.at),
            up: self.up.unwrap_or(default.up),
            s: self.s,
            d: self.d,
        }
    }

    /// The eye frame and the view volume, checked: a usage error names the options that
    /// cannot be viewed through (eye = at, up along the view direction, hither ≥ yon, …).
    pub fn resolve(&self) -> Result<(EyeFrame, View), Error> {
        let camera = self.camera();
        let frame = camera.frame().map_err(|why| {
            // Camera::frame checks the view direction, then up, then s and d.
            let f = camera.at - camera.eye;
            let options = if !(f.length_squared() > 0.0 && f.is_finite()) {
                format!("--eye {} --at {}", triple(camera.eye), triple(camera.at))
            } else if f.cross(camera.up).length_squared() <= 0.0 {
                format!(
                    "--up {} (looking from {} to {})",
                    triple(camera.up),
                    triple(camera.eye),
                    triple(camera.at)
                )
            } else {
                format!("--s {} --d {}", camera.s, camera.d)
            };
            Error::usage(format!("{options}: {why}"))
        })?;
        Ok((frame, self.view()?))
    }

    /// The view volume the options describe, checked.
    pub fn view(&self) -> Result<View, Error> {
        let aspect = match (self.aspect, self.size) {
            (Some(a), _) => a,
            (None, Some((w, h))) => w as f64 / h as f64,
            (None, None) => 1.0,
        };
        if !(aspect.is_finite() && aspect > 0.0) {
            return Err(Error::usage(format!(
                "--aspect {aspect}: the aspect ratio must be a positive number"
            )));
        }
        if !(self.hither.is_finite()
            && self.yon.is_finite()
            && 0.0 < self.hither
            && self.hither < self.yon)
        {
            return Err(Error::usage(format!(
                "--hither {} --yon {}: they must satisfy 0 < hither < yon",
                self.hither, self.yon
            )));
        }
        Ok(View {
            aspect,
            hither: self.hither,
            yon: self.yon,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::{FromArgMatches, Parser};

    #[derive(Parser, Debug)]
    #[command(name = "demo")]
    struct Demo {
        #[arg(long, value_parser = parse_size, value_name = "WxH")]
        size: (u32, u32),
        #[arg(long, value_enum, default_value = "a")]
        mode: Mode,
        #[command(flatten)]
        text: TextFlag,
    }

    #[derive(Clone, Copy, Debug, clap::ValueEnum)]
    enum Mode {
        A,
        BeeCee,
    }

    fn line(args: &[&str]) -> String {
        let mut cmd = command::<Demo>();
        let e = cmd
            .try_get_matches_from_mut(std::iter::once("demo").chain(args.iter().copied()))
            .and_then(|mut m| Demo::from_arg_matches_mut(&mut m))
            .unwrap_err();
        let e = e.format(&mut cmd);
        usage_line(&e, &cmd)
    }

    #[test]
    fn usage_errors_are_one_line_naming_the_option() {
        assert_eq!(
            line(&["--size", "0x4"]),
            "invalid value '0x4' for '--size <WxH>': `0` in `0x4` is not a size from 1 to 65536"
        );
        assert_eq!(
            line(&["--size", "4x4", "--mode", "c"]),
            "invalid value 'c' for '--mode <MODE>' [possible values: a, bee-cee]"
        );
        assert_eq!(
            line(&[]),
            "the following required arguments were not provided: --size <WxH>"
        );
        assert_eq!(
            line(&["--size", "4x4", "--bogus"]),
            "unexpected argument '--bogus' found"
        );
        assert_eq!(
            line(&["--sise", "4x4"]),
            "unexpected argument '--sise' found (a similar argument exists: '--size')"
        );
        for args in [&["--size", "4x4", "--text", "--text"][..], &["--size"]] {
            let l = line(args);
            assert!(!l.contains('\n') && !l.is_empty(), "{l}");
        }
    }

    #[test]
    fn every_binary_has_a_version() {
        let e = command::<Demo>()
            .try_get_matches_from(["demo", "--version"])
            .unwrap_err();
        assert_eq!(e.kind(), ErrorKind::DisplayVersion);
        assert_eq!(
            e.to_string(),
            format!("demo {}\n", env!("CARGO_PKG_VERSION"))
        );
        let d = Demo::try_parse_from(["demo", "--size", "2x3", "--text"]).unwrap();
        assert_eq!((d.size, d.text.form()), ((2, 3), Form::Text));
    }

    #[test]
    fn camera_errors_name_their_options() {
        let mut v = ViewArgs::try_parse_from_view(&["--eye", "0,0,0"]);
        assert_eq!(
            v.resolve().unwrap_err().to_string(),
            "--eye 0,0,0 --at 0,0,0: the eye and the point looked at must differ"
        );
        v = ViewArgs::try_parse_from_view(&["--up", "0,0,-1"]);
        assert_eq!(
            v.resolve().unwrap_err().to_string(),
            "--up 0,0,-1 (looking from 0,0,20 to 0,0,0): the up vector must not be \
             parallel to the view direction"
        );
        v = ViewArgs::try_parse_from_view(&["--hither", "5", "--yon", "2"]);
        let e = v.resolve().unwrap_err();
        assert_eq!(e.kind(), crate::Kind::Usage);
        assert_eq!(
            e.to_string(),
            "--hither 5 --yon 2: they must satisfy 0 < hither < yon"
        );
        v = ViewArgs::try_parse_from_view(&["--aspect", "nan"]);
        assert!(v
            .resolve()
            .unwrap_err()
            .to_string()
            .starts_with("--aspect NaN"));
        v = ViewArgs::try_parse_from_view(&["--s", "0"]);
        assert!(v
            .resolve()
            .unwrap_err()
            .to_string()
            .starts_with("--s 0 --d 16: "));
        // A negative value is the option's value, and the message says what is wrong
        // with it (clap took `-3` for an unknown option before).
        for (args, message) in [
            (
                ["--s", "-3"],
                "--s -3 --d 16: s = -3 and d = 16 must be positive",
            ),
            (
                ["--hither", "-1"],
                "--hither -1 --yon 30: they must satisfy 0 < hither < yon",
            ),
            (
                ["--aspect", "-2"],
                "--aspect -2: the aspect ratio must be a positive number",
            ),
        ] {
            let v = ViewArgs::try_parse_from_view(&args);
            assert_eq!(v.resolve().unwrap_err().to_string(), message);
        }
    }

    #[test]
    fn depth_arg_names_are_the_command_line_s() {
        use clap::ValueEnum;
        for mode in DepthArg::value_variants() {
            let value = mode.to_possible_value().unwrap();
            assert_eq!(mode.name(), value.get_name());
        }
        assert_eq!(DepthArg::default(), DepthArg::Reciprocal);
    }

    /// `--project [--zmode MODE]` and the old `--persp MODE`: the depth form asked, none
    /// without a projection, and `--zmode` alone refused naming what it is for.
    #[test]
    fn projection_reads_project_zmode_and_the_old_persp() {
        use DepthArg::*;
        let p = |project, zmode, persp| projection("demo", project, zmode, persp);
        assert_eq!(p(false, None, None).unwrap(), None);
        assert_eq!(p(true, None, None).unwrap(), Some(Reciprocal));
        assert_eq!(p(true, Some(EyeZ), None).unwrap(), Some(EyeZ));
        assert_eq!(p(false, None, Some(Projective)).unwrap(), Some(Projective));
        let e = p(false, Some(Projective), None).unwrap_err();
        assert_eq!(e.kind(), crate::Kind::Usage);
        assert_eq!(
            e.to_string(),
            "--zmode projective is for --project (the depth its projection writes)"
        );
        assert_eq!(
            renamed("persp", "--depth MODE", "--zmode MODE"),
            "persp: --depth MODE is now --zmode MODE; the old spelling goes in the next release"
        );
    }

    impl ViewArgs {
        fn try_parse_from_view(args: &[&str]) -> ViewArgs {
            #[derive(Parser)]
            struct V {
                #[command(flatten)]
                v: ViewArgs,
            }
            V::try_parse_from(std::iter::once("v").chain(args.iter().copied()))
                .unwrap()
                .v
        }
    }
}
