//! The kinematic and dynamic laws.

use harmonav_field::{Field, FieldEval};
use harmonav_potential::sigma;
use nalgebra::Vector2;

use crate::damping::{Branch, Damping, DampingPolicy};

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
            "`{}`: must be finite and positive, got {:e}",
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

    /// The gain `K`.
    pub fn gain(&self) -> f64 {
        self.gain
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

/// `c` of the uphill brake of [`DampingPolicy::Auto`] ([`Damping::uphill`] `= c·λ(x)`): chosen
/// on the motion-quality benchmark (`docs/maths.md` §9: 16, 64 and 256 were measured).
pub const UPHILL_GAIN: f64 = 64.0;

/// The potential a [`Dynamic`] law descends, `Ψ`, and its gradient.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Potential {
    /// `Ψ(x) ∈ [0, 1]`.
    pub value: f64,
    /// `∇Ψ(x)`.
    pub gradient: Vector2<f64>,
}

/// Eq. (`dynctrllocal`): `f = −μ∇Θ − λ(t)ẋ` for the dynamic robot `m ẍ = f` under the paper's
/// [`DampingPolicy`]; under the default one `f = −μ∇Ψ − λ(x)ẋ` on the shaped navigation
/// function `Ψ = 1 − √(1 − Θ)` ([`Dynamic::potential`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dynamic {
    mass: f64,
    mu: f64,
    d_min: f64,
    policy: DampingPolicy,
}

impl Dynamic {
    /// The law for mass `m` (`robot.mass`), gain `μ` (`controller.mu`) and the sensor's
    /// `d_min(θ)` (eq. `dmin`), with the default [`DampingPolicy`].
    pub fn new(mass: f64, mu: f64, d_min: f64) -> Result<Self, ControlError> {
        Ok(Self {
            mass: positive(mass, "robot.mass")?,
            mu: positive(mu, "controller.mu")?,
            d_min: positive(d_min, "sensor (d_min)")?,
            policy: DampingPolicy::default(),
        })
    }

    /// The same law under the damping policy `policy`.
    #[must_use]
    pub fn with_damping(self, policy: DampingPolicy) -> Self {
        Self { policy, ..self }
    }

    /// The damping policy.
    pub fn damping_policy(&self) -> DampingPolicy {
        self.policy
    }

    /// The mass `m`.
    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// The gain `μ`.
    pub fn mu(&self) -> f64 {
        self.mu
    }

    /// The potential the law descends, with its gradient: `Θ` under [`DampingPolicy::Paper`];
    /// `Ψ = 1 − √(1 − Θ)` under [`DampingPolicy::Auto`] (`docs/maths.md` §9). `Ψ = g(Θ)` with
    /// `g` smooth and increasing on `[0, 1)`, `g(0) = 0`, `g(1) = 1`, so `Ψ` is a navigation
    /// function with the critical points of `Θ`; near the goal `Ψ ≈ Θ/2`, near the walls and
    /// the outer boundary, where `Θ` saturates, `|∇Ψ| = |∇Θ|/(2√(1 − Θ))` is far larger.
    ///
    /// Numerical guards: `Ψ = Θ/(1 + √(1 − Θ))` (no cancellation at the goal), and `1 − Θ` is
    /// `sigma(−phi)` evaluated from `phi` (exact near the walls, where `1 − Θ` computed from
    /// `Θ` would round to 0); where even that underflows (`phi ≳ 745`, within ~1e-300 m of a
    /// wall) `∇Θ` has underflowed too and `∇Ψ = 0`, as under the paper's law.
    pub fn potential(&self, eval: &FieldEval) -> Potential {
        match self.policy {
            DampingPolicy::Paper => Potential {
                value: eval.value,
                gradient: eval.gradient,
            },
            DampingPolicy::Auto => {
                // 1 − Θ = sigma(−phi), sigma's own guard (a non-positive exponent only).
                let root = sigma(-eval.phi).sqrt();
                Potential {
                    value: eval.value / (1.0 + root),
                    gradient: if root > 0.0 {
                        eval.gradient / (2.0 * root)
                    } else {
                        Vector2::zeros()
                    },
                }
            }
        }
    }

