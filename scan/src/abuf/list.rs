//! The a-buffer's pixelstructs: per pixel nothing, one fully covering fragment (the sampling thesis's
//! *simple* pixelstruct), or a list of fragments sorted by depth (sampling thesis 6.3.1), with
//! the sampling thesis's insertion cases (6.3.4, 6.3.5) and the fragment packer (6.3.6).

use proto::depth::takes;
use proto::Colour;

/// A fragment's coverage: bit `8·j + i` is sub-pixel sample (i, j), at
/// (c + (i+½)/8, r + (j+½)/8) of pixel (c, r) (the sampling thesis's 8×8 pixel mask, 6.3.1).
pub type Mask = u64;

/// Every sample covered.
pub const FULL: Mask = u64::MAX;

/// Samples in a mask.
pub const SAMPLES: u32 = 64;

/// A pixel fragment (the sampling thesis, figure 6.6): the colour, the bit mask of the
/// samples the polygon covers, the least and greatest depth of the polygon at those
/// samples (smaller is nearer), the polygon's place in the frame's stream, which breaks
/// ties of depth as the z-buffer does (the earlier is in front), and its opacity (255
/// opaque; below, the fragment is transparent and what lies behind it shows through, 6.3.6
/// eq. 6.5).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fragment {
    pub colour: Colour,
    pub mask: Mask,
    pub zmin: crate::Depth,
    pub zmax: crate::Depth,
    pub order: u32,
    pub opacity: u8,
}

impl Fragment {
    /// Whether the fragment covers the whole pixel.
    #[inline]
    pub fn full(&self) -> bool {
        self.mask == FULL
    }

    /// Whether the fragment covers the whole pixel and hides what is behind it: full and
    /// opaque. Only such a fragment makes a simple pixelstruct or throws away the
    /// fragments behind it (6.3.4: "if a polygon is transparent, a list of fragments must
    /// be maintained").
    #[inline]
    pub fn solid(&self) -> bool {
        self.mask == FULL && self.opacity == proto::OPAQUE
    }

    /// The order of the sorted list: by zmin, then stream order, zmins within the tie
    /// rule's width of each other ([`proto::depth::takes`]: neither nearer by more than
    /// 2⁻³⁰ of the depth) counting as equal, so that of two such fragments the earlier
    /// polygon's comes first, as the z-buffer keeps the earlier at a tie.
    /// Whether this fragment comes before `other` in the sorted list.
    #[inline]
    fn before(&self, other: &Fragment) -> bool {
        let tied = !takes(self.zmin, other.zmin) && !takes(other.zmin, self.zmin);
        if tied && self.zmin.is_finite() && other.zmin.is_finite() {
            return self.order < other.order;
        }
        self.zmin
            .total_cmp(&other.zmin)
            .then(self.order.cmp(&other.order))
            .is_lt()
    }

    /// Whether the fragment lies wholly behind `front`, a fully covering opaque fragment,
    /// so that no sample of it can show (6.3.5: "throw away all the fragments behind fully
    /// covered, opaque fragments"), by the tie rule ([`proto::depth::takes`]): a later
    /// polygon's fragment whose nearest depth does not take a sample held at `front`'s
    /// farthest, or an earlier one's that `front`'s farthest takes from at its nearest.
    #[inline]
    fn behind(&self, front: &Fragment) -> bool {
        front.solid()
            && if self.order > front.order {
                !takes(self.zmin, front.zmax)
            } else {
                takes(front.zmax, self.zmin)
            }
    }

    /// Whether the fragment and `next` (its successor in the sorted list) cover one
    /// surface and combine (6.3.5, "combining fragments"): one colour, masks that do not
    /// overlap (the coverage rule gives a sample on a shared edge to one polygon only), and
    /// depths no further apart than either fragment's own depth extent (pieces of one
    /// surface meet where their depths meet; a fragment of one depth only combines with
    /// one of that depth). The seed combines fragments of one object; the stream has no
    /// objects, and this is the closest the fragments themselves can tell.
    #[inline]
    fn combines_with(&self, next: &Fragment) -> bool {
        let slack = (self.zmax - self.zmin).max(next.zmax - next.zmin);
        self.colour == next.colour
            && self.opacity == next.opacity
            && self.mask & next.mask == 0
            && next.zmin <= self.zmax + slack
    }

