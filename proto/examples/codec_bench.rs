//! The codec measured in one process (`bench stages codec` runs it and prints the
//! table): stream version 1's serde + bincode records against version 2's fixed-layout
//! records, encoding and decoding four-vertex eye-space polygons; the text form's reader
//! and writer in MB/s; and float parsers on the text's numbers.
//!
//!     cargo run --release -p proto --example codec_bench -- [POLYGONS] [REPS] [TEXT_FILE]
//!
//! Each figure is the best of REPS runs. The version-1 codec is reproduced here as it
//! was (`WireOut`/`WireIn` through bincode, read through a counting `BufReader` and
//! validated), so that the comparison stays runnable after it left `proto`.

use bincode::Options;
use proto::{Form, Fragment, Header, Polygon, Reader, Record, Space, Token, View, Writer};
use serde::{Deserialize, Serialize};
use std::hint::black_box;
use std::io::{self, BufRead, BufReader, BufWriter, Read, Write};
use std::time::{Duration, Instant};

/// Version 1's binary records.
#[derive(Serialize)]
enum WireOut<'a> {
    Polygon(PlainRef<'a>),
    #[allow(dead_code)]
    NextFrame,
    End,
}

#[derive(Serialize)]
struct PlainRef<'a> {
    colour: &'a [u8; 3],
    vertices: &'a Vec<proto::Vertex>,
}

#[derive(Deserialize)]
enum WireIn {
    Polygon(Plain),
    NextFrame,
    End,
}

#[derive(Deserialize)]
struct Plain {
    colour: [u8; 3],
    vertices: Vec<proto::Vertex>,
}

fn bincode_options() -> impl Options {
    bincode::DefaultOptions::new()
        .with_fixint_encoding()
        .with_little_endian()
        .with_limit(proto::codec::MAX_RECORD_BYTES)
}

/// Version 1's reader: a `BufReader` that counts the bytes taken.
struct Counted<R> {
    inner: BufReader<R>,
    offset: u64,
}

impl<R: Read> Read for Counted<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.offset += n as u64;
        Ok(n)
    }

    fn read_exact(&mut self, buf: &mut [u8]) -> io::Result<()> {
        let available = self.inner.buffer();
        if available.len() >= buf.len() {
            buf.copy_from_slice(&available[..buf.len()]);
            self.inner.consume(buf.len());
            self.offset += buf.len() as u64;
            return Ok(());
        }
        self.inner.read_exact(buf)?;
        self.offset += buf.len() as u64;
        Ok(())
    }
}

fn bincode_encode(polygons: &[Polygon]) -> Vec<u8> {
    let mut out = BufWriter::with_capacity(1 << 16, Vec::new());
    for p in polygons {
        let record = WireOut::Polygon(PlainRef {
            colour: &p.colour,
            vertices: &p.vertices,
        });
        bincode_options().serialize_into(&mut out, &record).unwrap();
    }
    bincode_options()
        .serialize_into(&mut out, &WireOut::End)
        .unwrap();
    out.into_inner().unwrap()
}

/// Decodes as version 1's stage loop did: a new Token per record, validated.
fn bincode_decode(bytes: &[u8]) -> usize {
    let mut input = Counted {
        inner: BufReader::with_capacity(1 << 16, bytes),
        offset: 0,
    };
    let space = Space::Eye(View::default());
    let mut count = 0;
    loop {
        let wire: WireIn = bincode_options().deserialize_from(&mut input).unwrap();
        let token = match wire {
            WireIn::Polygon(Plain { colour, vertices }) => {
                Token::Polygon(Polygon::new(colour, vertices))
            }
            WireIn::NextFrame => Token::NextFrame,
            WireIn::End => Token::End,
        };
        token.validate(&Header::new(space)).unwrap();
        if token == Token::End {
            break;
        }
        count += 1;
        black_box(&token);
    }
    count
}

/// Version 1's fragment records: `Fragment` through serde and bincode (its derive).
fn bincode_fragments(records: &[Fragment]) -> Vec<u8> {
    let mut out = BufWriter::with_capacity(1 << 16, Vec::new());
    for r in records {
        bincode_options().serialize_into(&mut out, r).unwrap();
    }
    out.into_inner().unwrap()
}

fn bincode_fragments_decode(bytes: &[u8]) -> usize {
    let mut input = Counted {
        inner: BufReader::with_capacity(1 << 16, bytes),
        offset: 0,
    };
    let space = Space::Fragments {
        width: 1 << 16,
        height: 1 << 16,
    };
    let mut count = 0;
    loop {
        let f: Fragment = bincode_options().deserialize_from(&mut input).unwrap();
        f.validate(&Header::new(space)).unwrap();
        count += 1;
        if f == Fragment::End {
            return count;
        }
        black_box(&f);
    }
}

