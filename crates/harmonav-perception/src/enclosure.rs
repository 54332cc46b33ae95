//! Whether the shapes of a scan update certainly wall the sensor in (eq. surround): then the
//! update ends with a perceived shape that holds the sensor, and [`crate::Perception::observe`]
//! refuses it before its merges ([`crate::PerceptionError::HoldsSensor`]).
//!
//! **Clusters.** The update's merge loop keeps its shapes pairwise certified apart
//! (`StarShape::distance_to > merge_gap ≥ 0`: each shape it keeps was checked against every
//! other when it was pushed, and the others did not change since), and every fit ends inside
//! one of its final shapes (held by one, or merged into one: a merge holds both). So two of
//! the update's shapes (fits, or perceived shapes from before) that share a point end inside
//! one final shape: two final shapes that share a point are not certified apart. A *cluster*
//! is a class of the relation "certainly share a point" (a point certainly inside both), closed
//! transitively; each cluster ends inside one final shape `M`.
//!
//! **Surround.** Each shape `F` of a cluster is a star about its centre `c`, so it holds the
//! segments `[c, b]` to the points `b = c + f·R(θ)·u(θ)`, `f < 1`. Seen from the sensor `s`,
//! outside `F`, such a segment covers the directions between those of `c` and `b` (the short
//! way, less than `π`); the segments to `N` points `b_j` cover the arc
//! `[φ_c + min(0, min δ_j), φ_c + max(0, max δ_j)]` (`δ_j` the angle from `c − s` to `b_j − s`),
//! inside the directions in which `F` lies. If the arcs of a cluster's shapes cover the whole
//! circle, every ray from `s` meets the cluster, so the final shape `M`, a star about a point
//! `p` that holds the cluster, holds `s`: the ray from `p` through `s` meets the cluster at a
//! `z` beyond `s`, and `s ∈ [p, z] ⊂ M` (eq. surround). `M` is then new or grown (no shape from
//! before holds the sensor, `PoseNotFree`), and the update would end with the sensor inside.
//!
//! Each arc is shrunk by `1e-9` rad at both ends, so that the cover does not rest on the
//! rounding of the angles, and a shape that may hold `s` (its certified lower bound `lo(s) ≤ 0`)
//! gives no arc (it is refused on its own when it certainly holds `s`).

use std::f64::consts::TAU;

use harmonav_transform::StarShape;
use nalgebra::Vector2;

/// Points per shape whose segments from the centre make its arc.
const ARC_POINTS: usize = 256;

/// How far in from the boundary the arc's points and the overlap's witnesses lie, as a fraction
/// of the radius: far above the rounding of `R(θ)`, so that they are certainly inside.
const INSIDE: f64 = 1.0 - 1e-6;

/// Directions per shape of the points tested in the other shape for an overlap.
const WITNESS_DIRECTIONS: usize = 32;

/// The arcs' shrink at each end, rad.
const ARC_SLACK: f64 = 1e-9;

/// The shapes of an update seen from the sensor, clustered by certain overlaps (module docs).
#[derive(Debug)]
pub(crate) struct Surround {
    s: Vector2<f64>,
    /// Per shape: the centre and the largest radius (a disc that holds it).
    discs: Vec<(Vector2<f64>, f64)>,
    /// Per shape: its arc seen from `s`, `(start, end)` rad, `0 < end − start < 2π`.
    arcs: Vec<Option<(f64, f64)>>,
    /// Union–find over the shapes.
    parent: Vec<usize>,
    /// Shapes whose overlaps with the earlier ones were tested.
    tested: usize,
}

impl Surround {
    /// No shape yet, the sensor at `s`.
    pub(crate) fn new(s: Vector2<f64>) -> Self {
        Self {
            s,
            discs: Vec::new(),
            arcs: Vec::new(),
            parent: Vec::new(),
            tested: 0,
        }
    }

    /// How many shapes were added.
    pub(crate) fn len(&self) -> usize {
        self.discs.len()
    }

