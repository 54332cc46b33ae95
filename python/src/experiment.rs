//! Batches of runs for `harmonav.experiment` (issue 28): a list of run configurations, each
//! through the library path of `harmonav run` (`physics::simulate` on a prepared scenario),
//! without the GIL, one record per run in the order given. A run that cannot be made — a bad
//! configuration, a world the scenario layer refuses, a run error, a panic — is a record with
//! its `error`, never an exception that stops the batch.
//!
//! The bindings convert and delegate: the worlds are `harmonav_bench::quality::world` or a
//! scenario file's text, the overrides are the scenario's own fields, the start the sweep's
//! (`sweep::start_problem`, then `robot.start`), the reference path `shortest::of_scenario`.
//! The overshoot is the benchmark's (`harmonav_bench::quality::overshoot`); `guarantees_held`
//! is `harmonav_sim::summary::Summary::safe`'s rule with the file's `[expect]` entries also left out, as they are
//! not monitors of the law. A floor-plan file (a `[floor_plan]` table) takes its own loop,
//! `physics::simulate_floor`, into the same record ([`floor`], issue 51).

use std::collections::BTreeMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;

use harmonav_bench::quality::{self, Cell, MAX_MARGIN, SensingKind};
use harmonav_rs::{DampingPolicy, KPolicy, SpeedPolicy, Vector2};
use harmonav_scenario::floorplan::FileKind;
use harmonav_scenario::scenario::read_text;
use harmonav_scenario::{Model, Prepared, Scenario, SensorSpec};
use harmonav_sim::descent::descend;
use harmonav_sim::guarantee::{Guarantee, Kind};
use harmonav_sim::outcome::Outcome;
use harmonav_sim::physics::{Physics, simulate};
use harmonav_sim::pool::parallel_map;
use harmonav_sim::shortest::of_scenario;
use harmonav_sim::sweep::{random_starts, start_problem};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::convert::{integer, value_error};
use crate::scenario::seed_arg;

mod floor;

/// A prepared world: a star world's scenario (a generated quality world or a file), or a
/// floor-plan file with its map solved ([`floor::FloorWorld`]).
enum PreparedWorld {
    Star(Prepared),
    Floor(floor::FloorWorld),
}

/// The most obstacles a generated quality world may have: the generator draws until the
/// obstacles fit (0.2–0.5 m shapes 0.3 m apart in a 5 m disc), so a count it cannot place
/// would never end. 40 fit in well under a second; the benchmark uses 6, 12 and 20.
pub const MAX_QUALITY_OBSTACLES: usize = 40;

/// The time budget of a quality world when the configuration gives none: the benchmark's.
const QUALITY_MAX_TIME: f64 = 120.0;

/// The paper's sector (range 1 m, aperture 60°): `sensing = "sector"` on a world without a
/// sensor of its own, as in the quality benchmark.
const PAPER_SECTOR: (f64, f64) = (1.0, 60.0);

/// Where a run's world comes from.
#[derive(Clone, Debug, PartialEq)]
enum WorldSource {
    /// `harmonav_bench::quality::world(obstacles, seed)`.
    Quality { obstacles: usize, seed: u64 },
    /// A scenario file: its text if given (so that a remote worker needs no file system),
    /// else read from `path`; `path` names it in errors.
    File { path: PathBuf, text: Option<String> },
}

/// One run as configured: the world, the overrides of its scenario (`None`: the world's own),
/// the start and what to measure.
#[derive(Clone, Debug, PartialEq)]
struct Config {
    world: WorldSource,
    /// The robot model (the spec's `law`; `harmonav run --model`).
    model: Option<Model>,
    /// The spec's `law = "descent"`: the normalised descent of `Θ` with every obstacle known
    /// (`harmonav_sim::descent::descend`, verify's Monte-Carlo) instead of a closed-loop run;
    /// `model` is then the kinematic one, whose flow line it follows.
    descent: bool,
    k: Option<KPolicy>,
    damping: Option<DampingPolicy>,
    speed: Option<SpeedPolicy>,
    sensing: Option<SensingKind>,
    margin: Option<f64>,
    max_time: Option<f64>,
    start: Option<[f64; 2]>,
    start_index: usize,
    physics: Physics,
    shortest: bool,
}