    /// The fragment that stands for `self` and `behind`, the next farther one, when a list
    /// is cut short: both masks; each sample the colour of the nearer fragment that
    /// covers it, so the colour is the mean over the merged mask with `self`'s samples in
    /// its colour and the rest in `behind`'s; the depth extent of both; `self`'s place.
    /// What the packer would have made of the pair's intersection is lost.
    pub fn merge_behind(&self, behind: &Fragment) -> Fragment {
        let mask = self.mask | behind.mask;
        let (near, far) = (
            self.mask.count_ones() as u64,
            (behind.mask & !self.mask).count_ones() as u64,
        );
        let total = (near + far).max(1);
        let mut colour = [0u8; 3];
        for (k, c) in colour.iter_mut().enumerate() {
            let sum = near * self.colour[k] as u64 + far * behind.colour[k] as u64;
            *c = ((sum + total / 2) / total) as u8;
        }
        Fragment {
            colour,
            mask,
            zmin: self.zmin.min(behind.zmin),
            zmax: self.zmax.max(behind.zmax),
            order: self.order,
            // A transparent pair cut short keeps the nearer one's opacity: what showed
            // through it is lost with the list's tail.
            opacity: self.opacity,
        }
    }

    /// The combined fragment: both masks, the depths of both, and the place in the list
    /// (zmin, then stream order) of the one nearer the front, so that the combined
    /// fragment keeps that one's place and the list stays sorted.
    #[inline]
    fn combine(&self, other: &Fragment) -> Fragment {
        let front = if !other.before(self) { self } else { other };
        Fragment {
            colour: self.colour,
            mask: self.mask | other.mask,
            zmin: front.zmin,
            zmax: self.zmax.max(other.zmax),
            order: front.order,
            opacity: self.opacity,
        }
    }
}

/// Counters of the insertion cases and the packer, for `--stats`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ListStats {
    /// Fragments inserted.
    pub fragments: u64,
    /// Fragments that were or became fully covering and went into an empty or simple
    /// pixelstruct as its only fragment: the fast path, no list.
    pub simple: u64,
    /// Pixelstructs that became lists.
    pub lists: u64,
    /// The longest list.
    pub max_list: u64,
    /// Fragments combined with a neighbour of the same surface.
    pub combined: u64,
    /// Fragments thrown away behind a fully covering one.
    pub hidden: u64,
    /// Intersecting fragments whose common samples the packer split by zmin/zmax.
    pub intersections: u64,
    /// Fragments merged into their neighbour because a list outgrew [`MAX_LIST`].
    pub merged: u64,
}

/// The longest a fragment list may grow. A longer one has its two farthest fragments
/// merged into one ([`Fragment::merge_behind`]): the seed (6.3.5) keeps lists short only by
/// combining fragments of one surface and throwing away those behind a fully covering
/// one, which does nothing for many small fragments at different depths (N tiny
/// triangles on one pixel: a list of N, and an insertion that costs N). 64, the samples
/// of a pixel: a list that long has, unless its fragments intersect in depth, at most 64
/// fragments that show at a sample.
pub const MAX_LIST: usize = 64;

/// A pixel of the a-buffer (the sampling thesis, figures 6.4 and 6.5): the thesis flags the kind by
/// the sign of its z; here it is the variant.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum PixelStruct {
    #[default]
    Empty,
    /// One fragment covering the whole pixel in front of everything else.
    Simple(Fragment),
    /// Fragments sorted by zmin (then stream order), none behind an earlier full one.
    List(Vec<Fragment>),
}

impl PixelStruct {
    /// Inserts a fragment (sampling thesis 6.3.4's six cases: a completely or partially covered
    /// incoming fragment into an empty, simple or list pixelstruct; 6.3.5's sorting,
    /// combining and throwing away). `pool` lends and takes back the lists' storage.
    pub fn insert(&mut self, f: Fragment, pool: &mut Vec<Vec<Fragment>>, stats: &mut ListStats) {
        stats.fragments += 1;
        match self {
            // Completely covered into empty: a simple pixelstruct. Partially covered into
            // empty: a list of one.
            PixelStruct::Empty => {
                if f.solid() {
                    stats.simple += 1;
                    *self = PixelStruct::Simple(f);
                } else {
                    let mut list = pool.pop().unwrap_or_default();
                    list.push(f);
                    stats.lists += 1;
                    stats.max_list = stats.max_list.max(1);
                    *self = PixelStruct::List(list);
                }
            }
            // Into a simple pixelstruct: nothing to do if the incoming fragment is behind
            // it; a fully covering one in front of it replaces it; otherwise the simple
            // pixelstruct becomes the head of a list and the incoming one is inserted.
            PixelStruct::Simple(s) => {
                let s = *s;
                if f.behind(&s) {
                    stats.hidden += 1;
                } else if f.solid() && s.behind(&f) {
                    stats.hidden += 1;
                    stats.simple += 1;
                    *self = PixelStruct::Simple(f);
                } else {
                    let mut list = pool.pop().unwrap_or_default();
                    list.push(s);
                    stats.lists += 1;
                    *self = PixelStruct::List(list);
                    self.insert_into_list(f, pool, stats);
                }
            }
            PixelStruct::List(_) => self.insert_into_list(f, pool, stats),
        }
    }

