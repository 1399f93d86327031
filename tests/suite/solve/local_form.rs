//! The local (Delassus) form (docs/contact.md §"The local form") and Siconos' problem files
//! (docs/problem-library.md): W from a run's problem, the solvers on both forms, the file
//! variant, the `.dat` reader against the text, and the solvers on Siconos' small problems to
//! 1e-8 in Siconos' measure.

use crate::common;

use common::problems::{build, physical_spec};
use nalgebra::{DMatrix, DVector, SVector};
use proptest::prelude::*;
use rigidref::problem::local_json::{AnyProblemFile, LocalProblemFile};
use rigidref::problem::siconos::{AnyLocalProblem, parse_dat, read_dat, write_dat};
use rigidref::problem::{FrictionModel, LocalProblem, ProblemView};
use rigidref::solve::residual::{coulomb_residual, residual, siconos_error};
use rigidref::solve::{
    ContactOrder, LocalSolve, NewtonSettings, PgsSettings, Solvable, solve_newton_local,
    solve_pgs_local,
};

fn data(name: &str) -> std::path::PathBuf {
    common::project_root().join("tests/data/siconos").join(name)
}

fn three(name: &str) -> LocalProblem<3> {
    match read_dat(&data(name)).unwrap() {
        AnyLocalProblem::Three(p) => p,
        AnyLocalProblem::Two(_) => panic!("{name}: 2D"),
    }
}

fn pgs_settings(local: LocalSolve, sweeps: u32, tolerance: Option<f64>) -> PgsSettings {
    PgsSettings {
        max_iterations: sweeps,
        tolerance,
        order: ContactOrder::Sequential,
        local,
    }
}

#[test]
fn the_local_form_of_a_run_problem_is_j_minv_jt_plus_c_and_b() {
    proptest!(common::seeded(60), |(s in physical_spec(1..5, 1..8), c in 0.0..1e-2f64, mu in 0.0..1.0f64)| {
        let problem = build(&s, mu, c, FrictionModel::Cone);
        let local = problem.to_local();
        let dense = problem.dense_delassus() + problem.dense_compliance();
        let w = local.dense_w();
        // 1e-12 of the largest entry: the blocks and the dense product sum the same terms in
        // another order.
        let scale = dense.amax().max(1e-300);
        prop_assert!((&w - &dense).amax() <= 1e-12 * scale, "{}", (&w - &dense).amax() / scale);
        prop_assert_eq!(local.dense_q(), problem.dense_b());
        // Blocks only where two contacts share a body, and every diagonal block.
        for (k, contact) in local.contacts.iter().enumerate() {
            for (j, _) in &contact.row {
                let share = j == &k || problem.contacts[k].bodies.iter().flatten()
                    .any(|b| problem.contacts[*j].bodies.contains(&Some(*b)));
                prop_assert!(share, "block ({k}, {j}) of contacts that share no body");
            }
        }
        prop_assert!(local.validate().is_ok());
        prop_assert!(local.asymmetry() <= 1e-14);
    });
}

#[test]
fn solvers_give_the_same_answer_on_both_forms() {
    // PGS visits in the same order with the same arithmetic up to where w comes from (Δu or W):
    // equal to round-off. Newton iterates on the local form in both cases: the same λ, except
    // where the acceptance test (through the bodies, or through W) differs in its last bits.
    proptest!(common::seeded(60), |(s in physical_spec(1..4, 1..7), mu in 0.0..1.0f64, cone: bool)| {
        let friction = if cone { FrictionModel::Cone } else { FrictionModel::Box };
        let problem = build(&s, mu, 1e-3, friction);
        let local = problem.to_local();
        for visit in [LocalSolve::Rows, LocalSolve::Exact] {
            let settings = pgs_settings(visit, 30, None);
            let (mut a, mut b) = (Vec::new(), Vec::new());
            let ra = problem.pgs(&settings, &mut a);
            let rb = local.pgs(&settings, &mut b);
            let scale = a.iter().map(|l| l.amax()).fold(1e-3, f64::max);
            for (x, y) in a.iter().zip(&b) {
                // 1e-9 of the largest impulse: 30 sweeps of round-off from two ways of
                // computing w, on problems with condition numbers up to ~1e4.
                prop_assert!((x - y).amax() <= 1e-9 * scale, "{visit:?}: body {x} local {y}");
            }
            prop_assert!((ra.residual - rb.residual).abs() <= 1e-9 * (1.0 + ra.residual));
        }
        let settings = NewtonSettings::default();
        let (mut a, mut b) = (Vec::new(), Vec::new());
        let ra = problem.newton(&settings, &mut a);
        let rb = local.newton(&settings, &mut b);
        prop_assert_eq!(ra.converged, rb.converged);
        if ra.converged {
            // Both answers are solutions to 1e-10 m/s; their velocities w agree to that scale.
            let (wa, wb) = (local.velocity(&a), local.velocity(&b));
            for (x, y) in wa.iter().zip(&wb) {
                prop_assert!((x - y).amax() <= 1e-8, "{x} {y}");
            }
            prop_assert!(residual(&local, &b) <= 1e-10);
        }
    });
}

