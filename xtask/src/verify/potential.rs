//! Guarantee checks of `harmonav-potential` (issue: potential core).

use harmonav_potential::{CriticalKind, PointWorld, Vector2, arrangements};

use super::{Check, Outcome, outcome};
use crate::rng::{PointWorlds, Rng, clearance};

pub fn checks() -> Vec<Check> {
    vec![
        Check::new("potential.gradient-matches-finite-differences", gradient_fd),
        Check::new("potential.hessian-matches-fd-and-is-harmonic", hessian_fd),
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

fn grad_scale(w: &PointWorld, h: Vector2<f64>) -> f64 {
    w.grad_term_scale(h)
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

/// Eq. (gradient) against central differences of phi_k and of varphi.
fn gradient_fd() -> Outcome {
    let step = 1e-6;
    let (ex, ey) = (Vector2::new(step, 0.0), Vector2::new(0.0, step));
    let mut worst = 0.0f64;
    let mut n = 0;
    for (w, hs) in samples(1, 200, 100) {
        for h in hs {
            let fd = |f: &dyn Fn(Vector2<f64>) -> f64| {
                Vector2::new(
                    (f(h + ex) - f(h - ex)) / (2.0 * step),
                    (f(h + ey) - f(h - ey)) / (2.0 * step),
                )
            };
            let scale = grad_scale(&w, h);
            let e1 = (w.grad_phi_k(h).map_err(|e| e.to_string())? - fd(&|x| w.phi_k(x))).norm();
            let e2 = (w.grad_varphi(h).map_err(|e| e.to_string())? - fd(&|x| w.varphi(x))).norm();
            worst = worst.max(e1.max(e2) / scale);
            n += 1;
        }
    }
    outcome(
        worst < 1e-6,
        format!(
            "worst error {worst:.1e} (relative to the term scale) over {n} points in 200 worlds"
        ),
    )
}

/// Eq. (hessquadratic) against differences of the gradient; tr H = 0 (lemma locminfree).
fn hessian_fd() -> Outcome {
    let step = 1e-6;
    let (ex, ey) = (Vector2::new(step, 0.0), Vector2::new(0.0, step));
    let (mut worst, mut worst_trace) = (0.0f64, 0.0f64);
    for (w, hs) in samples(2, 200, 100) {
        for h in hs {
            let g = |x: Vector2<f64>| w.grad_phi_k(x).expect("regular point");
            let hess = w.hess_phi_k(h).map_err(|e| e.to_string())?;
            let cx = (g(h + ex) - g(h - ex)) / (2.0 * step);
            let cy = (g(h + ey) - g(h - ey)) / (2.0 * step);
            let scale = hess_scale(&w, h);
            let err = ((hess.column(0) - cx).norm()).max((hess.column(1) - cy).norm());
            worst = worst.max(err / scale);
            worst_trace = worst_trace.max(hess.trace().abs() / scale);
        }
    }
    outcome(
        worst < 1e-6 && worst_trace < 1e-13,
        format!(
            "worst FD error {worst:.1e}, worst |tr H| {worst_trace:.1e} (relative) over 20000 points"
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
        let slope = 2.0 * (1.0 - m as f64 / w.k());
        let mut last = f64::NEG_INFINITY;
        for e in [3, 12, 100, 300] {
            let r = 10f64.powi(e);
            let phi = w.phi_k(r * u);
            if phi.is_nan() || phi <= last {
                return Err(format!(
                    "phi_k not increasing at |h| = 1e{e} (k = {})",
                    w.k()
                ));
            }
            last = phi;
            if e >= 12 {
                worst = worst.max((phi / (slope * r.ln()) - 1.0).abs());
            }
        }
    }
    outcome(
        worst < 1e-2,
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
    let extent = 6.0;
    let cell = 2.0 * extent / n as f64;
    for i in 0..20 {
        let w = rng.world(1 + i % 10);
        let node = |a: usize, b: usize| {
            Vector2::new(
                -extent + cell * a as f64 + 1e-7,
                -extent + cell * b as f64 + 3e-7,
            )
        };
        let v: Vec<f64> = (0..=n)
            .flat_map(|a| (0..=n).map(move |b| (a, b)))
            .map(|(a, b)| w.phi_k(node(a, b)))
            .collect();
        let at = |a: usize, b: usize| v[a * (n + 1) + b];
        for a in 1..n {
            for b in 1..n {
                if (node(a, b) - w.destination()).norm() < 2.0 * cell {
                    continue;
                }
                let c = at(a, b);
                let minimum = (0..3).all(|da| {
                    (0..3).all(|db| (da, db) == (1, 1) || at(a + da - 1, b + db - 1) > c)
                });
                if minimum {
                    return Err(format!("world {i}: local minimum at {:?}", node(a, b)));
                }
            }
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
        let m = w.obstacles().len();
        let cps = w.critical_points();
        let total: usize = cps.iter().map(|c| c.multiplicity).sum();
        if total != m {
            return Err(format!("world {i}: {total} critical points for M = {m}"));
        }
        for c in &cps {
            let g = w.grad_phi_k(c.position).map_err(|e| e.to_string())?;
            worst = worst.max(g.norm() / grad_scale(&w, c.position));
            let det = w
                .hess_phi_k(c.position)
                .map_err(|e| e.to_string())?
                .determinant();
            match c.kind {
                CriticalKind::Saddle if det >= 0.0 => {
                    return Err(format!(
                        "world {i}: critical point {:?} with det H = {det}",
                        c.position
                    ));
                }
                CriticalKind::Degenerate => degenerate += 1,
                _ => {}
            }
        }
        points += cps.len();
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
    let step = 1e-4;
    let (mut worst2, mut best4) = (0.0f64, f64::INFINITY);
    let mut example = String::new();
    let mut used = 0;
    while used < 500 {
        let w = rng.world(1 + used % 10);
        let d = w.destination();
        let ln_prod: f64 = w.obstacles().iter().map(|p| (d - p).norm().ln()).sum();
        if (ln_prod / w.k()).abs() < 0.05 {
            continue; // Π ≈ 1: the two exponents cannot be told apart
        }
        let f = |x: Vector2<f64>| w.varphi(x);
        let hxx = (f(d + Vector2::new(step, 0.0)) + f(d - Vector2::new(step, 0.0)) - 2.0 * f(d))
            / (step * step);
        let two = 2.0 * (-2.0 * ln_prod / w.k()).exp();
        let four = 2.0 * (-4.0 * ln_prod / w.k()).exp();
        if example.is_empty() {
            example = format!("e.g. FD {hxx:.6} vs 2/k: {two:.6}, 4/k: {four:.6}");
        }
        worst2 = worst2.max((hxx - two).abs() / two);
        best4 = best4.min((hxx - four).abs() / two);
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
        let dir = Vector2::new(a.cos(), a.sin());
        if w.varphi(w.destination()) != 0.0 || w.obstacles().iter().any(|&p| w.varphi(p) != 1.0) {
            return Err(format!(
                "world {i}: varphi not exactly 0 at P_d and 1 at P_i"
            ));
        }
        for e in (-300..=300).step_by(25) {
            let s = 10f64.powi(e);
            let mut hs = vec![s * dir];
            hs.extend(
                w.obstacles()
                    .iter()
                    .chain([&w.destination()])
                    .map(|p| p + s * dir),
            );
            for h in hs {
                if w.singularity(h).is_some() {
                    continue; // s below the resolution of the point's coordinates
                }
                let ok = w.phi_k(h).is_finite()
                    && (0.0..=1.0).contains(&w.varphi(h))
                    && w.grad_phi_k(h)
                        .is_ok_and(|g| g.iter().all(|x| x.is_finite()))
                    && w.grad_varphi(h)
                        .is_ok_and(|g| g.iter().all(|x| x.is_finite()))
                    && w.descent_direction(h).is_some();
                if !ok {
                    return Err(format!("world {i}: non-finite result at {h:?}"));
                }
                evaluations += 1;
            }
        }
    }
    outcome(
        true,
        format!("{evaluations} evaluations at offsets 1e-300..1e300: all finite, limits exact"),
    )
}
