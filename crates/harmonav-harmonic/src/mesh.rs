//! Boundary elements: every polygon edge cut into straight elements, graded toward its ends.
//!
//! **Grading.** On an edge of length `L`, at distance `d` (along the edge) from its nearer end,
//! the target element length is
//!
//! ```text
//! g(d) = min(h_e, h₀ + γ·d),    h₀ = f·h_e,    h_e = min(h, gap_e),
//! ```
//!
//! `h` the largest element length, `f` the corner fraction, `γ` the grading slope (element
//! lengths grow geometrically away from a corner, ratio ≈ `1 + γ`) and `gap_e` the edge's
//! distance to every non-adjacent edge that faces it across the free space (so a narrow
//! passage gets elements no longer than its width).
//!
//! **Facing.** The free space is on the left of every edge, so two edges bound a passage
//! between them only if each has a point strictly on the other's left; an edge wholly on the
//! other's right or on its line (the next pieces of a polyline arc about a wall's corner, the
//! steps of a pixel staircase, the far side of a thin wall, a collinear edge) is behind it, with
//! no free space between them to resolve. Until 2026-12-06 every non-adjacent edge counted: on
//! the shrunk outline of a ROS map, whose wall corners are circumscribed arcs of 22.5° pieces a
//! few millimetres long, each arc piece took the next-but-one as a "passage" as wide as itself
//! and was cut into about five elements (174 000 on `willow-2010` against 30 000 now). The edge gets `n = ⌈I⌉` elements, `I = ∫₀ᴸ dt / g(min(t, L − t))`, and node `i` sits
//! where `∫₀ᵗ dt/g = i·I/n` (closed form: `∫₀ᵈ dt/(h₀ + γt) = ln(1 + γd/h₀)/γ`). Folds of the
//! discrete map sit within about half an element of the boundary (notes §4), so grading
//! narrows the fold layer at corners, where the density is singular.

use nalgebra::Vector2;

use crate::domain::{Domain, RingId, point_segment_distance};

/// Most boundary elements: the dense system takes `8 (N + M + 1)²` bytes (200 MB at the cap).
pub const MAX_ELEMENTS: usize = 200_000;

/// How the boundary is cut into elements (see the module docs for `g(d)`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshOptions {
    /// Largest element length `h`, in the domain's units (> 0).
    pub max_element: f64,
    /// Corner fraction `f ∈ (0, 1]`: the target length at a vertex is `h₀ = f·h_e` (the first
    /// element is `h₀(e^γ − 1)/γ ≈ 1.3 h₀` long for `γ = ½`; `f = 1`: uniform).
    pub corner_fraction: f64,
    /// Grading slope `γ ∈ (0, 4]`: the target length grows by `γ` per unit distance from a corner.
    pub grading: f64,
}

impl MeshOptions {
    /// Uniform elements of length at most `h` (`f = 1`).
    #[must_use]
    pub fn uniform(max_element: f64) -> Self {
        Self {
            max_element,
            corner_fraction: 1.0,
            grading: 1.0,
        }
    }

    /// Elements graded toward every vertex: `f = 1/8`, `γ = 1/2` (ratio ≈ 1.5 between
    /// neighbours near a corner), about `2·ln(1 + γ(1 − f)h/(f h))/γ ≈ 2·3.1` elements more per
    /// edge than uniform ones.
    #[must_use]
    pub fn graded(max_element: f64) -> Self {
        Self {
            max_element,
            corner_fraction: 0.125,
            grading: 0.5,
        }
    }
}

/// Why a mesh cannot be built.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum MeshError {
    /// A [`MeshOptions`] field is out of its range (`name` is the field).
    InvalidOption {
        /// The field.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// The options would give more than [`MAX_ELEMENTS`] elements.
    TooManyElements {
        /// The count they would give (saturated at `usize::MAX`).
        elements: usize,
        /// The cap.
        max: usize,
    },
}

impl std::fmt::Display for MeshError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::InvalidOption { name, value } => {
                write!(f, "mesh option `{name}` = {value:e} is out of range")
            }
            Self::TooManyElements { elements, max } => write!(
                f,
                "the mesh would have {elements} boundary elements, more than the {max} allowed \
                 (about 1 GB); a larger max_element or fewer wall vertices give fewer"
            ),
        }
    }
}

