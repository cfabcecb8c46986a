//! The chart's runs (docs/DESIGN.md, "Measures"): every method of [`crate::methods`] on
//! every scene, through the real `scripts/render.sh`, timed as a whole process tree, its
//! frames measured against `zspec` (point sampling: `error_fraction`) and `zspec
//! --samples 16` (`edge_rmse` over the edge pixels, `rmse` over all pixels); and the cost
//! model's prediction beside zbuf's measured time at depths 0 to 4.

use crate::error::{Context, Error, Result};
use crate::look::{self, Environment};
use crate::measure::{self, Usage};
use crate::methods::{self, Draws, Input, Method};
use crate::model::{self, Constants};
use crate::stats::{self, Stats};
use serde::{Deserialize, Serialize};
use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// A scene to chart, and the screen it is rendered on.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    pub path: PathBuf,
    /// Its name in the CSV and on the chart (the file's stem).
    pub name: String,
    pub width: u32,
    pub height: u32,
}

impl Scene {
    /// `PATH` or `PATH@WxH` (the screen; else `default_size`).
    ///
    /// The part after the last `@` is a size when it could be meant as one (it starts with
    /// a digit and is no folder), and then it must be a good one: `fill.txt@0x5` is a
    /// usage error in `--size`'s words, not a scene file of that name that is missing. A
    /// file whose name has such an `@` in it is still the file when it exists.
    pub fn parse(arg: &str, default_size: (u32, u32)) -> Result<Scene> {
        let (path, size) = match arg.rsplit_once('@') {
            Some((p, s)) if meant_as_size(s) && !Path::new(arg).exists() => {
                let size = proto::camera::parse_size(s)
                    .map_err(|why| Error::Usage(format!("invalid size in scene '{arg}': {why}")))?;
                (p, size)
            }
            _ => (arg, default_size),
        };
        let (width, height) = size;
        let path = PathBuf::from(path);
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .ok_or_else(|| Error::Usage(format!("no scene file in '{arg}'")))?;
        Ok(Scene {
            path,
            name,
            width,
            height,
        })
    }

    pub fn size(&self) -> String {
        format!("{}x{}", self.width, self.height)
    }
}

/// Whether the text after a scene's `@` is meant as `WxH`: it starts with a digit and
/// names no folder (`b@c.txt` is a file's name).
fn meant_as_size(s: &str) -> bool {
    s.starts_with(|c: char| c.is_ascii_digit()) && !s.contains('/')
}

/// One row of `results.csv`.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Row {
    pub scene: String,
    pub method: String,
    pub depth: u8,
    pub size: String,
    /// Polygons in the scene (all frames).
    pub polygons: u64,
    pub frames: u64,
    /// The medians of the timed runs: wall seconds of the whole render, start-up
    /// included, and CPU seconds of its process tree.
    pub wall_s: f64,
    pub cpu_s: f64,
    /// The time the figures plot: the median CPU seconds (`cpu_s`) less the start-up
    /// (`startup_s`), at least 0, and the least and the most of the runs less the same
    /// start-up (the spread bar). CPU, not wall: on a machine shared with other work a
    /// run's wall time is mostly its wait for a core.
    #[serde(default)]
    pub time_s: f64,
    #[serde(default)]
    pub time_lo_s: f64,
    #[serde(default)]
    pub time_hi_s: f64,
    /// The start-up: the median CPU seconds of the same render (method, depth, screen,
    /// input form) of an empty scene, timed between the scene's runs; and its share of
    /// `cpu_s`.
    #[serde(default)]
    pub startup_s: f64,
    #[serde(default)]
    pub startup_share: f64,
    /// Timed runs, interleaved with the other methods' on the scene.
    #[serde(default)]
    pub runs: u32,
    /// Peak memory of the whole process tree, KiB: the sum of its processes' own peaks
    /// (`VmHWM`, sampled from /proc), in the first of the timed runs.
    pub max_rss_kib: u64,
    /// Pixels differing from the point-sampled reference (`zspec`), over all pixels;
    /// empty for a hidden-line method.
    pub error_fraction: Option<f64>,
    /// RMS error (0–255, three channels) over the edge pixels against `zspec --samples 16`.
    pub edge_rmse: Option<f64>,
    /// RMS error over all pixels against `zspec --samples 16` (0–255): the first figure's
    /// accuracy axis. A hidden-line method's is that of its drawing as a picture against
    /// the exact drawing's (`--hidden-line-method continuous`), both stroked black on
    /// white 1 px wide and sampled 16×16 a pixel ([`lines::raster::picture`]).
    #[serde(alias = "rmse")]
    pub rms_16x16: Option<f64>,
    /// A point-sampling method's visibility error: % of pixels whose visible polygon
    /// differs from the exact point-sampled reference ([`crate::visibility`]); empty for
    /// the anti-aliasing and hidden-line methods.
    #[serde(default)]
    pub visibility_error: Option<f64>,
    /// The scene's environment statistics, a frame ([`crate::stats`]): edges E_t, depth
    /// complexity Dc, and its visible complexity (polygons owning a pixel, segments on
    /// the scan lines, and those a scan line).
    #[serde(default)]
    pub edges: f64,
    #[serde(default)]
    pub depth_complexity: f64,
    #[serde(default)]
    pub visible_polygons: f64,
    #[serde(default)]
    pub visible_segments: f64,
    #[serde(default)]
    pub segments_per_line: f64,
    /// A hidden-line method's drawing (empty for the others): the pieces of edges and of
    /// lines of intersection it drew (`<line>`s in its SVGs, all frames), those of them
    /// lines of intersection, and their length in pixels.
    #[serde(default)]
    pub line_pieces: Option<u64>,
    #[serde(default)]
    pub intersection_pieces: Option<u64>,
    #[serde(default)]
    pub line_length_px: Option<f64>,
    /// A hidden-line method's line error, pixels, all frames ([`lines::line_error`]): the
    /// length of the exact drawing (`--hidden-line-method continuous`) that no drawn line
    /// comes within half a pixel of, plus the length drawn that comes within half a pixel
    /// of none of it, intersection lines included.
    #[serde(default)]
    pub line_error_px: Option<f64>,
}

