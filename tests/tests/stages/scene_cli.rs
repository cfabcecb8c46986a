//! The `scene` binary end to end: exact text output, the environment's statistics read
//! back through proto's reader, OBJ files written here, and the error paths.

use assert_cmd::Command;
use predicates::prelude::*;
use proto::{Polygon, Reader, Space, Token};
use std::fs;

fn scene() -> Command {
    Command::new(pipeline_tests::bin("scene"))
}

/// Reads a stream (either form) into frames of polygons, checking the header is world.
fn frames_of(bytes: &[u8]) -> Vec<Vec<Polygon>> {
    let mut reader = Reader::<Token, _>::new(bytes).unwrap();
    assert_eq!(reader.header().space, Space::World);
    let mut frames = vec![Vec::new()];
    let mut ended = false;
    while let Some(t) = reader.next_record().unwrap() {
        assert!(!ended, "records after END");
        match t {
            Token::Polygon(p) => frames.last_mut().unwrap().push(p),
            Token::NextFrame => frames.push(Vec::new()),
            Token::End => ended = true,
            Token::Skip(n) => panic!("scene wrote `skip {n}`"),
        }
    }
    assert!(ended, "no END");
    frames
}

const PENETRATING: &str = "polypipe 1 world
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
fn penetrating_text_is_exact() {
    scene()
        .args(["penetrating", "--text"])
        .assert()
        .success()
        .stdout(PENETRATING);
}

#[test]
fn penetrating_example_file_is_the_same_scene() {
    let text = fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/penetrating.txt"
    ))
    .unwrap();
    let out = scene().args(["penetrating", "--text"]).output().unwrap();
    assert_eq!(frames_of(text.as_bytes()), frames_of(&out.stdout));
}

#[test]
fn binary_and_text_carry_the_same_polygons() {
    for args in [
        &["penetrating"][..],
        &["environment", "--polygons", "50", "--frames", "3"],
        &["mesh", "--cols", "3", "--rows", "2", "--frames", "2"],
        &["spheres", "--stacks", "4", "--slices", "6"],
    ] {
        let binary = scene().args(args).output().unwrap();
        assert!(binary.status.success());
        assert_eq!(binary.stdout[0], 0x89, "binary by default");
        let text = scene().args(args).arg("--text").output().unwrap();
        assert_eq!(
            frames_of(&binary.stdout),
            frames_of(&text.stdout),
            "{args:?}"
        );
    }
}

#[test]
fn triangle_square_text_is_exact() {
    scene()
        .args(["triangle-square", "--text"])
        .assert()
        .success()
        .stdout(
            "polypipe 1 world\ncolour 60 200 80\n-6 -6 0\n6 -6 0\n6 6 0\n-6 6 0\n\
             NEXT.POLYGON\ncolour 240 200 40\n-8 -8 -5\n8 -8 -5\n0 3 4\nEND\n",
        );
}

/// A screen-space scene: a `screen W H` header, the size given after the scene's name,
/// and with --frames the same frame again after each NEXT.FRAME.
#[test]
fn screen_penetrate_text_is_exact() {
    let frame = "colour 200 0 0\n0 0 0.2\n10 0 0.6\n10 8 0.6\n0 8 0.2\nNEXT.POLYGON\n\
                 colour 0 0 200\n0 0 0.55\n10 0 0.31\n10 8 0.31\n0 8 0.55\n";
    scene()
        .args([
            "screen",
            "penetrate",
            "--size",
            "10x8",
            "--frames",
            "2",
            "--text",
        ])
        .assert()
        .success()
        .stdout(format!(
            "polypipe 1 screen 10 8\n{frame}NEXT.FRAME\n{frame}END\n"
        ));
    // The binary form holds the same polygons.
    let binary = scene()
        .args(["screen", "stack", "7", "--size", "64x48"])
        .output()
        .unwrap();
    let mut reader = Reader::<Token, _>::new(&binary.stdout[..]).unwrap();
    assert_eq!(
        reader.header().space,
        Space::Screen {
            width: 64,
            height: 48
        }
    );
    let mut polygons = 0;
    while let Some(Token::Polygon(p)) = reader.next_record().unwrap() {
        assert_eq!(p.vertices[2].truncate().truncate().to_array(), [64.0, 48.0]);
        polygons += 1;
    }
    assert_eq!(polygons, 7);
}

