//! The floor-plan loop (issue 25, `docs/maths.md` §13): the user's loop around a
//! [`harmonav::FloorNavigator`] on a [`FloorPrepared`] scenario, with its monitors (no
//! collision with the true walls and obstacles, at the states and along the steps, never
//! leaving, staying in the certified region, arrival within a stated threshold), its
//! [`FloorSummary`] (`harmonav run` on a floor plan), and the map's certificate.

use harmonav::control::Branch;
use harmonav::perception::sim::Enclosure;
use harmonav::{Controller, FloorNavigator, Law, Mover, NavError, Options, StarShape};
use harmonav_harmonic::Certificate;
use harmonav_scenario::floorplan::FloorPrepared;
use harmonav_scenario::{LidarSensor, Model, ShapeSpec};
use nalgebra::Vector2;
use serde::Serialize;

use crate::guarantee::MARGIN_TOLERANCE;
use crate::guarantee::{Check, Guarantee};
use crate::movers::{FleetReport, FleetRobot, MoverReport, MoverWorld, Sweep};
use crate::outcome::Outcome;
use crate::scanner::{Scanner, Scene};
use crate::summary::{PerceptionReport, Physics};
use crate::trace::{Discovery, Event, MoverFrame, MoverMark, Sample, frame_due, recorded_velocity};
use crate::trajectory::{Keep, Trajectory};
use crate::unicycle::{Diff, DiffReport};

/// How a floor-plan run ended: replaced by the star world's [`Outcome`] in
/// [`FloorRun::outcome`] (2026-12-07), kept for one release.
#[deprecated(note = "a floor-plan run ends with `Outcome` (`FloorRun::outcome`, `outcome_name`)")]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FloorEnding {
    /// Within the arrival threshold of the goal.
    Reached,
    /// The robot's disc touched a true wall or obstacle.
    Collision,
    /// The robot's centre left the floor plan (or entered a hole).
    Left,
    /// The time limit passed first.
    TimedOut,
    /// The navigator refused a command (the error is in [`FloorRun::error`]).
    Refused,
}

#[allow(deprecated)]
impl FloorEnding {
    /// The name for JSON and tables ([`outcome_name`]).
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Reached => "reached",
            Self::Collision => "collision",
            Self::Left => "left",
            Self::TimedOut => "timed_out",
            Self::Refused => "refused",
        }
    }
}

#[allow(deprecated)]
impl From<&Outcome> for FloorEnding {
    fn from(outcome: &Outcome) -> Self {
        match outcome {
            Outcome::Reached { .. } => Self::Reached,
            Outcome::Collision => Self::Collision,
            Outcome::LeftWorkspace => Self::Left,
            Outcome::CommandRefused { .. } | Outcome::ScanRefused { .. } => Self::Refused,
            _ => Self::TimedOut,
        }
    }
}

#[allow(deprecated)]
impl FloorRun {
    /// How the run ended, as before 2026-12-07 ([`FloorRun::outcome`] is the typed outcome).
    #[deprecated(note = "use the field `outcome` (an `Outcome`)")]
    #[must_use]
    pub fn ending(&self) -> FloorEnding {
        FloorEnding::from(&self.outcome)
    }
}

/// The name of a floor-plan run's [`Outcome`] in its `summary.json` (`outcome`: a string,
/// as before the two worlds shared one outcome type; the CLI's and Python's contract):
/// `"reached"`, `"collision"`, `"left"`, `"timed_out"`, or `"refused"` (a command or a scan).
#[must_use]
pub fn outcome_name(outcome: &Outcome) -> &'static str {
    match outcome {
        Outcome::Reached { .. } => "reached",
        Outcome::Collision => "collision",
        Outcome::LeftWorkspace => "left",
        Outcome::CommandRefused { .. } | Outcome::ScanRefused { .. } => "refused",
        _ => "timed_out",
    }
}

/// What one run measured.
#[derive(Clone, Debug)]
pub struct FloorRun {
    /// How it ended: [`Outcome::Reached`], [`Outcome::Collision`] (the disc touched a true
    /// wall, obstacle or map pixel), [`Outcome::LeftWorkspace`] (the centre left the plan or
    /// entered a hole), [`Outcome::TimedOut`], or [`Outcome::CommandRefused`] (the navigator
    /// refused a command or a scan; the error in [`FloorRun::error`]). The monitors' verdicts
    /// are judged with it by [`crate::sweep::floor_outcome`].
    pub outcome: Outcome,
    /// Simulated time, s.
    pub time: f64,
    /// The smallest distance from the robot's centre to a true wall, minus its radius (its
    /// disc's clearance), m.
    pub wall_clearance: f64,
    /// On a ROS map, the smallest clearance of the disc from the map's own occupied and unknown
    /// pixels ([`FloorPrepared::pixels`]), m; ∞ otherwise.
    pub pixel_clearance: f64,
    /// The smallest clearance of the robot's disc from a true obstacle, m (∞ with none).
    pub obstacle_clearance: f64,
    /// A lower bound on the disc's clearance from the true walls and obstacles along every
    /// held step, not only at the states: the clearance `c` is 1-Lipschitz, so a step of
    /// length `L` from `c₀` to `c₁` keeps at least `(c₀ + c₁ − L)/2`, m.
    pub swept_clearance: f64,
    /// The smallest certified clearance to the boundary layer (`sd − δ`) seen, m.
    pub layer_clearance: f64,
    /// `|x − x_d|` at the end, m.
    pub final_distance: f64,
    /// Path length, m.
    pub path: f64,
    /// The largest speed `|ẋ|`, m/s.
    pub max_speed: f64,
    /// The largest force `|f|` held (the dynamic law; 0 for the kinematic law), N.
    pub max_force: f64,
    /// Obstacles sensed and added.
    pub sensed: usize,
    /// The sensed obstacles in order: name, index, time, and the robot's position then (the
    /// sensing is a disc of radius `sim.sensor_range`: no axis).
    pub discoveries: Vec<Discovery>,
    /// `k` at the end (holes plus sensed obstacles, under the navigator's `k` policy).
    pub k: f64,
    /// Commands issued.
    pub commands: usize,
    /// Escapes begun from rest points of the hold's slide ([`harmonav::Mode::Escaping`],
    /// docs/maths.md §13.7).
    pub escapes: usize,
    /// The positions kept for figures, in time order: every state while they fit in
    /// [`crate::trajectory::MAX_KEPT_STATES`], then an even decimation (`Trajectory`), with
    /// the discoveries and the last state always kept.
    pub positions: Vec<[f64; 2]>,
    /// The navigator's error, if it refused.
    pub error: Option<NavError>,
    /// The integrator that moved the robot.
    pub physics: Physics,
    /// rapier's contact events between the robot and the walls or obstacles (rapier runs).
    pub contacts: Option<usize>,
    /// The largest distance from the built-in run's state at the same time, m (rapier runs
    /// given a built-in run as reference).
    pub max_deviation: Option<f64>,
    /// With a lidar (`[sensor] type = "lidar"`): what its perception did, and its guarantees
    /// (the seen truth covered, shapes only growing, every scan accepted; `crate::scanner`).
    pub perception: Option<(PerceptionReport, Vec<Guarantee>)>,
    /// With a lidar: the shapes it perceived by the end (not grown), in the perception's
    /// order; empty otherwise.
    pub perceived: Vec<StarShape>,
    /// What the file's movers did (`None` without movers).
    pub movers: Option<MoverReport>,
    /// The movers every [`crate::trace::MOVER_FRAME_PERIOD`] (empty without movers), as the
    /// observer got them.
    pub mover_frames: Vec<MoverFrame>,
    /// A differential drive's commands and arcs (`[robot] base = "diff"`; `None` otherwise).
    pub diff: Option<DiffReport>,
    /// A file with `[[robots]]`: the other robots and the clearances between all of them
    /// (the lockstep loop of the robots; this run is the first robot's). `None` otherwise.
    pub fleet: Option<FleetReport>,
    /// Under the dynamic law with the built-in step: the largest rise of `V = μΨ + ½m|ẋ|²`
    /// over one period relative to `V`, and the same beyond the step's own error
    /// (the held loop's `euler_energy_error`), over the periods whose command was the law's
    /// (`law` or `capped`) or a custom controller's, with no discovery in them
    /// ([`Check::EnergyNonIncreasing`]). `None` for the kinematic law, a differential drive,
    /// rapier, or a run with no such period.
    pub energy_rise: Option<(f64, f64)>,
}

