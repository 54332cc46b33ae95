//! The kinematic and dynamic laws.

use harmonav_field::{Field, FieldEval};
use harmonav_potential::{ln_sigma_prime, sigma};
use nalgebra::Vector2;

use crate::damping::{Branch, Damping, DampingPolicy};
use crate::heading::{HEADING_CONE_DEG, HeadingPolicy, TURN_TIME, steer, turn_angle, turn_fade};
use crate::speed::{BRAKING_TIME, LINEAR_CORE, SpeedPolicy};

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

/// Eq. (`kinctrl`) with a speed policy: `u = −s(x)·∇Θ/|∇Θ|` for the kinematic robot `ẋ = u`,
/// `s = K√(2Θ)` under [`SpeedPolicy::Paper`] (the paper's law), and under the default
/// [`SpeedPolicy::Auto`] `s = min(v_max, √(2a|x − x_d|))` (full speed, then a constant
/// deceleration `a`, then a linear core of 35 µm at the default `v_max`: within any tolerance
/// of the goal in finite time; `docs/maths.md` §6). Both follow the
/// flow lines of `−∇Θ`, so both keep the paper's guarantees. Given a nominal heading
/// ([`Kinematic::velocity_toward`], on a floor plan) the default [`HeadingPolicy::Auto`]
/// turns the direction towards it within [`HEADING_CONE_DEG`] of `−∇Θ` (`Θ` still decreases,
/// at least `cos α` times as fast; `docs/maths.md` §13.3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kinematic {
    gain: f64,
    policy: SpeedPolicy,
    v_max: f64,
    heading: HeadingPolicy,
}

impl Kinematic {
    /// The law with gain `K > 0` (`controller.gain`), the default [`SpeedPolicy`] and the
    /// default top speed `v_max = K√2` (the paper law's top speed, at `Θ = 1`).
    pub fn new(gain: f64) -> Result<Self, ControlError> {
        let gain = positive(gain, "controller.gain")?;
        Ok(Self {
            gain,
            policy: SpeedPolicy::default(),
            v_max: gain * std::f64::consts::SQRT_2,
            heading: HeadingPolicy::default(),
        })
    }

    /// The same law under the heading policy `heading`.
    #[must_use]
    pub fn with_heading(self, heading: HeadingPolicy) -> Self {
        Self { heading, ..self }
    }

    /// The heading policy.
    pub fn heading_policy(&self) -> HeadingPolicy {
        self.heading
    }

    /// The same law under the speed policy `policy`.
    #[must_use]
    pub fn with_speed(self, policy: SpeedPolicy) -> Self {
        Self { policy, ..self }
    }

    /// The same law with the top speed `v_max > 0`, m/s (`controller.v_max`). Under
    /// [`SpeedPolicy::Paper`] it caps `K√(2Θ)`; the default `K√2` leaves the paper's law as is.
    pub fn with_v_max(self, v_max: f64) -> Result<Self, ControlError> {
        Ok(Self {
            v_max: positive(v_max, "controller.v_max")?,
            ..self
        })
    }

    /// The gain `K`.
    pub fn gain(&self) -> f64 {
        self.gain
    }

    /// The speed policy.
    pub fn speed_policy(&self) -> SpeedPolicy {
        self.policy
    }

    /// The top speed `v_max`, m/s: `|u| ≤ v_max` everywhere.
    pub fn v_max(&self) -> f64 {
        self.v_max
    }

    /// The braking distance of [`SpeedPolicy::Auto`], `d_b = v_max·T_b/2` (`T_b =`
    /// [`BRAKING_TIME`]), m: the speed is `v_max` beyond it.
    pub fn braking_distance(&self) -> f64 {
        0.5 * self.v_max * BRAKING_TIME
    }

    /// The radius of the linear core of [`SpeedPolicy::Auto`], `r_0 = LINEAR_CORE·d_b`
    /// ([`LINEAR_CORE`]), m: within it the speed is `λ_0·|x − x_d|`,
    /// `λ_0 = v_max/√(r_0 d_b)`.
    pub fn linear_core(&self) -> f64 {
        LINEAR_CORE * self.braking_distance()
    }

    /// The speed `s(x) ∈ [0, v_max]` at a point with the evaluation `eval` and the distance
    /// `distance = |x − x_d|` to the goal (m):
    ///
    /// - [`SpeedPolicy::Paper`]: `min(v_max, K√(2Θ))` (eq. `kinctrl`);
    /// - [`SpeedPolicy::Auto`]: `v_max` beyond [`Kinematic::braking_distance`] `d_b`,
    ///   `v_max√(distance/d_b)` within it, and `v_max·distance/√(r_0 d_b)` within
    ///   [`Kinematic::linear_core`] `r_0` (a policy beyond the paper: `docs/maths.md` §6).
    ///
    /// It is continuous, Lipschitz, positive away from the goal and `0` at the goal.
    pub fn speed(&self, eval: &FieldEval, distance: f64) -> f64 {
        match self.policy {
            SpeedPolicy::Paper => (self.gain * (2.0 * eval.value).sqrt()).min(self.v_max),
            SpeedPolicy::Auto => {
                let (d_b, r_0) = (self.braking_distance(), self.linear_core());
                if distance >= d_b {
                    self.v_max
                } else if distance >= r_0 {
                    self.v_max * (distance / d_b).sqrt()
                } else {
                    self.v_max * distance / (r_0 * d_b).sqrt()
                }
            }
        }
    }

