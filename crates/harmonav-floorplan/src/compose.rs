//! [`FloorTransform`]: `Phi = S ∘ M_a ∘ H ∘ B` on a floor plan (`M_a` the identity unless the
//! plan recentres on the goal, [`CentrePolicy`]), with its Jacobian by the chain rule.

use std::sync::Arc;

use harmonav_harmonic::Enclosure;
use harmonav_transform::StarShape;
use harmonav_transform::nav::WIDTH_FACTOR;
use harmonav_transform::radial::{obstacle_map, outer_map};
use nalgebra::{Matrix2, Vector2};

use crate::plan::{CentrePolicy, FloorError, FloorMap};
use crate::sector::{Sector, Unenclosed};

/// Why `Phi` is not defined at a point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NotFree {
    /// Inside (or on) sensed obstacle `i` (in the order added).
    Obstacle(usize),
    /// In the boundary layer: closer than `δ` to a wall (or `|H| ≥ 1` there, which the
    /// certificate excludes on `W_δ`). The map is not claimed a diffeomorphism here.
    BoundaryLayer,
    /// On or beyond a wall (in a hole or outside the outer ring), or a non-finite point.
    Outside,
}

/// Which part of `Phi` acted on a point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// `B` was the identity and `M_a(H(x))` is in `S`'s identity disc.
    Harmonic,
    /// In the band of sensed obstacle `i`: `B` collapsed it towards the obstacle's centre.
    Obstacle(usize),
    /// `M_a(H(B(x)))` is in `S`'s band next to the unit circle.
    Stretched,
}

/// `Phi(x)`, `J_Phi(x) = J_S J_M J_H J_B` and the part that acted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FloorMapped {
    /// `Phi(x)` in the point world.
    pub h: Vector2<f64>,
    /// `J_Phi(x)`.
    pub jacobian: Matrix2<f64>,
    /// Which part acted.
    pub part: Part,
}

#[derive(Clone, Debug)]
struct Band {
    shape: StarShape,
    eps: f64,
    /// `(max R + ε)²`: beyond it from the centre the band cannot hold the point.
    reach2: f64,
}

