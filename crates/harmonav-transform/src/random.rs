//! Seeded random valid workspaces of mixed shapes, for property tests, `cargo xtask verify`
//! and benchmarks (deterministic: the same seed gives the same workspace everywhere).

use std::f64::consts::TAU;

use nalgebra::Vector2;

use crate::shape::StarShape;
use crate::workspace::Workspace;

/// SplitMix64 (Steele, Lea & Flood 2014): a small, fast, seedable generator.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator with the given seed.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `0..n`.
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// Uniform in the square `[-extent, extent]²`.
    pub fn point(&mut self, extent: f64) -> Vector2<f64> {
        Vector2::new(self.uniform(-extent, extent), self.uniform(-extent, extent))
    }
}

/// The four obstacle shapes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A disc.
    Circle,
    /// An ellipse.
    Ellipse,
    /// A rounded, possibly non-convex star-shaped polygon.
    Polygon,
    /// A Fourier star.
    Star,
}

/// A random shape of kind `kind` and size about `size` centred at `c`.
pub fn shape(rng: &mut Rng, kind: Kind, c: Vector2<f64>, size: f64) -> StarShape {
    loop {
        let s = match kind {
            Kind::Circle => StarShape::circle(c, size * rng.uniform(0.7, 1.0)),
            Kind::Ellipse => {
                let a = size * rng.uniform(0.7, 1.0);
                StarShape::ellipse(c, [a, a * rng.uniform(0.4, 1.0)], rng.uniform(0.0, TAU))
            }
            Kind::Polygon => {
                let n = 3 + rng.below(5);
                let phase = rng.uniform(0.0, TAU);
                let v: Vec<_> = (0..n)
                    .map(|i| {
                        let a = phase + TAU * (i as f64 + rng.uniform(-0.2, 0.2)) / n as f64;
                        c + size * rng.uniform(0.6, 1.0) * Vector2::new(a.cos(), a.sin())
                    })
                    .collect();
                StarShape::rounded_polygon(&v, size * rng.uniform(0.05, 0.2))
            }
            Kind::Star => {
                let h: Vec<_> = (0..1 + rng.below(3))
                    .map(|_| {
                        (
                            1 + rng.below(5) as u32,
                            size * rng.uniform(-0.12, 0.12),
                            size * rng.uniform(-0.12, 0.12),
                        )
                    })
                    .collect();
                StarShape::fourier_star(c, size * rng.uniform(0.7, 1.0), &h)
            }
        };
        if let Ok(s) = s {
            return s;
        }
    }
}

/// The outer boundary shapes (circle, ellipse, rounded polygon, star) of radius about `r`.
pub fn boundary(rng: &mut Rng, kind: Kind, r: f64) -> StarShape {
    let c = Vector2::zeros();
    match kind {
        Kind::Circle => StarShape::circle(c, r).expect("valid circle"),
        Kind::Ellipse => {
            StarShape::ellipse(c, [r * 1.1, r * 0.9], rng.uniform(0.0, TAU)).expect("valid ellipse")
        }
        Kind::Polygon => {
            let v: Vec<_> = (0..6)
                .map(|i| {
                    r * 1.1
                        * Vector2::new((TAU * i as f64 / 6.0).cos(), (TAU * i as f64 / 6.0).sin())
                })
                .collect();
            StarShape::rounded_polygon(&v, 0.3 * r).expect("valid hexagon")
        }
        Kind::Star => StarShape::fourier_star(c, r, &[(3, 0.06 * r, 0.0), (5, 0.0, 0.03 * r)])
            .expect("valid star"),
    }
}

/// A random valid workspace: boundary of radius ≈ 5 of kind `outer`, `m` obstacles of sizes
/// 0.3–0.8 and random kinds from `kinds`, at least `gap` apart and from the boundary, and a
/// destination at least 0.2 from everything.
pub fn workspace(rng: &mut Rng, m: usize, kinds: &[Kind], outer: Kind, gap: f64) -> Workspace {
    loop {
        let b = boundary(rng, outer, 5.0);
        let mut obstacles: Vec<StarShape> = Vec::with_capacity(m);
        let mut tries = 0;
        while obstacles.len() < m && tries < 2000 {
            tries += 1;
            let c = rng.point(4.0);
            let kind = kinds[rng.below(kinds.len())];
            let size = rng.uniform(0.3, 0.8);
            let o = shape(rng, kind, c, size);
            if o.clearance_inside(&b) > gap
                && obstacles
                    .iter()
                    .all(|p| apart(p, &o, gap) && !p.contains(c) && !o.contains(p.centre()))
            {
                obstacles.push(o);
            }
        }
        if obstacles.len() < m {
            continue;
        }
        for _ in 0..1000 {
            let d = rng.point(4.5);
            let clear = -b.coarse_signed_distance(d) > 0.2
                && obstacles.iter().all(|o| o.coarse_signed_distance(d) > 0.2);
            if let (true, Ok(ws)) = (clear, Workspace::new(b.clone(), obstacles.clone(), d)) {
                return ws;
            }
        }
    }
}

