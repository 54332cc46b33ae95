//! The braking certificate of a force-bounded dynamic robot ([`crate::Options::force_bound`],
//! issue 54, docs/movers.md §2): passive safety. Without a bound the dynamic hold may stop
//! the robot within one period (`h|v⁺| ≤ c·d(x)`); with `|f| ≤ F` it needs `|v|²/2a`
//! (`a = F/m`) to stop, and a command that is safe for one period can leave it no way to stop
//! in time. A command is certified here when, after it, the robot can still brake to rest
//! along its velocity inside the known free space and out of every mover's reach. Under the
//! hold model (semi-implicit Euler, `v⁺ = v + h f/m`, `x⁺ = x + h v⁺`):
//!
//! ```text
//! |f| ≤ F  ⇔  |v⁺ − v| ≤ h a                                     (the force bound)
//! L(s) = h s + s²/(2a),   T(s) = h + s/a,   s = |v⁺|                (eq. backup)
//! the segment from x along v⁺/s of length L(s) is certified free   (the known shapes)
//! d_j ≥ L(s) + V_j T(s)   for every mover j                         (eq. backupmover)
//! ```
//!
//! `L(s)` bounds the period's step `h s` and the brake after it (`v ← v − h a·v/|v|` each period,
//! the last one to 0), all on that segment: the brake's steps `h(s − k h a)` sum to at most
//! `s²/2a`. `T(s)` bounds the time to rest, and `d_j` is the clearance to mover `j` as reported
//! (`|x − p̂_j| − (radius + margin + r_j) − ε_j`): every point of the manoeuvre lies within
//! `L(s)` of `x`, and by its end the mover has come at most `V_j T(s)` nearer.
//!
//! **Recursive feasibility** against the known shapes. After a certified command the full brake
//! `v⁺⁺ = v⁺ − h a·v⁺/|v⁺|` (or 0) is certified again: its own manoeuvre, from `x⁺ = x + h v⁺`
//! along the same direction, has length `h s' + s'²/2a ≤ s²/2a` (`s' = s − h a`; the
//! difference is `h²a/2`), the tail of the segment just certified. So a robot that starts
//! certified (at rest, say) in a world that does not change always has a certified command.
//! Against a mover only for `s > h a` and reports that move by at most `V_j h` between periods
//! (`d_j' ≥ d_j − h s − V_j h` while `L(s') + V_j T(s') ≤ L(s) − h s + V_j(T(s) − h)`); a mover
//! that closes in on a robot slower than that overwhelms it, and if a contact happens the robot
//! is braking or at rest and the mover came to it (Fraichard's inevitable collision states).
//! The sphere tracing is evaluated afresh each period; should it fail to certify the brake,
//! the brake is still commanded, as [`Mode::Braking`] (not certified).

use nalgebra::Vector2;

use crate::error::NavError;
use crate::hold::{self, Mode};
use crate::movers::Mover;
use crate::space::Space;

/// The bisection steps between the brake and the command that was asked for: `2⁻⁴⁰` of their
/// difference is far below any speed that matters.
const BISECTIONS: u32 = 40;

/// `F` shrunk by four ulps, so that a force scaled to it never rounds above `F`.
fn within(force_bound: f64) -> f64 {
    force_bound * (1.0 - 4.0 * f64::EPSILON)
}

/// The force `f` scaled down to `|f| ≤ F` (unchanged if it is within): the force bound alone,
/// the first candidate of [`Backup::certify`] and the way out of the margin band's
/// ([`Backup::recovering`]).
pub(crate) fn clip(f: Vector2<f64>, force_bound: f64) -> Vector2<f64> {
    let norm = f.norm();
    if norm > force_bound {
        f * (within(force_bound) / norm)
    } else {
        f
    }
}

/// `L(s) = h s + s²/(2a)` of eq. backup: how far a robot goes in one period at speed `s` and
/// then braking at `a` to rest.
pub(crate) fn backup_length(s: f64, h: f64, a: f64) -> f64 {
    h * s + s * s / (2.0 * a)
}

/// The largest speed `s` with `L(s) + V T(s) ≤ d` (eq. backupmover), the larger root of
/// `s²/2a + s(h + V/a) + V h − d`:
///
/// ```text
/// s = −B + √D = 2a(d − V h)/(B + √D),   B = a h + V,   D = B² + 2a(d − V h) = a²h² + V² + 2ad
/// ```
///
/// Numerical guard: the second form, which subtracts nothing (the first loses `ulp(B)` to
/// cancellation, measured −0.09 m of `d` at `a` = 1e-15 m/s²). Negative when `d < V h` (the
/// mover can reach the robot within the period even at rest); `−∞` when `D < 0` (`d` far
/// below zero).
pub(crate) fn mover_cap(d: f64, speed_bound: f64, h: f64, a: f64) -> f64 {
    let b = a * h + speed_bound;
    let disc = b * b + 2.0 * a * (d - speed_bound * h);
    if disc < 0.0 {
        return f64::NEG_INFINITY;
    }
    2.0 * a * (d - speed_bound * h) / (b + disc.sqrt())
}

