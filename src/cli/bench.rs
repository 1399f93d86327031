//! `rigidref bench`: rigidref against the rapier3d mirror on the same scenes, side by side.

use anyhow::Context;
use clap::Args;
use rigidref::rigid3d::scene::load_scene;
use rigidref::tools::experiments::bench::{
    BenchSettings, assignment_scene, cube_pyramid, cube_stack_grid, factory_pile, markdown,
    peak_memory_bytes, pyramid_grid, run_case, solver_markdown, solver_row, sphere_rain,
    stack_grid, svg,
};
use rigidref::tools::experiments::factory::Pieces;
use std::path::PathBuf;

/// Arguments of `rigidref bench`.
#[derive(Args)]
#[command(after_long_help = "\
Scenes, each at several sizes: grids of the tapered five-cube stack of scenes/box_stack.json
(the vertex rule, 5 to 10 125 bodies); grids of the stack of four equal 0.5 m cubes of
scenes/cube_stack.json (collision: complete, 4 to 10 000 bodies); pyramids of those cubes,
alone and in grids (to 10 140 bodies); balls raining onto the ground (scenes/sphere_drop.json's
ball); the assignment's seven scenes (when ../shared is beside the project); and the 2D
factory's pile of random polyominoes at 1 000, 10 000 and 30 000 bodies and of bricks at 10 000
(rigidref only: there is no 2D rapier mirror).

Each 3D scene runs, after warm-up steps, in rounds of N steps in rigidref then N steps in the
rapier3d-f64 mirror of the same scene (same bodies, dt, gravity, μ; rapier's solver iterations =
the PGS sweeps; sleeping off; one thread), interleaved so that both see the machine's slow and
fast spells; the medians are reported. rigidref's step is split into detection, assembly, PGS,
applying, integration and the penetration measure (2D: post-stabilisation), rapier's by its own
timers (collision detection, the solver's serial set-up, velocity iterations: rapier 0.36 generates
its contact constraints inside the iterations' timer), and PGS's cost per contact
per sweep is given. Fitted exponents say how the cost grows with the bodies, and the speed
targets of docs/performance.md are read off the table. Timings are this machine's: compare
ratios from one run.

  rigidref bench --quick                 # the smallest sizes, seconds
  rigidref bench --out bench/            # the full table, about 5 minutes (20 sweeps);
                                         # bench/bench.md and bench/bench.svg (ms per step
                                         # against bodies, log-log)
  rigidref bench --only \"2D factory\"     # only the scenes whose name contains the text")]
pub struct BenchArgs {
    /// Only the smallest sizes and short rounds (a check that it runs, not a measurement).
    #[arg(long)]
    pub quick: bool,
    /// Write the table to DIR/bench.md and the plot to DIR/bench.svg as well.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// PGS sweeps in 3D (and rapier's solver iterations); the 2D factory keeps its own 20.
    #[arg(long, default_value_t = 20)]
    pub iterations: u32,
    /// Only the scenes whose name contains one of these texts, comma-separated (e.g. "grid 8",
    /// "stack grid 8×8,cube pyramid 12"); an error when none does.
    #[arg(long, value_name = "TEXT")]
    pub only: Option<String>,
    /// rigidref's PGS contact order in the 3D scenes: sequential (the order found, the
    /// scenes' own), random, or coloured (docs/contact.md §"Coloured order").
    #[arg(long, value_enum, default_value_t = rigidref::solve::ContactOrder::Sequential)]
    pub contact_order: rigidref::solve::ContactOrder,
    /// Threads of rigidref's coloured sweeps in the 3D scenes (with --contact-order coloured;
    /// rapier runs on one thread either way).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    pub threads: u32,
    /// Persistent manifolds in the `collision: complete` scenes (the cube grids and pyramids):
    /// each piece pair's separating-axis features kept between substeps (docs/contact.md
    /// §"Persistent manifolds").
    #[arg(long)]
    pub persistent_manifolds: bool,
    /// The project root (holding scenes/).
    #[arg(long, default_value = ".")]
    pub root: PathBuf,
}

