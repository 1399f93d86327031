//! The solvers, residuals and criteria on a `ContactProblem` of either form: PGS (through the
//! bodies or through W), Newton, clarabel; the natural-map, Coulomb and Siconos measures.

use super::*;

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
    /// `solve_newton_twins` only: the contacts left out of the answer (λ = 0 there; ascending,
    /// empty where the answer is a Newton run's on the whole problem). Empty for the others.
    pub left_out: Vec<usize>,
    /// `solve_newton_twins` only: the near-duplicate pairs found at the stalled answer
    /// (contact numbers, ascending). Empty for the others.
    pub pairs: Vec<(usize, usize)>,
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
        left_out: Vec::new(),
        pairs: Vec::new(),
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
/// replaces the problem's λ0 (None keeps it: the step's own warm start); order "sequential"
/// (also "found"), "random" (seeded by `seed`), "coloured" (docs/contact.md §"Coloured order") or "random_coloured" (§"Random coloured order"; on the local form the random order); local "rows" (the assignment's) or "exact". With the settings of
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
        "sequential" | "found" => ContactOrder::Sequential,
        "random" => ContactOrder::Random,
        "coloured" => ContactOrder::Coloured,
        "random_coloured" => ContactOrder::RandomColoured,
        o => {
            return Err(errors::problem(format!(
                "order {o:?}: expected \"sequential\", \"random\", \"coloured\" or \"random_coloured\""
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

/// The exact solver (src/solve/newton/, docs/contact.md §"Newton solver"): semismooth Newton
/// on the Alart–Curnier function with a proximal-point fallback, to `tolerance` (m/s).
/// `regularised`: the plain runs' Newton matrix regularised by ε = (‖F‖∞ / max|b|)^1.5
/// (`solve-problems --solver newton-regularised`; §"Newton solver", **Regularisation
/// following ‖F‖**).
#[pyfunction]
#[pyo3(signature = (problem, max_iterations = 50, tolerance = 1e-10, proximal_iterations = 60, warm_start = None, regularised = false))]
pub fn solve_newton(
    py: Python<'_>,
    problem: &ContactProblem,
    max_iterations: u32,
    tolerance: f64,
    proximal_iterations: u32,
    warm_start: Option<&Bound<'_, PyAny>>,
    regularised: bool,
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
        regularisation: regularised.then_some(Regularisation::MEASURED),
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

/// The exact solver with near-duplicate contacts left out (src/solve/twins.rs, docs/contact.md
/// §"Near-duplicate contacts left out"; `rigidref solve-problems --solver newton-twins`): Newton
/// on the problem's local form, restarted `restarts` times from its own answer, then, where it
/// still stalls, without one contact of each near-duplicate pair (normal rows of W with cosine
/// above 1 − 1e-8), at most `rounds` reduced problems. Every stage stops where the answer's
/// error on the whole problem is at most `tolerance`: Siconos' error (`siconos_error`) for the
/// Coulomb cone and for 2D, the residual over max(‖b‖, ‖w‖) for box friction in 3D, as
/// `solve-problems` measures it. `max_iterations` and `proximal_iterations` are each Newton
/// run's. `.method` is "twins" where contacts were left out (`.left_out`, with `.pairs`);
/// `.converged` is the stop rule's (that error ≤ `tolerance`, as `solve-problems` reports
/// it), not Newton's own 1e-10 m/s test on `.residual`.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
#[pyo3(signature = (problem, tolerance = 1e-8, max_iterations = 200, proximal_iterations = 60, restarts = 1, rounds = 8, warm_start = None))]
pub fn solve_newton_twins(
    py: Python<'_>,
    problem: &ContactProblem,
    tolerance: f64,
    max_iterations: u32,
    proximal_iterations: u32,
    restarts: u32,
    rounds: u32,
    warm_start: Option<&Bound<'_, PyAny>>,
) -> PyResult<Solution> {
    if tolerance.is_nan() || tolerance <= 0.0 {
        return Err(errors::problem(format!(
            "tolerance {tolerance}: expected a positive number"
        )));
    }
    let settings = TwinSettings {
        newton: NewtonSettings {
            max_iterations,
            proximal_iterations,
            ..Default::default()
        },
        restarts,
        rounds,
        tolerance,
        ..TwinSettings::default()
    };
    match &problem.inner {
        AnyProblem::P3(p) => run_twins(py, &p.to_local(), warm_start, &settings),
        AnyProblem::P2(p) => run_twins(py, &p.to_local(), warm_start, &settings),
        AnyProblem::L3(p) => run_twins(py, p, warm_start, &settings),
        AnyProblem::L2(p) => run_twins(py, p, warm_start, &settings),
    }
}

/// [`solve_newton_twins`] on a local problem, stopped on `solve-problems`' error.
fn run_twins<const R: usize>(
    py: Python<'_>,
    p: &LocalProblem<R>,
    warm_start: Option<&Bound<'_, PyAny>>,
    settings: &TwinSettings,
) -> PyResult<Solution> {
    let p = warm(p, warm_start)?;
    let (done, lambda, error) = py.detach(|| {
        let q_norm = p.dense_q().norm();
        let mut error = |l: &[SVector<f64, R>]| library_error_given(&p, l, q_norm);
        let mut lambda = Vec::new();
        let done = solve_twins_local_until(&p, settings, &mut error, &mut lambda);
        let e = error(&lambda);
        (done, lambda, e)
    });
    let mut s = solution(py, &done.report, &lambda);
    s.converged = error <= settings.tolerance;
    if !done.left_out.is_empty() {
        s.method = "twins".into();
    }
    s.left_out = done.left_out;
    s.pairs = done.pairs;
    Ok(s)
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
            left_out: Vec::new(),
            pairs: Vec::new(),
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
