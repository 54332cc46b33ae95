//! Measurements of the paper's properties of `phi_k` on one point world, shared by this crate's
//! tests and `cargo xtask verify`.
//!
//! Each function measures one property and returns the figure it measured (or the first place
//! where the property fails); the caller chooses the worlds, the points and the tolerance. The
//! tests assert on proptest-generated worlds, `verify` reports the worst figure over seeded ones,
//! and both measure the same thing the same way.

use nalgebra::{Matrix2, Vector2};

use crate::critical::CriticalKind;
use crate::error::Singularity;
use crate::world::PointWorld;

pub use crate::fd::{FD_STEP, fd_gradient, fd_jacobian};

/// The analytic derivatives at one point against central differences ([`FD_STEP`]), each
/// error divided by the scale of its terms ([`PointWorld::grad_term_scale`],
/// [`PointWorld::hess_term_scale`]) so that one tolerance serves every distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DerivativeErrors {
    /// `|∇phi_k − FD(phi_k)|` (eq. `gradient`).
    pub grad_phi_k: f64,
    /// `|∇varphi − FD(varphi)|`.
    pub grad_varphi: f64,
    /// `|H(phi_k) − FD(∇phi_k)|` (eq. `hessquadratic`, Frobenius norm).
    pub hess_phi_k: f64,
    /// `|H(varphi) − FD(∇varphi)|`.
    pub hess_varphi: f64,
    /// `|H − Hᵀ|` of `H(phi_k)`.
    pub asymmetry: f64,
    /// `|tr H(phi_k)|`: `phi_k` is harmonic (lemma `locminfree`), so this is rounding only.
    pub trace: f64,
}

impl DerivativeErrors {
    /// The largest of the six figures.
    pub fn worst(&self) -> f64 {
        [
            self.grad_phi_k,
            self.grad_varphi,
            self.hess_phi_k,
            self.hess_varphi,
            self.asymmetry,
            self.trace,
        ]
        .into_iter()
        .fold(0.0, f64::max)
    }
}

/// Measures [`DerivativeErrors`] at `h`, which must be a regular point at least a few
/// [`FD_STEP`]s from every singular point (or the differences straddle a singularity).
pub fn derivative_errors(w: &PointWorld, h: Vector2<f64>) -> Result<DerivativeErrors, Singularity> {
    let (gs, hs) = (w.grad_term_scale(h), w.hess_term_scale(h));
    let hess = w.hess_phi_k(h)?;
    let grad_phi = |x| {
        w.grad_phi_k(x)
            .unwrap_or_else(|_| Vector2::repeat(f64::NAN))
    };
    let grad_var = |x| {
        w.grad_varphi(x)
            .unwrap_or_else(|_| Vector2::repeat(f64::NAN))
    };
    Ok(DerivativeErrors {
        grad_phi_k: (w.grad_phi_k(h)? - fd_gradient(|x| w.phi_k(x), h, FD_STEP)).norm() / gs,
        grad_varphi: (w.grad_varphi(h)? - fd_gradient(|x| w.varphi(x), h, FD_STEP)).norm() / gs,
        hess_phi_k: (hess - fd_jacobian(grad_phi, h, FD_STEP)).norm() / hs,
        hess_varphi: (w.hess_varphi(h)? - fd_jacobian(grad_var, h, FD_STEP)).norm() / hs,
        asymmetry: (hess - hess.transpose()).norm() / hs,
        trace: hess.trace().abs() / hs,
    })
}

/// Where [`far_field`] found `phi_k` not increasing outward (or not finite).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NotIncreasing {
    /// `|h|` where it happened.
    pub radius: f64,
    /// `phi_k` there.
    pub phi: f64,
}

