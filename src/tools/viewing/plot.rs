//! `rigidref plot`'s drawing: the plots of [`super::series`] for one run or several overlaid
//! (rigidref against another simulator's trace, two integrators, …), one panel per quantity,
//! as SVG or PNG (the same chart code on plotters' SVG backend or on
//! [`super::pixmap_backend`]). docs/viewing.md §"Plots".

use super::series::Plot;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// One run to draw: a label for the legend, the time of each record, and its plots.
#[derive(Clone, Debug)]
pub struct PlottedRun {
    /// Legend prefix when several runs are overlaid (the trace's file name).
    pub label: String,
    /// Time of each record (s in 3D, time units in 2D).
    pub t: Vec<f64>,
    /// The unit of [`Self::t`], for the time axis: [`TIME_UNIT_3D`] or [`TIME_UNIT_2D`].
    pub time_unit: &'static str,
    /// The plots, as [`super::series::plots_3d`] or [`super::series::plots_2d`] made them.
    pub plots: Vec<Plot>,
}

/// The 3D system's time unit (SI).
pub const TIME_UNIT_3D: &str = "s";
/// The 2D system's time unit (its gravity is 1 block per time unit², docs/blocks2d.md).
pub const TIME_UNIT_2D: &str = "time units";

/// Pixels per panel.
const PANEL: (u32, u32) = (1000, 300);

/// Line colours, by series (the first run) and then by run.
pub(crate) const COLOURS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
];

/// Draws the panels named by `keys` (in that order; every panel of the first run when empty) of
/// `runs` into `path`, as PNG when its extension is .png, else as SVG. Series of the second and later
/// runs are drawn thinner, and with several runs every legend name is prefixed by its run's label.
pub fn plot_runs(
    runs: &[PlottedRun],
    keys: &[&str],
    path: &Path,
    title: &str,
) -> Result<(), String> {
    let Some(first) = runs.first() else {
        return Err("nothing to plot".into());
    };
    let panels: Vec<&Plot> = if keys.is_empty() {
        first.plots.iter().collect()
    } else {
        keys.iter()
            .filter_map(|k| first.plots.iter().find(|p| p.key == *k))
            .collect()
    };
    if panels.is_empty() {
        return Err(format!(
            "{}: none of the quantities asked for is in the trace",
            path.display()
        ));
    }
    let size = (PANEL.0, PANEL.1 * panels.len() as u32 + 40);
    let err = |e: &dyn std::fmt::Display| format!("{}: cannot draw: {e}", path.display());
    let png = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if png {
        let backend = super::pixmap_backend::PixmapBackend::new(path, size).ok_or_else(|| {
            format!(
                "{}: cannot draw {}×{} pixels",
                path.display(),
                size.0,
                size.1
            )
        })?;
        let root = backend.into_drawing_area();
        draw(&root, runs, &panels, title).map_err(|e| err(&e))?;
        root.present().map_err(|e| err(&e))
    } else {
        let root = SVGBackend::new(path, size).into_drawing_area();
        draw(&root, runs, &panels, title).map_err(|e| err(&e))?;
        root.present().map_err(|e| err(&e))
    }
}

