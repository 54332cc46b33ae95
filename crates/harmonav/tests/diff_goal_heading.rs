//! The goal heading of a differential-drive base (issue 53, docs/unicycle.md section 3.5):
//! `Navigator::set_goal_heading` makes `command_pose` turn in place at the goal until the
//! heading is within `GOAL_HEADING_TOLERANCE` of the goal yaw. The closed loop holds each
//! command for the period on the exact arc (`unicycle_arc`), as tests/diff_drive.rs does. The
//! negative control: the same loop without a goal yaw ends facing wherever it approached from.

use std::f64::consts::PI;

use harmonav::tuning::{GOAL_ARRIVAL, GOAL_HEADING_TOLERANCE};
use harmonav::{
    Base, GoalTolerance, Law, NavError, Navigator, Options, PoseCommand, StarShape, Steer, Vector2,
    unicycle_arc,
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
    /// Some pose given was within `GoalTolerance::xy` of the goal.
    reached: bool,
    /// The speed of the last command before the first pose within `xy`, m/s.
    entry_speed: f64,
    /// The path length driven from the first pose within `xy` on, m.
    rolled: f64,
}

impl Run {
    /// The latch (`set_goal_stateful`, the default): from the first pose within `xy` the base
    /// only brakes, at `a_max` (`v_b = max(0, v − a_max h)`), so it rolls at most
    /// `v²/(2 a_max)` from there (`v` the speed it entered with; 0 without limits), and ends
    /// within `xy` plus that.
    fn check_roll_out(&self, base: Base, xy: f64, label: &str) {
        let bound = match base {
            Base::Diff { accel: Some(a), .. } => self.entry_speed.powi(2) / (2.0 * a.a_max),
            _ => 0.0,
        };
        assert!(self.rolled <= bound * (1.0 + 1e-9), "{label}: {self:?}");
        let to_goal = (self.x - goal()).norm();
        assert!(to_goal < xy + self.rolled, "{label}: {to_goal}");
    }
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
        reached: false,
        entry_speed: 0.0,
        rolled: 0.0,
    };
    let mut last = (0.0, 0.0);
    for n in 0..periods {
        let c = nav.command_pose(x, yaw).unwrap();
        assert!(
            (0.0..=V_MAX).contains(&c.v) && c.omega.abs() <= OMEGA_MAX,
            "{c:?}"
        );
        // Within xy, or latched there (`set_goal_stateful`): a braking base may roll out.
        if !run.reached && (x - goal()).norm() < nav.goal_tolerance().xy {
            (run.reached, run.entry_speed) = (true, last.0);
        }
        if run.reached {
            run.rolled += c.v * H;
        }
        if c.steer == Steer::ToGoalHeading {
            assert_eq!(c.v, 0.0, "{c:?}");
            assert!(run.reached, "{x:?}");
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
        let (mut turning_max, mut rolled_max) = (0, 0.0_f64);
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
                // Within 1 cm plus what it rolls while braking (the latch: none without limits).
                run.check_roll_out(base, GOAL_ARRIVAL, &format!("{label} {yaw} {goal_yaw}"));
                rolled_max = rolled_max.max(run.rolled);
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
        println!("{label}: the longest roll from the first pose within 1 cm {rolled_max:.1e} m");
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
        let (mut farthest, mut sooner) = (0.0_f64, 0);
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
                run.check_roll_out(base, tolerance.xy, &format!("{yaw} {goal_yaw}"));
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
                // Not slower; under acceleration limits the default radius latches too (since
                // 2026-12-07) and one run arrives in the same period either way.
                let m = reference.arrived.unwrap();
                assert!(
                    n <= m,
                    "{yaw} {goal_yaw}: {n} periods, {m} with the default"
                );
                sooner += usize::from(n < m);
                for _ in 0..10 {
                    let c = nav.command_pose(run.x, run.yaw).unwrap();
                    assert_eq!((c.v, c.omega, c.steer), (0.0, 0.0, Steer::Arrived), "{c:?}");
                }
            }
        }
        let runs = GOAL_YAWS.len() * START_YAWS.len();
        println!(
            "tolerance 0.25 m: farthest arrival {farthest:.3} m from the goal, {sooner}/{runs} \
             runs sooner than with the default"
        );
        assert!(farthest > GOAL_ARRIVAL, "{farthest}");
        assert!(sooner + 1 >= runs, "{sooner}/{runs}");
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

