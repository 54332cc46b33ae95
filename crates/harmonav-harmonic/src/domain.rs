//! A validated polygonal domain with polygonal holes: the static free space `W_s` whose harmonic
//! map [`crate::HarmonicMap`] is built.
//!
//! `W_s = int(P_0) \ (P_1 ∪ … ∪ P_M)`: the outer ring `P_0` counter-clockwise (signed area
//! `A_0 = ½ Σ (x_i y_{i+1} − x_{i+1} y_i) > 0`), every hole `P_i` clockwise (`A_i < 0`), each
//! ring simple, every hole strictly inside `P_0` and strictly apart from every other ring.

use nalgebra::Vector2;

mod bands;
use bands::Bands;

/// Most vertices over all rings (each vertex starts at least one boundary element, and the
/// element count is capped by [`crate::MAX_ELEMENTS`]).
pub const MAX_VERTICES: usize = 200_000;
/// Most holes.
pub const MAX_HOLES: usize = 1_000;
/// Largest absolute coordinate (the same bound as `harmonav_transform::MAX_LENGTH`).
pub const MAX_COORDINATE: f64 = 1e9;
/// Relative tolerance: an edge shorter than `GAP_TOLERANCE · diameter` is degenerate, and two
/// rings (or two non-adjacent edges of one ring) closer than that touch.
pub const GAP_TOLERANCE: f64 = 1e-9;

/// Which boundary ring: the outer one or hole `i` (0-based, in the order given).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum RingId {
    /// The outer ring `P_0` (counter-clockwise).
    Outer,
    /// Hole `i` (clockwise).
    Hole(usize),
}

impl std::fmt::Display for RingId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Outer => write!(f, "the outer ring"),
            Self::Hole(i) => write!(f, "hole {i}"),
        }
    }
}

/// Why rings do not form a valid domain. Vertex and edge indices count from 0 in the ring as
/// given (edge `e` joins vertex `e` to vertex `e + 1`, cyclically).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum DomainError {
    /// A ring has fewer than three distinct vertices.
    TooFewVertices {
        /// The ring.
        ring: RingId,
        /// Its vertex count (without a repeated closing vertex).
        count: usize,
    },
    /// A coordinate is NaN or infinite.
    NonFinite {
        /// The ring.
        ring: RingId,
        /// The vertex.
        vertex: usize,
    },
    /// A coordinate exceeds [`MAX_COORDINATE`] in magnitude.
    TooLarge {
        /// The ring.
        ring: RingId,
        /// The vertex.
        vertex: usize,
    },
    /// More than [`MAX_VERTICES`] vertices in all.
    TooManyVertices {
        /// The count.
        count: usize,
        /// The cap.
        max: usize,
    },
    /// More than [`MAX_HOLES`] holes.
    TooManyHoles {
        /// The count.
        count: usize,
        /// The cap.
        max: usize,
    },
    /// An edge is shorter than [`GAP_TOLERANCE`] times the domain's diameter (a repeated vertex).
    DegenerateEdge {
        /// The ring.
        ring: RingId,
        /// The edge.
        edge: usize,
    },
    /// Two edges of one ring cross, touch or overlap (adjacent edges: fold back on each other).
    SelfIntersecting {
        /// The ring.
        ring: RingId,
        /// One edge.
        first: usize,
        /// The other edge.
        second: usize,
    },
    /// A ring runs the wrong way round (or encloses no area).
    WrongOrientation {
        /// The ring.
        ring: RingId,
        /// `true`: it must be counter-clockwise (the outer ring); `false`: clockwise (a hole).
        counter_clockwise: bool,
    },
    /// The boundaries of two rings cross or come closer than [`GAP_TOLERANCE`] × diameter.
    RingsMeet {
        /// One ring.
        first: RingId,
        /// The other ring.
        second: RingId,
    },
    /// A hole lies outside the outer ring.
    HoleOutside {
        /// The hole.
        hole: usize,
    },
    /// A hole lies inside another hole.
    HoleInHole {
        /// The inner hole.
        inner: usize,
        /// The hole around it.
        outer: usize,
    },
}

