//! Differential-drive bases (issue 53): the robot takes a forward speed `v` and a turn rate `ω`
//! (`ẋ = v·e(θ)`, `θ̇ = ω`, `e(θ) = (cos θ, sin θ)`), bounded by `|v| ≤ v_max`, `|ω| ≤ ω_max`,
//! and cannot move sideways. [`Navigator::command_pose`] steers it by **aligned descent**
//! (docs/unicycle.md): turn towards the held descent direction `d_h` of `Θ`
//! (`ω = k_ω φ`, `φ` the angle from the heading to `d_h`), drive forward only at the speed the
//! heading's projection on it allows (`v = s·cos⁺φ`), the turn rate clamped into its limit;
//! then the **arc hold**: the arc that `(v, ω)` held for the control period sweeps is certified
//! free by sphere tracing in arc length and `Θ` must fall at its end, shortening only `v`.
//! Turning in place moves no point of a disc robot whose axle is at its centre, so it is always
//! safe.

use harmonav_field::FieldEval;
use nalgebra::Vector2;

use crate::base::{Base, Brake, GoalTolerance};
use crate::controller::Controller;
use crate::error::NavError;
use crate::hold::{self, KINEMATIC_FRACTION, MAX_HALVINGS, Mode};
use crate::movers;
use crate::navigator::Navigator;
use crate::options::HoldPolicy;
use crate::space::Space;
use crate::world::World;

/// `k_ω` of aligned descent, 1/s: `ω = k_ω φ` before the limits. The gain in force is
/// `min(k_ω, 1/h)`, so the heading never overshoots the target within a period
/// (docs/unicycle.md section 2). 10 since 2026-12-06 (was 4): at 10 Hz the heading meets the
/// descent direction in one period once the turn rate is not saturated; measured in
/// docs/unicycle.md section 11.
pub const TURN_GAIN: f64 = 10.0;

/// `k_g / k_ω`: near the goal the forward speed is at most `k_g|x − x_d|` with
/// `k_g = GOAL_GAIN_RATIO·k` (`k` the turn gain in force); `k_g < k` makes the heading error
/// decay on the final approach instead of orbiting the goal (docs/unicycle.md, Theorem 2).
pub const GOAL_GAIN_RATIO: f64 = 0.5;

/// During a recovery ([`Mode::Recovering`]) the robot turns in place until its heading is within
/// this angle (rad) of the way out, then drives straight (`ω = 0`) along it.
pub const RECOVERY_ALIGNMENT: f64 = 1e-6;

// `GOAL_ARRIVAL` is the 1 cm of `checks::fly`'s arrival test, checked here (with the
// feature `checks`): `base` cannot name `checks` (it would close a module cycle).
#[cfg(feature = "checks")]
const _: () = assert!(crate::base::GOAL_ARRIVAL == crate::checks::GOAL_TOLERANCE);

/// The arc search (docs/unicycle.md section 11) runs when the held holonomic command was
/// shortened below this fraction of the law's step ([`Mode::Capped`]) or stepped from rest
/// ([`Mode::FromRest`]): the field is stiff there (next to a saddle of `Θ` by a grown shape,
/// `−∇Θ` turns round within millimetres) and the heading cannot follow `d_h`. It runs too
/// whenever aligned descent would turn in place (`v = 0`), on a base without acceleration
/// limits.
const STIFF_SCALE: f64 = 0.5;

/// The arc search tries the turn rates `ω_max·j/ARC_SEARCH` for `j = −ARC_SEARCH ..=
/// ARC_SEARCH` (five arcs), each at the top speed, through the same arc hold.
const ARC_SEARCH: i32 = 2;

/// The arc search's hold tries each arc at most this many times (`v` shortened to the certified
/// length or halved between tries), so that one search costs at most `5 × 6` traces and
/// evaluations of `Θ`; an arc it gives up on is not taken.
const SEARCH_TRIES: u32 = 6;

/// How the `(v, ω)` of [`Navigator::command_pose`] was formed from the held direction.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Steer {
    /// Aligned descent as it is: `v = s·cos⁺φ`, `ω = kφ`, within the limits; its arc certified.
    /// Also an arc of the arc search (where the field is stiff, docs/unicycle.md section 11) at
    /// the top speed `min(s, v_max, k_g|x − x_d|)`.
    Ahead,
    /// The arc hold shortened `v` to `scale ∈ (0, 1)` of aligned descent's (its arc was not
    /// certified free, or `Θ` did not fall at its end); `ω` kept. For an arc of the arc search,
    /// `scale` is of the top speed.
    Shortened {
        /// The fraction of `v` kept.
        scale: f64,
    },
    /// `v = 0`, `ω ≠ 0`: turning in place (the heading is not a descent direction, no forward
    /// arc was certified, or a recovery is turning towards its way out).
    Turning,
    /// `v = 0`: the position has arrived ([`GoalTolerance::xy`]) and the base turns in place to the
    /// goal yaw of [`Navigator::set_goal_heading`], `ω = clamp(k·wrap(θ_g − θ), ±ω_cap)`.
    ToGoalHeading,
    /// `v = ω = 0`: the position has arrived and the heading is within
    /// [`GoalTolerance::yaw`] of the goal yaw ([`Navigator::set_goal_heading`]).
    Arrived,
    /// `v = ω = 0`: at the goal, at a critical point of `Θ`, or halted ([`Mode::Halted`]).
    Stopped,
    /// `v = max(0, v_last − a_max h)`: under acceleration limits ([`crate::Accel`]) the most
    /// the base can brake, which the previous command's braking disc certifies (eq.
    /// brakedisc); what it would have commanded was slower.
    Braking,
}

impl Steer {
    /// The name used in logs and Python (`"ahead"`, `"shortened"`, `"turning"`, `"stopped"`,
    /// `"braking"`, `"to-goal-heading"`, `"arrived"`).
    #[must_use]
    pub fn as_str(&self) -> &'static str {
        match self {
            Self::Ahead => "ahead",
            Self::Shortened { .. } => "shortened",
            Self::Turning => "turning",
            Self::Stopped => "stopped",
            Self::Braking => "braking",
            Self::ToGoalHeading => "to-goal-heading",
            Self::Arrived => "arrived",
        }
    }
}

