//! The mover scenarios (`scenarios/movers/`, issue 54, item 4; docs/movers.md §8): every file
//! flown under both laws in the held-command loop, with the movers reported to the navigator
//! each period. Every guarantee must hold, arrival included (`no-collision-with-movers`: no
//! contact after a certified command; with `[[robots]]`, `no-collision-between-robots` and
//! every robot arrived); a contact only after `Overwhelmed` commands (passive safety) is a
//! target not met, issue 54's 0 contacts. A differential drive (`[robot] base = "diff"`) flies the
//! kinematic law, its arcs certified by `command_pose`; under the dynamic law its file must be
//! refused by name. Negative controls fly the crossing with the robot blind to the movers, the
//! differential drive blind to its walkers, and the four robots blind to each other: each must
//! record a contact. The crossing flown with `[robot] comfort` keeps the person farther away.

use std::path::{Path, PathBuf};

use harmonav_scenario::floorplan::{FileKind, FloorScenario};
use harmonav_scenario::{Model, Scenario};
use harmonav_sim::floor::FloorSummary;
use harmonav_sim::guarantee::Guarantee;
use harmonav_sim::movers::{FleetReport, MoverReport};
use harmonav_sim::physics::{Physics, simulate, simulate_floor};
use harmonav_sim::run::run_without_filter;
use nalgebra::Vector2;

use super::{Check, Outcome, Verdict};

fn folder() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenarios")
        .join(harmonav_scenario::MOVERS)
}

/// The mover files, sorted; an unreadable folder yields none.
fn files() -> Vec<PathBuf> {
    toml_files(&folder())
}

/// The `*.toml` files of `folder` (not below it), sorted; an unreadable folder yields none.
pub(super) fn toml_files(folder: &Path) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(folder)
        .map(|d| {
            d.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|e| e == "toml"))
                .collect()
        })
        .unwrap_or_default();
    out.sort();
    out
}

pub fn checks() -> Vec<Check> {
    let models = [Model::Kinematic, Model::Dynamic].map(|m| (m, m.as_str()));
    let mut checks = per_file(&files(), "movers", &models, fly);
    let in_rapier = [Model::Kinematic, Model::Dynamic].map(|m| {
        (
            m,
            match m {
                Model::Kinematic => "rapier-kinematic",
                Model::Dynamic => "rapier-dynamic",
            },
        )
    });
    checks.extend(per_file(&files(), "movers", &in_rapier, fly_rapier));
    checks.push(Check::new("movers.person-crossing.blind", blind));
    checks.push(Check::new("movers.person-crossing.comfort", comfort));
    checks.push(Check::new("movers.diff-walkers.blind", blind_diff));
    checks.push(Check::new("movers.four-robots-swap.blind", blind_robots));
    checks.push(Check::new(
        "movers.floor-corridor-swap.blind",
        blind_floor_robots,
    ));
    checks
}

/// One check per file of `files` and per variant of `variants`, named
/// `<prefix>.<stem>.<variant's name>`, flying `fly(file, variant)`.
pub(super) fn per_file<V: Copy + Send + Sync + 'static>(
    files: &[PathBuf],
    prefix: &str,
    variants: &[(V, &str)],
    fly: fn(&Path, V) -> Outcome,
) -> Vec<Check> {
    let mut checks = Vec::new();
    for file in files {
        let stem = file
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
        for &(variant, name) in variants {
            let file = file.clone();
            checks.push(Check::new(format!("{prefix}.{stem}.{name}"), move || {
                fly(&file, variant)
            }));
        }
    }
    checks
}

/// The names of the guarantees of `guarantees` that failed.
pub(super) fn failed_names(guarantees: &[Guarantee]) -> Vec<&'static str> {
    guarantees
        .iter()
        .filter(|g| !g.passed)
        .map(|g| g.name())
        .collect()
}

