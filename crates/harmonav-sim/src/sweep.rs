//! Many starts in one world (global sensing), in parallel: the outcome of each, typed.

use harmonav_sensing::Sensing;
use harmonav_transform::random::{self, Rng};
use nalgebra::Vector2;
use serde::Serialize;

pub use crate::outcome::Outcome;
use crate::quality::parallel_map;
use crate::run::{RunError, run};
use crate::scenario::{Model, Prepared};

/// The most starts one sweep takes (each outcome is kept; a larger count is refused rather
/// than allocated).
pub const MAX_STARTS: usize = 1_000_000;

/// One start: the scenario's law (or `model`) by the built-in integrator ([`run`]), every
/// obstacle known. A kinematic run that comes to rest at a saddle stops there as stalled.
fn one(prepared: &Prepared, x: Vector2<f64>, model: Model) -> Result<Outcome, RunError> {
    let mut p = prepared.clone();
    p.scenario.robot.start = [x.x, x.y];
    p.truth.sensing = Sensing::Global;
    Ok(run(&p, Some(model))?.summary.outcome)
}

/// The outcome of each start in `starts`, in order, on `threads` threads. Errors: more than
/// [`MAX_STARTS`] starts, or a start the run refuses (outside the free space).
pub fn sweep(
    prepared: &Prepared,
    starts: &[Vector2<f64>],
    model: Model,
    threads: usize,
) -> Result<Vec<Outcome>, RunError> {
    check_count(starts.len())?;
    parallel_map(starts, threads, |&x| one(prepared, x, model))
        .into_iter()
        .collect()
}

fn check_count(n: usize) -> Result<(), RunError> {
    if n > MAX_STARTS {
        return Err(RunError(format!(
            "{n} starts; a sweep takes at most {MAX_STARTS}"
        )));
    }
    Ok(())
}

/// `count` seeded random starts in the free space of the scenario's true (grown) obstacles,
/// each at least 1 mm (or a thousandth of the workspace's size, if smaller) from every
/// boundary: the same starts for the same seed on every machine. Errors: more than
/// [`MAX_STARTS`].
pub fn random_starts(
    prepared: &Prepared,
    count: usize,
    seed: u64,
) -> Result<Vec<Vector2<f64>>, RunError> {
    check_count(count)?;
    let ws = &prepared.truth.workspace;
    let margin = 1e-3_f64.min(1e-3 * ws.boundary().radius_bounds().0);
    let mut rng = Rng::new(seed);
    Ok((0..count)
        .map(|_| random::free_point(&mut rng, ws, margin))
        .collect())
}

/// A sweep summarised: counts by outcome, arrival times and the starts that did not arrive
/// (the JSON of `harmonav sweep --json`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Report {
    /// How many starts.
    pub starts: usize,
    /// Counts by outcome.
    #[serde(flatten)]
    pub counts: Counts,
    /// Median arrival time over the starts that arrived (`None` if none did).
    pub median_time_s: Option<f64>,
    /// Longest arrival time.
    pub max_time_s: Option<f64>,
    /// Each start that did not arrive, in order.
    pub failures: Vec<Failure>,
}

/// A start that did not arrive.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Failure {
    /// The start `[x, y]`.
    pub start: [f64; 2],
    /// What happened, in words.
    pub reason: String,
    /// What happened.
    pub outcome: Outcome,
}

impl Report {
    /// Summarises the `outcomes` of `starts` (paired by index).
    pub fn of(starts: &[Vector2<f64>], outcomes: &[Outcome]) -> Self {
        let mut times: Vec<f64> = outcomes
            .iter()
            .filter_map(|o| match o {
                Outcome::Reached { time } => Some(*time),
                _ => None,
            })
            .collect();
        times.sort_by(f64::total_cmp);
        let failures = starts
            .iter()
            .zip(outcomes)
            .filter(|(_, o)| !o.reached())
            .map(|(p, o)| Failure {
                start: [p.x, p.y],
                reason: o.to_string(),
                outcome: o.clone(),
            })
            .collect();
        Self {
            starts: starts.len(),
            counts: Counts::of(outcomes),
            median_time_s: times.get(times.len() / 2).copied(),
            max_time_s: times.last().copied(),
            failures,
        }
    }

    /// Did every start arrive?
    pub fn all_reached(&self) -> bool {
        self.counts.reached == self.starts
    }
}

/// Counts of a sweep's outcomes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
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
            Outcome::Stalled {
                time: 3.0,
                position: [0.0; 2],
                point: crate::outcome::StallPoint::Saddle,
            },
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
        let starts: Vec<_> = (0..7).map(|i| Vector2::new(i as f64, 0.0)).collect();
        let report = Report::of(&starts, &outcomes);
        assert_eq!((report.starts, report.counts), (7, c));
        assert_eq!(
            (report.median_time_s, report.max_time_s),
            (Some(2.0), Some(2.0))
        );
        let failed: Vec<[f64; 2]> = report.failures.iter().map(|f| f.start).collect();
        assert_eq!(
            failed,
            [[2.0, 0.0], [3.0, 0.0], [4.0, 0.0], [5.0, 0.0], [6.0, 0.0]]
        );
        assert!(!report.all_reached());
        let json = serde_json::to_value(&report).unwrap();
        assert_eq!(json["left_workspace"], 1);
        assert_eq!(json["failures"][1]["outcome"]["kind"], "left-workspace");
        for o in &outcomes {
            let json = serde_json::to_value(o).unwrap();
            assert_eq!(json["kind"], o.kind(), "{o:?}");
            assert_eq!(json["time"].as_f64(), o.time(), "{o:?}");
        }
    }
}
