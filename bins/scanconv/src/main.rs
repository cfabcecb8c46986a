//! scanconv: screen-space polygons in, fragments (spans or pixels with depth) out.

use clap::Parser;
use proto::{Fragment, Header, Space, SpaceKind, Token};
use scanconv::{Output, ScanConverter};
use stagecli::{Error, TextFlag};
use std::process::ExitCode;

/// Scan conversion with an edge table and active edge table (thesis ch. 4, Appendix 3).
///
/// Reads a screen-space polygon stream (from persp) on stdin and writes, per polygon, its
/// colour and the pixels whose centres it covers, with their depth, for zbuf.
///
/// Example:
///   persp --size 500x500 < eye.pp | scanconv | zbuf > frame.ppm
///   printf 'polypipe 1 screen 4 4\ncolour 255 0 0\n1 1 0.5\n3 1 0.5\n3 3 0.5\nEND\n' | scanconv --text
#[derive(Parser)]
#[command(name = "scanconv", version, verbatim_doc_comment)]
struct Args {
    #[command(flatten)]
    text: TextFlag,
    /// Send one record per pixel (the thesis's quadruplets) instead of spans.
    #[arg(long)]
    pixels: bool,
    /// Print counts (polygons in, polygons drawn, spans, pixels) on stderr at the end.
    #[arg(long)]
    stats: bool,
}

fn main() -> ExitCode {
    stagecli::main("scanconv", |args: Args| {
        let mut input = stagecli::read_stdin::<Token>(SpaceKind::Screen)?;
        let (width, height) = input
            .header()
            .space
            .screen_size()
            .ok_or_else(|| Error::data("screen-space header without a size"))?;
        let mut out = stagecli::write_stdout::<Fragment>(
            Header::new(Space::Fragments { width, height }),
            args.text.form(),
        )?;
        let output = if args.pixels {
            Output::Pixels
        } else {
            Output::Spans
        };
        let mut sc = ScanConverter::new(width, height, output);
        while let Some(token) = stagecli::next(&mut input)? {
            match token {
                Token::Polygon(p) => {
                    scanconv::check_on_screen(&p, width, height)
                        .map_err(|m| Error::data(format!("{}: {m}", input.position())))?;
                    sc.convert(&p, &mut |f| out.write(&f))?
                }
                Token::Skip(n) => out.write(&Fragment::Skip(n))?,
                Token::NextFrame => out.write(&Fragment::NextFrame)?,
                Token::End => out.write(&Fragment::End)?,
            }
        }
        out.flush()?;
        if args.stats {
            let s = sc.stats;
            eprintln!(
                "scanconv: {} polygons in, {} drawn, {} spans, {} pixels",
                s.polygons_in, s.polygons_drawn, s.spans, s.pixels
            );
        }
        Ok(())
    })
}
