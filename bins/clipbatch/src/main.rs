//! clipbatch: eye-space polygon stream → the same stream clipped against the whole
//! pyramid, a batch of polygons at a time.

use clap::Parser;
use clipbatch::{ClipBatch, DEFAULT_BATCH};
use proto::{SpaceKind, Token, Writer};
use stagecli::TextFlag;
use std::io::{self, Write};
use std::process::ExitCode;

/// Sutherland–Hodgman clipping against all six planes of the pyramid in one process, a
/// batch of polygons at a time (Theoharis & Page's DAP clipper).
///
/// Reads an eye-space stream on stdin (binary or text) and writes what
/// `clipplane left | clipplane right | clipplane top | clipplane bottom | clipplane hither
/// | clipplane yon` writes, bit for bit. The planes come from the view volume in the
/// stream header (viewxf --size/--aspect/--hither/--yon).
#[derive(Parser, Debug)]
#[command(
    name = "clipbatch",
    version,
    after_help = "Example:\n  viewxf < scene | clipbatch | persp --size 500x500 | scanconv | zbuf > frame.ppm\n  \
                  viewxf < scene | clipbatch --batch 1024 --text"
)]
struct Cli {
    /// Polygons clipped together (the DAP's processing elements); a frame's end, or a
    /// polygon of many vertices, ends a batch early.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_BATCH as u32,
          value_parser = clap::value_parser!(u32).range(1..=1 << 20))]
    batch: u32,
    #[command(flatten)]
    text: TextFlag,
}

fn main() -> ExitCode {
    stagecli::main("clipbatch", |cli: Cli| {
        let mut reader = stagecli::read_stdin::<Token>(SpaceKind::Eye)?;
        let header = *reader.header();
        let proto::Space::Eye(view) = header.space else {
            unreachable!("the reader checked the space")
        };
        let mut writer = stagecli::write_stdout(header, cli.text.form())?;
        let mut batch = ClipBatch::new(&view, cli.batch as usize);
        // Polygons wait in the batch. Anything else (NEXT.FRAME, END, a skip, or bad
        // input) first sends the waiting polygons on, clipped: the output up to any point
        // is the chain's, the polygons before a bad record included. Each polygon is read
        // into one the batch has handed back, and nothing is allocated per polygon.
        let mut token = Token::default();
        loop {
            match reader.next_into(&mut token) {
                Ok(true) => {}
                Ok(false) => break,
                Err(e) => {
                    write_clipped(&mut batch, &mut writer)?;
                    return Err(stagecli::input_error("stdin", e));
                }
            }
            match &mut token {
                Token::Polygon(poly) => {
                    if !batch.fits(poly) {
                        write_clipped(&mut batch, &mut writer)?;
                    }
                    let next = batch.recycled();
                    batch.push(std::mem::replace(poly, next));
                }
                control => {
                    write_clipped(&mut batch, &mut writer)?;
                    writer.write(control)?;
                }
            }
        }
        writer.flush()?;
        Ok(())
    })
}

/// Clips the waiting polygons and writes them.
fn write_clipped<W: Write>(batch: &mut ClipBatch, writer: &mut Writer<Token, W>) -> io::Result<()> {
    batch.clip_each(|poly| writer.write_polygon(poly))
}
