//! Projected Gauss–Seidel and its residual (docs/contact.md §"PGS", §"Residual"), and the
//! contact-problem file (docs/contact-problem-format.md).

use crate::common;

use common::problems::{build, spec};
use nalgebra::SVector;
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use rigidref::problem::json::ProblemFile;
use rigidref::problem::{
    ContactProblem, ContactProblem3, FrictionModel, ProblemBody, ProblemContact, RowBounds,
};
use rigidref::solve::{ContactOrder, PgsSettings, PgsWorkspace, residual, solve_pgs};
use std::cell::Cell;

/// Iterations PGS may use on the random frictionless problems below: measured at most a few
/// hundred sweeps on problems whose Delassus operator has condition number ≤ 1e3 (the printed
/// maximum), so 20 000 leaves a wide margin without letting a broken solver through.
const FRICTIONLESS_BUDGET: u32 = 20_000;

fn solve(
    problem: &ContactProblem3,
    iterations: u32,
    tolerance: Option<f64>,
    order: ContactOrder,
    seed: u64,
) -> (Vec<SVector<f64, 3>>, rigidref::solve::SolveReport) {
    let mut workspace = PgsWorkspace::new(seed);
    let mut lambda = Vec::new();
    let settings = PgsSettings {
        max_iterations: iterations,
        tolerance,
        order,
        local: rigidref::solve::LocalSolve::Rows,
    };
    let report = solve_pgs(problem, &settings, &mut workspace, &mut lambda);
    (lambda, report)
}

#[test]
fn pgs_solves_random_frictionless_lcps_to_the_residual_tolerance() {
    let most_sweeps = Cell::new(0);
    let solved = Cell::new(0);
    proptest!(common::seeded(500), |(s in spec(1..4, 1..8))| {
        let problem = build(&s, 0.0, 0.0, FrictionModel::Box);
        let a = problem.dense_delassus();
        // Only the normal rows matter without friction.
        let normal: Vec<usize> = (0..problem.contacts.len()).map(|k| 3 * k).collect();
        let an = a.select_rows(&normal).select_columns(&normal);
        let eigenvalues = an.clone().symmetric_eigenvalues();
        // A positive definite normal block makes the LCP feasible with a unique solution; keep
        // the conditioning within 1e3 so the iteration budget is meaningful.
        prop_assume!(eigenvalues.min() > 1e-3 * eigenvalues.max());
        let (lambda, report) = solve(&problem, FRICTIONLESS_BUDGET, Some(1e-9), ContactOrder::Sequential, 0);
        prop_assert!(report.converged, "not converged: {report:?}");
        // Converged means the residual reached the tolerance asked for, 1e-9 m/s.
        prop_assert!(report.residual <= 1e-9);
        most_sweeps.set(most_sweeps.get().max(report.iterations));
        solved.set(solved.get() + 1);
        // The complementarity conditions themselves, with w computed independently (dense A).
        let lambda_n = nalgebra::DVector::from_iterator(normal.len(), lambda.iter().map(|l| l[0]));
        let b_n = nalgebra::DVector::from_iterator(normal.len(), problem.contacts.iter().map(|c| c.b[0]));
        let w = &an * &lambda_n + &b_n;
        let scale = 1.0 + b_n.amax();
        for k in 0..normal.len() {
            prop_assert!(lambda_n[k] >= 0.0);
            prop_assert!(w[k] >= -1e-8 * scale, "w[{k}] = {}", w[k]);
            prop_assert!((lambda_n[k] * an[(k, k)]).min(w[k]).abs() <= 1e-8 * scale);
            // Friction rows stay zero when μ = 0.
            prop_assert_eq!(lambda[k][1], 0.0);
            prop_assert_eq!(lambda[k][2], 0.0);
        }
    });
    println!(
        "frictionless LCPs: {} solved, at most {} sweeps (budget {FRICTIONLESS_BUDGET})",
        solved.get(),
        most_sweeps.get()
    );
}

