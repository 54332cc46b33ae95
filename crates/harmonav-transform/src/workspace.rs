//! A validated workspace: the outer boundary, the (true) obstacles and the destination, with
//! every distance the navigation transformation needs computed once.

use nalgebra::Vector2;

use crate::error::ShapeError;
use crate::shape::StarShape;

/// Why a workspace or a point in it is not valid (indices are obstacle indices).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum WorldError {
    /// Two obstacles touch or overlap, or are not certified apart: closer than the sum of
    /// their [`StarShape::distance_tolerance`]s ([`StarShape::distance_to`]).
    Overlap {
        /// First obstacle.
        first: usize,
        /// Second obstacle.
        second: usize,
    },
    /// An obstacle is not strictly inside the outer boundary (certified, to the shapes'
    /// distance tolerances: [`StarShape::clearance_inside`]).
    OutsideBoundary {
        /// The obstacle.
        obstacle: usize,
    },
    /// The point (`what`: "destination", "start", …) lies in an obstacle.
    InObstacle {
        /// Which point.
        what: &'static str,
        /// The obstacle.
        obstacle: usize,
    },
    /// The point lies on or outside the outer boundary.
    OutsideWorkspace {
        /// Which point.
        what: &'static str,
    },
    /// An obstacle index that does not exist.
    NoSuchObstacle {
        /// The index.
        obstacle: usize,
    },
    /// The far-field valley radius given to [`crate::NavTransform::new`] is negative or not
    /// finite.
    InvalidValleyRadius {
        /// The value.
        value: f64,
    },
}

impl std::fmt::Display for WorldError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Overlap { first, second } => {
                write!(f, "obstacles {first} and {second} overlap or touch")
            }
            Self::OutsideBoundary { obstacle } => write!(
                f,
                "obstacle {obstacle} is not strictly inside the workspace boundary"
            ),
            Self::InObstacle { what, obstacle } => {
                write!(f, "the {what} lies inside obstacle {obstacle}")
            }
            Self::OutsideWorkspace { what } => {
                write!(f, "the {what} lies on or outside the workspace boundary")
            }
            Self::NoSuchObstacle { obstacle } => write!(f, "there is no obstacle {obstacle}"),
            Self::InvalidValleyRadius { value } => write!(
                f,
                "the far-field valley radius must be finite and non-negative, got {value:e}"
            ),
        }
    }
}

impl std::error::Error for WorldError {}

/// Why the workspace of a robot of some radius cannot be built.
#[derive(Clone, Debug, PartialEq)]
pub enum RobotWorldError {
    /// Offsetting a shape failed (`obstacle: None` for the boundary).
    Shape {
        /// The obstacle, or `None` for the boundary.
        obstacle: Option<usize>,
        /// What went wrong.
        error: ShapeError,
    },
    /// The grown world is invalid (e.g. two inflated obstacles overlap: the passage between
    /// them is narrower than the robot).
    World(WorldError),
}

impl std::fmt::Display for RobotWorldError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Shape {
                obstacle: Some(i),
                error,
            } => write!(f, "obstacle {i}: {error}"),
            Self::Shape {
                obstacle: None,
                error,
            } => write!(f, "workspace boundary: {error}"),
            Self::World(e) => write!(f, "with the robot radius: {e}"),
        }
    }
}

impl std::error::Error for RobotWorldError {}

/// The workspace `W`: boundary `∂O_0`, obstacles `O_1..O_M`, destination `x_d`.
#[derive(Clone, Debug)]
pub struct Workspace {
    boundary: StarShape,
    obstacles: Vec<StarShape>,
    destination: Vector2<f64>,
    /// `d(O_i, O_j)`, row-major `M × M` (diagonal `∞`).
    between: Vec<f64>,
    /// `d(O_i, ∂O_0)`.
    to_boundary: Vec<f64>,
    /// `d(x_d, O_i)`.
    goal_to_obstacle: Vec<f64>,
    /// `d(x_d, ∂O_0)`.
    goal_to_boundary: f64,
}

