//! The coloured sweep four contacts at a time (docs/contact.md §"Four contacts per lane"): the
//! one-contact-at-a-time sweep's bits, for both problem shapes and both friction models.

use nalgebra::{SMatrix, SVector};
use rigidref::problem::{ContactProblem, FrictionModel, ProblemBody, ProblemContact, RowBounds};
use rigidref::solve::{ContactOrder, LocalSolve, PgsSettings, PgsWorkspace, solve_pgs};

/// splitmix64: a small seeded generator, so the problems are the same on every run.
struct Numbers(u64);

impl Numbers {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [lo, hi).
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    /// True with probability p.
    fn chance(&mut self, p: f64) -> bool {
        self.uniform(0.0, 1.0) < p
    }
}

/// A random problem with every case a visit distinguishes: `bodies` bodies, a fifth of them
/// pinned (zero inverse mass); `contacts` contacts between two bodies, with the static world,
/// or with a pinned body; μ zero on some (a zero friction bound); compliance on some; a warm
/// start on most, its friction outside the bound on some; some rows all zero (a zero diagonal:
/// the row cannot move anything); b in [−2, 2] m/s.
fn random_problem<const D: usize, const R: usize>(
    numbers: &mut Numbers,
    bodies: usize,
    contacts: usize,
    friction: FrictionModel,
) -> ContactProblem<D, R> {
    let bodies: Vec<ProblemBody<D>> = (0..bodies)
        .map(|_| {
            let pinned = numbers.chance(0.2);
            let a = SMatrix::<f64, D, D>::from_fn(|_, _| numbers.uniform(-1.0, 1.0));
            let inverse_mass = if pinned {
                SMatrix::zeros()
            } else {
                // Symmetric positive definite, entries of order 0.01–1 kg⁻¹.
                a * a.transpose() * numbers.uniform(0.01, 1.0)
                    + SMatrix::identity() * numbers.uniform(1e-3, 1e-1)
            };
            ProblemBody {
                inverse_mass,
                velocity: SVector::zeros(),
            }
        })
        .collect();
    let n = bodies.len();
    let contacts = (0..contacts)
        .map(|_| {
            let first = numbers.below(n);
            let second = numbers.below(n + 1);
            let second = (second != n && second != first).then_some(second);
            let mut jacobian = [SMatrix::<f64, R, D>::zeros(); 2];
            for (s, j) in jacobian.iter_mut().enumerate() {
                if s == 1 && second.is_none() {
                    continue;
                }
                *j = SMatrix::from_fn(|_, _| numbers.uniform(-1.0, 1.0));
                for r in 0..R {
                    if numbers.chance(0.03) {
                        j.row_mut(r).fill(0.0);
                    }
                }
            }
            let mu = if numbers.chance(0.2) {
                0.0
            } else {
                numbers.uniform(0.1, 1.0)
            };
            let lambda0 = if numbers.chance(0.8) {
                SVector::from_fn(|r, _| {
                    if r == 0 {
                        numbers.uniform(-0.5, 2.0)
                    } else {
                        numbers.uniform(-2.0, 2.0)
                    }
                })
            } else {
                SVector::zeros()
            };
            ProblemContact {
                bodies: [Some(first), second],
                jacobian,
                b: SVector::from_fn(|_, _| numbers.uniform(-2.0, 2.0)),
                mu,
                compliance: if numbers.chance(0.3) {
                    numbers.uniform(0.0, 0.1)
                } else {
                    0.0
                },
                lambda0,
                bounds: RowBounds::Contact,
            }
        })
        .collect();
    ContactProblem {
        friction,
        bodies,
        contacts,
    }
}

