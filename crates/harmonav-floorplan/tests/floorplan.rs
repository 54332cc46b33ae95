//! The composition `Phi = S ∘ H ∘ B` and `Θ` on floor plans: each property can fail.

mod common;

use std::sync::Arc;

use harmonav_field::{FieldError, KPolicy};
use harmonav_floorplan::{
    CentrePolicy, FloorError, FloorField, FloorMap, FloorOptions, NotFree, Part,
};
use harmonav_harmonic::{CertifyOptions, Verdict, certify};
use harmonav_transform::StarShape;
use nalgebra::{Matrix2, Vector2};

fn v(x: f64, y: f64) -> Vector2<f64> {
    Vector2::new(x, y)
}

/// A 6 × 4 room with a U-shaped obstacle (2 × 2, pocket 1 wide, 1.4 deep, open upward).
fn u_trap(h: f64, clearance: f64) -> Arc<FloorMap> {
    u_trap_centred(h, clearance, CentrePolicy::Solve)
}

/// [`u_trap`] with the centre policy `centre`.
fn u_trap_centred(h: f64, clearance: f64, centre: CentrePolicy) -> Arc<FloorMap> {
    common::u_room(h, clearance, centre)
}

/// An L-shaped room with a square pillar in one arm.
fn l_room(h: f64, clearance: f64) -> Arc<FloorMap> {
    let room = vec![
        v(0.0, 0.0),
        v(5.0, 0.0),
        v(5.0, 2.0),
        v(2.0, 2.0),
        v(2.0, 5.0),
        v(0.0, 5.0),
    ];
    let pillar = vec![v(0.8, 3.2), v(1.2, 3.2), v(1.2, 3.6), v(0.8, 3.6)];
    Arc::new(FloorMap::new(room, vec![pillar], &FloorOptions::new(h, clearance)).unwrap())
}

/// Central differences of `Phi` with step `e`.
fn fd(field: &FloorField, x: Vector2<f64>, e: f64) -> Matrix2<f64> {
    let phi = |p: Vector2<f64>| field.transform().nav_transform(p).unwrap().h;
    let dx = (phi(x + v(e, 0.0)) - phi(x - v(e, 0.0))) / (2.0 * e);
    let dy = (phi(x + v(0.0, e)) - phi(x - v(0.0, e))) / (2.0 * e);
    Matrix2::new(dx.x, dy.x, dx.y, dy.y)
}

/// The composed Jacobian `J_S J_M J_H J_B` agrees with central differences of `Phi` in each
/// part: where only `H` acts, in a sensed obstacle's band (`B`), and next to the walls where `S`
/// stretches; under both centre policies (`M_a` the identity, or the Möbius map that puts the
/// goal at 0, which it does).
#[test]
fn composed_jacobian_matches_finite_differences_in_every_part() {
    for centre in CentrePolicy::ALL {
        composed_jacobian_matches_finite_differences(centre);
    }
}

fn composed_jacobian_matches_finite_differences(centre: CentrePolicy) {
    let floor = u_trap_centred(0.2, 0.25, centre);
    let rock = StarShape::ellipse(v(1.0, 2.0), [0.3, 0.2], 0.4).unwrap();
    let goal = v(5.0, 2.0);
    let field = FloorField::with_obstacles(floor.clone(), &[rock], goal, KPolicy::Auto).unwrap();
    let raw = floor.map().eval(goal).unwrap().value;
    let image = field.transform().destination_image();
    match centre {
        CentrePolicy::Solve => assert_eq!(image, raw),
        CentrePolicy::Goal => {
            assert!(raw.norm() > 0.1, "the control: H(x_d) is not already 0");
            assert!(image.norm() < 1e-15, "M_a(H(x_d)) = {image:?}");
        }
    }
    // The punctures stay strictly inside the disk (|M_a(w)| < 1 for |w| < 1).
    assert!(field.transform().raw_points().all(|p| p.norm() < 1.0));
    let mut seen = [false; 3];
    let mut worst: f64 = 0.0;
    for i in 0..60 {
        for j in 0..40 {
            let x = v(0.05 + 0.1 * i as f64, 0.05 + 0.1 * j as f64);
            // Central differences need the whole stencil in the domain of Phi.
            let e = 1e-6;
            let stencil = [
                x,
                x + v(e, 0.0),
                x - v(e, 0.0),
                x + v(0.0, e),
                x - v(0.0, e),
            ];
            let Ok(maps) = stencil
                .iter()
                .map(|&p| field.transform().nav_transform(p))
                .collect::<Result<Vec<_>, _>>()
            else {
                continue;
            };
            if maps.iter().any(|m| m.part != maps[0].part) {
                continue;
            }
            let m = maps[0];
            seen[match m.part {
                Part::Harmonic => 0,
                Part::Obstacle(_) => 1,
                Part::Stretched => 2,
            }] = true;
            let diff = fd(&field, x, e);
            let rel = (m.jacobian - diff).norm() / m.jacobian.norm().max(1e-3);
            worst = worst.max(rel);
            assert!(rel < 1e-5, "J − FD at {x:?}: {rel:e} ({:?})", m.part);
            assert!(m.jacobian.determinant() > 0.0, "det J_Phi ≤ 0 at {x:?}");
        }
    }
    assert_eq!(seen, [true; 3], "every part sampled ({centre})");
    assert!(worst > 0.0);
}