fn proto_fragments(records: &[Fragment]) -> Vec<u8> {
    let space = Space::Fragments {
        width: 1 << 16,
        height: 1 << 16,
    };
    let mut w = Writer::new(Vec::new(), Header::new(space), Form::Binary).unwrap();
    for r in records {
        w.write(r).unwrap();
    }
    w.into_inner().unwrap()
}

fn proto_fragments_decode(bytes: &[u8]) -> usize {
    let mut reader = Reader::<Fragment, _>::new(bytes).unwrap();
    let mut f = Fragment::default();
    let mut count = 0;
    while reader.next_into(&mut f).unwrap() {
        count += 1;
        black_box(&f);
    }
    count
}

/// A fragment stream: per polygon a colour record and 20 spans.
fn fragments(polygons: usize) -> Vec<Fragment> {
    let mut records = Vec::new();
    for i in 0..polygons {
        records.push(Fragment::Polygon([i as u8, 1, 2]));
        for y in 0..20u32 {
            records.push(Fragment::Span {
                y: (i as u32 + y) % 1000,
                x0: y,
                x1: y + 37,
                z: 0.5,
                dz: -1.2345e-8,
            });
        }
    }
    records.push(Fragment::End);
    records
}

fn header() -> Header {
    Header::new(Space::Eye(View::default()))
}

fn proto_encode(polygons: &[Polygon], form: Form) -> Vec<u8> {
    let mut w = Writer::new(Vec::new(), header(), form).unwrap();
    for p in polygons {
        w.write_polygon(p).unwrap();
    }
    w.write(&Token::End).unwrap();
    w.into_inner().unwrap()
}

/// Decodes as a version-2 stage loop does: one Token, read into.
fn proto_decode(bytes: &[u8]) -> usize {
    let mut reader = Reader::<Token, _>::new(bytes).unwrap();
    let mut token = Token::default();
    let mut count = 0;
    while reader.next_into(&mut token).unwrap() {
        if let Token::Polygon(p) = &token {
            count += 1;
            black_box(p);
        }
    }
    count
}

/// Best wall time of `reps` runs of `f`.
fn best<T>(reps: usize, mut f: impl FnMut() -> T) -> Duration {
    (0..reps)
        .map(|_| {
            let t = Instant::now();
            black_box(f());
            t.elapsed()
        })
        .min()
        .unwrap()
}

/// Four-vertex eye-space polygons scattered as bench stages geometry scatters them.
fn polygons(n: usize) -> Vec<Polygon> {
    let mut state = 1985u64;
    let mut next = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|i| {
            let (cx, cy, cz) = (
                next() * 26.0 - 13.0,
                next() * 26.0 - 13.0,
                next() * 16.0 + 12.0,
            );
            let w = cz * 10.0 / 16.0;
            let v = |dx: f64, dy: f64, dz: f64| proto::Vertex::new(cx + dx, cy + dy, cz + dz, w);
            Polygon::new(
                [i as u8, (i * 7) as u8, (i * 13) as u8],
                vec![
                    v(-0.5, -0.5, 0.0),
                    v(0.5, -0.4, 0.1),
                    v(0.4, 0.5, 0.0),
                    v(-0.5, 0.4, -0.1),
                ],
            )
        })
        .collect()
}

