//! Differential-drive robots in the held-command loop (issue 53, item 4; docs/unicycle.md,
//! "Simulator"): a file with `[robot] base = "diff"` runs in `held.rs`, which asks
//! [`harmonav::Navigator::command_pose`] for `(v, ω)` at every period and moves the robot on
//! the exact arc of the unicycle (`Diff::period`), and this module's monitors judge every arc:
//!
//! ```text
//! ẋ = v·e(θ),  θ̇ = ω,  e(θ) = (cos θ, sin θ);   held for h from (x₀, θ₀):
//! x(t) = x₀ + v t·sinc(ωt/2)·e(θ₀ + ωt/2),   θ(t) = θ₀ + ωt         (harmonav::unicycle_arc)
//! ```
//!
//! - **No collision along the arcs** ([`swept_clearance`]): the body disc's clearance `c` from
//!   the true obstacles and boundary is 1-Lipschitz in the position, and the arc is 1-Lipschitz
//!   in its length `ℓ` (a chord is never longer than its arc), so between two points of the
//!   arc `Δℓ` apart with clearances `c₀`, `c₁` the clearance is at least `(c₀ + c₁ − Δℓ)/2`.
//!   The points are spaced by a share of the clearance above the margin, so the bound is
//!   within [`ARC_STEP_MIN`] of the margin where the arc comes close, and cheap elsewhere.
//! - **The bounds** (`Diff::guarantees`): `0 ≤ v ≤ v_max`, `|ω| ≤ ω_max` for every command
//!   held, without tolerance.

use harmonav::{Base, Mode, NavError, Navigator, PoseCommand, Steer, unicycle_arc};
use harmonav_scenario::Truth;
use nalgebra::Vector2;
use serde::Serialize;

use crate::guarantee::MARGIN_TOLERANCE;
use crate::guarantee::{Check, Guarantee};

/// The spacing of the points along an arc, as a share of their clearance above the margin:
/// the bound `(c₀ + c₁ − Δℓ)/2` then lies within `ARC_STEP_SHARE/2` of it (2.5 %).
pub const ARC_STEP_SHARE: f64 = 0.05;

/// The least spacing of the points along an arc, m: within half of it of the margin the bound
/// is as fine as the spacing (well inside [`MARGIN_TOLERANCE`]).
pub const ARC_STEP_MIN: f64 = 1e-7;

/// The most points checked along one arc (its spacing is at least `L/ARC_MAX_POINTS`).
pub const ARC_MAX_POINTS: f64 = 1e5;

/// What a differential-drive run did (`summary.json`'s `diff`; absent for a holonomic robot).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct DiffReport {
    /// `v_max`, m/s.
    pub v_max: f64,
    /// `ω_max`, rad/s.
    pub omega_max: f64,
    /// The heading at the start, rad (`[robot] yaw`).
    pub start_yaw: f64,
    /// The heading at the end, rad (not controlled: the command is `(0, 0)` at the goal).
    pub final_yaw: f64,
    /// Commands of aligned descent as they are ([`Steer::Ahead`]).
    pub ahead: usize,
    /// Commands whose `v` the arc hold shortened ([`Steer::Shortened`]).
    pub shortened: usize,
    /// Commands turning in place ([`Steer::Turning`]).
    pub turning: usize,
    /// Commands `(0, 0)` ([`Steer::Stopped`]).
    pub stopped: usize,
    /// The smallest `v` held, m/s.
    pub min_v: f64,
    /// The largest `v` held, m/s.
    pub max_v: f64,
    /// The largest `|ω|` held, rad/s.
    pub max_omega: f64,
    /// The total turn `Σ|ω|h`, rad.
    pub total_turn: f64,
    /// A lower bound on the body's clearance from the true obstacles and boundary along every
    /// arc ([`swept_clearance`]), m.
    pub swept_clearance: f64,
    /// Points of the arcs whose clearance was measured.
    pub arc_points: usize,
    /// The acceleration limits `(a_max, alpha_max)` (`[robot] a_max`, `alpha_max`; `None`
    /// without them).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel: Option<(f64, f64)>,
    /// The largest `|v⁺ − v|/h` between consecutive commands, the first from rest, m/s²
    /// (reported with acceleration limits).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_dv: Option<f64>,
    /// The largest `|ω⁺ − ω|/h`, rad/s² (as `max_dv`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_domega: Option<f64>,
    /// Commands at the most the base can brake ([`Steer::Braking`]; with acceleration limits).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub braking: Option<usize>,
}

