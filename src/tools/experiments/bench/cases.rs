//! The benchmark's scenes: grids of stacks and pyramids, cube pyramids, sphere rain, the 2D
//! factory's packed pile and the assignment's scenes.

use super::*;

/// One scene of the benchmark.
#[derive(Clone, Debug)]
pub struct BenchCase {
    /// Family and size, e.g. `stack grid 4×4`.
    pub name: String,
    /// The family, for the fitted exponents.
    pub family: &'static str,
    /// The scene.
    pub scene: BenchScene,
}

/// What a case runs.
#[derive(Clone, Debug)]
pub enum BenchScene {
    /// A 3D scene, in rigidref and in the rapier3d mirror.
    Rigid3d(Box<Scene>),
    /// The 2D factory's pile of this many bodies ([`packed_pile`]), in rigidref alone (rapier3d
    /// has no 2D mirror here).
    FactoryPile {
        /// Bodies dropped (the container is one more).
        bodies: usize,
        /// What they are.
        pieces: Pieces,
    },
}

impl BenchScene {
    /// Bodies in the scene (a factory pile's container counts as one).
    pub fn bodies(&self) -> usize {
        match self {
            BenchScene::Rigid3d(scene) => scene.bodies.len(),
            BenchScene::FactoryPile { bodies, .. } => bodies + 1,
        }
    }
}

/// The 2D factory's step at `bodies` bodies of `pieces` (the factory's default is random
/// polyominoes) with the factory's settings: a pile made at once by [`packed_pile`], settled by
/// at least [`PILE_WARMUP`] steps.
pub fn factory_pile(bodies: usize, pieces: Pieces) -> BenchCase {
    let (name, family) = match pieces {
        Pieces::Random => (format!("2D factory {bodies}"), "2D factory"),
        Pieces::Bricks => (format!("2D factory bricks {bodies}"), "2D factory bricks"),
        Pieces::Tetris => (
            format!("2D factory tetrominoes {bodies}"),
            "2D factory tetrominoes",
        ),
    };
    BenchCase {
        name,
        family,
        scene: BenchScene::FactoryPile { bodies, pieces },
    }
}

/// Warm-up steps of a factory pile at least (5 time units): the pile is in contact and its
/// pieces have fallen into the holes of the packing, but it is not settled (1.3 to 2.7 contacts
/// per body, against about 3 in a factory run's pile). Longer does not help: a pile of 10 000
/// made at once is crushed by its own weight under 10 sweeps from a cold start (discs overlap by
/// their whole diameter after 200–400 steps, 11 contacts per body), where the factory's pile,
/// grown ten bodies a time unit, holds. The factory target is therefore judged on a factory run
/// (docs/performance.md); these rows are the step's cost at the size.
pub const PILE_WARMUP: u64 = 100;

/// `k × k` copies of the `levels`-row pyramid of [`cube_pyramid`], 2 m apart row to row.
pub fn pyramid_grid(cube: &Scene, levels: usize, k: usize) -> BenchCase {
    let one = cube_pyramid(cube, levels);
    let BenchScene::Rigid3d(pyramid) = one.scene else {
        unreachable!("cube_pyramid makes a 3D scene")
    };
    let pyramid = *pyramid;
    let width = pyramid.bodies.iter().map(|b| b.x0.x).fold(0.0, f64::max) + 2.0;
    let mut scene = pyramid.clone();
    scene.bodies.clear();
    for i in 0..k {
        for j in 0..k {
            for b in &pyramid.bodies {
                let mut copy = b.clone();
                copy.x0 += Vector3::new(i as f64 * width, 0.0, j as f64 * 2.0);
                copy.name = format!("{} [{i},{j}]", b.name);
                scene.bodies.push(copy);
            }
        }
    }
    scene.params.name = format!("{k}×{k} grid of {}", pyramid.params.name);
    BenchCase {
        name: format!("pyramid grid {k}×{k}"),
        family: "pyramid grid",
        scene: BenchScene::Rigid3d(Box::new(scene)),
    }
}

/// `n × n` copies of `stack` (a scene of one stack at the origin) on a grid `spacing` m apart:
/// the tapered five-cube stack of scenes/box_stack.json (family "stack grid").
pub fn stack_grid(stack: &Scene, n: usize, spacing: f64) -> BenchCase {
    grid_of(stack, n, spacing, "stack grid")
}

