//! The navigation transformation `Phi` (definition `NavTran`) for a set of known obstacles.

use nalgebra::{Matrix2, Vector2};

use crate::index::{DiscIndex, INDEX_MIN, Lookup, pad};
use crate::radial::{Radial, obstacle_map, outer_map};
use crate::shape::StarShape;
use crate::workspace::{Workspace, WorldError};

/// Safety factor on the band widths (½ would make neighbouring bands touch). The distances
/// between shapes are certified lower bounds ([`StarShape::distance_to`]), and those to the
/// destination within [`crate::DISTANCE_TOLERANCE`] of the truth; 0.45 keeps the bands well
/// apart either way.
pub const WIDTH_FACTOR: f64 = 0.45;

/// Where a point lies for `Phi`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Active {
    /// Outside every band: `Phi(x) = x`.
    Identity,
    /// In the band of known obstacle `slot` (an index into [`NavTransform::known`]): the exact
    /// offset `Phi(x) − P_i = ν u` is given to avoid cancellation near the collapsed point.
    Obstacle {
        /// Index into the known obstacles.
        slot: usize,
        /// `Phi(x) − P_i`, formed as `ν·u` directly (maths.md §4, pitfall C).
        offset: Vector2<f64>,
    },
    /// In the band along the outer boundary.
    Outer,
}

/// `Phi(x)`, its Jacobian and which band produced them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mapped {
    /// `h = Phi(x)`.
    pub h: Vector2<f64>,
    /// `J_Phi(x)`.
    pub jacobian: Matrix2<f64>,
    /// The band the point lies in.
    pub active: Active,
}

/// `x` is not in the free space of the known obstacles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NotFree {
    /// Inside (or on) known obstacle `slot`.
    Obstacle(usize),
    /// On or beyond the outer boundary.
    Outside,
}

#[derive(Clone, Debug)]
struct Band {
    shape: StarShape,
    /// `ε_i = f·gap`.
    eps: f64,
    /// `min( min_j d(O_i, O_j), d(O_i, ∂O_0), 2 d(x_d, O_i) )` over the known `j ≠ i`.
    gap: f64,
}

/// The navigation transformation for the known obstacles (`docs/maths.md` §5): obstacle `i`'s
/// band of width `ε_i` collapses it to its centre, the outer band of width `ε_0` stretches the
/// boundary to infinity with gain `A`, identity elsewhere.
///
/// Widths, chosen automatically from the workspace's cached distances (f = [`WIDTH_FACTOR`]):
///
/// ```text
/// ε_i = f·min( min_j d(O_i, O_j), d(O_i, ∂O_0), 2 d(x_d, O_i) )      (i, j known)
/// ε_0 = f·min( min_i d(O_i, ∂O_0), 2 d(x_d, ∂O_0) )
/// A   = max(ε_0, 2 r*),  r* = k/(k − M)·|P_d − c_0 − (1/k) Σ_i (P_i − c_0)|
/// ```
///
/// so the bands are disjoint, inside the workspace, and exclude a neighbourhood of `x_d`
/// (where `Phi` is the identity); `r*` is the radius of the far-field valley of `phi_k`
/// (pitfall A), placed inside the stretched band. The potential's side supplies `r*` (the field
/// crate passes `PointWorld::valley_radius`), so this crate needs nothing of `phi_k`.
#[derive(Clone, Debug)]
pub struct NavTransform {
    known: Vec<usize>,
    bands: Vec<Band>,
    /// `[c_x, c_y, (max R + ε)²]` per band, contiguous for the per-step scan.
    reach: Vec<[f64; 3]>,
    /// The discs `(c_i, max R_i + ε_i)` that hold the bands, indexed (slot order).
    reaches: DiscIndex,
    /// How the band of a point is found (the workspace's).
    lookup: Lookup,
    /// The known obstacles' bounding discs `(c_i, max R_i)`, slot order (indexed lookup only):
    /// the widths' neighbour search.
    discs: DiscIndex,
    /// The discs `(c_i, (max R_i + gap_i)(1 + 2⁻²⁰))` with `gap_i` as it was when slot `i` was
    /// indexed (indexed lookup only): the slots whose width a new obstacle can narrow
    /// ([`NavTransform::push`]).
    narrowing: DiscIndex,
    /// The slot of each workspace obstacle (`usize::MAX`: not known).
    slot_of: Vec<usize>,
    /// `min( min_i d(O_i, ∂O_0), 2 d(x_d, ∂O_0) )` over the known `i`: `ε_0 = f·d0`.
    d0: f64,
    outer: StarShape,
    /// The centre of the outer map when it is not the boundary's own: the destination, for an
    /// ellipse boundary ([`NavTransform::outer_centre`]).
    about: Option<Vector2<f64>>,
    eps0: f64,
    gain: f64,
    /// Points with `|x − c_0| ≤ min R_0 − ε_0` are inside the identity region of the outer map.
    inner2: f64,
}

