//! The benchmark's report: the fitted exponent of cost against bodies, the Markdown tables, the
//! targets of docs/performance.md and the SVG plot.

use super::*;

/// The least-squares slope of log y against log x: the exponent p of y ∝ xᵖ (`None` for fewer
/// than two distinct points).
pub fn fitted_exponent(points: &[(f64, f64)]) -> Option<f64> {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    crate::tools::experiments::scaling::linear_fit(&logs).map(|fit| fit.slope)
}

/// Bodies from which a family's exponent is fitted: the range starts at 100 (below it a
/// step is dominated by fixed costs); families with fewer than two such sizes use every size.
pub const EXPONENT_FROM_BODIES: usize = 100;

/// The rows of `family` the exponents are fitted over, and the smallest size used.
pub(super) fn fitted_rows<'a>(rows: &'a [BenchRow], family: &str) -> Vec<&'a BenchRow> {
    let all: Vec<&BenchRow> = rows.iter().filter(|r| r.family == family).collect();
    let large: Vec<&BenchRow> = all
        .iter()
        .copied()
        .filter(|r| r.bodies >= EXPONENT_FROM_BODIES)
        .collect();
    if large.len() >= 2 { large } else { all }
}

/// The fitted exponent of `g` against the bodies over `rows` (`None` where `g` has no value).
pub(super) fn exponent_of(rows: &[&BenchRow], g: impl Fn(&BenchRow) -> Option<f64>) -> Option<f64> {
    let points: Option<Vec<(f64, f64)>> = rows
        .iter()
        .map(|r| g(r).map(|y| (r.bodies as f64, y)))
        .collect();
    fitted_exponent(&points?)
}

pub(super) fn cell(x: Option<f64>, digits: usize) -> String {
    x.map_or("–".to_string(), |x| format!("{x:.digits$}"))
}

/// The families of `rows` in order of first appearance, the assignment's scenes left out (they
/// are not sizes of one scene).
pub(super) fn families(rows: &[BenchRow]) -> Vec<&'static str> {
    let mut out: Vec<&'static str> = Vec::new();
    for r in rows {
        if r.family != "assignment" && !out.contains(&r.family) {
            out.push(r.family);
        }
    }
    out
}

/// The report as Markdown: one table row per case, the fitted exponents per family, and the
/// issue's targets read off the rows.
pub fn markdown(rows: &[BenchRow], s: &BenchSettings) -> String {
    let mut out = format!(
        "{} PGS sweeps in 3D (rapier: {} solver iterations; the 2D factory keeps its own 20 sweeps), medians of {} rounds of {} steps ({} above 2 000 bodies) after {} warm-up steps at every size (so that a family's sizes are timed in the same phase of their motion). Times in ms per step; \"measure\" is the 3D penetration measure and 2D post-stabilisation; rapier's columns are its own timers, and its \"serial setup\" is only the part of its set-up before its workers start: it generates the contact constraints inside its iterations' timer (docs/performance.md §\"Issue 49: what rapier's set-up timer holds\").\n\n",
        s.iterations,
        s.iterations,
        s.rounds,
        s.steps,
        s.for_bodies(usize::MAX).steps,
        s.warmup,
    );
    out.push_str("| scene | bodies | contacts | rigidref ms/step | rapier ms/step | ratio | detect | assemble | PGS | apply | integrate | measure | PGS ns/contact/sweep | rapier collision | rapier serial setup | rapier iterations | detect+assemble+apply / rapier collision+serial setup | pair lists kept (nearest features kept) |\n");
    out.push_str("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for r in rows {
        let rp = |k: usize| cell(r.rapier_phases_ms.map(|p| p[k]), 3);
        out.push_str(&format!(
            "| {} | {} | {} | {:.3} | {} | {} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.1} | {} | {} | {} | {} | {} |\n",
            r.name,
            r.bodies,
            r.contacts,
            r.ours_ms,
            cell(r.rapier_ms, 3),
            cell(r.ratio(), 2),
            r.phases_ms[0],
            r.phases_ms[1],
            r.phases_ms[2],
            r.phases_ms[3],
            r.phases_ms[4],
            r.phases_ms[5],
            r.ns_per_contact_sweep,
            rp(0),
            rp(1),
            rp(2),
            cell(r.around_solve_ratio(), 2),
            match (r.detection_kept, r.nearest_kept) {
                (None, _) => "–".to_string(),
                (Some(k), None) => format!("{:.1} %", 100.0 * k),
                (Some(k), Some(n)) => format!("{:.1} % ({:.0} %)", 100.0 * k, 100.0 * n),
            },
        ));
    }
    out.push_str(&format!(
        "\nFitted exponents p of cost ∝ bodiesᵖ (least squares in log–log, over the sizes from {EXPONENT_FROM_BODIES} bodies up where a family has two, else over all):\n\n"
    ));
    out.push_str("| family | sizes (bodies) | rigidref step | rapier step | detection | contacts | PGS per contact-sweep |\n|---|---|---|---|---|---|---|\n");
    for f in families(rows) {
        let used = fitted_rows(rows, f);
        out.push_str(&format!(
            "| {f} | {}–{} | {} | {} | {} | {} | {} |\n",
            used.first().map_or(0, |r| r.bodies),
            used.last().map_or(0, |r| r.bodies),
            cell(exponent_of(&used, |r| Some(r.ours_ms)), 2),
            cell(exponent_of(&used, |r| r.rapier_ms), 2),
            cell(exponent_of(&used, |r| Some(r.phases_ms[0])), 2),
            cell(exponent_of(&used, |r| Some(r.contacts as f64)), 2),
            cell(exponent_of(&used, |r| Some(r.ns_per_contact_sweep)), 2),
        ));
    }
    out.push_str(&targets(rows));
    out
}

