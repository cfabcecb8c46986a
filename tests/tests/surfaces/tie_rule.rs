//! The tie rule (docs/DESIGN.md, "Visibility"): folding a pixel's polygons in stream
//! order, a later one takes the pixel only when nearer by more than 2^-30 of the holder's
//! depth. The pipeline at every tree depth, in both merge modes and with the scan-line
//! method draws exactly what the reference, zspec, draws, on the scenes where the rule
//! decides: coplanar decals, a pair of squares near yon at a hither/yon ratio of 10^6,
//! and the thesis's penetrating polygons at sizes where pixel centres fall on their line
//! of equal depth.

use pipeline_tests::reference::{agree_with_zspec as agree, one_frame as frame};
use pipeline_tests::scenes::{tilted_decals, Lcg};
use pipeline_tests::{sh, Frame};

const RED: [u8; 3] = [255, 0, 0];
const GREEN: [u8; 3] = [0, 255, 0];
const BLUE: [u8; 3] = [0, 0, 255];

/// The render.sh variants every scene is drawn with: depths 0 to 4 with the leaves
/// resolving (tiles), the thesis's one z-buffer (buffer) and the scan-line method.
const VARIANTS: &[&str] = &[
    "--depth 0",
    "--depth 1",
    "--depth 2",
    "--depth 3",
    "--depth 4",
    "--depth 0 --merge buffer",
    "--depth 3 --merge buffer",
    "--depth 0 --hse scanline",
    "--depth 2 --hse scanline",
];

fn count(f: &Frame, colour: [u8; 3]) -> usize {
    f.pixels.iter().filter(|p| **p == colour).count()
}

/// A red quad, then a green quad and a blue triangle inside it, all on one tilted plane.
fn decal_scene() -> String {
    tilted_decals(3)
}

#[test]
fn a_decal_on_a_tilted_plane_ties_and_the_earlier_polygon_shows() {
    for (camera, variants) in [
        ("--eye 6,-4,18 --size 500x500", VARIANTS),
        ("--eye -3,7,15 --size 320x240", &VARIANTS[..3]),
        ("--eye 1,1,9 --size 777x333", &VARIANTS[..3]),
    ] {
        let f = agree(&decal_scene(), camera, variants);
        assert!(count(&f, RED) > 10_000, "{camera}: the quad is drawn");
        assert_eq!((count(&f, GREEN), count(&f, BLUE)), (0, 0), "{camera}");
    }
}

/// Hither 0.001, yon 1000: a red square at z_e = 880 first in the stream, then a smaller
/// blue one `gap` of its depth nearer, scaled with its depth so that it covers the same
/// pixels at every gap.
fn near_yon_pair(gap: f64) -> String {
    let (z_red, z_blue) = (20.0 - 880.0, 20.0 - 880.0 * (1.0 - gap));
    let square = |h: f64, z: f64| {
        format!(
            "{} {} {z:.17}\n{h} {} {z:.17}\n{h} {h} {z:.17}\n{} {h} {z:.17}\n",
            -h, -h, -h, -h
        )
    };
    format!(
        "polypipe 1 world\ncolour 255 0 0\n{}NEXT.POLYGON\ncolour 0 0 255\n{}END\n",
        square(300.0, z_red),
        square(150.0 * (1.0 - gap), z_blue)
    )
}

#[test]
fn squares_near_yon_are_ordered_by_the_rule_at_a_ratio_of_a_million() {
    const CAMERA: &str = "--hither 0.001 --yon 1000 --size 200x200";
    // 2^-30 is 9.3e-10: gaps above it put blue in front, gaps below tie (red stays).
    let mut whole = None;
    for (gap, blue_in_front) in [
        (1e-2, true),
        (3.4e-7, true),
        (1e-8, true),
        (2e-9, true),
        (2e-10, false),
        (1e-12, false),
    ] {
        let variants: &[&str] = if gap == 3.4e-7 {
            VARIANTS
        } else {
            &VARIANTS[..1]
        };
        let f = agree(&near_yon_pair(gap), CAMERA, variants);
        let blue = count(&f, BLUE);
        assert_eq!(blue > 0, blue_in_front, "gap {gap}: {blue} blue pixels");
        if blue_in_front {
            // The whole blue square, as at the largest gap.
            assert_eq!(blue, *whole.get_or_insert(blue), "gap {gap}");
        }
    }
}

#[test]
fn projective_depth_loses_the_near_yon_square() {
    // The classic z-buffer's depth, crowded against 1 near yon: the blue square 3.4e-7 of
    // its depth nearer ties with red there, where the rule orders them.
    let f = frame(
        "scripts/render.sh --hither 0.001 --yon 1000 --size 200x200 --zmode projective -",
        near_yon_pair(3.4e-7).as_bytes(),
    );
    let right = frame(
        "scripts/render.sh --hither 0.001 --yon 1000 --size 200x200 -",
        near_yon_pair(3.4e-7).as_bytes(),
    );
    assert_eq!(count(&right, BLUE), 2916);
    assert!(count(&f, BLUE) < 2916, "{} blue", count(&f, BLUE));
}

