//! The process graph of a render, worked out from the options: the stages the launcher
//! ([`crate::launch`]) starts, each with its input, output and command line, the way
//! occam's PAR wires channels (thesis chapter 6.3, CLIPPER/SPLITTER; docs/DESIGN.md,
//! "The splitter tree"):
//!
//! ```text
//! viewxf | clipbatch (the six planes; --clip chain: clipplane left | right | … | yon)
//!   depth 0:  | zbuf (which projects, scan-converts and resolves the one leaf)
//!   depth N:  | a binary tree of splitter nodes, N levels, each node computing its own
//!             plane from its number (`splitter --node K`); persp | scanconv --resolve
//!             (or --hse's method) on each of the 2^N leaves; one zbuf placing the
//!             leaves' finished regions (--merge buffer: persp | scanconv on each leaf,
//!             every fragment depth-tested in the one zbuf, the thesis's PAR.BUFF).
//! ```
//!
//! The graph only wires: the stages check their own options, compute their own planes
//! and label their own --stats lines.

use crate::launch::{End, Stage};
use crate::options::{Clip, Merge, Options, Scene};
use stagecli::DepthArg;
use std::ffi::OsString;
use std::path::{Path, PathBuf};

/// The stages that take the depth form, and how each is told it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ZStage {
    /// persp: eye space to the screen.
    Persp,
    /// zbuf and splitter, projecting the stream themselves (persp's code).
    Projecting,
}

/// The words that tell `stage` the depth form `mode` (thesis 4.2's reciprocal depth,
/// the classic projective one, or eye-space z): `persp --zmode MODE`, and for a zbuf
/// or splitter that projects, `--project --zmode MODE`. The one place the spelling is
/// written.
pub fn zmode_words(stage: ZStage, mode: DepthArg) -> Vec<String> {
    let mode = mode.name();
    match stage {
        ZStage::Persp => vec!["--zmode".into(), mode.into()],
        ZStage::Projecting => vec!["--project".into(), "--zmode".into(), mode.into()],
    }
}

/// What the graph is built from besides the options.
pub struct Context<'a> {
    /// The stage binaries' folder.
    pub bin: &'a Path,
    /// The tree's depth, decided (auto resolved).
    pub depth: u32,
    /// The command that reaches a host (`POLYPIPE_SSH`, or ssh), for --hosts.
    pub ssh: &'a [String],
    /// The repository, whose scripts/render.sh the hosts run (at the same path).
    pub root: &'a Path,
    /// Whether viewxf reads the scene from the launcher's feed (a sample kept in
    /// memory, then the rest of the stream) rather than from the scene itself.
    pub fed: bool,
}

struct Builder<'a> {
    o: &'a Options,
    c: &'a Context<'a>,
    stages: Vec<Stage>,
    /// Each tree node's input: node K (numbered as a heap, root 1) reads input_of[K].
    input_of: std::collections::HashMap<u64, End>,
    /// Whether the tree's last level projects to the screen (`splitter --project`).
    projected: bool,
    /// The merger's own projection, at depth 0 (zbuf reads the clipper's stream).
    to_screen: Vec<String>,
    /// The channels the merger reads.
    fragments: Vec<String>,
}

fn pipe(name: impl Into<String>) -> End {
    End::Pipe(name.into())
}

fn os(words: impl IntoIterator<Item = impl Into<OsString>>) -> Vec<OsString> {
    words.into_iter().map(Into::into).collect()
}

/// The graph's stages, from the scene (or, for --subtree K, the stream into node K on
/// stdin) to the frames on stdout.
pub fn build(o: &Options, c: &Context) -> Vec<Stage> {
    let mut b = Builder {
        o,
        c,
        stages: Vec::new(),
        input_of: Default::default(),
        projected: false,
        to_screen: Vec::new(),
        fragments: Vec::new(),
    };
    let clipped = if o.subtree.is_some() {
        End::Inherit // the stream into node K
    } else {
        b.clipper_chain()
    };
    if o.hidden_line {
        b.hidden_line(clipped);
    } else {
        b.graph(clipped);
    }
    b.stages
}

