//! The movers of a scenario in a run (issue 54, item 4; `docs/movers.md` §8): their scripted
//! true motion, the reports handed to the navigator, and the monitor of the true clearance
//! between the robot's disc and every mover's disc along every held step.
//!
//! Over one control period the robot moves straight (the held step: `x + τu`, or `x + τv⁺`
//! under semi-implicit Euler) and each mover along a chain of straight pieces (its script's
//! breaks), so the least distance over the period is exact: the minimum of `|a + s·b|` over
//! `s ∈ [0, 1]` on each piece, in closed form ([`closest_approach`]).

use harmonav::transform::random::Rng;
use harmonav::{Mode, Mover};
use harmonav_scenario::MoverSpec;
use harmonav_scenario::movers::{Script, report};
use nalgebra::Vector2;
use serde::Serialize;

use crate::guarantee::{Check, Guarantee};
use crate::trace::{MoverFrame, MoverMark};

/// The least distance between two points moving straight and uniformly over the same interval,
/// one from `a0` to `a1`, the other from `b0` to `b1`: `min_{s∈[0,1]} |d₀ + s(d₁ − d₀)|` with
/// `d = a − b`, at `s* = clamp(−d₀·w/|w|², 0, 1)`, `w = d₁ − d₀`.
#[must_use]
pub fn closest_approach(
    a0: Vector2<f64>,
    a1: Vector2<f64>,
    b0: Vector2<f64>,
    b1: Vector2<f64>,
) -> f64 {
    let d0 = a0 - b0;
    let w = (a1 - b1) - d0;
    let ww = w.norm_squared();
    let s = if ww > 0.0 {
        (-d0.dot(&w) / ww).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (d0 + s * w).norm().min(d0.norm()).min((d0 + w).norm())
}

/// What the movers did in a run (`summary.json`'s `movers`, only for a file with movers).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct MoverReport {
    /// Movers in the file.
    pub movers: usize,
    /// Commands in a certified mode (anything but `Overwhelmed`), `Yielding` included.
    pub certified_commands: usize,
    /// Commands the filter could not certify (`Mode::Overwhelmed`).
    pub overwhelmed_commands: usize,
    /// Certified commands the filter changed (`Mode::Yielding`).
    pub yielding_commands: usize,
    /// Periods without a command: the robot's disc overlapped a mover's as reported
    /// (`NavError::InMover`); the robot held still (kinematic) or stopped (dynamic).
    pub refused_commands: usize,
    /// Contact episodes: a mover's disc touching the robot's (true clearance ≤ 0) in a period
    /// after a period it did not.
    pub mover_contacts: usize,
    /// Periods with a contact whose command was certified (Theorem 1 says 0).
    pub contacts_after_certified: usize,
    /// The least true clearance between the robot's disc and a mover's over every held step,
    /// m (`null` when there was none to measure).
    pub min_mover_clearance: f64,
}

/// One robot of a file with `[[robots]]`, as the first robot's summary reports it.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FleetRobot {
    /// Start.
    pub start: [f64; 2],
    /// Goal.
    pub goal: [f64; 2],
    /// Arrived.
    pub reached: bool,
    /// When it arrived or the run ended, s.
    pub time_s: f64,
    /// Distance to its goal at the end, m.
    pub final_distance: f64,
    /// Its own guarantees but arrival all held.
    pub safe: bool,
    /// Its contacts with the scripted movers and its commands by mode (`null` without
    /// scripted movers).
    pub movers: Option<MoverReport>,
}

/// The robots of a file with `[[robots]]` (`summary.json`'s `fleet`): every robot after the
/// first (whose summary this is), and the clearances between all of them.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FleetReport {
    /// The robots after the first.
    pub others: Vec<FleetRobot>,
    /// Contact episodes between two robots.
    pub robot_contacts: usize,
    /// Periods with a contact between two robots whose commands were both certified.
    pub contacts_after_certified: usize,
    /// The least clearance between two robots' bodies, m.
    pub min_robot_clearance: f64,
}

/// The movers of a run: their scripts, the report noise and the monitor.
pub(crate) struct MoverWorld {
    specs: Vec<MoverSpec>,
    scripts: Vec<Script>,
    noise: Vec<Rng>,
    reports: Vec<Mover>,
    touching: Vec<bool>,
    robot_radius: f64,
    pub report: MoverReport,
}

impl MoverWorld {
    /// The movers of `specs` at `t = 0`, with a robot of `robot_radius`.
    pub fn new(specs: &[MoverSpec], robot_radius: f64) -> Self {
        Self {
            scripts: specs.iter().map(MoverSpec::script).collect(),
            noise: specs
                .iter()
                .map(|m| Rng::new(m.report_seed.unwrap_or(0)))
                .collect(),
            reports: Vec::with_capacity(specs.len()),
            touching: vec![false; specs.len()],
            specs: specs.to_vec(),
            robot_radius,
            report: MoverReport {
                movers: specs.len(),
                min_mover_clearance: f64::INFINITY,
                ..MoverReport::default()
            },
        }
    }

    /// Whether there are any.
    pub fn is_empty(&self) -> bool {
        self.specs.is_empty()
    }

    /// [`MoverWorld::reports`] followed by `peers`, the other robots.
    pub fn reports_with(&mut self, peers: impl Iterator<Item = Mover>) -> &[Mover] {
        self.reports();
        self.reports.extend(peers);
        &self.reports
    }

