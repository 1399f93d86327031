//! `rigidref contacts`: print every quantity of one step's contact solve, for inspection and for
//! comparing a student's numbers against (the assignment's objectives 3–7).

use anyhow::{Context, bail};
use clap::Args;
use nalgebra::{DMatrix, SMatrix};
use rigidref::rigid3d::world::World;
use rigidref::sim::{
    Flow, NonFinite, Simulation, SubstepSolve, check_step_count, drive, steps_in,
};
use serde::Serialize;
use std::path::PathBuf;

/// Arguments of `rigidref contacts`.
#[derive(Args)]
#[command(after_long_help = "\
For each contact of the chosen step: the bodies (body 1 owns the penetrating vertex; body 2 is
the body it penetrates, −1 the ground), the point p and frame (n, t1, t2) in world coordinates,
the depth, the 3×12 Jacobian [J₁ | J₂] (columns v₁, ω₁, v₂, ω₂), the 3×3 Delassus block
A = J M⁻¹ Jᵀ, b = J u − stabilisation bias, the warm-start λ₀ and the solved impulse λ
(N·s; force = λ / h). Sign convention: n points from body 2 into body 1 and λn ≥ 0 pushes body 1
along +n. Definitions: docs/contact.md.

2D (an image or a 2D scene): per contact the two bodies and blocks, p, the normal n (from body 2's
block toward body 1's) and tangent t = (−n_y, n_x), the depth in blocks, the 2×6 Jacobian
(columns vx₁, vy₁, ω₁, vx₂, vy₂, ω₂), the 2×2 Delassus block, b, λ₀ and λ (mass × blocks per time
unit). Definitions: docs/blocks2d.md, section Contact problem.")]
pub struct ContactsArgs {
    /// Scene file (3D; or 2D: an image, run with the default parameters, or a 2D scene file).
    /// Without one, the built-in default scene.
    pub scene: Option<PathBuf>,
    /// The frame to show (1-based). Default: the first frame that has contacts.
    #[arg(long)]
    pub step: Option<u64>,
    /// Which substep of that frame (0-based). Default: the last one that had contacts.
    #[arg(long)]
    pub substep: Option<u32>,
    /// Give up looking for a first contact after this much simulated time, s (2D: time units).
    #[arg(long, default_value_t = 10.0)]
    pub time: f64,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct ContactsJson {
    scene: String,
    step: u64,
    t: f64,
    substep: u32,
    h: f64,
    mu: f64,
    friction_model: String,
    iterations: u32,
    residual: f64,
    contacts: Vec<ContactJson>,
}

#[derive(Serialize)]
struct ContactJson {
    bodies: [i64; 2],
    p: [f64; 3],
    n: [f64; 3],
    t1: [f64; 3],
    t2: [f64; 3],
    depth: f64,
    jacobian: Vec<Vec<f64>>,
    delassus: Vec<Vec<f64>>,
    b: [f64; 3],
    lambda0: [f64; 3],
    lambda: [f64; 3],
}

fn rows<const A: usize, const B: usize>(m: &SMatrix<f64, A, B>) -> Vec<Vec<f64>> {
    (0..A)
        .map(|i| (0..B).map(|j| m[(i, j)]).collect())
        .collect()
}

/// Steps `sim` to the chosen step, or without --step to the first step with contacts within
/// --time (`unit` names the time unit in messages). Errors name `source`.
fn step_to_contacts<S: Simulation<D, R>, const D: usize, const R: usize>(
    args: &ContactsArgs,
    sim: &mut S,
    source: &str,
    unit: &str,
) -> anyhow::Result<()> {
    if args.step == Some(0) {
        bail!(
            "--step counts frames from 1 (step 0 is the initial state, before any contact solve)"
        );
    }
    let limit = match args.step {
        Some(k) => {
            check_step_count(k as f64, sim.dt()).map_err(|e| anyhow::anyhow!("{source}: {e}"))?;
            k
        }
        None => steps_in(args.time, sim.dt(), "").map_err(|e| anyhow::anyhow!("{source}: {e}"))?,
    };
    let wanted = |w: &S, k: u64| k == limit || (args.step.is_none() && !w.solves().is_empty());
    drive(sim, limit, |w, k| -> Result<Flow, NonFinite> {
        Ok(if wanted(w, k) { Flow::Stop } else { Flow::Continue })
    })
    .map_err(|e| anyhow::anyhow!("{source}: the run stopped: {e}"))?;
    if !sim.solves().is_empty() {
        return Ok(());
    }
    match args.step {
        Some(k) => bail!("{source}: step {k} has no contacts"),
        None => bail!(
            "{source}: no contacts in the first {} {unit} (use --time to look further)",
            args.time
        ),
    }
}

/// The step's solve of the chosen --substep, or the last one with contacts.
fn choose_substep<'a, C, const D: usize, const R: usize>(
    args: &ContactsArgs,
    step: u64,
    solves: &'a [SubstepSolve<C, D, R>],
) -> anyhow::Result<&'a SubstepSolve<C, D, R>> {
    match args.substep {
        None => solves.last().context("no contacts"),
        Some(s) => solves.iter().find(|c| c.substep == s).with_context(|| {
            let had: Vec<String> = solves.iter().map(|c| c.substep.to_string()).collect();
            format!(
                "substep {s} of step {step} has no contacts (substeps with contacts: {})",
                had.join(", ")
            )
        }),
    }
}

