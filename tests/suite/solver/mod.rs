//! The shared core: the contact problem and PGS.

mod pgs;
