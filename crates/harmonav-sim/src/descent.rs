//! The normalised descent of `Θ` judged as a run: the flow line `ẋ = −∇Θ/|∇Θ|` of the
//! kinematic law (eq. `holint` at unit speed, every obstacle known), integrated by
//! [`harmonav_field::descent::follow`] from a start to the goal, a critical point, the time
//! budget or a step-size collapse. Its time is its path length.
//!
//! It is what `cargo xtask verify`'s Monte-Carlo study (`montecarlo.*`) and the experiment
//! runner's `law = "descent"` (`harmonav.run_batch`) both call: one library entry for the
//! convergence study, whichever runs it.

use harmonav_field::descent::{Descent, Ending, FollowOptions, follow};
use harmonav_scenario::Prepared;
use nalgebra::Vector2;

use crate::outcome::{Outcome, StallPoint};
use crate::summary::RunError;

/// A descent and how it ended.
#[derive(Clone, Debug, PartialEq)]
pub struct DescentRun {
    /// The integration's own result.
    pub descent: Descent,
    /// How it ended, as a run's outcome: `collision` when a point left the free space of the
    /// (grown) shapes, else from [`Ending`] (a critical point is a stall, classified).
    pub outcome: Outcome,
    /// `k` of the field.
    pub k: f64,
}

/// The options of a descent in `prepared`'s world: its goal tolerance, and its time budget
/// `sim.max_time` as a path length (the descent runs at unit speed).
pub fn options(prepared: &Prepared) -> FollowOptions {
    FollowOptions {
        goal_tolerance: prepared.scenario.sim.goal_tolerance,
        max_time: prepared.scenario.sim.max_time,
        ..FollowOptions::default()
    }
}

/// The descent of `Θ` (every obstacle of `prepared` known, its `k` policy) from `start` to the
/// goal. Errors: the field cannot be built, or `start` is not in its free space.
pub fn descend(prepared: &Prepared, start: Vector2<f64>) -> Result<DescentRun, RunError> {
    let field = prepared.global_field().map_err(RunError::Field)?;
    if field.eval(start).is_err() {
        return Err(RunError::StartNotFree);
    }
    let options = options(prepared);
    let d = follow(&field, start, &options);
    let outcome = match d.ending {
        _ if !d.collision_free => Outcome::Collision,
        Ending::Reached => Outcome::Reached { time: d.time },
        Ending::TimedOut => Outcome::TimedOut { time: d.time },
        Ending::StepCollapsed => Outcome::StepCollapsed { time: d.time },
        Ending::Stuck => {
            let (point, at) = StallPoint::classify(&field, d.end, options.goal_tolerance);
            Outcome::Stalled {
                time: d.time,
                position: [at.x, at.y],
                point,
            }
        }
    };
    Ok(DescentRun {
        descent: d,
        outcome,
        k: field.k(),
    })
}
