//! The pictures: speed against accuracy, one panel per scene (`speed-accuracy.png` and
//! `.svg`), and the cost model's predictions against measurement (`model.png`), drawn
//! with plotters in a font committed beside this crate (DejaVu Sans, through ab_glyph, so
//! no system font library is needed).

use crate::chart::{ModelRow, Row};
use crate::methods::METHODS;
use anyhow::{anyhow, Context, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::error::Error;
use std::path::Path;
use std::sync::Once;

type Drawn = std::result::Result<(), Box<dyn Error>>;

static FONT: &[u8] = include_bytes!("../fonts/DejaVuSans.ttf");

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The font is committed and valid; a failure would show as text missing.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// Distinct hues: the methods' marks, the model picture's scenes.
const PALETTE: [RGBColor; 12] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
    RGBColor(0, 0, 128),
    RGBColor(128, 0, 0),
];

/// A method's colour: its place in the method table, on [`PALETTE`].
fn colour_of(method: &str) -> RGBColor {
    let i = METHODS
        .iter()
        .position(|m| m.name == method)
        .unwrap_or(METHODS.len());
    PALETTE[i % PALETTE.len()]
}

/// Each method's mark on a scene's panel: its fastest depth.
pub fn marks<'a>(rows: &'a [Row], scene: &str) -> Vec<&'a Row> {
    let mut best: Vec<&Row> = Vec::new();
    for r in rows.iter().filter(|r| r.scene == scene) {
        match best.iter_mut().find(|b| b.method == r.method) {
            Some(b) if r.wall_s < b.wall_s => *b = r,
            Some(_) => {}
            None => best.push(r),
        }
    }
    best
}

/// The Pareto front of (time, error) marks: those that no other mark beats on both, in
/// order of time.
pub fn pareto<'a>(marks: &[&'a Row]) -> Vec<&'a Row> {
    let mut sorted: Vec<&Row> = marks.to_vec();
    sorted.sort_by(|a, b| {
        a.wall_s
            .total_cmp(&b.wall_s)
            .then(a.rmse.total_cmp(&b.rmse))
    });
    let mut front = Vec::new();
    let mut best = f64::INFINITY;
    for r in sorted {
        if r.rmse < best {
            best = r.rmse;
            front.push(r);
        }
    }
    front
}

fn scenes_of(rows: &[Row]) -> Vec<String> {
    let mut s: Vec<String> = Vec::new();
    for r in rows {
        if !s.contains(&r.scene) {
            s.push(r.scene.clone());
        }
    }
    s
}

/// Panel layout: (columns, rows) for n panels.
fn layout(n: usize) -> (usize, usize) {
    let cols = n.clamp(1, 3);
    (cols, n.max(1).div_ceil(cols))
}

const PANEL: (u32, u32) = (760, 560);

const TITLE: &str =
    "Speed against accuracy: each method at its fastest tree depth; the line is the Pareto front";

/// The title's font size and line height, pixels.
const TITLE_FONT: (u32, u32) = (24, 30);

/// The title broken into lines that fit a picture `width` pixels wide (with 12 px either
/// side): one panel is narrower than the title, which a single line would clip on both
/// sides.
fn title_lines(width: u32) -> Vec<String> {
    register_font();
    let font = ("sans-serif", TITLE_FONT.0).into_font();
    // Should the font not measure, about 14 px a character (its width at 24 px).
    let wide = |s: &str| {
        font.box_size(s)
            .map_or(14 * s.chars().count() as u32, |(w, _)| w)
    };
    wrap(TITLE, |s| wide(s) + 24 <= width)
}

/// The height of a title of `lines` lines: 50 px for one, as the picture always had.
fn title_height(lines: usize) -> u32 {
    20 + TITLE_FONT.1 * lines.max(1) as u32
}

