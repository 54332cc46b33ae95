//! The simulated lidar in the closed loop (`[sensor] type = "lidar"`, issue 26; docs/maths.md
//! §12.7): at every `t = n / rate_hz` it casts the scenario's beams against the true shapes
//! (seeded noise and dropouts, `harmonav_perception::sim::Lidar`), hands the scan to the
//! robot's navigator ([`Navigator::observe_scan`], its only perception) and judges what the
//! navigator perceived against the truth:
//!
//! - **covers the seen truth**: after each scan, `DENSE` times as many noise-free rays as the
//!   lidar's beams, from the same pose over the same aperture, find the true boundary points
//!   the sensor sees; each must lie in a perceived shape;
//! - **only grows**: at each event, points of every earlier perceived shape's boundary must
//!   lie in a perceived shape after it.

use std::f64::consts::TAU;

use harmonav::perception::Reading;
use harmonav::perception::growth::shrunk;
use harmonav::perception::sim::{Enclosure, Lidar};
use harmonav::{
    FloorNavigator, LaserScan, NavError, Navigator, Perceived, Pose, ScanUpdate, StarShape,
};
use harmonav_scenario::LidarSensor;
use harmonav_transform::random::Rng;
use nalgebra::Vector2;

use crate::guarantee::{Check, Guarantee};
use crate::summary::PerceptionReport;
use crate::trace::ScanRecord;

/// The coverage check casts this many noise-free rays per beam of the lidar.
pub const DENSE: usize = 10;

/// A scan is due at `t` once `t` is within this relative distance of its time (the
/// integrators land on it up to rounding).
const DUE: f64 = 1e-9;

/// A navigator the lidar feeds: [`Navigator`] in a star world, [`FloorNavigator`] in a floor
/// plan.
pub(crate) trait Scanned {
    /// The navigator's `observe_scan`.
    fn observe(&mut self, pose: Pose, scan: &LaserScan) -> Result<ScanUpdate, NavError>;
    /// The perceived shapes, in the perception's order.
    fn shapes(&self) -> Vec<&Perceived>;
}

impl Scanned for Navigator {
    fn observe(&mut self, pose: Pose, scan: &LaserScan) -> Result<ScanUpdate, NavError> {
        self.observe_scan(pose, scan)
    }

    fn shapes(&self) -> Vec<&Perceived> {
        self.perceived().map(|(_, p)| p).collect()
    }
}

impl Scanned for FloorNavigator {
    fn observe(&mut self, pose: Pose, scan: &LaserScan) -> Result<ScanUpdate, NavError> {
        self.observe_scan(pose, scan)
    }

    fn shapes(&self) -> Vec<&Perceived> {
        self.perceived().map(|(_, p)| p).collect()
    }
}

/// The truth a lidar scans: the obstacles and what encloses them (a star boundary or walls).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Scene<'a> {
    /// The true obstacles.
    pub obstacles: &'a [StarShape],
    /// The true boundary or walls.
    pub enclosure: Enclosure<'a>,
}

/// The lidar of a run, its seeded noise, and the running judgement.
pub(crate) struct Scanner {
    sensor: LidarSensor,
    rng: Rng,
    /// Scans taken; the next is due at `taken / rate_hz`.
    taken: u64,
    /// The perceived shapes after the last event.
    previous: Vec<StarShape>,
    report: PerceptionReport,
    /// The refused scan that stopped the run: when, and the navigator's error.
    refusal: Option<(f64, NavError)>,
}

impl Scanner {
    /// The lidar `sensor` before its first scan (due at `t = 0`).
    pub fn new(sensor: LidarSensor) -> Self {
        Self {
            sensor,
            rng: Rng::new(0x5CA0_0000 ^ sensor.seed),
            taken: 0,
            previous: Vec::new(),
            report: PerceptionReport::default(),
            refusal: None,
        }
    }

    /// The lidar, with the fit range of the run's law.
    pub fn sensor(&self) -> &LidarSensor {
        &self.sensor
    }

    /// The time of the next scan, s.
    pub fn next(&self) -> f64 {
        self.taken as f64 * self.sensor.period()
    }

    /// Whether a scan is due at `t`.
    pub fn due(&self, t: f64) -> bool {
        let next = self.next();
        t >= next - DUE * next.max(1.0)
    }

