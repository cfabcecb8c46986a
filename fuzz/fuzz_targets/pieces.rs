//! A text stream read in pieces on threads (`stagecli::pieces`, viewxf's reader) against
//! the one-reader loop (`stagecli::filter_records`) on arbitrary text after a world
//! header: the same output bytes, the same message (or none), whatever the bytes, the
//! piece size and the number of workers. The first two bytes choose a piece size of 16 to
//! 527 bytes (so that arbitrary inputs are cut many times) and 1 to 3 workers; the
//! transformation refuses a polygon with a vertex beyond x = 90, as a stage refuses one it
//! cannot process. Run with `-dict=dict/text.dict` for the keywords.
#![no_main]
use libfuzzer_sys::fuzz_target;
use proto::{Form, Header, Polygon, Reader, Space, Token, Writer};

fn shift(p: &mut Polygon) -> Result<(), String> {
    if p.vertices.iter().any(|v| v.x > 90.0) {
        return Err("a vertex beyond x = 90".into());
    }
    for v in &mut p.vertices {
        v.x += 1.0;
    }
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    let (size, workers, body) = match data {
        [a, b, rest @ ..] => (16 + 2 * *a as usize, 1 + (*b % 3) as usize, rest),
        _ => return,
    };
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
    let Ok(rest) = Reader::<Token, _>::new(&text[..]).unwrap().into_text_rest() else {
        panic!("a world header line ends where the header does");
    };
    let got_err = stagecli::pieces::filter_text_in_pieces(
        rest, header, header, &mut got, shift, "shifting", workers, size,
    )
    .err()
    .map(|e| e.to_string());
    got.flush().unwrap();

    assert_eq!(got_err, want_err);
    assert!(got.into_inner().unwrap() == want.into_inner().unwrap(), "outputs differ");
});
