//! The worst-case scan of the hostile round of 2026-12-06 (D2): a full turn of ranges at
//! random, as rain, dust, glass, a failing lidar or an adversarial reflector give, through
//! `Navigator::observe_scan`. Shared by the criterion bench (`cargo bench -p harmonav-bench
//! --bench hostile_scan`) and `cargo xtask bench --only observe_scan`
//! (`observe_scan_hostile_us_360`, target [`TARGET_US`]).
//!
//! The navigator of the round: the disc of radius 10 m, the goal at (8, 0), a robot of radius
//! 0.1 m at (−3, 0), the default scan options (radial hulls, the free fan, a 16-scan memory).
//! Before the fix one 360-beam scan of ranges uniform in [0.05, 3] m cost about 40 s of CPU
//! before the event was refused (`ContainsRobot`); 45 beams 4–14 s.

use harmonav::transform::random::Rng;
use harmonav::{LaserScan, Law, Navigator, Options, Pose, StarShape, Vector2};

/// The target for one hostile 360-beam scan, µs (≤ 10 ms, release build).
pub const TARGET_US: f64 = 10_000.0;

/// The round's navigator (module docs), nothing perceived yet.
///
/// # Panics
/// Never: the world is valid.
#[must_use]
pub fn navigator() -> Navigator {
    let boundary = StarShape::circle(Vector2::zeros(), 10.0).expect("a valid circle");
    Navigator::new(
        boundary,
        Vector2::new(8.0, 0.0),
        Law::kinematic(1.0),
        Options::default().with_robot(0.1, 0.0),
    )
    .expect("a valid world")
}

/// The robot's pose, (−3, 0), heading 0.
#[must_use]
pub fn pose() -> Pose {
    Pose::new(-3.0, 0.0, 0.0)
}

/// A full turn of `beams` ranges uniform in `[lo, hi]` m (seed 0), range 3 m: for `[0.05, 3]`
/// the round's hostile scan.
#[must_use]
pub fn scan(beams: usize, lo: f64, hi: f64) -> LaserScan {
    let mut rng = Rng::new(0);
    LaserScan {
        angle_min: -std::f64::consts::PI,
        angle_increment: std::f64::consts::TAU / beams as f64,
        range_min: 0.0,
        range_max: 3.0,
        ranges: (0..beams).map(|_| rng.uniform(lo, hi)).collect(),
    }
}
