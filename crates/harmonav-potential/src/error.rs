//! Typed errors of the point-world potential.

use std::fmt;

/// A point world that violates the hypotheses of the paper, or a kernel call with bad buffers.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum PotentialError {
    /// Lemma `attactive` needs `k > M`; `k` must also be finite.
    KNotAttractive {
        /// The rejected `k`.
        k: f64,
        /// The number of obstacle points `M`.
        obstacles: usize,
    },
    /// A coordinate of the destination (`index = None`) or of obstacle point `index` is NaN or
    /// infinite.
    NonFinite {
        /// `None` for the destination, `Some(i)` for obstacle point `i`.
        index: Option<usize>,
    },
    /// Obstacle point `index` coincides with the destination: `phi_k` is undefined there.
    ObstacleAtDestination {
        /// The obstacle's index.
        index: usize,
    },
    /// Two obstacle points coincide (the point world needs distinct points).
    DuplicateObstacle {
        /// The first obstacle's index.
        first: usize,
        /// The second obstacle's index.
        second: usize,
    },
    /// The buffers handed to a batched evaluation ([`crate::BatchGradient::eval`],
    /// [`crate::PointWorld::phi_and_grad_many`]) differ in length.
    LengthMismatch {
        /// Lengths of the inputs `hx`, `hy` and the outputs `gx`, `gy` (for
        /// `phi_and_grad_many`: the points twice, the outputs twice).
        lengths: [usize; 4],
    },
    /// An argument of a constructor outside its domain (named, with the requirement).
    InvalidArgument {
        /// What is wrong, e.g. "mu must be at least 1".
        problem: &'static str,
    },
    /// A query point of the batched kernel is a singular point (the destination or an obstacle
    /// point) or not finite, so its gradient is undefined.
    SingularQuery {
        /// The index of the first such query point.
        index: usize,
    },
}

impl fmt::Display for PotentialError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::KNotAttractive { k, obstacles } => write!(
                f,
                "k = {k} is not allowed with {obstacles} obstacle points: lemma `attactive` needs a finite k > M = {obstacles}"
            ),
            Self::NonFinite { index: None } => {
                write!(f, "the destination has a NaN or infinite coordinate")
            }
            Self::NonFinite { index: Some(i) } => {
                write!(f, "obstacle point {i} has a NaN or infinite coordinate")
            }
            Self::ObstacleAtDestination { index } => {
                write!(f, "obstacle point {index} coincides with the destination")
            }
            Self::DuplicateObstacle { first, second } => {
                write!(f, "obstacle points {first} and {second} coincide")
            }
            Self::LengthMismatch { lengths } => write!(
                f,
                "batched buffers differ in length (inputs x, y; outputs x, y) = {lengths:?}"
            ),
            Self::InvalidArgument { problem } => write!(f, "invalid argument: {problem}"),
            Self::SingularQuery { index } => write!(
                f,
                "query point {index} is the destination, an obstacle point or not finite: the gradient is undefined there"
            ),
        }
    }
}

impl std::error::Error for PotentialError {}

/// A point of the extended point world where `phi_k` is not differentiable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Singularity {
    /// The destination `P_d` (`phi_k = −∞`, `varphi = 0`).
    Destination,
    /// Obstacle point `P_i` (`phi_k = +∞`, `varphi = 1`).
    Obstacle(usize),
}

impl fmt::Display for Singularity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Destination => write!(f, "the destination P_d"),
            Self::Obstacle(i) => write!(f, "obstacle point P_{i}"),
        }
    }
}

impl std::error::Error for Singularity {}
