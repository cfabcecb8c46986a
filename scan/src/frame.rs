//! A frame of screen-space polygons resolved by a hidden-surface method (docs/DESIGN.md,
//! "Leaves resolve visibility").
//!
//! The z-buffer resolves polygons one at a time, as they arrive. The other methods of the
//! seeds need the whole frame first: Watkins's scan line walks every polygon's edges row
//! by row, Warnock's subdivision sorts every polygon into windows, the painter sorts them
//! all by depth. A stage for one of them gathers a frame's polygons in stream order and
//! hands them to its [`HiddenSurface`] at the frame's end; the method answers with the
//! frame's finished pixels as [`Run`]s, which the merger places like a z-buffer leaf's.
//!
//! Every method samples as [`crate::SpanWalker`] does (pixel centres, top-left rule) and
//! breaks a tie of equal depth the z-buffer's way (the polygon earlier in the stream
//! wins), so that those that are exact give frames byte-identical to [`ZBuffer`]'s.
//! [`ZBuffer`] and [`image_of`] are here for their tests to compare against.

use crate::region::{RegionBuffer, Run};
use crate::walk::SpanWalker;
use proto::shade::{Lighting, Shading};
use proto::{Colour, Polygon};
use std::ops::Range;
use std::sync::Arc;

/// A hidden-surface method that resolves a whole frame at once.
pub trait HiddenSurface {
    /// Resolves one frame. `polygons` are the frame's screen-space polygons in stream
    /// order (at equal depth the earlier one is in front), on a `width`×`height` screen.
    /// Pushes the pixels some polygon covers onto `runs`, each pixel once, in its visible
    /// polygon's colour; pixels no polygon covers are left out (the merger shows the
    /// background there).
    fn resolve(&mut self, polygons: &[Polygon], width: u32, height: u32, runs: &mut Vec<Run>);

    /// The method's counters over all frames so far, for `--stats`: one line, without the
    /// stage's name (`12 windows at depth 0, …`).
    fn stats(&self) -> String;

    /// The same counters as [`HiddenSurface::stats`], as the fields of the stage's
    /// `--stats` record (`stagecli::stats`): a key a counter, in the line's order
    /// (docs/DESIGN.md, "Structured stats", lists the keys).
    fn counters(&self) -> Vec<(&'static str, String)>;

    /// Where a method that draws shaded polygons keeps the lighting of a Phong-shaded
    /// stream, lent to [`HiddenSurface::shades`] and [`HiddenSurface::set_lighting`]: a
    /// method that shades holds an `Option<Arc<Lighting>>` and answers
    /// `Some(&mut self.lighting)`, and lights each pixel of a shaded polygon by it
    /// ([`proto::shade::Shading::of`]). `None`, the default: the method draws each
    /// polygon in one colour.
    fn lighting(&mut self) -> Option<&mut Option<Arc<Lighting>>> {
        None
    }

    /// Whether the method draws Gouraud- and Phong-shaded polygons (vertex colours or
    /// normals, docs/DESIGN.md, "Shading"): whether it keeps a lighting
    /// ([`HiddenSurface::lighting`]). A stage whose method does not refuses a stream that
    /// declares them, rather than drawing it flat.
    fn shades(&mut self) -> bool {
        self.lighting().is_some()
    }

    /// The lighting of a Phong-shaded stream (its header says `vertex-normals`), given
    /// before the first frame and kept where [`HiddenSurface::lighting`] says; `None` for
    /// a Gouraud or flat stream.
    fn set_lighting(&mut self, lighting: Option<Arc<Lighting>>) {
        if let Some(slot) = self.lighting() {
            *slot = lighting;
        }
    }

    /// Whether the method draws polygons of opacity below 255 as transparent; a stage whose
    /// method does not refuses such a polygon rather than draw it opaque.
    fn transparency(&self) -> bool {
        false
    }
}

/// The z-buffer (thesis chapter 2.3) as a [`HiddenSurface`]: the reference the other
/// methods must match pixel for pixel.
#[derive(Default)]
pub struct ZBuffer {
    walker: SpanWalker,
    region: Option<RegionBuffer>,
    lighting: Option<Arc<Lighting>>,
}

impl ZBuffer {
    pub fn new() -> Self {
        ZBuffer::default()
    }
}

impl HiddenSurface for ZBuffer {
    fn resolve(&mut self, polygons: &[Polygon], width: u32, height: u32, runs: &mut Vec<Run>) {
        let region = match &mut self.region {
            Some(r) if r.size() == (width, height) => r,
            slot => slot.insert(RegionBuffer::new(width, height)),
        };
        for p in polygons {
            region.draw_polygon(&mut self.walker, p, self.lighting.as_ref(), None);
        }
        let Ok(()) = region.finish_frame(|run| {
            runs.push(run);
            Ok::<(), std::convert::Infallible>(())
        });
    }

    fn lighting(&mut self) -> Option<&mut Option<Arc<Lighting>>> {
        Some(&mut self.lighting)
    }

