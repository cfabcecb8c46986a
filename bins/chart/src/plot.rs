//! The pictures: speed against accuracy, one panel per scene (`speed-accuracy.png` and
//! `.svg`), and the cost model's predictions against measurement (`model.png`), drawn
//! with plotters in a font committed beside this crate (DejaVu Sans, through ab_glyph, so
//! no system font library is needed).

use crate::chart::{Extrapolation, ModelRow, Row};
use crate::error::{Context, Error, Result};
use crate::maxerror::Choice;
use crate::methods::{draws_lines, Method, METHODS};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;
use std::sync::Once;

type Drawn = std::result::Result<(), Box<dyn std::error::Error>>;

static FONT: &[u8] = include_bytes!("../fonts/DejaVuSans.ttf");

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The font is committed and valid; a failure would show as text missing.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// The chart's marker shapes: the table's.
pub use methods::Marker as Shape;

/// Every row's colour and shape, in the order of [`METHODS`] (the table's `colour` and
/// `marker`: apart in colour, and those nearest apart in shape too, `methods::check`).
/// The model picture's scenes and lines take the colours in order.
pub const STYLES: [(RGBColor, Shape); METHODS.len()] = {
    let mut s = [(RGBColor(0, 0, 0), Shape::Circle); METHODS.len()];
    let mut i = 0;
    while i < METHODS.len() {
        let [r, g, b] = METHODS[i].colour;
        s[i] = (RGBColor(r, g, b), METHODS[i].marker);
        i += 1;
    }
    s
};

/// The colours alone, in order.
const PALETTE: [RGBColor; METHODS.len()] = {
    let mut p = [RGBColor(0, 0, 0); METHODS.len()];
    let mut i = 0;
    while i < METHODS.len() {
        p[i] = STYLES[i].0;
        i += 1;
    }
    p
};

/// A method's colour and shape, from its row in the method table (a name the table
/// does not have: the first row's).
pub fn style_of(method: &str) -> (RGBColor, Shape) {
    style_in(METHODS, method)
}

/// [`style_of`] in `table`.
pub fn style_in(table: &[Method], method: &str) -> (RGBColor, Shape) {
    let m = methods::by_name(table, method).unwrap_or(&table[0]);
    let [r, g, b] = m.colour;
    (RGBColor(r, g, b), m.marker)
}

/// Draws a mark of `shape` and radius `r` at `at` (data coordinates) on `area`.
fn draw_mark<DB: DrawingBackend, CT: plotters::coord::CoordTranslate>(
    area: &DrawingArea<DB, CT>,
    at: CT::From,
    style: (RGBColor, Shape),
    r: i32,
) -> Drawn
where
    DB::ErrorType: 'static,
    CT::From: Clone,
{
    draw_mark_as(area, at, style, r, true)
}

/// [`draw_mark`], filled or (`filled` false) its outline alone: a method at depth 0 on
/// the speed-accuracy panels.
fn draw_mark_as<DB: DrawingBackend, CT: plotters::coord::CoordTranslate>(
    area: &DrawingArea<DB, CT>,
    at: CT::From,
    (colour, shape): (RGBColor, Shape),
    r: i32,
    filled: bool,
) -> Drawn
where
    DB::ErrorType: 'static,
    CT::From: Clone,
{
    let fill = if filled {
        colour.filled()
    } else {
        colour.stroke_width(2)
    };
    match shape {
        Shape::Circle => area.draw(&(EmptyElement::at(at) + Circle::new((0, 0), r, fill)))?,
        Shape::Square => area.draw(
            &(EmptyElement::at(at) + Rectangle::new([(-r + 1, -r + 1), (r - 1, r - 1)], fill)),
        )?,
        Shape::Triangle => area.draw(
            &(EmptyElement::at(at)
                + Polygon::new(vec![(0, -r - 1), (r + 1, r - 1), (-r - 1, r - 1)], fill)),
        )?,
        Shape::Diamond => area.draw(
            &(EmptyElement::at(at)
                + Polygon::new(vec![(0, -r - 1), (r + 1, 0), (0, r + 1), (-r - 1, 0)], fill)),
        )?,
        Shape::Cross => area.draw(
            &(EmptyElement::at(at)
                + PathElement::new([(-r, -r), (r, r)], colour.stroke_width(3))
                + PathElement::new([(-r, r), (r, -r)], colour.stroke_width(3))),
        )?,
    }
    Ok(())
}

/// A log axis's range widened to whole decades below (`lo` down to a power of ten), so
/// that its ticks at 1, 2 and 5 of every decade in range are all drawn (plotters counts
/// a log axis's light ticks from the first power of ten in it), and at least one decade
/// wide.
pub fn decades(lo: f64, hi: f64) -> (f64, f64) {
    let lo = 10f64.powf(lo.max(1e-6).log10().floor());
    // A hair below the power of ten: plotters finds the first decade as
    // 10^ceil(ln(lo)/ln(10)), and ln(0.1)/ln(10) is −0.9999999999999998, whose ceiling
    // would skip the decade 0.1–1.
    (lo * (1.0 - 1e-9), hi.max(lo * 10.0))
}

/// Enough tick requests that plotters draws every 1..9 of each decade (the labels then
/// keep 1, 2 and 5: [`log_tick`]).
fn log_ticks(lo: f64, hi: f64) -> usize {
    10 * ((hi / lo).log10().ceil().max(1.0) as usize + 1)
}

/// Which error a figure plots.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Measure {
    /// RMS error against the 16×16 reference (0–255), every method that draws pixels.
    Rms,
    /// % of pixels whose visible polygon differs from the exact point-sampled reference,
    /// the point-sampling methods ([`crate::visibility`]).
    Visibility,
}

impl Measure {
    /// The y axis's title.
    pub fn axis(self) -> &'static str {
        match self {
            Measure::Rms => "RMS error vs 16×16 reference (0–255)",
            Measure::Visibility => "% pixels whose visible polygon is wrong",
        }
    }
}

/// The least time a mark is drawn at: a run no slower than its start-up (time less
/// start-up 0) sits on the axis's left, at 0.1 ms.
pub const TIME_FLOOR: f64 = 1e-4;

/// A run's time on the figures' x axis: CPU seconds less start-up, at least
/// [`TIME_FLOOR`].
pub fn time_of(r: &Row) -> f64 {
    r.time_s.max(TIME_FLOOR)
}

/// Each method's mark on a scene's panel of `measure`: its fastest depth, of the runs
/// that have the measure (every method drawing pixels for RMS; the point-sampling ones
/// for visibility). The hidden-line methods draw lines, not pixels, and have no mark
/// here; the cost figure and the hidden-line figure compare them.
pub fn marks<'a>(rows: &'a [Row], scene: &str, measure: Measure) -> Vec<&'a Row> {
    let mut best: Vec<&Row> = Vec::new();
    let drawn = |r: &&Row| !error_of(r, measure).is_nan() && !draws_lines(&r.method);
    for r in rows.iter().filter(|r| r.scene == scene).filter(drawn) {
        match best.iter_mut().find(|b| b.method == r.method) {
            Some(b) if r.time_s < b.time_s => *b = r,
            Some(_) => {}
            None => best.push(r),
        }
    }
    best
}

/// Whether a method anti-aliases: its row in the table of methods is an `--aa` mode
/// (`abuf`, `ssK`).
pub fn anti_aliased(method: &str) -> bool {
    crate::methods::by_name(method).is_some_and(|m| matches!(m.selector, methods::Selector::Aa(_)))
}

/// A method's run at depth 0 on a scene (the method alone, no splitter tree).
pub fn at_depth_zero<'a>(rows: &'a [Row], scene: &str, method: &str) -> Option<&'a Row> {
    rows.iter()
        .find(|r| r.scene == scene && r.method == method && r.depth == 0)
}

/// A run's error on a figure of `measure` (NaN where the run has none).
pub fn error_of(r: &Row, measure: Measure) -> f64 {
    match measure {
        Measure::Rms => r.rms(),
        Measure::Visibility => r.visibility_error.unwrap_or(f64::NAN),
    }
}

/// The Pareto front of (time, error) marks: those that no other mark beats on both, in
/// order of time.
pub fn pareto<'a>(marks: &[&'a Row]) -> Vec<&'a Row> {
    pareto_by(marks, &|r: &Row| r.rms())
}

