//! # splitter: the splitter node of thesis chapter 6.2
//!
//! A splitter node reads one eye-space polygon stream and writes two: the part of every
//! polygon on one side of its splitting plane goes to `out1`, the part on the other side
//! to `out2`. Planes through the eye, x_e = K·a·w and y_e = K·w, are the screen's column
//! and row boundaries x_s = K and y_s = K, so a binary tree of splitter nodes whose levels
//! alternate between them deals the screen out to its leaves in rectangles (chapter 6.3).
//!
//! Each output is the CSP specification of section 6.2.2 applied to the polygon's closed
//! vertex sequence. With `side1` the plane's inside, `side2` its outside and `onplane`
//! neither, the edge (s, p) contributes to out1
//!
//! | case | s      | p      | out1             | out2             |
//! |------|--------|--------|------------------|------------------|
//! | 1    | side1  | side1  | p                | –                |
//! | 2    | side2  | side2  | –                | p                |
//! | 3    | side1  | side2  | I                | I, p             |
//! | 4    | side2  | side1  | I, p             | I                |
//! | 5    | any    | on     | p                | p                |
//! | 6    | on     | side1 / side2 | p (side1) | p (side2)       |
//!
//! where I is the edge's intersection with the plane, computed once and sent to both
//! outputs so that the two pieces share the new edge exactly and render as the whole
//! polygon did (docs/DESIGN.md, "Coverage"). A vertex on the plane goes to both outputs.
//!
//! Unlike the occam X.SPLITTER, whose output began at the second vertex and ended with
//! the first, the edges are walked from (v_{n−1}, v_0) on, so a polygon wholly on one side
//! comes out with its vertices unchanged and in the same order.
//!
//! ## The lean stream
//!
//! The occam splitter sends every polygon down both branches, empty where it lies on the
//! other side, so that polygon k is polygon k at every leaf. A node here sends an output
//! a piece only if it can cover a pixel (three vertices or more); the polygons an output
//! gets nothing of in a row become one `skip N` record ([`Lean`]), written just before
//! that output's next record, so numbering is kept in a few bytes. That covers a polygon
//! wholly on the other side, the lone vertex or edge that touches the plane from there,
//! and a polygon that arrives with fewer than three vertices (clipped away upstream):
//! the scan converter would draw nothing of any of them. A skip that arrives is added to
//! both outputs' counts.

use proto::geometry::{Plane, Side};
use proto::{DVec3, Polygon, Token, Vertex, View, Writer};
use std::fmt;
use std::io::{self, Write};
use std::str::FromStr;

/// The plane a node splits about, as the command line gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SplitPlane {
    /// `x=K`: the column boundary x_s = K, the plane x_e = K·a·w. Out1 gets x_e ≤ K·a·w.
    Column(f64),
    /// `y=K`: the row boundary y_s = K, the plane y_e = K·w. Out1 gets y_e ≤ K·w.
    Row(f64),
    /// `a,b,c,d,k`: the plane a·x_e + b·y_e + c·z_e + d·w + k = 0. Out1 gets the side
    /// where it is ≥ 0.
    General(Plane),
}

impl SplitPlane {
    /// The half-space whose inside goes to out1, for a stream viewed through `view`
    /// (whose aspect ratio a places the column planes).
    pub fn plane(&self, view: &View) -> Plane {
        match *self {
            SplitPlane::Column(k) => Plane::column(k, view.aspect),
            SplitPlane::Row(k) => Plane::row(k),
            SplitPlane::General(p) => p,
        }
    }

    /// Parses the general form `a,b,c,d,k`.
    pub fn parse_general(s: &str) -> Result<SplitPlane, String> {
        Plane::parse(s).map(SplitPlane::General)
    }
}

impl FromStr for SplitPlane {
    type Err = String;

    /// Parses `x=K` or `y=K` with K in [−1, 1] (the screen runs from −1 to 1).
    fn from_str(s: &str) -> Result<Self, String> {
        let (axis, value) = s
            .split_once('=')
            .ok_or_else(|| format!("expected x=K or y=K, found `{s}`"))?;
        let k: f64 = value
            .trim()
            .parse()
            .map_err(|_| format!("`{value}` in `{s}` is not a number"))?;
        if !(-1.0..=1.0).contains(&k) {
            return Err(format!(
                "K = {value} in `{s}` is off the screen (K must be in [-1, 1])"
            ));
        }
        match axis.trim() {
            "x" | "X" => Ok(SplitPlane::Column(k)),
            "y" | "Y" => Ok(SplitPlane::Row(k)),
            other => Err(format!(
                "unknown axis `{other}` in `{s}` (expected x=K or y=K)"
            )),
        }
    }
}

impl fmt::Display for SplitPlane {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SplitPlane::Column(k) => write!(f, "x={k}"),
            SplitPlane::Row(k) => write!(f, "y={k}"),
            SplitPlane::General(p) => {
                write!(f, "{},{},{},{},{}", p.n.x, p.n.y, p.n.z, p.n.w, p.k)
            }
        }
    }
}

/// A rectangle of whole pixels of the screen: columns `x0..x1` and rows `y0..y1`
/// (half-open; row 0 at the top, as in device coordinates).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Region {
    pub x0: u32,
    pub x1: u32,
    pub y0: u32,
    pub y1: u32,
}

/// The splitter tree of thesis chapter 6.3 over a `width`×`height` screen: its nodes are
/// numbered as a heap (node 1 the root; the children of node i are 2i, which gets OUT1,
/// and 2i + 1, which gets OUT2), its levels alternate column and row planes, starting
/// with a column, and every node bisects its own region of the screen.
///
/// The cut is on a pixel BOUNDARY: column c = ⌊(x0 + x1)/2⌋ is the plane x_s = 2c/W − 1,
/// row r = ⌊(y0 + y1)/2⌋ the plane y_s = 1 − 2r/H. Pixel centres are at half-integers,
/// so a cut never passes through one, and the new edges along it decide no centre the
/// whole polygon would not have: with the edge supports and the recorded plane that
/// [`split`] adds, a tree of any depth renders byte for byte as depth 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tree {
    pub width: u32,
    pub height: u32,
}