/// The local form's coloured order is the body form's (docs/contact.md §"Coloured order"): W's
/// couplings stand for the shared bodies, the same greedy colouring in problem order, so one
/// coloured sweep, and thirty, on either form agree to round-off, as the problem order's do.
/// And it is an order of its own: on a chain of three contacts (the first and last sharing no
/// body) one coloured sweep visits the last before the middle, and so differs from one sweep in
/// problem order.
#[test]
fn the_local_forms_coloured_order_is_the_body_forms() {
    proptest!(common::seeded(60), |(s in physical_spec(2..5, 2..8), mu in 0.0..1.0f64, cone: bool)| {
        let friction = if cone { FrictionModel::Cone } else { FrictionModel::Box };
        let problem = build(&s, mu, 1e-3, friction);
        let local = problem.to_local();
        for (visit, sweeps) in [(LocalSolve::Rows, 1), (LocalSolve::Rows, 30), (LocalSolve::Exact, 1)] {
            let settings = PgsSettings {
                order: ContactOrder::Coloured,
                ..pgs_settings(visit, sweeps, None)
            };
            let (mut a, mut b) = (Vec::new(), Vec::new());
            problem.pgs(&settings, &mut a);
            local.pgs(&settings, &mut b);
            let scale = a.iter().map(|l| l.amax()).fold(1e-3, f64::max);
            for (x, y) in a.iter().zip(&b) {
                // As in `solvers_give_the_same_answer_on_both_forms`: round-off from two ways
                // of computing w; a different visiting order moves λ by far more.
                prop_assert!((x - y).amax() <= 1e-9 * scale, "{visit:?}, {sweeps}: body {x} local {y}");
            }
        }
    });
    // Two bodies: contact 0 of body 0 on the ground, contact 1 between the bodies, contact 2
    // of body 1 on the ground. Contacts 0 and 2 share no body, 1 touches both: colours {0, 2}
    // then {1}.
    let body = |x: f64| {
        (
            10.0,
            [1.0, 1.2, 1.5],
            nalgebra::Vector3::zeros(),
            nalgebra::Vector3::new(x, 0.5, 0.0),
        )
    };
    let up = nalgebra::Vector3::y();
    let approach = SVector::<f64, 3>::new(-1.0, 0.3, -0.2);
    let spec = common::problems::ProblemSpec {
        bodies: vec![body(0.0), body(1.0)],
        contacts: vec![
            (0, 2, nalgebra::Vector3::new(0.1, -0.5, 0.1), up, approach),
            (
                0,
                1,
                nalgebra::Vector3::new(0.5, 0.0, 0.0),
                nalgebra::Vector3::x(),
                approach,
            ),
            (1, 2, nalgebra::Vector3::new(-0.1, -0.5, -0.1), up, approach),
        ],
    };
    let chain = build(&spec, 0.5, 1e-3, FrictionModel::Cone);
    assert_eq!(
        chain.contacts.iter().map(|c| c.bodies).collect::<Vec<_>>(),
        [[Some(0), None], [Some(0), Some(1)], [Some(1), None]]
    );
    let local = chain.to_local();
    let one_sweep = |order| {
        let mut lambda = Vec::new();
        let settings = PgsSettings {
            order,
            ..pgs_settings(LocalSolve::Rows, 1, None)
        };
        local.pgs(&settings, &mut lambda);
        lambda
    };
    let (coloured, found) = (
        one_sweep(ContactOrder::Coloured),
        one_sweep(ContactOrder::Sequential),
    );
    let mut body_coloured = Vec::new();
    let settings = PgsSettings {
        order: ContactOrder::Coloured,
        ..pgs_settings(LocalSolve::Rows, 1, None)
    };
    chain.pgs(&settings, &mut body_coloured);
    for (x, y) in coloured.iter().zip(&body_coloured) {
        assert!((x - y).amax() <= 1e-12, "local {x} body {y}");
    }
    assert!(
        coloured
            .iter()
            .zip(&found)
            .any(|(x, y)| (x - y).amax() > 1e-6),
        "one coloured sweep gave the problem order's λ: {coloured:?}"
    );
}

