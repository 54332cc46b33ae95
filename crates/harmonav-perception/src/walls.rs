//! Known walls as polygon rings (a floor plan's, docs/maths.md §12.17): what explains a hit,
//! where the sensor may stand, and what a fit may leave out, when the workspace is not a star.
//!
//! The walls bound the free space `W` (inside the outer ring, outside every hole). With
//! `d(x)` the distance to the nearest wall segment and `sd(x) = ±d(x)` (positive in `W`):
//!
//! - a hit `p` with `d(p) ≤ ε_x` lies on a wall (eq. explained), and so does one with
//!   `d(p) < g_w − ε` under the wall prior (eq. wallgap: no unknown obstacle comes nearer the
//!   walls than `g_w`);
//! - an obstacle lies in `W_{g_w} = {sd ≥ g_w}` (in `W` itself for `g_w = 0`), so a fit may leave
//!   out the open set `{sd < g_w}`: the walls' outside and, under the prior, the band along
//!   them ([`crate::WallPrior::Level`]).
//!
//! Distances and rays are parry's queries on the segments ([`Polyline`]); the side is parry's
//! winding-number test on each ring.

use std::fmt;

use nalgebra::Vector2;
use parry2d_f64::math::Vector as PVector;
use parry2d_f64::query::{PointQuery, Ray, RayCast};
use parry2d_f64::shape::Polyline;
use parry2d_f64::utils::point_in_poly2d;

/// The walls of a floor plan: an outer ring and holes, each at least three finite vertices
/// (either orientation; the free space is inside the outer ring and outside the holes).
#[derive(Clone)]
pub struct Walls {
    /// The rings as parry points, the outer one first, for the winding test.
    rings: Vec<Vec<PVector>>,
    /// Every edge of every ring, for parry's distance and ray queries.
    segments: Polyline,
}

impl fmt::Debug for Walls {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Walls")
            .field("rings", &self.rings.len())
            .field("vertices", &self.rings.iter().map(Vec::len).sum::<usize>())
            .finish()
    }
}

/// Why walls could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WallsError {
    /// Ring `ring` (0 the outer one) has fewer than three vertices.
    TooFewVertices {
        /// The ring.
        ring: usize,
    },
    /// A vertex of ring `ring` is not finite.
    NotFinite {
        /// The ring.
        ring: usize,
    },
}

impl fmt::Display for WallsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooFewVertices { ring } => {
                write!(f, "wall ring {ring} has fewer than three vertices")
            }
            Self::NotFinite { ring } => write!(f, "wall ring {ring} has a non-finite vertex"),
        }
    }
}

impl std::error::Error for WallsError {}

impl Walls {
    /// The walls of the free space inside `outer` and outside every ring of `holes`.
    ///
    /// # Errors
    /// [`WallsError`] for a ring of fewer than three vertices or a non-finite vertex.
    pub fn new(
        outer: Vec<Vector2<f64>>,
        holes: Vec<Vec<Vector2<f64>>>,
    ) -> Result<Self, WallsError> {
        let given: Vec<Vec<Vector2<f64>>> = std::iter::once(outer).chain(holes).collect();
        for (ring, r) in given.iter().enumerate() {
            if r.len() < 3 {
                return Err(WallsError::TooFewVertices { ring });
            }
            if !r.iter().all(|p| p.x.is_finite() && p.y.is_finite()) {
                return Err(WallsError::NotFinite { ring });
            }
        }
        let rings: Vec<Vec<PVector>> = given
            .iter()
            .map(|r| r.iter().map(|p| PVector::new(p.x, p.y)).collect())
            .collect();
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        for ring in &rings {
            let base = vertices.len() as u32;
            let n = ring.len() as u32;
            vertices.extend(ring.iter().copied());
            indices.extend((0..n).map(|i| [base + i, base + (i + 1) % n]));
        }
        Ok(Self {
            rings,
            segments: Polyline::new(vertices, Some(indices)),
        })
    }

    /// `d(x)`, m: the distance to the nearest wall segment (parry), exact to rounding.
    #[must_use]
    pub fn distance(&self, x: Vector2<f64>) -> f64 {
        self.segments
            .distance_to_local_point(PVector::new(x.x, x.y), false)
    }

    /// Whether `x` lies in the free space: inside the outer ring and outside every hole
    /// (winding numbers). Points on a wall may go either way.
    #[must_use]
    pub fn contains(&self, x: Vector2<f64>) -> bool {
        let p = PVector::new(x.x, x.y);
        point_in_poly2d(p, &self.rings[0]) && !self.rings[1..].iter().any(|h| point_in_poly2d(p, h))
    }

    /// `sd(x)`, m: [`Walls::distance`], positive in the free space and negative outside it;
    /// 1-Lipschitz.
    #[must_use]
    pub fn signed_distance(&self, x: Vector2<f64>) -> f64 {
        let d = self.distance(x);
        if self.contains(x) { d } else { -d }
    }

    /// The first wall along the ray `s + t·u` (`u` a unit vector), `t ∈ [0, max]`: the
    /// simulated lidar's truth.
    #[must_use]
    pub fn ray_hit(&self, s: Vector2<f64>, u: Vector2<f64>, max: f64) -> Option<f64> {
        let ray = Ray::new(PVector::new(s.x, s.y), PVector::new(u.x, u.y));
        self.segments.cast_local_ray(&ray, max, false)
    }

