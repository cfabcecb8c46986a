//! The trivial hidden-surface method that docs/extending.md adds, as a test adds it:
//! at each pixel centre, the nearest polygon's colour, found by brute force.
//!
//! Each polygon is taken alone, in stream order, over every pixel centre it covers by
//! the coverage rule (`scan::SpanWalker`, which walks a piece the splitter cut along its
//! original edges, docs/DESIGN.md "Coverage"); a centre's depth is read off the polygon's
//! depth plane at the centre (`scan::Span::depth`, thesis Appendix 3.3), and the polygon
//! takes the centre only when nearer than what holds it by the tie rule (`scan::takes`,
//! docs/DESIGN.md's Z specification). That is the z-buffer's definition (thesis chapter
//! 2.3) with no coherence between polygons and no buffer of its own beyond the answer,
//! so its frames are the z-buffer's byte for byte.
//!
//! A real method is a crate of its own under `bins/`: this file would be its `lib.rs`,
//! and `src/bin/nearest.rs` its `main.rs`.

use proto::{Colour, Polygon};
use scan::frame::push_row_runs;
use scan::{HiddenSurface, Run, SpanWalker};

/// The brute-force method, with its one counter.
#[derive(Default)]
pub struct Nearest {
    walker: SpanWalker,
    /// Pixel centres some polygon covers, summed over the polygons and frames.
    pub centres_tested: u64,
}

impl HiddenSurface for Nearest {
    fn resolve(&mut self, polygons: &[Polygon], width: u32, height: u32, runs: &mut Vec<Run>) {
        let w = width as usize;
        // The nearest depth and colour found so far at each centre.
        let mut nearest: Vec<Option<(f64, Colour)>> = vec![None; w * height as usize];
        for polygon in polygons {
            let covered = self.walker.for_each_span(polygon, width, height, |span| {
                for x in span.columns() {
                    let z = span.depth(x);
                    let pixel = &mut nearest[span.y as usize * w + x as usize];
                    if pixel.is_none_or(|(held, _)| scan::takes(z, held)) {
                        *pixel = Some((z, polygon.colour));
                    }
                }
            });
            self.centres_tested += covered;
        }
        for (y, row) in nearest.chunks(w.max(1)).enumerate() {
            let colours: Vec<Option<Colour>> = row.iter().map(|p| p.map(|(_, c)| c)).collect();
            push_row_runs(y as u32, &colours, runs);
        }
    }

    fn stats(&self) -> String {
        format!("{} centres tested", self.centres_tested)
    }

    fn counters(&self) -> Vec<(&'static str, String)> {
        vec![("centres_tested", self.centres_tested.to_string())]
    }
}
