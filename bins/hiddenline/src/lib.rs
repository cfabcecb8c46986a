//! # hiddenline: the visible parts of polygon edges, as SVG (Archuleta's output)
//!
//! Archuleta's hidden-surface line drawing (1972, "Line Drawing Algorithm")
//! takes Watkins's scan-line visibility and, instead of shading the visible segments,
//! draws the parts of the polygons' edges that are visible, as vectors. His vectors are
//! found a scan line at a time, so they inherit the raster's resolution (his "third
//! problem", 256 scan lines) and overlap a little where edges cross (his "first
//! problem"). Here the visibility of an edge is computed in continuous geometry instead,
//! in f64, so the pieces are exact to rounding at any size:
//!
//! for an edge of polygon A and each other polygon B, the parameter intervals of the edge
//! where its projection is strictly inside B and B's plane is nearer than the edge are
//! hidden; their union is the hidden part, its complement is drawn. The breakpoints are
//! where the edge crosses B's edges and where the depth of the edge crosses B's plane (a
//! linear function along the edge: solved exactly); between two breakpoints one point
//! decides. A point on B's boundary is not inside B, so an edge B shares is not hidden by
//! B; at equal depth the polygon earlier in the stream hides the later (the tie rule of
//! every method here, docs/DESIGN.md, "Visibility").
//!
//! An edge two polygons share is drawn once, in the colour of the earlier. Edges that
//! are not edges of the model are left out: where the splitter tree cut a polygon (two
//! pieces of one polygon, with the same colour and the same recorded `plane`, meeting
//! along the cut; docs/DESIGN.md, "Annotations: `plane` and `on`") and where the clipper
//! cut one at the screen's border. Where two polygons pass through each other, their
//! line of intersection is not drawn (Archuleta's "second problem": no edge there).
//!
//! Screen coordinates are the device's (X right, Y down, pixels), so the SVG's viewBox
//! is `0 0 W H` and its user units are pixels of the PPM frames.

use proto::{Colour, DVec2, Polygon};
use std::fmt::Write as _;

/// A visible piece of an edge, in device coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    pub from: DVec2,
    pub to: DVec2,
    pub colour: Colour,
}

/// Counters for `--stats`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LineStats {
    /// Edges examined (of polygons that have an area on the screen).
    pub edges: u64,
    /// Edges left out: shared with an earlier polygon, splitter cuts, screen border.
    pub shared: u64,
    pub cuts: u64,
    pub border: u64,
    /// Edge–polygon pairs whose bounding boxes met, so that the edge was tested.
    pub pairs_tested: u64,
    /// Pieces drawn.
    pub segments: u64,
}

/// A polygon ready for the tests: its screen points, depths and depth plane.
struct Face {
    index: usize,
    colour: Colour,
    points: Vec<DVec2>,
    depths: Vec<f64>,
    /// Depth = −(a·X + b·Y + d)/c.
    plane: [f64; 4],
    recorded: Option<[u64; 4]>,
    min: DVec2,
    max: DVec2,
}

impl Face {
    fn of(index: usize, p: &Polygon) -> Option<Face> {
        let points: Vec<DVec2> = p.vertices.iter().map(|v| DVec2::new(v.x, v.y)).collect();
        if points.len() < 3 || proto::raster::on_one_line(&points) {
            return None;
        }
        let recorded = p.plane.filter(|n| n.z != 0.0 && n.is_finite());
        let n = recorded.unwrap_or_else(|| {
            let pts: Vec<_> = p.vertices.iter().map(|v| v.truncate()).collect();
            proto::geometry::newell_plane(&pts)
        });
        if n.z == 0.0 || !n.is_finite() {
            return None; // seen edge-on: no area
        }
        let min = points.iter().copied().fold(DVec2::INFINITY, DVec2::min);
        let max = points.iter().copied().fold(DVec2::NEG_INFINITY, DVec2::max);
        Some(Face {
            index,
            colour: p.colour,
            depths: p.vertices.iter().map(|v| v.z).collect(),
            points,
            plane: [n.x, n.y, n.z, n.w],
            recorded: p.plane.map(|n| n.to_array().map(f64::to_bits)),
            min,
            max,
        })
    }

