//! `rigidref contacts IMAGE.png` (or a 2D scene file): one step's 2D contact solve, every quantity.

use super::contacts::{ContactsArgs, choose_substep, rows, step_to_contacts};
use anyhow::bail;
use nalgebra::SMatrix;
use rigidref::blocks2d::world::{Solve2, World2};
use serde::Serialize;

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
    /// The contact's physical criteria (docs/contact.md §"Physical criteria").
    #[serde(flatten)]
    criteria: rigidref::solve::criteria::ContactCriteria,
}

/// The 2D counterpart: the contacts of one substep of an image or 2D scene file (docs/blocks2d.md
/// §"Contact problem"), with the 2 × 6 Jacobian [J₁ | J₂] (columns vx₁ vy₁ ω₁ vx₂ vy₂ ω₂) and the
/// 2 × 2 Delassus block.
pub fn contacts(path: &std::path::Path, args: &ContactsArgs) -> anyhow::Result<()> {
    let mut world = super::common::load_scene_2d(path, &Default::default(), &args.sets)?.world;
    if world.params.contact_model == rigidref::blocks2d::params::ContactModel::Penalty {
        bail!(
            "{}: the scene uses penalty contacts, which solve no contact problem; contacts shows PGS solves",
            path.display()
        );
    }
    let source = path.display().to_string();
    step_to_contacts(args, &mut world, &source, "time units")?;
    let solve = choose_substep(args, world.step, &world.solves)?;
    let (each, worst) = rigidref::solve::criteria::criteria(&solve.problem, &solve.lambda);
    let contacts: Vec<Contact2Json> = solve
        .contacts
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let pc = &solve.problem.contacts[k];
            let mut j = SMatrix::<f64, 2, 6>::zeros();
            j.fixed_view_mut::<2, 3>(0, 0).copy_from(&pc.jacobian[0]);
            j.fixed_view_mut::<2, 3>(0, 3).copy_from(&pc.jacobian[1]);
            let t = rigidref::blocks2d::collide::tangent(&c.normal);
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
                criteria: each[k],
            }
        })
        .collect();
    let p = &world.params;
    if args.json {
        let out = serde_json::json!({
            "scene": source, "dimension": 2, "step": world.step, "t": world.time(),
            "substep": solve.substep, "h": p.h(), "mu": p.mu,
            "iterations": solve.report.iterations, "residual": solve.report.residual,
            "criteria": worst, "contacts": contacts,
        });
        println!("{}", serde_json::to_string_pretty(&out)?);
        return Ok(());
    }
    print_table(&source, &world, solve, &contacts);
    Ok(())
}

/// The table: a header line, then each contact's quantities.
fn print_table(source: &str, world: &World2, solve: &Solve2, contacts: &[Contact2Json]) {
    let p = &world.params;
    println!(
        "{source}, step {} (t = {}), substep {}, h = {}, μ = {}",
        world.step,
        world.time(),
        solve.substep,
        p.h(),
        p.mu
    );
    println!(
        "{} contacts; {}, residual {:.3e} blocks per time unit",
        contacts.len(),
        super::contacts3d::iterations_phrase(solve.report.method.name(), solve.report.iterations),
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
}

fn fmt2(v: &[f64; 2]) -> String {
    format!("[{:>13.6e}, {:>13.6e}]", v[0], v[1])
}