/// The navigation transformation of a floor plan (docs/maths.md §13):
///
/// ```text
/// Phi = S ∘ M_a ∘ H ∘ B,     J_Phi(x) = J_S · J_M · J_H(B(x)) · J_B(x)
/// ```
///
/// - `B`: the star-obstacle map of the sensed obstacles (`radial::obstacle_map`, the bands of
///   `docs/maths.md` §5), each obstacle collapsed to its centre `c_i`; identity elsewhere.
///   Widths `ε_i = f·min(min_j d(O_i, O_j), d̲(O_i, ∂W_δ), 2 d(x_d, O_i))`, `f =`
///   [`WIDTH_FACTOR`], with `d̲(O_i, ∂W_δ)` the certified room [`FloorMap::star_room`] (eq.
///   starroom of `docs/maths.md` §12.17: the sampled distance from `O_i` to `∂W_s`, less `δ`
///   and the sampling slack). Each band and its obstacle lie in `W_δ`, so `B(x) ∈ W_δ`.
/// - `H`: the harmonic map of the walls onto the unit disk ([`FloorMap`]); holes collapse to
///   the punctures `p_j`, solved once. Adding a sensed obstacle needs no new solve.
/// - `M_a`: the identity under [`CentrePolicy::Solve`]; under [`CentrePolicy::Goal`] the disk
///   automorphism `M_a(w) = (w − a)/(1 − ā w)`, `a = H(x_d)`, which puts the goal's image at 0
///   (below, `H` stands for `M_a ∘ H`: the punctures are `M_a(p_j)`, `r_δ = min |M_a(H)|` over
///   the edge samples).
/// - `S`: the existing outer stretch applied to the unit circle, `radial::outer_map(|w|, 1, 0,
///   ε_0, A)` about 0, with
///   `ε_0 = clamp(max(f·min(min_i(1 − |p_i|), 2(1 − |H(x_d)|)), EDGE_BAND·(1 − r_δ)), MIN_BAND, MAX_BAND)`
///   ([`EDGE_BAND`], [`MIN_BAND`], [`MAX_BAND`], `r_δ = min |M_a(H)|` over
///   [`FloorMap::edge_images`]): the band holds the image
///   of `∂W_δ`, so the walls' barrier is steep where navigation stops;
///   `A = max(ε_0, 2r*, MIN_GAIN)` ([`MIN_GAIN`]) with `r*` the potential's valley radius
///   about 0 (computed on the points before `S`).
///
/// The point world is `P_d = S(M_a(H(x_d)))`, `P = (S(M_a(p_1)) … S(M_a(p_M)), S(M_a(H(c_1))) …
/// S(M_a(H(c_n))))`, `k > M + n`.
/// Defined on `W_δ` minus the sensed obstacles; [`NotFree::BoundaryLayer`] in the layer.
#[derive(Clone, Debug)]
pub struct FloorTransform {
    floor: Arc<FloorMap>,
    bands: Vec<Band>,
    /// `M_a(H(c_i))` of each sensed obstacle's centre.
    images: Vec<Vector2<f64>>,
    goal: Vector2<f64>,
    /// `a`: the centre of the recentring map `M_a`, `H(x_d)` (or 0 when not recentred).
    centre: Vector2<f64>,
    /// `M_a(H(x_d))`: 0 when recentred.
    goal_image: Vector2<f64>,
    /// `M_a(p_j)` of the holes' punctures.
    punctures: Vec<Vector2<f64>>,
    /// `S(p)` of every point (punctures, then `M_a(H(c_i))`).
    stretched: Vec<Vector2<f64>>,
    /// `S(M_a(H(x_d)))`.
    goal_point: Vector2<f64>,
    eps0: f64,
    gain: f64,
}

/// `S`'s band reaches `EDGE_BAND·(1 − r_δ)` into the disk, `r_δ = min |M_a(H)|` on `∂W_δ`
/// (over [`FloorMap::edge_images`]; [`FloorMap::edge_radius`] when `M_a` is the identity): the edge of the certified region lies in the band's outer
/// half, where the stretch makes the walls' barrier steep.
pub const EDGE_BAND: f64 = 2.0;

/// The narrowest band of `S` (measured: with the band only as wide as the points allow, the
/// L room's descents from the far arm stalled at the reflex corner's layer edge).
pub const MIN_BAND: f64 = 0.5;

/// The widest band of `S`: it leaves the disk of radius `1 − MAX_BAND` to the identity.
pub const MAX_BAND: f64 = 0.9;

/// The least gain `A` of `S`: the disk's own radius. On the L room with `A = ε_0` (≈ 0.1) the
/// barrier at `∂W_δ` was so flat that the descent from the far arm ran into the layer edge and
/// stalled there.
pub const MIN_GAIN: f64 = 1.0;