/// The differential drive of a run in progress: its pose's heading and its monitors.
#[derive(Clone, Debug)]
pub(crate) struct Diff {
    /// The heading `θ`, rad.
    pub yaw: f64,
    /// What was measured so far.
    pub report: DiffReport,
    /// The last command held, `(v, ω)` (`(0, 0)` at the start: at rest).
    last: (f64, f64),
}

impl Diff {
    /// A robot on the differential-drive `base` (its bounds and acceleration limits), heading
    /// `yaw` at the start; `None` for a holonomic base.
    pub fn of(base: Option<Base>, yaw: f64) -> Option<Self> {
        let Some(Base::Diff {
            v_max,
            omega_max,
            accel,
        }) = base
        else {
            return None;
        };
        let accel = accel.map(|a| (a.a_max, a.alpha_max));
        let measured = accel.map(|_| 0.0);
        Some(Self {
            yaw,
            report: DiffReport {
                v_max,
                omega_max,
                start_yaw: yaw,
                final_yaw: yaw,
                min_v: f64::INFINITY,
                swept_clearance: f64::INFINITY,
                accel,
                max_dv: measured,
                max_domega: measured,
                braking: accel.map(|_| 0),
                ..DiffReport::default()
            },
            last: (0.0, 0.0),
        })
    }

    /// The robot at `x` holds `c` for `h` from the current heading: the command and the arc
    /// are judged against `truth` (`margin` spaces the arc's points), and the position and
    /// velocity `v·e(θ)` at the period's end are returned, the heading updated.
    pub fn period(
        &mut self,
        truth: &Truth,
        x: Vector2<f64>,
        c: &PoseCommand,
        h: f64,
    ) -> (Vector2<f64>, Vector2<f64>) {
        self.period_in(&|p| truth_clearance(truth, p), truth.margin, x, c, h)
    }

    /// [`Diff::period`] in any world: `clearance` the body disc's clearance from the true
    /// shapes at a position (1-Lipschitz), `margin` the robot's (a floor plan's walls and
    /// obstacles, `crate::floor`).
    pub fn period_in(
        &mut self,
        clearance: &dyn Fn(Vector2<f64>) -> f64,
        margin: f64,
        x: Vector2<f64>,
        c: &PoseCommand,
        h: f64,
    ) -> (Vector2<f64>, Vector2<f64>) {
        let r = &mut self.report;
        match c.steer {
            Steer::Ahead => r.ahead += 1,
            Steer::Shortened { .. } => r.shortened += 1,
            Steer::Turning => r.turning += 1,
            Steer::Braking => *r.braking.get_or_insert(0) += 1,
            _ => r.stopped += 1,
        }
        if r.accel.is_some() {
            let (v0, w0) = self.last;
            r.max_dv = r.max_dv.map(|m| m.max((c.v - v0).abs() / h));
            r.max_domega = r.max_domega.map(|m| m.max((c.omega - w0).abs() / h));
        }
        self.last = (c.v, c.omega);
        r.min_v = r.min_v.min(c.v);
        r.max_v = r.max_v.max(c.v);
        r.max_omega = r.max_omega.max(c.omega.abs());
        r.total_turn += c.omega.abs() * h;
        let (swept, points) =
            swept_clearance_in(clearance, margin, (x, self.yaw), (c.v, c.omega), h);
        r.swept_clearance = r.swept_clearance.min(swept);
        r.arc_points += points;
        let (x1, yaw1, v1) = crate::step::arc_step(x, self.yaw, c.v, c.omega, h);
        self.yaw = yaw1;
        r.final_yaw = yaw1;
        (x1, v1)
    }

