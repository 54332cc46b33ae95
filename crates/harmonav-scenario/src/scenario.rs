//! The scenario file format (TOML) and its validation.
//!
//! The layout is a contract (see `scenarios/README.md`): it may be extended, not renamed.
//! Unknown keys are rejected. Every problem is reported as a [`ScenarioError`] naming the
//! file, the field and, where the TOML parser gives it, the line.

use std::path::{Path, PathBuf};

use harmonav::tuning::MIN_APERTURE_DEG;
use harmonav_control::{DampingPolicy, SpeedPolicy};
use harmonav_field::{Field, FieldError, KPolicy};
use harmonav_sensing::Sector;
use harmonav_transform::{RobotWorldError, Shown, StarShape, Workspace, WorldError};

use nalgebra::Vector2;

use crate::movers::{MAX_MOVERS, MoverSpec};
use crate::sensor::{self, SensorKind, SensorSpec};
use crate::truth::{Sensor, Truth};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// A problem with a scenario file.
#[derive(Clone, Debug, PartialEq)]
pub struct ScenarioError {
    /// The file.
    pub file: PathBuf,
    /// The field, as a path (`obstacles[2].radius`), or empty for the whole file.
    pub field: String,
    /// The line, where the parser gives it.
    pub line: Option<usize>,
    /// What is wrong.
    pub problem: String,
}

impl std::fmt::Display for ScenarioError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        if !self.field.is_empty() {
            write!(f, ": `{}`", self.field)?;
        }
        write!(f, ": {}", self.problem)
    }
}

impl std::error::Error for ScenarioError {}

/// A shape as written in a scenario (`type = "circle" | "ellipse" | "polygon" | "star"`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum ShapeSpec {
    /// A disc.
    Circle {
        /// Obstacle name (obstacles only).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        name: Option<String>,
        /// Centre.
        center: [f64; 2],
        /// Radius.
        radius: f64,
    },
    /// An ellipse.
    Ellipse {
        /// Obstacle name (obstacles only).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        name: Option<String>,
        /// Centre.
        center: [f64; 2],
        /// Semi-axes `[a, b]`.
        semi_axes: [f64; 2],
        /// Rotation of the first axis, degrees.
        #[serde(default)]
        angle_deg: f64,
    },
    /// A polygon with rounded corners, star-shaped about its vertex centroid.
    Polygon {
        /// Obstacle name (obstacles only).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        name: Option<String>,
        /// Vertices.
        vertices: Vec<[f64; 2]>,
        /// Corner radius (> 0).
        corner_radius: f64,
    },
    /// A Fourier star `R(θ) = r0 + Σ (a_n cos nθ + b_n sin nθ)`.
    Star {
        /// Obstacle name (obstacles only).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        name: Option<String>,
        /// Centre.
        center: [f64; 2],
        /// `r0`.
        radius: f64,
        /// `[n, a_n, b_n]` triples.
        #[serde(default)]
        harmonics: Vec<[f64; 3]>,
    },
}

impl ShapeSpec {
    /// The obstacle's `name`, if the file gives one.
    #[must_use]
    pub fn name(&self) -> Option<&str> {
        match self {
            Self::Circle { name, .. }
            | Self::Ellipse { name, .. }
            | Self::Polygon { name, .. }
            | Self::Star { name, .. } => name.as_deref(),
        }
    }
}

/// The robot model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Model {
    /// `ẋ = u` (eq. `holint`) under the kinematic law.
    Kinematic,
    /// `m ẍ = f` (eq. `dynmodel`) under the dynamic law.
    Dynamic,
}

impl Model {
    /// `"kinematic"` or `"dynamic"`, as the scenario file spells it.
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Kinematic => "kinematic",
            Self::Dynamic => "dynamic",
        }
    }

    /// The other robot model (a file's `[expect] other_model_reached` speaks of it).
    #[must_use]
    pub const fn other(self) -> Self {
        match self {
            Self::Kinematic => Self::Dynamic,
            Self::Dynamic => Self::Kinematic,
        }
    }
}

/// `[robot] base`: how the robot moves (issue 53; docs/unicycle.md, "Simulator").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BaseKind {
    /// The default: an omnidirectional robot, `ẋ = u` (or `m ẍ = f`), as before.
    #[default]
    Holonomic,
    /// A differential drive (unicycle): `ẋ = v·e(θ)`, `θ̇ = ω`, `e(θ) = (cos θ, sin θ)`, with
    /// `0 ≤ v ≤ v_max` (`[controller] v_max`) and `|ω| ≤ ω_max` (`[robot] omega_max`),
    /// commanded by [`harmonav::Navigator::command_pose`].
    Diff,
}

impl BaseKind {
    /// `"holonomic"` or `"diff"`, as the scenario file spells it.
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Holonomic => "holonomic",
            Self::Diff => "diff",
        }
    }

    /// Whether this is the default, [`BaseKind::Holonomic`] (not written back to a file).
    #[must_use]
    pub fn is_holonomic(&self) -> bool {
        *self == Self::Holonomic
    }
}

impl std::fmt::Display for BaseKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl std::str::FromStr for BaseKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "holonomic" => Ok(Self::Holonomic),
            "diff" => Ok(Self::Diff),
            _ => Err(format!(
                "unknown base `{s}`; expected \"holonomic\" (the default) or \"diff\" (a \
                 differential drive)"
            )),
        }
    }
}

/// A robot's base keys as either file format reads them: `[robot] base`, `omega_max`, `yaw`
/// and the top speed `v_max` (a star world's `[controller] v_max`, a floor plan's
/// `[robot] v_max`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct BaseKeys {
    pub base: BaseKind,
    pub omega_max: Option<f64>,
    pub yaw: Option<f64>,
    pub v_max: Option<f64>,
    pub a_max: Option<f64>,
    pub alpha_max: Option<f64>,
}

