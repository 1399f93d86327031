//! The exact local solve (docs/contact.md §"Exact local solve"): one contact's own problem solved
//! in one visit, the cycle of row-by-row PGS it removes, agreement with row-by-row PGS where both
//! converge, and convergence on the assignment's cone-friction problems.

use super::run_pgs as pgs;
use crate::common;

use common::problems::{build, physical_spec};
use nalgebra::{DMatrix, SMatrix, SVector};
use proptest::prelude::*;
use rigidref::problem::{ContactProblem, FrictionModel, ProblemBody, ProblemContact, RowBounds};
use rigidref::solve::qp::objective;
use rigidref::solve::residual::coulomb_residual;
use rigidref::solve::{LocalSolve, residual};
use std::cell::Cell;

/// One contact whose Delassus block is `a` (kg⁻¹): one body with inverse mass `a` and J₁ = I, so
/// that A = J M⁻¹ Jᵀ = a exactly, normal–tangent coupling and all.
fn one_contact<const R: usize>(
    a: SMatrix<f64, R, R>,
    b: SVector<f64, R>,
    mu: f64,
    friction: FrictionModel,
) -> ContactProblem<R, R> {
    ContactProblem {
        friction,
        bodies: vec![ProblemBody {
            inverse_mass: a,
            velocity: SVector::zeros(),
        }],
        contacts: vec![ProblemContact {
            bodies: [Some(0), None],
            jacobian: [SMatrix::identity(), SMatrix::zeros()],
            b,
            mu,
            compliance: 0.0,
            lambda0: SVector::zeros(),
            bounds: RowBounds::Contact,
        }],
    }
}

/// A random symmetric positive definite R × R block A = L Lᵀ + 0.05 I (kg⁻¹), L's entries in
/// [−1, 1]: every entry coupled, eigenvalues from 0.05 to about 3·R.
fn spd<const R: usize>() -> impl Strategy<Value = SMatrix<f64, R, R>> {
    proptest::collection::vec(-1.0..1.0f64, R * R).prop_map(|entries| {
        let l = SMatrix::<f64, R, R>::from_iterator(entries);
        l * l.transpose() + SMatrix::<f64, R, R>::identity() * 0.05
    })
}

/// b with every sign pattern: each entry's magnitude in [0.01, 2] m/s and its sign drawn
/// separately (0 included, the boundary case of separation and of sticking).
fn rhs<const R: usize>() -> impl Strategy<Value = SVector<f64, R>> {
    proptest::collection::vec((0.01..2.0f64, -1i32..=1), R).prop_map(|entries| {
        SVector::<f64, R>::from_iterator(entries.into_iter().map(|(m, s)| m * s as f64))
    })
}

#[test]
fn exact_local_solve_finishes_any_one_contact_problem_in_one_visit() {
    // 1e-12 m/s against b of up to 2 m/s and blocks of up to ~9 kg⁻¹: the candidates come from a
    // 3 × 3 elimination and a bisection to the last bit, so round-off is ~1e-14 (the largest
    // seen over 20 000 cases was 7e-14).
    let worst = Cell::new(0.0f64);
    proptest!(common::seeded(2000), |(
        a in spd::<3>(), b in rhs::<3>(), mu in 0.0..2.0f64,
        a2 in spd::<2>(), b2 in rhs::<2>(),
    )| {
        for friction in [FrictionModel::Box, FrictionModel::Cone] {
            let problem = one_contact(a, b, mu, friction);
            let (lambda, report) = pgs(&problem, LocalSolve::Exact, 1, None);
            prop_assert_eq!(report.iterations, 1);
            prop_assert!(report.residual <= 1e-12, "{friction:?}: {report:?}, λ {:?}", lambda[0]);
            // The independent measures agree: the residual from scratch and, for the disk,
            // the exact Coulomb law's.
            prop_assert!(residual(&problem, &lambda) <= 1e-12);
            if friction == FrictionModel::Cone {
                prop_assert!(coulomb_residual(&problem, &lambda) <= 1e-12, "{:?}", lambda[0]);
            }
            worst.set(worst.get().max(report.residual));
            // 2D: the 2 × 2 problem, where box and disk are the same interval.
            let problem = one_contact(a2, b2, mu, friction);
            let (lambda, report) = pgs(&problem, LocalSolve::Exact, 1, None);
            prop_assert!(report.residual <= 1e-12, "2D {friction:?}: {report:?}");
            prop_assert!(coulomb_residual(&problem, &lambda) <= 1e-12);
        }
    });
    println!("one visit, worst residual {:.2e} m/s", worst.get());
}