impl std::fmt::Display for DomainError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::TooFewVertices { ring, count } => {
                write!(
                    f,
                    "{ring} has {count} distinct vertices; at least 3 are needed"
                )
            }
            Self::NonFinite { ring, vertex } => {
                write!(
                    f,
                    "vertex {vertex} of {ring} has a NaN or infinite coordinate"
                )
            }
            Self::TooLarge { ring, vertex } => write!(
                f,
                "vertex {vertex} of {ring} has a coordinate beyond ±{MAX_COORDINATE:e}"
            ),
            Self::TooManyVertices { count, max } => {
                write!(f, "{count} vertices in all; at most {max} are allowed")
            }
            Self::TooManyHoles { count, max } => {
                write!(f, "{count} holes; at most {max} are allowed")
            }
            Self::DegenerateEdge { ring, edge } => {
                write!(f, "edge {edge} of {ring} has (nearly) zero length")
            }
            Self::SelfIntersecting {
                ring,
                first,
                second,
            } => write!(
                f,
                "edges {first} and {second} of {ring} cross, touch or overlap"
            ),
            Self::WrongOrientation {
                ring,
                counter_clockwise,
            } => write!(
                f,
                "{ring} must run {} (or it encloses no area)",
                if *counter_clockwise {
                    "counter-clockwise"
                } else {
                    "clockwise"
                }
            ),
            Self::RingsMeet { first, second } => {
                write!(f, "the boundaries of {first} and {second} cross or touch")
            }
            Self::HoleOutside { hole } => write!(f, "hole {hole} is outside the outer ring"),
            Self::HoleInHole { inner, outer } => {
                write!(f, "hole {inner} lies inside hole {outer}")
            }
        }
    }
}

impl std::error::Error for DomainError {}

/// A valid polygonal domain with polygonal holes (see the module docs for the conditions).
#[derive(Clone, Debug, PartialEq)]
pub struct Domain {
    rings: Vec<Vec<Vector2<f64>>>,
    /// The edges by horizontal band, for [`Domain::contains`].
    bands: Bands,
    diameter: f64,
    lower: Vector2<f64>,
    upper: Vector2<f64>,
}

/// Twice the signed area, `2A = Σ (x_i y_{i+1} − x_{i+1} y_i)` (shoelace), about the first vertex
/// to keep the sum's rounding relative to the ring's size.
fn twice_signed_area(ring: &[Vector2<f64>]) -> f64 {
    let o = ring[0];
    let n = ring.len();
    (0..n)
        .map(|i| {
            let a = ring[i] - o;
            let b = ring[(i + 1) % n] - o;
            a.x * b.y - a.y * b.x
        })
        .sum()
}

/// Distance from `p` to the segment `[a, b]`.
///
/// Overflow guard: `hypot` where `norm` (`√(x² + y²)`) overflows, beyond 1e154 m (`hypot` only
/// there: it is several times slower, and the certificate calls this per cell and element), and
/// a parameter `t` that overflowed to NaN (`∞ − ∞` in the dot product, only for points beyond
/// 1e290 m) taken as 0: from there every point of the segment is equally far to rounding.
pub(crate) fn point_segment_distance(p: Vector2<f64>, a: Vector2<f64>, b: Vector2<f64>) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let d = p - (a + ab * if t.is_nan() { 0.0 } else { t });
    let norm = d.norm();
    if norm.is_finite() {
        norm
    } else {
        d.x.hypot(d.y)
    }
}

/// Distance between the segments `[a, b]` and `[c, d]` (0 when they cross).
fn segment_distance(a: Vector2<f64>, b: Vector2<f64>, c: Vector2<f64>, d: Vector2<f64>) -> f64 {
    let orient = |p: Vector2<f64>, q: Vector2<f64>, r: Vector2<f64>| {
        let u = q - p;
        let v = r - p;
        u.x * v.y - u.y * v.x
    };
    let (o1, o2) = (orient(a, b, c), orient(a, b, d));
    let (o3, o4) = (orient(c, d, a), orient(c, d, b));
    if ((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0))
        && ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0))
    {
        return 0.0;
    }
    point_segment_distance(a, c, d)
        .min(point_segment_distance(b, c, d))
        .min(point_segment_distance(c, a, b))
        .min(point_segment_distance(d, a, b))
}

