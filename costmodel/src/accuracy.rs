//! The model of accuracy: for each sampling mode of the z-buffer (`render --aa`), its RMS
//! error against the 16×16 reference (`zspec --samples 16`, 0–255 levels) and its share
//! of pixels wrong, predicted from the look ([`crate::look`]) and a cheap scan of the
//! scene's colours ([`Colours`]); and `render --max-error E`'s choice, the configuration
//! (sampling mode and depth) predicted cheapest among those predicted to meet E.
//!
//! The model is small on purpose. A point-sampled or supersampled frame differs from
//! the 16×16 reference only in pixels that an edge crosses (inside a flat polygon every
//! sample has the polygon's colour), and there by about the contrast across the edge
//! times the coverage the samples misjudge. So, for a mode m:
//!
//! - RMS_m = a_m · √(edge · contrast²), where `edge` is the edge pixels a screen pixel,
//!   by thesis 5.2's closed form (each of the P_r polygons in view a square of side
//!   H = √(X·Y·Dc/P_r), so 4·P_r·H = 4·√(P_r·X·Y·Dc) pixels of edge a frame, at most one a
//!   pixel), and `contrast²` the mean square colour difference, 0–1 a channel, between
//!   polygons that follow one another in the stream (neighbours in a mesh, strangers in
//!   a random environment) or a polygon and the black background, whichever is larger;
//! - wrong_m = b_m · edge: the share of pixels whose bytes differ from the reference.
//!
//! a_m and b_m are fitted to the chart's rows ([`fit`]) as the largest ratio of measured
//! to feature over the scenes fitted, so that the prediction is an upper bound on every
//! scene it was fitted on. `ss16` is the reference's own sampling (a 16×16 grid, a box
//! filter: `zspec --samples 16`'s bytes), so its a and b are 0, and so are `adaptive16`'s
//! on flat, opaque scenes, where `adaptiveK` gives `ssK`'s bytes. Under Gouraud or Phong
//! shading, or transparency, `adaptiveK` is left out (its difference from `ssK` there is
//! bounded but not modelled). The exact hidden-surface methods (scanline, warnock) give
//! the z-buffer's bytes, and the painter those or worse (cycles), so the modes here are
//! the z-buffer's, whose leaf the time model knows.

use crate::error::{Context, Result};
use crate::look::Environment;
use crate::model::{self, Constants, Target};
use proto::{Reader, Token};
use serde::{Deserialize, Serialize};
use std::io::Read;
use std::path::Path;

/// The sampling modes `--max-error` chooses among, cheapest first by samples a pixel.
pub const MODES: [&str; 10] = [
    "none",
    "adaptive2",
    "ss2",
    "adaptive4",
    "ss4",
    "abuf",
    "adaptive8",
    "ss8",
    "adaptive16",
    "ss16",
];

/// The safe choice: the reference's own sampling, 0 error on any scene.
pub const SAFE: &str = "ss16";

/// The budgets `plan accuracy` reports, `plan max-error-check` tries and the chart marks
/// on its speed-accuracy panels (RMS, 0–255 levels).
pub const BUDGETS: [f64; 4] = [0.0, 1.0, 4.0, 16.0];

/// The deepest tree `--max-error` considers.
pub const MAX_DEPTH: u8 = 6;

/// K of `ssK` or `adaptiveK` (1 for none; abuf's 8×8 mask counts as 8).
pub fn samples(mode: &str) -> u32 {
    let k = mode
        .strip_prefix("ss")
        .or_else(|| mode.strip_prefix("adaptive"))
        .and_then(|k| k.parse().ok());
    match (mode, k) {
        (_, Some(k)) => k,
        ("abuf", _) => 8,
        _ => 1,
    }
}

/// What the colour scan of a scene says ([`Colours::scan`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Colours {
    /// Polygons scanned.
    pub polygons: u64,
    /// The mean square colour difference, 0–1 a channel, across an edge pixel of the
    /// closed form's count ([`edge_fraction`]): what the error of a misjudged edge pixel
    /// is made of. An edge no other polygon shares (a random environment's) counts the
    /// contrast between successive polygons, or a quarter of a polygon's against the
    /// black background, whichever is larger; an edge two polygons of a mesh share is
    /// one line where the closed form counts two, and shows the colour difference across
    /// it, except on the mesh's silhouette, where it shows the polygon against what is
    /// behind it (taken as the background).
    pub contrast2: f64,
    /// Whether every polygon scanned is one flat opaque colour.
    pub flat: bool,
    /// Polygon edges scanned that no other polygon scanned shares.
    pub open_edges: u64,
    /// Edges two polygons share (each counted once).
    pub shared_edges: u64,
    /// The mean square colour difference, 0–1 a channel, across the shared edges.
    pub across2: f64,
    /// The share of the shared edges' pixels on a silhouette: 1.25·√(meshes/polygons in
    /// them) (a mesh of n polygons seen as a disc of area A: 2√(πA) pixels of silhouette
    /// against 2·√(n·A) of shared edge; at most 1).
    pub silhouette: f64,
    /// `contrast2`'s two parts: the mean square difference across an open edge's pixel
    /// (between strangers), and across a shared edge's (the mesh's colours, or its
    /// silhouette against the background); `contrast2` is their sum weighted by
    /// [`Colours::open_share`] and [`Colours::shared_share`].
    pub open2: f64,
    pub shared2: f64,
}

impl Colours {
    /// The share of the closed form's edge pixels on open edges (a shared edge counts
    /// twice there, as the two polygons' edges it is): 1 where no edge was scanned.
    pub fn open_share(&self) -> f64 {
        match self.open_edges + 2 * self.shared_edges {
            0 => 1.0,
            counted => self.open_edges as f64 / counted as f64,
        }
    }

