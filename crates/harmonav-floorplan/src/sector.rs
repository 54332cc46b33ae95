//! [`Sector`]: an annular sector of the point world and the exact least and greatest distance
//! of a point to it, the last step of the certified level `c_δ` (docs/maths.md §13.5).

use nalgebra::Vector2;
use parry2d_f64::math::Vector as PVector;
use parry2d_f64::query::PointQuery;
use parry2d_f64::shape::Segment;

/// An annular sector `{r·(cos t, sin t) : r ∈ [r_lo, r_hi], |t − angle| ≤ half_width}` of the
/// point world (`half_width ≥ π`: the whole annulus).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sector {
    /// `(r_lo, r_hi)`, `0 ≤ r_lo ≤ r_hi`.
    pub radii: (f64, f64),
    /// The direction of its axis, radians.
    pub angle: f64,
    /// Its half opening, radians.
    pub half_width: f64,
}

/// Why [`crate::FloorTransform::enclose`] gave no sector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unenclosed {
    /// The disc may meet a sensed obstacle's band, where `B` is not the identity.
    Band,
    /// The bound of `M_a(H)` on the disc reaches the unit circle (or the disc meets an
    /// element): `S` has no finite bound there.
    Disk,
}

impl Sector {
    fn full(&self) -> bool {
        self.half_width >= std::f64::consts::PI
    }

    /// The signed angle from the axis to `p`'s direction, in `(−π, π]`.
    fn offset(&self, p: Vector2<f64>) -> f64 {
        let d = p.y.atan2(p.x) - self.angle;
        d.sin().atan2(d.cos())
    }

    /// The corner `r·(cos, sin)(angle + side·half_width)`.
    fn corner(&self, r: f64, side: f64) -> Vector2<f64> {
        let t = self.angle + side * self.half_width;
        Vector2::new(r * t.cos(), r * t.sin())
    }

    /// `min_{y ∈ A} |y − p|`: along `p`'s own ray when its direction lies in the opening
    /// (`|p − y|² = |p|² + s² − 2|p|s cos β ≥ (|p| − s)²`), else on one of the two straight
    /// edges (on an arc the nearest point is the arc's end).
    #[must_use]
    pub fn min_distance(&self, p: Vector2<f64>) -> f64 {
        let (lo, hi) = self.radii;
        let rp = p.norm();
        if self.full() || self.offset(p).abs() <= self.half_width {
            return (rp - rp.clamp(lo, hi)).abs();
        }
        let point = |v: Vector2<f64>| PVector::new(v.x, v.y);
        [-1.0, 1.0]
            .into_iter()
            .map(|side| {
                Segment::new(point(self.corner(lo, side)), point(self.corner(hi, side)))
                    .distance_to_local_point(point(p), true)
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// `max_{y ∈ A} |y − p|`: `|y − p|` is convex, so its maximum over `A` is on the two arcs
    /// (straight edges take theirs at the corners); on an arc of radius `R` it is `|p| + R` if
    /// the direction of `−p` lies in the opening, else at an end.
    #[must_use]
    pub fn max_distance(&self, p: Vector2<f64>) -> f64 {
        let rp = p.norm();
        let (lo, hi) = self.radii;
        if self.full() || (std::f64::consts::PI - self.offset(p).abs()) <= self.half_width {
            return rp + hi;
        }
        [lo, hi]
            .into_iter()
            .flat_map(|r| [self.corner(r, -1.0), self.corner(r, 1.0)])
            .map(|c| (c - p).norm())
            .fold(0.0, f64::max)
    }
}
