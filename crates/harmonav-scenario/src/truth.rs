//! The world as it is, which the robot's navigator does not know: the true shapes and the
//! sensor that finds them. The integrators sense against it and the monitors measure against
//! it; the navigator ([`harmonav::Navigator`]) learns only what the sensor reports.

use std::sync::Arc;

use harmonav_sensing::{Sector, Sensing};

use crate::sensor::LidarSensor;
use harmonav_transform::{StarShape, Workspace};
use nalgebra::Vector2;

/// How the robot perceives the true obstacles (`[sensor]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sensor {
    /// All obstacles are known at `t = 0` (no `[sensor]` table).
    Global,
    /// The paper's sector: an obstacle's exact shape becomes known at first sight.
    Sector(Sector),
    /// A simulated lidar: the navigator gets scans only, and perceives shapes from them.
    Lidar(LidarSensor),
}

impl Sensor {
    /// How exact shapes are discovered: `None` under a lidar (no exact shape is ever handed
    /// over).
    #[must_use]
    pub fn exact(&self) -> Option<Sensing> {
        match *self {
            Self::Global => Some(Sensing::Global),
            Self::Sector(s) => Some(Sensing::Sector(s)),
            Self::Lidar(_) => None,
        }
    }

    /// The lidar, if the robot has one.
    #[must_use]
    pub fn lidar(&self) -> Option<&LidarSensor> {
        match self {
            Self::Lidar(l) => Some(l),
            _ => None,
        }
    }
}

/// The truth of a scenario.
#[derive(Clone, Debug)]
pub struct Truth {
    /// The true boundary (not shrunk).
    pub boundary: StarShape,
    /// The true obstacle shapes (not grown), for sensing, clearance monitors and drawings.
    pub obstacles: Vec<StarShape>,
    /// Obstacle names (`O1`, … where the file gives none).
    pub names: Vec<String>,
    /// The configuration space: every shape grown by `radius + margin`, with the goal. The
    /// sector detects these shapes (the robot's centre must keep off them).
    pub workspace: Arc<Workspace>,
    /// How the robot perceives the obstacles.
    pub sensor: Sensor,
    /// `rho_min` for `d_min`.
    pub rho_min: f64,
    /// Robot radius, m.
    pub radius: f64,
    /// Clearance kept to the true shapes, m.
    pub margin: f64,
}

impl Truth {
    /// The goal `x_d`.
    pub fn goal(&self) -> Vector2<f64> {
        self.workspace.destination()
    }

    /// Obstacles (indices into [`Self::obstacles`]) that are not yet `known` and that the sector
    /// sees from `x` along `axis` (none under global sensing, where all are known at `t = 0`,
    /// and none under a lidar, which hands over scans instead).
    pub fn sees(&self, x: Vector2<f64>, axis: Vector2<f64>, known: &[usize]) -> Vec<usize> {
        let Sensor::Sector(sector) = self.sensor else {
            return Vec::new();
        };
        let grown = self.workspace.obstacles();
        (0..grown.len())
            .filter(|i| !known.contains(i) && sector.detects(x, axis, &grown[*i]))
            .collect()
    }

    /// The clearance of a robot at `x` to the true obstacles and to the true boundary, m
    /// (distance minus the robot radius; negative in collision).
    pub fn clearances(&self, x: Vector2<f64>) -> (f64, f64) {
        let obstacle = nearest_signed_distance(&self.obstacles, x) - self.radius;
        let boundary = -self.boundary.signed_distance(x) - self.radius;
        (obstacle, boundary)
    }
}

/// The smallest signed distance from `x` to the shapes (`+∞` for none). The exact distance
/// (a parry query refined on the curve, ~2 µs) is computed only for shapes whose bounding disc
/// could beat the best so far: `|x − c| − R_max` is a lower bound of the signed distance, inside
/// too (the boundary point on the ray through `x` is at most `R_max` from `c`). With 50
/// obstacles the monitor was 98 % of a run's time without this.
fn nearest_signed_distance(shapes: &[StarShape], x: Vector2<f64>) -> f64 {
    shapes.iter().fold(f64::INFINITY, |best, o| {
        if (x - o.centre()).norm() - o.radius_bounds().1 >= best {
            best
        } else {
            best.min(o.signed_distance(x))
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use harmonav_transform::random::{self, Kind, Rng};

    /// The pruned minimum equals the plain one, inside and outside the shapes.
    #[test]
    fn pruned_nearest_distance_is_the_minimum() {
        let kinds = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
        let mut rng = Rng::new(7);
        let ws = random::workspace(&mut rng, 12, &kinds, Kind::Circle, 0.1);
        let shapes = ws.obstacles();
        for i in 0..400 {
            // Half the probes at obstacle centres (inside), half anywhere in the box.
            let x = if i % 2 == 0 {
                shapes[i / 2 % shapes.len()].centre() + Vector2::new(0.01, -0.02)
            } else {
                Vector2::new(rng.uniform(-6.0, 6.0), rng.uniform(-6.0, 6.0))
            };
            let plain = shapes
                .iter()
                .map(|o| o.signed_distance(x))
                .fold(f64::INFINITY, f64::min);
            assert_eq!(nearest_signed_distance(shapes, x), plain, "at {x:?}");
        }
        assert_eq!(
            nearest_signed_distance(&[], Vector2::zeros()),
            f64::INFINITY
        );
    }
}
