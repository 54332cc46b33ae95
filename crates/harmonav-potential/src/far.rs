//! The obstacle sum `Σ_i ln|h − P_i|²` of `phi_k` by fast multipoles when the point world is
//! large (docs/maths.md §15): `O(p + near)` per point instead of `O(M)`.
//!
//! ```text
//! Σ_i ln|h − P_i|² = 2 Re F(h) (far, the leaf's local expansion) + Σ_near ln|h − P_i|²,
//! Σ_i (h − P_i)/|h − P_i|² = (Re F'(h), −Im F'(h)) + Σ_near (h − P_i)/|h − P_i|²,
//! F(z) = Σ_far log(z − P_i)                                             (harmonav-multipole)
//! ```
//!
//! The near points (those of the 3 × 3 leaves about `h`) keep the exact split product of
//! `world::split` and the exact offset of pitfall C; the far part carries an absolute error of
//! at most `2·TOLERANCE·M` in the sum, i.e. `2·TOLERANCE·M/k < 2·TOLERANCE` in `phi_k` and a
//! relative error of the same size in `Θ = sigma(phi_k)` (tested against the direct sum).

use std::sync::Arc;

use harmonav_multipole::{C64, Fmm, FmmError, Options, Source};
use nalgebra::Vector2;

/// From this many obstacle points on, [`crate::PointWorld`] sums its far points by multipoles
/// (measured crossover: the direct sum costs about 2.8 ns a point, the expansion about 0.2 µs
/// plus its near points; docs/benchmarks.md "Many obstacles").
pub const FAR_MIN: usize = 128;

/// The tolerance of the expansions: the far part of `Σ ln|h − P_i|` is within
/// `TOLERANCE · (number of far points)` of the direct sum.
pub const TOLERANCE: f64 = 1e-13;

/// The multipole tree over the obstacle points (unit weights; `1/k` is applied by the caller).
#[derive(Clone, Debug)]
pub(crate) struct FarField {
    fmm: Arc<Fmm<1>>,
}

impl FarField {
    /// The tree over `points` (all finite: checked by `PointWorld::new`).
    pub(crate) fn new(points: &[Vector2<f64>]) -> Self {
        let sources: Vec<Source> = points
            .iter()
            .map(|p| Source::Point(C64::new(p.x, p.y)))
            .collect();
        let weights = vec![[1.0]; points.len()];
        let options = Options {
            tolerance: TOLERANCE,
            ..Options::default()
        };
        // Infallible here: as many weights as sources, finite points, default options in range.
        let fmm = Fmm::new(&sources, &weights, &options)
            .unwrap_or_else(|e| unreachable!("the far field of finite points: {e}"));
        Self { fmm: Arc::new(fmm) }
    }

    /// This tree with `more` points appended (numbered after the existing ones): pushed into a
    /// copy when they fall inside the root box, otherwise rebuilt over `all`.
    pub(crate) fn extended(&self, all: &[Vector2<f64>], more: &[Vector2<f64>]) -> Self {
        let mut fmm = (*self.fmm).clone();
        for p in more {
            match fmm.push_point(C64::new(p.x, p.y), [1.0]) {
                Ok(_) => {}
                Err(FmmError::OutsideRoot) => return Self::new(all),
                Err(e) => unreachable!("a finite point pushed: {e}"),
            }
        }
        Self { fmm: Arc::new(fmm) }
    }

    /// `(Σ_far 1/(z − P_i), Σ_far 1/(z − P_i)²) = (F'(z), −F''(z))` of the far points, and
    /// `near(i)` called for each near point `i` (the census's sums, `crate::critical`).
    pub(crate) fn reciprocal_sums(&self, z: C64, mut near: impl FnMut(usize)) -> (C64, C64) {
        let [v] = self.fmm.eval2(z, |piece| near(piece.source));
        (v.d1, -v.d2)
    }

    /// `(2 Re F(h), (Re F'(h), −Im F'(h)))` of the far points, and `near(i)` called for each
    /// near point `i`.
    #[inline]
    pub(crate) fn eval(&self, h: Vector2<f64>, mut near: impl FnMut(usize)) -> (f64, Vector2<f64>) {
        let [v] = self
            .fmm
            .eval(C64::new(h.x, h.y), |piece| near(piece.source));
        (2.0 * v.value, Vector2::new(v.d1.re, -v.d1.im))
    }
}
