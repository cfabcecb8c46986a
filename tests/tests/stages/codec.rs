//! The codec's contract: text and binary carry the same records, every malformed stream
//! is refused with its position, and nothing is read past END.

use proptest::prelude::*;
use proto::fragment::Fragment;
use proto::{Attributes, DepthForm, Form, Header, Polygon, Reader, Space, Token, View, Writer};

fn encode<T: proto::Record>(header: Header, records: &[T], form: Form) -> Vec<u8> {
    let mut w = Writer::new(Vec::new(), header, form).unwrap();
    for r in records {
        w.write(r).unwrap();
    }
    w.into_inner().unwrap()
}

fn decode<T: proto::Record>(bytes: &[u8]) -> Result<(Header, Vec<T>), proto::StreamError> {
    let mut r = Reader::<T, _>::new(bytes)?;
    let mut out = Vec::new();
    while let Some(rec) = r.next_record()? {
        out.push(rec);
    }
    Ok((*r.header(), out))
}

fn decode_err<T: proto::Record>(bytes: &[u8]) -> String {
    match decode::<T>(bytes) {
        Ok(_) => panic!("stream was accepted"),
        Err(e) => e.to_string(),
    }
}

/// A reader that gives one byte a read: the text reader then never holds a line whole
/// before it reads it, and takes every line word by word.
struct OneByte<'a>(&'a [u8]);

impl std::io::Read for OneByte<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let Some((&b, rest)) = self.0.split_first() else {
            return Ok(0);
        };
        if buf.is_empty() {
            return Ok(0);
        }
        buf[0] = b;
        self.0 = rest;
        Ok(1)
    }
}

/// Every record of a token stream up to the first error, and that error's message.
fn read_all(input: Box<dyn std::io::Read + '_>) -> (Vec<Token>, Option<String>) {
    let mut out = Vec::new();
    let mut r = match Reader::<Token, _>::new(input) {
        Ok(r) => r,
        Err(e) => return (out, Some(e.to_string())),
    };
    loop {
        match r.next_record() {
            Ok(Some(t)) => out.push(t),
            Ok(None) => return (out, None),
            Err(e) => return (out, Some(e.to_string())),
        }
    }
}

const EXAMPLE: &str = "polypipe 1 world
colour 255 60 60
-8 -4 0
0 7 0
8 -4 0
NEXT.POLYGON
colour 60 60 255
-9 5 4
-7 7 4
7 -7 -4
5 -9 -4
END
";

#[test]
fn design_example_reads_and_prints_back_identically() {
    let (header, tokens) = decode::<Token>(EXAMPLE.as_bytes()).unwrap();
    assert_eq!(header.space, Space::World);
    assert_eq!(
        tokens,
        vec![
            Token::Polygon(Polygon::from_xyz(
                [255, 60, 60],
                &[[-8., -4., 0.], [0., 7., 0.], [8., -4., 0.]]
            )),
            Token::Polygon(Polygon::from_xyz(
                [60, 60, 255],
                &[[-9., 5., 4.], [-7., 7., 4.], [7., -7., -4.], [5., -9., -4.]]
            )),
            Token::End,
        ]
    );
    let text = encode(header, &tokens, Form::Text);
    assert_eq!(String::from_utf8(text).unwrap(), EXAMPLE);
}

#[test]
fn empty_polygons_and_frames_survive() {
    let text = "polypipe 1 eye aspect 1.5 hither 2 yon 40\ncolour 1 2 3\nNEXT.POLYGON\ncolour 4 5 6\n1 2 3 4\nNEXT.FRAME\nNEXT.FRAME\ncolour 0 0 0\nEND\n";
    let (header, tokens) = decode::<Token>(text.as_bytes()).unwrap();
    assert_eq!(
        header.space,
        Space::Eye(View {
            aspect: 1.5,
            hither: 2.0,
            yon: 40.0
        })
    );
    assert_eq!(tokens.len(), 6);
    assert_eq!(
        String::from_utf8(encode(header, &tokens, Form::Text)).unwrap(),
        text
    );
    let bin = encode(header, &tokens, Form::Binary);
    assert_eq!(decode::<Token>(&bin).unwrap(), (header, tokens));
}

#[test]
fn fragments_round_trip() {
    let header = Header::new(Space::Fragments {
        width: 8,
        height: 4,
    });
    let records = vec![
        Fragment::Polygon([9, 8, 7]),
        Fragment::Span {
            y: 3,
            x0: 1,
            x1: 8,
            z: -0.05,
            dz: 1.0 / 3.0,
        },
        Fragment::Pixel {
            x: 7,
            y: 0,
            z: 12.0,
        },
        Fragment::Polygon([1, 1, 1]),
        Fragment::NextFrame,
        Fragment::End,
    ];
    for form in [Form::Text, Form::Binary] {
        let bytes = encode(header, &records, form);
        assert_eq!(
            decode::<Fragment>(&bytes).unwrap(),
            (header, records.clone())
        );
    }
    let text = String::from_utf8(encode(header, &records, Form::Text)).unwrap();
    assert_eq!(
        text,
        "polypipe 2 fragments 8 4\ncolour 9 8 7\nspan 3 1 8 -0.05 0.3333333333333333\npixel 7 0 12\nNEXT.POLYGON\ncolour 1 1 1\nNEXT.FRAME\nEND\n"
    );
}

#[test]
fn pixels_before_a_colour_are_refused_in_both_forms() {
    let header = Header::new(Space::Fragments {
        width: 4,
        height: 4,
    });
    let records = [Fragment::Pixel { x: 1, y: 1, z: 0.0 }, Fragment::End];
    let bin = encode(header, &records, Form::Binary);
    // The pixel record is 24 bytes, END 8.
    let offset = bin.len() - 8 - 24;
    assert_eq!(
        decode_err::<Fragment>(&bin),
        format!("byte {offset} (frame 0): pixels before the frame's first colour record")
    );
    let text = "polypipe 2 fragments 4 4\npixel 1 1 0\nEND\n";
    assert_eq!(
        decode_err::<Fragment>(text.as_bytes()),
        "line 2, column 1: pixels before the frame's first `colour`"
    );
}

