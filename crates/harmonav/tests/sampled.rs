//! Sampled-data safety (`docs/maths.md` §10): every command of the default hold is safe when
//! held for the control period, the robot in the margin band is led back out, and no option
//! the navigator accepts makes a command non-finite. `cargo xtask verify` runs the same suite
//! (`harmonav::checks`) on 300 worlds at every rate.

use harmonav::checks::{Integrator, disc_world, fly, suite};
use harmonav::transform::random::Rng;
use harmonav::{Band, HoldPolicy, Law, Mode, NavError, Navigator, Options, StarShape, Vector2};

/// The worlds where the continuous law sampled as is (the hold off, as before the hold
/// existed) entered a grown shape or touched a true one, found by `cargo xtask verify`'s
/// negative control: `(world, law, rate, radius, margin)`. The kinematic ones were found under
/// the paper's speed `K√(2Θ)` (`SpeedPolicy::Paper`), the dynamic ones under the damping
/// `"shaped"` (`DampingPolicy::Shaped`, the default then), which they keep.
const DEFECTS: [(u64, bool, f64, f64, f64); 4] = [
    (48, true, 100.0, 0.1, 0.05),
    (101, true, 100.0, 0.1, 0.05),
    (167, false, 250.0, 0.1, 0.0),
    (220, false, 250.0, 0.1, 0.05),
];

#[test]
fn the_flights_that_failed_without_the_hold_are_safe_with_it() {
    for (seed, kinematic, hz, radius, margin) in DEFECTS {
        let law = if kinematic {
            Law::kinematic(1.0)
        } else {
            Law::dynamic(1.0, 10.0)
        };
        let world = disc_world(seed);
        let options = Options::default()
            .with_robot(radius, margin)
            .with_speed(harmonav::SpeedPolicy::Paper)
            .with_damping(harmonav::DampingPolicy::Shaped);
        let fly_with = |hold| {
            fly(
                &world,
                law,
                options.with_hold(hold),
                1.0 / hz,
                Integrator::SemiImplicitEuler,
            )
            .unwrap()
        };
        let before = fly_with(HoldPolicy::Paper);
        assert!(
            !before.safe(),
            "world {seed}: the defect is gone without the hold"
        );
        let after = fly_with(HoldPolicy::Auto);
        assert!(
            after.safe() && after.reached,
            "world {seed} at {hz} Hz: {after:?}"
        );
    }
}

/// 20 worlds of the suite at the slowest rate of each law: every flight safe, nearly all arrive.
#[test]
fn the_suite_is_safe_at_the_slowest_rates() {
    for (law, h) in [
        (Law::kinematic(1.0), 0.05),
        (Law::dynamic(1.0, 10.0), 0.004),
    ] {
        let r = suite(0..20, law, Options::default(), h).unwrap();
        assert!(
            r.failures.is_empty(),
            "{law:?} at h = {h}: {:?}",
            r.failures
        );
        assert!(r.arrival() >= 0.95, "{law:?} at h = {h}: {r:?}");
    }
}

/// The exact hold of the force (the double integrator between samples) is covered too.
#[test]
fn the_dynamic_hold_is_safe_under_the_exact_hold_of_the_force() {
    for seed in 0..20 {
        let world = disc_world(seed);
        let options = Options::default().with_robot(0.1, 0.05);
        let f = fly(
            &world,
            Law::dynamic(1.0, 10.0),
            options,
            0.004,
            Integrator::ExactHold,
        )
        .unwrap();
        assert!(f.safe() && f.reached, "world {seed}: {f:?}");
    }
}

