//! # clipbatch: a batch of polygons clipped against the whole pyramid at once
//!
//! Theoharis and Page (1989, "Two Parallel Methods for Polygon
//! Clipping") give two parallel forms of Sutherland–Hodgman. The thesis's pipeline, one process
//! per plane (§3, `clipplane`), is their method A: different polygons against different
//! planes at the same time. This crate is method B (§2.2): many polygons against the
//! *same* plane at the same time, as they ran it on the 64×64 ICL DAP (§4), where each
//! processing element held one polygon (§4.1, the second way of distributing vertices:
//! "assign the vertices of one polygon to each PE", so clipping an edge needs no
//! communication between elements and a shift of a whole row of vertices is one
//! parallel operation).
//!
//! ## Layout (§4.2's DAP Fortran arrays)
//!
//! The batch's vertices are stored as four arrays, one per coordinate, the paper's
//! `VERTEXX(,,I) … VERTEXW(,,I)`: row (slot) `j` holds the j-th vertex of every polygon
//! side by side, element `(j, p)` at `j·lanes + p`; `len[p]` is the paper's `N(,)`, the
//! number of vertices of polygon p. A lane of the batch plays the part of a processing
//! element, and one plane's inside test runs over a whole row (here: over every row at
//! once) with no branch, which the compiler vectorises
//! ([`proto::geometry::Plane::classify_lanes`]).
//!
//! ## One plane (§4.2's three steps, then the insert/compact step)
//!
//! For each plane of the pyramid in the chain's order (left, right, top, bottom, hither,
//! yon; the order the thesis's pipeline and `render.sh` use):
//!
//! 1. **Inside test** (step 1, `INSIDEV1 = VERTEXY(,,I).LE.VERTEXW(,,I)`): every vertex
//!    of every polygon is classified inside, on or outside the plane, and its distance
//!    kept for the intersection.
//! 2. **Marks** (step 3's masks), row by row across the batch: for the edge that ends at
//!    vertex j (from vertex j−1, or from the last vertex for j = 0), an intersection
//!    vertex is to be inserted before vertex j when the edge's ends are strictly on
//!    opposite sides (the paper's `EXTRAVERTEX`), and vertex j is kept unless it is
//!    outside (else it is marked for deletion: the paper's `VERTEXX(MASK,I) =
//!    MAT(DELETE)`). A vertex replaced by an intersection (the paper's case 1(c)) is a
//!    deletion and an insertion.
//! 3. **Intersections** (step 2): computed only where an insertion is marked, by
//!    [`proto::geometry::Plane::intersect`], the same function as `clipplane`'s (its snap
//!    onto the plane and its eye-space repair are what make the chain's vertices what
//!    they are, bit for bit; the paper computes a rough intersection in every element and
//!    ignores the unused ones, which a vector unit would do only at the cost of
//!    that exactness).
//! 4. **Insert and compact** (the end of §4.2): "before clipping against the next
//!    clipping plane it is necessary to create space for the new vertices … and remove
//!    the vertices marked for deletion"; the DAP shifts each marked column by one place
//!    per mark, all marked columns in parallel. The net effect on a column is that each
//!    kept vertex moves by the insertions less the deletions above it, and the
//!    intersections land in the gaps: here each column with a deletion (only such a
//!    column can have an insertion) is rebuilt in one pass down its marks, and the
//!    columns without one are not touched. A plane that deletes nothing anywhere in the
//!    batch (the usual case for hither and yon) moves nothing. A column may grow (a
//!    concave polygon gains up to half its vertices again per plane, §4.1's Figure 4);
//!    then the arrays grow by whole rows.
//!
//! ## The same output as the six-process chain
//!
//! `clipbatch` writes what `clipplane left | right | top | bottom | hither | yon` writes,
//! vertex for vertex and bit for bit: the same three-way classification (a vertex on the
//! plane is inside and never gets an intersection: thesis Appendix 2, where the DAP's
//! two-way test has none), the same intersection function, and the same order. The paper
//! puts an edge's intersection with the edge's first vertex, so the closing edge's comes
//! last; `clipplane` (the thesis's section 3.1) puts it before the edge's second vertex,
//! so a polygon's output starts with the closing edge's intersection. The marks above
//! follow `clipplane`. Like `clipplane`, a polygon whose vertices a plane changes loses its
//! edge supports (and keeps its plane), and a polygon clipped away is passed on empty, so
//! polygon numbering is kept.

