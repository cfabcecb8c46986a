//! The binary stream decoder on arbitrary bytes after the magic: every record kind, no
//! panic, and every error a message (the reader, not the fuzzer, must say what is wrong).
#![no_main]
use libfuzzer_sys::fuzz_target;
use proto::header::BINARY_MAGIC;
use proto::{Fragment, Reader, Record, Token};

fn drain<T: Record>(bytes: &[u8]) {
    let Ok(mut reader) = Reader::<T, _>::new(bytes) else {
        return;
    };
    loop {
        match reader.next_record() {
            Ok(Some(_)) => {}
            Ok(None) => break,
            Err(e) => {
                assert!(!e.to_string().is_empty());
                break;
            }
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let mut stream = BINARY_MAGIC.to_vec();
    stream.extend_from_slice(data);
    drain::<Token>(&stream);
    drain::<Fragment>(&stream);
});
