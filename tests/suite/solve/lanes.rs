//! The coloured sweep four contacts at a time (docs/contact.md §"Four contacts per lane"): the
//! one-contact-at-a-time sweep's bits, for both problem shapes and both friction models.

use super::{Solved, solve_on};
use crate::common::problems::tiled;
use nalgebra::{SMatrix, SVector};
use rigidref::problem::{ContactProblem, FrictionModel, ProblemBody, ProblemContact, RowBounds};
use rigidref::solve::LocalSolve;
use rigidref::solve::pgs::Lanes;

/// splitmix64: a small seeded generator, so the problems are the same on every run.
pub(super) struct Numbers(pub(super) u64);

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
/// pinned (zero inverse mass), the others with a rigid body's M⁻¹ (m⁻¹ on the ⌈D / 2⌉ linear
/// components, coupled to nothing, and any symmetric positive definite block on the rest, which
/// the groups take: docs/contact.md §"Four contacts per lane", "One inverse mass a side");
/// `contacts` contacts between two bodies, with the static world,
/// or with a pinned body; μ zero on some (a zero friction bound); compliance on some; a warm
/// start on most, its friction outside the bound on some, its normal impulse −0 on some; some
/// rows all zero (a zero diagonal: the row cannot move anything); b in [−2, 2] m/s, −0 on some
/// rows.
pub(super) fn random_problem<const D: usize, const R: usize>(
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
                let block = a * a.transpose() * numbers.uniform(0.01, 1.0)
                    + SMatrix::identity() * numbers.uniform(1e-3, 1e-1);
                let (linear, m) = (D.div_ceil(2), numbers.uniform(0.01, 1.0));
                SMatrix::from_fn(|i, j| match (i < linear || j < linear, i == j) {
                    (true, true) => m,
                    (true, false) => 0.0,
                    (false, _) => block[(i, j)],
                })
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
                    if r == 0 && numbers.chance(0.05) {
                        -0.0
                    } else if r == 0 {
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
                b: SVector::from_fn(|_, _| {
                    if numbers.chance(0.05) {
                        -0.0
                    } else {
                        numbers.uniform(-2.0, 2.0)
                    }
                }),
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

/// [`solve_on`] one thread.
fn solve<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    sweeps: u32,
    lanes: Lanes,
) -> Solved<D, R> {
    solve_on(problem, sweeps, lanes, 1)
}

/// Every bit of `a` is `b`'s: λ, Δu, the sweeps and both residuals (as bits, so that −0 and +0
/// differ).
fn assert_same_bits<const D: usize, const R: usize>(
    a: &Solved<D, R>,
    b: &Solved<D, R>,
    what: &str,
) {
    assert!(bits(&a.0) == bits(&b.0), "{what}: λ differs");
    assert!(bits(&a.1) == bits(&b.1), "{what}: Δu differs");
    assert_eq!(a.2.iterations, b.2.iterations, "{what}");
    assert_eq!(a.2.residual.to_bits(), b.2.residual.to_bits(), "{what}");
    assert_eq!(
        a.2.coulomb_residual.map(f64::to_bits),
        b.2.coulomb_residual.map(f64::to_bits),
        "{what}"
    );
}

fn bits<const N: usize>(v: &[SVector<f64, N>]) -> Vec<[u64; N]> {
    v.iter()
        .map(|x| std::array::from_fn(|i| x[i].to_bits()))
        .collect()
}

/// On 40 random problems per friction model, each of 30 bodies and 200 contacts (colours of many
/// contacts, so most visits go in groups): λ, every body's Δu and the report are the
/// one-at-a-time sweep's to the bit, with the widest instructions and with the baseline
/// processor's, after 1 sweep and after 30.
fn same_bits_as_one_at_a_time<const D: usize, const R: usize>(seed: u64) {
    let mut numbers = Numbers(seed);
    for friction in [FrictionModel::Box, FrictionModel::Cone] {
        for case in 0..40 {
            let problem = random_problem::<D, R>(&mut numbers, 30, 200, friction);
            for sweeps in [1, 30] {
                let what = format!("{D}×{R}, {friction:?} case {case}, {sweeps} sweeps");
                let one = solve(&problem, sweeps, Lanes::Off);
                assert_eq!(one.3, 0, "{what}: groups ran with Lanes::Off");
                for lanes in [Lanes::Native, Lanes::Portable] {
                    let grouped = solve(&problem, sweeps, lanes);
                    // Most contacts go in groups (the rest of each colour, fewer than four, does
                    // not): at least half of them.
                    assert!(
                        4 * grouped.3 >= problem.contacts.len() / 2,
                        "{what}: only {} groups",
                        grouped.3
                    );
                    assert_same_bits(&grouped, &one, &format!("{what}, {lanes:?}"));
                }
            }
        }
    }
}

/// The two shapes the simulations solve: 3D (6 velocities, 3 rows per contact) and 2D (3
/// velocities, 2 rows).
#[test]
fn four_contacts_per_lane_give_the_one_at_a_time_sweeps_bits_in_3d() {
    same_bits_as_one_at_a_time::<6, 3>(0x3D);
}

#[test]
fn four_contacts_per_lane_give_the_one_at_a_time_sweeps_bits_in_2d() {
    same_bits_as_one_at_a_time::<3, 2>(0x2D);
}

/// The other body dimensions the groups accept (below 8), each summing its dot products in its
/// own order (nalgebra's for 2, 4 and one by one from +0 for 1, 5, 7), and one row per contact
/// (no friction rows).
#[test]
fn four_contacts_per_lane_give_the_one_at_a_time_sweeps_bits_in_other_dimensions() {
    same_bits_as_one_at_a_time::<1, 1>(1);
    same_bits_as_one_at_a_time::<2, 2>(2);
    same_bits_as_one_at_a_time::<4, 3>(4);
    same_bits_as_one_at_a_time::<5, 3>(5);
    same_bits_as_one_at_a_time::<7, 2>(7);
}

/// Problems large enough for two threads (20 disjoint copies of a random problem: 4 000
/// contacts, more than 64 per thread and colour): with groups on two threads, every bit of the
/// one-at-a-time sweep on one thread, box and cone, after 3 sweeps and 30.
fn two_threads_same_bits_as_one_at_a_time<const D: usize, const R: usize>(seed: u64) {
    let mut numbers = Numbers(seed);
    for friction in [FrictionModel::Box, FrictionModel::Cone] {
        for case in 0..4 {
            let problem = tiled(&random_problem::<D, R>(&mut numbers, 30, 200, friction), 20);
            for sweeps in [3, 30] {
                let what = format!("{D}×{R}, {friction:?} case {case}, {sweeps} sweeps");
                let one = solve_on(&problem, sweeps, Lanes::Off, 1);
                let two = solve_on(&problem, sweeps, Lanes::Native, 2);
                assert_eq!(two.4, 2, "{what}: the threads did not run");
                assert!(two.3 > 0, "{what}: no groups");
                assert_same_bits(&two, &one, &what);
            }
        }
    }
}

/// [`two_threads_same_bits_as_one_at_a_time`] in 3D and 2D.
#[test]
fn four_contacts_per_lane_on_two_threads_give_the_one_at_a_time_sweeps_bits() {
    two_threads_same_bits_as_one_at_a_time::<6, 3>(0x3D2);
    two_threads_same_bits_as_one_at_a_time::<3, 2>(0x2D2);
}

/// Signed zeros, built on purpose (random problems rarely make them): four 2D bodies each on the
/// static world, a friction row J_t = (−1, −0, −0) with b_t = −0, a warm start (1, −0). The
/// normal row moves only Δu_y (to 1), so the friction row's velocity is
/// −0 + ((−1)(+0) + (−0)(1) + (−0)(+0)) = −0, and λ_t = −0 − (−0) / a_t = +0. A lane that added
/// the static world's side anyway (w + 0 = +0) would give λ_t = −0 − (+0) = −0 instead. The four
/// contacts make one group; λ and Δu are compared as bits, box and cone.
#[test]
fn four_contacts_per_lane_keep_the_sign_of_a_zero_velocity() {
    use rigidref::problem::ProblemBody;
    for friction in [FrictionModel::Box, FrictionModel::Cone] {
        let problem = ContactProblem::<3, 2> {
            friction,
            bodies: vec![
                ProblemBody {
                    inverse_mass: SMatrix::identity(),
                    velocity: SVector::zeros(),
                };
                4
            ],
            contacts: (0..4)
                .map(|i| ProblemContact {
                    bodies: [Some(i), None],
                    jacobian: [
                        SMatrix::<f64, 2, 3>::new(0.0, 1.0, 0.0, -1.0, -0.0, -0.0),
                        SMatrix::zeros(),
                    ],
                    b: SVector::<f64, 2>::new(-1.0, -0.0),
                    mu: 0.5,
                    compliance: 0.0,
                    lambda0: SVector::<f64, 2>::new(1.0, -0.0),
                    bounds: RowBounds::Contact,
                })
                .collect(),
        };
        let one = solve(&problem, 1, Lanes::Off);
        let grouped = solve(&problem, 1, Lanes::Native);
        assert_eq!(
            grouped.3, 1,
            "{friction:?}: the four contacts are not one group"
        );
        assert_eq!(
            one.0[0][1].to_bits(),
            0.0f64.to_bits(),
            "{friction:?}: the case is not the one built (λ_t = {:?})",
            one.0[0][1]
        );
        assert_same_bits(&grouped, &one, &format!("{friction:?}"));
    }
}

/// Where a body's M⁻¹ is not a rigid body's, the groups cannot keep one inverse mass per side in
/// place of M⁻¹Jᵀ's linear rows (`LaneGroup::set_lane` finds m⁻¹ J ≠ M⁻¹Jᵀ there): the solve lays
/// every contact out one at a time and gives the bits of the sweep without groups. Random
/// problems whose moving bodies have an M⁻¹ coupling a linear component to another (a dense
/// symmetric positive definite block) or differing inverse masses on the linear components
/// (diag(1, 2, …)), 3D and 2D, box and cone, 1 and 30 sweeps; the same problems with rigid
/// bodies keep their groups.
fn not_rigid_keeps_the_one_at_a_time_sweep<const D: usize, const R: usize>(seed: u64) {
    let mut numbers = Numbers(seed);
    for friction in [FrictionModel::Box, FrictionModel::Cone] {
        for shape in ["coupled", "unequal"] {
            let rigid = random_problem::<D, R>(&mut numbers, 30, 200, friction);
            assert!(solve(&rigid, 1, Lanes::Native).3 > 0, "no groups at all");
            let mut problem = rigid.clone();
            for body in &mut problem.bodies {
                if body.inverse_mass != SMatrix::<f64, D, D>::zeros() {
                    body.inverse_mass = if shape == "coupled" {
                        let a = SMatrix::<f64, D, D>::from_fn(|_, _| numbers.uniform(-1.0, 1.0));
                        a * a.transpose() + SMatrix::identity() * 0.01
                    } else {
                        SMatrix::from_diagonal(&SVector::from_fn(|i, _| 1.0 + i as f64))
                    };
                }
            }
            for sweeps in [1, 30] {
                let what = format!("{D}×{R}, {friction:?}, {shape}, {sweeps} sweeps");
                let native = solve(&problem, sweeps, Lanes::Native);
                assert_eq!(native.3, 0, "{what}: groups used");
                assert_same_bits(&native, &solve(&problem, sweeps, Lanes::Off), &what);
            }
        }
    }
}

/// [`not_rigid_keeps_the_one_at_a_time_sweep`] in 3D and 2D.
#[test]
fn a_body_whose_inverse_mass_is_not_a_rigid_bodys_keeps_the_one_at_a_time_sweep() {
    not_rigid_keeps_the_one_at_a_time_sweep::<6, 3>(0x9160);
    not_rigid_keeps_the_one_at_a_time_sweep::<3, 2>(0x9161);
}

/// Where a contact joins a body to itself, or a constraint is a joint, the sweep goes one at a
/// time (the groups' copies of Δu could not see each other's writes; a joint's rows are not a
/// contact's): the workspace says so. The plain problem keeps its groups.
#[test]
fn self_contacts_and_joints_keep_the_one_at_a_time_sweep() {
    let mut numbers = Numbers(7);
    let mut problem = random_problem::<6, 3>(&mut numbers, 10, 40, FrictionModel::Box);
    assert!(solve(&problem, 1, Lanes::Native).3 > 0);
    let mut joint = problem.clone();
    joint.contacts[3].bounds = RowBounds::Free;
    assert_eq!(solve(&joint, 1, Lanes::Native).3, 0);
    let body = problem.contacts[5].bodies[0];
    problem.contacts[5].bodies[1] = body;
    assert_eq!(solve(&problem, 1, Lanes::Native).3, 0);
}

/// A contact that joins a body to itself (J₁ and J₂ on the same body, visited through the
/// bodies' Δu directly rather than through copies) is solved as the contact with the one
/// Jacobian J₁ + J₂ against the static world: w = b + (J₁ + J₂) Δu either way, and its impulse
/// moves the body by M⁻¹(J₁ + J₂)ᵀ δ. λ and Δu agree to round-off (the sums are taken in
/// another order) after 20 sweeps, box and cone, with each contact between two bodies of a
/// random problem made the self contact in turn (at least one carrying an impulse); a wrong w
/// on the self contact moves λ by far more.
#[test]
fn a_contact_of_a_body_with_itself_is_solved_as_its_summed_jacobian() {
    let mut numbers = Numbers(11);
    for friction in [FrictionModel::Box, FrictionModel::Cone] {
        let original = random_problem::<6, 3>(&mut numbers, 6, 20, friction);
        // Each contact between two bodies made a self contact in turn; at least one of them
        // must carry an impulse (a self contact of a pinned body, or one whose body the other
        // contacts push away, carries none), so that the comparison is not of zeros only.
        let mut carrying = 0;
        for k in (0..original.contacts.len()).filter(|&k| original.contacts[k].bodies[1].is_some())
        {
            let mut problem = original.clone();
            let body = problem.contacts[k].bodies[0];
            problem.contacts[k].bodies[1] = body;
            // Approaching, so that it may carry an impulse.
            problem.contacts[k].b = nalgebra::Vector3::new(-1.5, 0.4, -0.3);
            let mut merged = problem.clone();
            let c = &mut merged.contacts[k];
            c.jacobian = [c.jacobian[0] + c.jacobian[1], nalgebra::SMatrix::zeros()];
            c.bodies[1] = None;
            let (a, b) = (
                solve(&problem, 20, Lanes::Off),
                solve(&merged, 20, Lanes::Off),
            );
            let scale = a.0.iter().map(|l| l.amax()).fold(1e-3, f64::max);
            for (x, y) in a.0.iter().zip(&b.0) {
                // 1e-9 of the largest impulse: 20 sweeps of round-off from summing J₁ and J₂
                // first or applying them one after the other.
                assert!(
                    (x - y).amax() <= 1e-9 * scale,
                    "{friction:?}, contact {k}: self {x} merged {y}"
                );
            }
            if a.0[k].amax() > 1e-6 {
                carrying += 1;
            }
        }
        assert!(
            carrying > 0,
            "{friction:?}: no self contact carries an impulse"
        );
    }
}

/// Groups of four at every size: a 3D problem of 20 000 contacts (100 disjoint copies of a
/// random problem of 200; above the 16 384 where the groups used to stop, when they were laid
/// out in a second pass) is solved four at a time, with every contact but the few left over per
/// colour in a group, and gives the one-at-a-time sweep's answer to the bit (tolerance zero:
/// each lane does the one-contact visit's arithmetic), box and cone, after 3 sweeps.
#[test]
fn groups_of_four_serve_a_problem_above_the_old_limit_with_the_same_bits() {
    let mut numbers = Numbers(0x4916);
    for friction in [FrictionModel::Box, FrictionModel::Cone] {
        let problem = tiled(
            &random_problem::<6, 3>(&mut numbers, 30, 200, friction),
            100,
        );
        assert!(problem.contacts.len() > 16_384);
        let one = solve(&problem, 3, Lanes::Off);
        assert_eq!(one.3, 0, "{friction:?}: groups ran with Lanes::Off");
        let grouped = solve(&problem, 3, Lanes::Native);
        assert!(
            4 * grouped.3 >= problem.contacts.len() / 2,
            "{friction:?}: only {} groups",
            grouped.3
        );
        assert_same_bits(&grouped, &one, &format!("{friction:?}"));
    }
}

/// A coloured solve of 4 sweeps then the shock pass with `pass` visits (row by row or the
/// exact local solve), with the groups as `lanes` says: λ, Δu, the groups the solve visited and
/// the visits the pass made.
fn shock_pass<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    lanes: Lanes,
    pass: LocalSolve,
) -> (Vec<SVector<f64, R>>, Vec<SVector<f64, D>>, usize, u64) {
    let settings = rigidref::solve::PgsSettings {
        max_iterations: 4,
        tolerance: None,
        order: rigidref::solve::ContactOrder::Coloured,
        local: LocalSolve::Rows,
    };
    let mut workspace = rigidref::solve::PgsWorkspace::new(0);
    workspace.set_lanes(lanes);
    let mut lambda = Vec::new();
    rigidref::solve::solve_pgs(problem, &settings, &mut workspace, &mut lambda);
    let groups = workspace.last_groups();
    let pass_settings = rigidref::solve::PgsSettings {
        local: pass,
        ..settings
    };
    let report = rigidref::solve::shock::propagate_shock(
        problem,
        &pass_settings,
        &mut workspace,
        &mut lambda,
    );
    let du = (0..problem.bodies.len())
        .map(|i| *workspace.delta_velocity(i))
        .collect();
    (lambda, du, groups, report.visits)
}