impl BaseKeys {
    /// The field and the problem of the first key that is wrong, `v_max_key` naming the top
    /// speed's key: `omega_max` or `yaw` without a differential drive; a differential drive
    /// without a positive, finite `omega_max` or without `v_max`, a yaw that is not finite, or
    /// with the dynamic law (`model`). Movers and other robots are taken (the held-command
    /// loop flies a differential drive's arcs among them, docs/movers.md §8).
    pub fn check(
        &self,
        v_max_key: &'static str,
        model: Model,
    ) -> Result<(), (&'static str, String)> {
        let only = |key: &str| {
            format!(
                "only a differential-drive base takes `{key}`; add `base = \"diff\"` to [robot]"
            )
        };
        if self.base == BaseKind::Holonomic {
            if self.omega_max.is_some() {
                return Err(("robot.omega_max", only("omega_max")));
            }
            if self.yaw.is_some() {
                return Err(("robot.yaw", only("yaw")));
            }
            if self.a_max.is_some() {
                return Err(("robot.a_max", only("a_max")));
            }
            if self.alpha_max.is_some() {
                return Err(("robot.alpha_max", only("alpha_max")));
            }
            return Ok(());
        }
        let Some(omega_max) = self.omega_max else {
            return Err((
                "robot.omega_max",
                "a differential-drive base (`base = \"diff\"`) needs its top turn rate, rad/s"
                    .into(),
            ));
        };
        parameter(omega_max).map_err(|p| ("robot.omega_max", p))?;
        if self.v_max.is_none() {
            return Err((
                v_max_key,
                "a differential-drive base (`base = \"diff\"`) needs its top forward speed, m/s"
                    .into(),
            ));
        }
        if let Some(yaw) = self.yaw
            && !yaw.is_finite()
        {
            return Err(("robot.yaw", format!("must be finite (rad), got {yaw:e}")));
        }
        match (self.a_max, self.alpha_max) {
            (None, None) => {}
            (Some(a), Some(alpha)) => {
                parameter(a).map_err(|p| ("robot.a_max", p))?;
                parameter(alpha).map_err(|p| ("robot.alpha_max", p))?;
            }
            (Some(_), None) => {
                return Err((
                    "robot.alpha_max",
                    "acceleration limits take both `a_max` (m/s²) and `alpha_max` (rad/s²)".into(),
                ));
            }
            (None, Some(_)) => {
                return Err((
                    "robot.a_max",
                    "acceleration limits take both `a_max` (m/s²) and `alpha_max` (rad/s²)".into(),
                ));
            }
        }
        if model == Model::Dynamic {
            return Err((
                "robot.base",
                "a differential-drive base runs the kinematic law only (`model = \"kinematic\"`)"
                    .into(),
            ));
        }
        Ok(())
    }

    /// `Base::Diff { v_max, omega_max, accel }` for a differential drive (its acceleration
    /// limits when `a_max` and `alpha_max` are given), `None` for a holonomic one.
    pub fn base(&self) -> Option<harmonav::Base> {
        let base = match (self.base, self.v_max, self.omega_max) {
            (BaseKind::Diff, Some(v_max), Some(omega_max)) => {
                harmonav::Base::diff(v_max, omega_max)
            }
            _ => return None,
        };
        Some(match (self.a_max, self.alpha_max) {
            (Some(a), Some(alpha)) => base.with_accel(a, alpha),
            _ => base,
        })
    }
}

impl ControllerSpec {
    /// The base's keys it carries.
    pub(crate) fn base_keys(&self) -> BaseKeys {
        BaseKeys {
            base: self.base,
            omega_max: self.omega_max,
            yaw: self.yaw,
            v_max: self.v_max,
            a_max: self.a_max,
            alpha_max: self.alpha_max,
        }
    }
}

/// `[robot]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSpec {
    /// `kinematic` or `dynamic`.
    pub model: Model,
    /// Start position.
    #[serde(deserialize_with = "crate::points::point")]
    pub start: [f64; 2],
    /// Goal position.
    #[serde(deserialize_with = "crate::points::point")]
    pub goal: [f64; 2],
    /// Mass (dynamic only), kg.
    #[serde(default = "one")]
    pub mass: f64,
    /// Disc radius (0: point robot).
    #[serde(default)]
    pub radius: f64,
    /// Clearance margin, m (default 0): the navigation function is built on the obstacles and
    /// the boundary offset by `radius + margin`, so the guaranteed clearance to the true shapes
    /// is `margin`.
    #[serde(default)]
    pub margin: f64,
}

/// `[field]`: how the navigation function is built.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FieldSpec {
    /// `k = "paper"` (`k = n + 1`) or `"auto"` (the default), see [`KPolicy`].
    #[serde(default, deserialize_with = "de_policy", serialize_with = "ser_policy")]
    pub k: KPolicy,
}

/// A policy field (`k`, `damping`, `speed`, a floor plan's `centre`) by name; an unknown name is an
/// error that lists the names.
pub(crate) fn de_policy<'de, D, P>(d: D) -> Result<P, D::Error>
where
    D: Deserializer<'de>,
    P: std::str::FromStr,
    P::Err: std::fmt::Display,
{
    String::deserialize(d)?
        .parse()
        .map_err(serde::de::Error::custom)
}

fn ser_policy<S: Serializer, P: std::fmt::Display>(p: &P, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(p)
}

/// `[controller]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControllerSpec {
    /// `K` of the kinematic law.
    #[serde(default = "one")]
    pub gain: f64,
    /// `μ` of the dynamic law (default [`DEFAULT_MU`], as a floor plan's `robot.mu`).
    #[serde(default = "default_mu")]
    pub mu: f64,
    /// `damping = "paper"` (eq. `dissipationfun`), `"shaped"`, `"auto"`, `"fast"` or
    /// `"governed"` (the default), see [`DampingPolicy`].
    #[serde(default, deserialize_with = "de_policy", serialize_with = "ser_policy")]
    pub damping: DampingPolicy,
    /// `speed = "paper"` (eq. `kinctrl`, `K√(2Θ)`) or `"auto"` (the default: full speed, then
    /// a constant deceleration to the goal), see [`SpeedPolicy`].
    #[serde(default, deserialize_with = "de_policy", serialize_with = "ser_policy")]
    pub speed: SpeedPolicy,
    /// `v_max`, m/s: the kinematic law's top speed (default `K√2`, the paper law's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v_max: Option<f64>,
    /// The file's `[robot] control_period`, s: the period the navigator's hold certifies
    /// ([`harmonav::Options::with_control_period`]) and for which a held-command loop (rapier)
    /// holds each command. `None`: the law's default, and rapier's steps of `sim.dt` cut to at
    /// most 1 ms. Written under `[robot]`, as a floor plan's (one key for both formats); kept
    /// here, with the law's other settings, so that code building a [`RobotSpec`] field by
    /// field keeps compiling.
    #[serde(skip)]
    pub control_period: Option<f64>,
    /// The file's `[robot] base` (default [`BaseKind::Holonomic`]); written under `[robot]`
    /// and kept here as `control_period` is.
    #[serde(skip)]
    pub base: BaseKind,
    /// The file's `[robot] omega_max`, rad/s: a differential drive's top turn rate `ω_max`
    /// (required with `base = "diff"`, refused without it).
    #[serde(skip)]
    pub omega_max: Option<f64>,
    /// The file's `[robot] yaw`, rad: a differential drive's heading `θ(0)` at the start
    /// (default 0, along `+x`; refused without `base = "diff"`). Not `heading`, which is a
    /// floor plan's heading policy.
    #[serde(skip)]
    pub yaw: Option<f64>,
    /// The file's `[robot] a_max`, m/s²: a differential drive's largest change of `v` per
    /// second between commands ([`harmonav::Accel`]; with `alpha_max`, refused without a
    /// differential drive).
    #[serde(skip)]
    pub a_max: Option<f64>,
    /// The file's `[robot] alpha_max`, rad/s²: its largest change of `ω` per second.
    #[serde(skip)]
    pub alpha_max: Option<f64>,
    /// The file's `[robot] force_bound`, N: the dynamic law's force bound `F`
    /// ([`harmonav::Options::with_force_bound`], the braking certificate; a kinematic run of
    /// the file, under `--model kinematic`, has no force to bound). A file with one runs in
    /// the held-command loop, as a file with movers does.
    #[serde(skip)]
    pub force_bound: Option<f64>,
    /// The file's `[robot] comfort`, m (default 0): the distance the nominal command keeps
    /// beyond the margin from the non-cooperative movers where it can
    /// ([`harmonav::Options::comfort`], docs/movers.md §7).
    #[serde(skip)]
    pub comfort: f64,
}