/// Crossing-number test: is `p` strictly inside the ring (boundary points either way)?
fn ring_contains(ring: &[Vector2<f64>], p: Vector2<f64>) -> bool {
    let n = ring.len();
    let mut inside = false;
    for i in 0..n {
        let a = ring[i];
        let b = ring[(i + 1) % n];
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if p.x < x {
                inside = !inside;
            }
        }
    }
    inside
}

impl Domain {
    /// Validates the outer ring (counter-clockwise) and the holes (clockwise). A ring may repeat
    /// its first vertex at the end (a closed `geo`-style ring); that copy is dropped. Validation
    /// costs `O(V²)` segment tests for `V` vertices (at most [`MAX_VERTICES`]).
    ///
    /// # Errors
    /// The first [`DomainError`] found, in the order: sizes, finite coordinates, edge lengths,
    /// self-intersections, orientation, rings meeting, holes inside the outer ring and apart.
    pub fn new(
        outer: Vec<Vector2<f64>>,
        holes: Vec<Vec<Vector2<f64>>>,
    ) -> Result<Self, DomainError> {
        Self::validated(outer, holes, true)
    }

    /// Whether [`Domain::new`] would accept the rings but for its caps on holes and vertices
    /// ([`MAX_HOLES`], [`MAX_VERTICES`]): the same checks, in the same order, for any number of
    /// rings (a traced map outline before its opening may hold thousands of specks). The cost
    /// is [`Domain::new`]'s: the sweep of the edges sorted by `x` (about `O(V log V)` on a
    /// map's rings, up to `O(V²)` when long edges span many others in `x`) and one point of
    /// each hole against every ring, `O(H·V)`.
    ///
    /// # Errors
    /// [`Domain::new`]'s, but for [`DomainError::TooManyHoles`] and
    /// [`DomainError::TooManyVertices`].
    pub fn check(
        outer: Vec<Vector2<f64>>,
        holes: Vec<Vec<Vector2<f64>>>,
    ) -> Result<(), DomainError> {
        Self::validated(outer, holes, false).map(|_| ())
    }

