//! The movers of a scenario in a run (issue 54, item 4; `docs/movers.md` §8): their scripted
//! true motion, the reports handed to the navigator, and the monitor of the true clearance
//! between the robot's disc and every mover's disc along every held step.
//!
//! Over one control period a holonomic robot moves straight (the held step: `x + τu`, or
//! `x + τv⁺` under semi-implicit Euler) and each mover along a chain of straight pieces (its
//! script's breaks), so the least distance over the period is exact: the minimum of
//! `|a + s·b|` over `s ∈ [0, 1]` on each piece, in closed form ([`closest_approach`]).
//!
//! A differential drive moves on the arc of its held `(v, ω)` ([`Sweep::Arc`]), at the
//! constant speed `|v|` with curvature `ω/v`. Its distance to a straight mover has no closed
//! form, so the arc is cut into pieces of duration `Δt`, and on each the arc is replaced by
//! its chord traversed uniformly in time; the arc stays within the **bow**
//!
//! ```text
//! |x(t₀ + sΔt) − ((1 − s)x(t₀) + s x(t₀ + Δt))| ≤ s(1 − s)/2 · Δt²|ẍ| ≤ |vω|Δt²/8,
//! ```
//!
//! of it (the error of linear interpolation of a curve whose second derivative is bounded by
//! `|ẍ| = |v||ω|`, the centripetal acceleration: the sagitta bound `L|Δ|/8` with `L = |v|Δt`
//! and `Δ = ωΔt`), so `closest_approach` of the chord less the bow is a proven lower bound on
//! the arc's least distance over the piece ([`least_distance`]). The chord's least distance is
//! itself within the bow of the arc's, so the bound lies within twice the bows below the
//! truth; the pieces are made short enough that the bows of both motions add to at most half
//! of [`ARC_TOLERANCE`]: the bound is within it of the true least distance, never above it.

use harmonav::transform::random::Rng;
use harmonav::{Mode, Mover};
use harmonav_scenario::MoverSpec;
use harmonav_scenario::movers::{Script, report};
use nalgebra::Vector2;
use serde::Serialize;

use crate::guarantee::{Check, Guarantee};
use crate::trace::{MoverFrame, MoverMark, Sample};

/// How far below the true least distance between two motions over a period the bound of
/// [`least_distance`] may lie when one of them is an arc, m: the pieces an arc is cut into
/// are short enough that the bows of the two motions add up to at most half of this.
pub const ARC_TOLERANCE: f64 = 1e-8;

/// The most pieces [`least_distance`] cuts one straight piece of the other motion into (a
/// longer arc's bound is looser than [`ARC_TOLERANCE`], never above the truth).
pub const ARC_MAX_PIECES: usize = 100_000;

/// How a robot moved over one control period of length `h`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sweep {
    /// Straight and uniformly from the first point to the second (a holonomic robot's held
    /// step, or a robot at rest).
    Straight(Vector2<f64>, Vector2<f64>),
    /// The arc of a differential drive holding `(v, ω)` from the pose `(x, yaw)`
    /// ([`harmonav::unicycle_arc`]).
    Arc {
        /// The position at the period's start.
        x: Vector2<f64>,
        /// The heading at the period's start, rad.
        yaw: f64,
        /// The forward speed held, m/s.
        v: f64,
        /// The turn rate held, rad/s.
        omega: f64,
    },
}

impl Sweep {
    /// The position `tau` s into the period of length `h`.
    #[must_use]
    pub fn at(&self, tau: f64, h: f64) -> Vector2<f64> {
        match *self {
            Self::Straight(x0, x1) => x0 + (tau / h) * (x1 - x0),
            Self::Arc { x, yaw, v, omega } => harmonav::unicycle_arc(x, yaw, v, omega, tau).0,
        }
    }

    /// The bow of a piece of `dt` s: how far the motion may stray from the chord between its
    /// ends traversed uniformly, `|vω|dt²/8` (0 for a straight motion).
    #[must_use]
    pub fn bow(&self, dt: f64) -> f64 {
        match *self {
            Self::Straight(..) => 0.0,
            Self::Arc { v, omega, .. } => 0.125 * (v * omega).abs() * dt * dt,
        }
    }
}

