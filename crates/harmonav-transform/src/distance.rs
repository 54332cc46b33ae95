//! Distance queries on shapes, exact to [`DISTANCE_TOLERANCE`]: parry2d-f64 point and
//! shape-distance queries on the certified outlines, widened by their chord bounds `δ` (argument
//! in [`crate::outline`]: the curve and its outline are less than `δ` apart everywhere, so every
//! polyline distance is within `δ` of the true one). Circles use closed forms. Signs come from
//! the exact containment test [`StarShape::contains`].

use nalgebra::Vector2;
use parry2d_f64::math::{Pose, Vector as PVector};
use parry2d_f64::query::{self, PointQuery, PointQueryWithLocation};

#[cfg(doc)]
use crate::outline::DISTANCE_TOLERANCE;
use crate::shape::{StarShape, golden_min};

impl StarShape {
    /// The certified width of [`Self::signed_distance_bounds`], `τ = 2δ ≤
    /// DISTANCE_TOLERANCE·max R` (`δ` the outline's chord bound, eq. chord of
    /// [`crate::outline`]); 0 for a circle, whose distance is a closed form.
    #[must_use]
    pub fn distance_tolerance(&self) -> f64 {
        match self.circle_radius() {
            Some(_) => 0.0,
            None => 2.0 * self.certified().delta,
        }
    }

    /// Certified bounds `(lo, hi)` on the true signed distance `d(x)` from `x` to the boundary
    /// (negative inside): `lo ≤ d(x) ≤ hi`, `hi − lo ≤` [`Self::distance_tolerance`] plus a
    /// rounding allowance `ρ = 64ε·(|x|∞ + |c|∞ + max R)` on each side.
    ///
    /// ```text
    /// d_P = parry's distance from x to the certified outline P     (|d(x, ∂S) − d_P| ≤ δ)
    /// outside: lo = max(d_P − δ, 0) − ρ,       hi = d_P + δ + ρ
    /// inside:  lo = −(d_P + δ) − ρ,            hi = −max(d_P − δ, 0) + ρ
    /// ```
    ///
    /// One bounding-volume-tree point query and one radius evaluation (about 0.3 µs for an
    /// offset shape); circles `|x − c| − r` exactly. On the boundary both bounds are within
    /// `δ + ρ` of 0. A point farther than `L = 1e8·max R` from the centre is answered at its
    /// proxy `x' = c + L·(x − c)/|x − c|` (parry's squared distances would overflow near
    /// 1e154): with `R = |x − c|`, `d(x) − R` does not increase with `R` and stays above
    /// `−h(u)` (`h` the support function), while `d(x') − L ≤ −h(u) + e`,
    /// `e = (max R)²/(2(L − max R))`, so `d(x) ∈ [d(x') + R − L − e, d(x') + R − L]`. A NaN
    /// coordinate gives `(NaN, NaN)`, an infinite one `(∞, ∞)`.
    #[must_use]
    pub fn signed_distance_bounds(&self, x: Vector2<f64>) -> (f64, f64) {
        if let Some(r) = self.circle_radius() {
            let d = length(x - self.centre()) - r;
            let pad = self.rounding(x);
            return (d - pad, d + pad);
        }
        if let Some(d) = non_finite(x) {
            return (d, d);
        }
        if let Some(far) = self.far(x) {
            let (lo, hi) = self.signed_distance_bounds(far.proxy);
            return (lo + far.extra - far.slack, hi + far.extra + far.slack);
        }
        let pad = self.rounding(x);
        let delta = self.certified().delta;
        let d = self
            .certified()
            .polyline
            .distance_to_local_point(PVector::new(x.x, x.y), false);
        let (near, far) = ((d - delta).max(0.0), d + delta);
        if self.contains(x) {
            (-far - pad, -near + pad)
        } else {
            (near - pad, far + pad)
        }
    }

