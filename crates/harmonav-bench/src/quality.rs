//! The motion-quality benchmark (`docs/benchmarks.md`): seeded random worlds, every cell of
//! (obstacle count × sensing × `k` policy × law × margin) run through the same [`run`] as the
//! CLI, and each path compared with the independent shortest path (`harmonav_sim::shortest`).
//!
//! The worlds follow the issue that introduced the benchmark: a disc workspace of radius 5 m,
//! `M` obstacles of the four shapes (discs, ellipses, rounded polygons, Fourier stars) of size
//! 0.2–0.5 m, at least [`GAP`] apart and from the wall, start and goal at least 5 m apart and
//! [`POINT_CLEARANCE`] from everything. Every shape also survives an offset by
//! [`MAX_MARGIN`], so the same worlds serve the runs with a clearance margin.

use harmonav::{DampingPolicy, KPolicy, SpeedPolicy};
use harmonav_transform::StarShape;
use harmonav_transform::random::{Kind, Rng};
use nalgebra::Vector2;

use harmonav_scenario::{
    ControllerSpec, FieldSpec, Model, Prepared, RobotSpec, Scenario, SensorSpec, ShapeSpec, SimSpec,
};
use harmonav_sim::pool::parallel_map;
use harmonav_sim::run::run;
use harmonav_sim::shortest::of_scenario;
use harmonav_sim::summary::Run;

use crate::table::{self, CellKey, CellStats, Record};

/// Workspace radius, m.
pub const WORKSPACE_RADIUS: f64 = 5.0;
/// Smallest distance between two obstacles and from an obstacle to the wall, m.
pub const GAP: f64 = 0.3;
/// Smallest distance from the start and the goal to every shape, m.
pub const POINT_CLEARANCE: f64 = 0.25;
/// Smallest start–goal distance, m.
pub const START_GOAL_DISTANCE: f64 = 5.0;
/// The largest margin the worlds are built for, m.
pub const MAX_MARGIN: f64 = 0.1;

/// A benchmark world: true shapes, start and goal.
#[derive(Clone, Debug)]
pub struct World {
    /// The seed it was drawn from.
    pub seed: u64,
    /// The obstacles as scenario shapes.
    pub obstacles: Vec<ShapeSpec>,
    /// Start.
    pub start: Vector2<f64>,
    /// Goal.
    pub goal: Vector2<f64>,
}

/// How the robot senses the obstacles in a cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SensingKind {
    /// Every obstacle known from the start.
    Global,
    /// The paper's sector: range 1 m, aperture 60°.
    Sector,
}

impl SensingKind {
    /// Both kinds.
    pub const ALL: [SensingKind; 2] = [SensingKind::Global, SensingKind::Sector];

    /// `"global"` or `"sector"`.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Global => "global",
            Self::Sector => "sector",
        }
    }
}

/// One cell of the benchmark table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cell {
    /// Obstacle count.
    pub obstacles: usize,
    /// Sensing.
    pub sensing: SensingKind,
    /// `k` policy.
    pub k: KPolicy,
    /// Law.
    pub model: Model,
    /// Damping policy (dynamic law; kinematic cells carry the default, which they ignore).
    pub damping: DampingPolicy,
    /// Speed policy (kinematic law; dynamic cells carry the default, which they ignore).
    pub speed: SpeedPolicy,
    /// `robot.margin`, m.
    pub margin: f64,
}

impl Cell {
    /// The key of the JSON figures and of the scenario's name ([`CellKey::figure_key`]).
    pub fn key(&self) -> String {
        self.table_key().figure_key()
    }

    /// The cell's key in the study tables ([`crate::table`]).
    pub fn table_key(&self) -> CellKey {
        CellKey::of(&self.record("", &Measured::default()))
    }

    /// The record of one run of this cell in the world named `world` (a generated world).
    pub fn record(&self, world: &str, m: &Measured) -> Record {
        Record {
            world: world.to_string(),
            generated: true,
            obstacles: Some(self.obstacles as u64),
            law: Some(self.model.as_str().to_string()),
            damping: Some(self.damping.as_str().to_string()),
            speed: Some(self.speed.as_str().to_string()),
            k: Some(self.k.as_str().to_string()),
            sensing: Some(self.sensing.as_str().to_string()),
            margin: Some(self.margin),
            physics: Some("builtin".to_string()),
            max_time: None,
            start_index: None,
            error: None,
            reached: m.reached,
            time_s: Some(m.time),
            path_over_shortest: Some(m.path_ratio),
            min_clearance: Some(m.min_clearance),
            collisions: Some(m.collisions as u64),
            overshoot: Some(m.overshoot),
            steps: Some(m.steps as u64),
            guarantees_held: m.guarantees_held,
            command_us: None,
            outcome: None,
            conservatism: None,
        }
    }
}

