//! The conservative star fit of one segment (crate docs: the region `Y`, the assumptions and
//! the proof that `Y` contains the true obstacle).
//!
//! With the hits `p_1..p_m` of the segment, the sensor at `s`, the noise bound `ε`, the depth
//! prior `D` and the curvature prior `ρ_min`:
//!
//! ```text
//! K   = ∩_k B(p_k, D + ε)                 (k over at most 8 hits spread along the segment)
//! T_i = triangle(s, p_i − κ_i u_i, p_{i+1} − κ_i u_{i+1}),  κ_i = e_i / min(u_i·n_i, u_{i+1}·n_i)
//! e_i = ε + sag(c_i),  c_i = |p_{i+1} − p_i| + 2ε,  sag(c) = ρ_min − √(ρ_min² − c²/4)   (eq. sagitta)
//! Y   = K \ int(T_1 ∪ … ∪ T_{m−1})                                                       (eq. region)
//! ```
//!
//! (`n_i` the unit normal of the chord `p_i p_{i+1}` pointing away from the sensor.) A wedge is
//! not cut (no `T_i`) when `c_i > 2ρ_min` (no sagitta bound), when the chord is seen at more
//! than ~87° from its normal (`u·n < 0.05`), or when the sensor is within `e_i` of the chord's
//! line. The fit is [`certified`] (a radial hull or a Fourier star, [`StarForm`]) about a centre
//! behind the visible arc over a cover of `∂Y` (eq. certify), so it contains `Y`.

use std::f64::consts::{PI, TAU};

use harmonav_transform::ShapeError;
use nalgebra::Vector2;

use crate::boxes::{Aabb, BoxTree};
use crate::free::{FreeSet, sagitta, segment_distance};
use crate::perceived::{Certification, Perceived, StarForm, certified, least_hull};
use crate::scan::{LaserScan, Pose};
use crate::segment::{Segment, hit_point};

/// How many beams outward from each end of a segment are searched for a side cut (eq. side).
pub const SIDE_BEAMS: usize = 64;

/// The most hits whose discs make `K` (any subset gives a superset of `K`, so fewer is still
/// sound: only looser).
const K_DISCS: usize = 8;

/// Smallest `u·n` at which a wedge is cut (`κ = e/(u·n)` grows without bound at grazing).
const MIN_INCIDENCE: f64 = 0.05;

/// The priors and resolution of a fit (see [`crate::Options`] for their meaning).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitParams {
    /// `ε`, m.
    pub range_noise: f64,
    /// `D`, m.
    pub max_obstacle_depth: f64,
    /// `ρ_min`, m.
    pub rho_min: f64,
    /// Highest harmonic of the fit (for [`StarForm::Fourier`]).
    pub order: u32,
    /// The fit's representation.
    pub form: StarForm,
    /// `h`, m: spacing of the cover of `∂Y` (eq. certify).
    pub check_spacing: f64,
    /// `r_k`, m: a radial hull that comes nearer than `r_k + 2h` to the sensor is taken about
    /// another centre that keeps it that far out, when one does (`crate::Options::keep_out`).
    pub keep_out: f64,
}

/// A fitted segment.
#[derive(Clone, Debug)]
pub struct Fit {
    /// The region `Y` the star contains (for tests of the claim `O ⊂ Y`).
    region: Region,
    /// The star, which contains the region `Y` of eq. region.
    pub perceived: Perceived,
    /// Wedges cut from `K` (at most `m − 1`).
    pub cut_wedges: usize,
    /// Side cuts (eq. side), 0 to 2.
    pub side_cuts: usize,
    /// Samples of the boundary of the free set `R` (eqs. freefan, wallgap) the star was
    /// certified over.
    pub free_samples: usize,
    /// How the star was certified.
    pub certification: Certification,
}

impl Fit {
    /// Whether `x` lies in the region `Y` of eq. region (closed: on `K` and the kept sides of
    /// the side cuts, outside the open cut polygons and the free side beams before their end
    /// cuts). The claim of the crate docs is `O ⊂ Y ⊂ F`; this tests the first inclusion.
    #[must_use]
    pub fn region_contains(&self, x: Vector2<f64>) -> bool {
        let r = &self.region;
        r.near_k_sharp(x, 0.0)
            && !r.planes.iter().any(|p| p.hair(x, 0.0))
            && !r.cuts.iter().any(|poly| inside(poly, x))
    }
}

/// Why a segment has no fit.
#[derive(Clone, Debug, PartialEq)]
pub enum FitFailure {
    /// Two hits are farther apart than `D + 2ε`: the depth prior cannot hold for this
    /// segment (an obstacle wider than `D`, or two obstacles joined by the segmentation).
    WiderThanDepth {
        /// The largest distance between two hits, m.
        span: f64,
        /// `D + 2ε`, m.
        limit: f64,
    },
    /// The star could not be built.
    Shape(ShapeError),
}

/// A side cut: the beam `s + t u`, the inward normal `m`, the chord of `K` on the beam.
#[derive(Clone, Debug)]
struct Plane {
    s: Vector2<f64>,
    u: Vector2<f64>,
    m: Vector2<f64>,
    chord: (f64, f64),
    /// Range of the end cut's vertex on this beam (eq. end), 0 without one: the beam is free
    /// across `K` and borders the removed end triangle before `tau`, so no point of the beam
    /// nearer than `tau` is on `∂Y`.
    tau: f64,
}

impl Plane {
    /// Whether `x` lies on this beam nearer than `tau − h` (not on `∂Y`, nor within `h/2` of a
    /// point of `∂Y` on the beam).
    fn hair(&self, x: Vector2<f64>, h: f64) -> bool {
        self.on_line(x) && self.u.dot(&(x - self.s)) < self.tau - h
    }

    /// Whether `x` lies on the beam's line (to rounding).
    fn on_line(&self, x: Vector2<f64>) -> bool {
        let v = x - self.s;
        self.m.dot(&v).abs() <= 1e-9 * (1.0 + v.norm())
    }
}

