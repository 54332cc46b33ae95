//! The guarantee monitors: fed every state online, measured against the [`Truth`], and
//! judged at the end of a run into the summary's guarantees. They keep `O(1)` memory, so a
//! run of any length is judged on every one of its states; what stays in memory for figures
//! is the bounded [`Trajectory`].

use harmonav::{Controller, Navigator};
use harmonav_scenario::{ExpectSpec, Model, Prepared, Truth};
use nalgebra::Vector2;

use crate::guarantee::{Check, Guarantee, MARGIN_TOLERANCE};
use crate::outcome::{Outcome, Rest};
use crate::summary::Summary;
use crate::trace::{Discovery, Event, Sample, ScanRecord};
use crate::trajectory::{Keep, Trajectory};

/// How a run ended, as its integrator saw it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct End {
    /// Within the goal tolerance.
    pub reached: bool,
    /// The time at the end, s.
    pub time: f64,
    /// The distance to the goal at the end, m.
    pub final_distance: f64,
    /// Accepted integration steps.
    pub steps: usize,
    /// Rejected integration steps.
    pub rejected: usize,
    /// The integrator.
    pub physics: crate::summary::Physics,
}

/// What a state's [`Sample::energy_tolerance`] bounds, by the integrator's own error model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum EnergyError {
    /// The error of `V` at each state (the built-in integrator's local error bound): a rise
    /// from one judged state to the next may be the sum of both states' errors.
    PerState,
    /// The energy error of the steps since the previous judged state (a fixed-step
    /// integrator's drift, rapier's semi-implicit Euler step), carried by the later state
    /// alone: the allowance of a rise is that state's tolerance, not the sum of two.
    PerInterval,
}

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
    /// What [`Sample::energy_tolerance`] bounds.
    energy_error: EnergyError,
    /// Set by the integrator when it stopped a run that had come to rest away from the goal:
    /// since when.
    stalled_since: Option<f64>,
    /// Since when the recorded states have been at rest.
    rest: Rest,
    /// The last approach of the recorded states, for [`overshoot`].
    approach: Approach,
    /// Whether a recorded state had the damping switched (`λ` in force, not critical).
    damping_switched: bool,
    /// The length of the recorded path, m, and its last point.
    path: (f64, Option<Vector2<f64>>),
    /// Recorded states.
    recorded: usize,
}

/// The last approach to the goal, judged online (corollary `critdamp`): the trailing recorded
/// states since the last discovery with the damping in its critical branch and `Θ < 0.01`, and
/// the largest increase of the distance to the goal between two consecutive ones.
#[derive(Clone, Copy, Debug, Default)]
struct Approach {
    /// Recorded states in the approach.
    len: usize,
    /// Of those, the trailing ones at the time of the last.
    at_last_t: usize,
    /// The largest increase of the distance to the goal, m.
    worst: f64,
    /// The last state's time and distance to the goal.
    last: Option<(f64, f64)>,
}

impl Approach {
    /// A recorded state at time `t`, `distance` from the goal; `inside`: critical damping and
    /// `Θ < 0.01`.
    fn observe(&mut self, t: f64, distance: f64, inside: bool) {
        if !inside {
            *self = Self::default();
            return;
        }
        match self.last {
            Some((last_t, last_d)) => {
                self.worst = self.worst.max(distance - last_d);
                self.at_last_t = if t == last_t { self.at_last_t + 1 } else { 1 };
            }
            None => self.at_last_t = 1,
        }
        self.len += 1;
        self.last = Some((t, distance));
    }

    /// A discovery at time `t`: the approach starts again there. The states recorded at `t`
    /// itself, the discovery's first side, stay in it (both sides lie at one position).
    fn discovery(&mut self, t: f64) {
        match self.last {
            Some((last_t, _)) if last_t == t => {
                self.len = self.at_last_t;
                self.worst = 0.0;
            }
            _ => *self = Self::default(),
        }
    }
}

impl Monitor {
    /// Monitors for a run whose goal tolerance is `tolerance`, its states' energy tolerances
    /// bounding `energy_error`.
    pub(crate) fn new(tolerance: f64, energy_error: EnergyError) -> Self {
        Self {
            min_clearance: f64::INFINITY,
            min_boundary: f64::INFINITY,
            collisions: 0,
            max_speed: 0.0,
            theta_range: (f64::INFINITY, f64::NEG_INFINITY),
            energy_rise: 0.0,
            energy_rise_raw: 0.0,
            last_energy: None,
            energy_error,
            stalled_since: None,
            rest: Rest::new(tolerance),
            approach: Approach::default(),
            damping_switched: false,
            path: (0.0, None),
            recorded: 0,
        }
    }

