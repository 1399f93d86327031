//! `siconos_error` against the values Siconos itself computed (docs/problem-library.md
//! §"Siconos' error measure"): non-solutions of three 3D problems and one 2D problem, whose
//! errors Siconos 4.4's `fc3d_compute_error` and `fc2d_compute_error` gave with norm = ‖q‖
//! (tests/data/siconos_error/make_errors.py made errors.json).

use crate::common;

use nalgebra::SVector;
use rigidref::problem::LocalProblem;
use rigidref::problem::siconos::{AnyLocalProblem, read_dat};
use rigidref::solve::residual::siconos_error;

/// λ (stacked) as impulses of R rows.
fn impulses<const R: usize>(values: &[f64]) -> Vec<SVector<f64, R>> {
    values
        .chunks(R)
        .map(|c| SVector::from_iterator(c.iter().copied()))
        .collect()
}

/// rigidref's error against Siconos' `want`, to 1e-13 relative: the same sums in another
/// order (the projection and the three norms), a few ulps apart.
fn check<const R: usize>(name: &str, problem: &LocalProblem<R>, lambda: &[f64], want: f64) {
    let got = siconos_error(problem, &impulses::<R>(lambda));
    assert!(
        (got - want).abs() <= 1e-13 * want,
        "{name}: rigidref {got:e}, Siconos {want:e}"
    );
}

#[test]
fn siconos_error_equals_the_value_siconos_computed() {
    let folder = common::project_root().join("tests/data");
    let text = std::fs::read_to_string(folder.join("siconos_error/errors.json")).unwrap();
    let data: serde_json::Value = serde_json::from_str(&text).unwrap();
    let (mut three, mut two) = (0, 0);
    for case in data["cases"].as_array().unwrap() {
        let file = case["file"].as_str().unwrap();
        let lambda: Vec<f64> = case["lambda"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        let want = case["error_norm_q"].as_f64().unwrap();
        // Non-solutions: errors of order 0.1–1, not round-off of zero.
        assert!(want > 0.1, "{file}: {want}");
        match read_dat(&folder.join(file)).unwrap() {
            AnyLocalProblem::Three(p) => {
                check(file, &p, &lambda, want);
                three += 1;
            }
            AnyLocalProblem::Two(p) => {
                check(file, &p, &lambda, want);
                two += 1;
            }
        }
    }
    assert_eq!((three, two), (4, 2));
}
