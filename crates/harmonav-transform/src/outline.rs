//! The certified outline of a shape: a closed polyline through points of the boundary curve,
//! with a proven bound `δ` on how far the curve strays from it. Every distance query
//! (`StarShape::signed_distance_bounds`, `distance_to`, `clearance_inside`) is a parry2d-f64
//! query on this polyline, widened by `δ`, so it is exact to a stated tolerance whatever the
//! shape's harmonics or curvature.
//!
//! # The chord bound
//!
//! Parametrise the boundary as `p(t)` (the polar angle `θ` for circles, Fourier stars and
//! offset shapes, `p = c + R(θ)(cos θ, sin θ)`; the eccentric anomaly for ellipses; piece index
//! plus fraction for rounded polygons), with `p ∈ C¹` and `|p''| ≤ K` on a span of `t`. For
//! consecutive vertices `a < b` of the span (`h = b − a`) and the chord `L(t)` between `p(a)`
//! and `p(b)`, linear in `t`,
//!
//! ```text
//! p(t) − L(t) = −∫_a^b G(t, s) p''(s) ds,   G ≥ 0,   ∫_a^b G(t, s) ds = (t − a)(b − t)/2
//! |p(t) − L(t)| ≤ K (t − a)(b − t)/2 ≤ K h²/8                              (eq. chord)
//! ```
//!
//! (`G` is the Green's function of `d²/dt²` with zero end values; the bound holds for vector
//! values because it bounds the norm of an integral by the integral of the norm.) Each curve
//! point is within `δ = max K h²/8` of the chord point of the same parameter, and each chord
//! point within `δ` of the curve: the Hausdorff distance between curve and polyline is at most
//! `δ`. By the triangle inequality, for any point `x` and shapes `A`, `B`:
//!
//! ```text
//! |d(x, ∂S) − d(x, P_S)| ≤ δ_S,        |d(∂A, ∂B) − d(P_A, P_B)| ≤ δ_A + δ_B
//! ```
//!
//! # The bounds on `|p''|`
//!
//! With `p = c + R u`, `u = (cos θ, sin θ)`, `u⊥ = (−sin θ, cos θ)`:
//! `p'' = (R'' − R) u + 2 R' u⊥`, so `|p''| ≤ √((max|R'' − R|)² + 4 (max|R'|)²)`.
//!
//! - **Fourier star** `R = r0 + Σ |c_n| cos(nθ − φ_n)`, `|c_n| = √(a_n² + b_n²)`:
//!   `|R'' − R| ≤ r0 + Σ (n² + 1)|c_n|`, `|R'| ≤ Σ n|c_n|` (one span, uniform in `θ`).
//! - **Offset shape** (a table of `(R, R')` with cubic Hermite cells of width `H`): on a cell
//!   `R''` is linear (largest at an end), `R'` quadratic (largest at an end or its vertex) and
//!   `|R| ≤ max(|R_a|, |R_b|) + max|R'|·H/2`; one span per block of 8 cells.
//! - **Ellipse** `p = c + a cos t e₁ + b sin t e₂`: `p'' = −(p − c)`, `K = max(a, b)`.
//! - **Circle**: `K = r` (its queries are closed forms; the outline serves ray casts).
//! - **Rounded polygon**: segments are exact (`K = 0`); an arc of radius `ρ_c` and angle `Δ`,
//!   parametrised by `s ∈ [0, 1]`, has `|p''| = ρ_c Δ²`.
//!
//! # The resolution
//!
//! A span `[t₀, t₁]` gets `m = ⌈(t₁ − t₀)·√(K/(8δ*))⌉` equal chords for the target
//! `δ* = DISTANCE_TOLERANCE·R_ref/2`, where `R_ref ≤ max R` is known before the outline is
//! built (`r0`, the mean of a star's `R`; the largest semi-axis; the largest tabulated radius;
//! the farthest piece end of a polygon). So `2δ ≤ DISTANCE_TOLERANCE·max R`: the resolution
//! follows the shape (a 200-lobe star with 5 % lobes gets ~14 000 vertices, a disc 315).

use nalgebra::Vector2;
use parry2d_f64::math::Vector as PVector;
use parry2d_f64::shape::Polyline;

/// The relative tolerance of every distance query: for a shape whose radius `R(θ)` reaches
/// `max R`, [`crate::StarShape::signed_distance_bounds`] returns `lo ≤ d ≤ hi` with
/// `hi − lo ≤ DISTANCE_TOLERANCE·max R` (plus rounding), and [`crate::StarShape::distance_to`]
/// is within the sum of both shapes' tolerances below the true gap.
///
/// Argument (module docs): the outline's chords are placed so that the curve stays within
/// `δ = K h²/8 ≤ DISTANCE_TOLERANCE·max R/2` of them (eq. chord, `K` a certified bound on
/// `|p''|`), hence every polyline distance is within `δ` of the true one. `1e-4` keeps typical
/// outlines near 500 vertices (4096 for offset shapes) while a 1 m obstacle is resolved to
/// 0.1 mm, far below a control step.
pub const DISTANCE_TOLERANCE: f64 = 1e-4;

/// The largest certified outline (vertices). Beyond it a shape is refused with a typed error:
/// at about 130 bytes per vertex (vertex, index, parameter and parry's bounding-volume tree)
/// the cap keeps one shape near 70 MB. A single harmonic `n ≤ 1000` needs at most ~315 000
/// (`K ≈ n²r0` for the deepest valid lobes).
pub const MAX_OUTLINE_VERTICES: usize = 1 << 19;

/// The number of Hermite cells of an offset shape's table per outline span.
pub(crate) const TABLE_BLOCK: usize = 8;

