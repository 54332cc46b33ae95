//! A validated workspace: the outer boundary, the (true) obstacles and the destination, with
//! every distance the navigation transformation needs computed once.

use std::sync::atomic::{AtomicU64, Ordering};

use nalgebra::Vector2;

use crate::error::ShapeError;
use crate::index::{DiscIndex, Lookup};
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
    /// [`Workspace::commit`] was given an [`Admitted`] made by [`Workspace::admit`] on a
    /// workspace in another state (another workspace, or this one before a change): its
    /// measured distances do not describe this one.
    StaleAdmission,
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
            Self::StaleAdmission => write!(
                f,
                "the obstacle was admitted by a workspace in another state; admit it again"
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
    /// `d(O_i, O_j)` of the near pairs (those [`separation`] measures on the outlines), sorted
    /// by `j`, per obstacle `i`; a far pair's gap is its bounding discs' ([`separation`]),
    /// computed when asked. `O(M)` memory instead of the `M × M` table of before.
    near: Vec<Vec<(usize, f64)>>,
    /// The obstacles' bounding discs `(c_i, max R_i)`, indexed.
    index: DiscIndex,
    /// How the queries over the obstacles are answered.
    lookup: Lookup,
    /// `d(O_i, ∂O_0)`.
    to_boundary: Vec<f64>,
    /// `d(x_d, O_i)`.
    goal_to_obstacle: Vec<f64>,
    /// `d(x_d, ∂O_0)`.
    goal_to_boundary: f64,
    /// `max_i max R_i` (0 with no obstacle): the reach of the near-pair queries.
    r_max: f64,
    /// The state's token ([`fresh_stamp`]): new at construction and at every change, copied by
    /// a clone (the same state), recorded by [`Workspace::admit`] and checked by
    /// [`Workspace::commit`].
    stamp: u64,
}

/// A token no workspace state has had before in this process.
fn fresh_stamp() -> u64 {
    static NEXT: AtomicU64 = AtomicU64::new(0);
    NEXT.fetch_add(1, Ordering::Relaxed)
}

/// An obstacle [`Workspace::admit`] validated as obstacle `M` of a workspace, with the
/// distances it measured, for [`Workspace::commit`].
#[derive(Clone, Debug)]
pub struct Admitted {
    /// The obstacle.
    obstacle: StarShape,
    /// Its index `M`.
    index: usize,
    /// Its near pairs `(j, d(O_M, O_j))`, sorted by `j`.
    row: Vec<(usize, f64)>,
    /// `d(O_M, ∂O_0)`.
    to_boundary: f64,
    /// `d(x_d, O_M)` (signed).
    goal: f64,
    /// `max R` over the obstacles with it.
    r_max: f64,
    /// The admitting workspace's state token.
    stamp: u64,
}

impl Admitted {
    /// The admitted obstacle `O_M`.
    #[must_use]
    pub fn obstacle(&self) -> &StarShape {
        &self.obstacle
    }

    /// Its index `M` in the workspace.
    #[must_use]
    pub fn index(&self) -> usize {
        self.index
    }

