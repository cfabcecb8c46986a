//! zspec: the exact reference renderer (world-space stream → PPM stream), and the
//! comparison of two PPM streams.

use anyhow::{bail, Context};
use clap::{CommandFactory, Parser, Subcommand};
use proto::camera::ViewArgs;
use proto::{Colour, Reader, SpaceKind, Token};
use std::fs::File;
use std::io::{self, BufReader, BufWriter, Write};
use std::process::ExitCode;
use zspec::Setup;

/// The exact reference: the Z spec (thesis 2.3; docs/DESIGN.md, "Visibility") evaluated in f64 at
/// every pixel centre — coverage by the even-odd and top-left rules, depth where the ray
/// through the centre meets the polygon's plane, hither ≤ z_e ≤ yon, nearest wins,
/// earlier wins a tie. No clipping chain, no edge table: an independent renderer to
/// measure the pipeline against.
///
/// Reads a world-space scene (binary or text; SCENE, or stdin for `-` or none) and writes
/// one binary PPM (P6) per frame, like zbuf. The camera options are viewxf's.
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
    #[arg(long, value_parser = zspec::parse_colour, default_value = "0,0,0", value_name = "R,G,B")]
    background: Colour,
    /// Anti-aliasing reference: K×K samples per pixel, at the sub-pixel centres
    /// (c + (i+½)/K, r + (j+½)/K), each decided by the rules of a pixel centre (exactly
    /// as on a K·W × K·H screen), box-filtered: each channel is the average of the K²
    /// samples rounded to nearest, halves up, (sum + K²/2) / K² in integers. K = 1 is
    /// point sampling. Holds the frame's polygons and draws bands of sample rows.
    #[arg(long, default_value_t = 1, value_name = "K",
          value_parser = clap::value_parser!(u32).range(1..=zspec::supersample::MAX_SAMPLES as i64))]
    samples: u32,
    /// Also write the edge pixels, those whose K×K samples are not all one colour, to
    /// FILE: one PPM a frame, white for an edge pixel, black elsewhere (for `zspec
    /// compare --metrics --edges FILE`).
    #[arg(long, value_name = "FILE")]
    edge_mask: Option<String>,
    /// The world-space scene; `-` or none for stdin.
    scene: Option<String>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Compare two PPM streams frame by frame: prints, per frame, the pixels, the
    /// differing pixels and the percentage that agree. Exit status 0 when every frame
    /// agrees on at least --min-agreement percent, 1 otherwise.
    #[command(after_help = "Example:\n  zspec compare ref.ppm pipe.ppm --min-agreement 99.9")]
    Compare {
        a: String,
        b: String,
        /// The least percentage of agreeing pixels every frame must reach.
        #[arg(long, default_value_t = 99.95)]
        min_agreement: f64,
        /// Instead, measure B against A: per frame and `overall`, the differing
        /// fraction, the RMSE (0-255 units, three channels), the largest channel error
        /// and, with --edges, the RMSE over the edge pixels, as `key value` pairs. Exit
        /// status 0 whatever the error, non-zero only for trouble.
        #[arg(long, conflicts_with = "min_agreement")]
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
    let cli = Cli::parse();
    match cli.command {
        Some(Command::Compare {
            a,
            b,
            metrics: true,
            edges,
            csv,
            ..
        }) => proto::cli::run("zspec compare", || {
            compare_metrics(&a, &b, edges.as_deref(), csv)
        }),
        Some(Command::Compare {
            a,
            b,
            min_agreement,
            ..
        }) => proto::cli::run("zspec compare", || compare(&a, &b, min_agreement)),
        None => {
            let (frame, view) = match cli.view.resolve() {
                Ok(resolved) => resolved,
                Err(msg) => Cli::command()
                    .error(clap::error::ErrorKind::ValueValidation, msg)
                    .exit(),
            };
            let (width, height) = cli.view.size.unwrap_or((500, 500));
            let setup = Setup::new(frame, view, width, height);
            let scene = cli.scene.unwrap_or_else(|| "-".into());
            if cli.samples == 1 && cli.edge_mask.is_none() {
                proto::cli::run("zspec", || render(&scene, &setup, cli.background))
            } else {
                proto::cli::run("zspec", || {
                    render_supersampled(
                        &scene,
                        &setup,
                        cli.samples,
                        cli.background,
                        cli.edge_mask.as_deref(),
                    )
                })
            }
        }
    }
}

