//! Why a navigator call failed ([`NavError`]): typed, and a failed call leaves the navigator
//! as it was.

use harmonav_control::ControlError;
use harmonav_field::FieldError;
use harmonav_sensing::SensorError;
use harmonav_transform::ShapeError;

use crate::ranges::{MIN_APERTURE_DEG, PARAMETER_RANGE};

/// Why a navigator call failed. A failed call leaves the navigator as it was.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum NavError {
    /// A parameter is not valid (`field` names it).
    InvalidOption {
        /// The parameter.
        field: &'static str,
        /// Its value.
        value: f64,
    },
    /// The sensor is not valid.
    Sensor(SensorError),
    /// A shape could not be grown by `radius + margin`.
    Shape(ShapeError),
    /// A coordinate is not finite (`what`: "position", "velocity", "goal").
    NotFinite {
        /// Which input.
        what: &'static str,
    },
    /// The goal lies in a grown obstacle or outside the shrunk boundary.
    GoalNotFree,
    /// The position passed to [`crate::Navigator::command`] lies in known obstacle `obstacle` grown by
    /// `radius` alone: the robot's disc overlaps the true shape (indices in the order of
    /// [`crate::Navigator::add_obstacle`]). From [`crate::Navigator::evaluate`] and [`crate::Navigator::theta`]: in
    /// the obstacle grown by `radius + margin`. Inside the margin band alone `command` recovers
    /// ([`crate::Mode::Recovering`]).
    InObstacle {
        /// The obstacle.
        obstacle: usize,
    },
    /// The position lies on or outside the boundary shrunk by `radius` (from `command`; by
    /// `radius + margin` from `evaluate` and `theta`).
    OutsideBoundary,
    /// The added obstacle (grown) overlaps or touches known obstacle `obstacle`.
    Overlap {
        /// The known obstacle.
        obstacle: usize,
    },
    /// The added obstacle (grown) reaches the (shrunk) boundary and cannot join it
    /// (`joined`, eq. carve): the goal or the robot would be left behind it as seen from the
    /// boundary's centre, or it holds that centre. (Before 2026-12-06 every obstacle that
    /// reached the boundary was refused.)
    CrossesBoundary,
    /// The added obstacle (grown) contains the goal.
    ContainsGoal,
    /// The added obstacle, grown by `radius` alone, contains the robot's last commanded
    /// position: the robot's disc would overlap it. (Grown by `radius + margin` it may contain
    /// the robot within its margin band: the next command then leads out. A scan's growth that
    /// holds the robot farther out, past the band, is refused too: `Navigator::observe_scan`.)
    ContainsRobot,
    /// The command came out non-finite (a guard: not expected within the validated ranges;
    /// reported rather than returned as NaN).
    NonFiniteCommand,
    /// The navigation function could not be built over the obstacles (not expected for a
    /// validated workspace; reported rather than hidden).
    Field(FieldError),
    /// [`crate::Navigator::observe_scan`]: the scan, the pose or the scan options are not valid, the
    /// sensor lies in a known shape, or a fit could not be built (the perception crate's
    /// typed error).
    Perception(harmonav_perception::PerceptionError),
    /// [`crate::Navigator::observe_scan`]: a new or grown perceived shape (grown by `radius +
    /// margin`) overlaps known obstacle `obstacle` and no star about a common kernel point
    /// holds both: the world as perceived is not a star world.
    NotStarWorld {
        /// The known obstacle (index before the scan); `None` when it is another shape fitted
        /// from the same scan.
        obstacle: Option<usize>,
    },
    /// A floor plan's navigation function could not be built, or a sensed obstacle does not
    /// fit in it ([`crate::FloorNavigator`]).
    Floor(harmonav_floorplan::FloorError),
    /// The position lies in a floor plan's boundary layer: closer than `δ` to a wall, where
    /// the discrete harmonic map is not certified ([`crate::FloorNavigator`]: `evaluate`
    /// always, `command` only when no step out of the layer can be certified).
    BoundaryLayer,
    /// [`crate::Navigator::set_movers`] or [`crate::MoverFilter::filter`]: mover `index` is not
    /// valid (`field` names what: `centre`, `radius`, `speed_bound`, `error`, `velocity`,
    /// `share`). The navigator keeps its movers.
    InvalidMover {
        /// The mover's index in the list given.
        index: usize,
        /// The field.
        field: &'static str,
    },
    /// The robot's disc and mover `mover`'s reported disc overlap: no command is certified
    /// (as inside a known obstacle). The navigator is unchanged.
    InMover {
        /// The mover's index.
        mover: usize,
    },
    /// [`crate::FloorNavigator::set_funnels`]: the chain of funnels does not fit this
    /// navigator (`reason` says why). The navigator keeps what it followed.
    InvalidFunnels {
        /// Why.
        reason: &'static str,
    },
}

/// `value` if it is finite and within [`PARAMETER_RANGE`], else the error naming `field`.
pub(crate) fn in_range(field: &'static str, value: f64) -> Result<f64, NavError> {
    let (lo, hi) = PARAMETER_RANGE;
    if value.is_finite() && (lo..=hi).contains(&value) {
        Ok(value)
    } else {
        Err(NavError::InvalidOption { field, value })
    }
}

