//! The shortest collision-free path between two points of a workspace, computed independently
//! of the navigation function: the reference of the motion-quality benchmark (`docs/benchmarks.md`).
//!
//! Every shape is replaced by its outline polygon ([`StarShape::outline`]: 512 vertices on the
//! curve, evenly spaced in arc length) and the path is found on the visibility graph of those
//! polygons (Lozano-Pérez & Wesley 1979) by Dijkstra's algorithm. A shortest path bends only at
//! vertices where the free space is locally non-convex, and each of its segments is tangent to
//! the polygon at both ends, so the graph keeps only such vertices and such segments (the
//! *reduced* visibility graph): a few thousand edges for 20 obstacles.
//!
//! **Error bound.** Outline vertices lie on the curve, so along a convex stretch the polygon lies
//! inside the shape, at most the chord's sagitta `δ` from it. A taut path around the polygon is
//! therefore never longer than the true shortest path around the shapes, and pushing each of its
//! bends out by `δ` (an arc of radius `δ` per bend) gives a path around the shapes that is longer
//! by at most `δ·Σ|turn|`. [`ShortestPath::error_bound`] is that figure: `length` is the
//! polygon path's length, and the true shortest length lies in `[length, length + error_bound]`
//! (about 1e-5 m in the benchmark worlds).

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use harmonav_scenario::Prepared;
use harmonav_transform::StarShape;
use nalgebra::Vector2;

/// The result of [`shortest_path`].
#[derive(Clone, Debug, PartialEq)]
pub struct ShortestPath {
    /// Length of the shortest path around the outline polygons (a lower bound of the true one).
    pub length: f64,
    /// `δ·Σ|turn|`: the true shortest length is at most `length + error_bound`.
    pub error_bound: f64,
    /// The path: start, the bends, goal.
    pub waypoints: Vec<Vector2<f64>>,
}

/// Why no shortest path was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoPath {
    /// The start or the goal is not in the free space.
    NotFree,
    /// The goal cannot be reached from the start (the graph is disconnected).
    Unreachable,
}

impl std::fmt::Display for NoPath {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::NotFree => "the start or the goal is not in the free space",
            Self::Unreachable => "the goal cannot be reached from the start",
        })
    }
}

impl std::error::Error for NoPath {}

/// One outline polygon (counter-clockwise) with its bounding disc.
struct Polygon {
    vertices: Vec<Vector2<f64>>,
    centre: Vector2<f64>,
    reach: f64,
    /// The outer boundary (free space inside) rather than an obstacle (free space outside).
    outer: bool,
}

impl Polygon {
    fn new(shape: &StarShape, outer: bool) -> Self {
        let vertices: Vec<_> = shape.outline().collect();
        let centre = shape.centre();
        let reach = vertices
            .iter()
            .map(|v| (v - centre).norm())
            .fold(0.0, f64::max);
        Self {
            vertices,
            centre,
            reach,
            outer,
        }
    }

    fn len(&self) -> usize {
        self.vertices.len()
    }

    fn prev(&self, i: usize) -> Vector2<f64> {
        self.vertices[(i + self.len() - 1) % self.len()]
    }

    fn next(&self, i: usize) -> Vector2<f64> {
        self.vertices[(i + 1) % self.len()]
    }

    /// Whether a taut path can bend at vertex `i`: the free space is locally non-convex there
    /// (a convex vertex of an obstacle, a reflex vertex of the outer boundary).
    fn can_bend(&self, i: usize) -> bool {
        let turn = cross(
            self.vertices[i] - self.prev(i),
            self.next(i) - self.vertices[i],
        );
        if self.outer { turn < 0.0 } else { turn > 0.0 }
    }

    /// Whether the line through vertex `i` in direction `d` leaves both neighbours on one side
    /// (or on the line): the only lines along which a shortest path can touch the vertex.
    fn tangent_at(&self, i: usize, d: Vector2<f64>) -> bool {
        let v = self.vertices[i];
        cross(d, self.prev(i) - v) * cross(d, self.next(i) - v) >= 0.0
    }

