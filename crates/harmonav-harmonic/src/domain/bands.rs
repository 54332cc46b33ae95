//! The crossing test of [`super::Domain::contains`] on the edges of one horizontal band.
//!
//! The even–odd rule casts a ray from `p` towards `+x` and counts the edges `ab` it crosses,
//! those with `(a_y > p_y) ≠ (b_y > p_y)`; such an edge has `min(a_y, b_y) ≤ p_y ≤ max(a_y, b_y)`.
//! The bounding box's height is cut into bands and each edge is listed in every band its
//! `y`-range meets, so only the edges of `p`'s band are tested: `O(V/B)` for `B` bands instead
//! of `O(V)` (12 308 vertices on `willow-full`, where the layer's edge samples and each
//! command ask). A band's edges are those of the rings in order and, within a ring, in order,
//! and the test per edge is `ring_contains`'s own, so the answer is the same bit for bit.

use nalgebra::Vector2;

/// The most bands: beyond this many, long edges (listed once per band they span) cost more
/// memory than the shorter lists save.
const MAX_BANDS: usize = 4096;

/// The most edges listed, per vertex: beyond it the bands are halved.
const MAX_LISTED: usize = 16;

/// Vertices per band, on average (the list of a band holds about this many edges plus the long
/// ones through it).
const EDGES_PER_BAND: usize = 4;

/// Edges listed by horizontal band.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Bands {
    /// The lowest and highest vertex `y`.
    y0: f64,
    y1: f64,
    /// Bands per metre: band of `y` is `⌊(y − y0)·scale⌋`, clamped to the last.
    scale: f64,
    /// How many bands (at least 1).
    count: usize,
    /// `starts[k]..starts[k + 1]` is band `k`'s range of `edges`.
    starts: Vec<usize>,
    /// `(ring, first vertex)` of each listed edge, grouped by band, then by ring and vertex.
    edges: Vec<(usize, usize)>,
}

impl Bands {
    /// The bands of `rings` (each ring closed implicitly, as in the domain).
    pub(super) fn new(rings: &[Vec<Vector2<f64>>]) -> Self {
        let ys = rings.iter().flatten().map(|v| v.y);
        let y0 = ys.clone().fold(f64::INFINITY, f64::min);
        let y1 = ys.fold(f64::NEG_INFINITY, f64::max);
        let vertices: usize = rings.iter().map(Vec::len).sum();
        let mut bands = Self {
            y0,
            y1,
            scale: 0.0,
            count: (vertices / EDGES_PER_BAND).clamp(1, MAX_BANDS),
            starts: Vec::new(),
            edges: Vec::new(),
        };
        // Fewer bands while the listed edges would exceed `MAX_LISTED` per vertex (edges that
        // span the height, a comb of tall walls, are listed once per band).
        loop {
            #[allow(clippy::cast_precision_loss)] // count ≤ MAX_BANDS
            let scale = if y1 > y0 {
                bands.count as f64 / (y1 - y0)
            } else {
                0.0
            };
            bands.scale = scale;
            let listed: usize = rings
                .iter()
                .flat_map(|ring| {
                    let n = ring.len();
                    (0..n).map(move |i| (ring[i].y, ring[(i + 1) % n].y))
                })
                .map(|(a, b)| bands.band(a.max(b)) - bands.band(a.min(b)) + 1)
                .sum();
            if listed <= MAX_LISTED * vertices || bands.count == 1 {
                break;
            }
            bands.count /= 2;
        }
        let count = bands.count;
        let mut lists: Vec<Vec<(usize, usize)>> = vec![Vec::new(); count];
        for (r, ring) in rings.iter().enumerate() {
            let n = ring.len();
            for i in 0..n {
                let (a, b) = (ring[i].y, ring[(i + 1) % n].y);
                let (lo, hi) = (bands.band(a.min(b)), bands.band(a.max(b)));
                for list in &mut lists[lo..=hi] {
                    list.push((r, i));
                }
            }
        }
        bands.starts.push(0);
        for list in lists {
            bands.edges.extend(list);
            bands.starts.push(bands.edges.len());
        }
        bands
    }

    /// The band of `y`, for `y` within `[y0, y1]` (the floor is monotone in `y`, so an edge's
    /// bands run from its lower end's to its upper end's; the top `y1` falls in the last).
    fn band(&self, y: f64) -> usize {
        let k = ((y - self.y0) * self.scale).floor();
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let k = if k > 0.0 { k as usize } else { 0 };
        k.min(self.count - 1)
    }

    /// Is `p` inside the outer ring (`rings[0]`) and inside no hole, by the even–odd rule on
    /// each ring: `ring_contains(rings[0], p) && !any(ring_contains(hole, p))`.
    pub(super) fn contains(&self, rings: &[Vec<Vector2<f64>>], p: Vector2<f64>) -> bool {
        // Outside the vertical extent (or NaN) no edge straddles `p_y`: every ring says no.
        if !(p.y >= self.y0 && p.y <= self.y1) {
            return false;
        }
        let k = self.band(p.y);
        let (mut ring, mut inside, mut outer) = (usize::MAX, false, false);
        for &(r, i) in &self.edges[self.starts[k]..self.starts[k + 1]] {
            if r != ring {
                if ring == 0 {
                    outer = inside;
                } else if ring != usize::MAX && inside {
                    return false;
                }
                (ring, inside) = (r, false);
            }
            let n = rings[r].len();
            let (a, b) = (rings[r][i], rings[r][(i + 1) % n]);
            if (a.y > p.y) != (b.y > p.y) {
                let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
                if p.x < x {
                    inside = !inside;
                }
            }
        }
        if ring == 0 {
            outer = inside;
        } else if ring != usize::MAX && inside {
            return false;
        }
        outer
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A comb of 200 teeth as tall as the domain: every tooth's sides span every band, so the
    /// bands are halved until at most `MAX_LISTED` edges per vertex are listed; the answers
    /// stay the whole rings' (checked on a grid).
    #[test]
    fn a_comb_of_tall_walls_lists_a_bounded_number_of_edges() {
        let mut ring = vec![Vector2::new(0.0, -1.0), Vector2::new(400.0, -1.0)];
        for k in (0..200).rev() {
            let x = 2.0 * f64::from(k);
            ring.extend([
                Vector2::new(x + 2.0, 100.0),
                Vector2::new(x + 1.0, 100.0),
                Vector2::new(x + 1.0, 0.0),
                Vector2::new(x, 0.0),
            ]);
        }
        ring.pop();
        ring.push(Vector2::new(0.0, 100.0));
        let rings = vec![ring];
        let bands = Bands::new(&rings);
        let vertices = rings[0].len();
        assert!(
            bands.edges.len() <= MAX_LISTED * vertices,
            "{}",
            bands.edges.len()
        );
        assert!(bands.count < (vertices / EDGES_PER_BAND).clamp(1, MAX_BANDS));
        let whole = |p: Vector2<f64>| super::super::ring_contains(&rings[0], p);
        for i in 0..400 {
            for j in 0..50 {
                let p = Vector2::new(f64::from(i) + 0.25, 2.0 * f64::from(j) - 0.5);
                assert_eq!(bands.contains(&rings, p), whole(p), "{p:?}");
            }
        }
    }
}
