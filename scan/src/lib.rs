//! # scan: the scan conversion every hidden-surface stage shares (thesis Appendix 3)
//!
//! A screen-space polygon becomes, row by row, the spans of pixels whose centres it
//! covers, each with the depth of the polygon's plane at its pixels. This is the part of
//! the thesis's SCAN.CONVERTER that does not depend on what is done with the pixels, so
//! it is written once here for every method that plugs in at a leaf of the splitter tree
//! (docs/DESIGN.md, "Leaves resolve visibility"): `scanconv` sends the spans on as fragments or resolves them in
//! a [`RegionBuffer`]; the scan-line, area-subdivision, depth-sort and a-buffer methods
//! take the same spans, so that every method samples every pixel the same way. The
//! anti-aliasing leaves' methods are here too ([`supersample`], [`abuf`]): zbuf runs them
//! in the leaf's place at depth 0 (`zbuf --aa`), and no stage crate depends on another.
//!
//! For each polygon the [`SpanWalker`]
//!
//! 1. builds an [`EdgeTable`]: one bucket per scanline, holding the edges whose first
//!    scanline it is (Appendix 3.1),
//! 2. walks the scanlines top to bottom, moving each bucket into the [`ActiveEdgeTable`]
//!    (MOVE.ET.BUCKET.TO.AET), dropping edges past their last scanline (UPDATE.AET),
//!    sorting the crossings (the thesis's BUBBLESORT) and pairing them into spans,
//! 3. gives every covered pixel its depth on the plane, stepping by `−a/c` along the row
//!    (Appendix 3.3), an f64 in the form persp wrote ([`DepthPlane`]).
//!
//! Coverage is the rule of docs/DESIGN.md, "Coverage", taken from [`proto::raster`]: the
//! polygon's vertices (and its edges' supports) are snapped to 1/256 pixel, and pixel
//! (c, r) is covered when its centre (c+½, r+½) is inside by the even-odd rule, a centre
//! on an edge going to the polygon for which that edge is a left or top edge. On
//! scanline r the crossings of the active edges with Y = r+½ are sorted,
//! x₀ ≤ x₁ ≤ x₂ ≤ …, and the centres in [x₀, x₁), [x₂, x₃), … are covered. Pairing
//! sorted crossings is the even-odd rule itself, so concave polygons, self-intersecting
//! ones (a bowtie) and the zero-width connecting edges Sutherland–Hodgman leaves when it
//! cuts a concave polygon all come out right.
//!
//! Each crossing is carried as the first column whose centre is at or right of it,
//! ⌈x − ½⌉, computed exactly on the snapped integers: once for an edge's first row, then
//! stepped from row to row by an integer DDA (Appendix 3.3 i's x ← x + 1/m, with its
//! remainder kept, [`proto::raster::EdgeWalk`]). Two polygons that share an edge get
//! identical crossings, so no pixel is covered twice or missed along it. An edge that is a
//! piece of a longer one cut by a splitter carries that edge (its support) and is crossed
//! where the whole edge is ([`polygon_edge`]), on the rows up to where the support meets
//! the cut ([`proto::raster::vertex_rows`]), so a split polygon covers exactly the pixels
//! of the whole.

pub mod abuf;
mod depth;
mod edges;
pub mod fine;
pub mod frame;
pub mod pages;
pub mod precision;
pub mod region;
pub mod supersample;
mod walk;
pub mod watkins;
mod ztest;

pub use depth::{depth_at, takes, Depth, DepthPlane};
pub use edges::{polygon_edge, sort_crossings, ActiveEdgeTable, EdgeTable, Outline};
pub use frame::{HiddenSurface, ZBuffer};
pub use pages::{advise_huge_pages, ZeroedBuffer};
pub use region::{RegionBuffer, RegionStats, Run};
pub use walk::{check_on_screen, covered_on_row, BandWalk, Span, SpanWalker, GUARD_BAND};
pub use ztest::ZTest;
