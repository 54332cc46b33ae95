//! The scenario suites (every file under `scenarios/`, built-in and rapier integrators), the
//! Monte-Carlo convergence study in a 20-obstacle world and the workspace census; outputs go to
//! `target/verify/`.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use harmonav_output::set::{Outputs, write_outputs};
use harmonav_scenario::{Model, Scenario};
use harmonav_sim::guarantee::Kind;
use harmonav_sim::guarantee::{Check as Measured, Guarantee};
use harmonav_sim::physics::{Physics, simulate, simulate_observed};
use harmonav_sim::pool::parallel_map;
use harmonav_sim::summary::Summary;
use harmonav_sim::sweep::random_starts;
use harmonav_sim::trace::Event;
use harmonav_sim::trajectory::MAX_KEPT_STATES;

use super::{Check, Outcome, Progress, Verdict, outcome};

/// Starts of the Monte-Carlo check (issue 7: 10⁴ seeded random starts).
const STARTS: usize = 10_000;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The suite files; an unreadable `scenarios/` yields none (and no scenario checks).
fn scenario_files() -> Vec<PathBuf> {
    harmonav_scenario::scenario_files(&root().join("scenarios")).unwrap_or_default()
}

pub fn checks() -> Vec<Check> {
    let mut checks: Vec<Check> = Vec::new();
    let mut named = Vec::new();
    for file in scenario_files() {
        let rel = file
            .strip_prefix(root().join("scenarios"))
            .unwrap_or(&file)
            .with_extension("");
        let name = rel
            .to_string_lossy()
            .replace(std::path::MAIN_SEPARATOR, "/");
        for physics in [Physics::Builtin, Physics::Rapier] {
            let (file, row) = (file.clone(), name.clone());
            let out = root()
                .join("target/verify")
                .join(&name)
                .join(physics.as_str());
            checks.push(Check::new(
                format!("scenario.{name}.{physics}"),
                move || scenario(&file, &row, physics, &out),
            ));
        }
        let row = name.clone();
        named.push((file.clone(), name.clone()));
        checks.push(Check::new(
            format!("scenario.{name}.other-model"),
            move || other_model(&file, &row),
        ));
    }
    checks.extend(super::lidar::rerun_checks(named));
    let long = root().join("scenarios").join(harmonav_scenario::LONG);
    for file in harmonav_scenario::scenario_files(&long).unwrap_or_default() {
        let name = file
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
        let out = root().join("target/verify/long").join(&name);
        checks.push(Check::new(format!("long.{name}"), move || long_run(&file, &out)).early());
    }
    checks.push(Check::new("montecarlo.20-obstacles-10k-starts", montecarlo).early());
    checks
}

/// A long run (`scenarios/long/`) as `harmonav run --out` makes it: its own robot model, the
/// built-in integrator, the recording streamed to `out` during the run. Every guarantee must
/// hold, every recorded state must have reached the recording, and the kept trajectory must
/// stay within its bound.
fn long_run(file: &Path, out: &Path) -> Outcome {
    let prepared = Scenario::load(file).map_err(|e| e.to_string())?;
    let mut outputs = Outputs::begin(out, &prepared).map_err(|e| e.to_string())?;
    let mut streamed = 0usize;
    let r = simulate_observed(&prepared, None, Physics::Builtin, &mut |e| {
        streamed += usize::from(matches!(e, Event::State(_)));
        outputs.observe(e);
    })
    .map_err(|e| e.to_string())?;
    outputs.finish(&r).map_err(|e| e.to_string())?;
    let s = &r.summary;
    // The pinned states (start, discoveries' two sides, end) come on top of the grid ones.
    let bound = MAX_KEPT_STATES + 2 * s.discoveries.len() + 2;
    if streamed != s.recorded_states || r.samples.len() > bound {
        return Err(format!(
            "{streamed} states streamed of {} recorded, {} kept (at most {bound})",
            s.recorded_states,
            r.samples.len()
        ));
    }
    let mb = std::fs::metadata(out.join("run.mcap")).map_or(0, |m| m.len()) as f64 / 1e6;
    let detail = format!(
        "{:?}: reached {} in {:.0} s, {} states streamed ({mb:.0} MB), {} kept, clearance {:.3} m",
        s.model,
        s.reached,
        s.time_s,
        s.recorded_states,
        r.samples.len(),
        s.min_clearance,
    );
    judge(format!("long.{}", s.name), s, detail, |_| true)
}

