//! Which integrator moves the robot ([`Physics`]), and the run with the scenario's warnings
//! ([`simulate`]): what the CLI, the bindings and `cargo xtask verify` call.

use harmonav_scenario::{Model, Prepared};
use serde::{Deserialize, Serialize};

use crate::run::run_observed;
use crate::summary::{Run, RunError};
use crate::trace::Event;

/// Which integrator moves the robot.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Physics {
    /// The built-in adaptive integrator ([`crate::run::run`]).
    #[default]
    Builtin,
    /// rapier2d, cross-checked against a built-in run of the same model (`rapier::run_rapier`;
    /// needs the crate's feature `rapier`, else [`RunError::NoRapier`]).
    Rapier,
}

impl std::str::FromStr for Physics {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "builtin" => Ok(Self::Builtin),
            "rapier" => Ok(Self::Rapier),
            other => Err(format!(
                "unknown physics \"{other}\": expected \"builtin\" or \"rapier\""
            )),
        }
    }
}

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