/// [`shock_pass`] with and without the groups on random problems: the same bits.
fn shock_same_bits<const D: usize, const R: usize>(seed: u64, pass: LocalSolve) {
    let mut numbers = Numbers(seed);
    for friction in [FrictionModel::Box, FrictionModel::Cone] {
        for case in 0..5 {
            let problem = random_problem::<D, R>(&mut numbers, 30, 200, friction);
            let one = shock_pass(&problem, Lanes::Off, pass);
            let grouped = shock_pass(&problem, Lanes::Native, pass);
            let what = format!("{D}×{R} {friction:?} case {case}");
            assert!(
                grouped.2 > 0 && one.2 == 0,
                "{what}: groups {grouped:?}",
                grouped = grouped.2
            );
            assert!(grouped.3 > 0, "{what}: the pass visited nothing");
            assert!(bits(&grouped.0) == bits(&one.0), "{what}: λ differs");
            assert!(bits(&grouped.1) == bits(&one.1), "{what}: Δu differs");
        }
    }
}

/// Shock propagation after a coloured solve reads and changes the contacts where the solve
/// kept them: in their groups' lanes with the groups of four, in the one-contact records
/// without. Random problems with pinned bodies (the layers' supports), 2D and 3D, box and cone:
/// after the solve and the pass, λ and every body's Δu are the same bits either way.
#[test]
fn shock_propagation_reads_the_groups_with_the_one_at_a_time_bits() {
    shock_same_bits::<6, 3>(0x5A0C, LocalSolve::Rows);
    shock_same_bits::<3, 2>(0x5A0D, LocalSolve::Rows);
}

