//! Benchmark suite (divan): rigidref's step against the rapier3d-f64 mirror's on the scenes of
//! `rigidref bench`, and rigidref's phases alone on frozen states (docs/performance.md).
//!
//!     cargo bench --bench versus_rapier                # everything
//!     cargo bench --bench versus_rapier -- pgs         # only the benchmarks whose name has "pgs"
//!
//! `rigidref bench` is the side-by-side report (interleaved rounds, ratios, the targets);
//! this suite is the statistician's view of the same work: divan's samples, medians and spreads
//! per function, for comparing a change against the last run. Settings as `rigidref bench`: the
//! same scenes, 20 PGS sweeps and 20 rapier solver iterations, sleeping off, one thread, after
//! 100 warm-up steps.

use divan::Bencher;
use rigidref::blocks2d::world::World2;
use rigidref::rigid3d::collide::detect_contacts;
use rigidref::rigid3d::collide::penetration::penetrations;
use rigidref::rigid3d::scene::{Scene, load_scene};
use rigidref::rigid3d::world::World;
use rigidref::solve::{PgsWorkspace, solve_pgs};
use rigidref::tools::experiments::bench::{BenchScene, cube_pyramid, stack_grid};
use rigidref::tools::experiments::factory::{Pieces, packed_pile};
use rigidref::verify::references::rapier::RapierMirror;
use std::path::Path;

fn main() {
    divan::main();
}

const ITERATIONS: u32 = 20;
const WARMUP: usize = 100;

fn scene(file: &str) -> Scene {
    load_scene(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenes")
            .join(file),
    )
    .unwrap()
}

fn rigid3d(case: rigidref::tools::experiments::bench::BenchCase) -> Scene {
    let BenchScene::Rigid3d(scene) = case.scene else {
        unreachable!("a 3D case")
    };
    let mut scene = *scene;
    scene.params.pgs_iterations = ITERATIONS;
    scene
}

fn grid(n: usize) -> Scene {
    rigid3d(stack_grid(&scene("box_stack.json"), n, 1.0))
}

fn pyramid(rows: usize) -> Scene {
    rigid3d(cube_pyramid(&scene("cube_stack.json"), rows))
}

/// rigidref's world after the warm-up steps.
fn settled(scene: &Scene) -> World {
    let mut world = World::new(scene).unwrap();
    for _ in 0..WARMUP {
        world.step().unwrap();
    }
    world
}

/// The rapier mirror after the warm-up steps.
fn settled_mirror(scene: &Scene) -> RapierMirror {
    let mut mirror = RapierMirror::new(scene).unwrap();
    mirror.set_solver_iterations(ITERATIONS as usize);
    for _ in 0..WARMUP {
        mirror.step();
    }
    mirror
}

/// One whole step of an n × n grid of tapered stacks (5 n² bodies), rigidref.
#[divan::bench(args = [2, 4, 8, 16])]
fn step_grid_rigidref(bencher: Bencher, n: usize) {
    let mut world = settled(&grid(n));
    bencher.bench_local(|| world.step().unwrap());
}

/// The same in the rapier3d mirror.
#[divan::bench(args = [2, 4, 8, 16])]
fn step_grid_rapier(bencher: Bencher, n: usize) {
    let mut mirror = settled_mirror(&grid(n));
    bencher.bench_local(|| mirror.step());
}

/// One whole step of a pyramid of equal cubes (`collision: complete`), rigidref.
#[divan::bench(args = [5, 12])]
fn step_pyramid_rigidref(bencher: Bencher, rows: usize) {
    let mut world = settled(&pyramid(rows));
    bencher.bench_local(|| world.step().unwrap());
}

/// The same in the rapier3d mirror.
#[divan::bench(args = [5, 12])]
fn step_pyramid_rapier(bencher: Bencher, rows: usize) {
    let mut mirror = settled_mirror(&pyramid(rows));
    bencher.bench_local(|| mirror.step());
}

/// PGS alone, 20 sweeps, on the last contact problem of the settled 8 × 8 grid (1 280
/// contacts): the solver's cost without the rest of the step.
#[divan::bench]
fn pgs_grid_8(bencher: Bencher) {
    let world = settled(&grid(8));
    let solve = world.solves.last().unwrap();
    let settings = world.pgs_settings();
    let mut workspace = PgsWorkspace::new(1);
    let mut lambda = Vec::new();
    bencher.bench_local(|| solve_pgs(&solve.problem, &settings, &mut workspace, &mut lambda));
}

/// Collision detection alone on the settled 8 × 8 grid.
#[divan::bench]
fn detect_grid_8(bencher: Bencher) {
    let world = settled(&grid(8));
    let mut contacts = Vec::new();
    bencher.bench_local(|| {
        detect_contacts(
            &world.bodies,
            world.colliders(),
            world.params.collision,
            &mut contacts,
        )
    });
}

/// The penetration measure alone on the settled 8 × 8 grid.
#[divan::bench]
fn measure_grid_8(bencher: Bencher) {
    let world = settled(&grid(8));
    let mut found = Vec::new();
    bencher.bench_local(|| penetrations(&world.bodies, world.colliders(), &mut found));
}

/// One step of the 2D factory's pile (random polyominoes, the factory's settings) after 100
/// warm-up steps.
#[divan::bench(args = [1000, 10_000], sample_count = 20)]
fn step_factory_2d(bencher: Bencher, bodies: usize) {
    let mut world: World2 = packed_pile(bodies, Pieces::Random, 1);
    for _ in 0..WARMUP {
        world.step().unwrap();
    }
    bencher.bench_local(|| world.step().unwrap());
}

/// PGS alone, the factory's 10 sweeps, on the last contact problem of the 1 000-body pile.
#[divan::bench]
fn pgs_factory_2d_1000(bencher: Bencher) {
    let mut world: World2 = packed_pile(1000, Pieces::Random, 1);
    for _ in 0..WARMUP {
        world.step().unwrap();
    }
    let solve = world.solves.last().unwrap();
    let settings = world.pgs_settings();
    let mut workspace = PgsWorkspace::new(1);
    let mut lambda = Vec::new();
    bencher.bench_local(|| solve_pgs(&solve.problem, &settings, &mut workspace, &mut lambda));
}
