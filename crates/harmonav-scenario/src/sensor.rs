//! `[sensor]`: the paper's sector or a simulated lidar ([`SensorSpec`]).
//!
//! `[sensor] type = "lidar"`: a simulated planar lidar as the robot's only perception
//! (issue 26, docs/maths.md §12.6). The scenario's obstacles are the truth: the lidar casts its
//! beams against them, and the robot's navigator gets the scans alone
//! ([`harmonav::Navigator::observe_scan`]). The workspace boundary is a known map wall.
//!
//! The priors the perceived shapes' containment rests on (A1–A4 of `harmonav_perception`)
//! are taken from the truth unless the file gives them, so that a run judges the
//! implementation, not a prior the world breaks:
//! - `ε` (A1) is the lidar's own noise bound `range_noise`;
//! - `D` (A3, `max_obstacle_depth`) defaults to the largest true obstacle's diameter;
//! - `ρ_min` (A2, A4, `sensor.rho_min`) defaults to the true obstacles' smallest curvature
//!   radius, as for the sector;
//! - `g_w` (the wall prior, eq. wallgap, `sensor.wall_gap`) defaults to 0.99 of the smallest
//!   distance from a true obstacle to the workspace boundary.
//!
//! The perception's own choices default to what arrives best in the rerun of `scenarios/`
//! (docs/maths.md §12.11): radial hulls (`sensor.shapes`), the free fan (`sensor.free`), the
//! free evidence of 16 earlier scans (`sensor.free_memory`), and segments fitted once within
//! the robot's radius and margin, the noise bound and three scans at top speed
//! (`sensor.fit_range`, §12.16; `D + 0.5 m` for the dynamic law with the paper's damping,
//! §12.18).

use std::f64::consts::TAU;

use harmonav::perception::perception::MAX_FREE_MEMORY;
use harmonav::perception::sim::Lidar;
use harmonav::tuning::{DEFAULT_FREE_MEMORY, FIT_BEYOND_DEPTH};
use harmonav::{Law, Options, ScanOptions};
use harmonav_transform::StarShape;
use serde::{Deserialize, Serialize};

/// `[sensor]` (omit the table for global sensing): the paper's sector (`type = "sector"`, the
/// default) or a simulated lidar (`type = "lidar"`, below).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorSpec {
    /// `"sector"` or `"lidar"`.
    #[serde(rename = "type", default)]
    pub kind: SensorKind,
    /// Range `r`, m (a lidar's `range_max`).
    pub range: f64,
    /// Aperture `θ`, degrees, in (0, 360]; default 360.
    #[serde(default = "full_turn")]
    pub aperture_deg: f64,
    /// A-priori minimum curvature radius of the obstacles for `d_min` (eq. `dmin`) and a
    /// lidar's fits; default: the smallest `rho_min` of the scenario's obstacles.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rho_min: Option<f64>,
    /// Lidar: beams per scan (default [`DEFAULT_BEAMS`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beams: Option<usize>,
    /// Lidar: scans per second, Hz (default [`DEFAULT_RATE_HZ`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate_hz: Option<f64>,
    /// Lidar: the half-width of its uniform range noise, m, which is also the noise bound `ε`
    /// the navigator is told (default [`DEFAULT_RANGE_NOISE`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range_noise: Option<f64>,
    /// Lidar: the fraction of beams that return nothing (NaN), in [0, 1) (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dropout: Option<f64>,
    /// Lidar: the seed of its noise and dropouts (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// Lidar: the depth prior `D`, m (A3: how far an obstacle may reach behind its seen
    /// surface); default: the largest true obstacle's diameter.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_obstacle_depth: Option<f64>,
    /// Lidar: the wall prior `g_w`, m (eq. wallgap: every unknown obstacle keeps this far from
    /// the workspace boundary, so a fit may leave out what lies nearer the wall); default:
    /// 0.99 of the smallest distance from a true obstacle to the boundary (0 without one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_gap: Option<f64>,
    /// Lidar: `r_f`, m: segments whose every hit lies farther are fitted from a later, nearer
    /// scan (docs/maths.md §12.11); under the paper's damping the dynamic law's `d_min` then
    /// comes from `r_f − D`. When given it serves both laws and must exceed `D`. Default, at
    /// most `range`: the robot's radius and margin, the noise bound and three scans at top
    /// speed (eq. fitnear, [`harmonav::Options::recommended_fit_range`], §12.16, §12.18), or
    /// `D +` [`harmonav::tuning::FIT_BEYOND_DEPTH`] under the dynamic law with the paper's damping.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fit_range: Option<f64>,
    /// Lidar: how many earlier scans' free evidence the fits also leave out (eq. memory,
    /// §12.11), at most `harmonav::perception::perception::MAX_FREE_MEMORY`; default
    /// [`harmonav::tuning::DEFAULT_FREE_MEMORY`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub free_memory: Option<usize>,
    /// Lidar: which free evidence of a scan the fits leave out: `"fan"` (the default) or
    /// `"disc"` (§12.7).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub free: Option<LidarFree>,
    /// Lidar: the perceived shapes' form: `"hull"` (radial hulls, the default) or `"fourier"`
    /// (order-6 Fourier stars, §12.10).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shapes: Option<LidarShapes>,
}

