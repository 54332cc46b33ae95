//! The online navigator: obstacles become known as the robot's own perception reports them
//! (the paper's assumptions `objknown`, `objpers`), and each call of [`Navigator::command`]
//! returns the command of the law for the current state.

use std::sync::Arc;

use harmonav_control::{ControlError, Damping, Dynamic, Kinematic};
use harmonav_field::{Field, FieldError, FieldEval};
use harmonav_sensing::SensorError;
use harmonav_transform::{ShapeError, StarShape, Workspace, WorldError};
use nalgebra::Vector2;

use crate::hold::{self, Band, Command, Mode};
use crate::options::{HoldPolicy, MIN_APERTURE_DEG, Options, PARAMETER_RANGE, in_range};
use crate::scan::ScanState;

/// The robot model and its law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Law {
    /// `ẋ = u` under eq. `kinctrl` with the speed of [`Options::speed`]: `u = −s(x)∇Θ/|∇Θ|`,
    /// `s = K√(2Θ)` (`"paper"`) or `min(v_max, √(2a|x − x_d|))` with a linear core at the goal
    /// (`"auto"`, the default; `v_max` from [`Options::v_max`], default `K√2`; `docs/maths.md`
    /// §6); [`Navigator::command`] returns the velocity `u`.
    Kinematic {
        /// `K > 0`.
        gain: f64,
    },
    /// `mẍ = f` under eq. `dynctrllocal`, `f = −μ∇Ψ − λẋ` with the damping of
    /// [`Options::damping`]; [`Navigator::command`] returns the force `f`.
    Dynamic {
        /// `m > 0`, kg.
        mass: f64,
        /// `μ > 0`: the speed bound is `√(2μ/m)`.
        mu: f64,
    },
}

impl Law {
    /// The kinematic law with gain `K` (speed at most `v_max`, by default `K√2`).
    pub fn kinematic(gain: f64) -> Self {
        Self::Kinematic { gain }
    }

    /// The dynamic law for mass `m` and gain `μ`.
    pub fn dynamic(mass: f64, mu: f64) -> Self {
        Self::Dynamic { mass, mu }
    }
}

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
    /// The position passed to [`Navigator::command`] lies in known obstacle `obstacle` grown by
    /// `radius` alone: the robot's disc overlaps the true shape (indices in the order of
    /// [`Navigator::add_obstacle`]). From [`Navigator::evaluate`] and [`Navigator::theta`]: in
    /// the obstacle grown by `radius + margin`. Inside the margin band alone `command` recovers
    /// ([`Mode::Recovering`]).
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
    /// The added obstacle (grown) is not strictly inside the (shrunk) boundary.
    CrossesBoundary,
    /// The added obstacle (grown) contains the goal.
    ContainsGoal,
    /// The added obstacle, grown by `radius` alone, contains the robot's last commanded
    /// position: the robot's disc would overlap it. (Grown by `radius + margin` it may contain
    /// the robot: the next command then leads out of the margin band.)
    ContainsRobot,
    /// The command came out non-finite (a guard: not expected within the validated ranges;
    /// reported rather than returned as NaN).
    NonFiniteCommand,
    /// The navigation function could not be built over the obstacles (not expected for a
    /// validated workspace; reported rather than hidden).
    Field(FieldError),
    /// [`Navigator::observe_scan`]: the scan, the pose or the scan options are not valid, the
    /// sensor lies in a known shape, or a fit could not be built (the perception crate's
    /// typed error).
    Perception(harmonav_perception::PerceptionError),
    /// [`Navigator::observe_scan`]: a new or grown perceived shape (grown by `radius +
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
    /// the discrete harmonic map is not certified ([`crate::FloorNavigator`]).
    BoundaryLayer,
}