use proto::geometry::{clip_coloured, Plane, PyramidPlane, Side};
use proto::{Polygon, Vertex, View};

/// Polygons clipped together by default: a 32×32 DAP's processing elements (Theoharis and
/// Page's was 64×64). Measured with bench stages clip: batches of 64 to 1024 quads
/// run alike, 4096 a quarter slower (the batch's polygons and arrays, some 2 MB, no
/// longer stay in this machine's cache).
pub const DEFAULT_BATCH: usize = 1024;

/// Vertex slots a batch may hold, per polygon of its capacity. A batch's rows are as many
/// as its widest polygon has vertices, so a batch of quadrilaterals fills its capacity,
/// while a polygon of many vertices makes the batch stop early (down to that polygon
/// alone): memory stays bounded whatever the polygons.
const SLOTS_PER_POLYGON: usize = 16;

/// Four coordinate arrays, row-major by vertex slot: element `(j, p)` at `j·lanes + p`.
#[derive(Debug, Default)]
struct VertexArrays {
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    w: Vec<f64>,
}

impl VertexArrays {
    /// Makes room for `slots` elements (contents of new slots unspecified).
    fn reserve_slots(&mut self, slots: usize) {
        for c in [&mut self.x, &mut self.y, &mut self.z, &mut self.w] {
            if c.len() < slots {
                c.resize(slots, 0.0);
            }
        }
    }

    #[inline]
    fn get(&self, i: usize) -> Vertex {
        Vertex::new(self.x[i], self.y[i], self.z[i], self.w[i])
    }

    #[inline]
    fn set(&mut self, i: usize, v: Vertex) {
        self.x[i] = v.x;
        self.y[i] = v.y;
        self.z[i] = v.z;
        self.w[i] = v.w;
    }

    /// The first `slots` elements of each coordinate.
    fn lanes(&self, slots: usize) -> [&[f64]; 4] {
        [
            &self.x[..slots],
            &self.y[..slots],
            &self.z[..slots],
            &self.w[..slots],
        ]
    }
}

/// Clips a polygon with vertex colours against `planes` in turn, with
/// [`proto::geometry::clip_coloured`]; clears its supports where a plane changed it.
fn clip_shaded(planes: &[Plane; 6], poly: &mut Polygon, scratch: &mut Vec<Vertex>) {
    let mut colours = Vec::with_capacity(poly.vertex_attrs.len() + 6);
    for plane in planes {
        clip_coloured(
            &poly.vertices,
            &poly.vertex_attrs,
            plane,
            scratch,
            &mut colours,
        );
        if *scratch != poly.vertices {
            poly.supports.clear();
        }
        std::mem::swap(&mut poly.vertices, scratch);
        std::mem::swap(&mut poly.vertex_attrs, &mut colours);
    }
}

/// A batch of eye-space polygons and the arrays to clip them in (reused batch after
/// batch: clipping allocates nothing once the arrays have grown to size).
#[derive(Debug)]
pub struct ClipBatch {
    /// The pyramid's planes, in the order they are applied.
    planes: [Plane; 6],
    capacity: usize,
    slot_budget: usize,
    polygons: Vec<Polygon>,
    /// The most vertices of any polygon in the batch.
    widest: usize,
    /// Rows (vertex slots) in use.
    rows: usize,
    vertices: VertexArrays,
    /// Vertices per polygon (the paper's `N(,)`).
    len: Vec<u32>,
    /// Per slot: the distance from the current plane, and the side.
    dist: Vec<f64>,
    side: Vec<Side>,
    /// Per polygon: the side of its last vertex, where the edge into slot 0 starts.
    last_side: Vec<Side>,
    /// Per slot: an intersection is inserted before this vertex (`EXTRAVERTEX`).
    cut: Vec<u8>,
    /// Per slot: the vertex stays (it is not marked for deletion).
    keep: Vec<u8>,
    /// Per polygon: some vertex is deleted by this plane.
    deleted: Vec<u8>,
    /// Per polygon: some plane changed its vertices (its edge supports no longer apply).
    reshaped: Vec<bool>,
    /// The polygons this plane deletes a vertex of.
    changed: Vec<usize>,
    /// One polygon's clipped vertices, while its column is rebuilt.
    column: Vec<Vertex>,
    /// Polygons handed back after [`ClipBatch::clip_each`], kept for their vertex lists.
    spare: Vec<Polygon>,
}

