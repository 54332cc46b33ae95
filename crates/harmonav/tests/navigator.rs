//! The online navigator: a robot that holds each command for a fixed step, with its own
//! perception, reaches the goal without collision under both laws; the commands equal the laws
//! evaluated on a field built independently; every error leaves the navigator unchanged.

use std::sync::Arc;

use harmonav::control::{Dynamic, Kinematic};
use harmonav::field::Field;
use harmonav::transform::Workspace;
use harmonav::transform::random::{self, Kind, Rng};
use harmonav::{
    DampingPolicy, HoldPolicy, Law, Mode, NavError, Navigator, Options, StarShape, Vector2,
};

const KINDS: [Kind; 4] = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];

/// A random world (true shapes, start, goal) with the start and goal at least `clear` from
/// every shape, and every shape still star-shaped when grown by 0.15 m (a robot of radius 0.1
/// with a 0.05 margin).
fn world(seed: u64, m: usize, clear: f64) -> (Workspace, Vector2<f64>) {
    let mut rng = Rng::new(seed);
    let ws = loop {
        let ws = random::workspace(&mut rng, m, &KINDS, Kind::Circle, 0.4);
        if ws.obstacles().iter().all(|o| o.offset(0.15).is_ok()) {
            break ws;
        }
    };
    loop {
        let start = random::free_point(&mut rng, &ws, clear);
        if (start - ws.destination()).norm() > 3.0 {
            return (ws, start);
        }
    }
}

/// What a fixed-step run measured.
struct Outcome {
    reached: bool,
    time: f64,
    /// Smallest distance from the robot's centre to the true shapes, minus the radius.
    clearance: f64,
    max_speed: f64,
}

/// The user's own loop: perception adds every true obstacle whose outline comes within 1 m;
/// the kinematic robot moves `x += h·u`, the dynamic one by semi-implicit Euler
/// `v += h·f/m, x += h·v`.
fn fly(ws: &Workspace, start: Vector2<f64>, law: Law, options: Options, h: f64) -> Outcome {
    let mut nav =
        Navigator::new(ws.boundary().clone(), ws.destination(), law, options).expect("navigator");
    let (mut x, mut v) = (start, Vector2::zeros());
    let mut known = vec![false; ws.obstacles().len()];
    let (mut t, mut clearance, mut max_speed) = (0.0, f64::INFINITY, 0.0f64);
    while t < 120.0 {
        for (i, o) in ws.obstacles().iter().enumerate() {
            if !known[i] && o.signed_distance(x) < 1.0 {
                nav.add_obstacle(o.clone())
                    .expect("a true obstacle is valid");
                known[i] = true;
            }
        }
        if (x - ws.destination()).norm() < 0.01 {
            return Outcome {
                reached: true,
                time: t,
                clearance,
                max_speed,
            };
        }
        let cmd = nav
            .command(x, v)
            .expect("the robot stays in the free space")
            .value;
        match law {
            Law::Kinematic { .. } => x += h * cmd,
            Law::Dynamic { mass, .. } => {
                v += h * cmd / mass;
                x += h * v;
            }
        }
        t += h;
        let true_clearance = ws
            .obstacles()
            .iter()
            .map(|o| o.signed_distance(x))
            .fold(-ws.boundary().signed_distance(x), f64::min)
            - options.radius;
        clearance = clearance.min(true_clearance);
        max_speed = max_speed.max(v.norm());
    }
    Outcome {
        reached: false,
        time: t,
        clearance,
        max_speed,
    }
}

/// The step sizes of the crate documentation, in 12 worlds of 4–10 mixed shapes, with a point
/// robot and with a 0.1 m disc plus a 0.05 m margin: at 100 Hz the kinematic robot never
/// touches a true shape and keeps the margin to within one step's travel; at 200 Hz it also
/// arrives every time (at 100 Hz one run of these 24 is caught in a 2-cycle across a saddle's
/// stable manifold on an obstacle's barrier, safe but stopped); the dynamic robot at 1 kHz
/// (semi-implicit Euler) is safe, arrives and stays below √(2μ/m).
#[test]
fn a_fixed_step_loop_with_its_own_perception_arrives_safely_with_both_laws() {
    for seed in 0..12u64 {
        let m = 4 + (seed as usize % 7);
        let (ws, start) = world(900 + seed, m, 0.3);
        for options in [Options::default(), Options::default().with_robot(0.1, 0.05)] {
            for (law, h, must_arrive) in [
                (Law::kinematic(1.0), 0.01, false),
                (Law::kinematic(1.0), 0.005, true),
                (Law::dynamic(1.0, 10.0), 0.001, true),
            ] {
                let o = fly(&ws, start, law, options, h);
                let label = format!("seed {seed}, {law:?}, h {h}, radius {}", options.radius);
                assert!(
                    o.reached || !must_arrive,
                    "{label}: not reached in {:.1} s",
                    o.time
                );
                assert!(o.clearance > 0.0, "{label}: clearance {}", o.clearance);
                // One step's travel is at most h·(speed); the margin holds to within it.
                let slack = h * 4.5;
                assert!(
                    o.clearance >= options.margin - slack,
                    "{label}: clearance {} below the margin {}",
                    o.clearance,
                    options.margin
                );
                if let Law::Dynamic { mass, mu } = law {
                    assert!(o.max_speed < (2.0 * mu / mass).sqrt(), "{label}");
                }
            }
        }
    }
}

