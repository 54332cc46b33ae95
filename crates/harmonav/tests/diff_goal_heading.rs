//! The goal heading of a differential-drive base (issue 53, docs/unicycle.md section 3.5):
//! `Navigator::set_goal_heading` makes `command_pose` turn in place at the goal until the
//! heading is within `GOAL_HEADING_TOLERANCE` of the goal yaw. The closed loop holds each
//! command for the period on the exact arc (`unicycle_arc`), as tests/diff_drive.rs does. The
//! negative control: the same loop without a goal yaw ends facing wherever it approached from.

use std::f64::consts::PI;

use harmonav::{
    Base, GOAL_ARRIVAL, GOAL_HEADING_TOLERANCE, GoalTolerance, Law, NavError, Navigator, Options,
    PoseCommand, StarShape, Steer, Vector2, unicycle_arc,
};

const RADIUS: f64 = 0.18;
const H: f64 = 0.1;
const V_MAX: f64 = 0.5;
const OMEGA_MAX: f64 = 2.0;
const A_MAX: f64 = 0.5;
const ALPHA_MAX: f64 = 4.0;
const BOUNDARY: f64 = 5.0;
/// Points per held arc at which the true body clearance is checked.
const SAMPLES: usize = 50;
/// The longest run, periods (60 s).
const PERIODS: usize = 600;

/// The start yaws: towards the goal (`0`), across it, facing away (`π`) and in between.
const START_YAWS: [f64; 6] = [0.0, PI / 2.0, -PI / 2.0, PI, 2.5, -2.9];
/// The goal yaws.
const GOAL_YAWS: [f64; 3] = [PI / 2.0, -2.0, PI];

fn disc() -> (Vector2<f64>, f64) {
    (Vector2::new(-0.2, -0.5), 0.4)
}

fn start() -> Vector2<f64> {
    Vector2::new(-2.0, 0.3)
}

fn goal() -> Vector2<f64> {
    Vector2::new(1.5, 0.0)
}

fn navigator(base: Base) -> Navigator {
    let options = Options::default()
        .with_robot(RADIUS, 0.05)
        .with_control_period(H)
        .with_base(base);
    let boundary = StarShape::circle(Vector2::zeros(), BOUNDARY).unwrap();
    let mut nav = Navigator::new(boundary, goal(), Law::kinematic(1.0), options).unwrap();
    let (c, r) = disc();
    nav.add_obstacle(StarShape::circle(c, r).unwrap()).unwrap();
    nav
}

/// The body's true clearance at `p`, m.
fn clearance(p: Vector2<f64>) -> f64 {
    let (c, r) = disc();
    ((p - c).norm() - r).min(BOUNDARY - p.norm()) - RADIUS
}

/// `wrap(b − a)` in `[−π, π]`.
fn wrap(a: f64) -> f64 {
    a.sin().atan2(a.cos())
}

/// What one closed-loop run measured.
#[derive(Debug)]
struct Run {
    x: Vector2<f64>,
    yaw: f64,
    commands: Vec<PoseCommand>,
    /// The least true body clearance along every arc, m.
    closest: f64,
    /// The largest `|Δv|/h`, `|Δω|/h` between commands (the first from rest).
    max_dv: f64,
    max_domega: f64,
    /// The period of the first `Steer::Arrived`.
    arrived: Option<usize>,
}

/// Drives from `start()` at `yaw` for `periods`, or until `stop` says so after a command.
fn fly(
    nav: &mut Navigator,
    yaw: f64,
    periods: usize,
    stop: impl Fn(Vector2<f64>, &PoseCommand) -> bool,
) -> Run {
    let (mut x, mut yaw) = (start(), yaw);
    let mut run = Run {
        x,
        yaw,
        commands: Vec::new(),
        closest: f64::INFINITY,
        max_dv: 0.0,
        max_domega: 0.0,
        arrived: None,
    };
    let mut last = (0.0, 0.0);
    for n in 0..periods {
        let c = nav.command_pose(x, yaw).unwrap();
        assert!(
            (0.0..=V_MAX).contains(&c.v) && c.omega.abs() <= OMEGA_MAX,
            "{c:?}"
        );
        if c.steer == Steer::ToGoalHeading {
            assert_eq!(c.v, 0.0, "{c:?}");
            assert!((x - goal()).norm() < nav.goal_tolerance().xy, "{x:?}");
        }
        run.max_dv = run.max_dv.max((c.v - last.0).abs() / H);
        run.max_domega = run.max_domega.max((c.omega - last.1).abs() / H);
        last = (c.v, c.omega);
        for i in 0..=SAMPLES {
            let p = unicycle_arc(x, yaw, c.v, c.omega, H * i as f64 / SAMPLES as f64).0;
            run.closest = run.closest.min(clearance(p));
        }
        (x, yaw) = unicycle_arc(x, yaw, c.v, c.omega, H);
        run.commands.push(c);
        if c.steer == Steer::Arrived && run.arrived.is_none() {
            run.arrived = Some(n);
        }
        if stop(x, &c) {
            break;
        }
    }
    (run.x, run.yaw) = (x, yaw);
    run
}

