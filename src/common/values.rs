//! Validated scene values that both systems' scene files use. Each type checks itself while it is deserialised, so that serde_json
//! reports the line and column of a bad value and serde_path_to_error its key path, e.g.
//! `scene.json:7:22: sim_parameters[0].dt: must be a positive number of seconds, got -0.01`.

use serde::de::Error;
use serde::{Deserialize, Deserializer};

/// A number > 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Positive(pub f64);

impl<'de> Deserialize<'de> for Positive {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let x = f64::deserialize(d)?;
        if !(x.is_finite() && x > 0.0) {
            return Err(D::Error::custom(format!(
                "must be a positive number, got {x}"
            )));
        }
        Ok(Positive(x))
    }
}

/// A number in [0, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fraction(pub f64);

impl<'de> Deserialize<'de> for Fraction {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let x = f64::deserialize(d)?;
        if !(x.is_finite() && (0.0..=1.0).contains(&x)) {
            return Err(D::Error::custom(format!(
                "must be a number in [0, 1], got {x}"
            )));
        }
        Ok(Fraction(x))
    }
}

/// A number ≥ 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NonNegative(pub f64);

impl<'de> Deserialize<'de> for NonNegative {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let x = f64::deserialize(d)?;
        if !(x.is_finite() && x >= 0.0) {
            return Err(D::Error::custom(format!("must be a number ≥ 0, got {x}")));
        }
        Ok(NonNegative(x))
    }
}

/// An integer ≥ 1 (a count of substeps or iterations).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Count(pub u32);

impl<'de> Deserialize<'de> for Count {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let x = f64::deserialize(d)?;
        if !(x.fract() == 0.0 && (1.0..=1e9).contains(&x)) {
            return Err(D::Error::custom(format!(
                "must be a whole number ≥ 1 (at most 1000000000), got {}",
                if x.abs() < 1e15 {
                    format!("{x}")
                } else {
                    format!("{x:e}")
                }
            )));
        }
        Ok(Count(x as u32))
    }
}
