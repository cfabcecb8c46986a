//! # scanconv: screen-space polygons → fragments, or a leaf's finished pixels
//! (thesis chapter 4.2.2, Appendix 3; docs/DESIGN.md, "Leaves resolve visibility")
//!
//! The scan converter of the Z-buffer HSE algorithm. The scan conversion itself (the
//! Edge Table and Active Edge Table, the pixel-centre coverage rule, the depth plane
//! stepped in fixed point) is the [`scan`] crate's, shared with every hidden-surface
//! method; this stage decides what becomes of the spans:
//!
//! - [`Output::Spans`] and [`Output::Pixels`]: sent on as fragments, each polygon's
//!   colour record then its spans (or the thesis's one record per pixel), for `zbuf` to
//!   depth-test: the thesis's PAR.BUFF design, every fragment to one Z-buffer.
//! - [`Output::Resolve`]: depth-tested here, in a [`RegionBuffer`] for the part of the
//!   screen this leaf of the splitter tree covers, and sent on at the end of each frame
//!   as runs of finished pixels (`Fragment::Run`), which `zbuf` places without a depth
//!   test. The leaves share the per-pixel work; the merger only assembles.

use proto::shade::Shading;
use proto::Fragment;
use scan::precision::QuantumWatch;
pub use scan::{check_on_screen, depth_at, DepthPlane, GUARD_BAND};
use scan::{RegionBuffer, SpanWalker};

/// What becomes of covered pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Output {
    /// Runs of pixels on one row, with the row's depth at column 0 and a step (the default).
    #[default]
    Spans,
    /// One record per pixel, the thesis's (colour, x, y, depth) quadruplet.
    Pixels,
    /// Visibility resolved here; finished runs of one colour sent at each frame's end.
    Resolve,
}

/// Counts for `--stats`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Polygons read.
    pub polygons_in: u64,
    /// Polygons that covered at least one pixel.
    pub polygons_drawn: u64,
    /// Span records written.
    pub spans: u64,
    /// Pixels covered (whether sent as spans or as pixels, or depth-tested here).
    pub pixels: u64,
    /// Depth tests that rounding, not the tie rule, decided ([`scan::precision`]).
    pub rounding_decided: u64,
}

/// The scan converter for one screen, its tables reused from polygon to polygon.
pub struct ScanConverter {
    width: u32,
    height: u32,
    output: Output,
    walker: SpanWalker,
    /// The leaf's Z-buffer, in [`Output::Resolve`] only.
    region: Option<RegionBuffer>,
    /// Where rounding in a coarse depth form decides ties, in [`Output::Resolve`] only
    /// ([`scan::precision`]).
    watch: Option<QuantumWatch>,
    /// The lighting of a Phong-shaded stream, in [`Output::Resolve`]
    /// ([`ScanConverter::light`]).
    lighting: Option<std::sync::Arc<proto::shade::Lighting>>,
    pub stats: Stats,
}

impl ScanConverter {
    pub fn new(width: u32, height: u32, output: Output) -> Self {
        ScanConverter {
            width,
            height,
            output,
            walker: SpanWalker::new(),
            region: (output == Output::Resolve).then(|| RegionBuffer::new(width, height)),
            watch: None,
            lighting: None,
            stats: Stats::default(),
        }
    }

    /// When resolving, watch for depth tests that the stream's depth `form` (its header's)
    /// is too coarse to decide by the tie rule ([`scan::precision::QuantumWatch`]); a form
    /// that is fine enough everywhere costs nothing.
    pub fn watch_depth(&mut self, form: Option<proto::DepthForm>) {
        if self.output == Output::Resolve {
            self.watch = QuantumWatch::for_form(form, self.width, self.height);
        }
    }

    /// When resolving a Phong-shaded stream (its header says `vertex-normals`), light its
    /// pixels by the header's lighting (`attributes.phong()`); sending fragments, the
    /// merger lights them.
    pub fn light(&mut self, lighting: Option<std::sync::Arc<proto::shade::Lighting>>) {
        self.lighting = lighting;
    }

    /// At a frame's end (`frame` from 0): the warning for it, when rounding decided some
    /// of its depth tests ([`ScanConverter::watch_depth`]), counted in
    /// [`Stats::rounding_decided`].
    pub fn quantum_warning(&mut self, frame: u64) -> Option<String> {
        let (lost, warning) = self.watch.as_mut()?.finish_frame(frame);
        self.stats.rounding_decided += lost;
        warning
    }

    /// The region buffer's counts (pixels tested and written, runs, tiles), in
    /// [`Output::Resolve`].
    pub fn region_stats(&self) -> Option<scan::RegionStats> {
        self.region.as_ref().map(|r| r.stats)
    }