#[test]
fn a_local_problem_file_round_trips_bit_for_bit() {
    proptest!(common::seeded(40), |(s in physical_spec(1..4, 1..7), mu in 0.0..1.0f64)| {
        let mut problem = build(&s, mu, 1e-4, FrictionModel::Cone);
        for c in &mut problem.contacts {
            c.lambda0 = nalgebra::Vector3::new(0.1, -0.02, 0.03);
        }
        let local = problem.to_local();
        let text = serde_json::to_string(&LocalProblemFile::new(&local)).unwrap();
        let back = match AnyProblemFile::parse(&text).unwrap() {
            AnyProblemFile::Local(file) => file.to_problem::<3>().unwrap(),
            AnyProblemFile::Body(_) => panic!("read as the body form"),
        };
        prop_assert_eq!(&back, &local);
        // A body-form file converts to the same local problem.
        let body = serde_json::to_string(&rigidref::problem::json::ProblemFile::new(&problem)).unwrap();
        prop_assert_eq!(&AnyProblemFile::parse(&body).unwrap().to_local::<3>().unwrap(), &local);
        // And through Siconos' text format, which writes every number to read back exactly.
        let dat = match parse_dat(&write_dat(&local)).unwrap() {
            AnyLocalProblem::Three(p) => p,
            AnyLocalProblem::Two(_) => panic!("2D"),
        };
        prop_assert_eq!(dat.dense_w(), local.dense_w());
        prop_assert_eq!(dat.dense_q(), local.dense_q());
    });
    // Malformed files are refused with what is wrong.
    let bad = r#"{"format":"rigidref-contact-problem","version":1,"form":"local","rows_per_contact":3,
        "friction":"cone","W":[{"row":0,"col":1,"block":[[1,0,0],[0,1,0],[0,0,1]]}],
        "contacts":[{"q":[0,0,0],"mu":0.5}]}"#;
    let AnyProblemFile::Local(file) = AnyProblemFile::parse(bad).unwrap() else {
        panic!()
    };
    let err = file.to_problem::<3>().unwrap_err();
    assert!(err.contains("out of range"), "{err}");
    let missing = bad.replace(r#""col":1"#, r#""col":0"#).replace(
        r#"{"q":[0,0,0],"mu":0.5}"#,
        r#"{"q":[0,0,0],"mu":0.5},{"q":[0,0,0],"mu":0.5}"#,
    );
    let AnyProblemFile::Local(file) = AnyProblemFile::parse(&missing).unwrap() else {
        panic!()
    };
    let err = file.to_problem::<3>().unwrap_err();
    assert!(
        err.contains("contact 1: the diagonal block W[1][1] is missing"),
        "{err}"
    );
    let err = AnyProblemFile::parse(&bad.replace(r#""local""#, r#""global""#)).unwrap_err();
    assert!(err.contains("form \"global\" is not known"), "{err}");
}

#[test]
// The file's own 25 digits, as Siconos printed them: f64 reads them to the nearest double.
#[allow(clippy::excessive_precision)]
fn siconos_dat_files_read_as_their_text_says() {
    // FrictionContact3D_1c.dat: W = [[15,-1,-2],[-1,14,1],[-2,1,16]], q = (-1, 2, 3), μ = 0.1.
    let one = three("FrictionContact3D_1c.dat");
    let w = DMatrix::from_row_slice(3, 3, &[15.0, -1.0, -2.0, -1.0, 14.0, 1.0, -2.0, 1.0, 16.0]);
    assert_eq!(one.dense_w(), w);
    assert_eq!(one.dense_q(), DVector::from_column_slice(&[-1.0, 2.0, 3.0]));
    assert_eq!(one.contacts[0].mu, 0.1);
    assert_eq!(one.friction, FrictionModel::Cone);
    // Rover11035.dat is dense and not symmetric: each text line is a column of W.
    let rover = three("Rover11035.dat");
    let w = rover.dense_w();
    assert_eq!(w[(0, 0)], 1.358309568142355636122254e-02);
    assert_eq!(w[(1, 0)], -1.426574206813656375825161e-04);
    assert_eq!(w[(0, 1)], -1.438285701497408206397943e-04);
    assert_eq!(w[(2, 1)], 5.352808907240413568984216e-05);
    assert_eq!(w[(1, 2)], 5.369789396199593209174292e-05);
    assert_eq!(rover.contacts[0].q[2], -1.064842752305118489530855e-01);
    assert_eq!(rover.contacts[0].mu, 6.999999999999999555910790e-01);
    assert!(rover.asymmetry() > 1e-6);
    // FC3D_Example1_SBM.dat: three identity blocks on the diagonal (sparse-block storage), the
    // same problem as the dense FC3D_Example1.dat.
    let sbm = three("FC3D_Example1_SBM.dat");
    assert_eq!(sbm.dense_w(), DMatrix::identity(9, 9));
    assert_eq!(sbm.blocks(), 3);
    assert_eq!(
        sbm.dense_q(),
        DVector::from_column_slice(&[-1.0, 1.0, 3.0, -1.0, 1.0, 3.0, -1.0, 1.0, 3.0])
    );
    assert_eq!(three("FC3D_Example1.dat").dense_w(), sbm.dense_w());
    // A global problem is refused as such; so are truncated and malformed files.
    let err = read_dat(&data("GFC3D_Example00.dat")).unwrap_err();
    assert!(
        err.contains("GFC3D_Example00.dat") && err.contains("global problem"),
        "{err}"
    );
    let text = std::fs::read_to_string(data("Rover4396.dat")).unwrap();
    let err = parse_dat(&text[..text.len() / 2]).unwrap_err();
    assert!(err.contains("the file ends before"), "{err}");
    let err = parse_dat("3 1 0 3 3 3 3 1 0 0 0 x 0 0 0 1 0 0 0 0.5").unwrap_err();
    assert!(
        err.contains("token 12") && err.contains("\"x\" is not a number"),
        "{err}"
    );
    let err = parse_dat("4 1").unwrap_err();
    assert!(err.contains("dimension 4"), "{err}");
    let err = parse_dat("3 1 1 3 3 1 1 1 3 3 2 1 0 1 0 0 1 0 0 0 1 0 0 0 1 0 0 0 -1").unwrap_err();
    assert!(err.contains("mu must be ≥ 0"), "{err}");
}

#[test]
fn newton_and_pgs_solve_the_small_siconos_problems_to_siconos_tolerance() {
    // Every local 3D problem kept in tests/data/siconos, solved to 1e-8 in Siconos' own
    // measure (the tolerance of Acary, Brémond and Huber's comparison) by the Newton solver and
    // by PGS with exact local solves (Siconos' NSGS) within 20 000 sweeps, as Siconos does.
    let mut names: Vec<String> =
        std::fs::read_dir(common::project_root().join("tests/data/siconos"))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".dat") && !n.starts_with("GFC3D_Example00"))
            .collect();
    names.sort();
    assert_eq!(names.len(), 21, "{names:?}");
    for name in &names {
        let problem = three(name);
        let newton = NewtonSettings {
            tolerance: 1e-12,
            ..NewtonSettings::default()
        };
        let mut lambda = Vec::new();
        let report = solve_newton_local(&problem, &newton, &mut lambda);
        let error = siconos_error(&problem, &lambda);
        assert!(
            error <= 1e-8,
            "{name}: Newton {report:?}, Siconos error {error:e}"
        );
        assert!(coulomb_residual(&problem, &lambda) <= 1e-8, "{name}");
        let mut nsgs = Vec::new();
        let settings = pgs_settings(LocalSolve::Exact, 20_000, Some(1e-12));
        solve_pgs_local(&problem, &settings, 0, &mut nsgs);
        let error = siconos_error(&problem, &nsgs);
        assert!(
            error <= 1e-8,
            "{name}: PGS (exact visits) Siconos error {error:e}"
        );
    }
}