    /// Whether the open segment `a → b` properly crosses an edge (edges at the endpoint
    /// vertices `skip` are ignored: a segment starting at a vertex touches its two edges).
    fn crossed_by(&self, a: Vector2<f64>, b: Vector2<f64>, skip: [Option<usize>; 2]) -> bool {
        // The segment's distance to the centre against the polygon's reach: most polygons are far.
        if segment_distance(self.centre, a, b) > self.reach && !self.outer {
            return false;
        }
        let n = self.len();
        (0..n).any(|j| {
            let k = (j + 1) % n;
            let touches = skip.iter().flatten().any(|&s| s == j || s == k);
            !touches && proper_cross(a, b, self.vertices[j], self.vertices[k])
        })
    }
}

fn cross(a: Vector2<f64>, b: Vector2<f64>) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Distance from `p` to the segment `a → b`.
fn segment_distance(p: Vector2<f64>, a: Vector2<f64>, b: Vector2<f64>) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(&ab) / ab.norm_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
    (a + t * ab - p).norm()
}

/// Whether the segments `a b` and `c d` cross at a point interior to both.
fn proper_cross(a: Vector2<f64>, b: Vector2<f64>, c: Vector2<f64>, d: Vector2<f64>) -> bool {
    let (d1, d2) = (cross(b - a, c - a), cross(b - a, d - a));
    let (d3, d4) = (cross(d - c, a - c), cross(d - c, b - c));
    d1 * d2 < 0.0 && d3 * d4 < 0.0
}

/// A graph node: the start, the goal, or vertex `vertex` of polygon `polygon`.
#[derive(Clone, Copy)]
struct Node {
    at: Vector2<f64>,
    on: Option<(usize, usize)>,
}

/// The shortest path from the start to the goal of a prepared scenario, in its configuration
/// space (the shapes grown by `robot.radius + robot.margin`): the independent reference of
/// "path over shortest".
pub fn of_scenario(prepared: &Prepared) -> Result<ShortestPath, NoPath> {
    let ws = &prepared.truth.workspace;
    let s = prepared.scenario.robot.start;
    shortest_path(
        ws.boundary(),
        ws.obstacles(),
        Vector2::new(s[0], s[1]),
        ws.destination(),
    )
}

