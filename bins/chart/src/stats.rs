//! A scene's environment statistics, counted on the reference's pixels: the quantities
//! by which Sutherland, Sproull and Schumacker ("A Characterization of Ten Hidden-Surface
//! Algorithms", 1974; through the thesis, 5.1) express each method's cost, and the
//! *visible complexity* to which Newman and Sproull (*Principles of Interactive Computer
//! Graphics*, 14.3.4 and 14.4.3) find Warnock's and Watkins's times roughly proportional.
//!
//! Every count is exact on the screen the scene is rendered on, with the reference's own
//! coverage rule (a pixel is covered when its centre is, inside the view volume) and its
//! tie rule (the nearest, the earliest on a tie), so "visible" means what the right
//! picture shows:
//!
//! - **polygons** P_t and **edges** E_t: the scene's, a frame (a polygon of n vertices
//!   has n edges).
//! - **depth complexity** Dc: the mean, over every pixel of the screen, of the number of
//!   polygons covering its centre (thesis 5.2: "the average number of polygons that cover
//!   a pixel"); empty pixels count 0.
//! - **visible polygons**: the polygons that own at least one pixel of the right picture.
//! - **visible segments**: on each scan line, the maximal runs of pixels owned by one
//!   polygon (the background owns none), summed over the scan lines: the segments a
//!   scan-line method outputs once it has resolved depth (Newman and Sproull 14.4.1), and
//!   the survey's measure of visible complexity. `segments_per_line` is this over the
//!   scan lines.
//!
//! Each is a mean over the scene's frames.

use crate::error::{Context, Error, Result};
use proto::{Polygon, Reader, Token};
use reference::Setup;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The environment statistics of a scene on one screen, a frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Stats {
    pub polygons: f64,
    pub edges: f64,
    pub depth_complexity: f64,
    pub visible_polygons: f64,
    pub visible_segments: f64,
    pub segments_per_line: f64,
}

/// The pixel's owner as a colour: polygon `k` of the frame (from 0) is k + 1, the
/// background 0. Twenty-four bits: 16,777,215 polygons a frame.
fn id_colour(k: usize) -> [u8; 3] {
    let id = (k + 1) as u32;
    [(id >> 16) as u8, (id >> 8) as u8, id as u8]
}

fn colour_id(c: [u8; 3]) -> u32 {
    (c[0] as u32) << 16 | (c[1] as u32) << 8 | c[2] as u32
}

/// One frame's counts: (covering sum over pixels, visible polygons, visible segments).
pub fn frame_counts(polys: &[Polygon], setup: &Setup) -> Result<(u64, u64, u64)> {
    if polys.len() >= (1 << 24) - 1 {
        return Err(Error::Data(format!(
            "a frame of {} polygons: the statistics count at most 16,777,214",
            polys.len()
        )));
    }
    let covered: u64 = reference::coverage_counts(polys, setup)
        .iter()
        .map(|&c| c as u64)
        .sum();
    // Each polygon flat in its own colour, its number: the reference picture of owners.
    let owners: Vec<Polygon> = polys
        .iter()
        .enumerate()
        .map(|(k, p)| Polygon {
            colour: id_colour(k),
            vertices: p.vertices.clone(),
            opacity: 255,
            ..Polygon::default()
        })
        .collect();
    let ids: Vec<u32> = reference::render_frame(&owners, setup, [0, 0, 0])
        .map_err(Error::Data)?
        .into_iter()
        .map(colour_id)
        .collect();
    let mut seen = vec![false; polys.len() + 1];
    let mut segments = 0u64;
    for row in ids.chunks(setup.width as usize) {
        let mut last = 0;
        for &id in row {
            if id != 0 && id != last {
                segments += 1;
            }
            seen[id as usize] = true;
            last = id;
        }
    }
    let visible = seen[1..].iter().filter(|&&s| s).count() as u64;
    Ok((covered, visible, segments))
}

