//! The free component's outline: marching squares (`contour`), the topology-preserving
//! simplification and the robot-disc opening (`geo`). Everything here is in the map's own
//! frame: metres from the lower-left corner of the image, `x` along the columns, `y` up.

use contour::ContourBuilder;
use geo::orient::{Direction, Orient};
use geo::{
    Area, BooleanOps, BoundingRect, Buffer, Contains, Coord, LineString, MultiPolygon, Point,
    Polygon, SimplifyVwPreserve, Validation,
};

/// How many times the simplification is retried with half the tolerance when its result is not
/// a valid polygon (geo's Visvalingam–Whyatt variant preserves the topology of each ring but
/// does not promise a valid polygon); after that the outline is kept unsimplified.
const SIMPLIFY_RETRIES: usize = 64;

/// The outline of the `true` pixels of `mask` (`width × height`, row 0 at the top): marching
/// squares at level ½ on the 0/1 indicator sampled at the pixel centres, with a one-pixel
/// occupied border so every ring closes. Pixel (column `c`, row `r`) covers
/// `[c·res, (c+1)·res] × [(height−1−r)·res, (height−r)·res]` (map_server: row 0 is the top).
/// The rings run along the pixel edges, except at corners: a convex corner of the free pixels
/// is cut by the diagonal (−1/8 pixel), a concave one filled (+1/8). Diagonal-only neighbours
/// are apart (contour's saddle rule separates the high corners), which matches the free pixels'
/// 4-connectivity.
pub(crate) fn trace(
    mask: &[bool],
    width: usize,
    height: usize,
    res: f64,
) -> Result<MultiPolygon<f64>, String> {
    let (w, h) = (width + 2, height + 2);
    let mut values = vec![0.0; w * h];
    for (i, _) in mask.iter().enumerate().filter(|(_, f)| **f) {
        let (c, r) = (i % width, i / width);
        // Grid row j counts upward from the padded bottom row.
        let j = height - r;
        values[j * w + c + 1] = 1.0;
    }
    let contours = ContourBuilder::new(w, h, false)
        .x_origin(-res)
        .y_origin(-res)
        .x_step(res)
        .y_step(res)
        .contours(&values, &[0.5])
        .map_err(|e| format!("marching squares: {e:?}"))?;
    let mut out = Vec::new();
    for c in contours {
        out.extend(c.into_inner().0);
    }
    Ok(MultiPolygon(out))
}

/// The polygon of `mp` that contains `p`, if any.
pub(crate) fn containing(mp: MultiPolygon<f64>, p: Point<f64>) -> Option<Polygon<f64>> {
    mp.0.into_iter().find(|poly| poly.contains(&p))
}

/// Visvalingam–Whyatt with topology preservation (geo's `SimplifyVwPreserve`): a vertex is
/// removed while the triangle it makes with its neighbours has an area below `epsilon` (m²),
/// each removal changing the enclosed area by that triangle's area, so
/// `|ΔA| ≤ (vertices removed)·epsilon`. Holes that would end with fewer than 3 distinct
/// vertices are kept as they were.
///
/// The tolerance is an upper bound: while the result is not a valid polygon, or moves the
/// outline by more than `max_moved` ([`moved`]: some vertex of `poly` farther than that from
/// the simplified walls), it is halved (at most [`SIMPLIFY_RETRIES`] times; a tolerance far
/// beyond the map's size comes down to the largest one that keeps the polygon valid and
/// close), then the polygon is returned unsimplified. A removed vertex lies within its
/// triangle's height `2·area/base` of the new edge, unbounded for a short base (a one-pixel
/// speck's ring at ½ px² moved 1.28 px on `fetch-office`), hence the check.
pub(crate) fn simplify(poly: &Polygon<f64>, epsilon: f64, max_moved: f64) -> Polygon<f64> {
    // No triangle of three vertices is larger than half the bounding box: a larger tolerance
    // (`1e300`) removes no more, so the halving starts from there.
    let bound = poly
        .bounding_rect()
        .map_or(0.0, |r| 0.5 * r.width() * r.height());
    let mut eps = epsilon.min(bound);
    for _ in 0..=SIMPLIFY_RETRIES {
        if eps <= 0.0 {
            break;
        }
        let s = poly.simplify_vw_preserve(eps);
        if s.interiors().len() == poly.interiors().len()
            && moved(poly, &s) <= max_moved
            && valid(&s)
        {
            return s;
        }
        eps *= 0.5;
    }
    poly.clone()
}