impl Row {
    /// The RMS error against the 16×16 reference, NaN where there is none.
    pub fn rms(&self) -> f64 {
        self.rms_16x16.unwrap_or(f64::NAN)
    }
}

/// What a hidden-line drawing holds: its pieces, those of them lines of intersection, and
/// their length in pixels.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Lines {
    pub pieces: u64,
    pub intersections: u64,
    pub length_px: f64,
}

impl Lines {
    /// Adds the pieces of one SVG as `hiddenline` writes them (`lines::read_svg`: a
    /// `<line>` a piece, or a dashed `<line>` for the pieces of one edge).
    pub fn add_svg(&mut self, svg: &str) -> Result<()> {
        for piece in lines::read_svg(svg).map_err(Error::Data)? {
            self.pieces += 1;
            self.intersections += u64::from(piece.intersection);
            self.length_px += piece.length();
        }
        Ok(())
    }
}

/// The exact hidden-line drawing of a scene, a frame at a time: its pieces and its
/// picture ([`line_picture`]).
pub struct ExactLines {
    pub pieces: Vec<Vec<lines::Segment>>,
    pub pictures: Vec<reference::Image>,
}

/// The pen of the hidden-line drawings' pictures, pixels: `hiddenline`'s default
/// `--stroke-width`, with which render draws them.
pub const LINE_PEN_PX: f64 = 1.0;

/// A hidden-line drawing as the picture it is seen as, for its RMS error: black lines
/// [`LINE_PEN_PX`] wide on white, 16×16 samples a pixel, the 16×16 reference's filter
/// ([`lines::raster::picture`]).
pub fn line_picture(pieces: &[lines::Segment], scene: &Scene) -> reference::Image {
    lines::raster::picture(pieces, scene.width, scene.height, LINE_PEN_PX, 16)
}

/// One row of `model.csv`.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ModelRow {
    pub scene: String,
    pub depth: u8,
    pub predicted_s: f64,
    pub measured_s: f64,
    /// (predicted − measured) / measured.
    pub error: f64,
    pub viewxf_s: f64,
    pub clip_s: f64,
    /// The root node's seconds (0 at depth 0).
    pub splitter_s: f64,
    /// One leaf's.
    pub persp_s: f64,
    pub hse_s: f64,
    pub merge_s: f64,
    /// The slowest stage process (the thesis's bound) and all work over the cores.
    pub slowest_s: f64,
    pub shared_s: f64,
    pub overhead_s: f64,
    pub processes: usize,
    pub bottleneck: String,
    pub polygons_in_view: u64,
    pub depth_complexity: f64,
    /// Other programs' runnable threads when the scene was measured (the load average
    /// less one): the prediction shares the cores with them, as the runs did.
    #[serde(default)]
    pub load: f64,
}

/// One row of `model-extrapolation.csv`: the model's prediction for a scene at a depth on
/// a target this machine cannot measure (more cores; hosts over a link).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Extrapolation {
    pub scene: String,
    /// `N cores`, or `4 hosts × C cores at G Gb/s` (no comma: a CSV field unquoted).
    pub target: String,
    pub depth: u8,
    pub predicted_s: f64,
    /// With hosts: the seconds a host's link is busy.
    pub link_s: f64,
}

