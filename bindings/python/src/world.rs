//! `rigidref.World`: a 3D scene or a 2D image loaded and stepped by the same library functions
//! as `rigidref run`, its state, its contacts and its solves as arrays.

use crate::arrays;
use crate::errors;
use crate::problem::{AnyProblem, ContactProblem, Solution, criteria_dict, lambda_array, solution};
use numpy::PyArray2;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rigidref::blocks2d::scene::{LoadOptions2, is_2d_scene, load_2d};
use rigidref::blocks2d::world::World2;
use rigidref::common::scene_json::Overrides;
use rigidref::rigid3d::scene::load_scene_with;
use rigidref::rigid3d::world::World as World3;
use rigidref::sim::{ContactGeometry, Simulation, SubstepSolve};
use rigidref::solve::SolverSettings;
use std::path::PathBuf;

/// How long `World.step` runs without looking for a signal (Ctrl-C).
const CHECK_EVERY: std::time::Duration = std::time::Duration::from_millis(200);

/// The system inside.
enum System {
    D3(Box<World3>),
    D2(Box<World2>),
}

/// A scene, loaded and ready to step: a 3D scene file (the assignment's JSON) or a 2D image or
/// 2D scene file, exactly as `rigidref run` loads it. One thread at a time: another thread that
/// touches the world while it steps gets a RuntimeError ("Already borrowed").
#[pyclass(module = "rigidref")]
pub struct World {
    system: System,
    source: String,
    warnings: Vec<String>,
    /// Why the world cannot step on: a step ended in a non-finite state (the message raised).
    failed: Option<String>,
}

