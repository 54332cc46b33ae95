//! Movers: people and other robots, as discs reported every period with a position error and a
//! speed bound, and the certified filter that keeps the held command clear of every place they
//! can reach within the period (issue 54; `docs/movers.md`).
//!
//! ```text
//! R_j = ρ + r_j,  d_j = |x − p̂_j| − R_j − ε_j,  n_j = (x − p̂_j)/|x − p̂_j|        (ρ = radius + margin)
//! g_j(τ) ≥ d_j + τ(n_j·u − V_j)                 for the held x(τ) = x + τu    (eq. reach)
//! non-cooperative:  n_j·u ≥ V_j − β·d_j/h       ⇒  g_j(τ) ≥ (1 − βτ/h)·d_j on [0, h]
//! reciprocal (share α, its peer 1 − α):  n_j·u − η_j|u| ≥ −α·β·max(d_j, 0)/h,  η_j = 2 sin(½ arcsin(ε_j/|x − p̂_j|))
//! ```
//!
//! `g_j` is the true gap between the robot's disc grown by its margin and mover `j`'s disc
//! (`|x(τ) − p_j(τ)| − R_j`, at least `|x(τ) − p̂_j| − ε_j − V_jτ − R_j` because the mover is within
//! `ε_j + V_jτ` of its report), and the tangent-plane bound `|y − p| ≥ n·(y − p)` of a convex set
//! makes each row a half-plane on the held velocity. A reciprocal row is robust to the report's
//! error (eq. robust): the true direction `n` between the two robots is within `η_j` of `n_j`,
//! so the row holds for `n`; it is taken as the four half-planes of eq. robust (one, today's
//! row, when `ε_j = 0`). `β` is the hold's
//! [`KINEMATIC_FRACTION`](crate::tuning::KINEMATIC_FRACTION): over a period a mover's clearance keeps at least half its value.
//! The command the hold produced is kept when it meets every row (then it is bit for bit the
//! command without movers); otherwise it is projected onto the rows and the static certificate
//! ([`program`]), or, when no velocity meets them all, the least largest shortfall is taken and
//! the command is not certified ([`crate::Mode::Overwhelmed`]).

pub(crate) mod program;

use nalgebra::Vector2;

use crate::error::NavError;
use crate::hold::KINEMATIC_FRACTION;
pub use crate::ranges::MAX_MOVER;
use program::{Row, minimax, project};

/// How a mover takes part in avoidance.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum MoverKind {
    /// A person, or a robot of another stack: it does nothing for us, and the row keeps the
    /// robot out of everything it can reach within the period.
    NonCooperative,
    /// Another harmonav robot running the same filter with the same control period, sampled at
    /// the same instants, each reporting the other within its `position_error` (exactly, when
    /// 0): each takes `share` of the pair's avoidance (the two shares add to 1; ½ by default).
    Reciprocal {
        /// This robot's share, in `[0, 1]`.
        share: f64,
    },
}

/// A moving disc as the robot's perception reports it at the time of
/// [`crate::Navigator::set_movers`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mover {
    /// The reported centre `p̂_j`, m.
    pub centre: Vector2<f64>,
    /// The body's radius `r_j` (not grown), m.
    pub radius: f64,
    /// `V_j`: the mover's speed never exceeds it, m/s.
    pub speed_bound: f64,
    /// `ε_j`: the report is within this of the true centre, m (a tracker's error plus its
    /// latency times `V_j`).
    pub position_error: f64,
    /// A tracked velocity, for logging and comfort: never used by the certificate.
    pub velocity: Option<Vector2<f64>>,
    /// How it takes part.
    pub kind: MoverKind,
}

impl Mover {
    /// A non-cooperative mover at `centre` of radius `radius`, whose speed never exceeds
    /// `speed_bound`, reported exactly.
    #[must_use]
    pub fn new(centre: Vector2<f64>, radius: f64, speed_bound: f64) -> Self {
        Self {
            centre,
            radius,
            speed_bound,
            position_error: 0.0,
            velocity: None,
            kind: MoverKind::NonCooperative,
        }
    }

    /// The same with the report's error bound `ε`, m.
    #[must_use]
    pub fn with_error(self, position_error: f64) -> Self {
        Self {
            position_error,
            ..self
        }
    }

    /// The same as another harmonav robot taking `share` of the avoidance.
    #[must_use]
    pub fn reciprocal(self, share: f64) -> Self {
        Self {
            kind: MoverKind::Reciprocal { share },
            ..self
        }
    }

    /// The mover checked: finite centre, radius and error in `[0, 1e6]` m, speed bound in
    /// `[0, 1e6]` m/s, share in `[0, 1]`; else [`NavError::InvalidMover`] naming `index` and
    /// the field.
    pub fn validate(&self, index: usize) -> Result<(), NavError> {
        let bad = |field| Err(NavError::InvalidMover { index, field });
        let length = |v: f64| v.is_finite() && (0.0..=MAX_MOVER).contains(&v);
        if !self.centre.iter().all(|c| c.is_finite()) {
            return bad("centre");
        }
        if !length(self.radius) {
            return bad("radius");
        }
        if !length(self.speed_bound) {
            return bad("speed_bound");
        }
        if !length(self.position_error) {
            return bad("error");
        }
        if self
            .velocity
            .is_some_and(|v| !v.iter().all(|c| c.is_finite()))
        {
            return bad("velocity");
        }
        if let MoverKind::Reciprocal { share } = self.kind
            && !(share.is_finite() && (0.0..=1.0).contains(&share))
        {
            return bad("share");
        }
        Ok(())
    }
}

