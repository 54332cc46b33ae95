//! The growth check of a perception (docs/maths.md §12): perceived shapes only grow, so a
//! point of an earlier shape's boundary lies inside a later one. The simulator judges every
//! scan event with it (`harmonav_sim`'s scanner) and the navigator's lidar checks measure
//! with it (`harmonav::checks::lidar`, feature `checks`).

use std::f64::consts::TAU;

use harmonav_transform::StarShape;
use nalgebra::Vector2;

/// Boundary samples per perceived shape in the growth check.
pub const GROWTH_SAMPLES: usize = 64;

/// How far outside a later perceived shape a point of an earlier one's boundary may be, m
/// (the refined distance's rounding: the point lies on the boundary of the same, unchanged
/// shape).
pub const GROWTH_TOLERANCE: f64 = 1e-9;

/// `n` points of the boundary of `s`, evenly in angle about its centre.
pub fn samples(s: &StarShape, n: usize) -> impl Iterator<Item = Vector2<f64>> + '_ {
    (0..n).map(move |j| s.boundary_point(TAU * j as f64 / n as f64))
}

/// The growth check: the points of [`GROWTH_SAMPLES`] on each boundary of `before` that lie
/// more than [`GROWTH_TOLERANCE`] outside every shape of `after` (0 when shapes only grow).
/// A point of an old boundary may lie on the new one (the same shape, unchanged): `contains`
/// is not decided there, the refined distance is.
pub fn shrunk(before: &[StarShape], after: &[StarShape]) -> usize {
    before
        .iter()
        .flat_map(|s| samples(s, GROWTH_SAMPLES))
        .filter(|&p| {
            !after
                .iter()
                .any(|s| s.signed_distance(p) <= GROWTH_TOLERANCE)
        })
        .count()
}
