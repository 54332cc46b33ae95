//! The law in use ([`Controller`]) and the commands every world shares: a recovery along a way
//! out, the halt after a refused scan, the discovery speed of the dynamic law, and the guards on
//! a state.

use harmonav_control::{Damping, Dynamic, Kinematic};
use harmonav_field::FieldEval;
use nalgebra::Vector2;

use crate::certified::Band;
use crate::error::NavError;
use crate::error::in_range;
use crate::hold::{Command, Mode};
use crate::law::Law;
use crate::options::Options;

/// The command that leads a robot at velocity `v` out of the margin band `band`: `length`
/// along the unit direction `dir` within one control period `h`, at most the kinematic law's
/// top speed `v_max`, or (dynamic law) the force whose semi-implicit step gives `v⁺` along
/// the way out at most half the speed bound `√(2μ/m)`, `f = (m/h)(v⁺ − v)`.
pub(crate) fn recovering(
    controller: &Controller,
    band: Band,
    dir: Vector2<f64>,
    length: f64,
    h: f64,
    v: Vector2<f64>,
) -> Command {
    Command {
        value: moving_along(controller, dir, length, h, v),
        mode: Mode::Recovering(band),
    }
}

/// The command of [`recovering`] without its mode: the velocity `min(length/h, v_max)·dir`
/// (kinematic), or the force `(m/h)(v⁺ − v)` with `v⁺ = min(length/h, ½√(2μ/m))·dir`
/// (dynamic). Held for `h`, the robot moves at most `length` along `dir`.
pub(crate) fn moving_along(
    controller: &Controller,
    dir: Vector2<f64>,
    length: f64,
    h: f64,
    v: Vector2<f64>,
) -> Vector2<f64> {
    match controller {
        Controller::Kinematic(law) => (length / h).min(law.v_max()) * dir,
        Controller::Dynamic(law) => {
            let next = (length / h).min(0.5 * law.speed_bound()) * dir;
            (law.mass() / h) * (next - v)
        }
    }
}

/// The discovery speed `|ẋ(T_n)|` of eq. `dissipationfun` after `command` at velocity `v`:
/// under the dynamic law a recovery ([`Mode::Recovering`]) lifts it to at least the speed
/// `|v⁺| = |v + (h/m)·f|` the command gives (semi-implicit Euler over the control period `h`).
/// The event's state is the one in which the robot leaves the band, where `Θ` is near 1 and the
/// damping may switch to `(m/d_min)|ẋ(T_n)|`; the speed recorded at the event (at rest, say)
/// would understate it. Otherwise `speed` is kept.
pub(crate) fn discovery_speed_after(
    controller: &Controller,
    command: &Command,
    v: Vector2<f64>,
    h: f64,
    speed: f64,
) -> f64 {
    match (command.mode, controller) {
        (Mode::Recovering(_), Controller::Dynamic(law)) => {
            speed.max((v + (h / law.mass()) * command.value).norm())
        }
        _ => speed,
    }
}

/// The discovery speed a scan event hands the dynamic law (eq. eventstop, docs/maths.md
/// §12.18): `|ẋ(T_n)|·max(1, d_min/d_e)`, so that the switched damping
/// `(m/d_min)·that = (m/min(d_min, d_e))|ẋ(T_n)|` stops the robot within the event's own room
/// `d_e` when that is less than `d_min`. `d_e` is the certified clearance from the robot's
/// centre to the changed shapes grown by `radius + margin` ([`crate::ScanUpdate::event_clearance`]),
/// or, in their margin band (`clearance ≤ 0`), to them grown by `radius` alone (`clearance +
/// margin`). A perceived shape may appear or grow nearer than `d_min` (a growth seen from
/// close by, or a fit range below `D + d_min`), where the paper's argument (discovery at
/// `d_min` or more) does not reach; its stopping distance is then the room the robot has.
/// The kinematic law keeps `speed`.
pub(crate) fn event_speed(controller: &Controller, speed: f64, clearance: f64, margin: f64) -> f64 {
    let Controller::Dynamic(law) = controller else {
        return speed;
    };
    let room = if clearance > 0.0 {
        clearance
    } else {
        clearance + margin
    };
    // Guard: a room of 0 or less (never accepted: the robot would touch the shape) or NaN
    // keeps the speed rather than dividing by it.
    if room > 0.0 && room < law.d_min() {
        speed * (law.d_min() / room)
    } else {
        speed
    }
}

/// Guard: `λ_c = 2√(m μ s)` (eq. `critdamp`, `s` the goal stiffness) must be finite for the
/// dynamic law's damping; a `μ` that overflows it is refused once, at construction, rather
/// than met at every command.
pub(crate) fn finite_lambda_c(law: &Dynamic, lambda_c: f64) -> Result<(), NavError> {
    if lambda_c.is_finite() {
        Ok(())
    } else {
        Err(NavError::InvalidOption {
            field: "mu",
            value: law.mu(),
        })
    }
}

