//! The online navigator: obstacles become known as the robot's own perception reports them
//! (the paper's assumptions `objknown`, `objpers`), and each call of [`Navigator::command`]
//! returns the command of the law for the current state.

use std::sync::Arc;

use harmonav_control::{ControlError, Damping, DampingPolicy, Dynamic, Kinematic};
use harmonav_field::{Field, FieldError, FieldEval, KPolicy};
use harmonav_sensing::{Sector, SensorError};
use harmonav_transform::{ShapeError, StarShape, Workspace, WorldError};
use nalgebra::Vector2;

/// The robot model and its law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Law {
    /// `ẋ = u` under eq. `kinctrl`, `u = −K√(2Θ)∇Θ/|∇Θ|`; [`Navigator::command`] returns the
    /// velocity `u`.
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
    /// The kinematic law with gain `K` (speed `K√(2Θ) ≤ K√2`).
    pub fn kinematic(gain: f64) -> Self {
        Self::Kinematic { gain }
    }

    /// The dynamic law for mass `m` and gain `μ`.
    pub fn dynamic(mass: f64, mu: f64) -> Self {
        Self::Dynamic { mass, mu }
    }
}

/// The navigator's settings, all with defaults (`Options::default()`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Robot disc radius, m (default 0: a point robot). Obstacles are grown and the boundary
    /// shrunk by `radius + margin`.
    pub radius: f64,
    /// Clearance kept to the true shapes, m (default 0).
    pub margin: f64,
    /// Sensor range `r`, m (default 1, the paper's).
    pub sensor_range: f64,
    /// Sensor aperture `θ`, degrees, in (0, 360] (default 60, the paper's).
    pub sensor_aperture_deg: f64,
    /// A-priori lower bound on the obstacles' curvature radius, m, for `d_min` (eq. `dmin`;
    /// default 0.05, the paper's).
    pub rho_min: f64,
    /// How `k` follows the number of known obstacles (default `"auto"`).
    pub k: KPolicy,
    /// The dynamic law's damping (default `"auto"`).
    pub damping: DampingPolicy,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            radius: 0.0,
            margin: 0.0,
            sensor_range: 1.0,
            sensor_aperture_deg: 60.0,
            rho_min: 0.05,
            k: KPolicy::default(),
            damping: DampingPolicy::default(),
        }
    }
}

impl Options {
    /// The sensor: range `r` (m) and aperture (degrees). It sets `d_min` (eq. `dmin`), the
    /// distance within which the dynamic law must be able to stop after a discovery.
    #[must_use]
    pub fn with_sensor(self, range: f64, aperture_deg: f64) -> Self {
        Self {
            sensor_range: range,
            sensor_aperture_deg: aperture_deg,
            ..self
        }
    }

    /// The robot's radius and the clearance margin, m.
    #[must_use]
    pub fn with_robot(self, radius: f64, margin: f64) -> Self {
        Self {
            radius,
            margin,
            ..self
        }
    }

    /// The a-priori curvature bound `ρ_min` of `d_min`, m.
    #[must_use]
    pub fn with_rho_min(self, rho_min: f64) -> Self {
        Self { rho_min, ..self }
    }

    /// The `k` policy.
    #[must_use]
    pub fn with_k(self, k: KPolicy) -> Self {
        Self { k, ..self }
    }

    /// The damping policy of the dynamic law.
    #[must_use]
    pub fn with_damping(self, damping: DampingPolicy) -> Self {
        Self { damping, ..self }
    }