/// The name of the `i`-th obstacle of a floor-plan file: its `name`, or `obstacles[i]`.
#[must_use]
pub fn obstacle_name(prepared: &FloorPrepared, i: usize) -> String {
    match prepared.scenario.obstacles.get(i).and_then(ShapeSpec::name) {
        Some(name) => name.to_string(),
        None => format!("obstacles[{i}]"),
    }
}

/// The file's robot as a [`FloorNavigator`] on its map, under `model`'s law (the file's by
/// default), knowing no obstacle yet: the navigator of [`run`], and of the CLI's `eval` and the
/// figure's level sets (for `Θ` the law does not matter).
///
/// # Errors
/// The navigator could not be built (a message naming the parameter).
pub fn navigator(
    prepared: &FloorPrepared,
    model: Option<Model>,
) -> Result<FloorNavigator, NavError> {
    navigator_and_lidar(prepared, model).map(|(nav, _)| nav)
}

/// [`navigator`], and the file's lidar for its law ([`LidarSensor::for_law`]: the fit range of
/// eq. fitnear under the kinematic law), whose priors the navigator's options then carry.
pub(crate) fn navigator_and_lidar(
    prepared: &FloorPrepared,
    model: Option<Model>,
) -> Result<(FloorNavigator, Option<LidarSensor>), NavError> {
    let r = &prepared.scenario.robot;
    let law = match model.unwrap_or(r.model) {
        Model::Kinematic => Law::kinematic(r.gain),
        Model::Dynamic => Law::dynamic(r.mass, r.mu),
    };
    let sc = &prepared.scenario;
    let mut options = Options::default()
        .with_robot(r.radius, r.margin)
        .with_heading(r.heading)
        .with_k(sc.field.k)
        .with_damping(sc.controller.damping)
        .with_speed(sc.controller.speed);
    if let Some(v) = r.v_max {
        options = options.with_v_max(v);
    }
    if let Some(h) = prepared.control_period() {
        options = options.with_control_period(h);
    }
    if let Some(base) = prepared.base() {
        options = options.with_base(base);
    }
    if let (Some(force), Model::Dynamic) = (r.force_bound, model.unwrap_or(r.model)) {
        options = options.with_force_bound(force);
    }
    let options = options.with_comfort(r.comfort);
    let lidar = prepared
        .lidar
        .map(|(l, rho)| (l.for_law(&law, &options), rho));
    let options = match &lidar {
        Some((l, rho)) => l.options(options, *rho),
        None => options,
    };
    let mut nav = FloorNavigator::new(prepared.floor.clone(), Vector2::from(r.goal), law, options)?;
    if let Some(chain) = &prepared.funnels {
        nav.set_funnels(chain.clone())?;
    }
    Ok((nav, lidar.map(|(l, _)| l)))
}

/// Runs the user's loop from `start` under `model` (the file's by default): at every period
/// `h` (`robot.control_period`, or the law's default) the robot senses the true obstacles
/// within `sim.sensor_range` (added once, grown by the navigator) or, with `[sensor] type = "lidar"`, hands the navigator a scan of the true walls
/// and obstacles whenever one is due ([`FloorNavigator::observe_scan`], judged as in a star
/// world), asks [`FloorNavigator::command`], and holds it — `x += h·u` (kinematic), or
/// `v += h·f/m, x += h·v` (dynamic, semi-implicit Euler; `Held::euler`). The monitors use
/// the true walls and shapes only, at every state and (by the Lipschitz bound of
/// [`FloorRun::swept_clearance`]) along every step.
///
/// # Errors
/// The navigator could not be built (a message naming the parameter).
pub fn run(
    prepared: &FloorPrepared,
    model: Option<Model>,
    start: Vector2<f64>,
) -> Result<FloorRun, NavError> {
    if !prepared.scenario.robots.is_empty() {
        return fleet(prepared, model, start, None, true);
    }
    fly(prepared, model, start, None, &mut |held| held.euler(), None)
}

/// [`run`], handing every state, scan and discovery to `observer` as they are made (in time
/// order: at each state its scan and discoveries first): what a recording streamed to disk
/// is written from (`harmonav_output::floor::FloorOutputs`).
///
/// # Errors
/// The navigator could not be built (a message naming the parameter).
pub fn run_observed(
    prepared: &FloorPrepared,
    model: Option<Model>,
    start: Vector2<f64>,
    observer: &mut dyn FnMut(Event<'_>),
) -> Result<FloorRun, NavError> {
    if !prepared.scenario.robots.is_empty() {
        return fleet(prepared, model, start, Some(observer), true);
    }
    fly(
        prepared,
        model,
        start,
        None,
        &mut |held| held.euler(),
        Some(observer),
    )
}

/// [`run`], with every state at the control period (the start first): the reference of a
/// rapier run's deviation (`harmonav_sim::rapier::run_floor_rapier`).
///
/// # Errors
/// The navigator could not be built (a message naming the parameter).
pub fn run_with_states(
    prepared: &FloorPrepared,
    model: Option<Model>,
    start: Vector2<f64>,
) -> Result<(FloorRun, Vec<Vector2<f64>>), NavError> {
    let mut states = vec![start];
    let run = fly(
        prepared,
        model,
        start,
        None,
        &mut |held| {
            let moved = held.euler();
            states.push(moved.x);
            moved
        },
        None,
    )?;
    Ok((run, states))
}

/// A controller other than the law on a floor plan: `(navigator, x, ẋ) → command` (the
/// velocity for the kinematic model, the force for the dynamic one).
pub type FloorLaw<'a> = &'a dyn Fn(&FloorNavigator, Vector2<f64>, Vector2<f64>) -> Vector2<f64>;

/// Where a held control period left the robot: its position, its velocity and, for a
/// differential drive, its heading (rad).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Moved {
    /// Position at the period's end.
    pub x: Vector2<f64>,
    /// Velocity at the period's end.
    pub v: Vector2<f64>,
    /// A differential drive's heading at the period's end (`None` for a holonomic robot).
    pub yaw: Option<f64>,
}