/// The keys a run configuration may have.
const KEYS: [&str; 15] = [
    "generator",
    "obstacles",
    "seed",
    "scenario",
    "scenario_text",
    "model",
    "k",
    "damping",
    "speed",
    "sensing",
    "margin",
    "max_time",
    "start",
    "start_index",
    "physics",
];

/// An optional item of `dict`, extracted, with errors naming the key.
pub(crate) fn item<'py, T>(dict: &Bound<'py, PyDict>, key: &str) -> Result<Option<T>, String>
where
    T: for<'a> FromPyObject<'a, 'py>,
    for<'a> <T as FromPyObject<'a, 'py>>::Error: Into<PyErr>,
{
    match dict.get_item(key).map_err(|e| format!("{key}: {e}"))? {
        None => Ok(None),
        Some(v) if v.is_none() => Ok(None),
        Some(v) => v
            .extract::<T>()
            .map(Some)
            .map_err(|e| format!("{key}: {}", e.into())),
    }
}

/// An optional policy name of `dict`, parsed by the policy's own `FromStr`.
fn named<T: std::str::FromStr>(dict: &Bound<'_, PyDict>, key: &str) -> Result<Option<T>, String>
where
    T::Err: std::fmt::Display,
{
    item::<String>(dict, key)?
        .map(|s| s.parse::<T>().map_err(|e| format!("{key}: {e}")))
        .transpose()
}

/// A run configuration from its dict (keys: [`KEYS`]); every problem names its key.
fn config(dict: &Bound<'_, PyDict>) -> Result<Config, String> {
    for key in dict.keys() {
        let key: String = key
            .extract()
            .map_err(|_| "keys must be strings".to_string())?;
        if !KEYS.contains(&key.as_str()) {
            return Err(format!(
                "unknown key `{key}`: expected one of {}",
                KEYS.join(", ")
            ));
        }
    }
    let generator: Option<String> = item(dict, "generator")?;
    let scenario: Option<PathBuf> = item(dict, "scenario")?;
    let world = match (generator.as_deref(), scenario) {
        (Some("quality"), None) => {
            let obstacles: usize =
                item(dict, "obstacles")?.ok_or("obstacles: required by generator = \"quality\"")?;
            if !(1..=MAX_QUALITY_OBSTACLES).contains(&obstacles) {
                return Err(format!(
                    "obstacles: {obstacles}; a quality world has 1 to {MAX_QUALITY_OBSTACLES}"
                ));
            }
            let seed: u64 =
                item(dict, "seed")?.ok_or("seed: required by generator = \"quality\"")?;
            WorldSource::Quality { obstacles, seed }
        }
        (Some(other), None) => {
            return Err(format!(
                "generator: unknown generator \"{other}\": expected \"quality\""
            ));
        }
        (None, Some(path)) => WorldSource::File {
            path,
            text: item(dict, "scenario_text")?,
        },
        (Some(_), Some(_)) => return Err("give generator or scenario, not both".into()),
        (None, None) => return Err("no world: give generator or scenario".into()),
    };
    let (model, descent) = match item::<String>(dict, "model")?.as_deref() {
        None => (None, false),
        Some("kinematic") => (Some(Model::Kinematic), false),
        Some("dynamic") => (Some(Model::Dynamic), false),
        Some("descent") => (Some(Model::Kinematic), true),
        Some(other) => {
            return Err(format!(
                "model: unknown model \"{other}\": expected \"kinematic\", \"dynamic\" or \
                 \"descent\""
            ));
        }
    };
    let physics: Physics = named(dict, "physics")?.unwrap_or_default();
    if descent && physics != Physics::Builtin {
        return Err(format!(
            "physics: \"{}\" with model \"descent\": a descent is integrated by its own \
             method (harmonav_field::descent::follow), not by a physics engine",
            physics.as_str()
        ));
    }
    let sensing = match item::<String>(dict, "sensing")?.as_deref() {
        None => None,
        Some("global") => Some(SensingKind::Global),
        Some("sector") => Some(SensingKind::Sector),
        Some(other) => {
            return Err(format!(
                "sensing: unknown sensing \"{other}\": expected \"global\" or \"sector\""
            ));
        }
    };
    if descent && sensing == Some(SensingKind::Sector) {
        return Err(
            "sensing: \"sector\" with model \"descent\": a descent follows Θ with \
                    every obstacle known (global sensing)"
                .into(),
        );
    }
    let finite = |key: &str, v: Option<f64>| match v {
        Some(x) if !x.is_finite() => Err(format!("{key}: must be finite, got {x}")),
        v => Ok(v),
    };
    let start: Option<[f64; 2]> = item(dict, "start")?;
    if let Some(p) = start
        && !p.iter().all(|c| c.is_finite())
    {
        return Err(format!("start: must be two finite numbers, got {p:?}"));
    }
    Ok(Config {
        world,
        model,
        descent,
        k: named(dict, "k")?,
        damping: named(dict, "damping")?,
        speed: named(dict, "speed")?,
        sensing,
        margin: finite("margin", item(dict, "margin")?)?,
        max_time: finite("max_time", item(dict, "max_time")?)?,
        start,
        start_index: item(dict, "start_index")?.unwrap_or(0),
        physics,
        shortest: true,
    })
}

/// The file keys both formats give the grid's overrides: `[field] k`, `[controller] damping`
/// and `speed`, `[robot] margin`, `[sim] max_time`.
struct Keys<'a> {
    k: &'a mut KPolicy,
    damping: &'a mut DampingPolicy,
    speed: &'a mut SpeedPolicy,
    margin: &'a mut f64,
    max_time: &'a mut f64,
}

