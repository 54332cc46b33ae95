//! A differential drive's acceleration limits (issue 53, item 2; docs/unicycle.md §10): every
//! command of `command_pose` stays within `a_max·h` and `alpha_max·h` of the last, every arc
//! keeps the robot's margin, and the robot arrives. The negative control: the same limits
//! applied by clamping the unlimited law's commands (what a downstream velocity smoother
//! does) drive the robot through an obstacle behind its goal, which the braking certificate
//! (eq. brakedisc) never lets it reach.

use harmonav::transform::random::Rng;
use harmonav::{Base, Law, Navigator, Options, StarShape, Steer, Vector2, unicycle_arc};

const RADIUS: f64 = 0.18;
const MARGIN: f64 = 0.05;
const H: f64 = 0.1;
const V_MAX: f64 = 1.0;
const OMEGA_MAX: f64 = 2.0;
const A_MAX: f64 = 0.3;
const ALPHA_MAX: f64 = 3.0;
const BOUNDARY: f64 = 5.0;
/// Points per held arc at which the true body clearance is checked.
const SAMPLES: usize = 200;

/// A 5 m disc with `discs`, the goal `goal`, every obstacle known.
fn navigator(discs: &[(Vector2<f64>, f64)], goal: Vector2<f64>, base: Base) -> Navigator {
    let options = Options::default()
        .with_robot(RADIUS, MARGIN)
        .with_control_period(H)
        .with_base(base);
    let boundary = StarShape::circle(Vector2::zeros(), BOUNDARY).unwrap();
    let mut nav = Navigator::new(boundary, goal, Law::kinematic(1.0), options).unwrap();
    for (c, r) in discs {
        nav.add_obstacle(StarShape::circle(*c, *r).unwrap())
            .unwrap();
    }
    nav
}

/// The body's true clearance at `p` (to the discs and the boundary), m.
fn clearance(discs: &[(Vector2<f64>, f64)], p: Vector2<f64>) -> f64 {
    let discs = discs
        .iter()
        .map(|(c, r)| (p - c).norm() - r)
        .fold(f64::INFINITY, f64::min);
    (BOUNDARY - p.norm()).min(discs) - RADIUS
}

/// What one run measured.
#[derive(Debug)]
struct Run {
    /// The least true clearance of the body along every arc, m.
    closest: f64,
    /// The largest `|Δv|/h` and `|Δω|/h` between commands (the first from rest).
    max_dv: f64,
    max_domega: f64,
    arrived: Option<f64>,
    braking: usize,
}

/// Drives from `start` (heading `yaw`) for at most `periods`: `command` gives `(v, ω)` and the
/// steer at the pose, the robot moves on the exact arc.
fn fly(
    discs: &[(Vector2<f64>, f64)],
    goal: Vector2<f64>,
    (start, yaw): (Vector2<f64>, f64),
    periods: usize,
    mut command: impl FnMut(Vector2<f64>, f64) -> (f64, f64, Steer),
) -> Run {
    let (mut x, mut yaw) = (start, yaw);
    let mut last = (0.0, 0.0);
    let mut run = Run {
        closest: f64::INFINITY,
        max_dv: 0.0,
        max_domega: 0.0,
        arrived: None,
        braking: 0,
    };
    for n in 0..periods {
        if (x - goal).norm() < 0.02 {
            run.arrived = Some(n as f64 * H);
            break;
        }
        let (v, omega, steer) = command(x, yaw);
        assert!(
            (0.0..=V_MAX).contains(&v) && omega.abs() <= OMEGA_MAX,
            "{v} {omega}"
        );
        run.max_dv = run.max_dv.max((v - last.0).abs() / H);
        run.max_domega = run.max_domega.max((omega - last.1).abs() / H);
        run.braking += usize::from(steer == Steer::Braking);
        last = (v, omega);
        for i in 0..=SAMPLES {
            let p = unicycle_arc(x, yaw, v, omega, H * i as f64 / SAMPLES as f64).0;
            run.closest = run.closest.min(clearance(discs, p));
        }
        (x, yaw) = unicycle_arc(x, yaw, v, omega, H);
    }
    run
}

/// The goal 0.07 m in front of a grown rock, reached head on from 5.2 m away at up to 1 m/s,
/// with 0.3 m/s² to brake (1.67 m from full speed).
fn rock_behind_the_goal() -> (Vec<(Vector2<f64>, f64)>, Vector2<f64>) {
    (vec![(Vector2::new(2.0, 0.0), 0.5)], Vector2::new(1.2, 0.0))
}

#[test]
fn commands_keep_the_limits_and_the_robot_stops_before_the_rock() {
    let (discs, goal) = rock_behind_the_goal();
    let base = Base::diff(V_MAX, OMEGA_MAX).with_accel(A_MAX, ALPHA_MAX);
    let mut nav = navigator(&discs, goal, base);
    let run = fly(
        &discs,
        goal,
        (Vector2::new(-4.0, 0.0), 0.0),
        2000,
        |x, yaw| {
            let c = nav.command_pose(x, yaw).unwrap();
            (c.v, c.omega, c.steer)
        },
    );
    println!("limited: {run:?}");
    assert!(run.max_dv <= A_MAX * (1.0 + 1e-12), "{run:?}");
    assert!(run.max_domega <= ALPHA_MAX * (1.0 + 1e-12), "{run:?}");
    assert!(run.closest >= MARGIN - 1e-9, "{run:?}");
    assert!(run.arrived.is_some(), "{run:?}");
}

