//! Watching the penetration measure during a run: the deepest interpenetration seen, and one
//! warning per pair of bodies (or body and ground) the first time it exceeds its bound.
//! docs/contact.md §"Penetration measure".

use crate::rigid3d::collide::CollisionMethod;
use crate::rigid3d::world::World;
use std::collections::HashSet;

/// The run's interpenetration so far.
#[derive(Clone, Debug, Default)]
pub struct InterpenetrationWatch {
    /// The deepest interpenetration measured after any step, m.
    pub deepest: f64,
    /// The step after which it was measured.
    pub deepest_step: u64,
    warned: HashSet<(usize, Option<usize>)>,
    /// Pairs already warned about resting deep in each other.
    warned_resting: HashSet<(usize, Option<usize>)>,
}

/// A pair at rest deeper than this fraction of the smaller body's size gets a warning
/// (docs/contact.md §"Penetration measure").
pub const RESTING_SINK_FRACTION: f64 = 0.1;

/// Bodies count as at rest when no point of theirs moves faster than this, m/s.
pub const RESTING_SPEED: f64 = 1e-3;

impl InterpenetrationWatch {
    /// Looks at the world's penetration measure after a step; returns a warning for each pair
    /// that exceeds its bound for the first time in this run. A run without collision checking
    /// (`check_collisions: false`) asked for bodies to pass through each other: it gets none.
    pub fn observe(&mut self, world: &World) -> Vec<String> {
        let mut warnings = Vec::new();
        let at_rest = |i: usize| {
            let b = &world.bodies[i];
            let radius = crate::rigid3d::collide::penetration::mesh_size(&b.mesh);
            b.v.norm() + b.omega.norm() * radius < RESTING_SPEED
        };
        for p in &world.penetrations {
            // The smaller body's size, of which the bound is a fixed fraction.
            let size = p.bound / crate::rigid3d::collide::penetration::PENETRATION_BOUND;
            // Only below the bound, and never for a pair the bound's warning has named: deeper
            // than the bound the contacts were missed, not holding the bodies.
            if world.params.check_collisions
                && p.depth > RESTING_SINK_FRACTION * size
                && !p.exceeds_bound()
                && !self.warned.contains(&(p.body1, p.body2))
                && at_rest(p.body1)
                && p.body2.is_none_or(at_rest)
                && self.warned_resting.insert((p.body1, p.body2))
            {
                let name = |i: usize| format!("body {i} ({:?})", world.bodies[i].name);
                let pair = match p.body2 {
                    Some(j) => format!("{} and {}", name(p.body1), name(j)),
                    None => format!("{} and the ground", name(p.body1)),
                };
                warnings.push(format!(
                    "warning: step {} (t = {} s): {pair} are at rest {:.4} m deep in each other, more than a tenth of the smaller body's size ({size:.4} m): a contact is holding them there (stabilization_slop {} m, stabilization {}, compliance {} kg⁻¹); lower the slop or the compliance, or raise stabilization",
                    world.step,
                    world.time(),
                    p.depth,
                    world.params.stabilization_slop,
                    world.params.stabilization,
                    world.params.compliance,
                ));
            }
            if p.depth > self.deepest {
                self.deepest = p.depth;
                self.deepest_step = world.step;
            }
            if !world.params.check_collisions
                || !p.exceeds_bound()
                || !self.warned.insert((p.body1, p.body2))
            {
                continue;
            }
            let name = |i: usize| format!("body {i} ({:?})", world.bodies[i].name);
            let pair = match p.body2 {
                Some(j) => format!("{} and {}", name(p.body1), name(j)),
                None => format!("{} and the ground", name(p.body1)),
            };
            let advice = match (world.params.collision, p.body2) {
                (CollisionMethod::Vertices, Some(_)) => {
                    "the vertex rule missed their contacts; `collision: complete` (or --set collision=complete) finds them"
                }
                _ => {
                    "the contacts found did not keep them apart (too fast a body for the step, or too few PGS iterations)"
                }
            };
            warnings.push(format!(
                "warning: step {} (t = {} s): {pair} interpenetrate by {:.4} m, more than the bound {:.4} m (a quarter of the smaller body's size): {advice}",
                world.step,
                world.time(),
                p.depth,
                p.bound
            ));
        }
        warnings
    }
}
