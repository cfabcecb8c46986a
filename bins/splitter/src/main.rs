//! splitter: one node of the splitter tree (thesis chapter 6.2), eye space in, two
//! eye-space streams out.

use anyhow::Context;
use clap::{CommandFactory, Parser};
use proto::{Form, Polygon, Reader, Space, SpaceKind, Token, Writer};
use splitter::{split, Lean, SplitPlane, Stats};
use std::fs::File;
use std::io::{self, Write};
use std::process::ExitCode;

/// A splitter node (thesis chapter 6.2): splits every polygon of an eye-space stream
/// about a plane through the eye.
///
/// OUT1 receives the part where x_e ≤ K·a·w (for `x=K`; the screen left of x_s = K) or
/// y_e ≤ K·w (for `y=K`; the screen below y_s = K), OUT2 the rest. Both outputs get every
/// NEXT.FRAME and END; the polygons an output gets nothing drawable of (fewer than three
/// vertices) come to it as `skip N`, so polygon k is the same polygon on both branches. OUT1 and OUT2 are files or
/// named pipes; `-` is stdout, for at most one of them.
#[derive(Parser, Debug)]
#[command(
    name = "splitter",
    version,
    override_usage = "splitter [OPTIONS] PLANE OUT1 OUT2\n       splitter [OPTIONS] --plane a,b,c,d,k OUT1 OUT2",
    after_help = "Examples:\n  \
        mkfifo left right\n  \
        viewxf < scene.txt | clipplane left | ... | clipplane yon | splitter x=0 left right\n  \
        splitter y=0.5 low - < eye.txt --text      # the upper part to stdout\n  \
        splitter --plane 1,0,0,-0.5,0 a b < eye.txt  # x_e - 0.5 w >= 0 to a"
)]
struct Cli {
    /// `x=K` or `y=K` (K in [-1, 1]), then OUT1 and OUT2; with --plane, only OUT1 OUT2.
    #[arg(value_name = "ARGS", num_args = 2..=3, required = true)]
    args: Vec<String>,
    /// A general plane a·x_e + b·y_e + c·z_e + d·w + k = 0, as `a,b,c,d,k`; OUT1 gets
    /// the side where it is ≥ 0.
    #[arg(long, value_name = "a,b,c,d,k", allow_hyphen_values = true)]
    plane: Option<String>,
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
    let (split_plane, outputs) = match (&cli.plane, cli.args.as_slice()) {
        (Some(general), [out1, out2]) => (
            SplitPlane::parse_general(general).unwrap_or_else(|m| usage(m)),
            [out1.clone(), out2.clone()],
        ),
        (None, [plane, out1, out2]) => (
            plane.parse::<SplitPlane>().unwrap_or_else(|m| usage(m)),
            [out1.clone(), out2.clone()],
        ),
        (Some(_), _) => usage("with --plane, give only OUT1 and OUT2".into()),
        (None, _) => usage("expected PLANE OUT1 OUT2, e.g. `splitter x=0 left right`".into()),
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
        // The two pieces' buffers, reused from polygon to polygon.
        let mut piece1 = Polygon::default();
        let mut piece2 = Polygon::default();
        let mut lean = [Lean::default(), Lean::default()];
        let mut token = Token::default();
        while reader.next_into(&mut token)? {
            match &token {
                Token::Polygon(poly) => {
                    split(poly, &plane, &mut piece1, &mut piece2);
                    stats.record(&piece1, &piece2);
                    lean[0]
                        .polygon(&mut out1, &piece1)
                        .with_context(|| format!("writing {}", outputs[0]))?;
                    lean[1]
                        .polygon(&mut out2, &piece2)
                        .with_context(|| format!("writing {}", outputs[1]))?;
                }
                Token::Skip(n) => {
                    stats.skipped(*n);
                    lean[0]
                        .skip(&mut out1, *n)
                        .with_context(|| format!("writing {}", outputs[0]))?;
                    lean[1]
                        .skip(&mut out2, *n)
                        .with_context(|| format!("writing {}", outputs[1]))?;
                }
                control => {
                    lean[0]
                        .control(&mut out1, control)
                        .with_context(|| format!("writing {}", outputs[0]))?;
                    lean[1]
                        .control(&mut out2, control)
                        .with_context(|| format!("writing {}", outputs[1]))?;
                    if *control == Token::End && cli.stats {
                        eprintln!("splitter {split_plane}: {stats}");
                    }
                }
            }
        }
        out1.flush()?;
        out2.flush()?;
        Ok(())
    })
}
