//! Helpers shared by the integration tests.
#![allow(dead_code)]

use nalgebra::{Matrix3, Vector3};
use rigidref::rigid3d::body::RigidBody;
use rigidref::rigid3d::mesh::TriMesh;
use std::path::PathBuf;
use std::sync::Arc;

/// The project root (where Cargo.toml is).
pub fn project_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `../shared/assignments/rigid3d`, or None after printing why the caller skips.
pub fn rigid3d_assignment() -> Option<PathBuf> {
    let dir = project_root().join("../shared/assignments/rigid3d");
    if dir.join("scenes").is_dir() {
        Some(dir)
    } else {
        eprintln!(
            "SKIPPED: {} is absent (it exists beside the project on developer and CI machines, not in a user's clone)",
            dir.display()
        );
        None
    }
}

/// A body with the given mass (kg), principal moments (kg·m²) along the axes of `frame`, state.
pub fn body(mass: f64, moments: [f64; 3], frame: Matrix3<f64>) -> RigidBody {
    let inertia = frame * Matrix3::from_diagonal(&Vector3::from(moments)) * frame.transpose();
    let mesh = Arc::new(TriMesh::cuboid(Vector3::repeat(-0.5), Vector3::repeat(0.5)));
    RigidBody::new("random", mass, (inertia + inertia.transpose()) * 0.5, mesh)
}

/// The seed of every property test: fixed, so that `cargo test` checks the same cases on every
/// machine and a failure reproduces; `RIGIDREF_PROPTEST_SEED=n` explores other cases.
pub const PROPTEST_SEED: u64 = 20_261_123;

/// A property-test configuration with `cases` cases and the project's fixed seed
/// ([`PROPTEST_SEED`], or `RIGIDREF_PROPTEST_SEED` where set).
pub fn seeded(cases: u32) -> proptest::test_runner::Config {
    let seed = match std::env::var("RIGIDREF_PROPTEST_SEED") {
        Ok(s) => s
            .parse()
            .unwrap_or_else(|_| panic!("RIGIDREF_PROPTEST_SEED={s:?} is not an unsigned integer")),
        Err(_) => PROPTEST_SEED,
    };
    let config = proptest::test_runner::Config {
        rng_seed: proptest::test_runner::RngSeed::Fixed(seed),
        ..proptest::test_runner::Config::with_cases(cases)
    };
    // Mutation testing (docs/verification.md §"Mutation testing") sets this: a mutant's failing
    // case must not be saved to tests/proptest-regressions and replayed under every later
    // mutant, where it changes the case counts some tests assert and so "catches" mutants that
    // no test catches.
    if std::env::var_os("RIGIDREF_PROPTEST_NO_PERSISTENCE").is_some() {
        return proptest::test_runner::Config {
            failure_persistence: None,
            ..config
        };
    }
    config
}

/// Path of the built `rigidref` binary.
pub fn rigidref_bin() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_rigidref"))
}

/// A command's standard error as text.
pub fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Fails the test, at the caller, when the command did not succeed; the message is its exit
/// status and standard error.
#[track_caller]
pub fn assert_success(out: &std::process::Output) {
    assert!(
        out.status.success(),
        "the command failed ({}):\n{}",
        out.status,
        stderr(out)
    );
}

pub mod problems {
    //! Random contact problems for the solver tests: bodies with random mass, inertia and
    //! orientation; contacts between random bodies or with the ground, at random points with
    //! random normals and right-hand sides.

    use nalgebra::{Matrix3, SVector, Vector3};
    use proptest::prelude::*;
    use rigidref::problem::{ContactProblem3, FrictionModel};
    use rigidref::rigid3d::assemble::{ProblemSettings, assemble_problem};
    use rigidref::rigid3d::collide::Contact;
    use rigidref::rigid3d::frame::ContactFrame;
    use rigidref::rigid3d::rotation::exp_so3;
    use rigidref::rigid3d::warm_start::WarmStart;

    fn vector(scale: f64) -> impl Strategy<Value = Vector3<f64>> {
        (-scale..scale, -scale..scale, -scale..scale).prop_map(|(x, y, z)| Vector3::new(x, y, z))
    }

