//! `clipbatch` (Theoharis & Page's batch clipper, all six planes in one process) writes
//! what the six-process chain `clipplane left | right | top | bottom | hither | yon`
//! writes, byte for byte in the binary form: every vertex's bits, the polygon
//! annotations (`plane`, edge `supports`), empty and degenerate polygons, NEXT.FRAME and
//! END, and the polygons before a bad record.

use pipeline_tests::sh;
use proptest::prelude::*;
use std::fmt::Write as _;

const CHAIN: &str = "clipplane left | clipplane right | clipplane top | clipplane bottom \
                     | clipplane hither | clipplane yon";

/// Runs `script` on `stdin` and returns (success, stdout), failing on a crash.
fn run_on(script: &str, stdin: &[u8]) -> (bool, Vec<u8>, String) {
    let out = sh(script, stdin);
    // A signal (a panic's abort, a crash) is never an answer.
    assert!(
        out.status.code().is_some(),
        "`{script}` was killed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    (
        out.status.success(),
        out.stdout,
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Asserts that clipbatch (with each `--batch` given) and the chain agree on `eye`, an
/// eye-space stream in either form: both succeed or both fail, with the same bytes out.
fn same_as_chain(what: &str, eye: &[u8], batches: &[u32]) -> Result<(), TestCaseError> {
    let (chain_ok, chain_out, chain_err) = run_on(CHAIN, eye);
    for &b in batches {
        let (ok, out, err) = run_on(&format!("clipbatch --batch {b}"), eye);
        prop_assert_eq!(
            ok,
            chain_ok,
            "{}, --batch {}: clipbatch {} / chain {}",
            what,
            b,
            err,
            chain_err
        );
        prop_assert!(
            out == chain_out,
            "{}, --batch {}: clipbatch's output differs from the chain's",
            what,
            b
        );
    }
    Ok(())
}

#[test]
fn every_example_clips_as_the_chain_does() {
    let mut scenes: Vec<String> = Vec::new();
    for dir in ["examples", "examples/degenerate"] {
        for entry in std::fs::read_dir(pipeline_tests::repo_root().join(dir)).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "txt") {
                scenes.push(format!(
                    "{dir}/{}",
                    path.file_name().unwrap().to_string_lossy()
                ));
            }
        }
    }
    scenes.sort();
    assert!(scenes.len() >= 20, "{scenes:?}");
    let mut cut = 0;
    for scene in &scenes {
        for size in ["500x500", "640x480"] {
            let (ok, eye, err) = run_on(&format!("viewxf --size {size} < {scene}"), b"");
            assert!(ok, "viewxf {scene}: {err}");
            same_as_chain(&format!("{scene} at {size}"), &eye, &[1, 3, 1024]).unwrap();
            // Text out too (the last stage's --text against clipbatch's).
            let (_, chain_text, _) = run_on(&format!("{CHAIN} --text"), &eye);
            let (_, text, _) = run_on("clipbatch --text", &eye);
            assert_eq!(
                String::from_utf8_lossy(&text),
                String::from_utf8_lossy(&chain_text),
                "{scene}"
            );
            let (_, unclipped, _) = run_on("clipplane --plane 0,0,0,1,1e300 --text", &eye);
            cut += usize::from(unclipped != text);
        }
    }
    // The comparison means something: the pyramid cuts polygons of 14 of the 40 runs
    // (of the others, some are wholly inside, some wholly outside the pyramid).
    assert!(cut >= 14, "only {cut} scene runs were cut at all");
}

#[test]
fn an_environment_movie_clips_as_the_chain_does() {
    let (ok, eye, err) = run_on(
        "scene environment --polygons 3000 --clipped 0.5 --frames 3 --seed 9 --size 320x200 | viewxf --size 320x200",
        b"",
    );
    assert!(ok, "{err}");
    same_as_chain("environment movie", &eye, &[1, 7, 1024, 4096]).unwrap();
}

#[test]
fn bad_input_gives_the_chain_s_output_up_to_the_error() {
    let header = "polypipe 1 eye aspect 1 hither 1 yon 30\n";
    let good = "colour 1 1 1\n0 0 16 10\n-20 0 16 10\n0 4 16 10\nNEXT.POLYGON\ncolour 2 2 2\n1 1 16 10\n2 1 16 10\n2 2 16 10\n";
    for (what, tail) in [
        ("three numbers", "NEXT.POLYGON\ncolour 3 3 3\n0 0 16\nEND\n"),
        (
            "not finite",
            "NEXT.POLYGON\ncolour 3 3 3\n0 nan 16 10\nEND\n",
        ),
        ("no END", "NEXT.FRAME\ncolour 3 3 3\n0 0 16 10\n"),
        ("after END", "END\ncolour 3 3 3\n"),
    ] {
        let stream = format!("{header}{good}{tail}");
        let (chain_ok, chain_out, _) = run_on(CHAIN, stream.as_bytes());
        let (ok, out, err) = run_on("clipbatch", stream.as_bytes());
        assert!(!chain_ok && !ok, "{what}: {err}");
        assert!(err.starts_with("clipbatch: "), "{what}: {err}");
        assert_eq!(out, chain_out, "{what}");
        // The two good polygons came out (clipped) before the error.
        let (_, text, _) = run_on("clipplane top --text", &out);
        let text = String::from_utf8_lossy(&text);
        assert!(
            text.contains("colour 1 1 1\n0 0 16 10\n-10 0 16 10\n-10 2 16 10\n0 4 16 10\n"),
            "{what}: {text}"
        );
    }
    // A binary stream cut short in the middle of a record.
    let (_, eye, _) = run_on("viewxf < examples/cube.txt", b"");
    let cut = &eye[..eye.len() - 40];
    let (_, chain_out, _) = run_on(CHAIN, cut);
    let (ok, out, err) = run_on("clipbatch", cut);
    assert!(!ok && err.contains("cut short"), "{err}");
    assert_eq!(out, chain_out);
}

