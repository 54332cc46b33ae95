//! The sampled-data hold: the command the robot holds for one control period `h`, made safe
//! by construction ([`crate::HoldPolicy::Auto`], `docs/maths.md` §10), and the way back out of
//! the margin band.
//!
//! Everything here rests on one certified quantity, the clearance `d(x)` (`certified.rs`, or a
//! floor plan's through [`crate::space`]): a lower bound on the distance from `x` to the
//! nearest known grown obstacle and to the shrunk boundary. The ball `B(x, d(x))` lies in the
//! free space, so a motion that stays in it cannot collide.

use harmonav_control::{Damping, Dynamic, Kinematic};
use harmonav_field::FieldEval;
use harmonav_transform::Workspace;
use nalgebra::Vector2;

use crate::certified::{BLIND, Band, clearance, ray};
use crate::space::Space;

/// How a command was formed ([`Command::mode`]). Non-exhaustive: a later release may add a
/// way of forming a command (`FromRest` was added on 2026-12-05).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Mode {
    /// The law's command, safe to hold for the control period as it is (under
    /// [`crate::HoldPolicy::Paper`]: the continuous law, unchecked).
    Law,
    /// Shortened to be safe to hold: the kinematic step is `scale ∈ [0, 1)` of the law's (the
    /// law's direction; in a stiff valley the chord of its flow line, `scale` its length over
    /// the law's step), or the dynamic velocity after the step is `scale` of the law's.
    Capped {
        /// The fraction kept.
        scale: f64,
    },
    /// A way out, under either hold policy: the robot was inside the margin band (inside a
    /// grown shape but clear of the true one by at least its radius), or under
    /// [`crate::HoldPolicy::Auto`] so close to a shape that is not a circle that its certified
    /// clearance is 0 (within about 1e-4 of its size); the command moves it along the shape's
    /// ray, away from it.
    Recovering(Band),
    /// On a floor plan under the heading policy `"auto"`: the hold had stalled at a rest point
    /// of its slide on the edge of the certified region (a local minimum of `Θ` there, not of
    /// `Θ` itself), or the shortest path turned more than 90° from the law's descent, and the
    /// robot follows the shortest path until `phi_k` is [`crate::tuning::ESCAPE_DROP`] below the level
    /// where it began, or until blocked (docs/maths.md §13.7).
    Escaping,
    /// In a star world under [`crate::HoldPolicy::Auto`], the kinematic law's held step had
    /// come to rest away from the goal (below [`REST_SCALE`] of the law's speed: a saddle of
    /// `Θ`, or a valley whose floor no step along the law's direction could descend); the
    /// command is the steepest certified descent among [`REST_DIRECTIONS`] directions at the
    /// law's speed (docs/maths.md §10.1).
    FromRest,
    /// The last [`crate::Navigator::observe_scan`] was refused: what it saw is not in `Θ`, so
    /// no command is certified against it, and the robot stops until a scan is accepted. The
    /// kinematic command is 0; the dynamic force is `f = −m·ẋ/h`, which brings the velocity to
    /// 0 over the period (the robot moves at most `|ẋ|h/2` more, along its last certified
    /// velocity). Issue 56: a refused scan left the robot commanded as if the space were free.
    Halted,
    /// The mover filter changed the held command ([`crate::Navigator::set_movers`]) and it is
    /// certified: against every mover over the period (eq. reach) and against the known
    /// shapes. `mover` binds; `scale = |u|/|u_nominal|` (the dynamic law: of `v⁺`).
    Yielding {
        /// The binding mover's index.
        mover: usize,
        /// The speed kept.
        scale: f64,
    },
    /// No command keeps out of every mover's reach within the period and of the known shapes:
    /// the command keeps the known shapes and the reciprocal robots' rows and falls short of
    /// the non-cooperative rows by at most `shortfall` (m/s); it is not certified against
    /// `mover`, the one that falls shortest. [`Command::certified`] is false.
    Overwhelmed {
        /// The mover it falls shortest of.
        mover: usize,
        /// The largest shortfall, m/s.
        shortfall: f64,
    },
    /// Under a force bound ([`crate::Options::force_bound`]): the command was scaled to the
    /// bound `|f| ≤ F`, or moved towards the full brake until the way it brakes to rest is
    /// certified free (the braking certificate, docs/movers.md §2); `scale` of the speed
    /// after the period that was asked for. The law is then not followed exactly, and its
    /// energy `V` may rise.
    Bounded {
        /// The speed kept.
        scale: f64,
    },
    /// Under a force bound ([`crate::Options::force_bound`]): the full brake, `|f| = F` (to
    /// rounding) against the velocity (or to rest within the period), and the way it brakes
    /// to rest is not certified free of the known shapes: the robot was handed a state it
    /// cannot stop from in the free space it knows (a start at speed, an obstacle found within
    /// its braking distance, a way out of the margin band it cannot follow, a halt after a
    /// refused scan). [`Command::certified`] is false (docs/movers.md §2).
    Braking,
}

