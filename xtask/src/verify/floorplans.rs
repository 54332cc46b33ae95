//! The floor-plan suite (`scenarios/floorplans/`, issue 25; docs/maths.md §13): every start
//! of each file (its `robot.start` and the seeded `[starts]`) flown under both laws in the
//! user's loop around `harmonav::FloorNavigator` (`harmonav_sim::floor::run`), built-in and in
//! rapier with the walls as colliders (`harmonav_sim::physics::simulate_floor`), and the
//! Lipschitz certificate of `det J_H > 0`, `|H| < 1` on `W_δ` for each map, with the certified
//! level `c_δ` on `∂W_δ`; and every file without a lidar rerun with one (issue 26 in issue 25's
//! plans: the walls from the map, the obstacles from the scans; docs/maths.md §12.17).

use std::path::{Path, PathBuf};

use harmonav_scenario::floorplan::{FLOORPLANS, FloorPrepared, FloorScenario};
use harmonav_scenario::{Model, SensorSpec};
use harmonav_sim::floor::{FloorSummary, certificate, outcome_name};
use harmonav_sim::guarantee::Kind;
use harmonav_sim::physics::{Physics, simulate_floor};
use harmonav_sim::pool::parallel_map;
use nalgebra::Vector2;

use super::lidar::RERUN_RANGE_BEYOND_DEPTH;
use super::{Check, Outcome, Verdict, outcome};

/// Cells of the certificate (each an `O(N)` evaluation; the first grid of the U room at
/// `δ = 0.05` m alone has 7·10⁴, and its pocket takes it to 1.3·10⁵).
const CERTIFY_BUDGET: usize = 300_000;

fn files() -> Vec<PathBuf> {
    super::movers::toml_files(&folder())
}

/// `scenarios/floorplans/`.
fn folder() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenarios")
        .join(FLOORPLANS)
}

pub fn checks() -> Vec<Check> {
    let mut all = Vec::new();
    let every = files();
    all.push(Check::new("lidar-rerun.floorplans", move || rerun(&every)).early());
    for file in files() {
        let name = file
            .file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned());
        for (law, model) in [("kinematic", Model::Kinematic), ("dynamic", Model::Dynamic)] {
            for physics in [Physics::Builtin, Physics::Rapier] {
                let file = file.clone();
                // The built-in runs keep their names; the rapier ones add `.rapier`.
                let suffix = match physics {
                    Physics::Builtin => String::new(),
                    Physics::Rapier => ".rapier".to_string(),
                };
                all.push(
                    Check::new(format!("floorplan.{name}.{law}{suffix}"), move || {
                        fly(&file, model, physics)
                    })
                    .early(),
                );
            }
        }
        all.push(
            Check::new(format!("floorplan.{name}.certificate"), move || {
                certify(&file)
            })
            .early(),
        );
    }
    for file in funnel_files() {
        let name = file
            .file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned());
        all.push(Check::new(format!("floorplan.funnels.{name}"), move || funnels(&file)).early());
    }
    all
}

/// The files of `scenarios/floorplans/funnels/`, whose navigator follows a chain of funnels.
fn funnel_files() -> Vec<PathBuf> {
    super::movers::toml_files(&folder().join("funnels"))
}

/// A file whose navigator follows a chain of certified funnels (`floor_plan.funnels`,
/// docs/maths.md §13.10; the kinematic law only): the chain certifies at least 90 % of the
/// reachable free area and every start, and every start arrives, built-in and in rapier, with
/// every guarantee of [`fly`] and no escape (in a funnel the law converges without one).
fn funnels(file: &Path) -> Outcome {
    let p = FloorScenario::load(file).map_err(|e| e.to_string())?;
    let chain = p.funnels.clone().ok_or("floor_plan.funnels is not set")?;
    let covered = p
        .starts
        .iter()
        .filter(|&&x| chain.entry(x).is_some())
        .count();
    let mut bad = Vec::new();
    let mut detail = Vec::new();
    for physics in [Physics::Builtin, Physics::Rapier] {
        match fly_prepared(&p, Model::Kinematic, physics, true) {
            Ok(Verdict::Held(d)) => detail.push(format!("{physics:?}: {d}")),
            Ok(v) => bad.push(format!("{physics:?}: {v:?}")),
            Err(e) => bad.push(format!("{physics:?}: {e}")),
        }
    }
    let n = p.starts.len();
    outcome(
        chain.fraction() >= 0.9 && covered == n && bad.is_empty(),
        format!(
            "{} funnels certify {:.1} % of the reachable area and {covered}/{n} starts; {}{}",
            chain.funnels.len(),
            100.0 * chain.fraction(),
            detail.join("; "),
            if bad.is_empty() {
                String::new()
            } else {
                format!("; {}", bad.join("; "))
            }
        ),
    )
}

/// Every start arrives within the file's `sim.arrival`, with no collision with the true walls
/// and obstacles, never leaving the plan, never entering the boundary layer, and every
/// guarantee of its summary held; under rapier (the walls as colliders, the built-in run as the
/// reference of the deviation) also with no contact event.
fn fly(file: &Path, model: Model, physics: Physics) -> Outcome {
    let p = FloorScenario::load(file).map_err(|e| e.to_string())?;
    fly_prepared(&p, model, physics, false)
}

