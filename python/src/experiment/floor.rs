//! Floor-plan files in a batch (issue 51, item 4): a `[floor_plan]` world prepared once (its
//! harmonic map solved), each run through the library path of `harmonav run` on a floor plan
//! (`physics::simulate_floor`), judged by `FloorSummary` and named by the sweep's
//! `floor_outcome` (a failed safety verdict is never reached), into the record a star world's
//! run makes.
//!
//! What differs from a star world, said in the record: the reference path is the grid geodesic
//! in `W_δ` towards the goal (`harmonav::floorplan::geodesic`, the walls only, computed once
//! per world and only when asked), `steps` counts commands (one per control period) and
//! `rejected_steps` is 0, `recorded_states` counts the kept positions, the overshoot is
//! measured on them, `collisions` is 1 for a run that ended in a collision (a floor-plan run
//! stops there) and `warnings` is empty; `effective.sensing` is `"range"` (obstacles known
//! within `sim.sensor_range`) or `"lidar"` (`[sensor] type = "lidar"`). The spec's `sensing`
//! and `law = "descent"` are star-world settings and are refused by name.

use std::path::Path;
use std::sync::OnceLock;

use harmonav_bench::quality::overshoot_of;
use harmonav_rs::Vector2;
use harmonav_rs::floorplan::geodesic::Geodesic;
use harmonav_scenario::Model;
use harmonav_scenario::floorplan::{FloorPrepared, FloorScenario};
use harmonav_sim::floor::FloorSummary;
use harmonav_sim::outcome::{Outcome, StartProblem};
use harmonav_sim::physics::simulate_floor;
use harmonav_sim::sweep::{check_count, floor_outcome};

use super::{Config, Effective, Keys, Measured, Ran, held};

/// A floor-plan world as prepared, and its reference geodesic once a run asked for it.
pub(super) struct FloorWorld {
    prepared: FloorPrepared,
    geodesic: OnceLock<Geodesic>,
}

/// The floor plan of `text` (read from `path`, which anchors a `map`'s files and names it in
/// errors) with `c`'s overrides: `k`, `damping`, `speed`, `margin` and `max_time` set the same
/// keys as in a star world (`[field] k`, `[controller]`, `[robot] margin`, `[sim] max_time`).
pub(super) fn prepare(c: &Config, path: &Path, text: &str) -> Result<FloorWorld, String> {
    if c.descent {
        return Err(format!(
            "model: \"descent\" follows Θ with every obstacle known in a star world \
             (harmonav_sim::descent); {} is a floor plan: give \"kinematic\" or \"dynamic\"",
            path.display()
        ));
    }
    if c.sensing.is_some() {
        return Err(format!(
            "sensing: \"global\" and \"sector\" are star-world settings; {} is a floor plan, \
             which senses its obstacles within sim.sensor_range or by its [sensor] lidar",
            path.display()
        ));
    }
    let mut s = FloorScenario::parse(path, text).map_err(|e| e.to_string())?;
    c.set_keys(Keys {
        k: &mut s.field.k,
        damping: &mut s.controller.damping,
        speed: &mut s.controller.speed,
        margin: &mut s.robot.margin,
        max_time: &mut s.sim.max_time,
    });
    let prepared = s.prepare(path).map_err(|e| e.to_string())?;
    Ok(FloorWorld {
        prepared,
        geodesic: OnceLock::new(),
    })
}

/// The configuration of `c` on the floor plan `p` (its own values filling the gaps).
fn effective(p: &FloorPrepared, c: &Config) -> Effective {
    let s = &p.scenario;
    let kinematic = c.model.unwrap_or(s.robot.model) == Model::Kinematic;
    Effective {
        model: if kinematic {
            Model::Kinematic.as_str()
        } else {
            Model::Dynamic.as_str()
        },
        k: s.field.k.as_str(),
        damping: (!kinematic).then(|| s.controller.damping.as_str()),
        speed: kinematic.then(|| s.controller.speed.as_str()),
        sensing: if p.lidar.is_some() { "lidar" } else { "range" },
        margin: s.robot.margin,
        max_time: s.sim.max_time,
        obstacles: p.obstacles.len(),
    }
}

/// Runs `c` on the floor plan of `w`: from `c.start` (checked as `robot.start` is, an invalid
/// one an `invalid-start` record) or the file's `robot.start`.
pub(super) fn run(c: &Config, w: &FloorWorld) -> Result<Ran, String> {
    let p = &w.prepared;
    let start = match c.start {
        Some([x, y]) => {
            let start = Vector2::new(x, y);
            if let Err(problem) = p.check_start(start) {
                let outcome = Outcome::InvalidStart {
                    index: c.start_index,
                    problem: StartProblem::NotCertified { problem },
                };
                return Ok(Ran::Invalid(outcome, [x, y], effective(p, c)));
            }
            start
        }
        None => p.starts[0],
    };
    let run = simulate_floor(p, c.model, start, c.physics).map_err(|e| e.to_string())?;
    let s = FloorSummary::new(p, c.model, start, &run);
    let goal = Vector2::from(p.scenario.robot.goal);
    let shortest = if c.shortest {
        w.geodesic
            .get_or_init(|| Geodesic::new(&p.floor, goal))
            .distance(start)
    } else {
        None
    };
    let outcome = floor_outcome(&s, &run);
    Ok(Ran::Run(
        Box::new(Measured {
            reached: s.reached,
            collisions: usize::from(outcome == Outcome::Collision),
            outcome,
            time_s: s.time_s,
            final_distance: s.final_distance,
            path_length: s.path_length,
            shortest,
            min_clearance: s.min_clearance,
            max_speed: s.max_speed,
            speed_bound: s.speed_bound,
            discoveries: s.discoveries.len(),
            steps: s.commands,
            rejected_steps: 0,
            recorded_states: run.positions.len(),
            overshoot: overshoot_of(run.positions.iter().copied(), goal),
            guarantees_held: held(&s.guarantees),
            all_passed: s.all_passed(),
            k_policy: s.k_policy.as_str(),
            guarantees: serde_json::to_string(&s.guarantees).map_err(|e| e.to_string())?,
            warnings: Vec::new(),
            start: [start.x, start.y],
        }),
        effective(p, c),
    ))
}

/// `count` seeded starts of the floor plan of `w`, drawn as its `[starts]` are
/// (`FloorPrepared::random_starts`): at most the sweep's `MAX_STARTS`.
pub(super) fn random_starts(
    w: &FloorWorld,
    count: usize,
    seed: u64,
) -> Result<Vec<Vector2<f64>>, String> {
    check_count(count).map_err(|e| format!("starts: {e}"))?;
    w.prepared
        .random_starts(count, seed)
        .map_err(|e| format!("starts: {e}"))
}
