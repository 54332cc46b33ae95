//! Bounding boxes over a sequence of items (the edges of a cut polygon, the cut polygons of a
//! region, the hits of a segment) in parry2d-f64's bounding-volume hierarchy (`Bvh`), so that a
//! query visits only the items whose boxes its node test accepts instead of all of them.
//!
//! A query is exact when its node test is *conservative*: it rejects a node only when no item
//! under it can pass the item test (the callers prove this for theirs, rounding included), so
//! the answer is the one of the loop over all items. The item test must decide on its own: a
//! visited item is only one whose box, and every box above it, the node test accepted.

use nalgebra::Vector2;
use parry2d_f64::bounding_volume::Aabb as PAabb;
use parry2d_f64::math::Vector as PVector;
use parry2d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhNode};

/// The axis-aligned box `[min, max]` (empty: `min = +∞`, `max = −∞`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Aabb {
    pub(crate) min: Vector2<f64>,
    pub(crate) max: Vector2<f64>,
}

impl Aabb {
    /// The empty box: it holds no point, and is the unit of the union.
    pub(crate) const EMPTY: Self = Self {
        min: Vector2::new(f64::INFINITY, f64::INFINITY),
        max: Vector2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
    };

    /// The smallest box holding the points.
    pub(crate) fn of(points: impl IntoIterator<Item = Vector2<f64>>) -> Self {
        points.into_iter().fold(Self::EMPTY, |b, p| Self {
            min: b.min.inf(&p),
            max: b.max.sup(&p),
        })
    }

    /// Whether `x` lies in the box grown by `g ≥ 0` on every side (never for the empty box).
    pub(crate) fn holds(&self, x: Vector2<f64>, g: f64) -> bool {
        x.x >= self.min.x - g
            && x.x <= self.max.x + g
            && x.y >= self.min.y - g
            && x.y <= self.max.y + g
    }

    /// A node's box.
    fn of_node(n: &BvhNode) -> Self {
        let (lo, hi) = (n.mins(), n.maxs());
        Self {
            min: Vector2::new(lo.x, lo.y),
            max: Vector2::new(hi.x, hi.y),
        }
    }
}

/// The hierarchy over the items' boxes (module docs). Items with an empty box are left out:
/// no query visits them.
#[derive(Clone, Debug, Default)]
pub(crate) struct BoxTree {
    bvh: Bvh,
    /// The item of each leaf.
    items: Vec<usize>,
}

impl BoxTree {
    /// The hierarchy over items with these boxes (item `i` the `i`-th; binned SAH build,
    /// `O(m log m)`).
    pub(crate) fn new(boxes: &[Aabb]) -> Self {
        let (items, leaves): (Vec<usize>, Vec<PAabb>) = boxes
            .iter()
            .enumerate()
            .filter(|(_, b)| b.min.x <= b.max.x && b.min.y <= b.max.y)
            .map(|(i, b)| {
                let leaf = PAabb::new(
                    PVector::new(b.min.x, b.min.y),
                    PVector::new(b.max.x, b.max.y),
                );
                (i, leaf)
            })
            .unzip();
        if items.is_empty() {
            return Self::default();
        }
        Self {
            bvh: Bvh::from_leaves(BvhBuildStrategy::Binned, &leaves),
            items,
        }
    }

    /// Whether `item` accepts an item whose box, and every node above it, `descend` accepts (a
    /// node rejected hides all its items); it stops at the first accepted.
    pub(crate) fn any(
        &self,
        descend: &impl Fn(&Aabb) -> bool,
        item: &mut impl FnMut(usize) -> bool,
    ) -> bool {
        self.bvh
            .leaves(|n: &BvhNode| descend(&Aabb::of_node(n)))
            .any(|leaf| item(self.items[leaf as usize]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A query visits every item whose box the node test accepts, each once, and no other.
    #[test]
    fn visits_the_items_in_accepted_boxes() {
        for n in [0, 1, 7, 8, 9, 31, 64, 100] {
            let points: Vec<Vector2<f64>> = (0..n)
                .map(|i| Vector2::new(f64::from(i), -f64::from(i)))
                .collect();
            let boxes: Vec<Aabb> = points.iter().map(|&p| Aabb::of([p])).collect();
            let tree = BoxTree::new(&boxes);
            for &(x, g) in &[(10.0, 0.5), (3.0, 2.0), (-5.0, 1.0), (50.0, 100.0)] {
                let c = Vector2::new(x, -x);
                let mut seen = Vec::new();
                tree.any(&|b| b.holds(c, g), &mut |i| {
                    seen.push(i);
                    false
                });
                let want: Vec<usize> = (0..points.len())
                    .filter(|&i| Aabb::of([points[i]]).holds(c, g))
                    .collect();
                seen.sort_unstable();
                assert_eq!(seen, want, "n {n}, x {x}");
            }
        }
    }
}
