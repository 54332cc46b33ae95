//! Many starts in one world (global sensing), in parallel: the outcome of each, typed; and
//! every start of a floor plan ([`sweep_floor`]).

use std::ops::Range;

use harmonav_scenario::Sensor;
use harmonav_transform::WorldError;
use harmonav_transform::random::{self, Rng};
use nalgebra::Vector2;
use serde::Serialize;

use harmonav_scenario::floorplan::FloorPrepared;
use harmonav_scenario::{Model, Prepared};

use crate::floor::{self, FloorRun, FloorSummary};
use crate::guarantee::{Guarantee, Kind};
pub use crate::outcome::{Outcome, StartProblem};
use crate::pool::parallel_map;
use crate::run::run;
use crate::summary::RunError;

/// The most starts one sweep takes (each outcome is kept; a larger count is refused rather
/// than allocated).
pub const MAX_STARTS: usize = 1_000_000;

/// Why a sweep could not be made.
#[derive(Clone, Debug, PartialEq)]
pub enum SweepError {
    /// No start: a sweep takes at least one.
    NoStarts,
    /// More than [`MAX_STARTS`] starts.
    TooManyStarts {
        /// How many were asked for.
        count: usize,
    },
    /// The run from the free start `starts[index]` could not start (the scenario's navigator
    /// refused it).
    Run {
        /// The start's index.
        index: usize,
        /// The start.
        start: [f64; 2],
        /// Why.
        error: RunError,
    },
}

impl std::fmt::Display for SweepError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NoStarts => write!(f, "no starts; a sweep takes at least 1"),
            Self::TooManyStarts { count } => {
                write!(f, "{count} starts; a sweep takes at most {MAX_STARTS}")
            }
            Self::Run {
                index,
                start: [x, y],
                error,
            } => write!(f, "starts[{index}] ({x}, {y}): {error}"),
        }
    }
}

impl std::error::Error for SweepError {}

/// Checks a sweep's start count: at least 1, at most [`MAX_STARTS`]. The CLI and the Python
/// `sweep` both check their count here.
pub fn check_count(n: usize) -> Result<(), SweepError> {
    match n {
        0 => Err(SweepError::NoStarts),
        n if n > MAX_STARTS => Err(SweepError::TooManyStarts { count: n }),
        _ => Ok(()),
    }
}

/// Why `x` is not a start of `prepared`'s free space (the configuration space: the true shapes
/// grown by the robot's radius and margin), if it is not; the same test as the file's own
/// `robot.start` ([`harmonav_transform::Workspace::check_free`]).
pub fn start_problem(prepared: &Prepared, x: Vector2<f64>) -> Option<StartProblem> {
    let truth = &prepared.truth;
    match truth.workspace.check_free(x, "start") {
        Ok(()) => None,
        Err(WorldError::InObstacle { obstacle, .. }) => {
            let name = truth.names[obstacle].clone();
            Some(if truth.obstacles[obstacle].contains(x) {
                StartProblem::InObstacle { obstacle: name }
            } else {
                StartProblem::NearObstacle { obstacle: name }
            })
        }
        Err(_) => Some(
            if x.iter().all(|c| c.is_finite())
                && truth.boundary.contains(x)
                && truth.boundary.signed_distance(x) < 0.0
            {
                StartProblem::NearBoundary
            } else {
                StartProblem::OutsideWorkspace
            },
        ),
    }
}

/// One start, `starts[index] = x`: an invalid start ([`start_problem`]) is an outcome, not an
/// error; a free one runs the scenario's law (or `model`) by the built-in integrator ([`run`]),
/// every obstacle known. A kinematic run that comes to rest at a saddle stops there as stalled.
fn one(
    prepared: &Prepared,
    index: usize,
    x: Vector2<f64>,
    model: Model,
) -> Result<Outcome, SweepError> {
    if let Some(problem) = start_problem(prepared, x) {
        return Ok(Outcome::InvalidStart { index, problem });
    }
    let mut p = prepared.clone();
    p.scenario.robot.start = [x.x, x.y];
    p.truth.sensor = Sensor::Global;
    match run(&p, Some(model)) {
        Ok(r) => Ok(r.summary.outcome),
        Err(error) => Err(SweepError::Run {
            index,
            start: [x.x, x.y],
            error,
        }),
    }
}

