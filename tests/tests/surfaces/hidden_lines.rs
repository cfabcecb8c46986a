//! `hiddenline` end to end (Archuleta's hidden-line output, 1972): the exact
//! visible pieces of the edges of a scene where one square hides part of another, shared
//! edges once, colours, the SVG's device coordinates, one file per frame, and, where
//! Chromium is installed, the SVG as a browser draws it.

use pipeline_tests::{sh, stat};

/// A `<line>`: its ends and its stroke.
#[derive(Debug, PartialEq, Clone)]
struct Line {
    from: (f64, f64),
    to: (f64, f64),
    stroke: String,
    /// `class="intersection"`: a piece of the line where two polygons cross.
    intersection: bool,
}

/// The pieces of an SVG (`lines::read_svg`: a dashed `<line>` is the pieces of one
/// edge), and its `<svg>` element.
fn parse(svg: &str) -> (String, Vec<Line>) {
    let head = svg.lines().next().expect("an svg element").to_string();
    assert!(head.starts_with("<svg "), "{head}");
    assert!(svg.trim_end().ends_with("</svg>"));
    let lines = lines::read_svg(svg)
        .expect("hiddenline's SVG")
        .into_iter()
        .map(|s| Line {
            from: (s.from.x, s.from.y),
            to: (s.to.x, s.to.y),
            stroke: format!("rgb({},{},{})", s.colour[0], s.colour[1], s.colour[2]),
            intersection: s.intersection,
        })
        .collect();
    (head, lines)
}

fn hiddenline(args: &str, stream: &str) -> String {
    let out = sh(&format!("hiddenline {args}"), stream.as_bytes());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("UTF-8")
}

/// Red (near, z 0.2) over the top-left corner of blue (far, z 0.6), on a 400×400
/// screen; a grey square shares blue's right edge, nearer than blue.
const SCENE: &str = "polypipe 1 screen 400 400
colour 255 0 0
40 40 0.2
200 40 0.2
200 200 0.2
40 200 0.2
NEXT.POLYGON
colour 0 0 255
120 120 0.6
280 120 0.6
280 280 0.6
120 280 0.6
NEXT.POLYGON
colour 128 128 128
280 120 0.4
360 120 0.4
360 280 0.4
280 280 0.4
END
";

/// A help text as one line: its words joined by single spaces (clap wraps it).
fn help_of(command: &str) -> String {
    let out = sh(&format!("{command} --help"), b"");
    assert!(out.status.success(), "{command} --help: {out:?}");
    String::from_utf8_lossy(&out.stdout)
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}

/// Each hidden-line method is credited to whom it is due: the default, `continuous`, is
/// hiddenline's own exact geometry, not Archuleta's; `archuleta` is his counters on the
/// visible segments of Watkins's scan-line algorithm (the scanline stage's), in
/// hiddenline's help and in render's.
#[test]
fn the_help_credits_each_method_rightly() {
    let help = help_of("hiddenline");
    for said in [
        "By default (`--method continuous`) visibility is exact geometry (f64), not \
         sampled, this program's own way rather than Archuleta's:",
        "`--method archuleta` is Archuleta's own output of Watkins's scan-line algorithm.",
        "`continuous` (this program's own), each edge against the polygons that may hide \
         it in exact geometry; or `archuleta`, Archuleta's (1972): counters on the visible \
         segments of Watkins's scan-line algorithm (the scanline stage's),",
    ] {
        assert!(
            help.contains(said),
            "hiddenline --help lacks {said:?}: {help}"
        );
    }
    // Once the whole stage, the default included, was "Archuleta's output of Watkins's
    // algorithm".
    assert!(!help.contains("output of Watkins's algorithm"), "{help}");
    let render = help_of("render");
    let said = "With --hidden-line: continuous (default: exact pieces, hiddenline's own) or \
                archuleta (Archuleta's counters on Watkins's scan-line segments, raster \
                resolution), hiddenline's --method";
    assert!(
        render.contains(said),
        "render --help lacks {said:?}: {render}"
    );
}

/// Equal to the SVG's precision: the ends of a `<line>` exactly, the inner ends of a
/// dashed one (an edge's pieces joined) to a thousandth of a pixel.
fn close(a: (f64, f64), b: (f64, f64)) -> bool {
    (a.0 - b.0).abs() <= 1e-3 && (a.1 - b.1).abs() <= 1e-3
}

