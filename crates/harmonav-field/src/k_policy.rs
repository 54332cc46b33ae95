//! How `k` of `phi_k` is chosen from the known world (`docs/maths.md` §8).

use harmonav_transform::{NavTransform, Workspace};
use nalgebra::Vector2;

/// The rule that sets `k` of `phi_k` from the `n` known obstacles, at construction and at every
/// discovery. Every policy gives `k > n` (lemma `attactive`), the only condition theorem `isNF`
/// puts on `k`, so `Θ` is a navigation function under each of them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum KPolicy {
    /// `k = n + 1`, exactly the paper (its simulations and theorem `isNF`'s statement).
    Paper,
    /// `k = max(AUTO_FACTOR·(n + 1), LAYER_FACTOR·layer_ratio)` (the default).
    /// The first term keeps the obstacles' joint repulsion `n/k` below `1/AUTO_FACTOR` of the
    /// goal's attraction, whatever `n`, which removes the far-field valley that sends the
    /// paper's robot along the outer wall. The second keeps each point obstacle's repulsion
    /// layer (radius `≈ |x_d − P_i|/k` in the point world) clear of the outer band, so that in
    /// a narrow workspace the detour round an obstacle is not pressed against the wall
    /// ([`layer_ratio`]). Chosen by
    /// measurement (`docs/maths.md` §8, `docs/benchmarks.md`).
    #[default]
    Auto,
}

/// The factor of [`KPolicy::Auto`]: `k ≥ AUTO_FACTOR·(n + 1)`.
pub const AUTO_FACTOR: f64 = 6.0;

/// The layer factor of [`KPolicy::Auto`]: `k ≥ LAYER_FACTOR·`[`layer_ratio`] (`docs/maths.md`
/// §8 has the measurements).
pub const LAYER_FACTOR: f64 = 2.0;

/// How far the destination lies from the known obstacles in units of their room to the outer
/// band:
///
/// ```text
/// layer_ratio = max_i |x_d − P_i| / (d(P_i, ∂O_0) − ε_0)        (0 with no obstacle known)
/// ```
///
/// with `P_i` the centre of known obstacle `i` and `ε_0` the outer band's width. Near `P_i` the
/// repulsion `(2/k)/|h − P_i|` of `phi_k` outweighs the attraction `2/|h − x_d|` within
/// `|h − P_i| < |x_d − P_i|/k`, the detour a descent makes round the point. `Phi` is the
/// identity between the obstacle's band and the outer band, which lies within `ε_0` of the wall,
/// so `k ≥ layer_ratio` keeps that detour out of the outer band, where it would be compressed to
/// millimetres against the wall of a narrow workspace (`docs/maths.md` §8).
#[must_use]
pub fn layer_ratio(ws: &Workspace, transform: &NavTransform) -> f64 {
    Layer::new(ws, transform).ratio
}

/// [`layer_ratio`] with its terms kept, so that a discovery updates it without `M` distances
/// to the boundary: per known point `|x_d − P_i|` and `d(P_i, ∂O_0) = −signed_distance`, and
/// the ratio for the `ε_0` it was taken at. Every ratio is formed by the same expression
/// as [`layer_ratio`]'s and the maximum is exact, so the result is the same bits.
#[derive(Clone, Debug)]
pub(crate) struct Layer {
    /// `(|x_d − P_i|, d(P_i, ∂O_0))` per known point, slot order.
    terms: Vec<(f64, f64)>,
    /// `ε_0` of the ratio.
    eps0: f64,
    /// `max_i |x_d − P_i| / (d(P_i, ∂O_0) − ε_0)`, 0 with no point.
    pub(crate) ratio: f64,
}

impl Layer {
    /// The terms and the ratio of `transform`'s points in `ws`.
    pub(crate) fn new(ws: &Workspace, transform: &NavTransform) -> Self {
        let terms: Vec<(f64, f64)> = transform.points().map(|p| Self::term(ws, p)).collect();
        let eps0 = transform.outer_band().0;
        Self {
            ratio: Self::max_ratio(&terms, eps0),
            terms,
            eps0,
        }
    }

    /// `(|x_d − p|, −signed_distance(∂O_0, p))`.
    pub(crate) fn term(ws: &Workspace, p: Vector2<f64>) -> (f64, f64) {
        (
            (ws.destination() - p).norm(),
            -ws.boundary().signed_distance(p),
        )
    }

    fn ratio_of((goal, wall): (f64, f64), eps0: f64) -> f64 {
        goal / (wall - eps0)
    }

    fn max_ratio(terms: &[(f64, f64)], eps0: f64) -> f64 {
        terms
            .iter()
            .map(|&t| Self::ratio_of(t, eps0))
            .fold(0.0, f64::max)
    }

    /// The ratio with the point of `term` added and `ε_0 = eps0`: one new ratio if `ε_0` is
    /// unchanged, else the maximum over the kept terms again (`M` divisions, no distance).
    pub(crate) fn ratio_with(&self, term: (f64, f64), eps0: f64) -> f64 {
        let old = if eps0 == self.eps0 {
            self.ratio
        } else {
            Self::max_ratio(&self.terms, eps0)
        };
        old.max(Self::ratio_of(term, eps0))
    }

    /// Adds the point of `term`; `ratio` from [`Self::ratio_with`] for the same arguments.
    pub(crate) fn push(&mut self, term: (f64, f64), eps0: f64, ratio: f64) {
        self.terms.push(term);
        self.eps0 = eps0;
        self.ratio = ratio;
    }
}

impl KPolicy {
    /// `k` for `n` known obstacles whose [`layer_ratio`] is `layer`; always `> n`. A `layer`
    /// that is not finite is ignored (the `n` term alone).
    #[must_use]
    pub fn k_for(self, n: usize, layer: f64) -> f64 {
        let n1 = n as f64 + 1.0;
        match self {
            Self::Paper => n1,
            Self::Auto if layer.is_finite() => (AUTO_FACTOR * n1).max(LAYER_FACTOR * layer),
            Self::Auto => AUTO_FACTOR * n1,
        }
    }

    /// `k` for `n` known obstacles before geometry: [`Self::k_for`]`(n, 0)`, the least `k`
    /// the policy gives (`n + 1` or `AUTO_FACTOR·(n + 1)`).
    #[must_use]
    pub fn k(self, n: usize) -> f64 {
        self.k_for(n, 0.0)
    }
}

harmonav_potential::named_policy!(
    KPolicy,
    UnknownKPolicy,
    "k policy",
    [Paper => "paper", Auto => "auto"]
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_policy_keeps_k_above_n_and_paper_is_n_plus_one() {
        for n in 0..200 {
            for p in KPolicy::ALL {
                for layer in [0.0, 1.0, 1e6, f64::NAN, f64::INFINITY] {
                    assert!(p.k_for(n, layer) > n as f64, "{p} at n = {n}");
                    assert!(p.k_for(n, layer).is_finite());
                }
                assert_eq!(p.k(n), p.k_for(n, 0.0));
            }
            assert_eq!(KPolicy::Paper.k_for(n, 1e6), n as f64 + 1.0);
            assert_eq!(KPolicy::Auto.k_for(n, 1e6), 2e6);
        }
    }

    #[test]
    fn names_round_trip_and_unknown_names_are_errors() {
        for p in KPolicy::ALL {
            assert_eq!(p.as_str().parse::<KPolicy>(), Ok(p));
        }
        let e = "n+1".parse::<KPolicy>().unwrap_err();
        assert!(e.to_string().contains("\"n+1\""), "{e}");
        assert_eq!(KPolicy::default(), KPolicy::Auto);
    }
}