    fn depth_at(&self, q: DVec2) -> f64 {
        let [a, b, c, d] = self.plane;
        -(a * q.x + b * q.y + d) / c
    }

    fn edge(&self, i: usize) -> (DVec2, DVec2) {
        (self.points[i], self.points[(i + 1) % self.points.len()])
    }

    /// Is `q` on the boundary, to `tol`?
    fn on_boundary(&self, q: DVec2, tol: f64) -> bool {
        (0..self.points.len()).any(|i| {
            let (a, b) = self.edge(i);
            let ab = b - a;
            let len2 = ab.length_squared();
            let t = if len2 > 0.0 {
                ((q - a).dot(ab) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (a + ab * t - q).length() <= tol
        })
    }

    /// Is `q` strictly inside (even-odd, the boundary excluded)?
    fn strictly_inside(&self, q: DVec2, tol: f64) -> bool {
        if self.on_boundary(q, tol) {
            return false;
        }
        let mut inside = false;
        for i in 0..self.points.len() {
            let (a, b) = self.edge(i);
            if (a.y > q.y) != (b.y > q.y) {
                let x = a.x + (q.y - a.y) / (b.y - a.y) * (b.x - a.x);
                if q.x < x {
                    inside = !inside;
                }
            }
        }
        inside
    }
}

/// Could the box [bmin, bmax] hold a point of the edge's box [emin, emax] strictly
/// inside it? (Each axis: the edge's range meets B's open range.)
fn straddles(bmin: DVec2, bmax: DVec2, emin: DVec2, emax: DVec2) -> bool {
    let axis = |bl: f64, bh: f64, el: f64, eh: f64| {
        if el == eh {
            bl < el && el < bh
        } else {
            bl < eh && el < bh
        }
    };
    axis(bmin.x, bmax.x, emin.x, emax.x) && axis(bmin.y, bmax.y, emin.y, emax.y)
}

/// A uniform grid over the screen, each cell listing the faces whose bounding box meets
/// it: the faces that may hide a point of an edge are those of the cells the edge's box
/// meets, not every face of the frame.
struct Grid {
    origin: DVec2,
    cell: DVec2,
    nx: usize,
    ny: usize,
    cells: Vec<Vec<u32>>,
}

impl Grid {
    fn new(faces: &[Face], width: u32, height: u32) -> Grid {
        let n = ((faces.len() as f64).sqrt().ceil() as usize).clamp(1, 256);
        let origin = DVec2::ZERO;
        let cell = DVec2::new(
            width.max(1) as f64 / n as f64,
            height.max(1) as f64 / n as f64,
        );
        let mut grid = Grid {
            origin,
            cell,
            nx: n,
            ny: n,
            cells: vec![Vec::new(); n * n],
        };
        for (k, f) in faces.iter().enumerate() {
            let (x, y) = grid.range(f.min, f.max);
            for j in y.clone() {
                for i in x.clone() {
                    grid.cells[j * grid.nx + i].push(k as u32);
                }
            }
        }
        grid
    }

    /// The cells a box meets (clamped to the grid: faces off the screen's edge share the
    /// border cells).
    fn range(&self, min: DVec2, max: DVec2) -> (std::ops::Range<usize>, std::ops::Range<usize>) {
        let idx = |v: f64, o: f64, c: f64, n: usize| {
            let i = ((v - o) / c).floor();
            if i.is_nan() || i < 0.0 {
                0
            } else {
                (i as usize).min(n - 1)
            }
        };
        let x0 = idx(min.x, self.origin.x, self.cell.x, self.nx);
        let x1 = idx(max.x, self.origin.x, self.cell.x, self.nx);
        let y0 = idx(min.y, self.origin.y, self.cell.y, self.ny);
        let y1 = idx(max.y, self.origin.y, self.cell.y, self.ny);
        (x0..x1 + 1, y0..y1 + 1)
    }

    /// The faces (positions, ascending) whose boxes may meet the box [min, max].
    fn near(&self, min: DVec2, max: DVec2, out: &mut Vec<u32>) {
        out.clear();
        let (x, y) = self.range(min, max);
        for j in y {
            for i in x.clone() {
                out.extend_from_slice(&self.cells[j * self.nx + i]);
            }
        }
        out.sort_unstable();
        out.dedup();
    }
}

fn cross(a: DVec2, b: DVec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Does segment (c, d) lie on the line of (a, b), overlapping it over a positive length?
fn collinear_overlap(a: DVec2, b: DVec2, c: DVec2, d: DVec2, tol: f64) -> bool {
    let ab = b - a;
    let len = ab.length();
    if len == 0.0 {
        return false;
    }
    let off = |p: DVec2| cross(ab, p - a).abs() / len;
    if off(c) > tol || off(d) > tol {
        return false;
    }
    let t = |p: DVec2| (p - a).dot(ab) / (len * len);
    let (lo, hi) = (t(c).min(t(d)), t(c).max(t(d)));
    hi.min(1.0) - lo.max(0.0) > tol / len
}

/// The visible pieces of every edge of a frame of screen-space polygons (stream order)
/// on a `width`×`height` screen.
pub fn visible_segments(
    polygons: &[Polygon],
    width: u32,
    height: u32,
    stats: &mut LineStats,
) -> Vec<Segment> {
    let faces: Vec<Face> = polygons
        .iter()
        .enumerate()
        .filter_map(|(i, p)| Face::of(i, p))
        .collect();
    // Lengths below this are rounding: a millionth of a millionth of the screen.
    let tol = 1e-12 * (width as f64 + height as f64).max(1.0);
    let (w, h) = (width as f64, height as f64);
    // Every edge's owners, in stream order: an edge two polygons share is drawn once.
    let mut owners: std::collections::HashMap<[u64; 4], Vec<usize>> = Default::default();
    for (k, f) in faces.iter().enumerate() {
        for i in 0..f.points.len() {
            let (p0, p1) = f.edge(i);
            owners.entry(edge_key(p0, p1)).or_default().push(k);
        }
    }
    let grid = Grid::new(&faces, width, height);
    let mut near = Vec::new();
    let mut drawn: std::collections::HashSet<[u64; 4]> = Default::default();
    let mut out = Vec::new();
    for a in &faces {
        for i in 0..a.points.len() {
            let (p0, p1) = a.edge(i);
            if p0 == p1 {
                continue;
            }
            stats.edges += 1;
            // On the screen's border: the clipper's cut.
            let on = |u: f64, v: f64, k: f64| (u - k).abs() <= tol && (v - k).abs() <= tol;
            if on(p0.x, p1.x, 0.0) || on(p0.x, p1.x, w) || on(p0.y, p1.y, 0.0) || on(p0.y, p1.y, h)
            {
                stats.border += 1;
                continue;
            }
            // A splitter's cut: another piece of the same polygon meets this one along it.
            grid.near(p0.min(p1), p0.max(p1), &mut near);
            let cut = a.recorded.is_some()
                && near.iter().map(|&k| &faces[k as usize]).any(|b| {
                    b.index != a.index
                        && b.recorded == a.recorded
                        && b.colour == a.colour
                        && (0..b.points.len()).any(|j| {
                            let (q0, q1) = b.edge(j);
                            collinear_overlap(p0, p1, q0, q1, tol)
                        })
                });
            if cut {
                stats.cuts += 1;
                continue;
            }
            // Shared with a polygon before: drawn once.
            let key = edge_key(p0, p1);
            if !drawn.insert(key) {
                stats.shared += 1;
                continue;
            }
            // In the colour of the first owner that shows beside it (a silhouette edge
            // shared with a hidden back face takes the front face's colour), else the
            // first's.
            let colour = owners[&key]
                .iter()
                .map(|&k| &faces[k])
                .find(|f| owners[&key].len() == 1 || side_shows(f, &faces, &grid, p0, p1))
                .map_or(a.colour, |f| f.colour);
            let (z0, z1) = (a.depths[i], a.depths[(i + 1) % a.points.len()]);
            let candidates = near.iter().map(|&k| &faces[k as usize]);
            let hidden = hidden_intervals(a, candidates, (p0, z0), (p1, z1), tol, stats);
            let mut t = 0.0;
            let mut piece = |t0: f64, t1: f64| {
                if (t1 - t0) * (p1 - p0).length() > tol {
                    let at = |t: f64| {
                        if t == 0.0 {
                            p0
                        } else if t == 1.0 {
                            p1
                        } else {
                            p0 + (p1 - p0) * t
                        }
                    };
                    out.push(Segment {
                        from: at(t0),
                        to: at(t1),
                        colour,
                    });
                    stats.segments += 1;
                }
            };
            for (h0, h1) in hidden {
                piece(t, h0);
                t = h1;
            }
            piece(t, 1.0);
        }
    }
    out
}

/// An edge's key: its ends, in either direction, bit for bit.
fn edge_key(p0: DVec2, p1: DVec2) -> [u64; 4] {
    let (u, v) = if (p0.x, p0.y) <= (p1.x, p1.y) {
        (p0, p1)
    } else {
        (p1, p0)
    };
    [u.x, u.y, v.x, v.y].map(f64::to_bits)
}

/// Does face `f` show just beside the middle of its edge p0→p1: is a point inside it a
/// hair from the edge hidden by no other polygon?
fn side_shows(f: &Face, faces: &[Face], grid: &Grid, p0: DVec2, p1: DVec2) -> bool {
    let m = (p0 + p1) * 0.5;
    let d = p1 - p0;
    let n = DVec2::new(-d.y, d.x) * (1e-6 / d.length().max(1e-300)) * (1.0 + m.abs().max_element());
    let tol = 1e-9;
    let Some(q) = [m + n, m - n]
        .into_iter()
        .find(|&q| f.strictly_inside(q, tol))
    else {
        return false;
    };
    let z = f.depth_at(q);
    let mut near = Vec::new();
    grid.near(q, q, &mut near);
    !near.iter().map(|&k| &faces[k as usize]).any(|b| {
        b.index != f.index && b.strictly_inside(q, tol) && {
            let zb = b.depth_at(q);
            let scale = 1e-12 * (1.0 + z.abs());
            if (zb - z).abs() <= scale {
                b.index < f.index
            } else {
                zb < z
            }
        }
    })
}

/// The hidden parameter intervals of A's edge p0→p1 (depths z0, z1), sorted and merged.
fn hidden_intervals<'f>(
    a: &Face,
    faces: impl Iterator<Item = &'f Face>,
    (p0, z0): (DVec2, f64),
    (p1, z1): (DVec2, f64),
    tol: f64,
    stats: &mut LineStats,
) -> Vec<(f64, f64)> {
    let r = p1 - p0;
    let (emin, emax) = (p0.min(p1), p0.max(p1));
    let mut hidden: Vec<(f64, f64)> = Vec::new();
    let mut ts = Vec::new();
    for b in faces {
        if b.index == a.index || !straddles(b.min, b.max, emin, emax) {
            continue; // apart, or touching only: no point of the edge strictly inside B
        }
        stats.pairs_tested += 1;
        // How much nearer B is than the edge, along the edge: linear in t.
        let (d0, d1) = (z0 - b.depth_at(p0), z1 - b.depth_at(p1));
        let scale = 1e-12 * (1.0 + z0.abs().max(z1.abs()));
        let tie_hides = b.index < a.index;
        if d0 < -scale && d1 < -scale {
            continue; // the edge is nearer than B's plane all along
        }
        if (d0.abs() <= scale && d1.abs() <= scale) && !tie_hides {
            continue; // coplanar, and B later: B does not hide it
        }
        ts.clear();
        ts.push(0.0);
        ts.push(1.0);
        if (d0 > scale && d1 < -scale) || (d0 < -scale && d1 > scale) {
            ts.push(d0 / (d0 - d1));
        }
        for j in 0..b.points.len() {
            let (q0, q1) = b.edge(j);
            let s = q1 - q0;
            let denom = cross(r, s);
            if denom == 0.0 {
                continue;
            }
            let t = cross(q0 - p0, s) / denom;
            let u = cross(q0 - p0, r) / denom;
            if t > 0.0 && t < 1.0 && (-1e-9..=1.0 + 1e-9).contains(&u) {
                ts.push(t);
            }
        }
        ts.sort_by(f64::total_cmp);
        for k in 0..ts.len() - 1 {
            let (t0, t1) = (ts[k], ts[k + 1]);
            if t1 <= t0 {
                continue;
            }
            let m = 0.5 * (t0 + t1);
            let d = d0 + (d1 - d0) * m;
            let nearer = if d.abs() <= scale { tie_hides } else { d > 0.0 };
            if nearer && b.strictly_inside(p0 + r * m, tol.max(1e-9)) {
                hidden.push((t0, t1));
            }
        }
    }
    hidden.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut merged: Vec<(f64, f64)> = Vec::new();
    for (t0, t1) in hidden {
        match merged.last_mut() {
            Some(last) if t0 <= last.1 => last.1 = last.1.max(t1),
            _ => merged.push((t0, t1)),
        }
    }
    merged
}

/// One frame's SVG: the pieces as `<line>`s stroked in their colours over a background.
pub fn svg(
    segments: &[Segment],
    width: u32,
    height: u32,
    background: Colour,
    stroke: f64,
) -> String {
    let mut s = String::new();
    let [r, g, b] = background;
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}">"#
    );
    let _ = writeln!(
        s,
        r#"<rect width="{width}" height="{height}" fill="rgb({r},{g},{b})"/>"#
    );
    let _ = writeln!(
        s,
        r#"<g fill="none" stroke-width="{stroke}" stroke-linecap="round">"#
    );
    for seg in segments {
        let [r, g, b] = seg.colour;
        let _ = writeln!(
            s,
            r#"<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="rgb({r},{g},{b})"/>"#,
            seg.from.x, seg.from.y, seg.to.x, seg.to.y
        );
    }
    s.push_str("</g>\n</svg>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(colour: Colour, x0: f64, y0: f64, x1: f64, y1: f64, z: f64) -> Polygon {
        Polygon::from_xyz(
            colour,
            &[[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]],
        )
    }

