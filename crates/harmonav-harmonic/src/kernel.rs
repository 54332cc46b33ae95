//! The closed-form single-layer element integral and its gradient.
//!
//! For a straight element of half-length `a`, in its local frame (`xo` along it from its
//! midpoint, `yo` along its left normal):
//!
//! ```text
//! W(xo, yo) = ∫₋ₐᵃ ln((xo − t)² + yo²) dt
//!           = (xo + a)·ln r₊² − (xo − a)·ln r₋² − 4a + 2·yo·θ,
//! r₊² = (xo + a)² + yo²,   r₋² = (xo − a)² + yo²,
//! θ   = atan2(2a·yo, (xo − a)(xo + a) + yo²)          (the angle the element subtends),
//! ∂W/∂xo = ln(r₊² / r₋²),   ∂W/∂yo = 2θ.
//! ```
//!
//! Guards, next to the equation they protect:
//! - `θ` comes from the two-argument `atan2`, so it is right in `(−π, π)` inside the circle that
//!   has the element as diameter (a one-argument arctangent loses π there, half an element from
//!   the boundary); `(xo − a)(xo + a)` instead of `xo² − a²` keeps the denominator's digits;
//! - `0·ln 0 := 0` at an end point (`r± = 0`), where `W` is continuous; the gradient's
//!   `ln r±²` is infinite there, which [`element`] reports as `singular`.

/// `W`, `∂W/∂xo`, `∂W/∂yo` of one element at local coordinates `(xo, yo)`; `singular` when the
/// point is an end point of the element (the gradient is logarithmically infinite there).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Local {
    pub w: f64,
    pub gx: f64,
    pub gy: f64,
    pub singular: bool,
}

/// The closed form of the module docs: [`interval`] on `[−a, a]` (bit for bit the same
/// arithmetic: `xo − (−a) = xo + a`, `(a − (−a))·yo = 2a·yo`).
#[inline]
pub(crate) fn element(xo: f64, yo: f64, a: f64) -> Local {
    let (l, at_start, at_end) = interval(xo, yo, -a, a);
    Local {
        singular: at_start || at_end,
        ..l
    }
}

/// The single layer of the part `[t₀, t₁]` of an element (local abscissae, `t₀ < t₁`), the same
/// closed form with its own ends:
///
/// ```text
/// W = (xo − t₀)·ln r₀² − (xo − t₁)·ln r₁² − 2(t₁ − t₀) + 2·yo·θ,
/// r_i² = (xo − t_i)² + yo²,   θ = atan2((t₁ − t₀)·yo, (xo − t₀)(xo − t₁) + yo²),
/// ∂W/∂xo = ln(r₀² / r₁²),   ∂W/∂yo = 2θ.
/// ```
///
/// The far-field evaluation (`crate::map`) adds it over the pieces of the elements the multipole
/// tree cuts at its leaf lines. Returns the local values (`singular` unset) and whether the point
/// is the start, resp. the end, of `[t₀, t₁]` (`r_i = 0`, where `0·ln 0 := 0`): at a cut inside
/// an element the two pieces' `ln r²` are `+ln 0` and `−ln 0`, and dropping both is their exact
/// sum, so only an element's own end points are singular.
#[inline]
pub(crate) fn interval(xo: f64, yo: f64, t0: f64, t1: f64) -> (Local, bool, bool) {
    let p = xo - t0;
    let m = xo - t1;
    let y2 = yo * yo;
    let rp = p * p + y2;
    let rm = m * m + y2;
    // 0·ln 0 := 0: the term (xo − t_i)·ln r_i² vanishes at the end point itself.
    let lp = if rp > 0.0 { rp.ln() } else { 0.0 };
    let lm = if rm > 0.0 { rm.ln() } else { 0.0 };
    let length = t1 - t0;
    let theta = (length * yo).atan2(p * m + y2);
    let local = Local {
        w: p * lp - m * lm - 2.0 * length + 2.0 * yo * theta,
        gx: lp - lm,
        gy: 2.0 * theta,
        singular: false,
    };
    (local, rp == 0.0, rm == 0.0)
}