/// The finite values of a series with their times; a log plot keeps the positive values only,
/// as log10.
fn points(t: &[f64], values: &[Option<f64>], log: bool) -> Vec<Vec<(f64, f64)>> {
    // Split at gaps (missing or unplottable values) so that a line is not drawn across them.
    let mut segments = vec![Vec::new()];
    for (&t, v) in t.iter().zip(values) {
        let y = match v {
            Some(v) if log && *v > 0.0 => Some(v.log10()),
            Some(v) if !log && v.is_finite() => Some(*v),
            _ => None,
        };
        match y {
            Some(y) => segments
                .last_mut()
                .expect("one segment at least")
                .push((t, y)),
            None if !segments.last().expect("one segment at least").is_empty() => {
                segments.push(Vec::new())
            }
            None => {}
        }
    }
    segments.retain(|s| !s.is_empty());
    segments
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    runs: &[PlottedRun],
    panels: &[&Plot],
    title: &str,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    root.fill(&WHITE)?;
    let (top, body) = root.split_vertically(40);
    top.titled(title, ("sans-serif", 20))?;
    let time_unit = runs.first().map_or(TIME_UNIT_3D, |r| r.time_unit);
    let areas = body.split_evenly((panels.len(), 1));
    for (area, panel) in areas.iter().zip(panels) {
        // Every run's version of this panel (matched by key), with its series' points.
        let mut lines = Vec::new();
        for (r, run) in runs.iter().enumerate() {
            let Some(p) = run.plots.iter().find(|p| p.key == panel.key) else {
                continue;
            };
            for (s, series) in p.series.iter().enumerate() {
                let name = if runs.len() > 1 {
                    format!("{}: {}", run.label, series.name)
                } else {
                    series.name.clone()
                };
                let colour = COLOURS[(s + r * p.series.len()) % COLOURS.len()];
                let recorded = series.values.iter().any(Option::is_some);
                let segments = points(&run.t, &series.values, panel.log);
                lines.push((name, colour, r, segments, recorded));
            }
        }
        let all = || lines.iter().flat_map(|l| l.3.iter().flatten());
        let (mut x0, mut x1) = all().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.0), b.max(p.0))
        });
        let (mut y0, mut y1) = all().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.1), b.max(p.1))
        });
        if !x0.is_finite() {
            (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
        }
        if x1 <= x0 {
            x1 = x0 + 1.0;
        }
        // A constant series gets a band around it instead of a zero-height axis.
        let pad = ((y1 - y0) * 0.05)
            .max(1e-12 * y0.abs().max(y1.abs()))
            .max(1e-300);
        let (y0, y1) = if y1 - y0 > 0.0 {
            (y0 - pad, y1 + pad)
        } else {
            (y0 - 1.0, y1 + 1.0)
        };
        let unit = if panel.unit.is_empty() {
            String::new()
        } else {
            format!(" ({})", panel.unit)
        };
        // A log panel's axis names only the unit (its caption names the quantity), so that the
        // criteria's three units fit beside it.
        let y_desc = if panel.log && !panel.unit.is_empty() {
            format!("log10{unit}")
        } else if panel.log {
            format!("log10 {}", panel.title.to_lowercase())
        } else {
            format!("{}{unit}", panel.title)
        };
        let mut chart = ChartBuilder::on(area)
            .caption(&panel.title, ("sans-serif", 16))
            .margin(10)
            .x_label_area_size(30)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, y0..y1)?;
        chart
            .configure_mesh()
            .x_desc(format!("t ({time_unit})"))
            .y_desc(y_desc)
            .draw()?;
        for (name, colour, run, segments, recorded) in &lines {
            let width = if *run == 0 { 2 } else { 1 };
            // A recorded series with nothing to draw (zero throughout on a log axis) still gets
            // its legend entry, saying why it has no line.
            if segments.is_empty() && *recorded {
                let why = if panel.log {
                    "never above 0: no line on a log axis"
                } else {
                    "no finite value"
                };
                chart
                    .draw_series(LineSeries::new(
                        std::iter::empty(),
                        colour.stroke_width(width),
                    ))?
                    .label(format!("{name} ({why})"))
                    .legend(legend_mark(*colour));
            }
            for (k, segment) in segments.iter().enumerate() {
                let drawn = chart.draw_series(LineSeries::new(
                    segment.iter().copied(),
                    colour.stroke_width(width),
                ))?;
                if k == 0 {
                    drawn.label(name.as_str()).legend(legend_mark(*colour));
                }
            }
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()?;
    }
    Ok(())
}

/// A series' mark in the legend: a short line in its colour.
fn legend_mark(colour: RGBColor) -> impl Fn((i32, i32)) -> PathElement<(i32, i32)> {
    move |(x, y)| PathElement::new([(x, y), (x + 18, y)], colour.stroke_width(2))
}