/// From every start yaw (facing away included), with and without acceleration limits, the
/// loop with a goal yaw ends `Arrived`: the position within `GOAL_ARRIVAL` of the goal, the
/// heading within `GOAL_HEADING_TOLERANCE` of the goal yaw, and it stays there (ten more
/// commands are `(0, 0)`); every command within the bounds (and the acceleration limits), the
/// body clear along every arc.
#[test]
fn the_loop_ends_at_the_goal_yaw_from_every_start() {
    for (label, base) in [
        ("no limits", Base::diff(V_MAX, OMEGA_MAX)),
        (
            "accel",
            Base::diff(V_MAX, OMEGA_MAX).with_accel(A_MAX, ALPHA_MAX),
        ),
    ] {
        let mut turning_max = 0;
        for goal_yaw in GOAL_YAWS {
            for yaw in START_YAWS {
                let mut nav = navigator(base);
                nav.set_goal_heading(Some(goal_yaw)).unwrap();
                assert_eq!(nav.goal_heading(), Some(goal_yaw));
                let run = fly(&mut nav, yaw, PERIODS, |_, c| c.steer == Steer::Arrived);
                let error = wrap(goal_yaw - run.yaw);
                let to_goal = (run.x - goal()).norm();
                let turning = run
                    .commands
                    .iter()
                    .filter(|c| c.steer == Steer::ToGoalHeading)
                    .count();
                turning_max = turning_max.max(turning);
                println!(
                    "{label}: start yaw {yaw:+.2}, goal yaw {goal_yaw:+.2}: arrived at period \
                     {:?}, {turning} periods turning to the goal yaw, heading error {error:+.1e} \
                     rad, {to_goal:.1e} m from the goal, closest {:+.3} m, max |dv|/h {:.2}, \
                     |dω|/h {:.2}",
                    run.arrived, run.closest, run.max_dv, run.max_domega
                );
                assert!(run.arrived.is_some(), "{label} {yaw} {goal_yaw}: {run:?}");
                assert!(
                    error.abs() < GOAL_HEADING_TOLERANCE,
                    "{label} {yaw}: {error}"
                );
                assert!(to_goal < GOAL_ARRIVAL, "{label} {yaw}: {to_goal}");
                assert!(run.closest > 0.0, "{label} {yaw}: {}", run.closest);
                if let Base::Diff { accel: Some(a), .. } = base {
                    assert!(run.max_dv <= a.a_max * (1.0 + 1e-9), "{}", run.max_dv);
                    assert!(
                        run.max_domega <= a.alpha_max * (1.0 + 1e-9),
                        "{}",
                        run.max_domega
                    );
                }
                // It stays: the pose does not change and the command is (0, 0), arrived.
                for _ in 0..10 {
                    let c = nav.command_pose(run.x, run.yaw).unwrap();
                    assert_eq!((c.v, c.omega, c.steer), (0.0, 0.0, Steer::Arrived), "{c:?}");
                }
            }
        }
        // Some start needed turning at the goal, or the test would not test the turn.
        assert!(turning_max > 0, "{label}");
    }
}

