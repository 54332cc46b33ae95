//! Floor-plan scenarios (`[floor_plan]`, issue 25): a polygon with polygonal holes as the known
//! walls and star obstacles sensed online inside it: the format and its validation (the loop
//! around a [`harmonav::FloorNavigator`] is `harmonav_sim::floor`).
//!
//! ```toml
//! name = "u-trap"
//! [floor_plan]
//! outer = [[0, 0], [8, 0], [8, 5], [0, 5]]      # either orientation
//! holes = [[[3, 1], [5, 1], [5, 4], …]]          # any shape (U, L, …)
//! max_element = 0.2                              # boundary element h (m)
//! centre = "solve"                               # or "goal" (the goal at the disk centre)
//! require_certified_start = false                # true: only starts with Θ(x₀) < c_δ
//! funnels = false                                # true: follow a chain of certified funnels (kinematic)
//! [robot]
//! model = "kinematic"                            # or "dynamic" (mass, mu)
//! start = [1, 2.5]
//! goal = [4, 2.5]
//! radius = 0.1
//! margin = 0.1
//! heading = "auto"                              # or "paper" (kinematic: along −∇Θ)
//! v_max = 0.22                                   # the kinematic law's top speed (default K√2)
//! control_period = 0.01                          # s, the hold's and the loop's step (default: the law's)
//! [field]
//! k = "auto"                                     # or "paper" (k = n + 1), a star world's key
//! [controller]
//! damping = "governed"                           # a star world's damping and speed policies
//! speed = "auto"
//! [starts]                                       # seeded starts in W_δ, besides `start`
//! count = 6
//! seed = 1
//! [[obstacles]]                                  # sensed online (scenario shapes)
//! type = "circle"
//! center = [6.5, 1.2]
//! radius = 0.3
//! [sensor]                                       # optional: the obstacles from scans
//! type = "lidar"                                 # a star world's lidar fields
//! range = 4.0
//! ```
//!
//! The `floorplans/` folder is not a suite of [`crate::scenario::Scenario`] files
//! ([`crate::suites::scenario_files`] skips it): `cargo xtask verify` runs it through
//! `harmonav_sim::floor::run`.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use harmonav::{CentrePolicy, FloorMap, FloorOptions, HeadingPolicy, StarShape};
use harmonav_floorplan::{
    FloorError, FloorField, FunnelOptions, Funnels, LayerLevel, LevelOptions, MapOptions, MapPoint,
    MapProblem, OccupiedPixels, RosMap, Specks,
};
use harmonav_harmonic::{DomainError, MeshError, RingId, SolveError};
use harmonav_transform::Shown;
use harmonav_transform::random::Rng;
use nalgebra::Vector2;
use serde::Deserialize;

pub use crate::kind::FileKind;
use crate::scenario::{BaseKind, Model, ScenarioError, ShapeSpec, build_shape, err};
use crate::sensor::{self, LidarSensor, SensorKind, SensorSpec, WallRoom};

/// The folder of floor-plan scenarios under `scenarios/`.
pub const FLOORPLANS: &str = "floorplans";

/// Most seeded starts of one file.
pub const MAX_STARTS: usize = 64;

/// `[floor_plan]`: the walls as rings (`outer`, `holes`), or a ROS map_server map (`map`).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FloorPlanSpec {
    /// The outer ring (either orientation; no repeated closing vertex needed); empty with
    /// `map`.
    #[serde(default, deserialize_with = "crate::points::ring")]
    pub outer: Vec<[f64; 2]>,
    /// The holes, each a ring.
    #[serde(default, deserialize_with = "crate::points::rings")]
    pub holes: Vec<Vec<[f64; 2]>>,
    /// A ROS map_server map (its YAML file, relative to the scenario file) instead of rings:
    /// the free component of the goal, outlined, simplified and opened by the robot's disc
    /// (`harmonav_floorplan::RosMap`, docs/maths.md §13.1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub map: Option<PathBuf>,
    /// With `map`: occupied islands of at most this many pixels are dropped (default 2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speck_pixels: Option<usize>,
    /// With `map`: the simplification tolerance in square pixels (default 0.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub simplify: Option<f64>,
    /// The longest boundary element `h`, m.
    #[serde(default = "default_element")]
    pub max_element: f64,
    /// Where the goal's image lies in the disk: `"solve"` (the default) or `"goal"` (recentred
    /// by a disk automorphism; [`harmonav::CentrePolicy`]).
    #[serde(default, deserialize_with = "crate::scenario::de_policy")]
    pub centre: CentrePolicy,
    /// Run only starts below `c_δ`, the certified least `Θ` on `∂W_δ` over the walls
    /// (docs/maths.md §13.5): from there the continuous law's sublevel set stays inside `W_δ`,
    /// so its convergence is certified wherever `H`'s own certificate holds on that set.
    /// `robot.start` above it is refused with both values, and the seeded starts are drawn
    /// below it. The default `false` runs every start of `W_δ`: the hold keeps it in `W_δ` and
    /// clear of every obstacle at every step, but that is all that is certified above `c_δ`.
    #[serde(default)]
    pub require_certified_start: bool,
    /// Build a chain of certified funnels towards intermediate goals at load
    /// ([`harmonav_floorplan::FloorField::funnels`], docs/maths.md §13.10) and have the
    /// navigator follow it ([`harmonav::FloorNavigator::set_funnels`]): convergence is then
    /// certified from their union. The kinematic law only; seconds to minutes of set-up (each
    /// funnel certifies its own `c_δ` and `c_s`). Default `false`.
    #[serde(default)]
    pub funnels: bool,
}

