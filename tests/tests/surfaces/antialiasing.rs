//! The anti-aliasing leaves, `supersample --samples K` and `abuf`, through the pipeline
//! (docs/DESIGN.md, "Anti-aliasing" and "Measures"): supersampling equals its exact
//! reference `zspec --samples K`; both cut the edge-pixel error against `zspec --samples
//! 16` to at most a quarter of point sampling's, at tree depth 0 and 2; frames are byte
//! for byte the same at every tree depth; two white triangles sharing an edge show no seam.

use pipeline_tests::{parse_ppm_stream, run, sh};
use std::path::Path;

const SIZE: &str = "64x48";

/// The scenes: a random environment (thesis 5.2), a sphere, the thesis's penetrating
/// polygons, and needle-thin triangles, as world-space files in `dir`.
fn scenes(dir: &Path) -> Vec<(&'static str, String)> {
    let env = dir.join("environment.pp");
    run(&format!(
        "scene environment --polygons 200 --seed 7 > {}",
        env.display()
    ));
    let sphere = dir.join("sphere.pp");
    run(&format!(
        "scene sphere --stacks 8 --slices 12 > {}",
        sphere.display()
    ));
    let needles = dir.join("needles.txt");
    std::fs::write(&needles, needles_scene()).unwrap();
    vec![
        ("environment", env.display().to_string()),
        ("sphere", sphere.display().to_string()),
        ("penetrating", "examples/penetrating.txt".to_string()),
        ("needles", needles.display().to_string()),
    ]
}

/// Triangles about half a pixel wide at their base, tapering to a point 20 world units
/// away, at many slopes: point sampling breaks them into dashes.
fn needles_scene() -> String {
    let mut s = String::from("polypipe 1 world\n");
    for i in 0..24 {
        if i > 0 {
            s.push_str("NEXT.POLYGON\n");
        }
        let x = -11.0 + i as f64 * 0.93;
        let lean = (i % 7) as f64 - 3.0;
        let colour = [255 - i * 8, 60 + i * 7, 40 + i * 9];
        s.push_str(&format!(
            "colour {} {} {}\n{x} -10 {z}\n{} -10 {z}\n{} 10 {z}\n",
            colour[0],
            colour[1],
            colour[2],
            x + 0.25,
            x + lean,
            z = (i % 5) as f64 - 2.0,
        ));
    }
    s.push_str("END\n");
    s
}

/// The frame of `scene` rendered through a splitter tree of `depth` built by hand as
/// render.sh's start_tree builds it (`splitter --node K --depth N`), each leaf
/// `persp | METHOD`, the leaves merged by zbuf.
fn render(scene: &str, depth: u32, method: &str) -> Vec<u8> {
    run(&format!(
        r#"d=$(mktemp -d); trap 'rm -rf "$d"' EXIT
viewxf --size {SIZE} < {scene} | clipbatch > "$d/node-1"
for ((n = 1; n < 1 << {depth}; n++)); do
    splitter --node $n --depth {depth} --size {SIZE} "$d/node-$((2 * n))" "$d/node-$((2 * n + 1))" < "$d/node-$n"
done
leaves=()
for ((l = 0; l < 1 << {depth}; l++)); do
    persp --size {SIZE} < "$d/node-$(((1 << {depth}) + l))" | {method} > "$d/leaf-$l"
    leaves+=("$d/leaf-$l")
done
zbuf "${{leaves[@]}}""#
    ))
}

/// The edge-pixel RMSE of `frame` against `zspec --samples 16` of `scene`.
fn edge_rmse(dir: &Path, scene: &str, frame: &[u8]) -> f64 {
    let (reference, mask, out) = (
        dir.join("ref16.ppm"),
        dir.join("edges.ppm"),
        dir.join("out.ppm"),
    );
    run(&format!(
        "zspec --size {SIZE} --samples 16 --edge-mask {} < {scene} > {}",
        mask.display(),
        reference.display()
    ));
    std::fs::write(&out, frame).unwrap();
    let report = String::from_utf8(run(&format!(
        "zspec compare --metrics --edges {} {} {}",
        mask.display(),
        reference.display(),
        out.display()
    )))
    .unwrap();
    let overall = report
        .lines()
        .find(|l| l.starts_with("overall"))
        .unwrap_or_else(|| panic!("no overall line in {report}"));
    let words: Vec<&str> = overall.split_whitespace().collect();
    let at = words.iter().position(|w| *w == "edge_rmse").unwrap();
    words[at + 1].parse().unwrap()
}

