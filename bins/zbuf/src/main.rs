//! zbuf: fragments from one or many scan converters in, one PPM per frame out.

use clap::Parser;
use proto::Colour;
use scan::abuf::ABuffer;
use scan::frame::HiddenSurface;
use scan::supersample::Supersample;
use stagecli::stats::Record;
use stagecli::{Error, PpmTextFlag, ProjectArgs};
use std::io::{self, Write};
use std::process::ExitCode;
use zbuf::par_buff::{par_buff, Input};
use zbuf::{parse_colour, FramePattern, ImageFormat};

/// The Z-buffer (thesis BUFFER / PAR.BUFF, ch. 4.2.3 and 6.3.3).
///
/// Reads fragment streams from scanconv, all inputs at once, keeps for each pixel the
/// nearest polygon (the earlier one on a tie), and writes each frame as a binary PPM (P6;
/// plain P3 with --text) when every input has finished it: frames concatenated on
/// stdout, or one file per frame. An input may also be a screen-space polygon stream
/// (persp's output): zbuf then scan-converts and depth-tests it itself, as
/// `scanconv --resolve` would, and places the result; with --project, an eye-space one
/// (the clipper's output), projected here as persp would (render.sh --depth 0 runs
/// `clipbatch | zbuf --project --size WxH`). With --aa MODE such an input is resolved by
/// an anti-aliasing leaf's method instead (supersample's or abuf's, their bytes): render
/// --aa MODE at depth 0.
///
/// Examples:
///   persp --size 500x500 < eye.pp | scanconv | zbuf > frame.ppm
///   persp --size 500x500 < eye.pp | zbuf > frame.ppm
///   zbuf --project --size 500x500 < eye.pp > frame.ppm
///   zbuf --project --size 500x500 --aa adaptive4 < eye.pp > frame.ppm
///   zbuf --project --zmode eye-z --size 500x500 < eye.pp > frame.ppm
///   zbuf --background 20,20,40 -o frame%04d.png left.frag right.frag
///   scene spheres --frames 100 | viewxf | clipplane left | ... | clipplane yon \
///     | persp --size 500x500 | scanconv | zbuf --progress -o frame%03d.png
///   mkfifo a b; scanconv < a.pp > a & scanconv < b.pp > b & zbuf a b | ffmpeg -f image2pipe -i - out.mp4
#[derive(Parser)]
#[command(name = "zbuf", version, verbatim_doc_comment)]
struct Args {
    /// Fragment streams, or screen-space polygon streams to resolve here (files or named
    /// pipes; `-` or none for stdin, at most once), read concurrently.
    inputs: Vec<String>,
    /// Background colour R,G,B.
    #[arg(long, value_parser = parse_colour, default_value = "0,0,0")]
    background: Colour,
    /// Write one file per frame instead of PPMs on stdout: `%d` or `%0Nd` in the name is
    /// the frame number from 0 (as ffmpeg's image2); .png or .ppm by the extension.
    #[arg(short = 'o', value_name = "PATTERN")]
    output: Option<String>,
    /// The number -o's pattern gives the first frame (the rest follow it): a chunk of a
    /// movie rendered on its own (`frames --from A --to B | … --first-frame A`) writes
    /// the files the whole movie's run would.
    #[arg(long, value_name = "N", default_value_t = 0, requires = "output",
          value_parser = stagecli::numbers::whole::<u64>(0, u64::MAX))]
    first_frame: u64,
    #[command(flatten)]
    text: PpmTextFlag,
    /// Pass the frames on as runs (a fragment stream, binary; text with --text) instead
    /// of pictures: the merger of a subtree of the splitter tree that runs on another
    /// host, whose leaves resolve their regions (runs only).
    #[arg(long, conflicts_with = "output")]
    runs: bool,
    /// Print, per input, the spans and pixels received (for a screen-space input, the
    /// polygons read and the pixels tested), on stderr at the end.
    #[arg(long)]
    stats: bool,
    #[command(flatten)]
    project: ProjectArgs,
    /// The screen's size in pixels, `WxH`, for --project.
    #[arg(long, value_parser = proto::camera::parse_size, value_name = "WxH")]
    size: Option<(u32, u32)>,
    /// Show frames done and frames per second on stderr while rendering; does nothing
    /// when stderr is not a terminal (redirected to a file or a pipe).
    #[arg(long)]
    progress: bool,
    /// Resolve the one polygon input here with an anti-aliasing leaf's method instead of
    /// the z-buffer (render's --aa at depth 0: the leaf and the merger in one process):
    /// ssK (`supersample --samples K`, K = 2, 4, 8 or 16), adaptiveK (`supersample
    /// --samples K --adaptive`) or abuf (`abuf`), each that leaf's bytes; none (the
    /// default) is the z-buffer.
    #[arg(long, value_name = "MODE", value_parser = parse_aa, default_value = "none")]
    aa: Aa,
}

