//! The checks made before a run ([`check`]): the [`Warning`]s about a scenario that its
//! verdict alone would not explain. The driver asks them of the field the robot starts with
//! (`driver.rs`), so a run's path goes through this module once, before its first state.

use harmonav_field::Field;
use harmonav_field::descent::{Ending, FollowOptions, follow};
use harmonav_scenario::Prepared;
use nalgebra::Vector2;

use crate::outcome::StallPoint;
use crate::warning::{TOLERANCE_SHARE, Warning};

/// Step attempts of the descent that looks for a saddle ahead of the start: a bound on the
/// warning's cost (a normal descent takes a few hundred).
pub const DESCENT_ATTEMPTS: usize = 20_000;

/// The warnings for a run of `prepared` whose robot starts knowing `field` (its `Θ` over the
/// obstacles known at `t = 0`); `crate::physics::warnings` asks them for a model.
#[must_use]
pub fn check(prepared: &Prepared, field: &Field) -> Vec<Warning> {
    let sc = &prepared.scenario;
    let start = Vector2::from(sc.robot.start);
    let goal = prepared.truth.goal();
    let tol = sc.sim.goal_tolerance;
    let mut warnings = Vec::new();
    let scale = (start - goal)
        .norm()
        .min(prepared.truth.workspace.boundary().radius_bounds().0);
    if tol >= TOLERANCE_SHARE * scale {
        warnings.push(Warning::GoalToleranceLarge {
            goal_tolerance: tol,
            scale,
        });
    }
    if (start - goal).norm() < tol {
        return warnings;
    }
    match field.eval(start) {
        Ok(e) if e.direction.is_none() => warnings.push(Warning::StartAtCriticalPoint),
        Ok(_) => {
            let options = FollowOptions {
                goal_tolerance: tol,
                max_time: sc.sim.max_time,
                max_attempts: DESCENT_ATTEMPTS,
                ..FollowOptions::default()
            };
            let d = follow(field, start, &options);
            // At a saddle the descent chatters in place: it ends stuck or out of attempts.
            if d.ending != Ending::Reached
                && let (StallPoint::Saddle, saddle) = StallPoint::classify(field, d.end, tol)
            {
                warnings.push(Warning::StartOnSaddleManifold {
                    saddle: saddle.into(),
                });
            }
        }
        Err(_) => {}
    }
    warnings
}
