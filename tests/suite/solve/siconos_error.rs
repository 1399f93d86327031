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

/// The cases of tests/data/siconos_error/errors.json: each problem file (under tests/data), the
/// stacked λ Siconos judged and the error it computed (norm = ‖q‖).
fn siconos_cases() -> Vec<(String, Vec<f64>, f64)> {
    let folder = common::project_root().join("tests/data");
    let text = std::fs::read_to_string(folder.join("siconos_error/errors.json")).unwrap();
    let data: serde_json::Value = serde_json::from_str(&text).unwrap();
    (data["cases"].as_array().unwrap().iter())
        .map(|case| {
            let lambda = (case["lambda"].as_array().unwrap().iter())
                .map(|v| v.as_f64().unwrap())
                .collect();
            let file = case["file"].as_str().unwrap().to_string();
            (file, lambda, case["error_norm_q"].as_f64().unwrap())
        })
        .collect()
}

#[test]
fn siconos_error_equals_the_value_siconos_computed() {
    let folder = common::project_root().join("tests/data");
    let (mut three, mut two) = (0, 0);
    for (file, lambda, want) in siconos_cases() {
        let file = file.as_str();
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

/// Siconos' error measures of `lambda` (stacked) on `problem`, with q and w = W λ + q stacked.
fn measures_q_and_w<const R: usize>(
    problem: &LocalProblem<R>,
    lambda: &[f64],
) -> (
    rigidref::solve::residual::SiconosErrorMeasures,
    nalgebra::DVector<f64>,
    Vec<f64>,
) {
    let lam = impulses::<R>(lambda);
    let w = problem
        .velocity(&lam)
        .iter()
        .flat_map(|v| v.iter().copied())
        .collect();
    (
        rigidref::solve::residual::siconos_error_measures(problem, &lam),
        problem.dense_q(),
        w,
    )
}

/// The ‖q‖-normalised (Siconos 4.1–4.3) and absolute measures of the same non-solutions: the
/// absolute error is Siconos 4.4's error times max(‖q‖, ‖λ‖, ‖w‖), and the ‖q‖-normalised one
/// is it over ‖q‖, with the norms recomputed here from W, q and λ. Their ratio to Siconos' own
/// value is exact up to the division's rounding and the norms' summation order (1e-13).
#[test]
fn the_q_normalised_and_absolute_errors_are_siconos_error_times_its_denominator() {
    let folder = common::project_root().join("tests/data");
    let mut larger_than_q = 0;
    for (file, lambda, want) in siconos_cases() {
        let file = file.as_str();
        let (measures, q, w) = match read_dat(&folder.join(file)).unwrap() {
            AnyLocalProblem::Three(p) => measures_q_and_w(&p, &lambda),
            AnyLocalProblem::Two(p) => measures_q_and_w(&p, &lambda),
        };
        let l = lambda;
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let q_norm = q.norm();
        let scale = q_norm.max(norm(&l)).max(norm(&w));
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-13 * b.abs();
        assert!(
            close(measures.relative(), want),
            "{file}: {measures:?} vs {want:e}"
        );
        assert!(
            close(measures.absolute, want * scale),
            "{file}: absolute {measures:?}"
        );
        assert!(
            close(measures.q_normalised(), want * scale / q_norm),
            "{file}: ‖q‖-normalised {measures:?}"
        );
        assert!(measures.q_normalised() >= measures.relative());
        if scale > 1.000001 * q_norm {
            larger_than_q += 1;
        }
    }
    // At least one case where ‖λ‖ or ‖w‖ exceeds ‖q‖, so that the two relative measures differ.
    assert!(larger_than_q >= 1, "no case tells the two measures apart");
}

/// Siconos' measures are divided by their denominator only above machine epsilon (Siconos'
/// `if (norm > DBL_EPSILON) error /= norm`), at the boundary to the ulp: a denominator of
/// exactly `f64::EPSILON` leaves the error as it is, the next double up divides it. Kills the
/// mutant `residual.rs:314:11` (`>` → `>=`).
#[test]
fn siconos_measures_are_divided_only_above_machine_epsilon() {
    use rigidref::solve::residual::SiconosErrorMeasures;
    let above = f64::EPSILON.next_up();
    let at = SiconosErrorMeasures {
        absolute: 1e-20,
        q_norm: f64::EPSILON,
        scale: f64::EPSILON,
    };
    assert_eq!((at.relative(), at.q_normalised()), (1e-20, 1e-20));
    let over = SiconosErrorMeasures {
        absolute: 1e-20,
        q_norm: above,
        scale: above,
    };
    assert_eq!(
        (over.relative(), over.q_normalised()),
        (1e-20 / above, 1e-20 / above)
    );
    let below = SiconosErrorMeasures {
        absolute: 1e-20,
        q_norm: f64::EPSILON.next_down(),
        scale: 0.0,
    };
    assert_eq!((below.relative(), below.q_normalised()), (1e-20, 1e-20));
}
