//! Shared proptest strategies: random valid point worlds and regular query points.
#![allow(dead_code)]

use harmonav_potential::{PointWorld, Vector2};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

/// Seeded, non-persisting proptest configuration (deterministic runs, no files written).
pub fn config(cases: u32) -> Config {
    Config {
        cases,
        rng_seed: RngSeed::Fixed(0x0048_4152_4D4E_4156),
        failure_persistence: None,
        ..Config::default()
    }
}

/// Minimum pairwise separation of the generated points.
pub const SEPARATION: f64 = 0.3;

pub fn point(extent: f64) -> impl Strategy<Value = Vector2<f64>> {
    (-extent..extent, -extent..extent).prop_map(|(x, y)| Vector2::new(x, y))
}

/// Random point worlds with 1..=max_m obstacle points in [-5, 5]², all points (destination
/// included) at least `SEPARATION` apart, default k = M + 1.
pub fn world(max_m: usize) -> impl Strategy<Value = PointWorld> {
    (1..=max_m)
        .prop_flat_map(|m| (proptest::collection::vec(point(5.0), m), point(5.0)))
        .prop_filter_map("points too close", |(pts, d)| {
            let mut all = pts.clone();
            all.push(d);
            for i in 0..all.len() {
                for j in 0..i {
                    if (all[i] - all[j]).norm() < SEPARATION {
                        return None;
                    }
                }
            }
            PointWorld::new(d, pts).ok()
        })
}

/// Smallest distance from `h` to the destination and the obstacle points.
pub fn clearance(w: &PointWorld, h: Vector2<f64>) -> f64 {
    w.obstacles()
        .iter()
        .map(|p| (h - p).norm())
        .fold((h - w.destination()).norm(), f64::min)
}

/// The scale of ∇phi_k at h (the sum of the magnitudes of the terms of eq. gradient).
pub fn grad_scale(w: &PointWorld, h: Vector2<f64>) -> f64 {
    w.grad_term_scale(h)
}

/// The scale of H(phi_k) at h (the sum of the magnitudes of the terms of eq. hessquadratic).
pub fn hess_scale(w: &PointWorld, h: Vector2<f64>) -> f64 {
    w.hess_term_scale(h)
}
