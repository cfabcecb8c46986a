//! Errors said the stages' way (CONTRIBUTING.md): one line, `stage: message`, with the
//! documented status, for cases that once said it twice, with another program's words, or
//! with the wrong status. The tables of exit statuses are in exit_codes.rs.

use pipeline_tests::sh;

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// `scene obj /tmp` exited 1 for an I/O error.
#[test]
fn an_obj_file_that_cannot_be_read_is_an_io_error() {
    let out = sh("scene obj /tmp", b"");
    assert_eq!(out.status.code(), Some(3));
    assert_eq!(stderr(&out), "scene: /tmp: Is a directory\n");
}

/// `zbuf /tmp` said `Is a directory (os error 21): Is a directory (os error 21)`.
#[test]
fn an_os_error_is_said_once() {
    let out = sh("zbuf /tmp", b"");
    assert_eq!(out.status.code(), Some(3));
    assert_eq!(stderr(&out), "zbuf: /tmp: Is a directory\n");
}

/// `zspec compare` used 1 both for "differ" and for "not a PPM"; now cmp's 0 same,
/// 1 different, 2 trouble.
#[test]
fn zspec_compare_exits_as_cmp_does() {
    let dir = tempfile::tempdir().unwrap();
    let file = |name: &str, bytes: &[u8]| {
        let p = dir.path().join(name);
        std::fs::write(&p, bytes).unwrap();
        p.display().to_string()
    };
    let red = file("red.ppm", b"P6\n1 1\n255\n\xff\x00\x00");
    let red_plain = file("red-plain.ppm", b"P3\n1 1\n255\n255 0 0\n");
    let blue = file("blue.ppm", b"P6\n1 1\n255\n\x00\x00\xff");
    let two = file(
        "two.ppm",
        b"P6\n1 1\n255\n\xff\x00\x00P6\n1 1\n255\n\xff\x00\x00",
    );
    let text = file("scene.txt", b"polypipe 1 world\nEND\n");
    let cases = [
        (format!("zspec compare {red} {red_plain}"), 0, ""),
        (
            format!("zspec compare {red} {blue}"),
            1,
            "zspec compare: 1 of 1 frames differ (frames [0])\n",
        ),
        (
            format!("zspec compare {red} {two}"),
            1,
            "zspec compare: the streams have 1 and 2 frames\n",
        ),
        (
            format!("zspec compare {red} {text}"),
            2,
            "expected a PPM (P6 or P3), found \"po\"\n",
        ),
        (
            format!("zspec compare {red} /nonexistent"),
            2,
            "zspec compare: cannot open /nonexistent: No such file or directory\n",
        ),
        (
            format!("zspec compare --min-agreement 101 {red} {red}"),
            2,
            "zspec: invalid value '101' for '--min-agreement <MIN_AGREEMENT>': `101` is not \
             a percentage from 0 to 100\n",
        ),
    ];
    for (cmd, status, message) in cases {
        let out = sh(&cmd, b"");
        assert_eq!(out.status.code(), Some(status), "{cmd}: {}", stderr(&out));
        assert!(stderr(&out).ends_with(message), "{cmd}: {}", stderr(&out));
    }
}

/// `render.sh /tmp` let `cat` say `cat: /tmp: Is a directory` and then
/// said only that it could not keep the scene; now one line in the stages' words, status 3,
/// at any depth (`--depth auto` copies a scene before looking at it; a given depth does not).
#[test]
fn render_sh_says_a_folder_is_not_a_scene() {
    for depth in ["auto", "0", "2"] {
        let out = sh(&format!("scripts/render.sh --depth {depth} /tmp"), b"");
        assert_eq!(out.status.code(), Some(3), "--depth {depth}");
        assert_eq!(
            stderr(&out),
            "render: /tmp: Is a directory\n",
            "--depth {depth}"
        );
        assert!(out.stdout.is_empty());
    }
}

/// `render.sh --subtree 3` without `--depth` failed with `line 237: auto: unbound
/// variable`, status 1: a subtree is cut by the tree's depth, which must be given.
#[test]
fn subtree_without_a_depth_is_a_usage_error() {
    let out = sh("scripts/render.sh --subtree 3 < /dev/null", b"");
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        stderr(&out),
        "render: --subtree needs --depth N, the depth of the tree it is part of\n"
    );
}