/// The command of a differential-drive base for one control period
/// ([`Navigator::command_pose`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoseCommand {
    /// The forward speed `v`, m/s: `0 ≤ v ≤ v_max`.
    pub v: f64,
    /// The turn rate `ω`, rad/s (positive anticlockwise): `|ω| ≤ ω_max`.
    pub omega: f64,
    /// How the held holonomic command the robot steers by was formed (the direction `d_h`).
    pub mode: Mode,
    /// How `(v, ω)` was formed from it.
    pub steer: Steer,
}

impl PoseCommand {
    /// Whether the arc is certified to keep the robot clear over the period: false only for
    /// [`Mode::Overwhelmed`] (a mover's reach could not be kept out of along the arc).
    #[must_use]
    pub fn certified(&self) -> bool {
        !matches!(self.mode, Mode::Overwhelmed { .. })
    }
}

/// The headings `θ` between `yaw` and `yaw + sweep` of an arc, with `e(θ) = (cos θ, sin θ)` at
/// both ends computed once for all the movers' rows ([`Headings::least`]).
struct Headings {
    /// The smaller and larger end, rad.
    lo: f64,
    hi: f64,
    /// `e(lo)` and `e(hi)`.
    e_lo: Vector2<f64>,
    e_hi: Vector2<f64>,
}

impl Headings {
    fn new(yaw: f64, sweep: f64) -> Self {
        let (lo, hi) = if sweep >= 0.0 {
            (yaw, yaw + sweep)
        } else {
            (yaw + sweep, yaw)
        };
        Self {
            lo,
            hi,
            e_lo: Vector2::new(lo.cos(), lo.sin()),
            e_hi: Vector2::new(hi.cos(), hi.sin()),
        }
    }

    /// The least of `n·e(θ)` over the headings (`n` a unit vector): `−1` where they pass the
    /// heading opposite `n`, else the smaller end.
    fn least(&self, n: Vector2<f64>) -> f64 {
        let opposite = n.y.atan2(n.x) + std::f64::consts::PI;
        // The first copy of `opposite` at or after `lo`.
        let k = ((self.lo - opposite) / std::f64::consts::TAU).ceil();
        if opposite + k * std::f64::consts::TAU <= self.hi {
            -1.0
        } else {
            let at = |e: Vector2<f64>| n.x * e.x + n.y * e.y;
            at(self.e_lo).min(at(self.e_hi))
        }
    }
}

/// `sin a / a`, with its series near 0 (no cancellation).
fn sinc(a: f64) -> f64 {
    if a.abs() < 1e-4 {
        1.0 - a * a / 6.0
    } else {
        a.sin() / a
    }
}

/// The pose after holding `(v, ω)` for `t` from `(x, yaw)`: the exact solution of the unicycle
/// under a zero-order hold, a circular arc (a segment for `ω = 0`),
///
/// ```text
/// x(t) = x + v t · sinc(ωt/2) · e(yaw + ωt/2),   yaw(t) = yaw + ωt.
/// ```
///
/// For simulators and monitors; [`Navigator::command_pose`] certifies exactly this arc.
#[must_use]
pub fn unicycle_arc(x: Vector2<f64>, yaw: f64, v: f64, omega: f64, t: f64) -> (Vector2<f64>, f64) {
    let turn = omega * t;
    let mid = yaw + 0.5 * turn;
    let p = x + (v * t * sinc(0.5 * turn)) * Vector2::new(mid.cos(), mid.sin());
    (p, yaw + turn)
}

/// The point at arc length `l ≥ 0` along the forward arc of curvature `kappa` from `(x, yaw)`.
fn arc_point(x: Vector2<f64>, yaw: f64, kappa: f64, l: f64) -> Vector2<f64> {
    unicycle_arc(x, yaw, 1.0, kappa, l).0
}

/// The certified free length of the forward arc that `(v, ω)` (`v ≥ 0`) sweeps from `(x, yaw)`
/// in `h`, clipped at its length `vh`: sphere tracing in arc length
/// ([`hold::free_length_along`]).
fn free_arc(space: &impl Space, x: Vector2<f64>, yaw: f64, v: f64, omega: f64, h: f64) -> f64 {
    let length = v * h;
    if length <= 0.0 {
        return 0.0;
    }
    let kappa = omega / v;
    hold::free_length_along(space, |l| arc_point(x, yaw, kappa, l), length)
}

/// The arc hold: the largest `v' ≤ min(v, |x − x_d|/h)` reached by shortening only `v`, such
/// that the arc of `(v', ω)` over `h` is certified free and, given `descent = Some(e)`, `phi_k`
/// (so `Θ`) is lower at its end than at `x` (`e`); 0 if none is found. `None`: the direction
/// steered by need not descend `Θ` (an escape along the shortest path, a command the mover
/// filter changed), and only the certificate is asked for. Where the trace certifies a free length `F` short of
/// the arc's length, `v ← β F/h` (`β =` [`KINEMATIC_FRACTION`]) and the new arc (tighter: the
/// same turn `ωh` over a shorter length) is traced again; where `Θ` does not fall, `v` halves.
/// Every returned `v' > 0` has a traced, certified arc.
fn arc_hold(
    space: &impl Space,
    x: Vector2<f64>,
    yaw: f64,
    descent: Option<&FieldEval>,
    (v, omega): (f64, f64),
    h: f64,
) -> f64 {
    arc_hold_to(space, x, yaw, descent, (v, omega), h, 2 * MAX_HALVINGS).0
}