/// The shock pass may visit with the exact local solve after a solve row by row
/// (`propagate_shock` takes its own settings): a contact kept in a group's lane is then solved
/// exactly through the lane's copies of its bodies' Δu, written back after every row's update
/// (`SlotRows`), and the answer is the one without the groups, bit for bit (tolerance zero: the
/// lane's arithmetic is the one-contact record's). Random problems as above, 3D and 2D, box and
/// cone.
#[test]
fn an_exact_shock_pass_reads_the_groups_with_the_one_at_a_time_bits() {
    shock_same_bits::<6, 3>(0x5A0E, LocalSolve::Exact);
    shock_same_bits::<3, 2>(0x5A0F, LocalSolve::Exact);
}

/// Random problems of 30 bodies of `D` velocities and 200 contacts, box and cone, 1 and 30
/// sweeps, with `Lanes::Native`: no groups, and every bit of the one-at-a-time sweep.
fn one_at_a_time_without_groups<const D: usize, const R: usize>(seed: u64) {
    let mut numbers = Numbers(seed);
    for friction in [FrictionModel::Box, FrictionModel::Cone] {
        for case in 0..5 {
            let problem = random_problem::<D, R>(&mut numbers, 30, 200, friction);
            for sweeps in [1, 30] {
                let what = format!("{D}×{R}, {friction:?} case {case}, {sweeps} sweeps");
                let one = solve(&problem, sweeps, Lanes::Off);
                let native = solve(&problem, sweeps, Lanes::Native);
                assert_eq!(native.3, 0, "{what}: groups used");
                assert_same_bits(&native, &one, &what);
            }
        }
    }
}

