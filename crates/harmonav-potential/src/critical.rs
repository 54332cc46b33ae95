//! The critical points of `phi_k`, found exactly as polynomial roots (a census).
//!
//! In complex notation (`z = x + iy`), `∇phi_k = 2·conj(F)` with
//!
//! ```text
//! F(z) = 1/(z − d) − (1/k) Σ_i 1/(z − p_i) = N(z) / ((z − d) P(z)),
//! P(z) = Π_i (z − p_i),     N(z) = P(z) − (1/k)(z − d) P'(z).
//! ```
//!
//! `N` has degree `M` and leading coefficient `1 − M/k ≠ 0` (because `k > M`), and `N` does
//! not vanish at `d` or at any `p_i`: `phi_k` has exactly `M` critical points counted with
//! multiplicity. The Hessian there is that of the real part of an analytic function, with
//! eigenvalues `±2|F'(z)|`: every non-degenerate critical point is a saddle (lemma `saddlep`);
//! a root of multiplicity `m ≥ 2` is a degenerate saddle of index `−m` (both eigenvalues 0).
//!
//! The roots are found with the Aberth–Ehrlich iteration, evaluating the logarithmic
//! derivative `N'/N = F'/F + 1/(z − d) + Σ 1/(z − p_i)` from the points directly, never
//! through the (ill-conditioned) monomial coefficients.

use nalgebra::{Complex, Vector2};

use crate::world::PointWorld;

type C = Complex<f64>;

/// The nature of a critical point of `phi_k`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CriticalKind {
    /// Non-degenerate: Hessian eigenvalues `−λ, +λ` with `λ > 0` (lemma `saddlep`).
    Saddle,
    /// Degenerate (proposition `Morse`): both eigenvalues 0 relative to the local scale; a
    /// saddle of index `−multiplicity`.
    Degenerate,
}

/// One critical point of `phi_k` in the point world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CriticalPoint {
    /// Position `h` with `∇phi_k(h) = 0`.
    pub position: Vector2<f64>,
    /// Eigenvalues of `H(phi_k)` at `position`, ascending (`−2|F'|, +2|F'|`).
    pub eigenvalues: [f64; 2],
    /// Saddle or degenerate saddle.
    pub kind: CriticalKind,
    /// Multiplicity as a root of `N` (1 for a non-degenerate saddle).
    pub multiplicity: usize,
}

/// Relative tolerance below which a Hessian eigenvalue counts as zero (degenerate point).
/// A double root is only located to ≈ √ε ≈ 1e-8 relative accuracy, where `|F'|` is of that
/// size relative to the scale `|F|`-terms; 1e-5 separates the two cases with margin.
pub const DEGENERATE_TOL: f64 = 1e-5;

impl PointWorld {
    /// All critical points of `phi_k` (eq. `gradient` = 0), each with its Hessian eigenvalues,
    /// kind and multiplicity; the multiplicities sum to `M` (the census of lemma `saddlep` and
    /// proposition `Morse`). Deterministic; sorted by `x`, then `y`.
    pub fn critical_points(&self) -> Vec<CriticalPoint> {
        let m = self.obstacles().len();
        if m == 0 {
            return Vec::new();
        }
        let d = to_c(self.destination());
        let p: Vec<C> = self.obstacles().iter().map(|&v| to_c(v)).collect();
        let k = self.k();
        let scale = length_scale(d, &p);
        let roots = aberth(d, &p, k, scale);
        cluster(self, d, &p, k, scale, &roots)
    }
}

fn to_c(v: Vector2<f64>) -> C {
    C::new(v.x, v.y)
}

/// `F(z)` and `F'(z)`.
fn f_and_df(z: C, d: C, p: &[C], k: f64) -> (C, C) {
    let rd = (z - d).inv();
    let (mut s1, mut s2) = (C::new(0.0, 0.0), C::new(0.0, 0.0));
    for &pi in p {
        let r = (z - pi).inv();
        s1 += r;
        s2 += r * r;
    }
    (rd - s1 / k, -rd * rd + s2 / k)
}

/// `N'(z)/N(z)` from `N = F·(z − d)·P`.
fn log_derivative(z: C, d: C, p: &[C], k: f64) -> C {
    let (f, df) = f_and_df(z, d, p, k);
    let mut s = (z - d).inv();
    for &pi in p {
        s += (z - pi).inv();
    }
    df / f + s
}