/// [`arc_hold`], with `phi_k` at the end of the returned arc (`+∞` when `descent` is `None` or
/// no arc was found).
fn arc_hold_to(
    space: &impl Space,
    x: Vector2<f64>,
    yaw: f64,
    descent: Option<&FieldEval>,
    (v, omega): (f64, f64),
    h: f64,
    tries: u32,
) -> (f64, f64) {
    let mut v = v.min((x - space.goal()).norm() / h);
    for _ in 0..tries {
        if v.is_nan() || v <= 0.0 {
            return (0.0, f64::INFINITY);
        }
        let length = v * h;
        let free = free_arc(space, x, yaw, v, omega, h);
        if free < length {
            v = v.min(KINEMATIC_FRACTION * free / h);
            continue;
        }
        let Some(e) = descent else {
            return (v, f64::INFINITY);
        };
        let (end, _) = unicycle_arc(x, yaw, v, omega, h);
        if let Ok(e1) = space.eval(end)
            && e1.phi < e.phi
        {
            return (v, e1.phi);
        }
        v *= 0.5;
    }
    (0.0, f64::INFINITY)
}

/// The arc search (docs/unicycle.md section 11): among the arcs of the turn rates
/// `ω_max·j/`[`ARC_SEARCH`] at the top speed `top`, each through [`arc_hold_to`] (certified free,
/// `phi_k` lower at its end than at `x`, shortening `v` only), the one whose end has the least
/// `phi_k`, if it is lower than `best` (`phi_k` at the end of the aligned arc, `+∞` if that
/// one does not move). `None`: no arc beats it. Only the nominal command changes: every arc
/// returned passed the same certificate as aligned descent's.
fn arc_search(
    space: &impl Space,
    x: Vector2<f64>,
    yaw: f64,
    e: &FieldEval,
    (top, omega_max): (f64, f64),
    h: f64,
    mut best: f64,
) -> Option<(f64, f64)> {
    let mut found = None;
    for j in -ARC_SEARCH..=ARC_SEARCH {
        let omega = omega_max * f64::from(j) / f64::from(ARC_SEARCH);
        let (v, phi) = arc_hold_to(space, x, yaw, Some(e), (top, omega), h, SEARCH_TRIES);
        if v > 0.0 && phi < best {
            (best, found) = (phi, Some((v, omega)));
        }
    }
    found
}

/// The braking certificate (docs/unicycle.md §10): the largest `v' ≤ v` (at most `|x − x_d|/h`,
/// halving) such that, with `κ = ω/v'`, either (eq. brakearc) `|κ| a_max ≤ alpha_max` and the
/// arc of curvature `κ` from `(x, yaw)` of length
///
/// ```text
/// v'h + v'²/(2 a_max)
/// ```
///
/// is certified free (sphere tracing in arc length), or (eq. brakedisc) the arc of `(v', ω)`
/// over `h` is certified free and so is the disc the base brakes to rest in from its end,
/// `c(x(h)) ≥ v'²/(2 a_max)` (`c` the certified clearance), whatever it turns meanwhile.
/// `(0, Disc)` if none is found. A speed that falls at `a_max` from `v'` covers at most
/// `v'²/(2 a_max)`.
fn braked_arc(
    space: &impl Space,
    x: Vector2<f64>,
    yaw: f64,
    (v, omega): (f64, f64),
    h: f64,
    a: crate::base::Accel,
) -> (f64, Brake) {
    let mut v = v.min((x - space.goal()).norm() / h);
    for _ in 0..2 * MAX_HALVINGS {
        if v.is_nan() || v <= 0.0 {
            return (0.0, Brake::Disc);
        }
        let kappa = omega / v;
        let stop = v * v / (2.0 * a.a_max);
        if kappa.abs() * a.a_max <= a.alpha_max {
            let length = v * h + stop;
            let free = hold::free_length_along(space, |l| arc_point(x, yaw, kappa, l), length);
            if free >= length {
                return (v, Brake::Arc(kappa));
            }
        }
        if free_arc(space, x, yaw, v, omega, h) >= v * h {
            let (end, _) = unicycle_arc(x, yaw, v, omega, h);
            if space.clearance(end, stop, None) >= stop {
                return (v, Brake::Disc);
            }
        }
        v *= 0.5;
    }
    (0.0, Brake::Disc)
}

/// What a base's acceleration limits leave of the next command: the most it can brake
/// (`floor`, with `floor_omega` its turn rate and `floor_brake` its certificate), and how the
/// command itself is certified (`brake`).
#[derive(Clone, Copy, Debug, Default)]
struct Limits {
    floor: f64,
    floor_omega: f64,
    floor_brake: Brake,
    brake: Brake,
}

/// Whether two goal yaws are the same, bit for bit (`None` equal to `None` only).
fn same_bits(a: Option<f64>, b: Option<f64>) -> bool {
    a.map(f64::to_bits) == b.map(f64::to_bits)
}

/// The signed angle from `a` to `b` (unit vectors), in `[−π, π]`.
fn angle(a: Vector2<f64>, b: Vector2<f64>) -> f64 {
    (a.x * b.y - a.y * b.x).atan2(a.dot(&b))
}