fn default_element() -> f64 {
    0.2
}

/// `[robot]` of a floor-plan scenario.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FloorRobotSpec {
    /// `kinematic` or `dynamic`.
    pub model: Model,
    /// Start position.
    #[serde(deserialize_with = "crate::points::point")]
    pub start: [f64; 2],
    /// Goal position.
    #[serde(deserialize_with = "crate::points::point")]
    pub goal: [f64; 2],
    /// Disc radius, m.
    #[serde(default)]
    pub radius: f64,
    /// Clearance margin, m.
    #[serde(default)]
    pub margin: f64,
    /// Kinematic gain `K`.
    #[serde(default = "one")]
    pub gain: f64,
    /// Mass (dynamic), kg.
    #[serde(default = "one")]
    pub mass: f64,
    /// `μ` (dynamic): the speed bound is `√(2μ/m)`. Default
    /// [`crate::scenario::DEFAULT_MU`], as a star world's `controller.mu`.
    #[serde(default = "crate::scenario::default_mu")]
    pub mu: f64,
    /// `heading = "auto"` (the default: the shortest path's direction within 60° of `−∇Θ`; the
    /// dynamic law turns its velocity towards it by a force that does no work) or `"paper"`
    /// (`−∇Θ`, eqs. `kinctrl` and `dynctrllocal`), both laws' [`HeadingPolicy`].
    #[serde(default, deserialize_with = "crate::scenario::de_policy")]
    pub heading: HeadingPolicy,
    /// `v_max`, m/s: the kinematic law's top speed (default `K√2`, the paper law's; a
    /// TurtleBot3 drives at 0.22 m/s), as a star world's `controller.v_max` (issue 52).
    #[serde(default)]
    pub v_max: Option<f64>,
    /// The control period `h`, s: the period the navigator's hold certifies
    /// ([`harmonav::Options::with_control_period`]) and the fixed step of the held-command loop
    /// (`harmonav_sim::floor`). Default: the law's (0.01 s kinematic, 0.001 s dynamic). The
    /// same key as a star world's `[robot] control_period`.
    #[serde(default)]
    pub control_period: Option<f64>,
    /// `"holonomic"` (the default) or `"diff"`: a differential drive commanded `(v, ω)` by
    /// [`harmonav::Navigator::command_pose`], its top speed `v_max` (required with it), as a
    /// star world's `[robot] base` (issue 53; docs/unicycle.md, "Simulator").
    #[serde(default, deserialize_with = "crate::scenario::de_policy")]
    pub base: BaseKind,
    /// A differential drive's top turn rate `ω_max`, rad/s (required with `base = "diff"`).
    #[serde(default)]
    pub omega_max: Option<f64>,
    /// A differential drive's heading `θ(0)` at the start, rad (default 0).
    #[serde(default)]
    pub yaw: Option<f64>,
    /// A differential drive's acceleration limits, `a_max` m/s² and `alpha_max` rad/s² (both
    /// or neither; [`harmonav::Accel`]), as a star world's `[robot]` keys.
    #[serde(default)]
    pub a_max: Option<f64>,
    /// See `a_max`.
    #[serde(default)]
    pub alpha_max: Option<f64>,
    /// The dynamic law's force bound `F`, N ([`harmonav::Options::with_force_bound`], the
    /// braking certificate), as a star world's `[robot] force_bound` (a kinematic run of the
    /// file has no force to bound).
    #[serde(default)]
    pub force_bound: Option<f64>,
    /// The distance the nominal command keeps beyond the margin from the non-cooperative
    /// movers where it can, m (default 0; [`harmonav::Options::comfort`]), as a star world's
    /// `[robot] comfort`.
    #[serde(default)]
    pub comfort: f64,
}

impl FloorRobotSpec {
    /// The base's keys it carries.
    pub(crate) fn base_keys(&self) -> crate::scenario::BaseKeys {
        crate::scenario::BaseKeys {
            base: self.base,
            omega_max: self.omega_max,
            yaw: self.yaw,
            v_max: self.v_max,
            a_max: self.a_max,
            alpha_max: self.alpha_max,
        }
    }
}

fn one() -> f64 {
    1.0
}

/// `[starts]`: seeded random starts in `W_δ`, run besides `robot.start`.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StartsSpec {
    /// How many (at most [`MAX_STARTS`]).
    pub count: usize,
    /// The seed.
    #[serde(default)]
    pub seed: u64,
}

/// `[sim]` of a floor-plan scenario.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FloorSimSpec {
    /// Simulated time limit, s.
    #[serde(default = "default_max_time")]
    pub max_time: f64,
    /// Arrival threshold `|x − x_d|`, m (default [`crate::scenario::DEFAULT_ARRIVAL`], as a
    /// star world's); also spelt `goal_tolerance`, a star world's name for it.
    #[serde(
        default = "crate::scenario::default_tolerance",
        alias = "goal_tolerance"
    )]
    pub arrival: f64,
    /// Sensor range: a true obstacle becomes known once it is this close, m.
    #[serde(default = "one")]
    pub sensor_range: f64,
}

fn default_max_time() -> f64 {
    120.0
}

impl Default for FloorSimSpec {
    fn default() -> Self {
        Self {
            max_time: default_max_time(),
            arrival: crate::scenario::DEFAULT_ARRIVAL,
            sensor_range: 1.0,
        }
    }
}

