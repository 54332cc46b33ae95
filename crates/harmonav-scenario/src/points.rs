//! Points read with their length checked: serde's `[f64; 2]` reads the first two numbers of a
//! longer TOML array and drops the rest, so `goal = [4.0, 0.0, "x"]` passed unnoticed. These
//! refuse any other length, naming it (`invalid length 3, expected a point [x, y]`); the
//! caller's error adds the field.

use serde::de::Error;
use serde::{Deserialize, Deserializer};

/// A point `[x, y]`, exactly two numbers.
struct Point([f64; 2]);

impl<'de> Deserialize<'de> for Point {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = Vec::<f64>::deserialize(d)?;
        <[f64; 2]>::try_from(v.as_slice())
            .map(Point)
            .map_err(|_| D::Error::invalid_length(v.len(), &"a point [x, y]"))
    }
}

/// `[x, y]`.
pub(crate) fn point<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 2], D::Error> {
    Point::deserialize(d).map(|p| p.0)
}

/// A ring `[[x, y], …]`.
pub(crate) fn ring<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<[f64; 2]>, D::Error> {
    Ok(Vec::<Point>::deserialize(d)?
        .into_iter()
        .map(|p| p.0)
        .collect())
}

/// Rings `[[[x, y], …], …]`.
pub(crate) fn rings<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Vec<[f64; 2]>>, D::Error> {
    Ok(Vec::<Vec<Point>>::deserialize(d)?
        .into_iter()
        .map(|r| r.into_iter().map(|p| p.0).collect())
        .collect())
}
