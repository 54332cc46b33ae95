//! The radial maps against their defining properties and finite differences.

use harmonav_transform::radial::{Radial, obstacle_map, outer_map};
use nalgebra::Vector2;
use proptest::prelude::*;

mod common;
use common::config;

/// A star boundary `R(θ) = r0 + a cos(nθ + φ)` (positive for |a| < r0) and its derivative.
fn star(r0: f64, a: f64, n: f64, phase: f64) -> impl Fn(f64) -> (f64, f64) {
    move |th| {
        (
            r0 + a * (n * th + phase).cos(),
            -a * n * (n * th + phase).sin(),
        )
    }
}

/// Phi of one radial map about the origin, as a function of the Cartesian point.
fn phi(
    map: &dyn Fn(f64, f64, f64) -> Radial,
    shape: &dyn Fn(f64) -> (f64, f64),
    x: Vector2<f64>,
) -> Vector2<f64> {
    let rho = x.norm();
    let th = x.y.atan2(x.x);
    let (r, dr) = shape(th);
    map(rho, r, dr).nu * x / rho
}

fn fd_jacobian(
    f: impl Fn(Vector2<f64>) -> Vector2<f64>,
    x: Vector2<f64>,
    h: f64,
) -> nalgebra::Matrix2<f64> {
    let cx = (f(x + Vector2::new(h, 0.0)) - f(x - Vector2::new(h, 0.0))) / (2.0 * h);
    let cy = (f(x + Vector2::new(0.0, h)) - f(x - Vector2::new(0.0, h))) / (2.0 * h);
    nalgebra::Matrix2::from_columns(&[cx, cy])
}

proptest! {
    #![proptest_config(config(2000))]

    /// Obstacle map: boundary → centre, identity at the outer edge, ν_ρ ≥ 1, det J > 0 down to
    /// 1e-9 from the boundary, and J against finite differences.
    #[test]
    fn obstacle_map_collapses_and_is_a_diffeomorphism(
        r0 in 0.2..2.0f64, rel in 0.0..0.6f64, n in 1u32..6, phase in 0.0..6.3f64,
        eps in 0.05..1.0f64, th in -3.1..3.1f64, t in 1e-12..1.2f64,
    ) {
        let shape = star(r0, rel * r0, n as f64, phase);
        let (r, dr) = shape(th);
        prop_assert_eq!(obstacle_map(r, r, dr, eps).nu, 0.0);
        prop_assert!((obstacle_map(r + eps, r, dr, eps).nu - (r + eps)).abs() < 1e-12);
        for tt in [t, 1e-9, 1e-6, 1.0 - 1e-9] {
            let rho = r + tt * eps;
            let m = obstacle_map(rho, r, dr, eps);
            prop_assert!(m.nu_rho >= 1.0 - 1e-12, "ν_ρ = {} at t = {tt}", m.nu_rho);
            prop_assert!(m.nu >= 0.0 && m.nu <= rho + 1e-12);
            prop_assert!(m.det(rho) > 0.0, "det J = {} at t = {tt}", m.det(rho));
        }
        let rho = r + t * eps;
        let x = rho * Vector2::new(th.cos(), th.sin());
        prop_assume!(t > 1e-3 && (t - 1.0).abs() > 1e-3);
        let map = |rho: f64, r: f64, dr: f64| obstacle_map(rho, r, dr, eps);
        let j = obstacle_map(rho, r, dr, eps).jacobian(x / rho, rho);
        let fd = fd_jacobian(|y| phi(&map, &shape, y), x, 1e-7);
        prop_assert!((j - fd).norm() <= 1e-5 * j.norm().max(1.0), "J = {j}, fd = {fd}");
    }

    /// Outer map: identity inside the band, ν_ρ ≥ 1, ν → ∞ at the wall, J against differences.
    #[test]
    fn outer_map_stretches_to_infinity_and_is_a_diffeomorphism(
        r0 in 3.0..8.0f64, rel in 0.0..0.2f64, n in 1u32..5, phase in 0.0..6.3f64,
        eps0 in 0.1..1.0f64, gain in 0.1..50.0f64, th in -3.1..3.1f64, s in 0.0..1.0f64,
    ) {
        let shape = star(r0, rel * r0, n as f64, phase);
        let (r, dr) = shape(th);
        let inner = r - eps0;
        prop_assert_eq!(outer_map(inner, r, dr, eps0, gain), Radial::identity(inner));
        for ss in [s, 1e-9, 1.0 - 1e-6, 1.0 - 1e-12] {
            let rho = inner + ss * eps0;
            let m = outer_map(rho, r, dr, eps0, gain);
            prop_assert!(m.nu.is_finite() && m.nu >= rho && m.nu_rho >= 1.0, "s = {ss}: {m:?}");
            prop_assert!(m.det(rho) > 0.0);
        }
        prop_assert!(outer_map(r - 1e-12, r, dr, eps0, gain).nu > 1e9);
        prop_assert_eq!(outer_map(r, r, dr, eps0, gain).nu, f64::INFINITY);
        let rho = inner + s * eps0;
        prop_assume!(s > 1e-3 && s < 0.9);
        let x = rho * Vector2::new(th.cos(), th.sin());
        let map = |rho: f64, r: f64, dr: f64| outer_map(rho, r, dr, eps0, gain);
        let j = outer_map(rho, r, dr, eps0, gain).jacobian(x / rho, rho);
        let fd = fd_jacobian(|y| phi(&map, &shape, y), x, 1e-7);
        prop_assert!((j - fd).norm() <= 1e-5 * j.norm().max(1.0), "J = {j}, fd = {fd}");
    }

    /// Both maps are injective along every ray (ν strictly increasing in ρ).
    #[test]
    fn maps_are_strictly_increasing_along_rays(r in 0.2..2.0f64, eps in 0.05..1.0f64, gain in 0.1..20.0f64) {
        let mut last = -1.0;
        for i in 0..=2000 {
            let rho = r + eps * 1.2 * i as f64 / 2000.0;
            let nu = obstacle_map(rho, r, 0.0, eps).nu;
            prop_assert!(nu > last, "obstacle map not increasing at ρ = {rho}");
            last = nu;
        }
        let mut last = -1.0;
        for i in 0..2000 {
            let rho = 5.0 - eps - 0.2 + (eps + 0.2) * i as f64 / 2000.0;
            let nu = outer_map(rho, 5.0, 0.0, eps, gain).nu;
            prop_assert!(nu > last, "outer map not increasing at ρ = {rho}");
            last = nu;
        }
    }
}
