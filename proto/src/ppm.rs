//! Frames as PPM images, the pipeline's picture format (netpbm's `ppm(5)`): written by
//! `zbuf` and the exact reference `zspec`, read back by `zspec compare` and the tests.
//!
//! A stream of frames is PPM images one after another, as netpbm's tools and ffmpeg's
//! `image2pipe` read them. Binary PPM (P6) is the default; plain PPM (P3, the pixel
//! values as decimal text) is the picture's text form, what `--text` asks for. Both are
//! read. Only 8-bit images (maximum value 255) are written or read.

use crate::text::{line_too_long, Shown, MAX_LINE_BYTES};
use crate::{Colour, StreamError};
use std::io::{self, BufRead, Read, Write};

/// Which PPM form to write.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// P6: a text header, then three bytes a pixel.
    Binary,
    /// P3: every value as decimal text, lines of at most 70 characters.
    Plain,
}

/// The largest width or height read: the stages' own limit on a screen.
pub const MAX_SIDE: u64 = 65536;

/// An RGB image, row-major from the top-left.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Colour>,
}

impl Image {
    /// The colour of pixel (x, y).
    pub fn at(&self, x: u32, y: u32) -> Colour {
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// Whether a 4-neighbour of (x, y) has another colour: the pixel lies on a boundary
    /// between polygons (or a polygon and the background).
    pub fn is_edge_pixel(&self, x: u32, y: u32) -> bool {
        let here = self.at(x, y);
        let (x, y) = (x as i64, y as i64);
        [(-1, 0), (1, 0), (0, -1), (0, 1)].iter().any(|(dx, dy)| {
            let (nx, ny) = (x + dx, y + dy);
            nx >= 0
                && ny >= 0
                && nx < self.width as i64
                && ny < self.height as i64
                && self.at(nx as u32, ny as u32) != here
        })
    }
}

/// Writes one image of `width`×`height` pixels, given as RGB bytes row by row from the
/// top-left (`rgb.len()` is 3·width·height).
pub fn write<W: Write>(
    out: &mut W,
    width: u32,
    height: u32,
    rgb: &[u8],
    form: Form,
) -> io::Result<()> {
    debug_assert_eq!(rgb.len(), 3 * width as usize * height as usize);
    match form {
        Form::Binary => {
            write!(out, "P6\n{width} {height}\n255\n")?;
            out.write_all(rgb)
        }
        Form::Plain => {
            write!(out, "P3\n{width} {height}\n255\n")?;
            // Each row starts a line; a line ends before it would pass 70 characters.
            let mut line = String::with_capacity(80);
            for row in rgb.chunks(3 * width.max(1) as usize) {
                for value in row {
                    let word = value.to_string();
                    if !line.is_empty() && line.len() + 1 + word.len() > 70 {
                        line.push('\n');
                        out.write_all(line.as_bytes())?;
                        line.clear();
                    }
                    if !line.is_empty() {
                        line.push(' ');
                    }
                    line.push_str(&word);
                }
                line.push('\n');
                out.write_all(line.as_bytes())?;
                line.clear();
            }
            Ok(())
        }
    }
}

/// Reads the next image of a stream of PPMs (P6 or P3); `None` at the clean end of the
/// stream. A malformed image is [`StreamError::Invalid`] saying what is wrong; a failed
/// read is [`StreamError::Io`].
pub fn read<R: BufRead>(input: &mut R) -> Result<Option<Image>, StreamError> {
    // Whitespace may separate images.
    loop {
        let buf = input.fill_buf()?;
        match buf.first() {
            None => return Ok(None),
            Some(b) if b.is_ascii_whitespace() => input.consume(1),
            Some(_) => break,
        }
    }
    let mut magic = [0u8; 2];
    read_exact(input, &mut magic, "the magic number")?;
    let plain = match &magic {
        b"P6" => false,
        b"P3" => true,
        _ => {
            return Err(invalid(format!(
                "expected a PPM (P6 or P3), found {:?}",
                String::from_utf8_lossy(&magic)
            )))
        }
    };
    let mut field = |what: &str| -> Result<u64, StreamError> {
        number(input, what)?
            .ok_or_else(|| invalid(format!("the PPM ends before the {what} (cut short?)")))
    };
    let width = field("width")?;
    let height = field("height")?;
    let maxval = field("maximum value")?;
    if maxval != 255 {
        return Err(invalid(format!(
            "maximum value {maxval}: only 8-bit PPMs (255) are read"
        )));
    }
    if !(1..=MAX_SIDE).contains(&width) || !(1..=MAX_SIDE).contains(&height) {
        return Err(invalid(format!(
            "image size {width}x{height} is out of range (1 to {MAX_SIDE} a side)"
        )));
    }
    let n = (width * height * 3) as usize;
    let bytes = if plain {
        let mut bytes = Vec::new();
        for k in 0..n {
            let what = "pixel values";
            let v = number(input, what)?.ok_or_else(|| {
                invalid(format!(
                    "the PPM ends after {k} of the {width}x{height} image's {n} {what} (cut short?)"
                ))
            })?;
            bytes.push(
                u8::try_from(v).map_err(|_| invalid(format!("pixel value {v} is above 255")))?,
            );
        }
        bytes
    } else {
        // Exactly one whitespace byte ends the header.
        let mut sep = [0u8; 1];
        read_exact(input, &mut sep, "the end of the header")?;
        if !sep[0].is_ascii_whitespace() {
            return Err(invalid("expected whitespace after the PPM header"));
        }
        // Read as the bytes arrive rather than allocating the header's size up front:
        // a header that promises 12 GiB and ends costs only what was sent.
        let mut bytes = Vec::new();
        input.take(n as u64).read_to_end(&mut bytes)?;
        if bytes.len() < n {
            return Err(invalid(format!(
                "the PPM ends before the {width}x{height} pixels ({} of {n} bytes; cut short?)",
                bytes.len()
            )));
        }
        bytes
    };
    let pixels = bytes.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
    Ok(Some(Image {
        width: width as u32,
        height: height as u32,
        pixels,
    }))
}

/// Reads every image of a stream of PPMs; an error says which frame (from 0) it is in.
pub fn read_all<R: BufRead>(mut input: R) -> Result<Vec<Image>, StreamError> {
    let mut images = Vec::new();
    loop {
        match read(&mut input) {
            Ok(Some(image)) => images.push(image),
            Ok(None) => return Ok(images),
            Err(StreamError::Invalid(m)) => {
                return Err(StreamError::Invalid(format!("frame {}: {m}", images.len())))
            }
            Err(e) => return Err(e),
        }
    }
}

fn invalid(msg: impl Into<String>) -> StreamError {
    StreamError::Invalid(msg.into())
}

/// `read_exact`, with a cut-short PPM reported as bad input rather than an I/O failure.
fn read_exact<R: BufRead>(input: &mut R, buf: &mut [u8], what: &str) -> Result<(), StreamError> {
    match input.read_exact(buf) {
        Err(e) if e.kind() == io::ErrorKind::UnexpectedEof => {
            Err(invalid(format!("the PPM ends before {what} (cut short?)")))
        }
        other => Ok(other?),
    }
}

/// Reads one decimal number of a PPM: skips whitespace and `#` comments, then reads
/// digits. `Ok(None)` at the end of the input before the number.
fn number<R: BufRead>(input: &mut R, what: &str) -> Result<Option<u64>, StreamError> {
    let mut digits = String::new();
    loop {
        let byte = {
            let buf = input.fill_buf()?;
            match buf.first() {
                Some(&b) => b,
                None if digits.is_empty() => return Ok(None),
                None => break,
            }
        };
        if byte.is_ascii_digit() {
            if digits.len() > 20 {
                // No u64 has more digits: stop reading what may be an endless number.
                return Err(invalid(format!(
                    "the {what} `{}` is too large",
                    Shown(&digits)
                )));
            }
            digits.push(byte as char);
            input.consume(1);
        } else if !digits.is_empty() {
            break;
        } else if byte == b'#' {
            let mut comment = Vec::new();
            let limit = MAX_LINE_BYTES as u64 + 1;
            input.by_ref().take(limit).read_until(b'\n', &mut comment)?;
            if comment.len() as u64 == limit && comment.last() != Some(&b'\n') {
                return Err(invalid(format!(
                    "a comment in the header: {}",
                    line_too_long()
                )));
            }
        } else if byte.is_ascii_whitespace() {
            input.consume(1);
        } else {
            return Err(invalid(format!(
                "expected the {what}, found byte {byte:#04x}"
            )));
        }
    }
    digits
        .parse()
        .map(Some)
        .map_err(|_| invalid(format!("the {what} `{}` is too large", Shown(&digits))))
}

#[cfg(test)]
mod tests {
    use super::*;

