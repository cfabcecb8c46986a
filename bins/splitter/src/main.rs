//! splitter: one node of the splitter tree (thesis chapter 6.2), eye space in, two
//! eye-space streams out (or, with --project, two screen-space ones).

use clap::Parser;
use proto::perspective::Perspective;
use proto::{Space, SpaceKind, Token};
use splitter::{Lean, SplitPlane, Subtree, Tree};
use stagecli::{Branch, DepthArg, Error, ProjectArgs, TextFlag};
use std::process::ExitCode;

/// A splitter node (thesis chapter 6.2): splits every polygon of an eye-space stream
/// about a plane through the eye.
///
/// OUT1 receives the part where x_e ≤ K·a·w (for `x=K`; the screen left of x_s = K) or
/// y_e ≤ K·w (for `y=K`; the screen below y_s = K), OUT2 the rest. Both outputs get every
/// polygon (empty where it lies wholly on the other side, so polygon k is the same
/// polygon on both branches) and every NEXT.FRAME and END. OUT1 and OUT2 are files or
/// named pipes; `-` is stdout, for at most one of them, and they must be two files. When
/// one output's reader goes away, the other still gets the whole stream.
///
/// With `--project` the two outputs are projected to the screen, as `persp --size WxH
/// --zmode MODE` after each would project them (`--zmode`, default reciprocal): what
/// render.sh asks of the tree's last level, whose outputs are the leaves', so that a leaf
/// needs no persp process of its own.
///
/// With `--levels L` the process is node K and the nodes below it, L levels deep: the
/// outputs are the streams of the 2^L nodes L levels below K, left to right, the bytes
/// that many levels of node processes would send them, without the processes or the
/// streams between them. render.sh runs its trees two levels to a process.
#[derive(Parser, Debug)]
#[command(
    name = "splitter",
    version,
    override_usage = "splitter [OPTIONS] PLANE OUT1 OUT2\n       \
        splitter [OPTIONS] --node K --depth N --size WxH OUT1 OUT2\n       \
        splitter [OPTIONS] --node K --depth N --levels L --size WxH OUT1 … OUT(2^L)\n       \
        splitter [OPTIONS] --plane a,b,c,d,k OUT1 OUT2",
    after_help = "Examples:\n  \
        mkfifo left right\n  \
        viewxf < scene.txt | clipplane left | ... | clipplane yon | splitter x=0 left right\n  \
        splitter y=0.5 low - < eye.txt --text      # the upper part to stdout\n  \
        splitter --node 2 --depth 2 --size 500x500 a b  # node 2 of render.sh --depth 2\n  \
        splitter --plane 1,0,0,-0.5,0 a b < eye.txt  # x_e - 0.5 w >= 0 to a\n  \
        splitter --node 2 --depth 2 --size 500x500 --project a b  # to the leaves\n  \
        splitter --node 1 --depth 2 --levels 2 --size 500x500 a b c d  # nodes 1, 2 and 3"
)]
struct Cli {
    /// `x=K` or `y=K` (K in [-1, 1]), then OUT1 and OUT2; with --plane or --node, only
    /// OUT1 OUT2; with --levels L, the 2^L outputs.
    #[arg(value_name = "ARGS", num_args = 2.., required = true)]
    args: Vec<String>,
    /// A general plane a·x_e + b·y_e + c·z_e + d·w + k = 0, as `a,b,c,d,k`; OUT1 gets
    /// the side where it is ≥ 0.
    #[arg(long, value_name = "a,b,c,d,k", allow_hyphen_values = true)]
    plane: Option<String>,
    /// Node K of a splitter tree (thesis 6.3) numbered as a heap (root 1, children 2K
    /// and 2K+1): the node bisects its region of the screen on a pixel boundary, levels
    /// alternating x then y; `--stats` names it `splitter x=K (node K)`.
    #[arg(long, value_name = "K", requires_all = ["depth", "size"], conflicts_with = "plane",
          value_parser = stagecli::numbers::whole::<u32>(1, (1 << splitter::MAX_TREE_DEPTH) - 1))]
    node: Option<u32>,
    /// The tree's depth, for --node: nodes 1 to 2^N − 1 split.
    #[arg(long, value_name = "N", requires = "node",
          value_parser = stagecli::numbers::whole::<u32>(1, splitter::MAX_TREE_DEPTH as u64))]
    depth: Option<u32>,
    /// For --node: node K and the nodes below it, L levels deep, in this one process
    /// (default 1: node K alone); the outputs are those of the level L below K's.
    #[arg(long, value_name = "L", requires = "node", default_value_t = 1,
          value_parser = stagecli::numbers::whole::<u32>(1, splitter::MAX_TREE_DEPTH as u64))]
    levels: u32,
    /// The screen's size in pixels, for --node and --project.
    #[arg(long, value_name = "WxH")]
    size: Option<String>,
    #[command(flatten)]
    project: ProjectArgs,
    #[command(flatten)]
    text: TextFlag,
    /// At END, print on stderr the polygons in and the non-empty polygons and vertices
    /// sent to each output.
    #[arg(long)]
    stats: bool,
}

