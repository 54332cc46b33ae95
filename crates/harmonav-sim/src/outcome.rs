//! How a run ended ([`Outcome`]), from its typed guarantees: reached, collision, left the
//! workspace, stalled at a saddle, timed out, step-size collapse. The sweep counts these.

use nalgebra::Vector2;
use serde::Serialize;

use crate::guarantee::{Guarantee, Kind};
use crate::run::Sample;

/// The share of the run's time a robot must rest (within the goal tolerance of its final
/// position, away from the goal) to be called stalled.
pub const STALL_WINDOW: f64 = 0.1;

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
    /// The robot stopped at a critical point of `Θ` (a saddle) at `time` s: it stayed within
    /// the goal tolerance of where it ended for the last [`STALL_WINDOW`] of the run (at least
    /// 1 s) without reaching the goal.
    Stalled {
        /// When, s.
        time: f64,
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
}

impl Outcome {
    /// The outcome of a run: its guarantees first (a collision or lost free space, leaving the
    /// workspace), then arrival, a step-size collapse, a stall (the integrator's `stalled_since`,
    /// or rest at the end of the recording), or the time budget.
    pub fn of(
        guarantees: &[Guarantee],
        reached: bool,
        time: f64,
        samples: &[Sample],
        goal_tolerance: f64,
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
        } else if let Some(since) = stalled_since {
            Self::Stalled { time: since }
        } else if let Some(since) = rest_since(samples, goal_tolerance)
            && time - since >= (STALL_WINDOW * time).max(1.0)
        {
            Self::Stalled { time: since }
        } else {
            Self::TimedOut { time }
        }
    }

    /// Whether the goal was reached.
    pub fn reached(&self) -> bool {
        matches!(self, Self::Reached { .. })
    }

    /// The name of the outcome, as in the JSON's `"kind"`: `reached`, `collision`,
    /// `left-workspace`, `stalled`, `timed-out` or `step-collapsed`.
    pub fn kind(&self) -> &'static str {
        match self {
            Self::Reached { .. } => "reached",
            Self::Collision => "collision",
            Self::LeftWorkspace => "left-workspace",
            Self::Stalled { .. } => "stalled",
            Self::TimedOut { .. } => "timed-out",
            Self::StepCollapsed { .. } => "step-collapsed",
        }
    }

    /// The time the outcome carries (arrival, stall, time budget or collapse), if any.
    pub fn time(&self) -> Option<f64> {
        match self {
            Self::Reached { time }
            | Self::Stalled { time }
            | Self::TimedOut { time }
            | Self::StepCollapsed { time } => Some(*time),
            Self::Collision | Self::LeftWorkspace => None,
        }
    }
}

impl std::fmt::Display for Outcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Reached { time } => write!(f, "reached at t = {time:.2} s"),
            Self::Collision => write!(f, "collision"),
            Self::LeftWorkspace => write!(f, "left the workspace"),
            Self::Stalled { time } => write!(f, "stalled at a critical point at t = {time:.2} s"),
            Self::TimedOut { time } => write!(f, "not reached within {time:.2} s"),
            Self::StepCollapsed { time } => write!(f, "step size collapsed at t = {time:.2} s"),
        }
    }
}

/// The earliest time from which every recorded position stays within `tolerance` of the last.
fn rest_since(samples: &[Sample], tolerance: f64) -> Option<f64> {
    let last = samples.last()?;
    let end = Vector2::new(last.x[0], last.x[1]);
    let moved = |s: &&Sample| (Vector2::new(s.x[0], s.x[1]) - end).norm() > tolerance;
    let i = samples.iter().rposition(|s| moved(&s)).map_or(0, |i| i + 1);
    Some(samples[i].t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::guarantee::Check;

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
        }
    }

    /// Moving until `stop`, then at rest until `end` (one sample per 0.1 s).
    fn path(stop: f64, end: f64) -> Vec<Sample> {
        (0..=(end * 10.0) as usize)
            .map(|i| i as f64 * 0.1)
            .map(|t| at(t, t.min(stop)))
            .collect()
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
        let stalled = Outcome::of(&ok, false, 20.0, &path(12.0, 20.0), 0.01, None);
        assert!(matches!(stalled, Outcome::Stalled { time } if (time - 12.0).abs() < 0.11));
        // At rest for less than 10 % of the run: still moving at the end.
        let moving = Outcome::of(&ok, false, 20.0, &path(19.5, 20.0), 0.01, None);
        assert_eq!(moving, Outcome::TimedOut { time: 20.0 });
        let reached = Outcome::of(&ok, true, 20.0, &path(12.0, 20.0), 0.01, None);
        assert_eq!(reached, Outcome::Reached { time: 20.0 });
    }

    #[test]
    fn a_lost_guarantee_decides_before_arrival() {
        let lost = [Guarantee::failed(Check::NoCollision {
            min_clearance: -0.1,
            margin: 0.0,
        })];
        assert_eq!(
            Outcome::of(&lost, true, 5.0, &path(5.0, 5.0), 0.01, None),
            Outcome::Collision
        );
        let outside = [Guarantee::failed(Check::StayedInWorkspace {
            min_boundary_distance: -0.1,
        })];
        assert_eq!(
            Outcome::of(&outside, false, 5.0, &path(5.0, 5.0), 0.01, None),
            Outcome::LeftWorkspace
        );
        let collapsed = [Guarantee::failed(Check::StepCollapsed {
            time_s: 3.0,
            position: [0.0; 2],
        })];
        assert_eq!(
            Outcome::of(&collapsed, false, 3.0, &path(3.0, 3.0), 0.01, None),
            Outcome::StepCollapsed { time: 3.0 }
        );
    }
}