/// One body of mass 2 kg on the ground, contact under its centre: A = diag(1/2, 1/2, 1/2).
fn one_contact(b: [f64; 3], mu: f64) -> ContactProblem3 {
    let mut inverse_mass = nalgebra::SMatrix::<f64, 6, 6>::zeros();
    for k in 0..3 {
        inverse_mass[(k, k)] = 0.5;
        inverse_mass[(k + 3, k + 3)] = 1.0;
    }
    let frame = rigidref::rigid3d::frame::ContactFrame::from_normal(&nalgebra::Vector3::y());
    ContactProblem {
        friction: FrictionModel::Box,
        bodies: vec![ProblemBody {
            inverse_mass,
            velocity: SVector::zeros(),
        }],
        contacts: vec![ProblemContact {
            bodies: [Some(0), None],
            jacobian: [
                rigidref::rigid3d::contact::jacobian_block(&frame, &nalgebra::Vector3::zeros()),
                Default::default(),
            ],
            b: SVector::from(b),
            mu,
            compliance: 0.0,
            lambda0: SVector::zeros(),
            bounds: RowBounds::Contact,
        }],
    }
}

#[test]
fn residual_is_zero_at_a_solution_and_positive_away_from_it() {
    // Approaching at 1 m/s, no friction: λn = 2 N·s stops it (w_n = 0).
    let p = one_contact([-1.0, 0.0, 0.0], 0.0);
    assert_eq!(residual(&p, &[SVector::from([2.0, 0.0, 0.0])]), 0.0);
    assert_eq!(residual(&p, &[SVector::zeros()]), 1.0); // still approaching at 1 m/s
    assert_eq!(residual(&p, &[SVector::from([4.0, 0.0, 0.0])]), 1.0); // pushing apart at 1 m/s
    // Separating at 1 m/s: λ = 0 is the solution.
    let p = one_contact([1.0, 0.0, 0.0], 0.0);
    assert_eq!(residual(&p, &[SVector::zeros()]), 0.0);
    assert_eq!(residual(&p, &[SVector::from([1.0, 0.0, 0.0])]), 0.5); // glue of 1 N·s, as velocity
    // Sliding along t1 at 3 m/s with μ = 0.5: λn = 2, friction saturates at −1 and leaves
    // w_t1 = 3 − 0.5 = 2.5 m/s: a solution (the bound is active), so the residual is zero.
    let p = one_contact([-1.0, 3.0, 0.0], 0.5);
    assert_eq!(residual(&p, &[SVector::from([2.0, -1.0, 0.0])]), 0.0);
    // Friction pushing the wrong way is not.
    assert!(residual(&p, &[SVector::from([2.0, 1.0, 0.0])]) > 0.5);
    // And PGS finds exactly that solution.
    let (lambda, report) = solve(&p, 100, None, ContactOrder::Sequential, 0);
    assert_eq!(lambda[0], SVector::from([2.0, -1.0, 0.0]));
    assert_eq!(report.residual, 0.0);
}

#[test]
fn cone_friction_impulses_stay_in_the_disk_and_converge() {
    // On any problem, after any number of sweeps, every impulse is in its cone.
    proptest!(common::seeded(300), |(s in spec(1..4, 1..8), mu in 0.0..2.0f64, sweeps in 1u32..60)| {
        let problem = build(&s, mu, 0.0, FrictionModel::Cone);
        let (lambda, _) = solve(&problem, sweeps, None, ContactOrder::Sequential, 0);
        for (k, l) in lambda.iter().enumerate() {
            let tangent = (l[1] * l[1] + l[2] * l[2]).sqrt();
            prop_assert!(l[0] >= 0.0);
            // 1e-12: the disk projection scales by μλn/‖λt‖, exact up to a few ulps.
            prop_assert!(tangent <= mu * l[0] * (1.0 + 1e-12), "contact {k}: |λt| {tangent} > μ λn {}", mu * l[0]);
        }
    });
    // Coupled friction is not a symmetric LCP, so PGS has no general convergence guarantee (on
    // random problems with large μ and strong rotational coupling it can cycle). On the problem
    // the simulator makes most, a box on the ground (four bottom corners) moving with any
    // velocity, it converges, and the independent residual agrees with the solver's.
    let most_sweeps = Cell::new(0);
    proptest!(common::seeded(300), |(
        v in (-3.0..3.0f64, -3.0..0.0f64, -3.0..3.0f64),
        w in (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64),
        mu in 0.0..1.0f64,
    )| {
        let problem = box_on_ground(nalgebra::Vector3::new(v.0, v.1, v.2), nalgebra::Vector3::new(w.0, w.1, w.2), mu, FrictionModel::Cone);
        let (lambda, report) = solve(&problem, 100_000, Some(1e-9), ContactOrder::Sequential, 0);
        prop_assert!(report.converged, "{report:?}");
        most_sweeps.set(most_sweeps.get().max(report.iterations));
        let independent = residual(&problem, &lambda);
        prop_assert!((independent - report.residual).abs() <= 1e-12);
    });
    println!(
        "cone friction, box on the ground: at most {} sweeps to residual 1e-9 m/s",
        most_sweeps.get()
    );
}