    /// Adds a shape (its index is the count before).
    pub(crate) fn push(&mut self, shape: &StarShape) {
        self.discs.push((shape.centre(), shape.radius_bounds().1));
        self.arcs.push(arc(shape, self.s));
        self.parent.push(self.parent.len());
    }

    fn root(&mut self, mut i: usize) -> usize {
        while self.parent[i] != i {
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        i
    }

    /// Whether the shapes added so far wall the sensor in (eq. surround); `shapes[i]` is the
    /// `i`-th shape added. The overlaps of the shapes added since the last call with all the
    /// others are tested first (pairs whose discs meet, in different clusters).
    pub(crate) fn walled_in(&mut self, shapes: &[&StarShape]) -> bool {
        let n = self.len();
        debug_assert_eq!(shapes.len(), n);
        for j in self.tested..n {
            for i in 0..j {
                let ((ci, ri), (cj, rj)) = (self.discs[i], self.discs[j]);
                if (ci - cj).norm() > ri + rj {
                    continue;
                }
                let (a, b) = (self.root(i), self.root(j));
                if a != b && overlap(shapes[i], shapes[j]) {
                    self.parent[a] = b;
                }
            }
        }
        self.tested = n;
        let mut clusters: Vec<Vec<(f64, f64)>> = vec![Vec::new(); n];
        for i in 0..n {
            if let Some(a) = self.arcs[i] {
                let r = self.root(i);
                clusters[r].push(a);
            }
        }
        clusters.into_iter().any(covers)
    }
}

/// The arc of directions from `s` in which `shape` certainly lies (module docs), `None` when
/// `s` may lie in it or the arc is empty.
fn arc(shape: &StarShape, s: Vector2<f64>) -> Option<(f64, f64)> {
    if shape.signed_distance_bounds(s).0 <= 0.0 {
        return None;
    }
    let c = shape.centre();
    let w = c - s;
    let (mut lo, mut hi) = (0.0f64, 0.0f64);
    for j in 0..ARC_POINTS {
        let t = TAU * j as f64 / ARC_POINTS as f64;
        let u = Vector2::new(t.cos(), t.sin());
        let v = c + (INSIDE * shape.radius_along(u).0) * u - s;
        let d = (w.x * v.y - w.y * v.x).atan2(w.dot(&v));
        lo = lo.min(d);
        hi = hi.max(d);
    }
    let phi = w.y.atan2(w.x);
    (hi - lo > 2.0 * ARC_SLACK).then_some((phi + lo + ARC_SLACK, phi + hi - ARC_SLACK))
}

/// Whether `x` lies certainly inside `shape`: nearer its centre than `INSIDE·R` along its ray.
fn deep(shape: &StarShape, x: Vector2<f64>) -> bool {
    let v = x - shape.centre();
    let rho = v.norm();
    let (r_min, r_max) = shape.radius_bounds();
    rho < INSIDE * r_min || (rho < r_max && rho < INSIDE * shape.radius_along(v / rho).0)
}

/// Whether `a` and `b` certainly share a point: the centre of one, or a point `c + f·R(θ)·u`
/// (`f` ½ or `INSIDE²`, 32 directions) of one, deep in the other.
fn overlap(a: &StarShape, b: &StarShape) -> bool {
    let witnessed = |p: &StarShape, q: &StarShape| {
        let c = p.centre();
        deep(q, c)
            || (0..WITNESS_DIRECTIONS).any(|j| {
                let t = TAU * j as f64 / WITNESS_DIRECTIONS as f64;
                let u = Vector2::new(t.cos(), t.sin());
                let r = p.radius_along(u).0;
                [0.5, INSIDE * INSIDE]
                    .into_iter()
                    .any(|f| deep(q, c + (f * r) * u))
            })
    };
    witnessed(a, b) || witnessed(b, a)
}

/// Whether the arcs (each `(start, end)`, shorter than a turn) cover the whole circle.
fn covers(mut arcs: Vec<(f64, f64)>) -> bool {
    if arcs.is_empty() {
        return false;
    }
    // Starts in [0, 2π), each arc also a turn later, so that a run may cross 2π.
    for a in &mut arcs {
        let shift = a.0.div_euclid(TAU) * TAU;
        *a = (a.0 - shift, a.1 - shift);
    }
    let mut all: Vec<(f64, f64)> = arcs
        .iter()
        .flat_map(|&(a, b)| [(a, b), (a + TAU, b + TAU)])
        .collect();
    all.sort_by(|p, q| p.0.total_cmp(&q.0));
    let (mut start, mut end) = (all[0].0, all[0].1);
    for &(a, b) in &all[1..] {
        if a > end {
            (start, end) = (a, b);
        } else {
            end = end.max(b);
        }
        if end - start >= TAU {
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    fn disc(x: f64, y: f64, r: f64) -> StarShape {
        StarShape::circle(Vector2::new(x, y), r).unwrap()
    }

    /// A ring of overlapping discs about the sensor walls it in; with one disc taken out, or
    /// with a gap between two discs that leaves them apart, it does not; a disc that may hold
    /// the sensor gives no arc.
    #[test]
    fn a_ring_of_overlapping_shapes_walls_the_sensor_in() {
        let s = Vector2::new(0.3, -0.2);
        let ring = |n: usize, skip: Option<usize>, r: f64| -> Vec<StarShape> {
            (0..n)
                .filter(|&k| Some(k) != skip)
                .map(|k| {
                    let t = TAU * k as f64 / n as f64;
                    disc(s.x + 2.0 * t.cos(), s.y + 2.0 * t.sin(), r)
                })
                .collect()
        };
        let walled = |shapes: &[StarShape]| {
            let mut w = Surround::new(s);
            for p in shapes {
                w.push(p);
            }
            let refs: Vec<&StarShape> = shapes.iter().collect();
            w.walled_in(&refs)
        };
        // Twelve discs of radius 0.6 on a circle of radius 2: neighbours 1.04 apart overlap.
        assert!(walled(&ring(12, None, 0.6)));
        assert!(!walled(&ring(12, Some(5), 0.6)));
        // 24 discs 0.52 m apart: of radius 0.1 they are apart, of 0.3 they overlap.
        assert!(!walled(&ring(24, None, 0.1)));
        assert!(walled(&ring(24, None, 0.3)));
        // Discs of radius 0.4 at 2 m and at 3.5 m from the sensor, in turn every 15°: their
        // arcs (±11.5° and ±6.6°) cover the turn, but no two share a point.
        let apart: Vec<StarShape> = (0..24)
            .map(|k| {
                let (t, d) = (TAU * k as f64 / 24.0, if k % 2 == 0 { 2.0 } else { 3.5 });
                disc(s.x + d * t.cos(), s.y + d * t.sin(), 0.4)
            })
            .collect();
        let arcs: Vec<(f64, f64)> = apart.iter().filter_map(|p| arc(p, s)).collect();
        assert!(covers(arcs));
        assert!(!walled(&apart));
        // Incrementally: the same answer, the overlaps of the new shapes tested once.
        let shapes = ring(12, None, 0.6);
        let mut w = Surround::new(s);
        let mut answers = Vec::new();
        for (k, p) in shapes.iter().enumerate() {
            w.push(p);
            let refs: Vec<&StarShape> = shapes[..=k].iter().collect();
            answers.push(w.walled_in(&refs));
        }
        assert_eq!(answers.iter().filter(|a| **a).count(), 1);
        assert!(answers[11]);
        // A shape over the sensor gives no arc.
        assert!(arc(&disc(s.x, s.y + 0.5, 0.6), s).is_none());
        assert!(arc(&disc(s.x, s.y + 0.5, 0.4), s).is_some());
    }

    /// The arcs' cover across the wrap at ±π, and not with a gap.
    #[test]
    fn arcs_cover_the_circle_across_the_wrap() {
        assert!(covers(vec![(3.0, 5.0), (4.5, 7.0), (6.9, 9.4)]));
        assert!(!covers(vec![(3.0, 5.0), (4.5, 7.0), (7.1, 9.4)]));
        assert!(covers(vec![(-3.0, 0.5), (0.4, 3.3)]));
        assert!(!covers(vec![(-3.0, 3.2)]));
        assert!(!covers(Vec::new()));
    }
}