/// Whether `poly` is a valid polygon (geo's `Validation`). [`harmonav_harmonic::Domain::check`]
/// decides first: it accepts only what geo accepts (no ring crosses or touches itself or
/// another, to `GAP_TOLERANCE` of the diameter; every hole inside the outer ring and outside
/// the others), in one sweep of the edges sorted by `x`, where geo's check compares every pair
/// of edges of a ring (0.4–0.6 s of `fetch-office`'s and `willow-2010`'s outlines, 0.9 s of
/// `willow-full`'s traced one with its 1 298 specks; docs/benchmarks.md, "Set-up of the large
/// maps"). What it refuses, geo decides: rings that touch at a point or come within the gap
/// tolerance (geo allows both). The answer is therefore geo's.
fn valid(poly: &Polygon<f64>) -> bool {
    use harmonav_harmonic::domain::Domain;
    use nalgebra::Vector2;
    let (outer, holes) = rings(poly);
    let ring = |r: Vec<Coord<f64>>| r.into_iter().map(|c| Vector2::new(c.x, c.y)).collect();
    Domain::check(ring(outer), holes.into_iter().map(ring).collect()).is_ok() || poly.is_valid()
}

/// Why the opening failed.
#[derive(Debug)]
pub(crate) enum Cut {
    /// The goal is closer than `rho` to the walls.
    Goal,
    /// The start is not in the goal's component of the eroded free space.
    Start,
}

/// The opening of `poly` by a disc of radius `rho`, restricted to the goal's component:
///
/// ```text
/// C = component of (poly ⊖ rho) holding the goal,    open = (C ⊕ rho) ∩ poly
/// ```
///
/// `C` is where the robot's centre may go (every point of it has clearance `rho`); `open` is
/// the area its disc sweeps, so it leaves out the dead-end slits, the gaps between a pillar and
/// a wall, and the corners that no disc of radius `rho` reaches (walls only grow; the
/// intersection keeps the polygonal arcs of the two buffers inside `poly`). Holes that the
/// robot cannot pass around merge into the outer ring. `geo::Buffer` with round joins.
pub(crate) fn open(
    poly: &Polygon<f64>,
    rho: f64,
    goal: Point<f64>,
    start: Point<f64>,
) -> Result<Polygon<f64>, Cut> {
    let eroded = poly.buffer(-rho);
    let c = containing(eroded, goal).ok_or(Cut::Goal)?;
    if !c.contains(&start) {
        return Err(Cut::Start);
    }
    let swept = c.buffer(rho);
    let open = swept.intersection(poly);
    // The goal's part (the intersection may leave slivers elsewhere, never the goal's).
    let part = containing(open, goal).ok_or(Cut::Goal)?;
    Ok(part)
}

/// How far the simplification moved the outline: the largest distance from a vertex of
/// `before` to the boundary of `after` (every vertex of `after` is one of `before`'s, so this
/// is the one-sided Hausdorff distance that matters), m. Each vertex asks parry's polyline of
/// `after`'s edges (its BVH), so the cost is `O(V log V)`, not the `O(V²)` of comparing every
/// vertex with every ring (issue 56, D3: a map of 26 000 pillars took hours).
pub(crate) fn moved(before: &Polygon<f64>, after: &Polygon<f64>) -> f64 {
    use parry2d_f64::math::Vector as PVector;
    use parry2d_f64::query::PointQuery;
    use parry2d_f64::shape::Polyline;
    let mut vertices = Vec::new();
    let mut indices = Vec::new();
    for ring in std::iter::once(after.exterior()).chain(after.interiors()) {
        for line in ring.lines() {
            let i = u32::try_from(vertices.len()).unwrap_or(u32::MAX);
            vertices.push(PVector::new(line.start.x, line.start.y));
            vertices.push(PVector::new(line.end.x, line.end.y));
            indices.push([i, i + 1]);
        }
    }
    if indices.is_empty() {
        return f64::INFINITY;
    }
    let edges = Polyline::new(vertices, Some(indices));
    before
        .exterior()
        .coords()
        .chain(before.interiors().iter().flat_map(|r| r.coords()))
        .map(|c| edges.distance_to_local_point(PVector::new(c.x, c.y), false))
        .fold(0.0, f64::max)
}