/// The model's predictions for `env` at depths 0–6 on 1 to 64 cores, and on four hosts of
/// this machine's cores at 1 and 10 Gb/s (depths 2–6, every host a subtree).
pub fn extrapolate(
    k: &Constants,
    env: &Environment,
    scene: &str,
    cores: usize,
) -> Vec<Extrapolation> {
    use crate::model::{predict_on, Hosts, Target};
    let mut rows = Vec::new();
    for c in [1usize, 2, 4, 8, 16, 32, 64] {
        for depth in 0..=6u8 {
            let p = predict_on(k, env, depth, &Target::cores(c));
            rows.push(Extrapolation {
                scene: scene.to_string(),
                target: format!("{c} core{}", if c == 1 { "" } else { "s" }),
                depth,
                predicted_s: p.total_s,
                link_s: 0.0,
            });
        }
    }
    for gbps in [1.0, 10.0] {
        let target = Target {
            cores,
            load: 0.0,
            hosts: Some(Hosts {
                count: 4,
                cores,
                link_bytes_per_s: gbps * 1e9 / 8.0,
                start_s: 0.1,
            }),
        };
        for depth in target.min_depth()..=6 {
            let p = predict_on(k, env, depth, &target);
            rows.push(Extrapolation {
                scene: scene.to_string(),
                target: format!("4 hosts × {cores} cores at {gbps} Gb/s"),
                depth,
                predicted_s: p.total_s,
                link_s: p.link_s,
            });
        }
    }
    rows
}

/// Where things are, and how to run.
pub struct Setup {
    /// The built binaries (zspec, frames, viewxf, …).
    pub bin: PathBuf,
    /// The `render` binary.
    pub render: PathBuf,
    /// The output folder.
    pub out: PathBuf,
    /// Where the references, rewritten scenes and frames go (`DIR/refs`, or `--work`).
    pub work: PathBuf,
    pub quick: bool,
    /// Only these methods (`--methods`), or all.
    pub only: Option<Vec<String>>,
    /// Timed runs per row (the median is kept).
    pub reps: usize,
    pub cores: usize,
    pub constants: Constants,
}

/// The references of a scene, made once and kept in `DIR/refs` (remade when the scene is
/// newer): the point-sampled picture, the 16×16 one and its edge mask.
struct References {
    point: PathBuf,
    sixteen: PathBuf,
    mask: PathBuf,
}

fn newer(a: &Path, b: &Path) -> bool {
    let m = |p: &Path| std::fs::metadata(p).and_then(|m| m.modified()).ok();
    match (m(a), m(b)) {
        (Some(a), Some(b)) => a > b,
        (Some(_), None) => true,
        _ => false,
    }
}

/// The stages' peak memory summed, KiB, from render's `--times` record of the sums
/// (`@stats render stages=N … peaks_kib=K …`, stagecli::stats).
pub fn peaks_kib(said: &str) -> Option<u64> {
    said.lines()
        .rev()
        .filter_map(stagecli::stats::parse_line)
        .filter_map(Result::ok)
        .find(|r| r.stage() == "render" && r.get("stages").is_some())?
        .count("peaks_kib")
}

/// Runs `cmd` with its stderr in `err` (said in the error when it fails).
fn quiet(cmd: &mut Command, err: &Path) -> Result<Usage> {
    cmd.stderr(File::create(err)?);
    measure::run(cmd).map_err(|e| {
        let said = std::fs::read_to_string(err).unwrap_or_default();
        Error::new(e.kind(), format!("{e}: {}", said.trim()))
    })
}

impl Setup {
    fn refs_dir(&self) -> PathBuf {
        self.work.join("refs")
    }

    fn references(&self, scene: &Scene) -> Result<References> {
        let dir = self.refs_dir();
        std::fs::create_dir_all(&dir)?;
        let stem = format!("{}-{}", scene.name, scene.size());
        let r = References {
            point: dir.join(format!("{stem}.ref1.ppm")),
            sixteen: dir.join(format!("{stem}.ref16.ppm")),
            mask: dir.join(format!("{stem}.mask.ppm")),
        };
        let err = dir.join("zspec.err");
        if newer(&scene.path, &r.point) {
            quiet(
                Command::new(self.bin.join("zspec"))
                    .args(["--size", &scene.size()])
                    .arg(&scene.path)
                    .stdout(File::create(&r.point)?),
                &err,
            )?;
        }
        if newer(&scene.path, &r.sixteen) || newer(&scene.path, &r.mask) {
            quiet(
                Command::new(self.bin.join("zspec"))
                    .args(["--samples", "16", "--edge-mask"])
                    .arg(&r.mask)
                    .args(["--size", &scene.size()])
                    .arg(&scene.path)
                    .stdout(File::create(&r.sixteen)?),
                &err,
            )?;
        }
        Ok(r)
    }