/// A lower bound on the least distance between two motions over `[ta, tb]` within a period of
/// length `h`: `a`, and a straight uniform motion from `pa` at `ta` to `pb` at `tb`, whose own
/// bow over the whole piece is `b_bow` (0 for a mover's straight piece; for another arc, the
/// other motion is given by `b_at` and bows as it). Exact ([`closest_approach`]) when
/// neither bows; else the piece is cut into `n` equal pieces with the bows of both within
/// half of [`ARC_TOLERANCE`], and each chord's least distance less its bows is taken.
fn least_over(
    a: &Sweep,
    b_at: &dyn Fn(f64) -> Vector2<f64>,
    b_bow: &dyn Fn(f64) -> f64,
    (ta, tb): (f64, f64),
    h: f64,
) -> f64 {
    let whole = a.bow(tb - ta) + b_bow(tb - ta);
    // Neither bows (or a bow that is not a number): the exact straight case.
    if whole.is_nan() || whole <= 0.0 {
        return closest_approach(a.at(ta, h), a.at(tb, h), b_at(ta), b_at(tb));
    }
    // The bows scale with the square of the piece's duration.
    let n = (2.0 * whole / ARC_TOLERANCE)
        .sqrt()
        .ceil()
        .clamp(1.0, ARC_MAX_PIECES as f64) as usize;
    let dt = (tb - ta) / n as f64;
    let bow = a.bow(dt) + b_bow(dt);
    (0..n)
        .map(|k| {
            let (s0, s1) = (
                ta + k as f64 * dt,
                if k + 1 == n {
                    tb
                } else {
                    ta + (k + 1) as f64 * dt
                },
            );
            closest_approach(a.at(s0, h), a.at(s1, h), b_at(s0), b_at(s1)) - bow
        })
        .fold(f64::INFINITY, f64::min)
}

/// The force that stops a robot of mass `mass` at velocity `v` within one period `h`,
/// `−m v/h`, scaled to `|f| ≤ F` under a force bound `bound` (the base can brake no harder):
/// what the loops hold when no command is certified (the bodies overlap).
pub(crate) fn stop(mass: f64, v: Vector2<f64>, h: f64, bound: Option<f64>) -> Vector2<f64> {
    let f = -mass * v / h;
    match bound {
        Some(b) if f.norm() > b => f * (b * (1.0 - 4.0 * f64::EPSILON) / f.norm()),
        _ => f,
    }
}

/// A lower bound on the least distance between two robots' centres moving as `a` and `b` over
/// one period of length `h`: exact for two straight motions ([`closest_approach`]), within
/// [`ARC_TOLERANCE`] below the truth when either is an arc.
#[must_use]
pub fn least_distance(a: &Sweep, b: &Sweep, h: f64) -> f64 {
    if let (Sweep::Straight(a0, a1), Sweep::Straight(b0, b1)) = (a, b) {
        return closest_approach(*a0, *a1, *b0, *b1);
    }
    least_over(a, &|t| b.at(t, h), &|dt| b.bow(dt), (0.0, h), h)
}