/// `sensor.free`: which free evidence of a scan a lidar's fits leave out of their regions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LidarFree {
    /// The whole free fan of eq. freefan. The default.
    #[default]
    Fan,
    /// The disc about the sensor of eq. free.
    Disc,
}

impl From<LidarFree> for harmonav::perception::FreeEvidence {
    fn from(f: LidarFree) -> Self {
        match f {
            LidarFree::Fan => Self::Fan,
            LidarFree::Disc => Self::Disc,
        }
    }
}

/// `sensor.shapes`: the form of a lidar's perceived shapes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LidarShapes {
    /// Radial hulls of the fits' covers (eq. radialhull). The default.
    #[default]
    Hull,
    /// Fourier stars of order 6.
    Fourier,
}

impl From<LidarShapes> for harmonav::StarForm {
    fn from(f: LidarShapes) -> Self {
        match f {
            LidarShapes::Hull => Self::Hull,
            LidarShapes::Fourier => Self::Fourier,
        }
    }
}

fn full_turn() -> f64 {
    360.0
}

impl SensorSpec {
    /// The paper's sector of range `r` (m) and aperture `θ` (degrees), `rho_min` from the
    /// obstacles.
    #[must_use]
    pub fn sector(range: f64, aperture_deg: f64) -> Self {
        Self {
            kind: SensorKind::Sector,
            range,
            aperture_deg,
            rho_min: None,
            beams: None,
            rate_hz: None,
            range_noise: None,
            dropout: None,
            seed: None,
            max_obstacle_depth: None,
            wall_gap: None,
            fit_range: None,
            free_memory: None,
            free: None,
            shapes: None,
        }
    }

    /// A simulated 360° lidar of range `r` (m), every other field at its default.
    #[must_use]
    pub fn lidar(range: f64) -> Self {
        Self {
            kind: SensorKind::Lidar,
            ..Self::sector(range, 360.0)
        }
    }
}

/// `sensor.type`: how the robot perceives the obstacles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SensorKind {
    /// The paper's symmetric sector (eq. `sensing`): an obstacle's exact shape becomes known
    /// the first time any point of it enters the sector. The default.
    #[default]
    Sector,
    /// A simulated lidar: the navigator gets range scans only.
    Lidar,
}

