//! scene: writes a world-space polygon stream (binary, or text with `--text`) to stdout.

use clap::{Parser, Subcommand};
use proto::{Form, Header, Polygon, Space, Token, Writer};
use std::io;
use std::process::ExitCode;

/// Scene sources for the polypipe pipeline: each subcommand writes a world-space stream,
/// frames separated by NEXT.FRAME, for the default camera (eye 0,0,20 looking at the
/// origin, s=10, d=16, hither 1, yon 30).
#[derive(Parser, Debug)]
#[command(
    name = "scene",
    version,
    after_help = "Examples:\n  \
        scene environment --polygons 1024 --clipped 0.5 --depth-complexity 1 --seed 1 --text\n  \
        scene environment --frames 10 | viewxf | clipplane left | ... | zbuf > movie.ppm"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Write the text form instead of binary.
    #[arg(long, global = true)]
    text: bool,
    /// Number of frames: a movie in which the objects move between frames.
    #[arg(long, global = true, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    frames: u32,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// The test environment of thesis chapter 5.2: N four-sided polygons, a fraction F of
    /// them wholly outside the clipping pyramid, the visible ones covering on average D
    /// polygons per pixel.
    #[command(after_help = "Example:\n  \
        scene environment --polygons 1024 --clipped 0.5 --depth-complexity 1 --seed 1 --size 500x500")]
    Environment {
        /// P_t: the number of polygons.
        #[arg(long, default_value_t = 1000)]
        polygons: usize,
        /// The fraction of polygons wholly outside the clipping pyramid (0 to 1).
        #[arg(long, default_value_t = 0.5, value_parser = fraction)]
        clipped: f64,
        /// Dc: the average number of visible polygons covering a pixel.
        #[arg(long, default_value_t = 1.0, value_parser = non_negative)]
        depth_complexity: f64,
        /// The random seed: the same seed gives the same scene on every platform.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// The screen size `WxH` the scene is made for (its aspect ratio W/H widens the
        /// pyramid); give the same size to viewxf and persp.
        #[arg(long, value_parser = proto::camera::parse_size, value_name = "WxH")]
        size: Option<(u32, u32)>,
    },
}

fn fraction(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|_| format!("`{s}` is not a number"))?;
    if (0.0..=1.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!("{v} is not a fraction from 0 to 1"))
    }
}

fn non_negative(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|_| format!("`{s}` is not a number"))?;
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(format!("{v} must be a finite number ≥ 0"))
    }
}

/// Writes a movie: a world-space header, the frames separated by NEXT.FRAME, then END.
fn write_movie(frames: &[Vec<Polygon>], form: Form) -> anyhow::Result<()> {
    let mut writer = Writer::new(io::stdout().lock(), Header::new(Space::World), form)?;
    for (i, frame) in frames.iter().enumerate() {
        if i > 0 {
            writer.write(&Token::NextFrame)?;
        }
        for polygon in frame {
            writer.write(&Token::Polygon(polygon.clone()))?;
        }
    }
    writer.write(&Token::End)?;
    writer.flush()?;
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let form = Form::from_text_flag(cli.text);
    let frames = cli.frames as usize;
    proto::cli::run("scene", || {
        let movie = match cli.command {
            Command::Environment {
                polygons,
                clipped,
                depth_complexity,
                seed,
                size,
            } => scene::environment(&scene::Environment {
                polygons,
                clipped,
                depth_complexity,
                seed,
                aspect: size.map_or(1.0, |(w, h)| w as f64 / h as f64),
                frames,
            }),
        };
        write_movie(&movie, form)
    })
}
