//! # harmonav-transform
//!
//! The building blocks of the navigation transformation `Phi` (definition `NavTran` of the
//! paper; construction in `docs/maths.md` §5): a `C^∞` smooth step and the two radial maps
//! that `Phi` is made of —
//!
//! - [`radial::obstacle_map`]: inside a band of width `ε` around a star-shaped obstacle, the
//!   boundary `ρ = R(θ)` is collapsed to the obstacle's centre and the outer edge of the band
//!   is left fixed (identity beyond);
//! - [`radial::outer_map`]: inside a band of width `ε_0` along the outer boundary, the
//!   boundary is sent to infinity (identity inside the band).
//!
//! Both maps keep the polar angle about their centre and increase strictly in `ρ`
//! (`∂ν/∂ρ ≥ 1`), hence are injective with `det J = ν_ρ·ν/ρ > 0`.
//!
//! This crate knows nothing of `phi_k`, sensing or time. Shapes and the assembled `Phi` with
//! automatic widths are still to come (issue 4).
//!
//! ```
//! use harmonav_transform::radial::obstacle_map;
//!
//! // A circle of radius 1 with a band of width 0.5: its boundary goes to the centre ...
//! assert_eq!(obstacle_map(1.0, 1.0, 0.0, 0.5).nu, 0.0);
//! // ... and the outer edge of the band stays where it is.
//! assert_eq!(obstacle_map(1.5, 1.0, 0.0, 0.5).nu, 1.5);
//! ```

#![warn(missing_docs)]

mod error;
pub mod nav;
pub mod radial;
pub mod random;
pub mod shape;
pub mod smooth;
pub mod workspace;

pub use error::ShapeError;
pub use nav::{Active, Mapped, NavTransform, NotFree};
pub use shape::StarShape;
pub use workspace::{RobotWorldError, Workspace, WorldError};