/// A large random world ([`scattered`]): a disc boundary, obstacles, a start and a goal.
#[derive(Clone, Debug)]
pub struct Scattered {
    /// The outer boundary, a disc of the requested radius about the origin.
    pub boundary: StarShape,
    /// The obstacles, at least the requested gap apart and from the boundary.
    pub obstacles: Vec<StarShape>,
    /// `(−0.8 R, 0.013 R)`: off the axis through the goal (off a saddle's stable manifold).
    pub start: Vector2<f64>,
    /// `(0.8 R, 0)`.
    pub goal: Vector2<f64>,
}

/// A random world of `m` obstacles in a disc of radius `radius` (the building-sized worlds of
/// the many-obstacle benchmarks and tests): sizes 0.3–0.8 and random kinds from `kinds`,
/// at least `gap` apart and from the boundary, none within 1 of the start or the goal. A
/// candidate is tested only against the obstacles of the neighbouring cells of a uniform grid,
/// so 1 000 obstacles take milliseconds, not the `O(M²)` pair tests of [`workspace`]. `None` if
/// fewer than `m` fit in `200·m` tries (the disc is too small for them).
pub fn scattered(
    rng: &mut Rng,
    radius: f64,
    m: usize,
    kinds: &[Kind],
    gap: f64,
) -> Option<Scattered> {
    let boundary = StarShape::circle(Vector2::zeros(), radius).ok()?;
    let (start, goal) = (
        Vector2::new(-0.8 * radius, 0.013 * radius),
        Vector2::new(0.8 * radius, 0.0),
    );
    // A star of size 0.8 reaches at most 0.8·(1 + 3·0.17) < 1.25 from its centre, so two
    // obstacles more than a cell apart (2·1.25 + gap) are apart by more than `gap`.
    let cell = 2.5 + gap;
    let n = (2.0 * radius / cell).ceil().max(1.0) as usize;
    let slot = |p: Vector2<f64>| {
        let f = |v: f64| (((v + radius) / cell).floor().max(0.0) as usize).min(n - 1);
        (f(p.x), f(p.y))
    };
    let mut grid: Vec<Vec<usize>> = vec![Vec::new(); n * n];
    let mut obstacles: Vec<StarShape> = Vec::with_capacity(m);
    let mut tries = 0;
    while obstacles.len() < m {
        tries += 1;
        if tries > 200 * m.max(1) {
            return None;
        }
        let c = rng.point(radius);
        let kind = kinds[rng.below(kinds.len())];
        let size = rng.uniform(0.3, 0.8);
        if c.norm() + 1.25 + gap >= radius || (c - start).norm() < 2.25 || (c - goal).norm() < 2.25
        {
            continue;
        }
        let o = shape(rng, kind, c, size);
        let (i, j) = slot(c);
        let near = (i.saturating_sub(1)..=(i + 1).min(n - 1))
            .flat_map(|a| (j.saturating_sub(1)..=(j + 1).min(n - 1)).map(move |b| a * n + b));
        let clear = o.clearance_inside(&boundary) > gap
            && near.into_iter().all(|g| {
                grid[g].iter().all(|&q| {
                    let p = &obstacles[q];
                    apart(p, &o, gap) && !p.contains(c) && !o.contains(p.centre())
                })
            });
        if clear {
            grid[i * n + j].push(obstacles.len());
            obstacles.push(o);
        }
    }
    Some(Scattered {
        boundary,
        obstacles,
        start,
        goal,
    })
}

/// Whether `a` and `b` are more than `gap` apart: their bounding discs first (most pairs), the
/// outline query ([`StarShape::distance_to`]) for the near ones.
fn apart(a: &StarShape, b: &StarShape, gap: f64) -> bool {
    let far = (a.centre() - b.centre()).norm() - a.radius_bounds().1 - b.radius_bounds().1;
    far > gap || a.distance_to(b) > gap
}

/// A random point of the free space of `ws` at least `margin` from every obstacle and the
/// boundary (rejection sampling).
pub fn free_point(rng: &mut Rng, ws: &Workspace, margin: f64) -> Vector2<f64> {
    let (_, r_max) = ws.boundary().radius_bounds();
    loop {
        let x = ws.boundary().centre() + rng.point(r_max);
        if ws.boundary().contains(x)
            && -ws.boundary().coarse_signed_distance(x) > margin
            && ws
                .obstacles()
                .iter()
                .all(|o| o.coarse_signed_distance(x) > margin)
        {
            return x;
        }
    }
}