    fn stats(&self) -> String {
        let s = self.region.as_ref().map(|r| r.stats).unwrap_or_default();
        format!(
            "{} pixels tested, {} written",
            s.pixels_tested, s.pixels_written
        )
    }

    fn counters(&self) -> Vec<(&'static str, String)> {
        let s = self.region.as_ref().map(|r| r.stats).unwrap_or_default();
        vec![
            ("pixels_tested", s.pixels_tested.to_string()),
            ("pixels_written", s.pixels_written.to_string()),
        ]
    }
}

/// The first two runs in a row of `runs` that should have been one: on the same row,
/// the second starting where the first ends, in the same colour. `None` where every run
/// is as long as it can be (what the methods promise, shaded pixels included).
pub fn unjoined_runs(runs: &[Run]) -> Option<(Run, Run)> {
    runs.windows(2)
        .map(|pair| (pair[0], pair[1]))
        .find(|(a, b)| a.y == b.y && a.x1 == b.x0 && a.colour == b.colour)
}

/// A small xorshift generator of numbers in [0, 1), for the methods' tests of random
/// scenes: the same scene from the same `seed` on every platform, no crate needed.
pub fn pseudo_random(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The rectangle from (x0, y0) to (x1, y1) on the screen at constant depth `z`, its
/// corners in the order (x0, y0), (x1, y0), (x1, y1), (x0, y1) (clockwise on a screen
/// whose Y grows downward): the methods' tests' commonest polygon.
pub fn square(colour: Colour, x0: f64, y0: f64, x1: f64, y1: f64, z: f64) -> Polygon {
    Polygon::from_xyz(
        colour,
        &[[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]],
    )
}

/// Three 8×8 squares red, green and blue, at depths z, z(1 − ½t) and z(1 − 1.2t) (t the
/// tie width, z = 0.25): each within the tie of the next, the first and the third not.
/// In that stream order the second fails to take a pixel from the first and the third
/// takes it, so the z-buffer shows blue, and a method that orders them pair by pair (the
/// tie rule is not transitive) does not: the methods' tests of the tie rule's fold
/// (differential seed 200470, made plain).
pub fn near_ties() -> [Polygon; 3] {
    let (z, t) = (0.25, proto::depth::TIE);
    [
        square([255, 0, 0], 0.0, 0.0, 8.0, 8.0, z),
        square([0, 255, 0], 0.0, 0.0, 8.0, 8.0, z * (1.0 - 0.5 * t)),
        square([0, 0, 255], 0.0, 0.0, 8.0, 8.0, z * (1.0 - 1.2 * t)),
    ]
}

/// Differential seed 50385, the two quads of it that differ: a screen-filling quad and a
/// copy 5e-11 nearer at each vertex, later in the stream, their depth through 0 near one
/// corner (on a 68×68 screen). The tie is relative to the held depth, so the copy takes
/// the pixels only where the first's depth is within 5e-11·2³⁰ of 0, a band across the
/// screen with the first quad on both sides of it: the methods' tests of a tie whose
/// answer changes twice along a line.
pub fn nearer_copy_through_depth_zero() -> [Polygon; 2] {
    let first = [
        [2.0, 65.875, 0.49931175253695725],
        [66.375, 65.875, -0.09677305106166045],
        [70.125, -2.125, 0.42284109596243646],
        [5.75, -2.125, 1.0189258995610544],
    ];
    let copy = [
        [2.0, 65.875, 0.49931175248741827],
        [66.375, 65.875, -0.09677305111119938],
        [70.125, -2.125, 0.42284109591289754],
        [5.75, -2.125, 1.0189258995115154],
    ];
    [
        Polygon::from_xyz([131, 155, 120], &first),
        Polygon::from_xyz([127, 79, 235], &copy),
    ]
}

/// The picture `runs` paint on a `width`×`height` screen, row-major: `None` where no run
/// reaches. A pixel painted twice is an error of the method that made the runs, and
/// panics here, in its tests.
pub fn image_of(runs: &[Run], width: u32, height: u32) -> Vec<Option<Colour>> {
    let mut image = vec![None; width as usize * height as usize];
    for run in runs {
        assert!(
            run.y < height && run.x0 <= run.x1 && run.x1 <= width,
            "run off the screen: {run:?}"
        );
        let row = run.y as usize * width as usize;
        for x in run.x0..run.x1 {
            let pixel = &mut image[row + x as usize];
            assert!(pixel.is_none(), "pixel ({x}, {}) painted twice", run.y);
            *pixel = Some(run.colour);
        }
    }
    image
}

/// The z-buffer's picture of `polygons`: what every exact method must give.
pub fn zbuffer_image(polygons: &[Polygon], width: u32, height: u32) -> Vec<Option<Colour>> {
    let mut runs = Vec::new();
    ZBuffer::new().resolve(polygons, width, height, &mut runs);
    image_of(&runs, width, height)
}

/// Pixels where two pictures differ.
pub fn differing_pixels(a: &[Option<Colour>], b: &[Option<Colour>]) -> usize {
    assert_eq!(a.len(), b.len(), "pictures of different sizes");
    a.iter().zip(b).filter(|(p, q)| p != q).count()
}

/// The runs of one row of finished pixels (`None`: not covered), each as long as it can
/// be: how a method that decides a row at a time sends it.
pub fn push_row_runs(y: u32, row: &[Option<Colour>], runs: &mut Vec<Run>) {
    push_row_runs_at(y, 0, row, runs)
}

/// [`push_row_runs`] for a piece of a row whose first pixel is column `x0`.
pub fn push_row_runs_at(y: u32, x0: u32, row: &[Option<Colour>], runs: &mut Vec<Run>) {
    let mut x = 0;
    while x < row.len() {
        let Some(colour) = row[x] else {
            x += 1;
            continue;
        };
        let start = x;
        while x < row.len() && row[x] == Some(colour) {
            x += 1;
        }
        runs.push(Run {
            y,
            x0: x0 + start as u32,
            x1: x0 + x as u32,
            colour,
        });
    }
}

/// Columns `columns` of row `y` of a Gouraud- or Phong-shaded polygon (docs/DESIGN.md,
/// "Shading"), each pixel in its colour at its centre, as [`proto::shade`] computes it
/// (the row once, then [`proto::shade::ShadeRow::at`] per pixel, exactly as the z-buffer's
/// shaded span): handed to `paint(x0, x1, colour)` as maximal runs of one colour, left to
/// right. How the methods that decide a span's visible polygon and send runs (scan line, area
/// subdivision, depth sort) draw a shaded one: a run of equal colours is one record, so a
/// shallow gradient costs less than a pixel each.
#[inline]
pub fn shaded_runs(
    shading: &Shading,
    y: u32,
    columns: Range<u32>,
    mut paint: impl FnMut(u32, u32, Colour),
) {
    if columns.is_empty() {
        return;
    }
    let row = shading.row(y);
    let mut x0 = columns.start;
    let mut colour = row.at(x0);
    for x in columns.start + 1..columns.end {
        let c = row.at(x);
        if c != colour {
            paint(x0, x, colour);
            (x0, colour) = (x, c);
        }
    }
    paint(x0, columns.end, colour);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_zbuffer_keeps_the_nearer_and_the_earlier_of_a_tie() {
        let polygons = [
            square([1, 0, 0], 0.0, 0.0, 2.0, 2.0, 0.5),
            square([2, 0, 0], 1.0, 0.0, 3.0, 1.0, 0.25), // nearer: wins (1, 0)
            square([3, 0, 0], 0.0, 1.0, 1.0, 2.0, 0.5),  // a tie: the first square keeps (0, 1)
        ];
        let image = zbuffer_image(&polygons, 3, 2);
        let r = |v| Some([v, 0, 0]);
        assert_eq!(image, vec![r(1), r(2), r(2), r(1), r(1), None]);
    }

    #[test]
    fn a_shaded_span_becomes_runs_of_its_pixel_centre_colours() {
        // Red 10.2 + 0.4·X at the centre X = x + ½: 10.4, 10.8, 11.2, 11.6, 12.0, 12.4
        // for columns 0..6, so 10, 11, 11, 12, 12, 12; green and blue constant.
        let planes = [
            proto::DVec4::new(-0.4, 0.0, 1.0, -10.2),
            proto::DVec4::new(0.0, 0.0, 1.0, -7.0),
            proto::DVec4::new(0.0, 0.0, 1.0, -200.0),
        ];
        let shading = Shading::new(planes);
        let mut got = Vec::new();
        shaded_runs(&shading, 3, 0..6, |a, b, c| got.push((a, b, c)));
        assert_eq!(
            got,
            vec![
                (0, 1, [10, 7, 200]),
                (1, 3, [11, 7, 200]),
                (3, 6, [12, 7, 200])
            ]
        );
        // Every pixel is the one `Shading::at` gives it; an empty span paints nothing.
        for &(a, b, c) in &got {
            assert!((a..b).all(|x| shading.at(x, 3) == c));
        }
        shaded_runs(&shading, 3, 4..4, |_, _, _| panic!("painted an empty span"));
    }

    #[test]
    fn rows_become_runs_of_one_colour() {
        let row = [
            None,
            Some([1, 1, 1]),
            Some([1, 1, 1]),
            Some([2, 2, 2]),
            None,
        ];
        let mut runs = Vec::new();
        push_row_runs(7, &row, &mut runs);
        assert_eq!(
            runs,
            vec![
                Run {
                    y: 7,
                    x0: 1,
                    x1: 3,
                    colour: [1, 1, 1]
                },
                Run {
                    y: 7,
                    x0: 3,
                    x1: 4,
                    colour: [2, 2, 2]
                },
            ]
        );
        assert_eq!(image_of(&runs, 5, 8)[7 * 5..], row);
    }
}