impl Config {
    /// Sets each of `keys` this configuration overrides (`None`: the world's own).
    fn set_keys(&self, keys: Keys<'_>) {
        if let Some(k) = self.k {
            *keys.k = k;
        }
        if let Some(d) = self.damping {
            *keys.damping = d;
        }
        if let Some(s) = self.speed {
            *keys.speed = s;
        }
        if let Some(m) = self.margin {
            *keys.margin = m;
        }
        if let Some(t) = self.max_time {
            *keys.max_time = t;
        }
    }
}

/// Everything a prepared scenario depends on (not the start, the physics or the
/// measurements): runs that share it share one preparation.
fn preparation_key(c: &Config) -> String {
    format!(
        "{:?}",
        (
            &c.world, c.model, c.k, c.damping, c.speed, c.sensing, c.margin, c.max_time
        )
    )
}

/// The world of `c` with its overrides, validated by the scenario layer: a floor-plan file (a
/// `[floor_plan]` table) by [`floor::prepare`], every other world as a star world.
fn prepare(c: &Config) -> Result<PreparedWorld, String> {
    let (mut scenario, path) = match &c.world {
        WorldSource::Quality { obstacles, seed } => {
            let margin = c.margin.unwrap_or(0.0);
            if !(0.0..=MAX_MARGIN).contains(&margin) {
                return Err(format!(
                    "margin: {margin} m; the quality worlds are built for margins from 0 to \
                     {MAX_MARGIN} m"
                ));
            }
            let cell = Cell {
                obstacles: *obstacles,
                sensing: c.sensing.unwrap_or(SensingKind::Global),
                k: c.k.unwrap_or_default(),
                model: c.model.unwrap_or(Model::Kinematic),
                damping: c.damping.unwrap_or_default(),
                speed: c.speed.unwrap_or_default(),
                margin,
            };
            let world = quality::world(*obstacles, *seed);
            let max_time = c.max_time.unwrap_or(QUALITY_MAX_TIME);
            let path = PathBuf::from(format!(
                "<quality world: {obstacles} obstacles, seed {seed}>"
            ));
            (world.scenario(&cell, max_time), path)
        }
        WorldSource::File { path, text } => {
            let text = match text {
                Some(t) => t.clone(),
                None => read_text(path).map_err(|e| e.to_string())?,
            };
            if FileKind::of_text(&text) == FileKind::FloorPlan {
                return floor::prepare(c, path, &text).map(PreparedWorld::Floor);
            }
            let scenario = Scenario::parse(path, &text).map_err(|e| e.to_string())?;
            (scenario, path.clone())
        }
    };
    c.set_keys(Keys {
        k: &mut scenario.field.k,
        damping: &mut scenario.controller.damping,
        speed: &mut scenario.controller.speed,
        margin: &mut scenario.robot.margin,
        max_time: &mut scenario.sim.max_time,
    });
    match c.sensing {
        None => {}
        Some(SensingKind::Global) => scenario.sensor = None,
        Some(SensingKind::Sector) if scenario.sensor.is_some() => {}
        Some(SensingKind::Sector) => {
            scenario.sensor = Some(SensorSpec::sector(PAPER_SECTOR.0, PAPER_SECTOR.1));
        }
    }
    scenario
        .prepare(&path)
        .map(PreparedWorld::Star)
        .map_err(|e| e.to_string())
}

