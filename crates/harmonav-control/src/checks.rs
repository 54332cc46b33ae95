//! Measurements of the laws' properties on one field, shared by this crate's tests and
//! `cargo xtask verify` (`control.*`).
//!
//! Each function measures one property and returns the figures it measured (or the point where
//! `Θ` could not be evaluated); the caller chooses the worlds, the laws, the points and the
//! bound. The tests assert on a few seeded worlds, `verify` reports the worst figure over more,
//! and both measure the same thing the same way (as `harmonav_potential::checks` does for
//! `phi_k`).

use std::cell::Cell;

use harmonav_field::{Field, FieldError, FieldEval};
use harmonav_potential::checks::fd_jacobian;
use nalgebra::{Matrix2, Vector2};

use crate::{Dynamic, Kinematic};

/// `Θ` could not be evaluated at `at`, a point a check needed (a start, a step of the
/// integration, a finite-difference node).
#[derive(Clone, Debug, PartialEq)]
pub struct EvalFailure {
    /// The point.
    pub at: Vector2<f64>,
    /// Why.
    pub error: FieldError,
}

impl std::fmt::Display for EvalFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} at {:?}", self.error, self.at)
    }
}

impl std::error::Error for EvalFailure {}

/// `field.eval(x)`, with the point in the error.
fn eval(field: &Field, x: Vector2<f64>) -> Result<FieldEval, EvalFailure> {
    field.eval(x).map_err(|error| EvalFailure { at: x, error })
}

/// `max(a, b)` with a NaN `b` counted as `+∞`: a figure that could not be measured is the
/// worst, never skipped (`f64::max` would drop it).
fn worst(a: f64, b: f64) -> f64 {
    if b.is_nan() { f64::INFINITY } else { a.max(b) }
}

/// Step of the central differences of `∇Ψ` at the goal in [`goal_damping`], m: the Hessian is
/// `O(1)` there and its third derivatives are bounded, so the truncation error is `O(step²)`
/// ≈ 1e-10, and the rounding error `ε/step` ≈ 1e-11.
pub const GOAL_FD_STEP: f64 = 1e-5;

/// Corollary `critdamp` (critical damping at the goal), measured: the Hessian `H` of the law's
/// potential at `x_d` by central differences of its gradient ([`GOAL_FD_STEP`]; `Θ` under
/// `"paper"`, `Ψ` under every other policy), independent of the closed form
/// `Dynamic::goal_stiffness`, and the damping ratio of the linearised closed loop
/// `m ẍ = −μ_pHx − λ_c ẋ` along each eigenvector of `H` (`μ_p` the law's pull,
/// `Dynamic::pull`: `μ` but under `"governed"`):
///
/// ```text
/// ζ_i = λ_c / (2√(m μ_p e_i)),    e_i the eigenvalues of H;  ζ_i = 1 is critical damping
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GoalDamping {
    /// `H` by central differences.
    pub hessian: Matrix2<f64>,
    /// `λ_c` of the law ([`Dynamic::lambda_c`]).
    pub lambda_c: f64,
    /// `ζ_i` for the two eigenvalues of `H` (NaN where an eigenvalue is negative).
    pub zeta: [f64; 2],
}

impl GoalDamping {
    /// `max_i |ζ_i − 1|`, `+∞` if a `ζ_i` is NaN.
    #[must_use]
    pub fn worst_deviation(&self) -> f64 {
        self.zeta
            .iter()
            .fold(0.0, |acc, z| worst(acc, (z - 1.0).abs()))
    }
}

/// Measures [`GoalDamping`] for `law` at the goal of `field`; an error if a difference node
/// (`GOAL_FD_STEP` from `x_d`) is not in the free space.
pub fn goal_damping(field: &Field, law: &Dynamic) -> Result<GoalDamping, EvalFailure> {
    let failure = Cell::new(None);
    let gradient = |x: Vector2<f64>| match eval(field, x) {
        Ok(e) => law.potential(field, &e).gradient,
        Err(f) => {
            failure.set(Some(f));
            Vector2::repeat(f64::NAN)
        }
    };
    let hessian = fd_jacobian(gradient, field.workspace().destination(), GOAL_FD_STEP);
    if let Some(f) = failure.take() {
        return Err(f);
    }
    let lambda_c = law.lambda_c(field);
    let eig = hessian.symmetric_eigenvalues();
    let zeta = [0, 1].map(|i| lambda_c / (2.0 * (law.mass() * law.pull() * eig[i]).sqrt()));
    Ok(GoalDamping {
        hessian,
        lambda_c,
        zeta,
    })
}

/// Below this energy, J, [`EnergyRun::worst_rise`] is measured against it instead of `V`: a
/// relative rise of an energy that has reached rounding level says nothing.
pub const ENERGY_FLOOR: f64 = 1e-12;

/// Eq. `totalenergy` (`V = μ_pΨ + ½m|ẋ|²`, `V̇ = −λ|ẋ|² ≤ 0` between discoveries, `μ_p` the
/// law's `Dynamic::pull`) and corollary `boundedvel` (`|ẋ| < √(2μ/m)`), measured along the
/// closed loop `m ẍ = f(x, ẋ)` ([`Dynamic::force`], global field, no discovery) integrated by
/// classical RK4.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergyRun {
    /// The largest step-to-step rise `(V_{n+1} − V_n) / max(V_n, ENERGY_FLOOR)` (negative if
    /// `V` fell at every step).
    pub worst_rise: f64,
    /// The largest speed `|ẋ_n|`, m/s.
    pub max_speed: f64,
    /// The largest step-to-step rise `|ẋ_{n+1}| − |ẋ_n|`, m/s, over the steps that start at
    /// `|ẋ_n| ≥ s₂·√(2μ/m)`, where the governor of `"governed"` takes the pull's whole power
    /// (`GOVERNOR_BAND`); `−∞` if no step starts there.
    pub worst_fast_speed_rise: f64,
    /// The state at the end, `(x, ẋ)`.
    pub end: (Vector2<f64>, Vector2<f64>),
}