/// Runs a scenario with the other robot model (built-in integrator). Every guarantee, arrival
/// included, must hold, except where the file's `[expect] other_model_reached = false` states a
/// limit of the paper's policies: then the run must *not* arrive (else the statement is stale)
/// and the check reports a limit, not a pass.
fn other_model(file: &Path, name: &str) -> Outcome {
    let prepared = Scenario::load(file).map_err(|e| e.to_string())?;
    let model = prepared.scenario.robot.model.other();
    let limit = prepared
        .scenario
        .expect
        .as_ref()
        .and_then(|e| e.other_model_reached)
        == Some(false);
    let r = simulate(&prepared, Some(model), Physics::Builtin).map_err(|e| e.to_string())?;
    let s = &r.summary;
    let policies = match s.damping {
        Some(d) => format!("k = {}, damping = {d}", s.k_policy),
        None => format!("k = {}", s.k_policy),
    };
    let detail = format!(
        "{model:?} ({policies}): {} in {:.1} s, clearance {:.3} m, max speed {:.2} m/s",
        if s.reached { "reached" } else { "not reached" },
        s.time_s,
        s.min_clearance,
        s.max_speed,
    );
    let row = format!("{name}.other-model");
    if !limit {
        return judge(row, s, detail, |_| true);
    }
    let (Verdict::Held(d) | Verdict::Limit(d) | Verdict::Target(d)) =
        judge(row, s, detail, |g| g.kind() != Kind::ReachedGoal)?;
    if s.reached {
        return Err(format!(
            "[expect] other_model_reached = false, but the {model:?} run arrived; update the file"
        ));
    }
    Ok(Verdict::Limit(format!(
        "a limit of the paper's law, as the file states: {d}"
    )))
}

/// Columns of the scenario × guarantee matrix: a header and the guarantee kinds it covers.
const COLUMNS: [(&str, &[Kind]); 10] = [
    ("reached", &[Kind::ReachedGoal, Kind::Integrated]),
    (
        "no-collision",
        &[Kind::NoCollision, Kind::StayedInFreeSpace],
    ),
    ("inside", &[Kind::StayedInWorkspace]),
    ("Θ∈[0,1]", &[Kind::ThetaInUnitInterval]),
    ("discoveries", &[Kind::Discoveries]),
    ("speed<bound", &[Kind::SpeedBelowBound]),
    ("V↓", &[Kind::EnergyNonIncreasing]),
    ("no-overshoot", &[Kind::NoOvershoot]),
    ("no-contact", &[Kind::PhysicsNoContact]),
    ("expect", &[Kind::Expect]),
];

/// Rows of the matrix, filled by the scenario checks: the row name and one cell per column.
static MATRIX: Mutex<Vec<(String, Vec<&'static str>)>> = Mutex::new(Vec::new());

/// One matrix cell: `ok` if every guarantee of the column held, `FAIL` if a required one did
/// not, `limit` if only an unrequired one did not (arrival under a paper policy whose file
/// states the limit), `·` if the run has
/// none of them (no sector, kinematic, built-in…) or, for the overshoot at the goal, never got
/// there (the check then holds vacuously).
fn cell(summary: &Summary, kinds: &[Kind], required: &impl Fn(&Guarantee) -> bool) -> &'static str {
    if kinds.contains(&Kind::NoOvershoot) && !summary.reached {
        return "·";
    }
    let mut present = summary
        .guarantees
        .iter()
        .filter(|g| kinds.contains(&g.kind()))
        .peekable();
    if present.peek().is_none() {
        return "·";
    }
    let failed: Vec<&Guarantee> = present.filter(|g| !g.passed).collect();
    match failed.as_slice() {
        [] => "ok",
        f if f.iter().any(|g| required(g)) => "FAIL",
        _ => "limit",
    }
}