/// A stretch `[t0, t1]` of the boundary parameter on which `|p''| ≤ k`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Span {
    pub(crate) t0: f64,
    pub(crate) t1: f64,
    pub(crate) k: f64,
}

/// The vertex parameters for `spans` (each cut into equal chords, at least `min_chords`) so that
/// eq. chord gives `δ ≤ DISTANCE_TOLERANCE·r_ref/2`, with that certified `δ`. `Err(count)`
/// when more than [`MAX_OUTLINE_VERTICES`] would be needed.
pub(crate) fn subdivide(
    spans: &[Span],
    r_ref: f64,
    min_chords: usize,
) -> Result<(Vec<f64>, f64), f64> {
    // m = (t1 − t0)·√(K/(8δ*)) with δ* = TOL·r_ref/2, i.e. √((K/r_ref)/(4 TOL)): the ratio
    // first, so that tiny shapes (r_ref of 1e-300) do not underflow.
    let chords: Vec<f64> = spans
        .iter()
        .map(|s| {
            let m = ((s.t1 - s.t0) * ((s.k / r_ref) / (4.0 * DISTANCE_TOLERANCE)).sqrt()).ceil();
            m.max(min_chords as f64)
        })
        .collect();
    let total: f64 = chords.iter().sum();
    // NaN (from an unusable bound) is refused too.
    if total.is_nan() || total > MAX_OUTLINE_VERTICES as f64 {
        return Err(total);
    }
    let mut params = Vec::with_capacity(total as usize);
    let mut delta = 0.0f64;
    for (s, &m) in spans.iter().zip(&chords) {
        let m = m as usize;
        let h = (s.t1 - s.t0) / m as f64;
        delta = delta.max(s.k * h * h / 8.0);
        params.extend((0..m).map(|j| s.t0 + j as f64 * h));
    }
    Ok((params, delta))
}

/// A closed polyline on the boundary with its vertex parameters and chord bound `δ`.
#[derive(Debug)]
pub(crate) struct Outline {
    /// The polyline (counter-clockwise; segment `i` joins vertices `i` and `i + 1 mod N`).
    pub(crate) polyline: Polyline,
    /// The parameter of each vertex, increasing; the closing segment ends at
    /// `params[0] + period`.
    params: Vec<f64>,
    period: f64,
    /// The certified Hausdorff distance between polyline and curve.
    pub(crate) delta: f64,
}

impl Outline {
    /// An empty outline (a placeholder while a shape is being built).
    pub(crate) fn empty() -> Self {
        Self::new(&[], Vec::new(), 1.0, 0.0)
    }

    /// The polyline through `vertices` (at `params`, one `period` around).
    pub(crate) fn new(
        vertices: &[Vector2<f64>],
        params: Vec<f64>,
        period: f64,
        delta: f64,
    ) -> Self {
        let n = vertices.len() as u32;
        let pts = vertices.iter().map(|p| PVector::new(p.x, p.y)).collect();
        let idx = (0..n).map(|i| [i, (i + 1) % n]).collect();
        Self {
            polyline: Polyline::new(pts, Some(idx)),
            params,
            period,
            delta,
        }
    }

    /// The number of vertices (and segments).
    pub(crate) fn len(&self) -> usize {
        self.params.len()
    }

    /// Vertex `i` (`i < len`).
    pub(crate) fn vertex(&self, i: usize) -> Vector2<f64> {
        let v = self.polyline.vertices()[i];
        Vector2::new(v.x, v.y)
    }

    /// The parameter of vertex `j` counted around the closed outline (any integer, unwrapped).
    pub(crate) fn param(&self, j: isize) -> f64 {
        let n = self.params.len() as isize;
        self.params[j.rem_euclid(n) as usize] + j.div_euclid(n) as f64 * self.period
    }

    /// The parameter interval from vertex `first` to vertex `last` (`first < last`), at most
    /// one period wide.
    pub(crate) fn window(&self, first: isize, last: isize) -> (f64, f64) {
        let lo = self.param(first);
        (lo, self.param(last).min(lo + self.period))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// eq. chord is what `subdivide` certifies: on the unit circle (`K = 1`) the sagitta
    /// `1 − cos(h/2)` of every chord is at most `δ`, and `δ` meets the target.
    #[test]
    fn subdivide_meets_the_target_and_the_cap() {
        let tau = std::f64::consts::TAU;
        let (params, delta) = subdivide(
            &[Span {
                t0: 0.0,
                t1: tau,
                k: 1.0,
            }],
            1.0,
            64,
        )
        .unwrap();
        let h = tau / params.len() as f64;
        assert!(1.0 - (h / 2.0).cos() <= delta);
        assert!(delta <= DISTANCE_TOLERANCE / 2.0 && delta > 0.5 * DISTANCE_TOLERANCE / 2.0);
        assert_eq!(params.len(), 315);
        // The same circle at 1e-300 m: the same vertex count, no underflow.
        let tiny = subdivide(
            &[Span {
                t0: 0.0,
                t1: tau,
                k: 1e-300,
            }],
            1e-300,
            64,
        )
        .unwrap();
        assert_eq!(tiny.0.len(), 315);
        // A flat span keeps its minimum; an over-detailed one is refused with its count.
        assert_eq!(
            subdivide(
                &[Span {
                    t0: 0.0,
                    t1: 1.0,
                    k: 0.0
                }],
                1.0,
                1
            )
            .unwrap()
            .0
            .len(),
            1
        );
        let e = subdivide(
            &[Span {
                t0: 0.0,
                t1: tau,
                k: 1e12,
            }],
            1.0,
            1,
        )
        .unwrap_err();
        assert!(e > MAX_OUTLINE_VERTICES as f64);
    }
}