/// At random free states: the kinematic step is certified free and Θ decreases over it; the
/// dynamic step keeps `h|v⁺| ≤ d(x)/4` and `|v⁺| < √(2μ/m)`.
#[test]
fn each_held_command_keeps_its_certificate() {
    let mut rng = Rng::new(7);
    for seed in 0..10 {
        let world = disc_world(seed);
        for h in [0.01, 0.05, 0.2] {
            let options = Options::default()
                .with_robot(0.1, 0.0)
                .with_control_period(h);
            let mut kin = Navigator::new(
                world.boundary.clone(),
                world.goal,
                Law::kinematic(2.0),
                options,
            )
            .unwrap();
            let mut dynamic = Navigator::new(
                world.boundary.clone(),
                world.goal,
                Law::dynamic(1.0, 10.0),
                options,
            )
            .unwrap();
            for o in &world.obstacles {
                kin.add_obstacle(o.clone()).unwrap();
                dynamic.add_obstacle(o.clone()).unwrap();
            }
            let mut tried = 0;
            while tried < 200 {
                let x = rng.point(5.0);
                if kin.theta(x).is_err() {
                    continue;
                }
                tried += 1;
                let u = kin.command(x, Vector2::zeros()).unwrap().value;
                let end = x + h * u;
                // The whole segment lies in the free space: sampled, against the true discs
                // grown by the radius (exact: the grown shape of a disc is a disc).
                for i in 0..=20 {
                    let p = x + (i as f64 / 20.0) * h * u;
                    let gap = world
                        .obstacles
                        .iter()
                        .map(|o| o.signed_distance(p))
                        .fold(-world.boundary.signed_distance(p), f64::min);
                    assert!(gap > 0.1, "h {h}: the step leaves the free space at {p:?}");
                }
                // phi_k strictly decreases (Θ = sigma(phi_k) would round to 1 near walls).
                if u.norm() > 0.0 {
                    let phi = |p| kin.field().eval(p).unwrap().phi;
                    assert!(phi(end) < phi(x), "phi_k rose");
                }
                let v = rng.point(3.0);
                let f = dynamic.command(x, v).unwrap().value;
                let next = v + h * f;
                assert!(h * next.norm() <= 0.25 * dynamic.clearance(x) * (1.0 + 1e-9));
                assert!(next.norm() < dynamic.speed_bound().unwrap());
            }
        }
    }
}

/// As `h → 0` the held force tends to the continuous law's (`Navigator::evaluate`).
#[test]
fn the_dynamic_hold_tends_to_the_law_as_the_period_shrinks() {
    let world = disc_world(3);
    let mut rng = Rng::new(11);
    let make = |h: f64| {
        let mut nav = Navigator::new(
            world.boundary.clone(),
            world.goal,
            Law::dynamic(1.0, 10.0),
            Options::default().with_control_period(h),
        )
        .unwrap();
        for o in &world.obstacles {
            nav.add_obstacle(o.clone()).unwrap();
        }
        nav
    };
    let (mut coarse, mut fine) = (make(1e-3), make(1e-7));
    let (mut worst_coarse, mut worst_fine) = (0.0f64, 0.0f64);
    for _ in 0..200 {
        let x = rng.point(5.0);
        if fine.clearance(x) < 0.3 {
            continue;
        }
        let v = rng.point(1.0);
        let law = fine.evaluate(x, v).unwrap().command;
        let rel = |f: Vector2<f64>| (f - law).norm() / (1.0 + law.norm());
        worst_fine = worst_fine.max(rel(fine.command(x, v).unwrap().value));
        worst_coarse = worst_coarse.max(rel(coarse.command(x, v).unwrap().value));
    }
    assert!(worst_fine < 1e-4, "h = 1e-7: {worst_fine:e}");
    assert!(
        worst_fine < worst_coarse,
        "{worst_fine:e} vs {worst_coarse:e}"
    );
}

