//! The ranges of the parameters that the navigator's options and scenario files share (a leaf:
//! the options check them, the errors name them).

/// The range of the physical parameters: the law's gain `K`, mass `m` and `μ`, the sensor's
/// range and `ρ_min`, and the control period `h`. Outside it the closed loop cannot be
/// evaluated in `f64`: `m = 5e-324` makes the speed bound `√(2μ/m)` infinite, `ρ_min = 5e-324`
/// makes `d_min` (eq. `dmin`) and with it the switched damping `(m/d_min)|ẋ(T_n)|` overflow,
/// and `m = μ = 1e308` overflows `λ_c = 2√(mμs)` (eq. `critdamp`). Scenario files use the
/// same range.
pub const PARAMETER_RANGE: (f64, f64) = (1e-9, 1e9);

/// The smallest sensor aperture, degrees: below it `r sin(θ/2)` of `d_min` (eq. `dmin`)
/// underflows towards 0 (at 1e-320° the dynamic law returned `[-inf, nan]`).
pub const MIN_APERTURE_DEG: f64 = 1e-3;

/// The largest radius and position error (m) and speed bound (m/s) a mover may have
/// ([`crate::Mover::validate`]).
pub const MAX_MOVER: f64 = 1e6;