/// A lower bound on the least distance between a robot moving as `robot` over a period of
/// length `h` and a mover along the straight pieces `breaks` (`(τ, centre)` in time order,
/// from `τ = 0` to `h`, [`Script::advance`]): exact for a straight robot, within
/// [`ARC_TOLERANCE`] below the truth for an arc.
#[must_use]
pub fn least_to_pieces(robot: &Sweep, breaks: &[(f64, Vector2<f64>)], h: f64) -> f64 {
    breaks
        .windows(2)
        .map(|w| {
            let ((ta, pa), (tb, pb)) = (w[0], w[1]);
            let mover = |t: f64| {
                if tb > ta {
                    pa + ((t - ta) / (tb - ta)) * (pb - pa)
                } else {
                    pa
                }
            };
            match robot {
                Sweep::Straight(..) => closest_approach(robot.at(ta, h), robot.at(tb, h), pa, pb),
                Sweep::Arc { .. } => least_over(robot, &mover, &|_| 0.0, (ta, tb), h),
            }
        })
        .fold(f64::INFINITY, f64::min)
}

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
    /// Commands in a certified mode (anything but `Overwhelmed` and `Braking`), `Yielding`
    /// included.
    pub certified_commands: usize,
    /// Commands not certified: the filter's `Mode::Overwhelmed`, or a force-bounded robot's
    /// `Mode::Braking` (its way to rest not certified).
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
    /// Its own recorded states, kept as the first robot's are (`crate::trajectory`): what the
    /// recording (`/robots/<i>/…`) and `trajectory.svg` draw of it. Not in `summary.json`.
    #[serde(skip)]
    pub samples: Vec<Sample>,
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
            // Not certified: overwhelmed by a mover, or a force-bounded robot's brake.
            Some(m) if !m.certified() => r.overwhelmed_commands += 1,
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
        self.period_along(&Sweep::Straight(x0, x1), h, certified);
    }

    /// [`MoverWorld::period`] for a robot that moved as `robot` (a differential drive's arc:
    /// every clearance bounded from below within [`ARC_TOLERANCE`], [`least_to_pieces`]).
    pub fn period_along(&mut self, robot: &Sweep, h: f64, certified: bool) {
        let mut contact = false;
        for ((m, s), touching) in self
            .specs
            .iter()
            .zip(&mut self.scripts)
            .zip(&mut self.touching)
        {
            let reach = self.robot_radius + m.radius;
            let least = least_to_pieces(robot, s.advance(h), h) - reach;
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

/// The guarantee `no-collision-between-robots` of a fleet of `robots` (star world or floor
/// plan): no contact between two robots in a period where both commands were certified
/// (Theorem 2, F2), and none of the `others_unsafe` other robots lost a guarantee of its own.
pub(crate) fn fleet_judged(r: &FleetReport, robots: usize, others_unsafe: usize) -> Guarantee {
    Guarantee::new(
        Check::NoCollisionBetweenRobots {
            robots,
            contacts: r.robot_contacts,
            after_certified: r.contacts_after_certified,
            min_clearance: r.min_robot_clearance,
            others_unsafe,
        },
        r.contacts_after_certified == 0 && others_unsafe == 0,
    )
}

impl FleetReport {
    /// Between every two robots `i < j` of a fleet of `n`, their motions over one period of
    /// `h` (`swept[i]`: how robot `i` moved and whether its command was certified), bodies of
    /// radius `radius` (all alike): the least clearance, a contact episode where it reaches 0
    /// after a period it did not (`touching`, `n × n`, kept across periods), and a contact in
    /// a period where both commands were certified. Exact for straight steps, within
    /// [`ARC_TOLERANCE`] below the truth along arcs ([`least_distance`]).
    pub(crate) fn period(
        &mut self,
        swept: &[(Sweep, bool)],
        touching: &mut [bool],
        radius: f64,
        h: f64,
    ) {
        let n = swept.len();
        for i in 0..n {
            for j in i + 1..n {
                let least = least_distance(&swept[i].0, &swept[j].0, h) - 2.0 * radius;
                self.min_robot_clearance = self.min_robot_clearance.min(least);
                let now = least <= 0.0;
                self.robot_contacts += usize::from(now && !touching[i * n + j]);
                self.contacts_after_certified += usize::from(now && swept[i].1 && swept[j].1);
                touching[i * n + j] = now;
            }
        }
    }
}

/// The other robots of a fleet as robot `i` is given them: `at[j]` is robot `j`'s position,
/// speed bound and whether it has ended; reciprocal (share ½, exact position) while it flies,
/// a non-cooperative mover at rest once it has ended. Bodies of radius `radius`.
pub(crate) fn peers(
    at: &[(Vector2<f64>, f64, bool)],
    i: usize,
    radius: f64,
) -> impl Iterator<Item = Mover> + '_ {
    at.iter()
        .enumerate()
        .filter(move |(j, _)| *j != i)
        .map(move |(_, &(p, speed, done))| {
            if done {
                Mover::new(p, radius, 0.0)
            } else {
                Mover::new(p, radius, speed).reciprocal(0.5)
            }
        })
}

/// The marks of the robots of `at` (as [`peers`]) in the first robot's movers' frames: the
/// reach of one control period `h`.
pub(crate) fn peer_marks(at: &[(Vector2<f64>, f64, bool)], radius: f64, h: f64) -> Vec<MoverMark> {
    at.iter()
        .map(|&(p, speed, done)| MoverMark {
            position: [p.x, p.y],
            radius,
            reach: radius + speed * h,
            reciprocal: !done,
        })
        .collect()
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

    /// The least of `|a(τ) − b(τ)|` over 10⁵ + 1 instants of the period.
    fn dense(a: impl Fn(f64) -> Vector2<f64>, b: impl Fn(f64) -> Vector2<f64>, h: f64) -> f64 {
        (0..=100_000)
            .map(|i| {
                let t = h * f64::from(i) / 1e5;
                (a(t) - b(t)).norm()
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Along an arc the bound is never above the densely sampled least distance and within
    /// `ARC_TOLERANCE` (and the samples' spacing) of it: against a mover with a break inside
    /// the period, another arc, and a straight robot (where it is `closest_approach` itself).
    #[test]
    fn the_arc_bound_is_below_the_truth_and_within_its_tolerance() {
        let h = 0.1;
        let arcs = [
            Sweep::Arc {
                x: v(0.0, 0.0),
                yaw: 0.3,
                v: 0.5,
                omega: 2.0,
            },
            Sweep::Arc {
                x: v(0.1, -0.2),
                yaw: -2.0,
                v: 0.4,
                omega: -1.5,
            },
            Sweep::Arc {
                x: v(0.0, 0.1),
                yaw: 1.0,
                v: 2.0,
                omega: 7.0,
            },
        ];
        // A mover along two pieces, breaking at τ = 0.04.
        let breaks = [
            (0.0, v(0.06, 0.05)),
            (0.04, v(0.03, 0.04)),
            (0.1, v(0.0, -0.01)),
        ];
        let mover = |t: f64| {
            let ((ta, pa), (tb, pb)) = if t <= 0.04 {
                (breaks[0], breaks[1])
            } else {
                (breaks[1], breaks[2])
            };
            pa + ((t - ta) / (tb - ta)) * (pb - pa)
        };
        for a in &arcs {
            let bound = least_to_pieces(a, &breaks, h);
            let truth = dense(|t| a.at(t, h), mover, h);
            assert!(
                bound <= truth && truth - bound < ARC_TOLERANCE + 1e-9,
                "{a:?}: {bound} {truth}"
            );
            for b in &arcs {
                let bound = least_distance(a, b, h);
                let truth = dense(|t| a.at(t, h), |t| b.at(t, h), h);
                assert!(
                    bound <= truth && truth - bound < ARC_TOLERANCE + 1e-9,
                    "{a:?} {b:?}: {bound} {truth}"
                );
            }
        }
        // A straight robot is judged as before, by `closest_approach` on each piece.
        let straight = Sweep::Straight(v(-0.1, 0.0), v(0.1, 0.02));
        let robot = |t: f64| straight.at(t, h);
        let by_pieces = closest_approach(robot(0.0), robot(0.04), breaks[0].1, breaks[1].1).min(
            closest_approach(robot(0.04), robot(0.1), breaks[1].1, breaks[2].1),
        );
        assert_eq!(least_to_pieces(&straight, &breaks, h), by_pieces);
    }

    /// The negative control of the arc monitor: a mover at rest just outside the chord of a
    /// turning robot's arc, inside the arc (the case of docs/unicycle.md §3.3 among movers).
    /// Judged along the chord, as the straight monitor would, the clearance is positive; along
    /// the arc it is not.
    #[test]
    fn the_arc_monitor_sees_a_contact_the_chord_misses() {
        let (h, reach) = (0.1, 0.45);
        let arc = Sweep::Arc {
            x: v(0.0, 0.0),
            yaw: 0.0,
            v: 0.5,
            omega: 2.0,
        };
        let (start, mid, end) = (arc.at(0.0, h), arc.at(0.5 * h, h), arc.at(h, h));
        let chord_mid = 0.5 * (start + end);
        // The sagitta: 1.25 mm at most (L|Δ|/8 = 0.05 · 0.2 / 8).
        let out = (mid - chord_mid).normalize();
        assert!((mid - chord_mid).norm() <= 0.05 * 0.2 / 8.0);
        // The mover's centre 0.3 mm closer than `reach` to the arc's middle.
        let p = mid + (reach - 3e-4) * out;
        let still = [(0.0, p), (h, p)];
        let chord = least_to_pieces(&Sweep::Straight(start, end), &still, h) - reach;
        let along = least_to_pieces(&arc, &still, h) - reach;
        assert!(chord > 5e-4, "the chord is clear: {chord}");
        assert!(along <= -3e-4, "the arc goes in: {along}");
    }
}