/// The commands are the laws of harmonav-control on a field built directly from the same grown
/// obstacles (an independent path through the crates): exactly under the paper's hold (the
/// continuous law sampled as is), and under the default hold wherever it did not shorten the
/// kinematic step.
#[test]
fn commands_are_the_laws_on_the_known_obstacles() {
    for seed in 0..8u64 {
        let (ws, _) = world(950 + seed, 5, 0.3);
        let mut rng = Rng::new(seed);
        for damping in DampingPolicy::ALL {
            let options = Options::default()
                .with_damping(damping)
                .with_hold(HoldPolicy::Paper);
            let mut held = Navigator::new(
                ws.boundary().clone(),
                ws.destination(),
                Law::kinematic(1.5),
                options.with_hold(HoldPolicy::Auto),
            )
            .unwrap();
            let mut kin = Navigator::new(
                ws.boundary().clone(),
                ws.destination(),
                Law::kinematic(1.5),
                options,
            )
            .unwrap();
            let mut dynamic = Navigator::new(
                ws.boundary().clone(),
                ws.destination(),
                Law::dynamic(2.0, 10.0),
                options,
            )
            .unwrap();
            let n = 3;
            for o in &ws.obstacles()[..n] {
                held.add_obstacle(o.clone()).unwrap();
                kin.add_obstacle(o.clone()).unwrap();
                dynamic.add_obstacle(o.clone()).unwrap();
            }
            let reference = Workspace::new(
                ws.boundary().clone(),
                ws.obstacles()[..n].to_vec(),
                ws.destination(),
            )
            .unwrap();
            let field = Field::all_known(Arc::new(reference)).unwrap();
            assert_eq!(kin.k(), field.k());
            let d_min = options.d_min().unwrap();
            let law = Dynamic::new(2.0, 10.0, d_min)
                .unwrap()
                .with_damping(damping)
                .with_world_radius(field.workspace().boundary().radius_bounds().1)
                .unwrap();
            for _ in 0..50 {
                let x = random::free_point(&mut rng, &ws, 0.05);
                let v = rng.point(1.0);
                let e = field.eval(x).unwrap();
                let u = Kinematic::new(1.5)
                    .unwrap()
                    .velocity(&e, (x - ws.destination()).norm());
                assert_eq!(kin.command(x, v).unwrap().value, u);
                let c = held.command(x, v).unwrap();
                match c.mode {
                    Mode::Law => assert_eq!(c.value, u),
                    // The law's step shortened, or in a stiff valley the chord of its flow
                    // line: never faster than the law here, and downhill.
                    Mode::Capped { scale } => {
                        assert!((0.0..1.0).contains(&scale), "scale {scale}");
                        assert!(c.value.norm() <= u.norm() * (1.0 + 1e-12));
                        assert!(c.value.norm() == 0.0 || c.value.dot(&u) > 0.0);
                    }
                    Mode::Recovering(_) => panic!("0.05 m clear of every shape"),
                    Mode::Escaping => panic!("a star world has no escape"),
                    // Only where the law's own step is held to rest (a saddle): at the law's
                    // speed, in another direction.
                    Mode::FromRest => assert!(c.value.norm() <= u.norm() * (1.0 + 1e-12)),
                    other => panic!("a mode this test does not know: {other:?}"),
                }
                // The discovery speed is that of the last command before the additions: 0.
                let d = law.damping(&field, &e, v, 0.0);
                let f = law.force(&field, &e, v, &d);
                // `evaluate` is `command` without remembering the state, and shows its parts.
                let eval = dynamic.evaluate(x, v).unwrap();
                assert_eq!((eval.command, eval.field, eval.damping), (f, e, Some(d)));
                assert_eq!(kin.evaluate(x, v).unwrap().damping, None);
                assert_eq!(dynamic.command(x, v).unwrap().value, f);
            }
        }
    }
}