/// The negative control: the same loop without a goal yaw, run until the position has arrived
/// and ten periods more, ends more than the tolerance away from the goal yaw for some start
/// (it faces wherever it approached from).
#[test]
fn without_a_goal_yaw_the_heading_is_not_controlled() {
    let mut worst: f64 = 0.0;
    for goal_yaw in GOAL_YAWS {
        for yaw in START_YAWS {
            let mut nav = navigator(Base::diff(V_MAX, OMEGA_MAX));
            let run = fly(&mut nav, yaw, PERIODS, |x, _| {
                (x - goal()).norm() < GOAL_ARRIVAL
            });
            assert!((run.x - goal()).norm() < GOAL_ARRIVAL, "{yaw}: {run:?}");
            let more = fly_on(&mut nav, run.x, run.yaw, 10);
            worst = worst.max(wrap(goal_yaw - more).abs());
        }
    }
    println!("without a goal yaw: largest final heading error {worst:.2} rad");
    assert!(worst > GOAL_HEADING_TOLERANCE, "{worst}");
}

/// `periods` more commands from `(x, yaw)`; the final yaw.
fn fly_on(nav: &mut Navigator, mut x: Vector2<f64>, mut yaw: f64, periods: usize) -> f64 {
    for _ in 0..periods {
        let c = nav.command_pose(x, yaw).unwrap();
        (x, yaw) = unicycle_arc(x, yaw, c.v, c.omega, H);
    }
    yaw
}

/// Without a goal yaw, `command_pose` is what it was, bit for bit: a navigator never given one,
/// one given `None`, and one given a yaw then `None` command the same sequence over a whole
/// run; one given a yaw commands the same until the position has arrived.
#[test]
fn none_is_bit_identical_to_no_goal_yaw() {
    for base in [
        Base::diff(V_MAX, OMEGA_MAX),
        Base::diff(V_MAX, OMEGA_MAX).with_accel(A_MAX, ALPHA_MAX),
    ] {
        for yaw in START_YAWS {
            let reference = fly(&mut navigator(base), yaw, 300, |_, _| false).commands;
            let mut none = navigator(base);
            none.set_goal_heading(None).unwrap();
            let mut reset = navigator(base);
            reset.set_goal_heading(Some(1.0)).unwrap();
            reset.set_goal_heading(None).unwrap();
            assert_eq!(reset.goal_heading(), None);
            for nav in [&mut none, &mut reset] {
                let got = fly(nav, yaw, 300, |_, _| false).commands;
                assert_eq!(got.len(), reference.len());
                for (a, b) in got.iter().zip(&reference) {
                    assert_eq!(a.v.to_bits(), b.v.to_bits(), "{a:?} {b:?}");
                    assert_eq!(a.omega.to_bits(), b.omega.to_bits(), "{a:?} {b:?}");
                    assert_eq!((a.mode, a.steer), (b.mode, b.steer));
                }
            }
            let mut with = navigator(base);
            with.set_goal_heading(Some(-2.0)).unwrap();
            let got = fly(&mut with, yaw, 300, |x, _| {
                (x - goal()).norm() < GOAL_ARRIVAL
            });
            let same = got.commands.len();
            assert!(same < reference.len(), "{yaw}: never arrived");
            assert_eq!(got.commands[..], reference[..same], "{yaw}");
        }
    }
}

/// A non-finite goal yaw is refused by name and leaves the navigator unchanged; so is a
/// holonomic base's `command_pose` with a goal yaw (as without one).
#[test]
fn a_bad_goal_yaw_is_refused_by_name() {
    let mut nav = navigator(Base::diff(V_MAX, OMEGA_MAX));
    nav.set_goal_heading(Some(0.7)).unwrap();
    let before = nav.clone();
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let e = nav.set_goal_heading(Some(bad)).unwrap_err();
        assert!(
            matches!(e, NavError::NotFinite { what: "goal_yaw" }),
            "{e:?}"
        );
        assert!(e.to_string().contains("goal_yaw"), "{e}");
        assert_eq!(nav.goal_heading(), Some(0.7));
    }
    // Unchanged: the same commands as the clone taken before, at the goal too.
    let mut before = before;
    for (x, yaw) in [(start(), 0.3), (goal() + Vector2::new(0.004, 0.0), -1.0)] {
        let a = nav.command_pose(x, yaw).unwrap();
        let b = before.command_pose(x, yaw).unwrap();
        assert_eq!(a, b);
    }
    let mut holonomic = navigator(Base::Holonomic);
    holonomic.set_goal_heading(Some(0.7)).unwrap();
    assert!(matches!(
        holonomic.command_pose(goal(), 0.0),
        Err(NavError::InvalidOption { field: "base", .. })
    ));
}