/// A differential drive's command held over a period: `(v, ω)` from the heading `yaw`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PoseHeld {
    /// Heading at the period's start, rad.
    pub yaw: f64,
    /// Forward speed, m/s.
    pub v: f64,
    /// Turn rate, rad/s.
    pub omega: f64,
}

/// One control period of the loop: the state at its start, the command held over it, the
/// law and the period. An integrator (`hold` of [`fly`]) returns where it left the robot.
pub(crate) struct Held<'a> {
    /// The law (the model, and the dynamic law's mass).
    pub controller: &'a Controller,
    /// The control period, s.
    pub h: f64,
    /// Position at the period's start.
    pub x: Vector2<f64>,
    /// Velocity at the period's start.
    pub v: Vector2<f64>,
    /// The command held: velocity (kinematic) or force (dynamic); for a differential drive,
    /// zero and [`Held::pose`] instead.
    pub command: Vector2<f64>,
    /// A differential drive's `(v, ω)` (`None` for a holonomic robot).
    pub pose: Option<PoseHeld>,
}

impl Held<'_> {
    /// The built-in step: `x += h·u` (kinematic, `ẋ = u`), or `v += h·f/m, x += h·v` (dynamic,
    /// semi-implicit Euler); a differential drive moves on the exact arc of its `(v, ω)`
    /// ([`harmonav::unicycle_arc`], the arc its monitor judged), its velocity `v·e(θ)` at the
    /// arc's end.
    #[must_use]
    pub(crate) fn euler(&self) -> Moved {
        if let Some(p) = self.pose {
            let (x, yaw, v) = crate::step::arc_step(self.x, p.yaw, p.v, p.omega, self.h);
            return Moved {
                x,
                v,
                yaw: Some(yaw),
            };
        }
        let (x, v) = crate::step::held(self.controller, self.h, self.x, self.v, self.command);
        Moved { x, v, yaw: None }
    }
}

/// The recorded state of a floor-plan run at `t`: `Θ`, and under the dynamic law `V` (of the
/// floor's `Θ`, whose scale shift is 0) and the damping in force, from the navigator's own
/// evaluation ([`FloorNavigator::evaluate`]: `NaN` where it refuses, as at a collision). The
/// velocity is `ẋ` under the dynamic law and the law's `u` under the kinematic one (the loop
/// replaces it by the command held, capped or escaping, when there is one). No energy
/// tolerance: a floor plan's energy is recorded, not judged.
fn sample(nav: &FloorNavigator, t: f64, x: Vector2<f64>, v: Vector2<f64>) -> Sample {
    let e = nav.evaluate(x, v).ok();
    let dynamic = match nav.controller() {
        Controller::Dynamic(law) => Some(law),
        Controller::Kinematic(_) => None,
    };
    let damping = e.as_ref().and_then(|e| e.damping);
    let calibration = (nav.field().destination_stiffness(), 0.0);
    Sample {
        t,
        x: [x.x, x.y],
        v: recorded_velocity(dynamic.is_some(), v, e.as_ref().map(|e| e.command)),
        theta: e.as_ref().map_or(f64::NAN, |e| e.field.value),
        energy: dynamic.map(|law| {
            e.as_ref()
                .map_or(f64::NAN, |e| law.energy_for(calibration, &e.field, v))
        }),
        k: nav.k(),
        lambda: damping.map(|d| d.lambda),
        energy_tolerance: 0.0,
        critical: damping.is_some_and(|d| d.branch == Branch::Critical),
        yaw: None,
    }
}

/// The rise of `V = μΨ + ½m|ẋ|²` over one held period of the dynamic law, from `(x₀, ẋ₀)`
/// to `(x₁, ẋ₁)` under the force `f`, relative to `V(x₀, ẋ₀)`: `(raw, beyond)`, the second
/// less the semi-implicit Euler step's own error ([`crate::held::euler_energy_error`], as a
/// star world's held loop allows). `None` under the kinematic law, or where either state has
/// no `V` (the boundary layer). `V` is the navigator's own (the floor's `Θ`, scale shift 0).
fn energy_rise(
    nav: &FloorNavigator,
    (x0, x1): (Vector2<f64>, Vector2<f64>),
    (v0, v1): (Vector2<f64>, Vector2<f64>),
    f: Vector2<f64>,
    h: f64,
) -> Option<(f64, f64)> {
    let Controller::Dynamic(law) = nav.controller() else {
        return None;
    };
    let calibration = (nav.field().destination_stiffness(), 0.0);
    let p0 = law.potential_for(calibration, &nav.evaluate(x0, v0).ok()?.field);
    let p1 = law.potential_for(calibration, &nav.evaluate(x1, v1).ok()?.field);
    let energy = |p: &harmonav::control::Potential, v: Vector2<f64>| {
        law.pull() * p.value + 0.5 * law.mass() * v.norm_squared()
    };
    let (e0, e1) = (energy(&p0, v0), energy(&p1, v1));
    let allowance = crate::held::euler_energy_error(law, h, (&p0, p1.value), (x0, x1), (v0, v1), f);
    // Guard: V is positive away from the goal; at the goal both are ~0 (as the star monitor).
    let scale = e0.max(1e-12);
    Some(((e1 - e0) / scale, (e1 - e0 - allowance) / scale))
}

/// The body disc's clearance at `p` from the true walls, obstacles and (on a map) pixels of
/// `prepared`.
fn body_clearance(prepared: &FloorPrepared, p: Vector2<f64>) -> f64 {
    let r = &prepared.scenario.robot;
    let pixels = prepared
        .pixels
        .as_ref()
        .map_or(f64::INFINITY, |px| px.signed_distance(p) - r.radius);
    prepared
        .obstacles
        .iter()
        .map(|o| o.signed_distance(p) - r.radius)
        .fold(prepared.floor.wall_distance(p) - r.radius, f64::min)
        .min(pixels)
}

/// The other robots of a fleet as one robot's loop sees them in a period ([`fleet`]): the
/// movers its navigator is given besides the file's, and their marks in its movers' frames.
#[derive(Clone, Copy, Default)]
pub(crate) struct Peers<'p> {
    /// The other robots as movers (reciprocal while they fly).
    pub movers: &'p [Mover],
    /// Their marks in the movers' frames (the first robot's recording only).
    pub marks: &'p [MoverMark],
}

