//! Guarantee checks of the navigation transformation and `Θ` (`harmonav-transform`,
//! `harmonav-field`) on seeded random worlds of all four shapes: runners over
//! `harmonav_field::checks`, which the crate's tests assert on.

use std::sync::Arc;

use harmonav_field::checks::{self, near_boundaries};
use harmonav_field::descent::FollowOptions;
use harmonav_field::{Field, KPolicy};
use harmonav_transform::random::{self, Kind, Rng};

use super::{Check, Outcome, outcome};

const KINDS: [Kind; 4] = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];

pub fn checks() -> Vec<Check> {
    vec![
        Check::new("field.phi-diffeomorphism-on-samples", diffeomorphism),
        Check::new("field.theta-range-and-boundary-limits", limits),
        Check::new("field.critical-points-one-min-m-saddles", census),
        Check::new("field.convergence-sphere-world", || {
            convergence(&[Kind::Circle], Kind::Circle, 1)
        }),
        Check::new("field.convergence-star-world", || {
            convergence(&KINDS, Kind::Star, 2)
        }),
    ]
}

fn world(seed: u64, m: usize) -> (Field, Rng) {
    world_with(seed, m, KPolicy::default())
}

fn world_with(seed: u64, m: usize, policy: KPolicy) -> (Field, Rng) {
    let mut rng = Rng::new(seed);
    let outer = KINDS[rng.below(4)];
    let ws = random::workspace(&mut rng, m, &KINDS, outer, 0.15);
    (
        Field::all_known_with(Arc::new(ws), policy).expect("valid random world"),
        rng,
    )
}

/// det J > 0 (including 1e-9 from every boundary), round trip Phi⁻¹∘Phi, J and ∇Θ against
/// central differences (`checks::{sample, round_trip, fd_errors}`).
fn diffeomorphism() -> Outcome {
    let (mut min_det, mut worst_j, mut worst_g, mut worst_trip, mut samples) =
        (f64::INFINITY, 0.0f64, 0.0f64, 0.0f64, 0);
    for seed in 0..300u64 {
        let (field, mut rng) = world(1000 + seed, 1 + (seed as usize) % 8);
        let ws = field.workspace();
        for s in 0..60 {
            let th = rng.uniform(-3.1, 3.1);
            let x = if s % 3 == 0 {
                // 1e-9 outside an obstacle or inside the outer boundary.
                near_boundaries(ws, th, 1e-9)[rng.below(ws.obstacles().len() + 1)]
            } else {
                random::free_point(&mut rng, ws, 1e-3)
            };
            let at = |e: checks::Failure| format!("seed {seed}: {e}");
            let sample = checks::sample(&field, x).map_err(at)?;
            if !sample.orientation_preserving() {
                return Err(format!("seed {seed}: det J = {} at {x:?}", sample.det));
            }
            min_det = min_det.min(sample.det);
            samples += 1;
            if s % 3 != 0 {
                worst_trip = worst_trip.max(checks::round_trip(&field, x).map_err(at)?);
                let fd = checks::fd_errors(&field, x).map_err(at)?;
                worst_j = worst_j.max(fd.jacobian);
                if fd.gradient_norm > 1e-6 {
                    worst_g = worst_g.max(fd.gradient / fd.gradient_norm);
                }
            }
        }
    }
    outcome(
        worst_j < 1e-4 && worst_g < 1e-4 && worst_trip < 1e-8,
        format!(
            "300 worlds, {samples} samples: min det J {min_det:.1e} > 0, worst J−FD {worst_j:.1e}, worst ∇Θ−FD {worst_g:.1e} (relative), round trip ≤ {worst_trip:.1e}"
        ),
    )
}

/// Θ ∈ [0, 1] and finite in the open free space; Θ(x_d) = 0; Θ → 1 at every boundary.
fn limits() -> Outcome {
    let mut report = Vec::new();
    for policy in KPolicy::ALL {
        let (lowest, exponent) = limits_under(policy)?;
        // The paper's k = n + 1 keeps Θ near 1 at 1e-12 from a wall; a larger k reaches 1 only
        // as δ^{2Θ/k} (docs/maths.md §8), so only the exponent is required of every policy.
        if policy == KPolicy::Paper && lowest <= 0.85 {
            return Err(format!(
                "k = \"paper\": Θ = {lowest:.3} at 1e-12 from a boundary"
            ));
        }
        if exponent > 1e-2 {
            return Err(format!(
                "k = \"{policy}\": phi_k near an obstacle departs from −(2/k)·ln δ by {exponent:.1e}"
            ));
        }
        report.push(format!(
            "{policy}: Θ ≥ {lowest:.3} at 1e-12 from every boundary, phi_k's rise within {exponent:.1e} of (2/k)·ln 1e3"
        ));
    }
    Ok(format!(
        "300 worlds × 50 free points: Θ ∈ [0,1], finite; Θ(x_d) = 0; {}",
        report.join("; ")
    )
    .into())
}

