//! # harmonav-bench
//!
//! The motion-quality benchmark (`docs/benchmarks.md`; not published): seeded worlds, every
//! cell of (obstacle count × sensing × `k` policy × law × margin) run through the same
//! closed loop as the CLI, each path compared with the independent shortest path
//! (`harmonav_sim::shortest`), and the quality tables with their targets ([`quality`]).
//! `cargo xtask quality`, `cargo xtask bench` and `cargo xtask verify` (`quality.*`) call it.
//!
//! May depend on: harmonav-scenario (the worlds are written as scenarios) and harmonav-sim
//! (the runs, the shortest path, the thread pool). Nothing depends on it but xtask.

#![warn(missing_docs)]

pub mod quality;
