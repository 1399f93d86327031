//! A 2D rigid body made of unit blocks. docs/blocks2d.md §"Bodies from pixels", §"Dynamics".

use super::disc_tree::{DiscTree, DiscTreeRule};
use super::image::BlockGroup;
use nalgebra::{Matrix2, Vector2};

/// How a body's rotational inertia about its centre of mass comes from its blocks (scene key
/// `inertia`). docs/blocks2d.md §"Bodies from pixels".
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "snake_case")]
#[value(rename_all = "snake_case")]
pub enum InertiaRule {
    /// Each block a unit square of uniform density: I = Σ mᵢ (|rᵢ|² + 1/6) (the default).
    #[default]
    Blocks,
    /// Each block a point mass at its centre, I = Σ mᵢ |rᵢ|², and a body of one block
    /// m (1 + 1)/12 = m/6: the Java starter's `RigidBody` (its own code, not the student's).
    BlockCentres,
}

/// A block of a body, in the body frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyBlock {
    /// Centre relative to the body's centre of mass, body frame.
    pub local: Vector2<f64>,
    /// Colour, channels in [0, 1].
    pub colour: [f64; 3],
    /// Mass, mass units (a black block is 1).
    pub mass: f64,
}

/// A 2D rigid body. Units: one block is one unit of length, a black block one unit of mass.
#[derive(Clone, Debug)]
pub struct Body2 {
    /// Blocks, body frame.
    pub blocks: Vec<BodyBlock>,
    /// Indices of the blocks on the body's boundary (a neighbour, of 8, is not in the body):
    /// the only ones that can touch another body.
    pub boundary: Vec<usize>,
    /// Bounding-disc tree over the boundary blocks.
    pub tree: DiscTree,
    /// Mass Σ mᵢ, mass units (a black block is 1).
    pub mass: f64,
    /// Rotational inertia about the centre of mass, mass units · blocks²: Σ mᵢ (|rᵢ|² + 1/6)
    /// (each block a unit square), or as [`InertiaRule::BlockCentres`] says.
    pub inertia: f64,
    /// Pinned: infinite mass and inertia (inverse 0); its motion, if any, is prescribed.
    pub pinned: bool,
    /// 1/mass, 0 when pinned.
    pub inv_mass: f64,
    /// 1/inertia, 0 when pinned.
    pub inv_inertia: f64,
    /// Centre of mass, world frame, blocks.
    pub x: Vector2<f64>,
    /// Angle, rad, from +x toward +y.
    pub theta: f64,
    /// Velocity of the centre of mass, blocks per time unit.
    pub v: Vector2<f64>,
    /// Angular velocity, rad per unit time, +x toward +y.
    pub omega: f64,
    /// Force accumulator, mass units · blocks per time unit².
    pub force: Vector2<f64>,
    /// Torque accumulator (about the centre of mass), force · blocks.
    pub torque: f64,
}

/// The 2D cross product a × b = a_x b_y − a_y b_x.
pub fn cross(a: &Vector2<f64>, b: &Vector2<f64>) -> f64 {
    a.x * b.y - a.y * b.x
}

/// The blocks of a group with a neighbour (of 8) not in the group: rigidref's boundary.
fn occupied_boundary(group: &BlockGroup) -> Vec<usize> {
    let occupied: std::collections::HashSet<(i64, i64)> = group
        .blocks
        .iter()
        .map(|b| (b.pixel.x as i64, b.pixel.y as i64))
        .collect();
    group
        .blocks
        .iter()
        .enumerate()
        .filter(|(_, b)| {
            let (j, i) = (b.pixel.x as i64, b.pixel.y as i64);
            (-1..=1).any(|di| (-1..=1).any(|dj| !occupied.contains(&(j + dj, i + di))))
        })
        .map(|(k, _)| k)
        .collect()
}

impl Body2 {
    /// The body of a group of image blocks, at rest where the image puts it, with rigidref's
    /// inertia and disc tree ([`InertiaRule::Blocks`], [`DiscTreeRule::Median`]).
    pub fn from_group(group: &BlockGroup) -> Body2 {
        Body2::from_group_with(group, InertiaRule::Blocks, DiscTreeRule::Median)
    }