    fn unit() -> impl Strategy<Value = Vector3<f64>> {
        vector(1.0)
            .prop_filter("not too short", |v| v.norm() > 1e-2)
            .prop_map(|v| v.normalize())
    }

    /// A random body: mass (kg), principal moments (kg·m²), rotation vector, position (m).
    pub type BodySpec = (f64, [f64; 3], Vector3<f64>, Vector3<f64>);
    /// A random contact: body 1 and body 2 choices (reduced modulo the body count; body 2 may
    /// come out as the ground), point (m), normal, b (m/s).
    pub type ContactSpec = (usize, usize, Vector3<f64>, Vector3<f64>, SVector<f64, 3>);

    /// What a random problem is made of.
    #[derive(Clone, Debug)]
    pub struct ProblemSpec {
        pub bodies: Vec<BodySpec>,
        pub contacts: Vec<ContactSpec>,
    }

    /// `bodies` bodies (mass 1–100 kg, principal moments 0.1–10 kg·m², random orientation, centre
    /// within 1 m of the origin) and `contacts` contacts (points within 1 m, random unit normals,
    /// b with entries in [−2, 2] m/s).
    pub fn spec(
        bodies: std::ops::Range<usize>,
        contacts: std::ops::Range<usize>,
    ) -> impl Strategy<Value = ProblemSpec> {
        let body = (
            1.0..100.0f64,
            (0.1..10.0f64, 0.1..10.0f64, 0.1..10.0f64),
            vector(3.0),
            vector(1.0),
        )
            .prop_map(|(m, (a, b, c), w, x)| {
                let mut moments = [a, b, c];
                moments.sort_by(f64::total_cmp);
                moments[2] = moments[2].min(0.99 * (moments[0] + moments[1]));
                (m, moments, w, x)
            });
        let contact = (0usize..8, 0usize..8, vector(1.0), unit(), vector(2.0))
            .prop_map(|(a, b, p, n, rhs)| (a, b, p, n, SVector::<f64, 3>::from(rhs)));
        (
            proptest::collection::vec(body, bodies),
            proptest::collection::vec(contact, contacts),
        )
            .prop_map(|(bodies, contacts)| ProblemSpec { bodies, contacts })
    }

    /// Bodies as real bodies are: principal moments m ρ² k with ρ = 1 m and k ∈ [0.1, 0.4] (a
    /// sphere has 0.4, a cube 1/6), contacts at points within 0.8 m of body 1's centre. The mass
    /// and lever arms match, unlike [`spec`]'s, whose independent masses and moments include
    /// thin rods struck at the far end.
    pub fn physical_spec(
        bodies: std::ops::Range<usize>,
        contacts: std::ops::Range<usize>,
    ) -> impl Strategy<Value = ProblemSpec> {
        let body = (
            1.0..100.0f64,
            (0.1..0.4f64, 0.1..0.4f64, 0.1..0.4f64),
            vector(3.0),
            vector(1.0),
        )
            .prop_map(|(m, (a, b, c), w, x)| {
                let mut moments = [m * a, m * b, m * c];
                moments.sort_by(f64::total_cmp);
                moments[2] = moments[2].min(0.99 * (moments[0] + moments[1]));
                (m, moments, w, x)
            });
        let contact = (
            0usize..8,
            0usize..8,
            vector(0.8 / 3f64.sqrt()),
            unit(),
            vector(2.0),
        )
            .prop_map(|(a, b, p, n, rhs)| (a, b, p, n, SVector::<f64, 3>::from(rhs)));
        (
            proptest::collection::vec(body, bodies),
            proptest::collection::vec(contact, contacts),
        )
            .prop_map(|(bodies, mut contacts)| {
                // Contact points relative to body 1's centre.
                let n = bodies.len();
                for c in &mut contacts {
                    c.2 += bodies[c.0 % n].3;
                }
                ProblemSpec { bodies, contacts }
            })
    }