    /// [`Domain::new`] with (`capped`) or without its caps.
    fn validated(
        outer: Vec<Vector2<f64>>,
        holes: Vec<Vec<Vector2<f64>>>,
        capped: bool,
    ) -> Result<Self, DomainError> {
        if capped && holes.len() > MAX_HOLES {
            return Err(DomainError::TooManyHoles {
                count: holes.len(),
                max: MAX_HOLES,
            });
        }
        let mut rings = Vec::with_capacity(holes.len() + 1);
        rings.push(outer);
        rings.extend(holes);
        let count: usize = rings.iter().map(Vec::len).sum();
        if capped && count > MAX_VERTICES + rings.len() {
            return Err(DomainError::TooManyVertices {
                count,
                max: MAX_VERTICES,
            });
        }
        let id = |r: usize| {
            if r == 0 {
                RingId::Outer
            } else {
                RingId::Hole(r - 1)
            }
        };
        for (r, ring) in rings.iter_mut().enumerate() {
            for (v, p) in ring.iter().enumerate() {
                if !(p.x.is_finite() && p.y.is_finite()) {
                    return Err(DomainError::NonFinite {
                        ring: id(r),
                        vertex: v,
                    });
                }
                if p.x.abs() > MAX_COORDINATE || p.y.abs() > MAX_COORDINATE {
                    return Err(DomainError::TooLarge {
                        ring: id(r),
                        vertex: v,
                    });
                }
            }
            if ring.len() >= 2 && ring.first() == ring.last() {
                ring.pop();
            }
            if ring.len() < 3 {
                return Err(DomainError::TooFewVertices {
                    ring: id(r),
                    count: ring.len(),
                });
            }
        }
        let count: usize = rings.iter().map(Vec::len).sum();
        if capped && count > MAX_VERTICES {
            return Err(DomainError::TooManyVertices {
                count,
                max: MAX_VERTICES,
            });
        }
        let mut lower = rings[0][0];
        let mut upper = rings[0][0];
        for p in rings.iter().flatten() {
            lower = lower.inf(p);
            upper = upper.sup(p);
        }
        let diameter = (upper - lower).norm();
        let tol = GAP_TOLERANCE * diameter;
        for (r, ring) in rings.iter().enumerate() {
            let n = ring.len();
            for e in 0..n {
                if (ring[(e + 1) % n] - ring[e]).norm() <= tol {
                    return Err(DomainError::DegenerateEdge {
                        ring: id(r),
                        edge: e,
                    });
                }
            }
        }
        // Edges with bounding boxes, for the O(V²) pair tests.
        struct Edge {
            ring: usize,
            index: usize,
            a: Vector2<f64>,
            b: Vector2<f64>,
            lo: Vector2<f64>,
            hi: Vector2<f64>,
        }
        let mut edges = Vec::with_capacity(count);
        for (r, ring) in rings.iter().enumerate() {
            let n = ring.len();
            for e in 0..n {
                let (a, b) = (ring[e], ring[(e + 1) % n]);
                edges.push(Edge {
                    ring: r,
                    index: e,
                    a,
                    b,
                    lo: a.inf(&b),
                    hi: a.sup(&b),
                });
            }
        }
        // Sort by the lower x so that the inner loop stops at the first box beyond reach.
        edges.sort_by(|p, q| p.lo.x.total_cmp(&q.lo.x));
        for i in 0..edges.len() {
            let p = &edges[i];
            for q in &edges[i + 1..] {
                if q.lo.x > p.hi.x + tol {
                    break;
                }
                if q.lo.y > p.hi.y + tol || p.lo.y > q.hi.y + tol {
                    continue;
                }
                let (first, second) = if (p.ring, p.index) < (q.ring, q.index) {
                    (p, q)
                } else {
                    (q, p)
                };
                if p.ring == q.ring {
                    let n = rings[p.ring].len();
                    let adjacent_next = (first.index + 1) % n == second.index;
                    let adjacent_prev = (second.index + 1) % n == first.index;
                    let meet = if adjacent_next || adjacent_prev {
                        // Adjacent edges share a vertex: they meet improperly when the far end
                        // of one lies on the other (a fold back, a 360° spike).
                        let (e, f) = if adjacent_next {
                            (first, second)
                        } else {
                            (second, first)
                        };
                        point_segment_distance(f.b, e.a, e.b) <= tol
                            || point_segment_distance(e.a, f.a, f.b) <= tol
                    } else {
                        segment_distance(p.a, p.b, q.a, q.b) <= tol
                    };
                    if meet {
                        return Err(DomainError::SelfIntersecting {
                            ring: id(p.ring),
                            first: first.index,
                            second: second.index,
                        });
                    }
                } else if segment_distance(p.a, p.b, q.a, q.b) <= tol {
                    return Err(DomainError::RingsMeet {
                        first: id(first.ring),
                        second: id(second.ring),
                    });
                }
            }
        }
        for (r, ring) in rings.iter().enumerate() {
            let area = twice_signed_area(ring);
            let ccw = r == 0;
            if (ccw && area <= 0.0) || (!ccw && area >= 0.0) {
                return Err(DomainError::WrongOrientation {
                    ring: id(r),
                    counter_clockwise: ccw,
                });
            }
        }
        // The rings do not meet, so one vertex decides where a whole ring lies.
        for h in 1..rings.len() {
            if !ring_contains(&rings[0], rings[h][0]) {
                return Err(DomainError::HoleOutside { hole: h - 1 });
            }
            for g in 1..rings.len() {
                if g != h && ring_contains(&rings[g], rings[h][0]) {
                    return Err(DomainError::HoleInHole {
                        inner: h - 1,
                        outer: g - 1,
                    });
                }
            }
        }
        Ok(Self {
            bands: Bands::new(&rings),
            rings,
            diameter,
            lower,
            upper,
        })
    }