    /// The scene in its own colours ([`crate::visibility`]), made once into `DIR/refs`.
    pub fn coloured(&self, scene: &Scene) -> Result<Scene> {
        let dir = self.refs_dir();
        std::fs::create_dir_all(&dir)?;
        // Named by the scene's file, not its name: `--quick --hard`'s smaller stack is
        // another file of the same name.
        let stem = scene
            .path
            .file_stem()
            .map_or_else(|| scene.name.clone(), |s| s.to_string_lossy().into_owned());
        let path = dir.join(format!("{stem}.coloured.pp"));
        if newer(&scene.path, &path) {
            crate::visibility::recolour(&scene.path, &path)?;
        }
        Ok(Scene {
            path,
            ..scene.clone()
        })
    }

    /// An empty scene (no polygons, one frame) in the form `input` reads, for the
    /// start-up runs: text, or binary (the coloured scenes are binary).
    fn empty(&self, input: Input) -> Result<PathBuf> {
        let dir = self.refs_dir();
        let text = dir.join("empty.txt");
        if !text.exists() {
            std::fs::write(&text, "polypipe 1 world\nEND\n")?;
        }
        if input == Input::Text {
            return Ok(text);
        }
        let binary = dir.join("empty.pp");
        if !binary.exists() {
            quiet(
                Command::new(self.bin.join("frames"))
                    .arg(&text)
                    .stdout(File::create(&binary)?),
                &dir.join("frames.err"),
            )?;
        }
        Ok(binary)
    }

    /// The scene in the form a variant reads (rewritten with `frames` into `DIR/refs`).
    fn input(&self, scene: &Scene, input: Input) -> Result<PathBuf> {
        let (ext, args): (&str, &[&str]) = match input {
            Input::AsGiven => return Ok(scene.path.clone()),
            Input::Text => ("txt", &["--text"]),
            Input::Binary => ("pp", &[]),
        };
        let path = self.refs_dir().join(format!("{}.as.{ext}", scene.name));
        if newer(&scene.path, &path) {
            quiet(
                Command::new(self.bin.join("frames"))
                    .args(args)
                    .arg(&scene.path)
                    .stdout(File::create(&path)?),
                &self.refs_dir().join("frames.err"),
            )?;
        }
        Ok(path)
    }

    /// One render of `input` by `method` at `depth` on the scene's screen, timed: the
    /// first (`first`) writes its frames to `frames` (or its SVGs to `lines-%d.svg`) and
    /// sums its stages' peaks (`--times`), the others write nowhere.
    fn time_once(
        &self,
        scene: &Scene,
        input: &Path,
        method: &Method,
        depth: u8,
        first: bool,
    ) -> Result<Usage> {
        let err = self.work.join("render.err");
        let mut cmd = Command::new(&self.render);
        cmd.args(["--size", &scene.size(), "--depth", &depth.to_string()])
            .args(method.options)
            .arg(input);
        if method.draws == Draws::Lines {
            let name = if first {
                "lines-%d.svg"
            } else {
                "scratch-%d.svg"
            };
            cmd.arg("-o")
                .arg(self.work.join(name))
                .stdout(Stdio::null());
        } else if first {
            cmd.stdout(File::create(self.work.join("frames.ppm"))?);
        } else {
            cmd.stdout(Stdio::null());
        }
        // The first run's memory is the tree's: render's `--times` sums the peaks that
        // its launcher's wait4 gave each stage (a sampler of /proc misses the stages of a
        // render of a few milliseconds); the others run without it.
        if first {
            cmd.arg("--times");
        }
        let mut usage = quiet(&mut cmd, &err)
            .with_context(|| format!("{} at depth {depth} on {}", method.name, scene.name))?;
        if first {
            let said = std::fs::read_to_string(&err).unwrap_or_default();
            if let Some(kib) = peaks_kib(&said) {
                usage.max_rss_kib = kib;
            }
        }
        Ok(usage)
    }

    /// The exact hidden-line drawing of a scene (`--hidden-line-method continuous`), an
    /// SVG's pieces a frame, for the line error, and its pictures, for the RMS error;
    /// drawn once a scene, untimed.
    fn exact_lines(&self, scene: &Scene, frames: u64) -> Result<ExactLines> {
        let err = self.work.join("render.err");
        quiet(
            Command::new(&self.render)
                .args(["--size", &scene.size(), "--hidden-line"])
                .args(["--hidden-line-method", "continuous", "-o"])
                .arg(self.work.join("exact-%d.svg"))
                .arg(&scene.path)
                .stdout(Stdio::null()),
            &err,
        )
        .with_context(|| format!("the exact hidden-line drawing of {}", scene.name))?;
        let mut all = Vec::new();
        for frame in 0..frames.max(1) {
            let path = self.work.join(format!("exact-{frame}.svg"));
            let text = std::fs::read_to_string(&path)
                .with_context(|| format!("{}: {}", scene.name, path.display()))?;
            all.push(lines::read_svg(&text).map_err(Error::Data)?);
            let _ = std::fs::remove_file(&path);
        }
        let pictures = all
            .iter()
            .map(|pieces| line_picture(pieces, scene))
            .collect();
        Ok(ExactLines {
            pieces: all,
            pictures,
        })
    }

