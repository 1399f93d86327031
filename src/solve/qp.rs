//! The contact problem as a convex program, solved by clarabel (an interior-point solver that
//! shares no code or method with PGS): the independent check of [`super::pgs`]'s and
//! [`super::newton`]'s answers. Without friction it solves the problem on its own; with friction
//! its bounds are frozen at the answer's normal impulses, so it checks the answer rather than
//! solving the frictional problem independently (the Newton solver does that).
//! docs/verification.md §"clarabel", derivations in docs/contact.md §"Convex formulations".
//!
//! Every formulation minimises the same objective, whose optimality conditions are the contact
//! problem's complementarity conditions:
//!
//!   f(λ) = ½ λᵀ (A + C) λ + bᵀ λ,   ∇f = (A + C) λ + b = w,
//!
//! over a convex set that depends on the friction model:
//!
//! - [`QpFormulation::Frictionless`]: λn ≥ 0, λt = 0 (μ = 0: the LCP 0 ≤ λn ⊥ w_n ≥ 0);
//! - [`QpFormulation::BoxFixed`]: λn ≥ 0, |λt_r| ≤ μ λ̄n with λ̄n given (PGS's own λn): box
//!   friction's bounds depend on the unknown λn, so the problem is not convex; with the bounds
//!   frozen at PGS's answer it is, and PGS's answer must be its minimiser (a fixed-point check);
//! - [`QpFormulation::ConeFixed`]: λn ≥ 0, ‖λt‖ ≤ μ λ̄n: the same for the disk;
//! - [`QpFormulation::Cone`]: (λn, λt) in the second-order cone ‖λt‖ ≤ μ λn: Anitescu's convex
//!   relaxation of Coulomb friction, a true convex program with no frozen data. It agrees with
//!   PGS's disk projection when no contact slides; a sliding contact gets a normal velocity
//!   w_n = μ ‖w_t‖ > 0 from it (the relaxation's spurious separation) and 0 from PGS.
//!
//! A joint's rows ([`RowBounds::Free`]) are in none of these sets: free variables of the same
//! objective, whose optimality condition is w_r = 0.

use crate::problem::{ProblemView, RowBounds};
use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};
use nalgebra::SVector;

/// Which convex program to pose (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub enum QpFormulation {
    /// λn ≥ 0, friction rows fixed at zero.
    Frictionless,
    /// λn ≥ 0, |λt_r| ≤ μ λ̄n\[k\] per friction row, λ̄n given per contact (N·s).
    BoxFixed(Vec<f64>),
    /// λn ≥ 0, ‖λt‖ ≤ μ λ̄n\[k\], λ̄n given per contact (N·s).
    ConeFixed(Vec<f64>),
    /// ‖λt‖ ≤ μ λn (second-order cone; Anitescu's relaxation).
    Cone,
}

impl QpFormulation {
    /// A short name for reports.
    pub fn name(&self) -> &'static str {
        match self {
            QpFormulation::Frictionless => "frictionless QP",
            QpFormulation::BoxFixed(_) => "box QP, bounds fixed at PGS's λn",
            QpFormulation::ConeFixed(_) => "SOCP, disks fixed at PGS's λn",
            QpFormulation::Cone => "SOCP, Anitescu cone",
        }
    }
}

/// What clarabel returned.
#[derive(Clone, Debug, PartialEq)]
pub struct QpSolution<const R: usize> {
    /// λ per contact, N·s.
    pub lambda: Vec<SVector<f64, R>>,
    /// f(λ) at clarabel's λ, J-like units (N·s · m/s).
    pub objective: f64,
    /// clarabel's status, e.g. `Solved`.
    pub status: String,
    /// Whether the status is `Solved` or `AlmostSolved`.
    pub solved: bool,
    /// Interior-point iterations.
    pub iterations: u32,
}

/// Settings of the clarabel solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QpSettings {
    /// Duality-gap and feasibility tolerance (absolute and relative), passed to clarabel.
    pub tolerance: f64,
    /// Interior-point iterations at most.
    pub max_iterations: u32,
}

