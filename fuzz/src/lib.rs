//! Shared helpers of the fuzz targets: turning the fuzzer's bytes into numbers and
//! polygons. Every coordinate is a finite f64 (the stream readers refuse anything else),
//! but any finite value, 1e-300 to 1e308, may come.

use proto::{Polygon, Vertex};

/// Reads the fuzzer's bytes as a sequence of values.
pub struct Bytes<'a>(pub &'a [u8]);

impl Bytes<'_> {
    pub fn u8(&mut self) -> u8 {
        match self.0.split_first() {
            Some((&b, rest)) => {
                self.0 = rest;
                b
            }
            None => 0,
        }
    }

    /// The next 8 bytes, little-endian (zeros past the end, as [`Bytes::u8`] gives).
    pub fn u64(&mut self) -> u64 {
        u64::from_le_bytes(std::array::from_fn(|_| self.u8()))
    }

    /// A finite f64: the next 8 bytes as bits when they are finite, otherwise a small
    /// integer made from the first, so both the whole range and simple values come up.
    pub fn f64(&mut self) -> f64 {
        if self.0.len() < 8 {
            return self.u8() as f64 - 128.0;
        }
        let (b, rest) = self.0.split_at(8);
        self.0 = rest;
        let v = f64::from_le_bytes(b.try_into().unwrap());
        if v.is_finite() {
            v
        } else {
            (b[0] as i8) as f64
        }
    }

    /// A small value on a 1/8 grid in [-16, 16): coincidences (vertices on planes,
    /// horizontal edges, collinear points) come up often.
    pub fn grid(&mut self) -> f64 {
        (self.u8() as i8) as f64 / 8.0
    }

    /// A coordinate: on the grid or any finite value, as the next byte says.
    pub fn coord(&mut self) -> f64 {
        if self.u8() & 1 == 0 {
            self.grid()
        } else {
            self.f64()
        }
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

/// A polygon of up to 16 vertices whose 4 coordinates are given by `vertex`.
pub fn polygon(b: &mut Bytes, mut vertex: impl FnMut(&mut Bytes) -> Vertex) -> Polygon {
    let n = (b.u8() % 17) as usize;
    let mut vertices = Vec::with_capacity(n);
    for _ in 0..n {
        vertices.push(vertex(b));
    }
    Polygon::new([b.u8(), b.u8(), b.u8()], vertices)
}

/// Projects `poly` with `perspective` and checks the outcome: every projected vertex
/// finite, or the polygon refused with a vertex of it named and left as it was.
pub fn project_and_check(perspective: &proto::perspective::Perspective, poly: &mut Polygon) {
    let before = poly.clone();
    match perspective.project_polygon(poly) {
        Ok(()) => {
            for v in &poly.vertices {
                assert!(v.is_finite(), "{v:?} projected from {before:?}");
            }
        }
        Err(e) => {
            assert!(e.vertex < before.vertices.len().max(before.supports.len()));
            assert_eq!(*poly, before, "a refused polygon was changed");
        }
    }
}

/// An eye-space vertex (x, y, z, w) with any finite coordinates.
pub fn eye_vertex(b: &mut Bytes) -> Vertex {
    Vertex::new(b.coord(), b.coord(), b.coord(), b.coord())
}

/// Reads a stream to its end or its first error, as a stage would: no panic, and every
/// error has a message (the reader, not the fuzzer, must say what is wrong). Then what
/// was read is written back and read again, and must come back the same: in binary
/// always, and in text too when it came as text (a world- or screen-space vertex's w,
/// which the binary form carries and the text form does not, is the difference).
pub fn drain<T: proto::Record + PartialEq + std::fmt::Debug>(bytes: &[u8]) {
    let Ok(mut reader) = proto::Reader::<T, _>::new(bytes) else {
        return;
    };
    let header = *reader.header();
    let mut records = Vec::new();
    let mut record = T::default();
    loop {
        match reader.next_into(&mut record) {
            Ok(true) => records.push(std::mem::take(&mut record)),
            Ok(false) => break,
            Err(e) => {
                assert!(!e.to_string().is_empty());
                break;
            }
        }
    }
    let came_as_text = !bytes.starts_with(&proto::header::BINARY_MAGIC[..1]);
    let forms: &[proto::Form] = if came_as_text {
        &[proto::Form::Binary, proto::Form::Text]
    } else {
        &[proto::Form::Binary]
    };
    for &form in forms {
        let mut w = proto::Writer::new(Vec::new(), header, form).expect("a header writes");
        for r in &records {
            w.write(r).expect("a record read writes back");
        }
        let again = w.into_inner().expect("a Vec takes the bytes");
        let mut reader = proto::Reader::<T, _>::new(again.as_slice()).expect("its header reads");
        for (i, r) in records.iter().enumerate() {
            match reader.next_record() {
                Ok(Some(back)) => assert_eq!(&back, r, "record {i} in {form:?}"),
                other => panic!("record {i} in {form:?}: {other:?}, wrote {r:?}"),
            }
        }
    }
}

/// A binary stream's start: the magic and a header of the current version for `space`.
pub fn binary_header(space: proto::Space) -> Vec<u8> {
    binary_header_with(space, proto::Attributes::default())
}

/// [`binary_header`] with `attributes` (vertex colours, opacity).
pub fn binary_header_with(space: proto::Space, attributes: proto::Attributes) -> Vec<u8> {
    let w = proto::Writer::<proto::Token, _>::new(
        Vec::new(),
        proto::Header::new(space).with(attributes),
        proto::Form::Binary,
    )
    .expect("a header writes");
    w.into_inner().expect("a Vec takes the bytes")
}

/// The spaces a fuzz target puts in front of its bytes.
pub fn spaces() -> [proto::Space; 4] {
    [
        proto::Space::World,
        proto::Space::Eye(proto::View::default()),
        proto::Space::Screen {
            width: 8,
            height: 8,
        },
        proto::Space::Fragments {
            width: 8,
            height: 8,
        },
    ]
}
