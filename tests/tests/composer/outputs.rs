//! What the pipeline's pictures become outside it: numbered PNG files from `-o`, the
//! README's ffmpeg movie recipe, and netpbm reading zbuf's PPM stream.
//!
//! ffmpeg and netpbm are not needed to build or test polypipe; when they are not on PATH
//! their tests print "skipped: … not installed" and pass.

use pipeline_tests::{bin_dir, parse_ppm_stream, repo_root, run, sh, Frame};
use std::path::{Path, PathBuf};

/// Whether an executable named `name` is on PATH.
fn on_path(name: &str) -> bool {
    use std::os::unix::fs::PermissionsExt;
    std::env::var_os("PATH").is_some_and(|paths| {
        std::env::split_paths(&paths).any(|dir| {
            std::fs::metadata(dir.join(name))
                .is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
        })
    })
}

fn quote(path: &Path) -> String {
    format!("'{}'", path.display())
}

/// A decoded PNG file as a frame.
fn read_png(path: &Path) -> Frame {
    let img = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8();
    Frame {
        width: img.width() as usize,
        height: img.height() as usize,
        pixels: img.pixels().map(|p| p.0).collect(),
    }
}

/// A 100-frame movie through render.sh with `-o dir/frame%03d.png` is 100 numbered PNG
/// files holding exactly the frames that the same run writes as a PPM stream without -o.
#[test]
fn movie_to_numbered_png_files() {
    let dir = tempfile::tempdir().unwrap();
    let pattern = dir.path().join("frame%03d.png");
    let movie = "scene spheres --frames 100 | scripts/render.sh --size 160x120 -";
    let stdout = run(&format!("{movie} -o {}", quote(&pattern)));
    assert!(stdout.is_empty(), "-o writes nothing on stdout");

    let stream = parse_ppm_stream(&run(movie)).unwrap();
    assert_eq!(stream.len(), 100);
    // The spheres move: consecutive frames differ, so a file holding the wrong frame
    // would be caught below.
    assert!(stream.windows(2).all(|w| w[0] != w[1]));

    for (i, want) in stream.iter().enumerate() {
        let path = dir.path().join(format!("frame{i:03}.png"));
        let got = read_png(&path);
        assert_eq!((got.width, got.height), (160, 120), "{}", path.display());
        assert!(
            got == *want,
            "{} differs from frame {i} of the stream",
            path.display()
        );
    }
    assert!(!dir.path().join("frame100.png").exists());
    let files = std::fs::read_dir(dir.path()).unwrap().count();
    assert_eq!(files, 100, "exactly the 100 frames, nothing else");
}

/// The ```sh block of README.md's `section` that contains `needle`.
fn readme_command(section: &str, needle: &str) -> String {
    readme_blocks(section)
        .into_iter()
        .find(|block| block.contains(needle))
        .unwrap_or_else(|| panic!("no ```sh block with {needle:?} in README's {section}"))
}