/// The shortest path from `start` to `goal` inside `boundary` and outside `obstacles` (the
/// shapes as given: pass configuration-space shapes for a robot with a radius or a margin).
pub fn shortest_path(
    boundary: &StarShape,
    obstacles: &[StarShape],
    start: Vector2<f64>,
    goal: Vector2<f64>,
) -> Result<ShortestPath, NoPath> {
    let free = |x: Vector2<f64>| boundary.contains(x) && obstacles.iter().all(|o| !o.contains(x));
    if !free(start) || !free(goal) {
        return Err(NoPath::NotFree);
    }
    let mut polygons: Vec<Polygon> = obstacles.iter().map(|o| Polygon::new(o, false)).collect();
    polygons.push(Polygon::new(boundary, true));
    let mut nodes = vec![
        Node {
            at: start,
            on: None,
        },
        Node { at: goal, on: None },
    ];
    for (p, poly) in polygons.iter().enumerate() {
        for i in 0..poly.len() {
            if poly.can_bend(i) {
                nodes.push(Node {
                    at: poly.vertices[i],
                    on: Some((p, i)),
                });
            }
        }
    }
    // The segment between two nodes is an edge if it is tangent at each polygon vertex it ends
    // on, crosses no polygon edge, and (for two vertices of one shape) does not cut through it.
    let visible = |a: &Node, b: &Node| -> bool {
        let d = b.at - a.at;
        let tangent = |n: &Node| n.on.is_none_or(|(p, i)| polygons[p].tangent_at(i, d));
        if !(tangent(a) && tangent(b)) {
            return false;
        }
        let mid = 0.5 * (a.at + b.at);
        if !free(mid) {
            return false;
        }
        !polygons.iter().enumerate().any(|(p, poly)| {
            let skip = [a, b].map(|n| n.on.filter(|&(q, _)| q == p).map(|(_, i)| i));
            poly.crossed_by(a.at, b.at, skip)
        })
    };
    let mut edges: Vec<Vec<(usize, f64)>> = vec![Vec::new(); nodes.len()];
    for i in 0..nodes.len() {
        for j in i + 1..nodes.len() {
            let (a, b) = (&nodes[i], &nodes[j]);
            // Neighbours along one outline are joined by the outline edge itself.
            let adjacent = match (a.on, b.on) {
                (Some((p, u)), Some((q, v))) if p == q => {
                    let n = polygons[p].len();
                    (u + 1) % n == v || (v + 1) % n == u
                }
                _ => false,
            };
            if adjacent || visible(a, b) {
                let w = (a.at - b.at).norm();
                edges[i].push((j, w));
                edges[j].push((i, w));
            }
        }
    }
    let previous = dijkstra(&edges, 0);
    let Some(mut at) = previous[1].map(|_| 1) else {
        return Err(NoPath::Unreachable);
    };
    let mut path = vec![nodes[1]];
    while at != 0 {
        at = previous[at].map_or(0, |(p, _)| p);
        path.push(nodes[at]);
    }
    path.reverse();
    let waypoints: Vec<Vector2<f64>> = path.iter().map(|n| n.at).collect();
    let length = previous[1].map_or(0.0, |(_, d)| d);
    // δ·Σ|turn| with δ the largest sagitta of the shapes the path bends on.
    let mut error_bound = 0.0;
    for (w, n) in waypoints.windows(3).zip(&path[1..]) {
        let (u, v) = (w[1] - w[0], w[2] - w[1]);
        let turn = cross(u, v).atan2(u.dot(&v)).abs();
        let delta = n.on.map_or(0.0, |(p, _)| {
            let shape = if p < obstacles.len() {
                &obstacles[p]
            } else {
                boundary
            };
            sagitta(&polygons[p], shape)
        });
        error_bound += turn * delta;
    }
    Ok(ShortestPath {
        length,
        error_bound,
        waypoints,
    })
}

/// The largest distance between an outline edge and the curve it cuts off, measured at the
/// edge's middle direction from the shape's centre.
fn sagitta(poly: &Polygon, shape: &StarShape) -> f64 {
    let c = shape.centre();
    (0..poly.len())
        .map(|j| {
            let (a, b) = (poly.vertices[j], poly.next(j));
            let m = 0.5 * (a + b) - c;
            let curve = shape.boundary_point(m.y.atan2(m.x)) - c;
            (curve.norm() - m.norm()).abs()
        })
        .fold(0.0, f64::max)
}

/// A heap entry ordered by smallest distance first.
struct Entry(f64, usize);

impl PartialEq for Entry {
    fn eq(&self, other: &Self) -> bool {
        self.0 == other.0
    }
}
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0)
    }
}