/// Bodies of 8 velocities or more: nalgebra sums a dot product of 8 terms or more in eight
/// interleaved partial sums, which the lanes' sums one term at a time would not reproduce, so
/// the groups stay off there and the sweep's bits are the one-at-a-time sweep's: 8, 9 and 12
/// velocities with 3, 1 and 2 rows.
#[test]
fn bodies_of_eight_velocities_or_more_keep_the_one_at_a_time_sweep() {
    one_at_a_time_without_groups::<8, 3>(8);
    one_at_a_time_without_groups::<9, 1>(9);
    one_at_a_time_without_groups::<12, 2>(12);
}

/// A problem whose friction is zero on every contact gives, solved by its normal rows alone
/// (`ContactProblem::normal_rows_into`), the full solve's normal impulses, every body's Δu, the
/// sweeps and the residual to the bit: the friction bound μ λn is then 0, so a friction row
/// only ever adds ±0 to Δu (post-stabilisation's shortcut, docs/blocks2d.md
/// §"Post-stabilisation", "Normal rows only"). 20 random 2D problems per friction model (30
/// bodies, 200 contacts, warm starts and −0 included), every order, the groups of four and
/// threads, 1 and 30 sweeps and a tolerance that stops early.
#[test]
fn normal_rows_alone_give_the_frictionless_solves_bits() {
    use rigidref::solve::{ContactOrder, LocalSolve, PgsSettings, PgsWorkspace, solve_pgs};
    let mut numbers = Numbers(0x49F);
    let orders = [
        ContactOrder::Sequential,
        ContactOrder::Random,
        ContactOrder::Coloured,
        ContactOrder::RandomColoured,
    ];
    let mut compared = 0;
    for friction in [FrictionModel::Box, FrictionModel::Cone] {
        for case in 0..20 {
            let mut problem = random_problem::<3, 2>(&mut numbers, 30, 200, friction);
            for c in &mut problem.contacts {
                c.mu = 0.0;
            }
            let mut normal = ContactProblem {
                friction,
                bodies: Vec::new(),
                contacts: Vec::new(),
            };
            problem.normal_rows_into(&mut normal);
            for order in orders {
                for (sweeps, tolerance) in [(1, None), (30, None), (200, Some(1e-3))] {
                    for threads in [1, 2] {
                        let settings = PgsSettings {
                            max_iterations: sweeps,
                            tolerance,
                            order,
                            local: LocalSolve::Rows,
                        };
                        let what = format!(
                            "{friction:?} case {case}, {order:?}, {sweeps} sweeps, {threads} threads"
                        );
                        let (mut full_ws, mut normal_ws) =
                            (PgsWorkspace::new(case), PgsWorkspace::new(case));
                        full_ws.set_threads(threads);
                        normal_ws.set_threads(threads);
                        // Two solves in a row: the second draws its random orders after the
                        // first's, as post-stabilisation's solves do substep after substep.
                        for solve in 0..2 {
                            let (mut full_l, mut normal_l) = (Vec::new(), Vec::new());
                            let a = solve_pgs(&problem, &settings, &mut full_ws, &mut full_l);
                            let b = solve_pgs(&normal, &settings, &mut normal_ws, &mut normal_l);
                            let what = format!("{what}, solve {solve}");
                            let normal_bits = |l: &[nalgebra::SVector<f64, 2>]| {
                                l.iter().map(|x| x[0].to_bits()).collect::<Vec<_>>()
                            };
                            assert!(
                                normal_bits(&full_l) == bits(&normal_l).concat(),
                                "{what}: λn"
                            );
                            let du = |w: &PgsWorkspace<3, 2>| {
                                (0..30).map(|i| *w.delta_velocity(i)).collect::<Vec<_>>()
                            };
                            let du_normal = (0..30)
                                .map(|i| *normal_ws.delta_velocity(i))
                                .collect::<Vec<_>>();
                            assert!(bits(&du(&full_ws)) == bits(&du_normal), "{what}: Δu");
                            assert_eq!(a.iterations, b.iterations, "{what}");
                            assert_eq!(a.residual.to_bits(), b.residual.to_bits(), "{what}");
                            if order.is_coloured() && solve == 0 {
                                assert!(full_ws.last_groups() > 0, "{what}: no groups ran");
                            }
                            compared += 1;
                        }
                    }
                }
            }
        }
    }
    assert_eq!(compared, 2 * 20 * 4 * 3 * 2 * 2);
}