#[test]
fn text_errors_say_line_and_column() {
    let cases: &[(&str, &str)] = &[
        ("", "empty input: expected a polypipe stream header"),
        ("hello 1 world\nEND\n", "line 1, column 1: not a polypipe stream: expected the header `polypipe 1 SPACE`, found `hello`"),
        ("polypipe 2 world\nEND\n", "line 1, column 10: stream version 2 is not supported (this is version 1 for world streams)"),
        ("polypipe 1 mars\nEND\n", "line 1, column 12: unknown coordinate space `mars` (expected world, eye, screen or fragments)"),
        ("polypipe 1 world\ncolour 256 0 0\nEND\n", "line 2, column 8: the red component of the colour is 256, out of range 0..=255"),
        ("polypipe 1 world\ncolour 1 2 3\n1 2\nEND\n", "line 4, column 1: expected z of vertex 0 (3 numbers a vertex in world space), found `END`"),
        ("polypipe 1 world\ncolour 1 2 3\n1 2 nan\nEND\n", "line 3, column 5: z of vertex 0 (3 numbers a vertex in world space) is `nan`; coordinates must be finite"),
        ("polypipe 1 world\ncolour 1 2 3\n1 2 3\n", "line 3, column 6: the stream ends without END (cut short?)"),
        ("polypipe 1 world\nEND\ncolour 1 2 3\n", "line 3, column 1: data after END: `colour`"),
        ("polypipe 1 world\ncolour 1 2 3\ncolour 1 2 3\nEND\n", "line 3, column 1: expected NEXT.POLYGON between polygons, found `colour`"),
        ("polypipe 1 world\nNEXT.POLYGON\nEND\n", "line 2, column 1: NEXT.POLYGON before the frame's first polygon (expected `colour`)"),
        ("polypipe 1 screen 0 10\nEND\n", "line 1, column 12: screen size 0x10 must be between 1x1 and 65536x65536"),
        ("polypipe 1 eye hither 5 yon 2\nEND\n", "line 1, column 12: hither 5 and yon 2 must satisfy 0 < hither < yon"),
    ];
    for (input, want) in cases {
        assert_eq!(
            &decode_err::<Token>(input.as_bytes()),
            want,
            "input: {input:?}"
        );
    }
}

#[test]
fn binary_errors_say_byte_offset_frame_and_polygon() {
    let header = Header::new(Space::World);
    let tokens = vec![
        Token::Polygon(Polygon::from_xyz([1, 2, 3], &[[1., 2., 3.], [4., 5., 6.]])),
        Token::End,
    ];
    let good = encode(header, &tokens, Form::Binary);
    // Every proper prefix is refused, never accepted and never a panic.
    for cut in 0..good.len() {
        let e = decode::<Token>(&good[..cut]);
        assert!(e.is_err(), "prefix of {cut} bytes accepted");
    }
    // The records: the polygon's 8-byte head and two 32-byte vertices, END's 8 bytes.
    let end_at = good.len() - 8;
    let polygon_at = end_at - 8 - 64;
    assert_eq!(
        decode_err::<Token>(&good[..end_at]),
        format!(
            "byte {end_at} (frame 0, after polygon 0): the stream ends without END (cut short?)"
        )
    );
    assert_eq!(
        decode_err::<Token>(&good[..end_at - 3]),
        format!(
            "byte {polygon_at} (frame 0, polygon 0): the stream ends in the middle of a record \
             (cut short?)"
        )
    );
    assert_eq!(
        decode_err::<Token>(&good[..polygon_at + 5]),
        format!(
            "byte {polygon_at} (frame 0, before its first polygon): the stream ends in the \
             middle of a record (cut short?)"
        )
    );
    let mut trailing = good.clone();
    trailing.push(0);
    assert_eq!(
        decode_err::<Token>(&trailing),
        format!("byte {}: data after END", good.len())
    );
    let mut bad_magic = good.clone();
    bad_magic[3] ^= 1;
    assert_eq!(
        decode_err::<Token>(&bad_magic),
        "byte 0: not a polypipe stream (bad magic)"
    );
    let mut nan = good.clone();
    // The first vertex's x is the first f64 after the polygon's head.
    let x_at = polygon_at + 8;
    nan[x_at..x_at + 8].copy_from_slice(&f64::NAN.to_le_bytes());
    assert!(decode_err::<Token>(&nan).contains(
        "(frame 0, polygon 0): vertex 0 is [NaN, 2.0, 3.0, 1.0]; coordinates must be finite"
    ));
    // A count claiming a million vertices reads what is there and no more (the vertex
    // list grows as the bytes arrive).
    let mut huge = good.clone();
    let n_at = polygon_at + 4;
    huge[n_at..n_at + 4].copy_from_slice(&1_000_000u32.to_le_bytes());
    assert_eq!(
        decode_err::<Token>(&huge),
        format!(
            "byte {polygon_at} (frame 0, polygon 0): the stream ends in the middle of a record \
             (cut short?)"
        )
    );
    // A count past the record limit is refused at the head, before anything is read.
    let too_many = proto::codec::MAX_VERTICES as u32 + 1;
    huge[n_at..n_at + 4].copy_from_slice(&too_many.to_le_bytes());
    let msg = decode_err::<Token>(&huge);
    assert_eq!(
        msg,
        format!(
            "byte {polygon_at} (frame 0, polygon 0): record larger than 67108864 bytes \
             (at most 2097151 vertices a polygon)"
        )
    );
    // An unknown tag, and a reserved byte set in END.
    let mut tagged = good.clone();
    tagged[polygon_at] = 9;
    assert_eq!(
        decode_err::<Token>(&tagged),
        format!(
            "byte {polygon_at} (frame 0, before its first polygon): not a valid record \
             (unknown polygon-stream tag 9); is the stream corrupt?"
        )
    );
    let mut reserved = good.clone();
    reserved[end_at + 5] = 1;
    assert_eq!(
        decode_err::<Token>(&reserved),
        format!(
            "byte {end_at} (frame 0): not a valid END record (unused bytes \
             [00, 00, 00, 00, 01, 00, 00] are not zero); is the stream corrupt?"
        )
    );
}