/// A robot pushed into the margin band, and one whose obstacle is perceived late, get a
/// command back out, flagged, and never touch the true shape; a robot whose disc overlaps the
/// true shape is refused.
#[test]
fn a_robot_in_the_margin_band_is_led_back_out() {
    let boundary = StarShape::circle(Vector2::zeros(), 5.0).unwrap();
    let rock = StarShape::circle(Vector2::new(0.0, 0.0), 1.0).unwrap();
    let goal = Vector2::new(3.0, 0.0);
    let (radius, margin) = (0.1, 0.2);
    for law in [Law::kinematic(1.0), Law::dynamic(1.0, 10.0)] {
        let options = Options::default().with_robot(radius, margin);
        let mut nav = Navigator::new(boundary.clone(), goal, law, options).unwrap();
        // Perceived late: the robot already stands in the rock's margin band.
        let mut x = Vector2::new(-1.2, 0.05);
        nav.command(x, Vector2::zeros()).unwrap();
        assert_eq!(nav.add_obstacle(rock.clone()), Ok(0));
        let h = nav.control_period();
        let mut v = Vector2::zeros();
        let mut recovered = 0;
        for _ in 0..20_000 {
            let c = nav.command(x, v).unwrap();
            if let Mode::Recovering(band) = c.mode {
                assert_eq!(band, Band::Obstacle(0));
                recovered += 1;
            }
            Integrator::SemiImplicitEuler.advance(law, h, c.value, &mut x, &mut v);
            assert!(
                rock.signed_distance(x) > radius,
                "{law:?}: touched at {x:?}"
            );
            if (x - goal).norm() < 0.01 {
                break;
            }
        }
        assert!(recovered >= 1, "{law:?}: no recovery flagged");
        assert!((x - goal).norm() < 0.01, "{law:?}: stopped at {x:?}");
        // Disc overlapping the true rock: refused, and the navigator unchanged.
        let inside = Vector2::new(-1.05, 0.0);
        assert_eq!(
            nav.command(inside, Vector2::zeros()),
            Err(NavError::InObstacle { obstacle: 0 })
        );
        // The boundary's band: inward.
        let near_wall = Vector2::new(0.0, -4.75);
        let c = nav.command(near_wall, Vector2::zeros()).unwrap();
        assert_eq!(c.mode, Mode::Recovering(Band::Boundary));
        // A perception that puts the robot's disc into the true shape is refused.
        let mut fresh = Navigator::new(boundary.clone(), goal, law, options).unwrap();
        fresh
            .command(Vector2::new(-1.05, 0.0), Vector2::zeros())
            .unwrap();
        assert_eq!(
            fresh.add_obstacle(rock.clone()),
            Err(NavError::ContainsRobot)
        );
    }
}

/// Parameters at the edge of `f64` are refused with the field named, and within the ranges
/// every command is finite.
#[test]
fn no_option_the_navigator_accepts_makes_a_nan() {
    let boundary = StarShape::circle(Vector2::zeros(), 5.0).unwrap();
    let goal = Vector2::new(3.0, 0.0);
    let d = Options::default();
    let refused = [
        (Law::dynamic(1.0, 10.0), d.with_rho_min(5e-324), "rho_min"),
        (
            Law::dynamic(1.0, 10.0),
            d.with_sensor(1.0, 1e-320),
            "sensor_aperture_deg",
        ),
        (Law::dynamic(1e308, 1e308), d, "mass"),
        (Law::dynamic(5e-324, 10.0), d, "mass"),
        (Law::dynamic(1.0, 1e308), d, "mu"),
        (Law::kinematic(1e308), d, "gain"),
        (
            Law::kinematic(1.0),
            d.with_control_period(0.0),
            "control_period",
        ),
        (
            Law::kinematic(1.0),
            d.with_sensor(f64::NAN, 60.0),
            "sensor_range",
        ),
        (
            Law::kinematic(1.0),
            d.with_robot(f64::INFINITY, 0.0),
            "radius",
        ),
        (Law::kinematic(1.0), d.with_v_max(0.0), "v_max"),
        (Law::kinematic(1.0), d.with_v_max(f64::NAN), "v_max"),
        (Law::kinematic(1.0), d.with_v_max(1e10), "v_max"),
    ];
    for (law, options, field) in refused {
        match Navigator::new(boundary.clone(), goal, law, options) {
            Err(NavError::InvalidOption { field: f, .. }) => {
                assert_eq!(f, field);
                let message = NavError::InvalidOption {
                    field: f,
                    value: 0.0,
                }
                .to_string();
                assert!(message.contains(field), "{message}");
            }
            other => panic!("{field}: {other:?}"),
        }
    }
    // Finite components whose norm (or its square, the energy's) overflows: refused, not an
    // infinite discovery speed, and named as out of range, not "not finite" (issue 56, D19.2).
    let mut nav = Navigator::new(boundary.clone(), goal, Law::dynamic(1.0, 10.0), d).unwrap();
    for huge in [Vector2::new(1.5e308, 1.5e308), Vector2::new(1e200, 0.0)] {
        let e = nav.command(Vector2::new(-3.0, 0.0), huge).unwrap_err();
        assert!(
            matches!(
                e,
                NavError::InvalidOption {
                    field: "velocity",
                    ..
                }
            ),
            "{e:?}"
        );
        assert!(e.to_string().contains("1e154"), "{e}");
    }
    // 1e150 m/s is absurd but its energy is finite: the law answers.
    assert!(
        nav.command(Vector2::new(-3.0, 0.0), Vector2::new(1e150, 0.0))
            .is_ok()
    );
    let rock = StarShape::circle(Vector2::new(0.0, 0.5), 1.0).unwrap();
    let mut rng = Rng::new(3);
    for (law, options) in [
        (
            Law::dynamic(1e-9, 1e9),
            d.with_rho_min(1e-9).with_sensor(1e-9, 1e-3),
        ),
        (
            Law::dynamic(1e9, 1e-9),
            d.with_sensor(1e9, 360.0).with_control_period(1e9),
        ),
        (Law::kinematic(1e9), d.with_control_period(1e-9)),
        (Law::kinematic(1e-9), d.with_control_period(1e9)),
        (Law::kinematic(1e-9), d.with_v_max(1e9)),
        (
            Law::kinematic(1.0),
            d.with_v_max(1e-9).with_speed(harmonav::SpeedPolicy::Paper),
        ),
    ] {
        let mut nav = Navigator::new(boundary.clone(), goal, law, options).unwrap();
        nav.add_obstacle(rock.clone()).unwrap();
        for _ in 0..300 {
            let x = rng.point(5.0);
            let v = rng.point(1e3);
            match nav.command(x, v) {
                Ok(c) => assert!(c.value.iter().all(|c| c.is_finite()), "{law:?} at {x:?}"),
                Err(NavError::InObstacle { .. } | NavError::OutsideBoundary) => {}
                Err(e) => panic!("{law:?} at {x:?}: {e}"),
            }
        }
    }
}

