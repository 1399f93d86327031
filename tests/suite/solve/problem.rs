//! The contact problem as plain data (src/problem/mod.rs): its dense forms are the per-contact
//! blocks put in place, and the names it prints are the scene files' spellings.

use crate::common;

use common::problems::{build, spec};
use nalgebra::{DVector, SVector};
use proptest::prelude::*;
use rigidref::problem::FrictionModel;
use rigidref::solve::LocalSolve;

#[test]
fn dense_matrices_are_the_per_contact_blocks_in_place() {
    // The dense J, M⁻¹, C, b and A = J M⁻¹ Jᵀ (for tests and clarabel) against the blocks PGS
    // uses: J u stacked equals each contact's J₁u₁ + J₂u₂ (a sign or a misplaced block shows
    // here even where A, which has J twice, would not), A's diagonal blocks are the Delassus
    // blocks, and w from the dense matrices equals w computed through the bodies. 1e-12
    // relative: sums of a few products.
    proptest!(common::seeded(100), |(
        s in spec(1..4, 1..6),
        velocities in proptest::collection::vec(-2.0..2.0f64, 6),
        lambdas in proptest::collection::vec(-1.0..1.0f64, 3),
        compliance in 0.0..0.1f64,
    )| {
        let mut problem = build(&s, 0.5, compliance, FrictionModel::Box);
        for (i, body) in problem.bodies.iter_mut().enumerate() {
            body.velocity = SVector::from_fn(|r, _| velocities[(6 * i + r) % velocities.len()]);
        }
        let u = DVector::from_iterator(
            6 * problem.bodies.len(),
            problem.bodies.iter().flat_map(|b| b.velocity.iter().copied()),
        );
        let ju = problem.dense_jacobian() * &u;
        let a = problem.dense_delassus();
        let c = problem.dense_compliance();
        let b = problem.dense_b();
        let lambda: Vec<SVector<f64, 3>> = (0..problem.contacts.len())
            .map(|k| SVector::from_fn(|r, _| lambdas[(3 * k + r) % lambdas.len()]))
            .collect();
        let stacked = DVector::from_iterator(3 * lambda.len(), lambda.iter().flat_map(|l| l.iter().copied()));
        let w_dense = (&a + &c) * &stacked + &b;
        let w = problem.constraint_velocity(&lambda);
        let m_inverse = problem.dense_inverse_mass();
        for (k, contact) in problem.contacts.iter().enumerate() {
            let mut expected = SVector::<f64, 3>::zeros();
            for side in 0..2 {
                if let Some(body) = contact.bodies[side] {
                    expected += contact.jacobian[side] * problem.bodies[body].velocity;
                    let block = m_inverse.view((6 * body, 6 * body), (6, 6));
                    prop_assert_eq!(block.clone_owned(), problem.bodies[body].inverse_mass.clone_owned());
                }
            }
            let block = problem.delassus_block(k);
            for r in 0..3 {
                let scale = 1.0 + expected.amax();
                prop_assert!((ju[3 * k + r] - expected[r]).abs() <= 1e-12 * scale, "J u, contact {k} row {r}");
                prop_assert_eq!(b[3 * k + r], contact.b[r]);
                prop_assert!((w_dense[3 * k + r] - w[k][r]).abs() <= 1e-12 * (1.0 + w[k].amax()), "w, contact {k} row {r}");
                for q in 0..3 {
                    prop_assert!((a[(3 * k + r, 3 * k + q)] - block[(r, q)]).abs() <= 1e-12 * (1.0 + block.amax()));
                }
            }
            prop_assert_eq!(c[(3 * k, 3 * k)], contact.compliance);
        }
    });
}

#[test]
fn printed_names_are_the_scene_file_spellings() {
    // `rigidref scene`, `contacts` and the crosscheck print these names; a user copies them back
    // into a scene file, so each must be exactly the value the scene reader accepts.
    for model in [FrictionModel::Box, FrictionModel::Cone] {
        assert_eq!(
            serde_json::to_string(&model).unwrap(),
            format!("\"{}\"", model.name())
        );
        let read: FrictionModel = serde_json::from_str(&format!("\"{}\"", model.name())).unwrap();
        assert_eq!(read, model);
    }
    for local in [LocalSolve::Rows, LocalSolve::Exact] {
        assert_eq!(
            serde_json::to_string(&local).unwrap(),
            format!("\"{}\"", local.name())
        );
        let read: LocalSolve = serde_json::from_str(&format!("\"{}\"", local.name())).unwrap();
        assert_eq!(read, local);
    }
}