impl NavTransform {
    /// The transformation for the obstacles `known` (indices into [`Workspace::obstacles`], in
    /// band order) of `ws`. `valley_radius` is the radius `r*` of the potential's far-field
    /// valley about the outer centre `c_0` ([`Self::outer_centre`]; `PointWorld::valley_radius` in
    /// harmonav-potential, which this crate does not depend on); the stretch gain is
    /// `A = max(ε_0, 2 r*)`. Errors: an index out of range, or a `valley_radius` that is
    /// negative or not finite.
    pub fn new(ws: &Workspace, known: &[usize], valley_radius: f64) -> Result<Self, WorldError> {
        if let Some(&obstacle) = known.iter().find(|&&i| i >= ws.obstacles().len()) {
            return Err(WorldError::NoSuchObstacle { obstacle });
        }
        let lookup = ws.lookup();
        // The known obstacles' bounding discs, slot order: the widths' neighbour search.
        let discs = match lookup {
            Lookup::Direct => DiscIndex::default(),
            Lookup::Indexed => DiscIndex::new(known.iter().map(|&i| {
                let o = &ws.obstacles()[i];
                (o.centre(), o.radius_bounds().1)
            })),
        };
        let mut slot_of = vec![usize::MAX; ws.obstacles().len()];
        for (slot, &i) in known.iter().enumerate() {
            slot_of[i] = slot;
        }
        let mut bands = Vec::with_capacity(known.len());
        for (slot, &i) in known.iter().enumerate() {
            let start = ws.to_boundary(i).min(2.0 * ws.goal_to_obstacle(i));
            let gap = match lookup {
                Lookup::Direct => known
                    .iter()
                    .filter(|&&j| j != i)
                    .fold(start, |d, &j| d.min(ws.between(i, j))),
                Lookup::Indexed => nearest_gap(ws, &discs, known, &slot_of, slot, start),
            };
            let shape = ws.obstacles()[i].clone();
            bands.push(Band {
                shape,
                eps: WIDTH_FACTOR * gap,
                gap,
            });
        }
        let narrowing = match lookup {
            Lookup::Direct => DiscIndex::default(),
            Lookup::Indexed => DiscIndex::new(bands.iter().map(narrowing_disc)),
        };
        let d0 = known
            .iter()
            .map(|&i| ws.to_boundary(i))
            .fold(2.0 * ws.goal_to_boundary(), f64::min);
        let outer = ws.boundary().clone();
        let (r_min, r_max) = outer.radius_bounds();
        let about = (r_min < r_max
            && outer
                .radius_about(ws.destination(), Vector2::new(1.0, 0.0))
                .is_some())
        .then(|| ws.destination());
        let reach = bands.iter().map(reach_of).collect();
        let reaches = match lookup {
            Lookup::Direct => DiscIndex::default(),
            Lookup::Indexed => DiscIndex::new(bands.iter().map(reach_disc)),
        };
        let mut transform = Self {
            known: known.to_vec(),
            bands,
            reach,
            reaches,
            lookup,
            discs,
            narrowing,
            slot_of,
            d0,
            outer,
            about,
            eps0: 0.0,
            gain: 0.0,
            inner2: 0.0,
        };
        transform.set_outer_width(ws, d0);
        transform.with_valley_radius(valley_radius)
    }