/// Binary version 1 (bincode records) is refused by its header, which names both.
#[test]
fn binary_version_1_is_refused() {
    let mut v1 = proto::header::BINARY_MAGIC.to_vec();
    v1.extend_from_slice(&[1, 0, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0]);
    assert_eq!(
        decode_err::<Token>(&v1),
        "byte 8: stream version 1 is not supported (this is version 5)"
    );
    // The text form is still version 1, and says so.
    let text = encode(Header::new(Space::World), &[Token::End], Form::Text);
    assert_eq!(text, b"polypipe 1 world\nEND\n");
    assert_eq!(Header::new(Space::World).version, 5);
}

#[test]
fn polygons_in_a_fragments_stream_are_refused_at_once() {
    // Found by the decode_text fuzz target: polygons in a fragments stream have vertices
    // of no numbers, and reading them took nothing from the input (2 million empty
    // vertices before the size limit stopped it).
    let text = "polypipe 2 fragments 8 8\ncolour 1 2 3\n22\nEND\n";
    assert_eq!(
        decode_err::<Token>(text.as_bytes()),
        "line 2, column 12: a polygon in a fragments-space stream, which holds no vertices"
    );
}

#[test]
fn wrong_space_messages_name_the_missing_stage() {
    let world = Header::new(Space::World);
    assert_eq!(
        world.expect(proto::SpaceKind::Screen).unwrap_err().to_string(),
        "input is world-space, expected screen-space; put viewxf, the clipper chain and persp first"
    );
    assert_eq!(
        world.expect(proto::SpaceKind::Eye).unwrap_err().to_string(),
        "input is world-space, expected eye-space; put viewxf first"
    );
}

fn arb_vertex() -> impl Strategy<Value = proto::Vertex> {
    (any::<f64>(), any::<f64>(), any::<f64>(), any::<f64>())
        .prop_filter("finite", |(a, b, c, d)| {
            a.is_finite() && b.is_finite() && c.is_finite() && d.is_finite()
        })
        .prop_map(|(a, b, c, d)| proto::Vertex::new(a, b, c, d))
}

/// A polygon, sometimes with a plane and edge supports (an empty list, or one entry per
/// edge with at least one support: the text form writes no `on` for an all-None list).
fn arb_polygon() -> impl Strategy<Value = Polygon> {
    (
        any::<[u8; 3]>(),
        prop::collection::vec(
            (
                arb_vertex(),
                prop::option::weighted(0.3, (arb_vertex(), arb_vertex())),
            ),
            0..6,
        ),
        prop::option::weighted(0.3, arb_vertex()),
    )
        .prop_map(|(c, vs, plane)| {
            let mut p = Polygon::new(c, vs.iter().map(|v| v.0).collect());
            p.plane = plane;
            if vs.iter().any(|v| v.1.is_some()) {
                p.supports = vs.iter().map(|v| v.1.map(|(a, b)| [a, b])).collect();
            }
            p
        })
}

fn arb_tokens() -> impl Strategy<Value = Vec<Token>> {
    let polygon = arb_polygon().prop_map(Token::Polygon);
    let token = prop_oneof![8 => polygon, 1 => Just(Token::NextFrame)];
    prop::collection::vec(token, 0..20).prop_map(|mut v| {
        v.push(Token::End);
        v
    })
}

proptest! {
    /// Text ↔ binary round trip: the same records come back from either form, and text
    /// printed from either is identical (floats print as their shortest exact form).
    #[test]
    fn text_and_binary_round_trip(tokens in arb_tokens()) {
        let header = Header::new(Space::Eye(View::default()));
        let bin = encode(header, &tokens, Form::Binary);
        let text = encode(header, &tokens, Form::Text);
        let (_, from_bin) = decode::<Token>(&bin).unwrap();
        let (_, from_text) = decode::<Token>(&text).unwrap();
        prop_assert_eq!(&from_bin, &tokens);
        prop_assert_eq!(&from_text, &tokens);
        prop_assert_eq!(encode(header, &from_text, Form::Binary), bin);
    }

    /// The same in screen space, where a vertex and a support end are three numbers.
    #[test]
    fn screen_space_annotations_round_trip(polygons in prop::collection::vec(arb_polygon(), 0..5)) {
        let tokens: Vec<Token> = polygons
            .into_iter()
            .map(|mut p| {
                let three = |v: proto::Vertex| proto::Vertex::new(v.x, v.y, v.z, 1.0);
                p.vertices.iter_mut().for_each(|v| *v = three(*v));
                for [a, b] in p.supports.iter_mut().flatten() {
                    (*a, *b) = (three(*a), three(*b));
                }
                Token::Polygon(p)
            })
            .chain([Token::End])
            .collect();
        let header = Header::new(Space::Screen { width: 7, height: 5 });
        let bin = encode(header, &tokens, Form::Binary);
        let text = encode(header, &tokens, Form::Text);
        prop_assert_eq!(&decode::<Token>(&bin).unwrap().1, &tokens);
        prop_assert_eq!(&decode::<Token>(&text).unwrap().1, &tokens);
    }

    /// The lexer's whole-line reading of vertex lines and of the `NEXT.POLYGON` and
    /// `colour R G B` between polygons (straight from its input buffer) reads what its
    /// word-by-word path reads, and fails with the same message at the same place, on
    /// valid streams and on streams with a byte changed: the same stream read through
    /// one-byte reads, where the buffer never holds a line ahead, goes word by word.
    #[test]
    fn lines_taken_whole_read_as_words_do(
        tokens in arb_tokens(),
        world in any::<bool>(),
        edits in prop::collection::vec((any::<prop::sample::Index>(), prop::sample::select(
            &[b'x', b'#', b'\r', b' ', b'\t', b'\n', b'-', b'+', b'.', b'e', b'0', b'9', 0xc3][..])), 0..3),
    ) {
        let header = if world { Header::new(Space::World) } else { Header::new(Space::Eye(View::default())) };
        let tokens: Vec<Token> = if world {
            // No annotations in world space: the plane and the supports are eye-space's.
            tokens.into_iter().map(|t| match t {
                Token::Polygon(mut p) => {
                    p.plane = None;
                    p.supports.clear();
                    p.vertices.iter_mut().for_each(|v| v.w = 1.0);
                    Token::Polygon(p)
                }
                t => t,
            }).collect()
        } else {
            tokens
        };
        let mut text = encode(header, &tokens, Form::Text);
        for (at, byte) in edits {
            let i = at.index(text.len());
            text[i] = byte;
        }
        let whole = read_all(Box::new(&text[..]));
        let words = read_all(Box::new(OneByte(&text)));
        prop_assert_eq!(whole, words);
    }

    /// Random bytes are refused or read, never a panic.
    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..200)) {
        let _ = decode::<Token>(&bytes);
        let mut framed = proto::header::BINARY_MAGIC.to_vec();
        framed.extend_from_slice(&bytes);
        let _ = decode::<Token>(&framed);
        let _ = decode::<Fragment>(&framed);
    }
}