impl Default for ControllerSpec {
    fn default() -> Self {
        Self {
            gain: 1.0,
            mu: DEFAULT_MU,
            damping: DampingPolicy::default(),
            speed: SpeedPolicy::default(),
            v_max: None,
            control_period: None,
            base: BaseKind::Holonomic,
            omega_max: None,
            yaw: None,
            a_max: None,
            alpha_max: None,
            force_bound: None,
            comfort: 0.0,
        }
    }
}

/// `[sim]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimSpec {
    /// Largest step and recording interval, s.
    #[serde(default = "default_dt")]
    pub dt: f64,
    /// Give up after this time, s.
    #[serde(default = "default_max_time")]
    pub max_time: f64,
    /// Arrival radius, m (default [`DEFAULT_ARRIVAL`]); also spelt `arrival`, a floor plan's
    /// name for it.
    #[serde(default = "default_tolerance", alias = "arrival")]
    pub goal_tolerance: f64,
    /// The file's `[[movers]]` (issue 54; `docs/movers.md` §8): people and other robots on
    /// scripted trajectories, which a run moves, reports to the navigator and judges contacts
    /// with. Written at the top level of the file; kept here, with the run's other settings, so
    /// that code building a [`Scenario`] field by field keeps compiling.
    #[serde(skip)]
    pub movers: Vec<MoverSpec>,
    /// The file's `[[robots]]`: more harmonav robots, each like `[robot]` but with its own start
    /// and goal, each running its own navigator with the others as reciprocal movers
    /// (`docs/movers.md` §8). Written at the top level; kept here as `movers` is.
    #[serde(skip)]
    pub robots: Vec<FleetRobotSpec>,
}

/// One `[[robots]]` entry: a robot like `[robot]` with its own start and goal, in a star world
/// and in a floor plan alike (one check, `check_fleet`, for both).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FleetRobotSpec {
    /// Start position.
    #[serde(deserialize_with = "crate::points::point")]
    pub start: [f64; 2],
    /// Goal position.
    #[serde(deserialize_with = "crate::points::point")]
    pub goal: [f64; 2],
    /// A differential drive's heading at the start, rad (only with `[robot] base = "diff"`,
    /// whose `yaw` it replaces for this robot; default: `[robot] yaw`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yaw: Option<f64>,
}

/// Every `[[robots]]` entry of a file, star world or floor plan (issue 54; docs/movers.md §8),
/// checked: at most [`MAX_MOVERS`] of them; each `start` and `goal` finite and accepted by the
/// world's `free` (its own rule for `robot.start`; else the problem, in words); each start's
/// disc (of the first robot's `radius`, all robots being alike) clear of the discs of the
/// robots before it, `[robot]` at `first` the first of them; every mover clear of each start
/// (as [`MoverSpec::check`] asks of `robot.start`); `yaw` only on a differential drive
/// (`diff`), and finite. On the first that is wrong, its key (`robots`, `robots[i].start`,
/// `movers[k].start`, …) and the problem.
pub(crate) fn check_fleet(
    robots: &[FleetRobotSpec],
    (first, radius): ([f64; 2], f64),
    movers: &[MoverSpec],
    diff: bool,
    free: impl Fn(Vector2<f64>) -> Result<(), String>,
) -> Result<(), (String, String)> {
    if robots.len() > MAX_MOVERS {
        return Err((
            "robots".into(),
            format!(
                "{} robots; at most {MAX_MOVERS} are supported",
                robots.len()
            ),
        ));
    }
    let mut starts = vec![first];
    for (i, robot) in robots.iter().enumerate() {
        let field = |key: &str| format!("robots[{i}].{key}");
        for (key, p) in [("start", robot.start), ("goal", robot.goal)] {
            check_point(p, "").map_err(|e| (field(key), e))?;
            free(Vector2::from(p)).map_err(|e| (field(key), e))?;
        }
        for (j, other) in starts.iter().enumerate() {
            let gap = (Vector2::from(robot.start) - Vector2::from(*other)).norm() - 2.0 * radius;
            if gap <= 0.0 {
                let whose = if j == 0 {
                    "robot.start".to_string()
                } else {
                    format!("robots[{}].start", j - 1)
                };
                return Err((
                    field("start"),
                    format!("the robot's disc overlaps the one at {whose} (gap {gap:e} m)"),
                ));
            }
        }
        starts.push(robot.start);
        for (k, m) in movers.iter().enumerate() {
            m.check(robot.start, radius)
                .map_err(|(_, p)| (format!("movers[{k}].start"), format!("{p} (robots[{i}])")))?;
        }
        match robot.yaw {
            Some(_) if !diff => {
                return Err((
                    field("yaw"),
                    "only a differential-drive base takes `yaw`; add `base = \"diff\"` to [robot]"
                        .into(),
                ));
            }
            Some(yaw) if !yaw.is_finite() => {
                return Err((field("yaw"), format!("must be finite (rad), got {yaw:e}")));
            }
            _ => {}
        }
    }
    Ok(())
}

impl Default for SimSpec {
    fn default() -> Self {
        Self {
            dt: default_dt(),
            max_time: default_max_time(),
            goal_tolerance: default_tolerance(),
            movers: Vec::new(),
            robots: Vec::new(),
        }
    }
}

/// `μ` of the dynamic law when the file gives none, in both formats (a star world's
/// `controller.mu`, a floor plan's `robot.mu`; Python's default too): the speed bound
/// `√(2μ/m)` is 4.5 m/s at the default mass of 1 kg.
pub const DEFAULT_MU: f64 = 10.0;

/// The arrival radius `|x − x_d|` when the file gives none, m, in both formats (a star
/// world's `sim.goal_tolerance`, a floor plan's `sim.arrival`; either key in either format).
pub const DEFAULT_ARRIVAL: f64 = 0.01;

/// The largest scenario file read, bytes.
pub const MAX_FILE_BYTES: u64 = 4 << 20;

/// The most obstacles a scenario may have. Validation and the census grow like `M²`; at the
/// limit, 2 000 discs, `harmonav census` takes 16 s and 190 MB (release build, this machine:
/// 0.8 s at 500, 3.7 s at 1 000), which keeps every command under 30 s.
pub const MAX_OBSTACLES: usize = 2000;

