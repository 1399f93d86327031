//! Which body and which contact of one problem file is which of another's
//! (docs/grading.md §"Comparing contact problems"). Two simulators may number a scene's bodies
//! differently (the 2D starter scans an image column by column, rigidref row by row), list a
//! state's contacts in another order, and list a contact's two bodies the other way round.
//!
//! Bodies: given (from the traces' matching, as `grade` does), or found from the files: the
//! contacts are paired by their points (when both files give every contact's geometry), each
//! pair votes for its bodies, and each reference body takes the other file's body with the most
//! votes, then the most alike (inverse mass and velocity), then the nearest index.
//!
//! Contacts: each reference contact [a₁, a₂] takes the other file's nearest unmatched contact
//! between the same two bodies, in either order. Listed the other way round, [a₂, a₁], it is
//! the same contact with its normal flipped and its Jacobian blocks swapped: J₁′ = J₂ and
//! J₂′ = J₁ body by body (−n with the other body's lever arm gives the same rows), b, the
//! Delassus block and λ unchanged.

use crate::problem::json::{ContactJson, ProblemFile};
use std::collections::HashMap;

/// How the bodies of two problem files were matched.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyMatching {
    /// `map[i]`: the other file's body of reference body i (`None`: no body left for it).
    pub map: Vec<Option<usize>>,
    /// `given` (the traces' matching), `contacts` (found from the contacts' points), `index`
    /// (in file order, or by likeness where the files give no geometry).
    pub by: &'static str,
}

/// The relative difference of two lists of numbers: |a − b| / max(|a|, |b|), 0 when both are 0
/// or the difference is round-off (below 1e-9).
fn unlike(a: impl Iterator<Item = f64>, b: impl Iterator<Item = f64>) -> f64 {
    let (mut d, mut na, mut nb) = (0.0, 0.0, 0.0);
    for (x, y) in a.zip(b) {
        d += (x - y) * (x - y);
        na += x * x;
        nb += y * y;
    }
    let r = d.sqrt() / f64::max(na, nb).sqrt().max(f64::MIN_POSITIVE);
    if r < 1e-9 { 0.0 } else { r }
}

/// How unlike body `a` of `reference` and body `b` of `other` are: inverse mass and velocity.
fn likeness(reference: &ProblemFile, a: usize, other: &ProblemFile, b: usize) -> f64 {
    let (p, q) = (&reference.bodies[a], &other.bodies[b]);
    let flat = |m: &Vec<Vec<f64>>| m.iter().flatten().copied().collect::<Vec<f64>>();
    let (ma, mb) = (flat(&p.inverse_mass), flat(&q.inverse_mass));
    if ma.len() != mb.len() || p.velocity.len() != q.velocity.len() {
        return f64::INFINITY;
    }
    unlike(ma.into_iter(), mb.into_iter())
        + unlike(p.velocity.iter().copied(), q.velocity.iter().copied())
}

/// The contacts of the two files paired by their points (both must give every contact's
/// geometry): nearest first, each at most once, within 1e-3 of the scene's size (1 + the
/// largest |p|). (reference contact, other contact) pairs.
fn contacts_by_point(reference: &ProblemFile, other: &ProblemFile) -> Vec<(usize, usize)> {
    let point = |c: &ContactJson| c.geometry.as_ref().map(|g| g.p.clone());
    let (Some(pa), Some(pb)) = (
        reference
            .contacts
            .iter()
            .map(point)
            .collect::<Option<Vec<_>>>(),
        other.contacts.iter().map(point).collect::<Option<Vec<_>>>(),
    ) else {
        return Vec::new();
    };
    let size = pa
        .iter()
        .flatten()
        .fold(1.0_f64, |m, x| m.max(1.0 + x.abs()));
    let near = 1e-3 * size;
    // A grid of cells of size `near`: a point's partner is in its cell or a neighbouring one.
    let cell = |p: &[f64]| -> Vec<i64> { p.iter().map(|x| (x / near).floor() as i64).collect() };
    let mut grid: HashMap<Vec<i64>, Vec<usize>> = HashMap::new();
    for (m, p) in pb.iter().enumerate() {
        grid.entry(cell(p)).or_default().push(m);
    }
    let mut candidates: Vec<(f64, usize, usize)> = Vec::new();
    for (k, p) in pa.iter().enumerate() {
        let home = cell(p);
        let dims = home.len();
        for offset in 0..3_usize.pow(dims as u32) {
            let neighbour: Vec<i64> = (0..dims)
                .map(|d| home[d] + (offset / 3_usize.pow(d as u32) % 3) as i64 - 1)
                .collect();
            for &m in grid.get(&neighbour).into_iter().flatten() {
                if pb[m].len() != p.len() {
                    continue;
                }
                let d = p
                    .iter()
                    .zip(&pb[m])
                    .map(|(a, b)| (a - b) * (a - b))
                    .sum::<f64>();
                if d.sqrt() <= near {
                    candidates.push((d, k, m));
                }
            }
        }
    }
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let (mut used_a, mut used_b) = (
        vec![false; reference.contacts.len()],
        vec![false; other.contacts.len()],
    );
    let mut pairs = Vec::new();
    for (_, k, m) in candidates {
        if !used_a[k] && !used_b[m] {
            used_a[k] = true;
            used_b[m] = true;
            pairs.push((k, m));
        }
    }
    pairs
}