#[test]
fn row_by_row_pgs_cycles_on_a_coupled_contact_and_the_exact_solve_does_not() {
    // A = [[1, ½, 0], [½, 1, 0], [0, 0, 1]] kg⁻¹ (pushing along n also pushes along t1), approach
    // at 1 m/s, sliding at −2 m/s along t1, μ = 2. The one solution: sliding, w_n = 0 and
    // λt1 = μλn, i.e. λn + ½·2λn = 1: λ = (½, 1, 0), w_t1 = −¾ m/s. (Separation fails, w_n < 0;
    // sticking needs λ = (0, 2, 0), outside the disk; sliding the other way gives w_n = −1.)
    let a = SMatrix::<f64, 3, 3>::new(1.0, 0.5, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0, 1.0);
    let b = SVector::<f64, 3>::new(-1.0, -2.0, 0.0);
    for friction in [FrictionModel::Box, FrictionModel::Cone] {
        let problem = one_contact(a, b, 2.0, friction);
        // Row by row, after the first two sweeps (from 0: (1, 1.5, 0), then (¼, ½, 0)), from λ = (¼, ½, 0): w_n = −½ raises λn to ¾, whose bound 1.5 then clamps
        // λt1 (the unclamped step wants 1.625); from (¾, 1.5, 0): w_n = +½ lowers λn to ¼, whose
        // bound ½ clamps λt1 again. A two-cycle, exactly, forever.
        let high = SVector::<f64, 3>::new(0.75, 1.5, 0.0);
        let low = SVector::<f64, 3>::new(0.25, 0.5, 0.0);
        for sweeps in [3, 4, 1_001, 1_002, 100_000] {
            let (lambda, report) = pgs(&problem, LocalSolve::Rows, sweeps, Some(1e-11));
            assert!(!report.converged, "{friction:?} {sweeps}: {report:?}");
            let expected = if sweeps % 2 == 1 { high } else { low };
            assert_eq!(lambda[0], expected, "{friction:?}, after {sweeps} sweeps");
            assert_eq!(report.residual, 0.5, "{friction:?}");
        }
        // The exact local solve: the solution in one visit.
        let (lambda, report) = pgs(&problem, LocalSolve::Exact, 1, None);
        assert!(
            (lambda[0] - SVector::<f64, 3>::new(0.5, 1.0, 0.0)).amax() < 1e-15,
            "{friction:?}: {:?}",
            lambda[0]
        );
        assert!(report.residual < 1e-15, "{report:?}");
    }
}

/// Whether λ is unique for `problem` at the solution `lambda`: the Hessian A + C restricted to
/// the rows that are free there (normal rows, and friction rows whose bound μλn is not zero) has
/// smallest eigenvalue above 1e-8 of its largest (the crosscheck's test).
fn unique_at<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    lambda: &[SVector<f64, R>],
) -> bool {
    let free: Vec<usize> = (0..problem.contacts.len())
        .flat_map(|k| {
            let bound = problem.contacts[k].mu * lambda[k][0];
            (0..R)
                .filter(move |&r| r == 0 || bound > 0.0)
                .map(move |r| R * k + r)
        })
        .collect();
    let h: DMatrix<f64> = problem.dense_delassus() + problem.dense_compliance();
    let e = h
        .select_rows(&free)
        .select_columns(&free)
        .symmetric_eigenvalues();
    e.is_empty() || e.min() > 1e-8 * e.max()
}

