//! Measurements of `Θ`'s properties on one field, shared by this crate's tests and
//! `cargo xtask verify` (`field.*`).
//!
//! Each function measures one property and returns the figures it measured (or the first point
//! where a map or `Θ` could not be evaluated); the caller chooses the worlds, the points and the
//! bound. The tests assert on proptest-generated worlds, `verify` reports the worst figure over
//! seeded ones, and both measure the same thing the same way (as `harmonav_potential::checks`
//! does for `phi_k`). The worlds are taken with every obstacle known
//! ([`Field::all_known`]): the boundaries measured are the workspace's.

use std::cell::Cell;

use harmonav_potential::checks::{fd_gradient, fd_jacobian};
use harmonav_transform::{NotFree, Workspace};
use nalgebra::Vector2;

use crate::descent::{Ending, FollowOptions, follow};
use crate::{Field, FieldError, FieldEval};

/// Where a check could not evaluate at a point it needed.
#[derive(Clone, Debug, PartialEq)]
pub enum Failure {
    /// `Θ` could not be evaluated at `at`.
    Eval {
        /// The point.
        at: Vector2<f64>,
        /// Why.
        error: FieldError,
    },
    /// `Phi` refused `at`.
    Transform {
        /// The point.
        at: Vector2<f64>,
        /// Why.
        error: NotFree,
    },
    /// `Phi⁻¹` found no preimage of `Phi(at)`.
    NoInverse {
        /// The point.
        at: Vector2<f64>,
    },
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Eval { at, error } => write!(f, "{error} at {at:?}"),
            Self::Transform { at, error } => write!(f, "Phi refused {at:?}: {error:?}"),
            Self::NoInverse { at } => write!(f, "Phi⁻¹ found no preimage of Phi({at:?})"),
        }
    }
}

impl std::error::Error for Failure {}

fn eval(field: &Field, at: Vector2<f64>) -> Result<FieldEval, Failure> {
    field.eval(at).map_err(|error| Failure::Eval { at, error })
}

/// Points `offset` off every obstacle boundary (outside it) and off the outer boundary (inside
/// it), along the ray at `angle` from each shape's centre: `c_i + (R_i(angle) ± offset)·u`.
/// The obstacles come first, in workspace order; the outer boundary's point is last.
pub fn near_boundaries(ws: &Workspace, angle: f64, offset: f64) -> Vec<Vector2<f64>> {
    let u = Vector2::new(angle.cos(), angle.sin());
    let mut points: Vec<_> = ws
        .obstacles()
        .iter()
        .map(|o| o.centre() + (o.radius(angle).0 + offset) * u)
        .collect();
    let b = ws.boundary();
    points.push(b.centre() + (b.radius(angle).0 - offset) * u);
    points
}

/// Tolerance of [`Sample::is_sound`] on `|−∇Θ/|∇Θ|| = 1`: a few rounding errors.
pub const UNIT_TOLERANCE: f64 = 1e-12;

/// Definition `NavTran` and eq. `phiseq` at one point: `det J_Phi(x)` (positive and finite
/// where `Phi` is a diffeomorphism, up to the boundaries) and the evaluation of `Θ` there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// `det J_Phi(x)`.
    pub det: f64,
    /// `Θ(x)`, `phi_k(Phi(x))`, `∇Θ(x)` and the direction.
    pub eval: FieldEval,
}

impl Sample {
    /// `det J_Phi > 0` and finite.
    #[must_use]
    pub fn orientation_preserving(&self) -> bool {
        self.det > 0.0 && self.det.is_finite()
    }

    /// `Θ ∈ [0, 1]`, `phi_k` and `∇Θ` finite, and the descent direction defined and of unit
    /// length within [`UNIT_TOLERANCE`] (everywhere in the open free space but at critical
    /// points).
    #[must_use]
    pub fn is_sound(&self) -> bool {
        let e = &self.eval;
        (0.0..=1.0).contains(&e.value)
            && e.phi.is_finite()
            && e.gradient.iter().all(|g| g.is_finite())
            && e.direction
                .is_some_and(|d| (d.norm() - 1.0).abs() < UNIT_TOLERANCE)
    }
}

/// Measures [`Sample`] at `x`.
pub fn sample(field: &Field, x: Vector2<f64>) -> Result<Sample, Failure> {
    let m = field
        .transform()
        .nav_transform(x)
        .map_err(|error| Failure::Transform { at: x, error })?;
    Ok(Sample {
        det: m.jacobian.determinant(),
        eval: eval(field, x)?,
    })
}