    /// The share of the closed form's edge pixels that shared edges draw: half those it
    /// counts for them, a shared edge being one line where it counts two.
    pub fn shared_share(&self) -> f64 {
        match self.open_edges + 2 * self.shared_edges {
            0 => 0.0,
            counted => self.shared_edges as f64 / counted as f64,
        }
    }
}

/// The scan's key of an edge: its ends' keys ([`vertex_key`]), the lesser first.
type EdgeKey = ([i64; 3], [i64; 3]);

/// The scan's key of a world vertex: its coordinates to a millionth.
fn vertex_key(v: &proto::polygon::Vertex) -> [i64; 3] {
    [v.x, v.y, v.z].map(|c| (c * 1.0e6).round() as i64)
}

/// The mean square difference, 0–1 a channel, of two colours given 0–255.
fn square_difference(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|i| ((a[i] - b[i]) / 255.0).powi(2)).sum::<f64>() / 3.0
}

/// Union-find's root of `i`, halving the path.
fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

impl Colours {
    /// Scans the polygons of a world-space stream (at most `limit` bytes of it; a
    /// record cut there ends the scan).
    pub fn scan<R: Read>(input: R, limit: u64) -> Result<Colours> {
        let mut reader = Reader::<Token, _>::new(std::io::BufReader::new(input.take(limit)))
            .context("reading the scene's colours")?;
        let mut scan = ColourScan::new(reader.header().attributes.vertex_colours);
        let mut record = Token::default();
        loop {
            match reader.next_into(&mut record) {
                Ok(true) => {}
                Ok(false) => break,
                Err(_) if scan.n > 0 => break,
                Err(e) => return Err(e).context("reading the scene's colours"),
            }
            if let Token::Polygon(p) = &record {
                scan.add(p);
            }
        }
        Ok(scan.finish())
    }
}

/// [`Colours::scan`]'s work a polygon at a time, so that the look can feed it the
/// polygons it reads ([`Seen::of`]).
pub struct ColourScan {
    gouraud: bool,
    n: u64,
    successive: f64,
    background: f64,
    flat: bool,
    last: Option<[f64; 3]>,
    /// Each edge seen once: (the polygon, its colour there); shared ones are removed.
    edges: std::collections::HashMap<EdgeKey, (usize, [f64; 3])>,
    shared: u64,
    across: f64,
    /// Union-find over the polygons: the meshes their shared edges join.
    parent: Vec<usize>,
}

impl ColourScan {
    /// A scan of a stream whose polygons carry vertex colours when `gouraud`.
    pub fn new(gouraud: bool) -> ColourScan {
        ColourScan {
            gouraud,
            n: 0,
            successive: 0.0,
            background: 0.0,
            flat: true,
            last: None,
            edges: std::collections::HashMap::new(),
            shared: 0,
            across: 0.0,
            parent: Vec::new(),
        }
    }

    /// One more polygon of the stream, in its order.
    pub fn add(&mut self, p: &proto::Polygon) {
        let gouraud = self.gouraud;
        self.flat &= p.vertex_attrs.is_empty() && p.opacity == 255;
        // The colour it shows: under Gouraud shading its vertices' mean.
        let c = match (gouraud, p.vertex_attrs.len()) {
            (true, k) if k > 0 => {
                let sum = p
                    .vertex_attrs
                    .iter()
                    .fold(proto::DVec3::ZERO, |s, a| s + *a);
                (sum / k as f64).to_array()
            }
            _ => p.colour.map(f64::from),
        };
        if let Some(l) = self.last {
            self.successive += square_difference(c, l);
        }
        self.background += square_difference(c, [0.0; 3]);
        self.last = Some(c);
        let me = self.parent.len();
        self.parent.push(me);
        let m = p.vertices.len();
        for i in 0..m {
            let j = (i + 1) % m;
            let (a, b) = (vertex_key(&p.vertices[i]), vertex_key(&p.vertices[j]));
            if a == b {
                continue;
            }
            // The colour along the edge: under Gouraud shading its ends' mean.
            let colour = match (gouraud, p.vertex_attrs.get(i), p.vertex_attrs.get(j)) {
                (true, Some(u), Some(v)) => {
                    [(u.x + v.x) / 2.0, (u.y + v.y) / 2.0, (u.z + v.z) / 2.0]
                }
                _ => c,
            };
            let key = if a < b { (a, b) } else { (b, a) };
            match self.edges.remove(&key) {
                Some((other, theirs)) => {
                    self.shared += 1;
                    self.across += square_difference(colour, theirs);
                    let (r1, r2) = (root(&mut self.parent, me), root(&mut self.parent, other));
                    self.parent[r1] = r2;
                }
                None => {
                    self.edges.insert(key, (me, colour));
                }
            }
        }
        self.n += 1;
    }

    /// The scan's measures of the polygons added.
    pub fn finish(mut self) -> Colours {
        let n = self.n;
        let open = self.edges.len() as u64;
        // The meshes: sets of two or more polygons joined by shared edges.
        let mut size = vec![0u64; self.parent.len()];
        for i in 0..self.parent.len() {
            let r = root(&mut self.parent, i);
            size[r] += 1;
        }
        let (meshes, in_meshes) = size
            .iter()
            .filter(|s| **s >= 2)
            .fold((0u64, 0u64), |(k, t), s| (k + 1, t + s));
        let mean = |s: f64, k: u64| if k == 0 { 0.0 } else { s / k as f64 };
        let unshared =
            mean(self.successive, n.saturating_sub(1)).max(mean(self.background, n) / 4.0);
        let across2 = mean(self.across, self.shared);
        let silhouette = if in_meshes == 0 {
            0.0
        } else {
            (1.25 * (meshes as f64 / in_meshes as f64).sqrt()).min(1.0)
        };
        let shared2 = (1.0 - silhouette) * across2 + silhouette * mean(self.background, n);
        let mut c = Colours {
            polygons: n,
            contrast2: 0.0,
            flat: self.flat,
            open_edges: open,
            shared_edges: self.shared,
            across2,
            silhouette,
            open2: unshared,
            shared2,
        };
        c.contrast2 = c.open_share() * unshared + c.shared_share() * shared2;
        c
    }
}