/// The beams of a lidar when `sensor.beams` is not given (a 1° resolution over a full turn).
pub const DEFAULT_BEAMS: usize = 360;
/// The scan rate when `sensor.rate_hz` is not given, Hz (a common 2-D lidar rate).
pub const DEFAULT_RATE_HZ: f64 = 10.0;
/// The range noise bound when `sensor.range_noise` is not given, m (a common 2-D lidar's
/// ±2 cm).
pub const DEFAULT_RANGE_NOISE: f64 = 0.02;
/// The closest return, m (returns closer than this read `range_min`).
pub const RANGE_MIN: f64 = 0.05;
/// At most this many beams per scan.
pub const MAX_BEAMS: usize = 100_000;
/// The depth prior `D` when the world has no obstacle and the file gives none, m.
pub const DEFAULT_DEPTH_NO_OBSTACLE: f64 = 1.0;
/// The default `D` is the largest true diameter times this (the outline's vertices lie on
/// the curve, so their spread can only fall short of the diameter).
const DEPTH_SLACK: f64 = 1.01;

/// The default wall prior's share of the true obstacles' smallest distance to the boundary
/// (below it, so that the prior holds with room).
const WALL_GAP_SLACK: f64 = 0.99;

/// A validated simulated lidar: what the truth casts and what the navigator is told.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LidarSensor {
    /// The beams as cast (the truth's noise and dropouts).
    pub lidar: Lidar,
    /// The aperture, degrees (the navigator's sector for `d_min`).
    pub aperture_deg: f64,
    /// Scans per second, Hz: a scan at every `t = n / rate_hz`.
    pub rate_hz: f64,
    /// The seed of the noise and the dropouts.
    pub seed: u64,
    /// The priors handed to the navigator: `ε = range_noise`, `D = max_obstacle_depth`,
    /// `g_w = wall_gap`; `r_f = fit_range` as the file gives it, else `D +`
    /// [`FIT_BEYOND_DEPTH`] until [`LidarSensor::for_law`] takes the law's own.
    pub scan: ScanOptions,
    /// Whether the file gave `sensor.fit_range` (then it serves both laws).
    pub fit_range_given: bool,
}

impl LidarSensor {
    /// The scan period `1 / rate_hz`, s.
    #[must_use]
    pub fn period(&self) -> f64 {
        1.0 / self.rate_hz
    }

    /// This lidar for `law`, with the robot of `options` (radius, margin, `v_max`): the fit
    /// range the file gives, or else [`Options::recommended_fit_range`] for the law, this scan
    /// period and this closest return (eq. fitnear, docs/maths.md §12.16, §12.18; `D + 0.5`
    /// for the dynamic law under the paper's damping), at most the range.
    #[must_use]
    pub fn for_law(&self, law: &Law, options: &Options) -> Self {
        let mut lidar = *self;
        if !self.fit_range_given {
            lidar.scan.fit_range = options
                .with_scan(self.scan)
                .recommended_fit_range(law, self.period(), self.lidar.range_min)
                .min(self.lidar.range_max);
        }
        lidar
    }

    /// The navigator's options for this lidar: a sector of range `r − D` (a first fit may
    /// reach `D` in front of the truth, so `d_min` is taken from what is left, docs/maths.md
    /// §12.6; `Options::d_min` cuts it to `r_f − D`) and the lidar's aperture, the curvature
    /// prior `rho_min` (when finite) and the scan priors.
    #[must_use]
    pub fn options(&self, options: Options, rho_min: f64) -> Options {
        let options = options
            .with_sensor(
                self.lidar.range_max - self.scan.max_obstacle_depth,
                self.aperture_deg,
            )
            .with_scan(self.scan);
        if rho_min.is_finite() {
            options.with_rho_min(rho_min)
        } else {
            options
        }
    }
}

/// What the wall prior may be in a world: below `limit` (no obstacle could keep farther from
/// the walls), by default `0.99·nearest`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct WallRoom {
    /// The least upper bound a prior may not reach, m, and what it is.
    pub limit: (f64, &'static str),
    /// The smallest distance from a true obstacle to the walls, m (0 without obstacles).
    pub nearest: f64,
}

impl WallRoom {
    /// In a star `boundary`: below its smallest radius; the obstacles' certified clearance
    /// inside it.
    pub(crate) fn star(boundary: &StarShape, obstacles: &[StarShape]) -> Self {
        Self {
            limit: (
                boundary.radius_bounds().0,
                "the workspace's smallest radius",
            ),
            nearest: wall_distance(boundary, obstacles),
        }
    }
}