/// A floor-plan scenario file.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FloorScenario {
    /// Name.
    pub name: String,
    /// Description.
    #[serde(default)]
    pub description: String,
    /// The walls.
    pub floor_plan: FloorPlanSpec,
    /// The robot.
    pub robot: FloorRobotSpec,
    /// Seeded starts.
    #[serde(default)]
    pub starts: Option<StartsSpec>,
    /// The loop.
    #[serde(default)]
    pub sim: FloorSimSpec,
    /// `[sensor] type = "lidar"`: the robot perceives the obstacles through a simulated lidar
    /// cast against the true walls and obstacles, its scans its only perception
    /// ([`harmonav::FloorNavigator::observe_scan`], docs/maths.md §12.17); `sim.sensor_range`
    /// is then unused. Without it, an obstacle becomes known (its exact shape) within
    /// `sim.sensor_range`. The lidar's fields and defaults are a star world's
    /// ([`crate::SensorSpec`]), the wall prior's default taken from the true walls.
    #[serde(default)]
    pub sensor: Option<SensorSpec>,
    /// Obstacles inside the plan, unknown until sensed.
    #[serde(default)]
    pub obstacles: Vec<ShapeSpec>,
    /// People and other robots on scripted trajectories, as in a star world
    /// ([`crate::MoverSpec`], `docs/movers.md` §8).
    #[serde(default)]
    pub movers: Vec<crate::MoverSpec>,
    /// More harmonav robots, each like `[robot]` with its own start and goal, each running its
    /// own floor navigator on the same map with the others as reciprocal movers: a star
    /// world's `[[robots]]`, the same keys and checks ([`crate::FleetRobotSpec`],
    /// `docs/movers.md` §8).
    #[serde(default)]
    pub robots: Vec<crate::FleetRobotSpec>,
    /// `[field] k`: the `k` policy, a star world's table and key ([`crate::FieldSpec`]).
    #[serde(default)]
    pub field: crate::FieldSpec,
    /// `[controller] damping` and `speed`: the laws' policies, a star world's keys.
    #[serde(default)]
    pub controller: FloorControllerSpec,
}

/// `[controller]` of a floor-plan scenario: the policies of the laws, under a star world's keys
/// and names (`crate::ControllerSpec`'s `damping` and `speed`). A floor plan's gain, `μ` and
/// `v_max` are `[robot]` keys, so this table refuses them by name.
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FloorControllerSpec {
    /// `damping = "paper"` (eq. `dissipationfun`), `"shaped"`, `"auto"`, `"fast"` or
    /// `"governed"` (the default), see [`harmonav::DampingPolicy`].
    #[serde(default, deserialize_with = "crate::scenario::de_policy")]
    pub damping: harmonav::DampingPolicy,
    /// `speed = "paper"` (eq. `kinctrl`, `K√(2Θ)`) or `"auto"` (the default), see
    /// [`harmonav::SpeedPolicy`].
    #[serde(default, deserialize_with = "crate::scenario::de_policy")]
    pub speed: harmonav::SpeedPolicy,
}

/// A loaded and validated floor-plan scenario: the solved map and the true obstacles.
#[derive(Clone, Debug)]
pub struct FloorPrepared {
    /// The file.
    pub path: PathBuf,
    /// What the file says.
    pub scenario: FloorScenario,
    /// The walls and `H`, solved once (with `δ ≥ radius + margin`).
    pub floor: Arc<FloorMap>,
    /// The true obstacles (the robot senses them online).
    pub obstacles: Vec<StarShape>,
    /// `robot.start`, then the seeded starts.
    pub starts: Vec<Vector2<f64>>,
    /// Seconds spent meshing and solving `H`.
    pub setup_seconds: f64,
    /// `c_δ` over the walls, when `floor_plan.require_certified_start` asked for it.
    pub level: Option<LayerLevel>,
    /// The chain of certified funnels, when `floor_plan.funnels` asked for it.
    pub funnels: Option<Arc<Funnels>>,
    /// The lidar of `[sensor]`, if any, and the curvature prior `ρ_min` of its fits.
    pub lidar: Option<(LidarSensor, f64)>,
    /// With `floor_plan.map`: the map's own non-free pixels, against which a run's collision
    /// monitors judge (besides the floor plan's walls), whatever the pipeline dropped or moved.
    pub pixels: Option<Arc<OccupiedPixels>>,
    /// With `floor_plan.map`: the occupied islands dropped as specks.
    pub specks: Option<Specks>,
}

/// Where a point may be (a start or the goal): in `W_δ` of `floor` and clear of every true
/// obstacle grown by `inflation` (radius + margin); else what is wrong.
fn placed(
    floor: &FloorMap,
    obstacles: &[StarShape],
    inflation: f64,
    p: Vector2<f64>,
) -> Result<(), String> {
    let at = format!("({}, {})", Shown(p.x), Shown(p.y));
    if !p.iter().all(|c| c.is_finite()) {
        return Err(format!("NaN or infinite coordinate in {at}"));
    }
    let (sd, delta) = (floor.signed_distance(p), floor.delta());
    if sd < delta {
        // `sd` is measured from the walls shrunk by `s`, not the true ones; `+ 0.0` prints a
        // negative zero as 0 (issue 56, D18).
        return Err(format!(
            "{at} is {:.4} m inside the walls shrunk by s = {:.4} m (radius + margin − δ, at \
             least 0), less than δ = {:.4} m: not in the certified region{}",
            Shown(sd),
            Shown(floor.shrink()),
            Shown(delta),
            if sd <= 0.0 {
                "; it is outside the shrunk walls (in a wall, outside, or within s of a wall)"
            } else {
                ""
            }
        ));
    }
    for (i, o) in obstacles.iter().enumerate() {
        if o.signed_distance(p) <= inflation {
            return Err(format!("{at} is within radius + margin of obstacles[{i}]"));
        }
    }
    Ok(())
}