    fn lines(polygons: &[Polygon]) -> Vec<(f64, f64, f64, f64, Colour)> {
        let mut stats = LineStats::default();
        visible_segments(polygons, 100, 100, &mut stats)
            .iter()
            .map(|s| (s.from.x, s.from.y, s.to.x, s.to.y, s.colour))
            .collect()
    }

    const RED: Colour = [255, 0, 0];
    const BLUE: Colour = [0, 0, 255];

    #[test]
    fn a_nearer_square_hides_part_of_a_farther_one() {
        // Red (near) over the top-left corner of blue (far).
        let red = square(RED, 10.0, 10.0, 50.0, 50.0, 0.2);
        let blue = square(BLUE, 30.0, 30.0, 70.0, 70.0, 0.6);
        let want = vec![
            (10.0, 10.0, 50.0, 10.0, RED),
            (50.0, 10.0, 50.0, 50.0, RED),
            (50.0, 50.0, 10.0, 50.0, RED),
            (10.0, 50.0, 10.0, 10.0, RED),
            (50.0, 30.0, 70.0, 30.0, BLUE),
            (70.0, 30.0, 70.0, 70.0, BLUE),
            (70.0, 70.0, 30.0, 70.0, BLUE),
            (30.0, 70.0, 30.0, 50.0, BLUE),
        ];
        assert_eq!(lines(&[red.clone(), blue.clone()]), want);
        // Stream order does not matter when depths differ.
        let mut swapped = lines(&[blue, red]);
        swapped.sort_by(|a, b| a.partial_cmp(b).unwrap());
        let mut want = want;
        want.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(swapped, want);
    }