/// One robot's loop of [`fly`] in flight, between two of its steps: so that the robots of a
/// fleet ([`fleet`]) can fly in lockstep. Each control period is [`Flight::judge`] (the
/// monitors at the state, arrival, the time limit), then [`Flight::act`] (perception, the
/// command, its hold); [`Flight::finish`] makes the run.
pub(crate) struct Flight<'a, 'c, 'h, 'o> {
    prepared: &'a FloorPrepared,
    custom: Option<FloorLaw<'c>>,
    hold: &'h mut dyn FnMut(&Held) -> Moved,
    observer: Option<&'o mut dyn FnMut(Event<'_>)>,
    nav: FloorNavigator,
    scanner: Option<Scanner>,
    walls: Option<std::sync::Arc<harmonav::perception::Walls>>,
    yaw: f64,
    h: f64,
    /// The last control period the run may reach.
    pub steps: usize,
    x: Vector2<f64>,
    vel: Vector2<f64>,
    known: Vec<bool>,
    kept: Trajectory<[f64; 2]>,
    out: FloorRun,
    /// The file's movers (docs/movers.md §8): reported before every command of the law.
    world: MoverWorld,
    mass: f64,
    /// The disc's clearance at the previous state and the length of the step since.
    last: Option<(f64, f64)>,
    /// The disc's clearance at the state [`Flight::judge`] judged last.
    clearance: f64,
    /// The time of the last state handed to the observer: a state the loop goes on from is
    /// handed after its scan and discoveries and with the command held from it (the kinematic
    /// robot's velocity), the state it ended at after the loop.
    observed: Option<f64>,
    kinematic: bool,
    /// How the last command was formed, for the movers' frames.
    last_mode: Option<&'static str>,
    /// A differential drive (`crate::unicycle`): its heading, and the monitors of its arcs. A
    /// custom controller or rapier (`hold` other than the built-in step) drives the holonomic
    /// robot only.
    diff: Option<Diff>,
    /// The movers (the file's and the peers') are handed to the navigator (`false`: a
    /// negative control, the robot blind to them).
    filter: bool,
    /// How the robot moved over the period of the last [`Flight::act`], and whether its
    /// command was certified (at rest and certified before the first, and after the end).
    pub swept: (Sweep, bool),
}

