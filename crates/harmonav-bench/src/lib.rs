//! # harmonav-bench
//!
//! The motion-quality benchmark (`docs/benchmarks.md`; not published): seeded worlds, every
//! cell of (obstacle count × sensing × `k` policy × law × margin) run through the same
//! closed loop as the CLI, each path compared with the independent shortest path
//! (`harmonav_sim::shortest`) ([`quality`]), and the tables of a study from its per-run records
//! ([`table`]: the one implementation, which `harmonav.experiment report` also calls), and the
//! hostile round's worst-case scan ([`hostile`], for the benches), and the worlds of the
//! per-command cost of a differential-drive base and of a command with movers ([`diff`]).
//! `cargo xtask quality`, `cargo xtask bench` and `cargo xtask verify` (`quality.*`) call it.
//!
//! May depend on: harmonav-scenario (the worlds are written as scenarios) and harmonav-sim
//! (the runs, the shortest path, the thread pool). Nothing depends on it but xtask and the Python
//! extension.

#![warn(missing_docs)]

pub mod diff;
pub mod hostile;
pub mod quality;
pub mod table;
