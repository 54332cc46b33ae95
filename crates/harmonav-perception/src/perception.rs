//! The perception state: known shapes (the map's, exact; the perceived, conservative) and the
//! scan update that explains, segments, fits and merges.

use std::fmt;
use std::sync::Arc;

use harmonav_transform::{ShapeError, Shown, StarShape};
use nalgebra::Vector2;

use crate::enclosure::Surround;
use crate::fit::{FitFailure, FitParams, fit_in_scan};
use crate::free::{FreeEvidence, FreeSpace, FreeUnion, WallPrior};
use crate::perceived::{MergeFailure, Perceived, StarForm, merge_clear_of};
use crate::scan::{LaserScan, Pose, ScanError};
use crate::segment::{Segment, hit_point, segment};
use crate::walls::{Walls, WallsError};

/// The most earlier scans' free evidence [`Options::free_memory`] may ask to remember: each
/// costs its fan's edges in every fit near them.
pub const MAX_FREE_MEMORY: usize = 256;

/// The priors and parameters of perception. The containment guarantee (crate docs) holds when
/// the truth satisfies the priors `range_noise`, `max_obstacle_depth` and `rho_min`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// `ε`, m: every return is within `ε` of the true first hit along its beam (pose exact).
    pub range_noise: f64,
    /// `D`, m: every point of an obstacle lies within `D` of every point of it that a segment
    /// saw (implied by `diameter ≤ D`).
    pub max_obstacle_depth: f64,
    /// `ρ_min`, m: between two neighbouring hits of a segment, the visible boundary is one arc
    /// of curvature radius `≥ ρ_min` turning by less than `π` (eq. sagitta).
    pub rho_min: f64,
    /// `d0`, m, of eq. jump.
    pub jump_distance: f64,
    /// Highest harmonic of a fit (1 to 16), when `form` is [`StarForm::Fourier`].
    pub order: u32,
    /// How perceived shapes are represented: a Fourier star of order `order` (the default) or
    /// the radial hull of their cover (docs/maths.md §12.10).
    pub form: StarForm,
    /// `h`, m: spacing of the certification cover (eq. certify); the fit is about `1.5h`
    /// larger than the region it contains.
    pub check_spacing: f64,
    /// `ε_g`, m: the growth threshold. A hit is explained (eq. explained) when it lies within
    /// `ε_x = max(ε, ε_g)` of a known shape (and, for a perceived shape, within the evidence
    /// radius of a hit it was fitted to), so a shape grows only for a hit more than `ε_x`
    /// outside it or away from its evidence. With `ε_g > 0` the hits that cause growth are
    /// `min(ε_x − τ, d_ev/2)` apart (`τ` the certified distance's bracket), so a bounded region
    /// sees finitely many growths (docs/maths.md §12.8).
    pub growth_threshold: f64,
    /// `g`, m: shapes closer than this merge ([`crate::merge`]), not only overlapping ones (by the
    /// certified distance, which may exceed the true one by its bracket). A navigator that grows
    /// every shape by `r` (the robot's radius and margin) sets `2r`, so that the grown shapes
    /// are not refused as overlapping in most cases; where they still are (the bracket, or a
    /// disc fallback of the growth), the scan is refused, never an overlap accepted. Default 0.
    pub merge_gap: f64,
    /// `r_k`, m: a fit or a merge of radial hulls keeps the sensor at least this far outside
    /// its star when some centre allows it (`fit::clear_of_sensor`, [`crate::merge_clear_of`];
    /// with the default 0, the sensor itself). A navigator sets its robot's radius and margin,
    /// so that an event does not put the robot in a grown star. Changes which sound star is
    /// chosen, never what it holds. Default 0.
    pub keep_out: f64,
    /// `g_w`, m: the wall prior (eq. wallgap, `crate::free`): every unknown obstacle keeps at
    /// least this distance from the known boundary, so a fit may leave out what lies nearer
    /// the wall. An assumption the containment guarantee then rests on, like `D`. Default 0
    /// (no prior).
    pub wall_gap: f64,
    /// Which of the scan's free evidence the fits leave out (eq. free's disc, the default, or
    /// eq. freefan's fan; `crate::free`).
    pub free_evidence: FreeEvidence,
    /// How many earlier scans' free evidence (of the kind `free_evidence`) the fits also leave
    /// out of their regions (eq. memory, docs/maths.md §12.11): a region seen free from an
    /// earlier pose holds no obstacle in a static world, so a segment seen at grazing incidence
    /// now is not closed over space an earlier scan saw through. 0: the current scan only.
    pub free_memory: usize,
    /// `r_f`, m: a segment whose nearest hit lies farther than this from the sensor is not
    /// fitted in this scan (deferred, [`Observation::deferred`]); its beams still count as free
    /// evidence. Fitted later, from nearer and with the free evidence remembered meanwhile
    /// (eq. memory), its region is tighter. A navigator then knows obstacles within `r_f` only,
    /// so its `d_min` comes from `r_f − D` (docs/maths.md §12.11). Default `∞` (every segment).
    pub fit_range: f64,
    /// `s_m`, m: a scan's free evidence is remembered only when its sensor lies at least this
    /// far from the last one remembered (the oldest is forgotten past [`Options::free_memory`]).
    pub memory_spacing: f64,
    /// `d_ev`, m, of eq. attribution ([`Options::evidence_radius`]; at least `h`); `None` (the
    /// default) for `max(d0 + 2ε, h)`. (A5) then asks obstacles to stay `d_ev + 2ε` apart: a larger value
    /// is a stronger assumption.
    pub evidence: Option<f64>,
}