/// `n × n` copies of the four equal cubes of scenes/cube_stack.json (`collision: complete`, as
/// the scene says), 1 m apart (family "cube stack grid").
pub fn cube_stack_grid(cubes: &Scene, n: usize) -> BenchCase {
    grid_of(cubes, n, 1.0, "cube stack grid")
}

pub(super) fn grid_of(stack: &Scene, n: usize, spacing: f64, family: &'static str) -> BenchCase {
    let mut scene = stack.clone();
    scene.bodies.clear();
    let half = (n as f64 - 1.0) / 2.0;
    for i in 0..n {
        for k in 0..n {
            let offset = Vector3::new(
                (i as f64 - half) * spacing,
                0.0,
                (k as f64 - half) * spacing,
            );
            for b in &stack.bodies {
                let mut copy: BodyDescription = b.clone();
                copy.x0 += offset;
                copy.name = format!("{} [{i},{k}]", b.name);
                scene.bodies.push(copy);
            }
        }
    }
    scene.params.name = format!("{n}×{n} grid of {}", stack.params.name);
    BenchCase {
        name: format!("{family} {n}×{n}"),
        family,
        scene: BenchScene::Rigid3d(Box::new(scene)),
    }
}

/// A wall-like pyramid of `levels` rows of equal cubes (`cube`, a scene holding one cube at the
/// origin): row k has `levels − k` cubes 1% of a side apart, each resting across two below,
/// with `collision: complete` (equal boxes need it).
pub fn cube_pyramid(cube: &Scene, levels: usize) -> BenchCase {
    let mut scene = cube.clone();
    let template = cube.bodies[0].clone();
    let side = 2.0
        * template
            .mesh
            .vertices
            .iter()
            .map(|v| v.y)
            .fold(0.0, f64::max);
    scene.bodies.clear();
    for row in 0..levels {
        for i in 0..levels - row {
            let mut b = template.clone();
            b.x0 = Vector3::new(
                (i as f64 + 0.5 * row as f64) * side * 1.01,
                side * (0.5 + row as f64) - 0.001,
                0.0,
            );
            b.name = format!("cube {row}.{i}");
            scene.bodies.push(b);
        }
    }
    scene.params.collision = CollisionMethod::Complete;
    scene.params.name = format!("pyramid of {levels} rows");
    BenchCase {
        name: format!("cube pyramid {levels} rows"),
        family: "cube pyramid",
        scene: BenchScene::Rigid3d(Box::new(scene)),
    }
}

/// Spheres raining: an `n × n × layers` lattice of copies of `ball` (a scene of one ball),
/// `spacing` m apart, the lowest layer 1.5 radii above the ground, falling onto it and each
/// other (the vertex rule).
pub fn sphere_rain(ball: &Scene, n: usize, layers: usize, spacing: f64) -> BenchCase {
    let mut scene = ball.clone();
    let template = ball.bodies[0].clone();
    let radius = template.mesh.bounding_radius();
    scene.bodies.clear();
    let half = (n as f64 - 1.0) / 2.0;
    for layer in 0..layers {
        for i in 0..n {
            for k in 0..n {
                let mut b = template.clone();
                // Alternate layers shifted by a quarter spacing, so that the balls do not
                // land exactly on top of each other.
                let shift = if layer % 2 == 1 { 0.25 * spacing } else { 0.0 };
                b.x0 = Vector3::new(
                    (i as f64 - half) * spacing + shift,
                    1.5 * radius + layer as f64 * spacing,
                    (k as f64 - half) * spacing + shift,
                );
                b.name = format!("ball {layer}.{i}.{k}");
                scene.bodies.push(b);
            }
        }
    }
    scene.params.name = format!("{} balls raining", scene.bodies.len());
    BenchCase {
        name: format!("sphere rain {n}×{n}×{layers}"),
        family: "sphere rain",
        scene: BenchScene::Rigid3d(Box::new(scene)),
    }
}

/// One of the assignment's scenes as it is (its own parameters).
pub fn assignment_scene(name: &str, scene: Scene) -> BenchCase {
    BenchCase {
        name: format!("assignment {name}"),
        family: "assignment",
        scene: BenchScene::Rigid3d(Box::new(scene)),
    }
}