impl Mode {
    /// Whether a command formed this way is certified ([`Command::certified`]): all but
    /// [`Mode::Overwhelmed`] and [`Mode::Braking`].
    #[must_use]
    pub fn certified(&self) -> bool {
        !matches!(self, Mode::Overwhelmed { .. } | Mode::Braking)
    }

    /// The name used in logs, JSON and Python (`"law"`, `"capped"`, `"recovering"`,
    /// `"escaping"`, `"from-rest"`, `"halted"`, `"yielding"`, `"overwhelmed"`, `"bounded"`,
    /// `"braking"`).
    #[must_use]
    pub fn as_str(&self) -> &'static str {
        match self {
            Self::Law => "law",
            Self::Capped { .. } => "capped",
            Self::Recovering(_) => "recovering",
            Self::Escaping => "escaping",
            Self::FromRest => "from-rest",
            Self::Halted => "halted",
            Self::Yielding { .. } => "yielding",
            Self::Overwhelmed { .. } => "overwhelmed",
            Self::Bounded { .. } => "bounded",
            Self::Braking => "braking",
        }
    }
}

/// The command to hold for one control period, and how it was formed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Command {
    /// The velocity `u` (kinematic law) or the force `f` (dynamic law).
    pub value: Vector2<f64>,
    /// Whether it is the law's, shortened, or a recovery.
    pub mode: Mode,
}

impl Command {
    /// Whether the command is certified to keep the robot clear over the period: false only
    /// for [`Mode::Overwhelmed`] (a mover's reach could not be kept out of) and
    /// [`Mode::Braking`] (a force-bounded robot's way to rest is not certified free), and
    /// [`crate::HoldPolicy::Paper`]'s unchecked law is not told apart (its mode is
    /// [`Mode::Law`]).
    #[must_use]
    pub fn certified(&self) -> bool {
        self.mode.certified()
    }
}

/// `β` of the kinematic hold: the step `h|u|` is at most `β·d(x)`, so that
/// `d(x⁺) ≥ (1 − β)·d(x) > 0` (`docs/maths.md` §10).
pub const KINEMATIC_FRACTION: f64 = 0.5;

/// `c = β(1 − β)` (`β = 1/2`) of the dynamic hold: `h|v⁺| ≤ c·d(x)`. It keeps the invariant
/// `h|v| ≤ β·d(x)` under both semi-implicit Euler and the exact hold of the force
/// (`docs/maths.md` §10).
pub const DYNAMIC_FRACTION: f64 = 0.25;

/// The most halvings of the kinematic step in search of a decrease of `Θ`; `2⁻⁴⁰` of a step is
/// below a picometre at any speed the ranges allow, where only a critical point is left.
pub const MAX_HALVINGS: u32 = 40;

/// `v⁺` is kept below `(1 − SPEED_SLACK)·√(2μ/m)`, strictly under the bound of corollary
/// `boundedvel`.
pub const SPEED_SLACK: f64 = 1e-6;

/// The most balls of the sphere tracing that certifies a step free (`docs/maths.md` §10).
pub const MAX_TRACE_BALLS: usize = 64;

/// A certified free length along the ray `x + t·dir` (`dir` a unit vector), clipped at `want`:
/// sphere tracing on the certified clearance. With `t_0 = 0`, `t_{j+1} = t_j + d(x + t_j dir)`,
/// every open ball `B(x + t_j dir, d(x + t_j dir))` lies in the free space, and they cover the
/// segment up to `t_{j+1}`. Returns `want` once a ball reaches past it (the whole segment is
/// free), else the covered length after [`MAX_TRACE_BALLS`] balls or at a ball too small to
/// advance. A ray that runs along a wall keeps its balls as large as its distance to the wall,
/// where the one ball of `d(x)` would cap the step at that distance.
pub(crate) fn free_length(
    space: &impl Space,
    x: Vector2<f64>,
    dir: Vector2<f64>,
    want: f64,
) -> f64 {
    let mut t = 0.0;
    for _ in 0..MAX_TRACE_BALLS {
        // Asked for twice the rest, so that the clip at `need` cannot bind by rounding.
        let d = space.clearance(x + t * dir, 2.0 * (want - t), None);
        if t + d > want {
            return want;
        }
        // A NaN clearance stops the trace as a zero one does.
        if d.is_nan() || d <= BLIND * (1.0 + t) {
            break;
        }
        t += d;
    }
    t
}