/// `text` in lines that `fits`: broken at its clauses (after a `;`) where it must break,
/// as a person would, and a clause too long for a line alone by words; as much a line as
/// fits. A word too long for a line alone has the line to itself.
fn wrap(text: &str, fits: impl Fn(&str) -> bool) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for clause in text.split_inclusive("; ").map(str::trim) {
        let pieces: Vec<&str> = if fits(clause) {
            vec![clause]
        } else {
            clause.split_whitespace().collect()
        };
        for piece in pieces {
            match lines.last_mut() {
                Some(line) if fits(&format!("{line} {piece}")) => {
                    line.push(' ');
                    line.push_str(piece);
                }
                _ => lines.push(piece.to_string()),
            }
        }
    }
    lines
}

fn speed_accuracy_on<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    rows: &[Row],
    title_text: &[String],
) -> Drawn
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let scenes = scenes_of(rows);
    let (cols, nrows) = layout(scenes.len());
    let (title, body) = root.split_vertically(title_height(title_text.len()));
    let centre = title.dim_in_pixel().0 as i32 / 2;
    for (i, line) in title_text.iter().enumerate() {
        title.draw(&Text::new(
            line.as_str(),
            (centre, 12 + (TITLE_FONT.1 * i as u32) as i32),
            ("sans-serif", TITLE_FONT.0)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Top)),
        ))?;
    }
    let panels = body.split_evenly((nrows, cols));
    for (scene, panel) in scenes.iter().zip(panels) {
        let marks = marks(rows, scene);
        let first = marks[0];
        let (tmin, tmax) = marks.iter().fold((f64::INFINITY, 0.0f64), |(a, b), r| {
            (a.min(r.wall_s), b.max(r.wall_s))
        });
        let emax = marks.iter().map(|r| r.rmse).fold(0.0f64, f64::max).max(0.5) * 1.3;
        let caption = format!(
            "{} ({} polygons{}, {})",
            scene,
            first.polygons,
            if first.frames > 1 {
                format!(", {} frames", first.frames)
            } else {
                String::new()
            },
            first.size.replace('x', "×")
        );
        let mut chart = ChartBuilder::on(&panel)
            .caption(caption, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(52)
            .y_label_area_size(72)
            .build_cartesian_2d(
                // At least a factor of ten, so that the log axis has its labels.
                ((tmin / 1.6).min(tmax * 1.6 / 10.0).max(1e-4)..(tmax * 1.6).max(2e-4)).log_scale(),
                0.0..emax * 1.2,
            )?;
        chart
            .configure_mesh()
            .x_desc("wall time, seconds (log scale)")
            .y_desc("RMS error vs 16×16 reference (0–255)")
            .axis_desc_style(("sans-serif", 18))
            .label_style(("sans-serif", 16))
            .x_labels(10)
            .x_label_formatter(&|v| log_tick(*v))
            .y_label_formatter(&|v| format!("{v:.1}"))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()?;
        let front: Vec<(f64, f64)> = pareto(&marks).iter().map(|r| (r.wall_s, r.rmse)).collect();
        chart.draw_series(LineSeries::new(front, RGBColor(90, 90, 90).stroke_width(2)))?;
        // Marks in order of time, each label placed where it overlaps no label placed
        // before it and no mark: the first free slot of a column of slots above the mark,
        // then below it, each joined to its mark by a leader line.
        let mut by_time = marks.clone();
        by_time.sort_by(|a, b| a.wall_s.total_cmp(&b.wall_s));
        let at: Vec<(i32, i32)> = by_time
            .iter()
            .map(|r| chart.backend_coord(&(r.wall_s, r.rmse)))
            .collect();
        let area = chart.plotting_area().get_pixel_range();
        let mut placed: Vec<LabelBox> = at.iter().map(|&(x, y)| LabelBox::mark(x, y)).collect();
        for (r, &(x, y)) in by_time.iter().zip(&at) {
            let c = colour_of(&r.method);
            let label = if r.depth > 0 {
                format!("{} d{}", r.method, r.depth)
            } else {
                r.method.clone()
            };
            let dy = place_label(&label, (x, y), (&area.0, &area.1), &placed);
            placed.push(LabelBox::text(&label, x + 2, y + dy - 8));
            chart.draw_series(std::iter::once(
                EmptyElement::at((r.wall_s, r.rmse))
                    + Circle::new((0, 0), 7, c.filled())
                    + PathElement::new(
                        [
                            (0, if dy < 0 { -7 } else { 7 }),
                            (0, dy + if dy < 0 { 4 } else { -8 }),
                        ],
                        c.stroke_width(1),
                    )
                    + Text::new(label, (2, dy - 8), ("sans-serif", 16).into_font().color(&c)),
            ))?;
        }
    }
    root.present()?;
    Ok(())
}