/// The nodes a process is, level by level (level j has 2^j), each with its number in
/// the tree (with --node) for its --stats label.
type Nodes = Vec<Vec<(SplitPlane, Option<u32>)>>;

/// What the arguments ask, checked before any input is read.
struct Plan {
    nodes: Nodes,
    /// The outputs, left to right: two per node of the last level.
    outputs: Vec<String>,
    /// The screen's size (--size), in pixels.
    size: Option<(u32, u32)>,
    /// With --project: the depth the outputs carry.
    depth: Option<DepthArg>,
}

fn plan(cli: &Cli) -> Result<Plan, Error> {
    let depth = cli.project.depth("splitter")?;
    let size = match cli.size.as_deref() {
        Some(size) => Some(
            proto::camera::parse_size(size)
                .map_err(|m| Error::usage(format!("--size {size}: {m}")))?,
        ),
        None => None,
    };
    if size.is_some() && cli.node.is_none() && depth.is_none() {
        return Err(Error::usage("--size is for --node or --project"));
    }
    let tree_nodes = match (cli.node, size) {
        (Some(node), Some((width, height))) => Some(subtree(
            Tree { width, height },
            node,
            cli.depth.unwrap_or_default(),
            cli.levels,
        )?),
        _ => None,
    };
    let one = |plane: Result<SplitPlane, String>| -> Result<_, Error> {
        Ok(vec![vec![(plane.map_err(Error::usage)?, None)]])
    };
    let (nodes, outputs) = match (&cli.plane, cli.args.as_slice(), tree_nodes) {
        (None, args, Some(nodes)) if args.len() == 2 << (nodes.len() - 1) => (nodes, args.to_vec()),
        (None, args, Some(nodes)) => {
            return Err(Error::usage(if nodes.len() == 1 {
                "with --node, give only OUT1 and OUT2".to_string()
            } else {
                format!(
                    "with --node and --levels {}, give the {} outputs, left to right ({} given)",
                    nodes.len(),
                    2 << (nodes.len() - 1),
                    args.len()
                )
            }))
        }
        (Some(general), [out1, out2], None) => (
            one(SplitPlane::parse_general(general).map_err(|m| format!("--plane {general}: {m}")))?,
            vec![out1.clone(), out2.clone()],
        ),
        (None, [plane, out1, out2], None) => (
            one(plane.parse::<SplitPlane>())?,
            vec![out1.clone(), out2.clone()],
        ),
        (Some(_), _, _) => return Err(Error::usage("with --plane, give only OUT1 and OUT2")),
        (None, _, None) => {
            return Err(Error::usage(
                "expected PLANE OUT1 OUT2, e.g. `splitter x=0 left right`",
            ))
        }
    };
    if outputs.iter().filter(|o| *o == "-").count() > 1 {
        return Err(Error::usage(if outputs.len() == 2 {
            "at most one of OUT1 and OUT2 may be `-` (stdout)"
        } else {
            "at most one output may be `-` (stdout)"
        }));
    }
    for (i, a) in outputs.iter().enumerate() {
        for (j, b) in outputs.iter().enumerate().skip(i + 1) {
            if stagecli::same_file(a, b) {
                let (na, nb) = (format!("OUT{}", i + 1), format!("OUT{}", j + 1));
                return Err(Error::usage(format!(
                    "{na} {a} and {nb} {b} are one file: the two streams would be mixed in it"
                )));
            }
        }
    }
    Ok(Plan {
        nodes,
        outputs,
        size,
        depth,
    })
}

/// The planes of node `node` of a depth-`depth` tree and of the nodes below it, `levels`
/// levels deep (node K's level j: nodes K·2^j to K·2^j + 2^j − 1), each with its number.
fn subtree(tree: Tree, node: u32, depth: u32, levels: u32) -> Result<Nodes, Error> {
    Tree::check_node(node, depth).map_err(Error::usage)?;
    if !(1..=splitter::MAX_TREE_DEPTH).contains(&levels) {
        return Err(Error::usage(format!(
            "--levels {levels}: a process is 1 to {} levels of nodes",
            splitter::MAX_TREE_DEPTH
        )));
    }
    // The last level's last node, (K + 1)·2^(L−1) − 1, must be a splitter node too:
    // under 2^depth.
    if (u64::from(node) + 1) << (levels - 1) > 1u64 << depth {
        return Err(Error::usage(format!(
            "--levels {levels}: node {node} and the nodes below it, {levels} levels deep, \
             are not all splitter nodes of a depth-{depth} tree (nodes 1 to {})",
            (1u64 << depth) - 1
        )));
    }
    Ok((0..levels)
        .map(|j| {
            let first = node << j;
            (first..first + (1 << j))
                .map(|n| (tree.plane(n), Some(n)))
                .collect()
        })
        .collect())
}