    /// `ε_0 = f·d0` and the identity disc of the outer map that follows from it; the gain is
    /// reset to `ε_0` (valley radius 0).
    fn set_outer_width(&mut self, ws: &Workspace, d0: f64) {
        self.d0 = d0;
        self.eps0 = WIDTH_FACTOR * d0;
        let inner = match self.about {
            Some(_) => (ws.goal_to_boundary() - self.eps0).max(0.0),
            None => (self.outer.radius_bounds().0 - self.eps0).max(0.0),
        };
        self.inner2 = inner * inner;
        self.gain = self.eps0;
    }

    /// Obstacle `i` of `ws` becomes known, in the next slot: the same transformation as
    /// [`Self::new`]`(ws, known ++ [i], 0)`, bit for bit (the same widths, reaches, `ε_0`
    /// and gain `A = ε_0`; set the valley radius afterwards), without rebuilding the others.
    /// `ws` must be the workspace this transformation was built on, or that workspace with
    /// obstacles appended ([`Workspace::push_obstacle`]).
    ///
    /// Only the widths that the new obstacle narrows change. Slot `j`'s width is
    /// `ε_j = f·gap_j`, `gap_j = min(start_j, min_{k known} d(O_j, O_k))` with `start_j =
    /// min(d(O_j, ∂O_0), 2 d(x_d, O_j))` fixed by the workspace: a new known obstacle `i` adds
    /// one term, so `gap_j' = min(gap_j, d(O_j, O_i))` (a minimum of the same numbers as the
    /// rebuild's, so the same bits) and `ε_j` changes iff `d(O_j, O_i) < gap_j`. Those `j` are
    /// found without a scan: a near pair's `d` is in `i`'s row of the workspace; a far pair's is
    /// `|c_i − c_j| − R_i − R_j` ([`Workspace`]'s bounding-disc gap), below `gap_j` only if
    /// `|c_i − c_j| < R_i + R_j + gap_j`, i.e. only if `c_i` comes within `R_i` of the disc
    /// `(c_j, R_j + gap_j)`. Gaps only shrink, so the disc indexed when slot `j` was added
    /// (padded by `2⁻²⁰` of itself against rounding) holds the current one, and the query of
    /// that index about `c_i` with reach `R_i(1 + 2⁻²⁰)` reports every such `j` (and maybe
    /// others, whose minimum does not move). `ε_0 = f·min(d0, d(O_i, ∂O_0))` likewise.
    ///
    /// The reach index keeps a narrowed band's former (larger) disc: it only prunes, and the
    /// exact test on `reach` decides, as in [`Self::nav_transform`].
    ///
    /// Errors: [`WorldError::NoSuchObstacle`] if `i` is not an obstacle of `ws` or is known
    /// already (nothing changes).
    pub fn push(&mut self, ws: &Workspace, i: usize) -> Result<(), WorldError> {
        self.push_with(ws, i, true)
    }

