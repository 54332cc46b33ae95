//! Guarantee checks of the sensing sector and the control laws.

use std::sync::Arc;

use harmonav_control::{DampingPolicy, Dynamic, Kinematic, SpeedPolicy};
use harmonav_field::Field;
use harmonav_potential::checks::fd_jacobian;
use harmonav_sensing::Sector;
use harmonav_transform::random::{self, Kind, Rng};
use nalgebra::Vector2;

use super::{Check, Outcome, outcome};

const KINDS: [Kind; 4] = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];

pub fn checks() -> Vec<Check> {
    vec![
        Check::new("sensing.d-min-formula", d_min),
        Check::new("control.critical-damping-at-goal", critical_damping),
        Check::new("control.energy-decreases-speed-bounded", energy),
        Check::new("control.kinematic-theta-decreases", kinematic),
    ]
}

fn world(seed: u64) -> (Field, Rng) {
    let mut rng = Rng::new(seed);
    let (m, outer) = (1 + rng.below(8), KINDS[rng.below(4)]);
    let ws = random::workspace(&mut rng, m, &KINDS, outer, 0.15);
    (
        Field::all_known(Arc::new(ws)).expect("valid random world"),
        rng,
    )
}

/// Eq. (dmin) for the paper's sector (r = 1 m, θ = 60°, ρ_min = 0.05 m) and θ ≥ π.
fn d_min() -> Outcome {
    let s = Sector::new(1.0, 60f64.to_radians()).map_err(|e| e.to_string())?;
    let d = s.d_min(0.05);
    let expected = 0.05 / 30f64.to_radians().cos();
    let wide = Sector::new(1.0, 200f64.to_radians())
        .map_err(|e| e.to_string())?
        .d_min(0.05);
    outcome(
        (d - expected).abs() < 1e-15 && wide == 1.0,
        format!("θ = 60°: d_min = {d:.4} m (= ρ_min/cos 30°); θ = 200°: {wide} m (= r)"),
    )
}

/// Corollary critdamp with the finite-difference Hessian at the goal of the potential each
/// damping policy descends (Θ, or Ψ under "auto"): ζ = 1.
fn critical_damping() -> Outcome {
    let mut worst = 0.0f64;
    for seed in 0..200u64 {
        let (field, _) = world(5000 + seed);
        let law = Dynamic::new(1.0, 10.0, 0.05)
            .map_err(|e| e.to_string())?
            .with_damping(DampingPolicy::ALL[seed as usize % 3]);
        let xd = field.workspace().destination();
        let h = 1e-5;
        let g = |x: Vector2<f64>| {
            field
                .eval(x)
                .map(|e| law.potential(&field, &e).gradient)
                .unwrap_or(Vector2::zeros())
        };
        let hess = fd_jacobian(g, xd, h);
        for eig in hess.symmetric_eigenvalues().iter() {
            let zeta = law.lambda_c(&field) / (2.0 * (law.mass() * law.mu() * eig).sqrt());
            worst = worst.max((zeta - 1.0).abs());
        }
    }
    outcome(
        worst < 1e-6,
        format!(
            "200 worlds, every damping policy: damping ratio at the goal within {worst:.1e} of 1 (λ_c with exponent 2/k)"
        ),
    )
}

/// Eq. (totalenergy) and corollary boundedvel along the closed loop from rest (global field,
/// RK4, 4000 steps of 1 ms), under every damping policy: V never rises, |ẋ| < √(2μ/m).
fn energy() -> Outcome {
    let (mut max_speed, mut worst_rise) = (0.0f64, 0.0f64);
    let base = Dynamic::new(1.0, 10.0, 0.05).map_err(|e| e.to_string())?;
    for seed in 0..30u64 {
        let law = base.with_damping(DampingPolicy::ALL[seed as usize % 3]);
        let (field, mut rng) = world(6000 + seed);
        let mut x = random::free_point(&mut rng, field.workspace(), 0.2);
        let mut v = Vector2::zeros();
        let eval = |x: Vector2<f64>| {
            field
                .eval(x)
                .map_err(|e| format!("seed {seed}: {e} at {x:?}"))
        };
        let accel = |x: Vector2<f64>, v: Vector2<f64>| -> Result<Vector2<f64>, String> {
            let e = eval(x)?;
            Ok(law.force(&field, &e, v, &law.damping(&field, &e, v, 0.0)) / law.mass())
        };
        let mut last = law.energy(&field, &eval(x)?, v);
        let dt = 1e-3;
        for _ in 0..4000 {
            let (k1x, k1v) = (v, accel(x, v)?);
            let (k2x, k2v) = (
                v + 0.5 * dt * k1v,
                accel(x + 0.5 * dt * k1x, v + 0.5 * dt * k1v)?,
            );
            let (k3x, k3v) = (
                v + 0.5 * dt * k2v,
                accel(x + 0.5 * dt * k2x, v + 0.5 * dt * k2v)?,
            );
            let (k4x, k4v) = (v + dt * k3v, accel(x + dt * k3x, v + dt * k3v)?);
            x += dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
            v += dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            let now = law.energy(&field, &eval(x)?, v);
            worst_rise = worst_rise.max((now - last) / last.max(1e-12));
            max_speed = max_speed.max(v.norm());
            last = now;
        }
    }
    let bound = base.speed_bound();
    outcome(
        worst_rise <= 1e-9 && max_speed < bound,
        format!(
            "30 runs × 4 s, every damping policy: largest relative rise of V {worst_rise:.1e}; max speed {max_speed:.2} m/s < bound {bound:.2} m/s"
        ),
    )
}

/// Eq. (kinctrl): dΘ/dt = ∇Θ·u = −K√(2Θ)|∇Θ| ≤ 0 at random free points (the paper's speed
/// policy; every policy has the same direction, `harmonav-control`'s tests).
fn kinematic() -> Outcome {
    let law = Kinematic::new(1.0)
        .map_err(|e| e.to_string())?
        .with_speed(SpeedPolicy::Paper);
    let mut worst = 0.0f64;
    let mut n = 0;
    for seed in 0..200u64 {
        let (field, mut rng) = world(7000 + seed);
        for _ in 0..50 {
            let x = random::free_point(&mut rng, field.workspace(), 1e-3);
            let e = field.eval(x).map_err(|e| e.to_string())?;
            let to_goal = (x - field.workspace().destination()).norm();
            let rate = e.gradient.dot(&law.velocity(&e, to_goal));
            let expected = -(2.0 * e.value).sqrt() * e.gradient.norm();
            if rate > 0.0 {
                return Err(format!("seed {seed}: dΘ/dt = {rate} > 0 at {x:?}"));
            }
            worst = worst.max((rate - expected).abs() / expected.abs().max(1e-300));
            n += 1;
        }
    }
    outcome(
        worst < 1e-12,
        format!("{n} points: dΘ/dt ≤ 0 and equal to −K√(2Θ)|∇Θ| within {worst:.1e}"),
    )
}