#[test]
fn supersampling_equals_its_exact_reference() {
    let dir = tempfile::tempdir().unwrap();
    for (name, scene) in scenes(dir.path()) {
        for k in [2, 4, 8, 16] {
            let got = render(&scene, 0, &format!("supersample --samples {k}"));
            let want = run(&format!("zspec --size {SIZE} --samples {k} < {scene}"));
            let (got, want) = (
                parse_ppm_stream(&got).unwrap(),
                parse_ppm_stream(&want).unwrap(),
            );
            let differing = got[0]
                .pixels
                .iter()
                .zip(&want[0].pixels)
                .filter(|(a, b)| a != b)
                .count();
            assert_eq!(differing, 0, "{name}, K = {k}");
        }
    }
}

#[test]
fn edge_error_is_at_most_a_quarter_of_point_samplings() {
    let dir = tempfile::tempdir().unwrap();
    for (name, scene) in scenes(dir.path()) {
        for depth in [0, 2] {
            let point = edge_rmse(
                dir.path(),
                &scene,
                &render(&scene, depth, "scanconv --resolve"),
            );
            assert!(
                point > 5.0,
                "{name}: point sampling's edge RMSE only {point}"
            );
            for method in ["abuf", "supersample --samples 4"] {
                let e = edge_rmse(dir.path(), &scene, &render(&scene, depth, method));
                assert!(
                    e <= point / 4.0,
                    "{name} at depth {depth}: {method} edge RMSE {e}, point sampling {point}"
                );
            }
        }
    }
}

#[test]
fn frames_are_the_same_at_every_tree_depth() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = scenes(dir.path());
    for method in [
        "abuf",
        "supersample --samples 2",
        "supersample --samples 4",
        "supersample --samples 8",
        "supersample --samples 16",
        "supersample --samples 4 --adaptive",
    ] {
        for (name, scene) in &scenes[..3] {
            let base = render(scene, 0, method);
            for depth in 1..=4 {
                assert!(
                    render(scene, depth, method) == base,
                    "{name}: {method} at depth {depth} differs from depth 0"
                );
            }
        }
    }
}

#[test]
fn two_white_triangles_sharing_an_edge_show_no_seam() {
    // A square of two triangles, its diagonal from corner to corner, on black.
    let scene = "polypipe 1 world\ncolour 255 255 255\n-10 -10 0\n10 -10 0\n-10 10 0\n\
                 NEXT.POLYGON\ncolour 255 255 255\n10 -10 0\n10 10 0\n-10 10 0\nEND\n";
    for method in ["abuf", "supersample --samples 4"] {
        let out = sh(
            &format!("viewxf --size 32x32 | clipbatch | persp --size 32x32 | {method} | zbuf"),
            scene.as_bytes(),
        );
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let frame = &parse_ppm_stream(&out.stdout).unwrap()[0];
        // The square spans X, Y from 3.2 to 28.8: pixels 4..28 are inside it, the
        // diagonal's among them.
        for y in 4..28 {
            for x in 4..28 {
                let p = frame.at(x, y);
                assert!(
                    p.iter().all(|&c| c >= 252),
                    "{method}: pixel ({x}, {y}) is {p:?}"
                );
            }
        }
        // The square's own border is anti-aliased: its edge X = 3.2 leaves 6 of pixel 3's
        // 8 sample columns (3 of 4) covered.
        assert_eq!(frame.at(3, 16), [191; 3], "{method}");
    }
}

#[test]
fn bad_samples_and_bad_input_are_refused() {
    let out = sh("supersample --samples 3 < /dev/null", b"");
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "supersample: invalid value '3' for '--samples <K>': `3` is not 1, 2, 4, 8 or 16\n"
    );
    for method in ["abuf", "supersample --samples 4"] {
        let out = sh(method, b"polypipe 1 screen 4 4\ncolour 1 2\n");
        assert_eq!(out.status.code(), Some(1), "{method}");
        assert!(!out.stderr.is_empty());
        let out = sh(&format!("{method} --background 1,2"), b"");
        assert_eq!(out.status.code(), Some(2), "{method}");
    }
}

#[test]
fn abuf_stats_count_the_fragments() {
    // One square over 2×2 pixels, wholly covering them: four simple pixelstructs.
    let out = sh(
        "abuf --stats --text",
        b"polypipe 1 screen 4 4\ncolour 9 9 9\n1 1 0.5\n3 1 0.5\n3 3 0.5\n1 3 0.5\nEND\n",
    );
    assert!(out.status.success());
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "abuf: 1 polygons in, 1 frames, 2 runs out, 4 fragments, 4 simple, 0 lists, max list \
         length 0, 0 combined, 0 hidden, 0 intersect cases, 0 merged past 64 a list, 0 polygon \
         rows, 0 blocks and 0 pixels culled, 4 pixels out\n\
         @stats abuf polygons_in=1 frames=1 runs_out=2 fragments=4 simple=4 lists=0 max_list=0 \
         combined=0 hidden=0 intersections=0 merged=0 merge_limit=64 rows_culled=0 \
         blocks_culled=0 pixels_culled=0 pixels_out=4\n"
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("run 1 1 3 9 9 9"));
}