/// [`fly`] on a loaded file; with `no_escape`, an escape also fails it.
fn fly_prepared(p: &FloorPrepared, model: Model, physics: Physics, no_escape: bool) -> Outcome {
    let (mut reached, mut bad) = (0, Vec::new());
    let (mut walls, mut obstacles, mut layer, mut slowest) =
        (f64::INFINITY, f64::INFINITY, f64::INFINITY, 0.0_f64);
    let (mut contacts, mut deviation, mut escapes) = (0, 0.0_f64, 0);
    // With a lidar: scans, events, and the seen truth points (uncovered ones fail the run).
    let mut lidar: Option<(usize, usize, usize)> = None;
    for &start in &p.starts {
        let r = simulate_floor(p, Some(model), start, physics).map_err(|e| e.to_string())?;
        if let Some((report, _)) = &r.perception {
            let l = lidar.get_or_insert((0, 0, 0));
            l.0 += report.scans;
            l.1 += report.events;
            l.2 += report.seen_points;
        }
        contacts += r.contacts.unwrap_or(0);
        escapes += r.escapes;
        deviation = deviation.max(r.max_deviation.unwrap_or(0.0));
        let summary = FloorSummary::new(p, Some(model), start, &r);
        // Arrival is reported with the ending below.
        if let Some(g) = summary
            .guarantees
            .iter()
            .find(|g| !g.passed && g.kind() != Kind::ReachedGoal)
        {
            bad.push(format!("{start:?}: {} failed: {}", g.name(), g.detail()));
        }
        walls = walls.min(r.wall_clearance);
        obstacles = obstacles.min(r.obstacle_clearance);
        layer = layer.min(r.layer_clearance);
        if r.outcome.reached() {
            reached += 1;
            slowest = slowest.max(r.time);
        } else {
            bad.push(format!(
                "{start:?}: {} at {:.3} m ({:?})",
                outcome_name(&r.outcome),
                r.final_distance,
                r.error
            ));
        }
    }
    let n = p.starts.len();
    let scans = lidar.map_or(String::new(), |(scans, events, seen)| {
        format!("; lidar: {scans} scans, {events} events, {seen} seen truth points covered")
    });
    let rapier = match physics {
        Physics::Builtin => String::new(),
        Physics::Rapier => format!(
            "; rapier: {contacts} contacts, max deviation from the built-in path {deviation:.1e} m"
        ),
    };
    outcome(
        bad.is_empty()
            && walls > 0.0
            && obstacles > 0.0
            && layer >= 0.0
            && contacts == 0
            && !(no_escape && escapes > 0),
        format!(
            "{reached}/{n} within {} m (slowest {slowest:.1} s, {escapes} escapes), 0 collisions: \
             wall clearance {walls:.3} m, obstacles {obstacles:.3} m, layer {layer:.1e} m{rapier}{scans}; N = {}, δ = {} m, setup {:.2} s{}",
            p.scenario.sim.arrival,
            p.floor.map().elements().len(),
            p.floor.delta(),
            p.setup_seconds,
            if bad.is_empty() {
                String::new()
            } else {
                format!("; {}", bad.join("; "))
            }
        ),
    )
}

/// The certificate's verdict on `W_δ`: it must be "certified" (since the second-order cells
/// of docs/maths.md §13.5 every suite map is); a fold, `|H| ≥ 1` or area left undecided
/// fails, and the sampled `min det J_H` must be positive. Then `c_δ`, certified on
/// `∂W_δ` over the walls (it must be bounded: a cell left unbounded fails), and how many starts
/// lie below it or below `c_s`, where the slide along `∂W_δ` may rest (docs/maths.md §13.5,
/// §13.9).
fn certify(file: &Path) -> Outcome {
    let p = FloorScenario::load(file).map_err(|e| e.to_string())?;
    let c = certificate(&p, CERTIFY_BUDGET)?;
    let bad = c.verdict != harmonav_harmonic::Verdict::Certified;
    // c_δ over the walls alone (the sensed obstacles are not known at the start).
    let (level, certified) = p.start_certificates().map_err(|e| e.to_string())?;
    let below = certified.iter().filter(|&&b| b).count();
    let field = harmonav::floorplan::FloorField::new(
        p.floor.clone(),
        nalgebra::Vector2::new(p.scenario.robot.goal[0], p.scenario.robot.goal[1]),
        harmonav::KPolicy::default(),
    )
    .map_err(|e| e.to_string())?;
    let slide = field.layer_slide();
    outcome(
        !bad && c.extremes.min_det > 0.0 && level.phi_certified.is_finite(),
        format!(
            "{} on W_δ (δ = {} m): certified {:.2} m², undecided {:.3} m², {} evaluations, \
             sampled min det J_H {:.1e}, max |H| {:.4}; c_δ = {:.4} certified on ∂W_δ \
             (sampled {:.4}, {} cells, {} unresolved), c_s = {}, {below}/{} starts certified; −∇Θ into \
             the layer at {}/{} edge samples, {} attracting rest points of the slide there{}",
            c.verdict.as_str(),
            c.delta,
            c.certified_area,
            c.undecided_area,
            c.evaluations,
            c.extremes.min_det,
            c.extremes.max_norm,
            level.certified(),
            level.sampled(),
            level.evaluations,
            level.unresolved,
            if level.phi_slide == f64::INFINITY {
                "1 (no rest point)".to_string()
            } else {
                format!("{:.4}", level.slide())
            },
            p.starts.len(),
            slide.into,
            slide.samples,
            slide.attracting.len(),
            slide.attracting.first().map_or(String::new(), |p| format!(
                " (the first at ({:.2}, {:.2}))",
                p.x, p.y
            )),
        ),
    )
}