impl std::error::Error for MeshError {}

/// One straight boundary element `E_j = [a, b]`, oriented along its ring (so the free space is
/// on its left).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Element {
    /// Start point.
    pub a: Vector2<f64>,
    /// End point.
    pub b: Vector2<f64>,
    /// The ring it lies on.
    pub ring: RingId,
}

impl Element {
    /// Midpoint `c_j` (the collocation point).
    #[must_use]
    pub fn midpoint(&self) -> Vector2<f64> {
        (self.a + self.b) * 0.5
    }

    /// Length `|E_j|`.
    #[must_use]
    pub fn length(&self) -> f64 {
        (self.b - self.a).norm()
    }
}

/// `∫₀ᵈ dt / g(t)` on one half of an edge (see the module docs).
struct Grading {
    h0: f64,
    h: f64,
    gamma: f64,
    /// `d*`: where `h₀ + γd` reaches `h`.
    knee: f64,
    /// `F(d*)`.
    knee_value: f64,
}

impl Grading {
    fn new(h: f64, fraction: f64, gamma: f64) -> Self {
        let h0 = fraction * h;
        let knee = (h - h0) / gamma;
        Self {
            h0,
            h,
            gamma,
            knee,
            knee_value: (1.0 + gamma * knee / h0).ln() / gamma,
        }
    }

    fn integral(&self, d: f64) -> f64 {
        if d <= self.knee {
            (1.0 + self.gamma * d / self.h0).ln() / self.gamma
        } else {
            self.knee_value + (d - self.knee) / self.h
        }
    }

    fn inverse(&self, f: f64) -> f64 {
        if f <= self.knee_value {
            self.h0 * (self.gamma * f).exp_m1() / self.gamma
        } else {
            self.knee + (f - self.knee_value) * self.h
        }
    }
}

fn validate(options: &MeshOptions, diameter: f64) -> Result<(), MeshError> {
    let MeshOptions {
        max_element,
        corner_fraction,
        grading,
    } = *options;
    // An element below 1e-12 of the diameter is below the rounding of its own end points.
    if !(max_element.is_finite() && max_element > 1e-12 * diameter) {
        return Err(MeshError::InvalidOption {
            name: "max_element",
            value: max_element,
        });
    }
    if !(corner_fraction > 0.0 && corner_fraction <= 1.0) {
        return Err(MeshError::InvalidOption {
            name: "corner_fraction",
            value: corner_fraction,
        });
    }
    if !(grading > 0.0 && grading <= 4.0) {
        return Err(MeshError::InvalidOption {
            name: "grading",
            value: grading,
        });
    }
    Ok(())
}

/// Whether the edges `[a, b]` and `[c, d]` (free space on the left of each) face each other: a
/// point of each strictly on the other's left (the side tests are linear, so the end points
/// decide). Every passage of free space between two edges has this; see the module docs.
fn facing(a: Vector2<f64>, b: Vector2<f64>, c: Vector2<f64>, d: Vector2<f64>) -> bool {
    let left = |p: Vector2<f64>, q: Vector2<f64>, x: Vector2<f64>| {
        let (u, w) = (q - p, x - p);
        u.x * w.y - u.y * w.x > 0.0
    };
    (left(a, b, c) || left(a, b, d)) && (left(c, d, a) || left(c, d, b))
}

