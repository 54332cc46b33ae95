//! # harmonav-scenario
//!
//! The scenario file format (TOML) and its validation: a file becomes a [`Prepared`]
//! scenario, the world as it is ([`Truth`]: the true shapes, the configuration space grown by
//! `robot.radius + robot.margin`, the sensor) and the robot, policies and settings to run in
//! it. Floor plans have their own format ([`floorplan`]). The layout is a contract
//! (`scenarios/README.md`): it may be extended, not renamed; unknown keys are errors, and
//! every problem is a [`ScenarioError`] naming the file, the field and, where the parser
//! gives it, the line.
//!
//! Equations held here: none of the paper's; the definitions of the valid world (the
//! workspace `W`, the configuration space of a disc robot, `rho_min` for `d_min` of eq.
//! `dmin`) are checked through harmonav-transform's `Workspace`.
//!
//! May depend on: the facade and the crates below it, serde and toml. Not on the closed
//! loop, rapier, foxglove or plotters: a program that only reads scenario files compiles no
//! simulator.
//!
//! ```
//! use std::path::Path;
//! use harmonav_scenario::{Model, Scenario};
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
//! let path = Path::new("one-rock.toml");
//! let prepared = Scenario::parse(path, text)?.prepare(path)?;
//! assert_eq!(prepared.scenario.robot.model, Model::Kinematic);
//! assert_eq!(prepared.truth.names, ["O1"]);
//! // A mistake names the file, the field and the line.
//! let bad = Scenario::parse(path, &text.replace("radius = 1.0", "radius = -1.0"))?.prepare(path);
//! assert!(bad.unwrap_err().to_string().contains("obstacles[0].radius"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

pub mod floorplan;
mod kind;
pub mod movers;
mod points;
pub mod scenario;
pub mod sensor;
pub mod suites;
pub mod truth;

pub use movers::{MoverKindSpec, MoverSpec};
pub use scenario::{
    BaseKind, ControllerSpec, DEFAULT_ARRIVAL, DEFAULT_MU, ExpectSpec, FieldSpec, FleetRobotSpec,
    MAX_FILE_BYTES, MAX_OBSTACLES, MAX_RECORDED_STATES, Model, PARAMETER_RANGE, Prepared,
    RobotSpec, Scenario, ScenarioError, ShapeSpec, SimSpec, build_shape,
};
pub use sensor::{LidarSensor, SensorKind, SensorSpec};
pub use suites::{ADVERSARIAL, DIFF, LONG, MOVERS, scenario_files};
pub use truth::{Sensor, Truth};
