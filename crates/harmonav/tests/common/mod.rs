//! Floor plans and the mover filter's exact oracle, shared by the facade's tests.

#![allow(dead_code)] // each test binary uses part of it

use std::sync::Arc;

use harmonav::{FloorMap, FloorOptions, Law, Mover, Vector2};

/// The L room: 4 m arms 1.5 m wide, reflex corner (1.5, 1.5); `h = 0.1` m, so `δ = 0.1` m, and
/// radius + margin 0.2 m, so `W_s` is the walls shrunk by 0.1 m.
pub fn l_room() -> Arc<FloorMap> {
    let v = Vector2::new;
    let room = vec![
        v(0.0, 0.0),
        v(4.0, 0.0),
        v(4.0, 1.5),
        v(1.5, 1.5),
        v(1.5, 4.0),
        v(0.0, 4.0),
    ];
    Arc::new(FloorMap::new(room, vec![], &FloorOptions::new(0.1, 0.2)).unwrap())
}

/// A 6 × 4 m room with a 4 m bar across it; `h = δ = 0.1` m, for radius and margin 0.1 m:
/// below the bar the hold's slide has attracting rest points (`floor_escape.rs`,
/// `funnels.rs`).
pub fn bar_room() -> Arc<FloorMap> {
    let v = Vector2::new;
    let room = vec![v(0.0, 0.0), v(6.0, 0.0), v(6.0, 4.0), v(0.0, 4.0)];
    let bar = vec![v(1.0, 1.8), v(5.0, 1.8), v(5.0, 2.2), v(1.0, 2.2)];
    Arc::new(FloorMap::new(room, vec![bar], &FloorOptions::new(0.1, 0.2)).unwrap())
}

/// One period `h` of the user's loop holding `command`: `x + h·u` (kinematic), or
/// `v += h·f/m, x += h·v` (dynamic, semi-implicit Euler; `vel` updated). Asserts that the disc
/// of radius 0.1 m stays clear of the walls along the step (the chord bound of the
/// 1-Lipschitz wall distance). Returns the position after the period.
pub fn held_step(
    floor: &FloorMap,
    law: Law,
    h: f64,
    x: Vector2<f64>,
    vel: &mut Vector2<f64>,
    command: Vector2<f64>,
) -> Vector2<f64> {
    let next = match law {
        Law::Kinematic { .. } => x + h * command,
        Law::Dynamic { mass, .. } => {
            *vel += h * command / mass;
            x + h * *vel
        }
    };
    let (c0, c1) = (
        floor.wall_distance(x) - 0.1,
        floor.wall_distance(next) - 0.1,
    );
    assert!(c0 + c1 - (next - x).norm() > 0.0, "{x:?} → {next:?}");
    next
}

/// The exact oracle of one period of a robot grown by `inflation` (radius + margin) holding `u`
/// from `x` for `h`: the least, over `τ ∈ [0, h]`, of `|x + τu − p̂| − (inflation + r + ε + Vτ)`,
/// the gap to the mover's reachable disc (convex in `τ`: golden-section search to 1e-12 s, plus
/// the ends).
pub fn reach_gap(x: Vector2<f64>, u: Vector2<f64>, h: f64, inflation: f64, m: &Mover) -> f64 {
    let r = inflation + m.radius + m.position_error;
    let g = |t: f64| (x + t * u - m.centre).norm() - r - m.speed_bound * t;
    let (mut a, mut b) = (0.0, h);
    let phi = 0.5 * (5f64.sqrt() - 1.0);
    while b - a > 1e-12 {
        let (c, d) = (b - phi * (b - a), a + phi * (b - a));
        if g(c) < g(d) {
            b = d;
        } else {
            a = c;
        }
    }
    g(0.0).min(g(h)).min(g(0.5 * (a + b)))
}