/// Each edge's distance to the nearest non-adjacent edge that faces it ([`facing`]), as far as
/// it matters: the mesh uses
/// `min(h, gap_e)`, so only edges within `h` count, and a farther one is reported as `∞` (or
/// as its own distance; either leaves `min(h, gap_e)` unchanged). The lower bound of the
/// segment distance used is the four end-point distances (segments of valid rings do not
/// cross). A uniform grid of cells at least `h` wide finds the candidates: `O(E·k)` for `k`
/// edges near each, where the all-pairs loop before it cost `O(E²)` (4·10⁸ pairs at 20 000
/// vertices). Every pair whose bounding boxes come within `h` is tested, so the result is the
/// all-pairs one bit for bit.
fn gaps(
    edges: &[(usize, usize, Vector2<f64>, Vector2<f64>)],
    rings: &[Vec<Vector2<f64>>],
    h: f64,
) -> Vec<f64> {
    let mut lo = Vector2::new(f64::INFINITY, f64::INFINITY);
    let mut hi = -lo;
    for &(_, _, a, b) in edges {
        lo = lo.inf(&a.inf(&b));
        hi = hi.sup(&a.sup(&b));
    }
    let extent = (hi - lo).max();
    // Cells at least h wide, and at most about 4·10⁶ of them.
    let cell = h.max(extent / 2048.0).max(f64::MIN_POSITIVE);
    let cols = ((hi.x - lo.x) / cell).floor() as usize + 1;
    let rows = ((hi.y - lo.y) / cell).floor() as usize + 1;
    let index = |p: Vector2<f64>| -> (usize, usize) {
        (
            (((p.x - lo.x) / cell).max(0.0) as usize).min(cols - 1),
            (((p.y - lo.y) / cell).max(0.0) as usize).min(rows - 1),
        )
    };
    let mut start = vec![0u32; cols * rows + 1];
    let boxes: Vec<((usize, usize), (usize, usize))> = edges
        .iter()
        .map(|&(_, _, a, b)| (index(a.inf(&b)), index(a.sup(&b))))
        .collect();
    for &((x0, y0), (x1, y1)) in &boxes {
        for y in y0..=y1 {
            for x in x0..=x1 {
                start[y * cols + x + 1] += 1;
            }
        }
    }
    for i in 0..cols * rows {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut members = vec![0u32; start[cols * rows] as usize];
    for (k, &((x0, y0), (x1, y1))) in boxes.iter().enumerate() {
        for y in y0..=y1 {
            for x in x0..=x1 {
                let c = y * cols + x;
                members[fill[c] as usize] = k as u32;
                fill[c] += 1;
            }
        }
    }
    let mut seen = vec![u32::MAX; edges.len()];
    edges
        .iter()
        .enumerate()
        .map(|(k, &(r, e, a, b))| {
            let n = rings[r].len();
            let pad = Vector2::new(h, h);
            let (x0, y0) = index(a.inf(&b) - pad);
            let (x1, y1) = index(a.sup(&b) + pad);
            let mut gap = f64::INFINITY;
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let c = y * cols + x;
                    for &m in &members[start[c] as usize..start[c + 1] as usize] {
                        if seen[m as usize] == k as u32 {
                            continue;
                        }
                        seen[m as usize] = k as u32;
                        let (r2, e2, c2, d2) = edges[m as usize];
                        let adjacent =
                            r2 == r && (e2 == e || (e2 + 1) % n == e || (e + 1) % n == e2);
                        if !adjacent && facing(a, b, c2, d2) {
                            let g = point_segment_distance(a, c2, d2)
                                .min(point_segment_distance(b, c2, d2))
                                .min(point_segment_distance(c2, a, b))
                                .min(point_segment_distance(d2, a, b));
                            gap = gap.min(g);
                        }
                    }
                }
            }
            gap
        })
        .collect()
}

