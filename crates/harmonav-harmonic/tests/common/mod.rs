//! Worlds shared by the integration tests and the example.
#![allow(dead_code)]

use harmonav_harmonic::{Domain, HarmonicMap};
use nalgebra::Vector2;

pub fn v(x: f64, y: f64) -> Vector2<f64> {
    Vector2::new(x, y)
}

/// Axis-aligned square of half-side `half` about `c`, counter-clockwise or clockwise.
pub fn square(c: Vector2<f64>, half: f64, ccw: bool) -> Vec<Vector2<f64>> {
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

/// Regular `n`-gon inscribed in the circle of radius `r` about `c`, vertex 0 at angle 0.
pub fn ngon(c: Vector2<f64>, r: f64, n: usize, ccw: bool) -> Vec<Vector2<f64>> {
    let mut p: Vec<_> = (0..n)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / n as f64;
            c + v(r * t.cos(), r * t.sin())
        })
        .collect();
    if !ccw {
        p[1..].reverse();
    }
    p
}

/// `[−1, 1]²` with a 0.4-wide square hole at the centre.
pub fn square_with_hole() -> Domain {
    Domain::new(
        square(v(0.0, 0.0), 1.0, true),
        vec![square(v(0.0, 0.0), 0.2, false)],
    )
    .unwrap()
}

/// A 4×4 box with a U-shaped obstacle (2×2, pocket 1.2 wide and 1.6 deep, open upward).
pub fn u_world() -> Domain {
    let mut u = vec![
        v(-1.0, -1.0),
        v(1.0, -1.0),
        v(1.0, 1.0),
        v(0.6, 1.0),
        v(0.6, -0.6),
        v(-0.6, -0.6),
        v(-0.6, 1.0),
        v(-1.0, 1.0),
    ];
    u.reverse();
    Domain::new(square(v(0.0, 0.0), 2.0, true), vec![u]).unwrap()
}

/// An L-shaped room (3 × 3 with a 2 × 2 bite) with a square pillar in one arm.
pub fn l_world() -> Domain {
    Domain::new(
        vec![
            v(0.0, 0.0),
            v(3.0, 0.0),
            v(3.0, 1.0),
            v(1.0, 1.0),
            v(1.0, 3.0),
            v(0.0, 3.0),
        ],
        vec![square(v(0.5, 2.2), 0.15, false)],
    )
    .unwrap()
}

/// Two rooms 8 × 3 split by a 0.1 m wall that stands on the outer boundary, with a 0.3 m door
/// at the top, and a pillar in each room.
pub fn two_rooms() -> Domain {
    Domain::new(
        vec![
            v(0.0, 0.0),
            v(3.95, 0.0),
            v(3.95, 2.7),
            v(4.05, 2.7),
            v(4.05, 0.0),
            v(8.0, 0.0),
            v(8.0, 3.0),
            v(0.0, 3.0),
        ],
        vec![
            square(v(2.0, 1.5), 0.2, false),
            square(v(6.0, 1.5), 0.2, false),
        ],
    )
    .unwrap()
}

/// Central-difference Jacobian of `H` with step `e`.
pub fn fd_jacobian(map: &HarmonicMap, x: Vector2<f64>, e: f64) -> nalgebra::Matrix2<f64> {
    let h = |p: Vector2<f64>| map.eval(p).unwrap().value;
    let dx = (h(x + v(e, 0.0)) - h(x - v(e, 0.0))) / (2.0 * e);
    let dy = (h(x + v(0.0, e)) - h(x - v(0.0, e))) / (2.0 * e);
    nalgebra::Matrix2::new(dx.x, dy.x, dx.y, dy.y)
}

/// Grid nodes of spacing `s` over the bounding box at distance ≥ `delta` in the free space.
pub fn grid(domain: &Domain, s: f64, delta: f64) -> Vec<Vector2<f64>> {
    let (lo, hi) = domain.bounding_box();
    let mut out = Vec::new();
    let mut x = lo.x + s / 2.0;
    while x < hi.x {
        let mut y = lo.y + s / 2.0;
        while y < hi.y {
            let p = v(x, y);
            if domain.signed_distance(p) >= delta {
                out.push(p);
            }
            y += s;
        }
        x += s;
    }
    out
}

/// Winding number of the closed curve `f(loop)` about `q`.
pub fn winding(points: &[Vector2<f64>], q: Vector2<f64>) -> f64 {
    let mut total = 0.0;
    for i in 0..points.len() {
        let a = points[i] - q;
        let b = points[(i + 1) % points.len()] - q;
        total += (a.x * b.y - a.y * b.x).atan2(a.dot(&b));
    }
    total / std::f64::consts::TAU
}

/// A 10 × 6 room with eight 0.6 m square pillars in two rows: the benchmark world of the
/// far field (`N` set by the element length).
pub fn pillared_room() -> Domain {
    let pillars = (0..8)
        .map(|i| {
            let (col, row) = ((i % 4) as f64, (i / 4) as f64);
            square(v(1.75 + 2.15 * col, 2.0 + 2.0 * row), 0.3, false)
        })
        .collect();
    Domain::new(
        vec![v(0.0, 0.0), v(10.0, 0.0), v(10.0, 6.0), v(0.0, 6.0)],
        pillars,
    )
    .unwrap()
}

/// The dense samples of the far-field agreement: a grid of spacing `s` in the free space, and
/// along every `stride`-th element points a fraction `f ∈ {0.5, 0.1, 0.01}` of its length off
/// it on the free side, at its midpoint and a quarter from each end, plus 1e-3 of its length
/// from its start along the bisector-free side.
pub fn dense_samples(map: &HarmonicMap, s: f64, stride: usize) -> Vec<Vector2<f64>> {
    let mut out = grid(map.domain(), s, 0.0);
    for e in map.elements().iter().step_by(stride.max(1)) {
        let d = e.b - e.a;
        let len = d.norm();
        // The free side is on the left (outer ring counter-clockwise, holes clockwise).
        let normal = v(-d.y, d.x) / len;
        for along in [0.25, 0.5, 0.75, 1e-3] {
            for f in [0.5, 0.1, 0.01] {
                let p = e.a + d * along + normal * (f * len);
                if map.domain().contains(p) {
                    out.push(p);
                }
            }
        }
    }
    out
}

/// A seeded-strategy world: a star-shaped room of 6 to 10 jittered vertices (radius 0.8–1.3)
/// with `holes` small regular polygonal holes (proptest).
pub fn random_world(
    holes: std::ops::Range<usize>,
) -> impl proptest::strategy::Strategy<Value = (Vec<Vector2<f64>>, Vec<Vec<Vector2<f64>>>)> {
    use proptest::prelude::*;
    use std::f64::consts::TAU;
    let outer = prop::collection::vec((0.0..0.6_f64, 0.8..1.3_f64), 6..11).prop_map(|v| {
        let n = v.len();
        v.iter()
            .enumerate()
            .map(|(i, &(jitter, r))| {
                let t = TAU * (i as f64 + jitter) / n as f64;
                Vector2::new(r * t.cos(), r * t.sin())
            })
            .collect::<Vec<_>>()
    });
    let hole = (
        -0.4..0.4_f64,
        -0.4..0.4_f64,
        0.05..0.15_f64,
        3_usize..6,
        0.0..1.0_f64,
    )
        .prop_map(|(x, y, r, n, phase)| {
            (0..n)
                .map(|i| {
                    let t = -TAU * (i as f64 + phase) / n as f64;
                    Vector2::new(x + r * t.cos(), y + r * t.sin())
                })
                .collect::<Vec<_>>()
        });
    (outer, prop::collection::vec(hole, holes))
}
