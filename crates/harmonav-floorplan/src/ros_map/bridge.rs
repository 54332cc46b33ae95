//! Walls that the shrink would join, joined first (issue 52).
//!
//! [`crate::FloorMap::new`] shrinks the free space by `s = radius + margin − δ`, offsetting
//! each ring on its own, and refuses rings that come to cross or touch. The robot-disc opening
//! does not keep two walls `2s` apart: the corners of two pillars one pixel apart diagonally
//! (0.07 m at 0.05 m/px, every SLAM map has them) are reached by the disc from both sides, so
//! both stay, and shrunk by `s` = 0.05 m each they overlap ("the boundaries of hole 37 and hole
//! 38 cross or touch", on outlines the pipeline produced itself). The free space shrunk by `s`
//! has joined them anyway; here they are joined before the shrink, by the convex hull of the
//! walls within `reach` of the gap, so that the rings handed to `FloorMap::new` keep apart.
//!
//! Walls only grow (the hull is taken out of the free space), so it is conservative: every point
//! the robot's centre may take after it could be taken before. What it costs is the free
//! space within `s + δ` of a hull, which lies within `reach` of a gap narrower than `2s`.

use std::collections::HashMap;

use geo::{BooleanOps, ConvexHull, Coord, LineString, MultiPolygon, Point, Polygon};

use super::outline::containing;

/// Rounds of joining: a hull can come near a third wall, which the next round joins.
pub(crate) const ROUNDS: usize = 8;

/// The sides of the polygon standing for the disc of radius `reach` about a gap.
const DISC_SIDES: usize = 32;

/// A segment of a ring: the ring's index and the ends.
type Piece = (usize, Coord<f64>, Coord<f64>);

/// Where two different rings of `poly` come within `gap` of each other: the midpoints of the
/// shortest segments from a vertex of one ring to the other ring, thinned so that no two lie
/// within `spacing` of each other.
pub(crate) fn close_spots(poly: &Polygon<f64>, gap: f64, spacing: f64) -> Vec<Coord<f64>> {
    let rings: Vec<&LineString<f64>> = std::iter::once(poly.exterior())
        .chain(poly.interiors())
        .collect();
    // Segments bucketed on a grid of cells `gap` wide: a vertex's neighbours within `gap` lie
    // in its cell's 3 × 3 block.
    let cell = gap.max(f64::MIN_POSITIVE);
    let key = |c: Coord<f64>| ((c.x / cell).floor() as i64, (c.y / cell).floor() as i64);
    let mut grid: HashMap<(i64, i64), Vec<Piece>> = HashMap::new();
    for (r, ring) in rings.iter().enumerate() {
        for line in ring.lines() {
            let (lo, hi) = (
                key(Coord {
                    x: line.start.x.min(line.end.x),
                    y: line.start.y.min(line.end.y),
                }),
                key(Coord {
                    x: line.start.x.max(line.end.x),
                    y: line.start.y.max(line.end.y),
                }),
            );
            for i in lo.0..=hi.0 {
                for j in lo.1..=hi.1 {
                    grid.entry((i, j))
                        .or_default()
                        .push((r, line.start, line.end));
                }
            }
        }
    }
    let mut spots: Vec<Coord<f64>> = Vec::new();
    for (r, ring) in rings.iter().enumerate() {
        for &v in ring.coords() {
            let (ci, cj) = key(v);
            let mut best: Option<(f64, Coord<f64>)> = None;
            for i in ci - 1..=ci + 1 {
                for j in cj - 1..=cj + 1 {
                    for &(other, a, b) in grid.get(&(i, j)).into_iter().flatten() {
                        if other == r {
                            continue;
                        }
                        let q = nearest_on_segment(v, a, b);
                        let d = (q.x - v.x).hypot(q.y - v.y);
                        if d < gap && best.is_none_or(|(bd, _)| d < bd) {
                            best = Some((d, q));
                        }
                    }
                }
            }
            if let Some((_, q)) = best {
                let m = Coord {
                    x: 0.5 * (v.x + q.x),
                    y: 0.5 * (v.y + q.y),
                };
                if spots
                    .iter()
                    .all(|s| (s.x - m.x).hypot(s.y - m.y) >= spacing)
                {
                    spots.push(m);
                }
            }
        }
    }
    spots
}

/// The point of the segment `ab` nearest to `p`.
fn nearest_on_segment(p: Coord<f64>, a: Coord<f64>, b: Coord<f64>) -> Coord<f64> {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p.x - a.x) * dx + (p.y - a.y) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    Coord {
        x: a.x + t * dx,
        y: a.y + t * dy,
    }
}

/// `poly` with the walls within `reach` of each of `spots` joined: the convex hull of the
/// complement of `opened` (`poly` opened by the robot's disc, where the spots were found)
/// within a disc of radius `reach` about a spot is taken out of `poly`, and the part holding
/// `goal` kept (`None` if none does). The hull is of the opened walls, not of `poly`'s: a gap
/// may lie between walls that the opening grew (an arc of the disc about a corner it cannot
/// enter), and a hull of `poly`'s walls alone leaves it open round after round (`willow-full`
/// with every speck kept: the same spot for all [`ROUNDS`]).
pub(crate) fn join_at(
    poly: &Polygon<f64>,
    opened: &Polygon<f64>,
    spots: &[Coord<f64>],
    reach: f64,
    goal: Point<f64>,
) -> Option<Polygon<f64>> {
    let mut hulls = MultiPolygon::new(Vec::new());
    for m in spots {
        let disc = Polygon::new(
            LineString::from(
                (0..DISC_SIDES)
                    .map(|k| {
                        let t = std::f64::consts::TAU * k as f64 / DISC_SIDES as f64;
                        (m.x + reach * t.cos(), m.y + reach * t.sin())
                    })
                    .collect::<Vec<_>>(),
            ),
            Vec::new(),
        );
        let walls = disc.difference(opened);
        if !walls.0.is_empty() {
            hulls = hulls.union(&walls.convex_hull());
        }
    }
    containing(poly.difference(&hulls), goal)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x: f64, y: f64, side: f64) -> LineString<f64> {
        LineString::from(vec![
            (x, y),
            (x, y + side),
            (x + side, y + side),
            (x + side, y),
            (x, y),
        ])
    }

    /// Two pillars whose corners are 0.07 m apart diagonally, in a 4 m room: the gap is found
    /// and joined, and the pillars become one hole; a gap of 0.3 m is not found.
    #[test]
    fn diagonal_corners_are_joined_and_wide_gaps_kept() {
        let outer = square(0.0, 0.0, 4.0);
        let close = Polygon::new(
            outer.clone(),
            vec![square(1.0, 1.0, 0.5), square(1.55, 1.55, 0.5)],
        );
        let spots = close_spots(&close, 0.125, 0.1);
        assert_eq!(spots.len(), 1);
        let joined = join_at(&close, &close, &spots, 0.2, Point::new(3.5, 3.5)).unwrap();
        assert_eq!(joined.interiors().len(), 1, "{joined:?}");
        assert!(close_spots(&joined, 0.125, 0.1).is_empty());
        let apart = Polygon::new(outer, vec![square(1.0, 1.0, 0.5), square(1.8, 1.8, 0.5)]);
        assert!(close_spots(&apart, 0.125, 0.1).is_empty());
    }
}