/// The most states a run may record, `sim.max_time / sim.dt`. Not a memory limit: a run keeps
/// its memory flat whatever its length (harmonav-sim's `trajectory`). A guard against a typo in
/// `sim.dt`: each recorded state costs at least one integration step of about a microsecond,
/// so 10⁹ of them are already a quarter of an hour to hours (10⁷ states, a 10 km world at
/// `sim.dt = 0.01`, take 20–100 s).
pub const MAX_RECORDED_STATES: f64 = 1e9;

/// The range of the physical parameters (`robot.mass`, `controller.gain`, `controller.mu`,
/// `controller.v_max`, `sensor.range`, `sensor.rho_min`, `sim.dt`, `sim.max_time`, `sim.goal_tolerance`): the
/// navigator's own ([`harmonav::tuning::PARAMETER_RANGE`]); outside it the closed loop cannot be
/// integrated in `f64` (a `dt` of 1e-300 or a mass of 5e-324 stopped at t = 0).
pub use harmonav::tuning::PARAMETER_RANGE;

/// `[expect]`: what a run of this scenario must show (checked by the CLI and `xtask verify`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExpectSpec {
    /// Whether the goal is reached.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reached: Option<bool>,
    /// Obstacle names in discovery order.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub discovery_order: Option<Vec<String>>,
    /// An upper bound on the largest speed, m/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_speed_below: Option<f64>,
    /// Whether the dynamic law's damping switches to `(m/d_min)|ẋ(T_n)|` during the run (a
    /// discovery lifts `V` to `μ` or above, eq. `dissipationfun`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping_switched: Option<bool>,
    /// `false` states that a run with the *other* robot model does not reach the goal within
    /// `sim.max_time`: a limit of the paper's policies (`xtask verify` reports it as a limit,
    /// and fails if the run arrives after all). Allowed only when the other model runs under
    /// a `"paper"` policy; under the default policies every scenario must arrive.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub other_model_reached: Option<bool>,
}

fn one() -> f64 {
    1.0
}
pub(crate) fn default_mu() -> f64 {
    DEFAULT_MU
}
fn default_dt() -> f64 {
    0.01
}
fn default_max_time() -> f64 {
    200.0
}
pub(crate) fn default_tolerance() -> f64 {
    DEFAULT_ARRIVAL
}

/// A scenario file as written (its `[robot] control_period` kept in
/// [`ControllerSpec::control_period`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(from = "ScenarioFile", into = "ScenarioFile")]
pub struct Scenario {
    /// Name.
    pub name: String,
    /// Free text.
    #[serde(default)]
    pub description: String,
    /// The outer boundary (circle, ellipse or polygon).
    pub workspace: ShapeSpec,
    /// The obstacles.
    #[serde(default)]
    pub obstacles: Vec<ShapeSpec>,
    /// The robot.
    pub robot: RobotSpec,
    /// The sensor; `None` for global sensing.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensor: Option<SensorSpec>,
    /// The navigation function's policies.
    #[serde(default)]
    pub field: FieldSpec,
    /// Controller gains.
    #[serde(default)]
    pub controller: ControllerSpec,
    /// Integration settings.
    #[serde(default)]
    pub sim: SimSpec,
    /// Expected outcome.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub expect: Option<ExpectSpec>,
}

/// The layout of a scenario file: [`Scenario`]'s tables, with `[robot]` as [`RobotFile`].
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ScenarioFile {
    name: String,
    #[serde(default)]
    description: String,
    workspace: ShapeSpec,
    #[serde(default)]
    obstacles: Vec<ShapeSpec>,
    robot: RobotFile,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    sensor: Option<SensorSpec>,
    #[serde(default)]
    field: FieldSpec,
    #[serde(default)]
    controller: ControllerSpec,
    #[serde(default)]
    sim: SimSpec,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    expect: Option<ExpectSpec>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    movers: Vec<MoverSpec>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    robots: Vec<FleetRobotSpec>,
}

/// `[robot]` as written: [`RobotSpec`]'s keys and `control_period`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct RobotFile {
    model: Model,
    #[serde(deserialize_with = "crate::points::point")]
    start: [f64; 2],
    #[serde(deserialize_with = "crate::points::point")]
    goal: [f64; 2],
    #[serde(default = "one")]
    mass: f64,
    #[serde(default)]
    radius: f64,
    #[serde(default)]
    margin: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    control_period: Option<f64>,
    #[serde(
        default,
        deserialize_with = "de_policy",
        serialize_with = "ser_policy",
        skip_serializing_if = "BaseKind::is_holonomic"
    )]
    base: BaseKind,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    omega_max: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    yaw: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    a_max: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    alpha_max: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    force_bound: Option<f64>,
    #[serde(default, skip_serializing_if = "no_comfort")]
    comfort: f64,
}

/// A comfort of 0 (the default, none) is left out of a written file.
fn no_comfort(comfort: &f64) -> bool {
    *comfort == 0.0
}

impl From<ScenarioFile> for Scenario {
    fn from(file: ScenarioFile) -> Self {
        let r = file.robot;
        Self {
            name: file.name,
            description: file.description,
            workspace: file.workspace,
            obstacles: file.obstacles,
            robot: RobotSpec {
                model: r.model,
                start: r.start,
                goal: r.goal,
                mass: r.mass,
                radius: r.radius,
                margin: r.margin,
            },
            sensor: file.sensor,
            field: file.field,
            controller: ControllerSpec {
                control_period: r.control_period,
                base: r.base,
                omega_max: r.omega_max,
                yaw: r.yaw,
                a_max: r.a_max,
                alpha_max: r.alpha_max,
                force_bound: r.force_bound,
                comfort: r.comfort,
                ..file.controller
            },
            sim: SimSpec {
                movers: file.movers,
                robots: file.robots,
                ..file.sim
            },
            expect: file.expect,
        }
    }
}

impl From<Scenario> for ScenarioFile {
    fn from(mut s: Scenario) -> Self {
        let r = s.robot;
        let movers = std::mem::take(&mut s.sim.movers);
        let robots = std::mem::take(&mut s.sim.robots);
        Self {
            name: s.name,
            description: s.description,
            workspace: s.workspace,
            obstacles: s.obstacles,
            robot: RobotFile {
                model: r.model,
                start: r.start,
                goal: r.goal,
                mass: r.mass,
                radius: r.radius,
                margin: r.margin,
                control_period: s.controller.control_period,
                base: s.controller.base,
                omega_max: s.controller.omega_max,
                yaw: s.controller.yaw,
                a_max: s.controller.a_max,
                alpha_max: s.controller.alpha_max,
                force_bound: s.controller.force_bound,
                comfort: s.controller.comfort,
            },
            sensor: s.sensor,
            field: s.field,
            controller: s.controller,
            sim: s.sim,
            expect: s.expect,
            movers,
            robots,
        }
    }
}