impl ClipBatch {
    /// A batch of at most `capacity` polygons (at least 1), clipped against the pyramid of
    /// the view volume the eye-space stream was computed with.
    pub fn new(view: &View, capacity: usize) -> Self {
        let capacity = capacity.max(1);
        ClipBatch {
            planes: PyramidPlane::ALL.map(|p| p.plane(view)),
            capacity,
            slot_budget: capacity.saturating_mul(SLOTS_PER_POLYGON),
            polygons: Vec::with_capacity(capacity),
            widest: 0,
            rows: 0,
            vertices: VertexArrays::default(),
            len: Vec::new(),
            dist: Vec::new(),
            side: Vec::new(),
            last_side: Vec::new(),
            cut: Vec::new(),
            keep: Vec::new(),
            deleted: Vec::new(),
            reshaped: Vec::new(),
            changed: Vec::new(),
            column: Vec::new(),
            spare: Vec::new(),
        }
    }

    /// The number of polygons waiting in the batch.
    pub fn len(&self) -> usize {
        self.polygons.len()
    }

    pub fn is_empty(&self) -> bool {
        self.polygons.is_empty()
    }

    /// Whether `polygon` can join the batch: the batch is below its capacity and its
    /// arrays, as wide as the widest polygon, stay within the slot budget. An empty batch
    /// takes any polygon.
    pub fn fits(&self, polygon: &Polygon) -> bool {
        let n = self.polygons.len();
        n == 0
            || (n < self.capacity
                && (n + 1).saturating_mul(self.widest.max(polygon.vertices.len()))
                    <= self.slot_budget)
    }

    /// Adds a polygon to the batch (check [`ClipBatch::fits`] first, or the batch grows
    /// past its budget).
    pub fn push(&mut self, polygon: Polygon) {
        self.widest = self.widest.max(polygon.vertices.len());
        self.polygons.push(polygon);
    }