/// The hold with the finite-time speed (`SpeedPolicy::Auto`, `docs/maths.md` §6): the user's
/// 100 Hz loop reaches the goal to 1e-9 m in finitely many steps, never stepping past it (the
/// distance to the goal never rises in the approach), at most `v_max`, and within the
/// continuous law's arrival time plus one period; the paper's speed is still 1 mm short then.
#[test]
fn the_sampled_loop_stops_at_the_goal_in_finite_time_under_the_auto_speed() {
    use harmonav::SpeedPolicy;
    let boundary = StarShape::circle(Vector2::zeros(), 5.0).unwrap();
    let goal = Vector2::new(0.0, 0.0);
    let h = 0.01;
    let start = Vector2::new(3.0, 1.0);
    let fly_to = |speed: SpeedPolicy| {
        let options = Options::default().with_speed(speed);
        let mut nav = Navigator::new(boundary.clone(), goal, Law::kinematic(1.0), options).unwrap();
        let mut x = start;
        let mut last = f64::INFINITY;
        for step in 0..2000 {
            let r = (x - goal).norm();
            if r < 1e-9 {
                return (step as f64 * h, r);
            }
            assert!(r <= last * (1.0 + 1e-12), "{speed}: stepped away at {x:?}");
            last = r;
            let c = nav.command(x, Vector2::zeros()).unwrap();
            assert!(c.value.norm() <= 2f64.sqrt() * (1.0 + 1e-12));
            x += h * c.value;
        }
        (2000.0 * h, (x - goal).norm())
    };
    let (t, _) = fly_to(SpeedPolicy::Auto);
    // Continuous closed form (straight ray): (D − d_b)/v + 2d_b/v = (D + d_b)/v.
    let (v, d_b) = (
        2f64.sqrt(),
        0.5 * 2f64.sqrt() * harmonav::control::BRAKING_TIME,
    );
    let closed = (start.norm() + d_b) / v;
    assert!(t <= closed + 2.0 * h, "{t} s vs {closed} s");
    // The paper's speed converges exponentially: ln(D/ε)/(K√σ), about 15 s to 1e-9 m here.
    let (t_paper, _) = fly_to(SpeedPolicy::Paper);
    assert!(t_paper > 4.0 * t, "paper {t_paper} s, auto {t} s");
}

