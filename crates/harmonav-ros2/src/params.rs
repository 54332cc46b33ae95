//! The node's parameters: a ROS 2 parameter file in ROS's own format, given as
//! `harmonav-ros2 --ros-args --params-file FILE` (several files: later ones win), and
//! `-p name:=value` overrides, as `ros2 run` passes them.
//!
//! ```yaml
//! /**:                      # or the node's name, `harmonav` (`/harmonav`)
//!   ros__parameters:
//!     global_frame: map
//!     controller_frequency: 20.0
//! ```
//!
//! Nested maps flatten with dots, as ROS's do. An unknown parameter or a value of the wrong
//! type is an error naming it (a typo must not silently keep a default).

use std::fmt;

use yaml_rust2::{Yaml, YamlLoader};

/// The node's name (the key a parameter file may use instead of `/**`).
pub const NODE_NAME: &str = "harmonav";

/// The kinematics of the base.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Base {
    /// `linear.x`, `linear.y`.
    Holonomic,
    /// `linear.x`, `angular.z` (differential drive).
    Diff,
}

/// How a service's request is matched to its reply on the wire: ROS 2's RMWs differ. The
/// `navigate_to_pose` action's three services use it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ServiceWire {
    /// The RPC-over-DDS "enhanced" mapping (the request's identity in inline QoS): Fast DDS,
    /// ROS 2's default RMW (`rmw_fastrtps_cpp`), and Connext.
    Enhanced,
    /// A header in the payload: `rmw_cyclonedds_cpp`.
    Cyclone,
}

/// The navigation law.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LawKind {
    /// `u = −K∇Θ` (a velocity).
    Kinematic,
    /// A force, integrated by the node into the velocity it publishes.
    Dynamic,
}

/// Every parameter, with Nav2's names where Nav2 has one.
#[derive(Clone, Debug, PartialEq)]
pub struct Params {
    /// The navigation frame of the floor plan and of goals (`map`).
    pub global_frame: String,
    /// The odometry frame (`odom`).
    pub odom_frame: String,
    /// The robot's base frame (`base_link`).
    pub robot_base_frame: String,
    /// The floor plan's topic; empty: no map, a disc around the robot from scans alone.
    pub map_topic: String,
    /// The laser scans' topic.
    pub scan_topic: String,
    /// The odometry's topic.
    pub odom_topic: String,
    /// The goals' topic (RViz's "2D Goal Pose").
    pub goal_topic: String,
    /// The velocity commands' topic.
    pub cmd_vel_topic: String,
    /// The status topic (`std_msgs/String`: mode and reasons).
    pub status_topic: String,
    /// The perceived obstacles' topic (`visualization_msgs/MarkerArray`, their outlines as line
    /// strips in `global_frame`, on each change); empty: none.
    pub obstacles_topic: String,
    /// The `navigate_to_pose` action's name (Nav2's); empty: no action server.
    pub action_name: String,
    /// The request/reply mapping of the action's services: `enhanced` (Fast DDS, the default
    /// RMW) or `cyclone` (`rmw_cyclonedds_cpp`).
    pub service_mapping: ServiceWire,
    /// Hz: the control period `1/f` is the period every command is certified to be held for.
    pub controller_frequency: f64,
    /// m.
    pub robot_radius: f64,
    /// m: the clearance kept beyond the radius.
    pub margin: f64,
    /// `kinematic` or `dynamic`.
    pub law: LawKind,
    /// The kinematic law's gain `K`.
    pub gain: f64,
    /// The dynamic law's mass (kg) and `μ`.
    pub mass: f64,
    /// The dynamic law's `μ` (the energy bound).
    pub mu: f64,
    /// m/s: the kinematic law's top speed (≤ 0: the law's own, `K√2`; a differential-drive
    /// base's top forward speed, 0.5 m/s when ≤ 0).
    pub v_max: f64,
    /// m: arrival radius of a goal without a yaw (unless `xy_goal_tolerance` is given). A goal
    /// with a yaw (`use_goal_orientation` on a `diff` base) is reached when harmonav's
    /// `command_pose` reports it arrived: within `xy_goal_tolerance` (default
    /// `GOAL_ARRIVAL`, 1 cm) of the position and then turned in place to within
    /// `yaw_goal_tolerance` of the yaw.
    pub goal_tolerance: f64,
    /// m: Nav2's goal checker's name. Given, it is the position tolerance of every goal: the
    /// arrival radius of a goal without a yaw (`goal_tolerance` is then not read) and the
    /// radius where a goal with a yaw turns in place (`harmonav::GoalTolerance::xy`). `None`
    /// (not given): `goal_tolerance`, and 1 cm (`GOAL_ARRIVAL`) for a goal with a yaw. Also
    /// read under a goal checker's name ([`GoalCheckerKeys`]), as `yaw_goal_tolerance` and
    /// `stateful` are.
    pub xy_goal_tolerance: Option<f64>,
    /// rad: where the turn in place to a goal's yaw ends (`harmonav::GoalTolerance::yaw`;
    /// Nav2's goal checker's name). Default harmonav's `GOAL_HEADING_TOLERANCE`, 1e-3 rad (Nav2's
    /// is 0.25).
    pub yaw_goal_tolerance: f64,
    /// Nav2's goal checker's `stateful`: the position tolerance of a goal with a yaw latches
    /// (`Navigator::set_goal_stateful`): once within `xy_goal_tolerance`, the base only brakes
    /// and turns in place, wherever it rolls. Default true, as Nav2's.
    pub stateful: bool,
    /// Nav2's goal checker keys under a plugin's name (`goal_checker_plugins`,
    /// `<name>.xy_goal_tolerance`, …) as given, taken by [`Params::resolve`].
    pub goal_checker: GoalCheckerKeys,
    /// A `diff` base finishes at the goal's yaw (the orientation of `/goal_pose` and of the
    /// action's goals, in `global_frame`), by turning in place once at the position
    /// (`Navigator::set_goal_heading`); false: the orientation is ignored and arrival is within
    /// `goal_tolerance`, as before. Ignored for a `holonomic` base, which never turns
    /// (`angular.z` is 0) and reads no goal orientation.
    pub use_goal_orientation: bool,
    /// Publish `TwistStamped` instead of `Twist` (Nav2's name).
    pub enable_stamped_cmd_vel: bool,
    /// `holonomic` or `diff`.
    pub base: Base,
    /// rad/s: a differential-drive base's top turn rate.
    pub omega_max: f64,
    /// m/s² and rad/s²: a differential-drive base's acceleration limits (`harmonav::Accel`,
    /// docs/unicycle.md §10); 0 for both: none. Both or neither.
    pub a_max: f64,
    /// See `a_max`.
    pub alpha_max: f64,
    /// s: a scan older than this stops the robot.
    pub scan_timeout: f64,
    /// s: odometry older than this stops the robot.
    pub odom_timeout: f64,
    /// s: a dynamic transform (`/tf`) older than this stops the robot.
    pub transform_timeout: f64,
    /// Stop on stale data (the negative control of the tests turns it off; never on a robot).
    pub stale_stop: bool,
    /// s: a goal during which the robot has not moved `required_movement_radius` for this long
    /// (however it came to stand: refused commands, stale data, a stuck base) is given up,
    /// aborted with Nav2's `FAILED_TO_MAKE_PROGRESS`, and the robot stopped (the name and
    /// default of Nav2's `SimpleProgressChecker`); 0 never gives up.
    pub movement_time_allowance: f64,
    /// m: the distance from where the robot last made progress that counts as progress
    /// (Nav2's `SimpleProgressChecker`).
    pub required_movement_radius: f64,
    /// m: the lidar's range for the perception's priors (`Options::with_sensor`).
    pub sensor_range: f64,
    /// m: without a map, the radius of the disc around the robot (at the goal's arrival) that
    /// is navigated; at least the goal's distance plus a metre.
    pub scan_world_radius: f64,
    /// m: the floor plan's boundary element (`FloorOptions`' `h`).
    pub max_element: f64,
    /// map_server's thresholds for the grid's occupancies (0–100 as 0–1).
    pub occupied_thresh: f64,
    /// map_server's free threshold.
    pub free_thresh: f64,
    /// Take time from `/clock` (`rosgraph_msgs/Clock`) for stamps.
    pub use_sim_time: bool,
}