#[test]
fn one_square_hides_part_of_another_exactly() {
    let (head, lines) = parse(&hiddenline("", SCENE));
    assert!(head.contains(r#"viewBox="0 0 400 400""#), "{head}");
    let (red, blue, grey) = ("rgb(255,0,0)", "rgb(0,0,255)", "rgb(128,128,128)");
    let want = [
        // Red: all four edges.
        ((40.0, 40.0), (200.0, 40.0), red),
        ((200.0, 40.0), (200.0, 200.0), red),
        ((200.0, 200.0), (40.0, 200.0), red),
        ((40.0, 200.0), (40.0, 40.0), red),
        // Blue: its top and left edges from where they leave red; its right edge is
        // shared with grey and drawn once (in blue's colour: blue is earlier, and
        // shows beside it).
        ((200.0, 120.0), (280.0, 120.0), blue),
        ((280.0, 120.0), (280.0, 280.0), blue),
        ((280.0, 280.0), (120.0, 280.0), blue),
        ((120.0, 280.0), (120.0, 200.0), blue),
        // Grey: its other three edges.
        ((280.0, 120.0), (360.0, 120.0), grey),
        ((360.0, 120.0), (360.0, 280.0), grey),
        ((360.0, 280.0), (280.0, 280.0), grey),
    ];
    assert_eq!(lines.len(), want.len(), "{lines:#?}");
    for (line, (from, to, stroke)) in lines.iter().zip(want) {
        assert!(
            close(line.from, from) && close(line.to, to),
            "{line:?}, want {from:?}–{to:?}"
        );
        assert_eq!(line.stroke, stroke);
    }
    // The shared edge X = 280 is one line.
    let on_280 = lines
        .iter()
        .filter(|l| l.from.0 == 280.0 && l.to.0 == 280.0)
        .count();
    assert_eq!(on_280, 1);
}

#[test]
fn the_thesis_scene_from_the_pipeline_in_device_coordinates() {
    let out = sh(
        "viewxf --size 320x240 < examples/penetrating.txt | clipbatch | persp --size 320x240 | hiddenline --stats",
        b"",
    );
    assert!(out.status.success());
    let (head, lines) = parse(&String::from_utf8_lossy(&out.stdout));
    assert_eq!(
        head,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="320" height="240" viewBox="0 0 320 240">"#
    );
    // Every piece on the screen, in one of the two colours.
    for l in &lines {
        for (x, y) in [l.from, l.to] {
            assert!(
                (0.0..=320.0).contains(&x) && (0.0..=240.0).contains(&y),
                "{l:?}"
            );
        }
        assert!(
            l.stroke == "rgb(255,60,60)" || l.stroke == "rgb(60,60,255)",
            "{l:?}"
        );
    }
    // Three triangle edges and four quadrilateral edges. The quadrilateral's two long
    // edges pass through the triangle's plane inside it: each is hidden from where it
    // goes behind to where it leaves the triangle (two pieces each); the triangle's
    // left edge is hidden where the quadrilateral's near part crosses it (two pieces).
    let stats = String::from_utf8_lossy(&out.stderr);
    let keys = ["frames", "edges", "shared", "cuts", "border"];
    assert_eq!(keys.map(|k| stat(&stats, k)), [1, 7, 0, 0, 0], "{stats}");
    assert_eq!(lines.len(), 11, "{lines:#?}");
    // Where the quadrilateral passes through the triangle, the line of intersection
    // (Archuleta's "second problem"): the triangle's depth is 0.98276, the
    // quadrilateral's 0.96121 + 7.697e-5·(X + Y), equal on X + Y = 280. Inside both it
    // runs from the quadrilateral's long edge, at (160, 120), to its other long edge
    // (200, 192)→(52, 60) at s = 0.4, (140.8, 139.2); drawn in the colour of the
    // triangle, earlier in the stream.
    let crossing: Vec<&Line> = lines.iter().filter(|l| l.intersection).collect();
    assert_eq!(crossing.len(), 1, "{lines:#?}");
    let c = crossing[0];
    assert!(
        close(c.from, (160.0, 120.0)) && close(c.to, (140.8, 139.2)),
        "{c:?}"
    );
    assert_eq!(c.stroke, "rgb(255,60,60)");
    let lines: Vec<Line> = lines.into_iter().filter(|l| !l.intersection).collect();
    // The long edge (76, 36)→(216, 176) runs from depth 0.9698 to 0.9914 through the
    // triangle's 0.9828: it goes behind at t = 0.6, (160, 120), and is seen again past
    // the triangle's base Y = 158.4.
    let blue: Vec<&Line> = lines
        .iter()
        .filter(|l| l.stroke == "rgb(60,60,255)")
        .collect();
    assert!(close(blue[1].from, (76.0, 36.0)) && (blue[1].to.0 - 160.0).abs() < 1e-3);
    assert!(close(blue[2].from, (198.4, 158.4)) && close(blue[2].to, (216.0, 176.0)));
}

#[test]
fn a_movie_is_one_file_per_frame() {
    let dir = tempfile::tempdir().expect("temp dir");
    let pattern = dir.path().join("f%03d.svg");
    let out = sh(
        &format!(
            "scene spheres --frames 3 | viewxf --size 120x90 | clipbatch | persp --size 120x90 | hiddenline -o '{}'",
            pattern.display()
        ),
        b"",
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let frames: Vec<String> = (0..3)
        .map(|n| {
            std::fs::read_to_string(dir.path().join(format!("f{n:03}.svg"))).expect("a frame file")
        })
        .collect();
    for f in &frames {
        let (head, lines) = parse(f);
        assert!(head.contains(r#"viewBox="0 0 120 90""#));
        assert!(lines.len() > 100);
    }
    assert_ne!(frames[0], frames[1], "the spheres move");
    // Two frames and no -o: refused, after the first.
    let out = sh(
        "scene spheres --frames 2 | viewxf | clipbatch | persp --size 50x50 | hiddenline",
        b"",
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr)
        .contains("hiddenline: more than one frame: give -o with %d"));
    // A world-space stream is not its input.
    let out = sh("hiddenline < examples/penetrating.txt", b"");
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).starts_with("hiddenline: "));
    let out = sh("hiddenline -o 'x%s.svg' < /dev/null", b"");
    assert_eq!(out.status.code(), Some(2));
    // SVG under another name (render.sh --hidden-line -o lines.png wrote SVG into a .png).
    for name in ["lines.png", "-", "frame%03d"] {
        let out = sh(&format!("hiddenline -o '{name}' < /dev/null"), b"");
        assert_eq!(out.status.code(), Some(2), "-o {name}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr),
            format!("hiddenline: -o {name}: the file name must end .svg\n")
        );
    }
}

#[test]
fn chromium_draws_the_visible_pieces() {
    let chromium = std::path::Path::new("/usr/bin/chromium");
    if !chromium.exists() {
        pipeline_tests::skip("/usr/bin/chromium is not installed (apt-get install -y chromium)");
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let svg = dir.path().join("scene.svg");
    let png = dir.path().join("scene.png");
    std::fs::write(&svg, hiddenline("--stroke-width 4", SCENE)).expect("write svg");
    let profile = tempfile::tempdir().expect("profile dir");
    let out = std::process::Command::new(chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--no-first-run",
        ])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .arg(format!("--screenshot={}", png.display()))
        .arg("--window-size=400,400")
        .arg(&svg)
        .output()
        .expect("run chromium");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let image = image::open(&png).expect("a PNG").to_rgb8();
    assert_eq!(image.dimensions(), (400, 400));
    let at = |x, y| image.get_pixel(x, y).0;
    // On red's top edge; on blue's visible right edge; on grey's right edge.
    assert_eq!(at(120, 40), [255, 0, 0]);
    assert_eq!(at(280, 200), [0, 0, 255]);
    assert_eq!(at(360, 200), [128, 128, 128]);
    // Where blue's left and top edges run under red: nothing drawn.
    assert_eq!(at(120, 160), [255, 255, 255]);
    assert_eq!(at(160, 120), [255, 255, 255]);
    // And blue's left edge below red is drawn.
    assert_eq!(at(120, 240), [0, 0, 255]);
}

#[test]
fn the_degenerate_scenes_draw_without_error() {
    // docs/degenerate.md's scenes and the flat examples: edge-on, zero-area and 0-2-vertex
    // polygons draw and hide nothing; every frame is a well-formed SVG of pieces on the
    // screen, by either method.
    let dir = tempfile::tempdir().expect("temp dir");
    let root = pipeline_tests::repo_root();
    let mut scenes: Vec<std::path::PathBuf> = std::fs::read_dir(root.join("examples/degenerate"))
        .expect("examples")
        .map(|e| e.expect("entry").path())
        .collect();
    scenes.extend(
        [
            "cube",
            "concave",
            "cyclic-bars",
            "overlapping-squares",
            "penetrating",
            "triangle-square",
        ]
        .map(|n| root.join(format!("examples/{n}.txt"))),
    );
    for path in scenes {
        for method in ["continuous", "archuleta"] {
            let pattern = dir.path().join(format!(
                "{}-{method}-%d.svg",
                path.file_stem().expect("name").to_string_lossy()
            ));
            let out = sh(
                &format!(
                    "viewxf --size 64x48 < '{}' | clipbatch | persp --size 64x48 | hiddenline --method {method} -o '{}'",
                    path.display(),
                    pattern.display()
                ),
                b"",
            );
            assert!(
                out.status.success(),
                "{} {method}: {}",
                path.display(),
                String::from_utf8_lossy(&out.stderr)
            );
            let first = std::fs::read_to_string(pattern.to_string_lossy().replace("%d", "0"))
                .expect("frame 0");
            let (head, lines) = parse(&first);
            assert!(head.contains(r#"viewBox="0 0 64 48""#));
            for l in lines {
                for (x, y) in [l.from, l.to] {
                    assert!(
                        (0.0..=64.0).contains(&x) && (0.0..=48.0).contains(&y),
                        "{} {method}: {l:?}",
                        path.display()
                    );
                }
            }
        }
    }
}

/// A stack of 2,000 squares over the same place, shuffled in depth: in every cell of the
/// grid the nearest surrounds it and the rest are left out, so no edge is tested against
/// the stack.
#[test]
fn a_stack_costs_nothing_but_its_nearest() {
    let n = 2000;
    let mut s = String::from("polypipe 1 screen 300 300\n");
    for i in 0..n {
        let k = (i * 1237) % n;
        let z = 0.2 + 0.6 * k as f64 / n as f64;
        if i > 0 {
            s += "NEXT.POLYGON\n";
        }
        s += &format!(
            "colour {} 0 0\n20 20 {z}\n280 20 {z}\n280 280 {z}\n20 280 {z}\n",
            k % 256
        );
    }
    s += "END\n";
    let out = sh("hiddenline --stats", s.as_bytes());
    assert!(out.status.success());
    let (_, lines) = parse(&String::from_utf8_lossy(&out.stdout));
    assert_eq!(lines.len(), 4, "{lines:#?}");
    let stats = String::from_utf8_lossy(&out.stderr);
    let keys = [
        "frames",
        "edges",
        "shared",
        "cuts",
        "border",
        "pairs_tested",
        "pieces",
        "intersection_lines",
    ];
    assert_eq!(
        keys.map(|k| stat(&stats, k)),
        [1, 4 * n, 4 * (n - 1), 0, 0, 0, 4, 0],
        "{stats}"
    );
}

/// The intersection pieces hiddenline draws for a scene (`scene ARGS` through the
/// pipeline at 500×500), and its --stats line.
fn intersections_of(scene: &str, method: &str) -> (usize, String) {
    let out = sh(
        &format!(
            "scene {scene} | viewxf --size 500x500 | clipbatch | persp --size 500x500 | hiddenline --stats {method}"
        ),
        b"",
    );
    assert!(
        out.status.success(),
        "{scene}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (_, lines) = parse(&String::from_utf8_lossy(&out.stdout));
    let n = lines.iter().filter(|l| l.intersection).count();
    (n, String::from_utf8_lossy(&out.stderr).into_owned())
}

/// Closed models whose faces meet only along shared edges and vertices have no line of
/// intersection: the planes of two neighbours meet along their common edge, which is an
/// edge of the model (drawn as one), not a line where one surface passes through another.
/// Before the neighbours were passed over, the sphere got 39 such pieces along its
/// silhouette and the building one across its roof.
#[test]
fn closed_models_have_no_line_of_intersection() {
    for scene in [
        "sphere",
        "building",
        "obj examples/models/icosahedron.obj",
        "obj examples/models/torus.obj",
    ] {
        for method in ["--method continuous", "--method archuleta"] {
            let (n, stats) = intersections_of(scene, method);
            assert_eq!(n, 0, "{scene} {method}: {stats}");
            assert_eq!(
                ["intersection_lines", "intersection_pieces"].map(|k| stat(&stats, k)),
                [0, 0],
                "{scene} {method}: {stats}"
            );
        }
    }
    // Two spheres that pass through each other do have one (Archuleta's figure 1).
    for method in ["", "--method archuleta"] {
        let (n, _) = intersections_of("spheres", method);
        assert!(n > 10, "{method}: {n}");
    }
}

/// The thesis's penetrating scene at 500×500: the quadrilateral passes through the
/// triangle along one line, drawn as one piece.
#[test]
fn the_penetrating_scene_has_its_one_line() {
    for method in ["continuous", "archuleta"] {
        let out = sh(
            &format!("viewxf --size 500x500 < examples/penetrating.txt | clipbatch | persp --size 500x500 | hiddenline --stats --method {method}"),
            b"",
        );
        assert!(out.status.success());
        let (_, lines) = parse(&String::from_utf8_lossy(&out.stdout));
        assert_eq!(
            lines.iter().filter(|l| l.intersection).count(),
            1,
            "{method}"
        );
        assert!(
            String::from_utf8_lossy(&out.stderr)
                .contains("; 1 lines of intersection, 1 pieces drawn;"),
            "{method}"
        );
    }
    let out = sh("hiddenline --method warnock < /dev/null", b"");
    assert_eq!(out.status.code(), Some(2));
}

/// render.sh passes `--hidden-line-method` to hiddenline's `--method`, and only with
/// `--hidden-line`.
#[test]
fn render_sh_draws_with_either_method() {
    let dir = tempfile::tempdir().expect("temp dir");
    for method in ["continuous", "archuleta"] {
        let svg = dir.path().join(format!("{method}.svg"));
        let out = sh(
            &format!(
                "scripts/render.sh --size 320x240 --hidden-line --hidden-line-method {method} -o '{}' examples/penetrating.txt",
                svg.display()
            ),
            b"",
        );
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let (_, lines) = parse(&std::fs::read_to_string(&svg).expect("the SVG"));
        assert_eq!(
            lines.iter().filter(|l| l.intersection).count(),
            1,
            "{method}"
        );
        assert_eq!(lines.len(), 11, "{method}: {lines:#?}");
    }
    let out = sh(
        "scripts/render.sh --hidden-line-method archuleta -o x.png examples/penetrating.txt",
        b"",
    );
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "render: --hidden-line-method needs --hidden-line\n"
    );
}

/// `--score REFERENCE.svg`: the line error of the drawing against a reference drawing of
/// the same frame (lines::line_error). The continuous drawing against itself is 0;
/// Archuleta's on the thesis's penetrating scene at 256 × 256 misses the ends of runs
/// between scan lines, a few pixels in all, and draws nothing far from the exact lines.
#[test]
fn a_drawing_is_scored_against_a_reference() {
    let dir = tempfile::tempdir().unwrap();
    let reference = dir.path().join("ref.svg");
    let stream = dir.path().join("in");
    let out = sh(
        &format!(
            "viewxf --size 256x256 < examples/penetrating.txt | clipbatch | persp --size 256x256 > {0} \
             && hiddenline < {0} > {1} && hiddenline --score {1} < {0} > /dev/null",
            stream.display(),
            reference.display()
        ),
        b"",
    );
    assert!(out.status.success(), "{out:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    let total = lines::read_svg(&std::fs::read_to_string(&reference).unwrap())
        .unwrap()
        .iter()
        .map(|s| s.length())
        .sum::<f64>();
    // (The drawn length is the exact pieces'; the reference's, read back, is to the
    // thousandth of a pixel of its dash array.)
    let want = format!(
        "hiddenline: line error 0.000 px: 0.000 px of the reference's {total:.3} px missed, \
         0.000 px of the "
    );
    assert!(
        err.trim().starts_with(&want) && err.trim().ends_with(" px drawn not on it"),
        "{err}"
    );
    let out = sh(
        &format!(
            "hiddenline --method archuleta --score {} < {}",
            reference.display(),
            stream.display()
        ),
        b"",
    );
    assert!(out.status.success(), "{out:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    let words: Vec<&str> = err.split_whitespace().collect();
    assert_eq!(words[..3], ["hiddenline:", "line", "error"], "{err}");
    let e: f64 = words[3].parse().unwrap();
    assert!(e > 0.0 && e < 20.0, "{err}");
    // More than one frame has no one reference.
    let out = sh(
        &format!(
            "scene spheres --frames 2 | viewxf | clipbatch | persp --size 64x64 | hiddenline -o {}/f%d.svg --score {}",
            dir.path().display(),
            reference.display()
        ),
        b"",
    );
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    assert_eq!(
        String::from_utf8_lossy(&out.stderr).trim(),
        "hiddenline: --score compares one frame with its reference, and this stream has more"
    );
}