/// The region `Y` of eq. region.
#[derive(Clone, Debug)]
struct Region {
    discs: Vec<Vector2<f64>>,
    radius: f64,
    /// Side cuts (eq. side): `(s, u, m, chord)` keeps `m·(x − s) ≥ 0` (`m ⊥ u`), with the
    /// chord `[t_in, t_out]` of `K` on the beam `s + t u`.
    planes: Vec<Plane>,
    /// Runs of neighbouring cut wedges, each the polygon `s, a_i, b_i, a_{i+1}, …, b_j`.
    cuts: Vec<Vec<Vector2<f64>>>,
    /// The cut polygons indexed for [`Region::deep_in_cut`] ([`Region::indexed`]).
    index: CutIndex,
}

/// The cut polygons of a [`Region`] indexed so that [`Region::deep_in_cut`] costs about
/// `O(log m)` instead of `O(m)` (`m` hits): the polygons that may hold a point found by its
/// direction from the sensor, and in a polygon only the edges near the point visited (a
/// [`BoxTree`] over its edges); the edges on a side cut's line (the direct test's
/// `on_plane`) found once.
///
/// *The directions.* A cut polygon `s, v_1, …, v_L` (a run of wedges and end triangles, all
/// vertices but `s` on beams) is, by the even-odd rule, inside the union of the triangles
/// `(s, v_k, v_{k+1})` (the winding number about a point off their lines is the sum of theirs).
/// With `α(y) = ∠(w, y − s) ∈ (−π, π]` (`w` the direction of the mean hit) and neighbouring
/// vertices less than `π − 10⁻⁶` apart in `α` (no `v_k = s`), each triangle's points have `α`
/// between its vertices', so the polygon's in `[α_lo, α_hi]` (its vertices' least and
/// largest); such a polygon is *regular*. A point within `δ` of it, `r = |x − s| > 2δ`, then has
/// `α(x)` within `μ = 2δ/r + 10⁻⁹` of that interval (or of it shifted by `±2π`): `asin(δ/r) ≤ 2δ/r`,
/// and the computed angles are off by `~10⁻¹⁵`.
///
/// *Same decisions.* With `δ = 10⁻⁹·(1 + M + h)` (`M` the largest coordinate magnitude of a
/// cut vertex) and `g = h + δ`: the crossing number computes each crossing's abscissa within
/// `~7u·M` (`u = 2⁻⁵³`) of the true one on the edge, so at a point farther than `δ` from the
/// polygon it is exact and says outside: a regular polygon without a side-cut edge whose
/// interval misses `α(x)` by more than `μ` is not deep (`deep` needs inside). In a polygon, an
/// edge box grown by `g` that misses `x` holds no edge within `h` as `segment_distance`
/// computes it (the nearest point is computed within `~5u·M` of the box, the distance within a
/// relative `~4u`), and a crossing lies at most `~7u·M` right of its edge's box. So the index
/// skips only what the loops over all polygons and edges would have found false: the same
/// decisions, to the bit. The other polygons (with a side-cut edge, or not regular) and
/// points within `2δ` of the sensor are tested polygon by polygon.
#[derive(Clone, Debug, Default)]
struct CutIndex {
    /// The sensor.
    s: Vector2<f64>,
    /// `w`: the direction of the mean hit from `s`.
    w: Vector2<f64>,
    /// The polygons tested whatever the point's direction: with an edge on a side cut's line,
    /// or not regular.
    always: Vec<usize>,
    /// Per polygon, whether it is in `sectors` (regular, no side-cut edge).
    sorted: Vec<bool>,
    /// Per polygon, the side cuts (indices into `Region::planes`) that carry one of its edges
    /// (each edge's first such plane, as `Iterator::find` takes it).
    planes: Vec<Vec<usize>>,
    /// Per polygon, whether edge `k` (`poly[k]` to `poly[k + 1]`, cyclically) lies on a side
    /// cut's line.
    on_plane: Vec<Vec<bool>>,
    /// Per polygon, the tree over its edges' boxes.
    edges: Vec<BoxTree>,
    /// The tree over the regular polygons' intervals `[α_lo, α_hi] × {0}` (empty for the others).
    sectors: BoxTree,
    /// `1 + M` (`M` above).
    scale: f64,
}

impl CutIndex {
    /// `α(x)` (type docs), `NaN` at `x = s`.
    fn angle(&self, x: Vector2<f64>) -> f64 {
        let v = x - self.s;
        if v == Vector2::zeros() {
            return f64::NAN;
        }
        (self.w.x * v.y - self.w.y * v.x).atan2(self.w.dot(&v))
    }

    /// The interval `[α_lo, α_hi]` of a regular polygon (type docs), `None` if it is not.
    fn sector(&self, poly: &[Vector2<f64>]) -> Option<(f64, f64)> {
        let alphas: Vec<f64> = poly[1..].iter().map(|&v| self.angle(v)).collect();
        let regular = poly[0] == self.s
            && alphas.iter().all(|a| a.is_finite())
            && alphas.windows(2).all(|p| (p[1] - p[0]).abs() <= PI - 1e-6);
        regular.then(|| {
            alphas
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &a| {
                    (lo.min(a), hi.max(a))
                })
        })
    }
}

impl Region {
    /// Whether `x` is within `tol` of `K`, tested disc by disc (sufficient: within `tol` of
    /// every disc holds for every point within `tol` of `K`).
    fn near_k(&self, x: Vector2<f64>, tol: f64) -> bool {
        self.near_discs(x, tol) && self.planes.iter().all(|p| p.m.dot(&(x - p.s)) >= -tol)
    }

    /// Within `tol` of the discs and on the kept side of every side cut.
    fn near_k_sharp(&self, x: Vector2<f64>, tol: f64) -> bool {
        self.near_discs(x, tol) && self.planes.iter().all(|p| p.m.dot(&(x - p.s)) >= 0.0)
    }

    /// Whether `x` is within `tol` of every disc of `K`.
    fn near_discs(&self, x: Vector2<f64>, tol: f64) -> bool {
        self.discs
            .iter()
            .all(|q| (x - q).norm() <= self.radius + tol)
    }