/// The annotations' text form, and a plain polygon's binary record is the version-1 one:
/// streams written before annotations existed still read, and are still written the same.
/// Every record and message is the same whether the reader sees the stream whole (its
/// lines taken straight from the buffer: vertex lines, `NEXT.POLYGON` with the next
/// `colour` line) or a byte at a time (every line read word by word): streams where the
/// lines between polygons are written in all the ways the shortcut must refuse.
#[test]
fn the_lines_between_polygons_read_alike_whole_and_word_by_word() {
    for (header, quad) in [
        ("polypipe 1 world", "0 0 -5\n1 0 -5\n1 1 -5\n0 1 -5\n"),
        ("polypipe 1 eye", "0 0 -5 5\n1 0 -5 5\n1 1 -5 5\n0 1 -5 5\n"),
    ] {
        lines_between_read_alike(header, quad);
    }
}

fn lines_between_read_alike(header: &str, quad: &str) {
    for between in [
        "NEXT.POLYGON\ncolour 1 2 3\n",
        "  NEXT.POLYGON\t \ncolour 1 2 3\n",
        "NEXT.POLYGON # a comment\ncolour 1 2 3\n",
        "NEXT.POLYGON\r\ncolour 1 2 3\n",
        "NEXT.POLYGONX\ncolour 1 2 3\n",
        "NEXT.POLYGON\n\ncolour 1 2 3\n",
        "NEXT.POLYGON\ncolour 1 2 3 # c\n",
        "NEXT.POLYGON\ncolour 1 2 300\n",
        "NEXT.POLYGON\nplane 0 0 1 5\n",
        "NEXT.POLYGON\nNEXT.POLYGON\ncolour 1 2 3\n",
        "NEXT.POLYGON\n",
        "colour 1 2 3\n",
        "on 0 0 -5 5 1 0 -5 5\nNEXT.POLYGON\ncolour 1 2 3\n",
        "# between\nNEXT.POLYGON\ncolour 1 2 3\n",
        "NEXT.FRAME\ncolour 1 2 3\n",
    ] {
        for end in ["END\n", "END", "NEXT.POLYGON\n", ""] {
            let text = format!("{header}\ncolour 9 9 9\n{quad}{between}{quad}{end}");
            let whole = read_all(Box::new(text.as_bytes()));
            let words = read_all(Box::new(OneByte(text.as_bytes())));
            assert_eq!(whole, words, "{text:?}");
        }
    }
    // The plain case reads both polygons.
    let text = format!("{header}\ncolour 9 9 9\n{quad}NEXT.POLYGON\ncolour 1 2 3\n{quad}END\n");
    let (tokens, error) = read_all(Box::new(text.as_bytes()));
    assert_eq!(error, None);
    assert_eq!(tokens.len(), 3, "{tokens:?}");
    assert!(
        matches!(&tokens[1], Token::Polygon(p) if p.colour == [1, 2, 3] && p.vertices.len() == 4),
        "{tokens:?}"
    );
}

#[test]
fn annotations_text_form_and_binary_compatibility() {
    let text = "polypipe 1 eye aspect 1 hither 1 yon 30
colour 1 2 3
plane 0 0 1 -16
0 -2 16 10 on 2 -2 16 10 -2 -2 16 10
-2 -2 16 10
-2 2 16 10
END
";
    let (header, tokens) = decode::<Token>(text.as_bytes()).unwrap();
    let v = |x, y| proto::Vertex::new(x, y, 16.0, 10.0);
    let mut expected = Polygon::new([1, 2, 3], vec![v(0.0, -2.0), v(-2.0, -2.0), v(-2.0, 2.0)]);
    expected.plane = Some(proto::DVec4::new(0.0, 0.0, 1.0, -16.0));
    expected.supports = vec![Some([v(2.0, -2.0), v(-2.0, -2.0)]), None, None];
    assert_eq!(tokens, vec![Token::Polygon(expected.clone()), Token::End]);
    assert_eq!(
        String::from_utf8(encode(header, &tokens, Form::Text)).unwrap(),
        text
    );

    // A plain polygon: the head (tag 0, colour, vertex count), then its vertices.
    let plain = Polygon::new([1, 2, 3], vec![v(0.0, -2.0)]);
    let bin = encode(
        header,
        &[Token::Polygon(plain.clone()), Token::End],
        Form::Binary,
    );
    let mut record = vec![0u8, 1, 2, 3, 1, 0, 0, 0];
    for x in [0.0f64, -2.0, 16.0, 10.0] {
        record.extend_from_slice(&x.to_le_bytes());
    }
    let end = [2u8, 0, 0, 0, 0, 0, 0, 0];
    assert!(bin.ends_with(&[record.as_slice(), &end].concat()));
    // An annotated one is record kind 3: head, flags (plane and supports), the plane,
    // the vertices, then the supports' presence bytes and the one support's two ends.
    let bin = encode(
        header,
        &[Token::Polygon(expected), Token::End],
        Form::Binary,
    );
    let header_len = encode(header, &[Token::End], Form::Binary).len() - end.len();
    let record = &bin[header_len..bin.len() - end.len()];
    assert_eq!(
        &record[..16],
        &[3u8, 1, 2, 3, 3, 0, 0, 0, 3, 0, 0, 0, 0, 0, 0, 0]
    );
    assert_eq!(record.len(), 16 + 32 + 3 * 32 + 8 + 64);
    assert_eq!(
        &record[16 + 32 + 96..16 + 32 + 96 + 8],
        &[1u8, 0, 0, 0, 0, 0, 0, 0]
    );
}

