//! The statements of docs/contact.md and docs/contact-problem-format.md that an expert reading
//! found wrong or loose, each checked as corrected: non-unique frictional velocities, the energy
//! balance of one solve, the frictionless QP, the rotation-invariant cone step, compliance with
//! Baumgarte as a spring–damper, box friction as a pyramid, the push-out inside λn.

use super::run_pgs as pgs;
use crate::common;

use common::problems::{build, spec};
use nalgebra::{DMatrix, DVector, Matrix3, SMatrix, SVector, Vector3};
use proptest::prelude::*;
use rigidref::problem::{ContactProblem, FrictionModel, ProblemBody, ProblemContact, RowBounds};
use rigidref::solve::qp::{QpFormulation, QpSettings, solve_qp};
use rigidref::solve::residual::coulomb_residual;
use rigidref::solve::{LocalSolve, residual};

/// `problem` with each contact's tangents turned about its normal by `turn` + k radians
/// (contact k): rows t1, t2 of J and b replaced by cos·t1 + sin·t2 and −sin·t1 + cos·t2, and
/// `lambda`'s friction part turned the same way. The physics is the same problem.
pub(super) fn turn_tangents(
    problem: &ContactProblem<6, 3>,
    lambda: &[SVector<f64, 3>],
    turn: f64,
) -> (ContactProblem<6, 3>, Vec<SVector<f64, 3>>) {
    let mut turned = problem.clone();
    let mut turned_lambda = lambda.to_vec();
    for (k, c) in turned.contacts.iter_mut().enumerate() {
        let (s, co) = (turn + k as f64).sin_cos();
        let q = Matrix3::new(1.0, 0.0, 0.0, 0.0, co, s, 0.0, -s, co);
        for side in 0..2 {
            c.jacobian[side] = q * c.jacobian[side];
        }
        c.b = q * c.b;
        c.lambda0 = q * c.lambda0;
        if k < turned_lambda.len() {
            turned_lambda[k] = q * turned_lambda[k];
        }
    }
    (turned, turned_lambda)
}

/// The 2D example of docs/contact-problem-format.md with right-hand side `b` (m/s): one body,
/// M⁻¹ = diag(0.1, 0.1, 1), against the static world; normal row [0, 1, 0.9], tangent row
/// [−1, 0, −2], μ = 1, so A = [[0.91, −1.8], [−1.8, 4.1]] kg⁻¹.
pub(super) fn painleve(b: [f64; 2]) -> ContactProblem<3, 2> {
    let mut inverse_mass = SMatrix::<f64, 3, 3>::zeros();
    inverse_mass.set_diagonal(&nalgebra::Vector3::new(0.1, 0.1, 1.0));
    ContactProblem::<3, 2> {
        friction: FrictionModel::Box,
        bodies: vec![ProblemBody {
            inverse_mass,
            velocity: SVector::zeros(),
        }],
        contacts: vec![ProblemContact {
            bodies: [Some(0), None],
            jacobian: [
                SMatrix::<f64, 2, 3>::new(0.0, 1.0, 0.9, -1.0, 0.0, -2.0),
                SMatrix::zeros(),
            ],
            b: SVector::from(b),
            mu: 1.0,
            compliance: 0.0,
            lambda0: SVector::zeros(),
            bounds: RowBounds::Contact,
        }],
    }
}

