//! The cost model's planner and its calibration (docs/model.md): `plan` and `chart`'s
//! `calibrate`, `thesis` and `choose-depth`; the calibration kept in the XDG cache with
//! the machine it was made on; `render.sh --depth auto` on a stream (sampled, then
//! relayed, never kept whole) and on a live source; `chart -o FILE`; and chart.sh's
//! freshness check. Every run that could calibrate is given a cache folder of its own and
//! the quick calibration, so that no test spends 20 seconds fitting the machine.

use pipeline_tests::{repo_root, sh};
use std::io::{Read, Write};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The environment of a run with the cache folder `cache`, and the quick calibration.
fn cached(cache: &Path) -> String {
    format!(
        "XDG_CACHE_HOME={} POLYPIPE_CALIBRATION=quick",
        cache.display()
    )
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn thesis_reproduces_5_2s_timings_and_6_4s_depth() {
    for command in ["chart thesis", "plan thesis", "scripts/chart.sh thesis"] {
        let out = sh(command, b"");
        assert!(out.status.success(), "{command}: {}", text(&out.stderr));
        let report = text(&out.stdout);
        // Each stage's row: | name | formula | model cycles | model s | thesis | ratio |.
        for (name, thesis_s) in [
            ("T_v", 0.09),
            ("T_p", 0.05),
            ("T_c", 0.21),
            ("T_SP", 0.12),
            ("T_sc", 5.2),
        ] {
            let row = report
                .lines()
                .find(|l| l.starts_with(&format!("| {name} |")))
                .unwrap_or_else(|| panic!("{command}: no {name} row in {report}"));
            let cells: Vec<&str> = row.split('|').map(str::trim).collect();
            let model_s: f64 = cells[4].parse().unwrap();
            assert!(
                (model_s / thesis_s - 1.0).abs() < 0.05,
                "{name}: {model_s} against the thesis's {thesis_s}: {row}"
            );
            let ratio: f64 = cells[6].parse().unwrap();
            assert!((ratio - 1.0).abs() < 0.05, "{row}");
        }
        // The exact figures of the formulas: T_v = 1024·(138 + 4·399) cycles, T_sc 103 M.
        assert!(report.contains("| T_v | P_t·(138 + E·399) | 1.78 M | 0.089 |"));
        assert!(report.contains("| 103.91 M | 5.196 |"), "{report}");
        assert!(
            report.contains("\ndepth 5 (32 leaves): 512 polygons in view, Dc 1.0, 500x500, 1 frame, a processor per process: predicted 0.212 s"),
            "{report}"
        );
    }
}

#[test]
fn calibration_is_kept_with_its_machine_and_judged_by_it() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let start = Instant::now();
    let out = sh(&format!("{} chart calibrate", cached(&cache)), b"");
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(start.elapsed() < Duration::from_secs(20));
    let err = text(&out.stderr);
    let file = cache.join("polypipe/model.toml");
    assert!(
        err.starts_with("chart: calibrating the cost model for this machine (at most 20 s)…\n"),
        "{err}"
    );
    assert!(err.contains(&format!("s: {}\n", file.display())), "{err}");
    // The constants, printed: a line a stage.
    let table = text(&out.stdout);
    for stage in [
        "viewxf (text)",
        "clip",
        "splitter",
        "persp",
        "hse",
        "merge",
        "start-up",
    ] {
        assert!(
            table.lines().any(|l| l.starts_with(stage)),
            "{stage}: {table}"
        );
    }
    // The file names the machine: its CPU model and cores, the binaries' version.
    let kept = std::fs::read_to_string(&file).unwrap();
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .unwrap()
        .lines()
        .find(|l| l.starts_with("model name"))
        .map(|l| l.split_once(':').unwrap().1.trim().to_string());
    if let Some(cpu) = cpu {
        assert!(kept.contains(&format!("cpu = \"{cpu}\"")), "{kept}");
    }
    // The machine's cores are those online, whatever this process's affinity or a
    // container's CPU quota (which the standard library's available_parallelism counts,
    // and `taskset -c 0` or a CI runner's cgroup lowers): getconf's count, or the
    // available ones where more are available than getconf says.
    let online = Command::new("getconf")
        .arg("_NPROCESSORS_ONLN")
        .output()
        .ok()
        .and_then(|o| text(&o.stdout).trim().parse::<usize>().ok());
    let available = std::thread::available_parallelism().unwrap().get();
    let cores = online.unwrap_or(available).max(available);
    assert!(kept.contains(&format!("\ncores = {cores}\n")), "{kept}");
    assert!(kept.contains("version = \"0.1.0\""), "{kept}");

    let status = |cache: &Path| text(&sh(&format!("{} plan status", cached(cache)), b"").stdout);
    assert!(
        status(&cache).starts_with("calibrated: "),
        "{}",
        status(&cache)
    );
    // --depth auto plans with it, and says nothing of calibration.
    let auto = sh(
        &format!(
            "{} scripts/render.sh --stats examples/penetrating.txt",
            cached(&cache)
        ),
        b"",
    );
    let line = text(&auto.stderr).lines().next().unwrap_or("").to_string();
    assert!(line.starts_with("render: depth auto chose 0 ("), "{line}");
    assert_eq!(pipeline_tests::stat(&text(&auto.stderr), "depth_auto"), 0);
    assert!(!line.contains("calibrat"), "{line}");

    // Rebuilt binaries: stale (still this machine's, planned with, and said so).
    let binaries = kept
        .lines()
        .find(|l| l.starts_with("binaries = "))
        .unwrap()
        .to_string();
    std::fs::write(&file, kept.replace(&binaries, "binaries = \"0000\"")).unwrap();
    assert_eq!(
        status(&cache).lines().next().unwrap(),
        "stale calibration (the binaries were rebuilt since)"
    );
    let plan = sh(
        &format!("{} plan depth examples/penetrating.txt", cached(&cache)),
        b"",
    );
    assert!(text(&plan.stdout).ends_with("; calibration stale: the binaries were rebuilt since)\n"));
    // --depth auto still plans with it, and says so under --stats.
    let auto = sh(
        &format!(
            "{} scripts/render.sh --stats examples/penetrating.txt",
            cached(&cache)
        ),
        b"",
    );
    let line = text(&auto.stderr).lines().next().unwrap_or("").to_string();
    assert!(
        line.starts_with("render: depth auto chose ")
            && line.ends_with("; calibration stale: the binaries were rebuilt since)"),
        "{line}"
    );
    // Another machine's (other cores): foreign, not used; the repository's file instead.
    std::fs::write(
        &file,
        kept.replace(&format!("\ncores = {cores}\n"), "\ncores = 977\n"),
    )
    .unwrap();
    assert!(
        status(&cache).starts_with("not calibrated on this machine (made on "),
        "{}",
        status(&cache)
    );
    let plan = sh(
        &format!("{} plan depth examples/penetrating.txt", cached(&cache)),
        b"",
    );
    assert!(
        text(&plan.stdout).ends_with(
            "; uncalibrated: bench/model.toml's constants; `chart calibrate` fits this machine's)\n"
        ),
        "{}",
        text(&plan.stdout)
    );
    // A chart run refits a foreign one first.
    let out_dir = dir.path().join("out");
    let run = sh(
        &format!(
            "{} chart --root . -o {} --quick --methods zbuf examples/penetrating.txt@40x30",
            cached(&cache),
            out_dir.display()
        ),
        b"",
    );
    assert!(run.status.success(), "{}", text(&run.stderr));
    assert!(text(&run.stderr).starts_with("chart: calibrating the cost model"));
    assert!(status(&cache).starts_with("calibrated: "));
}