impl<'a, 'c, 'h, 'o> Flight<'a, 'c, 'h, 'o> {
    /// The loop of `prepared` from `start` under `model`, before its first period.
    pub(crate) fn new(
        prepared: &'a FloorPrepared,
        model: Option<Model>,
        start: Vector2<f64>,
        custom: Option<FloorLaw<'c>>,
        hold: &'h mut dyn FnMut(&Held) -> Moved,
        observer: Option<&'o mut dyn FnMut(Event<'_>)>,
    ) -> Result<Self, NavError> {
        let r = &prepared.scenario.robot;
        let goal = Vector2::from(r.goal);
        let (nav, lidar) = navigator_and_lidar(prepared, model)?;
        let scanner = lidar.map(Scanner::new);
        let walls = scanner.as_ref().map(|_| nav.walls().clone());
        let h = nav.control_period();
        let steps = (prepared.scenario.sim.max_time / h).ceil() as usize;
        let out = FloorRun {
            outcome: Outcome::TimedOut {
                time: prepared.scenario.sim.max_time,
            },
            time: 0.0,
            wall_clearance: f64::INFINITY,
            pixel_clearance: f64::INFINITY,
            obstacle_clearance: f64::INFINITY,
            swept_clearance: f64::INFINITY,
            layer_clearance: f64::INFINITY,
            final_distance: (start - goal).norm(),
            path: 0.0,
            max_speed: 0.0,
            max_force: 0.0,
            sensed: 0,
            discoveries: Vec::new(),
            k: nav.k(),
            commands: 0,
            escapes: 0,
            positions: Vec::new(),
            error: None,
            physics: Physics::Builtin,
            contacts: None,
            max_deviation: None,
            perception: None,
            perceived: Vec::new(),
            movers: None,
            mover_frames: Vec::new(),
            diff: None,
            fleet: None,
            energy_rise: None,
        };
        let world = MoverWorld::new(&prepared.scenario.movers, r.radius);
        let mass = match nav.controller() {
            Controller::Dynamic(law) => law.mass(),
            Controller::Kinematic(_) => 1.0,
        };
        let kinematic = matches!(nav.controller(), Controller::Kinematic(_));
        let diff = match custom {
            None => Diff::of(prepared.base(), prepared.start_yaw()),
            Some(_) => None,
        };
        let yaw = diff.as_ref().map_or(0.0, |u| u.yaw);
        Ok(Self {
            prepared,
            custom,
            hold,
            observer,
            nav,
            scanner,
            walls,
            yaw,
            h,
            steps,
            x: start,
            vel: Vector2::zeros(),
            known: vec![false; prepared.obstacles.len()],
            kept: Trajectory::default(),
            out,
            world,
            mass,
            last: None,
            clearance: f64::INFINITY,
            observed: None,
            kinematic,
            last_mode: None,
            diff,
            filter: true,
            swept: (Sweep::Straight(start, start), true),
        })
    }

    /// The robot blind to the movers and to the other robots (a negative control).
    pub(crate) fn blind(mut self) -> Self {
        self.filter = false;
        self
    }

    /// The robot's position now.
    pub(crate) fn position(&self) -> Vector2<f64> {
        self.x
    }

    /// The robot's top speed: the kinematic law's `v_max`, the dynamic law's speed bound.
    pub(crate) fn speed_bound(&self) -> f64 {
        match self.nav.controller() {
            Controller::Dynamic(law) => law.speed_bound(),
            Controller::Kinematic(law) => law.v_max(),
        }
    }

    /// The monitors at the state of period `n` on the truth, then arrival and the time limit:
    /// `false` when the run ends here.
    pub(crate) fn judge(&mut self, n: usize) -> bool {
        let prepared = self.prepared;
        let (r, floor, x) = (&prepared.scenario.robot, &prepared.floor, self.x);
        let out = &mut self.out;
        self.swept = (Sweep::Straight(x, x), true);
        out.time = n as f64 * self.h;
        // Monitors on the truth.
        if !floor.walls().contains(x) {
            out.outcome = Outcome::LeftWorkspace;
            return false;
        }
        let wall = floor.wall_distance(x) - r.radius;
        // On a map, the map's own non-free pixels too (issue 56, D1): the floor plan's outline
        // dropped specks, was simplified and cuts pixel corners.
        let pixels = prepared
            .pixels
            .as_ref()
            .map_or(f64::INFINITY, |p| p.signed_distance(x) - r.radius);
        out.pixel_clearance = out.pixel_clearance.min(pixels);
        let obstacle = prepared
            .obstacles
            .iter()
            .map(|o| o.signed_distance(x) - r.radius)
            .fold(f64::INFINITY, f64::min);
        out.wall_clearance = out.wall_clearance.min(wall);
        out.obstacle_clearance = out.obstacle_clearance.min(obstacle);
        out.layer_clearance = out.layer_clearance.min(floor.clearance(x));
        let clearance = wall.min(obstacle).min(pixels);
        self.clearance = clearance;
        if let Some((before, step)) = self.last {
            out.swept_clearance = out.swept_clearance.min(0.5 * (before + clearance - step));
        }
        if out.wall_clearance <= 0.0 || out.obstacle_clearance <= 0.0 || out.pixel_clearance <= 0.0
        {
            out.outcome = Outcome::Collision;
            return false;
        }
        out.final_distance = (x - Vector2::from(r.goal)).norm();
        if out.final_distance < prepared.scenario.sim.arrival {
            out.outcome = Outcome::Reached { time: out.time };
            return false;
        }
        if n == self.steps {
            out.outcome = Outcome::TimedOut { time: out.time };
            return false;
        }
        true
    }

    /// The rest of the period after [`Flight::judge`]: perception, the command (given the
    /// file's movers and `peers`), its hold. `false`: the navigator refused, the run ends.
    ///
    /// # Errors
    /// The navigator refused a sensed obstacle or the movers (as [`fly`]).
    pub(crate) fn act(&mut self, peers: Peers<'_>) -> Result<bool, NavError> {
        let prepared = self.prepared;
        let r = &prepared.scenario.robot;
        let sim = prepared.scenario.sim;
        let (h, x) = (self.h, self.x);
        let out = &mut self.out;
        let nav = &mut self.nav;
        // Perception: a scan when one is due, or a true obstacle within range of the robot's
        // disc becomes known.
        let mut discovered = false;
        if let (Some(scanner), Some(walls)) = (self.scanner.as_mut(), self.walls.as_ref())
            && scanner.due(out.time)
        {
            let scene = Scene {
                obstacles: &prepared.obstacles,
                enclosure: Enclosure::Walls(walls),
            };
            match scanner.scan(nav, scene, out.time, x, self.yaw) {
                Ok(record) => {
                    discovered = record.perceived.is_some();
                    if let Some(o) = self.observer.as_mut() {
                        o(Event::Scan(&record));
                    }
                }
                Err(e) => {
                    out.outcome = Outcome::CommandRefused {
                        time: out.time,
                        reason: e.to_string(),
                    };
                    out.error = Some(e);
                    return Ok(false);
                }
            }
        }
        let exact = if self.scanner.is_some() {
            &[][..]
        } else {
            &prepared.obstacles[..]
        };
        for (i, (o, seen)) in exact.iter().zip(&mut self.known).enumerate() {
            if !*seen && o.signed_distance(x) - r.radius < sim.sensor_range {
                nav.add_obstacle(o.clone())?;
                *seen = true;
                discovered = true;
                out.sensed += 1;
                let discovery = Discovery {
                    obstacle: obstacle_name(prepared, i),
                    index: i,
                    time_s: out.time,
                    position: [x.x, x.y],
                    axis: [0.0; 2],
                };
                if let Some(o) = self.observer.as_mut() {
                    o(Event::Discovery(&discovery));
                }
                out.discoveries.push(discovery);
            }
        }
        // Sampled before the command (which moves the navigator's state on).
        let pending = self
            .observer
            .is_some()
            .then(|| sample(nav, out.time, x, self.vel));
        self.kept.push(
            [x.x, x.y],
            if discovered { Keep::Pinned } else { Keep::Grid },
        );
        let world = &mut self.world;
        let movers = !(world.is_empty() && peers.movers.is_empty());
        if !(world.is_empty() && peers.marks.is_empty()) && frame_due(&out.mover_frames, out.time) {
            let mut frame = world.frame(out.time, x, self.last_mode, h);
            frame.movers.extend_from_slice(peers.marks);
            if let Some(o) = self.observer.as_mut() {
                o(Event::Movers(&frame));
            }
            out.mover_frames.push(frame);
        }
        if self.custom.is_none() && movers && self.filter {
            nav.set_movers(world.reports_with(peers.movers.iter().copied()))?;
        }
        if let Some(u) = self.diff.as_mut() {
            // The arc of `(v, ω)` held for `h`, judged along its length against the walls and
            // obstacles and, with movers, against every mover (`crate::movers::Sweep::Arc`).
            let yaw = u.yaw;
            let (c, mode) = match crate::unicycle::pose_command(nav, x, yaw, movers) {
                Ok(c) => c,
                Err(e) => {
                    out.outcome = Outcome::CommandRefused {
                        time: out.time,
                        reason: e.to_string(),
                    };
                    out.error = Some(e);
                    return Ok(false);
                }
            };
            out.escapes = nav.escapes();
            out.commands += 1;
            if let (Some(o), Some(mut s)) = (self.observer.as_mut(), pending) {
                // Its motion `v·e(θ)` and heading, not the law's `u`.
                (s.v, s.yaw) = ([self.vel.x, self.vel.y], Some(u.yaw));
                o(Event::State(&s));
                self.observed = Some(out.time);
            }
            // The arc judged from the pose now; then the integrator moves the robot: the
            // built-in one on that exact arc, rapier's body along its heading.
            let (exact, _) = u.period_in(&|p| body_clearance(prepared, p), r.margin, x, &c, h);
            let moved = (self.hold)(&Held {
                controller: nav.controller(),
                h,
                x,
                v: self.vel,
                command: Vector2::zeros(),
                pose: Some(PoseHeld {
                    yaw,
                    v: c.v,
                    omega: c.omega,
                }),
            });
            let next = moved.x;
            self.vel = moved.v;
            if let Some(turned) = moved.yaw {
                (u.yaw, u.report.final_yaw) = (turned, turned);
            }
            self.yaw = u.yaw;
            out.max_speed = out.max_speed.max(self.vel.norm());
            // The arc's length, the path of the built-in step (a chord is never longer). Under
            // rapier the speed is set to |v| at every 1 ms step, so its path is the same length
            // (to rounding, measured); the chord guards a step that contacts pushed farther.
            let arc = c.v.abs() * h;
            let length = if next == exact {
                arc
            } else {
                arc.max((next - x).norm())
            };
            out.path += length;
            self.last = Some((self.clearance, length));
            let certified = mode.is_some_and(|m| m.certified());
            let arc = Sweep::Arc {
                x,
                yaw,
                v: c.v,
                omega: c.omega,
            };
            if movers {
                self.last_mode = Some(mode.as_ref().map_or("refused", harmonav::Mode::as_str));
            }
            if !world.is_empty() {
                world.count(mode.as_ref());
                world.period_along(&arc, h, certified);
            }
            self.swept = (arc, certified);
            self.x = next;
            return Ok(true);
        }
        let mut mode = None;
        let command = match self.custom {
            Some(law) => law(nav, x, self.vel),
            None => match nav.command(x, self.vel) {
                Ok(c) => {
                    out.escapes = nav.escapes();
                    mode = Some(c.mode);
                    c.value
                }
                // The reported bodies overlap: no certified command; the robot stops (as hard
                // as its force bound lets it).
                Err(NavError::InMover { .. }) if movers => {
                    if self.kinematic {
                        Vector2::zeros()
                    } else {
                        crate::movers::stop(self.mass, self.vel, h, nav.options().force_bound)
                    }
                }
                Err(e) => {
                    out.outcome = Outcome::CommandRefused {
                        time: out.time,
                        reason: e.to_string(),
                    };
                    out.error = Some(e);
                    return Ok(false);
                }
            },
        };
        out.commands += 1;
        if !self.kinematic {
            out.max_force = out.max_force.max(command.norm());
        }
        if let (Some(o), Some(mut s)) = (self.observer.as_mut(), pending) {
            if self.kinematic {
                s.v = [command.x, command.y];
            }
            o(Event::State(&s));
            self.observed = Some(out.time);
        }
        let held = Held {
            controller: nav.controller(),
            h,
            x,
            v: self.vel,
            command,
            pose: None,
        };
        let moved = (self.hold)(&held);
        // The energy monitor: on the built-in step (the one its error model describes) of a
        // period the law (or a custom controller, as in a star world) commanded, with nothing
        // discovered; an escape, a way out of the band, a filtered or a bounded command is
        // not the law's, and may add energy.
        let judged = !discovered
            && (self.custom.is_some()
                || matches!(
                    mode,
                    Some(harmonav::Mode::Law | harmonav::Mode::Capped { .. })
                ));
        if judged
            && {
                let euler = held.euler();
                (euler.x, euler.v) == (moved.x, moved.v)
            }
            && let Some((raw, beyond)) =
                energy_rise(nav, (x, moved.x), (self.vel, moved.v), command, h)
        {
            let (r0, b0) = out.energy_rise.unwrap_or((0.0, 0.0));
            out.energy_rise = Some((r0.max(raw), b0.max(beyond)));
        }
        let next = moved.x;
        self.vel = moved.v;
        out.max_speed = out.max_speed.max(self.vel.norm());
        let step = (next - x).norm();
        if step > 0.0 {
            self.yaw = (next.y - x.y).atan2(next.x - x.x);
        }
        out.path += step;
        self.last = Some((self.clearance, step));
        let certified = mode.as_ref().is_some_and(|m| m.certified());
        if movers {
            self.last_mode = Some(mode.as_ref().map_or("refused", harmonav::Mode::as_str));
        }
        if !world.is_empty() {
            world.count(mode.as_ref());
            world.period(x, next, h, certified);
        }
        self.swept = (Sweep::Straight(x, next), certified);
        self.x = next;
        Ok(true)
    }

    /// The robot's run alone (no other robots), every period to its end.
    ///
    /// # Errors
    /// As [`Flight::act`].
    fn alone(mut self) -> Result<FloorRun, NavError> {
        for n in 0..=self.steps {
            if !(self.judge(n) && self.act(Peers::default())?) {
                break;
            }
        }
        Ok(self.finish())
    }

    /// The run, after its last period.
    pub(crate) fn finish(mut self) -> FloorRun {
        let (x, vel) = (self.x, self.vel);
        let mut out = self.out;
        out.movers = (!self.world.is_empty()).then(|| self.world.report.clone());
        if let Some(o) = self.observer.as_mut()
            && self.observed != Some(out.time)
        {
            let mut s = sample(&self.nav, out.time, x, vel);
            if let Some(u) = &self.diff {
                (s.v, s.yaw) = ([vel.x, vel.y], Some(u.yaw));
            }
            o(Event::State(&s));
        }
        out.diff = self.diff.map(|u| u.report);
        self.kept.push([x.x, x.y], Keep::Pinned);
        out.positions = self.kept.into_samples();
        out.k = self.nav.k();
        out.perception = self
            .scanner
            .map(|s| s.judge(&self.nav, &self.prepared.obstacles));
        out.perceived = self
            .nav
            .perceived()
            .map(|(_, p)| p.shape().clone())
            .collect();
        out
    }
}