/// `Phi` injective on samples: `|Phi⁻¹(Phi(x)) − x|`. Within 1e-9 of a boundary
/// `h = P_i + ν u` with `ν ~ 1e-9` carries only ~7 significant digits of `u` (pitfall C), so
/// this is a measure for interior points.
pub fn round_trip(field: &Field, x: Vector2<f64>) -> Result<f64, Failure> {
    let t = field.transform();
    let h = t
        .nav_transform(x)
        .map_err(|error| Failure::Transform { at: x, error })?
        .h;
    let back = t.inverse(h).ok_or(Failure::NoInverse { at: x })?;
    Ok((back - x).norm())
}

/// Step of the central differences of [`fd_errors`], m: the rounding error is `≈ ε/step` ≈ 2e-9
/// (relative); over `verify`'s 12 000 interior samples (clearance ≥ 1e-3 m) the worst relative
/// `J_Phi` error is 2.3e-8 and the worst `∇Θ` error 6.2e-7.
pub const FD_STEP: f64 = 1e-7;

/// `J_Phi` (definition `NavTran`) and `∇Θ = sigma'·J_Phiᵀ∇phi_k` (eq. `phiseq`) against central
/// differences of `Phi` and `Θ` ([`FD_STEP`]) at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FdErrors {
    /// `max_i |J e_i − FD(Phi) e_i| / |J|` (Frobenius norm below).
    pub jacobian: f64,
    /// `|∇Θ − FD(Θ)|` (absolute: `∇Θ` underflows far from the goal).
    pub gradient: f64,
    /// `|∇Θ|`, to make [`FdErrors::gradient`] relative.
    pub gradient_norm: f64,
}

/// Measures [`FdErrors`] at `x`, which must be at least [`FD_STEP`] inside the free space.
pub fn fd_errors(field: &Field, x: Vector2<f64>) -> Result<FdErrors, Failure> {
    let t = field.transform();
    let m = t
        .nav_transform(x)
        .map_err(|error| Failure::Transform { at: x, error })?;
    let failure = Cell::new(None);
    let map = |y: Vector2<f64>| match t.nav_transform(y) {
        Ok(m) => m.h,
        Err(error) => {
            failure.set(Some(Failure::Transform { at: y, error }));
            Vector2::repeat(f64::NAN)
        }
    };
    let fd = fd_jacobian(map, x, FD_STEP);
    let value = |y: Vector2<f64>| match eval(field, y) {
        Ok(e) => e.value,
        Err(f) => {
            failure.set(Some(f));
            f64::NAN
        }
    };
    let fd_grad = fd_gradient(value, x, FD_STEP);
    if let Some(f) = failure.take() {
        return Err(f);
    }
    let column = |i: usize| (m.jacobian.column(i) - fd.column(i)).norm();
    let g = eval(field, x)?.gradient;
    Ok(FdErrors {
        jacobian: column(0).max(column(1)) / m.jacobian.norm(),
        gradient: (g - fd_grad).norm(),
        gradient_norm: g.norm(),
    })
}

/// `Θ` approaching one boundary along a ray (see [`limits`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Approach {
    /// The obstacle (workspace index), `None` for the outer boundary.
    pub obstacle: Option<usize>,
    /// `Θ` at the far offset.
    pub theta_far: f64,
    /// `Θ` at the near offset.
    pub theta_near: f64,
    /// For an obstacle, the rise of `phi_k = logit Θ` from the far to the near offset over its
    /// closed form `(2/k)·ln(far/near)` (`|h_i| = ν ∝ δ` at the band's inner edge, every other
    /// term constant, so `1 − Θ` falls as `δ^{2Θ/k}`, docs/maths.md §8): 1 where the closed form
    /// holds. `None` for the outer boundary.
    pub rise: Option<f64>,
}

impl Approach {
    /// `Θ` rises towards the boundary: `Θ(far) < Θ(near)`.
    #[must_use]
    pub fn rises(&self) -> bool {
        self.theta_far < self.theta_near
    }
}

/// The limits of eq. `NFcand`: `Θ(x_d) = 0`, and `Θ → 1` at every boundary.
#[derive(Clone, Debug, PartialEq)]
pub struct Limits {
    /// `Θ(x_d)`.
    pub at_goal: f64,
    /// One per obstacle (workspace order), then the outer boundary.
    pub approaches: Vec<Approach>,
}