    /// The guarantees of the run: `no-collision-between-states` along the arcs (the margin
    /// kept, within [`MARGIN_TOLERANCE`]), `diff-command-bounds`, and with acceleration
    /// limits `diff-accel-bounds`.
    pub fn guarantees(&self, margin: f64) -> Vec<Guarantee> {
        let r = &self.report;
        let mut out = vec![
            Guarantee::new(
                Check::NoCollisionBetweenStates {
                    swept_clearance: r.swept_clearance,
                },
                r.swept_clearance > 0.0 && r.swept_clearance >= margin - MARGIN_TOLERANCE,
            ),
            r.bounds(),
        ];
        out.extend(r.accel_bounds());
        out
    }
}

impl DiffReport {
    /// The guarantee `diff-accel-bounds` with acceleration limits (`None` without): every
    /// change between consecutive commands within the limits, to a relative `1e-12` (the
    /// rounding of `v ± a_max h` and of the division by `h`).
    #[must_use]
    pub fn accel_bounds(&self) -> Option<Guarantee> {
        let (a_max, alpha_max) = self.accel?;
        let (max_dv, max_domega) = (self.max_dv.unwrap_or(0.0), self.max_domega.unwrap_or(0.0));
        let within = |m: f64, limit: f64| m <= limit * (1.0 + 1e-12);
        Some(Guarantee::new(
            Check::DiffAccel {
                max_dv,
                a_max,
                max_domega,
                alpha_max,
            },
            within(max_dv, a_max) && within(max_domega, alpha_max),
        ))
    }

    /// The guarantee `diff-command-bounds`: `0 ≤ v ≤ v_max` and `|ω| ≤ ω_max` for every
    /// command held, without tolerance.
    #[must_use]
    pub fn bounds(&self) -> Guarantee {
        // No command held (the robot started at its goal): nothing exceeded.
        let min_v = if self.min_v.is_finite() {
            self.min_v
        } else {
            0.0
        };
        Guarantee::new(
            Check::DiffBounds {
                min_v,
                max_v: self.max_v,
                v_max: self.v_max,
                max_omega: self.max_omega,
                omega_max: self.omega_max,
            },
            min_v >= 0.0 && self.max_v <= self.v_max && self.max_omega <= self.omega_max,
        )
    }
}

/// A lower bound on the body disc's clearance from the true obstacles and boundary of `truth`
/// along the arc that `(v, ω)` held for `h` sweeps from the pose `(x, yaw)`, and the points
/// measured. With `ℓ_j` points along the arc (length `L = |v|h`) and `c_j` their clearances,
///
/// ```text
/// c(ℓ) ≥ (c_j + c_{j+1} − (ℓ_{j+1} − ℓ_j))/2   on [ℓ_j, ℓ_{j+1}],
/// ℓ_{j+1} − ℓ_j = max(ARC_STEP_SHARE·(c_j − margin), ARC_STEP_MIN, L/ARC_MAX_POINTS),
/// ```
///
/// (`c` 1-Lipschitz, the arc 1-Lipschitz in `ℓ`). Turning in place (`v = 0`) moves no point
/// of the disc: the clearance at `x`.
#[must_use]
pub fn swept_clearance(
    truth: &Truth,
    pose: (Vector2<f64>, f64),
    command: (f64, f64),
    h: f64,
) -> (f64, usize) {
    swept_clearance_in(
        &|p| truth_clearance(truth, p),
        truth.margin,
        pose,
        command,
        h,
    )
}

/// The body disc's clearance from a star world's true obstacles and boundary at `p`.
fn truth_clearance(truth: &Truth, p: Vector2<f64>) -> f64 {
    let (obstacle, boundary) = truth.clearances(p);
    obstacle.min(boundary)
}