impl Default for Params {
    fn default() -> Self {
        Self {
            global_frame: "map".into(),
            odom_frame: "odom".into(),
            robot_base_frame: "base_link".into(),
            map_topic: "map".into(),
            scan_topic: "scan".into(),
            odom_topic: "odom".into(),
            goal_topic: "goal_pose".into(),
            cmd_vel_topic: "cmd_vel".into(),
            status_topic: "harmonav/status".into(),
            obstacles_topic: "harmonav/obstacles".into(),
            action_name: "navigate_to_pose".into(),
            service_mapping: ServiceWire::Enhanced,
            controller_frequency: 20.0,
            robot_radius: 0.1,
            margin: 0.05,
            law: LawKind::Kinematic,
            gain: 1.0,
            mass: 1.0,
            mu: 10.0,
            v_max: 0.0,
            goal_tolerance: 0.1,
            xy_goal_tolerance: None,
            yaw_goal_tolerance: harmonav::tuning::GOAL_HEADING_TOLERANCE,
            stateful: true,
            goal_checker: GoalCheckerKeys::default(),
            use_goal_orientation: true,
            enable_stamped_cmd_vel: false,
            base: Base::Holonomic,
            omega_max: 1.0,
            a_max: 0.0,
            alpha_max: 0.0,
            scan_timeout: 0.5,
            odom_timeout: 0.5,
            transform_timeout: 1.0,
            stale_stop: true,
            movement_time_allowance: 10.0,
            required_movement_radius: 0.5,
            sensor_range: 3.5,
            scan_world_radius: 5.0,
            max_element: 0.2,
            occupied_thresh: 0.65,
            free_thresh: 0.25,
            use_sim_time: false,
        }
    }
}

impl Params {
    /// m: the arrival radius of a goal without a yaw, `xy_goal_tolerance` if given, else
    /// `goal_tolerance`.
    #[must_use]
    pub fn arrival_radius(&self) -> f64 {
        self.xy_goal_tolerance.unwrap_or(self.goal_tolerance)
    }

    /// Where a goal with a yaw has arrived (`Navigator::set_goal_tolerance`):
    /// `xy_goal_tolerance` if given (else harmonav's 1 cm) and `yaw_goal_tolerance`.
    #[must_use]
    pub fn goal_tolerance(&self) -> harmonav::GoalTolerance {
        harmonav::GoalTolerance {
            xy: self
                .xy_goal_tolerance
                .unwrap_or(harmonav::tuning::GOAL_ARRIVAL),
            yaw: self.yaw_goal_tolerance,
        }
    }
}

