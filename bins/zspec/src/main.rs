//! zspec: the exact reference renderer (world-space stream → PPM stream), and the
//! comparison of two PPM streams.

use clap::{Parser, Subcommand};
use proto::{ppm, Colour, Reader, SpaceKind, Token};
use reference::Setup;
use stagecli::{Error, PpmTextFlag, ViewArgs};
use std::io::{self, BufReader, BufWriter, Write};
use std::process::ExitCode;

/// The exact reference: the Z spec (thesis 2.3; docs/DESIGN.md, "Coverage" and
/// "Visibility") evaluated at every pixel centre — coverage by the even-odd rule, a centre
/// on an edge to the polygon it is a left or top edge of, decided exactly in integers on
/// the vertices snapped to 1/256 pixel; depth in f64 where the ray through the centre
/// meets the polygon's plane, hither ≤ z_e ≤ yon, nearest wins, earlier wins a tie. No
/// clipping chain, no edge table: an independent renderer to measure the pipeline
/// against.
///
/// Reads a world-space scene (binary or text; SCENE, or stdin for `-` or none) and writes
/// one binary PPM (P6; plain P3 with --text) per frame, like zbuf. The camera options are
/// viewxf's.
#[derive(Parser, Debug)]
#[command(
    name = "zspec",
    version,
    args_conflicts_with_subcommands = true,
    after_help = "Examples:\n  \
        scene environment --polygons 1000 > s.pp\n  \
        zspec --size 500x500 s.pp > ref.ppm\n  \
        viewxf --size 500x500 < s.pp | clipplane left | clipplane right | clipplane top \\\n    \
        | clipplane bottom | clipplane hither | clipplane yon | persp --size 500x500 \\\n    \
        | scanconv | zbuf > pipe.ppm\n  \
        zspec compare ref.ppm pipe.ppm\n  \
        zspec --samples 16 --edge-mask edges.ppm --size 500x500 s.pp > ref16.ppm\n  \
        zspec compare --metrics --edges edges.ppm ref16.ppm pipe.ppm"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    view: ViewArgs,
    /// The background colour `R,G,B`.
    #[arg(long, value_parser = reference::parse_colour, default_value = "0,0,0", value_name = "R,G,B")]
    background: Colour,
    /// Anti-aliasing reference: K×K samples per pixel, at the sub-pixel centres
    /// (c + (i+½)/K, r + (j+½)/K), each decided by the rules of a pixel centre (as on a
    /// K·W × K·H screen, the vertices snapped on this screen's 1/256-pixel grid),
    /// box-filtered: each channel is the average of the K²
    /// samples rounded to nearest, halves up, (sum + K²/2) / K² in integers. K = 1 is
    /// point sampling. Holds the frame's polygons and draws bands of sample rows.
    #[arg(long, default_value_t = 1, value_name = "K",
          value_parser = clap::value_parser!(u32).range(1..=reference::supersample::MAX_SAMPLES as i64))]
    samples: u32,
    /// Also write the edge pixels, those whose K×K samples are not all one colour, to
    /// FILE: one PPM a frame, white for an edge pixel, black elsewhere (for `zspec
    /// compare --metrics --edges FILE`).
    #[arg(long, value_name = "FILE")]
    edge_mask: Option<String>,
    #[command(flatten)]
    text: PpmTextFlag,
    /// The world-space scene; `-` or none for stdin.
    scene: Option<String>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Compare two PPM streams frame by frame: prints, per frame, the pixels, the
    /// differing pixels and the percentage that agree. Exit status as cmp's: 0 when the
    /// frames are the same (or differ in no more than --tolerance of a frame's pixels),
    /// 1 when any pixel differs (or the streams have different numbers or sizes of
    /// frames), 2 for trouble (a missing or empty file, one that is not a PPM stream, a
    /// bad argument).
    #[command(after_help = "Example:\n  zspec compare ref.ppm pipe.ppm\n  \
                            zspec compare ref.ppm pipe.ppm --tolerance 0.001")]
    Compare {
        /// The first PPM stream (`-` for stdin).
        a: String,
        /// The second PPM stream (`-` for stdin, if the first is not).
        b: String,
        /// The largest fraction of a frame's pixels that may differ with the streams still
        /// called the same (0 to 1; default 0: any differing pixel is a difference).
        #[arg(long, value_parser = stagecli::numbers::fraction, value_name = "FRACTION")]
        tolerance: Option<f64>,
        /// The same as --tolerance (100 − P)/100: the least percentage of agreeing pixels
        /// every frame must reach (0 to 100; default 100, every pixel the same).
        #[arg(long, value_parser = stagecli::numbers::percent, conflicts_with = "tolerance")]
        min_agreement: Option<f64>,
        /// Instead, measure B against A: per frame and `overall`, the differing
        /// fraction, the RMSE (0-255 units, three channels), the largest channel error
        /// and, with --edges, the RMSE over the edge pixels, as `key value` pairs. Exit
        /// status 0 whatever the error; 2 for trouble, as without --metrics, and for
        /// streams of different numbers or sizes of frames, which cannot be measured.
        #[arg(long, conflicts_with_all = ["min_agreement", "tolerance"])]
        metrics: bool,
        /// The edge mask (`zspec --samples 16 --edge-mask MASK`) naming the edge pixels.
        #[arg(long, requires = "metrics", value_name = "MASK")]
        edges: Option<String>,
        /// Write the measures as CSV (`frame,pixels,differing,differing_fraction,rmse,max,edge_pixels,edge_rmse`).
        #[arg(long, requires = "metrics")]
        csv: bool,
    },
}