/// zbuf's `--aa`: the anti-aliasing leaf whose method resolves a polygon input here.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Aa {
    None,
    Supersample { k: u32, adaptive: bool },
    ABuffer,
}

fn parse_aa(s: &str) -> Result<Aa, String> {
    let sampled = |digits: &str, adaptive| match digits.parse::<u32>() {
        Ok(k) if [2, 4, 8, 16].contains(&k) => Some(Aa::Supersample { k, adaptive }),
        _ => None,
    };
    match s {
        "none" => Some(Aa::None),
        "abuf" => Some(Aa::ABuffer),
        _ => match (s.strip_prefix("ss"), s.strip_prefix("adaptive")) {
            (Some(d), _) => sampled(d, false),
            (_, Some(d)) => sampled(d, true),
            _ => None,
        },
    }
    .ok_or_else(|| "not none, ssK, adaptiveK (K = 2, 4, 8 or 16) or abuf".to_string())
}

impl Aa {
    /// The leaf stage whose method this is, as messages name it.
    fn leaf(self) -> &'static str {
        match self {
            Aa::None => "zbuf",
            Aa::Supersample { .. } => "supersample",
            Aa::ABuffer => "abuf",
        }
    }

    /// The leaf's method, with the background its uncovered samples show.
    fn method(self, background: Colour) -> Option<Box<dyn HiddenSurface + Send>> {
        match self {
            Aa::None => None,
            Aa::Supersample { k, adaptive } => {
                let m = Supersample::new(k, background).ok()?;
                Some(Box::new(if adaptive { m.adaptive() } else { m }))
            }
            Aa::ABuffer => Some(Box::new(ABuffer::new(background))),
        }
    }
}

/// What the arguments ask, checked before any input is read.
struct Plan {
    /// Where the frames go: files named by the pattern, or stdout.
    pattern: Option<FramePattern>,
    /// The inputs, `-` for stdin.
    names: Vec<String>,
    /// With --project: the screen and depth eye-space inputs are projected to.
    to_screen: Option<zbuf::par_buff::ToScreen>,
}

fn plan(args: &Args) -> Result<Plan, Error> {
    let depth = args.project.depth("zbuf")?;
    let to_screen = match (depth, args.size) {
        (Some(depth), Some((width, height))) => Some(zbuf::par_buff::ToScreen {
            width,
            height,
            depth: depth.into(),
        }),
        (None, Some(_)) => return Err(Error::usage("--size is for --project")),
        // clap has asked --size of --project and --persp.
        _ => None,
    };
    let pattern = args
        .output
        .as_deref()
        .map(FramePattern::parse)
        .transpose()
        .map_err(Error::usage)?;
    if args.text.text
        && pattern
            .as_ref()
            .is_some_and(|p| p.format == ImageFormat::Png)
    {
        return Err(Error::usage(format!(
            "--text writes plain PPM, but -o {} asks for PNG: name .ppm files or leave out --text",
            args.output.as_deref().unwrap_or_default()
        )));
    }
    if args.aa != Aa::None && (args.inputs.len() > 1 || args.runs) {
        return Err(Error::usage(
            "--aa resolves one polygon input into pictures: not with several inputs or --runs",
        ));
    }
    if args.inputs.iter().filter(|i| *i == "-").count() > 1 {
        return Err(Error::usage(
            "`-` (stdin) is named more than once: it can be read only once",
        ));
    }
    let names = if args.inputs.is_empty() {
        vec!["-".to_string()]
    } else {
        args.inputs.clone()
    };
    Ok(Plan {
        pattern,
        names,
        to_screen,
    })
}