/// The goal checker keys of Nav2's parameter files, as given, before [`Params::resolve`].
///
/// Nav2's controller_server names its goal checkers in `goal_checker_plugins` (default
/// `["goal_checker"]`) and reads each one's keys under its name, e.g.
///
/// ```yaml
/// goal_checker_plugins: ["general_goal_checker"]
/// general_goal_checker:
///   plugin: "nav2_controller::SimpleGoalChecker"
///   xy_goal_tolerance: 0.25
///   yaw_goal_tolerance: 0.25
///   stateful: true
/// ```
///
/// The node has one goal checker: the keys `xy_goal_tolerance`, `yaw_goal_tolerance` and
/// `stateful` are read under the first name of `goal_checker_plugins` (`<name>.plugin` is
/// accepted and not read; keys under the other names listed are accepted and not read, as
/// the node does not pick a checker per goal). Without `goal_checker_plugins`, under any one
/// name (two names is an error naming a key of each). The bare keys (the node's own, before
/// the namespaced ones were read) still work; given both ways with different values is an
/// error naming both keys.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GoalCheckerKeys {
    /// `goal_checker_plugins`, if given.
    pub plugins: Option<Vec<String>>,
    /// The bare keys given (`xy_goal_tolerance`, …), the last value of each.
    bare: Vec<(&'static str, Value)>,
    /// The namespaced keys given: the plugin's name, the key, the value; the last of each.
    namespaced: Vec<(String, &'static str, Value)>,
}

/// The goal checker's keys, bare or under a plugin's name.
const CHECKER_KEYS: [&str; 3] = ["xy_goal_tolerance", "yaw_goal_tolerance", "stateful"];

/// Nav2's other goal checker keys (`SimpleGoalChecker`, `StoppedGoalChecker`), under a
/// plugin's name (`name`): checked for their type and accepted unread, so that a Nav2
/// parameter file loads (`None` for any other key). `trans_stopped_velocity` and
/// `rot_stopped_velocity` (non-negative): harmonav's arrival commands `(0, 0)` itself;
/// `path_length_tolerance` (non-negative): there is no global path; `symmetric_yaw_tolerance`:
/// `false` only (accepting the goal yaw + 180° is not built, and ignoring `true` would turn
/// the robot where the user asked it not to).
fn ignored_checker_key(name: &str, key: &str, value: &Value) -> Option<Result<(), ParamError>> {
    let number = |v: &Value| match *v {
        Value::Float(x) => Some(x),
        Value::Int(i) => Some(i as f64),
        _ => None,
    };
    Some(match key {
        "trans_stopped_velocity" | "rot_stopped_velocity" | "path_length_tolerance" => {
            match number(value) {
                Some(x) if x.is_finite() && x >= 0.0 => Ok(()),
                _ => Err(ParamError(format!(
                    "parameter {name}: expected a finite number ≥ 0, got {value:?} (Nav2's goal \
                     checker key; accepted and not read by harmonav)"
                ))),
            }
        }
        "symmetric_yaw_tolerance" => match value {
            Value::Bool(false) => Ok(()),
            Value::Bool(true) => Err(ParamError(format!(
                "parameter {name}: true is not supported (harmonav turns to the goal yaw \
                 itself, not to it or its opposite); remove it or set it false"
            ))),
            _ => Err(ParamError(format!(
                "parameter {name}: expected true or false, got {value:?}"
            ))),
        },
        _ => return None,
    })
}

impl GoalCheckerKeys {
    /// Records `value`, already checked, for `key` (bare: `plugin` `None`); a later value
    /// replaces an earlier one.
    fn record(&mut self, plugin: Option<&str>, key: &'static str, value: Value) {
        match plugin {
            None => {
                self.bare.retain(|(k, _)| *k != key);
                self.bare.push((key, value));
            }
            Some(p) => {
                self.namespaced.retain(|(q, k, _)| !(q == p && *k == key));
                self.namespaced.push((p.to_owned(), key, value));
            }
        }
    }

    /// The plugin whose keys are read: the first of `goal_checker_plugins`, else the one name
    /// keys were given under; `None` when no key was given under a name.
    fn chosen(&self) -> Result<Option<String>, ParamError> {
        if let Some(plugins) = &self.plugins {
            if let Some((p, k, _)) = self.namespaced.iter().find(|(p, ..)| !plugins.contains(p)) {
                return Err(ParamError(format!(
                    "parameter {p}.{k}: {p} is not in goal_checker_plugins {plugins:?}"
                )));
            }
            return Ok(plugins.first().cloned());
        }
        let mut names = self.namespaced.iter();
        let Some((first, k1, _)) = names.next() else {
            return Ok(None);
        };
        if let Some((other, k2, _)) = names.find(|(p, ..)| p != first) {
            return Err(ParamError(format!(
                "parameters {first}.{k1} and {other}.{k2}: two goal checkers; name the one to \
                 read in goal_checker_plugins"
            )));
        }
        Ok(Some(first.clone()))
    }

    /// The value of `key` under `plugin`, checked against the bare key's.
    fn value(&self, plugin: &str, key: &str) -> Result<Option<&Value>, ParamError> {
        let under = self
            .namespaced
            .iter()
            .find(|(p, k, _)| p == plugin && *k == key)
            .map(|(.., v)| v);
        let bare = self.bare.iter().find(|(k, _)| *k == key).map(|(_, v)| v);
        match (under, bare) {
            (Some(a), Some(b)) if !a.same(b) => Err(ParamError(format!(
                "parameters {key} ({b:?}) and {plugin}.{key} ({a:?}) differ: give one"
            ))),
            (Some(a), _) => Ok(Some(a)),
            (None, _) => Ok(None),
        }
    }
}

/// A parameter that could not be taken.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamError(pub String);

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ParamError {}

/// One value as ROS writes it.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// `true`/`false`.
    Bool(bool),
    /// An integer.
    Int(i64),
    /// A float.
    Float(f64),
    /// A string.
    Str(String),
    /// A list of strings (`goal_checker_plugins`).
    StrList(Vec<String>),
}

