//! The `C^∞` smooth step `beta` that blends the radial maps into the identity.

/// The logistic `s(w) = 1/(1 + e^{−w})` and its derivative `s(w)(1 − s(w))`, from one
/// exponential of a non-positive argument (no overflow for any `w`). The same function as the
/// potential crate's `sigma`, kept here so that this crate does not depend on it.
fn logistic_and_prime(w: f64) -> (f64, f64) {
    let e = (-w.abs()).exp();
    let d = 1.0 + e;
    let value = if w >= 0.0 { 1.0 / d } else { e / d };
    (value, e / (d * d))
}

/// Smooth step `beta(t) = f(t)/(f(t) + f(1 − t))`, `f(t) = e^{−1/t}`, and its derivative.
///
/// `beta = 0` for `t ≤ 0`, `1` for `t ≥ 1`; all derivatives vanish at both ends, so pieces
/// joined with it are `C^∞`. Returns `(beta, beta')`.
///
/// Numerical guard: evaluated as the logistic `s(w) = 1/(1 + e^{−w})` of
/// `w = 1/(1 − t) − 1/t` (no `e^{−1/t}` ratio of underflowed numbers), with
/// `beta' = s'(w)·(1/t² + 1/(1 − t)²)`; where `s'(w)` underflows to 0 (within ≈ 1/745 of either end) `beta' = 0` exactly, so the
/// huge `1/t²` never meets it as `0·∞`.
pub fn beta(t: f64) -> (f64, f64) {
    if t <= 0.0 {
        return (0.0, 0.0);
    }
    if t >= 1.0 {
        return (1.0, 0.0);
    }
    let w = 1.0 / (1.0 - t) - 1.0 / t;
    let (s, sp) = logistic_and_prime(w);
    let db = if sp == 0.0 {
        0.0
    } else {
        sp * (1.0 / (t * t) + 1.0 / ((1.0 - t) * (1.0 - t)))
    };
    (s, db)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_definition_and_its_symmetry() {
        for i in 1..100 {
            let t = i as f64 / 100.0;
            let f = |t: f64| (-1.0 / t).exp();
            let (b, _) = beta(t);
            assert!((b - f(t) / (f(t) + f(1.0 - t))).abs() < 1e-14, "t = {t}");
            // beta(t) + beta(1 − t) = 1
            assert!((b + beta(1.0 - t).0 - 1.0).abs() < 1e-14, "t = {t}");
        }
    }

    #[test]
    fn derivative_matches_finite_differences_and_is_non_negative() {
        for i in 1..1000 {
            let t = i as f64 / 1000.0;
            let h = 1e-7;
            let fd = (beta(t + h).0 - beta(t - h).0) / (2.0 * h);
            let (_, d) = beta(t);
            assert!(d >= 0.0);
            assert!((d - fd).abs() < 1e-6 * d.max(1.0), "t = {t}: {d} vs {fd}");
        }
    }

    #[test]
    fn flat_and_finite_at_the_ends() {
        for t in [1e-300, 1e-12, 1e-3, 1.0 - 1e-3, 1.0 - 1e-12] {
            let (b, d) = beta(t);
            assert!(b.is_finite() && d.is_finite(), "t = {t}");
            assert!(d < 1e-100, "t = {t}: beta' = {d}");
        }
        assert_eq!(beta(-1.0), (0.0, 0.0));
        assert_eq!(beta(0.0), (0.0, 0.0));
        assert_eq!(beta(1.0), (1.0, 0.0));
        assert_eq!(beta(0.5), (0.5, 8.0 * 0.25));
    }
}
