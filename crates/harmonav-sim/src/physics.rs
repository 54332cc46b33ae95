//! Which integrator moves the robot ([`Physics`]), and the run with the scenario's warnings
//! ([`simulate`]): what the CLI, the bindings and `cargo xtask verify` call.

use crate::run::run_observed;
pub use crate::summary::Physics;
use crate::summary::{Run, RunError};
use crate::trace::Event;
use harmonav_scenario::{Model, Prepared};

/// Runs the scenario with `model` (or the file's) under `physics`: the built-in run, or the
/// rapier run with the built-in run as the reference of its deviation guarantee, with the
/// scenario's warnings ([`crate::preflight::check`]).
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
    let warnings = crate::preflight::check(prepared, model)?;
    for w in &warnings {
        observer(Event::Warning(w));
    }
    let mut result = match physics {
        Physics::Builtin => run_observed(prepared, model, observer)?,
        #[cfg(feature = "rapier")]
        Physics::Rapier => {
            use crate::rapier::{Drive, rapier_observed};
            let builtin = run_observed(prepared, model, &mut |_| {})?;
            rapier_observed(prepared, model, Drive::Law, Some(&builtin), observer)?.0
        }
        #[cfg(not(feature = "rapier"))]
        Physics::Rapier => return Err(RunError::NoRapier),
    };
    result.summary.warnings = warnings;
    Ok(result)
}
