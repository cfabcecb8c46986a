//! viewxf: world-space polygon stream → eye-space polygon stream.

use clap::{CommandFactory, Parser};
use proto::camera::ViewArgs;
use proto::{Form, Header, Reader, Space, SpaceKind, Token, Writer};
use std::io;
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
    /// Write the text form instead of binary.
    #[arg(long)]
    text: bool,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    // A camera or volume that cannot be viewed through is a usage error (status 2).
    let (frame, view) = match cli.view.resolve() {
        Ok(resolved) => resolved,
        Err(msg) => Cli::command()
            .error(clap::error::ErrorKind::ValueValidation, msg)
            .exit(),
    };
    proto::cli::run("viewxf", || {
        let mut reader = Reader::<Token, _>::new(io::stdin().lock())?;
        reader.header().expect(SpaceKind::World)?;
        let mut writer = Writer::new(
            io::stdout().lock(),
            Header::new(Space::Eye(view)),
            Form::from_text_flag(cli.text),
        )?;
        let mut token = Token::default();
        while reader.next_into(&mut token)? {
            if let Token::Polygon(poly) = &mut token {
                viewxf::view_polygon(&frame, poly);
            }
            writer.write(&token)?;
        }
        writer.flush()?;
        Ok::<(), anyhow::Error>(())
    })
}
