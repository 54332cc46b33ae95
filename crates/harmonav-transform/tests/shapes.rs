//! Shapes: the radial function against its derivative and the boundary, containment, rho_min.

mod common;

use common::*;
use harmonav_transform::{ShapeError, StarShape};
use nalgebra::Vector2;
use proptest::prelude::*;

proptest! {
    #![proptest_config(config(1000))]

    /// R' against central differences of R; the boundary point is on the outline (distance ≈ 0),
    /// points just inside / outside along the ray are inside / outside.
    #[test]
    fn radial_function_is_consistent(shape in shape_at(Vector2::new(0.3, -0.2), 1.0), th in -3.2..3.2f64) {
        let (r, dr) = shape.radius(th);
        let h = 1e-6;
        let fd = (shape.radius(th + h).0 - shape.radius(th - h).0) / (2.0 * h);
        prop_assert!((dr - fd).abs() <= 1e-5 * (1.0 + dr.abs()), "R' = {dr}, fd = {fd}");
        let (lo, hi) = shape.radius_bounds();
        prop_assert!(r >= lo && r <= hi && lo > 0.0);
        let u = Vector2::new(th.cos(), th.sin());
        let p = shape.boundary_point(th);
        prop_assert!(shape.signed_distance(p).abs() < 1e-9, "boundary point at distance {}", shape.signed_distance(p));
        prop_assert!(shape.contains(shape.centre() + (r - 1e-9) * u));
        prop_assert!(!shape.contains(shape.centre() + (r + 1e-9) * u));
        prop_assert!(shape.signed_distance(shape.centre() + 0.5 * r * u) < 0.0);
        prop_assert!(shape.signed_distance(shape.centre() + 1.5 * r * u) > 0.0);
        prop_assert!(shape.rho_min() > 0.0 && shape.rho_min() <= hi * (1.0 + 1e-9));
    }
}

#[test]
fn closed_forms() {
    let c = Vector2::new(1.0, 2.0);
    let e = StarShape::ellipse(c, [2.0, 0.5], 0.3).unwrap();
    assert!((e.radius(0.3).0 - 2.0).abs() < 1e-14);
    assert!((e.radius(0.3 + std::f64::consts::FRAC_PI_2).0 - 0.5).abs() < 1e-14);
    assert!((e.rho_min() - 0.125).abs() < 1e-14);
    // A 2×2 square with rounded corners: R = 1 across the middle of each side.
    let sq =
        [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(x, y)| c + Vector2::new(x, y));
    let p = StarShape::rounded_polygon(&sq, 0.2).unwrap();
    assert!((p.radius(0.0).0 - 1.0).abs() < 1e-14 && p.radius(0.0).1.abs() < 1e-14);
    assert!((p.radius(std::f64::consts::FRAC_PI_2).0 - 1.0).abs() < 1e-14);
    // At 45° the ray meets the corner fillet: centre (0.8, 0.8), radius 0.2.
    let expected = 0.8 * 2f64.sqrt() + 0.2;
    assert!((p.radius(std::f64::consts::FRAC_PI_4).0 - expected).abs() < 1e-12);
    assert_eq!(p.rho_min(), 0.2);
    let s = StarShape::fourier_star(c, 1.0, &[(3, 0.1, 0.0)]).unwrap();
    assert!((s.radius(0.0).0 - 1.1).abs() < 1e-14);
    // Curvature radius of R = 1 + 0.1 cos 3θ at θ = 0: (R²)^{3/2}/(R² − R R'') = 1.21^{1.5}/(1.21 + 1.1·0.9).
    let rho0 = 1.21f64.powf(1.5) / (1.21 + 1.1 * 0.9);
    assert!(
        s.rho_min() <= rho0 + 1e-9 && s.rho_min() > 0.5 * rho0,
        "{}",
        s.rho_min()
    );
    // Areas: πab; the square 4 less four corners of (4 − π)·0.2²; π(r0² + a²/2) for the star.
    let pi = std::f64::consts::PI;
    assert!((e.area() - pi * 2.0 * 0.5).abs() < 1e-12, "{}", e.area());
    let square = 4.0 - (4.0 - pi) * 0.04;
    assert!((p.area() - square).abs() < 1e-4 * square, "{}", p.area());
    assert!(
        (s.area() - pi * (1.0 + 0.5 * 0.01)).abs() < 1e-12,
        "{}",
        s.area()
    );
}