/// Θ sound at free points (`checks::sample`), `Θ(x_d) = 0`, the lowest Θ at 1e-12 from a
/// boundary, and the worst relative error of the rise of `phi_k` from 1e-9 to 1e-12 off an
/// obstacle against its closed form `(2/k)·ln 1e3` (`checks::limits`).
fn limits_under(policy: KPolicy) -> Result<(f64, f64), String> {
    let mut lowest_near = f64::INFINITY;
    let mut worst_exponent = 0.0f64;
    for seed in 0..300u64 {
        let (field, mut rng) = world_with(2000 + seed, 1 + (seed as usize) % 8, policy);
        let at = |e: checks::Failure| format!("seed {seed}: {e}");
        for _ in 0..50 {
            let x = random::free_point(&mut rng, field.workspace(), 1e-6);
            let s = checks::sample(&field, x).map_err(at)?;
            if !s.is_sound() {
                return Err(format!("seed {seed}: bad evaluation {:?} at {x:?}", s.eval));
            }
        }
        let limits = checks::limits(&field, rng.uniform(-3.1, 3.1), 1e-9, 1e-12).map_err(at)?;
        if limits.at_goal != 0.0 {
            return Err(format!("seed {seed}: Θ(x_d) = {} ≠ 0", limits.at_goal));
        }
        for a in &limits.approaches {
            lowest_near = lowest_near.min(a.theta_near);
            if let Some(rise) = a.rise {
                worst_exponent = worst_exponent.max((rise - 1.0).abs());
            }
        }
    }
    Ok((lowest_near, worst_exponent))
}

/// Theorem isNF: exactly one minimum (x_d) and M saddles, each a zero of ∇Θ
/// (`checks::critical_points`).
fn census() -> Outcome {
    let mut total = 0;
    let mut worst = 0.0f64;
    for seed in 0..300u64 {
        let (field, _) = world(3000 + seed, 1 + (seed as usize) % 10);
        let c = checks::critical_points(&field).map_err(|e| format!("seed {seed}: {e}"))?;
        if c.saddles != c.obstacles {
            return Err(format!(
                "seed {seed}: {} saddles for M = {}",
                c.saddles, c.obstacles
            ));
        }
        worst = worst.max(c.worst_gradient_ratio);
        total += c.obstacles;
    }
    outcome(
        worst < 1e-4,
        format!(
            "300 worlds: 1 minimum + {total} saddles = Σ M; |∇Θ| at them ≤ {worst:.1e} of its value 1e-3 away"
        ),
    )
}

/// Following −∇Θ/|∇Θ| (unit speed, `descent::follow`: the Rosenbrock W-method 2(3) with
/// error control) from 1000 seeded random starts in a 6-obstacle world with `k` from the
/// default policy: ≥ 99.9 % arrive within 100 s, no collision (`checks::convergence`).
fn convergence(kinds: &[Kind], outer: Kind, seed: u64) -> Outcome {
    let mut rng = Rng::new(seed);
    let ws = Arc::new(random::workspace(&mut rng, 6, kinds, outer, 0.2));
    let field = Field::all_known(ws.clone()).map_err(|e| e.to_string())?;
    let starts = (0..1000).map(|_| random::free_point(&mut rng, &ws, 1e-3));
    let c = checks::convergence(&field, starts, &FollowOptions::default());
    outcome(
        c.reached * 1000 >= c.starts * 999 && c.collisions == 0,
        format!(
            "{}/{} reached in ≤ 100 s (median {:.2} s, max {:.2} s), {} collisions, k = {} (policy \"{}\", M = {})",
            c.reached,
            c.starts,
            c.median(),
            c.slowest(),
            c.collisions,
            field.k(),
            KPolicy::default(),
            ws.obstacles().len()
        ),
    )
}
