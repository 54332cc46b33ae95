//! Guarantee checks of the sensing sector and the control laws: runners over
//! `harmonav_control::checks`, which the crate's tests assert on.

use std::sync::Arc;

use harmonav_control::checks::{energy_run, goal_damping, theta_rate};
use harmonav_control::{DampingPolicy, Dynamic, Kinematic, SpeedPolicy};
use harmonav_field::Field;
use harmonav_sensing::Sector;
use harmonav_transform::random::{self, Kind, Rng};

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

/// Eq. (dmin) for the paper's sector (r = 1 m, θ = 60°, ρ_min = 0.05 m) and θ ≥ π: a closed
/// form against `Sector::d_min` (harmonav-sensing, whose tests check the same on more angles).
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
/// damping policy descends (Θ, or Ψ under "auto"): ζ = 1 (`checks::goal_damping`).
fn critical_damping() -> Outcome {
    let mut worst = 0.0f64;
    for seed in 0..200u64 {
        let (field, _) = world(5000 + seed);
        let law = Dynamic::new(1.0, 10.0, 0.05)
            .map_err(|e| e.to_string())?
            .with_damping(DampingPolicy::ALL[seed as usize % DampingPolicy::ALL.len()]);
        let g = goal_damping(&field, &law).map_err(|e| format!("seed {seed}: {e}"))?;
        worst = worst.max(g.worst_deviation());
    }
    outcome(
        worst < 1e-6,
        format!(
            "200 worlds, every damping policy: damping ratio at the goal within {worst:.1e} of 1 (λ_c with exponent 2/k)"
        ),
    )
}

/// Eq. (totalenergy) and corollary boundedvel along the closed loop from rest (global field,
/// RK4, 4000 steps of 1 ms), under every damping policy: V never rises, |ẋ| < √(2μ/m)
/// (`checks::energy_run`).
fn energy() -> Outcome {
    let (mut max_speed, mut worst_rise) = (0.0f64, 0.0f64);
    let base = Dynamic::new(1.0, 10.0, 0.05).map_err(|e| e.to_string())?;
    for seed in 0..30u64 {
        let law = base.with_damping(DampingPolicy::ALL[seed as usize % DampingPolicy::ALL.len()]);
        let (field, mut rng) = world(6000 + seed);
        let start = random::free_point(&mut rng, field.workspace(), 0.2);
        let run =
            energy_run(&field, &law, start, 1e-3, 4000).map_err(|e| format!("seed {seed}: {e}"))?;
        worst_rise = worst_rise.max(run.worst_rise);
        max_speed = max_speed.max(run.max_speed);
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
/// policy; every policy has the same direction, `harmonav-control`'s tests;
/// `checks::theta_rate`).
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
            let r = theta_rate(&field, &law, x).map_err(|e| format!("seed {seed}: {e}"))?;
            if r.rate > 0.0 {
                return Err(format!("seed {seed}: dΘ/dt = {} > 0 at {x:?}", r.rate));
            }
            // An unmeasurable point (NaN) counts as the worst, never as skipped.
            let e = r.relative_error();
            worst = if e.is_nan() {
                f64::INFINITY
            } else {
                worst.max(e)
            };
            n += 1;
        }
    }
    outcome(
        worst < 1e-12,
        format!("{n} points: dΘ/dt ≤ 0 and equal to −K√(2Θ)|∇Θ| within {worst:.1e}"),
    )
}