impl FloorTransform {
    /// The transformation for the sensed obstacles `obstacles` (true shapes already grown by
    /// `radius + margin`) towards `goal`, with stretch gain `A = max(ε_0, 2·valley_radius)`.
    ///
    /// # Errors
    /// [`FloorError::GoalNotCertified`] if the goal is not in `W_δ`;
    /// [`FloorError::ObstacleNearWall`], [`FloorError::Overlap`], [`FloorError::ContainsGoal`]
    /// for an obstacle that does not fit; [`FloorError::InvalidOption`] for a bad valley radius;
    /// [`FloorError::Map`] if `H` cannot be evaluated at a centre.
    pub fn new(
        floor: Arc<FloorMap>,
        obstacles: &[StarShape],
        goal: Vector2<f64>,
        valley_radius: f64,
    ) -> Result<Self, FloorError> {
        let delta = floor.delta();
        let sd_goal = floor.signed_distance(goal);
        if !(goal.x.is_finite() && goal.y.is_finite()) || sd_goal.is_nan() || sd_goal < delta {
            return Err(FloorError::GoalNotCertified {
                clearance: sd_goal,
                delta,
            });
        }
        let mut walls = Vec::with_capacity(obstacles.len());
        for (i, o) in obstacles.iter().enumerate() {
            let room = floor.star_room(o);
            if room.is_nan() || room <= 0.0 {
                return Err(FloorError::ObstacleNearWall { obstacle: i });
            }
            if o.signed_distance_bounds(goal).1 <= 0.0 {
                return Err(FloorError::ContainsGoal { obstacle: i });
            }
            for (j, p) in obstacles[..i].iter().enumerate() {
                if o.distance_to(p) <= 0.0 {
                    return Err(FloorError::Overlap {
                        first: j,
                        second: i,
                    });
                }
            }
            walls.push(room);
        }
        let mut bands = Vec::with_capacity(obstacles.len());
        for (i, o) in obstacles.iter().enumerate() {
            let mut d = walls[i].min(2.0 * o.signed_distance_bounds(goal).0);
            for (j, p) in obstacles.iter().enumerate() {
                if j != i {
                    d = d.min(o.distance_to(p));
                }
            }
            let eps = WIDTH_FACTOR * d;
            let r = o.radius_bounds().1 + eps;
            bands.push(Band {
                shape: o.clone(),
                eps,
                reach2: r * r,
            });
        }
        let map = floor.map();
        let raw_goal = map.eval(goal).map_err(FloorError::Map)?.value;
        // Guard: `H(x_d)` strictly inside the disk (the certificate's `|H| < 1` on `W_δ`), also
        // under `"goal"`, where `M_a` would otherwise map a goal on or beyond the circle to 0.
        let goal_radius = raw_goal.norm();
        if goal_radius.is_nan() || goal_radius >= 1.0 {
            return Err(FloorError::PointOnCircle);
        }
        let centre = match floor.centre_policy() {
            CentrePolicy::Solve => Vector2::zeros(),
            CentrePolicy::Goal => raw_goal,
        };
        let recentre = |w: Vector2<f64>| mobius(centre, w).0;
        let goal_image = recentre(raw_goal);
        let mut images = Vec::with_capacity(obstacles.len());
        for o in obstacles {
            images.push(recentre(
                map.eval(o.centre()).map_err(FloorError::Map)?.value,
            ));
        }
        let punctures: Vec<_> = map.punctures().iter().map(|&p| recentre(p)).collect();
        let edge_radius = floor
            .edge_images()
            .iter()
            .map(|&w| recentre(w).norm())
            .fold(1.0, f64::min);
        let room = punctures
            .iter()
            .chain(&images)
            .map(|p| 1.0 - p.norm())
            .fold(2.0 * (1.0 - goal_image.norm()), f64::min);
        if !(room.is_finite() && room > 0.0) {
            return Err(FloorError::GoalNotCertified {
                clearance: sd_goal,
                delta,
            });
        }
        let eps0 = (WIDTH_FACTOR * room)
            .max(EDGE_BAND * (1.0 - edge_radius))
            .clamp(MIN_BAND, MAX_BAND);
        Self {
            floor,
            bands,
            images,
            goal,
            centre,
            goal_image,
            punctures,
            stretched: Vec::new(),
            goal_point: goal_image,
            eps0,
            gain: eps0,
        }
        .with_valley_radius(valley_radius)
    }