    /// Scan-converts one polygon. Sending fragments: its colour record, then its spans or
    /// pixels, each handed to `emit` in order (top row first, left to right); a polygon
    /// that covers nothing still sends its colour record, to keep the numbering.
    /// Resolving: its spans go into the region buffer and nothing is sent.
    pub fn convert<E>(
        &mut self,
        polygon: &proto::Polygon,
        emit: &mut impl FnMut(Fragment) -> Result<(), E>,
    ) -> Result<(), E> {
        self.stats.polygons_in += 1;
        let (width, height) = (self.width, self.height);
        let covered = match (self.output, &mut self.region) {
            (Output::Resolve, Some(region)) => region.draw_polygon(
                &mut self.walker,
                polygon,
                self.lighting.as_ref(),
                self.watch.as_mut(),
            ),
            (Output::Pixels, _) => {
                emit(Fragment::Polygon(polygon.colour))?;
                emit_shade(polygon, emit)?;
                self.walker.spans(polygon, width, height, |s| {
                    for x in s.columns() {
                        emit(Fragment::Pixel {
                            x,
                            y: s.y,
                            z: s.depth(x),
                        })?;
                    }
                    Ok(())
                })?
            }
            _ => {
                emit(Fragment::Polygon(polygon.colour))?;
                emit_shade(polygon, emit)?;
                let spans = &mut self.stats.spans;
                self.walker.spans(polygon, width, height, |s| {
                    *spans += 1;
                    emit(Fragment::Span {
                        y: s.y,
                        x0: s.x0,
                        x1: s.x1,
                        z: s.z_row,
                        dz: s.dz,
                    })
                })?
            }
        };
        if covered > 0 {
            self.stats.polygons_drawn += 1;
        }
        self.stats.pixels += covered;
        Ok(())
    }

    /// `skip n`: n polygons of which this stream carries nothing. Passed on as it is when
    /// sending fragments (it keeps zbuf's polygon numbering); when resolving, the order
    /// of the polygons is all a tie needs (see [`scan::region`]), so nothing is sent.
    pub fn skip<E>(
        &mut self,
        n: u32,
        emit: &mut impl FnMut(Fragment) -> Result<(), E>,
    ) -> Result<(), E> {
        match self.output {
            Output::Resolve => Ok(()),
            Output::Spans | Output::Pixels => emit(Fragment::Skip(n)),
        }
    }

    /// The end of a frame (before its NEXT.FRAME or END is sent): when resolving, the
    /// frame's finished pixels as runs, rows top to bottom, and the buffer cleared for
    /// the next frame. Sending fragments, nothing.
    pub fn finish_frame<E>(
        &mut self,
        emit: &mut impl FnMut(Fragment) -> Result<(), E>,
    ) -> Result<(), E> {
        match &mut self.region {
            Some(region) => region.finish_frame(|r| emit(r.into())),
            None => Ok(()),
        }
    }
}