impl Tree {
    /// The region of the screen that node `node` (≥ 1) receives: the root has the whole
    /// screen; each node's OUT1 child gets the columns left of its cut (for a column
    /// plane, x_s ≤ K) or the rows below it (for a row plane, y_s ≤ K), OUT2 the rest.
    pub fn region(&self, node: u32) -> Region {
        let mut r = Region {
            x0: 0,
            x1: self.width,
            y0: 0,
            y1: self.height,
        };
        let level = Self::level(node);
        // The path from the root: bit (level − 1 − l) of `node` says which child was taken
        // at level l (0: OUT1, 1: OUT2).
        for l in 0..level {
            let out2 = (node >> (level - 1 - l)) & 1 == 1;
            if l % 2 == 0 {
                let c = midpoint(r.x0, r.x1);
                if out2 {
                    r.x0 = c
                } else {
                    r.x1 = c
                }
            } else {
                let row = midpoint(r.y0, r.y1);
                if out2 {
                    r.y1 = row
                } else {
                    r.y0 = row
                }
            }
        }
        r
    }

    /// The plane node `node` (≥ 1) splits its region about: `x=K` on even levels, `y=K`
    /// on odd ones, K computed as `sign·(2n/d − 1)` in doubles and a zero made +0 (the
    /// same operations, in the same order, as the awk of the scripts that used to compute
    /// it, so the planes are those of earlier trees to the bit).
    pub fn plane(&self, node: u32) -> SplitPlane {
        let r = self.region(node);
        // k(n, d, sign) = sign·(2n/d − 1): boundary n of d pixels in screen coordinates.
        let k = |n: u32, d: u32, sign: f64| {
            let k = sign * (2.0 * f64::from(n) / f64::from(d) - 1.0);
            if k == 0.0 {
                0.0
            } else {
                k
            }
        };
        if Self::level(node) & 1 == 0 {
            SplitPlane::Column(k(midpoint(r.x0, r.x1), self.width, 1.0))
        } else {
            // y_s = 1 − 2r/H: rows run down the screen, y_s up.
            SplitPlane::Row(k(midpoint(r.y0, r.y1), self.height, -1.0))
        }
    }

    /// The node's level: 0 for the root, ⌊log₂ node⌋.
    fn level(node: u32) -> u32 {
        assert!(node >= 1, "splitter tree nodes are numbered from 1");
        u32::BITS - 1 - node.leading_zeros()
    }

    /// Checks that `node` is an inner node (one that splits) of a tree of `depth`
    /// levels: 1 ≤ node < 2^depth.
    pub fn check_node(node: u32, depth: u32) -> Result<(), String> {
        if !(1..=MAX_TREE_DEPTH).contains(&depth) {
            return Err(format!(
                "--depth {depth}: a tree with splitter nodes has 1 to {MAX_TREE_DEPTH} levels"
            ));
        }
        let nodes = (1u32 << depth) - 1;
        if !(1..=nodes).contains(&node) {
            let range = if nodes == 1 {
                "only node 1".to_string()
            } else {
                format!("nodes 1 to {nodes}")
            };
            return Err(format!(
                "--node {node} is not a splitter node of a depth-{depth} tree ({range})"
            ));
        }
        Ok(())
    }
}

/// The deepest tree `--node`/`--depth` accept (node numbers fit a u32).
pub const MAX_TREE_DEPTH: u32 = 31;

/// ⌊(a + b)/2⌋ without overflow.
fn midpoint(a: u32, b: u32) -> u32 {
    ((u64::from(a) + u64::from(b)) / 2) as u32
}

/// Splits `poly` about `plane` (chapter 6.2's f¹ and f²): `out1` receives the part on the
/// plane's inside, `out2` the part outside; both receive the polygon's colour, and a part
/// that is empty comes out as a polygon without vertices, so that polygon k stays
/// polygon k on both branches. The outputs' vertex buffers are reused.
///
/// So that the pieces render bit for bit as the whole would have, a polygon that
/// is really cut (three vertices or more on each side) is given its plane,
/// [`Polygon::eye_plane`], unless an earlier node already gave it one; and every piece of
/// an edge that is cut gets the edge's *support*: the ends of the original edge (of the
/// edge's own support, if it is itself a piece), from which the scan converter computes
/// its crossings. The new edges along the plane need none: the two pieces share them
/// exactly, and their ends are their own.
pub fn split(poly: &Polygon, plane: &Plane, out1: &mut Polygon, out2: &mut Polygon) {
    for out in [&mut *out1, &mut *out2] {
        out.colour = poly.colour;
        out.opacity = poly.opacity;
        out.vertices.clear();
        out.supports.clear();
        out.vertex_attrs.clear();
        out.plane = poly.plane;
        out.shade.clone_from(&poly.shade);
    }
    if poly.vertices.is_empty() {
        return;
    }
    // A flat polygon walks without colours: the walk is compiled twice.
    if poly.is_shaded() && poly.vertex_attrs.len() == poly.vertices.len() {
        walk::<true>(poly, plane, out1, out2);
    } else {
        walk::<false>(poly, plane, out1, out2);
    }
    for out in [&mut *out1, &mut *out2] {
        if out.supports.iter().any(Option::is_some) {
            out.supports.rotate_left(1);
        } else {
            out.supports.clear();
        }
    }
    if out1.vertices.len() >= 3 && out2.vertices.len() >= 3 {
        if poly.plane.is_none() {
            let whole = poly.eye_plane();
            out1.plane = whole;
            out2.plane = whole;
        }
        if poly.shade.is_none() && poly.is_shaded() {
            // The whole polygon's colour planes, as its depth plane (viewxf records them
            // first, unless a vertex was behind the eye).
            let whole = proto::shade::eye_colour_planes(&poly.vertices, &poly.vertex_attrs);
            out1.shade = whole.map(Box::new);
            out2.shade = whole.map(Box::new);
        }
    }
}

/// Node K of a splitter tree and the nodes below it, `levels` levels deep, split in one
/// process (`splitter --node K --levels L`): what that many levels of nodes, each a
/// process, would send their leaves, byte for byte, without encoding the streams between
/// them, decoding them again or starting a process per node.
///
/// Each level splits the pieces of the level above with [`split`], as a node of its own
/// would; a piece of fewer than [`Lean::MIN_VERTICES`] vertices is emptied before it goes
/// on, as the lean stream between two processes would have skipped it, so that the level
/// below sees what a node process would have read.
#[derive(Debug, Default)]
pub struct Subtree {
    /// The nodes' planes, level by level: level j's 2^j nodes, left to right.
    planes: Vec<Vec<Plane>>,
    /// The pieces of each level, reused from polygon to polygon: level j's nodes' outputs,
    /// 2^(j+1) of them, node i's two at 2i and 2i + 1.
    pieces: Vec<Vec<Polygon>>,
    /// Each node's counts, level by level as `planes`.
    pub stats: Vec<Vec<Stats>>,
    /// Whether the last split sent pieces both ways at some node ([`Subtree::cut`]).
    cut: bool,
}

