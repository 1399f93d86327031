//! The coloured contact order: contacts grouped so that no two of a group (a colour) share a
//! moving body, colours visited in turn. docs/contact.md §"Coloured order".
//!
//! A sweep in this order is still Gauss–Seidel over every contact with the projection after
//! each; only the order differs from the problem's. Within a colour the visits are independent
//! (each reads and writes only its own bodies' Δu), so the processor overlaps consecutive
//! visits instead of waiting for each to finish, and threads could take a colour's contacts
//! in any split with the same result.

/// Greedy first-fit colouring, deterministic: contacts in problem order, each given the
/// smallest colour that neither of its moving bodies has yet. `sides(k)` gives contact k's two
/// bodies (`None`: the static world); a body is moving when `moving` says so (a pinned body's
/// Δu never changes, so contacts may share it). Writes the visiting order (colour by colour,
/// problem order within a colour) to `order` and the start of each colour in it to `starts`
/// (with the end appended). `masks` (per body the colours it has, 64 to a word) and
/// `colour_of` are scratch, kept by the caller so that a solve does not allocate.
pub fn colour_contacts(
    count: usize,
    sides: impl Fn(usize) -> [Option<usize>; 2],
    moving: &[bool],
    masks: &mut Vec<u64>,
    colour_of: &mut Vec<usize>,
    order: &mut Vec<usize>,
    starts: &mut Vec<usize>,
) {
    colour_contacts_in(count, |i| i, sides, moving, masks, colour_of, order, starts);
}

/// [`colour_contacts`] with the contacts taken in the sequence `contact_at(0)`, …,
/// `contact_at(count - 1)` (a permutation of the contacts) instead of problem order: each
/// given the smallest colour its moving bodies do not have yet. Each colour's contacts are then
/// laid out in problem order, whatever the sequence: a colour's contacts are independent, so
/// their order changes no bit, and problem order reads the problem and the bodies front to
/// back. With a random permutation this is the random coloured order's colouring
/// (docs/contact.md §"Random coloured order", "Problem order within a colour").
#[allow(clippy::too_many_arguments)]
pub fn colour_contacts_in(
    count: usize,
    contact_at: impl Fn(usize) -> usize,
    sides: impl Fn(usize) -> [Option<usize>; 2],
    moving: &[bool],
    masks: &mut Vec<u64>,
    colour_of: &mut Vec<usize>,
    order: &mut Vec<usize>,
    starts: &mut Vec<usize>,
) {
    let moving_sides = |k: usize| sides(k).map(|b| b.filter(|&b| moving[b]));
    // Words of colour bits per body: grown (and the masks laid out again) when a contact needs
    // a colour beyond them.
    let mut words = 1;
    masks.clear();
    masks.resize(moving.len() * words, 0);
    // Per contact (problem index), its colour.
    colour_of.clear();
    colour_of.resize(count, 0);
    let mut colours = 0;
    for i in 0..count {
        let k = contact_at(i);
        let sides = moving_sides(k);
        let taken = |w: usize, masks: &[u64]| {
            sides
                .iter()
                .flatten()
                .fold(0u64, |acc, &b| acc | masks[b * words + w])
        };
        let mut colour = None;
        for w in 0..words {
            let free = !taken(w, masks);
            if free != 0 {
                colour = Some(w * 64 + free.trailing_zeros() as usize);
                break;
            }
        }
        let colour = colour.unwrap_or_else(|| {
            // Every colour so far is taken: a new word for every body (rare: a body with more
            // than 64 contacts).
            let grown: Vec<u64> = (0..moving.len())
                .flat_map(|b| (0..=words).map(move |w| (b, w)))
                .map(|(b, w)| if w < words { masks[b * words + w] } else { 0 })
                .collect();
            *masks = grown;
            words += 1;
            (words - 1) * 64
        });
        for &b in sides.iter().flatten() {
            masks[b * words + colour / 64] |= 1 << (colour % 64);
        }
        colours = colours.max(colour + 1);
        colour_of[k] = colour;
    }
    // Problem order within a colour.
    sort_by_key(colour_of, colours, order, starts);
}

