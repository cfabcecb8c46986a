//! Numbers at the edge of f64: finite input whose transformation overflows, and input
//! that is not a number. No stage writes an infinity or a NaN of its own making: the stage
//! at fault refuses, naming the polygon's place (or the OBJ line), so that the next stage
//! does not take the blame; and the reference draws what the pipeline draws.

use pipeline_tests::{linear_pipeline, parse_ppm_stream, sh};

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Vertices at ±1.7e308: finite, but too large for the viewing transformation's sums.
const HUGE: &str = "polypipe 1 world\ncolour 1 2 3\n-1.7e308 -1.7e308 -1.7e308\n\
                    1.7e308 -1.7e308 1.7e308\n0 1.7e308 0\nEND\n";

/// `viewxf --eye 10,5,20` on vertices at ±1.7e308 printed `-inf` and exited 0, so
/// that the next stage took the blame.
#[test]
fn viewxf_refuses_to_write_an_infinity() {
    let out = sh("viewxf --eye 10,5,20 --text", HUGE.as_bytes());
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        stderr(&out),
        "viewxf: frame 0, polygon 0: vertex 0 comes out as (-7.602631123499285e307 \
         -1.1613210868087544e308 inf inf) after the viewing transformation: not a finite \
         number (coordinates this large overflow)\n"
    );
    // Only the header was written: no polygon with an infinity in it.
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "polypipe 1 eye aspect 1 hither 1 yon 30\n"
    );
}

/// persp refuses a vertex whose projection overflows, naming its place in the input.
#[test]
fn persp_refuses_to_write_an_infinity() {
    let eye = "polypipe 1 eye aspect 1 hither 1 yon 30\ncolour 1 2 3\n-1e300 0 16 10\n\
               1e300 0 16 10\n0 1e308 0 1e308\nEND\n";
    let out = sh("persp --size 4x4 --text", eye.as_bytes());
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(
        err.starts_with("persp: frame 0, polygon 0: vertex 2 ") && err.lines().count() == 1,
        "{err}"
    );
    assert!(!String::from_utf8_lossy(&out.stdout).contains("inf"));
}

/// the clippers and the splitter, on eye-space input and planes at the edge of f64:
/// whatever they make of it, they never write a number that is not finite. (Their
/// intersections clamp, so today they write; the shared check would refuse naming the
/// polygon if one did not.)
#[test]
fn clippers_and_splitters_never_write_an_infinity() {
    let header = "polypipe 1 eye aspect 1 hither 1 yon 30\ncolour 1 2 3\n";
    let polygons = [
        "1.7e308 0 16 1.7e308\n-1.7e308 0 16 10\n0 1 16 10\n",
        "1.7e308 1.7e308 16 1.7e308\n-1.7e308 -1.7e308 16 1.7e308\n0 -1.7e308 16 10\n",
        "-1.7e308 0 1.7e308 1.7e308\n1.7e308 0 -1.7e308 1.7e308\n0 1e308 0 1e308\n",
        "1e300 1e300 16 10\n-1e300 -1e300 16 10\n1e300 -1e300 16 10\n",
    ];
    let stages = [
        "clipplane left",
        "clipplane hither",
        "clipplane yon",
        "clipplane --plane 1e308,1e308,0,0,-1e308",
        "clipplane --plane 1e308,-1e308,1e308,0,0",
        "splitter x=0.5 /dev/null -",
        "splitter --plane 1e308,1e308,0,0,-1e308 /dev/null -",
    ];
    for polygon in polygons {
        let input = format!("{header}{polygon}END\n");
        for stage in stages {
            let out = sh(&format!("{stage} --text"), input.as_bytes());
            let text = String::from_utf8_lossy(&out.stdout).to_lowercase();
            assert!(
                !text.contains("inf") && !text.contains("nan"),
                "{stage}: {text}"
            );
            if !out.status.success() {
                let err = stderr(&out);
                assert_eq!(out.status.code(), Some(1), "{stage}: {err}");
                assert!(err.contains(": frame 0, polygon 0: "), "{stage}: {err}");
            }
        }
    }
}