/// The clipper chain alone (viewxf and the clipper, their output the channel
/// `clipped`): the stages `render --depth auto` starts while it looks at the scene, which
/// are [`build`]'s first stages at any depth (the channel out of them is `leaf-0` where
/// the merger reads it itself).
pub fn chain(o: &Options, c: &Context) -> Vec<Stage> {
    let provisional = Context { depth: 1, ..*c };
    let mut b = Builder {
        o,
        c: &provisional,
        stages: Vec::new(),
        input_of: Default::default(),
        projected: false,
        to_screen: Vec::new(),
        fragments: Vec::new(),
    };
    b.clipper_chain();
    b.stages
}

impl Builder<'_> {
    fn bin(&self, name: &str) -> OsString {
        self.c.bin.join(name).into_os_string()
    }

    fn start(&mut self, label: impl Into<String>, input: End, output: End, argv: Vec<OsString>) {
        self.start_named(label, input, output, argv, 0, None);
    }

    /// A stage whose last `pipes` words are channel names (given it as /dev/fd/N).
    fn start_named(
        &mut self,
        label: impl Into<String>,
        input: End,
        output: End,
        argv: Vec<OsString>,
        pipes: usize,
        host: Option<(String, u64)>,
    ) {
        self.stages.push(Stage {
            label: label.into(),
            input,
            output,
            host,
            argv,
            pipes,
        });
    }

    fn stats(&self) -> Vec<OsString> {
        if self.o.stats {
            os(["--stats"])
        } else {
            Vec::new()
        }
    }

    /// Whether the merger resolves leaf 0 itself: zbuf reads screen-space polygons and
    /// resolves them as `scanconv --resolve` does (the same code, scan's), into its frame
    /// with no runs encoded, piped and decoded, and a process fewer. At depth 0 that leaf
    /// is the whole screen: zbuf reads the clipper's stream and projects it too, so that
    /// depth 0 is viewxf | clipbatch | zbuf. In a tree, the last level's first splitter
    /// writes leaf 0's polygons, projected, straight to zbuf. Only for the leaves'
    /// point-sampled z-buffer with --merge tiles, the leaves here (docs/performance.md,
    /// "Start-up" and "The tree's depth").
    fn merger_is_leaf(&self) -> bool {
        let o = self.o;
        o.hse == "zbuf"
            && o.aa == "none"
            && o.merge == Merge::Tiles
            && o.subtree.is_none()
            && o.hosts.is_empty()
    }

    /// Whether the merger resolves the whole screen with the anti-aliasing leaf's method:
    /// at depth 0, with --merge tiles, every `--aa` mode runs as `zbuf --project --aa
    /// MODE`, the leaf's method in the merger's process as the point-sampled z-buffer's
    /// is ([`Builder::merger_is_leaf`]), so that depth 0 is viewxf | clipbatch | zbuf for
    /// them too: persp's and the leaf's processes, and the runs encoded, piped and
    /// decoded, fewer (docs/performance.md, "Start-up"). Deeper, every anti-aliasing
    /// leaf is a process of its own.
    fn merger_is_aa_leaf(&self) -> bool {
        let o = self.o;
        self.c.depth == 0
            && o.aa != "none"
            && o.merge == Merge::Tiles
            && o.subtree.is_none()
            && o.hosts.is_empty()
    }

    /// The clipper chain: viewxf and the six planes of the pyramid (chapter 3). Returns
    /// the clipped stream: at depth 0 with the merger the leaf, the merger's `leaf-0`.
    fn clipper_chain(&mut self) -> End {
        let out = if self.c.depth == 0 && (self.merger_is_leaf() || self.merger_is_aa_leaf()) {
            "leaf-0"
        } else {
            "clipped"
        };
        let scene = match (&self.o.scene, self.c.fed) {
            (_, true) | (Scene::Stdin, _) => End::Inherit,
            (Scene::Path(p), false) => End::Path(p.clone()),
        };
        let mut argv = os([self.bin("viewxf")]);
        argv.extend(os(["--size", &self.o.size]));
        argv.extend(os(self.o.camera.iter()));
        self.start("viewxf", scene, pipe("view"), argv);
        if self.o.clip == Clip::Batch {
            self.start(
                "clipbatch",
                pipe("view"),
                pipe(out),
                os([self.bin("clipbatch")]),
            );
            return pipe(out);
        }
        let mut input = pipe("view");
        for plane in ["left", "right", "top", "bottom", "hither", "yon"] {
            let to = if plane == "yon" {
                pipe(out)
            } else {
                pipe(format!("clip-{plane}"))
            };
            let argv = os([self.bin("clipplane"), plane.into()]);
            self.start(format!("clipplane {plane}"), input, to.clone(), argv);
            input = to;
        }
        input
    }

    /// The splitters of `root`'s subtree numbered below `below` (2^depth for the whole
    /// tree; less when subtrees go to other hosts), reading input_of[root]. Returns the
    /// nodes their outputs feed: the leaves' inputs, or the subtrees'. With `leaves`
    /// (leaves started here follow), the last level projects its outputs to the screen
    /// (`splitter --project`), as a persp at each leaf would: a process a leaf fewer
    /// (docs/performance.md, "The tree's depth").
    ///
    /// The nodes run two levels to a process (`splitter --node K --levels 2`, node K and
    /// its two children, writing its four grandchildren's streams), the levels paired
    /// from the bottom, so that an odd count leaves the top level's nodes alone: the same
    /// streams out, with a process and a stream's encoding and decoding fewer a pair.
    /// Depth 2 is one splitter; depth 3 the root and two pairs.
    fn tree(&mut self, root: u64, below: u64, leaves: bool) -> Vec<u64> {
        let depth = self.c.depth;
        self.projected = false;
        let mut levels = 0;
        let mut first = root;
        while first < below {
            levels += 1;
            first *= 2;
        }
        let (mut first, mut n) = (root, 1u64);
        let mut to_screen = Vec::new();
        while first < below {
            // This group of levels: one level if an odd number are left, else two.
            let span = if levels % 2 == 1 { 1 } else { 2 };
            levels -= span;
            let group = 1u64 << span;
            if leaves && first * group >= below {
                to_screen = zmode_words(ZStage::Projecting, self.o.zmode);
                self.projected = true;
            }
            for node in first..first + n {
                let mut outputs: Vec<OsString> = Vec::new();
                let mut into = End::Path(PathBuf::from("/dev/null"));
                let mut named = group as usize;
                for k in node * group..(node + 1) * group {
                    let name = format!("node-{k}");
                    self.input_of.insert(k, pipe(&name));
                    let mut out = OsString::from(name);
                    if self.projected && k == 1 << depth && self.merger_is_leaf() {
                        // Leaf 0's polygons go to the merger, which resolves them
                        // itself: that output is the splitter's stdout.
                        self.input_of.insert(k, pipe("leaf-0"));
                        out = "-".into();
                        into = pipe("leaf-0");
                        named = group as usize - 1;
                    }
                    outputs.push(out);
                }
                let mut label = format!("node {node}");
                if span != 1 {
                    label += &format!(", {span} levels");
                }
                let mut argv = os([self.bin("splitter")]);
                argv.extend(self.stats());
                argv.extend(os([
                    "--node".to_string(),
                    node.to_string(),
                    "--depth".into(),
                    depth.to_string(),
                    "--levels".into(),
                    span.to_string(),
                    "--size".into(),
                    self.o.size.clone(),
                ]));
                argv.extend(os(to_screen.iter()));
                argv.extend(outputs);
                let input = self.input_of[&node].clone();
                self.start_named(
                    format!("splitter ({label})"),
                    input,
                    into,
                    argv,
                    named,
                    None,
                );
            }
            first *= group;
            n *= group;
        }
        (first..first + n).collect()
    }

    /// The hidden-surface stage at each leaf, as --merge, --hse and --aa choose it: the
    /// binary's name, then its options. By default scanconv resolves its region with a
    /// z-buffer; --merge buffer sends fragments on for the one zbuf to test (PAR.BUFF).
    fn method(&self) -> Vec<String> {
        method(self.o)
    }

    /// Leaf `leaf` (0 .. 2^depth − 1), persp | METHOD, from `input` to `output`; only
    /// METHOD where the splitter above projected.
    fn leaf(&mut self, leaf: u64, mut input: End, output: End) {
        let label = if self.c.depth == 0 {
            String::new()
        } else {
            format!(" (leaf {leaf})")
        };
        if !self.projected {
            let screen = pipe(format!("screen-{leaf}"));
            let mut argv = os([self.bin("persp")]);
            argv.extend(os(["--size", &self.o.size]));
            argv.extend(os(zmode_words(ZStage::Persp, self.o.zmode)));
            self.start(format!("persp{label}"), input, screen.clone(), argv);
            input = screen;
        }
        let method = self.method();
        let mut argv = os([self.bin(&method[0])]);
        argv.extend(os(method[1..].iter()));
        argv.extend(self.stats());
        self.start(format!("{}{label}", method[0]), input, output, argv);
    }

    /// A leaf for each of `frontier` (all leaves' inputs), each into a channel the merger
    /// reads; or, given `to`, the one leaf into `to`.
    fn leaves(&mut self, frontier: &[u64], to: Option<End>) {
        let depth = self.c.depth;
        for &node in frontier {
            let leaf = node - (1 << depth);
            let input = self.input_of[&node].clone();
            if let Some(to) = &to {
                self.leaf(leaf, input, to.clone());
            } else if input == pipe("leaf-0") {
                self.fragments.push("leaf-0".into()); // the merger's own
                if depth == 0 {
                    // The clipper's eye-space stream: the merger projects it too.
                    self.to_screen = zmode_words(ZStage::Projecting, self.o.zmode);
                    self.to_screen
                        .extend(["--size".into(), self.o.size.clone()]);
                    if self.merger_is_aa_leaf() {
                        self.to_screen.extend(["--aa".into(), self.o.aa.clone()]);
                    }
                }
            } else {
                let name = format!("leaf-{leaf}");
                self.fragments.push(name.clone());
                self.leaf(leaf, input, pipe(name));
            }
        }
    }

    /// The level of the tree whose subtrees go to the hosts: the first with at least
    /// one subtree a host, or the leaves'.
    fn host_level(&self) -> u32 {
        let mut level = 0;
        while level < self.c.depth && (1usize << level) < self.o.hosts.len() {
            level += 1;
        }
        level
    }

    /// Each node of `frontier` and all below it on a host, round-robin, through ssh
    /// (docs/DESIGN.md, "Stages on other hosts"): the stream into the node goes down the
    /// ssh channel to `render.sh --subtree K` there, which runs the node's splitters and
    /// leaves and merges their runs (zbuf --runs); the runs come back up it into a
    /// channel the merger here reads. render.sh is run from the same path there as here,
    /// its binaries from --remote-bin (default: this one's). When ssh goes (the host
    /// drops, or the run is stopped), the far side's input ends short and its output has
    /// no reader: it stops.
    fn subtrees(&mut self, frontier: &[u64]) {
        let o = self.o;
        let dir = o
            .remote_bin
            .clone()
            .unwrap_or_else(|| self.c.bin.display().to_string());
        for (i, &node) in frontier.iter().enumerate() {
            let host = o.hosts[i % o.hosts.len()].clone();
            let mut words = vec![
                "env".to_string(),
                format!("POLYPIPE_BIN={dir}"),
                self.c.root.join("scripts/render.sh").display().to_string(),
                "--subtree".into(),
                node.to_string(),
                "--depth".into(),
                self.c.depth.to_string(),
                "--size".into(),
                o.size.clone(),
                "--zmode".into(),
                o.zmode.name().into(),
                "--hse".into(),
                o.hse.clone(),
            ];
            if o.split {
                words.push("--split".into());
            }
            words.extend(["--aa".into(), o.aa.clone()]);
            if o.stats {
                words.push("--stats".into());
            }
            let mut argv = os(self.c.ssh.iter());
            argv.push(host.clone().into());
            argv.push(stagecli::remote::remote_command(&words).into());
            let from = format!("from-{node}");
            self.fragments.push(from.clone());
            let label = format!(
                "{} (host {host})",
                crate::launch::what_node(node, self.c.depth)
            );
            let input = self.input_of[&node].clone();
            self.start_named(label, input, pipe(from), argv, 0, Some((host, node)));
        }
    }

    /// The tree and its leaves, here or on the hosts, and the merger: from `clipped` (or,
    /// for --subtree K, from stdin into node K) to stdout.
    fn graph(&mut self, clipped: End) {
        let depth = self.c.depth;
        let top = self.o.subtree.unwrap_or(1);
        self.input_of.insert(top, clipped);
        if !self.o.hosts.is_empty() {
            let frontier = self.tree(1, 1 << self.host_level(), false);
            self.subtrees(&frontier);
        } else {
            let frontier = self.tree(top, 1 << depth, true);
            if frontier.len() == 1 && self.o.subtree.is_some() {
                // One leaf: its runs are the subtree's.
                self.leaves(&frontier, Some(End::Inherit));
                return;
            }
            self.leaves(&frontier, None);
        }
        self.merger();
    }

    /// The merger (chapter 6.3.3): one zbuf reading every leaf, writing the frames.
    fn merger(&mut self) {
        let o = self.o;
        let mut argv = os([self.bin("zbuf")]);
        if o.subtree.is_some() {
            argv.push("--runs".into()); // a subtree's runs go on to the merger above
        }
        argv.extend(self.stats());
        argv.extend(os(self.to_screen.iter()));
        if let Some(pattern) = &o.output {
            argv.extend(os(["-o", pattern]));
        }
        if let Some(n) = o.first_frame {
            argv.extend(os(["--first-frame".to_string(), n.to_string()]));
        }
        let n = self.fragments.len();
        argv.extend(os(self.fragments.iter()));
        let null = End::Path(PathBuf::from("/dev/null"));
        self.start_named("zbuf", null, End::Inherit, argv, n, None);
    }

    /// --hidden-line: persp | hiddenline, writing the SVG (Archuleta's output) where -o
    /// says.
    fn hidden_line(&mut self, clipped: End) {
        let mut argv = os([self.bin("persp")]);
        argv.extend(os(["--size", &self.o.size]));
        argv.extend(os(zmode_words(ZStage::Persp, self.o.zmode)));
        self.start("persp", clipped, pipe("screen"), argv);
        // The row of the table of methods that --hidden-line-method selects.
        let o = self.o;
        let stage = &o.leaf;
        let mut argv = os([self.bin(&stage[0])]);
        argv.extend(os(stage[1..].iter()));
        argv.extend(self.stats());
        if let Some(pattern) = &self.o.output {
            argv.extend(os(["-o", pattern]));
        }
        self.start(stage[0].clone(), pipe("screen"), End::Inherit, argv);
    }
}