/// What the filter did to a command.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Verdict {
    /// The command met every row: unchanged.
    Kept,
    /// Changed and certified: `mover` binds, `scale = |u|/|u_nominal|`.
    Yielding { mover: usize, scale: f64 },
    /// No certified command: the least largest shortfall `shortfall` (m/s), `mover` the one
    /// that falls shortest.
    Overwhelmed { mover: usize, shortfall: f64 },
}

/// The rows of `movers` at `x` for a robot of radius `radius` and margin `margin`, control
/// period `h`, into `rows` (cleared; it keeps its capacity). `extra` is added to every `ε_j`
/// (the exact hold's deviation from the straight step, dynamic law). Errors: a reported body
/// that overlaps the robot's (`|x − p̂_j| ≤ radius + r_j`): [`NavError::InMover`].
pub(crate) fn rows(
    movers: &[Mover],
    (x, radius, margin): (Vector2<f64>, f64, f64),
    h: f64,
    extra: f64,
    rows: &mut Vec<Row>,
) -> Result<(), NavError> {
    rows.clear();
    let beta = KINEMATIC_FRACTION;
    for (j, m) in movers.iter().enumerate() {
        let diff = x - m.centre;
        let dist = diff.norm();
        // Guard: the bodies as reported overlap (or the centres coincide, where `n` is
        // undefined): no command is certified, as inside a known obstacle.
        if dist <= radius + m.radius {
            return Err(NavError::InMover { mover: j });
        }
        let n = diff / dist;
        let d = dist - (radius + margin + m.radius) - (m.position_error + extra);
        let row = |n, a, hard| Row {
            n,
            a,
            hard,
            mover: j,
            inside: d <= 0.0,
        };
        match m.kind {
            MoverKind::NonCooperative => rows.push(row(n, m.speed_bound - beta * d / h, false)),
            MoverKind::Reciprocal { share } => {
                // Under the dynamic law (`extra > 0`) the peer, running the same law ((A4)),
                // strays from its own straight step too, by at most `(h/2)(|v_j| + √(2μ/m)) ≤
                // h·V_j` (its speed bound at least its law's): the pair's gap loses both
                // deviations, so each robot's row takes the peer's off as well (docs/movers.md
                // §2, "The dynamic law").
                let d = if extra > 0.0 {
                    d - h * m.speed_bound
                } else {
                    d
                };
                // `max(d, 0)`: a clearance decayed to 0 must keep `u = 0` feasible.
                let c = -share * beta * d.max(0.0) / h;
                let eta = robust_tilt(m.position_error, dist);
                if eta == 0.0 {
                    rows.push(row(n, c, true));
                } else {
                    for (n, a) in robust_rows(n, c, eta) {
                        rows.push(row(n, a, true));
                    }
                }
            }
        }
    }
    Ok(())
}

/// `η = 2 sin(½ arcsin(ε/|x − p̂|))` (2 when `ε ≥ |x − p̂|`): the true unit direction
/// `n = (x − p)/|x − p|` from a peer reported at `p̂`, `|p − p̂| ≤ ε`, is within `η` of the
/// reported one `n̂ = (x − p̂)/|x − p̂|` (eq. robust): seen from `x`, outside the disc
/// `B(p̂, ε)`, every point of the disc lies within the angle `θ = arcsin(ε/|x − p̂|)` of its
/// centre (the tangents), and two unit vectors at angle `φ ≤ θ` are `2 sin(φ/2)` apart. About
/// `ε/|x − p̂|` for a small error. `0` exactly when `ε = 0`.
pub(crate) fn robust_tilt(error: f64, dist: f64) -> f64 {
    if error == 0.0 {
        0.0
    } else if error < dist {
        2.0 * (0.5 * (error / dist).asin()).sin()
    } else {
        2.0
    }
}

/// The four half-planes `(n_k, a_k)`, `n_k·u ≥ a_k`, whose intersection lies inside
/// `{u : n̂·u − η|u| ≥ c}` (eq. robust): with `s = n̂·u`, `w = t̂·u` (`t̂ ⊥ n̂`), `|u| ≤ |s| + |w|`,
/// so `s − η|s| − η|w| ≥ c` suffices, and that is the least of the four
///
/// ```text
/// (1 − σ₁η)·s − σ₂η·w ≥ c,   σ₁, σ₂ ∈ {−1, 1}                                    (eq. robust)
/// ```
///
/// each normalised (`|(1 − σ₁η, σ₂η)| ≥ η > 0`). For `c ≤ 0` every one admits `u = 0`. Then
/// for the true direction `n`, `n·u ≥ n̂·u − |n − n̂||u| ≥ c`: the reciprocal row holds as if
/// the positions were exact.
pub(crate) fn robust_rows(
    n: Vector2<f64>,
    c: f64,
    eta: f64,
) -> impl Iterator<Item = (Vector2<f64>, f64)> {
    let t = Vector2::new(-n.y, n.x);
    [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)]
        .into_iter()
        .map(move |(s1, s2): (f64, f64)| {
            let v = n * (1.0 - s1 * eta) - t * (s2 * eta);
            let norm = v.norm();
            (v / norm, c / norm)
        })
}

