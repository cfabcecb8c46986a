//! `bench aa-table`: the error table of docs/antialiasing.md: each anti-aliasing leaf of
//! render (--aa) against the exact 16×16 reference (`zspec --samples 16`), on the scenes
//! of tests/tests/surfaces/antialiasing.rs, through a splitter tree of depth D built as
//! render builds it (splitter --node K), every leaf `persp | METHOD`, merged by zbuf.
//! Columns: `zspec compare --metrics --edges`'s overall edge-pixel RMSE and whole-frame
//! RMSE (0-255 units), and the share of pixels differing from the 16×16 reference.
//! With `--pictures DIR`, also each scene's frames as PNGs, side by side: point, ss4,
//! abuf, reference, magnified 4×.

use crate::kit::{methods_list, Kind, Kit};
use stagecli::{Error, Result};

/// The options of `bench aa-table`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The screen.
    #[arg(long, default_value = "64x48")]
    pub size: String,
    /// The splitter tree's depth.
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u32).range(0..=6))]
    pub depth: u32,
    /// A folder to write each scene's frames to, as PNGs side by side.
    #[arg(long, value_name = "DIR")]
    pub pictures: Option<std::path::PathBuf>,
}

/// The value after `key` on zspec compare --metrics' `overall` line.
fn metric(text: &str, key: &str) -> f64 {
    let words: Vec<&str> = text
        .lines()
        .find(|l| l.starts_with("overall"))
        .map_or(Vec::new(), |l| l.split_whitespace().collect());
    words
        .iter()
        .position(|w| *w == key)
        .and_then(|i| words.get(i + 1)?.parse().ok())
        .unwrap_or(0.0)
}

/// Runs `bench aa-table`.
pub fn main(a: &Args) -> Result<()> {
    proto::numbers::parse_size(&a.size).map_err(|e| Error::usage(format!("--size: {e}")))?;
    let k = Kit::new()?;
    let (size, depth) = (&a.size, a.depth);
    let scenes = [
        (
            "environment",
            k.scene("environment.pp", "environment --polygons 200 --seed 7")?,
        ),
        (
            "sphere",
            k.scene("sphere.pp", "sphere --stacks 8 --slices 12")?,
        ),
        ("penetrating", k.r("examples/penetrating.txt")),
        ("needles", k.scene("needles.pp", "needles")?),
    ];
    // The frame of `scene` through a tree of depth `depth`, every leaf `persp | leaf`.
    let render = |scene: &str, leaf: &str, out: &str| -> Result<()> {
        k.make(
            "node-1",
            &format!(
                "{} --size {size} < {scene} | {}",
                k.b("viewxf"),
                k.b("clipbatch")
            ),
        )?;
        for n in 1..1usize << depth {
            k.out(&format!(
                "{} --node {n} --depth {depth} --size {size} {} {} < {}",
                k.b("splitter"),
                k.w(&format!("node-{}", 2 * n)),
                k.w(&format!("node-{}", 2 * n + 1)),
                k.w(&format!("node-{n}"))
            ))?;
        }
        let mut leaves = Vec::new();
        for l in 0..1usize << depth {
            k.make(
                &format!("leaf-{l}"),
                &format!(
                    "{} --size {size} < {} | {}",
                    k.b("persp"),
                    k.w(&format!("node-{}", (1 << depth) + l)),
                    k.leaf(leaf)
                ),
            )?;
            leaves.push(k.w(&format!("leaf-{l}")));
        }
        k.make(out, &format!("{} {}", k.b("zbuf"), leaves.join(" ")))?;
        Ok(())
    };
    println!("against zspec --samples 16, {size}, tree depth {depth}");
    println!(
        "{:<12} {:<6} {:>9} {:>9} {:>10}",
        "scene", "method", "edge_rmse", "rmse", "differing"
    );
    for (scene, file) in &scenes {
        k.make(
            "ref.ppm",
            &format!(
                "{} --size {size} --samples 16 --edge-mask {} < {file}",
                k.b("zspec"),
                k.w("edges.ppm")
            ),
        )?;
        for (m, leaf) in methods_list(Kind::Aa) {
            render(file, &leaf, &format!("{m}.ppm"))?;
            let text = k.out(&format!(
                "{} compare --metrics --edges {} {} {}",
                k.b("zspec"),
                k.w("edges.ppm"),
                k.w("ref.ppm"),
                k.w(&format!("{m}.ppm"))
            ))?;
            println!(
                "{scene:<12} {m:<6} {:>9.2} {:>9.2} {:>10.4}",
                metric(&text, "edge_rmse"),
                metric(&text, "rmse"),
                metric(&text, "differing_fraction")
            );
        }
        if let Some(dir) = &a.pictures {
            std::fs::create_dir_all(dir)
                .map_err(|e| Error::io(format!("{}: {e}", dir.display())))?;
            let frames = ["point", "ss4", "abuf", "ref"]
                .map(|n| read_ppm(&k.work(&format!("{n}.ppm"))))
                .into_iter()
                .collect::<Result<Vec<_>>>()?;
            let runs = k.work("montage.txt");
            std::fs::write(&runs, montage(&frames)).map_err(|e| Error::io(e.to_string()))?;
            let png = dir.join(format!("aa-{scene}.png"));
            k.out(&format!(
                "{} -o {} < {}",
                k.b("zbuf"),
                crate::kit::q(&png.display().to_string()),
                crate::kit::q(&runs.display().to_string())
            ))?;
        }
    }
    Ok(())
}

