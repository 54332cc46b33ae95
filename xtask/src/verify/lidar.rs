//! The Navigator on scans alone (issue 26, part 2; docs/maths.md §12.6): 24 seeded worlds
//! (`harmonav::checks::lidar::lidar_world`, discs only and every shape kind), a point and a
//! 0.1 m disc robot, a 360-beam lidar with 2 cm noise and 1 % dropouts at 10 Hz feeding
//! `Navigator::observe_scan`, both laws; and the negative control with a depth prior smaller
//! than the obstacles.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use harmonav::checks::lidar::{LidarReport, LidarSuite};
use harmonav::{Law, NavError};
use harmonav_scenario::{Model, Prepared, Scenario, SensorKind, SensorSpec};
use harmonav_sim::guarantee::Check as Measured;
use harmonav_sim::physics::{Physics, simulate};
use harmonav_sim::pool::parallel_map;
use harmonav_sim::summary::Summary;

use super::{Check, Outcome, Verdict, outcome};

/// The arrival each suite aims at: a suite below it is a [`Verdict::Target`] not met, a lost
/// guarantee of safety a failure. Every run: measured 48 of 48 in each suite since the radial
/// hulls, the free fan, the memory and the fit range (docs/maths.md §12.11); before, a
/// conservative shape sometimes covered the goal or the robot and the flight ended (46 of 48
/// before eq. attribution, §12.8; 44 and 45 with the fit's candidates, §12.9).
const ARRIVAL: f64 = 1.0;

pub fn checks() -> Vec<Check> {
    let kinematic = LidarSuite::new(Law::kinematic(1.0), 0.01);
    let dynamic = LidarSuite::new(Law::dynamic(1.0, 2.0), 0.001);
    let discs = LidarSuite {
        discs_only: true,
        ..kinematic.clone()
    };
    let control = LidarSuite {
        max_obstacle_depth: 0.3,
        ..kinematic.clone()
    };
    // Furniture 0.02–0.3 m from the walls (issue 52), fitted from 2.5 m so that it is fitted
    // from across the room: it joins the boundary instead of being refused.
    let furnished = |law, h| LidarSuite {
        furnished: true,
        fit_range: Some(2.5),
        ..LidarSuite::new(law, h)
    };
    let furnished_kinematic = furnished(Law::kinematic(1.0), 0.01);
    let furnished_dynamic = LidarSuite {
        seeds: 0..8,
        ..furnished(Law::dynamic(1.0, 2.0), 0.001)
    };
    vec![
        Check::new("navigator.lidar.furnished-kinematic", move || {
            safe(&furnished_kinematic, None)
        })
        .early(),
        Check::new("navigator.lidar.furnished-dynamic", move || {
            safe(&furnished_dynamic, Some((2.0f64 * 2.0 / 1.0).sqrt()))
        })
        .early(),
        Check::new("navigator.lidar.kinematic-discs", move || {
            safe(&discs, None)
        })
        .early(),
        Check::new("navigator.lidar.kinematic", move || safe(&kinematic, None)).early(),
        Check::new("navigator.lidar.dynamic", move || {
            safe(&dynamic, Some((2.0f64 * 2.0 / 1.0).sqrt()))
        })
        .early(),
        Check::new("navigator.lidar.negative-control", move || {
            negative_control(&control)
        })
        .early(),
    ]
}

/// The range of the 360° lidar a suite world is rerun with, beyond its depth prior `D`, m: the
/// navigator's `d_min` comes from `range − D` (docs/maths.md §12.6).
pub const RERUN_RANGE_BEYOND_DEPTH: f64 = 3.0;

/// A suite file rerun with a 360° lidar ([`with_lidar`]), and which of its two laws the file
/// itself states do not arrive with its own sensor.
pub struct Rerun {
    /// The file with its sensor replaced.
    pub prepared: Prepared,
    /// The models whose runs the file's `[expect]` states do not reach the goal with the
    /// file's own sensor (`reached = false` for its model, `other_model_reached = false` for
    /// the other: a limit of the paper's policies, which `scenarios.*` checks in verify).
    pub limits: Vec<Model>,
}

