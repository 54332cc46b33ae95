//! How a run ended ([`Outcome`]), from its typed guarantees: reached, collision, left the
//! workspace, stalled at a saddle, timed out, step-size collapse, a scan or (on a floor plan) a
//! command refused; and, for a sweep's start outside the free space, an invalid start
//! ([`StartProblem`]). The sweep counts these.

use harmonav_field::Field;
use nalgebra::Vector2;
use serde::Serialize;

use crate::guarantee::{Guarantee, Kind};

/// The share of the run's time a robot must rest (within the goal tolerance of its final
/// position, away from the goal) to be called stalled ([`rested_too_long`]).
pub const STALL_SHARE: f64 = 0.1;

/// Whether a rest since `since` has lasted, at time `t`, the window of a stall:
/// `t − since ≥ max(STALL_SHARE·t, 1 s)`. The one rule by which the driver stops a run
/// (`driver.rs`) and by which [`Outcome::of`] names its end.
pub fn rested_too_long(since: f64, t: f64) -> bool {
    t - since >= (STALL_SHARE * t).max(1.0)
}

/// How a run ended, judged from its typed guarantees and its recorded states.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Outcome {
    /// The goal was reached at `time` s.
    Reached {
        /// Time to the goal, s.
        time: f64,
    },
    /// The robot touched a true obstacle or lost the free space of its known ones.
    Collision,
    /// The robot left the workspace (dynamic law: the monitor `stayed-in-workspace` failed).
    LeftWorkspace,
    /// The robot came to rest away from the goal at `time` s: it stayed within the goal
    /// tolerance of where it ended for the last [`STALL_SHARE`] of the run (at least 1 s), or
    /// the kinematic integrator chattered in place for `driver::STALL_STEPS` steps.
    Stalled {
        /// When, s.
        time: f64,
        /// Where it rests.
        position: [f64; 2],
        /// What is there ([`StallPoint::classify`]).
        point: StallPoint,
    },
    /// `sim.max_time` elapsed first.
    TimedOut {
        /// The time budget, s.
        time: f64,
    },
    /// The integrator's step size collapsed at `time` s.
    StepCollapsed {
        /// When, s.
        time: f64,
    },
    /// A lidar's scan was refused by the navigator at `time` s (the world as perceived is not
    /// a star world, or a perceived shape would cover the robot or the goal): the run stopped.
    ScanRefused {
        /// When, s.
        time: f64,
    },
    /// The navigator refused a command at `time` s (a floor plan's robot in the walls' boundary
    /// layer with no certified step out, `NavError::BoundaryLayer`): the run stopped.
    CommandRefused {
        /// When, s.
        time: f64,
        /// The navigator's error, in words.
        reason: String,
    },
    /// A sweep's start `starts[index]` is not in the free space, so it was not run (sweeps
    /// only: a scenario's own start is checked when the file is loaded).
    InvalidStart {
        /// Its index in the sweep's starts.
        index: usize,
        /// What is wrong with it.
        problem: StartProblem,
    },
}

/// Why a sweep's start is not in the free space (the configuration space of the scenario: its
/// shapes grown by `robot.radius + robot.margin`).
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum StartProblem {
    /// Inside the true shape of obstacle `obstacle`.
    InObstacle {
        /// The obstacle's name.
        obstacle: String,
    },
    /// Outside obstacle `obstacle`'s true shape, but closer to it than `robot.radius +
    /// robot.margin`.
    NearObstacle {
        /// The obstacle's name.
        obstacle: String,
    },
    /// On or outside the true workspace boundary (or not finite).
    OutsideWorkspace,
    /// Inside the true workspace boundary, but closer to it than `robot.radius +
    /// robot.margin`.
    NearBoundary,
    /// On a floor plan: not a start the file's `robot.start` could be (outside the certified
    /// region `W_δ`, within radius + margin of a true obstacle, or above `c_δ` under
    /// `require_certified_start`; `FloorPrepared::check_start`), said in words.
    NotCertified {
        /// What is wrong with it.
        problem: String,
    },
}