/// The loop of [`run`] with its integrator `hold` (the built-in step, or rapier's), with
/// `custom` a controller other than the law, and with `observer` the run's events as they are
/// made ([`run_observed`]; the samples' evaluations are made only for an observer).
pub(crate) fn fly(
    prepared: &FloorPrepared,
    model: Option<Model>,
    start: Vector2<f64>,
    custom: Option<FloorLaw<'_>>,
    hold: &mut dyn FnMut(&Held) -> Moved,
    observer: Option<&mut dyn FnMut(Event<'_>)>,
) -> Result<FloorRun, NavError> {
    Flight::new(prepared, model, start, custom, hold, observer)?.alone()
}

/// A loop's observer of events.
type Observer<'a> = dyn FnMut(Event<'_>) + 'a;

/// The scenario of robot `i` of a floor plan's fleet (0: `[robot]` from `start`, then the
/// `[[robots]]`): the file with that start, goal and (a differential drive) start heading and
/// no other robots, on the same solved map (not solved again).
fn member(prepared: &FloorPrepared, i: usize, start: Vector2<f64>) -> FloorPrepared {
    let mut p = prepared.clone();
    let sc = &mut p.scenario;
    if i > 0 {
        let r = sc.robots[i - 1].clone();
        (sc.robot.start, sc.robot.goal) = (r.start, r.goal);
        if let Some(yaw) = r.yaw {
            sc.robot.yaw = Some(yaw);
        }
    } else {
        sc.robot.start = [start.x, start.y];
    }
    sc.robots.clear();
    p.starts = vec![Vector2::from(sc.robot.start)];
    p
}