impl Value {
    fn from_yaml(y: &Yaml) -> Option<Self> {
        Some(match y {
            Yaml::Boolean(b) => Self::Bool(*b),
            Yaml::Integer(i) => Self::Int(*i),
            Yaml::Real(_) => Self::Float(y.as_f64()?),
            Yaml::String(s) => Self::Str(s.clone()),
            Yaml::Array(items) => Self::StrList(
                items
                    .iter()
                    .map(|i| i.as_str().map(str::to_owned))
                    .collect::<Option<_>>()?,
            ),
            _ => return None,
        })
    }

    /// The same value: numbers compared as numbers (`1` and `1.0` are the same).
    fn same(&self, other: &Self) -> bool {
        #[allow(clippy::cast_precision_loss)]
        let number = |v: &Self| match *v {
            Self::Int(i) => Some(i as f64),
            Self::Float(f) => Some(f),
            _ => None,
        };
        match (number(self), number(other)) {
            (Some(a), Some(b)) => a == b,
            _ => self == other,
        }
    }

    /// A command-line value (`-p name:=value`): YAML's reading of the text.
    fn from_text(text: &str) -> Self {
        match YamlLoader::load_from_str(text)
            .ok()
            .and_then(|d| d.first().and_then(Value::from_yaml))
        {
            Some(v) => v,
            None => Self::Str(text.to_owned()),
        }
    }
}

impl Params {
    /// Sets one parameter by name.
    ///
    /// # Errors
    /// An unknown name, a value of the wrong type or out of range.
    pub fn set(&mut self, name: &str, value: &Value) -> Result<(), ParamError> {
        let wrong =
            |want: &str| ParamError(format!("parameter {name}: expected {want}, got {value:?}"));
        let text = |v: &Value| match v {
            Value::Str(s) => Ok(s.clone()),
            _ => Err(wrong("a string")),
        };
        let float = |v: &Value| match *v {
            #[allow(clippy::cast_precision_loss)]
            Value::Int(i) => Ok(i as f64),
            Value::Float(f) if f.is_finite() => Ok(f),
            _ => Err(wrong("a finite number")),
        };
        let positive = |v: &Value| {
            let f = float(v)?;
            if f > 0.0 {
                Ok(f)
            } else {
                Err(wrong("a number > 0"))
            }
        };
        let flag = |v: &Value| match *v {
            Value::Bool(b) => Ok(b),
            _ => Err(wrong("true or false")),
        };
        match name {
            "global_frame" => self.global_frame = text(value)?,
            "odom_frame" => self.odom_frame = text(value)?,
            "robot_base_frame" => self.robot_base_frame = text(value)?,
            "map_topic" => self.map_topic = text(value)?,
            "scan_topic" => self.scan_topic = text(value)?,
            "odom_topic" => self.odom_topic = text(value)?,
            "goal_topic" => self.goal_topic = text(value)?,
            "cmd_vel_topic" => self.cmd_vel_topic = text(value)?,
            "status_topic" => self.status_topic = text(value)?,
            "obstacles_topic" => self.obstacles_topic = text(value)?,
            "action_name" => self.action_name = text(value)?,
            "service_mapping" => {
                self.service_mapping = match text(value)?.as_str() {
                    "enhanced" => ServiceWire::Enhanced,
                    "cyclone" => ServiceWire::Cyclone,
                    _ => return Err(wrong("\"enhanced\" or \"cyclone\"")),
                }
            }
            "controller_frequency" => self.controller_frequency = positive(value)?,
            "robot_radius" => self.robot_radius = positive(value)?,
            "margin" => {
                self.margin = float(value)?;
                if self.margin < 0.0 {
                    return Err(wrong("a number ≥ 0"));
                }
            }
            "law" => {
                self.law = match text(value)?.as_str() {
                    "kinematic" => LawKind::Kinematic,
                    "dynamic" => LawKind::Dynamic,
                    _ => return Err(wrong("\"kinematic\" or \"dynamic\"")),
                }
            }
            "gain" => self.gain = positive(value)?,
            "mass" => self.mass = positive(value)?,
            "mu" => self.mu = positive(value)?,
            "v_max" => self.v_max = float(value)?,
            "goal_tolerance" => self.goal_tolerance = positive(value)?,
            "xy_goal_tolerance" => {
                self.xy_goal_tolerance = Some(positive(value)?);
                self.goal_checker
                    .record(None, "xy_goal_tolerance", value.clone());
            }
            "yaw_goal_tolerance" => {
                self.yaw_goal_tolerance = positive(value)?;
                self.goal_checker
                    .record(None, "yaw_goal_tolerance", value.clone());
            }
            "stateful" => {
                self.stateful = flag(value)?;
                self.goal_checker.record(None, "stateful", value.clone());
            }
            "goal_checker_plugins" => {
                self.goal_checker.plugins = Some(match value {
                    Value::StrList(names) if !names.is_empty() => names.clone(),
                    _ => return Err(wrong("a non-empty list of names")),
                });
            }
            "use_goal_orientation" => self.use_goal_orientation = flag(value)?,
            "enable_stamped_cmd_vel" => self.enable_stamped_cmd_vel = flag(value)?,
            "base" => {
                self.base = match text(value)?.as_str() {
                    "holonomic" => Base::Holonomic,
                    "diff" => Base::Diff,
                    _ => return Err(wrong("\"holonomic\" or \"diff\"")),
                }
            }
            "omega_max" => self.omega_max = positive(value)?,
            "a_max" => self.a_max = float(value)?,
            "alpha_max" => self.alpha_max = float(value)?,
            "scan_timeout" => self.scan_timeout = positive(value)?,
            "odom_timeout" => self.odom_timeout = positive(value)?,
            "transform_timeout" => self.transform_timeout = positive(value)?,
            "stale_stop" => self.stale_stop = flag(value)?,
            "movement_time_allowance" => {
                self.movement_time_allowance = float(value)?;
                if self.movement_time_allowance < 0.0 {
                    return Err(wrong("a number ≥ 0"));
                }
            }
            "required_movement_radius" => self.required_movement_radius = positive(value)?,
            "sensor_range" => self.sensor_range = positive(value)?,
            "scan_world_radius" => self.scan_world_radius = positive(value)?,
            "max_element" => self.max_element = positive(value)?,
            "occupied_thresh" => self.occupied_thresh = float(value)?,
            "free_thresh" => self.free_thresh = float(value)?,
            "use_sim_time" => self.use_sim_time = flag(value)?,
            _ => return self.set_namespaced(name, value),
        }
        Ok(())
    }

