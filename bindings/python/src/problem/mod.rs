//! `rigidref.ContactProblem`, the solvers, the residuals and the criteria: the library's
//! [`rigidref::problem::ContactProblem`] (3D: 6 degrees of freedom per body, 3 rows per contact;
//! 2D: 3 and 2) seen as arrays. docs/contact.md defines every quantity; docs/python.md the API.
//!
//! [`build`] makes problems from arrays; [`solvers`] holds the solver, residual and criteria
//! functions.

use crate::arrays;
use crate::errors;
use nalgebra::{SMatrix, SVector};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rigidref::problem::json::ProblemFile;
use rigidref::problem::local_json::{AnyProblemFile, LocalProblemFile};
use rigidref::problem::siconos::AnyLocalProblem;
use rigidref::problem::{
    ContactProblem as Problem, FrictionModel, LocalProblem, ProblemBody, ProblemContact,
    ProblemView, RowBounds, SolveReport,
};
use rigidref::solve::qp::{QpFormulation, QpSettings, solve_qp};
use rigidref::solve::twins::{TwinSettings, solve_twins_local_until};
use rigidref::solve::{
    ContactOrder, LocalSolve, NewtonSettings, PgsSettings, PgsWorkspace, Regularisation, Solvable,
    solve_pgs as pgs, solve_pgs_local,
};
use rigidref::tools::experiments::problem_library::library_error_given;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// A problem of either system, in either form.
#[derive(Clone, Debug)]
pub enum AnyProblem {
    /// 3D: 6 degrees of freedom per body (v, ω), 3 rows per contact (n, t1, t2).
    P3(Problem<6, 3>),
    /// 2D: 3 degrees of freedom per body (vx, vy, ω), 2 rows per contact (n, t).
    P2(Problem<3, 2>),
    /// The local form (W, q, μ; docs/contact.md §"The local form"), 3 rows per contact.
    L3(LocalProblem<3>),
    /// The local form, 2 rows per contact.
    L2(LocalProblem<2>),
}

/// Runs `$body` with `$p` bound to the problem inside, whichever system and form it is: the
/// body may use only what both forms have ([`ProblemView`], the solvers' generic functions).
macro_rules! with_problem {
    ($any:expr, $p:ident => $body:expr) => {
        match $any {
            AnyProblem::P3($p) => $body,
            AnyProblem::P2($p) => $body,
            AnyProblem::L3($p) => $body,
            AnyProblem::L2($p) => $body,
        }
    };
}
pub(crate) use with_problem;

/// Runs `$body` with `$p` bound to a body-form problem; a local-form problem raises ProblemError
/// saying that it has no `$what`.
macro_rules! with_bodies {
    ($any:expr, $what:expr, $p:ident => $body:expr) => {
        match $any {
            AnyProblem::P3($p) => $body,
            AnyProblem::P2($p) => $body,
            AnyProblem::L3(_) | AnyProblem::L2(_) => {
                return Err(errors::problem(format!(
                    "{}: a local-form problem (W, q) has no bodies or Jacobian; it has W, b (= q), mu",
                    $what
                )))
            }
        }
    };
}

/// One contact problem (docs/contact.md §"The contact problem"): find impulses λ with
/// w = (A + C) λ + b, A = J M⁻¹ Jᵀ, and each contact's complementarity and friction conditions.
/// Matrices are float64 arrays (a `CooMatrix` when the dense one would exceed `DENSE_LIMIT`
/// entries); rows are grouped per contact (normal first), columns per body.
#[pyclass(module = "rigidref", name = "ContactProblem")]
#[derive(Clone)]
pub struct ContactProblem {
    pub inner: AnyProblem,
}

mod build;
pub mod solvers;

pub use build::lambda_array;
use build::*;
pub use solvers::{Solution, criteria_dict, solution};

impl ContactProblem {
    /// (D, R): D is 0 for the local form (no bodies).
    fn dims(&self) -> (usize, usize) {
        match &self.inner {
            AnyProblem::P3(_) => (6, 3),
            AnyProblem::P2(_) => (3, 2),
            AnyProblem::L3(_) => (0, 3),
            AnyProblem::L2(_) => (0, 2),
        }
    }