/// `∇Θ` agrees with central differences of `Θ` (through `phi_k` in log space near walls).
#[test]
fn gradient_of_theta_matches_finite_differences() {
    let field = FloorField::new(l_room(0.2, 0.2), v(4.5, 1.0), KPolicy::Auto).unwrap();
    for x in [
        v(1.0, 4.5),
        v(0.5, 0.5),
        v(1.6, 1.6),
        v(3.0, 1.0),
        v(1.5, 3.0),
    ] {
        let e = field.eval(x).unwrap();
        let s = 1e-6;
        let t = |p: Vector2<f64>| field.eval(p).unwrap().value;
        let g = v(
            (t(x + v(s, 0.0)) - t(x - v(s, 0.0))) / (2.0 * s),
            (t(x + v(0.0, s)) - t(x - v(0.0, s))) / (2.0 * s),
        );
        assert!(
            (e.gradient - g).norm() <= 1e-5 * e.gradient.norm().max(1e-6),
            "∇Θ {:?} against {g:?} at {x:?}",
            e.gradient
        );
        assert!((0.0..=1.0).contains(&e.value));
    }
    assert_eq!(field.eval(v(4.5, 1.0)).unwrap().value, 0.0);
}

/// Holes are the punctures of the solve, sensed obstacles their centres' images; `k` counts
/// both, and adding an obstacle reuses the same solved map.
#[test]
fn points_are_punctures_then_sensed_centres_and_k_counts_both() {
    let floor = u_trap(0.25, 0.25);
    let field = FloorField::new(floor.clone(), v(5.0, 2.0), KPolicy::Paper).unwrap();
    assert_eq!(field.k(), 2.0);
    let pw: Vec<_> = field.transform().raw_points().collect();
    assert_eq!(pw, floor.map().punctures().to_vec());
    let rock = StarShape::circle(v(1.0, 2.0), 0.3).unwrap();
    let more = field.with_obstacle(rock).unwrap();
    assert_eq!(more.k(), 3.0);
    assert!(Arc::ptr_eq(more.floor(), field.floor()), "no new solve");
    let last = more.transform().raw_points().last().unwrap();
    assert!((last - floor.map().eval(v(1.0, 2.0)).unwrap().value).norm() < 1e-15);
    // Inside the obstacle, at its centre, and on the hole: typed, never a NaN.
    assert_eq!(
        more.eval(v(1.0, 2.1)).unwrap_err(),
        FieldError::InObstacle { obstacle: 0 }
    );
    assert_eq!(more.locate(v(3.0, 1.2)), Some(NotFree::Outside));
    assert_eq!(more.locate(v(3.0, 1.7)), Some(NotFree::BoundaryLayer));
    assert_eq!(
        more.eval(v(f64::NAN, 1.0)).unwrap_err(),
        FieldError::NotFinite
    );
}

/// Fold detection: a coarse map of the U room folds in its corner layer (`det J_H ≤ 0` at
/// some samples closer than one element to the walls), the certificate finds a fold when asked
/// for a `δ` inside that layer, and `Phi` refuses those points as the boundary layer.
#[test]
fn folds_in_the_layer_are_found_and_refused() {
    let floor = u_trap(0.5, 0.0);
    let h = floor.delta();
    assert_eq!(h, 0.5);
    assert!(floor.map().max_element_length() <= h);
    assert!(floor.keeps_delta());
    assert_eq!(floor.shrink(), 0.0);
    let field = FloorField::new(floor.clone(), v(5.0, 2.0), KPolicy::Auto).unwrap();
    let mut folds = Vec::new();
    for i in 0..600 {
        for j in 0..400 {
            let x = v(0.005 + 0.01 * i as f64, 0.005 + 0.01 * j as f64);
            let sd = floor.signed_distance(x);
            if sd > 0.0
                && let Ok(e) = floor.map().eval(x)
                && e.det() <= 0.0
            {
                folds.push((x, sd));
            }
        }
    }
    assert!(!folds.is_empty(), "the coarse map folds somewhere");
    for &(x, sd) in &folds {
        assert!(sd < h, "a fold {sd} from the walls, beyond δ = {h}");
        assert_eq!(field.locate(x), Some(NotFree::BoundaryLayer));
    }
    let deepest = folds.iter().map(|f| f.1).fold(0.0, f64::max);
    let c = certify(floor.map(), &CertifyOptions::new(0.5 * deepest)).unwrap();
    assert!(matches!(c.verdict, Verdict::Fold { .. }), "{:?}", c.verdict);
}

