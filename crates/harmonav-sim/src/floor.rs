//! The floor-plan loop (issue 25, `docs/maths.md` §13): the user's loop around a
//! [`harmonav::FloorNavigator`] on a [`FloorPrepared`] scenario, with its monitors (no
//! collision with the true walls and obstacles, at the states and along the steps, never
//! leaving, staying in the certified region, arrival within a stated threshold), its
//! [`FloorSummary`] (`harmonav run` on a floor plan), and the map's certificate.

use harmonav::control::Branch;
use harmonav::perception::sim::Enclosure;
use harmonav::{Controller, FloorNavigator, Law, NavError, Options, StarShape};
use harmonav_harmonic::Certificate;
use harmonav_scenario::floorplan::FloorPrepared;
use harmonav_scenario::{LidarSensor, Model, ShapeSpec};
use nalgebra::Vector2;
use serde::Serialize;

use crate::guarantee::MARGIN_TOLERANCE;
use crate::guarantee::{Check, Guarantee};
use crate::movers::{MoverReport, MoverWorld};
use crate::scanner::{Scanner, Scene};
use crate::summary::{PerceptionReport, Physics};
use crate::trace::{Discovery, Event, MoverFrame, Sample, frame_due, recorded_velocity};
use crate::trajectory::{Keep, Trajectory};
use crate::unicycle::{Diff, DiffReport};

/// How a floor-plan run ended.
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

impl FloorEnding {
    /// The name for JSON and tables.
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

/// What one run measured.
#[derive(Clone, Debug)]
pub struct FloorRun {
    /// How it ended.
    pub ending: FloorEnding,
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
    let lidar = prepared
        .lidar
        .map(|(l, rho)| (l.for_law(&law, &options), rho));
    let options = match &lidar {
        Some((l, rho)) => l.options(options, *rho),
        None => options,
    };
    let nav = FloorNavigator::new(prepared.floor.clone(), Vector2::from(r.goal), law, options)?;
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
            let (x, v) = held.euler();
            states.push(x);
            (x, v)
        },
        None,
    )?;
    Ok((run, states))
}

/// A controller other than the law on a floor plan: `(navigator, x, ẋ) → command` (the
/// velocity for the kinematic model, the force for the dynamic one).
pub type FloorLaw<'a> = &'a dyn Fn(&FloorNavigator, Vector2<f64>, Vector2<f64>) -> Vector2<f64>;

/// A position and a velocity.
pub(crate) type State = (Vector2<f64>, Vector2<f64>);

/// One control period of the loop: the state at its start, the command held over it, the
/// law and the period. An integrator (`hold` of [`fly`]) returns the state at its end.
pub(crate) struct Held<'a> {
    /// The law (the model, and the dynamic law's mass).
    pub controller: &'a Controller,
    /// The control period, s.
    pub h: f64,
    /// Position at the period's start.
    pub x: Vector2<f64>,
    /// Velocity at the period's start.
    pub v: Vector2<f64>,
    /// The command held: velocity (kinematic) or force (dynamic).
    pub command: Vector2<f64>,
}