/// The scenarios where an unlatched base rolls out of `xy` while braking: the test's own
/// limits (`a_max` 0.5, `alpha_max` 4) with a 2 cm radius, and a slow turn-rate limit
/// (`alpha_max` 1) with Nav2's 0.25 m.
const ROLL_OUT: [(f64, f64, f64); 2] = [(0.02, A_MAX, ALPHA_MAX), (0.25, A_MAX, 1.0)];

/// One closed-loop run to a goal yaw under acceleration limits, `stateful` or not, until
/// `Arrived` or `PERIODS`.
#[derive(Debug)]
struct Latched {
    /// The command and the pose it was given.
    steps: Vec<(Vector2<f64>, PoseCommand)>,
    /// The final pose.
    x: Vector2<f64>,
    yaw: f64,
    /// The index of the first command given a pose within `xy`.
    first_within: Option<usize>,
    /// The least true body clearance along every arc, m.
    closest: f64,
}

impl Latched {
    /// Whether a command after the first pose within `xy` is aligned descent's (the base
    /// drives towards the goal position again, or turns to do so).
    fn drove_again(&self) -> bool {
        let Some(first) = self.first_within else {
            return false;
        };
        self.steps[first..].iter().any(|(_, c)| {
            matches!(
                c.steer,
                Steer::Ahead | Steer::Shortened { .. } | Steer::Turning
            )
        })
    }

    /// Whether some pose after the first within `xy` is outside it.
    fn left(&self, xy: f64) -> bool {
        let Some(first) = self.first_within else {
            return false;
        };
        let outside = |x: &Vector2<f64>| (x - goal()).norm() >= xy;
        self.steps[first..].iter().any(|(x, _)| outside(x)) || outside(&self.x)
    }
}

fn fly_latched(
    (xy, a_max, alpha_max): (f64, f64, f64),
    stateful: bool,
    yaw: f64,
    goal_yaw: f64,
) -> (Navigator, Latched) {
    let mut nav = navigator(Base::diff(V_MAX, OMEGA_MAX).with_accel(a_max, alpha_max));
    nav.set_goal_heading(Some(goal_yaw)).unwrap();
    nav.set_goal_tolerance(GoalTolerance { xy, yaw: 0.05 })
        .unwrap();
    nav.set_goal_stateful(stateful);
    assert_eq!(nav.goal_stateful(), stateful);
    let (mut x, mut yaw) = (start(), yaw);
    let mut run = Latched {
        steps: Vec::new(),
        x,
        yaw,
        first_within: None,
        closest: f64::INFINITY,
    };
    let mut last = (0.0, 0.0);
    for n in 0..PERIODS {
        let c = nav.command_pose(x, yaw).unwrap();
        assert!(
            (0.0..=V_MAX).contains(&c.v) && c.omega.abs() <= OMEGA_MAX,
            "{c:?}"
        );
        assert!((c.v - last.0).abs() <= a_max * H * (1.0 + 1e-9), "{c:?}");
        assert!(
            (c.omega - last.1).abs() <= alpha_max * H * (1.0 + 1e-9),
            "{c:?}"
        );
        last = (c.v, c.omega);
        if run.first_within.is_none() && (x - goal()).norm() < xy {
            run.first_within = Some(n);
        }
        assert_eq!(nav.goal_latched(), stateful && run.first_within.is_some());
        for i in 0..=SAMPLES {
            let p = unicycle_arc(x, yaw, c.v, c.omega, H * i as f64 / SAMPLES as f64).0;
            run.closest = run.closest.min(clearance(p));
        }
        run.steps.push((x, c));
        (x, yaw) = unicycle_arc(x, yaw, c.v, c.omega, H);
        if c.steer == Steer::Arrived {
            break;
        }
    }
    (run.x, run.yaw) = (x, yaw);
    (nav, run)
}

