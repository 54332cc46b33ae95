//! The guarantee monitors: fed every recorded state, measured against the [`Truth`], and
//! judged at the end of a run into the summary's guarantees.

use harmonav::Controller;
use nalgebra::Vector2;

use crate::closed_loop::ClosedLoop;
use crate::guarantee::{Check, Guarantee};
use crate::outcome::Outcome;
use crate::run::{Discovery, Sample, Summary};
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
    /// Set by the integrator when it stopped a run that had come to rest away from the goal:
    /// since when.
    stalled_since: Option<f64>,
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
            stalled_since: None,
        }
    }

    /// The integrator stopped the run at rest away from the goal, at rest since `since`.
    pub(crate) fn stalled(&mut self, since: f64) {
        self.stalled_since = Some(since);
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
        aborted: Option<Guarantee>,
    ) -> Summary {
        let sc = &prepared.scenario;
        let model = lp.model;
        let speed_bound = lp.nav.speed_bound();
        let g = Guarantee::new;
        let margin = prepared.margin();
        let mut guarantees = vec![
            g(
                Check::ReachedGoal {
                    final_distance,
                    tolerance: sc.sim.goal_tolerance,
                    time_s: t,
                    max_time_s: sc.sim.max_time,
                },
                reached,
            ),
            g(
                Check::NoCollision {
                    min_clearance: self.min_clearance,
                    margin,
                },
                self.collisions == 0
                    && self.min_clearance > 0.0
                    && self.min_clearance >= margin - MARGIN_TOLERANCE,
            ),
            g(
                Check::StayedInWorkspace {
                    min_boundary_distance: self.min_boundary,
                },
                self.min_boundary > 0.0,
            ),
            g(
                Check::ThetaInUnitInterval {
                    min: self.theta_range.0,
                    max: self.theta_range.1,
                },
                self.theta_range.0 >= 0.0 && self.theta_range.1 <= 1.0,
            ),
            g(
                Check::Discoveries {
                    discoveries: discoveries
                        .iter()
                        .map(|d| (d.obstacle.clone(), d.time_s))
                        .collect(),
                },
                true,
            ),
        ];
        if let Some(bound) = speed_bound {
            guarantees.push(g(
                Check::SpeedBelowBound {
                    max_speed: self.max_speed,
                    bound,
                },
                self.max_speed < bound,
            ));
            guarantees.push(g(
                Check::EnergyNonIncreasing {
                    largest_rise: self.energy_rise_raw.max(0.0),
                    beyond_tolerance: self.energy_rise.max(0.0),
                },
                self.energy_rise <= 0.0,
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
        if let Some(expected) = expect.reached {
            guarantees.push(g(
                Check::ExpectReached {
                    expected,
                    got: reached,
                },
                expected == reached,
            ));
        }
        if let Some(expected) = expect.discovery_order {
            let got: Vec<String> = discoveries.iter().map(|d| d.obstacle.clone()).collect();
            let passed = got == expected;
            guarantees.push(g(Check::ExpectDiscoveryOrder { expected, got }, passed));
        }
        if let Some(expected) = expect.damping_switched {
            let got = samples.iter().any(|s| s.lambda.is_some() && !s.critical);
            guarantees.push(g(
                Check::ExpectDampingSwitched { expected, got },
                expected == got,
            ));
        }
        if let Some(limit) = expect.max_speed_below {
            guarantees.push(g(
                Check::ExpectMaxSpeedBelow {
                    max_speed: self.max_speed,
                    limit,
                },
                self.max_speed < limit,
            ));
        }
        // A guarantee lost on the way (a step-size collapse, the free space left).
        guarantees.extend(aborted);
        let outcome = Outcome::of(
            &guarantees,
            reached,
            t,
            samples,
            sc.sim.goal_tolerance,
            self.stalled_since,
        )
        .classify_stall(lp.nav.field(), sc.sim.goal_tolerance);
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
            outcome,
            warnings: Vec::new(),
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
    Guarantee::new(
        Check::NoOvershoot {
            samples: tail.len(),
            largest_increase: worst,
        },
        worst <= 1e-9,
    )
}
