//! `rigidref.ContactProblem`, the solvers, the residuals and the criteria: the library's
//! [`rigidref::problem::ContactProblem`] (3D: 6 degrees of freedom per body, 3 rows per contact;
//! 2D: 3 and 2) seen as arrays. docs/contact.md defines every quantity; docs/python.md the API.

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
use rigidref::solve::{
    ContactOrder, LocalSolve, NewtonSettings, PgsSettings, PgsWorkspace, Solvable,
    solve_pgs as pgs, solve_pgs_local,
};
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

/// λ (N·s) per contact from an array of shape (contacts, R).
fn lambdas<const R: usize>(
    obj: &Bound<'_, PyAny>,
    contacts: usize,
    what: &str,
) -> PyResult<Vec<SVector<f64, R>>> {
    let (data, _) = arrays::shaped(obj, what, &[Some(contacts), Some(R)])?;
    if let Some(x) = data.iter().find(|x| !x.is_finite()) {
        return Err(errors::problem(format!("{what}: not finite ({x})")));
    }
    Ok(data
        .chunks(R)
        .map(SVector::<f64, R>::from_column_slice)
        .collect())
}

/// λ per contact as an array of shape (contacts, R).
pub fn lambda_array<'py, const R: usize>(
    py: Python<'py>,
    lambda: &[SVector<f64, R>],
) -> Bound<'py, PyArray2<f64>> {
    let data = lambda.iter().flat_map(|l| l.iter().copied()).collect();
    arrays::matrix(py, lambda.len(), R, data)
}

/// The Jacobian J (R·contacts × D·bodies) as triplets.
fn jacobian_triplets<const D: usize, const R: usize>(
    p: &Problem<D, R>,
) -> Vec<(usize, usize, f64)> {
    let mut t = Vec::new();
    for (k, c) in p.contacts.iter().enumerate() {
        for side in 0..2 {
            if let Some(body) = c.bodies[side] {
                for r in 0..R {
                    for d in 0..D {
                        t.push((R * k + r, D * body + d, c.jacobian[side][(r, d)]));
                    }
                }
            }
        }
    }
    t
}

/// The Delassus operator A = J M⁻¹ Jᵀ (R·contacts square) as triplets: block (k, l) is the sum,
/// over the bodies contacts k and l share, of J_k,b M_b⁻¹ J_l,bᵀ.
fn delassus_triplets<const D: usize, const R: usize>(
    p: &Problem<D, R>,
) -> Vec<(usize, usize, f64)> {
    let mut touching: Vec<Vec<(usize, usize)>> = vec![Vec::new(); p.bodies.len()];
    for (k, c) in p.contacts.iter().enumerate() {
        for side in 0..2 {
            if let Some(body) = c.bodies[side] {
                touching[body].push((k, side));
            }
        }
    }
    let mut blocks: BTreeMap<(usize, usize), SMatrix<f64, R, R>> = BTreeMap::new();
    for (body, list) in touching.iter().enumerate() {
        let m = &p.bodies[body].inverse_mass;
        for &(k, sk) in list {
            let left = p.contacts[k].jacobian[sk] * m;
            for &(l, sl) in list {
                *blocks.entry((k, l)).or_insert_with(SMatrix::zeros) +=
                    left * p.contacts[l].jacobian[sl].transpose();
            }
        }
    }
    let mut t = Vec::new();
    for ((k, l), block) in blocks {
        for i in 0..R {
            for j in 0..R {
                t.push((R * k + i, R * l + j, block[(i, j)]));
            }
        }
    }
    t
}

/// The inverse mass M⁻¹ (D·bodies square, block diagonal) as triplets.
fn inverse_mass_triplets<const D: usize, const R: usize>(
    p: &Problem<D, R>,
) -> Vec<(usize, usize, f64)> {
    let mut t = Vec::new();
    for (b, body) in p.bodies.iter().enumerate() {
        for i in 0..D {
            for j in 0..D {
                t.push((D * b + i, D * b + j, body.inverse_mass[(i, j)]));
            }
        }
    }
    t
}