/// Nav2's `stateful` goal checker (`set_goal_stateful`, default true): under acceleration
/// limits, once the base has been given a pose within `xy` it only brakes (the most it can,
/// `v` falling by `a_max h` a period) and turns in place, never drives again, even where it
/// rolls out of the radius; it ends `Arrived` within the yaw tolerance and stays, the body
/// clear along every arc and every command within the limits. The negative control: the same
/// runs unlatched (`stateful` false, the behaviour before) roll out and drive back in, in some
/// runs of each scenario. A run that never leaves the radius is the same, bit for bit, either
/// way.
#[test]
fn the_latched_radius_never_drives_again() {
    for scenario in ROLL_OUT {
        let xy = scenario.0;
        let (mut left, mut drove_unlatched, mut outside_at_end) = (0, 0, 0);
        for goal_yaw in GOAL_YAWS {
            for yaw in START_YAWS {
                let (mut nav, run) = fly_latched(scenario, true, yaw, goal_yaw);
                let label = format!("{scenario:?} start {yaw} goal {goal_yaw}");
                let first = run
                    .first_within
                    .unwrap_or_else(|| panic!("{label}: {run:?}"));
                assert!(!run.drove_again(), "{label}: {run:?}");
                // After the first pose within xy: braking (v falling by a_max h to 0), then v = 0.
                let mut v_last = run.steps[first.saturating_sub(1)].1.v;
                for (_, c) in &run.steps[first..] {
                    if c.v > 0.0 {
                        assert_eq!(c.steer, Steer::Braking, "{label}: {c:?}");
                        assert!(c.v < v_last, "{label}: {c:?}");
                    }
                    v_last = c.v;
                }
                let (_, end) = run.steps.last().unwrap();
                assert_eq!(end.steer, Steer::Arrived, "{label}: {run:?}");
                assert!(wrap(goal_yaw - run.yaw).abs() < 0.05, "{label}");
                assert!(run.closest > 0.0, "{label}: {}", run.closest);
                for _ in 0..10 {
                    let c = nav.command_pose(run.x, run.yaw).unwrap();
                    assert_eq!((c.v, c.omega, c.steer), (0.0, 0.0, Steer::Arrived), "{c:?}");
                }
                let (_, unlatched) = fly_latched(scenario, false, yaw, goal_yaw);
                if run.left(xy) {
                    left += 1;
                    outside_at_end += usize::from((run.x - goal()).norm() >= xy);
                } else {
                    let same = run.steps.iter().zip(&unlatched.steps);
                    assert_eq!(run.steps.len(), unlatched.steps.len(), "{label}");
                    for ((_, a), (_, b)) in same {
                        assert_eq!(
                            (a.v.to_bits(), a.omega.to_bits()),
                            (b.v.to_bits(), b.omega.to_bits())
                        );
                        assert_eq!(a.steer, b.steer, "{label}");
                    }
                }
                drove_unlatched += usize::from(unlatched.drove_again());
            }
        }
        let runs = GOAL_YAWS.len() * START_YAWS.len();
        println!(
            "{scenario:?}: latched, {left}/{runs} runs roll out of xy ({outside_at_end} end \
             outside it), none drives again; unlatched, {drove_unlatched}/{runs} drive again"
        );
        assert!(
            left > 0,
            "{scenario:?}: no run rolls out: the test shows nothing"
        );
        assert!(
            drove_unlatched > 0,
            "{scenario:?}: the negative control never drove again"
        );
    }
}