/// The targets (issue 20, item 3) as read off `rows`: each with what was measured and
/// whether it holds. Only the families the run had.
pub fn targets(rows: &[BenchRow]) -> String {
    let mut out = String::from(
        "\nTargets, from the rows above:\n\n| target | measured | met |\n|---|---|---|\n",
    );
    let yes = |b: bool| if b { "yes" } else { "no" };
    // The grid and equal-cube scenes from 20 bodies (smaller ones are fixed costs).
    let structures: Vec<&BenchRow> = rows
        .iter()
        .filter(|r| {
            matches!(
                r.family,
                "stack grid" | "cube stack grid" | "cube pyramid" | "pyramid grid"
            ) && r.bodies >= 20
        })
        .collect();
    fn worst(g: &dyn Fn(&BenchRow) -> Option<f64>, of: &[&BenchRow]) -> Option<(f64, String)> {
        of.iter()
            .filter_map(|r| g(r).map(|x| (x, r.name.clone())))
            .max_by(|a, b| a.0.total_cmp(&b.0))
    }
    if let Some((ratio, name)) = worst(&|r| r.ratio(), &structures) {
        let best = structures
            .iter()
            .filter_map(|r| r.ratio())
            .fold(f64::INFINITY, f64::min);
        out.push_str(&format!(
            "| whole step ≤ 1.0× rapier's (grids and pyramids, ≥ 20 bodies) | {best:.2}–{ratio:.2}× (worst: {name}) | {} |\n",
            yes(ratio <= 1.0)
        ));
    }
    let per_iteration = |r: &BenchRow| {
        r.rapier_phases_ms
            .filter(|_| r.contacts > 0)
            .map(|p| p[2] * 1e6 / (r.contacts as f64 * f64::from(r.iterations)))
    };
    let pgs: Vec<(f64, f64)> = structures
        .iter()
        .filter_map(|r| per_iteration(r).map(|theirs| (r.ns_per_contact_sweep, theirs)))
        .collect();
    if !pgs.is_empty() {
        let ours = pgs.iter().map(|p| p.0).fold(0.0, f64::max);
        let theirs = pgs.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
        let below = pgs.iter().all(|(a, b)| a < b);
        out.push_str(&format!(
            "| PGS per contact per sweep below rapier's per contact per iteration | ours up to {ours:.1} ns; rapier's iterations from {theirs:.1} ns (its timer over our contact count) | {} |\n",
            yes(below)
        ));
    }
    let rigid: Vec<&BenchRow> = rows
        .iter()
        .filter(|r| r.family != "assignment" && r.bodies >= 20)
        .collect();
    if let Some((ratio, name)) = worst(&|r| r.around_solve_ratio(), &rigid) {
        out.push_str(&format!(
            "| detection, assembly and recording per body ≤ 3× rapier's collision detection and constraint setup | up to {ratio:.2}× (worst: {name}), against rapier's collision and serial set-up only: its timers hold its constraint generation in its iterations | {} |\n",
            yes(ratio <= 3.0)
        ));
    }
    if let Some(r) = rows
        .iter()
        .filter(|r| r.family == "2D factory")
        .min_by_key(|r| r.bodies.abs_diff(10_001))
    {
        // The packed pile is made at once and is not at rest (docs/performance.md): its rate is
        // the step's cost at the size, not the target's verdict, which a factory run gives.
        let rate = 1e3 / r.ours_ms;
        out.push_str(&format!(
            "| 2D factory at 10 000 bodies ≥ 30 steps/s | the packed pile (made at once, not at rest): {rate:.1} steps/s at {} bodies | judged by a factory run, not here: `rigidref factory --pieces bricks --bodies 10000` reports its steps per second at the end (docs/performance.md) |\n",
            r.bodies,
        ));
    }
    // Linear cost: the families measured across the range, 100 to 10 000 bodies (the
    // single pyramids and the rain stop short of it, and their contacts per body grow with size:
    // their exponents are in the table above, not judged here).
    let mut linear = Vec::new();
    for f in families(rows) {
        let used = fitted_rows(rows, f);
        let (low, top) = (
            used.first().map_or(0, |r| r.bodies),
            used.last().map_or(0, |r| r.bodies),
        );
        if low < EXPONENT_FROM_BODIES || top < 10_000 {
            continue;
        }
        let by_bodies = exponent_of(&used, |r| Some(r.ours_ms));
        // Against contacts: the same fit with contacts in place of bodies.
        let by_contacts = fitted_exponent(
            &used
                .iter()
                .map(|r| (r.contacts as f64, r.ours_ms))
                .collect::<Vec<_>>(),
        );
        if let (Some(b), Some(c)) = (by_bodies, by_contacts) {
            linear.push((f, b, c, low, top));
        }
    }
    if linear.is_empty() {
        out.push_str("| cost linear from 100 to 10 000 bodies: exponent ≤ 1.1 | no family measured from 100 to 10 000 bodies in this run | – |\n");
    } else {
        let listed: Vec<String> = linear
            .iter()
            .map(|(f, b, c, low, top)| {
                format!("{f} ({low}–{top}): {b:.2} in bodies, {c:.2} in contacts")
            })
            .collect();
        out.push_str(&format!(
            "| cost linear from 100 to 10 000 bodies and contacts: exponent ≤ 1.1 | {} | {} |\n",
            listed.join("; "),
            yes(linear.iter().all(|e| e.1 <= 1.1 && e.2 <= 1.1))
        ));
    }
    out
}