/// A log axis's tick label: the value at 1, 2 and 5 times a power of ten, nothing at the
/// ticks between (their labels would run together near each power of ten).
fn log_tick(v: f64) -> String {
    let mantissa = v / 10f64.powf(v.log10().floor());
    if [1.0, 2.0, 5.0, 10.0]
        .iter()
        .any(|m| (mantissa - m).abs() < 0.01)
    {
        let digits = (-v.log10().floor()).max(0.0) as usize;
        format!("{v:.digits$}")
    } else {
        String::new()
    }
}

/// A box on the picture, in pixels: a placed label, or a mark.
#[derive(Clone, Copy, Debug, PartialEq)]
struct LabelBox {
    x0: i32,
    y0: i32,
    x1: i32,
    y1: i32,
}

impl LabelBox {
    /// Text `label` at 16 px whose top left is (x, y): about 9 px a character.
    fn text(label: &str, x: i32, y: i32) -> Self {
        LabelBox {
            x0: x,
            y0: y,
            x1: x + 9 * label.chars().count() as i32,
            y1: y + 16,
        }
    }

    /// A mark of radius 7 at (x, y).
    fn mark(x: i32, y: i32) -> Self {
        LabelBox {
            x0: x - 7,
            y0: y - 7,
            x1: x + 7,
            y1: y + 7,
        }
    }

    fn overlaps(&self, o: &LabelBox) -> bool {
        self.x0 < o.x1 && o.x0 < self.x1 && self.y0 < o.y1 && o.y0 < self.y1
    }
}

/// The vertical offset from its mark at `at` of the first slot for `label` that overlaps
/// none of `placed` and stays inside the plotting area `xs`×`ys` (pixels): slots 18 px
/// apart above the mark, then below it; the nearest above if none is free.
fn place_label(
    label: &str,
    at: (i32, i32),
    (xs, ys): (&std::ops::Range<i32>, &std::ops::Range<i32>),
    placed: &[LabelBox],
) -> i32 {
    let above = (0..14).map(|k| -16 - 18 * k);
    let below = (0..10).map(|k| 24 + 18 * k);
    for dy in above.chain(below) {
        let b = LabelBox::text(label, at.0 + 2, at.1 + dy - 8);
        let inside = b.y0 >= ys.start && b.y1 <= ys.end && b.x1 <= xs.end + 40;
        // The mark's own box is among `placed`; a label never sits on a mark, its own
        // included.
        if inside && !placed.iter().any(|p| p.overlaps(&b)) {
            return dy;
        }
    }
    -16
}

fn png(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(DrawingArea<BitMapBackend, Shift>) -> Drawn,
) -> Result<()> {
    register_font();
    let mut buf = vec![255u8; size.0 as usize * size.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
        draw(root).map_err(|e| anyhow!("drawing {}: {e}", path.display()))?;
    }
    let image =
        image::RgbImage::from_raw(size.0, size.1, buf).ok_or_else(|| anyhow!("picture buffer"))?;
    image
        .save(path)
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}

