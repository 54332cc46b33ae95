//! The floor-plan loop (issue 25, `docs/maths.md` §13): the user's loop around a
//! [`harmonav::FloorNavigator`] on a [`FloorPrepared`] scenario, with its monitors (no
//! collision with the true walls and obstacles, never leaving, arrival within a stated
//! threshold), and the map's certificate.

use harmonav::{FloorNavigator, Law, NavError, Options};
use harmonav_harmonic::Certificate;
use harmonav_scenario::Model;
use harmonav_scenario::floorplan::FloorPrepared;
use nalgebra::Vector2;

/// How a floor-plan run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FloorEnding {
    /// Within the arrival threshold of the goal.
    Reached,
    /// The robot's disc touched a true wall or obstacle.
    Collision,
    /// The robot's centre left the floor plan (or entered a hole).
    Left,
    /// The time limit passed first.
    TimedOut,
    /// The navigator refused a command (the error is in [`FloorRun::error`]).
    Refused,
}

impl FloorEnding {
    /// The name for JSON and tables.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Reached => "reached",
            Self::Collision => "collision",
            Self::Left => "left",
            Self::TimedOut => "timed_out",
            Self::Refused => "refused",
        }
    }
}

/// What one run measured.
#[derive(Clone, Debug, PartialEq)]
pub struct FloorRun {
    /// How it ended.
    pub ending: FloorEnding,
    /// Simulated time, s.
    pub time: f64,
    /// The smallest distance from the robot's centre to a true wall, minus its radius (its
    /// disc's clearance), m.
    pub wall_clearance: f64,
    /// The smallest clearance of the robot's disc from a true obstacle, m (∞ with none).
    pub obstacle_clearance: f64,
    /// The smallest certified clearance to the boundary layer (`sd − δ`) seen, m.
    pub layer_clearance: f64,
    /// `|x − x_d|` at the end, m.
    pub final_distance: f64,
    /// Path length, m.
    pub path: f64,
    /// Obstacles sensed and added.
    pub sensed: usize,
    /// Commands issued.
    pub commands: usize,
    /// The navigator's error, if it refused.
    pub error: Option<NavError>,
}

/// Runs the user's loop from `start` under `model` (the file's by default): at every period
/// `h` the robot senses the true obstacles within `sim.sensor_range` (added once, grown by the
/// navigator), asks [`FloorNavigator::command`], and holds it — `x += h·u` (kinematic), or
/// `v += h·f/m, x += h·v` (dynamic, semi-implicit Euler). The monitors use the true walls and
/// shapes only.
///
/// # Errors
/// The navigator could not be built (a message naming the parameter).
pub fn run(
    prepared: &FloorPrepared,
    model: Option<Model>,
    start: Vector2<f64>,
) -> Result<FloorRun, NavError> {
    let r = &prepared.scenario.robot;
    let law = match model.unwrap_or(r.model) {
        Model::Kinematic => Law::kinematic(r.gain),
        Model::Dynamic => Law::dynamic(r.mass, r.mu),
    };
    let options = Options::default().with_robot(r.radius, r.margin);
    let goal = Vector2::from(r.goal);
    let mut nav = FloorNavigator::new(prepared.floor.clone(), goal, law, options)?;
    let h = nav.control_period();
    let sim = prepared.scenario.sim;
    let steps = (sim.max_time / h).ceil() as usize;
    let floor = &prepared.floor;
    let (mut x, mut vel) = (start, Vector2::zeros());
    let mut known = vec![false; prepared.obstacles.len()];
    let mut out = FloorRun {
        ending: FloorEnding::TimedOut,
        time: 0.0,
        wall_clearance: f64::INFINITY,
        obstacle_clearance: f64::INFINITY,
        layer_clearance: f64::INFINITY,
        final_distance: (x - goal).norm(),
        path: 0.0,
        sensed: 0,
        commands: 0,
        error: None,
    };
    for n in 0..=steps {
        out.time = n as f64 * h;
        // Monitors on the truth.
        if !floor.domain().contains(x) {
            out.ending = FloorEnding::Left;
            break;
        }
        out.wall_clearance = out.wall_clearance.min(floor.wall_distance(x) - r.radius);
        out.layer_clearance = out.layer_clearance.min(floor.clearance(x));
        for o in &prepared.obstacles {
            out.obstacle_clearance = out.obstacle_clearance.min(o.signed_distance(x) - r.radius);
        }
        if out.wall_clearance <= 0.0 || out.obstacle_clearance <= 0.0 {
            out.ending = FloorEnding::Collision;
            break;
        }
        out.final_distance = (x - goal).norm();
        if out.final_distance < sim.arrival {
            out.ending = FloorEnding::Reached;
            break;
        }
        if n == steps {
            break;
        }
        // Perception: a true obstacle within range of the robot's disc becomes known.
        for (o, seen) in prepared.obstacles.iter().zip(&mut known) {
            if !*seen && o.signed_distance(x) - r.radius < sim.sensor_range {
                nav.add_obstacle(o.clone())?;
                *seen = true;
                out.sensed += 1;
            }
        }
        let c = match nav.command(x, vel) {
            Ok(c) => c,
            Err(e) => {
                out.ending = FloorEnding::Refused;
                out.error = Some(e);
                break;
            }
        };
        out.commands += 1;
        let next = match &law {
            Law::Kinematic { .. } => {
                vel = c.value;
                x + h * c.value
            }
            Law::Dynamic { mass, .. } => {
                vel += h * c.value / *mass;
                x + h * vel
            }
        };
        out.path += (next - x).norm();
        x = next;
    }
    Ok(out)
}

/// The certificate of the scenario's map on `W_δ` ([`harmonav::FloorMap::certify`]) with at most
/// `max_evaluations` cells.
///
/// # Errors
/// The certificate's own error, as text.
pub fn certificate(
    prepared: &FloorPrepared,
    max_evaluations: usize,
) -> Result<Certificate, String> {
    prepared
        .floor
        .certify(max_evaluations)
        .map_err(|e| e.to_string())
}
