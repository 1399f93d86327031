//! The contact problem: plain data, the one interface between collision/dynamics and every
//! solver (our PGS, clarabel, and any external solver through its JSON file).
//! docs/contact-problem-format.md; the mathematics in docs/contact.md §"The contact problem".
//!
//! Generic over `D`, the degrees of freedom per body (6 in 3D: v, ω; 3 in 2D: vx, vy, ω), and
//! `R`, the constraint rows per contact (3 in 3D: n, t1, t2; 2 in 2D: n, t). For a contact, row 0
//! is the normal row and rows 1..R are friction rows. A constraint's [`RowBounds`] say how its
//! rows are bounded: a contact's as below, a joint's (a bilateral constraint, e.g. a 2D pin with
//! rows x and y) not at all, so that one PGS solves contacts and joints together
//! (docs/contact.md §"Row bounds").
//!
//! With u the bodies' velocities before contact (stacked), J the contact Jacobian (stacked rows)
//! and M⁻¹ the block-diagonal inverse mass, the problem is: find impulses λ (N·s) with
//!
//!   w = (A + C) λ + b,   A = J M⁻¹ Jᵀ (Delassus operator),   b = J u − bias,
//!
//! where w is the constraint-space velocity after the impulses (m/s), C is diagonal with each
//! contact's compliance on its normal row, and for each contact
//!   0 ≤ λn ⊥ wn ≥ 0                       (non-penetration, no glue),
//!   box friction:  |λt_k| ≤ μ λn, each row a clamp complementarity with w_t_k,
//!   cone friction: ‖λt‖ ≤ μ λn and λt = proj_disk(λt − s w_t) (maximal dissipation in the disk).
//! The bodies' velocities afterwards are u⁺ = u + M⁻¹ Jᵀ λ.

use nalgebra::{DMatrix, SMatrix, SVector};
use serde::{Deserialize, Serialize};

/// How the friction rows are bounded.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum FrictionModel {
    /// Each friction row separately in [−μ λn, μ λn] (the assignment's model; a pyramid).
    #[default]
    Box,
    /// The friction rows together in the disk ‖λt‖ ≤ μ λn, with maximal dissipation in it: at a
    /// fixed point, the exact Coulomb law (a non-convex problem; clarabel's SOCP
    /// `QpFormulation::Cone` is Anitescu's convex relaxation of it, docs/contact.md §"Which
    /// problem each solver answers").
    Cone,
}

impl FrictionModel {
    /// The scene-file spelling.
    pub fn name(self) -> &'static str {
        match self {
            FrictionModel::Box => "box",
            FrictionModel::Cone => "cone",
        }
    }
}

/// How a constraint's rows are bounded. docs/contact.md §"Row bounds".
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RowBounds {
    /// A contact: the normal row λn ∈ [0, ∞), the friction rows within μ λn (box or disk, the
    /// problem's [`FrictionModel`]); compliance on the normal row.
    #[default]
    Contact,
    /// A bilateral constraint (a joint): every row λ_r ∈ (−∞, ∞), w_r = 0 wanted; μ unused;
    /// compliance on every row.
    Free,
}

impl RowBounds {
    /// The problem-file spelling.
    pub fn name(self) -> &'static str {
        match self {
            RowBounds::Contact => "contact",
            RowBounds::Free => "free",
        }
    }
}

/// One body as the solver sees it.
#[derive(Clone, Debug, PartialEq)]
pub struct ProblemBody<const D: usize> {
    /// Generalised inverse mass M⁻¹ in world coordinates (3D: diag(m⁻¹ I₃, J⁻¹), kg⁻¹ and
    /// (kg·m²)⁻¹). All zero for a pinned body.
    pub inverse_mass: SMatrix<f64, D, D>,
    /// Generalised velocity u before contact (3D: v in m/s, ω in rad/s).
    pub velocity: SVector<f64, D>,
}

/// One contact as the solver sees it.
#[derive(Clone, Debug, PartialEq)]
pub struct ProblemContact<const D: usize, const R: usize> {
    /// Indices into [`ContactProblem::bodies`] of body 1 and body 2; `None` is the static world
    /// (the ground). The normal points from body 2 into body 1.
    pub bodies: [Option<usize>; 2],
    /// The Jacobian blocks J₁ and J₂ (R × D): rows · u = relative velocity along n, t1, t2.
    /// J₂ is zero when body 2 is `None`.
    pub jacobian: [SMatrix<f64, R, D>; 2],
    /// b = J u − bias, m/s (the bias is the stabilisation term on the normal row).
    pub b: SVector<f64, R>,
    /// Friction coefficient μ (dimensionless).
    pub mu: f64,
    /// Compliance c ≥ 0 on the normal row (kg⁻¹): w_n gains c λn (constraint force mixing).
    pub compliance: f64,
    /// Initial guess for λ (warm start), N·s; zero when cold.
    pub lambda0: SVector<f64, R>,
    /// How the rows are bounded: a contact's (the default) or free (a joint).
    pub bounds: RowBounds,
}