/// `file` with its sensor replaced by a 360° lidar of the defaults (360 beams at 10 Hz, ±2 cm
/// noise, the depth prior the largest true diameter `D`) and range `D +`
/// [`RERUN_RANGE_BEYOND_DEPTH`]; `[expect]` dropped (it describes the file's own sensor), its
/// statements of arrival kept in [`Rerun::limits`]. `None` for a file that already has a lidar.
pub fn with_lidar(file: &Path) -> Result<Option<Rerun>, String> {
    let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
    let mut sc = Scenario::parse(file, &text).map_err(|e| e.to_string())?;
    if sc
        .sensor
        .as_ref()
        .is_some_and(|s| s.kind == SensorKind::Lidar)
    {
        return Ok(None);
    }
    let own = sc.robot.model;
    let other = own.other();
    let limits = match sc.expect.take() {
        Some(e) => [(own, e.reached), (other, e.other_model_reached)]
            .into_iter()
            .filter(|(_, reached)| *reached == Some(false))
            .map(|(m, _)| m)
            .collect(),
        None => Vec::new(),
    };
    // First with a range beyond any depth, to learn the default D from the truth.
    sc.sensor = Some(SensorSpec::lidar(1e6));
    let probe = sc.clone().prepare(file).map_err(|e| e.to_string())?;
    let depth = probe
        .truth
        .sensor
        .lidar()
        .map_or(1.0, |l| l.scan.max_obstacle_depth);
    sc.sensor = Some(SensorSpec::lidar(depth + RERUN_RANGE_BEYOND_DEPTH));
    let prepared = sc.prepare(file).map_err(|e| e.to_string())?;
    Ok(Some(Rerun { prepared, limits }))
}

/// Every suite file (`files`, each with its name) rerun with a 360° lidar ([`with_lidar`])
/// under both laws, as one check (the issue's "both laws arrive in every world of
/// `scenarios/` rerun with a 360° lidar"). It fails on any lost guarantee of safety
/// ([`Summary::safe`]: collision, workspace, `Θ`, speed, energy, overshoot, the seen truth
/// covered, shapes only growing). Runs that stay safe but do not arrive (a refused scan, a
/// stall) make it a [`Verdict::Target`], with the count by reason; a run that the file states
/// does not arrive with its own sensor either ([`Rerun::limits`], the paper's damping) is
/// listed apart and must not arrive (else the file's statement is stale), as `scenarios.*`
/// treats it.
pub fn rerun_checks(files: Vec<(PathBuf, String)>) -> Vec<Check> {
    vec![Check::new("lidar-rerun.scenarios", move || rerun_all(&files)).early()]
}

fn rerun_all(files: &[(PathBuf, String)]) -> Outcome {
    let mut runs: Vec<(String, Model, Prepared)> = Vec::new();
    let mut limits: Vec<(String, Model)> = Vec::new();
    for (file, name) in files {
        if let Some(r) = with_lidar(file)? {
            for model in [Model::Kinematic, Model::Dynamic] {
                runs.push((name.clone(), model, r.prepared.clone()));
            }
            limits.extend(r.limits.iter().map(|m| (name.clone(), *m)));
        }
    }
    let threads = std::thread::available_parallelism().map_or(1, usize::from);
    let summaries = parallel_map(&runs, threads, |(_, model, p)| {
        simulate(p, Some(*model), Physics::Builtin).map(|r| r.summary)
    });
    let mut unsafe_runs = Vec::new();
    let mut reasons: BTreeMap<String, Vec<String>> = BTreeMap::new();
    let (mut arrived, mut seen, mut uncovered) = (0, 0, 0);
    let mut stated = Vec::new();
    for ((name, model, _), s) in runs.iter().zip(summaries) {
        let s = s.map_err(|e| format!("{name} ({model:?}): {e}"))?;
        let p = s.perception.clone().unwrap_or_default();
        (seen, uncovered) = (seen + p.seen_points, uncovered + p.uncovered_points);
        if !s.safe() {
            unsafe_runs.push(format!("{name} ({model:?}): {}", perception_line(&s)));
        }
        if limits.contains(&(name.clone(), *model)) {
            if s.reached {
                return Err(format!(
                    "{name} {}: the file states that this law does not arrive with its own \
                     sensor, but it arrived with the lidar; update the file",
                    model.as_str()
                ));
            }
            stated.push(format!("{name} {} ({})", model.as_str(), s.outcome.kind()));
            continue;
        }
        if s.reached {
            arrived += 1;
            continue;
        }
        let refused = s.guarantees.iter().find_map(|g| match &g.check {
            Measured::ScansAccepted { error: Some(e), .. } => Some(e),
            _ => None,
        });
        let reason = match refused {
            Some(e) => format!("refused ({})", refusal(e)),
            None => s.outcome.kind().to_string(),
        };
        reasons
            .entry(reason)
            .or_default()
            .push(format!("{name} {}", model.as_str()));
    }
    let expected = runs.len() - stated.len();
    let detail = format!(
        "{arrived}/{expected} runs arrived ({} worlds × 2 laws, less {} that the file states do \
         not arrive with its own sensor either: [{}]); not arrived: {}; {} unsafe; {uncovered} \
         of {seen} seen truth points uncovered",
        runs.len() / 2,
        stated.len(),
        stated.join(", "),
        reasons
            .iter()
            .map(|(r, runs)| format!("{} {r} [{}]", runs.len(), runs.join(", ")))
            .collect::<Vec<_>>()
            .join(", "),
        unsafe_runs.len()
    );
    if let Some(first) = unsafe_runs.first() {
        return Err(format!("{detail}; first: {first}"));
    }
    if arrived == expected {
        Ok(Verdict::Held(detail))
    } else {
        Ok(Verdict::Target(detail))
    }
}

