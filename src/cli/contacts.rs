//! `rigidref contacts`: print every quantity of one step's contact solve, for inspection and for
//! comparing a student's numbers against (the assignment's objectives 3–7). The arguments and
//! what both systems share; the 3D printout is in contacts3d.rs, the 2D one in contacts2d.rs.

use anyhow::{Context, bail};
use clap::Args;
use nalgebra::SMatrix;
use rigidref::sim::{Flow, NonFinite, Simulation, SubstepSolve, check_step_count, drive, steps_in};
use std::path::PathBuf;

/// Arguments of `rigidref contacts`.
#[derive(Args)]
#[command(after_long_help = "\
For each contact of the chosen step: the bodies (body 1 owns the penetrating vertex, or with `collision: complete`
the manifold point on its surface; body 2 is the body it penetrates, −1 the ground), the point p and frame (n, t1, t2) in world coordinates,
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
    #[command(flatten)]
    pub sets: super::args::SceneSets,
}

pub(crate) fn rows<const A: usize, const B: usize>(m: &SMatrix<f64, A, B>) -> Vec<Vec<f64>> {
    (0..A)
        .map(|i| (0..B).map(|j| m[(i, j)]).collect())
        .collect()
}

/// Steps `sim` to the chosen step, or without --step to the first step with contacts within
/// --time (`unit` names the time unit in messages). Errors name `source`.
pub(crate) fn step_to_contacts<S: Simulation<D, R>, const D: usize, const R: usize>(
    args: &ContactsArgs,
    sim: &mut S,
    source: &str,
    unit: &str,
) -> anyhow::Result<()> {
    // --time is checked whether or not --step makes it unused, so that a bad value is never
    // silently accepted.
    steps_in(args.time, sim.dt(), "").map_err(anyhow::Error::msg)?;
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
        Ok(if wanted(w, k) {
            Flow::Stop
        } else {
            Flow::Continue
        })
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
pub(crate) fn choose_substep<'a, C, const D: usize, const R: usize>(
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
