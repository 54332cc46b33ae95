//! # harmonav
//!
//! Provably correct robot navigation with the harmonic navigation functions of Loizou & Rimon,
//! *Correct-by-Construction Navigation Functions with Application to Sensor Based Robot
//! Navigation*: one dependency line for the whole stack.
//!
//! [`Navigator`] is the online API for a robot that does not know its map: obstacles are added
//! as its own perception finds them, and [`Navigator::command`] returns the law's command for
//! the current state — the velocity `u = −s(x)∇Θ/|∇Θ|` (eq. `kinctrl` with a speed policy) or the force
//! `f = −μ∇Ψ − λẋ` (eq. `dynctrllocal`, `docs/maths.md` §9). Every guarantee of the paper holds
//! over the obstacles known so far: no collision, never leaving the workspace, convergence from
//! almost every start, and for the dynamic law the speed bound `√(2μ/m)` and no overshoot.
//!
//! ```
//! use harmonav::{Law, Navigator, Options, StarShape, Vector2};
//!
//! let boundary = StarShape::circle(Vector2::zeros(), 5.0)?;
//! let goal = Vector2::new(3.0, 0.0);
//! let truth = [StarShape::circle(Vector2::new(0.0, 0.3), 0.8)?]; // the world, unknown to the robot
//! let mut nav = Navigator::new(boundary, goal, Law::kinematic(1.0), Options::default())?;
//! let (mut x, h) = (Vector2::new(-3.0, 0.0), 0.01); // a 100 Hz loop
//! let mut seen = [false];
//! for _ in 0..2000 {
//!     for (o, s) in truth.iter().zip(&mut seen) {
//!         if !*s && o.signed_distance(x) < 1.0 { // "perception": obstacles within 1 m
//!             nav.add_obstacle(o.clone())?;
//!             *s = true;
//!         }
//!     }
//!     let u = nav.command(x, Vector2::zeros())?.value;
//!     x += h * u;
//!     assert!(truth.iter().all(|o| o.signed_distance(x) > 0.0));
//! }
//! assert!((x - goal).norm() < 0.01);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The layers, re-exported: [`potential`] (`phi_k` on the point world), [`transform`] (shapes
//! and the navigation transformation), [`field`] (`Θ`), [`floorplan`] (`Θ` on floor plans,
//! `Phi = S ∘ H ∘ B`), [`sensing`] (the sector and `d_min`), [`control`] (the laws) and
//! [`perception`] (range scans to conservative star obstacles, fed to the navigator by
//! [`Navigator::observe_scan`]).
//!
//! The navigator is one type over a [`World`]: a star world ([`StarWorld`], the default) or a
//! floor plan (polygons with polygonal holes, walls of any shape: [`FloorWorld`], the navigator
//! [`FloorNavigator`] `= Navigator<FloorWorld>`), with the same calls; on a floor plan it
//! navigates in the certified region `W_δ` of the harmonic map ([`FloorMap`], `docs/maths.md`
//! §13).

#![warn(missing_docs)]

mod base;
mod braking;
mod certified;
#[cfg(feature = "checks")]
pub mod checks;
mod controller;
mod diff;
mod error;
mod event;
mod floor;
mod floor_joined;
mod hold;
mod joined;
mod law;
mod movers;
mod navigator;
mod options;
mod ranges;
mod scan;
mod scanning;
mod space;
mod star;
pub mod tuning;
mod world;

pub use harmonav_control as control;
pub use harmonav_field as field;
pub use harmonav_floorplan as floorplan;
pub use harmonav_perception as perception;
pub use harmonav_potential as potential;
pub use harmonav_sensing as sensing;
pub use harmonav_transform as transform;

pub use base::{Accel, Base, GoalTolerance};
pub use certified::Band;
pub use controller::{Controller, Evaluation};
pub use diff::{PoseCommand, Steer, unicycle_arc};
pub use error::NavError;
pub use event::{grow_perceived, grow_perceived_as};
pub use floor::{EscapeMemory, FloorWorld};
pub use harmonav_control::{DampingPolicy, HeadingPolicy, SpeedPolicy};
pub use harmonav_field::KPolicy;
pub use harmonav_floorplan::{CentrePolicy, FloorError, FloorMap, FloorOptions};
pub use harmonav_transform::{ShapeError, StarShape};
pub use hold::{Command, Mode};
pub use law::Law;
pub use movers::{Filtered, Mover, MoverFilter, MoverKind, MoverMemory};
pub use nalgebra::Vector2;
pub use navigator::{FloorNavigator, Navigator};
pub use options::{HoldPolicy, Options, UnknownHoldPolicy};
pub use scan::{LaserScan, Perceived, Pose, StarForm};
pub use scanning::{ScanOptions, ScanUpdate};
pub use star::StarWorld;
#[allow(deprecated)]
pub use tuning::root::*;
pub use world::{IntoWorld, World};

/// The README's code compiles and runs (checked by `cargo test --doc`).
#[doc = include_str!("../../../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
