//! The geodesic distance of a floor plan (fast marching on a grid over `W_δ`) against closed
//! forms: the straight distance in a convex room, and bounds through the corner of an L.

use std::sync::Arc;

use harmonav_field::KPolicy;
use harmonav_floorplan::{FloorField, FloorMap, FloorOptions, Geodesic};
use nalgebra::Vector2;

fn v(x: f64, y: f64) -> Vector2<f64> {
    Vector2::new(x, y)
}

fn angle(a: Vector2<f64>, b: Vector2<f64>) -> f64 {
    (a.dot(&b) / (a.norm() * b.norm()))
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}

#[test]
fn in_a_convex_room_the_distance_is_the_straight_one_and_the_heading_points_at_the_goal() {
    let room = vec![v(0.0, 0.0), v(6.0, 0.0), v(6.0, 4.0), v(0.0, 4.0)];
    let floor = FloorMap::new(room, vec![], &FloorOptions::new(0.1, 0.1)).unwrap();
    let goal = v(4.7, 1.3);
    let g = Geodesic::new(&floor, goal);
    assert!((g.cell() - 0.05).abs() < 1e-12, "cell {}", g.cell());
    let mut worst = (0.0_f64, 0.0_f64);
    for i in 0..24 {
        for j in 0..16 {
            let x = v(0.3 + 0.23 * f64::from(i), 0.3 + 0.22 * f64::from(j));
            let straight = (goal - x).norm();
            if straight < 0.5 {
                continue;
            }
            let t = g.distance(x).expect("inside W_δ, a cell from its edge");
            worst.0 = worst.0.max((t - straight).abs());
            let d = g.heading(x).unwrap();
            worst.1 = worst.1.max(angle(d, goal - x));
        }
    }
    // Second-order marching: 0.3 cells and 3.1° at worst here (first-order: 8° of heading).
    assert!(worst.0 < 0.5 * g.cell(), "distance error {} m", worst.0);
    assert!(worst.1 < 4.0, "heading error {}°", worst.1);
    // Outside W_δ (within δ of a wall) there is nothing.
    assert!(g.distance(v(0.05, 2.0)).is_none() && g.heading(v(0.05, 2.0)).is_none());
}

/// An L: 4 m arms, 1.5 m wide, the reflex corner `c = (1.5, 1.5)`, `W_δ = {sd ≥ 0.1}`.
/// Within a cell of the edge of `W_δ`, where the bilinear heading has a corner outside and is
/// `None`, `heading_near` looks one segment ahead on the grid: in a convex room it points at
/// the goal to within about the grid's angular resolution (`atan(1/2)` ≈ 27° between the
/// directions to nodes two cells away, a little more from a point off the nodes: < 35°), it is the bilinear heading wherever that is defined, and a
/// short step along it does not turn it back (the nearest nodes, each a local minimum of the
/// look-ahead, are left out).
#[test]
fn near_the_edge_the_look_ahead_heading_points_at_the_goal_and_does_not_turn_back() {
    // Slanted walls, so that the grid's nodes do not line up with them.
    let room = vec![v(0.0, 0.0), v(6.0, 1.0), v(5.5, 4.5), v(-0.5, 3.5)];
    let floor = FloorMap::new(room, vec![], &FloorOptions::new(0.1, 0.1)).unwrap();
    let goal = v(3.5, 2.0);
    let g = Geodesic::new(&floor, goal);
    let (mut near, mut worst) = (0, 0.0_f64);
    for &p in floor.layer_edge() {
        // A tenth of a cell inside the edge of W_δ.
        let Some(n) = floor.toward_boundary(p) else {
            continue;
        };
        {
            let x = p - 0.1 * g.cell() * n;
            let d = g.heading_near(x).expect("a reached node within two cells");
            if let Some(bilinear) = g.heading(x) {
                assert_eq!(d, bilinear);
                continue;
            }
            near += 1;
            if (goal - x).norm() > 0.5 {
                worst = worst.max(angle(d, goal - x));
            }
            let y = x + 0.2 * g.cell() * d;
            let e = g.heading_near(y).unwrap();
            assert!(d.dot(&e) > 0.0, "turned back from {x:?}: {d:?} then {e:?}");
        }
    }
    assert!(near > 100, "{near} points without the bilinear heading");
    assert!(worst < 35.0, "worst angle to the goal {worst}°");
}

fn l_room() -> Arc<FloorMap> {
    let room = vec![
        v(0.0, 0.0),
        v(4.0, 0.0),
        v(4.0, 1.5),
        v(1.5, 1.5),
        v(1.5, 4.0),
        v(0.0, 4.0),
    ];
    Arc::new(FloorMap::new(room, vec![], &FloorOptions::new(0.1, 0.1)).unwrap())
}