#[test]
fn exact_and_rows_agree_where_both_converge() {
    // Many-contact problems with real contact Jacobians (bodies with matched mass and inertia,
    // contacts within 0.8 m of their centre) and μ ≤ 1. Where both visits converge (residual
    // 1e-10 m/s), they must have found the same solution: the same λ where λ is unique, else the
    // same contact velocities w and objective (a rigid body on several contacts shares its load
    // in many ways). 1e-6: two solves converged to 1e-10 m/s on blocks of condition up to ~1e6
    // differ by up to residual × condition.
    let (both, by_lambda, by_velocity) = (Cell::new(0), Cell::new(0), Cell::new(0));
    proptest!(common::seeded(300), |(
        s in physical_spec(1..4, 2..8),
        mu in 0.0..1.0f64,
        cone in any::<bool>(),
    )| {
        let friction = if cone { FrictionModel::Cone } else { FrictionModel::Box };
        let problem = build(&s, mu, 0.0, friction);
        let (rows, rows_report) = pgs(&problem, LocalSolve::Rows, 100_000, Some(1e-10));
        let (exact, exact_report) = pgs(&problem, LocalSolve::Exact, 100_000, Some(1e-10));
        if !(rows_report.converged && exact_report.converged) {
            return Ok(());
        }
        both.set(both.get() + 1);
        let scale = problem.dense_b().amax().max(0.1);
        let lambda_scale = rows.iter().chain(&exact).map(|l| l.amax()).fold(scale / 10.0, f64::max);
        if unique_at(&problem, &rows) && unique_at(&problem, &exact) {
            by_lambda.set(by_lambda.get() + 1);
            for (k, (r, e)) in rows.iter().zip(&exact).enumerate() {
                prop_assert!((r - e).amax() <= 1e-6 * lambda_scale, "contact {k}: rows {r:?}, exact {e:?}");
            }
        } else {
            by_velocity.set(by_velocity.get() + 1);
            let (w_rows, w_exact) = (problem.constraint_velocity(&rows), problem.constraint_velocity(&exact));
            for (k, (r, e)) in w_rows.iter().zip(&w_exact).enumerate() {
                prop_assert!((r - e).amax() <= 1e-6 * scale, "contact {k}: w rows {r:?}, exact {e:?}");
            }
            let (f_rows, f_exact) = (objective(&problem, &rows), objective(&problem, &exact));
            prop_assert!((f_rows - f_exact).abs() <= 1e-6 * scale * lambda_scale);
        }
    });
    println!(
        "both converged on {} problems: {} compared by λ, {} by velocity and objective",
        both.get(),
        by_lambda.get(),
        by_velocity.get()
    );
    assert!(
        both.get() >= 200,
        "only {} problems converged both ways",
        both.get()
    );
}

#[test]
fn exact_local_solve_converges_on_the_assignment_cone_problems() {
    use rigidref::common::scene_json::Overrides;
    use rigidref::rigid3d::scene::load_scene_with;
    use rigidref::rigid3d::world::World;
    let Some(dir) = common::rigid3d_assignment() else {
        return;
    };
    // The budget: the most sweeps any of these problems needed was 15 481 (scene6; printed
    // below), on two-contact problems of the brick resting on an edge, whose 6 × 6 Delassus
    // operator is singular (a rigid body on two points); the exact visit cannot cycle on one
    // contact, but Gauss–Seidel between two strongly coupled contacts still converges slowly.
    const BUDGET: u32 = 50_000;
    for k in [5, 6, 7] {
        let path = dir.join(format!("scenes/scene{k}.json"));
        let sets = Overrides::parse(&[
            "friction_model=cone".into(),
            "pgs_local_solve=exact".into(),
            "pgs_tolerance=1e-11".into(),
            format!("pgs_iterations={BUDGET}"),
        ])
        .unwrap();
        let scene = load_scene_with(&path, &sets).unwrap_or_else(|e| panic!("{e}"));
        let mut world = World::new(&scene).unwrap();
        let frames = (2.0 / scene.params.dt).round() as u64;
        let (solves, most) = (Cell::new(0), Cell::new(0));
        let worst_coulomb = Cell::new(0.0f64);
        common::run(&mut world, frames, |w, step| {
            for s in &w.solves {
                solves.set(solves.get() + 1);
                most.set(most.get().max(s.report.iterations));
                assert!(
                    s.report.converged,
                    "scene{k} step {step}: {} contacts, {:?}",
                    s.problem.contacts.len(),
                    s.report
                );
                // The exact Coulomb law, relative to the problem's velocities: 1e-9 ‖b‖.
                let b = s.problem.dense_b().norm().max(1e-300);
                let coulomb = s.report.coulomb_residual.expect("cone friction reports it");
                assert!(
                    coulomb <= 1e-9 * b,
                    "scene{k} step {step}: Coulomb residual {coulomb:e}, ‖b‖ {b:e}"
                );
                worst_coulomb.set(worst_coulomb.get().max(coulomb / b));
            }
        });
        println!(
            "scene{k}: {} cone-friction solves, at most {} sweeps to 1e-11 m/s, worst Coulomb residual {:.2e} ‖b‖",
            solves.get(),
            most.get(),
            worst_coulomb.get()
        );
        assert!(solves.get() > 0, "scene{k}: no contact solves");
    }
}

