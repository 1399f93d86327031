//! The nut-bag challenge's measure: where the heaviest fifth of the moving bodies is relative to
//! the rest (height = −y, since image rows grow downward). docs/blocks2d.md §"Challenges".

use crate::blocks2d::body::Body2;
use crate::blocks2d::world::World2;

/// Where the heaviest fifth of the moving bodies is. NaN throughout with fewer than two moving
/// bodies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NutStatistics {
    /// Mean height of the heaviest fifth, blocks.
    pub heaviest_mean_height: f64,
    /// Mean height of the other moving bodies, blocks.
    pub others_mean_height: f64,
    /// Fraction of the heaviest fifth at or above the median height of all moving bodies.
    pub heaviest_fraction_in_upper_half: f64,
}

/// The statistics of `world`'s moving bodies now.
pub fn nut_statistics(world: &World2) -> NutStatistics {
    let mut moving: Vec<&Body2> = world.bodies.iter().filter(|b| !b.pinned).collect();
    if moving.len() < 2 {
        return NutStatistics {
            heaviest_mean_height: f64::NAN,
            others_mean_height: f64::NAN,
            heaviest_fraction_in_upper_half: f64::NAN,
        };
    }
    moving.sort_by(|a, b| b.mass.total_cmp(&a.mass));
    let heavy = (moving.len() / 5).max(1);
    let mean = |s: &[&Body2]| s.iter().map(|b| -b.x.y).sum::<f64>() / s.len() as f64;
    let mut heights: Vec<f64> = moving.iter().map(|b| -b.x.y).collect();
    heights.sort_by(f64::total_cmp);
    let median = heights[heights.len() / 2];
    let upper = moving[..heavy].iter().filter(|b| -b.x.y >= median).count() as f64 / heavy as f64;
    NutStatistics {
        heaviest_mean_height: mean(&moving[..heavy]),
        others_mean_height: mean(&moving[heavy..]),
        heaviest_fraction_in_upper_half: upper,
    }
}

/// The fraction of the heaviest fifth at or above the median height from which the largest nuts
/// count as risen: well above the 0.5 of a mixture and the 0.39 of nuts3.png as drawn.
pub const RISEN: f64 = 0.8;

/// The moving bodies whose centre of mass has left the pinned bodies' bounding box (the bag):
/// 0 while the bag holds every nut.
pub fn outside_bag(world: &World2) -> usize {
    let (mut lo, mut hi) = (
        nalgebra::Vector2::repeat(f64::INFINITY),
        nalgebra::Vector2::repeat(f64::NEG_INFINITY),
    );
    for b in world.bodies.iter().filter(|b| b.pinned) {
        for block in &b.blocks {
            let p = b.to_world(&block.local);
            lo = lo.inf(&p);
            hi = hi.sup(&p);
        }
    }
    world
        .bodies
        .iter()
        .filter(|b| !b.pinned)
        .filter(|b| b.x.x < lo.x || b.x.x > hi.x || b.x.y < lo.y || b.x.y > hi.y)
        .count()
}

/// The first time at which the fraction of the heaviest fifth in the upper half reached
/// [`RISEN`], from `(t, fraction)` points in time order; `None` if it never did.
pub fn time_to_rise(points: &[(f64, f64)]) -> Option<f64> {
    points.iter().find(|p| p.1 >= RISEN).map(|p| p.0)
}

/// How many shaking cycles the fraction must hold at [`RISEN`] on average for the largest nuts
/// to count as risen for good ([`time_to_rise_held`]): long against the one-nut flicker of the
/// fraction (one nut is 1/31 of nuts3.png's heaviest fifth) and short against the hundreds of
/// cycles the rise takes.
pub const HOLD_CYCLES: f64 = 50.0;

/// The first time t at which the fraction is at least [`RISEN`] and its mean over the points in
/// [t, t + `hold`] is too, the run reaching t + `hold` (so the rise holds, not a flicker); from
/// `(t, fraction)` points in time order, `hold` in time units; `None` if it never did.
/// docs/blocks2d.md §"Shaking the nut bag".
pub fn time_to_rise_held(points: &[(f64, f64)], hold: f64) -> Option<f64> {
    let end = points.last()?.0;
    // prefix[i] = sum of the fractions of points[..i], so a window's mean is two lookups.
    let mut prefix = Vec::with_capacity(points.len() + 1);
    prefix.push(0.0);
    for p in points {
        prefix.push(prefix.last().unwrap() + p.1);
    }
    let mut stop = 0;
    for (i, &(t, f)) in points.iter().enumerate() {
        if t + hold > end {
            return None;
        }
        stop = stop.max(i);
        while stop + 1 < points.len() && points[stop + 1].0 <= t + hold {
            stop += 1;
        }
        let mean = (prefix[stop + 1] - prefix[i]) / (stop + 1 - i) as f64;
        if f >= RISEN && mean >= RISEN {
            return Some(t);
        }
    }
    None
}

/// Plots the fraction of the heaviest fifth in the upper half against time as an SVG, with the
/// 0.5 of a mixture and the [`RISEN`] line; `title` heads it.
pub fn plot(points: &[(f64, f64)], path: &std::path::Path, title: &str) -> Result<(), String> {
    use plotters::prelude::*;
    let root = SVGBackend::new(path, (900, 500)).into_drawing_area();
    let err = |e: &dyn std::fmt::Display| format!("{}: cannot draw: {e}", path.display());
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let t_max = points.iter().map(|p| p.0).fold(1.0, f64::max);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 16))
        .margin(20)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..t_max, 0.0..1.0)
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc("time")
        .y_desc("heaviest fifth in the upper half")
        .draw()
        .map_err(|e| err(&e))?;
    for (level, colour) in [(0.5, RGBColor(180, 180, 180)), (RISEN, RED)] {
        chart
            .draw_series(LineSeries::new(
                [(0.0, level), (t_max, level)],
                colour.stroke_width(1),
            ))
            .map_err(|e| err(&e))?;
    }
    chart
        .draw_series(LineSeries::new(
            points.iter().copied(),
            BLUE.stroke_width(2),
        ))
        .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flicker above 0.8 is not a rise; a rise that holds is, from its first point; a run that
    /// ends before the window closes has not shown it.
    #[test]
    fn a_rise_counts_only_when_it_holds_for_the_window() {
        let flicker = [
            (0.0, 0.4),
            (10.0, 0.81),
            (20.0, 0.5),
            (30.0, 0.5),
            (40.0, 0.5),
        ];
        assert_eq!(time_to_rise(&flicker), Some(10.0));
        assert_eq!(time_to_rise_held(&flicker, 20.0), None);
        let rise = [
            (0.0, 0.4),
            (10.0, 0.81),
            (20.0, 0.77),
            (30.0, 0.9),
            (40.0, 0.85),
        ];
        assert_eq!(time_to_rise_held(&rise, 20.0), Some(10.0));
        // The window from t = 10 reaches 40 at most: a 40-unit window cannot close.
        assert_eq!(time_to_rise_held(&rise, 40.0), None);
        assert_eq!(time_to_rise_held(&[], 1.0), None);
        // hold 0: the first point at RISEN.
        assert_eq!(time_to_rise_held(&rise, 0.0), Some(10.0));
    }
}