/// The hold never steps past the goal: every kinematic command held for the period satisfies
/// `h|u| ≤ |x − x_d|`. Without the cap the finite-time speed `v_max√(r/d_b)` steps across the
/// goal wherever `r < h²v_max²/d_b` (within 5.7 cm at 20 Hz and the default `v_max`), and the
/// robot crosses it and comes back from the other side.
#[test]
fn the_kinematic_hold_never_steps_past_the_goal() {
    let boundary = StarShape::circle(Vector2::zeros(), 5.0).unwrap();
    let rock = StarShape::circle(Vector2::new(0.5, 1.5), 0.4).unwrap();
    let goal = Vector2::new(1.0, 0.5);
    let mut crossed_checked = 0;
    for (h, v_max) in [
        (0.01, 2f64.sqrt()),
        (0.05, 2f64.sqrt()),
        (0.1, 3.0),
        (0.2, 0.5),
    ] {
        for start in [
            Vector2::new(-3.0, 1.0),
            Vector2::new(2.5, -2.0),
            Vector2::new(0.4, 3.0),
        ] {
            let options = Options::default().with_control_period(h).with_v_max(v_max);
            let mut nav =
                Navigator::new(boundary.clone(), goal, Law::kinematic(1.0), options).unwrap();
            nav.add_obstacle(rock.clone()).unwrap();
            let mut x = start;
            for _ in 0..(30.0 / h) as usize {
                let r = (x - goal).norm();
                if r < 1e-12 {
                    break;
                }
                let c = nav.command(x, Vector2::zeros()).unwrap();
                let step = h * c.value.norm();
                assert!(
                    step <= r * (1.0 + 1e-12),
                    "h = {h}: a step of {step} m with the goal {r} m away at {x:?}"
                );
                let next = x + h * c.value;
                // Near the goal the goal is never behind the robot (to the rounding of the
                // coordinates: a step that lands on the goal ends within an ulp of it).
                if r < 0.05 {
                    let behind = -(next - goal).dot(&(x - goal));
                    let ulp = 4.0 * f64::EPSILON * goal.norm().max(1.0) * r;
                    assert!(
                        behind <= ulp,
                        "crossed the goal by {behind} m² at {x:?}, h = {h}"
                    );
                    crossed_checked += 1;
                }
                x = next;
            }
            assert!(
                (x - goal).norm() < 1e-6,
                "h = {h}, from {start:?}: ended at {x:?}"
            );
        }
    }
    assert!(crossed_checked > 20, "{crossed_checked}");
}

/// Flies `nav` from `x` for at most 60 s of commands held for its period; returns whether it
/// arrived, asserting at every step that the robot's centre stays outside `rock` grown by
/// `gap` (the navigator's grown shape: no entry).
fn fly_from(nav: &mut Navigator, mut x: Vector2<f64>, law: Law, rock: &StarShape) -> bool {
    let h = nav.control_period();
    let mut v = Vector2::zeros();
    for _ in 0..(60.0 / h) as usize {
        let c = nav.command(x, v).unwrap();
        Integrator::SemiImplicitEuler.advance(law, h, c.value, &mut x, &mut v);
        assert!(
            !rock.contains(x),
            "{law:?}: entered the grown shape at {x:?}"
        );
        if (x - nav.goal()).norm() < 0.01 {
            return true;
        }
    }
    false
}

/// Within the certificate's tolerance of a shape that is not a circle (about 1e-4 of its size)
/// the certified clearance is 0 or less at a free point: the command must still lead on, not
/// stop for good (the independent review of the hold found a zero command forever there).
#[test]
fn a_robot_in_the_blind_layer_of_a_curved_shape_moves_on() {
    let boundary = StarShape::circle(Vector2::zeros(), 5.0).unwrap();
    let ellipse = StarShape::ellipse(Vector2::zeros(), [1.0, 0.5], 0.0).unwrap();
    let goal = Vector2::new(3.0, 0.0);
    for law in [Law::kinematic(1.0), Law::dynamic(1.0, 10.0)] {
        for radius in [0.0, 0.1] {
            let options = Options::default().with_robot(radius, 0.0);
            let grown = ellipse.offset(radius).unwrap();
            for (angle, gap) in [(2.0, 1.9e-5), (2.3, 1e-5), (3.0, 1e-6)] {
                let u = Vector2::new(f64::cos(angle), f64::sin(angle));
                let x = grown.centre() + (grown.radius_along(u).0 + gap) * u;
                let mut nav = Navigator::new(boundary.clone(), goal, law, options).unwrap();
                nav.add_obstacle(ellipse.clone()).unwrap();
                assert!(
                    fly_from(&mut nav, x, law, &grown),
                    "{law:?}, radius {radius}, {gap} m off the shape at angle {angle}: stuck"
                );
            }
        }
    }
}