/// What one run measured (the record's outcome columns).
#[derive(Clone, Debug)]
struct Measured {
    reached: bool,
    outcome: Outcome,
    time_s: f64,
    final_distance: f64,
    path_length: f64,
    shortest: Option<f64>,
    min_clearance: f64,
    max_speed: f64,
    speed_bound: Option<f64>,
    collisions: usize,
    discoveries: usize,
    steps: usize,
    rejected_steps: usize,
    recorded_states: usize,
    overshoot: f64,
    guarantees_held: bool,
    all_passed: bool,
    k_policy: &'static str,
    guarantees: String,
    warnings: Vec<String>,
    start: [f64; 2],
}

/// The configuration a run had once its world's own values filled the gaps (the records'
/// configuration columns): the law's irrelevant policy is `None` (damping for the kinematic
/// law, speed for the dynamic one).
#[derive(Clone, Debug)]
struct Effective {
    model: &'static str,
    k: &'static str,
    damping: Option<&'static str>,
    speed: Option<&'static str>,
    sensing: &'static str,
    margin: f64,
    max_time: f64,
    obstacles: usize,
}

impl Effective {
    /// The configuration of the run `c` on `p` (the file's model when `c` gives none).
    fn of(p: &Prepared, c: &Config) -> Self {
        let s = &p.scenario;
        let kinematic = c.model.unwrap_or(s.robot.model) == Model::Kinematic;
        Self {
            model: match (c.descent, kinematic) {
                (true, _) => "descent",
                (false, true) => Model::Kinematic.as_str(),
                (false, false) => Model::Dynamic.as_str(),
            },
            k: s.field.k.as_str(),
            damping: (!kinematic).then(|| s.controller.damping.as_str()),
            speed: (kinematic && !c.descent).then(|| s.controller.speed.as_str()),
            // A descent knows every obstacle, whatever the file's sensor.
            sensing: if s.sensor.is_some() && !c.descent {
                "sector"
            } else {
                "global"
            },
            margin: s.robot.margin,
            max_time: s.sim.max_time,
            obstacles: s.obstacles.len(),
        }
    }
}

/// The outcome of one run: a start outside the free space is the outcome `invalid-start`
/// (as in a sweep), not an error.
enum Ran {
    Invalid(Outcome, [f64; 2], Effective),
    Run(Box<Measured>, Effective),
}

/// Runs `c` on its prepared world.
fn run_one(c: &Config, world: &PreparedWorld) -> Result<Ran, String> {
    match world {
        PreparedWorld::Star(p) => run_star(c, p),
        PreparedWorld::Floor(w) => floor::run(c, w),
    }
}

/// Whether every monitor of a run held but arrival and the file's `[expect]` entries (not
/// monitors of the law): a record's `guarantees_held`.
fn held(guarantees: &[Guarantee]) -> bool {
    guarantees
        .iter()
        .all(|g| g.passed || matches!(g.kind(), Kind::ReachedGoal | Kind::Expect))
}