    /// Scans the truth from `x` with heading `yaw` at `t` and hands the scan to `nav`. On
    /// success the record of the scan; on a refusal the navigator's error (`nav` unchanged).
    pub fn scan(
        &mut self,
        nav: &mut impl Scanned,
        truth: Scene<'_>,
        t: f64,
        x: Vector2<f64>,
        yaw: f64,
    ) -> Result<ScanRecord, NavError> {
        let pose = Pose::new(x.x, x.y, yaw);
        let lidar = self.sensor.lidar;
        let scan = lidar.scan_in(&pose, truth.obstacles, truth.enclosure, &mut self.rng);
        // The next scan is the first `n / rate_hz` after `t` (a fixed step longer than the
        // period skips the scans it stepped over instead of falling behind).
        let rate = self.sensor.rate_hz;
        self.taken = (self.taken + 1).max((t * rate + DUE).floor() as u64 + 1);
        let update = nav.observe(pose, &scan).inspect_err(|e| {
            self.refusal = Some((t, e.clone()));
        })?;
        self.report.scans += 1;
        self.report.unfitted_segments += update.unfitted;
        let now: Vec<StarShape> = nav
            .shapes()
            .into_iter()
            .map(|p| p.shape().clone())
            .collect();
        let c = coverage(
            &lidar,
            &pose,
            &scan,
            truth,
            &now,
            self.sensor.scan.fit_range,
        );
        self.report.seen_points += c.seen;
        self.report.uncovered_points += c.uncovered;
        if c.seen > c.uncovered {
            let d = self.report.min_cover_depth.get_or_insert(c.min_depth);
            *d = d.min(c.min_depth);
        }
        let perceived = update.changed().then(|| {
            self.report.events += 1;
            if let Some(c) = update.event_clearance {
                let m = self.report.min_event_clearance.get_or_insert(c);
                *m = m.min(c);
            }
            self.report.shrunk_points += shrunk(&self.previous, &now);
            self.previous.clone_from(&now);
            now
        });
        Ok(ScanRecord {
            time_s: t,
            pose,
            scan,
            perceived,
        })
    }

    /// The run stops at `t` because the navigator could not take a scan there (its command
    /// failed): the guarantee `scans-accepted` is lost.
    pub fn refuse(&mut self, t: f64, error: NavError) {
        self.refusal = Some((t, error));
    }

    /// The judgement at the end of the run, `nav` the navigator then: the report and the
    /// guarantees [`Kind::PerceivedCoversTruth`](crate::guarantee::Kind::PerceivedCoversTruth),
    /// [`Kind::PerceivedOnlyGrows`](crate::guarantee::Kind::PerceivedOnlyGrows) and
    /// [`Kind::ScansAccepted`](crate::guarantee::Kind::ScansAccepted).
    pub fn judge(
        &self,
        nav: &impl Scanned,
        truth: &[StarShape],
    ) -> (PerceptionReport, Vec<Guarantee>) {
        let r = self.report(nav, truth);
        let guarantees = vec![
            Guarantee::new(
                Check::PerceivedCoversTruth {
                    seen_points: r.seen_points,
                    uncovered_points: r.uncovered_points,
                },
                r.uncovered_points == 0,
            ),
            Guarantee::new(
                Check::PerceivedOnlyGrows {
                    shrunk_points: r.shrunk_points,
                },
                r.shrunk_points == 0,
            ),
            Guarantee::new(
                Check::ScansAccepted {
                    scans: r.scans,
                    refused_at_s: self.refusal.as_ref().map(|r| r.0),
                    error: self.refusal.as_ref().map(|r| r.1.clone()),
                },
                self.refusal.is_none(),
            ),
        ];
        (r, guarantees)
    }

    /// The report at the end of the run, `nav` the navigator then.
    fn report(&self, nav: &impl Scanned, truth: &[StarShape]) -> PerceptionReport {
        let perceived = nav.shapes();
        let seen: f64 = truth
            .iter()
            .filter(|o| perceived.iter().any(|p| p.shape().contains(o.centre())))
            .map(StarShape::area)
            .sum();
        let area: f64 = perceived.iter().map(|p| p.area()).sum();
        PerceptionReport {
            perceived: perceived.len(),
            conservatism: (seen > 0.0).then(|| area / seen),
            ..self.report.clone()
        }
    }
}

