//! Warm starting: each contact begins the solve from the impulse the same contact had at the
//! previous substep. docs/contact.md §"Warm starting".
//!
//! A contact is "the same" when it has the same body 1, the same body 2 (or the ground) and the
//! same features (the same vertex of body 1, or the same manifold features of the same convex
//! pieces). Its frame may have turned since, so the impulse is kept as a world
//! vector P = λn n + λt1 t1 + λt2 t2 and re-expressed in the new frame: λ₀ = (n·P, t1·P, t2·P).

use crate::common::hash::FastMap;
use crate::rigid3d::collide::{Contact, Feature};
use nalgebra::{SVector, Vector3};

/// Identifies a contact across substeps: (body 1, body 2 or ground, the features it comes from).
pub type ContactKey = (usize, Option<usize>, Feature);

/// The previous substep's impulses, by contact.
#[derive(Clone, Debug, Default)]
pub struct WarmStart {
    /// Whether to use them (the scene's `warm_start`); when false every λ₀ is zero.
    pub enabled: bool,
    impulses: FastMap<ContactKey, Vector3<f64>>,
    /// The previous substep's contacts in their order, with their impulses: a contact found at
    /// the same index as last substep (the usual case in a resting scene, whose detection order
    /// does not change) is matched without hashing.
    previous: Vec<(ContactKey, Vector3<f64>)>,
    /// Whether the previous substep's keys were all different (then the entry at an index is
    /// the one the map holds for its key; with a repeated key the map holds the last).
    unique: bool,
}

impl WarmStart {
    /// An empty cache.
    pub fn new(enabled: bool) -> WarmStart {
        WarmStart {
            enabled,
            impulses: FastMap::default(),
            previous: Vec::new(),
            unique: true,
        }
    }

    /// λ₀ for `contact`: its previous world impulse in its current frame, or zero.
    pub fn initial_impulse(&self, contact: &Contact) -> SVector<f64, 3> {
        self.initial_impulse_at(usize::MAX, contact)
    }

    /// λ₀ for `contact`, the `index`-th of this substep's contacts: the same impulse as
    /// [`Self::initial_impulse`], looked up first at the same index of the previous substep.
    pub fn initial_impulse_at(&self, index: usize, contact: &Contact) -> SVector<f64, 3> {
        if !self.enabled {
            return SVector::zeros();
        }
        let key = key(contact);
        let same_place = (self.previous.get(index))
            .filter(|(k, _)| self.unique && *k == key)
            .map(|(_, p)| p);
        match same_place.or_else(|| self.impulses.get(&key)) {
            Some(p) => SVector::<f64, 3>::new(
                contact.frame.n.dot(p),
                contact.frame.t1.dot(p),
                contact.frame.t2.dot(p),
            ),
            None => SVector::zeros(),
        }
    }

    /// Replaces the cache with this substep's contacts and impulses.
    pub fn store(&mut self, contacts: &[Contact], lambda: &[SVector<f64, 3>]) {
        self.impulses.clear();
        self.previous.clear();
        self.unique = true;
        if !self.enabled {
            return;
        }
        for (c, l) in contacts.iter().zip(lambda) {
            let p = c.frame.n * l[0] + c.frame.t1 * l[1] + c.frame.t2 * l[2];
            if self.impulses.insert(key(c), p).is_some() {
                self.unique = false;
            }
            self.previous.push((key(c), p));
        }
    }

    /// Forgets everything (a substep without contacts).
    pub fn clear(&mut self) {
        self.impulses.clear();
        self.previous.clear();
    }
}

fn key(c: &Contact) -> ContactKey {
    (c.body1, c.body2, c.feature)
}