#[test]
fn invalid_shapes_are_rejected_with_the_field_named() {
    let c = Vector2::new(0.0, 0.0);
    assert_eq!(
        StarShape::circle(c, 0.0).unwrap_err(),
        ShapeError::NotPositive {
            field: "radius",
            value: 0.0
        }
    );
    assert_eq!(
        StarShape::circle(Vector2::new(f64::NAN, 0.0), 1.0).unwrap_err(),
        ShapeError::NonFinite { field: "center" }
    );
    // Beyond MAX_LENGTH a squared distance would overflow: 1e155 is refused like 1e10.
    for huge in [1e10, 1e155] {
        let e = StarShape::ellipse(c, [huge, 1.0], 0.0).unwrap_err();
        assert!(
            matches!(
                e,
                ShapeError::Invalid {
                    field: "semi_axes",
                    ..
                }
            ) && e.to_string().contains("at most"),
            "{e}"
        );
        assert!(StarShape::circle(Vector2::new(0.0, huge), 1.0).is_err());
    }
    assert!(StarShape::ellipse(c, [1e9, 1.0], 0.0).is_ok());
    assert!(matches!(
        StarShape::ellipse(c, [1.0, -1.0], 0.0),
        Err(ShapeError::NotPositive {
            field: "semi_axes",
            ..
        })
    ));
    assert!(matches!(
        StarShape::fourier_star(c, 1.0, &[(2, 1.5, 0.0)]),
        Err(ShapeError::Invalid {
            field: "harmonics",
            ..
        })
    ));
    assert!(matches!(
        StarShape::fourier_star(c, 1.0, &[(0, 0.1, 0.0)]),
        Err(ShapeError::Invalid {
            field: "harmonics",
            ..
        })
    ));
    // A corner radius larger than the edges allow.
    let tri = [
        Vector2::new(0.0, 0.0),
        Vector2::new(1.0, 0.0),
        Vector2::new(0.0, 1.0),
    ];
    assert!(matches!(
        StarShape::rounded_polygon(&tri, 0.5),
        Err(ShapeError::Invalid {
            field: "corner_radius",
            ..
        })
    ));
    // A "C" shape is not star-shaped about its vertex centroid.
    let c_shape = [
        (0.0, 0.0),
        (3.0, 0.0),
        (3.0, 0.5),
        (0.5, 0.5),
        (0.5, 2.5),
        (3.0, 2.5),
        (3.0, 3.0),
        (0.0, 3.0),
    ]
    .map(|(x, y)| Vector2::new(x, y));
    assert!(matches!(
        StarShape::rounded_polygon(&c_shape, 0.05),
        Err(ShapeError::Invalid {
            field: "vertices",
            ..
        })
    ));
    assert!(matches!(
        StarShape::rounded_polygon(&tri[..2], 0.05),
        Err(ShapeError::Invalid {
            field: "vertices",
            ..
        })
    ));
}

#[test]
fn non_convex_star_polygon_is_accepted_and_smooth() {
    // A five-pointed star (reflex corners) rounded with radius 0.05.
    let v: Vec<_> = (0..10)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 10.0;
            let r = if i % 2 == 0 { 1.0 } else { 0.5 };
            Vector2::new(r * a.cos(), r * a.sin())
        })
        .collect();
    let s = StarShape::rounded_polygon(&v, 0.05).unwrap();
    // C¹: R' continuous across piece junctions (sampled densely).
    let n = 20000;
    let mut worst = 0.0f64;
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        let b = a + std::f64::consts::TAU / n as f64;
        worst = worst.max((s.radius(a).1 - s.radius(b).1).abs());
    }
    assert!(worst < 0.05, "R' jumps by {worst}");
    assert!(s.contains(Vector2::new(0.0, 0.0)));
    // At 18° the boundary runs along the edge from (1, 0) to the reflex vertex, at radius 0.634.
    let u = Vector2::new(0.951_056_5, 0.309_017);
    assert!(s.contains(0.6 * u) && !s.contains(0.7 * u));
    assert!((s.radius(0.1 * std::f64::consts::PI).0 - 0.634_2).abs() < 1e-3);
}

proptest! {
    #![proptest_config(config(300))]

    /// Inflating by r puts the boundary at distance r outside the original (and deflating at
    /// distance r inside), with R' still the derivative of R.
    #[test]
    fn offset_shapes_are_at_the_offset_distance(shape in shape_at(Vector2::new(-0.4, 0.1), 1.0), r in 0.01..0.3f64, th in -3.1..3.1f64) {
        // Concave parts sharper than r fold the offset curve: a typed error (checked below for
        // shapes that have none).
        let grown = match shape.offset(r) {
            Ok(g) => g,
            Err(e) => {
                let typed = matches!(e, ShapeError::Invalid { field: "robot.radius", .. });
                prop_assert!(typed, "unexpected error {e:?}");
                return Err(TestCaseError::reject("offset folds"));
            }
        };
        let p = grown.boundary_point(th);
        prop_assert!((shape.signed_distance(p) - r).abs() < 1e-5, "distance {} for r = {r}", shape.signed_distance(p));
        let h = 1e-6;
        let fd = (grown.radius(th + h).0 - grown.radius(th - h).0) / (2.0 * h);
        prop_assert!((grown.radius(th).1 - fd).abs() <= 1e-4 * (1.0 + fd.abs()), "R' {} vs {fd}", grown.radius(th).1);
        prop_assert!(grown.rho_min() >= shape.rho_min());
        if let Ok(shrunk) = shape.offset(-0.5 * shape.rho_min().min(r)) {
            let q = shrunk.boundary_point(th);
            let d = -shape.signed_distance(q);
            prop_assert!((d - 0.5 * shape.rho_min().min(r)).abs() < 1e-5, "inside distance {d}");
        }
    }
}

