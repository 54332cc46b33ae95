//! The user's own loop fed by a simulated lidar only (issue 26, part 2; docs/maths.md §12.6):
//! seeded worlds of discs, ellipses, rounded polygons and Fourier stars, the robot's loop with
//! [`Navigator::observe_scan`] as its only perception (no exact shape is ever added), and every
//! step measured against the truth. The crate's tests and `cargo xtask verify`'s
//! `navigator.lidar.*` call these functions.

use harmonav_perception::sim::Lidar;
use harmonav_transform::StarShape;
use harmonav_transform::random::{self, Kind, Rng};
use nalgebra::Vector2;

use super::Integrator;
use crate::{LaserScan, Law, NavError, Navigator, Options, Pose, ScanOptions};

/// The radius of a [`lidar_world`]'s boundary, m.
pub const LIDAR_WORLD_RADIUS: f64 = 6.0;

/// The depth prior `D` of the lidar worlds, m: every true obstacle has a diameter of at most
/// 1 m (assumption A3 of `harmonav_perception`).
pub const LIDAR_WORLD_DEPTH: f64 = 1.0;

/// A world of the lidar suite: star obstacles in a disc, with a start, a goal and the priors
/// the truth satisfies.
#[derive(Clone, Debug)]
pub struct LidarWorld {
    /// The workspace boundary (known: a map wall), a disc of radius [`LIDAR_WORLD_RADIUS`].
    pub boundary: StarShape,
    /// The true obstacles, never given to the navigator.
    pub obstacles: Vec<StarShape>,
    /// The start.
    pub start: Vector2<f64>,
    /// The goal.
    pub goal: Vector2<f64>,
    /// The smallest curvature radius of the truth, m (`StarShape::rho_min`), at most 0.5: the
    /// prior `ρ_min` (A2, A4).
    pub rho_min: f64,
}

/// The seeded world `seed`: 3–6 obstacles (`discs_only`: circles; otherwise circles, ellipses,
/// rounded polygons and Fourier stars in turn), each within a disc of radius 0.5 m (so of
/// diameter at most [`LIDAR_WORLD_DEPTH`]) and of curvature radius at least 0.03 m, bounding
/// discs at least `2D + 0.2` = 2.2 m apart and 1.2 m from the wall; the start and the goal at
/// least 1.2 m from every bounding disc and 3 m apart. The gaps leave room for the unseen side
/// that the depth prior closes (a perceived shape reaches at most about `D` beyond its
/// obstacle). Deterministic.
pub fn lidar_world(seed: u64, discs_only: bool) -> LidarWorld {
    lidar_world_with(seed, discs_only, false)
}

/// The gaps between a [`furnished_world`]'s furniture and the wall, m: the issue's "within
/// 0.3 m of the walls", never touching.
pub const FURNITURE_GAP: (f64, f64) = (0.02, 0.3);

/// [`lidar_world`] with furniture against the wall: every other obstacle (the first, third, …)
/// stands [`FURNITURE_GAP`] from the wall (its bounding disc's gap), the others, the start and
/// the goal as there. Grown by a robot's radius, and fitted a depth `D` behind what the lidar
/// saw, such an obstacle reaches the boundary and joins it (`harmonav_transform::carve`).
pub fn furnished_world(seed: u64, discs_only: bool) -> LidarWorld {
    lidar_world_with(seed, discs_only, true)
}