impl Subtree {
    /// The subtree whose nodes split about `planes`, level by level (level j has 2^j).
    ///
    /// # Panics
    ///
    /// When a level does not have twice the nodes of the one above.
    pub fn new(planes: Vec<Vec<Plane>>) -> Self {
        for (j, level) in planes.iter().enumerate() {
            assert_eq!(
                level.len(),
                1 << j,
                "level {j} of a subtree has 2^{j} nodes"
            );
        }
        Subtree {
            pieces: (0..planes.len())
                .map(|j| vec![Polygon::default(); 2 << j])
                .collect(),
            stats: planes
                .iter()
                .map(|l| vec![Stats::default(); l.len()])
                .collect(),
            planes,
            cut: false,
        }
    }

    /// The number of levels.
    pub fn levels(&self) -> usize {
        self.planes.len()
    }

    /// Splits `poly` down every level; the last level's pieces are the outputs, 2^levels
    /// of them, left to right ([`Subtree::outputs`]).
    pub fn split(&mut self, poly: &Polygon) {
        self.cut = false;
        for j in 0..self.planes.len() {
            let (above, below) = self.pieces.split_at_mut(j);
            let out = &mut below[0];
            for (i, plane) in self.planes[j].iter().enumerate() {
                let input = match above.last() {
                    Some(level) => &level[i],
                    None => poly,
                };
                let [out1, out2] = &mut out[2 * i..2 * i + 2] else {
                    unreachable!("level j has two pieces a node")
                };
                split(input, plane, out1, out2);
                self.cut |= !out1.vertices.is_empty() && !out2.vertices.is_empty();
                self.stats[j][i].record(out1, out2);
            }
            if j + 1 < self.planes.len() {
                for piece in out.iter_mut() {
                    if piece.vertices.len() < Lean::MIN_VERTICES {
                        piece.vertices.clear();
                    }
                }
            }
        }
    }

    /// Whether the last [`Subtree::split`] sent pieces both ways at some node. Only then
    /// can a piece hold a number the polygon did not (a crossing, the plane worked out
    /// for a cut polygon), which may overflow: a node that sends everything one way
    /// passes the polygon's own vertices, edge supports and planes on, and a stream's
    /// polygons come in finite (the reader refuses any other). So the checks of a
    /// piece's numbers ([`Subtree::pieces`]) are needed only then: on the fill-heavy
    /// scene at depth 2 they were a tenth of the splitter's time.
    pub fn cut(&self) -> bool {
        self.cut
    }

    /// Every piece the last [`Subtree::split`] made, level by level (for checks on them).
    pub fn pieces(&self) -> impl Iterator<Item = &Polygon> {
        self.pieces.iter().flatten()
    }

    /// The last level's pieces: the subtree's outputs, left to right.
    pub fn outputs(&mut self) -> &mut [Polygon] {
        self.pieces.last_mut().map_or(&mut [], |l| l.as_mut_slice())
    }

    /// Counts `n` polygons that arrived as a `skip n` at every node.
    pub fn skipped(&mut self, n: u32) {
        for s in self.stats.iter_mut().flatten() {
            s.skipped(n);
        }
    }
}

/// The split's walk round the polygon's edges; `SHADED`: with its vertex colours.
#[inline]
fn walk<const SHADED: bool>(poly: &Polygon, plane: &Plane, out1: &mut Polygon, out2: &mut Polygon) {
    let n = poly.vertices.len();
    // While walking, `supports` holds for each vertex pushed the support of the edge
    // that arrives at it; rotated by one at the end, it is per outgoing edge.
    let mut pieces = Pieces::<SHADED> {
        out1: &mut out1.vertices,
        in1: &mut out1.supports,
        colours1: &mut out1.vertex_attrs,
        out2: &mut out2.vertices,
        in2: &mut out2.supports,
        colours2: &mut out2.vertex_attrs,
    };
    let colour = |i: usize| {
        if SHADED {
            poly.vertex_attrs[i]
        } else {
            proto::DVec3::ZERO
        }
    };
    // s is the start of the current edge; the first edge is (v_{n−1}, v_0).
    let mut s_index = n - 1;
    let mut s = poly.vertices[s_index];
    let (mut s_side, mut ds) = plane.classify(s);
    for (p_index, &p) in poly.vertices.iter().enumerate() {
        let (p_side, dp) = plane.classify(p);
        pieces.emit_edge(
            plane,
            (s, s_side, ds, colour(s_index)),
            (p, p_side, dp, colour(p_index)),
            poly.support(s_index),
        );
        (s, s_side, ds, s_index) = (p, p_side, dp, p_index);
    }
}

/// The two pieces being built: their vertices and, per vertex, the support of the edge
/// arriving at it.
struct Pieces<'a, const SHADED: bool> {
    out1: &'a mut Vec<Vertex>,
    in1: &'a mut Vec<Option<[Vertex; 2]>>,
    colours1: &'a mut Vec<DVec3>,
    out2: &'a mut Vec<Vertex>,
    in2: &'a mut Vec<Option<[Vertex; 2]>>,
    colours2: &'a mut Vec<DVec3>,
}

impl<const SHADED: bool> Pieces<'_, SHADED> {
    #[inline]
    fn push1(&mut self, v: Vertex, c: DVec3, support: Option<[Vertex; 2]>) {
        self.out1.push(v);
        self.in1.push(support);
        if SHADED {
            self.colours1.push(c);
        }
    }

    #[inline]
    fn push2(&mut self, v: Vertex, c: DVec3, support: Option<[Vertex; 2]>) {
        self.out2.push(v);
        self.in2.push(support);
        if SHADED {
            self.colours2.push(c);
        }
    }

    /// The contribution of the edge (s, p), whose own support is `kept`, to both outputs:
    /// the cases of the module table. An edge that reaches a piece whole keeps `kept`; a
    /// piece of a cut edge gets `kept` or, for an original edge, (s, p); an edge along
    /// the plane gets none.
    #[inline]
    fn emit_edge(
        &mut self,
        plane: &Plane,
        (s, s_side, ds, sc): (Vertex, Side, f64, DVec3),
        (p, p_side, dp, pc): (Vertex, Side, f64, DVec3),
        kept: Option<[Vertex; 2]>,
    ) {
        let cut = || Some(kept.unwrap_or([s, p]));
        // The crossing, and its colour interpolated with the position's parameter.
        let crossing = || {
            let x = plane.crossing(s, ds, p, dp);
            let c = if SHADED { x.mix(sc, pc) } else { DVec3::ZERO };
            (x.point, c)
        };
        match (s_side, p_side) {
            // Case 5: p on the plane belongs to both pieces. The edge reaches a piece whole
            // if s is in it; otherwise the piece arrives at p along the plane.
            (_, Side::On) => {
                self.push1(p, pc, if s_side != Side::Outside { kept } else { None });
                self.push2(p, pc, if s_side != Side::Inside { kept } else { None });
            }
            // Cases 1 and 6: p inside, and the edge does not come from the outside.
            (Side::Inside | Side::On, Side::Inside) => self.push1(p, pc, kept),
            // Cases 2 and 6: p outside, and the edge does not come from the inside.
            (Side::Outside | Side::On, Side::Outside) => self.push2(p, pc, kept),
            // Case 3: leaving the inside. The crossing point closes out1's piece and opens
            // out2's, which continues with p.
            (Side::Inside, Side::Outside) => {
                let (i, ic) = crossing();
                self.push1(i, ic, cut());
                self.push2(i, ic, None);
                self.push2(p, pc, cut());
            }
            // Case 4: entering the inside.
            (Side::Outside, Side::Inside) => {
                let (i, ic) = crossing();
                self.push1(i, ic, None);
                self.push1(p, pc, cut());
                self.push2(i, ic, cut());
            }
        }
    }
}

