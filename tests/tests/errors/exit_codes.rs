//! Every binary's exit status by error class (stagecli's table, the README's):
//!
//! | status | class |
//! |--------|-------|
//! | 0 | success, or the reader of the output went away (`… \| head -c 10`), quietly |
//! | 1 | the input is not a valid stream (here: cut short) |
//! | 2 | usage: one line `stage: …` naming the option typed, before any input is read |
//! | 3 | an input or output cannot be opened, read or written |
//!
//! `zspec compare` follows cmp instead: 0 same, 1 different, 2 trouble.

use pipeline_tests::{bin, sh, wait_within};
use std::io::Read;
use std::process::{Command, Stdio};
use std::time::Duration;

/// Every binary, to check that no table below forgets one.
const BINARIES: &[&str] = &[
    "viewxf",
    "clipplane",
    "splitter",
    "persp",
    "scanconv",
    "zbuf",
    "zspec",
    "scene",
];

/// Usage errors: the binary, its arguments, and a piece of the message that names what
/// the user typed.
const USAGE: &[(&str, &[&str], &str)] = &[
    ("viewxf", &["--eye", "1,2"], "'--eye <X,Y,Z>'"),
    (
        "viewxf",
        &["--hither", "5", "--yon", "2"],
        "--hither 5 --yon 2",
    ),
    (
        "viewxf",
        &["--eye", "0,0,0", "--at", "0,0,0"],
        "--eye 0,0,0 --at 0,0,0",
    ),
    ("clipplane", &["sideways"], "'sideways'"),
    ("clipplane", &["--plane", "1,2,3"], "'--plane <a,b,c,d,k>'"),
    ("clipplane", &["left", "--at", "2"], "--at"),
    (
        "splitter",
        &["x=0", "same", "same"],
        "OUT1 same and OUT2 same",
    ),
    ("splitter", &["z=0", "a", "b"], "`z=0`"),
    ("splitter", &["--plane", "1,0,0", "a", "b"], "--plane 1,0,0"),
    ("persp", &["--size", "0x0"], "'--size <WxH>'"),
    (
        "persp",
        &["--size", "8x8", "--zmode", "foo"],
        "'--zmode <MODE>'",
    ),
    ("scanconv", &["--pixel"], "'--pixel'"),
    ("zbuf", &["-o", "x.jpg"], "-o x.jpg"),
    ("zbuf", &["-", "-"], "`-` (stdin)"),
    ("zbuf", &["--text", "-o", "f%d.png"], "--text"),
    (
        "zbuf",
        &["--background", "1,2"],
        "'--background <BACKGROUND>'",
    ),
    ("zspec", &["--size", "8"], "'--size <WxH>'"),
    ("zspec", &["--up", "0,0,1"], "--up 0,0,1"),
    (
        "zspec",
        &["compare", "a", "b", "--min-agreement", "nan"],
        "'--min-agreement",
    ),
    ("zspec", &["compare", "-", "-"], "`-` (stdin)"),
    ("scene", &[], "give a subcommand: environment, penetrating"),
    (
        "scene",
        &["sphere", "--radius", "-1"],
        "'--radius <RADIUS>'",
    ),
    (
        "scene",
        &["environment", "--clipped", "2"],
        "'--clipped <CLIPPED>'",
    ),
];

/// Runs `name args` with its stdin a pipe that stays open: a usage error must end it at
/// once, before it reads (or waits for) any input. Returns (status, stdout, stderr).
fn run_without_input(name: &str, args: &[&str]) -> (Option<i32>, String, String) {
    let mut child = Command::new(bin(name))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let stdin = child.stdin.take();
    let (status, _) = wait_within(&mut child, Duration::from_secs(20), || {
        format!("{name} {args:?} waited for its input instead of refusing its arguments")
    });
    drop(stdin);
    let mut out = String::new();
    let mut err = String::new();
    child.stdout.unwrap().read_to_string(&mut out).unwrap();
    child.stderr.unwrap().read_to_string(&mut err).unwrap();
    (status.code(), out, err)
}

