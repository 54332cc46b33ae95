//! The user's own loop, measured: seeded disc worlds and a fixed-step flight through them with
//! the navigator, its perception and its integrator as a user writes them (the README's loop).
//! The crate's tests assert on these functions and `cargo xtask verify` runs them on 300
//! worlds at every documented rate, so the two cannot drift apart (`docs/maths.md` §10).

pub mod lidar;

use harmonav_transform::StarShape;
use harmonav_transform::random::Rng;
use nalgebra::Vector2;

use crate::{Law, Mode, NavError, Navigator, Options};

/// A world of the sampled-data suite: discs in a disc, with a start and a goal.
#[derive(Clone, Debug)]
pub struct DiscWorld {
    /// The workspace boundary, a disc of radius [`DISC_WORLD_RADIUS`] about the origin.
    pub boundary: StarShape,
    /// The true obstacles, unknown to the robot until its perception reports them.
    pub obstacles: Vec<StarShape>,
    /// The start.
    pub start: Vector2<f64>,
    /// The goal.
    pub goal: Vector2<f64>,
}

/// The radius of a [`disc_world`]'s boundary, m.
pub const DISC_WORLD_RADIUS: f64 = 5.0;

/// The seeded world `seed` of the sampled-data suite (the hostile round of issue 23): 4–10
/// discs of radius 0.2–0.7 m in a disc of radius 5 m, with gaps of at least 0.4 m between them
/// and to the boundary; the start and the goal at least 0.4 m from every shape and at least
/// 3 m apart. Deterministic.
pub fn disc_world(seed: u64) -> DiscWorld {
    let mut rng = Rng::new(0x5A3D_0000 ^ seed);
    let gap = 0.4;
    let m = 4 + rng.below(7);
    let mut discs: Vec<(Vector2<f64>, f64)> = Vec::with_capacity(m);
    while discs.len() < m {
        let r = rng.uniform(0.2, 0.7);
        let c = rng.point(DISC_WORLD_RADIUS);
        let clear_of_wall = c.norm() + r + gap <= DISC_WORLD_RADIUS;
        if clear_of_wall
            && discs
                .iter()
                .all(|&(c2, r2)| (c - c2).norm() >= r + r2 + gap)
        {
            discs.push((c, r));
        }
    }
    let clear = |p: Vector2<f64>| {
        p.norm() + gap <= DISC_WORLD_RADIUS && discs.iter().all(|&(c, r)| (p - c).norm() >= r + gap)
    };
    let mut free = || loop {
        let p = rng.point(DISC_WORLD_RADIUS);
        if clear(p) {
            return p;
        }
    };
    let (start, goal) = loop {
        let (s, g) = (free(), free());
        if (s - g).norm() >= 3.0 {
            break (s, g);
        }
    };
    let circle = |c: Vector2<f64>, r: f64| {
        StarShape::circle(c, r).expect("a disc of positive radius within the length limit")
    };
    DiscWorld {
        boundary: circle(Vector2::zeros(), DISC_WORLD_RADIUS),
        obstacles: discs.iter().map(|&(c, r)| circle(c, r)).collect(),
        start,
        goal,
    }
}

/// How the robot integrates the held command (the user's integrator).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Integrator {
    /// `x += h·u` (kinematic law), or `v += h·f/m; x += h·v` (dynamic law).
    SemiImplicitEuler,
    /// The exact hold of the force for `h`: `x += h·v + h²f/(2m); v += h·f/m` (dynamic law;
    /// for the kinematic law the same as semi-implicit Euler).
    ExactHold,
}