/// The z-buffer says where projective depth ties what the rule orders: one line a frame
/// from the stage that resolves (zbuf at depth 0 and with one z-buffer, each leaf's
/// scanconv in a tree), with the number of depth tests, and nothing for reciprocal depth
/// or eye-z, whose test is the rule.
#[test]
fn zbuf_says_when_projective_depth_ties_what_the_rule_orders() {
    let scene = near_yon_pair(3.4e-7);
    let warning = "depth tests where a polygon nearer than the tie rule's 2^-30 lost to one \
                   within the projective depth's quantum (up to 9.3e-4 of the eye-space depth \
                   in this view volume): the earlier polygon shows there (persp --zmode \
                   reciprocal keeps the rule at any hither/yon)";
    let camera = "--hither 0.001 --yon 1000 --size 200x200";
    for (options, lines) in [
        ("--depth 0", vec![format!("zbuf: frame 0: 2916 {warning}")]),
        (
            "--depth 2 --merge buffer",
            vec![format!("zbuf: frame 0: 2916 {warning}")],
        ),
        (
            // Leaf 0 is the merger's own: zbuf resolves it and says so for it.
            "--depth 2",
            (1..4)
                .map(|leaf| format!("scanconv (leaf {leaf}): frame 0: 729 {warning}"))
                .chain([format!("zbuf: frame 0: 729 {warning}")])
                .collect(),
        ),
    ] {
        let out = sh(
            &format!("scripts/render.sh {camera} --zmode projective {options} -"),
            scene.as_bytes(),
        );
        assert!(out.status.success(), "{options}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        let mut got: Vec<&str> = stderr.lines().filter(|l| l.contains("frame 0:")).collect();
        got.sort();
        assert_eq!(got, lines, "{options}");
        // --stats counts them too.
        if options == "--depth 0" {
            let out = sh(
                &format!("scripts/render.sh {camera} --zmode projective {options} --stats -"),
                scene.as_bytes(),
            );
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert_eq!(
                pipeline_tests::stat(&stderr, "rounding_decided"),
                2916,
                "{stderr}"
            );
        }
    }
    for zmode in ["reciprocal", "eye-z"] {
        for options in ["--depth 0", "--depth 2", "--depth 2 --merge buffer"] {
            let out = sh(
                &format!("scripts/render.sh {camera} --zmode {zmode} {options} -"),
                scene.as_bytes(),
            );
            assert!(out.status.success());
            assert!(
                !String::from_utf8_lossy(&out.stderr).contains("tie rule"),
                "{zmode} {options}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
    }
}

#[test]
fn penetrating_polygons_are_the_reference_at_every_size() {
    // Sizes at which pixel centres lie on the polygons' line of equal depth, and others.
    for (i, size) in [
        "96x64",
        "320x240",
        "400x400",
        "512x512",
        "777x333",
        "1000x1000",
        "500x500",
        "21x21",
    ]
    .iter()
    .enumerate()
    {
        let scene =
            std::fs::read_to_string(pipeline_tests::repo_root().join("examples/penetrating.txt"))
                .unwrap();
        let variants = if i < 2 { VARIANTS } else { &VARIANTS[..2] };
        agree(&scene, &format!("--size {size}"), variants);
    }
}

#[test]
fn generated_eyes_and_sizes_agree_with_the_reference() {
    // A small linear congruential generator: the same cases every run.
    let mut state = Lcg(0x2545_f491_4f6c_dd1d);
    let mut next = |n: u64| state.next(n);
    let scene = decal_scene();
    let pen = std::fs::read_to_string(pipeline_tests::repo_root().join("examples/penetrating.txt"))
        .unwrap();
    for case in 0..6 {
        let (w, h) = (64 + next(500), 64 + next(400));
        let eye = format!(
            "{},{},{}",
            next(20) as i64 - 10,
            next(20) as i64 - 10,
            12 + next(20)
        );
        let camera = format!("--eye {eye} --size {w}x{h}");
        let variant = VARIANTS[case % VARIANTS.len()];
        agree(
            if case % 2 == 0 { &scene } else { &pen },
            &camera,
            &[variant],
        );
    }
}

#[test]
fn the_precision_table_is_right_for_the_reciprocal_form_only() {
    // docs/methods.md, "The z-buffer near yon": the example that prints it is built with
    // the tests.
    let exe = pipeline_tests::bin_dir().join("examples/depth_precision");
    let out = std::process::Command::new(&exe)
        .output()
        .unwrap_or_else(|e| panic!("{}: {e}", exe.display()));
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    let blocks: Vec<&str> = text.split("\n\n").collect();
    let table = |name: &str| -> Vec<&str> {
        let at = blocks.iter().position(|b| b.starts_with(name)).expect(name);
        blocks[at + 1].lines().skip(2).collect()
    };
    // The default: every ratio, every gap.
    assert!(table("reciprocal").iter().all(|r| !r.contains('✗')));
    // The old fixed point loses the pair at 10^6 for gaps 1e-7..1e-9.
    let fixed = table("projective, 2⁻⁴⁰ fixed point");
    assert_eq!(fixed.len(), 7);
    assert!(
        fixed[0].split('|').all(|c| !c.contains('✗')),
        "{}",
        fixed[0]
    );
    assert!(
        fixed[3].starts_with("| 1e6 |") && fixed[3].matches('✗').count() == 3,
        "{}",
        fixed[3]
    );
}