fn main() -> ExitCode {
    stagecli::main("splitter", |cli: Cli| {
        let Plan {
            nodes,
            outputs,
            size,
            depth,
        } = plan(&cli)?;
        let mut reader = stagecli::read_stdin::<Token>(SpaceKind::Eye)?;
        let header = *reader.header();
        let Space::Eye(view) = header.space else {
            unreachable!("the reader checked the space")
        };
        let mut tree = Subtree::new(
            nodes
                .iter()
                .map(|level| level.iter().map(|(p, _)| p.plane(&view)).collect())
                .collect(),
        );
        // persp's mapping, when the outputs go to the screen; a view volume it cannot
        // map (from the stream's header) is bad input, as it is to persp.
        let perspective = match (depth, size) {
            (Some(depth), Some((width, height))) => {
                Some(Perspective::new(width, height, view, depth.into()).map_err(Error::data)?)
            }
            _ => None,
        };
        let out_header = perspective.map_or(header, |p| p.screen_header(&header));
        let form = cli.text.form();
        let mut outs = outputs
            .iter()
            .map(|o| Branch::open(o, out_header, form))
            .collect::<Result<Vec<_>, _>>()?;
        // Each output's pending `skip N` (the lean stream: polygons it gets nothing of).
        let mut lean = vec![Lean::default(); outs.len()];
        let mut token = Token::default();
        while reader
            .next_into(&mut token)
            .map_err(|e| stagecli::input_error("stdin", e))?
        {
            if !outs.iter().any(Branch::is_open) {
                // Every reader has gone: nobody is left to write for.
                return Ok(());
            }
            match &token {
                Token::Polygon(poly) => {
                    tree.split(poly);
                    // Only a cut makes numbers the polygon did not have (`Subtree::cut`).
                    if tree.cut() {
                        for piece in tree.pieces() {
                            stagecli::check_finite_after(piece, "the split")
                                .map_err(|m| Error::data(format!("{}: {m}", reader.position())))?;
                        }
                    }
                    let pieces = tree.outputs();
                    if let Some(perspective) = &perspective {
                        // A piece too small to be sent (`Lean`) is not projected.
                        for piece in pieces.iter_mut() {
                            if piece.vertices.len() < Lean::MIN_VERTICES {
                                continue;
                            }
                            stagecli::stream::project_to_screen(perspective, piece)
                                .map_err(|m| Error::data(format!("{}: {m}", reader.position())))?;
                        }
                    }
                    for ((lean, out), piece) in lean.iter_mut().zip(&mut outs).zip(pieces.iter()) {
                        lean.polygon(out, piece)?;
                    }
                }
                Token::Skip(n) => {
                    tree.skipped(*n);
                    for (lean, out) in lean.iter_mut().zip(&mut outs) {
                        lean.skip(out, *n)?;
                    }
                }
                control => {
                    for (lean, out) in lean.iter_mut().zip(&mut outs) {
                        lean.control(out, control)?;
                    }
                    if *control == Token::End && cli.stats {
                        print_stats(&nodes, &tree, &outs);
                    }
                }
            }
        }
        for (lean, out) in lean.iter_mut().zip(&mut outs) {
            lean.flush(out)?;
        }
        for out in &mut outs {
            out.flush()?;
        }
        Ok(())
    })
}

/// `--stats`, a line a node and its record, level by level: what it split, and for the
/// nodes whose outputs this process writes, the bytes each carried, a link's load when
/// the branch runs on another host (thesis 6.5).
fn print_stats(nodes: &Nodes, tree: &Subtree, outs: &[Branch<Token>]) {
    for (j, level) in nodes.iter().enumerate() {
        for (i, (plane, number)) in level.iter().enumerate() {
            let label = match number {
                Some(node) => format!("splitter {plane} (node {node})"),
                None => format!("splitter {plane}"),
            };
            let stats = tree.stats[j][i];
            let mut record = stagecli::stats::Record::new("splitter");
            if let Some(node) = number {
                record.set("node", node);
            }
            let mut record = record
                .with("plane", plane)
                .with("polygons_in", stats.polygons_in)
                .with("out1_polygons", stats.polygons_out[0])
                .with("out1_vertices", stats.vertices_out[0])
                .with("out2_polygons", stats.polygons_out[1])
                .with("out2_vertices", stats.vertices_out[1]);
            if j + 1 == nodes.len() {
                let (a, b) = (outs[2 * i].bytes(), outs[2 * i + 1].bytes());
                record.set("out1_bytes", a);
                record.set("out2_bytes", b);
                record.print(&format!("{label}: {stats}; {a} and {b} bytes out"));
            } else {
                record.print(&format!("{label}: {stats}"));
            }
        }
    }
}