#[test]
fn usage_errors_exit_2_at_once_with_one_line_naming_the_option() {
    for name in BINARIES {
        assert!(
            USAGE.iter().any(|(n, _, _)| n == name),
            "no usage case for {name}"
        );
    }
    for &(name, args, typed) in USAGE {
        let (status, out, err) = run_without_input(name, args);
        assert_eq!(status, Some(2), "{name} {args:?}: {err}");
        assert_eq!(out, "", "{name} {args:?}");
        assert_eq!(err.lines().count(), 1, "{name} {args:?}: {err}");
        // `zspec compare`'s own checks name the subcommand too.
        assert!(
            err.starts_with(&format!("{name}: ")) || err.starts_with(&format!("{name} compare: ")),
            "{name} {args:?}: {err}"
        );
        assert!(
            err.contains(typed),
            "{name} {args:?}: `{typed}` not in {err}"
        );
    }
}

#[test]
fn help_and_version_still_print_and_exit_0() {
    for name in BINARIES {
        let out = Command::new(bin(name)).arg("--version").output().unwrap();
        assert_eq!(out.status.code(), Some(0), "{name} --version");
        assert_eq!(
            String::from_utf8_lossy(&out.stdout),
            format!("{name} {}\n", env!("CARGO_PKG_VERSION")),
            "{name} --version"
        );
        let out = Command::new(bin(name)).arg("--help").output().unwrap();
        assert_eq!(out.status.code(), Some(0), "{name} --help");
        let help = String::from_utf8_lossy(&out.stdout);
        assert!(
            help.contains("Usage:") && help.lines().count() > 5,
            "{name}: {help}"
        );
        assert!(out.stderr.is_empty(), "{name} --help");
    }
}

/// A world-space scene for the pipelines below (T in the commands).
const SCENE: &str = "polypipe 1 world\ncolour 255 0 0\n-5 -5 0\n5 -5 0\n0 5 0\nEND\n";

/// Each binary that reads a stream: a pipeline making a whole valid binary input for it
/// (from the scene T), its command, and the status a stream cut in half gets.
const READERS: &[(&str, &str, &str, i32)] = &[
    ("viewxf", "cat T", "viewxf", 1),
    ("clipplane", "viewxf < T", "clipplane left", 1),
    (
        "splitter",
        "viewxf < T",
        "splitter x=0 /dev/null /dev/null",
        1,
    ),
    ("persp", "viewxf < T", "persp --size 8x8", 1),
    ("scanconv", "viewxf < T | persp --size 8x8", "scanconv", 1),
    (
        "zbuf",
        "viewxf < T | persp --size 8x8 | scanconv",
        "zbuf",
        1,
    ),
    ("zspec", "scene penetrating", "zspec --size 8x8", 1),
    // The OBJ model reader: a vertex cut short.
    (
        "scene",
        "printf 'v 0 0 0\\nv 1 0 0\\nv 0 1 0\\n'",
        "scene obj -",
        1,
    ),
    // cmp's table: a PPM cut short is trouble.
    (
        "zspec",
        "zspec --size 4x4 T",
        "zspec compare - /dev/null",
        2,
    ),
];

fn scene_file() -> tempfile::TempPath {
    let f = tempfile::NamedTempFile::new().unwrap();
    std::fs::write(f.path(), SCENE).unwrap();
    f.into_temp_path()
}

#[test]
fn a_stream_cut_short_exits_1() {
    let scene = scene_file();
    let t = scene.to_str().unwrap();
    for name in BINARIES {
        assert!(
            READERS.iter().any(|(n, ..)| n == name),
            "no cut case for {name}"
        );
    }
    for &(name, make, cmd, status) in READERS {
        let whole = sh(&make.replace('T', t), b"");
        assert!(whole.status.success(), "{make}");
        let cut = &whole.stdout[..whole.stdout.len() / 2];
        let out = sh(cmd, cut);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(status), "{cmd}: {err}");
        assert_eq!(err.lines().count(), 1, "{cmd}: {err}");
        assert!(err.starts_with(name), "{cmd}: {err}");
        assert!(!err.contains("panicked"), "{cmd}: {err}");
    }
}

