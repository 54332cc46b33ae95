//! The scan perception's options ([`ScanOptions`]), what one scan did ([`ScanUpdate`]) and
//! the navigator's perception state; [`crate::Navigator::observe_scan`] (`scan.rs`) uses them.

use std::sync::Arc;

use harmonav_perception::{Known, Perceived, Perception, PerceptionError, Walls};
use harmonav_transform::StarShape;

use crate::error::NavError;

/// Above this `ρ_min` (m) the fits use `1e3` m: the perception crate's range (a smaller `ρ_min`
/// only enlarges the sagitta of eq. sagitta, so the fit stays conservative).
const FIT_RHO_MIN_CAP: f64 = 1e3;

/// The priors and parameters of [`crate::Navigator::observe_scan`]. The containment guarantee
/// (perceived shape ⊃ true obstacle, `harmonav_perception` crate docs, assumptions A1–A4) holds
/// when the truth satisfies `range_noise`, `max_obstacle_depth` and [`crate::Options::rho_min`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScanOptions {
    /// `ε`, m (A1): every return is within `ε` of the true first hit along its beam, the pose
    /// exact. Default 0.02.
    pub range_noise: f64,
    /// `D`, m (A3): every point of an obstacle lies within `D` of every point of it that a
    /// scan saw (implied by `diameter ≤ D`); how far the unseen side is closed. Default 1.
    pub max_obstacle_depth: f64,
    /// `ε_g`, m: a shape grows (or a new one is fitted) only for a hit more than
    /// `max(ε, ε_g)` outside every known shape, or more than `d_ev` ([`ScanOptions::evidence`])
    /// from the hits of every perceived shape within `max(ε, ε_g)` of it (eq. attribution), so
    /// that events are finitely many. Default 0.02.
    pub growth_threshold: f64,
    /// `d0`, m, of eq. jump (segmentation `|p_{i+1} − p_i| > d0 + r·Δθ`). Default 0.1.
    pub jump_distance: f64,
    /// Highest harmonic of a fitted Fourier star (1 to 16), under `form = Fourier`. Default 6.
    pub order: u32,
    /// How perceived shapes are represented: the radial hull of their cover (the default,
    /// docs/maths.md §12.10–12.11) or a Fourier star of order `order`.
    pub form: harmonav_perception::StarForm,
    /// Refuse an event that leaves the robot in a changed shape's margin band
    /// ([`crate::NavError::ContainsRobot`]) instead of leading it out (`Mode::Recovering`).
    /// For loops that integrate the continuous law alone, which has no value in the band (the
    /// simulator set it until 2026-12-04; its integrators now follow the held command out,
    /// docs/maths.md §12.12). Default `false`.
    pub refuse_in_band: bool,
    /// `h`, m: the spacing of the certification cover (eq. certify); a fit is about `1.5h`
    /// larger than the region it must contain. Default 0.01.
    pub check_spacing: f64,
    /// `g_w`, m, the wall prior (eq. wallgap, docs/maths.md §12.7): every unknown obstacle keeps
    /// at least this distance from the workspace boundary, so a fit leaves out what lies
    /// nearer the wall. An assumption the containment guarantee then rests on. Default 0 (none).
    pub wall_gap: f64,
    /// Which of the scan's free evidence the fits leave out: the whole free fan of eq. freefan
    /// (the default) or eq. free's disc (docs/maths.md §12.7, §12.11).
    pub free_evidence: harmonav_perception::FreeEvidence,
    /// How many earlier scans' free evidence the fits also leave out (eq. memory,
    /// docs/maths.md §12.11; a static world), remembered at least `memory_spacing` apart.
    /// Default [`DEFAULT_FREE_MEMORY`]; 0 for the current scan only.
    pub free_memory: usize,
    /// `s_m`, m: the least distance between two remembered scans' sensors. Default 0.25.
    pub memory_spacing: f64,
    /// `r_f`, m: segments whose every hit lies farther are left for a later scan (their beams
    /// still count as free evidence); under the dynamic law with the paper's damping the
    /// navigator's sector for `d_min` then reaches at most `r_f − D` ([`crate::Options::d_min`]),
    /// so `r_f` must exceed `D` there (docs/maths.md §12.11; the other policies brake within
    /// each event's room, eq. eventstop, §12.18). Default `∞`; recommended:
    /// [`crate::Options::recommended_fit_range`] (three scans of travel beyond the robot's
    /// radius, margin and the noise bound, §12.16; `D +` [`FIT_BEYOND_DEPTH`] under the paper's
    /// damping).
    pub fit_range: f64,
    /// `d_ev`, m, of eq. attribution (docs/maths.md §12.8): a hit is put down to a perceived
    /// shape only within `d_ev` of a hit that shape was fitted to, assuming (A5) that two
    /// obstacles stay `d_ev + 2ε` apart. `None` (the default): `max(d0 + 2ε, h)`.
    pub evidence: Option<f64>,
}