/// Counting sort of the contacts by `key` (per contact, problem index, each below `keys`),
/// stable: writes the contacts key by key, in problem order within a key, to `order`, and
/// where each key starts in it to `starts` (with the end appended).
pub fn sort_by_key(key: &[usize], keys: usize, order: &mut Vec<usize>, starts: &mut Vec<usize>) {
    starts.clear();
    starts.resize(keys + 1, 0);
    for &c in key.iter() {
        starts[c + 1] += 1;
    }
    for c in 0..keys {
        starts[c + 1] += starts[c];
    }
    // Place each contact at its key's next free slot; `starts[c]` runs ahead as it fills and
    // is then moved back by one key.
    order.clear();
    order.resize(key.len(), 0);
    for (k, &c) in key.iter().enumerate() {
        order[starts[c]] = k;
        starts[c] += 1;
    }
    for c in (1..=keys).rev() {
        starts[c] = starts[c - 1];
    }
    starts[0] = 0;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chain 0–1–2–3 with the ground (None) and a pinned body 4 under everything: the
    /// contacts' bodies, and which bodies move.
    const CHAIN: [[Option<usize>; 2]; 7] = [
        [Some(0), None],
        [Some(0), Some(1)],
        [Some(1), Some(2)],
        [Some(2), Some(3)],
        [Some(0), Some(4)],
        [Some(1), Some(4)],
        [Some(0), Some(1)],
    ];
    const CHAIN_MOVING: [bool; 5] = [true, true, true, true, false];

    #[test]
    fn contacts_of_one_colour_share_no_moving_body_and_every_contact_is_visited_once() {
        let (contacts, moving) = (CHAIN, CHAIN_MOVING);
        let (mut masks, mut scratch, mut order, mut starts) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        colour_contacts(
            contacts.len(),
            |k| contacts[k],
            &moving,
            &mut masks,
            &mut scratch,
            &mut order,
            &mut starts,
        );
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..contacts.len()).collect::<Vec<_>>());
        for c in 0..starts.len() - 1 {
            let members = &order[starts[c]..starts[c + 1]];
            assert!(
                members.windows(2).all(|w| w[0] < w[1]),
                "problem order within"
            );
            let mut used = [false; 5];
            for &k in members {
                for b in contacts[k].iter().flatten().filter(|&&b| moving[b]) {
                    assert!(!used[*b], "colour {c} shares body {b}");
                    used[*b] = true;
                }
            }
        }
        // Body 0 has four contacts, so at least four colours.
        assert!(starts.len() > 4);
    }

    /// The colouring takes the contacts in the given sequence (greedy first fit: which contacts
    /// share a colour is the sequence's) and lays each colour's contacts out in problem order
    /// (docs/contact.md §"Random coloured order", "Problem order within a colour"). The chain
    /// taken in reverse: contact 6 (0–1) takes colour 0 first, so the colours are {6, 3},
    /// {5, 4}, {2, 0}, {1}, each laid out ascending (the sequence's own order would give 6, 3,
    /// 5, 4, 2, 0, 1).
    #[test]
    fn a_colouring_in_a_sequence_lays_each_colour_out_in_problem_order() {
        let n = CHAIN.len();
        let (mut masks, mut scratch, mut order, mut starts) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        colour_contacts_in(
            n,
            |i| n - 1 - i,
            |k| CHAIN[k],
            &CHAIN_MOVING,
            &mut masks,
            &mut scratch,
            &mut order,
            &mut starts,
        );
        assert_eq!(order, [3, 6, 4, 5, 0, 2, 1]);
        assert_eq!(starts, [0, 2, 4, 6, 7]);
    }

    #[test]
    fn more_than_64_colours_grow_the_masks() {
        // 100 contacts all on bodies 0 and 1: one colour each.
        let contacts = vec![[Some(0), Some(1)]; 100];
        let (mut masks, mut scratch, mut order, mut starts) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        colour_contacts(
            contacts.len(),
            |k| contacts[k],
            &[true, true],
            &mut masks,
            &mut scratch,
            &mut order,
            &mut starts,
        );
        assert_eq!(starts.len(), 101);
        assert_eq!(order, (0..100).collect::<Vec<_>>());
    }
}