impl Integrator {
    /// Holds the command `c` of `law` for `h` from the state `(x, v)`: the kinematic robot
    /// moves `x += h·c` (and `v = c`), the dynamic one as the integrator says.
    pub fn advance(
        self,
        law: Law,
        h: f64,
        c: Vector2<f64>,
        x: &mut Vector2<f64>,
        v: &mut Vector2<f64>,
    ) {
        match (law, self) {
            (Law::Kinematic { .. }, _) => {
                *x += h * c;
                *v = c;
            }
            (Law::Dynamic { mass, .. }, Integrator::SemiImplicitEuler) => {
                *v += h * c / mass;
                *x += h * *v;
            }
            (Law::Dynamic { mass, .. }, Integrator::ExactHold) => {
                *x += h * *v + 0.5 * h * h * c / mass;
                *v += h * c / mass;
            }
        }
    }
}

/// What a [`fly`] measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Flight {
    /// Within [`GOAL_TOLERANCE`] of the goal before [`MAX_TIME`].
    pub reached: bool,
    /// The time flown, s.
    pub time: f64,
    /// The smallest distance from the robot's disc to a true shape (or the boundary), m:
    /// negative if it touched one.
    pub true_clearance: f64,
    /// The smallest distance from the robot's centre to a grown shape (radius + margin), m:
    /// negative if it entered one.
    pub grown_clearance: f64,
    /// The fastest speed, m/s.
    pub max_speed: f64,
    /// Commands shortened by the hold, and steps from rest ([`Mode::FromRest`]).
    pub capped: usize,
    /// Commands out of the margin band.
    pub recoveries: usize,
    /// The error that ended the flight, if one did (a non-finite command included).
    pub error: Option<NavError>,
    /// Not reached, and the last 10 s moved the robot less than 1 cm.
    pub stalled: bool,
}

impl Flight {
    /// No true shape touched, no grown shape entered, every command finite and accepted.
    pub fn safe(&self) -> bool {
        self.true_clearance > 0.0 && self.grown_clearance >= 0.0 && self.error.is_none()
    }
}

/// The goal tolerance of [`fly`], m.
pub const GOAL_TOLERANCE: f64 = 0.01;

/// The longest flight, s.
pub const MAX_TIME: f64 = 120.0;

/// The range within which [`fly`]'s perception reports an obstacle, m (distance from the
/// robot's centre to the true outline).
pub const PERCEPTION_RANGE: f64 = 1.0;

/// The user's own loop in `world` under `law` and `options`, holding each command for `h`
/// with `integrator`. Perception reports every true obstacle whose outline comes within
/// [`PERCEPTION_RANGE`] of the robot, once. The flight ends at the goal, at [`MAX_TIME`], or
/// at the first error, and measures every step's state against the truth.
pub fn fly(
    world: &DiscWorld,
    law: Law,
    options: Options,
    h: f64,
    integrator: Integrator,
) -> Result<Flight, NavError> {
    let options = options.with_control_period(h);
    let mut nav = Navigator::new(world.boundary.clone(), world.goal, law, options)?;
    let (mut x, mut v) = (world.start, Vector2::zeros());
    let mut known = vec![false; world.obstacles.len()];
    let mut flight = Flight {
        reached: false,
        time: 0.0,
        true_clearance: f64::INFINITY,
        grown_clearance: f64::INFINITY,
        max_speed: 0.0,
        capped: 0,
        recoveries: 0,
        error: None,
        stalled: false,
    };
    let inflation = options.inflation();
    let (mut anchor, mut anchor_time) = (x, 0.0);
    let steps = (MAX_TIME / h).ceil() as usize;
    for step in 0..steps {
        for (o, seen) in world.obstacles.iter().zip(&mut known) {
            if !*seen && o.signed_distance(x) < PERCEPTION_RANGE {
                if let Err(e) = nav.add_obstacle(o.clone()) {
                    flight.error = Some(e);
                    return Ok(flight);
                }
                *seen = true;
            }
        }
        if (x - world.goal).norm() < GOAL_TOLERANCE {
            flight.reached = true;
            return Ok(flight);
        }
        let command = match nav.command(x, v) {
            Ok(c) => c,
            Err(e) => {
                flight.error = Some(e);
                return Ok(flight);
            }
        };
        match command.mode {
            Mode::Law => {}
            Mode::Capped { .. } => flight.capped += 1,
            Mode::Recovering(_) => flight.recoveries += 1,
            // Only a floor plan's navigator escapes; a step from rest counts as a capped one.
            Mode::Escaping => {}
            Mode::FromRest => flight.capped += 1,
            // These flights stop at a refused scan, before any halted command, and have no
            // movers.
            Mode::Halted
            | Mode::Yielding { .. }
            | Mode::Overwhelmed { .. }
            | Mode::Bounded { .. }
            | Mode::Braking => {}
        }
        let c = command.value;
        integrator.advance(law, h, c, &mut x, &mut v);
        flight.time = (step + 1) as f64 * h;
        let true_gap = world
            .obstacles
            .iter()
            .map(|o| o.signed_distance(x))
            .fold(-world.boundary.signed_distance(x), f64::min)
            - options.radius;
        flight.true_clearance = flight.true_clearance.min(true_gap);
        // Every obstacle, known or not (the grown shape of a disc is the disc of radius
        // r + radius + margin, so this is exact).
        let grown_gap = world
            .obstacles
            .iter()
            .map(|o| o.signed_distance(x))
            .fold(-world.boundary.signed_distance(x), f64::min)
            - inflation;
        flight.grown_clearance = flight.grown_clearance.min(grown_gap);
        flight.max_speed = flight.max_speed.max(v.norm());
        if (x - anchor).norm() >= 0.01 {
            (anchor, anchor_time) = (x, flight.time);
        }
    }
    flight.stalled = flight.time - anchor_time >= 10.0;
    Ok(flight)
}

