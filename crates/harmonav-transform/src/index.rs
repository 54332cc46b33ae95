//! A spatial index over discs (parry2d-f64's bounding-volume hierarchy, `Bvh`): which of `M`
//! discs `(c_i, r_i)` can hold a point or come within a distance of it, in `O(log M + k)` for
//! `k` answers instead of the direct loop's `O(M)` (docs/maths.md §14).
//!
//! The index only ever *prunes*: every disc with `|x − c_i| < r_i + reach` is reported (each
//! leaf is the disc's square, padded by [`pad`] against rounding), some that do not qualify may
//! be too, and the caller applies the same exact test the direct loop applies. Answers built
//! on it are therefore the direct loop's, bit for bit, as long as the caller combines them in
//! an order-free way (a minimum, the lowest index that passes a test); the tests compare both
//! on seeded worlds. parry's types stay inside this module. A query allocates nothing unless
//! the tree is deeper than 32 levels (parry's traversal stack then spills to the heap; the
//! binned build of 1 000 leaves is far shallower).

use nalgebra::Vector2;
use parry2d_f64::bounding_volume::Aabb;
use parry2d_f64::math::Vector as PVector;
use parry2d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhNode, TraversalAction};

/// How the queries over the obstacles are answered: by the spatial index ([`Lookup::Indexed`],
/// the default) or by the direct loops over every obstacle ([`Lookup::Direct`], the reference
/// the tests and `cargo xtask bench --only many` compare it with). Both give the same answers,
/// bit for bit (docs/maths.md §14).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Lookup {
    /// Every query tests every obstacle.
    Direct,
    /// Every query tests only the obstacles the index cannot rule out.
    #[default]
    Indexed,
}

/// Below this many obstacles the queries of a [`Lookup::Indexed`] world loop over all of them
/// anyway (the same answers): a walk of the tree costs more than a few disc tests.
pub const INDEX_MIN: usize = 32;

/// The padding of a leaf box or a query box around a disc of radius `r` at `c`: `2⁻⁴⁰` of the
/// coordinates' size, far above the rounding of `|x − c| < r + reach` (a few ε) and far below
/// any distance that matters, so that the boxes contain the discs whatever the rounding.
#[must_use]
pub fn pad(c: Vector2<f64>, r: f64) -> f64 {
    (c.x.abs().max(c.y.abs()) + r.abs()) * 2f64.powi(-40) + f64::MIN_POSITIVE
}

/// A bounding-volume hierarchy over discs; leaf `i` is disc `i` in the order given.
#[derive(Clone, Debug, Default)]
pub struct DiscIndex {
    bvh: Bvh,
    len: usize,
}

fn square(c: Vector2<f64>, half: f64) -> Aabb {
    Aabb::new(
        PVector::new(c.x - half, c.y - half),
        PVector::new(c.x + half, c.y + half),
    )
}

impl DiscIndex {
    /// The index of the discs `(c_i, r_i)`, leaf `i` the `i`-th (binned SAH build,
    /// `O(M log M)`).
    pub fn new(discs: impl IntoIterator<Item = (Vector2<f64>, f64)>) -> Self {
        let boxes: Vec<Aabb> = discs
            .into_iter()
            .map(|(c, r)| square(c, r + pad(c, r)))
            .collect();
        Self {
            len: boxes.len(),
            bvh: Bvh::from_leaves(BvhBuildStrategy::Binned, &boxes),
        }
    }

    /// Adds disc `(c, r)` as the next leaf (index [`Self::len`]), `O(log M)` for a balanced
    /// tree.
    pub fn push(&mut self, c: Vector2<f64>, r: f64) {
        let index = self.len as u32;
        self.bvh.insert(square(c, r + pad(c, r)), index);
        self.len += 1;
    }

    /// The number of discs.
    #[must_use]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether there is no disc.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Calls `f(i)` for every disc `i` with `|x − c_i| < r_i + reach` (and maybe others whose
    /// box comes within `reach` of `x`), in no particular order. `reach = ∞` reports all.
    pub fn near(&self, x: Vector2<f64>, reach: f64, mut f: impl FnMut(usize)) {
        let half = reach + pad(x, reach);
        let (lo, hi) = (
            PVector::new(x.x - half, x.y - half),
            PVector::new(x.x + half, x.y + half),
        );
        let overlaps = |n: &BvhNode| {
            n.mins().x <= hi.x && n.mins().y <= hi.y && n.maxs().x >= lo.x && n.maxs().y >= lo.y
        };
        for leaf in self.bvh.leaves(overlaps) {
            f(leaf as usize);
        }
    }

    /// The smallest `cost(i)` over the discs, best first: `bound(d)` must be a lower bound of
    /// `cost(i)` for every disc `i` whose box lies at distance `d` or more from `x`
    /// (`cost(i) = None` skips disc `i`). Returns `start` if no cost is below it. With exact
    /// bounds the answer is the minimum of the direct loop `min(start, cost(0), …, cost(M−1))`,
    /// exactly (a minimum of the same numbers).
    pub fn min_cost(
        &self,
        x: Vector2<f64>,
        start: f64,
        bound: impl Fn(f64) -> f64,
        mut cost: impl FnMut(usize) -> Option<f64>,
    ) -> f64 {
        let mut best = start;
        self.bvh.traverse(|n: &BvhNode| {
            let (lo, hi) = (n.mins(), n.maxs());
            let dx = (lo.x - x.x).max(x.x - hi.x).max(0.0);
            let dy = (lo.y - x.y).max(x.y - hi.y).max(0.0);
            let d = (dx * dx + dy * dy).sqrt();
            if bound(d) >= best {
                return TraversalAction::Prune;
            }
            if let Some(i) = n.leaf_data()
                && n.is_leaf()
                && let Some(c) = cost(i as usize)
            {
                best = best.min(c);
            }
            TraversalAction::Continue
        });
        best
    }
}