impl<const D: usize, const R: usize> ProblemContact<D, R> {
    /// The compliance on row `r` (kg⁻¹): a contact's on its normal row only, a joint's on every
    /// row.
    pub fn row_compliance(&self, r: usize) -> f64 {
        self.bounds.row_compliance(self.compliance, r)
    }
}

impl RowBounds {
    /// The compliance on row `r` (kg⁻¹) of a constraint so bounded whose compliance is
    /// `compliance`: a contact's on its normal row only, a joint's on every row.
    pub fn row_compliance(self, compliance: f64, r: usize) -> f64 {
        if r == 0 || self == RowBounds::Free {
            compliance
        } else {
            0.0
        }
    }
}

/// The whole problem of one substep. Plain data; solvers read it and never change it.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactProblem<const D: usize, const R: usize> {
    /// How friction rows are bounded.
    pub friction: FrictionModel,
    /// The bodies, indexed by [`ProblemContact::bodies`].
    pub bodies: Vec<ProblemBody<D>>,
    /// The contacts.
    pub contacts: Vec<ProblemContact<D, R>>,
}

/// The 3D problem: 6 degrees of freedom per body, 3 rows per contact.
pub type ContactProblem3 = ContactProblem<6, 3>;

/// The (side, side) pairs of a contact's Delassus block, in the order they are summed: a
/// contact's two sides with themselves first, as every contact between two bodies (or a body
/// and the static world) has them, then the cross terms, which count only where both sides are
/// the same body.
pub const SIDE_PAIRS: [(usize, usize); 4] = [(0, 0), (1, 1), (0, 1), (1, 0)];

impl<const D: usize, const R: usize> ContactProblem<D, R> {
    /// The contact's R × R Delassus block A_kk = J₁ M₁⁻¹ J₁ᵀ + J₂ M₂⁻¹ J₂ᵀ (kg⁻¹), without
    /// compliance, averaged with its transpose so that it is symmetric to the bit (the product
    /// alone is symmetric only to round-off). A contact of a body with itself adds the cross
    /// terms J₁ M⁻¹ J₂ᵀ + J₂ M⁻¹ J₁ᵀ: its block is (J₁ + J₂) M⁻¹ (J₁ + J₂)ᵀ.
    /// docs/contact.md §"Delassus operator".
    pub fn delassus_block(&self, k: usize) -> SMatrix<f64, R, R> {
        let c = &self.contacts[k];
        let mut a = SMatrix::<f64, R, R>::zeros();
        for (s, t) in SIDE_PAIRS {
            if let Some(body) = c.bodies[s].filter(|_| c.bodies[s] == c.bodies[t]) {
                a += c.jacobian[s] * self.bodies[body].inverse_mass * c.jacobian[t].transpose();
            }
        }
        (a + a.transpose()) * 0.5
    }

    /// The problem of the normal rows alone, written into `out` (its buffers reused): the same
    /// bodies, and per contact row 0 of J₁, J₂, b and λ₀, with the same μ, compliance and bounds.
    /// Post-stabilisation solves it where friction is zero (docs/blocks2d.md
    /// §"Post-stabilisation", "Normal rows only").
    pub fn normal_rows_into(&self, out: &mut ContactProblem<D, 1>) {
        out.friction = self.friction;
        out.bodies.clone_from(&self.bodies);
        out.contacts.clear();
        out.contacts
            .extend(self.contacts.iter().map(|c| ProblemContact {
                bodies: c.bodies,
                jacobian: [
                    c.jacobian[0].fixed_rows::<1>(0).into_owned(),
                    c.jacobian[1].fixed_rows::<1>(0).into_owned(),
                ],
                b: SVector::<f64, 1>::new(c.b[0]),
                mu: c.mu,
                compliance: c.compliance,
                lambda0: SVector::<f64, 1>::new(c.lambda0[0]),
                bounds: c.bounds,
            }));
    }

    /// The dense Jacobian (R·contacts × D·bodies), assembled naively; for tests and for solvers
    /// that want matrices.
    pub fn dense_jacobian(&self) -> DMatrix<f64> {
        let mut j = DMatrix::zeros(R * self.contacts.len(), D * self.bodies.len());
        for (k, c) in self.contacts.iter().enumerate() {
            for side in 0..2 {
                if let Some(body) = c.bodies[side] {
                    let mut block = j.view_mut((R * k, D * body), (R, D));
                    block += c.jacobian[side];
                }
            }
        }
        j
    }

