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

use std::f64::consts::TAU;

use harmonav_transform::ShapeError;
use nalgebra::Vector2;

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

    /// Whether `B(x, h)` lies in the removed set `int(cuts) ∪ {beyond a side cut}`: `x` inside
    /// a cut polygon (or more than `h` beyond a side cut whose beam carries one of its edges)
    /// and more than `h` from the polygon's other edges. (A ball that meets no other edge can leave the
    /// polygon only across the side cut's beam, into the removed half-plane.)
    fn deep_in_cut(&self, x: Vector2<f64>, h: f64) -> bool {
        self.cuts.iter().any(|poly| {
            let on_plane = |a: Vector2<f64>, b: Vector2<f64>| {
                self.planes.iter().find(|p| p.on_line(a) && p.on_line(b))
            };
            let mut beyond = false;
            let mut near = f64::INFINITY;
            for (a, b) in edges(poly) {
                match on_plane(a, b) {
                    // Beyond by more than `h`: a point on the beam's line (where `∂Y`
                    // runs along a side cut) or just beyond it by rounding has a ball that
                    // reaches back into `Y`.
                    Some(p) => beyond |= p.m.dot(&(x - p.s)) < -h,
                    None => near = near.min(segment_distance(a, b, x)),
                }
            }
            (beyond || inside(poly, x)) && near > h
        })
    }
}

fn edges(poly: &[Vector2<f64>]) -> impl Iterator<Item = (Vector2<f64>, Vector2<f64>)> + '_ {
    (0..poly.len()).map(move |k| (poly[k], poly[(k + 1) % poly.len()]))
}

/// Crossing-number point-in-polygon.
fn inside(poly: &[Vector2<f64>], x: Vector2<f64>) -> bool {
    let mut odd = false;
    for (a, b) in edges(poly) {
        if (a.y > x.y) != (b.y > x.y) {
            let t = (x.y - a.y) / (b.y - a.y);
            if x.x < a.x + t * (b.x - a.x) {
                odd = !odd;
            }
        }
    }
    odd
}

/// The largest distance between two of the points (`O(m²)`).
#[must_use]
pub fn span(points: &[Vector2<f64>]) -> f64 {
    let mut best = 0.0f64;
    for (i, a) in points.iter().enumerate() {
        for b in &points[i + 1..] {
            best = best.max((a - b).norm());
        }
    }
    best
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
    region
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