#[test]
fn uncalibrated_depth_auto_uses_the_fallback_and_says_so_under_stats_only() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("empty");
    let out = sh(
        &format!(
            "{} scripts/render.sh --stats examples/penetrating.txt",
            cached(&cache)
        ),
        b"",
    );
    assert!(out.status.success());
    let err = text(&out.stderr);
    // With a core or less for the render (a one-CPU runner, a container's quota,
    // `taskset -c 0`), depth auto is 0 without asking the model, calibrated or not, and
    // says that instead.
    let said = if pipeline_tests::one_core_for_render() {
        format!("render: {}", render::auto::ONE_CORE)
    } else {
        "; uncalibrated: bench/model.toml's constants; `chart calibrate` fits this machine's)"
            .to_string()
    };
    assert!(err.lines().next().unwrap().ends_with(&said), "{err}");
    // Not a terminal: nothing said without --stats, nothing started, nothing kept.
    let out = sh(
        &format!(
            "{} scripts/render.sh examples/penetrating.txt",
            cached(&cache)
        ),
        b"",
    );
    assert!(
        out.status.success() && out.stderr.is_empty(),
        "{}",
        text(&out.stderr)
    );
    assert!(!cache.exists());
}

#[test]
fn choose_depth_states_its_rule_and_plans_for_cores_and_hosts() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("fill.txt");
    let made = sh(
        &format!(
            "scene environment --text --seed 2 --polygons 10000 --depth-complexity 10 --size 1920x1080 > {}",
            scene.display()
        ),
        b"",
    );
    assert!(made.status.success());
    let plan = |args: &str| {
        let out = sh(
            &format!(
                "plan depth --model bench/model.toml --load 0 --size 1920x1080 {args} {}",
                scene.display()
            ),
            b"",
        );
        assert!(out.status.success(), "{}", text(&out.stderr));
        let line = text(&out.stdout);
        let depth: u8 = line.split(' ').next().unwrap().parse().unwrap();
        (depth, line)
    };
    let rule =
        "; rule: a deeper tree only when predicted at least 5% faster than the best shallower one)\n";
    let (one, line) = plan("--cores 1");
    assert_eq!(one, 0, "{line}");
    assert!(line.ends_with(rule), "{line}");
    assert!(line.contains(", 1 core: predicted "), "{line}");
    // More cores, a deeper tree; 64 cores deeper still.
    let (many, line) = plan("--cores 64");
    assert!(many >= 2, "{line}");
    // The old name says the same.
    let alias = sh(
        &format!(
            "chart choose-depth --model bench/model.toml --load 0 --size 1920x1080 --cores 64 {}",
            scene.display()
        ),
        b"",
    );
    assert_eq!(text(&alias.stdout), line);
    // Four hosts: every host a subtree, so depth 2 at least, whatever the cores here.
    let (hosts, line) = plan("--cores 1 --hosts 4 --link-gbps 10");
    assert!(hosts >= 2, "{line}");
    assert!(
        line.contains("1 core here, 4 hosts of 1 cores at 10000 Mb/s"),
        "{line}"
    );
}