/// Runs the scene to the chosen step and prints its contacts.
pub fn contacts(args: ContactsArgs) -> anyhow::Result<()> {
    if let Some(path) = &args.scene
        && rigidref::blocks2d::scene::is_2d_scene(path)
    {
        return contacts2(path, &args);
    }
    let mut scene = super::load_scene_or_default(args.scene.as_deref())?;
    if !scene.params.check_collisions {
        eprintln!(
            "note: {}: check_collisions is false in the scene; contacts are computed here anyway",
            scene.source
        );
        scene.params.check_collisions = true;
    }
    let mut world = World::new(&scene).map_err(anyhow::Error::msg)?;
    step_to_contacts(&args, &mut world, &scene.source, "s")?;
    let solve = choose_substep(&args, world.step, &world.solves)?;
    let out = ContactsJson {
        scene: world.params.name.clone(),
        step: world.step,
        t: world.time(),
        substep: solve.substep,
        h: world.params.h(),
        mu: world.params.mu,
        friction_model: world.params.friction_model.name().into(),
        iterations: solve.report.iterations,
        residual: solve.report.residual,
        contacts: solve
            .contacts
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let pc = &solve.problem.contacts[k];
                let mut j = SMatrix::<f64, 3, 12>::zeros();
                j.fixed_view_mut::<3, 6>(0, 0).copy_from(&pc.jacobian[0]);
                j.fixed_view_mut::<3, 6>(0, 6).copy_from(&pc.jacobian[1]);
                ContactJson {
                    bodies: [c.body1 as i64, c.body2.map_or(-1, |b| b as i64)],
                    p: c.point.into(),
                    n: c.frame.n.into(),
                    t1: c.frame.t1.into(),
                    t2: c.frame.t2.into(),
                    depth: c.depth,
                    jacobian: rows(&j),
                    delassus: rows(&solve.problem.delassus_block(k)),
                    b: pc.b.into(),
                    lambda0: pc.lambda0.into(),
                    lambda: solve.lambda[k].into(),
                }
            })
            .collect(),
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&out)?);
        return Ok(());
    }
    println!(
        "scene {:?}, step {} (t = {} s), substep {}, h = {} s, μ = {}, {} friction",
        out.scene, out.step, out.t, out.substep, out.h, out.mu, out.friction_model
    );
    println!(
        "{} contacts; PGS {} sweeps, residual {:.3e} m/s",
        out.contacts.len(),
        out.iterations,
        out.residual
    );
    let names = |i: i64| {
        if i < 0 {
            "ground".to_string()
        } else {
            format!("{i} ({})", world.bodies[i as usize].name)
        }
    };
    for (k, c) in out.contacts.iter().enumerate() {
        println!();
        println!(
            "contact {k}: body 1 = {}, body 2 = {}",
            names(c.bodies[0]),
            names(c.bodies[1])
        );
        println!("  p      = {}", fmt3(&c.p));
        println!("  n      = {}   depth = {:.6e} m", fmt3(&c.n), c.depth);
        println!("  t1     = {}", fmt3(&c.t1));
        println!("  t2     = {}", fmt3(&c.t2));
        println!(
            "  J      =            v1 (x y z)                      ω1 (x y z)                      v2 (x y z)                      ω2 (x y z)"
        );
        for (row, name) in c.jacobian.iter().zip(["n ", "t1", "t2"]) {
            let cells: Vec<String> = row.iter().map(|x| format!("{x:>10.4}")).collect();
            println!("    {name}   {}", cells.join(" "));
        }
        let a = DMatrix::from_row_iterator(3, 3, c.delassus.iter().flatten().copied());
        println!("  A      = J M⁻¹ Jᵀ (kg⁻¹)");
        for i in 0..3 {
            println!(
                "           [{:>13.6e} {:>13.6e} {:>13.6e}]",
                a[(i, 0)],
                a[(i, 1)],
                a[(i, 2)]
            );
        }
        println!("  b      = {} m/s", fmt3(&c.b));
        println!("  λ0     = {} N·s", fmt3(&c.lambda0));
        println!(
            "  λ      = {} N·s  (force λ/h = {} N)",
            fmt3(&c.lambda),
            fmt3(&c.lambda.map(|l| l / out.h))
        );
    }
    Ok(())
}

