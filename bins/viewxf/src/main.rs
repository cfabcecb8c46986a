//! viewxf: world-space polygon stream → eye-space polygon stream.

use clap::Parser;
use proto::{Header, Polygon, Space, SpaceKind};
use stagecli::{TextFlag, ViewArgs};
use std::process::ExitCode;

/// The viewing transformation (world → eye coordinates, with w = z_e·s/d).
///
/// Reads a world-space stream on stdin (binary or text) and writes the eye-space stream,
/// whose header records the view volume (aspect, hither, yon) for the clippers and persp.
#[derive(Parser, Debug)]
#[command(
    name = "viewxf",
    version,
    after_help = "Example:\n  viewxf --eye 0,0,20 --at 0,0,0 --size 640x480 --text < scene.txt\n  \
                  scene | viewxf | clipplane left | ... | persp --size 640x480 | ..."
)]
struct Cli {
    #[command(flatten)]
    view: ViewArgs,
    #[command(flatten)]
    text: TextFlag,
}

fn main() -> ExitCode {
    stagecli::main("viewxf", |cli: Cli| {
        // A camera or volume that cannot be viewed through is a usage error (status 2).
        let (frame, view) = cli.view.resolve()?;
        stagecli::filter_polygons(
            SpaceKind::World,
            cli.text.form(),
            "the viewing transformation",
            |header| {
                Ok((
                    Header::new(Space::Eye(view)).with(header.attributes),
                    |poly: &mut Polygon| {
                        viewxf::view_polygon(&frame, view.hither, poly);
                        Ok(())
                    },
                ))
            },
        )
    })
}