/// One file under `model`: every guarantee holds and no mover touches the robot.
fn fly(file: &Path, model: Model) -> Outcome {
    if FileKind::of(file).map_err(|e| e.to_string())? == FileKind::FloorPlan {
        return fly_floor(file, model);
    }
    let prepared = Scenario::load(file).map_err(|e| e.to_string())?;
    if prepared.base().is_some() && model == Model::Dynamic {
        // A differential drive runs the kinematic law only: refused by name.
        return match simulate(&prepared, Some(model), Physics::Builtin) {
            Err(e) if e.to_string().contains("base") => Ok(Verdict::Held(format!("refused: {e}"))),
            Err(e) => Err(format!("refused for another reason: {e}")),
            Ok(_) => Err("the dynamic law ran a differential drive".into()),
        };
    }
    let run = simulate(&prepared, Some(model), Physics::Builtin).map_err(|e| e.to_string())?;
    let s = &run.summary;
    if let Some(f) = &s.fleet {
        return fleet(f, s.reached, s.time_s, &s.guarantees, prepared.margin());
    }
    let m = s.movers.as_ref().ok_or("no mover report")?;
    let detail = detail(s.reached, s.time_s, m, prepared.margin());
    judged(&detail, m, &s.guarantees)
}

/// One file under `model` in rapier (the movers judged along every rapier step): every
/// guarantee holds, rapier's `physics-no-contact` included, and no mover touches the robot. A
/// file with `[[robots]]` must be refused by name (several robots are not one rapier world),
/// as a differential drive under the dynamic law.
fn fly_rapier(file: &Path, model: Model) -> Outcome {
    let run = if FileKind::of(file).map_err(|e| e.to_string())? == FileKind::FloorPlan {
        let prepared = FloorScenario::load(file).map_err(|e| e.to_string())?;
        let start = Vector2::from(prepared.scenario.robot.start);
        let margin = prepared.scenario.robot.margin;
        simulate_floor(&prepared, Some(model), start, Physics::Rapier)
            .map(|run| FloorSummary::new(&prepared, Some(model), start, &run))
            .map(|s| (s.reached, s.time_s, s.guarantees, s.movers, margin))
    } else {
        let prepared = Scenario::load(file).map_err(|e| e.to_string())?;
        let margin = prepared.margin();
        simulate(&prepared, Some(model), Physics::Rapier).map(|r| {
            let s = r.summary;
            (s.reached, s.time_s, s.guarantees, s.movers, margin)
        })
    };
    let (reached, time_s, guarantees, movers, margin) = match run {
        Err(e @ harmonav_sim::summary::RunError::RobotsInRapier) => {
            return Ok(Verdict::Held(format!("refused: {e}")));
        }
        Err(e) if e.to_string().contains("base") && model == Model::Dynamic => {
            return Ok(Verdict::Held(format!("refused: {e}")));
        }
        Err(e) => return Err(e.to_string()),
        Ok(run) => run,
    };
    let m = movers.ok_or("no mover report")?;
    let detail = detail(reached, time_s, &m, margin);
    let failed = failed_names(&guarantees);
    if !failed.is_empty() || m.mover_contacts > 0 {
        return Err(format!("{detail}; failed: {failed:?}"));
    }
    Ok(Verdict::Held(detail))
}

/// A run with `[[robots]]`, star world or floor plan (the first robot's arrival `reached` at
/// `time_s`, its `guarantees`): every guarantee held, every robot arrived safe, no two robots
/// touched.
fn fleet(
    f: &FleetReport,
    reached: bool,
    time_s: f64,
    guarantees: &[Guarantee],
    margin: f64,
) -> Outcome {
    let detail = format!(
        "{} robots: all reached {}, last at {:.2} s; {} contacts between robots, min \
         clearance between two {:.3} m (margin {margin} m)",
        f.others.len() + 1,
        reached && f.others.iter().all(|o| o.reached),
        f.others.iter().map(|o| o.time_s).fold(time_s, f64::max),
        f.robot_contacts,
        f.min_robot_clearance,
    );
    let failed = failed_names(guarantees);
    let others_failed = f.others.iter().any(|o| !(o.reached && o.safe));
    if !failed.is_empty() || others_failed || f.robot_contacts > 0 {
        return Err(format!("{detail}; failed: {failed:?}"));
    }
    Ok(Verdict::Held(detail))
}