/// Runs `c` on a star world's prepared scenario.
fn run_star(c: &Config, prepared: &Prepared) -> Result<Ran, String> {
    let mut p = prepared.clone();
    if let Some([x, y]) = c.start {
        if let Some(problem) = start_problem(prepared, Vector2::new(x, y)) {
            let outcome = Outcome::InvalidStart {
                index: c.start_index,
                problem,
            };
            return Ok(Ran::Invalid(outcome, [x, y], Effective::of(prepared, c)));
        }
        p.scenario.robot.start = [x, y];
    }
    if c.descent {
        return descent_run(c, &p);
    }
    // The law as `harmonav run --model` gives it: the file's `[expect]` describes a run of
    // the file's own model, and is not applied to the other.
    let run = simulate(&p, c.model, c.physics).map_err(|e| e.to_string())?;
    let shortest = if c.shortest {
        of_scenario(&p).ok().map(|s| s.length)
    } else {
        None
    };
    let s = &run.summary;
    Ok(Ran::Run(
        Box::new(Measured {
            reached: s.reached,
            outcome: s.outcome.clone(),
            time_s: s.time_s,
            final_distance: s.final_distance,
            path_length: s.path_length,
            shortest,
            min_clearance: s.min_clearance,
            max_speed: s.max_speed,
            speed_bound: s.speed_bound,
            collisions: s.collisions,
            discoveries: s.discoveries.len(),
            steps: s.steps,
            rejected_steps: s.rejected_steps,
            recorded_states: s.recorded_states,
            overshoot: quality::overshoot(&run, p.truth.workspace.destination()),
            guarantees_held: held(&s.guarantees),
            all_passed: s.all_passed(),
            k_policy: s.k_policy.as_str(),
            guarantees: serde_json::to_string(&s.guarantees).map_err(|e| e.to_string())?,
            warnings: s.warnings.iter().map(|w| w.to_string()).collect(),
            start: p.scenario.robot.start,
        }),
        Effective::of(&p, c),
    ))
}

/// The descent of `c` from `p`'s start (`harmonav_sim::descent::descend`), as a record: its
/// time is its path length (unit speed). Its one monitor is the free space at every accepted
/// point (`follow`'s `collision_free`): `collisions` is 0 or 1 and `guarantees_held` says
/// whether it held; it has no summary guarantees, no clearance (NaN) and no overshoot.
fn descent_run(c: &Config, p: &Prepared) -> Result<Ran, String> {
    let start = p.scenario.robot.start;
    let r = descend(p, Vector2::from(start)).map_err(|e| e.to_string())?;
    let d = &r.descent;
    let reached = matches!(r.outcome, Outcome::Reached { .. });
    let collision_free = r.outcome != Outcome::Collision;
    let shortest = if c.shortest {
        of_scenario(p).ok().map(|s| s.length)
    } else {
        None
    };
    Ok(Ran::Run(
        Box::new(Measured {
            reached,
            outcome: r.outcome.clone(),
            time_s: d.time,
            final_distance: (d.end - p.truth.workspace.destination()).norm(),
            path_length: d.time,
            shortest,
            min_clearance: f64::NAN,
            max_speed: 1.0,
            speed_bound: None,
            collisions: usize::from(!collision_free),
            discoveries: 0,
            steps: d.steps,
            rejected_steps: d.rejected,
            recorded_states: 0,
            overshoot: 0.0,
            guarantees_held: collision_free,
            all_passed: collision_free && reached,
            k_policy: p.k_policy().as_str(),
            guarantees: "[]".to_string(),
            warnings: Vec::new(),
            start,
        }),
        Effective::of(p, c),
    ))
}

/// A panic's message.
fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic without a message".to_string())
}

/// `f()`, with a panic turned into an error.
fn guarded<T>(f: impl FnOnce() -> Result<T, String>) -> Result<T, String> {
    catch_unwind(AssertUnwindSafe(f))
        .unwrap_or_else(|p| Err(format!("panicked: {}", panic_text(&*p))))
}

/// `threads`, or every core for 0.
fn thread_count(threads: usize) -> usize {
    if threads == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        threads
    }
}

