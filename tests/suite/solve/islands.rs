//! The coloured solve island by island (docs/contact.md §"Island by island"): batches of whole
//! islands swept one after another give the bits of the sweeps over every contact.

use super::lanes::{Numbers, random_problem};
use nalgebra::SVector;
use rigidref::problem::{ContactProblem, FrictionModel, SolveReport};
use rigidref::solve::pgs::Lanes;
use rigidref::solve::{ContactOrder, LocalSolve, PgsSettings, PgsWorkspace};

/// `copies` copies of `problem`, each with its own moving bodies but all sharing the first
/// copy's pinned bodies (which join no islands, so that islands of different batches share
/// them), their contacts interleaved (copy c's contact i at position i · copies + c), so that
/// the islands' contacts alternate in problem order instead of following one another.
fn interleaved<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    copies: usize,
) -> ContactProblem<D, R> {
    let n = problem.bodies.len();
    let mut out = problem.clone();
    out.bodies = (0..copies)
        .flat_map(|_| problem.bodies.iter().cloned())
        .collect();
    out.contacts = (problem.contacts.iter())
        .flat_map(|c| {
            (0..copies).map(move |copy| {
                let mut c = c.clone();
                let pinned = |b: usize| problem.bodies[b].inverse_mass.iter().all(|&m| m == 0.0);
                c.bodies = c
                    .bodies
                    .map(|b| b.map(|b| if pinned(b) { b } else { b + copy * n }));
                c
            })
        })
        .collect();
    out
}

/// λ, Δu, the report, the batches and the groups of four of a one-thread solve of 12 sweeps,
/// no tolerance, batches of at most `batch` contacts (`None`: not batched).
fn solve<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    order: ContactOrder,
    local: LocalSolve,
    lanes: Lanes,
    batch: Option<usize>,
) -> (Vec<[u64; R]>, Vec<[u64; D]>, SolveReport, usize, usize) {
    let mut workspace = PgsWorkspace::new(5);
    workspace.set_lanes(lanes);
    workspace.set_batch_contacts(batch);
    let settings = PgsSettings {
        max_iterations: 12,
        tolerance: None,
        order,
        local,
    };
    let mut lambda = Vec::new();
    let report = rigidref::solve::solve_pgs(problem, &settings, &mut workspace, &mut lambda);
    let bits = |v: &SVector<f64, R>| std::array::from_fn(|i| v[i].to_bits());
    let du = (0..problem.bodies.len())
        .map(|b| std::array::from_fn(|i| workspace.delta_velocity(b)[i].to_bits()))
        .collect();
    (
        lambda.iter().map(bits).collect(),
        du,
        report,
        workspace.last_batches(),
        workspace.last_groups(),
    )
}

fn same_bits_island_by_island<const D: usize, const R: usize>(seed: u64) {
    let mut numbers = Numbers(seed);
    for friction in [FrictionModel::Box, FrictionModel::Cone] {
        for case in 0..3 {
            let problem = interleaved(&random_problem::<D, R>(&mut numbers, 12, 40, friction), 6);
            for order in [ContactOrder::Coloured, ContactOrder::RandomColoured] {
                for local in [LocalSolve::Rows, LocalSolve::Exact] {
                    for lanes in [Lanes::Native, Lanes::Off] {
                        let what = format!(
                            "{D}×{R} {friction:?} case {case} {order:?} {local:?} {lanes:?}"
                        );
                        let whole = solve(&problem, order, local, lanes, None);
                        assert_eq!(whole.3, 1, "{what}: batched with batching off");
                        // 1: every island a batch of its own; 90: two or three copies a batch.
                        for batch in [1, 90] {
                            let batched = solve(&problem, order, local, lanes, Some(batch));
                            assert!(batched.3 >= 3, "{what}, {batch}: {} batches", batched.3);
                            // Row by row with lanes on, most contacts go in groups of four.
                            let grouped = lanes == Lanes::Native && local == LocalSolve::Rows;
                            assert_eq!(batched.4 > 0, grouped, "{what}, {batch}: groups");
                            assert!(batched.0 == whole.0, "{what}, {batch}: λ differs");
                            assert!(batched.1 == whole.1, "{what}, {batch}: Δu differs");
                            assert_eq!(batched.2.iterations, whole.2.iterations, "{what}");
                            assert_eq!(
                                batched.2.residual.to_bits(),
                                whole.2.residual.to_bits(),
                                "{what}"
                            );
                            assert_eq!(
                                batched.2.coulomb_residual.map(f64::to_bits),
                                whole.2.coulomb_residual.map(f64::to_bits),
                                "{what}"
                            );
                        }
                    }
                }
            }
        }
    }
}

/// A problem of six interleaved copies of a random problem (each copy one or more islands: its
/// pinned bodies, shared by all the copies, do not join them), solved in batches of one island
/// and in batches of about two copies: λ, every body's Δu and the report (both residuals) are
/// those of the sweeps over every contact, to the bit (tolerance zero: an island's visits read
/// nothing of another island, so they are the same arithmetic on the same values), for both
/// coloured orders, row by row and with the exact local solve, four at a time and one at a
/// time, box and cone, 3D and 2D.
#[test]
fn sweeping_island_by_island_gives_the_bits_of_sweeping_every_contact() {
    same_bits_island_by_island::<6, 3>(0x1514);
    same_bits_island_by_island::<3, 2>(0x1515);
}
