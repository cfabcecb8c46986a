//! The splitter tree end to end (thesis chapter 6.3): however the polygons fall between
//! the leaves, and for movies of any length, `render.sh --depth N` gives the frames that
//! depth 0 gives, and never deadlocks.

use pipeline_tests::{parse_ppm_stream, sh};
use std::fmt::Write as _;

/// Renders `scene` (a file path, or `-` with `stdin`) at each depth and asserts every
/// depth's output is byte-identical to depth 0's; returns depth 0's frames.
fn same_at_every_depth(args: &str, depths: &[u32], stdin: &[u8]) -> Vec<pipeline_tests::Frame> {
    let base = sh(&format!("scripts/render.sh --depth 0 {args}"), stdin);
    assert!(
        base.status.success(),
        "depth 0: {}",
        String::from_utf8_lossy(&base.stderr)
    );
    for &d in depths {
        let out = sh(&format!("scripts/render.sh --depth {d} {args}"), stdin);
        assert!(
            out.status.success(),
            "depth {d}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            out.stdout == base.stdout,
            "depth {d} differs from depth 0 for `{args}`"
        );
    }
    parse_ppm_stream(&base.stdout).expect("a PPM stream")
}

#[test]
fn a_movie_of_200_frames_of_1000_polygons_at_depth_4() {
    let frames = same_at_every_depth(
        "--size 200x150 <(scene environment --polygons 1000 --depth-complexity 2 --frames 200 --size 200x150 --seed 11)",
        &[4],
        b"",
    );
    assert_eq!(frames.len(), 200);
    // The polygons move: the movie is not one frame repeated.
    assert_ne!(frames[0], frames[199]);
    // And each frame is a real picture: about e^-2 of it background.
    let black = frames[100]
        .pixels
        .iter()
        .filter(|p| **p == [0, 0, 0])
        .count();
    let fraction = black as f64 / frames[100].pixels.len() as f64;
    assert!(
        (0.05..0.3).contains(&fraction),
        "background fraction {fraction}"
    );
}

/// A world-space text scene whose frames put every polygon into one corner of the
/// screen (one leaf of the tree gets everything, the others nothing), then an empty
/// frame, then a frame with polygons everywhere.
fn lopsided_movie() -> String {
    let mut s = String::from("polypipe 1 world\n");
    let quad = |s: &mut String, x: f64, y: f64, size: f64, z: f64, colour: [u8; 3]| {
        writeln!(s, "colour {} {} {}", colour[0], colour[1], colour[2]).unwrap();
        for (dx, dy) in [(0.0, 0.0), (size, 0.0), (size, size), (0.0, size)] {
            writeln!(s, "{} {} {}", x + dx, y + dy, z).unwrap();
        }
    };
    // Frame 0: 3000 small quads, all in the top-left corner (x_w, y_w in [-9.5, -6.5]×[6.5, 9.5]).
    for i in 0..3000 {
        if i > 0 {
            s.push_str("NEXT.POLYGON\n");
        }
        let t = i as f64;
        let x = -9.5 + (t * 0.37) % 2.5;
        let y = 6.5 + (t * 0.61) % 2.5;
        // Depths 0.01 apart, repeating every 300 polygons: exact ties, else well apart
        // (depths a few ulps apart would be below the z-buffer's resolution).
        let z = (i % 300) as f64 * 0.01 - 1.5;
        quad(
            &mut s,
            x,
            y,
            0.5,
            z,
            [(40 + i % 200) as u8, 100, (i % 255) as u8],
        );
    }
    // Frame 1: empty.
    s.push_str("NEXT.FRAME\nNEXT.FRAME\n");
    // Frame 2: a grid of quads over the whole screen, cut by every splitting plane.
    let mut first = true;
    for j in 0..20 {
        for i in 0..20 {
            if !first {
                s.push_str("NEXT.POLYGON\n");
            }
            first = false;
            let (x, y) = (-15.0 + 1.6 * i as f64, -15.0 + 1.6 * j as f64);
            quad(
                &mut s,
                x,
                y,
                1.7,
                0.0,
                [(i * 12) as u8, (j * 12) as u8, 200],
            );
        }
    }
    s.push_str("END\n");
    s
}

