//! The binary stream decoder (stream version 4's fixed-layout records: polygons plain and
//! annotated, skips, fragment spans, pixels and runs) on arbitrary bytes, after the magic
//! alone and after a valid header of each space: no panic, every error a message, and
//! what was read writes back and reads again the same (polypipe_fuzz::drain).
#![no_main]
use libfuzzer_sys::fuzz_target;
use polypipe_fuzz::{binary_header, drain, spaces};
use proto::header::BINARY_MAGIC;
use proto::{Fragment, Token};

fuzz_target!(|data: &[u8]| {
    let mut stream = BINARY_MAGIC.to_vec();
    stream.extend_from_slice(data);
    drain::<Token>(&stream);
    drain::<Fragment>(&stream);
    // The first byte picks a space, so the records are reached at once.
    if let Some((&pick, rest)) = data.split_first() {
        let space = spaces()[(pick % 4) as usize];
        let mut stream = binary_header(space);
        stream.extend_from_slice(rest);
        drain::<Token>(&stream);
        drain::<Fragment>(&stream);
    }
});
