//! `rigidref scene`: load and check a scene, and print it with every default filled in.

use clap::Args;
use std::path::PathBuf;

/// Arguments of `rigidref scene`.
#[derive(Args)]
pub struct SceneArgs {
    /// Scene file; without one, the built-in default scene.
    pub scene: Option<PathBuf>,
    #[command(flatten)]
    pub sets: super::args::SceneSets,
}

/// Prints the resolved parameters and each body's mass properties and initial state.
pub fn scene(args: SceneArgs) -> anyhow::Result<()> {
    if let Some(path) = args.scene.as_deref()
        && rigidref::blocks2d::scene::is_2d_scene(path)
    {
        return scene2(path, &args.sets);
    }
    let scene = super::common::load_scene_or_default(args.scene.as_deref(), &args.sets)?;
    let p = &scene.params;
    println!("scene            {} ({})", p.name, scene.source);
    println!("preset           {:?}", p.preset);
    println!(
        "dt               {} s ({} substeps, h = {} s)",
        p.dt,
        p.substeps,
        p.h()
    );
    println!(
        "gravity          [{}, {}, {}] m/s²",
        p.gravity.x, p.gravity.y, p.gravity.z
    );
    println!("mu               {}", p.mu);
    println!("check_collisions {}", p.check_collisions);
    println!("stop_on_contact  {}", p.stop_on_contact);
    println!("pgs_iterations   {}", p.pgs_iterations);
    println!("integrator       {}", p.integrator.name());
    println!("friction_model   {}", p.friction_model.name());
    println!("compliance       {} kg⁻¹", p.compliance);
    println!("stabilization    {}", p.stabilization);
    println!("stabilization_slop {} m", p.stabilization_slop);
    println!("stabilization_max_speed {} m/s", p.stabilization_max_speed);
    println!("warm_start       {}", p.warm_start);
    match p.pgs_tolerance {
        Some(t) => println!("pgs_tolerance    {t} m/s"),
        None => println!("pgs_tolerance    none (all pgs_iterations sweeps)"),
    }
    println!("pgs_order        {:?} (seed {})", p.pgs_order, p.pgs_seed);
    println!("pgs_local_solve  {}", p.pgs_local_solve.name());
    println!("solver           {}", p.solver.name());
    println!("collision        {}", p.collision.name());
    println!("tangents         {}", p.tangents.name());
    println!("culling          {}", p.culling.name());
    for (i, b) in scene.bodies.iter().enumerate() {
        let moments = b.inertia.symmetric_eigenvalues();
        println!("body {i}: {} ({})", b.name, b.source);
        println!("  mass           {} kg", b.mass);
        println!(
            "  principal J    {:.6}, {:.6}, {:.6} kg·m²",
            moments[0], moments[1], moments[2]
        );
        println!(
            "  mesh           {} vertices, {} triangles, radius {:.4} m",
            b.mesh.vertices.len(),
            b.mesh.triangles.len(),
            b.mesh.bounding_radius()
        );
        println!("  x0             [{}, {}, {}] m", b.x0.x, b.x0.y, b.x0.z);
        println!("  v0             [{}, {}, {}] m/s", b.v0.x, b.v0.y, b.v0.z);
        println!(
            "  omega0         [{}, {}, {}] rad/s",
            b.omega0.x, b.omega0.y, b.omega0.z
        );
        let r = b.r0;
        println!(
            "  R0             [[{}, {}, {}], [{}, {}, {}], [{}, {}, {}]]",
            r[(0, 0)],
            r[(0, 1)],
            r[(0, 2)],
            r[(1, 0)],
            r[(1, 1)],
            r[(1, 2)],
            r[(2, 0)],
            r[(2, 1)],
            r[(2, 2)]
        );
    }
    Ok(())
}

/// The 2D version: the resolved parameters, each body's blocks, mass and centre, and the pins and
/// springs.
fn scene2(path: &std::path::Path, sets: &super::args::SceneSets) -> anyhow::Result<()> {
    use rigidref::blocks2d::scene::{LoadOptions2, load_2d};
    let cli = LoadOptions2 {
        overrides: sets.overrides()?,
        ..LoadOptions2::default()
    };
    let scene = load_2d(path, &cli).map_err(|e| anyhow::anyhow!("{}", e.0))?;
    let (world, p) = (&scene.world, &scene.world.params);
    println!("image            {}", scene.image.display());
    println!(
        "step             {} ({} substeps, h = {})",
        p.dt,
        p.substeps,
        p.h()
    );
    println!("gravity          {} at {}°", p.gravity, p.gravity_angle);
    println!("mu               {}", p.mu);
    println!("restitution      {}", p.restitution);
    println!("iterations       {}", p.iterations);
    match p.tolerance {
        Some(t) => println!("pgs_tolerance    {t}"),
        None => println!("pgs_tolerance    none (all iterations)"),
    }
    println!("order            {:?} (seed {})", p.order, p.seed);
    println!("pgs_local_solve  {}", p.local_solve.name());
    println!("solver           {}", p.solver.name());
    println!("warm_start       {}", p.warm_start);
    println!(
        "post_stabilization {} (slop {})",
        p.post_stabilization, p.slop
    );
    println!("contact_model    {:?}", p.contact_model);
    println!("preset           {:?}", p.preset);
    println!(
        "image_reader     {} (bodies numbered {})",
        p.image_reader.name(),
        p.image_reader.numbering()
    );
    println!("inertia          {:?}", p.inertia);
    println!("disc_tree        {:?}", p.disc_tree);
    for (i, b) in world.bodies.iter().enumerate() {
        println!(
            "body {i}: {} blocks, mass {:.4}, inertia {:.4}, centre [{}, {}]{}",
            b.blocks.len(),
            b.mass,
            b.inertia,
            b.x.x,
            b.x.y,
            if b.pinned { ", pinned" } else { "" }
        );
    }
    let end = |a: &rigidref::blocks2d::joints::Anchor| match a.body {
        Some(b) => format!("body {b}"),
        None => "world".to_string(),
    };
    for (k, pin) in world.pins.iter().enumerate() {
        let at = pin.ends[0].point(&world.bodies);
        println!(
            "pin {k}: {} to {} at [{}, {}]",
            end(&pin.ends[0]),
            end(&pin.ends[1]),
            at.x,
            at.y
        );
    }
    for (k, s) in world.springs.iter().enumerate() {
        println!(
            "spring {k}: {} to {}, stiffness {}, damping {}, rest length {}",
            end(&s.ends[0]),
            end(&s.ends[1]),
            s.stiffness,
            s.damping,
            s.rest_length
        );
    }
    Ok(())
}