    /// The velocity command `u = s·d` with the unit direction `d` of the evaluation (well
    /// defined where `sigma'` underflows) and the speed `s` of [`Kinematic::speed`];
    /// `distance = |x − x_d|`. `u = 0` at the goal and at exact critical points, where the
    /// direction is undefined. Along the law `dΘ/dt = −s|∇Θ| ≤ 0` (`−K√(2Θ)|∇Θ|` under the
    /// paper's policy).
    pub fn velocity(&self, eval: &FieldEval, distance: f64) -> Vector2<f64> {
        self.velocity_toward(eval, distance, None)
    }

    /// [`Kinematic::velocity`] with a nominal unit heading `nominal` (`None`: none here):
    /// `u = s·d` with `d` = [`steer`]`(−∇Θ/|∇Θ|, nominal, cos α)` under
    /// [`HeadingPolicy::Auto`] (`α` = [`HEADING_CONE_DEG`]), and `d = −∇Θ/|∇Θ|` under
    /// [`HeadingPolicy::Paper`] or without a nominal heading. Along it
    /// `dΘ/dt ≤ −s·cos α·|∇Θ| < 0` away from the critical points.
    pub fn velocity_toward(
        &self,
        eval: &FieldEval,
        distance: f64,
        nominal: Option<Vector2<f64>>,
    ) -> Vector2<f64> {
        let Some(d) = eval.direction else {
            return Vector2::zeros();
        };
        let d = match (self.heading, nominal) {
            (HeadingPolicy::Auto, Some(g)) => steer(d, g, HEADING_CONE_DEG.to_radians().cos()),
            _ => d,
        };
        self.speed(eval, distance) * d
    }
}

/// `ρ_ref` of [`Dynamic::scale_shift`], m: the outer radius of the motion-quality benchmark's
/// worlds, where [`DampingPolicy::Shaped`] was tuned. In a world of this size `"auto"` is
/// `"shaped"`; in any other it is `"shaped"` on the world scaled to this size.
pub const REFERENCE_RADIUS: f64 = 5.0;

/// `c` of the uphill brake of [`DampingPolicy::Auto`] ([`Damping::uphill`] `= c·λ(x)`): chosen
/// on the motion-quality benchmark (`docs/maths.md` §9: 16, 64 and 256 were measured).
pub const UPHILL_GAIN: f64 = 64.0;

/// `β` of [`DampingPolicy::Governed`]: the law pulls with `μ_p = βμ·max(1, ρ/ρ_ref)`
/// ([`Dynamic::pull`]). `"auto"`'s damping `λ(x) = 2√(mμ_p)|∇√(2Ψ)|` has the terminal speed
/// `½√(μ_p/m)·√(2Ψ)`; `β = 4` makes it `√(2μ/m)·√Ψ` in a world of radius `ρ_ref` or less, the
/// speed bound of corollary `boundedvel` times `√Ψ`, where `β = 1` reaches half the bound at
/// most. The governor keeps the bound ([`GOVERNOR_BAND`]).
pub const PULL_GAIN: f64 = 4.0;

/// `(s₁, s₂)` of the governor of [`DampingPolicy::Governed`]: with `s = |ẋ|/√(2μ/m)`, the
/// governor's damping is `λ_g = χ(s)·μ_p|∇Ψ|/|ẋ|`, `χ = 0` for `s ≤ s₁`, `χ = 1` for `s ≥ s₂`
/// and the smoothstep `3t² − 2t³`, `t = (s − s₁)/(s₂ − s₁)`, between. For `s ≥ s₂` the damping
/// takes at least the power `μ_p|∇Ψ||ẋ|` that the pull can add, so `d|ẋ|/dt ≤ 0` there and the
/// speed stays below `max(|ẋ(0)|, s₂√(2μ/m))`: `s₂ < 1` leaves the integrators a margin of 10 %.
pub const GOVERNOR_BAND: (f64, f64) = (0.8, 0.9);

/// `w` of [`DampingPolicy::Fast`]: the share of `Ψ` held by the goal bowl `B = q/(q + L)`;
/// the rest is the ramp `A = q/√(q² + L_A²)` ([`Dynamic::potential_for`]).
pub const FAST_BOWL_WEIGHT: f64 = 0.25;

/// `b` of [`DampingPolicy::Fast`], m: the radius of the bowl's quadratic core,
/// `q = √(r̃² + b²) − b ≈ r̃²/(2b)` within it and `≈ r̃ − b` beyond.
pub const FAST_BOWL_CORE: f64 = 0.1;

/// `L` of [`DampingPolicy::Fast`], m: the bowl `B = q/(q + L)` is half full at `q = L`. Where
/// the bowl dominates, the terminal speed of the damping `λ(x) = 2√(mμ)|∇√(2Ψ)|`,
/// `½√(μ/m)·√(2Ψ) ≈ √(μwq/(2mL))`, is the profile of a constant deceleration `μw/(4mL)`
/// (2.5 m/s² at `μ = 10`, `m = 1`).
pub const FAST_BRAKING_LENGTH: f64 = 0.25;

/// `κ` of [`DampingPolicy::Fast`]: the ramp `A = q/√(q² + L_A²)` is linear in `q` out to
/// `L_A = κ·ρ`, `ρ` the outer boundary's largest radius, and pulls with the force
/// `μ(1 − w)/L_A` there.
pub const FAST_RAMP: f64 = 2.0;

/// `(w, b, L, κ)` of [`DampingPolicy::Fast`].
const FAST: (f64, f64, f64, f64) = (
    FAST_BOWL_WEIGHT,
    FAST_BOWL_CORE,
    FAST_BRAKING_LENGTH,
    FAST_RAMP,
);