/// The scenario × guarantee matrix of the runs so far, rows sorted by name.
pub fn matrix() -> String {
    let Ok(mut rows) = MATRIX.lock() else {
        return String::new();
    };
    if rows.is_empty() {
        return String::new();
    }
    rows.sort();
    let width = rows.iter().map(|r| r.0.chars().count()).max().unwrap_or(0);
    let pad = |text: &str, n: usize| {
        format!(
            "{text}{}",
            " ".repeat(n.saturating_sub(text.chars().count()))
        )
    };
    let mut out = pad("scenario × guarantee", width);
    for (header, _) in COLUMNS {
        out.push_str("  ");
        out.push_str(header);
    }
    out.push('\n');
    for (name, cells) in rows.iter() {
        let mut line = pad(name, width);
        for ((header, _), c) in COLUMNS.iter().zip(cells) {
            line.push_str("  ");
            line.push_str(&pad(c, header.chars().count()));
        }
        out.push_str(line.trim_end());
        out.push('\n');
    }
    out
}

/// Passes if every guarantee of `summary` that is `required` passed; the failures are appended
/// to `detail`. Records the run's row of the matrix as `row`.
fn judge(
    row: String,
    summary: &Summary,
    detail: String,
    required: impl Fn(&Guarantee) -> bool,
) -> Outcome {
    let cells = COLUMNS
        .iter()
        .map(|(_, names)| cell(summary, names, &required))
        .collect();
    if let Ok(mut rows) = MATRIX.lock() {
        rows.push((row, cells));
    }
    let failed: Vec<String> = summary
        .guarantees
        .iter()
        .filter(|g| !g.passed && required(g))
        .map(|g| format!("{}: {}", g.name(), g.detail()))
        .collect();
    outcome(
        failed.is_empty(),
        if failed.is_empty() {
            detail
        } else {
            format!("{detail}; FAILED {}", failed.join("; "))
        },
    )
}

/// Runs one scenario with its own robot model; every guarantee (and `[expect]`) must hold.
fn scenario(file: &Path, name: &str, physics: Physics, out: &Path) -> Outcome {
    let prepared = Scenario::load(file).map_err(|e| e.to_string())?;
    // The one library entry of `harmonav run` (rapier: with the built-in run as the reference
    // of its deviation).
    let r = simulate(&prepared, None, physics).map_err(|e| e.to_string())?;
    let extra = match (r.summary.physics_contacts, deviation(&r.summary)) {
        (Some(contacts), Some(deviation)) => {
            format!(", {contacts} contacts, deviation {deviation:.3} m")
        }
        _ => String::new(),
    };
    write_outputs(out, &prepared, &r).map_err(|e| e.to_string())?;
    let s = &r.summary;
    let detail = format!(
        "{:?}: reached {} in {:.1} s, clearance {:.3} m, max speed {:.2} m/s, {} discoveries{extra}",
        s.model,
        s.reached,
        s.time_s,
        s.min_clearance,
        s.max_speed,
        s.discoveries.len()
    );
    judge(format!("{name}.{physics}"), s, detail, |_| true)
}

/// The rapier run's largest deviation from the built-in path, from its guarantee.
fn deviation(s: &Summary) -> Option<f64> {
    s.guarantees.iter().find_map(|g| match g.check {
        Measured::PhysicsDeviation { max_deviation } => Some(max_deviation),
        _ => None,
    })
}

/// The world of the Monte-Carlo study: the motion-quality benchmark's 20-obstacle world of
/// seed 20 (the four shape kinds), global sensing, the default `k` policy, no margin; its
/// starts are drawn with seed 20. `examples/experiments/montecarlo.toml` is the same study as
/// an experiment spec: the same world and starts through the same call (`descent::descend`).
const MONTECARLO_WORLD: (usize, u64) = (20, 20);