/// What [`bounded`] did with the command.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Verdict {
    /// The command keeps its mode: the hold's, within the bound and certified as it was (bit
    /// for bit); a halt's brake whose way to rest is certified; a way out of the band scaled
    /// to the bound that still leads out.
    Kept,
    /// Scaled to the force bound, or moved towards the brake until certified: `scale` of the
    /// speed asked for; `mover` binds, if one does.
    Shortened { scale: f64, mover: Option<usize> },
    /// Even the full brake is not certified against the known shapes: commanded anyway.
    Braking,
    /// Even the full brake leaves `mover`'s reach short by `shortfall` m/s.
    Overwhelmed { mover: usize, shortfall: f64 },
}

impl Verdict {
    /// The mode of the command, `kept` the hold's.
    pub(crate) fn mode_or(self, kept: Mode) -> Mode {
        match self {
            Self::Kept => kept,
            Self::Shortened {
                scale,
                mover: Some(mover),
            } => Mode::Yielding { mover, scale },
            Self::Shortened { scale, mover: None } => Mode::Bounded { scale },
            Self::Braking => Mode::Braking,
            Self::Overwhelmed { mover, shortfall } => Mode::Overwhelmed { mover, shortfall },
        }
    }
}

/// A robot at `x` moving at `v` under a force bound: what its manoeuvre after a force `f`
/// must clear (eq. backup, eq. backupmover).
struct Backup<'a, S> {
    space: &'a S,
    x: Vector2<f64>,
    v: Vector2<f64>,
    /// `m`, `h`, `a = F/m` (`F` four ulps within, [`within`]).
    mass: f64,
    h: f64,
    a: f64,
    /// The least of the movers' caps on the speed after the period, and whose it is.
    cap: (f64, Option<usize>),
}

impl<'a, S: Space> Backup<'a, S> {
    /// Errors: a reported mover's body overlaps the robot's ([`NavError::InMover`]).
    fn new(
        space: &'a S,
        movers: &[Mover],
        (x, radius, margin): (Vector2<f64>, f64, f64),
        v: Vector2<f64>,
        (mass, h, force_bound): (f64, f64, f64),
    ) -> Result<Self, NavError> {
        let a = within(force_bound) / mass;
        let mut cap = (f64::INFINITY, None);
        for (j, m) in movers.iter().enumerate() {
            let dist = (x - m.centre).norm();
            if dist <= radius + m.radius {
                return Err(NavError::InMover { mover: j });
            }
            let d = dist - (radius + margin + m.radius) - m.position_error;
            let s = mover_cap(d, m.speed_bound, h, a);
            if s < cap.0 {
                cap = (s, Some(j));
            }
        }
        Ok(Self {
            space,
            x,
            v,
            mass,
            h,
            a,
            cap,
        })
    }

    /// `v⁺ = v + h f/m`.
    fn speed_after(&self, f: Vector2<f64>) -> Vector2<f64> {
        self.v + (self.h / self.mass) * f
    }

    /// Whether `|v⁺|` is within every mover's cap (eq. backupmover).
    fn clear_of_movers(&self, f: Vector2<f64>) -> bool {
        self.speed_after(f).norm() <= self.cap.0
    }

    /// Whether the manoeuvre after `f` is certified: clear of the movers, and its segment of
    /// length `L(s)` along `v⁺` free of the known shapes (sphere tracing).
    fn certified(&self, f: Vector2<f64>) -> bool {
        let next = self.speed_after(f);
        let s = next.norm();
        // Eq. backupmover ([`Backup::clear_of_movers`], on the speed just computed).
        if s > self.cap.0 {
            return false;
        }
        let want = backup_length(s, self.h, self.a);
        s == 0.0 || hold::free_length(self.space, self.x, next / s, want) >= want
    }

    /// The full brake: to rest within the period if the bound allows, else `a` against `v`.
    fn brake(&self) -> Vector2<f64> {
        let speed = self.v.norm();
        if speed <= self.a * self.h {
            -(self.mass / self.h) * self.v
        } else {
            -(self.a * self.mass / speed) * self.v
        }
    }

    /// The verdict on the full brake `brake` when it is not certified.
    fn not_certified(&self, brake: Vector2<f64>) -> Verdict {
        let s = self.speed_after(brake).norm();
        match self.cap {
            (c, Some(mover)) if s > c => Verdict::Overwhelmed {
                mover,
                shortfall: s - c.max(0.0),
            },
            _ => Verdict::Braking,
        }
    }
}

/// The robot at `x` (radius, margin), velocity `v`, given the force `f` in mode `mode` by the
/// hold, under the bound `F` (`mass`, `h`: the robot's mass and control period): the force to
/// hold and what became of it. A halt after a refused scan ([`Mode::Halted`]) is
/// [`Backup::halt`], a way out of the margin band ([`Mode::Recovering`]) is
/// [`Backup::recovering`], every other command is [`Backup::certify`].
///
/// Errors: a reported mover's body overlaps the robot's ([`NavError::InMover`]).
pub(crate) fn bounded(
    space: &impl Space,
    movers: &[Mover],
    body: (Vector2<f64>, f64, f64),
    (v, f, mode): (Vector2<f64>, Vector2<f64>, Mode),
    (mass, h, force_bound): (f64, f64, f64),
) -> Result<(Vector2<f64>, Verdict), NavError> {
    let b = Backup::new(space, movers, body, v, (mass, h, force_bound))?;
    Ok(match mode {
        Mode::Halted => b.halt(),
        Mode::Recovering(_) => b.recovering(f, force_bound),
        _ => b.certify(f, force_bound),
    })
}

