//! The 2D warm start's store: the last solve's impulse of each contact, found again by the
//! contact's key (body 1, body 2, block 1, block 2), filed by its body pair in
//! [`crate::common::warm_store::WarmStore`] (the store both systems use). docs/blocks2d.md
//! §"Contact problem", "Finding the key".

use super::collide::{Contact2, tangent};
use crate::common::warm_store::{WarmKey, WarmStore};
use nalgebra::{SVector, Vector2};

pub use crate::common::warm_store::WarmCursor;

/// Identifies a 2D contact across substeps: (body 1, body 2, block 1, block 2).
pub type ContactKey2 = (usize, usize, usize, usize);

/// A 2D key's group is its body pair (body 1, body 2): detection lists contacts pair by pair in
/// increasing (body 1, body 2).
impl WarmKey for ContactKey2 {
    type Group = (usize, usize);
    fn group(&self) -> (usize, usize) {
        (self.0, self.1)
    }
}

/// The last solve's contacts' world impulses P = λn n + λt t (mass units · blocks per time
/// unit), by contact key.
pub type WarmStore2 = WarmStore<ContactKey2, Vector2<f64>>;

impl WarmStore<ContactKey2, Vector2<f64>> {
    /// Replaces the store with `contacts` and their impulses λ = (λn, λt).
    pub fn store(&mut self, contacts: &[Contact2], lambda: &[SVector<f64, 2>]) {
        self.fill(contacts.iter().zip(lambda).map(|(c, l)| {
            (
                (c.body1, c.body2, c.block1, c.block2),
                c.normal * l[0] + tangent(&c.normal) * l[1],
            )
        }));
    }
}