/// One output of a node in the lean stream: the number of polygons in a row it has got
/// nothing of, not yet written as a `skip N`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Lean {
    pending: u32,
}

/// Where a node's output goes: [`Lean`] writes through this, so that the same lean stream
/// serves a plain stream writer and the binary's outputs (which close alone when their
/// reader goes away).
pub trait TokenOut {
    type Error;
    /// Writes a record.
    fn write_token(&mut self, token: &Token) -> Result<(), Self::Error>;
    /// Writes a polygon record (without making a [`Token`] of it).
    fn write_polygon(&mut self, polygon: &Polygon) -> Result<(), Self::Error>;
}

impl<W: Write> TokenOut for Writer<Token, W> {
    type Error = io::Error;
    fn write_token(&mut self, token: &Token) -> io::Result<()> {
        self.write(token)
    }
    fn write_polygon(&mut self, polygon: &Polygon) -> io::Result<()> {
        Writer::write_polygon(self, polygon)
    }
}

impl TokenOut for stagecli::Branch<Token> {
    type Error = stagecli::Error;
    fn write_token(&mut self, token: &Token) -> stagecli::Result<()> {
        self.write(token)
    }
    fn write_polygon(&mut self, polygon: &Polygon) -> stagecli::Result<()> {
        stagecli::Branch::write_polygon(self, polygon)
    }
}

impl Lean {
    /// The fewest vertices of a piece that can cover a pixel.
    pub const MIN_VERTICES: usize = 3;

    /// Sends `piece` (this output's part of the next polygon), or counts it as skipped if
    /// it can cover no pixel.
    #[inline]
    pub fn polygon<O: TokenOut>(&mut self, out: &mut O, piece: &Polygon) -> Result<(), O::Error> {
        if piece.vertices.len() < Self::MIN_VERTICES {
            return self.skip(out, 1);
        }
        self.flush(out)?;
        out.write_polygon(piece)
    }

    /// Counts `n` more polygons this output gets nothing of (a `skip N` that arrived).
    #[inline]
    pub fn skip<O: TokenOut>(&mut self, out: &mut O, n: u32) -> Result<(), O::Error> {
        self.pending = match self.pending.checked_add(n) {
            Some(sum) => sum,
            None => {
                self.flush(out)?;
                n
            }
        };
        Ok(())
    }

    /// Writes a record other than a polygon (NEXT.FRAME, END), the pending skip first.
    #[inline]
    pub fn control<O: TokenOut>(&mut self, out: &mut O, token: &Token) -> Result<(), O::Error> {
        self.flush(out)?;
        out.write_token(token)
    }

    /// Writes the pending `skip N`, if any.
    #[inline]
    pub fn flush<O: TokenOut>(&mut self, out: &mut O) -> Result<(), O::Error> {
        if self.pending > 0 {
            out.write_token(&Token::Skip(self.pending))?;
            self.pending = 0;
        }
        Ok(())
    }
}

/// What a node did, for `--stats`: polygons in, and the pieces (of three vertices or
/// more, the ones sent) and their vertices out.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    pub polygons_in: u64,
    pub polygons_out: [u64; 2],
    pub vertices_out: [u64; 2],
}

impl Stats {
    /// Counts `n` polygons that arrived as a `skip n` (in, and nothing out).
    pub fn skipped(&mut self, n: u32) {
        self.polygons_in += n as u64;
    }

    /// Counts one split.
    pub fn record(&mut self, out1: &Polygon, out2: &Polygon) {
        self.polygons_in += 1;
        for (i, piece) in [out1, out2].into_iter().enumerate() {
            if piece.vertices.len() >= Lean::MIN_VERTICES {
                self.polygons_out[i] += 1;
                self.vertices_out[i] += piece.vertices.len() as u64;
            }
        }
    }
}