#[test]
fn frictional_velocities_need_not_be_unique() {
    // docs/contact-problem-format.md: a 2D body (M⁻¹ = diag(0.1, 0.1, 1)) against the static
    // world, normal row [0, 1, 0.9], tangent row [−1, 0, −2], b = (1, −5) m/s, μ = 1. A is
    // positive definite (A = [[0.91, −1.8], [−1.8, 4.1]], det 0.491), yet three λ solve it.
    let problem = painleve([1.0, -5.0]);
    assert!(problem.delassus_block(0).determinant() > 0.49);
    // Separation: λ = 0, w = b, w_n = 1 ≥ 0.
    let separate = vec![SVector::<f64, 2>::zeros()];
    // Sliding: w_n = 1 − 0.89 λn = 0 with λt = μλn, so λ = (1/0.89, 1/0.89), w_t = −2.416 m/s
    // against the friction impulse: Coulomb's law holds.
    let slide = vec![SVector::<f64, 2>::repeat(1.0 / 0.89)];
    // Sticking: A λ = −b, λ = (4.9, 2.75)/0.491 ≈ (9.980, 5.601), inside the friction bound.
    let stick = vec![SVector::<f64, 2>::new(4.9, 2.75) / 0.491];
    for (name, lambda) in [
        ("separation", &separate),
        ("sliding", &slide),
        ("sticking", &stick),
    ] {
        // 1e-13: round-off of 1/0.89 and 1/0.491 in a few products.
        assert!(residual(&problem, lambda) <= 1e-13, "{name}");
        assert!(coulomb_residual(&problem, lambda) <= 1e-13, "{name}");
    }
    assert!(problem.constraint_velocity(&slide)[0][1] < -2.4);
    // The bodies' velocities after differ: u⁺ is not unique.
    let du = |l: &Vec<SVector<f64, 2>>| problem.velocity_change(l)[0];
    assert!((du(&separate) - du(&slide)).norm() > 1.0);
    assert!((du(&stick) - du(&slide)).norm() > 1.0);
    // Which one PGS selects depends on how it visits: the exact local solve tries separation
    // first and takes it; row-by-row PGS from rest takes it too (λn = max(0, −1/0.91) = 0).
    for local in [LocalSolve::Exact, LocalSolve::Rows] {
        let (lambda, report) = pgs(&problem, local, 10, Some(1e-14));
        assert!(report.converged);
        assert_eq!(lambda[0], SVector::<f64, 2>::zeros(), "{local:?}");
    }
    // Started near the sliding solution (a warm start), row-by-row PGS stays at it.
    let mut warm = problem.clone();
    warm.contacts[0].lambda0 = slide[0];
    let (lambda, report) = pgs(&warm, LocalSolve::Rows, 10, Some(1e-14));
    assert!(report.converged);
    assert!((lambda[0] - slide[0]).amax() < 1e-12, "{lambda:?}");
}

/// The dense generalised mass M (the inverse of each body's M⁻¹), u, J, A, C, and b as dense
/// arrays, for the energy tests.
fn dense(problem: &ContactProblem<6, 3>) -> (DMatrix<f64>, DVector<f64>, DMatrix<f64>) {
    let m_inverse = problem.dense_inverse_mass();
    let mass = m_inverse.try_inverse().expect("bodies with finite mass");
    let u = DVector::from_iterator(
        6 * problem.bodies.len(),
        problem
            .bodies
            .iter()
            .flat_map(|b| b.velocity.iter().copied()),
    );
    (mass, u, problem.dense_jacobian())
}

fn stacked(lambda: &[SVector<f64, 3>]) -> DVector<f64> {
    DVector::from_iterator(
        3 * lambda.len(),
        lambda.iter().flat_map(|l| l.iter().copied()),
    )
}

/// Random problems with random body velocities u and b = J u − β̃, β̃ a bias ≥ 0 on the normal
/// rows only (Baumgarte's push-out, m/s) when `normal_bias_only`, else on every row.
fn with_velocities(
    s: &common::problems::ProblemSpec,
    velocities: &[f64],
    bias: &[f64],
    compliance: f64,
    friction: FrictionModel,
    normal_bias_only: bool,
) -> (ContactProblem<6, 3>, DVector<f64>) {
    let mut problem = build(s, 0.5, compliance, friction);
    for (i, body) in problem.bodies.iter_mut().enumerate() {
        body.velocity = SVector::from_fn(|r, _| velocities[(6 * i + r) % velocities.len()]);
    }
    let (_, u, j) = dense(&problem);
    let ju = &j * &u;
    let mut beta = DVector::zeros(ju.len());
    for (i, b) in beta.iter_mut().enumerate() {
        if !normal_bias_only || i % 3 == 0 {
            *b = bias[i % bias.len()];
        }
    }
    for (k, c) in problem.contacts.iter_mut().enumerate() {
        for r in 0..3 {
            c.b[r] = ju[3 * k + r] - beta[3 * k + r];
        }
    }
    (problem, beta)
}

