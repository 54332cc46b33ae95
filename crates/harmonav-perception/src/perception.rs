//! The perception state: known shapes (the map's, exact; the perceived, conservative) and the
//! scan update that explains, segments, fits and merges.

use std::fmt;

use harmonav_transform::{ShapeError, StarShape};
use nalgebra::Vector2;

use crate::fit::{FitFailure, FitParams, fit_in_scan};
use crate::free::{FreeEvidence, FreeSpace, WallPrior};
use crate::perceived::{MergeFailure, Perceived, merge};
use crate::scan::{LaserScan, Pose, ScanError};
use crate::segment::{Segment, hit_point, segment};

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
    /// Highest harmonic of a fit (1 to 16).
    pub order: u32,
    /// `h`, m: spacing of the certification cover (eq. certify); the fit is about `1.5h`
    /// larger than the region it contains.
    pub check_spacing: f64,
    /// `ε_g`, m: the growth threshold. A hit is explained (eq. explained) when it lies within
    /// `ε_x = max(ε, ε_g)` of a known shape, so a shape grows only for a hit more than `ε_x`
    /// outside every known shape. With `ε_g > 0` the hits that cause growth are `ε_x` apart,
    /// so a bounded region sees finitely many growths (docs/maths.md §12.6).
    pub growth_threshold: f64,
    /// `g`, m: shapes closer than this merge ([`merge`]), not only overlapping ones (by the
    /// certified distance, which may exceed the true one by its bracket). A navigator that grows
    /// every shape by `r` (the robot's radius and margin) sets `2r`, so that the grown shapes
    /// are not refused as overlapping in most cases; where they still are (the bracket, or a
    /// disc fallback of the growth), the scan is refused, never an overlap accepted. Default 0.
    pub merge_gap: f64,
    /// `g_w`, m: the wall prior (eq. wallgap, `crate::free`): every unknown obstacle keeps at
    /// least this distance from the known boundary, so a fit may leave out what lies nearer
    /// the wall. An assumption the containment guarantee then rests on, like `D`. Default 0
    /// (no prior).
    pub wall_gap: f64,
    /// Which of the scan's free evidence the fits leave out (eq. free's disc, the default, or
    /// eq. freefan's fan; `crate::free`).
    pub free_evidence: FreeEvidence,
}

impl Default for Options {
    /// `ε = 0.02`, `D = 1`, `ρ_min = 0.05`, `d0 = 0.1`, order 6, `h = 0.01`, `ε_g = 0.02`,
    /// `g = 0`, `g_w = 0`, eq. free's disc.
    fn default() -> Self {
        Self {
            range_noise: 0.02,
            max_obstacle_depth: 1.0,
            rho_min: 0.05,
            jump_distance: 0.1,
            order: 6,
            check_spacing: 0.01,
            growth_threshold: 0.02,
            merge_gap: 0.0,
            wall_gap: 0.0,
            free_evidence: FreeEvidence::Disc,
        }
    }
}

impl Options {
    /// Errors unless `0 ≤ ε ≤ 10`, `0 < D ≤ 100`, `0 < ρ_min ≤ 1e3`, `0 ≤ d0 ≤ 100`,
    /// `1 ≤ order ≤ 16`, `1e-4 ≤ h ≤ D/4`, `0 < ε_g ≤ 10`, `0 ≤ g ≤ 100`, `0 ≤ g_w ≤ 100` (finite, m). `h` bounds the cover's size, `~2πD/h`
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
        check("wall_gap", self.wall_gap, 0.0, 100.0, false)?;
        Ok(())
    }

    fn fit_params(&self) -> FitParams {
        FitParams {
            range_noise: self.range_noise,
            max_obstacle_depth: self.max_obstacle_depth,
            rho_min: self.rho_min,
            order: self.order,
            check_spacing: self.check_spacing,
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
    /// replaced). Perceived shapes always merge ([`merge`], eq. hull).
    NotStarWorld {
        /// The shape the fit overlaps.
        with: Known,
    },
    /// A star could not be built.
    Shape(ShapeError),
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
                write!(f, "the sensor pose lies outside the known boundary")
            }
            Self::NotStarWorld { with } => write!(
                f,
                "the world as perceived is not a star world: a fitted shape overlaps {with:?}, \
                 whose exact shape cannot be merged with it"
            ),
            Self::Shape(e) => write!(f, "{e}"),
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
    /// Hits dropped as explained by a known shape.
    pub explained: usize,
    /// The segments of the unexplained hits.
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
}