/// A refused scan's reason in a few words.
fn refusal(e: &NavError) -> &'static str {
    match e {
        NavError::ContainsRobot => "a shape over the robot",
        NavError::ContainsGoal => "a shape over the goal",
        NavError::CrossesBoundary => "a shape across the wall",
        NavError::NotStarWorld { .. } => "not a star world",
        _ => "another error",
    }
}

/// A lidar run in one line: its outcome, the failed guarantees, and the perception's counts.
pub fn perception_line(s: &Summary) -> String {
    let failed: Vec<String> = s
        .guarantees
        .iter()
        .filter(|g| !g.passed)
        .map(|g| format!("{} ({})", g.name(), g.detail()))
        .collect();
    let p = s.perception.clone().unwrap_or_default();
    format!(
        "{}{}, {} scans, {} events, {} shapes, {}/{} seen truth points uncovered, {} unfitted \
         segments, perceived/true area {}, clearance {:.3} m",
        s.outcome,
        if failed.is_empty() {
            String::new()
        } else {
            format!(" [FAILED: {}]", failed.join(", "))
        },
        p.scans,
        p.events,
        p.perceived,
        p.uncovered_points,
        p.seen_points,
        p.unfitted_segments,
        p.conservatism.map_or("-".into(), |c| format!("{c:.1}")),
        s.min_clearance
    )
}

fn summary(r: &LidarReport) -> String {
    format!(
        "{} runs: {} unsafe, {:.1} % arrived ({} stalled, {} refused{}), {} scans, {} events \
         ({} obstacles joined the boundary), true clearance ≥ {:.3} m, event clearance ≥ {:.3} m (first detections ≥ {:.3} m), {} \
         truth samples uncovered, \
         perceived/true area {:.1} (median), top speed {:.2} m/s",
        r.runs,
        r.failures.len(),
        100.0 * r.arrival(),
        r.stalled,
        r.refused.len(),
        r.refused
            .first()
            .map_or(String::new(), |(s, e)| format!(": world {s}: {e}")),
        r.scans,
        r.events,
        r.joined,
        r.min_clearance,
        r.min_event_clearance,
        r.min_detection_clearance,
        r.uncovered,
        r.median_conservatism,
        r.max_speed
    )
}

/// No collision with the true shapes, every perceived shape containing its true obstacle
/// (256 boundary samples each, at every event), shapes only growing, at least 90 % arrived,
/// every event with the robot outside the changed shapes, and (dynamic law) below `√(2μ/m)`.
fn safe(suite: &LidarSuite, speed_bound: Option<f64>) -> Outcome {
    let r = suite.run().map_err(|e| e.to_string())?;
    let first = r.failures.first().map_or(String::new(), |(seed, f)| {
        format!(
            "; first: world {seed}: true clearance {:.2e}, {} uncovered, {} shrunk, error {:?}",
            f.true_clearance, f.uncovered, f.shrunk, f.error
        )
    });
    let detail = format!("{}{first}", summary(&r));
    if !(r.failures.is_empty()
        && r.min_event_clearance > 0.0
        && speed_bound.is_none_or(|b| r.max_speed < b))
    {
        return Err(detail);
    }
    if r.arrival() >= ARRIVAL {
        Ok(Verdict::Held(detail))
    } else {
        Ok(Verdict::Target(detail))
    }
}

/// The same kinematic suite with `D` = 0.3 m (the obstacles' diameters reach 1 m, so A3 is
/// false) must find truth outside the perceived shapes: the containment check has teeth.
fn negative_control(suite: &LidarSuite) -> Outcome {
    let r = suite.run().map_err(|e| e.to_string())?;
    outcome(
        r.uncovered > 0 && !r.failures.is_empty(),
        format!("D = 0.3 m: {}", summary(&r)),
    )
}
