//! The 2D trace: the same JSON Lines format as 3D (docs/trace-format.md §"2D traces") with
//! `"dimension": 2` in the header and 2D states in the records.

use super::diagnostics::{Energy2, Momentum2};
use super::world::World2;
use serde::{Deserialize, Serialize};

/// First line.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TraceHeader2 {
    /// `rigidref-trace`.
    pub format: String,
    /// 1.
    pub version: u32,
    /// 2.
    pub dimension: u32,
    /// Scene name (the image's file stem).
    pub scene: String,
    /// Where it came from.
    pub source: String,
    /// Parameters set on the command line (`--set KEY=VALUE`), as `KEY=VALUE`; the key is
    /// present only when some were given.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub overrides: Vec<String>,
    /// Step size.
    pub dt: f64,
    /// Substeps per step.
    pub substeps: u32,
    /// Gravity vector, blocks/time², image frame (y down).
    pub gravity: [f64; 2],
    /// Bodies in order.
    pub bodies: Vec<BodyInfo2>,
}

/// A body in the header.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BodyInfo2 {
    /// `body{index}`.
    pub name: String,
    /// Mass (0 blocks never; pinned bodies report their block mass).
    pub mass: f64,
    /// Pinned (infinite mass).
    pub pinned: bool,
    /// Number of blocks.
    pub blocks: usize,
}

/// One recorded step.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Record2 {
    /// Step number.
    pub step: u64,
    /// Time.
    pub t: f64,
    /// Body states.
    pub bodies: Vec<State2>,
    /// Energies of the non-pinned bodies.
    pub energy: Energy2,
    /// Momenta of the non-pinned bodies.
    pub momentum: Momentum2,
    /// How many contacts the last substep had.
    pub contact_count: usize,
    /// The deepest disc overlap among them, blocks (0 without contacts).
    pub deepest_overlap: f64,
    /// The last substep's contacts, each with its impulse; present only when asked for
    /// (`run --all-contacts`), since they make up most of a trace's size.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contacts: Option<Vec<Contact2Record>>,
    /// What the step's contact solves did (sweeps, worst residual); absent when it solved none,
    /// and in traces written before issue 16.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solver: Option<crate::sim::SolverRecord>,
}

/// A body's state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct State2 {
    /// Centre of mass.
    pub x: [f64; 2],
    /// Angle, rad, +x toward +y.
    pub theta: f64,
    /// Velocity.
    pub v: [f64; 2],
    /// Angular velocity.
    pub omega: f64,
}

/// A contact.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Contact2Record {
    /// [body 1, body 2].
    pub bodies: [i64; 2],
    /// Point.
    pub p: [f64; 2],
    /// Normal, from body 2 into body 1.
    pub n: [f64; 2],
    /// Penetration.
    pub depth: f64,
    /// (λn, λt) impulses.
    pub lambda: [f64; 2],
    /// (c_n, c_t): body 1's contact-point velocity relative to body 2's along (n, t) after the
    /// impulses, with the lever arms the writer's engine used; present only where the writer
    /// gives it (`rigidref validate`'s runs), for the physical criteria (docs/validation.md
    /// §"2D: pymunk").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub c: Option<[f64; 2]>,
}

impl TraceHeader2 {
    /// The header of a world.
    pub fn for_world(world: &World2, scene: &str, source: &str) -> TraceHeader2 {
        let g = world.params.gravity_vector();
        TraceHeader2 {
            format: crate::common::trace::FORMAT_NAME.into(),
            version: crate::common::trace::FORMAT_VERSION,
            dimension: 2,
            scene: scene.into(),
            source: source.into(),
            overrides: Vec::new(),
            dt: world.params.dt,
            substeps: world.params.substeps,
            gravity: [g.x, g.y],
            bodies: world
                .bodies
                .iter()
                .enumerate()
                .map(|(i, b)| BodyInfo2 {
                    name: format!("body{i}"),
                    mass: b.mass,
                    pinned: b.pinned,
                    blocks: b.blocks.len(),
                })
                .collect(),
        }
    }
}

impl Record2 {
    /// The world's current state, with every contact of the last substep when `all_contacts`
    /// (else their count and deepest overlap only).
    pub fn of_world(world: &World2, all_contacts: bool) -> Record2 {
        // λ of the last substep, where it solved a contact problem (zeros otherwise).
        let lambda = world
            .solves
            .last()
            .filter(|s| s.substep + 1 == world.substeps_in_step)
            .map_or(&[][..], |s| &s.lambda[..]);
        Record2 {
            step: world.step,
            t: world.time(),
            bodies: world
                .bodies
                .iter()
                .map(|b| State2 {
                    x: [b.x.x, b.x.y],
                    theta: b.theta,
                    v: [b.v.x, b.v.y],
                    omega: b.omega,
                })
                .collect(),
            energy: world.energy(),
            momentum: world.momentum(),
            contact_count: world.contacts.len(),
            deepest_overlap: world.deepest_overlap(),
            contacts: all_contacts.then(|| {
                world
                    .contacts
                    .iter()
                    .enumerate()
                    .map(|(k, c)| {
                        let l = lambda.get(k).map_or([0.0, 0.0], |l| [l[0], l[1]]);
                        Contact2Record {
                            bodies: [c.body1 as i64, c.body2 as i64],
                            p: [c.point.x, c.point.y],
                            n: [c.normal.x, c.normal.y],
                            depth: c.depth,
                            lambda: l,
                            c: None,
                        }
                    })
                    .collect()
            }),
            solver: crate::sim::SolverRecord::of(&world.solves),
        }
    }
}