/// A Gouraud-shaded polygon's colour planes (a Phong-shaded one's normal planes), as three
/// `shade` records after its colour record (docs/DESIGN.md, "Fragment records"): one
/// record a channel a polygon, where per-span gradients would be six numbers a span.
/// Nothing for a flat polygon.
fn emit_shade<E>(
    polygon: &proto::Polygon,
    emit: &mut impl FnMut(Fragment) -> Result<(), E>,
) -> Result<(), E> {
    if let Some(shading) = Shading::of(polygon, None) {
        for (channel, plane) in shading.planes().iter().enumerate() {
            emit(Fragment::Shade {
                channel: channel as u8,
                plane: [plane.x, plane.y, plane.w],
            })?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proto::Polygon;

    fn poly(points: &[[f64; 3]]) -> Polygon {
        Polygon::from_xyz([10, 20, 30], points)
    }

    /// Runs the converter over one frame and returns its fragments (and the runs at its
    /// end, when resolving).
    fn run(w: u32, h: u32, output: Output, polys: &[Polygon]) -> Vec<Fragment> {
        let mut sc = ScanConverter::new(w, h, output);
        let mut out = Vec::new();
        let mut push = |f| {
            out.push(f);
            Ok::<_, ()>(())
        };
        for p in polys {
            sc.convert(p, &mut push).unwrap();
        }
        sc.finish_frame(&mut push).unwrap();
        out
    }

    fn square(colour: proto::Colour, x0: f64, x1: f64, z: f64) -> Polygon {
        Polygon::from_xyz(
            colour,
            &[[x0, 1.0, z], [x1, 1.0, z], [x1, 3.0, z], [x0, 3.0, z]],
        )
    }

    #[test]
    fn square_covers_its_pixels_at_constant_depth() {
        let sq = square([10, 20, 30], 1.0, 3.0, 0.5);
        let frags = run(4, 4, Output::Spans, &[sq]);
        let span = |y| Fragment::Span {
            y,
            x0: 1,
            x1: 3,
            z: 0.5,
            dz: 0.0,
        };
        assert_eq!(
            frags,
            vec![Fragment::Polygon([10, 20, 30]), span(1), span(2)]
        );
    }

    #[test]
    fn pixels_carry_the_depths_of_the_spans() {
        // depth = X/8 + Y/16: a span's z + x·dz is each pixel's depth.
        let p = |x: f64, y: f64| [x, y, x / 8.0 + y / 16.0];
        let sq = poly(&[p(0.0, 0.0), p(4.0, 0.0), p(4.0, 4.0), p(0.0, 4.0)]);
        let pixels = run(4, 4, Output::Pixels, std::slice::from_ref(&sq));
        assert_eq!(pixels.len(), 17);
        let mut from_spans = vec![];
        for f in &run(4, 4, Output::Spans, &[sq])[1..] {
            let Fragment::Span { y, x0, x1, z, dz } = *f else {
                panic!("{f:?}")
            };
            for x in x0..x1 {
                from_spans.push(Fragment::Pixel {
                    x,
                    y,
                    z: proto::fragment::span_depth(z, dz, x),
                });
            }
        }
        assert_eq!(from_spans, pixels[1..]);
    }

    #[test]
    fn degenerate_polygons_emit_only_their_colour() {
        let frags = run(
            4,
            4,
            Output::Spans,
            &[
                poly(&[]),
                poly(&[[1.0, 1.0, 0.0]]),
                poly(&[[1.0, 1.0, 0.0], [3.0, 3.0, 0.0]]),
                poly(&[[1.1, 1.1, 0.0], [1.4, 1.1, 0.0], [1.4, 1.4, 0.0]]),
                poly(&[[-5.0, -5.0, 0.0], [-1.0, -5.0, 0.0], [-1.0, -1.0, 0.0]]),
                poly(&[[0.0, 0.0, 0.7], [4.0, 4.0, 0.2], [2.0, 2.0, 0.9]]),
            ],
        );
        assert_eq!(frags, vec![Fragment::Polygon([10, 20, 30]); 6]);
    }

    #[test]
    fn resolving_sends_only_the_finished_runs() {
        // Red at depth 0.5 over columns 1..3, green nearer over 2..4, blue level with red
        // over 0..2 (a tie: the earlier red keeps column 1).
        let (r, g, b) = ([255, 0, 0], [0, 255, 0], [0, 0, 255]);
        let frags = run(
            5,
            4,
            Output::Resolve,
            &[
                square(r, 1.0, 3.0, 0.5),
                square(g, 2.0, 4.0, 0.25),
                square(b, 0.0, 2.0, 0.5),
            ],
        );
        let runs = |y| {
            [
                Fragment::Run {
                    y,
                    x0: 0,
                    x1: 1,
                    colour: b,
                },
                Fragment::Run {
                    y,
                    x0: 1,
                    x1: 2,
                    colour: r,
                },
                Fragment::Run {
                    y,
                    x0: 2,
                    x1: 4,
                    colour: g,
                },
            ]
        };
        assert_eq!(frags, [runs(1), runs(2)].concat());
    }

    #[test]
    fn skips_pass_on_unless_resolving() {
        let mut out = vec![];
        let mut push = |f| {
            out.push(f);
            Ok::<_, ()>(())
        };
        ScanConverter::new(4, 4, Output::Spans)
            .skip(3, &mut push)
            .unwrap();
        ScanConverter::new(4, 4, Output::Resolve)
            .skip(3, &mut push)
            .unwrap();
        assert_eq!(out, [Fragment::Skip(3)]);
    }

    #[test]
    fn stats_count() {
        let mut sc = ScanConverter::new(4, 4, Output::Spans);
        for p in [square([1, 1, 1], 1.0, 3.0, 0.5), poly(&[])] {
            sc.convert(&p, &mut |_| Ok::<_, ()>(())).unwrap();
        }
        assert_eq!(
            sc.stats,
            Stats {
                polygons_in: 2,
                polygons_drawn: 1,
                spans: 2,
                pixels: 4,
                rounding_decided: 0
            }
        );
        assert_eq!(sc.region_stats(), None);
        let mut sc = ScanConverter::new(4, 4, Output::Resolve);
        for p in [
            square([1, 1, 1], 1.0, 3.0, 0.5),
            square([2, 2, 2], 1.0, 2.0, 0.25),
        ] {
            sc.convert(&p, &mut |_| Ok::<_, ()>(())).unwrap();
        }
        sc.finish_frame(&mut |_| Ok::<_, ()>(())).unwrap();
        assert_eq!(
            sc.stats,
            Stats {
                polygons_in: 2,
                polygons_drawn: 2,
                spans: 0,
                pixels: 6,
                rounding_decided: 0
            }
        );
        assert_eq!(
            sc.region_stats(),
            Some(scan::RegionStats {
                pixels_tested: 6,
                pixels_written: 6,
                pixels_behind_row: 0,
                runs: 4,
                tiles: 1
            })
        );
    }
}
