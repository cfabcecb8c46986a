//! The cost model of thesis chapters 5.2 and 6.4, with its constants measured on this
//! machine.
//!
//! Chapter 5.2 writes each stage's time for an environment as a sum of per-polygon,
//! per-vertex, per-scan-line and per-pixel costs:
//!
//! * T_v  = P_t·(138 + E·399)                    viewing transformation (5.2.1)
//! * T_p  = P_r·(138 + E·439)                    perspective (5.2.2)
//! * T_c  = P_c·(1213 + (E−1)·979)               the first clipper (5.2.3)
//! * T_SP = P_r·(1430 + (E−1)·1131)              the root splitter node (6.4)
//! * T_sc = P_r·(1034 + T_cl + E·(…)) + P_r·H·(… + E_aet·(414 + W·152))   scan conversion
//!   (5.2.4), which with W = H = √(X_res·Y_res·Dc / P_r) is, summed over the polygons,
//!   a cost per polygon, per vertex, per span (P_r·H = √(P_r·X·Y·Dc)) and per pixel
//!   (P_r·W·H = X·Y·Dc);
//!
//! in transputer cycles. Here each stage is one process, and its cost is the same linear
//! form in seconds: [`Cost`] holds a constant for the process and one per polygon,
//! vertex, span, pixel and screen pixel (the last for what scales with the screen rather
//! than the polygons: a leaf's tiles and its `run` records, the merger's frame), fitted by
//! least squares to the CPU time of each stage binary run alone on synthetic scenes
//! ([`crate::calibrate`]).
//!
//! A tree of depth N (6.4) halves P_r and the screen at every level and leaves Dc, W and H
//! alone: a node of level l reads P_r/2^l polygons, a leaf P_r/2^N polygons and
//! X·Y/2^N pixels. The pipeline's time is that of its slowest stage, as the thesis
//! reasons ("the rate of flow through a pipeline is only as large as the smallest rate of
//! flow over all its stages") — when each stage has a processor of its own. With C cores
//! for its processes (the clipper chain; the splitters, the 2^N − 1 nodes two levels to a
//! process, [`splitter_groups`]; the 2^N leaves but the one the merger resolves; the
//! merger), it can be no faster than all their work shared among the cores either
//! (starting each process is part of that work); so the
//! time is the larger of the two, plus what the script costs before the first stage
//! starts ([`Overheads`]). On a machine already loaded by other programs, the render's
//! processes together get one scheduling group's share of the cores, and each at most a
//! core of it ([`Target::shares`]).

use crate::look::Environment;
use serde::{Deserialize, Serialize};

/// The cost of one stage process: seconds for the process and per unit of work.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Cost {
    /// Seconds for the process whatever it reads (starting, the header, exit).
    pub process: f64,
    /// Seconds per polygon read.
    pub polygon: f64,
    /// Seconds per vertex read.
    pub vertex: f64,
    /// Seconds per span (a scan line of a polygon).
    pub span: f64,
    /// Seconds per covered pixel (a fragment).
    pub pixel: f64,
    /// Seconds per pixel of the stage's part of the screen, a frame.
    pub screen: f64,
}

/// The work a stage process has (all frames together).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Work {
    pub polygons: f64,
    pub vertices: f64,
    pub spans: f64,
    pub pixels: f64,
    pub screen: f64,
}

impl Work {
    /// The regressors in [`Cost`]'s order, with 1 for the process.
    pub fn features(&self) -> [f64; 6] {
        [
            1.0,
            self.polygons,
            self.vertices,
            self.spans,
            self.pixels,
            self.screen,
        ]
    }

    /// The same work split `parts` ways (a node or leaf of a tree level).
    pub fn share(&self, parts: f64) -> Work {
        Work {
            polygons: self.polygons / parts,
            vertices: self.vertices / parts,
            spans: self.spans / parts,
            pixels: self.pixels / parts,
            screen: self.screen / parts,
        }
    }
}

impl Cost {
    pub fn from_coefficients(c: [f64; 6]) -> Cost {
        Cost {
            process: c[0],
            polygon: c[1],
            vertex: c[2],
            span: c[3],
            pixel: c[4],
            screen: c[5],
        }
    }

    /// Seconds for `work`.
    pub fn time(&self, work: &Work) -> f64 {
        let c = [
            self.process,
            self.polygon,
            self.vertex,
            self.span,
            self.pixel,
            self.screen,
        ];
        c.iter().zip(work.features()).map(|(c, x)| c * x).sum()
    }
}

/// What the pipeline costs beyond its stages' work: the script, each process started and
/// each pipe between two processes (wall seconds, fitted to `render.sh` on a two-polygon
/// scene at every depth: [`crate::calibrate`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Overheads {
    /// `render.sh` itself: bash, its checks, the private folder.
    pub script: f64,
    /// Each stage process started and watched (fork, exec, its wait).
    pub process: f64,
    /// Each pipe between two processes ([`pipes`]): made and closed, and the relay
    /// through it, a write, a reader woken and its read, for every record (the header,
    /// each frame's end) even when no polygon crosses it. A tree's splitters write two or
    /// four pipes a process, so the pipes outgrow the processes with depth (2 pipes for 3
    /// processes at depth 0, 37 for 23 at depth 4). 0 in a file from before it was
    /// measured: its start-up was all the process's.
    pub pipe: f64,
}

/// The machine a calibration was made on: what [`crate::cache`] compares to tell a
/// calibration of this machine and of these binaries from a foreign or stale one.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct Machine {
    /// The CPU model, as /proc/cpuinfo names it.
    pub cpu: String,
    /// The machine's cores, online (`calibrate::machine_cores`: `taskset` does not
    /// change them).
    pub cores: usize,
    /// The polypipe version of the binaries measured.
    pub version: String,
    /// The measured binaries' fingerprint (their sizes and modification times): another
    /// build of them makes the calibration stale.
    pub binaries: String,
}

/// The model's constants: one [`Cost`] per stage, as `chart calibrate` measures them.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Constants {
    /// Where and when they were measured, in words.
    pub measured_on: String,
    /// The machine, for telling this machine's calibration from another's.
    pub machine: Machine,
    /// Whether the clipper drops a polygon it empties (the thesis's occam clipper does);
    /// polypipe's passes it on with no vertices, to keep the numbering, so that the root
    /// splitter and a depth-0 leaf read every polygon of the scene.
    pub drops_emptied: bool,
    /// Whether each leaf runs a persp of its own (the thesis's, a process and a
    /// transputer a stage); polypipe's tree has its last level project the leaves'
    /// streams (`splitter --project`), a process a leaf fewer.
    pub persp_at_leaves: bool,
    pub overheads: Overheads,
    /// viewxf reading a text scene.
    pub viewxf_text: Cost,
    /// viewxf reading a binary scene.
    pub viewxf_binary: Cost,
    /// clipbatch (the six planes in one process).
    pub clip: Cost,
    /// A splitter node.
    pub splitter: Cost,
    pub persp: Cost,
    /// A leaf's hidden-surface stage, `scanconv --resolve` (the z-buffer of its region).
    pub hse: Cost,
    /// The merger, zbuf, placing the leaves' runs and writing the frames.
    pub merge: Cost,
    /// zbuf resolving the one leaf itself at depth 0 (`zbuf --project`, its projection
    /// counted at persp's cost): the leaf's z-buffer and the frames, in one process,
    /// with no runs between them.
    pub resolve: Cost,
}

