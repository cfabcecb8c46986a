//! splitter: one node of the splitter tree (thesis chapter 6.2), eye space in, two
//! eye-space streams out (or, with --persp, two screen-space ones).

use clap::Parser;
use proto::perspective::Perspective;
use proto::{Polygon, Space, SpaceKind, Token};
use splitter::{split, Lean, SplitPlane, Stats, Tree};
use stagecli::{Branch, DepthArg, Error, TextFlag};
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
/// With `--persp MODE` the two outputs are projected to the screen, as `persp --size WxH
/// --depth MODE` after each would project them: what render.sh asks of the tree's last
/// level, whose outputs are the leaves', so that a leaf needs no persp process of its own.
#[derive(Parser, Debug)]
#[command(
    name = "splitter",
    version,
    override_usage = "splitter [OPTIONS] PLANE OUT1 OUT2\n       \
        splitter [OPTIONS] --node K --depth N --size WxH OUT1 OUT2\n       \
        splitter [OPTIONS] --plane a,b,c,d,k OUT1 OUT2",
    after_help = "Examples:\n  \
        mkfifo left right\n  \
        viewxf < scene.txt | clipplane left | ... | clipplane yon | splitter x=0 left right\n  \
        splitter y=0.5 low - < eye.txt --text      # the upper part to stdout\n  \
        splitter --node 2 --depth 2 --size 500x500 a b  # node 2 of render.sh --depth 2\n  \
        splitter --plane 1,0,0,-0.5,0 a b < eye.txt  # x_e - 0.5 w >= 0 to a\n  \
        splitter --node 2 --depth 2 --size 500x500 --persp reciprocal a b  # to the leaves"
)]
struct Cli {
    /// `x=K` or `y=K` (K in [-1, 1]), then OUT1 and OUT2; with --plane or --node, only
    /// OUT1 OUT2.
    #[arg(value_name = "ARGS", num_args = 2..=3, required = true)]
    args: Vec<String>,
    /// A general plane a·x_e + b·y_e + c·z_e + d·w + k = 0, as `a,b,c,d,k`; OUT1 gets
    /// the side where it is ≥ 0.
    #[arg(long, value_name = "a,b,c,d,k", allow_hyphen_values = true)]
    plane: Option<String>,
    /// Node K of a splitter tree (thesis 6.3) numbered as a heap (root 1, children 2K
    /// and 2K+1): the node bisects its region of the screen on a pixel boundary, levels
    /// alternating x then y; `--stats` names it `splitter x=K (node K)`.
    #[arg(long, value_name = "K", requires_all = ["depth", "size"], conflicts_with = "plane")]
    node: Option<u32>,
    /// The tree's depth, for --node: nodes 1 to 2^N − 1 split.
    #[arg(long, value_name = "N", requires = "node")]
    depth: Option<u32>,
    /// The screen's size in pixels, for --node and --persp.
    #[arg(long, value_name = "WxH")]
    size: Option<String>,
    /// Project both outputs to a --size screen with this depth, as persp's --depth.
    #[arg(long, value_enum, value_name = "MODE", requires = "size")]
    persp: Option<DepthArg>,
    #[command(flatten)]
    text: TextFlag,
    /// At END, print on stderr the polygons in and the non-empty polygons and vertices
    /// sent to each output.
    #[arg(long)]
    stats: bool,
}

/// What the arguments ask, checked before any input is read.
struct Plan {
    split_plane: SplitPlane,
    outputs: [String; 2],
    /// The screen's size (--size), in pixels.
    size: Option<(u32, u32)>,
}