    const R: Colour = [255, 0, 0];
    const G: Colour = [0, 255, 0];
    const B: Colour = [0, 0, 255];
    const K: Colour = [0, 0, 0];

    fn bytes(pixels: &[Colour]) -> Vec<u8> {
        pixels.as_flattened().to_vec()
    }

    #[test]
    fn binary_round_trip() {
        let a = vec![R, G, B, K, R, G];
        let mut out = Vec::new();
        write(&mut out, 3, 2, &bytes(&a), Form::Binary).unwrap();
        assert_eq!(&out[..11], b"P6\n3 2\n255\n");
        assert_eq!(out.len(), 11 + 18);
        write(&mut out, 3, 2, &bytes(&[K; 6]), Form::Binary).unwrap();
        let images = read_all(&out[..]).unwrap();
        assert_eq!(images.len(), 2);
        assert_eq!(images[0].pixels, a);
        assert_eq!(images[0].at(0, 1), K);
        assert_eq!(images[1].pixels, vec![K; 6]);
        // Comments and varied whitespace in the header.
        let one = read_all(&b"P6 # c\n1\t1 255\n\x01\x02\x03"[..]).unwrap();
        assert_eq!(one[0].pixels, vec![[1, 2, 3]]);
    }

    #[test]
    fn plain_form_is_text_with_short_lines() {
        let mut out = Vec::new();
        write(&mut out, 2, 1, &[255, 0, 0, 1, 2, 3], Form::Plain).unwrap();
        assert_eq!(out, b"P3\n2 1\n255\n255 0 0 1 2 3\n");
        // A wide row wraps before 70 characters, and a new row starts a new line.
        let wide = vec![255u8; 3 * 30 * 2];
        let mut out = Vec::new();
        write(&mut out, 30, 2, &wide, Form::Plain).unwrap();
        let text = String::from_utf8(out.clone()).unwrap();
        assert!(text.lines().all(|l| l.len() <= 70), "{text}");
        assert_eq!(text.lines().count(), 3 + 2 * 6, "{text}");
        let back = read_all(&out[..]).unwrap();
        assert_eq!(back[0].pixels, vec![[255; 3]; 60]);
        // Plain and binary frames may follow one another in one stream.
        write(&mut out, 1, 1, &[7, 8, 9], Form::Binary).unwrap();
        assert_eq!(read_all(&out[..]).unwrap()[1].pixels, vec![[7, 8, 9]]);
    }