    /// The dense block-diagonal inverse mass matrix (D·bodies square).
    pub fn dense_inverse_mass(&self) -> DMatrix<f64> {
        let n = D * self.bodies.len();
        let mut m = DMatrix::zeros(n, n);
        for (i, body) in self.bodies.iter().enumerate() {
            m.view_mut((D * i, D * i), (D, D))
                .copy_from(&body.inverse_mass);
        }
        m
    }

    /// The dense Delassus operator A = J M⁻¹ Jᵀ, assembled naively from the dense matrices.
    pub fn dense_delassus(&self) -> DMatrix<f64> {
        let j = self.dense_jacobian();
        &j * self.dense_inverse_mass() * j.transpose()
    }

    /// The dense compliance matrix C: diagonal, each contact's compliance on its normal row
    /// (a joint's on every row).
    pub fn dense_compliance(&self) -> DMatrix<f64> {
        let mut c = DMatrix::zeros(R * self.contacts.len(), R * self.contacts.len());
        for (k, contact) in self.contacts.iter().enumerate() {
            for r in 0..R {
                c[(R * k + r, R * k + r)] = contact.row_compliance(r);
            }
        }
        c
    }

    /// The stacked right-hand side b.
    pub fn dense_b(&self) -> nalgebra::DVector<f64> {
        nalgebra::DVector::from_iterator(
            R * self.contacts.len(),
            self.contacts.iter().flat_map(|c| c.b.iter().copied()),
        )
    }

    /// w = (A + C) λ + b for the given impulses, computed through the bodies (u⁺ = u + M⁻¹Jᵀλ),
    /// not through a dense A. Allocates; for inspection and tests.
    pub fn constraint_velocity(&self, lambda: &[SVector<f64, R>]) -> Vec<SVector<f64, R>> {
        let delta = self.velocity_change(lambda);
        self.contacts
            .iter()
            .zip(lambda)
            .map(|(c, l)| {
                let mut w = c.b;
                for side in 0..2 {
                    if let Some(body) = c.bodies[side] {
                        w += c.jacobian[side] * delta[body];
                    }
                }
                for r in 0..R {
                    w[r] += c.row_compliance(r) * l[r];
                }
                w
            })
            .collect()
    }

    /// The change of each body's velocity Δu = M⁻¹ Jᵀ λ caused by the impulses.
    pub fn velocity_change(&self, lambda: &[SVector<f64, R>]) -> Vec<SVector<f64, D>> {
        let mut delta = vec![SVector::<f64, D>::zeros(); self.bodies.len()];
        for (c, l) in self.contacts.iter().zip(lambda) {
            for side in 0..2 {
                if let Some(body) = c.bodies[side] {
                    delta[body] +=
                        self.bodies[body].inverse_mass * c.jacobian[side].transpose() * l;
                }
            }
        }
        delta
    }

    /// Checks the problem is well formed: body indices in range, every number finite, inverse
    /// masses symmetric positive semi-definite, μ ≥ 0 (0 on free rows), compliance ≥ 0, no
    /// contact between the static world and itself, zero Jacobian blocks for the static world. Returns what is wrong.
    pub fn validate(&self) -> Result<(), String> {
        for (i, body) in self.bodies.iter().enumerate() {
            if body
                .inverse_mass
                .iter()
                .chain(body.velocity.iter())
                .any(|x| !x.is_finite())
            {
                return Err(format!("body {i}: non-finite inverse mass or velocity"));
            }
            // An inverse mass must be symmetric positive semi-definite; 1e-9 of its largest
            // entry allows the round-off of R J⁻¹ Rᵀ and of a file's printed digits.
            let m = &body.inverse_mass;
            let scale = m.amax();
            if (m - m.transpose()).amax() > 1e-9 * scale {
                return Err(format!("body {i}: the inverse mass is not symmetric"));
            }
            if DMatrix::from_iterator(D, D, m.iter().copied())
                .symmetric_eigenvalues()
                .min()
                < -1e-9 * scale
            {
                return Err(format!(
                    "body {i}: the inverse mass is not positive semi-definite"
                ));
            }
        }
        for (k, c) in self.contacts.iter().enumerate() {
            if c.bodies == [None, None] {
                return Err(format!("contact {k}: both bodies are the static world"));
            }
            if let [Some(a), Some(b)] = c.bodies
                && a == b
            {
                return Err(format!(
                    "contact {k}: both sides are body {a} (a contact is between two bodies)"
                ));
            }
            for body in c.bodies.iter().flatten() {
                if *body >= self.bodies.len() {
                    return Err(format!(
                        "contact {k}: body index {body} out of range (there are {} bodies)",
                        self.bodies.len()
                    ));
                }
            }
            for side in 0..2 {
                if c.bodies[side].is_none() && c.jacobian[side].iter().any(|x| *x != 0.0) {
                    return Err(format!(
                        "contact {k}: J{} must be zero: body {} is the static world",
                        side + 1,
                        side + 1
                    ));
                }
            }
            if c.bounds == RowBounds::Free && c.mu != 0.0 {
                return Err(format!(
                    "contact {k}: mu has no meaning on free rows (bounds \"free\"); give 0, got {}",
                    c.mu
                ));
            }
            let numbers = c.jacobian[0]
                .iter()
                .chain(c.jacobian[1].iter())
                .chain(c.b.iter())
                .chain(c.lambda0.iter());
            if numbers.clone().any(|x| !x.is_finite()) {
                return Err(format!("contact {k}: non-finite Jacobian, b or lambda0"));
            }
            if !(c.mu.is_finite() && c.mu >= 0.0) {
                return Err(format!("contact {k}: mu must be ≥ 0, got {}", c.mu));
            }
            if !(c.compliance.is_finite() && c.compliance >= 0.0) {
                return Err(format!(
                    "contact {k}: compliance must be ≥ 0, got {}",
                    c.compliance
                ));
            }
        }
        Ok(())
    }
}