    /// The chord `[t_in, t_out]` of `K` on the ray `s + t u`, `None` if it misses `K`.
    fn chord(&self, s: Vector2<f64>, u: Vector2<f64>) -> Option<(f64, f64)> {
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for q in &self.discs {
            let w = s - q;
            let b = w.dot(&u);
            let disc = b * b - (w.norm_squared() - self.radius * self.radius);
            if disc < 0.0 {
                return None;
            }
            lo = lo.max(-b - disc.sqrt());
            hi = hi.min(-b + disc.sqrt());
        }
        (lo <= hi && hi >= 0.0).then_some((lo.max(0.0), hi))
    }

    /// The region with its cut polygons indexed ([`CutIndex`]) for the sensor `s` and the
    /// direction `w` of the mean hit, once the cuts and the side cuts are final.
    fn indexed(mut self, s: Vector2<f64>, w: Vector2<f64>) -> Self {
        let mut index = CutIndex {
            s,
            w,
            scale: 1.0
                + self
                    .cuts
                    .iter()
                    .flatten()
                    .map(|v| v.x.abs().max(v.y.abs()))
                    .fold(0.0, f64::max),
            ..CutIndex::default()
        };
        let mut sectors = Vec::with_capacity(self.cuts.len());
        for (k, poly) in self.cuts.iter().enumerate() {
            let carrier: Vec<Option<usize>> = edges(poly)
                .map(|(a, b)| {
                    self.planes
                        .iter()
                        .position(|p| p.on_line(a) && p.on_line(b))
                })
                .collect();
            let mut planes: Vec<usize> = carrier.iter().flatten().copied().collect();
            planes.dedup();
            let sector = index.sector(poly).filter(|_| planes.is_empty());
            if sector.is_none() {
                index.always.push(k);
            }
            index.sorted.push(sector.is_some());
            sectors.push(sector.map_or(Aabb::EMPTY, |(lo, hi)| Aabb {
                min: Vector2::new(lo, 0.0),
                max: Vector2::new(hi, 0.0),
            }));
            index.planes.push(planes);
            index
                .on_plane
                .push(carrier.iter().map(Option::is_some).collect());
            let boxes: Vec<Aabb> = edges(poly).map(|(a, b)| Aabb::of([a, b])).collect();
            index.edges.push(BoxTree::new(&boxes));
        }
        index.sectors = BoxTree::new(&sectors);
        self.index = index;
        self
    }

    /// Whether `B(x, h)` lies in the removed set `int(cuts) ∪ {beyond a side cut}`: `x` inside
    /// a cut polygon (or more than `h` beyond a side cut whose beam carries one of its edges)
    /// and more than `h` from the polygon's other edges. (A ball that meets no other edge can leave the
    /// polygon only across the side cut's beam, into the removed half-plane.)
    ///
    /// Only the polygons that may hold `x` by its direction from the sensor are tested, and the
    /// others with a side-cut edge or not regular ([`CutIndex`]: the rest are not deep);
    /// [`Region::deep_in_polygon`] then looks only at the edges near `x`.
    fn deep_in_cut(&self, x: Vector2<f64>, h: f64) -> bool {
        let index = &self.index;
        let delta = 1e-9 * (index.scale + h);
        let g = h + delta;
        let r = (x - index.s).norm();
        let alpha = index.angle(x);
        if !(r > 2.0 * delta && alpha.is_finite()) {
            return (0..self.cuts.len()).any(|k| self.deep_in_polygon(k, x, h, g));
        }
        let mu = 2.0 * delta / r + 1e-9;
        let towards = |b: &Aabb| {
            [alpha - TAU, alpha, alpha + TAU]
                .iter()
                .any(|&a| b.holds(Vector2::new(a, 0.0), mu))
        };
        index
            .always
            .iter()
            .any(|&k| self.deep_in_polygon(k, x, h, g))
            || index.sectors.any(&towards, &mut |k| {
                index.sorted[k] && self.deep_in_polygon(k, x, h, g)
            })
    }

    /// [`Region::deep_in_cut`] for cut polygon `k` (`g` its slack): more than `h` beyond a
    /// side cut that carries one of its edges, or inside it (the crossing number over the
    /// edges that straddle `x`'s row and do not lie wholly left of it, more than `g`), and
    /// more than `h` from every other edge (over the edges whose box grown by `g` holds `x`).
    ///
    /// ```text
    /// deep_k(x) = (∃ side edge on plane p: m_p·(x − s) < −h  ∨  x ∈ int P_k)  ∧  ∀ other edge e: d(x, e) > h
    /// ```
    fn deep_in_polygon(&self, k: usize, x: Vector2<f64>, h: f64, g: f64) -> bool {
        let (poly, index) = (&self.cuts[k], &self.index);
        // Beyond by more than `h`: a point on the beam's line (where `∂Y` runs along a side
        // cut) or just beyond it by rounding has a ball that reaches back into `Y`.
        let beyond = index.planes[k].iter().any(|&j| {
            let p = &self.planes[j];
            p.m.dot(&(x - p.s)) < -h
        });
        let edge = |e: usize| (poly[e], poly[(e + 1) % poly.len()]);
        let tree = &index.edges[k];
        let inside = || {
            let mut odd = false;
            tree.any(
                &|b| b.min.y <= x.y && x.y < b.max.y && x.x <= b.max.x + g,
                &mut |e| {
                    let (a, b) = edge(e);
                    odd ^= crosses(a, b, x);
                    false
                },
            );
            odd
        };
        let near = || {
            tree.any(&|b| b.holds(x, g), &mut |e| {
                let (a, b) = edge(e);
                !index.on_plane[k][e] && segment_distance(a, b, x) <= h
            })
        };
        (beyond || inside()) && !near()
    }
}

fn edges(poly: &[Vector2<f64>]) -> impl Iterator<Item = (Vector2<f64>, Vector2<f64>)> + '_ {
    (0..poly.len()).map(move |k| (poly[k], poly[(k + 1) % poly.len()]))
}

