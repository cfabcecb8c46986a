//! A text stream read in pieces on threads (`stagecli::pieces`, viewxf's reader) against
//! the one-reader loop (`stagecli::filter_records`) on arbitrary text after a world
//! header: the same output bytes, the same message (or none), whatever the bytes, the
//! piece size, the number of workers, and how the input arrives. The first four bytes
//! choose a piece size of 16 to 526 bytes (so that arbitrary inputs are cut many times),
//! 1 to 3 workers, reads of 1 to 256 bytes, and after how many looks the input runs dry
//! (255: never), which hands the rest to the one reader. The transformation refuses a
//! polygon with a vertex beyond x = 90, as a stage refuses one it cannot process. Run with
//! `-dict=dict/text.dict` for the keywords.
#![no_main]
use libfuzzer_sys::fuzz_target;
use proto::{Form, Header, Polygon, Reader, Space, Token, Writer};
use std::io::Read;

fn shift(p: &mut Polygon) -> Result<(), String> {
    if p.vertices.iter().any(|v| v.x > 90.0) {
        return Err("a vertex beyond x = 90".into());
    }
    for v in &mut p.vertices {
        v.x += 1.0;
    }
    Ok(())
}

/// Hands the bytes out a few at a time, as a pipe does.
struct Chunks<'a>(&'a [u8], usize);

impl Read for Chunks<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.1.min(buf.len()).min(self.0.len());
        buf[..n].copy_from_slice(&self.0[..n]);
        self.0 = &self.0[n..];
        Ok(n)
    }
}

fuzz_target!(|data: &[u8]| {
    let [a, b, c, d, body @ ..] = data else {
        return;
    };
    let (size, workers) = (16 + 2 * *a as usize, 1 + (*b % 3) as usize);
    let (chunk, dry_after) = (1 + *c as usize, *d);
    let mut text = b"polypipe 1 world\n".to_vec();
    text.extend_from_slice(body);
    let header = Header::new(Space::World);

    let mut want = Writer::new(Vec::new(), header, Form::Binary).unwrap();
    let want_err = Reader::<Token, _>::new(&text[..])
        .map_err(|e| stagecli::input_error("stdin", e))
        .and_then(|mut r| stagecli::filter_records(&mut r, &mut want, &mut shift, "shifting"))
        .err()
        .map(|e| e.to_string());
    want.flush().unwrap();

    let mut got = Writer::new(Vec::new(), header, Form::Binary).unwrap();
    let Ok(rest) = Reader::<Token, _>::new(Chunks(&text, chunk))
        .unwrap()
        .into_text_rest()
    else {
        panic!("a world header line ends where the header does");
    };
    let looks = std::cell::Cell::new(0u32);
    let ready = || {
        looks.set(looks.get() + 1);
        dry_after == 255 || looks.get() <= dry_after as u32
    };
    let got_err = stagecli::pieces::filter_text_in_pieces(
        rest,
        header,
        header,
        &mut got,
        shift,
        "shifting",
        (workers, size),
        ready,
    )
    .err()
    .map(|e| e.to_string());
    got.flush().unwrap();

    assert_eq!(got_err, want_err);
    assert!(
        got.into_inner().unwrap() == want.into_inner().unwrap(),
        "outputs differ"
    );
});
