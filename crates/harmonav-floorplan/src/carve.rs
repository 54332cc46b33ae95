//! Furniture against the walls (issue 52): a sensed obstacle that reaches the boundary layer
//! of a floor plan joins its walls ([`FloorMap::carved`]).
//!
//! A sensed obstacle `O` is taken by `B` only when it and its band lie in the certified region
//! `W_δ` (eq. starroom, [`FloorMap::star_room`]); a table 0.1 m from a wall does not. Its
//! shadow, the gap between it and the wall, is closed to the robot anyway, so the walls take
//! it in: `W_s` loses a polygon `Q` that holds the obstacle, and `H` is solved again on
//!
//! ```text
//! W_s' = the component of W_s \ (Q_1 ∪ … ∪ Q_m) that holds the goal           (eq. wallcut)
//! ```
//!
//! with the same `δ` and the same true walls. Everything of §13 holds on the new floor as it
//! does on any floor plan (its certificate is that of a polygon with holes); its free space is
//! inside the old one (the walls' own vertices are all kept), and the caller
//! chooses each `Q_j` to hold its obstacle grown by `s = max(radius + margin − δ, 0)` for its
//! robot, so that `W_δ' = {sd' ≥ δ}` keeps `radius + margin` from the obstacle as from a wall.
//!
//! **The polygon** ([`enclosing_polygon`]): vertices on rays from the star's centre at equal
//! angles, each edge certified outside the star: at `K` points `m` of the edge, `K` equal parts
//! of length `L/K`, the certified signed distance's lower bound exceeds `L/(2K) + τ`, so every
//! point of the edge is farther than `τ` from the star (the distance is 1-Lipschitz). The star
//! is connected, holds the centre, which the polygon holds, and meets no edge: it lies inside,
//! `τ` from the polygon's boundary. A vertex whose edges fail moves out, each time twice as far,
//! and after 24 times the polygon is the circumscribed one of the bounding disc (certified by
//! `R ≤ R_max`).

use geo::{BooleanOps, Contains, Coord, LineString, MultiPolygon, Point, Polygon};
use harmonav_harmonic::Domain;
use harmonav_transform::StarShape;
use nalgebra::Vector2;
use std::f64::consts::TAU;

use crate::plan::{FloorError, FloorMap, oriented, rings};

/// Points certified on each edge of [`enclosing_polygon`]: the polygon lies about `L/K` beyond
/// the star (`L` its edge length) where a single midpoint would need `L/2`.
const EDGE_POINTS: usize = 8;

/// Fewest vertices of [`enclosing_polygon`].
const MIN_VERTICES: usize = 32;

/// Most vertices of [`enclosing_polygon`] (each adds boundary elements to the solve).
const MAX_VERTICES: usize = 2048;

/// How many times the vertices of failing edges move out (each time twice as far as the last)
/// before the polygon falls back to the bounding disc's.
const MAX_WIDENINGS: usize = 24;

/// How far (relative to the floor's diameter) each cut polygon stays beyond its star: the room
/// that [`FloorMap::carved`]'s clean-up of the difference's near-repeated vertices may take
/// (it moves the boundary by less than this).
const CUT_SLACK: f64 = 1e-6;

/// How near `∂W_s` (relative to the floor's diameter) a vertex of the difference is put back
/// on it: geo's boolean operations round to a grid of about `1e-9` of the plan's size, and the
/// walls would move by that much, some outwards. A cut's own vertices that move by this stay
/// within its slack ([`CUT_SLACK`]).
const SNAP: f64 = 1e-7;