/// How many earlier scans' free evidence the navigator's fits leave out by default
/// ([`ScanOptions::free_memory`]).
pub const DEFAULT_FREE_MEMORY: usize = 16;

/// `r_f − D`, m: the recommended [`ScanOptions::fit_range`] beyond the depth prior under the
/// dynamic law with the paper's damping (docs/maths.md §12.11, §12.18: 35 of the 44 rerun runs arrive with 0.5 m, 33 with 1 m,
/// 19 with none), [`crate::Options::recommended_fit_range`]. Not a default, as `r_f` is
/// absolute and `D` the user's; the simulator's lidar takes it.
pub const FIT_BEYOND_DEPTH: f64 = 0.5;

/// Scan periods of travel at top speed that the kinematic law's recommended fit range keeps
/// beyond the robot's radius and margin (or the lidar's closest return) and the noise bound
/// (eq. fitnear, docs/maths.md §12.16): an obstacle is fitted at least two scans before the
/// robot could come within its margin of it, with one scan to spare for dropouts.
pub const FIT_SCANS_AHEAD: f64 = 3.0;

impl Default for ScanOptions {
    /// `ε = 0.02`, `D = 1`, `ε_g = 0.02`, `d0 = 0.1`, radial hulls, `h = 0.01`, `g_w = 0` (m),
    /// the free fan, a memory of [`DEFAULT_FREE_MEMORY`] scans 0.25 m apart, `r_f = ∞`.
    fn default() -> Self {
        let p = harmonav_perception::Options::default();
        Self {
            range_noise: p.range_noise,
            max_obstacle_depth: p.max_obstacle_depth,
            growth_threshold: p.growth_threshold,
            jump_distance: p.jump_distance,
            order: p.order,
            // The navigator's choices differ from the perception crate's own defaults: radial
            // hulls, the free fan and a memory arrive best in closed loop (docs/maths.md
            // §12.11: `navigator.lidar` 48, 48, 48 of 48 against 48, 44, 45).
            form: harmonav_perception::StarForm::Hull,
            refuse_in_band: false,
            check_spacing: p.check_spacing,
            wall_gap: p.wall_gap,
            free_evidence: harmonav_perception::FreeEvidence::Fan,
            free_memory: DEFAULT_FREE_MEMORY,
            memory_spacing: p.memory_spacing,
            fit_range: p.fit_range,
            evidence: p.evidence,
        }
    }
}

impl ScanOptions {
    /// The perception crate's options, with the fits' `ρ_min = min(rho_min, 1e3)`, the merge
    /// gap `2·inflation` (`inflation`: the robot's radius and margin, by which the navigator
    /// grows every perceived shape; shapes closer than twice that merge, so that the grown
    /// shapes stay disjoint) and the keep-out `inflation` of fits and merges (a star that keeps
    /// the robot out of its growth is preferred, docs/maths.md §12.13, §12.15).
    #[must_use]
    pub fn perception(&self, rho_min: f64, inflation: f64) -> harmonav_perception::Options {
        harmonav_perception::Options {
            range_noise: self.range_noise,
            max_obstacle_depth: self.max_obstacle_depth,
            rho_min: rho_min.min(FIT_RHO_MIN_CAP),
            jump_distance: self.jump_distance,
            order: self.order,
            form: self.form,
            check_spacing: self.check_spacing,
            growth_threshold: self.growth_threshold,
            merge_gap: 2.0 * inflation,
            keep_out: inflation,
            wall_gap: self.wall_gap,
            free_evidence: self.free_evidence,
            free_memory: self.free_memory,
            memory_spacing: self.memory_spacing,
            fit_range: self.fit_range,
            evidence: self.evidence,
        }
    }