/// A random shape of `kind` and size `size` at `c`, as a scenario shape (so that runs go through
/// the scenario layer exactly as a file would).
fn random_shape(rng: &mut Rng, kind: Kind, c: Vector2<f64>, size: f64) -> ShapeSpec {
    use std::f64::consts::TAU;
    let centre = [c.x, c.y];
    match kind {
        Kind::Circle => ShapeSpec::Circle {
            name: None,
            center: centre,
            radius: size * rng.uniform(0.7, 1.0),
        },
        Kind::Ellipse => {
            let a = size * rng.uniform(0.7, 1.0);
            ShapeSpec::Ellipse {
                name: None,
                center: centre,
                semi_axes: [a, a * rng.uniform(0.4, 1.0)],
                angle_deg: rng.uniform(0.0, 360.0),
            }
        }
        Kind::Polygon => {
            let n = 3 + rng.below(5);
            let phase = rng.uniform(0.0, TAU);
            let vertices = (0..n)
                .map(|i| {
                    let a = phase + TAU * (i as f64 + rng.uniform(-0.2, 0.2)) / n as f64;
                    let r = size * rng.uniform(0.6, 1.0);
                    [c.x + r * a.cos(), c.y + r * a.sin()]
                })
                .collect();
            ShapeSpec::Polygon {
                name: None,
                vertices,
                corner_radius: size * rng.uniform(0.05, 0.2),
            }
        }
        Kind::Star => ShapeSpec::Star {
            name: None,
            center: centre,
            radius: size * rng.uniform(0.7, 1.0),
            harmonics: (0..1 + rng.below(3))
                .map(|_| {
                    [
                        (1 + rng.below(5)) as f64,
                        size * rng.uniform(-0.12, 0.12),
                        size * rng.uniform(-0.12, 0.12),
                    ]
                })
                .collect(),
        },
    }
}

/// The benchmark world of `m` obstacles drawn from `seed` (deterministic).
pub fn world(m: usize, seed: u64) -> World {
    let kinds = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
    let mut rng = Rng::new(seed);
    let boundary = StarShape::circle(Vector2::zeros(), WORKSPACE_RADIUS).expect("valid disc");
    loop {
        let mut specs = Vec::with_capacity(m);
        let mut shapes: Vec<StarShape> = Vec::with_capacity(m);
        let mut tries = 0;
        while shapes.len() < m && tries < 5000 {
            tries += 1;
            let c = rng.point(WORKSPACE_RADIUS);
            let kind = kinds[rng.below(kinds.len())];
            let size = rng.uniform(0.2, 0.5);
            let s = random_shape(&mut rng, kind, c, size);
            let Ok(o) = harmonav_scenario::build_shape(&s) else {
                continue;
            };
            let fits = boundary.contains(c)
                && o.clearance_inside(&boundary) > GAP
                && o.offset(MAX_MARGIN).is_ok()
                && shapes.iter().all(|p| {
                    p.distance_to(&o) > GAP && !p.contains(o.centre()) && !o.contains(p.centre())
                });
            if fits {
                shapes.push(o);
                specs.push(s);
            }
        }
        if shapes.len() < m {
            continue;
        }
        let clear = |x: Vector2<f64>| {
            -boundary.signed_distance(x) > POINT_CLEARANCE
                && shapes
                    .iter()
                    .all(|o| o.signed_distance(x) > POINT_CLEARANCE)
        };
        for _ in 0..1000 {
            let (start, goal) = (rng.point(WORKSPACE_RADIUS), rng.point(WORKSPACE_RADIUS));
            if (start - goal).norm() >= START_GOAL_DISTANCE && clear(start) && clear(goal) {
                return World {
                    seed,
                    obstacles: specs,
                    start,
                    goal,
                };
            }
        }
    }
}

impl World {
    /// The world's name in the records of a study: `quality-m{m}-seed{seed}` (as
    /// `harmonav.experiment` names the generated worlds).
    pub fn name(&self, m: usize) -> String {
        format!("quality-m{m}-seed{}", self.seed)
    }

    /// The scenario of this world for one cell (dynamic law: m = 1 kg, μ = 10; both laws with
    /// `sim.max_time` = `max_time`).
    pub fn scenario(&self, cell: &Cell, max_time: f64) -> Scenario {
        Scenario {
            name: format!("quality-{}-seed{}", cell.key(), self.seed),
            description: String::new(),
            workspace: ShapeSpec::Circle {
                name: None,
                center: [0.0, 0.0],
                radius: WORKSPACE_RADIUS,
            },
            obstacles: self.obstacles.clone(),
            robot: RobotSpec {
                model: cell.model,
                start: [self.start.x, self.start.y],
                goal: [self.goal.x, self.goal.y],
                mass: 1.0,
                radius: 0.0,
                margin: cell.margin,
            },
            sensor: (cell.sensing == SensingKind::Sector).then_some(SensorSpec::sector(1.0, 60.0)),
            field: FieldSpec { k: cell.k },
            controller: ControllerSpec {
                damping: cell.damping,
                speed: cell.speed,
                ..ControllerSpec::default()
            },
            sim: SimSpec {
                max_time,
                ..SimSpec::default()
            },
            expect: None,
        }
    }
}

