//! Sector membership and detection against hand-computed cases; d_min against eq. (dmin).

use std::f64::consts::PI;

use harmonav_sensing::{Sector, Sensing, axis, initially_known};
use harmonav_transform::{StarShape, Workspace};
use nalgebra::Vector2;

fn sixty() -> Sector {
    Sector::new(1.0, 60f64.to_radians()).unwrap()
}

const POLE: Vector2<f64> = Vector2::new(0.0, 0.0);
const EAST: Vector2<f64> = Vector2::new(1.0, 0.0);

fn disc(x: f64, y: f64, r: f64) -> StarShape {
    StarShape::circle(Vector2::new(x, y), r).unwrap()
}

/// One data-driven check: (description, shape, expected detection).
fn check(cases: &[(&str, StarShape, bool)]) {
    for (what, shape, expected) in cases {
        assert_eq!(sixty().detects(POLE, EAST, shape), *expected, "{what}");
    }
}

#[test]
fn membership() {
    let s = sixty();
    assert!(s.contains(POLE, EAST, Vector2::new(0.99, 0.0)));
    assert!(
        !s.contains(POLE, EAST, Vector2::new(1.01, 0.0)),
        "beyond the range"
    );
    let edge = 30f64.to_radians();
    assert!(s.contains(
        POLE,
        EAST,
        0.5 * Vector2::new((edge - 1e-6).cos(), (edge - 1e-6).sin())
    ));
    assert!(
        !s.contains(
            POLE,
            EAST,
            0.5 * Vector2::new((edge + 1e-6).cos(), (edge + 1e-6).sin())
        ),
        "outside the aperture"
    );
    assert!(!s.contains(POLE, EAST, Vector2::new(-0.5, 0.0)), "behind");
    assert!(
        Sector::omnidirectional(1.0)
            .unwrap()
            .contains(POLE, EAST, Vector2::new(-0.5, 0.0))
    );
}

#[test]
fn detection_hand_computed() {
    let edge = 30f64.to_radians();
    let (c, s) = (edge.cos(), edge.sin());
    check(&[
        ("ahead, within range", disc(0.9, 0.0, 0.05), true),
        // Nearest point at 1 + 1e-6: just outside the range.
        ("just outside range", disc(1.05 + 1e-6, 0.0, 0.05), false),
        ("just inside range", disc(1.05 - 1e-6, 0.0, 0.05), true),
        // A disc centred on the 31° ray, radius just below its distance to the 30° edge ray.
        (
            "just outside the aperture",
            {
                let a = 31f64.to_radians();
                let d = 0.6 * (1f64.to_radians()).sin();
                disc(0.6 * a.cos(), 0.6 * a.sin(), d - 1e-6)
            },
            false,
        ),
        (
            "touching over the edge",
            {
                let a = 31f64.to_radians();
                let d = 0.6 * (1f64.to_radians()).sin();
                disc(0.6 * a.cos(), 0.6 * a.sin(), d + 1e-6)
            },
            true,
        ),
        ("behind the robot", disc(-0.5, 0.0, 0.3), false),
        // A thin ellipse crossing the upper edge ray between two rays of any coarse fan.
        (
            "thin obstacle across the edge",
            StarShape::ellipse(
                Vector2::new(0.5 * c + 0.2 * -s, 0.5 * s + 0.2 * c),
                [0.3, 0.002],
                edge + PI / 2.0,
            )
            .unwrap(),
            true,
        ),
        (
            "thin obstacle outside, parallel to the edge",
            StarShape::ellipse(
                Vector2::new(0.5 * c - 0.01 * s, 0.5 * s + 0.01 * c),
                [0.3, 0.002],
                edge,
            )
            .unwrap(),
            false,
        ),
    ]);
}

#[test]
fn obstacle_inside_the_wedge_not_touching_the_edges() {
    // Only the distance-minimum candidate can see it (both edge rays miss).
    let rock = StarShape::fourier_star(Vector2::new(0.7, 0.0), 0.05, &[(5, 0.01, 0.0)]).unwrap();
    assert!(sixty().detects(POLE, EAST, &rock));
    assert!(!sixty().detects(POLE, -EAST, &rock));
    assert!(
        !Sector::new(0.6, 60f64.to_radians())
            .unwrap()
            .detects(POLE, EAST, &rock)
    );
}