/// [`STARTS`] seeded random free starts in [`MONTECARLO_WORLD`], each followed by the
/// normalised descent of `Θ` (`harmonav_sim::descent::descend`): at least 99.9 % reach the
/// goal, none collides.
fn montecarlo() -> Outcome {
    use harmonav_bench::quality::{Cell, SensingKind, world};
    use harmonav_sim::descent::descend;
    use harmonav_sim::outcome::Outcome as Ended;

    let (m, seed) = MONTECARLO_WORLD;
    let cell = Cell {
        obstacles: m,
        sensing: SensingKind::Global,
        k: Default::default(),
        model: Model::Kinematic,
        damping: Default::default(),
        speed: Default::default(),
        margin: 0.0,
    };
    let prepared = world(m, seed)
        .scenario(&cell, 120.0)
        .prepare(Path::new("<quality world: 20 obstacles, seed 20>"))
        .map_err(|e| e.to_string())?;
    let starts = random_starts(&prepared, STARTS, seed).map_err(|e| e.to_string())?;
    let workers = std::thread::available_parallelism()
        .map_or(2, |n| n.get())
        .clamp(1, 2);
    // Starts are handed out one at a time: the slow ones (along the outer wall) cluster.
    let progress = Progress::new("montecarlo", starts.len());
    let results = parallel_map(&starts, workers, |&x| {
        let r = descend(&prepared, x);
        progress.tick();
        r
    });
    let runs = results
        .into_iter()
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| e.to_string())?;
    let count = |f: fn(&Ended) -> bool| runs.iter().filter(|r| f(&r.outcome)).count();
    let reached = count(|o| matches!(o, Ended::Reached { .. }));
    let stalled = count(|o| matches!(o, Ended::Stalled { .. }));
    let timed_out = count(|o| matches!(o, Ended::TimedOut { .. }));
    let collapsed = count(|o| matches!(o, Ended::StepCollapsed { .. }));
    let collisions = count(|o| matches!(o, Ended::Collision));
    let mut times: Vec<f64> = runs
        .iter()
        .filter(|r| matches!(r.outcome, Ended::Reached { .. }))
        .map(|r| r.descent.time)
        .collect();
    times.sort_by(f64::total_cmp);
    let median = times.get(times.len() / 2).copied().unwrap_or(f64::NAN);
    outcome(
        collisions == 0 && reached * 1000 >= runs.len() * 999,
        format!(
            "{reached}/{} reached ({:.2} %), {stalled} stalled, {timed_out} timed out, \
             {collapsed} step collapses, median path {median:.2} m, {collisions} collisions, \
             k = {}",
            runs.len(),
            100.0 * reached as f64 / runs.len() as f64,
            runs.first().map_or(f64::NAN, |r| r.k)
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matrix_cells_tell_pass_fail_unrequired_and_absent_apart() {
        let prepared = Scenario::load(&root().join("scenarios/shapes/mixed.toml")).unwrap();
        let mut s = simulate(&prepared, None, Physics::Builtin).unwrap().summary;
        let all = |_: &Guarantee| true;
        let not_arrival = |g: &Guarantee| g.kind() != Kind::ReachedGoal;
        assert_eq!(cell(&s, &[Kind::NoCollision], &all), "ok");
        assert_eq!(cell(&s, &[Kind::PhysicsNoContact], &all), "·");
        let reached = s
            .guarantees
            .iter_mut()
            .find(|g| g.kind() == Kind::ReachedGoal)
            .unwrap();
        reached.passed = false;
        assert_eq!(cell(&s, &[Kind::ReachedGoal], &all), "FAIL");
        assert_eq!(cell(&s, &[Kind::ReachedGoal], &not_arrival), "limit");
        s.reached = false;
        assert_eq!(cell(&s, &[Kind::NoOvershoot], &all), "·");
    }
}
