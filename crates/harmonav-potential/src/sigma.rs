//! The squashing function `sigma(s) = e^s / (1 + e^s)` (eq. `switch`) and its derivatives.
//!
//! All three functions are finite for every finite `s` and for `s = ±∞`; none of them forms
//! `e^s` for large positive `s`, so nothing overflows (checked for `|s|` up to `f64::MAX`).

/// Eq. (`switch`): `sigma(s) = e^s / (1 + e^s)`, mapping the extended real line onto `[0, 1]`.
///
/// Edges: `sigma(−∞) = 0`, `sigma(+∞) = 1`, `sigma(0) = 1/2`.
///
/// Numerical guard: for `s ≥ 0` the form `1/(1 + e^{−s})` is used and for `s < 0` the form
/// `e^s/(1 + e^s)`, so the only exponential evaluated has a non-positive argument.
#[inline]
pub fn sigma(s: f64) -> f64 {
    if s >= 0.0 {
        1.0 / (1.0 + (-s).exp())
    } else {
        let e = s.exp();
        e / (1.0 + e)
    }
}

/// `sigma'(s) = sigma(s)(1 − sigma(s)) = e^{−|s|} / (1 + e^{−|s|})²`.
///
/// Edges: `0` at `s = ±∞`, `1/4` at `s = 0`. The symmetric form never overflows; it underflows
/// to exactly `0` for `|s| ≳ 745` (the *direction* of `∇varphi` is still available from
/// [`crate::PointWorld::descent_direction`], which does not go through `sigma'`).
#[inline]
pub fn sigma_prime(s: f64) -> f64 {
    let e = (-s.abs()).exp();
    let d = 1.0 + e;
    e / (d * d)
}

/// `(sigma(s), sigma'(s))` from one exponential (the hot path of `∇Θ`).
#[inline]
pub fn sigma_and_prime(s: f64) -> (f64, f64) {
    let e = (-s.abs()).exp();
    let d = 1.0 + e;
    let value = if s >= 0.0 { 1.0 / d } else { e / d };
    (value, e / (d * d))
}

/// `ln sigma'(s) = −|s| − 2 ln(1 + e^{−|s|})`: finite for every finite `s` (no underflow),
/// `−∞` at `s = ±∞`. Used to scale derivatives of `varphi` in log space.
#[inline]
pub fn ln_sigma_prime(s: f64) -> f64 {
    -s.abs() - 2.0 * (-s.abs()).exp().ln_1p()
}

/// `sigma''(s) = sigma'(s)(1 − 2 sigma(s))`, with `1 − 2 sigma(s) = −tanh(s/2)` evaluated
/// without cancellation.
///
/// Edges: `0` at `s = 0` and at `s = ±∞`.
#[inline]
pub fn sigma_second(s: f64) -> f64 {
    -sigma_prime(s) * (0.5 * s).tanh()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sigma_matches_the_definition_where_the_definition_is_safe() {
        for &s in &[-30.0, -3.0, -0.5, 0.0, 0.25, 2.0, 30.0] {
            let e = f64::exp(s);
            assert!((sigma(s) - e / (1.0 + e)).abs() <= 1e-15, "s = {s}");
            let p = e / ((1.0 + e) * (1.0 + e));
            assert!(
                (sigma_prime(s) - p).abs() <= 1e-15 * p.max(1e-300),
                "s = {s}"
            );
            assert!((ln_sigma_prime(s) - p.ln()).abs() <= 1e-13, "s = {s}");
            let (v, d) = sigma_and_prime(s);
            assert!(
                (v - sigma(s)).abs() <= 1e-16 && (d - sigma_prime(s)).abs() <= 1e-17,
                "s = {s}"
            );
        }
    }

    #[test]
    fn derivatives_match_central_differences() {
        for &s in &[-8.0, -1.3, -0.2, 0.0, 0.7, 3.0, 9.0] {
            let h = 1e-5;
            let fd1 = (sigma(s + h) - sigma(s - h)) / (2.0 * h);
            let fd2 = (sigma_prime(s + h) - sigma_prime(s - h)) / (2.0 * h);
            assert!((sigma_prime(s) - fd1).abs() < 1e-9, "sigma' at {s}");
            assert!((sigma_second(s) - fd2).abs() < 1e-9, "sigma'' at {s}");
        }
    }

    #[test]
    fn extreme_arguments_stay_finite_and_exact() {
        for &s in &[1e308, f64::MAX, f64::INFINITY] {
            assert_eq!(sigma(s), 1.0);
            assert_eq!(sigma(-s), 0.0);
            assert_eq!(sigma_prime(s), 0.0);
            assert_eq!(sigma_prime(-s), 0.0);
            assert_eq!(sigma_second(s), 0.0);
            assert_eq!(sigma_second(-s), 0.0);
        }
        assert_eq!(ln_sigma_prime(-1e300), -1e300);
        assert_eq!(sigma(0.0), 0.5);
        assert_eq!(sigma_prime(0.0), 0.25);
        // Deep in the tails sigma keeps full relative precision: sigma(−700) = e^{−700}/(1+e^{−700}).
        let tail = sigma(-700.0);
        assert!((tail / f64::exp(-700.0) - 1.0).abs() < 1e-14);
        assert!((1.0 - sigma(30.0) - f64::exp(-30.0)).abs() < 1e-16);
    }
}