/// Dijkstra from `source`: for each node, its predecessor and distance (`None` if unreached;
/// the source is its own predecessor).
fn dijkstra(edges: &[Vec<(usize, f64)>], source: usize) -> Vec<Option<(usize, f64)>> {
    let mut best: Vec<Option<(usize, f64)>> = vec![None; edges.len()];
    best[source] = Some((source, 0.0));
    let mut heap = BinaryHeap::from([Entry(0.0, source)]);
    while let Some(Entry(d, u)) = heap.pop() {
        if best[u].is_some_and(|(_, b)| d > b) {
            continue;
        }
        for &(v, w) in &edges[u] {
            let nd = d + w;
            if best[v].is_none_or(|(_, b)| nd < b) {
                best[v] = Some((u, nd));
                heap.push(Entry(nd, v));
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn disc_world() -> StarShape {
        StarShape::circle(Vector2::zeros(), 5.0).unwrap()
    }

    /// With nothing in the way the path is the straight segment.
    #[test]
    fn a_free_straight_line_is_the_segment() {
        let obstacles = [StarShape::circle(Vector2::new(0.0, 2.0), 0.5).unwrap()];
        let (a, b) = (Vector2::new(-3.0, 0.0), Vector2::new(3.0, 0.5));
        let p = shortest_path(&disc_world(), &obstacles, a, b).unwrap();
        assert!((p.length - (b - a).norm()).abs() < 1e-12, "{p:?}");
        assert_eq!(p.waypoints, vec![a, b]);
    }

    /// One disc between start and goal: tangent, arc, tangent, in closed form
    /// `√(a² − r²) + √(b² − r²) + r(γ − acos(r/a) − acos(r/b))`.
    #[test]
    fn one_disc_is_tangent_arc_tangent() {
        let check = |r: f64, a: Vector2<f64>, b: Vector2<f64>| {
            let obstacles = [StarShape::circle(Vector2::zeros(), r).unwrap()];
            let p = shortest_path(&disc_world(), &obstacles, a, b).unwrap();
            let (da, db) = (a.norm(), b.norm());
            let gamma = a.angle(&b);
            let exact = (da * da - r * r).sqrt()
                + (db * db - r * r).sqrt()
                + r * (gamma - (r / da).acos() - (r / db).acos());
            assert!(
                p.length <= exact + 1e-12 && exact <= p.length + p.error_bound + 1e-12,
                "r = {r}: {} + {:.1e} against {exact}",
                p.length,
                p.error_bound
            );
            assert!(p.error_bound < 1e-4 * exact, "{p:?}");
            assert!(p.waypoints.len() > 3, "the path wraps the disc");
        };
        check(1.0, Vector2::new(-3.0, 0.0), Vector2::new(3.0, 0.0));
        check(0.5, Vector2::new(-2.0, 0.3), Vector2::new(4.0, -0.2));
        check(2.0, Vector2::new(-2.5, -1.0), Vector2::new(2.5, 1.5));
    }

    /// Two discs side by side with a gap on the straight line: the path goes through the gap
    /// (straight), and closing the gap's line sends it round.
    #[test]
    fn a_gap_on_the_line_is_used_and_a_wall_of_discs_is_not_crossed() {
        let discs = [
            StarShape::circle(Vector2::new(0.0, 1.0), 0.9).unwrap(),
            StarShape::circle(Vector2::new(0.0, -1.0), 0.9).unwrap(),
        ];
        let (a, b) = (Vector2::new(-3.0, 0.0), Vector2::new(3.0, 0.0));
        let p = shortest_path(&disc_world(), &discs, a, b).unwrap();
        assert!((p.length - 6.0).abs() < 1e-12, "{p:?}");
        let off = Vector2::new(0.0, 0.5);
        let p = shortest_path(&disc_world(), &discs, a + off, b + off).unwrap();
        assert!(p.length > 6.0 && p.length < 6.2, "{p:?}");
        for w in p.waypoints.windows(2) {
            for t in 1..20 {
                let x = w[0] + (w[1] - w[0]) * (t as f64 / 20.0);
                assert!(discs.iter().all(|d| d.signed_distance(x) > -1e-4), "{x:?}");
            }
        }
    }

    #[test]
    fn points_outside_the_free_space_are_errors() {
        let obstacles = [StarShape::circle(Vector2::zeros(), 1.0).unwrap()];
        let r = shortest_path(
            &disc_world(),
            &obstacles,
            Vector2::zeros(),
            Vector2::new(3.0, 0.0),
        );
        assert_eq!(r, Err(NoPath::NotFree));
    }
}