    /// Eq. (`totalenergy`): `V = μΨ + ½ m |ẋ|²` with `Ψ` the law's [`Dynamic::potential`]
    /// (`Ψ = Θ` under the paper's policy). `V̇ = −λ|ẋ|² ≤ 0` between discoveries.
    pub fn energy(&self, eval: &FieldEval, velocity: Vector2<f64>) -> f64 {
        self.energy_at(&self.potential(eval), velocity)
    }

    /// [`Dynamic::energy`] from a potential already evaluated.
    fn energy_at(&self, p: &Potential, velocity: Vector2<f64>) -> f64 {
        self.mu * p.value + 0.5 * self.mass * velocity.norm_squared()
    }

    /// Corollary `boundedvel`: `|ẋ| < √(2μ/m)`.
    pub fn speed_bound(&self) -> f64 {
        (2.0 * self.mu / self.mass).sqrt()
    }

    /// The Hessian of the law's potential at the goal, `s·I`: `s` of `Θ`
    /// (`Field::destination_stiffness`, `2/Π|P_d − P_i|^{2/k}`, the exponent established in
    /// `docs/maths.md` §2) under the paper's policy, `s/2` for `Ψ ≈ Θ/2` under `"auto"`.
    pub fn goal_stiffness(&self, field: &Field) -> f64 {
        self.goal_stiffness_for(field.destination_stiffness())
    }

    /// [`Dynamic::goal_stiffness`] for a field whose `H(Θ)(x_d)` has smallest eigenvalue `s`
    /// (a floor plan's `Θ`, where `Phi` is not the identity at the goal).
    pub fn goal_stiffness_for(&self, s: f64) -> f64 {
        match self.policy {
            DampingPolicy::Paper => s,
            DampingPolicy::Auto => 0.5 * s,
        }
    }

    /// Eq. (`critdamp`): `λ_c = 2√(m k_sp)` with the spring constant `k_sp = μ·s` of
    /// [`Dynamic::goal_stiffness`]; under the paper's policy `2√(2μm) Π|P_d − P_i|^{−1/k}`.
    /// Damping ratio 1 at the goal.
    pub fn lambda_c(&self, field: &Field) -> f64 {
        self.lambda_c_for(field.destination_stiffness())
    }

    /// [`Dynamic::lambda_c`] for the goal stiffness `s` of [`Dynamic::goal_stiffness_for`].
    pub fn lambda_c_for(&self, s: f64) -> f64 {
        2.0 * (self.mass * self.mu * self.goal_stiffness_for(s)).sqrt()
    }

    /// The damping of [`DampingPolicy::Auto`] in the `V < μ` branch:
    /// `λ(x) = 2√(mμ)·|∇Ψ|/√(2Ψ) = 2√(mμ)·|∇√(2Ψ)|` (`docs/maths.md` §9), with `Ψ` the law's
    /// [`Dynamic::potential`]. On a quadratic bowl `Ψ = ½s|x − x_d|²` it is `2√(mμs) = λ_c`,
    /// the critical damping of eq. `critdamp`; away from the goal the terminal speed `μ|∇Ψ|/λ`
    /// is `½√(μ/m)·√(2Ψ)`, where `λ_c` would over-damp wherever `|∇Ψ|` is small.
    ///
    /// Numerical guard: at the goal (`Ψ = 0`, or so close that `Ψ` underflows) the ratio is
    /// `0/0`; its limit `λ_c` is returned instead.
    pub fn lambda_auto(&self, field: &Field, eval: &FieldEval) -> f64 {
        self.lambda_auto_at(field.destination_stiffness(), &self.potential(eval))
    }