/// The project's 0.5 m box (125 kg) on the ground with its four bottom corners in contact,
/// moving with velocity `v` and angular velocity `w`.
pub(super) fn box_on_ground(
    v: nalgebra::Vector3<f64>,
    w: nalgebra::Vector3<f64>,
    mu: f64,
    friction: FrictionModel,
) -> ContactProblem3 {
    use rigidref::rigid3d::assemble::{ProblemSettings, assemble_problem};
    let mesh = std::sync::Arc::new(
        rigidref::rigid3d::mesh::TriMesh::load_obj(
            &common::project_root().join("scenes/data/box.obj"),
        )
        .unwrap(),
    );
    let mut body = rigidref::rigid3d::body::RigidBody::new(
        "box",
        125.0,
        nalgebra::Matrix3::identity() * (125.0 * 0.5 / 12.0 * 0.5 * 2.0),
        mesh,
    );
    body.x = nalgebra::Vector3::new(0.0, 0.249, 0.0);
    body.v = v;
    body.omega = w;
    body.update_world_inertia();
    let mut contacts = Vec::new();
    rigidref::rigid3d::collide::ground::ground_contacts(0, &body, 0.0, &mut contacts);
    assert_eq!(contacts.len(), 4);
    let settings = ProblemSettings {
        h: 0.01,
        mu,
        friction,
        compliance: 0.0,
        stabilization: 0.0,
        slop: 0.0,
        max_push_speed: f64::INFINITY,
    };
    assemble_problem(
        &[body],
        &contacts,
        &settings,
        &rigidref::rigid3d::warm_start::WarmStart::new(false),
    )
}

#[test]
fn cone_friction_opposes_diagonal_sliding_and_box_friction_does_not() {
    // Sliding along (t1 + t2)/√2 at 2 m/s, pressed with λn = 2 N·s, μ = 0.5: the cone's friction
    // is μλn = 1 N·s straight against the motion; the box's is 1 N·s in each row, √2 in all,
    // and not straight against the motion unless the motion is diagonal (it is here, so the
    // direction agrees and the magnitude is √2 times too large).
    let v = 2.0 / 2f64.sqrt();
    let mut p = one_contact([-1.0, v, v], 0.5);
    p.friction = FrictionModel::Cone;
    let (lambda, report) = solve(&p, 100, None, ContactOrder::Sequential, 0);
    assert!(report.residual < 1e-12, "{report:?}");
    let expected = -1.0 / 2f64.sqrt();
    assert!(
        (lambda[0] - SVector::from([2.0, expected, expected])).amax() < 1e-12,
        "{lambda:?}"
    );
    p.friction = FrictionModel::Box;
    let (lambda, _) = solve(&p, 100, None, ContactOrder::Sequential, 0);
    assert_eq!(lambda[0], SVector::from([2.0, -1.0, -1.0]));
}

#[test]
fn random_contact_order_is_reproducible_from_its_seed() {
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let s = spec(3..4, 6..7).new_tree(&mut runner).unwrap().current();
    let problem = build(&s, 0.8, 0.0, FrictionModel::Box);
    let (a, _) = solve(&problem, 30, None, ContactOrder::Random, 7);
    let (b, _) = solve(&problem, 30, None, ContactOrder::Random, 7);
    let (c, _) = solve(&problem, 30, None, ContactOrder::Random, 8);
    let (d, _) = solve(&problem, 30, None, ContactOrder::Sequential, 7);
    let bits = |l: &[SVector<f64, 3>]| {
        l.iter()
            .flat_map(|v| v.iter().map(|x| x.to_bits()))
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&a), bits(&b), "same seed, same answer to the bit");
    assert_ne!(
        bits(&a),
        bits(&c),
        "another seed visits the contacts in another order"
    );
    assert_ne!(
        bits(&a),
        bits(&d),
        "the random order differs from the sequential one"
    );
}