    /// The integrator stopped the run at rest away from the goal, at rest since `since`.
    pub(crate) fn stalled(&mut self, since: f64) {
        self.stalled_since = Some(since);
    }

    /// A recorded state: besides [`Monitor::observe`], the judgements made on the recording
    /// (rest, the last approach, the damping switch, the path length). `discovered`: the
    /// state is a discovery's second side.
    fn recorded(&mut self, s: &Sample, discovered: bool, goal: Vector2<f64>) {
        let x = Vector2::from(s.x);
        self.recorded += 1;
        self.rest.observe(s.t, s.x);
        if discovered {
            self.approach.discovery(s.t);
        }
        self.approach
            .observe(s.t, (x - goal).norm(), s.critical && s.theta < 0.01);
        self.damping_switched |= s.lambda.is_some() && !s.critical;
        if let Some(last) = self.path.1 {
            self.path.0 += (x - last).norm();
        }
        self.path.1 = Some(x);
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
                let allowance = match self.energy_error {
                    EnergyError::PerState => tol + s.energy_tolerance,
                    EnergyError::PerInterval => s.energy_tolerance,
                };
                let excess = v - last - allowance;
                self.energy_rise = self.energy_rise.max(excess / scale);
                self.energy_rise_raw = self.energy_rise_raw.max((v - last) / scale);
            }
            self.last_energy = Some((v, s.energy_tolerance));
        }
    }

    /// The summary of the run of `model` that ended at `end`, `nav` the robot's navigator
    /// then; `later`: the guarantees judged elsewhere (a lidar's perception, a guarantee lost
    /// on the way), appended before the outcome is found.
    pub(crate) fn finish(
        self,
        prepared: &Prepared,
        model: Model,
        nav: &Navigator,
        end: End,
        discoveries: Vec<Discovery>,
        later: Vec<Guarantee>,
    ) -> Summary {
        let End {
            reached,
            time: t,
            final_distance,
            steps,
            rejected,
            physics,
        } = end;
        let sc = &prepared.scenario;
        let speed_bound = nav.speed_bound();
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
            guarantees.push(self.approach.judge());
        }
        // `[expect]` describes a run of the file's own robot model; a run with the other model
        // (`harmonav run --model …`) is judged on the guarantees alone.
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
            let got = self.damping_switched;
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
        // A lidar's perception, then a guarantee lost on the way (a step-size collapse, the
        // free space left).
        guarantees.extend(later);
        let outcome = Outcome::of(&guarantees, reached, t, &self.rest, self.stalled_since)
            .classify_stall(nav.field(), sc.sim.goal_tolerance);
        Summary {
            name: sc.name.clone(),
            model,
            physics,
            k_policy: prepared.k_policy(),
            damping: match nav.controller() {
                Controller::Dynamic(law) => Some(law.damping_policy()),
                Controller::Kinematic(_) => None,
            },
            reached,
            time_s: t,
            final_distance,
            min_clearance: self.min_clearance,
            path_length: self.path.0,
            max_speed: self.max_speed,
            speed_bound,
            collisions: self.collisions,
            physics_contacts: None,
            discoveries,
            guarantees,
            outcome,
            warnings: Vec::new(),
            recorded_states: self.recorded,
            steps,
            rejected_steps: rejected,
            perception: None,
            movers: None,
            fleet: None,
            diff: None,
        }
    }
}

impl Approach {
    /// No overshoot with critical damping (corollary `critdamp`): in the last approach the
    /// distance to the goal never increases (by more than 1e-9 m).
    fn judge(&self) -> Guarantee {
        Guarantee::new(
            Check::NoOvershoot {
                samples: self.len,
                largest_increase: self.worst,
            },
            self.worst <= 1e-9,
        )
    }
}

/// A run's monitors, its kept trajectory and the caller's observer, fed together: what the
/// built-in integrator and the rapier harness both do with a state.
pub(crate) struct Recorder<'o> {
    pub monitor: Monitor,
    kept: Trajectory,
    observer: &'o mut dyn FnMut(Event<'_>),
    goal: Vector2<f64>,
    /// The time of the last recorded state.
    last_t: Option<f64>,
}

