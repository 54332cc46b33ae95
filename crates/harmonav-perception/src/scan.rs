//! The `sensor_msgs/LaserScan` input, validated, and the sensor pose.
//!
//! Beam `i` points along `α_i = yaw + angle_min + i·Δθ` (`Δθ = angle_increment`) from the
//! sensor position `s`; a hit of range `r_i` is the point `p_i = s + r_i·(cos α_i, sin α_i)`.
//! Readings are classified as ROS does (REP 117):
//!
//! | reading | class | meaning |
//! |---|---|---|
//! | `range_min ≤ r < range_max` | [`Reading::Hit`] | a return: the true first hit is within `range_noise` of `r` |
//! | `+∞`, or finite `r ≥ range_max` | [`Reading::NoReturn`] | free-space evidence along the beam up to `range_max − ε` (A1: a true hit in the last `ε` may read `≥ range_max`) |
//! | `−∞` | [`Reading::TooClose`] | something nearer than `range_min`; no usable point |
//! | NaN, or finite `r < range_min` | [`Reading::Invalid`] | no information |

use std::f64::consts::TAU;
use std::fmt;

use harmonav_transform::{MAX_LENGTH, Shown};
use nalgebra::Vector2;

/// The most beams a scan may have (a 0.01° scanner has 36 000).
pub const MAX_BEAMS: usize = 1_000_000;

/// The largest angle a pose's yaw or a scan's `angle_min` may have, in magnitude, rad: beyond,
/// `cos` and `sin` of the beams' angles lose their digits.
pub const MAX_ANGLE: f64 = 1e6;

/// The sensor pose in the world frame: position `(x, y)` (m) and heading `yaw` (rad, the
/// direction of the scan's angle 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// `x`, m.
    pub x: f64,
    /// `y`, m.
    pub y: f64,
    /// Heading, rad.
    pub yaw: f64,
}

impl Pose {
    /// The pose `(x, y, yaw)`.
    #[must_use]
    pub fn new(x: f64, y: f64, yaw: f64) -> Self {
        Self { x, y, yaw }
    }

    /// The position `s = (x, y)`.
    #[must_use]
    pub fn position(&self) -> Vector2<f64> {
        Vector2::new(self.x, self.y)
    }

    /// Errors if a field is not finite or beyond [`MAX_LENGTH`] (or `|yaw| > 1e6` rad).
    pub fn validate(&self) -> Result<(), ScanError> {
        for (v, field, cap) in [
            (self.x, "pose.x", MAX_LENGTH),
            (self.y, "pose.y", MAX_LENGTH),
            (self.yaw, "pose.yaw", MAX_ANGLE),
        ] {
            if !v.is_finite() || v.abs() > cap {
                return Err(ScanError::NotFinite { field });
            }
        }
        Ok(())
    }
}

/// A planar laser scan with the fields of `sensor_msgs/LaserScan` that the geometry needs
/// (`angle_max = angle_min + (n − 1)·angle_increment` is implied by `ranges.len() = n`).
#[derive(Clone, Debug, PartialEq)]
pub struct LaserScan {
    /// Angle of the first beam in the sensor frame, rad.
    pub angle_min: f64,
    /// Angle between neighbouring beams `Δθ > 0`, rad (counter-clockwise).
    pub angle_increment: f64,
    /// Smallest valid range, m (`≥ 0`).
    pub range_min: f64,
    /// Largest valid range, m (`> range_min`); a reading at or beyond it is a no-return.
    pub range_max: f64,
    /// The ranges, m, one per beam, in angular order.
    pub ranges: Vec<f64>,
}

/// The class of one reading (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reading {
    /// A return at this range, m.
    Hit(f64),
    /// No return within `range_max`: the beam is free up to `range_max − ε` ([`LaserScan::free_until`]).
    NoReturn,
    /// `−∞`: something nearer than `range_min`.
    TooClose,
    /// NaN or below `range_min`: no information.
    Invalid,
}

/// A scan that cannot be used.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ScanError {
    /// No beams.
    Empty,
    /// More than [`MAX_BEAMS`] beams.
    TooManyBeams {
        /// The count.
        count: usize,
    },
    /// A field that must be finite (and at most [`MAX_LENGTH`]) is not.
    NotFinite {
        /// The field.
        field: &'static str,
    },
    /// `angle_increment` is not positive (a reversed scan must be reordered by the caller).
    NonPositiveIncrement {
        /// Its value.
        value: f64,
    },
    /// `range_min < 0` or `range_max ≤ range_min`.
    RangeLimits {
        /// `range_min`.
        range_min: f64,
        /// `range_max`.
        range_max: f64,
    },
    /// `n·Δθ` exceeds a full turn by more than half a beam: beams would overlap.
    Overlapping {
        /// `n·Δθ`, rad.
        aperture: f64,
    },
}