    /// Clips every polygon of the batch against the six planes and hands them back in
    /// the order they were pushed, leaving the batch empty.
    pub fn clip(&mut self) -> std::vec::Drain<'_, Polygon> {
        self.clip_in_place();
        self.polygons.drain(..)
    }

    /// [`ClipBatch::clip`], handing each clipped polygon to `each` in turn (to be
    /// written, say) and keeping it afterwards for [`ClipBatch::recycled`]: a stream
    /// clipped this way allocates nothing per polygon. Stops at the first error.
    pub fn clip_each<E>(
        &mut self,
        mut each: impl FnMut(&Polygon) -> Result<(), E>,
    ) -> Result<(), E> {
        self.clip_in_place();
        for polygon in &self.polygons {
            each(polygon)?;
        }
        self.spare.append(&mut self.polygons);
        Ok(())
    }

    /// A polygon to read the next one into: one handed back by
    /// [`ClipBatch::clip_each`], its vertex list's memory kept, or a new one.
    pub fn recycled(&mut self) -> Polygon {
        self.spare.pop().unwrap_or_default()
    }

    fn clip_in_place(&mut self) {
        if !self.polygons.is_empty() {
            self.load();
            for i in 0..self.planes.len() {
                let plane = self.planes[i];
                self.clip_against(&plane);
            }
            self.store();
        }
        self.widest = 0;
        self.rows = 0;
    }

    /// Distributes the polygons' vertices over the arrays, one polygon per lane (§4.1),
    /// rows past a polygon's last vertex padded with zeros.
    fn load(&mut self) {
        let lanes = self.polygons.len();
        self.rows = self.widest;
        let slots = self.rows * lanes;
        self.vertices.reserve_slots(slots);
        self.len.resize(lanes, 0);
        self.deleted.resize(lanes, 0);
        self.last_side.resize(lanes, Side::On);
        self.reshaped.clear();
        self.reshaped.resize(lanes, false);
        for (p, poly) in self.polygons.iter().enumerate() {
            let n = poly.vertices.len();
            self.len[p] = n as u32;
            for (j, v) in poly.vertices.iter().enumerate() {
                self.vertices.set(j * lanes + p, *v);
            }
            for j in n..self.rows {
                self.vertices.set(j * lanes + p, Vertex::ZERO);
            }
        }
    }

    /// Gives each polygon its clipped vertices back (into its own vertex list, whose
    /// allocation is reused), and clears the edge supports of those that changed.
    fn store(&mut self) {
        let lanes = self.polygons.len();
        for (p, poly) in self.polygons.iter_mut().enumerate() {
            if poly.is_shaded() {
                // A Gouraud-shaded polygon's colours are interpolated at each crossing
                // with the position's parameter: it is clipped as clipplane's chain clips
                // it (the same arithmetic, so the same vertices as its lane holds).
                clip_shaded(&self.planes, poly, &mut self.column);
                continue;
            }
            poly.vertices.clear();
            poly.vertices
                .extend((0..self.len[p] as usize).map(|j| self.vertices.get(j * lanes + p)));
            if self.reshaped[p] {
                // New vertices and edges: the splitter's edge supports (which clipping
                // before the tree never meets) no longer match; the plane still does.
                poly.supports.clear();
            }
        }
    }

    /// One plane for the whole batch: the inside test, the marks, the intersections and
    /// the insert/compact step (see the module notes).
    fn clip_against(&mut self, plane: &Plane) {
        let lanes = self.polygons.len();
        let rows = self.rows;
        let slots = rows * lanes;
        if slots == 0 {
            return;
        }
        for v in [&mut self.cut, &mut self.keep] {
            if v.len() < slots {
                v.resize(slots, 0);
            }
        }
        if self.dist.len() < slots {
            self.dist.resize(slots, 0.0);
            self.side.resize(slots, Side::On);
        }

        // 1. The inside test, every vertex of every polygon at once.
        plane.classify_lanes(
            self.vertices.lanes(slots),
            &mut self.dist[..slots],
            &mut self.side[..slots],
        );

        // 2. The marks, row by row across the batch. The edge into slot 0 is the closing
        // edge, from the polygon's last vertex (the paper repeats the first vertex after
        // the last instead).
        for p in 0..lanes {
            let n = self.len[p] as usize;
            self.last_side[p] = if n > 0 {
                self.side[(n - 1) * lanes + p]
            } else {
                Side::On
            };
        }
        self.deleted[..lanes].fill(0);
        for j in 0..rows {
            let row = j * lanes..(j + 1) * lanes;
            let prev = if j == 0 {
                &self.last_side[..lanes]
            } else {
                &self.side[row.start - lanes..row.start]
            };
            mark_row(
                j as u32,
                prev,
                &self.side[row.clone()],
                &self.len[..lanes],
                &mut self.cut[row.clone()],
                &mut self.keep[row],
                &mut self.deleted[..lanes],
            );
        }

        // 3 and 4. The columns of the polygons that lost a vertex (only they can gain
        // one) are rebuilt in order from their marks: the intersections where marked,
        // then each kept vertex moved by the insertions less the deletions above it,
        // the sum of the DAP's one-place shifts of that column. The other columns stay
        // where they are.
        self.changed.clear();
        self.changed
            .extend((0..lanes).filter(|&p| self.deleted[p] != 0));
        for k in 0..self.changed.len() {
            let p = self.changed[k];
            let n = self.len[p] as usize;
            self.column.clear();
            for j in 0..n {
                let i = j * lanes + p;
                let v = self.vertices.get(i);
                if self.cut[i] != 0 {
                    let s = if j == 0 { n - 1 } else { j - 1 } * lanes + p;
                    self.column.push(plane.intersect(
                        self.vertices.get(s),
                        self.dist[s],
                        v,
                        self.dist[i],
                    ));
                }
                if self.keep[i] != 0 {
                    self.column.push(v);
                }
            }
            // clipplane clears a polygon's supports when its output differs (==) from
            // its input.
            if !self.reshaped[p] {
                self.reshaped[p] = self.column.len() != n
                    || (0..n).any(|j| self.column[j] != self.vertices.get(j * lanes + p));
            }
            let m = self.column.len();
            if m > self.rows {
                // A concave polygon may gain vertices: the arrays grow by whole rows.
                self.rows = m;
                self.vertices.reserve_slots(m * lanes);
            }
            for (j, v) in self.column.iter().enumerate() {
                self.vertices.set(j * lanes + p, *v);
            }
            self.len[p] = m as u32;
        }
        if !self.changed.is_empty() {
            self.rows = self.len[..lanes].iter().copied().max().unwrap_or(0) as usize;
        }
    }
}

