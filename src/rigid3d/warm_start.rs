//! Warm starting: each contact begins the solve from the impulse the same contact had at the
//! previous substep. docs/contact.md §"Warm starting".
//!
//! A contact is "the same" when it has the same body 1, the same body 2 (or the ground) and the
//! same features (the same vertex of body 1, or the same manifold features of the same convex
//! pieces). Its frame may have turned since, so the impulse is kept as a world
//! vector P = λn n + λt1 t1 + λt2 t2 and re-expressed in the new frame: λ₀ = (n·P, t1·P, t2·P).

use crate::common::warm_store::{WarmKey, WarmStore};
use crate::rigid3d::collide::{Contact, Feature};
use nalgebra::{SVector, Vector3};

pub use crate::common::warm_store::WarmCursor;

/// Identifies a contact across substeps: (body 1, body 2 or ground, the features it comes from).
pub type ContactKey = (usize, Option<usize>, Feature);

/// A 3D key's group: the ground contacts of body i are group (0, i, 0), a body pair's contacts
/// (either body as body 1) group (1, lower body, higher body). Detection lists the ground
/// contacts body by body, then the body pairs in increasing order, each pair's contacts
/// together ([`crate::rigid3d::collide::detect::Detector::detect`]), so its lists are in group
/// order (the starter's detection's need not be: the store then keeps a map).
impl WarmKey for ContactKey {
    type Group = (u8, usize, usize);
    fn group(&self) -> (u8, usize, usize) {
        match self.1 {
            None => (0, self.0, 0),
            Some(b) => (1, self.0.min(b), self.0.max(b)),
        }
    }
}

/// The previous substep's impulses, by contact.
#[derive(Clone, Debug, Default)]
pub struct WarmStart {
    /// Whether to use them (the scene's `warm_start`); when false every λ₀ is zero.
    pub enabled: bool,
    /// The previous substep's contacts' world impulses P, N·s, in their order.
    impulses: WarmStore<ContactKey, Vector3<f64>>,
}

impl WarmStart {
    /// An empty cache.
    pub fn new(enabled: bool) -> WarmStart {
        WarmStart {
            enabled,
            impulses: WarmStore::default(),
        }
    }

    /// λ₀ for `contact`: its previous world impulse (the one stored last under its key) in its
    /// current frame, or zero. `cursor` carries where the last look-up's group began: start
    /// each assembly at `WarmCursor::default()` and look the contacts up in their order.
    pub fn initial_impulse(&self, contact: &Contact, cursor: &mut WarmCursor) -> SVector<f64, 3> {
        if !self.enabled {
            return SVector::zeros();
        }
        match self.impulses.find(&key(contact), cursor) {
            Some(p) => SVector::<f64, 3>::new(
                contact.frame.n.dot(&p),
                contact.frame.t1.dot(&p),
                contact.frame.t2.dot(&p),
            ),
            None => SVector::zeros(),
        }
    }

    /// Replaces the cache with this substep's contacts and impulses.
    pub fn store(&mut self, contacts: &[Contact], lambda: &[SVector<f64, 3>]) {
        if !self.enabled {
            self.impulses.clear();
            return;
        }
        self.impulses
            .fill(contacts.iter().zip(lambda).map(|(c, l)| {
                (
                    key(c),
                    c.frame.n * l[0] + c.frame.t1 * l[1] + c.frame.t2 * l[2],
                )
            }));
    }

    /// Forgets everything (a substep without contacts).
    pub fn clear(&mut self) {
        self.impulses.clear();
    }
}

fn key(c: &Contact) -> ContactKey {
    (c.body1, c.body2, c.feature)
}
