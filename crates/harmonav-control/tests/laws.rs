//! The control laws against the properties the paper proves for them.

use std::sync::Arc;

use harmonav_control::{Dynamic, Kinematic};
use harmonav_field::Field;
use harmonav_transform::random::{self, Kind, Rng};
use nalgebra::{Matrix2, Matrix4, Vector2};

const KINDS: [Kind; 4] = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];

fn world(seed: u64) -> (Field, Rng) {
    let mut rng = Rng::new(seed);
    let (m, outer) = (1 + rng.below(6), KINDS[rng.below(4)]);
    let ws = random::workspace(&mut rng, m, &KINDS, outer, 0.2);
    (Field::all_known(Arc::new(ws)).unwrap(), rng)
}

/// Corollary critdamp: the closed loop linearised at the goal, with the Hessian of Θ taken by
/// finite differences of ∇Θ (independent of the closed form), has damping ratio 1: a double
/// real eigenvalue per direction.
#[test]
fn critical_damping_at_the_goal() {
    for seed in 0..40 {
        let (field, _) = world(seed);
        let law = Dynamic::new(1.0 + seed as f64 * 0.1, 10.0, 0.05).unwrap();
        let xd = field.workspace().destination();
        let h = 1e-5;
        let g = |x: Vector2<f64>| field.eval(x).unwrap().gradient;
        let hx = (g(xd + Vector2::new(h, 0.0)) - g(xd - Vector2::new(h, 0.0))) / (2.0 * h);
        let hy = (g(xd + Vector2::new(0.0, h)) - g(xd - Vector2::new(0.0, h))) / (2.0 * h);
        let hess = Matrix2::from_columns(&[hx, hy]);
        let (m, mu, lc) = (law.mass(), law.mu(), law.lambda_c(&field));
        for eig in hess.symmetric_eigenvalues().iter() {
            let zeta = lc / (2.0 * (m * mu * eig).sqrt());
            assert!(
                (zeta - 1.0).abs() < 1e-6,
                "seed {seed}: damping ratio {zeta}"
            );
        }
        // The 4×4 closed-loop matrix has the double eigenvalue −λ_c/(2m).
        let mut a = Matrix4::zeros();
        a.fixed_view_mut::<2, 2>(0, 2)
            .copy_from(&Matrix2::identity());
        a.fixed_view_mut::<2, 2>(2, 0).copy_from(&(-mu / m * hess));
        a.fixed_view_mut::<2, 2>(2, 2)
            .copy_from(&(-lc / m * Matrix2::identity()));
        let target = -lc / (2.0 * m);
        for e in a.complex_eigenvalues().iter() {
            assert!(
                (e.re - target).abs() < 1e-3 * target.abs() && e.im.abs() < 1e-3 * target.abs(),
                "seed {seed}: {e} vs {target}"
            );
        }
    }
}

/// Eq. (totalenergy): between discoveries V = μΘ + ½m|ẋ|² does not increase along the closed
/// loop (V̇ = −λ|ẋ|²), and the speed stays below √(2μ/m).
#[test]
fn energy_decreases_and_speed_is_bounded() {
    for seed in 0..20 {
        let (field, mut rng) = world(100 + seed);
        let law = Dynamic::new(1.0, 10.0, 0.05).unwrap();
        let mut x = random::free_point(&mut rng, field.workspace(), 0.2);
        let mut v = Vector2::zeros();
        let accel = |x: Vector2<f64>, v: Vector2<f64>| {
            let e = field.eval(x).unwrap();
            let lambda = law.damping(&field, law.energy(e.value, v), 0.0);
            law.force(&e, v, lambda) / law.mass()
        };
        let energy = |x: Vector2<f64>, v: Vector2<f64>| law.energy(field.eval(x).unwrap().value, v);
        let mut last = energy(x, v);
        let dt = 1e-3;
        for _ in 0..3000 {
            // Classical RK4 on (x, v).
            let (k1x, k1v) = (v, accel(x, v));
            let (k2x, k2v) = (
                v + 0.5 * dt * k1v,
                accel(x + 0.5 * dt * k1x, v + 0.5 * dt * k1v),
            );
            let (k3x, k3v) = (
                v + 0.5 * dt * k2v,
                accel(x + 0.5 * dt * k2x, v + 0.5 * dt * k2v),
            );
            let (k4x, k4v) = (v + dt * k3v, accel(x + dt * k3x, v + dt * k3v));
            x += dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
            v += dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            let now = energy(x, v);
            assert!(
                now <= last + 1e-9 * last.max(1e-3),
                "seed {seed}: V rose from {last} to {now}"
            );
            assert!(v.norm() < law.speed_bound());
            last = now;
        }
    }
}

/// Eq. (kinctrl): dΘ/dt = ∇Θ·u = −K√(2Θ)|∇Θ| ≤ 0, also by a finite step along u.
#[test]
fn kinematic_law_decreases_theta() {
    let law = Kinematic::new(1.5).unwrap();
    for seed in 0..40 {
        let (field, mut rng) = world(200 + seed);
        for _ in 0..20 {
            let x = random::free_point(&mut rng, field.workspace(), 0.05);
            let e = field.eval(x).unwrap();
            let u = law.velocity(&e);
            let rate = e.gradient.dot(&u);
            let expected = -1.5 * (2.0 * e.value).sqrt() * e.gradient.norm();
            assert!(rate <= 0.0 && (rate - expected).abs() <= 1e-12 * expected.abs().max(1e-300));
            let dt = 1e-7;
            let fd = (field.eval(x + dt * u).unwrap().value - e.value) / dt;
            assert!(
                (fd - rate).abs() <= 1e-4 * rate.abs() + 1e-12,
                "fd {fd} vs {rate}"
            );
        }
        // At the goal the command is zero.
        let goal = field.eval(field.workspace().destination()).unwrap();
        assert_eq!(law.velocity(&goal), Vector2::zeros());
    }
}

/// Eq. (dissipationfun): the damping switches to (m/d_min)|ẋ(T_n)| once V ≥ μ.
#[test]
fn damping_switches_on_energy() {
    let (field, _) = world(7);
    let law = Dynamic::new(2.0, 10.0, 0.05).unwrap();
    assert_eq!(law.damping(&field, 9.999, 3.0), law.lambda_c(&field));
    assert_eq!(law.damping(&field, 10.0, 3.0), 2.0 / 0.05 * 3.0);
    // λ_c = 2√(2μm) Π|P_d − P_i|^{−1/k} (eq. critdamp), evaluated directly.
    let pw = field.point_world();
    let prod: f64 = pw
        .obstacles()
        .iter()
        .map(|p| (pw.destination() - p).norm().powf(-1.0 / pw.k()))
        .product();
    let direct = 2.0 * (2.0 * 10.0 * 2.0f64).sqrt() * prod;
    assert!((law.lambda_c(&field) - direct).abs() < 1e-12 * direct);
    assert!(Dynamic::new(0.0, 1.0, 1.0).is_err() && Dynamic::new(1.0, f64::NAN, 1.0).is_err());
    assert!(Kinematic::new(-1.0).is_err());
}