impl<S: Space> Backup<'_, S> {
    /// `f` itself when it is within `F` and certified (eq. backup, eq. backupmover), else the
    /// force on the segment from the full brake to `f` (scaled to `F`) nearest `f` that is
    /// certified (bisection), else the full brake.
    fn certify(&self, f: Vector2<f64>, force_bound: f64) -> (Vector2<f64>, Verdict) {
        let asked = clip(f, force_bound);
        if self.certified(asked) {
            if asked == f {
                return (f, Verdict::Kept);
            }
            let scale = ratio(self.speed_after(asked).norm(), self.speed_after(f).norm());
            return (asked, Verdict::Shortened { scale, mover: None });
        }
        let brake = self.brake();
        if !self.certified(brake) {
            return (brake, self.not_certified(brake));
        }
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..BISECTIONS {
            let mid = 0.5 * (lo + hi);
            if self.certified(brake + mid * (asked - brake)) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let chosen = brake + lo * (asked - brake);
        // The mover binds if the next candidate out was over its cap.
        let mover = self
            .cap
            .1
            .filter(|_| !self.clear_of_movers(brake + hi * (asked - brake)));
        let scale = ratio(self.speed_after(chosen).norm(), self.speed_after(f).norm());
        (chosen, Verdict::Shortened { scale, mover })
    }

    /// The halt after a refused scan (the halt's own force is not used): the full brake, kept
    /// if its way to rest is certified (eq. backup, eq. backupmover), else not certified.
    fn halt(&self) -> (Vector2<f64>, Verdict) {
        let brake = self.brake();
        if self.certified(brake) {
            (brake, Verdict::Kept)
        } else {
            (brake, self.not_certified(brake))
        }
    }

    /// The way out of the margin band, `f`. The band lies inside a grown shape, where the
    /// known shapes certify nothing; without a bound the way out leads into the free space
    /// within the period. Under it: `f` scaled to `F`, kept (as `Recovering`) while the
    /// velocity after it still points out along the way out (`v⁺·v⁺_out > 0`, `v⁺_out` the
    /// velocity `f` asked for) and is clear of every mover's cap: the robot then leaves the
    /// band over several periods instead of one. Otherwise (moving into the shape faster than
    /// the bound can turn, or a mover within reach) the full brake, not certified.
    fn recovering(&self, f: Vector2<f64>, force_bound: f64) -> (Vector2<f64>, Verdict) {
        let scaled = clip(f, force_bound);
        let out = self.speed_after(f);
        if self.clear_of_movers(scaled) && (scaled == f || self.speed_after(scaled).dot(&out) > 0.0)
        {
            return (scaled, Verdict::Kept);
        }
        let brake = self.brake();
        (brake, self.not_certified(brake))
    }
}

/// `kept/asked`, 0 when nothing was asked.
fn ratio(kept: f64, asked: f64) -> f64 {
    if asked > 0.0 { kept / asked } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Eq. backupmover's cap against its definition: `L(s) + V T(s) = d` at the cap, and 0
    /// when `d = V h`.
    #[test]
    fn the_mover_cap_solves_its_quadratic() {
        let (h, a) = (0.05, 1.5);
        for &(d, v) in &[(1.0, 0.5), (0.3, 2.0), (5.0, 0.0), (0.025, 0.5)] {
            let s = mover_cap(d, v, h, a);
            let used = backup_length(s, h, a) + v * (h + s / a);
            assert!((used - d).abs() <= 1e-12 * d.max(1.0), "{d} {v}: {used}");
        }
        assert!(mover_cap(0.5 * 0.05, 0.5, h, a).abs() < 1e-15);
        assert!(mover_cap(0.0, 0.5, h, a) < 0.0);
    }

    /// The brake's own manoeuvre lies in the tail of the one before it (recursive
    /// feasibility): `h s + L(s − h a) ≤ L(s)`, by `h²a/2`.
    #[test]
    fn the_brake_stays_within_the_manoeuvre_it_continues() {
        let (h, a) = (0.01, 2.0);
        for s in [0.03, 0.5, 1.0, 4.0] {
            let next = backup_length(s - h * a, h, a);
            let gap = backup_length(s, h, a) - (h * s + next);
            assert!((gap - 0.5 * h * h * a).abs() < 1e-15, "{s}: {gap}");
        }
    }

    #[test]
    fn a_clipped_force_never_rounds_above_the_bound() {
        for k in 1..1000 {
            let f = Vector2::new(3.7 * f64::from(k), -1.3 * f64::from(k));
            let bound = 0.37 * f64::from(k);
            assert!(clip(f, bound).norm() <= bound, "{k}");
        }
    }
}