impl fmt::Display for ScanError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Empty => write!(f, "the scan has no ranges"),
            Self::TooManyBeams { count } => {
                write!(
                    f,
                    "the scan has {count} beams, more than MAX_BEAMS = {MAX_BEAMS}"
                )
            }
            // The angles are capped at `MAX_ANGLE` rad (the pose's yaw is the scan's heading),
            // the lengths at `MAX_LENGTH` m.
            Self::NotFinite {
                field: field @ ("pose.yaw" | "angle_min"),
            } => write!(
                f,
                "`{field}` must be finite and at most {MAX_ANGLE:e} rad in magnitude"
            ),
            Self::NotFinite {
                field: "angle_increment",
            } => write!(f, "`angle_increment` must be finite"),
            Self::NotFinite { field } => {
                write!(
                    f,
                    "`{field}` must be finite and at most {MAX_LENGTH:e} in magnitude"
                )
            }
            Self::NonPositiveIncrement { value } => {
                write!(f, "`angle_increment` must be positive, got {value:e}")
            }
            Self::RangeLimits {
                range_min,
                range_max,
            } => write!(
                f,
                "need 0 ≤ range_min < range_max, got range_min = {range_min:e}, range_max = {range_max:e}"
            ),
            Self::Overlapping { aperture } => write!(
                f,
                "the beams cover {:.4} rad, more than a full turn: they would overlap",
                Shown(*aperture)
            ),
        }
    }
}

impl std::error::Error for ScanError {}

impl LaserScan {
    /// Checks the scan: non-empty, at most [`MAX_BEAMS`], finite angles (`|angle_min| ≤ 1e6`),
    /// `Δθ > 0`, `0 ≤ range_min < range_max ≤` [`MAX_LENGTH`], `n·Δθ ≤ 2π + Δθ/2`. Individual
    /// ranges may be anything (they are classified, never rejected).
    pub fn validate(&self) -> Result<(), ScanError> {
        let n = self.ranges.len();
        if n == 0 {
            return Err(ScanError::Empty);
        }
        if n > MAX_BEAMS {
            return Err(ScanError::TooManyBeams { count: n });
        }
        if !self.angle_min.is_finite() || self.angle_min.abs() > MAX_ANGLE {
            return Err(ScanError::NotFinite { field: "angle_min" });
        }
        if !self.angle_increment.is_finite() {
            return Err(ScanError::NotFinite {
                field: "angle_increment",
            });
        }
        if self.angle_increment <= 0.0 {
            return Err(ScanError::NonPositiveIncrement {
                value: self.angle_increment,
            });
        }
        for (v, field) in [(self.range_min, "range_min"), (self.range_max, "range_max")] {
            if !v.is_finite() || v.abs() > MAX_LENGTH {
                return Err(ScanError::NotFinite { field });
            }
        }
        if self.range_min < 0.0 || self.range_max <= self.range_min {
            return Err(ScanError::RangeLimits {
                range_min: self.range_min,
                range_max: self.range_max,
            });
        }
        let aperture = n as f64 * self.angle_increment;
        if aperture > TAU + 0.5 * self.angle_increment {
            return Err(ScanError::Overlapping { aperture });
        }
        Ok(())
    }

    /// Whether the beams close a full turn (`|n·Δθ − 2π| ≤ Δθ/2`): the last beam is then the
    /// first one's neighbour.
    #[must_use]
    pub fn full_turn(&self) -> bool {
        (self.ranges.len() as f64 * self.angle_increment - TAU).abs() <= 0.5 * self.angle_increment
    }

    /// The class of reading `i` (module docs).
    #[must_use]
    pub fn reading(&self, i: usize) -> Reading {
        let r = self.ranges[i];
        if r.is_nan() {
            Reading::Invalid
        } else if r == f64::NEG_INFINITY {
            Reading::TooClose
        } else if r >= self.range_max {
            Reading::NoReturn
        } else if r < self.range_min {
            Reading::Invalid
        } else {
            Reading::Hit(r)
        }
    }

    /// The world angle `α_i = yaw + angle_min + i·Δθ` of beam `i`.
    #[must_use]
    pub fn angle(&self, pose: &Pose, i: usize) -> f64 {
        pose.yaw + self.angle_min + i as f64 * self.angle_increment
    }

    /// The unit direction `u_i = (cos α_i, sin α_i)` of beam `i`.
    #[must_use]
    pub fn direction(&self, pose: &Pose, i: usize) -> Vector2<f64> {
        let a = self.angle(pose, i);
        Vector2::new(a.cos(), a.sin())
    }

    /// How far along beam `i` the scan shows free space, m: up to `r − ε` for a hit of range `r`
    /// with noise bound `ε` (the true first hit is at `≥ r − ε`), `range_max − ε` for a
    /// no-return (under A1 a true hit in the last `ε` of the range may read `≥ range_max`), 0
    /// otherwise.
    #[must_use]
    pub fn free_until(&self, i: usize, range_noise: f64) -> f64 {
        match self.reading(i) {
            Reading::Hit(r) => (r - range_noise).max(0.0),
            Reading::NoReturn => (self.range_max - range_noise).max(0.0),
            Reading::TooClose | Reading::Invalid => 0.0,
        }
    }
}
