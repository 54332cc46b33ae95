//! The cost of one command of a differential-drive base (issue 53: "≤ 30 µs per command
//! (release Rust)") and of a command with 20 movers (issue 54), in the worlds shared by the
//! criterion bench (`cargo bench -p harmonav-bench --bench diff_command`) and `cargo xtask
//! bench --only diff_command` (docs/benchmarks.md, "Per-call cost").
//!
//! The workload is what a robot asks: the poses of a closed-loop flight (each `(v, ω)` of
//! [`Navigator::command_pose`] held on its exact arc, [`unicycle_arc`]) from the start to the
//! goal, replayed in order on a fresh copy of the navigator, so that a base with acceleration
//! limits sees the same last command as in the flight and gives the same commands.
//!
//! - [`disc_world`]: a seeded disc world (a 5 m disc, 10 discs of radius 0.2–0.5 m), a robot of
//!   radius 0.18 m with a 0.05 m margin at 10 Hz, `v_max` 0.5 m/s, `omega_max` 2 rad/s (the
//!   issue's setting), and with `accel` the limits [`A_MAX`], [`ALPHA_MAX`].
//! - [`floor_plan`]: `scenarios/diff/floor-l-room.toml` (the L room, its two obstacles known),
//!   the file's robot and start yaw.
//! - [`ring`]: 20 movers (radius 0.3 m, 1 m/s) about a position, within reach of the period or
//!   20 m away, given by [`Navigator::set_movers`] before each command.

use std::f64::consts::PI;
use std::path::Path;

use harmonav::transform::random::Rng;
use harmonav::{
    Base, FloorNavigator, Law, Mover, Navigator, Options, StarShape, Vector2, World, unicycle_arc,
};

/// The target for one `command_pose`, µs (release build).
pub const TARGET_US: f64 = 30.0;
/// The target for a command with 20 movers within reach, µs (issue 54, docs/movers.md).
pub const MOVERS_NEAR_TARGET_US: f64 = 20.0;
/// The target for 20 movers out of reach: at most this much more than without, µs.
pub const MOVERS_FAR_EXTRA_US: f64 = 1.0;

/// The robot of [`disc_world`]: radius, margin (m), control period (s), `v_max` (m/s),
/// `omega_max` (rad/s).
pub const ROBOT: (f64, f64, f64, f64, f64) = (0.18, 0.05, 0.1, 0.5, 2.0);
/// The acceleration limit of [`disc_world`]'s and [`floor_plan`]'s bases with `accel`, m/s².
pub const A_MAX: f64 = 0.5;
/// The turn-rate acceleration limit with `accel`, rad/s².
pub const ALPHA_MAX: f64 = 4.0;
/// The most periods a flight lasts (120 s at 10 Hz).
pub const MAX_PERIODS: usize = 1200;

/// A pose `(x, yaw)`.
pub type PoseXY = (Vector2<f64>, f64);

/// A holonomic robot's state `(x, ẋ)`.
pub type State = (Vector2<f64>, Vector2<f64>);

/// A navigator and the poses of its closed-loop flight.
#[derive(Clone, Debug)]
pub struct Flight<W: World> {
    /// The navigator before the flight (clone it for each replay).
    pub nav: Navigator<W>,
    /// The pose at each command of the flight, in order.
    pub poses: Vec<PoseXY>,
    /// Whether the flight arrived within 1 cm of the goal.
    pub arrived: bool,
}

fn base(accel: bool) -> Base {
    let (_, _, _, v_max, omega_max) = ROBOT;
    let base = Base::diff(v_max, omega_max);
    if accel {
        base.with_accel(A_MAX, ALPHA_MAX)
    } else {
        base
    }
}

/// Flies `nav` (a copy) from `start` to its goal for at most [`MAX_PERIODS`] of `h` (its
/// control period) and records the poses at which it commanded.
///
/// # Errors
/// A command is refused (the message names the pose).
pub fn fly<W: World + Clone>(
    nav: &Navigator<W>,
    start: PoseXY,
    h: f64,
) -> Result<Flight<W>, String> {
    let mut run = nav.clone();
    let goal = run.goal();
    let (mut x, mut yaw) = start;
    let mut poses = Vec::new();
    let mut arrived = false;
    for _ in 0..MAX_PERIODS {
        if (x - goal).norm() < 0.01 {
            arrived = true;
            break;
        }
        poses.push((x, yaw));
        let c = run
            .command_pose(x, yaw)
            .map_err(|e| format!("command_pose at {x:?}, {yaw}: {e}"))?;
        (x, yaw) = unicycle_arc(x, yaw, c.v, c.omega, h);
    }
    Ok(Flight {
        nav: nav.clone(),
        poses,
        arrived,
    })
}

