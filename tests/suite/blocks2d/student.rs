//! A student-like 2D simulator, written here from the assignment's equations the way a student
//! fills in the Java starter, with the typical mistakes as switches (issue 36, item 5). It
//! shares nothing with the reference's step: only the bodies and their bounding-disc trees come
//! from rigidref ([`Body2::from_group`]), as the starter provides them (`RigidBody`, `BVNode`).
//!
//! Per step of length h (one substep, as the starter): detect contacts by descending the two
//! bodies' disc trees; v += h g for every body that is not pinned; projected Gauss–Seidel on
//! the contacts' normal and friction rows, starting from zero, updating velocities after every
//! row; x += h v, θ += h ω. No warm start, no post-stabilisation, no restitution: the scenes
//! graded with it set those off, so that a correct student and the reference solve the same
//! problems (to the solver's convergence).
//!
//! It writes its own trace (energies and momenta computed from its own state, docs/trace-format.md
//! §"2D traces") and its first contact problem (docs/contact-problem-format.md, 2D).

use nalgebra::Vector2;
use rigidref::blocks2d::body::Body2;
use rigidref::blocks2d::disc_tree::{BLOCK_RADIUS, NodeKind};
use serde_json::json;
use std::io::Write;

/// The typical mistakes of the 2D assignment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bug {
    /// None: the assignment's method.
    Correct,
    /// No rotational dynamics: impulses change v only (as if I were infinite); ω stays 0.
    NoRotation,
    /// The contact Jacobian's angular entries with the wrong sign (n × r for r × n).
    LeverArmSign,
    /// Friction bounded by ±μ, not ±μ λn.
    FrictionNotScaled,
    /// The normal pointing from body 1's block to body 2's (into body 1), not out of it.
    FlippedNormal,
    /// Positions updated before velocities (x += h v with the old v, then v += h g).
    PositionsFirst,
    /// The tree descent prunes a pair of inner nodes by the discs of the block centres (the
    /// node's radius without the block's), so contacts of blocks at a node's boundary are
    /// missed.
    TreeMissesBoundary,
}

impl Bug {
    /// Every variant, the correct one first.
    pub const ALL: [Bug; 7] = [
        Bug::Correct,
        Bug::NoRotation,
        Bug::LeverArmSign,
        Bug::FrictionNotScaled,
        Bug::FlippedNormal,
        Bug::PositionsFirst,
        Bug::TreeMissesBoundary,
    ];

    /// A short name, for folders and messages.
    pub fn name(self) -> &'static str {
        match self {
            Bug::Correct => "correct",
            Bug::NoRotation => "no_rotation",
            Bug::LeverArmSign => "lever_arm_sign",
            Bug::FrictionNotScaled => "friction_not_scaled",
            Bug::FlippedNormal => "flipped_normal",
            Bug::PositionsFirst => "positions_first",
            Bug::TreeMissesBoundary => "tree_misses_boundary",
        }
    }
}

/// What the student's program is run with: the scene's values.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// Step, time units.
    pub dt: f64,
    /// Gravity, blocks/t².
    pub gravity: Vector2<f64>,
    /// Friction coefficient.
    pub mu: f64,
    /// PGS sweeps.
    pub iterations: u32,
}

struct Contact {
    i: usize,
    j: usize,
    point: Vector2<f64>,
    normal: Vector2<f64>,
    depth: f64,
}

fn world(b: &Body2, local: &Vector2<f64>) -> Vector2<f64> {
    let (s, c) = b.theta.sin_cos();
    b.x + Vector2::new(c * local.x - s * local.y, s * local.x + c * local.y)
}

/// The student's tree descent for bodies i and j, recursive, splitting the node with the larger
/// disc.
fn descend(
    bodies: &[Body2],
    i: usize,
    j: usize,
    a: usize,
    b: usize,
    bug: Bug,
    out: &mut Vec<Contact>,
) {
    let (bi, bj) = (&bodies[i], &bodies[j]);
    let (na, nb) = (&bi.tree.nodes[a], &bj.tree.nodes[b]);
    let distance = (world(bi, &na.centre) - world(bj, &nb.centre)).norm();
    let both_inner =
        matches!(na.kind, NodeKind::Inner(..)) && matches!(nb.kind, NodeKind::Inner(..));
    let reach = if bug == Bug::TreeMissesBoundary && both_inner {
        na.radius + nb.radius - 2.0 * BLOCK_RADIUS
    } else {
        na.radius + nb.radius
    };
    if distance >= reach {
        return;
    }
    match (na.kind, nb.kind) {
        (NodeKind::Leaf(ka), NodeKind::Leaf(kb)) => {
            let pa = world(bi, &bi.blocks[ka].local);
            let pb = world(bj, &bj.blocks[kb].local);
            let d = (pa - pb).norm();
            if d < 2.0 * BLOCK_RADIUS && d > 1e-12 {
                let normal = if bug == Bug::FlippedNormal {
                    (pb - pa) / d
                } else {
                    (pa - pb) / d
                };
                out.push(Contact {
                    i,
                    j,
                    point: (pa + pb) / 2.0,
                    normal,
                    depth: 2.0 * BLOCK_RADIUS - d,
                });
            }
        }
        (NodeKind::Inner(l, r), NodeKind::Leaf(_)) => {
            descend(bodies, i, j, l, b, bug, out);
            descend(bodies, i, j, r, b, bug, out);
        }
        (NodeKind::Leaf(_), NodeKind::Inner(l, r)) => {
            descend(bodies, i, j, a, l, bug, out);
            descend(bodies, i, j, a, r, bug, out);
        }
        (NodeKind::Inner(al, ar), NodeKind::Inner(bl, br)) => {
            if na.radius >= nb.radius {
                descend(bodies, i, j, al, b, bug, out);
                descend(bodies, i, j, ar, b, bug, out);
            } else {
                descend(bodies, i, j, a, bl, bug, out);
                descend(bodies, i, j, a, br, bug, out);
            }
        }
    }
}