impl fmt::Display for Stats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} polygons in; out1 {} polygons, {} vertices; out2 {} polygons, {} vertices",
            self.polygons_in,
            self.polygons_out[0],
            self.vertices_out[0],
            self.polygons_out[1],
            self.vertices_out[1]
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proto::DVec4;

    /// An eye-space vertex at depth z_e = 16 of the default camera (w = 10), so that the
    /// plane x=0 is x_e = 0 and y=0.5 is y_e = 5.
    fn v(x: f64, y: f64) -> Vertex {
        DVec4::new(x, y, 16.0, 10.0)
    }

    fn poly(points: &[(f64, f64)]) -> Polygon {
        Polygon::new([1, 2, 3], points.iter().map(|&(x, y)| v(x, y)).collect())
    }

    fn run(points: &[(f64, f64)], plane: Plane) -> (Vec<Vertex>, Vec<Vertex>) {
        let mut a = Polygon::default();
        let mut b = Polygon::default();
        split(&poly(points), &plane, &mut a, &mut b);
        assert_eq!(a.colour, [1, 2, 3]);
        assert_eq!(b.colour, [1, 2, 3]);
        (a.vertices, b.vertices)
    }

    fn x0() -> Plane {
        Plane::column(0.0, 1.0)
    }

    /// A square right of x=0 with its left edge on it: node 1's OUT1 piece is that edge,
    /// two vertices, which a process per node would skip (the lean stream). Split again
    /// across y=0 it would make two three-vertex slivers, (I, v, I); the subtree empties
    /// it first, so the level below gets nothing, as node 2's process would have.
    #[test]
    fn a_polygon_sent_whole_one_way_at_every_node_is_not_cut() {
        let mut tree = Subtree::new(vec![vec![x0()], vec![Plane::row(0.0), Plane::row(0.0)]]);
        // Wholly on one side of x_e = 0 and of the row plane: every node sends it one way,
        // and the piece that reaches a leaf is the polygon's own vertices.
        let square = poly(&[(1.0, 1.0), (1.0, 2.0), (2.0, 2.0), (2.0, 1.0)]);
        tree.split(&square);
        assert!(!tree.cut());
        let whole: Vec<_> = tree
            .outputs()
            .iter()
            .filter(|p| !p.vertices.is_empty())
            .collect();
        assert_eq!(whole.len(), 1);
        assert!(whole[0]
            .vertices
            .iter()
            .all(|v| square.vertices.contains(v)));
        // Across x_e = 0: cut at the root.
        tree.split(&poly(&[(-1.0, 1.0), (-1.0, 2.0), (2.0, 2.0), (2.0, 1.0)]));
        assert!(tree.cut());
        // A vertex on the plane goes both ways: counted as cut, to be checked.
        tree.split(&poly(&[(0.0, 1.0), (1.0, 2.0), (2.0, 1.0)]));
        assert!(tree.cut());
        // And the next polygon starts afresh.
        tree.split(&square);
        assert!(!tree.cut());
    }

    #[test]
    fn a_subtree_empties_a_piece_too_small_to_send_before_the_level_below() {
        let mut tree = Subtree::new(vec![vec![x0()], vec![Plane::row(0.0), Plane::row(0.0)]]);
        let square = poly(&[(0.0, -2.0), (0.0, 2.0), (2.0, 2.0), (2.0, -2.0)]);
        let mut a = Polygon::default();
        let mut b = Polygon::default();
        split(&square, &x0(), &mut a, &mut b);
        assert_eq!(a.vertices, [v(0.0, -2.0), v(0.0, 2.0)]);
        // What node 2 would make of the edge, were it sent: slivers of three vertices.
        let (mut c, mut d) = (Polygon::default(), Polygon::default());
        split(&a, &Plane::row(0.0), &mut c, &mut d);
        assert_eq!((c.vertices.len(), d.vertices.len()), (3, 3));
        tree.split(&square);
        let out = tree.outputs();
        assert_eq!(
            out.iter().map(|p| p.vertices.len()).collect::<Vec<_>>(),
            [0, 0, 4, 4]
        );
        // Node 2 counts a polygon in and nothing out, as its process would have.
        assert_eq!(tree.stats[1][0].polygons_in, 1);
        assert_eq!(tree.stats[1][0].polygons_out, [0, 0]);
    }

    #[test]
    fn vertex_colours_are_cut_with_the_edges_and_the_whole_shade_is_kept() {
        // The square −2 ≤ x_e ≤ 2, red on the left, blue on the right: cut at x_e = 0,
        // both new vertices are half way, purple; both pieces get the whole square's
        // colour planes, and the opacity.
        let mut square = poly(&[(-2.0, -2.0), (2.0, -2.0), (2.0, 2.0), (-2.0, 2.0)]);
        let (red, blue) = (DVec3::new(255.0, 0.0, 0.0), DVec3::new(0.0, 0.0, 255.0));
        square.vertex_attrs = vec![red, blue, blue, red];
        square.opacity = 99;
        let whole = proto::shade::eye_colour_planes(&square.vertices, &square.vertex_attrs);
        assert!(whole.is_some());
        let (mut a, mut b) = (Polygon::default(), Polygon::default());
        split(&square, &x0(), &mut a, &mut b);
        let purple = DVec3::new(127.5, 0.0, 127.5);
        assert_eq!(
            a.vertices,
            [v(-2.0, -2.0), v(0.0, -2.0), v(0.0, 2.0), v(-2.0, 2.0)]
        );
        assert_eq!(a.vertex_attrs, [red, purple, purple, red]);
        assert_eq!(
            b.vertices,
            [v(0.0, -2.0), v(2.0, -2.0), v(2.0, 2.0), v(0.0, 2.0)]
        );
        assert_eq!(b.vertex_attrs, [purple, blue, blue, purple]);
        assert_eq!(
            (a.shade.clone(), b.shade.clone()),
            (whole.map(Box::new), whole.map(Box::new))
        );
        assert_eq!((a.opacity, b.opacity), (99, 99));
        // A recorded shade is kept, not refitted; a flat polygon's pieces stay flat.
        square.shade = Some(Box::new([DVec4::new(0.0, 0.0, 1.0, -7.0); 3]));
        split(&square, &x0(), &mut a, &mut b);
        assert_eq!(a.shade, square.shade);
        let flat = poly(&[(-2.0, -2.0), (2.0, -2.0), (2.0, 2.0)]);
        split(&flat, &x0(), &mut a, &mut b);
        assert!(a.vertex_attrs.is_empty() && b.vertex_attrs.is_empty() && a.shade.is_none());
    }

    #[test]
    fn case_1_and_2_wholly_on_one_side() {
        // Inside (x_e ≤ 0): everything to out1, unchanged; out2 gets an empty polygon.
        let tri = [(-3.0, 0.0), (-1.0, 4.0), (-2.0, -2.0)];
        let (a, b) = run(&tri, x0());
        assert_eq!(a, vec![v(-3.0, 0.0), v(-1.0, 4.0), v(-2.0, -2.0)]);
        assert!(b.is_empty());
        let tri = [(3.0, 0.0), (1.0, 4.0), (2.0, -2.0)];
        let (a, b) = run(&tri, x0());
        assert!(a.is_empty());
        assert_eq!(b, vec![v(3.0, 0.0), v(1.0, 4.0), v(2.0, -2.0)]);
    }

    #[test]
    fn case_3_and_4_crossing_each_way() {
        // A square straddling x_e = 0: edges cross inside → outside at the top and
        // outside → inside at the bottom.
        let square = [(-2.0, -2.0), (-2.0, 2.0), (2.0, 2.0), (2.0, -2.0)];
        let (a, b) = run(&square, x0());
        // Edge (v3, v0) enters the inside at (0, −2); edge (v1, v2) leaves at (0, 2).
        assert_eq!(
            a,
            vec![v(0.0, -2.0), v(-2.0, -2.0), v(-2.0, 2.0), v(0.0, 2.0)]
        );
        assert_eq!(
            b,
            vec![v(0.0, -2.0), v(0.0, 2.0), v(2.0, 2.0), v(2.0, -2.0)]
        );
    }

    #[test]
    fn case_5_and_6_vertices_on_the_plane() {
        // A diamond with its top and bottom vertices on x_e = 0: no intersection is
        // made; the two on-plane vertices go to both sides.
        let diamond = [(0.0, -3.0), (-3.0, 0.0), (0.0, 3.0), (3.0, 0.0)];
        let (a, b) = run(&diamond, x0());
        assert_eq!(a, vec![v(0.0, -3.0), v(-3.0, 0.0), v(0.0, 3.0)]);
        assert_eq!(b, vec![v(0.0, -3.0), v(0.0, 3.0), v(3.0, 0.0)]);
    }

    #[test]
    fn touching_the_plane_from_one_side() {
        // One vertex on the plane, the rest inside: out2 gets the lone on-plane vertex
        // (a degenerate polygon, which the scan converter discards).
        let tri = [(0.0, 0.0), (-2.0, 3.0), (-2.0, -3.0)];
        let (a, b) = run(&tri, x0());
        assert_eq!(a, vec![v(0.0, 0.0), v(-2.0, 3.0), v(-2.0, -3.0)]);
        assert_eq!(b, vec![v(0.0, 0.0)]);
        // An edge lying in the plane: both ends go to both sides.
        let tri = [(0.0, -2.0), (0.0, 2.0), (2.0, 0.0)];
        let (a, b) = run(&tri, x0());
        assert_eq!(a, vec![v(0.0, -2.0), v(0.0, 2.0)]);
        assert_eq!(b, vec![v(0.0, -2.0), v(0.0, 2.0), v(2.0, 0.0)]);
    }

    #[test]
    fn row_plane_at_one_half() {
        // y=0.5 is y_e = 0.5·w = 5 at this depth. Out1 gets y_e ≤ 5.
        let tri = [(0.0, 0.0), (4.0, 8.0), (-4.0, 8.0)];
        let (a, b) = run(&tri, Plane::row(0.5));
        // Edge (v2, v0) enters the inside at (−2.5, 5); edge (v0, v1) leaves at (2.5, 5).
        assert_eq!(a, vec![v(-2.5, 5.0), v(0.0, 0.0), v(2.5, 5.0)]);
        assert_eq!(
            b,
            vec![v(-2.5, 5.0), v(2.5, 5.0), v(4.0, 8.0), v(-4.0, 8.0)]
        );
    }

    #[test]
    fn degenerate_polygons() {
        let (a, b) = run(&[], x0());
        assert!(a.is_empty() && b.is_empty());
        let (a, b) = run(&[(1.0, 1.0)], x0());
        assert!(a.is_empty());
        assert_eq!(b, vec![v(1.0, 1.0)]);
        let (a, b) = run(&[(-1.0, 1.0), (1.0, 1.0)], x0());
        assert_eq!(a, vec![v(0.0, 1.0), v(-1.0, 1.0), v(0.0, 1.0)]);
        assert_eq!(b, vec![v(0.0, 1.0), v(0.0, 1.0), v(1.0, 1.0)]);
    }

    #[test]
    fn buffers_are_reused_and_cleared() {
        let mut a = Polygon::default();
        let mut b = Polygon::default();
        split(
            &poly(&[(-1.0, 0.0), (-1.0, 1.0), (-2.0, 0.0)]),
            &x0(),
            &mut a,
            &mut b,
        );
        split(
            &poly(&[(1.0, 0.0), (1.0, 1.0), (2.0, 0.0)]),
            &x0(),
            &mut a,
            &mut b,
        );
        assert!(a.vertices.is_empty());
        assert_eq!(b.vertices.len(), 3);
    }

    #[test]
    fn cut_edges_carry_their_original_edge_and_the_pieces_the_whole_plane() {
        let (v0, v1, v2, v3) = (v(-2.0, -2.0), v(-2.0, 2.0), v(2.0, 2.0), v(2.0, -2.0));
        let square = Polygon::new([1, 2, 3], vec![v0, v1, v2, v3]);
        let (mut a, mut b) = (Polygon::default(), Polygon::default());
        split(&square, &x0(), &mut a, &mut b);
        let (ib, it) = (v(0.0, -2.0), v(0.0, 2.0));
        assert_eq!(a.vertices, vec![ib, v0, v1, it]);
        // I_b→v0 is a piece of v3→v0, v1→I_t of v1→v2; v0→v1 is whole, I_t→I_b is new.
        assert_eq!(a.supports, vec![Some([v3, v0]), None, Some([v1, v2]), None]);
        assert_eq!(b.vertices, vec![ib, it, v2, v3]);
        assert_eq!(b.supports, vec![None, Some([v1, v2]), None, Some([v3, v0])]);
        // At one depth z_e = 16 the plane is exactly z_e = 16.
        assert_eq!(a.plane, Some(DVec4::new(0.0, 0.0, 1.0, -16.0)));
        assert_eq!(b.plane, a.plane);

        // The left piece cut again by y=0: supports are inherited, not replaced, and the
        // first cut's new edge, now cut itself, is the support of its own pieces.
        let (mut c, mut d) = (Polygon::default(), Polygon::default());
        split(&a, &Plane::row(0.0), &mut c, &mut d);
        let (j1, j2) = (v(0.0, 0.0), v(-2.0, 0.0));
        assert_eq!(c.vertices, vec![j1, ib, v0, j2]);
        assert_eq!(
            c.supports,
            vec![Some([it, ib]), Some([v3, v0]), Some([v0, v1]), None]
        );
        assert_eq!(d.vertices, vec![j1, j2, v1, it]);
        assert_eq!(
            d.supports,
            vec![None, Some([v0, v1]), Some([v1, v2]), Some([it, ib])]
        );
        assert_eq!(c.plane, a.plane);
        assert_eq!(d.plane, a.plane);
    }

    #[test]
    fn the_plane_is_the_wholes_and_kept_once_recorded() {
        // A tilted, non-planar quadrilateral: its plane is a best fit, which its pieces
        // must share with it bit for bit.
        let quad = Polygon::new(
            [1, 1, 1],
            vec![
                DVec4::new(-3.0, -1.0, 12.0, 7.5),
                DVec4::new(-2.5, 4.0, 14.0, 8.75),
                DVec4::new(3.5, 3.0, 21.0, 13.125),
                DVec4::new(4.0, -2.0, 16.5, 10.3125),
            ],
        );
        let whole = quad.eye_plane().unwrap();
        let (mut a, mut b) = (Polygon::default(), Polygon::default());
        split(&quad, &x0(), &mut a, &mut b);
        assert_eq!(a.plane, Some(whole));
        assert_eq!(b.plane, Some(whole));
        assert_ne!(a.eye_plane(), Some(whole), "a piece's own fit differs");
        // A polygon wholly on one side is not cut: nothing is added.
        let (mut c, mut d) = (Polygon::default(), Polygon::default());
        split(&quad, &Plane::column(0.9, 1.0), &mut c, &mut d);
        assert_eq!(c, quad);
        assert!(d.vertices.is_empty() && d.plane.is_none());
        // A plane recorded earlier is passed on, never recomputed.
        let mut recorded = quad.clone();
        recorded.plane = Some(DVec4::new(1.0, 2.0, 3.0, 4.0));
        split(&recorded, &x0(), &mut a, &mut b);
        assert_eq!(a.plane, recorded.plane);
        assert_eq!(b.plane, recorded.plane);
    }

    #[test]
    fn plane_arguments() {
        assert_eq!("x=0".parse::<SplitPlane>(), Ok(SplitPlane::Column(0.0)));
        assert_eq!("y=-0.5".parse::<SplitPlane>(), Ok(SplitPlane::Row(-0.5)));
        assert!("x=1.5"
            .parse::<SplitPlane>()
            .unwrap_err()
            .contains("[-1, 1]"));
        assert!("z=0".parse::<SplitPlane>().is_err());
        assert!("x".parse::<SplitPlane>().is_err());
        assert!("x=nan".parse::<SplitPlane>().is_err());
        let view = View {
            aspect: 2.0,
            ..View::default()
        };
        assert_eq!(
            SplitPlane::Column(0.5).plane(&view),
            Plane::column(0.5, 2.0)
        );
        assert_eq!(
            SplitPlane::parse_general("1,0,0,-2,0.5")
                .unwrap()
                .plane(&view),
            Plane::new(DVec4::new(1.0, 0.0, 0.0, -2.0), 0.5)
        );
        assert!(SplitPlane::parse_general("0,0,0,0,1").is_err());
        assert!(SplitPlane::parse_general("1,2,3").is_err());
    }

    fn text_of(out: Writer<Token, Vec<u8>>) -> String {
        String::from_utf8(out.into_inner().unwrap()).unwrap()
    }

    #[test]
    fn lean_outputs_skip_what_draws_nothing() {
        let header = proto::Header::new(proto::Space::Eye(View::default()));
        let mut out = Writer::new(Vec::new(), header, proto::Form::Text).unwrap();
        let mut lean = Lean::default();
        let two = poly(&[(1.0, 1.0), (2.0, 2.0)]);
        let tri = poly(&[(1.0, 1.0), (2.0, 2.0), (1.0, 3.0)]);
        lean.polygon(&mut out, &Polygon::default()).unwrap();
        lean.polygon(&mut out, &two).unwrap();
        lean.skip(&mut out, 4).unwrap();
        lean.polygon(&mut out, &tri).unwrap();
        lean.polygon(&mut out, &two).unwrap();
        lean.control(&mut out, &Token::End).unwrap();
        assert_eq!(
            text_of(out),
            "polypipe 1 eye aspect 1 hither 1 yon 30\nskip 6\nNEXT.POLYGON\ncolour 1 2 3\n\
             1 1 16 10\n2 2 16 10\n1 3 16 10\nNEXT.POLYGON\nskip 1\nEND\n"
        );
    }

    #[test]
    fn a_skip_count_past_u32_is_written_in_two() {
        let header = proto::Header::new(proto::Space::Eye(View::default()));
        let mut out = Writer::new(Vec::new(), header, proto::Form::Text).unwrap();
        let mut lean = Lean::default();
        lean.skip(&mut out, u32::MAX - 1).unwrap();
        lean.polygon(&mut out, &Polygon::default()).unwrap();
        lean.polygon(&mut out, &Polygon::default()).unwrap();
        lean.control(&mut out, &Token::NextFrame).unwrap();
        assert_eq!(
            text_of(out),
            "polypipe 1 eye aspect 1 hither 1 yon 30\nskip 4294967295\nNEXT.POLYGON\nskip 1\n\
             NEXT.FRAME\n"
        );
    }

    #[test]
    fn stats_count_non_empty_pieces() {
        let mut stats = Stats::default();
        let mut a = Polygon::default();
        let mut b = Polygon::default();
        split(
            &poly(&[(-2.0, -2.0), (-2.0, 2.0), (2.0, 2.0), (2.0, -2.0)]),
            &x0(),
            &mut a,
            &mut b,
        );
        stats.record(&a, &b);
        split(
            &poly(&[(-1.0, 0.0), (-1.0, 1.0), (-2.0, 0.0)]),
            &x0(),
            &mut a,
            &mut b,
        );
        stats.record(&a, &b);
        assert_eq!(
            stats,
            Stats {
                polygons_in: 2,
                polygons_out: [2, 1],
                vertices_out: [7, 4]
            }
        );
    }

    #[test]
    fn tree_regions_bisect_on_pixel_boundaries_alternating_x_and_y() {
        let t = Tree {
            width: 500,
            height: 500,
        };
        let r = |x0, x1, y0, y1| Region { x0, x1, y0, y1 };
        assert_eq!(t.region(1), r(0, 500, 0, 500));
        assert_eq!(t.region(2), r(0, 250, 0, 500)); // left of x=0
        assert_eq!(t.region(3), r(250, 500, 0, 500));
        assert_eq!(t.region(4), r(0, 250, 250, 500)); // below y=0: rows 250..500
        assert_eq!(t.region(5), r(0, 250, 0, 250));
        assert_eq!(t.region(7), r(250, 500, 0, 250));
        assert_eq!(t.region(8), r(0, 125, 250, 500));
        assert_eq!(t.region(9), r(125, 250, 250, 500));
        assert_eq!(t.plane(1), SplitPlane::Column(0.0));
        assert_eq!(t.plane(2), SplitPlane::Row(0.0));
        assert_eq!(t.plane(3), SplitPlane::Row(0.0));
        assert_eq!(t.plane(4), SplitPlane::Column(-0.5));
        assert_eq!(t.plane(6), SplitPlane::Column(0.5));
        assert_eq!(t.plane(8), SplitPlane::Row(-0.5)); // row 375, below the centre
        assert_eq!(t.plane(9), SplitPlane::Row(-0.5));
        assert_eq!(t.plane(10), SplitPlane::Row(0.5)); // row 125
    }

    #[test]
    fn tree_planes_of_an_odd_screen_and_a_zero_is_positive() {
        let t = Tree {
            width: 21,
            height: 21,
        };
        // Column 10 of 21, row 10 of 21: a pixel boundary just left of / above the centre.
        assert_eq!(t.plane(1), SplitPlane::Column(20.0 / 21.0 - 1.0));
        assert_eq!(t.plane(2), SplitPlane::Row(-(20.0 / 21.0 - 1.0)));
        assert_eq!(
            t.region(4),
            Region {
                x0: 0,
                x1: 10,
                y0: 10,
                y1: 21
            }
        );
        assert_eq!(t.plane(4), SplitPlane::Column(10.0 / 21.0 - 1.0));
        // 500 rows: row 250 is y_s = −(2·250/500 − 1) = −0 in doubles, printed as 0.
        let SplitPlane::Row(k) = Tree {
            width: 2,
            height: 500,
        }
        .plane(2) else {
            panic!("a row plane")
        };
        assert_eq!(k.to_bits(), 0.0f64.to_bits());
        // A 1-pixel-wide region still has a boundary to cut at: its left edge.
        let thin = Tree {
            width: 1,
            height: 1,
        };
        assert_eq!(
            thin.region(2),
            Region {
                x0: 0,
                x1: 0,
                y0: 0,
                y1: 1
            }
        );
        assert_eq!(thin.plane(1), SplitPlane::Column(-1.0));
    }

    #[test]
    fn tree_nodes_are_checked_against_the_depth() {
        assert_eq!(Tree::check_node(1, 1), Ok(()));
        assert_eq!(Tree::check_node(63, 6), Ok(()));
        assert_eq!(
            Tree::check_node(4, 2),
            Err("--node 4 is not a splitter node of a depth-2 tree (nodes 1 to 3)".into())
        );
        assert_eq!(
            Tree::check_node(0, 1),
            Err("--node 0 is not a splitter node of a depth-1 tree (only node 1)".into())
        );
        assert_eq!(
            Tree::check_node(1, 0),
            Err("--depth 0: a tree with splitter nodes has 1 to 31 levels".into())
        );
        assert!(Tree::check_node(1, 32).is_err());
        assert_eq!(Tree::check_node(u32::MAX >> 1, 31), Ok(()));
    }
}

