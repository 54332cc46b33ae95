//! The options several commands share, and loading the scenario they name.

use std::path::Path;

use clap::ValueEnum;
use harmonav_control::DampingPolicy;
use harmonav_field::KPolicy;
use harmonav_scenario::{Model, Prepared, Scenario};
use harmonav_sim::physics::Physics;

use crate::error::CliError;

/// `--model` (alias `--controller`): overrides the scenario's robot model (`[robot] model`).
#[derive(Clone, Copy, ValueEnum)]
pub enum ModelArg {
    /// `ẋ = u` under the kinematic law.
    Kinematic,
    /// `m ẍ = f` under the dynamic law.
    Dynamic,
}

/// `--k`: overrides the scenario's `[field] k`.
#[derive(Clone, Copy, ValueEnum)]
pub enum KArg {
    /// `k = n + 1`, exactly the paper.
    Paper,
    /// The default: `k` from the known world (docs/maths.md §8).
    Auto,
}

impl From<KArg> for KPolicy {
    fn from(k: KArg) -> Self {
        match k {
            KArg::Paper => KPolicy::Paper,
            KArg::Auto => KPolicy::Auto,
        }
    }
}

/// `--damping`: overrides the scenario's `[controller] damping`.
#[derive(Clone, Copy, ValueEnum)]
pub enum DampingArg {
    /// Eq. `dissipationfun` on Θ, exactly the paper.
    Paper,
    /// Damping critical at the goal, on the shaped potential Ψ = 1 − √(1 − Θ) (docs/maths.md
    /// §9), tuned in 5 m worlds: the default until 2026-12.
    Shaped,
    /// "shaped" on Θ made free of the world's scale, so the robot is as quick in a 100 m world
    /// as in a 5 m one (docs/maths.md §9): the default until 2026-12-03.
    Auto,
    /// A research policy: a goal bowl a braking distance wide and a ramp as long as the world
    /// (docs/maths.md §9, "fast").
    Fast,
    /// The default: "auto" with the pull 4μ·max(1, ρ/5 m) (ρ the world's radius), so that the
    /// robot uses the whole speed bound √(2μ/m) in a world of any size, and a governor that
    /// keeps it below 0.9·√(2μ/m) (docs/maths.md §9, part 5).
    Governed,
}

impl From<DampingArg> for DampingPolicy {
    fn from(d: DampingArg) -> Self {
        match d {
            DampingArg::Paper => DampingPolicy::Paper,
            DampingArg::Shaped => DampingPolicy::Shaped,
            DampingArg::Auto => DampingPolicy::Auto,
            DampingArg::Fast => DampingPolicy::Fast,
            DampingArg::Governed => DampingPolicy::Governed,
        }
    }
}

/// `--physics`: the integrator.
#[derive(Clone, Copy, ValueEnum, PartialEq)]
pub enum PhysicsArg {
    /// The built-in integrator.
    Builtin,
    /// The rapier2d cross-check.
    Rapier,
}

impl From<PhysicsArg> for Physics {
    fn from(p: PhysicsArg) -> Self {
        match p {
            PhysicsArg::Builtin => Physics::Builtin,
            PhysicsArg::Rapier => Physics::Rapier,
        }
    }
}

/// The model `--model` asks for, if any.
pub fn model(c: Option<ModelArg>) -> Option<Model> {
    c.map(|c| match c {
        ModelArg::Kinematic => Model::Kinematic,
        ModelArg::Dynamic => Model::Dynamic,
    })
}

/// Loads and validates a scenario; `k` and `damping` override its `[field] k` and
/// `[controller] damping` policies.
pub fn load(
    path: &Path,
    k: Option<KArg>,
    damping: Option<DampingArg>,
) -> Result<Prepared, CliError> {
    if path == Path::new("-") {
        return Err(CliError::Stdin);
    }
    let mut prepared = Scenario::load(path)?;
    if let Some(k) = k {
        prepared.scenario.field.k = k.into();
    }
    if let Some(d) = damping {
        prepared.scenario.controller.damping = d.into();
    }
    Ok(prepared)
}
