//! clipplane: eye-space polygon stream → the same stream clipped against one plane.

use clap::{CommandFactory, Parser};
use clipplane::{clip_against, ClipPlane};
use proto::geometry::{Plane, PyramidPlane};
use proto::{Form, Reader, SpaceKind, Token, Writer};
use std::io;
use std::process::ExitCode;

/// Sutherland–Hodgman clipping of every polygon against one plane (thesis chapter 3).
///
/// Reads an eye-space stream on stdin (binary or text) and writes it clipped. A polygon
/// wholly outside becomes an empty polygon (its colour, no vertices), so polygon
/// numbering is kept. The pyramid planes come from the view volume in the stream header
/// (viewxf --size/--aspect/--hither/--yon).
#[derive(Parser, Debug)]
#[command(
    name = "clipplane",
    version,
    after_help = "Example:\n  viewxf < scene | clipplane left | clipplane right | clipplane top \\\n    \
                  | clipplane bottom | clipplane hither | clipplane yon --text\n  \
                  clipplane hither --at 2      # clip at z_e = 2 instead of the header's K1\n  \
                  clipplane --plane 1,0,0,0,-3 # keep x_e ≥ 3"
)]
struct Cli {
    /// The pyramid plane: left, right, top, bottom, hither or yon.
    #[arg(value_name = "PLANE", required_unless_present = "plane")]
    which: Option<PyramidPlane>,
    /// A general plane `a,b,c,d,k`: inside where a·x_e + b·y_e + c·z_e + d·w + k ≥ 0.
    #[arg(long, value_parser = Plane::parse, allow_hyphen_values = true,
          value_name = "a,b,c,d,k", conflicts_with_all = ["which", "at"])]
    plane: Option<Plane>,
    /// For hither or yon: the distance K (clip at z_e = K) instead of the header's.
    #[arg(long, value_name = "K", allow_hyphen_values = true)]
    at: Option<f64>,
    /// Write the text form instead of binary.
    #[arg(long)]
    text: bool,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let choice = match (cli.plane, cli.which) {
        (Some(plane), _) => Ok(ClipPlane::General(plane)),
        (None, Some(which)) => ClipPlane::new(which, cli.at),
        (None, None) => Err("give a PLANE or --plane a,b,c,d,k".to_string()),
    };
    let choice = match choice {
        Ok(c) => c,
        Err(msg) => Cli::command()
            .error(clap::error::ErrorKind::ValueValidation, msg)
            .exit(),
    };
    proto::cli::run("clipplane", || {
        let mut reader = Reader::<Token, _>::new(io::stdin().lock())?;
        let header = *reader.header();
        header.expect(SpaceKind::Eye)?;
        let proto::Space::Eye(view) = header.space else {
            unreachable!("expect(Eye) passed")
        };
        let plane = choice.plane(&view);
        // The view volume is passed on unchanged: persp's depth mapping uses its K1, K2.
        let mut writer = Writer::new(io::stdout().lock(), header, Form::from_text_flag(cli.text))?;
        // The clipped vertices go to `scratch`, which then swaps places with the input's
        // vertex list: no allocation of our own per polygon.
        let mut scratch = Vec::new();
        let mut token = Token::default();
        while reader.next_into(&mut token)? {
            if let Token::Polygon(poly) = &mut token {
                clip_against(&poly.vertices, &plane, &mut scratch);
                if scratch != poly.vertices {
                    // New vertices and edges: the splitter's edge supports (which clipping
                    // before the tree never meets) no longer match; the plane still does.
                    poly.supports.clear();
                }
                std::mem::swap(&mut poly.vertices, &mut scratch);
            }
            writer.write(&token)?;
        }
        writer.flush()?;
        Ok::<(), anyhow::Error>(())
    })
}