#[test]
fn d_min_matches_eq_dmin() {
    let rho = 0.05;
    for (deg, expected) in [
        (
            30.0,
            (1.0 * 15f64.to_radians().sin()).min(rho / 15f64.to_radians().cos()),
        ),
        (60.0, rho / 30f64.to_radians().cos()),
        (90.0, rho / 45f64.to_radians().cos()),
        (180.0, 1.0),
        (360.0, 1.0),
    ] {
        let s = Sector::new(1.0, f64::to_radians(deg)).unwrap();
        assert!((s.d_min(rho) - expected).abs() < 1e-15, "θ = {deg}°");
    }
    // With a large rho_min the range term binds.
    assert!((sixty().d_min(10.0) - 0.5).abs() < 1e-15);
}

#[test]
fn invalid_sensors_are_rejected() {
    assert!(Sector::new(0.0, 1.0).is_err());
    assert!(Sector::new(f64::NAN, 1.0).is_err());
    assert!(Sector::new(1.0, 0.0).is_err());
    assert!(Sector::new(1.0, 7.0).is_err());
    assert!(Sector::new(1.0, 2.0 * PI).is_ok());
}

#[test]
fn axis_and_initial_knowledge() {
    assert_eq!(
        axis(Vector2::new(0.0, 2.0), None),
        Some(Vector2::new(0.0, 1.0))
    );
    assert_eq!(axis(Vector2::zeros(), Some(EAST)), Some(EAST));
    assert_eq!(axis(Vector2::zeros(), None), None);
    let boundary = StarShape::circle(Vector2::zeros(), 5.0).unwrap();
    let ws = Workspace::new(
        boundary,
        vec![
            disc(0.5, 0.0, 0.2),
            disc(-2.0, 0.0, 0.3),
            disc(0.0, 0.33, 0.3),
        ],
        Vector2::new(3.0, 3.0),
    )
    .unwrap();
    let start = Vector2::zeros();
    assert_eq!(
        initially_known(&ws, start, &Sensing::Global, 0.05, None),
        vec![0, 1, 2]
    );
    // d_min = 0.0577: obstacle 2 is 0.03 away (known), obstacle 0 is 0.3 away.
    let sector = Sensing::Sector(sixty());
    assert_eq!(initially_known(&ws, start, &sector, 0.05, None), vec![2]);
    // Looking east the sensor also sees obstacle 0 at once.
    assert_eq!(
        initially_known(&ws, start, &sector, 0.05, Some(EAST)),
        vec![0, 2]
    );
}

/// Detection agrees with a brute-force test on 20 000 boundary points for random shapes,
/// poses and apertures (cases within 1e-3 of the decision are skipped as ambiguous).
#[test]
fn detection_agrees_with_brute_force() {
    use harmonav_transform::random::{self, Kind, Rng};
    let kinds = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
    let mut rng = Rng::new(99);
    let (mut decided, mut seen) = (0, 0);
    for case in 0..600 {
        let kind = kinds[case % 4];
        let (centre, size) = (rng.point(1.5), rng.uniform(0.05, 0.6));
        let shape = random::shape(&mut rng, kind, centre, size);
        let pole = rng.point(2.0);
        if shape.contains(pole) {
            continue;
        }
        let a = rng.uniform(0.0, std::f64::consts::TAU);
        let axis = Vector2::new(a.cos(), a.sin());
        let sector = Sector::new(
            rng.uniform(0.2, 2.0),
            rng.uniform(0.1, std::f64::consts::TAU),
        )
        .unwrap();
        let gaps: Vec<f64> = (0..20_000)
            .map(|i| {
                sector.distance(
                    pole,
                    axis,
                    shape.boundary_point(std::f64::consts::TAU * i as f64 / 20_000.0),
                )
            })
            .collect();
        let inside = gaps.contains(&0.0);
        let near = gaps.iter().cloned().fold(f64::INFINITY, f64::min) < 1e-3;
        if !inside && near {
            continue;
        }
        decided += 1;
        seen += inside as usize;
        assert_eq!(
            sector.detects(pole, axis, &shape),
            inside,
            "case {case}: {kind:?}"
        );
    }
    assert!(
        decided > 400 && seen > 50 && decided - seen > 50,
        "{decided} decided, {seen} detected"
    );
}