/// The robots of the sampled-data suite: `(radius, margin)` of a point and a 0.1 m disc, each
/// with no margin and with a 0.05 m margin.
pub const ROBOTS: [(f64, f64); 4] = [(0.0, 0.0), (0.0, 0.05), (0.1, 0.0), (0.1, 0.05)];

/// What [`suite`] measured over its worlds and [`ROBOTS`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SuiteReport {
    /// Flights flown.
    pub runs: usize,
    /// Flights that arrived.
    pub reached: usize,
    /// Flights that did not arrive and stalled ([`Flight::stalled`]).
    pub stalled: usize,
    /// The flights that were not [`Flight::safe`]: `(seed, radius, margin, flight)`.
    pub failures: Vec<(u64, f64, f64, Flight)>,
    /// The median time to the goal of the flights that arrived, s.
    pub median_time: f64,
    /// Commands shortened by the hold, over all flights.
    pub capped: usize,
    /// The fastest speed of any flight, m/s.
    pub max_speed: f64,
}

impl SuiteReport {
    /// The fraction of flights that arrived.
    pub fn arrival(&self) -> f64 {
        self.reached as f64 / self.runs.max(1) as f64
    }
}

/// [`fly`] in the worlds `seeds` ([`disc_world`]) with every robot of [`ROBOTS`], holding each
/// command of `law` for `h` under the hold policy of `options` (semi-implicit Euler).
pub fn suite(
    seeds: std::ops::Range<u64>,
    law: Law,
    options: Options,
    h: f64,
) -> Result<SuiteReport, NavError> {
    let mut report = SuiteReport::default();
    let mut times = Vec::new();
    for seed in seeds {
        let world = disc_world(seed);
        for (radius, margin) in ROBOTS {
            let options = options.with_robot(radius, margin);
            let flight = fly(&world, law, options, h, Integrator::SemiImplicitEuler)?;
            report.runs += 1;
            report.capped += flight.capped;
            report.max_speed = report.max_speed.max(flight.max_speed);
            if flight.reached {
                report.reached += 1;
                times.push(flight.time);
            } else if flight.stalled {
                report.stalled += 1;
            }
            if !flight.safe() {
                report.failures.push((seed, radius, margin, flight));
            }
        }
    }
    times.sort_by(f64::total_cmp);
    report.median_time = times.get(times.len() / 2).copied().unwrap_or(f64::NAN);
    Ok(report)
}
