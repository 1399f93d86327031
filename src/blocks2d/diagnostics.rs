//! The 2D system's energies and momenta, as the world reports them and the trace records them
//! (of the non-pinned bodies; docs/blocks2d.md §"Dynamics").

use serde::{Deserialize, Serialize};

/// Energies.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Energy2 {
    /// ½ m v² + ½ I ω².
    pub kinetic: f64,
    /// −m g·x, plus the springs' elastic energy ½ k (|d| − L)².
    pub potential: f64,
    /// Sum.
    pub total: f64,
}

/// Momenta.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Momentum2 {
    /// Σ m v.
    pub linear: [f64; 2],
    /// Σ (x × m v + I ω) about the origin.
    pub angular: f64,
}
