//! The scaling report: PGS solve time against the number of contacts, a least-squares line and
//! its R², as CSV and an SVG plot. docs/blocks2d.md §"Scaling".

use crate::common::timing::timed;
use crate::problem::ContactProblem;
use crate::solve::{PgsSettings, PgsWorkspace, solve_pgs};
use plotters::prelude::*;
use rand::SeedableRng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;
use std::path::Path;

/// PGS solve time of each of `problems`, measured side by side: `rounds` rounds, each solving
/// every problem once in a fresh random order (seeded), and for each problem its number of
/// contacts with the median of its rounds' thread CPU times (wall times where there is no thread
/// clock), s.
///
/// Why not the times taken during the run: in a factory the contact count grows with time, so
/// the machine's slow and fast spells (other tenants, clock changes, shared caches) are tied to
/// the contact counts of the moment and bend the fit. Interleaved, every size sees every spell.
/// Each problem carries its warm start, so a re-solve does the run's work exactly.
pub fn retime<const D: usize, const R: usize>(
    problems: &[ContactProblem<D, R>],
    settings: &PgsSettings,
    rounds: usize,
    seed: u64,
) -> Vec<(f64, f64)> {
    let mut workspace = PgsWorkspace::<D, R>::new(seed);
    let mut lambda = Vec::new();
    // Grow the buffers to the largest problem first, so that no timed solve allocates.
    if let Some(largest) = problems.iter().max_by_key(|p| p.contacts.len()) {
        solve_pgs(largest, settings, &mut workspace, &mut lambda);
    }
    let mut times = vec![Vec::with_capacity(rounds); problems.len()];
    let mut order: Vec<usize> = (0..problems.len()).collect();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for _ in 0..rounds {
        order.shuffle(&mut rng);
        for &i in &order {
            let (_, wall, cpu) =
                timed(|| solve_pgs(&problems[i], settings, &mut workspace, &mut lambda));
            times[i].push(cpu.unwrap_or(wall));
        }
    }
    problems
        .iter()
        .zip(times)
        .map(|(p, mut t)| {
            t.sort_by(f64::total_cmp);
            (p.contacts.len() as f64, t[t.len() / 2])
        })
        .collect()
}

/// y ≈ slope x + intercept, and the coefficient of determination R².
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct LinearFit {
    /// Slope.
    pub slope: f64,
    /// Intercept.
    pub intercept: f64,
    /// R² = 1 − Σ(y − ŷ)² / Σ(y − ȳ)².
    pub r_squared: f64,
    /// Points fitted.
    pub points: usize,
}

impl LinearFit {
    /// "t = a ms × contacts ± c ms, R² = r", for seconds fitted against contacts.
    pub fn describe_ms(&self) -> String {
        let sign = if self.intercept < 0.0 { '−' } else { '+' };
        format!(
            "t = {:.3e} ms × contacts {sign} {:.3e} ms, R² = {:.3}",
            self.slope * 1e3,
            self.intercept.abs() * 1e3,
            self.r_squared
        )
    }
}

/// Least-squares line through `points` (x, y); `None` for fewer than two distinct x.
pub fn linear_fit(points: &[(f64, f64)]) -> Option<LinearFit> {
    let n = points.len() as f64;
    if points.len() < 2 {
        return None;
    }
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    let intercept = my - slope * mx;
    let ss_res: f64 = points
        .iter()
        .map(|p| (p.1 - (slope * p.0 + intercept)).powi(2))
        .sum();
    let ss_tot: f64 = points.iter().map(|p| (p.1 - my).powi(2)).sum();
    let r_squared = if ss_tot > 0.0 {
        1.0 - ss_res / ss_tot
    } else {
        1.0
    };
    Some(LinearFit {
        slope,
        intercept,
        r_squared,
        points: points.len(),
    })
}