#[cfg(test)]
mod properties {
    use super::*;
    use proptest::prelude::*;
    use proto::DVec4;

    /// A random convex polygon: points on an ellipse at sorted angles, at one depth
    /// z_e (so that its area in x_e, y_e is its area on the screen, scaled by w).
    fn convex() -> impl Strategy<Value = Polygon> {
        (
            -6.0..6.0f64,
            -6.0..6.0f64,
            0.5..8.0f64,
            0.5..8.0f64,
            1.5..29.0f64,
            prop::collection::vec(0.0..std::f64::consts::TAU, 3..12),
        )
            .prop_map(|(cx, cy, rx, ry, z, mut angles)| {
                angles.sort_by(f64::total_cmp);
                angles.dedup();
                let w = z * 10.0 / 16.0;
                Polygon::new(
                    [9, 9, 9],
                    angles
                        .iter()
                        .map(|t| DVec4::new(cx + rx * t.cos(), cy + ry * t.sin(), z, w))
                        .collect(),
                )
            })
    }

    fn planes() -> impl Strategy<Value = Plane> {
        prop_oneof![
            (-1.0..=1.0f64, 0.5..2.0f64).prop_map(|(k, a)| Plane::column(k, a)),
            (-1.0..=1.0f64).prop_map(Plane::row),
            // Exactly on the dyadic planes a splitter tree uses.
            (0..9i32).prop_map(|i| Plane::column(i as f64 / 4.0 - 1.0, 1.0)),
            (
                -1.0..1.0f64,
                -1.0..1.0f64,
                -0.2..0.2f64,
                -1.0..1.0f64,
                -1.0..1.0f64
            )
                .prop_map(|(a, b, c, d, k)| Plane::new(DVec4::new(a, b, c, d), k)),
        ]
    }

