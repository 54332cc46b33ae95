//! A ROS 2 node for harmonav, in pure Rust (`ros2-client` over RustDDS, no ROS install): it
//! takes `/map`, `/scan`, `/odom`, `/tf`, `/tf_static` and `/goal_pose` and drives `/cmd_vel`
//! with [`harmonav::Navigator`] (a disc around the robot, from scans alone) or
//! [`harmonav::FloorNavigator`] (the floor plan from `/map`).
//!
//! It also serves Nav2's `navigate_to_pose` action (`nav2_msgs/action/NavigateToPose`, Jazzy's
//! layout), so that goals come as from Nav2's navigator:
//!
//! ```sh
//! ros2 action send_goal --feedback /navigate_to_pose nav2_msgs/action/NavigateToPose \
//!     "{pose: {header: {frame_id: map}, pose: {position: {x: 3.4, y: 2.4}}}}"
//! ```
//!
//! or `nav2_simple_commander`'s `BasicNavigator().goToPose(pose)` (without
//! `waitUntilNav2Active`, which asks for lifecycle services this node does not have). One goal
//! runs at a time; a new one preempts it, a cancel stops the robot; see [`action`] for the
//! results and their error codes. The services use Fast DDS's request/reply mapping unless
//! `service_mapping: cyclone` (clients on `rmw_cyclonedds_cpp`).
//!
//! A goal during which the robot does not move `required_movement_radius` in
//! `movement_time_allowance` is given up (Nav2's progress checker). The obstacles the node
//! perceives go to RViz as `visualization_msgs/MarkerArray` line strips on
//! `/harmonav/obstacles` ([`bridge::Bridge::obstacle_markers`]).
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