/// What one run measured.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Measured {
    /// Goal reached.
    pub reached: bool,
    /// Every guarantee monitor held.
    pub guarantees_held: bool,
    /// Recorded states in collision.
    pub collisions: usize,
    /// Path length over the shortest path around the same (grown) shapes.
    pub path_ratio: f64,
    /// Time at the end of the run, s.
    pub time: f64,
    /// Smallest clearance to the true shapes, m.
    pub min_clearance: f64,
    /// Largest distance the robot moved away from the goal in its last approach (m, dynamic
    /// law; 0 for the kinematic law, which cannot overshoot).
    pub overshoot: f64,
    /// Integration steps, accepted and rejected (the stiffness of the closed loop).
    pub steps: usize,
}

/// The length of the recorded path (measured online over every recorded state,
/// [`harmonav_sim::summary::Summary::path_length`]).
pub fn path_length(r: &Run) -> f64 {
    r.summary.path_length
}

/// The benchmark's overshoot, m: after the closest approach to `goal` within the last tenth
/// of the kept states, the largest distance the robot got away from it again,
/// `max_{j ≥ i} (|x_j − x_d| − min_{i ≤ l ≤ j} |x_l − x_d|)` over that tenth. Every run,
/// arrived or not (the guarantee `no-overshoot-at-goal` judges only the critically damped
/// last approach; this is the table's wider measure).
pub fn overshoot(r: &Run, goal: Vector2<f64>) -> f64 {
    overshoot_of(r.samples.iter().map(|x| x.x), goal)
}

/// [`overshoot`] of the states `path` (in time order) of any run, a floor plan's kept
/// positions included: the largest rise of `|x − x_d|` above its running minimum over the last
/// tenth of the states.
pub fn overshoot_of(path: impl ExactSizeIterator<Item = [f64; 2]>, goal: Vector2<f64>) -> f64 {
    let skip = path.len() * 9 / 10;
    let mut closest = f64::INFINITY;
    let mut rise: f64 = 0.0;
    for x in path.skip(skip) {
        let d = (Vector2::from(x) - goal).norm();
        closest = closest.min(d);
        rise = rise.max(d - closest);
    }
    rise
}

/// Runs one cell of one world and measures it against `shortest` (the length of the shortest
/// path around the cell's grown shapes).
pub fn measure(prepared: &Prepared, shortest: f64) -> Result<Measured, String> {
    let r = run(prepared, None).map_err(|e| e.to_string())?;
    let s = &r.summary;

    Ok(Measured {
        reached: s.reached,
        guarantees_held: s.safe(),
        collisions: s.collisions,
        path_ratio: path_length(&r) / shortest,
        time: s.time_s,
        min_clearance: s.min_clearance,
        overshoot: overshoot(&r, prepared.truth.workspace.destination()),
        steps: s.steps + s.rejected_steps,
    })
}

/// What the benchmark runs.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// Obstacle counts.
    pub obstacle_counts: Vec<usize>,
    /// Worlds per obstacle count (seeds `1..=worlds`).
    pub worlds: usize,
    /// The cells to run for each obstacle count (its `obstacles` is overwritten).
    pub cells: Vec<Cell>,
    /// `sim.max_time` of every run, s.
    pub max_time: f64,
}

/// Runs `plan` on `threads` threads: the record of each run ([`Cell::record`]), in plan order
/// (obstacle count, cell, world). Deterministic: the threads only share out the runs. A run
/// that cannot be made fails the plan.
pub fn run_plan(plan: &Plan, threads: usize) -> Result<Vec<Record>, String> {
    let mut jobs: Vec<(Cell, usize)> = Vec::new();
    for &m in &plan.obstacle_counts {
        for cell in &plan.cells {
            for w in 0..plan.worlds {
                jobs.push((
                    Cell {
                        obstacles: m,
                        ..*cell
                    },
                    w,
                ));
            }
        }
    }
    let worlds: Vec<Vec<World>> = plan
        .obstacle_counts
        .iter()
        .map(|&m| (1..=plan.worlds as u64).map(|s| world(m, s)).collect())
        .collect();
    let results = parallel_map(&jobs, threads, |(cell, w)| {
        let mi = plan
            .obstacle_counts
            .iter()
            .position(|&m| m == cell.obstacles)
            .unwrap_or(0);
        let world = &worlds[mi][*w];
        let path = std::path::Path::new("<benchmark>");
        let prepared = world
            .scenario(cell, plan.max_time)
            .prepare(path)
            .map_err(|e| e.to_string())?;
        let shortest = of_scenario(&prepared).map_err(|e| e.to_string())?;
        let m = measure(&prepared, shortest.length)?;
        Ok(Record {
            max_time: Some(plan.max_time),
            ..cell.record(&world.name(cell.obstacles), &m)
        })
    });
    results.into_iter().collect()
}

/// The statistics of each cell of `plan` ([`table::cells`] of [`run_plan`]'s records), in plan
/// order.
pub fn run_cells(plan: &Plan, threads: usize) -> Result<Vec<CellStats>, String> {
    Ok(table::cells(&run_plan(plan, threads)?))
}
