//! Arrays across the boundary: anything array-like in (converted by numpy to float64), numpy
//! float64 arrays in C order out, and sparse matrices as COO triplets.

use numpy::ndarray::{Array1, Array2};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::IntoPyDict;

/// A matrix with at most this many entries is returned dense (32 MB of float64); a larger one as
/// a [`CooMatrix`].
pub const DENSE_LIMIT: usize = 1 << 22;

/// `CooMatrix.to_dense` makes no matrix of more entries than this (1 GiB of float64).
pub const MAX_DENSE: usize = 1 << 27;

/// An array-like converted to float64 by `numpy.asarray`: its entries in C order and its shape.
/// Fails with a `ProblemError` naming `what` when numpy cannot make numbers of it.
pub fn numbers(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<(Vec<f64>, Vec<usize>)> {
    let py = obj.py();
    let np = py.import("numpy")?;
    let array = np.call_method1("asarray", (obj, "float64")).map_err(|e| {
        crate::errors::problem(format!("{what}: not an array of numbers ({})", e.value(py)))
    })?;
    let array: PyReadonlyArrayDyn<'_, f64> = array.extract()?;
    let shape = array.shape().to_vec();
    let data = array.as_array().iter().copied().collect();
    Ok((data, shape))
}

/// `numbers`, checked to have `shape` (a `None` entry takes any length); the message names
/// `what` and both shapes.
pub fn shaped(
    obj: &Bound<'_, PyAny>,
    what: &str,
    shape: &[Option<usize>],
) -> PyResult<(Vec<f64>, Vec<usize>)> {
    let (data, got) = numbers(obj, what)?;
    let fits = got.len() == shape.len()
        && got
            .iter()
            .zip(shape)
            .all(|(g, s)| s.is_none_or(|s| *g == s));
    if !fits {
        let want: Vec<String> = shape
            .iter()
            .map(|s| s.map_or("n".to_string(), |s| s.to_string()))
            .collect();
        return Err(crate::errors::problem(format!(
            "{what}: shape {got:?}, expected ({})",
            want.join(", ")
        )));
    }
    Ok((data, got))
}

/// A 1-D float64 array.
pub fn vector<'py>(py: Python<'py>, data: Vec<f64>) -> Bound<'py, PyArray1<f64>> {
    data.into_pyarray(py)
}

/// A 2-D float64 array, `rows` × `cols`, from entries in C order.
pub fn matrix<'py>(
    py: Python<'py>,
    rows: usize,
    cols: usize,
    data: Vec<f64>,
) -> Bound<'py, PyArray2<f64>> {
    Array2::from_shape_vec((rows, cols), data)
        .expect("rows × cols entries")
        .into_pyarray(py)
}

/// A sparse matrix as coordinate triplets (`scipy.sparse.coo_matrix((data, (row, col)), shape)`
/// reads them): what a matrix property gives when the dense matrix would have more than
/// `DENSE_LIMIT` entries. A (row, col) pair repeats only where a problem names the same body on
/// both sides of a contact; its values are then to be summed (as scipy and `to_dense` do).
#[pyclass(module = "rigidref", frozen)]
pub struct CooMatrix {
    data: Vec<f64>,
    row: Vec<i64>,
    col: Vec<i64>,
    shape: (usize, usize),
}

impl CooMatrix {
    /// From triplets (row, column, value), in any order; zero values are dropped.
    pub fn new(
        shape: (usize, usize),
        triplets: impl IntoIterator<Item = (usize, usize, f64)>,
    ) -> CooMatrix {
        let mut m = CooMatrix {
            data: Vec::new(),
            row: Vec::new(),
            col: Vec::new(),
            shape,
        };
        for (i, j, v) in triplets {
            if v != 0.0 {
                m.row.push(i as i64);
                m.col.push(j as i64);
                m.data.push(v);
            }
        }
        m
    }
}

#[pymethods]
impl CooMatrix {
    /// The nonzero values.
    #[getter]
    fn data<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.data.clone())
    }
    /// Their rows (int64).
    #[getter]
    fn row<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        Array1::from(self.row.clone()).into_pyarray(py)
    }
    /// Their columns (int64).
    #[getter]
    fn col<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        Array1::from(self.col.clone()).into_pyarray(py)
    }
    /// (rows, columns).
    #[getter]
    fn shape(&self) -> (usize, usize) {
        self.shape
    }
    /// Entries stored.
    #[getter]
    fn nnz(&self) -> usize {
        self.data.len()
    }
    /// The matrix as `scipy.sparse.coo_matrix` (needs scipy).
    fn to_scipy<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let sparse = py.import("scipy.sparse")?;
        let args = (self.data(py), (self.row(py), self.col(py)));
        sparse.call_method(
            "coo_matrix",
            (args,),
            Some(&[("shape", self.shape)].into_py_dict(py)?),
        )
    }
    /// The matrix dense (float64, C order); a ProblemError above `MAX_DENSE` entries.
    fn to_dense<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (rows, cols) = self.shape;
        if rows.saturating_mul(cols) > MAX_DENSE {
            return Err(crate::errors::problem(format!(
                "a {rows} × {cols} matrix is too large to make dense (at most {MAX_DENSE} entries, 1 GiB); use its triplets"
            )));
        }
        let mut data = vec![0.0; rows * cols];
        for ((&i, &j), &v) in self.row.iter().zip(&self.col).zip(&self.data) {
            data[i as usize * cols + j as usize] += v;
        }
        Ok(matrix(py, rows, cols, data))
    }
    fn __repr__(&self) -> String {
        format!("CooMatrix(shape={:?}, nnz={})", self.shape, self.data.len())
    }
}

/// A matrix given by triplets: dense when it has at most `DENSE_LIMIT` entries, else a
/// [`CooMatrix`].
pub fn dense_or_sparse<'py>(
    py: Python<'py>,
    shape: (usize, usize),
    triplets: Vec<(usize, usize, f64)>,
) -> PyResult<Bound<'py, PyAny>> {
    let coo = CooMatrix::new(shape, triplets);
    if shape.0.saturating_mul(shape.1) <= DENSE_LIMIT {
        Ok(coo.to_dense(py)?.into_any())
    } else {
        Ok(Bound::new(py, coo)?.into_any())
    }
}