/// The velocity `u` filtered against `rows` with the static set `|u| ≤ r` (and, if the first
/// projection is not certified by `certified`, the smaller disc `|u| ≤ r_small`): `u` itself
/// when it is `trusted` (the hold's own command, certified against the known shapes) and meets
/// every row ([`Verdict::Kept`]), the projection when one is certified, else the least largest
/// shortfall. A nominal that is not trusted (turned by [`KeepRight`]) is always checked.
pub(crate) fn filter(
    rows: &[Row],
    (u, trusted): (Vector2<f64>, bool),
    r: f64,
    certified: impl Fn(Vector2<f64>) -> bool,
    r_small: f64,
) -> (Vector2<f64>, Verdict) {
    // Within a mover's margin already (`d_j ≤ 0`): the rows lead out, but Theorem 1 starts
    // from `d_j > 0`, so nothing is certified until the robot is out.
    if let Some(row) = rows.iter().find(|row| row.inside) {
        let (v, _) = match project(rows, r_small, u, 0.0) {
            Ok(v) => (v, ()),
            Err(_) => (
                minimax(rows, r_small, u).map_or(Vector2::zeros(), |(v, _)| v),
                (),
            ),
        };
        let shortfall = rows
            .iter()
            .map(|row| row.a - row.n.dot(&v))
            .fold(0.0_f64, f64::max);
        return (
            v,
            Verdict::Overwhelmed {
                mover: row.mover,
                shortfall,
            },
        );
    }
    if trusted && rows.iter().all(|row| row.slack(u) >= 0.0) {
        return (u, Verdict::Kept);
    }
    let yielding = |v: Vector2<f64>| {
        let binding = rows
            .iter()
            .min_by(|a, b| a.slack(v).total_cmp(&b.slack(v)))
            .map_or(0, |row| row.mover);
        let norm = u.norm();
        let scale = if norm > 0.0 { v.norm() / norm } else { 0.0 };
        (
            v,
            Verdict::Yielding {
                mover: binding,
                scale,
            },
        )
    };
    if let Ok(v) = project(rows, r, u, 0.0)
        && certified(v)
    {
        return yielding(v);
    }
    if let Ok(v) = project(rows, r_small, u, 0.0) {
        return yielding(v);
    }
    match minimax(rows, r_small, u) {
        Some((v, shortfall)) => {
            let worst = rows
                .iter()
                .filter(|row| !row.hard)
                .min_by(|a, b| a.slack(v).total_cmp(&b.slack(v)))
                .map_or(0, |row| row.mover);
            (
                v,
                Verdict::Overwhelmed {
                    mover: worst,
                    shortfall,
                },
            )
        }
        // Not expected (the hard rows and the disc admit 0): rest, uncertified.
        None => (
            Vector2::zeros(),
            Verdict::Overwhelmed {
                mover: 0,
                shortfall: f64::INFINITY,
            },
        ),
    }
}

/// The comfort stage (docs/movers.md §7, "Comfort"): the nominal `u` projected onto the
/// non-cooperative rows of a margin grown by `comfort` (eq. comfort),
///
/// ```text
/// n_j·u ≥ V_j − β·(d_j − c)/h     (d_j the clearance of [`rows`], c = comfort)   (eq. comfort)
/// ```
///
/// within `|u| ≤ r`, or, when none meets them all, their least largest shortfall: `u` as
/// given (bit for bit, `trusted` kept) when `comfort` is 0, no mover is non-cooperative or
/// `u` already meets every such row; else the turned nominal, not trusted, which the mover
/// filter then certifies as it certifies KeepRight's turn. Only the nominal changes: a robot
/// keeps its distance from people who do not avoid it where it can, and every certificate is
/// the filter's as before. `rows_buf` is scratch (cleared, its capacity kept); the body and
/// `(h, extra)` as in [`rows`], whose errors it returns.
pub(crate) fn comfort(
    movers: &[Mover],
    (x, radius, margin): (Vector2<f64>, f64, f64),
    (h, extra, comfort): (f64, f64, f64),
    rows_buf: &mut Vec<Row>,
    (u, trusted): (Vector2<f64>, bool),
    r: f64,
) -> Result<(Vector2<f64>, bool), NavError> {
    let noncooperative = |m: &Mover| m.kind == MoverKind::NonCooperative;
    if comfort == 0.0 || !movers.iter().any(noncooperative) {
        return Ok((u, trusted));
    }
    rows(movers, (x, radius, margin + comfort), h, extra, rows_buf)?;
    // The reciprocal rows are hard and the peers take their share: comfort is for the others.
    rows_buf.retain(|row| !row.hard);
    if rows_buf.iter().all(|row| row.slack(u) >= 0.0) {
        return Ok((u, trusted));
    }
    let (v, _) = filter(rows_buf, (u, false), r, |_| true, r);
    Ok((v, false))
}

/// How long ahead KeepRight's anticipation looks, s: a mover whose closest approach to the
/// nominal relative motion comes within this time and closer than `2R_j` turns the nominal
/// clockwise (docs/movers.md §7).
pub const ANTICIPATION: f64 = 3.0;

/// The largest clockwise turn of the anticipation, degrees (at a closest approach now; none at
/// [`ANTICIPATION`]).
pub const ANTICIPATION_TURN_DEG: f64 = 50.0;

/// The filtered command is "slow" below this fraction of the nominal's speed.
pub const STUCK_RATIO: f64 = 0.2;

