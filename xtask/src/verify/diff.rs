//! The differential-drive scenarios (`scenarios/diff/`, issue 53, item 4; docs/unicycle.md,
//! "Simulator"): every file flown built-in (the exact unicycle arcs of `command_pose`, each
//! judged) and in rapier (the body driven along its heading), with the file's start yaw. Every
//! guarantee must hold, arrival included, with 0 rapier contacts; the line compares the run
//! with the holonomic robot of the same file (the base's keys removed).

use std::path::{Path, PathBuf};

use harmonav_scenario::floorplan::{FileKind, FloorScenario};
use harmonav_scenario::{BaseKind, Scenario};
use harmonav_sim::floor::FloorSummary;
use harmonav_sim::physics::{Physics, simulate, simulate_floor};

use super::movers::{failed_names, per_file, toml_files};
use super::{Check, Outcome, Verdict};

fn folder() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenarios")
        .join(harmonav_scenario::DIFF)
}

pub fn checks() -> Vec<Check> {
    let files = toml_files(&folder());
    let physics = [Physics::Builtin, Physics::Rapier].map(|p| (p, p.as_str()));
    per_file(&files, "diff", &physics, fly)
}

/// One file under `physics`: every guarantee holds, the robot arrives, rapier sees no
/// contact; the holonomic robot of the same file for comparison. A floor plan goes to
/// [`fly_floor`].
fn fly(file: &Path, physics: Physics) -> Outcome {
    if FileKind::of(file).map_err(|e| e.to_string())? == FileKind::FloorPlan {
        return fly_floor(file, physics);
    }
    let prepared = Scenario::load(file).map_err(|e| e.to_string())?;
    if prepared.base().is_none() {
        return Err("not a differential-drive file (`[robot] base = \"diff\"`)".into());
    }
    let run = simulate(&prepared, None, physics).map_err(|e| e.to_string())?;
    let s = &run.summary;
    let d = s.diff.as_ref().ok_or("no differential-drive report")?;
    // The same file with a holonomic robot (the built-in integrator).
    let mut holonomic = prepared.scenario.clone();
    holonomic.controller.base = BaseKind::Holonomic;
    (holonomic.controller.omega_max, holonomic.controller.yaw) = (None, None);
    (holonomic.controller.a_max, holonomic.controller.alpha_max) = (None, None);
    let reference = holonomic
        .prepare(file)
        .map_err(|e| e.to_string())
        .and_then(|p| simulate(&p, None, Physics::Builtin).map_err(|e| e.to_string()))?
        .summary;
    let contacts = s.physics_contacts.unwrap_or(0);
    let detail = format!(
        "reached {} in {:.2} s ({:.2}× the holonomic robot's {:.2} s), path {:.3} m ({:.3}× \
         its), swept clearance {:.4} m, v ≤ {:.3}, |ω| ≤ {:.3}; {} ahead / {} shortened / {} \
         turning; {contacts} contacts",
        s.reached,
        s.time_s,
        s.time_s / reference.time_s,
        reference.time_s,
        s.path_length,
        s.path_length / reference.path_length,
        d.swept_clearance,
        d.max_v,
        d.max_omega,
        d.ahead,
        d.shortened,
        d.turning,
    );
    let failed = failed_names(&s.guarantees);
    if !failed.is_empty() || !s.reached || contacts > 0 {
        return Err(format!("{detail}; failed: {failed:?}"));
    }
    Ok(Verdict::Held(detail))
}

/// A floor plan with a differential drive under `physics`: every start (`robot.start` and the
/// file's `[starts]`) arrives with every guarantee (rapier: with 0 contacts), against the
/// holonomic robot of the same file (built-in).
fn fly_floor(file: &Path, physics: Physics) -> Outcome {
    let prepared = FloorScenario::load(file).map_err(|e| e.to_string())?;
    if prepared.base().is_none() {
        return Err("not a differential-drive file (`[robot] base = \"diff\"`)".into());
    }
    let mut holonomic = prepared.scenario.clone();
    holonomic.robot.base = BaseKind::Holonomic;
    (holonomic.robot.omega_max, holonomic.robot.yaw) = (None, None);
    (holonomic.robot.a_max, holonomic.robot.alpha_max) = (None, None);
    let reference = holonomic.prepare(file).map_err(|e| e.to_string())?;
    let (mut worst, mut ratios, mut swept) = (Vec::new(), Vec::new(), f64::INFINITY);
    let mut contacts = 0;
    for &start in &prepared.starts {
        let run = simulate_floor(&prepared, None, start, physics).map_err(|e| e.to_string())?;
        let s = FloorSummary::new(&prepared, None, start, &run);
        let failed = failed_names(&s.guarantees);
        contacts += s.physics_contacts.unwrap_or(0);
        if !failed.is_empty() || !s.reached {
            worst.push(format!("({:.2}, {:.2}): {failed:?}", start.x, start.y));
            continue;
        }
        swept = swept.min(s.swept_clearance);
        let holo =
            simulate_floor(&reference, None, start, Physics::Builtin).map_err(|e| e.to_string())?;
        ratios.push(s.time_s / holo.time);
    }
    ratios.sort_by(f64::total_cmp);
    let detail = format!(
        "{} of {} starts reached with every guarantee; time over the holonomic robot's: median \
         {:.2}, max {:.2}; swept clearance ≥ {swept:.4} m; {contacts} contacts",
        ratios.len(),
        prepared.starts.len(),
        ratios.get(ratios.len() / 2).copied().unwrap_or(f64::NAN),
        ratios.last().copied().unwrap_or(f64::NAN),
    );
    if !worst.is_empty() {
        return Err(format!("{detail}; failed: {}", worst.join(", ")));
    }
    Ok(Verdict::Held(detail))
}