    /// Whether `x` is certified to lie within `eps` of the shape, inside included: `true` only
    /// when the true signed distance `d(x) ≤ eps`, and whenever
    /// [`Self::signed_distance_bounds`]`(x).1 ≤ eps`. Most points are decided on the ray from
    /// the centre through `x`, without the outline's point query:
    ///
    /// ```text
    /// ρ = |x − c|,  u = (x − c)/ρ,  R = R(u) (the radial function)
    /// ρ > max R + eps + pad       →  false   (d(x) ≥ ρ − max R: ∂S lies within max R of c)
    /// ρ ≤ min R  or  ρ + pad ≤ R  →  true    (x in the region, as StarShape::contains)
    /// ρ − R ≤ eps − pad           →  true    (c + R·u is a boundary point ρ − R from x)
    /// otherwise                   →  hi(x) ≤ eps   (the certified bounds' point query)
    /// ```
    ///
    /// `pad` is the rounding allowance of [`Self::signed_distance_bounds`]. The radial tests
    /// are the hot path of a scan whose hits lie on perceived shapes (each hit inside or a few
    /// centimetres outside along its ray); only a hit off to the side of its ray's boundary
    /// point pays for the point query. A non-finite coordinate gives `false`; a negative `eps`
    /// (at least `|eps|` deep inside) skips the radial tests, a NaN `eps` gives `false`.
    #[must_use]
    pub fn within(&self, x: Vector2<f64>, eps: f64) -> bool {
        if non_finite(x).is_some() || eps.is_nan() {
            return false;
        }
        if eps < 0.0 {
            return self.signed_distance_bounds(x).1 <= eps;
        }
        let pad = self.rounding(x);
        let v = x - self.centre();
        let rho = length(v);
        let (r_min, r_max) = self.radius_bounds();
        if rho > r_max + eps + pad {
            return false;
        }
        if rho <= r_min {
            return true;
        }
        let r = self.radius_along(v / rho).0;
        if rho + pad <= r || rho - r <= eps - pad {
            return true;
        }
        self.signed_distance_bounds(x).1 <= eps
    }

    /// Signed distance to the boundary: negative inside, 0 on it, within
    /// [`Self::signed_distance_bounds`] always, and in practice exact to ~1e-12 m.
    ///
    /// Circles: `|x − c| − r`. Other shapes: parry projects `x` on the certified outline;
    /// a golden-section search for the nearest point of the exact curve `p(t)` over the
    /// projection's segment and its neighbours refines it, and the result is clamped into the
    /// certified bracket `[d_P − δ, d_P + δ]` (the refined point lies on the curve, so it can
    /// only overestimate; when the nearest point is on another stretch of boundary within the
    /// tolerance, the bracket still holds). 2–5 µs. The sign is the exact
    /// [`Self::contains`]. A NaN coordinate gives NaN, an infinite one `∞`.
    #[must_use]
    pub fn signed_distance(&self, x: Vector2<f64>) -> f64 {
        if let Some(r) = self.circle_radius() {
            return length(x - self.centre()) - r;
        }
        if let Some(d) = non_finite(x) {
            return d;
        }
        if let Some(far) = self.far(x) {
            return self.signed_distance(far.proxy) + far.extra;
        }
        let outline = self.certified();
        let (proj, (segment, _)) = outline
            .polyline
            .project_local_point_and_get_location(PVector::new(x.x, x.y), false);
        let coarse = (Vector2::new(proj.point.x, proj.point.y) - x).norm();
        let j = segment as isize;
        let (lo, hi) = outline.window(j - 1, j + 2);
        let t = golden_min(|t| (self.curve_point(t) - x).norm_squared(), lo, hi);
        let fine = (self.curve_point(t) - x).norm();
        let d = fine.clamp((coarse - outline.delta).max(0.0), coarse + outline.delta);
        if self.contains(x) { -d } else { d }
    }

    /// [`Self::signed_distance`] without the refinement: parry's distance to the certified
    /// outline with the exact sign, within the chord bound `δ` (half of
    /// [`Self::distance_tolerance`]) of the truth. For band widths and sampling.
    #[must_use]
    pub fn coarse_signed_distance(&self, x: Vector2<f64>) -> f64 {
        if let Some(r) = self.circle_radius() {
            return length(x - self.centre()) - r;
        }
        if let Some(d) = non_finite(x) {
            return d;
        }
        if let Some(far) = self.far(x) {
            return self.coarse_signed_distance(far.proxy) + far.extra;
        }
        let d = self
            .certified()
            .polyline
            .distance_to_local_point(PVector::new(x.x, x.y), false);
        if self.contains(x) { -d } else { d }
    }