/// Slow for this long (s), away from the goal, and for [`STUCK_TURN_TIME`] the nominal heads
/// for the freest direction ([`escape`]).
pub const STUCK_TIME: f64 = 1.0;

/// How long the stuck rule's escape lasts, s.
pub const STUCK_TURN_TIME: f64 = 2.0;

/// The escape's candidates: the nominal turned by every multiple of this angle, degrees.
pub const ESCAPE_STEP_DEG: f64 = 15.0;

/// How far ahead the escape measures a free run, in grown radii `ρ = radius + margin`: a
/// direction is wholly free once the grown disc can move its own diameter along it.
pub const ESCAPE_REACH: f64 = 2.0;

/// The free run `ℓ(d)` of the robot's disc grown to `inflation` at `x` along the unit
/// direction `d`, at most `cap`: the least root `t ≥ 0` of `|e_j + t·d| = R_j`
/// (`e_j = x − p̂_j`, `R_j = inflation + r_j`) over the movers approached (`e_j·d < 0`),
///
/// ```text
/// t_j = −e_j·d − √((e_j·d)² − |e_j|² + R_j²)                                     (eq. free run)
/// ```
///
/// clamped at 0 (a mover already within `R_j` that `d` closes on stops the run at once).
pub(crate) fn free_run(
    movers: &[Mover],
    x: Vector2<f64>,
    d: Vector2<f64>,
    inflation: f64,
    cap: f64,
) -> f64 {
    let mut run = cap;
    for m in movers {
        let e = x - m.centre;
        let b = e.dot(&d);
        let reach = inflation + m.radius;
        let disc = b * b - e.norm_squared() + reach * reach;
        // Guard: moving away (or along), or a miss: this mover never stops the run.
        if !(b < 0.0 && disc > 0.0) {
            continue;
        }
        run = run.min((-b - disc.sqrt()).max(0.0));
    }
    run
}

/// The stuck rule's escape (docs/movers.md §7), a clockwise turn of the nominal `u` in
/// `(−π, π]` rad (negative: anticlockwise): over `θ_k = k·`[`ESCAPE_STEP_DEG`], the largest
///
/// ```text
/// score(θ) = min(ℓ(θ), L)·(2 + cos θ)/3,   L = ESCAPE_REACH·inflation           (eq. escape)
/// ```
///
/// with `ℓ(θ)` the [`free_run`] along `u` turned by `θ` (`inflation = radius + margin`, the
/// robot's grown radius): the freest direction, forward preferred to sideways to back.
/// Candidates in the order `0, +1, −1, +2, …` and only a strictly larger score replaces the
/// best, so ties go to the smaller turn, then to the right (keep right). 0 when `u = 0` or no
/// direction is free (the nominal as it is: the robot waits).
pub(crate) fn escape(movers: &[Mover], x: Vector2<f64>, u: Vector2<f64>, inflation: f64) -> f64 {
    let speed = u.norm();
    // Guard: no nominal (or a NaN): nothing to turn.
    if speed.is_nan() || speed <= 0.0 {
        return 0.0;
    }
    let d = u / speed;
    let cap = ESCAPE_REACH * inflation;
    let step = ESCAPE_STEP_DEG.to_radians();
    // `ESCAPE_STEP_DEG` divides 180: k runs over −(n − 1) ..= n.
    let n = (std::f64::consts::PI / step).round() as i32;
    let (mut best, mut best_score) = (0.0, 0.0);
    for j in 0..2 * n {
        let k = if j % 2 == 1 { j / 2 + 1 } else { -(j / 2) };
        let theta = f64::from(k) * step;
        let run = free_run(movers, x, clockwise(d, theta), inflation, cap);
        let score = run * (2.0 + theta.cos()) / 3.0;
        if score > best_score * (1.0 + 1e-9) + 1e-12 {
            (best, best_score) = (theta, score);
        }
    }
    best
}

/// What a navigator remembers of its movers between commands, as
/// [`crate::Navigator::mover_memory`] gives it and [`crate::Navigator::set_mover_memory`] takes
/// it back: KeepRight's memory (docs/movers.md §7) and whether the filter changed the last
/// command. A copy rebuilt by replaying the calls that made a navigator (Python's pickle)
/// needs it to replay only some of the commands. It changes only the nominal command (the
/// deadlock rule's turn) and the dynamic law's discovery speed (after a command the filter
/// changed); every command stays certified by the filter.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MoverMemory {
    /// Seconds the filtered command has been below ⅕ of the nominal's speed (`STUCK_RATIO`),
    /// away from the goal: in `[0, 1)` s (at `STUCK_TIME` = 1 s the stuck rule's escape begins
    /// and this starts again from 0).
    pub slow: f64,
    /// Seconds the stuck rule's escape still runs: in `[0, 2]` s (`STUCK_TURN_TIME`).
    pub turning: f64,
    /// Whether the mover filter changed the last command: the next command then takes the
    /// speed `|ẋ|` as a discovery speed under the dynamic law ([`crate::Navigator::command`]).
    pub yielded: bool,
}

impl MoverMemory {
    /// The memory if every field is in its range, else [`NavError::InvalidOption`] naming it
    /// (`mover_memory.slow`, `mover_memory.turning`).
    pub(crate) fn validate(self) -> Result<Self, NavError> {
        if !(self.slow.is_finite() && (0.0..STUCK_TIME).contains(&self.slow)) {
            return Err(NavError::InvalidOption {
                field: "mover_memory.slow",
                value: self.slow,
            });
        }
        if !(self.turning.is_finite() && (0.0..=STUCK_TURN_TIME).contains(&self.turning)) {
            return Err(NavError::InvalidOption {
                field: "mover_memory.turning",
                value: self.turning,
            });
        }
        Ok(self)
    }
}