/// The configurations of `runs` (a list of dicts), each parsed or its error.
fn configs(runs: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<Result<Config, String>>> {
    let list = runs
        .cast::<PyList>()
        .map_err(|_| PyTypeError::new_err(format!("{what} must be a list of dicts")))?;
    list.iter()
        .map(|r| {
            let dict = r
                .cast::<PyDict>()
                .map_err(|_| PyTypeError::new_err(format!("{what} must be a list of dicts")))?;
            Ok(config(dict))
        })
        .collect()
}

/// Runs every configuration of `runs` on `threads` threads (0: every core) without the GIL and
/// returns one record (a dict) per run, in order.
///
/// A configuration is a dict with `generator = "quality"`, `obstacles`, `seed` (a world of the
/// motion-quality benchmark) or `scenario` (a file's path, which names it in errors and anchors
/// a floor plan's `map`; a star world or a floor plan, [`floor`]) and
/// optionally `scenario_text` (its text: then the file is not read); the overrides `model`
/// (`"kinematic"`, `"dynamic"`: the robot model, the spec's `law`; `"descent"`: the normalised
/// descent of `Θ` with every obstacle known, `harmonav_sim::descent::descend`), `k`, `damping`, `speed`
/// (policy names), `sensing` (`"global"`, `"sector"`: the file's sensor, or the paper's 1 m,
/// 60°), `margin`, `max_time`
/// (`None` or absent: the world's own; a quality world's defaults are the benchmark's), and
/// `start` (`[x, y]`, with `start_index` naming it) and `physics` (`"builtin"`, `"rapier"`).
///
/// A record has `error` (`None`, or why the run could not be made: the configuration, the
/// scenario layer's message naming the file and field, the run's error, or a panic), then
/// `reached`, `outcome` (the sweep's kinds, `"invalid-start"` for a start outside the free
/// space), `outcome_detail`, `time_s`, `path_length`, `shortest_length`,
/// `path_over_shortest`, `min_clearance`, `final_distance`, `max_speed`, `speed_bound`,
/// `collisions`, `discoveries`, `steps`, `rejected_steps`, `recorded_states`, `overshoot`,
/// `guarantees_held` (every monitor but arrival and the file's `[expect]`), `all_passed`,
/// `k_policy`, `guarantees` (summary.json's list: `name`, `passed`, `detail`, `measured`),
/// `warnings`, `start`, `version` (this package's) and `effective` (the configuration as run,
/// the world's own values filling the gaps: `model`, `k`, `damping`, `speed`, `sensing`,
/// `margin`, `max_time`, `obstacles`). The same configuration gives the same
/// record, bit for bit, on any thread count and in any batch.
#[pyfunction]
#[pyo3(signature = (runs, threads=1, shortest=true))]
pub fn run_batch<'py>(
    py: Python<'py>,
    runs: &Bound<'py, PyAny>,
    #[pyo3(from_py_with = threads_arg)] threads: usize,
    shortest: bool,
) -> PyResult<Bound<'py, PyList>> {
    let mut configs = configs(runs, "runs")?;
    for c in configs.iter_mut().flatten() {
        c.shortest = shortest;
    }
    let threads = thread_count(threads);
    let results = py.detach(|| batch(&configs, threads));
    let out = PyList::empty(py);
    for r in results {
        out.append(record(py, r)?)?;
    }
    Ok(out)
}

/// The runs of `configs`: each distinct preparation once, then the runs, on `threads`.
fn batch(configs: &[Result<Config, String>], threads: usize) -> Vec<Result<Ran, String>> {
    let mut keys: BTreeMap<String, usize> = BTreeMap::new();
    let mut unique: Vec<&Config> = Vec::new();
    let slots: Vec<Option<usize>> = configs
        .iter()
        .map(|c| {
            let c = c.as_ref().ok()?;
            let n = keys.len();
            let slot = *keys.entry(preparation_key(c)).or_insert(n);
            if slot == n {
                unique.push(c);
            }
            Some(slot)
        })
        .collect();
    let prepared: Vec<Result<PreparedWorld, String>> =
        parallel_map(&unique, threads, |c| guarded(|| prepare(c)));
    let jobs: Vec<(usize, Option<usize>)> = slots.into_iter().enumerate().collect();
    parallel_map(&jobs, threads, |&(i, slot)| {
        let c = configs[i].as_ref().map_err(Clone::clone)?;
        let p = prepared[slot.expect("a parsed configuration has a slot")]
            .as_ref()
            .map_err(Clone::clone)?;
        guarded(|| run_one(c, p))
    })
}