/// What an [`NavError::InvalidOption`] field must be.
fn expected(field: &str) -> String {
    let (lo, hi) = PARAMETER_RANGE;
    match field {
        "radius" | "margin" => format!(
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
        "check_spacing" => "must be finite and in [1e-4, max_obstacle_depth/4] m".to_string(),
        _ => format!("must be finite and in [{lo:e}, {hi:e}]"),
    }
}

impl std::fmt::Display for NavError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::InvalidOption { field, value } => {
                write!(f, "`{field}`: {}, got {value:e}", expected(field))
            }
            Self::Sensor(e) => write!(f, "sensor: {e}"),
            Self::Shape(e) => write!(f, "growing the shape by radius + margin: {e}"),
            Self::NotFinite { what } => write!(f, "the {what} is not finite"),
            Self::GoalNotFree => write!(
                f,
                "the goal is not in the free space (inside a grown obstacle, or within \
                 radius + margin of the boundary)"
            ),
            Self::InObstacle { obstacle } => {
                write!(f, "the position lies inside known obstacle {obstacle}")
            }
            Self::OutsideBoundary => {
                write!(f, "the position lies on or outside the workspace boundary")
            }
            Self::Overlap { obstacle } => write!(
                f,
                "the new obstacle overlaps known obstacle {obstacle} (grown by radius + margin)"
            ),
            Self::CrossesBoundary => write!(
                f,
                "the new obstacle is not strictly inside the workspace boundary (grown by \
                 radius + margin)"
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

/// The law in use, with its parameters (for logging and monitors: the dynamic law's energy
/// `V` and speed bound).
#[derive(Clone, Copy, Debug)]
pub enum Controller {
    /// Eq. `kinctrl`.
    Kinematic(Kinematic),
    /// Eq. `dynctrllocal` with its damping policy.
    Dynamic(Dynamic),
}

/// One evaluation of the continuous law at a state, without side effects
/// ([`Navigator::evaluate`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Evaluation {
    /// The continuous law's command: the velocity `u` (kinematic law) or the force `f`
    /// (dynamic law), before the hold of [`Navigator::command`].
    pub command: Vector2<f64>,
    /// `Θ(x)`, `∇Θ(x)` and the descent direction `−∇Θ/|∇Θ|` over the known obstacles.
    pub field: FieldEval,
    /// The damping `λ` and its branch (dynamic law).
    pub damping: Option<Damping>,
}

/// An online navigator: the navigation function `Θ` over the obstacles added so far, and the
/// law. See the crate documentation for a complete loop.
#[derive(Clone, Debug)]
pub struct Navigator {
    pub(crate) controller: Controller,
    pub(crate) options: Options,
    /// The control period `h` in force (s).
    pub(crate) period: f64,
    pub(crate) goal: Vector2<f64>,
    /// `Θ` over the known obstacles, grown by `radius + margin` (in the order they were
    /// added), in the boundary shrunk by `radius + margin`.
    pub(crate) field: Field,
    /// The same shapes grown by `radius` alone (the boundary: shrunk by `radius`): the robot's
    /// disc overlaps a true shape iff its centre is in one of these. Empty with no margin.
    pub(crate) inner: Vec<StarShape>,
    pub(crate) inner_boundary: Option<StarShape>,
    /// `|ẋ(T_n)|` at the latest discovery (eq. `dissipationfun`).
    pub(crate) speed_at_discovery: f64,
    /// The last state passed to a successful `command`.
    pub(crate) last: Option<(Vector2<f64>, Vector2<f64>)>,
    /// The scan perception: the true boundary, the exact shapes of `add_obstacle`, the
    /// perceived shapes and where each sits among the obstacles ([`Navigator::observe_scan`]).
    pub(crate) scan: ScanState,
}

/// The law's controller for `law` under `options`, validated (each error names the field).
pub(crate) fn controller(law: &Law, options: &Options) -> Result<Controller, NavError> {
    options.validate(law)?;
    let d_min = options.d_min()?;
    Ok(match *law {
        Law::Kinematic { gain } => {
            let law = Kinematic::new(in_range("gain", gain)?)?.with_speed(options.speed);
            // `v_max` was range-checked by `validate`; the default K√2 is finite.
            Controller::Kinematic(match options.v_max {
                Some(v) => law.with_v_max(v)?,
                None => law,
            })
        }
        Law::Dynamic { mass, mu } => {
            let law = Dynamic::new(in_range("mass", mass)?, in_range("mu", mu)?, d_min)?
                .with_damping(options.damping);
            // Guard: within the ranges √(2μ/m) ≤ √2·1e9; checked, not assumed.
            let bound = law.speed_bound();
            if !(bound.is_finite() && bound > 0.0) {
                return Err(NavError::InvalidOption {
                    field: "mu",
                    value: mu,
                });
            }
            Controller::Dynamic(law)
        }
    })
}

/// A field error at a point, as the navigator reports it.
fn not_free(e: FieldError) -> NavError {
    match e {
        FieldError::InObstacle { obstacle } => NavError::InObstacle { obstacle },
        _ => NavError::OutsideBoundary,
    }
}

pub(crate) fn finite(v: Vector2<f64>, what: &'static str) -> Result<(), NavError> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(())
    } else {
        Err(NavError::NotFinite { what })
    }
}