#[test]
fn frames_are_separated_by_next_frame() {
    let out = scene()
        .args(["penetrating", "--frames", "4", "--text"])
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    assert_eq!(text.matches("NEXT.FRAME").count(), 3);
    assert!(text.ends_with("END\n"));
    let frames = frames_of(text.as_bytes());
    assert_eq!(frames.len(), 4);
    // Frame 2 is half a turn about the vertical: (x, y, z) → (−x, y, −z).
    let v = frames[2][0].vertices[0];
    assert!(
        (v.x - 8.0).abs() < 1e-12 && v.y == -4.0 && v.z.abs() < 1e-12,
        "{v}"
    );
}

#[test]
fn environment_statistics_through_the_stream() {
    use scene::environment::{frame_stats, view_volume};
    let out = scene()
        .args([
            "environment",
            "--polygons",
            "1024",
            "--clipped",
            "0.5",
            "--depth-complexity",
            "2",
            "--seed",
            "5",
            "--size",
            "640x480",
        ])
        .output()
        .unwrap();
    assert!(out.status.success());
    let frames = frames_of(&out.stdout);
    assert_eq!(frames.len(), 1);
    assert_eq!(frames[0].len(), 1024);
    let stats = frame_stats(&frames[0], &view_volume(640.0 / 480.0));
    assert_eq!(stats.inside + stats.outside, 1024);
    let f = stats.outside as f64 / 1024.0;
    assert!((f - 0.5).abs() < 0.05, "clipped fraction {f}");
    assert!((stats.depth_complexity - 2.0).abs() < 1e-6, "{stats:?}");
    // The stream went through the binary codec (f64 exact): same as the library's.
    let lib = scene::environment(&scene::Environment {
        polygons: 1024,
        depth_complexity: 2.0,
        seed: 5,
        aspect: 640.0 / 480.0,
        ..scene::Environment::default()
    });
    assert_eq!(frames, lib);
}

#[test]
fn environment_is_reproducible_and_seeded() {
    let run = |seed: &str| {
        scene()
            .args(["environment", "--polygons", "100", "--seed", seed])
            .output()
            .unwrap()
            .stdout
    };
    assert_eq!(run("9"), run("9"));
    assert_ne!(run("9"), run("10"));
}

#[test]
fn environment_movie_keeps_its_statistics() {
    use scene::environment::{frame_stats, view_volume};
    let out = scene()
        .args(["environment", "--polygons", "200", "--frames", "5"])
        .output()
        .unwrap();
    let frames = frames_of(&out.stdout);
    assert_eq!(frames.len(), 5);
    let first = frame_stats(&frames[0], &view_volume(1.0));
    for frame in &frames[1..] {
        let s = frame_stats(frame, &view_volume(1.0));
        assert_eq!((s.inside, s.outside), (first.inside, first.outside));
        assert!((s.depth_complexity - 1.0).abs() < 1e-6);
    }
    assert_ne!(frames[0], frames[4]);
}

