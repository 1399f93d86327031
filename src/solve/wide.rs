//! Four f64 lanes and the operations the lane-wise sweep takes on them (docs/contact.md §"Four
//! contacts per lane"; [`super::pgs_lanes`]). Each operation is the scalar one lane by lane,
//! written as a loop over the four lanes that the compiler turns into one vector instruction;
//! the IEEE operations (+, −, ×, ÷, √, comparisons) are correctly rounded in either form, so a
//! lane's result is the scalar result to the bit. No fused multiply-add: a · b + c rounds twice,
//! as the scalar code does.

// Loops over side s, row r, component d and lane l index several arrays by the same subscript,
// as the derivation writes them.
#![allow(clippy::needless_range_loop)]

use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

/// Lanes per [`Wide`].
pub(super) const LANES: usize = 4;

/// Four f64, one per lane.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(32))]
pub(super) struct Wide(pub [f64; LANES]);

/// Four lane conditions: all bits set where true, none where false (the form a vector
/// comparison gives, so that a select is a bitwise blend).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(32))]
pub(super) struct Mask([u64; LANES]);

impl Wide {
    /// Every lane `x`.
    #[inline(always)]
    pub fn splat(x: f64) -> Wide {
        Wide([x; LANES])
    }

    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> Wide {
        let mut out = [0.0; LANES];
        for l in 0..LANES {
            out[l] = f(self.0[l]);
        }
        Wide(out)
    }

    #[inline(always)]
    fn zip(self, other: Wide, f: impl Fn(f64, f64) -> f64) -> Wide {
        let mut out = [0.0; LANES];
        for l in 0..LANES {
            out[l] = f(self.0[l], other.0[l]);
        }
        Wide(out)
    }

    #[inline(always)]
    fn compare(self, other: Wide, f: impl Fn(f64, f64) -> bool) -> Mask {
        let mut out = [0; LANES];
        for l in 0..LANES {
            out[l] = if f(self.0[l], other.0[l]) {
                u64::MAX
            } else {
                0
            };
        }
        Mask(out)
    }

    /// √x per lane.
    #[inline(always)]
    pub fn sqrt(self) -> Wide {
        self.map(f64::sqrt)
    }

    /// max(x, 0) per lane as [`super::projection::positive_part`] computes it (+0 for −0 and
    /// NaN).
    #[inline(always)]
    pub fn positive_part(self) -> Wide {
        let zero = Wide::splat(0.0);
        self.gt(zero).select(self, zero)
    }

    /// self > other per lane.
    #[inline(always)]
    pub fn gt(self, other: Wide) -> Mask {
        self.compare(other, |a, b| a > b)
    }

    /// self < other per lane.
    #[inline(always)]
    pub fn lt(self, other: Wide) -> Mask {
        self.compare(other, |a, b| a < b)
    }

    /// self == other per lane (−0 == +0; NaN equals nothing).
    #[inline(always)]
    pub fn eq(self, other: Wide) -> Mask {
        self.compare(other, |a, b| a == b)
    }

    /// self ≠ other per lane.
    #[inline(always)]
    pub fn ne(self, other: Wide) -> Mask {
        self.compare(other, |a, b| a != b)
    }

    /// `x.clamp(lo, hi)` per lane as the standard library computes it (below lo → lo, then
    /// above hi → hi), without its check that lo ≤ hi: a lane whose result is not taken may
    /// hold any bounds.
    #[inline(always)]
    pub fn clamp(self, lo: Wide, hi: Wide) -> Wide {
        let x = self.lt(lo).select(lo, self);
        x.gt(hi).select(hi, x)
    }
}

impl Mask {
    /// No lane's condition holds.
    pub const NONE: Mask = Mask([0; LANES]);

    /// Sets lane `l`'s condition to `holds`.
    #[inline(always)]
    pub fn assign(&mut self, l: usize, holds: bool) {
        self.0[l] = if holds { u64::MAX } else { 0 };
    }

    /// Lane `l`'s condition.
    #[inline(always)]
    pub fn lane(self, l: usize) -> bool {
        self.0[l] != 0
    }

    /// Per lane: `yes` where the condition holds, else `no` (a bitwise blend, exact).
    #[inline(always)]
    pub fn select(self, yes: Wide, no: Wide) -> Wide {
        let mut out = [0.0; LANES];
        for l in 0..LANES {
            let m = self.0[l];
            out[l] = f64::from_bits((yes.0[l].to_bits() & m) | (no.0[l].to_bits() & !m));
        }
        Wide(out)
    }
}

impl Add for Wide {
    type Output = Wide;
    #[inline(always)]
    fn add(self, other: Wide) -> Wide {
        self.zip(other, |a, b| a + b)
    }
}

impl AddAssign for Wide {
    #[inline(always)]
    fn add_assign(&mut self, other: Wide) {
        *self = *self + other;
    }
}

impl Sub for Wide {
    type Output = Wide;
    #[inline(always)]
    fn sub(self, other: Wide) -> Wide {
        self.zip(other, |a, b| a - b)
    }
}

impl Mul for Wide {
    type Output = Wide;
    #[inline(always)]
    fn mul(self, other: Wide) -> Wide {
        self.zip(other, |a, b| a * b)
    }
}

impl Div for Wide {
    type Output = Wide;
    #[inline(always)]
    fn div(self, other: Wide) -> Wide {
        self.zip(other, |a, b| a / b)
    }
}

impl Neg for Wide {
    type Output = Wide;
    #[inline(always)]
    fn neg(self) -> Wide {
        self.map(|a| -a)
    }
}