/// Crossing-number point-in-polygon.
fn inside(poly: &[Vector2<f64>], x: Vector2<f64>) -> bool {
    edges(poly).fold(false, |odd, (a, b)| odd ^ crosses(a, b, x))
}

/// Whether the edge `ab` crosses the ray from `x` towards `+x` (half-open in `y`: it straddles
/// the row, `min(a_y, b_y) ≤ x_y < max(a_y, b_y)`).
fn crosses(a: Vector2<f64>, b: Vector2<f64>, x: Vector2<f64>) -> bool {
    if (a.y > x.y) != (b.y > x.y) {
        let t = (x.y - a.y) / (b.y - a.y);
        x.x < a.x + t * (b.x - a.x)
    } else {
        false
    }
}

/// The largest distance between two of the points, `max |p_i − p_j|` as computed pair by
/// pair. A bounding-volume hierarchy (`boxes::BoxTree`) over the points skips, for each point
/// `a`, the nodes whose farthest corner from `a` is not farther than the largest distance found
/// so far: the computed distance to a point of a box is at most the one to the corner with the
/// larger `|a_x − x|` and `|a_y − y|` (rounding is monotone), so the skipped pairs cannot raise the
/// maximum and the result is the one of the loop over all pairs, to the bit. `O(m log m)` for
/// hits along a curve, `O(m²)` at worst.
#[must_use]
pub fn span(points: &[Vector2<f64>]) -> f64 {
    let boxes: Vec<Aabb> = points.iter().map(|&p| Aabb::of([p])).collect();
    let tree = BoxTree::new(&boxes);
    let best = std::cell::Cell::new(0.0f64);
    for a in points {
        let farthest = |b: &Aabb| {
            let dx = (a.x - b.min.x).abs().max((a.x - b.max.x).abs());
            let dy = (a.y - b.min.y).abs().max((a.y - b.max.y).abs());
            Vector2::new(dx, dy).norm()
        };
        tree.any(&|b| farthest(b) > best.get(), &mut |j| {
            best.set(best.get().max((a - points[j]).norm()));
            false
        });
    }
    best.get()
}

/// The wedge cut `T_i` between hits `(p, u)` and `(q, v)` (eq. region), as its far vertices
/// `(a, b)`, or `None` when the wedge is not cut.
fn wedge_cut(
    s: Vector2<f64>,
    (p, u): (Vector2<f64>, Vector2<f64>),
    (q, v): (Vector2<f64>, Vector2<f64>),
    params: &FitParams,
) -> Option<(Vector2<f64>, Vector2<f64>)> {
    let eps = params.range_noise;
    let chord = q - p;
    let len = chord.norm();
    if len == 0.0 {
        return None;
    }
    let e = eps + sagitta(len + 2.0 * eps, params.rho_min);
    if !e.is_finite() {
        return None;
    }
    let mut n = Vector2::new(chord.y, -chord.x) / len;
    if n.dot(&(p - s)) < 0.0 {
        n = -n;
    }
    let cos = u.dot(&n).min(v.dot(&n));
    // The sensor must lie on the near side, at least e from the chord's line.
    if cos < MIN_INCIDENCE || n.dot(&(p - s)) < e {
        return None;
    }
    let kappa = e / cos;
    let (rp, rq) = ((p - s).norm(), (q - s).norm());
    if kappa >= rp.min(rq) {
        return None;
    }
    Some((p - kappa * u, q - kappa * v))
}

/// Eq. end: the free triangle between the end hit `(p, u)` and the side beam `v` of its side
/// cut, as its far vertices `(on u, on v)`:
///
/// ```text
/// τ = |p − s| − ε − sag(2w) − w,   w = 2|p − s|·sin(∠(u, v)/2)                     (eq. end)
/// ```
///
/// `None` when `w ≥ 2ρ_min` or `τ ≤ 0`. Under (A4) (crate docs) no point of the obstacle lies in
/// it.
fn end_cut(
    s: Vector2<f64>,
    (p, u): (Vector2<f64>, Vector2<f64>),
    v: Vector2<f64>,
    params: &FitParams,
) -> Option<(Vector2<f64>, Vector2<f64>)> {
    let r = (p - s).norm();
    let half = 0.5 * (u - v).norm(); // sin(∠/2)
    let w = 2.0 * r * half;
    if w >= 2.0 * params.rho_min {
        return None;
    }
    let tau = r - params.range_noise - sagitta(2.0 * w, params.rho_min) - w;
    (tau.is_finite() && tau > 0.0).then(|| (s + tau * u, s + tau * v))
}