fn lidar_world_with(seed: u64, discs_only: bool, furnished: bool) -> LidarWorld {
    let mut rng = Rng::new(0x11DA_0000 ^ seed);
    let m = 3 + rng.below(4);
    let kinds = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
    let mut obstacles: Vec<StarShape> = Vec::with_capacity(m);
    let gap = 2.0 * LIDAR_WORLD_DEPTH + 0.2;
    let wall = 1.2;
    let bound = |s: &StarShape| s.radius_bounds().1;
    while obstacles.len() < m {
        let kind = if discs_only {
            Kind::Circle
        } else {
            kinds[obstacles.len() % kinds.len()]
        };
        let against = furnished && obstacles.len().is_multiple_of(2);
        // The default worlds draw the centre, then the size (their seeds stay the same worlds).
        let (c, size) = if against {
            let size = rng_size(&mut rng);
            let angle = rng.uniform(0.0, std::f64::consts::TAU);
            let at = LIDAR_WORLD_RADIUS - size - rng.uniform(FURNITURE_GAP.0, FURNITURE_GAP.1);
            (at * Vector2::new(angle.cos(), angle.sin()), size)
        } else {
            let c = rng.point(LIDAR_WORLD_RADIUS - wall);
            (c, rng_size(&mut rng))
        };
        let s = random::shape(&mut rng, kind, c, size);
        let r = bound(&s);
        let to_wall = LIDAR_WORLD_RADIUS - c.norm() - r;
        let placed = if against {
            (FURNITURE_GAP.0..=FURNITURE_GAP.1).contains(&to_wall)
        } else {
            to_wall >= wall
        };
        let fits = r <= 0.5
            && s.rho_min() >= 0.03
            && placed
            && obstacles
                .iter()
                .all(|o| (o.centre() - c).norm() >= r + bound(o) + gap);
        if fits {
            obstacles.push(s);
        }
    }
    let clear = |p: Vector2<f64>| {
        p.norm() + wall <= LIDAR_WORLD_RADIUS
            && obstacles
                .iter()
                .all(|o| (p - o.centre()).norm() >= bound(o) + 1.2)
    };
    let mut free = || loop {
        let p = rng.point(LIDAR_WORLD_RADIUS);
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
    let rho_min = obstacles.iter().map(StarShape::rho_min).fold(0.5, f64::min);
    LidarWorld {
        boundary: StarShape::circle(Vector2::zeros(), LIDAR_WORLD_RADIUS)
            .expect("a disc of positive radius within the length limit"),
        obstacles,
        start,
        goal,
        rho_min,
    }
}

/// The size passed to `random::shape`: 0.3–0.5 m.
fn rng_size(rng: &mut Rng) -> f64 {
    rng.uniform(0.3, 0.5)
}

/// The lidar of the suite: 360 beams over 360°, range 0.05–3 m, uniform noise within 0.02 m,
/// 1 % dropouts.
pub fn suite_lidar() -> Lidar {
    Lidar {
        noise: 0.02,
        dropout: 0.01,
        ..Lidar::full_turn(360, 3.0)
    }
}

/// The navigator options of a lidar flight in `world`: a 360° sensor of range `r − D` (`r`
/// the lidar's, so `d_min = r − D`: the room left when a first fit reaches `D` in front of the
/// truth, docs/maths.md §12.6), the world's `ρ_min`, the scan priors `range_noise` (`ε`)
/// and `max_obstacle_depth` (`D`), and the dynamic law's recommended fit range `D +`
/// [`crate::scanning::FIT_BEYOND_DEPTH`] (which cuts the sector of `d_min` to 0.5 m, §12.11;
/// [`LidarSuite::run`] takes each law's, [`Options::recommended_fit_range`]).
pub fn lidar_options(
    world: &LidarWorld,
    lidar: &Lidar,
    range_noise: f64,
    max_obstacle_depth: f64,
) -> Options {
    Options::default()
        .with_sensor(lidar.range_max - max_obstacle_depth, 360.0)
        .with_rho_min(world.rho_min)
        .with_scan(ScanOptions {
            range_noise,
            max_obstacle_depth,
            fit_range: max_obstacle_depth + crate::scanning::FIT_BEYOND_DEPTH,
            ..ScanOptions::default()
        })
}

/// What a [`fly_lidar`] measured.
#[derive(Clone, Debug, PartialEq)]
pub struct LidarFlight {
    /// Within [`super::GOAL_TOLERANCE`] of the goal before [`super::MAX_TIME`].
    pub reached: bool,
    /// The time flown, s.
    pub time: f64,
    /// The smallest distance from the robot's disc to a true shape or the boundary, m.
    pub true_clearance: f64,
    /// Scans observed.
    pub scans: usize,
    /// Scans that changed the obstacles (events).
    pub events: usize,
    /// The most obstacles the navigator knew.
    pub obstacles: usize,
    /// The true boundary points (sampled) of a seen obstacle outside every perceived shape,
    /// over all events: 0 when every perceived shape contains its true obstacle.
    pub uncovered: usize,
    /// Boundary points of a perceived shape outside the next perceived shapes, over all
    /// events: 0 when shapes only grow.
    pub shrunk: usize,
    /// The smallest [`crate::ScanUpdate::event_clearance`], m.
    pub event_clearance: f64,
    /// The smallest event clearance of the events that only added obstacles (first
    /// detections; the braking argument's case), m.
    pub detection_clearance: f64,
    /// Perceived area over true area of the seen obstacles at the end (NaN when the flight
    /// perceived none).
    pub conservatism: f64,
    /// The fastest speed, m/s.
    pub max_speed: f64,
    /// The error that ended the flight (a refused scan or command), if one did.
    pub error: Option<NavError>,
    /// Not reached, and the last 10 s moved the robot less than 1 cm.
    pub stalled: bool,
    /// The known obstacles that joined the boundary by the end (`harmonav::joined`).
    pub joined: usize,
}

impl LidarFlight {
    /// No true shape touched, every perceived shape containing its truth, shapes only
    /// growing. (A refused scan is not unsafe by itself: it is counted apart.)
    pub fn safe(&self) -> bool {
        self.true_clearance > 0.0 && self.uncovered == 0 && self.shrunk == 0
    }
}

/// Boundary samples per true obstacle in the containment check.
const TRUTH_SAMPLES: usize = 256;

pub use harmonav_perception::growth::{GROWTH_SAMPLES, GROWTH_TOLERANCE, samples, shrunk};

/// The containment check: for every true obstacle that some perceived shape meets (contains
/// one of its boundary samples or its centre), the number of its boundary samples outside
/// every perceived shape.
pub fn uncovered(truth: &[StarShape], perceived: &[StarShape]) -> usize {
    let inside = |p: Vector2<f64>| perceived.iter().any(|s| s.contains(p));
    truth
        .iter()
        .map(|o| {
            let pts: Vec<_> = samples(o, TRUTH_SAMPLES).collect();
            let seen = inside(o.centre()) || pts.iter().any(|&p| inside(p));
            if seen {
                pts.iter().filter(|&&p| !inside(p)).count()
            } else {
                0
            }
        })
        .sum()
}

/// The robot's own loop in `world` under `law` and `options`, holding each command for `h`
/// (semi-implicit Euler), with one scan of `lidar` (seeded by `seed`) every `scan_every`
/// steps as its only perception, from the robot's centre with heading 0. After every event it
/// checks containment ([`uncovered`]) and growth against the truth. The flight ends at the
/// goal, at [`super::MAX_TIME`], or at the first error.
pub fn fly_lidar(
    world: &LidarWorld,
    law: Law,
    options: Options,
    h: f64,
    lidar: &Lidar,
    scan_every: usize,
    seed: u64,
) -> Result<LidarFlight, NavError> {
    let options = options.with_control_period(h);
    let mut nav = Navigator::new(world.boundary.clone(), world.goal, law, options)?;
    let mut rng = Rng::new(0x5CA0_0000 ^ seed);
    let (mut x, mut v) = (world.start, Vector2::zeros());
    let mut f = LidarFlight {
        reached: false,
        time: 0.0,
        true_clearance: f64::INFINITY,
        scans: 0,
        events: 0,
        obstacles: 0,
        uncovered: 0,
        shrunk: 0,
        event_clearance: f64::INFINITY,
        detection_clearance: f64::INFINITY,
        conservatism: f64::NAN,
        max_speed: 0.0,
        error: None,
        stalled: false,
        joined: 0,
    };
    let mut previous: Vec<StarShape> = Vec::new();
    let (mut anchor, mut anchor_time) = (x, 0.0);
    let steps = (super::MAX_TIME / h).ceil() as usize;
    let scan_every = scan_every.max(1);
    for step in 0..steps {
        if step % scan_every == 0 {
            let pose = Pose::new(x.x, x.y, 0.0);
            let scan: LaserScan =
                lidar.scan(&pose, &world.obstacles, Some(&world.boundary), &mut rng);
            f.scans += 1;
            match nav.observe_scan(pose, &scan) {
                Ok(u) if u.changed() => {
                    f.events += 1;
                    f.obstacles = f.obstacles.max(nav.obstacles().len());
                    let clearance = u.event_clearance.unwrap_or(f64::INFINITY);
                    f.event_clearance = f.event_clearance.min(clearance);
                    if u.grown.is_empty() {
                        f.detection_clearance = f.detection_clearance.min(clearance);
                    }
                    let now: Vec<StarShape> =
                        nav.perceived().map(|(_, p)| p.shape().clone()).collect();
                    f.uncovered += uncovered(&world.obstacles, &now);
                    f.shrunk += shrunk(&previous, &now);
                    previous = now;
                }
                Ok(_) => {}
                Err(e) => {
                    f.error = Some(e);
                    break;
                }
            }
        }
        if (x - world.goal).norm() < super::GOAL_TOLERANCE {
            f.reached = true;
            break;
        }
        let c = match nav.command(x, v) {
            Ok(c) => c.value,
            Err(e) => {
                f.error = Some(e);
                break;
            }
        };
        Integrator::SemiImplicitEuler.advance(law, h, c, &mut x, &mut v);
        f.time = (step + 1) as f64 * h;
        let gap = world
            .obstacles
            .iter()
            .map(|o| o.signed_distance(x))
            .fold(-world.boundary.signed_distance(x), f64::min)
            - options.radius;
        f.true_clearance = f.true_clearance.min(gap);
        f.max_speed = f.max_speed.max(v.norm());
        if (x - anchor).norm() >= 0.01 {
            (anchor, anchor_time) = (x, f.time);
        }
    }
    f.stalled = !f.reached && f.error.is_none() && f.time - anchor_time >= 10.0;
    f.joined = nav.obstacles().len() - nav.field().workspace().obstacles().len();
    let (mut seen, mut perceived) = (0.0, 0.0);
    for (_, p) in nav.perceived() {
        perceived += p.area();
    }
    for o in &world.obstacles {
        if nav.perceived().any(|(_, p)| p.shape().contains(o.centre())) {
            seen += o.area();
        }
    }
    if seen > 0.0 {
        f.conservatism = perceived / seen;
    }
    Ok(f)
}

/// What [`LidarSuite::run`] measured.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LidarReport {
    /// Flights flown.
    pub runs: usize,
    /// Flights that arrived.
    pub reached: usize,
    /// Flights that stalled.
    pub stalled: usize,
    /// Obstacles that joined the boundary, over all flights.
    pub joined: usize,
    /// Flights ended by a refused scan (not a star world, a shape over the robot or the goal,
    /// crossing the boundary): `(seed, error)`.
    pub refused: Vec<(u64, NavError)>,
    /// Flights that were not [`LidarFlight::safe`]: `(seed, flight)`.
    pub failures: Vec<(u64, LidarFlight)>,
    /// Scans observed, over all flights.
    pub scans: usize,
    /// Events, over all flights.
    pub events: usize,
    /// Uncovered truth samples ([`uncovered`]), over all flights.
    pub uncovered: usize,
    /// The smallest true clearance of any flight, m.
    pub min_clearance: f64,
    /// The smallest event clearance of any flight, m.
    pub min_event_clearance: f64,
    /// The smallest clearance at a first detection of any flight, m.
    pub min_detection_clearance: f64,
    /// The median conservatism (perceived over true area) of the flights that perceived an
    /// obstacle (NaN if none did).
    pub median_conservatism: f64,
    /// The fastest speed of any flight, m/s.
    pub max_speed: f64,
}