/// The shaping of [`DampingPolicy::Fast`] as a function of `ℓ = ln r̃²`: `(Ψ, ln dΨ/dℓ)` with
/// `Ψ = w·q/(q + L) + (1 − w)·q/√(q² + L_A²)`, `q = √(r̃² + b²) − b`.
///
/// `dΨ/dℓ = r̃²/(2√(r̃² + b²))·(w·L/(q + L)² + (1 − w)·L_A²/(q² + L_A²)^{3/2})`, returned as its
/// logarithm `ℓ − ln 2 − ln√(r̃² + b²) + ln(…)`, finite for every finite `ℓ` (`ℓ` itself stands
/// for `ln r̃²`, exact where `r̃²` underflows at the goal). Guards: `q` is
/// `r̃·(r̃/(√(r̃² + b²) + b))` (no cancellation for `r̃ ≪ b`, no overflow of `r̃²`; the roots are
/// `hypot`); where `r̃ = e^{ℓ/2}` overflows (`ℓ > 1419`, far past saturation) `Ψ = 1` and
/// `ln dΨ/dℓ = −∞`; where the bracket underflows (`q ≳ 1e154`) its logarithm is `−∞` too.
fn fast_shape(ell: f64, (w, b, l, l_ramp): (f64, f64, f64, f64)) -> (f64, f64) {
    let r = (0.5 * ell).exp();
    if !r.is_finite() {
        return (1.0, f64::NEG_INFINITY);
    }
    let root = r.hypot(b);
    let q = r * (r / (root + b));
    let ramp_root = q.hypot(l_ramp);
    let value = w * q / (q + l) + (1.0 - w) * q / ramp_root;
    let slope_q = w * l / ((q + l) * (q + l))
        + (1.0 - w) * (l_ramp / ramp_root) * (l_ramp / ramp_root) / ramp_root;
    let ln_slope = ell - std::f64::consts::LN_2 - root.ln() + slope_q.ln();
    (value, ln_slope)
}

/// The pull of [`DampingPolicy::Governed`], `μ_p = βμ·max(1, ρ/ρ_ref)` ([`Dynamic::pull`]).
fn governed_pull(mu: f64, rho: f64) -> f64 {
    PULL_GAIN * mu * (rho / REFERENCE_RADIUS).max(1.0)
}

/// The potential a [`Dynamic`] law descends, `Ψ`, and its gradient.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Potential {
    /// `Ψ(x) ∈ [0, 1]`.
    pub value: f64,
    /// `∇Ψ(x)`.
    pub gradient: Vector2<f64>,
}

/// What the dynamic law reads of a world's `Θ` (`docs/maths.md` §9): the destination
/// stiffness `σ` (the smallest eigenvalue of `H(Θ)(x_d)`, `Field::destination_stiffness`,
/// `FloorField::destination_stiffness`) and the scale shift `s` of `Θ_s = sigma(phi − s)`
/// ([`Dynamic::scale_shift`] of a star world's field; 0 on a floor plan, whose `Θ` is free of
/// the world's scale already: its harmonic map goes onto the unit disk). One law serves every
/// world through it ([`Dynamic::potential_for`], [`Dynamic::damping_for`],
/// [`Dynamic::force_for`], …); a pair `(σ, s)` converts into it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Calibration {
    /// `σ`, the destination stiffness of `Θ`.
    pub stiffness: f64,
    /// `s`, the scale shift.
    pub shift: f64,
}

impl From<(f64, f64)> for Calibration {
    fn from((stiffness, shift): (f64, f64)) -> Self {
        Self { stiffness, shift }
    }
}

/// Eq. (`dynctrllocal`): `f = −μ∇Θ − λ(t)ẋ` for the dynamic robot `m ẍ = f` under the paper's
/// [`DampingPolicy`]; under the default one `f = −μ_p∇Ψ − λ(x)ẋ` on the shaped navigation
/// function `Ψ = 1 − √(1 − Θ_s)` ([`Dynamic::potential`]) with the pull
/// `μ_p = 4μ·max(1, ρ/ρ_ref)` ([`Dynamic::pull`]) and a governor that keeps the speed below `0.9·√(2μ/m)`
/// ([`Dynamic::governor`]).
///
/// Preconditions, the paper's with `μ_p` for `μ`: `V(0) < μ_p` for no collision, and
/// `|ẋ(0)| < √(2μ/m)` for the speed bound (neither implies the other); the governor never lets
/// the speed grow above `max(|ẋ(0)|, 0.9·√(2μ/m))`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dynamic {
    mass: f64,
    mu: f64,
    d_min: f64,
    policy: DampingPolicy,
    world_radius: f64,
    heading: HeadingPolicy,
}

impl Dynamic {
    /// The law for mass `m` (`robot.mass`), gain `μ` (`controller.mu`) and the sensor's
    /// `d_min(θ)` (eq. `dmin`), with the default [`DampingPolicy`].
    ///
    /// Guard: `μ` must leave the pull `μ_p = βμ` ([`PULL_GAIN`]) finite, so `μ` up to
    /// `f64::MAX/β` is accepted (`μ` beyond it is refused as not finite-and-positive).
    pub fn new(mass: f64, mu: f64, d_min: f64) -> Result<Self, ControlError> {
        let mu = positive(mu, "controller.mu")?;
        positive(PULL_GAIN * mu, "controller.mu").map_err(|_| ControlError {
            field: "controller.mu",
            value: mu,
        })?;
        Ok(Self {
            mass: positive(mass, "robot.mass")?,
            mu,
            d_min: positive(d_min, "sensor (d_min)")?,
            policy: DampingPolicy::default(),
            world_radius: REFERENCE_RADIUS,
            heading: HeadingPolicy::default(),
        })
    }

