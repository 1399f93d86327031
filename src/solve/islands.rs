//! Islands: the sets of contacts that share moving bodies, directly or through other contacts,
//! and batches of whole islands that a coloured solve sweeps one after another, every sweep of
//! a batch before the next batch. docs/contact.md §"Island by island".
//!
//! A contact's visit reads and writes only its own λ and its moving bodies' Δu (a pinned body's
//! Δu stays +0: adding M⁻¹Jᵀδ = 0 to it leaves it +0). Two islands share neither, so the
//! visits of one island never see the other's. The updates an island's contacts get, and their
//! order, are then the same whether the sweeps go over all the contacts, colour by colour, or
//! over one batch of islands at a time: the same bits, for a fixed number of sweeps. What
//! changes is only what the processor keeps in its caches: one batch's groups instead of the
//! whole problem's.

/// Gives each contact its batch in `batch_of` (problem index) and returns the number of
/// batches (at least 1). `sides(k)` gives contact k's two bodies (`None`: the static world); a
/// body is moving when `moving` says so. Islands are joined by contacts between two moving
/// bodies (union–find, the smaller root kept, so the result does not depend on anything but the
/// problem). The islands are taken in the order of their first contact in the problem, each
/// added to the current batch while the batch holds at most `budget` contacts with it, else
/// starting a new batch; an island larger than `budget` is a batch of its own. A contact with
/// no moving body is in batch 0. `parent`, `size` and `island_batch` (one per body) are scratch,
/// kept by the caller so that a solve does not allocate.
#[allow(clippy::too_many_arguments)]
pub fn batch_islands(
    count: usize,
    sides: impl Fn(usize) -> [Option<usize>; 2],
    moving: &[bool],
    budget: usize,
    parent: &mut Vec<usize>,
    size: &mut Vec<usize>,
    island_batch: &mut Vec<usize>,
    batch_of: &mut Vec<usize>,
) -> usize {
    let bodies = moving.len();
    parent.clear();
    parent.extend(0..bodies);
    // The root of body b's island, halving the path on the way.
    fn root(parent: &mut [usize], mut b: usize) -> usize {
        while parent[b] != b {
            parent[b] = parent[parent[b]];
            b = parent[b];
        }
        b
    }
    let moving_sides = |k: usize| sides(k).map(|b| b.filter(|&b| moving[b]));
    for k in 0..count {
        if let [Some(a), Some(b)] = moving_sides(k) {
            let (a, b) = (root(parent, a), root(parent, b));
            let (low, high) = (a.min(b), a.max(b));
            parent[high] = low;
        }
    }
    // Per contact its island's root (usize::MAX: no moving body), and per root its contacts.
    size.clear();
    size.resize(bodies, 0);
    batch_of.clear();
    for k in 0..count {
        let [a, b] = moving_sides(k);
        let island = a.or(b).map_or(usize::MAX, |body| root(parent, body));
        if island != usize::MAX {
            size[island] += 1;
        }
        batch_of.push(island);
    }
    island_batch.clear();
    island_batch.resize(bodies, usize::MAX);
    let (mut batches, mut filled) = (1, 0);
    for island in batch_of.iter_mut() {
        if *island == usize::MAX {
            *island = 0;
            continue;
        }
        if island_batch[*island] == usize::MAX {
            let n = size[*island];
            if filled > 0 && filled + n > budget {
                batches += 1;
                filled = 0;
            }
            island_batch[*island] = batches - 1;
            filled += n;
        }
        *island = island_batch[*island];
    }
    batches
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Islands {0, 1} (joined by contact 1) and {2, 3} (contact 3), body 4 pinned and shared
    /// by both, body 5 alone; contact 6 has no moving body.
    const SIDES: [[Option<usize>; 2]; 7] = [
        [Some(0), None],
        [Some(1), Some(0)],
        [Some(2), Some(4)],
        [Some(3), Some(2)],
        [Some(0), Some(4)],
        [Some(5), None],
        [Some(4), None],
    ];
    const MOVING: [bool; 6] = [true, true, true, true, false, true];

    fn batches(budget: usize) -> (usize, Vec<usize>) {
        let (mut p, mut s, mut i, mut b) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let n = batch_islands(
            SIDES.len(),
            |k| SIDES[k],
            &MOVING,
            budget,
            &mut p,
            &mut s,
            &mut i,
            &mut b,
        );
        (n, b)
    }

    #[test]
    fn islands_joined_only_through_a_pinned_body_are_batched_apart_under_a_small_budget() {
        // Island {0, 1}: contacts 0, 1, 4 (3); {2, 3}: 2, 3 (2); {5}: 5 (1); contact 6: batch 0.
        assert_eq!(batches(1), (3, vec![0, 0, 1, 1, 0, 2, 0]));
        assert_eq!(batches(5), (2, vec![0, 0, 0, 0, 0, 1, 0]));
        assert_eq!(batches(6), (1, vec![0; 7]));
        assert_eq!(batches(usize::MAX), (1, vec![0; 7]));
    }
}
