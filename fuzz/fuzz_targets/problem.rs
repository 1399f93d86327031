//! Contact-problem files of either form: parse, convert to a 3D or 2D problem (and the body form
//! to the local form), validate, and solve a valid one with a few PGS sweeps and the Newton
//! solver, and take its residuals. Nothing may panic.
#![no_main]
use libfuzzer_sys::fuzz_target;
use rigidref::problem::json::ProblemFile;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data)
        && let Ok(any) = rigidref::problem::local_json::AnyProblemFile::parse(text)
        && let Ok(local) = any.to_local::<3>()
        && local.contacts.len() <= 64
    {
        use rigidref::solve::*;
        let mut lambda = Vec::new();
        let pgs = PgsSettings { max_iterations: 10, tolerance: None, order: ContactOrder::Random, local: LocalSolve::Rows };
        let _ = solve_pgs_local(&local, &pgs, 1, &mut lambda);
        let newton = NewtonSettings { max_iterations: 10, proximal_iterations: 3, ..Default::default() };
        let _ = solve_newton_local(&local, &newton, &mut lambda);
        let _ = rigidref::solve::criteria::criteria(&local, &lambda);
    }
    let Ok(file) = serde_json::from_slice::<ProblemFile>(data) else { return };
    if let Ok(problem) = file.to_problem::<6, 3>() {
        if problem.validate().is_err() || problem.contacts.len() > 64 || problem.bodies.len() > 64 {
            return;
        }
        use rigidref::solve::*;
        let pgs = PgsSettings {
            max_iterations: 20,
            tolerance: None,
            order: ContactOrder::Sequential,
            local: LocalSolve::Rows,
        };
        let mut lambda = Vec::new();
        let _ = solve_pgs(&problem, &pgs, &mut PgsWorkspace::new(0), &mut lambda);
        let _ = residual(&problem, &lambda);
        let _ = rigidref::solve::residual::coulomb_residual(&problem, &lambda);
        let newton = NewtonSettings { max_iterations: 20, proximal_iterations: 5, ..Default::default() };
        let _ = solve_newton(&problem, &newton, &mut NewtonWorkspace::default(), &mut lambda);
    }
});