    /// `S(w)` and `J_S(w)` for `|w| < 1`: `radial::outer_map(|w|, 1, 0, ε_0, A)` about 0,
    /// the identity for `|w| ≤ 1 − ε_0`; `None` at or beyond the circle.
    fn stretch(&self, w: Vector2<f64>) -> Option<(Vector2<f64>, Matrix2<f64>)> {
        let rw = w.norm();
        // Guard: |H| ≥ 1 happens only in the layer (excluded on W_δ by the certificate); S is
        // infinite there, so the point is reported, never mapped to a NaN.
        if rw.is_nan() || rw >= 1.0 {
            return None;
        }
        if rw <= 1.0 - self.eps0 {
            return Some((w, Matrix2::identity()));
        }
        let u = w / rw;
        let m = outer_map(rw, 1.0, 0.0, self.eps0, self.gain);
        m.nu.is_finite().then(|| (m.nu * u, m.jacobian(u, rw)))
    }

    /// The same transformation with `A = max(ε_0, 2·valley_radius)`.
    ///
    /// # Errors
    /// [`FloorError::InvalidOption`] (`valley_radius`) if it is negative or not finite.
    pub fn with_valley_radius(mut self, valley_radius: f64) -> Result<Self, FloorError> {
        if !(valley_radius.is_finite() && valley_radius >= 0.0) {
            return Err(FloorError::InvalidOption {
                field: "valley_radius",
                value: valley_radius,
            });
        }
        self.gain = self.eps0.max(2.0 * valley_radius).max(MIN_GAIN);
        let raw: Vec<_> = self.raw_points().collect();
        let mut stretched = Vec::with_capacity(raw.len());
        for p in raw.into_iter().chain([self.goal_image]) {
            stretched.push(self.stretch(p).ok_or(FloorError::PointOnCircle)?.0);
        }
        self.goal_point = stretched.pop().ok_or(FloorError::PointOnCircle)?;
        self.stretched = stretched;
        Ok(self)
    }

    /// The floor plan and its map.
    #[must_use]
    pub fn floor(&self) -> &Arc<FloorMap> {
        &self.floor
    }

    /// The goal `x_d`.
    #[must_use]
    pub fn goal(&self) -> Vector2<f64> {
        self.goal
    }

    /// `P_d = S(M_a(H(x_d)))` (0 under [`CentrePolicy::Goal`]).
    #[must_use]
    pub fn destination_point(&self) -> Vector2<f64> {
        self.goal_point
    }

    /// `M_a(H(x_d))` in the disk (`H(x_d)` under [`CentrePolicy::Solve`], 0 under
    /// [`CentrePolicy::Goal`]).
    #[must_use]
    pub fn destination_image(&self) -> Vector2<f64> {
        self.goal_image
    }