#[test]
fn one_solve_energy_balance_is_exact() {
    // docs/contact.md §Stabilisation: ΔT = λᵀw − ½λᵀAλ − λᵀCλ + λᵀβ̃ for ANY λ (converged or
    // not), T = ½uᵀMu, u⁺ = u + M⁻¹Jᵀλ, w = (A + C)λ + b, b = Ju − β̃. Checked on the λ PGS
    // holds after 1–30 sweeps. 1e-9 relative: T and the terms are sums of products of numbers
    // of size up to ~1e3.
    proptest!(common::seeded(300), |(
        s in spec(1..4, 1..6),
        velocities in proptest::collection::vec(-2.0..2.0f64, 6),
        bias in proptest::collection::vec(0.0..1.0f64, 3),
        compliance in 0.0..0.1f64,
        sweeps in 1u32..30,
        cone in any::<bool>(),
    )| {
        let friction = if cone { FrictionModel::Cone } else { FrictionModel::Box };
        let (problem, beta) = with_velocities(&s, &velocities, &bias, compliance, friction, false);
        let (lambda, _) = pgs(&problem, LocalSolve::Rows, sweeps, None);
        let (mass, u, j) = dense(&problem);
        let l = stacked(&lambda);
        let u_after = &u + problem.dense_inverse_mass() * j.transpose() * &l;
        let energy = |v: &DVector<f64>| 0.5 * v.dot(&(&mass * v));
        let change = energy(&u_after) - energy(&u);
        let a = problem.dense_delassus();
        let c = problem.dense_compliance();
        let w = stacked(&problem.constraint_velocity(&lambda));
        let balance = l.dot(&w) - 0.5 * l.dot(&(&a * &l)) - l.dot(&(&c * &l)) + l.dot(&beta);
        let scale = energy(&u).max(energy(&u_after)).max(1e-3);
        prop_assert!((change - balance).abs() <= 1e-9 * scale, "ΔT {change}, balance {balance}");
    });
}