/// What an [`NavError::InvalidOption`] field must be.
fn expected(field: &str) -> String {
    let (lo, hi) = PARAMETER_RANGE;
    match field {
        "radius" | "margin" | "comfort" => format!(
            "must be finite and in [0, {:e}] m",
            harmonav_transform::MAX_LENGTH
        ),
        "sensor_aperture_deg" => format!("must be in [{MIN_APERTURE_DEG:e}, 360] degrees"),
        "d_min" => "must come out finite and positive (eq. dmin)".to_string(),
        "range_noise" => "must be finite and in [0, 10] m".to_string(),
        "growth_threshold" => "must be finite and in (0, 10] m".to_string(),
        "max_obstacle_depth" => "must be finite and in (0, 100] m".to_string(),
        "jump_distance" => "must be finite and in [0, 100] m".to_string(),
        "order" => "must be an integer from 1 to 16".to_string(),
        "velocity" => "its speed |ẋ| must be below about 1e154 m/s (the energy ½m|ẋ|² \
                       overflows above it)"
            .to_string(),
        "xy_goal_tolerance" => "must be finite and positive, m".to_string(),
        "yaw_goal_tolerance" => "must be finite and positive, rad".to_string(),
        "free_memory" => format!(
            "must be an integer from 0 to {}",
            harmonav_perception::perception::MAX_FREE_MEMORY
        ),
        "fit_range" => "must be positive, and above max_obstacle_depth under the dynamic law \
                        with the paper's damping (its d_min is taken from fit_range − \
                        max_obstacle_depth)"
            .to_string(),
        "check_spacing" => "must be finite and in [1e-4, max_obstacle_depth/4] m".to_string(),
        // `movers::STUCK_TIME` and `STUCK_TURN_TIME` (not named: `movers` depends on this
        // module).
        "mover_memory.slow" => "must be finite and in [0, 1) s (how long KeepRight has seen \
                                the robot held slow, docs/movers.md §7)"
            .to_string(),
        "mover_memory.turning" => "must be finite and in [0, 2] s (how long KeepRight's \
                                   escape still runs, docs/movers.md §7)"
            .to_string(),
        "force_bound" => format!(
            "must be finite and in [{lo:e}, {hi:e}] N, and is the dynamic law's only (the \
             kinematic law commands velocities)"
        ),
        "base" => "a differential-drive base takes the kinematic law only (the dynamic law \
                   is not built for it)"
            .to_string(),
        _ => format!("must be finite and in [{lo:e}, {hi:e}]"),
    }
}

impl std::fmt::Display for NavError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::InvalidOption { field: "base", .. } => write!(f, "`base`: {}", expected("base")),
            Self::InvalidOption { field, value } => {
                write!(f, "`{field}`: {}, got {value:e}", expected(field))
            }
            Self::Sensor(e) => write!(f, "sensor: {e}"),
            Self::Shape(e) => write!(
                f,
                "the shape cannot be offset by radius + margin (an obstacle grown, the \
                 boundary shrunk): {}",
                e.problem()
            ),
            Self::NotFinite { what } => write!(f, "the {what} is not finite"),
            Self::GoalNotFree => write!(
                f,
                "the goal is not in the free space (inside a grown obstacle, or within \
                 radius + margin of the boundary)"
            ),
            Self::InObstacle { obstacle } => {
                write!(f, "the position lies inside known obstacle {obstacle}")
            }
            // The centre may be inside the walls: what is out is the robot's disc (grown by
            // the margin for `evaluate` and `theta`; issue 56, D19.1).
            Self::OutsideBoundary => write!(
                f,
                "the position lies on or outside the workspace boundary shrunk by the robot's \
                 radius: the robot's disc reaches a wall or the boundary"
            ),
            Self::Overlap { obstacle } => write!(
                f,
                "the new obstacle overlaps known obstacle {obstacle} (grown by radius + margin)"
            ),
            Self::CrossesBoundary => write!(
                f,
                "the new obstacle reaches the workspace boundary (grown by radius + margin) \
                 and cannot join it: the goal or the robot would be behind it as seen from the \
                 boundary's centre, or it holds that centre"
            ),
            Self::ContainsGoal => write!(f, "the new obstacle contains the goal"),
            Self::ContainsRobot => {
                write!(f, "the new obstacle contains the robot's last position")
            }
            Self::NonFiniteCommand => write!(f, "the command came out non-finite"),
            Self::Field(e) => write!(f, "the navigation function: {e}"),
            Self::Perception(e) => write!(f, "scan: {e}"),
            Self::NotStarWorld {
                obstacle: Some(obstacle),
            } => write!(
                f,
                "the world as perceived is not a star world: a perceived shape overlaps known \
                 obstacle {obstacle} (grown by radius + margin)"
            ),
            Self::NotStarWorld { obstacle: None } => write!(
                f,
                "the world as perceived is not a star world: two shapes fitted from the scan \
                 overlap"
            ),
            Self::Floor(e) => write!(f, "the floor plan: {e}"),
            Self::BoundaryLayer => write!(
                f,
                "the position lies in the floor plan's boundary layer (closer than δ to a wall)"
            ),
            Self::InvalidMover { index, field } => write!(
                f,
                "movers[{index}].{field}: must be finite (a length or speed in [0, {:e}], a \
                 share in [0, 1])",
                crate::ranges::MAX_MOVER
            ),
            Self::InMover { mover } => write!(
                f,
                "the robot's disc overlaps mover {mover} as reported: no command is certified"
            ),
            Self::InvalidFunnels { reason } => write!(f, "the chain of funnels {reason}"),
        }
    }
}

impl std::error::Error for NavError {}

impl From<ControlError> for NavError {
    fn from(e: ControlError) -> Self {
        Self::InvalidOption {
            field: e.field,
            value: e.value,
        }
    }
}
