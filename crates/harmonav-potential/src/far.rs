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

use harmonav_multipole::{C64, Fmm, Options, Source};
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
    /// How many points the tree was built over (pushed ones come on top).
    built: usize,
}

impl FarField {
    /// The tree over `points` (all finite: checked by `PointWorld::new`), or `None` when they
    /// span more than an `f64` holds (coordinates near ±1e308; the direct sum serves them).
    pub(crate) fn new(points: &[Vector2<f64>]) -> Option<Self> {
        let sources: Vec<Source> = points
            .iter()
            .map(|p| Source::Point(C64::new(p.x, p.y)))
            .collect();
        let weights = vec![[1.0]; points.len()];
        let options = Options {
            tolerance: TOLERANCE,
            ..Options::default()
        };
        let fmm = Fmm::new(&sources, &weights, &options).ok()?;
        Some(Self {
            fmm: Arc::new(fmm),
            built: points.len(),
        })
    }

    /// This tree with `more` points appended (numbered after the existing ones): pushed into a
    /// copy when they fall inside the root box and the tree has fewer than twice the points it
    /// was built over, otherwise rebuilt over `all`. The doubling rule keeps the depth right
    /// (a push never deepens the tree, so a tree built at 128 points and pushed to 1 000 would
    /// leave hundreds of near points per evaluation) at an amortised cost of one build.
    pub(crate) fn extended(&self, all: &[Vector2<f64>], more: &[Vector2<f64>]) -> Option<Self> {
        if all.len() >= 2 * self.built {
            return Self::new(all);
        }
        let mut fmm = (*self.fmm).clone();
        for p in more {
            if fmm.push_point(C64::new(p.x, p.y), [1.0]).is_err() {
                // Outside the root box (a finite point cannot fail otherwise): rebuild.
                return Self::new(all);
            }
        }
        Some(Self {
            fmm: Arc::new(fmm),
            built: self.built,
        })
    }

    /// [`Self::extended`] in place by the last point of `all` (the tree holds the others): a
    /// push into the tree (copied first only if shared); or, when the tree has grown to twice
    /// the points it was built over or the point lies outside the root box, one rebuild over
    /// `all`. `false` (the tree unusable: the caller drops it and sums directly) only when that
    /// rebuild fails.
    pub(crate) fn push(&mut self, all: &[Vector2<f64>]) -> bool {
        let Some(p) = all.last() else {
            return true;
        };
        if all.len() < 2 * self.built
            && Arc::make_mut(&mut self.fmm)
                .push_point(C64::new(p.x, p.y), [1.0])
                .is_ok()
        {
            return true;
        }
        match Self::new(all) {
            Some(far) => {
                *self = far;
                true
            }
            None => false,
        }
    }

    /// How many points the tree was built over, and how many it holds.
    #[cfg(test)]
    pub(crate) fn counts(&self) -> (usize, usize) {
        (self.built, self.fmm.len())
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

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize, spacing: f64) -> Vec<Vector2<f64>> {
        (0..n * n)
            .map(|i| {
                Vector2::new(
                    (i % n) as f64 * spacing,
                    (i / n) as f64 * spacing + 0.01 * (i % 7) as f64,
                )
            })
            .collect()
    }

    #[test]
    fn points_inside_the_root_box_are_pushed_until_the_count_doubles() {
        let all = grid(40, 1.0); // 1 600 points
        let first = FarField::new(&all[..1_000]).unwrap();
        // Points among the first ones (inside their root box): pushed, not rebuilt.
        let pushed = first.extended(&all[..1_200], &all[1_000..1_200]).unwrap();
        assert_eq!(pushed.counts(), (1_000, 1_200));
        // Twice the built count: rebuilt (deeper).
        let rebuilt = pushed.extended(&all[..], &all[1_200..]).unwrap();
        assert_eq!(rebuilt.counts(), (1_600, 1_600));
        let twice: Vec<Vector2<f64>> = grid(45, 1.0)[..2_000].to_vec();
        assert_eq!(
            first.extended(&twice, &twice[1_000..]).unwrap().counts(),
            (2_000, 2_000)
        );
        // Outside the root box: rebuilt.
        let mut out = all[..1_000].to_vec();
        out.push(Vector2::new(500.0, -300.0));
        assert_eq!(
            first.extended(&out, &out[1_000..]).unwrap().counts(),
            (1_001, 1_001)
        );
        // Coordinates beyond an f64's span: no tree.
        assert!(FarField::new(&[Vector2::new(-1e308, 0.0), Vector2::new(1e308, 0.0)]).is_none());
        // In place: a point inside is pushed, one outside rebuilds the tree once, and a
        // rebuild that cannot be made reports the tree unusable.
        let mut tree = first.clone();
        assert!(tree.push(&all[..1_001]));
        assert_eq!(tree.counts(), (1_000, 1_001));
        let mut tree = first.clone();
        assert!(tree.push(&out));
        assert_eq!(tree.counts(), (1_001, 1_001));
        let beyond = [Vector2::new(-1e308, 0.0), Vector2::new(1e308, 0.0)];
        assert!(!FarField::new(&beyond[..1]).unwrap().push(&beyond));
    }
}