/// Eq. region for the hits `points` (in angular order, beam directions `dirs`) seen from `s`.
fn region(
    s: Vector2<f64>,
    points: &[Vector2<f64>],
    dirs: &[Vector2<f64>],
    sides: &[Vec<(Vector2<f64>, f64)>; 2],
    params: &FitParams,
) -> Region {
    let m = points.len();
    let discs = if m <= K_DISCS {
        points.to_vec()
    } else {
        (0..K_DISCS)
            .map(|k| points[(k * (m - 1)) / (K_DISCS - 1)])
            .collect()
    };
    let mut region = Region {
        discs,
        radius: params.max_obstacle_depth + params.range_noise,
        planes: Vec::new(),
        cuts: Vec::new(),
        index: CutIndex::default(),
    };
    // Eq. side: the first beam outward on each side whose free part covers its chord of K.
    let mut side_beam: [Option<Vector2<f64>>; 2] = [None, None];
    for (k, side) in sides.iter().enumerate() {
        for &(u, free) in side {
            let Some((t_in, t_out)) = region.chord(s, u) else {
                break; // K lies wholly on the hits' side of this line: no cut needed.
            };
            if free < t_out {
                continue;
            }
            let mut m = Vector2::new(-u.y, u.x);
            let side_of = |p: &Vector2<f64>| m.dot(&(p - s));
            let lo = points.iter().map(side_of).fold(f64::INFINITY, f64::min);
            let hi = points.iter().map(side_of).fold(f64::NEG_INFINITY, f64::max);
            if hi <= 0.0 {
                m = -m;
            } else if lo < 0.0 {
                break; // The hits straddle the line: it is not beside the segment.
            }
            region.planes.push(Plane {
                s,
                u,
                m,
                chord: (t_in, t_out),
                tau: 0.0,
            });
            side_beam[k] = Some(u);
            break;
        }
    }
    // The fan's free triangles in angular order: the start's end wedge (eq. end), the wedges
    // between hits (eq. region), the end's end wedge; runs of neighbours become one polygon.
    let mut fan: Vec<Option<(Vector2<f64>, Vector2<f64>)>> = Vec::with_capacity(m + 1);
    let mut end = |k: usize, hit: usize| -> Option<(Vector2<f64>, Vector2<f64>)> {
        let cut = end_cut(s, (points[hit], dirs[hit]), side_beam[k]?, params)?;
        let plane = region
            .planes
            .iter_mut()
            .find(|p| Some(p.u) == side_beam[k])?;
        plane.tau = (cut.1 - s).norm();
        Some(cut)
    };
    let first = end(0, 0).map(|(a, b)| (b, a));
    let last = end(1, m - 1);
    fan.push(first);
    for i in 0..m.saturating_sub(1) {
        fan.push(wedge_cut(
            s,
            (points[i], dirs[i]),
            (points[i + 1], dirs[i + 1]),
            params,
        ));
    }
    fan.push(last);
    let mut run: Vec<Vector2<f64>> = Vec::new();
    for t in fan {
        match t {
            Some((a, b)) => {
                if run.is_empty() {
                    run.push(s);
                }
                run.push(a);
                run.push(b);
            }
            None => {
                if !run.is_empty() {
                    region.cuts.push(std::mem::take(&mut run));
                }
            }
        }
    }
    if !run.is_empty() {
        region.cuts.push(run);
    }
    let mean = points.iter().sum::<Vector2<f64>>() / m as f64;
    let w = (mean - s).try_normalize(0.0).unwrap_or(Vector2::x());
    region.indexed(s, w)
}

/// A cover of `∂Y` with spacing `h`: points of the circles of `K` within `h` of `K` and not
/// deep in the cuts, the corners where they meet a side cut's beam, points of each side cut's
/// beam across `K` (all of them, including those that rounding puts just beyond the beam's
/// line: `∂Y` runs along it), and points of the cut polygons' edges within `h` of `K`. Every point of
/// `∂Y ⊂ (∂K \ int T) ∪ (∂T ∩ K)` lies within `h/2` of one (a point of `∂Y` on a circle has a
/// sample within `h/2` along it, which is then within `h` of `K` and cannot have `B(x, h)`
/// inside the cuts, which miss that point of `∂Y`).
fn cover(region: &Region, h: f64) -> Vec<Vector2<f64>> {
    let mut out = Vec::new();
    let count = ((TAU * region.radius / h).ceil() as usize).max(8);
    let keep =
        |x: Vector2<f64>| !region.deep_in_cut(x, h) && !region.planes.iter().any(|p| p.hair(x, h));
    for q in &region.discs {
        for j in 0..count {
            let t = TAU * j as f64 / count as f64;
            let x = q + region.radius * Vector2::new(t.cos(), t.sin());
            // Strictly on the kept side of the side cuts: the corners below stand for the
            // samples just beyond a side cut.
            if region.near_k_sharp(x, h) && keep(x) {
                out.push(x);
            }
        }
        // Corners: the circle meets a side cut's beam.
        for p in &region.planes {
            let w = p.s - q;
            let b = w.dot(&p.u);
            let disc = b * b - (w.norm_squared() - region.radius * region.radius);
            if disc >= 0.0 {
                for t in [-b - disc.sqrt(), -b + disc.sqrt()] {
                    let x = p.s + t * p.u;
                    if t >= 0.0 && region.near_k(x, h) && keep(x) {
                        out.push(x);
                    }
                }
            }
        }
    }
    for p in &region.planes {
        let (t_in, t_out) = p.chord;
        let (a, b) = (p.s + (t_in - h).max(0.0) * p.u, p.s + (t_out + h) * p.u);
        let steps = (((b - a).norm() / h).ceil() as usize).max(1);
        for j in 0..=steps {
            let x = a + (b - a) * (j as f64 / steps as f64);
            if region.near_k(x, h) && !region.deep_in_cut(x, h) && !p.hair(x, h) {
                out.push(x);
            }
        }
    }
    for poly in &region.cuts {
        for (a, b) in edges(poly) {
            let steps = (((b - a).norm() / h).ceil() as usize).max(1);
            for j in 0..=steps {
                let x = a + (b - a) * (j as f64 / steps as f64);
                if region.near_k(x, h) && !region.planes.iter().any(|p| p.hair(x, h)) {
                    out.push(x);
                }
            }
        }
    }
    out
}

/// Where along the ray behind the mean hit [`centre`] tries the fit's centre, as fractions of
/// the way to the ray's exit from `K`, in order.
const CENTRE_FRACTIONS: [f64; 6] = [0.5, 0.25, 0.75, 0.125, 0.0625, 0.03125];

/// The centre: behind the mean hit `p̄` along `ū = (p̄ − s)/|p̄ − s|`, the first of `p̄ + t·ū`
/// (`t` at ½, ¼, ¾, ⅛, 1/16, 1/32 of the way to where that ray leaves `K`) not deep in a cut
/// and not beyond the wall prior (a radial hull holds its centre, so a centre beyond the
/// prior's disc put that place in the star: a fit of one hit 0.76 m from the wall of
/// `scale/fifty-global` reached past the wall, docs/maths.md §12.14); halfway if none is.
fn centre(
    s: Vector2<f64>,
    points: &[Vector2<f64>],
    region: &Region,
    free: &impl FreeSet,
) -> Vector2<f64> {
    let mean = points.iter().sum::<Vector2<f64>>() / points.len() as f64;
    let u = (mean - s).try_normalize(0.0).unwrap_or(Vector2::x());
    // Far root of |mean + t u − q| = radius for every disc; the smallest is the exit of K.
    let exit = region
        .discs
        .iter()
        .map(|q| {
            let w = mean - q;
            let b = w.dot(&u);
            let disc = b * b - (w.norm_squared() - region.radius * region.radius);
            -b + disc.max(0.0).sqrt()
        })
        .fold(f64::INFINITY, f64::min)
        .max(0.0);
    CENTRE_FRACTIONS
        .iter()
        .map(|f| mean + f * exit * u)
        .find(|&c| !region.deep_in_cut(c, 0.0) && !free.beyond_wall(c))
        .unwrap_or(mean + 0.5 * exit * u)
}