    /// A goal checker's key under its plugin's name (`<plugin>.xy_goal_tolerance`, …,
    /// [`GoalCheckerKeys`]): checked as the bare key is (the error names the namespaced key)
    /// and recorded for [`Params::resolve`]; `<plugin>.plugin` takes any string.
    fn set_namespaced(&mut self, name: &str, value: &Value) -> Result<(), ParamError> {
        let unknown = || ParamError(format!("unknown parameter {name}"));
        let (plugin, key) = name.rsplit_once('.').ok_or_else(unknown)?;
        if key == "plugin" {
            return match value {
                Value::Str(_) => Ok(()),
                _ => Err(ParamError(format!(
                    "parameter {name}: expected a string, got {value:?}"
                ))),
            };
        }
        if let Some(ignored) = ignored_checker_key(name, key, value) {
            return ignored;
        }
        let key = CHECKER_KEYS
            .into_iter()
            .find(|k| *k == key)
            .ok_or_else(unknown)?;
        // The bare key's checks, on a scratch copy (the error renamed to the full name).
        let mut scratch = Params::default();
        scratch.set(key, value).map_err(|e| {
            ParamError(e.0.replacen(&format!("parameter {key}"), &format!("parameter {name}"), 1))
        })?;
        self.goal_checker.record(Some(plugin), key, value.clone());
        Ok(())
    }

    /// Takes the goal checker's keys given under a plugin's name ([`GoalCheckerKeys`]) into
    /// `xy_goal_tolerance`, `yaw_goal_tolerance` and `stateful`, once every file and `-p` has
    /// been read ([`parse_args`] calls it).
    ///
    /// # Errors
    /// A key under a name that is not in `goal_checker_plugins`, keys under two names without
    /// it, or a key given bare and namespaced with different values (naming both).
    pub fn resolve(&mut self) -> Result<(), ParamError> {
        let Some(plugin) = self.goal_checker.chosen()? else {
            return Ok(());
        };
        for key in CHECKER_KEYS {
            if let Some(value) = self.goal_checker.value(&plugin, key)?.cloned() {
                // Checked when given; `set` also records it as if bare, which only repeats it.
                self.set(key, &value)?;
            }
        }
        Ok(())
    }

    /// Reads a parameter file's text: the sections `/**` and the node's name
    /// ([`NODE_NAME`], with or without a leading slash), in the file's order.
    ///
    /// # Errors
    /// YAML errors, a section without `ros__parameters`, a parameter [`Params::set`] refuses.
    pub fn apply_file(&mut self, text: &str) -> Result<(), ParamError> {
        let docs = YamlLoader::load_from_str(text).map_err(|e| ParamError(format!("YAML: {e}")))?;
        let Some(Yaml::Hash(top)) = docs.first() else {
            return Err(ParamError("expected a map of node names".into()));
        };
        for (key, section) in top {
            let Some(node) = key.as_str() else { continue };
            let node = node.strip_prefix('/').unwrap_or(node);
            if node != "**" && node != NODE_NAME {
                continue;
            }
            let params = &section["ros__parameters"];
            let Yaml::Hash(params) = params else {
                return Err(ParamError(format!(
                    "section {node:?} has no ros__parameters map"
                )));
            };
            self.apply_map("", params)?;
        }
        Ok(())
    }

    fn apply_map(&mut self, prefix: &str, map: &yaml_rust2::yaml::Hash) -> Result<(), ParamError> {
        for (k, v) in map {
            let Some(k) = k.as_str() else {
                return Err(ParamError(format!(
                    "a parameter name that is not a string: {k:?}"
                )));
            };
            let name = if prefix.is_empty() {
                k.to_owned()
            } else {
                format!("{prefix}.{k}")
            };
            match v {
                Yaml::Hash(inner) => self.apply_map(&name, inner)?,
                _ => {
                    let value = Value::from_yaml(v).ok_or_else(|| {
                        ParamError(format!("parameter {name}: unsupported value {v:?}"))
                    })?;
                    self.set(&name, &value)?;
                }
            }
        }
        Ok(())
    }

