//! What the checks read of a contact problem, in either form: the body form
//! ([`ContactProblem`]: bodies, Jacobian, b) or the local form ([`LocalProblem`]: W, q). The
//! residuals, the physical criteria, clarabel's convex program and the cross-check are written
//! once against this trait, so that a problem from a run and one from FCLIB are judged by the
//! same code. docs/contact.md §"The local form".

use super::{ContactProblem, FrictionModel, LocalProblem, RowBounds};
use nalgebra::{DMatrix, DVector, SMatrix, SVector};

/// A contact problem as the checks see it: per constraint its law and its diagonal block, and
/// the constraint velocity w = (A + C) λ + b of given impulses.
pub trait ProblemView<const R: usize> {
    /// How friction rows are bounded.
    fn friction(&self) -> FrictionModel;
    /// Constraints (contacts and joints).
    fn count(&self) -> usize;
    /// μ of constraint `k`.
    fn mu(&self, k: usize) -> f64;
    /// How constraint `k`'s rows are bounded.
    fn bounds(&self, k: usize) -> RowBounds;
    /// Constraint `k`'s warm start, N·s.
    fn lambda0(&self, k: usize) -> SVector<f64, R>;
    /// The diagonal block (A + C)_kk, kg⁻¹ (the exact local solve's matrix).
    fn block(&self, k: usize) -> SMatrix<f64, R, R>;
    /// w = (A + C) λ + b per constraint, m/s.
    fn constraint_velocity(&self, lambda: &[SVector<f64, R>]) -> Vec<SVector<f64, R>>;
    /// The dense A + C (R·count square), kg⁻¹.
    fn dense_operator(&self) -> DMatrix<f64>;
    /// The stacked b (q in the local form), m/s.
    fn dense_b(&self) -> DVector<f64>;
    /// What the impulses do, for comparing two answers whose λ may differ where the solution is
    /// not unique: each body's velocity change M⁻¹Jᵀλ (body form; m/s and rad/s) or each
    /// constraint's velocity w (local form, m/s), flattened.
    fn outcome(&self, lambda: &[SVector<f64, R>]) -> Vec<f64>;
    /// Checks the problem is well formed.
    fn validate(&self) -> Result<(), String>;
}

impl<const D: usize, const R: usize> ProblemView<R> for ContactProblem<D, R> {
    fn friction(&self) -> FrictionModel {
        self.friction
    }
    fn count(&self) -> usize {
        self.contacts.len()
    }
    fn mu(&self, k: usize) -> f64 {
        self.contacts[k].mu
    }
    fn bounds(&self, k: usize) -> RowBounds {
        self.contacts[k].bounds
    }
    fn lambda0(&self, k: usize) -> SVector<f64, R> {
        self.contacts[k].lambda0
    }
    fn block(&self, k: usize) -> SMatrix<f64, R, R> {
        let mut block = self.delassus_block(k);
        for r in 0..R {
            block[(r, r)] += self.contacts[k].row_compliance(r);
        }
        block
    }
    fn constraint_velocity(&self, lambda: &[SVector<f64, R>]) -> Vec<SVector<f64, R>> {
        ContactProblem::constraint_velocity(self, lambda)
    }
    fn dense_operator(&self) -> DMatrix<f64> {
        self.dense_delassus() + self.dense_compliance()
    }
    fn dense_b(&self) -> DVector<f64> {
        ContactProblem::dense_b(self)
    }
    fn outcome(&self, lambda: &[SVector<f64, R>]) -> Vec<f64> {
        self.velocity_change(lambda)
            .iter()
            .flat_map(|d| d.iter().copied())
            .collect()
    }
    fn validate(&self) -> Result<(), String> {
        ContactProblem::validate(self)
    }
}

impl<const R: usize> ProblemView<R> for LocalProblem<R> {
    fn friction(&self) -> FrictionModel {
        self.friction
    }
    fn count(&self) -> usize {
        self.contacts.len()
    }
    fn mu(&self, k: usize) -> f64 {
        self.contacts[k].mu
    }
    fn bounds(&self, k: usize) -> RowBounds {
        self.contacts[k].bounds
    }
    fn lambda0(&self, k: usize) -> SVector<f64, R> {
        self.contacts[k].lambda0
    }
    fn block(&self, k: usize) -> SMatrix<f64, R, R> {
        *self.diagonal_block(k)
    }
    fn constraint_velocity(&self, lambda: &[SVector<f64, R>]) -> Vec<SVector<f64, R>> {
        self.velocity(lambda)
    }
    fn dense_operator(&self) -> DMatrix<f64> {
        self.dense_w()
    }
    fn dense_b(&self) -> DVector<f64> {
        self.dense_q()
    }
    fn outcome(&self, lambda: &[SVector<f64, R>]) -> Vec<f64> {
        self.velocity(lambda)
            .iter()
            .flat_map(|w| w.iter().copied())
            .collect()
    }
    fn validate(&self) -> Result<(), String> {
        LocalProblem::validate(self)
    }
}
