//! What a 2D scene's observables are expected to be: closed forms where the disc model has them,
//! else rigidref's exact run. docs/validation.md §"2D: pymunk".

use super::*;
use crate::tools::validation::judge::Expected;
use crate::tools::validation::observe::Measured;

/// The angle at which the toppling bar counts as having hit the ground, rad (80°: lying on its
/// side is 90°, and its top block's disc meets the ground's before that).
pub const HIT_ANGLE: f64 = 80.0 * std::f64::consts::PI / 180.0;

fn x(
    key: &'static str,
    name: &'static str,
    unit: &'static str,
    exact: Option<f64>,
    tolerance: Option<f64>,
    note: String,
) -> Expected {
    Expected {
        key,
        name,
        unit,
        exact,
        tolerance,
        note,
    }
}

/// The expectations of a 2D scene: closed forms where the disc model has them, else rigidref's
/// exact run (`reference`, its own observables).
pub fn expectations_2d(loaded: &Loaded2, reference: &[Measured]) -> Vec<Expected> {
    let p = &loaded.world.params;
    let theirs = |key: &str| {
        reference
            .iter()
            .find(|m| m.key == key)
            .and_then(|m| m.value)
    };
    let slop = p.slop;
    let pen = |from: &str| {
        x(
            "penetration",
            "deepest disc overlap",
            "blocks",
            Some(0.0),
            Some(2.0 * slop),
            format!(
                "rigidref's disc overlap on the run's poses{from}; within twice rigidref's slop {slop} (the overlap its post-stabilisation lets stand)"
            ),
        )
    };
    let mut out = match loaded.known.known {
        Known2::Slide => {
            let b = &loaded.world.bodies[0];
            let v0 = loaded
                .world
                .impulses
                .first()
                .map_or(0.0, |i| i.impulse.norm() / b.mass);
            let g = p.gravity;
            let flat = v0 * v0 / (2.0 * p.mu * g);
            let (t, d) = (theirs("stop_time"), theirs("stop_distance"));
            vec![
                x(
                    "stop_time",
                    "stop time after the push",
                    "time",
                    t,
                    t.map(|t| 2.0 * p.dt + 0.05 * t),
                    format!(
                        "rigidref's exact run (a flat Coulomb slide would stop after v₀/(μg) = {:.4}; the discs' bumps stop it sooner); within 2 steps + 5 %",
                        v0 / (p.mu * g)
                    ),
                ),
                x(
                    "stop_distance",
                    "slide distance",
                    "blocks",
                    d,
                    d.map(|d| 0.05 * d.abs()),
                    format!(
                        "rigidref's exact run (a flat Coulomb slide would go v₀²/(2μg) = {flat:.4}; over the ground's discs it climbs bumps 0.09 high); within 5 %"
                    ),
                ),
                pen(""),
            ]
        }
        Known2::Topple => {
            let t = theirs("hit_time");
            vec![
                x(
                    "hit_time",
                    "time from the push to 80°",
                    "time",
                    t,
                    t.map(|t| 2.0 * p.dt + 0.05 * t),
                    "rigidref's exact run; within 2 steps + 5 %".to_string(),
                ),
                x(
                    "final_angle",
                    "final |θ|",
                    "rad",
                    Some(std::f64::consts::FRAC_PI_2),
                    Some(0.05),
                    "lying on its side, π/2; within 0.05 rad (its ends rest on the ground's discs)"
                        .to_string(),
                ),
                pen(""),
            ]
        }
        Known2::Rest => vec![
            x(
                "rest_drift",
                "largest displacement after settling",
                "blocks",
                Some(0.0),
                Some(0.01),
                format!("0 from t = {REST_FROM} on (a stack at rest stays); within 0.01 block"),
            ),
            pen(&format!(" from t = {REST_FROM} on")),
        ],
    };
    out.push(x("criterion_primal", "primal criterion (max)", "mass·block/time", None, None,
        "reported: 0 for Coulomb's law (ContactBench), on each step's last substep's contacts and impulses".to_string()));
    out.push(x(
        "criterion_dual",
        "dual criterion (max)",
        "block/time",
        None,
        None,
        "reported: 0 for Coulomb's law".to_string(),
    ));
    out.push(x(
        "criterion_complementarity",
        "complementarity (max)",
        "mass·block²/time²",
        None,
        None,
        "reported: 0 for Coulomb's law".to_string(),
    ));
    out
}
