//! The text stream decoder (lexer and grammar, `skip` and `run` included; vertex colours,
//! vertex normals and the lighting words, opacity, `shade` lines and fragment `shade`
//! records too) on arbitrary
//! bytes: no panic, every error located (`line L, column C: …`) or about the input as a
//! whole, and what was read writes back and reads again the same in both forms
//! (polypipe_fuzz::drain). Run with `-dict=dict/text.dict` for the keywords.
#![no_main]
use libfuzzer_sys::fuzz_target;
use polypipe_fuzz::drain;
use proto::{Fragment, Token};

fuzz_target!(|data: &[u8]| {
    drain::<Token>(data);
    drain::<Fragment>(data);
    // The same with a valid header in front, so the fuzzer reaches the records quickly.
    for header in [
        "polypipe 1 world\n",
        "polypipe 1 eye\n",
        "polypipe 1 screen 8 8\n",
        "polypipe 1 screen 8 8 depth projective 0.001 1000\n",
        "polypipe 2 fragments 8 8\n",
        "polypipe 1 world vertex-colours opacity\n",
        "polypipe 1 eye vertex-colours\n",
        "polypipe 1 screen 8 8 depth reciprocal 1 vertex-colours\n",
        "polypipe 1 world vertex-normals ambient 0.2 light 0 0 1 0.8 specular 0.6 20\n",
        "polypipe 2 fragments 8 8 depth reciprocal 1 vertex-normals light 1 0 0 1\n",
    ] {
        let mut s = header.as_bytes().to_vec();
        s.extend_from_slice(data);
        drain::<Token>(&s);
        drain::<Fragment>(&s);
    }
});