fn main() -> ExitCode {
    let cli = match stagecli::parse::<Cli>("zspec") {
        Ok(cli) => cli,
        Err(status) => return status,
    };
    match cli.command {
        Some(Command::Compare {
            a,
            b,
            metrics: true,
            edges,
            csv,
            ..
        }) => stagecli::report_cmp(
            "zspec compare",
            compare_metrics(&a, &b, edges.as_deref(), csv).map(|()| true),
        ),
        Some(Command::Compare {
            a,
            b,
            tolerance,
            min_agreement,
            ..
        }) => {
            let tolerance = tolerance
                .or(min_agreement.map(|p| (100.0 - p) / 100.0))
                .unwrap_or(0.0);
            stagecli::report_cmp("zspec compare", compare(&a, &b, tolerance))
        }
        None if cli.samples == 1 && cli.edge_mask.is_none() => stagecli::report(
            "zspec",
            render(&cli.view, cli.background, cli.text, cli.scene),
        ),
        None => stagecli::report(
            "zspec",
            render_supersampled(
                &cli.view,
                cli.background,
                cli.text,
                cli.scene,
                cli.samples,
                cli.edge_mask.as_deref(),
            ),
        ),
    }
}

/// A world-space scene opened for rendering: the pixel setup the camera options give,
/// and the scene's reader (with its name, for messages).
struct Scene {
    setup: Setup,
    reader: Reader<Token, Box<dyn std::io::Read + Send>>,
    name: String,
}

impl Scene {
    fn open(view: &ViewArgs, scene: Option<String>) -> stagecli::Result<Scene> {
        // A camera or volume that cannot be viewed through is a usage error (status 2).
        let (frame, volume) = view.resolve()?;
        let (width, height) = view.size.unwrap_or((500, 500));
        let setup = Setup::new(frame, volume, width, height);
        let scene = scene.unwrap_or_else(|| "-".into());
        let name = stagecli::input_name(&scene).to_string();
        let reader = Reader::<Token, _>::new(stagecli::open_input(&scene)?)
            .map_err(|e| stagecli::input_error(&name, e))?;
        reader.header().expect(SpaceKind::World)?;
        let setup = setup.for_scene(&reader.header().attributes);
        Ok(Scene {
            setup,
            reader,
            name,
        })
    }

    /// The next record, errors naming the scene.
    fn next(&mut self) -> stagecli::Result<Option<Token>> {
        let name = &self.name;
        self.reader
            .next_record()
            .map_err(|e| stagecli::input_error(name, e))
    }
}

/// Renders every frame of the scene to stdout.
fn render(
    view: &ViewArgs,
    background: Colour,
    text: PpmTextFlag,
    scene: Option<String>,
) -> stagecli::Result<()> {
    let mut scene = Scene::open(view, scene)?;
    let setup = scene.setup.clone();
    let mut out = BufWriter::new(stagecli::stdout());
    let mut frame = reference::ReferenceFrame::new(&setup, background).map_err(Error::data)?;
    while let Some(token) = scene.next()? {
        match token {
            Token::Polygon(p) => {
                stagecli::refuse_transparent("zspec", &p, || scene.reader.position())?;
                frame
                    .draw(&setup, &p)
                    .map_err(|m| Error::data(format!("{}: {m}", scene.reader.position())))?
            }
            // Polygons this stream carries nothing of: nothing to draw.
            Token::Skip(_) => {}
            Token::NextFrame | Token::End => {
                let rgb = frame.colour.as_flattened();
                ppm::write(&mut out, setup.width, setup.height, rgb, text.form())?;
                // A frame is written whole before the next is read.
                out.flush()?;
                frame.clear();
            }
        }
    }
    Ok(())
}