impl Navigator {
    /// A navigator in the workspace bounded by `boundary`, towards `goal`, with no obstacle
    /// known yet.
    ///
    /// Errors: a law parameter (`gain`, `mass`, `mu`) or option outside its range
    /// ([`crate::PARAMETER_RANGE`], [`Options::validate`]; the error names the field), a
    /// boundary that cannot be shrunk by `radius + margin`, a goal that is not finite or not
    /// strictly inside.
    pub fn new(
        boundary: StarShape,
        goal: Vector2<f64>,
        law: Law,
        options: Options,
    ) -> Result<Self, NavError> {
        finite(goal, "goal")?;
        let controller = controller(&law, &options)?;
        let inflation = options.radius + options.margin;
        let shrunk = boundary.offset(-inflation).map_err(NavError::Shape)?;
        let inner_boundary = if options.margin > 0.0 {
            Some(boundary.offset(-options.radius).map_err(NavError::Shape)?)
        } else {
            None
        };
        let scan = ScanState::new(boundary, &options)?;
        let ws = Workspace::new(shrunk, Vec::new(), goal).map_err(|_| NavError::GoalNotFree)?;
        let field = Field::all_known_with(Arc::new(ws), options.k).map_err(NavError::Field)?;
        let nav = Self {
            controller,
            options,
            period: options.period_for(&law),
            goal,
            field,
            inner: Vec::new(),
            inner_boundary,
            speed_at_discovery: 0.0,
            last: None,
            scan,
        };
        // Guard: λ_c (eq. critdamp) overflowed for m = μ = 1e308; within the ranges it is
        // finite, and this checks it once rather than at every command.
        if let Controller::Dynamic(law) = &nav.controller {
            let lambda_c = law.lambda_c(&nav.field);
            if !lambda_c.is_finite() {
                return Err(NavError::InvalidOption {
                    field: "mu",
                    value: law.mu(),
                });
            }
        }
        Ok(nav)
    }

    /// Adds an obstacle that the robot's perception has just found (its true shape; it is grown
    /// by `radius + margin` here). `k`, `Phi` and the dynamic law's discovery state (`|ẋ(T_n)|`,
    /// the speed of the last commanded state) update. Returns its index. Allocates (the only
    /// call that does).
    ///
    /// A shape found late, whose margin band already holds the robot, is accepted: the next
    /// [`Navigator::command`] leads out of the band ([`Mode::Recovering`]).
    ///
    /// Errors (the navigator is then unchanged): the grown shape overlaps a known obstacle,
    /// crosses the boundary, or contains the goal; the shape grown by `radius` alone contains
    /// the robot's last commanded position; the shape cannot be grown.
    pub fn add_obstacle(&mut self, shape: StarShape) -> Result<usize, NavError> {
        let inflation = self.options.radius + self.options.margin;
        let grown = shape.offset(inflation).map_err(NavError::Shape)?;
        let inner = if self.options.margin > 0.0 {
            Some(shape.offset(self.options.radius).map_err(NavError::Shape)?)
        } else {
            None
        };
        let body = inner.as_ref().unwrap_or(&grown);
        if self.last.is_some_and(|(x, _)| body.contains(x)) {
            return Err(NavError::ContainsRobot);
        }
        let ws = self
            .field
            .workspace()
            .with_obstacle(grown)
            .map_err(|e| match e {
                WorldError::Overlap { first, .. } => NavError::Overlap { obstacle: first },
                WorldError::InObstacle { .. } => NavError::ContainsGoal,
                _ => NavError::CrossesBoundary,
            })?;
        let field = Field::all_known_with(Arc::new(ws), self.options.k).map_err(NavError::Field)?;
        self.field = field;
        self.inner.extend(inner);
        self.speed_at_discovery = self.last.map_or(0.0, |(_, v)| v.norm());
        let index = self.field.known().len() - 1;
        self.scan.add_exact(shape, index);
        Ok(index)
    }