    #[test]
    fn at_equal_depth_the_earlier_hides_the_later() {
        let a = square(RED, 10.0, 10.0, 50.0, 50.0, 0.5);
        let b = square(BLUE, 30.0, 30.0, 70.0, 70.0, 0.5);
        let l = lines(&[a.clone(), b.clone()]);
        assert_eq!(l.len(), 8);
        assert!(l.contains(&(30.0, 70.0, 30.0, 50.0, BLUE)));
        assert!(l.contains(&(50.0, 50.0, 10.0, 50.0, RED)));
        let l = lines(&[b, a]);
        // Now blue is first: red's corner inside blue is hidden.
        assert!(l.contains(&(50.0, 10.0, 50.0, 30.0, RED)));
        assert!(l.contains(&(30.0, 50.0, 10.0, 50.0, RED)));
        assert!(l.contains(&(30.0, 70.0, 30.0, 30.0, BLUE)));
    }

    #[test]
    fn a_shared_edge_is_drawn_once_in_the_earlier_colour() {
        let left = square(RED, 10.0, 10.0, 40.0, 40.0, 0.5);
        let right = square(BLUE, 40.0, 10.0, 70.0, 40.0, 0.3);
        let mut stats = LineStats::default();
        let segs = visible_segments(&[left, right], 100, 100, &mut stats);
        assert_eq!(segs.len(), 7);
        assert_eq!(stats.shared, 1);
        let on_x40: Vec<_> = segs
            .iter()
            .filter(|s| s.from.x == 40.0 && s.to.x == 40.0)
            .collect();
        assert_eq!(on_x40.len(), 1);
        assert_eq!(on_x40[0].colour, RED);
    }