/// The leaves' hidden-surface stage for these options: the binary's name, then its
/// options (see [`Builder::method`]): the row of the table of methods that --aa or
/// --hse selects (`methods::METHODS`), or with --merge buffer scanconv's fragments.
pub fn method(o: &Options) -> Vec<String> {
    let words = |w: &[&str]| w.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    if o.merge == Merge::Buffer {
        let mut m = words(&["scanconv"]);
        if o.pixels {
            m.push("--pixels".into());
        }
        m
    } else {
        // The row of the table of methods that --aa, else --hse, selects.
        let mut m = o.leaf.clone();
        if o.split {
            m.push("--split".into());
        }
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::options::{parse, Parsed};

    fn graph(args: &[&str], depth: u32) -> Vec<String> {
        let args = std::iter::once("render")
            .chain(args.iter().copied())
            .map(OsString::from);
        let Ok(Parsed::Run(cli)) = parse(args) else {
            panic!("options")
        };
        let hosts = cli
            .hosts
            .as_deref()
            .map(|h| stagecli::remote::parse_hosts(h).unwrap())
            .unwrap_or_default();
        let o = cli.validate(hosts, false).unwrap();
        let ssh = vec!["ssh".to_string()];
        let c = Context {
            bin: Path::new("/b"),
            depth,
            ssh: &ssh,
            root: Path::new("/r"),
            fed: false,
        };
        let end = |e: &End| match e {
            End::Inherit => "-".to_string(),
            End::Path(p) => p.display().to_string(),
            End::Pipe(n) => format!("|{n}"),
        };
        build(&o, &c)
            .iter()
            .map(|s| {
                let argv: Vec<String> = s
                    .argv
                    .iter()
                    .map(|w| w.to_string_lossy().replace("/b/", ""))
                    .collect();
                format!(
                    "{}: {} > {}: {} [{}]",
                    s.label,
                    end(&s.input),
                    end(&s.output),
                    argv.join(" "),
                    s.pipes
                )
            })
            .collect()
    }

    #[test]
    fn depth_0_is_viewxf_clipbatch_and_the_projecting_merger() {
        assert_eq!(
            graph(&["--size", "64x64", "s.txt"], 0),
            [
                "viewxf: s.txt > |view: viewxf --size 64x64 [0]",
                "clipbatch: |view > |leaf-0: clipbatch [0]",
                "zbuf: /dev/null > -: zbuf --project --zmode reciprocal --size 64x64 leaf-0 [1]",
            ]
        );
    }

    #[test]
    fn anti_aliasing_at_depth_0_is_the_merger_and_deeper_a_leaf_of_its_own() {
        for aa in ["ss4", "adaptive2", "abuf"] {
            assert_eq!(
                graph(&["--size", "64x64", "--aa", aa, "--stats", "s.txt"], 0),
                [
                    "viewxf: s.txt > |view: viewxf --size 64x64 [0]".to_string(),
                    "clipbatch: |view > |leaf-0: clipbatch [0]".into(),
                    format!(
                        "zbuf: /dev/null > -: zbuf --stats --project --zmode reciprocal --size \
                         64x64 --aa {aa} leaf-0 [1]"
                    ),
                ]
            );
        }
        let g = graph(&["--size", "64x64", "--aa", "adaptive4", "s.txt"], 1);
        assert_eq!(
            g[3..],
            [
                "supersample (leaf 0): |node-2 > |leaf-0: supersample --samples 4 --adaptive [0]",
                "supersample (leaf 1): |node-3 > |leaf-1: supersample --samples 4 --adaptive [0]",
                "zbuf: /dev/null > -: zbuf leaf-0 leaf-1 [2]",
            ]
        );
        // --merge buffer's leaves send fragments: no anti-aliasing there to take in.
        let g = graph(&["--merge", "buffer", "s"], 0);
        assert_eq!(g[3], "scanconv: |screen-0 > |leaf-0: scanconv [0]");
    }

    #[test]
    fn depth_3_pairs_the_lower_levels_and_projects_at_the_last() {
        let g = graph(&["--stats", "-"], 3);
        assert_eq!(
            g[..5],
            [
                "viewxf: - > |view: viewxf --size 500x500 [0]",
                "clipbatch: |view > |clipped: clipbatch [0]",
                "splitter (node 1): |clipped > /dev/null: splitter --stats --node 1 --depth 3 --levels 1 --size 500x500 node-2 node-3 [2]",
                "splitter (node 2, 2 levels): |node-2 > |leaf-0: splitter --stats --node 2 --depth 3 --levels 2 --size 500x500 --project --zmode reciprocal - node-9 node-10 node-11 [3]",
                "splitter (node 3, 2 levels): |node-3 > /dev/null: splitter --stats --node 3 --depth 3 --levels 2 --size 500x500 --project --zmode reciprocal node-12 node-13 node-14 node-15 [4]",
            ]
        );
        assert_eq!(
            g[5],
            "scanconv (leaf 1): |node-9 > |leaf-1: scanconv --resolve --stats [0]"
        );
        assert_eq!(
            g.last().unwrap(),
            "zbuf: /dev/null > -: zbuf --stats leaf-0 leaf-1 leaf-2 leaf-3 leaf-4 leaf-5 leaf-6 leaf-7 [8]"
        );
        assert_eq!(g.len(), 13);
    }

    #[test]
    fn the_chain_buffer_merge_and_a_leaf_method() {
        let g = graph(
            &["--clip", "chain", "--merge", "buffer", "--pixels", "s"],
            1,
        );
        assert_eq!(
            g[2],
            "clipplane right: |clip-left > |clip-right: clipplane right [0]"
        );
        assert_eq!(
            g[6],
            "clipplane yon: |clip-hither > |clipped: clipplane yon [0]"
        );
        assert_eq!(
            g[8],
            "scanconv (leaf 0): |node-2 > |leaf-0: scanconv --pixels [0]"
        );
        let g = graph(&["--hse", "painter", "--split", "--zmode", "eye-z", "s"], 0);
        assert_eq!(
            g[2..],
            [
                "persp: |clipped > |screen-0: persp --size 500x500 --zmode eye-z [0]",
                "painter: |screen-0 > |leaf-0: painter --split [0]",
                "zbuf: /dev/null > -: zbuf leaf-0 [1]",
            ]
        );
    }

    #[test]
    fn hosts_get_subtrees_through_ssh_and_a_subtree_is_a_hosts_part() {
        let g = graph(
            &["--hosts", "a,b", "--first-frame", "5", "-o", "f%d.png", "s"],
            2,
        );
        assert_eq!(
            g[3],
            "subtree 2 (host a): |node-2 > |from-2: ssh a exec 'env' 'POLYPIPE_BIN=/b' '/r/scripts/render.sh' '--subtree' '2' '--depth' '2' '--size' '500x500' '--zmode' 'reciprocal' '--hse' 'zbuf' '--aa' 'none' [0]"
        );
        assert_eq!(
            g[5],
            "zbuf: /dev/null > -: zbuf -o f%d.png --first-frame 5 from-2 from-3 [2]"
        );
        let g = graph(&["--subtree", "3", "--depth", "2"], 2);
        assert_eq!(
            g,
            [
                "splitter (node 3): - > /dev/null: splitter --node 3 --depth 2 --levels 1 --size 500x500 --project --zmode reciprocal node-6 node-7 [2]",
                "scanconv (leaf 2): |node-6 > |leaf-2: scanconv --resolve [0]",
                "scanconv (leaf 3): |node-7 > |leaf-3: scanconv --resolve [0]",
                "zbuf: /dev/null > -: zbuf --runs leaf-2 leaf-3 [2]",
            ]
        );
    }

    #[test]
    fn the_chain_started_early_is_the_graphs_first_stages_at_every_depth() {
        for args in [
            &["s.txt"][..],
            &["--clip", "chain", "-"],
            &["--hse", "painter", "s"],
        ] {
            let args = std::iter::once("render")
                .chain(args.iter().copied())
                .map(OsString::from);
            let Ok(Parsed::Run(cli)) = parse(args) else {
                panic!("options")
            };
            let o = cli.validate(Vec::new(), false).unwrap();
            let c = |depth| Context {
                bin: Path::new("/b"),
                depth,
                ssh: &[],
                root: Path::new("/r"),
                fed: false,
            };
            let early = chain(&o, &c(0));
            assert_eq!(early.last().unwrap().output, pipe("clipped"));
            for depth in 0..4 {
                let full = build(&o, &c(depth));
                for (e, f) in early.iter().zip(&full) {
                    assert_eq!((&e.label, &e.argv, &e.input), (&f.label, &f.argv, &f.input));
                }
                assert!(full.len() > early.len());
            }
        }
    }
}