    /// The same law in a world of size `ρ` (m; the outer boundary's largest radius, or a floor
    /// plan's): under [`DampingPolicy::Governed`] the pull grows with it,
    /// `μ_p = βμ·max(1, ρ/ρ_ref)` ([`Dynamic::pull`]). The default is `ρ_ref`
    /// ([`REFERENCE_RADIUS`]): no growth. The navigators set it from their workspace.
    ///
    /// Errors: `ρ` not finite and positive, or a pull that would overflow (`world_radius`).
    pub fn with_world_radius(self, rho: f64) -> Result<Self, ControlError> {
        let rho = positive(rho, "world_radius")?;
        // The governed pull, whatever the policy now: `with_damping` may switch to it later.
        positive(governed_pull(self.mu, rho), "world_radius").map_err(|_| ControlError {
            field: "world_radius",
            value: rho,
        })?;
        Ok(Self {
            world_radius: rho,
            ..self
        })
    }

    /// The world size `ρ` of [`Dynamic::with_world_radius`], m.
    pub fn world_radius(&self) -> f64 {
        self.world_radius
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

    /// The same law under the heading policy `heading` ([`Dynamic::force_toward`]).
    #[must_use]
    pub fn with_heading(self, heading: HeadingPolicy) -> Self {
        Self { heading, ..self }
    }

    /// The heading policy.
    pub fn heading_policy(&self) -> HeadingPolicy {
        self.heading
    }

    /// The direction the velocity is turned towards at a point evaluated as `eval` with the
    /// nominal unit heading `nominal`: [`steer`]`(−∇Θ/|∇Θ|, nominal, cos α)` under
    /// [`HeadingPolicy::Auto`]; `None` under [`HeadingPolicy::Paper`], without a nominal
    /// heading, and at critical points.
    fn turn_target(&self, eval: &FieldEval, nominal: Option<Vector2<f64>>) -> Option<Vector2<f64>> {
        match (self.heading, nominal, eval.direction) {
            (HeadingPolicy::Auto, Some(g), Some(d)) => {
                Some(steer(d, g, HEADING_CONE_DEG.to_radians().cos()))
            }
            _ => None,
        }
    }

    /// [`Dynamic::force_for`] plus the gyroscopic heading force `f_g = m·ω·Jẋ`,
    /// `ω = χ(Θ)·∠(ẋ, d)/τ` ([`turn_angle`], `τ` = [`TURN_TIME`], `χ` = [`turn_fade`], which
    /// makes `f_g` of higher order at the goal, `J` the quarter turn
    /// `(x, y) ↦ (−y, x)`, `d` the steered heading of [`HeadingPolicy::Auto`]; `f_g = 0`
    /// without a nominal heading or under [`HeadingPolicy::Paper`]). `ẋ·f_g = 0`, so
    /// `V̇ = −λ|ẋ|² − λ_up(ẋ·n)₊²` as without it: no collision, the speed bound and the
    /// convergence to a critical point of `Ψ` (LaSalle: `V̇ = 0` forces `ẋ = 0`, and then
    /// `f_g = 0`) are the paper's.
    pub fn force_toward(
        &self,
        calibration: impl Into<Calibration>,
        eval: &FieldEval,
        velocity: Vector2<f64>,
        d: &Damping,
        nominal: Option<Vector2<f64>>,
    ) -> Vector2<f64> {
        let f = self.force_for(calibration, eval, velocity, d);
        match self.turn_target(eval, nominal) {
            Some(target) => {
                let omega = turn_fade(eval.value) * turn_angle(velocity, target) / TURN_TIME;
                f + (self.mass * omega) * Vector2::new(-velocity.y, velocity.x)
            }
            None => f,
        }
    }

    /// The velocity `v` turned by the gyroscopic heading force over one held period `h`: the
    /// exact rotation by `χ(Θ)·∠(v, d)·min(1, h/τ)` (so `|v|` is kept, and the turn never
    /// passes `d`), `v` itself where [`Dynamic::force_toward`] adds no force.
    pub fn turned(
        &self,
        eval: &FieldEval,
        v: Vector2<f64>,
        nominal: Option<Vector2<f64>>,
        h: f64,
    ) -> Vector2<f64> {
        let Some(target) = self.turn_target(eval, nominal) else {
            return v;
        };
        let a = turn_fade(eval.value) * turn_angle(v, target) * (h / TURN_TIME).min(1.0);
        let (s, c) = a.sin_cos();
        Vector2::new(c * v.x - s * v.y, s * v.x + c * v.y)
    }

    /// The mass `m`.
    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// `d_min` of the switched damping `(m/d_min)|ẋ(T_n)|` (eq. `dissipationfun`), m: the
    /// stopping distance after a discovery.
    pub fn d_min(&self) -> f64 {
        self.d_min
    }

    /// The gain `μ` (`controller.mu`): it sets the speed bound `√(2μ/m)`.
    pub fn mu(&self) -> f64 {
        self.mu
    }

    /// The pull `μ_p` of the force `f = −μ_p∇Ψ − …` and of the energy `V = μ_pΨ + ½m|ẋ|²`:
    /// `μ_p = βμ·max(1, ρ/ρ_ref)` ([`PULL_GAIN`], `ρ` the [`Dynamic::world_radius`],
    /// `ρ_ref` = [`REFERENCE_RADIUS`]) under [`DampingPolicy::Governed`], `μ` under every other
    /// policy. The damping `λ(x)`, `λ_c` and the switch `V ≥ μ_p` use it too, so the law under
    /// `"governed"` is `"auto"`'s with `μ_p` for `μ`, exactly time-scaled by `√(μ_p/μ)`, plus
    /// the governor ([`Dynamic::governor`]). `μ_p` is constant for a given world, so
    /// `V̇ ≤ 0` holds as for any constant pull. `"auto"`'s `Ψ` is free of the world's scale,
    /// `|∇Ψ| ∝ 1/ρ`, so the growth with `ρ` keeps the force `μ_p|∇Ψ|` (newtons) of a 5 m
    /// world in any larger one: the robot accelerates from rest at the same rate in a 100 m
    /// world as in a 5 m one (`docs/maths.md` §9, part 5).
    pub fn pull(&self) -> f64 {
        match self.policy {
            DampingPolicy::Governed => governed_pull(self.mu, self.world_radius),
            _ => self.mu,
        }
    }

    /// The governor of [`DampingPolicy::Governed`] at speed `|ẋ|` where `|∇Ψ| = slope`:
    /// `λ_g = χ(|ẋ|/v_b)·μ_p·slope/|ẋ|`, `v_b = √(2μ/m)` ([`GOVERNOR_BAND`]); 0 under the
    /// other policies and below `s₁·v_b`. For `|ẋ| ≥ s₂·v_b`, `λ_g|ẋ|² = μ_p|∇Ψ||ẋ|`: the
    /// rate of change of the kinetic energy, `−μ_p∇Ψ·ẋ − (λ + λ_g)|ẋ|² − …`, is `≤ 0`, so the
    /// ball `|ẋ| ≤ s₂·v_b` is invariant between and across discoveries (a discovery changes
    /// `Ψ`, not `ẋ`; every other damping term only slows the robot). `λ_g ≥ 0` adds to `λ`, so
    /// `V̇ ≤ 0` holds.
    ///
    /// Numerical guard: `|ẋ| ≥ s₁·v_b > 0` wherever `χ > 0`, so the quotient is finite; a
    /// slope that is not finite gives 0 (the force is not finite either there, and the field
    /// refuses such points first).
    pub fn governor(&self, slope: f64, velocity: Vector2<f64>) -> f64 {
        if self.policy != DampingPolicy::Governed || !slope.is_finite() {
            return 0.0;
        }
        let speed = velocity.norm();
        let (s1, s2) = GOVERNOR_BAND;
        let t = ((speed / self.speed_bound() - s1) / (s2 - s1)).clamp(0.0, 1.0);
        if t == 0.0 {
            return 0.0;
        }
        t * t * (3.0 - 2.0 * t) * self.pull() * slope / speed
    }

    /// `s` of [`DampingPolicy::Auto`], the shift that makes `Θ_s = sigma(phi − s)` free of the
    /// world's scale: `s = (1 − n/k)·ln(ρ²/ρ_ref²)`, `n` the known obstacles, `ρ` the outer
    /// boundary's largest radius and `ρ_ref` = [`REFERENCE_RADIUS`]. Scaling a world by `α`
    /// scales `Phi` by `α` and adds `(1 − n/k)·ln α²` to `phi_k` (its `ln|h − P_d|²` term
    /// gains `ln α²`, each of the `n` terms `−(1/k)·ln|h − P_i|²` loses `ln α²/k`), which `s`
    /// takes away. `s` is constant between discoveries, so `Ψ` is a fixed function there and
    /// `V̇ ≤ 0` holds. Under [`DampingPolicy::Fast`] it is `ln ρ²` (ρ in metres), which sets the
    /// length `L_A = κρ` of its ramp ([`Dynamic::potential_for`]); 0 under the other policies.
    pub fn scale_shift(&self, field: &Field) -> f64 {
        match self.policy {
            DampingPolicy::Fast => {
                let rho = field.workspace().boundary().radius_bounds().1;
                rho.powi(2).ln()
            }
            DampingPolicy::Auto | DampingPolicy::Governed => {
                let n = field.known().len() as f64;
                let rho = field.workspace().boundary().radius_bounds().1;
                (1.0 - n / field.k()) * (rho / REFERENCE_RADIUS).powi(2).ln()
            }
            DampingPolicy::Paper | DampingPolicy::Shaped => 0.0,
        }
    }

    /// The potential the law descends, with its gradient: `Θ` under [`DampingPolicy::Paper`];
    /// `Ψ = 1 − √(1 − Θ)` under [`DampingPolicy::Shaped`] (`docs/maths.md` §9); the same on
    /// `Θ_s = sigma(phi − s)` ([`Dynamic::scale_shift`]) under [`DampingPolicy::Auto`]; the
    /// bowl and ramp of [`Dynamic::potential_for`] under [`DampingPolicy::Fast`].
    /// `Ψ = g(Θ)` with `g` smooth and increasing on `[0, 1)`, `g(0) = 0`, `g(1) = 1` (also
    /// `Θ ↦ Θ_s = sigma(logit Θ − s)` is), so `Ψ` is a navigation function with the critical
    /// points of `Θ`; near the goal `Ψ ≈ Θ_s/2 ≈ e^{−s}Θ/2`, near the walls and the outer
    /// boundary, where `Θ` saturates, `|∇Ψ| = |∇Θ_s|/(2√(1 − Θ_s))` is far larger.
    ///
    /// Numerical guards: `Ψ = Θ_s/(1 + √(1 − Θ_s))` (no cancellation at the goal), and
    /// `1 − Θ_s` is `sigma(s − phi)` evaluated from `phi` (exact near the walls, where
    /// `1 − Θ_s` computed from `Θ_s` would round to 0); `∇Θ_s = ∇Θ·sigma'(phi − s)/sigma'(phi)`
    /// with the ratio taken in log space (`ln_sigma_prime`, finite for every finite argument),
    /// and `∇Θ_s = 0` where `∇Θ = 0` (at the goal `phi = −∞` and the ratio is `∞ − ∞`; where
    /// `sigma'(phi)` underflows, `phi ≳ 745`, within ~1e-300 m of a wall, `∇Θ` has underflowed
    /// too and `∇Ψ = 0`, as under the paper's law).
    pub fn potential(&self, field: &Field, eval: &FieldEval) -> Potential {
        self.potential_for(self.calibration(field), eval)
    }

    /// The [`Calibration`] of a star world's field under this law: its destination stiffness
    /// and [`Dynamic::scale_shift`].
    pub fn calibration(&self, field: &Field) -> Calibration {
        Calibration {
            stiffness: field.destination_stiffness(),
            shift: self.scale_shift(field),
        }
    }

    /// [`Dynamic::potential`] for the destination stiffness `sigma` (the smallest eigenvalue of
    /// `H(Θ)(x_d)`, `Field::destination_stiffness`) and the scale shift `shift` (the
    /// [`Dynamic::scale_shift`] of the field that made `eval`; 0 for a `Θ` that is free of the
    /// world's scale already, such as a floor plan's, whose harmonic map goes onto the unit
    /// disk). `sigma` serves [`DampingPolicy::Fast`] only.
    ///
    /// Under [`DampingPolicy::Fast`] (`docs/maths.md` §9, "fast"),
    ///
    /// ```text
    /// Ψ = w·q/(q + L) + (1 − w)·q/√(q² + L_A²),   q = √(r̃² + b²) − b,
    /// r̃² = e^{phi − c} = (2/σ)·Θ/(1 − Θ),          c = ln(σ/2),   L_A = κρ = κ·e^{shift/2},
    /// ```
    ///
    /// (`w, b, L, κ` = [`FAST_BOWL_WEIGHT`], [`FAST_BOWL_CORE`], [`FAST_BRAKING_LENGTH`],
    /// [`FAST_RAMP`]; `ρ` the outer radius, [`Dynamic::scale_shift`]). Near the goal
    /// `Θ ≈ e^{phi} ≈ ½σ|x − x_d|²`, so `r̃ → |x − x_d|`: a length in metres (`r̃(αx) = α·r̃(x)`
    /// in a world scaled by `α`). The first term is a goal bowl a braking distance wide, the
    /// second a ramp linear in `q` out to `L_A`, twice the world's radius. `r̃` is a smooth
    /// increasing function of `Θ` and `Ψ` of `r̃`, so `Ψ = g(Θ)` with `g` smooth and strictly
    /// increasing on `[0, 1)`, `g(0) = 0`, `g(1) = 1` (`1 − Ψ ≈ wL/r̃ ∝ √(1 − Θ)` at the walls,
    /// as under `"shaped"`): a navigation function with the critical points of `Θ`. Its gradient
    /// is `(dΨ/dℓ)·∇phi`, `ℓ = phi − c`, `∇phi = ∇Θ/sigma'(phi)`. On a floor plan (`shift = 0`)
    /// `L_A = κ` m.
    ///
    /// Numerical guards of `"fast"`: `(dΨ/dℓ)/sigma'(phi)` is one exponential of a sum of
    /// logarithms (`fast_shape`, `ln_sigma_prime`), finite for every finite `phi` (at the goal,
    /// `phi → −∞`, `dΨ/dℓ` vanishes and `1/sigma'` blows up, and the sum is their finite ratio;
    /// at saturation it is `~e^{phi/2}`, finite up to `phi ≈ 1400`, where `∇Θ` has long
    /// underflowed); where `∇Θ = 0` (the goal, or `phi ≳ 745`) `∇Ψ = 0`.
    pub fn potential_for(
        &self,
        calibration: impl Into<Calibration>,
        eval: &FieldEval,
    ) -> Potential {
        let Calibration {
            stiffness: sigma_d,
            shift,
        } = calibration.into();
        if self.policy == DampingPolicy::Paper {
            return Potential {
                value: eval.value,
                gradient: eval.gradient,
            };
        }
        if self.policy != DampingPolicy::Fast {
            return self.shaped_potential(shift, eval);
        }
        let (w, b, l, kappa) = FAST;
        let c = (0.5 * sigma_d).ln();
        let (value, ln_slope) = fast_shape(eval.phi - c, (w, b, l, kappa * (0.5 * shift).exp()));
        let gradient = if eval.gradient == Vector2::zeros() {
            Vector2::zeros()
        } else {
            eval.gradient * (ln_slope - ln_sigma_prime(eval.phi)).exp()
        };
        Potential { value, gradient }
    }

    /// `Ψ = 1 − √(1 − Θ_s)` on `Θ_s = sigma(phi − s)`, `s = shift` under
    /// [`DampingPolicy::Auto`] and 0 under [`DampingPolicy::Shaped`] (the guards of
    /// [`Dynamic::potential`]).
    fn shaped_potential(&self, shift: f64, eval: &FieldEval) -> Potential {
        let s = if matches!(self.policy, DampingPolicy::Auto | DampingPolicy::Governed) {
            shift
        } else {
            0.0
        };
        let (theta, gradient) = if s == 0.0 {
            (eval.value, eval.gradient)
        } else if eval.gradient == Vector2::zeros() {
            (sigma(eval.phi - s), eval.gradient)
        } else {
            let ratio = (ln_sigma_prime(eval.phi - s) - ln_sigma_prime(eval.phi)).exp();
            (sigma(eval.phi - s), eval.gradient * ratio)
        };
        // 1 − Θ_s = sigma(s − phi), sigma's own guard (a non-positive exponent only).
        let root = sigma(s - eval.phi).sqrt();
        Potential {
            value: theta / (1.0 + root),
            gradient: if root > 0.0 {
                gradient / (2.0 * root)
            } else {
                Vector2::zeros()
            },
        }
    }

    /// Eq. (`totalenergy`): `V = μ_pΨ + ½ m |ẋ|²` with `Ψ` the law's [`Dynamic::potential`]
    /// (`Ψ = Θ` under the paper's policy) and `μ_p` its [`Dynamic::pull`] (`μ` but under
    /// `"governed"`). `V̇ = −λ|ẋ|² ≤ 0` between discoveries.
    pub fn energy(&self, field: &Field, eval: &FieldEval, velocity: Vector2<f64>) -> f64 {
        self.energy_at(&self.potential(field, eval), velocity)
    }

    /// [`Dynamic::energy`] of a field with destination stiffness `s` and scale shift `shift`
    /// ([`Dynamic::potential_for`]: a floor plan's `Θ`, whose shift is 0):
    /// `V = μ_pΨ + ½ m |ẋ|²`.
    pub fn energy_for(
        &self,
        calibration: impl Into<Calibration>,
        eval: &FieldEval,
        velocity: Vector2<f64>,
    ) -> f64 {
        self.energy_at(&self.potential_for(calibration, eval), velocity)
    }

    /// [`Dynamic::energy`] from a potential already evaluated.
    fn energy_at(&self, p: &Potential, velocity: Vector2<f64>) -> f64 {
        self.pull() * p.value + 0.5 * self.mass * velocity.norm_squared()
    }

    /// Corollary `boundedvel`: `|ẋ| < √(2μ/m)` (from `V < μ` where the pull is `μ`; under
    /// [`DampingPolicy::Governed`] from the governor, [`Dynamic::governor`]).
    pub fn speed_bound(&self) -> f64 {
        (2.0 * self.mu / self.mass).sqrt()
    }

    /// The Hessian of the law's potential at the goal, `s·I`: `s` of `Θ`
    /// (`Field::destination_stiffness`, `2/Π|P_d − P_i|^{2/k}`, the exponent established in
    /// `docs/maths.md` §2) under the paper's policy, `s/2` for `Ψ ≈ Θ/2` under `"shaped"`, and
    /// `e^{−s_c}·s/2` for `Ψ ≈ Θ_s/2 ≈ e^{−s_c}Θ/2` under `"auto"` (`s_c` the
    /// [`Dynamic::scale_shift`]: `sigma(phi − s_c) ≈ e^{phi − s_c}` as `phi → −∞`), and
    /// `(w/L + (1 − w)/L_A)/b` under `"fast"`, whatever the world
    /// (`Ψ ≈ (w/L + (1 − w)/L_A)·q`, `q ≈ r̃²/(2b)`, `r̃² ≈ |x − x_d|²`).
    pub fn goal_stiffness(&self, field: &Field) -> f64 {
        let c = self.calibration(field);
        self.goal_stiffness_for(c.stiffness, c.shift)
    }

    /// [`Dynamic::goal_stiffness`] for a field whose `H(Θ)(x_d)` has smallest eigenvalue `s`
    /// (a floor plan's `Θ`, where `Phi` is not the identity at the goal) and whose scale shift
    /// is `shift` ([`Dynamic::potential_for`]).
    pub fn goal_stiffness_for(&self, s: f64, shift: f64) -> f64 {
        match self.policy {
            DampingPolicy::Paper => s,
            DampingPolicy::Shaped => 0.5 * s,
            DampingPolicy::Auto | DampingPolicy::Governed => 0.5 * s * (-shift).exp(),
            DampingPolicy::Fast => {
                // Ψ ≈ (w/L + (1 − w)/L_A)·q, q ≈ r̃²/(2b), r̃² ≈ xᵀH(Θ)x/σ: H(Ψ) = that·H(Θ)/(bσ).
                let (w, b, l, kappa) = FAST;
                (w / l + (1.0 - w) / (kappa * (0.5 * shift).exp())) / b
            }
        }
    }

    /// Eq. (`critdamp`): `λ_c = 2√(m k_sp)` with the spring constant `k_sp = μ_p·s` of
    /// [`Dynamic::goal_stiffness`] (`μ_p` the [`Dynamic::pull`], `μ` but under `"governed"`);
    /// under the paper's policy `2√(2μm) Π|P_d − P_i|^{−1/k}`.
    /// Damping ratio 1 at the goal.
    pub fn lambda_c(&self, field: &Field) -> f64 {
        let c = self.calibration(field);
        self.lambda_c_for(c.stiffness, c.shift)
    }

    /// [`Dynamic::lambda_c`] for the goal stiffness `s` and the scale shift `shift` of
    /// [`Dynamic::goal_stiffness_for`].
    pub fn lambda_c_for(&self, s: f64, shift: f64) -> f64 {
        2.0 * (self.mass * self.pull() * self.goal_stiffness_for(s, shift)).sqrt()
    }

    /// The damping of [`DampingPolicy::Auto`] in the `V < μ_p` branch:
    /// `λ(x) = 2√(mμ_p)·|∇Ψ|/√(2Ψ) = 2√(mμ_p)·|∇√(2Ψ)|` (`docs/maths.md` §9), with `Ψ` the
    /// law's [`Dynamic::potential`] and `μ_p` its [`Dynamic::pull`]. On a quadratic bowl
    /// `Ψ = ½s|x − x_d|²` it is `2√(mμ_p s) = λ_c`, the critical damping of eq. `critdamp`;
    /// away from the goal the terminal speed `μ_p|∇Ψ|/λ` is `½√(μ_p/m)·√(2Ψ)`, where `λ_c`
    /// would over-damp wherever `|∇Ψ|` is small.
    ///
    /// Numerical guard: at the goal (`Ψ = 0`, or so close that `Ψ` underflows) the ratio is
    /// `0/0`; its limit `λ_c` is returned instead.
    pub fn lambda_auto(&self, field: &Field, eval: &FieldEval) -> f64 {
        let Calibration {
            stiffness: s,
            shift,
        } = self.calibration(field);
        self.lambda_auto_at(s, shift, &self.potential_for((s, shift), eval))
    }

    /// [`Dynamic::lambda_auto`] from a potential already evaluated (`s`: the field's
    /// destination stiffness, `shift` its scale shift).
    fn lambda_auto_at(&self, s: f64, shift: f64, p: &Potential) -> f64 {
        let ratio = p.gradient.norm() / (2.0 * p.value).sqrt();
        if p.value > 0.0 && ratio.is_finite() {
            2.0 * (self.mass * self.pull()).sqrt() * ratio
        } else {
            self.lambda_c_for(s, shift)
        }
    }

    /// Eq. (`dissipationfun`) under the law's [`DampingPolicy`], at the state `(eval, ẋ)`, with
    /// `speed_at_discovery = |ẋ(T_n)|` the speed at the latest discovery:
    ///
    /// - `"paper"`: `λ_c` while `V < μ`, otherwise `(m/d_min)|ẋ(T_n)|`; no uphill brake
    ///   (`μ` stands for the pull `μ_p` of [`Dynamic::pull`] under every policy);
    /// - `"governed"`: `"auto"`'s with the pull `μ_p` for `μ` ([`Dynamic::pull`]), plus the
    ///   governor `λ_g` ([`Dynamic::governor`]) in both branches;
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
        self.damping_for(self.calibration(field), eval, velocity, speed_at_discovery)
    }