/// λ, Δu and the report of one solve, with the warm start's zero starts skipped or applied.
fn solve_with_zero_starts<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    order: rigidref::solve::ContactOrder,
    sweeps: u32,
    lanes: Lanes,
    skipped: bool,
) -> Solved<D, R> {
    let settings = rigidref::solve::PgsSettings {
        max_iterations: sweeps,
        tolerance: None,
        order,
        local: LocalSolve::Rows,
    };
    let mut workspace = rigidref::solve::PgsWorkspace::new(3);
    workspace.set_lanes(lanes);
    workspace.set_zero_starts_skipped(skipped);
    let mut lambda = Vec::new();
    let report = rigidref::solve::solve_pgs(problem, &settings, &mut workspace, &mut lambda);
    let du = (0..problem.bodies.len())
        .map(|i| *workspace.delta_velocity(i))
        .collect();
    (
        lambda,
        du,
        report,
        workspace.last_groups(),
        workspace.last_threads(),
    )
}

/// The warm start skips a contact whose start is zero (+0 or −0 in every row, as given or after
/// the projection) when its M⁻¹Jᵀ is finite, since Δu += (M⁻¹Jᵀ)_r · (±0) changes no bit of a
/// Δu that is never −0 (docs/contact.md §"Warm starting", "Zero starts skipped"). Random
/// problems (2D and 3D, box and cone, a fifth of the starts zero, some normal impulses −0 or
/// negative), every order, with and without the groups, 0, 1 and 30 sweeps: λ, Δu and the
/// report are the bits of the warm start that applies every contact. One contact of some
/// problems has an infinite Jacobian entry and a zero start: there 0 · ∞ = NaN must still reach
/// Δu (after 0 sweeps Δu is the warm start's alone, so skipping it would show).
fn zero_starts_skipped_same_bits<const D: usize, const R: usize>(seed: u64) {
    use rigidref::solve::ContactOrder;
    let mut numbers = Numbers(seed);
    let mut compared = 0;
    for friction in [FrictionModel::Box, FrictionModel::Cone] {
        for case in 0..6 {
            let mut problem = random_problem::<D, R>(&mut numbers, 30, 200, friction);
            if case % 3 == 2 {
                let c = &mut problem.contacts[7];
                c.jacobian[0][(0, 0)] = f64::INFINITY;
                c.lambda0 = SVector::zeros();
            }
            for order in [
                ContactOrder::Sequential,
                ContactOrder::Random,
                ContactOrder::Coloured,
                ContactOrder::RandomColoured,
            ] {
                for sweeps in [0, 1, 30] {
                    for lanes in [Lanes::Off, Lanes::Native] {
                        let what = format!(
                            "{D}×{R} {friction:?} case {case}, {order:?}, {sweeps} sweeps, {lanes:?}"
                        );
                        let skipped = solve_with_zero_starts(&problem, order, sweeps, lanes, true);
                        let applied = solve_with_zero_starts(&problem, order, sweeps, lanes, false);
                        assert_same_bits(&skipped, &applied, &what);
                        if case % 3 == 2 && sweeps == 0 {
                            assert!(
                                skipped.1.iter().any(|u| u.iter().any(|x| x.is_nan())),
                                "{what}: the infinite column's NaN did not reach Δu"
                            );
                        }
                        compared += 1;
                    }
                }
            }
        }
    }
    assert_eq!(compared, 2 * 6 * 4 * 3 * 2);
}