    /// The command to hold for one control period at the state `(x, ẋ)`: the velocity `u`
    /// (kinematic law, `ẋ` unused) or the force `f` (dynamic law), with how it was formed.
    /// Does not allocate.
    ///
    /// Under [`HoldPolicy::Auto`] (the default) it is safe when held for the control period
    /// `h` ([`Options::with_control_period`]; 100 Hz kinematic, 1 kHz dynamic by default), by
    /// construction (`docs/maths.md` §10):
    ///
    /// - kinematic (`x += h·u`): the step stays within half the certified distance to the
    ///   nearest known grown shape, and `Θ` strictly decreases over it ([`Mode::Capped`] when
    ///   the law's step was shortened);
    /// - dynamic (`v += h·f/m, x += h·v`, or the exact hold of `f`): the damping acts
    ///   implicitly, `h|v⁺|` stays within a quarter of the certified distance, and
    ///   `|v⁺| < √(2μ/m)`.
    ///
    /// A robot inside the margin band of a known shape (clear of the true shape by at least
    /// `radius`, after a disturbance or a late perception) gets a command straight out of the
    /// band ([`Mode::Recovering`]), under either policy. Under [`HoldPolicy::Paper`] the command
    /// is otherwise the continuous law's (`Navigator::evaluate`), unchecked.
    ///
    /// Errors (the navigator is then unchanged): `x` or `ẋ` not finite, the robot's disc
    /// overlapping a known true shape or the boundary, a non-finite command (a guard).
    pub fn command(&mut self, x: Vector2<f64>, v: Vector2<f64>) -> Result<Command, NavError> {
        let command = self.held(x, v)?;
        if !command.value.iter().all(|c| c.is_finite()) {
            return Err(NavError::NonFiniteCommand);
        }
        self.last = Some((x, v));
        Ok(command)
    }

    /// [`Navigator::command`] without the finite check and the memory of the state.
    fn held(&self, x: Vector2<f64>, v: Vector2<f64>) -> Result<Command, NavError> {
        let eval = match self.evaluate(x, v) {
            Ok(eval) => eval,
            Err(e) => return self.recover(x, v, e),
        };
        if self.options.hold == HoldPolicy::Paper {
            return Ok(Command {
                value: eval.command,
                mode: Mode::Law,
            });
        }
        let h = self.period;
        Ok(match &self.controller {
            Controller::Dynamic(law) => {
                // `evaluate` gives the dynamic law's damping; computed again only if it did not.
                let d = eval.damping.unwrap_or_else(|| {
                    law.damping(&self.field, &eval.field, v, self.speed_at_discovery)
                });
                hold::dynamic(law, &self.field, x, (&eval.field, v), &d, h)
            }
            Controller::Kinematic(law) => {
                hold::kinematic(law, &self.field, x, &eval.field, eval.command, h)
            }
        })
    }

    /// The command out of the margin band, if `x` (not in the free space: `error`) is in it;
    /// otherwise `error`, with the obstacle or boundary that the robot's disc overlaps.
    fn recover(
        &self,
        x: Vector2<f64>,
        v: Vector2<f64>,
        error: NavError,
    ) -> Result<Command, NavError> {
        let band = match error {
            NavError::InObstacle { obstacle } => match self.inner.get(obstacle) {
                Some(inner) if !inner.contains(x) => Band::Obstacle(obstacle),
                _ => return Err(error),
            },
            NavError::OutsideBoundary => match &self.inner_boundary {
                Some(inner) if inner.contains(x) => Band::Boundary,
                _ => return Err(error),
            },
            _ => return Err(error),
        };
        let ws = self.field.workspace();
        let Some((dir, length)) = hold::way_out(ws, band, x, self.options.margin) else {
            return Err(error);
        };
        let h = self.period;
        let value = match &self.controller {
            Controller::Kinematic(law) => {
                // At most the law's top speed v_max.
                (length / h).min(law.v_max()) * dir
            }
            Controller::Dynamic(law) => {
                // v⁺ along the way out, at most half the speed bound; v += h f/m gives it.
                let next = (length / h).min(0.5 * law.speed_bound()) * dir;
                (law.mass() / h) * (next - v)
            }
        };
        Ok(Command {
            value,
            mode: Mode::Recovering(band),
        })
    }