#[test]
fn robot_radius_grows_obstacles_and_shrinks_the_boundary() {
    use harmonav_transform::{RobotWorldError, Workspace, WorldError};
    let c = |x: f64| StarShape::circle(Vector2::new(x, 0.0), 1.0).unwrap();
    let boundary = StarShape::circle(Vector2::zeros(), 6.0).unwrap();
    let goal = Vector2::new(0.0, 4.0);
    // Gap of 0.3 between the two discs: a robot of radius 0.1 passes, one of 0.2 does not.
    let ws = Workspace::for_robot(boundary.clone(), vec![c(-1.15), c(1.15)], goal, 0.1).unwrap();
    assert_eq!(ws.obstacles()[0].radius(0.3).0, 1.1);
    assert_eq!(ws.boundary().radius(0.3).0, 5.9);
    assert_eq!(
        Workspace::for_robot(boundary.clone(), vec![c(-1.15), c(1.15)], goal, 0.2).unwrap_err(),
        RobotWorldError::World(WorldError::Overlap {
            first: 0,
            second: 1
        })
    );
    assert!(Workspace::for_robot(boundary.clone(), vec![c(-1.15)], goal, -0.1).is_err());
    // Convex shapes always inflate.
    let e = StarShape::ellipse(Vector2::zeros(), [0.5, 0.1], 0.4).unwrap();
    for r in [0.01, 0.3, 2.0] {
        let g = e.offset(r).unwrap();
        assert!((e.signed_distance(g.boundary_point(1.0)) - r).abs() < 1e-5);
    }
    // Deflating a boundary below zero size is a clear error, not a panic.
    let tiny = StarShape::ellipse(Vector2::zeros(), [0.3, 0.2], 0.0).unwrap();
    assert!(matches!(
        tiny.offset(-0.5),
        Err(ShapeError::Invalid {
            field: "robot.radius",
            ..
        })
    ));
}

/// `radius_about`: about an off-centre point of an ellipse, `R` is where the ray meets the
/// boundary (the implicit equation, and bisection on `contains`) and `R'` its derivative
/// (central differences); about the centre it is `radius`; other shapes have none.
#[test]
fn the_radial_function_about_another_point_is_exact() {
    let e = StarShape::ellipse(Vector2::new(1.0, -0.5), [50.0, 1.0], 0.2).unwrap();
    let axis = Vector2::new(0.2f64.cos(), 0.2f64.sin());
    let p = Vector2::new(1.0, -0.5) + 40.0 * axis + Vector2::new(-0.1, 0.3) * 0.5;
    assert!(e.contains(p));
    let dir = |th: f64| Vector2::new(th.cos(), th.sin());
    for i in 0..720 {
        let th = -3.1 + i as f64 * 0.0086;
        let (r, dr) = e.radius_about(p, dir(th)).unwrap();
        let (mut lo, mut hi) = (0.0, 200.0);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if e.contains(p + mid * dir(th)) {
                lo = mid
            } else {
                hi = mid
            }
        }
        let hit = lo;
        assert!(
            (r - hit).abs() <= 1e-9 * r.max(1.0),
            "θ = {th}: {r} vs {hit}"
        );
        let q = p + r * dir(th) - Vector2::new(1.0, -0.5);
        let (x, y) = (q.dot(&axis), axis.x * q.y - axis.y * q.x);
        assert!(((x / 50.0).powi(2) + y * y - 1.0).abs() < 1e-12);
        let d = 1e-6;
        let fd = (e.radius_about(p, dir(th + d)).unwrap().0
            - e.radius_about(p, dir(th - d)).unwrap().0)
            / (2.0 * d);
        assert!(
            (dr - fd).abs() <= 1e-5 * (dr.abs() + r),
            "θ = {th}: R' {dr} vs {fd}"
        );
    }
    let (r, dr) = e.radius_about(e.centre(), dir(0.7)).unwrap();
    let (r0, dr0) = e.radius(0.7);
    assert!((r - r0).abs() < 1e-12 && (dr - dr0).abs() < 1e-9);
    let s = StarShape::fourier_star(Vector2::zeros(), 1.0, &[(3, 0.1, 0.0)]).unwrap();
    assert!(s.radius_about(Vector2::zeros(), dir(0.0)).is_none());
}

