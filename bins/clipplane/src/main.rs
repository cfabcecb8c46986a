//! clipplane: eye-space polygon stream → the same stream clipped against one plane.

use clap::Parser;
use clipplane::{clip_against, clip_coloured, ClipPlane};
use proto::geometry::{Plane, PyramidPlane};
use proto::{Polygon, Space, SpaceKind};
use stagecli::{Error, TextFlag};
use std::process::ExitCode;

/// Sutherland–Hodgman clipping of every polygon against one plane (thesis chapter 3).
///
/// Reads an eye-space stream on stdin (binary or text) and writes it clipped. A polygon
/// wholly outside becomes an empty polygon (its colour, no vertices), so polygon
/// numbering is kept. The pyramid planes come from the view volume in the stream header
/// (viewxf --size/--aspect/--hither/--yon).
#[derive(Parser, Debug)]
#[command(
    name = "clipplane",
    version,
    after_help = "Example:\n  viewxf < scene | clipplane left | clipplane right | clipplane top \\\n    \
                  | clipplane bottom | clipplane hither | clipplane yon --text\n  \
                  clipplane hither --at 2      # clip at z_e = 2 instead of the header's K1\n  \
                  clipplane --plane 1,0,0,0,-3 # keep x_e ≥ 3"
)]
struct Cli {
    /// The pyramid plane: left, right, top, bottom, hither or yon.
    #[arg(value_name = "PLANE", required_unless_present = "plane")]
    which: Option<PyramidPlane>,
    /// A general plane `a,b,c,d,k`: inside where a·x_e + b·y_e + c·z_e + d·w + k ≥ 0.
    #[arg(long, value_parser = Plane::parse, allow_hyphen_values = true,
          value_name = "a,b,c,d,k", conflicts_with_all = ["which", "at"])]
    plane: Option<Plane>,
    /// For hither or yon: the distance K (clip at z_e = K) instead of the header's.
    #[arg(long, value_name = "K", value_parser = stagecli::numbers::finite)]
    at: Option<f64>,
    #[command(flatten)]
    text: TextFlag,
}

fn main() -> ExitCode {
    stagecli::main("clipplane", |cli: Cli| {
        let choice = match (cli.plane, cli.which) {
            (Some(plane), _) => ClipPlane::General(plane),
            (None, Some(which)) => ClipPlane::new(which, cli.at).map_err(Error::usage)?,
            (None, None) => return Err(Error::usage("give a PLANE or --plane a,b,c,d,k")),
        };
        stagecli::filter_polygons(SpaceKind::Eye, cli.text.form(), "clipping", |header| {
            let Space::Eye(view) = header.space else {
                unreachable!("the reader checked the space")
            };
            let plane = choice.plane(&view);
            // The clipped vertices go to `scratch`, which then swaps places with the
            // input's vertex list: no allocation of our own per polygon.
            let mut scratch = Vec::new();
            // A Gouraud-shaded polygon's colours are cut with its edges, at the position's
            // parameter (proto::geometry::Crossing::mix); they too go to a scratch list.
            let mut colours = Vec::new();
            // The view volume is passed on unchanged: persp's depth mapping uses its K1, K2.
            Ok((*header, move |poly: &mut Polygon| {
                if poly.is_shaded() {
                    clip_coloured(
                        &poly.vertices,
                        &poly.vertex_attrs,
                        &plane,
                        &mut scratch,
                        &mut colours,
                    );
                    std::mem::swap(&mut poly.vertex_attrs, &mut colours);
                } else {
                    clip_against(&poly.vertices, &plane, &mut scratch);
                }
                if scratch != poly.vertices {
                    // New vertices and edges: the splitter's edge supports (which clipping
                    // before the tree never meets) no longer match; the plane still does.
                    poly.supports.clear();
                }
                std::mem::swap(&mut poly.vertices, &mut scratch);
                Ok(())
            }))
        })
    })
}