/// The outcome of each start in `starts`, in order, on `threads` threads. A start outside the
/// free space is the outcome [`Outcome::InvalidStart`] naming it. Errors: no start or more
/// than [`MAX_STARTS`] ([`check_count`]), or a free start whose run cannot start
/// ([`SweepError::Run`], naming it).
pub fn sweep(
    prepared: &Prepared,
    starts: &[Vector2<f64>],
    model: Model,
    threads: usize,
) -> Result<Vec<Outcome>, SweepError> {
    check_count(starts.len())?;
    sweep_part(prepared, starts, 0..starts.len(), model, threads)
}

/// The outcomes of `starts[range]` (indices in outcomes and errors are those of `starts`), as
/// [`sweep`] gives them: for a caller that runs a sweep in parts, to do something between
/// them (Python checks for Ctrl-C). It does not check the count; [`check_count`] does. A
/// range beyond `starts` is cut to it.
pub fn sweep_part(
    prepared: &Prepared,
    starts: &[Vector2<f64>],
    range: Range<usize>,
    model: Model,
    threads: usize,
) -> Result<Vec<Outcome>, SweepError> {
    let range = range.start.min(starts.len())..range.end.min(starts.len());
    let indexed: Vec<(usize, Vector2<f64>)> = range.map(|i| (i, starts[i])).collect();
    parallel_map(&indexed, threads, |&(i, x)| one(prepared, i, x, model))
        .into_iter()
        .collect()
}

/// The outcome of each start of a floor plan (`harmonav sweep` on a `[floor_plan]` file):
/// `prepared.starts` (its `robot.start`, then the seeded `[starts]`, each in `W_δ` by
/// construction), in order, under `model` by the built-in floor loop ([`floor::run`], the
/// file's own sensing), on `threads` threads. Each run is judged from its guarantees as a star
/// world's is ([`Outcome::of`]): a failed `no-collision` is a collision, a failed
/// `stayed-in-workspace` a departure, then arrival, a refused command
/// ([`Outcome::CommandRefused`]) or the time budget. Errors: as [`sweep`] (a navigator that
/// cannot be built names the start).
pub fn sweep_floor(
    prepared: &FloorPrepared,
    model: Model,
    threads: usize,
) -> Result<Vec<Outcome>, SweepError> {
    let starts = &prepared.starts;
    check_count(starts.len())?;
    let indexed: Vec<(usize, Vector2<f64>)> = starts.iter().copied().enumerate().collect();
    parallel_map(&indexed, threads, |&(index, x)| {
        let run = floor::run(prepared, Some(model), x).map_err(|e| SweepError::Run {
            index,
            start: [x.x, x.y],
            error: RunError::Navigator(e),
        })?;
        Ok(floor_outcome(
            &FloorSummary::new(prepared, Some(model), x, &run),
            &run,
        ))
    })
    .into_iter()
    .collect()
}

/// A floor-plan run's [`Outcome`], in the order of [`Outcome::of`] (`floor_outcome_of`): a
/// failed safety verdict is never counted as reached.
#[must_use]
pub fn floor_outcome(summary: &FloorSummary, run: &FloorRun) -> Outcome {
    floor_outcome_of(&summary.guarantees, &run.outcome, run.time)
}

/// The outcome of a floor-plan run that ended with `ended` at `time` with its `guarantees`:
/// every failed guarantee is judged before arrival, as in a star world. A collision:
/// `no-collision` (and a map's pixels), or `no-collision-between-states` (the swept bound, a
/// contact between two states); leaving the workspace: `stayed-in-workspace`, or
/// `stayed-in-certified-region` (the region `W_δ` the guarantee is about). Issue 51: a run that
/// reached the goal after failing either of the latter two counted as reached. A run that ran
/// out of time is timed out at `time`, where its loop stopped.
fn floor_outcome_of(guarantees: &[Guarantee], ended: &Outcome, time: f64) -> Outcome {
    let failed = |kind: Kind| guarantees.iter().any(|g| g.kind() == kind && !g.passed);
    if failed(Kind::NoCollision)
        || failed(Kind::NoCollisionBetweenStates)
        || *ended == Outcome::Collision
    {
        Outcome::Collision
    } else if failed(Kind::StayedInWorkspace)
        || failed(Kind::StayedInCertifiedRegion)
        || *ended == Outcome::LeftWorkspace
    {
        Outcome::LeftWorkspace
    } else if let Outcome::TimedOut { .. } = ended {
        Outcome::TimedOut { time }
    } else {
        ended.clone()
    }
}