    /// The row of a run whose first render wrote its frames (or drawings): its frames
    /// measured against the references, or its drawing counted and scored against the
    /// exact one. The times are filled in by [`finish`].
    #[allow(clippy::too_many_arguments)]
    fn measured(
        &self,
        scene: &Scene,
        env: &Environment,
        stats: &Stats,
        refs: &References,
        exact: &mut Option<ExactLines>,
        method: &Method,
        depth: u8,
        first: Usage,
    ) -> Result<Row> {
        let mut row = Row {
            scene: scene.name.clone(),
            method: method.name.to_string(),
            depth,
            size: scene.size(),
            polygons: env.polygons,
            frames: env.frames,
            wall_s: 0.0,
            cpu_s: 0.0,
            time_s: 0.0,
            time_lo_s: 0.0,
            time_hi_s: 0.0,
            startup_s: 0.0,
            startup_share: 0.0,
            runs: 0,
            max_rss_kib: first.max_rss_kib,
            error_fraction: None,
            edge_rmse: None,
            rms_16x16: None,
            visibility_error: None,
            edges: stats.edges,
            depth_complexity: stats.depth_complexity,
            visible_polygons: stats.visible_polygons,
            visible_segments: stats.visible_segments,
            segments_per_line: stats.segments_per_line,
            line_pieces: None,
            intersection_pieces: None,
            line_length_px: None,
            line_error_px: None,
        };
        if method.draws == Draws::Lines {
            if exact.is_none() {
                *exact = Some(self.exact_lines(scene, env.frames)?);
            }
            let Some(reference) = exact.as_ref() else {
                return Err(Error::Data(format!("no exact drawing of {}", scene.name)));
            };
            let mut lines = Lines::default();
            let mut error_px = 0.0;
            let mut pixels = reference::Metrics::default();
            for frame in 0..env.frames.max(1) {
                let path = self.work.join(format!("lines-{frame}.svg"));
                let text = std::fs::read_to_string(&path).with_context(|| {
                    format!("{} on {}: {}", method.name, scene.name, path.display())
                })?;
                lines.add_svg(&text)?;
                let pieces = lines::read_svg(&text).map_err(Error::Data)?;
                let f = frame as usize;
                let exact_frame = reference.pieces.get(f).map_or(&[][..], |p| &p[..]);
                error_px += lines::line_error(&pieces, exact_frame, 0.5).total_px();
                let drawn = line_picture(&pieces, scene);
                let blank;
                let exact_picture = match reference.pictures.get(f) {
                    Some(p) => p,
                    None => {
                        blank = line_picture(&[], scene);
                        &blank
                    }
                };
                pixels.add(
                    &reference::metrics(exact_picture, &drawn, None)
                        .map_err(|e| Error::Data(format!("{}: {e}", scene.name)))?,
                );
                let _ = std::fs::remove_file(&path);
            }
            row.line_pieces = Some(lines.pieces);
            row.intersection_pieces = Some(lines.intersections);
            row.line_length_px = Some(lines.length_px);
            row.line_error_px = Some(error_px);
            row.rms_16x16 = Some(pixels.rmse());
            return Ok(row);
        }
        let frames = self.work.join("frames.ppm");
        let point = self.compare(&refs.point, &frames, None)?;
        let sixteen = self.compare(&refs.sixteen, &frames, Some(&refs.mask))?;
        let _ = std::fs::remove_file(&frames);
        let fraction = point.differing as f64 / point.pixels.max(1) as f64;
        row.error_fraction = Some(fraction);
        row.edge_rmse = sixteen.edge_rmse;
        row.rms_16x16 = Some(sixteen.rmse);
        if !matches!(method.selector, ::methods::Selector::Aa(_)) {
            row.visibility_error = Some(100.0 * fraction);
        }
        Ok(row)
    }

