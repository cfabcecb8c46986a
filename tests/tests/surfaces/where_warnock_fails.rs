//! Where Warnock's area subdivision (`warnock`) pays, each cost measured on the scenes
//! `scene` makes and held to a bound: its windows follow the picture's edges, not its
//! pixels or its polygons (Newman and Sproull, 14.3.4: the work follows the *visible*
//! complexity), so a deep stack is one window while slivers take a pixel window for
//! nearly every visible segment. The method is exact: every frame here is the
//! z-buffer leaf's, byte for byte. The small hand-made cases (the Thinker's failures, a
//! crossing subdivided to pixels) are in `warnock.rs`, `where_it_slows` and `hostile`.

use pipeline_tests::{leaf_stats_drawing_as_zbuf, stat, stat_list};

/// Warnock's `--stats` line for `scene ARGS` at `size`×`size`, its runs the z-buffer
/// leaf's byte for byte.
fn warnock_stats(scene: &str, size: u32) -> String {
    leaf_stats_drawing_as_zbuf("warnock", scene, size)
}

/// The windows at each level of the subdivision, from the stats record.
fn windows_by_depth(stats: &str) -> Vec<u64> {
    stat_list(stats, "windows_by_depth")
}

#[test]
fn windows_grow_with_the_edges_not_the_pixels() {
    // Archuleta's two spheres (1,024 polygons) at 250, 500 and 1,000 pixels a side: each
    // step has 4 times the pixels and twice the length of edge in pixels. A window is
    // subdivided where an edge passes through it, so the windows, and the pixel windows
    // at the bottom of the subdivision, grow with the edges' length: measured 9,883 →
    // 22,405 → 49,407 windows (×2.27, ×2.21), 4,939 → 9,895 → 20,097 pixel windows
    // (×2.00, ×2.03). Growing with the pixels would be ×4 a step.
    let stats: Vec<String> = [250, 500, 1000]
        .map(|size| warnock_stats("spheres", size))
        .into();
    let windows: Vec<u64> = stats
        .iter()
        .map(|s| windows_by_depth(s).iter().sum())
        .collect();
    let pixels: Vec<u64> = stats.iter().map(|s| stat(s, "single_pixels")).collect();
    for k in 0..2 {
        let grew = windows[k + 1] as f64 / windows[k] as f64;
        assert!((1.8..2.6).contains(&grew), "windows {windows:?}");
        let grew = pixels[k + 1] as f64 / pixels[k] as f64;
        assert!((1.8..2.3).contains(&grew), "pixel windows {pixels:?}");
    }
    // One level more a step: the subdivision goes on to single pixels.
    let levels: Vec<usize> = stats.iter().map(|s| windows_by_depth(s).len()).collect();
    assert_eq!(levels, [9, 10, 11], "{stats:?}");
}

#[test]
fn a_deep_stack_is_one_window() {
    // 50,000 screen-filling squares, shuffled in depth: the nearest surrounds the whole
    // screen and the ZMIN exit passes over the other 49,999 unexamined, one window in
    // all, where the z-buffer writes every pixel once for each square that is nearer
    // than what it holds.
    let stats = warnock_stats("stack 50000", 500);
    assert_eq!(windows_by_depth(&stats), [1], "{stats}");
    assert_eq!(stat(&stats, "looked_at"), 1, "{stats}");
    assert!(
        stats.contains("1 ZMIN exits leaving 49999 unexamined"),
        "{stats}"
    );
}

#[test]
fn slivers_take_a_pixel_window_for_nearly_every_visible_segment() {
    // 2,000 slivers 0.4 pixel wide across a 500×500 screen: two of them share nearly
    // every window they pass through, and the Thinker cannot decide it, so the windows
    // along them are split down to pixels, ten levels. Measured: 140,324 pixel windows
    // for the 103,830 runs (one a visible segment) the frame writes, 217,600 windows at
    // the last level. The bound: between one and two pixel windows a visible segment.
    let stats = warnock_stats("slivers 2000", 500);
    let by_depth = windows_by_depth(&stats);
    assert_eq!(by_depth.len(), 10, "{stats}");
    let runs = stat(&stats, "runs_out");
    assert_eq!(runs, 103_830, "{stats}");
    let pixels = stat(&stats, "single_pixels");
    assert!(
        (runs..2 * runs).contains(&pixels),
        "{pixels} pixel windows for {runs} segments: {stats}"
    );
    // Nearly every window of the last level is a pixel the slivers cross.
    assert!(*by_depth.last().unwrap() > 200_000, "{stats}");
}
