//! scene: writes a world-space polygon stream (binary, or text with `--text`) to stdout.

use clap::{Parser, Subcommand};
use glam::DVec3;
use proto::{Form, Header, Polygon, Space, Token};
use scene::{obj, shapes, spin, Shading};
use stagecli::numbers::{between, degrees, fraction, non_negative, positive, whole};
use stagecli::{Error, TextFlag};
use std::io;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Scene sources for the polypipe pipeline: each subcommand writes a world-space stream,
/// frames separated by NEXT.FRAME, for the default camera (eye 0,0,20 looking at the
/// origin, s=10, d=16, hither 1, yon 30).
#[derive(Parser, Debug)]
#[command(
    name = "scene",
    version,
    after_help = "Examples:\n  \
        scene environment --polygons 1024 --clipped 0.5 --depth-complexity 1 --seed 1 --text\n  \
        scene environment --frames 10 | viewxf | clipplane left | ... | zbuf > movie.ppm\n  \
        scene penetrating --text\n  \
        scene spheres --frames 36 | viewxf | ...\n  \
        scene obj model.obj --frames 24",
    // `scene penetrating --text` as well as `scene --text penetrating`.
    mut_arg("text", |a| a.global(true))
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    #[command(flatten)]
    text: TextFlag,
    /// Number of frames: a movie in which the objects move between frames.
    #[arg(long, global = true, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    frames: u32,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// The test environment of thesis chapter 5.2: N four-sided polygons, a fraction F of
    /// them wholly outside the clipping pyramid, the visible ones covering on average D
    /// polygons per pixel.
    #[command(after_help = "Example:\n  \
        scene environment --polygons 1024 --clipped 0.5 --depth-complexity 1 --seed 1 --size 500x500")]
    Environment {
        /// P_t: the number of polygons.
        #[arg(long, default_value_t = 1000, value_parser = whole::<usize>(1, 1 << 30))]
        polygons: usize,
        /// The fraction of polygons wholly outside the clipping pyramid (0 to 1).
        #[arg(long, default_value_t = 0.5, value_parser = fraction)]
        clipped: f64,
        /// Dc: the average number of visible polygons covering a pixel.
        #[arg(long, default_value_t = 1.0, value_parser = between(1e-6, 1e6))]
        depth_complexity: f64,
        /// The random seed: the same seed gives the same scene on every platform.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// The screen size `WxH` the scene is made for (its aspect ratio W/H widens the
        /// pyramid); give the same size to viewxf and persp.
        #[arg(long, value_parser = proto::camera::parse_size, value_name = "WxH")]
        size: Option<(u32, u32)>,
    },
    /// The thesis INPUTTER's scene (Appendix 4): a red triangle and a blue quadrilateral
    /// that penetrate each other.
    #[command(after_help = "Example:\n  scene penetrating --text")]
    Penetrating,
    /// A latitude–longitude sphere at the origin, shaded, polar bands triangles.
    #[command(
        after_help = "Example:\n  scene sphere --stacks 24 --slices 48 --radius 9 --frames 36"
    )]
    Sphere {
        /// Bands from pole to pole.
        #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(2..=4096))]
        stacks: u32,
        /// Segments around.
        #[arg(long, default_value_t = 32, value_parser = clap::value_parser!(u32).range(3..=4096))]
        slices: u32,
        /// The radius (the visible square at the origin is ±12.5).
        #[arg(long, default_value_t = 8.0, value_parser = positive)]
        radius: f64,
        /// Light each vertex instead of each face, as vertex colours (the header says
        /// `vertex-colours`): the sphere is Gouraud-shaded.
        #[arg(long, conflicts_with = "phong")]
        gouraud: bool,
        /// Send each vertex's normal instead, with the lighting in the header
        /// (`vertex-normals`): the z-buffer lights each pixel, Phong shading.
        #[arg(long)]
        phong: bool,
        #[command(flatten)]
        lights: LightArgs,
    },
    /// Two intersecting spheres (Archuleta's figure 1).
    #[command(after_help = "Example:\n  scene spheres --stacks 16 --slices 32 --text")]
    Spheres {
        #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(2..=4096))]
        stacks: u32,
        #[arg(long, default_value_t = 32, value_parser = clap::value_parser!(u32).range(3..=4096))]
        slices: u32,
        /// Light each vertex instead of each face (`vertex-colours`): Gouraud shading.
        #[arg(long, conflicts_with = "phong")]
        gouraud: bool,
        /// Send each vertex's normal and the lighting (`vertex-normals`): Phong shading.
        #[arg(long)]
        phong: bool,
        #[command(flatten)]
        lights: LightArgs,
    },
    /// A building of a few hundred edges: walls, windows as separate quadrilaterals, a
    /// door and a gable roof (Archuleta's figures 2 and 3).
    #[command(after_help = "Example:\n  scene building --floors 6 --bays 8 --frames 24")]
    Building {
        /// Storeys.
        #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=1000))]
        floors: u32,
        /// Windows a floor on the long walls (half as many on the short ones).
        #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
        bays: u32,
    },
    /// A screen-filling mesh of quadrilaterals sharing their edges, at constant depth,
    /// each its own colour: any crack or doubly drawn pixel is a bug. In a movie the
    /// interior vertices wobble while the border stays put.
    #[command(after_help = "Example:\n  scene mesh --cols 64 --rows 48 --size 640x480")]
    Mesh {
        #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..=4096))]
        cols: u32,
        #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..=4096))]
        rows: u32,
        /// The screen size `WxH` to cover (its aspect ratio widens the mesh).
        #[arg(long, value_parser = proto::camera::parse_size, value_name = "WxH")]
        size: Option<(u32, u32)>,
    },
    /// A triangle whose tip pierces a square, showing the implied edge (the Warnock
    /// chapter of the survey).
    #[command(
        name = "triangle-square",
        after_help = "Example:\n  scene triangle-square --text"
    )]
    TriangleSquare,
    /// 24 thin triangles tapering to points at many slopes: what point sampling breaks
    /// into dashes (`bench aa-table`).
    #[command(
        after_help = "Example:\n  scene needles | scripts/render.sh --aa abuf --size 64x48 -"
    )]
    Needles,
    /// Hostile: N full-screen squares stacked in depth (depth complexity N everywhere).
    #[command(after_help = "Example:\n  scene stack 20000 | scripts/render.sh --hse painter -")]
    Stack {
        /// N, the number of squares.
        #[arg(value_parser = hostile_count)]
        count: usize,
    },
    /// Hostile: N long thin triangles across the screen at random heights, slopes and
    /// depths, about 0.4 of a pixel wide at 500×500.
    #[command(after_help = "Example:\n  scene slivers 10000 --seed 2")]
    Slivers {
        #[arg(value_parser = hostile_count)]
        count: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// Hostile: N tiny triangles at distinct depths all covering one pixel's centre at
    /// 500×500 (pixel 250, 249): N fragments in one pixel.
    #[command(after_help = "Example:\n  scene pinhead 100000 | scripts/render.sh --aa abuf -")]
    Pinhead {
        #[arg(value_parser = hostile_count)]
        count: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// Hostile: N full-screen planes tilted about different axes, every pair crossing on
    /// the screen (no depth order exists; a depth sort must cut them).
    #[command(
        after_help = "Example:\n  scene planes 50 | scripts/render.sh --hse painter --split -"
    )]
    Planes {
        #[arg(value_parser = hostile_count)]
        count: usize,
    },
    /// Hostile: N horizontal strips, disjoint on the screen, each slanted in depth so that
    /// all their depth extents overlap (a depth sort's quadratic case).
    #[command(after_help = "Example:\n  scene strips 3000 | scripts/render.sh --hse painter -")]
    Strips {
        #[arg(value_parser = hostile_count)]
        count: usize,
    },
    /// Screen-space scenes for timing one leaf method alone: polygons already in the
    /// device coordinates of a WxH screen (depth in (0, 1), smaller nearer), for
    /// `scanconv --resolve`, `scanline`, `warnock` or `hiddenline` to read with no stage
    /// in front; with --frames, the same frame repeated.
    #[command(after_help = "Examples:\n  \
        scene screen crossings 64 --size 1024x1024 --frames 10 | scanline --stats > /dev/null\n  \
        scene screen tiles 8 --behind 10000 | warnock > /dev/null")]
    Screen {
        /// The screen's size.
        #[arg(long, global = true, default_value = "500x500", value_parser = proto::camera::parse_size, value_name = "WxH")]
        size: (u32, u32),
        #[command(subcommand)]
        scene: ScreenScene,
    },
    /// A Wavefront OBJ model: each face one polygon, coloured by its material's diffuse
    /// colour (200 200 200 without one).
    #[command(
        after_help = "Examples:\n  scene obj teapot.obj --frames 36\n  scene obj --no-fit - < model.obj"
    )]
    Obj {
        /// The OBJ file, `-` for standard input (its mtllib files are then looked for in
        /// the current folder).
        file: String,
        /// Keep the model's own coordinates instead of centring and scaling it into
        /// view (by default it is fitted into a sphere of radius 8 at the origin).
        #[arg(long, overrides_with = "fit")]
        no_fit: bool,
        /// Fit the model into view (the default).
        #[arg(long, overrides_with = "no_fit")]
        fit: bool,
        /// Light the faces (colour × (0.3 + 0.7·|n·l|), a fixed light up, right and
        /// towards the eye) so that a one-colour model shows its shape.
        #[arg(long)]
        shade: bool,
        /// Light each vertex instead, by its normal (the file's `vn`, or the normals of
        /// the faces that meet there averaged within --crease), as vertex colours: the
        /// model is Gouraud-shaded (render.sh draws it with --hse zbuf or --aa ssK).
        #[arg(long, conflicts_with = "phong")]
        gouraud: bool,
        /// Send the same vertex normals instead, with the lighting in the header
        /// (`vertex-normals`): the z-buffer lights each pixel, Phong shading.
        #[arg(long, conflicts_with = "shade")]
        phong: bool,
        /// With --gouraud or --phong: faces that meet at a sharper angle than this, in
        /// degrees, are not smoothed across their edge.
        #[arg(long, value_name = "DEGREES", default_value_t = 60.0, value_parser = degrees)]
        crease: f64,
        #[command(flatten)]
        lights: LightArgs,
    },
}