impl<W: World> Navigator<W> {
    /// The `(v, ω)` to hold for one control period `h` at the pose `(x, yaw)` of a
    /// differential-drive base ([`Base::Diff`]; `yaw` the heading, rad, map frame), with how it
    /// was formed. Works in star worlds and on floor plans alike.
    ///
    /// The law (aligned descent, docs/unicycle.md): the held holonomic command at `x`
    /// ([`Navigator::command`], with its recoveries, steps from rest and escapes) gives the
    /// direction `d_h`, the speed policy the speed `s(x)`; with `φ` the angle from `e(yaw)` to
    /// `d_h` and `k = min(`[`TURN_GAIN`]`, 1/h)`,
    ///
    /// ```text
    /// ω = clamp(k φ, ±ω_max),   v = min(s(x), v_max, k_g|x − x_d|) · cos⁺φ,   k_g = GOAL_GAIN_RATIO·k
    /// ```
    ///
    /// (the robot drives while its turn rate is saturated). Then, under
    /// [`HoldPolicy::Auto`] (the default), the arc hold: `v` alone is shortened until the arc that
    /// `(v, ω)` sweeps over `h` is certified free (sphere tracing in arc length against the
    /// certified clearance) and `Θ` falls at its end; `v = 0` (turning in place) needs no
    /// certificate. Where the field is stiff (the held command [`Mode::Capped`] below
    /// ½ or [`Mode::FromRest`]) or aligned descent would turn in place, the arc search: the
    /// arcs of five turn rates at the
    /// top speed through the same hold, the one whose end has the least `Θ` kept if it beats
    /// aligned descent's (reported [`Steer::Ahead`] at the top speed, else
    /// [`Steer::Shortened`]). So, held as given for `h`, the robot's disc never touches a known grown
    /// shape (or a floor plan's boundary layer), `Θ` never rises, `0 ≤ v ≤ v_max` and
    /// `|ω| ≤ ω_max`. Under [`HoldPolicy::Paper`] the aligned `(v, ω)` is returned unchecked.
    ///
    /// In a margin band (or a floor plan's boundary layer, or the blind layer of a shape,
    /// [`Mode::Recovering`]) the robot turns in place towards the way out until within
    /// [`RECOVERY_ALIGNMENT`] of it, then drives straight along it (`ω = 0`) at the recovery's
    /// speed, at most `v_max`. After a refused scan ([`Mode::Halted`]) the command is `(0, 0)`.
    ///
    /// Only the kinematic law: a navigator with the dynamic law and a differential-drive base
    /// is refused at construction. The pose is assumed exact and the command executed as held
    /// (a downstream velocity smoother or a latency voids the certificate unless the control
    /// period covers it).
    ///
    /// # Errors
    /// The base is [`Base::Holonomic`] ([`NavError::InvalidOption`] naming `base`); `yaw` not
    /// finite ([`NavError::NotFinite`], `"yaw"`); then as [`Navigator::command`].
    pub fn command_pose(&mut self, x: Vector2<f64>, yaw: f64) -> Result<PoseCommand, NavError> {
        let (mut pose, limits) = self.pose(x, yaw)?;
        let (mut v, mode, rebrake) =
            self.arc_among_movers(x, yaw, (pose.v, pose.omega), pose.mode, limits.floor)?;
        if self.core.goal_yaw.is_some() && self.final_phase(x) {
            // Nav2's `stateful` goal checker: the position stays arrived for this goal
            // (`Navigator::set_goal_stateful`), set by a command that succeeded only.
            self.core.goal_latched = self.core.goal_stateful;
        }
        let mut brake = rebrake.unwrap_or(limits.brake);
        if limits.floor > 0.0 && v <= limits.floor && v < pose.v {
            // The movers asked for less than the base can brake to: it brakes as certified.
            (v, pose.omega, brake) = (limits.floor, limits.floor_omega, limits.floor_brake);
            pose.steer = Steer::Braking;
        }
        self.core.pose_command = (v, pose.omega);
        self.core.brake = brake;
        let steer = if pose.steer == Steer::Braking {
            Steer::Braking
        } else if v < pose.v {
            if v > 0.0 {
                Steer::Shortened { scale: v / pose.v }
            } else if pose.omega != 0.0 {
                Steer::Turning
            } else {
                Steer::Stopped
            }
        } else {
            pose.steer
        };
        Ok(PoseCommand {
            v,
            mode,
            steer,
            ..pose
        })
    }

    /// [`Navigator::command_pose`] before the movers' rows, and what the acceleration limits
    /// leave ([`Limits`]; none without them).
    fn pose(&mut self, x: Vector2<f64>, yaw: f64) -> Result<(PoseCommand, Limits), NavError> {
        let Base::Diff {
            v_max,
            omega_max,
            accel,
        } = self.core.options.base
        else {
            return Err(NavError::InvalidOption {
                field: "base",
                value: f64::NAN,
            });
        };
        if !yaw.is_finite() {
            return Err(NavError::NotFinite { what: "yaw" });
        }
        if let Some(goal_yaw) = self.core.goal_yaw
            && self.final_phase(x)
        {
            let want = self.turn_to_goal_heading(x, yaw, goal_yaw, omega_max, accel)?;
            let (mut pose, limits) = match accel {
                None => (want, Limits::default()),
                Some(a) => self.accelerated(want, x, yaw, a),
            };
            if pose.steer == Steer::Arrived && pose.omega != 0.0 {
                // The turn-rate acceleration limit kept some of the last turn.
                pose.steer = Steer::ToGoalHeading;
            }
            return Ok((pose, limits));
        }
        let want = self.aligned(x, yaw, v_max, omega_max)?;
        Ok(match accel {
            None => (want, Limits::default()),
            Some(a) => self.accelerated(want, x, yaw, a),
        })
    }

    /// Whether the pose `x` is in the final phase of a goal with a yaw: within
    /// [`GoalTolerance::xy`] of the goal, or the position latched
    /// ([`Navigator::set_goal_stateful`]).
    fn final_phase(&self, x: Vector2<f64>) -> bool {
        self.core.goal_latched || (x - self.goal()).norm() < self.core.goal_tolerance.xy
    }