/// A text environment of `polygons` quads on stdin-sized scales.
fn environment(dir: &Path, polygons: u32, frames: u32) -> std::path::PathBuf {
    let scene = dir.join(format!("env-{polygons}-{frames}.txt"));
    let made = sh(
        &format!(
            "scene environment --text --seed 7 --polygons {polygons} --frames {frames} --depth-complexity 3 > {}",
            scene.display()
        ),
        b"",
    );
    assert!(made.status.success());
    scene
}

#[test]
fn a_stream_longer_than_the_sample_is_planned_from_it_and_rendered_whole() {
    let dir = tempfile::tempdir().unwrap();
    // About 1.3 MB of text: the sample is its first 512 KiB.
    let scene = environment(dir.path(), 5000, 1);
    assert!(std::fs::metadata(&scene).unwrap().len() > 1_000_000);
    let stream = std::fs::read(&scene).unwrap();
    let out = sh(
        &format!(
            "{} scripts/render.sh --stats -",
            cached(&dir.path().join("c"))
        ),
        &stream,
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let err = text(&out.stderr);
    let depth = pipeline_tests::stat(&err, "depth_auto");
    // The frame is the one the file gives at that depth (and at depth 0: every depth
    // draws the same bytes): the sample and the rest of the stream reached viewxf whole.
    let at = sh(
        &format!("scripts/render.sh --depth {depth} {}", scene.display()),
        b"",
    );
    assert!(
        out.stdout == at.stdout,
        "not the file's frame at depth {depth}"
    );
    let at0 = sh(
        &format!("scripts/render.sh --depth 0 {}", scene.display()),
        b"",
    );
    assert!(out.stdout == at0.stdout);
}

#[test]
fn a_live_source_s_first_frame_comes_out_at_once() {
    // A movie written a frame at a time, a second apart, as `scene … | render.sh - |
    // ffmpeg` would be fed: the first frame must come out long before the source ends.
    let dir = tempfile::tempdir().unwrap();
    let scene = std::fs::read_to_string(repo_root().join("examples/penetrating.txt")).unwrap();
    let body = scene.trim_end().strip_suffix("END").unwrap();
    let mut render = Command::new("bash")
        .args(["-c", "exec scripts/render.sh --size 100x100 -"])
        .current_dir(repo_root())
        .env("POLYPIPE_BIN", pipeline_tests::bin_dir())
        .env("XDG_CACHE_HOME", dir.path())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut input = render.stdin.take().unwrap();
    let mut output = render.stdout.take().unwrap();
    // render.sh started and waiting on the stream.
    std::thread::sleep(Duration::from_millis(500));
    input
        .write_all(format!("{body}NEXT.FRAME\n").as_bytes())
        .unwrap();
    input.flush().unwrap();
    // "P6\n100 100\n255\n" and the pixels.
    let frame = 15 + 100 * 100 * 3;
    // The first frame must come while the source is still open and silent: a render that
    // waited for more of it (a full sample, or the stream's end) would never send it. On
    // an idle machine it comes in about 0.2 s (the sample's patience, then the render);
    // the bound is that of a render held up, not of a loaded machine's scheduling.
    let (tx, rx) = std::sync::mpsc::channel();
    let reader = std::thread::spawn(move || {
        let mut got = vec![0u8; frame];
        let first = output.read_exact(&mut got);
        let _ = tx.send(());
        (first.map(|()| got), output)
    });
    assert!(
        rx.recv_timeout(Duration::from_secs(60)).is_ok(),
        "no first frame 60 s after it was written, the source still open"
    );
    let (got, mut output) = reader.join().unwrap();
    let got = got.unwrap();
    // The rest of the movie, then its end.
    let second = body.lines().skip(1).collect::<Vec<_>>().join("\n");
    input
        .write_all(format!("{second}\nEND\n").as_bytes())
        .unwrap();
    drop(input);
    let mut rest = Vec::new();
    output.read_to_end(&mut rest).unwrap();
    assert!(render.wait().unwrap().success());
    assert_eq!(rest.len(), frame, "two frames in all");
    assert!(got.starts_with(b"P6\n100 100\n255\n"));
}

#[test]
fn chart_o_an_existing_file_says_what_o_wants() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("results");
    std::fs::write(&file, "mine").unwrap();
    let out = sh(
        &format!("chart -o {} examples/penetrating.txt", file.display()),
        b"",
    );
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        text(&out.stderr),
        format!(
            "chart: -o {0}: {0} is a file; -o names a folder for the CSV files and pictures (a new one, or one to write into)\n",
            file.display()
        )
    );
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine");
}