    fn is_local(&self) -> bool {
        matches!(self.inner, AnyProblem::L3(_) | AnyProblem::L2(_))
    }
}

#[pymethods]
impl ContactProblem {
    /// Reads a contact-problem file (docs/contact-problem-format.md), 3D or 2D, body or local
    /// form, or a Siconos `.dat` problem (docs/problem-library.md; the local form). Raises
    /// ProblemError naming the file and what is wrong.
    #[staticmethod]
    fn read(path: PathBuf) -> PyResult<ContactProblem> {
        let name = path.display().to_string();
        rigidref::common::input::check_size(&path)
            .map_err(|e| errors::problem(format!("{name}: {e}")))?;
        let named = |e: String| errors::problem(format!("{name}: {e}"));
        if path.extension().is_some_and(|e| e == "dat") {
            let inner =
                match rigidref::problem::siconos::read_dat(&path).map_err(errors::problem)? {
                    AnyLocalProblem::Three(p) => AnyProblem::L3(p),
                    AnyLocalProblem::Two(p) => AnyProblem::L2(p),
                };
            return Ok(ContactProblem { inner });
        }
        let inner = match AnyProblemFile::read(&path).map_err(errors::problem)? {
            AnyProblemFile::Body(file) => match (file.dof_per_body, file.rows_per_contact) {
                (6, 3) => AnyProblem::P3(file.to_problem::<6, 3>().map_err(named)?),
                (3, 2) => AnyProblem::P2(file.to_problem::<3, 2>().map_err(named)?),
                (d, r) => {
                    return Err(errors::problem(format!(
                        "{name}: dof_per_body {d} with rows_per_contact {r} is not a problem rigidref knows (6/3 in 3D, 3/2 in 2D)"
                    )));
                }
            },
            AnyProblemFile::Local(file) => match file.rows_per_contact {
                3 => AnyProblem::L3(file.to_problem::<3>().map_err(named)?),
                2 => AnyProblem::L2(file.to_problem::<2>().map_err(named)?),
                r => {
                    return Err(errors::problem(format!(
                        "{name}: rows_per_contact {r}: 3 (3D) or 2 (2D)"
                    )));
                }
            },
        };
        Ok(ContactProblem { inner })
    }

    /// Writes the problem as a contact-problem file (no provenance, no solution).
    fn write(&self, path: PathBuf) -> PyResult<()> {
        let file = match &self.inner {
            AnyProblem::P3(p) => serde_json::to_value(ProblemFile::new(p)),
            AnyProblem::P2(p) => serde_json::to_value(ProblemFile::new(p)),
            AnyProblem::L3(p) => serde_json::to_value(LocalProblemFile::new(p)),
            AnyProblem::L2(p) => serde_json::to_value(LocalProblemFile::new(p)),
        }
        .map_err(|e| errors::problem(format!("{}: {e}", path.display())))?;
        let text = serde_json::to_string(&file)
            .map_err(|e| errors::problem(format!("{}: {e}", path.display())))?;
        std::fs::write(&path, text + "\n")
            .map_err(|e| errors::problem(format!("{}: cannot write: {e}", path.display())))
    }