impl Held<'_> {
    /// The built-in step: `x += h·u` (kinematic, `ẋ = u`), or `v += h·f/m, x += h·v` (dynamic,
    /// semi-implicit Euler). Returns the position and velocity at the period's end.
    #[must_use]
    pub(crate) fn euler(&self) -> State {
        match self.controller {
            Controller::Kinematic(_) => (self.x + self.h * self.command, self.command),
            Controller::Dynamic(law) => {
                let v = self.v + self.h * self.command / law.mass();
                (self.x + self.h * v, v)
            }
        }
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

/// The loop of [`run`] with its integrator `hold` (the built-in step, or rapier's), with
/// `custom` a controller other than the law, and with `observer` the run's events as they are
/// made ([`run_observed`]; the samples' evaluations are made only for an observer).
pub(crate) fn fly(
    prepared: &FloorPrepared,
    model: Option<Model>,
    start: Vector2<f64>,
    custom: Option<FloorLaw<'_>>,
    hold: &mut dyn FnMut(&Held) -> State,
    mut observer: Option<&mut dyn FnMut(Event<'_>)>,
) -> Result<FloorRun, NavError> {
    let r = &prepared.scenario.robot;
    let goal = Vector2::from(r.goal);
    let (mut nav, lidar) = navigator_and_lidar(prepared, model)?;
    let mut scanner = lidar.map(Scanner::new);
    let walls = scanner.as_ref().map(|_| nav.walls().clone());
    let mut yaw = 0.0;
    let h = nav.control_period();
    let sim = prepared.scenario.sim;
    let steps = (sim.max_time / h).ceil() as usize;
    let floor = &prepared.floor;
    let (mut x, mut vel) = (start, Vector2::zeros());
    let mut known = vec![false; prepared.obstacles.len()];
    let mut kept = Trajectory::default();
    let mut out = FloorRun {
        ending: FloorEnding::TimedOut,
        time: 0.0,
        wall_clearance: f64::INFINITY,
        pixel_clearance: f64::INFINITY,
        obstacle_clearance: f64::INFINITY,
        swept_clearance: f64::INFINITY,
        layer_clearance: f64::INFINITY,
        final_distance: (x - goal).norm(),
        path: 0.0,
        max_speed: 0.0,
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
    };
    // The file's movers (docs/movers.md §8): reported before every command of the law.
    let mut world = MoverWorld::new(&prepared.scenario.movers, r.radius);
    let mass = match nav.controller() {
        Controller::Dynamic(law) => law.mass(),
        Controller::Kinematic(_) => 1.0,
    };
    // The disc's clearance at the previous state and the length of the step since.
    let mut last: Option<(f64, f64)> = None;
    // The time of the last state handed to the observer: a state the loop goes on from is
    // handed after its scan and discoveries and with the command held from it (the kinematic
    // robot's velocity), the state it ended at after the loop.
    let mut observed: Option<f64> = None;
    let kinematic = matches!(nav.controller(), Controller::Kinematic(_));
    // How the last command was formed, for the movers' frames.
    let mut last_mode: Option<&'static str> = None;
    // A differential drive (`crate::unicycle`): its heading, and the monitors of its arcs. A
    // custom controller or rapier (`hold` other than the built-in step) drives the
    // holonomic robot only.
    let mut diff = match custom {
        None => Diff::of(prepared.base(), prepared.start_yaw()),
        Some(_) => None,
    };
    if let Some(u) = &diff {
        yaw = u.yaw;
    }
    // The body disc's clearance from the true walls, obstacles and (on a map) pixels.
    let truth_clearance = |p: Vector2<f64>| {
        let pixels = prepared
            .pixels
            .as_ref()
            .map_or(f64::INFINITY, |px| px.signed_distance(p) - r.radius);
        prepared
            .obstacles
            .iter()
            .map(|o| o.signed_distance(p) - r.radius)
            .fold(floor.wall_distance(p) - r.radius, f64::min)
            .min(pixels)
    };
    for n in 0..=steps {
        out.time = n as f64 * h;
        // Monitors on the truth.
        if !floor.walls().contains(x) {
            out.ending = FloorEnding::Left;
            break;
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
        if let Some((before, step)) = last {
            out.swept_clearance = out.swept_clearance.min(0.5 * (before + clearance - step));
        }
        if out.wall_clearance <= 0.0 || out.obstacle_clearance <= 0.0 || out.pixel_clearance <= 0.0
        {
            out.ending = FloorEnding::Collision;
            break;
        }
        out.final_distance = (x - goal).norm();
        if out.final_distance < sim.arrival {
            out.ending = FloorEnding::Reached;
            break;
        }
        if n == steps {
            break;
        }
        // Perception: a scan when one is due, or a true obstacle within range of the robot's
        // disc becomes known.
        let mut discovered = false;
        if let (Some(scanner), Some(walls)) = (scanner.as_mut(), walls.as_ref())
            && scanner.due(out.time)
        {
            let scene = Scene {
                obstacles: &prepared.obstacles,
                enclosure: Enclosure::Walls(walls),
            };
            match scanner.scan(&mut nav, scene, out.time, x, yaw) {
                Ok(record) => {
                    discovered = record.perceived.is_some();
                    if let Some(o) = observer.as_mut() {
                        o(Event::Scan(&record));
                    }
                }
                Err(e) => {
                    out.ending = FloorEnding::Refused;
                    out.error = Some(e);
                    break;
                }
            }
        }
        let exact = if scanner.is_some() {
            &[][..]
        } else {
            &prepared.obstacles[..]
        };
        for (i, (o, seen)) in exact.iter().zip(&mut known).enumerate() {
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
                if let Some(o) = observer.as_mut() {
                    o(Event::Discovery(&discovery));
                }
                out.discoveries.push(discovery);
            }
        }
        // Sampled before the command (which moves the navigator's state on).
        let pending = observer.is_some().then(|| sample(&nav, out.time, x, vel));
        kept.push(
            [x.x, x.y],
            if discovered { Keep::Pinned } else { Keep::Grid },
        );
        if !world.is_empty() && frame_due(&out.mover_frames, out.time) {
            let frame = world.frame(out.time, x, last_mode, h);
            if let Some(o) = observer.as_mut() {
                o(Event::Movers(&frame));
            }
            out.mover_frames.push(frame);
        }
        if custom.is_none() && !world.is_empty() {
            nav.set_movers(world.reports())?;
        }
        if let Some(u) = diff.as_mut() {
            // The arc of `(v, ω)` held for `h`, judged along its length (no movers with a
            // differential drive: the file is refused).
            let c = match nav.command_pose(x, u.yaw) {
                Ok(c) => c,
                Err(e) => {
                    out.ending = FloorEnding::Refused;
                    out.error = Some(e);
                    break;
                }
            };
            out.escapes = nav.escapes();
            out.commands += 1;
            if let (Some(o), Some(mut s)) = (observer.as_mut(), pending) {
                // Its motion `v·e(θ)` and heading, not the law's `u`.
                (s.v, s.yaw) = ([vel.x, vel.y], Some(u.yaw));
                o(Event::State(&s));
                observed = Some(out.time);
            }
            let next;
            (next, vel) = u.period_in(&truth_clearance, r.margin, x, &c, h);
            yaw = u.yaw;
            out.max_speed = out.max_speed.max(vel.norm());
            // The arc's length: a chord is never longer, so the Lipschitz bound stays valid.
            let length = c.v.abs() * h;
            out.path += length;
            last = Some((clearance, length));
            x = next;
            continue;
        }
        let mut mode = None;
        let command = match custom {
            Some(law) => law(&nav, x, vel),
            None => match nav.command(x, vel) {
                Ok(c) => {
                    out.escapes = nav.escapes();
                    mode = Some(c.mode);
                    c.value
                }
                // The reported bodies overlap: no certified command; the robot stops.
                Err(NavError::InMover { .. }) if !world.is_empty() => {
                    if kinematic {
                        Vector2::zeros()
                    } else {
                        -mass * vel / h
                    }
                }
                Err(e) => {
                    out.ending = FloorEnding::Refused;
                    out.error = Some(e);
                    break;
                }
            },
        };
        out.commands += 1;
        if let (Some(o), Some(mut s)) = (observer.as_mut(), pending) {
            if kinematic {
                s.v = [command.x, command.y];
            }
            o(Event::State(&s));
            observed = Some(out.time);
        }
        let next;
        (next, vel) = hold(&Held {
            controller: nav.controller(),
            h,
            x,
            v: vel,
            command,
        });
        out.max_speed = out.max_speed.max(vel.norm());
        let step = (next - x).norm();
        if step > 0.0 {
            yaw = (next.y - x.y).atan2(next.x - x.x);
        }
        out.path += step;
        last = Some((clearance, step));
        if !world.is_empty() {
            let certified = mode
                .as_ref()
                .is_some_and(|m| !matches!(m, harmonav::Mode::Overwhelmed { .. }));
            world.count(mode.as_ref());
            last_mode = Some(mode.as_ref().map_or("refused", harmonav::Mode::as_str));
            world.period(x, next, h, certified);
        }
        x = next;
    }
    out.movers = (!world.is_empty()).then(|| world.report.clone());
    if let Some(o) = observer.as_mut()
        && observed != Some(out.time)
    {
        let mut s = sample(&nav, out.time, x, vel);
        if let Some(u) = &diff {
            (s.v, s.yaw) = ([vel.x, vel.y], Some(u.yaw));
        }
        o(Event::State(&s));
    }
    out.diff = diff.map(|u| u.report);
    kept.push([x.x, x.y], Keep::Pinned);
    out.positions = kept.into_samples();
    out.k = nav.k();
    out.perception = scanner.map(|s| s.judge(&nav, &prepared.obstacles));
    out.perceived = nav.perceived().map(|(_, p)| p.shape().clone()).collect();
    Ok(out)
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
    /// How the run ended ([`FloorEnding::as_str`]).
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
        let reached = run.ending == FloorEnding::Reached;
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
        guarantees.extend([
            Guarantee::new(
                Check::StayedInWorkspace {
                    min_boundary_distance: run.wall_clearance,
                },
                run.wall_clearance > 0.0 && run.ending != FloorEnding::Left,
            ),
            Guarantee::new(
                Check::StayedInCertifiedRegion {
                    min_layer_clearance: run.layer_clearance,
                    delta: prepared.floor.delta(),
                },
                run.layer_clearance >= 0.0 && run.ending != FloorEnding::Left,
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
        Self {
            name: sc.name.clone(),
            model,
            physics: run.physics,
            physics_contacts: run.contacts,
            start: [start.x, start.y],
            goal: r.goal,
            reached,
            outcome: run.ending.as_str(),
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
        }
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
