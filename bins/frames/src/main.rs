//! frames: a movie's frame count, or a contiguous range of its frames as a movie.

use clap::Parser;
use frames::{count_frames, pass_frames, skip_frames, FrameRange};
use proto::{Form, Reader, SpaceKind, Token, Writer};
use stagecli::Error;
use std::io::Write;
use std::process::ExitCode;

/// Counts a movie's frames, or passes a contiguous range of them through as a movie.
///
/// Reads a polygon stream (world, eye or screen space; binary or text) from INPUT or
/// stdin. With --count, prints the number of frames. Otherwise writes frames FROM,
/// FROM+1, …, TO−1 (numbered from 0) as a stream of their own, unchanged record for
/// record: the same header, no NEXT.FRAME before the first, END after the last.
/// Rendering the ranges 0..A, A..B, …, Z..N one after another gives the movie's frames.
#[derive(Parser, Debug)]
#[command(
    name = "frames",
    version,
    after_help = "Examples:\n  \
        scene spheres --frames 300 > movie.pp; frames --count movie.pp     # 300\n  \
        frames --from 100 --to 200 movie.pp | scripts/render.sh - > middle.ppm\n  \
        scene spheres --frames 10 | frames --from 9 --text                 # the last frame"
)]
struct Cli {
    /// The stream to read (`-` for stdin, the default).
    #[arg(default_value = "-")]
    input: String,
    /// Print the number of frames (reads and checks the whole stream).
    #[arg(long, conflicts_with_all = ["from", "to", "text"])]
    count: bool,
    /// The first frame to keep (from 0).
    #[arg(long, value_name = "A", default_value_t = 0,
          value_parser = stagecli::numbers::whole::<u64>(0, u64::MAX))]
    from: u64,
    /// The frame after the last to keep (default: to the end; past the end means the end).
    #[arg(long, value_name = "B", value_parser = stagecli::numbers::whole::<u64>(0, u64::MAX))]
    to: Option<u64>,
    /// Write the text form instead of binary.
    #[arg(long)]
    text: bool,
}

fn main() -> ExitCode {
    stagecli::main("frames", |cli: Cli| {
        let range = FrameRange::new(cli.from, cli.to).map_err(Error::usage)?;
        let name = stagecli::input_name(&cli.input).to_string();
        let input = stagecli::open_input(&cli.input)?;
        let mut reader =
            Reader::<Token, _>::new(input).map_err(|e| stagecli::input_error(&name, e))?;
        if SpaceKind::of(&reader.header().space) == SpaceKind::Fragments {
            return Err(Error::data(format!(
                "{name}: a fragment stream; frames cuts polygon streams (world, eye or screen)"
            )));
        }
        if cli.count {
            let n = count_frames(&mut reader).map_err(|e| stagecli::input_error(&name, e))?;
            let mut out = stagecli::stdout();
            writeln!(out, "{n}")?;
            out.flush()?;
            return Ok(());
        }
        // The frames before the range first, so that a range past the movie's end is
        // refused with nothing written (not a header and no END).
        skip_frames(&mut reader, range.from).map_err(|e| e.context(&name))?;
        let rest = FrameRange::new(0, range.to.map(|to| to - range.from)).map_err(Error::usage)?;
        let header = *reader.header();
        let mut writer = Writer::new(stagecli::stdout(), header, Form::from_text_flag(cli.text))?;
        pass_frames(&mut reader, &mut writer, rest).map_err(|e| e.context(&name))?;
        Ok(())
    })
}
