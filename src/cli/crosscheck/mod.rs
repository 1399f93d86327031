//! `rigidref crosscheck`: every contact problem of a run (or of problem files) solved by PGS run
//! to convergence and by clarabel, and compared. docs/verification.md §"clarabel".

mod print;
mod report;

use crate::cli::progress::{Progress, Stopped};
use anyhow::{Context, bail};
use clap::Args;
use print::{describe_verdict, print_summary, print_table};
pub use report::Unverified;
use report::{Limits, Row, summarise};
use rigidref::problem::local_json::AnyProblemFile;
use rigidref::rigid3d::collide::audit::DetectionAudit;
use rigidref::rigid3d::penetration_watch::InterpenetrationWatch;
use rigidref::rigid3d::world::World;
use rigidref::sim::{Flow, Simulation, drive, steps_in};
use rigidref::verify::crosscheck::{CrosscheckSettings, check_problem, check_step};
use std::path::{Path, PathBuf};

/// Arguments of `rigidref crosscheck`.
#[derive(Args)]
#[command(after_long_help = "\
For every contact problem, the answer of the solver under test is checked. With the default
solver (pgs), PGS is run to convergence (residual 1e-12 m/s, at most 200000 sweeps; not the
scene's pgs_iterations); with --set solver=newton, the answer checked is the step's own λ from
the Newton solver (what the run applied). Its residual is recomputed from the problem and λ
alone, and clarabel solves the convex program with the same solution: the frictionless QP when μ = 0, else the QP (box) or SOCP (cone) with the friction
bounds fixed at PGS's normal impulses, which PGS's answer must minimise. Where the objective is
strictly convex on the free rows, λ is unique and, where clarabel's answer provably lies within
1e-6 of it (a bound from clarabel's residual and the conditioning), compared:
‖λ_pgs − λ_qp‖ / max(‖λ_qp‖, λ_ref) with λ_ref = max(‖b‖, 0.1 m/s) / max diag(A + C). Where it is
not (a rigid brick resting on four corners; a nearly singular problem), only the optimal value
is, and the one-sided relative objective gap is compared (docs/verification.md §\"clarabel\").
For cone friction the report also gives the distance to Anitescu's relaxation (the SOCP with no
fixed data), which differs from PGS wherever a contact slides.

Coupled friction is not a monotone problem; where the answer is not converged (residual above
1e-10 m/s), the problem is reported as unverified, not compared. With PGS under test, the exact
solver (Newton, docs/contact.md §\"Newton solver\") also solves every problem, and the report gives
each problem's distance to the exact solution: max |u⁺ − u⁺_exact| over the bodies' velocities
for PGS's converged answer and for the step's λ, and the step λ's residual (its violation of the
contact law), so an unverified problem still says how wrong PGS was. --set solver=newton checks
the exact solver's own answers instead. For cone friction the exact Coulomb law's residual of
the answers is reported too. The verdict is one of three: agree (every problem verified within
tolerance; exit status 0), unverified (none disagrees, but some could not be checked; exit status
3), disagree (some comparison exceeds its tolerance or clarabel fails; exit status 1). With
--strict, unverified problems count as disagreeing.

A 3D scene's detection is checked too: on every substep, each pair of convex bodies within
reach has its contacts held against the separating-axis oracle (which shares no code with
detection): an overlap with no contact as deep, a contact deeper than the bodies overlap, or a
manifold normal along which they overlap by more than the least-penetration depth (up to the face
preferences' 11 %) is a disagreement (docs/contact.md §\"The oracle campaign\"). Formulations: docs/contact.md §\"Convex formulations\".")]
pub struct CrosscheckArgs {
    /// A scene file (3D, or 2D: an image or a 2D scene file), a contact-problem file (from
    /// `run --dump-problems`), or a folder of them. Without one, the built-in default scene.
    pub input: Option<PathBuf>,
    /// Simulated time to run a scene, s (2D: time units).
    #[arg(long, default_value_t = 5.0)]
    pub time: f64,
    /// Largest relative λ difference accepted where λ is unique.
    #[arg(long, default_value_t = 1e-5, conflicts_with = "rapier")]
    pub tolerance: f64,
    /// Largest relative objective gap accepted where λ is not unique.
    #[arg(long, default_value_t = 1e-8, conflicts_with = "rapier")]
    pub objective_tolerance: f64,
    /// Print one line per problem.
    #[arg(long, conflicts_with = "rapier")]
    pub table: bool,
    /// Also fail when PGS cannot converge on some problem (instead of reporting it unverified).
    #[arg(long, conflicts_with = "rapier")]
    pub strict: bool,
    /// How PGS visits a contact while run to convergence: `rows` (the assignment's row-by-row
    /// update) or `exact` (each contact's own problem solved exactly; docs/contact.md §"Exact
    /// local solve") [default: the scene's pgs_local_solve; rows for problem files].
    #[arg(long, value_enum)]
    pub pgs_local_solve: Option<rigidref::solve::LocalSolve>,
    /// Print the summary (and with --table every problem) as JSON.
    #[arg(long)]
    pub json: bool,
    /// Compare the scene against a rapier3d mirror instead (docs/verification.md §"rapier3d").
    #[arg(long)]
    pub rapier: bool,
    #[command(flatten)]
    pub sets: crate::cli::args::SceneSets,
}

/// Runs the cross-check.
pub fn crosscheck(args: CrosscheckArgs) -> anyhow::Result<()> {
    if args.rapier {
        return crate::cli::rapier::rapier(args.input.as_deref(), &args.sets, args.time, args.json);
    }
    if !(args.tolerance > 0.0 && args.objective_tolerance > 0.0) {
        bail!("--tolerance and --objective-tolerance must be positive");
    }
    let mut settings = CrosscheckSettings::default();
    settings.pgs.local = args.pgs_local_solve.unwrap_or_default();
    let mut penetration = None;
    let mut detection = None;
    let (input, rows) = rows_of(&args, &mut settings, (&mut penetration, &mut detection))?;
    let limits = Limits {
        tolerance: args.tolerance,
        objective_tolerance: args.objective_tolerance,
        strict: args.strict,
    };
    let mut summary = summarise(&input, &rows, &limits);
    summary.deepest_penetration = penetration.map(|(depth, _)| depth);
    summary.deepest_penetration_step = penetration.map(|(_, step)| step);
    summary.detection = detection.as_ref().map(report::DetectionSummary::of);
    if summary
        .detection
        .as_ref()
        .is_some_and(|d| d.disagreements > 0)
    {
        summary.verdict = "disagree";
        summary.passed = false;
    }
    if args.json {
        let value = if args.table {
            serde_json::json!({"summary": summary, "problems": rows})
        } else {
            serde_json::json!({"summary": summary})
        };
        println!("{}", serde_json::to_string_pretty(&value)?);
    } else {
        if args.table {
            print_table(&rows);
        }
        print_summary(&summary);
    }
    match summary.verdict {
        "disagree" => bail!(
            "{input}: {} (worst: {})",
            describe_verdict(&summary),
            summary.worst.as_deref().unwrap_or("-")
        ),
        "unverified" => Err(Unverified(format!("{input}: {}", describe_verdict(&summary))).into()),
        _ => Ok(()),
    }
}

/// The input's name and one row per contact problem: a folder of problem files, one problem
/// file, a 2D scene (an image with the default parameters, or a 2D scene file with its own) or a
/// 3D scene, run for --time.
/// For a 3D scene, `penetration` receives the run's deepest measured interpenetration (m) and
/// the step after which it was measured (docs/contact.md §"Penetration measure"), and
/// `detection` the audit of every substep's contacts against the separating-axis oracle
/// (docs/contact.md §"The oracle campaign").
fn rows_of(
    args: &CrosscheckArgs,
    settings: &mut CrosscheckSettings,
    (penetration, detection): (&mut Option<(f64, u64)>, &mut Option<DetectionAudit>),
) -> anyhow::Result<(String, Vec<Row>)> {
    Ok(match &args.input {
        Some(path) if path.is_dir() => (path.display().to_string(), check_folder(path, settings)?),
        Some(path) if is_problem_file(path) => (
            path.display().to_string(),
            vec![check_file(path, settings)?],
        ),
        Some(path) if rigidref::blocks2d::scene::is_2d_scene(path) => {
            // An image with the default parameters, or a 2D scene file with its own.
            let mut world =
                crate::cli::common::load_scene_2d(path, &Default::default(), &args.sets)?.world;
            settings.pgs.local = args.pgs_local_solve.unwrap_or(world.params.local_solve);
            settings.solver = world.params.solver;
            let source = path.display().to_string();
            let rows = check_run(&mut world, args.time, &source, &*settings, |_| {})?;
            (source, rows)
        }
        other => {
            let scene = crate::cli::common::load_scene_or_default(other.as_deref(), &args.sets)?;
            if !scene.params.check_collisions {
                eprintln!(
                    "note: {}: check_collisions is false: no contact problems to check",
                    scene.source
                );
            }
            let mut world = World::new(&scene).map_err(anyhow::Error::msg)?;
            world.audit_detection();
            settings.pgs.local = args.pgs_local_solve.unwrap_or(scene.params.pgs_local_solve);
            settings.solver = scene.params.solver;
            let mut watch = InterpenetrationWatch::default();
            let mut warnings = watch.observe(&world);
            let rows = check_run(&mut world, args.time, &scene.source, &*settings, |w| {
                warnings.extend(watch.observe(w));
            })?;
            for w in &warnings {
                eprintln!("{w}");
            }
            *penetration = Some((watch.deepest, watch.deepest_step));
            *detection = world.detection_audit().cloned();
            (scene.source.clone(), rows)
        }
    })
}

fn is_problem_file(path: &Path) -> bool {
    rigidref::common::input::read_text(path)
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .is_some_and(|v| {
            v.get("format").and_then(|f| f.as_str())
                == Some(rigidref::problem::json::PROBLEM_FORMAT)
        })
}

fn check_file(path: &Path, settings: &CrosscheckSettings) -> anyhow::Result<Row> {
    rigidref::common::input::check_size(path)
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let file = AnyProblemFile::read(path).map_err(|e| anyhow::anyhow!(e))?;
    let name = path.display().to_string();
    let at = |e: String| anyhow::anyhow!("{name}: {e}");
    let check = match file {
        AnyProblemFile::Body(file) => match (file.dof_per_body, file.rows_per_contact) {
            (6, 3) => check_problem(&file.to_problem::<6, 3>().map_err(at)?, settings),
            (3, 2) => check_problem(&file.to_problem::<3, 2>().map_err(at)?, settings),
            (d, r) => bail!("{name}: dof_per_body {d} with rows_per_contact {r} is not a problem rigidref knows (6/3 in 3D, 3/2 in 2D)"),
        },
        AnyProblemFile::Local(file) => match file.rows_per_contact {
            3 => check_problem(&file.to_problem::<3>().map_err(at)?, settings),
            2 => check_problem(&file.to_problem::<2>().map_err(at)?, settings),
            r => bail!("{name}: rows_per_contact {r} is not a problem rigidref knows (3 in 3D, 2 in 2D)"),
        },
    }
    .map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
    Ok(Row {
        source: name,
        check,
    })
}

fn check_folder(dir: &Path, settings: &CrosscheckSettings) -> anyhow::Result<Vec<Row>> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("{}: cannot read folder", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    paths.sort();
    if paths.is_empty() {
        bail!("{}: no .json problem files in the folder", dir.display());
    }
    paths.iter().map(|p| check_file(p, settings)).collect()
}

/// Every contact problem of a run of `sim` for `time`, one row per substep with contacts;
/// `observe` sees the state after each step.
fn check_run<S: Simulation<D, R>, const D: usize, const R: usize>(
    sim: &mut S,
    time: f64,
    source: &str,
    settings: &CrosscheckSettings,
    mut observe: impl FnMut(&S),
) -> anyhow::Result<Vec<Row>> {
    let steps = steps_in(time, sim.dt(), "").map_err(anyhow::Error::msg)?;
    let mut progress = Progress::steps(steps, false);
    let mut rows = Vec::new();
    let ran = drive(sim, steps, |w, k| -> Result<Flow, Stopped> {
        for solve in w.solves() {
            let step = Some((solve.lambda.as_slice(), &solve.report));
            let check = check_step(&solve.problem, settings, step).map_err(anyhow::Error::msg)?;
            rows.push(Row {
                source: format!("step {k} substep {}", solve.substep),
                check,
            });
        }
        observe(w);
        progress.tick(k);
        Ok(Flow::Continue)
    });
    progress.finish();
    Stopped::outcome(ran, |e| format!("{source}: the run stopped: {e}"))?;
    Ok(rows)
}
