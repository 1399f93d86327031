//! Temporal coherence in 2D detection: per body pair, the block pairs whose discs were within
//! [`MARGIN`] of touching, kept while the two bodies have moved less than half of it.
//! docs/blocks2d.md §"Temporal coherence".

use super::body::Body2;
use super::collide::{
    Contact2, Placed, descend, detect_contacts, placed_root_box, placed_tree_contacts,
};
use crate::common::broad::{Aabb, KeptPairs};
use crate::common::pair_cache::{CacheStats, PairCache};
use nalgebra::Vector2;

/// How much nearer than touching two block discs may be found as a candidate, blocks. A pair's
/// list holds while the two bodies' motions since it was found add up to at most half of this
/// (the other half a safety factor far above round-off). A quarter block: a body falling at the
/// factory's drop speed (5 blocks per time unit, 0.25 per step) keeps its lists for about half a
/// step; a body at rest keeps them for good.
pub const MARGIN: f64 = 0.25;

/// The poses a pair's list was found at: each body's position and angle; and whether there is
/// a list (a pair that moved more than half the margin in one step, or has just begun to overlap
/// in the broad phase, has its contacts found by the plain descent, which costs less than
/// finding a list it would not keep; its poses are remembered, and a list is found once it moves
/// less).
#[derive(Clone, Copy, Debug)]
pub struct Anchor {
    x: [Vector2<f64>; 2],
    theta: [f64; 2],
    listed: bool,
}

/// How far any block centre of `body` can have moved since it was at (x, θ), blocks: the
/// translation plus the turn times the farthest block centre's reach,
/// |Δx| + |Δθ| · (|c| + r) of the root disc (a rotation by Δθ moves a point at distance ρ from
/// the origin by 2ρ |sin(Δθ/2)| ≤ ρ |Δθ|). NaN when the state is.
fn moved(body: &Pose, x: &Vector2<f64>, theta: f64) -> f64 {
    (body.x - x).norm() + (body.theta - theta).abs() * body.reach
}

/// What [`moved`] reads of a body, gathered once per detection (one pass over the bodies,
/// where each pair's visit would reach into both bodies' trees).
#[derive(Clone, Copy, Debug)]
struct Pose {
    x: Vector2<f64>,
    theta: f64,
    /// The farthest block centre's reach, |c| + r of the root disc (0 without blocks), blocks.
    reach: f64,
    pinned: bool,
}

impl Pose {
    fn of(body: &Body2) -> Pose {
        Pose {
            x: body.x,
            theta: body.theta,
            reach: body.tree.root().map_or(0.0, |r| r.centre.norm() + r.radius),
            pinned: body.pinned,
        }
    }
}

/// 2D detection with kept candidate lists: the same contacts, in the same order, as
/// [`detect_contacts`].
#[derive(Clone, Debug, Default)]
pub struct CachedDetector {
    cache: PairCache<Anchor, (u32, u32)>,
    boxes: Vec<Aabb>,
    stack: Vec<(usize, usize)>,
    check: Vec<Contact2>,
    /// The broad phase's pairs of the root boxes grown by the margin, and each body's pose then.
    kept_pairs: KeptPairs<(Vector2<f64>, f64)>,
    pairs: Vec<(usize, usize)>,
    /// Each body's rotation matrix this call (one sine and cosine per body, not per pair).
    rotations: Vec<nalgebra::Matrix2<f64>>,
    /// Each body's pose and reach this call.
    poses: Vec<Pose>,
}

impl CachedDetector {
    /// All contacts between bodies into `out` (replaced), as [`detect_contacts`] finds them:
    /// the broad phase's pairs ascending, each pair's candidates in tree order, each tested
    /// exactly as the trees test a pair of leaves. With `check`, fresh detection runs too and
    /// any difference is counted in [`CacheStats::mismatches`].
    pub fn detect(&mut self, bodies: &[Body2], check: bool, out: &mut Vec<Contact2>) {
        out.clear();
        self.rotations.clear();
        self.rotations.extend(bodies.iter().map(Body2::rotation));
        self.poses.clear();
        self.poses.extend(bodies.iter().map(Pose::of));
        let poses = &self.poses;
        self.boxes.clear();
        let rotations = &self.rotations;
        self.boxes.extend(
            bodies
                .iter()
                .zip(rotations)
                .map(|(b, r)| placed_root_box(&Placed::with_rotation(b, *r))),
        );
        self.kept_pairs.overlapping(
            &self.boxes,
            |_| MARGIN,
            |k| (bodies[k].x, bodies[k].theta),
            |k, (x, theta)| moved(&poses[k], x, *theta),
            &mut self.pairs,
        );
        self.cache.begin();
        for &(i, j) in &self.pairs {
            let (qi, qj) = (&poses[i], &poses[j]);
            if qi.pinned && qj.pinned {
                continue;
            }
            let (bi, bj) = (&bodies[i], &bodies[j]);
            let (pi, pj) = (
                Placed::with_rotation(bi, self.rotations[i]),
                Placed::with_rotation(bj, self.rotations[j]),
            );
            let stack = &mut self.stack;
            let slow = |a: &Anchor| {
                moved(qi, &a.x[0], a.theta[0]) + moved(qj, &a.x[1], a.theta[1]) <= MARGIN / 2.0
            };
            let mut listed = true;
            let candidates = self.cache.candidates(
                (i, j),
                |a| a.listed && (crate::common::faults::fault!(stale_detection_cache) || slow(a)),
                |last, out| {
                    listed = last.is_some_and(slow);
                    if listed {
                        candidate_blocks(&pi, &pj, stack, out);
                    }
                    Anchor {
                        x: [qi.x, qj.x],
                        theta: [qi.theta, qj.theta],
                        listed,
                    }
                },
            );
            if !listed {
                placed_tree_contacts((i, &pi), (j, &pj), &mut self.stack, out);
                continue;
            }
            for &(a, b) in candidates.iter() {
                if let Some(c) =
                    super::collide::placed_block_contact((i, &pi), a as usize, (j, &pj), b as usize)
                {
                    out.push(c);
                }
            }
        }
        self.cache.end();
        if check {
            detect_contacts(bodies, &mut self.check);
            self.cache.stats.checked += 1;
            if self.check != *out {
                self.cache.stats.mismatches += 1;
            }
        }
    }

    /// How often the lists were kept, and the debug check's counts.
    pub fn stats(&self) -> CacheStats {
        self.cache.stats
    }
}

/// The block pairs of bodies i and j (block of i, block of j) whose discs are nearer than
/// [`MARGIN`] of touching, in the order the trees' descent ([`super::collide::tree_contacts`])
/// reaches them: the same descent with every disc grown by the margin, which prunes a subset of
/// what the plain descent prunes and so keeps its order.
fn candidate_blocks(
    pi: &Placed,
    pj: &Placed,
    stack: &mut Vec<(usize, usize)>,
    out: &mut Vec<(u32, u32)>,
) {
    descend(pi, pj, MARGIN, stack, |a, b| out.push((a as u32, b as u32)));
}
