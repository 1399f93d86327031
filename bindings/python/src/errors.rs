//! The exceptions: `rigidref.Error` and its kinds. Each carries the CLI's one-line message for
//! the same input (the file named first, then what is wrong).

use pyo3::create_exception;
use pyo3::prelude::*;

create_exception!(
    rigidref,
    Error,
    pyo3::exceptions::PyException,
    "Any error rigidref reports: the message is the CLI's one line for the same input."
);
create_exception!(
    rigidref,
    SceneError,
    Error,
    "A scene (3D scene file, its body files, a 2D image or scene file) that cannot be loaded, or a world that cannot be stepped on (a non-finite state)."
);
create_exception!(
    rigidref,
    ProblemError,
    Error,
    "A contact problem that is malformed: wrong shapes, non-finite numbers, a negative friction coefficient, a file that is not a problem file."
);
create_exception!(
    rigidref,
    TraceError,
    Error,
    "A trace that cannot be read, or a comparison that cannot be made (compare_traces, grade)."
);

/// Adds the exception classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("Error", py.get_type::<Error>())?;
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("ProblemError", py.get_type::<ProblemError>())?;
    m.add("TraceError", py.get_type::<TraceError>())?;
    Ok(())
}

/// A `SceneError` with `message`.
pub fn scene(message: impl std::fmt::Display) -> PyErr {
    SceneError::new_err(message.to_string())
}

/// A `ProblemError` with `message`.
pub fn problem(message: impl std::fmt::Display) -> PyErr {
    ProblemError::new_err(message.to_string())
}

/// A `TraceError` with `message`.
pub fn trace(message: impl std::fmt::Display) -> PyErr {
    TraceError::new_err(message.to_string())
}
