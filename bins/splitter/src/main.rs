//! splitter: one node of the splitter tree (thesis chapter 6.2), eye space in, two
//! eye-space streams out.

use anyhow::Context;
use clap::{CommandFactory, Parser};
use proto::{Form, Polygon, Reader, Space, SpaceKind, Token, Writer};
use splitter::{split, SplitPlane, Stats, Tree};
use std::fs::File;
use std::io::{self, Write};
use std::process::ExitCode;

/// A splitter node (thesis chapter 6.2): splits every polygon of an eye-space stream
/// about a plane through the eye.
///
/// OUT1 receives the part where x_e ≤ K·a·w (for `x=K`; the screen left of x_s = K) or
/// y_e ≤ K·w (for `y=K`; the screen below y_s = K), OUT2 the rest. Both outputs get every
/// polygon (empty where it lies wholly on the other side, so polygon k is the same
/// polygon on both branches) and every NEXT.FRAME and END. OUT1 and OUT2 are files or
/// named pipes; `-` is stdout, for at most one of them.
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
        splitter --plane 1,0,0,-0.5,0 a b < eye.txt  # x_e - 0.5 w >= 0 to a"
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
    /// The screen's size in pixels, for --node.
    #[arg(long, value_name = "WxH", requires = "node")]
    size: Option<String>,
    /// Write the text form instead of binary.
    #[arg(long)]
    text: bool,
    /// At END, print on stderr the polygons in and the non-empty polygons and vertices
    /// sent to each output.
    #[arg(long)]
    stats: bool,
}

fn usage(msg: String) -> ! {
    Cli::command()
        .error(clap::error::ErrorKind::ValueValidation, msg)
        .exit()
}

/// Opens an output named on the command line: `-` is stdout. A named pipe's open
/// waits for its reader, as the occam channel waits for its partner.
fn open_output(path: &str) -> anyhow::Result<Box<dyn Write>> {
    if path == "-" {
        Ok(Box::new(io::stdout().lock()))
    } else {
        let f = File::create(path).with_context(|| format!("cannot open {path} for writing"))?;
        Ok(Box::new(f))
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let tree_plane = cli.node.map(|node| {
        let (width, height) = proto::camera::parse_size(cli.size.as_deref().unwrap_or_default())
            .unwrap_or_else(|m| usage(m));
        Tree::check_node(node, cli.depth.unwrap_or_default()).unwrap_or_else(|m| usage(m));
        Tree { width, height }.plane(node)
    });
    let (split_plane, outputs) = match (&cli.plane, tree_plane, cli.args.as_slice()) {
        (None, Some(plane), [out1, out2]) => (plane, [out1.clone(), out2.clone()]),
        (None, Some(_), _) => usage("with --node, give only OUT1 and OUT2".into()),
        (Some(general), None, [out1, out2]) => (
            SplitPlane::parse_general(general).unwrap_or_else(|m| usage(m)),
            [out1.clone(), out2.clone()],
        ),
        (None, None, [plane, out1, out2]) => (
            plane.parse::<SplitPlane>().unwrap_or_else(|m| usage(m)),
            [out1.clone(), out2.clone()],
        ),
        (Some(_), _, _) => usage("with --plane, give only OUT1 and OUT2".into()),
        (None, None, _) => usage("expected PLANE OUT1 OUT2, e.g. `splitter x=0 left right`".into()),
    };
    // What --stats calls this node: its plane, and its place in the tree.
    let label = match cli.node {
        Some(node) => format!("splitter {split_plane} (node {node})"),
        None => format!("splitter {split_plane}"),
    };
    if outputs[0] == "-" && outputs[1] == "-" {
        usage("at most one of OUT1 and OUT2 may be `-` (stdout)".into());
    }
    proto::cli::run("splitter", || {
        let mut reader = Reader::<Token, _>::new(io::stdin().lock())?;
        reader.header().expect(SpaceKind::Eye)?;
        let header = *reader.header();
        let view = match header.space {
            Space::Eye(view) => view,
            other => anyhow::bail!("input is {}-space, expected eye-space", other.name()),
        };
        let plane = split_plane.plane(&view);
        let form = Form::from_text_flag(cli.text);
        let mut out1 = Writer::new(open_output(&outputs[0])?, header, form)
            .with_context(|| format!("writing {}", outputs[0]))?;
        let mut out2 = Writer::new(open_output(&outputs[1])?, header, form)
            .with_context(|| format!("writing {}", outputs[1]))?;
        let mut stats = Stats::default();
        // The two pieces' buffers, lent to a Token for writing and taken back.
        let mut piece1 = Polygon::default();
        let mut piece2 = Polygon::default();
        while let Some(token) = reader.next_record()? {
            match &token {
                Token::Polygon(poly) => {
                    split(poly, &plane, &mut piece1, &mut piece2);
                    stats.record(&piece1, &piece2);
                    let t1 = Token::Polygon(std::mem::take(&mut piece1));
                    out1.write(&t1)
                        .with_context(|| format!("writing {}", outputs[0]))?;
                    let t2 = Token::Polygon(std::mem::take(&mut piece2));
                    out2.write(&t2)
                        .with_context(|| format!("writing {}", outputs[1]))?;
                    if let (Token::Polygon(a), Token::Polygon(b)) = (t1, t2) {
                        (piece1, piece2) = (a, b);
                    }
                }
                control => {
                    out1.write(control)
                        .with_context(|| format!("writing {}", outputs[0]))?;
                    out2.write(control)
                        .with_context(|| format!("writing {}", outputs[1]))?;
                    if *control == Token::End && cli.stats {
                        eprintln!("{label}: {stats}");
                    }
                }
            }
        }
        out1.flush()?;
        out2.flush()?;
        Ok(())
    })
}