/// Solves `problem` in the coloured order, one thread, with or without the groups of four: λ,
/// every body's Δu, the report, and whether the groups ran.
fn solve<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    sweeps: u32,
    lanes: bool,
) -> (
    Vec<SVector<f64, R>>,
    Vec<SVector<f64, D>>,
    rigidref::solve::SolveReport,
    bool,
) {
    let mut workspace = PgsWorkspace::new(0);
    workspace.set_lanes(lanes);
    let mut lambda = Vec::new();
    let settings = PgsSettings {
        max_iterations: sweeps,
        tolerance: None,
        order: ContactOrder::Coloured,
        local: LocalSolve::Rows,
    };
    let report = solve_pgs(problem, &settings, &mut workspace, &mut lambda);
    let delta_velocity = (0..problem.bodies.len())
        .map(|i| *workspace.delta_velocity(i))
        .collect();
    (lambda, delta_velocity, report, workspace.last_lanes())
}

fn bits<const N: usize>(v: &[SVector<f64, N>]) -> Vec<[u64; N]> {
    v.iter().map(|x| std::array::from_fn(|i| x[i].to_bits())).collect()
}

/// For both shapes (3D: 6 velocities, 3 rows; 2D: 3 velocities, 2 rows) and both friction
/// models, on 40 random problems each of 30 bodies and 200 contacts (colours of many contacts,
/// so most visits go in groups): λ, every body's Δu and the report's residuals are the
/// one-at-a-time sweep's to the bit (compared as bits, so that −0 and +0 differ too), after 1
/// sweep and after 30.
fn same_bits_as_one_at_a_time<const D: usize, const R: usize>(seed: u64) {
    let mut numbers = Numbers(seed);
    let mut grouped = 0;
    for friction in [FrictionModel::Box, FrictionModel::Cone] {
        for case in 0..40 {
            let problem = random_problem::<D, R>(&mut numbers, 30, 200, friction);
            for sweeps in [1, 30] {
                let (l1, u1, r1, ran) = solve(&problem, sweeps, true);
                let (l0, u0, r0, _) = solve(&problem, sweeps, false);
                assert!(ran, "{friction:?} case {case}: the groups did not run");
                grouped += 1;
                assert!(
                    bits(&l1) == bits(&l0),
                    "{friction:?} case {case}, {sweeps} sweeps: λ differs"
                );
                assert!(
                    bits(&u1) == bits(&u0),
                    "{friction:?} case {case}, {sweeps} sweeps: Δu differs"
                );
                assert_eq!(r1.residual.to_bits(), r0.residual.to_bits());
                assert_eq!(
                    r1.coulomb_residual.map(f64::to_bits),
                    r0.coulomb_residual.map(f64::to_bits)
                );
            }
        }
    }
    assert_eq!(grouped, 160);
}

#[test]
fn four_contacts_per_lane_give_the_one_at_a_time_sweeps_bits_in_3d() {
    same_bits_as_one_at_a_time::<6, 3>(0x3D);
}

#[test]
fn four_contacts_per_lane_give_the_one_at_a_time_sweeps_bits_in_2d() {
    same_bits_as_one_at_a_time::<3, 2>(0x2D);
}

/// Where a contact joins a body to itself, or a constraint is a joint, the sweep goes one at a
/// time (the groups' copies of Δu could not see each other's writes; a joint's rows are not a
/// contact's), and so does a problem of more than `MAX_CONTACTS_IN_GROUPS` contacts (where
/// laying out the groups costs more than they gain): the workspace says so.
#[test]
fn self_contacts_joints_and_large_problems_keep_the_one_at_a_time_sweep() {
    let limit = rigidref::solve::pgs::MAX_CONTACTS_IN_GROUPS;
    let mut numbers = Numbers(11);
    let at_limit = random_problem::<3, 2>(&mut numbers, 500, limit, FrictionModel::Box);
    assert!(solve(&at_limit, 1, true).3);
    let mut above = at_limit.clone();
    above.contacts.push(above.contacts[0].clone());
    assert!(!solve(&above, 1, true).3);
    let mut numbers = Numbers(7);
    let mut problem = random_problem::<6, 3>(&mut numbers, 10, 40, FrictionModel::Box);
    assert!(solve(&problem, 1, true).3);
    let mut joint = problem.clone();
    joint.contacts[3].bounds = RowBounds::Free;
    assert!(!solve(&joint, 1, true).3);
    let body = problem.contacts[5].bodies[0];
    problem.contacts[5].bodies[1] = body;
    assert!(!solve(&problem, 1, true).3);
}
