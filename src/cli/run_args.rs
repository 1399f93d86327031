//! The arguments of `rigidref run` (and of `rigidref` with no subcommand).

use super::args::{RestThreshold, RunLength, SceneSets, TraceOutput};
use super::args2d::Blocks2dOptions;
use clap::Args;
use std::path::PathBuf;

const SCENE_KEYS: &str = "\
SCENE FILES (the 3D assignment's JSON, read as it is; docs/scene-format.md):
  sim_parameters[0] keys and their defaults when missing (the starter code's):
    name              scene name                       (file name)
    dt                frame step, s; h = dt/substeps   0.01
    gravity           m/s², y is up                    [0, 0, 0]
    mu                friction coefficient             0
    substeps          integration steps per frame      1
    check_collisions  detect and resolve contacts      true
    stop_on_contact   stop at the first contact        false
    pgs_iterations    PGS iterations per solve         100
    damping           only 0 is accepted (the assignment defines no damping model)
    show_contacts, is_running   user-interface keys; no effect here
  Keys this project adds (docs/scene-format.md, docs/contact.md):
    preset            \"default\" or \"starter\" (the Python starter's own behaviour:
                      warm_start false, stabilization 0, collision and tangents
                      \"starter\"; also `run --preset starter`); the keys given
                      override it                                      default
    integrator        angular velocity update: \"spatial\" (the assignment's explicit
                      spatial-frame scheme; default), \"body\" (the same equations in
                      the body frame), \"implicit_gyroscopic\" (implicit Euler on the
                      ω×Jω term, solved by Newton with step halving: never gains
                      energy (tested to h|ω| = 60), dissipates),
                      \"conservative\" (implicit midpoint on the body-frame Euler
                      equations with a Cayley rotation: a free body keeps E, |L| and
                      L to round-off at any step; torques and contacts as a kick)
    friction_model    \"box\" (each tangent impulse in [−μλn, μλn]; default) or
                      \"cone\" (the tangent pair in the disk of radius μλn)
    compliance        c ≥ 0 added to each normal row's diagonal, kg⁻¹ (constraint
                      force mixing: w_n = … + c λn); 0 = rigid          0
    stabilization     Baumgarte β in [0, 1]: fraction of the penetration beyond the
                      slop pushed out per step                         0.2 (starter: 0)
    stabilization_slop  penetration left alone, m                      0.005
    stabilization_max_speed  the largest push-out velocity, m/s: bodies
                      written overlapping are pushed apart, not launched  1
    warm_start        start PGS from the previous substep's impulses   true (starter: false)
    pgs_tolerance     stop PGS when its residual ≤ this, m/s           (none: all sweeps)
    pgs_order         \"sequential\" (problem order; also \"found\"), \"random\" (seeded
                      shuffle each sweep) or \"coloured\" (contacts grouped so no two
                      of a group share a moving body, four at a time, island by
                      island on one thread; different last bits, same bits on any
                      `threads`; docs/contact.md)  sequential
    threads           threads of the coloured sweeps (same bits for any N)  1
    pgs_seed          seed of the random order                        0
    pgs_local_solve   how a PGS visit updates its contact: \"rows\" (normal row, then
                      the friction rows bounded by the new λn: the assignment's;
                      default) or \"exact\" (the contact's 3×3 problem solved exactly,
                      normal and friction together: cannot cycle on one contact)
    solver            \"pgs\" (projected Gauss-Seidel, the assignment's; default) or
                      \"newton\" (the exact solver: semismooth Newton, every contact
                      problem solved to 1e-10 m/s or reported unresolved; use it
                      where PGS warns of unresolved solves, e.g. a heavy body on a
                      light one; docs/contact.md §\"Newton solver\")
    collision         \"vertices\" (the assignment's rule: vertices of one mesh
                      inside the other; default) or \"complete\" (also edge-edge
                      crossings and face contacts, from the contact manifolds of
                      the meshes' convex pieces: equal boxes stack) or \"starter\"
                      (the Python starter's collision.py: per pair only the vertices
                      of the mesh with more vertices, contacts at the closest surface
                      point, body by body; the starter preset's); every way the run
                      measures interpenetration and warns when contacts were missed
    tangents          \"orthonormal\" (unit tangents; default) or \"starter\" (the
                      Python starter's contact.py: its axis test, not normalised;
                      the starter preset's)
    culling           \"bvh\" (a vertex is tested against the other mesh when inside
                      its bounding box; default) or \"sphere_tree\" (and inside one of
                      the leaf spheres covering its solid): the same contacts either way
  Any other key is reported as a warning and ignored.
  bodies[i]: name, file_root (ROOT.json + ROOT.obj, looked up relative to the
    assignment root = parent of the scene's folder, then the scene's folder, then the
    working directory), x0 (m), R0 (rows; default identity), v0 (m/s), omega0 (rad/s,
    world frame); missing R0 is the identity, missing v0/omega0 are zero. This project adds
    ellipsoid ({\"semi_axes\": [a, b, c], \"centre\": [x, y, z]}, body frame, m: an analytic
    contact shape in place of the mesh, e.g. scenes/rattleback.json) and off_centre_mesh (true:
    the mesh is not centred on the centre of mass on purpose; its warning becomes a note), force
    (N, world frame, constant, at the centre of mass) and force_rate (N/s: F(t) = force_rate t).

TRACE (docs/trace-format.md): JSON Lines, a header line then one line per recorded step
with every body's x, R, v, ω, the energies and momenta; or a flat CSV of the same.";

/// Arguments of `rigidref run`.
#[derive(Args)]
#[command(after_long_help = SCENE_KEYS)]
pub struct RunArgs {
    /// Scene file: the 3D assignment's JSON, a 2D image (.png), or a 2D scene file (JSON naming
    /// an image; docs/blocks2d.md). Without one, the built-in default 3D scene (the project's
    /// Dzhanibekov-effect scene) runs. The options under the 2D heading apply to images (a 2D
    /// scene file sets its own: use --set); --no-collisions and CSV traces apply to 3D scenes;
    /// --set applies to both.
    pub scene: Option<PathBuf>,
    #[command(flatten)]
    pub length: RunLength,
    #[command(flatten)]
    pub sets: SceneSets,
    #[command(flatten)]
    pub output: TraceOutput,
    /// Print no progress bar and no summary.
    #[arg(long, short)]
    pub quiet: bool,
    /// 3D: run with check_collisions = false, whatever the scene says.
    #[arg(long)]
    pub no_collisions: bool,
    #[command(flatten)]
    pub blocks: Blocks2dOptions,
    #[command(flatten)]
    pub rest: RestThreshold,
    #[command(flatten)]
    pub reports: Run2dReports,
}

/// Reports a 2D run can write beside its trace.
#[derive(Args)]
#[command(next_help_heading = "2D scenes (an image, run with these; a 2D scene file sets its own)")]
pub struct Run2dReports {
    /// 2D: write, per recorded step (see --every), where the heaviest fifth of the moving bodies
    /// is relative to the rest (the nut-bag challenge) to this CSV, with a plot beside it; the
    /// summary says when they reached 0.8 in the upper half, whether that held for 50 cycles of
    /// the shake, and whether every nut stayed in the bag (a warning when one left).
    #[arg(long)]
    pub nut_report: Option<PathBuf>,
    /// 2D: write step, bodies, contacts, PGS solve seconds per step to this CSV (contacts and
    /// seconds summed over the step's substeps).
    #[arg(long)]
    pub scaling_csv: Option<PathBuf>,
    /// 2D: record every contact (point, normal, depth, impulse) in each trace record; without it
    /// a record gives the contacts' count and deepest overlap, which keeps a 30-time-unit run of
    /// the largest demonstration image at 12 MB instead of 127 MB (docs/trace-format.md).
    #[arg(long)]
    pub all_contacts: bool,
}

impl RunArgs {
    /// Every option given that applies to 2D scenes only.
    pub fn only_2d_given(&self) -> Vec<String> {
        let mut names = self.blocks.given();
        for (name, given) in [
            ("--rest-threshold", self.rest.rest_threshold.is_some()),
            ("--nut-report", self.reports.nut_report.is_some()),
            ("--scaling-csv", self.reports.scaling_csv.is_some()),
            ("--all-contacts", self.reports.all_contacts),
        ] {
            if given {
                names.push(name.to_string());
            }
        }
        names
    }
}
