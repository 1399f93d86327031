//! rigidref from Python: the native part of the `rigidref` package (`rigidref._rigidref`).
//! docs/python.md describes the API; the package's `__init__.py` re-exports what is here and
//! adds the pure-Python trace writer.
//!
//! Everything here is a thin layer over the library: a scene is loaded and stepped by the same
//! functions as `rigidref run`, problems are the library's [`rigidref::problem::ContactProblem`],
//! the solvers, residuals and criteria are the library's, and compare and grade are the
//! library's `tools::grading::compare` and `tools::grading::grade`. Arrays cross as float64 numpy arrays in C order;
//! errors cross as the exception hierarchy of [`errors`], carrying the CLI's one-line messages.

mod arrays;
mod errors;
mod grading;
mod problem;
mod validation;
mod world;

use pyo3::prelude::*;

/// The native module. Its classes and functions are documented where they are defined.
#[pymodule]
fn _rigidref(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    m.add_class::<world::World>()?;
    m.add_class::<world::Solve>()?;
    m.add_class::<problem::ContactProblem>()?;
    m.add_class::<problem::Solution>()?;
    m.add_class::<arrays::CooMatrix>()?;
    m.add_function(wrap_pyfunction!(problem::solvers::solve_pgs, m)?)?;
    m.add_function(wrap_pyfunction!(problem::solvers::solve_newton, m)?)?;
    m.add_function(wrap_pyfunction!(problem::solvers::solve_newton_twins, m)?)?;
    m.add_function(wrap_pyfunction!(problem::solvers::solve_clarabel, m)?)?;
    m.add_function(wrap_pyfunction!(problem::solvers::residual, m)?)?;
    m.add_function(wrap_pyfunction!(problem::solvers::coulomb_residual, m)?)?;
    m.add_function(wrap_pyfunction!(problem::solvers::criteria, m)?)?;
    m.add_function(wrap_pyfunction!(problem::solvers::siconos_error, m)?)?;
    m.add_function(wrap_pyfunction!(grading::compare_traces, m)?)?;
    m.add_function(wrap_pyfunction!(grading::grade, m)?)?;
    m.add_function(wrap_pyfunction!(validation::validate, m)?)?;
    m.add("DENSE_LIMIT", arrays::DENSE_LIMIT)?;
    Ok(())
}