/// A contact no impulse of its own can move (a pinned body on the ground: A = 0) and that
/// approaches has no exact case; the exact visit takes its best candidate, and the report counts
/// every such visit instead of passing over it (docs/contact.md §"Exact local solve").
#[test]
fn the_exact_local_solve_reports_its_fallbacks() {
    let stuck = super::local_solve_problem(
        nalgebra::SMatrix::zeros(),
        nalgebra::SVector::from([-1.0, 0.0, 0.0]),
        0.5,
        rigidref::problem::FrictionModel::Cone,
    );
    let (_, report) = super::run_pgs(&stuck, LocalSolve::Exact, 3, None);
    assert_eq!(report.local_fallbacks, 3, "{report:?}");
    assert!(
        report.residual > 0.5,
        "the violation stays in the residual: {report:?}"
    );
    // A well-posed contact never falls back.
    let fine = super::local_solve_problem(
        nalgebra::SMatrix::identity(),
        nalgebra::SVector::from([-1.0, 3.0, 4.0]),
        0.5,
        rigidref::problem::FrictionModel::Cone,
    );
    let (_, report) = super::run_pgs(&fine, LocalSolve::Exact, 3, None);
    assert_eq!(report.local_fallbacks, 0, "{report:?}");
}

/// The local form's PGS (`solve_pgs_local`, Siconos' NSGS with exact visits) counts its
/// fallbacks as the workspace's does: every visit of the contact that no exact case fits, and
/// none of the well-posed one's. The two problems of
/// [`the_exact_local_solve_reports_its_fallbacks`] in local form (`to_local`). Kills the mutant
/// `pgs_delassus.rs:118:24` (the `!` before `visit_exactly` deleted: the exact visits counted
/// instead of the fallbacks).
#[test]
fn the_local_forms_exact_solve_reports_its_fallbacks() {
    use rigidref::solve::pgs_delassus::solve_pgs_local;
    use rigidref::solve::{ContactOrder, PgsSettings};
    let settings = PgsSettings {
        max_iterations: 3,
        tolerance: None,
        order: ContactOrder::Sequential,
        local: LocalSolve::Exact,
    };
    for (a, b, fallbacks) in [
        (SMatrix::zeros(), SVector::from([-1.0, 0.0, 0.0]), 3),
        (SMatrix::identity(), SVector::from([-1.0, 3.0, 4.0]), 0),
    ] {
        let problem = super::local_solve_problem(a, b, 0.5, FrictionModel::Cone).to_local();
        let mut lambda = Vec::new();
        let report = solve_pgs_local(&problem, &settings, 0, &mut lambda);
        assert_eq!(report.iterations, 3, "{report:?}");
        assert_eq!(report.local_fallbacks, fallbacks, "{report:?}");
    }
}

/// The exact local solve of the disk (cone, R = 3) as it was before its grid of cos and sin was
/// tabulated: separate, stick, then the sliding roots bracketed on 256 cells with `sin` and `cos`
/// called at both ends of every cell and bisected to the last bit; the first candidate whose
/// residual is at most 1e-13 max|q| taken, else the one with the smallest residual. A reference
/// for [`cone_local_solve_is_unchanged_to_the_bit_by_the_tabulated_grid`].
fn direct_grid_cone_solve(a: &SMatrix<f64, 3, 3>, q: &SVector<f64, 3>, mu: f64) -> SVector<f64, 3> {
    use rigidref::solve::residual::{RowScales, contact_residual};
    let scales = RowScales::of_block(*a);
    let tolerance = 1e-13 * q.amax().max(f64::MIN_POSITIVE);
    let mut best: Option<(f64, SVector<f64, 3>)> = None;
    let mut consider = |lambda: SVector<f64, 3>| {
        let r = contact_residual(FrictionModel::Cone, mu, &lambda, &(a * lambda + q), &scales);
        if best.is_none_or(|(b, _)| r < b) {
            best = Some((r, lambda));
        }
        r <= tolerance
    };
    if consider(SVector::zeros()) {
        return SVector::zeros();
    }
    if let Some(lambda) = eliminate(a, &(-q))
        && consider(lambda)
    {
        return lambda;
    }
    let g = |t: f64| SVector::<f64, 3>::new(1.0, -mu * t.cos(), -mu * t.sin());
    let f = |t: f64| {
        let ag = a * g(t);
        (ag[0] * q[1] - q[0] * ag[1]) * t.sin() - (ag[0] * q[2] - q[0] * ag[2]) * t.cos()
    };
    let step = std::f64::consts::TAU / 256.0;
    for i in 0..256 {
        let (mut lo, mut hi) = (i as f64 * step, (i + 1) as f64 * step);
        let (mut f_lo, f_hi) = (f(lo), f(hi));
        if f_lo != 0.0 {
            if f_lo * f_hi >= 0.0 {
                continue;
            }
            loop {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                let f_mid = f(mid);
                if f_mid == 0.0 {
                    lo = mid;
                    break;
                }
                if f_lo * f_mid < 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                    f_lo = f_mid;
                }
            }
        }
        let normal = (a * g(lo))[0];
        if normal <= 0.0 || -q[0] / normal <= 0.0 {
            continue;
        }
        if consider(g(lo) * (-q[0] / normal)) {
            return g(lo) * (-q[0] / normal);
        }
    }
    best.map_or(SVector::zeros(), |(_, lambda)| lambda)
}