    /// [`Dynamic::lambda_auto`] from a potential already evaluated (`s`: the field's
    /// destination stiffness).
    fn lambda_auto_at(&self, s: f64, p: &Potential) -> f64 {
        let ratio = p.gradient.norm() / (2.0 * p.value).sqrt();
        if p.value > 0.0 && ratio.is_finite() {
            2.0 * (self.mass * self.mu).sqrt() * ratio
        } else {
            self.lambda_c_for(s)
        }
    }

    /// Eq. (`dissipationfun`) under the law's [`DampingPolicy`], at the state `(eval, ẋ)`, with
    /// `speed_at_discovery = |ẋ(T_n)|` the speed at the latest discovery:
    ///
    /// - `"paper"`: `λ_c` while `V < μ`, otherwise `(m/d_min)|ẋ(T_n)|`; no uphill brake;
    /// - `"auto"`: `λ =` [`Dynamic::lambda_auto`] while `V < μ`, otherwise
    ///   `max(λ(x), (m/d_min)|ẋ(T_n)|)` — at least the paper's damping, so its stopping-distance
    ///   argument (eq. `solpos`) holds a fortiori; and in both branches the uphill brake
    ///   `c·λ(x)` with `c =` [`UPHILL_GAIN`] on the velocity component that climbs `Ψ`
    ///   ([`Dynamic::force`]).
    pub fn damping(
        &self,
        field: &Field,
        eval: &FieldEval,
        velocity: Vector2<f64>,
        speed_at_discovery: f64,
    ) -> Damping {
        let s = field.destination_stiffness();
        self.damping_for(s, eval, velocity, speed_at_discovery)
    }

    /// [`Dynamic::damping`] for a field whose destination stiffness (the smallest eigenvalue
    /// of `H(Θ)(x_d)`) is `s`: the same law for any `Θ`, e.g. a floor plan's.
    pub fn damping_for(
        &self,
        s: f64,
        eval: &FieldEval,
        velocity: Vector2<f64>,
        speed_at_discovery: f64,
    ) -> Damping {
        // Ψ once per call: it serves both λ(x) and V.
        let p = self.potential(eval);
        let (own, uphill) = match self.policy {
            DampingPolicy::Paper => (self.lambda_c_for(s), 0.0),
            DampingPolicy::Auto => {
                let l = self.lambda_auto_at(s, &p);
                (l, UPHILL_GAIN * l)
            }
        };
        if self.energy_at(&p, velocity) < self.mu {
            return Damping {
                lambda: own,
                uphill,
                branch: Branch::Critical,
            };
        }
        let switched = self.mass / self.d_min * speed_at_discovery;
        Damping {
            lambda: match self.policy {
                DampingPolicy::Paper => switched,
                DampingPolicy::Auto => switched.max(own),
            },
            uphill,
            branch: Branch::Switched,
        }
    }

    /// The force `f = −μ∇Ψ − λẋ − λ_up·(ẋ·n)₊·n` with `n = ∇Ψ/|∇Ψ|` (eq. `dynctrllocal` with
    /// the uphill brake of `"auto"`; `Ψ = Θ` and `λ_up = 0` under the paper's policy). The
    /// damping force is `−Λẋ` with `Λ ⪰ 0`, so `V̇ = −λ|ẋ|² − λ_up(ẋ·n)₊² ≤ 0`. The brake acts
    /// only on the component of the velocity that climbs `Ψ` (towards an obstacle or away from
    /// the goal): the robot slides along a barrier instead of running into it and losing its
    /// speed. It is off where `n` is undefined (`∇Ψ = 0`).
    pub fn force(&self, eval: &FieldEval, velocity: Vector2<f64>, d: &Damping) -> Vector2<f64> {
        let g = self.potential(eval).gradient;
        let f = -self.mu * g - d.lambda * velocity;
        let n = g / g.norm();
        let climb = velocity.dot(&n);
        if d.uphill > 0.0 && climb > 0.0 && n.iter().all(|c| c.is_finite()) {
            f - d.uphill * climb * n
        } else {
            f
        }
    }
}