    /// Inserting into a list (6.3.5): sorted by zmin, combined with a neighbour of the
    /// same surface, thrown away if behind a full fragment, and everything behind a full
    /// fragment thrown away; a list headed by a full fragment becomes simple.
    fn insert_into_list(
        &mut self,
        f: Fragment,
        pool: &mut Vec<Vec<Fragment>>,
        stats: &mut ListStats,
    ) {
        let PixelStruct::List(list) = self else {
            return;
        };
        let pos = list.partition_point(|x| x.before(&f));
        if list[..pos].iter().any(|g| f.behind(g)) {
            stats.hidden += 1;
            return;
        }
        // Combine with the predecessor, or the successor, or take a place of its own.
        let mut at = if pos > 0 && list[pos - 1].combines_with(&f) {
            stats.combined += 1;
            list[pos - 1] = list[pos - 1].combine(&f);
            pos - 1
        } else if pos < list.len() && f.combines_with(&list[pos]) {
            stats.combined += 1;
            // f's key is the smaller: the combined fragment takes f's place, pos.
            list[pos] = f.combine(&list[pos]);
            pos
        } else {
            list.insert(pos, f);
            pos
        };
        // A combined fragment may now combine with the next one too.
        while at + 1 < list.len() && list[at].combines_with(&list[at + 1]) {
            stats.combined += 1;
            list[at] = list[at].combine(&list[at + 1]);
            list.remove(at + 1);
        }
        if at > 0 && list[at - 1].combines_with(&list[at]) {
            stats.combined += 1;
            list[at - 1] = list[at - 1].combine(&list[at]);
            list.remove(at);
            at -= 1;
        }
        let g = list[at];
        if g.solid() {
            let before = list.len();
            let mut k = 0;
            list.retain(|x| {
                k += 1;
                k <= at + 1 || !x.behind(&g)
            });
            stats.hidden += (before - list.len()) as u64;
        }
        while list.len() > MAX_LIST {
            if let (Some(far), Some(near)) = (list.pop(), list.last_mut()) {
                *near = near.merge_behind(&far);
                stats.merged += 1;
            }
        }
        stats.max_list = stats.max_list.max(list.len() as u64);
        if list.len() == 1 && list[0].solid() {
            let only = list[0];
            let mut list = std::mem::take(list);
            list.clear();
            pool.push(list);
            stats.simple += 1;
            *self = PixelStruct::Simple(only);
        }
    }

    /// The depth behind which every fragment is thrown away (6.3.5): the farthest depth
    /// of the nearest fully covering fragment; `+∞` when none covers the pixel.
    /// A fragment of a later polygon whose zmin is beyond it never enters the list.
    pub fn occluding_depth(&self) -> crate::Depth {
        match self {
            PixelStruct::Empty => f64::INFINITY,
            PixelStruct::Simple(f) => f.zmax,
            PixelStruct::List(list) => list
                .iter()
                .filter(|f| f.solid())
                .map(|f| f.zmax)
                .fold(f64::INFINITY, f64::min),
        }
    }

    /// The fragments, front to back.
    pub fn fragments(&self) -> &[Fragment] {
        match self {
            PixelStruct::Empty => &[],
            PixelStruct::Simple(f) => std::slice::from_ref(f),
            PixelStruct::List(list) => list,
        }
    }

    /// Empties the pixelstruct, giving its list's storage back to `pool`.
    pub fn clear(&mut self, pool: &mut Vec<Vec<Fragment>>) {
        if let PixelStruct::List(mut list) = std::mem::take(self) {
            list.clear();
            pool.push(list);
        }
    }

    /// The pixel's colour (6.3.6), `None` for an empty pixelstruct.
    pub fn pack(
        &self,
        background: Colour,
        scratch: &mut Packer,
        stats: &mut ListStats,
    ) -> Option<Colour> {
        match self {
            PixelStruct::Empty => None,
            // A simple pixelstruct needs no processing.
            PixelStruct::Simple(f) => Some(f.colour),
            PixelStruct::List(list) => Some(scratch.pack(list, background, stats)),
        }
    }
}