/// The seeded disc world (module docs): the navigator, every disc known, and its flight from
/// `(−4, 0.05)` at a seeded heading to `(4, 0)`.
///
/// # Errors
/// A command of the flight is refused.
///
/// # Panics
/// Never: the world is valid.
pub fn disc_world(accel: bool) -> Result<Flight<harmonav::StarWorld>, String> {
    let (radius, margin, h, v_max, _) = ROBOT;
    let mut rng = Rng::new(1003);
    let (start, goal) = (Vector2::new(-4.0, 0.05), Vector2::new(4.0, 0.0));
    let mut discs: Vec<(Vector2<f64>, f64)> = Vec::new();
    while discs.len() < 10 {
        let c = rng.point(4.0);
        let r = rng.uniform(0.2, 0.5);
        let clear = c.norm() + r + 0.5 < 5.0
            && (c - start).norm() > r + 0.8
            && (c - goal).norm() > r + 0.8
            && discs.iter().all(|(c2, r2)| (c - c2).norm() - r - r2 > 0.5);
        if clear {
            discs.push((c, r));
        }
    }
    let yaw = rng.uniform(-PI, PI);
    let options = Options::default()
        .with_robot(radius, margin)
        .with_control_period(h)
        .with_v_max(v_max)
        .with_base(base(accel));
    let boundary = StarShape::circle(Vector2::zeros(), 5.0).expect("a valid circle");
    let mut nav =
        Navigator::new(boundary, goal, Law::kinematic(1.0), options).expect("a valid world");
    for (c, r) in &discs {
        nav.add_obstacle(StarShape::circle(*c, *r).expect("a valid circle"))
            .expect("a valid obstacle");
    }
    fly(&nav, (start, yaw), h)
}

/// `scenarios/diff/floor-l-room.toml` (`root` the repository), its obstacles known: the
/// navigator and its flight from the file's start and yaw.
///
/// # Errors
/// The file does not load, or a command of the flight is refused.
pub fn floor_plan(root: &Path, accel: bool) -> Result<Flight<harmonav::FloorWorld>, String> {
    let file = root.join("scenarios/diff/floor-l-room.toml");
    let p = harmonav_scenario::floorplan::FloorScenario::load(&file).map_err(|e| e.to_string())?;
    let robot = &p.scenario.robot;
    let (_, _, h, v_max, _) = ROBOT;
    let options = Options::default()
        .with_robot(robot.radius, robot.margin)
        .with_control_period(h)
        .with_v_max(v_max)
        .with_base(base(accel));
    let goal = Vector2::from(robot.goal);
    let mut nav = FloorNavigator::new(p.floor.clone(), goal, Law::kinematic(1.0), options)
        .map_err(|e| e.to_string())?;
    for o in &p.obstacles {
        nav.add_obstacle(o.clone()).map_err(|e| e.to_string())?;
    }
    fly(&nav, (Vector2::from(robot.start), PI / 2.0), h)
}

/// 20 movers of radius 0.3 m and speed bound 1 m/s evenly round `x`: `near`, 0.5 to 3 cm
/// outside the distance at which they enter the row of a robot inflated by `inflation`
/// (within reach of the period: the filter projects); else 20 m further out (out of reach:
/// the rows are checked and the command kept).
#[must_use]
pub fn ring(x: Vector2<f64>, inflation: f64, near: bool) -> Vec<Mover> {
    let reach = inflation + 0.3;
    (0..20)
        .map(|j| {
            let a = std::f64::consts::TAU * f64::from(j) / 20.0;
            let d = if near {
                reach + 0.005 + 0.025 * f64::from(j % 5) / 4.0
            } else {
                20.0 + reach
            };
            Mover::new(x + d * Vector2::new(a.cos(), a.sin()), 0.3, 1.0)
        })
        .collect()
}

/// Replays `flight` once on a copy of its navigator (every pose in order, `movers` set before
/// each command when given). Returns the number of commands that moved (`v > 0`).
///
/// # Panics
/// A command that the flight made is refused on replay (never: the navigator is deterministic).
pub fn replay<W: World + Clone>(
    nav: &mut Navigator<W>,
    poses: &[PoseXY],
    movers: Option<&[Vec<Mover>]>,
) -> usize {
    let mut moved = 0;
    for (i, &(x, yaw)) in poses.iter().enumerate() {
        if let Some(m) = movers {
            nav.set_movers(&m[i]).expect("valid movers");
        }
        let c = nav.command_pose(x, yaw).expect("the flight's command");
        moved += usize::from(c.v > 0.0);
    }
    moved
}

/// The seeded world of `cargo xtask bench`'s control-step figures: 8 mixed-shape obstacles
/// (circles, ellipses, polygons, stars; seed 6) and 1024 states `(x, ẋ)` in its free space.
#[must_use]
pub fn control_workspace() -> (harmonav::transform::Workspace, Vec<State>) {
    use harmonav::transform::random::{self, Kind};
    let kinds = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
    let mut rng = Rng::new(6);
    let ws = random::workspace(&mut rng, 8, &kinds, Kind::Star, 0.15);
    let states = (0..1024)
        .map(|_| (random::free_point(&mut rng, &ws, 1e-3), rng.point(1.0)))
        .collect();
    (ws, states)
}

/// The world of `cargo xtask bench`'s `navigator_command_ns_m6*` figures (issue 54's mover
/// figures): [`control_workspace`], its first 6 obstacles given to a kinematic navigator with
/// the default options.
///
/// # Panics
/// Never: the world is valid.
#[must_use]
pub fn control_world() -> (Navigator, Vec<State>) {
    let (ws, states) = control_workspace();
    let mut nav = Navigator::new(
        ws.boundary().clone(),
        ws.destination(),
        Law::kinematic(1.0),
        Options::default(),
    )
    .expect("valid benchmark world");
    for o in &ws.obstacles()[..6] {
        nav.add_obstacle(o.clone())
            .expect("valid benchmark obstacle");
    }
    (nav, states)
}
