//! The navigator fed by range scans (issue 26, part 2; docs/maths.md §12.6):
//! [`Navigator::observe_scan`] turns a `sensor_msgs/LaserScan` into new and grown obstacles
//! through `harmonav-perception`, and treats each change like a discovery of
//! [`Navigator::add_obstacle`].
//!
//! **What it keeps.** The true workspace boundary (hits on it are explained), the exact shapes
//! of `add_obstacle` (the perception's map: their hits are explained, a fit that overlaps one is
//! refused) and the perceived shapes, each with its index among [`Navigator::obstacles`].
//!
//! **The event rule.** A hit is dropped when it lies within `ε_x = max(ε, ε_g)` of a known
//! shape or the boundary (eq. explained; `ε` = [`ScanOptions::range_noise`], `ε_g` =
//! [`ScanOptions::growth_threshold`]). Only the remaining hits are fitted, so a shape grows only
//! for a hit more than `ε_x` outside every known shape, and a new fit must contain that hit.
//! The hits of successive events are therefore `ε_x` apart, and a robot whose lidar sees a
//! bounded region `A` causes at most `area(A ⊕ B(ε_x/2)) / (π ε_x²/4)` events (a packing
//! bound; docs/maths.md §12.6).

use std::sync::Arc;

use harmonav_field::Field;
use harmonav_perception::{Known, Perception, PerceptionError};
use harmonav_transform::{StarShape, Workspace, WorldError};

pub use harmonav_perception::{LaserScan, Perceived, Pose};

use crate::navigator::{NavError, Navigator};
use crate::options::Options;

/// Above this `ρ_min` (m) the fits use `1e3` m: the perception crate's range (a smaller `ρ_min`
/// only enlarges the sagitta of eq. sagitta, so the fit stays conservative).
const FIT_RHO_MIN_CAP: f64 = 1e3;

/// The priors and parameters of [`Navigator::observe_scan`]. The containment guarantee
/// (perceived shape ⊃ true obstacle, `harmonav_perception` crate docs, assumptions A1–A4) holds
/// when the truth satisfies `range_noise`, `max_obstacle_depth` and [`Options::rho_min`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScanOptions {
    /// `ε`, m (A1): every return is within `ε` of the true first hit along its beam, the pose
    /// exact. Default 0.02.
    pub range_noise: f64,
    /// `D`, m (A3): every point of an obstacle lies within `D` of every point of it that a
    /// scan saw (implied by `diameter ≤ D`); how far the unseen side is closed. Default 1.
    pub max_obstacle_depth: f64,
    /// `ε_g`, m: a shape grows (or a new one is fitted) only for a hit more than
    /// `max(ε, ε_g)` outside every known shape, so that events are finitely many. Default
    /// 0.02.
    pub growth_threshold: f64,
    /// `d0`, m, of eq. jump (segmentation `|p_{i+1} − p_i| > d0 + r·Δθ`). Default 0.1.
    pub jump_distance: f64,
    /// Highest harmonic of a fitted Fourier star (1 to 16). Default 6.
    pub order: u32,
    /// `h`, m: the spacing of the certification cover (eq. certify); a fit is about `1.5h`
    /// larger than the region it must contain. Default 0.01.
    pub check_spacing: f64,
}

impl Default for ScanOptions {
    /// `ε = 0.02`, `D = 1`, `ε_g = 0.02`, `d0 = 0.1`, order 6, `h = 0.01` (m).
    fn default() -> Self {
        let p = harmonav_perception::Options::default();
        Self {
            range_noise: p.range_noise,
            max_obstacle_depth: p.max_obstacle_depth,
            growth_threshold: p.growth_threshold,
            jump_distance: p.jump_distance,
            order: p.order,
            check_spacing: p.check_spacing,
        }
    }
}

impl ScanOptions {
    /// The perception crate's options, with the fits' `ρ_min = min(rho_min, 1e3)`.
    #[must_use]
    pub fn perception(&self, rho_min: f64) -> harmonav_perception::Options {
        harmonav_perception::Options {
            range_noise: self.range_noise,
            max_obstacle_depth: self.max_obstacle_depth,
            rho_min: rho_min.min(FIT_RHO_MIN_CAP),
            jump_distance: self.jump_distance,
            order: self.order,
            check_spacing: self.check_spacing,
            growth_threshold: self.growth_threshold,
        }
    }

    /// Errors ([`NavError::InvalidOption`], naming the field) unless `0 ≤ ε ≤ 10`,
    /// `0 < D ≤ 100`, `0 < ε_g ≤ 10`, `0 ≤ d0 ≤ 100`, `1 ≤ order ≤ 16`, `1e-4 ≤ h ≤ D/4`
    /// (finite, m; `harmonav_perception::Options::validate`).
    pub fn validate(&self, rho_min: f64) -> Result<(), NavError> {
        self.perception(rho_min).validate().map_err(option_error)
    }
}

