//! Values and derivatives of phi_k and varphi against closed forms and finite differences.

mod common;

use common::*;
use harmonav_potential::checks::{self, derivative_errors};
use harmonav_potential::{Matrix2, PointWorld, Vector2, terms};
use proptest::prelude::*;

proptest! {
    #![proptest_config(config(1024))]

    /// Eq. (gradient) and eq. (hessquadratic) against central differences, for phi_k and
    /// varphi = sigma(phi_k); H symmetric and trace-free (lemma locminfree: Δphi_k = 0).
    #[test]
    fn derivatives_match_finite_differences(w in world(8), h in point(6.0)) {
        prop_assume!(clearance(&w, h) > 0.05);
        let e = derivative_errors(&w, h).unwrap();
        prop_assert!(e.grad_phi_k <= 1e-6 && e.grad_varphi <= 1e-7, "{e:?}");
        prop_assert!(e.hess_phi_k <= 1e-6 && e.hess_varphi <= 1e-6, "{e:?}");
        prop_assert!(e.asymmetry <= 1e-15 && e.trace <= 1e-13, "{e:?}");
        prop_assert!((0.0..=1.0).contains(&w.varphi(h)));
        // The unit descent direction is −∇varphi normalised wherever the gradient is resolvable.
        let g = w.grad_varphi(h).unwrap();
        if let Some(u) = w.descent_direction(h) {
            prop_assert!((u.norm() - 1.0).abs() < 1e-14);
            if g.norm() > 1e-300 {
                prop_assert!((u + g / g.norm()).norm() < 1e-12);
            }
        }
    }

    /// The one-logarithm hot path agrees with the sum-of-logs value and the plain gradient,
    /// also when one offset is given exactly and at extreme distances.
    #[test]
    fn phi_and_grad_agrees_with_the_separate_evaluations(w in world(8), h in point(6.0), e in -120i32..120) {
        prop_assume!(clearance(&w, h) > 0.05);
        let (phi, g) = w.phi_and_grad(h, None).unwrap();
        prop_assert!((phi - w.phi_k(h)).abs() <= 1e-13 * (1.0 + phi.abs()));
        prop_assert!((g - w.grad_phi_k(h).unwrap()).norm() <= 1e-14 * grad_scale(&w, h));
        // Near obstacle 0 with the offset given exactly (pitfall C): equal to phi_k where h − P_0
        // is still resolvable, finite and larger (closer to the point) where it is not.
        let dir = Vector2::new(0.6, 0.8);
        let moderate = 1e-4 * dir;
        let (phi_m, _) = w.phi_and_grad(w.obstacles()[0] + moderate, Some((0, moderate))).unwrap();
        prop_assert!((phi_m - w.phi_k(w.obstacles()[0] + moderate)).abs() <= 1e-8 * phi_m.abs().max(1.0));
        let tiny = 10f64.powi(e.min(0) - 30) * dir;
        let (phi_t, g_t) = w.phi_and_grad(w.obstacles()[0] + tiny, Some((0, tiny))).unwrap();
        prop_assert!(phi_t.is_finite() && g_t.iter().all(|x| x.is_finite()) && phi_t > phi_m);
        // The descent direction there points straight away from P_0.
        prop_assert!((-g_t / g_t.norm() - dir).norm() < 1e-6, "{g_t:?}");
        let far = 10f64.powi(e.max(0) + 3) * Vector2::new(0.6, 0.8);
        let (phi, _) = w.phi_and_grad(far, None).unwrap();
        prop_assert!((phi - w.phi_k(far)).abs() <= 1e-12 * phi.abs().max(1.0));
    }

    /// Lemma attactive: far away phi_k ≈ 2(1 − M/k) ln|h| → +∞ for k > M.
    #[test]
    fn attractive_far_away_for_k_above_m(w in world(8), angle in 0.0..std::f64::consts::TAU, extra in 0.0..3.0f64) {
        let m = w.obstacles().len() as f64;
        let w = w.with_k(m + 0.1 + extra).unwrap();
        let u = Vector2::new(angle.cos(), angle.sin());
        let deviation = checks::far_field(&w, u, &[3, 6, 12, 50, 150, 300]);
        prop_assert!(deviation.is_ok_and(|d| d <= 1e-9), "{deviation:?}");
    }

    /// Lemma attactive, converse: with k = M the potential stays bounded far away and with
    /// k < M it tends to −∞ — which is why PointWorld rejects k ≤ M. The sum is evaluated here
    /// term by term from the public `terms` module (an independent reference).
    #[test]
    fn not_attractive_for_k_at_most_m(w in world(8), angle in 0.0..std::f64::consts::TAU) {
        let m = w.obstacles().len();
        prop_assert!(w.clone().with_k(m as f64).is_err());
        let phi = |k: f64, h: Vector2<f64>| {
            terms::ln_norm2(h - w.destination())
                - w.obstacles().iter().map(|p| terms::ln_norm2(h - p)).sum::<f64>() / k
        };
        let u = Vector2::new(angle.cos(), angle.sin());
        let far = 1e12 * u;
        prop_assert!(phi(m as f64, far).abs() < 1e-9, "k = M: {}", phi(m as f64, far));
        if m > 1 {
            let k = m as f64 - 0.5;
            prop_assert!(phi(k, 1e100 * u) < phi(k, 1e10 * u) && phi(k, 1e100 * u) < -10.0);
        }
    }

    /// The destination Hessian of sigma∘phi_k against the closed form 2/Π|P_d−P_i|^{2/k}·I
    /// (eq. critdamp's exponent), from second differences of varphi values at P_d; and not the
    /// 4/k of eq. destphik2, which differs from it whenever Π|P_d − P_i| ≠ 1.
    #[test]
    fn destination_hessian_has_exponent_two_over_k(w in world(8)) {
        let d = w.destination();
        let ln_prod: f64 = w.obstacles().iter().map(|p| (d - p).norm().ln()).sum();
        prop_assume!((ln_prod / w.k()).abs() > 0.05);
        let m = checks::destination_hessian(&w, 1e-4);
        let closed = w.destination_hessian();
        prop_assert!((closed[(0, 0)] - m.two_over_k).abs() <= 1e-12 * m.two_over_k);
        prop_assert!((m.fd - closed).norm() <= 1e-4 * m.two_over_k, "fd {} vs closed {closed}", m.fd);
        prop_assert!((m.fd[(0, 0)] - m.four_over_k).abs() > 1e-2 * m.two_over_k, "4/k cannot be told apart");
    }

    /// No local minimum except the destination: on a dense grid no node (away from the
    /// destination) is strictly below all eight neighbours.
    #[test]
    fn no_local_minimum_on_a_dense_grid(w in world(6)) {
        let minimum = checks::grid_local_minimum(&w, 240, 6.0);
        prop_assert!(minimum.is_none(), "local minimum at {minimum:?}");
    }
}