/// One element in normalised coordinates with its two densities.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Panel {
    pub(crate) centre: [f64; 2],
    pub(crate) tangent: [f64; 2],
    pub(crate) half: f64,
    pub(crate) ku: f64,
    pub(crate) kv: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Gauss–Legendre on many sub-intervals: the reference integral.
    fn quadrature(xo: f64, yo: f64, a: f64) -> f64 {
        let nodes = [
            (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
            (-0.538_469_310_105_683, 0.478_628_670_499_366_5),
            (0.0, 0.568_888_888_888_888_9),
            (0.538_469_310_105_683, 0.478_628_670_499_366_5),
            (0.906_179_845_938_664, 0.236_926_885_056_189_1),
        ];
        let parts = 2000;
        let w = 2.0 * a / parts as f64;
        let mut s = 0.0;
        for k in 0..parts {
            let c = -a + (k as f64 + 0.5) * w;
            for (x, g) in nodes {
                let t = c + 0.5 * w * x;
                s += 0.5 * w * g * ((xo - t).powi(2) + yo * yo).ln();
            }
        }
        s
    }

    #[test]
    fn closed_form_matches_quadrature_and_its_gradient_matches_differences() {
        let a = 0.3;
        for &(xo, yo) in &[
            (0.0, 0.5),
            (0.1, 0.01),
            (-0.2, -0.02),
            (1.0, 0.0),
            (0.7, -0.9),
            (0.0, 0.001),
        ] {
            let l = element(xo, yo, a);
            let q = quadrature(xo, yo, a);
            assert!((l.w - q).abs() < 1e-9, "{xo} {yo}: {} vs {q}", l.w);
            let e = 1e-6;
            let gx = (element(xo + e, yo, a).w - element(xo - e, yo, a).w) / (2.0 * e);
            let gy = (element(xo, yo + e, a).w - element(xo, yo - e, a).w) / (2.0 * e);
            assert!(
                (l.gx - gx).abs() < 1e-6 && (l.gy - gy).abs() < 1e-6,
                "{xo} {yo}"
            );
        }
    }

    #[test]
    fn the_angle_is_right_inside_the_diameter_circle() {
        // Just above the midpoint the element subtends almost π: 2θ → 2π (the jump of the
        // single layer's normal derivative), not 0 as a one-argument arctangent gives.
        let l = element(0.0, 1e-9, 0.5);
        assert!((l.gy - 2.0 * std::f64::consts::PI).abs() < 1e-8);
        let below = element(0.0, -1e-9, 0.5);
        assert!((below.gy + 2.0 * std::f64::consts::PI).abs() < 1e-8);
    }

    #[test]
    fn pieces_add_up_to_the_element_also_at_a_cut() {
        let a = 0.4;
        for &(xo, yo) in &[
            (0.1, 0.2),
            (-0.7, 0.05),
            (0.13, 0.0),
            (0.13, 1e-9),
            (2.0, -1.0),
        ] {
            let whole = element(xo, yo, a);
            let (l, _, _) = interval(xo, yo, -a, 0.13);
            let (r, _, _) = interval(xo, yo, 0.13, a);
            let scale = whole.w.abs().max(1.0);
            assert!((l.w + r.w - whole.w).abs() < 1e-14 * scale, "{xo} {yo}");
            assert!((l.gx + r.gx - whole.gx).abs() < 1e-12, "{xo} {yo}");
            if (xo, yo) != (0.13, 0.0) {
                // On the element at the cut itself the normal derivative is the jump (one-sided
                // for the whole element, 0 for the two pieces): only off it must they agree.
                assert!((l.gy + r.gy - whole.gy).abs() < 1e-12, "{xo} {yo}");
            }
        }
        // Bit for bit the element on [−a, a].
        let (l, s, e) = interval(0.3, -0.2, -a, a);
        assert_eq!(
            Local {
                singular: s || e,
                ..l
            },
            element(0.3, -0.2, a)
        );
    }

    #[test]
    fn end_points_are_finite_in_value_and_flagged_singular() {
        let l = element(0.5, 0.0, 0.5);
        assert!(l.w.is_finite() && l.singular);
        // On the element: W = (a + x)ln(a + x)² + (a − x)ln(a − x)² − 4a, self term at x = 0.
        let s = element(0.0, 0.0, 0.5);
        assert!((s.w - (2.0 * 0.5 * (0.25_f64).ln() - 2.0)).abs() < 1e-15);
        assert!(!s.singular);
    }
}