    /// Checks what the single setters cannot.
    ///
    /// # Errors
    /// The thresholds out of order; a differential-drive base with the dynamic law (harmonav
    /// steers a unicycle under the kinematic law only).
    pub fn validate(&self) -> Result<(), ParamError> {
        if self.base == Base::Diff && self.law == LawKind::Dynamic {
            return Err(ParamError(
                "base = \"diff\" takes the kinematic law only (law = \"kinematic\")".into(),
            ));
        }
        let limit = |v: f64| v.is_finite() && v >= 0.0;
        if !(limit(self.a_max) && limit(self.alpha_max))
            || (self.a_max > 0.0) != (self.alpha_max > 0.0)
        {
            return Err(ParamError(
                "a_max (m/s²) and alpha_max (rad/s²): both positive (acceleration limits of a \
                 diff base) or both 0 (none)"
                    .into(),
            ));
        }
        if !(0.0 <= self.free_thresh
            && self.free_thresh < self.occupied_thresh
            && self.occupied_thresh <= 1.0)
        {
            return Err(ParamError(
                "expected 0 ≤ free_thresh < occupied_thresh ≤ 1".into(),
            ));
        }
        Ok(())
    }
}

/// What the command line asks for.
#[derive(Clone, Debug, PartialEq)]
pub enum Cli {
    /// Run with these parameters.
    Run(Box<Params>),
    /// Print the usage.
    Help,
}

/// The usage text.
pub const USAGE: &str = "\
usage: harmonav-ros2 [--ros-args [--params-file FILE]... [-p NAME:=VALUE]... [--log-level LEVEL]]

A ROS 2 node (pure Rust, DDS) that drives /cmd_vel from /map, /scan, /odom and /goal_pose (or
the navigate_to_pose action) with harmonav's navigation functions. Environment: ROS_DOMAIN_ID, ROS_AUTOMATIC_DISCOVERY_RANGE
(LOCALHOST, SUBNET, OFF) or ROS_LOCALHOST_ONLY=1; RUST_LOG-style level with --log-level.";

/// Parses the arguments (without the program's name); files are read with `read`.
///
/// # Errors
/// An unknown argument, a missing value, a file that cannot be read or parsed.
pub fn parse_args(
    args: &[String],
    read: &dyn Fn(&str) -> Result<String, String>,
) -> Result<(Cli, Option<String>), ParamError> {
    let mut params = Params::default();
    let mut level = None;
    let mut in_ros_args = false;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = |what: &str| {
            it.next()
                .cloned()
                .ok_or_else(|| ParamError(format!("{a} needs {what}")))
        };
        match a.as_str() {
            "-h" | "--help" => return Ok((Cli::Help, None)),
            "--ros-args" => in_ros_args = true,
            "--" => in_ros_args = false,
            "--params-file" if in_ros_args => {
                let path = value("a file")?;
                let text = read(&path).map_err(|e| ParamError(format!("{path}: {e}")))?;
                params
                    .apply_file(&text)
                    .map_err(|e| ParamError(format!("{path}: {e}")))?;
            }
            "-p" | "--param" if in_ros_args => {
                let kv = value("NAME:=VALUE")?;
                let (k, v) = kv
                    .split_once(":=")
                    .ok_or_else(|| ParamError(format!("{a} {kv}: expected NAME:=VALUE")))?;
                params.set(k, &Value::from_text(v))?;
            }
            "--log-level" if in_ros_args => level = Some(value("a level")?),
            other => {
                return Err(ParamError(format!(
                    "unknown argument {other:?}{}",
                    if in_ros_args {
                        ""
                    } else {
                        " (ROS arguments follow --ros-args)"
                    }
                )));
            }
        }
    }
    params.resolve()?;
    params.validate()?;
    Ok((Cli::Run(Box::new(params)), level))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(a: &[&str]) -> Vec<String> {
        a.iter().map(|s| (*s).to_owned()).collect()
    }

    const FILE: &str = "