impl Workspace {
    /// Validates the workspace and caches the distances between its parts: certified gaps and
    /// clearances ([`StarShape::distance_to`], [`StarShape::clearance_inside`]: positive only if
    /// the parts are apart, exact to [`crate::DISTANCE_TOLERANCE`]) and refined signed distances
    /// of the destination.
    ///
    /// Errors: overlapping obstacles (or obstacles closer than their distance tolerances), an
    /// obstacle not strictly inside the boundary, a destination inside an obstacle or outside
    /// the workspace.
    pub fn new(
        boundary: StarShape,
        obstacles: Vec<StarShape>,
        destination: Vector2<f64>,
    ) -> Result<Self, WorldError> {
        let m = obstacles.len();
        let mut to_boundary = Vec::with_capacity(m);
        for (i, o) in obstacles.iter().enumerate() {
            let d = o.clearance_inside(&boundary);
            if d <= 0.0 || !boundary.contains(o.centre()) {
                return Err(WorldError::OutsideBoundary { obstacle: i });
            }
            to_boundary.push(d);
        }
        let mut between = vec![f64::INFINITY; m * m];
        for i in 0..m {
            for j in 0..i {
                let d = separation(&obstacles[i], &obstacles[j]).ok_or(WorldError::Overlap {
                    first: j,
                    second: i,
                })?;
                between[i * m + j] = d;
                between[j * m + i] = d;
            }
        }
        let mut ws = Self {
            boundary,
            obstacles,
            destination,
            between,
            to_boundary,
            goal_to_obstacle: Vec::new(),
            goal_to_boundary: 0.0,
        };
        ws.check_free(destination, "destination")?;
        ws.goal_to_obstacle = ws
            .obstacles
            .iter()
            .map(|o| o.signed_distance(destination))
            .collect();
        ws.goal_to_boundary = -ws.boundary.signed_distance(destination);
        Ok(ws)
    }

    /// This workspace with `obstacle` added as obstacle `M + 1` (index `M`), validated against
    /// the boundary, the known obstacles and the destination as in [`Self::new`], and the cached
    /// distances extended by its row alone: `O(M)` distance queries instead of `O(M²)`. Used
    /// when obstacles become known one at a time.
    ///
    /// Errors: the obstacle overlaps or touches obstacle `first` ([`WorldError::Overlap`] with
    /// `second = M`), is not strictly inside the boundary, or contains the destination.
    pub fn with_obstacle(&self, obstacle: StarShape) -> Result<Self, WorldError> {
        let m = self.obstacles.len();
        let to_boundary = obstacle.clearance_inside(&self.boundary);
        if to_boundary <= 0.0 || !self.boundary.contains(obstacle.centre()) {
            return Err(WorldError::OutsideBoundary { obstacle: m });
        }
        let mut row = Vec::with_capacity(m);
        for (j, o) in self.obstacles.iter().enumerate() {
            row.push(separation(&obstacle, o).ok_or(WorldError::Overlap {
                first: j,
                second: m,
            })?);
        }
        if obstacle.contains(self.destination) {
            return Err(WorldError::InObstacle {
                what: "destination",
                obstacle: m,
            });
        }
        let goal = obstacle.signed_distance(self.destination);
        let n = m + 1;
        let mut between = vec![f64::INFINITY; n * n];
        for i in 0..m {
            between[i * n..i * n + m].copy_from_slice(&self.between[i * m..(i + 1) * m]);
            between[i * n + m] = row[i];
            between[m * n + i] = row[i];
        }
        let mut ws = self.clone();
        ws.obstacles.push(obstacle);
        ws.between = between;
        ws.to_boundary.push(to_boundary);
        ws.goal_to_obstacle.push(goal);
        Ok(ws)
    }