impl Default for Options {
    /// `ε = 0.02`, `D = 1`, `ρ_min = 0.05`, `d0 = 0.1`, Fourier stars of order 6,
    /// `h = 0.01`, `ε_g = 0.02`,
    /// `g = 0`, `g_w = 0`, eq. free's disc, no memory (`s_m = 0.25`).
    fn default() -> Self {
        Self {
            range_noise: 0.02,
            max_obstacle_depth: 1.0,
            rho_min: 0.05,
            jump_distance: 0.1,
            order: 6,
            form: StarForm::Fourier,
            check_spacing: 0.01,
            growth_threshold: 0.02,
            merge_gap: 0.0,
            keep_out: 0.0,
            wall_gap: 0.0,
            free_evidence: FreeEvidence::Disc,
            free_memory: 0,
            fit_range: f64::INFINITY,
            memory_spacing: 0.25,
            evidence: None,
        }
    }
}

impl Options {
    /// Errors unless `0 ≤ ε ≤ 10`, `0 < D ≤ 100`, `0 < ρ_min ≤ 1e3`, `0 ≤ d0 ≤ 100`,
    /// `1 ≤ order ≤ 16`, `1e-4 ≤ h ≤ D/4`, `0 < ε_g ≤ 10`, `0 ≤ g ≤ 100`, `0 ≤ g_w ≤ 100`,
    /// `free_memory ≤` [`MAX_FREE_MEMORY`], `0 ≤ s_m ≤ 100`, `r_f > 0` (may be `∞`),
    /// `h ≤ d_ev ≤ 1e3` when given (finite, m). `h` bounds the cover's size, `~2πD/h`
    /// samples per disc of `K`.
    pub fn validate(&self) -> Result<(), PerceptionError> {
        let check = |field: &'static str, v: f64, lo: f64, hi: f64, open_lo: bool| {
            let ok = v.is_finite() && v <= hi && if open_lo { v > lo } else { v >= lo };
            if ok {
                Ok(())
            } else {
                Err(PerceptionError::InvalidOption { field, value: v })
            }
        };
        check("range_noise", self.range_noise, 0.0, 10.0, false)?;
        check(
            "max_obstacle_depth",
            self.max_obstacle_depth,
            0.0,
            100.0,
            true,
        )?;
        check("rho_min", self.rho_min, 0.0, 1e3, true)?;
        check("jump_distance", self.jump_distance, 0.0, 100.0, false)?;
        check("order", f64::from(self.order), 1.0, 16.0, false)?;
        check(
            "check_spacing",
            self.check_spacing,
            1e-4,
            0.25 * self.max_obstacle_depth,
            false,
        )?;
        check("growth_threshold", self.growth_threshold, 0.0, 10.0, true)?;
        check("merge_gap", self.merge_gap, 0.0, 100.0, false)?;
        check("keep_out", self.keep_out, 0.0, 100.0, false)?;
        check("wall_gap", self.wall_gap, 0.0, 100.0, false)?;
        check(
            "free_memory",
            self.free_memory as f64,
            0.0,
            MAX_FREE_MEMORY as f64,
            false,
        )?;
        check("memory_spacing", self.memory_spacing, 0.0, 100.0, false)?;
        if self.fit_range.is_nan() || self.fit_range <= 0.0 {
            return Err(PerceptionError::InvalidOption {
                field: "fit_range",
                value: self.fit_range,
            });
        }
        if let Some(d) = self.evidence {
            // At least `h`: the evidence is thinned to `d_ev/2`, and a finer one would keep
            // nearly every hit.
            check("evidence", d, self.check_spacing, 1e3, false)?;
        }
        Ok(())
    }

    /// `d_ev`, m: [`Options::evidence`], by default `max(d0 + 2ε, h)`; the evidence radius of
    /// eq. explained. A hit is attributed to
    /// a perceived shape only within `d_ev` of a hit that shape was fitted to; (A5) asks that two
    /// obstacles stay more than `d_ev + 2ε` apart (the segmentation of eq. jump already joins
    /// obstacles nearer than `d0`).
    #[must_use]
    pub fn evidence_radius(&self) -> f64 {
        self.evidence
            .unwrap_or((self.jump_distance + 2.0 * self.range_noise).max(self.check_spacing))
    }

    /// `ε_x = max(ε, ε_g)`, m: how far outside a known shape a hit may lie and still be
    /// explained by it (eqs. explained, attribution).
    fn explained_band(&self) -> f64 {
        self.range_noise.max(self.growth_threshold)
    }

    fn fit_params(&self) -> FitParams {
        FitParams {
            range_noise: self.range_noise,
            max_obstacle_depth: self.max_obstacle_depth,
            rho_min: self.rho_min,
            order: self.order,
            form: self.form,
            check_spacing: self.check_spacing,
            keep_out: self.keep_out,
        }
    }
}

/// A known shape, by kind and index.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Known {
    /// Map obstacle `i` (exact, as given).
    Map(usize),
    /// Perceived shape `i` ([`Perception::perceived`]).
    Perceived(usize),
    /// Another shape fitted from the same scan (not yet perceived).
    Fit,
}