    /// `copies` disjoint copies of `problem` (body indices shifted), one problem: as many
    /// independent copies as the coloured sweep's threads need contacts.
    pub fn tiled<const D: usize, const R: usize>(
        problem: &rigidref::problem::ContactProblem<D, R>,
        copies: usize,
    ) -> rigidref::problem::ContactProblem<D, R> {
        let n = problem.bodies.len();
        let mut out = problem.clone();
        out.bodies.clear();
        out.contacts.clear();
        for copy in 0..copies {
            out.bodies.extend(problem.bodies.iter().cloned());
            out.contacts.extend(problem.contacts.iter().map(|c| {
                let mut c = c.clone();
                c.bodies = c.bodies.map(|b| b.map(|b| b + copy * n));
                c
            }));
        }
        out
    }

    /// The problem: assembled from the random bodies and contacts by the project's own assembly
    /// (so its Jacobians are real contact Jacobians), then b replaced by the random one.
    pub fn build(
        spec: &ProblemSpec,
        mu: f64,
        compliance: f64,
        friction: FrictionModel,
    ) -> ContactProblem3 {
        let bodies: Vec<_> = spec
            .bodies
            .iter()
            .map(|&(m, moments, w, x)| {
                let r = exp_so3(&w);
                let mut b = super::body(m, moments, Matrix3::identity());
                b.x = x;
                b.rotation = r;
                b.update_world_inertia();
                b
            })
            .collect();
        let n = bodies.len();
        let contacts: Vec<Contact> = spec
            .contacts
            .iter()
            .map(|&(a, b, p, normal, _)| {
                let body1 = a % n;
                let body2 = if b % (n + 1) == n || b % (n + 1) == body1 {
                    None
                } else {
                    Some(b % (n + 1))
                };
                Contact {
                    body1,
                    body2,
                    feature: rigidref::rigid3d::collide::Feature::Vertex(0),
                    point: p,
                    frame: ContactFrame::from_normal(&normal),
                    depth: 0.0,
                }
            })
            .collect();
        let settings = ProblemSettings {
            h: 0.01,
            mu,
            friction,
            compliance,
            stabilization: 0.0,
            slop: 0.0,
            max_push_speed: f64::INFINITY,
        };
        let mut problem = assemble_problem(&bodies, &contacts, &settings, &WarmStart::new(false));
        for (c, s) in problem.contacts.iter_mut().zip(&spec.contacts) {
            c.b = s.4;
        }
        problem
    }
}

/// `../shared/assignments/blocks2d`, or None after printing why the caller skips.
pub fn blocks2d_assignment() -> Option<PathBuf> {
    let dir = project_root().join("../shared/assignments/blocks2d");
    if dir.join("tower100.png").is_file() {
        Some(dir)
    } else {
        eprintln!(
            "SKIPPED: {} is absent (it exists beside the project on developer and CI machines, not in a user's clone)",
            dir.display()
        );
        None
    }
}