/// The `--set KEY=VALUE` texts of an overrides dict: a str value as it is, anything else as JSON
/// (Python's json.dumps), so that {"pgs_iterations": 50} is `--set pgs_iterations=50`.
pub(crate) fn override_texts(overrides: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<String>> {
    let Some(dict) = overrides else {
        return Ok(Vec::new());
    };
    let json = dict.py().import("json")?;
    let mut texts = Vec::new();
    for (key, value) in dict.iter() {
        let key: String = key
            .extract()
            .map_err(|_| errors::scene(format!("overrides: key {key}: expected a str")))?;
        let value: String = match value.extract::<String>() {
            Ok(s) => s,
            Err(_) => json
                .call_method1("dumps", (value,))
                .map_err(|e| errors::scene(format!("overrides: {key}: {}", e.value(dict.py()))))?
                .extract()?,
        };
        texts.push(format!("{key}={value}"));
    }
    Ok(texts)
}

#[pymethods]
impl World {
    /// Loads a scene: a 3D scene file (with its body files beside it), a PNG image or a 2D
    /// scene file. `overrides` is a dict of the CLI's `--set KEY=VALUE` pairs (scene parameters,
    /// docs/scene-format.md), e.g. {"pgs_iterations": 50, "friction_model": "cone"}. Raises
    /// SceneError with the CLI's message when the scene cannot be loaded.
    #[staticmethod]
    #[pyo3(signature = (path, overrides = None))]
    fn load(path: PathBuf, overrides: Option<&Bound<'_, PyDict>>) -> PyResult<World> {
        let overrides = Overrides::parse(&override_texts(overrides)?).map_err(errors::scene)?;
        let source = path.display().to_string();
        if is_2d_scene(&path) {
            let cli = LoadOptions2 {
                overrides,
                ..Default::default()
            };
            let scene = load_2d(&path, &cli).map_err(|e| errors::scene(e.0))?;
            scene
                .world
                .check_finite()
                .map_err(|e| errors::scene(format!("{source}: {e}")))?;
            return Ok(World {
                system: System::D2(Box::new(scene.world)),
                source,
                warnings: scene.warnings,
                failed: None,
            });
        }
        let scene = load_scene_with(&path, &overrides).map_err(|e| errors::scene(e.0))?;
        let world = World3::new(&scene).map_err(errors::scene)?;
        Ok(World {
            system: System::D3(Box::new(world)),
            source,
            warnings: scene.warnings,
            failed: None,
        })
    }

    /// Steps the world `n` times (the interpreter's lock is released meanwhile). A state that
    /// becomes non-finite raises SceneError saying which quantity of which body, at which step;
    /// the world then holds that state (inspect it with `state()`) and refuses further steps
    /// with the same error. Ctrl-C (KeyboardInterrupt) is honoured between
    /// steps, at most about 0.2 s late; the world keeps the steps done.
    #[pyo3(signature = (n = 1))]
    fn step(&mut self, py: Python<'_>, n: u64) -> PyResult<()> {
        if let Some(why) = &self.failed {
            return Err(errors::scene(why.clone()));
        }
        let source = &self.source;
        let system = &mut self.system;
        let mut done = 0;
        while done < n {
            // Steps for up to CHECK_EVERY without the interpreter, then look for a signal.
            let ran = match py.detach(|| -> Result<u64, String> {
                let start = std::time::Instant::now();
                let mut ran = 0;
                while done + ran < n && (ran == 0 || start.elapsed() < CHECK_EVERY) {
                    match system {
                        System::D3(w) => w.step(),
                        System::D2(w) => w.step(),
                    }
                    .map_err(|e| format!("{source}: the run stopped: {e}"))?;
                    ran += 1;
                }
                Ok(ran)
            }) {
                Ok(ran) => ran,
                Err(why) => {
                    self.failed = Some(why.clone());
                    return Err(errors::scene(why));
                }
            };
            done += ran;
            py.check_signals()?;
        }
        Ok(())
    }

    /// 3 for a 3D scene, 2 for a 2D one.
    #[getter]
    fn dimension(&self) -> u32 {
        match self.system {
            System::D3(_) => 3,
            System::D2(_) => 2,
        }
    }
    /// Simulated time, s (2D: the image's time unit).
    #[getter]
    fn time(&self) -> f64 {
        match &self.system {
            System::D3(w) => w.time(),
            System::D2(w) => w.time(),
        }
    }
    /// The step length, s.
    #[getter]
    fn dt(&self) -> f64 {
        match &self.system {
            System::D3(w) => w.dt(),
            System::D2(w) => w.dt(),
        }
    }
    /// Steps done.
    #[getter]
    fn steps(&self) -> u64 {
        match &self.system {
            System::D3(w) => w.steps_done(),
            System::D2(w) => w.steps_done(),
        }
    }
    /// The scene's path, as given.
    #[getter]
    fn source(&self) -> &str {
        &self.source
    }
    /// What loading the scene warned about (unknown keys, conditions outside the assignment's
    /// method), as the CLI prints them.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }
    /// The bodies' names (3D: the scene's; 2D: "body K").
    #[getter]
    fn body_names(&self) -> Vec<String> {
        match &self.system {
            System::D3(w) => w.bodies.iter().map(|b| b.name.clone()).collect(),
            System::D2(w) => (0..w.bodies.len()).map(|k| format!("body {k}")).collect(),
        }
    }

    /// The state as arrays (float64): 3D "x" (bodies × 3, m), "R" (bodies × 3 × 3, body to
    /// world), "v" (m/s), "omega" (rad/s, world frame); 2D "x" (bodies × 2), "q" (angle, rad),
    /// "v", "omega" (bodies); both "time", "step", "energy" and "momentum" (dicts, the
    /// trace's definitions: docs/dynamics.md §"Energy and momentum").
    fn state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("time", self.time())?;
        d.set_item("step", self.steps())?;
        let energy = PyDict::new(py);
        let momentum = PyDict::new(py);
        match &self.system {
            System::D3(w) => {
                let n = w.bodies.len();
                let flat3 = |f: &dyn Fn(&rigidref::rigid3d::body::RigidBody) -> [f64; 3]| {
                    arrays::matrix(py, n, 3, w.bodies.iter().flat_map(f).collect())
                };
                d.set_item("x", flat3(&|b| b.x.into()))?;
                d.set_item("v", flat3(&|b| b.v.into()))?;
                d.set_item("omega", flat3(&|b| b.omega.into()))?;
                let r: Vec<f64> = w
                    .bodies
                    .iter()
                    .flat_map(|b| (0..3).flat_map(move |i| (0..3).map(move |j| b.rotation[(i, j)])))
                    .collect();
                let r = numpy::ndarray::Array3::from_shape_vec((n, 3, 3), r).expect("n × 3 × 3");
                d.set_item("R", numpy::IntoPyArray::into_pyarray(r, py))?;
                let e = w.energy();
                energy.set_item("kinetic_linear", e.kinetic_linear)?;
                energy.set_item("kinetic_angular", e.kinetic_angular)?;
                energy.set_item("potential", e.potential)?;
                energy.set_item("total", e.total)?;
                let m = w.momentum();
                momentum.set_item(
                    "linear",
                    arrays::vector(py, m.linear.iter().copied().collect()),
                )?;
                momentum.set_item(
                    "angular",
                    arrays::vector(py, m.angular.iter().copied().collect()),
                )?;
                momentum.set_item(
                    "angular_com",
                    arrays::vector(py, m.angular_com.iter().copied().collect()),
                )?;
            }
            System::D2(w) => {
                let n = w.bodies.len();
                let pairs = |f: &dyn Fn(&rigidref::blocks2d::body::Body2) -> [f64; 2]| {
                    arrays::matrix(py, n, 2, w.bodies.iter().flat_map(f).collect())
                };
                let scalars = |f: &dyn Fn(&rigidref::blocks2d::body::Body2) -> f64| {
                    arrays::vector(py, w.bodies.iter().map(f).collect())
                };
                d.set_item("x", pairs(&|b| [b.x.x, b.x.y]))?;
                d.set_item("q", scalars(&|b| b.theta))?;
                d.set_item("v", pairs(&|b| [b.v.x, b.v.y]))?;
                d.set_item("omega", scalars(&|b| b.omega))?;
                let e = w.energy();
                energy.set_item("kinetic", e.kinetic)?;
                energy.set_item("potential", e.potential)?;
                energy.set_item("total", e.total)?;
                let m = w.momentum();
                momentum.set_item("linear", arrays::vector(py, m.linear.to_vec()))?;
                momentum.set_item("angular", m.angular)?;
            }
        }
        d.set_item("energy", energy)?;
        d.set_item("momentum", momentum)?;
        Ok(d)
    }

    /// The contacts of the last solve of the last step (its last substep with contacts), as
    /// arrays: "bodies" (contacts × 2, int64; 3D: −1 is the ground; 2D: pinned bodies are bodies), "point" (world
    /// frame), "normal" (from the second body into the first), "depth" (penetration, m), "lam"
    /// (the impulses applied, contacts × R, N·s). Empty arrays when the step had no contact.
    fn contacts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        match &self.system {
            System::D3(w) => {
                let bodies = |c: &rigidref::rigid3d::collide::vertex_contact::Contact| {
                    [c.body1 as i64, c.body2.map_or(-1, |b| b as i64)]
                };
                contacts_dict(py, w.solves.last(), 3, bodies)
            }
            System::D2(w) => {
                let bodies =
                    |c: &rigidref::blocks2d::collide::Contact2| [c.body1 as i64, c.body2 as i64];
                contacts_dict(py, w.solves.last(), 2, bodies)
            }
        }
    }

    /// The contact solves of the last step, one per substep that had contacts: each a Solve
    /// with its problem (.problem: J, Minv, A, b, mu, ...), the λ the step applied (.lam), the
    /// solver's report and the physical criteria.
    fn last_solves(&self, py: Python<'_>) -> PyResult<Vec<Solve>> {
        match &self.system {
            System::D3(w) => w
                .solves
                .iter()
                .map(|s| Solve::of(py, s, AnyProblem::P3(s.problem.clone())))
                .collect(),
            System::D2(w) => w
                .solves
                .iter()
                .map(|s| Solve::of(py, s, AnyProblem::P2(s.problem.clone())))
                .collect(),
        }
    }

    /// The solver settings the steps use, as keyword arguments of solve_pgs ("pgs") and
    /// solve_newton ("newton"), and which one the scene picked ("solver"). solve_pgs with
    /// "pgs" reproduces a step's λ to the bit when the step used PGS in sequential order (the
    /// default): a random order's generator has moved on from its seed by then.
    fn solver_settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s: SolverSettings = match &self.system {
            System::D3(w) => w.solver_settings(),
            System::D2(w) => w.solver_settings(),
        };
        let d = PyDict::new(py);
        d.set_item("solver", s.solver.name())?;
        let pgs = PyDict::new(py);
        pgs.set_item("iterations", s.pgs.max_iterations)?;
        pgs.set_item("tolerance", s.pgs.tolerance)?;
        pgs.set_item(
            "order",
            match s.pgs.order {
                rigidref::solve::ContactOrder::Sequential => "sequential",
                rigidref::solve::ContactOrder::Random => "random",
                rigidref::solve::ContactOrder::Coloured => "coloured",
                rigidref::solve::ContactOrder::RandomColoured => "random_coloured",
            },
        )?;
        pgs.set_item("local", s.pgs.local.name())?;
        d.set_item("pgs", pgs)?;
        let newton = PyDict::new(py);
        newton.set_item("max_iterations", s.newton.max_iterations)?;
        newton.set_item("tolerance", s.newton.tolerance)?;
        newton.set_item("proximal_iterations", s.newton.proximal_iterations)?;
        d.set_item("newton", newton)?;
        Ok(d)
    }

    fn __repr__(&self) -> String {
        format!(
            "World({:?}, {}D, {} bodies, t = {} s)",
            self.source,
            self.dimension(),
            self.body_names().len(),
            self.time()
        )
    }
}

