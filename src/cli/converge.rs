//! `rigidref converge`: a scene run at several step sizes, each observable's observed order of
//! convergence. docs/verification.md §"Convergence order".

use anyhow::bail;
use clap::Args;
use rigidref::sim::readable;
use rigidref::verify::convergence::{
    Convergence, Observable, ROUND_OFF, ReferenceChoice, converge,
};
use std::path::PathBuf;

/// Arguments of `rigidref converge`.
#[derive(Args)]
#[command(after_long_help = "\
Runs the scene once per step size (the scene's substeps are kept, so h = dt / substeps shrinks
with dt) and measures each observable of one body:

  stop_time       the time it stops, s: at the first step whose speed is below 1e-9 m/s, where
                  the line through the speeds of the two steps before reaches 0 (exact under
                  constant deceleration; reading the step grid would be an O(dt) quantisation)
  stop_distance   the horizontal distance its centre travelled until then, m
  first_flip      the first sign change of its body-frame spin about the intermediate principal
                  axis (the Dzhanibekov flip), s, interpolated between steps
  first_reversal  the first sign change of its world spin ω_y (the rattleback), s, interpolated
  final_x … final_wz
                  a position (m), velocity (m/s) or world spin (rad/s) component at --time

Errors are measured against a reference (--reference; by default the observable's own): the
closed form v₀/(μg) or v₀²/(2μg) of a body sliding on the ground (cone friction, or box friction
along a tangent axis; one body, no spin, no load), RK4 of the torque-free Euler equations for a
body that touches nothing, RK4 of the ellipsoid rolling without slipping for a body with an
`ellipsoid`, or a number you give. The observed order between successive step sizes is
p = ln(|e₁|/|e₂|) / ln(dt₁/dt₂). Independently of any reference, every three successive runs give
Richardson's order (the p of Q(dt) = Q* + C dtᵖ through them) and the last three the extrapolated
value Q*; `richardson` uses that alone. A computed reference also states its own error (the
change when its step is doubled).

With --expect P, the command exits with status 1 when an observed order (against the reference,
else Richardson's) lies outside P ± --band.

Example: rigidref converge scenes/sliding_cube.json --dt 1e-3,5e-4,2.5e-4,1.25e-4 \\
             --observable stop_time --observable stop_distance")]
pub struct ConvergeArgs {
    /// A 3D scene file.
    pub scene: PathBuf,
    /// Step sizes dt, s, comma-separated (at least two; run largest first).
    #[arg(
        long,
        value_delimiter = ',',
        required = true,
        allow_negative_numbers = true
    )]
    pub dt: Vec<f64>,
    /// What to measure (repeatable): stop_time, stop_distance, first_flip, first_reversal,
    /// final_x … final_wz (see below).
    #[arg(long, required = true)]
    pub observable: Vec<String>,
    /// The reference: auto, closed-form, rk4, no-slip, richardson, or a number in the
    /// observable's unit (only with one observable).
    #[arg(long, default_value = "auto", allow_negative_numbers = true)]
    pub reference: String,
    /// The body measured, by index from 0.
    #[arg(long, default_value_t = 0)]
    pub body: usize,
    /// Longest simulated time of a run, s (event observables stop at the event).
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
    pub time: f64,
    /// Exit with status 1 when an observed order is outside EXPECT ± BAND.
    #[arg(long)]
    pub expect: Option<f64>,
    /// Half-width of the accepted band around --expect.
    #[arg(long, default_value_t = 0.2, requires = "expect")]
    pub band: f64,
    /// Print the reports as JSON.
    #[arg(long)]
    pub json: bool,
    /// No progress lines.
    #[arg(long, short)]
    pub quiet: bool,
    #[command(flatten)]
    pub sets: super::args::SceneSets,
}