/**:
  ros__parameters:
    global_frame: world
    controller_frequency: 10
    robot_radius: 0.2
    enable_stamped_cmd_vel: true
    base: holonomic
    law: dynamic
other_node:
  ros__parameters:
    robot_radius: 9.0
harmonav:
  ros__parameters:
    map_topic: ''
";

    #[test]
    fn file_in_ros_format() {
        let read = |p: &str| {
            if p == "a.yaml" {
                Ok(FILE.to_owned())
            } else {
                Err("no such file".to_owned())
            }
        };
        let (cli, level) = parse_args(
            &args(&[
                "--ros-args",
                "--params-file",
                "a.yaml",
                "-p",
                "margin:=0.3",
                "--log-level",
                "debug",
            ]),
            &read,
        )
        .unwrap();
        let Cli::Run(p) = cli else { panic!() };
        assert_eq!(p.global_frame, "world");
        assert_eq!(p.controller_frequency, 10.0);
        assert_eq!(p.robot_radius, 0.2);
        assert!(p.enable_stamped_cmd_vel);
        assert_eq!(p.law, LawKind::Dynamic);
        assert_eq!(p.map_topic, "");
        assert_eq!(p.margin, 0.3);
        assert_eq!(level.as_deref(), Some("debug"));
        assert!(
            parse_args(&args(&["--ros-args", "--params-file", "b.yaml"]), &read)
                .unwrap_err()
                .0
                .contains("no such file")
        );
    }

    #[test]
    fn nested_names_flatten_and_errors_name_the_parameter() {
        let mut p = Params::default();
        let e = p
            .apply_file("/**:\n  ros__parameters:\n    robot:\n      radius: 1\n")
            .unwrap_err();
        assert!(e.0.contains("robot.radius"), "{e}");
        let e = p
            .apply_file("/**:\n  ros__parameters:\n    robot_radius: -1\n")
            .unwrap_err();
        assert!(e.0.contains("robot_radius"), "{e}");
        let e = p
            .apply_file("/**:\n  ros__parameters:\n    base: tracked\n")
            .unwrap_err();
        assert!(e.0.contains("base"), "{e}");
        let e = p
            .apply_file("/**:\n  ros__parameters:\n    service_mapping: basic\n")
            .unwrap_err();
        assert!(e.0.contains("service_mapping"), "{e}");
        p.apply_file(
            "/**:\n  ros__parameters:\n    service_mapping: cyclone\n    action_name: ''\n",
        )
        .unwrap();
        assert_eq!(
            (p.service_mapping, p.action_name.as_str()),
            (ServiceWire::Cyclone, "")
        );
        let e = p
            .apply_file("/**:\n  ros__parameters:\n    enable_stamped_cmd_vel: 1\n")
            .unwrap_err();
        assert!(e.0.contains("enable_stamped_cmd_vel"), "{e}");
        assert!(p.apply_file("/**:\n  params: {}\n").is_err());
        assert!(p.apply_file("- a\n").is_err());
        assert!(p.apply_file("/**: [\n").is_err());
        // `.nan` is not a finite number.
        assert!(
            p.apply_file("/**:\n  ros__parameters:\n    goal_tolerance: .nan\n")
                .is_err()
        );
        // The progress check: 0 turns it off, a negative allowance is refused.
        p.apply_file("/**:\n  ros__parameters:\n    movement_time_allowance: 0\n")
            .unwrap();
        assert_eq!(p.movement_time_allowance, 0.0);
        let e = p
            .apply_file("/**:\n  ros__parameters:\n    movement_time_allowance: -1.0\n")
            .unwrap_err();
        assert!(e.0.contains("movement_time_allowance"), "{e}");
        let e = p
            .apply_file("/**:\n  ros__parameters:\n    required_movement_radius: 0\n")
            .unwrap_err();
        assert!(e.0.contains("required_movement_radius"), "{e}");
    }

    /// Nav2's goal checker's names: `xy_goal_tolerance`, given, is the position tolerance of
    /// every goal (in place of `goal_tolerance`, and for a goal with a yaw in place of 1 cm);
    /// `yaw_goal_tolerance` ends the turn; neither given, nothing changes; a bad value is
    /// refused by name.
    #[test]
    fn nav2_goal_tolerances() {
        let mut p = Params::default();
        assert_eq!(p.arrival_radius(), p.goal_tolerance);
        assert_eq!(p.goal_tolerance(), harmonav::GoalTolerance::default());
        p.apply_file(
            "/**:\n  ros__parameters:\n    xy_goal_tolerance: 0.25\n    yaw_goal_tolerance: 0.2\n",
        )
        .unwrap();
        assert_eq!(p.arrival_radius(), 0.25);
        assert_eq!(
            p.goal_tolerance(),
            harmonav::GoalTolerance { xy: 0.25, yaw: 0.2 }
        );
        for bad in [
            "xy_goal_tolerance: 0",
            "yaw_goal_tolerance: -0.1",
            "xy_goal_tolerance: .inf",
        ] {
            let mut q = p.clone();
            let e = q
                .apply_file(&format!("/**:\n  ros__parameters:\n    {bad}\n"))
                .unwrap_err();
            let name = bad.split(':').next().unwrap();
            assert!(e.0.contains(name), "{e}");
            assert_eq!(q.goal_tolerance(), p.goal_tolerance(), "{bad}");
        }
    }

    /// A parameter file's `/**` section with these lines of parameters, read and resolved as
    /// `parse_args` does.
    fn resolved(lines: &str) -> Result<Params, ParamError> {
        let mut p = Params::default();
        let body: String = lines.lines().map(|l| format!("    {l}\n")).collect();
        p.apply_file(&format!("/**:\n  ros__parameters:\n{body}"))?;
        p.resolve()?;
        Ok(p)
    }

    /// Nav2's goal checker keys under the plugin's name (`goal_checker_plugins`): read as the
    /// bare keys are; `stateful` defaults to true and switches the latch; `<name>.plugin` is
    /// accepted; without `goal_checker_plugins` any one name is read; the bare keys still work
    /// alone, and agreeing with the namespaced ones.
    #[test]
    fn nav2_namespaced_goal_checker() {
        let nav2 = "goal_checker_plugins: [\"general_goal_checker\"]
general_goal_checker:
  plugin: \"nav2_controller::SimpleGoalChecker\"
  xy_goal_tolerance: 0.25
  yaw_goal_tolerance: 0.05
  stateful: false";
        let p = resolved(nav2).unwrap();
        assert_eq!(
            p.goal_tolerance(),
            harmonav::GoalTolerance {
                xy: 0.25,
                yaw: 0.05
            }
        );
        assert_eq!(p.arrival_radius(), 0.25);
        assert!(!p.stateful);
        assert!(Params::default().stateful, "Nav2's default");
        // A StoppedGoalChecker's block loads; its other keys are accepted unread.
        let stopped = "goal_checker_plugins: [\"stopped\"]
stopped:
  plugin: \"nav2_controller::StoppedGoalChecker\"
  trans_stopped_velocity: 0.25
  rot_stopped_velocity: 0.25
  path_length_tolerance: 1
  symmetric_yaw_tolerance: false
  xy_goal_tolerance: 0.2";
        let p = resolved(stopped).unwrap();
        assert_eq!(p.xy_goal_tolerance, Some(0.2));
        // Without goal_checker_plugins: the one name given.
        let p = resolved("precise.xy_goal_tolerance: 0.05\nprecise.stateful: true").unwrap();
        assert_eq!(p.xy_goal_tolerance, Some(0.05));
        assert!(p.stateful);
        // Several plugins listed: the first one's keys are read, the others' accepted.
        let p = resolved(
            "goal_checker_plugins: [a, b]\na.xy_goal_tolerance: 0.3\nb.xy_goal_tolerance: 0.1",
        )
        .unwrap();
        assert_eq!(p.xy_goal_tolerance, Some(0.3));
        // Bare keys alone (today's contract), and both forms agreeing (1 and 1.0 too).
        let p = resolved("xy_goal_tolerance: 0.2\nstateful: false").unwrap();
        assert_eq!((p.xy_goal_tolerance, p.stateful), (Some(0.2), false));
        let p = resolved("yaw_goal_tolerance: 1\ng.yaw_goal_tolerance: 1.0").unwrap();
        assert_eq!(p.yaw_goal_tolerance, 1.0);
        // The command line's -p takes a namespaced key and a list, after the file.
        let read =
            |_: &str| Ok("/**:\n  ros__parameters:\n    c.xy_goal_tolerance: 0.4\n".to_owned());
        let (Cli::Run(p), _) = parse_args(
            &args(&[
                "--ros-args",
                "--params-file",
                "f.yaml",
                "-p",
                "goal_checker_plugins:=[c]",
                "-p",
                "c.stateful:=false",
            ]),
            &read,
        )
        .unwrap() else {
            panic!()
        };
        assert_eq!((p.xy_goal_tolerance, p.stateful), (Some(0.4), false));
    }

    /// What the namespaced keys refuse, naming the keys: different bare and namespaced values
    /// (both named), a bad value (the namespaced name), a name not in `goal_checker_plugins`,
    /// two names without it, an unknown key under a name, a bad `goal_checker_plugins`.
    #[test]
    fn nav2_namespaced_goal_checker_errors() {
        for (lines, names) in [
            (
                "xy_goal_tolerance: 0.3\ngc.xy_goal_tolerance: 0.25",
                &["xy_goal_tolerance (", "gc.xy_goal_tolerance"][..],
            ),
            (
                "gc.stateful: true\nstateful: false",
                &["stateful (", "gc.stateful"][..],
            ),
            (
                "gc.xy_goal_tolerance: 0",
                &["gc.xy_goal_tolerance", "> 0"][..],
            ),
            (
                "gc.yaw_goal_tolerance: .nan",
                &["gc.yaw_goal_tolerance"][..],
            ),
            ("gc.stateful: 1", &["gc.stateful", "true or false"][..]),
            (
                "goal_checker_plugins: [gc]\nother.xy_goal_tolerance: 0.2",
                &["other.xy_goal_tolerance", "goal_checker_plugins"][..],
            ),
            (
                "a.xy_goal_tolerance: 0.2\nb.yaw_goal_tolerance: 0.2",
                &["a.xy_goal_tolerance", "b.yaw_goal_tolerance"][..],
            ),
            (
                "gc.trans_stopped_velocity: -0.2",
                &["gc.trans_stopped_velocity", "≥ 0"][..],
            ),
            (
                "gc.symmetric_yaw_tolerance: true",
                &["gc.symmetric_yaw_tolerance", "not supported"][..],
            ),
            (
                "gc.xy_goal_tolerance_typo: 0.2",
                &["unknown parameter gc.xy_goal_tolerance_typo"][..],
            ),
            ("gc.plugin: 3", &["gc.plugin"][..]),
            ("goal_checker_plugins: []", &["goal_checker_plugins"][..]),
            ("goal_checker_plugins: gc", &["goal_checker_plugins"][..]),
        ] {
            let e = resolved(lines).unwrap_err();
            for name in names {
                assert!(e.0.contains(name), "{lines}: {e}");
            }
        }
    }

    #[test]
    fn arguments() {
        let none = |_: &str| Err("unused".to_owned());
        assert_eq!(parse_args(&args(&["--help"]), &none).unwrap().0, Cli::Help);
        assert!(parse_args(&args(&["--params-file", "x"]), &none).is_err());
        assert!(parse_args(&args(&["--ros-args", "-p", "margin=1"]), &none).is_err());
        assert!(parse_args(&args(&["--ros-args", "--params-file"]), &none).is_err());
        assert!(parse_args(&args(&["--ros-args", "-p", "free_thresh:=0.9"]), &none).is_err());
        let (Cli::Run(p), _) =
            parse_args(&args(&["--ros-args", "-p", "base:=diff"]), &none).unwrap()
        else {
            panic!()
        };
        assert_eq!(p.base, Base::Diff);
        assert!(
            p.use_goal_orientation,
            "a diff base reads the goal's yaw by default"
        );
        let (Cli::Run(p), _) = parse_args(
            &args(&[
                "--ros-args",
                "-p",
                "base:=diff",
                "-p",
                "use_goal_orientation:=false",
            ]),
            &none,
        )
        .unwrap() else {
            panic!()
        };
        assert!(!p.use_goal_orientation);
        assert!(
            parse_args(
                &args(&["--ros-args", "-p", "use_goal_orientation:=1"]),
                &none
            )
            .is_err()
        );
        // Acceleration limits: both or neither.
        for (given, ok) in [
            (&["a_max:=0.5", "alpha_max:=3.0"][..], true),
            (&["a_max:=0.5"][..], false),
            (&["alpha_max:=3.0"][..], false),
            (&["a_max:=-0.5", "alpha_max:=3.0"][..], false),
        ] {
            let mut all = vec!["--ros-args"];
            for g in given {
                all.extend(["-p", g]);
            }
            assert_eq!(parse_args(&args(&all), &none).is_ok(), ok, "{given:?}");
        }
    }
}