    /// [`Self::push`]; `narrow = false` leaves the other widths as they were (wrong: the test
    /// that the incremental transformation equals a rebuilt one must detect it).
    #[doc(hidden)]
    pub fn push_with(&mut self, ws: &Workspace, i: usize, narrow: bool) -> Result<(), WorldError> {
        let m = ws.obstacles().len();
        if i >= m || self.slot_of.get(i).is_some_and(|&s| s != usize::MAX) {
            return Err(WorldError::NoSuchObstacle { obstacle: i });
        }
        self.slot_of.resize(m, usize::MAX);
        let slot = self.known.len();
        self.slot_of[i] = slot;
        self.known.push(i);
        let o = &ws.obstacles()[i];
        let start = ws.to_boundary(i).min(2.0 * ws.goal_to_obstacle(i));
        let gap = match self.lookup {
            Lookup::Direct => self.known[..slot]
                .iter()
                .fold(start, |d, &j| d.min(ws.between(i, j))),
            Lookup::Indexed => {
                self.discs.push(o.centre(), o.radius_bounds().1);
                nearest_gap(ws, &self.discs, &self.known, &self.slot_of, slot, start)
            }
        };
        // The slots whose gap the new obstacle may narrow (a superset; the minimum decides).
        let mut candidates = Vec::new();
        if narrow {
            match self.lookup {
                Lookup::Direct => candidates.extend(0..slot),
                Lookup::Indexed => {
                    for &(j, _) in ws.near_pairs(i) {
                        if let Some(&s) = self.slot_of.get(j)
                            && s != usize::MAX
                            && s != slot
                        {
                            candidates.push(s);
                        }
                    }
                    let reach = o.radius_bounds().1 * (1.0 + 2f64.powi(-20));
                    self.narrowing
                        .near(o.centre(), reach, |s| candidates.push(s));
                }
            }
        }
        for s in candidates {
            let d = ws.between(i, self.known[s]);
            let band = &mut self.bands[s];
            if d < band.gap {
                band.gap = d;
                band.eps = WIDTH_FACTOR * d;
                self.reach[s] = reach_of(band);
            }
        }
        let band = Band {
            shape: o.clone(),
            eps: WIDTH_FACTOR * gap,
            gap,
        };
        self.reach.push(reach_of(&band));
        if self.lookup == Lookup::Indexed {
            let (c, r) = reach_disc(&band);
            self.reaches.push(c, r);
            let (c, r) = narrowing_disc(&band);
            self.narrowing.push(c, r);
        }
        self.bands.push(band);
        self.set_outer_width(ws, self.d0.min(ws.to_boundary(i)));
        Ok(())
    }

    /// `ε_0` once an obstacle of clearance `d(O_i, ∂O_0) = to_boundary` becomes known
    /// ([`Self::push`]), without pushing it: `f·min(d0, to_boundary)`.
    #[must_use]
    pub fn outer_width_with(&self, to_boundary: f64) -> f64 {
        WIDTH_FACTOR * self.d0.min(to_boundary)
    }

    /// The same transformation with the stretch gain `A = max(ε_0, 2 r*)` for the valley
    /// radius `r* = valley_radius` (the bands do not depend on it). Errors: a `valley_radius`
    /// that is negative or not finite.
    pub fn with_valley_radius(mut self, valley_radius: f64) -> Result<Self, WorldError> {
        self.set_valley_radius(valley_radius)?;
        Ok(self)
    }

    /// [`Self::with_valley_radius`] in place (unchanged on error).
    pub fn set_valley_radius(&mut self, valley_radius: f64) -> Result<(), WorldError> {
        if !(valley_radius.is_finite() && valley_radius >= 0.0) {
            return Err(WorldError::InvalidValleyRadius {
                value: valley_radius,
            });
        }
        self.gain = self.eps0.max(2.0 * valley_radius);
        Ok(())
    }

    /// The known obstacles (indices into the workspace), in the order of their bands.
    pub fn known(&self) -> &[usize] {
        &self.known
    }