impl Default for QpSettings {
    /// 1e-10 (on the scaled problem): measured over 3000 random problems, the tightest
    /// tolerance clarabel reaches cleanly on nearly all (4 reported reduced accuracy; 1e-11: 91,
    /// 1e-12: 381), with λ within 4e-6 of PGS's converged answer.
    fn default() -> Self {
        QpSettings {
            tolerance: 1e-10,
            max_iterations: 200,
        }
    }
}

/// f(λ) = ½ λᵀ(A + C)λ + bᵀλ = ½ λ·(w + b), computed through the bodies (or W).
pub fn objective<const R: usize, P: ProblemView<R> + ?Sized>(
    problem: &P,
    lambda: &[SVector<f64, R>],
) -> f64 {
    let w = problem.constraint_velocity(lambda);
    let b = problem.dense_b();
    lambda
        .iter()
        .zip(&w)
        .enumerate()
        .map(|(k, (l, w))| 0.5 * l.dot(&(w + b.fixed_rows::<R>(R * k))))
        .sum()
}

/// The variable scaling λ = S x of [`solve_qp`]: S = diag(1/√P_ii), so that Sᵀ P S has a unit
/// diagonal; a row with P_ii = 0 (no impulse can move that constraint) is left unscaled (1).
pub fn diagonal_scaling(p: &nalgebra::DMatrix<f64>) -> Vec<f64> {
    (0..p.nrows())
        .map(|i| {
            if p[(i, i)] > 0.0 {
                1.0 / p[(i, i)].sqrt()
            } else {
                1.0
            }
        })
        .collect()
}