#[test]
fn newton_matches_siconos_solutions_on_known_problems() {
    // Siconos 4.4's Newton (Alart–Curnier) answers r, in full precision (docs/problem-library.md
    // §"Known answers"): sliding single contacts (Rover11035, FrictionContact3D_1c), three
    // separate sliding contacts (FC3D_Example1_SBM) and four coupled contacts of which one
    // carries the load (Confeti). Ours must agree to 1e-7 of ‖r‖: Siconos stopped at its
    // relative error 1e-8 or below, ours at 1e-12 m/s.
    let known: [(&str, Vec<[f64; 3]>); 4] = [
        (
            "Rover11035.dat",
            vec![[3.855527686824136, 1.0750356386021485, 2.4755189982088317]],
        ),
        (
            "FrictionContact3D_1c.dat",
            vec![[
                0.06569568289769018,
                -0.0036786149069098152,
                -0.005443070813868708,
            ]],
        ),
        (
            "FC3D_Example1_SBM.dat",
            vec![[1.0, -0.0316227766016838, -0.09486832980505139]; 3],
        ),
        (
            "Confeti-ex13-4contact-Fc3D-SBM.dat",
            vec![
                [0.0, -2.2123580536140904e-16, -1.893475646534647e-17],
                [0.0, -2.1957432276801253e-16, 3.302912892102808e-17],
                [387.26299136821257, -15.422891482731771, -1.445896775502959],
                [0.0, -2.212699881334021e-16, -1.8531026084848616e-17],
            ],
        ),
    ];
    for (name, r) in known {
        let problem = three(name);
        let mut lambda = Vec::new();
        let settings = NewtonSettings {
            tolerance: 1e-12,
            ..NewtonSettings::default()
        };
        let report = solve_newton_local(&problem, &settings, &mut lambda);
        assert!(report.converged, "{name}: {report:?}");
        let size = r
            .iter()
            .map(|x| x.iter().map(|v| v * v).sum::<f64>())
            .sum::<f64>()
            .sqrt();
        let difference = lambda
            .iter()
            .zip(&r)
            .map(|(l, r)| (l - SVector::<f64, 3>::from_column_slice(r)).norm_squared())
            .sum::<f64>()
            .sqrt();
        assert!(
            difference <= 1e-7 * size,
            "{name}: {lambda:?} vs Siconos {r:?}"
        );
    }
}

