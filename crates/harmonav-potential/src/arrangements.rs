//! Special point-world arrangements from the paper's analysis.

use nalgebra::Vector2;

use crate::error::PotentialError;
use crate::world::PointWorld;

/// The symmetric arrangement of proposition `Morse`: `M = 2μ + 1` obstacle points for which
/// `phi_k` (with `k = M + 1`) has a degenerate critical point (both Hessian eigenvalues 0).
///
/// Returns the world and the degenerate critical point `h_c`. With `ĥ_d` the unit vector
/// from `P_d` to `h_c`, obstacle 1 lies on the axis with `θ_1d = 0` (`h_1 ∥ ĥ_d`) and the `μ`
/// pairs have `θ_id = ±45°`, i.e. seen from `h_c` they lie at `±135°` from `ĥ_d`
/// (the paper's `±135°` is measured between `−h_i` and `ĥ_d`). Distances `a = |h_1|` (given),
/// `|h_d| = √k·a` (eq. `nondegreqlmd`, which makes `λ` of eq. `lambda` vanish), and pair `j` at
/// `b_j = j·β` with `β = √2·H_μ·a/(√k − 1)` (`H_μ` the harmonic number), which makes the
/// gradient along `ĥ_d` vanish (eq. `critpreq`); the perpendicular component cancels by
/// symmetry. `h_c = centre`, `ĥ_d = e_x`.
///
/// Errors with [`PotentialError::InvalidArgument`] if `mu == 0` or `a` is not finite and
/// positive.
pub fn non_morse(
    mu: usize,
    a: f64,
    centre: Vector2<f64>,
) -> Result<(PointWorld, Vector2<f64>), PotentialError> {
    if mu == 0 {
        return Err(PotentialError::InvalidArgument {
            problem: "mu (the number of obstacle pairs) must be at least 1",
        });
    }
    if !(a.is_finite() && a > 0.0) {
        return Err(PotentialError::InvalidArgument {
            problem: "a (the distance to obstacle 1) must be finite and positive",
        });
    }
    let m = 2 * mu + 1;
    let k = m as f64 + 1.0;
    let harmonic: f64 = (1..=mu).map(|j| 1.0 / j as f64).sum();
    let beta = std::f64::consts::SQRT_2 * harmonic * a / (k.sqrt() - 1.0);
    let destination = centre - Vector2::new(k.sqrt() * a, 0.0);
    let mut obstacles = vec![centre - Vector2::new(a, 0.0)];
    let diag = std::f64::consts::FRAC_1_SQRT_2;
    for j in 1..=mu {
        let b = j as f64 * beta;
        // h_i = h_c − P_i = b (cos ±45°, sin ±45°)
        obstacles.push(centre - b * Vector2::new(diag, diag));
        obstacles.push(centre - b * Vector2::new(diag, -diag));
    }
    Ok((PointWorld::new(destination, obstacles)?, centre))
}

/// A deterministic benchmark world: `m` obstacle points on a golden-angle spiral
/// (`r_i = 1 + 0.05 i`, `θ_i = 2.399963 i`) around the destination `(0.123, −0.077)`.
/// Used by the criterion benches and `cargo xtask bench` so that both time the same world.
pub fn golden_spiral(m: usize) -> PointWorld {
    let points: Vec<_> = (0..m)
        .map(|i| {
            let (r, a) = (1.0 + 0.05 * i as f64, 2.399_963 * i as f64);
            Vector2::new(r * a.cos(), r * a.sin())
        })
        .collect();
    PointWorld::new(Vector2::new(0.123, -0.077), points)
        .expect("distinct points: the radii strictly increase")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gradient_and_hessian_vanish_at_the_constructed_point() {
        for mu in 1..=4 {
            let (w, hc) = non_morse(mu, 0.7, Vector2::new(0.3, -0.2)).unwrap();
            assert_eq!(w.obstacles().len(), 2 * mu + 1);
            let g = w.grad_phi_k(hc).unwrap();
            let h = w.hess_phi_k(hc).unwrap();
            assert!(g.norm() < 1e-13, "mu = {mu}: |grad| = {}", g.norm());
            assert!(h.norm() < 1e-13, "mu = {mu}: |H| = {}", h.norm());
            // While a nearby generic point has a clearly non-zero Hessian.
            let h2 = w.hess_phi_k(hc + Vector2::new(0.05, 0.02)).unwrap();
            assert!(h2.norm() > 1e-4, "mu = {mu}: |H| nearby = {}", h2.norm());
        }
    }
}