/// The constants committed after a calibration run on the project's machine: the fallback
/// until this machine is calibrated, and the documented example of the file.
pub const COMMITTED: &str = include_str!("../../bench/model.toml");

impl Constants {
    pub fn parse(text: &str) -> crate::Result<Constants> {
        Ok(toml::from_str(text)?)
    }

    pub fn committed() -> Constants {
        Constants::parse(COMMITTED).unwrap_or_default()
    }

    pub fn to_toml(&self) -> crate::Result<String> {
        Ok(toml::to_string(self)?)
    }
}

/// One stage's share of a prediction.
#[derive(Clone, Debug, PartialEq)]
pub struct StageTime {
    /// `viewxf`, `clip`, `splitter`, `persp`, `hse`, `merge`.
    pub stage: &'static str,
    /// Seconds of the busiest process of the stage (the root node; one leaf).
    pub each_s: f64,
    /// How many processes the stage has.
    pub processes: usize,
    /// Seconds of all its processes together.
    pub total_s: f64,
}

/// The model's prediction for one scene at one depth.
#[derive(Clone, Debug, PartialEq)]
pub struct Prediction {
    pub depth: u8,
    /// Wall seconds predicted for the whole render.
    pub total_s: f64,
    pub stages: Vec<StageTime>,
    /// The slowest stage process's seconds (the thesis's bound).
    pub slowest_s: f64,
    /// Every process's work, its start included, over the cores (the machine's bound).
    pub shared_s: f64,
    /// Script and process start-up (the script's is added to the larger bound; the
    /// processes' is in `shared_s`).
    pub overhead_s: f64,
    pub processes: usize,
    /// The pipes between them ([`pipes`]).
    pub pipes: usize,
    /// With hosts: the seconds a host's link is busy (its bytes over the link's rate).
    pub link_s: f64,
}

impl Prediction {
    /// The stage whose process is slowest.
    pub fn bottleneck(&self) -> &'static str {
        self.stages
            .iter()
            .max_by(|a, b| a.each_s.total_cmp(&b.each_s))
            .map_or("none", |s| s.stage)
    }
}

/// The work of the stages for an environment, before any split (all frames).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StageWork {
    /// What viewxf and the clipper read: every polygon of the scene.
    pub world: Work,
    /// What leaves the clipper: a polygon record for every polygon of the scene (one the
    /// clipper emptied still goes on, with no vertices, to keep the numbering), the
    /// vertices and the pixels of those in view. The root splitter, and at depth 0 persp
    /// and the hidden-surface stage, read this.
    pub flowing: Work,
    /// The polygons in view (P_r) only: a splitter sends an emptied polygon on as a skip,
    /// so below the root the work is this, split among the nodes of a level.
    pub relevant: Work,
    /// The merger's: the screen a frame, and the runs (a span's worth each).
    pub merge: Work,
}

/// The work of each stage for an environment. `drops_emptied`: the clipper drops the
/// polygons it empties (the thesis's), so that what flows on is only those in view.
pub fn stage_work(env: &Environment, drops_emptied: bool) -> StageWork {
    let world = Work {
        polygons: env.polygons as f64,
        vertices: env.vertices as f64,
        ..Default::default()
    };
    let relevant = Work {
        polygons: env.relevant as f64,
        vertices: env.relevant_vertices as f64,
        spans: env.spans(),
        pixels: env.area,
        screen: env.screen() * env.frames as f64,
    };
    let flowing = if drops_emptied {
        relevant
    } else {
        Work {
            polygons: env.polygons.max(env.relevant) as f64,
            ..relevant
        }
    };
    let merge = Work {
        spans: env.spans(),
        screen: env.screen() * env.frames as f64,
        ..Default::default()
    };
    StageWork {
        world,
        flowing,
        relevant,
        merge,
    }
}

/// Other hosts that take the tree's subtrees (`render.sh --hosts`, by leaves).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hosts {
    /// How many.
    pub count: usize,
    /// Cores each.
    pub cores: usize,
    /// The link to each, bytes a second each way (1 Gb/s: 125e6).
    pub link_bytes_per_s: f64,
    /// Seconds to start a host's part (an ssh login and its render.sh).
    pub start_s: f64,
}

/// What the render runs on: this machine's cores and the load already on them, and
/// perhaps other hosts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Target {
    /// Cores here. [`Target::unbounded`]: a processor for every process, the thesis's
    /// assumption (6.4: "each of our processes is running on a separate transputer").
    pub cores: usize,
    pub hosts: Option<Hosts>,
    /// Other programs' runnable threads on these cores
    /// ([`crate::calibrate::background_load`]): the render's processes share the cores
    /// with them.
    pub load: f64,
}

impl Target {
    pub fn cores(cores: usize) -> Target {
        Target {
            cores: cores.max(1),
            hosts: None,
            load: 0.0,
        }
    }

    /// A processor for every process.
    pub fn unbounded() -> Target {
        Target {
            cores: usize::MAX,
            hosts: None,
            load: 0.0,
        }
    }

    /// The same, with `load` other runnable threads on the cores.
    pub fn loaded(self, load: f64) -> Target {
        Target {
            load: load.max(0.0),
            ..self
        }
    }

    /// The share of the cores a busy process gets, and the cores the render's
    /// `processes` get together, beside [`Target::load`] other runnable threads.
    ///
    /// Linux's scheduler shares the cores fairly among groups of threads, not among the
    /// threads (autogroup, on by default: a group a session, which a render's stages all
    /// belong to; cgroups do the same for services): the render's processes, however
    /// many, together get one group's part, and each other group at most what its own
    /// threads can use. Taking each other thread for a group of its own (a bound: there
    /// are no more groups than threads), the render's part of C cores beside L of them
    /// is C − L while the others leave that much free, and the fair C/(1 + L) once they
    /// do not: S = max(C − L, C/(1 + L)), and a busy process at most one core of it.
    /// Unloaded: 1 and C. When S is a core or less, a deeper tree cannot run its stages
    /// side by side and only adds work: on the bench's fill scene (10,000 quads, Dc 10,
    /// 1920x1080) with 10 to 13 other threads runnable, depths 0 to 3 took 0.216, 0.244,
    /// 0.276 and 0.259 s on two cores, their wall time about three times their CPU time
    /// at every depth, where the threads' fair share (N·C/(N + L) for N processes) had
    /// the deeper trees gain and chose depth 3 (`target/bin/bench tree depth-auto`).
    pub fn shares(&self, _processes: usize) -> (f64, f64) {
        let c = self.cores as f64;
        let l = self.load.max(0.0);
        let all = (c - l).max(c / (1.0 + l)).min(c);
        (all.min(1.0), all)
    }