    /// The band width `ε_i` of each known obstacle.
    pub fn widths(&self) -> impl Iterator<Item = f64> + '_ {
        self.bands.iter().map(|b| b.eps)
    }

    /// The centre `c_0` of the outer map's rays. For an ellipse boundary (an exact ellipse: a
    /// boundary shrunk by the robot's radius is a sampled table and is not one) it is the
    /// destination `x_d` (the ellipse is convex, so star-shaped about it, and `R_0`, `R_0'`
    /// about it are closed forms: [`StarShape::radius_about`]); otherwise the boundary's
    /// centre, as in the paper. About the boundary's centre, a band near the long side of an
    /// elongated ellipse maps onto every radius out to infinity, including `|x_d − c_0|`, and
    /// so lies close to `x_d` in the point world: descents ran into it and stalled along the
    /// wall (50:1 ellipse: 13 of 20 random starts arrived). About `x_d`, `|Phi(x) − x_d| = ν`
    /// grows along every ray of the band, and 20 of 20 arrive (docs/maths.md §8).
    pub fn outer_centre(&self) -> Vector2<f64> {
        self.about.unwrap_or(self.outer.centre())
    }

    /// `(R_0, R_0')` of the boundary about [`Self::outer_centre`] in the direction `u`.
    fn outer_radius(&self, u: Vector2<f64>) -> (f64, f64) {
        match self.about.and_then(|p| self.outer.radius_about(p, u)) {
            Some(r) => r,
            None => self.outer.radius_along(u),
        }
    }

    /// The outer band width `ε_0` and stretch gain `A`.
    pub fn outer_band(&self) -> (f64, f64) {
        (self.eps0, self.gain)
    }

    /// The obstacle points `P_i` (the centres of the known obstacles, in band order).
    pub fn points(&self) -> impl Iterator<Item = Vector2<f64>> + '_ {
        self.bands.iter().map(|b| b.shape.centre())
    }

    /// The answer of the first slot (in order) for which `answer` is `Some`, among the slots
    /// whose reach could hold `p`: the direct loop stops at the first; the index visits only
    /// the slots whose reach holds `p` and keeps the lowest that answers, which is the same
    /// slot (every slot it skips would answer `None`).
    fn first_slot<T>(&self, p: Vector2<f64>, answer: impl Fn(usize) -> Option<T>) -> Option<T> {
        if self.lookup == Lookup::Direct || self.bands.len() < INDEX_MIN {
            return (0..self.bands.len()).find_map(answer);
        }
        let mut first: Option<(usize, T)> = None;
        self.reaches.near(p, 0.0, |slot| {
            if first.as_ref().is_none_or(|(s, _)| slot < *s)
                && let Some(a) = answer(slot)
            {
                first = Some((slot, a));
            }
        });
        first.map(|(_, a)| a)
    }

    /// `Phi(x)` with its Jacobian (definition `NavTran`); errors if `x` is not in the free
    /// space of the known obstacles. Allocation-free.
    pub fn nav_transform(&self, x: Vector2<f64>) -> Result<Mapped, NotFree> {
        // The first slot (in order) whose band or obstacle holds x: the direct loop stops at
        // it; the index tests only the slots whose reach could hold x and keeps the lowest
        // that answers, which is the same slot (every slot it skips fails the reach test).
        if let Some(answer) = self.first_slot(x, |slot| self.in_band(slot, x)) {
            return answer;
        }
        self.outside_bands(x)
    }

    /// Band `slot`'s answer at `x`: inside its obstacle, `Phi` in its band, or `None` (`x` is
    /// beyond its reach or its band). The reach test is inlined into the loop over the slots
    /// ([`Self::first_slot`]); only a slot whose reach holds `x` calls [`Self::band_at`]. (As
    /// one call per slot, with its large return value, the lookup took 1.6·10⁹ instructions of
    /// `bench --only field_eval` (20 discs) where the inline test takes 0.8·10⁹: callgrind,
    /// docs/benchmarks.md "Side by side".)
    #[inline(always)]
    fn in_band(&self, slot: usize, x: Vector2<f64>) -> Option<Result<Mapped, NotFree>> {
        let [cx, cy, reach2] = self.reach[slot];
        let (dx, dy) = (x.x - cx, x.y - cy);
        let rho2 = dx * dx + dy * dy;
        if rho2 >= reach2 {
            return None;
        }
        self.band_at(slot, Vector2::new(dx, dy), rho2)
    }

    /// [`Self::in_band`] for a slot whose reach holds the point `c_i + v`, `rho2 = |v|²`.
    #[inline(never)]
    fn band_at(&self, slot: usize, v: Vector2<f64>, rho2: f64) -> Option<Result<Mapped, NotFree>> {
        let band = &self.bands[slot];
        let rho = rho2.sqrt();
        if rho == 0.0 {
            return Some(Err(NotFree::Obstacle(slot)));
        }
        let u = v / rho;
        let (r, dr) = band.shape.radius_along(u);
        if rho <= r {
            return Some(Err(NotFree::Obstacle(slot)));
        }
        if rho < r + band.eps {
            let m = obstacle_map(rho, r, dr, band.eps);
            let offset = m.nu * u;
            return Some(Ok(Mapped {
                h: band.shape.centre() + offset,
                jacobian: m.jacobian(u, rho),
                active: Active::Obstacle { slot, offset },
            }));
        }
        None
    }

    /// Band `slot`'s inverse at `h`: `Some(None)` at its point `P_i`, `Some(Some(x))` if `h`
    /// lies in its image (`ν < R + ε`), `None` otherwise.
    fn band_inverse(&self, slot: usize, h: Vector2<f64>) -> Option<Option<Vector2<f64>>> {
        let band = &self.bands[slot];
        let v = h - band.shape.centre();
        let nu = v.norm();
        if nu == 0.0 {
            return Some(None);
        }
        let (r, dr) = band.shape.radius(v.y.atan2(v.x));
        if nu < r + band.eps {
            let rho = bisect(r, r + band.eps, nu, |rho| {
                obstacle_map(rho, r, dr, band.eps).nu
            });
            return Some(Some(band.shape.centre() + rho * v / nu));
        }
        None
    }

    /// `Phi(x)` for a point in no obstacle band: the outer band or the identity.
    fn outside_bands(&self, x: Vector2<f64>) -> Result<Mapped, NotFree> {
        let v = x - self.outer_centre();
        let rho2 = v.norm_squared();
        if rho2 > self.inner2 {
            let rho = rho2.sqrt();
            let u = v / rho;
            let (r0, dr0) = self.outer_radius(u);
            if rho >= r0 {
                return Err(NotFree::Outside);
            }
            if rho > r0 - self.eps0 {
                let m: Radial = outer_map(rho, r0, dr0, self.eps0, self.gain);
                return Ok(Mapped {
                    h: self.outer_centre() + m.nu * u,
                    jacobian: m.jacobian(u, rho),
                    active: Active::Outer,
                });
            }
        }
        Ok(Mapped {
            h: x,
            jacobian: Matrix2::identity(),
            active: Active::Identity,
        })
    }

    /// For many points at once, which ones lie where `Phi` is the identity and the point is
    /// free: outside every band's reach (`|x − c_i| ≥ max R_i + ε_i`, which also excludes the
    /// obstacles) and inside the identity disc of the outer map (`|x − c_0| ≤ min R_0 − ε_0`).
    /// `identity[n]` is set for `xs[n]`; `false` says only that [`Self::nav_transform`] has to
    /// decide (a band, an obstacle, outside, or a NaN coordinate). There
    /// `nav_transform(x) = (x, I, Identity)` exactly. The band loop runs outside the point loop
    /// without branches, so it vectorises across points. Only the common length is written.
    pub fn identity_mask(&self, xs: &[Vector2<f64>], identity: &mut [bool]) {
        let n = xs.len().min(identity.len());
        let (xs, identity) = (&xs[..n], &mut identity[..n]);
        let c0 = self.outer_centre();
        for (x, id) in xs.iter().zip(identity.iter_mut()) {
            let (dx, dy) = (x.x - c0.x, x.y - c0.y);
            *id = dx * dx + dy * dy <= self.inner2;
        }
        for &[cx, cy, reach2] in &self.reach {
            for (x, id) in xs.iter().zip(identity.iter_mut()) {
                let (dx, dy) = (x.x - cx, x.y - cy);
                *id &= dx * dx + dy * dy >= reach2;
            }
        }
    }

    /// `Phi⁻¹(h)` by bisection on `ν` along the ray (each band map increases strictly in `ρ`);
    /// `None` if `h` is an obstacle point `P_i`. Accurate to ~1e-14 relative.
    pub fn inverse(&self, h: Vector2<f64>) -> Option<Vector2<f64>> {
        // The first band in order that holds h (its ν < R + ε ≤ max R + ε: only slots whose
        // reach holds h can), as in `nav_transform`.
        if let Some(answer) = self.first_slot(h, |slot| self.band_inverse(slot, h)) {
            return answer;
        }
        let c0 = self.outer_centre();
        let v = h - c0;
        let nu = v.norm();
        if nu == 0.0 {
            // c_0 lies inside the identity region (the boundary's centre, or x_d).
            return Some(h);
        }
        let (r0, dr0) = self.outer_radius(v / nu);
        if nu > r0 - self.eps0 {
            let rho = bisect(r0 - self.eps0, r0, nu, |rho| {
                outer_map(rho, r0, dr0, self.eps0, self.gain).nu
            });
            return Some(c0 + rho * v / nu);
        }
        Some(h)
    }
}

