//! persp: eye-space polygon stream → screen-space (device coordinates and depth).

use anyhow::anyhow;
use clap::Parser;
use persp::{DepthMode, Perspective};
use proto::camera::parse_size;
use proto::{Form, Header, Reader, Space, SpaceKind, StreamError, Token, Writer};
use std::io;
use std::process::ExitCode;

/// Perspective division and device mapping for a W×H screen.
///
/// Reads a clipped eye-space stream on stdin (binary or text) and writes the screen-space
/// stream: each vertex becomes `X Y depth`, with (0,0) the top-left corner of the screen.
/// The screen's W/H must be the aspect ratio given to viewxf.
#[derive(Parser, Debug)]
#[command(
    name = "persp",
    version,
    after_help = "Example:\n  viewxf --size 640x480 < scene | clipplane left | ... | clipplane yon \\\n    \
                  | persp --size 640x480 --text\n  \
                  persp --size 500x500 --depth eye-z   # the occam code's depth, to compare"
)]
struct Cli {
    /// The screen size in pixels, `WxH`; recorded in the output header.
    #[arg(long, value_parser = parse_size, value_name = "WxH")]
    size: (u32, u32),
    /// The depth written for each vertex.
    #[arg(long, value_enum, default_value_t = DepthMode::Projective)]
    depth: DepthMode,
    /// Write the text form instead of binary.
    #[arg(long)]
    text: bool,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    proto::cli::run("persp", || {
        let mut reader = Reader::<Token, _>::new(io::stdin().lock())?;
        reader.header().expect(SpaceKind::Eye)?;
        let Space::Eye(view) = reader.header().space else {
            unreachable!("expect(Eye) passed")
        };
        let (width, height) = cli.size;
        let perspective =
            Perspective::new(width, height, view, cli.depth).map_err(StreamError::Invalid)?;
        let mut writer = Writer::new(
            io::stdout().lock(),
            Header::new(Space::Screen { width, height }),
            Form::from_text_flag(cli.text),
        )?;
        let mut token = Token::default();
        while reader.next_into(&mut token)? {
            if let Token::Polygon(poly) = &mut token {
                perspective.project_polygon(poly).map_err(|e| {
                    anyhow!(StreamError::Invalid(format!(
                        "{}: {}",
                        reader.position(),
                        e.reason
                    )))
                })?;
            }
            writer.write(&token)?;
        }
        writer.flush()?;
        Ok::<(), anyhow::Error>(())
    })
}