fn main() -> ExitCode {
    stagecli::main("zbuf", |args: Args| {
        let Plan {
            pattern,
            names,
            to_screen,
        } = plan(&args)?;
        let form = args.text.form();
        let mut inputs: Vec<Input> = names
            .iter()
            .map(|name| {
                let path = name.clone();
                Input {
                    to_screen,
                    name: stagecli::input_name(name).to_string(),
                    // par_buff names the input in every message about it.
                    open: Box::new(move || Ok(stagecli::stream::open(&path)?)),
                }
            })
            .collect();
        let mut out = io::BufWriter::with_capacity(1 << 16, stagecli::stdout());
        let progress = zbuf::frame_progress(args.progress);
        let mut relay: Option<proto::Writer<proto::Fragment, _>> = None;
        let on_frame = |frame: u64, fb: &zbuf::FrameBuffer| -> stagecli::Result<()> {
            if args.runs {
                let out = match &mut relay {
                    Some(w) => w,
                    None => relay.insert(stagecli::write_stdout(
                        proto::Header::new(proto::Space::Fragments {
                            width: fb.width(),
                            height: fb.height(),
                        }),
                        proto::Form::from_text_flag(args.text.text),
                    )?),
                };
                if frame > 0 {
                    out.write(&proto::Fragment::NextFrame)?;
                }
                let runs = fb.runs().ok_or_else(|| {
                    Error::data(format!(
                        "frame {frame}: --runs passes on finished runs, but spans or pixels came (leaves that resolve send runs only)"
                    ))
                })?;
                for (y, x0, x1, colour) in runs {
                    out.write(&proto::Fragment::Run { y, x0, x1, colour })?;
                }
                out.flush()?;
                return Ok(());
            }
            match &pattern {
                // Known only once a second frame comes: the input is a movie where one
                // picture was asked for (so not a usage error, found before reading).
                // The first frame's picture is taken back: a movie cut to its first
                // frame is not what was asked for.
                Some(p) if frame > 0 && !p.numbered() => {
                    let _ = std::fs::remove_file(p.path(0));
                    let name = args.output.as_deref().unwrap_or_default();
                    return Err(Error::data(format!(
                        "-o {name}: the input is a movie (a second frame came), and {name} \
                         names one picture: give a pattern with %d for the frame number \
                         (as frame%03d.png); nothing was kept"
                    )));
                }
                Some(p) => {
                    let number = frame.checked_add(args.first_frame).ok_or_else(|| {
                        Error::data(format!(
                            "frame {frame}: --first-frame {} numbers it past {}",
                            args.first_frame,
                            u64::MAX
                        ))
                    })?;
                    p.save(number, fb, form)?
                }
                None => {
                    fb.write_ppm(&mut out, form)?;
                    out.flush()?;
                }
            }
            progress.inc(1);
            stagecli::progress::frame_done();
            Ok(())
        };
        // One input and pictures out: a screen-space input is resolved and painted in
        // this thread, with nothing passed between threads (`one_input`).
        let mut method = args.aa.method(args.background);
        let stats = if inputs.len() == 1 && !args.runs {
            let m = match &mut method {
                Some(m) => Some(zbuf::par_buff::Leaf {
                    name: args.aa.leaf(),
                    method: &mut **m,
                }),
                None => None,
            };
            zbuf::par_buff::one_input(inputs.remove(0), args.background, m, on_frame)
        } else {
            par_buff(inputs, args.background, args.runs, on_frame)
        };
        // Leave the last count on the terminal, its line ended (also after an error, so
        // that the message starts a line of its own).
        progress.abandon();
        if !progress.is_hidden() {
            eprintln!();
        }
        let stats = stats?;
        if let Some(mut out) = relay {
            out.write(&proto::Fragment::End)?;
            out.flush()?;
        }
        if args.stats {
            for (name, s) in names.iter().zip(stats) {
                let name = stagecli::input_name(name);
                let record = Record::new("zbuf").with("input", name);
                if let (Some(r), Some(m)) = (s.resolved, &method) {
                    // The leaf's line (`leaf::resolve_frames`), under zbuf's name.
                    let mut record = record
                        .with("polygons_in", r.polygons)
                        .with("frames", r.frames)
                        .with("runs", s.runs);
                    for (key, value) in m.counters() {
                        record.set(key, value);
                    }
                    record.print(&format!(
                        "zbuf: {name}: {} polygons in, {} frames, {} runs, {}",
                        r.polygons,
                        r.frames,
                        s.runs,
                        m.stats()
                    ));
                } else if let Some(r) = s.resolved {
                    // Runs only where they were passed between threads.
                    let runs = if s.runs > 0 {
                        format!(", {} runs", s.runs)
                    } else {
                        String::new()
                    };
                    let rounding = scan::precision::stats_suffix(r.rounding_decided);
                    record
                        .with("polygons_in", r.polygons)
                        .with("pixels_tested", r.pixels_tested)
                        .with("pixels_written", r.pixels_written)
                        .with("runs", s.runs)
                        .with("rounding_decided", r.rounding_decided)
                        .print(&format!(
                            "zbuf: {name}: {} polygons in, {} pixels tested, {} written{runs}{rounding}",
                            r.polygons, r.pixels_tested, r.pixels_written
                        ));
                } else {
                    let human = if s.runs > 0 {
                        format!(
                            "zbuf: {name}: {} spans, {} runs, {} pixels, {} bytes in",
                            s.spans, s.runs, s.pixels, s.bytes
                        )
                    } else {
                        format!(
                            "zbuf: {name}: {} spans, {} pixels, {} bytes in",
                            s.spans, s.pixels, s.bytes
                        )
                    };
                    record
                        .with("spans", s.spans)
                        .with("runs", s.runs)
                        .with("pixels", s.pixels)
                        .with("bytes_in", s.bytes)
                        .print(&human);
                }
            }
        }
        Ok(())
    })
}