#[test]
fn converged_solve_gains_at_most_the_bias_energy() {
    // At a solution λᵀw = λtᵀw_t ≤ 0, so ΔT ≤ λᵀβ̃ − ½λᵀAλ − λᵀCλ ≤ sup_λ (λᵀβ̃ − ½λᵀAλ)
    // = ½ β̃ᵀA⁻¹β̃, with the WHOLE A (β̃ zero on the friction rows): through the normal–tangent
    // coupling a sticking contact can take more than the normal block alone would allow. With
    // β̃ = 0 no converged solve adds energy; with Baumgarte's bias it adds at most this.
    //
    // The bound is reached: the 2D body of `frictional_velocities_need_not_be_unique` at rest,
    // pushed out at 1 m/s (b = (−1, 0), β̃ = (1, 0)), sticks with λ = A⁻¹β̃ = (4.1, 1.8)/0.491
    // and gains ΔT = ½β̃ᵀA⁻¹β̃ = 4.1/0.982 = 4.1752 J, while ½ β̃nᵀA_nn⁻¹β̃n is only 0.5495 J.
    let stuck = painleve([-1.0, 0.0]);
    let (lambda, report) = pgs(&stuck, LocalSolve::Exact, 1, None);
    assert!(report.residual < 1e-14);
    assert!(
        (lambda[0] - SVector::from([4.1, 1.8]) / 0.491).amax() < 1e-12,
        "{lambda:?}"
    );
    let du = stuck.velocity_change(&lambda)[0];
    let gained = 0.5 * (du.x * du.x / 0.1 + du.y * du.y / 0.1 + du.z * du.z);
    assert!((gained - 4.1 / 0.982).abs() < 1e-12, "ΔT = {gained}");
    assert!(
        gained > 7.0 * 0.5 / 0.91,
        "more than the normal block's bound"
    );

    // Random problems: ΔT ≤ λᵀβ̃ and ΔT ≤ ½β̃ᵀA⁻¹β̃ where A is invertible. Tolerance 1e-9
    // relative (round-off) plus the residual 1e-10 m/s times the impulses.
    let (checked, tight) = (std::cell::Cell::new(0), std::cell::Cell::new(0.0f64));
    proptest!(common::seeded(300), |(
        s in spec(1..4, 1..6),
        velocities in proptest::collection::vec(-2.0..2.0f64, 6),
        bias in proptest::collection::vec(0.0..1.0f64, 3),
        compliance in 0.0..0.1f64,
        cone in any::<bool>(),
    )| {
        let friction = if cone { FrictionModel::Cone } else { FrictionModel::Box };
        let (problem, beta) = with_velocities(&s, &velocities, &bias, compliance, friction, true);
        let (lambda, report) = pgs(&problem, LocalSolve::Exact, 50_000, Some(1e-10));
        if !report.converged {
            return Ok(());
        }
        let (mass, u, j) = dense(&problem);
        let l = stacked(&lambda);
        let u_after = &u + problem.dense_inverse_mass() * j.transpose() * &l;
        let energy = |v: &DVector<f64>| 0.5 * v.dot(&(&mass * v));
        let change = energy(&u_after) - energy(&u);
        let slack = 1e-9 * energy(&u).max(energy(&u_after)).max(1e-3) + 1e-10 * l.amax() * l.len() as f64;
        let push = l.dot(&beta);
        prop_assert!(change <= push + slack, "ΔT {change} > λᵀβ̃ {push}");
        let a = problem.dense_delassus();
        let e = a.symmetric_eigenvalues();
        if e.min() > 1e-6 * e.max() {
            let inverse = a.try_inverse().unwrap();
            let bound = 0.5 * beta.dot(&(&inverse * &beta));
            prop_assert!(change <= bound + slack, "ΔT {change} > ½β̃ᵀA⁻¹β̃ {bound}");
            checked.set(checked.get() + 1);
            if bound > 1e-6 { tight.set(tight.get().max(change / bound)); }
        }
    });
    println!(
        "bound checked on {} problems; the largest ΔT reached {:.2} of ½β̃ᵀA⁻¹β̃",
        checked.get(),
        tight.get()
    );
    assert!(checked.get() > 100);
}

#[test]
fn frictionless_qp_fixes_friction_rows_at_zero() {
    // μ = 0 with fast sliding (b_t up to 2 m/s): the frictionless QP must leave the friction
    // rows at 0, not free (free rows would be infinite friction: they would stop the sliding).
    proptest!(common::seeded(100), |(s in spec(1..3, 1..5))| {
        let problem = build(&s, 0.0, 0.0, FrictionModel::Box);
        let qp = solve_qp(&problem, &QpFormulation::Frictionless, &QpSettings::default()).unwrap();
        prop_assert!(qp.solved, "{}", qp.status);
        for l in &qp.lambda {
            // The zero cone holds them to clarabel's feasibility tolerance (1e-10, scaled).
            prop_assert!(l[1].abs() <= 1e-8 && l[2].abs() <= 1e-8, "{l:?}");
        }
        // And PGS with μ = 0 agrees on the tangential velocities: both leave them alone.
        let (lambda, report) = pgs(&problem, LocalSolve::Rows, 20_000, Some(1e-10));
        if report.converged {
            let (w_qp, w_pgs) = (problem.constraint_velocity(&qp.lambda), problem.constraint_velocity(&lambda));
            for (a, b) in w_qp.iter().zip(&w_pgs) {
                prop_assert!((a[1] - b[1]).abs() <= 1e-5 && (a[2] - b[2]).abs() <= 1e-5);
            }
        }
    });
}

