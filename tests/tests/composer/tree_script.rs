//! scripts/tree.sh, the splitter tree of the design card written out as a short script
//! (thesis 6.3.3: the clipper chain, the splitter nodes, persp and scanconv at each leaf,
//! one zbuf): the bytes of `render.sh --merge buffer`, which runs the same graph with
//! fewer processes, at every depth; a failing stage named, and nothing left behind.

use pipeline_tests::{bin, bin_dir, parse_ppm_stream, repo_root, sh};
use std::path::Path;
use std::process::{Command, Output};

/// Runs scripts/tree.sh with `args` and `stdin`, its named pipes in `tmp`.
fn tree(args: &[&str], stdin: &[u8], tmp: &Path) -> Output {
    let mut cmd = Command::new(repo_root().join("scripts/tree.sh"));
    cmd.args(args)
        .env("POLYPIPE_BIN", bin_dir())
        .env("TMPDIR", tmp);
    pipeline_tests::output_with_stdin(cmd, stdin)
}

/// A scene of `scene`'s subcommand and options, written to `dir/name`.
fn scene_file(dir: &Path, name: &str, args: &str) -> String {
    let out = Command::new(bin("scene"))
        .args(args.split(' '))
        .output()
        .unwrap();
    assert!(out.status.success(), "scene {args}: {out:?}");
    let path = dir.join(name);
    std::fs::write(&path, out.stdout).unwrap();
    path.display().to_string()
}

/// The penetrating example, the test environment (thesis 5.2) and a movie of it, at odd
/// sizes so that the tree's cuts fall between pixels unevenly: tree.sh at depths 0 to 3
/// gives render.sh --merge buffer's bytes at the same depth, the scene named or on stdin,
/// and leaves no named pipe behind.
#[test]
fn tree_sh_writes_render_sh_merge_buffer_s_bytes_at_depths_0_to_3() {
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let penetrating = repo_root().join("examples/penetrating.txt");
    let environment = scene_file(
        dir.path(),
        "environment",
        "environment --polygons 400 --depth-complexity 3 --seed 7 --size 97x61",
    );
    let movie = scene_file(
        dir.path(),
        "movie",
        "environment --polygons 200 --depth-complexity 2 --seed 3 --size 80x80 --frames 3",
    );
    for (scene, size, frames) in [
        (penetrating.display().to_string(), "61x47", 1),
        (environment, "97x61", 1),
        (movie, "80x80", 3),
    ] {
        let mut pictures = Vec::new();
        for depth in ["0", "1", "2", "3"] {
            let what = format!("{scene} at {size}, depth {depth}");
            let render = sh(
                &format!("scripts/render.sh --merge buffer --depth {depth} --size {size} {scene}"),
                b"",
            );
            assert!(render.status.success(), "render.sh, {what}: {render:?}");
            let out = tree(&["--depth", depth, "--size", size, &scene], b"", &tmp);
            assert!(out.status.success(), "tree.sh, {what}: {out:?}");
            assert!(
                out.stdout == render.stdout,
                "tree.sh, {what}: not render.sh's bytes"
            );
            assert_eq!(out.stderr, b"", "tree.sh, {what}");
            pictures.push(out.stdout);
        }
        // The scene on stdin (`-`, and no SCENE at all): the same bytes.
        let stdin = std::fs::read(&scene).unwrap();
        for args in [
            &["--depth", "2", "--size", size, "-"][..],
            &["--depth", "2", "--size", size],
        ] {
            let out = tree(args, &stdin, &tmp);
            assert!(
                out.stdout == pictures[0],
                "tree.sh {args:?} < {scene}: {out:?}"
            );
        }
        // Real pictures, of the frames asked: something drawn on a black background.
        let parsed = parse_ppm_stream(&pictures[0]).unwrap();
        assert_eq!(parsed.len(), frames, "{scene}");
        for frame in &parsed {
            let (w, h) = size.split_once('x').unwrap();
            assert_eq!(
                (frame.width.to_string(), frame.height.to_string()),
                (w.into(), h.into())
            );
            let black = frame.pixels.iter().filter(|p| **p == [0, 0, 0]).count();
            assert!(
                0 < black && black < frame.pixels.len(),
                "{scene}: {black} black"
            );
        }
        assert!(
            pictures.iter().all(|p| *p == pictures[0]),
            "{scene}: depends on the depth"
        );
    }
    assert_eq!(
        std::fs::read_dir(&tmp).unwrap().count(),
        0,
        "named pipes left"
    );
}

/// A stage that fails is named after its own message, with its status (1 bad data, 2 a
/// usage error), the other stages' consequent complaints unsaid; tree.sh's own options
/// are usage errors; nothing is left in TMPDIR.
#[test]
fn a_failing_stage_is_named_with_its_status_and_nothing_is_left() {
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path();
    let out = tree(&["--depth", "3", "--size", "64x64"], b"garbage\n", tmp);
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    assert_eq!(out.stdout, b"");
    assert_eq!(
        String::from_utf8(out.stderr).unwrap(),
        "viewxf: line 1, column 1: not a polypipe stream: expected the header `polypipe 1 \
         SPACE`, found `garbage`\ntree.sh: viewxf failed (status 1)\n"
    );
    let penetrating = repo_root().join("examples/penetrating.txt");
    let out = tree(&["--size", "0x4", penetrating.to_str().unwrap()], b"", tmp);
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.ends_with(" failed (status 2)\n") && err.lines().count() == 2,
        "{err}"
    );
    for (args, message) in [
        (
            &["--depth", "7"][..],
            "--depth must be an integer from 0 to 6, not '7'",
        ),
        (&["--depth"], "--depth needs a value"),
        (
            &["--zmode", "eye-z"],
            "unknown option '--zmode' (tree.sh --help lists them)",
        ),
        (&["no-such-scene"], "cannot read the scene no-such-scene"),
    ] {
        let out = tree(args, b"", tmp);
        let status = if args[0] == "no-such-scene" { 3 } else { 2 };
        assert_eq!(out.status.code(), Some(status), "{args:?}");
        assert_eq!(
            String::from_utf8(out.stderr).unwrap(),
            format!("tree.sh: {message}\n")
        );
    }
    assert_eq!(std::fs::read_dir(tmp).unwrap().count(), 0, "left in TMPDIR");
}

/// The card's picture stays short enough to read: at most 100 lines of bash.
#[test]
fn tree_sh_is_at_most_100_lines() {
    let text = std::fs::read_to_string(repo_root().join("scripts/tree.sh")).unwrap();
    assert!(
        text.lines().count() <= 100,
        "{} lines",
        text.lines().count()
    );
}