/// A certified free length along a curve `c(t)` parametrised so that `|c(t) − c(t')| ≤ |t − t'|`
/// (by arc length, or any 1-Lipschitz parameter), clipped at `want`: [`free_length`]'s sphere
/// tracing with `c(t)` in place of `x + t·dir`. With `t_{j+1} = t_j + d(c(t_j))` the open ball
/// `B(c(t_j), d(c(t_j)))` lies in the free space and contains `c(t)` for `t_j ≤ t < t_{j+1}`, so
/// the balls cover the curve up to the length returned. The differential-drive hold traces the
/// arc that a held `(v, ω)` sweeps with it (`diff.rs`, docs/unicycle.md).
pub(crate) fn free_length_along(
    space: &impl Space,
    curve: impl Fn(f64) -> Vector2<f64>,
    want: f64,
) -> f64 {
    let mut t = 0.0;
    for _ in 0..MAX_TRACE_BALLS {
        let d = space.clearance(curve(t), 2.0 * (want - t), None);
        if t + d > want {
            return want;
        }
        if d.is_nan() || d <= BLIND * (1.0 + t) {
            break;
        }
        t += d;
    }
    t
}

/// The length of a kinematic step of at most `want` along the unit `dir`: all of it if
/// [`free_length`] certifies it free, otherwise `β·L` (`β =` [`KINEMATIC_FRACTION`], `L` the
/// certified free length), so that the step ends inside the free space.
pub(crate) fn held_length(
    space: &impl Space,
    x: Vector2<f64>,
    dir: Vector2<f64>,
    want: f64,
) -> f64 {
    let free = free_length(space, x, dir, want);
    if free >= want {
        want
    } else {
        KINEMATIC_FRACTION * free
    }
}

/// The sub-steps of the kinematic hold's chord through a stiff valley (`docs/maths.md` §10).
pub const CHORD_SUBSTEPS: usize = 8;

/// The kinematic hold tries the chord once `Θ`'s decrease has halved the step this many times.
/// Measured on the 300 worlds at 100 Hz: after one halving, median time 7.13 s; after two,
/// 7.20 s, for the same cost (both arrive everywhere; without the chord 7.24 s, and at 20 Hz
/// four of 1 200 flights crawled).
pub const CHORD_AFTER_HALVINGS: u32 = 1;

/// The kinematic hold at `x` (with its evaluation `e` and the law's velocity `u`).
///
/// First the single step ([`kinematic_step`]). Where `Θ`'s decrease shortened it
/// ([`CHORD_AFTER_HALVINGS`]; in a stiff valley, where the straight step overshoots the
/// floor), the flow line is followed over `h` instead by [`CHORD_SUBSTEPS`] single steps of
/// `h/`[`CHORD_SUBSTEPS`] (each certified, each decreasing `phi_k`), ending at `y`; the chord `[x, y]` is taken if it is certified free
/// ([`free_length`]) and longer than the single step, with the command `(y − x)/h`. Its end
/// is `y`, so `Θ` decreases over it as over the sub-steps.
pub(crate) fn kinematic(
    law: &Kinematic,
    field: &impl Space,
    x: Vector2<f64>,
    e: &FieldEval,
    u: Vector2<f64>,
    h: f64,
) -> Command {
    let (single, halvings) = kinematic_step(field, x, e, u, h);
    if halvings < CHORD_AFTER_HALVINGS {
        return single;
    }
    let tau = h / CHORD_SUBSTEPS as f64;
    let mut y = x;
    for _ in 0..CHORD_SUBSTEPS {
        let Ok(ey) = field.eval(y) else {
            return single;
        };
        let to_goal = (y - field.goal()).norm();
        let (c, _) = kinematic_step(
            field,
            y,
            &ey,
            law.velocity_toward(&ey, to_goal, field.heading(y, &ey)),
            tau,
        );
        y += tau * c.value;
    }
    let chord = y - x;
    let length = chord.norm();
    let better = length > h * single.value.norm();
    let decreases = field.eval(y).is_ok_and(|ey| ey.phi < e.phi);
    if better && decreases && free_length(field, x, chord / length, length) >= length {
        Command {
            value: chord / h,
            mode: Mode::Capped {
                scale: length / (h * u.norm()),
            },
        }
    } else {
        single
    }
}