/// Builds a problem of D dof per body and R rows per contact from dense arrays.
#[allow(clippy::too_many_arguments)]
fn build<const D: usize, const R: usize>(
    jacobian: &Bound<'_, PyAny>,
    inverse_mass: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
    mu: &Bound<'_, PyAny>,
    friction: FrictionModel,
    compliance: Option<&Bound<'_, PyAny>>,
    lambda0: Option<&Bound<'_, PyAny>>,
    velocity: Option<&Bound<'_, PyAny>>,
    bounds: Option<Vec<RowBounds>>,
) -> PyResult<Problem<D, R>> {
    let (j, shape) = arrays::numbers(jacobian, "J")?;
    if shape.len() != 2 || shape[0] % R != 0 || shape[1] % D != 0 || shape[1] == 0 {
        return Err(errors::problem(format!(
            "J: shape {shape:?}, expected ({R}·contacts, {D}·bodies) with at least one body"
        )));
    }
    let (rows, cols) = (shape[0], shape[1]);
    let (m, n) = (rows / R, cols / D);
    let (minv, mshape) = arrays::numbers(inverse_mass, "Minv")?;
    // Minv: the block-diagonal matrix (D·bodies square) or its blocks (bodies, D, D).
    let block = |b: usize, i: usize, jj: usize| -> f64 {
        if mshape.len() == 3 {
            minv[(b * D + i) * D + jj]
        } else {
            minv[(D * b + i) * cols + D * b + jj]
        }
    };
    if mshape == [cols, cols] {
        for r in 0..cols {
            for c in 0..cols {
                if r / D != c / D && minv[r * cols + c] != 0.0 {
                    return Err(errors::problem(format!(
                        "Minv: entry ({r}, {c}) is {} outside the bodies' {D} × {D} diagonal blocks; a body's inverse mass couples only its own velocities",
                        minv[r * cols + c]
                    )));
                }
            }
        }
    } else if mshape != [n, D, D] {
        return Err(errors::problem(format!(
            "Minv: shape {mshape:?}, expected ({cols}, {cols}) or ({n}, {D}, {D}) for the {n} bodies of J"
        )));
    }
    let (b, _) = arrays::numbers(b, "b")?;
    if b.len() != rows {
        return Err(errors::problem(format!(
            "b: {} entries, expected {rows} (J's rows)",
            b.len()
        )));
    }
    let per_contact =
        |obj: Option<&Bound<'_, PyAny>>, what: &str, default: f64| -> PyResult<Vec<f64>> {
            let Some(obj) = obj else {
                return Ok(vec![default; m]);
            };
            let (v, s) = arrays::numbers(obj, what)?;
            match s.len() {
                0 => Ok(vec![v[0]; m]),
                1 if v.len() == m => Ok(v),
                _ => Err(errors::problem(format!(
                    "{what}: shape {s:?}, expected a number or ({m},), one per contact"
                ))),
            }
        };
    let mu = per_contact(Some(mu), "mu", 0.0)?;
    let compliance = per_contact(compliance, "compliance", 0.0)?;
    let lambda0 = match lambda0 {
        Some(l) => arrays::shaped(l, "lambda0", &[Some(m), Some(R)])?.0,
        None => vec![0.0; rows],
    };
    let velocity = match velocity {
        Some(u) => {
            let (u, _) = arrays::numbers(u, "velocity")?;
            if u.len() != cols {
                return Err(errors::problem(format!(
                    "velocity: {} entries, expected {cols} (J's columns)",
                    u.len()
                )));
            }
            u
        }
        None => vec![0.0; cols],
    };
    if let Some(b) = &bounds
        && b.len() != m
    {
        return Err(errors::problem(format!(
            "bounds: {} entries, expected {m}, one per contact",
            b.len()
        )));
    }
    let bodies = (0..n)
        .map(|i| ProblemBody {
            inverse_mass: SMatrix::<f64, D, D>::from_fn(|r, c| block(i, r, c)),
            velocity: SVector::<f64, D>::from_column_slice(&velocity[D * i..D * i + D]),
        })
        .collect();
    let mut contacts = Vec::with_capacity(m);
    for k in 0..m {
        let entry = |r: usize, c: usize| j[(R * k + r) * cols + c];
        let touched: Vec<usize> = (0..n)
            .filter(|&body| (0..R).any(|r| (0..D).any(|d| entry(r, D * body + d) != 0.0)))
            .collect();
        if touched.len() > 2 {
            return Err(errors::problem(format!(
                "J: contact {k}'s rows act on bodies {touched:?}; a contact acts on at most two bodies"
            )));
        }
        let side = |s: usize| -> (Option<usize>, SMatrix<f64, R, D>) {
            match touched.get(s) {
                Some(&body) => (Some(body), SMatrix::from_fn(|r, d| entry(r, D * body + d))),
                None => (None, SMatrix::zeros()),
            }
        };
        let ((b1, j1), (b2, j2)) = (side(0), side(1));
        contacts.push(ProblemContact {
            bodies: [b1, b2],
            jacobian: [j1, j2],
            b: SVector::from_column_slice(&b[R * k..R * k + R]),
            mu: mu[k],
            compliance: compliance[k],
            lambda0: SVector::from_column_slice(&lambda0[R * k..R * k + R]),
            bounds: bounds.as_ref().map_or(RowBounds::Contact, |b| b[k]),
        });
    }
    let problem = Problem {
        friction,
        bodies,
        contacts,
    };
    problem.validate().map_err(errors::problem)?;
    Ok(problem)
}