/// The smallest `d(O_i, O_j)` over the known `j ≠ i` (`i` = `known[slot]`) and `start`, as
/// the direct fold computes it: the near pairs from the workspace's cache, the far ones (whose
/// gap is `|c_i − c_j| − R_i − R_j`, at least the distance from `c_i` to `j`'s box less `R_i`)
/// by a pruned search of the known discs.
fn nearest_gap(
    ws: &Workspace,
    discs: &DiscIndex,
    known: &[usize],
    slot_of: &[usize],
    slot: usize,
    start: f64,
) -> f64 {
    let i = known[slot];
    let near = ws.near_pairs(i);
    let mut best = start;
    for &(j, d) in near {
        if slot_of[j] != usize::MAX {
            best = best.min(d);
        }
    }
    let o = &ws.obstacles()[i];
    let (c, r) = (o.centre(), o.radius_bounds().1);
    let slack = 2.0 * pad(c, r);
    discs.min_cost(
        c,
        best,
        |d| d - r - slack,
        |s| {
            let j = known[s];
            let is_near = near.binary_search_by_key(&j, |&(j, _)| j).is_ok();
            (j != i && !is_near).then(|| ws.between(i, j))
        },
    )
}

/// `[c_x, c_y, (max R + ε)²]`: beyond `max R + ε` from its centre a band cannot hold a point.
fn reach_of(b: &Band) -> [f64; 3] {
    let c = b.shape.centre();
    let r = b.shape.radius_bounds().1 + b.eps;
    [c.x, c.y, r * r]
}