/// A floor plan with `[[robots]]` (docs/movers.md §8), the first robot from `start`: every
/// robot flies its own loop ([`Flight`], its own [`FloorNavigator`] on the one solved map) in
/// lockstep at the control period, its navigator given the file's movers and the other robots
/// (reciprocal, share ½, exact positions; one whose run has ended as a non-cooperative mover
/// at rest), as in a star world. The run is the first robot's, its `fleet` the others and the
/// clearances between all of them ([`FloorSummary`] judges `no-collision-between-robots`).
/// Only the first robot's events go to `observer`. `filter: false` (a negative control): no
/// robot is given the movers or the other robots.
fn fleet(
    prepared: &FloorPrepared,
    model: Option<Model>,
    start: Vector2<f64>,
    observer: Option<&mut dyn FnMut(Event<'_>)>,
    filter: bool,
) -> Result<FloorRun, NavError> {
    let n = prepared.scenario.robots.len() + 1;
    let members: Vec<FloorPrepared> = (0..n).map(|i| member(prepared, i, start)).collect();
    let radius = prepared.scenario.robot.radius;
    let mut holds: Vec<fn(&Held) -> Moved> = vec![|held: &Held| held.euler(); n];
    // The other robots' states as their loops hand them over (their own trajectories).
    let mut tracks: Vec<Trajectory<Sample>> = (1..n).map(|_| Trajectory::default()).collect();
    let mut keep: Vec<Box<Observer<'_>>> = tracks
        .iter_mut()
        .map(|track| {
            Box::new(move |e: Event<'_>| {
                if let Event::State(s) = e {
                    track.push(s.clone(), Keep::Grid);
                }
            }) as Box<Observer<'_>>
        })
        .collect();
    // The caller's observer, for the first robot, behind a borrow as short as the others'.
    let mut observer = observer;
    let given = observer.is_some();
    let mut first = |e: Event<'_>| {
        if let Some(o) = observer.as_mut() {
            o(e);
        }
    };
    let mut observers: Vec<Option<&mut Observer<'_>>> =
        vec![given.then_some(&mut first as &mut Observer<'_>)];
    observers.extend(keep.iter_mut().map(|k| Some(&mut **k as &mut Observer<'_>)));
    let mut flights = Vec::with_capacity(n);
    for ((p, hold), o) in members.iter().zip(holds.iter_mut()).zip(observers) {
        let from = Vector2::from(p.scenario.robot.start);
        let flight = Flight::new(p, model, from, None, hold, o)?;
        flights.push(if filter { flight } else { flight.blind() });
    }
    let (h, steps) = (flights[0].h, flights[0].steps);
    let mut ended = vec![false; n];
    let mut report = FleetReport {
        min_robot_clearance: f64::INFINITY,
        ..FleetReport::default()
    };
    let mut touching = vec![false; n * n];
    for step in 0..=steps {
        for (f, done) in flights.iter_mut().zip(&mut ended) {
            if !*done && !f.judge(step) {
                *done = true;
            }
        }
        if ended.iter().all(|&done| done) {
            break;
        }
        let at: Vec<(Vector2<f64>, f64, bool)> = flights
            .iter()
            .zip(&ended)
            .map(|(f, &done)| (f.position(), f.speed_bound(), done))
            .collect();
        let marks = crate::movers::peer_marks(&at[1..], radius, h);
        for (i, f) in flights.iter_mut().enumerate() {
            if ended[i] {
                continue;
            }
            let movers: Vec<Mover> = crate::movers::peers(&at, i, radius).collect();
            let peers = Peers {
                movers: &movers,
                marks: if i == 0 { &marks } else { &[] },
            };
            if !f.act(peers)? {
                ended[i] = true;
            }
        }
        let swept: Vec<(Sweep, bool)> = flights.iter().map(|f| f.swept).collect();
        report.period(&swept, &mut touching, radius, h);
    }
    let mut runs: Vec<FloorRun> = flights.into_iter().map(Flight::finish).collect();
    drop(keep);
    // Never empty: `[robot]` is robot 0.
    let mut lead = runs.remove(0);
    report.others = runs
        .into_iter()
        .zip(&members[1..])
        .zip(tracks)
        .map(|((run, p), track)| {
            let from = Vector2::from(p.scenario.robot.start);
            let s = FloorSummary::new(p, model, from, &run);
            FleetRobot {
                start: p.scenario.robot.start,
                goal: p.scenario.robot.goal,
                reached: s.reached,
                time_s: s.time_s,
                final_distance: s.final_distance,
                safe: s.safe(),
                movers: s.movers,
                samples: track.into_samples(),
            }
        })
        .collect();
    lead.fleet = Some(report);
    Ok(lead)
}

/// [`run`] with the robot blind to the movers (its navigator never given them) while they
/// still move and every contact is judged; in a file with `[[robots]]`, every robot blind to
/// the movers and to the others: the negative control of `no-collision-with-movers` and
/// `no-collision-between-robots` on a floor plan.
///
/// # Errors
/// The navigator could not be built (a message naming the parameter).
pub fn run_without_filter(
    prepared: &FloorPrepared,
    model: Option<Model>,
    start: Vector2<f64>,
) -> Result<FloorRun, NavError> {
    if !prepared.scenario.robots.is_empty() {
        return fleet(prepared, model, start, None, false);
    }
    let mut hold = |held: &Held| held.euler();
    Flight::new(prepared, model, start, None, &mut hold, None)?
        .blind()
        .alone()
}

/// The judgement of a floor-plan run (`harmonav run` on a `[floor_plan]` file, its
/// `summary.json`): what was measured and each guarantee with its verdict.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FloorSummary {
    /// The scenario's name.
    pub name: String,
    /// The robot model that ran.
    pub model: Model,
    /// The integrator that moved the robot.
    pub physics: Physics,
    /// rapier's contact events (`null` for the built-in integrator), as in a star world's
    /// summary.
    pub physics_contacts: Option<usize>,
    /// The start.
    pub start: [f64; 2],
    /// The goal.
    pub goal: [f64; 2],
    /// Within `sim.arrival` of the goal.
    pub reached: bool,
    /// How the run ended ([`outcome_name`]).
    pub outcome: &'static str,
    /// The navigator's refusal, if it refused.
    pub error: Option<String>,
    /// Simulated time, s.
    pub time_s: f64,
    /// `|x − x_d|` at the end, m.
    pub final_distance: f64,
    /// Path length, m.
    pub path_length: f64,
    /// Largest speed, m/s.
    pub max_speed: f64,
    /// `√(2μ/m)` (dynamic law), m/s.
    pub speed_bound: Option<f64>,
    /// The robot disc's smallest clearance from the true walls and obstacles at the states, m.
    pub min_clearance: f64,
    /// The same along every held step (the Lipschitz bound of [`FloorRun::swept_clearance`]).
    pub swept_clearance: f64,
    /// The smallest `sd − δ` (the certified region's edge is at 0), m.
    pub layer_clearance: f64,
    /// `δ`, the boundary layer's width, m.
    pub delta: f64,
    /// Boundary elements of the harmonic map.
    pub elements: usize,
    /// Where the goal's image lies in the disk: `"solve"` or `"goal"` (`[floor_plan] centre`).
    pub centre: &'static str,
    /// The heading policy, `"auto"` or `"paper"` (`[robot] heading`), of either law.
    pub heading: &'static str,
    /// The `k` policy (`[field] k`, by its name), as in a star world's summary.
    #[serde(serialize_with = "crate::summary::by_name")]
    pub k_policy: harmonav::KPolicy,
    /// The damping policy of the dynamic law that ran (`[controller] damping`, by its name;
    /// `null` for the kinematic model), as in a star world's summary.
    #[serde(serialize_with = "crate::summary::by_name_if_any")]
    pub damping: Option<harmonav::DampingPolicy>,
    /// Seconds spent meshing and solving the harmonic map.
    pub setup_s: f64,
    /// `k` at the end.
    pub k: f64,
    /// Commands issued (one per control period).
    pub commands: usize,
    /// Escapes begun from rest points of the hold's slide (docs/maths.md §13.7).
    pub escapes: usize,
    /// The obstacles sensed, in order (exact sensing; empty with a lidar).
    pub discoveries: Vec<Discovery>,
    /// With a lidar: what its perception did (`null` otherwise), as in a star world's summary.
    pub perception: Option<PerceptionReport>,
    /// Every guarantee with what its monitor measured.
    pub guarantees: Vec<Guarantee>,
    /// What the file's movers did (`[[movers]]`; absent otherwise, so that a summary without
    /// movers is as before).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub movers: Option<MoverReport>,
    /// A differential drive's commands and arcs (`[robot] base = "diff"`; absent otherwise, so
    /// that a holonomic robot's summary is as before).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub diff: Option<DiffReport>,
    /// A file with `[[robots]]`: the other robots and the clearances between all of them, as
    /// a star world's summary (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fleet: Option<FleetReport>,
}

impl FloorSummary {
    /// The summary of `run`, the run of `model` (the file's by default) from `start`.
    #[must_use]
    pub fn new(
        prepared: &FloorPrepared,
        model: Option<Model>,
        start: Vector2<f64>,
        run: &FloorRun,
    ) -> Self {
        let sc = &prepared.scenario;
        let r = &sc.robot;
        let model = model.unwrap_or(r.model);
        let speed_bound = (model == Model::Dynamic).then(|| (2.0 * r.mu / r.mass).sqrt());
        let min_clearance = run.wall_clearance.min(run.obstacle_clearance);
        // A differential drive's arcs, judged along their length (`crate::unicycle`).
        let swept_clearance = run.diff.as_ref().map_or(run.swept_clearance, |d| {
            run.swept_clearance.min(d.swept_clearance)
        });
        let reached = run.outcome.reached();
        let mut guarantees = vec![
            Guarantee::new(
                Check::ReachedGoal {
                    final_distance: run.final_distance,
                    tolerance: sc.sim.arrival,
                    time_s: run.time,
                    max_time_s: sc.sim.max_time,
                },
                reached,
            ),
            Guarantee::new(
                Check::NoCollision {
                    min_clearance,
                    margin: r.margin,
                },
                min_clearance > 0.0 && min_clearance >= r.margin - MARGIN_TOLERANCE,
            ),
            Guarantee::new(
                Check::NoCollisionBetweenStates { swept_clearance },
                swept_clearance > 0.0,
            ),
        ];
        if let Some(d) = &run.diff {
            guarantees.push(d.bounds());
            guarantees.extend(d.accel_bounds());
        }
        if prepared.pixels.is_some() {
            guarantees.push(Guarantee::new(
                Check::NoCollisionWithMap {
                    min_pixel_clearance: run.pixel_clearance,
                },
                run.pixel_clearance > 0.0,
            ));
        }
        if let (Some(bound), Model::Dynamic) = (r.force_bound, model) {
            guarantees.push(crate::guarantee::force_within(run.max_force, bound));
        }
        guarantees.extend([
            Guarantee::new(
                Check::StayedInWorkspace {
                    min_boundary_distance: run.wall_clearance,
                },
                run.wall_clearance > 0.0 && run.outcome != Outcome::LeftWorkspace,
            ),
            Guarantee::new(
                Check::StayedInCertifiedRegion {
                    min_layer_clearance: run.layer_clearance,
                    delta: prepared.floor.delta(),
                },
                run.layer_clearance >= 0.0 && run.outcome != Outcome::LeftWorkspace,
            ),
            Guarantee::new(
                Check::Discoveries {
                    discoveries: run
                        .discoveries
                        .iter()
                        .map(|d| (d.obstacle.clone(), d.time_s))
                        .collect(),
                },
                true,
            ),
        ]);
        if let Some(bound) = speed_bound {
            guarantees.push(Guarantee::new(
                Check::SpeedBelowBound {
                    max_speed: run.max_speed,
                    bound,
                },
                run.max_speed < bound,
            ));
        }
        // The energy monitor of a star world's held loop, on the built-in step (issue 51).
        if let Some((raw, beyond)) = run.energy_rise {
            guarantees.push(Guarantee::new(
                Check::EnergyNonIncreasing {
                    largest_rise: raw.max(0.0),
                    beyond_tolerance: beyond.max(0.0),
                },
                beyond <= 0.0,
            ));
        }
        // rapier's own checks, as in a star world (`crate::rapier`): no contact event, and
        // the deviation from the built-in run (measured, not judged).
        if let Some(contacts) = run.contacts {
            guarantees.push(Guarantee::new(
                Check::PhysicsContacts { contacts },
                contacts == 0,
            ));
        }
        if let Some(max_deviation) = run.max_deviation {
            guarantees.push(Guarantee::new(
                Check::PhysicsDeviation { max_deviation },
                true,
            ));
        }
        if let Some((_, checks)) = &run.perception {
            guarantees.extend(checks.iter().cloned());
        }
        if let Some(report) = &run.movers {
            guarantees.push(crate::movers::judged(report, r.margin));
        }
        if let Some(fleet) = &run.fleet {
            let others_unsafe = fleet.others.iter().filter(|o| !o.safe).count();
            let robots = fleet.others.len() + 1;
            guarantees.push(crate::movers::fleet_judged(fleet, robots, others_unsafe));
        }
        Self {
            name: sc.name.clone(),
            model,
            physics: run.physics,
            physics_contacts: run.contacts,
            start: [start.x, start.y],
            goal: r.goal,
            reached,
            outcome: outcome_name(&run.outcome),
            error: run.error.as_ref().map(ToString::to_string),
            time_s: run.time,
            final_distance: run.final_distance,
            path_length: run.path,
            max_speed: run.max_speed,
            speed_bound,
            min_clearance,
            swept_clearance,
            layer_clearance: run.layer_clearance,
            delta: prepared.floor.delta(),
            elements: prepared.floor.map().elements().len(),
            centre: prepared.floor.centre_policy().as_str(),
            heading: r.heading.as_str(),
            k_policy: sc.field.k,
            damping: (model == Model::Dynamic).then_some(sc.controller.damping),
            setup_s: prepared.setup_seconds,
            k: run.k,
            commands: run.commands,
            escapes: run.escapes,
            discoveries: run.discoveries.clone(),
            perception: run.perception.as_ref().map(|(r, _)| r.clone()),
            guarantees,
            movers: run.movers.clone(),
            diff: run.diff.clone(),
            fleet: run.fleet.clone(),
        }
    }

    /// Whether every guarantee but arrival (and a lidar's `scans-accepted`: a refused scan
    /// stops the robot, it does not endanger it) held, as a star world's
    /// [`crate::summary::Summary::safe`].
    #[must_use]
    pub fn safe(&self) -> bool {
        self.guarantees.iter().all(|g| {
            g.passed
                || matches!(
                    g.kind(),
                    crate::guarantee::Kind::ReachedGoal | crate::guarantee::Kind::ScansAccepted
                )
        })
    }

    /// Whether every guarantee held, arrival included.
    #[must_use]
    pub fn all_passed(&self) -> bool {
        self.guarantees.iter().all(|g| g.passed)
    }
}

/// The certificate of the scenario's map on `W_δ` ([`harmonav::FloorMap::certify`]) with at most
/// `max_evaluations` cells.
///
/// # Errors
/// The certificate's own error, as text.
pub fn certificate(
    prepared: &FloorPrepared,
    max_evaluations: usize,
) -> Result<Certificate, String> {
    prepared
        .floor
        .certify(max_evaluations)
        .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use harmonav_scenario::floorplan::FloorScenario;

    use super::*;

    /// The energy monitor on a floor plan (issue 51, item 2): the dynamic law's run of the L
    /// room is judged, `V` never rising beyond the step's own error; a controller that pumps
    /// energy in (the law's continuous force plus `2m·ẋ`) fails it (the negative control);
    /// the kinematic law has no `V` and is not judged.
    #[test]
    fn the_energy_monitor_judges_the_dynamic_law_and_catches_a_pump() {
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/floorplans/l-room.toml");
        let p = FloorScenario::load(&path).unwrap();
        let start = Vector2::from(p.scenario.robot.start);
        let law = run(&p, Some(Model::Dynamic), start).unwrap();
        let (_, beyond) = law.energy_rise.expect("the dynamic law is judged");
        assert!(beyond <= 0.0, "{beyond:e}");
        assert!(
            matches!(law.outcome, Outcome::Reached { .. }),
            "{:?}",
            law.outcome
        );
        let pump = |nav: &FloorNavigator, x: Vector2<f64>, v: Vector2<f64>| {
            nav.evaluate(x, v).map_or(Vector2::zeros(), |e| e.command) + 2.0 * v
        };
        let pumped = fly(
            &p,
            Some(Model::Dynamic),
            start,
            Some(&pump),
            &mut |held| held.euler(),
            None,
        )
        .unwrap();
        let (_, beyond) = pumped.energy_rise.expect("a custom controller is judged");
        assert!(beyond > 0.0, "the pump was not caught: {beyond:e}");
        let kinematic = run(&p, Some(Model::Kinematic), start).unwrap();
        assert_eq!(kinematic.energy_rise, None);
    }
}
