//! Springs, dampers and pin joints between two bodies, or a body and the world.
//! docs/blocks2d.md §"Springs, dampers and pins".
//!
//! A spring is a force, added with gravity before the velocity kick. A pin is a bilateral
//! constraint: two rows (x, y) of the shared contact problem with free bounds
//! ([`crate::problem::RowBounds::Free`]), solved by the same PGS as the contacts, in the same
//! sweeps; post-stabilisation removes its drift with the contacts' penetration.

use super::body::Body2;
use crate::problem::{ProblemContact, RowBounds};
use nalgebra::{SMatrix, SVector, Vector2};

/// One end of a spring or pin: a point fixed in a body, or in the world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Anchor {
    /// The body; `None` is the world.
    pub body: Option<usize>,
    /// The point in the body's frame, relative to its centre of mass (blocks); for the world,
    /// the world point.
    pub local: Vector2<f64>,
}

impl Anchor {
    /// The anchor at world point `p` of `body` (or the world) in the bodies' current poses.
    pub fn at(bodies: &[Body2], body: Option<usize>, p: &Vector2<f64>) -> Anchor {
        let local = match body {
            Some(i) => bodies[i].rotation().transpose() * (p - bodies[i].x),
            None => *p,
        };
        Anchor { body, local }
    }

    /// The anchor's world point, blocks.
    pub fn point(&self, bodies: &[Body2]) -> Vector2<f64> {
        match self.body {
            Some(i) => bodies[i].to_world(&self.local),
            None => self.local,
        }
    }

    /// The anchor point's world velocity v + ω × r, blocks per time unit.
    pub fn velocity(&self, bodies: &[Body2]) -> Vector2<f64> {
        match self.body {
            Some(i) => {
                let b = &bodies[i];
                let r = b.rotation() * self.local;
                b.v + Vector2::new(-r.y, r.x) * b.omega
            }
            None => Vector2::zeros(),
        }
    }

    /// The lever arm r = p − x of the anchor on its body (zero for the world).
    fn arm(&self, bodies: &[Body2]) -> Vector2<f64> {
        match self.body {
            Some(i) => bodies[i].rotation() * self.local,
            None => Vector2::zeros(),
        }
    }
}

/// A spring and damper between two anchors: with d = p₁ − p₂, the force on end 1 is
///
///   f = −(k (|d| − L) + c ḋ·d̂) d̂          (rest length L > 0),
///   f = −k d − c ḋ                          (L = 0: a linear spring in both directions),
///
/// and −f on end 2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spring2 {
    /// End 1 and end 2.
    pub ends: [Anchor; 2],
    /// Stiffness k ≥ 0, force per block.
    pub stiffness: f64,
    /// Damping c ≥ 0, force per (block per time unit).
    pub damping: f64,
    /// Rest length L ≥ 0, blocks.
    pub rest_length: f64,
}

impl Spring2 {
    /// The force on end 1 (end 2 gets its negative).
    pub fn force(&self, bodies: &[Body2]) -> Vector2<f64> {
        let d = self.ends[0].point(bodies) - self.ends[1].point(bodies);
        let d_dot = self.ends[0].velocity(bodies) - self.ends[1].velocity(bodies);
        if self.rest_length == 0.0 {
            return -d * self.stiffness - d_dot * self.damping;
        }
        let length = d.norm();
        if length == 0.0 {
            // Ends together with a positive rest length: no direction to push along.
            return Vector2::zeros();
        }
        let n = d / length;
        -n * (self.stiffness * (length - self.rest_length) + self.damping * d_dot.dot(&n))
    }

    /// Elastic energy ½ k (|d| − L)² (the linear spring's ½ k |d|²).
    pub fn energy(&self, bodies: &[Body2]) -> f64 {
        let d = self.ends[0].point(bodies) - self.ends[1].point(bodies);
        let stretch = d.norm() - self.rest_length;
        0.5 * self.stiffness * stretch * stretch
    }

    /// Adds the force to both ends' accumulators (nothing on the world, or on a pinned body:
    /// its inverse mass is zero).
    pub fn apply(&self, bodies: &mut [Body2]) {
        let f = self.force(bodies);
        for (end, sign) in self.ends.iter().zip([1.0, -1.0]) {
            if let Some(i) = end.body {
                let p = end.point(bodies);
                bodies[i].add_force_at(&(f * sign), &p);
            }
        }
    }
}

/// A pin (revolute joint): the anchors' world points coincide, C = p₁ − p₂ = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pin2 {
    /// End 1 and end 2; end 1 must be a body.
    pub ends: [Anchor; 2],
}

impl Pin2 {
    /// The pin's error C = p₁ − p₂, blocks.
    pub fn error(&self, bodies: &[Body2]) -> Vector2<f64> {
        self.ends[0].point(bodies) - self.ends[1].point(bodies)
    }

    /// The pin's two rows (x, y) as a constraint of the contact problem, free bounds:
    ///
    ///   Ċ = v₁ + ω₁ × r₁ − v₂ − ω₂ × r₂,   J_s = ±[1 0 −r_s,y; 0 1 r_s,x],
    ///
    /// b = J u − `bias` (u the bodies' velocities in `problem_velocity`), λ₀ the warm start.
    /// docs/blocks2d.md §"Springs, dampers and pins".
    pub fn constraint(
        &self,
        bodies: &[Body2],
        problem_velocity: &[nalgebra::Vector3<f64>],
        bias: &Vector2<f64>,
        lambda0: SVector<f64, 2>,
    ) -> ProblemContact<3, 2> {
        let block = |r: &Vector2<f64>| SMatrix::<f64, 2, 3>::new(1.0, 0.0, -r.y, 0.0, 1.0, r.x);
        let j1 = block(&self.ends[0].arm(bodies));
        // The static world's block is zero (a problem's J₂ for `None`; ContactProblem::validate).
        let j2 = match self.ends[1].body {
            Some(_) => -block(&self.ends[1].arm(bodies)),
            None => SMatrix::zeros(),
        };
        let mut b = -bias;
        for (end, j) in self.ends.iter().zip([&j1, &j2]) {
            if let Some(i) = end.body {
                b += j * problem_velocity[i];
            }
        }
        ProblemContact {
            bodies: [self.ends[0].body, self.ends[1].body],
            jacobian: [j1, j2],
            b,
            mu: 0.0,
            compliance: 0.0,
            lambda0,
            bounds: RowBounds::Free,
        }
    }
}