/// Nav2's tolerances (`set_goal_tolerance`, xy 0.25 m and yaw 0.05 rad): the turn in place
/// begins at the first pose within 0.25 m of the goal (no command after it drives), and the
/// loop ends `Arrived` within 0.25 m and 0.05 rad, and stays. The tolerance takes effect: some
/// run ends farther from the goal than the default's 1 cm (where the test above ends every
/// run), and every run ends in fewer periods than with the default.
#[test]
fn a_goal_tolerance_ends_the_drive_where_it_says() {
    let tolerance = GoalTolerance {
        xy: 0.25,
        yaw: 0.05,
    };
    for base in [
        Base::diff(V_MAX, OMEGA_MAX),
        Base::diff(V_MAX, OMEGA_MAX).with_accel(A_MAX, ALPHA_MAX),
    ] {
        let mut farthest: f64 = 0.0;
        for goal_yaw in GOAL_YAWS {
            for yaw in START_YAWS {
                let mut nav = navigator(base);
                nav.set_goal_heading(Some(goal_yaw)).unwrap();
                nav.set_goal_tolerance(tolerance).unwrap();
                assert_eq!(nav.goal_tolerance(), tolerance);
                let run = fly(&mut nav, yaw, PERIODS, |_, c| c.steer == Steer::Arrived);
                let n = run
                    .arrived
                    .unwrap_or_else(|| panic!("{yaw} {goal_yaw}: {run:?}"));
                let to_goal = (run.x - goal()).norm();
                assert!(to_goal < tolerance.xy, "{yaw}: {to_goal}");
                assert!(wrap(goal_yaw - run.yaw).abs() < tolerance.yaw, "{run:?}");
                assert!(run.closest > 0.0, "{yaw}: {}", run.closest);
                // Once within xy the base only turns: replay the positions.
                let first = run
                    .commands
                    .iter()
                    .position(|c| matches!(c.steer, Steer::ToGoalHeading | Steer::Arrived))
                    .unwrap();
                assert!(run.commands[first..].iter().all(|c| c.v == 0.0), "{yaw}");
                farthest = farthest.max(to_goal);
                let mut default = navigator(base);
                default.set_goal_heading(Some(goal_yaw)).unwrap();
                let reference = fly(&mut default, yaw, PERIODS, |_, c| c.steer == Steer::Arrived);
                assert!(
                    n < reference.arrived.unwrap(),
                    "{yaw} {goal_yaw}: {n} periods, {:?} with the default",
                    reference.arrived
                );
                for _ in 0..10 {
                    let c = nav.command_pose(run.x, run.yaw).unwrap();
                    assert_eq!((c.v, c.omega, c.steer), (0.0, 0.0, Steer::Arrived), "{c:?}");
                }
            }
        }
        println!("tolerance 0.25 m: farthest arrival {farthest:.3} m from the goal");
        assert!(farthest > GOAL_ARRIVAL, "{farthest}");
    }
}

/// A tolerance that is not finite and positive is refused by the parameter's name and leaves
/// the navigator unchanged.
#[test]
fn a_bad_goal_tolerance_is_refused_by_name() {
    let mut nav = navigator(Base::diff(V_MAX, OMEGA_MAX));
    assert_eq!(nav.goal_tolerance(), GoalTolerance::default());
    assert_eq!(
        GoalTolerance::default(),
        GoalTolerance {
            xy: GOAL_ARRIVAL,
            yaw: GOAL_HEADING_TOLERANCE
        }
    );
    for (bad, name) in [
        (GoalTolerance { xy: 0.0, yaw: 0.1 }, "xy_goal_tolerance"),
        (
            GoalTolerance {
                xy: f64::NAN,
                yaw: 0.1,
            },
            "xy_goal_tolerance",
        ),
        (GoalTolerance { xy: 0.1, yaw: -1.0 }, "yaw_goal_tolerance"),
        (
            GoalTolerance {
                xy: 0.1,
                yaw: f64::INFINITY,
            },
            "yaw_goal_tolerance",
        ),
    ] {
        let e = nav.set_goal_tolerance(bad).unwrap_err();
        assert!(
            matches!(e, NavError::InvalidOption { field, .. } if field == name),
            "{e:?}"
        );
        assert!(e.to_string().contains(name), "{e}");
        assert!(e.to_string().contains("positive"), "{e}");
        assert_eq!(nav.goal_tolerance(), GoalTolerance::default());
    }
}
