//! # harmonav-floorplan
//!
//! Navigation functions on floor plans (issue 25, part 2; docs/maths.md §13): any polygonal
//! free space with polygonal holes (walls on the outer ring, U- and L-shaped furniture), with
//! star-shaped obstacles sensed online inside it.
//!
//! ```text
//! Phi = S ∘ M_a ∘ H ∘ B,    J_Phi = J_S · J_M · J_H · J_B,    Θ = sigma ∘ phi_k ∘ Phi
//! ```
//!
//! - `B`: the star-obstacle bands of harmonav-transform for the sensed obstacles (each
//!   collapsed to its centre; no new solve when one is added);
//! - `H`: the harmonic map of the walls onto the unit disk (harmonav-harmonic), holes collapsed
//!   to their punctures, solved once;
//! - `M_a`: the identity, or under [`CentrePolicy::Goal`] the disk automorphism that puts the
//!   goal's image at 0 (docs/maths.md §13.2);
//! - `S`: the outer stretch of harmonav-transform applied to the unit circle, so the walls go
//!   to infinity;
//! - `k` counts the holes plus the sensed obstacles.
//!
//! **The guarantee, honestly.** The discrete `H` may fold within about half an element of the
//! walls. Everything here is defined on the certified region `W_δ = {sd ≥ δ}`,
//! `δ = max(radius + margin, h_max)` ([`FloorMap`]); [`FloorMap::certify`] proves (or fails to
//! prove) `det J_H > 0` and `|H| < 1` on all of it. In the layer `sd < δ`, `Phi` and `Θ`
//! return [`NotFree::BoundaryLayer`] instead of a value.
//!
//! Catalogue:
//! - [`FloorMap`], [`FloorOptions`], typed [`FloorError`]: walls, `H`, `δ`, wall distances
//!   (parry), the certificate;
//! - [`FloorMap::carved`], [`enclosing_polygon`]: sensed furniture against the walls joins
//!   them (a new solve of `H`);
//! - [`FloorTransform`] (`nav_transform` → [`FloorMapped`], [`Part`], [`NotFree`]);
//! - [`FloorField`]: `Θ`, `∇Θ`, the direction, `k`, the destination stiffness;
//! - [`CertifiedArea`] ([`FloorField::certified_area`]): the fraction of the robot's reachable
//!   free space below the certified level `c_δ`, on a grid;
//! - [`Funnels`] ([`FloorField::funnels`]): a chain of certified funnels towards several goals
//!   over the same `H`, whose union certifies convergence to the file's goal;
//! - [`Geodesic`]: the shortest-path distance to the goal in `W_δ` (fast marching on a grid),
//!   whose direction is the kinematic law's nominal heading;
//! - [`RosMap`] (`load`, `outline`, `free_space`, `to_floor_map`), [`FloorMap::from_ros_map`],
//!   [`MapOptions`], [`MapOutline`], [`Cell`], [`MapMode`], typed [`MapError`]
//!   ([`MapProblem`], [`MapPoint`]): ROS map_server occupancy grids (YAML + PGM/PNG) to floor
//!   plans, map_server's conventions, marching squares and geo's simplification and buffer
//!   (docs/maths.md §13.1).
//!
//! **Invariant:** knows polygons, star shapes, the harmonic map and `phi_k`; nothing of
//! robots' laws, sensing or time. The only files it reads are ROS maps ([`RosMap::load`]),
//! by the path it is given. Star worlds keep their own exact construction
//! (harmonav-field); nothing here changes it.
//!
//! ```
//! use std::sync::Arc;
//! use harmonav_floorplan::{FloorField, FloorMap, FloorOptions};
//! use harmonav_field::KPolicy;
//! use nalgebra::Vector2;
//!
//! let v = Vector2::new;
//! // An L-shaped room, 4 m arms, 1.5 m wide corridors.
//! let room = vec![v(0.0, 0.0), v(4.0, 0.0), v(4.0, 1.5), v(1.5, 1.5), v(1.5, 4.0), v(0.0, 4.0)];
//! let floor = Arc::new(FloorMap::new(room, vec![], &FloorOptions::new(0.25, 0.2))?);
//! let field = FloorField::new(floor, v(3.5, 0.75), KPolicy::default())?;
//! let e = field.eval(v(0.75, 3.5))?;
//! assert!(e.value > 0.0 && e.value < 1.0 && e.direction.is_some());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

pub mod carve;
pub mod census;
pub mod compose;
pub mod coverage;
pub mod funnel;
pub mod geodesic;
mod halves;
pub mod level;
pub mod plan;
pub mod ros_map;
pub mod sector;
pub mod slide;
pub mod theta;

pub use carve::enclosing_polygon;
pub use compose::{FloorMapped, FloorTransform, NotFree, Part};
pub use coverage::{CertifiedArea, MAX_AREA_SAMPLES, Region, area_cell};
pub use funnel::{FUNNEL_MARGIN, Funnel, FunnelOptions, Funnels};
pub use geodesic::Geodesic;
pub use level::{LayerLevel, LayerSlide, LevelOptions};
pub use plan::{CentrePolicy, FloorError, FloorMap, FloorOptions, Reach, UnknownCentrePolicy};
pub use ros_map::{
    Cell, MAX_TRACED_HOLES, MapError, MapMode, MapOptions, MapOutline, MapPoint, MapProblem,
    OccupiedPixels, RosMap, Specks, max_speck_pixels,
};
pub use sector::{Sector, Unenclosed};
pub use slide::{DirectionArc, SLIDE_WORK, SlideLevel};
pub use theta::{FloorField, SADDLE_GUARD};
