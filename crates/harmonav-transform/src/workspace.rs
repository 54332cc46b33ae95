//! A validated workspace: the outer boundary, the (true) obstacles and the destination, with
//! every distance the navigation transformation needs computed once.

use nalgebra::Vector2;

use crate::error::ShapeError;
use crate::shape::StarShape;

/// Why a workspace or a point in it is not valid (indices are obstacle indices).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum WorldError {
    /// Two obstacles touch or overlap.
    Overlap {
        /// First obstacle.
        first: usize,
        /// Second obstacle.
        second: usize,
    },
    /// An obstacle is not strictly inside the outer boundary.
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
                "the far-field valley radius must be finite and non-negative, got {value}"
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
    /// Validates the workspace and caches the distances between its parts (computed with
    /// parry point queries, see [`StarShape::distance_to`]).
    ///
    /// Errors: overlapping obstacles, an obstacle not strictly inside the boundary, a
    /// destination inside an obstacle or outside the workspace.
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
                let (a, b) = (&obstacles[i], &obstacles[j]);
                let (ca, cb) = (a.centre(), b.centre());
                // Bounding circles first: only near pairs need the outline query.
                let lower = (ca - cb).norm() - a.radius_bounds().1 - b.radius_bounds().1;
                let d = if lower > 0.0 && lower > 0.5 * (ca - cb).norm() {
                    lower
                } else {
                    a.distance_to(b)
                };
                if d <= 0.0 || a.contains(cb) || b.contains(ca) {
                    return Err(WorldError::Overlap {
                        first: j,
                        second: i,
                    });
                }
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