/// Why a scan update failed. A failed update changes nothing.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum PerceptionError {
    /// An option is out of range ([`Options::validate`]).
    InvalidOption {
        /// The option.
        field: &'static str,
        /// Its value.
        value: f64,
    },
    /// The scan or the pose is invalid.
    Scan(ScanError),
    /// The sensor lies inside a known shape or outside the known boundary.
    PoseNotFree {
        /// The shape it lies in, `None` for outside the boundary.
        inside: Option<Known>,
    },
    /// A fit overlaps a shape it cannot be merged with: a map obstacle (exact shapes are not
    /// replaced). Perceived shapes always merge ([`crate::merge`], eq. hull).
    NotStarWorld {
        /// The shape the fit overlaps.
        with: Known,
    },
    /// A star could not be built.
    Shape(ShapeError),
    /// The walls could not be built ([`Walls::new`]).
    Walls(WallsError),
    /// The update would leave the sensor inside a perceived shape, or nearer one than the
    /// robot's `guard` allows ([`Perception::observe_guarded`], eq. guard): a fit, or a merge
    /// of a fit with perceived shapes, comes certainly that near. Perceived shapes only grow (a
    /// merge holds what it merges), so the shape the update would end with comes as near, and
    /// a navigator would refuse it (its robot's disc over an obstacle); the update is refused
    /// as soon as this is certain, before the remaining fits and merges. A scan of ranges at
    /// random (rain, dust, glass, a failing lidar) does this at its nearest fit: `D` behind a
    /// hit a few centimetres from the sensor reaches over the sensor.
    HoldsSensor {
        /// The first beam of the segment whose fit, alone or merged, comes that near.
        beam: usize,
        /// The guard, m (0: the fit holds the sensor).
        guard: f64,
    },
}

impl fmt::Display for PerceptionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidOption { field, value } => {
                write!(f, "option `{field}` out of range: {value:e}")
            }
            Self::Scan(e) => write!(f, "{e}"),
            Self::PoseNotFree { inside: Some(k) } => {
                write!(f, "the sensor pose lies inside known shape {k:?}")
            }
            Self::PoseNotFree { inside: None } => {
                write!(
                    f,
                    "the sensor pose lies outside the known boundary or walls"
                )
            }
            Self::NotStarWorld { with } => write!(
                f,
                "the world as perceived is not a star world: a fitted shape overlaps {with:?}, \
                 whose exact shape cannot be merged with it"
            ),
            Self::Shape(e) => write!(f, "{e}"),
            Self::Walls(e) => write!(f, "{e}"),
            Self::HoldsSensor { beam, guard } if *guard > 0.0 => write!(
                f,
                "the scan would put a perceived obstacle within {} m of the sensor (the fit \
                 of the segment from beam {beam}, alone or merged)",
                Shown(*guard)
            ),
            Self::HoldsSensor { beam, .. } => write!(
                f,
                "the scan would put the sensor inside a perceived obstacle (the fit of the \
                 segment from beam {beam}, alone or merged, holds it)"
            ),
        }
    }
}

impl std::error::Error for PerceptionError {}

impl From<ScanError> for PerceptionError {
    fn from(e: ScanError) -> Self {
        Self::Scan(e)
    }
}

/// What one scan did.
#[derive(Clone, Debug, Default)]
pub struct Observation {
    /// Hits (returns in `[range_min, range_max)`).
    pub hits: usize,
    /// Hits dropped: explained by the boundary or a map obstacle (eq. explained), or in a
    /// segment a perceived shape explains (eq. attribution).
    pub explained: usize,
    /// The segments fitted: runs of hits the boundary and the map do not explain, each with a
    /// hit that no perceived shape explains and not put down to one shape whole.
    pub segments: Vec<Segment>,
    /// Indices (into [`Perception::perceived`] after the update) of new shapes.
    pub added: Vec<usize>,
    /// Indices of shapes that grew (merged with a fit).
    pub grown: Vec<usize>,
    /// Shapes merged into another and removed, by their index before the update.
    pub absorbed: Vec<usize>,
    /// Segments (index into `segments`) with no fit, and why (the guarantee does not cover
    /// what they saw).
    pub unfitted: Vec<(usize, FitFailure)>,
    /// Segments with an unexplained hit left for a later scan: every hit farther than
    /// [`Options::fit_range`].
    pub deferred: usize,
}

/// The perception state (see the crate docs).
#[derive(Clone, Debug)]
pub struct Perception {
    options: Options,
    boundary: Option<StarShape>,
    /// A floor plan's walls (docs/maths.md §12.17), in place of or besides `boundary`.
    walls: Option<Arc<Walls>>,
    map: Vec<StarShape>,
    perceived: Vec<Perceived>,
    /// For each perceived shape, the hits it was fitted to (thinned to `d_ev/2` apart): the
    /// evidence of eq. explained.
    evidence: Vec<Vec<Vector2<f64>>>,
    /// The remembered scans' free evidence, oldest first (eq. memory; shared, so that the
    /// navigator's copy per update is cheap).
    memory: Vec<Arc<FreeSpace>>,
}

