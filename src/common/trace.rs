//! What the traces of both systems share: the header's format name and version
//! (docs/trace-format.md).

/// Value of the header's `format` key.
pub const FORMAT_NAME: &str = "rigidref-trace";
/// Value of the header's `version` key; raised on any incompatible change. Version 2 (issue 13):
/// 3D headers name the `collision` method, 3D records carry `penetration`, and a 3D contact's
/// point may be a manifold point rather than a vertex (`collision: complete`).
pub const FORMAT_VERSION: u32 = 2;

use crate::sim::SubstepSolve;
use serde::{Deserialize, Serialize};

/// What the contact solves of a recorded frame did: a trace record's `solver` key
/// (docs/trace-format.md), absent when the frame solved no contact problem. Both systems.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SolverRecord {
    /// The method that produced the frame's answers: `pgs`, `newton`, or `proximal` when the
    /// Newton solver's proximal fallback produced at least one of them (docs/contact.md §"Newton
    /// solver"). Traces written before the Newton solver have no key: `pgs`.
    #[serde(default)]
    pub solver: crate::problem::SolveMethod,
    /// Contact solves in the frame (one per substep with contacts).
    pub solves: u32,
    /// Iterations, summed over the frame's solves: PGS sweeps, or Newton iterations.
    pub sweeps: u64,
    /// The largest residual a solve of the frame ended with (m/s in 3D, blocks/time in 2D).
    pub residual: f64,
    /// Cone friction: the largest exact Coulomb residual of the frame's solves (same unit;
    /// docs/contact.md §"The exact Coulomb residual"); absent with box friction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coulomb_residual: Option<f64>,
}

impl SolverRecord {
    /// The record of a frame's `solves`; `None` when there were none.
    pub fn of<C, const D: usize, const R: usize>(
        solves: &[SubstepSolve<C, D, R>],
    ) -> Option<SolverRecord> {
        if solves.is_empty() {
            return None;
        }
        let method = solves
            .iter()
            .map(|s| s.report.method)
            .max_by_key(|m| *m as u8)
            .unwrap_or_default();
        let mut r = SolverRecord {
            solver: method,
            solves: solves.len() as u32,
            sweeps: 0,
            residual: 0.0,
            coulomb_residual: None,
        };
        for s in solves {
            r.sweeps += u64::from(s.report.iterations);
            r.residual = r.residual.max(s.report.residual);
            if let Some(c) = s.report.coulomb_residual {
                r.coulomb_residual = Some(r.coulomb_residual.map_or(c, |w| w.max(c)));
            }
        }
        Some(r)
    }
}
