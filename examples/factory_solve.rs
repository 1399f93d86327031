//! Times PGS on contact-problem files of the 2D factory (rigidref JSON, 3 dof, 1 or 2 rows) or
//! of a 3D run (6 dof, 3 rows; `rigidref run --dump-problems`):
//! the factory's settings (20 sweeps, no tolerance, rows), each order, one and two threads,
//! median of ROUNDS solves; also the set-up alone (0 sweeps). docs/performance.md §"Issue 49:
//! the factory's velocity solve".
//!
//!     cargo run --release --example factory_solve -- velocity-problem.json [post-problem.json]

use rigidref::problem::ContactProblem;
use rigidref::problem::json::ProblemFile;
use rigidref::solve::local::LocalSolve;
use rigidref::solve::pgs::{ContactOrder, PgsSettings, PgsWorkspace, solve_pgs};
use std::time::Instant;

const ROUNDS: usize = 21;

fn time<const D: usize, const R: usize>(
    p: &ContactProblem<D, R>,
    order: ContactOrder,
    sweeps: u32,
    threads: usize,
) -> (f64, f64) {
    let settings = PgsSettings {
        max_iterations: sweeps,
        tolerance: None,
        order,
        local: LocalSolve::Rows,
    };
    let mut ws = PgsWorkspace::<D, R>::new(7);
    ws.set_threads(threads);
    let mut lambda = Vec::new();
    solve_pgs(p, &settings, &mut ws, &mut lambda);
    let mut t: Vec<f64> = (0..ROUNDS)
        .map(|_| {
            let c = Instant::now();
            solve_pgs(p, &settings, &mut ws, &mut lambda);
            c.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    t.sort_by(f64::total_cmp);
    (t[0], t[ROUNDS / 2])
}

fn report<const D: usize, const R: usize>(name: &str, p: &ContactProblem<D, R>) {
    println!(
        "{name}: {} bodies, {} contacts, {R} rows",
        p.bodies.len(),
        p.contacts.len()
    );
    let only = std::env::var("ORDER").ok();
    let max_threads: usize = std::env::var("THREADS")
        .ok()
        .and_then(|t| t.parse().ok())
        .unwrap_or(2);
    for order in [
        ContactOrder::Random,
        ContactOrder::Coloured,
        ContactOrder::RandomColoured,
        ContactOrder::Sequential,
    ] {
        if only.as_ref().is_some_and(|o| *o != format!("{order:?}")) {
            continue;
        }
        for threads in (1..=max_threads).filter(|&t| t == 1 || t == 2) {
            if threads == 2 && !order.is_coloured() {
                continue;
            }
            let full = time(p, order, 20, threads);
            let setup = time(p, order, 0, threads);
            println!(
                "  {order:?} threads {threads}: 20 sweeps {:.2} (median {:.2}) ms, set-up alone {:.2} ({:.2}) ms, sweeps {:.2} ms (of the fastest)",
                full.0,
                full.1,
                setup.0,
                setup.1,
                full.0 - setup.0
            );
        }
    }
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    for path in &args {
        let file = ProblemFile::read(std::path::Path::new(path))?;
        match (file.dof_per_body, file.rows_per_contact) {
            (6, _) => report(path, &file.to_problem::<6, 3>()?),
            (_, 1) => report(path, &file.to_problem::<3, 1>()?),
            _ => report(path, &file.to_problem::<3, 2>()?),
        }
    }
    Ok(())
}
