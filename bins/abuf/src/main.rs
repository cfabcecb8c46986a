//! abuf: a leaf that anti-aliases with Carpenter's a-buffer.

use clap::Parser;
use scan::abuf::ABuffer;
use stagecli::AntialiasArgs;
use std::process::ExitCode;

/// Anti-aliasing with Carpenter's a-buffer (sampling thesis 6.3; docs/DESIGN.md,
/// "Anti-aliasing"), a leaf of the splitter tree.
///
/// Reads a screen-space polygon stream (from persp) on stdin and gathers each frame. Per
/// pixel it keeps a list of fragments sorted by depth, each with an 8×8 coverage mask of
/// the sub-pixel samples (c+(i+½)/8, r+(j+½)/8) the polygon covers by the point rule, its
/// colour and its zmin/zmax; a pixel one polygon covers wholly in front of the rest needs
/// no list. The packer resolves each list front to back, splitting the samples of two
/// fragments that intersect in depth by their zmin/zmax. It works one pixel row at a
/// time, so its memory does not grow with the screen. A list longer than 64 fragments
/// has its two farthest merged into one (counted as `merged`), and a polygon wholly
/// behind the fully covering fragments of a block of 8 pixels is left out there unmade
/// (`culled`): time stays bounded in fragments per pixel and in depth complexity. A
/// Gouraud-shaded polygon (a `vertex-colours` stream) gives each fragment its colour at the
/// pixel centre; a polygon of opacity below 255 (an `opacity` stream) is blended by the
/// sampling thesis's eq. 6.5. The output is runs of finished
/// pixels (`run Y X0 X1 R G B`) for zbuf, which must be given the same --background.
///
/// Example:
///   persp --size 500x500 < eye.pp | abuf --stats | zbuf > frame.ppm
#[derive(Parser)]
#[command(name = "abuf", version, verbatim_doc_comment)]
struct Args {
    #[command(flatten)]
    aa: AntialiasArgs,
    /// Print counts (polygons in, frames, runs out; fragments, simple pixelstructs,
    /// lists, the longest list, fragments combined and hidden, intersect cases, pixels
    /// out) on stderr at the end.
    #[arg(long)]
    stats: bool,
}

fn main() -> ExitCode {
    stagecli::main("abuf", |args: Args| {
        let mut method = ABuffer::new(args.aa.background);
        leaf::resolve_frames("abuf", args.aa.text.form(), args.stats, &mut method)?;
        Ok(())
    })
}
