//! The 3D system: integrators, mass properties, collision, the contact Jacobian and problem, and
//! its scenes.

mod allocations;
mod assignment_scenes;
mod coherence;
mod collision;
mod complete;
mod contact_jacobian;
mod contact_scenes;
mod dzhanibekov;
mod exact_contact;
mod integrators;
mod massprops;
mod persistent;
mod projectile;
mod rattleback;
mod rotation;
mod sphere_tree;
mod starter_collision;
mod warm_start;
