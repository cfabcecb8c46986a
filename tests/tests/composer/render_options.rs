//! render's command line: what it draws by default, its option errors (one line, naming
//! the option as typed, status 2), --version and --help.

use pipeline_tests::render::{differing_pixels, example, frames, render, render_cmd, render_ok};
use pipeline_tests::{bin_dir, repo_root};
use std::path::PathBuf;
use std::process::Command;

#[test]
fn the_example_renders_the_penetrating_polygons_at_500x500() {
    let ppm = render_ok(&[&example()], b"");
    assert_eq!(ppm.len(), 15 + 500 * 500 * 3);
    let f = frames(&ppm);
    assert_eq!(f.len(), 1);
    assert_eq!((f[0].width, f[0].height), (500, 500));
    // The blue quadrilateral's upper-left end projects to (25,125)-(75,75): pixel
    // (50, 100) is inside it and nothing else; (150, 320) is inside only the red
    // triangle (90,330)-(250,110)-(410,330); the corner is background.
    assert_eq!(f[0].at(50, 100), [60, 60, 255]);
    assert_eq!(f[0].at(150, 320), [255, 60, 60]);
    assert_eq!(f[0].at(5, 5), [0, 0, 0]);
}

/// an option error is one line, starting with `render:`, naming the option
/// the user typed (`--zmode foo` used to come back as persp's `--depth <DEPTH>`).
#[test]
fn option_errors_are_one_line_naming_the_option_typed() {
    for (args, message) in [
        (
            &["--zmode", "foo"][..],
            "render: --zmode must be reciprocal, projective or eye-z, not 'foo'",
        ),
        (
            &["--zmode=bar"],
            "render: --zmode must be reciprocal, projective or eye-z, not 'bar'",
        ),
        (
            &["--depth", "7"],
            "render: --depth must be an integer from 0 to 6 or auto, not '7'",
        ),
        (
            &["--size", "65537x10"],
            "render: --size must be WxH with W and H from 1 to 65536, not '65537x10'",
        ),
        (&["--size"], "render: --size needs a value"),
        (&["--stats=yes"], "render: --stats takes no value"),
        (&["--bogus=1"], "render: unknown option --bogus"),
        (
            &["a.txt", "b.txt"],
            "render: more than one SCENE: 'a.txt' and 'b.txt'",
        ),
    ] {
        let out = render(args, b"");
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr),
            format!("{message}\n"),
            "{args:?}"
        );
        assert!(out.stdout.is_empty());
    }
    // The valid modes get through to persp.
    let eye_z = render_ok(&["--size", "21x21", "--zmode", "eye-z", &example()], b"");
    assert_eq!(frames(&eye_z).len(), 1);
}

/// `--version`, and what --help and the README say about eye-z and the
/// depth.
#[test]
fn version_and_the_eye_z_caveat() {
    let out = render(&["--version"], b"");
    assert!(out.status.success());
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        format!("render {}\n", env!("CARGO_PKG_VERSION"))
    );
    let help = String::from_utf8(render(&["--help"], b"").stdout).unwrap();
    assert!(
        help.contains("The frames are byte-identical for every --depth with reciprocal or projective depth, but not\nwith --zmode eye-z"),
        "{help}"
    );
    assert!(help.contains("Needs Linux (/proc)."), "{help}");
    // The caveat is real: with eye-z depth, a tree changes pixels where the polygons
    // interpenetrate (2,282 of 250,000 at depth 4), and the README says how many. The
    // linear render names depth 0: the default, auto, weighs the machine's load.
    let linear = render_ok(&["--zmode", "eye-z", "--depth", "0", &example()], b"");
    let tree = render_ok(&["--zmode", "eye-z", "--depth", "4", &example()], b"");
    let differ = differing_pixels(&linear, &tree).len();
    assert!(differ > 0 && differ < 2500, "{differ} pixels differ");
    let readme = std::fs::read_to_string(repo_root().join("README.md")).unwrap();
    assert!(
        readme.contains(&format!(
            "{},{:03} of the penetrating polygons' 250,000 pixels",
            differ / 1000,
            differ % 1000
        )),
        "the README should say that {differ} pixels differ"
    );
}

/// render.sh is a bash script; plain sh stops at its first lines with one clear message
/// and status 3 (the environment, as for a missing cargo), not a syntax error half-way.
#[test]
fn plain_sh_is_told_that_render_sh_needs_bash() {
    let script = repo_root().join("scripts/render.sh");
    // A POSIX sh (dash on Debian and Ubuntu) that is not bash at all.
    let sh = ["dash", "posh", "busybox"]
        .into_iter()
        .find(|sh| {
            Command::new("sh")
                .args(["-c", &format!("command -v {sh}")])
                .output()
                .is_ok_and(|o| o.status.success())
        })
        .expect("a POSIX sh other than bash (dash) to test with");
    let mut cmd = Command::new(sh);
    if sh == "busybox" {
        cmd.arg("sh");
    }
    let out = cmd.arg(&script).arg("--version").output().unwrap();
    assert_eq!(out.status.code(), Some(3), "{sh}");
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "render.sh: needs bash (this is not bash)\n"
    );
}