#[test]
fn pgs_leaves_alone_a_contact_no_impulse_can_move() {
    // A contact between two bodies that cannot move (both inverse masses zero: two pinned 2D
    // bodies, say) has A = 0: no impulse changes its velocity. PGS must leave its impulse where
    // the start put it (projected onto the friction set) rather than divide by a zero diagonal,
    // and the residual must report the violation it cannot remove (|min(λn, w_n)| = 1 m/s here).
    use rigidref::problem::{ContactProblem3, ProblemBody, ProblemContact, RowBounds};
    use rigidref::solve::{ContactOrder, PgsSettings, PgsWorkspace, solve_pgs};
    let still = ProblemBody {
        inverse_mass: nalgebra::SMatrix::zeros(),
        velocity: SVector::zeros(),
    };
    let mut jacobian = nalgebra::SMatrix::<f64, 3, 6>::zeros();
    jacobian.fixed_view_mut::<3, 3>(0, 0).fill_with_identity();
    let problem = ContactProblem3 {
        friction: FrictionModel::Box,
        bodies: vec![still.clone(), still],
        contacts: vec![ProblemContact {
            bodies: [Some(0), Some(1)],
            jacobian: [jacobian, -jacobian],
            b: SVector::from([-1.0, 2.0, 0.0]),
            mu: 0.5,
            compliance: 0.0,
            lambda0: SVector::from([1.0, 0.3, -0.2]),
            bounds: RowBounds::Contact,
        }],
    };
    let settings = PgsSettings {
        max_iterations: 5,
        tolerance: None,
        order: ContactOrder::Sequential,
        local: LocalSolve::Rows,
    };
    for friction in [FrictionModel::Box, FrictionModel::Cone] {
        let mut problem = problem.clone();
        problem.friction = friction;
        let mut workspace = PgsWorkspace::new(0);
        let mut lambda = Vec::new();
        let report = solve_pgs(&problem, &settings, &mut workspace, &mut lambda);
        assert_eq!(lambda[0], SVector::from([1.0, 0.3, -0.2]), "{friction:?}");
        assert_eq!(report.residual, 1.0, "{friction:?}");
        for i in 0..2 {
            assert_eq!(*workspace.delta_velocity(i), SVector::<f64, 6>::zeros());
        }
    }
}

#[test]
fn validation_rejects_a_negative_or_infinite_compliance() {
    // A contact problem is checked before it is solved (`ContactProblem::validate`, used on every
    // problem file read): compliance is a finite number ≥ 0. −1e-3 and ∞ are refused with a
    // message naming the contact and the quantity; 0 and 1e-3 pass.
    proptest!(common::seeded(5), |(s in spec(1..3, 1..4))| {
        for (c, ok) in [(0.0, true), (1e-3, true), (-1e-3, false), (f64::INFINITY, false)] {
            let mut problem = build(&s, 0.5, 0.0, FrictionModel::Box);
            let last = problem.contacts.len() - 1;
            problem.contacts[last].compliance = c;
            let result = problem.validate();
            prop_assert_eq!(result.is_ok(), ok, "compliance {}: {:?}", c, result);
            if let Err(e) = result {
                prop_assert!(e.contains(&format!("contact {last}")) && e.contains("compliance"), "{}", e);
            }
        }
    });
}

