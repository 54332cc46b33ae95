//! [`FloorMap`]: the static floor plan (walls), its harmonic map `H` onto the punctured disk,
//! and the certified region `W_δ` in which navigation is claimed.

use harmonav_harmonic::{
    Certificate, CertifyError, CertifyOptions, Domain, DomainError, HarmonicMap, MeshOptions,
    SolveError, certify,
};
use nalgebra::Vector2;
use parry2d_f64::math::Vector as PVector;
use parry2d_f64::query::PointQuery;
use parry2d_f64::shape::Polyline;

/// Why a floor plan could not be built.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum FloorError {
    /// The rings do not form a valid polygon with holes (the problem is named).
    Domain(DomainError),
    /// The boundary-element solve failed (too many elements, or a singular system).
    Solve(SolveError),
    /// An option is out of range (`field` names it).
    InvalidOption {
        /// The option.
        field: &'static str,
        /// Its value.
        value: f64,
    },
    /// The goal is not in the certified region `W_δ` (closer than `δ` to a wall, or outside).
    GoalNotCertified {
        /// Its signed distance to the walls (positive inside).
        clearance: f64,
        /// `δ`.
        delta: f64,
    },
    /// A sensed obstacle's bounding disc reaches into the boundary layer (closer than `δ` to a
    /// wall): it is not inside `W_δ`.
    ObstacleNearWall {
        /// The sensed obstacle (its index in the order added).
        obstacle: usize,
    },
    /// A sensed obstacle overlaps or touches another sensed obstacle.
    Overlap {
        /// The earlier obstacle.
        first: usize,
        /// The later one.
        second: usize,
    },
    /// A sensed obstacle contains the goal.
    ContainsGoal {
        /// The obstacle.
        obstacle: usize,
    },
    /// The point world could not be formed (two points coincide in the disk, to rounding).
    Potential(harmonav_potential::PotentialError),
    /// The goal maps outside the disk or onto a puncture (a map that failed there).
    Map(harmonav_harmonic::EvalError),
}

impl std::fmt::Display for FloorError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Domain(e) => write!(f, "the floor plan: {e}"),
            Self::Solve(e) => write!(f, "the harmonic map: {e}"),
            Self::InvalidOption { field, value } => {
                write!(f, "`{field}` must be finite and positive, got {value:e}")
            }
            Self::GoalNotCertified { clearance, delta } => write!(
                f,
                "the goal is {clearance:.4} m from the walls, not in the certified region \
                 (at least δ = {delta:.4} m from every wall)"
            ),
            Self::ObstacleNearWall { obstacle } => write!(
                f,
                "sensed obstacle {obstacle} reaches within δ of a wall (its bounding disc leaves \
                 the certified region)"
            ),
            Self::Overlap { first, second } => {
                write!(f, "sensed obstacles {first} and {second} overlap")
            }
            Self::ContainsGoal { obstacle } => {
                write!(f, "sensed obstacle {obstacle} contains the goal")
            }
            Self::Potential(e) => write!(f, "the point world: {e}"),
            Self::Map(e) => write!(f, "the harmonic map at the goal: {e}"),
        }
    }
}

impl std::error::Error for FloorError {}

impl From<DomainError> for FloorError {
    fn from(e: DomainError) -> Self {
        Self::Domain(e)
    }
}

impl From<SolveError> for FloorError {
    fn from(e: SolveError) -> Self {
        Self::Solve(e)
    }
}

impl From<harmonav_potential::PotentialError> for FloorError {
    fn from(e: harmonav_potential::PotentialError) -> Self {
        Self::Potential(e)
    }
}

/// Options of [`FloorMap::new`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FloorOptions {
    /// Largest boundary element `h` (m), graded toward corners ([`MeshOptions::graded`]).
    pub max_element: f64,
    /// The clearance the robot keeps from every wall: `radius + margin` (m, ≥ 0).
    pub clearance: f64,
}

impl FloorOptions {
    /// Elements of at most `max_element` and the clearance `radius + margin`.
    #[must_use]
    pub fn new(max_element: f64, clearance: f64) -> Self {
        Self {
            max_element,
            clearance,
        }
    }
}

/// Twice the signed area of a ring (positive counter-clockwise).
fn twice_area(ring: &[Vector2<f64>]) -> f64 {
    let n = ring.len();
    (0..n)
        .map(|i| {
            let (a, b) = (ring[i], ring[(i + 1) % n]);
            a.x * b.y - b.x * a.y
        })
        .sum()
}

/// The ring in the orientation `ccw` (reversed if it has the other one).
fn oriented(mut ring: Vec<Vector2<f64>>, ccw: bool) -> Vec<Vector2<f64>> {
    if (twice_area(&ring) > 0.0) != ccw {
        ring.reverse();
    }
    ring
}

