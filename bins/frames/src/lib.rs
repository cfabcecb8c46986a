//! # frames: a movie's frames, counted or cut into a contiguous range
//!
//! A movie is `frame { NEXT.FRAME frame } END` (thesis Appendix 1; docs/DESIGN.md,
//! "Grammar"), so its frames are independent: a range of them is a movie of its own, and
//! rendering the ranges one after another gives the frames of the whole.
//! `scripts/render-frames.sh` cuts a movie this way to render its parts on other hosts
//! (`render.sh --hosts … --by frames`).
//!
//! The cut renumbers nothing: polygon numbers restart in every frame, so the records of
//! the frames kept pass through unchanged, and only the frame boundaries around them are
//! new (no NEXT.FRAME before the first frame kept, END after the last).

use proto::codec::{Control, Record};
use proto::{Reader, StreamError, Token, Writer};
use std::io::{Read, Write};

/// A half-open range of frame numbers (frames numbered from 0): `from`, `from + 1`, …,
/// `to − 1`, or to the end of the movie when `to` is `None`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameRange {
    pub from: u64,
    pub to: Option<u64>,
}

impl FrameRange {
    /// A range that selects at least one frame, or a message saying why not.
    pub fn new(from: u64, to: Option<u64>) -> Result<Self, String> {
        match to {
            Some(to) if to <= from => Err(format!(
                "--to {to} must be greater than --from {from} (the range is from..to, \
                 `to` not included)"
            )),
            _ => Ok(FrameRange { from, to }),
        }
    }

    fn contains(&self, frame: u64) -> bool {
        frame >= self.from && !matches!(self.to, Some(to) if frame >= to)
    }
}

/// The number of frames in a movie: one more than its NEXT.FRAME records. Reads (and so
/// checks) the whole stream.
pub fn count_frames<T: Record, R: Read>(reader: &mut Reader<T, R>) -> Result<u64, StreamError> {
    let mut frames = 1;
    while let Some(record) = reader.next_record()? {
        if record.control() == Control::NextFrame {
            frames += 1;
        }
    }
    Ok(frames)
}

/// Copies the frames of `range` from `reader` to `writer` as a movie of their own, and
/// returns how many were written. Reading stops at the end of the range: what follows is
/// not read (nor checked). A range that starts past the movie's last frame is an error
/// naming the movie's length, since a movie of no frames cannot be written.
pub fn pass_frames<R: Read, W: Write>(
    reader: &mut Reader<Token, R>,
    writer: &mut Writer<Token, W>,
    range: FrameRange,
) -> stagecli::Result<u64> {
    let mut frame = 0; // the frame the next record belongs to
    while let Some(record) = reader.next_record()? {
        match record.control() {
            Control::NextFrame => {
                // A boundary between two kept frames stays; the one after the range's
                // last frame becomes the END of the cut.
                if range.to == Some(frame + 1) {
                    writer.write(&Token::End)?;
                    writer.flush()?;
                    return Ok(frame + 1 - range.from);
                }
                if range.contains(frame) {
                    writer.write(&record)?;
                }
                frame += 1;
            }
            Control::End => {
                if frame < range.from {
                    return Err(stagecli::Error::data(format!(
                        "the movie has {} frame{} (0 to {frame}): --from {} selects none",
                        frame + 1,
                        if frame == 0 { "" } else { "s" },
                        range.from
                    )));
                }
                writer.write(&record)?;
                writer.flush()?;
                return Ok(frame + 1 - range.from);
            }
            _ => {
                if range.contains(frame) {
                    writer.write(&record)?;
                }
            }
        }
    }
    unreachable!("the reader returns END before it returns None")
}

#[cfg(test)]
mod tests {
    use super::*;
    use proto::{Form, Header, Space};

    /// A text movie of `n` frames; frame k has k + 1 polygons whose colour is (k, i, 0).
    fn movie(n: u64) -> String {
        let mut s = String::from("polypipe 1 world\n");
        for k in 0..n {
            if k > 0 {
                s += "NEXT.FRAME\n";
            }
            for i in 0..=k {
                if i > 0 {
                    s += "NEXT.POLYGON\n";
                }
                s += &format!("colour {k} {i} 0\n0 0 0\n1 0 0\n0 1 {k}\n");
            }
        }
        s + "END\n"
    }

    fn cut(input: &str, range: FrameRange) -> Result<(String, u64), Box<dyn std::error::Error>> {
        let mut reader = Reader::<Token, _>::new(input.as_bytes())?;
        let mut out = Vec::new();
        let n = {
            let mut writer = Writer::new(&mut out, Header::new(Space::World), Form::Text)?;
            pass_frames(&mut reader, &mut writer, range)?
        };
        Ok((String::from_utf8(out)?, n))
    }