impl LidarReport {
    /// The fraction of flights that arrived.
    pub fn arrival(&self) -> f64 {
        self.reached as f64 / self.runs.max(1) as f64
    }
}

/// A lidar suite: [`fly_lidar`] in the worlds `seeds` ([`lidar_world`]) with a point robot
/// and a 0.1 m disc robot.
#[derive(Clone, Debug, PartialEq)]
pub struct LidarSuite {
    /// The worlds.
    pub seeds: std::ops::Range<u64>,
    /// Circles only ([`lidar_world`]).
    pub discs_only: bool,
    /// The law.
    pub law: Law,
    /// The control period, s.
    pub h: f64,
    /// One scan every this many control periods.
    pub scan_every: usize,
    /// The simulated lidar (the truth's noise and dropouts).
    pub lidar: Lidar,
    /// The noise bound `ε` given to the navigator, m.
    pub range_noise: f64,
    /// The depth prior `D` given to the navigator, m.
    pub max_obstacle_depth: f64,
    /// The fit range `r_f`, m; `None` (the default): the law's recommended one
    /// ([`Options::recommended_fit_range`], eq. fitnear).
    pub fit_range: Option<f64>,
    /// Furniture against the walls ([`furnished_world`]) instead of [`lidar_world`]'s 1.2 m
    /// from them.
    pub furnished: bool,
}

