//! # harmonav-potential
//!
//! The harmonic point-world potential of Loizou & Rimon, *Correct-by-Construction Navigation
//! Functions with Application to Sensor Based Robot Navigation* (section "Construction of
//! Navigation Function based on Harmonic Potentials").
//!
//! The point world is `P = R² \ {P_1..P_M}` with destination `P_d`. The potential
//!
//! ```text
//! phi_k(h) = ln|h − P_d|² − (1/k) Σ_i ln|h − P_i|²            (k > M, default k = M + 1)
//! ```
//!
//! is harmonic, has no local minima (lemma `locminfree`), tends to `+∞` far away iff `k > M`
//! (lemma `attactive`) and has exactly `M` critical points counted with multiplicity, all
//! saddles. Composed with `sigma(s) = e^s/(1+e^s)` (eq. `switch`) it becomes the point-world
//! navigation function with values in `[0, 1]`.
//!
//! This crate knows nothing of obstacle shapes, transformations or robots: it depends on
//! nalgebra and harmonav-multipole (our own, nalgebra only) alone.
//!
//! ```
//! use harmonav_potential::{PointWorld, Vector2};
//!
//! let world = PointWorld::new(Vector2::new(4.0, 0.0), vec![Vector2::new(0.0, 0.0)])?;
//! assert_eq!(world.k(), 2.0); // k = M + 1
//! let h = Vector2::new(-3.0, 0.5);
//! let value = world.varphi(h); // sigma(phi_k(h)) ∈ [0, 1]
//! assert!(value > 0.0 && value < 1.0);
//! let downhill = world.descent_direction(h).expect("h is not a critical point");
//! assert!((downhill.norm() - 1.0).abs() < 1e-12);
//! # Ok::<(), harmonav_potential::PotentialError>(())
//! ```
//!
//! Modules:
//! - [`sigma`](mod@sigma): the squashing function `sigma`, its derivatives, stable for any `s`;
//! - [`terms`]: the single harmonic term `ln|v|²`, its gradient and Hessian, guarded against
//!   overflow and `0/0`;
//! - [`world`]: [`PointWorld`] with `phi_k`, `∇phi_k`, `H(phi_k)`, `varphi`, `∇varphi`,
//!   `H(varphi)` and the destination Hessian (eq. `destphik2`, with the corrected exponent);
//! - [`batch`]: the structure-of-arrays gradient kernel for many query points;
//! - [`far`]: the obstacle sum of the hot path by fast multipoles from [`far::FAR_MIN`] points
//!   on (harmonav-multipole; docs/maths.md §15);
//! - [`critical`]: the critical points of `phi_k` as polynomial roots (a census);
//! - [`arrangements`]: the symmetric non-Morse arrangement of proposition `Morse`, and the
//!   deterministic golden-spiral world the benchmarks time.

#![warn(missing_docs)]

pub mod arrangements;
pub mod batch;
#[cfg(feature = "checks")]
pub mod checks;
pub mod critical;
mod error;
pub mod far;
pub mod fd;
pub mod named;
pub mod sigma;
pub mod terms;
pub mod world;

pub use batch::BatchGradient;
pub use critical::{CriticalKind, CriticalPoint};
pub use error::{PotentialError, Singularity};
pub use nalgebra::{Matrix2, Vector2};
pub use sigma::{ln_sigma_prime, sigma, sigma_and_prime, sigma_prime, sigma_second};
pub use world::PointWorld;
