//! Guarantee checks of `harmonav-potential` (issue: potential core).

use harmonav_potential::{CriticalKind, Matrix2, PointWorld, Vector2, arrangements, checks};

use super::{Check, Outcome, outcome};
use crate::rng::{PointWorlds, Rng, clearance};

pub fn checks() -> Vec<Check> {
    vec![
        Check::new(
            "potential.derivatives-match-fd-and-are-harmonic",
            derivatives,
        ),
        Check::new("potential.attractive-iff-k-above-m", attractive),
        Check::new("potential.no-local-minimum-on-grid", no_local_minimum),
        Check::new("potential.critical-points-are-m-saddles", census),
        Check::new(
            "potential.destination-hessian-exponent",
            destination_hessian,
        ),
        Check::new("potential.non-morse-arrangement-degenerate", non_morse),
        Check::new("potential.extreme-scales-finite", extreme_scales),
    ]
}

fn hess_scale(w: &PointWorld, h: Vector2<f64>) -> f64 {
    w.hess_term_scale(h)
}

/// Samples `(world, h)` pairs with `h` at least 0.05 from every point.
fn samples(seed: u64, worlds: usize, per_world: usize) -> Vec<(PointWorld, Vec<Vector2<f64>>)> {
    let mut rng = Rng::new(seed);
    (0..worlds)
        .map(|i| {
            let w = rng.world(1 + i % 10);
            let mut hs = Vec::with_capacity(per_world);
            while hs.len() < per_world {
                let h = rng.point(6.0);
                if clearance(&w, h) > 0.05 {
                    hs.push(h);
                }
            }
            (w, hs)
        })
        .collect()
}

/// Eq. (gradient) and eq. (hessquadratic) against central differences, for phi_k and varphi;
/// tr H = 0 (lemma locminfree).
fn derivatives() -> Outcome {
    let (mut grad, mut hess, mut trace, mut n) = (0.0f64, 0.0f64, 0.0f64, 0);
    for (w, hs) in samples(1, 200, 100) {
        for h in hs {
            let e = checks::derivative_errors(&w, h).map_err(|e| format!("{h:?}: {e}"))?;
            grad = grad.max(e.grad_phi_k.max(e.grad_varphi));
            hess = hess.max(e.hess_phi_k.max(e.hess_varphi));
            trace = trace.max(e.trace.max(e.asymmetry));
            n += 1;
        }
    }
    outcome(
        grad < 1e-6 && hess < 1e-6 && trace < 1e-13,
        format!(
            "worst error (relative to the term scale) over {n} points in 200 worlds: gradient \
             {:.1e}, Hessian {:.1e}, |tr H| and asymmetry {:.1e}",
            grad, hess, trace
        ),
    )
}

/// Lemma attactive: phi_k → +∞ like 2(1 − M/k) ln|h| iff k > M; k ≤ M is rejected.
fn attractive() -> Outcome {
    let mut rng = Rng::new(3);
    let mut worst = 0.0f64;
    for i in 0..500 {
        let w = rng.world(1 + i % 10);
        let m = w.obstacles().len();
        if w.clone().with_k(m as f64).is_ok() {
            return Err(format!("k = M = {m} was accepted"));
        }
        let w = w
            .with_k(m as f64 + rng.uniform(0.05, 3.0))
            .map_err(|e| e.to_string())?;
        let a = rng.uniform(0.0, std::f64::consts::TAU);
        let u = Vector2::new(a.cos(), a.sin());
        let deviation = checks::far_field(&w, u, &[3, 12, 100, 300]).map_err(|e| {
            format!(
                "phi_k not increasing at |h| = {:.0e} (k = {})",
                e.radius,
                w.k()
            )
        })?;
        worst = worst.max(deviation);
    }
    outcome(
        worst < 1e-9,
        format!(
            "500 worlds: k ≤ M rejected; phi_k/(2(1−M/k) ln|h|) − 1 ≤ {worst:.1e} for |h| ≥ 1e12; increasing from 1e3"
        ),
    )
}

/// Lemma locminfree on dense samples: no grid node is strictly below its eight neighbours,
/// except next to the destination.
fn no_local_minimum() -> Outcome {
    let mut rng = Rng::new(4);
    let n = 300;
    for i in 0..20 {
        let w = rng.world(1 + i % 10);
        if let Some(x) = checks::grid_local_minimum(&w, n, 6.0) {
            return Err(format!("world {i}: local minimum at {x:?}"));
        }
    }
    outcome(
        true,
        format!("20 worlds × {} grid nodes: none", (n - 1) * (n - 1)),
    )
}