/// A validated scenario, ready to run.
#[derive(Clone, Debug)]
pub struct Prepared {
    /// The scenario as written.
    pub scenario: Scenario,
    /// The world it describes: the true shapes, the configuration space and the sensor.
    pub truth: Truth,
}

impl Scenario {
    /// Reads and validates a scenario file (at most [`MAX_FILE_BYTES`]: a device or a huge file
    /// is refused instead of read forever).
    pub fn load(path: &Path) -> Result<Prepared, ScenarioError> {
        let text = read_text(path)?;
        Self::parse(path, &text)?.prepare(path)
    }

    /// Parses TOML text (`path` names it in errors); unknown keys are errors.
    pub fn parse(path: &Path, text: &str) -> Result<Self, ScenarioError> {
        // A floor plan given where a star world is expected (issue 56, D11): said so, not
        // "unknown field `floor_plan`".
        if crate::kind::FileKind::of_text(text) == crate::kind::FileKind::FloorPlan {
            return Err(err(
                path,
                "floor_plan",
                None,
                "this is a floor-plan file (it has a [floor_plan] table); this loader takes \
                 star-world files (`harmonav run` takes either; in Python, FloorPlan.load)"
                    .into(),
            ));
        }
        toml::from_str::<Scenario>(text).map_err(|e| toml_error(path, text, &e))
    }

    /// The base's keys (`[robot] base`, `omega_max`, `yaw`, and `[controller] v_max` for a
    /// differential drive): the field and the problem of the first that is wrong.
    fn check_base(&self) -> Result<(), (&'static str, String)> {
        self.controller
            .base_keys()
            .check("controller.v_max", self.robot.model)
    }

