//! `rigidref contacts SCENE.json`: one step's 3D contact solve, every quantity.

use super::contacts::{ContactsArgs, choose_substep, rows, step_to_contacts};
use nalgebra::{DMatrix, SMatrix};
use rigidref::rigid3d::world::{Solve3, World};
use rigidref::solve::criteria::{ContactCriteria, criteria};
use serde::Serialize;

#[derive(Serialize)]
struct ContactsJson {
    scene: String,
    step: u64,
    t: f64,
    substep: u32,
    h: f64,
    mu: f64,
    friction_model: String,
    /// The method that produced λ: `pgs`, `newton` or `proximal`.
    solver: &'static str,
    iterations: u32,
    residual: f64,
    /// Cone friction: the exact Coulomb law's residual, m/s.
    #[serde(skip_serializing_if = "Option::is_none")]
    coulomb_residual: Option<f64>,
    /// The largest of each physical criterion over the contacts.
    criteria: ContactCriteria,
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
    /// The contact's physical criteria (docs/contact.md §"Physical criteria").
    #[serde(flatten)]
    criteria: ContactCriteria,
}

/// Runs the scene to the chosen step and prints its contacts.
pub fn contacts(args: &ContactsArgs) -> anyhow::Result<()> {
    let mut scene = super::common::load_scene_or_default(args.scene.as_deref(), &args.sets)?;
    if !scene.params.check_collisions {
        eprintln!(
            "note: {}: check_collisions is false in the scene; contacts are computed here anyway",
            scene.source
        );
        scene.params.check_collisions = true;
    }
    let mut world = World::new(&scene).map_err(anyhow::Error::msg)?;
    step_to_contacts(args, &mut world, &scene.source, "s")?;
    let solve = choose_substep(args, world.step, &world.solves)?;
    let out = contacts_json(&world, solve);
    if args.json {
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        print_table(&out, &world);
    }
    Ok(())
}

/// The solve's contacts with every quantity, as printed.
fn contacts_json(world: &World, solve: &Solve3) -> ContactsJson {
    let (each, worst) = criteria(&solve.problem, &solve.lambda);
    ContactsJson {
        criteria: worst,
        scene: world.params.name.clone(),
        step: world.step,
        t: world.time(),
        substep: solve.substep,
        h: world.params.h(),
        mu: world.params.mu,
        friction_model: world.params.friction_model.name().into(),
        solver: solve.report.method.name(),
        iterations: solve.report.iterations,
        residual: solve.report.residual,
        coulomb_residual: solve.report.coulomb_residual,
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
                    criteria: each[k],
                }
            })
            .collect(),
    }
}

/// The table: a header line, then each contact's quantities.
fn print_table(out: &ContactsJson, world: &World) {
    println!(
        "scene {:?}, step {} (t = {} s), substep {}, h = {} s, μ = {}, {} friction",
        out.scene, out.step, out.t, out.substep, out.h, out.mu, out.friction_model
    );
    println!(
        "{} contacts; {}, residual {:.3e} m/s{}",
        out.contacts.len(),
        iterations_phrase(out.solver, out.iterations),
        out.residual,
        match out.coulomb_residual {
            Some(r) => format!(", exact Coulomb residual {r:.3e} m/s"),
            None => String::new(),
        }
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
}

fn fmt3(v: &[f64; 3]) -> String {
    format!("[{:>13.6e}, {:>13.6e}, {:>13.6e}]", v[0], v[1], v[2])
}

/// "PGS 100 sweeps" or "Newton 3 iterations" (with the fallback named when it answered).
pub(super) fn iterations_phrase(method: &str, iterations: u32) -> String {
    match method {
        "pgs" => format!("PGS {iterations} sweeps"),
        "pgs_shock" => format!(
            "PGS {iterations} sweeps, then shock propagation (λ is PGS's; the motion is the pass's)"
        ),
        "proximal" => format!("Newton {iterations} iterations (its proximal fallback answered)"),
        _ => format!("Newton {iterations} iterations"),
    }
}