/// Eq. region and its certified star for one segment: hits `points` in angular order with their
/// beam directions `dirs`, seen from `s`. `free`: what the scan shows free and the wall prior
/// (eqs. freefan, wallgap; [`crate::FreeSpace::none`] for nothing): the star then contains `Y \ R`,
/// which holds the obstacle as `Y` does (`crate::free` module docs), and is cut back from what
/// was seen free where its order allows.
pub fn fit_segment(
    s: Vector2<f64>,
    points: &[Vector2<f64>],
    dirs: &[Vector2<f64>],
    sides: &[Vec<(Vector2<f64>, f64)>; 2],
    params: &FitParams,
    free: &impl FreeSet,
) -> Result<Fit, FitFailure> {
    if points.is_empty() || points.len() != dirs.len() {
        return Err(FitFailure::Shape(ShapeError::Invalid {
            field: "points",
            problem: "a segment needs at least one hit and one beam direction per hit".into(),
        }));
    }
    crate::work::count(|w| w.fits += 1);
    let limit = params.max_obstacle_depth + 2.0 * params.range_noise;
    let w = span(points);
    if w > limit {
        return Err(FitFailure::WiderThanDepth { span: w, limit });
    }
    let region = region(s, points, dirs, sides, params);
    let h = params.check_spacing;
    let mut samples = cover(&region, h);
    // A cover of ∂(Y \ R) ⊂ (∂Y \ R) ∪ (∂R ∩ Y): the samples of ∂Y whose ball of radius h/2
    // is not inside R (every point of ∂Y outside R has one within h/2), and the samples of ∂R at
    // spacing h within h of Y (crate::free module docs).
    samples.retain(|x| !free.contains_ball(*x, 0.5 * h));
    let before = samples.len();
    samples.extend(
        free.boundary_samples(h, region.discs[0], region.radius, &|x| {
            region.near_k(x, h) && !region.deep_in_cut(x, h) && !free.contains_ball(x, 0.5 * h)
        }),
    );
    let c = centre(s, points, &region, free);
    let (perceived, certification) =
        certified(params.form, c, &samples, params.check_spacing, params.order)
            .map_err(FitFailure::Shape)?;
    let room = params.keep_out + MERGE_ROOM * params.check_spacing;
    let (perceived, certification) =
        if params.form == StarForm::Hull && perceived.shape().signed_distance_bounds(s).0 < room {
            clear_of_sensor(s, points, &samples, h, room).unwrap_or((perceived, certification))
        } else {
            (perceived, certification)
        };
    Ok(Fit {
        cut_wedges: region.cuts.iter().map(|p| (p.len() - 1) / 2).sum(),
        side_cuts: region.planes.len(),
        free_samples: samples.len() - before,
        region,
        perceived,
        certification,
    })
}

/// How many of the cover's samples [`clear_of_sensor`] takes as directions for further centres.
const CLEAR_CENTRES: usize = 48;

/// The room, in cover spacings `h`, that a fit keeps between the sensor and itself beyond
/// `keep_out` when a centre allows: a merge covers each shape's boundary again with discs of
/// radius `h/2 + τ` about samples on it ([`crate::merge`]), so a fit nearer the sensor than
/// about `h` leaves it inside any merge with a neighbour (`hard/narrow-passage` under the
/// dynamic law: a fit 3.5 mm from the robot, every merged star holding it by a few mm).
const MERGE_ROOM: f64 = 2.0;

/// A radial hull of the cover `samples` (spacing `h`) that keeps the sensor `s` at least
/// `room` = `r_k + MERGE_ROOM·h` out (`r_k` = `params.keep_out`), about one of the points
/// halfway from the mean hit to 48 of the samples spread along the cover, the one of least
/// area ([`least_hull`]); `None` if none does. Any centre gives a star that holds the samples'
/// discs (eq. certify), so the choice changes the shape, not what it holds. It matters where
/// the region closed `D` behind the hits reaches, through a gap the sensor looks out of, over
/// a neighbour's unseen inside: the star about a centre behind the hits then holds the segment
/// from it across the gap, and the sensor on it (`hard/narrow-passage` rerun with a lidar,
/// docs/maths.md §12.15).
fn clear_of_sensor(
    s: Vector2<f64>,
    points: &[Vector2<f64>],
    samples: &[Vector2<f64>],
    h: f64,
    room: f64,
) -> Option<(Perceived, Certification)> {
    let mean = points.iter().sum::<Vector2<f64>>() / points.len() as f64;
    let step = (samples.len() / CLEAR_CENTRES).max(1);
    let centres: Vec<Vector2<f64>> = samples
        .iter()
        .step_by(step)
        .map(|&q| 0.5 * (mean + q))
        .collect();
    least_hull(&centres, samples, h, Some((s, room)))?.ok()
}

/// The beams beside a segment, outward from each end (at most [`SIDE_BEAMS`] per side): their
/// directions and how far each is free ([`LaserScan::free_until`]).
#[must_use]
pub fn side_beams(
    scan: &LaserScan,
    pose: &Pose,
    seg: &Segment,
    range_noise: f64,
) -> [Vec<(Vector2<f64>, f64)>; 2] {
    let n = scan.ranges.len();
    let wrap = scan.full_turn();
    let room = SIDE_BEAMS.min(n.saturating_sub(seg.beams.len()));
    let walk = |start: usize, forward: bool| -> Vec<(Vector2<f64>, f64)> {
        let mut out = Vec::new();
        let mut i = start;
        for _ in 0..room {
            i = match (forward, i) {
                (true, i) if i + 1 < n => i + 1,
                (true, _) if wrap => 0,
                (false, 0) if wrap => n - 1,
                (false, i) if i > 0 => i - 1,
                _ => break,
            };
            out.push((scan.direction(pose, i), scan.free_until(i, range_noise)));
        }
        out
    };
    [
        walk(seg.beams[0], false),
        walk(*seg.beams.last().expect("segments are not empty"), true),
    ]
}