/// The rings of `poly` as [`crate::FloorMap::new`] takes them: the outer ring
/// counter-clockwise, each hole clockwise (geo's `orient`), without the repeated closing vertex.
pub(crate) fn rings(poly: &Polygon<f64>) -> (Vec<Coord<f64>>, Vec<Vec<Coord<f64>>>) {
    let p = poly.orient(Direction::Default);
    let open = |ls: &LineString<f64>| {
        let mut v = ls.0.clone();
        if v.len() > 1 && v.first() == v.last() {
            v.pop();
        }
        v
    };
    (open(p.exterior()), p.interiors().iter().map(open).collect())
}

/// The enclosed area (holes subtracted), m².
pub(crate) fn area(poly: &Polygon<f64>) -> f64 {
    poly.unsigned_area()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One free pixel in a 3 × 3 image: a diamond about the centre pixel's centre, half a
    /// pixel across each way, area ½ pixel.
    #[test]
    fn one_pixel_is_a_diamond_about_its_centre() {
        let mut mask = vec![false; 9];
        mask[4] = true;
        let mp = trace(&mask, 3, 3, 1.0).unwrap();
        assert_eq!(mp.0.len(), 1);
        let poly = &mp.0[0];
        assert!((poly.unsigned_area() - 0.5).abs() < 1e-12);
        for c in &poly.exterior().0 {
            assert!((c.x - 1.5).abs() + (c.y - 1.5).abs() - 0.5 < 1e-12, "{c:?}");
        }
    }

    /// The top-left pixel lands at the top left (high y).
    #[test]
    fn row_zero_is_the_top() {
        let mut mask = vec![false; 6]; // 3 wide, 2 high
        mask[0] = true;
        let mp = trace(&mask, 3, 2, 0.5).unwrap();
        let c = geo::Centroid::centroid(&mp.0[0]).unwrap();
        assert!((c.x() - 0.25).abs() < 1e-12 && (c.y() - 0.75).abs() < 1e-12);
    }

    /// A spike on a short base (0.4 × 1.3 px, area 0.26 px²) goes at a tolerance of ½ px²
    /// and moves the wall by 1.3 px (the control, with no bound); bounded by one pixel, the
    /// tolerance is lowered until the spike stays.
    #[test]
    fn the_simplification_keeps_the_walls_within_its_bound() {
        let ring: Vec<(f64, f64)> = vec![
            (0.0, 0.0),
            (10.0, 0.0),
            (10.0, 10.0),
            (5.2, 10.0),
            (5.0, 11.3),
            (4.8, 10.0),
            (0.0, 10.0),
        ];
        let poly = Polygon::new(LineString::from(ring), vec![]);
        let free = simplify(&poly, 0.5, f64::INFINITY);
        assert!((moved(&poly, &free) - 1.3).abs() < 1e-9, "{free:?}");
        let bounded = simplify(&poly, 0.5, 1.0);
        assert!(moved(&poly, &bounded) <= 1.0, "{bounded:?}");
        assert_eq!(bounded.exterior().0.len(), poly.exterior().0.len());
    }

    /// The validity test answers as geo's: two holes touching at a corner are valid (the
    /// domain refuses them, geo decides), crossing holes and a bow-tie are not, and a plain
    /// room with a pillar is (the domain decides).
    #[test]
    fn validity_is_geos_with_the_domain_first() {
        let square = |x: f64, y: f64, s: f64| {
            LineString::from(vec![(x, y), (x + s, y), (x + s, y + s), (x, y + s)])
        };
        let room = |holes: Vec<LineString<f64>>| Polygon::new(square(0.0, 0.0, 10.0), holes);
        let cases = [
            (room(vec![square(2.0, 2.0, 1.0)]), true),
            (
                room(vec![square(2.0, 2.0, 1.0), square(3.0, 3.0, 1.0)]),
                true,
            ),
            (
                room(vec![square(2.0, 2.0, 1.0), square(2.5, 2.5, 1.0)]),
                false,
            ),
            (
                Polygon::new(
                    LineString::from(vec![(0.0, 0.0), (10.0, 10.0), (10.0, 0.0), (0.0, 10.0)]),
                    vec![],
                ),
                false,
            ),
        ];
        for (poly, expected) in cases {
            assert_eq!(poly.is_valid(), expected, "geo: {poly:?}");
            assert_eq!(valid(&poly), expected, "{poly:?}");
        }
    }
}
