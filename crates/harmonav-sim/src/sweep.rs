//! Many starts in one world (global sensing), in parallel: the outcome of each, typed.

use harmonav_field::descent::{Ending, FollowOptions, follow};
use harmonav_sensing::Sensing;
use nalgebra::Vector2;

pub use crate::outcome::Outcome;
use crate::quality::parallel_map;
use crate::run::{RunError, run};
use crate::scenario::{Model, Prepared};

/// One start: the kinematic law by [`follow`] (the normalised descent), the dynamic law by the
/// built-in integrator ([`run`]), both with every obstacle known.
fn one(
    prepared: &Prepared,
    field: &harmonav_field::Field,
    x: Vector2<f64>,
    model: Model,
) -> Result<Outcome, RunError> {
    let sc = &prepared.scenario;
    Ok(match model {
        Model::Kinematic => {
            let options = FollowOptions {
                goal_tolerance: sc.sim.goal_tolerance,
                max_time: sc.sim.max_time,
                ..FollowOptions::default()
            };
            let d = follow(field, x, &options);
            match (d.ending, d.collision_free) {
                (_, false) => Outcome::Collision,
                (Ending::Reached, true) => Outcome::Reached { time: d.time },
                (Ending::Stuck, true) => Outcome::Stalled { time: d.time },
                (Ending::TimedOut, true) => Outcome::TimedOut { time: d.time },
                (Ending::StepCollapsed, true) => Outcome::StepCollapsed { time: d.time },
            }
        }
        Model::Dynamic => {
            let mut p = prepared.clone();
            p.scenario.robot.start = [x.x, x.y];
            p.truth.sensing = Sensing::Global;
            run(&p, Some(Model::Dynamic))?.summary.outcome
        }
    })
}

/// The outcome of each start in `starts`, in order, on `threads` threads.
pub fn sweep(
    prepared: &Prepared,
    starts: &[Vector2<f64>],
    model: Model,
    threads: usize,
) -> Result<Vec<Outcome>, RunError> {
    let field = prepared
        .global_field()
        .map_err(|e| RunError(e.to_string()))?;
    parallel_map(starts, threads, |&x| one(prepared, &field, x, model))
        .into_iter()
        .collect()
}

/// Counts of a sweep's outcomes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    /// Reached the goal.
    pub reached: usize,
    /// Touched an obstacle.
    pub collisions: usize,
    /// Left the workspace.
    pub left_workspace: usize,
    /// Stopped at a critical point.
    pub stalled: usize,
    /// Ran out of time.
    pub timed_out: usize,
    /// Step-size collapse.
    pub step_collapsed: usize,
}

impl Counts {
    /// Counts `outcomes` by kind.
    pub fn of(outcomes: &[Outcome]) -> Self {
        let mut c = Self::default();
        for o in outcomes {
            match o {
                Outcome::Reached { .. } => c.reached += 1,
                Outcome::Collision => c.collisions += 1,
                Outcome::LeftWorkspace => c.left_workspace += 1,
                Outcome::Stalled { .. } => c.stalled += 1,
                Outcome::TimedOut { .. } => c.timed_out += 1,
                Outcome::StepCollapsed { .. } => c.step_collapsed += 1,
            }
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_follow_the_outcome_kinds() {
        let outcomes = [
            Outcome::Reached { time: 1.0 },
            Outcome::Reached { time: 2.0 },
            Outcome::Collision,
            Outcome::LeftWorkspace,
            Outcome::Stalled { time: 3.0 },
            Outcome::TimedOut { time: 4.0 },
            Outcome::StepCollapsed { time: 5.0 },
        ];
        let c = Counts::of(&outcomes);
        assert_eq!(
            c,
            Counts {
                reached: 2,
                collisions: 1,
                left_workspace: 1,
                stalled: 1,
                timed_out: 1,
                step_collapsed: 1
            }
        );
        assert_eq!(outcomes[3].to_string(), "left the workspace");
        assert!(outcomes[0].reached() && !outcomes[2].reached());
    }
}