/// Far points: parry's queries square the coordinates and overflowed beyond 1e154 m (a wall
/// distance of `∞`, a signed distance of 0 and so a clearance of `−δ`, and a goal "−0.0000 m
/// from the walls"); the far branch gives `|x|` to rounding, with the sign of "outside".
#[test]
fn far_points_are_as_far_from_the_walls_as_they_are_from_the_origin() {
    let floor = l_room(0.25, 0.3);
    for far in [1e20, 1e40, 1e160, 1e200, 1e300] {
        for x in [v(far, 1.0), v(-far, far), v(2.0, -far)] {
            let r = x.x.hypot(x.y);
            let (d, sd) = (floor.wall_distance(x), floor.signed_distance(x));
            assert!((d / r - 1.0).abs() < 1e-12, "{x:?}: wall distance {d}");
            assert!((sd / r + 1.0).abs() < 1e-12, "{x:?}: signed distance {sd}");
            assert!(
                floor.clearance(x) < -0.5 * r,
                "{x:?}: {}",
                floor.clearance(x)
            );
            // Towards the walls: back towards the origin, a unit vector (it was `None`, "on
            // the boundary", beyond 1e154 m).
            let t = floor.toward_boundary(x).expect("a direction");
            assert!(
                (t.norm() - 1.0).abs() < 1e-12 && t.dot(&(-x / r)) > 0.999,
                "{x:?}: {t:?}"
            );
        }
    }
    let Err(e) = FloorField::new(floor, v(1e200, 1.0), KPolicy::Auto) else {
        panic!("a goal 1e200 m away was accepted");
    };
    assert_eq!(
        e.to_string(),
        "the goal is -1.0000e200 m from the walls, not in the certified region (at least δ = \
         0.2500 m from every wall)"
    );
}

/// Bad input is a typed error and leaves the field as it was.
#[test]
fn bad_inputs_are_typed_errors() {
    let floor = l_room(0.25, 0.3);
    assert!(matches!(
        FloorField::new(floor.clone(), v(0.1, 0.1), KPolicy::Auto),
        Err(FloorError::GoalNotCertified { .. })
    ));
    assert!(matches!(
        FloorField::new(floor.clone(), v(6.0, 1.0), KPolicy::Auto),
        Err(FloorError::GoalNotCertified { .. })
    ));
    let field = FloorField::new(floor.clone(), v(4.5, 1.0), KPolicy::Auto).unwrap();
    let near = StarShape::circle(v(4.0, 0.5), 0.3).unwrap();
    assert_eq!(
        field.with_obstacle(near).unwrap_err(),
        FloorError::ObstacleNearWall { obstacle: 0 }
    );
    let on_goal = StarShape::circle(v(4.3, 1.0), 0.3).unwrap();
    assert_eq!(
        field.with_obstacle(on_goal).unwrap_err(),
        FloorError::ContainsGoal { obstacle: 0 }
    );
    let a = field
        .with_obstacle(StarShape::circle(v(1.0, 1.0), 0.2).unwrap())
        .unwrap();
    assert_eq!(
        a.with_obstacle(StarShape::circle(v(1.2, 1.0), 0.2).unwrap())
            .unwrap_err(),
        FloorError::Overlap {
            first: 0,
            second: 1
        }
    );
    assert_eq!(a.k(), field.k().max(a.k()));
    for bad in [0.0, -1.0, f64::NAN] {
        let r = FloorMap::new(
            vec![v(0.0, 0.0), v(1.0, 0.0), v(0.0, 1.0)],
            vec![],
            &FloorOptions::new(bad, 0.0),
        );
        assert!(matches!(r, Err(FloorError::InvalidOption { .. })));
    }
    // Either orientation is accepted.
    let cw = vec![v(0.0, 0.0), v(0.0, 1.0), v(1.0, 1.0), v(1.0, 0.0)];
    assert!(FloorMap::new(cw, vec![], &FloorOptions::new(0.1, 0.0)).is_ok());
    // A crossing ring is named.
    let bow = vec![v(0.0, 0.0), v(1.0, 1.0), v(1.0, 0.0), v(0.0, 1.0)];
    assert!(matches!(
        FloorMap::new(bow, vec![], &FloorOptions::new(0.1, 0.0)),
        Err(FloorError::Domain(_))
    ));
}