#[test]
fn annotation_errors_are_located() {
    // (These were world-space streams until annotations there were refused.)
    assert_eq!(
        decode_err::<Token>(b"polypipe 1 screen 8 8\ncolour 1 2 3\nplane 1 2 x 4\nEND\n"),
        "line 3, column 11: expected c of the polygon's plane (plane a b c d), found `x`"
    );
    assert_eq!(
        decode_err::<Token>(b"polypipe 1 screen 8 8\ncolour 1 2 3\n1 2 3 on 1 2 3 4 5\nEND\n"),
        "line 4, column 1: expected coordinate 2 of support end B of edge 0 (3 numbers a point), found `END`"
    );
    // Binary: a support's presence byte that is neither 0 nor 1.
    let mut p = Polygon::from_xyz([1, 1, 1], &[[0.0, 0.0, 0.0]]);
    p.supports = vec![Some([proto::Vertex::ZERO; 2])];
    let screen = Header::new(Space::Screen {
        width: 8,
        height: 8,
    });
    let mut bin = encode(screen, &[Token::Polygon(p), Token::End], Form::Binary);
    let present_at = bin.len() - 8 - 64 - 8;
    bin[present_at] = 2;
    assert!(decode_err::<Token>(&bin).ends_with(
        "(frame 0, polygon 0): not a valid annotated polygon (support flag 2 for edge 0); \
         is the stream corrupt?"
    ));
}

/// A `plane` or `on` in a world-space stream would pass viewxf
/// untransformed and draw a wrong picture; the reader refuses it where it stands, in
/// both forms.
#[test]
fn annotations_in_world_space_are_refused() {
    assert_eq!(
        decode_err::<Token>(b"polypipe 1 world\ncolour 1 2 3\nplane 0 0 1 -16\n0 0 0\nEND\n"),
        "line 3, column 1: a `plane` line in a world-space stream: annotations (`plane`, `shade`, `on`) \
         are defined for eye and screen space only"
    );
    assert_eq!(
        decode_err::<Token>(b"polypipe 1 world\ncolour 1 2 3\n0 0 0\n1 0 0 on 1 0 0 0 1 0\nEND\n"),
        "line 4, column 7: an edge support (`on`) in a world-space stream: annotations \
         (`plane`, `shade`, `on`) are defined for eye and screen space only"
    );
    let mut p = Polygon::from_xyz([1, 1, 1], &[[0.0, 0.0, 0.0]]);
    p.plane = Some(proto::DVec4::new(0.0, 0.0, 1.0, 0.0));
    let bin = encode(
        Header::new(Space::World),
        &[Token::Polygon(p), Token::End],
        Form::Binary,
    );
    assert_eq!(
        decode_err::<Token>(&bin),
        "byte 21 (frame 0, polygon 0): an annotated polygon in a world-space stream: \
         annotations (`plane`, `shade`, `on`) are defined for eye and screen space only"
    );
}

/// The lean stream's `skip N` and a leaf's finished `run`s: the same records in both
/// forms, the polygon count kept (a later error names the right polygon), and `skip 0`
/// refused.
#[test]
fn skips_and_runs_round_trip_and_keep_numbering() {
    let tokens = vec![
        Token::Skip(3),
        Token::Polygon(Polygon::from_xyz(
            [1, 2, 3],
            &[[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]],
        )),
        Token::Skip(1),
        Token::NextFrame,
        Token::Skip(7),
        Token::End,
    ];
    let text = encode(Header::new(Space::World), &tokens, Form::Text);
    assert_eq!(
        String::from_utf8(text.clone()).unwrap(),
        "polypipe 1 world\nskip 3\nNEXT.POLYGON\ncolour 1 2 3\n0 0 0\n1 0 0\n0 1 0\n\
         NEXT.POLYGON\nskip 1\nNEXT.FRAME\nskip 7\nEND\n"
    );
    for form in [Form::Text, Form::Binary] {
        let bytes = encode(Header::new(Space::World), &tokens, form);
        assert_eq!(decode::<Token>(&bytes).unwrap().1, tokens);
    }
    let frags = vec![
        Fragment::Skip(2),
        Fragment::Polygon([9, 9, 9]),
        Fragment::Span {
            y: 1,
            x0: 0,
            x1: 3,
            z: 5.0,
            dz: 0.0,
        },
        Fragment::Run {
            y: 2,
            x0: 1,
            x1: 4,
            colour: [255, 0, 7],
        },
        Fragment::NextFrame,
        Fragment::Run {
            y: 0,
            x0: 0,
            x1: 8,
            colour: [1, 1, 1],
        },
        Fragment::End,
    ];
    let header = Header::new(Space::Fragments {
        width: 8,
        height: 4,
    });
    let text = String::from_utf8(encode(header, &frags, Form::Text)).unwrap();
    assert!(
        text.contains("skip 2\nNEXT.POLYGON\ncolour 9 9 9\nspan 1 0 3 5 0\nrun 2 1 4 255 0 7\n"),
        "{text}"
    );
    for form in [Form::Text, Form::Binary] {
        let bytes = encode(header, &frags, form);
        assert_eq!(decode::<Fragment>(&bytes).unwrap().1, frags);
    }
    // Numbering: after `skip 4` the polygon that follows is polygon 4 of the frame.
    let bad = "polypipe 1 world\nskip 4\nNEXT.POLYGON\ncolour 1 2 3\n1e999 0 0\nEND\n";
    let msg = decode_err::<Token>(bad.as_bytes());
    assert!(msg.starts_with("line 5, column 1"), "{msg}");
    assert_eq!(
        decode_err::<Token>(b"polypipe 1 world\nskip 0\nEND\n"),
        "line 2, column 6: `skip 0`: a skip stands for at least one polygon"
    );
    assert_eq!(
        decode_err::<Fragment>(b"polypipe 2 fragments 4 4\nrun 4 0 1 1 1 1\nEND\n"),
        "line 2, column 15: run of row 4, columns 0..1, is outside the 4x4 screen"
    );
}