    /// Twice the signed area in (x_e, y_e).
    fn area2(vs: &[Vertex]) -> f64 {
        let n = vs.len();
        (0..n)
            .map(|i| {
                let (p, q) = (vs[i], vs[(i + 1) % n]);
                p.x * q.y - q.x * p.y
            })
            .sum()
    }

    proptest! {
        #[test]
        fn pieces_lie_on_their_sides_and_their_areas_add_up(
            poly in convex(),
            plane in planes(),
        ) {
            let mut a = Polygon::default();
            let mut b = Polygon::default();
            split(&poly, &plane, &mut a, &mut b);
            for v in &a.vertices {
                prop_assert_ne!(plane.classify(*v).0, Side::Outside, "{:?} in out1", v);
            }
            let other = plane.flipped();
            for v in &b.vertices {
                prop_assert_ne!(other.classify(*v).0, Side::Outside, "{:?} in out2", v);
            }
            let whole = area2(&poly.vertices);
            let sum = area2(&a.vertices) + area2(&b.vertices);
            let scale = poly.vertices.iter().map(|v| v.x.abs() + v.y.abs()).fold(1.0, f64::max);
            prop_assert!(
                (whole - sum).abs() <= 1e-12 * scale * scale * poly.vertices.len() as f64,
                "whole {} pieces {}", whole, sum
            );
            // Every edge of a piece either is an edge of the whole, or lies on a support
            // (an edge of the whole), or is new and lies in the plane.
            let whole_edges: Vec<_> = poly.edges().collect();
            for piece in [&a, &b] {
                prop_assert!(piece.supports.is_empty() || piece.supports.len() == piece.vertices.len());
                for (i, (p, q)) in piece.edges().enumerate() {
                    if let Some([s, t]) = piece.support(i) {
                        prop_assert!(whole_edges.contains(&(s, t)), "support {:?}", (s, t));
                        let off = |x: Vertex| {
                            let (d, e) = ((t - s).truncate(), (x - s).truncate());
                            d.cross(e).length() / d.length().max(1e-300)
                        };
                        prop_assert!(off(p) <= 1e-9 * scale && off(q) <= 1e-9 * scale);
                    } else {
                        let in_plane = |x: Vertex| plane.classify(x).0 == Side::On;
                        prop_assert!(
                            whole_edges.contains(&(p, q)) || (in_plane(p) && in_plane(q)),
                            "edge {:?} is neither original nor on the plane", (p, q)
                        );
                    }
                }
            }
            // A piece of a convex polygon has at most one vertex more than the whole.
            prop_assert!(a.vertices.len() <= poly.vertices.len() + 1);
            prop_assert!(b.vertices.len() <= poly.vertices.len() + 1);
        }
    }
}
