//! Independent references that checks compare the simulator against. Nothing in the simulator
//! calls these; they share no integration code with it.

pub mod compare;
pub mod euler;
pub mod noslip;
pub mod rapier;