#[test]
fn chart_sh_runs_cargo_only_when_a_binary_is_stale() {
    // A cargo that only says it was called: once the binaries are current (the first
    // run's cargo, if any, brings render.sh's stamp up to date), chart.sh does not call
    // it again.
    let dir = tempfile::tempdir().unwrap();
    let fake = dir.path().join("cargo");
    let log = dir.path().join("called");
    std::fs::write(
        &fake,
        format!("#!/bin/sh\necho \"$@\" >> {}\n", log.display()),
    )
    .unwrap();
    let mut perms = std::fs::metadata(&fake).unwrap().permissions();
    std::os::unix::fs::PermissionsExt::set_mode(&mut perms, 0o755);
    std::fs::set_permissions(&fake, perms).unwrap();
    let run = || {
        let out = sh(
            &format!(
                "env -u POLYPIPE_BIN PATH={}:$PATH CARGO_TARGET_DIR={} scripts/chart.sh thesis",
                dir.path().display(),
                pipeline_tests::bin_dir().parent().unwrap().display()
            ),
            b"",
        );
        assert!(out.status.success(), "{}", text(&out.stderr));
    };
    run();
    let _ = std::fs::remove_file(&log);
    run();
    assert!(
        !log.exists(),
        "cargo was run: {:?}",
        std::fs::read_to_string(&log)
    );
}

