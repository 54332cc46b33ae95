//! The rapier2d cross-check of a floor plan (issue 25; docs/maths.md §13, "The rapier
//! cross-check"): the loop of [`crate::floor::run`] with rapier as its integrator. The true
//! walls (the outer ring and every hole of the floor plan as given, not the shrunk `W_s`) are
//! one static polyline collider whose index buffer closes each ring; each sensed obstacle is
//! a static collider as in a star world (`rapier/engine.rs`); the robot is the dynamic
//! ball of the star-world harness, driven by the floor navigator's command (its velocity for
//! the kinematic model, a force for the dynamic one; a differential drive's `(v, ω)` along
//! its body's heading), held over the control period in rapier steps of at most 1 ms. Contacts are counted as in a star world
//! (`Engine::step`, shared), and the monitors of the built-in loop judge the states
//! rapier makes.

use harmonav::NavError;
use harmonav_scenario::Model;
use harmonav_scenario::floorplan::FloorPrepared;
use nalgebra::Vector2;

use super::engine::{Engine, rings, star};
use super::{Drive, RapierReport};
use crate::floor::{FloorRun, Held, Moved, fly, navigator};
use crate::summary::Physics;
use crate::trace::Event;

pub use crate::floor::FloorLaw;

/// Runs the floor plan's loop from `start` under `model` (the file's by default) in rapier,
/// driven by `drive`. `builtin`, the states of a built-in run of the same model and start at
/// every control period ([`crate::floor::run_with_states`]), is the reference of the
/// deviation: the state after `n` periods is compared with `builtin[n]` (the same times).
/// The run's [`FloorRun::contacts`] and [`FloorRun::max_deviation`] become the guarantees
/// `physics-no-contact` and `physics-deviation` of its [`crate::floor::FloorSummary`].
///
/// A differential drive's body turns: at every rapier step its velocity is set to `v·e(θ)`
/// along its heading now and its turn rate to `ω` (`Engine::drive_unicycle`, as in a star
/// world), and each period's arc is judged from the pose rapier made.
///
/// # Errors
/// The navigator could not be built (a message naming the parameter).
pub fn run_floor_rapier(
    prepared: &FloorPrepared,
    model: Option<Model>,
    start: Vector2<f64>,
    drive: Drive<FloorLaw<'_>>,
    builtin: Option<&[Vector2<f64>]>,
) -> Result<(FloorRun, RapierReport), NavError> {
    rapier_floor_observed(prepared, model, start, drive, builtin, None)
}

/// [`run_floor_rapier`], handing the run's events to `observer` as
/// [`crate::floor::run_observed`] does.
pub(crate) fn rapier_floor_observed(
    prepared: &FloorPrepared,
    model: Option<Model>,
    start: Vector2<f64>,
    drive: Drive<FloorLaw<'_>>,
    builtin: Option<&[Vector2<f64>]>,
    observer: Option<&mut dyn FnMut(Event<'_>)>,
) -> Result<(FloorRun, RapierReport), NavError> {
    let r = &prepared.scenario.robot;
    let model = model.unwrap_or(r.model);
    let period = navigator(prepared, Some(model))?.control_period();
    // rapier's fixed step, at most 1 ms; the command is held over the control period.
    let substeps = (period / 1e-3).ceil().max(1.0) as usize;
    let floor = &prepared.floor;
    // The walls (wall 0: every ring of the true plan), then the obstacles; the exact gap from
    // `x` to each (positive in the free space).
    let gap = |i: usize, x: Vector2<f64>| match i.checked_sub(1) {
        None => floor.walls().signed_distance(x),
        Some(j) => prepared.obstacles[j].signed_distance(x),
    };
    let walls = floor.walls();
    let colliders = std::iter::once(rings(
        std::iter::once(walls.outer())
            .chain(walls.holes().iter().map(Vec::as_slice))
            .map(|ring| ring.iter().copied()),
    ))
    .chain(prepared.obstacles.iter().map(|o| star(o, true)));
    let mut engine = Engine::new(
        period / substeps as f64,
        colliders,
        (start, r.radius, r.mass),
        &gap,
    );
    // A differential drive: the body turns, driven along its heading at every step.
    if prepared.base().is_some() {
        engine.set_yaw(prepared.start_yaw());
    }
    let (mut steps, mut max_deviation) = (0usize, 0.0f64);
    let mut hold = |held: &Held| {
        if held.pose.is_none() {
            engine.drive(model, held.command);
        }
        for _ in 0..substeps {
            if let Some(p) = held.pose {
                engine.drive_unicycle(p.v, p.omega);
            }
            engine.step(&gap);
        }
        steps += 1;
        let (x, v) = engine.state();
        if let Some(reference) = builtin.and_then(|b| b.get(steps)) {
            max_deviation = max_deviation.max((x - reference).norm());
        }
        Moved {
            x,
            v,
            yaw: held.pose.map(|_| engine.yaw()),
        }
    };
    let custom = match drive {
        Drive::Law => None,
        Drive::Custom(law) => Some(law),
    };
    let mut run = fly(prepared, Some(model), start, custom, &mut hold, observer)?;
    let contacts = engine.contacts();
    run.physics = Physics::Rapier;
    run.contacts = Some(contacts);
    run.max_deviation = builtin.map(|_| max_deviation);
    Ok((
        run,
        RapierReport {
            contacts,
            max_deviation,
        },
    ))
}