/// `scripts/render.sh --aa MODE` as a user runs it: every mode gives the same bytes at
/// depths 0-4 (the tree's cuts are on pixel boundaries, so each pixel's samples are all in
/// one leaf), and `ssK` is byte for byte `zspec --samples K` of the same view.
#[test]
fn render_sh_aa_is_the_same_at_every_depth_and_ss_k_is_its_reference() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("env.pp");
    run(&format!(
        "scene environment --polygons 300 --frames 2 --size 96x64 --seed 5 > {}",
        scene.display()
    ));
    let s = scene.display();
    for mode in ["ss2", "ss4", "ss8", "ss16", "abuf"] {
        let at0 = run(&format!("scripts/render.sh --size 96x64 --aa {mode} {s}"));
        assert_eq!(parse_ppm_stream(&at0).unwrap().len(), 2);
        for depth in 1..=4 {
            let deeper = run(&format!(
                "scripts/render.sh --size 96x64 --aa {mode} --depth {depth} {s}"
            ));
            assert!(
                deeper == at0,
                "--aa {mode} --depth {depth} differs from depth 0"
            );
        }
        if let Some(k) = mode.strip_prefix("ss") {
            let reference = run(&format!("zspec --size 96x64 --samples {k} {s}"));
            assert!(at0 == reference, "--aa {mode} is not zspec --samples {k}");
        }
    }
    let point = run(&format!("scripts/render.sh --size 96x64 {s}"));
    let abuf = run(&format!("scripts/render.sh --size 96x64 --aa abuf {s}"));
    assert!(point != abuf, "the a-buffer changes the edge pixels");
}

#[test]
fn render_sh_refuses_aa_with_another_method_or_the_one_zbuffer() {
    for (options, message) in [
        (
            "--aa ss3",
            "render: --aa must be none, abuf, ss2, ss4, ss8, ss16, adaptive2, adaptive4, \
             adaptive8 or adaptive16, not 'ss3'",
        ),
        (
            "--aa abuf --hse warnock",
            "render: --aa abuf is a z-buffer's anti-aliasing: not with --hse warnock",
        ),
        (
            "--aa ss4 --merge buffer",
            "render: --merge buffer is the z-buffer's, point-sampled: not with --hse zbuf --aa ss4",
        ),
    ] {
        let out = sh(&format!("scripts/render.sh {options}"), b"");
        assert_eq!(out.status.code(), Some(2), "{options}");
        assert_eq!(
            String::from_utf8(out.stderr).unwrap().lines().next(),
            Some(message),
            "{options}"
        );
    }
}

/// `render --aa adaptiveK` as a user runs it: on flat scenes (the 1,024-quad environment,
/// the intersecting spheres, the penetrating polygons) byte for byte `--aa ssK` at tree
/// depths 0 and 2, at 500×500, with K×K samples in a few pixels only.
#[test]
fn adaptive_is_ss_byte_for_byte_on_flat_scenes() {
    let dir = tempfile::tempdir().unwrap();
    let env = dir.path().join("environment.pp");
    run(&format!(
        "scene environment --polygons 1024 --clipped 0.5 --depth-complexity 1 --seed 1 \
         --size 500x500 > {}",
        env.display()
    ));
    let spheres = dir.path().join("spheres.pp");
    run(&format!("scene spheres > {}", spheres.display()));
    let scenes = [
        ("environment", env.display().to_string()),
        ("spheres", spheres.display().to_string()),
        ("penetrating", "examples/penetrating.txt".to_string()),
    ];
    for (name, scene) in &scenes {
        for k in [4, 16] {
            let ss = run(&format!(
                "scripts/render.sh --size 500x500 --aa ss{k} {scene}"
            ));
            for depth in [0, 2] {
                let adaptive = run(&format!(
                    "scripts/render.sh --size 500x500 --aa adaptive{k} --depth {depth} {scene}"
                ));
                assert!(
                    adaptive == ss,
                    "{name}: adaptive{k} at depth {depth} is not ss{k}"
                );
            }
        }
    }
    // The environment's leaf samples K×K in a few of the pixels it sends.
    let out = sh(
        &format!(
            "viewxf --size 500x500 < {} | clipbatch | persp --size 500x500 \
             | supersample --samples 4 --adaptive --stats > /dev/null",
            scenes[0].1
        ),
        b"",
    );
    let stats = String::from_utf8_lossy(&out.stderr);
    let count = |key: &str| pipeline_tests::stat(&stats, key);
    let (pixels, sampled) = (count("pixels_out"), count("sampled"));
    assert!(
        sampled * 5 < pixels,
        "{sampled} of {pixels} pixels sampled: {stats}"
    );
}