/// `runs_into`, the merger's batch decoder of a leaf's runs, reads what `next_record`
/// reads: the runs next in the buffer, at most as many as asked, and stops before any
/// other record and before a run off the screen, which `next_record` then refuses with
/// its place in the stream.
#[test]
fn runs_decoded_in_a_batch_are_the_records_and_a_bad_one_is_left_to_refuse() {
    let run = |y, x0, x1, c| Fragment::Run {
        y,
        x0,
        x1,
        colour: [c, 2, 3],
    };
    let header = Header::new(Space::Fragments {
        width: 8,
        height: 4,
    });
    let frags = vec![
        run(0, 0, 8, 1),
        run(1, 2, 5, 7),
        run(3, 0, 0, 9),
        Fragment::NextFrame,
        run(2, 1, 2, 4),
        Fragment::End,
    ];
    let bytes = encode(header, &frags, Form::Binary);
    let mut reader = Reader::<Fragment, _>::new(&bytes[..]).unwrap();
    let mut got = Vec::new();
    reader.runs_into(&mut got, 2);
    assert_eq!(got, frags[..2]);
    reader.runs_into(&mut got, 10);
    assert_eq!(got, frags[..3], "stops before NEXT.FRAME");
    reader.runs_into(&mut got, 10);
    assert_eq!(got.len(), 3);
    assert_eq!(reader.next_record().unwrap(), Some(Fragment::NextFrame));
    reader.runs_into(&mut got, 10);
    assert_eq!(got, [&frags[..3], &frags[4..5]].concat());
    assert_eq!(reader.next_record().unwrap(), Some(Fragment::End));
    assert_eq!(reader.next_record().unwrap(), None);

    // A run below the screen: left in the stream, and refused where it is.
    let mut bad = encode(header, &frags, Form::Binary);
    // The second run's record: END (8 bytes), a run (16), NEXT.FRAME (8) and two runs
    // from the end.
    let second = bad.len() - 8 - 16 - 8 - 16 - 16;
    bad[second + 4] = 9; // its row
    let mut reader = Reader::<Fragment, _>::new(&bad[..]).unwrap();
    let mut got = Vec::new();
    reader.runs_into(&mut got, 10);
    assert_eq!(got, frags[..1]);
    let e = reader.next_record().unwrap_err().to_string();
    assert!(
        e.contains("run of row 9, columns 2..5, is outside the 8x4 screen"),
        "{e}"
    );
}

/// A Gouraud-shaded polygon's record: vertex colours, colour planes and opacity come back
/// from the binary form bit for bit, and a flat polygon's record is unchanged by them.
#[test]
fn vertex_colours_shade_and_opacity_round_trip_in_binary() {
    use proto::{Attributes, DVec3, DVec4};
    let plain = Header::new(Space::Eye(View::default()));
    let header = plain.with(Attributes {
        vertex_colours: true,
        opacity: true,
        ..Attributes::default()
    });
    let mut p = Polygon::new(
        [1, 2, 3],
        vec![
            DVec4::new(-8.0, -4.0, 20.0, 12.5),
            DVec4::new(0.0, 7.0, 20.0, 12.5),
            DVec4::new(8.0, -4.0, 20.0, 12.5),
        ],
    );
    // A flat polygon is a head and its vertices (the record of stream version 3).
    let flat = encode(plain, &[Token::Polygon(p.clone())], Form::Binary);
    let start = encode::<Token>(plain, &[], Form::Binary).len();
    assert_eq!(flat.len() - start, 8 + 96);
    assert_eq!(&flat[start..start + 8], &[0, 1, 2, 3, 3, 0, 0, 0]);
    p.vertex_attrs = vec![
        DVec3::new(255.0, 0.0, 0.0),
        DVec3::new(0.1, 254.9, 1.0 / 3.0),
        DVec3::new(0.0, 0.0, 255.0),
    ];
    p.shade = Some(Box::new([
        DVec4::new(1.0, 2.0, 3.0, 4.0),
        DVec4::new(-1.0, 0.5, 1.0, -7.25),
        DVec4::new(0.0, 0.0, 1.0, -255.0),
    ]));
    p.opacity = 128;
    let tokens = vec![Token::Polygon(p.clone()), Token::End];
    let bin = encode(header, &tokens, Form::Binary);
    assert_eq!(decode::<Token>(&bin).unwrap().1, tokens);
    // The head, flags (4 shade | 8 colours, transparency 127 in byte 4), 96 bytes of
    // planes, 96 of vertices, 72 of colours, and END.
    let start = encode::<Token>(header, &[], Form::Binary).len();
    assert_eq!(bin.len() - start, 8 + 8 + 96 + 96 + 72 + 8);
    assert_eq!(
        &bin[start..start + 16],
        &[3, 1, 2, 3, 3, 0, 0, 0, 12, 0, 0, 0, 127, 0, 0, 0]
    );
    // The text form: the opacity after the colour, the colour planes' line, each vertex's
    // colour after its coordinates; and it reads back.
    let text = encode(header, &tokens, Form::Text);
    assert_eq!(
        String::from_utf8(text.clone()).unwrap(),
        "polypipe 1 eye aspect 1 hither 1 yon 30 vertex-colours opacity\n\
         colour 1 2 3 128\n\
         shade 1 2 3 4  -1 0.5 1 -7.25  0 0 1 -255\n\
         -8 -4 20 12.5 255 0 0\n\
         0 7 20 12.5 0.1 254.9 0.3333333333333333\n\
         8 -4 20 12.5 0 0 255\n\
         END\n"
    );
    assert_eq!(decode::<Token>(&text).unwrap(), (header, tokens.clone()));
    // A stream that does not declare them refuses them, and one that does refuses a
    // polygon without them.
    let undeclared = encode(plain, &tokens, Form::Binary);
    assert!(decode_err::<Token>(&undeclared)
        .contains("declares neither (`vertex-colours`, `vertex-normals`)"));
    let bare = encode(
        header,
        &[
            Token::Polygon(Polygon::new([1, 2, 3], vec![DVec4::W; 3])),
            Token::End,
        ],
        Form::Binary,
    );
    assert!(decode_err::<Token>(&bare).contains("0 vertex colours for 3 vertices"));
}

