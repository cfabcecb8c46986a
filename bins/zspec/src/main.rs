//! zspec: the exact reference renderer (world-space stream → PPM stream), and the
//! comparison of two PPM streams.

use clap::{Parser, Subcommand};
use proto::{ppm, Colour, Reader, SpaceKind, Token};
use stagecli::{Error, PpmTextFlag, ViewArgs};
use std::io::{self, BufReader, BufWriter, Write};
use std::process::ExitCode;
use zspec::Setup;

/// The exact reference: DESIGN.md's Z spec (chapter 2.3) evaluated directly in f64 at
/// every pixel centre — coverage by the even-odd and top-left rules, depth where the ray
/// through the centre meets the polygon's plane, hither ≤ z_e ≤ yon, nearest wins,
/// earlier wins a tie. No clipping chain, no edge table: an independent renderer to
/// measure the pipeline against.
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
        zspec compare ref.ppm pipe.ppm"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    view: ViewArgs,
    /// The background colour `R,G,B`.
    #[arg(long, value_parser = zspec::parse_colour, default_value = "0,0,0", value_name = "R,G,B")]
    background: Colour,
    #[command(flatten)]
    text: PpmTextFlag,
    /// The world-space scene; `-` or none for stdin.
    scene: Option<String>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Compare two PPM streams frame by frame: prints, per frame, the pixels, the
    /// differing pixels and the percentage that agree. Exit status as cmp's: 0 when every
    /// frame agrees on at least --min-agreement percent, 1 when one does not (or the
    /// streams have different numbers or sizes of frames), 2 for trouble (a missing file,
    /// one that is not a PPM stream, a bad argument).
    #[command(after_help = "Example:\n  zspec compare ref.ppm pipe.ppm --min-agreement 99.9")]
    Compare {
        /// The first PPM stream (`-` for stdin).
        a: String,
        /// The second PPM stream (`-` for stdin, if the first is not).
        b: String,
        /// The least percentage of agreeing pixels every frame must reach (0 to 100).
        #[arg(long, default_value_t = 99.95, value_parser = percentage)]
        min_agreement: f64,
    },
}

/// A percentage from 0 to 100.
fn percentage(s: &str) -> Result<f64, String> {
    s.parse::<f64>()
        .ok()
        .filter(|p| (0.0..=100.0).contains(p))
        .ok_or_else(|| format!("`{s}` is not a percentage from 0 to 100"))
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
            min_agreement,
        }) => stagecli::report_cmp("zspec compare", compare(&a, &b, min_agreement)),
        None => stagecli::report(
            "zspec",
            render(&cli.view, cli.background, cli.text, cli.scene),
        ),
    }
}

/// Renders every frame of the scene to stdout.
fn render(
    view: &ViewArgs,
    background: Colour,
    text: PpmTextFlag,
    scene: Option<String>,
) -> stagecli::Result<()> {
    // A camera or volume that cannot be viewed through is a usage error (status 2).
    let (frame, volume) = view.resolve()?;
    let (width, height) = view.size.unwrap_or((500, 500));
    let setup = Setup::new(frame, volume, width, height);
    let scene = scene.unwrap_or_else(|| "-".into());
    let name = stagecli::input_name(&scene).to_string();
    let mut reader = Reader::<Token, _>::new(stagecli::open_input(&scene)?)
        .map_err(|e| stagecli::input_error(&name, e))?;
    reader.header().expect(SpaceKind::World)?;
    let mut out = BufWriter::new(stagecli::stdout());
    let mut frame = zspec::ReferenceFrame::new(&setup, background).map_err(Error::data)?;
    while let Some(token) = reader
        .next_record()
        .map_err(|e| stagecli::input_error(&name, e))?
    {
        match token {
            Token::Polygon(p) => frame
                .draw(&setup, &p)
                .map_err(|m| Error::data(format!("{}: {m}", reader.position())))?,
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

/// Reads a whole PPM stream; an error names the file.
fn read_ppms(path: &str) -> stagecli::Result<Vec<ppm::Image>> {
    let input = stagecli::open_input(path)?;
    ppm::read_all(BufReader::new(input))
        .map_err(|e| Error::from(e).context(stagecli::input_name(path)))
}

/// Compares two PPM streams: `Ok(true)` when every frame agrees well enough.
fn compare(a: &str, b: &str, min_agreement: f64) -> stagecli::Result<bool> {
    if a == "-" && b == "-" {
        return Err(Error::usage(
            "`-` (stdin) is named twice: it can be read only once",
        ));
    }
    let (ia, ib) = (read_ppms(a)?, read_ppms(b)?);
    let frames = zspec::compare(&ia, &ib);
    if let Ok(frames) = &frames {
        let mut out = stagecli::stdout();
        for (k, f) in frames.iter().enumerate() {
            writeln!(out, "frame {k}: {f}")?;
        }
        out.flush()?;
    }
    // Different, as cmp says: status 1, and a line saying how.
    match frames.and_then(|f| zspec::agreed(&f, min_agreement)) {
        Ok(()) => Ok(true),
        Err(why) => {
            let _ = writeln!(io::stderr(), "zspec compare: {why}");
            Ok(false)
        }
    }
}