/// A polygon (counter-clockwise, edges at most about `spacing` long) that holds `shape` with
/// every point of its boundary more than `tau` from it (module docs).
#[must_use]
pub fn enclosing_polygon(shape: &StarShape, spacing: f64, tau: f64) -> Vec<Vector2<f64>> {
    let c = shape.centre();
    let r_max = shape.radius_bounds().1;
    let n = ((TAU * (r_max + tau) / spacing).ceil() as usize).clamp(MIN_VERTICES, MAX_VERTICES);
    let step = TAU / n as f64;
    let dirs: Vec<Vector2<f64>> = (0..n)
        .map(|i| {
            let t = step * i as f64;
            Vector2::new(t.cos(), t.sin())
        })
        .collect();
    // The chord between vertices at radius ρ/cos(Δ/2) keeps ρ from the centre; the rest is
    // the edge's certified room.
    let stretch = 1.0 / (0.5 * step).cos();
    let chord = stretch * (r_max + tau) * step;
    let lift = chord / EDGE_POINTS as f64 + tau;
    let mut radii: Vec<f64> = dirs
        .iter()
        .map(|&u| stretch * (shape.radius_along(u).0 + lift))
        .collect();
    let outside = |a: Vector2<f64>, b: Vector2<f64>| {
        let part = (b - a).norm() / EDGE_POINTS as f64;
        (0..EDGE_POINTS).all(|k| {
            let m = a + (b - a) * ((k as f64 + 0.5) / EDGE_POINTS as f64);
            shape.signed_distance_bounds(m).0 > 0.5 * part + tau
        })
    };
    // Each widening moves a failing edge's ends out by twice the last one's step.
    let mut steps = vec![lift; n];
    for _ in 0..MAX_WIDENINGS {
        let vertex = |i: usize| c + radii[i] * dirs[i];
        let failing: Vec<usize> = (0..n)
            .filter(|&i| !outside(vertex(i), vertex((i + 1) % n)))
            .collect();
        if failing.is_empty() {
            return (0..n).map(vertex).collect();
        }
        let mut moved = vec![false; n];
        for i in failing {
            for k in [i, (i + 1) % n] {
                if !moved[k] {
                    moved[k] = true;
                    radii[k] += steps[k];
                    steps[k] *= 2.0;
                }
            }
        }
    }
    // R ≤ R_max: the circumscribed polygon of the disc of radius R_max + 2τ.
    let rho = stretch * (r_max + 2.0 * tau);
    dirs.iter().map(|&u| c + rho * u).collect()
}

/// A ring as geo's closed line string.
fn line(ring: &[Vector2<f64>]) -> LineString<f64> {
    ring.iter()
        .chain(ring.first())
        .map(|p| Coord { x: p.x, y: p.y })
        .collect()
}

/// A geo ring (closed) of the difference as a ring of distinct vertices: each vertex within
/// `SNAP · diameter` of `∂W_s` put back on it ([`FloorMap::snapped`]), then each of the
/// difference's own vertices within `tol` of its neighbour dropped (its near-repeats, which
/// [`Domain::new`] would call degenerate edges; a cut's boundary moves by less than `tol`).
fn vertices(floor: &FloorMap, ring: &LineString<f64>, tol: f64) -> Vec<Vector2<f64>> {
    let snap = SNAP * floor.domain().diameter();
    // Each vertex with whether it is one of `∂W_s`'s own, which is never dropped: dropping a
    // reflex corner of the walls would move them outwards (by up to `tol`), and the walls have
    // no slack for it; the difference's own vertices lie on the cuts, which have.
    let mut out: Vec<(Vector2<f64>, bool)> = Vec::with_capacity(ring.0.len());
    let closed = ring.0.len().saturating_sub(1);
    for p in &ring.0[..closed] {
        let (v, own) = floor.snapped(Vector2::new(p.x, p.y), snap);
        match out.last_mut() {
            // Two of the walls' own are both kept; an own one takes the place of one of the
            // difference's; one of the difference's near another vertex goes.
            Some(last) if (v - last.0).norm() <= tol && !(own && last.1) => {
                if own {
                    *last = (v, own);
                }
            }
            _ => out.push((v, own)),
        }
    }
    while out.len() > 1 {
        let (first, last) = (out[0], out[out.len() - 1]);
        if (last.0 - first.0).norm() > tol || (first.1 && last.1) {
            break;
        }
        if last.1 {
            out[0] = last;
        }
        out.pop();
    }
    out.into_iter().map(|(v, _)| v).collect()
}