impl LidarSuite {
    /// Worlds 0–23 of every shape kind, [`suite_lidar`] at 10 Hz, the priors the truth
    /// satisfies (`ε` = the lidar's noise, `D` = [`LIDAR_WORLD_DEPTH`]).
    pub fn new(law: Law, h: f64) -> Self {
        let lidar = suite_lidar();
        Self {
            seeds: 0..24,
            discs_only: false,
            law,
            h,
            scan_every: ((0.1 / h).round() as usize).max(1),
            lidar,
            range_noise: lidar.noise,
            max_obstacle_depth: LIDAR_WORLD_DEPTH,
            fit_range: None,
            furnished: false,
        }
    }

    /// Flies every world with both robots.
    pub fn run(&self) -> Result<LidarReport, NavError> {
        let mut r = LidarReport {
            min_clearance: f64::INFINITY,
            min_event_clearance: f64::INFINITY,
            min_detection_clearance: f64::INFINITY,
            ..LidarReport::default()
        };
        let mut cons = Vec::new();
        for seed in self.seeds.clone() {
            let world = lidar_world_with(seed, self.discs_only, self.furnished);
            for radius in [0.0, 0.1] {
                let mut options = lidar_options(
                    &world,
                    &self.lidar,
                    self.range_noise,
                    self.max_obstacle_depth,
                )
                .with_robot(radius, 0.0);
                // The law's own fit range (eq. fitnear): nearer under the kinematic law.
                options.scan.fit_range = self.fit_range.unwrap_or_else(|| {
                    options.recommended_fit_range(
                        &self.law,
                        self.h * self.scan_every as f64,
                        self.lidar.range_min,
                    )
                });
                let f = fly_lidar(
                    &world,
                    self.law,
                    options,
                    self.h,
                    &self.lidar,
                    self.scan_every,
                    seed,
                )?;
                r.runs += 1;
                r.scans += f.scans;
                r.events += f.events;
                r.joined += f.joined;
                r.uncovered += f.uncovered;
                r.min_clearance = r.min_clearance.min(f.true_clearance);
                r.max_speed = r.max_speed.max(f.max_speed);
                r.min_event_clearance = r.min_event_clearance.min(f.event_clearance);
                r.min_detection_clearance = r.min_detection_clearance.min(f.detection_clearance);
                if f.conservatism.is_finite() {
                    cons.push(f.conservatism);
                }
                if f.reached {
                    r.reached += 1;
                } else if f.stalled {
                    r.stalled += 1;
                }
                if let Some(e) = &f.error {
                    r.refused.push((seed, e.clone()));
                }
                if !f.safe() {
                    r.failures.push((seed, f));
                }
            }
        }
        cons.sort_by(f64::total_cmp);
        r.median_conservatism = cons.get(cons.len() / 2).copied().unwrap_or(f64::NAN);
        Ok(r)
    }
}