/// The disc `(c_i, max R_i + ε_i)` that holds band `i`.
fn reach_disc(b: &Band) -> (Vector2<f64>, f64) {
    (b.shape.centre(), b.shape.radius_bounds().1 + b.eps)
}

/// The disc `(c_i, (max R_i + gap_i)(1 + 2⁻²⁰))`: a far obstacle narrows band `i` only if its
/// bounding disc reaches into it ([`NavTransform::push`]).
fn narrowing_disc(b: &Band) -> (Vector2<f64>, f64) {
    let r = b.shape.radius_bounds().1 + b.gap;
    (b.shape.centre(), r * (1.0 + 2f64.powi(-20)))
}

/// Solves `f(ρ) = target` for increasing `f` on `[lo, hi]` by bisection.
fn bisect(mut lo: f64, mut hi: f64, target: f64, f: impl Fn(f64) -> f64) -> f64 {
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if f(mid) < target { lo = mid } else { hi = mid }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn world() -> Workspace {
        let boundary = StarShape::circle(Vector2::zeros(), 5.0).unwrap();
        let rock = StarShape::circle(Vector2::new(1.0, 0.0), 0.5).unwrap();
        Workspace::new(boundary, vec![rock], Vector2::new(-3.0, 0.0)).unwrap()
    }

    #[test]
    fn bad_indices_and_valley_radii_are_rejected() {
        let ws = world();
        assert_eq!(
            NavTransform::new(&ws, &[1], 1.0).err(),
            Some(WorldError::NoSuchObstacle { obstacle: 1 })
        );
        for bad in [-1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                NavTransform::new(&ws, &[0], bad),
                Err(WorldError::InvalidValleyRadius { .. })
            ));
        }
    }

    /// The stretch gain is `A = max(ε_0, 2 r*)`: the valley radius sets it once it exceeds
    /// `ε_0/2`.
    #[test]
    fn the_valley_radius_sets_the_stretch_gain() {
        let ws = world();
        let (eps0, small) = NavTransform::new(&ws, &[0], 0.0).unwrap().outer_band();
        assert_eq!(small, eps0);
        let (_, gain) = NavTransform::new(&ws, &[0], 30.0).unwrap().outer_band();
        assert_eq!(gain, 60.0);
    }
}