/// The perception's option error as the navigator's.
fn option_error(e: PerceptionError) -> NavError {
    match e {
        PerceptionError::InvalidOption { field, value } => NavError::InvalidOption { field, value },
        e => NavError::Perception(e),
    }
}

/// What one [`Navigator::observe_scan`] did. Indices are those of [`Navigator::obstacles`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ScanUpdate {
    /// New obstacles (indices after the scan), fitted from hits no known shape explains.
    pub added: Vec<usize>,
    /// Obstacles that grew (indices after the scan): a perceived shape merged with a fit or
    /// with other perceived shapes; each contains what it was.
    pub grown: Vec<usize>,
    /// Obstacles merged into a grown one and removed (indices before the scan, ascending);
    /// the indices above each removed one move down by one.
    pub absorbed: Vec<usize>,
    /// Returns in `[range_min, range_max)`.
    pub hits: usize,
    /// Hits explained by a known shape or the boundary (eq. explained), dropped.
    pub explained: usize,
    /// Segments of unexplained hits that no fit covers (wider than `D + 2ε`: the assumption
    /// A3 fails for them; they are not obstacles of the navigator).
    pub unfitted: usize,
    /// At an event (`added` or `grown` not empty): the smallest distance from the robot's
    /// centre to a changed obstacle grown by `radius + margin`, m (the room the dynamic law
    /// has to brake in, docs/maths.md §12.6); `None` when nothing changed.
    pub event_clearance: Option<f64>,
}

impl ScanUpdate {
    /// Whether the scan changed the obstacles (an event: `k`, `Φ` and the damping state were
    /// rebuilt).
    #[must_use]
    pub fn changed(&self) -> bool {
        !(self.added.is_empty() && self.grown.is_empty())
    }
}

/// The navigator's scan perception (see the module docs).
#[derive(Clone, Debug)]
pub(crate) struct ScanState {
    perception: Perception,
    /// The index among the navigator's obstacles of each perceived shape.
    slots: Vec<usize>,
    /// The index among the navigator's obstacles of each exact shape (the perception's map).
    exact: Vec<usize>,
}

impl ScanState {
    /// No shape perceived, none exact, in the true `boundary`.
    pub(crate) fn new(boundary: StarShape, options: &Options) -> Result<Self, NavError> {
        let perception = Perception::new(
            options.scan.perception(options.rho_min),
            Some(boundary),
            Vec::new(),
        )
        .map_err(option_error)?;
        Ok(Self {
            perception,
            slots: Vec::new(),
            exact: Vec::new(),
        })
    }

    /// Records the exact shape just added as the navigator's last obstacle `index`.
    pub(crate) fn add_exact(&mut self, shape: StarShape, index: usize) {
        self.perception.add_map(shape);
        self.exact.push(index);
    }
}