/// [`swept_clearance`] with the clearance function `clearance` (1-Lipschitz) and the margin
/// `margin` that spaces the points: any world's.
#[must_use]
pub fn swept_clearance_in(
    clearance: &dyn Fn(Vector2<f64>) -> f64,
    margin: f64,
    (x, yaw): (Vector2<f64>, f64),
    (v, omega): (f64, f64),
    h: f64,
) -> (f64, usize) {
    let c0 = clearance(x);
    let length = v.abs() * h;
    if !(length > 0.0 && length.is_finite()) {
        return (c0, 1);
    }
    // The point at arc length `l`: the arc at unit speed with the curvature `ω/v` (backwards
    // for `v < 0`, which aligned descent never commands).
    let at = |l: f64| unicycle_arc(x, yaw, v.signum(), omega / v.abs(), l).0;
    let least = ARC_STEP_MIN.max(length / ARC_MAX_POINTS);
    let (mut l, mut c, mut worst, mut points) = (0.0, c0, c0, 1);
    while l < length {
        let step = (ARC_STEP_SHARE * (c - margin)).max(least);
        let next = if l + step >= length { length } else { l + step };
        let c1 = clearance(at(next));
        worst = worst.min(0.5 * (c + c1 - (next - l)));
        (l, c) = (next, c1);
        points += 1;
    }
    (worst, points)
}