/// With no SCENE and stdin a terminal, render draws the example and says so on stderr.
/// The terminal is a pseudo-terminal of `script` (util-linux), which runs render with
/// its stdin, stdout and stderr on it; the frame goes to a file.
#[test]
fn on_a_terminal_with_no_scene_the_example_is_drawn_and_said() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("render-terminal");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("example.png");
    let line = format!(
        // (Its progress, shown on a terminal, is the progress module's.)
        "POLYPIPE_LOAD=0 {} --size 32x32 --depth 1 --no-progress -o {}",
        repo_root().join("scripts/render.sh").display(),
        png.display()
    );
    bin_dir();
    let out = Command::new("script")
        .args(["-qec", &line, "/dev/null"])
        .stdin(std::process::Stdio::null())
        .output()
        .expect("script (util-linux) to run render on a terminal");
    let said = String::from_utf8_lossy(&out.stdout).replace('\r', "");
    assert!(out.status.success(), "{said}");
    assert_eq!(
        said,
        format!(
            "render: no SCENE given and stdin is a terminal: rendering {} (give a SCENE, `-`, or pipe one in)\n",
            example()
        )
    );
    let expected = dir.join("expected.png");
    render_ok(
        &[
            "--size",
            "32x32",
            "-o",
            expected.to_str().unwrap(),
            &example(),
        ],
        b"",
    );
    assert_eq!(
        std::fs::read(&png).unwrap(),
        std::fs::read(&expected).unwrap()
    );
}

/// With no SCENE and stdin /dev/null (a job started with no input: cron, CI, `ssh HOST
/// COMMAND`), render draws the example, as on a terminal, and says why; a pipe, even an
/// empty one, is a scene.
#[test]
fn with_stdin_dev_null_and_no_scene_the_example_is_drawn_and_said() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("render-dev-null");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let (png, expected) = (dir.join("example.png"), dir.join("expected.png"));
    bin_dir();
    let out = Command::new(repo_root().join("scripts/render.sh"))
        .args([
            "--size",
            "32x32",
            "--depth",
            "0",
            "-o",
            png.to_str().unwrap(),
        ])
        .stdin(std::process::Stdio::null())
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        format!(
            "render: no SCENE given and stdin is a device (such as /dev/null): rendering {} (give a SCENE, `-`, or pipe one in)\n",
            example()
        )
    );
    render_ok(
        &[
            "--size",
            "32x32",
            "-o",
            expected.to_str().unwrap(),
            &example(),
        ],
        b"",
    );
    assert_eq!(
        std::fs::read(&png).unwrap(),
        std::fs::read(&expected).unwrap()
    );
    // An empty pipe is a scene: viewxf says it is empty.
    let out = render(&["--size", "32x32", "--depth", "0"], b"");
    assert_eq!(out.status.code(), Some(1));
    assert!(
        String::from_utf8_lossy(&out.stderr).starts_with("viewxf: empty input"),
        "{out:?}"
    );
}

/// A POLYPIPE_SSH that is set but blank names no command: refused before any host is
/// tried, status 2, naming the variable (for --by leaves and --by frames alike).
#[test]
fn a_blank_polypipe_ssh_is_refused_naming_it() {
    for by in ["leaves", "frames"] {
        let mut cmd = render_cmd(&["--hosts", "a,b", "--by", by, "--depth", "1", &example()]);
        cmd.env("POLYPIPE_SSH", " \t");
        let out = pipeline_tests::output_with_stdin(cmd, b"");
        assert_eq!(out.status.code(), Some(2), "--by {by}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr),
            "render: POLYPIPE_SSH is set but blank: set it to the command that reaches a host \
             (say 'ssh -p 2222'), or unset it for ssh\n"
        );
        assert!(out.stdout.is_empty());
    }
}

/// farm's options are farm's: refused without --by frames; --first-frame numbers -o's
/// files.
#[test]
fn farm_options_need_by_frames_and_first_frame_needs_o() {
    for (args, said) in [
        (
            &["--joblog", "j.txt"][..],
            "render: --joblog is for --by frames\n",
        ),
        (&["--resume"], "render: --resume is for --by frames\n"),
        (&["--chunk", "2"], "render: --chunk is for --by frames\n"),
        (
            &["--first-frame", "3"],
            "render: --first-frame numbers -o's files: it needs -o\n",
        ),
    ] {
        let out = render(&[args, &[example().as_str()]].concat(), b"");
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert_eq!(String::from_utf8_lossy(&out.stderr), said);
    }
}
