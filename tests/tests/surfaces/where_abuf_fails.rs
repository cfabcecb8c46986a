//! Where Carpenter's a-buffer (`abuf`) fails or pays, each symptom measured and held to a
//! bound: pixels wrong where the packer takes two fragments whose depth extents overlap
//! for planes crossing inside the pixel (the seed's own method, kept); fragments made for
//! every covering polygon at every pixel on crossing planes, nearly all thrown away
//! (the z-buffer writes a pixel once a nearer polygon); and the list a pixel, capped at
//! the 64 samples, on polygons piled in one pixel (docs/methods.md, "abuf").

use pipeline_tests::{parse_ppm_stream, sh, stat};

/// abuf's `--stats` line for `scene ARGS` at 200×200.
fn abuf_stats(scene: &str) -> String {
    let out = sh(
        &format!(
            "scene {scene} | viewxf --size 200x200 | clipbatch | persp --size 200x200 \
             | abuf --stats > /dev/null"
        ),
        b"",
    );
    let stats = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{scene}: {stats}");
    stats
}

#[test]
fn a_plane_crossing_just_outside_an_edge_takes_samples_it_is_behind_on() {
    // examples/screen/abuf-depth-extent.txt: a flat red rectangle ends at X = 7.5; a
    // steep green plane crosses its depth at X = 7.55, behind it wherever both cover.
    // Column 7 holds both, with depth extents that overlap, so the packer splits the
    // samples as if they crossed there: 48 levels of red too few on all 16 rows, against
    // the 8×8 supersampled picture (`supersample --samples 8`, zspec's to the byte).
    let frames = |leaf: &str| {
        let out = sh(
            &format!("{leaf} < examples/screen/abuf-depth-extent.txt | zbuf"),
            b"",
        );
        assert!(out.status.success(), "{leaf}");
        parse_ppm_stream(&out.stdout).expect("PPM").remove(0)
    };
    let (abuf, reference) = (frames("abuf"), frames("supersample --samples 8"));
    let mut wrong = Vec::new();
    for y in 0..16 {
        for x in 0..16 {
            if abuf.at(x, y) != reference.at(x, y) {
                wrong.push((x, y, abuf.at(x, y), reference.at(x, y)));
            }
        }
    }
    let want: Vec<_> = (0..16)
        .map(|y| (7, y, [100, 155, 40], [148, 120, 40]))
        .collect();
    assert_eq!(wrong, want);
}

#[test]
fn crossing_planes_make_a_fragment_for_every_plane_at_every_pixel() {
    // `scene planes N` at 200×200: every plane covers every pixel and no order holds
    // across the screen, so the a-buffer makes about N fragments a pixel and throws
    // nearly all of them away behind a covering one (6.3.5): the cost is N·pixels where
    // the z-buffer's is the pixels a nearer polygon wins. Measured: 948,380 fragments
    // for 50 planes, 1,875,575 for 100, 3,733,933 for 200; 85%, 86%, 86% thrown away.
    let stats: Vec<String> = [50, 100, 200]
        .map(|n| abuf_stats(&format!("planes {n}")))
        .into();
    let pixels = 200.0 * 200.0;
    for (n, s) in [50.0, 100.0, 200.0].iter().zip(&stats) {
        let fragments = stat(s, "fragments") as f64;
        // Most planes reach the screen's every pixel: between 0.4·N and N a pixel.
        assert!(
            (0.4 * n * pixels..=n * pixels).contains(&fragments),
            "{n} planes: {s}"
        );
        let hidden = stat(s, "hidden") as f64;
        assert!(hidden > 0.8 * fragments, "{n} planes: {s}");
        // The list stays within the samples of a pixel.
        assert!(stat(s, "max_list") <= 64, "{n} planes: {s}");
    }
    // Twice the planes, twice the fragments: linear in N, each a pixel's worth.
    for k in 0..2 {
        let grew = stat(&stats[k + 1], "fragments") as f64 / stat(&stats[k], "fragments") as f64;
        assert!((1.8..2.2).contains(&grew), "{stats:?}");
    }
}

#[test]
fn a_pinhead_keeps_one_list_of_64_fragments() {
    // 20,000 triangles around one pixel centre, at 20,000 depths: one list, which the
    // seed's combining never shortens (no two are of one surface, none covers the
    // pixel). Capped at 64 fragments, its two farthest merged as each new one comes:
    // 19,927 merges (measured), the list's length and its time bounded.
    let stats = abuf_stats("pinhead 20000");
    assert_eq!(stat(&stats, "max_list"), 64, "{stats}");
    assert_eq!(stat(&stats, "lists"), 1, "{stats}");
    let merged = stat(&stats, "merged");
    let fragments = stat(&stats, "fragments");
    assert!(
        fragments > 19_000 && merged + 64 >= fragments,
        "{fragments} fragments, {merged} merged: {stats}"
    );
}