/// Pipelines in which the named binary writes far more than a pipe holds into `head -c
/// 10`: it must end quietly with status 0 (bash's pipefail reports any stage's failure).
const CLOSED_OUTPUT: &[(&str, &str)] = &[
    ("scene", "scene environment --polygons 100000"),
    ("viewxf", "scene environment --polygons 50000 | viewxf"),
    (
        "clipplane",
        "scene environment --polygons 50000 | viewxf | clipplane left --text",
    ),
    (
        "splitter",
        "scene environment --polygons 50000 | viewxf | splitter x=0 - /dev/null --text",
    ),
    (
        "splitter",
        "scene environment --polygons 50000 | viewxf | splitter y=0 /dev/null - --text",
    ),
    (
        "persp",
        "scene environment --polygons 50000 | viewxf | clipplane hither | persp --size 64x64 --text",
    ),
    (
        "scanconv",
        "scene environment --polygons 2000 | viewxf | clipplane hither | clipplane left \
         | clipplane right | clipplane top | clipplane bottom | persp --size 256x256 \
         | scanconv --pixels --text",
    ),
    (
        "zbuf",
        "scene sphere --frames 8 | viewxf --size 600x600 | clipplane hither \
         | persp --size 600x600 | scanconv | zbuf",
    ),
    ("zspec", "scene sphere --frames 4 | zspec --size 600x600 --text"),
];

