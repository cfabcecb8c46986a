//! Where Watkins's scan-line method (`scanline`) pays, each cost measured and held to a
//! bound: its tables on a frame of many polygons active at once (memory linear in the
//! polygons: the active polygons' edges share one table), and its depth comparisons
//! where planes cross everywhere (Newman and Sproull, 14.4.3: the computation grows with
//! the *visible* complexity, here the crossings of every line). The pictures stay the
//! z-buffer leaf's to the byte.

use pipeline_tests::{leaf_stats_drawing_as_zbuf, sh, stat};

#[test]
fn two_hundred_thousand_pinhead_triangles_fit_in_256_mb() {
    // 200,000 triangles inside one pixel, all active on the same lines: each used to
    // keep an Edge Table and an Active Edge Table of its own (358 MB peak); in one shared
    // table they take 105 MB (measured, /usr/bin/time's maximum resident set). The
    // frame is the z-buffer leaf's, byte for byte.
    let out = sh(
        "set -e; d=$(mktemp -d); trap 'rm -rf \"$d\"' EXIT
         scene pinhead 200000 | viewxf | clipbatch | persp --size 500x500 > \"$d/in\"
         /usr/bin/time -f %M -o \"$d/rss\" scanline < \"$d/in\" > \"$d/scanline\"
         scanconv --resolve < \"$d/in\" > \"$d/zbuf\"
         cmp \"$d/scanline\" \"$d/zbuf\"
         cat \"$d/rss\"",
        b"",
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let kib: u64 = stdout.trim().parse().expect("peak RSS in KiB");
    assert!(kib < 256 * 1024, "{kib} KiB");
}

#[test]
fn crossing_planes_cost_comparisons_growing_with_the_crossings() {
    // `scene planes N` at 200×200: every pair of planes crosses, and the front changes
    // along every line. Each crossing column is computed from the two depth lines
    // (XINTER) and settled by the tie rule at the centres beside it: none searched.
    let stats = |n: u32| leaf_stats_drawing_as_zbuf("scanline", &format!("planes {n}"), 200);
    let s50 = stats(50);
    assert_eq!(stat(&s50, "crossings"), 3434, "{s50}");
    assert_eq!(stat(&s50, "crossings_computed"), 1849, "{s50}");
    assert_eq!(stat(&s50, "crossings_searched"), 0, "{s50}");
    assert_eq!(stat(&s50, "depth_comparisons"), 715_384, "{s50}");
    // Twice the planes, nearly twice the crossings (6,409) and 3.4 times the depth
    // comparisons (2,439,223): the sample spans hold every plane, and each crossing
    // is looked for among all of them.
    let s100 = stats(100);
    assert_eq!(stat(&s100, "crossings"), 6409, "{s100}");
    assert_eq!(stat(&s100, "crossings_searched"), 0, "{s100}");
    let ratio = stat(&s100, "depth_comparisons") as f64 / 715_384.0;
    assert!((3.0..4.0).contains(&ratio), "{ratio}");
}