/// Whether `p` lies below the certified level `max(c_δ, c_s)`
/// (`floor_plan.require_certified_start`, docs/maths.md §13.5 and §13.9), so that its convergence
/// is certified; else why not.
fn below_level(field: &FloorField, level: &LayerLevel, p: Vector2<f64>) -> Result<(), String> {
    match field.eval(p) {
        Ok(e) if level.holds(e.phi) => Ok(()),
        Ok(e) => Err(format!(
            "{p:?} has Θ = {:.6} (phi_k {:.4}), not below c_δ = {:.6} (phi_k {:.4}), the \
             certified least Θ on the edge of the certified region, nor below c_s = {:.6} \
             (phi_k {:.4}), the least Θ where the slide along that edge may rest: its \
             convergence is not certified (floor_plan.require_certified_start = true; without \
             it the hold still keeps every step clear)",
            e.value,
            e.phi,
            level.certified(),
            level.phi_certified,
            level.slide(),
            level.phi_slide
        )),
        Err(e) => Err(format!("{p:?}: Θ cannot be evaluated: {e}")),
    }
}

impl FloorPrepared {
    /// The file's `[robot] control_period`, s (`None`: the law's default).
    #[must_use]
    pub fn control_period(&self) -> Option<f64> {
        self.scenario.robot.control_period
    }

    /// `Base::Diff { v_max, omega_max }` for `[robot] base = "diff"`, `None` for a holonomic
    /// robot (as a star world's [`crate::Prepared::base`]).
    #[must_use]
    pub fn base(&self) -> Option<harmonav::Base> {
        self.scenario.robot.base_keys().base()
    }

    /// A differential drive's start heading `θ(0)`, rad (`[robot] yaw`, default 0).
    #[must_use]
    pub fn start_yaw(&self) -> f64 {
        self.scenario.robot.yaw.unwrap_or(0.0)
    }

    /// Whether `start` may start a run, as `robot.start` must: in the certified region `W_δ`,
    /// clear of every true obstacle grown by radius + margin, and, with
    /// `floor_plan.require_certified_start`, below `c_δ`; else the problem.
    ///
    /// # Errors
    /// What is wrong with `start`, in words.
    pub fn check_start(&self, start: Vector2<f64>) -> Result<(), String> {
        let r = &self.scenario.robot;
        placed(&self.floor, &self.obstacles, r.radius + r.margin, start)?;
        match &self.level {
            None => Ok(()),
            Some(level) => {
                let field = FloorField::new(self.floor.clone(), v(r.goal), self.scenario.field.k)
                    .map_err(|e| format!("Θ cannot be built: {e}"))?;
                below_level(&field, level, start)
            }
        }
    }

    /// `count` seeded starts drawn as the file's `[starts]` are (the same rule, with `seed`):
    /// in `W_δ`, clear of the true obstacles grown by radius + margin, more than 1 m from the
    /// goal, able to reach it within `W_δ`, and below `c_δ` with
    /// `floor_plan.require_certified_start`. What a study draws its starts from
    /// (`harmonav.experiment`), without solving the map again.
    ///
    /// # Errors
    /// No such start found in `10⁴·(count + 1)` tries, or `Θ` could not be built for the
    /// level's test; in words.
    pub fn random_starts(&self, count: usize, seed: u64) -> Result<Vec<Vector2<f64>>, String> {
        let r = &self.scenario.robot;
        let goal = v(r.goal);
        let reach = self.floor.reach(goal);
        let certified = match &self.level {
            None => None,
            Some(level) => Some((
                FloorField::new(self.floor.clone(), goal, self.scenario.field.k)
                    .map_err(|e| format!("Θ cannot be built: {e}"))?,
                level,
            )),
        };
        let inflation = r.radius + r.margin;
        draw_starts(&self.floor, goal, count, seed, |p| {
            placed(&self.floor, &self.obstacles, inflation, p).is_ok()
                && reach.contains(p)
                && certified
                    .as_ref()
                    .is_none_or(|(field, level)| below_level(field, level, p).is_ok())
        })
        .ok_or_else(|| format!("no free start found in 10⁴·{} tries", count + 1))
    }

    /// `c_δ` and `c_s` over the walls (the level `floor_plan.require_certified_start`
    /// computed, or certified now with [`LevelOptions::default`]; docs/maths.md §13.5 and
    /// §13.9) and, for each of [`FloorPrepared::starts`], whether `Θ(x₀) < max(c_δ, c_s)`: its
    /// convergence is certified ([`LayerLevel::holds`]).
    ///
    /// # Errors
    /// As [`FloorField::new`] (the file's goal was checked on loading, so not expected).
    pub fn start_certificates(&self) -> Result<(LayerLevel, Vec<bool>), FloorError> {
        let goal = v(self.scenario.robot.goal);
        let field = FloorField::new(self.floor.clone(), goal, self.scenario.field.k)?;
        let level = self
            .level
            .unwrap_or_else(|| field.certify_level(&LevelOptions::default()));
        let below = self
            .starts
            .iter()
            .map(|&x| field.eval(x).is_ok_and(|e| level.holds(e.phi)))
            .collect();
        Ok((level, below))
    }
}

fn v(p: [f64; 2]) -> Vector2<f64> {
    Vector2::new(p[0], p[1])
}

