//! The way out of a floor plan's boundary layer (docs/maths.md §13.6): a robot pushed into the
//! layer (`sd < δ`, its disc clear of the walls) gets a recovery command straight away from the
//! nearest wall, certified clear of the walls, and goes back to the law once in `W_δ`; a disc
//! that touches a wall still gets an error.

mod common;

use std::sync::Arc;

use harmonav::{Band, FloorMap, FloorNavigator, Law, Mode, NavError, Options, Vector2};

fn v(x: f64, y: f64) -> Vector2<f64> {
    Vector2::new(x, y)
}

/// The L room of `common::l_room`: `h = δ = 0.1` m, radius 0.1 m and margin 0.1 m.
fn floor() -> Arc<FloorMap> {
    common::l_room()
}

/// Flies `law` from `start` in the layer for at most `steps` periods of `h` (the dynamic law
/// by semi-implicit Euler): returns how long the recovery lasted, s, and the end.
fn fly(law: Law, h: f64, start: Vector2<f64>, steps: usize) -> (f64, Vector2<f64>) {
    let floor = floor();
    let goal = v(0.75, 3.3);
    let options = Options::default()
        .with_robot(0.1, 0.1)
        .with_control_period(h);
    let mut nav = FloorNavigator::new(floor.clone(), goal, law, options).unwrap();
    assert_eq!(
        nav.evaluate(start, Vector2::zeros()).unwrap_err(),
        NavError::BoundaryLayer
    );
    let (mut x, mut vel) = (start, Vector2::zeros());
    let (mut recovering, mut left) = (0, false);
    for _ in 0..steps {
        if (x - goal).norm() < 0.05 {
            break;
        }
        let c = nav.command(x, vel).unwrap();
        let before = floor.signed_distance(x);
        // The disc never touches a wall: along the step, by the chord bound.
        let next = common::held_step(&floor, law, h, x, &mut vel, c.value);
        if c.mode == Mode::Recovering(Band::Boundary) {
            assert!(!left, "back in the layer at {x:?} after leaving it");
            assert!(
                floor.signed_distance(next) > before,
                "no progress out at {x:?}"
            );
            recovering += 1;
        } else {
            left = true;
            assert!(
                floor.clearance(x) >= 0.0,
                "the law's command in the layer at {x:?}"
            );
        }
        x = next;
    }
    assert!(
        left && recovering > 0,
        "{recovering} recovery periods, left: {left}"
    );
    (recovering as f64 * h, x)
}

#[test]
fn a_kinematic_robot_pushed_into_the_layer_is_led_out_and_arrives() {
    // 5 cm from the shrunk wall below (δ = 10 cm), and in the reflex corner's layer.
    for start in [v(2.5, 0.15), v(1.394, 1.606)] {
        let (recovering, end) = fly(Law::kinematic(1.0), 0.01, start, 3000);
        assert!(
            recovering <= 0.1,
            "{start:?}: {recovering} s to leave the layer"
        );
        assert!(
            (end - v(0.75, 3.3)).norm() < 0.05,
            "{start:?}: stopped at {end:?}"
        );
    }
}

#[test]
fn a_dynamic_robot_pushed_into_the_layer_is_led_out() {
    let (recovering, end) = fly(Law::dynamic(1.0, 1.0), 0.001, v(2.5, 0.15), 1500);
    assert!(recovering <= 0.2, "{recovering} s to leave the layer");
    assert!(floor().clearance(end) >= 0.0, "{end:?}");
}

#[test]
fn a_disc_touching_a_wall_gets_no_command() {
    let options = Options::default().with_robot(0.1, 0.1);
    let mut nav = FloorNavigator::new(floor(), v(0.75, 3.3), Law::kinematic(1.0), options).unwrap();
    // 5 cm from the true wall: the disc (radius 0.1) overlaps it.
    assert_eq!(
        nav.command(v(2.5, 0.05), Vector2::zeros()).unwrap_err(),
        NavError::OutsideBoundary
    );
}

/// As [`harmonav::Navigator`]'s: a dynamic robot at rest in the walls' layer (5 cm from the
/// shrunk wall, `δ = 0.1` m) gets a recovery, which lifts the discovery speed from 0 to the
/// speed `|v⁺| = |(h/m)·f|` the command gives; a kinematic robot's is left alone.
#[test]
fn a_recovery_lifts_the_discovery_speed() {
    let (h, x) = (0.01, v(2.5, 0.15));
    for law in [Law::dynamic(1.0, 10.0), Law::kinematic(1.0)] {
        let options = Options::default()
            .with_robot(0.1, 0.1)
            .with_control_period(h);
        let mut nav = FloorNavigator::new(floor(), v(0.75, 3.3), law, options).unwrap();
        assert_eq!(nav.discovery_speed(), 0.0);
        let c = nav.command(x, Vector2::zeros()).unwrap();
        assert_eq!(c.mode, Mode::Recovering(Band::Boundary));
        let lifted = match law {
            Law::Dynamic { mass, .. } => (h / mass) * c.value.norm(),
            Law::Kinematic { .. } => 0.0,
        };
        assert!(lifted > 0.0 || matches!(law, Law::Kinematic { .. }));
        assert_eq!(nav.discovery_speed(), lifted, "{law:?}");
    }
}

/// A robot standing exactly on the edge of the certified region (`sd = δ` to rounding, where
/// no step of positive length is certified by the clearance alone) is led in, under either
/// law, instead of being held still for ever; it then arrives (kinematic).
#[test]
fn a_robot_on_the_edge_of_the_certified_region_is_led_in() {
    let floor = floor();
    let goal = v(0.75, 3.3);
    for start in [v(2.5, 0.2), v(0.2, 2.5), v(3.8, 1.0)] {
        let clearance = floor.clearance(start);
        assert!(clearance.abs() < 1e-12, "{start:?}: {clearance}");
        for (law, h) in [(Law::kinematic(1.0), 0.01), (Law::dynamic(1.0, 1.0), 0.001)] {
            let options = Options::default()
                .with_robot(0.1, 0.1)
                .with_control_period(h);
            let mut nav = FloorNavigator::new(floor.clone(), goal, law, options).unwrap();
            let (mut x, mut vel) = (start, Vector2::zeros());
            let c = nav.command(x, vel).unwrap();
            assert!(
                c.value.norm() > 0.0,
                "{start:?} {law:?}: held still ({:?})",
                c.mode
            );
            // It moves off the start within 0.2 s, and stays in the certified region.
            for _ in 0..(0.2 / h) as usize {
                let c = nav.command(x, vel).unwrap();
                x = common::held_step(&floor, law, h, x, &mut vel, c.value);
                assert!(
                    floor.clearance(x) >= -1e-12,
                    "{start:?} {law:?}: left at {x:?}"
                );
            }
            assert!(
                (x - start).norm() > 1e-3,
                "{start:?} {law:?}: still at {x:?}"
            );
            if matches!(law, Law::Kinematic { .. }) {
                for _ in 0..3000 {
                    if (x - goal).norm() < 0.05 {
                        break;
                    }
                    let c = nav.command(x, vel).unwrap();
                    x = common::held_step(&floor, law, h, x, &mut vel, c.value);
                }
                assert!((x - goal).norm() < 0.05, "{start:?}: stopped at {x:?}");
            }
        }
    }
}
