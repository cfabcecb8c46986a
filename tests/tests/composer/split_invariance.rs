//! Split invariance in process: every example scene, cut by the splitter tree's planes at
//! depths 1 to 6, renders to the bytes of the uncut scene.
//!
//! The same stage libraries render.sh's processes run (viewxf, clipbatch, the splitter's
//! `split` at each node's plane, persp, scanconv, zbuf's frame buffer), called in one
//! process: a polygon goes down the tree of Theoharis's chapter 6.3 (node k's OUT1 to
//! node 2k, OUT2 to node 2k + 1), and every piece that reaches a leaf is projected, scan
//! converted and depth-tested as polygon k of its frame, as PAR.BUFF tests the leaves'
//! fragments. This is what `render.sh --depth N` promises (byte-identical frames at
//! every depth), checked on all 22 examples at four sizes and six depths in a second or
//! two; the processes, pipes and merge modes are checked by the real tree renders of
//! tests/tree_script.rs, render_graph.rs and render_failures.rs.

use clap::Parser;
use clipbatch::ClipBatch;
use proto::perspective::{DepthMode, Perspective};
use proto::{Polygon, Reader, SpaceKind, Token};
use scanconv::{Output, ScanConverter};
use splitter::{split, Tree};
use stagecli::ViewArgs;
use std::path::{Path, PathBuf};
use zbuf::FrameBuffer;

#[derive(Parser)]
struct Camera {
    #[command(flatten)]
    view: ViewArgs,
}

/// Renders a world-space scene at `size` through a splitter tree of `depth` levels (0:
/// none): the PPM frames, or the first error (a scene the pipeline refuses).
fn render(scene: &[u8], size: &str, depth: u32) -> Result<Vec<u8>, String> {
    let camera = Camera::try_parse_from(["camera", "--size", size]).map_err(|e| e.to_string())?;
    let (frame, view) = camera.view.resolve().map_err(|e| e.to_string())?;
    let (width, height) = camera.view.size.ok_or("no size")?;
    let mut reader = Reader::<Token, _>::new(scene).map_err(|e| e.to_string())?;
    reader
        .header()
        .expect(SpaceKind::World)
        .map_err(|e| e.to_string())?;
    let perspective = Perspective::new(width, height, view, DepthMode::Projective)?;
    let tree = Tree { width, height };
    let planes: Vec<_> = (1..1u32 << depth)
        .map(|node| tree.plane(node).plane(&view))
        .collect();
    let mut batch = ClipBatch::new(&view, clipbatch::DEFAULT_BATCH);
    let mut sc = ScanConverter::new(width, height, Output::Spans);
    let mut fb = FrameBuffer::new(width, height, [0, 0, 0])?;
    let mut out = Vec::new();
    let mut index = 0u32; // the polygon's number in its frame
    let mut clipped: Vec<Polygon> = Vec::new();
    let mut finish_frame = |clipped: &mut Vec<Polygon>,
                            fb: &mut FrameBuffer,
                            index: &mut u32,
                            out: &mut Vec<u8>|
     -> Result<(), String> {
        for poly in clipped.drain(..) {
            // Down the tree: node k (heap-numbered, root 1) cuts its polygon about its
            // plane; the leaves are nodes 2^depth .. 2^(depth+1) − 1.
            let mut at = vec![(1u32, poly)];
            let mut leaves = Vec::new();
            while let Some((node, p)) = at.pop() {
                if node >= 1 << depth {
                    leaves.push(p);
                    continue;
                }
                let (mut a, mut b) = (Polygon::default(), Polygon::default());
                split(&p, &planes[node as usize - 1], &mut a, &mut b);
                at.push((2 * node, a));
                at.push((2 * node + 1, b));
            }
            for mut piece in leaves {
                if piece.vertices.is_empty() {
                    continue;
                }
                perspective
                    .project_polygon(&mut piece)
                    .map_err(|e| e.reason.to_string())?;
                scanconv::check_on_screen(&piece, width, height)?;
                let colour = piece.colour;
                let polygon = *index;
                sc.convert(&piece, &mut |f| {
                    match f {
                        proto::Fragment::Span { y, x0, x1, z, dz } => {
                            fb.span(y, x0..x1, z, dz, polygon, colour)
                        }
                        proto::Fragment::Pixel { x, y, z } => fb.pixel(x, y, z, polygon, colour),
                        _ => {}
                    }
                    Ok::<_, String>(())
                })?;
            }
            *index += 1;
        }
        fb.write_ppm(out, proto::ppm::Form::Binary)
            .map_err(|e| e.to_string())?;
        fb.clear();
        *index = 0;
        Ok(())
    };
    while let Some(token) = reader.next_record().map_err(|e| e.to_string())? {
        match token {
            Token::Polygon(mut poly) => {
                viewxf::view_polygon(&frame, view.hither, &mut poly);
                if !batch.fits(&poly) {
                    clipped.extend(batch.clip());
                }
                batch.push(poly);
            }
            Token::Skip(_) => {}
            Token::NextFrame | Token::End => {
                clipped.extend(batch.clip());
                finish_frame(&mut clipped, &mut fb, &mut index, &mut out)?;
            }
        }
    }
    Ok(out)
}

fn examples(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            examples(&p, out);
        } else if p.extension().is_some_and(|x| x == "txt") {
            out.push(p);
        }
    }
}

#[test]
fn every_example_renders_as_the_uncut_scene_at_depths_1_to_6() {
    let mut files = Vec::new();
    examples(&pipeline_tests::repo_root().join("examples"), &mut files);
    files.sort();
    assert!(files.len() >= 20, "{files:?}");
    let mut rendered = 0;
    for f in &files {
        let scene = std::fs::read(f).unwrap();
        for size in ["500x500", "333x187", "64x48", "21x21"] {
            let whole = render(&scene, size, 0);
            for depth in 1..=6 {
                let cut = render(&scene, size, depth);
                match (&whole, &cut) {
                    (Ok(a), Ok(b)) => assert!(
                        a == b,
                        "{} at {size}: depth {depth} differs from depth 0",
                        f.display()
                    ),
                    (Err(_), Err(_)) => {}
                    _ => panic!(
                        "{} at {size}: depth 0 {:?}, depth {depth} {:?}",
                        f.display(),
                        whole.as_ref().map(|_| "renders"),
                        cut.as_ref().map(|_| "renders")
                    ),
                }
            }
            rendered += usize::from(whole.is_ok());
        }
    }
    // Most examples are world-space scenes that render; the screen-space ones are
    // refused alike at every depth.
    assert!(rendered >= 40, "only {rendered} renders");
}

#[test]
fn the_in_process_pipeline_is_render_sh_at_depth_0() {
    // The harness itself: the penetrating polygons' frame is render.sh's, byte for byte.
    let scene =
        std::fs::read(pipeline_tests::repo_root().join("examples/penetrating.txt")).unwrap();
    let ours = render(&scene, "333x187", 0).unwrap();
    let theirs =
        pipeline_tests::run("scripts/render.sh --depth 0 --size 333x187 examples/penetrating.txt");
    assert!(
        ours == theirs,
        "the in-process render differs from render.sh's"
    );
    assert_eq!(render(&scene, "333x187", 3).unwrap(), theirs);
}