/// Whether ffmpeg can be started (for `render --mp4`; `.ci/run` installs it).
pub fn has_ffmpeg() -> bool {
    std::process::Command::new("ffmpeg")
        .arg("-version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Runs the built `rigidref` with `args` in `dir` and returns what it printed and its status.
pub fn rigidref(args: &[&str], dir: &std::path::Path) -> std::process::Output {
    std::process::Command::new(rigidref_bin())
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

pub mod blocks {
    //! 2D bodies for the tests: random blobs of blocks and bodies made of given cells.

    use nalgebra::Vector2;
    use proptest::prelude::*;
    use rigidref::blocks2d::body::Body2;
    use rigidref::blocks2d::image::{Block, BlockGroup, block_mass};

    /// A random blob of up to 30 blocks grown from one cell.
    pub fn blob() -> impl Strategy<Value = Vec<(i64, i64)>> {
        proptest::collection::vec(0usize..4, 0..30).prop_map(|steps| {
            let mut cells = vec![(0i64, 0i64)];
            let mut at = (0, 0);
            for s in steps {
                let d = [(1, 0), (-1, 0), (0, 1), (0, -1)][s];
                at = (at.0 + d.0, at.1 + d.1);
                if !cells.contains(&at) {
                    cells.push(at);
                }
            }
            cells
        })
    }

    /// A body of unit blocks at `cells` (dark red, or blue when `pinned`).
    pub fn body_of(cells: &[(i64, i64)], pinned: bool) -> Body2 {
        let colour = if pinned {
            [0.0, 0.0, 0.64]
        } else {
            [0.2, 0.1, 0.1]
        };
        let blocks = cells
            .iter()
            .map(|&(x, y)| Block {
                pixel: Vector2::new(x as f64, y as f64),
                colour,
                mass: block_mass(colour),
            })
            .collect();
        Body2::from_group(&BlockGroup {
            blocks,
            pinned,
            boundary: None,
        })
    }
}

/// The starter's step, sweeps and order (1 substep, 10 sweeps in the order found) with the
/// project's warm start, post-stabilisation, inertia, disc trees and body numbering: what
/// `Params2::starter` was before issue 47 (since then the starter's own values, no warm start
/// and no post-stabilisation), which the tests that start from it were measured with.
pub fn one_substep_ten_sweeps_in_order() -> rigidref::blocks2d::params::Params2 {
    rigidref::blocks2d::params::Params2 {
        substeps: 1,
        iterations: 10,
        order: rigidref::solve::ContactOrder::Sequential,
        ..rigidref::blocks2d::params::Params2::demonstration()
    }
}

/// Runs `steps` steps of `sim` through the one driver loop ([`rigidref::sim::drive`]), calling
/// `each(sim, k)` after step k; panics, naming the step, if the state stops being finite.
pub fn run<S, const D: usize, const R: usize>(
    sim: &mut S,
    steps: u64,
    mut each: impl FnMut(&mut S, u64),
) where
    S: rigidref::sim::Simulation<D, R>,
{
    run_until(sim, steps, |w, k| {
        each(w, k);
        false
    });
}

/// Runs `sim` through the one driver loop until `stop(sim, k)` is true after step k, at most
/// `limit` steps; returns the steps run. Panics if the state stops being finite.
pub fn run_until<S, const D: usize, const R: usize>(
    sim: &mut S,
    limit: u64,
    mut stop: impl FnMut(&mut S, u64) -> bool,
) -> u64
where
    S: rigidref::sim::Simulation<D, R>,
{
    use rigidref::sim::{Flow, NonFinite, drive};
    drive(sim, limit, |w, k| {
        Ok::<_, NonFinite>(if stop(w, k) {
            Flow::Stop
        } else {
            Flow::Continue
        })
    })
    .unwrap_or_else(|e| panic!("{e}"))
}

thread_local! {
    static ALLOCATIONS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// The system allocator, counting the allocations (and reallocations) each thread makes.
pub struct CountingAllocator;

// SAFETY: every call is passed on to the system allocator unchanged; the count is a
// thread-local cell with a constant initialiser, which does not allocate.
unsafe impl std::alloc::GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
        unsafe { std::alloc::System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: std::alloc::Layout) {
        unsafe { std::alloc::System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: std::alloc::Layout, size: usize) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
        unsafe { std::alloc::System.realloc(ptr, layout, size) }
    }
}

/// Heap allocations this thread has made so far.
pub fn allocations() -> u64 {
    ALLOCATIONS.with(|c| c.get())
}

/// `rigidref run SCENE --time T --out t.jsonl` with `set` added, in a fresh folder: the trace's
/// records, one line each, without the header (which names the overrides). Panics if the run
/// fails.
pub fn trace_records(scene: &std::path::Path, time: &str, set: &[&str]) -> Vec<String> {
    let tmp = tempfile::tempdir().unwrap();
    let mut args = vec![
        "run",
        scene.to_str().unwrap(),
        "--time",
        time,
        "--out",
        "t.jsonl",
    ];
    args.extend(set);
    let out = rigidref(&args, tmp.path());
    assert_success(&out);
    let text = std::fs::read_to_string(tmp.path().join("t.jsonl")).unwrap();
    text.lines().skip(1).map(str::to_string).collect()
}