    /// The movers as reported now: each true centre offset within its error.
    pub fn reports(&mut self) -> &[Mover] {
        self.reports.clear();
        for ((m, s), rng) in self.specs.iter().zip(&self.scripts).zip(&mut self.noise) {
            let centre = report(s.position(), m.error, rng);
            let mover = Mover::new(centre, m.radius, m.speed_bound).with_error(m.error);
            self.reports.push(match m.share() {
                Some(share) => mover.reciprocal(share),
                None => mover,
            });
        }
        &self.reports
    }

    /// The movers now, the robot at `x` after a command formed as `mode` (control period `h`):
    /// what the recording draws.
    pub fn frame(&self, t: f64, x: Vector2<f64>, mode: Option<&'static str>, h: f64) -> MoverFrame {
        MoverFrame {
            t,
            robot: [x.x, x.y],
            mode,
            movers: self
                .specs
                .iter()
                .zip(&self.scripts)
                .map(|(m, s)| {
                    let p = s.position();
                    MoverMark {
                        position: [p.x, p.y],
                        radius: m.radius,
                        reach: m.radius + m.error + m.speed_bound * h,
                        reciprocal: m.share().is_some(),
                    }
                })
                .collect(),
        }
    }

    /// The command of this period: `Some(mode)`, or `None` when it was refused.
    pub fn count(&mut self, mode: Option<&Mode>) {
        let r = &mut self.report;
        match mode {
            None => r.refused_commands += 1,
            Some(Mode::Overwhelmed { .. }) => r.overwhelmed_commands += 1,
            Some(m) => {
                r.certified_commands += 1;
                r.yielding_commands += usize::from(matches!(m, Mode::Yielding { .. }));
            }
        }
    }

    /// One period of `h` s: the robot went straight from `x0` to `x1` under a command that was
    /// `certified` or not; the movers advance by their scripts, and every true clearance along
    /// the period is measured exactly.
    pub fn period(&mut self, x0: Vector2<f64>, x1: Vector2<f64>, h: f64, certified: bool) {
        let robot_at = |tau: f64| x0 + (tau / h) * (x1 - x0);
        let mut contact = false;
        for ((m, s), touching) in self
            .specs
            .iter()
            .zip(&mut self.scripts)
            .zip(&mut self.touching)
        {
            let reach = self.robot_radius + m.radius;
            let least = s
                .advance(h)
                .windows(2)
                .map(|w| {
                    let ((ta, pa), (tb, pb)) = (w[0], w[1]);
                    closest_approach(robot_at(ta), robot_at(tb), pa, pb)
                })
                .fold(f64::INFINITY, f64::min)
                - reach;
            self.report.min_mover_clearance = self.report.min_mover_clearance.min(least);
            let now = least <= 0.0;
            self.report.mover_contacts += usize::from(now && !*touching);
            *touching = now;
            contact |= now;
        }
        self.report.contacts_after_certified += usize::from(contact && certified);
    }

    /// The guarantee `no-collision-with-movers`, the robot's margin `margin`.
    pub fn guarantee(&self, margin: f64) -> Guarantee {
        judged(&self.report, margin)
    }
}

/// The guarantee `no-collision-with-movers` of a run's report `r`, the robot's margin `margin`.
pub(crate) fn judged(r: &MoverReport, margin: f64) -> Guarantee {
    Guarantee::new(
        Check::NoCollisionWithMovers {
            contacts: r.mover_contacts,
            after_certified: r.contacts_after_certified,
            overwhelmed_commands: r.overwhelmed_commands + r.refused_commands,
            min_clearance: r.min_mover_clearance,
            margin,
        },
        r.contacts_after_certified == 0,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vector2<f64> {
        Vector2::new(x, y)
    }

    /// Two linear motions, worked by hand: a from (0, 0) to (2, 0), b from (2, 1) to (0, 1)
    /// over the same interval. `d(s) = (−2 + 4s, −1)`: least at `s = ½`, distance 1.
    #[test]
    fn closest_approach_of_two_linear_motions_by_hand() {
        let d = closest_approach(v(0.0, 0.0), v(2.0, 0.0), v(2.0, 1.0), v(0.0, 1.0));
        assert!((d - 1.0).abs() < 1e-15, "{d}");
        // a from (0, 0) to (1, 0), b from (3, 4) to (3, 2): d(s) = (−3 + s, −4 + 2s), least
        // where (−3 + s) + 2(−4 + 2s) = 0, s = 11/5 > 1: at s = 1, |(−2, −2)| = 2√2.
        let d = closest_approach(v(0.0, 0.0), v(1.0, 0.0), v(3.0, 4.0), v(3.0, 2.0));
        assert!((d - 8f64.sqrt()).abs() < 1e-15, "{d}");
        // Both at rest, and a pass through each other (distance 0 at s = 0.25).
        let d = closest_approach(v(1.0, 1.0), v(1.0, 1.0), v(4.0, 5.0), v(4.0, 5.0));
        assert_eq!(d, 5.0);
        let d = closest_approach(v(0.0, 0.0), v(4.0, 0.0), v(1.0, 0.0), v(1.0, 0.0));
        assert!(d.abs() < 1e-15);
        // Against 10⁵ samples of the interval: never above them, and within the samples'
        // spacing error (|w|²(Δs/2)²/(2d) ≈ 8e-9 m here).
        let (a0, a1, b0, b1) = (v(-1.0, 0.3), v(2.0, -0.7), v(0.5, -2.0), v(0.2, 1.9));
        let sampled = (0..=100_000)
            .map(|i| {
                let s = f64::from(i) / 1e5;
                ((a0 + s * (a1 - a0)) - (b0 + s * (b1 - b0))).norm()
            })
            .fold(f64::INFINITY, f64::min);
        let exact = closest_approach(a0, a1, b0, b1);
        assert!(
            exact <= sampled && sampled - exact < 2e-8,
            "{exact} {sampled}"
        );
    }
}