/// Runs the convergence study.
pub fn converge_command(args: ConvergeArgs) -> anyhow::Result<()> {
    super::common::check_readable(Some(&args.scene))?;
    if rigidref::blocks2d::scene::is_2d_scene(&args.scene) {
        bail!(
            "{}: converge works on 3D scenes; this is a 2D scene",
            args.scene.display()
        );
    }
    let observables = args
        .observable
        .iter()
        .map(|o| o.parse::<Observable>())
        .collect::<Result<Vec<_>, _>>()
        .map_err(anyhow::Error::msg)?;
    let reference: ReferenceChoice = args.reference.parse().map_err(anyhow::Error::msg)?;
    if matches!(reference, ReferenceChoice::Value(_)) && observables.len() > 1 {
        bail!(
            "--reference {}: a number is one observable's reference; give one --observable",
            args.reference
        );
    }
    let scene = super::common::load_scene_or_default(Some(&args.scene), &args.sets)?;
    let mut reports = Vec::new();
    for &observable in &observables {
        let report = converge(
            &scene,
            &args.dt,
            observable,
            args.body,
            args.time,
            reference,
            |run| {
                if !args.quiet {
                    eprintln!(
                        "{observable}: dt {} s, {} steps: {} {}",
                        readable(run.dt),
                        run.steps,
                        run.value,
                        observable.unit()
                    );
                }
            },
        )
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.scene.display()))?;
        reports.push(report);
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&reports)?);
    } else {
        for r in &reports {
            print_report(r);
        }
    }
    if let Some(expect) = args.expect {
        let outside: Vec<String> = reports
            .iter()
            .flat_map(|r| {
                judged_orders(r)
                    .into_iter()
                    .filter(|p| (p - expect).abs() > args.band || p.is_nan())
                    .map(move |p| format!("{} {p:.3}", r.observable))
            })
            .collect();
        let none: Vec<&str> = reports
            .iter()
            .filter(|r| judged_orders(r).is_empty())
            .map(|r| r.observable.as_str())
            .collect();
        if !outside.is_empty() || !none.is_empty() {
            let mut why = Vec::new();
            if !outside.is_empty() {
                why.push(format!(
                    "outside {expect} ± {}: {}",
                    args.band,
                    outside.join(", ")
                ));
            }
            if !none.is_empty() {
                why.push(format!(
                    "no order could be measured for {}",
                    none.join(", ")
                ));
            }
            bail!(
                "{}: observed orders {}",
                args.scene.display(),
                why.join("; ")
            );
        }
    }
    Ok(())
}

/// The orders judged by --expect: against the reference where there is one, else Richardson's.
fn judged_orders(r: &Convergence) -> Vec<f64> {
    if r.reference.is_some() {
        r.runs.iter().filter_map(|run| run.order).collect()
    } else {
        r.richardson_orders.iter().flatten().copied().collect()
    }
}

fn print_report(r: &Convergence) {
    println!("{} ({})", r.observable, r.unit);
    match &r.reference {
        Some(reference) => println!(
            "  reference {} {} ({}{})",
            reference.value,
            r.unit,
            reference.how,
            if reference.uncertainty > 0.0 {
                format!("; its own error ≈ {:.1e}", reference.uncertainty)
            } else {
                String::new()
            }
        ),
        None => println!("  no reference: Richardson extrapolation of the runs"),
    }
    println!(
        "  {:>10}  {:>8}  {:>20}  {:>11}  {:>6}",
        "dt (s)", "steps", "value", "error", "order"
    );
    for run in &r.runs {
        println!(
            "  {:>10}  {:>8}  {:>20.12}  {:>11}  {:>6}",
            readable(run.dt),
            run.steps,
            run.value,
            run.error.map_or("–".into(), |e| format!("{e:+.3e}")),
            run.order.map_or("–".into(), |p| format!("{p:.3}"))
        );
    }
    if let Some(reference) = &r.reference
        && r.runs.iter().all(|run| {
            run.error
                .is_some_and(|e| e.abs() <= ROUND_OFF * reference.value.abs().max(1.0))
        })
    {
        println!(
            "  every error is at round-off ({ROUND_OFF:.0e} relative): the scheme is exact for this observable; no order to measure"
        );
    }
    if r.reference.is_none()
        && let Some(last) = r.runs.last()
        && r.runs
            .iter()
            .all(|run| (run.value - last.value).abs() <= ROUND_OFF * last.value.abs().max(1.0))
    {
        println!(
            "  the runs agree to round-off ({ROUND_OFF:.0e} relative): the step does not change this observable; no order to measure"
        );
    }
    let orders: Vec<String> = r
        .richardson_orders
        .iter()
        .map(|p| p.map_or("undefined".into(), |p| format!("{p:.3}")))
        .collect();
    if !orders.is_empty() {
        println!(
            "  Richardson orders (successive triples): {}; extrapolated {}",
            orders.join(", "),
            r.extrapolated
                .map_or("–".into(), |q| format!("{q} {}", r.unit))
        );
    }
}