/// `scene obj` on `v nan 0 0` wrote `NaN`; it refuses, naming the OBJ line. A model
/// too large to turn (--no-fit) is refused naming the frame where it overflows.
#[test]
fn scene_refuses_numbers_that_are_not_finite() {
    let out = sh("scene obj -", b"v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        stderr(&out),
        "scene: <stdin>: line 2: vertex `v nan 0 0` has a coordinate `nan` that is not a \
         finite number\n"
    );
    assert!(out.stdout.is_empty());
    let huge = b"v 1.7e308 0 1.7e308\nv 1.7e308 1 1.7e308\nv 1.6e308 0 1.7e308\nf 1 2 3\n";
    let out = sh("scene obj --no-fit --frames 8 -", huge);
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(
        err.starts_with("scene: frame 1, polygon 0: vertex 0 comes out as (inf ")
            && err.ends_with("leave out --no-fit)\n"),
        "{err}"
    );
    // Fitted (the default), the same model is scaled into view without overflowing.
    let out = sh("scene obj --frames 8 --text -", huge);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout).to_lowercase();
    assert!(!text.contains("inf") && !text.contains("nan"));
}

/// `zspec`, the reference, drew a triangle with vertices at ±1e307 all black (its
/// Newell sums overflowed) while the pipeline drew it; now both draw it, alike.
#[test]
fn the_reference_draws_a_triangle_at_1e307() {
    let triangle = "polypipe 1 world\ncolour 255 0 0\n-1e307 -1e307 1\n1e307 -1e307 1\n\
                    0 1e307 -1\nEND\n";
    let exact = sh("zspec --size 8x8", triangle.as_bytes());
    assert!(exact.status.success(), "{}", stderr(&exact));
    let exact = parse_ppm_stream(&exact.stdout).unwrap();
    assert!(
        exact[0].pixels.iter().all(|p| *p == [255, 0, 0]),
        "{exact:?}"
    );
    let piped = sh(&linear_pipeline("8x8"), triangle.as_bytes());
    assert!(piped.status.success(), "{}", stderr(&piped));
    assert_eq!(parse_ppm_stream(&piped.stdout).unwrap(), exact);
}

/// `render` filled the screen with a triangle at ±1e308 while `zspec` exited 1 ("a
/// vertex projects to (-inf, inf) on the screen"): the reference now cuts such a polygon
/// to a guard band around the view before projecting it, as the pipeline's clippers cut it
/// to the view, and both draw the same bytes, at ±1e308 and at its neighbours.
#[test]
fn the_reference_and_render_draw_the_same_huge_triangles() {
    for v in ["1.7e308", "1e308", "1e300", "1e154", "1e30"] {
        for (a, b) in [("0", "0"), ("1", "-1"), ("-3", "5")] {
            let triangle = format!(
                "polypipe 1 world\ncolour 255 0 0\n-{v} -{v} {a}\n{v} -{v} {a}\n0 {v} {b}\nEND\n"
            );
            let exact = sh("zspec --size 16x16", triangle.as_bytes());
            assert!(exact.status.success(), "{v}: {}", stderr(&exact));
            let exact = parse_ppm_stream(&exact.stdout).unwrap();
            // Every pixel red: the triangle holds the whole view.
            assert!(
                exact[0].pixels.iter().all(|p| *p == [255, 0, 0]),
                "{v} {a} {b}"
            );
            let rendered = sh("render --size 16x16 -", triangle.as_bytes());
            assert!(rendered.status.success(), "{v}: {}", stderr(&rendered));
            assert_eq!(
                parse_ppm_stream(&rendered.stdout).unwrap(),
                exact,
                "{v} {a} {b}"
            );
        }
    }
}

/// What is not a number is bad data to both, status 1, the same message but for the
/// stage's name (render's viewxf reads it).
#[test]
fn the_reference_and_render_refuse_inf_and_nan_alike() {
    for bad in ["inf", "-inf", "nan"] {
        let triangle = format!("polypipe 1 world\ncolour 255 0 0\n0 0 0\n1 0 0\n{bad} 1 0\nEND\n");
        let said = format!(
            "line 5, column 1: x of vertex 2 (3 numbers a vertex in world space) is `{bad}`; \
             coordinates must be finite\n"
        );
        let exact = sh("zspec --size 16x16", triangle.as_bytes());
        assert_eq!(exact.status.code(), Some(1), "{bad}");
        assert_eq!(stderr(&exact), format!("zspec: {said}"));
        let rendered = sh("render --size 16x16 -", triangle.as_bytes());
        assert_eq!(rendered.status.code(), Some(1), "{bad}");
        assert_eq!(stderr(&rendered), format!("viewxf: {said}"));
    }
}
