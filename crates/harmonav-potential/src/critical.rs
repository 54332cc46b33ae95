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
//!
//! **Large worlds** (a point world with a multipole tree, `M ≥ far::FAR_MIN`; docs/maths.md
//! §15): the sums `Σ 1/(z − p_i)` and `Σ 1/(z − p_i)²` come from the tree (near points exact),
//! and the iteration starts from the first-order roots next to each point instead of a circle,
//!
//! ```text
//! F(z) = 0  ⇔  (1/k)/(z − p_j) = G_j(z),   G_j(z) = 1/(z − d) − (1/k) Σ_{i≠j} 1/(z − p_i),
//! z_j⁰ = p_j + 1/(k G_j(p_j))                                          (eq. census-start)
//! ```
//!
//! which needs a few sweeps where the circle needs about a hundred. The iteration is run from
//! distinct starts away from the points (a start that is not finite, farther than the world's
//! scale, or nearer another point than to its own is put back on the circle, and a root whose
//! step is singular is nudged off); the tests compare its roots with the direct census's. The
//! repulsion `Σ_{l≠j} 1/(z_j − z_l)` stays direct; each root is polished by Newton on the
//! direct `F`, so the roots carry the direct sums' rounding whatever the tree's tolerance.

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
        let start = circle(d, &p, scale);
        let roots = match self.far_field() {
            Some(far) => {
                let sums = |z: C, skip: Option<usize>| {
                    let (mut s1, mut s2) = (C::new(0.0, 0.0), C::new(0.0, 0.0));
                    let (f1, f2) = far.reciprocal_sums(z, |i| {
                        if Some(i) != skip {
                            let r = (z - p[i]).inv();
                            s1 += r;
                            s2 += r * r;
                        }
                    });
                    (s1 + f1, s2 + f2)
                };
                // A start nearer another point than to its own would sit on (or round onto)
                // that point, where every sum is singular: such a start goes on the circle.
                let clear = |j: usize, z: C| {
                    let mut clear = true;
                    far.reciprocal_sums(z, |i| {
                        clear &= i == j || (z - p[i]).norm() > 0.5 * (z - p[j]).norm();
                    });
                    clear
                };
                let others = |j: usize| sums(p[j], Some(j)).0;
                let start = first_order(d, &p, k, scale, start, others, clear);
                aberth(d, &p, k, scale, start, |z| sums(z, None))
            }
            None => aberth(d, &p, k, scale, start, |z| direct_sums(z, &p)),
        };
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

/// `(Σ 1/(z − p_i), Σ 1/(z − p_i)²)`, directly.
fn direct_sums(z: C, p: &[C]) -> (C, C) {
    let (mut s1, mut s2) = (C::new(0.0, 0.0), C::new(0.0, 0.0));
    for &pi in p {
        let r = (z - pi).inv();
        s1 += r;
        s2 += r * r;
    }
    (s1, s2)
}

/// `N'(z)/N(z)` from `N = F·(z − d)·P`, with `(s1, s2) = (Σ 1/(z − p_i), Σ 1/(z − p_i)²)`:
/// `F = 1/(z − d) − s1/k`, `F' = −1/(z − d)² + s2/k`, `N'/N = F'/F + 1/(z − d) + s1`.
fn log_derivative(z: C, d: C, k: f64, (s1, s2): (C, C)) -> C {
    let rd = (z - d).inv();
    let (f, df) = (rd - s1 / k, -rd * rd + s2 / k);
    df / f + rd + s1
}

fn length_scale(d: C, p: &[C]) -> f64 {
    let centre = p.iter().fold(d, |a, &b| a + b) / (p.len() as f64 + 1.0);
    p.iter()
        .map(|&q| (q - centre).norm())
        .fold((d - centre).norm(), f64::max)
        .max(f64::MIN_POSITIVE)
}

/// The starts on a circle enclosing the points, rotated off any symmetry axis.
fn circle(d: C, p: &[C], scale: f64) -> Vec<C> {
    let m = p.len();
    let centre = p.iter().fold(d, |a, &b| a + b) / (m as f64 + 1.0);
    (0..m)
        .map(|j| {
            let a = 0.4 + std::f64::consts::TAU * j as f64 / m as f64;
            centre + C::from_polar(1.3 * scale, a)
        })
        .collect()
}

