//! The guarantee monitors: fed every recorded state, measured against the [`Truth`], and
//! judged at the end of a run into the summary's guarantees.

use harmonav::Controller;
use nalgebra::Vector2;

use crate::closed_loop::ClosedLoop;
use crate::run::{Discovery, Guarantee, Sample, Summary};
use crate::scenario::{ExpectSpec, Prepared};
use crate::truth::Truth;

/// How far below `robot.margin` the measured clearance may fall and still pass: the offset
/// outlines of non-circular shapes are Hermite tables (`StarShape::offset`) and the exact
/// distances are refined to ~1e-9 m, so the grown shapes sit within this of the true offset.
pub const MARGIN_TOLERANCE: f64 = 1e-6;

/// Guarantee monitors, fed every accepted state.
pub(crate) struct Monitor {
    min_clearance: f64,
    min_boundary: f64,
    collisions: usize,
    max_speed: f64,
    theta_range: (f64, f64),
    /// The largest rise of `V` between consecutive states beyond their integration tolerances,
    /// relative to `V` (0 if none).
    energy_rise: f64,
    /// The largest relative rise of `V` between consecutive states, tolerance included.
    energy_rise_raw: f64,
    last_energy: Option<(f64, f64)>,
}

impl Monitor {
    pub(crate) fn new() -> Self {
        Self {
            min_clearance: f64::INFINITY,
            min_boundary: f64::INFINITY,
            collisions: 0,
            max_speed: 0.0,
            theta_range: (f64::INFINITY, f64::NEG_INFINITY),
            energy_rise: 0.0,
            energy_rise_raw: 0.0,
            last_energy: None,
        }
    }

    /// Called after every accepted step (and every recorded sample of the rapier run).
    pub(crate) fn observe(&mut self, s: &Sample, discovered: bool, truth: &Truth) {
        let x = Vector2::new(s.x[0], s.x[1]);
        let (obstacle, boundary) = truth.clearances(x);
        let clearance = obstacle.min(boundary);
        self.min_clearance = self.min_clearance.min(clearance);
        self.min_boundary = self.min_boundary.min(boundary);
        if clearance <= 0.0 {
            self.collisions += 1;
        }
        self.max_speed = self.max_speed.max(Vector2::new(s.v[0], s.v[1]).norm());
        self.theta_range = (
            self.theta_range.0.min(s.theta),
            self.theta_range.1.max(s.theta),
        );
        if let Some(v) = s.energy {
            if let (Some((last, tol)), false) = (self.last_energy, discovered) {
                // Guard: V is positive away from the goal; at the goal both are ~0.
                let scale = last.max(1e-12);
                let excess = v - last - (tol + s.energy_tolerance);
                self.energy_rise = self.energy_rise.max(excess / scale);
                self.energy_rise_raw = self.energy_rise_raw.max((v - last) / scale);
            }
            self.last_energy = Some((v, s.energy_tolerance));
        }
    }