/// A scene file as `--max-error` sees it: the look at it on its screen and the scan of
/// its colours, each over its first [`crate::look::LOOK_BYTES`].
#[derive(Clone, Debug, PartialEq)]
pub struct Seen {
    pub env: Environment,
    pub colours: Colours,
}

impl Seen {
    /// The scene file `path` on a `width`×`height` screen through `camera` (viewxf's
    /// options, as [`crate::look::look`] takes them); `None` where the look or the colour
    /// scan cannot read it.
    ///
    /// One pass: the look hands the colour scan each polygon it reads, so the file is
    /// read and parsed once (the two passes it took before were half of `render
    /// --max-error`'s look).
    pub fn of(path: &Path, width: u32, height: u32, camera: &[String]) -> Option<Seen> {
        let limit = crate::look::LOOK_BYTES;
        let mut scan: Option<ColourScan> = None;
        let env = crate::look::look_each(path, width, height, camera, Some(limit), &mut |a, p| {
            scan.get_or_insert_with(|| ColourScan::new(a.vertex_colours))
                .add(p)
        })
        .ok()?;
        let colours = scan.unwrap_or_else(|| ColourScan::new(false)).finish();
        Some(Seen { env, colours })
    }
}

/// `render --max-error E`'s choice on a seen scene: every allowed configuration
/// predicted ([`Accuracy::predict_all`], trees to [`MAX_DEPTH`]) and the cheapest of those
/// predicted to meet `max_error` ([`cheapest`]); `None` where none is. The chart marks the
/// same choice on its panels.
pub fn choose(
    model: &Accuracy,
    k: &Constants,
    seen: &Seen,
    target: &Target,
    max_error: f64,
) -> Option<Predicted> {
    let all = model.predict_all(k, &seen.env, &seen.colours, target, MAX_DEPTH);
    cheapest(&all, max_error).cloned()
}

/// The visible edge pixels a screen pixel (0–1), by thesis 5.2's closed form: each of
/// the P_r polygons in view a square of side H = √(X·Y·Dc/P_r), 4·P_r·H = 4·√(P_r·X·Y·Dc)
/// pixels of edge a frame, of which a pixel covered Dc times shows one polygon's: over
/// the screen, 4/H where Dc ≥ 1.
pub fn edge_fraction(env: &Environment) -> f64 {
    if env.frames == 0 || env.screen() == 0.0 {
        return 0.0;
    }
    let all = 4.0 * env.spans() / (env.frames as f64 * env.screen());
    (all / env.depth_complexity().max(1.0)).min(1.0)
}

/// The fitted coefficients, a mode each: RMS_m = √(edge·(w_o·a²·open² + w_s·a_s²·shared²))
/// (w_o and w_s the open and the shared edges' shares of the edge pixels,
/// [`Colours::open_share`]; with one coefficient for both, a·√(edge·contrast²)),
/// wrong_m = b·edge.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Accuracy {
    /// Where they were fitted (the command, the scenes).
    pub fitted_on: String,
    pub modes: Vec<ModeFit>,
}

/// One mode's coefficients.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModeFit {
    pub aa: String,
    /// RMS (0–255) per unit of √(edge·contrast²) on open edges (a random
    /// environment's), and on shared ones (a mesh's); a fit without the second (an
    /// older accuracy.toml) uses the first for both.
    pub rms: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rms_shared: Option<f64>,
    /// Pixels wrong per edge pixel.
    pub wrong: f64,
    /// The leaf's work a covered pixel, in point samples' (1 for none, K² for ssK).
    pub samples: f64,
}

/// What the model predicts of one configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct Predicted {
    pub aa: String,
    pub depth: u8,
    pub seconds: f64,
    /// RMS error against the 16×16 reference, 0–255.
    pub rms: f64,
    /// Share of pixels wrong, 0–1.
    pub wrong: f64,
}

/// One measured row the fit reads: the scene's features and a mode's measured error.
#[derive(Clone, Debug, PartialEq)]
pub struct Measured {
    pub aa: String,
    pub edge: f64,
    pub colours: Colours,
    pub rms: f64,
    pub wrong: f64,
}

impl Accuracy {
    /// The repository's coefficients (bench/accuracy.toml), fitted by `plan accuracy
    /// --fit` on generated scenes none of which the check uses.
    pub fn committed() -> Accuracy {
        toml::from_str(include_str!("../../bench/accuracy.toml"))
            .expect("bench/accuracy.toml is the model's own")
    }

    pub fn to_toml(&self) -> Result<String> {
        Ok(toml::to_string(self)?)
    }

    pub fn parse(text: &str) -> Result<Accuracy> {
        Ok(toml::from_str(text)?)
    }

    /// The fit this machine's cache holds (`accuracy.toml` beside model.toml), else the
    /// repository's.
    pub fn load() -> Accuracy {
        crate::cache::dir()
            .and_then(|d| std::fs::read_to_string(d.join("accuracy.toml")).ok())
            .and_then(|t| Accuracy::parse(&t).ok())
            .unwrap_or_else(Accuracy::committed)
    }

