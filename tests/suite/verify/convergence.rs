//! Observed orders of convergence in the step size (docs/verification.md §"Convergence order"),
//! measured by `rigidref::verify::convergence` (the library side of `rigidref converge`).

use crate::common;

use rigidref::rigid3d::scene::{Scene, load_scene};
use rigidref::verify::convergence::{Convergence, Observable, ReferenceChoice, converge};

fn scene(name: &str) -> Scene {
    load_scene(&common::project_root().join("scenes").join(name)).unwrap()
}

fn study(scene: &Scene, dts: &[f64], observable: &str, time: f64) -> Convergence {
    let observable: Observable = observable.parse().unwrap();
    let report = converge(
        scene,
        dts,
        observable,
        0,
        time,
        ReferenceChoice::Auto,
        |_| {},
    )
    .unwrap();
    println!("{report:#?}");
    report
}

/// The sliding cube (scenes/sliding_cube.json, v₀ = 1 m/s, μ = 0.4): its stopping distance
/// converges to v₀²/(2μg) at first order (the error is −v₀ h/2: the first step's friction acts
/// before its position update), and its stop time, read where the speed's line reaches 0, equals
/// v₀/(μg) at every step size to round-off: under constant deceleration symplectic Euler's
/// velocity is exact. Richardson's order from the runs alone agrees with the closed form's.
#[test]
fn the_sliding_stop_distance_is_first_order_and_its_time_exact() {
    let cube = scene("sliding_cube.json");
    let dts = [1e-3, 5e-4, 2.5e-4, 1.25e-4];
    let distance = study(&cube, &dts, "stop_distance", 1.0);
    for run in &distance.runs[1..] {
        // Within 0.01 of 1: the last step's partial deceleration adds a term of order h² that the
        // halvings do not cancel exactly (measured 1.000 to 3 decimals).
        let order = run.order.unwrap();
        assert!((order - 1.0).abs() <= 0.01, "{order}");
        let e = run.error.unwrap();
        // e = −v₀ h/2 to 1% (v₀ = 1 m/s).
        assert!(
            (e + run.dt / 2.0).abs() <= 0.01 * run.dt / 2.0,
            "error {e} at dt {}",
            run.dt
        );
    }
    for p in &distance.richardson_orders {
        assert!((p.unwrap() - 1.0).abs() <= 0.01, "{p:?}");
    }
    let exact = distance.reference.as_ref().unwrap().value;
    // Richardson's extrapolation removes the O(h) term: 1e-6 m of 0.127 m (measured 1.6e-8).
    assert!((distance.extrapolated.unwrap() - exact).abs() < 1e-6);

    let time = study(&cube, &dts, "stop_time", 1.0);
    for run in &time.runs {
        // 1e-13 s: round-off of a few hundred steps of 1 m/s.
        assert!(run.error.unwrap().abs() < 1e-13, "{run:?}");
        assert_eq!(run.order, None, "an order read from round-off");
    }
    assert!(time.richardson_orders.iter().all(Option::is_none));
}

/// The rattleback (scenes/rattleback.json): its first reversal (ω_y's sign change) converges as
/// the step shrinks, at Richardson's order 0.87 over dt = 0.1, 0.05, 0.025 ms, to about 4.84 s,
/// 1% after the no-slip model's 4.789 s (RK4, its own error 3e-6 s): the contact stepping is
/// first order, and what remains at h → 0 is the difference of the models (slip, the slop's
/// stabilisation), not the step. Band: order within 0.25 of 1 (the runs are still approaching
/// the asymptotic range: 0.78 for the triple ending at 0.05 ms); the extrapolated time within
/// 2% of the no-slip reference and later than it.
#[test]
fn the_rattleback_reversal_converges_at_first_order_near_the_no_slip_model() {
    let rattleback = scene("rattleback.json");
    let report = study(&rattleback, &[1e-4, 5e-5, 2.5e-5], "first_reversal", 8.0);
    let reference = report.reference.as_ref().unwrap();
    assert!(reference.how.contains("without slipping"));
    assert!(reference.uncertainty < 1e-4, "{reference:?}");
    // The errors shrink toward the model's: each run nearer the no-slip time than the last.
    let errors: Vec<f64> = report.runs.iter().map(|r| r.error.unwrap().abs()).collect();
    assert!(errors.windows(2).all(|e| e[1] < e[0]), "{errors:?}");
    let p = report.richardson_orders[0].unwrap();
    assert!((p - 1.0).abs() <= 0.25, "Richardson order {p}");
    let limit = report.extrapolated.unwrap();
    let gap = (limit - reference.value) / reference.value;
    assert!(
        gap > 0.0 && gap < 0.02,
        "extrapolated {limit}, no-slip {}",
        reference.value
    );
}

/// A reference that does not apply is refused in one line, naming why: the closed form of the
/// stop for a spinning body in zero gravity, RK4 for a body that can touch others, the no-slip
/// model for a body without an ellipsoid, and a reference kind for the wrong observable.
#[test]
fn a_reference_that_does_not_apply_is_refused_naming_why() {
    let refuse = |scene: &Scene, observable: &str, reference: ReferenceChoice| -> String {
        let e = converge(
            scene,
            &[1e-3, 5e-4],
            observable.parse().unwrap(),
            0,
            0.01,
            reference,
            |_| {},
        )
        .unwrap_err();
        assert!(!e.contains('\n'), "{e}");
        e
    };
    let spinning = scene("dzhanibekov.json");
    let e = refuse(&spinning, "stop_time", ReferenceChoice::Auto);
    assert!(
        e.contains("no closed form") && e.contains("gravity") && e.contains("richardson"),
        "{e}"
    );
    let stack = scene("box_stack.json");
    let e = refuse(&stack, "first_flip", ReferenceChoice::Auto);
    assert!(e.contains("rk4") && e.contains("touches nothing"), "{e}");
    let e = refuse(&stack, "first_reversal", ReferenceChoice::Auto);
    assert!(e.contains("no-slip") && e.contains("ellipsoid"), "{e}");
    let e = refuse(&spinning, "final_x", ReferenceChoice::Rk4);
    assert!(e.contains("does not give final_x"), "{e}");
    // An event that does not happen within the time is an error naming the body and the step.
    let e = converge(
        &spinning,
        &[1e-2, 5e-3],
        Observable::FirstFlip,
        0,
        0.05,
        ReferenceChoice::Richardson,
        |_| {},
    )
    .unwrap_err();
    assert!(e.contains("did not flip") && e.contains("--time"), "{e}");
}