    /// `d_min(θ)` of eq. `dmin` for this sensor and `ρ_min`.
    pub fn d_min(&self) -> Result<f64, NavError> {
        let sector = Sector::new(self.sensor_range, self.sensor_aperture_deg.to_radians())
            .map_err(NavError::Sensor)?;
        if !(self.rho_min.is_finite() && self.rho_min > 0.0) {
            return Err(NavError::InvalidOption {
                field: "rho_min",
                value: self.rho_min,
            });
        }
        Ok(sector.d_min(self.rho_min))
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
    /// The position passed to [`Navigator::command`] lies in known obstacle `obstacle` (grown by
    /// `radius + margin`; indices in the order of [`Navigator::add_obstacle`]).
    InObstacle {
        /// The obstacle.
        obstacle: usize,
    },
    /// The position lies on or outside the (shrunk) boundary.
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
    /// The added obstacle (grown) contains the robot's last commanded position.
    ContainsRobot,
    /// The navigation function could not be built over the obstacles (not expected for a
    /// validated workspace; reported rather than hidden).
    Field(FieldError),
}

impl std::fmt::Display for NavError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::InvalidOption { field, value } => {
                write!(f, "`{field}`: must be finite and positive, got {value:e}")
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
            Self::Field(e) => write!(f, "the navigation function: {e}"),
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

/// One evaluation of the law at a state, without side effects ([`Navigator::evaluate`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Evaluation {
    /// The command: the velocity `u` (kinematic law) or the force `f` (dynamic law).
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
    controller: Controller,
    options: Options,
    goal: Vector2<f64>,
    /// `Θ` over the known obstacles, grown by `radius + margin` (in the order they were
    /// added), in the boundary shrunk by `radius + margin`.
    field: Field,
    /// `|ẋ(T_n)|` at the latest discovery (eq. `dissipationfun`).
    speed_at_discovery: f64,
    /// The last state passed to a successful `command`.
    last: Option<(Vector2<f64>, Vector2<f64>)>,
}

/// A field error at a point, as the navigator reports it.
fn not_free(e: FieldError) -> NavError {
    match e {
        FieldError::InObstacle { obstacle } => NavError::InObstacle { obstacle },
        _ => NavError::OutsideBoundary,
    }
}

fn finite(v: Vector2<f64>, what: &'static str) -> Result<(), NavError> {
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
    /// Errors: a law or option parameter that is not finite and positive (a negative radius or
    /// margin), an invalid sensor, a boundary that cannot be shrunk by `radius + margin`, a goal
    /// that is not finite or not strictly inside.
    pub fn new(
        boundary: StarShape,
        goal: Vector2<f64>,
        law: Law,
        options: Options,
    ) -> Result<Self, NavError> {
        finite(goal, "goal")?;
        for (field, value) in [("radius", options.radius), ("margin", options.margin)] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(NavError::InvalidOption { field, value });
            }
        }
        let d_min = options.d_min()?;
        let controller = match law {
            Law::Kinematic { gain } => Controller::Kinematic(Kinematic::new(gain)?),
            Law::Dynamic { mass, mu } => {
                Controller::Dynamic(Dynamic::new(mass, mu, d_min)?.with_damping(options.damping))
            }
        };
        let boundary = boundary
            .offset(-(options.radius + options.margin))
            .map_err(NavError::Shape)?;
        let ws = Workspace::new(boundary, Vec::new(), goal).map_err(|_| NavError::GoalNotFree)?;
        let field = Field::all_known_with(Arc::new(ws), options.k).map_err(NavError::Field)?;
        Ok(Self {
            controller,
            options,
            goal,
            field,
            speed_at_discovery: 0.0,
            last: None,
        })
    }

    /// Adds an obstacle that the robot's perception has just found (its true shape; it is grown
    /// by `radius + margin` here). `k`, `Phi` and the dynamic law's discovery state (`|ẋ(T_n)|`,
    /// the speed of the last commanded state) update. Returns its index. Allocates (the only
    /// call that does).
    ///
    /// Errors (the navigator is then unchanged): the grown shape overlaps a known obstacle,
    /// crosses the boundary, contains the goal or the robot's last commanded position, or
    /// cannot be grown.
    pub fn add_obstacle(&mut self, shape: StarShape) -> Result<usize, NavError> {
        let inflation = self.options.radius + self.options.margin;
        let grown = shape.offset(inflation).map_err(NavError::Shape)?;
        if self
            .last
            .is_some_and(|(x, _)| grown.signed_distance(x) <= 0.0)
        {
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
        self.field =
            Field::all_known_with(Arc::new(ws), self.options.k).map_err(NavError::Field)?;
        self.speed_at_discovery = self.last.map_or(0.0, |(_, v)| v.norm());
        Ok(self.field.known().len() - 1)
    }

    /// The command for the state `(x, ẋ)`: the velocity `u` (kinematic law, `ẋ` unused) or the
    /// force `f` (dynamic law). Does not allocate.
    ///
    /// Held for a fixed step `h` (a sampled-data loop), the guarantees are those of the
    /// continuous law only for small enough `h`. Tested (`tests/navigator.rs`, 12 worlds of 4–10
    /// mixed shapes, point robot and 0.1 m disc with a 0.05 m margin): the kinematic law
    /// (`K = 1`, `x += h·u`) never touches a shape at `h = 0.01 s` and also always arrives at
    /// `h = 0.005 s` (at 0.01 s one run in 24 stops in a 2-cycle across a saddle's stable
    /// manifold); the dynamic law (`m = 1`, `μ = 10`, semi-implicit Euler) is safe and arrives at
    /// `h = 0.001 s`. Its damping must stay stable in discrete time: `h(1 + c)λ/m < 2` with `c`
    /// the uphill gain of `harmonav_control::UPHILL_GAIN` (`docs/maths.md` §9).
    ///
    /// Errors (the navigator is then unchanged): `x` or `ẋ` not finite, `x` inside a known
    /// (grown) obstacle or outside the (shrunk) boundary.
    pub fn command(&mut self, x: Vector2<f64>, v: Vector2<f64>) -> Result<Vector2<f64>, NavError> {
        let command = self.evaluate(x, v)?.command;
        self.last = Some((x, v));
        Ok(command)
    }

    /// The law at the state `(x, ẋ)` with what it is made of (`Θ`, `∇Θ`, the damping), without
    /// remembering the state: for integrators that evaluate trial states, and for logging. The
    /// command equals [`Navigator::command`]'s; errors as there. Does not allocate.
    pub fn evaluate(&self, x: Vector2<f64>, v: Vector2<f64>) -> Result<Evaluation, NavError> {
        finite(x, "position")?;
        finite(v, "velocity")?;
        let e = self.field.eval(x).map_err(not_free)?;
        let (command, damping) = match &self.controller {
            Controller::Kinematic(law) => (law.velocity(&e), None),
            Controller::Dynamic(law) => {
                let d = law.damping(&self.field, &e, v, self.speed_at_discovery);
                (law.force(&e, v, &d), Some(d))
            }
        };
        Ok(Evaluation {
            command,
            field: e,
            damping,
        })
    }

    /// `Θ(x)` over the known obstacles (for logging); errors as [`Navigator::command`].
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

    /// The options in use.
    pub fn options(&self) -> &Options {
        &self.options
    }
}