    fn mode(&self, aa: &str) -> Option<&ModeFit> {
        self.modes.iter().find(|m| m.aa == aa)
    }

    /// The predicted RMS and share of pixels wrong of `aa` on a scene; `None` for a mode
    /// the fit has no row for.
    pub fn error(&self, aa: &str, edge: f64, colours: &Colours) -> Option<(f64, f64)> {
        let m = self.mode(aa)?;
        let (a, a_shared) = (m.rms, m.rms_shared.unwrap_or(m.rms));
        let square = colours.open_share() * a * a * colours.open2
            + colours.shared_share() * a_shared * a_shared * colours.shared2;
        Some(((edge * square).sqrt(), m.wrong * edge))
    }

    /// The modes that may run on a scene: adaptiveK only on flat opaque ones.
    pub fn allowed<'a>(&'a self, colours: &'a Colours) -> impl Iterator<Item = &'a ModeFit> {
        self.modes
            .iter()
            .filter(move |m| colours.flat || !m.aa.starts_with("adaptive"))
    }

    /// Every allowed configuration's prediction: each mode at every depth the tree
    /// allows (from the target's least to `max_depth`), timed by the time model: `none`
    /// by [`model::predict_on`], an anti-aliasing mode by [`mode_time`] (at depth 0 in
    /// the merger's one process, deeper its leaves processes of their own, as render
    /// runs them) on the scene with its covered pixels times the mode's samples, the
    /// leaf's work that sampling multiplies.
    pub fn predict_all(
        &self,
        k: &Constants,
        env: &Environment,
        colours: &Colours,
        target: &Target,
        max_depth: u8,
    ) -> Vec<Predicted> {
        let edge = edge_fraction(env);
        let least = target.min_depth().min(max_depth);
        self.allowed(colours)
            .flat_map(|m| {
                let samples = self.effective_samples(m, edge);
                let (rms, wrong) = self.error(&m.aa, edge, colours).unwrap_or((0.0, 0.0));
                (least..=max_depth).map(move |depth| Predicted {
                    aa: m.aa.clone(),
                    depth,
                    seconds: mode_time(k, env, &m.aa, samples, depth, target),
                    rms,
                    wrong,
                })
            })
            .collect()
    }
}

impl Accuracy {
    /// A mode's leaf work a covered pixel, in point samples: its fitted samples, and for
    /// `adaptiveK` one sample in the interior and its fitted K² in the edge pixels, at
    /// most `ssK`'s (it samples no pixel more than `ssK` does; the edge pixels the closed
    /// form counts are not all those an edge touches, so the fit's factor an edge pixel
    /// is large, and uncapped it ranks `adaptiveK` behind `ssK` on scenes of many edges,
    /// where `plan max-error-check` measured it several times faster).
    fn effective_samples(&self, m: &ModeFit, edge: f64) -> f64 {
        match m.aa.strip_prefix("adaptive") {
            Some(k) => {
                let adaptive = 1.0 + (m.samples - 1.0) * edge;
                self.mode(&format!("ss{k}"))
                    .map_or(adaptive, |ss| adaptive.min(ss.samples))
            }
            None => m.samples,
        }
    }
}

/// The predicted time of mode `aa` at `depth` on a scene, its covered pixels costing
/// `samples` point samples each: `none` as the point-sampled z-buffer runs
/// ([`model::predict_on`]: at depth 0 one `zbuf --project`, deeper zbuf resolving leaf
/// 0); any other mode at depth 0 as `none` plus its leaf's samples beyond one a covered
/// pixel (render runs it in the same one process, `zbuf --project --aa MODE`), deeper
/// with its leaves apart ([`model::predict_sampled`]), at the leaves' rate a sample at
/// every depth. With one layout for all depths, a leaf's processes were priced as
/// samples, on screens of every size alike, and `--max-error` chose depth 0 for the
/// sampling modes where depth 1 was 1.3–1.6 times faster on 250×250 and 500×500 frames.
pub fn mode_time(
    k: &Constants,
    env: &Environment,
    aa: &str,
    samples: f64,
    depth: u8,
    target: &Target,
) -> f64 {
    let point = model::predict_on(k, env, depth, target).total_s;
    if aa == "none" {
        return point;
    }
    let scaled = Environment {
        area: env.area * samples,
        ..*env
    };
    if depth == 0 && target.hosts.is_none() {
        // render runs the leaf's method in `zbuf --project --aa MODE` (its graph's
        // `merger_is_aa_leaf`): `none`'s one process, its leaf's work `samples` times a
        // covered pixel's where `none`'s is one, at the leaves' rate.
        let one = model::predict_sampled(k, env, 0, target).total_s;
        let many = model::predict_sampled(k, &scaled, 0, target).total_s;
        return point + (many - one).max(0.0);
    }
    // A sampling mode does all that `none` does at the same depth and more, so it costs at
    // least that: on a tiny scene the model's two cores otherwise spread the layout's five
    // short stages below `none`'s one `zbuf --project` doing persp's work and the
    // leaf's (the penetrating polygons at 120×90 chose adaptive2 over `none` for E = 16
    // on one calibration).
    model::predict_sampled(k, &scaled, depth, target)
        .total_s
        .max(point)
}

