//! `rigidref contacts`: print every quantity of one step's contact solve, for inspection and for
//! comparing a student's numbers against (the assignment's objectives 3–7).

use anyhow::{Context, bail};
use clap::Args;
use nalgebra::{DMatrix, SMatrix};
use rigidref::world::{SubstepContacts, World};
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
along +n. Definitions: docs/contact.md.")]
pub struct ContactsArgs {
    /// Scene file. Without one, the built-in default scene.
    pub scene: Option<PathBuf>,
    /// The frame to show (1-based). Default: the first frame that has contacts.
    #[arg(long)]
    pub step: Option<u64>,
    /// Which substep of that frame (0-based). Default: the last one that had contacts.
    #[arg(long)]
    pub substep: Option<u32>,
    /// Give up looking for a first contact after this much simulated time, s.
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

/// Runs the scene to the chosen step and prints its contacts.
pub fn contacts(args: ContactsArgs) -> anyhow::Result<()> {
    let mut scene = super::load_scene_or_default(args.scene.as_deref())?;
    if !scene.params.check_collisions {
        eprintln!(
            "note: {}: check_collisions is false in the scene; contacts are computed here anyway",
            scene.source
        );
        scene.params.check_collisions = true;
    }
    if !(args.time.is_finite() && args.time > 0.0) {
        bail!(
            "--time must be a positive number of seconds, got {}",
            args.time
        );
    }
    if args.step == Some(0) {
        bail!(
            "--step counts frames from 1 (step 0 is the initial state, before any contact solve)"
        );
    }
    let mut world = World::new(&scene).map_err(|e| anyhow::anyhow!(e))?;
    let limit = match args.step {
        Some(k) => k,
        None => (args.time / scene.params.dt).ceil() as u64,
    };
    loop {
        world
            .step()
            .map_err(|e| anyhow::anyhow!("{}: the run stopped: {e}", scene.source))?;
        if world.step == limit || (args.step.is_none() && !world.frame_contacts.is_empty()) {
            break;
        }
    }
    if world.frame_contacts.is_empty() {
        match args.step {
            Some(k) => bail!("{}: step {k} has no contacts", scene.source),
            None => bail!(
                "{}: no contacts in the first {} s (use --time to look further)",
                scene.source,
                args.time
            ),
        }
    }
    let solve: &SubstepContacts = match args.substep {
        None => world.frame_contacts.last().context("no contacts")?,
        Some(s) => world
            .frame_contacts
            .iter()
            .find(|c| c.substep == s)
            .with_context(|| {
                let had: Vec<String> = world
                    .frame_contacts
                    .iter()
                    .map(|c| c.substep.to_string())
                    .collect();
                format!(
                    "substep {s} of step {} has no contacts (substeps with contacts: {})",
                    world.step,
                    had.join(", ")
                )
            })?,
    };
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