/// `file` with a 360° lidar of the defaults (360 beams at 10 Hz, ±2 cm noise, 1 % none; the
/// depth prior the largest true diameter `D`, the wall prior from the true walls) and range
/// `D +` [`RERUN_RANGE_BEYOND_DEPTH`], as a star world is rerun; `None` for a file that has a
/// lidar already.
fn with_lidar(file: &Path) -> Result<Option<FloorPrepared>, String> {
    let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
    let mut sc = FloorScenario::parse(file, &text).map_err(|e| e.to_string())?;
    if sc.sensor.is_some() {
        return Ok(None);
    }
    // First with a range beyond any depth, to learn the default D from the truth.
    sc.sensor = Some(SensorSpec::lidar(1e6));
    let probe = sc.clone().prepare(file).map_err(|e| e.to_string())?;
    let depth = probe.lidar.map_or(1.0, |(l, _)| l.scan.max_obstacle_depth);
    sc.sensor = Some(SensorSpec::lidar(depth + RERUN_RANGE_BEYOND_DEPTH));
    sc.prepare(file).map(Some).map_err(|e| e.to_string())
}

/// Every floor plan without a lidar rerun with one ([`with_lidar`]), every start under both
/// laws (built-in): each run must keep every guarantee of its summary (no collision, the
/// certified region, the seen truth covered, shapes only growing); runs that stay safe but do
/// not arrive (a refused scan, a time-out) make it a target not met.
fn rerun(files: &[PathBuf]) -> Outcome {
    let mut runs: Vec<(String, Model, Vector2<f64>, usize)> = Vec::new();
    let mut plans = Vec::new();
    for file in files {
        if let Some(p) = with_lidar(file)? {
            let name = file
                .file_stem()
                .map_or(String::new(), |s| s.to_string_lossy().into_owned());
            for &start in &p.starts {
                for model in [Model::Kinematic, Model::Dynamic] {
                    runs.push((name.clone(), model, start, plans.len()));
                }
            }
            plans.push(p);
        }
    }
    let threads = std::thread::available_parallelism().map_or(1, usize::from);
    let results = parallel_map(&runs, threads, |(_, model, start, i)| {
        let p = &plans[*i];
        simulate_floor(p, Some(*model), *start, Physics::Builtin)
            .map(|r| FloorSummary::new(p, Some(*model), *start, &r))
    });
    let (mut arrived, mut events, mut seen) = (0, 0, 0);
    let (mut lost, mut missed) = (Vec::new(), Vec::new());
    for ((name, model, start, _), s) in runs.iter().zip(results) {
        let s = s.map_err(|e| format!("{name} ({model:?}): {e}"))?;
        let p = s.perception.clone().unwrap_or_default();
        (events, seen) = (events + p.events, seen + p.seen_points);
        let run = format!("{name} {} from {start:?}", model.as_str());
        if let Some(g) = s
            .guarantees
            .iter()
            .find(|g| !g.passed && g.kind() != Kind::ReachedGoal && g.kind() != Kind::ScansAccepted)
        {
            lost.push(format!("{run}: {} failed: {}", g.name(), g.detail()));
        } else if s.reached {
            arrived += 1;
        } else {
            missed.push(format!(
                "{run}: {}{}",
                s.outcome,
                s.error.map_or(String::new(), |e| format!(" ({e})"))
            ));
        }
    }
    let detail = format!(
        "{arrived}/{} runs arrived ({} plans, every start, both laws), {events} events, {seen} \
         seen truth points covered",
        runs.len(),
        plans.len(),
    );
    judged(detail, &lost, &missed)
}

/// The verdict on runs measured as `detail`: a lost guarantee (`lost`) fails, naming the first;
/// runs that stayed safe but did not arrive (`missed`, appended to the detail) make it a target
/// not met; else it held.
pub(super) fn judged(detail: String, lost: &[String], missed: &[String]) -> Outcome {
    let detail = if missed.is_empty() {
        detail
    } else {
        format!("{detail}; not arrived: {}", missed.join("; "))
    };
    if let Some(first) = lost.first() {
        return Err(format!("{detail}; {} unsafe, first: {first}", lost.len()));
    }
    if missed.is_empty() {
        Ok(Verdict::Held(detail))
    } else {
        Ok(Verdict::Target(detail))
    }
}