fn length_scale(d: C, p: &[C]) -> f64 {
    let centre = p.iter().fold(d, |a, &b| a + b) / (p.len() as f64 + 1.0);
    p.iter()
        .map(|&q| (q - centre).norm())
        .fold((d - centre).norm(), f64::max)
        .max(f64::MIN_POSITIVE)
}

/// Aberth–Ehrlich iteration for the `M` roots of `N`.
fn aberth(d: C, p: &[C], k: f64, scale: f64) -> Vec<C> {
    let m = p.len();
    let centre = p.iter().fold(d, |a, &b| a + b) / (m as f64 + 1.0);
    // Start on a circle enclosing the points, rotated off any symmetry axis.
    let mut z: Vec<C> = (0..m)
        .map(|j| {
            let a = 0.4 + std::f64::consts::TAU * j as f64 / m as f64;
            centre + C::from_polar(1.3 * scale, a)
        })
        .collect();
    for _ in 0..2000 {
        let mut worst = 0.0f64;
        for j in 0..m {
            let ratio = log_derivative(z[j], d, p, k);
            let mut repulse = C::new(0.0, 0.0);
            for (l, &zl) in z.iter().enumerate() {
                if l != j {
                    repulse += (z[j] - zl).inv();
                }
            }
            let w = (ratio - repulse).inv();
            if w.re.is_finite() && w.im.is_finite() {
                z[j] -= w;
                worst = worst.max(w.norm());
            }
        }
        if worst <= 1e-15 * scale {
            break;
        }
    }
    z
}

/// Groups roots that coincide (a multiple root shows up as a tight cluster), polishes each
/// group and classifies it by its Hessian eigenvalues.
fn cluster(
    world: &PointWorld,
    d: C,
    p: &[C],
    k: f64,
    scale: f64,
    roots: &[C],
) -> Vec<CriticalPoint> {
    // Aberth locates a root of multiplicity m only to ≈ ε^{1/m}·scale (6e-6 for m = 3), as m
    // nearby approximations. Merge approximations closer than 1e-4·scale if each of them is
    // itself nearly degenerate (|F'| tiny): two distinct simple roots that close would each
    // have a clearly non-zero |F'|.
    let tol = 1e-4 * scale;
    let nearly_degenerate = |z: C| {
        let (_, df) = f_and_df(z, d, p, k);
        2.0 * df.norm() <= 1e-3 * world.hess_term_scale(Vector2::new(z.re, z.im))
    };
    let mut used = vec![false; roots.len()];
    let mut out = Vec::new();
    for i in 0..roots.len() {
        if used[i] {
            continue;
        }
        let mut members = vec![roots[i]];
        used[i] = true;
        if nearly_degenerate(roots[i]) {
            for j in i + 1..roots.len() {
                if !used[j] && (roots[j] - roots[i]).norm() <= tol && nearly_degenerate(roots[j]) {
                    used[j] = true;
                    members.push(roots[j]);
                }
            }
        }
        let multiplicity = members.len();
        // The mean of the m approximations of an m-fold root is accurate to ≈ ε·scale.
        let mut z = members.iter().sum::<C>() / multiplicity as f64;
        if multiplicity == 1 {
            // Newton on F for the last digits of a simple root. An m-fold root cannot be
            // polished: within ε^{1/m}·scale of it F is rounding noise, so the cluster mean
            // (accurate to about that) is kept.
            for _ in 0..3 {
                let (f, df) = f_and_df(z, d, p, k);
                let step = f / df;
                if step.re.is_finite() && step.im.is_finite() && step.norm() <= tol {
                    z -= step;
                }
            }
        }
        let (_, df) = f_and_df(z, d, p, k);
        let lambda = 2.0 * df.norm();
        let position = Vector2::new(z.re, z.im);
        let local = world.hess_term_scale(Vector2::new(z.re, z.im));
        let kind = if lambda <= DEGENERATE_TOL * local || multiplicity > 1 {
            CriticalKind::Degenerate
        } else {
            CriticalKind::Saddle
        };
        out.push(CriticalPoint {
            position,
            eigenvalues: [-lambda, lambda],
            kind,
            multiplicity,
        });
    }
    out.sort_by(|a, b| {
        a.position
            .x
            .total_cmp(&b.position.x)
            .then(a.position.y.total_cmp(&b.position.y))
    });
    out
}
