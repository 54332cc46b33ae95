//! # harmonav-sim
//!
//! The closed loop and its judgement, with no files and no outputs: the robot's
//! [`harmonav::Navigator`] driven against the scenario's truth ([`harmonav_scenario`]), every
//! guarantee judged online, and the run's [`summary::Summary`].
//!
//! The path of a run goes down through the modules in this order, each entered once: the
//! integrators reach the closed loop only through the driver, and the driver asks
//! `preflight` for the warnings on the field its loop starts with.
//!
//! ```text
//! physics::simulate → run | rapier (the integrator: advances the state)
//!   → driver (start, the warnings from preflight, sensing, recording, the stall rule, the end)
//!     → closed_loop (Navigator against the Truth) → monitor (guarantees) → summary
//! ```
//!
//! The shared types below the loop, in their own order (each uses only those before it):
//! [`warning`] and [`guarantee`], then [`trace`] (samples, discoveries, events) and
//! [`outcome`], then [`trajectory`]. Studies: [`sweep`] (many starts, typed outcomes)
//! on the one thread pool [`pool`], [`shortest`] (the independent shortest path of "path
//! over shortest"), and [`descent`] (the normalised descent of `Θ` judged as a run: the
//! convergence study's one entry). A file with `[[movers]]` runs in the held-command loop
//! (`held.rs`, the user's loop at the control period, judged) with the movers of [`movers`]:
//! the built-in integrator hands it over. [`floor`] is the loop of the floor-plan scenarios;
//! `rapier::floor` flies it in rapier with the walls as colliders, and
//! [`physics::simulate_floor`] runs either ([`physics::simulate_floor_observed`] with an
//! observer, which a recording streams from).
//!
//! Equations held here: the closed loops `ẋ = u` (eq. `holint`) and `m ẍ = f` (eq.
//! `dynmodel`) integrated by Bogacki–Shampine 3(2) with step control ([`run`]); the
//! Carathéodory solution at a discovery (the state cut at the first instant the sector sees
//! an obstacle); the monitors' measures of each guarantee ([`guarantee::Check`]).
//!
//! May depend on: the facade and the crates below it, [`harmonav_scenario`] (the validated
//! scenario), serde (the summary's JSON form), and rapier2d-f64 only with the feature
//! `rapier` (the cross-check [`physics::Physics::Rapier`]). Not on toml parsing of its own,
//! foxglove or plotters (those are `harmonav-output`'s).
//!
//! ```
//! use std::path::Path;
//! use harmonav_scenario::Scenario;
//!
//! let text = r#"
//!     name = "one-rock"
//!     [workspace]
//!     type = "circle"
//!     center = [0.0, 0.0]
//!     radius = 5.0
//!     [[obstacles]]
//!     type = "circle"
//!     center = [0.0, 0.0]
//!     radius = 1.0
//!     [robot]
//!     model = "kinematic"
//!     start = [-3.0, 0.2]
//!     goal = [3.0, 0.0]
//! "#;
//! let prepared = Scenario::parse(Path::new("one-rock.toml"), text)?.prepare(Path::new("one-rock.toml"))?;
//! let run = harmonav_sim::run::run(&prepared, None)?;
//! assert!(run.summary.reached && run.summary.all_passed());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

mod closed_loop;
pub mod descent;
mod driver;
pub mod floor;
pub mod golden;
pub mod guarantee;
mod held;
mod monitor;
pub mod movers;
pub mod outcome;
pub mod physics;
pub mod pool;
pub mod preflight;
#[cfg(feature = "rapier")]
pub mod rapier;
pub mod run;
mod scanner;
pub mod shortest;
mod step;
pub mod summary;
pub mod sweep;
pub mod trace;
pub mod trajectory;
pub mod unicycle;
pub mod warning;

pub use driver::STALL_STEPS;
pub use guarantee::MARGIN_TOLERANCE;
pub use scanner::DENSE;
