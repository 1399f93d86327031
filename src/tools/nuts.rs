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