/// What a problem file could carry that no solver would read as written is refused (not
/// silently symmetrised, ignored or dropped): a non-symmetric or indefinite inverse mass, a
/// non-zero Jacobian block for the static world, a friction coefficient on free (joint) rows.
/// Each message names the body or contact and what is wrong; the unchanged problem passes.
#[test]
fn validation_refuses_what_a_solver_would_silently_read_differently() {
    use rigidref::problem::RowBounds;
    proptest!(common::seeded(5), |(s in spec(1..3, 1..4))| {
        let problem = build(&s, 0.5, 0.0, FrictionModel::Box);
        prop_assert!(problem.validate().is_ok());
        let mut skew = problem.clone();
        skew.bodies[0].inverse_mass[(0, 1)] += 0.5;
        let e = skew.validate().unwrap_err();
        prop_assert!(e.contains("body 0") && e.contains("not symmetric"), "{}", e);
        let mut indefinite = problem.clone();
        indefinite.bodies[0].inverse_mass[(2, 2)] = -1.0;
        let e = indefinite.validate().unwrap_err();
        prop_assert!(e.contains("body 0") && e.contains("positive semi-definite"), "{}", e);
        let mut grounded = problem.clone();
        grounded.contacts[0].bodies[1] = None;
        grounded.contacts[0].jacobian[1][(0, 0)] = 1.0;
        let e = grounded.validate().unwrap_err();
        prop_assert!(e.contains("contact 0") && e.contains("J2 must be zero"), "{}", e);
        let mut joint = problem.clone();
        joint.contacts[0].bounds = RowBounds::Free;
        let e = joint.validate().unwrap_err();
        prop_assert!(e.contains("contact 0") && e.contains("free rows"), "{}", e);
        joint.contacts[0].mu = 0.0;
        prop_assert!(joint.validate().is_ok());
    });
}

#[test]
fn a_row_no_impulse_can_move_counts_in_the_residual_only_as_far_as_it_is_violated() {
    // A contact between two pinned bodies has a zero Delassus diagonal: its rows cannot be
    // scaled to velocities, so the residual takes the violation itself (docs/contact.md
    // §"Residual"): a negative λn or an approach w_n < 0 by its size, a friction impulse by how
    // far it is outside ±μλn. The values here are exact in binary, so the checks are exact.
    use rigidref::solve::residual::{RowScales, contact_residual};
    let scales = RowScales::<3> {
        diagonal: SVector::zeros(),
        tangent_rho: 0.0,
        block: nalgebra::SMatrix::zeros(),
    };
    let r = |lambda: [f64; 3], w: [f64; 3]| {
        contact_residual(
            FrictionModel::Box,
            0.5,
            &SVector::from(lambda),
            &SVector::from(w),
            &scales,
        )
    };
    assert_eq!(r([0.0, 0.0, 0.0], [2.0, 1.0, -1.0]), 0.0); // separating, no impulse
    assert_eq!(r([-1.0, 0.0, 0.0], [5.0, 0.0, 0.0]), 1.0); // a pulling impulse of 1
    assert_eq!(r([2.0, 0.0, 0.0], [-0.25, 0.0, 0.0]), 0.25); // approaching at 0.25
    assert_eq!(r([2.0, 0.75, -0.5], [0.0, 3.0, 3.0]), 0.0); // friction within ±μλn = ±1
    assert_eq!(r([2.0, 1.5, 0.0], [0.0, 0.0, 0.0]), 0.5); // friction 0.5 beyond its bound
    assert_eq!(r([2.0, 0.0, -1.25], [0.0, 0.0, 0.0]), 0.25);
}

#[test]
fn the_residuals_are_velocities_on_the_contacts_own_scale() {
    // Row and cone residuals are velocities (m/s): a sticking contact inside its disk that
    // still slips at ‖w_t‖ has the friction residual ρ‖Δλ‖ with Δλ = w_t/ρ its one projected
    // step, i.e. exactly ‖w_t‖, whatever ρ; the Coulomb residual's scale is the trace of the
    // contact's block, or 1 kg⁻¹ for a contact no impulse of its own can move. Values exact
    // in binary.
    use rigidref::solve::residual::{RowScales, contact_residual, coulomb_scale};
    let block =
        nalgebra::SMatrix::<f64, 3, 3>::from_diagonal(&nalgebra::Vector3::new(4.0, 2.0, 2.0));
    let scales = RowScales::<3> {
        diagonal: block.diagonal(),
        tangent_rho: 2.0,
        block,
    };
    let r = contact_residual(
        FrictionModel::Cone,
        0.5,
        &SVector::from([2.0, 0.0, 0.0]),
        &SVector::from([0.0, 0.5, 0.0]),
        &scales,
    );
    assert_eq!(r, 0.5);
    assert_eq!(coulomb_scale(&scales), 8.0);
    let pinned = RowScales::<3> {
        diagonal: SVector::zeros(),
        tangent_rho: 0.0,
        block: nalgebra::SMatrix::zeros(),
    };
    assert_eq!(coulomb_scale(&pinned), 1.0);
}