/// The number of directions a step from rest ([`Mode::FromRest`]) tries, evenly spaced.
pub const REST_DIRECTIONS: usize = 16;

/// Below this fraction of the law's speed the held kinematic command counts as at rest, and a
/// step from rest ([`Mode::FromRest`]) is tried.
pub const REST_SCALE: f64 = 1e-3;

/// The kinematic hold's way on from rest away from the goal (the held command below
/// [`REST_SCALE`] of the law's speed `speed`): a saddle of `Θ`, where the continuous law rests
/// on the saddle's stable manifold (`docs/maths.md` §10.1), or the floor of a valley where no
/// step along the law's direction decreases `phi_k`. Of [`REST_DIRECTIONS`] directions
/// `d_j`, each tried as the law's velocity `speed·d_j` through [`kinematic_step`] (certified
/// free, `phi_k` decreasing, never past the goal), the step that lowers `phi_k` most, if it is
/// longer than the held one. Near a saddle `phi_k(x + s d) = phi_k(x) + s∇phi_k·d + ½s²dᵀHd +
/// O(s³)`, and `H` has a negative eigenvalue, so the directions near its eigenvector decrease
/// `phi_k` at the law's step `s` even where `∇phi_k = 0`. `None` where none does (a minimum at
/// that scale: only the goal, for a navigation function) or at the goal itself.
///
/// Every step is one of [`kinematic_step`]'s, so the hold's guarantees stand: each step is
/// certified free and decreases `phi_k`; `Θ` never returns to the saddle's level. Cost: up to
/// [`REST_DIRECTIONS`] single steps, some tens of µs, paid only at rest (also where no
/// direction lowers `phi_k`, every period).
pub(crate) fn kinematic_from_rest(
    field: &impl Space,
    x: Vector2<f64>,
    e: &FieldEval,
    speed: f64,
    held: &Command,
    h: f64,
) -> Option<Command> {
    if speed <= 0.0 || !speed.is_finite() {
        return None;
    }
    let mut best: Option<(f64, Command)> = None;
    for j in 0..REST_DIRECTIONS {
        let angle = std::f64::consts::TAU * j as f64 / REST_DIRECTIONS as f64;
        let u = speed * Vector2::new(angle.cos(), angle.sin());
        let (c, _) = kinematic_step(field, x, e, u, h);
        if c.value.norm() <= held.value.norm() {
            continue;
        }
        let Ok(end) = field.eval(x + h * c.value) else {
            continue;
        };
        if end.phi < e.phi && best.as_ref().is_none_or(|(phi, _)| end.phi < *phi) {
            best = Some((end.phi, c));
        }
    }
    best.map(|(_, c)| Command {
        value: c.value,
        mode: Mode::FromRest,
    })
}

/// The kinematic command out of the blind layer ([`escape`]), at most the law's step `step`,
/// halved until `phi_k` decreases over it (`None` if it never does: the law's step stands).
/// Held for `h`, it moves along the shape's ray, certified free.
fn kinematic_escape(
    field: &impl Space,
    x: Vector2<f64>,
    e: &FieldEval,
    step: f64,
    h: f64,
) -> Option<Command> {
    let (band, dir, mut length) = field.blind_exit(x, step)?;
    for _ in 0..=MAX_HALVINGS {
        if field.eval(x + length * dir).is_ok_and(|e1| e1.phi < e.phi) {
            return Some(Command {
                value: (length / h) * dir,
                mode: Mode::Recovering(band),
            });
        }
        length *= 0.5;
    }
    None
}

/// `u` slid along `∂W_δ` ([`Space::slide`]) if it is still a descent direction, `u'·d > 0`
/// (`d = −∇Θ/|∇Θ|`); otherwise `−∇Θ` at the same speed, slid. The slide keeps a descent
/// direction only for `u ∥ −∇Θ`: a nominal heading (`HeadingPolicy::Auto`) that runs into the
/// layer can slide into an ascent, where the halving would stop the robot.
fn slid_descent(
    field: &impl Space,
    x: Vector2<f64>,
    e: &FieldEval,
    u: Vector2<f64>,
    h: f64,
) -> Vector2<f64> {
    let speed = u.norm();
    let slid = field.slide(x, u, h * speed);
    match e.direction {
        Some(d) if slid.dot(&d) <= 0.0 => field.slide(x, speed * d, h * speed),
        _ => slid,
    }
}