/// Measures [`Limits`] along the rays at `angle` ([`near_boundaries`]) at the offsets `far` and
/// `near` (`far > near`).
pub fn limits(field: &Field, angle: f64, far: f64, near: f64) -> Result<Limits, Failure> {
    let ws = field.workspace();
    let n = ws.obstacles().len();
    let unit_rise = 2.0 / field.k() * (far / near).ln();
    let pairs = near_boundaries(ws, angle, far)
        .into_iter()
        .zip(near_boundaries(ws, angle, near));
    let mut approaches = Vec::with_capacity(n + 1);
    for (i, (a, b)) in pairs.enumerate() {
        let (ea, eb) = (eval(field, a)?, eval(field, b)?);
        approaches.push(Approach {
            obstacle: (i < n).then_some(i),
            theta_far: ea.value,
            theta_near: eb.value,
            rise: (i < n).then(|| (eb.phi - ea.phi) / unit_rise),
        });
    }
    Ok(Limits {
        at_goal: eval(field, ws.destination())?.value,
        approaches,
    })
}

/// Offset of the probe of [`CriticalPoints::worst_gradient_ratio`], m.
pub const GRADIENT_PROBE: f64 = 1e-3;

/// Theorem `isNF` (`Θ` is a navigation function): the critical points of [`Field::critical_points`]
/// are the destination, a minimum, and the saddles of `phi_k` pulled back through `Phi⁻¹`, `M`
/// of them counted with multiplicity (lemma `saddlep`), each a zero of `∇Θ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CriticalPoints {
    /// The first point, the minimum (the destination).
    pub minimum: Vector2<f64>,
    /// Σ multiplicity of the saddles.
    pub saddles: usize,
    /// `M`, the known obstacles.
    pub obstacles: usize,
    /// The largest `|∇Θ(c)| / |∇Θ(c + GRADIENT_PROBE·e_x)|` over the saddles `c`: `∇Θ` at a
    /// saddle relative to its size nearby (`sigma'` sets its scale, which varies by orders of
    /// magnitude over the workspace).
    pub worst_gradient_ratio: f64,
}

/// Measures [`CriticalPoints`].
pub fn critical_points(field: &Field) -> Result<CriticalPoints, Failure> {
    let cps = field.critical_points();
    let mut out = CriticalPoints {
        minimum: cps[0].x,
        saddles: cps
            .iter()
            .filter_map(|c| c.point_world.map(|p| p.multiplicity))
            .sum(),
        obstacles: field.known().len(),
        worst_gradient_ratio: 0.0,
    };
    for c in &cps[1..] {
        let at = eval(field, c.x)?.gradient.norm();
        let probe = eval(field, c.x + Vector2::new(GRADIENT_PROBE, 0.0))?;
        let ratio = at / probe.gradient.norm().max(1e-300);
        out.worst_gradient_ratio = if ratio.is_nan() {
            f64::INFINITY
        } else {
            out.worst_gradient_ratio.max(ratio)
        };
    }
    Ok(out)
}

/// Convergence of the normalised gradient flow `ẋ = −∇Θ/|∇Θ|` ([`follow`], unit speed, so a
/// time is a path length) from many starts: the theorem `isNF` guarantee that almost every start
/// reaches `x_d` without collision.
#[derive(Clone, Debug, PartialEq)]
pub struct Convergence {
    /// Starts followed.
    pub starts: usize,
    /// Descents that ended [`Ending::Reached`].
    pub reached: usize,
    /// Descents with an accepted point outside the true free space.
    pub collisions: usize,
    /// The start of the first of them.
    pub first_collision: Option<Vector2<f64>>,
    /// The arrival times of the reached descents, s, ascending.
    pub times: Vec<f64>,
}

impl Convergence {
    /// The median arrival time (NaN if none arrived).
    #[must_use]
    pub fn median(&self) -> f64 {
        self.times
            .get(self.times.len() / 2)
            .copied()
            .unwrap_or(f64::NAN)
    }

    /// The slowest arrival (NaN if none arrived).
    #[must_use]
    pub fn slowest(&self) -> f64 {
        self.times.last().copied().unwrap_or(f64::NAN)
    }
}

/// Measures [`Convergence`] from each of `starts`.
pub fn convergence(
    field: &Field,
    starts: impl IntoIterator<Item = Vector2<f64>>,
    options: &FollowOptions,
) -> Convergence {
    let mut out = Convergence {
        starts: 0,
        reached: 0,
        collisions: 0,
        first_collision: None,
        times: Vec::new(),
    };
    for x in starts {
        let d = follow(field, x, options);
        out.starts += 1;
        if !d.collision_free {
            out.collisions += 1;
            out.first_collision.get_or_insert(x);
        }
        if d.ending == Ending::Reached {
            out.reached += 1;
            out.times.push(d.time);
        }
    }
    out.times.sort_by(f64::total_cmp);
    out
}