/// Cuts every edge of `domain` into elements, ring by ring (outer first), in ring order.
///
/// # Errors
/// [`MeshError::InvalidOption`] for an option out of range; [`MeshError::TooManyElements`]
/// when the count would pass [`MAX_ELEMENTS`] (the whole count, checked before the elements
/// are allocated).
pub fn mesh(domain: &Domain, options: &MeshOptions) -> Result<Vec<Element>, MeshError> {
    validate(options, domain.diameter())?;
    let rings = domain.rings();
    // Every edge: its ring, end points and the distance to every non-adjacent edge.
    let mut edges = Vec::new();
    for (r, ring) in rings.iter().enumerate() {
        let n = ring.len();
        for e in 0..n {
            edges.push((r, e, ring[e], ring[(e + 1) % n]));
        }
    }
    let gaps = gaps(&edges, rings, options.max_element);
    let mut plans = Vec::with_capacity(edges.len());
    let mut total = 0.0_f64;
    for (&(_, _, a, b), &gap) in edges.iter().zip(&gaps) {
        let h = options.max_element.min(gap);
        let grading = Grading::new(h, options.corner_fraction, options.grading);
        let length = (b - a).norm();
        let half = grading.integral(length / 2.0);
        let count = (2.0 * half - 1e-9).ceil().max(1.0);
        total += count;
        plans.push((grading, count, half));
    }
    // The whole count, not a partial one: the message names it.
    if total.is_nan() || total > MAX_ELEMENTS as f64 {
        return Err(MeshError::TooManyElements {
            elements: if total.is_finite() && total < usize::MAX as f64 {
                total as usize
            } else {
                usize::MAX
            },
            max: MAX_ELEMENTS,
        });
    }
    let plans: Vec<(Grading, usize, f64)> = plans
        .into_iter()
        .map(|(g, count, half)| (g, count as usize, half))
        .collect();
    let mut elements = Vec::with_capacity(total as usize);
    for (&(r, _, a, b), (grading, count, half)) in edges.iter().zip(plans) {
        let ring = if r == 0 {
            RingId::Outer
        } else {
            RingId::Hole(r - 1)
        };
        let length = (b - a).norm();
        let node = |i: usize| -> Vector2<f64> {
            if i == 0 {
                return a;
            }
            if i == count {
                return b;
            }
            let f = 2.0 * half * i as f64 / count as f64;
            let t = if f <= half {
                grading.inverse(f)
            } else {
                length - grading.inverse(2.0 * half - f)
            };
            a + (b - a) * (t / length)
        };
        let mut start = a;
        for i in 1..=count {
            let end = node(i);
            elements.push(Element {
                a: start,
                b: end,
                ring,
            });
            start = end;
        }
    }
    Ok(elements)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Domain {
        let v = Vector2::new;
        Domain::new(
            vec![v(-1.0, -1.0), v(1.0, -1.0), v(1.0, 1.0), v(-1.0, 1.0)],
            vec![vec![v(-0.2, -0.2), v(-0.2, 0.2), v(0.2, 0.2), v(0.2, -0.2)]],
        )
        .unwrap()
    }

    #[test]
    fn uniform_elements_cover_each_edge_exactly() {
        let m = mesh(&square(), &MeshOptions::uniform(0.1)).unwrap();
        assert_eq!(m.len(), 4 * 20 + 4 * 4);
        for e in &m {
            assert!((e.length() - 0.1).abs() < 1e-12, "{}", e.length());
        }
        let outer: f64 = m
            .iter()
            .filter(|e| e.ring == RingId::Outer)
            .map(Element::length)
            .sum();
        assert!((outer - 8.0).abs() < 1e-12);
        // Consecutive elements join.
        for w in m.windows(2) {
            if w[0].ring == w[1].ring {
                assert_eq!(w[0].b, w[1].a);
            }
        }
    }

    #[test]
    fn graded_elements_shrink_toward_corners_and_stay_below_h() {
        let m = mesh(&square(), &MeshOptions::graded(0.1)).unwrap();
        // The first element spans one unit of ∫dt/g, so it is h₀(e^γ − 1)/γ ≈ 1.3 h₀ long.
        let first = m[0].length();
        let expected = 0.0125 * 0.5_f64.exp_m1() / 0.5;
        assert!((first - expected).abs() < 0.1 * expected, "{first}");
        for e in &m {
            assert!(e.length() <= 0.1 + 1e-12);
        }
        // Neighbours differ by at most the grading ratio (plus rounding to whole elements).
        for w in m.windows(2) {
            if w[0].ring == w[1].ring {
                let r = w[0].length() / w[1].length();
                assert!((1.0 / 1.8..1.8).contains(&r), "{r}");
            }
        }
    }

    /// A narrow slot of free space (two walls facing each other 0.05 apart) still gets elements
    /// no longer than its width, while a pillar's circumscribed polyline arc (pieces 0.02 long,
    /// each 0.02 from the next-but-one, with the wall behind them) and a thin wall's two sides
    /// (back to back, 0.01 apart) are not refined below their own lengths and `h`.
    #[test]
    fn only_edges_facing_across_the_free_space_narrow_the_elements() {
        let v = Vector2::new;
        let h = 0.2;
        // A 4 × 4 room whose bottom wall has a slot 0.05 wide and 1 deep, a 16-gon pillar of
        // radius 0.05 (pieces 0.0196 long) and a wall 2 long and 0.01 thick.
        let outer = vec![
            v(-2.0, -2.0),
            v(0.0, -2.0),
            v(0.0, -3.0),
            v(0.05, -3.0),
            v(0.05, -2.0),
            v(2.0, -2.0),
            v(2.0, 2.0),
            v(-2.0, 2.0),
        ];
        let pillar: Vec<_> = (0..16)
            .rev()
            .map(|k| {
                let t = std::f64::consts::TAU * f64::from(k) / 16.0;
                v(-1.0 + 0.05 * t.cos(), 1.0 + 0.05 * t.sin())
            })
            .collect();
        let wall = vec![v(-1.0, 0.0), v(-1.0, 0.01), v(1.0, 0.01), v(1.0, 0.0)];
        let d = Domain::new(outer, vec![pillar, wall]).unwrap();
        let m = mesh(&d, &MeshOptions::uniform(h)).unwrap();
        let inside = |e: &Element, x0: f64, x1: f64, y0: f64, y1: f64| {
            let c = e.midpoint();
            (x0..=x1).contains(&c.x) && (y0..=y1).contains(&c.y)
        };
        // The slot's sides (x = 0 and x = 0.05, y in (−3, −2)): at most its width.
        let slot: Vec<_> = m
            .iter()
            .filter(|e| e.ring == RingId::Outer && inside(e, -0.01, 0.06, -2.95, -2.05))
            .collect();
        assert!(!slot.is_empty());
        assert!(slot.iter().all(|e| e.length() <= 0.05 + 1e-12));
        // The pillar: one element per piece (uniform, each piece shorter than h).
        let pillar = m.iter().filter(|e| e.ring == RingId::Hole(0)).count();
        assert_eq!(pillar, 16);
        // The thin wall's long sides: h-long elements, not 0.01.
        let sides: Vec<_> = m
            .iter()
            .filter(|e| e.ring == RingId::Hole(1) && (e.b - e.a).x.abs() > 0.0)
            .collect();
        assert!(sides.iter().all(|e| e.length() > 0.1), "{sides:?}");
        // The facing test itself: antiparallel walls across free space face; a wall and the
        // one behind it, or the next-but-one piece of an arc about a wall, do not.
        assert!(facing(v(0.0, 0.0), v(1.0, 0.0), v(1.0, 0.1), v(0.0, 0.1)));
        assert!(!facing(
            v(0.0, 0.0),
            v(1.0, 0.0),
            v(0.0, -0.1),
            v(1.0, -0.1)
        ));
        assert!(!facing(v(0.0, 0.1), v(1.0, 0.1), v(1.0, 0.0), v(0.0, 0.0)));
        assert!(!facing(v(0.0, 0.0), v(1.0, 0.0), v(2.0, 0.0), v(3.0, 0.0)));
    }

    #[test]
    fn rejects_bad_options_and_too_many_elements() {
        let d = square();
        let bad = |o: MeshOptions, name: &'static str| match mesh(&d, &o) {
            Err(MeshError::InvalidOption { name: n, .. }) => assert_eq!(n, name),
            other => panic!("{other:?}"),
        };
        bad(MeshOptions::uniform(f64::NAN), "max_element");
        bad(MeshOptions::uniform(0.0), "max_element");
        bad(
            MeshOptions {
                corner_fraction: 0.0,
                ..MeshOptions::graded(0.1)
            },
            "corner_fraction",
        );
        bad(
            MeshOptions {
                grading: f64::INFINITY,
                ..MeshOptions::graded(0.1)
            },
            "grading",
        );
        assert!(matches!(
            mesh(&d, &MeshOptions::uniform(1e-6)),
            Err(MeshError::TooManyElements {
                max: MAX_ELEMENTS,
                ..
            })
        ));
    }
}