/// Who explains a hit (eq. explained).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Explanation {
    /// The known boundary or a map obstacle (exact shapes): the hit is dropped.
    Map,
    /// A perceived shape, near a hit it was fitted to.
    Perceived,
    /// Nothing: the hit's segment is fitted.
    None,
}

/// Whether `p` lies within `d_ev` of a point of `evidence`.
fn near_evidence(evidence: &[Vector2<f64>], p: Vector2<f64>, d_ev: f64) -> bool {
    evidence.iter().any(|e| (e - p).norm() <= d_ev)
}

/// Adds the points of `new` that lie more than `spacing` from every point of `evidence`.
fn thin_into(evidence: &mut Vec<Vector2<f64>>, new: &[Vector2<f64>], spacing: f64) {
    for &p in new {
        if evidence.iter().all(|e| (e - p).norm() > spacing) {
            evidence.push(p);
        }
    }
}

impl Perception {
    /// Perception with the known boundary (free space inside it; `None`: unbounded) and map
    /// obstacles (exact shapes), nothing perceived yet. Errors: [`Options::validate`].
    pub fn new(
        options: Options,
        boundary: Option<StarShape>,
        map: Vec<StarShape>,
    ) -> Result<Self, PerceptionError> {
        options.validate()?;
        Ok(Self {
            options,
            boundary,
            walls: None,
            map,
            perceived: Vec::new(),
            evidence: Vec::new(),
            memory: Vec::new(),
        })
    }

    /// The same perception inside known walls (a floor plan's, docs/maths.md §12.17): a hit
    /// within `ε_x` of a wall, nearer one than `g_w − ε` under the wall prior, or outside the
    /// free space, is explained (eq. explained with `d(p)` the walls' distance); the sensor
    /// must lie in their free space; a fit leaves out `{sd < g_w}` ([`WallPrior::Level`]), up
    /// to the cover's slack: a fit keeps `sd ≥ g_w − h − τ` (`h` the cover's spacing, `τ` the
    /// distance bracket), so it may reach about `h` past `{sd = g_w}`, into a wall at `g_w = 0`.
    #[must_use]
    pub fn with_walls(mut self, walls: Arc<Walls>) -> Self {
        self.walls = Some(walls);
        self
    }

    /// The walls, if any ([`Perception::with_walls`]).
    #[must_use]
    pub fn walls(&self) -> Option<&Arc<Walls>> {
        self.walls.as_ref()
    }

    /// The options.
    #[must_use]
    pub fn options(&self) -> &Options {
        &self.options
    }

    /// Adds an exact shape to the map (a known obstacle that did not come from a scan, e.g.
    /// `Navigator::add_obstacle`): its hits are explained from now on and a fit that overlaps
    /// it is [`PerceptionError::NotStarWorld`]. The caller checks that it is disjoint from the
    /// perceived shapes.
    pub fn add_map(&mut self, shape: StarShape) {
        self.map.push(shape);
    }

    /// The map obstacles (exact), in the order they were given.
    #[must_use]
    pub fn map(&self) -> &[StarShape] {
        &self.map
    }

    /// The perceived shapes, pairwise disjoint (certified, `StarShape::distance_to > 0`).
    #[must_use]
    pub fn perceived(&self) -> &[Perceived] {
        &self.perceived
    }

    /// Whether hit `p` is explained by a known shape within `ε_x = max(ε, ε_g)` (the noise
    /// bound or the growth threshold, [`Options::growth_threshold`]; certified by
    /// `StarShape::within`, on the hit's ray from the shape's centre where that decides, else
    /// by the bounds of `StarShape::signed_distance_bounds`), and, for a perceived shape `P`,
    /// near its evidence `E_P` (the hits it was fitted to; `d_ev` of
    /// [`Options::evidence_radius`]):
    ///
    /// ```text
    /// map obstacle S (exact):  hi_S(p) ≤ ε_x    (p is within ε_x outside S, or inside)
    /// boundary B:              lo_B(p) ≥ −ε_x  or  lo_B(p) > −(g_w − ε)   (within ε_x of the
    ///                          wall, or nearer than the wall prior allows an obstacle, eq. wallgap)
    /// perceived P:             hi_P(p) ≤ ε_x  and  min_{e ∈ E_P} |p − e| ≤ d_ev      (eq. explained)
    /// ```
    ///
    /// A hit inside a perceived shape proves only that *some* obstacle is there: the shape's
    /// unseen side, closed `D` behind what it saw, may reach over a neighbour that was out of
    /// view. Near the shape's evidence, under (A5), the hit is on the obstacle the shape was
    /// fitted to, which it contains. Quick rejects by the bounding discs `|p − c| > max R + ε_x`
    /// and `|p − c_B| < min R_B − max(ε_x, g_w − ε)`.
    #[must_use]
    pub fn explained(&self, p: Vector2<f64>) -> bool {
        self.explanation(p) != Explanation::None
    }