#[test]
fn problem_file_round_trips_exactly() {
    proptest!(common::seeded(100), |(s in spec(1..4, 1..6), mu in 0.0..2.0f64, c in 0.0..0.1f64)| {
        let mut problem = build(&s, mu, c, FrictionModel::Cone);
        problem.contacts[0].lambda0 = SVector::from([0.1, -0.2, 1.0 / 3.0]);
        let text = serde_json::to_string(&ProblemFile::new(&problem)).unwrap();
        let file: ProblemFile = serde_json::from_str(&text).unwrap();
        let back: ContactProblem3 = file.to_problem().unwrap();
        prop_assert_eq!(&back, &problem);
        // Asking for the wrong dimensions is an error, not a misread.
        prop_assert!(file.to_problem::<3, 2>().unwrap_err().contains("dof_per_body"));
    });
    // A 2D problem (3 DOF per body, 2 rows) through the same file.
    let problem: ContactProblem<3, 2> = ContactProblem {
        friction: FrictionModel::Box,
        bodies: vec![ProblemBody {
            inverse_mass: nalgebra::Matrix3::identity() * 0.25,
            velocity: nalgebra::Vector3::new(1.0, -2.0, 0.5),
        }],
        contacts: vec![ProblemContact {
            bodies: [Some(0), None],
            jacobian: [
                nalgebra::SMatrix::<f64, 2, 3>::new(0.0, 1.0, 0.3, 1.0, 0.0, -0.2),
                Default::default(),
            ],
            b: nalgebra::Vector2::new(-2.0, 1.0),
            mu: 0.33,
            compliance: 0.0,
            lambda0: nalgebra::Vector2::zeros(),
            bounds: RowBounds::Contact,
        }],
    };
    let text = serde_json::to_string(&ProblemFile::new(&problem)).unwrap();
    let back: ContactProblem<3, 2> = serde_json::from_str::<ProblemFile>(&text)
        .unwrap()
        .to_problem()
        .unwrap();
    assert_eq!(back, problem);
    // A malformed file names what is wrong.
    let bad = text.replace("\"mu\":0.33", "\"mu\":-1.0");
    let err = serde_json::from_str::<ProblemFile>(&bad)
        .unwrap()
        .to_problem::<3, 2>()
        .unwrap_err();
    assert!(err.contains("mu must be ≥ 0"), "{err}");
}

/// The disk projection (src/solve/projection.rs::project_disk) at its edges: a zero bound
/// leaves no friction, even where the friction rows are so small that their squares underflow
/// and the computed norm is 0 (1e-170: the projection left them before, a violation of the
/// zero bound); a trial exactly on the rim (norm = bound, 3-4-5) comes back with the same bits;
/// ±0 rows keep their signs; the normal row is never changed; 2D as 3D.
#[test]
fn the_disk_projection_is_exact_at_a_zero_bound_and_on_the_rim() {
    use rigidref::solve::projection::project_disk;
    let tiny = nalgebra::Vector3::new(1.0, 1e-170, -1e-170);
    let p = project_disk(&tiny, 0.0);
    assert_eq!(p[0], 1.0);
    assert!(p[1] == 0.0 && p[2] == 0.0, "{p:?}");
    assert!(p[1].is_sign_positive() && p[2].is_sign_negative(), "{p:?}");
    let p2 = project_disk(&nalgebra::Vector2::new(2.0, -1e-170), 0.0);
    assert_eq!((p2[0], p2[1]), (2.0, 0.0));
    let zeros = nalgebra::Vector3::new(0.5, -0.0, 0.0);
    let p = project_disk(&zeros, 0.0);
    assert!(p[1] == 0.0 && p[1].is_sign_negative() && p[2].is_sign_positive());
    let rim = nalgebra::Vector3::new(7.0, 3.0, -4.0);
    assert_eq!(project_disk(&rim, 5.0), rim);
    let outside = project_disk(&nalgebra::Vector3::new(7.0, 6.0, -8.0), 5.0);
    assert_eq!(outside, nalgebra::Vector3::new(7.0, 3.0, -4.0));
    let inside = nalgebra::Vector3::new(7.0, 1e-170, 2.0);
    assert_eq!(project_disk(&inside, 5.0), inside);
}