    /// The goal heading's command once the position has arrived (before the acceleration
    /// limits and the movers): with `e = wrap(θ_g − θ) ∈ [−π, π]` and `k = min(`[`TURN_GAIN`]`,
    /// 1/h)` (as aligned descent's, so the heading never overshoots within a period),
    ///
    /// ```text
    /// v = 0,   ω = clamp(k e, ±ω_cap),   ω_cap = ω_max  (or min(ω_max, √(2 alpha_max |e|)))
    /// ```
    ///
    /// ([`Steer::ToGoalHeading`]; the `√` under acceleration limits, so that the turn rate can
    /// be shed before the goal yaw), and `(0, 0)` ([`Steer::Arrived`]) once `|e| <` the yaw
    /// tolerance ([`GoalTolerance::yaw`], default [`GOAL_HEADING_TOLERANCE`](crate::tuning::GOAL_HEADING_TOLERANCE)). Turning
    /// in place moves no point of a disc robot whose axle is at its centre: the body occupies the same disc all period, so the command is safe
    /// whatever `ω` is, and the position keeps its certificate (it does not move). The held
    /// holonomic command is still formed (its mode reported, a refused scan halting the robot:
    /// [`Steer::Stopped`]).
    fn turn_to_goal_heading(
        &mut self,
        x: Vector2<f64>,
        yaw: f64,
        goal_yaw: f64,
        omega_max: f64,
        accel: Option<crate::base::Accel>,
    ) -> Result<PoseCommand, NavError> {
        let held = self.command(x, Vector2::zeros())?;
        let stopped = PoseCommand {
            v: 0.0,
            omega: 0.0,
            mode: held.mode,
            steer: Steer::Stopped,
        };
        if held.mode == Mode::Halted {
            return Ok(stopped);
        }
        let e = |a: f64| Vector2::new(a.cos(), a.sin());
        let error = angle(e(yaw), e(goal_yaw));
        if error.abs() < self.core.goal_tolerance.yaw {
            return Ok(PoseCommand {
                steer: Steer::Arrived,
                ..stopped
            });
        }
        let k = TURN_GAIN.min(1.0 / self.core.period);
        let cap = accel.map_or(omega_max, |a| {
            omega_max.min((2.0 * a.alpha_max * error.abs()).sqrt())
        });
        Ok(PoseCommand {
            omega: (k * error).clamp(-cap, cap),
            steer: Steer::ToGoalHeading,
            ..stopped
        })
    }

    /// Sets the goal yaw `θ_g` (rad, map frame) a differential-drive base finishes at (`None`:
    /// none, the default; Nav2's goals carry one). Once the position has arrived, `|x − x_d| <`
    /// [`GoalTolerance::xy`] (default [`GOAL_ARRIVAL`](crate::tuning::GOAL_ARRIVAL)), [`Navigator::command_pose`] turns in
    /// place, `v = 0`, `ω = clamp(k·wrap(θ_g − θ), ±ω_max)` ([`Steer::ToGoalHeading`]; within
    /// the acceleration limits, if any), until `|wrap(θ_g − θ)| <` [`GoalTolerance::yaw`]
    /// (default [`GOAL_HEADING_TOLERANCE`](crate::tuning::GOAL_HEADING_TOLERANCE)), then commands
    /// `(0, 0)` ([`Steer::Arrived`]); away from the goal it is not read. Without a goal yaw
    /// `command_pose` is what it was, bit for bit. [`Navigator::command`] does not read it.
    /// A different yaw (or `None`) releases the position latch ([`Navigator::goal_latched`]);
    /// the same yaw again keeps it.
    ///
    /// # Errors
    /// A non-finite yaw: [`NavError::NotFinite`] naming `"goal_yaw"`, the navigator unchanged.
    pub fn set_goal_heading(&mut self, yaw: Option<f64>) -> Result<(), NavError> {
        if yaw.is_some_and(|y| !y.is_finite()) {
            return Err(NavError::NotFinite { what: "goal_yaw" });
        }
        if !same_bits(self.core.goal_yaw, yaw) {
            self.core.goal_latched = false;
        }
        self.core.goal_yaw = yaw;
        Ok(())
    }

    /// The goal yaw of [`Navigator::set_goal_heading`] (`None`: none).
    #[must_use]
    pub fn goal_heading(&self) -> Option<f64> {
        self.core.goal_yaw
    }