#[test]
fn the_checks_read_both_forms_alike() {
    // The residual, the exact Coulomb residual and the criteria of a λ are the same computed
    // through the bodies or through W.
    proptest!(common::seeded(40), |(s in physical_spec(1..4, 1..6), mu in 0.0..1.0f64)| {
        let problem = build(&s, mu, 1e-3, FrictionModel::Cone);
        let local = problem.to_local();
        let lambda: Vec<SVector<f64, 3>> = (0..problem.contacts.len())
            .map(|k| nalgebra::Vector3::new(0.1 * (k + 1) as f64, 0.01, -0.02))
            .collect();
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * (1.0 + a.abs());
        prop_assert!(close(residual(&problem, &lambda), residual(&local, &lambda)));
        prop_assert!(close(coulomb_residual(&problem, &lambda), coulomb_residual(&local, &lambda)));
        prop_assert!(close(siconos_error(&problem, &lambda), siconos_error(&local, &lambda)));
        let (_, a) = rigidref::solve::criteria::criteria(&problem, &lambda);
        let (_, b) = rigidref::solve::criteria::criteria(&local, &lambda);
        prop_assert!(close(a.complementarity, b.complementarity) && close(a.dual, b.dual));
        prop_assert_eq!(ProblemView::count(&local), problem.contacts.len());
    });
}

#[test]
fn siconos_sparse_storage_and_hostile_headers_read_or_fail_in_one_line() {
    // W = [[2, 0, 1], [0, 3, 0], [1, 0, 4]] (one 3D contact) in each CSparse layout Siconos
    // writes: compressed columns (origin 2), compressed rows (3: the transpose's text), triplets.
    let banner = "CSparse Version 3.1.9, May 4, 2016.  Copyright (c) Timothy A. Davis, 2006-2016";
    let csc = format!(
        "3\n1\n2\n3\n3\n2\n{banner}\n3-by-3, nzmax: 5 nnz: 5, 1-norm: 5\n    col 0 : locations 0 to 1\n      0 : 2\n      2 : 1\n    col 1 : locations 2 to 2\n      1 : 3\n    col 2 : locations 3 to 4\n      0 : 1\n      2 : 4\n-1 0 0\n0.5\n"
    );
    let w = DMatrix::from_row_slice(3, 3, &[2.0, 0.0, 1.0, 0.0, 3.0, 0.0, 1.0, 0.0, 4.0]);
    let read = |text: &str| match parse_dat(text).unwrap() {
        AnyLocalProblem::Three(p) => p.dense_w(),
        AnyLocalProblem::Two(_) => panic!("2D"),
    };
    assert_eq!(read(&csc), w);
    // Compressed rows of a non-symmetric W: row 0 holds (0, 0) = 2 and (0, 2) = 5.
    let csr = csc
        .replace("\n2\n3\n3\n2\n", "\n2\n3\n3\n3\n")
        .replace("col ", "row ")
        .replace("      2 : 1\n    row 1", "      2 : 5\n    row 1");
    let mut nonsymmetric = w.clone();
    nonsymmetric[(0, 2)] = 5.0;
    assert_eq!(read(&csr), nonsymmetric);
    let triplet = format!(
        "3\n1\n2\n3\n3\n1\n{banner}\ntriplet: 3-by-3, nzmax: 5 nnz: 5\n    0 0 : 2\n    2 0 : 1\n    1 1 : 3\n    0 2 : 1\n    2 2 : 4\n-1 0 0\n0.5\n"
    );
    assert_eq!(read(&triplet), w);
    // A column header out of order is refused with the line.
    let err = parse_dat(&csc.replace("col 1 :", "col 7 :")).unwrap_err();
    assert!(err.contains("col 7"), "{err}");
    // Headers that promise absurd sizes are refused before anything is allocated, never a
    // panic (sizes near usize::MAX, whose sums and products overflow).
    for text in [
        "3 1 1 3 3 18446744073709551615 1 1 3 3 2 18446744073709551615",
        "3 1431655766 1 4294967298 4294967298 1 1 1 4294967298 4294967298 2 1 0 1 0 0",
        "3 6148914691236517206 0 18446744073709551618 0",
    ] {
        assert!(parse_dat(text).is_err(), "{text}");
    }
    // A problem without contacts writes and reads back.
    let empty = LocalProblem::<3> {
        friction: FrictionModel::Cone,
        contacts: Vec::new(),
    };
    match parse_dat(&write_dat(&empty)).unwrap() {
        AnyLocalProblem::Three(p) => assert!(p.contacts.is_empty()),
        AnyLocalProblem::Two(_) => panic!("2D"),
    }
}