    /// The workspace of a disc robot of radius `robot_radius` (configuration space): every
    /// obstacle inflated and the boundary deflated by it ([`StarShape::offset`]), then
    /// validated as in [`Self::new`]. A zero radius is the point robot.
    pub fn for_robot(
        boundary: StarShape,
        obstacles: Vec<StarShape>,
        destination: Vector2<f64>,
        robot_radius: f64,
    ) -> Result<Self, RobotWorldError> {
        if !(robot_radius >= 0.0 && robot_radius.is_finite()) {
            return Err(RobotWorldError::Shape {
                obstacle: None,
                error: ShapeError::NotPositive {
                    field: "robot.radius",
                    value: robot_radius,
                },
            });
        }
        let boundary = boundary
            .offset(-robot_radius)
            .map_err(|error| RobotWorldError::Shape {
                obstacle: None,
                error,
            })?;
        let obstacles = obstacles
            .iter()
            .enumerate()
            .map(|(i, o)| {
                o.offset(robot_radius)
                    .map_err(|error| RobotWorldError::Shape {
                        obstacle: Some(i),
                        error,
                    })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Self::new(boundary, obstacles, destination).map_err(RobotWorldError::World)
    }

    /// `Ok` if `x` lies in the free space (outside every obstacle, strictly inside the
    /// boundary); `what` names the point in the error ("start", "destination", …).
    pub fn check_free(&self, x: Vector2<f64>, what: &'static str) -> Result<(), WorldError> {
        let inside = x.x.is_finite() && x.y.is_finite() && self.boundary.contains(x);
        if !inside || self.boundary.coarse_signed_distance(x) >= 0.0 {
            return Err(WorldError::OutsideWorkspace { what });
        }
        match self.obstacles.iter().position(|o| o.contains(x)) {
            Some(obstacle) => Err(WorldError::InObstacle { what, obstacle }),
            None => Ok(()),
        }
    }

    /// The outer boundary `∂O_0`.
    pub fn boundary(&self) -> &StarShape {
        &self.boundary
    }

    /// The obstacles `O_1..O_M`.
    pub fn obstacles(&self) -> &[StarShape] {
        &self.obstacles
    }

    /// The destination `x_d`.
    pub fn destination(&self) -> Vector2<f64> {
        self.destination
    }

    pub(crate) fn between(&self, i: usize, j: usize) -> f64 {
        self.between[i * self.obstacles.len() + j]
    }

    pub(crate) fn to_boundary(&self, i: usize) -> f64 {
        self.to_boundary[i]
    }

    pub(crate) fn goal_to_obstacle(&self, i: usize) -> f64 {
        self.goal_to_obstacle[i]
    }

    pub(crate) fn goal_to_boundary(&self) -> f64 {
        self.goal_to_boundary
    }
}

/// The distance between two obstacles, `None` if they overlap or touch. Bounding circles first:
/// only near pairs need the outline query ([`StarShape::distance_to`]); a pair whose bounding
/// circles are apart by more than half their centre distance gets that gap as a lower bound.
fn separation(a: &StarShape, b: &StarShape) -> Option<f64> {
    let (ca, cb) = (a.centre(), b.centre());
    let lower = (ca - cb).norm() - a.radius_bounds().1 - b.radius_bounds().1;
    let d = if lower > 0.0 && lower > 0.5 * (ca - cb).norm() {
        lower
    } else {
        a.distance_to(b)
    };
    (d > 0.0 && !a.contains(cb) && !b.contains(ca)).then_some(d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::{self, Kind, Rng};

    /// Adding the obstacles one at a time gives the workspace `new` builds from all of them.
    #[test]
    fn with_obstacle_matches_new() {
        let kinds = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
        let mut rng = Rng::new(11);
        let all = random::workspace(&mut rng, 8, &kinds, Kind::Circle, 0.1);
        let mut ws = Workspace::new(all.boundary().clone(), Vec::new(), all.destination()).unwrap();
        for o in all.obstacles() {
            ws = ws.with_obstacle(o.clone()).unwrap();
        }
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(1.0) || a == b;
        let m = all.obstacles().len();
        for i in 0..m {
            assert!(close(ws.to_boundary(i), all.to_boundary(i)));
            assert!(close(ws.goal_to_obstacle(i), all.goal_to_obstacle(i)));
            for j in 0..m {
                assert!(close(ws.between(i, j), all.between(i, j)), "{i}, {j}");
            }
        }
        assert_eq!(ws.goal_to_boundary(), all.goal_to_boundary());
    }

    #[test]
    fn with_obstacle_rejects_what_new_rejects_and_names_the_new_index() {
        let boundary = StarShape::circle(Vector2::zeros(), 5.0).unwrap();
        let disc = |x: f64, y: f64, r: f64| StarShape::circle(Vector2::new(x, y), r).unwrap();
        let ws =
            Workspace::new(boundary, vec![disc(1.0, 0.0, 0.5)], Vector2::new(-3.0, 0.0)).unwrap();
        assert_eq!(
            ws.with_obstacle(disc(1.8, 0.0, 0.5)).err(),
            Some(WorldError::Overlap {
                first: 0,
                second: 1
            })
        );
        assert_eq!(
            ws.with_obstacle(disc(4.8, 0.0, 0.5)).err(),
            Some(WorldError::OutsideBoundary { obstacle: 1 })
        );
        assert_eq!(
            ws.with_obstacle(disc(-3.0, 0.2, 0.5)).err(),
            Some(WorldError::InObstacle {
                what: "destination",
                obstacle: 1
            })
        );
        assert_eq!(
            ws.with_obstacle(disc(0.0, 2.0, 0.5))
                .unwrap()
                .obstacles()
                .len(),
            2
        );
    }
}