impl std::fmt::Display for StartProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::InObstacle { obstacle } => write!(f, "lies inside obstacle {obstacle}"),
            Self::NearObstacle { obstacle } => write!(
                f,
                "lies closer to obstacle {obstacle} than robot.radius + robot.margin"
            ),
            Self::OutsideWorkspace => write!(f, "lies on or outside the workspace boundary"),
            Self::NearBoundary => write!(
                f,
                "lies closer to the workspace boundary than robot.radius + robot.margin"
            ),
            Self::NotCertified { problem } => write!(f, "is not a floor plan's start: {problem}"),
        }
    }
}

impl Outcome {
    /// The outcome of a run: its guarantees first (a collision or lost free space, leaving the
    /// workspace), then arrival, a step-size collapse, a stall (the integrator's `stalled_since`,
    /// or rest at the end of the recording), or the time budget.
    pub fn of(
        guarantees: &[Guarantee],
        reached: bool,
        time: f64,
        rest: &Rest,
        stalled_since: Option<f64>,
    ) -> Self {
        let failed = |kind: Kind| guarantees.iter().any(|g| g.kind() == kind && !g.passed);
        if failed(Kind::NoCollision) || failed(Kind::StayedInFreeSpace) {
            Self::Collision
        } else if failed(Kind::StayedInWorkspace) {
            Self::LeftWorkspace
        } else if reached {
            Self::Reached { time }
        } else if failed(Kind::Integrated) {
            Self::StepCollapsed { time }
        } else if failed(Kind::ScansAccepted) {
            Self::ScanRefused { time }
        } else if let Some(since) =
            stalled_since.or_else(|| rest.since().filter(|&since| rested_too_long(since, time)))
        {
            Self::Stalled {
                time: since,
                position: rest.position().unwrap_or([f64::NAN; 2]),
                point: StallPoint::Unclassified,
            }
        } else {
            Self::TimedOut { time }
        }
    }

    /// The same outcome with a stall's point classified on `field` (the field in force when
    /// the run ended); `tolerance` is the goal tolerance.
    pub fn classify_stall(self, field: &Field, tolerance: f64) -> Self {
        match self {
            Self::Stalled { time, position, .. } => {
                let (point, at) = StallPoint::classify(field, Vector2::from(position), tolerance);
                Self::Stalled {
                    time,
                    position: at.into(),
                    point,
                }
            }
            other => other,
        }
    }

    /// Whether the goal was reached.
    pub fn reached(&self) -> bool {
        matches!(self, Self::Reached { .. })
    }

    /// The name of the outcome, as in the JSON's `"kind"`: `reached`, `collision`,
    /// `left-workspace`, `stalled`, `timed-out`, `step-collapsed`, `scan-refused`,
    /// `command-refused` or `invalid-start`.
    pub fn kind(&self) -> &'static str {
        match self {
            Self::Reached { .. } => "reached",
            Self::Collision => "collision",
            Self::LeftWorkspace => "left-workspace",
            Self::Stalled { .. } => "stalled",
            Self::TimedOut { .. } => "timed-out",
            Self::StepCollapsed { .. } => "step-collapsed",
            Self::ScanRefused { .. } => "scan-refused",
            Self::CommandRefused { .. } => "command-refused",
            Self::InvalidStart { .. } => "invalid-start",
        }
    }

    /// The time the outcome carries (arrival, stall, time budget or collapse), if any.
    pub fn time(&self) -> Option<f64> {
        match self {
            Self::Reached { time }
            | Self::Stalled { time, .. }
            | Self::TimedOut { time }
            | Self::StepCollapsed { time }
            | Self::ScanRefused { time }
            | Self::CommandRefused { time, .. } => Some(*time),
            Self::Collision | Self::LeftWorkspace | Self::InvalidStart { .. } => None,
        }
    }
}