#[test]
fn bad_arguments_are_usage_errors() {
    scene()
        .args(["environment", "--clipped", "1.5"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("not a fraction from 0 to 1"));
    scene()
        .args(["penetrating", "--frames", "0"])
        .assert()
        .code(2);
    scene().args(["sphere", "--radius", "-1"]).assert().code(2);
    scene().assert().code(2);
}

#[test]
fn hostile_scenes_have_their_counts() {
    for (name, n) in [
        ("stack", 7),
        ("slivers", 9),
        ("pinhead", 11),
        ("planes", 5),
        ("strips", 13),
    ] {
        let out = scene().args([name, &n.to_string()]).output().unwrap();
        assert!(out.status.success(), "{name}");
        let frames = frames_of(&out.stdout);
        assert_eq!(frames.len(), 1, "{name}");
        assert_eq!(frames[0].len(), n, "{name}");
    }
    let two = frames_of(
        &scene()
            .args(["stack", "3", "--frames", "2"])
            .output()
            .unwrap()
            .stdout,
    );
    assert_eq!(two.len(), 2);
    scene()
        .args(["stack", "0"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("0 is not from 1 to 16777216"));
    scene().args(["pinhead", "many"]).assert().code(2);
}

#[test]
fn help_shows_examples() {
    scene()
        .args(["environment", "--help"])
        .assert()
        .success()
        .stdout(predicate::str::contains(
            "scene environment --polygons 1024 --clipped 0.5",
        ));
}

#[test]
fn mesh_and_sphere_sizes() {
    let frames = frames_of(
        &scene()
            .args(["mesh", "--cols", "5", "--rows", "4"])
            .output()
            .unwrap()
            .stdout,
    );
    assert_eq!(frames[0].len(), 20);
    let frames = frames_of(
        &scene()
            .args(["sphere", "--stacks", "3", "--slices", "5", "--radius", "2"])
            .output()
            .unwrap()
            .stdout,
    );
    // Two polar bands of triangles, one band of quads.
    let arities: Vec<usize> = frames[0].iter().map(|p| p.vertices.len()).collect();
    assert_eq!(arities, [3, 3, 3, 3, 3, 4, 4, 4, 4, 4, 3, 3, 3, 3, 3]);
    for p in &frames[0] {
        for v in &p.vertices {
            assert!((v.truncate().length() - 2.0).abs() < 1e-12);
        }
    }
}

// ---- OBJ ----

const MTL: &str = "newmtl red\nKd 1 0 0\nnewmtl half\nKd 0.5 0.25 1\n";

/// Quads, a pentagon, negative indices, two materials and a face before any material.
const OBJ: &str = "mtllib scene.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0.5 1.5 0
f 1 2 3 4
usemtl red
f 1 2 3 5 4
f -5 -4 -3
usemtl half
f -1 -2 -3 -4
";

#[test]
fn obj_faces_and_materials() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("scene.mtl"), MTL).unwrap();
    let obj = dir.path().join("scene.obj");
    fs::write(&obj, OBJ).unwrap();
    scene()
        .args(["obj", "--no-fit", "--text"])
        .arg(&obj)
        .assert()
        .success()
        .stderr("")
        .stdout(
            "polypipe 1 world\n\
             colour 200 200 200\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n\
             NEXT.POLYGON\ncolour 255 0 0\n0 0 0\n1 0 0\n1 1 0\n0.5 1.5 0\n0 1 0\n\
             NEXT.POLYGON\ncolour 255 0 0\n0 0 0\n1 0 0\n1 1 0\n\
             NEXT.POLYGON\ncolour 128 64 255\n0.5 1.5 0\n0 1 0\n1 1 0\n1 0 0\n\
             END\n",
        );
}

#[test]
fn obj_from_stdin_looks_for_materials_in_the_current_folder() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("scene.mtl"), MTL).unwrap();
    let out = scene()
        .current_dir(dir.path())
        .args(["obj", "--no-fit", "-"])
        .write_stdin(OBJ)
        .output()
        .unwrap();
    assert!(out.status.success());
    let colours: Vec<_> = frames_of(&out.stdout)[0].iter().map(|p| p.colour).collect();
    assert_eq!(
        colours,
        [[200, 200, 200], [255, 0, 0], [255, 0, 0], [128, 64, 255]]
    );
}

#[test]
fn obj_missing_mtl_warns_and_uses_default_colours() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("scene.obj");
    fs::write(&obj, OBJ).unwrap();
    let out = scene()
        .args(["obj", "--no-fit"])
        .arg(&obj)
        .output()
        .unwrap();
    assert!(out.status.success());
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.starts_with("scene: warning: cannot read material library "),
        "{stderr}"
    );
    assert!(stderr.contains("scene.mtl"), "{stderr}");
    let frames = frames_of(&out.stdout);
    assert!(frames[0].iter().all(|p| p.colour == [200, 200, 200]));
    assert_eq!(frames[0].len(), 4);
}

#[test]
fn obj_fit_puts_the_model_in_view() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("far.obj");
    fs::write(
        &obj,
        "v 100 100 100\nv 140 100 100\nv 140 130 100\nf 1 2 3\n",
    )
    .unwrap();
    let out = scene().args(["obj"]).arg(&obj).output().unwrap();
    let frames = frames_of(&out.stdout);
    let v = &frames[0][0].vertices;
    // Bounding box centred on the origin, bounding-sphere radius 8 about its centre.
    assert_eq!(v[0].truncate(), proto::DVec3::new(-6.4, -4.8, 0.0));
    assert_eq!(v[2].truncate(), proto::DVec3::new(6.4, 4.8, 0.0));
}