    /// Errors ([`NavError::InvalidOption`], naming the field) unless `0 ≤ ε ≤ 10`,
    /// `0 < D ≤ 100`, `0 < ε_g ≤ 10`, `0 ≤ d0 ≤ 100`, `1 ≤ order ≤ 16`, `1e-4 ≤ h ≤ D/4`,
    /// `0 ≤ g_w ≤ 100`, `0 ≤ s_m ≤ 100` (finite, m), `free_memory ≤`
    /// [`harmonav_perception::perception::MAX_FREE_MEMORY`], `r_f > 0` (may be
    /// `∞`; `harmonav_perception::Options::validate`). `r_f > D` is checked with the sensor,
    /// by [`crate::Options::d_min`].
    pub fn validate(&self, rho_min: f64) -> Result<(), NavError> {
        self.perception(rho_min, 0.0)
            .validate()
            .map_err(option_error)
    }
}

/// The perception's option error as the navigator's.
fn option_error(e: PerceptionError) -> NavError {
    match e {
        PerceptionError::InvalidOption { field, value } => NavError::InvalidOption { field, value },
        e => NavError::Perception(e),
    }
}

/// What one [`crate::Navigator::observe_scan`] did. Indices are those of [`crate::Navigator::obstacles`].
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
pub struct ScanState {
    pub(crate) perception: Perception,
    /// The index among the navigator's obstacles of each perceived shape.
    pub(crate) slots: Vec<usize>,
    /// The index among the navigator's obstacles of each exact shape (the perception's map).
    pub(crate) exact: Vec<usize>,
}

impl ScanState {
    /// No shape perceived, none exact, in the true `boundary`.
    pub(crate) fn new(
        boundary: StarShape,
        options: &ScanOptions,
        rho_min: f64,
        inflation: f64,
    ) -> Result<Self, NavError> {
        let perception = Perception::new(
            options.perception(rho_min, inflation),
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

    /// No shape perceived, none exact, inside a floor plan's true `walls` (docs/maths.md
    /// §12.17).
    pub(crate) fn in_walls(
        walls: Arc<Walls>,
        options: &ScanOptions,
        rho_min: f64,
        inflation: f64,
    ) -> Result<Self, NavError> {
        let perception = Perception::new(options.perception(rho_min, inflation), None, Vec::new())
            .map_err(option_error)?
            .with_walls(walls);
        Ok(Self {
            perception,
            slots: Vec::new(),
            exact: Vec::new(),
        })
    }

    /// The exact shapes (true, not grown) with their indices among the navigator's obstacles,
    /// in the order they were added.
    pub(crate) fn added(&self) -> impl Iterator<Item = (usize, &StarShape)> + '_ {
        self.exact.iter().copied().zip(self.perception.map())
    }

    /// Records the exact shape just added as the navigator's last obstacle `index`.
    pub(crate) fn add_exact(&mut self, shape: StarShape, index: usize) {
        self.perception.add_map(shape);
        self.exact.push(index);
    }
}

impl ScanState {
    /// The perceived shapes with their indices among the navigator's obstacles.
    pub(crate) fn perceived(&self) -> impl Iterator<Item = (usize, &Perceived)> + '_ {
        self.slots.iter().copied().zip(self.perception.perceived())
    }

    /// The perception's error as the navigator's, with known shapes named by their index among
    /// the navigator's obstacles (`None`: another fit of the same scan).
    pub(crate) fn error(&self, e: PerceptionError) -> NavError {
        match e {
            PerceptionError::NotStarWorld { with } => NavError::NotStarWorld {
                obstacle: match with {
                    Known::Map(i) => self.exact.get(i).copied(),
                    Known::Perceived(i) => self.slots.get(i).copied(),
                    Known::Fit => None,
                },
            },
            // A changed shape, grown by `radius` (`radius + margin` under `refuse_in_band`),
            // would hold the robot: the refusal of `observe`, known before the end.
            PerceptionError::HoldsSensor { .. } => NavError::ContainsRobot,
            e => NavError::Perception(e),
        }
    }
}