/// Shaded scenes: Gouraud's pixels within one level of `--aa ss4`'s in every channel (the
/// central 2×2 samples of an affine colour), Phong's byte for byte (every sample lit),
/// even with a highlight a few pixels wide.
#[test]
fn adaptive_shading_is_within_a_level_of_ss() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a.ppm"), dir.path().join("b.ppm"));
    for (options, most) in [
        ("--gouraud", 1),
        ("--gouraud --stacks 4 --slices 6 --specular 1,50", 1),
        ("--phong --specular 1,1000 --radius 3", 0),
    ] {
        for k in [4, 16] {
            run(&format!(
                "scene sphere {options} | scripts/render.sh --size 300x300 --aa ss{k} - > {}",
                a.display()
            ));
            run(&format!(
                "scene sphere {options} | scripts/render.sh --size 300x300 --aa adaptive{k} \
                 --depth 2 - > {}",
                b.display()
            ));
            let report = sh(
                &format!("zspec compare --metrics {} {}", a.display(), b.display()),
                b"",
            );
            let text = String::from_utf8_lossy(&report.stdout).to_string()
                + &String::from_utf8_lossy(&report.stderr);
            let overall = text
                .lines()
                .find(|l| l.starts_with("overall"))
                .unwrap_or_else(|| panic!("no overall line in {text}"));
            let words: Vec<&str> = overall.split_whitespace().collect();
            let at = words.iter().position(|w| *w == "max").unwrap();
            let max: u32 = words[at + 1].parse().unwrap();
            assert!(max <= most, "{options}, K = {k}: {overall}");
            if most == 1 {
                assert!(
                    overall.contains(" differing ") && !overall.contains(" differing 0 "),
                    "{options}: {overall}"
                );
            }
        }
    }
}

/// `render --aa ss4` gave `scene planes 10` one pixel unlike `zspec --samples 4` (8
/// levels), `planes 50` eight: where two crossing planes' depths at a sample were within
/// the tie rule's 2⁻³⁰, ss4 kept the earlier polygon (the tie rule) and zspec's
/// supersampled reference took the nearer (a strict `<`; its pixel-centre frame has the
/// tie rule). Both now decide every sample by `proto::depth::takes`. Each case below has
/// such a sample: with the strict `<` back in zspec, 1, 1 and 3 pixels differ (planes 10
/// at ss16 on 200×200 had none).
#[test]
fn ss_k_is_zspec_samples_k_byte_for_byte_on_crossing_planes() {
    for (n, k, size) in [(10, 4, "500x500"), (50, 4, "100x100"), (50, 16, "80x80")] {
        let exact = sh(
            &format!("scene planes {n} | zspec --samples {k} --size {size}"),
            b"",
        );
        assert!(exact.status.success());
        for depth in [0, 2] {
            let drawn = sh(
                &format!("scene planes {n} | render --depth {depth} --aa ss{k} --size {size} -"),
                b"",
            );
            assert!(drawn.status.success());
            assert!(
                drawn.stdout == exact.stdout,
                "planes {n}, ss{k}, depth {depth}: not zspec's bytes"
            );
        }
    }
}

/// Memory is bounded by a row, not the finer screen: at K = 16 on 600×600 the K·W × K·H
/// screen is 92 million samples (over 1 GB at 12 bytes a sample); `supersample` (whole
/// and adaptive) and `abuf` on two full-screen planes crossing stay under 64 MB of
/// resident memory (/usr/bin/time's maximum resident set).
#[test]
fn memory_is_a_rows_not_the_finer_screens() {
    for leaf in [
        "supersample --samples 16",
        "supersample --samples 16 --adaptive",
        "abuf",
    ] {
        let out = sh(
            &format!(
                "set -e; d=$(mktemp -d); trap 'rm -rf \"$d\"' EXIT
                 scene planes 2 | viewxf | clipbatch | persp --size 600x600 > \"$d/in\"
                 /usr/bin/time -f %M -o \"$d/rss\" {leaf} < \"$d/in\" > \"$d/out\"
                 test -s \"$d/out\"
                 cat \"$d/rss\""
            ),
            b"",
        );
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "{leaf}: {stdout}{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let kib: u64 = stdout.trim().parse().expect("peak RSS in KiB");
        assert!(kib < 64 * 1024, "{leaf}: {kib} KiB");
    }
}