#[test]
fn frictionless_separation_is_a_solution_of_every_measure() {
    // μ = 0, W = I, q = (1, 0, 0): the contact separates, λ = 0 exactly. The cone K₀ is the
    // half-line λt = 0, λn ≥ 0; its polar must be tested first (a bug returned (n < 0, 0) as
    // inside K₀ and reported this exact solution with error 1).
    let problem = LocalProblem::<3>::from_dense(
        FrictionModel::Cone,
        &DMatrix::identity(3, 3),
        &DVector::from_column_slice(&[1.0, 0.0, 0.0]),
        &[0.0],
    )
    .unwrap();
    let zero = vec![SVector::<f64, 3>::zeros()];
    assert_eq!(siconos_error(&problem, &zero), 0.0);
    assert_eq!(coulomb_residual(&problem, &zero), 0.0);
    let (_, worst) = rigidref::solve::criteria::criteria(&problem, &zero);
    assert_eq!(worst.dual, 0.0);
    let mut lambda = Vec::new();
    let report = solve_newton_local(&problem, &NewtonSettings::default(), &mut lambda);
    assert!(
        report.converged && lambda[0] == SVector::<f64, 3>::zeros(),
        "{report:?} {lambda:?}"
    );
    // And a pulling λn is outside K₀: its distance is |λn|.
    let pulling = vec![SVector::<f64, 3>::new(-1.0, 0.0, 0.0)];
    assert_eq!(
        rigidref::solve::criteria::criteria(&problem, &pulling)
            .1
            .primal,
        1.0
    );
}

#[test]
fn a_contact_of_a_body_with_itself_is_refused() {
    // Its Delassus block would differ between the forms (the cross terms J₁M⁻¹J₂ᵀ of one body).
    proptest!(common::seeded(5), |(s in physical_spec(1..3, 1..3))| {
        let mut problem = build(&s, 0.5, 0.0, FrictionModel::Box);
        problem.contacts[0].bodies = [Some(0), Some(0)];
        let err = problem.validate().unwrap_err();
        prop_assert!(err.contains("both sides are body 0"), "{}", err);
    });
}

#[test]
fn box_friction_problems_are_judged_by_their_own_law_in_the_library() {
    // A run's problems have the assignment's box friction; solve-problems stops on the box
    // law's residual (relative), which the solvers reach, not on the cone's error.
    use rigidref::tools::experiments::problem_library::{LibrarySettings, LibrarySolver, attempt};
    proptest!(common::seeded(20), |(s in physical_spec(1..3, 1..5), mu in 0.1..1.0f64)| {
        let local = build(&s, mu, 1e-3, FrictionModel::Box).to_local();
        let newton = attempt(&local, LibrarySolver::Newton, &LibrarySettings::default());
        prop_assert!(newton.converged, "{:?}", newton);
        prop_assert!(newton.error <= 1e-8);
    });
}

#[cfg(feature = "fclib")]
mod fclib {
    //! FCLIB's HDF5 files (docs/problem-library.md §"FCLIB"), with the feature `fclib`.
    use super::*;
    use rigidref::problem::fclib::{FclibProblem, read_fclib, write_fclib};