    /// The outer ring (counter-clockwise, without a repeated closing vertex).
    #[must_use]
    pub fn outer(&self) -> &[Vector2<f64>] {
        &self.rings[0]
    }

    /// The holes (each clockwise, without a repeated closing vertex).
    #[must_use]
    pub fn holes(&self) -> &[Vec<Vector2<f64>>] {
        &self.rings[1..]
    }

    /// The vertices of one ring.
    ///
    /// # Panics
    /// Never for `RingId::Outer`; for `RingId::Hole(i)` with `i ≥` the hole count it panics like
    /// a slice index (use [`Domain::holes`] to iterate).
    #[must_use]
    pub fn ring(&self, ring: RingId) -> &[Vector2<f64>] {
        match ring {
            RingId::Outer => &self.rings[0],
            RingId::Hole(i) => &self.rings[i + 1],
        }
    }

    /// The rings in order: outer first, then the holes.
    pub(crate) fn rings(&self) -> &[Vec<Vector2<f64>>] {
        &self.rings
    }

    /// Diameter of the bounding box, `|upper − lower|`.
    #[must_use]
    pub fn diameter(&self) -> f64 {
        self.diameter
    }

    /// The bounding box `(lower, upper)` of every vertex.
    #[must_use]
    pub fn bounding_box(&self) -> (Vector2<f64>, Vector2<f64>) {
        (self.lower, self.upper)
    }

    /// Area of the free space, `A_0 + Σ_i A_i` (holes have negative signed area).
    #[must_use]
    pub fn area(&self) -> f64 {
        self.rings.iter().map(|r| twice_signed_area(r)).sum::<f64>() / 2.0
    }

    /// Is `p` in the open free space (inside the outer ring, outside every hole)? Points on the
    /// boundary may go either way. The even–odd rule on each ring, testing only the edges of
    /// `p`'s horizontal band (`O(V/B)`, the same answer as every ring's whole test).
    #[must_use]
    pub fn contains(&self, p: Vector2<f64>) -> bool {
        self.bands.contains(&self.rings, p)
    }

