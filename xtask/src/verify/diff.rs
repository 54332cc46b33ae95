//! The differential-drive scenarios (`scenarios/diff/`, issue 53, item 4; docs/unicycle.md,
//! "Simulator"): every file flown built-in (the exact unicycle arcs of `command_pose`, each
//! judged) and in rapier (the body driven along its heading), with the file's start yaw. Every
//! guarantee must hold, arrival included, with 0 rapier contacts; the line compares the run
//! with the holonomic robot of the same file (the base's keys removed).

use std::path::{Path, PathBuf};

use harmonav_scenario::{BaseKind, Scenario};
use harmonav_sim::physics::{Physics, simulate};

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
/// contact; the holonomic robot of the same file for comparison.
fn fly(file: &Path, physics: Physics) -> Outcome {
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