/// [`zero_starts_skipped_same_bits`] in 3D and in 2D.
#[test]
fn zero_warm_starts_skipped_give_the_applied_warm_starts_bits() {
    zero_starts_skipped_same_bits::<6, 3>(0x49A);
    zero_starts_skipped_same_bits::<3, 2>(0x49B);
}

/// [`velocity_changes_are_the_inverse_mass_times_the_impulses_for_any_inverse_mass`] on one
/// inverse mass block `m`, given to every body that is not pinned (scaled by 0.1–1).
fn check_velocity_changes<const D: usize, const R: usize>(seed: u64, m: SMatrix<f64, D, D>) {
    let mut numbers = Numbers(seed);
    for friction in [FrictionModel::Box, FrictionModel::Cone] {
        let mut problem = random_problem::<D, R>(&mut numbers, 30, 200, friction);
        for body in &mut problem.bodies {
            if body.inverse_mass != SMatrix::<f64, D, D>::zeros() {
                body.inverse_mass = m * numbers.uniform(0.1, 1.0);
            }
        }
        for sweeps in [1, 20] {
            for lanes in [Lanes::Off, Lanes::Native] {
                let (lambda, du, ..) = solve(&problem, sweeps, lanes);
                let expected = problem.velocity_change(&lambda);
                let scale = expected.iter().map(|v| v.amax()).fold(0.0, f64::max);
                assert!(scale > 0.0);
                for (i, (a, b)) in du.iter().zip(&expected).enumerate() {
                    assert!(
                        (a - b).amax() <= 1e-12 * scale,
                        "{D}×{R} {friction:?}, {sweeps} sweeps, {lanes:?}: body {i}'s Δu {a} against M⁻¹Jᵀλ {b}"
                    );
                }
            }
        }
    }
}

