//! Typed errors of shapes and navigation transformations.

use std::fmt;

/// A shape description that cannot be used (the field names follow the scenario format).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ShapeError {
    /// A NaN or infinite number in `field`.
    NonFinite {
        /// The offending field.
        field: &'static str,
    },
    /// A size that must be positive is not.
    NotPositive {
        /// The offending field.
        field: &'static str,
        /// Its value.
        value: f64,
    },
    /// Any other problem with `field`, explained.
    Invalid {
        /// The offending field.
        field: &'static str,
        /// What is wrong.
        problem: String,
    },
}

impl ShapeError {
    /// What is wrong, without the field: for a caller that names the field itself (the
    /// offset's own parameter is called `robot.radius`, but a navigator grows a shape by
    /// `radius + margin`, and the shape at fault is the obstacle; issue 56, D19.10).
    #[must_use]
    pub fn problem(&self) -> String {
        match self {
            Self::NonFinite { .. } => "NaN or infinite number".into(),
            Self::NotPositive { value, .. } => format!("must be positive, got {value:e}"),
            Self::Invalid { problem, .. } => problem.clone(),
        }
    }
}

impl fmt::Display for ShapeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NonFinite { field } => write!(f, "`{field}`: NaN or infinite number"),
            Self::NotPositive { field, value } => {
                write!(f, "`{field}`: must be positive, got {value:e}")
            }
            Self::Invalid { field, problem } => write!(f, "`{field}`: {problem}"),
        }
    }
}

impl std::error::Error for ShapeError {}