/// One coordinate of an eye-space vertex, relative to w: on a side plane exactly
/// (x_e = ±a·w), near one, anywhere, or huge.
fn across(aspect: f64, w: f64) -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => (-3.0..3.0f64).prop_map(move |t| t * aspect * w),
        2 => prop::sample::select(vec![-1.0, 1.0, 0.0, 0.5, -0.999999999999, 1.0000000001])
            .prop_map(move |t| t * aspect * w),
        2 => -100.0..100.0f64,
        1 => prop::sample::select(vec![1e30, -1e30, 1e300, -1e300, f64::MAX, -f64::MIN_POSITIVE, 5e-324]),
    ]
}

/// An eye-space vertex: z_e in front of, on, near and behind the eye and the hither and
/// yon planes, and huge; w = z_e·s/d as viewxf makes it (s/d = 0.625), now and then
/// anything else.
fn vertex(view: (f64, f64, f64)) -> impl Strategy<Value = [f64; 4]> {
    let (aspect, hither, yon) = view;
    let z = prop_oneof![
        5 => -10.0..50.0f64,
        2 => prop::sample::select(vec![hither, yon, 0.0, -hither, hither * 0.5, yon * 2.0, -0.0]),
        1 => prop::sample::select(vec![1e30, -1e30, 1e300, -1e300, f64::MAX, -f64::MAX, 1e-310]),
    ];
    let w_of = prop_oneof![
        6 => Just(None),
        1 => (-1e3..1e3f64).prop_map(Some),
    ];
    (z, w_of)
        .prop_flat_map(move |(z, w_of)| {
            let w = w_of.unwrap_or(z * 0.625);
            (across(aspect, w), across(1.0, w), Just(z), Just(w))
        })
        .prop_map(|(x, y, z, w)| [x, y, z, w])
}

#[derive(Clone, Debug)]
struct Poly {
    vertices: Vec<[f64; 4]>,
    plane: Option<[f64; 4]>,
    /// Per vertex, optionally its edge's support.
    supports: Vec<Option<([f64; 4], [f64; 4])>>,
}

fn polygon(view: (f64, f64, f64)) -> impl Strategy<Value = Poly> {
    (
        prop::collection::vec(vertex(view), 0..10),
        prop::option::weighted(0.2, prop::array::uniform4(-10.0..10.0f64)),
        any::<bool>(),
    )
        .prop_flat_map(move |(vertices, plane, supported)| {
            let n = vertices.len();
            let supports = if supported && n > 0 {
                prop::collection::vec(prop::option::of((vertex(view), vertex(view))), n..=n).boxed()
            } else {
                Just(Vec::new()).boxed()
            };
            (Just(vertices), Just(plane), supports)
        })
        .prop_map(|(vertices, plane, supports)| Poly {
            vertices,
            plane,
            supports,
        })
}

fn view() -> impl Strategy<Value = (f64, f64, f64)> {
    (
        prop::sample::select(vec![1.0, 16.0 / 9.0, 0.5]),
        prop::sample::select(vec![(1.0, 30.0), (0.25, 4.0), (2.0, 1e6)]),
    )
        .prop_map(|(a, (k1, k2))| (a, k1, k2))
}

/// A text eye-space stream: frames of polygons.
fn stream() -> impl Strategy<Value = String> {
    view().prop_flat_map(|v| {
        prop::collection::vec(prop::collection::vec(polygon(v), 0..12), 1..4).prop_map(
            move |frames| {
                let (aspect, hither, yon) = v;
                let mut s = format!("polypipe 1 eye aspect {aspect} hither {hither} yon {yon}\n");
                let point = |p: &[f64; 4]| format!("{} {} {} {}", p[0], p[1], p[2], p[3]);
                for (f, frame) in frames.iter().enumerate() {
                    if f > 0 {
                        s += "NEXT.FRAME\n";
                    }
                    for (i, poly) in frame.iter().enumerate() {
                        if i > 0 {
                            s += "NEXT.POLYGON\n";
                        }
                        s += "colour 10 20 30\n";
                        if let Some(n) = poly.plane {
                            writeln!(s, "plane {} {} {} {}", n[0], n[1], n[2], n[3]).unwrap();
                        }
                        for (k, v) in poly.vertices.iter().enumerate() {
                            s += &point(v);
                            if let Some(Some((a, b))) = poly.supports.get(k) {
                                write!(s, " on {} {}", point(a), point(b)).unwrap();
                            }
                            s += "\n";
                        }
                    }
                }
                s + "END\n"
            },
        )
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// Random eye-space streams (vertices on the planes, behind the eye, huge,
    /// subnormal; annotations; empty and one- and two-vertex polygons; several frames)
    /// through the chain and through clipbatch with batches small enough to end mid-frame:
    /// the same bytes.
    #[test]
    fn clipbatch_is_the_chain(text in stream(), batch in 1u32..6) {
        same_as_chain("random stream", text.as_bytes(), &[batch, 1024])?;
    }
}
