//! scanconv: screen-space polygons in, fragments (spans or pixels with depth) out.

use clap::Parser;
use proto::{Fragment, Header, Space, SpaceKind, Token};
use scanconv::{Output, ScanConverter};
use stagecli::stats::Record;
use stagecli::{Error, TextFlag};
use std::process::ExitCode;

/// Scan conversion with an edge table and active edge table (thesis ch. 4, Appendix 3).
///
/// Reads a screen-space polygon stream (from persp) on stdin and writes, per polygon, its
/// colour and the pixels whose centres it covers, with their depth, for zbuf; or, with
/// --resolve, decides visibility itself and writes each frame's finished pixels.
///
/// Example:
///   persp --size 500x500 < eye.pp | scanconv | zbuf > frame.ppm
///   persp --size 500x500 < leaf.pp | scanconv --resolve > leaf.frag
///   printf 'polypipe 1 screen 4 4\ncolour 255 0 0\n1 1 0.5\n3 1 0.5\n3 3 0.5\nEND\n' | scanconv --text
#[derive(Parser)]
#[command(name = "scanconv", version, verbatim_doc_comment)]
struct Args {
    #[command(flatten)]
    text: TextFlag,
    /// Send one record per pixel (the thesis's quadruplets) instead of spans.
    #[arg(long)]
    pixels: bool,
    /// Resolve visibility here (a leaf of the splitter tree): keep a Z-buffer for the
    /// pixels the polygons cover and send, at the end of each frame, its finished pixels
    /// as runs of one colour (`run Y X0 X1 R G B`), which zbuf places without a depth test.
    #[arg(long, conflicts_with = "pixels")]
    resolve: bool,
    /// Print counts (polygons in, polygons drawn, spans, pixels; with --resolve pixels
    /// tested and written, runs out, tiles allocated) on stderr at the end.
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
        if args.resolve {
            // The region buffer, where the leaf's polygons cover the whole screen: a
            // depth and a packed colour a pixel.
            let bytes = std::mem::size_of::<scan::Depth>() as u64 + 4;
            stagecli::memory::check_screen(width, height, bytes, "depth and colour")?;
        }
        let attributes = input.header().attributes.for_fragments();
        let mut out = stagecli::write_stdout::<Fragment>(
            Header::new(Space::Fragments { width, height }).with(attributes),
            args.text.form(),
        )?;
        // The header at once: the merger checks the screen's size before any frame.
        out.flush()?;
        let output = if args.resolve {
            Output::Resolve
        } else if args.pixels {
            Output::Pixels
        } else {
            Output::Spans
        };
        let mut sc = ScanConverter::new(width, height, output);
        sc.watch_depth(attributes.depth);
        sc.light(attributes.phong());
        let mut frame = 0u64;
        let warn = |sc: &mut ScanConverter, frame: &mut u64| {
            if let Some(message) = sc.quantum_warning(*frame) {
                eprintln!("scanconv: {message}");
            }
            *frame += 1;
        };
        while let Some(token) = stagecli::next(&mut input)? {
            match token {
                Token::Polygon(p) => {
                    scanconv::check_on_screen(&p, width, height)
                        .map_err(|m| Error::data(format!("{}: {m}", input.position())))?;
                    stagecli::refuse_transparent("scanconv", &p, || input.position())?;
                    sc.convert(&p, &mut |f| out.write(&f))?
                }
                Token::Skip(n) => sc.skip(n, &mut |f| out.write(&f))?,
                Token::NextFrame => {
                    sc.finish_frame(&mut |f| out.write(&f))?;
                    warn(&mut sc, &mut frame);
                    out.write(&Fragment::NextFrame)?
                }
                Token::End => {
                    sc.finish_frame(&mut |f| out.write(&f))?;
                    warn(&mut sc, &mut frame);
                    out.write(&Fragment::End)?
                }
            }
        }
        out.flush()?;
        if args.stats {
            let s = sc.stats;
            let record = Record::new("scanconv")
                .with("polygons_in", s.polygons_in)
                .with("polygons_drawn", s.polygons_drawn);
            match sc.region_stats() {
                Some(r) => record
                    .with("pixels_tested", r.pixels_tested)
                    .with("pixels_written", r.pixels_written)
                    .with("runs_out", r.runs)
                    .with("tiles", r.tiles)
                    .with("rounding_decided", s.rounding_decided)
                    .print(&format!(
                        "scanconv: {} polygons in, {} drawn, {} pixels tested, {} written, {} runs out, {} tiles{}",
                        s.polygons_in, s.polygons_drawn, r.pixels_tested, r.pixels_written, r.runs, r.tiles,
                        scan::precision::stats_suffix(s.rounding_decided)
                    )),
                None => record
                    .with("spans", s.spans)
                    .with("pixels", s.pixels)
                    .print(&format!(
                        "scanconv: {} polygons in, {} drawn, {} spans, {} pixels",
                        s.polygons_in, s.polygons_drawn, s.spans, s.pixels
                    )),
            }
        }
        Ok(())
    })
}