    #[test]
    fn counts_frames() {
        for n in [1, 2, 7] {
            let text = movie(n);
            let mut reader = Reader::<Token, _>::new(text.as_bytes()).unwrap();
            assert_eq!(count_frames(&mut reader).unwrap(), n);
        }
    }

    #[test]
    fn a_range_is_the_movie_of_those_frames() {
        // Frames 2..4 of a 6-frame movie are, record for record, the frames 2 and 3.
        let (text, n) = cut(&movie(6), FrameRange::new(2, Some(4)).unwrap()).unwrap();
        assert_eq!(n, 2);
        let expected = "polypipe 1 world\n\
            colour 2 0 0\n0 0 0\n1 0 0\n0 1 2\nNEXT.POLYGON\n\
            colour 2 1 0\n0 0 0\n1 0 0\n0 1 2\nNEXT.POLYGON\n\
            colour 2 2 0\n0 0 0\n1 0 0\n0 1 2\nNEXT.FRAME\n\
            colour 3 0 0\n0 0 0\n1 0 0\n0 1 3\nNEXT.POLYGON\n\
            colour 3 1 0\n0 0 0\n1 0 0\n0 1 3\nNEXT.POLYGON\n\
            colour 3 2 0\n0 0 0\n1 0 0\n0 1 3\nNEXT.POLYGON\n\
            colour 3 3 0\n0 0 0\n1 0 0\n0 1 3\nEND\n";
        assert_eq!(text, expected);
    }

    #[test]
    fn the_whole_range_is_the_movie() {
        let input = movie(4);
        let (text, n) = cut(&input, FrameRange::new(0, None).unwrap()).unwrap();
        assert_eq!((text.as_str(), n), (input.as_str(), 4));
        let (text, n) = cut(&input, FrameRange::new(0, Some(4)).unwrap()).unwrap();
        assert_eq!((text.as_str(), n), (input.as_str(), 4));
    }

    #[test]
    fn ranges_concatenate_to_the_movie() {
        // Cutting at every point and joining the pieces' frames gives the movie back.
        let input = movie(5);
        let frames_of = |text: &str| -> Vec<String> {
            let body = text.strip_prefix("polypipe 1 world\n").unwrap();
            let body = body.strip_suffix("END\n").unwrap();
            body.split("NEXT.FRAME\n").map(str::to_string).collect()
        };
        let whole = frames_of(&input);
        for a in 0..5 {
            for b in a + 1..=5 {
                let (text, n) = cut(&input, FrameRange::new(a, Some(b)).unwrap()).unwrap();
                assert_eq!(n, b - a);
                assert_eq!(frames_of(&text), whole[a as usize..b as usize]);
            }
        }
    }

    #[test]
    fn a_range_past_the_end_is_cut_at_the_end() {
        let (text, n) = cut(&movie(3), FrameRange::new(2, Some(10)).unwrap()).unwrap();
        assert_eq!(n, 1);
        assert!(
            text.starts_with("polypipe 1 world\ncolour 2 0 0\n"),
            "{text}"
        );
        assert!(text.ends_with("0 1 2\nEND\n"), "{text}");
    }

    #[test]
    fn a_range_wholly_past_the_end_is_an_error() {
        let err = cut(&movie(3), FrameRange::new(3, None).unwrap()).unwrap_err();
        assert_eq!(
            err.to_string(),
            "the movie has 3 frames (0 to 2): --from 3 selects none"
        );
        let err = cut(&movie(1), FrameRange::new(1, Some(2)).unwrap()).unwrap_err();
        assert_eq!(
            err.to_string(),
            "the movie has 1 frame (0 to 0): --from 1 selects none"
        );
    }

    #[test]
    fn an_empty_range_is_refused() {
        assert!(FrameRange::new(3, Some(3)).is_err());
        assert!(FrameRange::new(3, Some(2)).is_err());
        assert!(FrameRange::new(3, Some(4)).is_ok());
    }

    #[test]
    fn reading_stops_at_the_end_of_the_range() {
        // Garbage after frame 1's boundary is never read when the range ends there.
        let input = "polypipe 1 world\ncolour 1 2 3\n0 0 0\nNEXT.FRAME\ncolour 4 5 6\n\
                     NEXT.FRAME\nthis is not a stream";
        let (text, n) = cut(input, FrameRange::new(0, Some(2)).unwrap()).unwrap();
        assert_eq!(n, 2);
        assert_eq!(
            text,
            "polypipe 1 world\ncolour 1 2 3\n0 0 0\nNEXT.FRAME\ncolour 4 5 6\nEND\n"
        );
    }
}