/// Which body of `other` each body of `reference` is, found from the files (module
/// documentation).
pub fn match_problem_bodies(reference: &ProblemFile, other: &ProblemFile) -> BodyMatching {
    let (nr, no) = (reference.bodies.len(), other.bodies.len());
    let mut votes: HashMap<(usize, usize), u32> = HashMap::new();
    let pairs = contacts_by_point(reference, other);
    for &(k, m) in &pairs {
        for &a in &reference.contacts[k].bodies {
            for &b in &other.contacts[m].bodies {
                if a >= 0 && b >= 0 && (a as usize) < nr && (b as usize) < no {
                    *votes.entry((a as usize, b as usize)).or_default() += 1;
                }
            }
        }
    }
    let mut map: Vec<Option<usize>> = vec![None; nr];
    let mut taken = vec![false; no];
    // The voted pairs first: most votes, then most alike, then nearest index.
    let mut voted: Vec<(u32, f64, usize, usize)> = votes
        .iter()
        .map(|(&(a, b), &n)| {
            (
                n,
                likeness(reference, a, other, b),
                a.abs_diff(b),
                a * no + b,
            )
        })
        .collect();
    voted.sort_by(|x, y| {
        y.0.cmp(&x.0)
            .then(x.1.total_cmp(&y.1))
            .then(x.2.cmp(&y.2))
            .then(x.3.cmp(&y.3))
    });
    for (_, _, _, key) in voted {
        let (a, b) = (key / no, key % no);
        if map[a].is_none() && !taken[b] {
            map[a] = Some(b);
            taken[b] = true;
        }
    }
    // The rest: the most alike unmatched body, then the nearest index (so that files in the
    // same order stay matched in order).
    for (a, slot) in map.iter_mut().enumerate() {
        if slot.is_some() {
            continue;
        }
        let best = (0..no).filter(|&b| !taken[b]).min_by(|&x, &y| {
            likeness(reference, a, other, x)
                .total_cmp(&likeness(reference, a, other, y))
                .then(a.abs_diff(x).cmp(&a.abs_diff(y)))
        });
        if let Some(b) = best {
            *slot = Some(b);
            taken[b] = true;
        }
    }
    let by = if pairs.is_empty() {
        "index"
    } else {
        "contacts"
    };
    BodyMatching { map, by }
}

/// A contact of the other file as the reference's contact sees it: its index, and whether it
/// lists the two bodies the other way round.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Partner {
    /// The other file's contact.
    pub contact: usize,
    /// Listed as [a₂, a₁]: compared with its normal flipped and its Jacobian blocks swapped.
    pub swapped: bool,
}

/// The contact's [body 1, body 2], in the reference's order when `swapped` (the blocks' order
/// the comparison reads).
pub fn sides(c: &ContactJson, swapped: bool) -> [(i64, usize); 2] {
    if swapped {
        [(c.bodies[1], 1), (c.bodies[0], 0)]
    } else {
        [(c.bodies[0], 0), (c.bodies[1], 1)]
    }
}

/// Which contact of `other` each contact of `reference` is (module documentation), with the
/// bodies matched by `bodies`: among the other's contacts between the same two bodies not yet
/// taken, the nearest by contact point (when both have geometry) or else by normal Jacobian row
/// (`row(file, contact, swapped)`), in reference order.
pub fn match_contacts(
    reference: &ProblemFile,
    other: &ProblemFile,
    bodies: &[Option<usize>],
    row: &dyn Fn(&ProblemFile, usize, bool) -> Vec<f64>,
) -> Vec<Option<Partner>> {
    let mapped = |a: i64| -> Option<i64> {
        if a < 0 {
            Some(-1)
        } else {
            bodies.get(a as usize).copied().flatten().map(|b| b as i64)
        }
    };
    let mut taken = vec![false; other.contacts.len()];
    (0..reference.contacts.len())
        .map(|k| {
            let ca = &reference.contacts[k];
            let (Some(b1), Some(b2)) = (mapped(ca.bodies[0]), mapped(ca.bodies[1])) else {
                return None;
            };
            let ra = row(reference, k, false);
            let distance = |m: usize, swapped: bool| {
                let cb = &other.contacts[m];
                match (&ca.geometry, &cb.geometry) {
                    (Some(ga), Some(gb)) if ga.p.len() == gb.p.len() => {
                        ga.p.iter()
                            .zip(&gb.p)
                            .map(|(a, b)| (a - b).powi(2))
                            .sum::<f64>()
                    }
                    _ => {
                        let rb = row(other, m, swapped);
                        ra.iter()
                            .zip(&rb)
                            .map(|(a, b)| (a - b).powi(2))
                            .sum::<f64>()
                    }
                }
            };
            let best = (0..other.contacts.len())
                .filter(|&m| !taken[m])
                .filter_map(|m| {
                    let cb = &other.contacts[m].bodies;
                    if *cb == [b1, b2] {
                        Some((m, false))
                    } else if *cb == [b2, b1] {
                        Some((m, true))
                    } else {
                        None
                    }
                })
                .min_by(|x, y| distance(x.0, x.1).total_cmp(&distance(y.0, y.1)));
            best.map(|(m, swapped)| {
                taken[m] = true;
                Partner {
                    contact: m,
                    swapped,
                }
            })
        })
        .collect()
}
