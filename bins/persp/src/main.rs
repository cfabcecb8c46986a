//! persp: eye-space polygon stream → screen-space (device coordinates and depth).

use clap::Parser;
use proto::camera::parse_size;
use proto::perspective::Perspective;
use proto::{Polygon, Space, SpaceKind};
use stagecli::{DepthArg, Error, TextFlag};
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
                  persp --size 500x500 --zmode eye-z   # the occam code's depth, to compare"
)]
struct Cli {
    /// The screen size in pixels, `WxH`; recorded in the output header.
    #[arg(long, value_parser = parse_size, value_name = "WxH")]
    size: (u32, u32),
    /// The depth written for each vertex.
    #[arg(long, value_enum, value_name = "MODE", default_value_t = DepthArg::Reciprocal)]
    zmode: DepthArg,
    /// --zmode's old name, taken for one release with a note on stderr.
    #[arg(
        long,
        value_enum,
        value_name = "MODE",
        hide = true,
        conflicts_with = "zmode"
    )]
    depth: Option<DepthArg>,
    #[command(flatten)]
    text: TextFlag,
}

fn main() -> ExitCode {
    stagecli::main("persp", |cli: Cli| {
        let (width, height) = cli.size;
        let depth = match cli.depth {
            Some(old) => {
                eprintln!(
                    "{}",
                    stagecli::args::renamed("persp", "--depth MODE", "--zmode MODE")
                );
                old
            }
            None => cli.zmode,
        };
        stagecli::filter_polygons(
            SpaceKind::Eye,
            cli.text.form(),
            "the perspective division",
            |header| {
                let Space::Eye(view) = header.space else {
                    unreachable!("the reader checked the space")
                };
                // A view volume persp cannot map (from the stream's header) is bad input.
                let perspective =
                    Perspective::new(width, height, view, depth.into()).map_err(Error::data)?;
                Ok((
                    perspective.screen_header(header),
                    move |poly: &mut Polygon| {
                        perspective.project_polygon(poly).map_err(|e| e.reason)
                    },
                ))
            },
        )
    })
}