/// Every body's Δu is M⁻¹ Jᵀ λ of the answer (`ContactProblem::velocity_change`, nalgebra's
/// full product) where M⁻¹ is not a rigid body's diag(m⁻¹ I, J⁻¹) but any symmetric positive
/// definite block with exact zeros between nonzero entries of a row (a problem file may give
/// one): the set-up once summed M⁻¹Jᵀ over each row's span of nonzero columns, where a span
/// that started at the first zero would drop the row's first term; it now takes nalgebra's full
/// product (`pgs_setup.rs::inverse_mass_times`), which this keeps checked against
/// `velocity_change` on such blocks. 2D and 3D, box and cone, one at a time and four per lane, 1 and
/// 20 sweeps. Tolerance 1e-12 of the largest |Δu|: the two sums differ only in the order of
/// their additions (the solve accumulates Δu impulse by impulse).
#[test]
fn velocity_changes_are_the_inverse_mass_times_the_impulses_for_any_inverse_mass() {
    // Rows [a, 0, c]: a nonzero entry, an exact zero, then a nonzero one.
    let m2 = SMatrix::<f64, 3, 3>::new(2.0, 0.0, 0.5, 0.0, 1.0, 0.0, 0.5, 0.0, 3.0);
    assert!(m2.cholesky().is_some(), "positive definite");
    check_velocity_changes::<3, 2>(0xA0C, m2);
    let mut m3 = SMatrix::<f64, 6, 6>::identity() * 2.0;
    for (i, j, v) in [
        (0, 2, 0.4),
        (0, 5, 0.3),
        (1, 4, -0.2),
        (3, 5, 0.5),
        (2, 4, 0.1),
    ] {
        m3[(i, j)] = v;
        m3[(j, i)] = v;
    }
    assert!(m3.cholesky().is_some(), "positive definite");
    check_velocity_changes::<6, 3>(0xA0C3, m3);
}

