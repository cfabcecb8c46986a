//! Helpers for the end-to-end tests: where the built binaries and scripts are, how to run
//! a shell pipeline of them, and how to read the PPM frames they write.
//!
//! Cargo gives a test the path of its own package's binaries only; the stages are other
//! packages, so the tests find them beside the test executable in the target directory,
//! building them once first if they are missing.

pub mod differential;
pub mod hosts;
pub mod nearest;
pub mod reference;
pub mod render;
pub mod scenes;
pub mod slurm;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Output, Stdio};
use std::sync::OnceLock;

/// The repository's root folder.
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ lives in the repository root")
        .to_path_buf()
}

/// The folder with the built binaries (the profile the tests were built with), after
/// making sure every stage binary is built and current (unless `POLYPIPE_BINARIES_BUILT`
/// is set: `.ci/run` has built them).
pub fn bin_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let exe = std::env::current_exe().expect("test executable path");
        // target/<profile>/deps/<test> → target/<profile>
        let dir = exe
            .parent()
            .and_then(Path::parent)
            .expect("test executable inside target/<profile>/deps")
            .to_path_buf();
        // `.ci/run` builds every binary once before the tests, and says so: then no test
        // binary runs a cargo of its own (each one's took about a second).
        if std::env::var_os("POLYPIPE_BINARIES_BUILT").is_some() {
            return dir;
        }
        let release = dir.file_name().is_some_and(|n| n == "release");
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let mut build = Command::new(cargo);
        build
            .current_dir(repo_root())
            .args(["build", "--quiet", "--bins"]);
        if release {
            build.arg("--release");
        }
        let status = build.status().expect("run cargo build");
        assert!(status.success(), "cargo build --bins failed");
        dir
    })
}

/// The path of a built stage binary.
pub fn bin(name: &str) -> PathBuf {
    bin_dir().join(name)
}

