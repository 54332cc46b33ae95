//! What a run produces as it goes: the recorded states ([`Sample`]), the discoveries
//! ([`Discovery`]) and the events an observer is handed in time order ([`Event`]). Below the
//! loop: every module of the closed loop may use it; it uses only [`crate::warning`] (the
//! events carry warnings).

use harmonav::{LaserScan, Pose, StarShape};
use serde::Serialize;

use crate::warning::Warning;

/// One recorded state.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Sample {
    /// Time, s.
    pub t: f64,
    /// Position.
    pub x: [f64; 2],
    /// Velocity.
    pub v: [f64; 2],
    /// `Θ(x)`.
    pub theta: f64,
    /// `V = μ_pΨ + ½m|ẋ|²` (dynamic law, `μ_p` its pull, `Dynamic::pull`; `Ψ` its potential under the damping policy, `Θ`
    /// itself under `"paper"`).
    pub energy: Option<f64>,
    /// `k` in force (its policy: the summary's `k_policy`; `n + 1` under `"paper"`).
    pub k: f64,
    /// Damping `λ` in force (dynamic model).
    pub lambda: Option<f64>,
    /// How much `V` may differ from the exact solution's through integration error alone
    /// (dynamic model), by the integrator's own error model: for the built-in one, the error
    /// at this state, its local error bound ([`crate::run::step_tolerance`]) times the
    /// sensitivity `μ_p|∇Ψ| + m|ẋ|` of `V` to the state, times a safety factor of 10 (a rise
    /// between two states may use both states' errors); for rapier, the energy error of the
    /// fixed steps since the previous recorded state (`rapier.rs`), allowed once.
    #[serde(skip)]
    pub energy_tolerance: f64,
    /// Whether the damping is in its `V < μ_p` branch, critical at the goal (`λ_c` under the
    /// `"paper"` policy, `λ(x)` under `"auto"`), rather than switched (dynamic model).
    pub critical: bool,
    /// The heading `θ`, rad, of a differential-drive robot (`[robot] base = "diff"`; docs/unicycle.md,
    /// "Simulator"); `None` for a holonomic robot, whose recording shows the velocity's
    /// direction (and whose JSON is as before).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub yaw: Option<f64>,
}

/// The velocity a [`Sample`] records: `ẋ` under the dynamic law; under the kinematic one the
/// law's velocity `u` at the state (`law`), zero where the law has none.
pub(crate) fn recorded_velocity(
    dynamic: bool,
    v: nalgebra::Vector2<f64>,
    law: Option<nalgebra::Vector2<f64>>,
) -> [f64; 2] {
    match (dynamic, law) {
        (true, _) => [v.x, v.y],
        (false, Some(u)) => [u.x, u.y],
        (false, None) => [0.0; 2],
    }
}

/// A discovery event.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Discovery {
    /// Obstacle name.
    pub obstacle: String,
    /// Obstacle index in the scenario.
    #[serde(skip)]
    pub index: usize,
    /// Time, s.
    pub time_s: f64,
    /// Robot position at discovery.
    #[serde(skip)]
    pub position: [f64; 2],
    /// Sector axis at discovery.
    #[serde(skip)]
    pub axis: [f64; 2],
}

/// What a run hands its observer as it goes, in time order ([`crate::run::run_observed`]).
/// A floor plan's loop ([`crate::floor::run_observed`]) hands each state once, after that
/// state's scan and discoveries: its `Θ` is that of the world known from then on.
#[derive(Clone, Copy, Debug)]
pub enum Event<'a> {
    /// A warning about the scenario, before the run starts
    /// ([`crate::physics::simulate_observed`]).
    Warning(&'a Warning),
    /// An obstacle became known (those known at the start come before the first state).
    Discovery(&'a Discovery),
    /// A recorded state (a discovery's first side comes before its [`Event::Discovery`], the
    /// second after).
    State(&'a Sample),
    /// A lidar scan (`[sensor] type = "lidar"`), after the navigator observed it (a scan that
    /// changed the obstacles comes between the two sides of its state, as a discovery does).
    Scan(&'a ScanRecord),
    /// The movers (`[[movers]]`) at the time of a state, every [`MOVER_FRAME_PERIOD`] of
    /// simulated time.
    Movers(&'a MoverFrame),
}

/// Simulated seconds between two [`MoverFrame`]s of a run with movers (10 Hz: a person at
/// 1.5 m/s moves 0.15 m between two).
pub const MOVER_FRAME_PERIOD: f64 = 0.1;

/// Whether a frame at `t` is due after the frames kept so far: none yet, or
/// [`MOVER_FRAME_PERIOD`] since the last (up to rounding).
pub(crate) fn frame_due(frames: &[MoverFrame], t: f64) -> bool {
    frames
        .last()
        .is_none_or(|f| t - f.t >= MOVER_FRAME_PERIOD * (1.0 - 1e-9))
}

/// The movers at one instant, and how the robot's last command was formed: what the recording
/// and `trajectory.svg` draw (issue 54, item 4).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MoverFrame {
    /// Time, s.
    pub t: f64,
    /// The robot's position.
    pub robot: [f64; 2],
    /// The mode of the robot's last command (`Mode::as_str`: `"yielding"`, `"overwhelmed"`,
    /// …; `"refused"` when its disc overlapped a reported mover's), `None` before the first.
    pub mode: Option<&'static str>,
    /// Every mover, in the file's order.
    pub movers: Vec<MoverMark>,
}

/// One mover in a [`MoverFrame`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MoverMark {
    /// Its true centre.
    pub position: [f64; 2],
    /// Its radius, m.
    pub radius: f64,
    /// The radius of the disc it may reach within one control period as the robot's filter
    /// sees it: `radius + ε + V·h` (report error `ε`, speed bound `V`), m.
    pub reach: f64,
    /// Reciprocal (another harmonav robot taking a share), not non-cooperative.
    pub reciprocal: bool,
}

/// One scan of a simulated lidar, as the navigator got it and what it made of it.
#[derive(Clone, Debug)]
pub struct ScanRecord {
    /// Time, s.
    pub time_s: f64,
    /// The sensor's pose (the robot's centre; heading: the sector's axis).
    pub pose: Pose,
    /// The scan as the navigator got it (noise, dropouts, `+∞` for no return).
    pub scan: LaserScan,
    /// When the scan changed the obstacles (an event): the perceived shapes after it, not
    /// grown by the robot's radius and margin. `None`: nothing changed.
    pub perceived: Option<Vec<StarShape>>,
}