/// A free row whose diagonal is zero moves nothing (here a joint on a pinned body, without
/// compliance): PGS leaves its λ at the start, as it leaves a contact row's (docs/contact.md
/// §"Row bounds": the update is taken only where a_r > 0), instead of dividing by zero; the
/// joint on the moving body beside it is still solved, in both orders and both local solves.
#[test]
fn a_free_row_that_moves_nothing_keeps_its_start() {
    use nalgebra::{Matrix3, SMatrix, Vector3};
    use rigidref::problem::{ContactProblem, ProblemBody, ProblemContact, RowBounds};
    use rigidref::solve::{ContactOrder, LocalSolve, PgsSettings, PgsWorkspace, solve_pgs};
    let arm = |rx: f64, ry: f64| SMatrix::<f64, 2, 3>::new(1.0, 0.0, -ry, 0.0, 1.0, rx);
    let joint = |body: usize, start: [f64; 2]| ProblemContact {
        bodies: [Some(body), None],
        jacobian: [arm(0.4, -0.2), SMatrix::zeros()],
        b: nalgebra::Vector2::new(0.5, -0.3),
        mu: 0.0,
        compliance: 0.0,
        lambda0: SVector::<f64, 2>::from(start),
        bounds: RowBounds::Free,
    };
    let problem = ContactProblem::<3, 2> {
        friction: FrictionModel::Box,
        bodies: vec![
            ProblemBody {
                inverse_mass: Matrix3::zeros(),
                velocity: Vector3::zeros(),
            },
            ProblemBody {
                inverse_mass: Matrix3::from_diagonal(&Vector3::new(0.5, 0.5, 2.0)),
                velocity: Vector3::new(0.1, -0.4, 0.3),
            },
        ],
        contacts: vec![joint(0, [0.3, -0.2]), joint(1, [0.0, 0.0])],
    };
    problem.validate().unwrap();
    for order in [ContactOrder::Sequential, ContactOrder::Coloured] {
        for local in [LocalSolve::Rows, LocalSolve::Exact] {
            let settings = PgsSettings {
                max_iterations: 20,
                tolerance: None,
                order,
                local,
            };
            let mut lambda = Vec::new();
            let mut workspace = PgsWorkspace::new(0);
            solve_pgs(&problem, &settings, &mut workspace, &mut lambda);
            assert_eq!(
                lambda[0],
                SVector::<f64, 2>::new(0.3, -0.2),
                "{order:?} {local:?}"
            );
            // The moving body's joint holds: w = b + J Δu = 0 on both rows (to round-off of a
            // converged one-body solve). The pinned one cannot: its w stays b.
            let c = &problem.contacts[1];
            let w = c.b + c.jacobian[0] * workspace.delta_velocity(1);
            assert!(
                w.amax() < 1e-12,
                "{order:?} {local:?}: w = {w}, λ = {lambda:?}"
            );
        }
    }
}