#[test]
fn round_the_corner_of_an_l_the_distance_lies_between_the_corner_bounds() {
    let floor = l_room();
    let (x, goal, c) = (v(0.75, 3.5), v(3.5, 0.75), v(1.5, 1.5));
    let g = Geodesic::new(&floor, goal);
    let t = g.distance(x).unwrap();
    // Every path from x to the goal goes round c: at least |x − c| + |c − goal|.
    let lower = (x - c).norm() + (c - goal).norm();
    // A path in W_δ: to the circle of radius R = 0.15 about c, four chords of 22.5° along it
    // (each at least R·cos 11.25° = 0.147 > δ from c), then to the goal.
    let r = 0.15;
    let q = |deg: f64| c + r * v(deg.to_radians().cos(), deg.to_radians().sin());
    let arc: f64 = (0..4)
        .map(|i| (q(180.0 + 22.5 * f64::from(i + 1)) - q(180.0 + 22.5 * f64::from(i))).norm())
        .sum();
    let upper = (x - q(180.0)).norm() + arc + (q(270.0) - goal).norm();
    assert!(
        (lower - g.cell()..=upper + 3.0 * g.cell()).contains(&t),
        "T = {t}, bounds [{lower}, {upper}]"
    );
    // The straight distance (through the wall) is far below: the march went round.
    assert!((goal - x).norm() < lower - 0.3);
    // Up the first arm the heading points at the corner's side of the goal, not at the goal.
    let d = g.heading(x).unwrap();
    assert!(angle(d, q(225.0) - x) < 10.0, "{}°", angle(d, q(225.0) - x));
    assert!(angle(d, goal - x) > 20.0);
}

#[test]
fn the_field_drops_the_heading_in_a_saddle_guard_disc_and_keeps_it_elsewhere() {
    // A square room with a square pillar between the start and the goal: the point world has
    // one saddle; FloorField::heading is None where Phi(x) lies within its guard disc.
    let room = vec![v(0.0, 0.0), v(6.0, 0.0), v(6.0, 4.0), v(0.0, 4.0)];
    let pillar = vec![v(2.7, 1.7), v(3.3, 1.7), v(3.3, 2.3), v(2.7, 2.3)];
    let floor = Arc::new(FloorMap::new(room, vec![pillar], &FloorOptions::new(0.1, 0.1)).unwrap());
    let field = FloorField::new(floor, v(5.0, 2.0), KPolicy::default()).unwrap();
    let x = v(1.0, 2.6);
    let e = field.eval(x).unwrap();
    assert_eq!(field.heading(x, &e), None, "no geodesic built");
    let field = field.with_geodesic();
    assert!(field.heading(x, &e).is_some());
    let saddles = field.point_world().critical_points();
    assert_eq!(saddles.len(), 1);
    // A point whose image is the saddle itself (e.h moved onto it) is guarded.
    let guarded = harmonav_field::FieldEval {
        h: saddles[0].position,
        ..e
    };
    assert_eq!(field.heading(x, &guarded), None);
}

#[test]
fn a_sensed_obstacle_keeps_the_geodesic_and_moves_the_saddle_guards() {
    let room = vec![v(0.0, 0.0), v(6.0, 0.0), v(6.0, 4.0), v(0.0, 4.0)];
    let floor = Arc::new(FloorMap::new(room, vec![], &FloorOptions::new(0.1, 0.1)).unwrap());
    let field = FloorField::new(floor, v(5.0, 2.0), KPolicy::default())
        .unwrap()
        .with_geodesic();
    // No hole: no saddle, nothing guarded.
    assert!(field.point_world().critical_points().is_empty());
    let box_ = harmonav_transform::StarShape::circle(v(3.0, 2.0), 0.4).unwrap();
    let sensed = field.with_obstacle(box_).unwrap();
    assert!(std::ptr::eq(
        sensed.geodesic().unwrap(),
        field.geodesic().unwrap()
    ));
    let saddles = sensed.point_world().critical_points();
    assert_eq!(saddles.len(), 1);
    let x = v(1.0, 2.6);
    let e = sensed.eval(x).unwrap();
    assert!(sensed.heading(x, &e).is_some());
    let guarded = harmonav_field::FieldEval {
        h: saddles[0].position,
        ..e
    };
    assert_eq!(sensed.heading(x, &guarded), None);
    // Outside the grid, or not finite: no heading, no panic.
    let g = sensed.geodesic().unwrap();
    for p in [
        v(f64::NAN, 1.0),
        v(1e300, 1.0),
        v(-1e300, 2.0),
        v(2.0, f64::INFINITY),
    ] {
        assert!(g.heading(p).is_none() && g.distance(p).is_none());
    }
}