/// The lidar of `spec` (`sensor.type = "lidar"`) in a world of the true `obstacles` and walls
/// `room`, or the first problem: the field of `[sensor]` and what is wrong.
pub(crate) fn prepare(
    spec: &SensorSpec,
    room: WallRoom,
    obstacles: &[StarShape],
) -> Result<LidarSensor, (&'static str, String)> {
    let f = |field: &'static str, problem: String| (field, problem);
    let beams = spec.beams.unwrap_or(DEFAULT_BEAMS);
    if !(2..=MAX_BEAMS).contains(&beams) {
        return Err(f(
            "beams",
            format!("must be in [2, {MAX_BEAMS}], got {beams}"),
        ));
    }
    let rate_hz = spec.rate_hz.unwrap_or(DEFAULT_RATE_HZ);
    if !(rate_hz.is_finite() && rate_hz > 0.0 && rate_hz <= 1e4) {
        return Err(f(
            "rate_hz",
            format!("must be in (0, 1e4] Hz, got {rate_hz:e}"),
        ));
    }
    let noise = spec.range_noise.unwrap_or(DEFAULT_RANGE_NOISE);
    if !(noise.is_finite() && noise >= 0.0 && noise < 0.5 * spec.range) {
        return Err(f(
            "range_noise",
            format!(
                "must be finite, ≥ 0 and below half of sensor.range ({}), got {noise:e}",
                spec.range
            ),
        ));
    }
    let dropout = spec.dropout.unwrap_or(0.0);
    if !(0.0..1.0).contains(&dropout) {
        return Err(f("dropout", format!("must be in [0, 1), got {dropout:e}")));
    }
    if spec.range <= RANGE_MIN {
        return Err(f(
            "range",
            format!(
                "a lidar's range must exceed its closest return {RANGE_MIN} m, got {:e}",
                spec.range
            ),
        ));
    }
    let (depth, from) = match spec.max_obstacle_depth {
        Some(d) => (d, ""),
        None if obstacles.is_empty() => (DEFAULT_DEPTH_NO_OBSTACLE, " (the default)"),
        None => (
            DEPTH_SLACK * obstacles.iter().map(diameter).fold(0.0, f64::max),
            " (the largest obstacle's diameter, as none is given)",
        ),
    };
    // The fits certify containment on a cover of spacing `h`, at most `D/4`.
    let min_depth = 4.0 * ScanOptions::default().check_spacing;
    if !(depth.is_finite() && depth >= min_depth && depth < spec.range) {
        return Err(f(
            "max_obstacle_depth",
            format!(
                "must be at least {min_depth} m (four times the fits' certification spacing) \
                 and below sensor.range = {} m (d_min is taken from range − depth), got \
                 {depth:e} m{from}",
                spec.range
            ),
        ));
    }
    let wall_gap = match spec.wall_gap {
        Some(g) if !(g.is_finite() && (0.0..=100.0).contains(&g)) => {
            return Err(f(
                "wall_gap",
                format!("must be finite and in [0, 100] m, got {g:e}"),
            ));
        }
        Some(g) if g >= room.limit.0 => {
            return Err(f(
                "wall_gap",
                format!(
                    "must be below {} {:e} m (no obstacle could keep that far from the wall, \
                     and every hit would count as the wall's), got {g:e}",
                    room.limit.1, room.limit.0
                ),
            ));
        }
        Some(g) => g,
        None => WALL_GAP_SLACK * room.nearest.min(100.0),
    };
    let fit_range = spec
        .fit_range
        .unwrap_or((depth + FIT_BEYOND_DEPTH).min(spec.range));
    if !(fit_range.is_finite() && fit_range > depth && fit_range <= spec.range) {
        return Err(f(
            "fit_range",
            format!(
                "must exceed max_obstacle_depth = {depth} m (d_min is taken from fit_range − \
                 depth) and be at most sensor.range = {} m, got {fit_range:e} m",
                spec.range
            ),
        ));
    }
    let free_memory = spec.free_memory.unwrap_or(DEFAULT_FREE_MEMORY);
    if free_memory > MAX_FREE_MEMORY {
        return Err(f(
            "free_memory",
            format!("must be at most {MAX_FREE_MEMORY}, got {free_memory}"),
        ));
    }
    let aperture = spec.aperture_deg.to_radians();
    Ok(LidarSensor {
        lidar: Lidar {
            beams,
            aperture: if spec.aperture_deg >= 360.0 {
                TAU
            } else {
                aperture
            },
            range_min: RANGE_MIN,
            range_max: spec.range,
            noise,
            dropout,
        },
        aperture_deg: spec.aperture_deg,
        rate_hz,
        seed: spec.seed.unwrap_or(0),
        scan: ScanOptions {
            range_noise: noise,
            max_obstacle_depth: depth,
            wall_gap,
            fit_range,
            free_memory,
            free_evidence: spec.free.unwrap_or_default().into(),
            form: spec.shapes.unwrap_or_default().into(),
            ..ScanOptions::default()
        },
        fit_range_given: spec.fit_range.is_some(),
    })
}