/// The default damping's pull grows with the world, `4μ·max(1, ρ/5 m)`, `ρ` the largest radius
/// of the boundary the field uses (the disc shrunk by `radius + margin`); the other policies
/// keep `μ`; a kinematic navigator is unaffected.
#[test]
fn the_governed_pull_grows_with_the_world() {
    let options = Options {
        radius: 0.1,
        margin: 0.05,
        ..Options::default()
    };
    for r in [2.0, 5.0, 20.0, 100.0] {
        let disc = StarShape::circle(Vector2::zeros(), r).unwrap();
        let goal = Vector2::new(0.5 * r, 0.0);
        let pull = |damping| {
            let nav = Navigator::new(
                disc.clone(),
                goal,
                Law::dynamic(2.0, 10.0),
                options.with_damping(damping),
            )
            .unwrap();
            let harmonav::Controller::Dynamic(law) = nav.controller() else {
                panic!("a dynamic navigator")
            };
            assert_eq!(law.world_radius(), r - 0.15);
            law.pull()
        };
        let want = 40.0 * ((r - 0.15) / 5.0).max(1.0);
        assert!(
            (pull(DampingPolicy::Governed) - want).abs() <= 1e-12 * want,
            "R = {r}"
        );
        assert_eq!(pull(DampingPolicy::Auto), 10.0);
        assert_eq!(pull(DampingPolicy::Paper), 10.0);
    }
}

/// Every error is typed and leaves the navigator as it was: the next command is the same.
#[test]
fn errors_are_typed_and_leave_the_navigator_unchanged() {
    let boundary = StarShape::circle(Vector2::zeros(), 5.0).unwrap();
    let goal = Vector2::new(3.0, 0.0);
    let options = Options::default().with_robot(0.2, 0.05);
    let mut nav = Navigator::new(boundary.clone(), goal, Law::dynamic(1.0, 10.0), options).unwrap();
    let a = StarShape::circle(Vector2::new(0.0, 0.0), 1.0).unwrap();
    assert_eq!(nav.add_obstacle(a.clone()).unwrap(), 0);
    let (x, v) = (Vector2::new(-3.0, 0.4), Vector2::new(0.3, -0.1));
    let before = nav.command(x, v).unwrap();
    let k = nav.k();
    let circle = |c: [f64; 2], r: f64| StarShape::circle(Vector2::new(c[0], c[1]), r).unwrap();
    let cases = [
        // 0.3 m from A: closer than 2 × (radius + margin) = 0.5 m once both are grown.
        (circle([1.6, 0.0], 0.3), NavError::Overlap { obstacle: 0 }),
        // One that reaches the boundary joins it (tests/joined.rs); a join that would shut
        // the goal or the robot out is refused there.
        (circle([3.1, 0.0], 0.3), NavError::ContainsGoal),
        (circle([-3.1, 0.4], 0.3), NavError::ContainsRobot),
    ];
    for (shape, want) in cases {
        assert_eq!(nav.add_obstacle(shape), Err(want.clone()));
        assert!(!want.to_string().is_empty());
        assert_eq!(nav.obstacles().len(), 1);
        assert_eq!(nav.k(), k);
        assert_eq!(nav.command(x, v).unwrap(), before, "after {want:?}");
    }
    let bad_points = [
        (Vector2::new(0.0, 1.1), NavError::InObstacle { obstacle: 0 }),
        (Vector2::new(4.9, 0.0), NavError::OutsideBoundary),
        (
            Vector2::new(f64::NAN, 0.0),
            NavError::NotFinite { what: "position" },
        ),
    ];
    for (p, want) in bad_points {
        assert_eq!(nav.command(p, v), Err(want));
        assert_eq!(nav.command(x, v).unwrap(), before);
    }
    assert_eq!(
        nav.command(x, Vector2::new(0.0, f64::INFINITY)),
        Err(NavError::NotFinite { what: "velocity" })
    );
    // A valid obstacle still goes in after the errors.
    assert_eq!(nav.add_obstacle(circle([-1.0, 2.5], 0.3)).unwrap(), 1);
    // Bad options and goals.
    let bad = |law: Law, options: Options, goal: Vector2<f64>| {
        Navigator::new(boundary.clone(), goal, law, options).unwrap_err()
    };
    let d = Options::default();
    assert_eq!(
        bad(Law::kinematic(-1.0), d, goal),
        NavError::InvalidOption {
            field: "gain",
            value: -1.0
        }
    );
    assert!(matches!(
        bad(Law::dynamic(1.0, 10.0), d.with_robot(-0.1, 0.0), goal),
        NavError::InvalidOption {
            field: "radius",
            ..
        }
    ));
    assert!(matches!(
        bad(Law::dynamic(1.0, 10.0), d.with_sensor(0.0, 60.0), goal),
        NavError::InvalidOption {
            field: "sensor_range",
            ..
        }
    ));
    assert_eq!(
        bad(Law::kinematic(1.0), d, Vector2::new(6.0, 0.0)),
        NavError::GoalNotFree
    );
    assert_eq!(
        bad(
            Law::kinematic(1.0),
            d.with_robot(0.2, 0.0),
            Vector2::new(4.9, 0.0)
        ),
        NavError::GoalNotFree
    );
}
