//! `Field::push_obstacle` (a discovery in place) against the field built at once over the same
//! obstacles: the same `Phi` and `k` bit for bit, the same `Θ` and `∇Θ` bit for bit with the
//! direct point-world sum and to the multipole tolerance with the tree; a refused obstacle
//! leaves the field as it was.

use std::sync::Arc;

use harmonav_field::{Field, KPolicy};
use harmonav_transform::random::{self, Kind, Rng, Scattered};
use harmonav_transform::{StarShape, Workspace};
use nalgebra::Vector2;

/// 300 obstacles (past the multipole tree's 128 and its rebuild at 256) in a disc of radius 32.
fn world() -> Scattered {
    let kinds = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
    random::scattered(&mut Rng::new(41), 32.0, 300, &kinds, 0.05).unwrap()
}

fn points(ws: &Workspace) -> Vec<Vector2<f64>> {
    let mut rng = Rng::new(9);
    (0..1500)
        .map(|_| random::free_point(&mut rng, ws, 1e-9))
        .collect()
}

/// The field grown by `push_obstacle` from no obstacle, and the one built over all of them.
fn both(w: &Scattered, policy: KPolicy) -> (Field, Field) {
    let empty = Workspace::new(w.boundary.clone(), Vec::new(), w.goal).unwrap();
    let mut pushed = Field::all_known_with(Arc::new(empty), policy).unwrap();
    for (i, o) in w.obstacles.iter().enumerate() {
        assert_eq!(pushed.push_obstacle(o.clone()), Ok(i));
    }
    let ws = Workspace::new(w.boundary.clone(), w.obstacles.clone(), w.goal).unwrap();
    (pushed, Field::all_known_with(Arc::new(ws), policy).unwrap())
}

#[test]
fn pushed_obstacles_give_the_field_built_at_once() {
    let w = world();
    for policy in [KPolicy::Auto, KPolicy::Paper] {
        let (pushed, built) = both(&w, policy);
        assert_eq!(pushed.known(), built.known());
        assert_eq!(pushed.k().to_bits(), built.k().to_bits(), "{policy}");
        assert_eq!(
            pushed.destination_stiffness().to_bits(),
            built.destination_stiffness().to_bits()
        );
        let (a, b) = (pushed.transform(), built.transform());
        assert!(
            a.widths()
                .zip(b.widths())
                .all(|(x, y)| x.to_bits() == y.to_bits())
        );
        assert_eq!(a.outer_band(), b.outer_band());
        assert_eq!(pushed.point_world(), built.point_world());
        let (direct_a, direct_b) = (
            pushed.clone().without_far_field(),
            built.clone().without_far_field(),
        );
        let mut banded = 0;
        for x in points(built.workspace()) {
            let (ma, mb) = (a.nav_transform(x), b.nav_transform(x));
            assert_eq!(ma, mb, "Phi, J_Phi at {x:?}");
            banded += usize::from(matches!(
                ma,
                Ok(m) if !matches!(m.active, harmonav_transform::Active::Identity)
            ));
            // The direct sums: the same numbers in the same order.
            assert_eq!(direct_a.eval(x), direct_b.eval(x), "direct Θ at {x:?}");
            // The multipole sums: pushed into a tree vs built at once, to their tolerance.
            let (ea, eb) = (pushed.eval(x).unwrap(), built.eval(x).unwrap());
            let exact = direct_b.eval(x).unwrap();
            assert!(
                (ea.value - eb.value).abs() <= 1e-11 * exact.value.max(1e-300),
                "{x:?}"
            );
            assert!(
                (ea.phi - eb.phi).abs() <= 1e-11 * exact.phi.abs().max(1.0),
                "{x:?}"
            );
            let g = exact.gradient.norm();
            assert!(
                (ea.gradient - eb.gradient).norm() <= 1e-8 * g + 1e-300,
                "{x:?}"
            );
        }
        assert!(banded > 100, "only {banded} points in a band");
    }
}

#[test]
fn a_refused_obstacle_leaves_the_field_unchanged() {
    let w = world();
    let ws = Workspace::new(w.boundary.clone(), w.obstacles[..200].to_vec(), w.goal).unwrap();
    let mut field = Field::all_known(Arc::new(ws)).unwrap();
    let before = field.clone();
    let xs = points(before.workspace());
    for bad in [
        StarShape::circle(w.obstacles[7].centre(), 0.2).unwrap(), // overlaps obstacle 7
        StarShape::circle(w.goal, 0.3).unwrap(),                  // holds the destination
        StarShape::circle(Vector2::new(31.9, 0.0), 1.0).unwrap(), // crosses the boundary
    ] {
        assert!(field.push_obstacle(bad).is_err());
        assert_eq!(field.known(), before.known());
        assert_eq!(field.workspace().obstacles().len(), 200);
        assert_eq!(field.k().to_bits(), before.k().to_bits());
        for &x in &xs {
            assert_eq!(field.eval(x), before.eval(x));
        }
    }
}