impl<'o> Recorder<'o> {
    /// A recorder for a run to `goal` (tolerance `tolerance`, energy tolerances bounding
    /// `energy_error`); every recorded state also goes to `observer`.
    pub fn new(
        goal: Vector2<f64>,
        tolerance: f64,
        energy_error: EnergyError,
        observer: &'o mut dyn FnMut(Event<'_>),
    ) -> Self {
        Self {
            monitor: Monitor::new(tolerance, energy_error),
            kept: Trajectory::default(),
            observer,
            goal,
            last_t: None,
        }
    }

    /// A state the monitors judge but the recording leaves out (an integration step's end).
    pub fn step(&mut self, s: &Sample, discovered: bool, truth: &Truth) {
        self.monitor.observe(s, discovered, truth);
    }

    /// A recorded state: judged, offered to the observer and kept as `keep` says.
    /// `discovered`: it is a discovery's second side (`V` may jump there).
    pub fn record(&mut self, s: Sample, keep: Keep, discovered: bool, truth: &Truth) {
        self.monitor.observe(&s, discovered, truth);
        self.monitor.recorded(&s, discovered, self.goal);
        (self.observer)(Event::State(&s));
        self.last_t = Some(s.t);
        self.kept.push(s, keep);
    }

    /// Any other event (the movers' frames), for the observer.
    pub fn observe(&mut self, event: Event<'_>) {
        (self.observer)(event);
    }

    /// A lidar scan, for the observer.
    pub fn scanned(&mut self, scan: &ScanRecord) {
        (self.observer)(Event::Scan(scan));
    }

    /// Obstacles that became known, for the observer.
    pub fn discovered(&mut self, discoveries: &[Discovery]) {
        for d in discoveries {
            (self.observer)(Event::Discovery(d));
        }
    }

    /// The time of the last recorded state.
    pub fn last_time(&self) -> Option<f64> {
        self.last_t
    }

    /// The monitors and the kept states.
    pub fn into_parts(self) -> (Monitor, Vec<Sample>) {
        (self.monitor, self.kept.into_samples())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(t: f64, energy: f64, energy_tolerance: f64) -> Sample {
        Sample {
            t,
            x: [1.0, 0.0],
            v: [0.0; 2],
            theta: 0.5,
            energy: Some(energy),
            k: 2.0,
            lambda: Some(1.0),
            energy_tolerance,
            critical: true,
            yaw: None,
        }
    }

    /// A fixed-step integrator's tolerance is the drift of the interval it ends: a rise of 1.5
    /// times that drift is beyond it, though within the sum of two states' tolerances (the
    /// allowance that counted the previous interval's drift twice).
    #[test]
    fn an_interval_drift_is_allowed_once() {
        let truth = harmonav_scenario::Scenario::parse(
            std::path::Path::new("w.toml"),
            "name = \"w\"\n[workspace]\ntype = \"circle\"\ncenter = [0.0, 0.0]\nradius = 5.0\n\
             [robot]\nmodel = \"dynamic\"\nstart = [-3.0, 0.0]\ngoal = [3.0, 0.0]\n",
        )
        .unwrap()
        .prepare(std::path::Path::new("w.toml"))
        .unwrap()
        .truth;
        let drift = 1e-3;
        let rises = |energy_error| {
            let mut m = Monitor::new(0.01, energy_error);
            m.observe(&state(0.0, 1.0, drift), false, &truth);
            m.observe(&state(0.1, 1.0 + 1.5 * drift, drift), false, &truth);
            m.energy_rise
        };
        assert!(
            rises(EnergyError::PerInterval) > 0.0,
            "beyond the interval's drift"
        );
        assert!(
            rises(EnergyError::PerState) <= 0.0,
            "within two states' errors"
        );
    }

    #[test]
    fn the_last_approach_restarts_at_a_discovery_and_keeps_its_first_side() {
        let mut a = Approach::default();
        // Away, then back: an increase of 0.1 m inside the approach.
        for (t, d) in [(0.0, 0.5), (1.0, 0.6), (2.0, 0.4)] {
            a.observe(t, d, true);
        }
        assert!(a.len == 3 && (a.worst - 0.1).abs() < 1e-12);
        // A discovery at t = 3 after a state recorded at t = 3: that state stays in.
        a.observe(3.0, 0.3, true);
        a.discovery(3.0);
        a.observe(3.0, 0.3, true);
        assert_eq!((a.len, a.worst), (2, 0.0));
        a.observe(4.0, 0.35, true);
        assert!((a.worst - 0.05).abs() < 1e-12);
        assert!(!a.judge().passed);
        // A discovery at a later time than the last state, or a state outside: from scratch.
        a.discovery(5.0);
        assert_eq!(a.len, 0);
        a.observe(5.0, 0.2, true);
        a.observe(6.0, 0.1, false);
        assert_eq!((a.len, a.worst), (0, 0.0));
        a.observe(7.0, 0.1, true);
        a.observe(8.0, 0.05, true);
        assert!(a.judge().passed);
    }
}