/// [`pareto`] on the error `err` gives each mark.
pub fn pareto_by<'a>(marks: &[&'a Row], err: &dyn Fn(&Row) -> f64) -> Vec<&'a Row> {
    let mut sorted: Vec<&Row> = marks.to_vec();
    sorted.sort_by(|a, b| {
        time_of(a)
            .total_cmp(&time_of(b))
            .then(err(a).total_cmp(&err(b)))
    });
    let mut front = Vec::new();
    let mut best = f64::INFINITY;
    for r in sorted {
        if err(r) < best {
            best = err(r);
            front.push(r);
        }
    }
    front
}

/// The scenes of the speed-accuracy panels, in order: those with a run of a method that
/// draws pixels (a scene run by the hidden-line methods alone has no panel).
fn scenes_of(rows: &[Row]) -> Vec<String> {
    let mut s: Vec<String> = Vec::new();
    for r in rows.iter().filter(|r| !draws_lines(&r.method)) {
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

const TITLE: &str = "Speed against accuracy, one measure on every panel: RMS error against \
the 16×16 reference; each method at depth 0 (hollow mark) and at its fastest tree depth \
(filled, named dN), joined by a line in its colour; the bar under a mark is the spread of \
its runs; the grey line is the Pareto front of the filled marks";

const VISIBILITY_TITLE: &str = "Visibility, the same runs: % of pixels whose visible \
polygon differs from the exact point-sampled reference, for the point-sampling methods; \
each at depth 0 (hollow mark) and at its fastest tree depth (filled, named dN); the bar \
under a mark is the spread of its runs";

/// The x axis's title: what the time is.
pub const TIME_AXIS: &str = "CPU s less start-up (log; median, bar least–most of the runs)";

/// The title's font size and line height, pixels.
const TITLE_FONT: (u32, u32) = (24, 30);

/// The title broken into lines that fit a picture `width` pixels wide (with 12 px either
/// side): one panel is narrower than the title, which a single line would clip on both
/// sides.
fn title_lines(width: u32, measure: Measure) -> Vec<String> {
    wrap_title(
        match measure {
            Measure::Rms => TITLE,
            Measure::Visibility => VISIBILITY_TITLE,
        },
        width,
    )
}

/// A title `text` in lines that fit a picture `width` pixels wide.
fn wrap_title(text: &str, width: u32) -> Vec<String> {
    register_font();
    let font = ("sans-serif", TITLE_FONT.0).into_font();
    // Should the font not measure, about 14 px a character (its width at 24 px).
    let wide = |s: &str| {
        font.box_size(s)
            .map_or(14 * s.chars().count() as u32, |(w, _)| w)
    };
    wrap(text, |s| wide(s) + 24 <= width)
}

/// The height of a title of `lines` lines: 50 px for one, as the picture always had.
fn title_height(lines: usize) -> u32 {
    20 + TITLE_FONT.1 * lines.max(1) as u32
}

/// A figure's title, its lines centred at the top of `title` (made `title_height` tall).
fn draw_title<DB: DrawingBackend>(title: &DrawingArea<DB, Shift>, title_text: &[String]) -> Drawn
where
    DB::ErrorType: 'static,
{
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
    Ok(())
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
    choices: &[Choice],
    title_text: &[String],
    measure: Measure,
) -> Drawn
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let scenes = scenes_of(rows);
    let (cols, nrows) = layout(scenes.len());
    let (title, rest) = root.split_vertically(title_height(title_text.len()));
    let height = rest.dim_in_pixel().1;
    // `--max-error`'s choices are marked on the RMS panels alone.
    let choices = if measure == Measure::Rms {
        choices
    } else {
        &[]
    };
    let marked = !choices.is_empty();
    let (body, foot) =
        rest.split_vertically(height - legend_height(rest.dim_in_pixel().0, measure, marked));
    draw_title(&title, title_text)?;
    let panels = body.split_evenly((nrows, cols));
    for (scene, panel) in scenes.iter().zip(panels) {
        let marks = marks(rows, scene, measure);
        let Some(&first) = marks.first() else {
            continue;
        };
        let point = measure == Measure::Visibility;
        let err = |r: &Row| error_of(r, measure);
        // Each method's depth-0 run beside its fastest, where they differ.
        let zeros: Vec<(&Row, &Row)> = marks
            .iter()
            .filter(|b| b.depth != 0)
            .filter_map(|b| at_depth_zero(rows, scene, &b.method).map(|z| (*b, z)))
            .collect();
        let all: Vec<&Row> = marks
            .iter()
            .copied()
            .chain(zeros.iter().map(|(_, z)| *z))
            .collect();
        let chosen = chosen_marks(rows, scene, choices);
        let (tmin, tmax) = all.iter().fold((f64::INFINITY, 0.0f64), |(a, b), r| {
            (
                a.min(r.time_lo_s.max(TIME_FLOOR)),
                b.max(r.time_hi_s.max(time_of(r))),
            )
        });
        let (tmin, tmax) = chosen
            .iter()
            .fold((tmin, tmax), |(a, b), c| (a.min(c.at.0), b.max(c.at.0)));
        let floor = if point { 0.05 } else { 0.5 };
        let emax = all
            .iter()
            .map(|r| err(r))
            .chain(chosen.iter().map(|c| c.at.1))
            .fold(0.0f64, f64::max)
            .max(floor)
            * 1.3;
        let (xlo, xhi) = decades(tmin / 1.3, tmax * 1.6);
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
            .build_cartesian_2d((xlo..xhi).log_scale(), 0.0..emax * 1.2)?;
        chart
            .configure_mesh()
            .x_desc(TIME_AXIS)
            .y_desc(measure.axis())
            .axis_desc_style(("sans-serif", 18))
            .label_style(("sans-serif", 16))
            .x_labels(log_ticks(xlo, xhi))
            // The 1-9 of every decade are the grid; no lighter lines between them.
            .x_max_light_lines(0)
            .x_label_formatter(&|v| log_tick_across(*v, xlo, xhi))
            .y_label_formatter(&|v| {
                if point && emax < 1.0 {
                    format!("{v:.2}")
                } else {
                    format!("{v:.1}")
                }
            })
            .light_line_style(RGBColor(235, 235, 235))
            .draw()?;
        let front: Vec<(f64, f64)> = pareto_by(&marks, &err)
            .iter()
            .map(|r| (time_of(r), err(r)))
            .collect();
        if !point {
            chart.draw_series(LineSeries::new(front, RGBColor(90, 90, 90).stroke_width(2)))?;
        }
        // Each mark's spread: its runs' least and most time less start-up, a bar in its
        // colour through the mark.
        for r in all.iter() {
            let (c, _) = style_of(&r.method);
            let y = err(r);
            chart.draw_series(LineSeries::new(
                [
                    (r.time_lo_s.max(TIME_FLOOR), y),
                    (r.time_hi_s.max(time_of(r)), y),
                ],
                c.mix(0.6).stroke_width(3),
            ))?;
        }
        // Depth 0 joined to the fastest depth, in the method's colour.
        for (best, zero) in &zeros {
            let (c, _) = style_of(&best.method);
            chart.draw_series(LineSeries::new(
                [(time_of(zero), err(zero)), (time_of(best), err(best))],
                c.stroke_width(1),
            ))?;
        }
        // Marks in order of time, each drawn in its method's colour and shape, and
        // labelled where the label overlaps no label placed before it and no mark: the
        // first free slot beside it, above or below. A mark in a crowd whose label finds
        // no free slot is named by the legend alone. The fastest depths first, then the
        // depth-0 runs.
        let mut by_time = marks.clone();
        by_time.sort_by(|a, b| time_of(a).total_cmp(&time_of(b)));
        let mut hollow: Vec<&Row> = zeros.iter().map(|(_, z)| *z).collect();
        hollow.sort_by(|a, b| time_of(a).total_cmp(&time_of(b)));
        let px = |r: &Row| chart.backend_coord(&(time_of(r), err(r)));
        let area = chart.plotting_area().get_pixel_range();
        let mut placed: Vec<LabelBox> = by_time
            .iter()
            .chain(&hollow)
            .map(|r| {
                let (x, y) = px(r);
                LabelBox::mark(x, y)
            })
            .collect();
        for r in &hollow {
            draw_mark_as(
                chart.plotting_area(),
                (time_of(r), err(r)),
                style_of(&r.method),
                7,
                false,
            )?;
        }
        for r in &by_time {
            draw_mark(
                chart.plotting_area(),
                (time_of(r), err(r)),
                style_of(&r.method),
                7,
            )?;
        }
        // A depth-0 run is named only where it is worse than the fastest depth (a
        // failure the tree hides), so that the panel's labels stay few.
        let named_zeros: Vec<&Row> = zeros
            .iter()
            .filter(|(b, z)| err(z) > err(b) + emax / 50.0)
            .map(|(_, z)| *z)
            .collect();
        for r in by_time.iter().chain(&named_zeros) {
            let (x, y) = px(r);
            let (c, _) = style_of(&r.method);
            let label = if r.depth > 0 {
                format!("{} d{}", r.method, r.depth)
            } else if named_zeros.iter().any(|z| std::ptr::eq(*z, *r)) {
                format!("{} d0", r.method)
            } else {
                r.method.clone()
            };
            let Some((dx, dy)) = place_label(&label, (x, y), (&area.0, &area.1), &placed) else {
                continue;
            };
            let b = LabelBox::text(&label, x + dx, y + dy);
            placed.push(b);
            chart.plotting_area().draw(
                &(EmptyElement::at((time_of(r), err(r)))
                    + Text::new(label, (dx, dy), ("sans-serif", 16).into_font().color(&c))),
            )?;
        }
        // `--max-error`'s choices: a black ring, labelled ≤E, around the run chosen (its
        // mark drawn too where the panel has not drawn that depth), or around a hollow
        // mark at the model's predicted time (less its start-up) and RMS where the chart did not
        // run it.
        for c in &chosen {
            let drawn = c
                .row
                .is_some_and(|r| by_time.iter().chain(&hollow).any(|m| std::ptr::eq(*m, r)));
            if !drawn {
                draw_mark_as(
                    chart.plotting_area(),
                    c.at,
                    style_of(&c.method),
                    7,
                    c.row.is_some(),
                )?;
                let (x, y) = chart.backend_coord(&c.at);
                placed.push(LabelBox::mark(x, y));
            }
        }
        for c in &chosen {
            chart.plotting_area().draw(
                &(EmptyElement::at(c.at) + Circle::new((0, 0), RING, BLACK.stroke_width(2))),
            )?;
            let drawn = c
                .row
                .is_some_and(|r| by_time.iter().chain(&hollow).any(|m| std::ptr::eq(*m, r)));
            let label = c.label(drawn);
            let (x, y) = chart.backend_coord(&c.at);
            // Beyond the ring: the label slots beside a mark start 10 px from its centre.
            let w = LabelBox::text(&label, 0, 0).x1;
            let beyond = |dx: i32| match dx {
                d if d > 0 => RING - 8,
                d if d + w < 0 => 8 - RING,
                _ => 0,
            };
            let Some((dx, dy)) = place_label(&label, (x, y), (&area.0, &area.1), &placed)
                .map(|(dx, dy)| (dx + beyond(dx), dy))
            else {
                continue;
            };
            placed.push(LabelBox::text(&label, x + dx, y + dy));
            let font = ("sans-serif", 16).into_font();
            // A label pushed away from its ring by others is joined to it by a thin line,
            // from the ring to the nearest point of the text.
            let w = font.box_size(&label).map_or(0, |(w, _)| w as i32);
            let near = (0.clamp(dx, dx + w), 0.clamp(dy, dy + 16));
            let far = f64::from(near.0).hypot(f64::from(near.1));
            if far > 40.0 {
                let from = |v: i32| (f64::from(v) * f64::from(RING) / far).round() as i32;
                chart.plotting_area().draw(
                    &(EmptyElement::at(c.at)
                        + PathElement::new(
                            [(from(near.0), from(near.1)), near],
                            RGBColor(120, 120, 120).stroke_width(1),
                        )),
                )?;
            }
            chart
                .plotting_area()
                .draw(&(EmptyElement::at(c.at) + Text::new(label, (dx, dy), font.color(&BLACK))))?;
        }
    }
    legend(&foot, measure, marked)?;
    root.present()?;
    Ok(())
}

/// A log axis's tick label: the value at 1, 2 and 5 times a power of ten, nothing at the
/// ticks between (their labels would run together near each power of ten).
fn log_tick(v: f64) -> String {
    let mantissa = v / 10f64.powf(v.log10().floor());
    // Not at a mantissa of 10: that is the last light tick of the decade below (0.01·10,
    // a hair under 0.1), drawn beside the next decade's own first tick.
    if [1.0, 2.0, 5.0].iter().any(|m| (mantissa - m).abs() < 0.01) {
        let digits = (-v.log10().floor()).max(0.0) as usize;
        format!("{v:.digits$}")
    } else {
        String::new()
    }
}

/// [`log_tick`] on an axis from `lo` to `hi`: across more than three decades only the
/// powers of ten are labelled, as 1, 2 and 5 of every decade would run into each other on
/// a panel a third of the figure wide.
fn log_tick_across(v: f64, lo: f64, hi: f64) -> String {
    let label = log_tick(v);
    let power = (v / 10f64.powf(v.log10().floor()) - 1.0).abs() < 0.01;
    if (hi / lo).log10() > 3.0 && !power {
        String::new()
    } else {
        label
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

/// The offset (from its mark at `at`, to the label's top left) of the first slot for
/// `label` that overlaps none of `placed` and stays inside the plotting area `xs`×`ys`
/// (pixels): right of the mark, above it, below it, left of it, then a little further
/// out above and below, and further out again to either side; `None` when every one is
/// taken.
fn place_label(
    label: &str,
    at: (i32, i32),
    (xs, ys): (&std::ops::Range<i32>, &std::ops::Range<i32>),
    placed: &[LabelBox],
) -> Option<(i32, i32)> {
    let w = LabelBox::text(label, 0, 0).x1;
    let slots = [
        (10, -8),
        (-w / 2, -27),
        (-w / 2, 11),
        (-w - 10, -8),
        (6, -27),
        (6, 11),
        (-w - 6, -27),
        (-w - 6, 11),
        (-w / 2, -45),
        (-w / 2, 29),
        (-w - 6, -45),
        (6, -45),
        (-w - 6, 29),
        (6, 29),
        (-w - 6, -63),
        (6, -63),
    ];
    slots.into_iter().find(|&(dx, dy)| {
        let b = LabelBox::text(label, at.0 + dx, at.1 + dy);
        let inside = b.y0 >= ys.start && b.y1 <= ys.end && b.x0 >= xs.start && b.x1 <= xs.end;
        // The mark's own box is among `placed`; a label never sits on a mark.
        inside && !placed.iter().any(|p| p.overlaps(&b))
    })
}

/// The methods a figure of `measure` draws: all but the hidden-line ones, and for
/// visibility the point-sampling ones.
fn surface_methods(measure: Measure) -> impl Iterator<Item = &'static Method> {
    METHODS.iter().filter(move |m| {
        m.draws == methods::Draws::Pixels && (measure == Measure::Rms || !anti_aliased(m.name))
    })
}

/// The legend's height for a picture `width` pixels wide: a row of entries of
/// [`LEGEND_ENTRY`] px each, as many rows as the methods need, and with `marked` (the
/// RMS figure with `--max-error`'s choices) the lines that say what the rings are.
fn legend_height(width: u32, measure: Measure, marked: bool) -> u32 {
    let per_row = (width.saturating_sub(40) / LEGEND_ENTRY).max(1) as usize;
    let rings = if marked {
        26 * ring_legend(width).len() as u32
    } else {
        0
    };
    16 + 26 * surface_methods(measure).count().div_ceil(per_row) as u32 + rings
}

const LEGEND_ENTRY: u32 = 150;

/// The radius of the ring that marks `--max-error`'s choice, pixels.
const RING: i32 = 13;

/// What the rings are, under the legend's methods.
pub const RING_LEGEND: &str = "Ringed, labelled ≤E: what render --max-error E chooses \
for E = 0, 1, 4 and 16 (by the same code; listed in max-error.csv); labelled \
\"predicted\": a configuration the chart did not run, hollow at the model's predicted \
seconds (less its prediction for an empty scene) and RMS";

/// [`RING_LEGEND`] in lines that fit `width` pixels beside the ring drawn before it.
fn ring_legend(width: u32) -> Vec<String> {
    register_font();
    let font = ("sans-serif", 16).into_font();
    let wide = |s: &str| {
        font.box_size(s)
            .map_or(9 * s.chars().count() as u32, |(w, _)| w)
    };
    wrap(RING_LEGEND, |s| wide(s) + 80 <= width)
}

/// Every method's colour and shape, under the panels; with `marked`, what the rings of
/// `--max-error`'s choices are.
fn legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    measure: Measure,
    marked: bool,
) -> Drawn
where
    DB::ErrorType: 'static,
{
    let width = area.dim_in_pixel().0;
    let per_row = (width.saturating_sub(40) / LEGEND_ENTRY).max(1) as usize;
    let count = surface_methods(measure).count();
    // Centred: the last row's entries line up under the others'.
    let used = (per_row.min(count) as u32 * LEGEND_ENTRY) as i32;
    let left = (width as i32 - used) / 2;
    for (i, m) in surface_methods(measure).enumerate() {
        let (row, col) = (i / per_row, i % per_row);
        let x = left + col as i32 * LEGEND_ENTRY as i32;
        let y = 8 + row as i32 * 26 + 10;
        let style = style_of(m.name);
        draw_mark(area, (x + 8, y), style, 7)?;
        area.draw(&Text::new(
            m.name,
            (x + 22, y),
            ("sans-serif", 16)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
    }
    if marked {
        let top = 8 + count.div_ceil(per_row) as i32 * 26 + 10;
        let left = 40;
        area.draw(&Circle::new((left, top), RING, BLACK.stroke_width(2)))?;
        for (i, line) in ring_legend(width).iter().enumerate() {
            area.draw(&Text::new(
                line.clone(),
                (left + 24, top + 26 * i as i32),
                ("sans-serif", 16)
                    .into_font()
                    .color(&BLACK)
                    .pos(Pos::new(HPos::Left, VPos::Center)),
            ))?;
        }
    }
    Ok(())
}

/// A `--max-error` choice as a panel marks it: where, its method, the chart's row when it
/// ran that configuration, and the budgets that chose it.
struct ChosenMark<'a> {
    at: (f64, f64),
    method: String,
    depth: Option<u8>,
    row: Option<&'a Row>,
    budgets: Vec<f64>,
}

impl ChosenMark<'_> {
    /// `≤1, ≤4` beside a mark the panel names already (`drawn`); else with the
    /// configuration, and `predicted` where the chart did not run it.
    fn label(&self, drawn: bool) -> String {
        let budgets: Vec<String> = self.budgets.iter().map(|e| format!("≤{e}")).collect();
        let budgets = budgets.join(", ");
        let depth = self.depth.map_or(String::new(), |d| format!(" d{d}"));
        match (drawn, self.row) {
            (true, _) => budgets,
            (false, Some(_)) => format!("{budgets}: {}{depth}", self.method),
            (false, None) => format!("{budgets}: {}{depth}, predicted", self.method),
        }
    }
}

/// The choices on `scene`'s panel, a mark a configuration (the budgets that chose it
/// together): at the chart's run of it, or at the model's prediction where there is
/// none (a safe choice without a prediction or a run is not drawn).
fn chosen_marks<'a>(rows: &'a [Row], scene: &str, choices: &[Choice]) -> Vec<ChosenMark<'a>> {
    let mut out: Vec<ChosenMark> = Vec::new();
    for c in choices.iter().filter(|c| c.scene == scene) {
        let row = c.depth.and_then(|d| {
            rows.iter()
                .find(|r| r.scene == scene && r.method == c.method && r.depth == d)
                .filter(|r| !r.rms().is_nan())
        });
        let at = match (row, c.predicted_less_startup_s, c.predicted_error) {
            (Some(r), _, _) => (time_of(r), r.rms()),
            (None, Some(t), Some(e)) => (t.max(TIME_FLOOR), e),
            _ => continue,
        };
        match out
            .iter_mut()
            .find(|m| m.method == c.method && m.depth == c.depth)
        {
            Some(m) => m.budgets.push(c.budget),
            None => out.push(ChosenMark {
                at,
                method: c.method.clone(),
                depth: c.depth,
                row,
                budgets: vec![c.budget],
            }),
        }
    }
    out
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
        draw(root).map_err(|e| Error::Data(format!("drawing {}: {e}", path.display())))?;
    }
    let image = image::RgbImage::from_raw(size.0, size.1, buf)
        .ok_or_else(|| Error::Data("picture buffer".into()))?;
    let mut bytes = std::io::Cursor::new(Vec::new());
    image
        .write_to(&mut bytes, image::ImageFormat::Png)
        .with_context(|| format!("cannot write {}", path.display()))?;
    stagecli::whole::write_whole(path, bytes.get_ref())?;
    Ok(())
}