/// The contacts of one solve as a dict of arrays (see `World.contacts`).
fn contacts_dict<'py, C: ContactGeometry, const D: usize, const R: usize>(
    py: Python<'py>,
    solve: Option<&SubstepSolve<C, D, R>>,
    dim: usize,
    bodies: impl Fn(&C) -> [i64; 2],
) -> PyResult<Bound<'py, PyDict>> {
    let empty = [];
    let (contacts, lambda) =
        solve.map_or((&empty[..], &[][..]), |s| (&s.contacts[..], &s.lambda[..]));
    let k = contacts.len();
    let d = PyDict::new(py);
    let pairs: Vec<i64> = contacts.iter().flat_map(&bodies).collect();
    d.set_item(
        "bodies",
        numpy::IntoPyArray::into_pyarray(
            numpy::ndarray::Array2::from_shape_vec((k, 2), pairs).expect("pairs"),
            py,
        ),
    )?;
    d.set_item(
        "point",
        arrays::matrix(
            py,
            k,
            dim,
            contacts.iter().flat_map(|c| c.point()).collect(),
        ),
    )?;
    d.set_item(
        "normal",
        arrays::matrix(
            py,
            k,
            dim,
            contacts.iter().flat_map(|c| c.normal()).collect(),
        ),
    )?;
    d.set_item(
        "depth",
        arrays::vector(py, contacts.iter().map(|c| c.depth()).collect()),
    )?;
    let lam: Bound<'py, PyArray2<f64>> = lambda_array(py, lambda);
    d.set_item("lam", lam)?;
    Ok(d)
}