/// Gaussian elimination with partial pivoting, as the exact local solve's stick case does it.
fn eliminate(m: &SMatrix<f64, 3, 3>, rhs: &SVector<f64, 3>) -> Option<SVector<f64, 3>> {
    let (mut m, mut x) = (*m, *rhs);
    let tiny = 1e-14 * m.amax();
    for col in 0..3 {
        let pivot = (col..3).max_by(|&i, &j| m[(i, col)].abs().total_cmp(&m[(j, col)].abs()))?;
        if m[(pivot, col)].abs() <= tiny || m[(pivot, col)].is_nan() {
            return None;
        }
        m.swap_rows(col, pivot);
        x.swap_rows(col, pivot);
        for row in col + 1..3 {
            let factor = m[(row, col)] / m[(col, col)];
            for c in col..3 {
                m[(row, c)] -= factor * m[(col, c)];
            }
            x[row] -= factor * x[col];
        }
    }
    for row in (0..3).rev() {
        let mut sum = x[row];
        for c in row + 1..3 {
            sum -= m[(row, c)] * x[c];
        }
        x[row] = sum / m[(row, row)];
    }
    Some(x)
}

#[test]
fn cone_local_solve_is_unchanged_to_the_bit_by_the_tabulated_grid() {
    // Bitwise: the tabulated cos and sin are the values the direct calls return at the same grid
    // points, and each grid value of F is computed by the same expression, so every bracket,
    // bisection and candidate is the same; only the number of `sin`/`cos` calls changes.
    let slides = Cell::new(0u32);
    proptest!(common::seeded(2000), |(a in spd::<3>(), b in rhs::<3>(), mu in 0.0..2.0f64)| {
        let scales = rigidref::solve::residual::RowScales::of_block(a);
        let (lambda, _) =
            rigidref::solve::local::solve_local(&a, &b, mu, FrictionModel::Cone, &scales, None);
        let reference = direct_grid_cone_solve(&a, &b, mu);
        let tangent = lambda[1].hypot(lambda[2]);
        if lambda[0] > 0.0 && tangent >= mu * lambda[0] * (1.0 - 1e-12) && mu > 0.0 {
            slides.set(slides.get() + 1);
        }
        prop_assert_eq!(lambda, reference, "A {} q {} μ {}", a, b, mu);
    });
    // The property must exercise the sliding path, not only separation and sticking.
    assert!(slides.get() >= 200, "only {} sliding cases", slides.get());
    println!("{} of 2000 cases slide", slides.get());
}

/// The accepted sliding roots of the disk's scan for (A, q, μ): the candidates of
/// `disk_slides` whose contact residual is at most 1e-13 max|q| (the exact local solve's
/// acceptance).
fn accepted_scan_roots(
    a: &SMatrix<f64, 3, 3>,
    q: &SVector<f64, 3>,
    mu: f64,
) -> Vec<SVector<f64, 3>> {
    use rigidref::solve::residual::{RowScales, contact_residual};
    let scales = RowScales::of_block(*a);
    let tolerance = 1e-13 * q.amax().max(f64::MIN_POSITIVE);
    rigidref::solve::local::disk_slides(a, q, mu)
        .filter(|l| {
            contact_residual(FrictionModel::Cone, mu, l, &(a * l + q), &scales) <= tolerance
        })
        .collect()
}