/// Draws ms per step against bodies, log–log, one colour per family: rigidref solid with filled
/// dots, rapier dashed with open circles (DIR/bench.svg of `rigidref bench --out DIR`).
pub fn svg(rows: &[BenchRow], path: &std::path::Path, title: &str) -> Result<(), String> {
    use plotters::prelude::*;
    let err = |e: &dyn std::fmt::Display| format!("{}: cannot draw: {e}", path.display());
    let plotted: Vec<&BenchRow> = rows.iter().filter(|r| r.family != "assignment").collect();
    let (mut x_max, mut y_min, mut y_max) = (10.0_f64, f64::INFINITY, 0.0_f64);
    for r in &plotted {
        x_max = x_max.max(r.bodies as f64);
        for y in [Some(r.ours_ms), r.rapier_ms].into_iter().flatten() {
            y_min = y_min.min(y);
            y_max = y_max.max(y);
        }
    }
    if !y_min.is_finite() {
        (y_min, y_max) = (0.01, 1.0);
    }
    // Whole decades on the time axis, so that every point lies between two labelled powers of
    // ten (with a range inside one decade the axis labelled only the upper decade's ticks).
    let (y_low, y_high) = (
        decade_below((y_min * 0.7).max(1e-6)),
        decade_above((y_max * 1.5).max(1e-6)),
    );
    let root = SVGBackend::new(path, (900, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(20)
        .x_label_area_size(45)
        .y_label_area_size(65)
        .build_cartesian_2d((1.0..x_max * 1.5).log_scale(), (y_low..y_high).log_scale())
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc("bodies")
        .y_desc("ms per step")
        .draw()
        .map_err(|e| err(&e))?;
    let palette = crate::tools::viewing::plot::COLOURS;
    for (k, family) in families(rows).into_iter().enumerate() {
        let colour = palette[k % palette.len()];
        let of = |g: &dyn Fn(&BenchRow) -> Option<f64>| -> Vec<(f64, f64)> {
            plotted
                .iter()
                .filter(|r| r.family == family)
                .filter_map(|r| g(r).map(|y| (r.bodies as f64, y)))
                .collect()
        };
        let ours = of(&|r| Some(r.ours_ms));
        chart
            .draw_series(LineSeries::new(ours.clone(), colour.stroke_width(2)))
            .map_err(|e| err(&e))?
            .label(format!("rigidref: {family}"))
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
            });
        chart
            .draw_series(ours.iter().map(|p| Circle::new(*p, 4, colour.filled())))
            .map_err(|e| err(&e))?;
        let theirs = of(&|r| r.rapier_ms);
        if !theirs.is_empty() {
            chart
                .draw_series(DashedLineSeries::new(
                    theirs.clone(),
                    6,
                    4,
                    colour.stroke_width(1),
                ))
                .map_err(|e| err(&e))?
                .label(format!("rapier3d: {family}"))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(1))
                });
            chart
                .draw_series(
                    theirs
                        .iter()
                        .map(|p| Circle::new(*p, 4, colour.stroke_width(1))),
                )
                .map_err(|e| err(&e))?;
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))?;
    Ok(())
}