/// What the coverage check found at one pose.
struct Coverage {
    /// True boundary points seen.
    seen: usize,
    /// Of those, outside every perceived shape.
    uncovered: usize,
    /// The smallest depth of a covered one inside the perceived shape that holds it deepest,
    /// m (`+∞`: none covered).
    min_depth: f64,
}

/// The coverage check at `pose`: the true boundary points that [`DENSE`] noise-free rays per
/// beam of `lidar` hit first (within `range_max − noise`, the reach at which every true hit
/// reads as a return under A1, and not behind the boundary) on an obstacle that a return of
/// `scan` within `fit_range` hit (farther segments are left for a later scan, docs/maths.md
/// §12.11) (the perception's claim is about the obstacles its beams saw, all of each: an
/// obstacle seen only through a gap narrower than the beams, or behind dropouts, is not one),
/// how many of them lie outside every shape of `perceived`, and how deep the others lie.
fn coverage(
    lidar: &Lidar,
    pose: &Pose,
    scan: &LaserScan,
    truth: Scene<'_>,
    perceived: &[StarShape],
    fit_range: f64,
) -> Coverage {
    let s = pose.position();
    let boundary = truth.enclosure;
    // Only the obstacles whose bounding disc the range reaches.
    let near: Vec<&StarShape> = truth
        .obstacles
        .iter()
        .filter(|o| (o.centre() - s).norm() - o.radius_bounds().1 <= lidar.range_max)
        .collect();
    let mut c = Coverage {
        seen: 0,
        uncovered: 0,
        min_depth: f64::INFINITY,
    };
    if near.is_empty() {
        return c;
    }
    // The obstacles the scan's returns hit (noise-free along their beams).
    let mut hit = vec![false; near.len()];
    for i in 0..scan.ranges.len() {
        if matches!(scan.reading(i), Reading::Hit(r) if r <= fit_range)
            && let Some((k, _)) = lidar.first_obstacle_hit_in(
                s,
                scan.direction(pose, i),
                near.iter().copied(),
                boundary,
            )
        {
            hit[k] = true;
        }
    }
    let lidar = &Lidar {
        range_max: lidar.range_max - lidar.noise,
        ..*lidar
    };
    let (angle_min, increment) = lidar.angles();
    let full = (lidar.aperture - TAU).abs() < 1e-12;
    let rays = if full {
        lidar.beams * DENSE
    } else {
        (lidar.beams - 1) * DENSE + 1
    };
    let step = increment / DENSE as f64;
    for i in 0..rays {
        let a = pose.yaw + angle_min + i as f64 * step;
        let u = Vector2::new(a.cos(), a.sin());
        let first = lidar.first_obstacle_hit_in(s, u, near.iter().copied(), boundary);
        if let Some((_, t)) = first.filter(|(k, _)| hit[*k]) {
            c.seen += 1;
            let p = s + t * u;
            let depth = perceived
                .iter()
                .filter(|q| q.contains(p))
                .map(|q| -q.signed_distance(p))
                .fold(f64::NEG_INFINITY, f64::max);
            if depth == f64::NEG_INFINITY {
                c.uncovered += 1;
            } else {
                c.min_depth = c.min_depth.min(depth);
            }
        }
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;
    use harmonav::perception::growth::GROWTH_SAMPLES;

    /// A shape that shrinks is caught, one that grows or stays is not.
    #[test]
    fn growth_check() {
        let small = StarShape::circle(Vector2::new(1.0, 0.0), 0.5).unwrap();
        let large = StarShape::circle(Vector2::new(1.0, 0.0), 0.6).unwrap();
        assert_eq!(
            shrunk(std::slice::from_ref(&small), std::slice::from_ref(&large)),
            0
        );
        assert_eq!(
            shrunk(std::slice::from_ref(&large), std::slice::from_ref(&small)),
            GROWTH_SAMPLES
        );
        // The same shape again: every point lies on it, none outside.
        assert_eq!(
            shrunk(std::slice::from_ref(&small), std::slice::from_ref(&small)),
            0
        );
    }
}