#[test]
fn depth_auto_with_hosts_gives_every_host_a_subtree() {
    // A "host" reached by running the command here (POLYPIPE_SSH: the host's name is
    // dropped): four hosts, so the tree is at least two levels deep, and the frames are a
    // local run's. The planner said so (before the fix, depth 0, and hosts idle).
    let dir = tempfile::tempdir().unwrap();
    let fake = dir.path().join("here-ssh");
    std::fs::write(&fake, "#!/bin/bash\nshift\nexec bash -c \"$1\"\n").unwrap();
    let mut perms = std::fs::metadata(&fake).unwrap().permissions();
    std::os::unix::fs::PermissionsExt::set_mode(&mut perms, 0o755);
    std::fs::set_permissions(&fake, perms).unwrap();
    let scene = environment(dir.path(), 2000, 1);
    let out = sh(
        &format!(
            "{} POLYPIPE_SSH={} scripts/render.sh --hosts a,b,c,d --stats {}",
            cached(&dir.path().join("c")),
            fake.display(),
            scene.display()
        ),
        b"",
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let err = text(&out.stderr);
    let line = err.lines().next().unwrap();
    let depth = pipeline_tests::stat(&err, "depth_auto");
    assert!(depth >= 2, "{line}");
    assert!(line.contains(" here, 4 hosts of "), "{line}");
    assert!(err.contains("on host d"), "every host had a subtree: {err}");
    let at0 = sh(
        &format!("scripts/render.sh --depth 0 {}", scene.display()),
        b"",
    );
    assert!(out.stdout == at0.stdout);
}

/// Watched from a terminal (a pseudo-terminal of `script`, util-linux), the first
/// `--depth auto` on an uncalibrated machine says once that the model is another
/// machine's and that this one's is being fitted in the background; the next run says
/// nothing. A calibration already under way (a young lock file) keeps the test from
/// starting one: the start is `costmodel::cli::background`'s, the telling this test's. At
/// 400×400 no scene file is too small to ask the model about (`render::auto::tiny_bound`).
#[test]
fn on_a_terminal_the_first_uncalibrated_depth_auto_says_so_once() {
    if pipeline_tests::one_core_for_render() {
        // With a core or less, depth auto is 0 without the model, and nothing to tell.
        pipeline_tests::skip("one core: depth auto does not ask the model");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    std::fs::create_dir_all(cache.join("polypipe")).unwrap();
    std::fs::write(cache.join("polypipe/calibrating"), b"1").unwrap();
    let png = dir.path().join("out.png");
    let line = format!(
        "{} POLYPIPE_LOAD=0 {} --no-progress --size 400x400 -o {} {}",
        cached(&cache),
        repo_root().join("scripts/render.sh").display(),
        png.display(),
        repo_root().join("examples/penetrating.txt").display()
    );
    pipeline_tests::bin_dir();
    let run = || {
        let out = Command::new("script")
            .args(["-qec", &line, "/dev/null"])
            .stdin(Stdio::null())
            .output()
            .expect("script (util-linux) to run render on a terminal");
        assert!(out.status.success(), "{}", text(&out.stdout));
        text(&out.stdout).replace('\r', "")
    };
    assert_eq!(
        run(),
        "render: the cost model is not calibrated on this machine: --depth auto uses bench/model.toml's constants (another machine's) until this machine's are fitted, now, in the background (at most 20 s; `chart calibrate` to do it yourself)\n"
    );
    assert_eq!(run(), "");
    assert!(png.is_file());
}
