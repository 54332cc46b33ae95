//! # harmonav-sensing
//!
//! The symmetric sensing sector `S_{r,θ}` of the paper (eq. `sensing`): the points within
//! range `r` of the robot whose direction is within `θ/2` of the axis — the robot's velocity,
//! or when it is at rest the direction it is about to move (`−∇Θ`). An obstacle is detected
//! at the first instant that any point of it lies in the sector; the test is exact against the
//! true shape (a bounding rays cast plus the local minima of the distance, never a sparse ray
//! fan). Also `d_min(θ)` (eq. `dmin`) and the obstacles known at the start (assumption
//! `localobs`).
//!
//! ```
//! use harmonav_sensing::Sector;
//! use harmonav_transform::StarShape;
//! use nalgebra::Vector2;
//!
//! let sector = Sector::new(1.0, 60f64.to_radians())?;
//! let rock = StarShape::circle(Vector2::new(0.9, 0.0), 0.1)?;
//! let (pole, axis) = (Vector2::zeros(), Vector2::new(1.0, 0.0));
//! assert!(sector.detects(pole, axis, &rock));             // straight ahead, 0.8 away
//! assert!(!sector.detects(pole, -axis, &rock));           // behind the robot
//! // d_min = min(r sin 30°, rho_min / cos 30°) = min(0.5, 0.0577) for rho_min = 0.05.
//! assert!((sector.d_min(0.05) - 0.05 / 30f64.to_radians().cos()).abs() < 1e-12);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

mod sector;

pub use sector::{Sector, Sensing, SensorError, axis, initially_known};
