//! [`MapError`]: what went wrong with a ROS map, and in which file.

use std::fmt;
use std::path::{Path, PathBuf};

use harmonav_transform::Shown;

use crate::FloorError;

use super::Cell;

/// Which of the two points given with the map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MapPoint {
    /// The robot's start.
    Start,
    /// The goal `x_d`.
    Goal,
}

impl MapPoint {
    /// `"start"` or `"goal"` (for JSON and messages).
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Start => "start",
            Self::Goal => "goal",
        }
    }
}

impl fmt::Display for MapPoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A ROS map that could not be read or turned into a floor plan: the file ([`MapError::file`],
/// the YAML file or the image) and the problem. Its `Display` is `"<file>: <problem>"`, for a
/// CLI to print as it is.
#[derive(Clone, Debug, PartialEq)]
pub struct MapError {
    /// The file the problem is in: the YAML file for its keys, the start, the goal and the
    /// floor plan built from the map; the image file for the pixels.
    pub file: PathBuf,
    /// What went wrong.
    pub problem: MapProblem,
}

impl MapError {
    pub(crate) fn new(file: &Path, problem: MapProblem) -> Self {
        Self {
            file: file.to_path_buf(),
            problem,
        }
    }
}

impl fmt::Display for MapError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.file.display(), self.problem)
    }
}

impl std::error::Error for MapError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.problem {
            MapProblem::Floor(e) => Some(e),
            _ => None,
        }
    }
}

/// What went wrong with a ROS map ([`MapError`] adds the file).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum MapProblem {
    /// The file could not be read (missing, a folder, no permission): the OS's message.
    Read(String),
    /// The file is larger than its cap (checked before it is read whole).
    TooLarge {
        /// What the file is (`"a map's YAML file"`, `"a map's image"`).
        what: String,
        /// Its size, at least, bytes.
        bytes: u64,
        /// The cap, bytes.
        cap: u64,
    },
    /// The YAML file is not valid YAML, or is not a mapping of keys.
    Yaml(String),
    /// A required key is missing (`field` names it).
    MissingField {
        /// The key.
        field: &'static str,
    },
    /// A key has a value of the wrong type or form.
    InvalidField {
        /// The key.
        field: &'static str,
        /// What it must be.
        expected: &'static str,
        /// What was found (as written in the file, abridged).
        found: String,
    },
    /// `resolution` is not a number of metres per pixel in [`super::RESOLUTION_RANGE`].
    Resolution(f64),
    /// A threshold is not a finite number in `[0, 1]`.
    Threshold {
        /// `free_thresh` or `occupied_thresh`.
        field: &'static str,
        /// Its value.
        value: f64,
    },
    /// `free_thresh ≥ occupied_thresh`: no pixel could be both below the one and not above the
    /// other as map_server's three classes need.
    ThresholdOrder {
        /// `free_thresh`.
        free: f64,
        /// `occupied_thresh`.
        occupied: f64,
    },
    /// The image could not be decoded: truncated, not a PGM or PNG, or an unsupported variant
    /// (the decoder's message).
    Image(String),
    /// The image has no pixels, or more than [`super::MAX_SIDE`] on a side.
    ImageSize {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
    /// A start or goal coordinate is not finite.
    NonFinitePoint(MapPoint),
    /// The point lies outside the image.
    OutsideImage {
        /// Which point.
        point: MapPoint,
        /// Its world coordinates.
        at: [f64; 2],
    },
    /// The point lies in an occupied or unknown pixel (unknown counts as occupied).
    NotFree {
        /// Which point.
        point: MapPoint,
        /// Its world coordinates.
        at: [f64; 2],
        /// The pixel's class.
        cell: Cell,
        /// The pixel (column, row; row 0 at the top of the image).
        pixel: [usize; 2],
    },
    /// `speck_pixels` would drop occupied islands larger than the robot's clearance disc
    /// (`super::max_speck_pixels`): an island that large is an obstacle, not noise.
    SpeckTooLarge {
        /// The speck size asked for, pixels.
        speck_pixels: usize,
        /// The most allowed for this robot and map, pixels.
        most: usize,
        /// The robot's clearance `radius + margin`, m.
        clearance: f64,
        /// The map's resolution, m/pixel.
        resolution: f64,
    },
    /// The goal's free component has more islands (occupied areas inside it, each a hole of
    /// its outline) than [`super::MAX_TRACED_HOLES`]: refused before the outline is simplified.
    TooManyIslands {
        /// The islands counted.
        islands: usize,
        /// The most allowed.
        most: usize,
    },
    /// The start's free pixels are not connected to the goal's (4-connected): the goal cannot
    /// be reached from it.
    Unreachable,
    /// The robot cannot get from the start to the goal: every free path passes a gap narrower
    /// than `2 × clearance` (the robot's diameter plus its margins), or the point itself is
    /// closer than `clearance` to a wall.
    TooNarrow {
        /// The point that is cut off (`Goal`: the goal itself is too close to a wall).
        point: MapPoint,
        /// The clearance the robot needs, `max(radius + margin, δ)` (m).
        clearance: f64,
    },
    /// The outline could not be made into a valid polygon with holes (a geometry step failed;
    /// the message says which).
    Outline(String),
    /// The floor plan built from the outline was refused ([`FloorError`]: e.g. `TooNarrow`,
    /// a passage narrower than the robot; too many elements).
    Floor(FloorError),
    /// The point is in the floor plan but not in its certified region `W_δ`.
    NotCertified {
        /// Which point.
        point: MapPoint,
        /// `sd(x) − δ` (m, negative).
        clearance: f64,
    },
}