#[test]
fn lopsided_leaves_empty_frames_and_full_frames_never_deadlock() {
    let scene = lopsided_movie();
    let frames = same_at_every_depth("--size 96x96 -", &[1, 2, 3, 5], scene.as_bytes());
    assert_eq!(frames.len(), 3);
    // Frame 0: only the top-left corner is drawn.
    let drawn: Vec<(usize, usize)> = (0..96)
        .flat_map(|y| (0..96).map(move |x| (x, y)))
        .filter(|&(x, y)| frames[0].at(x, y) != [0, 0, 0])
        .collect();
    assert!(!drawn.is_empty());
    assert!(
        drawn.iter().all(|&(x, y)| x < 30 && y < 30),
        "frame 0 drawn outside the corner"
    );
    // Frame 1 is empty: all background.
    assert!(frames[1].pixels.iter().all(|p| *p == [0, 0, 0]));
    // Frame 2 covers the screen.
    assert!(frames[2].pixels.iter().all(|p| *p != [0, 0, 0]));
    // And it is the exact reference's picture.
    let reference = sh("zspec --size 96x96 -", scene.as_bytes());
    assert!(reference.status.success());
    assert_eq!(parse_ppm_stream(&reference.stdout).unwrap(), frames);
}

/// Ctrl-C at any moment: render.sh exits 130 (or 0, had it finished), within seconds,
/// leaving no private folder and no stage behind. `timeout -s INT` signals the script and
/// then its process group, as a terminal's Ctrl-C does. Before, a signal that came between
/// a stage's fork and the recording of its process id left that child waiting for ever in
/// the open of a named pipe, and render.sh waiting for it (6 hangs in 40 such runs); a
/// second signal during the clean-up ended the script before it removed its folder.
#[test]
fn an_interrupted_render_ends_at_once_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let movie = dir.path().join("movie.pp");
    let made = sh(
        &format!("scene spheres --frames 200 > '{}'", movie.display()),
        b"",
    );
    assert!(made.status.success());
    let root = pipeline_tests::repo_root();
    // The scene named (a child of render.sh not yet started as its stage has render.sh's
    // command line, with the scene's path in it) and on stdin.
    let named = movie.display().to_string();
    for (depth, after, scene) in [
        ("6", "0.05", "-"),
        ("6", "0.1", named.as_str()),
        ("6", "0.2", "-"),
        ("3", "0.05", named.as_str()),
        ("3", "0.1", "-"),
        ("6", "0.15", named.as_str()),
        ("6", "0.3", "-"),
        ("auto", "0.1", "-"),
        ("0", "0.05", named.as_str()),
        ("6", "0.25", named.as_str()),
    ] {
        let what = format!("--depth {depth} {scene}, INT after {after} s");
        let mut child = std::process::Command::new("timeout")
            .args(["--preserve-status", "-s", "INT", after])
            .arg(root.join("scripts/render.sh"))
            .args(["--depth", depth, scene])
            .stdin(std::fs::File::open(&movie).unwrap())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .env("TMPDIR", &tmp)
            .env("POLYPIPE_BIN", pipeline_tests::bin_dir())
            .spawn()
            .unwrap();
        let (status, _) =
            pipeline_tests::wait_within(&mut child, std::time::Duration::from_secs(20), || {
                format!("{what}: render.sh still running after 20 s")
            });
        assert!(
            matches!(status.code(), Some(130) | Some(0)),
            "{what}: {status:?}"
        );
        let left: Vec<_> = std::fs::read_dir(&tmp).unwrap().collect();
        assert!(left.is_empty(), "{what}: left {left:?}");
        // No process of the run left: the stages that open the named pipes themselves
        // (splitter, zbuf) have them on their command lines, render.sh and its children
        // the scene's path.
        let needle = dir.path().display().to_string();
        let running: Vec<String> = std::fs::read_dir("/proc")
            .unwrap()
            .filter_map(|e| std::fs::read(e.ok()?.path().join("cmdline")).ok())
            .map(|c| String::from_utf8_lossy(&c).replace('\0', " "))
            .filter(|c| c.contains(&needle))
            .collect();
        assert!(running.is_empty(), "{what}: still running: {running:?}");
    }
}