    /// [`Dynamic::damping`] for a field whose destination stiffness (the smallest eigenvalue
    /// of `H(Θ)(x_d)`) is `s` and whose scale shift is `shift` ([`Dynamic::potential_for`]):
    /// the same law for any `Θ`, e.g. a floor plan's.
    pub fn damping_for(
        &self,
        calibration: impl Into<Calibration>,
        eval: &FieldEval,
        velocity: Vector2<f64>,
        speed_at_discovery: f64,
    ) -> Damping {
        let Calibration {
            stiffness: s,
            shift,
        } = calibration.into();
        // Ψ once per call: it serves both λ(x) and V.
        let p = self.potential_for((s, shift), eval);
        let (own, uphill) = match self.policy {
            DampingPolicy::Paper => (self.lambda_c_for(s, shift), 0.0),
            DampingPolicy::Shaped
            | DampingPolicy::Auto
            | DampingPolicy::Fast
            | DampingPolicy::Governed => {
                let l = self.lambda_auto_at(s, shift, &p);
                (l, UPHILL_GAIN * l)
            }
        };
        let governor = self.governor(p.gradient.norm(), velocity);
        if self.energy_at(&p, velocity) < self.pull() {
            return Damping {
                lambda: own + governor,
                uphill,
                branch: Branch::Critical,
            };
        }
        let switched = self.mass / self.d_min * speed_at_discovery;
        Damping {
            lambda: match self.policy {
                DampingPolicy::Paper => switched,
                DampingPolicy::Shaped
                | DampingPolicy::Auto
                | DampingPolicy::Fast
                | DampingPolicy::Governed => switched.max(own) + governor,
            },
            uphill,
            branch: Branch::Switched,
        }
    }