/// The impulse λn g(θ) of a contact sliding along θ with normal impulse `lambda_n` and friction
/// coefficient μ: λt = −μλn (cos θ, sin θ).
fn sliding_impulse(lambda_n: f64, mu: f64, theta: f64) -> SVector<f64, 3> {
    SVector::<f64, 3>::new(
        lambda_n,
        -mu * lambda_n * theta.cos(),
        -mu * lambda_n * theta.sin(),
    )
}

#[test]
fn the_warm_started_slide_is_exact_and_agrees_with_a_lone_scan_root() {
    // Random cone contacts, each solved from a warm start within 0.3 rad of the scan's
    // sliding root (the PGS case: a contact that slid last sweep slides nearly the same way).
    // Where the scan's answer is its one accepted sliding root, the warm-started solve must take
    // the Newton root (the fast path, not the scan behind it), which must pass the same residual
    // and agree with the scan's root to 1e-12 relative: both are F's root to round-off, the
    // scan's by bisection to the last bit, Newton's by steps to below 1e-9 rad (so the next step
    // would be ~1e-18 rad), each off by about ε |F's terms| / |F'| in angle, ~1e-15 on these
    // well-scaled blocks; 1e-12 leaves room for roots where F' is small. Where the scan's answer
    // is separation or sticking, the warm start must change nothing: bit for bit the same λ.
    use rigidref::solve::local::{disk_slide_from, solve_local};
    use rigidref::solve::residual::RowScales;
    let (lone, earlier, worst) = (Cell::new(0u32), Cell::new(0u32), Cell::new(0.0f64));
    let missed = Cell::new(0u32);
    proptest!(common::seeded(4000), |(
        a in spd::<3>(), b in rhs::<3>(), mu in 0.05..2.0f64,
        turn in -0.3..0.3f64, warm_n in 0.01..3.0f64,
    )| {
        let scales = RowScales::of_block(a);
        let (scan, scan_exact) = solve_local(&a, &b, mu, FrictionModel::Cone, &scales, None);
        let roots = accepted_scan_roots(&a, &b, mu);
        let slides = scan_exact && roots.first() == Some(&scan);
        if !slides {
            // Separation, sticking, or a fallback: the warm start is never read before the
            // slide, and a fallback's scan is the same; any warm start gives the same bits.
            let warm = sliding_impulse(warm_n, mu, turn);
            let (lambda, exact) = solve_local(&a, &b, mu, FrictionModel::Cone, &scales, Some(&warm));
            if scan_exact {
                earlier.set(earlier.get() + 1);
                prop_assert_eq!(lambda, scan);
                prop_assert!(exact);
            } else {
                // No scan candidate accepted: the warm start may find an exact root the grid
                // missed, never lose one.
                prop_assert!(exact || lambda == scan);
            }
            return Ok(());
        }
        if roots.len() != 1 {
            return Ok(());
        }
        lone.set(lone.get() + 1);
        let theta = (-scan[2]).atan2(-scan[1]);
        let warm = sliding_impulse(warm_n, mu, theta + turn);
        let fast = disk_slide_from(&a, &b, mu, &warm);
        let (lambda, exact) = solve_local(&a, &b, mu, FrictionModel::Cone, &scales, Some(&warm));
        prop_assert!(exact);
        if fast != Some(lambda) {
            // Newton went elsewhere (or nowhere) and the scan answered.
            missed.set(missed.get() + 1);
        }
        let relative = (lambda - scan).amax() / scan.amax();
        worst.set(worst.get().max(relative));
        prop_assert!(relative <= 1e-12, "{relative:e}: A {} q {} μ {}", a, b, mu);
    });
    println!(
        "{} lone sliding roots ({} answered by the scan), worst relative difference {:.1e}; {} separate or stick",
        lone.get(),
        missed.get(),
        worst.get(),
        earlier.get()
    );
    // The property must exercise the fast path often, and the fast path must take it: from
    // within 0.3 rad Newton reaches the root in all but a few cases (4 of 884 when written:
    // starts beyond a nearby extremum of F, where Newton heads away), which the scan answers.
    assert!(lone.get() >= 400, "only {} lone sliding roots", lone.get());
    assert!(
        missed.get() * 100 <= lone.get(),
        "{} of {} answered by the scan",
        missed.get(),
        lone.get()
    );
}

