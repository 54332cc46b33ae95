//! # harmonav-output
//!
//! What a run leaves on disk: the MCAP recording for Foxglove ([`record`]: the official
//! Foxglove schemas through the `foxglove` crate, streamed during a run of any length), the
//! SVG figures ([`figures`], plotters), a floor-plan run's figure and outputs ([`floor`]), the
//! level sets of `Θ` they share ([`levels`], marching squares, vertices moved onto the level
//! sets), the figures drawn at a multiple of their size so that lines keep sub-pixel
//! coordinates ([`canvas`]), the shapes as drawn ([`drawing`]), and output folders checked
//! before a run and written as one set, atomically ([`atomic`], [`set`]).
//!
//! Equations held here: none of the paper's; `Θ` is sampled on a grid (`levels`) and drawn.
//!
//! May depend on: harmonav-scenario (what is drawn), harmonav-sim (the run and its events),
//! foxglove, plotters, contour, serde_json. Nothing below it knows it exists: a user of the
//! closed loop alone compiles neither foxglove nor plotters.

#![warn(missing_docs)]

pub mod atomic;
pub mod canvas;
pub mod drawing;
pub mod figures;
pub mod floor;
pub mod levels;
mod messages;
pub mod record;
pub mod set;
mod world;
