//! The certified clearance `d(x)` in a star world: a lower bound on the distance from `x` to
//! the nearest known grown obstacle and to the shrunk boundary, from certified distance bounds
//! ([`StarShape::signed_distance_bounds`]); the ball `B(x, d(x))` lies in the free space. And
//! the way out of the blind layer where that bound cannot prove a free point free. The hold
//! (`hold.rs`) and the star world's [`crate::space`] rest on it; it rests on nothing of theirs.

use harmonav_transform::{Lookup, StarShape, Workspace};
use nalgebra::Vector2;

/// Where a recovering robot is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Band {
    /// In the margin band of known obstacle `i` (indices in the order of
    /// [`crate::Navigator::add_obstacle`]).
    Obstacle(usize),
    /// In the margin band along the workspace boundary.
    Boundary,
}

/// A certified lower bound on the signed distance from `x` to `shape` (negative inside):
/// [`StarShape::signed_distance_bounds`].
pub(crate) fn lower(shape: &StarShape, x: Vector2<f64>) -> f64 {
    shape.signed_distance_bounds(x).0
}

/// A certified upper bound on the signed distance from `x` to `shape`.
fn upper(shape: &StarShape, x: Vector2<f64>) -> f64 {
    shape.signed_distance_bounds(x).1
}

/// The certified clearance `d(x)`, clipped at `need`: `min(need, d̲(x))` with `d̲(x)` a lower
/// bound on the distance from `x` to every grown obstacle of `ws` (but `except`) and to its
/// boundary. A shape is queried exactly only when its bounding disc could come within `need`
/// (`|x − c| − max R` for an obstacle, `min R − |x − c|` inside the boundary, both exact
/// lower bounds), so the usual far-from-everything call costs a few multiplications a shape.
pub(crate) fn clearance(ws: &Workspace, x: Vector2<f64>, need: f64, except: Option<Band>) -> f64 {
    let mut best = need;
    if except != Some(Band::Boundary) {
        let b = ws.boundary();
        let cheap = b.radius_bounds().0 - (x - b.centre()).norm();
        if cheap < best {
            best = best.min(-upper(b, x));
        }
    }
    let mut buf = [0; CANDIDATES];
    let list = candidates(ws, x, best, &mut buf);
    for i in list.map_or(Either::All(0..ws.obstacles().len()), Either::Some) {
        if except == Some(Band::Obstacle(i)) {
            continue;
        }
        let o = &ws.obstacles()[i];
        let cheap = (x - o.centre()).norm() - o.radius_bounds().1;
        if cheap < best {
            best = best.min(lower(o, x));
        }
    }
    best
}

/// At most this many obstacles are taken from the index for one query (a buffer on the
/// stack: the hold allocates nothing); with more the query loops over all of them.
pub const CANDIDATES: usize = 64;

/// The obstacles of `ws` whose bounding disc comes within `reach` of `x`, ascending, from the
/// workspace's index (`Lookup::Indexed`); `None` with `Lookup::Direct`, with fewer than
/// `INDEX_MIN` obstacles, for an infinite
/// `reach` or more than [`CANDIDATES`] of them. A loop over them in this order meets the
/// obstacles that the direct loop `0..M` does anything with (those with `|x − c| − max R`
/// below a bound that only decreases from `reach`), in the same order: the same answer, bit for
/// bit (docs/maths.md §14).
fn candidates<'a>(
    ws: &Workspace,
    x: Vector2<f64>,
    reach: f64,
    buf: &'a mut [usize; CANDIDATES],
) -> Option<std::iter::Copied<std::slice::Iter<'a, usize>>> {
    let small = ws.obstacles().len() < harmonav_transform::index::INDEX_MIN;
    if ws.lookup() != Lookup::Indexed || small || !reach.is_finite() {
        return None;
    }
    let mut n = 0;
    ws.index().near(x, reach, |i| {
        if n < CANDIDATES {
            buf[n] = i;
        }
        n += 1;
    });
    if n > CANDIDATES {
        return None;
    }
    buf[..n].sort_unstable();
    Some(buf[..n].iter().copied())
}

/// The obstacles a query visits: all, or the index's candidates.
enum Either<I> {
    All(std::ops::Range<usize>),
    Some(I),
}

impl<I: Iterator<Item = usize>> Iterator for Either<I> {
    type Item = usize;
    fn next(&mut self) -> Option<usize> {
        match self {
            Self::All(r) => r.next(),
            Self::Some(i) => i.next(),
        }
    }
}

/// A certified clearance at or below this (m) cannot carry a step: the tracing stops, and the
/// hold leads out of the blind layer ([`crate::Mode::Recovering`]) instead.
pub const BLIND: f64 = 1e-12;