#[test]
fn cone_pgs_is_invariant_under_tangent_rotation() {
    // (t1, t2) is any orthonormal pair in the tangent plane; the physics cannot depend on it.
    // With the cone step 1/ρ, ρ the largest eigenvalue of A_tt (which turns by a similarity), PGS
    // after any number of sweeps gives the same λn and the turned λt; with Gershgorin's row-sum
    // bound ρ changed with the turn and so did λ. 1e-9 relative: round-off through the sweeps.
    proptest!(common::seeded(300), |(
        s in spec(1..4, 1..6),
        mu in 0.0..1.5f64,
        sweeps in 1u32..40,
        turn in 0.0..6.3f64,
    )| {
        let problem = build(&s, mu, 0.0, FrictionModel::Cone);
        let (lambda, _) = pgs(&problem, LocalSolve::Rows, sweeps, None);
        let (turned, expected) = turn_tangents(&problem, &lambda, turn);
        let (got, _) = pgs(&turned, LocalSolve::Rows, sweeps, None);
        let scale = lambda.iter().map(|l| l.amax()).fold(1e-3, f64::max);
        for (k, (g, e)) in got.iter().zip(&expected).enumerate() {
            prop_assert!((g - e).amax() <= 1e-9 * scale, "contact {k}: {g:?} vs {e:?}");
        }
    });
}

#[test]
fn compliance_with_baumgarte_is_a_spring_damper() {
    use rigidref::rigid3d::assemble::{ProblemSettings, assemble_problem};
    use rigidref::rigid3d::collide::{Contact, Feature};
    use rigidref::rigid3d::frame::ContactFrame;
    use rigidref::rigid3d::warm_start::WarmStart;
    // One solve, one contact under a 2 kg body's centre: with e the penetration beyond the slop
    // and v⁺_n the normal velocity after, e⁺ = e − h v⁺_n the penetration at the step's end, the
    // force λn/h is exactly k e⁺ + d (−v⁺_n) with k = β/(c h²) and d = (1 − β)/(c h).
    let (m, h, slop) = (2.0, 0.01, 0.005);
    for (c, beta, depth, v_in) in [
        (0.01, 0.2, 0.02, -0.5),
        (0.001, 0.8, 0.011, 0.1),
        (0.05, 0.0, 0.03, -1.0),
        (0.02, 1.0, 0.006, -0.2),
    ] {
        let mut body = common::body(m, [0.1, 0.1, 0.1], Matrix3::identity());
        body.x = Vector3::new(0.0, 0.5 - depth, 0.0);
        body.v = Vector3::new(0.0, v_in, 0.0);
        body.update_world_inertia();
        let contact = Contact {
            body1: 0,
            body2: None,
            feature: Feature::Vertex(0),
            point: Vector3::new(0.0, -depth, 0.0),
            frame: ContactFrame::from_normal(&Vector3::y()),
            depth,
        };
        let settings = ProblemSettings {
            h,
            mu: 0.0,
            friction: FrictionModel::Box,
            compliance: c,
            stabilization: beta,
            slop,
            max_push_speed: f64::INFINITY,
        };
        let problem = assemble_problem(&[body], &[contact], &settings, &WarmStart::new(false));
        let (lambda, report) = pgs(&problem, LocalSolve::Exact, 1, None);
        assert!(report.residual < 1e-14);
        let v_after = v_in + lambda[0][0] / m;
        let e = depth - slop;
        let e_after = e - h * v_after;
        let (k, d) = (beta / (c * h * h), (1.0 - beta) / (c * h));
        let force = lambda[0][0] / h;
        let model = k * e_after - d * v_after;
        assert!(
            (force - model).abs() <= 1e-9 * force.abs().max(1.0),
            "c {c}, β {beta}: {force} N vs k e⁺ + d(−v⁺) = {model} N"
        );
        // ERP and CFM (force units) of the same spring–damper: β and c h.
        assert!((h * k / (h * k + d) - beta).abs() < 1e-12);
        assert!((1.0 / (h * k + d) - c * h).abs() < 1e-15);
    }

    // A brick (384 kg) at rest on four compliant corners sinks until the springs carry it:
    // n k e = m g, e = m g c h² / (n β) beyond the slop. scenes/brick_rest.json: c = 0.01 kg⁻¹,
    // β = 0.2, slop 5 mm, h = 0.01 s: e = 4.704 mm, 9.704 mm in all.
    let scene = rigidref::rigid3d::scene::load_scene(
        &common::project_root().join("scenes/brick_rest.json"),
    )
    .unwrap();
    let mut world = rigidref::rigid3d::world::World::new(&scene).unwrap();
    common::run(&mut world, 500, |_, _| {});
    let p = &scene.params;
    let expected = p.stabilization_slop
        + world.bodies[0].mass * 9.8 * p.compliance * p.h() * p.h() / (4.0 * p.stabilization);
    let measured = world.deepest_penetration();
    // 1e-6 m: after 5 s the oscillation (ζ = d/(2√(nkm)) ≈ 1.8) has long died out.
    assert!(
        (measured - expected).abs() < 1e-6,
        "rests {measured} m deep, the spring model says {expected} m"
    );
}