    /// The continuous law at the state `(x, ẋ)` with what it is made of (`Θ`, `∇Θ`, the
    /// damping), without remembering the state and without the hold: for integrators of the
    /// continuous closed loop that evaluate trial states, and for logging. Does not allocate.
    ///
    /// Errors: `x` or `ẋ` not finite, `x` inside a known obstacle grown by `radius + margin`
    /// or outside the boundary shrunk by it.
    pub fn evaluate(&self, x: Vector2<f64>, v: Vector2<f64>) -> Result<Evaluation, NavError> {
        finite(x, "position")?;
        finite(v, "velocity")?;
        // Guard: components of 1.5e308 are finite but |ẋ| overflows, and with it |ẋ(T_n)| at
        // the next discovery and the damping (m/d_min)|ẋ(T_n)| (eq. dissipationfun).
        if !v.norm().is_finite() {
            return Err(NavError::NotFinite { what: "velocity" });
        }
        let e = self.field.eval(x).map_err(not_free)?;
        let (command, damping) = match &self.controller {
            Controller::Kinematic(law) => (law.velocity(&e, (x - self.goal).norm()), None),
            Controller::Dynamic(law) => {
                let d = law.damping(&self.field, &e, v, self.speed_at_discovery);
                (law.force(&self.field, &e, v, &d), Some(d))
            }
        };
        Ok(Evaluation {
            command,
            field: e,
            damping,
        })
    }

    /// `Θ(x)` over the known obstacles (for logging); errors as [`Navigator::evaluate`].
    pub fn theta(&self, x: Vector2<f64>) -> Result<f64, NavError> {
        finite(x, "position")?;
        self.field.eval(x).map(|e| e.value).map_err(not_free)
    }

    /// The goal.
    pub fn goal(&self) -> Vector2<f64> {
        self.goal
    }

    /// The known obstacles, grown by `radius + margin`, in the order they were added.
    pub fn obstacles(&self) -> &[StarShape] {
        self.field.workspace().obstacles()
    }

    /// The law in use.
    pub fn controller(&self) -> &Controller {
        &self.controller
    }

    /// `Θ` over the known obstacles (read only).
    pub fn field(&self) -> &Field {
        &self.field
    }

    /// `k` of `phi_k` for the known obstacles.
    pub fn k(&self) -> f64 {
        self.field.k()
    }

    /// The speed bound `√(2μ/m)` of the dynamic law (corollary `boundedvel`), `None` for the
    /// kinematic law.
    pub fn speed_bound(&self) -> Option<f64> {
        match &self.controller {
            Controller::Kinematic(_) => None,
            Controller::Dynamic(law) => Some(law.speed_bound()),
        }
    }

    /// The control period `h` in force, s ([`Options::control_period`] or the law's default).
    pub fn control_period(&self) -> f64 {
        self.period
    }

    /// The certified clearance at `x`: a lower bound on the distance to the nearest known grown
    /// obstacle and to the shrunk boundary (0 or less outside the free space, `−∞` at a
    /// non-finite point), the quantity the hold of [`Navigator::command`] keeps its steps
    /// within. Within the certificate's tolerance of a shape that is not a circle (about 1e-4
    /// of its size) it may be 0 or less at a free point.
    pub fn clearance(&self, x: Vector2<f64>) -> f64 {
        if !x.iter().all(|c| c.is_finite()) {
            return f64::NEG_INFINITY;
        }
        hold::clearance(self.field.workspace(), x, f64::INFINITY, None)
    }

    /// The options in use.
    pub fn options(&self) -> &Options {
        &self.options
    }
}