/// An SVG picture drawn by `draw` into `path`, written whole or not at all.
fn svg(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(DrawingArea<SVGBackend, Shift>) -> Drawn,
) -> Result<()> {
    let mut text = String::new();
    draw(SVGBackend::with_string(&mut text, size).into_drawing_area())
        .map_err(|e| Error::Data(format!("drawing {}: {e}", path.display())))?;
    stagecli::whole::write_whole(path, text.as_bytes())?;
    Ok(())
}

/// `speed-accuracy.png` and `.svg` (RMS against the 16×16 reference) and
/// `visibility.png` and `.svg` (% of pixels whose visible polygon differs) in `dir`.
pub fn speed_accuracy(dir: &Path, rows: &[Row]) -> Result<()> {
    speed_accuracy_marked(dir, rows, &[])
}

/// [`speed_accuracy`], its RMS panels marked with `render --max-error`'s `choices`
/// (`DIR/max-error.csv`, [`crate::maxerror`]).
pub fn speed_accuracy_marked(dir: &Path, rows: &[Row], choices: &[Choice]) -> Result<()> {
    for (measure, name) in [
        (Measure::Rms, "speed-accuracy"),
        (Measure::Visibility, "visibility"),
    ] {
        let (cols, nrows) = layout(scenes_of(rows).len());
        let width = PANEL.0 * cols as u32;
        let title = title_lines(width, measure);
        let marked = measure == Measure::Rms && !choices.is_empty();
        let size = (
            width,
            PANEL.1 * nrows as u32
                + title_height(title.len())
                + legend_height(width, measure, marked),
        );
        png(&dir.join(format!("{name}.png")), size, |root| {
            speed_accuracy_on(root, rows, choices, &title, measure)
        })?;
        svg(&dir.join(format!("{name}.svg")), size, |root| {
            speed_accuracy_on(root, rows, choices, &title, measure)
        })?;
    }
    Ok(())
}