#[test]
fn obj_shade_lights_faces_by_their_normal() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("facing.obj");
    // A face whose normal is +z: |n·l| = 2/√7.25 for l = (1, 1.5, 2)/|…|.
    fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let out = scene()
        .args(["obj", "--shade", "--no-fit"])
        .arg(&obj)
        .output()
        .unwrap();
    let k = 0.3 + 0.7 * 2.0 / 7.25f64.sqrt();
    let c = (200.0 * k).round() as u8;
    assert_eq!(frames_of(&out.stdout)[0][0].colour, [c, c, c]);
    assert_eq!(c, 164);
}

/// `--gouraud`: the stream says `vertex-colours`, and each vertex is lit by its normal:
/// a flat triangle's three corners all get the face's Lambert colour, and a crease angle
/// outside 0–180 is refused.
#[test]
fn obj_gouraud_lights_each_vertex_by_its_normal() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("facing.obj");
    fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let out = scene()
        .args(["obj", "--gouraud", "--no-fit"])
        .arg(&obj)
        .output()
        .unwrap();
    assert!(out.status.success());
    let reader = Reader::<Token, _>::new(&out.stdout[..]).unwrap();
    assert!(reader.header().attributes.vertex_colours);
    let k = 0.3 + 0.7 * 2.0 / 7.25f64.sqrt();
    let polygon = &frames_of(&out.stdout)[0][0];
    assert_eq!(polygon.vertex_attrs.len(), 3);
    for c in &polygon.vertex_attrs {
        assert!(
            (c.x - 200.0 * k).abs() < 1e-9 && c.x == c.y && c.y == c.z,
            "{c:?}"
        );
    }
    scene()
        .args(["obj", "--gouraud", "--crease", "200"])
        .arg(&obj)
        .assert()
        .code(2)
        .stderr(predicate::str::contains(
            "`200` is not an angle from 0 to 180 degrees",
        ));
}

/// `--light` (repeatable) and `--ambient` replace the default light: a face of normal
/// +z under a light towards +z of intensity 0.5 and one towards -z of 0.25 (lighting is
/// two-sided), ambient 0.1, is lit by 0.1 + 0.5 + 0.25 = 0.85, flat and per vertex.
#[test]
fn obj_lights_and_ambient_are_the_users() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("facing.obj");
    fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let lights = [
        "--light",
        "0,0,1,0.5",
        "--light",
        "-0,0,-2,0.25", // a value may start with a minus
        "--ambient",
        "0.1",
    ];
    let out = scene()
        .args(["obj", "--shade", "--no-fit"])
        .args(lights)
        .arg(&obj)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(frames_of(&out.stdout)[0][0].colour, [170, 170, 170]);
    let out = scene()
        .args(["obj", "--gouraud", "--no-fit"])
        .args(lights)
        .arg(&obj)
        .output()
        .unwrap();
    for c in &frames_of(&out.stdout)[0][0].vertex_attrs {
        assert!((c.x - 170.0).abs() < 1e-9, "{c:?}");
    }
    for (light, message) in [
        ("0,0,0", "a light needs a direction, not 0,0,0"),
        ("0,0,1,-1", "the intensity -1 must be 0 or more"),
    ] {
        scene()
            .args(["obj", "--shade", "--light", light])
            .arg(&obj)
            .assert()
            .code(2)
            .stderr(predicate::str::contains(message));
    }
}

#[test]
fn obj_errors() {
    scene()
        .args(["obj", "/nonexistent/x.obj"])
        .assert()
        .code(3)
        .stderr(predicate::str::starts_with(
            "scene: cannot open /nonexistent/x.obj",
        ));
    scene()
        .args(["obj", "-"])
        .write_stdin("v 0 0 0\nf 1 2 3\n")
        .assert()
        .code(1)
        .stderr(
            "scene: <stdin>: line 2: face `f 1 2 3`: vertex index 2 is out of bounds (the file has 1 vertex)\n",
        );
    // What the line check does not catch is tobj's to say, without a line.
    scene()
        .args(["obj", "-"])
        .write_stdin("v 0 0 0 0\n")
        .assert()
        .code(1)
        .stderr(predicate::str::starts_with(
            "scene: <stdin>: not a valid OBJ file: ",
        ));
}

#[test]
fn example_scenes_are_valid_world_streams() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples");
    let mut n = 0;
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "txt") {
            let frames = frames_of(&fs::read(&path).unwrap());
            assert!(!frames[0].is_empty(), "{}", path.display());
            n += 1;
        }
    }
    assert!(n >= 5);
}