/// The law in use, with its parameters (for logging and monitors: the dynamic law's energy
/// `V` and speed bound).
#[derive(Clone, Copy, Debug)]
pub enum Controller {
    /// Eq. `kinctrl`.
    Kinematic(Kinematic),
    /// Eq. `dynctrllocal` with its damping policy.
    Dynamic(Dynamic),
}

impl Controller {
    /// The same controller in a world of radius `rho` (m): the dynamic law's governed pull
    /// grows with it (`Dynamic::with_world_radius`); the kinematic law does not depend on it.
    pub(crate) fn in_world(self, rho: f64) -> Result<Self, NavError> {
        Ok(match self {
            Self::Dynamic(law) => Self::Dynamic(law.with_world_radius(rho)?),
            kinematic => kinematic,
        })
    }
}

/// One evaluation of the continuous law at a state, without side effects
/// ([`Navigator::evaluate`](crate::Navigator::evaluate)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Evaluation {
    /// The continuous law's command: the velocity `u` (kinematic law) or the force `f`
    /// (dynamic law), before the hold of [`Navigator::command`](crate::Navigator::command).
    pub command: Vector2<f64>,
    /// `Θ(x)`, `∇Θ(x)` and the descent direction `−∇Θ/|∇Θ|` over the known obstacles.
    pub field: FieldEval,
    /// The damping `λ` and its branch (dynamic law).
    pub damping: Option<Damping>,
}

/// The halting command of [`Mode::Halted`] at `(x, v)` after a refused scan, control period
/// `h`: 0 for the kinematic law, `f = −m·v/h` for the dynamic law (the velocity 0 at the end of
/// the period). The state is checked finite and kept as the last commanded one.
pub(crate) fn halted(
    controller: &Controller,
    x: Vector2<f64>,
    v: Vector2<f64>,
    h: f64,
    last: &mut Option<(Vector2<f64>, Vector2<f64>)>,
) -> Result<Command, NavError> {
    let value = match controller {
        Controller::Kinematic(_) => Vector2::zeros(),
        Controller::Dynamic(law) => -law.mass() / h * v,
    };
    let command = Command {
        value,
        mode: Mode::Halted,
    };
    if !(x.iter().chain(v.iter()).all(|c| c.is_finite())
        && command.value.iter().all(|c| c.is_finite()))
    {
        return Err(NavError::NonFiniteCommand);
    }
    *last = Some((x, v));
    Ok(command)
}

/// The law's controller for `law` under `options`, validated (each error names the field).
pub(crate) fn controller(law: &Law, options: &Options) -> Result<Controller, NavError> {
    options.validate(law)?;
    Ok(match *law {
        Law::Kinematic { gain } => {
            let law = Kinematic::new(in_range("gain", gain)?)?
                .with_speed(options.speed)
                .with_heading(options.heading);
            // `v_max` was range-checked by `validate`; the default K√2 is finite.
            Controller::Kinematic(match options.v_max {
                Some(v) => law.with_v_max(v)?,
                None => law,
            })
        }
        Law::Dynamic { mass, mu } => {
            let d_min = options.d_min()?;
            let law = Dynamic::new(in_range("mass", mass)?, in_range("mu", mu)?, d_min)?
                .with_damping(options.damping)
                .with_heading(options.heading);
            // Guard: within the ranges √(2μ/m) ≤ √2·1e9; checked, not assumed.
            let bound = law.speed_bound();
            if !(bound.is_finite() && bound > 0.0) {
                return Err(NavError::InvalidOption {
                    field: "mu",
                    value: mu,
                });
            }
            Controller::Dynamic(law)
        }
    })
}

/// The state `(x, ẋ)` a law may be evaluated at: finite coordinates, and a finite `|ẋ|²`.
/// Guard: components of 1.5e308 are finite but `|ẋ|` overflows, and with it `|ẋ(T_n)|` at the
/// next discovery and the damping `(m/d_min)|ẋ(T_n)|` (eq. `dissipationfun`).
pub(crate) fn finite_state(x: Vector2<f64>, v: Vector2<f64>) -> Result<(), NavError> {
    finite(x, "position")?;
    finite(v, "velocity")?;
    // Guard: `|ẋ|²` overflows (about 1.3e154 m/s) before `|ẋ|` does; the energy
    // `½m|ẋ|²` and every `λ(t)` after it would be infinite. The velocity is finite, so it is
    // named as out of range, not as "not finite" (issue 56, D19.2).
    if v.norm_squared().is_finite() {
        Ok(())
    } else {
        Err(NavError::InvalidOption {
            field: "velocity",
            // `hypot`, not `norm` (`√|ẋ|²`, infinite here): the speed as it is.
            value: v.x.hypot(v.y),
        })
    }
}

/// `v` with finite coordinates, else [`NavError::NotFinite`] naming `what`.
pub(crate) fn finite(v: Vector2<f64>, what: &'static str) -> Result<(), NavError> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(())
    } else {
        Err(NavError::NotFinite { what })
    }
}
