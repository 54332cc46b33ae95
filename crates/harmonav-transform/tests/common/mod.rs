//! Shared proptest strategies: random shapes of all four kinds.
#![allow(dead_code)]

use harmonav_transform::StarShape;
use nalgebra::Vector2;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

/// Seeded, non-persisting proptest configuration.
pub fn config(cases: u32) -> Config {
    Config {
        cases,
        rng_seed: RngSeed::Fixed(0x0048_4152_4D4E_4156),
        failure_persistence: None,
        ..Config::default()
    }
}

/// A random shape of size about `size` centred at `c`: circle, ellipse, rounded polygon
/// (star-shaped, possibly non-convex) or Fourier star.
pub fn shape_at(c: Vector2<f64>, size: f64) -> impl Strategy<Value = StarShape> {
    let circle = (0.5..1.0f64).prop_map(move |r| StarShape::circle(c, r * size).unwrap());
    let ellipse = (0.5..1.0f64, 0.3..1.0f64, 0.0..3.2f64)
        .prop_map(move |(a, q, ang)| StarShape::ellipse(c, [a * size, a * q * size], ang).unwrap());
    let polygon = (
        3usize..8,
        prop::collection::vec(0.6..1.0f64, 8),
        0.0..1.0f64,
        0.02..0.2f64,
    )
        .prop_filter_map("polygon rejected", move |(n, radii, phase, rc)| {
            let v: Vec<_> = (0..n)
                .map(|i| {
                    let a = phase + std::f64::consts::TAU * i as f64 / n as f64;
                    c + radii[i] * size * Vector2::new(a.cos(), a.sin())
                })
                .collect();
            StarShape::rounded_polygon(&v, rc * size).ok()
        });
    let star = (
        0.6..1.0f64,
        prop::collection::vec((1u32..6, -0.15..0.15f64, -0.15..0.15f64), 1..4),
    )
        .prop_filter_map("star rejected", move |(r0, h)| {
            let h: Vec<_> = h
                .into_iter()
                .map(|(n, a, b)| (n, a * size, b * size))
                .collect();
            StarShape::fourier_star(c, r0 * size, &h).ok()
        });
    prop_oneof![circle, ellipse, polygon, star]
}