    #[allow(clippy::too_many_arguments)]
    pub(crate) fn finish(
        self,
        prepared: &Prepared,
        lp: &ClosedLoop,
        reached: bool,
        t: f64,
        final_distance: f64,
        discoveries: Vec<Discovery>,
        steps: usize,
        rejected: usize,
        samples: &[Sample],
    ) -> Summary {
        let sc = &prepared.scenario;
        let model = lp.model;
        let speed_bound = lp.nav.speed_bound();
        let g = |name: &str, passed: bool, detail: String| Guarantee {
            name: name.to_string(),
            passed,
            detail,
        };
        let mut guarantees = vec![
            g(
                "reached-goal",
                reached,
                format!(
                    "final distance {final_distance:.2e} m (tolerance {}) at t = {t:.3} s (max {} s)",
                    sc.sim.goal_tolerance, sc.sim.max_time
                ),
            ),
            g(
                "no-collision",
                self.collisions == 0
                    && self.min_clearance > 0.0
                    && self.min_clearance >= prepared.margin() - MARGIN_TOLERANCE,
                format!(
                    "min clearance {:.4} m to the true obstacles and boundary (margin {} m)",
                    self.min_clearance,
                    prepared.margin()
                ),
            ),
            g(
                "stayed-in-workspace",
                self.min_boundary > 0.0,
                format!("min distance to the boundary {:.4} m", self.min_boundary),
            ),
            g(
                "theta-in-unit-interval",
                self.theta_range.0 >= 0.0 && self.theta_range.1 <= 1.0,
                format!(
                    "Θ ∈ [{:.3e}, {:.6}]",
                    self.theta_range.0, self.theta_range.1
                ),
            ),
            g(
                "discoveries",
                true,
                if discoveries.is_empty() {
                    "none".to_string()
                } else {
                    discoveries
                        .iter()
                        .map(|d| format!("{} at {:.3} s", d.obstacle, d.time_s))
                        .collect::<Vec<_>>()
                        .join(", ")
                },
            ),
        ];
        if let Some(bound) = speed_bound {
            guarantees.push(g(
                "speed-below-bound",
                self.max_speed < bound,
                format!(
                    "max speed {:.3} m/s < √(2μ/m) = {bound:.3} m/s",
                    self.max_speed
                ),
            ));
            guarantees.push(g(
                "energy-non-increasing-between-discoveries",
                self.energy_rise <= 0.0,
                format!(
                    "largest relative rise of V between states {:.1e}, {:.1e} beyond the \
                     integration tolerance",
                    self.energy_rise_raw.max(0.0),
                    self.energy_rise.max(0.0)
                ),
            ));
            guarantees.push(overshoot(samples, prepared.truth.goal(), &discoveries));
        }
        // `[expect]` describes a run of the file's own robot model; a run with the other model
        // (`harmonav run --controller …`) is judged on the guarantees alone.
        let expect = if model == sc.robot.model {
            sc.expect.clone().unwrap_or_default()
        } else {
            ExpectSpec::default()
        };
        if let Some(want) = expect.reached {
            guarantees.push(g(
                "expect.reached",
                want == reached,
                format!("expected {want}, got {reached}"),
            ));
        }
        if let Some(order) = &expect.discovery_order {
            let got: Vec<String> = discoveries.iter().map(|d| d.obstacle.clone()).collect();
            guarantees.push(g(
                "expect.discovery-order",
                &got == order,
                format!("expected {order:?}, got {got:?}"),
            ));
        }
        if let Some(want) = expect.damping_switched {
            let switched = samples.iter().any(|s| s.lambda.is_some() && !s.critical);
            guarantees.push(g(
                "expect.damping-switched",
                want == switched,
                format!("expected {want}, got {switched}"),
            ));
        }
        if let Some(limit) = expect.max_speed_below {
            guarantees.push(g(
                "expect.max-speed-below",
                self.max_speed < limit,
                format!("max speed {:.3} m/s, limit {limit} m/s", self.max_speed),
            ));
        }
        Summary {
            name: sc.name.clone(),
            model,
            physics: "builtin".into(),
            k_policy: prepared.k_policy().as_str(),
            damping: match lp.nav.controller() {
                Controller::Dynamic(law) => Some(law.damping_policy().as_str()),
                Controller::Kinematic(_) => None,
            },
            reached,
            time_s: t,
            final_distance,
            min_clearance: self.min_clearance,
            max_speed: self.max_speed,
            speed_bound,
            collisions: self.collisions,
            physics_contacts: None,
            discoveries,
            guarantees,
            steps,
            rejected_steps: rejected,
        }
    }
}

/// No overshoot with critical damping (corollary `critdamp`): in the last approach — the
/// trailing samples after the last discovery with the damping in its critical branch (`λ_c`, or
/// `λ(x, ẋ)` under `"auto"`, which tends to it) and `Θ < 0.01` (the quadratic basin of the
/// goal) — the distance to the goal never increases.
fn overshoot(samples: &[Sample], goal: Vector2<f64>, discoveries: &[Discovery]) -> Guarantee {
    let last_discovery = discoveries.last().map_or(0.0, |d| d.time_s);
    let tail: Vec<&Sample> = samples
        .iter()
        .rev()
        .take_while(|s| s.critical && s.theta < 0.01 && s.t >= last_discovery)
        .collect();
    let dist = |s: &Sample| (Vector2::new(s.x[0], s.x[1]) - goal).norm();
    let mut worst: f64 = 0.0;
    for w in tail.windows(2) {
        // `tail` runs backwards in time: w[1] precedes w[0].
        worst = worst.max(dist(w[0]) - dist(w[1]));
    }
    Guarantee {
        name: "no-overshoot-at-goal".into(),
        passed: worst <= 1e-9,
        detail: if tail.len() < 2 {
            "the run did not enter the critically damped goal basin".into()
        } else {
            format!(
                "{} samples in the last approach (Θ < 0.01, critical damping): largest increase of the distance {worst:.1e} m",
                tail.len()
            )
        },
    }
}
