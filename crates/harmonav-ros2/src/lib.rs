//! A ROS 2 node for harmonav, in pure Rust (`ros2-client` over RustDDS, no ROS install): it
//! takes `/map`, `/scan`, `/odom`, `/tf`, `/tf_static` and `/goal_pose` and drives `/cmd_vel`
//! with [`harmonav::Navigator`] (a disc around the robot, from scans alone) or
//! [`harmonav::FloorNavigator`] (the floor plan from `/map`).
//!
//! This crate is a leaf: no other crate of the workspace depends on it, so a user of
//! `harmonav` compiles no DDS.
//!
//! - [`msgs`]: the messages, hand-written serde structs laid out like the `.msg` files;
//! - [`tf`]: a small transform buffer (latest transform per edge, stamps checked);
//! - [`params`]: the parameter file (`--ros-args --params-file FILE`);
//! - [`bridge`]: the node's logic without DDS (stale data, refusals, the command);
//! - [`action`]: the `navigate_to_pose` action's goals, cancels and results without DDS;
//! - the binary `harmonav-ros2` (`src/main.rs`): the DDS side.

pub mod action;
pub mod bridge;
pub mod msgs;
pub mod params;
pub mod tf;