/// `count` seeded starts of `floor`: points drawn uniformly in its bounding box from the seed,
/// kept when more than 1 m from `goal`, more than `1.1·δ` from the walls shrunk by the robot
/// (away from the layer by a little) and `accepted`; `None` after `10⁴·(count + 1)` tries.
/// The one rule of a file's `[starts]` and of [`FloorPrepared::random_starts`].
fn draw_starts(
    floor: &FloorMap,
    goal: Vector2<f64>,
    count: usize,
    seed: u64,
    accepted: impl Fn(Vector2<f64>) -> bool,
) -> Option<Vec<Vector2<f64>>> {
    let (lo, hi) = floor.domain().bounding_box();
    let delta = floor.delta();
    let mut rng = Rng::new(seed);
    let mut starts = Vec::with_capacity(count);
    let mut tries = 0;
    while starts.len() < count {
        tries += 1;
        if tries > 10_000 * (count + 1) {
            return None;
        }
        let p = Vector2::new(rng.uniform(lo.x, hi.x), rng.uniform(lo.y, hi.y));
        if (p - goal).norm() > 1.0 && floor.signed_distance(p) > 1.1 * delta && accepted(p) {
            starts.push(p);
        }
    }
    Some(starts)
}

/// The scenario field a domain error is about.
fn ring_field(e: &DomainError) -> String {
    let ring = match e {
        DomainError::TooFewVertices { ring, .. }
        | DomainError::NonFinite { ring, .. }
        | DomainError::TooLarge { ring, .. }
        | DomainError::DegenerateEdge { ring, .. }
        | DomainError::SelfIntersecting { ring, .. }
        | DomainError::WrongOrientation { ring, .. } => Some(*ring),
        // The later of the two rings (the one whose placement made them meet).
        DomainError::RingsMeet { second, .. } => Some(*second),
        DomainError::HoleOutside { hole } | DomainError::HoleInHole { inner: hole, .. } => {
            Some(RingId::Hole(*hole))
        }
        _ => None,
    };
    match ring {
        Some(RingId::Outer) => "floor_plan.outer".into(),
        Some(RingId::Hole(i)) => format!("floor_plan.holes[{i}]"),
        None => "floor_plan".into(),
    }
}

impl FloorScenario {
    /// Reads, parses and validates a floor-plan scenario (at most [`crate::MAX_FILE_BYTES`]).
    ///
    /// # Errors
    /// A [`ScenarioError`] naming the file, the field (`floor_plan.holes[1]`, `robot.start`,
    /// `obstacles[0]`, …), the line where the parser gives it, and the problem.
    pub fn load(path: &Path) -> Result<FloorPrepared, ScenarioError> {
        let text = crate::scenario::read_text(path)?;
        Self::parse(path, &text)?.prepare(path)
    }

    /// Parses TOML text; unknown keys are errors, with the line.
    ///
    /// # Errors
    /// A [`ScenarioError`] with the line of the problem.
    pub fn parse(path: &Path, text: &str) -> Result<Self, ScenarioError> {
        // A star world given where a floor plan is expected (issue 56, D11 and D19.13): said
        // so, not "unknown field `controller`".
        if FileKind::of_text(text) == FileKind::Star {
            if crate::scenario::is_map_yaml(text) {
                return Err(crate::scenario::map_yaml_error(path));
            }
            return Err(err(
                path,
                "floor_plan",
                None,
                "not a floor plan: the file has no [floor_plan] table (a star-world file? \
                 `harmonav run` takes either; in Python, Scenario.load)"
                    .into(),
            ));
        }
        toml::from_str::<Self>(text).map_err(|e| crate::scenario::toml_error(path, text, &e))
    }