impl std::fmt::Display for Outcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Reached { time } => write!(f, "reached at t = {time:.2} s"),
            Self::Collision => write!(f, "collision"),
            Self::LeftWorkspace => write!(f, "left the workspace"),
            Self::Stalled {
                time,
                position: [x, y],
                point,
            } => write!(
                f,
                "stalled {} ({x:.4}, {y:.4}) at t = {time:.2} s",
                point.phrase()
            ),
            Self::TimedOut { time } => write!(f, "not reached within {time:.2} s"),
            Self::StepCollapsed { time } => write!(f, "step size collapsed at t = {time:.2} s"),
            Self::ScanRefused { time } => write!(f, "a scan was refused at t = {time:.2} s"),
            Self::CommandRefused { time, reason } => {
                write!(
                    f,
                    "the navigator refused a command at t = {time:.2} s: {reason}"
                )
            }
            Self::InvalidStart { index, problem } => {
                write!(f, "not run: starts[{index}] {problem}")
            }
        }
    }
}

/// What lies where a run stalled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum StallPoint {
    /// A saddle of `Θ` (the Hessian's eigenvalues have opposite signs, and Newton's step to the
    /// critical point is shorter than the goal tolerance): the start lay on the saddle's stable
    /// manifold, e.g. a symmetry axis of the world through the goal. Moving the start off it
    /// resolves it; the law cannot, as `∇Θ = 0` there.
    Saddle,
    /// Against a wall: `Θ` cannot be differentiated within 1e-6 m of the point in the free
    /// space.
    Wall,
    /// Not a critical point of `Θ`: the integrator could not follow a stiff valley of `Θ`
    /// (the outer band of a narrow workspace, docs/maths.md §8).
    NotCritical,
    /// Not classified (no field was at hand).
    Unclassified,
}

impl StallPoint {
    /// Classifies `x` on `field`, and returns the critical point's position for a saddle
    /// (`x − H⁻¹∇Θ`, one Newton step) or `x` itself:
    ///
    /// ```text
    /// saddle        det H < 0 and |H⁻¹∇Θ| ≤ tolerance
    /// wall          H not defined (a finite-difference point outside the free space)
    /// not critical  otherwise
    /// ```
    pub fn classify(field: &Field, x: Vector2<f64>, tolerance: f64) -> (Self, Vector2<f64>) {
        let (Ok(h), Ok(e)) = (field.hessian(x), field.eval(x)) else {
            return (Self::Wall, x);
        };
        let newton = h.try_inverse().map(|inv| inv * e.gradient);
        match newton {
            Some(step) if h.determinant() < 0.0 && step.norm() <= tolerance => {
                (Self::Saddle, x - step)
            }
            _ => (Self::NotCritical, x),
        }
    }

    /// How the CLI phrases it: "at a saddle of Θ at", "against a wall at", …
    pub fn phrase(self) -> &'static str {
        match self {
            Self::Saddle => "at a saddle of Θ at",
            Self::Wall => "against a wall at",
            Self::NotCritical => "in a stiff valley of Θ (not a critical point) at",
            Self::Unclassified => "at",
        }
    }
}

/// Since when the robot has been at rest, judged online from every recorded state: the
/// positions since [`Rest::since`] all stay within half the goal tolerance of the one recorded
/// then, so within the tolerance of the last (and of one another). It needs no trajectory in
/// memory, so runs of any length are judged the same way.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rest {
    /// The position the rest is measured from, and since when.
    anchor: Option<([f64; 2], f64)>,
    /// The last recorded position.
    last: Option<[f64; 2]>,
    /// Half the goal tolerance, m.
    radius: f64,
}

impl Rest {
    /// No state recorded yet; `tolerance` is the goal tolerance.
    pub fn new(tolerance: f64) -> Self {
        Self {
            anchor: None,
            last: None,
            radius: 0.5 * tolerance,
        }
    }