    /// The body of a group of image blocks, at rest where the image puts it, its inertia by
    /// `inertia` and its disc tree by `tree`. The boundary blocks are the group's own when its
    /// reader decided them, else those with a neighbour (of 8) not in the body.
    pub fn from_group_with(group: &BlockGroup, inertia: InertiaRule, tree: DiscTreeRule) -> Body2 {
        let mass: f64 = group.blocks.iter().map(|b| b.mass).sum();
        let com = group
            .blocks
            .iter()
            .map(|b| b.pixel * b.mass)
            .sum::<Vector2<f64>>()
            / mass;
        let blocks: Vec<BodyBlock> = group
            .blocks
            .iter()
            .map(|b| BodyBlock {
                local: b.pixel - com,
                colour: b.colour,
                mass: b.mass,
            })
            .collect();
        let inertia: f64 = match inertia {
            InertiaRule::Blocks => blocks
                .iter()
                .map(|b| b.mass * (b.local.norm_squared() + 1.0 / 6.0))
                .sum(),
            // The starter's rule for one block, m (1 + 1)/12, keeps a lone block's inertia from
            // being zero; it is the unit square's, as for the other rule.
            InertiaRule::BlockCentres if blocks.len() == 1 => blocks[0].mass * (1.0 + 1.0) / 12.0,
            InertiaRule::BlockCentres => {
                blocks.iter().map(|b| b.mass * b.local.norm_squared()).sum()
            }
        };
        let boundary = match &group.boundary {
            Some(decided) => decided.clone(),
            None => occupied_boundary(group),
        };
        let centres: Vec<Vector2<f64>> = blocks.iter().map(|b| b.local).collect();
        let tree = match tree {
            DiscTreeRule::Median => DiscTree::build(&centres, &boundary),
            DiscTreeRule::Starter => {
                let pixels: Vec<Vector2<f64>> = group.blocks.iter().map(|b| b.pixel).collect();
                DiscTree::build_starter(&centres, &pixels, &boundary)
            }
        };
        let pinned = group.pinned;
        Body2 {
            blocks,
            boundary,
            tree,
            mass,
            inertia,
            pinned,
            inv_mass: if pinned { 0.0 } else { 1.0 / mass },
            inv_inertia: if pinned { 0.0 } else { 1.0 / inertia },
            x: com,
            theta: 0.0,
            v: Vector2::zeros(),
            omega: 0.0,
            force: Vector2::zeros(),
            torque: 0.0,
        }
    }
    /// The rotation matrix of θ.
    pub fn rotation(&self) -> Matrix2<f64> {
        let (s, c) = self.theta.sin_cos();
        Matrix2::new(c, -s, s, c)
    }

    /// A body-frame point in the world frame.
    pub fn to_world(&self, local: &Vector2<f64>) -> Vector2<f64> {
        self.x + self.rotation() * local
    }

    /// Adds a force applied at a world point: torque (p − x) × f. docs/blocks2d.md §"Dynamics".
    pub fn add_force_at(&mut self, force: &Vector2<f64>, point: &Vector2<f64>) {
        self.force += force;
        self.torque += cross(&(point - self.x), force);
    }

    /// Applies an impulse (mass × length / time) at a world point: Δv = J/m, Δω = (p − x) × J / I.
    /// No effect on a pinned body.
    pub fn apply_impulse_at(&mut self, impulse: &Vector2<f64>, point: &Vector2<f64>) {
        self.v += impulse * self.inv_mass;
        self.omega += cross(&(point - self.x), impulse) * self.inv_inertia;
    }

    /// Velocity half of symplectic Euler: v += h f/m, ω += h τ/I (nothing for a pinned body).
    pub fn step_velocity(&mut self, h: f64) {
        self.v += self.force * (h * self.inv_mass);
        self.omega += self.torque * h * self.inv_inertia;
    }

    /// Position half, with the new velocities plus an extra position-only velocity (the
    /// post-stabilisation correction): x += h (v + δv), θ += h (ω + δω).
    pub fn step_position(&mut self, h: f64, correction: &Vector2<f64>, correction_omega: f64) {
        self.x += (self.v + correction) * h;
        self.theta += (self.omega + correction_omega) * h;
    }

    /// The fastest speed of any point of the body's blocks, |v| + |ω| ρ, with ρ the reach of its
    /// bounding disc from the centre of mass (|c| + r of the disc tree's root; the root bounds
    /// the boundary blocks' discs, which hold the body). Blocks per time unit.
    pub fn fastest_point_speed(&self) -> f64 {
        let reach = self
            .tree
            .root()
            .map_or(0.0, |root| root.centre.norm() + root.radius);
        self.v.norm() + self.omega.abs() * reach
    }

    /// Kinetic energy ½ m v² + ½ I ω² (0 for a pinned body).
    pub fn kinetic_energy(&self) -> f64 {
        if self.pinned {
            0.0
        } else {
            0.5 * self.mass * self.v.norm_squared() + 0.5 * self.inertia * self.omega * self.omega
        }
    }
}