/// KeepRight's memory (docs/movers.md §7): how long the filtered command has been slow, and how
/// long the stuck rule's escape still runs. It changes only the nominal command, which the filter
/// certifies whatever it is: it can cost time, never safety.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct KeepRight {
    /// Seconds the filtered command has been below [`STUCK_RATIO`] of the nominal.
    pub slow: f64,
    /// Seconds the stuck rule's escape still runs.
    pub turning: f64,
}

impl KeepRight {
    /// The clockwise turn of the nominal `u` at `x`, rad, in `[0, 2π)` (an anticlockwise turn
    /// `θ` is `2π − θ`): while the stuck rule runs, its [`escape`] from the movers' geometry
    /// now (eq. escape, chosen afresh every period: this memory is read-only here; 0: the
    /// nominal as it is); else the anticipation's: for each mover with `e = x − p̂_j`,
    /// `w = u − v̂_j` (`v̂_j` its tracked velocity, 0 if none), `t* = −e·w/|w|²` and the miss
    /// `|e + t*w|`; if `0 < t* < T_a` and the miss is below `2R_j` (`R_j = inflation + r_j`),
    /// `θ_max(1 − t*/T_a)`; the largest.
    pub(crate) fn turn(
        &self,
        movers: &[Mover],
        x: Vector2<f64>,
        u: Vector2<f64>,
        inflation: f64,
    ) -> f64 {
        if self.turning > 0.0 {
            return escape(movers, x, u, inflation).rem_euclid(std::f64::consts::TAU);
        }
        let mut turn: f64 = 0.0;
        for m in movers {
            let e = x - m.centre;
            let w = u - m.velocity.unwrap_or_else(Vector2::zeros);
            let ww = w.norm_squared();
            // Guard: no relative motion (or a NaN): no closest approach to anticipate.
            if ww.is_nan() || ww <= 0.0 {
                continue;
            }
            let t = -e.dot(&w) / ww;
            let miss = (e + t * w).norm();
            if t > 0.0 && t < ANTICIPATION && miss < 2.0 * (inflation + m.radius) {
                turn = turn.max(ANTICIPATION_TURN_DEG.to_radians() * (1.0 - t / ANTICIPATION));
            }
        }
        turn
    }

    /// The memory after a command whose filtered speed was `kept` of the nominal `wanted`
    /// (`yielded`: the filter changed it), `far`: away from the goal, over the period `h`.
    pub(crate) fn after(
        self,
        (kept, wanted): (f64, f64),
        yielded: bool,
        far: bool,
        h: f64,
    ) -> Self {
        let turning = (self.turning - h).max(0.0);
        let slow = if yielded && far && kept < STUCK_RATIO * wanted {
            self.slow + h
        } else {
            0.0
        };
        if slow >= STUCK_TIME {
            Self {
                slow: 0.0,
                turning: STUCK_TURN_TIME,
            }
        } else {
            Self { slow, turning }
        }
    }
}

/// `u` turned clockwise by `angle` rad.
pub(crate) fn clockwise(u: Vector2<f64>, angle: f64) -> Vector2<f64> {
    let (s, c) = angle.sin_cos();
    Vector2::new(c * u.x + s * u.y, -s * u.x + c * u.y)
}

/// A standalone mover filter: certifies any planner's velocity (ORCA's, DWB's, your own)
/// against movers, for a disc robot of `radius` and `margin` that holds the velocity for the
/// control period `h` and moves at most `v_max`. The static world is the caller's: a certified
/// lower bound `clearance` on the distance from the robot's centre to every static obstacle
/// (grown by `radius + margin`), inside which every step of length `β·clearance` is free.
#[derive(Clone, Debug)]
pub struct MoverFilter {
    radius: f64,
    margin: f64,
    v_max: f64,
    period: f64,
    rows: Vec<Row>,
}

/// A filtered velocity and how it was formed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Filtered {
    /// The velocity to hold for the period.
    pub velocity: Vector2<f64>,
    /// [`crate::Mode::Law`] when the nominal velocity met every row (returned as given),
    /// [`crate::Mode::Yielding`] or [`crate::Mode::Overwhelmed`].
    pub mode: crate::Mode,
}

impl MoverFilter {
    /// The filter for a robot of `radius` and `margin` (m) at most `v_max` fast (m/s), control
    /// period `h` (s).
    ///
    /// # Errors
    /// A parameter not finite or out of range ([`NavError::InvalidOption`], naming it).
    pub fn new(radius: f64, margin: f64, v_max: f64, h: f64) -> Result<Self, NavError> {
        let length = |field, v: f64| {
            if v.is_finite() && (0.0..=MAX_MOVER).contains(&v) {
                Ok(v)
            } else {
                Err(NavError::InvalidOption { field, value: v })
            }
        };
        let positive = |field, v: f64| {
            if v.is_finite() && v > 0.0 && v <= MAX_MOVER {
                Ok(v)
            } else {
                Err(NavError::InvalidOption { field, value: v })
            }
        };
        Ok(Self {
            radius: length("radius", radius)?,
            margin: length("margin", margin)?,
            v_max: positive("v_max", v_max)?,
            period: positive("control_period", h)?,
            rows: Vec::new(),
        })
    }

