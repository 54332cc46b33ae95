//! Critical points of phi_k: exactly M saddles counted with multiplicity (lemma saddlep,
//! Poincaré–Hopf), and the degenerate point of proposition Morse.

mod common;

use common::*;
use harmonav_potential::{CriticalKind, PointWorld, Vector2, arrangements, checks};
use proptest::prelude::*;

/// Winding number of ∇phi_k along a circle of radius r about c (the Poincaré–Hopf index of
/// the critical points inside): +1 for a minimum, −1 for a saddle, −m for a monkey saddle.
fn winding(w: &PointWorld, c: Vector2<f64>, r: f64) -> i64 {
    let n = 720;
    let mut total = 0.0;
    let angle = |i: usize| {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        let g = w
            .grad_phi_k(c + r * Vector2::new(a.cos(), a.sin()))
            .unwrap();
        g.y.atan2(g.x)
    };
    let mut prev = angle(0);
    for i in 1..=n {
        let next = angle(i % n);
        let mut d = next - prev;
        while d > std::f64::consts::PI {
            d -= std::f64::consts::TAU;
        }
        while d < -std::f64::consts::PI {
            d += std::f64::consts::TAU;
        }
        total += d;
        prev = next;
    }
    (total / std::f64::consts::TAU).round() as i64
}

/// Checks one world's census: multiplicities sum to M, every point is critical, a saddle by
/// its eigenvalues, by the mean-value argument (values above and below on a small circle) and
/// by its index (winding number −multiplicity).
fn check_census(w: &PointWorld) -> Result<(), TestCaseError> {
    let points = w.critical_points();
    let measured = checks::census(w);
    prop_assert!(
        measured.is_ok_and(|c| c.worst_gradient <= 1e-7),
        "{measured:?}: {points:?}"
    );
    for c in &points {
        let h = c.position;
        let radius = 1e-3 * clearance(w, h);
        prop_assume!(clearance(w, h) > 1e-3);
        let [lo, hi] = c.eigenvalues;
        prop_assert!(lo <= 0.0 && hi >= 0.0 && (lo + hi).abs() <= 1e-12 * hess_scale(w, h));
        if c.kind == CriticalKind::Saddle {
            let det = w.hess_phi_k(h).unwrap().determinant();
            prop_assert!((det + hi * hi).abs() <= 1e-6 * hi * hi);
        }
        let centre = w.phi_k(h);
        let ring: Vec<f64> = (0..64)
            .map(|i| {
                let a = std::f64::consts::TAU * (i as f64 + 0.5) / 64.0;
                w.phi_k(h + radius * Vector2::new(a.cos(), a.sin()))
            })
            .collect();
        prop_assert!(ring.iter().any(|&v| v > centre) && ring.iter().any(|&v| v < centre));
        prop_assert_eq!(winding(w, h, radius), -(c.multiplicity as i64));
    }
    // Poincaré–Hopf on a large circle: +1 (destination) + M (obstacle points, index +1 each
    // for ∇phi_k) − M (saddles) = 1.
    prop_assert_eq!(winding(w, Vector2::zeros(), 1e4), 1);
    Ok(())
}

proptest! {
    #![proptest_config(config(512))]

    #[test]
    fn m_saddles_and_nothing_else(w in world(10)) {
        check_census(&w)?;
    }

    #[test]
    fn m_saddles_for_any_admissible_k(w in world(6), extra in 0.01..4.0f64) {
        let m = w.obstacles().len() as f64;
        check_census(&w.with_k(m + extra).unwrap())?;
    }
}

/// Proposition Morse: the census finds the constructed degenerate critical point (a double
/// root, both eigenvalues ≈ 0) and the remaining critical points are ordinary saddles.
#[test]
fn symmetric_arrangement_has_a_degenerate_saddle() {
    for mu in 1..=3 {
        let (w, hc) = arrangements::non_morse(mu, 0.8, Vector2::new(1.0, 2.0)).unwrap();
        let points = w.critical_points();
        let degenerate: Vec<_> = points
            .iter()
            .filter(|c| c.kind == CriticalKind::Degenerate)
            .collect();
        assert_eq!(degenerate.len(), 1, "mu = {mu}: {points:?}");
        let c = degenerate[0];
        assert!(c.multiplicity >= 2, "mu = {mu}: {c:?}");
        // An m-fold root is determined by the function values only to ≈ ε^{1/m}·scale
        // (6e-6 for m = 3): within that F is rounding noise.
        assert!(
            (c.position - hc).norm() < 3e-5,
            "mu = {mu}: {:?} vs {hc:?}",
            c.position
        );
        let scale = hess_scale(&w, hc);
        assert!(
            c.eigenvalues[1] <= 1e-6 * scale,
            "mu = {mu}: {:?}",
            c.eigenvalues
        );
        let exact = w.hess_phi_k(hc).unwrap().symmetric_eigenvalues();
        assert!(exact.iter().all(|l| l.abs() <= 1e-12 * scale), "{exact:?}");
        // A monkey saddle where F has a zero of order m has index −m.
        assert_eq!(winding(&w, hc, 1e-3), -(c.multiplicity as i64), "mu = {mu}");
        println!(
            "mu = {mu}: degenerate point of multiplicity {} at distance {:.1e}, eigenvalues {:?}",
            c.multiplicity,
            (c.position - hc).norm(),
            c.eigenvalues
        );
        let total: usize = points.iter().map(|c| c.multiplicity).sum();
        assert_eq!(total, 2 * mu + 1);
    }
}