/// The methods of the cost-against-environment figure: the hidden-surface methods, the
/// anti-aliasing ones and the two hidden-line methods, each alone (depth 0). The
/// hidden-line methods have no pixel error, so this is the figure that compares them:
/// the continuous method's edge-against-polygon tests against Archuleta's counters on
/// Watkins's scan-line segments. A selection by name, not a column of the table of
/// methods: a new method is added here to appear on the figure.
pub const ENVIRONMENT_METHODS: [&str; 9] = [
    "zbuf",
    "scanline",
    "warnock",
    "painter",
    "painter-split",
    "abuf",
    "ss4",
    "hiddenline",
    "hiddenline-archuleta",
];

/// The least-squares slope of log y on log x: the power of the statistic a method's
/// cost grows with (1: in proportion; 0: not at all); `None` for fewer than three points
/// or one x.
pub fn log_slope(points: &[(f64, f64)]) -> Option<f64> {
    if points.len() < 3 {
        return None;
    }
    let n = points.len() as f64;
    let (mx, my) = points.iter().fold((0.0, 0.0), |(a, b), &(x, y)| {
        (a + x.ln() / n, b + y.ln() / n)
    });
    let (sxy, sxx) = points.iter().fold((0.0, 0.0), |(a, b), &(x, y)| {
        let dx = x.ln() - mx;
        (a + dx * (y.ln() - my), b + dx * dx)
    });
    (sxx > 1e-12).then(|| sxy / sxx)
}

/// A statistic of a run's scene, a frame.
pub type Statistic = fn(&Row) -> f64;

/// The environment statistics on the figure's x axes: a name, and the value of a run's
/// scene, a frame.
pub const STATISTICS: [(&str, Statistic); 4] = [
    ("polygons P_t, a frame", |r| {
        r.polygons as f64 / r.frames.max(1) as f64
    }),
    ("edges E_t, a frame", |r| r.edges),
    ("depth complexity Dc (covering polygons a pixel)", |r| {
        r.depth_complexity
    }),
    ("visible segments on the scan lines, a frame", |r| {
        r.visible_segments
    }),
];