    /// Validates the scenario and solves the map.
    ///
    /// # Errors
    /// A [`ScenarioError`] naming the field: bad rings, element size, robot parameters, a
    /// start or goal not in the certified region `W_δ` or inside an obstacle, a bad obstacle.
    pub fn prepare(self, path: &Path) -> Result<FloorPrepared, ScenarioError> {
        let f = |field: &str, problem: String| err(path, field, None, problem);
        let r = &self.robot;
        for (name, value) in [
            ("robot.radius", r.radius),
            ("robot.margin", r.margin),
            ("robot.comfort", r.comfort),
        ] {
            crate::scenario::length(value).map_err(|p| f(name, p))?;
        }
        // Both laws' parameters, whichever the file names: a run may take the other
        // (`--model`), and the navigator would refuse them there without the file's names.
        for (name, value) in [
            ("robot.gain", r.gain),
            ("robot.mass", r.mass),
            ("robot.mu", r.mu),
        ] {
            crate::scenario::parameter(value).map_err(|p| f(name, p))?;
        }
        if let Some(v) = r.v_max {
            crate::scenario::parameter(v).map_err(|p| f("robot.v_max", p))?;
        }
        r.base_keys()
            .check("robot.v_max", r.model)
            .map_err(|(key, p)| f(key, p))?;
        if let Some(h) = r.control_period {
            crate::scenario::control_period(h, self.sim.max_time)
                .map_err(|p| f("robot.control_period", p))?;
        }
        if let Some(force) = r.force_bound {
            crate::scenario::parameter(force).map_err(|p| f("robot.force_bound", p))?;
        }
        let h = self.floor_plan.max_element;
        if !(h.is_finite() && h > 0.0 && h <= harmonav_transform::MAX_LENGTH) {
            return Err(f(
                "floor_plan.max_element",
                format!(
                    "must be finite and in (0, {:e}] m, got {h:e}",
                    harmonav_transform::MAX_LENGTH
                ),
            ));
        }
        for (name, p) in [("robot.start", r.start), ("robot.goal", r.goal)] {
            if !p.iter().all(|c| c.is_finite()) {
                return Err(f(name, format!("NaN or infinite coordinate in {p:?}")));
            }
        }
        if self.movers.len() > crate::movers::MAX_MOVERS {
            return Err(f(
                "movers",
                format!(
                    "{} movers; at most {} are supported",
                    self.movers.len(),
                    crate::movers::MAX_MOVERS
                ),
            ));
        }
        crate::movers::check_all(&self.movers, r.start, r.radius)
            .map_err(|(field, p)| f(&field, p))?;
        if !self.robots.is_empty() {
            // Both ask one goal's questions of the one robot; a fleet flies from its starts.
            if self.starts.is_some() {
                return Err(f(
                    "starts",
                    "seeded starts run one robot; a file with [[robots]] flies each robot from \
                     its own start"
                        .into(),
                ));
            }
            if self.floor_plan.require_certified_start {
                return Err(f(
                    "floor_plan.require_certified_start",
                    "certifies the starts of robot.goal only, not built for [[robots]]".into(),
                ));
            }
        }
        if self.floor_plan.funnels {
            if r.model != Model::Kinematic {
                return Err(f(
                    "floor_plan.funnels",
                    "the funnels are sublevel sets of Θ and certify the kinematic law; \
                     robot.model is \"dynamic\""
                        .into(),
                ));
            }
            if !self.robots.is_empty() {
                return Err(f(
                    "floor_plan.funnels",
                    "a chain of funnels leads to robot.goal only, not built for [[robots]]".into(),
                ));
            }
        }
        let s = &self.sim;
        for (name, value) in [
            ("sim.max_time", s.max_time),
            ("sim.arrival", s.arrival),
            ("sim.sensor_range", s.sensor_range),
        ] {
            if !(value.is_finite() && value > 0.0 && value <= 1e6) {
                return Err(f(
                    name,
                    format!("must be finite and in (0, 1e6], got {value:e}"),
                ));
            }
        }
        let mut obstacles: Vec<StarShape> = Vec::with_capacity(self.obstacles.len());
        let inflation = r.radius + r.margin;
        for (j, o) in self.obstacles.iter().enumerate() {
            let shape =
                build_shape(o).map_err(|(sub, p)| f(&format!("obstacles[{j}].{sub}"), p))?;
            // The navigator grows each sensed obstacle by radius + margin (and by radius alone
            // for the body): a shape that cannot be grown is refused here, naming it, not when
            // the robot first senses it (issue 56, D8).
            for (grow, by) in [
                (inflation, "robot.radius + robot.margin"),
                (r.radius, "robot.radius"),
            ] {
                if let Err(e) = shape.offset(grow) {
                    return Err(f(
                        &format!("obstacles[{j}]"),
                        format!("grown by {by} = {} m: {}", Shown(grow), e.problem()),
                    ));
                }
            }
            // The navigator grows each sensed obstacle by radius + margin, and the grown
            // shapes must be disjoint: `dist(A ⊕ B_r, B ⊕ B_r) = dist(A, B) − 2r`.
            for (i, other) in obstacles.iter().enumerate() {
                let gap = other.distance_to(&shape);
                let problem = if gap <= 0.0 {
                    format!("overlaps or touches obstacles[{i}]")
                } else if gap <= 2.0 * inflation {
                    format!(
                        "{gap:e} m from obstacles[{i}]: grown by robot.radius + robot.margin = \
                         {inflation:e} m they overlap or touch (the gap must exceed twice that)"
                    )
                } else {
                    continue;
                };
                return Err(f(&format!("obstacles[{j}]"), problem));
            }
            obstacles.push(shape);
        }
        // Unnamed sensed obstacles are shown as `obstacles[i]`, which no name can repeat.
        crate::scenario::obstacle_names(&self.obstacles, |i| format!("obstacles[{i}]"))
            .map_err(|(field, p)| f(&field, p))?;
        let plan = &self.floor_plan;
        let clock = std::time::Instant::now();
        let options = FloorOptions::new(h, r.radius + r.margin).with_centre(plan.centre);
        let floor_error = |e: FloorError| match &e {
            FloorError::Domain(d) => f(&ring_field(d), d.to_string()),
            FloorError::Solve(SolveError::Mesh(m)) => f("floor_plan.max_element", m.to_string()),
            _ => f("floor_plan", e.to_string()),
        };
        let (mut pixels, mut specks) = (None, None);
        let floor = match &plan.map {
            Some(_) if !(plan.outer.is_empty() && plan.holes.is_empty()) => {
                return Err(f(
                    "floor_plan.map",
                    "give the walls either as a map or as rings (outer, holes), not both".into(),
                ));
            }
            Some(map) => {
                let mut map_options = MapOptions::new(options);
                if let Some(n) = plan.speck_pixels {
                    map_options.speck_pixels = n;
                }
                if let Some(t) = plan.simplify {
                    if !(t.is_finite() && t >= 0.0) {
                        return Err(f(
                            "floor_plan.simplify",
                            format!("must be finite and ≥ 0 (square pixels), got {t:e}"),
                        ));
                    }
                    map_options.simplify = t;
                }
                // Relative to the scenario file, as `image` is to the YAML file in map_server.
                let yaml = path.parent().unwrap_or(Path::new("")).join(map);
                let ros = RosMap::load(&yaml);
                let built = ros
                    .as_ref()
                    .map_err(Clone::clone)
                    .and_then(|m| m.to_floor_map(v(r.start), v(r.goal), &map_options));
                if let (Ok(m), Ok(_)) = (&ros, &built) {
                    specks = Some(m.specks(map_options.speck_pixels));
                    pixels = Some(Arc::new(m.occupied_pixels()));
                }
                built.map_err(|e| {
                    match &e.problem {
                        // Every vertex of a map's outline ends an element: a lowered
                        // `simplify` is what made the mesh too large.
                        MapProblem::Floor(FloorError::Solve(SolveError::Mesh(
                            MeshError::TooManyElements { elements, max },
                        ))) if map_options.simplify
                            < harmonav_floorplan::ros_map::DEFAULT_SIMPLIFY =>
                        {
                            f(
                                "floor_plan.simplify",
                                format!(
                                    "the mesh would have {elements} boundary elements, more \
                                     than the {max} allowed, and every vertex of the map's \
                                     outline ends one: simplify = {:e} square pixels keeps too \
                                     many (the default is {})",
                                    map_options.simplify,
                                    harmonav_floorplan::ros_map::DEFAULT_SIMPLIFY
                                ),
                            )
                        }
                        // The map's own outline: its rings are not in the file.
                        MapProblem::Floor(fe @ FloorError::Domain(_)) => {
                            f("floor_plan.map", fe.to_string())
                        }
                        MapProblem::Floor(fe) => floor_error(fe.clone()),
                        // A problem of the start or the goal names that field; the map's
                        // own message names the map file.
                        MapProblem::NonFinitePoint(point)
                        | MapProblem::OutsideImage { point, .. }
                        | MapProblem::NotFree { point, .. }
                        | MapProblem::TooNarrow { point, .. }
                        | MapProblem::NotCertified { point, .. } => f(
                            match point {
                                MapPoint::Start => "robot.start",
                                MapPoint::Goal => "robot.goal",
                            },
                            e.to_string(),
                        ),
                        MapProblem::Unreachable => f("robot.goal", e.to_string()),
                        MapProblem::SpeckTooLarge { .. } => {
                            f("floor_plan.speck_pixels", e.to_string())
                        }
                        _ => f("floor_plan.map", e.to_string()),
                    }
                })?
            }
            None if plan.speck_pixels.is_some() || plan.simplify.is_some() => {
                return Err(f(
                    "floor_plan",
                    "speck_pixels and simplify apply to a map (floor_plan.map) only".into(),
                ));
            }
            None => {
                let outer = plan.outer.iter().copied().map(v).collect();
                let holes = plan
                    .holes
                    .iter()
                    .map(|ring| ring.iter().copied().map(v).collect())
                    .collect();
                FloorMap::new(outer, holes, &options).map_err(floor_error)?
            }
        };
        let setup_seconds = clock.elapsed().as_secs_f64();
        let floor = Arc::new(floor);
        let delta = floor.delta();
        let goal = v(r.goal);
        let place = |p: Vector2<f64>| placed(&floor, &obstacles, r.radius + r.margin, p);
        place(goal).map_err(|p| f("robot.goal", p))?;
        let start = v(r.start);
        place(start).map_err(|p| f("robot.start", p))?;
        // The start must reach the goal within W_δ (a map's opening checks so already); a
        // polygon's narrow passage is refused here, not met by a robot held still for ever.
        let reach = floor.reach(goal);
        if !reach.contains(start) {
            return Err(f(
                "robot.start",
                format!(
                    "the goal cannot be reached from ({}, {}) within the certified region \
                     (at least max(radius + margin, δ) = {:.4} m from the walls): a passage \
                     between them is narrower than the robot with its margin",
                    Shown(start.x),
                    Shown(start.y),
                    Shown(floor.shrink() + delta)
                ),
            ));
        }
        for (i, o) in obstacles.iter().enumerate() {
            // Furniture near or against a wall joins the walls when sensed (FloorMap::carved);
            // one whose centre is not in the free space is not furniture of this room.
            if !floor.walls().contains(o.centre()) {
                let c = o.centre();
                return Err(f(
                    &format!("obstacles[{i}]"),
                    format!(
                        "its centre ({}, {}) is not in the floor plan's free space (inside a \
                         wall or outside the outer ring)",
                        Shown(c.x),
                        Shown(c.y)
                    ),
                ));
            }
        }
        // With `require_certified_start`: c_δ over the walls, and each start's phi_k below it.
        let certified = if self.floor_plan.require_certified_start {
            let field = FloorField::new(floor.clone(), goal, self.field.k)
                .map_err(|e| f("robot.goal", e.to_string()))?;
            let level = field.certify_level(&LevelOptions::default());
            Some((field, level))
        } else {
            None
        };
        let below = |p: Vector2<f64>| match &certified {
            None => Ok(()),
            Some((field, level)) => below_level(field, level, p),
        };
        below(start).map_err(|p| f("robot.start", p))?;
        // `[[robots]]`: the star world's keys and checks, each start and goal placed as
        // robot.start is (in W_δ, clear of the grown obstacles) and each start able to reach
        // its goal within W_δ.
        crate::scenario::check_fleet(
            &self.robots,
            (r.start, r.radius),
            &self.movers,
            r.base == BaseKind::Diff,
            place,
        )
        .map_err(|(field, p)| f(&field, p))?;
        for (i, robot) in self.robots.iter().enumerate() {
            let (start, goal) = (v(robot.start), v(robot.goal));
            if !floor.reach(goal).contains(start) {
                return Err(f(
                    &format!("robots[{i}].start"),
                    format!(
                        "its goal cannot be reached from ({}, {}) within the certified region \
                         (at least max(radius + margin, δ) = {:.4} m from the walls): a passage \
                         between them is narrower than the robot with its margin",
                        Shown(start.x),
                        Shown(start.y),
                        Shown(floor.shrink() + delta)
                    ),
                ));
            }
        }
        let mut starts = vec![start];
        if let Some(spec) = self.starts {
            if spec.count > MAX_STARTS {
                return Err(f(
                    "starts.count",
                    format!("at most {MAX_STARTS} starts, got {}", spec.count),
                ));
            }
            let drawn = draw_starts(&floor, goal, spec.count, spec.seed, |p| {
                place(p).is_ok() && reach.contains(p) && below(p).is_ok()
            });
            let Some(drawn) = drawn else {
                let what = if certified.is_some() {
                    "no free start below c_δ (floor_plan.require_certified_start)"
                } else {
                    "no free start"
                };
                return Err(f("starts", format!("{what} found in 10⁴ tries")));
            };
            starts.extend(drawn);
        }
        let lidar = match &self.sensor {
            None => None,
            Some(spec) => {
                Some(floor_lidar(spec, &floor, &obstacles).map_err(|(field, p)| f(&field, p))?)
            }
        };
        // The chain of funnels over the walls (before any obstacle is sensed), from the level
        // of `require_certified_start` when it was certified.
        let funnels = if self.floor_plan.funnels {
            let field = match &certified {
                Some((field, _)) => field.clone(),
                None => FloorField::new(floor.clone(), goal, self.field.k)
                    .map_err(|e| f("robot.goal", e.to_string()))?,
            };
            let options = FunnelOptions::on_this_machine();
            let level = certified.as_ref().map(|(_, level)| *level);
            let inflation = r.radius + r.margin;
            Some(Arc::new(
                field.funnels(level, start, inflation, &obstacles, &options),
            ))
        } else {
            None
        };
        Ok(FloorPrepared {
            path: path.to_path_buf(),
            scenario: self,
            floor,
            obstacles,
            starts,
            setup_seconds,
            funnels,
            level: certified.map(|(_, level)| level),
            lidar,
            pixels,
            specks,
        })
    }
}