/// Solves `problem` in the given formulation with clarabel. Errors only for malformed input
/// (a fixed-bound list of the wrong length) or a clarabel set-up failure; a solve that does not
/// reach `Solved` is reported in the status, not as an error.
pub fn solve_qp<const R: usize, P: ProblemView<R> + ?Sized>(
    problem: &P,
    formulation: &QpFormulation,
    settings: &QpSettings,
) -> Result<QpSolution<R>, String> {
    let k_count = problem.count();
    let n = R * k_count;
    if let QpFormulation::BoxFixed(fixed) | QpFormulation::ConeFixed(fixed) = formulation
        && fixed.len() != k_count
    {
        return Err(format!(
            "{} fixed normal impulses for {k_count} contacts",
            fixed.len()
        ));
    }
    // No contacts: nothing to solve (clarabel's factorisation indexes into an empty matrix).
    if k_count == 0 {
        return Ok(QpSolution {
            lambda: Vec::new(),
            objective: 0.0,
            status: "Solved".into(),
            solved: true,
            iterations: 0,
        });
    }
    // Objective: P = A + C (clarabel keeps the upper triangle), q = b, in scaled variables
    // λ = S x with S = diag(1/√P_ii): P's diagonal becomes 1, so clarabel's absolute
    // tolerances mean the same for a 1 kg body and a 10 t one.
    let p_dense = problem.dense_operator();
    let scale = diagonal_scaling(&p_dense);
    let (mut pi, mut pj, mut pv) = (Vec::new(), Vec::new(), Vec::new());
    for j in 0..n {
        for i in 0..=j {
            let v = 0.5 * (p_dense[(i, j)] + p_dense[(j, i)]) * scale[i] * scale[j];
            if v != 0.0 {
                pi.push(i);
                pj.push(j);
                pv.push(v);
            }
        }
    }
    let p = CscMatrix::new_from_triplets(n, n, pi, pj, pv);
    let q: Vec<f64> = problem
        .dense_b()
        .iter()
        .zip(&scale)
        .map(|(b, s)| b * s)
        .collect();

    // Constraints A x + s = b_c, s in the cones, rows grouped by cone in clarabel's order.
    let mut rows = ConstraintRows::default();
    // A joint's rows (free bounds) are in no cone: unconstrained variables of the objective.
    let contacts = || (0..k_count).filter(|&k| problem.bounds(k) == RowBounds::Contact);
    if *formulation == QpFormulation::Frictionless {
        // Zero cone: λt = 0.
        for k in contacts() {
            for r in 1..R {
                rows.row(&[(R * k + r, 1.0)], 0.0);
            }
        }
        rows.close_cone(SupportedConeT::ZeroConeT);
    }
    // Non-negative cone: s = λn ≥ 0 (for the Anitescu cone too: with μ = 0 the cone alone would
    // leave λn free), and for fixed box bounds s = μλ̄n ∓ λt ≥ 0.
    for k in contacts() {
        rows.row(&[(R * k, -1.0)], 0.0);
    }
    if let QpFormulation::BoxFixed(fixed) = formulation {
        for k in contacts() {
            let bound = problem.mu(k) * fixed[k].max(0.0);
            for r in 1..R {
                rows.row(&[(R * k + r, 1.0)], bound);
                rows.row(&[(R * k + r, -1.0)], bound);
            }
        }
    }
    rows.close_cone(SupportedConeT::NonnegativeConeT);
    // Second-order cones, one per contact: s = (radius, λt), radius μλ̄n (fixed) or μλn.
    if matches!(
        formulation,
        QpFormulation::ConeFixed(_) | QpFormulation::Cone
    ) {
        for k in contacts() {
            match formulation {
                QpFormulation::ConeFixed(fixed) => rows.row(&[], problem.mu(k) * fixed[k].max(0.0)),
                _ => rows.row(&[(R * k, -problem.mu(k))], 0.0),
            }
            for r in 1..R {
                rows.row(&[(R * k + r, -1.0)], 0.0);
            }
            rows.close_cone(SupportedConeT::SecondOrderConeT);
        }
    }
    // Constraint coefficients act on λ = S x.
    let scaled: Vec<f64> = rows
        .v
        .iter()
        .zip(&rows.j)
        .map(|(v, &j)| v * scale[j])
        .collect();
    let a = CscMatrix::new_from_triplets(rows.b.len(), n, rows.i, rows.j, scaled);
    let (bc, cones) = (rows.b, rows.cones);

    let mut s = DefaultSettings::<f64> {
        verbose: false,
        max_iter: settings.max_iterations,
        tol_gap_abs: settings.tolerance,
        tol_gap_rel: settings.tolerance,
        tol_feas: settings.tolerance,
        ..DefaultSettings::default()
    };
    // Presolve may drop rows it finds redundant; keep the problem as posed.
    s.presolve_enable = false;
    let mut solver = DefaultSolver::new(&p, &q, &a, &bc, &cones, s)
        .map_err(|e| format!("clarabel set-up failed: {e:?}"))?;
    solver.solve();
    let x = &solver.solution.x;
    let lambda: Vec<SVector<f64, R>> = (0..k_count)
        .map(|k| SVector::<f64, R>::from_fn(|r, _| x[R * k + r] * scale[R * k + r]))
        .collect();
    let status = solver.solution.status;
    Ok(QpSolution {
        objective: objective(problem, &lambda),
        lambda,
        status: format!("{status:?}"),
        solved: matches!(status, SolverStatus::Solved | SolverStatus::AlmostSolved),
        iterations: solver.solution.iterations,
    })
}

/// Constraint rows of A x + s = b being built, grouped into cones.
#[derive(Default)]
struct ConstraintRows {
    i: Vec<usize>,
    j: Vec<usize>,
    v: Vec<f64>,
    b: Vec<f64>,
    cones: Vec<SupportedConeT<f64>>,
    cone_start: usize,
}

impl ConstraintRows {
    /// Appends a row with the given (column, coefficient) entries and right-hand side.
    fn row(&mut self, entries: &[(usize, f64)], rhs: f64) {
        let r = self.b.len();
        for &(col, coefficient) in entries {
            self.i.push(r);
            self.j.push(col);
            self.v.push(coefficient);
        }
        self.b.push(rhs);
    }

    /// Makes the rows since the last cone into one cone of the given kind (none if empty).
    fn close_cone(&mut self, cone: fn(usize) -> SupportedConeT<f64>) {
        let dimension = self.b.len() - self.cone_start;
        if dimension > 0 {
            self.cones.push(cone(dimension));
        }
        self.cone_start = self.b.len();
    }
}