    #[test]
    fn the_fclib_reader_reads_the_fclib_test_problem_as_h5py_does() {
        let path = common::project_root().join("tests/data/fclib/local_problem_test.hdf5");
        let FclibProblem::Local {
            problem: AnyLocalProblem::Three(p),
            solution,
        } = read_fclib(&path).unwrap()
        else {
            panic!("not a 3D local problem")
        };
        // Values as h5py reads them (W in compressed rows: row 0's first entries, row 100's).
        assert_eq!(p.contacts.len(), 48);
        let w = p.dense_w();
        assert_eq!(w[(0, 0)], 100.0);
        assert_eq!(w[(0, 1)], 8.352906270848802e-09);
        assert_eq!(w[(0, 2)], -8.001161284610685e-09);
        assert_eq!(w[(0, 3)], 100.00000000765515);
        assert_eq!(w[(0, 4)], 1.4378473643289639e-08);
        assert_eq!(w[(100, 84)], 3.3794218208705846e-09);
        assert_eq!(w[(100, 85)], 27.311553811812914);
        assert_eq!(p.contacts[0].q[0], -0.004904999642630031);
        assert_eq!(p.contacts[0].q[1], -4.4967715418338097e-10);
        assert_eq!(p.contacts[0].mu, 0.7);
        // The first guess is the warm start; the solution is there.
        assert_eq!(p.contacts[0].lambda0[0], 0.0004010604092983265);
        assert_eq!(p.contacts[0].lambda0[1], -2.560624503173503e-06);
        assert_eq!(solution.map(|r| r.len()), Some(144));
        // Every stored entry counted: 4896 in W, in 3 × 3 blocks.
        assert!(p.blocks() * 9 >= 4896);
        // And it is solved to Siconos' tolerance.
        let mut lambda = Vec::new();
        let settings = NewtonSettings {
            tolerance: 1e-12,
            ..NewtonSettings::default()
        };
        solve_newton_local(&p, &settings, &mut lambda);
        assert!(siconos_error(&p, &lambda) <= 1e-8);
        // Something that is not an FCLIB file is refused with the file's name.
        let err = read_fclib(&data("Rover4396.dat")).unwrap_err();
        assert!(
            err.contains("Rover4396.dat") && err.contains("not an HDF5 file"),
            "{err}"
        );
    }

    #[test]
    fn a_problem_written_as_fclib_reads_back_bit_for_bit() {
        let dir = tempfile::tempdir().unwrap();
        proptest!(common::seeded(20), |(s in physical_spec(1..4, 1..7), mu in 0.0..1.0f64, warm: bool)| {
            let mut problem = build(&s, mu, 1e-4, FrictionModel::Cone);
            if warm {
                for c in &mut problem.contacts {
                    c.lambda0 = nalgebra::Vector3::new(0.2, 0.01, -0.03);
                }
            }
            let local = problem.to_local();
            let path = dir.path().join("p.hdf5");
            let lambda: Vec<SVector<f64, 3>> =
                local.contacts.iter().map(|_| nalgebra::Vector3::new(1.0, 0.1, 0.2)).collect();
            write_fclib(&local, "a test", Some(&lambda), &path).unwrap();
            let FclibProblem::Local { problem: AnyLocalProblem::Three(back), solution } =
                read_fclib(&path).unwrap()
            else {
                panic!("not read back as a 3D local problem")
            };
            prop_assert_eq!(&back, &local);
            let r: Vec<f64> = lambda.iter().flat_map(|l| l.iter().copied()).collect();
            prop_assert_eq!(solution, Some(r));
        });
    }

