//! The radial maps of the navigation transformation and their Jacobian.
//!
//! Both maps act along the ray of angle `θ` from a centre `q`: a point at distance `ρ` is sent
//! to distance `ν(ρ, θ)` on the same ray. With `u = (cos θ, sin θ)`, `u⊥ = (−sin θ, cos θ)`:
//!
//! ```text
//! Phi(x) = q + ν u,    J = ν_ρ u uᵀ + (ν_θ/ρ) u u⊥ᵀ + (ν/ρ) u⊥ u⊥ᵀ,    det J = ν_ρ ν/ρ
//! ```

use nalgebra::{Matrix2, Vector2};

use crate::smooth::beta;

/// The distance `ν` along the ray and its partial derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Radial {
    /// `ν(ρ, θ)`: the image's distance from the centre (`+∞` on the outer boundary).
    pub nu: f64,
    /// `∂ν/∂ρ` (≥ 1 for both maps).
    pub nu_rho: f64,
    /// `∂ν/∂θ = ν_R·R'(θ)` through the boundary radius.
    pub nu_theta: f64,
}

impl Radial {
    /// The identity `ν = ρ`.
    pub fn identity(rho: f64) -> Self {
        Self {
            nu: rho,
            nu_rho: 1.0,
            nu_theta: 0.0,
        }
    }

    /// `J = ν_ρ u uᵀ + (ν_θ/ρ) u u⊥ᵀ + (ν/ρ) u⊥ u⊥ᵀ` at a point at distance `rho > 0` in the
    /// unit direction `u` from the centre.
    pub fn jacobian(&self, u: Vector2<f64>, rho: f64) -> Matrix2<f64> {
        let perp = Vector2::new(-u.y, u.x);
        self.nu_rho * u * u.transpose()
            + (self.nu_theta / rho) * u * perp.transpose()
            + (self.nu / rho) * perp * perp.transpose()
    }

    /// `det J = ν_ρ·ν/ρ`.
    pub fn det(&self, rho: f64) -> f64 {
        self.nu_rho * self.nu / rho
    }
}

/// Obstacle map: collapses the boundary `ρ = R(θ)` of a star-shaped obstacle to its centre
/// within the band `R ≤ ρ ≤ R + ε`, identity beyond (`docs/maths.md` §5).
///
/// ```text
/// t   = (ρ − R)/ε                      0 at the boundary, 1 at the outer edge
/// ν   = t(R + ε) + R·beta(t)·(1 − t)
/// ν_ρ = [(R + ε) + R(beta'(t)(1 − t) − beta(t))]/ε   ≥ 1
/// ν_R = t + beta(t)(1 − t) − ν_ρ,      ν_θ = ν_R·R'(θ)
/// ```
///
/// `ν(R) = 0` exactly, `ν − ρ = −R(1 − t)(1 − beta(t))` is flat at `t = 1`, and `ν_ρ ≥ 1`
/// because `beta'(1 − t) ≥ 0` and `beta ≤ 1`. Arguments: `rho ≥ R` (points inside the obstacle
/// are not in the workspace and get `ν = 0`), `r = R(θ) > 0`, `dr = R'(θ)`, `eps > 0`.
pub fn obstacle_map(rho: f64, r: f64, dr: f64, eps: f64) -> Radial {
    let t = (rho - r) / eps;
    if t >= 1.0 {
        return Radial::identity(rho);
    }
    let t = t.max(0.0);
    let (b, db) = beta(t);
    let nu = t * (r + eps) + r * b * (1.0 - t);
    let nu_rho = ((r + eps) + r * (db * (1.0 - t) - b)) / eps;
    let nu_r = t + b * (1.0 - t) - nu_rho;
    Radial {
        nu,
        nu_rho,
        nu_theta: nu_r * dr,
    }
}

/// Outer map: sends the outer boundary `ρ = R_0(θ)` to infinity within the band
/// `R_0 − ε_0 ≤ ρ < R_0`, identity inside (`docs/maths.md` §5).
///
/// ```text
/// s   = (ρ − R_0 + ε_0)/ε_0            0 at the inner edge, 1 at the wall
/// ν   = ρ + A·beta(s)·s/(1 − s)        → ∞ like A ε_0/(R_0 − ρ)
/// ν_ρ = 1 + (A/ε_0)[beta'(s) s/(1 − s) + beta(s)/(1 − s)²]   ≥ 1
/// ν_R0 = 1 − ν_ρ,      ν_θ = ν_R0·R_0'(θ)
/// ```
///
/// The stretch is rational, not exponential, so it stays finite until `ρ` reaches `R_0`
/// (an exponential overflows once `R_0 − ρ < 1e-3`). At and beyond the wall `ν = +∞`.
/// Arguments: `r0 = R_0(θ) > 0`, `dr0 = R_0'(θ)`, `eps0 > 0`, `gain = A > 0`.
pub fn outer_map(rho: f64, r0: f64, dr0: f64, eps0: f64, gain: f64) -> Radial {
    let s = (rho - r0 + eps0) / eps0;
    if s <= 0.0 {
        return Radial::identity(rho);
    }
    if s >= 1.0 {
        return Radial {
            nu: f64::INFINITY,
            nu_rho: f64::INFINITY,
            nu_theta: 0.0,
        };
    }
    let (b, db) = beta(s);
    let gap = 1.0 - s;
    let nu = rho + gain * b * s / gap;
    let nu_rho = 1.0 + (gain / eps0) * (db * s / gap + b / (gap * gap));
    Radial {
        nu,
        nu_rho,
        nu_theta: (1.0 - nu_rho) * dr0,
    }
}