fn row_bounds(name: &str) -> PyResult<RowBounds> {
    match name {
        "contact" => Ok(RowBounds::Contact),
        "free" => Ok(RowBounds::Free),
        other => Err(errors::problem(format!(
            "bounds {other:?}: expected \"contact\" or \"free\""
        ))),
    }
}

fn friction_model(name: &str) -> PyResult<FrictionModel> {
    match name {
        "box" => Ok(FrictionModel::Box),
        "cone" => Ok(FrictionModel::Cone),
        other => Err(errors::problem(format!(
            "friction_model {other:?}: expected \"box\" or \"cone\""
        ))),
    }
}

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

/// W (R·contacts square) of a local problem as triplets, block by block.
fn local_triplets<const R: usize>(p: &LocalProblem<R>) -> Vec<(usize, usize, f64)> {
    let mut t = Vec::new();
    for (k, c) in p.contacts.iter().enumerate() {
        for (j, block) in &c.row {
            for a in 0..R {
                for b in 0..R {
                    t.push((R * k + a, R * j + b, block[(a, b)]));
                }
            }
        }
    }
    t
}

/// A local problem of R rows per contact from a dense W (A), b and μ, with the optional warm
/// start and bounds.
fn build_local<const R: usize>(
    a: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
    mu: &Bound<'_, PyAny>,
    friction: FrictionModel,
    lambda0: Option<&Bound<'_, PyAny>>,
    bounds: Option<Vec<RowBounds>>,
) -> PyResult<LocalProblem<R>> {
    let (w, shape) = arrays::numbers(a, "A")?;
    if shape.len() != 2 || shape[0] != shape[1] || shape[0] % R != 0 {
        return Err(errors::problem(format!(
            "A: shape {shape:?}, expected ({R}·contacts, {R}·contacts)"
        )));
    }
    let n = shape[0];
    let m = n / R;
    let (q, _) = arrays::numbers(b, "b")?;
    if q.len() != n {
        return Err(errors::problem(format!(
            "b: {} entries, expected {n} (A's rows)",
            q.len()
        )));
    }
    let (mu_values, mu_shape) = arrays::numbers(mu, "mu")?;
    let mu = match mu_shape.len() {
        0 => vec![mu_values[0]; m],
        1 if mu_values.len() == m => mu_values,
        _ => {
            return Err(errors::problem(format!(
                "mu: shape {mu_shape:?}, expected a number or ({m},), one per contact"
            )));
        }
    };
    let entries = (0..n)
        .flat_map(|i| (0..n).map(move |j| (i, j)))
        .filter_map(|(i, j)| {
            let v = w[i * n + j];
            (v != 0.0 || i / R == j / R).then_some((i, j, v))
        });
    let mut problem =
        LocalProblem::<R>::from_entries(friction, entries, &q, &mu).map_err(errors::problem)?;
    if let Some(l) = lambda0 {
        for (c, l) in problem
            .contacts
            .iter_mut()
            .zip(lambdas::<R>(l, m, "lambda0")?)
        {
            c.lambda0 = l;
        }
    }
    if let Some(bounds) = bounds {
        if bounds.len() != m {
            return Err(errors::problem(format!(
                "bounds: {} entries, expected {m}, one per contact",
                bounds.len()
            )));
        }
        for (c, b) in problem.contacts.iter_mut().zip(bounds) {
            c.bounds = b;
        }
    }
    problem.validate().map_err(errors::problem)?;
    Ok(problem)
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
    /// Both: friction_model ("box" or "cone"), lambda0 ((contacts, R), the warm start) and
    /// bounds ("contact" or "free" per constraint, default all "contact"). Checked as a problem
    /// file is: a ProblemError says what is wrong (shapes, non-finite numbers, negative μ, ...).
    #[staticmethod]
    #[pyo3(signature = (J = None, Minv = None, b = None, mu = None, *, A = None, friction_model = "box", compliance = None, lambda0 = None, velocity = None, bounds = None, dof_per_body = 6))]
    #[allow(non_snake_case, clippy::too_many_arguments)]
    fn from_arrays(
        J: Option<&Bound<'_, PyAny>>,
        Minv: Option<&Bound<'_, PyAny>>,
        b: Option<&Bound<'_, PyAny>>,
        mu: Option<&Bound<'_, PyAny>>,
        A: Option<&Bound<'_, PyAny>>,
        friction_model: &str,
        compliance: Option<&Bound<'_, PyAny>>,
        lambda0: Option<&Bound<'_, PyAny>>,
        velocity: Option<&Bound<'_, PyAny>>,
        bounds: Option<Vec<String>>,
        dof_per_body: usize,
    ) -> PyResult<ContactProblem> {
        let friction = self::friction_model(friction_model)?;
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

/// A solver's answer: λ and what the solver reports.
#[pyclass(module = "rigidref", frozen, get_all)]
pub struct Solution {
    /// λ per contact (contacts × R, N·s).
    pub lam: Py<PyArray2<f64>>,
    /// Iterations (PGS sweeps, Newton iterations, interior-point iterations).
    pub iterations: u32,
    /// The natural-map residual of λ (m/s; docs/contact.md §"Residual").
    pub residual: f64,
    /// Whether the solver reached its tolerance (clarabel: status Solved or AlmostSolved).
    pub converged: bool,
    /// For cone friction, the exact Coulomb residual (m/s); None for box friction.
    pub coulomb_residual: Option<f64>,
    /// "pgs", "newton", "proximal", "pgs_shock" or "clarabel".
    pub method: String,
    /// clarabel's status (e.g. "Solved"); None for the other solvers.
    pub status: Option<String>,
}

#[pymethods]
impl Solution {
    fn __repr__(&self) -> String {
        format!(
            "Solution(method={:?}, iterations={}, residual={:e}, converged={})",
            self.method, self.iterations, self.residual, self.converged
        )
    }
}

/// The method's snake_case name.
pub fn method_name(report: &SolveReport) -> String {
    serde_json::to_value(report.method)
        .ok()
        .and_then(|v| v.as_str().map(str::to_string))
        .unwrap_or_default()
}

/// A Solution from a report and λ.
pub fn solution<const R: usize>(
    py: Python<'_>,
    report: &SolveReport,
    lambda: &[SVector<f64, R>],
) -> Solution {
    Solution {
        lam: lambda_array(py, lambda).unbind(),
        iterations: report.iterations,
        residual: report.residual,
        converged: report.converged,
        coulomb_residual: report.coulomb_residual,
        method: method_name(report),
        status: None,
    }
}

/// A problem whose warm start can be replaced, in either form.
trait WarmStart<const R: usize>: Clone + ProblemView<R> {
    /// Sets contact k's warm start.
    fn set_lambda0(&mut self, k: usize, l: SVector<f64, R>);
}

impl<const D: usize, const R: usize> WarmStart<R> for Problem<D, R> {
    fn set_lambda0(&mut self, k: usize, l: SVector<f64, R>) {
        self.contacts[k].lambda0 = l;
    }
}

impl<const R: usize> WarmStart<R> for LocalProblem<R> {
    fn set_lambda0(&mut self, k: usize, l: SVector<f64, R>) {
        self.contacts[k].lambda0 = l;
    }
}

/// The problem with its warm start replaced by `warm_start` (contacts × R), when given.
fn warm<const R: usize, P: WarmStart<R>>(
    p: &P,
    warm_start: Option<&Bound<'_, PyAny>>,
) -> PyResult<P> {
    let mut p = p.clone();
    if let Some(ws) = warm_start {
        let l = lambdas::<R>(ws, p.count(), "warm_start")?;
        for (k, l) in l.into_iter().enumerate() {
            p.set_lambda0(k, l);
        }
    }
    Ok(p)
}

/// Projected Gauss–Seidel (src/solve/pgs.rs, docs/contact.md §"Projected Gauss–Seidel"): at most
/// `iterations` sweeps, stopping at `tolerance` (m/s) when given; warm_start (contacts × R)
/// replaces the problem's λ0 (None keeps it: the step's own warm start); order "sequential" or
/// "random" (seeded by `seed`); local "rows" (the assignment's) or "exact". With the settings of
/// `World.solver_settings()` it reproduces a step's λ to the bit.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
#[pyo3(signature = (problem, iterations = 100, tolerance = None, warm_start = None, order = "sequential", local = "rows", seed = 0))]
pub fn solve_pgs(
    py: Python<'_>,
    problem: &ContactProblem,
    iterations: u32,
    tolerance: Option<f64>,
    warm_start: Option<&Bound<'_, PyAny>>,
    order: &str,
    local: &str,
    seed: u64,
) -> PyResult<Solution> {
    let order = match order {
        "sequential" => ContactOrder::Sequential,
        "random" => ContactOrder::Random,
        o => {
            return Err(errors::problem(format!(
                "order {o:?}: expected \"sequential\" or \"random\""
            )));
        }
    };
    let local = match local {
        "rows" => LocalSolve::Rows,
        "exact" => LocalSolve::Exact,
        o => {
            return Err(errors::problem(format!(
                "local {o:?}: expected \"rows\" or \"exact\""
            )));
        }
    };
    if tolerance.is_some_and(|t| t.is_nan() || t <= 0.0) {
        return Err(errors::problem(format!(
            "tolerance {tolerance:?}: expected a positive number"
        )));
    }
    let settings = PgsSettings {
        max_iterations: iterations,
        tolerance,
        order,
        local,
    };
    match &problem.inner {
        AnyProblem::P3(p) => run_pgs(py, p, warm_start, &settings, seed),
        AnyProblem::P2(p) => run_pgs(py, p, warm_start, &settings, seed),
        AnyProblem::L3(p) => run_pgs(py, p, warm_start, &settings, seed),
        AnyProblem::L2(p) => run_pgs(py, p, warm_start, &settings, seed),
    }
}

/// PGS on either form: through the bodies' Δu, or through W (src/solve/pgs_delassus.rs).
trait PgsForm<const R: usize>: WarmStart<R> + Send + Sync {
    fn pgs(
        &self,
        settings: &PgsSettings,
        seed: u64,
        lambda: &mut Vec<SVector<f64, R>>,
    ) -> SolveReport;
}

impl<const D: usize, const R: usize> PgsForm<R> for Problem<D, R> {
    fn pgs(
        &self,
        settings: &PgsSettings,
        seed: u64,
        lambda: &mut Vec<SVector<f64, R>>,
    ) -> SolveReport {
        pgs(self, settings, &mut PgsWorkspace::new(seed), lambda)
    }
}

impl<const R: usize> PgsForm<R> for LocalProblem<R> {
    fn pgs(
        &self,
        settings: &PgsSettings,
        seed: u64,
        lambda: &mut Vec<SVector<f64, R>>,
    ) -> SolveReport {
        solve_pgs_local(self, settings, seed, lambda)
    }
}

fn run_pgs<const R: usize, P: PgsForm<R>>(
    py: Python<'_>,
    p: &P,
    warm_start: Option<&Bound<'_, PyAny>>,
    settings: &PgsSettings,
    seed: u64,
) -> PyResult<Solution> {
    let p = warm(p, warm_start)?;
    let (report, lambda) = py.detach(|| {
        let mut lambda = Vec::new();
        let report = p.pgs(settings, seed, &mut lambda);
        (report, lambda)
    });
    Ok(solution(py, &report, &lambda))
}

/// The exact solver (src/solve/newton.rs, docs/contact.md §"Newton solver"): semismooth Newton
/// on the Alart–Curnier function with a proximal-point fallback, to `tolerance` (m/s).
#[pyfunction]
#[pyo3(signature = (problem, max_iterations = 50, tolerance = 1e-10, proximal_iterations = 60, warm_start = None))]
pub fn solve_newton(
    py: Python<'_>,
    problem: &ContactProblem,
    max_iterations: u32,
    tolerance: f64,
    proximal_iterations: u32,
    warm_start: Option<&Bound<'_, PyAny>>,
) -> PyResult<Solution> {
    if tolerance.is_nan() || tolerance <= 0.0 {
        return Err(errors::problem(format!(
            "tolerance {tolerance}: expected a positive number"
        )));
    }
    let settings = NewtonSettings {
        max_iterations,
        tolerance,
        proximal_iterations,
        ..Default::default()
    };
    with_problem!(&problem.inner, p => {
        let p = warm(p, warm_start)?;
        let (report, lambda) = py.detach(|| {
            let mut lambda = Vec::new();
            let report = Solvable::newton(&p, &settings, &mut lambda);
            (report, lambda)
        });
        Ok(solution(py, &report, &lambda))
    })
}

/// The problem as a convex program solved by clarabel (src/solve/qp.rs, docs/contact.md
/// §"Convex formulations"): formulation "cone" (Anitescu's relaxation; the default),
/// "frictionless", or "box_fixed" / "cone_fixed" with the friction bounds frozen at
/// `fixed_normal` (one λn per contact, e.g. PGS's), which checks an answer rather than finding one.
#[pyfunction]
#[pyo3(signature = (problem, formulation = "cone", fixed_normal = None, tolerance = 1e-10, max_iterations = 200))]
pub fn solve_clarabel(
    py: Python<'_>,
    problem: &ContactProblem,
    formulation: &str,
    fixed_normal: Option<&Bound<'_, PyAny>>,
    tolerance: f64,
    max_iterations: u32,
) -> PyResult<Solution> {
    let m = problem.num_contacts();
    let fixed = || -> PyResult<Vec<f64>> {
        let Some(f) = fixed_normal else {
            return Err(errors::problem(format!(
                "formulation {formulation:?} needs fixed_normal, one λn per contact"
            )));
        };
        let (f, _) = arrays::shaped(f, "fixed_normal", &[Some(m)])?;
        if let Some(x) = f.iter().find(|x| !(x.is_finite() && **x >= 0.0)) {
            return Err(errors::problem(format!(
                "fixed_normal: {x} is not a normal impulse (finite, ≥ 0)"
            )));
        }
        Ok(f)
    };
    if tolerance.is_nan() || tolerance <= 0.0 {
        return Err(errors::problem(format!(
            "tolerance {tolerance}: expected a positive number"
        )));
    }
    let formulation = match formulation {
        "cone" => QpFormulation::Cone,
        "frictionless" => QpFormulation::Frictionless,
        "box_fixed" => QpFormulation::BoxFixed(fixed()?),
        "cone_fixed" => QpFormulation::ConeFixed(fixed()?),
        f => {
            return Err(errors::problem(format!(
                "formulation {f:?}: expected \"cone\", \"frictionless\", \"box_fixed\" or \"cone_fixed\""
            )));
        }
    };
    let settings = QpSettings {
        tolerance,
        max_iterations,
    };
    with_problem!(&problem.inner, p => {
        let solved = py.detach(|| solve_qp(p, &formulation, &settings)).map_err(errors::problem)?;
        let residual = rigidref::solve::residual(p, &solved.lambda);
        let coulomb = (ProblemView::friction(p) == FrictionModel::Cone)
            .then(|| rigidref::solve::residual::coulomb_residual(p, &solved.lambda));
        Ok(Solution {
            lam: lambda_array(py, &solved.lambda).unbind(),
            iterations: solved.iterations,
            residual,
            converged: solved.solved,
            coulomb_residual: coulomb,
            method: "clarabel".into(),
            status: Some(solved.status),
        })
    })
}

/// The natural-map residual of impulses `lam` (contacts × R) for `problem`, m/s
/// (docs/contact.md §"Residual"): 0 exactly at a solution of the problem's friction model.
#[pyfunction]
pub fn residual(problem: &ContactProblem, lam: &Bound<'_, PyAny>) -> PyResult<f64> {
    with_problem!(&problem.inner, p => Ok(rigidref::solve::residual(p, &lambdas(lam, p.count(), "lam")?)))
}

/// The exact Coulomb law's residual of `lam` (De Saxcé's natural map, m/s; docs/contact.md
/// §"The exact Coulomb residual"), whatever the problem's friction model.
#[pyfunction]
pub fn coulomb_residual(problem: &ContactProblem, lam: &Bound<'_, PyAny>) -> PyResult<f64> {
    with_problem!(&problem.inner, p => Ok(rigidref::solve::residual::coulomb_residual(p, &lambdas(lam, p.count(), "lam")?)))
}

/// The physical criteria of `lam` against Coulomb's law, per contact (docs/contact.md §"Physical
/// criteria"): a dict of arrays "primal", "dual", "complementarity", "signorini",
/// "cone_boundary", "max_dissipation" (one entry per contact) and "max", their largest values.
#[pyfunction]
pub fn criteria<'py>(
    py: Python<'py>,
    problem: &ContactProblem,
    lam: &Bound<'_, PyAny>,
) -> PyResult<Bound<'py, PyDict>> {
    let (each, max) = with_problem!(&problem.inner, p => rigidref::solve::criteria::criteria(p, &lambdas(lam, p.count(), "lam")?));
    criteria_dict(py, &each, &max)
}