/// `count` seeded random starts in the free space of the scenario's true (grown) obstacles,
/// each at least 1 mm (or a thousandth of the workspace's size, if smaller) from every
/// boundary: the same starts for the same seed on every machine. Errors: no start or more
/// than [`MAX_STARTS`] ([`check_count`]).
pub fn random_starts(
    prepared: &Prepared,
    count: usize,
    seed: u64,
) -> Result<Vec<Vector2<f64>>, SweepError> {
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

fn is_zero(n: &usize) -> bool {
    *n == 0
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
    /// A lidar's scan refused (left out of the JSON when 0: a sweep senses globally).
    #[serde(skip_serializing_if = "is_zero")]
    pub scan_refused: usize,
    /// A command refused by a floor plan's navigator (left out of the JSON when 0).
    #[serde(skip_serializing_if = "is_zero")]
    pub command_refused: usize,
    /// Starts outside the free space, not run.
    pub invalid_starts: usize,
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
                Outcome::ScanRefused { .. } => c.scan_refused += 1,
                Outcome::CommandRefused { .. } => c.command_refused += 1,
                Outcome::InvalidStart { .. } => c.invalid_starts += 1,
            }
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 51: a floor run that reached the goal after failing the swept bound or leaving
    /// the certified region is a collision or a departure, not an arrival (the adapter read
    /// only `no-collision` and `stayed-in-workspace`).
    #[test]
    fn every_failed_floor_guarantee_is_judged_before_arrival() {
        use crate::guarantee::Check;
        let reached =
            |g: Vec<Guarantee>| floor_outcome_of(&g, &Outcome::Reached { time: 3.0 }, 3.0);
        let swept = Guarantee::new(
            Check::NoCollisionBetweenStates {
                swept_clearance: -0.01,
            },
            false,
        );
        assert_eq!(reached(vec![swept]), Outcome::Collision);
        let layer = Guarantee::new(
            Check::StayedInCertifiedRegion {
                min_layer_clearance: -0.01,
                delta: 0.2,
            },
            false,
        );
        assert_eq!(reached(vec![layer]), Outcome::LeftWorkspace);
        let pixels = Guarantee::new(
            Check::NoCollisionWithMap {
                min_pixel_clearance: -0.01,
            },
            false,
        );
        assert_eq!(reached(vec![pixels]), Outcome::Collision);
        let passed = Guarantee::new(
            Check::NoCollisionBetweenStates {
                swept_clearance: 0.01,
            },
            true,
        );
        assert_eq!(reached(vec![passed]), Outcome::Reached { time: 3.0 });
    }

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
            Outcome::InvalidStart {
                index: 7,
                problem: StartProblem::OutsideWorkspace,
            },
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
                step_collapsed: 1,
                scan_refused: 0,
                command_refused: 0,
                invalid_starts: 1,
            }
        );
        let refused = Counts::of(&[Outcome::ScanRefused { time: 1.0 }]);
        assert_eq!((refused.scan_refused, refused.reached), (1, 0));
        let command = Outcome::CommandRefused {
            time: 2.0,
            reason: "in the boundary layer".into(),
        };
        assert_eq!(
            Counts::of(std::slice::from_ref(&command)).command_refused,
            1
        );
        assert_eq!(command.kind(), "command-refused");
        assert_eq!(command.time(), Some(2.0));
        assert!(
            command
                .to_string()
                .ends_with("at t = 2.00 s: in the boundary layer")
        );
        let json = serde_json::to_value(Counts::of(&outcomes)).unwrap();
        assert!(
            json.get("command_refused").is_none(),
            "left out when 0: {json}"
        );
        assert_eq!(outcomes[3].to_string(), "left the workspace");
        assert!(outcomes[0].reached() && !outcomes[2].reached());
        let starts: Vec<_> = (0..8).map(|i| Vector2::new(i as f64, 0.0)).collect();
        let report = Report::of(&starts, &outcomes);
        assert_eq!((report.starts, report.counts), (8, c));
        assert_eq!(
            (report.median_time_s, report.max_time_s),
            (Some(2.0), Some(2.0))
        );
        let failed: Vec<[f64; 2]> = report.failures.iter().map(|f| f.start).collect();
        assert_eq!(
            failed,
            [
                [2.0, 0.0],
                [3.0, 0.0],
                [4.0, 0.0],
                [5.0, 0.0],
                [6.0, 0.0],
                [7.0, 0.0]
            ]
        );
        assert!(!report.all_reached());
        let json = serde_json::to_value(&report).unwrap();
        assert_eq!(json["left_workspace"], 1);
        assert_eq!(json["failures"][1]["outcome"]["kind"], "left-workspace");
        assert_eq!(json["invalid_starts"], 1);
        assert_eq!(json["failures"][5]["outcome"]["index"], 7);
        assert_eq!(
            json["failures"][5]["outcome"]["problem"]["kind"],
            "outside-workspace"
        );
        for o in &outcomes {
            let json = serde_json::to_value(o).unwrap();
            assert_eq!(json["kind"], o.kind(), "{o:?}");
            assert_eq!(json["time"].as_f64(), o.time(), "{o:?}");
        }
    }

    /// One disc of radius 1 in a disc of radius 5; the robot's radius and margin add 0.2 m.
    fn one_rock() -> Prepared {
        let text = r#"
            name = "one-rock"
            [workspace]
            type = "circle"
            center = [0.0, 0.0]
            radius = 5.0
            [[obstacles]]
            name = "rock"
            type = "circle"
            center = [0.0, 0.0]
            radius = 1.0
            [robot]
            model = "kinematic"
            radius = 0.15
            margin = 0.05
            start = [-3.0, 0.2]
            goal = [3.0, 0.0]
        "#;
        let path = std::path::Path::new("one-rock.toml");
        harmonav_scenario::Scenario::parse(path, text)
            .unwrap()
            .prepare(path)
            .unwrap()
    }

    /// Each kind of start outside the free space is its own outcome naming `starts[i]`; the
    /// free starts around it still run (before, the first bad start aborted the sweep with a
    /// message about a discovery that named no start).
    #[test]
    fn an_invalid_start_is_an_outcome_naming_it_and_the_others_run() {
        let prepared = one_rock();
        let rock = || "rock".to_string();
        let check = |x: [f64; 2], expected: Option<StartProblem>| {
            assert_eq!(
                start_problem(&prepared, Vector2::from(x)),
                expected,
                "at {x:?}"
            );
        };
        check([-3.0, 0.2], None);
        check(
            [0.5, 0.0],
            Some(StartProblem::InObstacle { obstacle: rock() }),
        );
        check(
            [1.1, 0.0],
            Some(StartProblem::NearObstacle { obstacle: rock() }),
        );
        check([4.9, 0.0], Some(StartProblem::NearBoundary));
        check([6.0, 0.0], Some(StartProblem::OutsideWorkspace));
        check([f64::NAN, 0.0], Some(StartProblem::OutsideWorkspace));

        let starts = [
            Vector2::new(-3.0, 0.2),
            Vector2::new(0.5, 0.0),
            Vector2::new(-3.0, -0.5),
            Vector2::new(6.0, 0.0),
        ];
        let outcomes = sweep(&prepared, &starts, Model::Kinematic, 2).unwrap();
        assert!(
            outcomes[0].reached() && outcomes[2].reached(),
            "{outcomes:?}"
        );
        assert_eq!(
            outcomes[1],
            Outcome::InvalidStart {
                index: 1,
                problem: StartProblem::InObstacle { obstacle: rock() }
            }
        );
        assert_eq!(
            outcomes[1].to_string(),
            "not run: starts[1] lies inside obstacle rock"
        );
        assert_eq!(outcomes[3].kind(), "invalid-start");
        assert_eq!(outcomes[3].time(), None);
        // In parts, the indices stay those of the whole list.
        let part = sweep_part(&prepared, &starts, 3..9, Model::Kinematic, 1).unwrap();
        assert_eq!(part, [outcomes[3].clone()]);
        let report = Report::of(&starts, &outcomes);
        assert_eq!(
            (report.counts.reached, report.counts.invalid_starts),
            (2, 2)
        );
        assert_eq!(report.failures[1].reason, outcomes[3].to_string());
    }

    /// One check of the count for every caller: 0 and more than MAX_STARTS are refused
    /// (before, `sweep` and `random_starts` returned nothing for 0 while the CLI refused it).
    #[test]
    fn a_sweep_takes_one_to_max_starts() {
        let prepared = one_rock();
        assert_eq!(check_count(0), Err(SweepError::NoStarts));
        assert_eq!(check_count(1), Ok(()));
        assert_eq!(check_count(MAX_STARTS), Ok(()));
        assert_eq!(
            check_count(MAX_STARTS + 1),
            Err(SweepError::TooManyStarts {
                count: MAX_STARTS + 1
            })
        );
        assert_eq!(
            sweep(&prepared, &[], Model::Kinematic, 1),
            Err(SweepError::NoStarts)
        );
        assert_eq!(random_starts(&prepared, 0, 1), Err(SweepError::NoStarts));
        assert!(
            SweepError::TooManyStarts { count: 2_000_000 }
                .to_string()
                .contains("at most 1000000")
        );
    }
}
