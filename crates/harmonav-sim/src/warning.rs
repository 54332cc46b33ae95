//! Warnings about a scenario that a run's verdict alone would not explain: a start on a
//! saddle's stable manifold (a symmetry axis), a start at a critical point, a goal tolerance
//! comparable to the world ([`crate::preflight::check`] finds them). `physics::simulate`
//! attaches them to the summary; the CLI prints
//! them, the JSON and `summary.json` carry them, and the recording logs them at t = 0.

use serde::Serialize;

/// The share of the start–goal distance (or of the workspace's smallest radius) above which
/// `sim.goal_tolerance` draws a warning.
pub const TOLERANCE_SHARE: f64 = 0.05;

/// A warning about a scenario.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Warning {
    /// The normalised descent of `Θ` (the obstacles known at the start) from the start ends at
    /// this saddle: the start lies on its stable manifold, typically a symmetry axis of the
    /// world through the goal, and the law stops there.
    StartOnSaddleManifold {
        /// The saddle.
        saddle: [f64; 2],
    },
    /// `∇Θ = 0` at the start: the law does not move.
    StartAtCriticalPoint,
    /// `sim.goal_tolerance` is at least [`TOLERANCE_SHARE`] of the start–goal distance or of
    /// the workspace's smallest radius, so "reached" says little.
    GoalToleranceLarge {
        /// `sim.goal_tolerance`, m.
        goal_tolerance: f64,
        /// The smaller of the start–goal distance and the workspace's smallest radius, m.
        scale: f64,
    },
    /// A lidar's scans are so sparse that the robot may cover its fit range, less its radius,
    /// margin and the noise bound, between two of them (top speed over `sensor.rate_hz`): an
    /// obstacle may be reached before it is fitted (docs/maths.md §12.16, eq. fitnear).
    ScansTooSparse {
        /// The most the robot moves between two scans, m.
        travel: f64,
        /// The fit range less the robot's radius, margin and the noise bound, m.
        room: f64,
    },
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::StartOnSaddleManifold { saddle: [x, y] } => write!(
                f,
                "the descent from the start ends at a saddle of Θ at ({x:.4}, {y:.4}): the start \
                 lies on its stable manifold (a symmetry axis through the goal?) and the law stops \
                 there; move the start off the axis"
            ),
            Self::StartAtCriticalPoint => {
                write!(
                    f,
                    "∇Θ = 0 at the start: the law does not move; move the start"
                )
            }
            Self::GoalToleranceLarge {
                goal_tolerance,
                scale,
            } => write!(
                f,
                "sim.goal_tolerance = {goal_tolerance:e} m is comparable to the world ({scale:e} \
                 m): arrival within it says little"
            ),
            Self::ScansTooSparse { travel, room } => write!(
                f,
                "the robot may move {travel:.3e} m between two lidar scans, at least its fit range \
                 less its radius, margin and noise bound ({room:.3e} m): an obstacle may be \
                 reached before it is fitted; raise sensor.rate_hz or sensor.range"
            ),
        }
    }
}