fn detect(bodies: &[Body2], bug: Bug) -> Vec<Contact> {
    let mut out = Vec::new();
    for i in 0..bodies.len() {
        for j in i + 1..bodies.len() {
            let both_pinned = bodies[i].pinned && bodies[j].pinned;
            if !both_pinned && !bodies[i].tree.nodes.is_empty() && !bodies[j].tree.nodes.is_empty()
            {
                descend(bodies, i, j, 0, 0, bug, &mut out);
            }
        }
    }
    out
}

fn cross(a: &Vector2<f64>, b: &Vector2<f64>) -> f64 {
    a.x * b.y - a.y * b.x
}

/// A contact's rows: per row (n, t) the Jacobian blocks [J₁ | J₂], each (x, y, angular).
fn jacobian(bodies: &[Body2], c: &Contact, bug: Bug) -> [[[f64; 3]; 2]; 2] {
    let t = Vector2::new(-c.normal.y, c.normal.x);
    let sign = if bug == Bug::LeverArmSign { -1.0 } else { 1.0 };
    let block = |body: &Body2, d: &Vector2<f64>, side: f64| {
        let r = c.point - body.x;
        [side * d.x, side * d.y, side * sign * cross(&r, d)]
    };
    let (b1, b2) = (&bodies[c.i], &bodies[c.j]);
    [
        [block(b1, &c.normal, 1.0), block(b2, &c.normal, -1.0)],
        [block(b1, &t, 1.0), block(b2, &t, -1.0)],
    ]
}

fn inverse_mass(b: &Body2, bug: Bug) -> [f64; 3] {
    if b.pinned {
        [0.0; 3]
    } else if bug == Bug::NoRotation {
        [1.0 / b.mass, 1.0 / b.mass, 0.0]
    } else {
        [1.0 / b.mass, 1.0 / b.mass, 1.0 / b.inertia]
    }
}

fn velocity(b: &Body2) -> [f64; 3] {
    [b.v.x, b.v.y, b.omega]
}

fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Projected Gauss–Seidel, row by row, velocities updated after each row. Returns λ per contact.
fn pgs(
    bodies: &mut [Body2],
    contacts: &[Contact],
    rows: &[[[[f64; 3]; 2]; 2]],
    s: &Settings,
    bug: Bug,
) -> Vec<[f64; 2]> {
    let mut lambda = vec![[0.0; 2]; contacts.len()];
    let minv: Vec<[f64; 3]> = bodies.iter().map(|b| inverse_mass(b, bug)).collect();
    for _ in 0..s.iterations {
        for (k, c) in contacts.iter().enumerate() {
            for r in 0..2 {
                let (j1, j2) = (&rows[k][r][0], &rows[k][r][1]);
                let a: f64 = (0..3)
                    .map(|d| j1[d] * j1[d] * minv[c.i][d] + j2[d] * j2[d] * minv[c.j][d])
                    .sum();
                if a <= 0.0 {
                    continue;
                }
                let w = dot(j1, &velocity(&bodies[c.i])) + dot(j2, &velocity(&bodies[c.j]));
                let unclamped = lambda[k][r] - w / a;
                let new = if r == 0 {
                    unclamped.max(0.0)
                } else {
                    let bound = if bug == Bug::FrictionNotScaled {
                        s.mu
                    } else {
                        s.mu * lambda[k][0]
                    };
                    unclamped.clamp(-bound, bound)
                };
                let delta = new - lambda[k][r];
                lambda[k][r] = new;
                for (body, j) in [(c.i, j1), (c.j, j2)] {
                    let m = minv[body];
                    let b = &mut bodies[body];
                    b.v.x += m[0] * j[0] * delta;
                    b.v.y += m[1] * j[1] * delta;
                    b.omega += m[2] * j[2] * delta;
                }
            }
        }
    }
    lambda
}

