//! # harmonav-field
//!
//! The navigation function of the paper over the obstacles known so far (eq. `phiseq`):
//!
//! ```text
//! Θ(x) = varphi_k(x) = sigma(phi_k(Phi(x))),      k = policy.k_for(n, ·) > n (n known obstacles)
//! ∇Θ   = sigma'(phi_k) · J_Phiᵀ ∇phi_k(Phi(x))
//! ```
//!
//! `k` follows a [`KPolicy`]: `Paper` (`k = n + 1`, exactly the paper) or `Auto` (the default,
//! `k = max(6(n + 1), 2·layer_ratio)`: near-shortest paths, and elongated workspaces crossed
//! without stiffness, `docs/maths.md` §8).
//!
//! [`Field`] keeps the obstacle memory (assumption `objpers`: [`Field::discover`] adds an
//! obstacle, nothing is ever forgotten), rebuilds `Phi` and the point world at each discovery
//! (the only allocations), and evaluates `Θ`, `∇Θ` and the unit descent direction
//! `−∇Θ/|∇Θ|` without allocating.
//!
//! `checks` (the feature `checks`) measures `Θ`'s properties (`Phi` a diffeomorphism, the limits at the goal and the
//! boundaries, theorem `isNF`'s critical points, convergence of the descent) for this crate's
//! tests and `cargo xtask verify`.
//!
//! ```
//! use std::sync::Arc;
//! use harmonav_field::Field;
//! use harmonav_transform::{StarShape, Workspace};
//! use nalgebra::Vector2;
//!
//! let boundary = StarShape::circle(Vector2::zeros(), 5.0)?;
//! let obstacles = vec![StarShape::circle(Vector2::new(0.0, 0.0), 1.0)?];
//! let ws = Arc::new(Workspace::new(boundary, obstacles, Vector2::new(3.0, 0.0))?);
//! let mut field = Field::new(ws, [])?;          // nothing known yet: k = 6 (k = "auto")
//! assert!(field.discover(0)?);                  // obstacle 0 seen: k = 6·(1 + 1)
//! assert_eq!(field.k(), 12.0);
//! let e = field.eval(Vector2::new(-3.0, 0.5))?;
//! assert!(e.value > 0.0 && e.value < 1.0);
//! assert!(e.direction.is_some());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

mod census;
#[cfg(feature = "checks")]
pub mod checks;
pub mod descent;
mod field;
mod k_policy;

pub use census::{Census, CensusPoint, CriticalType, ascending_eigenvalues, fd_hessian};
pub use field::{Critical, Field, FieldError, FieldEval};
pub use k_policy::{AUTO_FACTOR, KPolicy, LAYER_FACTOR, UnknownKPolicy, layer_ratio};