#[test]
fn box_friction_is_the_diagonal_pyramid() {
    // docs/contact.md §"Box and cone friction": |λt1|, |λt2| ≤ μλn is the four-sided pyramid
    // whose edges lie along the diagonals ±t1 ± t2, reaching √2 μλn there and μλn along t1 or t2.
    // A body sliding fast in direction φ in the tangent plane gets the full box friction in that
    // direction's quadrant corner: the friction impulse's size is μλn·√2 on the diagonals and μλn
    // on the axes; the cone's is μλn in every direction.
    let p = |phi: f64, friction| {
        let v = 5.0;
        let mut problem = super::local_solve_problem(
            SMatrix::<f64, 3, 3>::identity() * 0.5,
            SVector::from([-1.0, v * phi.cos(), v * phi.sin()]),
            0.5,
            friction,
        );
        problem.friction = friction;
        let (lambda, _) = pgs(&problem, LocalSolve::Exact, 1, None);
        let l = lambda[0];
        (l[0], l[1].hypot(l[2]))
    };
    let quarter = std::f64::consts::FRAC_PI_4;
    for (phi, reach) in [
        (0.0, 1.0),
        (quarter, 2f64.sqrt()),
        (2.0 * quarter, 1.0),
        (3.0 * quarter, 2f64.sqrt()),
    ] {
        let (n, t) = p(phi, FrictionModel::Box);
        assert!(
            (t - reach * 0.5 * n).abs() < 1e-12,
            "box at φ = {phi}: |λt| {t}, μλn {}",
            0.5 * n
        );
        let (n, t) = p(phi, FrictionModel::Cone);
        assert!((t - 0.5 * n).abs() < 1e-12, "cone at φ = {phi}");
    }
    // Between axis and diagonal the box friction points at the corner, not against the motion.
    let (n, t) = p(0.3, FrictionModel::Box);
    assert!((t - 2f64.sqrt() * 0.5 * n).abs() < 1e-12);
}

#[test]
fn baumgarte_push_out_is_inside_the_friction_bound() {
    // A resting contact (b_n = −bias: the body is still but 2 cm in, the bias pushes it out at
    // bias m/s) sliding sideways: λn includes the push-out impulse, so the friction bound μλn
    // grows with it: the push-out is part of the normal force, in the friction bound and in the
    // reported impulse. A = ½ I (a 2 kg body at its centre), μ = 0.5, sliding at 3 m/s.
    for bias in [0.0, 0.4, 1.0] {
        let problem = super::local_solve_problem(
            SMatrix::<f64, 3, 3>::identity() * 0.5,
            SVector::from([-0.1 - bias, 3.0, 0.0]),
            0.5,
            FrictionModel::Box,
        );
        let (lambda, report) = pgs(&problem, LocalSolve::Rows, 100, Some(1e-14));
        assert!(report.converged);
        let expected_n = 2.0 * (0.1 + bias); // stops the approach and adds the push-out
        assert!((lambda[0][0] - expected_n).abs() < 1e-12, "{:?}", lambda[0]);
        assert!(
            (lambda[0][1] + 0.5 * expected_n).abs() < 1e-12,
            "friction is μ times the whole λn"
        );
    }
}