fn header(scene: &str, source: &str, bodies: &[Body2], s: &Settings) -> serde_json::Value {
    json!({
        "format": "rigidref-trace", "version": 2, "dimension": 2, "scene": scene, "source": source,
        "dt": s.dt, "substeps": 1, "gravity": [s.gravity.x, s.gravity.y],
        "bodies": bodies.iter().enumerate().map(|(i, b)| json!({
            "name": format!("body{i}"), "mass": b.mass, "pinned": b.pinned, "blocks": b.blocks.len()
        })).collect::<Vec<_>>(),
    })
}

fn record(step: u64, t: f64, bodies: &[Body2], s: &Settings, contacts: usize) -> serde_json::Value {
    let (mut kinetic, mut potential, mut p, mut angular) = (0.0, 0.0, Vector2::zeros(), 0.0);
    for b in bodies.iter().filter(|b| !b.pinned) {
        kinetic += 0.5 * b.mass * b.v.norm_squared() + 0.5 * b.inertia * b.omega * b.omega;
        potential -= b.mass * s.gravity.dot(&b.x);
        p += b.v * b.mass;
        angular += cross(&b.x, &(b.v * b.mass)) + b.inertia * b.omega;
    }
    json!({
        "step": step, "t": t,
        "bodies": bodies.iter().map(|b| json!({
            "x": [b.x.x, b.x.y], "theta": b.theta, "v": [b.v.x, b.v.y], "omega": b.omega
        })).collect::<Vec<_>>(),
        "energy": {"kinetic": kinetic, "potential": potential, "total": kinetic + potential},
        "momentum": {"linear": [p.x, p.y], "angular": angular},
        "contact_count": contacts, "deepest_overlap": 0.0,
    })
}

fn problem(
    bodies: &[Body2],
    contacts: &[Contact],
    rows: &[[[[f64; 3]; 2]; 2]],
    s: &Settings,
    bug: Bug,
) -> serde_json::Value {
    json!({
        "format": "rigidref-contact-problem", "version": 1, "dof_per_body": 3, "rows_per_contact": 2,
        "friction": "box",
        "bodies": bodies.iter().map(|b| {
            let m = inverse_mass(b, bug);
            json!({
                "inverse_mass": [[m[0], 0.0, 0.0], [0.0, m[1], 0.0], [0.0, 0.0, m[2]]],
                "velocity": velocity(b),
            })
        }).collect::<Vec<_>>(),
        "contacts": contacts.iter().zip(rows).map(|(c, j)| {
            let b: Vec<f64> = (0..2)
                .map(|r| dot(&j[r][0], &velocity(&bodies[c.i])) + dot(&j[r][1], &velocity(&bodies[c.j])))
                .collect();
            json!({
                "bodies": [c.i, c.j],
                "jacobian": [[j[0][0], j[1][0]], [j[0][1], j[1][1]]],
                "b": b, "mu": s.mu, "compliance": 0.0, "lambda0": [0.0, 0.0],
                "geometry": {"p": [c.point.x, c.point.y], "n": [c.normal.x, c.normal.y], "depth": c.depth},
            })
        }).collect::<Vec<_>>(),
    })
}

/// Runs the student's simulator on `bodies` for `steps` steps, writing its trace to `trace` and
/// its first contact problem (the problem of the first step that has contacts, before it is
/// solved) to `first_problem`.
pub fn simulate(
    mut bodies: Vec<Body2>,
    scene: &str,
    s: &Settings,
    steps: u64,
    bug: Bug,
    trace: &std::path::Path,
    first_problem: &std::path::Path,
) {
    let mut out = std::io::BufWriter::new(std::fs::File::create(trace).unwrap());
    writeln!(
        out,
        "{}",
        header(scene, &format!("{scene}.png"), &bodies, s)
    )
    .unwrap();
    writeln!(out, "{}", record(0, 0.0, &bodies, s, 0)).unwrap();
    let mut wrote_problem = false;
    for step in 1..=steps {
        let contacts = detect(&bodies, bug);
        for b in bodies.iter_mut().filter(|b| !b.pinned) {
            if bug == Bug::PositionsFirst {
                b.x += s.dt * b.v;
                b.theta += s.dt * b.omega;
            }
            b.v += s.dt * s.gravity;
        }
        let rows: Vec<_> = contacts.iter().map(|c| jacobian(&bodies, c, bug)).collect();
        if !wrote_problem && !contacts.is_empty() {
            let text =
                serde_json::to_string_pretty(&problem(&bodies, &contacts, &rows, s, bug)).unwrap();
            std::fs::write(first_problem, text).unwrap();
            wrote_problem = true;
        }
        pgs(&mut bodies, &contacts, &rows, s, bug);
        if bug != Bug::PositionsFirst {
            for b in bodies.iter_mut().filter(|b| !b.pinned) {
                b.x += s.dt * b.v;
                b.theta += s.dt * b.omega;
            }
        }
        writeln!(
            out,
            "{}",
            record(step, step as f64 * s.dt, &bodies, s, contacts.len())
        )
        .unwrap();
    }
}