proptest! {
    #![proptest_config(config(256))]

    /// Numerics on random worlds: finite values and directions from 1e-300 to 1e300 away from
    /// the origin, the destination and every obstacle point; exact limits at the points.
    #[test]
    fn every_scale_stays_finite(w in world(8), angle in 0.0..std::f64::consts::TAU) {
        let u = Vector2::new(angle.cos(), angle.sin());
        let evaluated = checks::extreme_scales(&w, u, (-300..=300).step_by(25));
        prop_assert!(evaluated.is_ok_and(|n| n > 0), "non-finite at {evaluated:?}");
    }
}

/// The closed form of varphi in the point world, and the exact limits at the singular points,
/// across extreme scales: nothing overflows or turns NaN as h → P_i, h → P_d, |h| → ∞.
#[test]
fn extreme_scales_stay_finite() {
    let w = PointWorld::new(
        Vector2::new(1.0, 0.0),
        vec![
            Vector2::new(0.0, 0.0),
            Vector2::new(-2.0, 1.5),
            Vector2::new(3.0, -2.0),
        ],
    )
    .unwrap();
    let dir = Vector2::new(0.6, 0.8);
    for e in [-300, -200, -150, -100, -50, -12, -3] {
        let eps = 10f64.powi(e);
        for (base, label) in [(w.obstacles()[0], "P_1"), (w.destination(), "P_d")] {
            let h = base + eps * dir;
            if h == base {
                continue; // below the resolution of base's coordinates
            }
            let phi = w.phi_k(h);
            let g = w.grad_phi_k(h).unwrap();
            let gv = w.grad_varphi(h).unwrap();
            let hv = match w.hess_varphi(h) {
                Ok(hv) => hv,
                // The Hessian grows like |h_i|^{2/k−2}: beyond f64 closer than ~1e-150.
                Err(_) if label == "P_1" && e < -150 => Matrix2::zeros(),
                Err(err) => panic!("{label} + 1e{e}: {err}"),
            };
            assert!(phi.is_finite(), "{label} + 1e{e}: phi = {phi}");
            assert!(
                g.iter().all(|x| x.is_finite()),
                "{label} + 1e{e}: grad {g:?}"
            );
            assert!(
                gv.iter().all(|x| x.is_finite()),
                "{label} + 1e{e}: grad varphi {gv:?}"
            );
            assert!(
                hv.iter().all(|x| x.is_finite()),
                "{label} + 1e{e}: hess varphi {hv}"
            );
            assert!((0.0..=1.0).contains(&w.varphi(h)));
            assert!(w.descent_direction(h).is_some());
        }
        // The Hessian at the destination is continuous: within 1e-12 of it, it is the closed form.
        let hd = w.hess_varphi(w.destination() + eps * dir).unwrap();
        if e <= -12 {
            let closed = w.destination_hessian();
            assert!(
                (hd - closed).norm() <= 1e-9 * closed.norm(),
                "P_d + 1e{e}: {hd}"
            );
        }
        // Approaching an obstacle point varphi → 1, approaching the destination → 0.
        if e <= -12 {
            assert!(w.varphi(w.obstacles()[0] + eps * dir) > 0.99);
            assert!(w.varphi(w.destination() + eps * dir) < 1e-20);
        }
    }
    for e in [3, 50, 150, 200, 300, 307] {
        let h = 10f64.powi(e) * dir;
        let phi = w.phi_k(h);
        assert!(phi.is_finite() && phi > 0.0, "1e{e}: phi = {phi}");
        let g = w.grad_phi_k(h).unwrap();
        assert!(g.iter().all(|x| x.is_finite()), "1e{e}: grad {g:?}");
        // Far away the descent direction points back towards the origin.
        let u = w.descent_direction(h).unwrap();
        assert!(u.dot(&dir) < -0.99, "1e{e}: {u:?}");
        assert!(w.varphi(h) > 0.0 && w.varphi(h) <= 1.0);
    }
}