fn fmt3(v: &[f64; 3]) -> String {
    format!("[{:>13.6e}, {:>13.6e}, {:>13.6e}]", v[0], v[1], v[2])
}

/// One 2D contact as printed.
#[derive(Serialize)]
struct Contact2Json {
    bodies: [usize; 2],
    blocks: [usize; 2],
    p: [f64; 2],
    n: [f64; 2],
    t: [f64; 2],
    depth: f64,
    jacobian: Vec<Vec<f64>>,
    delassus: Vec<Vec<f64>>,
    b: [f64; 2],
    lambda0: [f64; 2],
    lambda: [f64; 2],
}

/// The 2D counterpart: the contacts of one substep of an image or 2D scene file (docs/blocks2d.md
/// §"Contact problem"), with the 2 × 6 Jacobian [J₁ | J₂] (columns vx₁ vy₁ ω₁ vx₂ vy₂ ω₂) and the
/// 2 × 2 Delassus block.
fn contacts2(path: &std::path::Path, args: &ContactsArgs) -> anyhow::Result<()> {
    let mut world = super::run2d::load_world(path, &Default::default())?;
    if world.params.contact_model == rigidref::blocks2d::world::ContactModel::Penalty {
        bail!(
            "{}: the scene uses penalty contacts, which solve no contact problem; contacts shows PGS solves",
            path.display()
        );
    }
    let source = path.display().to_string();
    step_to_contacts(args, &mut world, &source, "time units")?;
    let solve = choose_substep(args, world.step, &world.solves)?;
    let contacts: Vec<Contact2Json> = solve
        .contacts
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let pc = &solve.problem.contacts[k];
            let mut j = SMatrix::<f64, 2, 6>::zeros();
            j.fixed_view_mut::<2, 3>(0, 0).copy_from(&pc.jacobian[0]);
            j.fixed_view_mut::<2, 3>(0, 3).copy_from(&pc.jacobian[1]);
            let t = rigidref::blocks2d::world::tangent(&c.normal);
            Contact2Json {
                bodies: [c.body1, c.body2],
                blocks: [c.block1, c.block2],
                p: c.point.into(),
                n: c.normal.into(),
                t: t.into(),
                depth: c.depth,
                jacobian: rows(&j),
                delassus: rows(&solve.problem.delassus_block(k)),
                b: pc.b.into(),
                lambda0: pc.lambda0.into(),
                lambda: solve.lambda[k].into(),
            }
        })
        .collect();
    let p = &world.params;
    if args.json {
        let out = serde_json::json!({
            "scene": source, "dimension": 2, "step": world.step, "t": world.time(),
            "substep": solve.substep, "h": p.h(), "mu": p.mu,
            "iterations": solve.report.iterations, "residual": solve.report.residual,
            "contacts": contacts,
        });
        println!("{}", serde_json::to_string_pretty(&out)?);
        return Ok(());
    }
    println!(
        "{source}, step {} (t = {}), substep {}, h = {}, μ = {}",
        world.step,
        world.time(),
        solve.substep,
        p.h(),
        p.mu
    );
    println!(
        "{} contacts; PGS {} sweeps, residual {:.3e} blocks per time unit",
        contacts.len(),
        solve.report.iterations,
        solve.report.residual
    );
    for (k, c) in contacts.iter().enumerate() {
        println!();
        println!(
            "contact {k}: body 1 = {} (block {}), body 2 = {} (block {})",
            c.bodies[0], c.blocks[0], c.bodies[1], c.blocks[1]
        );
        println!("  p      = {}", fmt2(&c.p));
        println!("  n      = {}   depth = {:.6e} blocks", fmt2(&c.n), c.depth);
        println!("  t      = {}", fmt2(&c.t));
        println!("  J      =        vx1        vy1         ω1        vx2        vy2         ω2");
        for (row, name) in c.jacobian.iter().zip(["n", "t"]) {
            let cells: Vec<String> = row.iter().map(|x| format!("{x:>10.4}")).collect();
            println!("    {name}      {}", cells.join(" "));
        }
        println!("  A      = J M⁻¹ Jᵀ");
        for row in &c.delassus {
            println!("           [{:>13.6e} {:>13.6e}]", row[0], row[1]);
        }
        println!("  b      = {}", fmt2(&c.b));
        println!("  λ0     = {}", fmt2(&c.lambda0));
        println!("  λ      = {}", fmt2(&c.lambda));
    }
    Ok(())
}

fn fmt2(v: &[f64; 2]) -> String {
    format!("[{:>13.6e}, {:>13.6e}]", v[0], v[1])
}