/// Runs the benchmark and prints the table.
pub fn bench(args: BenchArgs) -> anyhow::Result<()> {
    if args.iterations == 0 {
        anyhow::bail!("--iterations must be at least 1");
    }
    let scenes = args.root.join("scenes");
    let stack = load_scene(&scenes.join("box_stack.json"))
        .map_err(|e| anyhow::anyhow!("{} (give --root the project folder)", e.0))?;
    let cubes = load_scene(&scenes.join("cube_stack.json"))
        .map_err(|e| anyhow::anyhow!("{} (give --root the project folder)", e.0))?;
    let ball = load_scene(&scenes.join("sphere_drop.json"))
        .map_err(|e| anyhow::anyhow!("{} (give --root the project folder)", e.0))?;
    type Sizes = &'static [usize];
    let (grids, cube_grids, pyramids, pyramid_grids, rains, piles, settings): (
        Sizes,
        Sizes,
        Sizes,
        Sizes,
        Sizes,
        Sizes,
        _,
    ) = if args.quick {
        (
            &[1, 2],
            &[],
            &[2, 3],
            &[],
            &[],
            &[100],
            BenchSettings {
                warmup: 10,
                steps: 10,
                rounds: 3,
                iterations: args.iterations,
                contact_order: args.contact_order,
                threads: args.threads,
                persistent_manifolds: args.persistent_manifolds,
            },
        )
    } else {
        (
            &[1, 2, 4, 8, 12, 20, 32, 45],
            &[1, 4, 8, 16, 32, 50],
            &[3, 5, 8, 12],
            &[2, 4, 8, 16, 26],
            &[2, 4, 8],
            &[1000, 10_000, 30_000],
            BenchSettings {
                warmup: 100,
                steps: 30,
                rounds: 5,
                iterations: args.iterations,
                contact_order: args.contact_order,
                threads: args.threads,
                persistent_manifolds: args.persistent_manifolds,
            },
        )
    };
    let mut cases: Vec<_> = grids.iter().map(|&n| stack_grid(&stack, n, 1.0)).collect();
    cases.extend(cube_grids.iter().map(|&n| cube_stack_grid(&cubes, n)));
    cases.extend(pyramids.iter().map(|&n| cube_pyramid(&cubes, n)));
    cases.extend(pyramid_grids.iter().map(|&k| pyramid_grid(&cubes, 5, k)));
    cases.extend(rains.iter().map(|&n| sphere_rain(&ball, n, 2, 1.2)));
    cases.extend(piles.iter().map(|&n| factory_pile(n, Pieces::Random)));
    if !args.quick {
        // The issue's own measurement was of bricks (more contacts per body).
        cases.push(factory_pile(10_000, Pieces::Bricks));
    }
    // The assignment's scenes, where ../shared is there (full runs only).
    let shared = args.root.join("../shared/assignments/rigid3d/scenes");
    if !args.quick {
        for k in 1..=7 {
            let path = shared.join(format!("scene{k}.json"));
            match load_scene(&path) {
                Ok(scene) => cases.push(assignment_scene(&format!("scene{k}"), scene)),
                Err(_) if k == 1 => {
                    eprintln!(
                        "note: {} not found: the assignment's scenes are left out",
                        path.display()
                    );
                    break;
                }
                Err(e) => anyhow::bail!("{}", e.0),
            }
        }
    }
    if let Some(only) = &args.only {
        let names: Vec<String> = cases.iter().map(|c| c.name.clone()).collect();
        let texts: Vec<&str> = only
            .split(',')
            .map(str::trim)
            .filter(|t| !t.is_empty())
            .collect();
        cases.retain(|c| texts.iter().any(|t| c.name.contains(t)));
        if cases.is_empty() {
            anyhow::bail!(
                "--only {only:?}: no scene's name contains it (the scenes: {})",
                names.join(", ")
            );
        }
    }
    let mut rows = Vec::new();
    for (k, case) in cases.iter().enumerate() {
        eprintln!(
            "[{}/{}] {} ({} bodies)",
            k + 1,
            cases.len(),
            case.name,
            case.scene.bodies()
        );
        rows.push(run_case(case, &settings).map_err(|e| anyhow::anyhow!("{}: {e}", case.name))?);
    }
    let mut table = markdown(&rows, &settings);
    // The exact solver against PGS on the assignment's contact scenes 5–7 (issue 30's target:
    // within 20× PGS's step).
    let mut solver_rows = Vec::new();
    for case in cases.iter().filter(|c| {
        ["scene5", "scene6", "scene7"]
            .iter()
            .any(|n| c.name.ends_with(n))
    }) {
        if let rigidref::tools::experiments::bench::BenchScene::Rigid3d(scene) = &case.scene {
            eprintln!("[solvers] {}", case.name);
            solver_rows.push(
                solver_row(&case.name, scene, &settings.for_bodies(scene.bodies.len()))
                    .map_err(|e| anyhow::anyhow!("{}: {e}", case.name))?,
            );
        }
    }
    if !solver_rows.is_empty() {
        table.push_str(&solver_markdown(&solver_rows));
    }
    if args.quick {
        table.insert_str(
            0,
            "Quick run: the smallest sizes and short rounds, a check that the benchmark runs; its \
             ratios and targets are not measurements (run without --quick for those).\n\n",
        );
    }
    if let Some(bytes) = peak_memory_bytes() {
        table.push_str(&format!(
            "\nPeak resident memory of the process: {:.1} MB.\n",
            bytes as f64 / 1e6
        ));
    }
    println!("{table}");
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("{}: cannot create", dir.display()))?;
        let path = dir.join("bench.md");
        std::fs::write(&path, &table)
            .with_context(|| format!("{}: cannot write", path.display()))?;
        eprintln!("table          {}", path.display());
        let plot = dir.join("bench.svg");
        svg(
            &rows,
            &plot,
            &format!(
                "ms per step against bodies, {} sweeps: rigidref (solid) and rapier3d (dashed)",
                settings.iterations
            ),
        )
        .map_err(|e| anyhow::anyhow!(e))?;
        eprintln!("plot           {}", plot.display());
    }
    Ok(())
}