    #[test]
    fn fclib_files_that_contradict_themselves_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let mut problem = LocalProblem::<3>::from_dense(
            FrictionModel::Cone,
            &DMatrix::identity(3, 3),
            &DVector::from_column_slice(&[-1.0, 0.0, 0.0]),
            &[0.5],
        )
        .unwrap();
        // A NaN in the first guess (the warm start) cannot reach a solver.
        problem.contacts[0].lambda0 = nalgebra::Vector3::new(f64::NAN, 0.0, 0.0);
        let path = dir.path().join("nan.hdf5");
        write_fclib(&problem, "nan guess", None, &path).unwrap();
        let err = read_fclib(&path).unwrap_err();
        assert!(
            err.contains("nan.hdf5") && err.contains("non-finite"),
            "{err}"
        );
        // A solution of another length than W's rows is an error, not dropped.
        problem.contacts[0].lambda0 = SVector::zeros();
        let short = [SVector::<f64, 3>::zeros(); 2];
        let path = dir.path().join("long.hdf5");
        write_fclib(&problem, "two solutions", Some(&short), &path).unwrap();
        let err = read_fclib(&path).unwrap_err();
        assert!(
            err.contains("solution/r has 6 entries, W has 3 rows"),
            "{err}"
        );
    }

    #[test]
    fn a_global_fclib_problem_reads_into_the_body_form() {
        // Written here from a run-like problem: M block diagonal (6 × 6 per body), H = Jᵀ,
        // f = M u, w = b − J u; read back, the body form gives the same local form.
        proptest!(common::seeded(10), |(s in physical_spec(1..4, 1..6))| {
            let problem = build(&s, 0.5, 0.0, FrictionModel::Cone);
            let dir = tempfile::tempdir().unwrap();
            let path = dir.path().join("g.hdf5");
            write_global(&problem, &path);
            let FclibProblem::Global(back) = read_fclib(&path).unwrap() else { panic!() };
            let (a, b) = (problem.to_local(), back.to_local());
            let scale = a.dense_w().amax();
            prop_assert!((a.dense_w() - b.dense_w()).amax() <= 1e-9 * scale);
            prop_assert!((a.dense_q() - b.dense_q()).amax() <= 1e-9 * (1.0 + a.dense_q().amax()));
        });
    }

    /// An FCLIB global file of a body-form problem, written with the hdf5 crate directly (the
    /// project writes local files only).
    fn write_global(problem: &rigidref::problem::ContactProblem<6, 3>, path: &std::path::Path) {
        // Unlocked, as the project's writer does (src/problem/fclib.rs::unlocked).
        let file = hdf5::File::with_options()
            .with_fapl(|p| p.file_locking(false))
            .create(path)
            .unwrap();
        let g = file.create_group("fclib_global").unwrap();
        let put_i = |g: &hdf5::Group, n: &str, v: &[i32]| {
            g.new_dataset_builder().with_data(v).create(n).unwrap();
        };
        let put_f = |g: &hdf5::Group, n: &str, v: &[f64]| {
            g.new_dataset_builder().with_data(v).create(n).unwrap();
        };
        put_i(&g, "spacedim", &[3]);
        let nb = problem.bodies.len();
        let (mut i, mut p, mut x) = (vec![], vec![], vec![]);
        let mut f = vec![0.0; 6 * nb];
        for (b, body) in problem.bodies.iter().enumerate() {
            let m = body.inverse_mass.try_inverse().unwrap();
            let fb = m * body.velocity;
            for r in 0..6 {
                f[6 * b + r] = fb[r];
                for c in 0..6 {
                    i.push((6 * b + r) as i32);
                    p.push((6 * b + c) as i32);
                    x.push(m[(r, c)]);
                }
            }
        }
        let mg = g.create_group("M").unwrap();
        for (n, v) in [
            ("m", 6 * nb),
            ("n", 6 * nb),
            ("nz", x.len()),
            ("nzmax", x.len()),
        ] {
            put_i(&mg, n, &[v as i32]);
        }
        put_i(&mg, "i", &i);
        put_i(&mg, "p", &p);
        put_f(&mg, "x", &x);
        let j = problem.dense_jacobian();
        let (mut i, mut p, mut x) = (vec![], vec![], vec![]);
        for r in 0..j.nrows() {
            for c in 0..j.ncols() {
                if j[(r, c)] != 0.0 {
                    // H = Jᵀ: row c, column r.
                    i.push(c as i32);
                    p.push(r as i32);
                    x.push(j[(r, c)]);
                }
            }
        }
        let hg = g.create_group("H").unwrap();
        for (n, v) in [
            ("m", j.ncols()),
            ("n", j.nrows()),
            ("nz", x.len()),
            ("nzmax", x.len()),
        ] {
            put_i(&hg, n, &[v as i32]);
        }
        put_i(&hg, "i", &i);
        put_i(&hg, "p", &p);
        put_f(&hg, "x", &x);
        let u: Vec<f64> = problem
            .bodies
            .iter()
            .flat_map(|b| b.velocity.iter().copied())
            .collect();
        let ju = &j * nalgebra::DVector::from_vec(u);
        let w: Vec<f64> = (0..j.nrows())
            .map(|r| problem.dense_b()[r] - ju[r])
            .collect();
        let v = g.create_group("vectors").unwrap();
        put_f(&v, "f", &f);
        put_f(&v, "w", &w);
        let mu: Vec<f64> = problem.contacts.iter().map(|c| c.mu).collect();
        put_f(&v, "mu", &mu);
        drop((g, mg, hg, v));
        file.close().unwrap();
    }
}