    /// The shallowest depth that gives every host a subtree: 2^depth ≥ hosts.
    pub fn min_depth(&self) -> u8 {
        match self.hosts {
            Some(h) if h.count > 1 => (h.count as f64).log2().ceil().min(6.0) as u8,
            _ => 0,
        }
    }
}

/// How many times the polygons in view a node of level `l` reads are its P_r/2^l share:
/// a polygon that a splitting plane cuts goes to both sides (6.4 assumes that "the
/// majority of the polygons are not cut"; the majority, not all). A polygon W pixels wide
/// (5.2's W = H = √(X·Y·Dc/P_r)) is cut by a line across a region E pixels wide with
/// probability about W/E; the levels cut x, y, x, … of regions halved at every second
/// level, so level l reads Π (1 + W/E_k) times its share over the cuts above it. On the
/// bench's fill-heavy scene this gives the measured averages within 3% (2,664, 1,411 and
/// 752 polygons a node at levels 1 to 3, against 2,656, 1,428 and 772).
pub fn cut_growth(env: &Environment, l: u8) -> f64 {
    let frames = env.frames.max(1) as f64;
    let per_frame = env.relevant as f64 / frames;
    if per_frame < 1.0 {
        return 1.0;
    }
    let w = (env.screen() * env.depth_complexity() / per_frame).sqrt();
    let (mut x, mut y) = (env.width as f64, env.height as f64);
    let mut growth = 1.0;
    for k in 0..l {
        // Level k's nodes cut x (even k) or y (odd k) of their region.
        let extent = if k % 2 == 0 { &mut x } else { &mut y };
        growth *= 1.0 + (w / *extent).min(1.0);
        *extent /= 2.0;
    }
    growth
}

/// Bytes of the binary eye-space stream a polygon: an 8-byte head, 32 bytes a vertex
/// (four f64), and about 40 more for the annotations a split adds (the plane, the
/// supports of cut edges); a run of finished pixels back is 16 bytes.
const LINK_POLYGON: f64 = 48.0;
const LINK_VERTEX: f64 = 32.0;
const LINK_RUN: f64 = 16.0;

/// The predicted time of a render of `env` at tree depth `depth` on `cores` cores here.
pub fn predict(k: &Constants, env: &Environment, depth: u8, cores: usize) -> Prediction {
    predict_on(k, env, depth, &Target::cores(cores))
}

/// The predicted time of a render of `env` at tree depth `depth` on `target`.
pub fn predict_on(k: &Constants, env: &Environment, depth: u8, target: &Target) -> Prediction {
    predict_layout(k, env, depth, target, false)
}

/// [`predict_on`] for a render of an anti-aliasing leaf (`--aa ssK`, `adaptiveK`,
/// `abuf`): at depth 0 one `zbuf --project --samples K` doing persp's, the leaf's and the
/// merger's work (the a-buffer's leaf is priced so too), as the point-sampled z-buffer
/// is one `zbuf --project`; deeper, every leaf a process of its own, where zbuf resolves
/// the z-buffer's leaf 0 itself. The leaf is priced at the leaves' scan converter's rates
/// ([`Constants::hse`]) at every depth, `env.area` its samples.
pub fn predict_sampled(k: &Constants, env: &Environment, depth: u8, target: &Target) -> Prediction {
    predict_layout(k, env, depth, target, true)
}