    /// Validates the scenario and builds the workspace (see [`Prepared`]).
    pub fn prepare(self, path: &Path) -> Result<Prepared, ScenarioError> {
        let f = |field: &str, problem: String| err(path, field, None, problem);
        if self.obstacles.len() > MAX_OBSTACLES {
            return Err(f(
                "obstacles",
                format!(
                    "{} obstacles; at most {MAX_OBSTACLES} are supported",
                    self.obstacles.len()
                ),
            ));
        }
        let in_range = |name: &str, v: f64| parameter(v).map_err(|p| f(name, p));
        if let Some(n) = self.workspace.name() {
            return Err(f(
                "workspace.name",
                format!("the workspace boundary takes no name (got \"{n}\")"),
            ));
        }
        if matches!(self.workspace, ShapeSpec::Star { .. }) {
            return Err(f(
                "workspace.type",
                "the workspace boundary must be a circle, an ellipse or a polygon".into(),
            ));
        }
        let true_boundary =
            build_shape(&self.workspace).map_err(|e| f(&format!("workspace.{}", e.0), e.1))?;
        let mut true_obstacles = Vec::with_capacity(self.obstacles.len());
        for (i, o) in self.obstacles.iter().enumerate() {
            true_obstacles
                .push(build_shape(o).map_err(|e| f(&format!("obstacles[{i}].{}", e.0), e.1))?);
        }
        let names = obstacle_names(&self.obstacles, |i| format!("O{}", i + 1))
            .map_err(|(field, p)| f(&field, p))?;
        let r = &self.robot;
        check_point(r.start, "robot.start").map_err(|p| f("robot.start", p))?;
        check_point(r.goal, "robot.goal").map_err(|p| f("robot.goal", p))?;
        in_range("robot.mass", r.mass)?;
        for (name, v) in [
            ("robot.radius", r.radius),
            ("robot.margin", r.margin),
            ("robot.comfort", self.controller.comfort),
        ] {
            length(v).map_err(|p| f(name, p))?;
        }
        // Every shape is offset by the robot radius plus the clearance margin; an error caused by
        // the offset names the field that set it (the margin where there is one) and the value.
        let inflation = r.radius + r.margin;
        let inflation_field = if r.margin > 0.0 {
            "robot.margin"
        } else {
            "robot.radius"
        };
        let inflated_by = format!("with robot.radius + robot.margin = {inflation} m");
        let c = &self.controller;
        in_range("controller.gain", c.gain)?;
        in_range("controller.mu", c.mu)?;
        if let Some(v) = c.v_max {
            in_range("controller.v_max", v)?;
        }
        if let Some(h) = c.control_period {
            control_period(h, self.sim.max_time).map_err(|p| f("robot.control_period", p))?;
        }
        if let Some(force) = c.force_bound {
            in_range("robot.force_bound", force)?;
        }
        self.check_base().map_err(|(field, p)| f(field, p))?;
        if let Some(v) = self.expect.as_ref().and_then(|e| e.max_speed_below)
            && !(v.is_finite() && v > 0.0)
        {
            return Err(f(
                "expect.max_speed_below",
                format!("must be finite and positive, got {v:e}"),
            ));
        }
        if let Some(false) = self.expect.as_ref().and_then(|e| e.other_model_reached) {
            let paper = match r.model {
                // The other model is the dynamic law: the paper's k or damping.
                Model::Kinematic => {
                    self.field.k == KPolicy::Paper || c.damping == DampingPolicy::Paper
                }
                // The other model is the kinematic law: the paper's k or speed.
                Model::Dynamic => self.field.k == KPolicy::Paper || c.speed == SpeedPolicy::Paper,
            };
            if !paper {
                return Err(f(
                    "expect.other_model_reached",
                    "only a scenario that runs the other model under a \"paper\" policy \
                     (`[field] k`, or `[controller] damping` for the dynamic law, `speed` for the \
                     kinematic one) may state that \
                     it does not arrive; under the default policies every scenario must arrive"
                        .into(),
                ));
            }
        }
        if self.sim.movers.len() > MAX_MOVERS {
            return Err(f(
                "movers",
                format!(
                    "{} movers; at most {MAX_MOVERS} are supported",
                    self.sim.movers.len()
                ),
            ));
        }
        crate::movers::check_all(&self.sim.movers, r.start, r.radius)
            .map_err(|(field, p)| f(&field, p))?;
        let s = &self.sim;
        in_range("sim.dt", s.dt)?;
        in_range("sim.max_time", s.max_time)?;
        in_range("sim.goal_tolerance", s.goal_tolerance)?;
        if s.max_time / s.dt > MAX_RECORDED_STATES {
            return Err(f(
                "sim.dt",
                format!(
                    "sim.max_time / sim.dt = {:.3e} states to record; at most \
                     {MAX_RECORDED_STATES:e}, about an hour of computing (raise sim.dt or lower \
                     sim.max_time)",
                    s.max_time / s.dt
                ),
            ));
        }
        let goal = Vector2::new(r.goal[0], r.goal[1]);
        let start = Vector2::new(r.start[0], r.start[1]);
        let name_of = |i: usize| names[i].clone();
        let point_field = |what: &str| {
            if what == "start" {
                "robot.start"
            } else {
                "robot.goal"
            }
        };
        let world_error = |e: WorldError| match e {
            WorldError::Overlap { first, second }
                if inflation > 0.0
                    && true_obstacles[first].distance_to(&true_obstacles[second]) > 0.0 =>
            {
                f(
                    inflation_field,
                    format!(
                        "{inflated_by} the grown obstacles {} and {} overlap: the passage between \
                     them is narrower than 2 × {inflation} m",
                        name_of(first),
                        name_of(second)
                    ),
                )
            }
            WorldError::Overlap { first, second } => f(
                "obstacles",
                format!(
                    "obstacles {} and {} overlap or touch",
                    name_of(first),
                    name_of(second)
                ),
            ),
            WorldError::OutsideBoundary { obstacle }
                if inflation > 0.0
                    && true_obstacles[obstacle].clearance_inside(&true_boundary) > 0.0 =>
            {
                f(
                    inflation_field,
                    format!(
                        "{inflated_by} obstacle {} reaches the shrunk workspace boundary: the \
                         passage between them is narrower than 2 × {inflation} m",
                        name_of(obstacle)
                    ),
                )
            }
            WorldError::OutsideBoundary { obstacle } => f(
                "obstacles",
                format!(
                    "obstacle {} crosses or lies outside the workspace boundary",
                    name_of(obstacle)
                ),
            ),
            WorldError::InObstacle { what, obstacle }
                if inflation > 0.0
                    && !true_obstacles[obstacle].contains(if what == "start" {
                        start
                    } else {
                        goal
                    }) =>
            {
                let p = if what == "start" { start } else { goal };
                f(
                    point_field(what),
                    format!(
                        "lies {:.4} m from obstacle {}, closer than robot.radius + robot.margin = {} m",
                        Shown(true_obstacles[obstacle].signed_distance(p)),
                        name_of(obstacle),
                        Shown(inflation)
                    ),
                )
            }
            WorldError::InObstacle { what, obstacle } => f(
                point_field(what),
                format!("lies inside obstacle {}", name_of(obstacle)),
            ),
            WorldError::OutsideWorkspace { what }
                if inflation > 0.0 && {
                    let p = if what == "start" { start } else { goal };
                    true_boundary.contains(p) && true_boundary.signed_distance(p) < 0.0
                } =>
            {
                let p = if what == "start" { start } else { goal };
                f(
                    point_field(what),
                    format!(
                        "lies {:.4} m from the workspace boundary, closer than robot.radius + \
                         robot.margin = {} m",
                        Shown(-true_boundary.signed_distance(p)),
                        Shown(inflation)
                    ),
                )
            }
            WorldError::OutsideWorkspace { what } => f(
                point_field(what),
                "lies on or outside the workspace boundary".into(),
            ),
            other => f("", other.to_string()),
        };
        let workspace = Workspace::for_robot(
            true_boundary.clone(),
            true_obstacles.clone(),
            goal,
            inflation,
        )
        .map_err(|e| match e {
            RobotWorldError::World(w) => world_error(w),
            RobotWorldError::Shape {
                obstacle: Some(i),
                error,
            } => f(
                inflation_field,
                format!("{inflated_by} obstacle {}: {error}", name_of(i)),
            ),
            RobotWorldError::Shape {
                obstacle: None,
                error,
            } => f(
                inflation_field,
                format!("{inflated_by} the workspace boundary: {error}"),
            ),
        })?;
        workspace.check_free(start, "start").map_err(world_error)?;
        // Free of the grown obstacles and inside the shrunk boundary, as robot.start.
        let free = |p: Vector2<f64>| {
            let clear = workspace
                .obstacles()
                .iter()
                .all(|o| o.signed_distance(p) > 0.0)
                && workspace.boundary().signed_distance(p) < 0.0;
            if clear {
                Ok(())
            } else {
                Err(format!(
                    "lies within robot.radius + robot.margin = {inflation} m of an obstacle or \
                     the boundary"
                ))
            }
        };
        let diff = self.controller.base == BaseKind::Diff;
        check_fleet(
            &self.sim.robots,
            (r.start, r.radius),
            &self.sim.movers,
            diff,
            free,
        )
        .map_err(|(field, p)| f(&field, p))?;
        let lidar = self
            .sensor
            .as_ref()
            .is_some_and(|s| s.kind == SensorKind::Lidar);
        // A lidar's fits bound the true surface it scans (A2, A4), the sector's d_min the grown
        // shapes the navigator holds: a lidar takes the smaller of the two.
        let rho_default = workspace
            .obstacles()
            .iter()
            .chain(if lidar { &true_obstacles[..] } else { &[] })
            .map(StarShape::rho_min)
            .fold(f64::INFINITY, f64::min);
        let (sensor, rho_min) = match &self.sensor {
            None => (Sensor::Global, rho_default),
            Some(spec) => {
                if spec.kind == SensorKind::Sector {
                    let given = sensor::lidar_only_fields(spec).into_iter().find(|f| f.1);
                    if let Some((name, _)) = given {
                        return Err(f(
                            &format!("sensor.{name}"),
                            "only a lidar takes it (sensor.type = \"lidar\")".into(),
                        ));
                    }
                }
                // Below a thousandth of a degree the sector's d_min (eq. dmin) underflows.
                if !(spec.aperture_deg.is_finite() && spec.aperture_deg >= MIN_APERTURE_DEG) {
                    return Err(f(
                        "sensor.aperture_deg",
                        format!(
                            "must be in (0, 360] and at least {MIN_APERTURE_DEG}°, got {:e}",
                            spec.aperture_deg
                        ),
                    ));
                }
                in_range("sensor.range", spec.range)?;
                let sector = Sector::new(spec.range, spec.aperture_deg.to_radians()).map_err(
                    |e| match e {
                        harmonav_sensing::SensorError::Range(v) => f(
                            "sensor.range",
                            format!("must be finite and positive, got {v:e}"),
                        ),
                        harmonav_sensing::SensorError::Aperture(_) => f(
                            "sensor.aperture_deg",
                            format!("must be in (0, 360], got {:e}", spec.aperture_deg),
                        ),
                    },
                )?;
                let rho = spec.rho_min.unwrap_or(rho_default);
                let no_bound_needed = spec.rho_min.is_none() && self.obstacles.is_empty();
                let (lo, hi) = PARAMETER_RANGE;
                if !(no_bound_needed || rho.is_finite() && (lo..=hi).contains(&rho)) {
                    // Without `sensor.rho_min`, the obstacle whose curvature set it is named
                    // (grown by radius + margin, as the default takes it, and as seen by a
                    // lidar).
                    let grown = workspace.obstacles().iter().map(|o| (o.rho_min(), true));
                    let seen = true_obstacles
                        .iter()
                        .filter(|_| lidar)
                        .map(|o| (o.rho_min(), false));
                    let sharpest = grown
                        .enumerate()
                        .chain(seen.enumerate())
                        .min_by(|a, b| a.1.0.total_cmp(&b.1.0))
                        .filter(|_| spec.rho_min.is_none());
                    return Err(match sharpest {
                        Some((i, (r, grown))) => f(
                            &format!("obstacles[{i}]"),
                            format!(
                                "its smallest curvature radius{} {r:e} m is outside [{lo:e}, \
                                 {hi:e}] m, the range of sensor.rho_min, which defaults to it; \
                                 give sensor.rho_min, or round the shape",
                                if grown {
                                    " (grown by robot.radius + robot.margin)"
                                } else {
                                    ""
                                }
                            ),
                        ),
                        None => f(
                            "sensor.rho_min",
                            format!("must be finite and in [{lo:e}, {hi:e}] m, got {rho:e}"),
                        ),
                    });
                }
                match spec.kind {
                    SensorKind::Sector => (Sensor::Sector(sector), rho),
                    SensorKind::Lidar => (
                        Sensor::Lidar(
                            sensor::prepare(
                                spec,
                                sensor::WallRoom::star(&true_boundary, &true_obstacles),
                                &true_obstacles,
                            )
                            .map_err(|(field, problem)| f(&format!("sensor.{field}"), problem))?,
                        ),
                        rho,
                    ),
                }
            }
        };
        let (radius, margin) = (self.robot.radius, self.robot.margin);
        Ok(Prepared {
            scenario: self,
            truth: Truth {
                boundary: true_boundary,
                obstacles: true_obstacles,
                names,
                workspace: std::sync::Arc::new(workspace),
                sensor,
                rho_min,
                radius,
                margin,
            },
        })
    }
}