    /// `zspec compare --metrics --csv [--edges MASK] REF FRAMES`: its `overall` row.
    fn compare(&self, reference: &Path, frames: &Path, mask: Option<&Path>) -> Result<Compared> {
        let mut cmd = Command::new(self.bin.join("zspec"));
        cmd.args(["compare", "--metrics", "--csv"]);
        if let Some(m) = mask {
            cmd.arg("--edges").arg(m);
        }
        let out = cmd
            .arg(reference)
            .arg(frames)
            .output()
            .context("zspec compare")?;
        if !out.status.success() {
            return Err(Error::Data(format!(
                "zspec compare {} {}: {}",
                reference.display(),
                frames.display(),
                String::from_utf8_lossy(&out.stderr).trim()
            )));
        }
        parse_overall(&String::from_utf8_lossy(&out.stdout))
    }
}

/// The `overall` row of `zspec compare --metrics --csv`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Compared {
    pub pixels: u64,
    pub differing: u64,
    pub rmse: f64,
    pub edge_rmse: Option<f64>,
}

pub fn parse_overall(csv_text: &str) -> Result<Compared> {
    let mut reader = csv::Reader::from_reader(csv_text.as_bytes());
    let headers = reader.headers()?.clone();
    let col = |name: &str| {
        headers
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| Error::Data(format!("zspec compare's CSV has no column {name}")))
    };
    let (pixels, differing, rmse, edge) = (
        col("pixels")?,
        col("differing")?,
        col("rmse")?,
        col("edge_rmse")?,
    );
    for record in reader.records() {
        let r = record?;
        if r.get(0) == Some("overall") {
            let get = |i: usize| r.get(i).unwrap_or("");
            return Ok(Compared {
                pixels: get(pixels)
                    .parse()
                    .map_err(|e| Error::Data(format!("{e}")))?,
                differing: get(differing)
                    .parse()
                    .map_err(|e| Error::Data(format!("{e}")))?,
                rmse: get(rmse).parse().map_err(|e| Error::Data(format!("{e}")))?,
                edge_rmse: get(edge).parse().ok(),
            });
        }
    }
    Err(Error::Data("zspec compare printed no overall row".into()))
}

/// The median of `v` (0 for none).
fn median_of(v: &[f64]) -> f64 {
    measure::median(
        &v.iter()
            .map(|&wall_s| Usage {
                wall_s,
                ..Usage::default()
            })
            .collect::<Vec<_>>(),
    )
    .wall_s
}

/// A row's times from its timed runs and its start-up runs' CPU seconds: the medians,
/// the CPU time less start-up and its spread, the start-up's share.
pub fn finish(row: &mut Row, runs: &[Usage], startups: &[f64]) {
    let usage = measure::median(runs);
    let startup = median_of(startups);
    let (lo, hi) = runs.iter().fold((f64::INFINITY, 0.0f64), |(a, b), u| {
        (a.min(u.cpu_s), b.max(u.cpu_s))
    });
    row.wall_s = usage.wall_s;
    row.cpu_s = usage.cpu_s;
    row.startup_s = startup;
    row.startup_share = if usage.cpu_s > 0.0 {
        startup / usage.cpu_s
    } else {
        0.0
    };
    row.time_s = (usage.cpu_s - startup).max(0.0);
    row.time_lo_s = (lo - startup).max(0.0).min(row.time_s);
    row.time_hi_s = (hi - startup).max(row.time_s);
    row.runs = runs.len() as u32;
}