/// [`predict_on`], or with `apart` [`predict_sampled`].
fn predict_layout(
    k: &Constants,
    env: &Environment,
    depth: u8,
    target: &Target,
    apart: bool,
) -> Prediction {
    let StageWork {
        world,
        flowing,
        relevant,
        merge: merge_work,
    } = stage_work(env, k.drops_emptied);
    let leaves = (1u64 << depth) as f64;
    // What a node of level l reads: the root every polygon, a lower one its share of those
    // in view.
    let node = |l: u8| {
        if l == 0 {
            flowing
        } else {
            let mut w = relevant.share((1u64 << l) as f64);
            let more = cut_growth(env, l);
            w.polygons *= more;
            w.vertices *= more;
            w
        }
    };
    let viewxf = if env.text {
        &k.viewxf_text
    } else {
        &k.viewxf_binary
    };
    let mut stages = vec![
        one("viewxf", viewxf.time(&world)),
        one("clip", k.clip.time(&world)),
    ];
    // The level whose subtrees go to the hosts (render.sh's host_level): the first with a
    // node for every host, or the leaves'.
    let host_level = target.hosts.map(|h| {
        (0..depth)
            .find(|&l| (1usize << l) >= h.count)
            .unwrap_or(depth)
    });
    let here_levels = host_level.unwrap_or(depth);
    let leaf = node(depth);
    // With the leaves here, the tree's last level projects the leaves' streams
    // (`splitter --project`), and a leaf has no persp process: each node of that level
    // does its two leaves' persp work, counted at persp's own cost (an upper bound: on
    // the fill-heavy scene the projection inside the splitter costs about a sixth of
    // the two persp processes it replaces, docs/performance.md).
    let projected = depth > 0 && host_level.is_none() && !k.persp_at_leaves;
    if depth > 0 {
        // Level l has 2^l nodes, each reading P_r/2^l (6.4); the root is the busiest,
        // or the last level, where it projects too.
        let project = if projected {
            2.0 * k.persp.time(&leaf)
        } else {
            0.0
        };
        let node_s = |l: u8| k.splitter.time(&node(l)) + if l + 1 == depth { project } else { 0.0 };
        if here_levels > 0 {
            stages.push(splitter_stage(k, 0, here_levels, node_s));
        }
    }
    // The leaves' part: persp (unless projected above) and the hidden-surface stage on
    // each.
    let mut leaf_stages = Vec::new();
    if depth == 0 && host_level.is_none() && apart {
        // One leaf, whose region is the screen: render runs `zbuf --project --samples K`,
        // zbuf doing persp's work, the leaf's (at the leaves' rates, `env.area` its
        // samples) and its own, painting the leaf's runs and writing the frames, in one
        // process: the three stages' work less the two processes' starts.
        let total = k.persp.time(&leaf) - k.persp.process + k.hse.time(&leaf) - k.hse.process
            + k.merge.time(&merge_work);
        stages.push(one("hse", total));
    } else if depth == 0 && host_level.is_none() {
        // One leaf, whose region is the screen: render.sh runs `zbuf --project`, zbuf
        // projecting the clipper's stream (at persp's cost), resolving the leaf and
        // writing the frames in one process; the thesis's figures keep persp's process.
        if k.persp_at_leaves {
            stages.push(one("persp", k.persp.time(&leaf)));
            stages.push(one("hse", k.resolve.time(&leaf)));
        } else {
            // zbuf paints each finished frame into the picture and writes it on a thread
            // of its own while its reader thread projects and resolves the next frame
            // (bins/zbuf/src/par_buff.rs, `one_input`): the screen's share of its work
            // (a frame's pixels, painted and written) is off the reader's path but for
            // the last frame's, which nothing follows. A still is all on one path; a
            // movie's frames overlap: (d), 100 frames of 1,024 quads at 500x500, was
            // predicted slower at depth 0 than at depth 1, and is faster.
            let total = k.persp.time(&leaf) + k.resolve.time(&leaf);
            let paint = k.resolve.screen * leaf.screen;
            let overlapped = paint * (1.0 - 1.0 / env.frames.max(1) as f64);
            stages.push(StageTime {
                stage: "hse",
                each_s: (total - overlapped).max(paint),
                processes: 1,
                total_s: total,
            });
        }
    } else {
        let leaf_costs: &[(&'static str, &Cost)] = if projected {
            &[("hse", &k.hse)]
        } else {
            &[("persp", &k.persp), ("hse", &k.hse)]
        };
        // With the leaves here, the merger resolves leaf 0 itself, on a thread of its own
        // beside the one placing the other leaves' runs (render.sh's merger_is_leaf):
        // one leaf process fewer, and the merger busier.
        let own = usize::from(projected && !apart);
        for &(stage, cost) in leaf_costs {
            let each = cost.time(&leaf);
            leaf_stages.push(StageTime {
                stage,
                each_s: each,
                processes: (1 << depth) - own,
                total_s: each * (leaves - own as f64),
            });
        }
        let merge_s = k.merge.time(&merge_work);
        let resolve_s = if own == 1 { k.hse.time(&leaf) } else { 0.0 };
        stages.push(StageTime {
            stage: "merge",
            each_s: merge_s.max(resolve_s),
            processes: 1,
            total_s: merge_s + resolve_s,
        });
    }
    let mut hosts_s = 0.0;
    let mut link_s = 0.0;
    let mut host_starts = 0.0;
    match (target.hosts, host_level) {
        (Some(h), Some(level)) => {
            // Each host takes its round-robin share of the 2^level subtrees: their
            // splitters below `level`, their leaves and a relaying zbuf --runs; what it
            // reads and sends back crosses its link while it works.
            let subtrees = 1usize << level;
            let per_host = subtrees.div_ceil(h.count.max(1)) as f64;
            let below = (level < depth)
                .then(|| splitter_stage(k, level, depth, |l| k.splitter.time(&node(l))));
            let lower = below.as_ref().map_or(0.0, |s| s.total_s);
            let leaves_work: f64 = leaf_stages.iter().map(|s| s.total_s).sum();
            let relay = k.merge.time(&merge_work.share(subtrees as f64));
            let share = (lower + leaves_work) / subtrees as f64 + relay;
            let slowest_there = leaf_stages
                .iter()
                .map(|s| s.each_s)
                .chain(below.as_ref().map(|s| s.each_s))
                .fold(relay, f64::max);
            let compute = (share * per_host / h.cores.max(1) as f64).max(slowest_there);
            let into = relevant.share(subtrees as f64);
            let bytes_in = LINK_POLYGON * into.polygons + LINK_VERTEX * into.vertices;
            let runs = relevant.spans / env.depth_complexity().max(1.0).sqrt();
            let bytes_back = LINK_RUN * runs / subtrees as f64;
            link_s = per_host * bytes_in.max(bytes_back) / h.link_bytes_per_s.max(1.0);
            hosts_s = compute.max(link_s);
            host_starts = h.start_s;
        }
        _ => stages.extend(leaf_stages),
    }
    let processes: usize = stages.iter().map(|s| s.processes).sum();
    let pipes = pipes(processes, here_levels);
    let slowest_s = stages.iter().map(|s| s.each_s).fold(hosts_s, f64::max);
    // Starting a process (the fork, the exec, its wait) and relaying through a pipe
    // (made, written, a reader woken) is work for the cores like the stages' own, done
    // while the stages run; the script's own start is before any of it.
    let starting = k.overheads.process * processes as f64 + k.overheads.pipe * pipes as f64;
    let work: f64 = stages.iter().map(|s| s.total_s).sum::<f64>() + starting;
    // On a loaded machine the render's processes together get their group's share of
    // the cores, and each at most a core of it.
    let (slowest_s, shared_s) = if target.cores == usize::MAX {
        (slowest_s, 0.0)
    } else {
        let (one, all) = target.shares(processes);
        (slowest_s / one, work / all)
    };
    let overhead_s = k.overheads.script + starting + host_starts;
    Prediction {
        depth,
        total_s: k.overheads.script + host_starts + slowest_s.max(shared_s),
        stages,
        slowest_s,
        shared_s,
        overhead_s,
        processes,
        pipes,
        link_s,
    }
}

/// The pipes between a render's `processes` when the merger reads `2^merged_levels`
/// streams (the leaves', or with hosts the subtrees'), as render's graph makes them
/// (bins/render/src/graph.rs): viewxf reads the scene and the merger writes the frames,
/// every other process reads one pipe (a splitter's outputs are its children's inputs,
/// a leaf's its persp's or its splitter's), and the merger reads one from each leaf,
/// leaf 0's included (the last splitter's, projected, where the merger resolves leaf 0
/// itself; the clipper's at depth 0). Depth 0 to 4: 2, 5, 9, 19 and 37 pipes.
pub fn pipes(processes: usize, merged_levels: u8) -> usize {
    processes.saturating_sub(2) + (1usize << merged_levels.min(20))
}

/// How render.sh runs `levels` levels of a tree, top to bottom: the levels of each group
/// one process a node of its top level (`splitter --levels`), two levels to a group,
/// paired from the bottom, so that an odd count leaves the top level alone.
pub fn splitter_groups(levels: u8) -> Vec<u8> {
    let mut groups = vec![2; usize::from(levels / 2)];
    if levels % 2 == 1 {
        groups.insert(0, 1);
    }
    groups
}

/// The splitter processes of levels `top..bottom` of a tree, grouped as render.sh runs them
/// ([`splitter_groups`]), where a node of level l costs `node_s(l)` as a process of its
/// own: a process for a group's top node does the work of the nodes below it in the
/// group too, but starts once (one [`Cost::process`] for all of them).
fn splitter_stage(k: &Constants, top: u8, bottom: u8, node_s: impl Fn(u8) -> f64) -> StageTime {
    let (mut each_s, mut processes, mut total_s) = (0.0f64, 0usize, 0.0);
    let mut level = top;
    for span in splitter_groups(bottom - top) {
        let process_s = (0..span)
            .map(|j| (1u64 << j) as f64 * node_s(level + j))
            .sum::<f64>()
            - ((1u64 << span) - 2) as f64 * k.splitter.process;
        let nodes = 1usize << level;
        each_s = each_s.max(process_s);
        processes += nodes;
        total_s += nodes as f64 * process_s;
        level += span;
    }
    StageTime {
        stage: "splitter",
        each_s,
        processes,
        total_s,
    }
}

fn one(stage: &'static str, t: f64) -> StageTime {
    StageTime {
        stage,
        each_s: t,
        processes: 1,
        total_s: t,
    }
}

/// How much faster a deeper tree must be predicted to be chosen over the best shallower
/// one: 5%. Model no more than a scene needs (docs/DESIGN.md): a deeper tree costs more
/// processes and memory for a gain the model cannot promise within its error.
pub const DEEPER_BY: f64 = 0.05;

/// The rule [`choose_depth`] applies, in words, for its output.
pub const RULE: &str =
    "rule: a deeper tree only when predicted at least 5% faster than the best shallower one";

/// The depth the model says is fastest (the target's least depth to `max_depth`), with its
/// reason. Model no more than a scene needs: a deeper tree must be predicted at least
/// [`DEEPER_BY`] faster than the best shallower one to be chosen. With a processor for
/// every process ([`Target::unbounded`]) and no start-up costs this is thesis 6.4's rule,
/// "increase the depth of the splitter tree until the rate of flow through the HSE layer
/// is equal to the smallest rate of flow over all the other stages": past that depth the
/// slowest stage is no longer the leaves' and a level more gains nothing.
pub fn choose_depth(
    k: &Constants,
    env: &Environment,
    cores: usize,
    max_depth: u8,
) -> (u8, String, Vec<Prediction>) {
    choose_depth_on(k, env, &Target::cores(cores), max_depth)
}

/// [`choose_depth`] for a target with hosts, or unbounded.
pub fn choose_depth_on(
    k: &Constants,
    env: &Environment,
    target: &Target,
    max_depth: u8,
) -> (u8, String, Vec<Prediction>) {
    let least = target.min_depth().min(max_depth);
    let all: Vec<Prediction> = (least..=max_depth)
        .map(|d| predict_on(k, env, d, target))
        .collect();
    let mut best = &all[0];
    for p in &all[1..] {
        if p.total_s < best.total_s * (1.0 - DEEPER_BY) {
            best = p;
        }
    }
    let fastest = all
        .iter()
        .min_by(|a, b| a.total_s.total_cmp(&b.total_s))
        .unwrap_or(best);
    let others = if fastest.depth != best.depth {
        format!(
            "; depth {} predicted {:.3} s, not 5% faster",
            fastest.depth, fastest.total_s
        )
    } else {
        all.get((best.depth - least) as usize + 1)
            .map(|p| format!("; depth {} {:.3} s", p.depth, p.total_s))
            .unwrap_or_default()
    };
    let loaded = if target.load >= 0.05 {
        format!(", load {:.1}", target.load)
    } else {
        String::new()
    };
    let on = match (target.hosts, target.cores) {
        (Some(h), c) => format!(
            "{c} core{} here, {} hosts of {} cores at {:.0} Mb/s",
            if c == 1 { "" } else { "s" },
            h.count,
            h.cores,
            h.link_bytes_per_s * 8e-6
        ),
        (None, usize::MAX) => "a processor per process".to_string(),
        (None, c) => format!("{c} core{}", if c == 1 { "" } else { "s" }),
    };
    let reason = format!(
        "{} polygons in view, Dc {:.1}, {}x{}, {} frame{}, {on}{loaded}: predicted {:.3} s{others}; slowest stage {}; {RULE}",
        env.relevant / env.frames.max(1),
        env.depth_complexity(),
        env.width,
        env.height,
        env.frames,
        if env.frames == 1 { "" } else { "s" },
        best.total_s,
        best.bottleneck()
    );
    (best.depth, reason, all)
}

/// Least squares with non-negative coefficients (a cost cannot be negative): solves the
/// normal equations on the columns still free, and drops the most negative coefficient's
/// column until none is negative. `rows` are the regressors, `y` the measured seconds;
/// `use_column[j]` false leaves column j out (its coefficient 0).
pub fn fit(rows: &[[f64; 6]], y: &[f64], use_column: [bool; 6]) -> [f64; 6] {
    let mut free = use_column;
    loop {
        let cols: Vec<usize> = (0..6).filter(|&j| free[j]).collect();
        let mut coef = [0.0; 6];
        if cols.is_empty() {
            return coef;
        }
        // Columns scaled to unit largest value, for the conditioning.
        let scale: Vec<f64> = cols
            .iter()
            .map(|&j| {
                rows.iter()
                    .map(|r| r[j].abs())
                    .fold(0.0, f64::max)
                    .max(1e-300)
            })
            .collect();
        let n = cols.len();
        let mut a = vec![vec![0.0; n + 1]; n];
        for (r, &yv) in rows.iter().zip(y) {
            for i in 0..n {
                let xi = r[cols[i]] / scale[i];
                for j in 0..n {
                    a[i][j] += xi * r[cols[j]] / scale[j];
                }
                a[i][n] += xi * yv;
            }
        }
        let solved = solve(a);
        let Some(x) = solved else {
            // Singular: drop the last free column and try again.
            free[*cols.last().unwrap_or(&0)] = false;
            continue;
        };
        for (i, &j) in cols.iter().enumerate() {
            coef[j] = x[i] / scale[i];
        }
        match cols
            .iter()
            .copied()
            .filter(|&j| coef[j] < 0.0)
            .min_by(|&a, &b| coef[a].total_cmp(&coef[b]))
        {
            Some(j) => free[j] = false,
            None => return coef,
        }
    }
}

/// Gaussian elimination with partial pivoting on an augmented n×(n+1) matrix.
fn solve(mut a: Vec<Vec<f64>>) -> Option<Vec<f64>> {
    let n = a.len();
    for c in 0..n {
        let p = (c..n).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c].abs() < 1e-12 {
            return None;
        }
        a.swap(c, p);
        let pivot = a[c].clone();
        for (r, row) in a.iter_mut().enumerate() {
            if r != c {
                let f = row[c] / pivot[c];
                for (x, p) in row.iter_mut().zip(&pivot).skip(c) {
                    *x -= f * p;
                }
            }
        }
    }
    Some((0..n).map(|i| a[i][n] / a[i][i]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env(polygons: u64, w: u32, h: u32, dc: f64) -> Environment {
        Environment {
            frames: 1,
            polygons: 2 * polygons,
            vertices: 8 * polygons,
            relevant: polygons,
            relevant_vertices: 4 * polygons,
            area: w as f64 * h as f64 * dc,
            width: w,
            height: h,
            text: true,
        }
    }

    /// What render's `--depth auto` leans on to skip the look when the render has a
    /// core or less (`render::auto::one_core_at_most`): then every depth's time is its
    /// work over that share, and the tree only adds work, so the model takes depth 0 for
    /// every scene, with these constants and the committed ones.
    #[test]
    fn a_core_or_less_is_depth_0_for_every_scene() {
        let targets = [
            Target::cores(1),
            Target {
                load: 1.0,
                ..Target::cores(2)
            },
            Target {
                load: 7.0,
                ..Target::cores(2)
            },
            Target {
                load: 3.0,
                ..Target::cores(4)
            },
        ];
        for target in targets {
            assert!(target.shares(0).1 <= 1.0, "{target:?}");
            for k in [constants(), Constants::committed()] {
                for e in [
                    env(2, 64, 64, 1.0),
                    env(1_024, 500, 500, 2.0),
                    env(10_000, 1920, 1080, 10.0),
                    env(100_000, 3840, 2160, 10.0),
                ] {
                    let (depth, why, _) = choose_depth_on(&k, &e, &target, 6);
                    assert_eq!(depth, 0, "{target:?}, {e:?}: {why}");
                }
            }
        }
    }

    fn constants() -> Constants {
        Constants {
            overheads: Overheads {
                script: 0.02,
                process: 0.002,
                pipe: 0.0,
            },
            viewxf_text: Cost {
                process: 0.001,
                vertex: 1e-8,
                ..Default::default()
            },
            clip: Cost {
                process: 0.001,
                vertex: 3e-7,
                ..Default::default()
            },
            splitter: Cost {
                process: 0.001,
                vertex: 3e-7,
                ..Default::default()
            },
            persp: Cost {
                process: 0.001,
                vertex: 2e-7,
                ..Default::default()
            },
            hse: Cost {
                process: 0.001,
                polygon: 1e-6,
                span: 5e-8,
                pixel: 5e-9,
                screen: 1e-9,
                ..Default::default()
            },
            merge: Cost {
                process: 0.001,
                screen: 5e-9,
                ..Default::default()
            },
            resolve: Cost {
                process: 0.001,
                polygon: 8e-7,
                pixel: 4e-9,
                screen: 2e-9,
                ..Default::default()
            },
            ..Default::default()
        }
    }

    #[test]
    fn a_movie_paints_its_frames_beside_resolving_the_next_at_depth_0() {
        let k = constants();
        let hse = |e: &Environment| {
            let p = predict(&k, e, 0, 2);
            p.stages.iter().find(|s| s.stage == "hse").unwrap().clone()
        };
        // A still: the frame is painted after it is resolved, on the same path.
        let still = env(1_000, 500, 500, 1.0);
        let w = stage_work(&still, false).flowing;
        let whole = k.persp.time(&w) + k.resolve.time(&w);
        assert_eq!((hse(&still).each_s, hse(&still).total_s), (whole, whole));
        // 100 such frames: every frame's painting but the last beside the next frame's
        // resolving; the work the same.
        let movie = Environment {
            frames: 100,
            polygons: 100 * still.polygons,
            vertices: 100 * still.vertices,
            relevant: 100 * still.relevant,
            relevant_vertices: 100 * still.relevant_vertices,
            area: 100.0 * still.area,
            ..still
        };
        let w = stage_work(&movie, false).flowing;
        let whole = k.persp.time(&w) + k.resolve.time(&w);
        let paint = k.resolve.screen * 500.0 * 500.0;
        assert_eq!(hse(&movie).total_s, whole);
        let off = whole - hse(&movie).each_s;
        assert!((off - 99.0 * paint).abs() < 1e-9 * whole, "{off} {paint}");
    }

    #[test]
    fn fit_recovers_known_constants_and_keeps_them_non_negative() {
        let truth = [0.001, 2e-6, 5e-7, 0.0, 3e-9, 0.0];
        let mut rows = Vec::new();
        let mut y = Vec::new();
        for p in [100.0f64, 1000.0, 10000.0, 50000.0] {
            for px in [1e4, 1e6, 4e6] {
                for k in [0.0, 1.0, 2.0] {
                    let r = [1.0, p, (3.0 + k) * p, (p * px).sqrt(), px, px / (1.0 + k)];
                    y.push(r.iter().zip(truth).map(|(a, b)| a * b).sum());
                    rows.push(r);
                }
            }
        }
        let c = fit(&rows, &y, [true, true, true, false, true, false]);
        for j in 0..6 {
            assert!(
                (c[j] - truth[j]).abs() <= 1e-6 * truth[j].abs().max(1e-12),
                "{c:?}"
            );
        }
        // A regressor that only hurts gets 0, not a negative cost.
        let y2: Vec<f64> = rows.iter().map(|r| 0.01 + 1e-6 * r[1]).collect();
        let c = fit(&rows, &y2, [true; 6]);
        assert!(c.iter().all(|&v| v >= 0.0), "{c:?}");
    }

    #[test]
    fn depth_multiplies_processes_and_halves_the_leaves() {
        let k = constants();
        let e = env(10_000, 1920, 1080, 10.0);
        let p0 = predict(&k, &e, 0, 2);
        let p2 = predict(&k, &e, 2, 2);
        // viewxf, clipbatch, zbuf (projecting and resolving the leaf).
        assert_eq!(p0.processes, 3);
        // viewxf, clipbatch, one splitter for the 3 nodes (the last level projecting), 3
        // leaves, zbuf (resolving leaf 0 itself).
        assert_eq!(p2.processes, 2 + 1 + 3 + 1);
        assert!(p2.stages.iter().all(|s| s.stage != "persp"));
        // The two nodes of the last level project their leaves' streams; the three nodes
        // are one process, started once.
        let splitter = p2.stages.iter().find(|s| s.stage == "splitter").unwrap();
        let leaf_work = |l: u8| {
            let mut w = stage_work(&e, false).relevant.share((1u64 << l) as f64);
            w.polygons *= cut_growth(&e, l);
            w.vertices *= cut_growth(&e, l);
            w
        };
        let expected = k.splitter.time(&stage_work(&e, false).flowing)
            + 2.0 * (k.splitter.time(&leaf_work(1)) + 2.0 * k.persp.time(&leaf_work(2)))
            - 2.0 * k.splitter.process;
        assert!(
            (splitter.total_s - expected).abs() < 1e-12 * expected,
            "{splitter:?}"
        );
        assert_eq!((splitter.processes, splitter.each_s), (1, splitter.total_s));
        let hse = |p: &Prediction| p.stages.iter().find(|s| s.stage == "hse").unwrap().clone();
        // At depth 0 the leaf reads every polygon the clipper passes on (half of them
        // emptied here); a leaf of depth 2 a quarter of those in view and of the screen.
        let w = stage_work(&e, false);
        assert_eq!(w.flowing.polygons, 20_000.0);
        // At depth 0 zbuf projects and resolves the one leaf itself, at persp's cost and
        // its own.
        assert_eq!(
            hse(&p0).each_s,
            k.persp.time(&w.flowing) + k.resolve.time(&w.flowing)
        );
        assert!(p0.stages.iter().all(|s| s.stage != "persp"));
        assert!(p0.stages.iter().all(|s| s.stage != "merge"));
        let quarter = w.relevant.share(4.0);
        assert_eq!(
            (quarter.polygons, quarter.screen),
            (2_500.0, 1920.0 * 1080.0 / 4.0)
        );
        // … and the polygons the two cuts above it cut, on both sides.
        let mut leaf = quarter;
        leaf.polygons *= cut_growth(&e, 2);
        leaf.vertices *= cut_growth(&e, 2);
        assert!(cut_growth(&e, 2) > 1.0);
        assert!((hse(&p2).each_s - k.hse.time(&leaf)).abs() < 1e-15);
        assert!(hse(&p2).each_s < k.hse.time(&w.flowing) / 4.0);
        // Three leaf processes; the merger resolves the fourth leaf beside placing the
        // others' runs: both are its work, the larger its time.
        assert_eq!(hse(&p2).processes, 3);
        assert!((hse(&p2).total_s - 3.0 * hse(&p2).each_s).abs() < 1e-12);
        let merge = p2.stages.iter().find(|s| s.stage == "merge").unwrap();
        assert_eq!(merge.processes, 1);
        assert!(merge.each_s >= hse(&p2).each_s && merge.total_s > merge.each_s);
        assert_eq!(p0.bottleneck(), "hse");
    }

    #[test]
    fn two_polygons_get_depth_0_and_a_fill_heavy_scene_on_many_cores_a_tree() {
        let k = constants();
        let (d, reason, _) = choose_depth(&k, &env(1, 500, 500, 0.01), 2, 6);
        assert_eq!(d, 0, "{reason}");
        assert!(reason.contains("1 polygons in view"), "{reason}");
        let (d, reason, _) = choose_depth(&k, &env(10_000, 1920, 1080, 10.0), 64, 6);
        assert!(d >= 2, "{d}: {reason}");
    }

    #[test]
    fn hosts_get_a_subtree_each_and_a_slow_link_shows() {
        let k = constants();
        let e = env(10_000, 1920, 1080, 10.0);
        let hosts = |count, gbps: f64| Target {
            load: 0.0,
            cores: 2,
            hosts: Some(Hosts {
                count,
                cores: 2,
                link_bytes_per_s: gbps * 1e9 / 8.0,
                start_s: 0.1,
            }),
        };
        assert_eq!(hosts(1, 1.0).min_depth(), 0);
        assert_eq!(hosts(3, 1.0).min_depth(), 2);
        assert_eq!(hosts(4, 1.0).min_depth(), 2);
        assert_eq!(hosts(5, 1.0).min_depth(), 3);
        let (d, reason, all) = choose_depth_on(&k, &e, &hosts(4, 1.0), 6);
        assert!(d >= 2 && all[0].depth == 2, "{reason}");
        assert!(
            reason.contains("4 hosts of 2 cores at 1000 Mb/s"),
            "{reason}"
        );
        // The link: 48 bytes a polygon and 32 a vertex of a quarter of those in view, in
        // to each host; 16 bytes a run back, a run a visible span (spans over √Dc); over
        // 1 Mb/s (125,000 bytes a second) and over 10 Gb/s.
        let slow = predict_on(&k, &e, 2, &hosts(4, 0.001));
        let fast = predict_on(&k, &e, 2, &hosts(4, 10.0));
        let bytes_in = 2_500.0 * 48.0 + 10_000.0 * 32.0;
        let bytes_back = 16.0 * e.spans() / 10f64.sqrt() / 4.0;
        assert!(bytes_back > bytes_in);
        assert!(
            (slow.link_s - bytes_back / 125_000.0).abs() < 1e-9,
            "{slow:?}"
        );
        assert!(slow.total_s > fast.total_s + 3.0);
        // The local stages are the ones above the hosts' level: viewxf and the clipper.
        assert!(fast.stages.iter().all(|s| s.stage != "hse"));
    }

    #[test]
    fn splitter_levels_are_paired_from_the_bottom_as_render_sh_runs_them() {
        assert_eq!(splitter_groups(0), Vec::<u8>::new());
        assert_eq!(splitter_groups(1), [1]);
        assert_eq!(splitter_groups(2), [2]);
        assert_eq!(splitter_groups(3), [1, 2]);
        assert_eq!(splitter_groups(6), [2, 2, 2]);
        // Depth 3: the root alone, then nodes 2 and 3 with their children; depth 5: 1 + 2
        // + 8 processes for the 31 nodes.
        let k = constants();
        let node_s = |l: u8| 1.0 + f64::from(l);
        let d3 = splitter_stage(&k, 0, 3, node_s);
        assert_eq!(d3.processes, 3);
        assert_eq!(splitter_stage(&k, 0, 5, node_s).processes, 11);
        // Each of nodes 2 and 3's processes: its own node (2 s) and its two children (3 s
        // each), one start fewer than three processes.
        let pair = 2.0 + 2.0 * 3.0 - 2.0 * k.splitter.process;
        assert_eq!(d3.each_s, pair.max(1.0));
        assert!((d3.total_s - (1.0 + 2.0 * pair)).abs() < 1e-12, "{d3:?}");
    }

    #[test]
    fn starting_processes_is_work_shared_by_the_cores() {
        let mut k = constants();
        k.overheads.process = 0.01;
        let e = env(1, 500, 500, 0.01);
        let p1 = predict(&k, &e, 4, 1);
        let p2 = predict(&k, &e, 4, 2);
        // 23 processes' starts (viewxf, clipbatch, 5 splitters for the 15 nodes, levels
        // paired, 15 leaves, zbuf resolving the sixteenth): 0.23 s on one core, 0.115 s on
        // two, after the script's (and the stages' own 0.05 s of work, halved too).
        assert_eq!(p1.processes, 23);
        let gain = p1.total_s - p2.total_s;
        assert!(gain > 0.115 && gain < 0.165, "{p1:?} {p2:?}");
        assert!(p2.total_s > k.overheads.script + 0.115);
    }

    #[test]
    fn a_sampling_leaf_is_the_merger_at_depth_0_and_a_process_of_its_own_deeper() {
        let k = constants();
        let e = env(1, 500, 500, 0.01);
        // render --aa ssK's graph (bins/render/src/graph.rs, `merger_is_aa_leaf`): at depth
        // 0 viewxf, clipbatch and `zbuf --project --aa ssK`; deeper the splitters, every
        // leaf a process, and zbuf merging.
        let counts: Vec<(usize, usize)> = (0..=3)
            .map(|d| {
                let p = predict_sampled(&k, &e, d, &Target::cores(2));
                (p.processes, p.pipes)
            })
            .collect();
        assert_eq!(counts, [(3, 2), (6, 6), (8, 10), (14, 20)]);
        let p0 = predict_sampled(&k, &e, 0, &Target::cores(2));
        let stage = |name: &str| p0.stages.iter().find(|s| s.stage == name).unwrap().each_s;
        let w = stage_work(&e, false);
        // persp's work, the leaf's and the merger's, in one process.
        let one = k.persp.time(&w.flowing) - k.persp.process + k.hse.time(&w.flowing)
            - k.hse.process
            + k.merge.time(&w.merge);
        assert_eq!(stage("hse"), one);
        assert!(p0
            .stages
            .iter()
            .all(|s| s.stage != "persp" && s.stage != "merge"));
        // Deeper, zbuf resolves no leaf: its work is the merge alone.
        let p2 = predict_sampled(&k, &e, 2, &Target::cores(2));
        let merge = p2.stages.iter().find(|s| s.stage == "merge").unwrap();
        assert_eq!(merge.total_s, k.merge.time(&w.merge));
        // The point-sampled layout is unchanged.
        assert_eq!(predict(&k, &e, 0, 2).processes, 3);
    }

    #[test]
    fn every_pipe_is_work_shared_by_the_cores() {
        let mut k = constants();
        let e = env(1, 500, 500, 0.01);
        // The pipes render's graph makes (bins/render/src/graph.rs) at depths 0 to 5:
        // every process but viewxf reads one, and the merger one from each leaf.
        let counts: Vec<(usize, usize)> = (0..=5)
            .map(|d| {
                let p = predict(&k, &e, d, 2);
                (p.processes, p.pipes)
            })
            .collect();
        assert_eq!(
            counts,
            [(3, 2), (5, 5), (7, 9), (13, 19), (23, 37), (45, 75)]
        );
        let before = predict(&k, &e, 4, 2);
        k.overheads.pipe = 0.001;
        let after = predict(&k, &e, 4, 2);
        // 37 pipes of 1 ms on two cores: 18.5 ms more, the start-up's share of it too.
        assert!(
            (after.total_s - before.total_s - 0.0185).abs() < 1e-9,
            "{before:?} {after:?}"
        );
        assert!((after.overhead_s - before.overhead_s - 0.037).abs() < 1e-9);
        // An older constants file, with no pipe, reads as one of no pipe cost.
        let old = Constants::parse("[overheads]\nscript = 0.01\nprocess = 0.002\n").unwrap();
        assert_eq!(old.overheads.pipe, 0.0);
    }

    #[test]
    fn a_loaded_machine_gives_the_render_one_groups_share() {
        let t = Target::cores(2).loaded(6.0);
        // Six others: 2/7 of a core for the render, whatever its processes.
        assert_eq!(t.shares(4), (2.0 / 7.0, 2.0 / 7.0));
        assert_eq!(t.shares(50), t.shares(4));
        // Half a thread's load on two cores leaves one and a half free.
        assert_eq!(Target::cores(2).loaded(0.5).shares(3), (1.0, 1.5));
        assert_eq!(Target::cores(2).shares(4), (1.0, 2.0));
        // So a loaded machine makes every render slower, the deeper trees (more work in
        // the same share) the most; past a core's share the model takes depth 0.
        let k = constants();
        let e = env(10_000, 1920, 1080, 10.0);
        let quiet: Vec<f64> = (0..=4).map(|d| predict(&k, &e, d, 2).total_s).collect();
        let busy: Vec<f64> = (0..=4).map(|d| predict_on(&k, &e, d, &t).total_s).collect();
        for d in 0..=4 {
            assert!(busy[d] > quiet[d], "{busy:?} {quiet:?}");
        }
        assert!(
            busy[0] / quiet[0] < busy[4] / quiet[4],
            "{busy:?} {quiet:?}"
        );
        let (depth, reason, _) = choose_depth_on(&k, &e, &t, 6);
        assert_eq!(depth, 0, "{reason}");
        assert!(
            reason.contains(", 2 cores, load 6.0: predicted "),
            "{reason}"
        );
    }

    #[test]
    fn cut_polygons_are_counted_on_both_sides() {
        // The bench's fill-heavy scene: 5,157 polygons in view, Dc 10.14, 1920x1080.
        let e = Environment {
            frames: 1,
            polygons: 9_999,
            vertices: 39_996,
            relevant: 5_157,
            relevant_vertices: 20_628,
            area: 1920.0 * 1080.0 * 10.14,
            width: 1920,
            height: 1080,
            text: true,
        };
        let each = |l: u8| 5_157.0 / (1u64 << l) as f64 * cut_growth(&e, l);
        // Measured (render.sh --depth 3 --stats): 2,656, 1,428 and 772 a node on average.
        for (l, measured) in [(1, 2_656.0), (2, 1_428.0), (3, 772.0)] {
            assert!(
                (each(l) / measured - 1.0).abs() < 0.03,
                "level {l}: {}",
                each(l)
            );
        }
        assert_eq!(cut_growth(&e, 0), 1.0);
        // Two polygons in view: a big one is cut by every plane, at most doubling.
        let two = env(1, 500, 500, 0.5);
        assert!(cut_growth(&two, 3) <= 8.0);
    }

    #[test]
    fn constants_round_trip_through_toml() {
        let k = constants();
        assert_eq!(Constants::parse(&k.to_toml().unwrap()).unwrap(), k);
    }
}
