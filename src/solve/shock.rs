//! Velocity-based shock propagation (Erleben 2007; Guendelman, Bridson and Fedkiw 2003), a pass
//! after PGS. docs/blocks2d.md §"Shock propagation".
//!
//! The bodies are put in layers by their distance, in the contact graph, from what cannot move:
//! layer 0 is the static world and the bodies with zero inverse mass (pinned), layer L the
//! bodies whose nearest such support is L contacts away. Then, layer by layer from the bottom,
//! the entries whose highest body is in layer L are solved again by the same Gauss–Seidel visits
//! as PGS, with every body of a lower layer held fixed: its side of an entry neither moves nor
//! counts in the entry's diagonal. What a layer's impulses would do to its supports is dropped,
//! so a layer settles on its supports as on the ground: a stack reaches the velocities of a
//! stiff stack in one pass from the bottom, where plain Gauss–Seidel needs sweeps in proportion
//! to its height. The price: Newton's third law is broken between layers (the supports do not
//! feel the reaction of that pass), so a stack is stiffer than it is, and after the pass λ no
//! longer gives the velocities through u⁺ = u + M⁻¹Jᵀλ.

use super::pgs_settings::PgsSettings;
use super::pgs_sweep::visit;
use super::pgs_workspace::PgsWorkspace;
use super::residual::RowScales;
use crate::problem::ContactProblem;
use nalgebra::{SMatrix, SVector};
use rand::seq::SliceRandom;
use std::collections::VecDeque;

/// What a shock-propagation pass did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShockReport {
    /// Layers above the supports (the deepest body's layer).
    pub layers: u32,
    /// Entry visits made, over all layers and sweeps.
    pub visits: u64,
    /// Bodies not connected to any support through contacts (left as PGS left them).
    pub unsupported: usize,
}

/// Each body's layer: 0 for a body with zero inverse mass, else 1 + the smallest layer among the
/// bodies it shares an entry with (the static world counting as layer 0); `None` for a body
/// connected to no support. Breadth-first over the problem's entries.
pub fn layers<const D: usize, const R: usize>(problem: &ContactProblem<D, R>) -> Vec<Option<u32>> {
    let n = problem.bodies.len();
    let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut layer: Vec<Option<u32>> = vec![None; n];
    let mut queue = VecDeque::new();
    for (i, body) in problem.bodies.iter().enumerate() {
        if body.inverse_mass.iter().all(|x| *x == 0.0) {
            layer[i] = Some(0);
            queue.push_back(i);
        }
    }
    for c in &problem.contacts {
        match c.bodies {
            [Some(a), Some(b)] => {
                neighbours[a].push(b);
                neighbours[b].push(a);
            }
            [Some(a), None] | [None, Some(a)] => {
                if layer[a].is_none() {
                    layer[a] = Some(1);
                }
            }
            [None, None] => {}
        }
    }
    // Bodies on the world enter the search at layer 1, after the pinned ones at layer 0.
    for (i, l) in layer.iter().enumerate() {
        if *l == Some(1) {
            queue.push_back(i);
        }
    }
    while let Some(i) = queue.pop_front() {
        let next = layer[i].map(|l| l + 1);
        for &j in &neighbours[i] {
            if layer[j].is_none() || layer[j] > next {
                layer[j] = next;
                queue.push_back(j);
            }
        }
    }
    layer
}

/// Runs the shock-propagation pass on a problem PGS has just solved (`workspace` and `lambda` as
/// [`super::solve_pgs`] left them), `settings.max_iterations` sweeps per layer in the settings'
/// order (a fresh permutation of the layer each sweep for random order).
/// On return `workspace.delta_velocity(i)` holds each body's velocity change after the pass.
pub fn propagate_shock<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    settings: &PgsSettings,
    workspace: &mut PgsWorkspace<D, R>,
    lambda: &mut [SVector<f64, R>],
) -> ShockReport {
    let layer = layers(problem);
    let entry_layer = |k: usize| -> Option<u32> {
        let c = &problem.contacts[k];
        let of = |s: usize| c.bodies[s].map_or(Some(0), |b| layer[b]);
        Some(of(0)?.max(of(1)?))
    };
    let deepest = (0..problem.contacts.len())
        .filter_map(entry_layer)
        .max()
        .unwrap_or(0);
    let mut report = ShockReport {
        layers: deepest,
        visits: 0,
        unsupported: layer.iter().filter(|l| l.is_none()).count(),
    };
    let mut members = Vec::new();
    for current in 1..=deepest {
        members.clear();
        members.extend((0..problem.contacts.len()).filter(|&k| entry_layer(k) == Some(current)));
        for &k in &members {
            hold_lower_sides_fixed(problem, workspace, k, &layer, current);
        }
        for _ in 0..settings.max_iterations {
            // The solve's own order: a fixed order within a layer pushes every bar the same way
            // each sweep (sequential sweeps at 2 or 3 per layer toppled tower100).
            if settings.order.is_random() {
                members.shuffle(&mut workspace.rng);
            }
            for &k in &members {
                visit(problem, settings.local, workspace, k, &mut lambda[k]);
            }
            report.visits += members.len() as u64;
        }
    }
    report
}

/// Holds the sides of entry `k` whose body is below layer `current` fixed: their M⁻¹Jᵀ is set to
/// zero, so a visit does not move them, and the entry's row scales are those of the free sides.
fn hold_lower_sides_fixed<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    workspace: &mut PgsWorkspace<D, R>,
    k: usize,
    layer: &[Option<u32>],
    current: u32,
) {
    let c = &problem.contacts[k];
    let mut held = [false; 2];
    for s in 0..2 {
        let Some(b) = c.bodies[s] else { continue };
        if layer[b].is_some_and(|l| l < current) {
            workspace.hold_side_fixed(k, s);
            held[s] = true;
        }
    }
    // The free sides' block, with a contact of a body with itself's cross terms
    // (`ContactProblem::delassus_block`).
    let mut block = SMatrix::<f64, R, R>::zeros();
    for (s, t) in crate::problem::SIDE_PAIRS {
        if c.bodies[s].is_some() && c.bodies[s] == c.bodies[t] && !held[s] {
            block += c.jacobian[s] * workspace.inverse_mass_jacobian_t(k, t);
        }
    }
    let mut block = (block + block.transpose()) * 0.5;
    for r in 0..R {
        block[(r, r)] += c.row_compliance(r);
    }
    let scales = RowScales {
        diagonal: block.diagonal(),
        tangent_rho: super::residual::tangent_eigenvalue(&block),
        block,
    };
    workspace.set_scales(k, scales);
}