/// Eq. region and its star for segment `seg` of `scan` taken at `pose`, leaving out what
/// `free` shows free (eqs. freefan, wallgap; build it once per scan with
/// [`crate::FreeSpace::of_scan`]).
pub fn fit_in_scan(
    scan: &LaserScan,
    pose: &Pose,
    seg: &Segment,
    params: &FitParams,
    free: &impl FreeSet,
) -> Result<Fit, FitFailure> {
    let points: Vec<Vector2<f64>> = seg
        .beams
        .iter()
        .map(|&i| hit_point(scan, pose, i).expect("segments hold hits"))
        .collect();
    let dirs: Vec<Vector2<f64>> = seg.beams.iter().map(|&i| scan.direction(pose, i)).collect();
    let sides = side_beams(scan, pose, seg, params.range_noise);
    fit_segment(pose.position(), &points, &dirs, &sides, params, free)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::free::FreeSpace;
    use crate::segment::segment;
    use crate::sim::Lidar;
    use harmonav_transform::StarShape;
    use harmonav_transform::random::{self, Kind, Rng};

    /// The direct test the index replaces: every polygon, every edge.
    fn deep_in_cut_direct(region: &Region, x: Vector2<f64>, h: f64) -> bool {
        region.cuts.iter().any(|poly| {
            let on_plane = |a: Vector2<f64>, b: Vector2<f64>| {
                region.planes.iter().find(|p| p.on_line(a) && p.on_line(b))
            };
            let mut beyond = false;
            let mut near = f64::INFINITY;
            for (a, b) in edges(poly) {
                match on_plane(a, b) {
                    Some(p) => beyond |= p.m.dot(&(x - p.s)) < -h,
                    None => near = near.min(segment_distance(a, b, x)),
                }
            }
            (beyond || inside(poly, x)) && near > h
        })
    }

    /// The direct loop over all pairs.
    fn span_direct(points: &[Vector2<f64>]) -> f64 {
        let mut best = 0.0f64;
        for (i, a) in points.iter().enumerate() {
            for b in &points[i + 1..] {
                best = best.max((a - b).norm());
            }
        }
        best
    }

    /// The regions of every segment of a scan of `obstacles` from `pose`, with the scan's free
    /// set.
    fn regions(
        lidar: &Lidar,
        pose: &Pose,
        obstacles: &[StarShape],
        params: &FitParams,
        rng: &mut Rng,
    ) -> Vec<(Region, Vec<Vector2<f64>>, FreeSpace)> {
        let scan = lidar.scan(pose, obstacles, None, rng);
        let n = scan.ranges.len();
        let usable: Vec<bool> = (0..n)
            .map(|i| hit_point(&scan, pose, i).is_some())
            .collect();
        let free = FreeSpace::of_scan(&scan, pose, params.range_noise, params.rho_min);
        segment(&scan, pose, &usable, 0.1)
            .iter()
            .map(|seg| {
                let points: Vec<Vector2<f64>> = seg
                    .beams
                    .iter()
                    .map(|&i| hit_point(&scan, pose, i).expect("hits"))
                    .collect();
                let dirs: Vec<Vector2<f64>> =
                    seg.beams.iter().map(|&i| scan.direction(pose, i)).collect();
                let sides = side_beams(&scan, pose, seg, params.range_noise);
                let r = region(pose.position(), &points, &dirs, &sides, params);
                (r, points, free.clone())
            })
            .collect()
    }

    /// Points where `deep_in_cut` is queried or decided: the cover and the free set's
    /// boundary samples (what the fit asks), random points about `K`, the cut vertices and
    /// points on the cut edges moved by nothing, by rounding and by about `h`, points on the
    /// side cuts' lines, and the sensor and points near it.
    fn probes(
        region: &Region,
        free: &FreeSpace,
        s: Vector2<f64>,
        h: f64,
        rng: &mut Rng,
    ) -> Vec<Vector2<f64>> {
        let mut out = cover(region, h);
        out.extend(free.boundary_samples(h, region.discs[0], region.radius, &|_| true));
        let c = region.discs[0];
        for _ in 0..2000 {
            let v = Vector2::new(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0));
            out.push(c + 1.2 * region.radius * v);
        }
        for poly in &region.cuts {
            // At most about 400 edges of a long polygon (the loops are slow).
            let every = poly.len().div_ceil(400);
            for (a, b) in edges(poly).step_by(every) {
                for t in [0.0, 0.5, rng.uniform(0.0, 1.0)] {
                    let x = a + t * (b - a);
                    let n = Vector2::new(b.y - a.y, a.x - b.x).try_normalize(0.0);
                    let n = n.unwrap_or(Vector2::x());
                    out.push(x);
                    for d in [1e-15, 1e-12, h, h * (1.0 + 1e-12), 0.5 * h, 2.0 * h] {
                        out.push(x + d * n);
                        out.push(x - d * n);
                    }
                }
            }
        }
        for p in &region.planes {
            for _ in 0..50 {
                let t = rng.uniform(0.0, p.chord.1 + h);
                let x = p.s + t * p.u;
                out.extend([x, x + h * p.m, x - h * p.m, x - 2.0 * h * p.m]);
            }
        }
        out.push(s);
        for d in [1e-15, 1e-9, 1e-6, 1e-3] {
            for k in 0..16 {
                let a = TAU * f64::from(k) / 16.0;
                out.push(s + d * Vector2::new(a.cos(), a.sin()));
            }
        }
        out
    }

    /// Checks the index against the direct loops on the probes of every region of a scan;
    /// returns (regions, cut polygons, largest polygon count, side cuts, deep decisions).
    fn check(
        lidar: &Lidar,
        pose: &Pose,
        obstacles: &[StarShape],
        params: &FitParams,
        rng: &mut Rng,
    ) -> (usize, usize, usize, usize, usize) {
        let (mut count, mut polys, mut most, mut planes, mut deep) = (0, 0, 0, 0, 0);
        for (region, points, free) in regions(lidar, pose, obstacles, params, rng) {
            count += 1;
            polys += region.cuts.len();
            most = most.max(region.cuts.len());
            planes += region.planes.len();
            for h in [0.0, params.check_spacing, 0.05] {
                for x in probes(&region, &free, pose.position(), h.max(1e-3), rng) {
                    let want = deep_in_cut_direct(&region, x, h);
                    assert_eq!(region.deep_in_cut(x, h), want, "x {x:?}, h {h}");
                    deep += usize::from(want);
                }
            }
            assert_eq!(span(&points), span_direct(&points));
        }
        (count, polys, most, planes, deep)
    }

    fn params(eps: f64, depth: f64, rho_min: f64) -> FitParams {
        FitParams {
            range_noise: eps,
            max_obstacle_depth: depth,
            rho_min,
            order: 6,
            form: StarForm::Fourier,
            check_spacing: 0.01,
            keep_out: 0.0,
        }
    }

    /// A disc straight behind the sensor of a 360° scan (its segment wraps at `±π`), seen
    /// alone (side cuts and end cuts on both sides), with and without noise, sparse and dense.
    #[test]
    fn index_decides_as_the_loops_across_the_wrap() {
        let mut rng = Rng::new(1);
        let disc = StarShape::circle(Vector2::new(-2.0, 0.0), 0.5).expect("a disc");
        let pose = Pose::new(0.0, 0.0, 0.0);
        let (mut planes, mut deep) = (0, 0);
        for (beams, noise) in [(360, 0.0), (1000, 0.01), (3000, 0.0), (3000, 0.02)] {
            let lidar = Lidar {
                noise,
                ..Lidar::full_turn(beams, 5.0)
            };
            let (count, _, most, p, d) = check(
                &lidar,
                &pose,
                std::slice::from_ref(&disc),
                &params(0.02, 1.5, 0.05),
                &mut rng,
            );
            assert_eq!(count, 1, "one segment, across the wrap");
            assert!(most >= 1);
            (planes, deep) = (planes + p, deep + d);
        }
        assert!(planes >= 4, "side cuts: {planes}");
        assert!(deep > 1000, "deep decisions: {deep}");
    }

    /// Random shapes and poses, noisy dense scans with small `ρ_min` (many short runs of cut
    /// wedges: many polygons), occlusions, and scans of a limited aperture.
    #[test]
    fn index_decides_as_the_loops_on_random_scans() {
        let mut rng = Rng::new(2);
        let (mut most, mut deep) = (0, 0);
        for trial in 0..24 {
            let kind = [Kind::Circle, Kind::Ellipse, Kind::Star][trial % 3];
            let obstacles: Vec<StarShape> = (0..3)
                .map(|_| {
                    let (c, size) = (rng.point(2.5), rng.uniform(0.15, 0.6));
                    random::shape(&mut rng, kind, c, size)
                })
                .collect();
            let Some(pose) = (0..100)
                .map(|_| rng.point(3.0))
                .find(|p| obstacles.iter().all(|o| o.signed_distance(*p) > 0.2))
                .map(|p| Pose::new(p.x, p.y, rng.uniform(-3.0, 3.0)))
            else {
                continue;
            };
            let lidar = Lidar {
                noise: rng.uniform(0.0, 0.02),
                dropout: 0.02,
                aperture: if trial % 4 == 3 { 4.0 } else { TAU },
                ..Lidar::full_turn([360, 1080, 2000][trial % 3], 8.0)
            };
            let rho = [0.05, 0.1, 0.3][(trial / 3) % 3];
            let (_, _, m, _, d) =
                check(&lidar, &pose, &obstacles, &params(0.02, 1.5, rho), &mut rng);
            most = most.max(m);
            deep += d;
        }
        assert!(most >= 2, "a region with several cut polygons: {most}");
        assert!(deep > 1000, "deep decisions: {deep}");
    }

    /// A dense noisy scan: neighbouring hits 1 mm apart whose ranges differ by up to 4 cm
    /// leave many wedges uncut at grazing incidence, so the cut is many short polygons.
    #[test]
    fn index_decides_as_the_loops_with_many_polygons() {
        let mut rng = Rng::new(4);
        let disc = StarShape::circle(Vector2::new(1.2, 1.6), 0.5).expect("a disc");
        let lidar = Lidar {
            noise: 0.02,
            ..Lidar::full_turn(12_000, 5.0)
        };
        let pose = Pose::new(0.0, 0.0, 0.3);
        let (count, _, most, _, deep) =
            check(&lidar, &pose, &[disc], &params(0.02, 1.5, 0.05), &mut rng);
        assert_eq!(count, 1);
        assert!(most >= 50, "many cut polygons: {most}");
        assert!(deep > 1000, "deep decisions: {deep}");
    }

    /// The span over a tree is the direct loop's, to the bit.
    #[test]
    fn span_is_the_loop_over_pairs() {
        let mut rng = Rng::new(3);
        for m in [0, 1, 2, 3, 9, 50, 400] {
            for _ in 0..5 {
                let arc = rng.uniform(0.1, 6.0);
                let points: Vec<Vector2<f64>> = (0..m)
                    .map(|i| {
                        let a = arc * i as f64 / m.max(1) as f64;
                        Vector2::new(a.cos(), a.sin()) * rng.uniform(0.9, 1.1)
                    })
                    .collect();
                assert_eq!(span(&points), span_direct(&points));
                let cloud: Vec<Vector2<f64>> = (0..m).map(|_| rng.point(3.0)).collect();
                assert_eq!(span(&cloud), span_direct(&cloud));
            }
        }
    }
}