/// Plots solve time (ms) against contacts as SVG: `points` (the fitted measurements) in blue
/// with the fitted line in red, and `background` (other measurements of the same, for
/// comparison) in light grey underneath.
pub fn plot(
    points: &[(f64, f64)],
    background: &[(f64, f64)],
    fit: &LinearFit,
    path: &Path,
    title: &str,
) -> Result<(), String> {
    let root = SVGBackend::new(path, (900, 600)).into_drawing_area();
    let err = |e: &dyn std::fmt::Display| format!("{}: cannot draw: {e}", path.display());
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let all = || points.iter().chain(background);
    let x_max = all().map(|p| p.0).fold(1.0, f64::max);
    let y_max = all().map(|p| p.1 * 1e3).fold(1e-3, f64::max);
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("{title}: {}", fit.describe_ms()),
            ("sans-serif", 16),
        )
        .margin(20)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..x_max * 1.05, 0.0..y_max * 1.05)
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc("number of contacts")
        .y_desc("PGS solve time (ms)")
        .draw()
        .map_err(|e| err(&e))?;
    let grey = RGBColor(200, 200, 200);
    for (series, colour, size) in [(background, grey, 1), (points, BLUE, 2)] {
        chart
            .draw_series(
                series
                    .iter()
                    .map(|p| Circle::new((p.0, p.1 * 1e3), size, colour.filled())),
            )
            .map_err(|e| err(&e))?;
    }
    chart
        .draw_series(LineSeries::new(
            [0.0, x_max]
                .iter()
                .map(|&x| (x, (fit.slope * x + fit.intercept) * 1e3)),
            RED.stroke_width(2),
        ))
        .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))?;
    Ok(())
}

/// Size of the scaling plot drawn as a 2D scene image ([`scene_png`]), pixels = blocks.
pub const SCENE_SIZE: (u32, u32) = (160, 100);

/// Draws the scaling plot as an image for the 2D system to run ("use your graph as a test
/// image in your simulation"): one pixel per block, no anti-aliasing, so that every drawn pixel
/// is a whole block. The axes are blue (pinned: the ground and a wall), each measurement a black
/// 2 × 2 dot (dots that touch are one body), the fitted line red and 8-connected (one rigid
/// body). It falls onto the axes when run. docs/blocks2d.md §"Scaling".
pub fn scene_png(points: &[(f64, f64)], fit: &LinearFit, path: &Path) -> Result<(), String> {
    let (w, h) = SCENE_SIZE;
    let mut img = image::RgbImage::from_pixel(w, h, image::Rgb([255, 255, 255]));
    // Plot area: x in [left, right], y in [top, bottom], y up on the page.
    let (left, right, top, bottom) = (4u32, w - 4, 4u32, h - 5);
    for x in left..=right {
        img.put_pixel(x, bottom + 1, image::Rgb([0, 0, 163]));
    }
    for y in top..=bottom + 1 {
        img.put_pixel(left - 1, y, image::Rgb([0, 0, 163]));
    }
    let x_max = points.iter().map(|p| p.0).fold(1.0, f64::max);
    let y_max = points.iter().map(|p| p.1).fold(f64::MIN_POSITIVE, f64::max) * 1.1;
    let to_pixel = |x: f64, y: f64| -> (i64, i64) {
        let px = f64::from(left + 1) + x / x_max * f64::from(right - left - 2);
        let py = f64::from(bottom - 1) - y / y_max * f64::from(bottom - top - 2);
        (px.round() as i64, py.round() as i64)
    };
    // Drawn pixels keep one white pixel from each axis: a pixel next to an axis would join it
    // into one body that is no longer all blue, so nothing would be pinned (a fitted line with
    // a negative intercept reaches the bottom row; the 10 000-body factory's did).
    let inside = |x: i64, y: i64| {
        (i64::from(left + 1)..=i64::from(right)).contains(&x)
            && (i64::from(top)..=i64::from(bottom - 1)).contains(&y)
    };
    for &(x, y) in points {
        let (px, py) = to_pixel(x, y);
        for (dx, dy) in [(0, 0), (1, 0), (0, -1), (1, -1)] {
            if inside(px + dx, py + dy) {
                img.put_pixel((px + dx) as u32, (py + dy) as u32, image::Rgb([0, 0, 0]));
            }
        }
    }
    // The line, one pixel per column (8-connected: adjacent columns differ by one row at most
    // where the slope is below one pixel per pixel; steeper parts fill the rows between).
    let mut previous: Option<i64> = None;
    for px in i64::from(left + 1)..=i64::from(right - 1) {
        let x = (px as f64 - f64::from(left + 1)) / f64::from(right - left - 2) * x_max;
        let (_, py) = to_pixel(x, fit.slope * x + fit.intercept);
        let rows = match previous {
            Some(p) if (py - p).abs() > 1 => (p.min(py)..=p.max(py)).collect::<Vec<_>>(),
            _ => vec![py],
        };
        for y in rows {
            if inside(px, y) {
                img.put_pixel(px as u32, y as u32, image::Rgb([200, 0, 0]));
            }
        }
        previous = Some(py);
    }
    img.save(path)
        .map_err(|e| format!("{}: cannot write: {e}", path.display()))
}
