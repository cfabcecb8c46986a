//! The text stream decoder (lexer and grammar) on arbitrary bytes: no panic, and every
//! error located (`line L, column C: …`) or about the input as a whole.
#![no_main]
use libfuzzer_sys::fuzz_target;
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
    drain::<Token>(data);
    drain::<Fragment>(data);
    // The same with a valid header in front, so the fuzzer reaches the records quickly.
    for header in ["polypipe 1 world\n", "polypipe 1 eye\n", "polypipe 1 screen 8 8\n", "polypipe 1 fragments 8 8\n"] {
        let mut s = header.as_bytes().to_vec();
        s.extend_from_slice(data);
        drain::<Token>(&s);
        drain::<Fragment>(&s);
    }
});