/// One workspace solving a run of random problems of different sizes (see the test below):
/// each solve's bits are a fresh workspace's without groups.
fn reused_workspace_gives_fresh_bits<const D: usize, const R: usize>(seed: u64) {
    let mut numbers = Numbers(seed);
    for friction in [FrictionModel::Box, FrictionModel::Cone] {
        for sweeps in [1, 5] {
            let mut workspace = rigidref::solve::PgsWorkspace::new(0);
            workspace.set_lanes(Lanes::Native);
            let settings = rigidref::solve::PgsSettings {
                max_iterations: sweeps,
                tolerance: None,
                order: rigidref::solve::ContactOrder::Coloured,
                local: LocalSolve::Rows,
            };
            let mut reused_groups = 0;
            for (case, contacts) in [240, 80, 320, 40, 200].into_iter().enumerate() {
                let problem = random_problem::<D, R>(&mut numbers, 30, contacts, friction);
                let mut lambda = Vec::new();
                let report =
                    rigidref::solve::solve_pgs(&problem, &settings, &mut workspace, &mut lambda);
                let du = (0..problem.bodies.len())
                    .map(|i| *workspace.delta_velocity(i))
                    .collect();
                let what = format!("{D}×{R}, {friction:?}, {sweeps} sweeps, problem {case}");
                if case > 0 {
                    reused_groups += workspace.last_groups();
                }
                let reused = (lambda, du, report, workspace.last_groups(), 1);
                let fresh = solve(&problem, sweeps, Lanes::Off);
                assert_same_bits(&reused, &fresh, &what);
            }
            assert!(
                reused_groups > 50,
                "only {reused_groups} groups after the first"
            );
        }
    }
}

/// The groups of four are kept from solve to solve and each lane overwritten whole (a static
/// side as zeros), not zeroed again: one workspace solving a run of random problems of
/// different sizes, with the static world and pinned bodies on different sides from problem to
/// problem (so that a reused lane once held a body where the next problem has the static world,
/// and fewer groups follow more), gives on each the bits of a fresh workspace without groups:
/// λ, Δu and the report, 3D and 2D, box and cone, after 1 sweep and after 5.
#[test]
fn groups_reused_from_solve_to_solve_keep_nothing_of_the_last_problem() {
    reused_workspace_gives_fresh_bits::<6, 3>(0x6E05);
    reused_workspace_gives_fresh_bits::<3, 2>(0x6E06);
}
