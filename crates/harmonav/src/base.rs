//! The robot's base ([`Base`]): holonomic, or a differential drive with its bounds
//! (issue 53; the law that steers it is `diff.rs`, docs/unicycle.md).

use crate::error::{NavError, in_range};
use crate::law::Law;

/// The robot's base: how it moves and which command it takes ([`crate::Options::base`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Base {
    /// The default: an omnidirectional robot commanded by [`Navigator::command`](crate::Navigator::command) (a velocity or
    /// a force), today's behaviour bit for bit.
    #[default]
    Holonomic,
    /// A differential-drive (unicycle) base with its axle at the disc's centre, commanded by
    /// [`Navigator::command_pose`](crate::Navigator::command_pose): forward speed `0 ≤ v ≤ v_max` (m/s) and turn rate
    /// `|ω| ≤ omega_max` (rad/s). Kinematic law only ([`Law::Kinematic`]); the dynamic law is
    /// refused at construction (`base`).
    Diff {
        /// The top forward speed, m/s, in [`crate::tuning::PARAMETER_RANGE`].
        v_max: f64,
        /// The top turn rate, rad/s, in [`crate::tuning::PARAMETER_RANGE`].
        omega_max: f64,
        /// The acceleration limits between two commands (`None`: none, the default;
        /// [`Base::with_accel`]).
        accel: Option<Accel>,
    },
}

/// A differential drive's acceleration limits (issue 53, item 2; docs/unicycle.md §10):
/// between two commands of [`Navigator::command_pose`](crate::Navigator::command_pose) held
/// for the control period `h`,
///
/// ```text
/// |v⁺ − v| ≤ a_max·h,   |ω⁺ − ω| ≤ alpha_max·h,
/// ```
///
/// and the braking certificate (eq. brakedisc): every command leaves the disc the base can
/// brake to rest in, radius `v⁺²/(2 a_max)` about the end of its arc, certified free, so
/// that the most it can brake (`v⁺ = max(0, v − a_max h)`) is always safe.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Accel {
    /// The largest change of the forward speed, m/s², in [`crate::tuning::PARAMETER_RANGE`].
    pub a_max: f64,
    /// The largest change of the turn rate, rad/s², in [`crate::tuning::PARAMETER_RANGE`].
    pub alpha_max: f64,
}

impl Base {
    /// A differential-drive base with these bounds ([`Base::Diff`]); checked by
    /// [`crate::Options::validate`].
    #[must_use]
    pub fn diff(v_max: f64, omega_max: f64) -> Self {
        Self::Diff {
            v_max,
            omega_max,
            accel: None,
        }
    }

    /// This base with the acceleration limits `a_max` (m/s²) and `alpha_max` (rad/s²)
    /// ([`Accel`]); a holonomic base is returned as it is (it takes no such limits).
    #[must_use]
    pub fn with_accel(self, a_max: f64, alpha_max: f64) -> Self {
        match self {
            Self::Diff {
                v_max, omega_max, ..
            } => Self::Diff {
                v_max,
                omega_max,
                accel: Some(Accel { a_max, alpha_max }),
            },
            Self::Holonomic => self,
        }
    }

    /// The name used in logs and Python (`"holonomic"`, `"diff"`).
    #[must_use]
    pub fn as_str(&self) -> &'static str {
        match self {
            Self::Holonomic => "holonomic",
            Self::Diff { .. } => "diff",
        }
    }

    /// The bounds checked for `law`: `v_max`, `omega_max` (and `a_max`, `alpha_max` when
    /// given) finite and in [`crate::tuning::PARAMETER_RANGE`] (the error names the field); a
    /// differential-drive base with
    /// the dynamic law is [`NavError::InvalidOption`] naming `base` (not built in this
    /// release: the kinematic law only).
    pub(crate) fn validate(&self, law: &Law) -> Result<(), NavError> {
        if let Self::Diff {
            v_max,
            omega_max,
            accel,
        } = *self
        {
            in_range("v_max", v_max)?;
            in_range("omega_max", omega_max)?;
            if let Some(a) = accel {
                in_range("a_max", a.a_max)?;
                in_range("alpha_max", a.alpha_max)?;
            }
            if matches!(law, Law::Dynamic { .. }) {
                return Err(NavError::InvalidOption {
                    field: "base",
                    value: f64::NAN,
                });
            }
        }
        Ok(())
    }
}

/// How a command's braking is certified (docs/unicycle.md §10): what the base may do next
/// period at the most it can brake, `v_b = max(0, v − a_max h)`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) enum Brake {
    /// Eq. brakedisc: the disc of radius `v²/(2 a_max)` about the end of the command's arc is
    /// certified free; braking may turn at any rate within the limits.
    #[default]
    Disc,
    /// Eq. brakearc: the arc of curvature `κ` from the command's pose, of length
    /// `v h + v²/(2 a_max)` (the command's arc and its continuation), is certified free, and
    /// `|κ| a_max ≤ alpha_max`; braking keeps to it, `ω_b = κ v_b`.
    Arc(f64),
}

/// The default arrival test of the goal heading ([`crate::Navigator::set_goal_heading`],
/// [`GoalTolerance::xy`]), m: the position has arrived when `|x − x_d| <` this, the same test
/// as `checks::fly`'s (it equals `checks::GOAL_TOLERANCE`, feature `checks`) and the 1 cm the
/// differential-drive tests and the scenarios' default `sim.arrival` use.
pub const GOAL_ARRIVAL: f64 = 0.01;

/// The default heading tolerance of the goal heading ([`GoalTolerance::yaw`]), rad: once the
/// position has arrived ([`GOAL_ARRIVAL`]), [`crate::Navigator::command_pose`] turns in place
/// until `|wrap(θ_g − θ)| <` this, then commands `(0, 0)` ([`crate::Steer::Arrived`]).
pub const GOAL_HEADING_TOLERANCE: f64 = 1e-3;

/// Where a differential-drive base has arrived at a goal with a yaw
/// ([`crate::Navigator::set_goal_heading`], [`crate::Navigator::set_goal_tolerance`]): the
/// turn in place begins once `|x − x_d| < xy`, and ends ([`crate::Steer::Arrived`]) once
/// `|wrap(θ_g − θ)| < yaw`; `xy` latches ([`crate::Navigator::set_goal_stateful`], Nav2's
/// `stateful`: the turn, once begun, goes on wherever a braking base rolls to). Nav2's goal
/// checker calls them `xy_goal_tolerance` and
/// `yaw_goal_tolerance`. The default is [`GOAL_ARRIVAL`] and [`GOAL_HEADING_TOLERANCE`]
/// (1 cm, 1e-3 rad). Either is a stopping rule only: turning in place is safe anywhere
/// (a disc robot's body does not move), so no tolerance weakens a certificate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GoalTolerance {
    /// m: the turn in place begins within this distance of the goal.
    pub xy: f64,
    /// rad: the turn ends within this angle of the goal yaw.
    pub yaw: f64,
}

impl Default for GoalTolerance {
    fn default() -> Self {
        Self {
            xy: GOAL_ARRIVAL,
            yaw: GOAL_HEADING_TOLERANCE,
        }
    }
}
