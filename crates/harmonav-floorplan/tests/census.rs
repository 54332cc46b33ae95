//! The census of a floor plan's `Θ` (`FloorField::census`): `Phi`'s preimage by Newton's method
//! round-trips, every saddle found is a zero of `∇Θ` with a Hessian of one negative and one
//! positive eigenvalue, and the goal is the minimum; the U room's hole and its sensed pillar
//! give one saddle each (theorem `isNF`).

use std::sync::Arc;

use harmonav_field::{CriticalType, KPolicy};
use harmonav_floorplan::{FloorField, FloorMap, FloorOptions};
use harmonav_transform::StarShape;
use nalgebra::Vector2;

fn v(x: f64, y: f64) -> Vector2<f64> {
    Vector2::new(x, y)
}

/// An 8 × 5 m room with a U-shaped hole open to the left and a pillar right of it (the
/// U-trap of `scenarios/floorplans/`, at a coarser element).
fn u_trap() -> FloorField {
    let outer = vec![v(0.0, 0.0), v(8.0, 0.0), v(8.0, 5.0), v(0.0, 5.0)];
    let u = vec![
        v(3.0, 1.0),
        v(5.0, 1.0),
        v(5.0, 4.0),
        v(3.0, 4.0),
        v(3.0, 3.2),
        v(4.5, 3.2),
        v(4.5, 1.8),
        v(3.0, 1.8),
    ];
    let floor = Arc::new(FloorMap::new(outer, vec![u], &FloorOptions::new(0.1, 0.2)).unwrap());
    let pillar = StarShape::circle(v(6.3, 1.0), 0.25 + 0.2).unwrap();
    FloorField::with_obstacles(floor, &[pillar], v(6.8, 2.5), KPolicy::Auto).unwrap()
}

#[test]
fn the_preimage_round_trips() {
    let field = u_trap();
    for x in [
        v(1.0, 2.1),
        v(6.0, 4.0),
        v(2.5, 0.6),
        v(7.2, 1.3),
        v(3.9, 2.5),
    ] {
        let h = field.transform().nav_transform(x).unwrap().h;
        let back = field.preimage(h).unwrap();
        assert!((back - x).norm() < 1e-8, "{x:?} → {back:?}");
    }
    // Far beyond the image of `W_δ` (the stretched disk): no preimage.
    assert_eq!(field.preimage(v(1e3, 0.0)), None);
}

#[test]
fn one_saddle_per_hole_and_obstacle_each_a_zero_of_the_gradient() {
    let field = u_trap();
    let census = field.census();
    assert_eq!(
        (census.minima, census.saddles, census.degenerate),
        (1, 2, 0)
    );
    let goal = census.points[0];
    assert_eq!((goal.x, goal.kind), (v(6.8, 2.5), CriticalType::Minimum));
    assert!(goal.eigenvalues.unwrap()[0] > 0.0);
    for p in &census.points[1..] {
        let g = field.eval(p.x).unwrap().gradient.norm();
        // Against the gradient 1 cm away: a zero, not a slow slope.
        let near = field.eval(p.x + v(0.01, 0.0)).unwrap().gradient.norm();
        assert!(g < 1e-6 * near, "{:?}: |∇Θ| {g:e} against {near:e}", p.x);
        let [lo, hi] = p.eigenvalues.unwrap();
        assert!(lo < 0.0 && hi > 0.0, "{:?}: {lo:e} {hi:e}", p.x);
    }
}