#[cfg(feature = "fclib")]
pub mod fclib;
pub mod json;
pub mod local;
pub mod local_json;
pub mod siconos;
pub mod view;

pub use local::{LocalContact, LocalProblem};
pub use view::ProblemView;

/// What a solve did (any solver's answer to the problem: PGS's, or a reference's).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct SolveReport {
    /// Iterations run: PGS sweeps, or Newton iterations (the fallback's included).
    pub iterations: u32,
    /// Residual of the returned λ (docs/contact.md §"Residual"), m/s.
    pub residual: f64,
    /// The tolerance was given and reached.
    pub converged: bool,
    /// For cone friction: the exact Coulomb law's residual of the returned λ (De Saxcé's natural
    /// map, docs/contact.md §"The exact Coulomb residual"), m/s; `None` for box friction.
    pub coulomb_residual: Option<f64>,
    /// The method that produced the answer.
    pub method: SolveMethod,
    /// PGS with `pgs_local_solve: exact`: visits that took the exact local solve's best
    /// candidate because none of its cases was exact to round-off (docs/contact.md §"Exact local
    /// solve"); 0 otherwise.
    pub local_fallbacks: u32,
}

/// Which method produced an answer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolveMethod {
    /// Projected Gauss–Seidel (`crate::solve::pgs`).
    #[default]
    Pgs,
    /// The semismooth Newton iteration alone.
    Newton,
    /// Newton stalled; the proximal-point fallback produced the answer.
    Proximal,
    /// PGS, followed by shock propagation (2D, `shock_propagation`): the recorded λ is PGS's,
    /// but the bodies moved by the shock pass's velocity changes, which no single λ gives
    /// through u⁺ = u + M⁻¹Jᵀλ (the pass holds one side of each layer fixed). The record is
    /// not the step's law: its residual and criteria describe PGS's λ.
    PgsShock,
}

impl SolveMethod {
    /// The spelling in reports and traces.
    pub fn name(self) -> &'static str {
        match self {
            SolveMethod::Pgs => "pgs",
            SolveMethod::Newton => "newton",
            SolveMethod::Proximal => "proximal",
            SolveMethod::PgsShock => "pgs_shock",
        }
    }
}

/// One contact's physical criteria against Coulomb's law (computed by
/// `crate::solve::criteria`, docs/contact.md §"Physical criteria"); all zero at a Coulomb
/// solution.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactCriteria {
    /// dist_K(λ), N·s: how far the impulse is outside the friction cone.
    pub primal: f64,
    /// dist_K*(ĉ), m/s: how far De Saxcé's velocity is outside the dual cone (an approach
    /// without impulse shows here).
    pub dual: f64,
    /// |λ·ĉ|, J.
    pub complementarity: f64,
    /// |λn c_n|, J: impulse on a contact that separates (or approaches).
    pub signorini: f64,
    /// |‖c_T‖ (μλn − ‖λ_T‖)|, J: a sliding contact whose friction is inside the cone.
    pub cone_boundary: f64,
    /// ‖λ_T‖ ‖c_T‖ + λ_T·c_T, J: friction not opposite to the slip.
    pub max_dissipation: f64,
}

impl ContactCriteria {
    /// The larger of each criterion.
    pub fn max(&self, other: &ContactCriteria) -> ContactCriteria {
        ContactCriteria {
            primal: self.primal.max(other.primal),
            dual: self.dual.max(other.dual),
            complementarity: self.complementarity.max(other.complementarity),
            signorini: self.signorini.max(other.signorini),
            cone_boundary: self.cone_boundary.max(other.cone_boundary),
            max_dissipation: self.max_dissipation.max(other.max_dissipation),
        }
    }
}