    /// Eq. explained, saying by what.
    fn explanation(&self, p: Vector2<f64>) -> Explanation {
        let eps = self.options.explained_band();
        let near = |s: &StarShape| s.within(p, eps);
        // Under the wall prior (eq. wallgap) a hit `p` whose true point `p*` (`|p − p*| ≤ ε`,
        // A1) is nearer the wall than `g_w` lies on the wall: no unknown obstacle comes that
        // near. So a hit less than `g_w − ε` from the wall is explained, as one within `ε_x` is.
        let prior = self.options.wall_gap - self.options.range_noise;
        if let Some(b) = &self.boundary
            && (p - b.centre()).norm() >= b.radius_bounds().0 - eps.max(prior)
            && let lo = b.signed_distance_bounds(p).0
            && (lo >= -eps || lo > -prior)
        {
            return Explanation::Map;
        }
        // The walls: `d(p) ≤ ε_x`, or `d(p) < g_w − ε` under the prior (as the boundary's), or
        // `p` outside the free space (a beam through glass, or a map a little off): its true
        // hit, within `ε < d(p)` of it, is outside too, where no obstacle stands.
        if let Some(w) = &self.walls
            && let d = w.distance(p)
            && (d <= eps || d < prior || !w.contains(p))
        {
            return Explanation::Map;
        }
        if self.map.iter().any(near) {
            return Explanation::Map;
        }
        let d_ev = self.options.evidence_radius();
        let by_perceived = self
            .perceived
            .iter()
            .zip(&self.evidence)
            .any(|(s, e)| near(s.shape()) && near_evidence(e, p, d_ev));
        if by_perceived {
            Explanation::Perceived
        } else {
            Explanation::None
        }
    }

    /// The perceived shape that a segment's `hits` (one obstacle, (A2)) lie on: the first `P`
    /// with `hi_P(p) ≤ ε_x` for every hit and `|p − e| ≤ d_ev` for some hit `p` and some `e`
    /// of its evidence `E_P`:
    ///
    /// ```text
    /// ∀p: hi_P(p) ≤ ε_x   and   ∃p, e ∈ E_P: |p − e| ≤ d_ev                    (eq. attribution)
    /// ```
    ///
    /// Under (A5) the hit near `E_P` lies on the obstacle of that evidence, which `P` holds, and
    /// under (A2) so does the whole segment.
    fn attribution(&self, hits: &[Vector2<f64>]) -> Option<usize> {
        let eps = self.options.explained_band();
        let d_ev = self.options.evidence_radius();
        self.perceived
            .iter()
            .zip(&self.evidence)
            .position(|(s, e)| {
                hits.iter().all(|&p| s.shape().within(p, eps))
                    && hits.iter().any(|&p| near_evidence(e, p, d_ev))
            })
    }

    /// Updates the perceived shapes from one scan taken at `pose`:
    ///
    /// 1. checks the scan and pose ([`LaserScan::validate`], [`Pose::validate`]; the sensor
    ///    must not lie in a known shape or outside the boundary);
    /// 2. drops the hits explained by the boundary or a map obstacle (eq. explained);
    /// 3. segments the rest ([`segment`], eq. jump); a segment one perceived shape explains
    ///    (eq. attribution) is dropped and its hits join that shape's evidence, and of the
    ///    others those that hold a hit no perceived shape explains are kept;
    /// 4. fits each whole segment kept ([`fit_in_scan`]; a fit inside the perceived shape of
    ///    its hits (certified) only adds them to its evidence; segments wider than `D + 2ε` are reported in
    ///    [`Observation::unfitted`]), leaving out of each region what the scan shows free and,
    ///    with [`Options::wall_gap`], what lies nearer the wall (eqs. freefan, wallgap);
    /// 5. merges each fit with every perceived shape it overlaps or comes within
    ///    [`Options::merge_gap`] of ([`crate::merge`]), repeatedly, so that the perceived shapes stay
    ///    disjoint (and `merge_gap` apart); a fit overlapping a map obstacle is
    ///    [`PerceptionError::NotStarWorld`].
    ///
    /// A perceived shape is only ever replaced by a merge that contains it: shapes only grow.
    ///
    /// The segments are fitted nearest first (by their nearest hit to the sensor), then merged
    /// in scan order: a fit depends only on its segment, the scan and the options, so the
    /// shapes are those of fitting in scan order. An update that would leave the sensor inside
    /// a perceived shape is refused ([`PerceptionError::HoldsSensor`]) as soon as that is
    /// certain: a fit or a merge holds it, or fits wall it in ([`Perception::observe_guarded`]
    /// with `guard = 0`).
    pub fn observe(
        &mut self,
        pose: Pose,
        scan: &LaserScan,
    ) -> Result<Observation, PerceptionError> {
        self.observe_guarded(pose, scan, 0.0)
    }