#[test]
fn free_rows_are_solved_to_their_linear_system_and_round_trip() {
    // Two 2D bodies (D = 3, R = 2): body 0 pinned to the world by a compliant free entry (the
    // compliance on both its rows), body 0 and body 1 joined by a second free entry, and body 1
    // pressed onto the world by a contact with μ = 10, so that it sticks. With every row active
    // the solution is the linear system (A + C) λ = −b, and PGS (row by row and with the exact
    // local solve) and clarabel must all reach it: a free row clamped at 0 like a normal row, or
    // projected onto a friction bound, would leave λ off it. 1e-9 relative: converged solves of a
    // well-conditioned 6 × 6 system.
    use nalgebra::{Matrix3, SMatrix, Vector3};
    use rigidref::problem::{ContactProblem, ProblemBody, ProblemContact, RowBounds};
    use rigidref::solve::qp::{QpFormulation, QpSettings, solve_qp};
    let arm = |rx: f64, ry: f64| SMatrix::<f64, 2, 3>::new(1.0, 0.0, -ry, 0.0, 1.0, rx);
    let body = |m: f64, i: f64, v: Vector3<f64>| ProblemBody {
        inverse_mass: Matrix3::from_diagonal(&Vector3::new(1.0 / m, 1.0 / m, 1.0 / i)),
        velocity: v,
    };
    // μ only on the contact: a free entry carries none (ContactProblem::validate).
    let entry = |bodies, jacobian: [SMatrix<f64, 2, 3>; 2], b, compliance, bounds| ProblemContact {
        bodies,
        jacobian,
        b,
        mu: if bounds == RowBounds::Free { 0.0 } else { 10.0 },
        compliance,
        lambda0: SVector::<f64, 2>::zeros(),
        bounds,
    };
    let problem = ContactProblem::<3, 2> {
        friction: FrictionModel::Box,
        bodies: vec![
            body(2.0, 0.7, Vector3::new(0.3, -0.8, 0.2)),
            body(1.0, 0.4, Vector3::new(-0.5, -1.2, 0.1)),
        ],
        contacts: vec![
            entry(
                [Some(0), None],
                [arm(-0.5, 0.2), SMatrix::zeros()],
                nalgebra::Vector2::new(0.25, -0.7),
                0.05,
                RowBounds::Free,
            ),
            entry(
                [Some(0), Some(1)],
                [arm(0.6, -0.1), -arm(-0.4, 0.3)],
                nalgebra::Vector2::new(0.4, 0.2),
                0.0,
                RowBounds::Free,
            ),
            entry(
                [Some(1), None],
                [
                    SMatrix::<f64, 2, 3>::new(0.0, 1.0, 0.3, -1.0, 0.0, 0.1),
                    SMatrix::zeros(),
                ],
                nalgebra::Vector2::new(-1.2, 0.3),
                0.0,
                RowBounds::Contact,
            ),
        ],
    };
    problem.validate().unwrap();
    let hessian = problem.dense_delassus() + problem.dense_compliance();
    let compliance = problem.dense_compliance();
    assert_eq!(
        (compliance[(0, 0)], compliance[(1, 1)]),
        (0.05, 0.05),
        "compliance on rows x, y"
    );
    assert_eq!(compliance[(5, 5)], 0.0, "a contact's friction row has none");
    let exact = hessian.lu().solve(&(-problem.dense_b())).unwrap();
    assert!(
        exact[4] > 0.0 && exact[5].abs() < 10.0 * exact[4],
        "the contact must stick: {exact}"
    );
    assert!(
        exact.rows(0, 4).min() < 0.0,
        "a free row must be negative: {exact}"
    );
    let flat = |l: &[SVector<f64, 2>]| DVector::from_iterator(6, l.iter().flatten().copied());
    let close = |l: &DVector<f64>, what: &str| {
        let error = (l - &exact).amax() / exact.amax();
        assert!(error < 1e-9, "{what}: {l} against {exact} ({error:e})");
    };
    for local in [LocalSolve::Rows, LocalSolve::Exact] {
        let (lambda, report) = super::run_pgs(&problem, local, 10_000, Some(1e-14));
        assert!(report.converged, "{local:?}: {report:?}");
        close(&flat(&lambda), &format!("PGS {local:?}"));
        assert!(rigidref::solve::residual(&problem, &lambda) <= 1e-13);
    }
    let fixed = vec![exact[0], exact[2], exact[4]];
    let qp = solve_qp(
        &problem,
        &QpFormulation::BoxFixed(fixed),
        &QpSettings::default(),
    )
    .unwrap();
    assert!(qp.solved, "{}", qp.status);
    let error = (flat(&qp.lambda) - &exact).amax() / exact.amax();
    assert!(error < 1e-6, "clarabel {:?} ({error:e})", qp.lambda);

    // The file writes "bounds": "free" on the joints only and reads back the same problem.
    let file = rigidref::problem::json::ProblemFile::new(&problem);
    let text = serde_json::to_string(&file).unwrap();
    assert_eq!(text.matches(r#""bounds":"free""#).count(), 2, "{text}");
    let back: rigidref::problem::json::ProblemFile = serde_json::from_str(&text).unwrap();
    assert_eq!(back.to_problem::<3, 2>().unwrap(), problem);
}

#[test]
fn the_cone_step_scale_is_the_largest_friction_eigenvalue_and_never_negative() {
    // ρ (RowScales::tangent_rho) is the largest eigenvalue of the friction rows' block A_tt, and
    // PGS steps a friction impulse by w_t/ρ: a negative ρ would step it the wrong way, so a
    // block whose A_tt has no positive eigenvalue gets ρ = 0 (a row no impulse of its own can
    // move), in 2D (one friction row) as in 3D. Such blocks are reachable: validation accepts an
    // inverse mass with eigenvalues down to −1e-9 of its largest entry (a file's printed digits),
    // and its round-off floor (64 ε of the largest diagonal) is far smaller. Values exact in
    // binary except the 3D eigenvalue, compared with nalgebra's to 1e-14 relative.
    use nalgebra::{Matrix2, Matrix3, Matrix4, SMatrix, Vector3};
    use rigidref::problem::{ContactProblem, ProblemBody, ProblemContact, RowBounds};
    use rigidref::solve::residual::{row_scales, tangent_eigenvalue};
    // 2D: A_tt is the one friction row's diagonal.
    assert_eq!(tangent_eigenvalue(&Matrix2::new(3.0, 0.5, 0.5, 2.0)), 2.0);
    assert_eq!(tangent_eigenvalue(&Matrix2::new(3.0, 0.5, 0.5, -0.5)), 0.0);
    // 3D: the closed form of the symmetric 2 × 2 A_tt.
    let a = Matrix3::new(5.0, 0.25, -0.5, 0.25, 2.0, 0.75, -0.5, 0.75, 1.5);
    let largest = a
        .fixed_view::<2, 2>(1, 1)
        .into_owned()
        .symmetric_eigenvalues()
        .max();
    assert!((tangent_eigenvalue(&a) - largest).abs() <= 1e-14 * largest);
    let negative = Matrix3::new(5.0, 0.0, 0.0, 0.0, -0.5, 0.125, 0.0, 0.125, -0.25);
    assert_eq!(tangent_eigenvalue(&negative), 0.0);
    // Above three rows, Gershgorin's bound (the largest absolute row sum of A_tt).
    let four = Matrix4::new(
        9.0, 0.0, 0.0, 0.0, 0.0, 2.0, -1.0, 0.5, 0.0, -1.0, 1.0, 0.25, 0.0, 0.5, 0.25, 3.0,
    );
    assert_eq!(tangent_eigenvalue(&four), 3.75);
    // A validated 2D problem whose friction row's diagonal is −5e-10 kg⁻¹.
    let problem = ContactProblem::<3, 2> {
        friction: FrictionModel::Box,
        bodies: vec![ProblemBody {
            inverse_mass: Matrix3::from_diagonal(&Vector3::new(1.0, -5e-10, 1.0)),
            velocity: Vector3::new(0.0, -1.0, 0.0),
        }],
        contacts: vec![ProblemContact {
            bodies: [Some(0), None],
            // normal row along x, friction row along y
            jacobian: [
                SMatrix::<f64, 2, 3>::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0),
                SMatrix::zeros(),
            ],
            b: nalgebra::Vector2::zeros(),
            mu: 0.5,
            compliance: 0.0,
            lambda0: SVector::<f64, 2>::zeros(),
            bounds: RowBounds::Contact,
        }],
    };
    problem.validate().unwrap();
    let scales = row_scales(&problem, 0);
    assert_eq!(scales.diagonal[1], -5e-10);
    assert_eq!(scales.tangent_rho, 0.0);
}