/// The harmonic cap is one constant, refused with the field and the cap named; the issue's
/// `(4_000_000_000, 1e-12, 0)` hung (the radius built `u^n` by `n` products) and is now a
/// prompt typed error; at the cap, `R` and `R'` match `cos nθ`, `sin nθ` computed directly.
#[test]
fn harmonic_numbers_are_capped_and_high_harmonics_are_exact() {
    use harmonav_transform::MAX_HARMONIC;
    let c = Vector2::new(0.5, -1.0);
    assert_eq!(MAX_HARMONIC, 1000);
    for n in [MAX_HARMONIC + 1, 4_000_000_000] {
        let e = StarShape::fourier_star(c, 1.0, &[(n, 1e-12, 0.0)]).unwrap_err();
        assert!(
            matches!(&e, ShapeError::Invalid { field: "harmonics", problem } if problem.contains("1000")),
            "{e}"
        );
    }
    let terms = [
        (1, 0.1, 0.05),
        (7, -0.02, 0.01),
        (999, 1e-5, 2e-5),
        (MAX_HARMONIC, 2e-5, -1e-5),
    ];
    let s = StarShape::fourier_star(c, 1.0, &terms).unwrap();
    let mut worst = (0.0f64, 0.0f64);
    for i in 0..5000 {
        let th = -3.2 + i as f64 * 0.00128;
        let (r, dr) = s.radius(th);
        let direct = terms.iter().fold((1.0, 0.0), |(r, dr), &(n, a, b)| {
            let (sin, cos) = (n as f64 * th).sin_cos();
            (r + a * cos + b * sin, dr + n as f64 * (b * cos - a * sin))
        });
        worst = (
            worst.0.max((r - direct.0).abs()),
            worst.1.max((dr - direct.1).abs()),
        );
    }
    assert!(worst.0 < 1e-13 && worst.1 < 1e-11, "{worst:?}");
    // Terms of equal n add up.
    let split = StarShape::fourier_star(c, 1.0, &[(3, 0.1, 0.0), (3, -0.05, 0.02)]).unwrap();
    let whole = StarShape::fourier_star(c, 1.0, &[(3, 0.05, 0.02)]).unwrap();
    for th in [0.0, 1.0, 2.5] {
        assert!((split.radius(th).0 - whole.radius(th).0).abs() < 1e-15);
    }
}

/// A valid star whose curvature is too fine for any outline of at most
/// `MAX_OUTLINE_VERTICES` (the Fejér kernel `1 + 2Σ_{k ≤ 1000}(1 − k/1001) cos kθ ≥ 0`, plus
/// 0.01) is refused with a typed error, promptly.
#[test]
fn a_too_detailed_star_is_a_typed_error() {
    let terms: Vec<_> = (1..=1000u32)
        .map(|k| (k, 2.0 * (1.0 - k as f64 / 1001.0), 0.0))
        .collect();
    let e = StarShape::fourier_star(Vector2::zeros(), 1.01, &terms).unwrap_err();
    assert!(
        matches!(&e, ShapeError::Invalid { field: "harmonics", problem } if problem.contains("MAX_OUTLINE_VERTICES")),
        "{e}"
    );
}

/// The ellipse's angle has its own range and message, in radians (it spoke of metres).
#[test]
fn the_angle_is_checked_as_an_angle() {
    use harmonav_transform::MAX_ANGLE;
    let c = Vector2::zeros();
    let e = StarShape::ellipse(c, [1.0, 0.5], 1e7).unwrap_err();
    let text = e.to_string();
    assert!(
        matches!(
            e,
            ShapeError::Invalid {
                field: "angle_deg",
                ..
            }
        ) && text.contains("rad")
            && !text.contains(" m "),
        "{text}"
    );
    assert_eq!(
        StarShape::ellipse(c, [1.0, 0.5], f64::NAN).unwrap_err(),
        ShapeError::NonFinite { field: "angle_deg" }
    );
    assert!(StarShape::ellipse(c, [1.0, 0.5], MAX_ANGLE).is_ok());
    // A whole turn more is the same ellipse.
    let a = StarShape::ellipse(c, [1.0, 0.5], 0.3).unwrap();
    let b = StarShape::ellipse(c, [1.0, 0.5], 0.3 + std::f64::consts::TAU).unwrap();
    assert!((a.radius(1.0).0 - b.radius(1.0).0).abs() < 1e-14);
}