/// The perception state (see the crate docs).
#[derive(Clone, Debug)]
pub struct Perception {
    options: Options,
    boundary: Option<StarShape>,
    map: Vec<StarShape>,
    perceived: Vec<Perceived>,
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
            map,
            perceived: Vec::new(),
        })
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
    /// bound or the growth threshold, [`Options::growth_threshold`]; certified bounds of
    /// `StarShape::signed_distance_bounds`):
    ///
    /// ```text
    /// obstacle S (map or perceived):  hi_S(p) ≤ ε_x    (p is within ε_x outside S, or inside)
    /// boundary B:                     lo_B(p) ≥ −ε_x   (p is within ε_x inside B, or beyond)
    /// ```
    ///
    /// (eq. explained). Quick rejects by the bounding discs `|p − c| > max R + ε_x` and
    /// `|p − c_B| < min R_B − ε_x`.
    #[must_use]
    pub fn explained(&self, p: Vector2<f64>) -> bool {
        let eps = self.options.range_noise.max(self.options.growth_threshold);
        let near = |s: &StarShape| {
            (p - s.centre()).norm() <= s.radius_bounds().1 + eps
                && s.signed_distance_bounds(p).1 <= eps
        };
        if let Some(b) = &self.boundary
            && (p - b.centre()).norm() >= b.radius_bounds().0 - eps
            && b.signed_distance_bounds(p).0 >= -eps
        {
            return true;
        }
        self.map.iter().any(near) || self.perceived.iter().any(|s| near(s.shape()))
    }

    /// Updates the perceived shapes from one scan taken at `pose`:
    ///
    /// 1. checks the scan and pose ([`LaserScan::validate`], [`Pose::validate`]; the sensor
    ///    must not lie in a known shape or outside the boundary);
    /// 2. drops the hits explained by known shapes (eq. explained);
    /// 3. segments the rest ([`segment`], eq. jump);
    /// 4. fits each segment ([`fit_in_scan`]; segments wider than `D + 2ε` are reported in
    ///    [`Observation::unfitted`]), leaving out of each region what the scan shows free and,
    ///    with [`Options::wall_gap`], what lies nearer the wall (eqs. freefan, wallgap);
    /// 5. merges each fit with every perceived shape it overlaps or comes within
    ///    [`Options::merge_gap`] of ([`merge`]), repeatedly, so that the perceived shapes stay
    ///    disjoint (and `merge_gap` apart); a fit overlapping a map obstacle is
    ///    [`PerceptionError::NotStarWorld`].
    ///
    /// A perceived shape is only ever replaced by a merge that contains it: shapes only grow.
    pub fn observe(
        &mut self,
        pose: Pose,
        scan: &LaserScan,
    ) -> Result<Observation, PerceptionError> {
        scan.validate()?;
        pose.validate()?;
        let s = pose.position();
        if let Some(b) = &self.boundary
            && !b.contains(s)
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
        for (i, flag) in usable.iter_mut().enumerate() {
            if let Some(p) = hit_point(scan, &pose, i) {
                obs.hits += 1;
                if self.explained(p) {
                    obs.explained += 1;
                } else {
                    *flag = true;
                }
            }
        }
        obs.segments = segment(scan, &pose, &usable, self.options.jump_distance);
        let params = self.options.fit_params();
        let h = self.options.check_spacing;
        let wall = self
            .boundary
            .as_ref()
            .and_then(|b| WallPrior::new(b, self.options.wall_gap));
        let free = FreeSpace::of_kind(
            self.options.free_evidence,
            scan,
            &pose,
            params.range_noise,
            params.rho_min,
            h,
        )
        .with_wall(wall);
        // Work on a copy: the update is all or nothing.
        let mut shapes: Vec<(Perceived, Origin)> = self
            .perceived
            .iter()
            .cloned()
            .enumerate()
            .map(|(i, p)| (p, Origin::Old(i)))
            .collect();
        for (k, seg) in obs.segments.iter().enumerate() {
            let fit = match fit_in_scan(scan, &pose, seg, &params, &free) {
                Ok(fit) => fit,
                Err(e @ FitFailure::WiderThanDepth { .. }) => {
                    obs.unfitted.push((k, e));
                    continue;
                }
                Err(FitFailure::Shape(e)) => return Err(PerceptionError::Shape(e)),
            };
            let mut current = fit.perceived;
            let mut origin = Origin::New;
            while let Some(j) = shapes.iter().position(|(other, _)| {
                current.shape().distance_to(other.shape()) <= self.options.merge_gap
            }) {
                let (other, other_origin) = shapes.remove(j);
                current = match merge(&current, &other, h, params.order) {
                    Ok((merged, _)) => merged,
                    Err(MergeFailure::Shape(e)) => return Err(PerceptionError::Shape(e)),
                };
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
            shapes.push((current, origin));
        }
        // Keep old shapes in their order (grown ones in place of the lowest index they
        // absorbed), new ones after.
        let mut ordered: Vec<(usize, Perceived, Origin)> = shapes
            .into_iter()
            .map(|(p, o)| {
                let key = match o {
                    Origin::Old(i) | Origin::Grown(i) => i,
                    Origin::New => usize::MAX,
                };
                (key, p, o)
            })
            .collect();
        ordered.sort_by_key(|t| t.0);
        self.perceived = Vec::with_capacity(ordered.len());
        for (idx, (_, p, o)) in ordered.into_iter().enumerate() {
            match o {
                Origin::New => obs.added.push(idx),
                Origin::Grown(_) => obs.grown.push(idx),
                Origin::Old(_) => {}
            }
            self.perceived.push(p);
        }
        obs.absorbed.sort_unstable();
        obs.absorbed.dedup();
        Ok(obs)
    }
}

/// Where a shape of the update's working list comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Origin {
    Old(usize),
    Grown(usize),
    New,
}
