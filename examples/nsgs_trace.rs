//! NSGS (PGS with exact local solves, problem order) on one problem file, one line per sweep:
//! the sweep, the change of λ over it relative to ‖λ‖ (Siconos' "light" error) and Siconos'
//! error; it stops where Siconos' error is at most 1e-8. docs/contact.md §"Automatic choice:
//! NSGS, then Newton", **The first version, and why it changed**.
//!
//!     cargo run --release --features fclib --example nsgs_trace -- Confeti-ex13-Fc3D-SBM.dat [SWEEPS]
use nalgebra::SVector;
use rigidref::problem::LocalProblem;
use rigidref::problem::siconos::AnyLocalProblem;
use rigidref::solve::local::LocalSolve;
use rigidref::solve::pgs::{ContactOrder, PgsSettings};
use rigidref::solve::pgs_delassus::solve_pgs_local_until;
use rigidref::tools::experiments::problem_library::{library_error, load};

fn run<const R: usize>(p: &LocalProblem<R>, sweeps: u32) {
    let s = PgsSettings {
        max_iterations: sweeps,
        tolerance: None,
        order: ContactOrder::Sequential,
        local: LocalSolve::Exact,
    };
    let mut prev: Vec<SVector<f64, R>> = Vec::new();
    let mut k = 0;
    let mut stop = |l: &[SVector<f64, R>]| {
        k += 1;
        let (mut d2, mut n2) = (0.0, 0.0);
        if !prev.is_empty() {
            for (a, b) in l.iter().zip(prev.iter()) {
                d2 += (a - b).norm_squared();
                n2 += a.norm_squared();
            }
        }
        prev = l.to_vec();
        let e = library_error(p, l);
        println!("{k} {:.3e} {:.3e}", d2.sqrt() / n2.sqrt().max(1e-300), e);
        e <= 1e-8
    };
    let mut lambda = Vec::new();
    solve_pgs_local_until(p, &s, 0, &mut stop, &mut lambda);
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let sweeps = match a.get(2).map(|s| s.parse::<u32>()) {
        None => 2000,
        Some(Ok(n)) => n,
        Some(Err(e)) => {
            eprintln!("nsgs_trace: SWEEPS {:?}: {e}", a[2]);
            std::process::exit(2)
        }
    };
    let Some(path) = a.get(1) else {
        eprintln!("usage: nsgs_trace PROBLEM_FILE [SWEEPS]");
        std::process::exit(2);
    };
    let problem = load(std::path::Path::new(path)).unwrap_or_else(|e| {
        eprintln!("nsgs_trace: {e}");
        std::process::exit(1)
    });
    match problem {
        AnyLocalProblem::Three(p) => run(&p, sweeps),
        AnyLocalProblem::Two(p) => run(&p, sweeps),
    }
}