/// A margin far thinner than the certificate's tolerance: the recovery out of the band must
/// not leave the robot in the blind layer.
#[test]
fn a_recovery_through_a_thin_margin_arrives() {
    let boundary = StarShape::circle(Vector2::zeros(), 5.0).unwrap();
    let ellipse = StarShape::ellipse(Vector2::zeros(), [1.0, 0.5], 0.0).unwrap();
    let goal = Vector2::new(3.0, 0.0);
    for law in [Law::kinematic(1.0), Law::dynamic(1.0, 10.0)] {
        for margin in [1e-4, 2e-5, 1e-5] {
            let options = Options::default().with_robot(0.1, margin);
            let inner = ellipse.offset(0.1).unwrap();
            let u = Vector2::new(f64::cos(2.5), f64::sin(2.5));
            let x = inner.centre() + (inner.radius_along(u).0 + 0.5 * margin) * u;
            let mut nav = Navigator::new(boundary.clone(), goal, law, options).unwrap();
            nav.command(x, Vector2::zeros()).unwrap();
            nav.add_obstacle(ellipse.clone()).unwrap();
            assert!(
                fly_from(&mut nav, x, law, &inner),
                "{law:?}, margin {margin}: stuck after the recovery"
            );
        }
    }
}

/// One disc between the start and the goal: the start lies on the stable manifold of the
/// saddle behind the disc, where the continuous law (and its sampled form, `hold = "paper"`)
/// rests for ever. The default hold comes to rest there too, then takes the steepest certified
/// descent among 16 directions ([`Mode::FromRest`], `docs/maths.md` §10.1), and arrives; every
/// step lowers `phi_k` and stays clear of the disc.
#[test]
fn a_robot_at_a_saddle_steps_off_it_and_arrives() {
    let saddle = Vector2::new(-1.1753, 0.0);
    let fly = |hold| {
        let boundary = StarShape::circle(Vector2::zeros(), 5.0).unwrap();
        let disc = StarShape::circle(Vector2::zeros(), 1.0).unwrap();
        let options = Options::default().with_hold(hold);
        let mut nav = Navigator::new(
            boundary,
            Vector2::new(3.0, 0.0),
            Law::kinematic(1.0),
            options,
        )
        .unwrap();
        nav.add_obstacle(disc).unwrap();
        let (h, v) = (0.01, Vector2::zeros());
        let mut x = Vector2::new(-3.0, 0.0);
        let mut phi = nav.evaluate(x, v).unwrap().field.phi;
        let mut first_from_rest = None;
        for step in 0..2_000 {
            if (x - Vector2::new(3.0, 0.0)).norm() < 0.05 {
                return (x, first_from_rest, true);
            }
            let c = nav.command(x, v).unwrap();
            if c.mode == Mode::FromRest && first_from_rest.is_none() {
                first_from_rest = Some((step, x));
            }
            x += h * c.value;
            assert!(x.norm() > 1.0, "{hold:?}: inside the disc at {x:?}");
            let next = nav.evaluate(x, v).unwrap().field.phi;
            // The paper's hold is the law sampled as is: it steps across the saddle and back.
            assert!(
                hold == HoldPolicy::Paper || next < phi,
                "phi_k did not fall from {phi} to {next} at {x:?}"
            );
            phi = next;
        }
        (x, first_from_rest, false)
    };
    let (end, _, reached) = fly(HoldPolicy::Paper);
    // Across the saddle and back, one step of the law (1.41 cm) each period.
    assert!(
        !reached && (end - saddle).norm() < 0.015,
        "the paper's hold ends at {end:?}"
    );
    let (_, from_rest, reached) = fly(HoldPolicy::Auto);
    let (step, at) = from_rest.expect("a step from rest");
    assert!(
        (at - saddle).norm() < 1e-3,
        "the first step from rest at {at:?}"
    );
    assert!(step < 300 && reached, "step {step}, reached {reached}");
}