impl Prepared {
    /// The start `robot.start`.
    pub fn start(&self) -> Vector2<f64> {
        Vector2::from(self.scenario.robot.start)
    }

    /// The `k` policy of the file's `[field]` table.
    pub fn k_policy(&self) -> KPolicy {
        self.scenario.field.k
    }

    /// The damping policy of the file's `[controller]` table.
    pub fn damping_policy(&self) -> DampingPolicy {
        self.scenario.controller.damping
    }

    /// The kinematic law's speed policy of the file's `[controller]` table.
    pub fn speed_policy(&self) -> SpeedPolicy {
        self.scenario.controller.speed
    }

    /// `Θ` with every obstacle known (global sensing) under the file's `k` policy.
    pub fn global_field(&self) -> Result<Field, FieldError> {
        Field::all_known_with(self.truth.workspace.clone(), self.k_policy())
    }

    /// The guaranteed clearance to the true shapes: `robot.margin`.
    pub fn margin(&self) -> f64 {
        self.scenario.robot.margin
    }

    /// The file's `[robot] control_period`, s (`None`: the law's default).
    pub fn control_period(&self) -> Option<f64> {
        self.scenario.controller.control_period
    }

    /// The robot's base for the navigator ([`harmonav::Options::with_base`]):
    /// `Base::Diff { v_max, omega_max }` for `[robot] base = "diff"` (`v_max` the file's
    /// `[controller] v_max`), `None` for the default holonomic base.
    pub fn base(&self) -> Option<harmonav::Base> {
        self.scenario.controller.base_keys().base()
    }

    /// A differential drive's start heading `θ(0)`, rad (`[robot] yaw`, default 0).
    pub fn start_yaw(&self) -> f64 {
        self.scenario.controller.yaw.unwrap_or(0.0)
    }
}

/// The text of a scenario file (at most [`MAX_FILE_BYTES`]: a device or a huge file is refused
/// instead of read forever), or the error naming the file.
pub fn read_text(path: &Path) -> Result<String, ScenarioError> {
    use std::io::Read;
    let cannot = |e: std::io::Error| err(path, "", None, format!("cannot read the file: {e}"));
    // Only a regular file: a FIFO would block in `open` (issue 56, D14).
    if !std::fs::metadata(path).map_err(cannot)?.is_file() {
        return Err(err(
            path,
            "",
            None,
            "cannot read the file: not a regular file (a folder, a FIFO or a device)".into(),
        ));
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .map_err(cannot)?
        .take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(cannot)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(err(
            path,
            "",
            None,
            format!("the file is larger than {} MiB", MAX_FILE_BYTES >> 20),
        ));
    }
    let text = String::from_utf8(bytes)
        .map_err(|e| err(path, "", None, format!("the file is not UTF-8 text: {e}")))?;
    Ok(text)
}

/// A physical parameter (`robot.mass`, a gain, `μ`, …): finite and in
/// [`PARAMETER_RANGE`]; else the problem.
pub(crate) fn parameter(v: f64) -> Result<(), String> {
    let (lo, hi) = PARAMETER_RANGE;
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(format!("must be finite and in [{lo:e}, {hi:e}], got {v:e}"))
    }
}

/// `robot.control_period` `h`, s, of a run of at most `max_time` s: finite and in
/// [`PARAMETER_RANGE`] (the navigator's range), and at most [`MAX_RECORDED_STATES`] periods
/// in `max_time` (a held-command loop takes a step each period); else the problem.
pub(crate) fn control_period(h: f64, max_time: f64) -> Result<(), String> {
    let (lo, hi) = PARAMETER_RANGE;
    if !(h.is_finite() && (lo..=hi).contains(&h)) {
        return Err(format!(
            "must be finite and in [{lo:e}, {hi:e}] s, got {h:e}"
        ));
    }
    if max_time / h > MAX_RECORDED_STATES {
        return Err(format!(
            "sim.max_time / robot.control_period = {:.3e} periods; at most \
             {MAX_RECORDED_STATES:e} (raise robot.control_period or lower sim.max_time)",
            max_time / h
        ));
    }
    Ok(())
}

/// A length of the robot (`robot.radius`, `robot.margin`): finite and in `[0, MAX_LENGTH]` m;
/// else the problem.
pub(crate) fn length(v: f64) -> Result<(), String> {
    let hi = harmonav_transform::MAX_LENGTH;
    if v.is_finite() && (0.0..=hi).contains(&v) {
        Ok(())
    } else {
        Err(format!("must be finite and in [0, {hi:e}] m, got {v:e}"))
    }
}

/// The obstacles' names (`unnamed(i)` where none is given: `O1`, `O2`, … in a star world,
/// as its outputs show them), or the field of the first name used twice and the problem.
pub(crate) fn obstacle_names(
    obstacles: &[ShapeSpec],
    unnamed: impl Fn(usize) -> String,
) -> Result<Vec<String>, (String, String)> {
    let mut names: Vec<String> = Vec::with_capacity(obstacles.len());
    for (i, o) in obstacles.iter().enumerate() {
        let name = o.name().map_or_else(|| unnamed(i), str::to_string);
        if names.contains(&name) {
            return Err((
                format!("obstacles[{i}].name"),
                format!("the name \"{name}\" is used twice"),
            ));
        }
        names.push(name);
    }
    Ok(names)
}