    /// The force `f = −μ_p∇Ψ − λẋ − λ_up·(ẋ·n)₊·n` with `n = ∇Ψ/|∇Ψ|` (eq. `dynctrllocal` with
    /// the uphill brake of `"auto"`; `Ψ = Θ`, `μ_p = μ` and `λ_up = 0` under the paper's
    /// policy; `μ_p` the [`Dynamic::pull`]). The
    /// damping force is `−Λẋ` with `Λ ⪰ 0`, so `V̇ = −λ|ẋ|² − λ_up(ẋ·n)₊² ≤ 0`. The brake acts
    /// only on the component of the velocity that climbs `Ψ` (towards an obstacle or away from
    /// the goal): the robot slides along a barrier instead of running into it and losing its
    /// speed. It is off where `n` is undefined (`∇Ψ = 0`).
    pub fn force(
        &self,
        field: &Field,
        eval: &FieldEval,
        velocity: Vector2<f64>,
        d: &Damping,
    ) -> Vector2<f64> {
        self.force_for(self.calibration(field), eval, velocity, d)
    }

    /// [`Dynamic::force`] for the destination stiffness and scale shift `(sigma, shift)` of
    /// [`Dynamic::potential_for`].
    pub fn force_for(
        &self,
        calibration: impl Into<Calibration>,
        eval: &FieldEval,
        velocity: Vector2<f64>,
        d: &Damping,
    ) -> Vector2<f64> {
        let g = self.potential_for(calibration, eval).gradient;
        let f = -self.pull() * g - d.lambda * velocity;
        let n = g / g.norm();
        let climb = velocity.dot(&n);
        if d.uphill > 0.0 && climb > 0.0 && n.iter().all(|c| c.is_finite()) {
            f - d.uphill * climb * n
        } else {
            f
        }
    }
}