/// The points of one method on one statistic's panel: (statistic, CPU s a frame above
/// the method's fixed cost) of its depth-0 runs, in order of the statistic.
///
/// Every run pays the pipeline's start (a dozen processes, about 0.01 s of CPU here)
/// whatever the scene: the row's start-up, measured on an empty scene (`startup_s`), is
/// taken off before its frames divide it, so that what is left is the work the scene
/// asks of the method. (A CSV from before the start-up was measured, `runs` 0, takes
/// off the method's least CPU time over the scenes instead.) A run within 0.1 ms of its
/// start-up has nothing left to show on a log axis and is left out; so is a scene
/// without the statistics (a CSV from before them).
pub fn environment_points(rows: &[Row], method: &str, stat: Statistic) -> Vec<(f64, f64)> {
    let runs: Vec<&Row> = rows
        .iter()
        .filter(|r| r.method == method && r.depth == 0)
        .collect();
    let least = runs.iter().map(|r| r.cpu_s).fold(f64::INFINITY, f64::min);
    let fixed = |r: &Row| if r.runs > 0 { r.startup_s } else { least };
    let mut p: Vec<(f64, f64)> = runs
        .iter()
        .map(|r| (stat(r), (r.cpu_s - fixed(r)) / r.frames.max(1) as f64))
        .filter(|&(x, y)| x > 0.0 && y >= 1e-4)
        .collect();
    p.sort_by(|a, b| a.0.total_cmp(&b.0));
    p
}

const ENV_TITLE: &str = "Cost against the environment statistics: CPU seconds a frame of \
each method alone (depth 0, the whole pipeline, its start-up measured on an empty scene taken off) on every \
scene, log-log; the dashed line is slope 1 (time proportional to the statistic)";

fn environment_on<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    rows: &[Row],
    title_text: &[String],
) -> Drawn
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (title, rest) = root.split_vertically(title_height(title_text.len()));
    draw_title(&title, title_text)?;
    let height = rest.dim_in_pixel().1;
    let (body, foot) = rest.split_vertically(height - 50);
    let panels = body.split_evenly((2, 2));
    for ((name, stat), panel) in STATISTICS.iter().zip(panels) {
        let points: Vec<(&str, Vec<(f64, f64)>)> = ENVIRONMENT_METHODS
            .iter()
            .map(|m| (*m, environment_points(rows, m, *stat)))
            .collect();
        let all: Vec<(f64, f64)> = points.iter().flat_map(|(_, p)| p.clone()).collect();
        if all.is_empty() {
            continue;
        }
        let (xmin, xmax, ymin, ymax) = all.iter().fold(
            (f64::INFINITY, 0.0f64, f64::INFINITY, 0.0f64),
            |(a, b, c, d), &(x, y)| (a.min(x), b.max(x), c.min(y), d.max(y)),
        );
        let (xlo, xhi) = decades(xmin / 1.5, xmax * 1.5);
        let (ylo, yhi) = decades(ymin / 1.5, ymax * 1.5);
        let mut chart = ChartBuilder::on(&panel)
            .caption(*name, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(52)
            .y_label_area_size(72)
            .build_cartesian_2d((xlo..xhi).log_scale(), (ylo..yhi).log_scale())?;
        chart
            .configure_mesh()
            .x_desc(format!("{name} (log scale)"))
            .y_desc("CPU s a frame less start-up (log)")
            .axis_desc_style(("sans-serif", 18))
            .label_style(("sans-serif", 16))
            .x_labels(log_ticks(xlo, xhi))
            .y_labels(log_ticks(ylo, yhi))
            .x_max_light_lines(0)
            .y_max_light_lines(0)
            .x_label_formatter(&|v| log_tick(*v))
            .y_label_formatter(&|v| log_tick(*v))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()?;
        // Slope 1 through the points' geometric mean: a method whose marks climb with it
        // costs in proportion to the statistic.
        let n = all.len() as f64;
        let (mx, my) = all.iter().fold((0.0, 0.0), |(a, b), &(x, y)| {
            (a + x.ln() / n, b + y.ln() / n)
        });
        let k = (my - mx).exp();
        chart.draw_series(DashedLineSeries::new(
            [(xlo, k * xlo), (xhi, k * xhi)],
            6,
            4,
            RGBColor(120, 120, 120).stroke_width(2),
        ))?;
        for (method, p) in &points {
            let style = style_of(method);
            for &at in p {
                draw_mark(chart.plotting_area(), at, style, 6)?;
            }
        }
        // Each method's fitted slope, in its colour, top left: the power of the
        // statistic its cost grows with, over these scenes.
        let mut line = 0;
        for (method, p) in &points {
            let Some(slope) = log_slope(p) else { continue };
            let (c, _) = style_of(method);
            chart.plotting_area().draw(
                &(EmptyElement::at((xlo, yhi))
                    + Text::new(
                        format!("{method}: slope {slope:.2}"),
                        (10, 8 + 18 * line),
                        ("sans-serif", 15).into_font().color(&c),
                    )),
            )?;
            line += 1;
        }
    }
    // The legend: the figure's methods in one row.
    let width = foot.dim_in_pixel().0 as i32;
    let entry = 150;
    let left = (width - entry * ENVIRONMENT_METHODS.len() as i32) / 2;
    for (i, m) in ENVIRONMENT_METHODS.iter().enumerate() {
        let x = left + i as i32 * entry;
        draw_mark(&foot, (x + 8, 25), style_of(m), 7)?;
        foot.draw(&Text::new(
            *m,
            (x + 22, 25),
            ("sans-serif", 16)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
    }
    root.present()?;
    Ok(())
}

/// `cost-environment.png` and `.svg` in `dir`: each method's cost against the scenes'
/// environment statistics ([`crate::stats`]).
pub fn environment(dir: &Path, rows: &[Row]) -> Result<()> {
    let width = PANEL.0 * 2;
    let title = wrap_title(ENV_TITLE, width);
    let size = (width, PANEL.1 * 2 + title_height(title.len()) + 50);
    png(&dir.join("cost-environment.png"), size, |root| {
        environment_on(root, rows, &title)
    })?;
    svg(&dir.join("cost-environment.svg"), size, |root| {
        environment_on(root, rows, &title)
    })
}

fn model_on<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    rows: &[ModelRow],
    extra: &[Extrapolation],
) -> Drawn
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (left, right) = root.split_horizontally(900);
    measured_panel(&left, rows)?;
    prediction_panel(&right, extra)?;
    root.present()?;
    Ok(())
}

/// The model against measurement: predicted against measured seconds, a mark a depth.
fn measured_panel<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, rows: &[ModelRow]) -> Drawn
where
    DB::ErrorType: 'static,
{
    // A run without zbuf (`--methods hiddenline`) has no row to predict: no panel (an
    // axis from infinity would ask plotters for ticks without end).
    if rows.is_empty() {
        return Ok(());
    }
    let all = rows.iter().flat_map(|r| [r.predicted_s, r.measured_s]);
    let (lo, hi) = all.fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    let (lo, hi) = decades(lo / 1.3, hi * 1.5);
    let mean = rows.iter().map(|r| r.error.abs()).sum::<f64>() / rows.len().max(1) as f64;
    let mut chart = ChartBuilder::on(root)
        .caption(
            format!(
                "Cost model (thesis 5.2, 6.4) against measurement: mean |error| {:.0}%",
                mean * 100.0
            ),
            ("sans-serif", 22),
        )
        .margin(16)
        .x_label_area_size(56)
        .y_label_area_size(80)
        .build_cartesian_2d((lo..hi).log_scale(), (lo..hi).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("measured wall time of render (median), seconds (log scale)")
        .y_desc("predicted, seconds (log scale)")
        .axis_desc_style(("sans-serif", 18))
        .label_style(("sans-serif", 16))
        .x_labels(log_ticks(lo, hi))
        .y_labels(log_ticks(lo, hi))
        .max_light_lines(0)
        .x_label_formatter(&|v| log_tick(*v))
        .y_label_formatter(&|v| log_tick(*v))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    chart
        .draw_series(LineSeries::new([(lo, lo), (hi, hi)], BLACK.stroke_width(1)))?
        .label("predicted = measured")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], BLACK));
    let grey = RGBColor(150, 150, 150);
    for f in [0.75, 1.25] {
        chart.draw_series(DashedLineSeries::new(
            [(lo, lo * f), (hi, hi * f)],
            6,
            4,
            grey.stroke_width(1),
        ))?;
    }
    chart
        .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())?
        .label("±25% (the target)")
        .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], grey));
    let mut scenes: Vec<&str> = Vec::new();
    for r in rows {
        if !scenes.contains(&r.scene.as_str()) {
            scenes.push(&r.scene);
        }
    }
    for (i, scene) in scenes.iter().enumerate() {
        // Circles, as the legend draws them: the scenes differ by colour.
        let c = STYLES[i % STYLES.len()].0;
        let style = (c, Shape::Circle);
        let mine: Vec<&ModelRow> = rows.iter().filter(|r| r.scene == *scene).collect();
        for r in &mine {
            draw_mark(
                chart.plotting_area(),
                (r.measured_s, r.predicted_s),
                style,
                6,
            )?;
        }
        chart
            .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())?
            .label(format!("{scene} (dN: depth N)"))
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
        .label_font(("sans-serif", 16))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .draw()?;
    Ok(())
}

