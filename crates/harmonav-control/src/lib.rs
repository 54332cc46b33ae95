//! # harmonav-control
//!
//! The two control laws of the paper as pure functions of the state and the field — no
//! simulator inside:
//!
//! - [`Kinematic`] (eq. `kinctrl`): `u = −K √(2Θ) ∇Θ/|∇Θ|` for `ẋ = u` under
//!   [`SpeedPolicy::Paper`]; the default [`SpeedPolicy::Auto`] keeps the direction and moves at
//!   `s = min(v_max, √(2a|x − x_d|))` with a linear core at the goal, arriving within any
//!   tolerance in finite time; given a nominal heading (on a floor plan, the shortest path's
//!   direction), the default [`HeadingPolicy::Auto`] turns the direction towards it within
//!   [`HEADING_CONE_DEG`] of `−∇Θ` ([`steer`]; `docs/maths.md` §13.3);
//! - [`Dynamic`] (eq. `dynctrllocal`): `f = −μ∇Θ − λ(t)ẋ` for `m ẍ = f`, with the critical
//!   damping `λ_c` (eq. `critdamp`) while the energy `V = μΘ + ½m|ẋ|²` (eq. `totalenergy`)
//!   stays below `μ`, and `(m/d_min)|ẋ(T_n)|` otherwise (eq. `dissipationfun`); the speed
//!   bound `√(2μ/m)` (corollary `boundedvel`). That is [`DampingPolicy::Paper`];
//!   [`DampingPolicy::Shaped`] descends `Ψ = 1 − √(1 − Θ)` and damps with
//!   `λ(x) = 2√(mμ)|∇Ψ|/√(2Ψ)`, which equals `λ_c` at the goal and does not over-damp far from
//!   it;
//!   [`DampingPolicy::Auto`] does the same on `Θ_s = sigma(phi − s)`, free of the world's
//!   scale ([`Dynamic::scale_shift`]); the default [`DampingPolicy::Governed`] is `"auto"` with
//!   the pull `4μ·max(1, ρ/5 m)` ([`Dynamic::pull`], `ρ` the world's radius), whose damping's
//!   terminal speed spans the whole bound
//!   `√(2μ/m)`, and a governor that keeps the speed below `0.9·√(2μ/m)`.
//!
//! `checks` (the feature `checks`) measures the laws' properties (corollary `critdamp` at the goal, eq.
//! `totalenergy` and corollary `boundedvel` along the closed loop, eq. `kinctrl`'s decrease of
//! `Θ`) for this crate's tests and `cargo xtask verify`.
//!
//! ```
//! use std::sync::Arc;
//! use harmonav_control::{Branch, DampingPolicy, Dynamic, Kinematic, SpeedPolicy};
//! use harmonav_field::Field;
//! use harmonav_transform::{StarShape, Workspace};
//! use nalgebra::Vector2;
//!
//! let ws = Workspace::new(
//!     StarShape::circle(Vector2::zeros(), 5.0)?,
//!     vec![StarShape::circle(Vector2::new(0.0, 0.0), 1.0)?],
//!     Vector2::new(3.0, 0.0),
//! )?;
//! let field = Field::all_known(Arc::new(ws))?;
//! let x = Vector2::new(-3.0, 0.5);
//! let eval = field.eval(x)?;
//! let to_goal = (x - field.workspace().destination()).norm();
//! let paper = Kinematic::new(1.0)?.with_speed(SpeedPolicy::Paper);
//! let u = paper.velocity(&eval, to_goal);               // speed K√(2Θ) ≤ √2
//! assert!(u.norm() > 0.0 && u.norm() < 2f64.sqrt());
//! let auto = Kinematic::new(1.0)?;                      // the default: v_max = K√2 until d_b
//! let w = auto.velocity(&eval, to_goal);
//! assert!((w.norm() - auto.v_max()).abs() < 1e-12 && to_goal > auto.braking_distance());
//! assert!((w.normalize() - u.normalize()).norm() < 1e-12); // the same flow line
//! let law = Dynamic::new(1.0, 10.0, 0.05)?;             // m = 1 kg, μ = 10, d_min = 0.05 m
//! assert!((law.speed_bound() - 20f64.sqrt()).abs() < 1e-12);
//! let paper = law.with_damping(DampingPolicy::Paper);
//! let d = paper.damping(&field, &eval, Vector2::zeros(), 0.0);
//! assert_eq!((d.lambda, d.branch), (paper.lambda_c(&field), Branch::Critical)); // V < μ: λ_c
//! let d = law.damping(&field, &eval, Vector2::zeros(), 0.0); // the default, "governed"
//! assert_eq!(d.lambda, law.lambda_auto(&field, &eval)); // the governor is off at rest
//! assert_eq!(law.pull(), 4.0 * law.mu());
//! let f = law.force(&field, &eval, Vector2::zeros(), &d);
//! assert!(f.dot(&eval.gradient) < 0.0);                 // pushes downhill
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

#[cfg(feature = "checks")]
pub mod checks;
mod damping;
mod heading;
mod laws;
mod speed;

pub use damping::{Branch, Damping, DampingPolicy, UnknownDampingPolicy};
pub use heading::{
    HEADING_CONE_DEG, HeadingPolicy, TURN_FADE, TURN_TIME, UnknownHeadingPolicy, steer, turn_angle,
    turn_fade,
};
pub use laws::{
    Calibration, ControlError, Dynamic, FAST_BOWL_CORE, FAST_BOWL_WEIGHT, FAST_BRAKING_LENGTH,
    FAST_RAMP, GOVERNOR_BAND, Kinematic, PULL_GAIN, Potential, REFERENCE_RADIUS, UPHILL_GAIN,
};
pub use speed::{BRAKING_TIME, LINEAR_CORE, SpeedPolicy, UnknownSpeedPolicy};