/// The criteria as a dict of arrays (see [`criteria`]).
pub fn criteria_dict<'py>(
    py: Python<'py>,
    each: &[rigidref::problem::ContactCriteria],
    max: &rigidref::problem::ContactCriteria,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    type Field = fn(&rigidref::problem::ContactCriteria) -> f64;
    let fields: [(&str, Field); 6] = [
        ("primal", |c| c.primal),
        ("dual", |c| c.dual),
        ("complementarity", |c| c.complementarity),
        ("signorini", |c| c.signorini),
        ("cone_boundary", |c| c.cone_boundary),
        ("max_dissipation", |c| c.max_dissipation),
    ];
    let largest = PyDict::new(py);
    for (name, f) in fields {
        d.set_item(name, arrays::vector(py, each.iter().map(f).collect()))?;
        largest.set_item(name, f(max))?;
    }
    d.set_item("max", largest)?;
    Ok(d)
}

/// Siconos' error measure of `lam` (docs/problem-library.md §"Siconos' error measure"): the
/// unit-scale natural map of the Coulomb law, 2-norm over the contacts, divided by
/// max(‖b‖, ‖λ‖, ‖w‖); the stopping criterion of `rigidref solve-problems`.
#[pyfunction]
pub fn siconos_error(problem: &ContactProblem, lam: &Bound<'_, PyAny>) -> PyResult<f64> {
    with_problem!(&problem.inner, p => Ok(rigidref::solve::residual::siconos_error(p, &lambdas(lam, p.count(), "lam")?)))
}