    /// A problem from arrays, in either form.
    ///
    /// Body form, from_arrays(J, Minv, b, mu, ...): J (R·contacts × D·bodies; each contact's
    /// rows act on at most two bodies, which are read off J's nonzero column blocks and kept in
    /// ascending order, so the normal's direction is J's), Minv (block diagonal, D·bodies
    /// square, or its blocks as (bodies, D, D)), b (R·contacts entries in contact order, any
    /// shape), mu (a number or one per contact, ≥ 0); optionally compliance (kg⁻¹, a number or
    /// one per contact) and velocity (the bodies' u before contact, D·bodies entries).
    /// dof_per_body is 6 (3D: R = 3) or 3 (2D: R = 2).
    ///
    /// Local form (docs/contact.md §"The local form"), from_arrays(A, b, mu, ...) with three
    /// arrays, or from_arrays(A=..., b=..., mu=...): A the Delassus operator W (R·contacts
    /// square, kg⁻¹, compliance included; it need not be symmetric), b (= q), mu; R is 3, or 2
    /// with dof_per_body=3. Its blocks are those with a nonzero entry, and every diagonal block.
    ///
    /// Both: friction_model ("box", the default of the body form, the assignment's; or "cone":
    /// the local form has no default and must be given one), lambda0 ((contacts, R), the warm start) and
    /// bounds ("contact" or "free" per constraint, default all "contact"). Checked as a problem
    /// file is: a ProblemError says what is wrong (shapes, non-finite numbers, negative μ, ...).
    #[staticmethod]
    #[pyo3(signature = (J = None, Minv = None, b = None, mu = None, *, A = None, friction_model = None, compliance = None, lambda0 = None, velocity = None, bounds = None, dof_per_body = 6))]
    #[allow(non_snake_case, clippy::too_many_arguments)]
    fn from_arrays(
        J: Option<&Bound<'_, PyAny>>,
        Minv: Option<&Bound<'_, PyAny>>,
        b: Option<&Bound<'_, PyAny>>,
        mu: Option<&Bound<'_, PyAny>>,
        A: Option<&Bound<'_, PyAny>>,
        friction_model: Option<&str>,
        compliance: Option<&Bound<'_, PyAny>>,
        lambda0: Option<&Bound<'_, PyAny>>,
        velocity: Option<&Bound<'_, PyAny>>,
        bounds: Option<Vec<String>>,
        dof_per_body: usize,
    ) -> PyResult<ContactProblem> {
        let given_friction = friction_model.map(self::friction_model).transpose()?;
        let bounds = bounds
            .map(|b| {
                b.iter()
                    .map(|s| row_bounds(s))
                    .collect::<PyResult<Vec<_>>>()
            })
            .transpose()?;
        // The local form: A given by name, or three positional arrays (A, b, mu).
        let local = match (A, J, Minv, b, mu) {
            (Some(a), None, None, Some(b), Some(mu)) => Some((a, b, mu)),
            (None, Some(a), Some(b), Some(mu), None) => Some((a, b, mu)),
            (Some(_), _, _, _, _) => {
                return Err(errors::problem(
                    "from_arrays(A=..., b=..., mu=...): with A give b and mu, and no J or Minv",
                ));
            }
            _ => None,
        };
        if let Some((a, b, mu)) = local {
            if compliance.is_some() || velocity.is_some() {
                return Err(errors::problem(
                    "the local form has no compliance or velocity: put the compliance in A's diagonal (A + C) and the velocities in b",
                ));
            }
            // No default law for a problem from elsewhere: FCLIB's and Siconos' are the cone,
            // the assignment's the box; a default would change the physics without a word.
            let Some(friction) = given_friction else {
                return Err(errors::problem(
                    "from_arrays(A, b, mu): give friction_model=\"cone\" (Coulomb's law, as FCLIB and Siconos problems) or \"box\" (the assignment's)",
                ));
            };
            let inner = match dof_per_body {
                6 => AnyProblem::L3(build_local::<3>(a, b, mu, friction, lambda0, bounds)?),
                3 => AnyProblem::L2(build_local::<2>(a, b, mu, friction, lambda0, bounds)?),
                d => {
                    return Err(errors::problem(format!(
                        "dof_per_body {d}: expected 6 (3D) or 3 (2D)"
                    )));
                }
            };
            return Ok(ContactProblem { inner });
        }
        let (Some(J), Some(Minv), Some(b), Some(mu)) = (J, Minv, b, mu) else {
            return Err(errors::problem(
                "from_arrays: give J, Minv, b and mu (the body form), or A, b and mu (the local form)",
            ));
        };
        let friction = given_friction.unwrap_or(FrictionModel::Box);
        let inner = match dof_per_body {
            6 => AnyProblem::P3(build::<6, 3>(
                J, Minv, b, mu, friction, compliance, lambda0, velocity, bounds,
            )?),
            3 => AnyProblem::P2(build::<3, 2>(
                J, Minv, b, mu, friction, compliance, lambda0, velocity, bounds,
            )?),
            d => {
                return Err(errors::problem(format!(
                    "dof_per_body {d}: expected 6 (3D) or 3 (2D)"
                )));
            }
        };
        Ok(ContactProblem { inner })
    }