    #[test]
    fn bad_ppms_are_refused_saying_which_frame_and_why() {
        let err = |b: &[u8]| read_all(b).unwrap_err().to_string();
        assert_eq!(
            err(b"P5\n1 1\n255\n"),
            "frame 0: expected a PPM (P6 or P3), found \"P5\""
        );
        assert_eq!(
            err(b"P6\n1 1\n65535\n"),
            "frame 0: maximum value 65535: only 8-bit PPMs (255) are read"
        );
        assert_eq!(
            err(b"P6\n1 1\n255\n\x01\x02\x03P6\n2 1\n255\n\x01\x02\x03"),
            "frame 1: the PPM ends before the 2x1 pixels (3 of 6 bytes; cut short?)"
        );
        assert_eq!(
            err(b"P6\n2"),
            "frame 0: the PPM ends before the height (cut short?)"
        );
        assert_eq!(
            err(b"P6\n0 1\n255\n"),
            "frame 0: image size 0x1 is out of range (1 to 65536 a side)"
        );
        assert_eq!(
            err(b"P3\n1 1\n255\n1 2 300\n"),
            "frame 0: pixel value 300 is above 255"
        );
        assert_eq!(
            err(b"P3\n1 1\n255\n1 2"),
            "frame 0: the PPM ends after 2 of the 1x1 image's 3 pixel values (cut short?)"
        );
        assert_eq!(
            err(b"P6\nx"),
            "frame 0: expected the width, found byte 0x78"
        );
        assert_eq!(
            err(b"P"),
            "frame 0: the PPM ends before the magic number (cut short?)"
        );
        assert!(matches!(read_all(&b"P"[..]), Err(StreamError::Invalid(_))));
    }

    #[test]
    fn a_huge_header_without_its_pixels_allocates_nothing_much() {
        let e = read_all(&b"P6\n65536 65536\n255\n\x01"[..]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "frame 0: the PPM ends before the 65536x65536 pixels (1 of 12884901888 bytes; cut short?)"
        );
    }

    #[test]
    fn edge_pixels_have_a_differently_coloured_neighbour() {
        let img = Image {
            width: 3,
            height: 3,
            pixels: vec![R, R, R, R, R, R, R, R, G],
        };
        assert!(!img.is_edge_pixel(0, 0));
        assert!(!img.is_edge_pixel(1, 1));
        assert!(img.is_edge_pixel(2, 1));
        assert!(img.is_edge_pixel(2, 2));
    }
}
