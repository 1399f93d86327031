//! Watching the penetration measure during a run: the deepest interpenetration seen, and one
//! warning per pair of bodies (or body and ground) the first time it exceeds its bound, the
//! first time a contact found between them is deeper than the bound, and the first time a
//! contact is deeper than the bodies overlap by the measure (which reads the separating-axis
//! oracle, not the contacts). docs/contact.md §"Penetration measure", §"Never silent".

use crate::rigid3d::collide::CollisionMethod;
use crate::rigid3d::collide::audit::preferred_depth_bound;
use crate::rigid3d::collide::penetration::PENETRATION_BOUND;
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
    /// Pairs already warned about a contact deeper than the bound.
    warned_deep_contact: HashSet<(usize, usize)>,
    /// Pairs already warned about a contact deeper than the measured overlap.
    warned_disagreeing: HashSet<(usize, usize)>,
    /// Warnings given so far (every kind), for the run's summary.
    pub warnings: usize,
    /// Working list of each pair's deepest contact in the last substep.
    deepest_by_pair: Vec<((usize, usize), f64)>,
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
        let mut warnings = self.contacts_against_measure(world);
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
            let found = match p.body2 {
                Some(_) if world.step == 0 => String::new(),
                Some(j) => {
                    let between = world.solves.last().map_or(0, |s| {
                        s.contacts
                            .iter()
                            .filter(|c| pair_of(c) == Some((p.body1, j)))
                            .count()
                    });
                    if between == 0 {
                        "; no contact between them was found".to_string()
                    } else {
                        format!("; {between} contacts between them were found")
                    }
                }
                None => String::new(),
            };
            let advice = match (world.step, world.params.collision, p.body2) {
                (0, _, _) => format!(
                    "the scene writes them overlapping; stabilisation pushes them apart at most at stabilization_max_speed ({} m/s)",
                    world.params.stabilization_max_speed
                ),
                (_, CollisionMethod::Vertices, Some(_)) => {
                    "the vertex rule missed their contacts; `collision: complete` (or --set collision=complete) finds them".into()
                }
                (_, CollisionMethod::Starter, Some(_)) => {
                    "the starter's rule (only the vertices of the mesh with more vertices, against the other) missed their contacts; `collision: complete` (or --set collision=complete) finds them".into()
                }
                _ => {
                    "the contacts found did not keep them apart (too fast a body for the step, or too few PGS iterations)".into()
                }
            };
            warnings.push(format!(
                "warning: step {} (t = {} s): {pair} interpenetrate by {:.4} m, more than the bound {:.4} m (a quarter of the smaller body's size){found}: {advice}",
                world.step,
                world.time(),
                p.depth,
                p.bound
            ));
        }
        self.warnings += warnings.len();
        warnings
    }

    /// The warnings about the last substep's contacts between bodies: one deeper than the
    /// bound, or one deeper than the bodies overlap by the measure (convex bodies; the measure
    /// is taken after the step, so it is allowed the bodies' motion since detection).
    fn contacts_against_measure(&mut self, world: &World) -> Vec<String> {
        let mut warnings = Vec::new();
        let Some(solve) = world.solves.last() else {
            return warnings;
        };
        let colliders = world.colliders();
        let name = |i: usize| format!("body {i} ({:?})", world.bodies[i].name);
        // The last substep's deepest contact of each run of one body pair's contacts (detection
        // lists a pair's contacts together, so this is one entry per pair without a search).
        let deepest = &mut self.deepest_by_pair;
        deepest.clear();
        for c in &solve.contacts {
            let Some(pair) = pair_of(c) else { continue };
            match deepest.last_mut() {
                Some((p, d)) if *p == pair => *d = d.max(c.depth),
                _ => deepest.push((pair, c.depth)),
            }
        }
        let deepest = std::mem::take(deepest);
        let motion_steps = f64::from(world.params.substeps - solve.substep);
        let h = world.params.h();
        for &((i, j), depth) in &deepest {
            let bound = PENETRATION_BOUND * colliders[i].size().min(colliders[j].size());
            if depth > bound && self.warned_deep_contact.insert((i, j)) {
                warnings.push(format!(
                    "warning: step {} (t = {} s): a contact between {} and {} is {depth:.4} m deep, more than the bound {bound:.4} m (a quarter of the smaller body's size): the step let them pass far into each other (too fast for the step), or detection is wrong there",
                    world.step,
                    world.time(),
                    name(i),
                    name(j)
                ));
            }
            let convex =
                |k: usize| colliders[k].pieces.convex && world.bodies[k].ellipsoid.is_none();
            if !(convex(i) && convex(j)) {
                continue;
            }
            // The measure lists the ground's entries first, then the pairs in sorted order.
            let pairs =
                &world.penetrations[world.penetrations.partition_point(|p| p.body2.is_none())..];
            let measured = pairs
                .binary_search_by_key(&(i, j), |p| (p.body1, p.body2.unwrap_or(usize::MAX)))
                .map_or(0.0, |k| pairs[k].depth);
            let speed = |k: usize| {
                let b = &world.bodies[k];
                b.v.norm() + b.omega.norm() * colliders[k].radius()
            };
            let motion = motion_steps * h * (speed(i) + speed(j));
            let radius = colliders[i].radius().max(colliders[j].radius());
            let allowed = preferred_depth_bound(measured + motion, radius);
            if depth > allowed && self.warned_disagreeing.insert((i, j)) {
                warnings.push(format!(
                    "warning: step {} (t = {} s): a contact between {} and {} is {depth:.4} m deep, but the bodies overlap by {measured:.4} m (measured by separating axes, independently of the contacts; {allowed:.4} m allowed for the motion since): detection found a contact that is not there",
                    world.step,
                    world.time(),
                    name(i),
                    name(j)
                ));
            }
        }
        self.deepest_by_pair = deepest;
        warnings
    }
}

/// A contact's body pair, lower index first; `None` for a ground contact.
fn pair_of(c: &crate::rigid3d::collide::Contact) -> Option<(usize, usize)> {
    c.body2.map(|j| (c.body1.min(j), c.body1.max(j)))
}
