//! Cutting the movie into chunks, each a movie of its own.

use proto::codec::{Control, Record};
use proto::{Form, Reader, SpaceKind, Token, Writer};
use stagecli::{Error, Result};
use std::io::Read;

/// One chunk of the movie: a movie of its own, in the binary form.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Chunk {
    /// Its place among the chunks, from 0.
    pub index: usize,
    /// The movie's number of its first frame (from 0).
    pub first: u64,
    /// How many frames it has.
    pub frames: u64,
    /// The stream: the movie's header, the frames' records, END.
    pub bytes: Vec<u8>,
}

/// Cuts a movie into chunks of `size` frames (the last may have fewer), reading it only
/// as far as the chunk asked for. Records pass unchanged (polygon numbers restart in
/// every frame); only the frame boundaries at a cut are new: END ends a chunk, and the
/// next starts with the header and no NEXT.FRAME.
pub struct Cutter<R: Read> {
    reader: Reader<Token, R>,
    size: u64,
    next_index: usize,
    next_frame: u64,
    done: bool,
}

impl<R: Read> Cutter<R> {
    /// A cutter of the movie `reader` reads: a polygon stream (world, eye or screen).
    pub fn new(reader: Reader<Token, R>, size: u64) -> Result<Self> {
        if SpaceKind::of(&reader.header().space) == SpaceKind::Fragments {
            return Err(Error::data(
                "a fragment stream; the hosts render polygon streams (world, eye or screen)",
            ));
        }
        Ok(Cutter {
            reader,
            size: size.max(1),
            next_index: 0,
            next_frame: 0,
            done: false,
        })
    }

    /// The next chunk, or `None` after the last.
    pub fn next_chunk(&mut self) -> Result<Option<Chunk>> {
        if self.done {
            return Ok(None);
        }
        let header = *self.reader.header();
        let mut writer = Writer::<Token, _>::new(Vec::new(), header, Form::Binary)?;
        let mut frames = 1; // the frame now being copied is the chunk's `frames`th
        loop {
            let Some(record) = self.reader.next_record()? else {
                // The reader returns END before the stream's end; a stream cut short
                // is its error, not this.
                return Err(Error::data("the movie ends without END"));
            };
            match record.control() {
                Control::NextFrame if frames == self.size => {
                    writer.write(&Token::End)?;
                    break;
                }
                Control::NextFrame => {
                    writer.write(&record)?;
                    frames += 1;
                }
                Control::End => {
                    writer.write(&record)?;
                    self.done = true;
                    break;
                }
                _ => writer.write(&record)?,
            }
        }
        let chunk = Chunk {
            index: self.next_index,
            first: self.next_frame,
            frames,
            bytes: writer.into_inner()?,
        };
        self.next_index += 1;
        self.next_frame += frames;
        Ok(Some(chunk))
    }

    /// The movie's frames cut so far.
    pub fn frames_so_far(&self) -> u64 {
        self.next_frame
    }
}

/// Counts the movie's frames (cutting it as [`Cutter`] does, holding a chunk at a time).
pub fn count_frames<R: Read>(reader: Reader<Token, R>) -> Result<u64> {
    let mut cutter = Cutter::new(reader, 64)?;
    while cutter.next_chunk()?.is_some() {}
    Ok(cutter.frames_so_far())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A text movie of `n` frames, frame k one triangle of colour (k, 0, 0).
    fn movie(n: u64) -> String {
        let frames: Vec<String> = (0..n)
            .map(|k| format!("colour {k} 0 0\n0 0 0\n1 0 0\n0 1 0\n"))
            .collect();
        format!("polypipe 1 world\n{}END\n", frames.join("NEXT.FRAME\n"))
    }

    fn chunks(n: u64, size: u64) -> Vec<Chunk> {
        let text = movie(n);
        let reader = Reader::<Token, _>::new(std::io::Cursor::new(text.into_bytes())).unwrap();
        let mut cutter = Cutter::new(reader, size).unwrap();
        let mut out = Vec::new();
        while let Some(c) = cutter.next_chunk().unwrap() {
            out.push(c);
        }
        out
    }

    /// A chunk's frames, each as its colour's red.
    fn reds(chunk: &Chunk) -> Vec<u8> {
        let mut reader = Reader::<Token, _>::new(&chunk.bytes[..]).unwrap();
        let mut reds = Vec::new();
        let mut ends = 0;
        while let Some(t) = reader.next_record().unwrap() {
            match t {
                Token::Polygon(p) => reds.push(p.colour[0]),
                Token::End => ends += 1,
                _ => {}
            }
        }
        assert_eq!(ends, 1, "a chunk ends with one END");
        reds
    }

    #[test]
    fn a_movie_is_cut_into_chunks_that_are_movies_of_their_own() {
        let c = chunks(7, 3);
        let places: Vec<(usize, u64, u64)> =
            c.iter().map(|c| (c.index, c.first, c.frames)).collect();
        assert_eq!(places, [(0, 0, 3), (1, 3, 3), (2, 6, 1)]);
        assert_eq!(reds(&c[0]), [0, 1, 2]);
        assert_eq!(reds(&c[1]), [3, 4, 5]);
        assert_eq!(reds(&c[2]), [6]);
        // One chunk of the whole movie when it is no longer than a chunk.
        let c = chunks(2, 8);
        assert_eq!((c.len(), c[0].frames), (1, 2));
    }

    #[test]
    fn a_fragment_stream_is_refused() {
        let reader = Reader::<Token, _>::new(&b"polypipe 2 fragments 4 4\nEND\n"[..]).unwrap();
        let err = Cutter::new(reader, 4).err().unwrap();
        assert_eq!(err.kind(), stagecli::Kind::Data);
        assert_eq!(
            err.to_string(),
            "a fragment stream; the hosts render polygon streams (world, eye or screen)"
        );
    }

    proptest! {
        /// Cut at any chunk size, the chunks' frames are the movie's, each once, in
        /// order, and every chunk but the last has the size asked for.
        #[test]
        fn chunks_join_to_the_movie(n in 1u64..20, size in 1u64..8) {
            let c = chunks(n, size);
            let all: Vec<u8> = c.iter().flat_map(reds).collect();
            prop_assert_eq!(all, (0..n as u8).collect::<Vec<_>>());
            for (i, chunk) in c.iter().enumerate() {
                prop_assert_eq!(chunk.first, i as u64 * size);
                if i + 1 < c.len() {
                    prop_assert_eq!(chunk.frames, size);
                }
            }
        }
    }
}