/// The model's extrapolation, not measured: one scene's predicted time at each depth on
/// more cores than this machine has, and with its subtrees on other hosts.
fn prediction_panel<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    extra: &[Extrapolation],
) -> Drawn
where
    DB::ErrorType: 'static,
{
    let Some(first) = extra.first() else {
        return Ok(());
    };
    let (lo, hi) = extra.iter().fold((f64::INFINITY, 0.0f64), |(a, b), r| {
        (a.min(r.predicted_s), b.max(r.predicted_s))
    });
    let (lo, hi) = decades(lo / 1.3, hi * 1.5);
    let mut chart = ChartBuilder::on(root)
        .caption(
            format!(
                "PREDICTION, not measured: {} on more cores, on hosts",
                first.scene
            ),
            ("sans-serif", 22),
        )
        .margin(16)
        .x_label_area_size(56)
        .y_label_area_size(80)
        .build_cartesian_2d(-0.2f64..6.2f64, (lo..hi).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("splitter tree depth (2^depth leaves)")
        .y_desc("predicted wall time, seconds (log scale)")
        .axis_desc_style(("sans-serif", 18))
        .label_style(("sans-serif", 16))
        .x_labels(7)
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_labels(log_ticks(lo, hi))
        .y_max_light_lines(0)
        .y_label_formatter(&|v| log_tick(*v))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    let mut targets: Vec<&str> = Vec::new();
    for r in extra {
        if !targets.contains(&r.target.as_str()) {
            targets.push(&r.target);
        }
    }
    for (i, target) in targets.iter().enumerate() {
        let c = PALETTE[i % PALETTE.len()];
        let points: Vec<(f64, f64)> = extra
            .iter()
            .filter(|r| r.target == *target)
            .map(|r| (r.depth as f64, r.predicted_s))
            .collect();
        let hosts = target.contains("host");
        // The first hosts' line is drawn wide, so that where the second lies on it
        // (the link is not what limits) both show.
        let line = c.stroke_width(if hosts && i + 2 == targets.len() {
            6
        } else {
            2
        });
        if hosts {
            chart
                .draw_series(DashedLineSeries::new(points.clone(), 8, 5, line))?
                .label(target.to_string())
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], c.stroke_width(2)));
        } else {
            chart
                .draw_series(LineSeries::new(points.clone(), line))?
                .label(target.to_string())
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], c.stroke_width(2)));
        }
        chart.draw_series(points.iter().map(|&p| Circle::new(p, 4, c.filled())))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerLeft)
        .label_font(("sans-serif", 16))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .draw()?;
    Ok(())
}

/// `model.png` in `dir`: the model against measurement (left; the dashed lines ±25%) and
/// its extrapolation to more cores and to hosts (right), marked as prediction.
pub fn model(dir: &Path, rows: &[ModelRow], extra: &[Extrapolation]) -> Result<()> {
    png(&dir.join("model.png"), (1800, 760), |root| {
        model_on(root, rows, extra)
    })
}

/// `hidden-lines.png`: seconds a frame (log) against line error (% of the reference
/// drawing's length) for the two hidden-line methods, a colour a scene, a line through
/// each method's sizes, each point labelled with its size (`crate::hidden`).
pub fn hidden_lines(path: &Path, rows: &[crate::hidden::HiddenRow]) -> Result<()> {
    let size = (1100, 760);
    png(path, size, |root| hidden_lines_on(root, rows))
}