/// The samples a covered pixel that make an anti-aliasing mode's predicted depth-0 time
/// ([`mode_time`]) `ratio` times the point-sampled one's: a mode's `samples`, from a
/// measured ratio of its time to `none`'s on the scene (bisection; 1 when its two
/// processes more alone pass the ratio).
pub fn samples_for_ratio(k: &Constants, env: &Environment, target: &Target, ratio: f64) -> f64 {
    let time = |s: f64| mode_time(k, env, "ss", s, 0, target);
    let want = mode_time(k, env, "none", 1.0, 0, target) * ratio;
    let (mut lo, mut hi) = (1.0f64, 1.0e5f64);
    if time(1.0) >= want || env.area <= 0.0 {
        return 1.0;
    }
    for _ in 0..60 {
        let mid = (lo * hi).sqrt();
        if time(mid) < want {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// The configuration predicted cheapest among those predicted to meet `max_error`
/// (`predicted`: [`Accuracy::predict_all`]); with `max_error` 0 only a mode of the
/// reference's own bytes (rms 0) qualifies. `None` when none is predicted to meet it.
///
/// A tie goes to `ssK` over `adaptiveK`: the two tie only where adaptiveK's time is held
/// at ssK's (the cap of `Accuracy::effective_samples`), that is where the model sees no
/// saving in it; and there `plan max-error-check` measured adaptive2 at 1.5× ss2's time.
pub fn cheapest(predicted: &[Predicted], max_error: f64) -> Option<&Predicted> {
    let adaptive = |p: &Predicted| p.aa.starts_with("adaptive");
    predicted
        .iter()
        .filter(|p| p.rms <= max_error)
        .min_by(|a, b| {
            a.seconds
                .total_cmp(&b.seconds)
                .then(adaptive(a).cmp(&adaptive(b)))
        })
}

/// Fits each mode's coefficients to measured rows: the largest ratio of measured to
/// feature over the rows (an upper envelope, so that every fitted scene is predicted at
/// or above its measured error); a mode of 0 error everywhere (ss16) gets 0. The RMS has
/// two envelopes: over the rows whose edge pixels are mostly on open edges (random
/// environments) and over the others (meshes), each the other's where a class has no
/// row, since a mode's error falls with K differently on the two (a mesh's shared edges
/// show little contrast, its silhouette much). `samples_of` gives each mode's factor on
/// the covered pixels ([`samples_for_ratio`]).
pub fn fit(rows: &[Measured], fitted_on: &str, samples_of: impl Fn(&str) -> f64) -> Accuracy {
    let envelope = |rows: &[&Measured], num: fn(&Measured) -> f64, den: fn(&Measured) -> f64| {
        rows.iter()
            .filter(|r| den(r) > 0.0)
            .map(|r| num(r) / den(r))
            .fold(0.0, f64::max)
    };
    let rms = |r: &Measured| r.rms;
    let unit = |r: &Measured| (r.edge * r.colours.contrast2).sqrt();
    let modes = MODES
        .iter()
        .filter_map(|aa| {
            let mine: Vec<&Measured> = rows.iter().filter(|r| r.aa == *aa).collect();
            if mine.is_empty() {
                return None;
            }
            let (open, shared): (Vec<&Measured>, Vec<&Measured>) =
                mine.iter().partition(|r| r.colours.open_share() >= 0.5);
            let class = |rows: &[&Measured], other: &[&Measured]| match rows.is_empty() {
                true => envelope(other, rms, unit),
                false => envelope(rows, rms, unit),
            };
            Some(ModeFit {
                aa: aa.to_string(),
                rms: class(&open, &shared),
                rms_shared: Some(class(&shared, &open)),
                wrong: envelope(&mine, |r| r.wrong, |r| r.edge),
                samples: samples_of(aa),
            })
        })
        .collect();
    Accuracy {
        fitted_on: fitted_on.to_string(),
        modes,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn colours(contrast2: f64, flat: bool) -> Colours {
        Colours {
            polygons: 10,
            contrast2,
            open2: contrast2,
            flat,
            ..Colours::default()
        }
    }

    #[test]
    fn samples_of_each_mode() {
        let k: Vec<u32> = MODES.iter().map(|m| samples(m)).collect();
        assert_eq!(k, [1, 2, 2, 4, 4, 8, 8, 8, 16, 16]);
    }

    #[test]
    fn the_fit_is_the_upper_envelope_and_ss16_is_exact() {
        let row = |aa: &str, edge: f64, rms: f64, wrong: f64| Measured {
            aa: aa.into(),
            edge,
            colours: colours(0.25, true),
            rms,
            wrong,
        };
        let rows = [
            row("none", 0.16, 4.0, 0.08), // √(0.04) = 0.2: 20 a unit, 0.5 an edge pixel
            row("none", 0.04, 3.0, 0.028), // √(0.01) = 0.1: 30 a unit, 0.7
            row("ss16", 0.16, 0.0, 0.0),
        ];
        let a = fit(&rows, "test", |aa| f64::from(samples(aa)).powi(2));
        assert_eq!(a.modes.len(), 2);
        let none = &a.modes[0];
        assert_eq!((none.aa.as_str(), none.samples), ("none", 1.0));
        assert!((none.rms - 30.0).abs() < 1e-9, "{}", none.rms);
        assert!((none.wrong - 0.7).abs() < 1e-9, "{}", none.wrong);
        assert_eq!(
            (a.modes[1].rms, a.modes[1].wrong, a.modes[1].samples),
            (0.0, 0.0, 256.0)
        );
        // Every fitted row is predicted at or above what was measured.
        for r in &rows {
            let (rms, wrong) = a.error(&r.aa, r.edge, &colours(0.25, true)).unwrap();
            assert!(rms >= r.rms - 1e-9 && wrong >= r.wrong - 1e-9);
        }
        let back = Accuracy::parse(&a.to_toml().unwrap()).unwrap();
        assert_eq!(back, a);
    }

    #[test]
    fn open_and_shared_edges_have_envelopes_of_their_own() {
        // An environment's open edges and a mesh's shared ones: a ss4 error of 0.2 units
        // on the first and 0.5 on the second.
        let env = Colours {
            open_edges: 100,
            open2: 0.25,
            contrast2: 0.25,
            ..colours(0.25, true)
        };
        // A shared edge is one line where the closed form counts two: half the weight.
        let mesh = Colours {
            shared_edges: 100,
            open2: 0.0,
            shared2: 0.08,
            contrast2: 0.04,
            ..colours(0.04, true)
        };
        assert_eq!((env.open_share(), mesh.open_share()), (1.0, 0.0));
        let row = |colours: Colours, rms: f64| Measured {
            aa: "ss4".into(),
            edge: 0.16,
            colours,
            rms,
            wrong: 0.1,
        };
        // √(0.16·0.25) = 0.2, √(0.16·0.04) = 0.08.
        let rows = [row(env, 0.2 * 10.0), row(mesh, 0.08 * 25.0)];
        let a = fit(&rows, "test", |_| 16.0);
        let m = &a.modes[0];
        assert!((m.rms - 10.0).abs() < 1e-9, "{m:?}");
        assert!((m.rms_shared.unwrap() - 25.0).abs() < 1e-9, "{m:?}");
        // Each predicted exactly; half of each kind of edge pixel, the mean square.
        for r in &rows {
            let (rms, _) = a.error("ss4", r.edge, &r.colours).unwrap();
            assert!((rms - r.rms).abs() < 1e-9, "{rms} {}", r.rms);
        }
        let half = Colours {
            open_edges: 100,
            shared_edges: 50,
            ..Colours {
                shared2: 0.08,
                ..env
            }
        };
        let (rms, _) = a.error("ss4", 0.16, &half).unwrap();
        let want = (0.16f64 * (0.5 * 100.0 * 0.25 + 0.25 * 625.0 * 0.08)).sqrt();
        assert!((rms - want).abs() < 1e-9, "{rms} {want}");
        // One class alone: its envelope serves both; an older fit without the second
        // coefficient reads as one for both.
        let only = fit(&rows[..1], "test", |_| 16.0);
        assert_eq!(only.modes[0].rms_shared, Some(only.modes[0].rms));
        let old =
            "fitted_on = \"x\"\n[[modes]]\naa = \"ss4\"\nrms = 10.0\nwrong = 0.5\nsamples = 16.0\n";
        let old = Accuracy::parse(old).unwrap();
        let (rms, _) = old.error("ss4", 0.16, &mesh).unwrap();
        assert!((rms - 10.0 * 0.08).abs() < 1e-9, "{rms}");
    }

    #[test]
    fn the_edge_fraction_is_the_closed_form_at_most_one() {
        // 512 squares tiling 500×500: sides of 22.1 px, 4·√(512·250000) = 45,255 px.
        let env = Environment {
            frames: 1,
            relevant: 512,
            area: 250_000.0,
            width: 500,
            height: 500,
            ..Default::default()
        };
        assert!((edge_fraction(&env) - 0.181).abs() < 0.001);
        let tiny = Environment {
            relevant: 100_000,
            ..env
        };
        assert_eq!(edge_fraction(&tiny), 1.0);
        // Stacked four deep: a quarter of the edges show (4/H, H = √(4·250000/512)).
        let deep = Environment {
            area: 1_000_000.0,
            ..env
        };
        assert!((edge_fraction(&deep) - 4.0 / (1_000_000.0f64 / 512.0).sqrt()).abs() < 1e-9);
        assert_eq!(edge_fraction(&Environment::default()), 0.0);
    }

    #[test]
    fn the_colour_scan_reads_contrast_and_shading() {
        let text = "polypipe 1 world\ncolour 255 0 0\n0 0 0\n1 0 0\n0 1 0\nNEXT.POLYGON\n\
                    colour 0 0 0\n5 5 0\n6 5 0\n5 6 0\nNEXT.POLYGON\n";
        let c = Colours::scan(text.as_bytes(), 1 << 20).unwrap();
        assert_eq!((c.polygons, c.shared_edges, c.open_edges), (2, 0, 6));
        assert!(c.flat);
        // Successive: (1² + 0 + 0)/3 once; background: (1/3 + 0)/2 / 4.
        assert!((c.contrast2 - 1.0 / 3.0).abs() < 1e-9, "{}", c.contrast2);
    }

    #[test]
    fn the_colour_scan_finds_shared_edges_and_weighs_them_as_one_line() {
        // Two triangles of one mesh sharing the edge (1,0,0)–(0,1,0): 1 shared, 4 open.
        let text = "polypipe 1 world\ncolour 200 0 0\n0 0 0\n1 0 0\n0 1 0\nNEXT.POLYGON\n\
                    colour 100 0 0\n1 0 0\n1 1 0\n0 1 0\nNEXT.POLYGON\n";
        let c = Colours::scan(text.as_bytes(), 1 << 20).unwrap();
        assert_eq!((c.polygons, c.shared_edges, c.open_edges), (2, 1, 4));
        // Across the shared edge: (100/255)²/3.
        assert!((c.across2 - 0.051_262_335).abs() < 1e-8, "{}", c.across2);
        // One mesh of two polygons: 1.25·√(1/2).
        assert!(
            (c.silhouette - 0.883_883_476).abs() < 1e-8,
            "{}",
            c.silhouette
        );
        // (4 open × 0.0513 + 1 shared × (0.116·0.0513 + 0.884·0.1282)) / (4 + 2·1).
        assert!(
            (c.contrast2 - 0.054_046_095).abs() < 1e-8,
            "{}",
            c.contrast2
        );
        // A fine mesh of near colours: its edges count little contrast (its open rim
        // most of it), against the 0.063 (a quarter of theirs against black) the same
        // polygons would count as strangers.
        let mut fine = String::from("polypipe 1 world\n");
        for i in 0..20 {
            for j in 0..20 {
                let g = 128 + (i + j) % 3;
                fine += &format!(
                    "colour {g} {g} {g}\n{i} {j} 0\n{} {j} 0\n{} {} 0\n{i} {} 0\nNEXT.POLYGON\n",
                    i + 1,
                    i + 1,
                    j + 1,
                    j + 1
                );
            }
        }
        let c = Colours::scan(fine.as_bytes(), 1 << 20).unwrap();
        assert_eq!((c.polygons, c.shared_edges, c.open_edges), (400, 760, 80));
        assert!((c.silhouette - 0.0625).abs() < 1e-12, "{}", c.silhouette);
        assert!((c.contrast2 - 0.0108).abs() < 1e-4, "{}", c.contrast2);
    }

    #[test]
    fn the_one_pass_look_sees_what_the_look_and_the_scan_saw_apart() {
        use std::io::Write;
        // Generated scenes: meshes of shared edges (flat and Gouraud), strangers, and one
        // past the look's limit, whose last record is cut there.
        let mut seed = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % 1000
        };
        for (polygons, gouraud, mesh) in [
            (50, false, true),
            (200, true, true),
            (300, false, false),
            (4000, true, false),
        ] {
            let mut text = format!(
                "polypipe 1 world{}\n",
                if gouraud { " vertex-colours" } else { "" }
            );
            for q in 0..polygons {
                text += &format!(
                    "colour {} {} {}\n",
                    next() % 256,
                    next() % 256,
                    next() % 256
                );
                let (x, y) = if mesh {
                    ((q % 10) as f64, (q / 10) as f64)
                } else {
                    (next() as f64 / 50.0, next() as f64 / 50.0)
                };
                // A mesh's quads share their edges: one plane.
                let z = if mesh {
                    -6.0
                } else {
                    -5.0 - next() as f64 / 100.0
                };
                for (dx, dy) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
                    text += &format!("{} {} {z}", x + dx - 5.0, y + dy - 5.0);
                    if gouraud {
                        text += &format!(" {} {} {}", next() % 256, next() % 256, next() % 256);
                    }
                    text += "\n";
                }
                text += if q + 1 == polygons {
                    "END\n"
                } else {
                    "NEXT.POLYGON\n"
                };
            }
            let mut f = tempfile::NamedTempFile::new().unwrap();
            f.write_all(text.as_bytes()).unwrap();
            let limit = crate::look::LOOK_BYTES;
            assert_eq!(polygons == 4000, text.len() as u64 > limit);
            let seen = Seen::of(f.path(), 200, 200, &[]).unwrap();
            let apart = Seen {
                env: crate::look::look(f.path(), 200, 200, &[], Some(limit)).unwrap(),
                colours: Colours::scan(crate::look::open(f.path()).unwrap(), limit).unwrap(),
            };
            assert_eq!(seen, apart, "{polygons} polygons");
            assert_eq!(seen.colours.flat, !gouraud);
            assert_eq!(seen.colours.shared_edges > 0, mesh);
            assert!(seen.colours.polygons > 0);
        }
    }

    #[test]
    fn a_sampling_mode_is_never_predicted_below_point_sampling() {
        // Two penetrating polygons at 120×90, on a calibration whose one-process z-buffer
        // starts slowly: the sampling layout's stages, each short, spread over two cores
        // below it, and the floor holds every mode at `none`'s time.
        let mut k = Constants::committed();
        k.resolve.process = 4.0 * k.merge.process.max(1e-4);
        let env = Environment {
            polygons: 2,
            vertices: 7,
            relevant: 2,
            relevant_vertices: 7,
            ..quads(2, 100)
        };
        let t = Target::cores(2);
        let none = mode_time(&k, &env, "none", 1.0, 0, &t);
        let scaled = Environment {
            area: env.area * 2.0,
            ..env
        };
        assert!(model::predict_sampled(&k, &scaled, 0, &t).total_s < none);
        for depth in 0..=2 {
            let point = mode_time(&k, &env, "none", 1.0, depth, &t);
            for (aa, samples) in [("adaptive2", 2.0), ("ss4", 30.0), ("abuf", 60.0)] {
                assert!(
                    mode_time(&k, &env, aa, samples, depth, &t) >= point,
                    "{aa} {depth}"
                );
            }
        }
        // A tie at the floor goes to `none`, first in MODES.
        let a = Accuracy::committed();
        let all = a.predict_all(&k, &env, &colours(0.01, true), &t, 2);
        assert_eq!(cheapest(&all, 255.0).unwrap().aa, "none");
    }

    #[test]
    fn a_modes_samples_reproduce_its_measured_ratio_in_the_merger_at_depth_0() {
        let k = Constants::committed();
        let env = Environment {
            text: true,
            ..quads(1024, 400)
        };
        let t = Target::cores(2);
        let none = mode_time(&k, &env, "none", 1.0, 0, &t);
        // At depth 0 the leaf's method runs in none's one process: one sample a pixel
        // costs what `none` does, and each sample more adds to it.
        assert_eq!(mode_time(&k, &env, "ss4", 1.0, 0, &t), none);
        assert!(mode_time(&k, &env, "ss4", 2.0, 0, &t) > none);
        assert!(mode_time(&k, &env, "ss4", 4.0, 0, &t) > mode_time(&k, &env, "ss4", 2.0, 0, &t));
        assert_eq!(samples_for_ratio(&k, &env, &t, 0.99), 1.0);
        for ratio in [2.0, 5.0, 20.0] {
            let s = samples_for_ratio(&k, &env, &t, ratio);
            let back = mode_time(&k, &env, "ss4", s, 0, &t) / none;
            assert!(
                (back - ratio).abs() < 1e-6 * ratio,
                "{ratio}: {s} gives {back}"
            );
        }
        // `none` is the point-sampled layout whatever its samples.
        assert_eq!(none, model::predict_on(&k, &env, 0, &t).total_s);
    }

    /// One binary frame of `n` quads in view covering an `side`×`side` screen once.
    fn quads(n: u64, side: u32) -> Environment {
        Environment {
            frames: 1,
            polygons: n,
            vertices: 4 * n,
            relevant: n,
            relevant_vertices: 4 * n,
            area: f64::from(side * side),
            width: side,
            height: side,
            text: false,
        }
    }

    #[test]
    fn every_depth_the_tree_allows_is_a_candidate() {
        let k = Constants::committed();
        let env = quads(4096, 500);
        let a = Accuracy::committed();
        let all = a.predict_all(&k, &env, &colours(0.1, true), &Target::cores(2), 3);
        assert_eq!(all.len(), MODES.len() * 4);
        for m in MODES {
            let depths: Vec<u8> = all.iter().filter(|p| p.aa == m).map(|p| p.depth).collect();
            assert_eq!(depths, [0, 1, 2, 3], "{m}");
        }
        // Edge pixels a pixel 0.512: adaptiveK's fitted factor there would pass ssK's, and
        // is held at it, so adaptiveK is never predicted slower than ssK.
        assert!((edge_fraction(&env) - 0.512).abs() < 1e-9);
        for k in [2, 4, 8, 16] {
            let time = |aa: String| {
                let t: Vec<f64> = all
                    .iter()
                    .filter(|p| p.aa == aa)
                    .map(|p| p.seconds)
                    .collect();
                t
            };
            let (adaptive, ss) = (time(format!("adaptive{k}")), time(format!("ss{k}")));
            assert!(
                adaptive.iter().zip(&ss).all(|(a, s)| a <= s),
                "{k}: {adaptive:?} {ss:?}"
            );
        }
        // A sample costs the leaves' rate at every depth, so ss16 over two leaves on two
        // cores is predicted faster than in one, even with the leaves' covered pixel
        // priced four times the one-process z-buffer's.
        let mut dear = k.clone();
        dear.hse.pixel = 4.0 * dear.resolve.pixel;
        let fine = a.predict_all(&dear, &env, &colours(0.1, true), &Target::cores(2), 1);
        let ss16: Vec<f64> = fine
            .iter()
            .filter(|p| p.aa == "ss16")
            .map(|p| p.seconds)
            .collect();
        assert!(ss16[1] < ss16[0], "{ss16:?}");
        // The choice is the fastest of them all that meets the budget.
        let best = cheapest(&all, 4.0).unwrap();
        assert!(all
            .iter()
            .filter(|p| p.rms <= 4.0)
            .all(|p| p.seconds >= best.seconds));
    }

    #[test]
    fn the_cheapest_that_meets_the_budget_and_zero_is_the_reference() {
        let p = |aa: &str, seconds: f64, rms: f64| Predicted {
            aa: aa.into(),
            depth: 0,
            seconds,
            rms,
            wrong: 0.0,
        };
        let all = [
            p("none", 0.1, 12.0),
            p("ss2", 0.2, 4.0),
            p("adaptive4", 0.15, 1.5),
            p("ss16", 2.0, 0.0),
        ];
        assert_eq!(cheapest(&all, 16.0).unwrap().aa, "none");
        assert_eq!(cheapest(&all, 4.0).unwrap().aa, "adaptive4");
        assert_eq!(cheapest(&all, 0.0).unwrap().aa, "ss16");
        assert!(cheapest(&all[..2], 1.0).is_none());
    }

    #[test]
    fn a_tie_at_adaptives_cap_goes_to_whole_supersampling() {
        let p = |aa: &str, depth: u8, seconds: f64| Predicted {
            aa: aa.into(),
            depth,
            seconds,
            rms: 1.0,
            wrong: 0.0,
        };
        // adaptive2 first, as MODES lists it, and at ss2's time: ss2 is chosen.
        let tied = [p("adaptive2", 0, 0.2), p("ss2", 0, 0.2), p("ss2", 1, 0.3)];
        let chose = cheapest(&tied, 4.0).unwrap();
        assert_eq!((chose.aa.as_str(), chose.depth), ("ss2", 0));
        // Below its cap adaptive2 is chosen when it is the faster.
        let below = [p("adaptive2", 0, 0.19), p("ss2", 0, 0.2)];
        assert_eq!(cheapest(&below, 4.0).unwrap().aa, "adaptive2");
        // Among equals of one kind the first is kept.
        let same = [p("ss2", 1, 0.2), p("ss2", 0, 0.2)];
        assert_eq!(cheapest(&same, 4.0).unwrap().depth, 1);
    }

    #[test]
    fn shaded_scenes_leave_the_adaptive_modes_out() {
        let a = Accuracy::committed();
        let shaded_scene = colours(0.1, false);
        let shaded: Vec<&str> = a.allowed(&shaded_scene).map(|m| m.aa.as_str()).collect();
        assert!(!shaded.iter().any(|m| m.starts_with("adaptive")));
        assert!(shaded.contains(&SAFE));
        assert_eq!(a.allowed(&colours(0.1, true)).count(), MODES.len());
    }
}