/// `speed-accuracy.png` and `.svg` in `dir`.
pub fn speed_accuracy(dir: &Path, rows: &[Row]) -> Result<()> {
    let (cols, nrows) = layout(scenes_of(rows).len());
    let width = PANEL.0 * cols as u32;
    let title = title_lines(width);
    let size = (width, PANEL.1 * nrows as u32 + title_height(title.len()));
    png(&dir.join("speed-accuracy.png"), size, |root| {
        speed_accuracy_on(root, rows, &title)
    })?;
    let svg = dir.join("speed-accuracy.svg");
    let root = SVGBackend::new(&svg, size).into_drawing_area();
    speed_accuracy_on(root, rows, &title).map_err(|e| anyhow!("drawing {}: {e}", svg.display()))
}

fn model_on<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, rows: &[ModelRow]) -> Drawn
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let all = rows.iter().flat_map(|r| [r.predicted_s, r.measured_s]);
    let (lo, hi) = all.fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    let (lo, hi) = ((lo / 1.5).max(1e-4), (hi * 1.5).max(2e-4));
    let mean = rows.iter().map(|r| r.error.abs()).sum::<f64>() / rows.len().max(1) as f64;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!(
                "Cost model (thesis 5.2, 6.4) against measurement: mean |error| {:.0}%",
                mean * 100.0
            ),
            ("sans-serif", 24),
        )
        .margin(16)
        .x_label_area_size(56)
        .y_label_area_size(80)
        .build_cartesian_2d((lo..hi).log_scale(), (lo..hi).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("measured wall time, seconds (log scale)")
        .y_desc("predicted, seconds (log scale)")
        .axis_desc_style(("sans-serif", 18))
        .label_style(("sans-serif", 16))
        .x_label_formatter(&|v| log_tick(*v))
        .y_label_formatter(&|v| log_tick(*v))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    chart
        .draw_series(LineSeries::new([(lo, lo), (hi, hi)], BLACK.stroke_width(1)))?
        .label("predicted = measured")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], BLACK));
    for f in [0.7, 1.3] {
        chart.draw_series(LineSeries::new(
            [(lo, lo * f), (hi, hi * f)],
            RGBColor(170, 170, 170).stroke_width(1),
        ))?;
    }
    let mut scenes: Vec<&str> = Vec::new();
    for r in rows {
        if !scenes.contains(&r.scene.as_str()) {
            scenes.push(&r.scene);
        }
    }
    for (i, scene) in scenes.iter().enumerate() {
        let c = PALETTE[i % PALETTE.len()];
        let mine: Vec<&ModelRow> = rows.iter().filter(|r| r.scene == *scene).collect();
        chart
            .draw_series(
                mine.iter()
                    .map(|r| Circle::new((r.measured_s, r.predicted_s), 6, c.filled())),
            )?
            .label(scene.to_string())
            .legend(move |(x, y)| Circle::new((x + 10, y), 6, c.filled()));
        chart.draw_series(mine.iter().map(|r| {
            Text::new(
                format!("d{}", r.depth),
                (r.measured_s, r.predicted_s),
                ("sans-serif", 15)
                    .into_font()
                    .color(&c)
                    .pos(Pos::new(HPos::Left, VPos::Bottom)),
            )
        }))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .label_font(("sans-serif", 17))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

/// `model.png` in `dir` (the grey lines are ±30%).
pub fn model(dir: &Path, rows: &[ModelRow]) -> Result<()> {
    png(&dir.join("model.png"), (900, 760), |root| {
        model_on(root, rows)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(method: &str, depth: u8, wall_s: f64, rmse: f64) -> Row {
        Row {
            scene: "s".into(),
            method: method.into(),
            depth,
            size: "10x10".into(),
            polygons: 2,
            frames: 1,
            wall_s,
            cpu_s: wall_s,
            max_rss_kib: 1,
            error_fraction: 0.0,
            edge_rmse: None,
            rmse,
        }
    }

    #[test]
    fn marks_take_each_methods_fastest_depth_and_the_front_drops_the_beaten() {
        let rows = vec![
            row("zbuf", 0, 0.2, 30.0),
            row("zbuf", 1, 0.1, 30.0),
            row("ss4", 0, 0.4, 10.0),
            row("slow", 0, 0.5, 20.0),
        ];
        let m = marks(&rows, "s");
        assert_eq!(m.len(), 3);
        assert_eq!(m[0].depth, 1);
        let front: Vec<&str> = pareto(&m).iter().map(|r| r.method.as_str()).collect();
        assert_eq!(front, ["zbuf", "ss4"]);
    }

    #[test]
    fn log_ticks_are_labelled_at_1_2_and_5() {
        let labels: Vec<String> = [0.1, 0.2, 0.3, 0.5, 0.9, 1.0, 2.0, 0.02, 0.05]
            .iter()
            .map(|v| log_tick(*v))
            .collect();
        assert_eq!(
            labels,
            ["0.1", "0.2", "", "0.5", "", "1", "2", "0.02", "0.05"]
        );
    }

    #[test]
    fn labels_take_the_first_free_slot_above_then_below() {
        let area = (0..400, 0..300);
        let at = (100, 150);
        let marks = [LabelBox::mark(at.0, at.1)];
        assert_eq!(place_label("zbuf", at, (&area.0, &area.1), &marks), -16);
        let mut placed = marks.to_vec();
        placed.push(LabelBox::text("zbuf", at.0 + 2, at.1 - 16 - 8));
        assert_eq!(
            place_label("scanline", at, (&area.0, &area.1), &placed),
            -34
        );
        // Near the top edge: no room above, so below.
        let top = (100, 10);
        assert_eq!(
            place_label("ss4", top, (&area.0, &area.1), &[LabelBox::mark(100, 10)]),
            24
        );
    }

    #[test]
    fn the_title_is_wrapped_to_fit_one_panel_and_kept_whole_on_three() {
        for (width, lines) in [(PANEL.0, 2), (3 * PANEL.0, 1)] {
            let t = title_lines(width);
            assert_eq!(t.len(), lines, "{width}: {t:?}");
            assert_eq!(t.join(" "), TITLE);
            let font = ("sans-serif", TITLE_FONT.0).into_font();
            for line in &t {
                let (w, _) = font.box_size(line).unwrap();
                assert!(w + 24 <= width, "{line:?} is {w} px in {width}");
            }
        }
    }

    #[test]
    fn wrap_fills_lines_by_words() {
        let fits = |s: &str| s.len() <= 7;
        assert_eq!(
            wrap("ab cd ef ghijklmno p", fits),
            ["ab cd", "ef", "ghijklmno", "p"]
        );
        // At the clause, though its first word would fit on the line before.
        assert_eq!(wrap("ab; cd ef", fits), ["ab;", "cd ef"]);
        assert_eq!(wrap("ab; cd", fits), ["ab; cd"]);
        assert_eq!(wrap("", fits), Vec::<String>::new());
    }

    #[test]
    fn pictures_are_written() {
        let dir = tempfile::tempdir().unwrap();
        let rows = vec![row("zbuf", 0, 0.2, 30.0), row("zbuf-eye-z", 0, 0.3, 31.0)];
        speed_accuracy(dir.path(), &rows).unwrap();
        let png = image::open(dir.path().join("speed-accuracy.png")).unwrap();
        // One panel is narrower than the title: two lines, the picture taller by one.
        assert_eq!((png.width(), png.height()), (PANEL.0, PANEL.1 + 80));
        let svg = std::fs::read_to_string(dir.path().join("speed-accuracy.svg")).unwrap();
        assert!(svg.contains("zbuf-eye-z"), "the label is in the SVG");
        assert!(svg.contains("wall time, seconds"));
    }
}