/// A mover run's verdict: a failed guarantee fails it (`no-collision-with-movers` fails on a
/// contact after a certified command: Theorem 1 broken); a contact only after `Overwhelmed`
/// or refused commands (passive safety, which the theorem allows) is issue 54's "0 contacts"
/// not met, a [`Verdict::Target`]; else it held.
fn judged(detail: &str, m: &MoverReport, guarantees: &[Guarantee]) -> Outcome {
    let failed = failed_names(guarantees);
    if !failed.is_empty() || m.contacts_after_certified > 0 {
        return Err(format!("{detail}; failed: {failed:?}"));
    }
    if m.mover_contacts > 0 {
        return Ok(Verdict::Target(format!(
            "{detail}; every contact after an uncertified command (passive safety)"
        )));
    }
    Ok(Verdict::Held(detail.to_string()))
}

/// What a mover run measured, for its line in the verify table.
fn detail(reached: bool, time_s: f64, m: &MoverReport, margin: f64) -> String {
    format!(
        "reached {reached} in {time_s:.2} s; commands: {} certified ({} yielding), {} \
         overwhelmed, {} refused; {} contacts; min mover clearance {:.3} m (margin {margin} m)",
        m.certified_commands,
        m.yielding_commands,
        m.overwhelmed_commands,
        m.refused_commands,
        m.mover_contacts,
        m.min_mover_clearance,
    )
}

/// A floor plan with movers under `model` (its `robot.start`): every guarantee holds and no
/// mover touches the robot.
fn fly_floor(file: &Path, model: Model) -> Outcome {
    let prepared = FloorScenario::load(file).map_err(|e| e.to_string())?;
    let start = Vector2::from(prepared.scenario.robot.start);
    let run = simulate_floor(&prepared, Some(model), start, Physics::Builtin)
        .map_err(|e| e.to_string())?;
    let s = FloorSummary::new(&prepared, Some(model), start, &run);
    let margin = prepared.scenario.robot.margin;
    if let Some(f) = &s.fleet {
        return fleet(f, s.reached, s.time_s, &s.guarantees, margin);
    }
    let m = s.movers.as_ref().ok_or("no mover report")?;
    let detail = detail(s.reached, s.time_s, m, margin);
    judged(&detail, m, &s.guarantees)
}

/// A negative control: `file` run without the filter must fail the guarantee `guarantee`, with
/// `contacts` (from the summary) above 0; `detail` says what was measured.
fn must_fail(
    file: &str,
    guarantee: &str,
    measure: impl Fn(&harmonav_sim::summary::Summary) -> Option<(usize, String)>,
) -> Outcome {
    let prepared = Scenario::load(&folder().join(file)).map_err(|e| e.to_string())?;
    let run = run_without_filter(&prepared, None).map_err(|e| e.to_string())?;
    let (contacts, detail) = measure(&run.summary).ok_or("no mover or fleet report")?;
    let judged = run
        .summary
        .guarantees
        .iter()
        .find(|g| g.name() == guarantee)
        .is_some_and(|g| !g.passed);
    if contacts == 0 || !judged {
        return Err(format!("the negative control saw no failure: {detail}"));
    }
    Ok(Verdict::Held(detail))
}

