//! The sector, detection, `d_min` and the initially known obstacles.

use std::f64::consts::{PI, TAU};

use harmonav_transform::{StarShape, Workspace};
use nalgebra::Vector2;

/// A sensor description that cannot be used (field names follow the scenario format).
#[derive(Clone, Debug, PartialEq)]
pub enum SensorError {
    /// `range` is not finite and positive.
    Range(f64),
    /// The aperture is outside `(0, 2π]` (`(0, 360]` degrees).
    Aperture(f64),
}

impl std::fmt::Display for SensorError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Range(r) => write!(f, "`sensor.range`: must be finite and positive, got {r:e}"),
            Self::Aperture(a) => write!(
                f,
                "`sensor.aperture_deg`: must be in (0, 360], got {:e}",
                a.to_degrees()
            ),
        }
    }
}

impl std::error::Error for SensorError {}

/// The symmetric sensing sector `S_{r,θ}` (eq. `sensing`): range `r`, aperture `θ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sector {
    range: f64,
    aperture: f64,
    /// `(cos θ/2, sin θ/2)`, cached for the per-step tests.
    half: (f64, f64),
}

impl Sector {
    /// A sector of range `r > 0` and aperture `θ ∈ (0, 2π]` (radians).
    pub fn new(range: f64, aperture: f64) -> Result<Self, SensorError> {
        if !(range.is_finite() && range > 0.0) {
            return Err(SensorError::Range(range));
        }
        if !(aperture > 0.0 && aperture <= TAU) {
            return Err(SensorError::Aperture(aperture));
        }
        let (sin, cos) = (0.5 * aperture).sin_cos();
        Ok(Self {
            range,
            aperture,
            half: (cos, sin),
        })
    }

    /// The omnidirectional sensor (`θ = 2π`) of range `r`.
    pub fn omnidirectional(range: f64) -> Result<Self, SensorError> {
        Self::new(range, TAU)
    }

    /// Range `r`.
    pub fn range(&self) -> f64 {
        self.range
    }

    /// Aperture `θ` (radians).
    pub fn aperture(&self) -> f64 {
        self.aperture
    }

    /// Eq. (`dmin`): `d_min(θ) = min(r sin(θ/2), rho_min/cos(θ/2))` for `θ < π`, `r` for
    /// `θ ≥ π`, with `rho_min` the smallest radius of curvature of the (convex parts of the)
    /// obstacle boundaries: every obstacle within `d_min` of the robot is inside the sector or
    /// already behind it.
    pub fn d_min(&self, rho_min: f64) -> f64 {
        if self.aperture >= PI {
            self.range
        } else {
            let half = 0.5 * self.aperture;
            (self.range * half.sin()).min(rho_min / half.cos())
        }
    }

    /// Whether the point `y` lies in the sector with pole `pole` and unit axis `axis`.
    pub fn contains(&self, pole: Vector2<f64>, axis: Vector2<f64>, y: Vector2<f64>) -> bool {
        let v = y - pole;
        let d = v.norm();
        d <= self.range && (d == 0.0 || self.within_aperture(axis, v / d))
    }

    /// Euclidean distance from `y` to the sector (0 inside).
    pub fn distance(&self, pole: Vector2<f64>, axis: Vector2<f64>, y: Vector2<f64>) -> f64 {
        let v = y - pole;
        let d = v.norm();
        if d == 0.0 || self.within_aperture(axis, v / d) {
            return (d - self.range).max(0.0);
        }
        // Outside the wedge: the nearest point is on one of the two edge segments.
        self.edges(axis)
            .iter()
            .map(|edge| {
                let t = v.dot(edge).clamp(0.0, self.range);
                (v - t * edge).norm()
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// The unit directions of the two bounding rays (the axis turned by `±θ/2`).
    fn edges(&self, axis: Vector2<f64>) -> [Vector2<f64>; 2] {
        let (c, s) = self.half;
        [
            Vector2::new(c * axis.x - s * axis.y, s * axis.x + c * axis.y),
            Vector2::new(c * axis.x + s * axis.y, -s * axis.x + c * axis.y),
        ]
    }

    fn within_aperture(&self, axis: Vector2<f64>, u: Vector2<f64>) -> bool {
        self.aperture >= TAU || axis.dot(&u) >= self.half.0 - 1e-15
    }

    /// Whether any point of `shape` lies in the sector (exact against the shape).
    ///
    /// Take the point `y*` of `shape ∩ wedge` nearest to the pole. Either `y*` lies on one of
    /// the wedge's two bounding rays — then it is that ray's first hit on the shape — or inside
    /// the wedge — then it is a local minimum of the distance along the shape's boundary. So
    /// the shape meets the sector iff a bounding ray hits it within `r`, or a local distance
    /// minimum inside the wedge is within `r` ([`StarShape::ray_hit`],
    /// [`StarShape::distance_minima`]). The pole must be outside the shape.
    pub fn detects(&self, pole: Vector2<f64>, axis: Vector2<f64>, shape: &StarShape) -> bool {
        // Quick decisions from the discs about the centre that bound the shape from outside
        // (radius max R) and from inside (radius min R).
        let (r_in, r_out) = shape.radius_bounds();
        let gap = self.distance(pole, axis, shape.centre());
        if gap > r_out {
            return false;
        }
        if gap <= r_in {
            return true;
        }
        if self.aperture >= TAU {
            return shape.signed_distance(pole) <= self.range;
        }
        for edge in self.edges(axis) {
            if shape.ray_hit(pole, edge, self.range).is_some() {
                return true;
            }
        }
        shape.distance_minima(pole).any(|y| {
            let v = y - pole;
            let d = v.norm();
            d <= self.range && self.within_aperture(axis, v / d)
        })
    }
}

/// How the robot learns about obstacles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sensing {
    /// Every obstacle is known from the start.
    Global,
    /// The symmetric sector along the velocity.
    Sector(Sector),
}

/// The sector axis: along the velocity `ẋ`, or when the robot is at rest along the direction
/// it is about to move (`descent`, i.e. `−∇Θ/|∇Θ|`). `None` if both are zero or undefined.
pub fn axis(velocity: Vector2<f64>, descent: Option<Vector2<f64>>) -> Option<Vector2<f64>> {
    let speed = velocity.norm();
    if speed > 0.0 && speed.is_finite() {
        Some(velocity / speed)
    } else {
        descent
    }
}

/// Assumption `localobs`: the obstacles known at `t = 0` — every one for global sensing,
/// otherwise those within `d_min` of the start (and, as the sensor sees from the start on,
/// those already in the sector, if `axis` is given). `rho_min` is the a-priori bound of the
/// obstacles' curvature radius (eq. `dmin`).
pub fn initially_known(
    ws: &Workspace,
    start: Vector2<f64>,
    sensing: &Sensing,
    rho_min: f64,
    axis: Option<Vector2<f64>>,
) -> Vec<usize> {
    match sensing {
        Sensing::Global => (0..ws.obstacles().len()).collect(),
        Sensing::Sector(sector) => {
            let d = sector.d_min(rho_min);
            ws.obstacles()
                .iter()
                .enumerate()
                .filter(|(_, o)| {
                    o.signed_distance(start) <= d
                        || axis.is_some_and(|a| sector.detects(start, a, o))
                })
                .map(|(i, _)| i)
                .collect()
        }
    }
}