    /// The wall segments within `reach` of `x`.
    pub fn segments_near(
        &self,
        x: Vector2<f64>,
        reach: f64,
    ) -> impl Iterator<Item = (Vector2<f64>, Vector2<f64>)> + '_ {
        let p = PVector::new(x.x, x.y);
        self.segments
            .segments()
            .filter(move |e| e.distance_to_local_point(p, true) <= reach)
            .map(|e| (Vector2::new(e.a.x, e.a.y), Vector2::new(e.b.x, e.b.y)))
    }

    /// Points of the level set `{sd = g}` (`g ≥ 0`) within `reach` of `near`, at spacing at
    /// most `h` along it, accepted by `keep`: the segments moved by `g` to either side and
    /// the arcs of radius `g` about their ends, each sampled at spacing `h`, of which those
    /// with `sd ≥ g − h/2` are kept. Every point `y` of the level set lies on one of these
    /// pieces, within `h/2` of a sample of it, and that sample has `sd ≥ sd(y) − h/2` (1-Lipschitz):
    /// so every point of the level set is within `h/2` of a kept sample (the cover of
    /// `crate::free`). Samples on the walls' side (`sd ≈ −g`) go unless `g ≤ h/4`; those nearer
    /// another wall than `g` stay, which only adds samples.
    pub(crate) fn level_samples(
        &self,
        g: f64,
        h: f64,
        near: Vector2<f64>,
        reach: f64,
        keep: &dyn Fn(Vector2<f64>) -> bool,
    ) -> Vec<Vector2<f64>> {
        let mut out = Vec::new();
        let mut push = |x: Vector2<f64>| {
            if (x - near).norm() <= reach + h && self.signed_distance(x) >= g - 0.5 * h && keep(x) {
                out.push(x);
            }
        };
        for (a, b) in self.segments_near(near, reach + g + h) {
            let ab = b - a;
            let len = ab.norm();
            if len == 0.0 {
                continue;
            }
            let n = Vector2::new(-ab.y, ab.x) / len;
            let steps = ((len / h).ceil() as usize).max(1);
            let sides: &[f64] = if g > 0.0 { &[1.0, -1.0] } else { &[0.0] };
            for &side in sides {
                for j in 0..=steps {
                    push(a + ab * (j as f64 / steps as f64) + side * g * n);
                }
            }
            if g > 0.0 {
                let count = ((std::f64::consts::TAU * g / h).ceil() as usize).max(8);
                for j in 0..count {
                    let th = std::f64::consts::TAU * j as f64 / count as f64;
                    push(a + g * Vector2::new(th.cos(), th.sin()));
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vector2<f64> {
        Vector2::new(x, y)
    }

    /// A 4 m square room with a 1 m square pillar in its middle.
    fn room() -> Walls {
        let outer = vec![v(0.0, 0.0), v(4.0, 0.0), v(4.0, 4.0), v(0.0, 4.0)];
        let hole = vec![v(1.5, 1.5), v(1.5, 2.5), v(2.5, 2.5), v(2.5, 1.5)];
        Walls::new(outer, vec![hole]).unwrap()
    }

    /// Distances, sides and rays against closed forms.
    #[test]
    fn queries_match_closed_forms() {
        let w = room();
        assert!((w.signed_distance(v(0.5, 3.0)) - 0.5).abs() < 1e-12);
        assert!((w.signed_distance(v(2.0, 2.2)) + 0.3).abs() < 1e-12);
        assert!((w.signed_distance(v(-1.0, 2.0)) + 1.0).abs() < 1e-12);
        // Corner of the pillar: the distance to its vertex.
        let d = w.signed_distance(v(1.0, 1.0));
        assert!((d - 0.5f64.hypot(0.5)).abs() < 1e-12, "{d}");
        let hit = w.ray_hit(v(0.5, 2.0), v(1.0, 0.0), 10.0).unwrap();
        assert!((hit - 1.0).abs() < 1e-12, "{hit}");
        assert!(w.ray_hit(v(0.5, 2.0), v(1.0, 0.0), 0.9).is_none());
        assert_eq!(
            Walls::new(vec![v(0.0, 0.0), v(1.0, 0.0)], vec![]).unwrap_err(),
            WallsError::TooFewVertices { ring: 0 }
        );
        assert_eq!(
            Walls::new(vec![v(0.0, 0.0), v(1.0, 0.0), v(f64::NAN, 1.0)], vec![]).unwrap_err(),
            WallsError::NotFinite { ring: 0 }
        );
    }

    /// Every point of the level set `{sd = g}` near a point lies within `h/2` of a sample,
    /// checked on a fine independent grid of the set (bisection along rays from inside).
    #[test]
    fn level_samples_cover_the_level_set() {
        let w = room();
        let (h, near, reach) = (0.02, v(1.2, 1.2), 0.8);
        for g in [0.0, 0.005, 0.3] {
            let samples = w.level_samples(g, h, near, reach, &|_| true);
            assert!(!samples.is_empty());
            // Points of {sd = g} within `reach` of `near`: bisect sd − g along rays from `near`
            // (where sd > g) outwards.
            let mut checked = 0;
            for j in 0..720 {
                let th = std::f64::consts::TAU * j as f64 / 720.0;
                let u = v(th.cos(), th.sin());
                let (mut lo, mut hi) = (0.0, reach);
                if w.signed_distance(near + hi * u) >= g {
                    continue;
                }
                for _ in 0..60 {
                    let m = 0.5 * (lo + hi);
                    if w.signed_distance(near + m * u) >= g {
                        lo = m;
                    } else {
                        hi = m;
                    }
                }
                let y = near + lo * u;
                let gap = samples
                    .iter()
                    .map(|s| (s - y).norm())
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    gap <= 0.5 * h + 1e-9,
                    "g = {g}: {y:?} is {gap} from a sample"
                );
                checked += 1;
            }
            assert!(checked > 50, "g = {g}: only {checked} level points checked");
        }
    }
}
