//! The kinematic and dynamic laws.

use harmonav_field::{Field, FieldEval};
use nalgebra::Vector2;

/// A controller parameter that is not finite and positive (field names follow the scenario
/// format).
#[derive(Clone, Debug, PartialEq)]
pub struct ControlError {
    /// The offending field.
    pub field: &'static str,
    /// Its value.
    pub value: f64,
}

impl std::fmt::Display for ControlError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "`{}`: must be finite and positive, got {}",
            self.field, self.value
        )
    }
}

impl std::error::Error for ControlError {}

fn positive(value: f64, field: &'static str) -> Result<f64, ControlError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(ControlError { field, value })
    }
}

/// Eq. (`kinctrl`): `u = −K √(2Θ) ∇Θ/|∇Θ|` for the kinematic robot `ẋ = u`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kinematic {
    gain: f64,
}

impl Kinematic {
    /// The law with gain `K > 0` (`controller.gain`).
    pub fn new(gain: f64) -> Result<Self, ControlError> {
        Ok(Self {
            gain: positive(gain, "controller.gain")?,
        })
    }

    /// The velocity command. Uses the unit direction of the evaluation (well defined where
    /// `sigma'` underflows); `u = 0` at the goal (`Θ = 0`) and at exact critical points, where
    /// the direction is undefined. Along the law `dΘ/dt = −K √(2Θ) |∇Θ| ≤ 0`.
    pub fn velocity(&self, eval: &FieldEval) -> Vector2<f64> {
        match eval.direction {
            Some(d) => self.gain * (2.0 * eval.value).sqrt() * d,
            None => Vector2::zeros(),
        }
    }
}

/// Eq. (`dynctrllocal`): `f = −μ∇Θ − λ(t)ẋ` for the dynamic robot `m ẍ = f`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dynamic {
    mass: f64,
    mu: f64,
    d_min: f64,
}

impl Dynamic {
    /// The law for mass `m` (`robot.mass`), gain `μ` (`controller.mu`) and the sensor's
    /// `d_min(θ)` (eq. `dmin`).
    pub fn new(mass: f64, mu: f64, d_min: f64) -> Result<Self, ControlError> {
        Ok(Self {
            mass: positive(mass, "robot.mass")?,
            mu: positive(mu, "controller.mu")?,
            d_min: positive(d_min, "sensor (d_min)")?,
        })
    }

    /// The mass `m`.
    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// The gain `μ`.
    pub fn mu(&self) -> f64 {
        self.mu
    }

    /// Eq. (`totalenergy`): `V = μΘ + ½ m |ẋ|²`.
    pub fn energy(&self, theta: f64, velocity: Vector2<f64>) -> f64 {
        self.mu * theta + 0.5 * self.mass * velocity.norm_squared()
    }

    /// Corollary `boundedvel`: `|ẋ| < √(2μ/m)`.
    pub fn speed_bound(&self) -> f64 {
        (2.0 * self.mu / self.mass).sqrt()
    }

    /// Eq. (`critdamp`): `λ_c = 2√(m k_sp)` with `k_sp = μ·s` and `s` the Hessian of `Θ` at the
    /// goal (`Field::destination_stiffness`, `2/Π|P_d − P_i|^{2/k}`, the exponent established
    /// in `docs/maths.md` §2), i.e. `2√(2μm) Π|P_d − P_i|^{−1/k}`: damping ratio 1 there.
    pub fn lambda_c(&self, field: &Field) -> f64 {
        2.0 * (self.mass * self.mu * field.destination_stiffness()).sqrt()
    }

    /// Eq. (`dissipationfun`): `λ_c` while `V < μ`, otherwise `(m/d_min)|ẋ(T_n)|` with
    /// `speed_at_discovery = |ẋ(T_n)|` the speed at the latest discovery.
    pub fn damping(&self, field: &Field, energy: f64, speed_at_discovery: f64) -> f64 {
        if energy < self.mu {
            self.lambda_c(field)
        } else {
            self.mass / self.d_min * speed_at_discovery
        }
    }

    /// The force `f = −μ∇Θ − λẋ`.
    pub fn force(&self, eval: &FieldEval, velocity: Vector2<f64>, lambda: f64) -> Vector2<f64> {
        -self.mu * eval.gradient - lambda * velocity
    }
}