/// Lemma saddlep + Poincaré–Hopf: exactly M critical points (with multiplicity), all saddles.
fn census() -> Outcome {
    let mut rng = Rng::new(5);
    let (mut points, mut degenerate, mut worst) = (0usize, 0usize, 0.0f64);
    for i in 0..1000 {
        let w = rng.world(1 + i % 20);
        let c = checks::census(&w).map_err(|e| format!("world {i}: {e:?}"))?;
        points += c.points;
        degenerate += c.degenerate;
        worst = worst.max(c.worst_gradient);
    }
    outcome(
        worst < 1e-7,
        format!(
            "1000 worlds (M ≤ 20): {points} critical points = Σ M, all saddles ({degenerate} degenerate), worst |∇phi_k| {worst:.1e}"
        ),
    )
}

/// Eq. (destphik2) vs corollary critdamp: second differences of varphi at P_d against
/// 2/Π|P_d − P_i|^{e/k} for e = 2 and e = 4.
fn destination_hessian() -> Outcome {
    let mut rng = Rng::new(6);
    let (mut worst2, mut best4) = (0.0f64, f64::INFINITY);
    let mut example = String::new();
    let mut used = 0;
    while used < 500 {
        let w = rng.world(1 + used % 10);
        let m = checks::destination_hessian(&w, 1e-4);
        if (m.two_over_k / m.four_over_k).ln().abs() < 0.1 {
            continue; // Π|P_d − P_i|^{2/k} ≈ 1: the two exponents cannot be told apart
        }
        let hxx = m.fd[(0, 0)];
        if example.is_empty() {
            example = format!(
                "e.g. FD {hxx:.6} vs 2/k: {:.6}, 4/k: {:.6}",
                m.two_over_k, m.four_over_k
            );
        }
        worst2 = worst2.max((m.fd - m.two_over_k * Matrix2::identity()).norm() / m.two_over_k);
        best4 = best4.min((hxx - m.four_over_k).abs() / m.two_over_k);
        used += 1;
    }
    outcome(
        worst2 < 1e-5 && best4 > 1e-2,
        format!(
            "500 worlds: exponent 2/k within {worst2:.1e}, 4/k off by ≥ {best4:.1e}; {example}"
        ),
    )
}

/// Proposition Morse: the symmetric arrangement has a degenerate critical point.
fn non_morse() -> Outcome {
    let mut details = Vec::new();
    for mu in 1..=4 {
        let (w, hc) =
            arrangements::non_morse(mu, 0.8, Vector2::new(0.5, -1.0)).map_err(|e| e.to_string())?;
        let cps = w.critical_points();
        let Some(c) = cps.iter().find(|c| c.kind == CriticalKind::Degenerate) else {
            return Err(format!(
                "mu = {mu}: census found no degenerate point: {cps:?}"
            ));
        };
        let exact = w.hess_phi_k(hc).map_err(|e| e.to_string())?.norm() / hess_scale(&w, hc);
        if (c.position - hc).norm() > 3e-5 || exact > 1e-12 {
            return Err(format!(
                "mu = {mu}: found {:?}, expected {hc:?}; |H|/scale = {exact:.1e}",
                c.position
            ));
        }
        details.push(format!(
            "M={}: ×{} at {:.0e}",
            2 * mu + 1,
            c.multiplicity,
            (c.position - hc).norm()
        ));
    }
    outcome(
        true,
        format!(
            "degenerate saddle found (multiplicity, distance): {}",
            details.join(", ")
        ),
    )
}

/// Numerics: finite values from 1e-300 to 1e300 away, exact limits at the singular points.
fn extreme_scales() -> Outcome {
    let mut rng = Rng::new(7);
    let mut evaluations = 0;
    for i in 0..200 {
        let w = rng.world(1 + i % 10);
        let a = rng.uniform(0.0, std::f64::consts::TAU);
        let u = Vector2::new(a.cos(), a.sin());
        evaluations += checks::extreme_scales(&w, u, (-300..=300).step_by(25))
            .map_err(|h| format!("world {i}: non-finite result or inexact limit at {h:?}"))?;
    }
    outcome(
        true,
        format!("{evaluations} evaluations at offsets 1e-300..1e300: all finite, limits exact"),
    )
}