fn plan(cli: &Cli) -> Result<Plan, Error> {
    let size = match cli.size.as_deref() {
        Some(size) => Some(
            proto::camera::parse_size(size)
                .map_err(|m| Error::usage(format!("--size {size}: {m}")))?,
        ),
        None => None,
    };
    if size.is_some() && cli.node.is_none() && cli.persp.is_none() {
        return Err(Error::usage("--size is for --node or --persp"));
    }
    let tree_plane = match (cli.node, size) {
        (Some(node), Some((width, height))) => {
            Tree::check_node(node, cli.depth.unwrap_or_default()).map_err(Error::usage)?;
            Some(Tree { width, height }.plane(node))
        }
        _ => None,
    };
    let (plane, outputs) = match (&cli.plane, cli.args.as_slice()) {
        (None, [out1, out2]) if tree_plane.is_some() => (
            tree_plane.ok_or_else(String::new),
            [out1.clone(), out2.clone()],
        ),
        (None, _) if tree_plane.is_some() => {
            return Err(Error::usage("with --node, give only OUT1 and OUT2"))
        }
        (Some(general), [out1, out2]) => (
            SplitPlane::parse_general(general).map_err(|m| format!("--plane {general}: {m}")),
            [out1.clone(), out2.clone()],
        ),
        (None, [plane, out1, out2]) => (plane.parse::<SplitPlane>(), [out1.clone(), out2.clone()]),
        (Some(_), _) => return Err(Error::usage("with --plane, give only OUT1 and OUT2")),
        (None, _) => {
            return Err(Error::usage(
                "expected PLANE OUT1 OUT2, e.g. `splitter x=0 left right`",
            ))
        }
    };
    let plane = plane.map_err(Error::usage)?;
    if outputs[0] == "-" && outputs[1] == "-" {
        return Err(Error::usage(
            "at most one of OUT1 and OUT2 may be `-` (stdout)",
        ));
    }
    if stagecli::same_file(&outputs[0], &outputs[1]) {
        return Err(Error::usage(format!(
            "OUT1 {} and OUT2 {} are one file: the two streams would be mixed in it",
            outputs[0], outputs[1]
        )));
    }
    Ok(Plan {
        split_plane: plane,
        outputs,
        size,
    })
}

fn main() -> ExitCode {
    stagecli::main("splitter", |cli: Cli| {
        let Plan {
            split_plane,
            outputs,
            size,
        } = plan(&cli)?;
        // What --stats calls this node: its plane, and its place in the tree.
        let label = match cli.node {
            Some(node) => format!("splitter {split_plane} (node {node})"),
            None => format!("splitter {split_plane}"),
        };
        let mut reader = stagecli::read_stdin::<Token>(SpaceKind::Eye)?;
        let header = *reader.header();
        let Space::Eye(view) = header.space else {
            unreachable!("the reader checked the space")
        };
        let plane = split_plane.plane(&view);
        // persp's mapping, when the outputs go to the screen; a view volume it cannot
        // map (from the stream's header) is bad input, as it is to persp.
        let perspective = match (cli.persp, size) {
            (Some(depth), Some((width, height))) => {
                Some(Perspective::new(width, height, view, depth.into()).map_err(Error::data)?)
            }
            _ => None,
        };
        let out_header = perspective.map_or(header, |p| p.screen_header(&header));
        let form = cli.text.form();
        let mut out1 = Branch::open(&outputs[0], out_header, form)?;
        let mut out2 = Branch::open(&outputs[1], out_header, form)?;
        let mut stats = Stats::default();
        // The two pieces' buffers, reused from polygon to polygon; each output's pending
        // `skip N` (the lean stream: polygons it gets nothing of).
        let mut piece1 = Polygon::default();
        let mut piece2 = Polygon::default();
        let mut lean = [Lean::default(), Lean::default()];
        let mut token = Token::default();
        while reader
            .next_into(&mut token)
            .map_err(|e| stagecli::input_error("stdin", e))?
        {
            if !(out1.is_open() || out2.is_open()) {
                // Both readers have gone: nobody is left to write for.
                return Ok(());
            }
            match &token {
                Token::Polygon(poly) => {
                    split(poly, &plane, &mut piece1, &mut piece2);
                    for piece in [&piece1, &piece2] {
                        stagecli::check_finite_after(piece, "the split")
                            .map_err(|m| Error::data(format!("{}: {m}", reader.position())))?;
                    }
                    if let Some(perspective) = &perspective {
                        // A piece too small to be sent (`Lean`) is not projected.
                        for piece in [&mut piece1, &mut piece2] {
                            if piece.vertices.len() < Lean::MIN_VERTICES {
                                continue;
                            }
                            stagecli::stream::project_to_screen(perspective, piece)
                                .map_err(|m| Error::data(format!("{}: {m}", reader.position())))?;
                        }
                    }
                    stats.record(&piece1, &piece2);
                    lean[0].polygon(&mut out1, &piece1)?;
                    lean[1].polygon(&mut out2, &piece2)?;
                }
                Token::Skip(n) => {
                    stats.skipped(*n);
                    lean[0].skip(&mut out1, *n)?;
                    lean[1].skip(&mut out2, *n)?;
                }
                control => {
                    lean[0].control(&mut out1, control)?;
                    lean[1].control(&mut out2, control)?;
                    if *control == Token::End && cli.stats {
                        // The bytes each output carried: a link's load, when the
                        // branch runs on another host (thesis 6.5).
                        eprintln!(
                            "{label}: {stats}; {} and {} bytes out",
                            out1.bytes(),
                            out2.bytes()
                        );
                    }
                }
            }
        }
        lean[0].flush(&mut out1)?;
        lean[1].flush(&mut out2)?;
        out1.flush()?;
        out2.flush()
    })
}
