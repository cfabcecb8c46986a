//! The windows Warnock's subdivision visits, drawn: reads one frame of a screen-space
//! stream (text) on stdin, resolves it, and writes an SVG of the frame's pixels with the
//! outline of every window that was decided, coloured by how (docs/methods.md's
//! pictures: `cargo run --release --example windows < frame.txt > windows.svg`).
//!
//! Outlines: grey, empty; blue, one surrounder fills it; green, an intersector drawn over
//! a surrounder or alone; red, a single pixel decided at its centre.

use proto::{Polygon, SpaceKind, Token};
use scan::frame::HiddenSurface;
use std::fmt::Write as _;
use std::process::ExitCode;
use warnock::{Resolution, Warnock};

/// Draws the windows Warnock's subdivision decides, as SVG.
#[derive(clap::Parser)]
struct Args {}

fn main() -> ExitCode {
    stagecli::main("windows", |_: Args| {
        let mut input = stagecli::read_stdin::<Token>(SpaceKind::Screen)?;
        let (width, height) = input
            .header()
            .space
            .screen_size()
            .ok_or_else(|| stagecli::Error::data("screen-space header without a size"))?;
        let mut polygons: Vec<Polygon> = Vec::new();
        while let Some(token) = stagecli::next(&mut input)? {
            match token {
                Token::Polygon(p) => polygons.push(p),
                Token::Skip(_) => {}
                Token::NextFrame | Token::End => break,
            }
        }
        let mut m = Warnock::new();
        m.record = Some(Vec::new());
        let mut runs = Vec::new();
        m.resolve(&polygons, width, height, &mut runs);
        let mut s = String::new();
        let _ = writeln!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{}" height="{}" viewBox="0 0 {width} {height}">"#,
            512,
            512 * height / width.max(1)
        );
        let _ = writeln!(
            s,
            r#"<rect width="{width}" height="{height}" fill="black"/>"#
        );
        for r in &runs {
            let [cr, cg, cb] = r.colour;
            let _ = writeln!(
                s,
                r#"<rect x="{}" y="{}" width="{}" height="1" fill="rgb({cr},{cg},{cb})"/>"#,
                r.x0,
                r.y,
                r.x1 - r.x0
            );
        }
        for (w, how) in m.record.iter().flatten() {
            let colour = match how {
                Resolution::Subdivided => continue,
                Resolution::Empty => "#888",
                Resolution::Surrounded => "#36f",
                Resolution::OnePolygon | Resolution::InFront => "#2c2",
                Resolution::Pixel => "#f33",
            };
            let _ = writeln!(
                s,
                r#"<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="{colour}" stroke-width="0.15"/>"#,
                w.x0 as f64 + 0.075,
                w.y0 as f64 + 0.075,
                (w.x1 - w.x0) as f64 - 0.15,
                (w.y1 - w.y0) as f64 - 0.15
            );
        }
        s.push_str("</svg>\n");
        print!("{s}");
        eprintln!("windows: {}", m.stats());
        Ok(())
    })
}