    /// Its certified clearance `d(O_M, ∂O_0)` ([`StarShape::clearance_inside`]).
    #[must_use]
    pub fn to_boundary(&self) -> f64 {
        self.to_boundary
    }
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
        Self::with_lookup(boundary, obstacles, destination, Lookup::default())
    }

    /// [`Self::new`] with the queries over the obstacles answered by `lookup` (the same
    /// workspace, the same errors, bit for bit: [`Lookup`]). With [`Lookup::Indexed`] the pair
    /// checks test only the pairs whose bounding discs the index cannot rule out (`O(M log M)`
    /// for obstacles of bounded size instead of `M(M − 1)/2` pairs), and so do every later
    /// query of this workspace, its [`Self::with_obstacle`] and its [`crate::NavTransform`]s.
    pub fn with_lookup(
        boundary: StarShape,
        obstacles: Vec<StarShape>,
        destination: Vector2<f64>,
        lookup: Lookup,
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
        let index = DiscIndex::new(obstacles.iter().map(|o| (o.centre(), o.radius_bounds().1)));
        let r_max = obstacles
            .iter()
            .map(|o| o.radius_bounds().1)
            .fold(0.0, f64::max);
        let mut near = vec![Vec::new(); m];
        let mut candidates = Vec::new();
        for i in 0..m {
            // The pairs (i, j < i) in the order of j, as the direct loop meets them; only a near
            // pair can fail.
            candidates.clear();
            match lookup {
                Lookup::Direct => candidates.extend(0..i),
                Lookup::Indexed => {
                    let o = &obstacles[i];
                    index.near(o.centre(), near_reach(o, r_max), |j| {
                        if j < i {
                            candidates.push(j);
                        }
                    });
                    candidates.sort_unstable();
                }
            }
            for &j in &candidates {
                if let Some(d) = measured(&obstacles[i], &obstacles[j]) {
                    let d = d.ok_or(WorldError::Overlap {
                        first: j,
                        second: i,
                    })?;
                    near[i].push((j, d));
                    near[j].push((i, d));
                }
            }
        }
        for row in &mut near {
            row.sort_unstable_by_key(|&(j, _)| j);
        }
        let mut ws = Self {
            boundary,
            obstacles,
            destination,
            near,
            index,
            lookup,
            to_boundary,
            goal_to_obstacle: Vec::new(),
            goal_to_boundary: 0.0,
            r_max,
            stamp: fresh_stamp(),
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
    /// distances extended by its row alone: the distance queries of the obstacles near it
    /// (found by the index) instead of `O(M²)`. Used when obstacles become known one at a time;
    /// [`Self::push_obstacle`] does the same in place, without the copy of the `M` obstacles.
    ///
    /// Errors: the obstacle overlaps or touches obstacle `first` ([`WorldError::Overlap`] with
    /// `second = M`), is not strictly inside the boundary, or contains the destination.
    pub fn with_obstacle(&self, obstacle: StarShape) -> Result<Self, WorldError> {
        let admitted = self.admit(obstacle)?;
        let mut ws = self.clone();
        ws.commit(admitted)?;
        Ok(ws)
    }

    /// [`Self::with_obstacle`] in place: `obstacle` becomes obstacle `M + 1` (index `M`, which
    /// is returned). Its row is measured and validated first and only then appended (with its
    /// distance to each near obstacle added to that obstacle's row), so on error the workspace
    /// is unchanged. Cost: the new obstacle's own distances (to the boundary, the destination
    /// and its near obstacles) and `O(log M)` for the index; nothing is copied.
    ///
    /// Errors: those of [`Self::with_obstacle`].
    pub fn push_obstacle(&mut self, obstacle: StarShape) -> Result<usize, WorldError> {
        let admitted = self.admit(obstacle)?;
        self.commit(admitted)
    }

    /// The first half of [`Self::push_obstacle`]: `obstacle` validated as obstacle `M` and its
    /// cached distances measured (its clearance `d(O_M, ∂O_0)`, its near pairs `d(O_M, O_j)`:
    /// the index's candidates within reach, each measured on the outlines, and its signed
    /// distance to `x_d`), without changing the workspace. A caller that has more to check
    /// before a discovery takes effect (`Field::push_obstacle`) checks it between this and
    /// [`Self::commit`].
    ///
    /// Errors: those of [`Self::with_obstacle`].
    pub fn admit(&self, obstacle: StarShape) -> Result<Admitted, WorldError> {
        let m = self.obstacles.len();
        let to_boundary = obstacle.clearance_inside(&self.boundary);
        if to_boundary <= 0.0 || !self.boundary.contains(obstacle.centre()) {
            return Err(WorldError::OutsideBoundary { obstacle: m });
        }
        let r_max = self.r_max.max(obstacle.radius_bounds().1);
        let mut candidates = Vec::new();
        match self.lookup {
            Lookup::Direct => candidates.extend(0..m),
            Lookup::Indexed => {
                self.index
                    .near(obstacle.centre(), near_reach(&obstacle, r_max), |j| {
                        candidates.push(j)
                    });
                candidates.sort_unstable();
            }
        }
        let mut row = Vec::new();
        for &j in &candidates {
            if let Some(d) = measured(&obstacle, &self.obstacles[j]) {
                row.push((
                    j,
                    d.ok_or(WorldError::Overlap {
                        first: j,
                        second: m,
                    })?,
                ));
            }
        }
        if obstacle.contains(self.destination) {
            return Err(WorldError::InObstacle {
                what: "destination",
                obstacle: m,
            });
        }
        Ok(Admitted {
            index: m,
            row,
            to_boundary,
            goal: obstacle.signed_distance(self.destination),
            r_max,
            obstacle,
            stamp: self.stamp,
        })
    }

    /// The second half of [`Self::push_obstacle`]: appends the obstacle that [`Self::admit`]
    /// admitted, with what it measured, and returns its index `M`.
    ///
    /// Errors: [`WorldError::StaleAdmission`] (nothing changes) unless the workspace is in the
    /// state that admitted the obstacle (the same workspace unchanged since, or a clone of it):
    /// the admission's distances were measured against that state's obstacles.
    pub fn commit(&mut self, admitted: Admitted) -> Result<usize, WorldError> {
        let m = self.obstacles.len();
        if admitted.stamp != self.stamp {
            return Err(WorldError::StaleAdmission);
        }
        debug_assert_eq!(admitted.index, m, "one state, one obstacle count");
        let obstacle = admitted.obstacle;
        for &(j, d) in &admitted.row {
            // Rows stay sorted: m is the largest index.
            self.near[j].push((m, d));
        }
        self.near.push(admitted.row);
        self.index
            .push(obstacle.centre(), obstacle.radius_bounds().1);
        self.obstacles.push(obstacle);
        self.to_boundary.push(admitted.to_boundary);
        self.goal_to_obstacle.push(admitted.goal);
        self.r_max = admitted.r_max;
        self.stamp = fresh_stamp();
        Ok(m)
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

    /// `d(O_i, O_j)` as [`Self::new`] measured it (`∞` for `i = j`): a near pair's from the
    /// cache, a far pair's bounding-disc gap recomputed (the same expression, so the same
    /// bits).
    pub(crate) fn between(&self, i: usize, j: usize) -> f64 {
        if i == j {
            return f64::INFINITY;
        }
        let (a, b) = (i.max(j), i.min(j));
        match far_gap(&self.obstacles[a], &self.obstacles[b]) {
            Some(d) => d,
            None => self.near[i]
                .binary_search_by_key(&j, |&(j, _)| j)
                .map_or(f64::NAN, |k| self.near[i][k].1),
        }
    }

    /// The near pairs of obstacle `i` (`j`, `d(O_i, O_j)`), sorted by `j`: every pair whose
    /// gap is not its bounding discs'.
    pub(crate) fn near_pairs(&self, i: usize) -> &[(usize, f64)] {
        &self.near[i]
    }

    /// How the queries over the obstacles are answered.
    #[must_use]
    pub fn lookup(&self) -> Lookup {
        self.lookup
    }

    /// The index of the obstacles' bounding discs `(c_i, max R_i)`, leaf `i` obstacle `i`.
    #[must_use]
    pub fn index(&self) -> &DiscIndex {
        &self.index
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

/// The gap of two obstacles whose bounding circles are apart by more than half their centre
/// distance: that gap, a lower bound of the distance; `None` for a near pair. `a` is the
/// obstacle of the larger index (the order of the subtractions is part of the value).
fn far_gap(a: &StarShape, b: &StarShape) -> Option<f64> {
    let n = (a.centre() - b.centre()).norm();
    let lower = n - a.radius_bounds().1 - b.radius_bounds().1;
    (lower > 0.0 && lower > 0.5 * n).then_some(lower)
}

/// The distance of a near pair measured on the outlines ([`StarShape::distance_to`]):
/// `Some(Some(d))`, `Some(None)` if they overlap or touch; `None` for a far pair
/// ([`far_gap`], never overlapping). `a` is the obstacle of the larger index.
fn measured(a: &StarShape, b: &StarShape) -> Option<Option<f64>> {
    if far_gap(a, b).is_some() {
        return None;
    }
    let d = a.distance_to(b);
    Some((d > 0.0 && !a.contains(b.centre()) && !b.contains(a.centre())).then_some(d))
}

/// The reach of a query about `o`'s centre that meets every obstacle (bounding radius at most
/// `r_max`) forming a near pair with it: a near pair has `|c_a − c_b| ≤ 2(R_a + R_b)` (the
/// negation of [`far_gap`]'s test), so the other's bounding disc comes within `2R_a + R_b ≤
/// 2R_a + r_max` of `c_a`; padded by `2⁻²⁰` of it against rounding.
fn near_reach(o: &StarShape, r_max: f64) -> f64 {
    (2.0 * o.radius_bounds().1 + r_max) * (1.0 + 2f64.powi(-20))
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