/// Lemma `attactive` along the ray `h = r·u` for `r = 10^e`, `e` in `exponents` (ascending):
/// `phi_k` increases outward, and `phi_k(r u) / (2(1 − M/k) ln r) − 1` is the returned worst
/// relative deviation over `r ≥ 1e12` (below that the `O(|P_i|/r)` terms are not negligible).
pub fn far_field(w: &PointWorld, u: Vector2<f64>, exponents: &[i32]) -> Result<f64, NotIncreasing> {
    let slope = 2.0 * (1.0 - w.obstacles().len() as f64 / w.k());
    let (mut last, mut worst) = (f64::NEG_INFINITY, 0.0f64);
    for &e in exponents {
        let radius = 10f64.powi(e);
        let phi = w.phi_k(radius * u);
        if !phi.is_finite() || phi <= last {
            return Err(NotIncreasing { radius, phi });
        }
        last = phi;
        if radius >= 1e12 {
            worst = worst.max((phi / (slope * radius.ln()) - 1.0).abs());
        }
    }
    Ok(worst)
}

/// Lemma `locminfree` on a grid of `(n + 1)²` nodes over `[−extent, extent]²` (offset by
/// 1e-7 to stay off symmetric points): the first node, away from the destination, that is
/// strictly below its eight neighbours, or `None`.
pub fn grid_local_minimum(w: &PointWorld, n: usize, extent: f64) -> Option<Vector2<f64>> {
    let cell = 2.0 * extent / n as f64;
    let node = |a: usize, b: usize| {
        Vector2::new(
            -extent + cell * a as f64 + 1e-7,
            -extent + cell * b as f64 + 3e-7,
        )
    };
    let values: Vec<f64> = (0..=n)
        .flat_map(|a| (0..=n).map(move |b| (a, b)))
        .map(|(a, b)| w.phi_k(node(a, b)))
        .collect();
    let at = |a: usize, b: usize| values[a * (n + 1) + b];
    for a in 1..n {
        for b in 1..n {
            if (node(a, b) - w.destination()).norm() < 2.0 * cell {
                continue;
            }
            let c = at(a, b);
            let minimum = (0..3)
                .all(|da| (0..3).all(|db| (da, db) == (1, 1) || at(a + da - 1, b + db - 1) > c));
            if minimum {
                return Some(node(a, b));
            }
        }
    }
    None
}

/// What [`census`] measured on a world whose census is right.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Census {
    /// Critical points found (a degenerate one counts once).
    pub points: usize,
    /// Of which degenerate (proposition `Morse`).
    pub degenerate: usize,
    /// The largest `|∇phi_k|` at a reported point, relative to the term scale.
    pub worst_gradient: f64,
}

/// How a census is wrong.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CensusError {
    /// The multiplicities do not sum to `M` (lemma `saddlep` with Poincaré–Hopf).
    Count {
        /// Σ multiplicity.
        found: usize,
        /// `M`.
        expected: usize,
    },
    /// A point reported as a non-degenerate saddle has `det H ≥ 0`.
    NotASaddle {
        /// The point.
        at: Vector2<f64>,
        /// `det H(phi_k)` there.
        det: f64,
    },
    /// A reported point is singular.
    Singular {
        /// The point.
        at: Vector2<f64>,
    },
}

/// Lemma `saddlep` and Poincaré–Hopf: `phi_k` has exactly `M` critical points counted with
/// multiplicity, every one a saddle. Measures the census of [`PointWorld::critical_points`].
pub fn census(w: &PointWorld) -> Result<Census, CensusError> {
    let points = w.critical_points();
    let found: usize = points.iter().map(|c| c.multiplicity).sum();
    let expected = w.obstacles().len();
    if found != expected {
        return Err(CensusError::Count { found, expected });
    }
    let mut out = Census {
        points: points.len(),
        degenerate: 0,
        worst_gradient: 0.0,
    };
    for c in &points {
        let at = c.position;
        let singular = |_| CensusError::Singular { at };
        let g = w.grad_phi_k(at).map_err(singular)?;
        out.worst_gradient = out.worst_gradient.max(g.norm() / w.grad_term_scale(at));
        match c.kind {
            CriticalKind::Degenerate => out.degenerate += 1,
            CriticalKind::Saddle => {
                let det = w.hess_phi_k(at).map_err(singular)?.determinant();
                if det >= 0.0 {
                    return Err(CensusError::NotASaddle { at, det });
                }
            }
        }
    }
    Ok(out)
}

