//! A cheap look at a scene: the environment parameters of thesis chapter 5.2 that the cost
//! model needs — polygons and vertices before clipping (P_t), after it (P_r), the screen
//! (X_res × Y_res), the depth complexity Dc (projected area over screen area) and the
//! number of frames. The world-space scene is counted as it is read; the screen-space
//! figures come from `viewxf | clipbatch | persp`, the stages a render runs first.

use anyhow::{bail, Context, Result};
use proto::{Polygon, Reader, Token};
use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};

/// The environment parameters of one scene (totals over all its frames).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Environment {
    /// Frames in the scene.
    pub frames: u64,
    /// P_t: polygons in the world-space scene (all frames).
    pub polygons: u64,
    /// Their vertices (E·P_t).
    pub vertices: u64,
    /// P_r: polygons after clipping (all frames).
    pub relevant: u64,
    /// Their vertices.
    pub relevant_vertices: u64,
    /// Σ projected area of the clipped polygons, pixels (all frames): X·Y·Dc per frame.
    pub area: f64,
    /// X_res, Y_res.
    pub width: u32,
    pub height: u32,
    /// Whether the scene is in the text form.
    pub text: bool,
}

impl Environment {
    /// X_res × Y_res.
    pub fn screen(&self) -> f64 {
        self.width as f64 * self.height as f64
    }

    /// Dc: the average number of polygons covering a pixel (area over screen, per frame).
    pub fn depth_complexity(&self) -> f64 {
        if self.frames == 0 || self.screen() == 0.0 {
            0.0
        } else {
            self.area / (self.screen() * self.frames as f64)
        }
    }

    /// Σ H over the relevant polygons, the scan lines (spans) they cover, by the thesis's
    /// closed form (5.2): W = H = √(X·Y·Dc / P_r), so P_r·H = √(P_r·X·Y·Dc) a frame.
    pub fn spans(&self) -> f64 {
        if self.frames == 0 {
            return 0.0;
        }
        let f = self.frames as f64;
        f * ((self.relevant as f64 / f) * self.screen() * self.depth_complexity()).sqrt()
    }
}

/// Counts polygons and vertices of a world-space stream, and its frames.
pub fn count_world<R: Read>(input: R) -> Result<(u64, u64, u64)> {
    let mut reader = Reader::<Token, _>::new(input)?;
    let (mut frames, mut polygons, mut vertices) = (1u64, 0u64, 0u64);
    let mut record = Token::default();
    while reader.next_into(&mut record)? {
        match &record {
            Token::Polygon(p) => {
                polygons += 1;
                vertices += p.vertices.len() as u64;
            }
            Token::NextFrame => frames += 1,
            Token::Skip(_) | Token::End => {}
        }
    }
    Ok((frames, polygons, vertices))
}

/// The area of a screen-space polygon, pixels (the shoelace formula; either winding).
pub fn area(p: &Polygon) -> f64 {
    let n = p.vertices.len();
    let mut twice = 0.0;
    for i in 0..n {
        let a = p.vertices[i];
        let b = p.vertices[(i + 1) % n];
        twice += a.x * b.y - b.x * a.y;
    }
    (twice / 2.0).abs()
}

/// Counts a screen-space stream: (polygons, vertices, Σ area).
pub fn count_screen<R: Read>(input: R) -> Result<(u64, u64, f64)> {
    let mut reader = Reader::<Token, _>::new(input)?;
    let (mut polygons, mut vertices, mut sum) = (0u64, 0u64, 0.0);
    let mut record = Token::default();
    while reader.next_into(&mut record)? {
        if let Token::Polygon(p) = &record {
            polygons += 1;
            vertices += p.vertices.len() as u64;
            sum += area(p);
        }
    }
    Ok((polygons, vertices, sum))
}

/// Whether the file starts like a text-form stream (else binary).
pub fn is_text(scene: &Path) -> Result<bool> {
    let mut first = [0u8; 8];
    let mut f =
        std::fs::File::open(scene).with_context(|| format!("cannot open {}", scene.display()))?;
    let n = f.read(&mut first)?;
    Ok(n > 0 && first[..n] != proto::header::BINARY_MAGIC[..n])
}

/// Looks at a scene for a `width`×`height` screen, running the first stages from `bin`.
/// `camera` are viewxf's options as render.sh was given them (`--eye X,Y,Z` …).
pub fn look(
    bin: &Path,
    scene: &Path,
    width: u32,
    height: u32,
    camera: &[String],
) -> Result<Environment> {
    let text = is_text(scene)?;
    let file =
        std::fs::File::open(scene).with_context(|| format!("cannot open {}", scene.display()))?;
    let (frames, polygons, vertices) = count_world(std::io::BufReader::new(file))
        .with_context(|| format!("reading {}", scene.display()))?;
    let size = format!("{width}x{height}");
    let q = |p: &Path| format!("'{}'", p.display().to_string().replace('\'', r"'\''"));
    let line = format!(
        "{v} --size {size} {cam} < {s} | {c} | {p} --size {size}",
        v = q(&bin.join("viewxf")),
        cam = camera
            .iter()
            .map(|a| q(Path::new(a)))
            .collect::<Vec<_>>()
            .join(" "),
        s = q(scene),
        c = q(&bin.join("clipbatch")),
        p = q(&bin.join("persp")),
    );
    let mut child = Command::new("bash")
        .args(["-o", "pipefail", "-c", &line])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .context("cannot run viewxf | clipbatch | persp")?;
    let out = child.stdout.take().context("persp's output")?;
    let counted = count_screen(std::io::BufReader::new(out));
    let output = child.wait_with_output()?;
    if !output.status.success() {
        bail!(
            "viewxf | clipbatch | persp failed on {}: {}",
            scene.display(),
            String::from_utf8_lossy(&output.stderr).trim()
        );
    }
    let (relevant, relevant_vertices, area) = counted?;
    Ok(Environment {
        frames,
        polygons,
        vertices,
        relevant,
        relevant_vertices,
        area,
        width,
        height,
        text,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proto::DVec4;

    #[test]
    fn area_of_a_square_either_winding() {
        let v = |x, y| DVec4::new(x, y, 0.5, 1.0);
        let mut p = Polygon::new(
            Default::default(),
            vec![v(0.0, 0.0), v(10.0, 0.0), v(10.0, 10.0), v(0.0, 10.0)],
        );
        assert_eq!(area(&p), 100.0);
        p.vertices.reverse();
        assert_eq!(area(&p), 100.0);
    }

    #[test]
    fn closed_form_spans() {
        // 512 polygons over 500×500 at Dc 1: H = √(250000/512) ≈ 22 (thesis 5.2).
        let e = Environment {
            frames: 1,
            relevant: 512,
            area: 250_000.0,
            width: 500,
            height: 500,
            ..Default::default()
        };
        assert!((e.depth_complexity() - 1.0).abs() < 1e-12);
        let h = e.spans() / 512.0;
        assert!((h - 22.097).abs() < 0.01, "{h}");
    }

    #[test]
    fn counts_a_text_scene() {
        let scene = "polypipe 1 world\ncolour 1 2 3\n0 0 0\n1 0 0\n0 1 0\nNEXT.FRAME\ncolour 1 2 3\n0 0 0\n1 0 0\n0 1 0\n1 1 0\nEND\n";
        let (frames, polygons, vertices) = count_world(scene.as_bytes()).unwrap();
        assert_eq!((frames, polygons, vertices), (2, 2, 7));
    }
}