    #[test]
    fn penetration_hides_up_to_the_crossing() {
        // Blue slopes through red's plane (z = 0.5) at X = 40: nearer on the right.
        let red = square(RED, 10.0, 10.0, 70.0, 70.0, 0.5);
        let blue = Polygon::from_xyz(
            BLUE,
            &[
                [20.0, 30.0, 0.7],
                [60.0, 30.0, 0.3],
                [60.0, 50.0, 0.3],
                [20.0, 50.0, 0.7],
            ],
        );
        let l = lines(&[red, blue]);
        let blue_lines: Vec<_> = l.iter().filter(|s| s.4 == BLUE).collect();
        assert_eq!(
            blue_lines,
            vec![
                &(40.0, 30.0, 60.0, 30.0, BLUE),
                &(60.0, 30.0, 60.0, 50.0, BLUE),
                &(60.0, 50.0, 40.0, 50.0, BLUE),
            ]
        );
    }

    #[test]
    fn splitter_cuts_and_the_screen_border_are_left_out() {
        // A square cut at X = 40 into two pieces that carry the whole's plane.
        let plane = proto::DVec4::new(0.0, 0.0, 1.0, -0.5);
        let mut l = square(RED, 10.0, 10.0, 40.0, 40.0, 0.5);
        let mut r = square(RED, 40.0, 10.0, 70.0, 40.0, 0.5);
        l.plane = Some(plane);
        r.plane = Some(plane);
        // A polygon the clipper cut at the screen's left and top.
        let clipped = square(BLUE, 0.0, 0.0, 5.0, 5.0, 0.9);
        let mut stats = LineStats::default();
        let segs = visible_segments(&[l, r, clipped], 100, 100, &mut stats);
        assert_eq!((stats.cuts, stats.border), (2, 2));
        assert_eq!(segs.len(), 6 + 2);
        assert!(segs.iter().all(|s| !(s.from.x == 40.0 && s.to.x == 40.0)));
    }

