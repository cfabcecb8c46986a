//! The binary stream decoder on arbitrary bytes after the magic: every record kind, no
//! panic, and every error a message (the reader, not the fuzzer, must say what is wrong).
#![no_main]
use libfuzzer_sys::fuzz_target;
use polypipe_fuzz::drain;
use proto::header::BINARY_MAGIC;
use proto::{Fragment, Token};

fuzz_target!(|data: &[u8]| {
    let mut stream = BINARY_MAGIC.to_vec();
    stream.extend_from_slice(data);
    drain::<Token>(&stream);
    drain::<Fragment>(&stream);
});