/// A floor plan with its harmonic map: the walls (an outer polygon and polygonal holes, which
/// may be of any shape: U, L, walls on the outer ring), `H` solved once (docs/maths.md §11), and
/// the certified region
///
/// ```text
/// W_δ = { x : sd(x) ≥ δ },   δ = max(radius + margin, h_max)
/// ```
///
/// with `sd` the signed distance to the walls and `h_max` the longest boundary element. The
/// map is built on the walls themselves, so `W_δ` is the robot's configuration space with its
/// margin (`radius + margin − δ = 0` in the issue's terms); when `radius + margin < h_max` the
/// robot keeps `δ = h_max` instead, the boundary layer in which the discrete map may fold, and
/// [`FloorMap::keeps_delta`] says so.
#[derive(Clone, Debug)]
pub struct FloorMap {
    map: HarmonicMap,
    /// Every wall segment (all rings), for parry's distance queries.
    walls: Polyline,
    delta: f64,
    clearance: f64,
}

impl FloorMap {
    /// Validates the rings (either orientation is accepted: the outer ring is made
    /// counter-clockwise and the holes clockwise), meshes and solves `H` (one LU,
    /// `O((N + M)³)`), and sets `δ = max(clearance, h_max)`.
    ///
    /// # Errors
    /// [`FloorError::InvalidOption`] for a non-positive or non-finite `max_element` or a
    /// negative `clearance`; [`FloorError::Domain`] for invalid rings (self-crossing, holes
    /// outside or touching, …); [`FloorError::Solve`] when the solve fails.
    pub fn new(
        outer: Vec<Vector2<f64>>,
        holes: Vec<Vec<Vector2<f64>>>,
        options: &FloorOptions,
    ) -> Result<Self, FloorError> {
        let h = options.max_element;
        if !(h.is_finite() && h > 0.0) {
            return Err(FloorError::InvalidOption {
                field: "max_element",
                value: h,
            });
        }
        let c = options.clearance;
        if !(c.is_finite() && c >= 0.0) {
            return Err(FloorError::InvalidOption {
                field: "clearance",
                value: c,
            });
        }
        let outer = oriented(outer, true);
        let holes: Vec<_> = holes.into_iter().map(|r| oriented(r, false)).collect();
        let domain = Domain::new(outer, holes)?;
        let map = HarmonicMap::new(&domain, &MeshOptions::graded(h))?;
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        for ring in std::iter::once(domain.outer()).chain(domain.holes().iter().map(Vec::as_slice))
        {
            let base = vertices.len() as u32;
            let n = ring.len() as u32;
            vertices.extend(ring.iter().map(|p| PVector::new(p.x, p.y)));
            indices.extend((0..n).map(|i| [base + i, base + (i + 1) % n]));
        }
        let walls = Polyline::new(vertices, Some(indices));
        let delta = c.max(map.max_element_length());
        Ok(Self {
            map,
            walls,
            delta,
            clearance: c,
        })
    }

    /// The harmonic map `H`.
    #[must_use]
    pub fn map(&self) -> &HarmonicMap {
        &self.map
    }

    /// The walls as a validated domain.
    #[must_use]
    pub fn domain(&self) -> &Domain {
        self.map.domain()
    }

    /// `δ = max(radius + margin, h_max)`: the certified region is `W_δ = {sd ≥ δ}`.
    #[must_use]
    pub fn delta(&self) -> f64 {
        self.delta
    }

    /// `true` when `radius + margin < h_max`: the robot keeps the larger `δ = h_max` from the
    /// walls (the discrete map is only claimed a diffeomorphism there).
    #[must_use]
    pub fn keeps_delta(&self) -> bool {
        self.clearance < self.delta
    }

    /// The distance from `x` to the nearest wall (parry's point query on the wall segments),
    /// exact to rounding.
    #[must_use]
    pub fn wall_distance(&self, x: Vector2<f64>) -> f64 {
        self.walls
            .distance_to_local_point(PVector::new(x.x, x.y), false)
    }

    /// The signed distance `sd(x)` to the walls: positive in the free space, negative in a
    /// hole or beyond the outer ring. 1-Lipschitz.
    #[must_use]
    pub fn signed_distance(&self, x: Vector2<f64>) -> f64 {
        let d = self.wall_distance(x);
        if self.domain().contains(x) { d } else { -d }
    }

    /// A lower bound on the distance from `x ∈ W_δ` to the boundary layer: `sd(x) − δ` (exact:
    /// `sd` is 1-Lipschitz, so every `y` with `sd(y) < δ` is farther than `sd(x) − δ`). Negative
    /// in the layer and outside.
    #[must_use]
    pub fn clearance(&self, x: Vector2<f64>) -> f64 {
        self.signed_distance(x) - self.delta
    }

    /// The Lipschitz certificate of `det J_H > 0` and `|H| < 1` on all of `W_δ`
    /// ([`harmonav_harmonic::certify`], `O(N)` per cell) with at most `max_evaluations` cells.
    ///
    /// # Errors
    /// [`CertifyError`] when `δ` is out of range or the first grid exceeds the budget.
    pub fn certify(&self, max_evaluations: usize) -> Result<Certificate, CertifyError> {
        let mut options = CertifyOptions::new(self.delta);
        options.max_evaluations = max_evaluations;
        certify(&self.map, &options)
    }
}