    #[test]
    fn degenerate_polygons_draw_and_hide_nothing() {
        let line = Polygon::from_xyz(
            RED,
            &[[0.0, 0.0, 0.1], [50.0, 50.0, 0.1], [20.0, 20.0, 0.1]],
        );
        let two = Polygon::from_xyz(RED, &[[0.0, 0.0, 0.1], [50.0, 50.0, 0.1]]);
        let sq = square(BLUE, 10.0, 10.0, 30.0, 30.0, 0.5);
        assert_eq!(lines(&[line, two, sq]).len(), 4);
        assert_eq!(lines(&[]), vec![]);
    }

    #[test]
    fn svg_in_device_coordinates() {
        let segs = [Segment {
            from: DVec2::new(1.5, 2.0),
            to: DVec2::new(3.0, 0.1),
            colour: [1, 2, 3],
        }];
        assert_eq!(
            svg(&segs, 8, 6, [255, 255, 255], 1.0),
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"8\" height=\"6\" viewBox=\"0 0 8 6\">\n\
             <rect width=\"8\" height=\"6\" fill=\"rgb(255,255,255)\"/>\n\
             <g fill=\"none\" stroke-width=\"1\" stroke-linecap=\"round\">\n\
             <line x1=\"1.5\" y1=\"2\" x2=\"3\" y2=\"0.1\" stroke=\"rgb(1,2,3)\"/>\n\
             </g>\n</svg>\n"
        );
    }