/// One straight kinematic step at `x`: the largest `s ∈ {1, ½, ¼, …}·s_0` with
/// `phi_k(Phi(x + s h u)) < phi_k(Phi(x))`, the command `s·u`, and the number of halvings.
/// `s_0 = 1` if the whole step is certified free ([`free_length`] `≥ h|u|`), otherwise
/// `β·L/(h|u|)` with `L` the certified free length and `β =` [`KINEMATIC_FRACTION`], so the
/// step ends inside the free space; and `s_0 ≤ |x − x_d|/(h|u|)`: the step never passes the
/// goal (near the goal the speed of `SpeedPolicy::Auto`, `∝ √|x − x_d|` and then `λ_0|x − x_d|`
/// with `hλ_0 > 1`, would otherwise step across it and back: `docs/maths.md` §6).
/// `Θ = sigma(phi_k∘Phi)` with `sigma` increasing, so `Θ` decreases over the step; the
/// comparison is made on `phi_k`, in log space, where `Θ` near a wall would round to 1 at both
/// ends. After [`MAX_HALVINGS`] the robot is at a critical point
/// to working precision and the command is 0.
fn kinematic_step(
    field: &impl Space,
    x: Vector2<f64>,
    e: &FieldEval,
    u: Vector2<f64>,
    h: f64,
) -> (Command, u32) {
    let u = slid_descent(field, x, e, u, h);
    let step = h * u.norm();
    if step == 0.0 {
        return (
            Command {
                value: u,
                mode: Mode::Law,
            },
            0,
        );
    }
    let length = held_length(field, x, u / u.norm(), step);
    if length <= 0.0
        && let Some(out) = kinematic_escape(field, x, e, step, h)
    {
        return (out, 0);
    }
    let to_goal = (x - field.goal()).norm();
    let mut scale = (length / step).min(to_goal / step);
    let mut halvings = 0;
    while !field.eval(x + scale * h * u).is_ok_and(|e1| e1.phi < e.phi) {
        halvings += 1;
        if halvings > MAX_HALVINGS {
            scale = 0.0;
            break;
        }
        scale *= 0.5;
    }
    let command = Command {
        value: scale * u,
        mode: if scale == 1.0 {
            Mode::Law
        } else {
            Mode::Capped { scale }
        },
    };
    (command, halvings)
}

/// The dynamic hold at `(x, v)` for the law `law` with damping `d`: the velocity after the
/// step with the damping taken implicitly,
///
/// ```text
/// v⁺ = (I + hΛ/m)⁻¹ (v − hμ_p∇Ψ/m),   Λ = λI + λ_up·n nᵀ (n = ∇Ψ/|∇Ψ|, if (v − hμ_p∇Ψ/m)·n > 0)
///    = w/a − n (w·n)(1/a − 1/(a + b)),  w = v − hμ_p∇Ψ/m,  a = 1 + hλ/m,  b = hλ_up/m,
/// ```
///
/// turned towards the nominal heading (`Dynamic::turned`, an exact rotation: `|v⁺|` kept),
/// slid along `∂W_δ` and the sensed obstacles' bands on a floor plan (`Space::slide`), both
/// kept dissipative ([`dissipative`], eq. heldwork), shortened if needed to `|v⁺| ≤ min(DYNAMIC_FRACTION·d(x)/h, (1 − SPEED_SLACK)√(2μ/m))`,
/// and the force `f = m(v⁺ − v)/h` that produces it under `v += h f/m`. As `h → 0`,
/// `f → −μ_p∇Ψ − Λv + f_g`, the continuous law of [`Dynamic::force_toward`] (`μ_p` its
/// [`Dynamic::pull`], `f_g` the heading force, 0 in a star world). The implicit damping contracts
/// every velocity for every `h` (`|(I + hΛ/m)⁻¹| ≤ 1`), where the explicit one is stable only
/// for `h(λ + λ_up)/m < 2`.
pub(crate) fn dynamic(
    law: &Dynamic,
    space: &impl Space,
    x: Vector2<f64>,
    (e, v): (&FieldEval, Vector2<f64>),
    d: &Damping,
    h: f64,
) -> Command {
    let m = law.mass();
    let g = law.potential_for(space.calibration(law), e).gradient;
    let w = v - (h * law.pull() / m) * g;
    let a = 1.0 + h * d.lambda / m;
    let mut next = w / a;
    let n = g / g.norm();
    let climb = w.dot(&n);
    if d.uphill > 0.0 && climb > 0.0 && n.iter().all(|c| c.is_finite()) {
        let b = h * d.uphill / m;
        next -= n * (climb * (1.0 / a - 1.0 / (a + b)));
    }
    // The gyroscopic heading force over the period: an exact rotation, `|v⁺|` kept.
    let damped = next;
    next = law.turned(e, next, space.heading(x, e), h);
    next = space.slide(x, next, 2.0 * h * next.norm());
    if next != damped {
        next = dissipative(next, w);
    }
    let speed = next.norm();
    let bound = (1.0 - SPEED_SLACK) * law.speed_bound();
    let d = space.clearance(x, 2.0 * h * speed / DYNAMIC_FRACTION, None);
    if d <= BLIND
        && let Some((band, dir, length)) = space.blind_exit(x, 0.5 * h * bound)
    {
        // In the blind layer (`escape`): v⁺ along the shape's ray, `h|v⁺|` the way out.
        let out = (length / h) * dir;
        return Command {
            value: (m / h) * (out - v),
            mode: Mode::Recovering(band),
        };
    }
    let room = DYNAMIC_FRACTION * d.max(0.0) / h;
    let cap = bound.min(room);
    let mut mode = Mode::Law;
    if speed > cap {
        let scale = cap / speed;
        next *= scale;
        mode = Mode::Capped { scale };
    }
    Command {
        value: (m / h) * (next - v),
        mode,
    }
}