/// One contact solve of a step: the problem, the λ the step applied and what the solver said.
#[pyclass(module = "rigidref", frozen, get_all)]
pub struct Solve {
    /// The substep within its step (0-based).
    pub substep: u32,
    /// The contact problem the step assembled.
    pub problem: Py<ContactProblem>,
    /// λ the step applied (contacts × R, N·s).
    pub lam: Py<PyArray2<f64>>,
    /// Iterations (PGS sweeps or Newton iterations).
    pub iterations: u32,
    /// The residual of λ (m/s).
    pub residual: f64,
    /// Whether the solver's tolerance was given and reached (Newton: converged).
    pub converged: bool,
    /// For cone friction, the exact Coulomb residual (m/s).
    pub coulomb_residual: Option<f64>,
    /// "pgs", "newton", "proximal" or "pgs_shock".
    pub method: String,
    /// The physical criteria of λ (see rigidref.criteria).
    pub criteria: Py<PyDict>,
    /// Wall time of the solve, s.
    pub solve_seconds: f64,
}

impl Solve {
    fn of<C, const D: usize, const R: usize>(
        py: Python<'_>,
        s: &SubstepSolve<C, D, R>,
        problem: AnyProblem,
    ) -> PyResult<Solve> {
        let Solution {
            lam,
            iterations,
            residual,
            converged,
            coulomb_residual,
            method,
            ..
        } = solution(py, &s.report, &s.lambda);
        let (each, max) = rigidref::solve::criteria::criteria(&s.problem, &s.lambda);
        Ok(Solve {
            substep: s.substep,
            problem: Py::new(py, ContactProblem { inner: problem })?,
            lam,
            iterations,
            residual,
            converged,
            coulomb_residual,
            method,
            criteria: criteria_dict(py, &each, &max)?.unbind(),
            solve_seconds: s.solve_seconds,
        })
    }
}

#[pymethods]
impl Solve {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "Solve(substep={}, contacts={}, method={:?}, iterations={}, residual={:e})",
            self.substep,
            self.problem.borrow(py).inner_contacts(),
            self.method,
            self.iterations,
            self.residual
        )
    }
}

impl ContactProblem {
    fn inner_contacts(&self) -> usize {
        crate::problem::with_problem!(&self.inner, p => rigidref::problem::ProblemView::count(p))
    }
}
