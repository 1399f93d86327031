//! The 3D system of the first assignment: mesh bodies (OBJ + mass properties) on the ground
//! plane y = 0 and against each other. One step ([`world::World::step`]), per substep of length
//! h = dt / substeps, in the order it runs:
//!
//! 1. forces and velocities: v += h f/m, ω += h J⁻¹(τ − ω × Jω) ([`body`], [`rotation`]);
//! 2. detect: vertices below the ground or inside another mesh, and with `collision: complete`
//!    the contact manifolds of the meshes' convex pieces ([`collide`]);
//! 3. assemble: contact frames ([`frame`]) and Jacobians ([`contact`]) into the shared contact
//!    problem ([`assemble`], [`crate::problem`]), warm-started ([`warm_start`]);
//! 4. solve: the shared PGS ([`crate::solve::pgs`]), then u⁺ = u + M⁻¹Jᵀλ;
//! 5. integrate positions: x += h v, R ← exp(h \[ω\]×) R.
//!
//! Around the step: [`scene`] (the assignment's JSON, read as it is), [`mesh`] and [`massprops`]
//! (OBJ meshes and polyhedral mass properties), [`shape`] (the analytic ellipsoid a body may
//! carry), [`diagnostics`] (energy, momentum, flips) and
//! [`trace`] (the trace format); after each step the penetration measure, which
//! [`penetration_watch`] watches for missed contacts. docs/dynamics.md, docs/contact.md.

pub mod assemble;
pub mod body;
pub mod collide;
pub mod contact;
pub mod diagnostics;
pub mod frame;
pub mod massprops;
pub mod mesh;
pub mod penetration_watch;
pub mod rotation;
pub mod scene;
pub mod shape;
pub mod trace;
pub mod warm_start;
pub mod world;