/// The latch releases when the goal yaw, the tolerance or `stateful` changes (the same value
/// again keeps it), is never set unlatched or without a goal yaw, and after a release the
/// base drives again from outside the radius.
#[test]
fn the_latch_releases_when_the_goal_changes() {
    let base = Base::diff(V_MAX, OMEGA_MAX).with_accel(A_MAX, ALPHA_MAX);
    let tolerance = GoalTolerance { xy: 0.1, yaw: 0.05 };
    let near = goal() + Vector2::new(0.05, 0.0);
    let far = goal() + Vector2::new(-1.0, 0.3);
    let latched = || {
        let mut nav = navigator(base);
        nav.set_goal_heading(Some(1.0)).unwrap();
        nav.set_goal_tolerance(tolerance).unwrap();
        assert!(nav.goal_stateful());
        assert!(!nav.goal_latched());
        nav.command_pose(far, 0.0).unwrap();
        assert!(!nav.goal_latched(), "latched away from the goal");
        let c = nav.command_pose(near, 0.0).unwrap();
        assert_eq!(c.steer, Steer::ToGoalHeading);
        assert!(nav.goal_latched());
        // Far from the goal, latched: still the turn in place.
        let c = nav.command_pose(far, 0.0).unwrap();
        assert_eq!((c.v, c.steer), (0.0, Steer::ToGoalHeading), "{c:?}");
        nav
    };
    let mut nav = latched();
    nav.set_goal_heading(Some(1.0)).unwrap();
    nav.set_goal_tolerance(tolerance).unwrap();
    nav.set_goal_stateful(true);
    assert!(nav.goal_latched(), "the same values released the latch");
    type Change = fn(&mut Navigator);
    let changes: [(&str, Change); 4] = [
        ("goal yaw", |n| n.set_goal_heading(Some(1.5)).unwrap()),
        ("no goal yaw", |n| n.set_goal_heading(None).unwrap()),
        ("tolerance", |n| {
            n.set_goal_tolerance(GoalTolerance { xy: 0.1, yaw: 0.06 })
                .unwrap();
        }),
        ("stateful", |n| n.set_goal_stateful(false)),
    ];
    for (what, change) in changes {
        let mut nav = latched();
        change(&mut nav);
        assert!(!nav.goal_latched(), "{what}");
        // Released: from far away it is aligned descent again (it turns towards the goal
        // first: the goal is behind-left of yaw 0 there).
        let c = nav.command_pose(far, 0.0).unwrap();
        assert!(
            !matches!(c.steer, Steer::ToGoalHeading | Steer::Arrived),
            "{what}: {c:?}"
        );
        // Unlatched or without a goal yaw, a pose within xy does not latch.
        if what == "stateful" || what == "no goal yaw" {
            nav.command_pose(near, 0.0).unwrap();
            assert!(!nav.goal_latched(), "{what}");
        }
    }
}

/// Without acceleration limits a base in the final phase commands `v = 0` and never leaves the
/// radius, so the latch changes nothing: latched and unlatched closed loops are the same, bit
/// for bit, with the default tolerance and Nav2's 0.25 m.
#[test]
fn without_limits_the_latch_changes_nothing() {
    for xy in [GOAL_ARRIVAL, 0.25] {
        for goal_yaw in GOAL_YAWS {
            for yaw in START_YAWS {
                let commands = |stateful: bool| {
                    let mut nav = navigator(Base::diff(V_MAX, OMEGA_MAX));
                    nav.set_goal_heading(Some(goal_yaw)).unwrap();
                    nav.set_goal_tolerance(GoalTolerance {
                        xy,
                        yaw: GOAL_HEADING_TOLERANCE,
                    })
                    .unwrap();
                    nav.set_goal_stateful(stateful);
                    let run = fly(&mut nav, yaw, PERIODS, |_, c| c.steer == Steer::Arrived);
                    assert!(run.arrived.is_some(), "{xy} {yaw} {goal_yaw}");
                    assert_eq!(nav.goal_latched(), stateful);
                    run.commands
                };
                let (a, b) = (commands(true), commands(false));
                assert_eq!(a.len(), b.len());
                for (a, b) in a.iter().zip(&b) {
                    assert_eq!(
                        (a.v.to_bits(), a.omega.to_bits()),
                        (b.v.to_bits(), b.omega.to_bits())
                    );
                    assert_eq!((a.mode, a.steer), (b.mode, b.steer));
                }
            }
        }
    }
}