    /// The gap `D` between two shapes (the smallest distance between their boundaries when
    /// they are apart): positive only if they are certified apart, and then within
    /// `[D − τ_A − τ_B, 1.1·D]` (τ the [`Self::distance_tolerance`]s, plus rounding); in
    /// practice `D` to ~1e-12. Not positive when they overlap or touch or come within the
    /// tolerance of each other; negative when they overlap by more.
    ///
    /// The certified lower bound `lo`:
    ///
    /// ```text
    /// two circles:        |c_A − c_B| − r_A − r_B                                (exact)
    /// circle and shape S:  lo_S(c) − r   (lo_S of [`Self::signed_distance_bounds`])
    /// otherwise:           d_P − δ_A − δ_B,   d_P = parry's distance between the outlines
    /// ```
    ///
    /// `|D − d_P| ≤ δ_A + δ_B` because each boundary is within its `δ` of its outline. When
    /// `d_P` exceeds `δ_A + δ_B` the boundaries are disjoint, and the shapes are apart unless
    /// one holds a boundary point of the other (tested exactly with [`Self::contains`]). Once
    /// `lo > 0`, the gap is refined on the exact curves (a golden-section search along `A`'s
    /// boundary near parry's closest segment for [`Self::signed_distance`] to `B`); the refined
    /// value is a distance between boundary points, so at least `D`, and it is returned when
    /// it is at most `1.1·lo`, else `lo` (so the value never exceeds `1.1·D`: the band widths
    /// `0.45·d` of [`crate::NavTransform`] stay disjoint). For overlapping shapes the value is
    /// the deepest outline vertex of one inside the other, less the tolerance: an estimate of
    /// the overlap depth.
    #[must_use]
    pub fn distance_to(&self, other: &StarShape) -> f64 {
        match (self.circle_radius(), other.circle_radius()) {
            (Some(ra), Some(rb)) => (self.centre() - other.centre()).norm() - ra - rb,
            (Some(r), None) => disc_gap(self.centre(), r, other),
            (None, Some(r)) => disc_gap(other.centre(), r, self),
            (None, None) => {
                let slack = self.certified().delta
                    + other.certified().delta
                    + self.rounding(other.centre())
                    + other.rounding(self.centre());
                let (d, near, _) = outline_distance(self, other);
                if d > slack {
                    let held = self.contains(other.certified().vertex(0))
                        || other.contains(self.certified().vertex(0));
                    if !held {
                        let refined = refine_along(self, near, |p| other.signed_distance(p));
                        return settle(d - slack, refined);
                    }
                } else if d > 0.0 {
                    return d - slack;
                }
                deepest_vertex(self, other, 1.0)
                    .min(deepest_vertex(other, self, 1.0))
                    .min(0.0)
                    - slack
            }
        }
    }

    /// The clearance `D` of `self` inside the region `outer` (the smallest distance from the
    /// boundary of `self` to that of `outer`): positive only if `self` is certified to lie
    /// strictly inside `outer`, and then within `[D − τ_self − τ_outer, 1.1·D]` (plus
    /// rounding; in practice `D` to ~1e-12). Not positive when `self` crosses, touches or
    /// leaves `outer`.
    ///
    /// The certified lower bound, refined and returned as in [`Self::distance_to`]:
    ///
    /// ```text
    /// outer a circle (c, r): r − max over ∂self of |p − c|
    ///                        (self a circle: r − |c_self − c| − r_self; otherwise the
    ///                         largest outline vertex distance + δ_self: along a chord |p − c|
    ///                         is convex, so its maximum is at a vertex)
    /// self a circle (c, r):  −hi_outer(c) − r   (hi of [`Self::signed_distance_bounds`])
    /// otherwise:             d_P − δ_self − δ_outer when the outlines are more than that
    ///                        apart and a boundary point of self is inside outer
    /// ```
    ///
    /// When the clearance is not positive the value estimates the depth of the deepest outline
    /// vertex of `self` beyond `outer`, less the tolerance.
    #[must_use]
    pub fn clearance_inside(&self, outer: &StarShape) -> f64 {
        if let Some(r) = outer.circle_radius() {
            let c = outer.centre();
            let Some(rs) = self.circle_radius() else {
                let outline = self.certified();
                let (far, i) = (0..outline.len())
                    .map(|i| ((outline.vertex(i) - c).norm(), i))
                    .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a });
                let lo = r - far - outline.delta - self.rounding(c);
                // The farthest curve point near the farthest vertex.
                let refined = r + refine_along(self, i as u32, |p| -(p - c).norm());
                return settle(lo, refined);
            };
            return r - (self.centre() - c).norm() - rs;
        }
        if let Some(r) = self.circle_radius() {
            let lo = -outer.signed_distance_bounds(self.centre()).1 - r;
            return settle(lo, -outer.signed_distance(self.centre()) - r);
        }
        let slack = self.certified().delta
            + outer.certified().delta
            + self.rounding(outer.centre())
            + outer.rounding(self.centre());
        let (d, _, near) = outline_distance(outer, self);
        if d > slack && outer.contains(self.certified().vertex(0)) {
            let refined = refine_along(self, near, |p| -outer.signed_distance(p));
            return settle(d - slack, refined);
        }
        deepest_vertex(self, outer, -1.0).min(d).min(0.0) - slack
    }

    /// The rounding allowance `64ε·(|x|∞ + |c|∞ + max R)` of a query at `x`.
    fn rounding(&self, x: Vector2<f64>) -> f64 {
        64.0 * f64::EPSILON * (x.amax() + self.centre().amax() + self.radius_bounds().1)
    }

    /// The proxy of a point farther than `L = 1e8·max R` from the centre (see
    /// [`Self::signed_distance_bounds`]), `None` for nearer points.
    fn far(&self, x: Vector2<f64>) -> Option<Far> {
        let r_max = self.radius_bounds().1;
        let reach = 1e8 * r_max;
        let v = x - self.centre();
        let dist = length(v);
        (dist > reach).then(|| Far {
            proxy: self.centre() + v * (reach / dist),
            extra: dist - reach,
            slack: r_max * r_max / (2.0 * (reach - r_max)) + 4.0 * f64::EPSILON * dist,
        })
    }
}