/// The fields only a lidar takes, with whether `spec` gives each: a sector given one is an
/// error that names it.
pub(crate) fn lidar_only_fields(spec: &SensorSpec) -> [(&'static str, bool); 11] {
    [
        ("beams", spec.beams.is_some()),
        ("rate_hz", spec.rate_hz.is_some()),
        ("range_noise", spec.range_noise.is_some()),
        ("dropout", spec.dropout.is_some()),
        ("seed", spec.seed.is_some()),
        ("max_obstacle_depth", spec.max_obstacle_depth.is_some()),
        ("wall_gap", spec.wall_gap.is_some()),
        ("fit_range", spec.fit_range.is_some()),
        ("free_memory", spec.free_memory.is_some()),
        ("free", spec.free.is_some()),
        ("shapes", spec.shapes.is_some()),
    ]
}

/// The smallest certified clearance of a true obstacle inside the boundary
/// ([`StarShape::clearance_inside`], a lower bound of the true distance to the shapes' distance
/// tolerances), m; 0 without obstacles (no prior).
fn wall_distance(boundary: &StarShape, obstacles: &[StarShape]) -> f64 {
    let nearest = obstacles
        .iter()
        .map(|o| o.clearance_inside(boundary))
        .fold(f64::INFINITY, f64::min);
    if nearest.is_finite() {
        nearest.max(0.0)
    } else {
        0.0
    }
}

/// The diameter of `shape`'s display outline, m: the largest width over 720 directions,
/// divided by `cos(π/720)` (the true diameter's direction is within `π/720` of one of them).
fn diameter(shape: &StarShape) -> f64 {
    let points: Vec<_> = shape.outline().collect();
    let n = 720;
    let widest = (0..n)
        .map(|i| {
            let a = std::f64::consts::PI * i as f64 / n as f64;
            let (s, c) = a.sin_cos();
            let (lo, hi) = points
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    let t = c * p.x + s * p.y;
                    (lo.min(t), hi.max(t))
                });
            hi - lo
        })
        .fold(0.0, f64::max);
    widest / (std::f64::consts::PI / (2.0 * n as f64)).cos()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    /// A disc's diameter, an ellipse's major axis.
    #[test]
    fn diameter_of_known_shapes() {
        let disc = StarShape::circle(Vector2::new(1.0, 2.0), 0.7).unwrap();
        assert!((diameter(&disc) - 1.4).abs() < 1e-4, "{}", diameter(&disc));
        let ellipse = StarShape::ellipse(Vector2::zeros(), [2.0, 0.5], 0.3).unwrap();
        assert!(
            (diameter(&ellipse) - 4.0).abs() < 1e-3,
            "{}",
            diameter(&ellipse)
        );
        // An upper bound, never short.
        assert!(diameter(&disc) >= 1.4 - 1e-9);
    }
}