    /// The obstacle points of the point world: `S(M_a(p_j))` of the holes' punctures, then
    /// `S(M_a(H(c_i)))` of the sensed obstacles.
    pub fn points(&self) -> impl Iterator<Item = Vector2<f64>> + '_ {
        self.stretched.iter().copied()
    }

    /// The same points in the disk, before `S`: the punctures `M_a(p_j)`, then `M_a(H(c_i))`.
    pub fn raw_points(&self) -> impl Iterator<Item = Vector2<f64>> + '_ {
        self.punctures.iter().chain(&self.images).copied()
    }

    /// The number of holes `M` (the first `M` points).
    #[must_use]
    pub fn holes(&self) -> usize {
        self.floor.map().punctures().len()
    }

    /// The sensed obstacles (grown), in the order added.
    pub fn obstacles(&self) -> impl Iterator<Item = &StarShape> + '_ {
        self.bands.iter().map(|b| &b.shape)
    }

    /// The band width `ε_i` of each sensed obstacle.
    pub fn widths(&self) -> impl Iterator<Item = f64> + '_ {
        self.bands.iter().map(|b| b.eps)
    }

    /// `a`, the centre of the recentring map `M_a` (0 when the plan is not recentred).
    pub(crate) fn recentre(&self) -> Vector2<f64> {
        self.centre
    }

    /// `S`'s band width `ε_0` (in the disk) and gain `A`.
    #[must_use]
    pub fn outer_band(&self) -> (f64, f64) {
        (self.eps0, self.gain)
    }

    /// An annular sector of the point world that holds `Phi(B(x, ρ))`, for a disc that meets
    /// no sensed obstacle's band (there `B` is the identity): the enclosure of `H`
    /// ([`harmonav_harmonic::HarmonicMap::enclosure`], `H(B(x, ρ)) ⊂ B(w, r)`), then the exact
    /// image of that disc under `M_a` (a disc: the ends of its diameter through the pole map to
    /// opposite points of the image circle), then `S`, which keeps each ray and stretches the
    /// radius monotonically (`ν_ρ ≥ 1`), so a disc `B(w', r')` with `|w'| + r' < 1` goes into
    /// the radii
    /// `[ν(max(|w'| − r', 0)), ν(|w'| + r')]` within `asin(r'/|w'|)` of `arg w'`
    /// (docs/maths.md §13.5).
    ///
    /// # Errors
    /// [`Unenclosed::Band`] if the disc may meet a band; [`Unenclosed::Disk`] if the bound
    /// of `M_a(H)` reaches the unit circle (or the disc meets an element), where `S` has no
    /// finite bound: a smaller disc may succeed.
    pub fn enclose(&self, x: Vector2<f64>, rho: f64) -> Result<Sector, Unenclosed> {
        if self
            .bands
            .iter()
            .any(|b| (x - b.shape.centre()).norm() < b.reach2.sqrt() + rho)
        {
            return Err(Unenclosed::Band);
        }
        let e = self.floor.enclosure(x, rho).map_err(|_| Unenclosed::Disk)?;
        self.sector_of(&e)
    }

    /// [`FloorTransform::enclose`] from `H`'s enclosure of the disc (no band check).
    ///
    /// # Errors
    /// [`Unenclosed::Disk`] as [`FloorTransform::enclose`].
    pub(crate) fn sector_of(&self, e: &Enclosure) -> Result<Sector, Unenclosed> {
        let (w, r) = (e.eval.value, e.radius);
        // Guard: M_a's image disc needs the disc strictly inside the unit disk (the pole 1/ā
        // outside it), and S is finite only there; NaN or ∞ fail the comparisons too.
        if (w.norm() + r).partial_cmp(&1.0) != Some(std::cmp::Ordering::Less) {
            return Err(Unenclosed::Disk);
        }
        let (w, r) = mobius_disc(self.centre, w, r);
        let t = w.norm();
        if (t + r).partial_cmp(&1.0) != Some(std::cmp::Ordering::Less) {
            return Err(Unenclosed::Disk);
        }
        let nu = |t: f64| {
            if t <= 1.0 - self.eps0 {
                t
            } else {
                outer_map(t, 1.0, 0.0, self.eps0, self.gain).nu
            }
        };
        let half_width = if r < t {
            (r / t).asin()
        } else {
            std::f64::consts::PI
        };
        Ok(Sector {
            radii: (nu((t - r).max(0.0)), nu(t + r)),
            angle: w.y.atan2(w.x),
            half_width,
        })
    }

    /// `Phi(x) = S(M_a(H(B(x))))` with `J_Phi = J_S J_M J_H J_B` (chain rule; each factor exact:
    /// `Radial::jacobian` for `B` and `S`, the closed-form `J_H` and `M_a'`). `O(N + n)`, no
    /// allocation.
    ///
    /// # Errors
    /// [`NotFree::Outside`] on or beyond a wall or at a non-finite point;
    /// [`NotFree::BoundaryLayer`] where `sd(x) < δ`, or where `|H| ≥ 1` or `H` cannot be
    /// evaluated (excluded on `W_δ` by a certificate); [`NotFree::Obstacle`] inside a sensed
    /// obstacle.
    pub fn nav_transform(&self, x: Vector2<f64>) -> Result<FloorMapped, NotFree> {
        if !(x.x.is_finite() && x.y.is_finite()) {
            return Err(NotFree::Outside);
        }
        let sd = self.floor.signed_distance(x);
        if sd.is_nan() || sd <= 0.0 {
            return Err(NotFree::Outside);
        }
        if sd < self.floor.delta() {
            return Err(NotFree::BoundaryLayer);
        }
        // B: at most one band holds x (they are disjoint).
        let (mut y, mut jb, mut part) = (x, Matrix2::identity(), Part::Harmonic);
        for (i, band) in self.bands.iter().enumerate() {
            let c = band.shape.centre();
            let v = x - c;
            let rho2 = v.norm_squared();
            if rho2 >= band.reach2 {
                continue;
            }
            let rho = rho2.sqrt();
            if rho == 0.0 {
                return Err(NotFree::Obstacle(i));
            }
            let u = v / rho;
            let (r, dr) = band.shape.radius_along(u);
            if rho <= r {
                return Err(NotFree::Obstacle(i));
            }
            if rho < r + band.eps {
                let m = obstacle_map(rho, r, dr, band.eps);
                y = c + m.nu * u;
                jb = m.jacobian(u, rho);
                part = Part::Obstacle(i);
                break;
            }
        }
        // H: exact value and Jacobian.
        let e = self
            .floor
            .map()
            .eval(y)
            .map_err(|_| NotFree::BoundaryLayer)?;
        let (w, jm) = mobius(self.centre, e.value);
        let (h, js) = self.stretch(w).ok_or(NotFree::BoundaryLayer)?;
        if part == Part::Harmonic && w.norm() > 1.0 - self.eps0 {
            part = Part::Stretched;
        }
        Ok(FloorMapped {
            h,
            jacobian: js * jm * e.jacobian * jb,
            part,
        })
    }
}