/// The negative control: the unlimited law's commands clamped into the same limits (a velocity
/// smoother behind `command_pose`) reach 1 m/s and cannot brake before the rock.
#[test]
fn clamping_the_unlimited_law_into_the_limits_hits_the_rock() {
    let (discs, goal) = rock_behind_the_goal();
    let mut nav = navigator(&discs, goal, Base::diff(V_MAX, OMEGA_MAX));
    let mut last = (0.0_f64, 0.0_f64);
    let run = fly(
        &discs,
        goal,
        (Vector2::new(-4.0, 0.0), 0.0),
        2000,
        |x, yaw| {
            // Inside the grown rock the law refuses: the smoother is then asked to stop.
            let (want, steer) = nav
                .command_pose(x, yaw)
                .map_or(((0.0, 0.0), Steer::Stopped), |c| ((c.v, c.omega), c.steer));
            let v = want
                .0
                .clamp((last.0 - A_MAX * H).max(0.0), last.0 + A_MAX * H);
            let omega = want.1.clamp(last.1 - ALPHA_MAX * H, last.1 + ALPHA_MAX * H);
            last = (v, omega);
            (v, omega, steer)
        },
    );
    println!("clamped: {run:?}");
    assert!(run.closest < 0.0, "the clamped law kept clear: {run:?}");
}

/// Seeded disc worlds (as tests/diff_drive.rs draws them): within the limits, every arc clear
/// of the margin, and arrival, from random headings.
#[test]
fn seeded_worlds_keep_the_limits_and_the_margin() {
    let mut arrived = 0;
    for seed in 0..8u64 {
        let mut rng = Rng::new(2000 + seed);
        let (start, goal) = (Vector2::new(-4.0, 0.05), Vector2::new(4.0, 0.0));
        let mut discs: Vec<(Vector2<f64>, f64)> = Vec::new();
        while discs.len() < 8 {
            let c = rng.point(4.0);
            let r = rng.uniform(0.2, 0.5);
            if c.norm() + r + 0.5 < BOUNDARY
                && (c - start).norm() > r + 0.8
                && (c - goal).norm() > r + 0.8
                && discs.iter().all(|(c2, r2)| (c - c2).norm() - r - r2 > 0.5)
            {
                discs.push((c, r));
            }
        }
        let yaw = rng.uniform(-3.0, 3.0);
        let base = Base::diff(V_MAX, OMEGA_MAX).with_accel(A_MAX, ALPHA_MAX);
        let mut nav = navigator(&discs, goal, base);
        let run = fly(&discs, goal, (start, yaw), 3000, |x, yaw| {
            let c = nav.command_pose(x, yaw).unwrap();
            (c.v, c.omega, c.steer)
        });
        let mut free = navigator(&discs, goal, Base::diff(V_MAX, OMEGA_MAX));
        let unlimited = fly(&discs, goal, (start, yaw), 3000, |x, yaw| {
            let c = free.command_pose(x, yaw).unwrap();
            (c.v, c.omega, c.steer)
        });
        println!(
            "seed {seed}: {run:?}; unlimited arrived {:?}",
            unlimited.arrived
        );
        assert!(run.max_dv <= A_MAX * (1.0 + 1e-12), "seed {seed}: {run:?}");
        assert!(
            run.max_domega <= ALPHA_MAX * (1.0 + 1e-12),
            "seed {seed}: {run:?}"
        );
        assert!(run.closest >= MARGIN - 1e-9, "seed {seed}: {run:?}");
        arrived += usize::from(run.arrived.is_some());
    }
    assert_eq!(arrived, 8);
}

/// Bad limits are refused by name, the navigator not built.
#[test]
fn bad_limits_are_refused_by_name() {
    let (discs, goal) = rock_behind_the_goal();
    for (base, field) in [
        (
            Base::diff(V_MAX, OMEGA_MAX).with_accel(f64::NAN, 1.0),
            "a_max",
        ),
        (
            Base::diff(V_MAX, OMEGA_MAX).with_accel(1.0, -1.0),
            "alpha_max",
        ),
        (Base::diff(V_MAX, OMEGA_MAX).with_accel(0.0, 1.0), "a_max"),
    ] {
        let options = Options::default()
            .with_robot(RADIUS, MARGIN)
            .with_control_period(H)
            .with_base(base);
        let boundary = StarShape::circle(Vector2::zeros(), BOUNDARY).unwrap();
        let e = Navigator::new(boundary, goal, Law::kinematic(1.0), options).unwrap_err();
        assert!(e.to_string().contains(field), "{e}");
    }
    let _ = discs;
}