    /// Sets where a goal with a yaw has arrived ([`GoalTolerance`]: the turn in place begins
    /// within `xy` of the goal and ends within `yaw` of the goal yaw; Nav2's
    /// `xy_goal_tolerance` and `yaw_goal_tolerance`). Without a goal yaw it is not read, and
    /// with the default `command_pose` is what it was, bit for bit. The radius latches
    /// ([`Navigator::set_goal_stateful`]): under acceleration limits the base brakes first and
    /// may roll out of it, and then keeps braking and turning in place, never driving back.
    /// A different tolerance releases the latch; the same one again keeps it.
    ///
    /// # Errors
    /// A bound that is not finite and positive: [`NavError::InvalidOption`] naming
    /// `"xy_goal_tolerance"` or `"yaw_goal_tolerance"`, the navigator unchanged.
    pub fn set_goal_tolerance(&mut self, tolerance: GoalTolerance) -> Result<(), NavError> {
        for (field, value) in [
            ("xy_goal_tolerance", tolerance.xy),
            ("yaw_goal_tolerance", tolerance.yaw),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(NavError::InvalidOption { field, value });
            }
        }
        if self.core.goal_tolerance != tolerance {
            self.core.goal_latched = false;
        }
        self.core.goal_tolerance = tolerance;
        Ok(())
    }

    /// Where a goal with a yaw has arrived ([`Navigator::set_goal_tolerance`]).
    #[must_use]
    pub fn goal_tolerance(&self) -> GoalTolerance {
        self.core.goal_tolerance
    }

    /// Whether the position tolerance of a goal with a yaw latches (Nav2's goal checker
    /// parameter `stateful`; `true`, the default, as Nav2's). Latched: once
    /// [`Navigator::command_pose`] has been given a pose within [`GoalTolerance::xy`] of the
    /// goal (with a goal yaw set, [`Navigator::set_goal_heading`]), every later command is the
    /// final phase, wherever the pose is: under acceleration limits the most the base can
    /// brake ([`Steer::Braking`], `v_b = max(0, v_last − a_max h)`) until it is at rest, then
    /// the turn in place ([`Steer::ToGoalHeading`], `v = 0`) until within
    /// [`GoalTolerance::yaw`] ([`Steer::Arrived`]). It never drives back towards the goal
    /// position: without the latch a base that rolled out of the radius while braking drove
    /// back in and braked again. The latch holds after [`Steer::Arrived`] too (a pose pushed
    /// out afterwards is not driven back; set the goal yaw again to re-arm). The goal itself
    /// is fixed for a navigator's life (a new goal is a new navigator, with no latch); a
    /// different goal yaw, tolerance or `stateful` releases the latch.
    ///
    /// Why the latch cannot weaken a certificate: the latched commands are of two kinds, both
    /// certified already without it. (1) `v = 0`: the unicycle `ẋ = v e(θ)`, `θ̇ = ω` gives
    /// `x(t) = x(0)` for every `t` in the period whatever `ω`, so the body, the disc
    /// `B(x(t), r)` of a robot whose axle is at its centre, is the same disc all period: the
    /// one it occupied at the pose, clear (the last command's arc, certified, ended there);
    /// `Θ(x(t)) = Θ(x(0))` does not rise. (2) Braking, `v_b`: the last command's braking
    /// certificate covers it (eq. brakedisc: the disc of radius `v_last²/(2 a_max)` about
    /// the end of its arc, certified free, holds every arc of length `v_b h + v_b²/(2a) ≤
    /// v_last²/(2a)`; eq. brakearc: its arc), the same command the unlatched base brakes
    /// with today. Without acceleration limits a base in the final phase commands `v = 0`, so
    /// in a closed loop with exact poses it never leaves the radius and the latch changes
    /// nothing, bit for bit; it acts only where the pose leaves the radius by itself (a
    /// braking base, a localisation jump).
    ///
    /// Unlatched (`false`): the final phase is decided afresh at every command by
    /// `|x − x_d| < xy`, the behaviour before 2026-12-07. Setting a different value releases
    /// the latch.
    pub fn set_goal_stateful(&mut self, stateful: bool) {
        if self.core.goal_stateful != stateful {
            self.core.goal_latched = false;
        }
        self.core.goal_stateful = stateful;
    }

    /// Whether the position tolerance latches ([`Navigator::set_goal_stateful`]).
    #[must_use]
    pub fn goal_stateful(&self) -> bool {
        self.core.goal_stateful
    }

    /// Whether the position tolerance is latched: a pose within [`GoalTolerance::xy`] of the
    /// goal has been commanded ([`Navigator::command_pose`], with a goal yaw) since the goal
    /// yaw, the tolerance or `stateful` last changed ([`Navigator::set_goal_stateful`]).
    #[must_use]
    pub fn goal_latched(&self) -> bool {
        self.core.goal_latched
    }

    /// The acceleration limits `a` applied to `want` (docs/unicycle.md §10): `ω` within
    /// `alpha_max·h` of the last command's, `v` at most `a_max·h` above it and at most
    /// `√(2 a_max |x − x_d|)`, and, under [`HoldPolicy::Auto`], shortened until its braking is
    /// certified ([`braked_arc`]); never below `v_b = max(0, v_last − a_max h)`, the most the
    /// base can brake ([`Steer::Braking`]), which the last command's certificate covers: on
    /// its arc (`ω_b = κ v_b`, eq. brakearc) or within its disc (eq. brakedisc), since
    /// `v_b h + v_b²/(2a) ≤ v_last²/(2a)`.
    fn accelerated(
        &self,
        want: PoseCommand,
        x: Vector2<f64>,
        yaw: f64,
        a: crate::base::Accel,
    ) -> (PoseCommand, Limits) {
        let h = self.core.period;
        let (v0, w0) = self.core.pose_command;
        let floor = (v0 - a.a_max * h).max(0.0);
        let omega = want.omega.clamp(w0 - a.alpha_max * h, w0 + a.alpha_max * h);
        let (floor_omega, floor_brake) = match self.core.brake {
            Brake::Arc(kappa) if floor > 0.0 => (kappa * floor, Brake::Arc(kappa)),
            _ => (omega, Brake::Disc),
        };
        // The goal is approached at a speed the base can shed before it (`v² ≤ 2 a_max |x −
        // x_d|`, the braking profile of the "auto" speed policy): without it the robot
        // overshot the goal and came back in loops the turn-rate limit made wide.
        let to_goal = (x - self.goal()).norm();
        let mut v = want
            .v
            .min(v0 + a.a_max * h)
            .min((2.0 * a.a_max * to_goal).sqrt());
        let mut brake = Brake::Disc;
        if let Mode::Recovering(_) = want.mode {
            // Inside a margin band no braking is certified (the clearance is negative): the
            // recovery's own straight step, a prefix of the one the hold certified, once the
            // turn rate has come to the recovery's.
            if omega != want.omega {
                v = 0.0;
            }
        } else if self.core.options.hold == HoldPolicy::Auto && v > floor {
            (v, brake) = braked_arc(self.world.field(), x, yaw, (v, omega), h, a);
        }
        let limits = Limits {
            floor,
            floor_omega,
            floor_brake,
            brake,
        };
        // At or below `v_b` only the braking command is certified (by the last command).
        if floor > 0.0 && v <= floor {
            let pose = PoseCommand {
                v: floor,
                omega: floor_omega,
                steer: Steer::Braking,
                ..want
            };
            return (
                pose,
                Limits {
                    brake: floor_brake,
                    ..limits
                },
            );
        }
        let steer = if v == want.v {
            want.steer
        } else if v > 0.0 {
            Steer::Shortened { scale: v / want.v }
        } else if omega != 0.0 {
            Steer::Turning
        } else {
            Steer::Stopped
        };
        let pose = PoseCommand {
            v,
            omega,
            steer,
            ..want
        };
        (pose, limits)
    }

    /// Aligned descent within `v_max` and `omega_max`, its arc held (the command of a base
    /// without acceleration limits).
    fn aligned(
        &mut self,
        x: Vector2<f64>,
        yaw: f64,
        v_max: f64,
        omega_max: f64,
    ) -> Result<PoseCommand, NavError> {
        let held = self.command(x, Vector2::zeros())?;
        let h = self.core.period;
        let stopped = PoseCommand {
            v: 0.0,
            omega: 0.0,
            mode: held.mode,
            steer: Steer::Stopped,
        };
        let s = held.value.norm();
        if held.mode == Mode::Halted || s.is_nan() || s <= 0.0 {
            return Ok(stopped);
        }
        let heading = Vector2::new(yaw.cos(), yaw.sin());
        let phi = angle(heading, held.value / s);
        if let Mode::Recovering(_) = held.mode {
            let pose = if phi.abs() > RECOVERY_ALIGNMENT {
                PoseCommand {
                    omega: (phi / h).clamp(-omega_max, omega_max),
                    steer: Steer::Turning,
                    ..stopped
                }
            } else {
                PoseCommand {
                    v: s.min(v_max),
                    steer: Steer::Ahead,
                    ..stopped
                }
            };
            return Ok(pose);
        }
        let k = TURN_GAIN.min(1.0 / h);
        let to_goal = (x - self.goal()).norm();
        let mut omega = k * phi;
        // The speed policy's `s(x)`, not the held command's (capped for a straight step along
        // `d_h`, which the robot does not take): the arc hold does its own shortening. Measured
        // in the 20 disc worlds of tests/diff_drive.rs (10 Hz): 20/20 arrivals, median 1.07× the
        // holonomic robot's time, against 19/20 and 1.13× with the held speed, whose
        // narrow-valley crawl the unicycle inherited.
        let field = self.world.field();
        let e = field.eval(x).ok();
        let s = match (&self.core.controller, &e) {
            (Controller::Kinematic(law), Some(e)) => law.speed(e, to_goal).max(s),
            _ => s,
        };
        let top = s.min(v_max).min(GOAL_GAIN_RATIO * k * to_goal);
        let mut v = top * phi.cos().max(0.0);
        // The turn rate alone is clamped: the robot drives while it turns at `ω_max` (measured,
        // docs/unicycle.md section 11: scaling `v` with it, the curvature kept, cost 1–3 % of
        // the time against HL and up to 8 % in the files that start facing away).
        omega = omega.clamp(-omega_max, omega_max);
        let mut aligned = v;
        // The law's own commands descend `Θ`; an escape follows the shortest path and a command
        // the mover filter changed dodges: their arcs need only be certified free (without
        // this a diff robot escaping on a floor plan turned in place for ever).
        let descends = matches!(held.mode, Mode::Law | Mode::Capped { .. } | Mode::FromRest);
        if self.core.options.hold == HoldPolicy::Auto && v > 0.0 {
            v = match (&e, descends) {
                (Some(e), true) => arc_hold(field, x, yaw, Some(e), (v, omega), h),
                (_, false) => arc_hold(field, x, yaw, None, (v, omega), h),
                (None, true) => 0.0,
            };
        }
        let stiff = match held.mode {
            Mode::Capped { scale } => scale < STIFF_SCALE,
            Mode::FromRest => true,
            _ => false,
        };
        // Under acceleration limits the searched arc is rarely reachable from a turn in place
        // (the turn rate changes by `alpha_max·h` at most): there the search runs only where
        // the field is stiff (measured, docs/unicycle.md section 11).
        let limited = matches!(self.core.options.base, Base::Diff { accel: Some(_), .. });
        let trigger = stiff || (v <= 0.0 && !limited);
        if let (Some(e), true, true) = (&e, descends, trigger)
            && self.core.options.hold == HoldPolicy::Auto
        {
            // Next to a saddle of `Θ` by a grown shape `d_h` turns round within millimetres
            // and the heading chases it (docs/unicycle.md section 11): the arc search picks
            // the certified arc that lowers `Θ` most, usually along the shape, away from the
            // saddle.
            let best = if v > 0.0 {
                let (end, _) = unicycle_arc(x, yaw, v, omega, h);
                field.eval(end).map_or(f64::INFINITY, |e1| e1.phi)
            } else {
                f64::INFINITY
            };
            if let Some(found) = arc_search(field, x, yaw, e, (top, omega_max), h, best) {
                (v, omega) = found;
                aligned = top;
            }
        }
        let steer = if v == aligned && v > 0.0 {
            Steer::Ahead
        } else if v > 0.0 {
            Steer::Shortened { scale: v / aligned }
        } else if omega != 0.0 {
            Steer::Turning
        } else {
            Steer::Stopped
        };
        if !(v.is_finite() && omega.is_finite()) {
            return Err(NavError::NonFiniteCommand);
        }
        let pose = PoseCommand {
            v,
            omega,
            mode: held.mode,
            steer,
        };
        Ok(pose)
    }

    /// The forward speed of the arc `(v, ω)` from `(x, yaw)` kept out of every mover's reach
    /// over the period (docs/movers.md §2, docs/unicycle.md): along the arc
    /// `n_j·(x(τ) − x) ≥ τ·v·m_j`, `m_j` the least of `n_j·e(θ)` over the arc's headings, so eq.
    /// reach gives the row `v·m_j ≥ V_j − β d_j/h` on `v ≥ 0`. A row with `m_j < 0` caps `v`; one
    /// with `m_j > 0` and a positive bound asks for a least speed. `v` is only ever shortened
    /// (and the shortened arc certified again against the known shapes, and `Θ`); the mode is
    /// `mode` when nothing changed, [`Mode::Yielding`] when `v` was shortened for a mover, and
    /// [`Mode::Overwhelmed`] when no `v ≤` the certified one meets every row (the largest
    /// shortfall, m/s; the command then keeps the shortest certified `v`).
    fn arc_among_movers(
        &mut self,
        x: Vector2<f64>,
        yaw: f64,
        (v, omega): (f64, f64),
        mode: Mode,
        floor: f64,
    ) -> Result<(f64, Mode, Option<Brake>), NavError> {
        if self.core.movers.is_empty() {
            return Ok((v, mode, None));
        }
        let h = self.core.period;
        let body = (x, self.core.options.radius, self.core.options.margin);
        movers::rows(&self.core.movers, body, h, 0.0, &mut self.core.rows)?;
        let headings = Headings::new(yaw, omega * h);
        // `m_j` of each row, computed once (reused by `worst` below).
        let along = &mut self.core.along;
        along.clear();
        along.extend(self.core.rows.iter().map(|row| headings.least(row.n)));
        let (mut cap, mut least) = (v, 0.0_f64);
        for (row, &m) in self.core.rows.iter().zip(along.iter()) {
            if m < 0.0 {
                cap = cap.min((row.a / m).max(0.0));
            } else if row.a > 0.0 {
                least = least.max(if m > 0.0 { row.a / m } else { f64::INFINITY });
            }
        }
        let mut kept = cap;
        let mut rebrake = None;
        if kept < v && kept > floor && self.core.options.hold == HoldPolicy::Auto {
            // The shorter arc is another curve: certified free again (the filter drops the
            // descent of `Θ` while it acts, docs/movers.md §2), with its braking under
            // acceleration limits.
            kept = match self.core.options.base {
                Base::Diff { accel: Some(a), .. } => {
                    let (kept, brake) = braked_arc(self.world.field(), x, yaw, (kept, omega), h, a);
                    rebrake = Some(brake);
                    kept
                }
                _ => arc_hold(self.world.field(), x, yaw, None, (kept, omega), h),
            };
        }
        // Under acceleration limits the base cannot be slower than `floor`: a row that asks
        // for less is not met (Overwhelmed below).
        kept = kept.max(floor);
        let worst = |speed: f64| {
            self.core
                .rows
                .iter()
                .zip(&self.core.along)
                .map(|(row, &m)| (row.mover, row.a - speed * m))
                .fold((0, f64::NEG_INFINITY), |a, b| if b.1 > a.1 { b } else { a })
        };
        let (mover, shortfall) = worst(kept);
        let inside = self.core.rows.iter().any(|row| row.inside);
        if kept < least || shortfall > 0.0 || inside {
            return Ok((kept, Mode::Overwhelmed { mover, shortfall }, rebrake));
        }
        if kept < v {
            let scale = if v > 0.0 { kept / v } else { 0.0 };
            return Ok((kept, Mode::Yielding { mover, scale }, rebrake));
        }
        // The arc meets every row, whatever the holonomic command it steers by did.
        Ok(match mode {
            Mode::Overwhelmed { mover, .. } => (v, Mode::Yielding { mover, scale: 1.0 }, None),
            mode => (v, mode, None),
        })
    }

    /// The certified free length of the arc that `(v, ω)` held for the control period sweeps
    /// from the pose `(x, yaw)` (`v ≥ 0`; for `ω = 0`, the straight step along `e(yaw)`), clipped
    /// at its length `vh`: sphere tracing in arc length against the certified clearance of
    /// [`Navigator::clearance`]. The arc is certified free iff this equals `vh`. For monitors
    /// and tests of [`Navigator::command_pose`]'s hold. 0 for a negative, zero or non-finite
    /// `v`, or a non-finite pose or `ω`.
    pub fn free_arc_length(&self, x: Vector2<f64>, yaw: f64, v: f64, omega: f64) -> f64 {
        let finite = x.iter().all(|c| c.is_finite()) && yaw.is_finite() && omega.is_finite();
        if !(finite && v.is_finite() && v > 0.0) {
            return 0.0;
        }
        free_arc(self.world.field(), x, yaw, v, omega, self.core.period)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// The closed form against a fine explicit integration of `ẋ = v e(θ)`, `θ̇ = ω`, including
    /// `ω → 0` (the series branch) and `ω = 0`.
    #[test]
    fn the_arc_is_the_unicycle_under_a_hold() {
        for (v, omega, t) in [
            (0.5, 2.0, 0.1),
            (0.3, -1.7, 0.05),
            (0.2, 1e-6, 0.1),
            (0.4, 0.0, 0.1),
            (0.1, 7.0, 1.0),
        ] {
            let (x0, yaw0) = (Vector2::new(0.3, -0.2), 0.7);
            let n = 20_000;
            let dt = t / n as f64;
            let (mut x, mut yaw) = (x0, yaw0);
            for _ in 0..n {
                let mid = yaw + 0.5 * omega * dt; // midpoint rule: O(dt²) per step
                x += v * dt * Vector2::new(mid.cos(), mid.sin());
                yaw += omega * dt;
            }
            let (p, y) = unicycle_arc(x0, yaw0, v, omega, t);
            assert!((p - x).norm() < 1e-9, "{v} {omega}: {}", (p - x).norm());
            assert!((y - yaw).abs() < 1e-9);
        }
    }

    /// `Headings::least` against the least of `n·e(θ)` over 20 001 headings of the arc: never
    /// above it (the rows stay conservative) and within the sampling's error of it, for sweeps
    /// of either sign, through the heading opposite `n` or not, and of length 0.
    #[test]
    fn the_least_projection_along_an_arc_is_the_sampled_least() {
        let e = |a: f64| Vector2::new(a.cos(), a.sin());
        for (i, (yaw, sweep)) in [
            (0.3, 0.0),
            (0.3, 0.2),
            (-2.0, -0.7),
            (3.0, 1.5),
            (-3.1, -0.3),
            (1.0, 6.0),
            (10.0, -2.5),
        ]
        .into_iter()
        .enumerate()
        {
            let headings = Headings::new(yaw, sweep);
            for k in 0..64 {
                let n = e(f64::from(k) * std::f64::consts::TAU / 64.0 + 0.01 * i as f64);
                let sampled = (0..=20_000)
                    .map(|j| n.dot(&e(yaw + sweep * f64::from(j) / 20_000.0)))
                    .fold(f64::INFINITY, f64::min);
                let least = headings.least(n);
                assert!(
                    least <= sampled + 1e-15,
                    "{yaw} {sweep} {n:?}: {least} > {sampled}"
                );
                assert!(
                    sampled - least < 1e-7,
                    "{yaw} {sweep} {n:?}: {least} ≪ {sampled}"
                );
            }
        }
    }

    #[test]
    fn the_angle_is_signed() {
        let e = |a: f64| Vector2::new(a.cos(), a.sin());
        assert!((angle(e(0.0), e(0.5)) - 0.5).abs() < 1e-15);
        assert!((angle(e(0.5), e(0.0)) + 0.5).abs() < 1e-15);
        assert!((angle(e(3.0), e(-3.0)) - (2.0 * PI - 6.0)).abs() < 1e-12);
    }
}