/// Measures [`EnergyRun`] over `steps` RK4 steps of `dt` s from `(start, 0)`; an error if a
/// stage leaves the free space.
pub fn energy_run(
    field: &Field,
    law: &Dynamic,
    start: Vector2<f64>,
    dt: f64,
    steps: usize,
) -> Result<EnergyRun, EvalFailure> {
    energy_run_from(field, law, (start, Vector2::zeros()), dt, steps)
}

/// [`energy_run`] from the state `(x₀, ẋ₀)` = `state`.
pub fn energy_run_from(
    field: &Field,
    law: &Dynamic,
    state: (Vector2<f64>, Vector2<f64>),
    dt: f64,
    steps: usize,
) -> Result<EnergyRun, EvalFailure> {
    energy_run_toward(field, law, state, |_| None, dt, steps)
}

/// [`energy_run_from`] under [`Dynamic::force_toward`] with the nominal heading `nominal(x)`:
/// the law's gyroscopic heading force is added (`None`: none at `x`).
pub fn energy_run_toward(
    field: &Field,
    law: &Dynamic,
    state: (Vector2<f64>, Vector2<f64>),
    nominal: impl Fn(Vector2<f64>) -> Option<Vector2<f64>>,
    dt: f64,
    steps: usize,
) -> Result<EnergyRun, EvalFailure> {
    let calibration = (field.destination_stiffness(), law.scale_shift(field));
    let accel = |x: Vector2<f64>, v: Vector2<f64>| -> Result<Vector2<f64>, EvalFailure> {
        let e = eval(field, x)?;
        let d = law.damping(field, &e, v, 0.0);
        Ok(law.force_toward(calibration, &e, v, &d, nominal(x)) / law.mass())
    };
    let (mut x, mut v) = state;
    let mut last = law.energy(field, &eval(field, x)?, v);
    let (mut worst_rise, mut max_speed) = (f64::NEG_INFINITY, v.norm());
    let mut worst_fast_speed_rise = f64::NEG_INFINITY;
    let governed_speed = crate::GOVERNOR_BAND.1 * law.speed_bound();
    for _ in 0..steps {
        let speed = v.norm();
        let (k1x, k1v) = (v, accel(x, v)?);
        let (k2x, k2v) = (
            v + 0.5 * dt * k1v,
            accel(x + 0.5 * dt * k1x, v + 0.5 * dt * k1v)?,
        );
        let (k3x, k3v) = (
            v + 0.5 * dt * k2v,
            accel(x + 0.5 * dt * k2x, v + 0.5 * dt * k2v)?,
        );
        let (k4x, k4v) = (v + dt * k3v, accel(x + dt * k3x, v + dt * k3v)?);
        x += dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        v += dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        let now = law.energy(field, &eval(field, x)?, v);
        worst_rise = worst(worst_rise, (now - last) / last.max(ENERGY_FLOOR));
        max_speed = worst(max_speed, v.norm());
        if speed >= governed_speed {
            worst_fast_speed_rise = worst(worst_fast_speed_rise, v.norm() - speed);
        }
        last = now;
    }
    Ok(EnergyRun {
        worst_rise,
        max_speed,
        worst_fast_speed_rise,
        end: (x, v),
    })
}

/// Eq. `kinctrl` (the kinematic law decreases `Θ`), measured at one point: the rate
/// `dΘ/dt = ∇Θ·u` along the command `u` ([`Kinematic::velocity`]) and the paper's closed form
///
/// ```text
/// dΘ/dt = −K√(2Θ)|∇Θ| ≤ 0
/// ```
///
/// The closed form is the rate of [`crate::SpeedPolicy::Paper`] without a speed cap; every
/// policy has the same direction, so the same sign (`−s|∇Θ|`, `s` its speed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThetaRate {
    /// `Θ` at the point.
    pub eval: FieldEval,
    /// The command `u`.
    pub velocity: Vector2<f64>,
    /// `∇Θ·u`.
    pub rate: f64,
    /// `−K√(2Θ)|∇Θ|`.
    pub closed_form: f64,
}

impl ThetaRate {
    /// `|rate − closed_form| / |closed_form|` (the denominator at least 1e-300).
    #[must_use]
    pub fn relative_error(&self) -> f64 {
        (self.rate - self.closed_form).abs() / self.closed_form.abs().max(1e-300)
    }
}

/// Measures [`ThetaRate`] for `law` at `x`.
pub fn theta_rate(
    field: &Field,
    law: &Kinematic,
    x: Vector2<f64>,
) -> Result<ThetaRate, EvalFailure> {
    let e = eval(field, x)?;
    let to_goal = (x - field.workspace().destination()).norm();
    let velocity = law.velocity(&e, to_goal);
    Ok(ThetaRate {
        eval: e,
        velocity,
        rate: e.gradient.dot(&velocity),
        closed_form: -law.gain() * (2.0 * e.value).sqrt() * e.gradient.norm(),
    })
}