    mod properties {
        use super::*;
        use proptest::prelude::*;

        proptest! {
            /// Flat squares at distinct depths: a point of an edge is drawn exactly when
            /// no nearer square has it strictly inside (checked at many points).
            #[test]
            fn drawn_points_are_those_no_nearer_square_covers(
                squares in prop::collection::vec(([0.0f64..80.0, 0.0f64..80.0, 1.0f64..40.0, 1.0f64..40.0], 0u8..255), 1..6),
            ) {
                let polygons: Vec<Polygon> = squares.iter().enumerate().map(|(i, &([x, y, w, h], c))| {
                    square([c, i as u8, 0], x, y, x + w, y + h, 0.1 + 0.1 * ((i * 7) % 6) as f64)
                }).collect();
                let mut stats = LineStats::default();
                let segs = visible_segments(&polygons, 100, 100, &mut stats);
                let faces: Vec<Face> = polygons.iter().enumerate().filter_map(|(i, p)| Face::of(i, p)).collect();
                for a in &faces {
                    for e in 0..4 {
                        let (p0, p1) = a.edge(e);
                        for k in 1..40 {
                            let q = p0 + (p1 - p0) * (k as f64 / 40.0 + 0.0031);
                            let z = a.depths[0];
                            let covered = faces.iter().any(|b| b.index != a.index && b.depths[0] < z && b.strictly_inside(q, 1e-6));
                            let near_cover = faces.iter().any(|b| b.index != a.index && b.on_boundary(q, 1e-6));
                            if near_cover { continue; }
                            let drawn = segs.iter().any(|s| {
                                s.colour == a.colour && {
                                    let d = s.to - s.from;
                                    let t = (q - s.from).dot(d) / d.length_squared();
                                    (-1e-9..=1.0 + 1e-9).contains(&t) && (s.from + d * t - q).length() < 1e-6
                                }
                            });
                            prop_assert_eq!(drawn, !covered, "edge {} of {} at {:?}", e, a.index, q);
                        }
                    }
                }
            }
        }
    }
}