/// Renders every frame of the scene to stdout.
fn render(scene: &str, setup: &Setup, background: Colour) -> anyhow::Result<()> {
    let mut reader = Reader::<Token, _>::new(proto::cli::open_input(scene)?)?;
    reader.header().expect(SpaceKind::World)?;
    let mut out = BufWriter::new(io::stdout().lock());
    let mut frame = zspec::ReferenceFrame::new(setup, background);
    while let Some(token) = reader.next_record()? {
        match token {
            Token::Polygon(p) => frame.draw(setup, &p),
            // Polygons this stream carries nothing of: nothing to draw.
            Token::Skip(_) => {}
            Token::NextFrame | Token::End => {
                zspec::write_ppm(&mut out, setup.width, setup.height, &frame.colour)?;
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
    scene: &str,
    setup: &Setup,
    k: u32,
    background: Colour,
    edge_mask: Option<&str>,
) -> anyhow::Result<()> {
    let mut reader = Reader::<Token, _>::new(proto::cli::open_input(scene)?)?;
    reader.header().expect(SpaceKind::World)?;
    let mut out = BufWriter::new(io::stdout().lock());
    let mut mask = match edge_mask {
        Some(path) => Some(BufWriter::new(
            File::create(path).with_context(|| format!("cannot create {path}"))?,
        )),
        None => None,
    };
    let mut frame = zspec::SupersampledFrame::new(setup, k, background)?;
    while let Some(token) = reader.next_record()? {
        match token {
            Token::Polygon(p) => frame.draw(&p),
            Token::Skip(_) => {}
            Token::NextFrame | Token::End => {
                let done = frame.finish();
                zspec::write_ppm(&mut out, done.width, done.height, &done.pixels)?;
                out.flush()?;
                if let Some(m) = mask.as_mut() {
                    zspec::write_ppm(m, done.width, done.height, &done.edge_mask())?;
                    m.flush()?;
                }
            }
        }
    }
    Ok(())
}

fn open_ppm_stream(path: &str) -> anyhow::Result<Vec<zspec::Image>> {
    let input = proto::cli::open_input(path)?;
    zspec::read_ppm_stream(BufReader::new(input)).with_context(|| path.to_string())
}

fn compare(a: &str, b: &str, min_agreement: f64) -> anyhow::Result<()> {
    let (ia, ib) = (open_ppm_stream(a)?, open_ppm_stream(b)?);
    let frames = zspec::compare(&ia, &ib)?;
    let mut out = io::stdout().lock();
    let mut failing = Vec::new();
    for (k, f) in frames.iter().enumerate() {
        writeln!(
            out,
            "frame {k}: {} pixels, {} differ, {:.4}% agree",
            f.pixels,
            f.differing,
            f.percent()
        )?;
        if f.percent() < min_agreement {
            failing.push(k);
        }
    }
    out.flush()?;
    if !failing.is_empty() {
        bail!(
            "{} of {} frames agree on fewer than {min_agreement}% of pixels (frames {:?})",
            failing.len(),
            frames.len(),
            failing
        );
    }
    Ok(())
}

/// `compare --metrics`: the error measures of B against A, per frame and overall.
fn compare_metrics(a: &str, b: &str, edges: Option<&str>, csv: bool) -> anyhow::Result<()> {
    let (ia, ib) = (open_ppm_stream(a)?, open_ppm_stream(b)?);
    let masks = edges.map(open_ppm_stream).transpose()?;
    let frames = zspec::metrics_streams(&ia, &ib, masks.as_deref())?;
    let overall = zspec::Metrics::overall(&frames);
    let mut out = io::stdout().lock();
    if csv {
        writeln!(out, "{}", zspec::Metrics::CSV_HEADER)?;
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