/// `--phong`: the stream says `vertex-normals` and carries the lighting in its header
/// (the user's lights, ambient, highlight and viewer); each vertex carries its normal
/// (the file's `vn` here) and the polygon its base colour, unlit.
#[test]
fn obj_phong_sends_normals_and_the_lighting() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("normals.obj");
    fs::write(
        &obj,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0 0.6 0.8\nf 1//1 2//2 3//1\n",
    )
    .unwrap();
    let out = scene()
        .args([
            "obj",
            "--phong",
            "--no-fit",
            "--text",
            "--light",
            "0,0,2,0.5",
        ])
        .args([
            "--ambient",
            "0.1",
            "--specular",
            "0.4,12",
            "--viewer",
            "0,1,0",
        ])
        .arg(&obj)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        String::from_utf8(out.stdout.clone()).unwrap(),
        "polypipe 1 world vertex-normals ambient 0.1 light 0 0 1 0.5 specular 0.4 12 \
         viewer 0 1 0\n\
         colour 200 200 200\n\
         0 0 0 0 0 1\n\
         1 0 0 0 0.6 0.8\n\
         0 1 0 0 0 1\n\
         END\n"
    );
    for (args, message) in [
        (&["--phong", "--gouraud"][..], "cannot be used with"),
        (&["--phong", "--shade"][..], "cannot be used with"),
        (
            &["--phong", "--specular", "1,0.5"][..],
            "the exponent 0.5 must be 1 or more",
        ),
        (
            &["--phong", "--viewer", "0,0,0"][..],
            "the viewer needs a direction",
        ),
    ] {
        scene()
            .arg("obj")
            .args(args)
            .arg(&obj)
            .assert()
            .code(2)
            .stderr(predicate::str::contains(message));
    }
    // Nine lights are one too many for the header.
    let mut nine = scene();
    nine.args(["obj", "--phong"]);
    for _ in 0..9 {
        nine.args(["--light", "1,0,0"]);
    }
    nine.arg(&obj)
        .assert()
        .code(2)
        .stderr(predicate::str::contains("9 lights: a lighting has 1 to 8"));
}

/// `scene sphere --phong`: the sphere's own normals (from its centre), one a vertex, of
/// unit length; `--gouraud` and `--phong` with a highlight agree where a vertex is lit.
#[test]
fn sphere_phong_normals_are_the_spheres() {
    let out = scene()
        .args([
            "sphere", "--stacks", "4", "--slices", "6", "--phong", "--radius", "5",
        ])
        .output()
        .unwrap();
    assert!(out.status.success());
    let reader = Reader::<Token, _>::new(&out.stdout[..]).unwrap();
    assert!(reader.header().attributes.vertex_normals);
    for polygon in &frames_of(&out.stdout)[0] {
        assert_eq!(polygon.colour, [220, 120, 60]);
        assert_eq!(polygon.vertex_attrs.len(), polygon.vertices.len());
        for (n, v) in polygon.vertex_attrs.iter().zip(&polygon.vertices) {
            assert!((n.length() - 1.0).abs() < 1e-12);
            assert!((v.truncate() / 5.0 - *n).length() < 1e-12, "{n:?} at {v:?}");
        }
    }
}

/// `scene spheres --phong` and `--gouraud`: each sphere's normals point from its own
/// centre, not from the origin the movie turns about.
#[test]
fn spheres_normals_point_from_each_spheres_centre() {
    let out = scene()
        .args(["spheres", "--stacks", "4", "--slices", "6", "--phong"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let centres = [
        (proto::DVec3::new(-3.5, 0.0, -1.0), 6.0),
        (proto::DVec3::new(3.5, 0.5, 1.0), 5.0),
    ];
    let polygons = &frames_of(&out.stdout)[0];
    assert_eq!(polygons.len(), 2 * 4 * 6);
    for (k, polygon) in polygons.iter().enumerate() {
        let (centre, radius) = centres[k / 24];
        for (n, v) in polygon.vertex_attrs.iter().zip(&polygon.vertices) {
            assert!(
                ((v.truncate() - centre) / radius - *n).length() < 1e-12,
                "{k}"
            );
        }
    }
    let gouraud = scene()
        .args(["spheres", "--stacks", "4", "--slices", "6", "--gouraud"])
        .output()
        .unwrap();
    let reader = Reader::<Token, _>::new(&gouraud.stdout[..]).unwrap();
    assert!(reader.header().attributes.vertex_colours);
}