/// Runs a shell command line with the stage binaries first on PATH and the repository
/// as the working folder; `stdin` is fed to it.
pub fn sh(script: &str, stdin: &[u8]) -> Output {
    let path = format!(
        "{}:{}",
        bin_dir().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let mut cmd = Command::new("bash");
    cmd.args(["-o", "pipefail", "-c", script])
        .current_dir(repo_root())
        .env("PATH", path)
        .env("POLYPIPE_BIN", bin_dir())
        // The depth auto chooses weighs the load average; the tests' own load must not
        // change it (docs/model.md).
        .env("POLYPIPE_LOAD", "0");
    output_with_stdin(cmd, stdin)
}

/// Runs `cmd` with `stdin` written to it from a thread of its own (so that a large input
/// cannot deadlock against a large output), and collects its status, stdout and stderr.
pub fn output_with_stdin(mut cmd: Command, stdin: &[u8]) -> Output {
    use std::io::Write;
    let mut child = cmd
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start {cmd:?}: {e}"));
    let mut input = child.stdin.take().expect("stdin");
    let data = stdin.to_vec();
    let feeder = std::thread::spawn(move || {
        let _ = input.write_all(&data);
    });
    let out = child.wait_with_output().expect("wait for the command");
    let _ = feeder.join();
    out
}

/// Runs `script` (see [`sh`]) with no input and returns its stdout; a failure fails the
/// test with the script and its stderr.
pub fn run(script: &str) -> Vec<u8> {
    run_with(script, b"")
}

/// [`run`] with `stdin` as the script's input.
pub fn run_with(script: &str, stdin: &[u8]) -> Vec<u8> {
    succeeded(script, sh(script, stdin))
}

/// The stdout of `out`, which must be a success; else the test fails naming `what` ran,
/// its status and its stderr.
pub fn succeeded(what: &str, out: Output) -> Vec<u8> {
    assert!(
        out.status.success(),
        "`{what}` failed ({}): {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// A leaf method's `--stats` line (its stderr) for `scene ARGS` drawn at
/// `size`×`size`, after checking that the leaf's runs are the z-buffer leaf's
/// (`scanconv --resolve`) byte for byte: the exact methods' costs, measured on a frame
/// they draw right.
pub fn leaf_stats_drawing_as_zbuf(leaf: &str, scene: &str, size: u32) -> String {
    let out = sh(
        &format!(
            "set -e; d=$(mktemp -d); trap 'rm -rf \"$d\"' EXIT
             scene {scene} | viewxf --size {size}x{size} | clipbatch | persp --size {size}x{size} > \"$d/in\"
             {leaf} --stats < \"$d/in\" 2> \"$d/stats\" > \"$d/leaf\"
             scanconv --resolve < \"$d/in\" | cmp - \"$d/leaf\"
             cat \"$d/stats\""
        ),
        b"",
    );
    assert!(
        out.status.success(),
        "{leaf} on {scene} at {size}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The count `key` in `stderr`'s last `--stats` record that has it (stagecli::stats;
/// docs/DESIGN.md, "Structured stats", lists the keys).
pub fn stat(stderr: &str, key: &str) -> u64 {
    stat_record(stderr, key)
        .count(key)
        .unwrap_or_else(|| panic!("{key} is not a count in {stderr}"))
}

/// The list `key` (`warnock`'s `windows_by_depth`) in `stderr`'s last `--stats` record
/// that has it.
pub fn stat_list(stderr: &str, key: &str) -> Vec<u64> {
    stat_record(stderr, key)
        .list(key)
        .unwrap_or_else(|| panic!("{key} is not a list of counts in {stderr}"))
}

/// `stderr`'s last `--stats` record that has `key`.
pub fn stat_record(stderr: &str, key: &str) -> stagecli::stats::Record {
    stagecli::stats::records(stderr)
        .unwrap_or_else(|e| panic!("{e}"))
        .into_iter()
        .rev()
        .find(|r| r.get(key).is_some())
        .unwrap_or_else(|| panic!("no {key} in the records of {stderr}"))
}

/// The whole linear pipeline at `size` (W×H), from a world-space scene on stdin to
/// zbuf's PPM frames on stdout: the viewing transformation, the six clippers, the
/// perspective division, the scan converter and the z-buffer.
pub fn linear_pipeline(size: &str) -> String {
    format!(
        "viewxf --size {size} | clipplane left | clipplane right | clipplane top \
         | clipplane bottom | clipplane hither | clipplane yon | persp --size {size} \
         | scanconv | zbuf"
    )
}

/// One frame of a PPM stream.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Frame {
    pub width: usize,
    pub height: usize,
    /// Row-major RGB pixels, row 0 at the top.
    pub pixels: Vec<[u8; 3]>,
}

impl Frame {
    pub fn at(&self, x: usize, y: usize) -> [u8; 3] {
        self.pixels[y * self.width + x]
    }

    /// The pixels where this frame and `other` (of the same size) differ, with the colour
    /// each shows there.
    pub fn differences(&self, other: &Frame) -> Vec<([u8; 3], [u8; 3])> {
        assert_eq!(self.pixels.len(), other.pixels.len());
        self.pixels
            .iter()
            .zip(&other.pixels)
            .filter(|(p, q)| p != q)
            .map(|(p, q)| (*p, *q))
            .collect()
    }

    /// The frame as characters, one per pixel, from a colour → character table; any
    /// other colour prints as `?`.
    pub fn as_chars(&self, table: &[([u8; 3], char)]) -> String {
        let mut s = String::new();
        for y in 0..self.height {
            for x in 0..self.width {
                let p = self.at(x, y);
                s.push(
                    table
                        .iter()
                        .find(|(c, _)| *c == p)
                        .map_or('?', |(_, ch)| *ch),
                );
            }
            s.push('\n');
        }
        s
    }
}

/// Whether a render started by these tests (`POLYPIPE_LOAD=0`, no hosts) has a core or
/// less: the cores this process may use (its affinity, a container's CPU quota), as
/// render counts them. There `--depth auto` is 0 for every scene, without a look or the
/// model (render's `auto::one_core_at_most`), and a test of what the look or the model
/// decides checks that instead.
pub fn one_core_for_render() -> bool {
    std::thread::available_parallelism().map_or(1, |n| n.get()) <= 1
}

/// Waits for `child` to exit, and returns its status and the time it took; if it is still
/// running after `limit` (waiting for input it should not need, or hung), kills it and
/// fails the test with `what()`.
pub fn wait_within(
    child: &mut Child,
    limit: std::time::Duration,
    what: impl Fn() -> String,
) -> (ExitStatus, std::time::Duration) {
    let start = std::time::Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return (status, start.elapsed());
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            panic!("{}", what());
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
}

/// Parses a stream of PPM frames (binary P6 or plain P3) with the pipeline's own reader,
/// `proto::ppm` (the one `zspec compare` uses).
pub fn parse_ppm_stream(bytes: &[u8]) -> Result<Vec<Frame>, String> {
    let images = proto::ppm::read_all(bytes).map_err(|e| e.to_string())?;
    Ok(images
        .into_iter()
        .map(|i| Frame {
            width: i.width as usize,
            height: i.height as usize,
            pixels: i.pixels,
        })
        .collect())
}

/// The one frame of a PPM stream; a stream of any other number of frames fails the test.
pub fn only_frame(ppm: &[u8]) -> Frame {
    let mut frames = parse_ppm_stream(ppm).expect("a PPM stream");
    assert_eq!(frames.len(), 1, "frames in the stream");
    frames.remove(0)
}

/// Three per-vertex values of a world-space triangle (colours or normals) mixed at the
/// screen point `p` by its barycentric weights on the screen, computed here without the
/// pipeline's code: the vertices projected with the thesis's camera (eye at z = 20,
/// s = 10, d = 16, so w = 0.625·z_e) onto a `width`×`height` screen. `None` for a point
/// outside (a weight below `margin`). The held-out reference of the shading tests:
/// Gouraud's and Phong's interpolation is linear on the screen.
pub fn screen_mix(
    vertices: [[f64; 3]; 3],
    values: [[f64; 3]; 3],
    (width, height): (usize, usize),
    p: (f64, f64),
    margin: f64,
) -> Option<[f64; 3]> {
    let aspect = width as f64 / height as f64;
    let screen = vertices.map(|[x, y, z]| {
        let w = 0.625 * (20.0 - z);
        (
            (x / (aspect * w) + 1.0) * width as f64 / 2.0,
            (1.0 - y / w) * height as f64 / 2.0,
        )
    });
    let area = |a: (f64, f64), b: (f64, f64), c: (f64, f64)| {
        (b.0 - a.0) * (c.1 - a.1) - (c.0 - a.0) * (b.1 - a.1)
    };
    let whole = area(screen[0], screen[1], screen[2]);
    let l = [
        area(p, screen[1], screen[2]) / whole,
        area(screen[0], p, screen[2]) / whole,
        area(screen[0], screen[1], p) / whole,
    ];
    if l.iter().any(|&w| w < margin) {
        return None;
    }
    Some([0, 1, 2].map(|k| l[0] * values[0][k] + l[1] * values[1][k] + l[2] * values[2][k]))
}

/// Checks a frame of one triangle on a black background against a held-out colour,
/// `want(x, y, margin)` (`None` for a pixel centre outside the triangle by `margin`):
/// no centre well inside it (margin 1e-6) is left black, none drawn lies outside it
/// (margin −1e-9), and every drawn pixel is within one level a channel of `want`.
/// Returns how many pixels are drawn.
pub fn check_triangle_frame(
    f: &Frame,
    want: impl Fn(usize, usize, f64) -> Option<[f64; 3]>,
) -> usize {
    let mut covered = 0;
    for y in 0..f.height {
        for x in 0..f.width {
            let got = f.at(x, y);
            if got == [0, 0, 0] {
                assert!(
                    want(x, y, 1e-6).is_none(),
                    "pixel ({x}, {y}) is inside the triangle and not drawn"
                );
                continue;
            }
            covered += 1;
            let want = want(x, y, -1e-9)
                .unwrap_or_else(|| panic!("pixel ({x}, {y}) is drawn outside the triangle"));
            for k in 0..3 {
                assert!(
                    (got[k] as f64 - want[k]).abs() <= 1.0,
                    "pixel ({x}, {y}): {got:?} against {want:?}"
                );
            }
        }
    }
    covered
}

/// Whether the tests run under CI (`CI=true`, as `.ci/run` sets it): there a test that
/// cannot run what it tests fails instead of skipping.
pub fn under_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true")
}

/// A test that cannot run here (a tool not installed, a mount refused) calls this and
/// returns: under `CI=true` it panics with `why` instead, so that a machine missing what
/// `.ci/run` installs fails the run rather than passing it untested; elsewhere it prints
/// `SKIPPED: why` and counts the skip, and the test binary lists every skip when it exits.
pub fn skip(why: &str) {
    assert!(
        !under_ci(),
        "not skipped under CI=true, where it must run: {why}"
    );
    note_skip(why);
}

/// Counts a skip without [`skip`]'s check of `CI` (for a helper such as
/// [`hosts::Hosts::start_using`] whose caller has made that check), prints `SKIPPED: why`,
/// and has the skips listed when the test binary exits.
pub fn note_skip(why: &str) {
    use std::sync::Mutex;
    static SKIPS: Mutex<Vec<String>> = Mutex::new(Vec::new());
    extern "C" fn list_skips() {
        let skips = SKIPS.lock().unwrap_or_else(|e| e.into_inner());
        eprintln!("\n{} test(s) skipped in this test binary:", skips.len());
        for why in skips.iter() {
            eprintln!("  SKIPPED: {why}");
        }
    }
    extern "C" {
        fn atexit(callback: extern "C" fn()) -> std::ffi::c_int;
    }
    eprintln!("SKIPPED: {why}");
    let mut skips = SKIPS.lock().unwrap_or_else(|e| e.into_inner());
    if skips.is_empty() {
        // SAFETY: atexit only records the function pointer; `list_skips` is a plain
        // `extern "C" fn` that takes no arguments and does not unwind (eprintln and the
        // lock do not panic on a poisoned mutex here), as atexit requires.
        unsafe {
            atexit(list_skips);
        }
    }
    skips.push(why.to_string());
}