/// The largest power of ten at or below `y` (> 0), ms.
fn decade_below(y: f64) -> f64 {
    10f64.powf(y.log10().floor())
}

/// The smallest power of ten at or above `y` (> 0), ms.
fn decade_above(y: f64) -> f64 {
    10f64.powf(y.log10().ceil())
}

/// The solver rows as a Markdown table.
pub fn solver_markdown(rows: &[SolverRow]) -> String {
    let mut out = String::from(
        "\nThe exact solver's cost: each scene with its own parameters, PGS and `solver: newton` \
         side by side (interleaved rounds, medians).\n\n\
         | scene | PGS ms/step | Newton ms/step | Newton / PGS | Newton iterations per solve | unconverged solves |\n\
         |---|---|---|---|---|---|\n",
    );
    for r in rows {
        out.push_str(&format!(
            "| {} | {:.4} | {:.4} | {:.2} | {:.2} | {} |\n",
            r.name,
            r.pgs_ms,
            r.newton_ms,
            r.ratio(),
            r.newton_iterations,
            r.unconverged
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{decade_above, decade_below};

    #[test]
    fn the_time_axis_spans_whole_decades_around_the_points() {
        // A range inside one decade (1.23 to 49 ms) becomes 1 to 100 ms, so that both ends are
        // labelled powers of ten; a power of ten is its own decade, exactly.
        assert_eq!(decade_below(1.23), 1.0);
        assert_eq!(decade_above(49.0), 100.0);
        assert_eq!(decade_below(10.0), 10.0);
        assert_eq!(decade_above(10.0), 10.0);
        assert!(decade_below(0.0147) <= 0.0147 && decade_below(0.0147) > 0.00147);
        assert!(decade_above(0.0147) >= 0.0147 && decade_above(0.0147) < 0.147);
    }
}