impl fmt::Display for MapProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Read(e) => write!(f, "cannot read the file: {e}"),
            Self::TooLarge { what, bytes, cap } => write!(
                f,
                "the file has {bytes} bytes or more; {what} has at most {cap}"
            ),
            Self::Yaml(e) => write!(f, "not a valid map_server YAML file: {e}"),
            Self::MissingField { field } => write!(f, "the key `{field}` is missing"),
            Self::InvalidField {
                field,
                expected,
                found,
            } => write!(f, "`{field}` must be {expected}, found `{found}`"),
            Self::Resolution(r) => write!(
                f,
                "`resolution` must be a number of metres per pixel in [{:e}, {:e}], found {}",
                super::yaml::RESOLUTION_RANGE.0,
                super::yaml::RESOLUTION_RANGE.1,
                Shown(*r)
            ),
            Self::Threshold { field, value } => {
                write!(
                    f,
                    "`{field}` must be a number in [0, 1], found {}",
                    Shown(*value)
                )
            }
            Self::ThresholdOrder { free, occupied } => write!(
                f,
                "`free_thresh` ({}) must be less than `occupied_thresh` ({})",
                Shown(*free),
                Shown(*occupied)
            ),
            Self::Image(e) => write!(
                f,
                "the image cannot be decoded (truncated, or not a PGM or PNG?): {e}"
            ),
            Self::ImageSize { width, height } => write!(
                f,
                "the image is {width} × {height} pixels; it must have pixels and at most {} on \
                 a side",
                super::MAX_SIDE
            ),
            Self::NonFinitePoint(p) => write!(f, "the {p} has a NaN or infinite coordinate"),
            Self::OutsideImage { point, at } => write!(
                f,
                "the {point} ({}, {}) lies outside the map's image",
                Shown(at[0]),
                Shown(at[1])
            ),
            Self::NotFree {
                point,
                at,
                cell,
                pixel,
            } => write!(
                f,
                "the {point} ({}, {}) lies in {} pixel (column {}, row {} from the top)",
                Shown(at[0]),
                Shown(at[1]),
                match cell {
                    Cell::Free => "a free",
                    Cell::Occupied => "an occupied",
                    Cell::Unknown => "an unknown (counted as occupied)",
                },
                pixel[0],
                pixel[1]
            ),
            Self::SpeckTooLarge {
                speck_pixels,
                most,
                clearance,
                resolution,
            } => {
                #[allow(clippy::cast_precision_loss)]
                let area = *speck_pixels as f64 * resolution * resolution;
                write!(
                    f,
                    "`speck_pixels` = {speck_pixels} would drop occupied islands of up to {} \
                     m², larger than the robot's clearance disc π·(radius + margin)² = {} m²: \
                     an island that large is an obstacle, not noise; at most {most} pixels \
                     here",
                    Shown(area),
                    Shown(std::f64::consts::PI * clearance * clearance)
                )
            }
            Self::TooManyIslands { islands, most } => write!(
                f,
                "the free space around the goal holds {islands} occupied islands (holes); at \
                 most {most} are traced, and a floor plan takes at most {} holes after the \
                 robot's opening merges the close ones",
                harmonav_harmonic::domain::MAX_HOLES
            ),
            Self::Unreachable => write!(
                f,
                "the goal is unreachable from the start: they lie in different free areas of \
                 the map"
            ),
            Self::TooNarrow { point, clearance } => match point {
                MapPoint::Goal => write!(
                    f,
                    "the goal is closer than the robot's clearance {} m (radius + \
                     margin, at least δ) to a wall",
                    Shown(*clearance)
                ),
                MapPoint::Start => write!(
                    f,
                    "the robot cannot get from the start to the goal: a passage narrower than \
                     the robot (it needs {} m to each side: radius + margin, at least \
                     δ), or the start is that close to a wall",
                    Shown(*clearance)
                ),
            },
            Self::Outline(e) => write!(f, "the map's outline is not a valid polygon: {e}"),
            Self::Floor(e) => write!(f, "{e}"),
            Self::NotCertified { point, clearance } => write!(
                f,
                "the {point} is {:.4} m inside the boundary layer of the floor plan (not in the \
                 certified region)",
                Shown(-clearance)
            ),
        }
    }
}