    /// Distance from `p` to the nearest boundary edge (any ring), `O(V)`.
    #[must_use]
    pub fn distance_to_boundary(&self, p: Vector2<f64>) -> f64 {
        self.rings
            .iter()
            .flat_map(|ring| {
                let n = ring.len();
                (0..n).map(move |i| point_segment_distance(p, ring[i], ring[(i + 1) % n]))
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Signed distance to the boundary: positive in the free space, negative outside it (in a
    /// hole or beyond the outer ring). It is 1-Lipschitz.
    #[must_use]
    pub fn signed_distance(&self, p: Vector2<f64>) -> f64 {
        let d = self.distance_to_boundary(p);
        if self.contains(p) { d } else { -d }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vector2<f64> {
        Vector2::new(x, y)
    }

    fn square(c: Vector2<f64>, half: f64, ccw: bool) -> Vec<Vector2<f64>> {
        let mut r = vec![
            c + v(-half, -half),
            c + v(half, -half),
            c + v(half, half),
            c + v(-half, half),
        ];
        if !ccw {
            r.reverse();
        }
        r
    }

    fn check(outer: Vec<Vector2<f64>>, holes: Vec<Vec<Vector2<f64>>>, expected: DomainError) {
        assert_eq!(Domain::new(outer, holes), Err(expected));
    }

    #[test]
    fn accepts_a_square_with_a_hole_and_a_closing_vertex() {
        let mut outer = square(v(0.0, 0.0), 1.0, true);
        outer.push(outer[0]);
        let d = Domain::new(outer, vec![square(v(0.0, 0.0), 0.2, false)]).unwrap();
        assert_eq!(d.outer().len(), 4);
        assert!((d.area() - (4.0 - 0.16)).abs() < 1e-14);
        assert!(d.contains(v(0.5, 0.5)) && !d.contains(v(0.0, 0.0)) && !d.contains(v(2.0, 0.0)));
        assert!((d.signed_distance(v(0.5, 0.0)) - 0.3).abs() < 1e-15);
        assert!((d.signed_distance(v(0.0, 0.0)) + 0.2).abs() < 1e-15);
        // Far points: the norm overflowed to ∞ beyond 1e154 m, and the dot product to NaN
        // beyond 1e290 m.
        for far in [v(1e200, 1.0), v(-1e300, 1e300), v(1e308, -1e308)] {
            let r = far.x.hypot(far.y);
            assert!((d.signed_distance(far) / r + 1.0).abs() < 1e-12, "{far:?}");
        }
    }

    /// `check` is `new` without the caps: a room with more pillars than a domain takes passes
    /// it (and `new` names the cap), and the same room with two pillars overlapping fails both
    /// with the same error.
    #[test]
    fn the_check_is_new_without_its_caps() {
        let room = || square(v(0.0, 0.0), 100.0, true);
        let pillars = |n: usize| -> Vec<Vec<Vector2<f64>>> {
            (0..n)
                .map(|i| {
                    let c = v(-90.0 + 2.0 * (i % 80) as f64, -90.0 + 2.0 * (i / 80) as f64);
                    square(c, 0.5, false)
                })
                .collect()
        };
        let many = MAX_HOLES + 200;
        assert!(Domain::check(room(), pillars(many)).is_ok());
        assert_eq!(
            Domain::new(room(), pillars(many)).unwrap_err(),
            DomainError::TooManyHoles {
                count: many,
                max: MAX_HOLES
            }
        );
        let mut overlapping = pillars(many);
        overlapping.push(square(v(-89.5, -89.5), 0.5, false));
        let e = Domain::check(room(), overlapping.clone()).unwrap_err();
        let meet = |second| DomainError::RingsMeet {
            first: RingId::Hole(0),
            second: RingId::Hole(second),
        };
        assert_eq!(e, meet(many));
        overlapping.truncate(3);
        overlapping.push(square(v(-89.5, -89.5), 0.5, false));
        assert_eq!(Domain::new(room(), overlapping).unwrap_err(), meet(3));
    }

    #[test]
    fn names_each_problem() {
        let o = square(v(0.0, 0.0), 1.0, true);
        check(
            vec![v(0.0, 0.0), v(1.0, 0.0)],
            vec![],
            DomainError::TooFewVertices {
                ring: RingId::Outer,
                count: 2,
            },
        );
        check(
            square(v(0.0, 0.0), 1.0, false),
            vec![],
            DomainError::WrongOrientation {
                ring: RingId::Outer,
                counter_clockwise: true,
            },
        );
        check(
            o.clone(),
            vec![square(v(0.0, 0.0), 0.2, true)],
            DomainError::WrongOrientation {
                ring: RingId::Hole(0),
                counter_clockwise: false,
            },
        );
        check(
            o.clone(),
            vec![square(v(3.0, 0.0), 0.2, false)],
            DomainError::HoleOutside { hole: 0 },
        );
        check(
            o.clone(),
            vec![square(v(0.9, 0.0), 0.2, false)],
            DomainError::RingsMeet {
                first: RingId::Outer,
                second: RingId::Hole(0),
            },
        );
        check(
            o.clone(),
            vec![
                square(v(0.0, 0.0), 0.5, false),
                square(v(0.0, 0.0), 0.2, false),
            ],
            DomainError::HoleInHole { inner: 1, outer: 0 },
        );
        check(
            o.clone(),
            vec![
                square(v(0.0, 0.0), 0.3, false),
                square(v(0.5, 0.0), 0.3, false),
            ],
            DomainError::RingsMeet {
                first: RingId::Hole(0),
                second: RingId::Hole(1),
            },
        );
        // A bow tie.
        check(
            vec![v(0.0, 0.0), v(1.0, 1.0), v(1.0, 0.0), v(0.0, 1.0)],
            vec![],
            DomainError::SelfIntersecting {
                ring: RingId::Outer,
                first: 0,
                second: 2,
            },
        );
        // A spike folding back on its edge.
        check(
            vec![v(0.0, 0.0), v(2.0, 0.0), v(1.0, 0.0), v(1.0, 1.0)],
            vec![],
            DomainError::SelfIntersecting {
                ring: RingId::Outer,
                first: 0,
                second: 1,
            },
        );
        check(
            vec![v(0.0, 0.0), v(1.0, 0.0), v(1.0, 0.0), v(0.0, 1.0)],
            vec![],
            DomainError::DegenerateEdge {
                ring: RingId::Outer,
                edge: 1,
            },
        );
        check(
            vec![v(0.0, 0.0), v(f64::NAN, 0.0), v(0.0, 1.0)],
            vec![],
            DomainError::NonFinite {
                ring: RingId::Outer,
                vertex: 1,
            },
        );
        check(
            vec![v(0.0, 0.0), v(1e10, 0.0), v(0.0, 1.0)],
            vec![],
            DomainError::TooLarge {
                ring: RingId::Outer,
                vertex: 1,
            },
        );
        let many: Vec<_> = (0..=MAX_VERTICES)
            .map(|i| {
                let t = i as f64 / (MAX_VERTICES + 1) as f64 * std::f64::consts::TAU;
                v(t.cos(), t.sin())
            })
            .collect();
        check(
            many,
            vec![],
            DomainError::TooManyVertices {
                count: MAX_VERTICES + 1,
                max: MAX_VERTICES,
            },
        );
        for e in [
            DomainError::HoleInHole { inner: 1, outer: 0 },
            DomainError::RingsMeet {
                first: RingId::Outer,
                second: RingId::Hole(2),
            },
        ] {
            assert!(!e.to_string().is_empty());
        }
    }

    /// The banded test answers as every ring's whole even–odd test does, bit for bit: a wavy
    /// outer ring of 400 vertices with 12 square holes, at 20 000 points of its box and at
    /// every vertex and edge midpoint (the rule's ties), and outside the box and at NaN.
    #[test]
    fn the_banded_test_answers_as_the_whole_rings_do() {
        let outer: Vec<Vector2<f64>> = (0..400)
            .map(|i| {
                let t = std::f64::consts::TAU * f64::from(i) / 400.0;
                let r = 10.0 + 1.5 * (7.0 * t).sin() + 0.5 * (23.0 * t).cos();
                v(r * t.cos(), r * t.sin())
            })
            .collect();
        let holes: Vec<Vec<Vector2<f64>>> = (0..12)
            .map(|k| {
                let t = std::f64::consts::TAU * f64::from(k) / 12.0;
                square(v(5.0 * t.cos(), 5.0 * t.sin()), 0.6, false)
            })
            .collect();
        let d = Domain::new(outer, holes).unwrap();
        let whole = |p: Vector2<f64>| {
            ring_contains(&d.rings[0], p) && !d.rings[1..].iter().any(|h| ring_contains(h, p))
        };
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            #[allow(clippy::cast_precision_loss)]
            let u = (seed >> 11) as f64 / (1u64 << 53) as f64;
            u
        };
        let mut points: Vec<Vector2<f64>> = (0..20_000)
            .map(|_| v(-13.0 + 26.0 * next(), -13.0 + 26.0 * next()))
            .collect();
        for ring in &d.rings {
            for (i, &a) in ring.iter().enumerate() {
                points.push(a);
                points.push(0.5 * (a + ring[(i + 1) % ring.len()]));
            }
        }
        points.extend([
            v(0.0, 20.0),
            v(0.0, -20.0),
            v(f64::NAN, 0.0),
            v(0.0, f64::NAN),
        ]);
        let mut inside = 0;
        for p in points {
            assert_eq!(d.contains(p), whole(p), "{p:?}");
            inside += usize::from(whole(p));
        }
        assert!(inside > 5_000, "{inside}");
    }
}