/// Renders every frame of the scene with K×K samples per pixel to stdout, and the edge
/// masks to `edge_mask` when given.
fn render_supersampled(
    view: &ViewArgs,
    background: Colour,
    text: PpmTextFlag,
    scene: Option<String>,
    k: u32,
    edge_mask: Option<&str>,
) -> stagecli::Result<()> {
    let mut scene = Scene::open(view, scene)?;
    let setup = scene.setup.clone();
    let mut out = BufWriter::new(stagecli::stdout());
    let mut mask = match edge_mask {
        Some(path) => {
            // Whole or not at all: a temporary renamed at the end.
            Some(BufWriter::new(stagecli::whole::WholeFile::create(path)?))
        }
        None => None,
    };
    let mut frame =
        reference::SupersampledFrame::new(&setup, k, background).map_err(Error::from)?;
    while let Some(token) = scene.next()? {
        match token {
            Token::Polygon(p) => {
                stagecli::refuse_transparent("zspec", &p, || scene.reader.position())?;
                frame
                    .draw(&p)
                    .map_err(|m| Error::data(format!("{}: {m}", scene.reader.position())))?
            }
            Token::Skip(_) => {}
            Token::NextFrame | Token::End => {
                let done = frame.finish();
                ppm::write(
                    &mut out,
                    done.width,
                    done.height,
                    done.pixels.as_flattened(),
                    text.form(),
                )?;
                out.flush()?;
                if let Some(m) = mask.as_mut() {
                    ppm::write(
                        m,
                        done.width,
                        done.height,
                        done.edge_mask().as_flattened(),
                        text.form(),
                    )?;
                    m.flush()?;
                }
            }
        }
    }
    if let Some(m) = mask {
        m.into_inner().map_err(|e| e.into_error())?.commit()?;
    }
    Ok(())
}

/// Reads a whole PPM stream; an error names the file.
fn read_ppms(path: &str) -> stagecli::Result<Vec<ppm::Image>> {
    let input = stagecli::open_input(path)?;
    ppm::read_all(BufReader::new(input))
        .map_err(|e| Error::from(e).context(stagecli::input_name(path)))
}

/// The two PPM streams compared, with or without --metrics, and the same trouble said the
/// same way by both: `-` named twice, or an input that is empty. An empty input is trouble,
/// not a stream of no frames: comparing two files that were never written would otherwise
/// say they are the same.
fn read_pair(a: &str, b: &str) -> stagecli::Result<(Vec<ppm::Image>, Vec<ppm::Image>)> {
    if a == "-" && b == "-" {
        return Err(Error::usage(
            "`-` (stdin) is named twice: it can be read only once",
        ));
    }
    let (ia, ib) = (read_ppms(a)?, read_ppms(b)?);
    for (path, frames) in [(a, &ia), (b, &ib)] {
        if frames.is_empty() {
            return Err(Error::data("empty: not a PPM stream (no frame)")
                .context(stagecli::input_name(path)));
        }
    }
    Ok((ia, ib))
}

/// Compares two PPM streams: `Ok(true)` when no frame has more than `tolerance` of its
/// pixels differing.
fn compare(a: &str, b: &str, tolerance: f64) -> stagecli::Result<bool> {
    let (ia, ib) = read_pair(a, b)?;
    let frames = reference::compare(&ia, &ib);
    if let Ok(frames) = &frames {
        let mut out = stagecli::stdout();
        for (k, f) in frames.iter().enumerate() {
            writeln!(out, "frame {k}: {f}")?;
        }
        out.flush()?;
    }
    // Different, as cmp says: status 1, and a line saying how.
    match frames.and_then(|f| reference::agreed(&f, tolerance)) {
        Ok(()) => Ok(true),
        Err(why) => {
            let _ = writeln!(io::stderr(), "zspec compare: {why}");
            Ok(false)
        }
    }
}

/// `compare --metrics`: the error measures of B against A, per frame and overall.
fn compare_metrics(a: &str, b: &str, edges: Option<&str>, csv: bool) -> stagecli::Result<()> {
    let (ia, ib) = read_pair(a, b)?;
    let masks = edges.map(read_ppms).transpose()?;
    let frames = reference::metrics_streams(&ia, &ib, masks.as_deref()).map_err(Error::from)?;
    let overall = reference::Metrics::overall(&frames);
    let mut out = stagecli::stdout();
    if csv {
        writeln!(out, "{}", reference::Metrics::CSV_HEADER)?;
        for (k, m) in frames.iter().enumerate() {
            writeln!(out, "{}", m.csv_row(&k.to_string()))?;
        }
        writeln!(out, "{}", overall.csv_row("overall"))?;
    } else {
        for (k, m) in frames.iter().enumerate() {
            writeln!(out, "frame {k}: {}", m.pairs())?;
        }
        writeln!(out, "overall: {}", overall.pairs())?;
    }
    out.flush()?;
    Ok(())
}