/// A binary PPM's width, height and pixels (its first frame).
pub fn read_ppm(path: &std::path::Path) -> Result<(usize, usize, Vec<u8>)> {
    let data = std::fs::read(path).map_err(|e| Error::io(format!("{}: {e}", path.display())))?;
    let mut fields = Vec::new();
    let mut i = 0;
    while fields.len() < 4 {
        while data.get(i).is_some_and(u8::is_ascii_whitespace) {
            i += 1;
        }
        let j = i + data[i..]
            .iter()
            .take_while(|b| !b.is_ascii_whitespace())
            .count();
        fields.push(String::from_utf8_lossy(&data[i..j]).into_owned());
        i = j;
    }
    let bad = || Error::data(format!("{}: not a PPM", path.display()));
    let w: usize = fields[1].parse().map_err(|_| bad())?;
    let h: usize = fields[2].parse().map_err(|_| bad())?;
    let px = data.get(i + 1..i + 1 + 3 * w * h).ok_or_else(bad)?.to_vec();
    Ok((w, h, px))
}

/// Frames side by side, magnified 4×, 4 pixels of white between, as a stream of `run`
/// records (which `zbuf -o` writes as a PNG).
pub fn montage(frames: &[(usize, usize, Vec<u8>)]) -> String {
    use std::fmt::Write;
    let (w, h) = (frames[0].0, frames[0].1);
    let (z, gap) = (4, 4);
    let width = frames.len() * (w * z + gap) - gap;
    let mut s = format!("polypipe 2 fragments {width} {}\n", h * z);
    for y in 0..h * z {
        let _ = writeln!(s, "run {y} 0 {width} 255 255 255");
    }
    for (k, (_, _, px)) in frames.iter().enumerate() {
        let x0 = k * (w * z + gap);
        for y in 0..h * z {
            for x in 0..w {
                let o = 3 * ((y / z) * w + x);
                let _ = writeln!(
                    s,
                    "run {y} {} {} {} {} {}",
                    x0 + x * z,
                    x0 + x * z + z,
                    px[o],
                    px[o + 1],
                    px[o + 2]
                );
            }
        }
    }
    s.push_str("END\n");
    s
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_montage_magnifies_each_pixel_four_times() {
        let f = (1, 1, vec![10, 20, 30]);
        let m = super::montage(&[f.clone(), f]);
        assert!(m.starts_with("polypipe 2 fragments 12 4\nrun 0 0 12 255 255 255\n"));
        assert!(m.contains("run 3 8 12 10 20 30\n"));
        assert!(m.ends_with("END\n"));
    }
}