/// The fast path's split product (`|h_i|² = m_i·2^{e_i}`, one logarithm per 512 factors) at
/// many points far apart: 1 100 points in a disc of radius 50 (three blocks, factors from 1e-6
/// to 1e4, where the old single product left its range and every call took `M` logarithms)
/// agrees with the sum of logarithms of `phi_k` within the bound of `phi_and_grad`'s docs,
/// `4ε(M + Σ|ln|h_i|²|)/k + 4ε|ln|h_d|²|`, also with one offset given exactly.
#[test]
fn split_product_agrees_with_the_sum_of_logarithms_at_many_points() {
    let n = 1100;
    let pts: Vec<Vector2<f64>> = (0..n)
        .map(|i| {
            let (r, a) = (
                50.0 * ((i as f64 + 0.5) / n as f64).sqrt(),
                2.399963 * i as f64,
            );
            Vector2::new(r * a.cos(), r * a.sin())
        })
        .collect();
    let world = PointWorld::new(Vector2::new(40.0, 0.3), pts.clone())
        .unwrap()
        .with_k(6.0 * (n as f64 + 1.0))
        .unwrap();
    // The split product (the direct hot path), then the multipole path with its tolerance
    // (`far::TOLERANCE` per far point in the sum) on top.
    for (w, far) in [
        (world.clone().without_far_field(), 0.0),
        (world, 2.0 * harmonav_potential::far::TOLERANCE * n as f64),
    ] {
        check_split_product(&w, &pts, far);
    }
}

fn check_split_product(w: &PointWorld, pts: &[Vector2<f64>], far: f64) {
    let n = pts.len();
    let eps = f64::EPSILON;
    for j in 0..200 {
        let a = 0.77 * j as f64;
        let h = Vector2::new(45.0 * a.cos(), 45.0 * (1.3 * a).sin()) * (j as f64 / 200.0);
        let bound = |h: Vector2<f64>| {
            let logs: f64 = pts.iter().map(|p| (h - p).norm_squared().ln().abs()).sum();
            (4.0 * eps * (n as f64 + logs) + far) / w.k()
                + 4.0 * eps * (h - w.destination()).norm_squared().ln().abs()
        };
        let (phi, g) = w.phi_and_grad(h, None).unwrap();
        assert!(
            (phi - w.phi_k(h)).abs() <= bound(h),
            "{j}: {phi} vs {}",
            w.phi_k(h)
        );
        assert!((g - w.grad_phi_k(h).unwrap()).norm() <= 1e-12 * g.norm().max(1e-3));
        // 1e-3 from point 7, that offset given exactly.
        let v = Vector2::new(6e-4, -8e-4);
        let (phi, _) = w.phi_and_grad(pts[7] + v, Some((7, v))).unwrap();
        let direct = w.phi_k(pts[7] + v);
        assert!(
            (phi - direct).abs() <= bound(pts[7] + v) + 1e-12,
            "{j}: {phi} vs {direct}"
        );
    }
}