/// The scenes of `scene screen` (the library's `screen` module says what each is for).
#[derive(Subcommand, Debug)]
enum ScreenScene {
    /// N columns, each two full-height quadrilaterals whose planes cross down its middle:
    /// N crossings on every scan line, depth complexity 2.
    Crossings {
        #[arg(value_parser = hostile_count)]
        count: usize,
    },
    /// N full-screen planes at random depths, none crossing: depth complexity N.
    Parallel {
        #[arg(value_parser = hostile_count)]
        count: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// N full-screen planes tilted at random: depth complexity N, the front changing
    /// along every line.
    Tilted {
        #[arg(value_parser = hostile_count)]
        count: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// N full-screen planes that all pass through each other: corners at depths a, b,
    /// 1 − a, 1 − b (random a, b), every plane at depth 0.5 at the centre.
    Through {
        #[arg(value_parser = hostile_count)]
        count: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// N strips a pixel wide whose order along a line reverses from top to bottom.
    Reversing {
        #[arg(value_parser = hostile_count)]
        count: usize,
    },
    /// N full-screen squares at distinct depths, shuffled: depth complexity N.
    Stack {
        #[arg(value_parser = hostile_count)]
        count: usize,
    },
    /// N triangles from one side of the screen to the other, 0.4 of a pixel wide at
    /// their base, at random heights and depths.
    Slivers {
        #[arg(value_parser = hostile_count)]
        count: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// N triangles at distinct depths around one pixel's centre: N fragments in it.
    Pinhead {
        #[arg(value_parser = hostile_count)]
        count: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// K x K tiles covering the screen in front of N random squares.
    Tiles {
        /// K, the tiles along each side.
        #[arg(value_parser = clap::value_parser!(u32).range(1..=4096))]
        k: u32,
        /// N, the squares hidden behind the tiles.
        #[arg(long, default_value_t = 2000, value_parser = hostile_count)]
        behind: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// Two full-screen planes crossing along a vertical line.
    Penetrate,
}

impl ScreenScene {
    /// The scene's one frame on a `size` screen.
    fn polygons(&self, size: scene::screen::Size) -> Vec<Polygon> {
        use scene::screen;
        match *self {
            ScreenScene::Crossings { count } => screen::crossings(count, size),
            ScreenScene::Parallel { count, seed } => screen::parallel(count, seed, size),
            ScreenScene::Tilted { count, seed } => screen::tilted(count, seed, size),
            ScreenScene::Through { count, seed } => screen::through(count, seed, size),
            ScreenScene::Reversing { count } => screen::reversing(count, size),
            ScreenScene::Stack { count } => screen::stack(count, size),
            ScreenScene::Slivers { count, seed } => screen::slivers(count, seed, size),
            ScreenScene::Pinhead { count, seed } => screen::pinhead(count, seed, size),
            ScreenScene::Tiles { k, behind, seed } => screen::tiles(k as usize, behind, seed, size),
            ScreenScene::Penetrate => screen::penetrate(size),
        }
    }
}

/// The lighting of `--shade`, `--gouraud` and `--phong` (proto's `Lighting`: Phong's
/// model, lights and viewer at infinity, two-sided diffuse).
#[derive(clap::Args, Debug)]
struct LightArgs {
    /// A directional light towards X,Y,Z (world coordinates) of intensity I (default 1);
    /// repeatable, up to 8. Without it, one light towards 1,1.5,2 of intensity 0.7. A
    /// surface of colour C and unit normal n is lit to C·(ambient + Σ I·|n·l|) +
    /// 255·KS·Σ I·max(0, r·v)^N, clamped.
    #[arg(long, value_name = "X,Y,Z[,I]", value_parser = light, allow_hyphen_values = true)]
    light: Vec<(DVec3, f64)>,
    /// The ambient term, lit everywhere.
    #[arg(long, value_name = "A", default_value_t = 0.3, value_parser = non_negative)]
    ambient: f64,
    /// A white highlight: coefficient KS and Phong's exponent N (N ≥ 1: the larger, the
    /// sharper). Without it, none.
    #[arg(long, value_name = "KS,N", value_parser = specular)]
    specular: Option<(f64, f64)>,
    /// The direction towards the viewer, for the highlight (default 0,0,1: the default
    /// camera's side). Give the camera's direction when --eye moves it.
    #[arg(long, value_name = "X,Y,Z", value_parser = viewer, allow_hyphen_values = true)]
    viewer: Option<DVec3>,
}

impl LightArgs {
    fn lighting(&self) -> stagecli::Result<proto::shade::Lighting> {
        let mut lighting = proto::shade::Lighting::default();
        lighting.set_ambient(self.ambient).map_err(Error::usage)?;
        if !self.light.is_empty() {
            lighting.set_lights(&self.light).map_err(Error::usage)?;
        }
        if let Some((ks, n)) = self.specular {
            lighting.set_specular(ks, n).map_err(Error::usage)?;
        }
        if let Some(v) = self.viewer {
            lighting.set_viewer(v).map_err(Error::usage)?;
        }
        Ok(lighting)
    }
}

/// The shading `--phong` or `--gouraud` asks for, else `otherwise` (the faces lit, or flat).
fn chosen_shading(gouraud: bool, phong: bool, otherwise: Shading) -> Shading {
    if phong {
        Shading::Phong
    } else if gouraud {
        Shading::Gouraud
    } else {
        otherwise
    }
}

/// A highlight: KS ≥ 0 and N ≥ 1.
fn specular(s: &str) -> Result<(f64, f64), String> {
    let [ks, n] = proto::camera::parse_numbers::<2>(s, "KS,N")?;
    if !(ks.is_finite() && ks >= 0.0) {
        return Err(format!("`{s}`: the coefficient {ks} must be 0 or more"));
    }
    if !(n.is_finite() && n >= 1.0) {
        return Err(format!("`{s}`: the exponent {n} must be 1 or more"));
    }
    Ok((ks, n))
}

/// The viewer's direction X,Y,Z (not zero).
fn viewer(s: &str) -> Result<DVec3, String> {
    let [x, y, z] = proto::camera::parse_numbers::<3>(s, "X,Y,Z")?;
    let v = DVec3::new(x, y, z);
    if v.try_normalize().is_none() {
        return Err(format!("`{s}`: the viewer needs a direction, not 0,0,0"));
    }
    Ok(v)
}

/// A light: a direction X,Y,Z (not zero) and an intensity I ≥ 0 (default 1).
fn light(s: &str) -> Result<(DVec3, f64), String> {
    let (direction, intensity) = match proto::camera::parse_numbers::<4>(s, "X,Y,Z,I") {
        Ok([x, y, z, i]) => (DVec3::new(x, y, z), i),
        Err(_) => {
            let [x, y, z] = proto::camera::parse_numbers::<3>(s, "X,Y,Z[,I]")?;
            (DVec3::new(x, y, z), 1.0)
        }
    };
    let Some(direction) = direction.try_normalize() else {
        return Err(format!("`{s}`: a light needs a direction, not 0,0,0"));
    };
    if intensity < 0.0 {
        return Err(format!(
            "`{s}`: the intensity {intensity} must be 0 or more"
        ));
    }
    Ok((direction, intensity))
}

/// A hostile scene's polygon count: 1 to 2^24 (each polygon keeps a colour of its own).
fn hostile_count(s: &str) -> Result<usize, String> {
    let v: usize = s
        .parse()
        .map_err(|_| format!("`{s}` is not a whole number"))?;
    if (1..=1 << 24).contains(&v) {
        Ok(v)
    } else {
        Err(format!("{v} is not from 1 to 16777216"))
    }
}

/// Writes a movie: a header for `space`, the frames separated by NEXT.FRAME, then END.
/// A polygon with a coordinate that is not finite (a model too large to turn) is refused,
/// naming its frame and place.
/// `fix`, when not empty, says what to change then (`leave out --no-fit`).
fn write_movie<F: IntoIterator<Item = Polygon>>(
    frames: impl IntoIterator<Item = F>,
    space: Space,
    form: Form,
    attributes: proto::Attributes,
    fix: &str,
) -> stagecli::Result<()> {
    let mut writer = stagecli::write_stdout(Header::new(space).with(attributes), form)?;
    for (i, frame) in frames.into_iter().enumerate() {
        if i > 0 {
            writer.write(&Token::NextFrame)?;
        }
        for (k, polygon) in frame.into_iter().enumerate() {
            stagecli::check_finite(&polygon).map_err(|m| {
                let fix = if fix.is_empty() {
                    String::new()
                } else {
                    format!("; {fix}")
                };
                Error::data(format!(
                    "frame {i}, polygon {k}: {m}: not a finite number (coordinates this \
                     large overflow when the model turns{fix})"
                ))
            })?;
            writer.write(&Token::Polygon(polygon))?;
        }
    }
    writer.write(&Token::End)?;
    writer.flush()?;
    Ok(())
}

fn main() -> ExitCode {
    stagecli::main("scene", |cli: Cli| {
        let form = cli.text.form();
        let frames = cli.frames as usize;
        // The sphere's and the model's shading and lighting (the other scenes' are fixed).
        let mut shading = Shading::Flat;
        let mut lighting = proto::shade::Lighting::default();
        // What to change when the movie's coordinates overflow: only a model not fitted
        // to the view can make them so large.
        let mut fix = "";
        let movie = match cli.command {
            Command::Environment {
                polygons,
                clipped,
                depth_complexity,
                seed,
                size,
            } => {
                // Written as it is made: a large environment's movie need not fit in memory.
                let env = scene::Environment {
                    polygons,
                    clipped,
                    depth_complexity,
                    seed,
                    aspect: size.map_or(1.0, |(w, h)| w as f64 / h as f64),
                    frames,
                };
                return write_movie(
                    scene::environment::frames(&env),
                    Space::World,
                    form,
                    proto::Attributes::default(),
                    "",
                );
            }
            Command::Penetrating => {
                spin(&shapes::penetrating(), frames, DVec3::ZERO, Shading::Flat)
            }
            Command::Sphere {
                stacks,
                slices,
                radius,
                gouraud,
                phong,
                lights,
            } => {
                lighting = lights.lighting()?;
                shading = chosen_shading(gouraud, phong, Shading::Lambert);
                let sphere = shapes::sphere(
                    DVec3::ZERO,
                    radius,
                    stacks as usize,
                    slices as usize,
                    [220, 120, 60],
                );
                shapes::spin_lit(&sphere, frames, DVec3::ZERO, shading, &lighting)
            }
            Command::Spheres {
                stacks,
                slices,
                gouraud,
                phong,
                lights,
            } => {
                lighting = lights.lighting()?;
                shading = chosen_shading(gouraud, phong, Shading::Lambert);
                let spheres = shapes::spheres(stacks as usize, slices as usize);
                shapes::spin_lit(&spheres, frames, DVec3::ZERO, shading, &lighting)
            }
            Command::Building { floors, bays } => spin(
                &shapes::building(floors as usize, bays as usize),
                frames,
                DVec3::ZERO,
                Shading::Lambert,
            ),
            Command::Mesh { cols, rows, size } => shapes::mesh(
                cols as usize,
                rows as usize,
                size.map_or(1.0, |(w, h)| w as f64 / h as f64),
                frames,
            ),
            Command::TriangleSquare => spin(
                &shapes::triangle_square(),
                frames,
                DVec3::ZERO,
                Shading::Flat,
            ),
            Command::Needles => spin(&shapes::needles(), frames, DVec3::ZERO, Shading::Flat),
            Command::Stack { count } => {
                spin(&shapes::stack(count), frames, DVec3::ZERO, Shading::Flat)
            }
            Command::Slivers { count, seed } => spin(
                &shapes::slivers(count, seed),
                frames,
                DVec3::ZERO,
                Shading::Flat,
            ),
            Command::Pinhead { count, seed } => spin(
                &shapes::pinhead(count, seed),
                frames,
                DVec3::ZERO,
                Shading::Flat,
            ),
            Command::Planes { count } => {
                spin(&shapes::planes(count), frames, DVec3::ZERO, Shading::Flat)
            }
            Command::Strips { count } => {
                spin(&shapes::strips(count), frames, DVec3::ZERO, Shading::Flat)
            }
            Command::Screen {
                size: (width, height),
                scene,
            } => {
                let frame = scene.polygons(scene::screen::Size::new(width, height));
                return write_movie(
                    std::iter::repeat_n(frame, frames),
                    Space::Screen { width, height },
                    form,
                    proto::Attributes::default(),
                    "",
                );
            }
            Command::Obj {
                file,
                no_fit,
                shade,
                gouraud,
                phong,
                crease,
                lights,
                ..
            } => {
                let input = stagecli::open_input(&file)?;
                let dir = if file == "-" {
                    PathBuf::from(".")
                } else {
                    Path::new(&file)
                        .parent()
                        .map_or_else(|| PathBuf::from("."), Path::to_path_buf)
                };
                let name = if file == "-" {
                    "<stdin>"
                } else {
                    file.as_str()
                };
                let mut model = obj::load(&mut io::BufReader::new(input), &dir, name)?;
                for w in &model.warnings {
                    eprintln!("scene: warning: {w}");
                }
                if no_fit {
                    fix = "leave out --no-fit";
                } else {
                    obj::fit(&mut model.faces);
                }
                let faces_only = if shade {
                    Shading::Lambert
                } else {
                    Shading::Flat
                };
                shading = chosen_shading(gouraud, phong, faces_only);
                if gouraud || phong {
                    obj::smooth_normals(&mut model.faces, crease);
                }
                lighting = lights.lighting()?;
                shapes::spin_lit(&model.faces, frames, DVec3::ZERO, shading, &lighting)
            }
        };
        // A movie of Gouraud-shaded polygons (`scene sphere --gouraud`) says so in its
        // header, and one of Phong-shaded polygons carries its lighting there.
        let attributes = proto::Attributes {
            vertex_colours: shading == Shading::Gouraud,
            vertex_normals: shading == Shading::Phong,
            lighting: if shading == Shading::Phong {
                lighting
            } else {
                proto::shade::Lighting::default()
            },
            ..proto::Attributes::default()
        };
        write_movie(movie, Space::World, form, attributes, fix)
    })
}