impl FloorMap {
    /// The same floor with the stars `cuts` joined to its walls (eq. wallcut, module docs):
    /// `W_s` less a polygon holding each cut ([`enclosing_polygon`], edges at most `δ/2`), the
    /// component that holds `goal`, `H` solved again on it with the same `δ`, shrink and true
    /// walls. Each cut must hold its obstacle grown by `max(radius + margin − δ, 0)` for `W_δ`
    /// to keep `radius + margin` from it. `H`'s far field is
    /// [`harmonav_harmonic::HarmonicMap::new`]'s choice.
    ///
    /// # Errors
    /// [`FloorError::CutOff`] when the goal is not in what is left; [`FloorError::Domain`]
    /// when the rings left are not a valid polygon with holes; [`FloorError::Solve`].
    pub fn carved(&self, cuts: &[StarShape], goal: Vector2<f64>) -> Result<FloorMap, FloorError> {
        let domain = self.domain();
        let tol = CUT_SLACK * domain.diameter();
        let mut rings = rings(domain);
        let outer = line(rings.next().unwrap_or_default());
        let free = Polygon::new(outer, rings.map(line).collect());
        let polygons: Vec<Polygon<f64>> = cuts
            .iter()
            .map(|s| {
                let ring = enclosing_polygon(s, 0.5 * self.delta(), 2.0 * tol);
                Polygon::new(line(&ring), Vec::new())
            })
            .collect();
        let left = free.difference(&MultiPolygon::new(polygons));
        let g = Point::new(goal.x, goal.y);
        let part = left
            .0
            .into_iter()
            .find(|p| p.contains(&g))
            .ok_or(FloorError::CutOff { what: "goal" })?;
        let outer = oriented(vertices(self, part.exterior(), tol), true);
        let holes = part
            .interiors()
            .iter()
            .map(|r| oriented(vertices(self, r, tol), false))
            .collect();
        let cut = Domain::new(outer, holes)?;
        FloorMap::solved(
            self.walls().clone(),
            &cut,
            self.delta(),
            self.shrink(),
            self.clearance_asked(),
            self.centre_policy(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::FloorOptions;

    /// The polygon holds a wavy star with every boundary point more than `τ` from it: checked
    /// at 20 000 points of the star's boundary against the polygon (geo's containment and the
    /// distance to its edges), and its edges are no longer than asked (to the lift).
    #[test]
    fn the_enclosing_polygon_holds_the_star() {
        let star =
            StarShape::fourier_star(Vector2::new(1.0, -2.0), 0.5, &[(5, 0.08, 0.03)]).unwrap();
        let tau = 1e-4;
        let ring = enclosing_polygon(&star, 0.05, tau);
        let poly = Polygon::new(line(&ring), Vec::new());
        let n = ring.len();
        for i in 0..20_000 {
            let t = TAU * i as f64 / 20_000.0;
            let p = star.boundary_point(t);
            assert!(poly.contains(&Point::new(p.x, p.y)), "point {i} outside");
            let d = (0..n)
                .map(|j| segment_distance(p, ring[j], ring[(j + 1) % n]))
                .fold(f64::INFINITY, f64::min);
            assert!(d > tau, "point {i} within {d} of the polygon");
        }
        let longest = (0..n)
            .map(|j| (ring[(j + 1) % n] - ring[j]).norm())
            .fold(0.0, f64::max);
        assert!(longest < 0.06, "longest edge {longest}");
    }

    /// The negative control: the polygon through the star's own boundary points at the same
    /// angles (what the certificate replaces) cuts the star between its vertices.
    #[test]
    fn the_polygon_through_boundary_points_cuts_the_star() {
        let star = StarShape::circle(Vector2::zeros(), 0.5).unwrap();
        let n = 64;
        let ring: Vec<Vector2<f64>> = (0..n)
            .map(|i| star.boundary_point(TAU * i as f64 / n as f64))
            .collect();
        let poly = Polygon::new(line(&ring), Vec::new());
        let mid = star.boundary_point(TAU * 0.5 / n as f64);
        assert!(!poly.contains(&Point::new(mid.x, mid.y)));
        let certified = enclosing_polygon(&star, 0.5 * TAU / n as f64, 0.0);
        let poly = Polygon::new(line(&certified), Vec::new());
        assert!(poly.contains(&Point::new(mid.x, mid.y)));
    }

    fn segment_distance(p: Vector2<f64>, a: Vector2<f64>, b: Vector2<f64>) -> f64 {
        let e = b - a;
        let t = ((p - a).dot(&e) / e.norm_squared()).clamp(0.0, 1.0);
        (a + t * e - p).norm()
    }

    /// The walls' own vertices are kept, however near each other: an L room shrunk by a
    /// micrometre has the shrink's arc pieces at its reflex corner a fraction of a micrometre
    /// long, below the clean-up's tolerance (`10⁻⁶·diam`). Away from the cut, every vertex of
    /// the carved floor lies on `∂W_s` and every vertex of `∂W_s` on the carved floor's
    /// boundary (geo drops only collinear ones), to rounding. Dropping the reflex corner's
    /// pieces, as the clean-up did before it told the walls' vertices apart, moved the wall
    /// outwards by 3.7e-7 m here.
    #[test]
    fn the_walls_own_vertices_are_kept_however_near() {
        let v = Vector2::new;
        let room = vec![
            v(0.0, 0.0),
            v(6.0, 0.0),
            v(6.0, 2.0),
            v(2.0, 2.0),
            v(2.0, 6.0),
            v(0.0, 6.0),
        ];
        let floor = FloorMap::new(room, vec![], &FloorOptions::new(0.1, 0.1 + 1e-6)).unwrap();
        let ring = floor.domain().outer().to_vec();
        let n = ring.len();
        let tol = CUT_SLACK * floor.domain().diameter();
        let short = (0..n)
            .filter(|&i| (ring[(i + 1) % n] - ring[i]).norm() < tol)
            .count();
        assert!(
            short > 0,
            "no edge below the tolerance: the test shows nothing"
        );
        let cut = StarShape::circle(v(4.5, 0.5), 0.35).unwrap();
        let carved = floor.carved(&[cut], v(1.0, 5.0)).unwrap();
        let away = |p: &&Vector2<f64>| (*p - v(4.5, 0.5)).norm() > 1.0;
        for q in carved.domain().outer().iter().filter(away) {
            assert!(
                floor.signed_distance(*q).abs() < 1e-12,
                "{q:?} off the walls"
            );
        }
        for p in ring.iter().filter(away) {
            let sd = carved.signed_distance(*p);
            assert!(sd.abs() < 1e-12, "{p:?} is {sd:e} from the carved walls");
        }
    }

    /// A 6 × 4 m room with a disc 0.1 m from its south wall: the carved floor keeps the goal,
    /// loses the disc and the gap behind it (a point in the gap is outside the new `W_s`), and
    /// every point of the disc grown by the shrink is outside it; the rest of the room is as
    /// before far from the disc.
    #[test]
    fn a_disc_near_a_wall_is_carved_out_with_its_gap() {
        let v = Vector2::new;
        let room = vec![v(0.0, 0.0), v(6.0, 0.0), v(6.0, 4.0), v(0.0, 4.0)];
        let floor = FloorMap::new(room, vec![], &FloorOptions::new(0.1, 0.2)).unwrap();
        let s = floor.shrink();
        let disc = StarShape::circle(v(3.0, 0.6), 0.5).unwrap();
        let cut = disc.offset(s).unwrap();
        let goal = v(5.0, 3.0);
        let carved = floor.carved(std::slice::from_ref(&cut), goal).unwrap();
        assert!(carved.signed_distance(goal) > 0.5);
        // The gap between the disc (reaching y = 0.1) and the wall.
        assert!(carved.signed_distance(v(3.0, 0.05)) < 0.0);
        assert!(floor.signed_distance(v(3.0, 0.2)) > 0.0);
        for i in 0..720 {
            let p = cut.boundary_point(TAU * i as f64 / 720.0);
            assert!(
                carved.signed_distance(p) < 0.0,
                "grown disc point {i} left free"
            );
        }
        let far = v(1.0, 3.0);
        let (a, b) = (carved.signed_distance(far), floor.signed_distance(far));
        assert!(
            (a - b).abs() < 1e-12,
            "{a} {b} {:?} {:?}",
            carved.domain().outer(),
            floor.domain().outer()
        );
        assert_eq!(carved.delta(), floor.delta());
        // A goal inside the cut is cut off.
        assert!(matches!(
            floor.carved(&[cut], v(3.0, 0.6)),
            Err(FloorError::CutOff { what: "goal" })
        ));
    }
}
