//! The checks made before a run ([`check`]): the [`Warning`]s about a scenario that its
//! verdict alone would not explain.

use harmonav_field::descent::{Ending, FollowOptions, follow};
use harmonav_scenario::{Model, Prepared};
use nalgebra::Vector2;

use crate::closed_loop::ClosedLoop;
use crate::outcome::StallPoint;
use crate::summary::RunError;
use crate::warning::{TOLERANCE_SHARE, Warning};

/// Step attempts of the descent that looks for a saddle ahead of the start: a bound on the
/// warning's cost (a normal descent takes a few hundred).
pub const DESCENT_ATTEMPTS: usize = 20_000;

/// The warnings for a run of `prepared` with `model` (or the file's).
pub fn check(prepared: &Prepared, model: Option<Model>) -> Result<Vec<Warning>, RunError> {
    let sc = &prepared.scenario;
    let (lp, _) = ClosedLoop::start(prepared, model, None)?;
    let field = lp.nav.field();
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
        return Ok(warnings);
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
    Ok(warnings)
}
