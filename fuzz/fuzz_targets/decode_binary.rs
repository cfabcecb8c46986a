//! The binary stream decoder (stream version 5's fixed-layout records: polygons plain and
//! annotated, with vertex colours or normals, colour planes and opacity, skips, fragment spans,
//! pixels, runs and shade records) on arbitrary bytes, after the magic
//! alone and after a valid header of each space: no panic, every error a message, and
//! what was read writes back and reads again the same (polypipe_fuzz::drain).
#![no_main]
use libfuzzer_sys::fuzz_target;
use polypipe_fuzz::{binary_header, binary_header_with, drain, spaces};
use proto::header::BINARY_MAGIC;
use proto::{Fragment, Token};

fuzz_target!(|data: &[u8]| {
    let mut stream = BINARY_MAGIC.to_vec();
    stream.extend_from_slice(data);
    drain::<Token>(&stream);
    drain::<Fragment>(&stream);
    // The first byte picks a space, so the records are reached at once.
    // Its bit 2 declares vertex colours and opacity (polygon streams), so that annotated
    // records with colours, colour planes and opacities are read as valid; with bit 3
    // too, vertex normals and a lighting instead of the colours (Phong shading).
    if let Some((&pick, rest)) = data.split_first() {
        let space = spaces()[(pick % 4) as usize];
        let mut stream = if pick & 4 != 0 && space.vertex_arity() > 0 {
            let normals = pick & 8 != 0;
            let mut lighting = proto::shade::Lighting::default();
            if normals {
                lighting.specular = 0.5;
            }
            binary_header_with(
                space,
                proto::Attributes {
                    vertex_colours: !normals,
                    vertex_normals: normals,
                    lighting,
                    opacity: true,
                    ..proto::Attributes::default()
                },
            )
        } else {
            binary_header(space)
        };
        stream.extend_from_slice(rest);
        drain::<Token>(&stream);
        drain::<Fragment>(&stream);
    }
});
