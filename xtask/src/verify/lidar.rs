//! The Navigator on scans alone (issue 26, part 2; docs/maths.md §12.6): 24 seeded worlds
//! (`harmonav::checks::lidar::lidar_world`, discs only and every shape kind), a point and a
//! 0.1 m disc robot, a 360-beam lidar with 2 cm noise and 1 % dropouts at 10 Hz feeding
//! `Navigator::observe_scan`, both laws; and the negative control with a depth prior smaller
//! than the obstacles.

use harmonav::Law;
use harmonav::checks::lidar::{LidarReport, LidarSuite};

use super::{Check, Outcome, outcome};

/// The arrival each suite must show. Below 1 because a conservative shape may cover the goal
/// (the unseen side is closed up to `D` = 1 m behind what was seen; the scan is then refused
/// with `ContainsGoal` and the flight ends): measured 46 of 48 at 24 worlds.
const ARRIVAL: f64 = 0.9;

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
    vec![
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

fn summary(r: &LidarReport) -> String {
    format!(
        "{} runs: {} unsafe, {:.1} % arrived ({} stalled, {} refused{}), {} scans, {} events, \
         true clearance ≥ {:.3} m, event clearance ≥ {:.3} m (first detections ≥ {:.3} m), {} \
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
    outcome(
        r.failures.is_empty()
            && r.arrival() >= ARRIVAL
            && r.min_event_clearance > 0.0
            && speed_bound.is_none_or(|b| r.max_speed < b),
        format!("{}{first}", summary(&r)),
    )
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
