//! The scaling report: PGS solve time against the number of contacts, a least-squares line and
//! its R², as CSV and an SVG plot. docs/blocks2d.md §"Scaling".

use plotters::prelude::*;
use std::path::Path;

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

/// Plots solve time (ms) against contacts with the fitted line, as SVG.
pub fn plot(
    points: &[(f64, f64)],
    fit: &LinearFit,
    path: &Path,
    title: &str,
) -> Result<(), String> {
    let root = SVGBackend::new(path, (900, 600)).into_drawing_area();
    let err = |e: &dyn std::fmt::Display| format!("{}: cannot draw: {e}", path.display());
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let x_max = points.iter().map(|p| p.0).fold(1.0, f64::max);
    let y_max = points.iter().map(|p| p.1 * 1e3).fold(1e-3, f64::max);
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!(
                "{title}: t = {:.3e} ms × contacts + {:.3e} ms, R² = {:.3}",
                fit.slope * 1e3,
                fit.intercept * 1e3,
                fit.r_squared
            ),
            ("sans-serif", 18),
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
    chart
        .draw_series(
            points
                .iter()
                .map(|p| Circle::new((p.0, p.1 * 1e3), 1, BLUE.filled())),
        )
        .map_err(|e| err(&e))?;
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