/// Marks row `j` of every polygon at once, from the sides of the vertices before (`prev`)
/// and at (`this`) the slot: whether an intersection is inserted before the vertex
/// (`cut`, the paper's `EXTRAVERTEX`), whether the vertex stays (`keep`; else it is marked
/// for deletion), and, per polygon, whether any vertex is deleted. Slots past a polygon's
/// last vertex mark nothing. No branch: vectorised.
#[inline]
fn mark_row(
    j: u32,
    prev: &[Side],
    this: &[Side],
    len: &[u32],
    cut: &mut [u8],
    keep: &mut [u8],
    deleted: &mut [u8],
) {
    let n = len.len();
    let (prev, this, cut, keep, deleted) = (
        &prev[..n],
        &this[..n],
        &mut cut[..n],
        &mut keep[..n],
        &mut deleted[..n],
    );
    for p in 0..n {
        let valid = j < len[p];
        let (s, v) = (prev[p], this[p]);
        let outside = v == Side::Outside;
        // Strictly opposite sides: a vertex on the plane never gets an intersection.
        let crosses = (s == Side::Inside) & outside | (s == Side::Outside) & (v == Side::Inside);
        cut[p] = (valid & crosses) as u8;
        keep[p] = (valid & !outside) as u8;
        deleted[p] |= (valid & outside) as u8;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use proto::DVec4;

    /// Eye point at z_e = 16 (w = 10 with the default s/d).
    fn e(x: f64, y: f64) -> Vertex {
        DVec4::new(x, y, 16.0, 10.0)
    }

    fn clip_all(batch: &mut ClipBatch, polys: Vec<Polygon>) -> Vec<Polygon> {
        for p in polys {
            assert!(batch.fits(&p));
            batch.push(p);
        }
        batch.clip().collect()
    }

    #[test]
    fn clip_each_hands_on_what_clip_gives_and_keeps_the_polygons() {
        let view = View::default();
        let polys = vec![
            Polygon::new([1, 2, 3], vec![e(-1.0, -1.0), e(1.0, -1.0), e(0.0, 1.0)]),
            // Across the left plane (x = -w at w = 10): cut there.
            Polygon::new([4, 5, 6], vec![e(-30.0, 0.0), e(0.0, 0.0), e(0.0, 5.0)]),
            // Wholly outside: no vertices left.
            Polygon::new([7, 8, 9], vec![e(50.0, 0.0), e(60.0, 0.0), e(55.0, 5.0)]),
        ];
        let want = clip_all(&mut ClipBatch::new(&view, 8), polys.clone());
        let mut batch = ClipBatch::new(&view, 8);
        for p in polys {
            batch.push(p);
        }
        let mut got = vec![];
        batch
            .clip_each(|p| {
                got.push(p.clone());
                Ok::<_, ()>(())
            })
            .unwrap();
        assert_eq!(got, want);
        assert!(batch.is_empty());
        // The three come back for reuse, their vertex lists' memory kept.
        let mut recycled: Vec<Polygon> = (0..3).map(|_| batch.recycled()).collect();
        assert!(recycled.iter().all(|p| p.vertices.capacity() >= 3));
        recycled.push(batch.recycled());
        assert_eq!(recycled[3].vertices.capacity(), 0, "then new ones");
        // An error stops the hand-on at the polygon that gave it.
        batch.push(want[0].clone());
        batch.push(want[1].clone());
        let mut seen = 0;
        assert_eq!(
            batch.clip_each(|_| {
                seen += 1;
                Err("full")
            }),
            Err("full")
        );
        assert_eq!(seen, 1);
    }

    /// Sutherland–Hodgman against the six planes one polygon at a time, as the chain of
    /// clipplane processes does it (bins/clipplane: its `clip_against` and its main
    /// loop's supports rule), written out here as the reference.
    fn chain(view: &View, mut poly: Polygon) -> Polygon {
        for which in PyramidPlane::ALL {
            let plane = which.plane(view);
            let mut out = Vec::new();
            if let Some(&last) = poly.vertices.last() {
                let (mut s, (mut ss, mut sd)) = (last, plane.classify(last));
                for &p in &poly.vertices {
                    let (ps, pd) = plane.classify(p);
                    if matches!(
                        (ss, ps),
                        (Side::Inside, Side::Outside) | (Side::Outside, Side::Inside)
                    ) {
                        out.push(plane.intersect(s, sd, p, pd));
                    }
                    if ps != Side::Outside {
                        out.push(p);
                    }
                    (s, ss, sd) = (p, ps, pd);
                }
            }
            if out != poly.vertices {
                poly.supports.clear();
            }
            poly.vertices = out;
        }
        poly
    }

    /// A polygon's numbers as bits: vertices, plane, supports.
    type Bits = (Vec<[u64; 4]>, Option<[u64; 4]>, Vec<Option<[[u64; 4]; 2]>>);

    /// The bits of a polygon's numbers (so that −0 and 0 differ).
    fn bits(p: &Polygon) -> Bits {
        let b = |v: DVec4| v.to_array().map(f64::to_bits);
        (
            p.vertices.iter().map(|v| b(*v)).collect(),
            p.plane.map(b),
            p.supports
                .iter()
                .map(|s| s.map(|[a, c]| [b(a), b(c)]))
                .collect(),
        )
    }

    /// Any finite coordinate, or one on a 1/8 grid (so that vertices on planes and
    /// coincidences come up often), as fuzz/src/lib.rs makes them.
    fn coordinate() -> impl Strategy<Value = f64> {
        prop_oneof![
            2 => (-128i32..128).prop_map(|i| i as f64 / 8.0),
            1 => any::<f64>().prop_filter("finite", |v| v.is_finite()),
            1 => -60.0..60.0f64,
        ]
    }

    fn any_polygon() -> impl Strategy<Value = Polygon> {
        let vertex = || {
            (
                coordinate(),
                coordinate(),
                coordinate(),
                prop::option::of(coordinate()),
            )
                .prop_map(|(x, y, z, w)| DVec4::new(x, y, z, w.unwrap_or(z * 0.625)))
        };
        (prop::collection::vec(vertex(), 0..12), any::<bool>()).prop_flat_map(move |(v, s)| {
            let n = v.len();
            let supports = if s {
                prop::collection::vec(prop::option::of((vertex(), vertex())), n..=n).boxed()
            } else {
                Just(Vec::new()).boxed()
            };
            (Just(v), supports).prop_map(|(vertices, supports)| Polygon {
                colour: [1, 2, 3],
                vertices,
                plane: None,
                supports: supports
                    .into_iter()
                    .map(|s| s.map(|(a, b)| [a, b]))
                    .collect(),
                ..Polygon::default()
            })
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        /// In process, many more cases than the binaries' property in
        /// tests/tests/composer/clipbatch_render.rs: every polygon of a batch comes out bit for bit as the
        /// one-polygon-at-a-time chain makes it, whatever the batch size and view volume.
        #[test]
        fn a_batch_is_the_chain_bit_for_bit(
            polys in prop::collection::vec(any_polygon(), 0..20),
            capacity in 1usize..8,
            which_view in 0usize..3,
        ) {
            let view = [
                View::default(),
                View { aspect: 16.0 / 9.0, hither: 0.5, yon: 100.0 },
                View { aspect: 0.75, hither: 1e-3, yon: 1e6 },
            ][which_view];
            let mut batch = ClipBatch::new(&view, capacity);
            let mut got = Vec::new();
            for p in polys.clone() {
                if !batch.fits(&p) {
                    got.extend(batch.clip());
                }
                batch.push(p);
            }
            got.extend(batch.clip());
            prop_assert_eq!(got.len(), polys.len());
            for (g, p) in got.iter().zip(polys) {
                let want = chain(&view, p.clone());
                prop_assert_eq!(bits(g), bits(&want), "from {:?}", p);
            }
        }
    }

    #[test]
    fn the_four_cases_against_left_in_clipplane_order() {
        let view = View::default(); // x_e ≥ −w = −10 at z_e = 16
        let mut batch = ClipBatch::new(&view, 8);
        // In, out, in: the closing edge (2, 8) → (2, 0) is inside, so the output starts at
        // vertex 0; the edge in → out gets (−10, 4), the edge out → in (−10, 8).
        let tri = Polygon::new([1, 2, 3], vec![e(2.0, 0.0), e(-22.0, 8.0), e(2.0, 8.0)]);
        // Out first: the closing edge (2, 8) → (−22, 0), in → out, is cut first, so the
        // output starts with its intersection, as clipplane's does (the paper would put
        // it last).
        let out_first = Polygon::new([4, 5, 6], vec![e(-22.0, 0.0), e(2.0, 0.0), e(2.0, 8.0)]);
        let wholly_out = Polygon::new([7, 8, 9], vec![e(-22.0, 0.0), e(-30.0, 1.0), e(-25.0, 5.0)]);
        let empty = Polygon::new([0, 0, 0], vec![]);
        let got = clip_all(&mut batch, vec![tri, out_first, wholly_out, empty]);
        assert_eq!(
            got[0].vertices,
            vec![e(2.0, 0.0), e(-10.0, 4.0), e(-10.0, 8.0), e(2.0, 8.0)]
        );
        assert_eq!(
            got[1].vertices,
            vec![e(-10.0, 4.0), e(-10.0, 0.0), e(2.0, 0.0), e(2.0, 8.0)]
        );
        assert_eq!(got[2], Polygon::new([7, 8, 9], vec![]));
        assert_eq!(got[3], Polygon::new([0, 0, 0], vec![]));
        assert!(batch.is_empty());
    }

    #[test]
    fn vertices_on_a_plane_are_kept_and_never_doubled() {
        let view = View::default();
        let mut batch = ClipBatch::new(&view, 4);
        // (−10, ±5) lie on the left plane: no intersection is made next to them.
        let poly = Polygon::new(
            [1, 1, 1],
            vec![e(2.0, 0.0), e(-10.0, 5.0), e(-22.0, 0.0), e(-10.0, -5.0)],
        );
        let got = clip_all(&mut batch, vec![poly]);
        assert_eq!(
            got[0].vertices,
            vec![e(2.0, 0.0), e(-10.0, 5.0), e(-10.0, -5.0)]
        );
    }

    #[test]
    fn supports_are_cleared_only_where_a_plane_changed_the_polygon() {
        let view = View::default();
        let support = Some([e(-20.0, 0.0), e(20.0, 0.0)]);
        let inside = Polygon {
            colour: [1, 2, 3],
            vertices: vec![e(1.0, 1.0), e(2.0, 1.0), e(2.0, 2.0)],
            plane: Some(DVec4::new(0.0, 0.0, 1.0, -16.0)),
            supports: vec![support, None, None],
            ..Polygon::default()
        };
        let cut = Polygon {
            vertices: vec![e(1.0, 1.0), e(12.0, 1.0), e(2.0, 2.0)],
            ..inside.clone()
        };
        let mut batch = ClipBatch::new(&view, 4);
        let got = clip_all(&mut batch, vec![inside.clone(), cut.clone()]);
        assert_eq!(got[0], inside);
        assert_eq!(got[1].supports, vec![]);
        assert_eq!(got[1].plane, inside.plane);
        assert_eq!(got[1], chain(&view, cut));
    }

    #[test]
    fn a_batch_stops_at_its_capacity_and_its_slot_budget() {
        let view = View::default();
        let quad = Polygon::new([1, 1, 1], vec![e(0.0, 0.0); 4]);
        let mut batch = ClipBatch::new(&view, 2);
        assert!(batch.fits(&quad));
        batch.push(quad.clone());
        assert!(batch.fits(&quad));
        batch.push(quad.clone());
        assert!(!batch.fits(&quad));
        assert_eq!(batch.clip().count(), 2);
        // 2 polygons × 16 slots: a polygon of 17 vertices goes alone.
        let wide = Polygon::new([1, 1, 1], vec![e(0.0, 0.0); 17]);
        assert!(batch.fits(&wide));
        batch.push(wide.clone());
        assert!(!batch.fits(&quad));
        assert_eq!(batch.clip().collect::<Vec<_>>(), vec![wide]);
    }

    /// Growth past the batch's rows: a zig-zag that left cuts into many pieces gains
    /// vertices (one plane can add half as many again), so the arrays grow a row.
    #[test]
    fn a_polygon_may_gain_vertices() {
        let view = View::default();
        let mut zigzag = Vec::new();
        for i in 0..5 {
            let y = i as f64;
            zigzag.push(e(0.0, y));
            zigzag.push(e(-20.0, y + 0.5));
        }
        zigzag.push(e(0.0, 5.0));
        zigzag.push(e(5.0, 2.0));
        let poly = Polygon::new([9, 9, 9], zigzag);
        let want = chain(&view, poly.clone());
        assert!(want.vertices.len() > poly.vertices.len());
        let mut batch = ClipBatch::new(&view, 4);
        let small = Polygon::new([1, 1, 1], vec![e(1.0, 1.0), e(2.0, 1.0), e(2.0, 2.0)]);
        let got = clip_all(&mut batch, vec![small.clone(), poly]);
        assert_eq!(got, vec![small, want]);
    }
}
