//! The single harmonic term `ln|v|²` of the point-world potential, with `v = h − P`.
//!
//! `phi_k` is a weighted sum of such terms (`+1` for the destination, `−1/k` for each obstacle
//! point), so these three functions carry every numerical guard of the crate:
//!
//! ```text
//! ln|v|²            value
//! ∇ ln|v|²  = 2 v/|v|²                          (the summands of eq. gradient)
//! H ln|v|²  = (2/|v|²)(I − 2 v̂ v̂ᵀ)              (the summands of eq. hessquadratic)
//! ```
//!
//! Guards: `|v|²` is formed directly only when it is a normal `f64`; otherwise (|v| beyond
//! ≈ 1e154 or below ≈ 1e-154) the vector is first scaled by its largest component, so far
//! points (e.g. |v| = 1e300) and points very close to a singularity give finite, correctly
//! rounded results instead of `inf/inf` or `0/0`. At `v = 0` exactly the term is singular:
//! the value is `−∞` and the derivatives return `None`.

use nalgebra::{Matrix2, Vector2};

/// `ln|v|²`, finite for every finite non-zero `v`; `−∞` at `v = 0`.
#[inline]
pub fn ln_norm2(v: Vector2<f64>) -> f64 {
    let r2 = v.x * v.x + v.y * v.y;
    if r2.is_normal() {
        r2.ln()
    } else {
        // Guard: |v|² overflowed or underflowed; hypot does not.
        2.0 * v.x.hypot(v.y).ln()
    }
}

/// `v / |v|²` (half of `∇ ln|v|²`); `None` at `v = 0` where the term is singular.
#[inline]
pub fn reciprocal(v: Vector2<f64>) -> Option<Vector2<f64>> {
    let r2 = v.x * v.x + v.y * v.y;
    if r2.is_normal() {
        Some(v / r2)
    } else {
        // Guard against 0/0 and inf/inf: scale by the largest component first.
        let s = v.x.abs().max(v.y.abs());
        if s == 0.0 || !s.is_finite() {
            return None;
        }
        let w = v / s;
        Some(w / (s * w.norm_squared()))
    }
}

/// The unit vector `v̂ = v/|v|`, scaled first so that `|v|` neither overflows nor
/// underflows; `None` at `v = 0`.
#[inline]
pub fn unit(v: Vector2<f64>) -> Option<Vector2<f64>> {
    let s = v.x.abs().max(v.y.abs());
    if s == 0.0 || !s.is_finite() {
        return None;
    }
    let w = v / s;
    Some(w / w.norm())
}

/// `∇ ln|v|² = 2 v/|v|²`; `None` at `v = 0`.
#[inline]
pub fn grad_ln_norm2(v: Vector2<f64>) -> Option<Vector2<f64>> {
    reciprocal(v).map(|r| 2.0 * r)
}

/// `H ln|v|² = (2/|v|²)(I − 2 v̂ v̂ᵀ)`: trace zero (harmonic), eigenvalues `∓2/|v|²` along
/// `v̂` and `v̂⊥`; `None` at `v = 0`.
#[inline]
pub fn hess_ln_norm2(v: Vector2<f64>) -> Option<Matrix2<f64>> {
    let r = reciprocal(v)?; // r = v̂/|v|
    // 2/|v|² = 2|r|², and v̂ v̂ᵀ/|v|² = r rᵀ: no normalisation needed.
    let r2 = r.norm_squared();
    Some(2.0 * (Matrix2::identity() * r2 - 2.0 * r * r.transpose()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn far_and_near_vectors_stay_finite() {
        for &s in &[1e-300, 1e-160, 1e-3, 1.0, 1e150, 1e200, 1e300] {
            let v = Vector2::new(0.6 * s, -0.8 * s);
            let ln = ln_norm2(v);
            assert!(
                (ln - 2.0 * s.ln()).abs() <= 1e-12 * ln.abs().max(1.0),
                "ln at {s}"
            );
            let r = reciprocal(v).unwrap();
            // v/|v|² = (0.6, −0.8)/s
            assert!(
                (r.x * s - 0.6).abs() < 1e-14 && (r.y * s + 0.8).abs() < 1e-14,
                "1/v at {s}"
            );
            if s >= 1e-150 {
                let h = hess_ln_norm2(v).unwrap();
                assert!(h.iter().all(|x| x.is_finite()), "Hessian at {s}");
                assert!(h.trace().abs() <= 1e-14 * h.norm(), "trace at {s}");
            }
        }
    }

    #[test]
    fn zero_vector_is_singular_not_nan() {
        let z = Vector2::zeros();
        assert_eq!(ln_norm2(z), f64::NEG_INFINITY);
        assert!(reciprocal(z).is_none());
        assert!(grad_ln_norm2(z).is_none());
        assert!(hess_ln_norm2(z).is_none());
    }

    #[test]
    fn hessian_eigenvalues_are_minus_and_plus_two_over_r_squared() {
        let v = Vector2::new(3.0, 4.0); // |v|² = 25
        let h = hess_ln_norm2(v).unwrap();
        let n = v / 5.0;
        let t = Vector2::new(-n.y, n.x);
        assert!(((n.transpose() * h * n)[0] + 2.0 / 25.0).abs() < 1e-15);
        assert!(((t.transpose() * h * t)[0] - 2.0 / 25.0).abs() < 1e-15);
    }
}