/// Eq. census-start: `z_j⁰ = p_j + 1/(k G_j(p_j))` with `others(j) = Σ_{i≠j} 1/(p_j − p_i)`;
/// the circle's start where that is not finite, lies farther than `scale` from `p_j`, or is
/// not `clear(j, z)` (nearer another point than half its distance to `p_j`: two points
/// `δ` apart put each other's start `O(δ²k/L)` from the other point, exactly on it below
/// `δ ≈ √(ulp·L/k)`).
fn first_order(
    d: C,
    p: &[C],
    k: f64,
    scale: f64,
    circle: Vec<C>,
    others: impl Fn(usize) -> C,
    clear: impl Fn(usize, C) -> bool,
) -> Vec<C> {
    circle
        .into_iter()
        .enumerate()
        .map(|(j, fallback)| {
            let g = (p[j] - d).inv() - others(j) / k;
            let step = (g * k).inv();
            let z = p[j] + step;
            if z.re.is_finite()
                && z.im.is_finite()
                && step.norm() <= scale
                && z != p[j]
                && clear(j, z)
            {
                z
            } else {
                fallback
            }
        })
        .collect()
}

/// Aberth–Ehrlich iteration for the `M` roots of `N` from `start`, with `sums(z) = (Σ 1/(z −
/// p_i), Σ 1/(z − p_i)²)`.
fn aberth(d: C, p: &[C], k: f64, scale: f64, start: Vec<C>, sums: impl Fn(C) -> (C, C)) -> Vec<C> {
    let m = p.len();
    let mut z = start;
    let mut history: Vec<f64> = Vec::new();
    for _ in 0..2000 {
        let mut worst = 0.0f64;
        for j in 0..m {
            let ratio = log_derivative(z[j], d, k, sums(z[j]));
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
            } else {
                // On a point or another root (every sum singular there): step off it, by a
                // fixed small amount in a direction of its own, and let the iteration go on.
                let angle = 0.4 + j as f64;
                z[j] += C::from_polar(1e-8 * scale, angle);
                worst = f64::INFINITY;
            }
        }
        // Converged, or stalled at the rounding noise of `F`: the largest update no longer
        // halves over eight sweeps while below 1e-9 of the scale (a far-field root of a small
        // `k − M` settles near 1e-12 of its own distance and never meets 1e-15·scale; a
        // multiple root converges linearly, faster than that). Each simple root is polished
        // by Newton on the direct `F` afterwards (`cluster`).
        let stalled =
            history.len() >= 8 && worst <= 1e-9 * scale && worst > 0.5 * history[history.len() - 8];
        if worst <= 1e-15 * scale || stalled {
            break;
        }
        history.push(worst);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The large-world census (tree sums, first-order starts) finds the same saddles as the
    /// direct iteration from the circle, in a world just above `FAR_MIN` and a spiral.
    /// The spiral of `m` points with a point added `δ` from point 37 (a close pair).
    fn with_close_pair(m: usize, delta: f64) -> PointWorld {
        let spiral = crate::arrangements::golden_spiral(m);
        let mut points = spiral.obstacles().to_vec();
        points.push(points[37] + Vector2::new(delta, 0.3 * delta));
        PointWorld::new(spiral.destination(), points).unwrap()
    }

    #[test]
    fn the_tree_census_finds_the_direct_census_roots() {
        for world in [
            // k = M + 1 (the paper's): a far-field root that stalls at rounding noise.
            crate::arrangements::golden_spiral(crate::far::FAR_MIN + 72),
            crate::arrangements::golden_spiral(300)
                .with_k(450.0)
                .unwrap(),
            // Close pairs: first-order starts that would land on the other point.
            with_close_pair(200, 1e-9).with_k(1_000.0).unwrap(),
            with_close_pair(200, 1e-12).with_k(1_000.0).unwrap(),
            with_close_pair(200, 1e-4).with_k(1_000.0).unwrap(),
        ] {
            assert!(world.has_far_field());
            let fast = world.critical_points();
            let d = to_c(world.destination());
            let p: Vec<C> = world.obstacles().iter().map(|&v| to_c(v)).collect();
            let (k, scale) = (world.k(), length_scale(d, &p));
            let roots = aberth(d, &p, k, scale, circle(d, &p, scale), |z| {
                direct_sums(z, &p)
            });
            let direct = cluster(&world, d, &p, k, scale, &roots);
            assert_eq!(fast.len(), direct.len());
            assert_eq!(fast.len(), p.len(), "M simple saddles");
            for (a, b) in fast.iter().zip(&direct) {
                assert!(
                    (a.position - b.position).norm() <= 1e-9 * scale,
                    "{:?} against {:?}",
                    a.position,
                    b.position
                );
                assert_eq!(a.kind, CriticalKind::Saddle);
                assert!(a.eigenvalues.iter().all(|e| e.is_finite()));
                assert!(p.iter().all(|&q| q != C::new(a.position.x, a.position.y)));
            }
        }
    }
}