#[test]
fn vertex_colour_text_is_checked_where_it_stands() {
    let header = "polypipe 1 world vertex-colours\ncolour 1 2 3\n0 0 0 1 2 3\n1 0 0 4 5\n";
    assert_eq!(
        decode_err::<Token>(format!("{header}END\n").as_bytes()),
        "line 5, column 1: expected the blue of vertex 1's colour (the header says \
         `vertex-colours`: r g b after the coordinates), found `END`"
    );
    let over = "polypipe 1 world vertex-colours\ncolour 1 2 3\n0 0 0 1 2 256\nEND\n";
    assert!(decode_err::<Token>(over.as_bytes()).contains(
        "vertex 0's colour 1 2 256: a vertex colour's channels are numbers from 0 to 255"
    ));
    let twice = "polypipe 1 world vertex-colours opacity vertex-colours\nEND\n";
    assert!(
        decode_err::<Token>(twice.as_bytes()).contains("the header says `vertex-colours` twice")
    );
    let fragments = "polypipe 2 fragments 4 4 opacity\nEND\n";
    assert!(decode_err::<Fragment>(fragments.as_bytes()).contains(
        "`opacity` in the header is for polygon streams (world, eye, screen), not fragments-space"
    ));
    let alpha = "polypipe 1 world opacity\ncolour 1 2 3\nEND\n";
    assert!(decode_err::<Token>(alpha.as_bytes()).contains("expected the opacity of the colour"));
}

#[test]
fn colour_plane_text_reads_back_and_is_refused_in_world_space() {
    let eye = "polypipe 1 eye\ncolour 1 2 3\nshade 1 2 3 4 5 6 7 8 9 10 11 12\n0 0 1 1\n1 0 1 1\n0 1 1 1\nEND\n";
    let (_, tokens) = decode::<Token>(eye.as_bytes()).unwrap();
    let Token::Polygon(p) = &tokens[0] else {
        panic!("{tokens:?}")
    };
    assert_eq!(
        p.shade.as_ref().unwrap()[2],
        proto::DVec4::new(9.0, 10.0, 11.0, 12.0)
    );
    let world = "polypipe 1 world\ncolour 1 2 3\nshade 1 2 3 4 5 6 7 8 9 10 11 12\nEND\n";
    assert_eq!(
        decode_err::<Token>(world.as_bytes()),
        "line 3, column 1: a `shade` line in a world-space stream: annotations (`plane`, \
         `shade`, `on`) are defined for eye and screen space only"
    );
    let short = "polypipe 1 eye\ncolour 1 2 3\nshade 1 2 3 4 5\nEND\n";
    assert!(decode_err::<Token>(short.as_bytes())
        .contains("b of the green colour plane (shade, four numbers a channel)"));
}

#[test]
fn shade_fragments_round_trip_and_are_checked() {
    // A shade record is no larger in memory than a span: zbuf's batches do not grow.
    assert_eq!(std::mem::size_of::<Fragment>(), 32);
    let header = Header::new(Space::Fragments {
        width: 8,
        height: 4,
    });
    let records = vec![
        Fragment::Polygon([9, 8, 7]),
        Fragment::Shade {
            channel: 0,
            plane: [0.25, -1.5, -100.0],
        },
        Fragment::Shade {
            channel: 2,
            plane: [0.0, 0.0, 3.0],
        },
        Fragment::Span {
            y: 3,
            x0: 1,
            x1: 8,
            z: -0.05,
            dz: 0.0,
        },
        Fragment::End,
    ];
    for form in [Form::Text, Form::Binary] {
        let bytes = encode(header, &records, form);
        assert_eq!(
            decode::<Fragment>(&bytes).unwrap(),
            (header, records.clone())
        );
    }
    let text = String::from_utf8(encode(header, &records, Form::Text)).unwrap();
    assert!(
        text.contains("\nshade 0 0.25 -1.5 -100\nshade 2 0 0 3\n"),
        "{text}"
    );
    let bad = "polypipe 2 fragments 8 4\ncolour 1 1 1\nshade 3 1 2 4\nEND\n";
    assert!(decode_err::<Fragment>(bad.as_bytes()).contains("the shade's channel (0, 1 or 2)"));
    let early = "polypipe 2 fragments 8 4\nshade 1 1 2 4\nEND\n";
    assert!(decode_err::<Fragment>(early.as_bytes())
        .contains("pixels before the frame's first `colour`"));
}

/// The depth form persp names in the header: written after the space's words, read back
/// from either form, and refused where it means nothing or its numbers cannot be.
#[test]
fn the_depth_form_in_the_header_round_trips_and_is_checked() {
    let screen = Space::Screen {
        width: 8,
        height: 4,
    };
    for (form, words) in [
        (DepthForm::Reciprocal { hither: 1.0 }, "depth reciprocal 1"),
        (
            DepthForm::Projective {
                hither: 0.001,
                yon: 1000.0,
            },
            "depth projective 0.001 1000",
        ),
        (DepthForm::EyeZ, "depth eye-z"),
    ] {
        let header = Header::new(screen).with(Attributes {
            depth: Some(form),
            ..Attributes::default()
        });
        let text = encode(header, &[Token::End], Form::Text);
        assert_eq!(
            String::from_utf8(text.clone()).unwrap(),
            format!("polypipe 1 screen 8 4 {words}\nEND\n")
        );
        for bytes in [text, encode(header, &[Token::End], Form::Binary)] {
            let (back, records) = decode::<Token>(&bytes).unwrap();
            assert_eq!((back, records), (header, vec![Token::End]));
        }
        let fragments = Header::new(Space::Fragments {
            width: 8,
            height: 4,
        })
        .with(Attributes {
            depth: Some(form),
            ..Attributes::default()
        });
        let text = encode(fragments, &[Fragment::End], Form::Text);
        assert!(String::from_utf8_lossy(&text)
            .starts_with(&format!("polypipe 2 fragments 8 4 {words}\n")));
        assert_eq!(decode::<Fragment>(&text).unwrap().0, fragments);
    }
    // Without the words: no form, as every hand-written screen stream.
    let (plain, _) = decode::<Token>(b"polypipe 1 screen 8 4\nEND\n").unwrap();
    assert_eq!(plain.attributes.depth, None);
    for (text, message) in [
        (
            "polypipe 1 world depth eye-z\nEND\n",
            "line 1, column 18: `depth` in the header is for screen and fragment streams, not world-space",
        ),
        (
            "polypipe 1 screen 8 4 depth linear\nEND\n",
            "line 1, column 29: unknown depth form `linear` (expected reciprocal, projective or eye-z)",
        ),
        (
            "polypipe 1 screen 8 4 depth projective 2 1\nEND\n",
            "line 1, column 42: the depth form's hither 2 and yon 1 must satisfy hither < yon",
        ),
        (
            "polypipe 1 screen 8 4 depth reciprocal -1\nEND\n",
            "line 1, column 40: the depth form's hither -1 must be positive",
        ),
        (
            "polypipe 1 screen 8 4 depth eye-z depth eye-z\nEND\n",
            "line 1, column 35: the header names the depth form twice",
        ),
    ] {
        assert_eq!(decode_err::<Token>(text.as_bytes()), message, "{text}");
    }
    // A binary header holds what a text one could say, or is refused.
    let bad = Header::new(screen).with(Attributes {
        depth: Some(DepthForm::Projective {
            hither: 5.0,
            yon: 1.0,
        }),
        ..Attributes::default()
    });
    assert_eq!(
        decode_err::<Token>(&encode(bad, &[Token::End], Form::Binary)),
        "byte 8: the depth form's hither and yon must satisfy 0 < hither < yon"
    );
}