fn hidden_lines_on<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    rows: &[crate::hidden::HiddenRow],
) -> Drawn
where
    DB::ErrorType: 'static,
{
    // Exact drawings (error 0) are drawn at the axis's floor.
    const FLOOR: f64 = 0.1;
    const COLOURS: [RGBColor; 4] = [
        RGBColor(31, 119, 180),
        RGBColor(214, 39, 40),
        RGBColor(44, 160, 44),
        RGBColor(148, 103, 189),
    ];
    root.fill(&WHITE)?;
    let tmin = rows.iter().map(|r| r.seconds).fold(f64::INFINITY, f64::min);
    let tmax = rows.iter().map(|r| r.seconds).fold(0.0, f64::max);
    let emax = rows.iter().map(|r| r.error_px).fold(FLOOR, f64::max);
    let largest = rows.iter().map(|r| r.size).max().unwrap_or(0);
    // Room right of and above the last marks for their size labels (`256²`), which
    // were cut at the frame when the axes ended at the largest values.
    let (ylo, yhi) = decades(tmin.max(1e-4), 1.5 * tmax.max(2e-4));
    let (xlo, xhi) = decades(FLOOR, 3.0 * emax);
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Hidden lines: time against line error (Archuleta's counters against exact geometry)",
            ("sans-serif", 22),
        )
        .margin(16)
        .x_label_area_size(56)
        .y_label_area_size(80)
        .build_cartesian_2d((xlo..xhi).log_scale(), (ylo..yhi).log_scale())?;
    chart
        .configure_mesh()
        .x_desc(format!(
            "line error: visible length missed + length drawn off it, pixels of {largest}² \
             (0.5 px reach; exact = 0, drawn at {FLOOR})"
        ))
        .y_desc("hiddenline wall time a frame, seconds (log)")
        .axis_desc_style(("sans-serif", 17))
        .label_style(("sans-serif", 16))
        .x_labels(log_ticks(xlo, xhi))
        .x_max_light_lines(0)
        .x_label_formatter(&|v| log_tick(*v))
        .y_labels(log_ticks(ylo, yhi))
        .y_max_light_lines(0)
        .y_label_formatter(&|v| log_tick(*v))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    for (i, (scene, _)) in crate::hidden::SCENES.iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        for method in crate::hidden::METHODS {
            let mut pts: Vec<&crate::hidden::HiddenRow> = rows
                .iter()
                .filter(|r| r.scene == *scene && r.method == method)
                .collect();
            pts.sort_by_key(|r| r.size);
            let xy: Vec<(f64, f64)> = pts
                .iter()
                .map(|r| (r.error_px.max(FLOOR), r.seconds))
                .collect();
            let exact = method == "continuous";
            let line = chart.draw_series(LineSeries::new(
                xy.clone(),
                colour.stroke_width(if exact { 1 } else { 2 }),
            ))?;
            if exact {
                line.label(format!("{scene}: continuous (exact)"))
                    .legend(move |(x, y)| Circle::new((x + 10, y), 5, colour.stroke_width(2)));
                chart.draw_series(
                    xy.iter()
                        .map(|&p| Circle::new(p, 5, colour.stroke_width(2))),
                )?;
            } else {
                line.label(format!("{scene}: archuleta"))
                    .legend(move |(x, y)| TriangleMarker::new((x + 10, y), 6, colour.filled()));
                chart.draw_series(
                    xy.iter()
                        .map(|&p| TriangleMarker::new(p, 7, colour.filled())),
                )?;
            }
            for (r, &(x, y)) in pts.iter().zip(&xy) {
                chart.draw_series(std::iter::once(Text::new(
                    format!(" {}²", r.size),
                    (x, y),
                    ("sans-serif", 13).into_font().color(&colour),
                )))?;
            }
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::Coordinate(110, 470))
        .background_style(WHITE.mix(0.9))
        .border_style(RGBColor(180, 180, 180))
        .label_font(("sans-serif", 15))
        .draw()?;
    Ok(())
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
            time_s: wall_s,
            time_lo_s: wall_s,
            time_hi_s: wall_s,
            startup_s: 0.0,
            startup_share: 0.0,
            runs: 0,
            max_rss_kib: 1,
            error_fraction: Some(0.0),
            edge_rmse: None,
            rms_16x16: Some(rmse),
            visibility_error: (!anti_aliased(method)).then_some(0.0),
            edges: 8.0,
            depth_complexity: 1.0,
            visible_polygons: 2.0,
            visible_segments: 10.0,
            segments_per_line: 1.0,
            line_pieces: None,
            intersection_pieces: None,
            line_length_px: None,
            line_error_px: None,
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
        let m = marks(&rows, "s", Measure::Rms);
        assert_eq!(m.len(), 3);
        assert_eq!(m[0].depth, 1);
        let front: Vec<&str> = pareto(&m).iter().map(|r| r.method.as_str()).collect();
        assert_eq!(front, ["zbuf", "ss4"]);
    }

    #[test]
    fn a_log_axis_from_decades_gets_its_ticks_at_1_2_and_5_of_every_decade() {
        use plotters::coord::ranged1d::{KeyPointHint, Ranged};
        // The labels drawn on the log axis that spans the decades around lo..hi.
        let labels = |lo: f64, hi: f64| -> Vec<String> {
            let (lo, hi) = decades(lo, hi);
            let axis: plotters::coord::combinators::LogCoord<f64> = (lo..hi).log_scale().into();
            axis.key_points(log_ticks(lo, hi))
                .iter()
                .map(|v| log_tick(*v))
                .filter(|l| !l.is_empty())
                .fold(Vec::new(), |mut v: Vec<String>, l| {
                    // The last light tick of a decade is the next decade's first: drawn
                    // twice in one place.
                    if v.last() != Some(&l) {
                        v.push(l);
                    }
                    v
                })
        };
        assert_eq!(labels(0.135, 0.28), ["0.1", "0.2", "0.5", "1"]);
        assert_eq!(
            labels(0.004, 0.9),
            ["0.001", "0.002", "0.005", "0.01", "0.02", "0.05", "0.1", "0.2", "0.5"]
        );
        let _ = KeyPointHint::max_num_points(&3usize);
    }

    #[test]
    fn the_anti_aliased_methods_are_the_tables_aa_rows() {
        let aa: Vec<&str> = METHODS
            .iter()
            .map(|m| m.name)
            .filter(|n| anti_aliased(n))
            .collect();
        assert_eq!(
            aa,
            [
                "abuf",
                "ss2",
                "ss4",
                "ss8",
                "ss16",
                "adaptive2",
                "adaptive4",
                "adaptive8",
                "adaptive16"
            ]
        );
        assert!(!anti_aliased("nothing") && !anti_aliased("zbuf-pixels"));
    }

    #[test]
    fn every_method_its_own_colour_and_no_two_alike() {
        assert_eq!(METHODS.len(), STYLES.len());
        for (i, a) in STYLES.iter().enumerate() {
            for b in &STYLES[i + 1..] {
                let d = (a.0 .0 as i32 - b.0 .0 as i32).abs()
                    + (a.0 .1 as i32 - b.0 .1 as i32).abs()
                    + (a.0 .2 as i32 - b.0 .2 as i32).abs();
                // Apart in colour, and those nearest apart in shape too.
                assert!(d > 60, "{a:?} and {b:?}");
                assert!(d > 150 || a.1 != b.1, "{a:?} and {b:?}");
            }
            // Dark enough to print on white: no channel sum above 600.
            assert!(
                (a.0 .0 as u32 + a.0 .1 as u32 + a.0 .2 as u32) < 600,
                "{a:?}"
            );
        }
        // The pairs the old chart confused.
        assert_ne!(style_of("painter"), style_of("zbuf-binary"));
        assert_ne!(style_of("scanline").1, style_of("zbuf-eye-z").1);
    }

    #[test]
    fn wide_log_axes_label_only_the_powers_of_ten() {
        let at = [0.0001, 0.0002, 0.0005, 0.001, 0.002, 0.05, 0.1];
        let wide: Vec<String> = at.iter().map(|v| log_tick_across(*v, 1e-5, 1.0)).collect();
        assert_eq!(wide, ["0.0001", "", "", "0.001", "", "", "0.1"]);
        let narrow: Vec<String> = at.iter().map(|v| log_tick_across(*v, 1e-4, 0.1)).collect();
        assert_eq!(
            narrow,
            ["0.0001", "0.0002", "0.0005", "0.001", "0.002", "0.05", "0.1"]
        );
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
    fn labels_take_the_first_free_slot_and_none_when_all_are_taken() {
        let area = (0..400, 0..300);
        let at = (100, 150);
        let marks = [LabelBox::mark(at.0, at.1)];
        // Right of the mark first.
        assert_eq!(
            place_label("zbuf", at, (&area.0, &area.1), &marks),
            Some((10, -8))
        );
        let mut placed = marks.to_vec();
        placed.push(LabelBox::text("zbuf", at.0 + 10, at.1 - 8));
        // Then above, centred.
        let w = LabelBox::text("scanline", 0, 0).x1;
        assert_eq!(
            place_label("scanline", at, (&area.0, &area.1), &placed),
            Some((-w / 2, -27))
        );
        // In the top right corner: no room right, above or below; so left.
        assert_eq!(
            place_label(
                "ss4",
                (395, 10),
                (&area.0, &area.1),
                &[LabelBox::mark(395, 10)]
            ),
            Some((-LabelBox::text("ss4", 0, 0).x1 - 10, -8))
        );
        // Every slot taken: no label (the legend names the mark).
        let crowd = [LabelBox {
            x0: 0,
            y0: 0,
            x1: 400,
            y1: 300,
        }];
        assert_eq!(place_label("abuf", at, (&area.0, &area.1), &crowd), None);
    }

    #[test]
    fn the_title_is_wrapped_to_fit_one_panel_and_kept_whole_on_three() {
        for (width, measure, text) in [
            (PANEL.0, Measure::Rms, TITLE),
            (3 * PANEL.0, Measure::Rms, TITLE),
            (PANEL.0, Measure::Visibility, VISIBILITY_TITLE),
        ] {
            let t = title_lines(width, measure);
            assert!(t.len() > 1, "{width}: {t:?}");
            assert_eq!(t.join(" "), text);
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
    fn the_slope_is_the_power_the_cost_grows_with() {
        let square: Vec<(f64, f64)> = [1.0, 10.0, 100.0].map(|x| (x, 3.0 * x * x)).to_vec();
        assert!((log_slope(&square).unwrap() - 2.0).abs() < 1e-12);
        let flat = [(1.0, 0.5), (10.0, 0.5), (1000.0, 0.5)];
        assert!(log_slope(&flat).unwrap().abs() < 1e-12);
        assert_eq!(log_slope(&square[..2]), None, "two points fit any line");
        assert_eq!(log_slope(&[(5.0, 1.0), (5.0, 2.0), (5.0, 3.0)]), None);
    }

    #[test]
    fn the_visibility_figure_leaves_the_anti_aliased_methods_out() {
        let mut rows = vec![
            row("zbuf", 0, 0.2, 3.0),
            row("ss4", 0, 0.3, 1.0),
            row("painter", 0, 0.1, 9.0),
            row("painter", 1, 0.05, 3.0),
        ];
        rows[2].visibility_error = Some(25.0);
        let m = marks(&rows, "s", Measure::Visibility);
        let names: Vec<&str> = m.iter().map(|r| r.method.as_str()).collect();
        assert_eq!(names, ["zbuf", "painter"]);
        // The painter's fastest depth is 1; its depth 0 is the one that is wrong.
        let zero = at_depth_zero(&rows, "s", "painter").unwrap();
        assert_eq!(error_of(zero, Measure::Visibility), 25.0);
        assert_eq!(error_of(zero, Measure::Rms), 9.0);
        assert_eq!(m[1].depth, 1);
        // On RMS every method is drawn.
        assert_eq!(marks(&rows, "s", Measure::Rms).len(), 3);
        // A run no slower than its start-up sits at the floor.
        rows[0].time_s = 0.0;
        assert_eq!(time_of(&rows[0]), TIME_FLOOR);
    }

    #[test]
    fn environment_points_take_off_the_fixed_cost() {
        let mut rows = vec![
            row("zbuf", 0, 0.0, 1.0),
            row("zbuf", 0, 0.0, 1.0),
            row("zbuf", 0, 0.0, 1.0),
            row("zbuf", 1, 0.0, 1.0),
        ];
        for (r, (cpu, polygons)) in
            rows.iter_mut()
                .zip([(0.01, 2), (0.11, 1000), (0.51, 5000), (9.0, 9)])
        {
            r.cpu_s = cpu;
            r.polygons = polygons;
        }
        let p = environment_points(&rows, "zbuf", STATISTICS[0].1);
        // The fixed cost is the least (0.01 s); the scene at it has nothing left and is
        // left out; depth 1 is not depth 0.
        assert_eq!(p.len(), 2);
        assert!(
            (p[0].0 - 1000.0).abs() < 1e-9 && (p[0].1 - 0.1).abs() < 1e-9,
            "{p:?}"
        );
        assert!(
            (p[1].0 - 5000.0).abs() < 1e-9 && (p[1].1 - 0.5).abs() < 1e-9,
            "{p:?}"
        );
        // With each row's start-up measured, that is what is taken off.
        for r in rows.iter_mut() {
            (r.runs, r.startup_s) = (5, 0.005);
        }
        let p = environment_points(&rows, "zbuf", STATISTICS[0].1);
        assert_eq!(p.len(), 3);
        assert!(
            (p[0].0 - 2.0).abs() < 1e-9 && (p[0].1 - 0.005).abs() < 1e-9,
            "{p:?}"
        );
    }

    #[test]
    fn the_hidden_line_methods_are_on_the_cost_figure_alone() {
        // Three scenes of 1, 100 and 1,000 polygons: zbuf's cost in proportion, the
        // continuous hidden-line method's as the square, Archuleta's in proportion.
        let mut rows = Vec::new();
        for (scene, p) in [("a", 1.0f64), ("b", 100.0), ("c", 1000.0)] {
            for (method, cpu) in [
                ("zbuf", 0.01 + 1e-4 * p),
                ("hiddenline", 0.01 + 1e-6 * p * p),
                ("hiddenline-archuleta", 0.01 + 2e-4 * p),
            ] {
                let mut r = row(method, 0, cpu, 1.0);
                r.scene = scene.into();
                r.cpu_s = cpu;
                r.polygons = p as u64;
                if method.starts_with("hiddenline") {
                    (r.rms_16x16, r.error_fraction, r.visibility_error) = (None, None, None);
                    r.line_pieces = Some(3 * p as u64);
                }
                rows.push(r);
            }
        }
        // A point to every scene but the cheapest (the fixed cost), for both.
        for m in ["hiddenline", "hiddenline-archuleta"] {
            assert!(ENVIRONMENT_METHODS.contains(&m));
            assert_eq!(
                environment_points(&rows, m, STATISTICS[0].1).len(),
                2,
                "{m}"
            );
        }
        // No mark on a speed-accuracy panel (their error is NaN), and the panel of a
        // scene with a 16×16 reference still draws its anti-aliased methods.
        let m = marks(&rows, "b", Measure::Rms);
        assert_eq!(
            m.iter().map(|r| r.method.as_str()).collect::<Vec<_>>(),
            ["zbuf"]
        );
        let dir = tempfile::tempdir().unwrap();
        speed_accuracy(dir.path(), &rows).unwrap();
        let svg = std::fs::read_to_string(dir.path().join("speed-accuracy.svg")).unwrap();
        assert!(
            !svg.contains("hiddenline"),
            "figure 1 names no hidden-line method"
        );
        // Figure 2: their fitted slopes (2 points fit any line; 4 scenes give 3).
        let mut more = rows.clone();
        for m in ["zbuf", "hiddenline", "hiddenline-archuleta"] {
            let mut r = rows
                .iter()
                .find(|r| r.method == m && r.scene == "c")
                .unwrap()
                .clone();
            r.scene = "d".into();
            r.polygons = 10_000;
            r.cpu_s = match m {
                "zbuf" => 0.01 + 1.0,
                "hiddenline" => 0.01 + 100.0,
                _ => 0.01 + 2.0,
            };
            more.push(r);
        }
        environment(dir.path(), &more).unwrap();
        let svg = std::fs::read_to_string(dir.path().join("cost-environment.svg")).unwrap();
        assert!(
            svg.contains("hiddenline: slope 2.00"),
            "the continuous one's square"
        );
        assert!(
            svg.contains("hiddenline-archuleta: slope 1.00"),
            "Archuleta's line"
        );
        assert!(svg.contains("zbuf: slope 1.00"));
    }

    fn choice(budget: f64, method: &str, depth: u8, predicted: (f64, f64)) -> Choice {
        Choice {
            scene: "s".into(),
            budget,
            method: method.into(),
            aa: if method == "zbuf" { "none" } else { method }.into(),
            depth: Some(depth),
            predicted_time_s: Some(predicted.0),
            predicted_error: Some(predicted.1),
            predicted_less_startup_s: Some(predicted.0),
            measured_time_s: None,
            measured_rms: None,
            rule: "cheapest predicted to meet it".into(),
        }
    }

    #[test]
    fn max_error_choices_are_ringed_at_their_runs_or_their_predictions() {
        let rows = vec![
            row("zbuf", 0, 0.2, 30.0),
            row("ss4", 0, 0.4, 3.0),
            row("ss4", 2, 0.5, 3.0),
        ];
        let choices = [
            choice(0.0, "adaptive16", 0, (0.9, 0.0)),
            choice(1.0, "ss4", 2, (0.3, 0.8)),
            choice(4.0, "ss4", 2, (0.3, 0.8)),
            choice(16.0, "zbuf", 0, (0.1, 12.0)),
        ];
        let m = chosen_marks(&rows, "s", &choices);
        let seen: Vec<String> = m
            .iter()
            .map(|c| {
                format!(
                    "{} at {:?}, run {}: {:?} / {:?}",
                    c.method,
                    c.at,
                    c.row.is_some(),
                    c.label(true),
                    c.label(false)
                )
            })
            .collect();
        assert_eq!(
            seen,
            [
                // Not run: at the prediction, named.
                r#"adaptive16 at (0.9, 0.0), run false: "≤0" / "≤0: adaptive16 d0, predicted""#,
                // Run: at the run's time and measured RMS, two budgets on one ring.
                r#"ss4 at (0.5, 3.0), run true: "≤1, ≤4" / "≤1, ≤4: ss4 d2""#,
                r#"zbuf at (0.2, 30.0), run true: "≤16" / "≤16: zbuf d0""#,
            ]
        );
        assert!(chosen_marks(&rows, "other", &choices).is_empty());
        // On the RMS figure, a ring each and one in the legend, which says what they are;
        // none on the visibility figure.
        let dir = tempfile::tempdir().unwrap();
        speed_accuracy_marked(dir.path(), &rows, &choices).unwrap();
        let svg = std::fs::read_to_string(dir.path().join("speed-accuracy.svg")).unwrap();
        let rings = svg.matches(r##"r="13" opacity="1" fill="none" stroke="#000000""##);
        assert_eq!(rings.count(), 4);
        for line in ring_legend(PANEL.0) {
            let escaped = line.replace('"', "&quot;").replace('\'', "&apos;");
            assert!(svg.contains(&escaped), "{line}");
        }
        assert!(svg.contains("≤0: adaptive16 d0, predicted"));
        let vis = std::fs::read_to_string(dir.path().join("visibility.svg")).unwrap();
        assert!(!vis.contains(r#"r="13""#) && !vis.contains("max-error"));
        let png = image::open(dir.path().join("speed-accuracy.png")).unwrap();
        let lines = title_lines(PANEL.0, Measure::Rms).len();
        assert_eq!(
            png.height(),
            PANEL.1 + title_height(lines) + legend_height(PANEL.0, Measure::Rms, true)
        );
        assert_eq!(
            legend_height(PANEL.0, Measure::Rms, true),
            legend_height(PANEL.0, Measure::Rms, false) + 26 * ring_legend(PANEL.0).len() as u32
        );
    }

    #[test]
    fn pictures_are_written() {
        let dir = tempfile::tempdir().unwrap();
        let rows = vec![row("zbuf", 0, 0.2, 30.0), row("zbuf-eye-z", 0, 0.3, 31.0)];
        speed_accuracy(dir.path(), &rows).unwrap();
        let png = image::open(dir.path().join("speed-accuracy.png")).unwrap();
        // One panel is narrower than the title: it is wrapped, the picture taller; the
        // legend below, the table's surface methods four to a row.
        let lines = title_lines(PANEL.0, Measure::Rms).len();
        assert_eq!(
            (png.width(), png.height()),
            (
                PANEL.0,
                PANEL.1 + title_height(lines) + legend_height(PANEL.0, Measure::Rms, false)
            )
        );
        let rows = surface_methods(Measure::Rms).count().div_ceil(4) as u32;
        assert_eq!(legend_height(PANEL.0, Measure::Rms, false), 16 + 26 * rows);
        let svg = std::fs::read_to_string(dir.path().join("speed-accuracy.svg")).unwrap();
        assert!(svg.contains("zbuf-eye-z"), "the label is in the SVG");
        assert!(svg.contains(TIME_AXIS) && svg.contains(Measure::Rms.axis()));
        // The visibility figure beside it, its own measure on the y axis, the
        // anti-aliasing methods out of its legend.
        let vis = std::fs::read_to_string(dir.path().join("visibility.svg")).unwrap();
        assert!(vis.contains(Measure::Visibility.axis()) && vis.contains(TIME_AXIS));
        assert!(!vis.contains(">ss4<") && svg.contains("ss4"));
    }
}