#[test]
fn a_useless_warm_start_still_gives_the_exact_slide_by_the_scan() {
    use rigidref::solve::local::{disk_slide_from, solve_local};
    use rigidref::solve::residual::RowScales;
    // The coupled contact of `row_by_row_pgs_cycles_on_a_coupled_contact_and_the_exact_solve_does_not`:
    // its one solution slides along θ = π, λ = (½, 1, 0). A warm start sliding along θ = 0 (the
    // wrong way) sits on a root of F where (A g)_n = 1 − μ·½ = 0: no candidate, so the scan runs.
    let a = SMatrix::<f64, 3, 3>::new(1.0, 0.5, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0, 1.0);
    let b = SVector::<f64, 3>::new(-1.0, -2.0, 0.0);
    let scales = RowScales::of_block(a);
    let wrong = sliding_impulse(1.0, 2.0, 0.0);
    assert_eq!(disk_slide_from(&a, &b, 2.0, &wrong), None);
    let expected = SVector::<f64, 3>::new(0.5, 1.0, 0.0);
    for warm in [Some(wrong), Some(SVector::zeros()), None] {
        let (lambda, exact) = solve_local(&a, &b, 2.0, FrictionModel::Cone, &scales, warm.as_ref());
        assert!(exact, "{warm:?}");
        assert!((lambda - expected).amax() < 1e-15, "{warm:?}: {lambda:?}");
    }
    // λ_now = 0 and q_t = 0: no direction to start from at all.
    let b = SVector::<f64, 3>::new(-1.0, 0.0, 0.0);
    assert_eq!(disk_slide_from(&a, &b, 0.5, &SVector::zeros()), None);

    // Random contacts warm started the opposite way from the scan's lone sliding root: whatever
    // Newton finds there (the root, another root, a root with w_t along −d that the residual
    // rejects, or nothing), the answer is exact and, the root being the only accepted one, the
    // scan's to 1e-12 relative (the tolerance of
    // `the_warm_started_slide_is_exact_and_agrees_with_a_lone_scan_root`).
    let (cases, rescued) = (Cell::new(0u32), Cell::new(0u32));
    proptest!(common::seeded(2000), |(a in spd::<3>(), b in rhs::<3>(), mu in 0.05..2.0f64)| {
        let scales = RowScales::of_block(a);
        let (scan, scan_exact) = solve_local(&a, &b, mu, FrictionModel::Cone, &scales, None);
        let roots = accepted_scan_roots(&a, &b, mu);
        if !(scan_exact && roots.len() == 1 && roots[0] == scan) {
            return Ok(());
        }
        cases.set(cases.get() + 1);
        let theta = (-scan[2]).atan2(-scan[1]) + std::f64::consts::PI;
        let warm = sliding_impulse(1.0, mu, theta);
        let fast = disk_slide_from(&a, &b, mu, &warm);
        let (lambda, exact) = solve_local(&a, &b, mu, FrictionModel::Cone, &scales, Some(&warm));
        if fast != Some(lambda) {
            rescued.set(rescued.get() + 1);
        }
        prop_assert!(exact);
        prop_assert!((lambda - scan).amax() <= 1e-12 * scan.amax(), "{:?} vs {:?}", lambda, scan);
    });
    // When written: 462 cases, every one answered by the scan (Newton from the opposite
    // direction finds a root with w_t along −d, or none).
    println!(
        "{} lone sliding roots warm started the wrong way, {} answered by the scan",
        cases.get(),
        rescued.get()
    );
    // The fallback must be exercised, not only Newton finding its way round.
    assert!(
        rescued.get() >= 20,
        "only {} answered by the scan",
        rescued.get()
    );
}