/// The unit direction `u` of the ray from `shape`'s centre through `x`, and `ρ = |x − c|`;
/// `None` at the centre (or for a NaN `x`), where the ray is undefined.
pub(crate) fn ray(shape: &StarShape, x: Vector2<f64>) -> Option<(Vector2<f64>, f64)> {
    let radial = x - shape.centre();
    let rho = radial.norm();
    (rho > 0.0).then(|| (radial / rho, rho))
}

/// The width of the layer along a shape in which its certified distance bounds cannot prove
/// a free point free: twice the certified width `τ` of [`StarShape::signed_distance_bounds`]
/// plus its rounding allowance (`64ε` of the coordinates' size, twice).
pub(crate) fn blind_layer(shape: &StarShape, x: Vector2<f64>) -> f64 {
    let size = x.amax() + shape.centre().amax() + shape.radius_bounds().1;
    2.0 * shape.distance_tolerance() + 256.0 * f64::EPSILON * size
}

/// The way out of the blind layer: at a free point `x` where the certified clearance is not
/// positive (within [`blind_layer`] of a shape that is not a circle, whose distance bounds are
/// `τ` wide), the shape with the lowest bound is the one in the way. Every shape is star-shaped
/// about its centre `c`, so the ray from `c` through `x` (towards `c` for the boundary) moves
/// away from it: its points beyond `x` are outside the obstacle (inside the boundary), exactly,
/// by the radial function. Returns that shape, the unit direction and the length to go: the
/// layer's width, at most half the certified clearance from every other shape, and at most
/// `most`.
pub(crate) fn blind_exit(
    ws: &Workspace,
    x: Vector2<f64>,
    most: f64,
) -> Option<(Band, Vector2<f64>, f64)> {
    let mut worst = (Band::Boundary, -upper(ws.boundary(), x));
    let mut buf = [0; CANDIDATES];
    let list = candidates(ws, x, worst.1, &mut buf);
    for i in list.map_or(Either::All(0..ws.obstacles().len()), Either::Some) {
        let o = &ws.obstacles()[i];
        let cheap = (x - o.centre()).norm() - o.radius_bounds().1;
        if cheap < worst.1 {
            let d = lower(o, x);
            if d < worst.1 {
                worst = (Band::Obstacle(i), d);
            }
        }
    }
    let (band, shape, outward) = match worst.0 {
        Band::Obstacle(i) => (worst.0, &ws.obstacles()[i], true),
        Band::Boundary => (worst.0, ws.boundary(), false),
    };
    let (u, _) = ray(shape, x)?;
    let dir = if outward { u } else { -u };
    let others = clearance(ws, x, 2.0 * most, Some(band)).max(0.0);
    let length = blind_layer(shape, x).min(0.5 * others).min(most);
    (length > 0.0).then_some((band, dir, length))
}

#[cfg(test)]
mod index_tests {
    use super::*;
    use harmonav_transform::random::{self, Kind, Rng};

    /// The certified clearance and the blind layer's way out from the index's candidates equal
    /// the direct loop's, bit for bit, on seeded worlds of many obstacles, for the short reaches
    /// of the sphere tracing and the unbounded one of `Navigator::clearance`.
    #[test]
    fn indexed_clearance_equals_the_direct_loop() {
        let kinds = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
        for seed in 0..3 {
            let mut rng = Rng::new(40 + seed);
            let w = random::scattered(&mut rng, 20.0, 150, &kinds, 0.2).unwrap();
            let make = |lookup| {
                Workspace::with_lookup(w.boundary.clone(), w.obstacles.clone(), w.goal, lookup)
                    .unwrap()
            };
            let (direct, indexed) = (make(Lookup::Direct), make(Lookup::Indexed));
            let mut near = 0;
            for n in 0..4000 {
                let x = if n % 2 == 0 {
                    let o = &w.obstacles[rng.below(w.obstacles.len())];
                    let r = o.radius_bounds().1;
                    let a = rng.uniform(0.0, 6.3);
                    o.centre() + rng.uniform(0.5 * r, 1.5 * r) * Vector2::new(a.cos(), a.sin())
                } else {
                    rng.point(20.0)
                };
                for need in [1e-3, 0.05, 0.5, 3.0, f64::INFINITY] {
                    let except = (n % 5 == 0).then_some(Band::Obstacle(n % 150));
                    let (a, b) = (
                        clearance(&direct, x, need, except),
                        clearance(&indexed, x, need, except),
                    );
                    assert_eq!(a.to_bits(), b.to_bits(), "seed {seed}, {x:?}, need {need}");
                    near += usize::from(a < need && a > 0.0);
                }
                assert_eq!(
                    blind_exit(&direct, x, 0.1),
                    blind_exit(&indexed, x, 0.1),
                    "{x:?}"
                );
            }
            assert!(near > 1000, "seed {seed}: {near} answers below the reach");
        }
    }
}