/// The lidar of a floor plan's `[sensor]` and its `ρ_min` (the file's, or the true obstacles'
/// smallest curvature radius), or the field and the problem.
fn floor_lidar(
    spec: &SensorSpec,
    floor: &FloorMap,
    obstacles: &[StarShape],
) -> Result<(LidarSensor, f64), (String, String)> {
    let f = |field: &str, problem: String| (format!("sensor.{field}"), problem);
    if spec.kind != SensorKind::Lidar {
        return Err(f(
            "type",
            "a floor plan senses through a lidar (sensor.type = \"lidar\") or, without \
             [sensor], within sim.sensor_range; the paper's sector is not built for floor plans"
                .into(),
        ));
    }
    if !(spec.aperture_deg.is_finite()
        && spec.aperture_deg >= harmonav::tuning::MIN_APERTURE_DEG
        && spec.aperture_deg <= 360.0)
    {
        return Err(f(
            "aperture_deg",
            format!(
                "must be in (0, 360] and at least {}°, got {:e}",
                harmonav::tuning::MIN_APERTURE_DEG,
                spec.aperture_deg
            ),
        ));
    }
    let closest = crate::sensor::RANGE_MIN;
    if !(spec.range.is_finite() && spec.range > closest && spec.range <= 1e6) {
        return Err(f(
            "range",
            format!(
                "must be finite, above the closest return {closest} m and at most 1e6, got {:e}",
                spec.range
            ),
        ));
    }
    let rho = spec.rho_min.unwrap_or_else(|| {
        obstacles
            .iter()
            .map(StarShape::rho_min)
            .fold(f64::INFINITY, f64::min)
    });
    let (lo, hi) = crate::scenario::PARAMETER_RANGE;
    if !(obstacles.is_empty() && spec.rho_min.is_none()
        || rho.is_finite() && (lo..=hi).contains(&rho))
    {
        return Err(f(
            "rho_min",
            format!(
                "must be finite and in [{lo:e}, {hi:e}] m, got {rho:e}{}",
                if spec.rho_min.is_none() {
                    " (the obstacles' smallest curvature radius, as none is given)"
                } else {
                    ""
                }
            ),
        ));
    }
    // No point of the plan is much farther from a wall than the farthest of a 100 × 100 grid
    // over it (within a cell's half diagonal); the true obstacles' distance to the walls from
    // their outlines (a vertex each 5e-5 of the size apart, within the default prior's 1 %
    // slack).
    let (a, b) = floor.walls().bounding_box();
    let cells = 100;
    let farthest = (0..=cells)
        .flat_map(|i| (0..=cells).map(move |j| (i, j)))
        .map(|(i, j)| {
            let t = Vector2::new(i as f64, j as f64) / cells as f64;
            a + (b - a).component_mul(&t)
        })
        .filter(|&p| floor.walls().contains(p))
        .map(|p| floor.wall_distance(p))
        .fold(0.0, f64::max);
    let nearest = obstacles
        .iter()
        .flat_map(|o| o.outline())
        .map(|p| floor.wall_distance(p))
        .fold(f64::INFINITY, f64::min);
    let room = WallRoom {
        limit: (
            farthest,
            "the farthest any point of the plan lies from its walls",
        ),
        nearest: if nearest.is_finite() { nearest } else { 0.0 },
    };
    let lidar = sensor::prepare(spec, room, obstacles).map_err(|(field, p)| f(field, p))?;
    Ok((lidar, rho))
}

impl FileKind {
    /// The format of the file at `path`: a floor plan when its top level has a `[floor_plan]`
    /// table, a star world otherwise (text that is not TOML is a star world too, so that its
    /// loader reports the parse error with its line; [`FileKind::of_text`]).
    ///
    /// # Errors
    /// The file cannot be read ([`crate::scenario::read_text`]).
    pub fn of(path: &Path) -> Result<Self, ScenarioError> {
        Ok(Self::of_text(&crate::scenario::read_text(path)?))
    }
}
