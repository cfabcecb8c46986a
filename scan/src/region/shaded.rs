//! The region z-buffer's shaded span: Gouraud and Phong shading (docs/DESIGN.md,
//! "Shading"), beside the flat span's z-test and apart from it, so that a flat polygon's
//! inner loop is untouched by shading; and the one function that sends a whole polygon,
//! flat or shaded, down the one path or the other.

use super::{pack, RegionBuffer, SHIFT, TILE};
use crate::depth::{depth_at, Depth};
use crate::precision::QuantumWatch;
use crate::walk::Span;
use crate::walk::SpanWalker;
use proto::shade::{Lighting, ShadeRow, Shading};
use proto::Polygon;
use std::ops::Range;
use std::sync::Arc;

impl RegionBuffer {
    /// A whole polygon scan-converted by `walker` into this buffer: flat in its colour,
    /// or shaded where it has per-vertex values ([`Shading::of`], lit by `lighting` in a
    /// Phong-shaded stream); every span also handed to `watch`, where the stream's depth
    /// form is watched ([`crate::precision::QuantumWatch`]). Returns the pixels covered.
    /// The one way a region z-buffer takes a polygon: zbuf reading persp's stream, the
    /// `scanconv --resolve` leaf and [`crate::ZBuffer`].
    pub fn draw_polygon(
        &mut self,
        walker: &mut SpanWalker,
        polygon: &Polygon,
        lighting: Option<&Arc<Lighting>>,
        watch: Option<&mut QuantumWatch>,
    ) -> u64 {
        let (width, height) = self.size();
        match (Shading::of(polygon, lighting), watch) {
            (None, None) => {
                let colour = polygon.colour;
                walker.for_each_span(polygon, width, height, |s| self.draw(&s, colour))
            }
            (None, Some(watch)) => {
                let colour = polygon.colour;
                walker.for_each_span(polygon, width, height, |s| {
                    self.draw(&s, colour);
                    watch.span(&s);
                })
            }
            (Some(shading), mut watch) => walker.for_each_span(polygon, width, height, |s| {
                self.draw_shaded(&s, &shading);
                if let Some(watch) = watch.as_deref_mut() {
                    watch.span(&s);
                }
            }),
        }
    }

    /// One span of a Gouraud-shaded polygon ([`crate::SpanWalker`]), its colours given by
    /// `shading` (`Shading::of(polygon)`): [`RegionBuffer::shaded_span`] with the row's
    /// colours.
    #[inline]
    pub fn draw_shaded(&mut self, span: &Span, shading: &Shading) {
        self.shaded_span(
            span.y,
            span.columns(),
            (span.z_row, span.dz),
            shading.row(span.y),
        );
    }

    /// [`RegionBuffer::span`] for a Gouraud-shaded polygon: pixel x of row `y` has depth
    /// `z_row + x·dz` and, where it is written, the colour
    /// `row.at(x)` ([`ShadeRow::at`]): the polygon's shading at the pixel's centre,
    /// rounded per channel.
    pub fn shaded_span(
        &mut self,
        y: u32,
        columns: Range<u32>,
        (z_row, dz): (Depth, Depth),
        row: ShadeRow<'_>,
    ) {
        if y >= self.height {
            return;
        }
        let x1 = columns.end.min(self.width);
        let mut x = columns.start.min(x1);
        let (ty, offset) = (y >> SHIFT, ((y & (TILE - 1)) << SHIFT) as usize);
        let mut written = 0u64;
        while x < x1 {
            let tx = x >> SHIFT;
            let end = x1.min((tx + 1) << SHIFT);
            let n = (end - x) as usize;
            let tile = self.tile(tx, ty);
            let at = offset + (x & (TILE - 1)) as usize;
            let (bars, colours) = self.tiles.tile_mut(tile);
            let (bars, colours) = (&mut bars[at..at + n], &mut colours[at..at + n]);
            let mut taken = 0;
            for (i, (bar, f)) in bars.iter_mut().zip(colours.iter_mut()).enumerate() {
                let column = x + i as u32;
                let z = depth_at(z_row, dz, column);
                // The flat z-test's rule: an empty pixel, or under the holder's bar.
                let win = (*f == 0 && !z.is_nan()) || z < *bar;
                if win {
                    *bar = proto::depth::bar(z);
                    *f = pack(row.at(column));
                    taken += 1;
                }
            }
            if taken > 0 {
                self.refresh_row_bar(tile, y);
            }
            written += taken;
            self.stats.pixels_tested += n as u64;
            x = end;
        }
        self.stats.pixels_written += written;
    }
}

#[cfg(test)]
mod tests {
    use crate::RegionBuffer;
    use proto::shade::ShadeRow;
    use proto::DVec3;

    #[test]
    fn a_shaded_span_takes_its_colour_per_pixel_and_obeys_the_tie_rule() {
        let mut rb = RegionBuffer::new(4, 1);
        rb.span(0, 0..4, 10.0, 0.0, [9, 9, 9]);
        // Colour 10.4 + 30x in red, falling green, blue 0: nearer at columns 1 and 2,
        // tying at column 0 (the earlier stays), farther at 3.
        rb.shaded_span(
            0,
            0..4,
            (10.0, 0.0),
            ShadeRow::gouraud(DVec3::new(10.4, 200.0, 0.0), DVec3::new(30.0, -50.5, 0.0)),
        );
        assert_eq!(rb.colour_at(0, 0), Some([9, 9, 9]));
        rb.shaded_span(
            0,
            1..4,
            (8.0, 0.5),
            ShadeRow::gouraud(DVec3::new(10.4, 200.0, 0.0), DVec3::new(30.0, -50.5, 0.0)),
        );
        // Depths 8.5, 9, 9.5 at columns 1..3 are nearer than 10.
        assert_eq!(rb.colour_at(1, 0), Some([40, 150, 0]));
        assert_eq!(rb.colour_at(2, 0), Some([70, 99, 0]));
        assert_eq!(rb.colour_at(3, 0), Some([100, 49, 0]));
    }
}