impl Navigator {
    /// Observes one scan taken from `pose` (the sensor at the robot's centre, heading `yaw`):
    /// drops the hits that known shapes or the boundary explain within `max(ε, ε_g)` (eq.
    /// explained), fits conservative stars to the rest, merges fits with the perceived shapes
    /// they overlap (shapes only grow), and hands every new or grown shape to the field grown
    /// by `radius + margin` (docs/maths.md §12). A change is an event, handled as a discovery
    /// of [`Navigator::add_obstacle`]: `k`, `Φ` and the dynamic law's `|ẋ(T_n)|` (the speed of
    /// the last commanded state) update. Allocates; a scan that changes nothing rebuilds
    /// nothing.
    ///
    /// Every perceived shape contains the true obstacle it saw when the truth satisfies the
    /// priors of [`ScanOptions`] and [`Options::rho_min`] (A1–A4 of `harmonav_perception`).
    ///
    /// Errors (the navigator, its perceived shapes included, is then unchanged):
    /// [`NavError::Perception`] for a scan or pose that is not valid (empty, non-finite angles,
    /// `angle_increment ≤ 0`, bad range limits, overlapping beams), a sensor inside a known
    /// shape or outside the boundary; [`NavError::NotStarWorld`] when a new or grown shape
    /// overlaps a known one (raw, or grown by `radius + margin`) with no common kernel point;
    /// [`NavError::ContainsRobot`] when a changed shape grown by `radius` contains the pose;
    /// [`NavError::ContainsGoal`]; [`NavError::CrossesBoundary`].
    pub fn observe_scan(&mut self, pose: Pose, scan: &LaserScan) -> Result<ScanUpdate, NavError> {
        let mut perception = self.scan.perception.clone();
        let obs = perception
            .observe(pose, scan)
            .map_err(|e| self.scan_error(e))?;
        let mut update = ScanUpdate {
            hits: obs.hits,
            explained: obs.explained,
            unfitted: obs.unfitted.len(),
            ..ScanUpdate::default()
        };
        if obs.added.is_empty() && obs.grown.is_empty() {
            // Nothing absorbed either (an absorption is a growth): the same shapes.
            return Ok(update);
        }
        let old_slots = &self.scan.slots;
        let surviving: Vec<usize> = (0..old_slots.len())
            .filter(|i| obs.absorbed.binary_search(i).is_err())
            .collect();
        let mut removed: Vec<usize> = obs.absorbed.iter().map(|&i| old_slots[i]).collect();
        removed.sort_unstable();
        // Old navigator index → index after the removals.
        let remap = |j: usize| j - removed.partition_point(|&r| r < j);
        let old = self.field.workspace().obstacles();
        let with_margin = self.options.margin > 0.0;
        let keep: Vec<usize> = (0..old.len())
            .filter(|j| removed.binary_search(j).is_err())
            .collect();
        let mut obstacles: Vec<StarShape> = keep.iter().map(|&j| old[j].clone()).collect();
        let mut inner: Vec<StarShape> = if with_margin {
            keep.iter().map(|&j| self.inner[j].clone()).collect()
        } else {
            Vec::new()
        };
        let mut slots: Vec<usize> = surviving.iter().map(|&i| remap(old_slots[i])).collect();
        let exact: Vec<usize> = self.scan.exact.iter().map(|&j| remap(j)).collect();
        let x = pose.position();
        let (radius, inflation) = (
            self.options.radius,
            self.options.radius + self.options.margin,
        );
        let mut event_clearance = f64::INFINITY;
        for (p, shape) in perception.perceived().iter().enumerate() {
            let is_new = p >= slots.len();
            if !is_new && obs.grown.binary_search(&p).is_err() {
                continue;
            }
            let grown = shape.shape().offset(inflation).map_err(NavError::Shape)?;
            let body = if with_margin {
                Some(shape.shape().offset(radius).map_err(NavError::Shape)?)
            } else {
                None
            };
            if body.as_ref().unwrap_or(&grown).contains(x) {
                return Err(NavError::ContainsRobot);
            }
            event_clearance = event_clearance.min(grown.signed_distance(x));
            let j = if is_new {
                slots.push(obstacles.len());
                obstacles.push(grown);
                inner.extend(body);
                update.added.push(obstacles.len() - 1);
                obstacles.len() - 1
            } else {
                let j = slots[p];
                obstacles[j] = grown;
                if let Some(b) = body {
                    inner[j] = b;
                }
                update.grown.push(j);
                j
            };
            debug_assert!(j < obstacles.len());
        }
        let boundary = self.field.workspace().boundary().clone();
        let before = |j: usize| keep.get(j).copied();
        let ws = Workspace::new(boundary, obstacles, self.goal).map_err(|e| match e {
            WorldError::Overlap { first, second } => NavError::NotStarWorld {
                obstacle: before(first).or(before(second)),
            },
            WorldError::InObstacle { .. } => NavError::ContainsGoal,
            _ => NavError::CrossesBoundary,
        })?;
        let field = Field::all_known_with(Arc::new(ws), self.options.k).map_err(NavError::Field)?;
        self.field = field;
        self.inner = inner;
        self.speed_at_discovery = self.last.map_or(0.0, |(_, v)| v.norm());
        self.scan = ScanState {
            perception,
            slots,
            exact,
        };
        update.absorbed = removed;
        update.event_clearance = Some(event_clearance);
        Ok(update)
    }

    /// The perceived shapes (not grown), each with its index among [`Navigator::obstacles`],
    /// in the perception's order. Each contains the true obstacle it saw under the priors.
    pub fn perceived(&self) -> impl Iterator<Item = (usize, &Perceived)> + '_ {
        self.scan
            .slots
            .iter()
            .copied()
            .zip(self.scan.perception.perceived())
    }

    /// The perception's error as the navigator's, with known shapes named by their index among
    /// the navigator's obstacles (`None`: another fit of the same scan).
    fn scan_error(&self, e: PerceptionError) -> NavError {
        match e {
            PerceptionError::NotStarWorld { with } => NavError::NotStarWorld {
                obstacle: match with {
                    Known::Map(i) => self.scan.exact.get(i).copied(),
                    Known::Perceived(i) => self.scan.slots.get(i).copied(),
                    Known::Fit => None,
                },
            },
            e => NavError::Perception(e),
        }
    }
}