    /// Filters `nominal` at `x` against `movers`, with `clearance` the caller's certified
    /// distance to the static world (`f64::INFINITY` for none): the nominal velocity, clipped
    /// to the static set `|u| ≤ min(v_max, β·clearance/h)` ([`crate::Mode::Capped`] if it was),
    /// when it meets every row; else the certified projection onto the rows and the static set
    /// ([`crate::Mode::Yielding`]); else the least largest shortfall of the rows, not certified
    /// ([`crate::Mode::Overwhelmed`]).
    ///
    /// # Errors
    /// A mover not valid ([`NavError::InvalidMover`]), a non-finite input
    /// ([`NavError::NotFinite`]), a mover whose reported body overlaps the robot's
    /// ([`NavError::InMover`]).
    pub fn filter(
        &mut self,
        x: Vector2<f64>,
        nominal: Vector2<f64>,
        movers: &[Mover],
        clearance: f64,
    ) -> Result<Filtered, NavError> {
        crate::controller::finite(x, "position")?;
        crate::controller::finite(nominal, "velocity")?;
        for (i, m) in movers.iter().enumerate() {
            m.validate(i)?;
        }
        let h = self.period;
        rows(
            movers,
            (x, self.radius, self.margin),
            h,
            0.0,
            &mut self.rows,
        )?;
        // The static set: every step of length β·clearance is free.
        let r = if clearance.is_nan() {
            0.0
        } else {
            self.v_max.min(KINEMATIC_FRACTION * clearance.max(0.0) / h)
        };
        let norm = nominal.norm();
        let (u, kept) = if norm > r {
            let scale = r / norm;
            (nominal * scale, crate::Mode::Capped { scale })
        } else {
            (nominal, crate::Mode::Law)
        };
        let (velocity, verdict) = filter(&self.rows, (u, true), r, |_| true, r);
        Ok(Filtered {
            velocity,
            mode: verdict.mode_or(kept),
        })
    }
}

