//! Which integrator moves the robot ([`Physics`]), and the run with the scenario's warnings
//! ([`simulate`]), or of a floor plan ([`simulate_floor`]): what the CLI, the bindings and
//! `cargo xtask verify` call.

use crate::driver::{Driver, Warnings};
use crate::run::integrate;
pub use crate::summary::Physics;
use crate::summary::{Run, RunError};
use crate::trace::Event;
use crate::warning::Warning;
use harmonav_scenario::floorplan::FloorPrepared;
use harmonav_scenario::{Model, Prepared};
use nalgebra::Vector2;

use crate::floor::{self, FloorRun};

/// Runs the scenario with `model` (or the file's) under `physics`: the built-in run, or the
/// rapier run with the built-in run as the reference of its deviation guarantee, with the
/// scenario's warnings ([`warnings`]).
pub fn simulate(
    prepared: &Prepared,
    model: Option<Model>,
    physics: Physics,
) -> Result<Run, RunError> {
    simulate_observed(prepared, model, physics, &mut |_| {})
}

/// [`simulate`], handing the warnings first, then every recorded state and discovery of the
/// run it returns (the built-in or the rapier one) to `observer` as they are made: a recording
/// streamed to disk this way holds every state, whatever the run's length.
pub fn simulate_observed(
    prepared: &Prepared,
    model: Option<Model>,
    physics: Physics,
    observer: &mut dyn FnMut(Event<'_>),
) -> Result<Run, RunError> {
    match physics {
        Physics::Builtin => integrate(prepared, model, Warnings::Find, observer),
        Physics::Rapier if !prepared.scenario.sim.robots.is_empty() => {
            Err(RunError::RobotsInRapier)
        }
        #[cfg(feature = "rapier")]
        Physics::Rapier => {
            use crate::rapier::{Drive, rapier_observed};
            let builtin = integrate(prepared, model, Warnings::Skip, &mut |_| {})?;
            let (run, _) = rapier_observed(
                prepared,
                model,
                Drive::Law,
                Some(&builtin),
                Warnings::Find,
                observer,
            )?;
            Ok(run)
        }
        #[cfg(not(feature = "rapier"))]
        Physics::Rapier => Err(RunError::NoRapier),
    }
}

/// Runs a floor plan from `start` with `model` (or the file's) under `physics`: the built-in
/// loop ([`crate::floor::run`]), or its rapier cross-check with the built-in run as the
/// reference of its deviation (`rapier::run_floor_rapier`), as [`simulate`] does in a star
/// world.
///
/// # Errors
/// The navigator could not be built ([`RunError::Navigator`]), or rapier was asked of a build
/// without it ([`RunError::NoRapier`]).
pub fn simulate_floor(
    prepared: &FloorPrepared,
    model: Option<Model>,
    start: Vector2<f64>,
    physics: Physics,
) -> Result<FloorRun, RunError> {
    floor_with(prepared, model, start, physics, None)
}

/// [`simulate_floor`], handing every state, scan and discovery of the run it returns (the
/// built-in or the rapier one) to `observer` as they are made ([`floor::run_observed`]): what
/// a floor plan's `run.mcap` streams from.
///
/// # Errors
/// As [`simulate_floor`].
pub fn simulate_floor_observed(
    prepared: &FloorPrepared,
    model: Option<Model>,
    start: Vector2<f64>,
    physics: Physics,
    observer: &mut dyn FnMut(Event<'_>),
) -> Result<FloorRun, RunError> {
    floor_with(prepared, model, start, physics, Some(observer))
}

fn floor_with(
    prepared: &FloorPrepared,
    model: Option<Model>,
    start: Vector2<f64>,
    physics: Physics,
    observer: Option<&mut dyn FnMut(Event<'_>)>,
) -> Result<FloorRun, RunError> {
    match (physics, observer) {
        (Physics::Rapier, _) if !prepared.scenario.robots.is_empty() => {
            Err(RunError::RobotsInRapier)
        }
        (Physics::Builtin, None) => Ok(floor::run(prepared, model, start)?),
        (Physics::Builtin, Some(observer)) => {
            Ok(floor::run_observed(prepared, model, start, observer)?)
        }
        #[cfg(feature = "rapier")]
        (Physics::Rapier, observer) => {
            use crate::rapier::{Drive, rapier_floor_observed};
            let (_, states) = floor::run_with_states(prepared, model, start)?;
            let (run, _) =
                rapier_floor_observed(prepared, model, start, Drive::Law, Some(&states), observer)?;
            Ok(run)
        }
        #[cfg(not(feature = "rapier"))]
        (Physics::Rapier, _) => Err(RunError::NoRapier),
    }
}

/// The warnings a run of `prepared` with `model` (or the file's) would start with: what
/// [`crate::preflight::check`] finds on the field the robot knows at `t = 0`.
///
/// # Errors
/// The run could not start ([`RunError`]).
pub fn warnings(prepared: &Prepared, model: Option<Model>) -> Result<Vec<Warning>, RunError> {
    let mut found = Vec::new();
    Driver::start(prepared, model, None, 0.0, Warnings::Find, &mut |e| {
        if let Event::Warning(w) = e {
            found.push(w.clone());
        }
    })?;
    Ok(found)
}