/// The fragment packer (the sampling thesis, 6.3.6), front to back with masks.
///
/// The sampling thesis's recursion C = P_i·A_i + T_i·Q_i, with the areas as masks
/// M_A_i = M_Q_{i+1} ∩ M_i (covered and visible) and M_Q_i = M_Q_{i+1} ∩ ¬M_i (visible and
/// not covered; M_Q at the front is the full mask, I), is evaluated as a walk down the
/// list carrying the still-visible region: fragment i paints the samples of M_A_i in its
/// colour and passes M_Q_i on; what is left after the last fragment shows the
/// background. Areas are counted in samples (6.3.6: "counting the percentage of on
/// bits"), so a list whose fragments do not intersect packs to exactly the 8×8
/// supersampled colour.
///
/// Intersecting fragments (Carpenter's a-buffer, which the sampling thesis follows): when the next
/// fragment's zmin is nearer than this one's zmax the two surfaces may cross inside the
/// pixel, and on the samples both cover the nearer one is not known. Taking both as
/// planes across the pixel, the share of this fragment in front is
/// f = (zmax_next − zmin_this) / ((zmax_this − zmin_this) + (zmax_next − zmin_next)):
/// those samples take f of this colour, and 1 − f of them go on to the next fragment
/// (and whatever shows through it). The visible regions stay disjoint, so at most 64
/// are carried, each with its weight; no recursion, so no list is too long to pack.
#[derive(Debug, Default)]
pub struct Packer {
    regions: Vec<(Mask, f64)>,
    next: Vec<(Mask, f64)>,
}

impl Packer {
    pub fn pack(&mut self, list: &[Fragment], background: Colour, stats: &mut ListStats) -> Colour {
        let mut sum = [0f64; 3];
        let paint = |sum: &mut [f64; 3], c: Colour, w: f64| {
            for (s, v) in sum.iter_mut().zip(c) {
                *s += w * v as f64;
            }
        };
        self.regions.clear();
        self.regions.push((FULL, 1.0));
        for (i, f) in list.iter().enumerate() {
            // The next fragment reaches in front of this one's far end by more than the
            // tie rule's width: their samples in common are shared by depth.
            let next = list.get(i + 1).filter(|n| takes(n.zmin, f.zmax));
            // f: this fragment's share of the samples both it and the next one cover.
            let share = next.map(|n| {
                let extent = (f.zmax - f.zmin) + (n.zmax - n.zmin);
                let front = (n.zmax - f.zmin) / extent;
                if front.is_finite() {
                    front.clamp(0.0, 1.0)
                } else {
                    0.5
                }
            });
            // Eq. 6.5: a transparent fragment's covered region is its colour times its
            // opacity, plus what lies behind it times the rest; so its samples are painted
            // with weight α and go on to the fragments behind with weight 1 − α.
            let alpha = f.opacity as f64 / proto::OPAQUE as f64;
            self.next.clear();
            for &(q, w) in &self.regions {
                let (a, out) = (q & f.mask, q & !f.mask);
                if out != 0 {
                    self.next.push((out, w));
                }
                match (next, share) {
                    (Some(n), Some(share)) if a & n.mask != 0 => {
                        let both = a & n.mask;
                        let only = a & !n.mask;
                        stats.intersections += 1;
                        paint(
                            &mut sum,
                            f.colour,
                            alpha
                                * w
                                * (only.count_ones() as f64 + share * both.count_ones() as f64),
                        );
                        if share * alpha < 1.0 {
                            self.next.push((both, w * (1.0 - share * alpha)));
                        }
                        if alpha < 1.0 && only != 0 {
                            self.next.push((only, w * (1.0 - alpha)));
                        }
                    }
                    _ => {
                        paint(&mut sum, f.colour, alpha * w * a.count_ones() as f64);
                        if alpha < 1.0 && a != 0 {
                            self.next.push((a, w * (1.0 - alpha)));
                        }
                    }
                }
            }
            std::mem::swap(&mut self.regions, &mut self.next);
            if self.regions.is_empty() {
                break;
            }
        }
        for &(q, w) in &self.regions {
            paint(&mut sum, background, w * q.count_ones() as f64);
        }
        // Nearest, halves up: for whole sums exactly (sum + 32) / 64.
        sum.map(|s| (s / SAMPLES as f64 + 0.5).floor().clamp(0.0, 255.0) as u8)
    }
}