    /// The robot was at `x` at time `t`: a move of more than half the tolerance from the
    /// anchor starts a new rest there.
    pub fn observe(&mut self, t: f64, x: [f64; 2]) {
        let moved = |a: [f64; 2]| (Vector2::from(a) - Vector2::from(x)).norm() > self.radius;
        match self.anchor {
            Some((a, _)) if !moved(a) => {}
            _ => self.anchor = Some((x, t)),
        }
        self.last = Some(x);
    }

    /// The start of the current rest (`None` before the first state).
    pub fn since(&self) -> Option<f64> {
        self.anchor.map(|(_, t)| t)
    }

    /// The last recorded position.
    pub fn position(&self) -> Option<[f64; 2]> {
        self.last
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::guarantee::Check;
    use crate::trace::Sample;

    fn at(t: f64, x: f64) -> Sample {
        Sample {
            t,
            x: [x, 0.0],
            v: [0.0; 2],
            theta: 0.5,
            energy: None,
            k: 2.0,
            lambda: None,
            energy_tolerance: 0.0,
            critical: false,
            yaw: None,
        }
    }

    /// Moving until `stop`, then at rest until `end` (one sample per 0.1 s), judged online.
    fn path(stop: f64, end: f64) -> Rest {
        let mut rest = Rest::new(0.01);
        for s in (0..=(end * 10.0) as usize)
            .map(|i| i as f64 * 0.1)
            .map(|t| at(t, t.min(stop)))
        {
            rest.observe(s.t, s.x);
        }
        rest
    }

    #[test]
    fn a_robot_at_rest_away_from_the_goal_stalled_and_a_moving_one_timed_out() {
        let ok = [Guarantee::new(
            Check::NoCollision {
                min_clearance: 0.1,
                margin: 0.0,
            },
            true,
        )];
        let stalled = Outcome::of(&ok, false, 20.0, &path(12.0, 20.0), None);
        assert!(matches!(stalled, Outcome::Stalled { time, position, .. }
            if (time - 12.0).abs() < 0.11 && position == [12.0, 0.0]));
        // At rest for less than 10 % of the run: still moving at the end.
        let moving = Outcome::of(&ok, false, 20.0, &path(19.5, 20.0), None);
        assert_eq!(moving, Outcome::TimedOut { time: 20.0 });
        let reached = Outcome::of(&ok, true, 20.0, &path(12.0, 20.0), None);
        assert_eq!(reached, Outcome::Reached { time: 20.0 });
    }

    #[test]
    fn a_lost_guarantee_decides_before_arrival() {
        let lost = [Guarantee::failed(Check::NoCollision {
            min_clearance: -0.1,
            margin: 0.0,
        })];
        assert_eq!(
            Outcome::of(&lost, true, 5.0, &path(5.0, 5.0), None),
            Outcome::Collision
        );
        let outside = [Guarantee::failed(Check::StayedInWorkspace {
            min_boundary_distance: -0.1,
        })];
        assert_eq!(
            Outcome::of(&outside, false, 5.0, &path(5.0, 5.0), None),
            Outcome::LeftWorkspace
        );
        let collapsed = [Guarantee::failed(Check::StepCollapsed {
            time_s: 3.0,
            position: [0.0; 2],
        })];
        assert_eq!(
            Outcome::of(&collapsed, false, 3.0, &path(3.0, 3.0), None),
            Outcome::StepCollapsed { time: 3.0 }
        );
    }

    #[test]
    fn a_creep_of_many_small_moves_is_not_a_rest() {
        // 1 mm per 0.1 s for 20 s: each move is far below the 5 mm half-tolerance, the whole
        // is 20 cm; the rest starts at most one half-tolerance before the end.
        let mut rest = Rest::new(0.01);
        for i in 0..=200 {
            rest.observe(i as f64 * 0.1, [i as f64 * 1e-3, 0.0]);
        }
        let since = rest.since().unwrap();
        assert!(since > 19.4 && since <= 20.0, "{since}");
        assert_eq!(rest.position(), Some([0.2, 0.0]));
        assert_eq!(Rest::new(0.01).since(), None);
    }
}