/// NSGS written out on a 3D local problem: `sweeps` sweeps in problem order from λ = 0, contact
/// k's local q = w_k − W_kk λ_k solved by `solve_local`, warm started from λ_k or not (the scan
/// alone, the solve as it was before the warm start). Returns the visits that took the best
/// candidate (fallbacks) and the visits whose answer slides (λn > 0, ‖λt‖ = μλn to 1e-12).
fn nsgs_by_hand(
    problem: &rigidref::problem::LocalProblem<3>,
    sweeps: u32,
    warm: bool,
) -> (u32, u32) {
    use rigidref::solve::local::solve_local;
    use rigidref::solve::residual::RowScales;
    let count = problem.contacts.len();
    let mut lambda = vec![SVector::<f64, 3>::zeros(); count];
    let (mut fallbacks, mut slides) = (0, 0);
    for _ in 0..sweeps {
        for k in 0..count {
            let contact = &problem.contacts[k];
            let block = *problem.diagonal_block(k);
            let mut w = contact.q;
            for (j, w_kj) in &contact.row {
                w += w_kj * lambda[*j];
            }
            let q = w - block * lambda[k];
            let scales = RowScales::of_block(block);
            let start = lambda[k];
            let (solution, exact) = solve_local(
                &block,
                &q,
                contact.mu,
                problem.friction,
                &scales,
                warm.then_some(&start),
            );
            fallbacks += u32::from(!exact);
            let tangent = solution[1].hypot(solution[2]);
            if solution[0] > 0.0
                && contact.mu > 0.0
                && tangent >= contact.mu * solution[0] * (1.0 - 1e-12)
            {
                slides += 1;
            }
            lambda[k] = solution;
        }
    }
    (fallbacks, slides)
}

#[test]
fn the_warm_start_leaves_the_count_of_fallbacks_unchanged() {
    // Siconos' 3D test problems kept in tests/data (and, with FCLIB, spheres-in-a-box-98, where
    // most visits slide), 200 NSGS sweeps each with and without the warm start: the visits that
    // found no exact case are the same number. The warm start only adds a candidate before the
    // scan; a visit falls back with it only where Newton's root is rejected and the scan finds
    // nothing either, which is where it fell back without it.
    use rigidref::problem::siconos::{AnyLocalProblem, read_dat};
    let root = common::project_root().join("tests/data");
    let mut problems = Vec::new();
    for name in [
        "siconos/Confeti-ex13-4contact-Fc3D-SBM.dat",
        "siconos/FC3D_Example1.dat",
        "siconos/NESpheres_10_1.dat",
        "siconos/Rover4144.dat",
        "siconos/Rover9770.dat",
        "siconos_hard/BoxesStack1-i100000-32.hdf5.dat",
    ] {
        if let AnyLocalProblem::Three(p) = read_dat(&root.join(name)).unwrap() {
            problems.push((name, p));
        }
    }
    #[cfg(feature = "fclib")]
    {
        let name = "siconos_hard/spheres-in-a-box-98-i10000-256-10.hdf5";
        let path = root.join(name);
        if let AnyLocalProblem::Three(p) =
            rigidref::tools::experiments::problem_library::load(&path).unwrap()
        {
            problems.push((name, p));
        }
    }
    // No visit of these problems falls back (nor of any 3D problem of Siconos' test folder up to
    // 600 contacts in 100 sweeps, checked when this was written), so each gets one more contact
    // that falls back at every visit: a pinned body approaching (W_kk = 0, coupled to nothing)
    // and sliding, q = (−1, 0.5, 0.2) m/s, whose Newton start (along q_t) finds F ≡ 0.
    let mut all_slides = 0;
    for (name, problem) in &mut problems {
        let k = problem.contacts.len();
        problem.contacts.push(rigidref::problem::LocalContact {
            row: vec![(k, SMatrix::zeros())],
            q: SVector::<f64, 3>::new(-1.0, 0.5, 0.2),
            mu: 0.5,
            lambda0: SVector::zeros(),
            bounds: RowBounds::Contact,
        });
        let (scan_fallbacks, scan_slides) = nsgs_by_hand(problem, 200, false);
        let (warm_fallbacks, warm_slides) = nsgs_by_hand(problem, 200, true);
        println!(
            "{name}: {} contacts, fallbacks {scan_fallbacks} (scan) {warm_fallbacks} (warm), sliding visits {scan_slides} {warm_slides}",
            problem.contacts.len()
        );
        assert_eq!(warm_fallbacks, scan_fallbacks, "{name}");
        assert_eq!(
            warm_fallbacks, 200,
            "{name}: the pinned contact's visits, and only those"
        );
        all_slides += warm_slides;
    }
    // The fast path must have run: visits that slide are where it answers.
    assert!(all_slides >= 1000, "only {all_slides} sliding visits");
}