/// A Phong-shaded stream (`vertex-normals`): the lighting in the header and each vertex's
/// normal come back bit for bit from both forms; the text header spells every word; a
/// header without them is as small as before.
#[test]
fn vertex_normals_and_lighting_round_trip() {
    use proto::shade::Lighting;
    use proto::{Attributes, DVec3, DVec4};
    let mut lighting = Lighting::default();
    lighting.ambient = 0.25;
    lighting.specular = 0.5;
    lighting.exponent = 30.0;
    lighting
        .set_lights(&[
            (DVec3::new(1.0, 1.0, 1.0), 0.6),
            (DVec3::new(-1.0, 0.0, 0.0), 0.3),
        ])
        .unwrap();
    lighting.set_viewer(DVec3::new(0.0, 0.0, 2.0)).unwrap();
    let header = Header::new(Space::World).with(Attributes {
        vertex_normals: true,
        lighting,
        ..Attributes::default()
    });
    let mut p = Polygon::from_xyz(
        [200, 100, 50],
        &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    );
    p.vertex_attrs = vec![
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(0.6, 0.0, 0.8),
        DVec3::new(-0.1, 1e-300, 0.99),
    ];
    let tokens = vec![Token::Polygon(p), Token::End];
    for form in [Form::Binary, Form::Text] {
        let bytes = encode(header, &tokens, form);
        assert_eq!(decode::<Token>(&bytes).unwrap(), (header, tokens.clone()));
    }
    let text = String::from_utf8(encode(header, &tokens, Form::Text)).unwrap();
    let first = text.lines().next().unwrap();
    let s = 1.0 / 3f64.sqrt();
    assert_eq!(
        first,
        format!(
            "polypipe 1 world vertex-normals ambient 0.25 light {s} {s} {s} 0.6 light -1 0 0 0.3 \
             specular 0.5 30 viewer 0 0 1"
        )
    );
    assert!(text.contains("\n0 0 0 0 0 1\n1 0 0 0.6 0 0.8\n"), "{text}");
    // The binary header of a stream without them: two bytes more than version 4's (the
    // flag, and the absent lighting).
    let flat = encode::<Token>(Header::new(Space::World), &[], Form::Binary).len();
    assert_eq!(flat, 8 + 4 + 4 + 1 + 1 + 1 + 1 + 1);
    // A lighting word read alone; a light replaces the default one.
    let (h, _) =
        decode::<Token>(b"polypipe 1 world vertex-normals light 0 2 0 1 specular 1 5\nEND\n")
            .unwrap();
    let lights: Vec<_> = h.attributes.lighting.lights().collect();
    assert_eq!(lights, vec![(DVec3::Y, 1.0)]);
    assert_eq!(h.attributes.lighting.ambient, 0.3);
    let _ = DVec4::ZERO;
}

/// What a Phong-shaded header may not say, each refused at the word.
#[test]
fn lighting_words_are_checked() {
    let err = |s: &str| decode_err::<Token>(format!("{s}\nEND\n").as_bytes());
    assert_eq!(
        err("polypipe 1 world ambient 0.5"),
        "line 1, column 18: lighting words (ambient, light, specular, viewer) in a header \
         without `vertex-normals`: they light the normals of a Phong-shaded stream"
    );
    assert_eq!(
        err("polypipe 1 world vertex-normals vertex-colours"),
        "line 1, column 33: the header says both `vertex-colours` and `vertex-normals`: a \
         vertex carries a colour (Gouraud) or a normal (Phong), not both"
    );
    assert!(err("polypipe 1 world vertex-normals light 0 0 0 1")
        .ends_with("the header's lights: light 0 has no direction (0 0 0, or not finite)"));
    assert!(err("polypipe 1 world vertex-normals specular 1 0.5")
        .ends_with("the header's `specular`: the specular exponent 0.5 must be 1 or more"));
    assert!(err("polypipe 1 world vertex-normals ambient -1")
        .ends_with("the header's `ambient`: the ambient term -1 must be 0 or more"));
    let nine = " light 1 0 0 1".repeat(9);
    assert!(err(&format!("polypipe 1 world vertex-normals{nine}"))
        .ends_with("the header's `light`: more than 8 lights"));
    // A vertex of a vertex-normals stream has six numbers: a line of five runs into the
    // next, and the last vertex comes up short.
    assert!(
        err("polypipe 1 world vertex-normals\ncolour 1 2 3\n0 0 0 0 0\n1 0 0 0 0 1\n0 1 0 0 0 1")
            .contains("expected the z of vertex 2's normal (the header says `vertex-normals`: nx ny nz after the coordinates), found `END`"),
    );
}
