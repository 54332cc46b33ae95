//! # harmonav-transform
//!
//! Star-shaped obstacles and the navigation transformation `Phi` (definition `NavTran` of the
//! paper; construction in `docs/maths.md` §5), which maps the free workspace
//! diffeomorphically onto a point world: every known obstacle collapses to its centre, the
//! outer boundary goes to infinity.
//!
//! - [`StarShape`]: circle, ellipse, rounded polygon and Fourier star with their radial
//!   function `R(θ)`, `R'(θ)`, `rho_min` and robot-radius offset;
//! - [`outline`]: the certified outline behind every distance query, a polyline with a proven
//!   chord bound, so that signed distances ([`StarShape::signed_distance_bounds`]), gaps
//!   between shapes and clearances are exact to [`DISTANCE_TOLERANCE`] (parry2d-f64 queries);
//! - [`Workspace`]: a validated world with the distances the widths need, cached;
//! - [`NavTransform`]: `Phi`, `J_Phi` and `Phi⁻¹`, with band widths and the outer stretch gain
//!   chosen automatically; built from [`radial::obstacle_map`] and [`radial::outer_map`],
//!   which keep the polar angle and increase strictly in `ρ` (`det J = ν_ρ·ν/ρ > 0`);
//! - [`index`]: a bounding-volume hierarchy over the obstacles' bounding discs (parry2d-f64's
//!   `Bvh`), so that `Phi`, the pair checks and the widths test only the obstacles near a
//!   point ([`Lookup`]; the direct loops give the same answers, bit for bit);
//! - [`random`]: seeded random valid worlds for tests and benchmarks;
//! - [`Shown`]: a user's number as an error message prints it (`1e300`, not 301 digits).
//!
//! This crate knows nothing of `phi_k`, sensing or time.
//!
//! ```
//! use harmonav_transform::{Active, NavTransform, StarShape, Workspace};
//! use nalgebra::Vector2;
//!
//! let boundary = StarShape::circle(Vector2::zeros(), 5.0)?;
//! let rock = StarShape::ellipse(Vector2::new(1.0, 0.0), [1.0, 0.5], 0.0)?;
//! let ws = Workspace::new(boundary, vec![rock], Vector2::new(-3.0, 0.0))?;
//! // Obstacle 0 known; the far-field valley radius r* = 4 m comes from the potential's side.
//! let phi = NavTransform::new(&ws, &[0], 4.0)?;
//! // Just outside the ellipse the point maps next to its centre P_1 = (1, 0).
//! let m = phi.nav_transform(Vector2::new(2.0 + 1e-6, 0.0)).unwrap();
//! assert!(matches!(m.active, Active::Obstacle { .. }) && (m.h - Vector2::new(1.0, 0.0)).norm() < 1e-5);
//! assert!(m.jacobian.determinant() > 0.0);
//! // Far from every band Phi is the identity.
//! assert_eq!(phi.nav_transform(Vector2::new(-3.0, 0.0)).unwrap().h, Vector2::new(-3.0, 0.0));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

pub mod carve;
mod distance;
mod error;
pub mod hull;
pub mod index;
pub mod nav;
pub mod outline;
pub mod radial;
pub mod random;
pub mod shape;
pub mod shown;
pub mod smooth;
pub mod workspace;

pub use carve::CARVE_CELLS;
pub use error::ShapeError;
pub use hull::HULL_CELLS;
pub use index::{DiscIndex, Lookup};
pub use nav::{Active, Mapped, NavTransform, NotFree};
pub use outline::{DISTANCE_TOLERANCE, MAX_OUTLINE_VERTICES};
pub use shape::{MAX_ANGLE, MAX_HARMONIC, MAX_LENGTH, StarShape};
pub use shown::Shown;
pub use workspace::{Admitted, RobotWorldError, Workspace, WorldError};