/// `H(varphi)(P_d)` from second differences of `varphi` values (step `step`), next to the two
/// candidate closed forms `2/Π|P_d − P_i|^{e/k}` for `e = 2` (`docs/maths.md` §2, used by
/// corollary `critdamp`) and `e = 4` (eq. `destphik2` as printed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DestinationHessian {
    /// The second differences `[[h_xx, h_xy], [h_xy, h_yy]]`.
    pub fd: Matrix2<f64>,
    /// `2/Π|P_d − P_i|^{2/k}`.
    pub two_over_k: f64,
    /// `2/Π|P_d − P_i|^{4/k}`.
    pub four_over_k: f64,
}

/// Measures [`DestinationHessian`] (second differences need `step ≈ ε^{1/4}`, e.g. 1e-4).
pub fn destination_hessian(w: &PointWorld, step: f64) -> DestinationHessian {
    let d = w.destination();
    let ln_prod: f64 = w.obstacles().iter().map(|p| (d - p).norm().ln()).sum();
    let f = |x: Vector2<f64>| w.varphi(x);
    let (ex, ey) = (Vector2::new(step, 0.0), Vector2::new(0.0, step));
    let hxx = (f(d + ex) - 2.0 * f(d) + f(d - ex)) / (step * step);
    let hyy = (f(d + ey) - 2.0 * f(d) + f(d - ey)) / (step * step);
    let hxy =
        (f(d + ex + ey) - f(d + ex - ey) - f(d - ex + ey) + f(d - ex - ey)) / (4.0 * step * step);
    DestinationHessian {
        fd: Matrix2::new(hxx, hxy, hxy, hyy),
        two_over_k: 2.0 * (-2.0 * ln_prod / w.k()).exp(),
        four_over_k: 2.0 * (-4.0 * ln_prod / w.k()).exp(),
    }
}

/// Numerics: at `s·u` and at every point `P + s·u` for `s = 10^e`, `e` in `exponents`,
/// `phi_k`, `varphi ∈ [0, 1]`, both gradients and the descent direction are finite, and the
/// limits are exact (`varphi(P_d) = 0`, `varphi(P_i) = 1`). Offsets below the resolution of a
/// point's coordinates (where `P + s·u` is singular) are skipped. Returns the number of points
/// evaluated, or the first point with a non-finite result.
pub fn extreme_scales(
    w: &PointWorld,
    u: Vector2<f64>,
    exponents: impl IntoIterator<Item = i32>,
) -> Result<usize, Vector2<f64>> {
    if w.varphi(w.destination()) != 0.0 {
        return Err(w.destination());
    }
    if let Some(&p) = w.obstacles().iter().find(|&&p| w.varphi(p) != 1.0) {
        return Err(p);
    }
    let finite =
        |g: Result<Vector2<f64>, Singularity>| g.is_ok_and(|g| g.iter().all(|x| x.is_finite()));
    let mut evaluated = 0;
    for e in exponents {
        let s = 10f64.powi(e);
        let bases = w.obstacles().iter().copied().chain([w.destination()]);
        for h in std::iter::once(s * u).chain(bases.map(|p| p + s * u)) {
            if w.singularity(h).is_some() {
                continue;
            }
            let ok = w.phi_k(h).is_finite()
                && (0.0..=1.0).contains(&w.varphi(h))
                && finite(w.grad_phi_k(h))
                && finite(w.grad_varphi(h))
                && w.descent_direction(h).is_some();
            if !ok {
                return Err(h);
            }
            evaluated += 1;
        }
    }
    Ok(evaluated)
}