    /// [`Perception::observe`] for a robot that must stay `guard` (m) clear of every perceived
    /// shape, as a navigator's robot of radius `guard` (its disc must not overlap a shape) must:
    /// the update is refused ([`PerceptionError::HoldsSensor`]) as soon as a fit, or the merge
    /// of a fit with perceived shapes, comes certainly nearer the sensor `s` than
    ///
    /// ```text
    /// g' = max(guard − h, 0):   hi_F(s) < g'     (hi_F the certified upper bound of F's signed distance)   (eq. guard)
    /// ```
    ///
    /// (`h` the cover's spacing, [`Options::check_spacing`]). Perceived shapes only grow: the
    /// fit `F` ends in a shape `M ⊃ F` of the update (held by it, or merged into it), so
    /// `d(s, M) ≤ d(s, F) < g'`, and `M` is new or grown: no shape from before the update holds
    /// `F` (the sensor lies outside them, `PoseNotFree`; for `g' > 0` they must also lie
    /// certainly `g'` or more from the sensor, `lo_P(s) ≥ g'`, else `g' = 0` is used). A
    /// navigator that refuses an update whose new or grown shape, grown by `guard`, holds its
    /// robot would refuse this one at its end: the early refusal changes when the refusal is
    /// known, not whether (where the update would also have failed otherwise, a map obstacle
    /// overlapped or a star not built, the error reported may be this one instead). `h` is slack for the navigator's tabulated offset (8 192 exact
    /// samples per turn, far nearer the true offset than `h`), so that what is refused here is
    /// refused there. With `guard = 0` a shape that holds the sensor (`hi_F(s) < 0`) is refused:
    /// no obstacle holds the sensor (A2), so no sound update leaves it inside.
    ///
    /// Fits and perceived shapes that certainly share points all round the sensor (eq.
    /// surround, `crate::enclosure`: a ring of them about it) end in one shape that holds it:
    /// refused too, before any merge.
    ///
    /// *Cost.* The segments are fitted nearest first and all fitted before the first merge:
    /// a scan of ranges at random (rain, dust, glass, a failing or hostile lidar) has a hit a
    /// few centimetres from the sensor, and the region `K` of radius `D + ε` of its fit
    /// reaches over the sensor, so it is refused after one fit (~ms) instead of after every
    /// fit and merge of its hundreds of one-hit segments (40 s for 360 beams before
    /// 2026-12-06, the hostile round's D2).
    ///
    /// # Errors
    /// As [`Perception::observe`]; [`PerceptionError::InvalidOption`] (field `guard`) unless
    /// `guard` is finite and `≥ 0`.
    pub fn observe_guarded(
        &mut self,
        pose: Pose,
        scan: &LaserScan,
        guard: f64,
    ) -> Result<Observation, PerceptionError> {
        if !(guard.is_finite() && guard >= 0.0) {
            return Err(PerceptionError::InvalidOption {
                field: "guard",
                value: guard,
            });
        }
        scan.validate()?;
        pose.validate()?;
        let s = pose.position();
        if let Some(b) = &self.boundary
            && !b.contains(s)
        {
            return Err(PerceptionError::PoseNotFree { inside: None });
        }
        if let Some(w) = &self.walls
            && w.signed_distance(s) <= 0.0
        {
            return Err(PerceptionError::PoseNotFree { inside: None });
        }
        if let Some(i) = self.map.iter().position(|m| m.contains(s)) {
            return Err(PerceptionError::PoseNotFree {
                inside: Some(Known::Map(i)),
            });
        }
        if let Some(i) = self.perceived.iter().position(|m| m.shape().contains(s)) {
            return Err(PerceptionError::PoseNotFree {
                inside: Some(Known::Perceived(i)),
            });
        }
        let n = scan.ranges.len();
        let mut obs = Observation::default();
        let mut usable = vec![false; n];
        let mut unexplained = vec![false; n];
        for i in 0..n {
            if let Some(p) = hit_point(scan, &pose, i) {
                obs.hits += 1;
                match self.explanation(p) {
                    Explanation::Map => obs.explained += 1,
                    Explanation::Perceived => usable[i] = true,
                    Explanation::None => (usable[i], unexplained[i]) = (true, true),
                }
            }
        }
        // Eq. attribution: a segment (one obstacle, under (A2)) with a hit near the evidence
        // of a perceived shape `P` and every hit within `ε_x` of `P` is on `P`'s obstacle
        // (A5), which `P` holds: it is dropped whole and its hits join `P`'s evidence. Any
        // other segment with a hit that no shape explains is fitted whole (its neighbours on
        // the same obstacle make its `K` tight).
        let d_ev = self.options.evidence_radius();
        let mut attributed: Vec<(usize, Vec<Vector2<f64>>)> = Vec::new();
        obs.segments = segment(scan, &pose, &usable, self.options.jump_distance)
            .into_iter()
            .filter(|seg| {
                let hits: Vec<Vector2<f64>> = seg
                    .beams
                    .iter()
                    .filter_map(|&i| hit_point(scan, &pose, i))
                    .collect();
                if let Some(j) = self.attribution(&hits) {
                    attributed.push((j, hits));
                } else if seg.beams.iter().any(|&i| unexplained[i]) {
                    if hits.iter().all(|p| (p - s).norm() > self.options.fit_range) {
                        obs.deferred += 1;
                        return false;
                    }
                    return true;
                }
                obs.explained += seg.beams.len();
                false
            })
            .collect();
        let params = self.options.fit_params();
        let h = self.options.check_spacing;
        // Walls keep fits in `{sd ≥ g_w}` (at `g_w = 0` out of the walls); a star boundary only
        // under a prior.
        let wall = match &self.walls {
            Some(w) => Some(WallPrior::Level {
                walls: w.clone(),
                gap: self.options.wall_gap,
            }),
            None => self
                .boundary
                .as_ref()
                .and_then(|b| WallPrior::new(b, self.options.wall_gap)),
        };
        // The scan's free evidence is built only when a segment is fitted or the memory keeps
        // it: a scan that changes nothing (the common case) costs no fan.
        let remembered = self.remembers(s);
        let now = if obs.segments.is_empty() && !remembered {
            FreeSpace::none(s)
        } else {
            FreeSpace::of_kind(
                self.options.free_evidence,
                scan,
                &pose,
                params.range_noise,
                params.rho_min,
                h,
            )
        }
        .with_wall(wall);
        let free = FreeUnion {
            now: &now,
            past: &self.memory,
        };
        // Work on a copy: the update is all or nothing.
        let mut shapes: Vec<(Perceived, Origin, Vec<Vector2<f64>>)> = self
            .perceived
            .iter()
            .cloned()
            .zip(self.evidence.iter().cloned())
            .enumerate()
            .map(|(i, (p, e))| (p, Origin::Old(i), e))
            .collect();
        for (j, hits) in &attributed {
            thin_into(&mut shapes[*j].2, hits, 0.5 * d_ev);
        }
        // Eq. guard, for shapes this update adds or grows: a shape from before within `g'` of
        // the sensor (a robot already that near) could hold a near fit unchanged; then only a
        // fit that holds the sensor, which none of those shapes can hold, is refused early.
        let near = Some((guard - h).max(0.0))
            .filter(|&g| {
                self.perceived
                    .iter()
                    .all(|p| p.shape().signed_distance_bounds(s).0 >= g)
            })
            .unwrap_or(0.0);
        let refused = |p: &Perceived, seg: &Segment| {
            (p.shape().signed_distance_bounds(s).1 < near).then(|| PerceptionError::HoldsSensor {
                beam: seg.beams[0],
                guard,
            })
        };
        let fit = |seg: &Segment| -> Result<Result<Perceived, FitFailure>, PerceptionError> {
            let fit = fit_in_scan(scan, &pose, seg, &params, &free).map(|f| f.perceived);
            match fit.as_ref().ok().and_then(|p| refused(p, seg)) {
                Some(e) => Err(e),
                None => Ok(fit),
            }
        };
        let walled = |seg: &Segment| PerceptionError::HoldsSensor {
            beam: seg.beams[0],
            guard,
        };
        let mut fits = nearest_first(
            &obs.segments,
            (s, scan, &pose),
            &self.perceived,
            fit,
            walled,
        )?;
        for (k, seg) in obs.segments.iter().enumerate() {
            let hits: Vec<Vector2<f64>> = seg
                .beams
                .iter()
                .filter_map(|&i| hit_point(scan, &pose, i))
                .collect();
            let fitted = match fits[k].take() {
                Some(f) => f,
                None => fit(seg)?,
            };
            let fitted = match fitted {
                Ok(p) => p,
                Err(e @ FitFailure::WiderThanDepth { .. }) => {
                    obs.unfitted.push((k, e));
                    continue;
                }
                Err(FitFailure::Shape(e)) => return Err(PerceptionError::Shape(e)),
            };
            // A fit that a shape already holds (certified over the fit's boundary cover, eq.
            // certify) adds its hits to that shape's evidence and changes nothing else.
            if let Some((_, _, evidence)) = shapes
                .iter_mut()
                .find(|(other, _, _)| holds(other, &fitted, h))
            {
                thin_into(evidence, &hits, 0.5 * d_ev);
                continue;
            }
            let mut current = fitted;
            let mut origin = Origin::New;
            let mut evidence = Vec::new();
            thin_into(&mut evidence, &hits, 0.5 * d_ev);
            while let Some(j) = shapes.iter().position(|(other, _, _)| {
                current.shape().distance_to(other.shape()) <= self.options.merge_gap
            }) {
                let (other, other_origin, other_evidence) = shapes.remove(j);
                let fresh = std::mem::replace(&mut evidence, other_evidence);
                thin_into(&mut evidence, &fresh, 0.5 * d_ev);
                let clear = Some((pose.position(), self.options.keep_out));
                current = match merge_clear_of(&current, &other, h, params.order, clear) {
                    Ok((merged, _)) => merged,
                    Err(MergeFailure::Shape(e)) => return Err(PerceptionError::Shape(e)),
                };
                // Shapes only grow: the update's result would come as near (eq. guard).
                if let Some(e) = refused(&current, seg) {
                    return Err(e);
                }
                origin = match (origin, other_origin) {
                    (Origin::New, Origin::New) => Origin::New,
                    (Origin::New, Origin::Old(i) | Origin::Grown(i)) => Origin::Grown(i),
                    (Origin::Grown(a) | Origin::Old(a), Origin::Old(b) | Origin::Grown(b)) => {
                        obs.absorbed.push(a.max(b));
                        Origin::Grown(a.min(b))
                    }
                    (o, Origin::New) => o,
                };
            }
            if let Some(i) = self
                .map
                .iter()
                .position(|m| current.shape().distance_to(m) <= 0.0)
            {
                return Err(PerceptionError::NotStarWorld {
                    with: Known::Map(i),
                });
            }
            shapes.push((current, origin, evidence));
        }
        // Keep old shapes in their order (grown ones in place of the lowest index they
        // absorbed), new ones after.
        let mut ordered: Vec<(usize, Perceived, Origin, Vec<Vector2<f64>>)> = shapes
            .into_iter()
            .map(|(p, o, e)| {
                let key = match o {
                    Origin::Old(i) | Origin::Grown(i) => i,
                    Origin::New => usize::MAX,
                };
                (key, p, o, e)
            })
            .collect();
        ordered.sort_by_key(|t| t.0);
        self.perceived = Vec::with_capacity(ordered.len());
        self.evidence = Vec::with_capacity(ordered.len());
        for (idx, (_, p, o, e)) in ordered.into_iter().enumerate() {
            match o {
                Origin::New => obs.added.push(idx),
                Origin::Grown(_) => obs.grown.push(idx),
                Origin::Old(_) => {}
            }
            self.perceived.push(p);
            self.evidence.push(e);
        }
        obs.absorbed.sort_unstable();
        obs.absorbed.dedup();
        if remembered {
            if self.memory.len() == self.options.free_memory {
                self.memory.remove(0);
            }
            self.memory.push(Arc::new(now));
        }
        Ok(obs)
    }