/// The movie recipe of README.md's "Viewing the output", run as written (only the name
/// of the mp4 it writes is moved into a temporary folder), makes an mp4 of 100 frames.
#[test]
fn readme_ffmpeg_recipe_makes_a_100_frame_movie() {
    let recipe = readme_command("## Viewing the output", "ffmpeg");
    assert!(
        recipe.contains("--frames 100") && recipe.trim_end().ends_with(" spheres.mp4"),
        "the recipe changed; update this test: {recipe}"
    );
    if !on_path("ffmpeg") {
        pipeline_tests::skip("ffmpeg not installed (apt-get install ffmpeg)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mp4 = dir.path().join("spheres.mp4");
    let script = recipe
        .trim_end()
        .strip_suffix("spheres.mp4")
        .unwrap()
        .to_string()
        + &quote(&mp4);
    run(&script);
    let size = std::fs::metadata(&mp4).map(|m| m.len()).unwrap_or(0);
    assert!(size > 1000, "{} is {size} bytes", mp4.display());

    if !on_path("ffprobe") {
        pipeline_tests::skip("ffprobe not installed: the mp4's frames are not counted");
        return;
    }
    let probe = run(&format!(
        "ffprobe -v error -count_frames -select_streams v:0 \
         -show_entries stream=nb_read_frames,width,height -of csv=p=0 {}",
        quote(&mp4)
    ));
    assert_eq!(String::from_utf8_lossy(&probe).trim(), "500,500,100");
}

/// netpbm reads zbuf's PPM stream directly (every frame), and a frame survives a round
/// trip through PNG with netpbm's own converters pixel for pixel.
#[test]
fn netpbm_reads_the_ppm_stream_and_round_trips_png() {
    let tools = ["pnmtopng", "pngtopnm", "pamfile"];
    if let Some(missing) = tools.iter().find(|t| !on_path(t)) {
        pipeline_tests::skip(&format!("netpbm not installed (no {missing})"));
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let stream_path: PathBuf = dir.path().join("spheres.ppm");
    let stream = run(&format!(
        "scene spheres --frames 3 | scripts/render.sh --size 64x48 - | tee {}",
        quote(&stream_path)
    ));
    let frames = parse_ppm_stream(&stream).unwrap();
    assert_eq!(frames.len(), 3);

    let info = String::from_utf8(run(&format!(
        "pamfile -allimages < {}",
        quote(&stream_path)
    )))
    .unwrap();
    let images: Vec<&str> = info.lines().collect();
    assert_eq!(images.len(), 3, "{info}");
    for (i, line) in images.iter().enumerate() {
        assert!(
            line.contains(&format!("Image {i}:")) && line.contains("PPM raw, 64 by 48"),
            "{line}"
        );
    }

    // pnmtopng takes the first image of the stream.
    let png = dir.path().join("first.png");
    run(&format!(
        "pnmtopng < {} > {}",
        quote(&stream_path),
        quote(&png)
    ));
    assert!(
        read_png(&png) == frames[0],
        "pnmtopng's PNG differs from frame 0"
    );
    let back = parse_ppm_stream(&run(&format!("pngtopnm {}", quote(&png)))).unwrap();
    assert_eq!(back.len(), 1);
    assert!(back[0] == frames[0], "PPM → PNG → PPM changed the pixels");
}

/// The ```sh blocks of README.md's `section`, each as its text.
fn readme_blocks(section: &str) -> Vec<String> {
    let readme = std::fs::read_to_string(repo_root().join("README.md")).unwrap();
    let start = readme
        .find(&format!("\n{section}\n"))
        .unwrap_or_else(|| panic!("README.md has no section {section:?}"));
    let body = &readme[start + section.len() + 2..];
    let body = &body[..body.find("\n## ").unwrap_or(body.len())];
    body.split("```sh\n")
        .skip(1)
        .map(|block| block[..block.find("```").expect("closed code block")].to_string())
        .collect()
}

/// Every picture of README.md's Gallery is what the command above it makes today: each
/// command is run with its `-o docs/images/NAME.png` moved into a temporary folder, and
/// the result must have exactly the committed picture's pixels. The pictures are small
/// (under 64 KiB) and every one is shown in the README.
#[test]
fn gallery_pictures_are_what_their_commands_make() {
    let readme = std::fs::read_to_string(repo_root().join("README.md")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = format!("{}/", dir.path().display());
    let mut checked = Vec::new();
    for block in readme_blocks("## Gallery") {
        // Every picture the block writes (a block may write several, e.g. a row of
        // shadings).
        let names: Vec<String> = block
            .match_indices("-o docs/images/")
            .map(|(at, m)| {
                block[at + m.len()..]
                    .split_whitespace()
                    .next()
                    .unwrap()
                    .to_string()
            })
            .collect();
        if names.is_empty() {
            continue;
        }
        // B: the binaries' folder (the README's target/bin is a link render.sh makes).
        run(&format!(
            "B={}\n{}",
            quote(bin_dir()),
            block.replace("docs/images/", &out)
        ));
        for name in names {
            assert!(name.ends_with(".png"), "{name}");
            let committed = repo_root().join("docs/images").join(&name);
            let size = std::fs::metadata(&committed)
                .unwrap_or_else(|e| panic!("{}: {e}", committed.display()))
                .len();
            assert!(size < 64 * 1024, "{name} is {size} bytes");
            assert!(
                readme.contains(&format!("(docs/images/{name})"))
                    || readme.contains(&format!("src=\"docs/images/{name}\"")),
                "{name} is rendered but not shown"
            );
            let made = read_png(&dir.path().join(&name));
            assert!(
                made == read_png(&committed),
                "docs/images/{name} is not what its README command makes now; run the \
                 command in README.md's Gallery to update it (and look at it)"
            );
            checked.push(name);
        }
    }
    assert!(checked.len() >= 13, "only {checked:?}");

    // The movie with --progress: stderr is a pipe here, so --progress prints nothing.
    let movie = readme_blocks("## Gallery")
        .into_iter()
        .find(|b| b.contains("--progress"))
        .expect("a Gallery block using zbuf --progress");
    let script = format!(
        "B={}\n{}",
        quote(bin_dir()),
        movie.replace("-o ico%03d.png", &format!("-o {out}ico%03d.png"))
    );
    assert!(
        script.contains(&out),
        "the movie's -o changed; update this test"
    );
    let result = sh(&script, b"");
    assert!(result.status.success(), "{result:?}");
    assert_eq!(String::from_utf8_lossy(&result.stderr), "");
    let frames = (0..)
        .take_while(|i| dir.path().join(format!("ico{i:03}.png")).exists())
        .count();
    assert_eq!(frames, 100);
}

/// `scene ARGS…` into `dir/NAME`.
fn scene_file(dir: &Path, name: &str, args: &[&str]) -> PathBuf {
    let out = std::process::Command::new(bin_dir().join("scene"))
        .args(args)
        .output()
        .unwrap();
    assert!(out.status.success(), "scene {args:?}");
    let path = dir.join(name);
    std::fs::write(&path, out.stdout).unwrap();
    path
}

/// The names of the files in `dir`, sorted.
fn names_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map(|d| {
            d.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    names
}

/// Each file in `dir` a whole frame named `f%04d.png` that equals that frame of
/// `reference`: no temporary, no empty or cut file.
fn only_whole_frames(dir: &Path, reference: &[Frame], what: &str) {
    for name in names_in(dir) {
        let number: usize = name
            .strip_prefix('f')
            .and_then(|n| n.strip_suffix(".png"))
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("{what}: a file that is no frame left: {name}"));
        let frame = read_png(&dir.join(&name));
        assert!(
            frame == reference[number],
            "{what}: {name} is not that frame"
        );
    }
}

#[test]
fn frames_stopped_by_sigterm_or_sigint_are_whole_or_absent() {
    let dir = tempfile::tempdir().unwrap();
    let movie = scene_file(dir.path(), "movie.pp", &["spheres", "--frames", "120"]);
    let render = |out: &Path| {
        let mut cmd = std::process::Command::new(bin_dir().join("render"));
        cmd.args(["--size", "96x96", "--depth", "0", "-o"])
            .arg(out.join("f%04d.png"))
            .arg(&movie)
            .stdin(std::process::Stdio::null())
            .stderr(std::process::Stdio::null());
        cmd
    };
    let whole = dir.path().join("whole");
    let start = std::time::Instant::now();
    assert!(render(&whole).status().unwrap().success());
    let took = start.elapsed();
    let reference: Vec<Frame> = (0..120)
        .map(|i| read_png(&whole.join(format!("f{i:04}.png"))))
        .collect();
    // 20 moments spread over the run, in an order from a seed the test prints.
    let seed = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .subsec_nanos() as u64;
    println!("seed {seed}");
    let mut x = seed | 1;
    for run in 0..20 {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        let at = took.mul_f64((x % 1000) as f64 / 1000.0);
        let out = dir.path().join(format!("run{run}"));
        let mut child = render(&out).spawn().unwrap();
        std::thread::sleep(at);
        let signal = if run % 2 == 0 { "-TERM" } else { "-INT" };
        std::process::Command::new("kill")
            .args([signal, &child.id().to_string()])
            .status()
            .unwrap();
        let status = child.wait().unwrap();
        only_whole_frames(
            &out,
            &reference,
            &format!("seed {seed}, run {run}, {at:?}: {status}"),
        );
    }
}

/// A 64 KiB tmpfs at `dir`, unmounted when dropped; `None` (the test skips, saying so)
/// where mount is refused, but not under CI=true, where the tests run as root.
struct SmallDisk(PathBuf);

impl SmallDisk {
    fn new(dir: &Path) -> Option<SmallDisk> {
        std::fs::create_dir_all(dir).unwrap();
        let ok = std::process::Command::new("mount")
            .args(["-t", "tmpfs", "-o", "size=64k", "tmpfs"])
            .arg(dir)
            .status()
            .is_ok_and(|s| s.success());
        if ok {
            return Some(SmallDisk(dir.to_path_buf()));
        }
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "mount -t tmpfs refused under CI=true"
        );
        println!("SKIPPED: mount -t tmpfs refused (not root?)");
        None
    }
}

impl Drop for SmallDisk {
    fn drop(&mut self) {
        let _ = std::process::Command::new("umount").arg(&self.0).status();
    }
}

#[test]
fn on_a_full_disk_the_file_is_named_and_nothing_cut_is_left() {
    let dir = tempfile::tempdir().unwrap();
    let Some(disk) = SmallDisk::new(&dir.path().join("disk")) else {
        return;
    };
    let movie = scene_file(dir.path(), "movie.pp", &["spheres", "--frames", "40"]);
    let lines = scene_file(dir.path(), "slivers.pp", &["slivers", "2000"]);
    let one = scene_file(dir.path(), "one.pp", &["spheres"]);
    let render = |args: &[&str], scene: &Path| {
        std::process::Command::new(bin_dir().join("render"))
            .args(args)
            .arg(scene)
            .stdin(std::process::Stdio::null())
            .output()
            .unwrap()
    };
    let at = |name: &str| disk.0.join(name).display().to_string();
    // PNG frames: some fit, the one that does not is named and left out.
    let reference_dir = dir.path().join("reference");
    let size = ["--size", "160x160", "--depth", "0"];
    let out = render(
        &[
            &size[..],
            &["-o", &reference_dir.join("f%04d.png").display().to_string()],
        ]
        .concat(),
        &movie,
    );
    assert!(out.status.success());
    let reference: Vec<Frame> = (0..40)
        .map(|i| read_png(&reference_dir.join(format!("f{i:04}.png"))))
        .collect();
    let cases: [(Vec<String>, &Path, &str); 3] = [
        (vec!["-o".into(), at("f%04d.png")], &movie, ".png"),
        // One frame, too big for the disk (160×160 is 77 kB as a PPM).
        (vec!["-o".into(), at("f.ppm")], &one, ".ppm"),
        (
            vec!["--hidden-line".into(), "-o".into(), at("lines.svg")],
            &lines,
            ".svg",
        ),
    ];
    for (args, scene, ext) in cases {
        for name in names_in(&disk.0) {
            std::fs::remove_file(disk.0.join(name)).unwrap();
        }
        let args: Vec<&str> = size
            .iter()
            .copied()
            .chain(args.iter().map(String::as_str))
            .collect();
        let out = render(&args, scene);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(3), "{ext}: {err}");
        let left = names_in(&disk.0);
        match ext {
            ".png" => {
                let cut = (0..40)
                    .find(|i| !left.contains(&format!("f{i:04}.png")))
                    .expect("a frame the disk could not hold");
                assert!(
                    err.contains(&format!(
                        "cannot write {}: No space left on device\n",
                        at(&format!("f{cut:04}.png"))
                    )),
                    "{err}"
                );
                only_whole_frames(&disk.0, &reference, "full disk");
            }
            _ => {
                let file = if ext == ".ppm" { "f.ppm" } else { "lines.svg" };
                assert!(
                    err.contains(&format!(
                        "cannot write {}: No space left on device\n",
                        at(file)
                    )),
                    "{err}"
                );
                assert!(left.is_empty(), "{ext}: {left:?}");
            }
        }
    }
}