/// Every run of the chart: the rows of `results.csv` and of `model.csv`. `tick` is told
/// each run as it starts.
///
/// Each scene is first drawn in colours of its own ([`crate::visibility`]). Its runs are
/// timed `reps` times, interleaved: every (method, depth) once, then every one again, so
/// that a change in the machine's load falls on all of them alike; after each, the same
/// render of an empty scene is timed, its start-up. The first round writes the frames
/// that are measured.
pub fn chart(
    setup: &Setup,
    scenes: &[Scene],
    mut tick: impl FnMut(&str),
) -> Result<(Vec<Row>, Vec<ModelRow>, Vec<Extrapolation>)> {
    let runs = methods::runs(setup.quick, setup.only.as_deref());
    let mut rows = Vec::new();
    let mut model_rows = Vec::new();
    // The extrapolation is drawn for the scene with the most work (pixels drawn).
    let mut heaviest: Option<(f64, Vec<Extrapolation>)> = None;
    let reps = setup.reps.max(1);
    for given in scenes {
        tick(&format!("{}: references", given.name));
        let scene = setup.coloured(given)?;
        let refs = setup.references(&scene)?;
        let env = look::look(&scene.path, scene.width, scene.height, &[], None)?;
        let stats = stats::stats(&scene.path, scene.width, scene.height)
            .with_context(|| format!("the statistics of {}", scene.name))?;
        if heaviest.as_ref().is_none_or(|(area, _)| env.area > *area) {
            heaviest = Some((
                env.area,
                extrapolate(&setup.constants, &env, &scene.name, setup.cores),
            ));
        }
        let mut exact = None;
        let mut here: Vec<Row> = Vec::with_capacity(runs.len());
        let mut timed: Vec<Vec<Usage>> = vec![Vec::new(); runs.len()];
        let mut startups: Vec<Vec<f64>> = vec![Vec::new(); runs.len()];
        for rep in 0..reps {
            for (i, (method, depth)) in runs.iter().enumerate() {
                tick(&format!(
                    "{}: {} depth {depth}, run {} of {reps}",
                    scene.name,
                    method.name,
                    rep + 1
                ));
                let input = setup.input(&scene, method.input)?;
                let usage = setup.time_once(&scene, &input, method, *depth, rep == 0)?;
                if rep == 0 {
                    here.push(setup.measured(
                        &scene, &env, &stats, &refs, &mut exact, method, *depth, usage,
                    )?);
                }
                timed[i].push(usage);
                let empty = setup.empty(if method.input == Input::Text {
                    Input::Text
                } else {
                    Input::Binary
                })?;
                let start = setup
                    .time_once(&scene, &empty, method, *depth, false)
                    .context("the start-up run, on an empty scene")?;
                startups[i].push(start.cpu_s);
            }
        }
        for (i, row) in here.iter_mut().enumerate() {
            finish(row, &timed[i], &startups[i]);
        }
        rows.extend(here);
        // The machine's load while this scene was measured.
        let load = crate::calibrate::background_load();
        for depth in 0..=4u8 {
            let measured = rows
                .iter()
                .find(|r| r.scene == scene.name && r.method == "zbuf" && r.depth == depth)
                .map(|r| r.wall_s);
            let Some(measured_s) = measured else { continue };
            model_rows.push(model_row(
                &setup.constants,
                &env,
                &scene.name,
                depth,
                setup.cores,
                load,
                measured_s,
            ));
        }
    }
    Ok((
        rows,
        model_rows,
        heaviest.map(|(_, e)| e).unwrap_or_default(),
    ))
}

/// The model's prediction for a scene at a depth, beside what was measured.
pub fn model_row(
    k: &Constants,
    env: &Environment,
    scene: &str,
    depth: u8,
    cores: usize,
    load: f64,
    measured_s: f64,
) -> ModelRow {
    let p = model::predict_on(k, env, depth, &model::Target::cores(cores).loaded(load));
    let stage = |name: &str| {
        p.stages
            .iter()
            .find(|s| s.stage == name)
            .map_or(0.0, |s| s.each_s)
    };
    ModelRow {
        scene: scene.to_string(),
        depth,
        predicted_s: p.total_s,
        measured_s,
        error: (p.total_s - measured_s) / measured_s,
        viewxf_s: stage("viewxf"),
        clip_s: stage("clip"),
        splitter_s: stage("splitter"),
        persp_s: stage("persp"),
        hse_s: stage("hse"),
        merge_s: stage("merge"),
        slowest_s: p.slowest_s,
        shared_s: p.shared_s,
        overhead_s: p.overhead_s,
        processes: p.processes,
        bottleneck: p.bottleneck().to_string(),
        polygons_in_view: env.relevant / env.frames.max(1),
        depth_complexity: env.depth_complexity(),
        load,
    }
}

/// Reads rows written by [`write_csv`].
pub fn read_csv<T: serde::de::DeserializeOwned>(path: &Path) -> Result<Vec<T>> {
    let mut r =
        csv::Reader::from_path(path).with_context(|| format!("cannot read {}", path.display()))?;
    Ok(r.deserialize().collect::<std::result::Result<_, _>>()?)
}