/// The image `M_a(B(w, r))` of a disc inside the unit disk, exactly: a disc. The diameter of
/// `B(w, r)` on the line through the pole `1/ā` meets the circle at right angles, so its image
/// is a line through the image circle's centre, and the images of its two ends are opposite
/// points of that circle. Returns the image's centre and radius (`(w, r)` when `a = 0`).
pub(crate) fn mobius_disc(a: Vector2<f64>, w: Vector2<f64>, r: f64) -> (Vector2<f64>, f64) {
    if a == Vector2::zeros() || r == 0.0 {
        return (mobius(a, w).0, 0.0_f64.max(r));
    }
    let pole = a / a.norm_squared();
    let u = (pole - w).normalize();
    let (p, q) = (mobius(a, w + r * u).0, mobius(a, w - r * u).0);
    (0.5 * (p + q), 0.5 * (p - q).norm())
}

/// The disk automorphism `M_a(w) = (w − a)/(1 − ā w)` (complex notation, `|a| < 1`) and its
/// Jacobian, the conformal `M_a'(w) = (1 − |a|²)/(1 − ā w)²` as a rotation-scaling matrix.
fn mobius(a: Vector2<f64>, w: Vector2<f64>) -> (Vector2<f64>, Matrix2<f64>) {
    if a == Vector2::zeros() {
        // `M_0` is the identity: exact, and no `0·∞` for a non-finite `w`.
        return (w, Matrix2::identity());
    }
    // 1 − ā w
    let dr = 1.0 - (a.x * w.x + a.y * w.y);
    let di = -(a.x * w.y - a.y * w.x);
    let d2 = dr * dr + di * di;
    let (nr, ni) = (w.x - a.x, w.y - a.y);
    let m = Vector2::new((nr * dr + ni * di) / d2, (ni * dr - nr * di) / d2);
    // (1 − |a|²)/d² with d² the complex square (dr² − di², 2 dr di).
    let k = (1.0 - a.norm_squared()) / (d2 * d2);
    let (sr, si) = (dr * dr - di * di, 2.0 * dr * di);
    let (jr, ji) = (k * sr, -k * si);
    (m, Matrix2::new(jr, -ji, ji, jr))
}