impl Verdict {
    /// The command's mode after the filter: `kept` when it was kept.
    pub(crate) fn mode_or(self, kept: crate::Mode) -> crate::Mode {
        match self {
            Self::Kept => kept,
            Self::Yielding { mover, scale } => crate::Mode::Yielding { mover, scale },
            Self::Overwhelmed { mover, shortfall } => crate::Mode::Overwhelmed { mover, shortfall },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use harmonav_transform::random::Rng;

    const RADIUS: f64 = 0.2;
    const MARGIN: f64 = 0.05;
    const H: f64 = 0.1;
    const V_MAX: f64 = 1.5;

    /// The mover memory's ranges, as `validate` checks them and its errors state them (the
    /// error module writes the constants out): the ends of each range are in or out as said.
    #[test]
    fn the_mover_memorys_ranges_are_the_constants() {
        let m = |slow, turning| MoverMemory {
            slow,
            turning,
            yielded: true,
        };
        assert!(m(0.0, 0.0).validate().is_ok());
        assert!(
            m(STUCK_TIME.next_down(), STUCK_TURN_TIME)
                .validate()
                .is_ok()
        );
        for (bad, field) in [
            (m(STUCK_TIME, 0.0), "mover_memory.slow"),
            (m(0.0, STUCK_TURN_TIME.next_up()), "mover_memory.turning"),
        ] {
            let e = bad.validate().unwrap_err();
            assert!(matches!(e, NavError::InvalidOption { field: f, .. } if f == field));
            let range = if field.ends_with("slow") {
                format!("[0, {STUCK_TIME})")
            } else {
                format!("[0, {STUCK_TURN_TIME}]")
            };
            assert!(e.to_string().contains(&range), "{e}");
        }
    }

    /// Robot `i`'s filtered command: its nominal `u` against its peer as it sees it (`report`,
    /// declared with `error`, share `share`); `None` when not certified. `plain`: the row of
    /// before eq. robust (`n̂` as if exact, `d` still shrunk by `ε`), the negative control.
    fn command(
        x: Vector2<f64>,
        report: Vector2<f64>,
        (error, share): (f64, f64),
        u: Vector2<f64>,
        plain: bool,
    ) -> Option<Vector2<f64>> {
        let peer = Mover::new(report, RADIUS, V_MAX)
            .with_error(error)
            .reciprocal(share);
        let mut buffer = Vec::new();
        rows(&[peer], (x, RADIUS, MARGIN), H, 0.0, &mut buffer).ok()?;
        if plain {
            let first = buffer[0];
            let n = (x - report).normalize();
            let d = (x - report).norm() - (RADIUS + MARGIN + RADIUS) - error;
            buffer = vec![Row {
                n,
                a: -share * KINEMATIC_FRACTION * d.max(0.0) / H,
                ..first
            }];
        }
        match filter(&buffer, (u, true), V_MAX, |_| true, V_MAX) {
            (v, Verdict::Kept | Verdict::Yielding { .. }) => Some(v),
            (_, Verdict::Overwhelmed { .. }) => None,
        }
    }

    /// The worst of `g(τ) − (1 − βτ/h)·d` over the period for the true positions and the
    /// commands held (`g` the true gap of the grown disc to the peer's body, `d` at `τ = 0`).
    fn worst_decay(x: [Vector2<f64>; 2], u: [Vector2<f64>; 2]) -> f64 {
        let reach = 2.0 * RADIUS + MARGIN;
        let d = (x[0] - x[1]).norm() - reach;
        (0..=200)
            .map(|k| {
                let tau = H * f64::from(k) / 200.0;
                let g = (x[0] - x[1] + tau * (u[0] - u[1])).norm() - reach;
                g - (1.0 - KINEMATIC_FRACTION * tau / H) * d
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Eq. robust: two reciprocal robots, each reporting the other within its own `ε`
    /// (0.02–0.5 m, drawn per pair), with shares adding to 1 and nominal commands towards each
    /// other: whenever both commands are certified, the true gap keeps at least `(1 − βτ/h)` of
    /// its value over the period, in 20 000 draws (Theorem 1 of docs/movers.md with the
    /// errors). The negative control: the row of before (the reported normal taken as exact)
    /// breaks it in some draws. With `ε = 0` the row is the one of before, bit for bit.
    #[test]
    fn the_robust_reciprocal_row_holds_for_the_true_positions() {
        let mut rng = Rng::new(54);
        let (mut checked, mut broken_plain, mut worst) = (0, 0, f64::INFINITY);
        for _ in 0..20_000 {
            let x0 = Vector2::zeros();
            let angle = rng.uniform(-3.2, 3.2);
            let gap = rng.uniform(0.0, 0.3);
            let x1 = (2.0 * RADIUS + MARGIN + gap) * Vector2::new(angle.cos(), angle.sin());
            let errors = [rng.uniform(0.02, 0.5), rng.uniform(0.02, 0.5)];
            let share = rng.uniform(0.0, 1.0);
            // Each sees the other's body within its error (on the disc's edge: the worst).
            let seen = |p: Vector2<f64>, e: f64, rng: &mut Rng| {
                let a = rng.uniform(-3.2, 3.2);
                p + e * rng.uniform(0.5, 1.0) * Vector2::new(a.cos(), a.sin())
            };
            let (r0, r1) = (seen(x1, errors[0], &mut rng), seen(x0, errors[1], &mut rng));
            // Nominals roughly at each other (the case the rows are for), at up to v_max.
            let towards = |from: Vector2<f64>, to: Vector2<f64>, rng: &mut Rng| {
                let a = rng.uniform(-1.4, 1.4);
                let d = (to - from).normalize();
                let (c, s) = (a.cos(), a.sin());
                V_MAX * rng.uniform(0.3, 1.0) * Vector2::new(c * d.x - s * d.y, s * d.x + c * d.y)
            };
            let (n0, n1) = (towards(x0, x1, &mut rng), towards(x1, x0, &mut rng));
            let ok = |plain| {
                let u0 = command(x0, r0, (errors[0], share), n0, plain)?;
                let u1 = command(x1, r1, (errors[1], 1.0 - share), n1, plain)?;
                Some(worst_decay([x0, x1], [u0, u1]))
            };
            if let Some(w) = ok(false) {
                checked += 1;
                worst = worst.min(w);
                assert!(w >= -1e-12, "robust rows broke the decay by {w}");
            }
            if ok(true).is_some_and(|w| w < -1e-9) {
                broken_plain += 1;
            }
        }
        println!(
            "robust rows: {checked} certified pairs, worst slack {worst:e}; \
             the plain row broke {broken_plain}"
        );
        assert!(checked > 2_000, "{checked}");
        assert!(broken_plain > 0, "the negative control shows nothing");
    }

    /// The dynamic law's pair (docs/movers.md §2, "The dynamic law"): two reciprocal robots,
    /// each straying from its straight step by up to its own `e = (h/2)(|v| + bound)` (taken
    /// here as the worst: the full `e`, towards the other, at every instant), peers declared
    /// with the law's speed bound. Whenever both filtered `v⁺` are certified and the gap net of
    /// both deviations `d* = D − e_A − e_B` starts at 0 or more, the gap keeps `(1 − βτ/h)d*`
    /// over the period, in 20 000 seeded pairs. The negative control: with rows that take off
    /// only the robot's own deviation (before 2026-12-07) the grown discs overlap in some.
    #[test]
    fn the_dynamic_pair_takes_both_deviations_off() {
        const BOUND: f64 = 2.0;
        let mut rng = Rng::new(55);
        let (mut checked, mut broken_old) = (0, 0);
        let reach = 2.0 * RADIUS + MARGIN;
        for _ in 0..20_000 {
            let angle = rng.uniform(-3.2, 3.2);
            let x = [
                Vector2::zeros(),
                (reach + rng.uniform(0.0, 0.8)) * Vector2::new(angle.cos(), angle.sin()),
            ];
            let speed = |rng: &mut Rng| {
                let a = rng.uniform(-3.2, 3.2);
                BOUND * rng.uniform(0.0, 1.0) * Vector2::new(a.cos(), a.sin())
            };
            let v = [speed(&mut rng), speed(&mut rng)];
            let e = v.map(|v| 0.5 * H * (v.norm() + BOUND));
            let d_star = (x[0] - x[1]).norm() - reach - e[0] - e[1];
            if d_star < 0.0 {
                continue;
            }
            let nominal = |i: usize| (x[1 - i] - x[i]).normalize() * BOUND * 0.99;
            let filtered = |i: usize, old: bool| -> Option<Vector2<f64>> {
                let peer = Mover::new(x[1 - i], RADIUS, BOUND).reciprocal(0.5);
                let mut buffer = Vec::new();
                rows(&[peer], (x[i], RADIUS, MARGIN), H, e[i], &mut buffer).ok()?;
                if old {
                    let d = (x[i] - x[1 - i]).norm() - reach - e[i];
                    buffer[0].a = -0.5 * KINEMATIC_FRACTION * d.max(0.0) / H;
                }
                match filter(&buffer, (nominal(i), true), BOUND, |_| true, BOUND) {
                    (u, Verdict::Kept | Verdict::Yielding { .. }) => Some(u),
                    (_, Verdict::Overwhelmed { .. }) => None,
                }
            };
            // The least of `g(τ) − (1 − βτ/h)d*` and the least gap `g(τ)` itself.
            let worst = |old: bool| -> Option<(f64, f64)> {
                let u = [filtered(0, old)?, filtered(1, old)?];
                Some(
                    (1..=100).fold((f64::INFINITY, f64::INFINITY), |(w, least), k| {
                        let tau = H * f64::from(k) / 100.0;
                        let g = (x[0] - x[1] + tau * (u[0] - u[1])).norm() - reach - e[0] - e[1];
                        (
                            w.min(g - (1.0 - KINEMATIC_FRACTION * tau / H) * d_star),
                            least.min(g),
                        )
                    }),
                )
            };
            if let Some((w, _)) = worst(false) {
                checked += 1;
                assert!(
                    w >= -1e-12,
                    "both deviations off: the gap fell short by {w}"
                );
            }
            // The old rows let the bodies (grown by the margin) overlap.
            if worst(true).is_some_and(|(_, least)| least < -1e-9) {
                broken_old += 1;
            }
        }
        println!(
            "dynamic pairs: {checked} certified; the rows of before overlapped in {broken_old}"
        );
        assert!(checked > 2_000, "{checked}");
        assert!(broken_old > 0, "the negative control shows nothing");
    }

    /// The comfort stage returns the nominal bit for bit (its trust kept) with no comfort, with
    /// reciprocal movers only, and where the nominal meets its rows; else a turned nominal,
    /// not trusted, that meets every comfort row when one can (eq. comfort).
    #[test]
    fn the_comfort_turns_only_a_nominal_that_comes_too_close() {
        let x = Vector2::new(0.0, 0.0);
        let body = (x, 0.2, 0.05);
        let person = Mover::new(Vector2::new(0.7, 0.0), 0.2, 0.2);
        let peer = person.reciprocal(0.5);
        let towards = (Vector2::new(0.5, 0.1), true);
        let mut buf = Vec::new();
        let same = |movers: &[Mover], c: f64, u, buf: &mut Vec<Row>| {
            comfort(movers, body, (0.1, 0.0, c), buf, u, 1.0).unwrap()
        };
        assert_eq!(same(&[person], 0.0, towards, &mut buf), towards);
        assert_eq!(same(&[peer], 0.3, towards, &mut buf), towards);
        let away = (Vector2::new(-0.5, 0.1), true);
        assert_eq!(same(&[person], 0.3, away, &mut buf), away);
        let (u, trusted) = same(&[person], 0.3, towards, &mut buf);
        assert!(!trusted && u != towards.0);
        // The comfort's row: `n·u ≥ V − β(d − c)/h`, `n = (−1, 0)`, `d = 0.7 − 0.45`.
        let row = 0.2 - KINEMATIC_FRACTION * (0.25 - 0.3) / 0.1;
        assert!(-u.x >= row - 1e-12, "{u:?} against {row}");
        // With the same distance as margin alone the nominal met the filter's row already.
        assert!(-towards.0.x >= 0.2 - KINEMATIC_FRACTION * 0.25 / 0.1);
    }

    /// With `ε = 0` a reciprocal mover gives one row, today's; with `ε > 0` four, each
    /// admitting `u = 0` and each tilted from `n̂` by at most `atan(η/(1 − η))`.
    #[test]
    fn an_exact_report_keeps_the_one_row() {
        let x = Vector2::new(0.3, -0.1);
        let p = Vector2::new(1.2, 0.5);
        let mut buffer = Vec::new();
        let peer = Mover::new(p, RADIUS, 1.0).reciprocal(0.5);
        rows(&[peer], (x, RADIUS, MARGIN), H, 0.0, &mut buffer).unwrap();
        assert_eq!(buffer.len(), 1);
        let n = (x - p).normalize();
        let d = (x - p).norm() - (2.0 * RADIUS + MARGIN);
        assert_eq!(buffer[0].n, n);
        assert_eq!(buffer[0].a, -0.5 * KINEMATIC_FRACTION * d / H);
        let error = 0.1;
        rows(
            &[peer.with_error(error)],
            (x, RADIUS, MARGIN),
            H,
            0.0,
            &mut buffer,
        )
        .unwrap();
        assert_eq!(buffer.len(), 4);
        let eta = 2.0 * (0.5 * (error / (x - p).norm()).asin()).sin();
        for row in &buffer {
            assert!(row.hard && row.a <= 0.0 && row.slack(Vector2::zeros()) >= 0.0);
            assert!((row.n.norm() - 1.0).abs() < 1e-15);
            let least = (1.0 - eta) / ((1.0 - eta).powi(2) + eta * eta).sqrt();
            assert!(row.n.dot(&n) >= least - 1e-12, "{row:?}");
        }
    }
}