/// The `(v, ω)` of a differential drive at the pose `(x, yaw)`
/// ([`Navigator::command_pose`]) and the mode it was formed in; the mode `None` when it was
/// refused because the robot's disc overlaps a reported mover's (`NavError::InMover`, only
/// with `movers`): no certified command, the robot holds still, `(0, 0)`.
pub(crate) fn pose_command(
    nav: &mut Navigator<impl harmonav::World>,
    x: Vector2<f64>,
    yaw: f64,
    movers: bool,
) -> Result<(PoseCommand, Option<Mode>), NavError> {
    match nav.command_pose(x, yaw) {
        Ok(c) => Ok((c, Some(c.mode))),
        Err(NavError::InMover { .. }) if movers => {
            let stopped = PoseCommand {
                v: 0.0,
                omega: 0.0,
                mode: Mode::Halted,
                steer: Steer::Stopped,
            };
            Ok((stopped, None))
        }
        Err(e) => Err(e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use harmonav::Mode;
    use std::path::Path;

    /// One disc of radius 2 m at the origin in a 10 m world, a robot of radius 0.1 m.
    fn truth() -> Truth {
        let text = "name = \"disc\"\n[workspace]\ntype = \"circle\"\ncenter = [0.0, 0.0]\n\
                    radius = 10.0\n[[obstacles]]\ntype = \"circle\"\ncenter = [0.0, 0.0]\n\
                    radius = 2.0\n[robot]\nmodel = \"kinematic\"\nstart = [-5.0, 0.0]\n\
                    goal = [5.0, 0.0]\nradius = 0.1\n";
        let path = Path::new("disc.toml");
        harmonav_scenario::Scenario::parse(path, text)
            .unwrap()
            .prepare(path)
            .unwrap()
            .truth
    }

    fn command(v: f64, omega: f64) -> PoseCommand {
        PoseCommand {
            v,
            omega,
            mode: Mode::Law,
            steer: Steer::Ahead,
        }
    }

    /// The loop's step is the closed form, against a fine midpoint integration of the
    /// unicycle, and the velocity at the end lies along the new heading.
    #[test]
    fn a_period_moves_the_robot_on_the_exact_arc() {
        let t = truth();
        for (v, omega) in [(0.5, 2.0), (0.3, -1.7), (0.4, 0.0), (0.0, 2.0)] {
            let (x0, yaw0, h) = (Vector2::new(-5.0, 1.0), 0.7, 0.1);
            let mut d = Diff::of(Some(Base::diff(0.5, 2.0)), yaw0).unwrap();
            let (x1, v1) = d.period(&t, x0, &command(v, omega), h);
            let n = 20_000;
            let dt = h / f64::from(n);
            let (mut x, mut yaw) = (x0, yaw0);
            for _ in 0..n {
                let mid = yaw + 0.5 * omega * dt;
                x += v * dt * Vector2::new(mid.cos(), mid.sin());
                yaw += omega * dt;
            }
            assert!((x1 - x).norm() < 1e-9, "{v} {omega}: {}", (x1 - x).norm());
            assert!((d.yaw - yaw).abs() < 1e-12);
            assert!((v1 - v * Vector2::new(yaw.cos(), yaw.sin())).norm() < 1e-12);
        }
    }

    /// The negative control of the arc monitor: the robot 0.1 mm clear of the disc, heading
    /// along its tangent and turning into it (`v = 0.5`, `ω = −2`, `h = 0.05`; the case of
    /// docs/unicycle.md §3.3). The straight step along the heading is clear at its states and at
    /// 1 001 points between (a loop that integrated the arc as a straight line would see
    /// nothing); the arc goes about 1 mm in, and the arc monitor flags it.
    #[test]
    fn the_arc_monitor_flags_what_a_straight_judgement_misses() {
        let t = truth();
        let grown = 2.0 + t.radius;
        let x = Vector2::new(0.0, grown + 1e-4);
        let (yaw, v, omega, h) = (0.0, 0.5, -2.0, 0.05);
        let clearance = |p: Vector2<f64>| t.clearances(p).0;
        // The wrong integration: a straight step along the heading, judged at its states and by
        // their Lipschitz bound.
        let straight_end = x + v * h * Vector2::new(1.0, 0.0);
        let (c0, c1) = (clearance(x), clearance(straight_end));
        assert!(c0 > 0.0 && c1 > 0.0, "the straight step's states are clear");
        let dense = (0..=1000)
            .map(|i| clearance(x + f64::from(i) / 1000.0 * (straight_end - x)))
            .fold(f64::INFINITY, f64::min);
        assert!(dense > 0.0, "the straight step is clear: {dense}");
        // The true arc's end is clear too: only the arc between goes in.
        let (arc_end, _) = unicycle_arc(x, yaw, v, omega, h);
        assert!(clearance(arc_end) > -2e-3);
        let (swept, points) = swept_clearance(&t, (x, yaw), (v, omega), h);
        assert!(swept < -5e-4, "the arc goes in: {swept} ({points} points)");
        // And the loop's monitor fails it.
        let mut d = Diff::of(Some(Base::diff(0.5, 2.0)), yaw).unwrap();
        d.period(&t, x, &command(v, omega), h);
        let g = d.guarantees(0.0);
        assert!(!g[0].passed && g[1].passed, "{g:?}");
    }

    /// A clear arc passes, and its bound is within 2.5 % of the margin's excess of the densely
    /// sampled least clearance.
    #[test]
    fn a_clear_arc_passes_with_a_tight_bound() {
        let t = truth();
        let x = Vector2::new(0.0, 2.1 + 0.01);
        let (yaw, v, omega, h) = (0.0, 0.5, -0.5, 0.1);
        let (swept, _) = swept_clearance(&t, (x, yaw), (v, omega), h);
        let dense = (0..=10_000)
            .map(|i| {
                t.clearances(unicycle_arc(x, yaw, v, omega, h * f64::from(i) / 1e4).0)
                    .0
            })
            .fold(f64::INFINITY, f64::min);
        assert!(swept > 0.0 && swept <= dense, "{swept} {dense}");
        assert!(swept >= dense * (1.0 - ARC_STEP_SHARE) - ARC_STEP_MIN);
        let mut d = Diff::of(Some(Base::diff(0.5, 2.0)), yaw).unwrap();
        d.period(&t, x, &command(v, omega), h);
        assert!(d.guarantees(0.0).iter().all(|g| g.passed));
    }

    /// The other negative control: a command beyond a bound is flagged (`v > v_max`,
    /// `|ω| > ω_max`, `v < 0`), each alone.
    #[test]
    fn a_command_beyond_a_bound_is_flagged() {
        let t = truth();
        let x = Vector2::new(-5.0, 0.0);
        for (v, omega) in [(0.5 + 1e-12, 0.0), (0.2, -2.0 - 1e-12), (-0.1, 0.0)] {
            let mut d = Diff::of(Some(Base::diff(0.5, 2.0)), 0.0).unwrap();
            d.period(&t, x, &command(0.5, 2.0), 0.1);
            d.period(&t, x, &command(v, omega), 0.1);
            let g = d.guarantees(0.0);
            assert!(g[0].passed && !g[1].passed, "{v} {omega}: {g:?}");
        }
        let mut d = Diff::of(Some(Base::diff(0.5, 2.0)), 0.0).unwrap();
        d.period(&t, x, &command(0.5, -2.0), 0.1);
        assert!(d.guarantees(0.0)[1].passed);
    }
}
