//! Siconos `.dat` problem files (src/problem/siconos.rs): parse, and solve a valid small one
//! with a few PGS sweeps on W and the Newton solver, and take Siconos' error. Nothing may panic.
#![no_main]
use libfuzzer_sys::fuzz_target;
use rigidref::problem::siconos::{AnyLocalProblem, parse_dat};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(problem) = parse_dat(text) else { return };
    if problem.contacts() > 64 {
        return;
    }
    use rigidref::solve::*;
    let pgs = PgsSettings {
        max_iterations: 20,
        tolerance: None,
        order: ContactOrder::Sequential,
        local: LocalSolve::Exact,
    };
    let newton = NewtonSettings { max_iterations: 20, proximal_iterations: 5, ..Default::default() };
    match problem {
        AnyLocalProblem::Three(p) => {
            let mut lambda = Vec::new();
            let _ = solve_pgs_local(&p, &pgs, 0, &mut lambda);
            let _ = residual::siconos_error(&p, &lambda);
            let _ = solve_newton_local(&p, &newton, &mut lambda);
            let _ = rigidref::problem::siconos::write_dat(&p);
        }
        AnyLocalProblem::Two(p) => {
            let mut lambda = Vec::new();
            let _ = solve_pgs_local(&p, &pgs, 0, &mut lambda);
            let _ = solve_newton_local(&p, &newton, &mut lambda);
        }
    }
});