#[test]
fn a_reader_that_goes_away_ends_every_binary_quietly_with_0() {
    for name in BINARIES {
        assert!(
            CLOSED_OUTPUT.iter().any(|(n, _)| n == name),
            "no case for {name}"
        );
    }
    for &(name, pipeline) in CLOSED_OUTPUT {
        // The whole output is far more than a pipe holds, so the binary meets the
        // closed pipe (rather than finishing into the pipe's buffer).
        let size = sh(&format!("{pipeline} | wc -c"), b"");
        let bytes: u64 = String::from_utf8_lossy(&size.stdout)
            .trim()
            .parse()
            .unwrap();
        assert!(bytes > 1 << 20, "{name}: only {bytes} bytes");
        let out = sh(&format!("{pipeline} | head -c 10"), b"");
        assert_eq!(
            out.status.code(),
            Some(0),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert_eq!(out.stdout.len(), 10, "{name}");
        assert!(
            out.stderr.is_empty(),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

/// Inputs and outputs that cannot be opened, read or written: the command, its status
/// and its whole message.
const UNREADABLE: &[(&str, &str, i32, &str)] = &[
    ("viewxf", "viewxf < /", 3, "viewxf: stdin: Is a directory"),
    (
        "clipplane",
        "clipplane left < /",
        3,
        "clipplane: stdin: Is a directory",
    ),
    (
        "splitter",
        "splitter x=0 a b < /",
        3,
        "splitter: stdin: Is a directory",
    ),
    (
        "persp",
        "persp --size 4x4 < /",
        3,
        "persp: stdin: Is a directory",
    ),
    (
        "scanconv",
        "scanconv < /",
        3,
        "scanconv: stdin: Is a directory",
    ),
    ("zbuf", "zbuf < /", 3, "zbuf: stdin: Is a directory"),
    ("zbuf", "zbuf /", 3, "zbuf: /: Is a directory"),
    (
        "zbuf",
        "zbuf /nonexistent/f",
        3,
        "zbuf: /nonexistent/f: No such file or directory",
    ),
    ("zspec", "zspec < /", 3, "zspec: stdin: Is a directory"),
    ("zspec", "zspec /", 3, "zspec: /: Is a directory"),
    (
        "zspec",
        "zspec /nonexistent/s",
        3,
        "zspec: cannot open /nonexistent/s: No such file or directory",
    ),
    ("scene", "scene obj /", 3, "scene: /: Is a directory"),
    (
        "scene",
        "scene obj - < /",
        3,
        "scene: <stdin>: Is a directory",
    ),
    (
        "scene",
        "scene obj /nonexistent/m.obj",
        3,
        "scene: cannot open /nonexistent/m.obj: No such file or directory",
    ),
    // cmp's table: a missing file is trouble.
    (
        "zspec",
        "zspec compare /nonexistent/a /dev/null",
        2,
        "zspec compare: cannot open /nonexistent/a: No such file or directory",
    ),
];

#[test]
fn an_unreadable_input_exits_3_saying_so_once() {
    for name in BINARIES {
        assert!(
            UNREADABLE.iter().any(|(n, ..)| n == name),
            "no case for {name}"
        );
    }
    for &(_, cmd, status, message) in UNREADABLE {
        let out = sh(cmd, b"");
        assert_eq!(out.status.code(), Some(status), "{cmd}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr),
            format!("{message}\n"),
            "{cmd}"
        );
    }
}

#[test]
fn an_unwritable_output_exits_3() {
    let scene = scene_file();
    let t = scene.to_str().unwrap();
    let cases: &[(&str, &str)] = &[
        (
            "viewxf < T | splitter x=0 /nonexistent/a /dev/null",
            "splitter: cannot open /nonexistent/a for writing: No such file or directory\n",
        ),
        (
            "viewxf < T | persp --size 4x4 | scanconv | zbuf -o /dev/null/f.ppm",
            "zbuf: cannot write /dev/null/f.ppm: Not a directory\n",
        ),
        (
            "viewxf < T | persp --size 4x4 | scanconv | zbuf -o /dev/null/f.png",
            "zbuf: cannot write /dev/null/f.png: Not a directory\n",
        ),
        (
            "viewxf < T > /dev/full",
            "viewxf: stdout: No space left on device\n",
        ),
        (
            "viewxf < T | splitter x=0 /dev/full /dev/null",
            "splitter: /dev/full: No space left on device\n",
        ),
        (
            "viewxf < T | persp --size 4x4 | scanconv > /dev/full",
            "scanconv: stdout: No space left on device\n",
        ),
        (
            "scene penetrating > /dev/full",
            "scene: stdout: No space left on device\n",
        ),
        (
            "zspec --size 4x4 T > /dev/full",
            "zspec: stdout: No space left on device\n",
        ),
        (
            "viewxf < T | persp --size 4x4 | scanconv | zbuf > /dev/full",
            "zbuf: stdout: No space left on device\n",
        ),
        // zbuf resolving a screen-space input itself (`one_input`): the output is named,
        // not the input (this was `zbuf: stdin: stdout: …`, `zbuf: leaf-0: cannot write …`).
        (
            "viewxf < T | persp --size 4x4 | zbuf > /dev/full",
            "zbuf: stdout: No space left on device\n",
        ),
        (
            "viewxf < T | persp --size 4x4 | zbuf -o /dev/null/f.png",
            "zbuf: cannot write /dev/null/f.png: Not a directory\n",
        ),
        (
            "scripts/render.sh --size 4x4 -o /dev/null/dir/a.png T",
            "zbuf: cannot write /dev/null/dir/a.png: Not a directory\n",
        ),
    ];
    for &(cmd, message) in cases {
        let out = sh(&cmd.replace('T', t), b"");
        assert_eq!(out.status.code(), Some(3), "{cmd}");
        assert_eq!(String::from_utf8_lossy(&out.stderr), message, "{cmd}");
    }
}

/// `zspec compare`, with `--metrics` and without, exits alike for the same trouble, as cmp
/// does: 2 for a file that is not a PPM stream, one that cannot be opened or read, or a
/// bad argument, so that 1 always means the pictures differ (before, --metrics said 1 or
/// 3 where the plain form said 2). A (a good PPM) and the file named by each case, its
/// status and whole message.
#[test]
fn zspec_compare_exits_alike_with_and_without_metrics() {
    let dir = tempfile::tempdir().unwrap();
    let file = |name: &str, bytes: &[u8]| {
        let p = dir.path().join(name);
        std::fs::write(&p, bytes).unwrap();
        p.display().to_string()
    };
    let a = file("a.ppm", b"P6\n1 1\n255\n\xff\x00\x00");
    let png = file("b.png", b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR");
    let cut = file("cut.ppm", b"P6\n2 2\n255\n\xff\x00");
    let empty = file("empty.ppm", b"");
    let cases: &[(&str, i32, String)] = &[
        // The same fault in the same words, with --metrics and without.
        (
            &empty,
            2,
            format!("zspec compare: {empty}: empty: not a PPM stream (no frame)\n"),
        ),
        (
            &png,
            2,
            format!(
                "zspec compare: {png}: frame 0: expected a PPM (P6 or P3), found \"\u{fffd}P\"\n"
            ),
        ),
        (
            &cut,
            2,
            format!(
                "zspec compare: {cut}: frame 0: the PPM ends before the 2x2 pixels (2 of 12 \
                 bytes; cut short?)\n"
            ),
        ),
        (
            "/nonexistent/b.ppm",
            2,
            "zspec compare: cannot open /nonexistent/b.ppm: No such file or directory\n".into(),
        ),
        ("/", 2, "zspec compare: /: Is a directory\n".into()),
    ];
    for metrics in ["", "--metrics "] {
        for (b, status, message) in cases {
            let cmd = format!("zspec compare {metrics}{a} {b}");
            let out = sh(&cmd, b"");
            assert_eq!(out.status.code(), Some(*status), "{cmd}");
            assert_eq!(String::from_utf8_lossy(&out.stderr), *message, "{cmd}");
            assert!(out.stdout.is_empty(), "{cmd}");
        }
        let cmd = format!("zspec compare {metrics}- -");
        let out = sh(&cmd, b"");
        assert_eq!(out.status.code(), Some(2), "{cmd}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr),
            "zspec compare: `-` (stdin) is named twice: it can be read only once\n",
            "{cmd}"
        );
    }
}

/// A screen too large to hold is refused as its header is read, before zbuf waits for
/// (or scan-converts) a single polygon, with status 3 and the same line whichever way
/// zbuf reads it: resolved here with pictures out (`one_input`, which made its frame
/// buffer only when the first frame was painted: 40 s and 10 GB for persp's 65536x65536
/// screen) or through the reader threads (`--runs`). The address space is limited to 8 GB
/// so that the frame cannot be had on any machine; the input stays open, so a zbuf that
/// waited for more would be stopped after 20 s and fail.
#[test]
fn a_screen_too_large_to_hold_is_refused_at_its_header() {
    for args in [&[][..], &["--runs"]] {
        let mut child = Command::new("bash")
            .arg("-c")
            .arg("ulimit -v 8000000; exec \"$0\" \"$@\"")
            .arg(bin("zbuf"))
            .args(args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut stdin = child.stdin.take().unwrap();
        std::io::Write::write_all(&mut stdin, b"polypipe 1 screen 65536 65536\ncolour 1 2 3\n")
            .unwrap();
        let (status, _) = wait_within(&mut child, Duration::from_secs(20), || {
            format!("zbuf {args:?} waited for polygons instead of refusing the screen")
        });
        drop(stdin);
        let mut out = Vec::new();
        let mut err = String::new();
        child.stdout.take().unwrap().read_to_end(&mut out).unwrap();
        child
            .stderr
            .take()
            .unwrap()
            .read_to_string(&mut err)
            .unwrap();
        // Too large for this machine: status 3 (stagecli::memory), the memory this
        // process can have (at most the 7.6 GiB of the limit) at the end.
        assert_eq!(status.code(), Some(3), "zbuf {args:?}: {err}");
        assert!(
            err.starts_with(
                "zbuf: stdin: a 65536x65536 screen needs 60 GiB (15 bytes a pixel: depth, \
                 polygon and colour), more memory than this machine can give ("
            ) && err.ends_with(" available)\n"),
            "zbuf {args:?}: {err}"
        );
        assert!(out.is_empty(), "zbuf {args:?}");
    }
}

/// A movie where `-o` names one file is refused when its second frame comes, status 1,
/// leaving no picture and saying that a pattern is needed,
/// naming the option and not the input (this was `zbuf: stdin: -o one.png: …` when zbuf
/// resolved a screen-space input itself), the same from persp and from scanconv.
#[test]
fn a_movie_to_one_file_name_is_refused_naming_the_option() {
    let dir = tempfile::tempdir().unwrap();
    let one = dir.path().join("one.png").display().to_string();
    for leaf in ["", " | scanconv"] {
        let cmd = format!(
            "scene sphere --frames 3 | viewxf | clipplane hither | persp --size 8x8{leaf} \
             | zbuf -o {one}"
        );
        let out = sh(&cmd, b"");
        assert_eq!(out.status.code(), Some(1), "{cmd}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr),
            format!(
                "zbuf: -o {one}: the input is a movie (a second frame came), and {one} names \
                 one picture: give a pattern with %d for the frame number (as frame%03d.png); \
                 nothing was kept\n"
            ),
            "{cmd}"
        );
        // The first frame's picture, written before the second came, is taken back.
        assert!(!std::path::Path::new(&one).exists(), "{cmd}");
    }
}

/// Every numeric option of every binary, given a value out of its range, NaN, an
/// infinity or a negative number: status 2 at once, one line naming the option (a
/// negative value is the option's value, not an unknown option `-1`). The binary, the
/// words before the option, the option, the words after it, and the bad values.
type NumberCase = (
    &'static str,
    &'static [&'static str],
    &'static str,
    &'static [&'static str],
    &'static [&'static str],
);

const NUMBERS: &[NumberCase] = &[
    ("viewxf", &[], "--s", &[], &["-3", "nan", "inf", "0"]),
    ("viewxf", &[], "--d", &[], &["-1", "nan"]),
    ("viewxf", &[], "--hither", &[], &["-1", "nan", "inf"]),
    ("viewxf", &[], "--yon", &[], &["-1", "nan"]),
    ("viewxf", &[], "--aspect", &[], &["-2", "nan", "inf", "0"]),
    ("viewxf", &[], "--size", &[], &["-5x5", "0x5", "nanxnan"]),
    ("zspec", &[], "--samples", &[], &["-1", "0", "nan", "1e308"]),
    ("zspec", &[], "--background", &[], &["-1,0,0", "256,0,0"]),
    (
        "zspec",
        &["compare", "a", "b"],
        "--tolerance",
        &[],
        &["-1", "nan", "inf", "1.5"],
    ),
    (
        "zspec",
        &["compare", "a", "b"],
        "--min-agreement",
        &[],
        &["-1", "nan", "101"],
    ),
    ("persp", &[], "--size", &[], &["-5x5", "0x0", "65537x1"]),
    (
        "clipplane",
        &["hither"],
        "--at",
        &[],
        &["nan", "inf", "-inf"],
    ),
    ("clipbatch", &[], "--batch", &[], &["-1", "0", "nan"]),
    (
        "splitter",
        &["--depth", "2", "--size", "8x8"],
        "--node",
        &["a", "b"],
        &["-1", "nan", "0", "2147483648"],
    ),
    (
        "splitter",
        &["--node", "1", "--size", "8x8"],
        "--depth",
        &["a", "b"],
        &["-1", "0", "32", "1.5"],
    ),
    (
        "splitter",
        &["--node", "1", "--depth", "2", "--size", "8x8"],
        "--levels",
        &["a", "b"],
        &["-1", "0", "32"],
    ),
    (
        "zbuf",
        &["-o", "f%03d.png"],
        "--first-frame",
        &[],
        &["-3", "nan", "1.5"],
    ),
    ("zbuf", &[], "--background", &[], &["-1,0,0", "nan,0,0"]),
    (
        "supersample",
        &[],
        "--samples",
        &[],
        &["-1", "nan", "0", "3", "32"],
    ),
    ("supersample", &[], "--background", &[], &["-1,0,0"]),
    (
        "hiddenline",
        &[],
        "--stroke-width",
        &[],
        &["-1", "0", "nan", "inf"],
    ),
    ("painter", &["--split"], "--cuts-base", &[], &["-1", "nan"]),
    ("painter", &["--split"], "--cuts-per-polygon", &[], &["-1"]),
    ("frames", &[], "--from", &[], &["-1", "nan", "1.5"]),
    ("frames", &[], "--to", &[], &["-2"]),
    (
        "scene",
        &[],
        "--frames",
        &["penetrating"],
        &["-1", "0", "nan"],
    ),
    (
        "scene",
        &["environment"],
        "--depth-complexity",
        &[],
        &["1e308", "-1", "0", "nan", "inf"],
    ),
    (
        "scene",
        &["environment"],
        "--clipped",
        &[],
        &["-0.5", "nan", "2"],
    ),
    (
        "scene",
        &["environment"],
        "--polygons",
        &[],
        &["-1", "0", "nan"],
    ),
    ("scene", &["sphere"], "--radius", &[], &["-1", "0", "inf"]),
    ("scene", &["sphere"], "--stacks", &[], &["-1", "1"]),
    ("plan", &["depth"], "--cores", &["x"], &["-1", "0", "nan"]),
    (
        "plan",
        &["depth"],
        "--link-gbps",
        &["x"],
        &["nan", "0", "inf", "1e-300", "-1"],
    ),
    ("plan", &["depth"], "--load", &["x"], &["-1", "nan"]),
    ("plan", &["depth"], "--max-depth", &["x"], &["-1", "7"]),
    ("plan", &["movie"], "--login", &["x"], &["-1", "nan"]),
    ("plan", &["movie"], "--chunk", &["x"], &["-1", "0"]),
    (
        "farm",
        &["--hosts", "a"],
        "--chunk",
        &["-", "--", "true"],
        &["-1", "0"],
    ),
    (
        "farm",
        &["--hosts", "a"],
        "--retries",
        &["-", "--", "true"],
        &["-1", "0", "nan"],
    ),
    (
        "farm",
        &["--hosts", "a"],
        "--host-failures",
        &["-", "--", "true"],
        &["-1", "0"],
    ),
    (
        "farm",
        &["--hosts", "a"],
        "--host-timeout",
        &["-", "--", "true"],
        &["-1", "1.5", "inf"],
    ),
    (
        "farm",
        &["--hosts", "a", "-o", "f%03d.png"],
        "--first-frame",
        &["-", "--", "true"],
        &["-3", "nan"],
    ),
    ("chart", &["-o", "x"], "--reps", &[], &["-1", "0"]),
    ("render", &[], "--size", &[], &["-5x5", "0x5"]),
    ("render", &[], "--depth", &[], &["-1", "7", "nan"]),
    (
        "render",
        &["-o", "f%03d.png"],
        "--first-frame",
        &[],
        &["-1", "nan"],
    ),
];

#[test]
fn every_numeric_option_refuses_bad_values_naming_itself() {
    for &(name, before, option, after, values) in NUMBERS {
        for value in values {
            let args: Vec<&str> = before
                .iter()
                .copied()
                .chain([option, *value])
                .chain(after.iter().copied())
                .collect();
            let (status, out, err) = run_without_input(name, &args);
            let what = format!("{name} {}", args.join(" "));
            assert_eq!(status, Some(2), "{what}: {err}");
            assert_eq!(out, "", "{what}");
            assert_eq!(err.lines().count(), 1, "{what}: {err}");
            assert!(err.starts_with(name), "{what}: {err}");
            assert!(err.contains(option), "{what}: `{option}` not in {err}");
            for wrong in ["unexpected argument", "unknown option"] {
                assert!(!err.contains(wrong), "{what}: {err}");
            }
        }
    }
    // The range, in the option's own words.
    for (args, said) in [
        (
            &["plan", "depth", "--link-gbps", "nan", "x"][..],
            "plan: invalid value 'nan' for '--link-gbps <G>': `nan` is not a finite number \
             from 0.001 to 100000\n",
        ),
        (
            &["frames", "--from", "-1"],
            "frames: invalid value '-1' for '--from <A>': `-1` is not a whole number 0 or more\n",
        ),
        (
            &[
                "splitter", "--node", "1", "--size", "8x8", "--depth", "-1", "a", "b",
            ],
            "splitter: invalid value '-1' for '--depth <N>': `-1` is not a whole number \
             from 1 to 31\n",
        ),
        (
            &[
                "splitter", "--node", "0", "--size", "8x8", "--depth", "2", "a", "b",
            ],
            "splitter: invalid value '0' for '--node <K>': `0` is not a whole number \
             from 1 to 2147483647\n",
        ),
        (
            &["supersample", "--samples", "-1"],
            "supersample: invalid value '-1' for '--samples <K>': `-1` is not 1, 2, 4, 8 \
             or 16\n",
        ),
        (
            &["farm", "--hosts", "a", "--chunk", "-1", "-", "--", "true"],
            "farm: invalid value '-1' for '--chunk <N>': `-1` is not a whole number \
             1 or more\n",
        ),
        (
            &[
                "farm",
                "--hosts",
                "a",
                "--host-timeout",
                "-5",
                "-",
                "--",
                "true",
            ],
            "farm: invalid value '-5' for '--host-timeout <S>': `-5` is not a whole number \
             0 or more\n",
        ),
        (
            &["render", "--depth", "-1"],
            "render: --depth must be an integer from 0 to 6 or auto, not '-1'\n",
        ),
        (
            &["scene", "environment", "--depth-complexity", "1e308"],
            "scene: invalid value '1e308' for '--depth-complexity <DEPTH_COMPLEXITY>': \
             `1e308` is not a finite number from 0.000001 to 1000000\n",
        ),
    ] {
        let (status, _, err) = run_without_input(args[0], &args[1..]);
        assert_eq!((status, err.as_str()), (Some(2), said), "{args:?}");
    }
}

/// A subcommand given without its own subcommand lists its own (`scene screen`'s
/// scenes), not the top level's.
#[test]
fn a_missing_subcommand_lists_its_parents_own() {
    let (status, _, err) = run_without_input("scene", &["screen"]);
    assert_eq!(status, Some(2), "{err}");
    assert!(
        err.starts_with("scene: give a subcommand: ") && err.contains("(`scene screen --help`"),
        "{err}"
    );
    assert!(!err.contains("environment, penetrating"), "{err}");
}

/// `zspec compare`'s default is what the README says: every pixel the same (100%), so
/// that one differing pixel in 10,000 is a difference (status 1) unless `--tolerance` or
/// `--min-agreement` accepts it.
#[test]
fn zspec_compare_agrees_on_every_pixel_by_default_as_the_readme_says() {
    let readme = std::fs::read_to_string(pipeline_tests::repo_root().join("README.md")).unwrap();
    assert!(
        readme.contains("`--min-agreement` percent, default 100: every pixel)"),
        "README"
    );
    let dir = tempfile::tempdir().unwrap();
    let mut a = b"P6\n100 100\n255\n".to_vec();
    a.extend(std::iter::repeat_n(0u8, 30_000));
    let mut b = a.clone();
    let last = b.len() - 1;
    b[last] = 255;
    std::fs::write(dir.path().join("a.ppm"), &a).unwrap();
    std::fs::write(dir.path().join("b.ppm"), &b).unwrap();
    let d = dir.path().display();
    for (options, status) in [
        ("", 1),
        ("--min-agreement 100", 1),
        ("--min-agreement 99.99", 0),
        ("--tolerance 0.0001", 0),
    ] {
        let cmd = format!("zspec compare {options} {d}/a.ppm {d}/b.ppm");
        assert_eq!(sh(&cmd, b"").status.code(), Some(status), "{cmd}");
    }
}

/// `plan depth` is the name the README and the help give; `chart choose-depth`, its old
/// name, still runs (scripts use it) but is not listed in chart's help.
#[test]
fn plan_depth_has_one_name_in_the_help() {
    let chart = sh("chart --help", b"");
    let help = String::from_utf8_lossy(&chart.stdout);
    assert!(!help.contains("choose-depth"), "{help}");
    let plan = sh("plan --help", b"");
    assert!(
        String::from_utf8_lossy(&plan.stdout).contains("\n  depth "),
        "plan --help"
    );
    let readme = std::fs::read_to_string(pipeline_tests::repo_root().join("README.md")).unwrap();
    assert!(readme.contains("(`chart choose-depth`, its old name, still runs it)"));
    assert!(!readme.contains("(`plan depth` is its old name)"));
    let old = sh("chart choose-depth --help", b"");
    assert_eq!(old.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&old.stdout).contains("plan depth --size"));
}

/// The cost model's errors carry their kind to `plan`'s exit status and its one line, and
/// to `chart choose-depth`'s (the same library): a scene that cannot be opened 3, a
/// constants file that is not the model's TOML 1, a camera that cannot be looked through
/// 2, the reader gone 0.
#[test]
fn the_cost_models_errors_keep_their_status_in_plan_and_chart() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "overheads = 3\n").unwrap();
    let missing = dir.path().join("missing.txt");
    for tool in ["plan depth", "chart choose-depth"] {
        let me = tool.split(' ').next().unwrap();
        let out = sh(&format!("{tool} {}", missing.display()), b"");
        assert_eq!(out.status.code(), Some(3), "{tool}: {out:?}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr),
            format!(
                "{me}: cannot open {}: No such file or directory\n",
                missing.display()
            )
        );
        let out = sh(
            &format!("{tool} --model {} examples/penetrating.txt", bad.display()),
            b"",
        );
        assert_eq!(out.status.code(), Some(1), "{tool}: {out:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.starts_with(&format!("{me}: reading {}: ", bad.display()))
                && err.lines().count() == 1,
            "{tool}: {err}"
        );
        let out = sh(&format!("{tool} --hither 0 examples/penetrating.txt"), b"");
        assert_eq!(out.status.code(), Some(2), "{tool}: {out:?}");
        assert!(
            String::from_utf8_lossy(&out.stderr).starts_with(&format!("{me}: ")),
            "{tool}: {out:?}"
        );
    }
    let out = sh(
        "plan predict --model bench/model.toml examples/penetrating.txt | head -c 1 >/dev/null",
        b"",
    );
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert_eq!(String::from_utf8_lossy(&out.stderr), "");
}