    /// "body" (bodies, J, M⁻¹, b) or "local" (W, q, μ only).
    #[getter]
    fn form(&self) -> &'static str {
        if self.is_local() { "local" } else { "body" }
    }

    /// The problem in local form (docs/contact.md §"The local form"): W = J M⁻¹ Jᵀ + C, q = b;
    /// a local problem is returned as it is.
    fn to_local(&self) -> ContactProblem {
        let inner = match &self.inner {
            AnyProblem::P3(p) => AnyProblem::L3(p.to_local()),
            AnyProblem::P2(p) => AnyProblem::L2(p.to_local()),
            other => other.clone(),
        };
        ContactProblem { inner }
    }

    /// W = A + C (R·contacts square, kg⁻¹): the operator of w = W λ + b, compliance included,
    /// in either form.
    #[getter(W)]
    fn operator<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let n = self.dims().1 * self.num_contacts();
        let triplets = match &self.inner {
            AnyProblem::P3(p) => local_triplets(&p.to_local()),
            AnyProblem::P2(p) => local_triplets(&p.to_local()),
            AnyProblem::L3(p) => local_triplets(p),
            AnyProblem::L2(p) => local_triplets(p),
        };
        arrays::dense_or_sparse(py, (n, n), triplets)
    }

    /// Degrees of freedom per body D: 6 in 3D (v, ω), 3 in 2D (vx, vy, ω).
    #[getter]
    fn dof_per_body(&self) -> usize {
        self.dims().0
    }
    /// Rows per contact R: 3 in 3D (n, t1, t2), 2 in 2D (n, t).
    #[getter]
    fn rows_per_contact(&self) -> usize {
        self.dims().1
    }
    /// Number of contacts.
    #[getter]
    fn num_contacts(&self) -> usize {
        with_problem!(&self.inner, p => p.count())
    }
    /// Number of bodies (0 in the local form).
    #[getter]
    fn num_bodies(&self) -> usize {
        match &self.inner {
            AnyProblem::P3(p) => p.bodies.len(),
            AnyProblem::P2(p) => p.bodies.len(),
            _ => 0,
        }
    }
    /// "box" or "cone".
    #[getter]
    fn friction_model(&self) -> &'static str {
        with_problem!(&self.inner, p => ProblemView::friction(p).name())
    }
    /// The Jacobian J (R·contacts × D·bodies): J u is the contacts' relative velocity (m/s).
    #[getter(J)]
    fn jacobian<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let (d, r) = self.dims();
        let shape = (r * self.num_contacts(), d * self.num_bodies());
        let triplets = with_bodies!(&self.inner, "J", p => jacobian_triplets(p));
        arrays::dense_or_sparse(py, shape, triplets)
    }
    /// The inverse mass M⁻¹ (D·bodies square, block diagonal; kg⁻¹ and (kg·m²)⁻¹).
    #[getter(Minv)]
    fn inverse_mass<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let n = self.dims().0 * self.num_bodies();
        let triplets = with_bodies!(&self.inner, "Minv", p => inverse_mass_triplets(p));
        arrays::dense_or_sparse(py, (n, n), triplets)
    }
    /// The Delassus operator A = J M⁻¹ Jᵀ (R·contacts square, kg⁻¹), without compliance; in the
    /// local form, W itself (which holds any compliance).
    #[getter(A)]
    fn delassus<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let n = self.dims().1 * self.num_contacts();
        let triplets = match &self.inner {
            AnyProblem::P3(p) => delassus_triplets(p),
            AnyProblem::P2(p) => delassus_triplets(p),
            AnyProblem::L3(p) => local_triplets(p),
            AnyProblem::L2(p) => local_triplets(p),
        };
        arrays::dense_or_sparse(py, (n, n), triplets)
    }
    /// The matrix `name` ("J", "Minv", "A" or "W") as a CooMatrix, whatever its size.
    fn sparse(&self, py: Python<'_>, name: &str) -> PyResult<Py<arrays::CooMatrix>> {
        let (d, r) = self.dims();
        let (m, n) = (self.num_contacts(), self.num_bodies());
        if name == "W" || (name == "A" && self.is_local()) {
            let triplets = match &self.inner {
                AnyProblem::P3(p) => local_triplets(&p.to_local()),
                AnyProblem::P2(p) => local_triplets(&p.to_local()),
                AnyProblem::L3(p) => local_triplets(p),
                AnyProblem::L2(p) => local_triplets(p),
            };
            return Py::new(py, arrays::CooMatrix::new((r * m, r * m), triplets));
        }
        let coo = with_bodies!(&self.inner, name, p => match name {
            "J" => arrays::CooMatrix::new((r * m, d * n), jacobian_triplets(p)),
            "Minv" => arrays::CooMatrix::new((d * n, d * n), inverse_mass_triplets(p)),
            "A" => arrays::CooMatrix::new((r * m, r * m), delassus_triplets(p)),
            other => return Err(errors::problem(format!("matrix {other:?}: expected \"J\", \"Minv\", \"A\" or \"W\""))),
        });
        Py::new(py, coo)
    }
    /// b = J u − bias (R·contacts, m/s): w when λ = 0.
    #[getter]
    fn b<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arrays::vector(
            py,
            with_problem!(&self.inner, p => ProblemView::dense_b(p).iter().copied().collect()),
        )
    }
    /// Friction coefficient μ per contact.
    #[getter]
    fn mu<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arrays::vector(
            py,
            with_problem!(&self.inner, p => (0..p.count()).map(|k| p.mu(k)).collect()),
        )
    }
    /// Compliance c per contact (kg⁻¹), on its normal row (the local form holds it in W).
    #[getter]
    fn compliance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let c = with_bodies!(&self.inner, "compliance", p => p.contacts.iter().map(|c| c.compliance).collect());
        Ok(arrays::vector(py, c))
    }
    /// The warm start λ0 (contacts × R, N·s).
    #[getter]
    fn lambda0<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        with_problem!(&self.inner, p => {
            let l: Vec<_> = (0..p.count()).map(|k| p.lambda0(k)).collect();
            lambda_array(py, &l)
        })
    }
    /// The bodies' velocities u before contact (D·bodies).
    #[getter]
    fn velocity<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let u = with_bodies!(&self.inner, "velocity", p => p.bodies.iter().flat_map(|b| b.velocity.iter().copied()).collect());
        Ok(arrays::vector(py, u))
    }
    /// Each constraint's row bounds: "contact" (λn ≥ 0, friction bounded by μ λn) or "free" (a
    /// joint's rows, unbounded; docs/contact.md §"Row bounds").
    #[getter]
    fn bounds(&self) -> Vec<&'static str> {
        with_problem!(&self.inner, p => (0..p.count()).map(|k| p.bounds(k).name()).collect())
    }
    /// Each contact's two bodies (contacts × 2, int64; −1 is the static world). The normal
    /// points from the second into the first.
    #[getter]
    fn bodies<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let pairs: Vec<i64> = with_bodies!(&self.inner, "bodies", p => p.contacts.iter().flat_map(|c| c.bodies.map(|b| b.map_or(-1, |b| b as i64))).collect());
        let m = pairs.len() / 2;
        Ok(numpy::IntoPyArray::into_pyarray(
            numpy::ndarray::Array2::from_shape_vec((m, 2), pairs).expect("pairs"),
            py,
        ))
    }
    /// w = (A + C) λ + b for impulses λ (contacts × R): the contacts' velocities after them.
    fn w<'py>(
        &self,
        py: Python<'py>,
        lam: &Bound<'_, PyAny>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        with_problem!(&self.inner, p => {
            let l = lambdas(lam, p.count(), "lam")?;
            Ok(lambda_array(py, &ProblemView::constraint_velocity(p, &l)))
        })
    }
    fn __repr__(&self) -> String {
        let dimension = if self.dims().1 == 3 { 3 } else { 2 };
        if self.is_local() {
            return format!(
                "ContactProblem({dimension}D, local form, {} contacts, friction_model={:?})",
                self.num_contacts(),
                self.friction_model()
            );
        }
        format!(
            "ContactProblem({dimension}D, {} bodies, {} contacts, friction_model={:?})",
            self.num_bodies(),
            self.num_contacts(),
            self.friction_model()
        )
    }
}