/// A TOML error of the scenario file `path` (text `text`) with the field it lies in: the
/// failing `obstacles[i]` (a shape is an internally tagged enum, whose errors point at the
/// whole `[[obstacles]]` array), else the table at the error and the key on its line, so that
/// a wrong type names its field.
pub(crate) fn toml_error(path: &Path, text: &str, e: &toml::de::Error) -> ScenarioError {
    if is_map_yaml(text) {
        return map_yaml_error(path);
    }
    let problem = e.message().trim().to_string();
    let Some(span) = e.span() else {
        return err(path, "", None, problem);
    };
    let start = span.start.min(text.len());
    // A key missing at the top level: its span is empty at the start (or the whole document),
    // which the table scan below would blame on the first table ("`floor_plan`: missing field
    // `name`").
    if start == 0
        && (span.end == 0 || span.end >= text.trim_end().len())
        && let Some(key) = problem
            .strip_prefix("missing field `")
            .and_then(|r| r.strip_suffix('`'))
    {
        return err(
            path,
            key,
            None,
            "missing: a top-level key of the file".into(),
        );
    }
    if let Some(i) = failing_obstacle(text) {
        return err(
            path,
            &format!("obstacles[{i}]"),
            obstacle_line(text, i),
            problem,
        );
    }
    let line = text[..start].matches('\n').count() + 1;
    let table = table_at(text, start);
    let key = text[..start]
        .rsplit('\n')
        .next()
        .and_then(|l| l.split_once('='))
        .map(|(k, _)| k.trim().trim_matches('"').to_string())
        .filter(|k| !k.is_empty() && !k.contains(['[', ' ']));
    let field = match (table.is_empty(), key) {
        (_, None) => table,
        (true, Some(k)) => k,
        (false, Some(k)) => format!("{table}.{k}"),
    };
    err(path, &field, Some(line), problem)
}

/// Whether `text` (which is not TOML) reads as a ROS map_server YAML: top-level `image:` and
/// `resolution:` keys (issue 56, D19.12: such a file given as the scenario got "key with no
/// value, expected `=`").
pub(crate) fn is_map_yaml(text: &str) -> bool {
    let key = |name: &str| {
        text.lines().any(|l| {
            l.strip_prefix(name)
                .is_some_and(|r| r.trim_start().starts_with(':'))
        })
    };
    key("image") && key("resolution")
}

/// The error of a map_server YAML given as the scenario ([`is_map_yaml`]).
pub(crate) fn map_yaml_error(path: &Path) -> ScenarioError {
    err(
        path,
        "",
        None,
        "this is a map_server YAML (a map's `image`, `resolution` and `origin`), not a \
         scenario: name it in a floor-plan file, `[floor_plan] map = \"FILE.yaml\"` (README, \
         \"Floor plans\")"
            .into(),
    )
}

pub(crate) fn err(path: &Path, field: &str, line: Option<usize>, problem: String) -> ScenarioError {
    ScenarioError {
        file: path.to_path_buf(),
        field: field.to_string(),
        line,
        problem,
    }
}

fn check_point(p: [f64; 2], _field: &str) -> Result<(), String> {
    if p.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(format!("NaN or infinite coordinate in {p:?}"))
    }
}

/// The shape a scenario gives ([`ShapeSpec`]); on error, the sub-field (`radius`, `harmonics`)
/// and the problem, for a [`ScenarioError`] that names the whole field path.
pub fn build_shape(s: &ShapeSpec) -> Result<StarShape, (String, String)> {
    let v = |p: [f64; 2]| Vector2::new(p[0], p[1]);
    let shape = match s {
        ShapeSpec::Circle { center, radius, .. } => StarShape::circle(v(*center), *radius),
        ShapeSpec::Ellipse {
            center,
            semi_axes,
            angle_deg,
            ..
        } => StarShape::ellipse(v(*center), *semi_axes, angle_deg.to_radians()),
        ShapeSpec::Polygon {
            vertices,
            corner_radius,
            ..
        } => StarShape::rounded_polygon(
            &vertices.iter().map(|p| v(*p)).collect::<Vec<_>>(),
            *corner_radius,
        ),
        ShapeSpec::Star {
            center,
            radius,
            harmonics,
            ..
        } => {
            let mut h = Vec::with_capacity(harmonics.len());
            for &[n, a, b] in harmonics {
                if !(n >= 1.0
                    && n.fract() == 0.0
                    && n <= f64::from(harmonav_transform::MAX_HARMONIC))
                {
                    return Err((
                        "harmonics".into(),
                        format!("harmonic numbers must be whole numbers from 1, got {n}"),
                    ));
                }
                h.push((n as u32, a, b));
            }
            StarShape::fourier_star(v(*center), *radius, &h)
        }
    };
    shape.map_err(|e| match e {
        harmonav_transform::ShapeError::NonFinite { field } => {
            (field.to_string(), "NaN or infinite number".into())
        }
        harmonav_transform::ShapeError::NotPositive { field, value } => (
            field.to_string(),
            format!("must be positive, got {value:e}"),
        ),
        harmonav_transform::ShapeError::Invalid { field, problem } => (field.to_string(), problem),
        other => ("".into(), other.to_string()),
    })
}

/// The index of the first `[[obstacles]]` entry that is not a valid shape on its own, if any.
fn failing_obstacle(text: &str) -> Option<usize> {
    let doc: toml::Table = toml::from_str(text).ok()?;
    let obstacles = doc.get("obstacles")?.as_array()?;
    obstacles
        .iter()
        .position(|o| o.clone().try_into::<ShapeSpec>().is_err())
}

/// The line of the `i`-th `[[obstacles]]` header.
fn obstacle_line(text: &str, i: usize) -> Option<usize> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| l.trim().starts_with("[[obstacles]]"))
        .nth(i)
        .map(|(n, _)| n + 1)
}

/// The table a byte offset falls in: `workspace`, `obstacles[i]`, `robot`, … (for error
/// messages; empty before the first table header).
fn table_at(text: &str, offset: usize) -> String {
    let mut table = String::new();
    // The entries so far of each array of tables (`[[obstacles]]`, `[[movers]]`).
    let mut arrays: Vec<(String, usize)> = Vec::new();
    let mut pos = 0;
    for line in text.split_inclusive('\n') {
        if pos > offset {
            break;
        }
        let t = line.trim();
        if let Some(rest) = t.strip_prefix("[[") {
            let name = rest.split("]]").next().unwrap_or("").trim().to_string();
            let i = match arrays.iter_mut().find(|(n, _)| *n == name) {
                Some((_, count)) => {
                    *count += 1;
                    *count - 1
                }
                None => {
                    arrays.push((name.clone(), 1));
                    0
                }
            };
            table = format!("{name}[{i}]");
        } else if t.starts_with('[') {
            table = t
                .trim_matches(|c| c == '[' || c == ']')
                .split(']')
                .next()
                .unwrap_or("")
                .trim()
                .to_string();
        }
        pos += line.len();
    }
    table
}