/// A far point's proxy at `L` on the same ray, the extra distance `R − L`, and the slack `e`
/// (plus the rounding of `R − L`).
struct Far {
    proxy: Vector2<f64>,
    extra: f64,
    slack: f64,
}

/// `|v|` without overflow.
fn length(v: Vector2<f64>) -> f64 {
    v.x.hypot(v.y)
}

/// The answer for a point with a non-finite coordinate: NaN for a NaN, `∞` for an infinity
/// (every shape is bounded); `None` for a finite point.
fn non_finite(x: Vector2<f64>) -> Option<f64> {
    if x.x.is_nan() || x.y.is_nan() {
        Some(f64::NAN)
    } else if x.x.is_infinite() || x.y.is_infinite() {
        Some(f64::INFINITY)
    } else {
        None
    }
}

/// The gap between the disc `(c, r)` and `shape`, as in [`StarShape::distance_to`].
fn disc_gap(c: Vector2<f64>, r: f64, shape: &StarShape) -> f64 {
    let lo = shape.signed_distance_bounds(c).0 - r;
    if lo > 0.0 {
        settle(lo, shape.signed_distance(c) - r)
    } else {
        lo
    }
}

/// The refined value of a gap with certified lower bound `lo`: `refined` (at least the true
/// gap) when it is at most `1.1·lo`, else `lo`; `lo` itself when it is not positive.
fn settle(lo: f64, refined: f64) -> f64 {
    if lo > 0.0 && refined <= 1.1 * lo {
        refined.max(lo)
    } else {
        lo
    }
}

/// The smallest `f(p(t))` for the curve parameter `t` over outline segment `segment` of
/// `shape` and its neighbours (golden-section search).
fn refine_along(shape: &StarShape, segment: u32, f: impl Fn(Vector2<f64>) -> f64) -> f64 {
    let j = segment as isize;
    let (lo, hi) = shape.certified().window(j - 1, j + 2);
    let t = golden_min(|t| f(shape.curve_point(t)), lo, hi);
    f(shape.curve_point(t))
}

/// parry's distance between the certified outlines of `a` and `b` (0 when they cross), with
/// the segments of each that realise it. The bounding-volume tree of `a` is walked against
/// the whole of `b`.
fn outline_distance(a: &StarShape, b: &StarShape) -> (f64, u32, u32) {
    query::distance(
        &Pose::IDENTITY,
        &a.certified().polyline,
        &Pose::IDENTITY,
        &b.certified().polyline,
    )
    .map_or((0.0, 0, 0), |d| (d.distance, d.subshape1, d.subshape2))
}

/// The smallest `sign·coarse_signed_distance` to `other` over the outline vertices of `shape`
/// that lie in `other`'s bounding disc (`+∞` if none): with `sign = 1` the depth of the
/// deepest vertex inside `other`, with `sign = −1` the clearance of the vertex nearest to
/// leaving it.
fn deepest_vertex(shape: &StarShape, other: &StarShape, sign: f64) -> f64 {
    let outline = shape.certified();
    let (c, reach) = (other.centre(), other.radius_bounds().1);
    (0..outline.len())
        .map(|i| outline.vertex(i))
        .filter(|v| sign < 0.0 || (v - c).norm() <= reach)
        .map(|v| sign * other.coarse_signed_distance(v))
        .fold(f64::INFINITY, f64::min)
}