/// `v⁺` shortened, if need be, so that the held step dissipates (eq. heldwork):
///
/// ```text
/// v⁺·(f + μ_p∇Ψ(x)) = (m/h)·v⁺·(v⁺ − w) ≤ 0,   f = m(v⁺ − v)/h,   w = v − hμ_p∇Ψ/m,
/// ```
///
/// the held step's own term of `V' − V` (`harmonav_sim`'s `euler_energy_error` has the
/// integrator's other two). The implicitly damped `v⁺ = w/a` (`a ≥ 1`) meets it; the heading's
/// exact rotation by `θ` does only while `a·cos θ ≥ 1`, and the slide along `∂W_δ` not always:
/// the continuous force `f_g ⟂ ẋ` does no work, its held rotation does `O(h²)` (measured: `V`
/// rose by 1.6e-9 of itself over one period of `map-office-solve.toml`). Where it fails, `v⁺`
/// becomes `w`'s projection on it, `(v⁺·w/|v⁺|²)·v⁺` (0 if that is negative), the longest
/// velocity along `v⁺` that meets it. The hold's caps after it only shorten `v⁺` further,
/// which keeps it (`c²|v⁺|² − c·v⁺·w ≤ c·(|v⁺|² − v⁺·w)` for `c ≤ 1`).
fn dissipative(next: Vector2<f64>, w: Vector2<f64>) -> Vector2<f64> {
    let (along, square) = (next.dot(&w), next.norm_squared());
    if along >= square {
        next
    } else {
        next * (along.max(0.0) / square)
    }
}

/// The way out of the margin band: the robot at `x` is inside grown shape `band` of `ws` but
/// outside `inner` (the same true shape grown by the robot radius alone). Every shape is
/// star-shaped about its centre `c`, so the ray from `c` through `x` (for an obstacle; towards
/// `c` for the boundary) leaves the grown shape at one point `p` and never re-enters it, and
/// the part of it inside the band meets no other grown shape (they are disjoint from this one).
/// Returns the unit direction and the length to go: to `p`, and beyond by half of the
/// clearance of `p` from the other shapes (at most half the margin), so that the robot comes
/// out into the free space and not onto its edge.
pub(crate) fn way_out(
    ws: &Workspace,
    band: Band,
    x: Vector2<f64>,
    margin: f64,
) -> Option<(Vector2<f64>, f64)> {
    let (shape, outward) = match band {
        Band::Obstacle(i) => (ws.obstacles().get(i)?, true),
        Band::Boundary => (ws.boundary(), false),
    };
    let (u, rho) = ray(shape, x)?;
    let r = shape.radius_along(u).0;
    let (dir, to_edge) = if outward { (u, r - rho) } else { (-u, rho - r) };
    let edge = x + to_edge.max(0.0) * dir;
    let room = clearance(ws, edge, margin, Some(band)).max(0.0);
    Some((dir, to_edge.max(0.0) + 0.5 * room))
}