    /// Eq. memory: whether a scan taken at `s` is kept, which it is when the options ask for a
    /// memory and `s` lies at least [`Options::memory_spacing`] from the last scan kept (the
    /// oldest is forgotten beyond [`Options::free_memory`]).
    fn remembers(&self, s: Vector2<f64>) -> bool {
        self.options.free_memory > 0
            && self
                .memory
                .last()
                .is_none_or(|last| (last.sensor() - s).norm() >= self.options.memory_spacing)
    }

    /// How many earlier scans' free evidence the fits leave out (eq. memory).
    #[must_use]
    pub fn remembered(&self) -> usize {
        self.memory.len()
    }
}

/// The fits of the kept `segments` (`fit` of each: the perceived star, or why there is none),
/// computed nearest segment first (by its nearest hit to the sensor `s`, ties in scan order),
/// for [`Perception::observe`]'s merge loop to take in scan order. A fit depends only on its
/// segment, the scan, the pose, the options and the scan's free evidence, never on the other
/// fits or on the order, so the loop sees the fits it would have computed itself.
///
/// Nearest first, so that a fit that comes too near the sensor ([`PerceptionError::HoldsSensor`],
/// returned by `fit` at once) is found before the others are fitted: the fit of a hit inside or
/// just beside the robot, whose region `K` of radius `D + ε` reaches over the sensor, is the
/// likeliest. And all before the first merge, so that fits and the perceived shapes `old` that
/// certainly wall the sensor in (eq. surround, `crate::enclosure`) are refused before the merges
/// that would put it inside (`walled`, with the segment fitted last): tested when 2, 4, 8, …
/// segments are fitted and after the last (the pairs tested once in all).
/// Stops at the first fit whose star could not be built, leaving that segment and the ones not
/// yet fitted to the loop (`None`), which then reports the first error in scan order as it did.
fn nearest_first(
    segments: &[Segment],
    (s, scan, pose): (Vector2<f64>, &LaserScan, &Pose),
    old: &[Perceived],
    fit: impl Fn(&Segment) -> Result<Result<Perceived, FitFailure>, PerceptionError>,
    walled: impl Fn(&Segment) -> PerceptionError,
) -> Result<Vec<Option<Result<Perceived, FitFailure>>>, PerceptionError> {
    let nearest: Vec<f64> = segments
        .iter()
        .map(|seg| {
            seg.beams
                .iter()
                .filter_map(|&i| hit_point(scan, pose, i))
                .map(|p| (p - s).norm())
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    let mut order: Vec<usize> = (0..segments.len()).collect();
    order.sort_by(|&a, &b| nearest[a].total_cmp(&nearest[b]));
    let mut fits: Vec<Option<Result<Perceived, FitFailure>>> =
        (0..segments.len()).map(|_| None).collect();
    let mut surround = Surround::new(s);
    for p in old {
        surround.push(p.shape());
    }
    // The segments whose fits were added to `surround`, in order.
    let mut added: Vec<usize> = Vec::new();
    let last = order.len().saturating_sub(1);
    for (n, &k) in order.iter().enumerate() {
        let fitted = fit(&segments[k])?;
        if matches!(fitted, Err(FitFailure::Shape(_))) {
            break;
        }
        let grew = if let Ok(p) = &fitted {
            surround.push(p.shape());
            added.push(k);
            true
        } else {
            false
        };
        fits[k] = Some(fitted);
        let due = (grew && added.len().is_power_of_two()) || n == last;
        if due && !added.is_empty() && surround.len() >= 2 {
            let shapes: Vec<&StarShape> = old
                .iter()
                .map(Perceived::shape)
                .chain(added.iter().filter_map(|&j| match &fits[j] {
                    Some(Ok(p)) => Some(p.shape()),
                    _ => None,
                }))
                .collect();
            if surround.walled_in(&shapes) {
                return Err(walled(&segments[k]));
            }
        }
    }
    Ok(fits)
}

/// Whether `outer` holds `inner`: every sample of `inner`'s boundary cover (every boundary
/// point within `h/2` of one) lies at least `h/2` inside `outer` (certified), so `∂inner ⊂ outer`
/// and, `outer` being a star, `inner ⊂ outer` (eq. certify).
fn holds(outer: &Perceived, inner: &Perceived, h: f64) -> bool {
    inner
        .boundary_cover(h)
        .into_iter()
        .all(|x| outer.shape().signed_distance_bounds(x).1 <= -0.5 * h)
}

/// Where a shape of the update's working list comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Origin {
    Old(usize),
    Grown(usize),
    New,
}
