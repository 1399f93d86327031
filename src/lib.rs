//! rigidref: a verification-focused reference implementation of rigid-body dynamics with
//! frictional contact.
//!
//! One step of the 3D system ([`world::World::step`]), per substep of length h = dt / substeps:
//!
//! 1. forces: zero the accumulators, add gravity ([`body::RigidBody::zero_forces`]);
//! 2. velocities: v += h f/m, ω += h J⁻¹(τ − ω × Jω) ([`body::RigidBody::step_velocity`]);
//! 3. contacts: detect ([`collide`]) → assemble the contact problem ([`assemble`], [`problem`])
//!    → solve ([`solve::pgs`]) → apply u⁺ = u + M⁻¹Jᵀλ;
//! 4. positions: x += h v, R ← exp(h[ω]×) R ([`body::RigidBody::step_position`]);
//! 5. world inertia J = R J₀ Rᵀ follows R ([`body::RigidBody::update_world_inertia`]).
//!
//! Every quantity is defined once, with its symbol and units, in `docs/`: the equations of motion
//! in docs/dynamics.md, contact in docs/contact.md, mass properties in docs/massprops.md, the scene format in
//! docs/scene-format.md, the trace format in docs/trace-format.md.
//!
//! Units are SI, the world's y axis points up, the ground is the plane y = 0, and all arithmetic
//! is f64. Runs are deterministic: the same inputs give a bitwise-identical trace.

#![warn(missing_docs)]

pub mod assemble;
pub mod blocks;
pub mod body;
pub mod collide;
pub mod contact;
pub mod crosscheck;
pub mod diagnostics;
pub mod faults;
pub mod golden;
pub mod massprops;
pub mod mesh;
pub mod problem;
pub mod reference;
pub mod rotation;
pub mod scene;
pub mod solve;
pub mod trace;
pub mod warm_start;
pub mod world;