/// The crossing with `[robot] comfort = 0.6` (docs/movers.md §7, "Comfort"): every guarantee
/// held, arrived, no contact, and the person kept at least `margin + 0.9·c` away; the file as
/// it is (its own negative control) lets the person closer than that.
fn comfort() -> Outcome {
    const COMFORT: f64 = 0.6;
    let mut prepared =
        Scenario::load(&folder().join("person-crossing.toml")).map_err(|e| e.to_string())?;
    let fly = |prepared: &harmonav_scenario::Prepared| {
        let run = simulate(prepared, None, Physics::Builtin).map_err(|e| e.to_string())?;
        let m = run.summary.movers.clone().ok_or("no mover report")?;
        Ok::<_, String>((run.summary, m))
    };
    let (_, plain) = fly(&prepared)?;
    prepared.scenario.controller.comfort = COMFORT;
    let (s, m) = fly(&prepared)?;
    let kept = prepared.margin() + 0.9 * COMFORT;
    let detail = format!(
        "comfort {COMFORT} m: {}; without: min mover clearance {:.3} m",
        detail(s.reached, s.time_s, &m, prepared.margin()),
        plain.min_mover_clearance
    );
    let failed = failed_names(&s.guarantees);
    if !failed.is_empty()
        || !s.reached
        || m.mover_contacts > 0
        || m.min_mover_clearance < kept
        || plain.min_mover_clearance >= kept
    {
        return Err(format!("{detail}; failed: {failed:?}"));
    }
    Ok(Verdict::Held(detail))
}

/// The negative control: the crossing with the robot blind to the person touches them, and
/// `no-collision-with-movers` fails.
fn blind() -> Outcome {
    must_fail("person-crossing.toml", "no-collision-with-movers", |s| {
        let m = s.movers.as_ref()?;
        let detail = format!(
            "without set_movers: {} contacts, min mover clearance {:.3} m",
            m.mover_contacts, m.min_mover_clearance
        );
        Some((m.mover_contacts, detail))
    })
}

/// The negative control of a differential drive among movers: the robot of
/// `diff-walkers.toml` never given the movers (its arcs certified against the known shapes
/// only) runs into the person it should follow, and `no-collision-with-movers` fails.
fn blind_diff() -> Outcome {
    must_fail("diff-walkers.toml", "no-collision-with-movers", |s| {
        let m = s.movers.as_ref()?;
        let detail = format!(
            "differential drive without set_movers: {} contacts, min mover clearance {:.3} m",
            m.mover_contacts, m.min_mover_clearance
        );
        Some((m.mover_contacts, detail))
    })
}

/// The negative control of the fleet: the four robots blind to each other collide, and
/// `no-collision-between-robots` fails.
fn blind_robots() -> Outcome {
    must_fail(
        "four-robots-swap.toml",
        "no-collision-between-robots",
        |s| {
            let f = s.fleet.as_ref()?;
            let detail = format!(
                "robots blind to each other: {} contacts, min clearance between two {:.3} m",
                f.robot_contacts, f.min_robot_clearance
            );
            Some((f.robot_contacts, detail))
        },
    )
}

/// The negative control of a floor plan's fleet: the four robots of `floor-corridor-swap.toml`
/// blind to each other meet in the corridor, and `no-collision-between-robots` fails.
fn blind_floor_robots() -> Outcome {
    let file = folder().join("floor-corridor-swap.toml");
    let prepared = FloorScenario::load(&file).map_err(|e| e.to_string())?;
    let start = Vector2::from(prepared.scenario.robot.start);
    let run = harmonav_sim::floor::run_without_filter(&prepared, None, start)
        .map_err(|e| e.to_string())?;
    let s = FloorSummary::new(&prepared, None, start, &run);
    let f = s.fleet.as_ref().ok_or("no fleet report")?;
    let detail = format!(
        "robots blind to each other: {} contacts, min clearance between two {:.3} m",
        f.robot_contacts, f.min_robot_clearance
    );
    let judged = s
        .guarantees
        .iter()
        .find(|g| g.name() == "no-collision-between-robots")
        .is_some_and(|g| !g.passed);
    if f.robot_contacts == 0 || !judged {
        return Err(format!("the negative control saw no failure: {detail}"));
    }
    Ok(Verdict::Held(detail))
}