/// Writes rows as CSV with a header row.
pub fn write_csv<T: Serialize>(path: &Path, rows: &[T]) -> Result<()> {
    let mut w = csv::Writer::from_writer(Vec::new());
    for r in rows {
        w.serialize(r)?;
    }
    let bytes = w
        .into_inner()
        .map_err(|e| Error::Data(format!("{}: {}", path.display(), e.error())))?;
    // Whole or not at all: a temporary renamed when complete.
    stagecli::whole::write_whole(path, &bytes)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scene_arguments() {
        let s = Scene::parse("a/fill.txt@1920x1080", (500, 500)).unwrap();
        assert_eq!((s.name.as_str(), s.width, s.height), ("fill", 1920, 1080));
        assert_eq!(s.path, PathBuf::from("a/fill.txt"));
        let s = Scene::parse("b@c.txt", (500, 400)).unwrap();
        assert_eq!((s.name.as_str(), s.width, s.height), ("b@c", 500, 400));
    }

    #[test]
    fn a_bad_size_after_at_is_a_usage_error_in_sizes_words() {
        for (arg, why) in [
            ("p.txt@0x5", "`0` in `0x5` is not a size from 1 to 65536"),
            (
                "p.txt@65537x10",
                "`65537` in `65537x10` is not a size from 1 to 65536",
            ),
            ("p.txt@500", "expected WxH, e.g. 500x500, found `500`"),
        ] {
            let e = Scene::parse(arg, (500, 500)).unwrap_err();
            assert_eq!(
                e,
                Error::Usage(format!("invalid size in scene '{arg}': {why}")),
                "{arg}"
            );
        }
        // A file named so is taken whole.
        let dir = tempfile::tempdir().unwrap();
        let odd = dir.path().join("take@2x.txt");
        std::fs::write(&odd, "").unwrap();
        let s = Scene::parse(&odd.to_string_lossy(), (5, 6)).unwrap();
        assert_eq!((s.path, s.width, s.height), (odd, 5, 6));
    }

    #[test]
    fn the_trees_peak_is_the_sum_render_times_gives() {
        let said =
            "render: zbuf: 2.4 ms CPU (2.4 user, 0.0 system), 2.6 MB peak, ended at 3.6 ms\n\
             @stats render label=zbuf user_ms=2.400 system_ms=0.000 peak_kib=2662 ended_ms=3.600\n\
             render: 3 stages: 5.1 ms CPU, 6.3 MB of peaks, the last ended at 3.6 ms\n\
             @stats render stages=3 cpu_ms=5.100 peaks_kib=6451 last_ended_ms=3.600\n";
        assert_eq!(peaks_kib(said), Some(6451));
        // The readable lines alone are not read.
        assert_eq!(peaks_kib(&stagecli::stats::human(said)), None);
        assert_eq!(peaks_kib("viewxf: empty input\n"), None);
    }

    #[test]
    fn a_drawing_is_counted_by_its_pieces_and_their_length() {
        let svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10\" height=\"10\">\n\
                   <g stroke-width=\"1\">\n\
                   <line x1=\"0\" y1=\"0\" x2=\"3\" y2=\"4\" stroke=\"rgb(1,2,3)\"/>\n\
                   <line class=\"intersection\" x1=\"1.5\" y1=\"2\" x2=\"1.5\" y2=\"4.5\" stroke=\"rgb(1,2,3)\"/>\n\
                   </g>\n</svg>\n";
        let mut l = Lines::default();
        l.add_svg(svg).unwrap();
        assert_eq!((l.pieces, l.intersections), (2, 1));
        assert!((l.length_px - 7.5).abs() < 1e-12, "{l:?}");
        // A second frame adds to the first.
        l.add_svg(svg).unwrap();
        assert_eq!((l.pieces, l.intersections, l.length_px), (4, 2, 15.0));
        let e = Lines::default()
            .add_svg("<line x1=\"0\" y1=\"0\" x2=\"a\" y2=\"1\"/>")
            .unwrap_err();
        assert!(
            e.to_string()
                .contains(r#"x2="a" is not a number in the SVG's line"#),
            "{e}"
        );
        assert_eq!(e.status(), 1, "{e}");
        // The pieces of one edge, joined: each dash a piece.
        let mut l = Lines::default();
        l.add_svg(
            r#"<line x1="0" y1="0" x2="6" y2="8" stroke="rgb(1,2,3)" stroke-dasharray="2 3 5"/>"#,
        )
        .unwrap();
        assert_eq!((l.pieces, l.intersections, l.length_px), (2, 0, 7.0));
    }

    #[test]
    fn overall_row_of_zspec_compare() {
        let text = "frame,pixels,differing,differing_fraction,rmse,max,edge_pixels,edge_rmse\n\
                    0,250000,31467,0.125868,12.545737,214,31897,35.122972\n\
                    overall,250000,31467,0.125868,12.545737,214,31897,35.122972\n";
        let c = parse_overall(text).unwrap();
        assert_eq!((c.pixels, c.differing), (250000, 31467));
        assert_eq!(c.edge_rmse, Some(35.122972));
        let none = "frame,pixels,differing,differing_fraction,rmse,max,edge_pixels,edge_rmse\n\
                    overall,4,0,0.000000,0.000000,0,,\n";
        assert_eq!(parse_overall(none).unwrap().edge_rmse, None);
        assert_eq!(
            parse_overall("frame,pixels\n"),
            Err(Error::Data(
                "zspec compare's CSV has no column differing".into()
            ))
        );
        let bad = "frame,pixels,differing,differing_fraction,rmse,max,edge_pixels,edge_rmse\n\
                   overall,4,x,0,0,0,,\n";
        assert_eq!(
            parse_overall(bad),
            Err(Error::Data("invalid digit found in string".into()))
        );
    }
}
