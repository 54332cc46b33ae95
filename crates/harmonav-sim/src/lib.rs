//! # harmonav-sim
//!
//! Scenario files ([`scenario`]), the built-in integrator with discovery events and the
//! online guarantee monitors ([`run`]), the states kept in bounded memory ([`trajectory`]), the MCAP recording ([`record`]) and the SVG figures
//! ([`figures`]), output folders checked before a run and written as one set ([`atomic`]),
//! and many starts with typed outcomes ([`sweep`]). Only this crate and the CLI know about
//! files.
//!
//! ```
//! use std::path::Path;
//! use harmonav_sim::scenario::Scenario;
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

pub mod atomic;
mod closed_loop;
pub mod figures;
pub mod floorplan;
pub mod guarantee;
pub mod levels;
mod monitor;
pub mod outcome;
pub mod physics;
pub mod quality;
pub mod record;
pub mod run;
pub mod scenario;
pub mod shortest;
pub mod sweep;
pub mod trajectory;
pub mod truth;
pub mod warning;
