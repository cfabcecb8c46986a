//! hiddenline: screen-space polygons in, the visible parts of their edges out, as SVG.

use clap::Parser;
use hiddenline::{for_each_segment_by, svg_start, LineStats, Method, Segment, SvgWriter, SVG_END};
use proto::{Colour, Polygon, SpaceKind, Token};
use stagecli::Error;
use stagecli::FrameNames;
use std::io::Write;
use std::process::ExitCode;

/// Hidden-line drawing (Archuleta (1972)): the visible parts of every polygon edge, as
/// SVG.
///
/// Reads a screen-space polygon stream (from persp) on stdin and writes, per frame, an
/// SVG whose viewBox is the screen in device coordinates (`0 0 W H`, X right, Y down, the
/// pixels of the PPM frames), each visible piece of an edge a <line> stroked in its
/// polygon's colour (the pieces of one edge, one after another, one <line> with a
/// stroke-dasharray: the same drawing). By default (`--method continuous`) visibility is
/// exact geometry (f64), not sampled, this program's own way rather than Archuleta's: a
/// piece of an edge is hidden where it lies strictly inside a nearer polygon; at equal
/// depth the earlier polygon hides the later. `--method archuleta` is Archuleta's own
/// output of Watkins's scan-line algorithm. An edge two polygons share is drawn once;
/// edges that the splitter tree or the clipper made (cuts along a splitting plane, the
/// screen's border) are not drawn. Where two polygons pass through each other, the
/// visible part of their line of intersection is drawn as <line class="intersection">
/// (Archuleta's "second problem"), in the colour of the earlier polygon.
///
/// One frame goes to stdout; a movie needs -o with %d in the name.
///
/// Examples:
///   viewxf < examples/cube.txt | clipbatch | persp --size 400x400 | hiddenline > cube.svg
///   scene spheres --frames 10 | viewxf | clipbatch | persp --size 300x300 | hiddenline -o f%03d.svg
#[derive(Parser)]
#[command(name = "hiddenline", version, verbatim_doc_comment)]
struct Args {
    /// Write one file per frame instead of one SVG on stdout: `%d` or `%0Nd` in the name
    /// is the frame number from 0 (as zbuf's -o); the name must end .svg.
    #[arg(short = 'o', value_name = "PATTERN")]
    output: Option<String>,
    /// Background colour R,G,B (a rectangle under the lines).
    #[arg(long, value_parser = stagecli::parse_colour, default_value = "255,255,255")]
    background: Colour,
    /// Line width in pixels.
    #[arg(long, default_value_t = 1.0, value_parser = stagecli::numbers::positive)]
    stroke_width: f64,
    /// Print counts on stderr at the end: frames, edges, edges left out (shared, cuts,
    /// screen border), edge–polygon pairs tested, pieces drawn; lines of intersection and
    /// their pieces drawn; placements of polygons in the grid's cells that a surrounder
    /// hid.
    #[arg(long)]
    stats: bool,
    /// How the visible pieces are found: `continuous` (this program's own), each edge
    /// against the polygons that may hide it in exact geometry; or `archuleta`,
    /// Archuleta's (1972): counters on the visible segments of Watkins's scan-line
    /// algorithm (the scanline stage's), a line drawn when its edge exits or stops being
    /// visible, its ends between the screen's rows (raster resolution in Y). With --stats
    /// under archuleta, "pairs tested" counts the edges' visibility tests, one an edge a
    /// scan line, and "visible segments" Watkins's segments passed on.
    #[arg(long, value_enum, default_value_t = MethodArg::Continuous)]
    method: MethodArg,
    /// Score the drawing against a reference drawing of the same frame (an SVG as this
    /// program writes it, e.g. the continuous method's): print on stderr its line error,
    /// the length of the reference's lines that no drawn line comes within half the
    /// line width of (visible lines missed), plus the length drawn that no reference
    /// line comes within half the line width of (hidden lines drawn), in pixels,
    /// intersection lines included, computed exactly (lines::line_error). One frame.
    #[arg(long, value_name = "REFERENCE.svg")]
    score: Option<String>,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum MethodArg {
    Continuous,
    Archuleta,
}

fn main() -> ExitCode {
    stagecli::main("hiddenline", |args: Args| {
        let pattern = args
            .output
            .as_deref()
            .map(|p| FrameNames::parse_ending(p, &["svg"]).map(|(names, _)| names))
            .transpose()
            .map_err(Error::usage)?;
        let mut input = stagecli::read_stdin::<Token>(SpaceKind::Screen)?;
        if let Some((name, word)) = input.header().attributes.smooth_shading() {
            return Err(Error::usage(format!(
                "hiddenline strokes each polygon's edges in its one colour, and this stream \
                 is {name}-shaded (its header says `{word}`); shading is drawn by every \
                 hidden-surface method (render.sh --hse zbuf, scanline, warnock, painter) and \
                 by anti-aliasing (--aa ssK, abuf)"
            )));
        }
        let (width, height) = input
            .header()
            .space
            .screen_size()
            .ok_or_else(|| Error::data("screen-space header without a size"))?;
        let reference = match &args.score {
            Some(name) => {
                let text = std::fs::read_to_string(name)
                    .map_err(|e| Error::io(format!("cannot read {name}: {e}")))?;
                Some(lines::read_svg(&text).map_err(|e| Error::data(format!("{name}: {e}")))?)
            }
            None => None,
        };
        let mut drawn: Vec<Segment> = Vec::new();
        let mut stats = LineStats::default();
        let mut polygons: Vec<Polygon> = Vec::new();
        let mut frame = 0u64;
        while let Some(token) = stagecli::next(&mut input)? {
            match token {
                Token::Polygon(p) => {
                    scan::check_on_screen(&p, width, height)
                        .map_err(|m| Error::data(format!("{}: {m}", input.position())))?;
                    stagecli::refuse_transparent("hiddenline", &p, || input.position())?;
                    polygons.push(p);
                    continue;
                }
                Token::Skip(_) => continue,
                Token::NextFrame | Token::End => {}
            }
            // The SVG is written as its pieces are found: memory for the frame's
            // polygons, not for its drawing.
            let mut file: Option<std::io::BufWriter<stagecli::whole::WholeFile>> = None;
            let mut sink: Box<dyn Write> =
                match &pattern {
                    Some(p) if frame > 0 && !p.numbered() => {
                        return Err(Error::data(format!(
                        "-o {}: more than one frame, but the name has no %d for the frame number",
                        args.output.as_deref().unwrap_or_default()
                    )))
                    }
                    // Written whole or not at all: a temporary renamed when complete.
                    Some(p) => {
                        let whole = stagecli::whole::WholeFile::create(p.name(frame))?;
                        file = Some(std::io::BufWriter::with_capacity(1 << 16, whole));
                        Box::new(std::io::sink())
                    }
                    None if frame > 0 => return Err(Error::data(
                        "more than one frame: give -o with %d in the name (e.g. -o frame%03d.svg)",
                    )),
                    None => Box::new(stagecli::stdout()),
                };
            let mut text = svg_start(width, height, args.background, args.stroke_width);
            let mut failed: Option<std::io::Error> = None;
            let method = match args.method {
                MethodArg::Continuous => Method::Continuous,
                MethodArg::Archuleta => Method::Archuleta,
            };
            let mut joined = SvgWriter::new();
            if reference.is_some() && frame > 0 {
                return Err(Error::data(
                    "--score compares one frame with its reference, and this stream has more",
                ));
            }
            for_each_segment_by(method, &polygons, width, height, &mut stats, |seg| {
                if reference.is_some() {
                    drawn.push(seg);
                }
                joined.push(&mut text, &seg);
                if text.len() >= 1 << 16 && failed.is_none() {
                    failed = match &mut file {
                        Some(f) => f.write_all(text.as_bytes()),
                        None => sink.write_all(text.as_bytes()),
                    }
                    .err();
                    text.clear();
                }
            });
            polygons.clear();
            joined.flush(&mut text);
            text.push_str(SVG_END);
            if let Some(e) = failed {
                return Err(e.into());
            }
            match file {
                Some(mut f) => {
                    f.write_all(text.as_bytes())?;
                    f.into_inner().map_err(|e| e.into_error())?.commit()?;
                }
                None => {
                    sink.write_all(text.as_bytes())?;
                    sink.flush()?;
                }
            }
            frame += 1;
            stagecli::progress::frame_done();
        }
        if let Some(reference) = &reference {
            let e = lines::line_error(&drawn, reference, args.stroke_width / 2.0);
            eprintln!(
                "hiddenline: line error {:.3} px: {:.3} px of the reference's {:.3} px missed, \
                 {:.3} px of the {:.3} px drawn not on it",
                e.total_px(),
                e.missed_px,
                e.reference_px,
                e.extra_px,
                e.drawn_px
            );
        }
        if args.stats {
            let s = stats;
            stagecli::stats::Record::new("hiddenline")
                .with("frames", frame)
                .with("edges", s.edges)
                .with("shared", s.shared)
                .with("cuts", s.cuts)
                .with("border", s.border)
                .with("pairs_tested", s.pairs_tested)
                .with("pieces", s.segments)
                .with("intersection_lines", s.intersection_lines)
                .with("intersection_pieces", s.intersections)
                .with("culled", s.culled)
                .with("neighbours_passed", s.neighbours)
                .with("visible_segments", s.visible_segments)
                .print(&format!(
                    "hiddenline: {frame} frames, {} edges, {} shared, {} cuts, {} on the border, {} pairs tested, {} pieces drawn; \
                     {} lines of intersection, {} pieces drawn; {} placements in cells hidden by a surrounder; \
                     {} pairs of neighbours passed over; {} visible segments",
                    s.edges, s.shared, s.cuts, s.border, s.pairs_tested, s.segments,
                    s.intersection_lines, s.intersections, s.culled, s.neighbours,
                    s.visible_segments
                ));
        }
        Ok(())
    })
}
