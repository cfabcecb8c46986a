//! supersample: a leaf that anti-aliases by K×K samples per pixel.

use clap::Parser;
use scan::supersample::Supersample;
use stagecli::{AntialiasArgs, Error};
use std::process::ExitCode;

/// Anti-aliasing by supersampling (docs/DESIGN.md, "Anti-aliasing"), a leaf of the
/// splitter tree.
///
/// Reads a screen-space polygon stream (from persp) on stdin, gathers each frame, samples
/// every pixel at the K×K sub-pixel centres (c+(i+½)/K, r+(j+½)/K) by the point rule (the
/// pixel centres of a screen K times finer), and writes each pixel some polygon reaches as
/// the average of its samples, each channel (sum + K²/2)/K², uncovered samples counting as
/// the background. The output is runs of finished pixels (`run Y X0 X1 R G B`) for zbuf,
/// which must be given the same --background. `zspec --samples K` is its exact reference.
///
/// With --adaptive, only the pixels an edge, a silhouette or a crossing touches are
/// sampled K×K (render --aa adaptiveK).
///
/// Example:
///   persp --size 500x500 < eye.pp | supersample --samples 4 | zbuf > frame.ppm
#[derive(Parser)]
#[command(name = "supersample", version, verbatim_doc_comment)]
struct Args {
    /// K: samples a side of each pixel, 2, 4, 8 or 16 (1 is point sampling).
    #[arg(long, value_name = "K", default_value_t = 4,
          value_parser = stagecli::numbers::one_of(&[1, 2, 4, 8, 16]))]
    samples: u32,
    /// K×K samples only in the pixels an edge, a silhouette or a crossing of two
    /// polygons touches, one polygon's colour elsewhere: the same bytes on flat polygons,
    /// shaded ones averaged at the pixel's central 2×2 samples (docs/antialiasing.md).
    #[arg(long)]
    adaptive: bool,
    #[command(flatten)]
    aa: AntialiasArgs,
    /// Print counts (polygons in, frames, runs out, samples tested and written, pixels out)
    /// on stderr at the end.
    #[arg(long)]
    stats: bool,
}

fn main() -> ExitCode {
    stagecli::main("supersample", |args: Args| {
        let mut method = Supersample::new(args.samples, args.aa.background)
            .map_err(|m| Error::usage(format!("--samples {m}")))?;
        if args.adaptive {
            method = method.adaptive();
        }
        leaf::resolve_frames("supersample", args.aa.text.form(), args.stats, &mut method)?;
        Ok(())
    })
}