/// The statistics of the scene at `path` rendered `width`×`height` by the default camera.
pub fn stats(path: &Path, width: u32, height: u32) -> Result<Stats> {
    #[derive(clap::Parser)]
    struct Camera {
        #[command(flatten)]
        view: stagecli::ViewArgs,
    }
    let size = format!("{width}x{height}");
    let cam = <Camera as clap::Parser>::try_parse_from(["zspec", "--size", &size])
        .map_err(|e| Error::Data(e.to_string()))?;
    let (frame, view) = cam.view.resolve()?;
    // No lighting: every polygon is one flat colour, its number.
    let setup = Setup::new(frame, view, width, height);
    let file =
        std::fs::File::open(path).with_context(|| format!("cannot open {}", path.display()))?;
    let mut reader = Reader::<Token, _>::new(std::io::BufReader::new(file))
        .with_context(|| format!("reading {}", path.display()))?;
    let mut sum = Stats::default();
    let mut frames = 0u64;
    let mut coverings = 0u64;
    let mut polys: Vec<Polygon> = Vec::new();
    loop {
        let token = reader
            .next_record()
            .with_context(|| format!("reading {}", path.display()))?;
        match token {
            Some(Token::Polygon(p)) => polys.push(p),
            Some(Token::Skip(_)) => {}
            Some(Token::NextFrame) | Some(Token::End) | None => {
                let end = !matches!(token, Some(Token::NextFrame));
                if !(end && polys.is_empty() && frames > 0) {
                    let (covered, visible, segments) = frame_counts(&polys, &setup)?;
                    frames += 1;
                    sum.polygons += polys.len() as f64;
                    sum.edges += polys.iter().map(|p| p.vertices.len() as f64).sum::<f64>();
                    coverings += covered;
                    sum.visible_polygons += visible as f64;
                    sum.visible_segments += segments as f64;
                }
                polys.clear();
                if end {
                    break;
                }
            }
        }
    }
    let n = frames.max(1) as f64;
    Ok(Stats {
        polygons: sum.polygons / n,
        edges: sum.edges / n,
        depth_complexity: coverings as f64 / (width as f64 * height as f64 * n),
        visible_polygons: sum.visible_polygons / n,
        visible_segments: sum.visible_segments / n,
        segments_per_line: sum.visible_segments / n / height as f64,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two squares facing the eye at z = 0, where the default camera sees ±12.5 across a
    /// 10×10 screen: 2.5 units a pixel, pixel centres at −11.25, −8.75, … 11.25. The
    /// first spans x −12.5 to 2.5 (the centres of columns 0–5), the second −2.5 to 12.5
    /// (columns 4–9), both the whole height. By hand: 60 + 60 = 120 coverings over 100
    /// pixels, Dc 1.2; on the tie in columns 4 and 5 the first is drawn (the earliest),
    /// so each row has two segments, 0–5 and 6–9: 20 segments, 2 a scan line, both
    /// polygons visible. A second frame of the first square alone: 60 coverings, Dc 0.6,
    /// one polygon, one segment a row. The means of the two frames are the statistics.
    #[test]
    fn two_squares_counted_by_hand() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("squares.txt");
        let first = "colour 200 0 0\n-12.5 -12.5 0\n2.5 -12.5 0\n2.5 12.5 0\n-12.5 12.5 0\n";
        let second = "colour 0 0 200\n-2.5 -12.5 0\n12.5 -12.5 0\n12.5 12.5 0\n-2.5 12.5 0\n";
        std::fs::write(
            &path,
            format!("polypipe 1 world\n{first}NEXT.POLYGON\n{second}NEXT.FRAME\n{first}END\n"),
        )
        .unwrap();
        let s = stats(&path, 10, 10).unwrap();
        assert_eq!(
            s,
            Stats {
                polygons: 1.5,
                edges: 6.0,
                depth_complexity: 0.9,
                visible_polygons: 1.5,
                visible_segments: 15.0,
                segments_per_line: 1.5,
            }
        );
    }

    #[test]
    fn a_hidden_polygon_is_not_visible_and_an_empty_row_has_no_segment() {
        // A square covering columns 0–5 of rows 0–4 (y 0 to 12.5, the top half), and
        // the same square behind it (z −1), which projects smaller, towards the middle,
        // wholly under the first.
        let polys = |z: f64| {
            Polygon::new(
                [1, 2, 3],
                [(-12.5, 0.0), (2.5, 0.0), (2.5, 12.5), (-12.5, 12.5)]
                    .iter()
                    .map(|&(x, y)| proto::Vertex::new(x, y, z, 1.0))
                    .collect(),
            )
        };
        let setup = {
            #[derive(clap::Parser)]
            struct Camera {
                #[command(flatten)]
                view: stagecli::ViewArgs,
            }
            let cam =
                <Camera as clap::Parser>::try_parse_from(["zspec", "--size", "10x10"]).unwrap();
            let (frame, view) = cam.view.resolve().unwrap();
            Setup::new(frame, view, 10, 10)
        };
        let (covered, visible, segments) =
            frame_counts(&[polys(0.0), polys(-1.0)], &setup).unwrap();
        assert_eq!(visible, 1, "the one behind owns no pixel");
        assert_eq!(segments, 5, "one segment on each of the five rows covered");
        assert!(covered > 30 && covered <= 60, "{covered}");
    }

    #[test]
    fn ids_round_trip_through_colours() {
        for k in [0usize, 1, 254, 255, 65_535, 1 << 20, (1 << 24) - 2] {
            assert_eq!(colour_id(id_colour(k)), k as u32 + 1);
        }
    }
}