fn row(what: &str, n: usize, bytes: usize, t: Duration) {
    let s = t.as_secs_f64();
    println!(
        "| {what} | {:.2} | {:.0} |",
        n as f64 / s / 1e6,
        bytes as f64 / s / 1e6
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map_or(200_000, |a| a.parse().unwrap());
    let reps: usize = args.get(2).map_or(5, |a| a.parse().unwrap());
    let polys = polygons(n);

    println!(
        "### Binary records, {n} four-vertex eye-space polygons, in memory (best of {reps})\n"
    );
    println!("| codec | M polygons/s | MB/s |");
    println!("|---|---|---|");
    let v1 = bincode_encode(&polys);
    let v2 = proto_encode(&polys, Form::Binary);
    assert_eq!(bincode_decode(&v1), n);
    assert_eq!(proto_decode(&v2), n);
    row(
        "version 1 (serde + bincode) encode",
        n,
        v1.len(),
        best(reps, || bincode_encode(&polys)),
    );
    row(
        "version 2 (fixed layout) encode",
        n,
        v2.len(),
        best(reps, || proto_encode(&polys, Form::Binary)),
    );
    row(
        "version 1 (serde + bincode) decode",
        n,
        v1.len(),
        best(reps, || bincode_decode(&v1)),
    );
    row(
        "version 2 (fixed layout) decode",
        n,
        v2.len(),
        best(reps, || proto_decode(&v2)),
    );

    let frags = fragments(n / 20);
    let f1 = bincode_fragments(&frags);
    let f2 = proto_fragments(&frags);
    assert_eq!(bincode_fragments_decode(&f1), frags.len());
    assert_eq!(proto_fragments_decode(&f2), frags.len());
    let m = frags.len();
    println!("\n### Fragment records, {m} (a colour and 20 spans a polygon), in memory (best of {reps})\n");
    println!("| codec | M records/s | MB/s |");
    println!("|---|---|---|");
    row(
        "version 1 (serde + bincode) encode",
        m,
        f1.len(),
        best(reps, || bincode_fragments(&frags)),
    );
    row(
        "version 2 (fixed layout) encode",
        m,
        f2.len(),
        best(reps, || proto_fragments(&frags)),
    );
    row(
        "version 1 (serde + bincode) decode",
        m,
        f1.len(),
        best(reps, || bincode_fragments_decode(&f1)),
    );
    row(
        "version 2 (fixed layout) decode",
        m,
        f2.len(),
        best(reps, || proto_fragments_decode(&f2)),
    );

    let text = match args.get(3) {
        Some(path) => std::fs::read(path).unwrap(),
        None => proto_encode(&polys, Form::Text),
    };
    let source = args
        .get(3)
        .map_or("the same polygons as text", |p| p.as_str());
    println!(
        "\n### Text form ({source}, {} bytes, best of {reps})\n",
        text.len()
    );
    println!("| codec | M polygons/s | MB/s |");
    println!("|---|---|---|");
    let count = {
        let mut reader = Reader::<Token, _>::new(text.as_slice()).unwrap();
        let mut token = Token::default();
        let mut count = 0;
        while reader.next_into(&mut token).unwrap() {
            count += matches!(token, Token::Polygon(_)) as usize;
        }
        count
    };
    let read = best(reps, || {
        let mut reader = Reader::<Token, _>::new(text.as_slice()).unwrap();
        let mut token = Token::default();
        while reader.next_into(&mut token).unwrap() {
            black_box(&token);
        }
    });
    row("text read", count, text.len(), read);
    let written = proto_encode(&polys, Form::Text);
    row(
        "text write (eye space)",
        n,
        written.len(),
        best(reps, || proto_encode(&polys, Form::Text)),
    );

    // The numbers of the text, parsed by each parser.
    let words: Vec<&str> = std::str::from_utf8(&text)
        .unwrap()
        .split_ascii_whitespace()
        .filter(|w| {
            w.len() > 3
                && w.bytes()
                    .all(|b| b.is_ascii_digit() || b"+-.eE".contains(&b))
        })
        .collect();
    for w in &words {
        let want = w.parse::<f64>().unwrap().to_bits();
        assert_eq!(
            fast_float2::parse::<f64, _>(w).unwrap().to_bits(),
            want,
            "{w}"
        );
        assert_eq!(
            lexical_core::parse::<f64>(w.as_bytes()).unwrap().to_bits(),
            want,
            "{w}"
        );
    }
    println!(
        "\n### Float parsers on the text's {} numbers (best of {reps})\n",
        words.len()
    );
    println!("| parser | ns a number |");
    println!("|---|---|");
    let per = |t: Duration| t.as_secs_f64() * 1e9 / words.len() as f64;
    let sum = |f: &dyn Fn(&str) -> f64| words.iter().map(|w| f(w)).sum::<f64>();
    let t = best(reps, || sum(&|w| w.parse::<f64>().unwrap()));
    println!("| str::parse::<f64> | {:.1} |", per(t));
    let t = best(reps, || sum(&|w| fast_float2::parse::<f64, _>(w).unwrap()));
    println!("| fast-float2 0.2 | {:.1} |", per(t));
    // proto's parser as the reader uses it: in place, the text after each word there
    // to look at (its eight-bytes-at-a-time reading needs them).
    let at = |w: &str| &text[w.as_ptr() as usize - text.as_ptr() as usize..];
    for w in &words {
        let got = proto::text::parse_decimal(at(w)).map(|(v, n)| (v.to_bits(), n));
        assert_eq!(
            got,
            Some((w.parse::<f64>().unwrap().to_bits(), w.len())),
            "{w}"
        );
    }
    let t = best(reps, || {
        sum(&|w| proto::text::parse_decimal(at(w)).unwrap().0)
    });
    println!(
        "| proto::text::parse_decimal (in the text) | {:.1} |",
        per(t)
    );
    let t = best(reps, || {
        sum(&|w| lexical_core::parse::<f64>(w.as_bytes()).unwrap())
    });
    println!("| lexical-core 1.0 | {:.1} |", per(t));
    io::stdout().flush().unwrap();
}
