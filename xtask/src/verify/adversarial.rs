//! The hostile-input regression suite (issue 16): every case of
//! `scenarios/adversarial/cases.toml` through the library calls the CLI makes, with the error
//! or the verdict it must end with.

use std::path::{Path, PathBuf};
use std::time::Instant;

use harmonav_scenario::floorplan::{FileKind, FloorScenario};
use harmonav_scenario::{ADVERSARIAL, Scenario};
use harmonav_sim::physics::{Physics, simulate};
use harmonav_sim::sweep::{random_starts, sweep};
use serde::Deserialize;

use super::{Check, Outcome, outcome};

/// What a case runs.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(rename_all = "kebab-case")]
enum Command {
    /// Load and validate (`harmonav check`).
    Check,
    /// The built-in run (`harmonav run`).
    Run,
    /// The rapier2d cross-check (`harmonav run --physics rapier`).
    Rapier,
    /// Random starts (`harmonav sweep --seed 1`).
    Sweep,
}

/// One case of `cases.toml`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Case {
    file: String,
    command: Command,
    /// Sweep: the number of starts.
    starts: Option<usize>,
    /// The load must fail with a message holding each of these.
    error: Option<Vec<String>>,
    /// How the run (every start of a sweep) must end: `Outcome::kind`.
    outcome: Option<String>,
    /// Sweep: at least this many starts must end as `outcome` (default: all of them).
    at_least: Option<usize>,
    /// A warning whose message holds this.
    warning: Option<String>,
    /// The report the case reproduces (for the reader of `cases.toml`; required so that no
    /// case is without one).
    #[serde(rename = "why")]
    _why: String,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Manifest {
    case: Vec<Case>,
}

fn folder() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenarios")
        .join(ADVERSARIAL)
}

pub fn checks() -> Vec<Check> {
    let manifest = folder().join("cases.toml");
    let cases = std::fs::read_to_string(&manifest)
        .map_err(|e| e.to_string())
        .and_then(|text| toml::from_str::<Manifest>(&text).map_err(|e| e.to_string()));
    match cases {
        Err(e) => vec![Check::new("adversarial.cases", move || {
            Err(format!("{}: {e}", manifest.display()))
        })],
        Ok(m) => m
            .case
            .into_iter()
            .map(|case| {
                let stem = case.file.trim_end_matches(".toml").to_string();
                let name = format!("adversarial.{stem}.{:?}", case.command).to_lowercase();
                Check::new(name, move || run_case(&case))
            })
            .collect(),
    }
}

/// A refusal's verdict: its message must hold each of `needles`.
fn refused(message: &str, needles: &[String], started: Instant) -> Outcome {
    let missing: Vec<&String> = needles.iter().filter(|n| !message.contains(*n)).collect();
    outcome(
        missing.is_empty(),
        format!(
            "refused in {:.2} s: {message}{}",
            started.elapsed().as_secs_f64(),
            if missing.is_empty() {
                String::new()
            } else {
                format!(" (missing {missing:?})")
            }
        ),
    )
}

/// The safety guarantees (everything but arrival) all held ([`harmonav_sim::summary::Summary::safe`]).
fn safe(s: &harmonav_sim::summary::Summary) -> Result<(), String> {
    match s.first_unsafe() {
        Some(g) => Err(format!("{} failed: {}", g.name(), g.detail())),
        None => Ok(()),
    }
}

fn run_case(case: &Case) -> Outcome {
    let path = folder().join(&case.file);
    let started = Instant::now();
    // A floor plan is loaded as `check` loads it; its cases are errors or loads only.
    if FileKind::of(&path).map_err(|e| e.to_string())? == FileKind::FloorPlan {
        if !matches!(case.command, Command::Check) {
            return Err("a floor plan's case must be a `check`".into());
        }
        return match (FloorScenario::load(&path), &case.error) {
            (Ok(_), Some(_)) => Err("loaded, but must be refused".into()),
            (Ok(_), None) => outcome(true, "loads".into()),
            (Err(e), Some(needles)) => refused(&e.to_string(), needles, started),
            (Err(e), None) => Err(format!("must load: {e}")),
        };
    }
    let loaded = Scenario::load(&path);
    if let Some(needles) = &case.error {
        let message = match loaded {
            Ok(_) => return Err("loaded, but must be refused".into()),
            Err(e) => e.to_string(),
        };
        return refused(&message, needles, started);
    }
    let prepared = loaded.map_err(|e| format!("must load: {e}"))?;
    let expected = case.outcome.as_deref().unwrap_or("reached");
    match case.command {
        Command::Check => outcome(true, "loads".into()),
        Command::Run | Command::Rapier => {
            let physics = match case.command {
                Command::Rapier => Physics::Rapier,
                _ => Physics::Builtin,
            };
            let r = simulate(&prepared, None, physics).map_err(|e| e.to_string())?;
            let s = &r.summary;
            safe(s)?;
            let warned = case
                .warning
                .as_ref()
                .is_none_or(|w| s.warnings.iter().any(|x| x.to_string().contains(w)));
            let bound = s
                .speed_bound
                .map_or(String::new(), |b| format!(", bound {b:.3} m/s"));
            let contacts = s
                .physics_contacts
                .map_or(String::new(), |c| format!(", {c} contacts"));
            outcome(
                s.outcome.kind() == expected && warned,
                format!(
                    "{} in {:.2} s ({} steps), max speed {:.3} m/s{bound}{contacts}, warnings {:?}",
                    s.outcome,
                    started.elapsed().as_secs_f64(),
                    s.steps,
                    s.max_speed,
                    s.warnings.iter().map(|w| w.to_string()).collect::<Vec<_>>()
                ),
            )
        }
        Command::Sweep => {
            let n = case.starts.unwrap_or(20);
            let points = random_starts(&prepared, n, 1).map_err(|e| e.to_string())?;
            let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
            let model = prepared.scenario.robot.model;
            let outcomes = sweep(&prepared, &points, model, threads).map_err(|e| e.to_string())?;
            let hit = outcomes.iter().filter(|o| o.kind() == expected).count();
            let mut tally = std::collections::BTreeMap::<&str, usize>::new();
            for o in &outcomes {
                *tally.entry(o.kind()).or_default() += 1;
            }
            let collisions = tally.get("collision").copied().unwrap_or(0);
            outcome(
                hit >= case.at_least.unwrap_or(n) && collisions == 0,
                format!(
                    "{hit}/{n} {expected}, {collisions} collisions, in {:.2} s {tally:?}",
                    started.elapsed().as_secs_f64()
                ),
            )
        }
    }
}
