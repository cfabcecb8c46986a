//! How the chart tells a pixel whose *visible polygon* is wrong from one that is only
//! aliased: every scene it charts is first drawn in colours of its own, each polygon of a
//! frame one flat colour no other polygon of that frame has, and never the background's
//! black. A point-sampling method's pixel then equals the exact point-sampled reference's
//! (`zspec`, pixel centres, the tie rule) exactly when it shows the same polygon, so the
//! share of pixels unlike that reference is the share whose visible polygon differs: the
//! visibility error of the chart's second figure. The same frames, against the 16×16
//! reference, give the RMS error of the first.
//!
//! Smooth shading (vertex colours or normals), shade planes and opacity are dropped with
//! the old colours: the charted scenes are flat and opaque, the geometry untouched.

use crate::error::{Context, Error, Result};
use proto::{Colour, Form, Reader, Token, Writer, OPAQUE};
use std::path::Path;

/// Polygon `k` of a frame's colour: k + 1 times an odd constant modulo 2²⁴, a bijection
/// of the 24-bit colours, so that the colours of a frame's first 16,777,215 polygons are
/// distinct, none black (0 only for k + 1 = 2²⁴), and neighbours far apart in colour.
pub fn colour_of(k: usize) -> Colour {
    let c = ((k as u64 + 1).wrapping_mul(0x9E_3779) & 0xFF_FFFF) as u32;
    [(c >> 16) as u8, (c >> 8) as u8, c as u8]
}

/// Writes the scene at `from` to `to` (binary) with every polygon in its own colour
/// ([`colour_of`], numbered from 0 in each frame), flat and opaque.
pub fn recolour(from: &Path, to: &Path) -> Result<()> {
    let file =
        std::fs::File::open(from).with_context(|| format!("cannot open {}", from.display()))?;
    let mut reader = Reader::<Token, _>::new(std::io::BufReader::new(file))
        .with_context(|| format!("reading {}", from.display()))?;
    let mut header = *reader.header();
    header.attributes.vertex_colours = false;
    header.attributes.vertex_normals = false;
    header.attributes.opacity = false;
    let mut writer = Writer::<Token, _>::new(Vec::new(), header, Form::Binary)?;
    let mut k = 0usize;
    loop {
        let token = reader
            .next_record()
            .with_context(|| format!("reading {}", from.display()))?;
        match token {
            Some(Token::Polygon(mut p)) => {
                if k >= 0xFF_FFFF {
                    return Err(Error::Data(format!(
                        "{}: a frame of more than 16,777,215 polygons has no distinct colours",
                        from.display()
                    )));
                }
                p.colour = colour_of(k);
                p.vertex_attrs.clear();
                p.shade = None;
                p.opacity = OPAQUE;
                writer.write(&Token::Polygon(p))?;
                k += 1;
            }
            Some(Token::Skip(n)) => {
                k += n as usize;
                writer.write(&Token::Skip(n))?;
            }
            Some(Token::NextFrame) => {
                k = 0;
                writer.write(&Token::NextFrame)?;
            }
            Some(Token::End) | None => {
                writer.write(&Token::End)?;
                break;
            }
        }
    }
    let bytes = writer.into_inner()?;
    stagecli::whole::write_whole(to, &bytes)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_colours_of_a_frame_are_distinct_and_none_is_black() {
        let mut seen = std::collections::HashSet::new();
        for k in 0..200_000 {
            let c = colour_of(k);
            assert_ne!(c, [0, 0, 0], "{k}");
            assert!(seen.insert(c), "{k}: {c:?} twice");
        }
        assert_eq!(colour_of(0xFF_FFFF - 1), {
            let c = (0xFF_FFFFu64 * 0x9E_3779) & 0xFF_FFFF;
            [(c >> 16) as u8, (c >> 8) as u8, c as u8]
        });
    }

    #[test]
    fn a_scene_is_recoloured_flat_frame_by_frame() {
        let dir = tempfile::tempdir().unwrap();
        let from = dir.path().join("a.txt");
        std::fs::write(
            &from,
            "polypipe 1 world\ncolour 9 9 9\n0 0 0\n1 0 0\n0 1 0\nNEXT.POLYGON\n\
             colour 9 9 9\n0 0 1\n1 0 1\n0 1 1\nNEXT.FRAME\ncolour 7 7 7\n0 0 0\n1 0 0\n0 1 0\nEND\n",
        )
        .unwrap();
        let to = dir.path().join("a.pp");
        recolour(&from, &to).unwrap();
        let mut r = Reader::<Token, _>::new(std::fs::File::open(&to).unwrap()).unwrap();
        let mut colours = Vec::new();
        while let Some(t) = r.next_record().unwrap() {
            match t {
                Token::Polygon(p) => colours.push(Some(p.colour)),
                Token::NextFrame => colours.push(None),
                _ => break,
            }
        }
        assert_eq!(
            colours,
            [
                Some(colour_of(0)),
                Some(colour_of(1)),
                None,
                Some(colour_of(0))
            ]
        );
    }
}