/// The record of one run (see [`run_batch`]).
fn record<'py>(py: Python<'py>, r: Result<Ran, String>) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let nan = f64::NAN;
    d.set_item("version", env!("CARGO_PKG_VERSION"))?;
    let m = match r {
        Err(e) => {
            d.set_item("error", e)?;
            return Ok(d);
        }
        Ok(Ran::Invalid(outcome, start, effective)) => {
            effective_items(&d, &effective)?;
            d.set_item("error", py.None())?;
            d.set_item("reached", false)?;
            d.set_item("outcome", outcome.kind())?;
            d.set_item("outcome_detail", outcome.to_string())?;
            d.set_item("start", start)?;
            return Ok(d);
        }
        Ok(Ran::Run(m, effective)) => {
            effective_items(&d, &effective)?;
            m
        }
    };
    d.set_item("error", py.None())?;
    d.set_item("reached", m.reached)?;
    d.set_item("outcome", m.outcome.kind())?;
    d.set_item("outcome_detail", m.outcome.to_string())?;
    d.set_item("time_s", m.time_s)?;
    d.set_item("path_length", m.path_length)?;
    d.set_item("shortest_length", m.shortest)?;
    d.set_item(
        "path_over_shortest",
        m.shortest.map_or(nan, |s| m.path_length / s),
    )?;
    d.set_item("min_clearance", m.min_clearance)?;
    d.set_item("final_distance", m.final_distance)?;
    d.set_item("max_speed", m.max_speed)?;
    d.set_item("speed_bound", m.speed_bound)?;
    d.set_item("collisions", m.collisions)?;
    d.set_item("discoveries", m.discoveries)?;
    d.set_item("steps", m.steps)?;
    d.set_item("rejected_steps", m.rejected_steps)?;
    d.set_item("recorded_states", m.recorded_states)?;
    d.set_item("overshoot", m.overshoot)?;
    d.set_item("guarantees_held", m.guarantees_held)?;
    d.set_item("all_passed", m.all_passed)?;
    d.set_item("k_policy", m.k_policy)?;
    let guarantees = py
        .import("json")?
        .call_method1("loads", (m.guarantees.as_str(),))?;
    d.set_item("guarantees", guarantees)?;
    d.set_item("warnings", m.warnings)?;
    d.set_item("start", m.start)?;
    Ok(d)
}

/// The effective configuration's items of a record, under `effective`.
fn effective_items(d: &Bound<'_, PyDict>, e: &Effective) -> PyResult<()> {
    let py = d.py();
    let c = PyDict::new(py);
    c.set_item("model", e.model)?;
    c.set_item("k", e.k)?;
    c.set_item("damping", e.damping)?;
    c.set_item("speed", e.speed)?;
    c.set_item("sensing", e.sensing)?;
    c.set_item("margin", e.margin)?;
    c.set_item("max_time", e.max_time)?;
    c.set_item("obstacles", e.obstacles)?;
    d.set_item("effective", c)
}

/// Checks a run configuration as [`run_batch`] reads it, and with `prepare` also prepares its
/// world (the scenario layer's validation of the world with its overrides), without running
/// it. Raises `ValueError` naming the key, or the file and field.
#[pyfunction]
#[pyo3(signature = (config, prepare=false))]
pub fn check_run_config(py: Python<'_>, config: &Bound<'_, PyDict>, prepare: bool) -> PyResult<()> {
    let c = self::config(config).map_err(value_error)?;
    if prepare {
        py.detach(|| guarded(|| self::prepare(&c).map(drop)))
            .map_err(value_error)?;
    }
    Ok(())
}

/// `threads=` of `run_batch`, refused by name when negative or beyond 64 bits.
fn threads_arg(obj: &Bound<'_, PyAny>) -> PyResult<usize> {
    integer(obj, "threads", "an integer ≥ 0 (0: one per core)")
}

/// `count=` of `random_start_points`, refused by name when negative or beyond 64 bits.
fn count_arg(obj: &Bound<'_, PyAny>) -> PyResult<usize> {
    integer(obj, "count", "an integer ≥ 0")
}

/// `count` seeded random starts in the free space of the world of `config` (a run
/// configuration, as [`run_batch`] takes), as `harmonav sweep --starts count --seed seed` draws
/// them: a list of `[x, y]`. Raises `ValueError` for a configuration or world the layer
/// refuses.
#[pyfunction]
pub fn random_start_points(
    py: Python<'_>,
    config: &Bound<'_, PyDict>,
    #[pyo3(from_py_with = count_arg)] count: usize,
    #[pyo3(from_py_with = seed_arg)] seed: u64,
) -> PyResult<Vec<[f64; 2]>> {
    let c = self::config(config).map_err(value_error)?;
    let points = py
        .detach(|| {
            guarded(|| match prepare(&c)? {
                PreparedWorld::Star(p) => {
                    random_starts(&p, count, seed).map_err(|e| format!("starts: {e}"))
                }
                PreparedWorld::Floor(w) => floor::random_starts(&w, count, seed),
            })
        })
        .map_err(value_error)?;
    Ok(points.iter().map(|p| [p.x, p.y]).collect())
}
